"""A run as a CommonRoad scenario, planning problems and a KS solution (``commonroad-io``).

:func:`write_commonroad` writes two files into a folder:

* ``<name>.xml``: the scenario (the 2020a XML format, ``FileFormat.XML``): the lot's
  boundary as four thin road-boundary obstacles outside its edges, every wall, island,
  obstacle and no-go zone as a static obstacle, every car parked at start as a static
  ``parkedVehicle``, each car's dwell in its slot as a dynamic obstacle that occupies its
  parked footprint over that time interval (a set-based prediction), and one planning
  problem per trip: a car's way in (its entrance to its slot, the goal its slot's polygon)
  and, for a car that leaves, its way out (its slot to within 0.5 m and 0.1 rad of its
  exit);
* ``solution.xml``: one kinematic single-track (KS) trajectory per planning problem.

Conventions (``docs/export.md``)
--------------------------------
* **Step.** States are on CommonRoad's uniform step ``dt`` (0.1 s): time step ``k`` is
  ``k * dt`` seconds of the run. Between lotsim's samples (every 0.05 s, plus starts,
  stops and cusps) the track is interpolated linearly, as ``docs/result.md`` defines it;
  :func:`~lotsim.io.export.tracks.resample_error` measures what the step skips.
* **Vehicle.** Each lotsim type maps to the CommonRoad vehicle (1 Ford Escort, 2 BMW 320i,
  3 VW Vanagon) whose wheelbase ``a + b`` is nearest its own (:func:`commonroad_vehicle`).
* **Position.** CommonRoad's KS states give the vehicle's centre: its checker moves the
  position back by its parameter ``b`` (centre of gravity to rear axle) along the heading
  to get the rear axle it integrates. lotsim's rear-axle centre is therefore written moved
  *forward* by that vehicle's ``b``, so the checker's rear axle is lotsim's exactly.
* **Steering.** The steering angle written is ``atan(l * tan(steer) / wheelbase)``, ``l``
  the CommonRoad vehicle's wheelbase: the KS model then turns on lotsim's curvature, so its
  path is lotsim's path. Velocity is lotsim's signed speed (negative in reverse).
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from lotsim.io.export.commonroad_lot import FIRST_ID, lot_scenario, ring_of
from lotsim.io.export.files import staged_folder
from lotsim.io.export.tracks import (
    CarTrack,
    ExportError,
    VehicleShape,
    Visit,
    forward,
    require,
    resample,
    resample_error,
    tracks,
    visits,
)

FILE_DATE = "2000-01-01"
"""The date in each scenario file's header: fixed, so that the same result gives the same
files."""
DT = 0.1
"""CommonRoad's time step [s]."""
EXIT_REACH = (0.5, 0.1)
"""A trip out reaches its exit within this distance [m] and heading [rad] (as ``lotsim
check`` judges a departed vehicle)."""

COMMONROAD_VEHICLES = {
    1: ("FORD_ESCORT", 0.88392 + 1.50876, 1.50876),
    2: ("BMW_320i", 1.1561957064 + 1.4227170936, 1.4227170936),
    3: ("VW_VANAGON", 1.1507916024 + 1.3211363976, 1.3211363976),
}
"""CommonRoad vehicle id: (``VehicleType`` name, wheelbase ``a + b`` [m], ``b`` [m]), as
``commonroad-vehicle-models`` gives them (parameters_vehicle1-3)."""


@dataclass(frozen=True, slots=True)
class Trip:
    """One planning problem: a vehicle's track between two time steps."""

    id: int
    """Planning problem id."""
    vehicle: str
    kind: str
    """``in`` (entrance to slot), ``out`` (slot to exit) or ``whole``."""
    first: int
    """First time step (``first * dt`` s)."""
    last: int
    """Last time step."""


@dataclass(frozen=True, slots=True)
class CommonRoadInfo:
    """What :func:`write_commonroad` wrote: one scenario and one solution per trip."""

    folder: Path
    files: tuple[tuple[Trip, Path, Path], ...]
    """``(trip, scenario file, solution file)``, in the order of :func:`trips`."""
    states: int
    """KS states in all solutions."""
    dt: float
    """[s]"""
    position_error: float
    """Largest distance of a lotsim sample from the resampled track [m]."""
    heading_error: float
    """Largest heading difference there [rad]."""
    vehicles: dict[str, int]
    """lotsim type name → CommonRoad vehicle id."""
    bytes: int


