"""Turnarounds: a multi-point turn from the end of a lane into the opposite lane of its aisle.

Where a two-way aisle ends in a dead end (a cul-de-sac, the closed half of an aisle, a lot
whose one gate is both the way in and the way out), a car turns back as a driver does in a
narrow street: forward at full lock towards the far side until the next step would touch
something, reverse at the other lock (which keeps turning it the same way), and so on, until
one last forward move — a straight, one arc and a straight along the lane, or, where the
strokes have turned it round beside the lane, an S of two wide arcs — lands it on the
opposite lane heading back. The fewest direction changes win, then the shortest path.

Everything is checked for the scenario's design vehicle (the envelope of its types, so every
type can drive it: its arcs are no tighter than the largest minimum turning radius) grown by
a safety margin, against every slot (all count as taken), wall, obstacle and no-go area,
inside the lot boundary; sweeps are checked as hulls of consecutive footprints.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from lotsim.core.geometry import FloatArray, Segment, advance, sample_segments
from lotsim.lot.build import obstacle_polygons
from lotsim.lot.clearance import Collider, first_blocked
from lotsim.lot.model import DesignVehicle, Lane, Lot
from lotsim.roadmap.multipoint import closings, segment_to_world, to_local, to_world

MARGIN = 0.1
"""Clearance kept to slots, walls and the boundary during a turnaround [m] (seed 004)."""
MAX_CHANGES = 8
"""Most direction changes a turnaround may have."""
PROBE = 0.25
"""Spacing of the places along each stroke where the last move onto the lane is tried [m]."""
STEP = 0.1
"""Spacing of the footprints whose hulls cover a stroke when checking it [m]."""
STARTS = (0.0, 2.0, 4.0, 6.0)
"""How far before a lane's end a turnaround may begin [m]: a driver who knows the street
ends starts turning before it does, where the first forward stroke has room."""
MIN_STROKE = 0.3
"""Shorter strokes are not worth a stop [m]."""


@dataclass(frozen=True, slots=True)
class Turnaround:
    """A multi-point turn from ``lane_a`` at ``station_a`` onto ``lane_b`` at ``station_b``.

    ``segments`` are driven in order, each in its own gear (the sign of its distance).
    """

    lane_a: str
    station_a: float
    lane_b: str
    station_b: float
    segments: tuple[Segment, ...]

    @property
    def changes(self) -> int:
        """Direction changes (cusps)."""
        gears = [s.gear for s in self.segments]
        return sum(1 for a, b in zip(gears[:-1], gears[1:], strict=True) if a != b)


def turnaround_collider(lot: Lot, design: DesignVehicle | None = None, margin: float = MARGIN
                        ) -> tuple[Collider, DesignVehicle]:
    """A checker for turnarounds on ``lot``: every slot, area and the boundary (no gates
    beyond aisle ends: a car turns back inside the lot), and ``design`` (default the lot's
    design vehicle) grown by ``margin``."""
    d = design or lot.design
    grown = dataclasses.replace(d, width=d.width + 2 * margin, front=d.front + margin,
                                rear=d.rear + margin)
    return Collider(obstacle_polygons(lot.areas, lot.slots), lot.boundary), grown


def turnaround_clear(t: Turnaround, collider: Collider, body: DesignVehicle) -> bool:
    """Whether ``body`` (see :func:`turnaround_collider`) drives turnaround ``t`` clear of
    everything ``collider`` holds (hulls of footprints :data:`STEP` apart)."""
    return not _blocked(np.zeros(3), list(t.segments), collider, body)  # world = local


def plan_turnaround(lane: Lane, back: Lane, collider: Collider, body: DesignVehicle,
                    radius: float, *, starts: tuple[float, ...] = ()) -> Turnaround | str:
    """A turnaround from the end of ``lane`` onto ``back`` (the opposite lane of the aisle,
    straight where it begins), for a car whose outline is ``body`` and whose tightest arc
    has ``radius`` [m], beginning :data:`STARTS` (or ``starts``) metres before the lane's
    end; or why there is none.

    Examples
    --------
    >>> from lotsim.lot.model import DesignVehicle
    >>> from shapely.geometry import box
    >>> from lotsim.core.geometry import Segment
    >>> from lotsim.lot.model import Lane
    >>> street = box(0, 0, 40, 9)   # a 9 m wide dead-end street, closed at x = 40
    >>> car = DesignVehicle(1.8, 3.7, 1.0, 4.97, 0.15, 2.0)
    >>> east = Lane("e", "a", (Segment((0.0, 2.25, 0.0), 36.0, 0.0),), 2.25, True)
    >>> west = Lane("w", "a", (Segment((36.0, 6.75, math.pi), 36.0, 0.0),), 2.25, False)
    >>> t = plan_turnaround(east, west, Collider([], street), car, 4.97)
    >>> t.changes, t.lane_b, t.station_a
    (2, 'w', 30.0)
    """
    seg = back.segments[0]
    if seg.curvature != 0.0 or seg.sharpness != 0.0:
        return "the opposite lane bends where it begins"
    frame = np.array(seg.start)  # local frame: the opposite lane runs along +x from 0
    found = []
    for back_off in starts or STARTS:
        station = lane.length - back_off
        i, _ = lane.locate(max(station, 0.0))
        if station < 0 or lane.segments[i].curvature or lane.segments[i].sharpness:
            break  # the lane bends (or ends) there: start no further back
        start = to_local(frame, np.array(lane.pose_at(station)))
        if start[1] <= 0.0:
            return "the opposite lane is not on the left"
        start[2] = math.pi  # heading the other way, up to rounding
        best = _multipoint(frame, start, seg.length, collider, body, radius)
        if best is not None:
            found.append((best[0], best[1], station, best[2]))
    if not found:
        return (f"no multi-point turn with up to {MAX_CHANGES} direction changes keeping "
                f"{MARGIN:g} m clear")
    _, _, station, local = min(found, key=lambda c: c[:3])
    segs = tuple(segment_to_world(frame, x) for x in local)
    return Turnaround(lane.id, station, back.id, float(local[-1].end[0]), segs)


def plan_turnarounds(lane: Lane, back: Lane, collider: Collider, body: DesignVehicle,
                     radius: float) -> list[Turnaround] | str:
    """The best turnaround at the end of ``lane`` (:func:`plan_turnaround`) and, when that
    begins before the lane's last stretch, the best one that begins last: a car that parks
    or comes out of a slot past the first's start must still be able to turn."""
    best = plan_turnaround(lane, back, collider, body, radius)
    if isinstance(best, str):
        return best
    out = [best]
    for k in range(len(STARTS)):
        if lane.length - STARTS[k] <= best.station_a + 1e-9:
            break
        last = plan_turnaround(lane, back, collider, body, radius, starts=STARTS[k : k + 1])
        if not isinstance(last, str):
            out.append(last)
            break
    return out


