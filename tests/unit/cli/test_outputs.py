"""Every command's outputs: checked before the work starts, named as the user gave them in
an error, written as one set (all or none), their folders made when missing."""

from __future__ import annotations

import errno
import os

import pytest

from conftest import ROOT
from lotsim.cli import main

QUICKSTART = ROOT / "scenarios" / "quickstart.yaml"
PLOT = """\
boundary: [[0, 0], [36, 0], [36, 30], [0, 30]]
gates: [{id: south, at: [18, 0]}]
bays: {angles_deg: [90]}
demand: {count: 4}
"""
SUITE = """\
name: tiny
scenarios: [quickstart.yaml]
planners: [hca]
assignments: [shortest]
seeds: [1]
"""


def _files(folder) -> list[str]:
    """Every file and folder under ``folder``, hidden ones too, as relative paths."""
    return sorted(os.path.relpath(p, folder) for p in folder.rglob("*"))


@pytest.fixture
def here(tmp_path, monkeypatch):
    """A folder to work in, holding a regular file (``file.txt``: a folder cannot be made
    under it, even by root, for whom no folder is read-only)."""
    (tmp_path / "file.txt").write_text("not a folder")
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.fixture(scope="module")
def result_json(tmp_path_factory):
    out = tmp_path_factory.mktemp("run")
    assert main(["run", str(QUICKSTART), "-o", str(out), "--no-gif"]) == 0
    return out / "result.json"


def test_run_into_a_folder_that_cannot_be_made_says_which_and_why(here, capsys):
    assert main(["run", str(QUICKSTART), "-o", "file.txt/sub"]) == 2
    cap = capsys.readouterr()
    assert cap.err == "lotsim: -o file.txt/sub: 'file.txt' is a file, not a folder\n"
    assert cap.out == ""  # nothing planned
    assert _files(here) == ["file.txt"]


@pytest.mark.skipif(os.geteuid() == 0, reason="as root no folder is read-only (chmod does "
                    "not stop root writing); the folder that cannot be made is tested above")
def test_run_into_a_read_only_folder_says_which_and_why(here, capsys):
    (here / "ro").mkdir()
    (here / "ro").chmod(0o555)
    try:
        assert main(["run", str(QUICKSTART), "-o", "ro/out"]) == 2
        assert main(["run", str(QUICKSTART), "-o", "ro"]) == 2
    finally:
        (here / "ro").chmod(0o755)
    err = capsys.readouterr().err
    assert err.splitlines() == [
        "lotsim: -o ro/out: cannot make the folder 'ro/out' (Permission denied)",
        "lotsim: -o ro: cannot write in the folder 'ro' (Permission denied)"]
    assert _files(here) == ["file.txt", "ro"]


def test_run_checks_every_picture_before_planning_and_writes_none_of_its_set(here, capsys):
    """``-o ok --html file.txt/replay.html`` planned, wrote result.json and run.gif, then
    failed on the replay, leaving them behind."""
    assert main(["run", str(QUICKSTART), "-o", "ok", "--gif", "ok/run.gif",
                 "--html", "file.txt/replay.html"]) == 2
    cap = capsys.readouterr()
    assert cap.err == ("lotsim: --html file.txt/replay.html: 'file.txt' is a file, not a "
                       "folder\n")
    assert cap.out == ""
    assert _files(here) == ["file.txt"]  # not even the folder 'ok' the check made


def test_run_makes_the_folders_of_its_pictures(here, capsys):
    assert main(["run", str(QUICKSTART), "-o", "a/out", "--no-gif",
                 "--html", "b/c/replay.html"]) == 0
    assert _files(here) == ["a", "a/out", "a/out/result.json", "b", "b/c", "b/c/replay.html",
                            "file.txt"]
    assert "wrote b/c/replay.html: " in capsys.readouterr().out