def commonroad_vehicle(shape: VehicleShape) -> int:
    """The CommonRoad vehicle id (1-3) whose wheelbase is nearest the type's.

    >>> commonroad_vehicle(VehicleShape("valet", 1.8, 3.9, 1.0, 2.8, 0.51, 0.44))
    2
    """
    return min(
        COMMONROAD_VEHICLES, key=lambda k: (abs(COMMONROAD_VEHICLES[k][1] - shape.wheelbase), k)
    )


def ks_states(tr: CarTrack, first: int, last: int, dt: float = DT) -> dict[str, np.ndarray]:
    """The KS states of ``tr`` at time steps ``first..last``: ``time_step``, ``x``, ``y``
    (the CommonRoad centre [m]), ``orientation`` [rad], ``velocity`` [m/s],
    ``steering_angle`` [rad] (module docstring)."""
    _, wheelbase, b = COMMONROAD_VEHICLES[commonroad_vehicle(tr.shape)]
    steps = np.arange(first, last + 1)
    r = resample(tr, steps * dt)
    x, y = forward(r["x"], r["y"], r["theta"], b)
    steer = np.arctan(wheelbase * np.tan(r["steer"]) / tr.shape.wheelbase)
    # continuous over the trip, starting in [-pi, pi); CommonRoad reads [-2 pi, 2 pi]
    theta = r["theta"] - 2 * np.pi * np.floor((r["theta"][0] + np.pi) / (2 * np.pi))
    if np.abs(theta).max() > 2 * np.pi:
        theta = (theta + np.pi) % (2 * np.pi) - np.pi
    return {
        "time_step": steps,
        "x": x,
        "y": y,
        "orientation": theta,
        "velocity": r["v"],
        "steering_angle": steer,
    }


def trips(doc: dict, dt: float = DT) -> list[tuple[Trip, CarTrack, Visit]]:
    """Each vehicle's trips on the step: in (first sample to parked; none for a car that
    stood in its slot when it came), out (moved off to last sample), or whole (a car that
    never stood in its slot). A trip begins at the first
    step within its samples, or in the dwell before it; it ends at the last step within its
    samples, or in the dwell after it."""
    vs = visits(doc)
    out, pid = [], 1
    for tr in tracks(doc):
        v = vs[tr.id]
        first_in = math.ceil(tr.t[0] / dt - 1e-9)
        last_in = math.floor(tr.t[-1] / dt + 1e-9)
        spans = []
        if v.park is None:
            spans.append(("whole", first_in, last_in))
        else:
            park_step = min(
                math.ceil(v.park / dt - 1e-9),
                last_in if v.leave is None else math.floor(v.leave / dt + 1e-9),
            )
            if not v.in_bay:  # one that stood in its slot when it came has no way in
                spans.append(("in", first_in, max(park_step, first_in)))
            if v.leave is not None:
                leave_step = max(math.floor(v.leave / dt + 1e-9), park_step)
                spans.append(("out", leave_step, max(last_in, leave_step)))
        for kind, a, b in spans:
            out.append((Trip(pid, tr.id, kind, a, b), tr, v))
            pid += 1
    return out


