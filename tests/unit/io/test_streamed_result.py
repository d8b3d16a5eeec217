"""A run written car by car (:func:`lotsim.write_result` of a run, what ``lotsim run``
does): the same bytes as the whole document written at once, plain and compressed, with
every part a document may hold (cars inside the lot when they came, disturbances, a lot
with bays by use); and nothing at the path when the writing fails half way."""

from __future__ import annotations

import gzip
import json

import pytest

import lotsim
from lotsim.io import result as result_io
from lotsim.io.result import result_dict, write_json
from tests.oracles.compact_samples import decoded


@pytest.fixture(scope="module")
def runs():
    stalled = lotsim.run("scenarios/mixed_lot.yaml",
                         disturbances=lotsim.Disturbances(stall_rate=60.0,
                                                          stall_duration=(30.0, 60.0), seed=1))
    live = lotsim.Live(lotsim.prepare("scenarios/quickstart.yaml"))
    free = sorted(s.id for s in live.prepared.lot_graph.lot.free_slots)
    live.add("inside1", live.prepared.scenario.vehicle_types[0].name, slot=free[-1],
             dwell=120.0)
    return {"stalled": stalled, "inside": live.finish(),
            "uses": lotsim.run("scenarios/lots/storefront.yaml")}


@pytest.mark.slow
@pytest.mark.parametrize("name", ["stalled", "inside", "uses"])
@pytest.mark.parametrize("suffix", ["result.json", "result.json.gz"])
def test_a_run_written_car_by_car_is_the_whole_document_byte_for_byte(runs, name, suffix,
                                                                        tmp_path):
    rr = runs[name]
    whole, streamed = tmp_path / "whole" / suffix, tmp_path / "streamed" / suffix
    whole.parent.mkdir()
    write_json(result_dict(rr), whole)
    seen = []
    lotsim.write_result(rr, streamed, progress=lambda done, total: seen.append((done, total)))
    assert streamed.read_bytes() == whole.read_bytes()
    n = len(rr.vehicles)
    assert seen[0] == (0, n) and seen[-1] == (n, n)
    if suffix.endswith(".gz"):
        read = decoded(json.loads(gzip.decompress(streamed.read_bytes())))
    else:
        read = json.loads(streamed.read_text())
    assert read == json.loads(json.dumps(result_dict(rr)))


def test_the_parts_the_runs_cover(runs):
    # the byte comparison above is worth as much as the parts its runs hold
    assert "disturbances" in result_dict(runs["stalled"])
    assert any("inside" in v for v in result_dict(runs["inside"])["vehicles"])
    assert "access_aisles" in result_dict(runs["uses"])["lot"]


def test_a_write_that_fails_half_way_leaves_nothing(runs, tmp_path, monkeypatch):
    rr = runs["stalled"]
    target = tmp_path / "result.json"
    monkeypatch.setattr(result_io, "vehicle_doc", _failing_after(3))
    with pytest.raises(OSError, match="disk full"):
        lotsim.write_result(rr, target)
    assert list(tmp_path.iterdir()) == []


def _failing_after(n: int):
    real = result_io.vehicle_doc
    made = []

    def doc(v):
        if len(made) == n:
            raise OSError("disk full")
        made.append(v.id)
        return real(v)

    return doc
