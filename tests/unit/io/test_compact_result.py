"""A result in its compact form (``result.json.gz``, ``lotsim run --compact``): gzip and JSON
the standard library reads, whose samples a second reader decodes to the same document,
several times smaller than the plain document gzip-compressed, the same bytes for the same
run, read by ``lotsim check``, ``render`` and ``export`` as ``result.json`` is, and a broken
one told in a line."""

from __future__ import annotations

import gzip
import json

import pytest

import lotsim
from lotsim.cli import main
from lotsim.errors import ResultFormatError
from tests.oracles.compact_samples import decoded


@pytest.fixture(scope="module")
def doc():
    return lotsim.result_dict(lotsim.run("scenarios/quickstart.yaml"))


def test_the_compact_form_is_gzip_of_the_same_document(doc, tmp_path):
    plain = lotsim.write_result(doc, tmp_path / "result.json")
    packed = lotsim.write_result(doc, tmp_path / "result.json.gz")
    # the standard library's gzip and json read it, and a reader of the test's own decodes
    # its samples to the plain document's numbers
    raw = json.loads(gzip.decompress(packed.read_bytes()))
    assert all("encoding" in v["samples"] for v in raw["vehicles"])
    assert decoded(raw) == json.loads(plain.read_text())
    # the encoding is worth its keep: twice as small as the plain document gzip-compressed
    assert packed.stat().st_size * 2 < len(gzip.compress(plain.read_bytes()))
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


@pytest.mark.parametrize("change, told", [
    (lambda s: s["encoding"].pop("differences"), "'encoding' must be an object of"),
    (lambda s: s["encoding"]["decimals"].pop("x"),
     "'encoding' must be an object of .*, 'decimals' naming each of"),
    (lambda s: s["encoding"].update(differences=7), "'differences' must be 0 to 3, not 7"),
    (lambda s: s["encoding"]["decimals"].update(t=1.5),
     "the decimals of 't' must be 0 to 9, not 1.5"),
    (lambda s: s["x"].__setitem__(1, 0.5), "'x' must be a list of whole numbers"),
    (lambda s: s["y"].__setitem__(0, 10 ** 20), "'y' must be a list of whole numbers"),
    (lambda s: s["v"].extend([2 ** 53] * 2000), "'v' sums beyond the range"),
])
def test_samples_whose_encoding_cannot_be_decoded_are_told_in_a_line(doc, tmp_path, change,
                                                                      told):
    packed = lotsim.write_result(doc, tmp_path / "result.json.gz")
    raw = json.loads(gzip.decompress(packed.read_bytes()))
    change(next(v for v in raw["vehicles"] if v["samples"]["t"])["samples"])
    broken = tmp_path / "broken.json.gz"
    broken.write_bytes(gzip.compress(json.dumps(raw).encode()))
    for packed_columns in (False, True):
        with pytest.raises(ResultFormatError, match="broken.json.gz: a vehicle's samples: "
                           + told):
            lotsim.load_result(broken, packed=packed_columns)