def write_commonroad(doc: dict, folder: str | os.PathLike, *, dt: float = DT) -> CommonRoadInfo:
    """Write a run (a ``result.json`` document) as CommonRoad files into ``folder``: for
    each trip ``<vehicle>-<in|out|whole>.xml`` (its scenario) and
    ``<vehicle>-<in|out|whole>.solution.xml`` (its KS trajectory).

    Parameters
    ----------
    doc : dict
        The result (:func:`lotsim.api.load_result`).
    folder : path-like
        Made if need be; the files are written to a temporary folder beside it and each
        moved in when all are complete.
    dt : float, keyword-only
        The time step [s].

    Returns
    -------
    CommonRoadInfo

    Raises
    ------
    ExportUnavailable
        Without ``commonroad-io`` (``pip install 'lotsim[commonroad]'``).
    ExportError
        For a run in which no vehicle moved.
    """
    require("commonroad", "commonroad")
    lot = doc["lot"]
    trip_list = trips(doc, dt)
    if not trip_list:
        raise ExportError("no vehicle of this run moved: there is nothing to plan")
    name = "".join(c for c in str(lot.get("name") or "lot").title() if c.isalnum()) or "Lot"
    slots = {s["id"]: s for s in lot["slots"]}
    exits = {e["id"]: e for e in lot.get("exits", [])}
    every = tracks(doc)
    vs = visits(doc)

    target = Path(folder)
    written, states, worst = [], 0, [0.0, 0.0]
    vehicle_ids: dict[str, int] = {}
    with staged_folder(target) as tmp:
        for trip, tr, visit in trip_list:
            crid = commonroad_vehicle(tr.shape)
            vehicle_ids[tr.shape.name] = crid
            sid = _scenario_id(name, trip)
            scenario = lot_scenario(doc, sid, dt)
            _add_other_cars(scenario, trip, every, vs, dt)
            ks = _ks_list(tr, trip.first, trip.last, trip.first, dt)
            pe, he = resample_error(tr, np.arange(trip.first, trip.last + 1) * dt)
            worst = [max(worst[0], pe), max(worst[1], he)]
            states += len(ks)
            goal = _goal(trip, visit, ks, crid, slots, exits)
            stem = f"{_file_name(trip.vehicle)}-{trip.kind}"
            _write_trip(
                tmp,
                stem,
                scenario,
                _planning_problems(trip, ks[0], goal),
                _solution(sid, trip, crid, ks),
            )
            written.append((trip, target / f"{stem}.xml", target / f"{stem}.solution.xml"))
    size = sum(p.stat().st_size for _, a, b in written for p in (a, b))
    return CommonRoadInfo(target, tuple(written), states, dt, worst[0], worst[1], vehicle_ids, size)


def _scenario_id(name: str, trip: Trip):
    """The benchmark id of ``trip``'s scenario (``ZAM_<name>-1_<trip>_T-1``): a made-up map
    (CommonRoad's country code ``ZAM``) named after the lot, one configuration per trip, the
    other cars predicted by their trajectories (``T``)."""
    from commonroad.scenario.scenario import ScenarioID

    return ScenarioID(
        country_id="ZAM",
        map_name=name,
        map_id=1,
        configuration_id=trip.id,
        obstacle_behavior="T",
        prediction_id=1,
    )


def _add_other_cars(
    scenario, trip: Trip, every: list[CarTrack], vs: dict[str, Visit], dt: float
) -> None:
    """Add the cars other than ``trip``'s to its scenario, as they are from the trip's
    start: one standing through the whole trip is a static parked vehicle at its footprint,
    one that moves (or leaves the run during the trip) a dynamic obstacle on its KS states
    (:func:`_moving_car`). A car that enters the run after the trip's start, or left it
    before, is left out."""
    from commonroad.geometry.obstacle_shapes.rect_obstacle_shape import RectObstacleShape
    from commonroad.scenario.obstacle import ObstacleType, StaticObstacle
    from commonroad.scenario.state import InitialState

    ids = iter(range(scenario.next_id, 100 * FIRST_ID))
    for other in every:
        if other.id == trip.vehicle:
            continue
        first_k = math.ceil(other.t[0] / dt - 1e-9)
        gone = vs[other.id].status == "departed"
        last_k = math.floor(other.t[-1] / dt + 1e-9) if gone else trip.last
        if first_k > trip.first or last_k < trip.first:
            continue
        last_k = min(last_k, trip.last)
        ks = _ks_list(other, trip.first, last_k, trip.first, dt)
        moving = (
            any(abs(s.velocity) > 0 for s in ks)
            or len(ks) > 1
            and (np.ptp([s.position for s in ks], axis=0).max() > 1e-6)
        )
        if moving or last_k != trip.last:
            scenario.add_objects(_moving_car(next(ids), other, ks))
            continue
        centre, heading = _footprint(other, trip.first, dt)
        scenario.add_objects(
            StaticObstacle(
                next(ids),
                ObstacleType.PARKED_VEHICLE,
                RectObstacleShape(other.shape.width, other.shape.length),
                InitialState(position=centre, orientation=heading, velocity=0.0, time_step=0),
            )
        )


