"""A run written as it goes (``lotsim.run(..., write=path)``, what ``lotsim run`` does
without pictures or disturbances): each car written once it is done and its moves let go,
the file the same bytes as the run written after it ends, the figures the same, and
nothing at the path when the run fails."""

from __future__ import annotations

import pytest

import lotsim
from lotsim.cli import main
from lotsim.errors import SettingsError
from lotsim.io import result as result_io


@pytest.fixture(scope="module")
def prepared():
    return lotsim.prepare("scenarios/mixed_lot.yaml")


def _figures(rr):
    # (wall-clock planning times differ run to run)
    m = {k: v for k, v in rr.metrics().items() if not k.startswith("planning_time")}
    return m, rr.trip_figures(), rr.hourly()


@pytest.mark.parametrize("suffix", ["result.json", "result.json.gz"])
def test_a_run_written_as_it_goes_is_the_run_written_after_byte_for_byte(prepared, suffix,
                                                                          tmp_path):
    after = lotsim.run(prepared)
    lotsim.write_result(after, tmp_path / f"after-{suffix}")
    going = lotsim.run(prepared, write=tmp_path / suffix)
    assert (tmp_path / suffix).read_bytes() == (tmp_path / f"after-{suffix}").read_bytes()
    # every car was written and let go; the run's figures are the same floats
    assert all(v.written is not None and not v.moves for v in going.vehicles)
    assert _figures(going) == _figures(after)
    assert [v.status for v in going.vehicles] == [v.status for v in after.vehicles]
    assert going.metrics()["departed"] > 20  # (cars that leave: their standing on the way out)


def test_cars_are_written_while_the_run_goes_in_the_results_order(prepared, tmp_path,
                                                                  monkeypatch):
    trips = []  # trips dealt with, as the progress says
    written = []  # (car, trips dealt with when it was written)
    real = result_io.vehicle_doc

    def doc(v):
        assert v.done and v.moves  # written whole, before its moves go
        written.append((v.id, trips[-1] if trips else 0))
        return real(v)

    monkeypatch.setattr(result_io, "vehicle_doc", doc)
    rr = lotsim.run(prepared, write=tmp_path / "result.json",
                    progress=lambda done, total: trips.append(done))
    assert [car for car, _ in written] == [v.id for v in rr.vehicles]
    # most were written long before the last trip was planned: the run held them no longer
    total = trips[-1]
    early = sum(at < total * 0.75 for _, at in written)
    assert early >= len(written) // 2


def test_a_run_that_fails_half_way_leaves_nothing(prepared, tmp_path, monkeypatch):
    real = result_io.vehicle_doc
    made = []

    def doc(v):
        if len(made) == 3:
            raise OSError("disk full")
        made.append(v.id)
        return real(v)

    monkeypatch.setattr(result_io, "vehicle_doc", doc)
    with pytest.raises(OSError, match="disk full"):
        lotsim.run(prepared, write=tmp_path / "result.json.gz")
    assert list(tmp_path.iterdir()) == []


def test_what_cannot_be_written_as_it_goes_is_told(prepared, tmp_path):
    with pytest.raises(SettingsError, match="disturbances"):
        lotsim.run(prepared, write=tmp_path / "r.json",
                   disturbances=lotsim.Disturbances(stall_rate=60.0, seed=1))
    assert list(tmp_path.iterdir()) == []
    live = lotsim.Live(prepared, release=lambda v: None)
    with pytest.raises(SettingsError, match="from outside"):
        live.add("late", prepared.scenario.vehicle_types[0].name, "gate-in", at=5.0)
    rr = lotsim.run(prepared, write=tmp_path / "r.json")
    with pytest.raises(ValueError, match="written as it went"):
        lotsim.write_result(rr, tmp_path / "again.json")


def test_lotsim_run_writes_the_result_as_it_goes(prepared, tmp_path, capsys):
    assert main(["run", "scenarios/mixed_lot.yaml", "--no-gif", "--compact",
                 "-o", str(tmp_path / "run")]) == 0
    lotsim.write_result(lotsim.run(prepared), tmp_path / "after.json.gz")
    assert (tmp_path / "run" / "result.json.gz").read_bytes() == \
        (tmp_path / "after.json.gz").read_bytes()
    assert "writing the result" not in capsys.readouterr().err  # (no second pass)


def test_a_writer_closed_before_the_run_ended_leaves_nothing_and_says_so(prepared, tmp_path):
    with pytest.raises(ValueError, match="before the run ended"), \
            result_io.ResultWriter(tmp_path / "r.json", prepared.scenario, prepared.lot_graph):
        pass
    assert list(tmp_path.iterdir()) == []
