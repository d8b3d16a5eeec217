"""The problem of parking one car in one slot from one lane, OMPL's problem definition:
the slot's local frame, the stretch of lane a maneuver may begin on, the window the search
may use and what it must keep out of (:class:`ManeuverProblem`); the lot's problems posed
and digested (:class:`LotProblems`).

The planner works in a frame attached to the slot and its lane (mirrored so the slot is
always on the right). Every other slot counts as taken (what a car parked there keeps
others out of: :meth:`~lotsim.lot.kinds.SlotKind.taken`), as do walls, obstacles and no-go
areas, each grown by the margin; the car stays inside the lot boundary shrunk by the margin
and on the pavement (up to its edge, a kerb and not a thing to hit), short of the far side
of the aisle by the margin (that side is a wall), or inside its own slot. Same geometry,
same maneuver: a problem's digest is the vehicle type, the rounded geometry inside the
window around the slot — the search cannot see past the window — and where the lane's
start grid falls beside the slot (the closing move runs on to a grid station), so
problems with equal digests have the same answer. It is worked out in the slot's frame,
from what meets the window there to the micrometre: it does not depend on where the lot
lies, and the bays of a regular row are posed for it once.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from lotsim.core.geometry import FloatArray, Segment, wrap_angle
from lotsim.core.keys import inputs, key_of, unordered
from lotsim.lot.kinds import kind_of
from lotsim.lot.model import Lane, Lot, Slot
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.vehicles.model import VehicleType


@dataclass(frozen=True, slots=True)
class LocalFrame:
    """A rigid (possibly mirrored) frame: local ``(x, y)`` ↦ origin + R(heading)·(x, ±y)."""

    x: float
    y: float
    heading: float
    mirror: bool

    def __reduce__(self) -> tuple:
        # by its fields, not by dataclass's slot state (a prepared lot keeps one a problem)
        return LocalFrame, (self.x, self.y, self.heading, self.mirror)

    def poses_to_world(self, p: FloatArray) -> FloatArray:
        p = np.atleast_2d(np.asarray(p, dtype=float))
        sy = -1.0 if self.mirror else 1.0
        c, s = math.cos(self.heading), math.sin(self.heading)
        lx, ly = p[:, 0], sy * p[:, 1]
        return np.stack([self.x + c * lx - s * ly, self.y + s * lx + c * ly,
                         wrap_angle(self.heading + sy * p[:, 2])], axis=-1)

    def poses_to_local(self, p: FloatArray) -> FloatArray:
        p = np.atleast_2d(np.asarray(p, dtype=float))
        sy = -1.0 if self.mirror else 1.0
        c, s = math.cos(self.heading), math.sin(self.heading)
        dx, dy = p[:, 0] - self.x, p[:, 1] - self.y
        return np.stack([c * dx + s * dy, sy * (-s * dx + c * dy),
                         wrap_angle(sy * (p[:, 2] - self.heading))], axis=-1)

    def points_to_world(self, pts: FloatArray) -> FloatArray:
        """Local points (..., 2) in the world."""
        pts = np.asarray(pts, dtype=float)
        sy = -1.0 if self.mirror else 1.0
        c, s = math.cos(self.heading), math.sin(self.heading)
        lx, ly = pts[..., 0], sy * pts[..., 1]
        return np.stack([self.x + c * lx - s * ly, self.y + s * lx + c * ly], axis=-1)

    def points_to_local(self, pts: FloatArray) -> FloatArray:
        pts = np.asarray(pts, dtype=float)
        flat = np.column_stack([pts.reshape(-1, 2), np.zeros(pts.size // 2)])
        return self.poses_to_local(flat)[:, :2].reshape(pts.shape)

    def segments_to_world(self, segs: Sequence[Segment]) -> tuple[Segment, ...]:
        """Each of ``segs`` in world coordinates: :meth:`poses_to_world` of their starts, in
        the same operations on Python floats (a handful of segments: numpy's set-up would
        cost more than the sums), so the same floats."""
        sy = -1.0 if self.mirror else 1.0
        c, s = math.cos(self.heading), math.sin(self.heading)
        x0, y0, h0 = self.x, self.y, self.heading
        out = []
        for seg in segs:
            lx, ly, th = seg.start
            ly = sy * ly
            start = (x0 + c * lx - s * ly, y0 + s * lx + c * ly,
                     (h0 + sy * th + math.pi) % (2 * math.pi) - math.pi)
            out.append(Segment(start, seg.distance, sy * seg.curvature, sy * seg.sharpness))
        return tuple(out)


@dataclass(frozen=True, eq=False)
class ManeuverProblem:
    """One car into one slot from one lane, seen in the slot's local frame (slot at y < 0,
    the lane heading +x): everything a search reads, frozen. Its validity checks (is this
    footprint free, is this motion free) are :class:`~lotsim.maneuvers.validity.Validity`.

    Attributes
    ----------
    vehicle : VehicleType
    slot : Slot
    lane : Lane
    frame : LocalFrame
        Local ↔ world.
    lane_y : float
        The lane's straight near the slot is the line y = lane_y (NaN: it bends there).
    lane_x : tuple of float
        ... between these x [m]: where a maneuver may begin.
    lane_s0 : float
        Lane station at local x = 0 [m].
    half : float
        Half the size of the square window the search may use [m].
    allowed : BaseGeometry
        The prepared world region the car must stay in.
    obstacles : ndarray of Polygon
        What the car must keep out of near the slot (world).
    tree : STRtree
        Of ``obstacles``.
    sweep : float
        Footprint spacing when checking a motion [m].
    window : Polygon
        The square the search may use (:meth:`LotProblems.window`).
    """

    vehicle: VehicleType
    slot: Slot
    lane: Lane
    frame: LocalFrame
    lane_y: float
    lane_x: tuple[float, float]
    lane_s0: float
    half: float
    allowed: BaseGeometry
    obstacles: np.ndarray
    tree: shapely.STRtree
    sweep: float
    window: Polygon


class LotProblems:
    """The maneuver problems of one lot: poses each (vehicle, slot, lane) problem against what
    the lot's parked cars, walls, obstacles and no-go areas take (each grown by the margin),
    and digests it by its rounded local geometry (equal digests, equal answers).

    Parameters
    ----------
    lot : Lot
    settings : ManeuverSettings
    parked_width : float, keyword-only
        Width of the widest car that may stand in a perpendicular or angled slot [m];
        default the lot's design width.
    lane_ranges : dict, keyword-only
        Lane id → (first, last) station [m] where a maneuver may start, or several such
        ranges (a slot's maneuver is planned in the one nearest it); a lane not listed gets
        none. Default (None): every lane, whole.
    """

    def __init__(self, lot: Lot, settings: ManeuverSettings, *,
                 parked_width: float | None = None,
                 lane_ranges: dict[str, tuple] | None = None):
        margin = settings.margin
        self.lot, self.settings, self.lane_ranges = lot, settings, lane_ranges
        width = max(parked_width or 0.0, lot.design.width)
        polys = [kind_of(s).taken(s, width, margin) for s in lot.slots]
        polys += [a.polygon.buffer(margin, join_style="mitre") if margin else a.polygon
                  for a in lot.areas]
        # an access aisle is ground no car parks or drives on (its own bays' cars come up to
        # its markings: the slot itself is cut out of what a problem keeps out of)
        polys += [a.shape.buffer(margin, join_style="mitre") if margin else a.shape
                  for a in lot.access_aisles]
        self._polys = np.array(polys, dtype=object)
        self._tree = shapely.STRtree(self._polys)
        # the margin keeps the car off the lot's walls; the pavement's edge is a kerb or a
        # verge, not a thing to hit: the car may come up to it, not over it
        self._region = lot.boundary.buffer(-margin, join_style="mitre") if margin \
            else lot.boundary
        if lot.pavement is not None:
            self._region = self._region.intersection(lot.pavement)
        self._index = {s.id: k for k, s in enumerate(lot.slots)}
        self._framings: dict[tuple, tuple] = {}  # (vehicle, slot id, lane id) → its framing
        self._far: dict[tuple, float] = {}  # (slot id, frame) → :meth:`_far_sides`

    def __getstate__(self) -> dict:
        # without what it worked out for problems (made again when asked for)
        return {**self.__dict__, "_framings": {}, "_far": {}}

    @property
    def margin(self) -> float:
        return self.settings.margin

    def pose(self, vehicle: VehicleType, slot: Slot, lane: Lane) -> ManeuverProblem:
        """The problem of parking ``vehicle`` in ``slot`` from ``lane``."""
        frame, lane_y, lane_x, s0, half = self.framing(vehicle, slot, lane)
        index = self._index[slot.id]
        win = self.window(slot, frame, half)
        shapely.prepare(win)
        # the slot itself is the car's to fill: no margin to its own lines
        allowed = self._region.union(slot.shape).intersection(win)
        shapely.prepare(allowed)
        near = [int(k) for k in self._tree.query(win) if k != index]
        # the margin around neighbours stops at this slot's lines: the car may fill its slot.
        # Inside the window, those clear of the slot are kept as they are (the same shapes as
        # their difference, in another vertex order); those across its edge are made as
        # before, as :meth:`digest` cuts them at the edge (a cut's rounded corners follow
        # the order of the vertices cut).
        obstacles = self._polys[near]
        cut = ~shapely.contains_properly(win, obstacles) | shapely.intersects(obstacles,
                                                                              slot.shape)
        obstacles[cut] = shapely.difference(obstacles[cut], slot.shape)
        return ManeuverProblem(vehicle, slot, lane, frame, lane_y, lane_x, s0, half, allowed,
                               obstacles, shapely.STRtree(obstacles), self.settings.sweep, win)

    def framing(self, vehicle: VehicleType, slot: Slot, lane: Lane
             ) -> tuple[LocalFrame, float, tuple[float, float], float, float]:
        """A problem's frame, lane line (``lane_y``, NaN on a bend), the stretch of it a
        maneuver may begin on (``lane_x``), the lane station at x = 0 and the window's
        half size (:meth:`framings` of the one triple)."""
        return self.framings([(vehicle, slot, lane)])[0]

    def framings(self, triples: Sequence[tuple[VehicleType, Slot, Lane]]
                 ) -> list[tuple[LocalFrame, float, tuple[float, float], float, float]]:
        """:meth:`framing` of each triple: the slot's entry projected onto the lane a lane at
        a time (lanes are told apart by their ids) and posed there
        (:meth:`~lotsim.lot.model.Lane.poses_at`), the rest in the sums of
        :meth:`LocalFrame.poses_to_local`, so the same floats. Each is worked out once and
        kept (a problem keyed in a batch is posed whole later, one at a time)."""
        return _kept(self._framings, [(v, slot.id, lane.id) for v, slot, lane in triples],
                     lambda at: self._made_framings([triples[k] for k in at]))

    def _made_framings(self, triples: Sequence[tuple[VehicleType, Slot, Lane]]
                       ) -> list[tuple[LocalFrame, float, tuple[float, float], float, float]]:
        """:meth:`framings` of ``triples``, worked out."""
        n = len(triples)
        mids = np.array([slot.entry for _, slot, _ in triples], dtype=float).reshape(
            n, -1, 2).mean(axis=1)
        stations = np.empty(n)
        by_lane: dict[str, list[int]] = {}
        for k, (_, _, lane) in enumerate(triples):
            by_lane.setdefault(lane.id, []).append(k)
        heading = np.empty(n)
        index = np.empty(n, dtype=np.int64)
        for at in by_lane.values():
            lane = triples[at[0]][2]
            s_mid = shapely.line_locate_point(lane.line, shapely.points(mids[at]))
            stations[at] = s_mid
            heading[at] = [pose[2] for pose in lane.poses_at(s_mid)]
            index[at] = lane.locate_all(s_mid)[0]
        out = []
        for k, (vehicle, slot, lane) in enumerate(triples):
            mx, my, t, i = float(mids[k, 0]), float(mids[k, 1]), float(heading[k]), int(index[k])
            seg = lane.segments[i]
            cx, cy = slot.center
            c, s = math.cos(t), math.sin(t)
            frame = LocalFrame(mx, my, t, c * (cy - my) - s * (cx - mx) > 0)
            half = _half(vehicle)
            if seg.curvature != 0.0 or seg.sharpness != 0.0:
                out.append((frame, math.nan, (0.0, 0.0), 0.0, half))
                continue
            sy = -1.0 if frame.mirror else 1.0
            dx, dy = seg.start[0] - mx, seg.start[1] - my
            lo, lane_y = c * dx + s * dy, sy * (-s * dx + c * dy)
            s0 = float(lane.starts[i]) - lo
            if kind_of(slot).parks_along:
                # a parallel slot is left at a shallow heading (about 25°), so the closing
                # straight onto a lane lane_y away reaches some 2 lane_y along it: the
                # window must hold the car at its end (a fixed window refused roomy aisles)
                half += 2.0 * abs(lane_y)
            first, last = self._span(lane, float(stations[k]))
            out.append((frame, lane_y, (max(lo, -half, first - s0),
                                        min(lo + seg.length, half, last - s0)), s0, half))
        return out

    def _span(self, lane: Lane, station: float) -> tuple[float, float]:
        """The (first, last) stations of ``lane`` where a maneuver may start nearest
        ``station`` (the first of those it lies in)."""
        spans = (((0.0, lane.length),) if self.lane_ranges is None
                 else self.lane_ranges.get(lane.id, ((math.inf, -math.inf),)))
        if spans and not isinstance(spans[0], tuple):
            spans = (spans,)  # one (first, last)
        return min(spans, key=lambda r: max(r[0] - station, station - r[1], 0.0))

    def window(self, slot: Slot, frame: LocalFrame, half: float) -> Polygon:
        """The square the search may use, cut at the far side of the aisle less the margin."""
        h, top = half, self._top(slot, frame, half)
        corners = np.array([[-h, -h, 0], [h, -h, 0], [h, top, 0], [-h, top, 0]], dtype=float)
        return Polygon(frame.poses_to_world(corners)[:, :2])

    def _top(self, slot: Slot, frame: LocalFrame, half: float) -> float:
        """The window's top edge (local y): its half size, or the far side of the aisle less
        the margin where that is nearer (:meth:`_tops` of the one slot)."""
        return float(self._tops([slot], [frame], np.array([half]))[0])

    def _tops(self, slots: Sequence[Slot], frames: Sequence[LocalFrame], halves: FloatArray
              ) -> FloatArray:
        """:meth:`_top` of each slot in its frame with its window's half size: where its
        entry's middle lies across its aisle (:meth:`_far_sides`, each worked out once and
        kept)."""
        far = _kept(self._far, [(slot.id, frame) for slot, frame in zip(slots, frames,
                                                                        strict=True)],
                    lambda at: self._far_sides([slots[k] for k in at],
                                               [frames[k] for k in at]).tolist())
        return np.minimum(halves, np.array(far))

    def _far_sides(self, slots: Sequence[Slot], frames: Sequence[LocalFrame]) -> FloatArray:
        """The far side of each slot's aisle less the margin (local y in its frame), an
        aisle at a time."""
        n = len(slots)
        mids = np.array([slot.entry for slot in slots], dtype=float).reshape(n, -1, 2).mean(
            axis=1)
        by_aisle: dict[str, list[int]] = {}
        for k, slot in enumerate(slots):
            by_aisle.setdefault(slot.aisle, []).append(k)
        on_line = np.empty((n, 2))
        widths = np.empty(n)
        for aisle_id, at in by_aisle.items():
            aisle = self.lot.aisles[aisle_id]
            along = shapely.line_locate_point(aisle.line, shapely.points(mids[at]))
            on_line[at] = shapely.get_coordinates(shapely.line_interpolate_point(aisle.line,
                                                                                 along))
            widths[at] = aisle.width
        centre_y = _to_local(on_line, _frames(frames))[:, 1]
        return centre_y + widths / 2 - self.margin

    def digest(self, p: ManeuverProblem) -> bytes:
        """The car, the slot, the rounded local geometry within the window and where the
        lane's start grid falls (:meth:`digests` of the problem alone)."""
        return self.digests([(p.vehicle, p.slot, p.lane)])[0][0]

    def digests(self, triples: Sequence[tuple[VehicleType, Slot, Lane]]
                ) -> list[tuple[bytes, LocalFrame, float, bytes | None]]:
        """The digest of each triple's problem, with its frame, lane station at x = 0 and
        shape (:func:`shape_key`), without the rest of a problem (its obstacle tree), which
        only a search needs.

        A digest is worked out in the slot's frame from what meets the window, to the
        micrometre: the slot, the ground and the neighbours (each taken slot, wall, obstacle
        and no-go area, grown by the margin). Those are posed there as :meth:`pose` poses
        them in the world — the ground cut at the window, the neighbours at the slot's
        lines and the window — and rounded to 1 cm. Problems alike to the micrometre (the
        bays of a regular row) are posed once, and a digest depends on nothing else: not
        on where the lot lies, nor on which problems are digested with it. Each step is one
        shapely or numpy call over all of them."""
        n = len(triples)
        if n == 0:
            return []
        framings = self.framings(triples)
        frames = [f[0] for f in framings]
        halves = np.array([f[4] for f in framings])
        tops = self._tops([slot for _, slot, _ in triples], frames, halves)
        # what may meet each window: what meets its bounds in the world, a millimetre wider
        # (touching is decided in the slot's frame, to the micrometre)
        corners = np.stack([np.column_stack(c) for c in (
            (-halves, -halves), (halves, -halves), (halves, tops), (-halves, tops))], axis=1)
        axes = _frames(frames)
        world = _to_world(corners, axes)
        boxes = shapely.box(*(world.min(axis=1) - 0.001).T, *(world.max(axis=1) + 0.001).T)
        own = np.arange(n)
        tops = _micro(tops)
        wins = shapely.box(-halves, -halves, halves, tops)
        ground = _local(shapely.intersection(self._region, boxes), axes, own)
        shapes = _local(np.array([slot.shape for _, slot, _ in triples], dtype=object),
                        axes, own)
        k, j = self._tree.query(boxes)
        order = np.argsort(k, kind="stable")
        k, j = k[order], j[order]
        mine = np.array([self._index[slot.id] for _, slot, _ in triples], dtype=np.int64)
        k, j = k[j != mine[k]], j[j != mine[k]]
        near = _local(self._polys[j], axes, k)
        meets = shapely.intersects(wins[k], near)
        k, near = k[meets], near[meets]
        near_wkb = shapely.to_wkb(near).tolist()
        at = np.searchsorted(k, np.arange(n + 1)).tolist()
        ground_wkb = shapely.to_wkb(ground).tolist()
        shape_wkb = shapely.to_wkb(shapes).tolist()
        outlines = _micro(_to_local(np.array([slot.polygon for _, slot, _ in triples],
                                             dtype=float), axes))
        keys, commons = [], []
        margin, sweep = self.margin, self.settings.sweep
        cars = _keyed_once([v for v, _, _ in triples], lambda v: CarChecked(v, margin, sweep))
        for i, ((v, slot, _), (_, lane_y, lane_x, s0, half)) in enumerate(
                zip(triples, framings, strict=True)):
            outline = outlines[i]
            commons.append(_shape_of(v, slot, outline, lane_y, half))
            keys.append(key_of(WindowSeen(
                commons[-1], cars[i], float(halves[i]), float(tops[i]),
                round(lane_y, 6) if math.isfinite(lane_y) else None,
                self._along(lane_x, s0), outline, shape_wkb[i], ground_wkb[i],
                unordered(near_wkb[at[i]:at[i + 1]]))))
        first = {}
        for i, key in enumerate(keys):
            first.setdefault(key, i)
        posed = self._posed_locally(list(first.values()), triples, framings, commons, wins,
                                    ground, shapes, near, at)
        return [(posed[first[key]], f[0], f[3], shape_key(v, slot, f[1], f[4], c))
                for key, (v, slot, _), f, c in zip(keys, triples, framings, commons,
                                                   strict=True)]

    def _posed_locally(self, reps: list[int], triples, framings, commons, wins, ground, shapes,
                       near, at) -> dict[int, bytes]:
        """:meth:`digests` of the triples ``reps``, from their windows and what meets each
        in its frame (``ground``, ``shapes``; ``near[at[i]:at[i + 1]]`` for triple ``i``):
        those problems posed there and digested."""
        m = len(reps)
        r = np.array(reps, dtype=np.int64)
        wins = wins[r]
        shapely.prepare(wins)
        # the slot itself is the car's to fill: no margin to its own lines
        allowed = shapely.intersection(shapely.union(ground[r], shapes[r]), wins)
        pick = np.concatenate([np.arange(at[i], at[i + 1]) for i in reps]).astype(np.int64)
        of = np.repeat(np.arange(m), [at[i + 1] - at[i] for i in reps])
        obstacles = near[pick].copy()
        # the margin around neighbours stops at the slot's lines; only what reaches the
        # window's edge is cut there (as :meth:`pose`, then the window)
        cut = ~shapely.contains_properly(wins[of], obstacles) | shapely.intersects(
            obstacles, shapes[r][of])
        obstacles[cut] = shapely.difference(obstacles[cut], shapes[r][of[cut]])
        cross = ~shapely.contains_properly(wins[of], obstacles)
        obstacles[cross] = shapely.intersection(obstacles[cross], wins[of[cross]])
        # pointwise: a cache key needs rounded coordinates, not a valid polygon (a
        # neighbour's thin margin strip may self-touch once rounded, and GEOS's default mode
        # then throws a TopologyException)
        rounded = shapely.to_wkb(shapely.normalize(shapely.set_precision(
            np.concatenate([allowed, obstacles]), 0.01, mode="pointwise"))).tolist()
        per: list[list[bytes]] = [[rounded[q]] for q in range(m)]
        for g, o in zip(rounded[m:], of.tolist(), strict=True):
            per[o].append(g)
        out = {}
        for q, i in enumerate(reps):
            v, slot, _ = triples[i]
            _, lane_y, lane_x, s0, half = framings[i]
            out[i] = self._hashed(v, slot, lane_y, lane_x, s0, half, per[q], commons[i])
        return out

    def sources(self, triples: Sequence[tuple[VehicleType, Slot, Lane]]) -> list[bytes]:
        """What each triple's problem is made from, to the last bit, without posing it: the
        car, the slot, its lane and the stretch of it a maneuver may begin on, its aisle, and
        what lies about it — every taken slot, wall, obstacle and no-go area whose bounds meet
        a square about the slot holding the problem's window, and the edges of the region
        the car must stay in that meet it. Triples with equal sources pose the same problem
        (:meth:`pose`, :meth:`digests`), whatever else in the lot differs: an edited lot
        looks up what it posed before where the edit did not reach. A few times cheaper
        than :meth:`digests` (one tree query for all, and hashing)."""
        n = len(triples)
        if n == 0:
            return []
        mids = np.array([slot.entry.mean(axis=0) for _, slot, _ in triples])
        halves = np.array([self.framing(v, slot, lane)[4] if kind_of(slot).parks_along
                           else _half(v) for v, slot, lane in triples])
        reach = halves * math.sqrt(2.0) + 0.01  # the window, turned any way about the slot
        # where along its lane each slot lies (as :meth:`framing` finds it), for the stretch
        # of lane its window holds
        stations = np.empty(n)
        by_lane: dict[str, list[int]] = {}
        for k, (_, _, lane) in enumerate(triples):
            by_lane.setdefault(lane.id, []).append(k)
        for at in by_lane.values():
            stations[at] = shapely.line_locate_point(triples[at[0]][2].line,
                                                     shapely.points(mids[at]))
        boxes = shapely.box(mids[:, 0] - reach, mids[:, 1] - reach, mids[:, 0] + reach,
                            mids[:, 1] + reach)
        # the neighbours as a set (the tree's order changes with edits elsewhere): each by
        # the digest of its shape, in the digests' order, all of a triple's in one string
        wkb = shapely.to_wkb(self._polys).tolist()
        marks = np.array([hashlib.blake2b(g, digest_size=20).digest() for g in wkb],
                         dtype="S20")
        rank = np.argsort(np.argsort(marks, kind="stable"), kind="stable")
        k, j = self._tree.query(boxes)
        mine = np.array([self._index[slot.id] for _, slot, _ in triples], dtype=np.int64)
        k, j = k[j != mine[k]], j[j != mine[k]]
        order = np.lexsort((rank[j], k))
        near = marks[j[order]].tobytes()
        at = (np.searchsorted(k[order], np.arange(n + 1)) * 20).tolist()
        # the region's edges, each ring oriented alike (the interior on one side)
        rings = shapely.get_rings(shapely.normalize(self._region))
        ends = np.concatenate([np.empty((0, 4))] + [
            np.hstack([c[:-1], c[1:]]) for c in (shapely.get_coordinates(r) for r in rings)])
        edges = [[] for _ in range(n)]
        for k, j in zip(*shapely.STRtree(shapely.linestrings(ends.reshape(-1, 2, 2)))
                        .query(boxes).tolist(), strict=True):
            edges[k].append(j)
        inside = shapely.covers(self._region, shapely.points(mids)).tolist()
        aisles = {name: self.lot.aisles[name] for name in {slot.aisle for _, slot, _ in triples}}
        lines = {name: aisle.line.wkb for name, aisle in aisles.items()}
        margin, sweep = self.margin, self.settings.sweep
        cars = _keyed_once([v for v, _, _ in triples], lambda v: CarChecked(v, margin, sweep))
        lanes = _keyed_once([lane for _, _, lane in triples],
                            lambda lane: LaneLine(lane.id, lane.segments))
        out = []
        for k, (_, slot, lane) in enumerate(triples):
            # the stretch of lane a maneuver may begin on, as far as the window holds it
            s_mid, half = float(stations[k]), float(halves[k]) + 1.0
            first, last = self._span(lane, s_mid)
            aisle = aisles[slot.aisle]
            out.append(key_of(ProblemSources(
                cars[k], lanes[k],
                (max(first, s_mid - half), min(last, s_mid + half)), aisle.width,
                lines[slot.aisle], slot.id, slot.kind, slot.aisle, slot.width, slot.length,
                inside[k], slot.polygon, slot.entry, near[at[k]:at[k + 1]],
                wkb[int(mine[k])], ends[sorted(edges[k])])))
        return out

    def shape(self, vehicle: VehicleType, slot: Slot, lane: Lane) -> bytes | None:
        """:func:`shape_key` of the problem of ``vehicle`` in ``slot`` from ``lane``."""
        frame, lane_y, _, _, half = self.framing(vehicle, slot, lane)
        outline = _micro(frame.points_to_local(slot.polygon))
        return shape_key(vehicle, slot, lane_y, half, _shape_of(vehicle, slot, outline, lane_y,
                                                             half))

    def _along(self, lane_x: tuple[float, float], s0: float) -> tuple:
        """What a digest holds of the lane: the stretch a maneuver may begin on (to 1 cm)
        and where the lane's start grid falls (a closing move runs on along the lane to a
        grid station, so slots alike but for it do not start on the same offsets)."""
        grid = self.settings.start_grid
        phase = round(s0 % grid, 6) % grid if grid > 0 else 0.0
        return tuple(np.round(lane_x, 2)), phase

    def _hashed(self, v: VehicleType, slot: Slot, lane_y: float, lane_x: tuple[float, float],
                s0: float, half: float, local: list[bytes], common: ProblemShape) -> bytes:
        """The digest of a problem from its framing, its :func:`_shape_of` and its rounded local
        geometry (in any order)."""
        return key_of(ProblemDigest(common, self._along(lane_x, s0), unordered(local)))


