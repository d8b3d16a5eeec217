"""A run as an OpenSCENARIO scenario with a timed trajectory per car, on the lot as an
OpenDRIVE road network with a ``parkingSpace`` object per slot (``scenariogeneration``).

:func:`write_openscenario` writes two files into a folder:

* ``lot.xodr``: OpenDRIVE 1.7 (``revMinor="7"``). Each aisle is a road on its centreline
  (a ``line`` per straight piece), with a ``driving`` lane each way for a two-way aisle and
  one lane along its way for a one-way aisle (shifted onto the centreline by a
  ``laneOffset``). Each slot is a ``parkingSpace`` object on its aisle's road: ``s, t`` its
  centre, ``hdg`` its heading relative to the road, ``length`` along it and ``width``
  across;
* ``lot.xosc``: OpenSCENARIO 1.2 (``scenariogeneration``): a vehicle per car (its bounding
  box and axles from its type), teleported to its first pose at the start, and one
  ``FollowTrajectoryAction`` per car, started at its first sample, whose ``Trajectory`` is
  a ``Polyline`` of timed vertices on the absolute simulation clock.

Conventions (``docs/export.md``)
--------------------------------
* **Reference point.** OpenSCENARIO places a vehicle by its reference point, the centre of
  its rear axle, as lotsim does: vertices are lotsim's rear-axle centre as they are, and
  the bounding box's centre is ``(front - rear) / 2`` ahead of it.
* **Vertices.** A polyline keeps the samples it needs for every lotsim sample to lie
  within :data:`POSITION_ERROR` and :data:`HEADING_ERROR` of the linear interpolation
  between its vertices in time (:func:`vertices`): starts, stops, cusps and curves keep
  theirs, straights and rests lose most. Headings are continuous (unwrapped), so that a
  tool interpolating between two vertices turns the short way.
"""

from __future__ import annotations

import datetime
import math
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from shapely.geometry import LineString

from lotsim.io.export.files import staged_folder
from lotsim.io.export.tracks import CarTrack, ExportError, VehicleShape, require, tracks, visits

POSITION_ERROR = 0.01
"""Every lotsim sample lies within this of its polyline [m] ..."""
HEADING_ERROR = 0.002
"""... and within this of its heading [rad]."""
OSC_MINOR = 2
"""The OpenSCENARIO version written: 1.2."""
FILES = ("lot.xodr", "lot.xosc")
FILE_DATE = datetime.datetime(2000, 1, 1)
"""The date in the scenario's file header: fixed, so that the same result gives the same
files."""
VEHICLE_HEIGHT = 1.5
"""Bounding-box height of every car [m] (lotsim has none)."""
WHEEL_DIAMETER = 0.65
"""Every car's wheels [m] (lotsim has none)."""


@dataclass(frozen=True, slots=True)
class OpenScenarioInfo:
    """What :func:`write_openscenario` wrote."""

    folder: Path
    scenario: Path
    """``lot.xosc``."""
    road_network: Path
    """``lot.xodr``."""
    roads: int
    parking_spaces: int
    vehicles: int
    vertices: int
    """Polyline vertices of all cars."""
    samples: int
    """lotsim samples they stand for."""
    position_error: float
    """Largest distance of a lotsim sample from its polyline [m]."""
    heading_error: float
    """Largest heading difference there [rad]."""
    bytes: int


def vertices(
    tr: CarTrack, *, position: float = POSITION_ERROR, heading: float = HEADING_ERROR
) -> np.ndarray:
    """Indices of the samples a timed polyline of ``tr`` keeps: the fewest (a
    Douglas-Peucker split in time) such that every sample lies within ``position`` [m] and
    ``heading`` [rad] of the linear interpolation between the kept ones at its time.

    >>> import numpy as np
    >>> from lotsim.io.export.tracks import VehicleShape
    >>> t = np.arange(5.0)
    >>> tr = CarTrack("a", VehicleShape("car", 1.8, 3.9, 1.0, 2.8, 0.5, 0.4), t, t, 0 * t,
    ...            0 * t, 1 + 0 * t, 0 * t, 1 + 0 * t)
    >>> vertices(tr).tolist()  # a straight at constant speed: its ends
    [0, 4]
    """
    n = len(tr)
    if n <= 2:
        return np.arange(n)
    theta = np.unwrap(tr.theta)
    keep = np.zeros(n, dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, n - 1)]
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            continue
        t = tr.t[i + 1 : j]
        span = tr.t[j] - tr.t[i]
        f = (t - tr.t[i]) / span if span > 0 else np.zeros_like(t)
        dx = tr.x[i] + f * (tr.x[j] - tr.x[i]) - tr.x[i + 1 : j]
        dy = tr.y[i] + f * (tr.y[j] - tr.y[i]) - tr.y[i + 1 : j]
        dh = theta[i] + f * (theta[j] - theta[i]) - theta[i + 1 : j]
        # the worse of the two, each in units of its tolerance
        err = np.maximum(np.hypot(dx, dy) / position, np.abs(dh) / heading)
        k = int(np.argmax(err))
        if err[k] > 1.0:
            m = i + 1 + k
            keep[m] = True
            stack += [(i, m), (m, j)]
    return np.flatnonzero(keep)


