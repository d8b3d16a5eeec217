"""Walks over a lot's paved ground: the shortest path a person walks from a bay to a building
entrance, not across other bays (parked cars), islands, obstacles or buildings.

The ground people walk over (:func:`walking_ground`) is the paved ground less every bay and
every area; the bays are united first, so a row of bays is one block. A walk
(:func:`shortest_walk`) may also cross the ground it is *opened* to (the walker's own bay).
The shortest path in a polygon with holes bends only at the region's reflex corners, so it is
found exactly on the visibility graph of those corners (which corners see each other: a
segment covered by the region, tested for all pairs at once with shapely's vectorised
predicates) by Dijkstra's algorithm, with no stepping.

An entrance off the walkable ground (just outside the lot's boundary, or in a building) is
reached by walking to the nearest point of the walkable ground and then straight on.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, Point
from shapely.geometry.base import BaseGeometry
from shapely.geometry.polygon import orient
from shapely.ops import nearest_points

from lotsim.core.geometry import FloatArray

Point2 = tuple[float, float]

GAP = 1e-6
"""Bays closer than twice this [m] stand as one block: no one walks between them."""
TOLERANCE = 1e-7
"""How far [m] a segment may stray over the region's edge and still count as on it (the
nearest point of the ground to an entrance is on its edge only to within rounding)."""


@dataclass(frozen=True, eq=False)
class WalkingGround:
    """Where people walk, with the visibility graph of its corners.

    Attributes
    ----------
    ground : BaseGeometry
        The paved ground (the lot's pavement, or its boundary when paved wall to wall).
    region : BaseGeometry
        ``ground`` less the bays and areas: where a walk may go [m].
    corners : ndarray, shape (N, 2)
        The region's reflex corners: where a shortest walk may bend [m].
    seen : ndarray, shape (M, 2)
        Pairs of ``corners`` (indices) that see each other over ``region``.
    unseen : ndarray, shape (K, 2)
        The other pairs (a walk opened to more ground may see across them).
    """

    ground: BaseGeometry
    region: BaseGeometry
    corners: FloatArray
    seen: np.ndarray
    unseen: np.ndarray


@dataclass(frozen=True, slots=True)
class WalkPath:
    """A walk: its points from the start to the entrance, its length and the straight line
    between its ends [m]."""

    points: FloatArray
    length: float
    straight: float

    @property
    def line(self) -> LineString:
        return LineString(self.points)


def walking_ground(ground: BaseGeometry, bays: Iterable, obstacles: Iterable = ()
                   ) -> WalkingGround:
    """The ground people walk over: ``ground`` less the polygons of ``bays`` ((4, 2) corners
    or shapely polygons, united into blocks) and of ``obstacles`` (islands, buildings).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> row = [box(x, 4, x + 2.5, 9) for x in (2.5, 5.0, 7.5)]  # one block of three bays
    >>> wg = walking_ground(box(0, 0, 20, 12), row)
    >>> len(wg.corners), round(wg.region.area, 3)
    (4, 202.5)
    """
    shapes = [b if isinstance(b, BaseGeometry) else shapely.Polygon(np.asarray(b))
              for b in bays]
    blocked = [shapely.union_all(shapely.buffer(np.asarray(shapes, dtype=object), GAP,
                                                join_style="mitre"))] if shapes else []
    blocked += list(obstacles)
    region = ground.difference(shapely.union_all(blocked)) if blocked else ground
    region = shapely.simplify(region, TOLERANCE / 10)
    corners = _reflex_corners(region)
    n = len(corners)
    i, j = np.triu_indices(n, 1)
    tolerant = _tolerant(region)
    ok = (shapely.covered_by(shapely.linestrings(np.stack([corners[i], corners[j]], axis=1)),
                             tolerant) if len(i) else np.zeros(0, dtype=bool))
    pairs = np.stack([i, j], axis=1)
    return WalkingGround(ground, region, corners, pairs[ok], pairs[~ok])


def shortest_walk(wg: WalkingGround, start: Point2, entrance: Point2, *,
                  opened: BaseGeometry | None = None) -> WalkPath:
    """The shortest walk over ``wg`` (and over ``opened``, such as the walker's own bay) from
    ``start`` to ``entrance`` [m]: to the entrance, or, where it stands off the walkable
    ground, to the ground's nearest point and straight on from there.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> wg = walking_ground(box(0, 0, 20, 12), [box(2, 4, 18, 6)])  # a row in the way
    >>> w = shortest_walk(wg, (10.0, 2.0), (10.0, 8.0))  # round the row's end
    >>> round(w.length, 4), round(2 * math.hypot(8.0, 2.0) + 2.0, 4), w.straight
    (18.4924, 18.4924, 6.0)
    """
    region = wg.region
    if opened is not None:  # over the blocks' edges, which stand out by GAP
        opened = shapely.intersection(shapely.buffer(opened, 2 * GAP, join_style="mitre"),
                                      wg.ground)
        region = shapely.union(region, opened)
    tolerant = _tolerant(region)
    start_p = np.asarray(start, dtype=float)
    door = np.asarray(entrance, dtype=float)
    if shapely.covered_by(Point(door), tolerant):
        target = door
    else:
        near = nearest_points(region, Point(door))[0]
        target = np.array([near.x, near.y])
    last = float(np.hypot(*(door - target)))
    tail = [door] if last > 0.0 else []
    straight = math.dist(start_p, door)
    if shapely.covered_by(LineString([start_p, target]), tolerant):
        return WalkPath(np.array([start_p, target, *tail]),
                        math.dist(start_p, target) + last, straight)
    base = wg.corners
    extra = [start_p, target]
    if opened is not None:
        # its corners: where it meets a block they are the region's new reflex corners
        extra += list(shapely.get_coordinates(opened))
    nodes = np.concatenate([base, np.asarray(extra)])
    n, m = len(base), len(nodes)
    # pairs with a new node, and corners' pairs the opened ground may join
    a, b = np.meshgrid(np.arange(m), np.arange(n, m), indexing="ij")
    new = np.stack([a.ravel(), b.ravel()], axis=1)
    new = new[(new[:, 0] < n) | (new[:, 0] < new[:, 1])]
    if opened is not None and len(wg.unseen):
        lines = shapely.linestrings(np.stack([base[wg.unseen[:, 0]], base[wg.unseen[:, 1]]],
                                             axis=1))
        new = np.concatenate([new, wg.unseen[shapely.intersects(lines, opened)]])
    lines = shapely.linestrings(np.stack([nodes[new[:, 0]], nodes[new[:, 1]]], axis=1))
    edges = np.concatenate([wg.seen, new[shapely.covered_by(lines, tolerant)]])
    lengths = np.hypot(*(nodes[edges[:, 0]] - nodes[edges[:, 1]]).T)
    import networkx as nx  # (here: a lot from the cache is validated without the library)

    graph = nx.Graph()
    graph.add_weighted_edges_from(zip(edges[:, 0].tolist(), edges[:, 1].tolist(),
                                      lengths.tolist(), strict=True))
    try:
        length, path = nx.single_source_dijkstra(graph, n, n + 1)
    except (nx.NetworkXNoPath, nx.NodeNotFound):
        return WalkPath(np.array([start_p, door]), math.inf, straight)
    return WalkPath(np.concatenate([nodes[path], np.asarray(tail).reshape(-1, 2)]),
                    float(length) + last, straight)


def _tolerant(region: BaseGeometry) -> BaseGeometry:
    out = shapely.buffer(region, TOLERANCE, join_style="mitre")
    shapely.prepare(out)
    return out


def _reflex_corners(region: BaseGeometry) -> FloatArray:
    """The corners of ``region``'s rings where its inside turns more than half a turn (a
    hole's convex corners, the outline's concave ones): (N, 2) [m]."""
    out = []
    for poly in shapely.get_parts(region):
        if not isinstance(poly, shapely.Polygon) or poly.is_empty:
            continue
        poly = orient(poly, 1.0)  # outline ccw, holes cw
        for ring in (poly.exterior, *poly.interiors):
            p = np.asarray(ring.coords)[:-1]
            if len(p) < 3:
                continue
            before, after = p - np.roll(p, 1, axis=0), np.roll(p, -1, axis=0) - p
            turn = before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]
            out.append(p[turn < 0])  # a right turn, inside on the left: reflex
    return np.concatenate(out) if out else np.zeros((0, 2))


def walk_start(slot, access_aisles: Iterable = ()) -> Point2:
    """Where a walk from ``slot`` (a :class:`~lotsim.lot.model.Slot`) begins: the middle of
    its side that opens onto the nearest of ``access_aisles`` (their (4, 2) corners), where
    a person gets out beside the car, or of its entry (the side opening onto the driving
    aisle) for a bay without one [m].

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> bay = NS(polygon=np.array([[0, 0], [2.5, 0], [2.5, 5], [0, 5]]),
    ...          entry=np.array([[0, 0], [2.5, 0]]))
    >>> walk_start(bay, [np.array([[2.5, 0], [4.0, 0], [4.0, 5], [2.5, 5]])]), walk_start(bay)
    ((2.5, 2.5), (1.25, 0.0))
    """
    aisles = [shapely.Polygon(np.asarray(a)) for a in access_aisles]
    if not aisles:
        mid = np.asarray(slot.entry, dtype=float).mean(axis=0)
        return (float(mid[0]), float(mid[1]))
    p = np.asarray(slot.polygon, dtype=float)
    mids = (p + np.roll(p, -1, axis=0)) / 2
    points = shapely.points(mids)
    far = np.min([shapely.distance(points, a) for a in aisles], axis=0)
    mid = mids[int(np.argmin(far))]
    return (float(mid[0]), float(mid[1]))
