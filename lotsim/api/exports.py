"""A run in other tools' formats (``lotsim export``, ``docs/export.md``): CommonRoad, SUMO
and OpenSCENARIO; and a lot, of a scenario or a run, as a DXF drawing for CAD. Each format's
packages are an optional extra, imported only when its export is asked for."""

from __future__ import annotations

import os
from typing import Any

from lotsim.api.results import result_document
from lotsim.core import checks as _checks
from lotsim.errors import SettingsError
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.model import Lot
from lotsim.scenario import Scenario
from lotsim.sim.results import RunResult


def export_commonroad(result: RunResult | dict | str | os.PathLike, folder: str | os.PathLike,
                      *, dt: float = 0.1):
    """Write a run as CommonRoad files (``lotsim export --commonroad``, ``docs/export.md``):
    ``scenario.xml`` (the lot's boundary, walls, islands and parked cars as obstacles, each
    car's dwell in its slot, one planning problem per trip in or out) and ``solution.xml``
    (a kinematic single-track trajectory per planning problem, on the uniform step ``dt``
    [s], positions at the CommonRoad vehicle's centre).

    Needs ``pip install 'lotsim[commonroad]'``; raises ``ExportUnavailable`` (a
    :class:`LotsimError`) without it. Returns a ``CommonRoadInfo`` (files, counts, the
    resampling error [m, rad], bytes).
    """
    if not (_checks.is_real(dt) and 0.01 <= dt <= 1.0):
        raise SettingsError("dt", f"expected 0.01 to 1 s, found {_checks.shown(dt)}")
    from lotsim.io.export import write_commonroad as write

    return write(result_document(result), folder, dt=dt)



def export_sumo(result: RunResult | dict | str | os.PathLike, folder: str | os.PathLike,
                *, step: float = 0.1):
    """Write a run as a SUMO simulation (``lotsim export --sumo``, ``docs/export.md``): the
    aisles as a network built by ``netconvert`` (``lot.net.xml``), a parking area per slot
    with one space at the pose a car stands in it (``lot.add.xml``), each car as a trip from
    its entrance at its arrival time through a stop in its slot until it moved off, to its
    exit (``lot.rou.xml``), and ``lot.sumocfg`` to run them on the step ``step`` [s].

    Needs ``pip install 'lotsim[sumo]'``; raises ``ExportUnavailable`` (a
    :class:`LotsimError`) without it. Returns a ``SumoInfo`` (files, spaces, trips, bytes).
    """
    if not (_checks.is_real(step) and 0.001 <= step <= 1.0):
        raise SettingsError("step", f"expected 0.001 to 1 s, found {_checks.shown(step)}")
    from lotsim.io.export import write_sumo as write

    return write(result_document(result), folder, step=step)


def export_openscenario(result: RunResult | dict | str | os.PathLike,
                        folder: str | os.PathLike):
    """Write a run as OpenSCENARIO and OpenDRIVE (``lotsim export --openscenario``,
    ``docs/export.md``): ``lot.xodr`` (OpenDRIVE 1.7: a road per aisle, a ``parkingSpace``
    object per slot) and ``lot.xosc`` (OpenSCENARIO 1.2: a vehicle per car following a
    timed polyline of its rear-axle centre, within 1 cm and 2 mrad of every sample).

    Needs ``pip install 'lotsim[openscenario]'``; raises ``ExportUnavailable`` (a
    :class:`LotsimError`) without it. Returns an ``OpenScenarioInfo`` (files, counts, the
    polylines' error [m, rad], bytes).
    """
    from lotsim.io.export import write_openscenario as write

    return write(result_document(result), folder)


LotLike = Any
"""What :func:`export_dxf` draws the lot of: a scenario (a :class:`~lotsim.scenario.Scenario`,
a :class:`~lotsim.sim.preparation.PreparedLot`, a scenario file or its YAML text) or a run (a
:class:`~lotsim.sim.results.RunResult`, its document, or a ``result.json``)."""


def lot_of(source: LotLike) -> Lot:
    """The built lot of a scenario or of a run (:data:`LotLike`): a scenario's lot is built
    for its vehicle types (as ``lotsim show`` builds it, without planning a maneuver), a
    run's read back from its ``lot.drawing``."""
    return _scenario_and_lot(source)[1]


def _scenario_and_lot(source: LotLike) -> tuple[Scenario | None, Lot]:
    """:func:`lot_of`, and the scenario it is of (None for a run's)."""
    from lotsim.io.file_kinds import file_kind
    from lotsim.io.lot_json import lot_from_json
    from lotsim.lot.build import build_lot
    from lotsim.lot.model import DesignVehicle
    from lotsim.sim.preparation import PreparedLot

    if isinstance(source, PreparedLot):
        return source.scenario, source.lot
    if isinstance(source, RunResult):
        return None, source.lot_graph.lot
    is_file = isinstance(source, os.PathLike) or (isinstance(source, str)
                                                  and "\n" not in source)
    if isinstance(source, dict) or (is_file and file_kind(source) == "result"):
        lot = result_document(source).get("lot")
        drawing = lot.get("drawing") if isinstance(lot, dict) else None
        if drawing is None:
            raise SettingsError("source", "expected a result document with a lot.drawing "
                                          "(docs/result.md)")
        return None, lot_from_json(drawing, root="lot.drawing")
    if not isinstance(source, (Scenario, str, os.PathLike)):
        raise SettingsError("source", f"expected a scenario or a run (a Scenario, "
                                      f"PreparedLot, RunResult, result dict or a path), "
                                      f"found {type(source).__name__}")
    scenario = source if isinstance(source, Scenario) else load_scenario(source)
    return scenario, build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))


def export_dxf(source: LotLike, path: str | os.PathLike, *, units: str | None = None):
    """Write the lot of a scenario or of a run (:data:`LotLike`) as a DXF drawing for CAD
    (``lotsim export --dxf``, ``docs/export.md``): its boundary, aisles (centrelines,
    pavement edges, direction arrows), every bay as a closed polyline on the layer of its
    use, stripes, bay numbers, islands, obstacles, walls, speed bumps and zones, entrances,
    exits and gates, and the bays taken at start, each on its named layer
    (:data:`lotsim.io.cad_layers.LAYERS`). A scenario's service routes (its ``routes``
    section) are planned and drawn too: each swept envelope and path on layers of their own
    (a run's lot is drawn without them: a result holds no routes).

    The drawing is in ``units``, ``m`` or ``ft`` (``lotsim export --dxf-units``); by
    default in the scenario's own (``units: ft`` draws in feet), and a run's lot, whose
    result is in metres, in metres.

    Needs ``pip install 'lotsim[dxf]'``; raises ``ExportUnavailable`` (a
    :class:`LotsimError`) without it. The file is written whole or not at all (its folder
    must exist). Returns a ``DxfInfo`` (the path, bays, entities per layer, bytes, units);
    the example is ``docs/export.md``'s.
    """
    from lotsim.io.export.dxf import drawing_units, write_dxf
    from lotsim.io.export.tracks import require

    if units is not None:
        drawing_units(units)
    require("ezdxf", "dxf")  # before the lot is built
    scenario, lot = _scenario_and_lot(source)
    reports = ()
    if scenario is not None and scenario.routes:  # planned only when there are some
        from lotsim.roadmap.service_routes import plan_routes

        reports = plan_routes(lot, scenario.routes)
    if units is None:
        units = scenario.units if scenario is not None else "m"
    return write_dxf(lot, path, routes=reports, units=units)