def polyline_error(tr: CarTrack, idx: np.ndarray) -> tuple[float, float]:
    """Largest distance [m] and heading difference [rad] of ``tr``'s samples from the
    polyline through ``idx`` (linear in time)."""
    theta = np.unwrap(tr.theta)
    x = np.interp(tr.t, tr.t[idx], tr.x[idx])
    y = np.interp(tr.t, tr.t[idx], tr.y[idx])
    h = np.interp(tr.t, tr.t[idx], theta[idx])
    return float(np.hypot(x - tr.x, y - tr.y).max()), float(np.abs(h - theta).max())


def _road_of(aisle: dict) -> tuple[np.ndarray, bool]:
    """An aisle's reference line (its centreline, reversed for a one-way aisle whose lane
    runs against it) and whether it has a lane each way."""
    line = np.asarray(aisle["centerline"], dtype=float)
    lanes = aisle["lanes"]
    two_way = len(lanes) > 1
    if not two_way and lanes and not lanes[0]["with_polyline"]:
        line = line[::-1]
    return line, two_way


def opendrive(doc: dict, name: str) -> tuple[ET.Element, int, int]:
    """The lot as an OpenDRIVE 1.7 document (module docstring): the root, its roads and
    parking spaces."""
    drawing = doc["lot"].get("drawing") or {}
    aisles = drawing.get("aisles") or []
    if not aisles:
        raise ExportError("the result's lot has no aisles (lot.drawing.aisles): no roads")
    root = ET.Element("OpenDRIVE")
    ET.SubElement(
        root, "header", revMajor="1", revMinor="7", name=name, version="1.00",
        north="0.0", south="0.0", east="0.0", west="0.0", vendor="lotsim",
    )  # fmt: skip
    slots_of: dict[str, list[dict]] = {}
    for s in drawing.get("slots", []):
        slots_of.setdefault(str(s["aisle"]), []).append(s)
    spaces = 0
    for rid, aisle in enumerate(aisles, start=1):
        line, two_way = _road_of(aisle)
        seg = np.diff(line, axis=0)
        lengths = np.hypot(*seg.T)
        road = ET.SubElement(
            root, "road", name=str(aisle["id"]), length=_f(lengths.sum()), id=str(rid),
            junction="-1",
        )  # fmt: skip
        ET.SubElement(ET.SubElement(road, "type", s="0.0", type="town"), "speed",
                      max=_f(float(drawing.get("speed_limit") or 5.0)), unit="m/s")
        plan = ET.SubElement(road, "planView")
        s = 0.0
        for (x, y), (dx, dy), length in zip(line[:-1], seg, lengths, strict=True):
            if length < 1e-9:
                continue
            geo = ET.SubElement(
                plan, "geometry", s=_f(s), x=_f(x), y=_f(y), hdg=_f(math.atan2(dy, dx)),
                length=_f(length),
            )  # fmt: skip
            ET.SubElement(geo, "line")
            s += float(length)
        lanes = ET.SubElement(road, "lanes")
        width = float(aisle["width"])
        if not two_way:  # one lane to the right of the reference line, moved onto it
            ET.SubElement(lanes, "laneOffset", s="0.0", a=_f(width / 2), b="0.0", c="0.0",
                          d="0.0")
        section = ET.SubElement(lanes, "laneSection", s="0.0")
        sides = [("left", 1), ("right", -1)] if two_way else [("right", -1)]
        lane_width = width / 2 if two_way else width
        for side, lane_id in sides:
            group = ET.SubElement(section, side)
            lane = ET.SubElement(group, "lane", id=str(lane_id), type="driving", level="false")
            ET.SubElement(lane, "width", sOffset="0.0", a=_f(lane_width), b="0.0", c="0.0",
                          d="0.0")
            if side == "left":
                ET.SubElement(section, "center")
        if not two_way:
            ET.SubElement(section, "center")
        # the center group comes between left and right (the schema's order)
        order = {"left": 0, "center": 1, "right": 2}
        section[:] = sorted(section, key=lambda e: order[e.tag])
        for e in section.findall("center"):
            ET.SubElement(e, "lane", id="0", type="none", level="false")
        objects = ET.SubElement(road, "objects")
        ref = LineString(line)
        for slot in slots_of.get(str(aisle["id"]), []):
            c = shapely.Polygon(slot["polygon"]).centroid
            s_at = ref.project(c)
            a = ref.interpolate(max(s_at - 0.01, 0.0))
            b = ref.interpolate(min(s_at + 0.01, ref.length))
            road_hdg = math.atan2(b.y - a.y, b.x - a.x)
            p = ref.interpolate(s_at)
            t = -(c.x - p.x) * math.sin(road_hdg) + (c.y - p.y) * math.cos(road_hdg)
            hdg = (float(slot["heading"]) - road_hdg + math.pi) % (2 * math.pi) - math.pi
            obj = ET.SubElement(
                objects, "object", id=f"{rid}{spaces:05d}", name=str(slot["id"]),
                s=_f(s_at), t=_f(t), zOffset="0.0", type="parkingSpace", orientation="none",
                length=_f(float(slot["length"])), width=_f(float(slot["width"])),
                hdg=_f(hdg), pitch="0.0", roll="0.0", height="0.0",
            )  # fmt: skip
            ET.SubElement(obj, "parkingSpace", access="all")
            spaces += 1
        if not len(objects):
            road.remove(objects)
    return root, len(aisles), spaces