def _half(vehicle: VehicleType) -> float:
    """Half the size of a problem's square window [m] (a parallel slot's grows with how far
    its lane is: :meth:`LotProblems.framing`)."""
    return 2 * vehicle.min_turning_radius + vehicle.length + 1.0


@inputs
class CarChecked:
    """The car a problem is posed for, with the margin kept from what it must not touch and
    the sweep's step [m]: the key of this is a field of :class:`ProblemSources` and
    :class:`WindowSeen`, made once per car (:func:`_keyed_once`) rather than in every
    problem's key."""

    vehicle: VehicleType
    margin: float
    sweep: float


@inputs
class LaneLine:
    """The lane a problem's maneuver begins on: its id and segments. The key of this is a
    field of :class:`ProblemSources`, made once per lane (:func:`_keyed_once`)."""

    lane: str
    segments: tuple[Segment, ...]


def _keyed_once(things: Sequence[object], made: Callable[[object], object]) -> list[bytes]:
    """The key of ``made(thing)`` for each of ``things`` (vehicle types, lanes: a few,
    each in many problems), each distinct object keyed once."""
    by: dict[int, bytes] = {}
    out = []
    for thing in things:
        key = by.get(id(thing))
        if key is None:
            key = by[id(thing)] = key_of(made(thing))
        out.append(key)
    return out


