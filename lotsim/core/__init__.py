"""What every layer of lotsim uses: plane geometry (:mod:`~lotsim.core.geometry`), the worker
processes (:mod:`~lotsim.core.workers`), the on-disk cache (:mod:`~lotsim.core.diskcache`)
and atomic file writes (:mod:`~lotsim.core.atomic`). It imports nothing of lotsim but
:mod:`lotsim.errors`."""
