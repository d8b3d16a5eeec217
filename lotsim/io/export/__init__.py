"""Exports of a run (a ``result.json``) to other tools' formats (``docs/export.md``).

Each reads only the result document and needs its own optional packages, imported when it
runs, so that ``import lotsim`` does not:

* :func:`write_commonroad`: CommonRoad scenarios and KS solutions, one per trip
  (``pip install 'lotsim[commonroad]'``);
* :func:`write_sumo`: a SUMO network, parking areas, trips and configuration
  (``pip install 'lotsim[sumo]'``);
* :func:`write_openscenario`: OpenSCENARIO with a timed trajectory per car on an OpenDRIVE
  lot with a ``parkingSpace`` per slot (``pip install 'lotsim[openscenario]'``).

and one writes a built lot (a scenario's, or a result's ``lot.drawing``) for CAD:

* :func:`write_dxf`: a DXF drawing in metres, each kind of thing on its named layer
  (:mod:`lotsim.io.cad_layers`; ``pip install 'lotsim[dxf]'``).
"""

from __future__ import annotations

from lotsim.io.export.commonroad import CommonRoadInfo, write_commonroad
from lotsim.io.export.dxf import DxfInfo, write_dxf
from lotsim.io.export.openscenario import OpenScenarioInfo, write_openscenario
from lotsim.io.export.sumo import SumoInfo, write_sumo
from lotsim.io.export.tracks import ExportError, ExportUnavailable

__all__ = [
    "CommonRoadInfo",
    "DxfInfo",
    "ExportError",
    "ExportUnavailable",
    "OpenScenarioInfo",
    "SumoInfo",
    "write_commonroad",
    "write_dxf",
    "write_openscenario",
    "write_sumo",
]