@inputs
class ProblemSources:
    """What a problem is made from, to the last bit, before it is posed
    (:meth:`LotProblems.sources`): the car with the margin and sweep (the key of its
    :class:`CarChecked`); its lane (the key of its :class:`LaneLine`) and the stretch of
    it a maneuver may begin on, as far as the window holds it [m]; the slot's aisle (width
    [m], line as WKB); the slot (id, kind, aisle, width and length [m], whether its entry
    lies in the region, outline and entry); the neighbours (the digests of their shapes,
    sorted: a set); the slot's own taken shape (WKB); and the region's edges that meet the
    square about the slot (each ring oriented alike)."""

    car: bytes
    lane: bytes
    stretch: tuple[float, float]
    aisle_width: float
    aisle_line: bytes
    slot: str
    kind: str
    aisle: str
    width: float
    length: float
    inside: bool
    outline: FloatArray
    entry: FloatArray
    neighbours: bytes
    taken: bytes
    edges: FloatArray


@inputs
class ProblemShape:
    """What a problem's digest and its shape (:func:`shape_key`) both hold: the car's body
    (name, width, front and rear overhangs, wheelbase [m], steering limit [rad]), the
    slot's kind and outline in the local frame to 1 cm (its corners sorted), the lane line
    (y to 1 mm; None where it bends) and the window's half size (to 1 mm)."""

    body: tuple[str, float, float, float, float, float]
    kind: str
    outline: FloatArray
    lane_y: float | None
    half: float


