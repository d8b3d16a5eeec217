"""Exports of a run (a ``result.json``) to other tools' formats (``docs/export.md``).

Each reads only the result document and needs its own optional packages, imported when it
runs, so that ``import lotsim`` does not:

* :func:`export_commonroad`: a CommonRoad scenario, planning problems and a KS solution
  (``pip install 'lotsim[commonroad]'``);
* :func:`export_sumo`: a SUMO network, parking areas, routes and a ``.sumocfg``
  (``pip install 'lotsim[sumo]'``);
* :func:`export_openscenario`: an OpenSCENARIO file with every car's timed trajectory and
  the lot as OpenDRIVE (``pip install 'lotsim[openscenario]'``).
"""

from __future__ import annotations

from lotsim.io.export.commonroad import CommonRoadInfo, export_commonroad
from lotsim.io.export.tracks import ExportError, ExportUnavailable

__all__ = ["CommonRoadInfo", "ExportError", "ExportUnavailable", "export_commonroad"]
