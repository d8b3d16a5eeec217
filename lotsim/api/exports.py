"""A run in other tools' formats (``lotsim export``, ``docs/export.md``): CommonRoad, SUMO
and OpenSCENARIO. Each format's packages are an optional extra, imported only when its
export is asked for."""

from __future__ import annotations

import os

from lotsim.api.results import result_document
from lotsim.core import checks as _checks
from lotsim.errors import SettingsError
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
