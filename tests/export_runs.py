"""The runs the export tests read: the README's main run (``scenarios/mixed_lot.yaml``),
``scenarios/lots/ladder.yaml`` and a stepped run of the quickstart lot with cars that are
inside the lot when they come (:func:`inside_run`), each planned once for the test session
(by whichever of pytest-xdist's workers asks first, the others waiting for it and reading its
file) and written as ``result.json`` into the session's folder, removed at exit."""

from __future__ import annotations

import atexit
import fcntl
import functools
import os
import shutil
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RUNS = {
    "mixed_lot": ROOT / "scenarios" / "mixed_lot.yaml",
    "ladder": ROOT / "scenarios" / "lots" / "ladder.yaml",
    "inside": ROOT / "scenarios" / "quickstart.yaml",
}
"""The runs every export is checked on: the README's, ladder's, and the quickstart lot's
with cars inside it (:func:`inside_run`)."""
SLOW_RUNS = ("ladder",)
"""Runs whose planning takes long: their exports are checked in the slow set."""


def run_params() -> list:
    """:data:`RUNS`' names as a fixture's params, those of :data:`SLOW_RUNS` marked slow."""
    import pytest

    return [pytest.param(n, marks=pytest.mark.slow) if n in SLOW_RUNS else n
            for n in sorted(RUNS)]


def inside_run(path: Path):
    """The lot of ``path`` stepped with cars that are in it when they come: one standing in
    a bay, called out after 20 s; one standing on the entrance lane, which looks for a slot;
    and two that come by the gate (each leaves again: SUMO reports a trip when it ends)."""
    import lotsim

    live = lotsim.Live(lotsim.prepare(path), traffic=False)
    lg = live.prepared.lot_graph
    gate = min(lg.entrances)
    bay = sorted(s.id for s in lg.lot.free_slots)[-1]
    live.add("called", _type(live), slot=bay, dwell=20.0)
    node = next(n for n in lg.graph.successors(lg.entrances[gate])
                if lg.graph.nodes[n].get("kind") == "lane")
    live.add("dropped", _type(live), pose=lg.graph.nodes[node]["pose"], dwell=25.0)
    live.add("first", _type(live), gate, at=2.0, dwell=30.0)
    live.add("second", _type(live), gate, at=6.0, dwell=25.0)
    return live.finish()


def _type(live) -> str:
    return live.prepared.scenario.vehicle_types[0].name


@functools.cache
def result_path(name: str) -> Path:
    """``result.json`` of the run ``name``, planned on first use in the session: the runs
    are the same in every process, so one plans it and the others read its file."""
    import lotsim

    shared = os.environ.get("LOTSIM_TEST_SESSION_CACHE")  # tests/conftest.py's
    if shared is None:  # this module imported on its own
        shared = tempfile.mkdtemp(prefix="lotsim-export-runs-")
        atexit.register(shutil.rmtree, shared, True)
    runs = Path(shared) / "export-runs"
    runs.mkdir(exist_ok=True)
    path = runs / name / "result.json"
    with open(runs / f".{name}.lock", "wb") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # another process planning it: wait, then read it
        if not path.exists():
            folder = Path(tempfile.mkdtemp(prefix=f".{name}-", dir=runs))
            result = inside_run(RUNS[name]) if name == "inside" else lotsim.run(RUNS[name])
            lotsim.write_result(result, folder / "result.json")
            os.replace(folder, path.parent)  # whole or not at all
    return path


def need(module: str, extra: str = "export"):
    """Import ``module`` of the optional ``extra`` (an export oracle's, or ``learn`` for the
    learning environments): skip without it, unless ``LOTSIM_REQUIRE_EXPORTS=1`` (set by
    ``.ci/run``), where its absence fails."""
    if os.environ.get("LOTSIM_REQUIRE_EXPORTS") == "1":
        import importlib

        return importlib.import_module(module)
    return pytest.importorskip(
        module, reason=f"{module} is not installed (pip install 'lotsim[{extra}]')"
    )