@inputs
class ProblemDigest:
    """What a problem's digest (:meth:`LotProblems.digests`) is made from: its shape, the
    stretch of lane a maneuver may begin on with the start grid's phase
    (:meth:`LotProblems._along`), and its rounded local geometry as a set."""

    shape: ProblemShape
    along: tuple
    local: tuple[bytes, ...]


@inputs
class WindowSeen:
    """What poses a problem's rounded local geometry (:meth:`LotProblems.digests`): its
    shape, the car with the margin and sweep (the key of its :class:`CarChecked`), the
    window's half size and top [m],
    the lane line (y to 1 µm), the stretch of lane, and the slot's outline, its shape, the
    ground and the neighbours (as a set) in the slot's frame to 1 µm (WKB). Problems
    alike in these are posed once."""

    shape: ProblemShape
    car: bytes
    half: float
    top: float
    lane_y: float | None
    along: tuple
    outline: FloatArray
    slot_shape: bytes
    ground: bytes
    near: tuple[bytes, ...]


def _shape_of(vehicle: VehicleType, slot: Slot, outline: FloatArray, lane_y: float,
            half: float) -> ProblemShape:
    """The :class:`ProblemShape` of the problem of ``vehicle`` in ``slot`` (``outline`` in
    the local frame, the lane line at ``lane_y``, a window of half size ``half``)."""
    outline = np.sort(np.round(outline, 2).reshape(-1, 2) + 0.0, axis=0)
    return ProblemShape((vehicle.name, vehicle.width, vehicle.front, vehicle.rear,
                         vehicle.wheelbase, vehicle.max_steer), slot.kind, outline,
                        round(lane_y, 3) if math.isfinite(lane_y) else None, round(half, 3))


