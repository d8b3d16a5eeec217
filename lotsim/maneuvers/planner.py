"""Parking maneuvers: from a pose on an aisle lane into a slot, and back out.

A maneuver is a chain of :class:`~lotsim.core.geometry.Segment` pieces — straights and
arcs no tighter than the car's minimum turning radius, each driven forward or in
reverse — from a pose on a lane (on its centreline, heading its way) to the
parked pose inside the slot. Leaving is the same path driven backwards in time
(:meth:`Maneuver.reversed`): each piece flips gear, so a car that reversed in
drives out forward.

How each kind is planned
------------------------
* **Perpendicular and angled** slots: the car is parked centred in the slot,
  nose-in or nose-out. The planner works *outward* from the parked pose (the
  departure, which is the constrained end): drive out straight some distance,
  then shuffle — full lock turning toward the lane's heading until the next
  motion would touch something, the other gear with the opposite lock (which
  keeps turning the same way), and so on, as a driver does in a narrow aisle.
  From every 0.5 m of every stroke it tries an exact closing move — a straight
  then one arc of radius R·{1, 1.25, 1.5, 2, 3} that lands on the lane line
  heading the lane's way. The fewest direction changes wins, then the shortest
  path; the parking maneuver is that path reversed in time.
* **Parallel** slots: the minimum-slot planner's strokes (:mod:`.minslot`) for
  the real slot, shrunk by the safety margin on its three closed sides, over
  start headings 0…90° in order of (changes, length), joined to the lane by
  the same closing move from its start pose.

Everything is checked against the lot: every other slot counts as taken —
a perpendicular or angled slot by a strip as wide as the widest car centred
across it, a parallel slot whole (grown at its ends and kerb but not over its
entry line, which the minimum-slot strategy starts on) — as do walls,
obstacles and no-go areas, each grown by the safety margin; the car stays
inside the lot boundary shrunk by the margin and short of the far side of the
aisle by the margin (that side is a wall), or inside its own slot.
Sweeps are checked as hulls of consecutive footprints 0.2 m apart.

Same geometry, same maneuver: the planner works in a frame attached to the slot
and its lane (mirrored so the slot is always on the right), and caches results
by the vehicle type, the rounded geometry inside a window around the slot — the
search cannot see past the window — and where the lane's start grid falls beside
the slot (the closing move runs on to a grid station), so a cache hit is the
maneuver it would have planned.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import math
import multiprocessing
import os
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from enum import Enum

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from lotsim.core.geometry import (
    FloatArray,
    Pose,
    Segment,
    advance,
    ease_joints,
    same_pose,
    sample_pieces,
    sample_segments,
    wrap_angle,
)
from lotsim.core.workers import quiet_worker
from lotsim.errors import InfeasibleManeuver
from lotsim.lot.clearance import first_blocked, hulls, hulls_blocked
from lotsim.lot.model import Lane, Lot, Slot, unit
from lotsim.maneuvers.minslot import SlotFrame, simulate, start_headings
from lotsim.maneuvers.settings import MARGIN, STYLES
from lotsim.roadmap.lanes import lane_serves
from lotsim.roadmap.multipoint import plan_onto
from lotsim.vehicles.model import VehicleType
from lotsim.vehicles.motion import Motion, Piece, runs, timed_path

SWEEP = 0.2
"""Spacing of the footprints whose hulls cover a path when checking it [m]."""
ROUGH = 1.0
"""Spacing of the footprints of the cheap first pass that drops most blocked candidate paths
before their sweeps are checked [m]."""
SWEEP_BLOCK = 4
"""Consecutive sweeps a path's check takes at once, as the hull of their footprints, before
it looks at them one by one (:meth:`_Problem.first_blocked`): a free block clears them all.
(Footprints alone, as the cheap first pass checks them, are cheaper one by one.)"""
CLOSING_RADII = (1.0, 1.25, 1.5, 2.0, 3.0)
"""Closing arcs try these multiples of the car's minimum turning radius."""
COMMON_STYLES = ("forward", "reverse")
"""The ways of parking tried for a pose shared by a slot's lanes, in the order tried."""
EASE_RAMPS = (3.0, 2.2, 1.6, 1.1, 0.7, 0.4)
"""Lengths of path over which a maneuver's curvature jumps are smoothed, longest first [m]:
a longer ramp is driven faster (the steering rate caps ``v`` at ``φ̇ / (σ b)``) but moves
the path further from the planned one."""
CREEP = 0.1
"""Shortest straight a closing move may begin with [m] (none at all is fine)."""
EASE_DRIFT = 0.03
"""Farthest an eased maneuver may end from the planned parked pose [m] (the clothoid
ramps that let the car steer as it rolls shift the path by a few millimetres each)."""


@dataclass(frozen=True, slots=True)
class ManeuverSettings:
    """The maneuver planner's tuning, checked on construction.

    Attributes
    ----------
    margin : float
        Clearance kept to parked cars, walls, obstacles and the edges of the
        drivable area [m], 0 to 1.
    max_changes : int
        Most direction changes a maneuver may have, 0 to 50.
    probe : float
        Spacing of the places along every stroke (and of the straight exits from a
        perpendicular or angled slot) where a closing move onto the lane is tried [m].
    first_turn : float
        The first full-lock stroke out of a slot turns at most the slot's angle to the
        lane plus this [rad] (20°).
    candidates : int
        Closing moves checked for collisions per number of direction changes, cheapest
        first.
    closing_radii : tuple of float
        Multiples of the minimum turning radius the closing arc tries.
    sweep : float
        Spacing of the footprints whose hulls cover a path when checking it [m].
    min_stroke : float
        Shorter strokes of the perpendicular search are not worth a stop [m].
    parallel_extra : float
        Parallel slots: the minimum-slot strokes run to contact, so they are kept
        this far inside the margin [m].
    parallel_heading_step : float
        Parallel slots: spacing of the start headings tried [°].
    ease_ramps : tuple of float
        :data:`EASE_RAMPS`.
    ease_drift : float
        :data:`EASE_DRIFT` [m].
    start_grid : float
        Maneuvers start (and leaving ends) on lane stations that are multiples of this
        [m]: every vehicle type's maneuvers into nearby slots share lane nodes, and no car
        creeps a few millimetres from one node to the next (0: anywhere).
    approach : float
        ... at least this far along the lane from where the closing arc meets it [m]: a
        straight on which the car turns its wheels as it rolls into the arc.

    Examples
    --------
    >>> ManeuverSettings(margin=0.2).margin
    0.2
    >>> ManeuverSettings(probe=0.0)
    Traceback (most recent call last):
      ...
    ValueError: probe must be positive, got 0.0
    """

    margin: float = MARGIN
    max_changes: int = 8
    probe: float = 0.5
    first_turn: float = math.radians(20)
    candidates: int = 400
    closing_radii: tuple[float, ...] = CLOSING_RADII
    sweep: float = SWEEP
    min_stroke: float = 0.3
    parallel_extra: float = 0.02
    parallel_heading_step: float = 0.5
    ease_ramps: tuple[float, ...] = EASE_RAMPS
    ease_drift: float = EASE_DRIFT
    start_grid: float = 0.5
    approach: float = 0.5

    def __post_init__(self) -> None:
        if not 0.0 <= self.margin <= 1.0:
            raise ValueError(f"margin must be 0 to 1 m, got {self.margin!r}")
        if not 0 <= self.max_changes <= 50:
            raise ValueError(f"max_changes must be 0 to 50, got {self.max_changes!r}")
        for key in ("probe", "sweep", "parallel_heading_step", "candidates"):
            if not getattr(self, key) > 0:
                raise ValueError(f"{key} must be positive, got {getattr(self, key)!r}")
        for key in ("first_turn", "min_stroke", "parallel_extra", "ease_drift", "start_grid",
                    "approach"):
            if not getattr(self, key) >= 0:
                raise ValueError(f"{key} must be zero or more, got {getattr(self, key)!r}")
        if not self.closing_radii or min(self.closing_radii) < 1.0:
            raise ValueError("closing_radii must be multiples of at least 1")
        if any(r <= 0 for r in self.ease_ramps):
            raise ValueError("ease_ramps must be positive")


class ManeuverStatus(Enum):
    """How a maneuver search ended."""

    FOUND = "found"
    INFEASIBLE = "infeasible"


@dataclass(frozen=True)
class ManeuverResult:
    """A search's answer: ``maneuver`` when ``status`` is FOUND, else why not (``reason``)."""

    status: ManeuverStatus
    maneuver: Maneuver | None = None
    reason: str = ""

    @property
    def ok(self) -> bool:
        return self.status is ManeuverStatus.FOUND