def _moving_car(oid: int, other: CarTrack, ks: list):
    """A car other than the planned one as a dynamic obstacle with id ``oid``: its KS
    states ``ks`` (from the trip's start) as its trajectory prediction. Its reference point
    is the KS centre, so its box is shifted along the heading to cover the car's footprint."""
    from commonroad.geometry.obstacle_shapes.rect_obstacle_shape import RectObstacleShape
    from commonroad.prediction.prediction import TrajectoryPrediction
    from commonroad.scenario.obstacle import DynamicObstacle, ObstacleType
    from commonroad.scenario.state import CustomState, InitialState
    from commonroad.scenario.trajectory import Trajectory

    cr_b = COMMONROAD_VEHICLES[commonroad_vehicle(other.shape)][2]
    box = RectObstacleShape(
        other.shape.width,
        other.shape.length,
        origin_x_shift=(cr_b - (other.shape.front - other.shape.rear) / 2),
    )
    init = ks[0]
    prediction = None
    if len(ks) > 1:
        states = [
            CustomState(
                time_step=s.time_step,
                position=s.position,
                orientation=_angle(s.orientation),
                velocity=s.velocity,
            )
            for s in ks[1:]
        ]
        prediction = TrajectoryPrediction(Trajectory(1, states), box)
    return DynamicObstacle(
        oid,
        ObstacleType.CAR,
        box,
        InitialState(
            position=init.position,
            orientation=_angle(init.orientation),
            velocity=init.velocity,
            acceleration=0.0,
            yaw_rate=0.0,
            slip_angle=0.0,
            time_step=0,
        ),
        prediction,
    )


def _footprint(tr: CarTrack, k: int, dt: float) -> tuple[np.ndarray, float]:
    """Centre [m] and heading [rad] of ``tr``'s footprint at step ``k``."""
    r = resample(tr, np.array([k * dt]))
    cx, cy = forward(r["x"], r["y"], r["theta"], (tr.shape.front - tr.shape.rear) / 2)
    return np.array([cx[0], cy[0]]), _angle(r["theta"][0])


def _ks_list(tr: CarTrack, first: int, last: int, shift: int, dt: float) -> list:
    """:func:`ks_states` of ``tr`` at steps ``first..last`` as CommonRoad ``KSState``
    objects, their time steps counted from ``shift`` (a trip's scenario starts at 0)."""
    from commonroad.scenario.state import KSState

    s = ks_states(tr, first, last, dt)
    return [
        KSState(
            time_step=int(k) - shift,
            position=np.array([x, y]),
            steering_angle=float(d),
            velocity=float(v),
            orientation=float(o),
        )
        for k, x, y, d, v, o in zip(
            s["time_step"],
            s["x"],
            s["y"],
            s["steering_angle"],
            s["velocity"],
            s["orientation"],
            strict=True,
        )
    ]


def _goal(trip: Trip, visit: Visit, ks: list, crid: int, slots: dict, exits: dict):
    """The goal state of ``trip``, reached by its last step: a way in ends anywhere in its
    slot's polygon; a way out within :data:`EXIT_REACH` of its exit (the exit's pose moved
    to the KS centre of CommonRoad vehicle ``crid``); a car that neither parked nor left
    ends in a 1 m square around where it stopped."""
    from commonroad.common.util import AngleInterval, Interval
    from commonroad.geometry.occupancy.polygon_occupancy import PolygonOccupancy
    from commonroad.geometry.occupancy.rect_occupancy import RectOccupancy
    from commonroad.scenario.state import CustomState

    when = Interval(0, trip.last - trip.first)
    if trip.kind == "in":
        ring = ring_of(slots[str(visit.slot)]["polygon"])
        return CustomState(position=PolygonOccupancy(shapely.Polygon(ring)), time_step=when)
    if visit.exit is not None:
        ex, ey, eth = exits[visit.exit]["pose"]
        cx, cy = forward(np.array(ex), np.array(ey), np.array(eth), COMMONROAD_VEHICLES[crid][2])
        reach, turn = EXIT_REACH
        return CustomState(
            position=RectOccupancy(
                shapely.Point(float(cx), float(cy)), 2 * reach, 2 * reach, _angle(eth)
            ),
            orientation=AngleInterval(eth - turn, eth + turn),
            time_step=when,
        )
    last = ks[-1]
    return CustomState(
        position=RectOccupancy(shapely.Point(*last.position), 1.0, 1.0, _angle(last.orientation)),
        time_step=when,
    )