def _multipoint(frame: FloatArray, start: FloatArray, lane_length: float, collider: Collider,
                body: DesignVehicle, radius: float) -> tuple[int, float, list[Segment]] | None:
    """The fewest-changes, then shortest, turnaround from local ``start`` onto the line
    y = 0 heading +x (local frame ``frame``), as ``(changes, length, segments)``."""
    kmax = 1.0 / radius
    pose, done = start, []  # strokes so far
    best = None
    for k in range(MAX_CHANGES + 1):
        gear = 1 if k % 2 == 0 else -1
        kappa = gear * kmax  # forward at left lock, reverse at right lock: turning left
        left = 2 * math.pi - pose[2]  # heading still to turn
        extent = _extent(frame, pose, gear, kappa, min(left, math.pi / 2) / kmax, collider, body)
        probes = np.unique(np.append(np.arange(0.0, extent, PROBE), extent)) if gear > 0 \
            else np.array([extent])
        poses = advance(pose, gear * probes, kappa) if len(probes) else np.zeros((0, 3))
        changes = k + (1 if gear < 0 else 0)
        order = sorted(zip(poses, probes, strict=True), key=lambda c: c[1])
        options = [closings(q, lane_length, radius) for q, _ in order]
        # the shortest clear closing from each pose is enough
        for (_, s), paths, clear in zip(order, options,
                                        _first_clear(frame, options, collider, body),
                                        strict=True):
            if clear is None:
                continue
            segs = done + ([Segment(tuple(map(float, pose)), gear * float(s), kappa)]
                           if s > 1e-9 else []) + paths[clear]
            length = sum(x.length for x in segs)
            if best is None or (changes, length) < best[:2]:
                best = (changes, length, segs)
        if best is not None and best[0] <= changes:
            break
        if left <= 1e-6 or extent < MIN_STROKE and k > 0:
            break
        if extent < MIN_STROKE:
            continue  # no room ahead at the lane's end: begin by reversing
        stroke = Segment(tuple(map(float, pose)), gear * float(extent), kappa)
        done.append(stroke)
        pose = np.array(stroke.end)
    return best


