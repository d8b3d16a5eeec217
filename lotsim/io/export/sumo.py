"""A run as a SUMO simulation: the aisles as a network, each slot a parking space at its
real pose, the cars as vehicles that park there for their dwell (``eclipse-sumo``).

:func:`write_sumo` writes into a folder:

* ``lot.nod.xml``, ``lot.edg.xml``: the network in SUMO's plain XML. A node wherever an
  aisle ends or meets another aisle; an edge per lane of each aisle between two nodes
  (a one-way aisle has one, a two-way aisle one each way), its shape lotsim's lane
  centreline (``spreadType="center"``), its width the lane's, its speed the lot's limit;
* ``lot.net.xml``: that network built by SUMO's ``netconvert``, in lotsim's coordinates
  (``--offset.disable-normalization``);
* ``lot.add.xml``: a ``<parkingArea>`` per slot with one ``<space>`` at the pose a car
  stands in it (below), on the lane of the slot's aisle nearest its entry side;
* ``lot.rou.xml``: a ``<vType>`` per lotsim type and a ``<trip>`` per car, from its
  entrance (at its arrival time) to its exit, with a stop at its slot's parking area
  ``until`` the time it moved off (SUMO finds the route through the stop);
* ``lot.sumocfg``: the configuration that runs them (``sumo -c lot.sumocfg``).

Conventions (``docs/export.md``)
--------------------------------
* **Binaries.** ``netconvert`` is the one of the ``eclipse-sumo`` package
  (``sumo.SUMO_HOME/bin``), else the first on ``PATH`` (:func:`sumo_binary`).
* **Spaces.** SUMO puts a parked vehicle's position, the centre of its front bumper, at
  the space's ``x, y``, and reports its heading as ``(180 - angle) mod 360`` degrees
  clockwise from north. A space is therefore written at the front-bumper centre of the
  first car that stood in that slot, with ``angle = 90 + heading`` [deg] (lotsim's heading
  counter-clockwise from east): SUMO then shows the car where lotsim parked it. A slot no
  car used gets the pose of a car of the lot's design length centred in it, facing its
  ``heading``.
* **One area per slot.** SUMO gives a vehicle that reaches a parking area the area's first
  free space, not a space of its choosing: an area per slot puts each car in its own.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import LineString, Point
from shapely.ops import substring

from lotsim.io.export.files import staged_folder
from lotsim.io.export.tracks import (
    CarTrack,
    ExportError,
    VehicleShape,
    Visit,
    forward,
    offset_line,
    require,
    tracks,
    visits,
)

NODE_MERGE = 1.0
"""Aisle ends and crossings closer than this are one node [m]."""
MIN_EDGE = 0.1
"""Pieces of aisle shorter than this between two nodes are left out [m]."""
STEP = 0.1
"""The simulation's step [s]."""
MIN_GAP = 0.5
"""The gap SUMO's vehicles keep to the one ahead when standing [m]."""
END_MARGIN = 60.0
"""The simulation runs this long after the last car's last sample [s]."""
FILES = ("lot.nod.xml", "lot.edg.xml", "lot.net.xml", "lot.add.xml", "lot.rou.xml", "lot.sumocfg")


@dataclass(frozen=True, slots=True)
class SumoInfo:
    """What :func:`write_sumo` wrote."""

    folder: Path
    config: Path
    """``lot.sumocfg``: run it with ``sumo -c``."""
    files: tuple[Path, ...]
    edges: int
    """Edges of the network (one per lane of each aisle piece)."""
    spaces: dict[str, tuple[float, float, float]]
    """Slot id → its space's ``x, y`` [m] and SUMO ``angle`` [deg]."""
    vehicles: int
    """Cars of the run written as trips."""
    parked: int
    """Cars parked at start, written as vehicles standing in their spaces."""
    left_out: tuple[str, ...]
    """Cars not written: they never entered, or neither parked nor left."""
    end: float
    """The simulation's end [s]."""
    bytes: int


