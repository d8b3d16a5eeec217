"""Shared fixtures: building lots from YAML text, locating tokens in that text."""

from __future__ import annotations

import atexit
import os
import shutil
import signal
import tempfile
import textwrap
from collections.abc import Mapping
from contextlib import contextmanager
from pathlib import Path

import networkx as nx
import pytest

from lotsim.io.scenario_yaml import parse_scenario
from lotsim.io.yamlnodes import parse_text
from lotsim.roadmap.model import LotGraph
from lotsim.scenario import Scenario
from lotsim.sim.preparation import prepare_graph

ROOT = Path(__file__).resolve().parents[1]

# prepared lots are cached for this session only (and for the lotsim processes it starts):
# each lot is planned in full the first time a test prepares it, never read from a
# developer's own cache. pytest-xdist's workers inherit the folder from the process that
# started them, so they share it; that process removes it at the end.
_SESSION_CACHE = "LOTSIM_TEST_SESSION_CACHE"
if _SESSION_CACHE not in os.environ:
    os.environ[_SESSION_CACHE] = tempfile.mkdtemp(prefix="lotsim-test-cache-")
    atexit.register(shutil.rmtree, os.environ[_SESSION_CACHE], True)
os.environ["LOTSIM_CACHE_DIR"] = os.environ[_SESSION_CACHE]
SCENARIOS = sorted((ROOT / "scenarios").glob("*.yaml"))

ONE_AISLE = """\
name: small
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [50, 0], [50, 22], [0, 22]]
  aisles:
    - {id: a, centerline: [[0, 11], [50, 11]], width: 7.0, direction: one-way}
  rows:
    - {aisle: a, side: left, kind: perpendicular, count: 6, slot_width: 2.5,
       slot_length: 5.0, start: 12, id_prefix: N}
    - {aisle: a, side: right, kind: perpendicular, count: 6, slot_width: 2.5,
       slot_length: 5.0, start: 12, id_prefix: S}
  entrances:
    - {id: in, x: 3.0, y: 11.0, heading_deg: 0}
  exits:
    - {id: out, x: 44.0, y: 11.0, heading_deg: 0}
  occupied: [N1, N2, N3, N4, N5, S1, S2, S3, S4]
"""
"""A one-way aisle between two rows of six perpendicular slots, nine of them taken."""


@contextmanager
def time_limit(seconds: float):
    """Raise TimeoutError in the block after ``seconds``: a hang becomes a test failure."""
    def stop(signum, frame):
        raise TimeoutError(f"took more than {seconds:g} s")

    old = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def scenario_from_text(text: str, file: str = "t.yaml") -> Scenario:
    return parse_scenario(parse_text(textwrap.dedent(text), file))


def graph_from_text(text: str) -> LotGraph:
    return prepare_graph(scenario_from_text(text))


def position(text: str, needle: str, nth: int = 0) -> tuple[int, int]:
    """1-based (line, column) of the ``nth`` occurrence of ``needle`` in dedented ``text``.

    A ``|`` in ``needle`` marks the character meant: ``"angle_deg: |60"``.
    """
    text = textwrap.dedent(text)
    shift = needle.find("|")
    if shift >= 0:
        needle = needle.replace("|", "", 1)
    at = -1
    for _ in range(nth + 1):
        at = text.index(needle, at + 1)
    at += max(shift, 0)
    line = text.count("\n", 0, at) + 1
    col = at - (text.rfind("\n", 0, at) + 1) + 1
    return line, col


HEAVY = ("day", "large_lot")
"""Shipped scenarios whose lots take long to prepare: the tests of them are in the slow set."""


def shipped(*leave_out: str) -> list:
    """The shipped scenarios' names but ``leave_out``, as a test's parameters (those of
    :data:`HEAVY` marked slow)."""
    return [pytest.param(p.stem, marks=pytest.mark.slow) if p.stem in HEAVY else p.stem
            for p in SCENARIOS if p.stem not in leave_out]


SHIPPED = shipped()
"""Every shipped scenario's name, as a test's parameters."""


class ShippedGraphs(Mapping):
    """Every shipped scenario's lot by name, in SCENARIOS' order, each prepared when first
    asked for (a test of one lot prepares only that one; iterating prepares them all)."""

    def __init__(self) -> None:
        self._made: dict[str, LotGraph] = {}

    def __getitem__(self, name: str) -> LotGraph:
        from lotsim.io.scenario_yaml import load_scenario

        if name not in self._made:
            path = ROOT / "scenarios" / f"{name}.yaml"
            if path not in SCENARIOS:
                raise KeyError(name)
            self._made[name] = prepare_graph(load_scenario(path))
        return self._made[name]

    def __iter__(self):
        return (p.stem for p in SCENARIOS)

    def __len__(self) -> int:
        return len(SCENARIOS)


@pytest.fixture(scope="session")
def shipped_graphs() -> ShippedGraphs:
    """The shipped scenarios' lots, prepared as asked for (:class:`ShippedGraphs`); the
    session's cache shares them between pytest-xdist's workers."""
    return ShippedGraphs()


@pytest.fixture(scope="session")
def mixed_lot_doc(shipped_graphs) -> dict:
    """The README's main run (scenarios/mixed_lot.yaml, default settings) as its result
    document, planned once for the session."""
    from lotsim.io.result import result_dict
    from lotsim.io.scenario_yaml import load_scenario
    from lotsim.sim.running import simulate

    sc = load_scenario(ROOT / "scenarios" / "mixed_lot.yaml")
    return result_dict(simulate(sc, lot_graph=shipped_graphs["mixed_lot"]))


DISTURBED = """disturbances:
  stalls: {at: [{car: ada, time: 0, duration: 20}]}
  closures: [{gate: out, from: 30, to: 90}]
  taken: [{slot: S4, time: 20}]
"""
"""A disturbances section for the example scenario (lotsim.EXAMPLE): ada stalls for 20 s
from the first stop it reaches (about 3.8 s to 23.8 s), the exit closes from 30 s (from
about 35.4 s, once the car on its ground has gone) to 90 s, and a car the plan does not
know parks in S4 at 20 s."""


@pytest.fixture(scope="session")
def disturbed_doc() -> dict:
    """The example scenario driven through :data:`DISTURBED`, as its result document read
    back from JSON (a stall, a closed gate, a bay taken)."""
    import json

    import lotsim
    from lotsim.io.result import result_dict

    rr = lotsim.run(lotsim.prepare(lotsim.EXAMPLE + DISTURBED))
    return json.loads(json.dumps(result_dict(rr)))


def static_times(lg, vehicle, source):
    """Travel time lower bounds along lanes (networkx Dijkstra on length / limit)."""
    g = nx.DiGraph()
    top = vehicle.limits.max_forward_speed
    for u, v, d in lg.graph.edges(data=True):
        if d["kind"] in ("lane", "turn", "join"):
            w = d["length"] / min(d["speed_limit"], top) if d["length"] > 0 else 0.0
            g.add_edge(u, v, weight=w)
    return nx.single_source_dijkstra_path_length(g, source)