def test_an_error_while_writing_names_the_users_path_and_leaves_nothing(here, capsys,
                                                                        monkeypatch):
    def full(doc, path, *args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr("lotsim.api.render_html", full)
    assert main(["run", str(QUICKSTART), "-o", "out", "--no-gif",
                 "--html", "out/replay.html"]) == 2
    err = capsys.readouterr().err
    assert err.splitlines()[-1] == "lotsim: out/replay.html: cannot write: No space left on device"
    assert ".tmp" not in err and ".lotsim-" not in err
    assert _files(here) == ["file.txt"]


def test_bench_checks_its_folder_before_the_runs(here, capsys):
    (here / "quickstart.yaml").write_text(QUICKSTART.read_text())
    (here / "suite.yaml").write_text(SUITE)
    assert main(["bench", "suite.yaml", "-o", "file.txt/bench", "--jobs", "1"]) == 2
    cap = capsys.readouterr()
    assert cap.err == "lotsim: -o file.txt/bench: 'file.txt' is a file, not a folder\n"
    assert cap.out == ""  # no run started
    assert main(["bench", "suite.yaml", "-o", "new/bench", "--jobs", "1"]) == 0
    assert {"runs.csv", "summary.md"} <= {p.name for p in (here / "new" / "bench").iterdir()}
    assert not [p for p in (here / "new").rglob(".*")]  # no staging folder left


def test_layout_checks_its_file_before_the_search_and_names_no_temporary(here, capsys,
                                                                         monkeypatch):
    (here / "plot.yaml").write_text(PLOT)
    assert main(["layout", "plot.yaml", "-o", "file.txt/lot.yaml"]) == 2
    cap = capsys.readouterr()
    assert cap.err == "lotsim: -o file.txt/lot.yaml: 'file.txt' is a file, not a folder\n"
    assert cap.out == ""

    def full(plot, output, **kwargs):  # the disk fills as the scenario is written
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC),
                      str(output.with_name(f".{output.name}.hg8_2z9g.tmp")))

    monkeypatch.setattr("lotsim.api.layout", full)
    assert main(["layout", "plot.yaml", "-o", "new/lot.yaml"]) == 2
    assert capsys.readouterr().err == ("lotsim: new/lot.yaml: cannot write: No space left on "
                                       "device\n")
    assert _files(here) == ["file.txt", "plot.yaml"]


@pytest.mark.slow
def test_layout_makes_its_folder(here, capsys):
    (here / "plot.yaml").write_text(PLOT)
    assert main(["layout", "plot.yaml", "-o", "new/lot.yaml", "--offsets", "1",
                 "--orientations", "1", "--prepared", "1"]) == 0
    assert _files(here) == ["file.txt", "new", "new/lot.yaml", "plot.yaml"]
    assert "wrote new/lot.yaml: " in capsys.readouterr().out


def test_export_checks_every_folder_first_and_names_the_one_typed(here, result_json, capsys):
    assert main(["export", str(result_json), "--sumo", "out/sumo", "--openscenario",
                 "file.txt/xosc"]) == 2
    err = capsys.readouterr().err
    assert err == "lotsim: --openscenario file.txt/xosc: 'file.txt' is a file, not a folder\n"
    assert _files(here) == ["file.txt"]


def test_render_and_show_make_a_missing_folder(here, result_json, capsys):
    assert main(["render", str(result_json), "--html", "new/a/replay.html"]) == 0
    assert main(["show", str(QUICKSTART), "-o", "pictures/lot.png", "--size", "400x300"]) == 0
    assert main(["show", str(QUICKSTART), "-o", "file.txt/lot.png"]) == 2
    cap = capsys.readouterr()
    assert "wrote new/a/replay.html: replay of 6 vehicles" in cap.out
    assert "wrote pictures/lot.png" in cap.out
    assert cap.err == "lotsim: -o file.txt/lot.png: 'file.txt' is a file, not a folder\n"
    assert _files(here) == ["file.txt", "new", "new/a", "new/a/replay.html", "pictures",
                            "pictures/lot.png"]


def test_render_writes_all_its_files_or_none(here, result_json, capsys, monkeypatch):
    def broken(doc, path, *args, **kwargs):
        from lotsim.errors import ReplayError

        raise ReplayError("vehicles[0].path: not drawable")

    monkeypatch.setattr("lotsim.api.render_html", broken)
    argv = ["render", str(result_json), "--gif", "out/run.gif", "--html", "out/replay.html",
            "--size", "320x240", "--to", "5"]
    assert main(argv) == 2
    assert "cannot draw this result" in capsys.readouterr().err
    assert _files(here) == ["file.txt"]  # the GIF drawn first is not left alone


def test_a_set_of_outputs_refuses_a_file_named_twice_and_leaves_nothing(here):
    from lotsim.api import OutputSet
    from lotsim.errors import OutputError

    with OutputSet() as outputs, pytest.raises(OutputError, match="named twice"):
        outputs.file("x/a.gif", name="--gif x/a.gif")
        outputs.file("x/../x/a.gif", name="--mp4 x/a.gif")
    assert _files(here) == ["file.txt"]