def sumo_binary(name: str) -> str:
    """The path of SUMO's program ``name`` (``sumo``, ``netconvert``): the one shipped in
    the ``eclipse-sumo`` package (``sumo.SUMO_HOME/bin``), else the first on ``PATH``.

    Raises
    ------
    ExportUnavailable
        Without the ``sumo`` package (``pip install 'lotsim[sumo]'``).
    ExportError
        When neither has the program.
    """
    sumo = require("sumo", "sumo")
    home = getattr(sumo, "SUMO_HOME", None)
    for candidate in (Path(home) / "bin" / name if home else None, shutil.which(name)):
        if candidate and os.access(candidate, os.X_OK):
            return str(candidate)
    raise ExportError(f"SUMO's {name} was found neither in the sumo package nor on PATH")


@dataclass(frozen=True, slots=True)
class _Edge:
    id: str
    aisle: str
    start: str
    end: str
    shape: np.ndarray
    width: float


def network(doc: dict) -> tuple[dict[str, tuple[float, float]], list[_Edge]]:
    """The lot's aisles as SUMO nodes (id → ``x, y`` [m]) and edges (one per lane of each
    piece of aisle between two nodes)."""
    aisles = (doc["lot"].get("drawing") or {}).get("aisles") or []
    if not aisles:
        raise ExportError("the result's lot has no aisles (lot.drawing.aisles): no network")
    lines = {a["id"]: LineString(np.asarray(a["centerline"], dtype=float)) for a in aisles}
    points: list[Point] = []
    for a in aisles:
        points += [Point(a["centerline"][0]), Point(a["centerline"][-1])]
    ids = [a["id"] for a in aisles]
    for i, p in enumerate(ids):
        for q in ids[i + 1 :]:
            cross = lines[p].intersection(lines[q])
            points += [g for g in getattr(cross, "geoms", [cross]) if isinstance(g, Point)]
    nodes: list[Point] = []
    for p in points:
        if not any(p.distance(n) < NODE_MERGE for n in nodes):
            nodes.append(p)
    node_ids = {f"n{k}": (float(n.x), float(n.y)) for k, n in enumerate(nodes)}
    edges = []
    for a in aisles:
        line, reach = lines[a["id"]], float(a["width"]) / 2 + 1e-6
        at = sorted(
            (line.project(n), f"n{k}") for k, n in enumerate(nodes) if line.distance(n) <= reach
        )
        lanes = a["lanes"]
        width = float(a["width"]) / max(len(lanes), 1)
        for piece, ((s0, n0), (s1, n1)) in enumerate(zip(at, at[1:], strict=False)):
            if s1 - s0 < MIN_EDGE or n0 == n1:
                continue
            part = np.asarray(substring(line, s0, s1).coords)
            for lane in lanes:
                if lane["with_polyline"]:
                    shape, ends = offset_line(part, -float(lane["offset"])), (n0, n1)
                else:
                    shape, ends = offset_line(part[::-1], -float(lane["offset"])), (n1, n0)
                edges.append(
                    _Edge(f"{_sumo_id(lane['id'])}#{piece}", a["id"], *ends, shape, width)
                )
    return node_ids, edges


def _sumo_id(name: str) -> str:
    """A lotsim id as a SUMO id: ``>``/``<`` (a lane's way) as ``+``/``-``, and the other
    characters SUMO refuses in ids as ``_``."""
    name = str(name).replace(">", "+").replace("<", "-")
    return "".join("_" if c in " \t\n\r|\\'\";,&#" else c for c in name) or "_"


def _points(a) -> str:
    return " ".join(f"{x:.4f},{y:.4f}" for x, y in np.asarray(a, dtype=float))


XSI = "http://www.w3.org/2001/XMLSchema-instance"


def _write(root: ET.Element, path: Path, xsd: str) -> None:
    """Write ``root`` to ``path``, naming SUMO's schema ``xsd`` (which ``sumo`` validates
    the file against when it finds its ``SUMO_HOME``)."""
    root.set("xmlns:xsi", XSI)
    root.set("xsi:noNamespaceSchemaLocation", f"http://sumo.dlr.de/xsd/{xsd}")
    ET.indent(root)
    ET.ElementTree(root).write(path, encoding="UTF-8", xml_declaration=True)


