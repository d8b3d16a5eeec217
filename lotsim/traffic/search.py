"""Cooperative space-time A* over the lot graph: CA*, HCA* and WHCA*.

A vehicle's search state is ``(node, speed level, time)``: it stands on a lot
graph node at a time [s], at rest (level 0) or passing through at one of a few
speeds (multiples of :attr:`~lotsim.traffic.settings.SearchSettings.speed_step`, 5 km/h,
up to its top speed). Moves are

* **drive an edge** from speed level ``a`` to ``b``: the fastest jerk-limited
  profile (:func:`~lotsim.vehicles.motion.scurve`) within the edge's speed limit —
  the lowest of the lot's, the vehicle's top speed, and what the edge's curves
  allow for lateral acceleration and steering rate — and the vehicle's
  acceleration, braking and jerk, with zero acceleration at both nodes; so plans
  are the trajectories, with no re-timing afterwards;
* **wait** at a node, at rest, for as long as it needs: from rest a vehicle departs on
  each edge at the earliest time of each stretch of time in which the edge's motion
  meets nobody (safe-interval path planning, SIPP: Phillips & Likhachev 2011), as long
  as its body stands in nobody's way meanwhile;
* **park** (from rest, through the slot's planned maneuver, ending at rest in
  the slot) or **leave** (the same backwards), taking the maneuver's time,
  with the car standing to turn its wheels at cusps and wherever the maneuver's
  curvature still jumps (:func:`~lotsim.vehicles.motion.timed_path`);
* **turn round** (from rest, through a multi-point turn at a dead end, to rest on the
  opposite lane), timed the same way;
* **enter**: a vehicle not yet in the lot waits outside its entrance, taking
  no space, until its first move is free.

Every move is checked against the :class:`~lotsim.traffic.reservation.ReservationTable`
with the hulls of what the vehicle sweeps, chunk by chunk (:mod:`~lotsim.traffic.swept`) —
a cover of its real
footprint at every instant, including the whole of a parking maneuver that
sweeps across the aisle. A goal in a slot is accepted only if the slot stays
free for ever after (the vehicle will stand there).

Heuristics: CA* uses the straight-line distance at top speed; HCA* the true
static time to the goal, from a Reverse Resumable A* (RRA*, Silver 2005) run
backwards from the goal and resumed on demand (:mod:`~lotsim.traffic.heuristic`). WHCA*
(in :func:`lotsim.sim.running.simulate`) searches like HCA* and replans every half window as
it drives, keeping the new plan when it arrives sooner. The expansion limit (the fuse of the
modelling-contest paper "Path planning for automatic parking of unmanned vehicles", 2022)
stops a search that expands more than ``omega`` times the nodes its reverse search closed;
the search then ends :attr:`~lotsim.core.outcome.Status.OUT_OF_BUDGET`.

The graph (:mod:`~lotsim.traffic.searchgraph`) and the tuning
(:class:`~lotsim.traffic.settings.SearchSettings`, the graph's) are the search's inputs
besides the table and the :class:`SearchRequest`; the answer is a
:class:`~lotsim.traffic.plans.Plan`.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from lotsim.core.geometry import same_pose
from lotsim.core.outcome import Status
from lotsim.traffic.heuristic import ReverseResumable
from lotsim.traffic.plans import Move, Plan
from lotsim.traffic.reservation import ReservationTable
from lotsim.traffic.searchgraph import SearchGraph
from lotsim.traffic.settings import OMEGA, PLANNERS
from lotsim.traffic.swept import Swept, standing_body

Pose = tuple[float, float, float]
"""``(x [m], y [m], heading [rad])`` of the rear-axle centre."""


@dataclass(frozen=True, slots=True)
class Goal:
    """Where a search ends: in ``slot`` (a slot node, for ever) or at any of ``exits``.

    A car that will leave again (``park_by`` given) parks only by the park edges
    ``(lane node, slot node)`` in ``park_by``, those that park it on a pose it can leave
    by (:meth:`~lotsim.roadmap.model.LotGraph.leavable`), and never with a maneuver the lot
    graph keeps for cars that stay (a park edge's ``park_only``)."""

    slot: int | None = None
    exits: tuple[int, ...] = ()
    park_by: frozenset[tuple[int, int]] | None = None

    def nodes(self) -> dict[int, float]:
        """The goal nodes, each with no extra time at it (what its reverse search starts
        from)."""
        return {self.slot: 0.0} if self.slot is not None else {n: 0.0 for n in self.exits}


@dataclass(frozen=True, slots=True)
class SearchRequest:
    """What one search is asked: whose way, from where and when, to what goal.

    Attributes
    ----------
    owner : str
        The vehicle: its own reservations are ignored.
    start : int
        Start node; ``level`` its speed level there (0: at rest).
    t0 : float
        Start time [s].
    goal : Goal
    level : int
    outside : bool
        The vehicle is not in the lot yet: it may wait outside ``start`` (an entrance) for
        free, and appears there at rest.
    start_pose : tuple or None
        The parked pose, when ``start`` is a slot: only the leave maneuver that begins
        there is driven, and waiting there holds this footprint.
    budget : int or None
        Stop at the expansion limit after this many expansions at the latest (a probe).
    """

    owner: str
    start: int
    t0: float
    goal: Goal
    level: int = 0
    outside: bool = False
    start_pose: Pose | None = None
    budget: int | None = None


def search(sg: SearchGraph, table: ReservationTable, request: SearchRequest, *,
           planner: str = "hca", heuristic: ReverseResumable | None = None,
           shared: bool = False, omega: float = OMEGA) -> Plan:
    """Plan one vehicle against the reservations of those planned before it.

    Parameters
    ----------
    sg : SearchGraph
        The lot graph for this vehicle's type; its
        :attr:`~lotsim.traffic.searchgraph.SearchGraph.settings` tune the search.
    table : ReservationTable
        Everyone else's reservations (``request.owner``'s own are ignored).
    request : SearchRequest
        Whose way, from where and when, to what goal.
    planner : {"ca", "hca", "whca"}
    heuristic : ReverseResumable, optional
        The RRA* towards the goal (made here if not given); also sizes the expansion limit.
    shared : bool
        ``heuristic`` serves other searches too: the expansion limit is sized by what a new
        one would have closed to answer ``start`` (:meth:`ReverseResumable.closed_at`), not
        by all it has closed for them, so a search reaches its expansion limit where it
        would with its own.
    omega : float
        The expansion limit's factor: a search stops after expanding ``omega`` times the
        nodes its reverse search closed (at least ``settings.min_budget``).

    Returns
    -------
    Plan
        ``FOUND`` with the moves; ``OUT_OF_BUDGET`` (the expansion limit was reached) or
        ``NO_PATH`` with none.
    """
    if planner not in PLANNERS:
        raise ValueError(f"unknown planner {planner!r}; expected one of {PLANNERS}")
    rra = heuristic or sg.reverse_search(request.goal.nodes())
    if rra(request.start) == math.inf:
        return Plan(Status.NO_PATH)
    h = _straight_line_time(sg, request.goal) if planner == "ca" else rra
    # (CA*'s reverse search still runs, for the expansion limit and to prune dead ends)
    state = _SpaceTimeSearch(sg, table, request, rra, h)
    state.push(request.start, request.level, request.t0, request.outside, -1, None)
    return state.run(_expansion_limit(sg, request, rra, shared, omega))


def _straight_line_time(sg: SearchGraph, goal: Goal) -> Callable[[int], float]:
    """CA*'s heuristic: the straight-line distance to the nearest goal node at top speed
    [s]."""
    top = float(sg.levels[-1])
    goal_xy = np.array([sg.pose[n][:2] for n in goal.nodes()])

    def h(n: int) -> float:
        x, y, _ = sg.pose[n]
        return float(np.min(np.hypot(goal_xy[:, 0] - x, goal_xy[:, 1] - y))) / top

    return h


def _expansion_limit(sg: SearchGraph, request: SearchRequest, rra: ReverseResumable, shared: bool,
          omega: float) -> float:
    """How many expansions a search may make: ``omega`` times the nodes its reverse search
    closed (for a shared one, those a new one would have closed to answer the start), at
    least ``settings.min_budget``, at most ``request.budget``."""
    min_budget = sg.settings.min_budget
    sized_by = rra.closed
    if shared and omega * sized_by > min_budget:  # (otherwise the limit is the same either way)
        sized_by = rra.closed_at(request.start)
    limit = max(min_budget, omega * sized_by)
    if request.budget is not None:
        limit = min(limit, request.budget)
    return limit


class _SpaceTimeSearch:
    """One search's state: the open states, each with the step that led there (made into
    moves only for the plan found), what is closed, and what it has asked the table.

    A state is ``(node, level, time, outside)``, kept by an integer id; the heap orders
    ids by time plus the weighted heuristic plus the time lost reaching top speed."""

    __slots__ = ("sg", "table", "request", "rra", "h", "heap", "states", "parent", "closed",
                 "passed", "h_of", "loss", "in_way", "parked_until", "gathered", "end",
                 "start_stand", "weight", "passing", "depart_after", "push")

    def __init__(self, sg: SearchGraph, table: ReservationTable, request: SearchRequest,
                 rra: ReverseResumable, h: Callable[[int], float]):
        s = sg.settings
        self.sg, self.table, self.request, self.rra, self.h = sg, table, request, rra, h
        self.weight, self.passing, self.depart_after = s.weight, s.passing, s.depart_after
        self.end = request.t0 + s.horizon
        # a car leaving its slot stands there first (other nodes' bodies are the graph's)
        self.start_stand = (Swept.of([(0.0, 0.0, standing_body(sg.vehicle, request.start_pose))])
                            if request.start_pose is not None else None)
        self.heap: list[tuple[float, float, int]] = []
        self.states: list[tuple[int, int, float, bool]] = []
        self.parent: list[tuple[int, tuple | None]] = []
        self.closed: set[tuple[int, bool, float]] = set()  # at rest: node, outside, free till
        self.passed: dict[tuple[int, int], float] = {}  # moving: (node, level) → last expanded
        lim = sg.vehicle.limits
        top = float(sg.levels[-1])
        # time lost reaching top speed from each level, and braking to rest before parking:
        # exact on long runs, an overestimate on the last few metres (plans are near-optimal)
        stop = top / (2 * lim.max_brake) if request.goal.slot is not None else 0.0
        self.loss = [(top - v) ** 2 / (2 * lim.max_accel * top) + stop for v in sg.levels]
        self.h_of: dict[int, float] = {}  # node → weight × heuristic, inf: goal out of reach
        self.in_way: dict[int, list[tuple[float, float]]] = {}  # node → when standing is not
        self.parked_until: dict[int, float] = {}  # park edge → till when its pose is taken
        self.gathered: dict = {}  # what the table holds near each edge, by time buckets
        self.push = _opener(self)

    def run(self, limit: float) -> Plan:
        """Expand states, best first, until the goal, the expansion limit or nothing left."""
        heap, states, closed, passed = self.heap, self.states, self.closed, self.passed
        goal, end, passing = self.request.goal, self.end, self.passing
        exits = set(goal.exits)
        heappop, inf = heapq.heappop, math.inf
        expansions = 0
        while heap:
            _, _, sid = heappop(heap)
            node, lvl, t, out = states[sid]
            if lvl == 0:
                # at rest: it may stand here until its body is first in someone's way
                # (outside, for ever); an earlier arrival within that same free stretch
                # could have waited till now, so the state is the node and the stretch's
                # end (SIPP)
                free_till = inf if out else self.free_till(node, t)
                # (standing where it is already in someone's way, it may only drive on)
                key = (node, out, free_till) if free_till > t else (node, out, t)
                if key in closed:
                    continue
                closed.add(key)
            else:
                # passing at speed it cannot wait, so a later state is no worse in every
                # way; but one soon after an earlier is taken for it, or every way of
                # stopping before a queue and going on again would be searched (a plan that
                # needs the later one waits on the way instead, at rest)
                last = passed.get((node, lvl))
                if last is not None and t - last < passing:
                    continue
                passed[node, lvl] = t
            expansions += 1
            if expansions > limit:
                return Plan(Status.OUT_OF_BUDGET, expansions=expansions)
            if t > end:
                continue
            if not out and (node in exits or node == goal.slot):
                return self.found(sid, expansions)
            # from rest it departs when the way is free, waiting for it where it stands
            self.expand(sid, node, lvl, t, out, min(free_till, end) if lvl == 0 else t)
        return Plan(Status.NO_PATH, expansions=expansions)

    def free_till(self, node: int, t: float) -> float:
        """Till when [s] the vehicle may stand at ``node`` from ``t`` (see
        :func:`_free_till`), from when its body there is in someone's way (asked of the
        table once per node: the table does not change meanwhile)."""
        hit = self.in_way.get(node)
        if hit is None:
            r = self.request
            if node == r.start and self.start_stand is not None:
                hit = self.table.blocked(self.start_stand, r.t0, self.end, ignore=r.owner)
            else:  # (what the body meets kept with it, for the next searches)
                hit = self.table.blocked_standing(self.sg.standing(node), r.t0, self.end,
                                                  ignore=r.owner)
            self.in_way[node] = hit
        return _free_till(hit, t)

    def expand(self, sid: int, node: int, lvl: int, t: float, out: bool, latest: float
               ) -> None:
        """Open every move from state ``sid`` (``node`` at level ``lvl`` at ``t``): along
        each edge it may take, to each end level, departing at ``t`` or, from rest, at the
        start of each stretch up to ``latest`` [s] in which the move meets nobody."""
        sg, table, r = self.sg, self.table, self.request
        goal, owner, start, push = r.goal, r.owner, r.start, self.push
        edges, variants_kept, boxes, cells_kept = sg.edges, sg._variants, sg._boxes, sg._cells
        is_free, inf = table.is_free, math.inf
        for ei in sg.out[node]:
            e = edges[ei]
            ek = e.kind
            if ek == "leave" and (node != start or out or not same_pose(
                    sg.parked_pose(ei), r.start_pose)):
                continue
            if ek == "park" and (e.v != goal.slot or (
                    goal.park_by is not None and (e.park_only or (node, e.v) not in goal.park_by))):
                continue
            if ek == "join":
                if not out:
                    push(e.v, lvl, t, out, sid, None)
                continue
            variants, longest = variants_kept.get((ei, lvl)) or sg.variants(ei, lvl)
            if not variants:
                continue
            cells = cells_kept.get(ei) or sg.edge_cells(ei, variants[0][1])
            # who is near the edge while any variant drives it (nobody: no exact test needed)
            near = table.nearby(cells, t, latest + longest, ignore=owner, memo=self.gathered)
            if near.ids:  # only those near what it sweeps (worked out only now: when needed)
                near = near.within(boxes.get((ei, lvl)) or sg.sweep_box(ei, lvl))
            kind = ek if ek in ("park", "leave") else "drive"
            for b, em in variants:
                after = -inf  # a parked vehicle must be able to stay for ever
                if ek == "park":
                    after = self.taken_until(ei) - em.duration
                if lvl > 0 or latest <= t:
                    if t <= after or (near.ids and not is_free(em.swept, offset=t, among=near)):
                        continue
                    departs: list[float] | tuple[float] = (t,)
                else:
                    hit = table.blocked(em.swept, t, latest, among=near) if near.ids else []
                    if after >= t:
                        hit = _merged_with(hit, (-inf, after))
                    departs = _departures(hit, t, latest, self.depart_after)
                for d in departs:
                    push(e.v, b, d + em.duration, False, sid,
                         (kind, t, d, em, node, lvl, b, ei, out))

    def taken_until(self, ei: int) -> float:
        """Till when [s] someone else's body meets the pose park edge ``ei`` parks on (asked
        of the table once per edge)."""
        taken = self.parked_until.get(ei)
        if taken is None:
            taken = self.parked_until[ei] = self.table.taken_until(
                self.sg.parked_body(ei), ignore=self.request.owner)
        return taken

    def moves_of(self, step: tuple | None) -> tuple[Move, ...]:
        """The moves of a step: from ``node`` (at ``lvl``, at ``t``) along edge ``ei`` from
        time ``d`` (waiting there before, from rest, when ``d`` is later), to level ``b``."""
        if step is None:
            return ()
        sg, r = self.sg, self.request
        kind, t, d, em, node, lvl, b, ei, out = step
        drive = Move(kind, d, d + em.duration, node, sg.edges[ei].v, lvl, b, ei, em.motion,
                     em.end)
        if d <= t:
            return (drive,)
        here = r.start_pose if node == r.start and r.start_pose is not None else sg.pose[node]
        wait = (Move("outside", t, d, node, node, 0, 0) if out else
                Move("wait", t, d, node, node, 0, 0, end_pose=here, steer=sg.steer[node]))
        return (wait, drive)

    def found(self, sid: int, expansions: int) -> Plan:
        """The plan that reaches state ``sid``."""
        moves: list[Move] = []
        while sid >= 0:
            sid, step = self.parent[sid]
            moves.extend(reversed(self.moves_of(step)))
        moves.reverse()
        return Plan(Status.FOUND, moves, expansions)


def _opener(search: _SpaceTimeSearch
            ) -> Callable[[int, int, float, bool, int, tuple | None], None]:
    """``push(node, lvl, t, out, par, step)`` for ``search``: open state ``(node, lvl, t,
    out)``, reached from state ``par`` by ``step`` (see :meth:`_SpaceTimeSearch.moves_of`);
    not where the goal is out of reach, nor passing a node soon after a state already
    expanded there (it would be dropped when popped: the times expanded at a node and level
    only grow).

    The search's most frequent call (millions in a busy run), so the state it touches is
    bound once, here; and it holds that state, not the search (which holds it): no cycle,
    so a search's states are let go as soon as it ends, not by the garbage collector."""
    passed, passing, h_of = search.passed, search.passing, search.h_of
    states, parent, heap, loss = search.states, search.parent, search.heap, search.loss
    h, rra, weight = search.h, search.rra, search.weight
    heappush, inf = heapq.heappush, math.inf

    def weighted(node: int) -> float:
        """The weight × ``node``'s heuristic (inf where the goal is out of reach), kept."""
        hv = h(node)
        if h is not rra and hv != inf and rra(node) == inf:
            hv = inf
        wh = h_of[node] = weight * hv
        return wh

    def push(node: int, lvl: int, t: float, out: bool, par: int, step: tuple | None) -> None:
        if lvl:
            last = passed.get((node, lvl))
            if last is not None and t - last < passing:
                return
        wh = h_of.get(node)
        if wh is None:
            wh = weighted(node)
        if wh == inf:
            return
        states.append((node, lvl, t, out))
        parent.append((par, step))
        heappush(heap, (t + (wh + loss[lvl]), -t, len(states) - 1))  # ties: deepest

    return push


def _free_till(in_way: list[tuple[float, float]], t: float) -> float:
    """Till when [s] a body standing from ``t`` [s] is free, given when it is in somebody's
    way (:meth:`~lotsim.traffic.reservation.ReservationTable.blocked` from any time up to
    ``t``): the start of the first stretch reaching past ``t`` — as from a query from
    ``t`` on, or, where the body is in the way at ``t`` already, a time before ``t`` both
    ways (a stretch that began before ``t`` may only have merged with earlier ones)."""
    return next((lo for lo, hi in in_way if hi >= t), math.inf)


def _departures(hit: list[tuple[float, float]], t: float, latest: float, depart_after: float
                ) -> list[float]:
    """The earliest time [s] of each stretch of ``[t, latest]`` (``latest`` itself
    excluded when it is after ``t``: the first instant the waiting body is in the way)
    outside the sorted, disjoint closed intervals ``hit``, departing ``depart_after`` [s]
    after each interval's end."""
    out = []
    d = t
    for lo, hi in hit:
        if hi < d:
            continue
        if lo > d:
            out.append(d)
        d = hi + depart_after
        if d >= latest:
            return out
    if d < latest or d == t:
        out.append(d)
    return out


def _merged_with(hit: list[tuple[float, float]], extra: tuple[float, float]
                 ) -> list[tuple[float, float]]:
    """``hit`` (sorted, disjoint closed intervals) with ``extra`` added."""
    out: list[tuple[float, float]] = []
    for lo, hi in sorted([*hit, extra]):
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(hi, out[-1][1]))
        else:
            out.append((lo, hi))
    return out
