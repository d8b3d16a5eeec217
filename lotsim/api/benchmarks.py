"""Benchmark suites (``lotsim bench``): reaching a Dask cluster to run one on
(:func:`connect_scheduler`); reading, running and reporting a suite are
:mod:`lotsim.bench`'s (``load_suite``, ``run_suite``, ``table_text``, ``hour_rows``,
``hours_text``, ``write_outputs``), offered by :mod:`lotsim.api`."""

from __future__ import annotations

from typing import Any


def connect_scheduler(address: str, *, timeout: float | None = None) -> Any:
    """A :class:`distributed.Client` of the Dask scheduler at ``address``, for
    ``run_suite(..., client=...)``; ``timeout`` [s] defaults to
    :data:`lotsim.bench.CONNECT_TIMEOUT`.

    Raises
    ------
    DaskMissing
        ``distributed`` is not installed (``pip install 'lotsim[dask]'``).
    SchedulerUnreachable
        ``address`` is malformed, or no scheduler answered there in time.
    """
    from lotsim import bench

    return bench.connect(address, timeout=bench.CONNECT_TIMEOUT if timeout is None else timeout)
