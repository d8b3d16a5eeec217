"""Ctrl-C on a real ``lotsim`` process: it stops with exit 130, says what it had written,
and leaves no partial result.json, GIF or temporary file.

The interrupt goes to the whole process group, as a terminal's Ctrl-C does.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import ROOT
from lotsim.check import check_result

SCENARIOS = ROOT / "scenarios"


def _start(*args: str, cwd) -> subprocess.Popen:
    env = dict(os.environ, PYTHONUNBUFFERED="1", LOTSIM_CACHE_DIR="off")  # plans in full
    return subprocess.Popen([sys.executable, "-m", "lotsim", *args], cwd=cwd, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)


def _ctrl_c(proc: subprocess.Popen) -> tuple[int, str, str]:
    os.killpg(proc.pid, signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    return proc.returncode, out, err


def _wait_for(condition, proc: subprocess.Popen, timeout: float = 120.0) -> None:
    end = time.monotonic() + timeout
    while not condition():
        assert proc.poll() is None, f"lotsim ended first: {proc.communicate()}"
        assert time.monotonic() < end, "timed out"
        time.sleep(0.02)


def test_ctrl_c_while_planning_writes_nothing(tmp_path):
    """The large lot takes ~20 s to prepare and plan: interrupted after 4 s."""
    proc = _start("run", str(SCENARIOS / "large_lot.yaml"), "-o", "out", "--no-gif",
                  cwd=tmp_path)
    time.sleep(4.0)
    assert proc.poll() is None
    code, out, err = _ctrl_c(proc)
    assert code == 130
    assert err.strip().splitlines()[-1] == "lotsim: interrupted; nothing was written", err
    assert "Traceback" not in err
    assert not (tmp_path / "out").exists() or list((tmp_path / "out").iterdir()) == []


def test_ctrl_c_while_drawing_the_gif_keeps_result_json_and_no_gif(tmp_path):
    """The mixed lot's GIF takes ~13 s after result.json is written: interrupted half a
    second after result.json appears."""
    out_dir = tmp_path / "out"
    proc = _start("run", str(SCENARIOS / "mixed_lot.yaml"), "-o", "out", cwd=tmp_path)
    _wait_for(lambda: (out_dir / "result.json").exists(), proc)
    time.sleep(0.5)
    assert proc.poll() is None
    code, out, err = _ctrl_c(proc)
    assert code == 130, err
    assert f"interrupted; {os.path.join('out', 'result.json')} was written, the GIF was not" \
        in err, err
    assert "Traceback" not in err
    assert sorted(p.name for p in out_dir.iterdir()) == ["result.json"]  # no GIF, no temp file
    doc = json.loads((out_dir / "result.json").read_text())
    assert check_result(doc).ok
    assert "wrote out/result.json" in out.replace(os.sep, "/")


@pytest.mark.parametrize("when", [0.3, 1.5])
def test_ctrl_c_while_rendering_leaves_an_older_gif_untouched(tmp_path, when):
    """``lotsim render`` over an existing GIF: interrupted, the old GIF is still whole."""
    proc = _start("run", str(SCENARIOS / "quickstart.yaml"), "-o", "out", "--no-gif",
                  cwd=tmp_path)
    assert proc.wait(timeout=120) == 0, proc.communicate()
    old = tmp_path / "old.gif"
    old.write_bytes(b"GIF89a an older picture")
    proc = _start("render", "out/result.json", "--gif", "old.gif", "--fps", "50", "--speed",
                  "0.2", cwd=tmp_path)
    time.sleep(when + 1.0)  # imports take about a second
    if proc.poll() is not None:
        pytest.fail(f"render ended before the interrupt: {proc.communicate()}")
    code, out, err = _ctrl_c(proc)
    assert code == 130 and "Traceback" not in err, err
    assert err.strip().splitlines()[-1] == "lotsim: interrupted; nothing was written", err
    assert old.read_bytes() == b"GIF89a an older picture"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.gif", "out"]


def test_ctrl_c_during_a_benchmark_on_two_processes_writes_nothing(tmp_path):
    """The runs in flight (each takes several seconds) are stopped, not waited for, and no
    worker prints a traceback."""
    proc = _start("bench", str(SCENARIOS / "bench" / "seed004.yaml"), "-o", "out", "--jobs",
                  "2", cwd=tmp_path)
    time.sleep(8.0)
    assert proc.poll() is None
    clock = time.monotonic()
    code, out, err = _ctrl_c(proc)
    assert time.monotonic() - clock < 5.0
    assert code == 130
    assert err.strip() == "lotsim: interrupted; nothing was written", err
    assert not (tmp_path / "out").exists()
