"""The runs the export tests read: the README's main run (``scenarios/mixed_lot.yaml``)
and ``scenarios/lots/ladder.yaml``, each planned once per test process and written as
``result.json`` into a folder removed at exit."""

from __future__ import annotations

import atexit
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
}
"""The runs every export is checked on (issue "Plans go out": the README's and ladder's)."""


@functools.cache
def result_path(name: str) -> Path:
    """``result.json`` of the run ``name`` (planned on first use)."""
    import lotsim

    folder = Path(tempfile.mkdtemp(prefix=f"lotsim-export-{name}-"))
    atexit.register(shutil.rmtree, folder, True)
    return lotsim.write_result(lotsim.run(RUNS[name]), folder / "result.json")


def need(module: str):
    """Import ``module`` for an export oracle: skip without it, unless
    ``LOTSIM_REQUIRE_EXPORTS=1`` (set by ``.ci/run``), where its absence fails."""
    if os.environ.get("LOTSIM_REQUIRE_EXPORTS") == "1":
        import importlib

        return importlib.import_module(module)
    return pytest.importorskip(
        module, reason=f"{module} is not installed (pip install 'lotsim[export]')"
    )