def _extent(frame: FloatArray, pose: FloatArray, gear: int, kappa: float, cap: float,
            collider: Collider, body: DesignVehicle) -> float:
    """How far a stroke from local ``pose`` runs clear, to :data:`STEP` [m]."""
    n = max(1, math.ceil(cap / STEP))
    s = np.linspace(0.0, cap, n + 1)
    local = advance(pose, gear * s, kappa)
    bad = first_blocked(collider.blocked, body.footprints(to_world(frame, local)),
                        np.zeros(n, dtype=int))
    first = int(bad.argmax()) if bad.any() else n
    return float(s[first])


def _first_clear(frame: FloatArray, options: list[list[list[Segment]]], collider: Collider,
                 body: DesignVehicle) -> list[int | None]:
    """For each list of paths (local, in ``frame``) in ``options``, the index of the first
    not :func:`_blocked`, or None: the first paths of all checked in one batch, then the
    second paths of those whose first was blocked, and so on."""
    out: list[int | None] = [None] * len(options)
    todo = [i for i, paths in enumerate(options) if paths]
    k = 0
    while todo:
        hit = _blocked_each(frame, [options[i][k] for i in todo], collider, body)
        for i, blocked in zip(todo, hit, strict=True):
            if not blocked:
                out[i] = k
        k += 1
        todo = [i for i, blocked in zip(todo, hit, strict=True) if blocked and k < len(options[i])]
    return out


def _blocked_each(frame: FloatArray, paths: list[list[Segment]], collider: Collider,
                  body: DesignVehicle) -> list[bool]:
    """Whether each of ``paths`` (local, in ``frame``) touches anything: the hulls of its
    consecutive footprints :data:`STEP` apart, a path a run of its own in
    :func:`~lotsim.lot.clearance.first_blocked` (so checking them together tests the same
    bodies as one by one); a path that is a point, its footprint."""
    sampled = [sample_segments(segs, STEP)[0] for segs in paths]
    sizes = [len(x) for x in sampled]
    owner = np.repeat(np.arange(len(paths)), sizes)
    run = np.where(owner[1:] == owner[:-1], owner[1:], -1)
    prints = body.footprints(to_world(frame, np.concatenate(sampled)))
    hit = np.zeros(len(paths), dtype=bool)
    hit[run[first_blocked(collider.blocked, prints, run)]] = True
    point = [k for k, n in enumerate(sizes) if n == 1]
    if point:
        hit[point] = collider.blocked(prints[np.cumsum(sizes)[point] - 1])
    return hit.tolist()


def _blocked(frame: FloatArray, segs: list[Segment], collider: Collider,
             body: DesignVehicle) -> bool:
    return _blocked_each(frame, [segs], collider, body)[0]