def _f(v: float) -> str:
    """A number as written: 6 decimals (1 µm, 1 µrad), no trailing zeros."""
    out = f"{float(v):.6f}".rstrip("0")
    return out + "0" if out.endswith(".") else out


def write_openscenario(doc: dict, folder: str | os.PathLike) -> OpenScenarioInfo:
    """Write a run (a ``result.json`` document) as ``lot.xosc`` (OpenSCENARIO 1.2) and
    ``lot.xodr`` (OpenDRIVE 1.7) into ``folder`` (module docstring).

    Parameters
    ----------
    doc : dict
        The result (:func:`lotsim.api.load_result`).
    folder : path-like
        Made if need be; the files are written to a temporary folder beside it and each
        moved in when both are complete.

    Returns
    -------
    OpenScenarioInfo

    Raises
    ------
    ExportUnavailable
        Without ``scenariogeneration`` (``pip install 'lotsim[openscenario]'``).
    ExportError
        For a lot without aisles or a run in which no vehicle moved.
    """
    require("scenariogeneration", "openscenario")
    lot = doc["lot"]
    every = tracks(doc)
    if not every:
        raise ExportError("no vehicle of this run moved: there is nothing to follow")
    name = "".join(c for c in str(lot.get("name") or "lot") if c.isalnum() or c in "_-") or "lot"
    road_root, roads, spaces = opendrive(doc, name)
    vs = visits(doc)
    cars = _cars(every)
    end = max(v.end for v in vs.values() if v.end is not None)
    scenario = _scenario(name, cars, end)

    target = Path(folder)
    with staged_folder(target) as tmp:
        ET.indent(road_root)
        ET.ElementTree(road_root).write(tmp / "lot.xodr", encoding="UTF-8",
                                        xml_declaration=True)
        scenario.write_xml(str(tmp / "lot.xosc"), prettyprint=True)
    files = [target / f for f in FILES]
    return OpenScenarioInfo(
        target,
        target / "lot.xosc",
        target / "lot.xodr",
        roads,
        spaces,
        len(every),
        cars.vertices,
        cars.samples,
        cars.position_error,
        cars.heading_error,
        sum(p.stat().st_size for p in files),
    )


@dataclass(slots=True)
class _Cars:
    """The cars of a scenario as :func:`_cars` builds them: the ``xosc`` entities, their
    init actions and the act that drives them, with the counts and errors of their
    polylines for :class:`OpenScenarioInfo`."""

    entities: Any
    init: Any
    act: Any
    vertices: int = 0
    samples: int = 0
    position_error: float = 0.0
    heading_error: float = 0.0


def _cars(every: list[CarTrack]) -> _Cars:
    """Every car as a vehicle entity, teleported to its first pose at the start and then
    following its timed polyline (:func:`vertices`) in the act ``run``; a car with a single
    vertex stays where it was put."""
    from scenariogeneration import xosc

    cars = _Cars(
        xosc.Entities(),
        xosc.Init(),
        xosc.Act(
            "run",
            xosc.ValueTrigger(
                "start", 0, xosc.ConditionEdge.none,
                xosc.SimulationTimeCondition(0, xosc.Rule.greaterOrEqual),
            ),
        ),
    )  # fmt: skip
    for tr in every:
        cars.entities.add_scenario_object(tr.id, _vehicle(tr.shape))
        theta = np.unwrap(tr.theta)
        cars.init.add_init_action(
            tr.id,
            xosc.TeleportAction(
                xosc.WorldPosition(float(tr.x[0]), float(tr.y[0]), 0.0, float(theta[0]))
            ),
        )
        idx = vertices(tr)
        pe, he = polyline_error(tr, idx)
        cars.position_error = max(cars.position_error, pe)
        cars.heading_error = max(cars.heading_error, he)
        cars.vertices += len(idx)
        cars.samples += len(tr)
        if len(idx) >= 2:
            cars.act.add_maneuver_group(_follow(tr, theta, idx))
    return cars