def shape_key(vehicle: VehicleType, slot: Slot, lane_y: float, half: float,
              common: ProblemShape) -> bytes | None:
    """What problems that may share a maneuver have in common
    (:mod:`~lotsim.maneuvers.reuse`), or None for a problem that shares with none (a
    parallel slot, a lane that bends beside the slot): the key of their
    :class:`ProblemShape` — a digest without the stretch of lane a maneuver may begin on,
    the start grid's phase and the geometry around the slot."""
    if kind_of(slot).parks_along or not math.isfinite(lane_y):
        return None
    return key_of(common)


def _kept(known: dict, keys: list, make: Callable[[list[int]], Sequence]) -> list:
    """The value of each of ``keys`` in ``known``; those missing made first, once each, in
    one batch: ``make(indices)`` gives the values of the keys at those indices."""
    at: dict = {}
    for i, k in enumerate(keys):
        if k not in known:
            at.setdefault(k, i)
    if at:
        known.update(zip(at, make(list(at.values())), strict=True))
    return [known[k] for k in keys]


def _frames(frames: Sequence[LocalFrame]) -> np.ndarray:
    """(F, 5): the origin x and y, cosine, sine and sign of local y of each of ``frames``."""
    return np.array([(f.x, f.y, math.cos(f.heading), math.sin(f.heading),
                      -1.0 if f.mirror else 1.0) for f in frames]).reshape(-1, 5)


