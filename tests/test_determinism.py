"""Same scenario and seed ⇒ the same result.json, byte for byte, in fresh processes whatever
their string-hash seed (``PYTHONHASHSEED``), so no set or dict iteration order leaks into
a plan."""

import os
import subprocess
import sys

from conftest import ROOT


def _run(tmp_path, name, hashseed, *extra):
    out = tmp_path / f"{name}-{hashseed}"
    # prepared from scratch each time: the lot's planning is what must not depend on it
    env = {**os.environ, "PYTHONHASHSEED": str(hashseed), "LOTSIM_CACHE_DIR": "off"}
    subprocess.run([sys.executable, "-m", "lotsim", "run", str(ROOT / "scenarios" / name),
                    "-o", str(out), "--no-gif", *extra],
                   check=True, env=env, capture_output=True, cwd=tmp_path, timeout=600)
    return (out / "result.json").read_bytes()


def test_results_do_not_depend_on_the_hash_seed(tmp_path):
    # the street: three vehicle types, arrivals and departures, parallel parking;
    # seed003: a full lot with a queue and cars turned away
    for name in ("street.yaml", "seed003_two_rows.yaml"):
        assert _run(tmp_path, name, 0) == _run(tmp_path, name, 4242), name


def test_booked_priorities_do_not_depend_on_the_hash_seed(tmp_path):
    args = ("--priority", "shortest_first")
    assert _run(tmp_path, "street.yaml", 7, *args) == _run(tmp_path, "street.yaml", 99, *args)