@dataclass(frozen=True)
class Maneuver:
    """A path from a lane pose into a slot (or, reversed, out of it).

    Attributes
    ----------
    segments : tuple of Segment
        In driving order; consecutive pieces meet exactly.
    vehicle : str
        Name of the vehicle type it was planned for.
    slot : str
    lane : str
        The lane it starts on (parking) or ends on (leaving).
    station : float
        Station on ``lane`` where it starts or ends [m].
    leaving : bool
        False for the way in, True for the way out.
    """

    segments: tuple[Segment, ...]
    vehicle: str
    slot: str
    lane: str
    station: float
    leaving: bool = False

    @property
    def start(self) -> Pose:
        return self.segments[0].start

    @property
    def end(self) -> Pose:
        return self.segments[-1].end

    @property
    def length(self) -> float:
        """Path length [m]."""
        return float(sum(s.length for s in self.segments))

    @property
    def gears(self) -> tuple[int, ...]:
        return tuple(s.gear for s in self.segments)

    @property
    def changes(self) -> int:
        """Direction changes (cusps) within the maneuver."""
        g = self.gears
        return sum(1 for a, b in zip(g[:-1], g[1:], strict=True) if a != b)

    @property
    def cusps(self) -> tuple[Pose, ...]:
        """Poses where the car stops and changes direction."""
        return tuple(a.end for a, b in zip(self.segments[:-1], self.segments[1:], strict=True)
                     if a.gear != b.gear)

    def strokes(self) -> list[tuple[int, float]]:
        """Maximal runs of one gear as ``(gear, length)``: the car stops between them."""
        out: list[tuple[int, float]] = []
        for s in self.segments:
            if out and out[-1][0] == s.gear:
                out[-1] = (s.gear, out[-1][1] + s.length)
            else:
                out.append((s.gear, s.length))
        return out

    def sample(self, step: float = 0.05) -> tuple[FloatArray, np.ndarray]:
        """Poses (N, 3) at most ``step`` apart along the path, and the gear of each (N,).

        Cusps appear once, with the gear of the stroke they end.
        """
        parts, gears = [], []
        for k, seg in enumerate(self.segments):
            p = seg.sample(step)
            if k:
                p = p[1:]
            parts.append(p)
            gears.append(np.full(len(p), seg.gear))
        return np.concatenate(parts), np.concatenate(gears)

    def reversed(self) -> Maneuver:
        """The same path driven backwards in time: each piece with the other gear."""
        segs = tuple(s.backwards() for s in reversed(self.segments))
        return Maneuver(segs, self.vehicle, self.slot, self.lane, self.station, not self.leaving)

    def motion(self, vehicle: VehicleType, speed_limit: float = math.inf) -> Motion:
        """The maneuver timed from rest, wheels straight, to rest, wheels straight
        (:func:`~lotsim.vehicles.motion.timed_path`): the car stops at every cusp and wherever
        the curvature changes, and turns its wheels there standing."""
        return timed_path([Piece(s, speed_limit) for s in self.segments], vehicle)

    def duration(self, vehicle: VehicleType, speed_limit: float = math.inf) -> float:
        """Time to drive it (:meth:`motion`) [s]: jerk-limited rest-to-rest runs within the
        vehicle's limits and ``speed_limit`` [m/s], and the steering between them."""
        return self.motion(vehicle, speed_limit).duration