def _to_world(local: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """Points ``local[i, ...]`` in the world, in frame ``i`` of ``axes`` (:func:`_frames`)."""
    ox, oy, c, s, sy = (a.reshape((-1,) + (1,) * (local.ndim - 2)) for a in axes.T)
    lx, ly = local[..., 0], sy * local[..., 1]
    return np.stack([ox + c * lx - s * ly, oy + s * lx + c * ly], axis=-1)


def _to_local(points: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """Points ``points[i, ...]`` in frame ``i`` of ``axes`` (:func:`_frames`): the sums of
    :meth:`LocalFrame.points_to_local`, so the same floats."""
    ox, oy, c, s, sy = (a.reshape((-1,) + (1,) * (points.ndim - 2)) for a in axes.T)
    dx, dy = points[..., 0] - ox, points[..., 1] - oy
    return np.stack([c * dx + s * dy, sy * (-s * dx + c * dy)], axis=-1)


def _local(geoms: np.ndarray, axes: np.ndarray, owner: np.ndarray) -> np.ndarray:
    """Each of ``geoms`` in its frame, row ``owner[i]`` of ``axes`` (:func:`_frames`) for
    ``geoms[i]``, to the micrometre (the sums of :meth:`LocalFrame.points_to_local`, so the
    same floats)."""
    xy, at = shapely.get_coordinates(geoms, return_index=True)
    return shapely.set_coordinates(np.array(geoms, dtype=object),
                                   _micro(_to_local(xy, axes[np.asarray(owner)[at]])))


def _micro(xy: FloatArray) -> FloatArray:
    """``xy`` to the micrometre, -0 as 0 (the same bytes for the same place)."""
    return np.round(xy, 6) + 0.0


@inputs
class ExactProblem:
    """Everything a search of a problem in a style reads, floats to the last bit: the car,
    the slot's kind, size [m] and outline, the frame, the lane (its line y, the stretch a
    maneuver may begin on, the station at x = 0 [m]), the window's half size, the sweep,
    the style, and as WKB the slot's shape, the allowed region, the window and the set of
    obstacles (a search only asks whether a body meets any: their order is the lot's
    tree's, which an edit elsewhere in the lot changes)."""

    vehicle: VehicleType
    kind: str
    length: float
    width: float
    frame: LocalFrame
    lane_y: float
    lane_x: tuple[float, float]
    lane_s0: float
    half: float
    sweep: float
    style: str
    outline: FloatArray
    slot_shape: bytes
    allowed: bytes
    window: bytes
    obstacles: tuple[bytes, ...]


def exact_key(p: ManeuverProblem, style: str) -> bytes:
    """The key of the :class:`ExactProblem` of ``p`` in ``style``. Problems with equal
    keys, from any lot, are searched alike and have the same answer (for the same settings
    and lotsim). :meth:`ManeuverPlanner.key` rounds to 1 cm instead: it finds the problems
    of one lot that may share an answer."""
    shape, allowed, window = shapely.to_wkb([p.slot.shape, p.allowed, p.window]).tolist()
    return key_of(ExactProblem(
        p.vehicle, p.slot.kind, p.slot.length, p.slot.width, p.frame, p.lane_y, p.lane_x,
        p.lane_s0, p.half, p.sweep, style, np.asarray(p.slot.polygon, dtype=float), shape,
        allowed, window, unordered(shapely.to_wkb(p.obstacles).tolist())))
