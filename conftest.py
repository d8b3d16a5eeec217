"""What pytest collects from the package itself (its doctests, ``--doctest-modules``):
``lotsim.envs`` needs the ``learn`` extra (gymnasium and pettingzoo), and without it its
modules are left out, as the header of the run says; ``LOTSIM_REQUIRE_EXPORTS=1`` (set by
``.ci/run``) keeps them in, so that a missing extra fails. The test suite's own fixtures
are in ``tests/conftest.py``."""

from __future__ import annotations

import importlib.util
import os

LEARN = ("gymnasium", "pettingzoo")


def _missing(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is None
    except (ImportError, ValueError):
        return True


MISSING = [m for m in LEARN if _missing(m)]

collect_ignore_glob = (["lotsim/envs/*.py"]
                       if MISSING and os.environ.get("LOTSIM_REQUIRE_EXPORTS") != "1" else [])


def pytest_report_header(config):
    if collect_ignore_glob:
        return (f"lotsim.envs' doctests left out: {', '.join(MISSING)} not installed "
                f"(pip install 'lotsim[learn]')")
    return None