def _lanes(net: Path) -> dict[str, tuple[str, LineString]]:
    """Each non-internal edge of a ``.net.xml``: its lane's id and shape."""
    out = {}
    for edge in ET.parse(net).getroot().iter("edge"):
        if edge.get("function"):
            continue
        lane = edge.find("lane")
        pts = [tuple(map(float, p.split(","))) for p in lane.get("shape").split()]
        out[edge.get("id")] = (lane.get("id"), LineString(pts))
    return out


def parked_at_start(doc: dict) -> dict[str, tuple[float, float, float, float, float]]:
    """The cars parked at start, by slot: front-bumper centre ``x, y`` [m], heading
    [rad] (the slot's), ``length`` and ``width`` [m] of their footprints."""
    drawing = doc["lot"].get("drawing") or {}
    slots = [(s, shapely.Polygon(s["polygon"])) for s in drawing.get("slots", [])]
    out = {}
    for points in doc["lot"].get("parked", []):
        p = np.asarray(points, dtype=float)[:4]
        c = shapely.Polygon(p).centroid
        slot = next((s for s, poly in slots if poly.contains(c)), None)
        if slot is None:
            continue
        sides = np.hypot(*np.diff(np.vstack([p, p[:1]]), axis=0).T)
        length, width = float(sides.max()), float(sides.min())
        h = float(slot["heading"])
        x, y = forward(c.x, c.y, h, length / 2)
        out[slot["id"]] = (float(x), float(y), h, length, width)
    return out


def space_poses(doc: dict, vs: dict[str, Visit]) -> dict[str, tuple[float, float, float]]:
    """Each slot's space: ``x, y`` the front-bumper centre [m] and the SUMO ``angle`` [deg]
    of the first car parked there in the run, or of the car parked there at start, or of a
    design car centred in a slot no car used, facing the slot's heading."""
    lot = doc["lot"]
    drawing = lot.get("drawing") or {}
    front = float((drawing.get("design") or {}).get("front", 3.9))
    rear = float((drawing.get("design") or {}).get("rear", 1.0))
    poses: dict[str, tuple[float, float, float]] = {}
    for tr in sorted(tracks(doc), key=lambda tr: vs[tr.id].park or math.inf):
        v = vs[tr.id]
        if v.park is None or v.slot in poses:
            continue
        i = int(np.searchsorted(tr.t, v.park))
        x, y = forward(tr.x[i], tr.y[i], tr.theta[i], tr.shape.front)
        poses[str(v.slot)] = (float(x), float(y), _sumo_angle(float(tr.theta[i])))
    for slot, (x, y, h, _, _) in parked_at_start(doc).items():
        poses.setdefault(slot, (x, y, _sumo_angle(h)))
    for s in drawing.get("slots", []):
        if s["id"] in poses:
            continue
        c = shapely.Polygon(s["polygon"]).centroid
        h = float(s["heading"])
        x, y = forward(c.x, c.y, h, (front + rear) / 2)
        poses[s["id"]] = (float(x), float(y), _sumo_angle(h))
    return poses


def _sumo_angle(theta: float) -> float:
    """The space ``angle`` [deg] SUMO turns into lotsim's heading ``theta`` [rad]."""
    return round((90.0 + math.degrees(theta)) % 360.0, 4)


def _on_lane(lanes, edges: list[_Edge], x: float, y: float, theta: float | None, aisle=None):
    """The lane nearest ``x, y`` (among an aisle's; running along ``theta`` when given)
    and the distance along it [m]."""
    best = None
    p = Point(x, y)
    for e in edges:
        if aisle is not None and e.aisle != aisle:
            continue
        lane, line = lanes[e.id]
        if theta is not None:
            s = line.project(p)
            a, b = line.interpolate(max(s - 0.1, 0)), line.interpolate(min(s + 0.1, line.length))
            if (b.x - a.x) * math.cos(theta) + (b.y - a.y) * math.sin(theta) <= 0:
                continue
        d = line.distance(p)
        if best is None or d < best[0]:
            best = (d, e.id, lane, line.project(p), line.length)
    if best is None:
        raise ExportError(f"no lane runs past ({x:.2f}, {y:.2f}) in the result's lot")
    return best[1:]


