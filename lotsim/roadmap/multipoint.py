"""Multi-point turns anywhere the drivable area allows: from a pose onto a lane's line.

Where no single turn takes a car onto a lane — a junction too small to turn in at one go,
the end of a short arm, a dead end whose turnaround must land before the lane's next turn
— a driver makes a few strokes at or near full lock, forward and back, and then one last
move onto the lane. :func:`plan_onto` finds such a path with a Hybrid A* (Dolgov, Thrun,
Montemerlo and Diebel, 2008):

* states are continuous poses, one kept per cell of an (x, y, heading) grid;
* a move is a short arc at full left lock, a straight or an arc at full right lock,
  forward or in reverse, and is kept only if the body's sweep over it touches nothing
  (hulls of footprints :attr:`~MultipointSettings.step` apart, as everywhere in lotsim);
* from every state the search tries to finish at once with the turnaround planner's last
  move (:func:`closing_moves`: a straight, one arc and a straight along
  the lane, or an S of two wide arcs), left-handed or mirrored;
* the cost is path length, plus a price on every change of direction and of steering
  (each is a stop to turn the wheels: :func:`lotsim.vehicles.motion.timed_path`), so the
  fewest strokes win; the heuristic is the larger of the straight-line distance to the
  stretch of lane it may land on and the full-lock arc that turns the car to the lane's
  heading, neither of which overestimates, weighted by
  :attr:`~MultipointSettings.weight` (a path found costs at most that much more than the
  cheapest, and is found far sooner).

The move, the grid, the prices, the expansion limit and the last moves' radii are a
:class:`~lotsim.roadmap.settings.MultipointSettings` the caller passes.

Everything is checked for ``body`` (a design vehicle grown by the safety margin, as
:func:`lotsim.roadmap.turnarounds.turnaround_collider` makes it) against ``collider``.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Sequence

import numpy as np

from lotsim.core.geometry import FloatArray, Pose, Segment, advance, sample_segments
from lotsim.core.outcome import Outcome, Status
from lotsim.lot.clearance import Collider, RigidSweeps, first_blocked
from lotsim.lot.model import DesignVehicle
from lotsim.roadmap.settings import DEFAULTS, MultipointSettings

AHEAD = 8
"""States whose moves are checked at once: the one expanded and those nearest the top of the
search's heap (most are expanded soon after; checking several in one batch costs less a
state, and what the search finds is the same)."""
MOVE_BLOCK = 5
"""Sweeps of a move checked first as one hull (a move's ten in two blocks: what checks a
lot's moves quickest; the answers are the same for any)."""


def plan_onto(starts: Sequence[Pose], frame: Pose, lo: float, hi: float,
              collider: Collider, body: DesignVehicle, radius: float, *,
              settings: MultipointSettings = DEFAULTS.multipoint, max_changes: int | None = None,
              budget: int | None = None, ahead: int = AHEAD
              ) -> Outcome[tuple[int, tuple[Segment, ...]]]:
    """The cheapest multi-point path found from any of ``starts`` onto the line through
    ``frame`` (heading along it), landing between ``lo`` and ``hi`` metres along it and
    ending there heading along it, driven forward at the end: an
    :class:`~lotsim.core.outcome.Outcome` holding ``(index of its start, segments)``, or
    why there is none: ``infeasible`` (no stretch to land on), ``out of budget`` (the
    search stopped at ``budget`` states), ``no path`` (every state within ``max_changes``
    direction changes searched). One search serves every start (a tie goes to the
    earlier).

    ``body`` is checked against ``collider`` all the way; no arc is tighter than
    ``radius`` [m]. All poses are in the world frame: the frame of ``body.footprints(poses)``
    and of ``collider.blocked(bodies, convex=False)`` (as a
    :class:`~lotsim.lot.clearance.Collider` and a design vehicle have them; the moves' sweeps
    are made once, from the origin, and placed at each state). ``settings``: the search's
    tuning; ``max_changes`` and ``budget`` (states expanded), when given, replace its
    ``max_changes`` and ``expansion_limit``. ``ahead``: states whose moves are checked in
    one batch (:data:`AHEAD`; the paths found are the same for any).

    Examples
    --------
    A car heading north up a 6 m spur into a 6 m cross street that is too short on its
    right for one right turn (a car 4.3 m long, radius 5 m): it lands on the east-bound
    lane after a few strokes, all clear of the lot's edges.

    >>> from shapely.geometry import box
    >>> from lotsim.lot.clearance import Collider
    >>> lot = box(4, -12, 10, 0).union(box(0, 0, 16, 6))
    >>> car = DesignVehicle(1.9, 3.6, 0.9, 5.0, 0.15, 2.0)
    >>> found = plan_onto([(8.5, -8.0, math.pi / 2)], (0.0, 1.5, 0.0), 9.0, 11.5,
    ...                   Collider([], lot), car, 5.0)
    >>> _, path = found.value
    >>> end = path[-1].end
    >>> round(end[1], 6), round(end[2], 6), 9.0 <= end[0] <= 11.5
    (1.5, 0.0, True)
    """
    max_changes = settings.max_changes if max_changes is None else max_changes
    budget = settings.expansion_limit if budget is None else budget
    search = _Search(starts, frame, lo, hi, collider, body, radius, ahead, settings)
    if search.span < 0:
        return Outcome.failed(Status.INFEASIBLE, "no stretch of lane to land on")
    best = search.run(max_changes, budget)
    if best is None:
        if search.expanded >= budget:
            return Outcome.failed(Status.OUT_OF_BUDGET,
                                  f"no multi-point path within {budget} states")
        return Outcome.failed(Status.NO_PATH, f"no multi-point path with up to "
                                              f"{max_changes} direction changes")
    _, sid, tail = best
    states = search.states
    segs: list[Segment] = []
    while states[sid][4] >= 0:
        segs.append(states[sid][5])
        sid = states[sid][4]
    segs.reverse()
    return Outcome.of((sid, tuple(segment_to_world(search.origin, x)
                                  for x in _merged([*segs, *tail]))))


class _Search:
    """The state of one :func:`plan_onto` search, in the local frame of the landing
    stretch (its start at the origin, heading +x, ``span`` long).

    A state is (local pose, gear of the last move, curvature, changes, parent, segment);
    the first ``len(starts)`` are the starts."""

    def __init__(self, starts: Sequence[Pose], frame: Pose, lo: float, hi: float,
                 collider: Collider, body: DesignVehicle, radius: float, ahead: int,
                 settings: MultipointSettings):
        self.settings = settings
        self.expanded = 0  # states expanded so far
        self.origin = np.array(frame, dtype=float)
        self.origin[:2] += lo * np.array([math.cos(frame[2]), math.sin(frame[2])])
        self.span = hi - lo
        self.collider, self.body, self.radius, self.ahead = collider, body, radius, ahead
        kmax = 1.0 / radius
        self.moves = [(gear, kappa) for gear in (1, -1) for kappa in (kmax, 0.0, -kmax)]
        move = settings.move
        n = round(move / settings.step)
        s = np.linspace(0.0, move, n + 1)
        # the sweeps of the moves from the origin, (n + 1) footprints along each, placed at
        # each state checked
        along = np.concatenate([g * s for g, _ in self.moves])
        bend = np.repeat([k for _, k in self.moves], n + 1)
        prints = body.footprints(advance(np.zeros(3), along, bend))
        self.sweeps = RigidSweeps(np.split(prints, len(self.moves)), MOVE_BLOCK)
        self.states: list[tuple[FloatArray, int, float, int, int, Segment | None]] = [
            (to_local(self.origin, np.array(p, dtype=float)), 0, math.nan, 0, -1, None)
            for p in starts]
        self.cost = [0.0] * len(self.states)
        self.heap = [(settings.weight * self.h(x[0]), k) for k, x in enumerate(self.states)]
        heapq.heapify(self.heap)
        self.closed: set[tuple[int, int, int]] = set()
        # what expanding a state checks (its shortest clear last move, its blocked moves),
        # for it and the states likely next (``ahead``), in one batch
        self.checked: dict[int, tuple[tuple[float, list[Segment]] | None, set[int]]] = {}
        self.cells: dict[int, tuple[int, int, int]] = {}  # :meth:`cell_of`

    def h(self, q: FloatArray) -> float:
        """Never more than the path still to drive: the distance to the landing stretch,
        and the arc that turns the car to the lane's heading at full lock."""
        return max(math.hypot(max(-q[0], 0.0, q[0] - self.span), q[1]),
                   self.radius * abs(math.remainder(q[2], 2 * math.pi)))

    def cell(self, q: FloatArray) -> tuple[int, int, int]:
        cell, headings = self.settings.cell, self.settings.headings
        return (round(q[0] / cell), round(q[1] / cell),
                round(q[2] / (2 * math.pi / headings)) % headings)

    def cell_of(self, sid: int) -> tuple[int, int, int]:
        """:meth:`cell` of state ``sid``, worked out once (a state near the top of the heap
        is looked at again each time the states ahead are chosen)."""
        got = self.cells.get(sid)
        if got is None:
            got = self.cells[sid] = self.cell(self.states[sid][0])
        return got

    def run(self, max_changes: int, budget: int
            ) -> tuple[float, int, list[Segment]] | None:
        """The cheapest path found: (its cost, the state it leaves from, its last move)."""
        states, cost, heap, closed, moves = (self.states, self.cost, self.heap, self.closed,
                                             self.moves)
        tune = self.settings
        move, cusp, steer, reverse, weight = (tune.move, tune.cusp, tune.steer, tune.reverse,
                                              tune.weight)
        best: tuple[float, int, list[Segment]] | None = None
        expanded = found_at = 0
        while heap and expanded < budget:
            f, sid = heapq.heappop(heap)
            if best is not None and (f >= best[0] or expanded >= found_at + tune.improve):
                break
            q, gear, kappa, changes, _, _ = states[sid]
            key = self.cell_of(sid)
            if key in closed:
                continue
            closed.add(key)
            expanded += 1
            self.expanded = expanded
            if sid not in self.checked:
                ahead = [k for _, k in sorted(heap[:2 * self.ahead])
                         if k not in self.checked
                         and self.cell_of(k) not in closed][:self.ahead - 1]
                self.check([sid, *ahead])
            last, hit = self.checked.pop(sid)
            if last is not None:
                extra = (cusp if gear < 0 else 0.0) + last[0]
                if changes + (gear < 0) <= max_changes and (
                        best is None or cost[sid] + extra < best[0]):
                    if best is None:
                        found_at = expanded
                    best = (cost[sid] + extra, sid, last[1])
            ends = advance(np.repeat(q[None, :], len(moves), axis=0),
                           np.array([g * move for g, _ in moves]),
                           np.array([k for _, k in moves]))
            for m, (g, k) in enumerate(moves):
                if m in hit:
                    continue
                turn = gear != 0 and g != gear
                if changes + turn > max_changes:
                    continue
                c = cost[sid] + move * (1.0 if g > 0 else reverse) + (cusp if turn else 0.0) + (
                    steer if not turn and gear != 0 and k != kappa else 0.0)
                end = ends[m]
                end[2] %= 2 * math.pi
                states.append((end, g, k, changes + turn, sid,
                               Segment(tuple(map(float, q)), g * move, k)))
                cost.append(c)
                heapq.heappush(heap, (c + weight * self.h(end), len(states) - 1))
        return best

    def check(self, sids: list[int]) -> None:
        """For each of states ``sids``, its shortest clear last move (or None) and its
        blocked moves, all checked in one batch."""
        radius, span = self.radius, self.span
        prints, runs, lasts = [], [], []
        at = 0  # runs so far: the closings
        for sid in sids:
            q = self.states[sid][0]
            found = [(sum(x.length for x in segs), segs)
                     for segs in closing_moves(q, span, radius, settings=self.settings)]
            found += [(sum(x.length for x in segs), _mirror(segs))
                      for segs in closing_moves(_mirror_pose(q), span, radius,
                                                settings=self.settings)]
            found.sort(key=lambda c: c[0])
            lasts.append((found, at))
            if found:  # the last moves, shortest first: one run each
                sampled = [sample_segments(segs, self.settings.step)[0] for _, segs in found]
                owner = np.repeat(np.arange(len(sampled)), [len(x) for x in sampled])
                prints.append(self.body.footprints(to_world(self.origin,
                                                            np.concatenate(sampled))))
                runs.append(np.where(owner[1:] == owner[:-1], owner[1:] + at, -1))
                runs.append([-1])
                at += len(found)
        hit = np.zeros(at, dtype=bool)
        if prints:
            of = np.concatenate(runs)[:-1].astype(int)
            hit[of[first_blocked(self.collider.blocked, np.concatenate(prints), of)]] = True
        # every state's moves in one batch
        qs = np.array([self.states[sid][0] for sid in sids])
        moved = self.sweeps.first_blocked(self.collider.blocked, to_world(self.origin, qs))
        blocked = moved < self.sweeps.counts
        for i, (sid, (found, first)) in enumerate(zip(sids, lasts, strict=True)):
            last = next((found[k] for k in range(len(found)) if not hit[first + k]), None)
            self.checked[sid] = (last, set(np.flatnonzero(blocked[i]).tolist()))


def _merged(segs: list[Segment]) -> list[Segment]:
    """Consecutive moves of one gear and curvature as one segment."""
    out: list[Segment] = []
    for x in segs:
        if x.length < 1e-9:
            continue
        if out and out[-1].sharpness == 0.0 == x.sharpness and out[-1].gear == x.gear \
                and out[-1].curvature == x.curvature:
            out[-1] = Segment(out[-1].start, out[-1].distance + x.distance, x.curvature)
        else:
            out.append(x)
    return out


def _mirror_pose(q: FloatArray) -> FloatArray:
    """``q`` reflected in the lane's line (y → -y, heading → -heading)."""
    return np.array([q[0], -q[1], (-q[2]) % (2 * math.pi)])


def _mirror(segs: list[Segment]) -> list[Segment]:
    return [Segment((x.start[0], -x.start[1], -x.start[2]), x.distance, -x.curvature,
                    -x.sharpness) for x in segs]


def closing_moves(q: FloatArray, lane_length: float, radius: float, *,
                  settings: MultipointSettings = DEFAULTS.multipoint) -> list[list[Segment]]:
    """Last moves from local pose ``q`` onto the line y = 0 heading +x, driven forward: a
    straight, a left arc, a straight along the lane to a grid station, or (from above the
    line, heading along it or down) an S of two arcs and a straight; shortest first. The
    arcs try ``settings``' :attr:`~MultipointSettings.closing_radii` and
    :attr:`~MultipointSettings.s_radii` times ``radius``; the lane's stations are its
    :attr:`~MultipointSettings.grid`."""
    x, y, th = (float(v) for v in q)
    out = []
    if math.pi < th < 2 * math.pi - 1e-9:
        sin, cos = math.sin(th), math.cos(th)
        for f in settings.closing_radii:
            r = f * radius
            d = (r * (1 - cos) - y) / sin  # straight before the arc (sin < 0)
            if d < -1e-9:
                continue
            p = (x, y, th)
            segs = [Segment(p, max(d, 0.0), 0.0)] if d > 1e-9 else []
            p = segs[-1].end if segs else p
            segs.append(Segment(p, (2 * math.pi - th) * r, 1.0 / r))
            out += _onto_lane(segs, lane_length, settings.grid)
    if 1.5 * math.pi < th <= 2 * math.pi + 1e-9 and y > 1e-6:
        for f in settings.s_radii:
            out += _onto_lane(_s_curve(x, y, th, f * radius), lane_length, settings.grid)
    return [segs for _, segs in sorted(out, key=lambda c: c[0])]


def _s_curve(x: float, y: float, th: float, r: float) -> list[Segment]:
    """A right arc then a left arc, both of radius ``r``, from local ``(x, y, th)`` to the
    line y = 0 heading +x (empty when the two circles cannot meet)."""
    c1 = (x + r * math.sin(th), y - r * math.cos(th))  # centre of the right arc
    gap = c1[1] - r  # the left arc's centre lies at height r
    if abs(gap) > 2 * r:
        return []
    c2 = (c1[0] + math.sqrt(4 * r * r - gap * gap), r)
    mx, my = (c1[0] + c2[0]) / 2, (c1[1] + c2[1]) / 2  # where the arcs meet
    h = math.atan2(-(mx - c1[0]), my - c1[1])  # heading there
    first = (th - h) % (2 * math.pi)
    second = (-h) % (2 * math.pi)
    if first > math.pi or second > math.pi:
        return []  # not an S: it would loop
    a = Segment((x, y, th), first * r, -1.0 / r)
    return [a, Segment(a.end, second * r, 1.0 / r)]


def _onto_lane(segs: list[Segment], lane_length: float, grid: float
               ) -> list[tuple[float, list[Segment]]]:
    """``segs``, which end on the line y = 0 heading +x, and a straight along it to the next
    station that is a multiple of ``grid`` [m], ``grid`` or more ahead (with their length),
    if that is on the lane."""
    if not segs:
        return []
    end_x = segs[-1].end[0]
    target = math.ceil((end_x + grid) / grid - 1e-9) * grid
    if end_x < -1e-9 or target > lane_length + 1e-9:
        return []
    segs = [*segs, Segment((segs[-1].end[0], 0.0, 0.0), target - end_x, 0.0)]
    return [(sum(s.length for s in segs), segs)]



def to_local(frame: FloatArray, poses: FloatArray) -> FloatArray:
    p = np.atleast_2d(poses).astype(float)
    c, s = math.cos(frame[2]), math.sin(frame[2])
    dx, dy = p[:, 0] - frame[0], p[:, 1] - frame[1]
    out = np.column_stack([c * dx + s * dy, -s * dx + c * dy,
                           np.mod(p[:, 2] - frame[2], 2 * math.pi)])
    return out[0] if np.ndim(poses) == 1 else out


def to_world(frame: FloatArray, poses: FloatArray) -> FloatArray:
    p = np.atleast_2d(poses)
    c, s = math.cos(frame[2]), math.sin(frame[2])
    return np.column_stack([frame[0] + c * p[:, 0] - s * p[:, 1],
                            frame[1] + s * p[:, 0] + c * p[:, 1], p[:, 2] + frame[2]])


def segment_to_world(frame: FloatArray, seg: Segment) -> Segment:
    x, y, t = to_world(frame, np.array(seg.start))[0]
    pose: Pose = (float(x), float(y), float(math.remainder(t, 2 * math.pi)))
    return Segment(pose, seg.distance, seg.curvature, seg.sharpness)
