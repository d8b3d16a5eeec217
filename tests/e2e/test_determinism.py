"""Same scenario and seed ⇒ the same result.json, byte for byte, in fresh processes whatever
their string-hash seed (``PYTHONHASHSEED``), so no set or dict iteration order leaks into
a plan."""

import os
import subprocess
import sys

import pytest

from conftest import ROOT


def _results(tmp_path, name, hashseeds, *extra) -> list[bytes]:
    """result.json of ``lotsim run`` on the scenario ``name`` in one fresh process per hash
    seed, run side by side (they are independent: the suite waits for the slower only)."""
    procs = []
    for hashseed in hashseeds:
        out = tmp_path / f"{name}-{hashseed}"
        # prepared from scratch each time: the lot's planning is what must not depend on it
        env = {**os.environ, "PYTHONHASHSEED": str(hashseed), "LOTSIM_CACHE_DIR": "off"}
        procs.append((out, subprocess.Popen(
            [sys.executable, "-m", "lotsim", "run", str(ROOT / "scenarios" / name), "-o",
             str(out), "--no-gif", *extra], env=env, cwd=tmp_path,
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)))
    for _, proc in procs:
        _, err = proc.communicate(timeout=600)
        assert proc.returncode == 0, err.decode()
    return [(out / "result.json").read_bytes() for out, _ in procs]


@pytest.mark.slow
def test_results_do_not_depend_on_the_hash_seed(tmp_path):
    # the street: three vehicle types, arrivals and departures, parallel parking;
    # two rows: a full lot with a queue and cars turned away
    for name in ("street.yaml", "two_rows.yaml"):
        a, b = _results(tmp_path, name, (0, 4242))
        assert a == b, name


@pytest.mark.slow
def test_booked_priorities_do_not_depend_on_the_hash_seed(tmp_path):
    a, b = _results(tmp_path, "street.yaml", (7, 99), "--priority", "shortest_first")
    assert a == b