def write_sumo(doc: dict, folder: str | os.PathLike, *, step: float = STEP) -> SumoInfo:
    """Write a run (a ``result.json`` document) as a SUMO simulation into ``folder``
    (module docstring; run it with ``sumo -c folder/lot.sumocfg``).

    Parameters
    ----------
    doc : dict
        The result (:func:`lotsim.api.load_result`).
    folder : path-like
        Made if need be; the files are written to a temporary folder beside it and each
        moved in when all are complete.
    step : float, keyword-only
        The simulation's step [s], written to the configuration.

    Returns
    -------
    SumoInfo

    Raises
    ------
    ExportUnavailable
        Without the ``eclipse-sumo`` package (``pip install 'lotsim[sumo]'``).
    ExportError
        For a lot without aisles, a portal off every lane, or a network ``netconvert``
        refuses (its message is quoted).
    """
    netconvert = sumo_binary("netconvert")
    lot = doc["lot"]
    drawing = lot.get("drawing") or {}
    nodes, edges = network(doc)
    vs = visits(doc)
    target = Path(folder)
    with staged_folder(target) as tmp:
        _write(_nodes_xml(nodes), tmp / "lot.nod.xml", "nodes_file.xsd")
        speed = float(lot.get("speed_limit") or drawing.get("speed_limit") or 13.89)
        _write(_edges_xml(edges, speed), tmp / "lot.edg.xml", "edges_file.xsd")
        lanes = _build_network(netconvert, tmp)
        spaces = space_poses(doc, vs)
        areas, area_edge = _parking_areas(drawing, lanes, edges, spaces)
        _write(areas, tmp / "lot.add.xml", "additional_file.xsd")
        end = max((v.end for v in vs.values() if v.end is not None), default=0.0) + END_MARGIN
        routes, moving, parked, left_out = _routes(doc, vs, lanes, edges, area_edge, end)
        _write(routes, tmp / "lot.rou.xml", "routes_file.xsd")
        _write(_config_xml(end, step), tmp / "lot.sumocfg", "sumoConfiguration.xsd")
    files = tuple(target / f for f in FILES)
    return SumoInfo(
        target,
        target / "lot.sumocfg",
        files,
        len(edges),
        {s["id"]: spaces[s["id"]] for s in drawing.get("slots", [])},
        moving,
        parked,
        tuple(left_out),
        end,
        sum(p.stat().st_size for p in files),
    )


def _nodes_xml(nodes: dict[str, tuple[float, float]]) -> ET.Element:
    """``lot.nod.xml``: the network's nodes (:func:`network`), each a priority junction."""
    root = ET.Element("nodes")
    for nid, (x, y) in nodes.items():
        ET.SubElement(root, "node", id=nid, x=f"{x:.4f}", y=f"{y:.4f}", type="priority")
    return root


def _edges_xml(edges: list[_Edge], speed: float) -> ET.Element:
    """``lot.edg.xml``: an edge of one lane per lane of each piece of aisle, its shape the
    lane's centreline (``spreadType="center"`` keeps SUMO from moving it aside), its width
    the lane's and its speed ``speed`` [m/s], the lot's limit."""
    root = ET.Element("edges")
    for e in edges:
        ET.SubElement(
            root,
            "edge",
            id=e.id,
            to=e.end,
            numLanes="1",
            width=f"{e.width:.4f}",
            speed=f"{speed:.4f}",
            shape=_points(e.shape),
            spreadType="center",
            name=e.aisle,
            attrib={"from": e.start},
        )
    return root


def _build_network(netconvert: str, folder: Path) -> dict[str, tuple[str, LineString]]:
    """Build ``lot.net.xml`` from the node and edge files in ``folder`` with ``netconvert``,
    keeping lotsim's coordinates, and return its lanes (:func:`_lanes`): the parking areas
    and trips are placed on the lanes SUMO made, not on the ones lotsim asked for.

    Raises
    ------
    ExportError
        When ``netconvert`` refuses the network (its message is quoted).
    """
    done = subprocess.run(
        [
            netconvert,
            "--node-files", "lot.nod.xml",
            "--edge-files", "lot.edg.xml",
            "--output-file", "lot.net.xml",
            "--offset.disable-normalization", "true",
            "--no-warnings", "true",
        ],
        cwd=folder, capture_output=True, text=True,
    )  # fmt: skip
    if done.returncode != 0:
        raise ExportError(f"netconvert refused the lot's network: {done.stderr.strip()}")
    return _lanes(folder / "lot.net.xml")


