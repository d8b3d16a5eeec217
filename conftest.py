"""What pytest collects from the package itself (its doctests, ``--doctest-modules``):
``lotsim.envs`` needs the ``learn`` extra (gymnasium and pettingzoo), and without it its
modules are left out, as the header of the run says; ``LOTSIM_REQUIRE_EXPORTS=1`` (set by
``.ci/run``) keeps them in, so that a missing extra fails. lotsim works in each test's own
process (:func:`one_core_each`) but in the tests marked ``cores``. The test suite's own
fixtures are in ``tests/conftest.py``."""

from __future__ import annotations

import gc
import importlib.util
import os

import pytest

LEARN = ("gymnasium", "pettingzoo")


def _missing(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is None
    except (ImportError, ValueError):
        return True


MISSING = [m for m in LEARN if _missing(m)]

collect_ignore_glob = (["lotsim/envs/*.py"]
                       if MISSING and os.environ.get("LOTSIM_REQUIRE_EXPORTS") != "1" else [])


SUITE_GC_THRESHOLDS = (10_000, 20, 20)
"""The cycle collector's thresholds in the suite's processes (Python's are 700, 10, 10):
the tests prepare and plan lots, making millions of objects and almost no cycles, as
lotsim.sim.running.RUN_GC_THRESHOLDS says of ``lotsim run``; the collections come in
larger batches (a few per cent of the suite's time). Nothing is frozen, so that the tests
of lotsim's own tuning (collector_tuned) see the collector as a user's process has it."""


def pytest_configure(config):
    gc.set_threshold(*SUITE_GC_THRESHOLDS)


def pytest_report_header(config):
    if collect_ignore_glob:
        return (f"lotsim.envs' doctests left out: {', '.join(MISSING)} not installed "
                f"(pip install 'lotsim[learn]')")
    return None


@pytest.fixture(autouse=True)
def one_core_each(request, monkeypatch):
    """lotsim's default number of worker processes is one (as in a worker of the bench):
    pytest-xdist already keeps every core busy with a test each, and work shared out over
    forked workers on a busy machine costs more processor time than it saves (forking, each
    worker building the lot's trees again), where the answers are the same on any number of
    workers. Tests marked ``cores`` keep the machine's cores (those of lotsim's workers
    themselves); a test may still ask for workers, ``workers=2``."""
    if request.node.get_closest_marker("cores") is None:
        import lotsim.core.workers

        monkeypatch.setattr(lotsim.core.workers, "_default_workers", lambda: 1)
