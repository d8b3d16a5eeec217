"""Ctrl-C on a real ``lotsim`` process: it stops with exit 130, says what it had written,
and leaves no partial result.json, GIF or temporary file.

The interrupt goes to the whole process group, as a terminal's Ctrl-C does, at a moment
told by what the process shows (its progress on a terminal, its files, its workers), not
by the clock.
"""

from __future__ import annotations

import os
import pty
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from conftest import ROOT

SCENARIOS = ROOT / "scenarios"


def _start(*args: str, cwd, terminal: bool = False) -> subprocess.Popen:
    """``lotsim ARGS`` in its own process group; with ``terminal``, its stderr is a
    pseudo-terminal (so it shows its progress), read into ``proc.shown``."""
    env = dict(os.environ, PYTHONUNBUFFERED="1", LOTSIM_CACHE_DIR="off")  # plans in full
    master = None
    if terminal:
        master, stderr = pty.openpty()
    else:
        stderr = subprocess.PIPE
    # Ctrl-C as at a terminal even when the suite itself ignores it (run in the background,
    # a shell gives its jobs SIGINT ignored, and lotsim would inherit that)
    proc = subprocess.Popen([sys.executable, "-m", "lotsim", *args], cwd=cwd, env=env,
                            stdout=subprocess.PIPE, stderr=stderr, text=True,
                            start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    proc.shown = []
    if master is not None:
        os.close(stderr)

        def read() -> None:
            while True:
                try:
                    chunk = os.read(master, 4096)
                except OSError:  # the process closed its end
                    chunk = b""
                if not chunk:
                    os.close(master)
                    return
                proc.shown.append(chunk.decode(errors="replace"))

        proc.reader = threading.Thread(target=read, daemon=True)
        proc.reader.start()
    return proc


def _ctrl_c(proc: subprocess.Popen) -> tuple[int, str, str]:
    os.killpg(proc.pid, signal.SIGINT)
    out, err = proc.communicate(timeout=60)  # a hang guard, not a measure of speed
    if err is None:  # a terminal: what it shows last, after the progress line it clears
        proc.reader.join(timeout=60)
        err = "".join(proc.shown).replace("\r\n", "\n").split("\r")[-1]
    return proc.returncode, out, err


def _wait_for(condition, proc: subprocess.Popen, timeout: float = 120.0) -> None:
    end = time.monotonic() + timeout  # a hang guard, not a measure of speed
    while not condition():
        assert proc.poll() is None, f"lotsim ended first: {proc.communicate()}"
        assert time.monotonic() < end, "timed out"
        time.sleep(0.02)


def _temporary(folder: Path, name: str) -> list[Path]:
    """The temporary files :func:`lotsim.core.atomic.atomic_write` is writing ``name`` into,
    beside it or in the staging folder of a command's outputs."""
    return list(folder.glob(f".{name}.*.tmp")) + list(folder.glob(f".lotsim-*/.{name}.*.tmp"))


def _workers(proc: subprocess.Popen) -> dict[int, float]:
    """The live processes of ``proc``'s group that are not its children (the pool's workers,
    started by the forkserver) and the processor time each has used [s] (Linux's /proc)."""
    found = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue  # ended while we looked
        state, parent, group = fields[0], int(fields[1]), int(fields[2])
        pid = int(stat.parent.name)
        if group == proc.pid and state != "Z" and proc.pid not in (parent, pid):
            found[pid] = (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    return found


@pytest.mark.slow
def test_ctrl_c_while_planning_writes_nothing(tmp_path):
    """The large lot takes ~20 s to prepare and plan: interrupted while its maneuvers are
    planned."""
    proc = _start("run", str(SCENARIOS / "large_lot.yaml"), "-o", "out", "--no-gif",
                  cwd=tmp_path, terminal=True)
    _wait_for(lambda: "planning maneuvers [" in "".join(proc.shown), proc)
    code, out, err = _ctrl_c(proc)
    assert code == 130
    assert err.strip().splitlines()[-1] == "lotsim: interrupted; nothing was written", err
    assert "Traceback" not in err
    assert not (tmp_path / "out").exists() or list((tmp_path / "out").iterdir()) == []


@pytest.mark.slow
def test_ctrl_c_while_drawing_the_gif_writes_nothing(tmp_path):
    """The mixed lot's GIF of its whole first quarter hour (quiet stretches kept) takes
    ~13 s after the result is staged: interrupted while its frames go into the temporary
    file, the run's outputs are one set, and none of it is written."""
    out_dir = tmp_path / "out"
    text = (SCENARIOS / "mixed_lot.yaml").read_text()
    assert "skip_quiet: true" in text
    (tmp_path / "mixed.yaml").write_text(text.replace("skip_quiet: true", "skip_quiet: false"))
    proc = _start("run", "mixed.yaml", "-o", "out", cwd=tmp_path)
    _wait_for(lambda: any(f.stat().st_size for f in _temporary(out_dir, "run.gif")), proc)
    code, out, err = _ctrl_c(proc)
    assert code == 130, err
    assert err.strip().splitlines()[-1] == "lotsim: interrupted; nothing was written", err
    assert "Traceback" not in err
    assert not out_dir.exists()  # not even the folder the run made for its outputs
    assert "wrote" not in out


@pytest.fixture(scope="module")
def quickstart_result() -> bytes:
    """quickstart's result.json, as ``lotsim run`` writes it (the run itself is not what
    these tests interrupt)."""
    import tempfile

    import lotsim

    with tempfile.TemporaryDirectory() as folder:
        path = lotsim.write_result(lotsim.run(SCENARIOS / "quickstart.yaml"),
                                   Path(folder) / "result.json")
        return path.read_bytes()


@pytest.mark.slow
@pytest.mark.parametrize("written", [False, True])
def test_ctrl_c_while_rendering_leaves_an_older_gif_untouched(tmp_path, written,
                                                              quickstart_result):
    """``lotsim render`` over an existing GIF: interrupted as soon as the new one is opened
    beside it, or once frames are in it, the old GIF is still whole."""
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "result.json").write_bytes(quickstart_result)
    old = tmp_path / "old.gif"
    old.write_bytes(b"GIF89a an older picture")
    proc = _start("render", "out/result.json", "--gif", "old.gif", "--fps", "50", "--speed",
                  "0.2", cwd=tmp_path)
    _wait_for(lambda: any(f.stat().st_size >= written
                          for f in _temporary(tmp_path, "old.gif")), proc)
    code, out, err = _ctrl_c(proc)
    assert code == 130 and "Traceback" not in err, err
    assert err.strip().splitlines()[-1] == "lotsim: interrupted; nothing was written", err
    assert old.read_bytes() == b"GIF89a an older picture"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.gif", "out"]


@pytest.mark.slow
def test_ctrl_c_during_a_benchmark_on_two_processes_writes_nothing(tmp_path):
    """The runs in flight (each takes several seconds) are stopped with lotsim, and no
    worker prints a traceback."""
    if not Path("/proc/self/stat").exists():
        pytest.skip("finds the workers in /proc")
    proc = _start("bench", str(SCENARIOS / "bench" / "valet.yaml"), "-o", "out", "--jobs",
                  "2", cwd=tmp_path)
    # two runs in flight: two workers past their start-up (imports take about 0.5 s of
    # processor time; an interrupt then is reported by multiprocessing itself)
    _wait_for(lambda: sum(cpu >= 1.5 for cpu in _workers(proc).values()) >= 2, proc)
    workers = set(_workers(proc))
    code, out, err = _ctrl_c(proc)
    assert not set(_workers(proc)) & workers  # stopped with lotsim: none outlives it
    assert code == 130 and "Traceback" not in err, err
    # (on a busy machine the runs' progress may have had time to show first)
    assert err.strip().splitlines()[-1] == "lotsim: interrupted; nothing was written", err
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
@pytest.mark.parametrize("moment", ["starting", "importing"])
def test_ctrl_c_while_benchmark_workers_start_is_one_line_and_exit_130(tmp_path, moment):
    """An interrupt while the pool's workers are still starting (the forkserver's children
    importing lotsim) or before there are any: no worker or forkserver prints a traceback."""
    if not Path("/proc/self/stat").exists():
        pytest.skip("finds the workers in /proc")
    proc = _start("bench", str(SCENARIOS / "bench" / "valet.yaml"), "-o", "out", "--jobs",
                  "2", cwd=tmp_path)
    if moment == "importing":  # a worker has appeared and has not yet done its imports
        _wait_for(lambda: any(cpu < 0.3 for cpu in _workers(proc).values()), proc)
    else:  # the forkserver or the resource tracker (children of lotsim's) has appeared
        _wait_for(lambda: any(_children(proc)), proc)
    code, out, err = _ctrl_c(proc)
    assert code == 130, err
    assert err.strip() == "lotsim: interrupted; nothing was written", err
    assert not (tmp_path / "out").exists()
    end = time.monotonic() + 30  # the forkserver and its workers go soon after lotsim
    while _workers(proc):
        assert time.monotonic() < end, _workers(proc)
        time.sleep(0.05)


def _children(proc: subprocess.Popen) -> list[int]:
    """The live processes whose parent is ``proc``."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == proc.pid and fields[0] != "Z":
            found.append(int(stat.parent.name))
    return found