def _parking_areas(
    drawing: dict, lanes, edges: list[_Edge], spaces: dict[str, tuple[float, float, float]]
) -> tuple[ET.Element, dict[str, str]]:
    """``lot.add.xml``: a parking area per slot (module docstring), as long as the slot is
    wide, on the lane of the slot's aisle nearest the middle of its entry side, with one
    space at ``spaces[slot]``; and each slot's area's edge, where the trips stop."""
    root = ET.Element("additional")
    area_edge: dict[str, str] = {}
    for s in drawing.get("slots", []):
        (ax, ay), (bx, by) = s["entry"]
        area_edge[s["id"]], lane, pos, length = _on_lane(
            lanes, edges, (ax + bx) / 2, (ay + by) / 2, None, s["aisle"]
        )
        half = min(float(s["width"]) / 2, length / 2)
        start = min(max(pos - half, 0.0), length - 2 * half)
        area = ET.SubElement(
            root,
            "parkingArea",
            id=_sumo_id(s["id"]),
            lane=lane,
            startPos=f"{start:.4f}",
            endPos=f"{start + 2 * half:.4f}",
            roadsideCapacity="0",
            name=str(s["id"]),
        )
        x, y, angle = spaces[s["id"]]
        ET.SubElement(
            area,
            "space",
            x=f"{x:.4f}",
            y=f"{y:.4f}",
            width=f"{float(s['width']):.4f}",
            length=f"{float(s['length']):.4f}",
            angle=f"{angle:.4f}",
        )
    return root, area_edge


def _routes(
    doc: dict,
    vs: dict[str, Visit],
    lanes,
    edges: list[_Edge],
    area_edge: dict[str, str],
    end: float,
) -> tuple[ET.Element, int, int, list[str]]:
    """``lot.rou.xml``: a ``<vType>`` per lotsim type and a trip per car
    (:func:`_car_trip`), then a type per footprint and a trip per car parked at start
    (:func:`_parked_trips`), the trips in order of departure. Also returns the number of
    cars written as trips, of cars parked at start, and the ids of the cars left out."""
    lot = doc["lot"]
    portals = {p["id"]: p["pose"] for p in lot.get("entrances", []) + lot.get("exits", [])}
    types: dict[str, ET.Element] = {}
    trips, left_out = [], []
    for tr in tracks(doc):
        v = vs[tr.id]
        if tr.shape.name not in types:
            types[tr.shape.name] = _vehicle_type(tr.shape)
        trip = _car_trip(tr, v, portals, lanes, edges, area_edge, end)
        if trip is None:
            left_out.append(tr.id)
            continue
        trips.append((v.arrival, tr.id, trip))
    moving = len(trips)
    trips += _parked_trips(doc, area_edge, end, types)
    root = ET.Element("routes")
    for t in types.values():
        root.append(t)
    for _, _, trip in sorted(trips, key=lambda x: (x[0], x[1])):
        root.append(trip)
    return root, moving, len(trips) - moving, left_out


def _vehicle_type(sh: VehicleShape) -> ET.Element:
    """A lotsim type as a SUMO ``<vType>``: its footprint and limits, an unlimited one
    (lotsim's infinity) capped to a finite number SUMO accepts (1000 m/s, 100 m/s²), the
    emergency deceleration at least SUMO's usual 9 m/s²; driven without imperfection
    (``sigma="0"``) at its own top speed (``speedFactor="1"``)."""
    return ET.Element(
        "vType",
        id=_sumo_id(sh.name),
        vClass="passenger",
        length=f"{sh.length:.4f}",
        width=f"{sh.width:.4f}",
        minGap=f"{MIN_GAP:.2f}",
        maxSpeed=f"{min(sh.max_forward_speed, 1000.0):.4f}",
        accel=f"{min(sh.max_accel, 100.0):.4f}",
        decel=f"{min(sh.max_brake, 100.0):.4f}",
        emergencyDecel=f"{max(min(sh.max_brake, 100.0), 9.0):.4f}",
        sigma="0",
        speedFactor="1",
    )