# -- frames ------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class _Frame:
    """A rigid (possibly mirrored) frame: local ``(x, y)`` ↦ origin + R(heading)·(x, ±y)."""

    x: float
    y: float
    heading: float
    mirror: bool

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

    def points_to_local(self, pts: FloatArray) -> FloatArray:
        pts = np.asarray(pts, dtype=float)
        flat = np.column_stack([pts.reshape(-1, 2), np.zeros(pts.size // 2)])
        return self.poses_to_local(flat)[:, :2].reshape(pts.shape)

    def segments_to_world(self, segs: Sequence[Segment]) -> tuple[Segment, ...]:
        """Each of ``segs`` in world coordinates (their starts moved in one batch)."""
        starts = self.poses_to_world(np.array([seg.start for seg in segs])).tolist()
        sign = -1.0 if self.mirror else 1.0
        return tuple(Segment(tuple(p), seg.distance, sign * seg.curvature, sign * seg.sharpness)
                     for p, seg in zip(starts, segs, strict=True))


# -- the planner -------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class _Problem:
    """One slot seen from one lane, in the slot's local frame (slot at y < 0, lane heading
    +x): frozen, with what a state or a motion may not touch (its validity checks)."""

    vehicle: VehicleType
    slot: Slot
    lane: Lane
    frame: _Frame
    lane_y: float  # the lane's straight near the slot is the line y = lane_y
    lane_x: tuple[float, float]  # ... between these x [m]
    lane_s0: float  # lane station at local x = 0
    half: float  # window half-size [m]
    index: int  # the slot's index in the lot
    allowed: BaseGeometry  # prepared world region the car must stay in
    obstacles: np.ndarray  # world obstacles near the slot
    tree: shapely.STRtree  # of ``obstacles``
    sweep: float  # footprint spacing when checking a motion [m]
    window: Polygon  # the square the search may use (:meth:`ManeuverPlanner._window`)
    # (segment, step) → whether a footprint along it is blocked (:meth:`footprints_blocked`)
    seen: dict = dataclasses.field(default_factory=dict, repr=False)

    # -- validity: OMPL's state validity checker and motion validator ---------------------
    def bodies_blocked(self, bodies: FloatArray) -> np.ndarray:
        """(N,) whether each body (N, K, 2 points, taken as their hull) is not free."""
        return hulls_blocked(hulls(bodies), self.allowed, self.tree)

    def first_blocked(self, prints: FloatArray, run: np.ndarray, span: int = 2
                      ) -> np.ndarray:
        """:func:`~lotsim.lot.clearance.first_blocked` of this problem's bodies, coarse to
        fine in blocks of :data:`SWEEP_BLOCK`."""
        return first_blocked(self.bodies_blocked, prints, run, span, SWEEP_BLOCK)

    def poses_blocked(self, local_poses: FloatArray) -> np.ndarray:
        """(N-1,) whether each sweep between consecutive local poses (N, 3) is not free
        ((1,) for a single pose)."""
        bodies = self.vehicle.footprints(self.frame.poses_to_world(local_poses))
        if len(bodies) > 1:
            bodies = np.concatenate([bodies[:-1], bodies[1:]], axis=1)
        return self.bodies_blocked(bodies)

    def pieces_blocked(self, starts: FloatArray, distance: FloatArray, curvature: FloatArray,
                       step: float, sharpness: FloatArray | float = 0.0) -> np.ndarray:
        """(N,) whether a footprint ``step`` apart along each segment, given as arrays
        (:func:`~lotsim.core.geometry.sample_pieces`, local frame), touches anything."""
        poses, of = sample_pieces(starts, distance, curvature, step, sharpness)
        bodies = self.vehicle.footprints(self.frame.poses_to_world(poses))
        return np.bincount(of[self.bodies_blocked(bodies)], minlength=len(starts)) > 0

    def footprints_blocked(self, paths: Sequence[Sequence[Segment]], step: float
                           ) -> np.ndarray:
        """(P,) whether a footprint ``step`` apart along each path touches anything
        (:meth:`paths_blocked` without ``sweep``), each segment checked once in this problem
        (a search's paths share their first strokes): a footprint lies on one segment, so
        a path is blocked when one of its segments is."""
        seen = self.seen
        new = list({seg: None for path in paths for seg in path if (seg, step) not in seen})
        if new:
            bad = self.pieces_blocked(np.array([seg.start for seg in new], dtype=float),
                                      np.array([seg.distance for seg in new], dtype=float),
                                      np.array([seg.curvature for seg in new], dtype=float),
                                      step, np.array([seg.sharpness for seg in new]))
            seen.update(zip(((seg, step) for seg in new), bad.tolist(), strict=True))
        return np.array([any(seen[seg, step] for seg in path) for path in paths], dtype=bool)

    def paths_blocked(self, paths: Sequence[Sequence[Segment]], *, step: float | None = None,
                      sweep: bool = True) -> np.ndarray:
        """(P,) whether each path (pieces in order, local frame) touches anything.

        With ``sweep``, the hulls of consecutive footprints ``step`` apart (default
        the problem's sweep step) are checked (the whole swept area); without, only
        the footprints.
        """
        flat = [seg for path in paths for seg in path]
        if not flat:
            return np.zeros(len(paths), dtype=bool)
        path_of = np.repeat(np.arange(len(paths)), [len(path) for path in paths])
        poses, seg_of = sample_segments(flat, step or self.sweep)
        own = path_of[seg_of]
        bodies = self.vehicle.footprints(self.frame.poses_to_world(poses))
        if sweep:
            own = own[:-1]
            bad = self.first_blocked(bodies, np.where(own == path_of[seg_of][1:], own, -1))
        else:
            bad = self.bodies_blocked(bodies)  # one by one: cheaper than in blocks
        return np.bincount(own[bad], minlength=len(paths)) > 0


class ManeuverPlanner:
    """Plans and caches parking maneuvers for one lot.

    Parameters
    ----------
    lot : Lot
    settings : ManeuverSettings, keyword-only
        The tuning; ``margin`` and ``max_changes``, when given, replace its own.
    margin : float, keyword-only
        Clearance kept to parked cars, walls, obstacles and the edges of the
        drivable area [m] (:attr:`ManeuverSettings.margin`).
    parked_width : float, keyword-only
        Width of the widest car that may stand in a perpendicular or angled
        slot [m]; default the lot's design width.
    max_changes : int, keyword-only
        Most direction changes a maneuver may have (:attr:`ManeuverSettings.max_changes`).
    lane_ranges : dict, keyword-only
        Lane id → (first, last) station [m] where a maneuver may start, or several such
        ranges (a slot's maneuver is planned in the one nearest it); a lane not listed gets
        none. Default (None): every lane, whole.
        :func:`~lotsim.roadmap.reach.maneuver_ranges` gives the parts a car can reach or
        leave by.

    Notes
    -----
    The shape is OMPL's: a frozen problem per slot and lane (its cache key derived
    from it without side effects), a state validity checker and a motion validator
    on the problem, and :meth:`solve`, which returns a :class:`ManeuverResult` with a
    status and a reason instead of raising.
    """

    def __init__(self, lot: Lot, *, settings: ManeuverSettings | None = None,
                 margin: float | None = None, parked_width: float | None = None,
                 max_changes: int | None = None,
                 lane_ranges: dict[str, tuple] | None = None):
        settings = settings or ManeuverSettings()
        changes = {k: v for k, v in (("margin", margin), ("max_changes", max_changes))
                   if v is not None}
        if changes:
            settings = dataclasses.replace(settings, **changes)
        self.settings = settings
        margin = settings.margin
        self.lot = lot
        self.lane_ranges = lane_ranges
        width = max(parked_width or 0.0, lot.design.width)
        polys = [_taken_zone(s, width, margin) for s in lot.slots]
        polys += [a.polygon.buffer(margin, join_style="mitre") if margin else a.polygon
                  for a in lot.areas]
        self._polys = np.array(polys, dtype=object)
        self._tree = shapely.STRtree(self._polys)
        self._region = lot.boundary.buffer(-margin, join_style="mitre") if margin \
            else lot.boundary
        self._index = {s.id: k for k, s in enumerate(lot.slots)}
        self._cache: dict[bytes, tuple[tuple[Segment, ...], float] | str] = {}
        self._raw: dict[bytes, tuple[tuple[Segment, ...], float] | str] = {}  # not eased
        self.stats = {"planned": 0, "reused": 0, "remembered": 0}
        self._posed: dict[tuple[str, str, str, str], tuple[bytes, _Frame, float]] = {}
        self._fresh: set[bytes] = set()  # searched by prefetch, not yet asked for
        self._known: dict[bytes, tuple] | None = None  # prefetch's ``known``, while it runs

    @property
    def margin(self) -> float:
        """Clearance kept [m] (:attr:`ManeuverSettings.margin`)."""
        return self.settings.margin

    @property
    def max_changes(self) -> int:
        return self.settings.max_changes

    # -- public API ---------------------------------------------------------------------------
    def lanes_for(self, slot: Slot) -> list[Lane]:
        """The lanes a car can park into ``slot`` from: by kind and direction of travel."""
        mid = slot.entry.mean(axis=0)
        return [lane for lane in self.lot.aisles[slot.aisle].lanes
                if lane_serves(lane, lane.project((float(mid[0]), float(mid[1])))[0], slot)]

    def solve(self, vehicle: VehicleType, slot: Slot, lane: Lane, *,
              style: str = "any", eased: bool = True) -> ManeuverResult:
        """Search for the parking maneuver into ``slot`` starting on ``lane``.

        With ``eased`` (the default) its curvature jumps inside strokes are smoothed where
        that stays clear (the car steers as it rolls; the parked pose moves by at most
        :attr:`ManeuverSettings.ease_drift`); without, the car stops to steer at every jump
        and parks exactly centred.

        Returns
        -------
        ManeuverResult
            FOUND with the maneuver, or INFEASIBLE with the reason.

        Examples
        --------
        >>> from lotsim.io.scenario_yaml import parse_scenario
        >>> from lotsim.io.yamlnodes import parse_text
        >>> from lotsim.lot.build import build_lot
        >>> from lotsim.lot.model import DesignVehicle
        >>> from lotsim.vehicles import CATALOGUE
        >>> sc = parse_scenario(parse_text('''
        ... lot:
        ...   boundary: [[0, 0], [40, 0], [40, 20], [0, 20]]
        ...   aisles: [{id: a, centerline: [[0, 10], [40, 10]], width: 7.0}]
        ...   rows: [{aisle: a, side: left, kind: perpendicular, count: 4, slot_width: 2.5,
        ...           slot_length: 5.0, start: 10}]
        ...   entrances: [{id: in, x: 2, y: 8.25, heading_deg: 0}]
        ... traffic: {vehicles: [{id: x, arrival: 0}]}
        ... ''', "doc.yaml"))
        >>> lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
        >>> planner = ManeuverPlanner(lot)
        >>> slot = lot.slot_by_id["a-left-2"]
        >>> result = planner.solve(CATALOGUE["valet"], slot, planner.lanes_for(slot)[0])
        >>> result.status.value, result.maneuver.slot
        ('found', 'a-left-2')
        >>> planner.solve(CATALOGUE["vclass"], slot, planner.lanes_for(slot)[0]).reason
        'the car is 5.37 m long, the slot 5.00 m'
        """
        if style not in STYLES:
            raise ValueError(f"style must be one of {', '.join(STYLES)}")
        problem = None
        posed = self._posed.get((vehicle.name, slot.id, lane.id, style))
        if posed is None:
            problem = self._problem(vehicle, slot, lane)
            posed = self._key(problem, style), problem.frame, problem.lane_s0
        key, frame, s0 = posed
        hit = self._cache.get(key)
        if hit is None:
            problem = problem or self._problem(vehicle, slot, lane)
            hit, self._raw[key] = self._search(problem, style)
            self._cache[key] = hit
            self.stats["planned"] += 1
        elif key in self._fresh:  # searched ahead of time (:meth:`prefetch`): first use
            self._fresh.discard(key)
            self.stats["planned"] += 1
        else:
            self.stats["reused"] += 1
        if not eased:
            hit = self._raw[key]
        if isinstance(hit, str):
            return ManeuverResult(ManeuverStatus.INFEASIBLE, reason=hit)
        local, x0 = hit
        segs = frame.segments_to_world(local)
        return ManeuverResult(ManeuverStatus.FOUND,
                              Maneuver(segs, vehicle.name, slot.id, lane.id, s0 + x0))

    def _search(self, problem: _Problem, style: str) -> tuple[object, object]:
        """(eased, as planned) local answer to ``problem``: segments and start x, or why not."""
        raw = self._solve(problem, style)
        return (raw if isinstance(raw, str) else (self._eased(problem, raw[0]), raw[1])), raw

    def prefetch(self, vehicles: Iterable[VehicleType], *, style: str = "any",
                 shared: bool = True, workers: int | None = None,
                 progress: Callable[[int, int], None] | None = None,
                 known: dict[bytes, tuple] | None = None) -> None:
        """Search every distinct problem :meth:`solve_lanes` will meet for ``vehicles`` in
        every slot, on ``workers`` processes (default: as many as the machine has), so that
        it then only looks them up.

        The answers are exactly those of searching them one after another: each distinct
        problem (by its rounded local geometry, as the cache keys it) is searched as posed
        the first time :meth:`solve_lanes` meets it in slot order, as it would be without
        this. Problems are posed (and keyed) on the workers too. Needs the ``fork`` start
        method (Linux); elsewhere, or for a few problems, it works in this process.
        ``progress(done, total)`` is called as the distinct problems are searched.

        ``known`` (exact problem key → answer, :func:`_exact_key`) holds answers found
        before, for this planner's settings and this lotsim, in any lot (the on-disk cache
        keeps one per lot name: :func:`lotsim.sim.preparation.prepare`): a problem it holds is not
        searched again, and those searched now are added to it, most recently used last, at
        most :data:`KNOWN_MOST`. A search reads nothing but its problem (to the last bit of
        every float) and the settings, so the answers are the same with it as without.
        """
        self._known = known
        try:
            self._prefetch(vehicles, style, shared, workers, progress)
        finally:
            self._known = None

    def _prefetch(self, vehicles, style, shared, workers, progress) -> None:
        known = self._known
        calls = [(v, slot, lane, st) for v in vehicles for slot in self.lot.slots
                 for st, lane in self._searches(slot, style, shared)]  # solve_lanes' order
        where = {(v.name, slot.id, lane.id): (v, slot, lane) for v, slot, lane, _ in calls}
        triples = list(where.values())  # each problem posed once: the styles share it
        at = {name: k for k, name in enumerate(where)}
        todo: dict[bytes, tuple[int, str]] = {}  # key → (triple, style), first met first
        with _Workers(self, triples, workers) as pool:
            # keyed in batches, a few per worker (each batch one shapely call a step)
            size = max(16, -(-len(triples) // (4 * pool.count)))
            parts = [(k, min(k + size, len(triples))) for k in range(0, len(triples), size)]
            posed = [x for part in pool.map(_digest_job, parts, chunk=1) for x in part]
            for v, slot, lane, st in calls:
                k = at[v.name, slot.id, lane.id]
                digest, frame, s0 = posed[k]
                key = self._key(None, st, digest)
                self._posed[(v.name, slot.id, lane.id, st)] = (key, frame, s0)
                if key not in self._cache and key not in todo:
                    todo[key] = (k, st)
            answers = pool.map(_search_job, list(todo.values()), chunk=8, progress=progress)
        for key, (hit, raw, exact, remembered) in zip(todo, answers, strict=True):
            self._cache[key], self._raw[key] = hit, raw
            self._fresh.add(key)
            if known is not None:
                known.pop(exact, None)
                known[exact] = hit, raw  # most recently used last
                self.stats["remembered"] += remembered
        if known is not None:
            for old in list(itertools.islice(known, max(0, len(known) - KNOWN_MOST))):
                del known[old]

    def plan(self, vehicle: VehicleType, slot: Slot, lane: Lane, *,
             style: str = "any") -> Maneuver:
        """The parking maneuver into ``slot`` starting on ``lane`` (:meth:`solve`).

        Raises
        ------
        InfeasibleManeuver
            When no maneuver within the limits exists, with the reason.
        """
        result = self.solve(vehicle, slot, lane, style=style)
        if not result.ok:
            raise InfeasibleManeuver(f"{vehicle.name} cannot park in slot {slot.id!r} from lane "
                                     f"{lane.id!r}: {result.reason}")
        return result.maneuver

    def best(self, vehicle: VehicleType, slot: Slot, *, style: str = "any") -> Maneuver:
        """The best maneuver into ``slot`` over its lanes: fewest changes, then shortest."""
        return min(self.plan_all(vehicle, slot, style=style, shared=False).values(),
                   key=lambda m: (m.changes, m.length))

    def plan_all(self, vehicle: VehicleType, slot: Slot, *, style: str = "any",
                 shared: bool = True) -> dict[str, Maneuver]:
        """Maneuvers into ``slot`` from every lane that has one (lane id → Maneuver)
        (:meth:`solve_all`).

        Raises
        ------
        InfeasibleManeuver
            When no lane has one; the message gives each lane's reason.
        """
        out, why = self.solve_all(vehicle, slot, style=style, shared=shared)
        if not out:
            raise InfeasibleManeuver(f"{vehicle.name} cannot park in slot {slot.id!r}: {why}")
        return out

    def solve_all(self, vehicle: VehicleType, slot: Slot, *, style: str = "any",
                  shared: bool = True) -> tuple[dict[str, Maneuver], str]:
        """Maneuvers into ``slot`` from every lane that has one, and, when none has, why
        (each lane's reason, once; empty when some lane has one).

        With ``shared`` (and ``style`` "any"), a perpendicular or angled slot served by
        several lanes is parked on one pose from all of them where it can be, so that the
        car may leave towards any (:meth:`_solve_common`); without, each lane's best.
        """
        out, _, why = self.solve_lanes(vehicle, slot, style=style, shared=shared)
        return out, why

    def solve_lanes(self, vehicle: VehicleType, slot: Slot, *, style: str = "any",
                    shared: bool = True) -> tuple[dict[str, Maneuver], dict[str, Maneuver], str]:
        """:meth:`solve_all`, and each lane's own best maneuver where it parks the other way
        round (nose-in or backed in) than the shared pose: a car that will not leave again
        need not park so that it could leave towards every lane (lane id → Maneuver)."""
        lanes = self.lanes_for(slot)
        if self._shares(slot, lanes, style, shared):
            return self._solve_common(vehicle, slot, lanes)
        out, reasons = {}, []
        for lane in lanes:
            result = self.solve(vehicle, slot, lane, style=style)
            if result.ok:
                out[lane.id] = result.maneuver
            else:
                reasons.append(result.reason)
        if out:
            return out, {}, ""
        return out, {}, "; ".join(dict.fromkeys(reasons)) or "no lane of its aisle leads to it"

    @staticmethod
    def _shares(slot: Slot, lanes: list[Lane], style: str, shared: bool) -> bool:
        """Whether :meth:`solve_lanes` parks ``slot`` on one pose from all its ``lanes``."""
        return shared and style == "any" and len(lanes) > 1 and slot.kind != "parallel"

    def _searches(self, slot: Slot, style: str, shared: bool) -> list[tuple[str, Lane]]:
        """(style, lane) of every search :meth:`solve_lanes` makes for ``slot``, in order (the
        same whatever the answers)."""
        lanes = self.lanes_for(slot)
        styles = COMMON_STYLES if self._shares(slot, lanes, style, shared) else (style,)
        return [(st, lane) for st in styles for lane in lanes]

    def _solve_common(self, vehicle: VehicleType, slot: Slot, lanes: list[Lane]
                      ) -> tuple[dict[str, Maneuver], dict[str, Maneuver], str]:
        """:meth:`solve_lanes` for a slot served by several lanes: nose-in from every lane, or
        backed in from every lane — whichever costs fewer direction changes (then less path)
        on the worst lane and parks the car on the one pose from every lane — so the car
        can leave towards any of them; each lane's own best when no way of parking serves
        them all."""
        tried = {st: [self.solve(vehicle, slot, lane, style=st) for lane in lanes]
                 for st in COMMON_STYLES}

        def cost(results: list[ManeuverResult]) -> tuple[int, float]:
            ms = [r.maneuver for r in results]
            return max(m.changes for m in ms), sum(m.length for m in ms)

        plain = {st: [self.solve(vehicle, slot, lane, style=st, eased=False) for lane in lanes]
                 for st in tried}
        # each lane's best as planned (fewest changes, then shortest; nose-in on a tie)
        own = {}
        for k, lane in enumerate(lanes):
            ok = [st for st in tried if tried[st][k].ok]
            if ok:
                own[lane.id] = min(ok, key=lambda x, k=k: (plain[x][k].maneuver.changes,
                                                            plain[x][k].maneuver.length))
        common = [st for st, results in tried.items() if all(r.ok for r in results)]
        for st in sorted(common, key=lambda k: cost(tried[k])):
            # an eased path may park a few millimetres off the planned pose (when no two
            # straights could take the drift up): drive that lane's path as planned, stopping
            # to steer — and no path that has the car creep from stop to stop
            found = [r.maneuver if same_pose(r.maneuver.end, q.maneuver.end) else q.maneuver
                     for r, q in zip(tried[st], plain[st], strict=True)]
            if min(_shortest_run(m) for m in found) >= self.settings.min_stroke:
                stays = {lane.id: tried[own[lane.id]][k].maneuver
                         for k, lane in enumerate(lanes) if own[lane.id] != st}
                return {lane.id: m for lane, m in zip(lanes, found, strict=True)}, stays, ""
        # no one way of parking serves every lane: each lane's best, eased — left the way it
        # came in
        out = {lane.id: tried[own[lane.id]][k].maneuver
               for k, lane in enumerate(lanes) if lane.id in own}
        if out:
            return out, {}, ""
        reasons = [tried[st][k].reason for k in range(len(lanes)) for st in tried]
        return out, {}, "; ".join(dict.fromkeys(reasons))

    # -- problem set-up -----------------------------------------------------------------------
    def _problem(self, vehicle: VehicleType, slot: Slot, lane: Lane) -> _Problem:
        frame, lane_y, lane_x, s0, half = self._head(vehicle, slot, lane)
        index = self._index[slot.id]
        win = self._window(slot, frame, half)
        shapely.prepare(win)
        # the slot itself is the car's to fill: no margin to its own lines
        allowed = self._region.union(slot.shape).intersection(win)
        shapely.prepare(allowed)
        near = [int(k) for k in self._tree.query(win) if k != index]
        # the margin around neighbours stops at this slot's lines: the car may fill its slot.
        # Inside the window, those clear of the slot are kept as they are (the same shapes as
        # their difference, in another vertex order); those across its edge are made as
        # before, as :meth:`_digest` cuts them at the edge (a cut's rounded corners follow
        # the order of the vertices cut).
        obstacles = self._polys[near]
        cut = ~shapely.contains_properly(win, obstacles) | shapely.intersects(obstacles,
                                                                              slot.shape)
        obstacles[cut] = shapely.difference(obstacles[cut], slot.shape)
        return _Problem(vehicle, slot, lane, frame, lane_y, lane_x, s0, half, index, allowed,
                        obstacles, shapely.STRtree(obstacles), self.settings.sweep, win)

    def _head(self, vehicle: VehicleType, slot: Slot, lane: Lane
              ) -> tuple[_Frame, float, tuple[float, float], float, float]:
        """A problem's frame, lane line (``lane_y``, NaN on a bend), the stretch of it a
        maneuver may begin on (``lane_x``), the lane station at x = 0 and the window's
        half size."""
        mid = slot.entry.mean(axis=0)
        s_mid, _ = lane.project((float(mid[0]), float(mid[1])))
        i, _ = lane.locate(s_mid)
        seg = lane.segments[i]
        heading = lane.pose_at(s_mid)[2]
        d = np.asarray(slot.center) - mid
        left = math.cos(heading) * d[1] - math.sin(heading) * d[0] > 0
        frame = _Frame(float(mid[0]), float(mid[1]), heading, left)
        if seg.curvature != 0.0 or seg.sharpness != 0.0:
            lane_y, lane_x, s0 = math.nan, (0.0, 0.0), 0.0
        else:
            a = frame.poses_to_local(np.array(seg.start))[0]
            lane_y = float(a[1])
            lo = float(a[0])
            s0 = float(lane.starts[i]) - lo
        half = 2 * vehicle.min_turning_radius + vehicle.length + 1.0
        if slot.kind == "parallel" and math.isfinite(lane_y):
            # a parallel slot is left at a shallow heading (about 25°), so the closing
            # straight onto a lane lane_y away reaches some 2 lane_y along it: the window
            # must hold the car at its end (a fixed window refused roomy aisles)
            half += 2.0 * abs(lane_y)
        if math.isfinite(lane_y):
            whole = (0.0, lane.length)
            spans = ((whole,) if self.lane_ranges is None
                     else self.lane_ranges.get(lane.id, ((math.inf, -math.inf),)))
            if spans and not isinstance(spans[0], tuple):
                spans = (spans,)  # one (first, last)
            # the range nearest the slot (the first of those it lies in)
            first, last = min(spans, key=lambda r: max(r[0] - s_mid, s_mid - r[1], 0.0))
            lane_x = (max(lo, -half, first - s0), min(lo + seg.length, half, last - s0))
        return frame, lane_y, lane_x, s0, half

    def _window(self, slot: Slot, frame: _Frame, half: float) -> Polygon:
        """The square the search may use, cut at the far side of the aisle less the margin."""
        h = half
        aisle = self.lot.aisles[slot.aisle]
        mid = shapely.Point(slot.entry.mean(axis=0))
        on_line = aisle.line.interpolate(aisle.line.project(mid))
        centre_y = float(frame.points_to_local(np.array([on_line.x, on_line.y]))[1])
        top = min(h, centre_y + aisle.width / 2 - self.margin)
        corners = np.array([[-h, -h, 0], [h, -h, 0], [h, top, 0], [-h, top, 0]], dtype=float)
        return Polygon(frame.poses_to_world(corners)[:, :2])

    def _key(self, p: _Problem, style: str, digest: bytes | None = None) -> bytes:
        """The problem and the style: equal keys plan equal maneuvers. ``digest`` is
        :meth:`_digest` of ``p`` when the caller has it."""
        h = hashlib.blake2b(digest if digest is not None else self._digest(p), digest_size=20)
        h.update(style.encode())
        return h.digest()

    def _digest(self, p: _Problem) -> bytes:
        """The car, the slot, the rounded local geometry within the window and where the
        lane's start grid falls."""
        # only what reaches the window's edge is cut (the rest would come out as the same
        # shape, and the key is of normalised shapes)
        clipped = p.obstacles.copy()
        cross = ~shapely.contains_properly(p.window, clipped)
        clipped[cross] = shapely.intersection(clipped[cross], p.window)
        clipped = np.concatenate([[p.allowed], clipped])
        local = _local_geometry(clipped, [p.frame], np.zeros(len(clipped), dtype=np.int64))
        return self._hashed(p.vehicle, p.slot, p.frame, p.lane_y, p.lane_x, p.lane_s0,
                            p.half, local)

    def _digests(self, triples: Sequence[tuple[VehicleType, Slot, Lane]]
                 ) -> list[tuple[bytes, _Frame, float]]:
        """:meth:`_digest` of each triple's problem, with its frame and lane station at
        x = 0: posed and keyed together, each step one shapely or numpy call over all of
        them (the same operations on the same shapes as :meth:`_problem` and
        :meth:`_digest` make one problem at a time, so the same digests), without the
        rest of a problem (its obstacle tree), which only a search needs."""
        heads = [self._head(*t) for t in triples]
        n = len(triples)
        wins = np.array([self._window(slot, h[0], h[4]) for (_, slot, _), h
                         in zip(triples, heads, strict=True)], dtype=object)
        shapely.prepare(wins)
        shapes = np.array([slot.shape for _, slot, _ in triples], dtype=object)
        allowed = shapely.intersection(shapely.union(self._region, shapes), wins)
        # each problem's neighbours (all but its own slot) as (problem, polygon) pairs
        k, j = self._tree.query(wins)
        mine = np.array([self._index[slot.id] for _, slot, _ in triples], dtype=np.int64)
        k, j = k[j != mine[k]], j[j != mine[k]]
        obstacles = self._polys[j]
        cut = ~shapely.contains_properly(wins[k], obstacles) | shapely.intersects(obstacles,
                                                                                  shapes[k])
        obstacles[cut] = shapely.difference(obstacles[cut], shapes[k[cut]])
        cross = ~shapely.contains_properly(wins[k], obstacles)
        obstacles[cross] = shapely.intersection(obstacles[cross], wins[k[cross]])
        owner = np.concatenate([np.arange(n), k])
        local = _local_geometry(np.concatenate([allowed, obstacles]), [h[0] for h in heads],
                                owner)
        per: list[list[bytes]] = [[] for _ in range(n)]
        for g, o in zip(local, owner.tolist(), strict=True):
            per[o].append(g)
        return [(self._hashed(v, slot, *h, mine_local), h[0], h[3])
                for (v, slot, _), h, mine_local in zip(triples, heads, per, strict=True)]

    def _hashed(self, v: VehicleType, slot: Slot, frame: _Frame, lane_y: float,
                lane_x: tuple[float, float], s0: float, half: float, local: list[bytes]
                ) -> bytes:
        """The digest of a problem from its head and its local geometry (:func:`_local_geometry`,
        in any order)."""
        slot_local = np.round(frame.points_to_local(slot.polygon), 2)
        # where the lane's start grid falls: a closing move runs on along the lane to a
        # grid station, so slots alike but for it do not start on the same offsets
        grid = self.settings.start_grid
        phase = round(s0 % grid, 6) % grid if grid > 0 else 0.0
        head = (v.name, v.width, v.front, v.rear, v.wheelbase, v.max_steer, slot.kind,
                round(lane_y, 3) if math.isfinite(lane_y) else None,
                tuple(np.round(lane_x, 2)), round(half, 3), phase)
        h = hashlib.blake2b(repr(head).encode(), digest_size=20)
        h.update(np.sort(slot_local.reshape(-1, 2), axis=0).tobytes())
        for g in sorted(local):
            h.update(g)
        return h.digest()

    # -- solving ------------------------------------------------------------------------------
    def _eased(self, p: _Problem, local: tuple[Segment, ...]) -> tuple[Segment, ...]:
        """``local`` with its curvature jumps inside strokes eased by clothoids
        (:func:`~lotsim.core.geometry.ease_joints`: the car steers as it rolls instead of
        stopping to steer), with the longest ramp of ``settings.ease_ramps`` whose path is as
        clear as the original, ends inside the slot and within ``settings.ease_drift`` of the
        original end; else ``local``."""
        was = np.array(local[-1].end)
        for ramp in self.settings.ease_ramps:
            eased = tuple(ease_joints(local, ramp))
            if len(eased) == len(local):
                return local  # nothing to ease
            end = np.array(eased[-1].end)
            if (math.dist(end[:2], was[:2]) > self.settings.ease_drift
                    or abs(wrap_angle(end[2] - was[2])) > 1e-9):
                continue
            # two straights at right angles take up the drift, so the car parks exactly
            # where planned, whichever lane it came by
            anchored = _anchored(eased, was) if p.slot.kind != "parallel" else None
            for path in (anchored, eased):
                if path is None or p.paths_blocked([path])[0]:
                    continue
                body = Polygon(p.vehicle.footprints(p.frame.poses_to_world(
                    np.array(path[-1].end)))[0])
                if p.slot.shape.buffer(1e-9).covers(body):
                    return path
        return local

    # -- solving ------------------------------------------------------------------------------
    def _solve(self, p: _Problem, style: str) -> tuple[tuple[Segment, ...], float] | str:
        v, s = p.vehicle, p.slot
        if not math.isfinite(p.lane_y):
            return "the lane bends beside the slot"
        if v.width > s.width:
            return f"the car is {v.width:.2f} m wide, the slot {s.width:.2f} m"
        if v.length > s.length:
            return f"the car is {v.length:.2f} m long, the slot {s.length:.2f} m"
        if p.lane_x[0] > p.lane_x[1]:
            return ("no car can reach the lanes beside it (no way along them from an entrance "
                    "or to an exit)")
        if s.kind == "parallel":
            return self._solve_parallel(p)
        heading_in = float(p.frame.poses_to_local(np.array([0.0, 0.0, s.heading]))[0, 2])
        centre = p.frame.points_to_local(np.asarray(s.center))
        best = None
        for nose_in in (True, False):
            if style == ("reverse" if nose_in else "forward"):
                continue
            h = heading_in if nose_in else heading_in + math.pi
            axle = centre - unit(h) * (v.front - v.rear) / 2
            root = (float(axle[0]), float(axle[1]), float(wrap_angle(h)))
            if p.poses_blocked(np.array([root]))[0]:
                continue
            # leave-time: a nose-in car backs out, a nose-out car drives out
            found = self._shuffle(p, root, -1 if nose_in else 1, best[:2] if best else None)
            if found is not None and (best is None or found[:2] < best[:2]):
                best = found
        way_out = best[2] if best is not None else self._any_way_out(
            p, style, heading_in, axle_of=lambda h: centre - unit(h) * (v.front - v.rear) / 2)
        if way_out is None:
            return (f"no way out with up to {self.max_changes} direction changes "
                    f"keeping {self.margin:g} m from the neighbours and the aisle's far side")
        return _park_path(way_out)

    def _any_way_out(self, p: _Problem, style: str, heading_in: float, axle_of
                     ) -> list[Segment] | None:
        """The way out of a perpendicular or angled slot when the full-lock shuffle finds
        none (a corner bay against a closed end, where the strokes must not all be at full
        lock): a multi-point search over arcs and straights in either gear
        (:func:`~lotsim.roadmap.multipoint.plan_onto`) from the parked pose, nose-in or
        nose-out as ``style`` allows, onto the lane within its reachable stretch, inside the
        same window and clear of the same obstacles; in leave-time, local frame."""
        roots = []
        for nose_in in (True, False):
            if style == ("reverse" if nose_in else "forward"):
                continue
            h = heading_in if nose_in else heading_in + math.pi
            axle = axle_of(h)
            root = (float(axle[0]), float(axle[1]), float(wrap_angle(h)))
            if not p.poses_blocked(np.array([root]))[0]:
                roots.append(root)
        if not roots:
            return None
        local = _LocalChecks(p)
        found = plan_onto(roots, (0.0, p.lane_y, 0.0), p.lane_x[0], p.lane_x[1], local, local,
                          p.vehicle.min_turning_radius, max_changes=self.max_changes,
                          budget=WAY_OUT_BUDGET)
        return None if found is None else list(found[1])

    def _shuffle(self, p: _Problem, root: Pose, gear0: int, bound: tuple[int, float] | None
                 ) -> tuple[int, float, list[Segment]] | None:
        """The way out of a perpendicular or angled slot, in leave-time.

        Drive out straight for ``d0`` (every 0.5 m up to the first contact),
        then shuffle: full lock turning toward the lane heading until contact,
        the other gear with the opposite lock (which keeps turning the same
        way), and so on. From every 0.5 m of every stroke try the closing move
        in either gear; the first level of direction changes with a clear
        closing gives the answer, the shortest at that level.
        """
        kmax = p.vehicle.max_curvature
        theta = float(wrap_angle(root[2]))
        rho = -1.0 if theta > 0 else 1.0  # turn toward heading 0 the short way
        e0 = float(self._extents(p, np.array([root]), gear0, 0.0)[0])
        heads = []
        probe = self.settings.probe
        for d0 in np.arange(0.0, e0 + 1e-9, probe):
            segs = [Segment(root, gear0 * float(d0), 0.0)] if d0 > 0 else []
            heads.append((segs, segs[-1].end if segs else root, float(d0)))
        registry: list[tuple] = []  # per level: (heads, stops, poses, head of each pose)
        reached: dict[tuple[int, int], bool] = {}  # (level, stop) → the way there blocked

        def build(row: FloatArray) -> tuple[int, float, list[Segment]]:
            level, m = int(row[2]), int(row[3])
            close = (int(row[4]), float(row[5]), float(row[6]), float(row[7]))
            return int(row[0]), float(row[1]), _way(registry, level, m) + _closing_segments(
                tuple(map(float, registry[level][2][m])), close)

        pending = np.zeros((0, 8))  # rows: changes, length, level, m, gear, straight, κ, extend
        for k in range(self.max_changes + 1):
            g = gear0 if k % 2 == 0 else -gear0
            kappa = rho * g * kmax
            turn_cap = abs(theta) + self.settings.first_turn if k == 0 else math.pi / 2
            extents = (self._extents(p, np.array([h[1] for h in heads]), g, kappa, turn_cap)
                       if heads else np.zeros(0))
            stops = [np.unique(np.concatenate([np.arange(0.0, e, probe), [e]]))
                     for e in extents]
            owner = np.repeat(np.arange(len(heads)), [len(st) for st in stops])
            flat = np.concatenate(stops) if stops else np.zeros(0)
            starts = np.array([h[1] for h in heads]).reshape(-1, 3)[owner]
            q = advance(starts, g * flat, kappa)
            base = np.array([h[2] for h in heads])[owner] + flat
            tab = self._closings(p, q, g, k, base)
            registry.append((heads, flat, q, owner, g, kappa))
            table = np.concatenate([pending, np.column_stack(
                [tab[:, :2], np.full(len(tab), k), tab[:, 2:]])])
            now = table[:, 0] == k
            if bound is not None:
                now &= (table[:, 0] < bound[0]) | ((table[:, 0] == bound[0])
                                                   & (table[:, 1] < bound[1]))
            level = table[now][np.argsort(table[now][:, 1], kind="stable")]
            pending = table[table[:, 0] > k]

            found = self._first_clear(p, level[:self.settings.candidates], build,
                                      lambda rows: self._rough(p, registry, rows, reached))
            if found is not None:
                return found
            if bound is not None and k >= bound[0]:
                return None
            heads = []
            for (segs, pose, length), e in zip(registry[-1][0], extents, strict=True):
                if e >= self.settings.min_stroke:
                    stroke = Segment(pose, g * float(e), kappa)
                    heads.append((segs + [stroke], stroke.end, length + float(e)))
            if not heads and not len(pending):
                return None
        return None

    def _first_clear(self, p: _Problem, rows: Sequence, build=None, rough=None,
                     chunk: int = 8):
        """The first clear path of ``rows`` (in order), made by ``build(row)`` as
        ``(changes, length, segments)`` (default: rows are already such triples).

        A cheap pass over footprints :data:`ROUGH` apart drops most blocked paths first:
        ``rough(rows)`` (a mask of the rows whose paths it finds blocked) when given,
        without making them. It looks at ``chunk`` rows first, then ``8 * chunk`` at a
        time: the first clear one is often among the first few (then the rest need not be
        made and checked), and when it is not, the larger batches cost less a row. The
        first clear row is the same whatever the batches.
        """
        build = build or (lambda r: r)
        i = 0
        while i < len(rows):
            size = chunk if i == 0 else 8 * chunk
            some = rows[i : i + size]
            i += size
            if rough is None:
                batch = [build(r) for r in some]
                bad = p.paths_blocked([c[2] for c in batch], step=ROUGH, sweep=False)
                batch = [c for c, b in zip(batch, bad, strict=True) if not b]
            else:
                batch = [build(r) for r, b in zip(some, rough(some), strict=True) if not b]
            for j in range(0, len(batch), chunk):
                part = batch[j : j + chunk]
                ok = np.flatnonzero(~p.paths_blocked([c[2] for c in part]))
                if ok.size:
                    return part[int(ok[0])]
        return None

    def _rough(self, p: _Problem, registry: list[tuple], rows: FloatArray,
               reached: dict[tuple[int, int], bool]) -> np.ndarray:
        """(R,) whether a footprint :data:`ROUGH` apart along the path of each of
        :meth:`_shuffle`'s ``rows`` touches anything — what
        ``p.paths_blocked(paths, step=ROUGH, sweep=False)`` finds of the paths its
        ``build`` makes, without making them. A footprint lies on one piece of a path, so
        a path is blocked when a piece is: the way to each stop (the strokes before it and
        the part of its own up to it) is checked once a search (``reached``: (level, stop)
        → blocked), and the closing moves from the stops, in one batch."""
        level, m = rows[:, 2].astype(int), rows[:, 3].astype(int)
        stops = list(zip(level.tolist(), m.tolist(), strict=True))
        new = [k for k in dict.fromkeys(stops) if k not in reached]
        if new:
            ways = [_way(registry, a, b) for a, b in new]
            reached.update(zip(new, p.footprints_blocked(ways, ROUGH).tolist(), strict=True))
        bad = np.array([reached[k] for k in stops], dtype=bool)
        # the closing moves (:func:`_closing_segments`, as arrays): a straight, an arc onto
        # the lane and a straight along it
        c = np.flatnonzero(rows[:, 6] != 0.0)
        if not c.size:
            return bad
        q = np.empty((len(c), 3))
        for a in np.unique(level[c]).tolist():
            at = level[c] == a
            q[at] = registry[a][2][m[c][at]]
        g, d, kappa, extend = rows[c, 4], rows[c, 5], rows[c, 6], rows[c, 7]
        straight = d > 1e-9
        mid = np.where(straight[:, None], advance(q, g * d, 0.0), q)
        arc = -np.asarray(wrap_angle(mid[:, 2])) / kappa
        end = advance(mid, arc, kappa)
        on = extend > 1e-9
        piece_of = np.concatenate([c[straight], c, c[on]])
        hit = p.pieces_blocked(
            np.concatenate([q[straight], mid, end[on]]),
            np.concatenate([(g * d)[straight], arc, (g * extend)[on]]),
            np.concatenate([np.zeros(int(straight.sum())), kappa, np.zeros(int(on.sum()))]),
            ROUGH)
        bad[piece_of[hit]] = True
        return bad

    def _solve_parallel(self, p: _Problem) -> tuple[tuple[Segment, ...], float] | str:
        v, s = p.vehicle, p.slot
        m = self.margin + self.settings.parallel_extra
        frame = SlotFrame(s.length - 2 * m, s.width - m)
        if frame.length <= v.length or frame.width < v.width:
            return (f"with {self.margin:g} m margins the slot leaves "
                    f"{frame.length:.2f} × {frame.width:.2f} m for a "
                    f"{v.length:.2f} × {v.width:.2f} m car")
        thetas = start_headings(self.settings.parallel_heading_step)
        changes, strokes = simulate(v, frame, thetas, max_changes=self.max_changes, record=True)
        ok = np.flatnonzero(changes >= 0)
        if not ok.size:
            return (f"the minimum-slot maneuver needs more than {self.max_changes} direction "
                    f"changes in a {s.length:.2f} m slot")
        shift = np.array([-s.length / 2 + m, -s.width + m])  # minslot frame → local frame
        ok = [k for k in ok if strokes[k]]
        inside = [[Segment((x.start[0] + shift[0], x.start[1] + shift[1], x.start[2]),
                           x.distance, x.curvature)
                   for x in strokes[k] + _straighten(v, frame, strokes[k])] for k in ok]
        starts = np.array([segs[0].start for segs in inside]).reshape(-1, 3)
        paths = []
        for row in self._closings(p, starts, 0, 0, np.zeros(len(starts))):
            j, close = int(row[2]), (int(row[3]), float(row[4]), float(row[5]), float(row[6]))
            path = _park_path(_closing_segments(inside[j][0].start, close))[0] + tuple(inside[j])
            c = sum(1 for a, b in zip(path[:-1], path[1:], strict=True) if a.gear != b.gear)
            askew = abs(float(wrap_angle(path[-1].end[2]))) > math.radians(1.0)
            paths.append((c, askew, sum(x.length for x in path), list(path)))
        # fewest changes, then parked parallel to the kerb, then shortest
        paths.sort(key=lambda c: c[:3])
        found = self._first_clear(p, [(c[0], c[2], c[3]) for c in paths])
        if found is None:
            return "no start heading of the minimum-slot maneuver joins the lane clear"
        return tuple(found[2]), found[2][0].start[0]

    def _closings(self, p: _Problem, q: FloatArray, gear: int, changes: int,
                  base: FloatArray) -> FloatArray:
        """Closing moves from poses ``q`` (M, 3): a straight, one arc that lands on the
        lane line heading +x, and a straight along the lane to a station on the start grid
        (:attr:`ManeuverSettings.start_grid`, at least ``approach`` on), in leave-time.
        Unchecked for collisions.

        Returns rows ``(changes, length, m, gear, straight, curvature, extend)`` sorted by
        cost, where ``m`` indexes ``q``, ``base`` (M,) is the length already driven
        and ``gear`` the gear driven so far (0: none). Curvature 0 means the pose
        is already on the lane.
        """
        x, y = q[:, 0], q[:, 1]
        th = np.asarray(wrap_angle(q[:, 2]), dtype=float)
        sin, cos = np.sin(th), np.cos(th)
        kmax = p.vehicle.max_curvature
        grid, lead = self.settings.start_grid, self.settings.approach
        index = np.arange(len(q), dtype=float)
        turning = (np.abs(th) > 1e-9) & (np.abs(th) < math.pi - 1e-6)
        on_lane = (np.abs(th) <= 1e-9) & (np.abs(y - p.lane_y) < 1e-6)
        zeros = np.zeros(int(on_lane.sum()))
        parts = [np.column_stack([zeros + changes, base[on_lane], index[on_lane], zeros + 1,
                                  zeros, zeros, zeros])]
        radii = np.array(self.settings.closing_radii, dtype=float)[:, None]  # every radius
        for g in (1, -1):  # at once: rows (radius, pose), in that order
            c = changes + (1 if gear and g != gear else 0)
            kappa = np.where(-th * g >= 0, kmax / radii, -kmax / radii)
            with np.errstate(divide="ignore", invalid="ignore"):
                d = (p.lane_y - y + (1 - cos) / kappa) / (g * sin)
            d0 = np.maximum(d, 0.0)
            end_x = x + g * d0 * cos - sin / kappa
            station = p.lane_s0 + end_x
            if grid > 0:  # on along the lane, in the same gear, to a grid station
                with np.errstate(invalid="ignore"):
                    target = (np.ceil((station + lead) / grid - 1e-9) if g > 0
                              else np.floor((station - lead) / grid + 1e-9)) * grid
                extend = np.abs(target - station)
            else:
                extend = np.zeros(kappa.shape)
            last_x = end_x + g * extend
            # no straight of a few centimetres before the arc: where the curvature
            # jumps cannot be eased the car stops at both its ends (it would creep)
            ok = (turning & (d >= -1e-9) & ((d0 <= 1e-9) | (d0 >= CREEP))
                  & (end_x >= p.lane_x[0]) & (end_x <= p.lane_x[1])
                  & (last_x >= p.lane_x[0] - 1e-9) & (last_x <= p.lane_x[1] + 1e-9))
            n = int(ok.sum())
            parts.append(np.column_stack([
                np.full(n, c), (base + d0 + np.abs(th / kappa) + extend)[ok],
                np.broadcast_to(index, ok.shape)[ok], np.full(n, g), d0[ok], kappa[ok],
                extend[ok]]))
        out = np.concatenate(parts)
        return out[np.lexsort((out[:, 1], out[:, 0]))]

    def _extents(self, p: _Problem, poses: FloatArray, gear: int, kappa: float,
                 turn_cap: float = math.pi) -> FloatArray:
        """How far strokes from ``poses`` (H, 3) run clear [m], to the sweep step; (H,)."""
        cap = 1.5 * p.vehicle.length + 2.0
        if kappa:
            cap = min(cap, turn_cap / abs(kappa))
        n = max(1, math.ceil(cap / self.settings.sweep))
        s = np.linspace(0.0, cap, n + 1)
        local = advance(poses[:, None, :], gear * s[None, :], kappa)  # (H, n+1, 3)
        bodies = p.vehicle.footprints(p.frame.poses_to_world(local.reshape(-1, 3)))
        at = np.arange(len(bodies) - 1)
        row = np.where(at % (n + 1) != n, at // (n + 1), -1)  # not from one into the next
        bad = np.append(p.first_blocked(bodies, row), False).reshape(len(poses), n + 1)[:, :n]
        first = np.where(bad.any(axis=1), bad.argmax(axis=1), n)
        return s[first]


def _anchored(segments: Sequence[Segment], target: FloatArray) -> tuple[Segment, ...] | None:
    """``segments`` with two of its straights lengthened or shortened (the pair most nearly
    at right angles; what follows each moves with it) so that it ends exactly on ``target``
    (same heading, a few centimetres off); None when there is no such pair, or a straight
    would get shorter than 5 cm."""
    straights = [k for k, x in enumerate(segments) if x.curvature == 0.0 and x.sharpness == 0.0]
    pairs = [(abs(math.sin(segments[i].start[2] - segments[j].start[2])), i, j)
             for i, j in itertools.combinations(straights, 2)]
    if not pairs or max(pairs)[0] < 0.3:
        return None
    _, i, j = max(pairs)
    miss = np.asarray(target[:2], dtype=float) - np.asarray(segments[-1].end[:2], dtype=float)
    # miss = a * gi * u(θi) + b * gj * u(θj)
    m = np.column_stack([segments[i].gear * unit(segments[i].start[2]),
                         segments[j].gear * unit(segments[j].start[2])])
    a, b = np.linalg.solve(m, miss)
    lengths = [x.length for x in segments]
    lengths[i] += float(a)
    lengths[j] += float(b)
    if min(lengths[i], lengths[j]) < 0.05:
        return None
    out, pose = [], segments[0].start
    for x, length in zip(segments, lengths, strict=True):
        seg = Segment(pose, x.gear * length, x.curvature, x.sharpness)
        out.append(seg)
        pose = seg.end
    return tuple(out)


def _shortest_run(m: Maneuver) -> float:
    """The shortest stretch [m] a car drives between two stops on ``m``: the runs the timing
    drives without stopping (:func:`~lotsim.vehicles.motion.runs`)."""
    return min(sum(p.segment.length for p in run)
               for run in runs([Piece(s, math.inf) for s in m.segments]))


def _straighten(vehicle: VehicleType, frame: SlotFrame, strokes: list[Segment]) -> list[Segment]:
    """One full-lock arc that turns a car parked by the minimum-slot strategy (which stops
    the moment it is inside, often askew) parallel to the kerb, staying inside ``frame``;
    in the gear it was in if that fits, else the other. Nothing if neither fits."""
    end = strokes[-1].end
    th = float(wrap_angle(end[2]))
    if abs(th) < math.radians(0.5):
        return []
    for g, f in itertools.product((strokes[-1].gear, -strokes[-1].gear), (1.0, 0.5, 0.25)):
        kappa = vehicle.max_curvature * f
        arc = Segment(end, g * abs(th) / kappa, -math.copysign(kappa, th * g))
        corners = vehicle.footprints(arc.sample(0.05))
        x, y = corners[..., 0], corners[..., 1]
        if (x.min() >= 0 and x.max() <= frame.length and y.min() >= 0
                and y.max() <= frame.width):
            return [arc]
    return []


def _way(registry: list[tuple], level: int, m: int) -> list[Segment]:
    """The way to stop ``m`` of ``level`` of :meth:`ManeuverPlanner._shuffle`'s
    ``registry``: the strokes before it, and the part of its own stroke up to it."""
    heads, flat, _, owner, g, kappa = registry[level]
    segs, pose, _ = heads[owner[m]]
    return segs + ([Segment(pose, g * float(flat[m]), kappa)] if flat[m] > 1e-9 else [])


def _closing_segments(pose: Pose, close: tuple[int, float, float, float]) -> list[Segment]:
    """The pieces of a closing move ``(gear, straight, curvature, extend)`` from ``pose``:
    the straight, the arc onto the lane, and ``extend`` metres along the lane."""
    g, d, kappa, extend = close
    if kappa == 0.0:
        return []
    segs = []
    if d > 1e-9:
        segs.append(Segment(pose, g * d, 0.0))
        pose = segs[0].end
    segs.append(Segment(pose, -float(wrap_angle(pose[2])) / kappa, kappa))
    if extend > 1e-9:
        segs.append(Segment(segs[-1].end, g * extend, 0.0))
    return segs


WAY_OUT_BUDGET = 1500
"""Most states the multi-point search for a way out of a slot expands (when the shuffle
found none): ways out of the drawn real-style lots were found within 1000, and a slot with
none costs the whole budget."""


class _LocalChecks:
    """A problem's validity checks for :func:`~lotsim.roadmap.multipoint.plan_onto` run in the
    problem's local frame: footprints of local poses, and whether bodies are free."""

    def __init__(self, p: _Problem):
        self._p = p
        self.blocked = p.bodies_blocked

    def footprints(self, local_poses: FloatArray) -> FloatArray:
        return self._p.vehicle.footprints(self._p.frame.poses_to_world(local_poses))


def _park_path(leave: Sequence[Segment]) -> tuple[tuple[Segment, ...], float]:
    """Leave-time pieces → parking pieces (time-reversed), and the start's local x."""
    segs = tuple(s.backwards() for s in reversed(leave))
    return segs, (segs[0].start[0] if segs else 0.0)


def _taken_zone(slot: Slot, width: float, margin: float) -> Polygon:
    """What a maneuver must keep out of because of a car parked in ``slot``.

    Perpendicular and angled: a strip ``width`` wide centred across the slot
    along its whole length (cars park centred), grown by ``margin``. Parallel:
    the whole slot (the car may stand anywhere in it) grown by ``margin`` at
    both ends and the kerb but not past the entry line — a car parking next to
    it starts with its corner on that line (the minimum-slot strategy), and the
    parked car does not reach over it.
    """
    c = np.asarray(slot.center)
    if slot.kind == "parallel":
        a, b = slot.entry
        u = (b - a) / np.linalg.norm(b - a)
        n = c - (a + b) / 2
        n = n / np.linalg.norm(n) * (slot.width + margin)
        a, b = a - u * margin, b + u * margin
        return Polygon([a, b, b + n, a + n])
    u = unit(slot.heading)
    n = np.array([-u[1], u[0]])
    hl, hw = slot.length / 2, min(width, slot.width) / 2
    strip = Polygon([c - hl * u - hw * n, c + hl * u - hw * n, c + hl * u + hw * n,
                     c - hl * u + hw * n])
    return strip.buffer(margin, join_style="mitre") if margin else strip


def _local_geometry(geoms: np.ndarray, frames: Sequence[_Frame], owner: np.ndarray
                    ) -> list[bytes]:
    """Rounded (1 cm), normalised WKB of each of ``geoms`` in its frame, ``frames[owner[i]]``
    for ``geoms[i]`` (the sums of :meth:`_Frame.points_to_local`, so the same floats)."""
    xy, at = shapely.get_coordinates(geoms, return_index=True)
    of = owner[at]
    ox, oy = np.array([f.x for f in frames])[of], np.array([f.y for f in frames])[of]
    c = np.array([math.cos(f.heading) for f in frames])[of]
    s = np.array([math.sin(f.heading) for f in frames])[of]
    sy = np.array([-1.0 if f.mirror else 1.0 for f in frames])[of]
    dx, dy = xy[:, 0] - ox, xy[:, 1] - oy
    local = shapely.set_coordinates(geoms.copy(), np.stack(
        [c * dx + s * dy, sy * (-s * dx + c * dy)], axis=-1))
    # pointwise: a cache key needs rounded coordinates, not a valid polygon (a neighbour's
    # thin margin strip, moved into the local frame, may self-touch, and GEOS's default
    # mode then throws a TopologyException)
    local = shapely.normalize(shapely.set_precision(local, 0.01, mode="pointwise"))
    return list(shapely.to_wkb(local))


def plan_maneuver(vehicle: VehicleType, slot: Slot, lot: Lot, *, style: str = "any",
                  margin: float = MARGIN, max_changes: int = 8) -> Maneuver:
    """The best parking maneuver for one slot: fewest direction changes, then shortest.

    A one-off convenience; to plan many slots of one lot, keep one
    :class:`ManeuverPlanner`, which caches by geometry.

    Raises
    ------
    InfeasibleManeuver
        When ``vehicle`` cannot park in ``slot`` from any lane, with the reason.
    """
    planner = ManeuverPlanner(lot, margin=margin, max_changes=max_changes)
    return planner.best(vehicle, slot, style=style)


def plan_lot(planner: ManeuverPlanner, vehicles: Iterable[VehicleType], *,
             style: str = "any", workers: int | None = None,
             progress: Callable[[int, int], None] | None = None,
             known: dict[bytes, tuple] | None = None
             ) -> tuple[dict[tuple[str, str, str], Maneuver], dict[str, dict[str, str]],
                        dict[tuple[str, str, str], Maneuver]]:
    """Maneuvers for every slot, vehicle type and lane of a lot, searched on ``workers``
    processes (:meth:`ManeuverPlanner.prefetch`; the same answers on any number).

    Returns
    -------
    maneuvers : dict
        ``(vehicle name, slot id, lane id)`` → Maneuver (:meth:`ManeuverPlanner.solve_all`).
    infeasible : dict
        vehicle name → {slot id: reason} for the slots it cannot use.
    stays : dict
        ``(vehicle name, slot id, lane id)`` → that lane's own best Maneuver, where it parks
        the other way round than the one in ``maneuvers`` (for cars that will not leave;
        :meth:`ManeuverPlanner.solve_lanes`).

    ``progress(done, total)`` is called as the distinct problems are searched; ``known``:
    answers found before, and kept (:meth:`ManeuverPlanner.prefetch`).
    """
    vehicles = list(vehicles)
    planner.prefetch(vehicles, style=style, workers=workers, progress=progress, known=known)
    maneuvers: dict[tuple[str, str, str], Maneuver] = {}
    stays: dict[tuple[str, str, str], Maneuver] = {}
    infeasible: dict[str, dict[str, str]] = {}
    for v in vehicles:
        infeasible[v.name] = {}
        for slot in planner.lot.slots:
            found, own, why = planner.solve_lanes(v, slot, style=style)
            for lane, m in found.items():
                maneuvers[(v.name, slot.id, lane)] = m
            for lane, m in own.items():
                stays[(v.name, slot.id, lane)] = m
            if not found:
                infeasible[v.name][slot.id] = why
    return maneuvers, infeasible, stays


def _counted(answers: Iterable, total: int, progress: Callable[[int, int], None] | None
             ) -> list:
    """``list(answers)``, calling ``progress(done, total)`` as they come."""
    out = []
    for answer in answers:
        out.append(answer)
        if progress is not None:
            progress(len(out), total)
    return out


_JOB: tuple = ()  # (planner, triples, parent pid) for the forked workers of _Workers
PARALLEL_FROM = 64
"""Fewest problems worth starting worker processes for."""


class _Workers:
    """Forked processes that pose and search ``planner``'s problems ``triples`` (vehicle,
    slot, lane), found by index in their copy of ``_JOB``: nothing but indices and answers
    is pickled. A process that multiprocessing started (a worker of the bench's pool, of
    Dask, of the caller's) works by itself instead: its parent already shares the cores out;
    so does one with few problems, or without ``fork``."""

    def __init__(self, planner: ManeuverPlanner, triples: list, workers: int | None):
        workers = (workers or (1 if multiprocessing.parent_process() else os.cpu_count()) or 1)
        workers = min(workers, max(1, len(triples) // 16))
        self.count = workers if (workers >= 2 and len(triples) >= PARALLEL_FROM and "fork"
                                 in multiprocessing.get_all_start_methods()) else 1
        self.job = (planner, triples, os.getpid())
        self.pool = None

    def __enter__(self) -> _Workers:
        global _JOB
        _JOB = self.job
        if self.count > 1:
            self.pool = multiprocessing.get_context("fork").Pool(
                self.count, initializer=quiet_worker, initargs=(self.job[2],))
        return self

    def __exit__(self, *exc: object) -> None:
        global _JOB
        _JOB = ()
        if self.pool is not None:  # done, or Ctrl-C here: its workers end
            self.pool.terminate()
            self.pool.join()

    def map(self, fn: Callable, items: list, *, chunk: int,
            progress: Callable[[int, int], None] | None = None) -> list:
        """``[fn(item) for item in items]``, on the workers; ``progress(done, total)`` as
        answers come."""
        answers = (self.pool.imap(fn, items, chunksize=chunk) if self.pool is not None
                   else map(fn, items))
        return _counted(answers, len(items), progress)


def _digest_job(part: tuple[int, int]) -> list[tuple[bytes, _Frame, float]]:
    """:meth:`ManeuverPlanner._digests` of triples ``part[0]`` to ``part[1]`` (excluded):
    each one's problem digest, frame and lane station at x = 0."""
    planner, triples, _ = _JOB
    return planner._digests(triples[part[0]:part[1]])


def _search_job(job: tuple[int, str]) -> tuple:
    """Triple ``job[0]``'s problem searched in style ``job[1]`` (posed here: it was keyed
    without being posed whole): (eased, as planned, its exact key, whether the planner's
    ``known`` answers held it). No exact key (None) when there is no ``known``."""
    planner, triples, _ = _JOB
    k, style = job
    problem = planner._problem(*triples[k])
    if planner._known is None:
        return *planner._search(problem, style), None, False
    exact = _exact_key(problem, style)
    found = planner._known.get(exact)
    if found is not None:
        return *found, exact, True
    return *planner._search(problem, style), exact, False


KNOWN_MOST = 20_000
"""Most answers :meth:`ManeuverPlanner.prefetch` keeps in ``known`` (under 1 kB each; the
364-bay lot with four types has 5072 distinct problems)."""


def _exact_key(p: _Problem, style: str) -> bytes:
    """Everything a search of ``p`` in ``style`` reads, floats to the last bit: the car, the
    slot, the frame, the lane, the window, the allowed region and the set of obstacles. Problems
    with equal keys, from any lot, are searched alike and have the same answer (for the
    same settings and lotsim). :meth:`ManeuverPlanner._key` rounds to 1 cm instead: it
    finds the problems of one lot that may share an answer."""
    h = hashlib.blake2b(digest_size=20)
    h.update(repr((p.vehicle, p.slot.kind, p.slot.length, p.slot.width, p.frame, p.lane_y,
                   p.lane_x, p.lane_s0, p.half, p.sweep, style)).encode())
    h.update(np.asarray(p.slot.polygon, dtype=float).tobytes())
    for wkb in shapely.to_wkb([p.slot.shape, p.allowed, p.window]):
        h.update(wkb)
    # the obstacles as a set: a search only asks whether a body meets any (their order is
    # the lot's tree's, which an edit elsewhere in the lot changes)
    for wkb in sorted(shapely.to_wkb(p.obstacles)):
        h.update(wkb)
    return h.digest()
