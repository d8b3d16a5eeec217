"""A result in its compact form (``result.json.gz``, ``lotsim run --compact``): gzip the
standard library reads back to the same document, the same bytes for the same run, read
by ``lotsim check``, ``render`` and ``export`` as ``result.json`` is, and a broken one told
in a line."""

from __future__ import annotations

import gzip
import json

import pytest

import lotsim
from lotsim.cli import main
from lotsim.errors import ResultFormatError


@pytest.fixture(scope="module")
def doc():
    return lotsim.result_dict(lotsim.run("scenarios/quickstart.yaml"))


def test_the_compact_form_is_gzip_of_the_same_document(doc, tmp_path):
    plain = lotsim.write_result(doc, tmp_path / "result.json")
    packed = lotsim.write_result(doc, tmp_path / "result.json.gz")
    # the standard library's gzip, not lotsim, unpacks it
    assert json.loads(gzip.decompress(packed.read_bytes())) == json.loads(plain.read_text())
    assert packed.stat().st_size * 2 < plain.stat().st_size
    assert lotsim.load_result(packed) == lotsim.load_result(plain)
    assert lotsim.check(str(packed)).ok


def test_run_compact_writes_it_alone_the_same_bytes_each_time_and_check_reads_it(
        tmp_path, capsys):
    a, b = tmp_path / "a", tmp_path / "b"
    assert main(["run", "scenarios/quickstart.yaml", "-o", str(a), "--no-gif"]) == 0
    assert main(["run", "scenarios/quickstart.yaml", "-o", str(a), "--no-gif",
                 "--compact"]) == 0
    said = capsys.readouterr().out
    assert sorted(p.name for p in a.iterdir()) == ["result.json.gz"]  # the earlier form gone
    assert f"removed {a / 'result.json'}" in said
    assert main(["run", "scenarios/quickstart.yaml", "-o", str(b), "--no-gif",
                 "--compact"]) == 0
    assert (a / "result.json.gz").read_bytes() == (b / "result.json.gz").read_bytes()
    assert main(["check", str(a / "result.json.gz")]) == 0
    assert main(["render", str(a / "result.json.gz"), "--html", str(tmp_path / "r.html")]) == 0
    assert "<html" in (tmp_path / "r.html").read_text(encoding="utf-8").lower()


def test_a_cut_compact_result_is_told_in_a_line(doc, tmp_path):
    packed = lotsim.write_result(doc, tmp_path / "result.json.gz")
    cut = tmp_path / "cut.json.gz"
    cut.write_bytes(packed.read_bytes()[: packed.stat().st_size // 2])
    with pytest.raises(ResultFormatError, match=r"cut\.json\.gz: not a whole gzip file"):
        lotsim.load_result(cut)
