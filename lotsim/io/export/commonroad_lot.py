"""The lot in CommonRoad's terms, shared by every trip's scenario: the lanes and slots as
lanelets (of type ``driveWay`` and ``parking``), the boundary, walls, islands and the cars
parked at start as static obstacles (:func:`lot_scenario`)."""

from __future__ import annotations

import math

import numpy as np

from lotsim.io.export.tracks import offset_line

FIRST_ID = 1_000_000
"""Ids of lanelets and obstacles start here; a planning problem's id is its trip's (1, 2,
...), unique in the run."""

BOUNDARY_THICKNESS = 0.2
"""Thickness of the obstacles that stand for the lot's outline, outside it [m]."""


def ring_of(points) -> list[tuple[float, float]]:
    """A polygon's corners as floats, without the closing repeat of the first (CommonRoad's
    polygons close themselves)."""
    ring = [(float(x), float(y)) for x, y in points]
    return ring[:-1] if ring[0] == ring[-1] else ring


def boundary_boxes(boundary) -> list[tuple[float, tuple[float, float, float]]]:
    """The thin boxes that stand for the lot's outline: for each edge of ``boundary`` its
    length [m] and the box's centre ``x, y`` [m] and heading [rad], the box lying
    :data:`BOUNDARY_THICKNESS` wide just outside the edge (a planner must stay inside the
    lot, and CommonRoad has no outline of its own)."""
    ring = np.array(ring_of(boundary))
    ccw = np.sum(ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1]) > 0
    out = []
    for p, q in zip(ring, np.roll(ring, -1, axis=0), strict=True):
        d = q - p
        length = float(np.hypot(*d))
        if length < 1e-9:
            continue
        outward = np.array([d[1], -d[0]]) / length * (1 if ccw else -1)
        centre = (p + q) / 2 + outward * BOUNDARY_THICKNESS / 2
        out.append((length, (float(centre[0]), float(centre[1]), math.atan2(d[1], d[0]))))
    return out


def static_obstacles(lot: dict) -> list[tuple]:
    """``(ObstacleType, shape, (x, y, heading))`` of everything in the lot that never
    moves, in id order: the outline's boxes, every drawn area (walls as road boundaries,
    islands, obstacles and no-go zones as unknown: the 2020a format's static types) or,
    for a lot without a drawing, its obstacles, and the cars parked at start."""
    from commonroad.geometry.obstacle_shapes.polygon_obstacle_shape import (
        PolygonObstacleShape,
    )
    from commonroad.geometry.obstacle_shapes.rect_obstacle_shape import RectObstacleShape
    from commonroad.scenario.obstacle import ObstacleType

    origin = (0.0, 0.0, 0.0)
    out: list[tuple] = [
        (
            ObstacleType.ROAD_BOUNDARY,
            RectObstacleShape(BOUNDARY_THICKNESS, length + 2 * BOUNDARY_THICKNESS),
            where,
        )
        for length, where in boundary_boxes(lot["boundary"])
    ]
    kinds = {"wall": ObstacleType.ROAD_BOUNDARY}
    areas = (lot.get("drawing") or {}).get("areas")
    if areas is None:
        areas = [
            {"kind": "obstacle", "polygon": {"type": "Polygon", "coordinates": [o]}}
            for o in lot.get("obstacles", [])
        ]
    for area in areas:
        geom = area["polygon"]
        polys = [geom["coordinates"]] if geom["type"] == "Polygon" else geom["coordinates"]
        for rings in polys:
            out.append(
                (
                    kinds.get(area["kind"], ObstacleType.UNKNOWN),
                    PolygonObstacleShape(tuple(ring_of(rings[0]))),
                    origin,
                )
            )
    for points in lot.get("parked", []):
        out.append(
            (ObstacleType.PARKED_VEHICLE, PolygonObstacleShape(tuple(ring_of(points))), origin)
        )
    return out


def lot_scenario(doc: dict, sid, dt: float):
    """The scenario of what every trip shares: the lanes and slots as lanelets
    (:func:`lanelets`) and the static obstacles (:func:`static_obstacles`). Ids count up
    from :data:`FIRST_ID`; the scenario's ``next_id`` is the first one left for the trip's
    own objects."""
    from commonroad.scenario.lanelet import Lanelet, LaneletType
    from commonroad.scenario.obstacle import StaticObstacle
    from commonroad.scenario.scenario import Scenario
    from commonroad.scenario.state import InitialState

    scenario = Scenario(dt, sid)
    ids = iter(range(FIRST_ID, 100 * FIRST_ID))
    for lanelet in lanelets(doc, ids):
        scenario.add_objects(
            Lanelet(
                *lanelet[:4],
                lanelet_type={
                    LaneletType.PARKING if lanelet[4] == "slot" else LaneletType.DRIVE_WAY
                },
            )
        )
    for kind, shape, where in static_obstacles(doc["lot"]):
        state = InitialState(
            position=np.array(where[:2]), orientation=where[2], velocity=0.0, time_step=0
        )
        scenario.add_objects(StaticObstacle(next(ids), kind, shape, state))
    scenario.next_id = next(ids)
    return scenario


def lanelets(doc: dict, ids) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, int, str]]:
    """``(left, centre, right, id, kind)`` of each lane of each aisle (kind ``lane``: its
    centreline offset as the lane is, bounds half the lane's width either side) and of each
    slot (kind ``slot``: from its entry side to its far end, bounds along its sides)."""
    drawing = doc["lot"].get("drawing") or {}
    out = []
    for aisle in drawing.get("aisles", []):
        line = np.asarray(aisle["centerline"], dtype=float)
        lanes = aisle["lanes"]
        width = float(aisle["width"]) / max(len(lanes), 1)
        for lane in lanes:
            centre = offset_line(line, -float(lane["offset"]))
            if not lane["with_polyline"]:
                centre = offset_line(line[::-1], -float(lane["offset"]))
            out.append(
                (
                    offset_line(centre, width / 2),
                    centre,
                    offset_line(centre, -width / 2),
                    next(ids),
                    "lane",
                )
            )
    for slot in drawing.get("slots", []):
        ring = [tuple(map(float, q)) for q in slot["polygon"]]
        a, b = (tuple(map(float, q)) for q in slot["entry"])
        ia, ib = ring.index(a), ring.index(b)
        n = len(ring)
        # the side from a: its other end is the neighbour of a that is not b
        far_a = ring[(ia - 1) % n] if ring[(ia + 1) % n] == b else ring[(ia + 1) % n]
        far_b = ring[(ib - 1) % n] if ring[(ib + 1) % n] == a else ring[(ib + 1) % n]
        side_a, side_b = np.array([a, far_a]), np.array([b, far_b])
        # left bound: on the left of the way in
        way = (side_a[1] + side_b[1]) / 2 - (side_a[0] + side_b[0]) / 2
        across = side_a[0] - side_b[0]
        left, right = (
            (side_a, side_b) if way[0] * across[1] - way[1] * across[0] < 0 else (side_b, side_a)
        )
        out.append((left, (left + right) / 2, right, next(ids), "slot"))
    return out