def _vehicle(sh: VehicleShape):
    """A lotsim type as an OpenSCENARIO car: its bounding box centred ``(front - rear) / 2``
    ahead of the rear axle (the reference point), its front axle a wheelbase ahead turning
    up to its steering limit, and its limits capped to finite numbers (lotsim's infinity
    means none). Height, wheels and track width lotsim does not have are set to
    :data:`VEHICLE_HEIGHT`, :data:`WHEEL_DIAMETER` and 85 % of the width."""
    from scenariogeneration import xosc

    rear_track = 0.85 * sh.width
    return xosc.Vehicle(
        sh.name,
        xosc.VehicleCategory.car,
        xosc.BoundingBox(sh.width, sh.length, VEHICLE_HEIGHT, (sh.front - sh.rear) / 2, 0.0,
                         VEHICLE_HEIGHT / 2),
        xosc.Axle(sh.max_steer, WHEEL_DIAMETER, rear_track, sh.wheelbase, WHEEL_DIAMETER / 2),
        xosc.Axle(0.0, WHEEL_DIAMETER, rear_track, 0.0, WHEEL_DIAMETER / 2),
        min(sh.max_forward_speed, 1000.0),
        min(sh.max_accel, 100.0),
        min(sh.max_brake, 100.0),
    )


def _follow(tr: CarTrack, theta: np.ndarray, idx: np.ndarray):
    """The maneuver group in which car ``tr`` follows its polyline through the samples
    ``idx`` (headings ``theta``, unwrapped), times absolute on the simulation clock, from
    when the simulation reaches its first sample. Values are rounded to 1 µm, 1 µs and
    1 µrad, as the road network's are."""
    from scenariogeneration import xosc

    trajectory = xosc.Trajectory(f"{tr.id}-track", False)
    trajectory.add_shape(
        xosc.Polyline(
            [round(float(tr.t[i]), 6) for i in idx],
            [
                xosc.WorldPosition(
                    round(float(tr.x[i]), 6), round(float(tr.y[i]), 6), 0.0,
                    round(float(theta[i]), 6),
                )
                for i in idx
            ],
        )
    )  # fmt: skip
    event = xosc.Event(f"{tr.id}-drive", xosc.Priority.override)
    event.add_action(
        f"{tr.id}-follow",
        xosc.FollowTrajectoryAction(
            trajectory,
            xosc.FollowingMode.position,
            xosc.ReferenceContext.absolute,
            1,
            0,
        ),
    )
    event.add_trigger(
        xosc.ValueTrigger(
            f"{tr.id}-enters", 0, xosc.ConditionEdge.none,
            xosc.SimulationTimeCondition(float(tr.t[0]), xosc.Rule.greaterOrEqual),
        )
    )  # fmt: skip
    maneuver = xosc.Maneuver(f"{tr.id}-way")
    maneuver.add_event(event)
    group = xosc.ManeuverGroup(f"{tr.id}-group")
    group.add_actor(tr.id)
    group.add_maneuver(maneuver)
    return group


def _scenario(name: str, cars: _Cars, end: float):
    """The OpenSCENARIO document: ``cars`` in a story ``lotsim`` on the road network
    ``lot.xodr``, stopped a second after the run's end ``end`` [s], dated
    :data:`FILE_DATE` so that the same result gives the same file."""
    from scenariogeneration import xosc

    story = xosc.Story("lotsim")
    story.add_act(cars.act)
    storyboard = xosc.StoryBoard(
        cars.init,
        xosc.ValueTrigger(
            "end", 0, xosc.ConditionEdge.none,
            xosc.SimulationTimeCondition(end + 1.0, xosc.Rule.greaterThan), "stop",
        ),
    )  # fmt: skip
    storyboard.add_story(story)
    return xosc.Scenario(
        name,
        "lotsim",
        xosc.ParameterDeclarations(),
        cars.entities,
        storyboard,
        xosc.RoadNetwork("lot.xodr"),
        xosc.Catalog(),
        osc_minor_version=OSC_MINOR,
        creation_date=FILE_DATE,
    )