def _planning_problems(trip: Trip, k0, goal):
    """The scenario's one planning problem: from ``trip``'s first KS state ``k0`` (at rest
    in acceleration, yaw rate and slip) to ``goal``; its id is the trip's."""
    from commonroad.planning.goal import GoalRegion
    from commonroad.planning.planning_problem import PlanningProblem, PlanningProblemSet
    from commonroad.scenario.state import InitialState

    initial = InitialState(
        position=k0.position,
        orientation=_angle(k0.orientation),
        velocity=k0.velocity,
        acceleration=0.0,
        yaw_rate=0.0,
        slip_angle=0.0,
        time_step=0,
    )
    return PlanningProblemSet([PlanningProblem(trip.id, initial, GoalRegion([goal]))])


def _solution(sid, trip: Trip, crid: int, ks: list):
    """The KS solution of ``trip`` on CommonRoad vehicle ``crid``: its states ``ks``, the
    first written as the planning problem's initial state (heading wrapped into
    ``[-pi, pi)``), so that the trajectory starts where the problem does."""
    from commonroad.common.solution import (
        CostFunction,
        PlanningProblemSolution,
        Solution,
        VehicleModel,
        VehicleType,
    )
    from commonroad.scenario.state import KSState
    from commonroad.scenario.trajectory import Trajectory

    k0 = ks[0]
    first = KSState(
        time_step=0,
        position=k0.position,
        steering_angle=k0.steering_angle,
        velocity=k0.velocity,
        orientation=_angle(k0.orientation),
    )
    return Solution(
        sid,
        [
            PlanningProblemSolution(
                trip.id,
                VehicleModel.KS,
                getattr(VehicleType, COMMONROAD_VEHICLES[crid][0]),
                CostFunction.SA1,
                Trajectory(0, [first, *ks[1:]]),
            )
        ],
        date=None,
    )


def _write_trip(folder: Path, stem: str, scenario, problems, solution) -> None:
    """Write one trip's files into ``folder``: ``<stem>.xml`` (the scenario with its
    planning problem, 2020a XML) and ``<stem>.solution.xml``."""
    from commonroad.common.file_writer import CommonRoadFileWriter, OverwriteExistingFile
    from commonroad.common.solution import CommonRoadSolutionWriter
    from commonroad.common.util import FileFormat

    CommonRoadFileWriter(
        scenario,
        problems,
        author="lotsim",
        affiliation="lotsim",
        source="lotsim run",
        tags=set(),
        file_format=FileFormat.XML,
    ).write_to_file(str(folder / f"{stem}.xml"), OverwriteExistingFile.ALWAYS)
    # CommonRoad's writer stamps the day it writes; a fixed date keeps the same result's
    # files the same (the date is the file's, not the plan's)
    path = folder / f"{stem}.xml"
    text = path.read_text()
    path.write_text(re.sub(r'(<commonRoad [^>]*\bdate=")[0-9-]+(")', rf"\g<1>{FILE_DATE}\g<2>",
                           text, count=1))
    (folder / f"{stem}.solution.xml").write_text(
        CommonRoadSolutionWriter(solution).dump(pretty=True)
    )


def _file_name(vehicle: str) -> str:
    """A vehicle id as a file name: letters, digits, ``_`` and ``-`` kept."""
    return "".join(c if c.isalnum() or c in "_-" else "_" for c in vehicle) or "_"


def _angle(theta: float) -> float:
    """``theta`` [rad] wrapped into ``[-pi, pi)``."""
    return float((theta + math.pi) % (2 * math.pi) - math.pi)