def _car_trip(
    tr: CarTrack,
    v: Visit,
    portals: dict,
    lanes,
    edges: list[_Edge],
    area_edge: dict[str, str],
    end: float,
) -> ET.Element | None:
    """A car's ``<trip>``: from the lane at its entrance (at its arrival time; from its
    space, for a car that stood in its slot when it came) to the lane at its exit, with a
    stop in its slot's parking area until it moved off (or past ``end`` when it stays, its
    trip then ending at the area's edge). ``None`` for a car that neither
    parked nor left: SUMO has nowhere to send it."""
    if v.park is None and v.exit is None:
        return None
    attrs = {"id": _sumo_id(tr.id), "type": _sumo_id(tr.shape.name),
             "depart": f"{v.arrival:.2f}"}
    if v.in_bay:  # it stood in its slot when it came: it departs from its space
        attrs |= {"departPos": "stop", "from": area_edge[str(v.slot)]}
    else:
        ex, ey, eth = portals.get(v.entrance, (tr.x[0], tr.y[0], tr.theta[0]))
        src, _, depart_pos, _ = _on_lane(lanes, edges, ex, ey, eth)
        attrs |= {"departLane": "0", "departPos": f"{depart_pos:.4f}", "departSpeed": "0",
                  "from": src}
    if v.exit is not None:
        ox, oy, oth = portals[v.exit]
        dst, _, arrival_pos, _ = _on_lane(lanes, edges, ox, oy, oth)
        attrs |= {"to": dst, "arrivalPos": f"{arrival_pos:.4f}"}
    trip = ET.Element("trip", attrs)
    if v.park is not None:
        ET.SubElement(
            trip,
            "stop",
            parkingArea=_sumo_id(str(v.slot)),
            parking="true",
            until=f"{(v.leave if v.leave is not None else end + 1.0):.2f}",
        )
        if v.exit is None:
            trip.set("to", area_edge[str(v.slot)])
    return trip


def _parked_trips(
    doc: dict, area_edge: dict[str, str], end: float, types: dict[str, ET.Element]
) -> list[tuple[float, str, ET.Element]]:
    """The cars parked at start as trips inserted in their spaces (``departPos="stop"``) at
    time 0 and parked past ``end``, each ``(-1, id, trip)`` to sort before every car of the
    run. A ``<vType>`` per footprint is added to ``types`` (they have no lotsim type)."""
    out = []
    for slot, (_, _, _, length, width) in sorted(parked_at_start(doc).items()):
        tid = f"parked-{length:.2f}x{width:.2f}"
        types.setdefault(
            tid,
            ET.Element(
                "vType", id=tid, vClass="passenger", length=f"{length:.4f}",
                width=f"{width:.4f}", minGap=f"{MIN_GAP:.2f}",
            ),
        )  # fmt: skip
        trip = ET.Element(
            "trip",
            {
                "id": f"parked-{_sumo_id(slot)}",
                "type": tid,
                "depart": "0.00",
                "departPos": "stop",
                "from": area_edge[slot],
                "to": area_edge[slot],
            },
        )
        ET.SubElement(
            trip, "stop", parkingArea=_sumo_id(slot), parking="true", until=f"{end + 1:.2f}"
        )
        out.append((-1.0, trip.get("id"), trip))
    return out


def _config_xml(end: float, step: float) -> ET.Element:
    """``lot.sumocfg``: the network, routes and parking areas, run from 0 to ``end`` [s] on
    the step ``step`` [s]."""
    cfg = ET.Element("configuration")
    inp = ET.SubElement(cfg, "input")
    ET.SubElement(inp, "net-file", value="lot.net.xml")
    ET.SubElement(inp, "route-files", value="lot.rou.xml")
    ET.SubElement(inp, "additional-files", value="lot.add.xml")
    tm = ET.SubElement(cfg, "time")
    ET.SubElement(tm, "begin", value="0")
    ET.SubElement(tm, "end", value=f"{end:.2f}")
    ET.SubElement(tm, "step-length", value=f"{step:g}")
    return cfg
