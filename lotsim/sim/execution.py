"""Driving a planned run through its disturbances: every car keeps the order in which the
plan has the cars pass each piece of the lot, so that a delay spreads but never turns
into a collision (the temporal plan graph of Hönig et al., "Multi-Agent Path Finding with
Kinematic Constraints", ICAPS 2016).

The plan is cut into *runs*: what a car drives from one standstill to the next (from its
gate, a wait, a cusp between maneuvers, its slot). A car waits only where it stands still,
so it never has to brake harder than its plan does; within a run it drives the plan's own
motion, slowed by its speed factor (:func:`~lotsim.vehicles.motion.slowed`: every limit
still kept). Each run's swept hulls, chunk by chunk, are those the reservation table held:
for every two chunks of two cars that meet in space, the plan passes one car first, and
the executed run keeps it so: the later car may enter its chunk only once the earlier has
left its own. The executed start of every run is the earliest that keeps every such order,
its car's own order, its plan's start (a car never sets off before its plan says) and its
disturbances: a longest-path problem over the runs (:func:`schedule`).

Where two runs pass each other both ways (one car ahead of the other at one place and
behind it at another, within the same two runs), their timing is tied: when their speed
factors differ the faster is slowed to the slower's for those runs, and a stall that would
break the tie takes effect at the stalled car's next standstill instead (both counted in
the execution's record).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import shapely

from lotsim.sim import rerouting
from lotsim.sim.repairs import LotChanges
from lotsim.sim.results import RunResult, VehicleRun
from lotsim.sim.standstills import Driven, Run, runs_of, stop_after, stretch
from lotsim.traffic.disturbances import Disturbances, Drawn, Stall, draw
from lotsim.traffic.plans import Move
from lotsim.traffic.searchgraph import SearchGraphMemo, search_graph
from lotsim.traffic.swept import standing_body
from lotsim.vehicles.motion import slowed

EPS = 1e-9
"""Times closer than this are the same instant [s]."""
AFTER = 1e-3
"""A closure, or a stranger's car in a bay, that waits for a late car begins this long after
that car has left [s]: after its last sample there, which is written to the microsecond."""
MAX_ROUNDS = 10_000
"""Most times :func:`schedule` slows a pair of tied runs or moves a stall before it gives
up (it never has on the shipped scenarios)."""


@dataclass
class Execution:
    """How a run was driven: the disturbances drawn and what they did.

    Attributes
    ----------
    spec : Disturbances
    seed : int
        Of the generator the random parts were drawn from.
    speed : dict of str to float
        Each car's speed factor.
    late : list of dict
        Each late start: ``car``, ``t`` (when it set off) and ``by`` [s].
    stalls : list of dict
        Each stall honoured: ``car``, ``t0``, ``t1`` (the car stood still throughout) and
        ``at`` (when it was to happen).
    repaired : int
        Cars planned again from where they stood, their wait for the plan's order grown
        past :attr:`~lotsim.traffic.disturbances.Disturbances.repair_after` (each a
        repair in the result's ``replans``).
    moved : int
        Stalls taken at the car's next standstill, since the one they fell at tied it to a
        car passing it both ways.
    dropped : int
        Stalls that fell where a car had no standstill left on the lanes.
    slowed : int
        Runs slowed below their car's factor to keep a tie with a slower car.
    waited : float
        Seconds cars stood for the order of the plan beyond their plans' waits, in all.
    planned : dict
        The plan's :meth:`~lotsim.sim.results.RunResult.trip_figures`, to hold the
        executed run's against.
    """

    spec: Disturbances
    seed: int
    speed: dict[str, float]
    late: list[dict]
    stalls: list[dict]
    repaired: int = 0
    moved: int = 0
    dropped: int = 0
    slowed: int = 0
    waited: float = 0.0
    planned: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """As ``result.json``'s ``disturbances`` holds it (``docs/result.md``)."""
        return {"settings": self.spec.as_dict(), "seed": self.seed,
                "speed": {k: round(v, 6) for k, v in self.speed.items()},
                "late": self.late, "stalls": self.stalls, "repaired": self.repaired,
                "stalls_moved": self.moved, "stalls_dropped": self.dropped,
                "runs_slowed": self.slowed, "waited": round(self.waited, 4),
                "planned": {k: round(v, 4) for k, v in self.planned.items()}}


def execute(rr: RunResult, spec: Disturbances, *, memo: SearchGraphMemo | None = None
            ) -> RunResult:
    """The run ``rr`` planned, driven through ``spec``'s disturbances: a new
    :class:`RunResult` whose vehicles' moves are those executed, with
    :attr:`RunResult.execution` saying what was drawn and what it did.

    ``memo`` holds the lot's search graphs (a prepared lot's ``search_graphs``): the
    swept hulls of the plan's moves are read from them.

    Examples
    --------
    >>> import lotsim
    >>> prepared = lotsim.prepare(lotsim.EXAMPLE)
    >>> plan = lotsim.run(prepared)
    >>> late = execute(plan, Disturbances(late_probability=1.0, late_max=4.0),
    ...                memo=prepared.search_graphs)
    >>> lotsim.check(late).ok, late.metrics()["makespan"] > plan.metrics()["makespan"]
    (True, True)
    """
    seed = rr.seed if spec.seed is None else spec.seed
    rng = np.random.default_rng(seed)
    cars = rr.vehicles
    runs = [runs_of(v, c) for c, v in enumerate(cars)]
    spans = []
    for v, rs in zip(cars, runs, strict=True):
        ends = [r.t1 for r in rs if not r.in_slot] or [math.nan]
        spans.append((v.id, len(rs), rs[0].t0 if rs else math.nan, max(ends)))
    drawn = draw(spec, spans, rng)
    _apply(drawn, cars, runs)
    _stalled_live(rr, runs)
    rec = Execution(spec, seed, drawn.speed, [], [], planned=rr.trip_figures())
    driven = _drive(rr, cars, runs, rr.lot_changes, memo, rec)
    replans = [] if rr.lot_changes is None else list(rr.lot_changes.replans)
    if spec.repair_after is not None:
        driven = rerouting.repair_waits(
            driven, spec.repair_after, replans,
            lambda plan, rs, before, c: _drive(rr, plan, rs, before.changes, memo, rec,
                                               before, c),
            rerouting.Context(rr, memo, drawn.speed))
        rec.repaired = driven.repaired
        rec.dropped += driven.stalls_dropped
    for v, rs in zip(driven.executed, driven.runs, strict=True):
        for r in rs:
            s = driven.starts[id(r)]
            if r.late_by > 0:
                rec.late.append({"car": v.id, "t": round(s, 6), "by": round(r.late_by, 6)})
            if r.stalls:  # from where it came to rest, one stall after the other
                before = rs[r.index - 1]
                t = driven.starts[id(before)] + before.duration
                for st in r.stalls:
                    rec.stalls.append({"car": v.id, "t0": round(t, 6),
                                       "t1": round(t + st.duration, 6), "at": st.at})
                    t += st.duration
    rec.waited = sum(_stood(v) for v in driven.executed) - sum(_stood(v) for v in cars)
    changes = driven.changes
    if changes is None and len(replans):
        changes = LotChanges([], [], [])
    if changes is not None:
        changes = replace(changes, replans=sorted(replans, key=lambda p: p.t))
    # the searches of the repairs are counted in their cars' planning, and the run's
    repairing = (sum(v.planning_time for v in driven.executed)
                 - sum(v.planning_time for v in cars))
    out = RunResult(rr.scenario, rr.lot_graph, rr.settings, rr.seed, driven.executed,
                    rr.planning_time + repairing, ordering=rr.ordering,
                    motion_time=rr.motion_time, lot_changes=changes)
    out.execution = rec
    return out


def _drive(rr: RunResult, cars: list[VehicleRun], runs: list[list[Run]],
           changes: LotChanges | None, memo: SearchGraphMemo | None, rec: Execution,
           before: Driven | None = None, changed: int = -1) -> Driven:
    """Drive ``cars``' plans, cut into ``runs``, keeping every order they pass the lot's
    pieces in. ``before``: the drive whose executed cars are these, but for car
    ``changed``'s (planned again): the chunks of the others that meet are those that met
    there (the same hulls, at other times), and only the changed car's are looked for."""
    flat = [r for rs in runs for r in rs]
    chunks = _chunks(rr, cars, runs, memo)
    tree = shapely.STRtree(chunks.geoms)
    a, b = (_meeting(chunks, tree) if before is None or before.chunks is None
            else _meeting_again(chunks, tree, before.chunks, before.meets, changed))
    src, dst, alpha, beta = _orders(chunks, a, b)
    starts = schedule(flat, src, dst, alpha, beta, runs, rec)
    executed = [retimed(v, rs, starts) for v, rs in zip(cars, runs, strict=True)]
    met = (None if changes is None
           else _changes_driven(changes, chunks, tree, flat, starts, cars))
    return Driven(cars, runs, starts, executed, met, chunks=chunks, meets=(a, b))


def _changes_driven(changes: LotChanges, ch: _Chunks, tree: shapely.STRtree, flat: list[Run],
                    starts: dict[int, float], cars: list[VehicleRun]) -> LotChanges:
    """``changes`` as a run driven late meets them: a closure begins, and a car the plan
    does not know parks in a bay, once every car planned past that ground before it has
    passed (cars already in a closed aisle go on, as planned)."""
    def passed(area, t: float, exempt: set[str]) -> float:
        idx = tree.query(area, predicate="intersects")
        idx = idx[(ch.t1[idx] <= t + EPS)]
        out = t
        for k in idx:
            if cars[ch.car[k]].id in exempt:
                continue
            r = flat[ch.run[k]]
            left = starts[id(r)] + (ch.t1[k] - r.t0) / r.factor
            if left > t:  # it begins once that car is gone, a millisecond after its sample
                out = max(out, left + AFTER)
        return out

    closures = [replace(c, t0=min(c.t1, passed(c.area, c.t0, set(c.inside))))
                for c in changes.closures]
    taken = [r if r.body is None else replace(r, t=passed(r.body, r.bay.at, set()))
             for r in changes.taken]
    return LotChanges(closures, taken, list(changes.replans))


def _apply(drawn: Drawn, cars: list[VehicleRun], runs: list[list[Run]]) -> None:
    """Give each run its car's speed factor, its late start and the stalls that fall at
    its start."""
    index = {v.id: c for c, v in enumerate(cars)}
    for v, rs in zip(cars, runs, strict=True):
        lates = drawn.late.get(v.id, [])
        for r, late in zip(rs, lates, strict=False):
            r.factor = drawn.speed.get(v.id, 1.0)
            r.late = r.late_by = late
    for st in drawn.stalls:
        c = index.get(st.car)
        if c is None:
            continue
        r = stop_after(runs[c], st.at)
        if r is not None:
            r.stall += st.duration
            r.stalls.append(st)


def _stalled_live(rr: RunResult, runs: list[list[Run]]) -> None:
    """The stalls of a stepped run (:meth:`lotsim.Live.stall`, planned as waits) kept as
    stalls when it is driven: the run after each sets off no sooner than the stall's length
    after the car came to rest there, however late it came."""
    index = {v.id: c for c, v in enumerate(rr.vehicles)}
    for st in () if rr.lot_changes is None else rr.lot_changes.stalls:
        if st.refused:
            continue
        rs = runs[index[st.car]]
        r = next((r for r in rs[1:] if r.t0 >= st.t1 - EPS), None)
        if r is not None:
            r.stall += st.duration
            r.stalls.append(Stall(st.car, st.at, st.duration))


@dataclass
class _Chunks:
    t0: np.ndarray
    t1: np.ndarray
    run: np.ndarray  # index into the flat run list
    car: np.ndarray
    geoms: np.ndarray
    run_t0: np.ndarray  # by flat run index


def _chunks(rr: RunResult, cars: list[VehicleRun], runs: list[list[Run]],
            memo: SearchGraphMemo | None) -> _Chunks:
    """Every chunk the plan's moves sweep, in plan time, with its run and car (a move
    driven slower than its edge's motion, in a plan driven before, sweeps the same hulls
    over times stretched alike)."""
    lg = rr.lot_graph
    graphs = {}
    t0, t1, run, car, geoms = [], [], [], [], []
    flat_index = 0
    run_t0 = []
    for c, (v, rs) in enumerate(zip(cars, runs, strict=True)):
        name = v.vehicle.name
        if name not in graphs and rs:
            graphs[name] = search_graph(lg, v.vehicle, memo, settings=rr.settings.search)
        for r in rs:
            run_t0.append(r.t0)
            for m in v.moves[r.first:r.last + 1]:
                if m.motion is None:  # waiting inside its gate
                    rows = [((0.0, m.t1 - m.t0), standing_body(v.vehicle, m.end_pose))]
                else:
                    em = graphs[name].motion(m.edge, m.level_from, m.level_to)
                    sw = em.swept
                    k = stretch(em, m)
                    if k == 1.0:  # driven as its edge's motion
                        rows = zip(sw.rows, sw.geoms, strict=True)
                    else:
                        rows = (((a * k, b * k), g)
                                for (a, b, *_), g in zip(sw.rows, sw.geoms, strict=True))
                for (a, b, *_), g in rows:
                    t0.append(m.t0 + a)
                    t1.append(m.t0 + b)
                    run.append(flat_index)
                    car.append(c)
                    geoms.append(g)
            flat_index += 1
    arr = np.empty(len(geoms), dtype=object)
    arr[:] = geoms
    return _Chunks(np.array(t0), np.array(t1), np.array(run, dtype=int),
                   np.array(car, dtype=int), arr, np.array(run_t0))


def _meeting(ch: _Chunks, tree: shapely.STRtree) -> tuple[np.ndarray, np.ndarray]:
    """Every two chunks of two cars that meet, as index arrays."""
    if not len(ch.geoms):
        z = np.zeros(0, dtype=int)
        return z, z
    # boxes first (cheap), then the exact test only for chunks of two cars: most boxes that
    # meet are a car's own chunks one after another
    a, b = tree.query(ch.geoms)
    keep = (a < b) & (ch.car[a] != ch.car[b])
    a, b = a[keep], b[keep]
    shapely.prepare(ch.geoms)  # each chunk is tested against many
    meet = shapely.intersects(ch.geoms[a], ch.geoms[b])
    return a[meet], b[meet]


def _meeting_again(ch: _Chunks, tree: shapely.STRtree, old: _Chunks,
                   meets: tuple[np.ndarray, np.ndarray], changed: int
                   ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_meeting` of ``ch``, whose cars' chunks are ``old``'s but for car
    ``changed``'s: the others' pairs carried over, the changed car's looked for."""
    n_cars = int(max(ch.car.max(initial=-1), old.car.max(initial=-1))) + 1
    count_new = np.bincount(ch.car, minlength=n_cars)
    count_old = np.bincount(old.car, minlength=n_cars)
    same = np.ones(n_cars, dtype=bool)
    same[changed] = False
    if not np.array_equal(count_new[same], count_old[same]):
        return _meeting(ch, tree)  # (never so far: a car's chunks are its plan's)
    off_new = np.concatenate([[0], np.cumsum(count_new)[:-1]])
    off_old = np.concatenate([[0], np.cumsum(count_old)[:-1]])
    a, b = meets
    keep = (old.car[a] != changed) & (old.car[b] != changed)
    a, b = a[keep], b[keep]
    a = a - off_old[old.car[a]] + off_new[old.car[a]]
    b = b - off_old[old.car[b]] + off_new[old.car[b]]
    mine = np.flatnonzero(ch.car == changed)
    if len(mine):
        i, j = tree.query(ch.geoms[mine])
        i = mine[i]
        other = ch.car[j] != changed
        i, j = i[other], j[other]
        shapely.prepare(ch.geoms)
        meet = shapely.intersects(ch.geoms[i], ch.geoms[j])
        a = np.concatenate([a, i[meet]])
        b = np.concatenate([b, j[meet]])
    return a, b


def _orders(ch: _Chunks, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, ...]:
    """For every two chunks ``a``, ``b`` of two cars that meet: the run passing first
    (``src``), the one passing after (``dst``), how far into its run the first leaves its
    chunk (``alpha``) and how far into its run the second enters its own (``beta``) [s]."""
    if not len(a):
        z = np.zeros(0)
        return z.astype(int), z.astype(int), z, z
    a_first = ch.t1[a] <= ch.t0[b] + EPS
    b_first = ch.t1[b] <= ch.t0[a] + EPS
    # no two chunks that meet share a moment (the reservation table saw to it); were some
    # to, the one that starts first goes first
    a_first |= ~a_first & ~b_first & (ch.t0[a] <= ch.t0[b])
    first = np.where(a_first, a, b)
    then = np.where(a_first, b, a)
    src, dst = ch.run[first], ch.run[then]
    alpha = ch.t1[first] - ch.run_t0[src]
    beta = ch.t0[then] - ch.run_t0[dst]
    return src, dst, alpha, beta


def schedule(flat: list[Run], src: np.ndarray, dst: np.ndarray, alpha: np.ndarray,
             beta: np.ndarray, runs: list[list[Run]], rec: Execution) -> dict[int, float]:
    """The executed start of every run (by ``id`` of the run) [s]: the earliest that keeps
    every order of the plan (a chunk of ``dst`` entered only after the chunk of ``src``
    was left: ``S_dst + beta / f_dst ≥ S_src + alpha / f_src``), its car's own order (a run
    after the one before, and the stall at its start), its plan's start and its late start.
    Tied runs are slowed to the slower's factor, and stalls that break a tie moved, as the
    module says."""
    n = len(flat)
    pos = {id(r): k for k, r in enumerate(flat)}
    key = src.astype(np.int64) * max(n, 1) + dst
    order = np.argsort(key, kind="stable")
    src, dst, alpha, beta = src[order], dst[order], alpha[order], beta[order]
    keys, cut = np.unique(key[order], return_index=True)
    pairs = np.stack([keys // max(n, 1), keys % max(n, 1)], axis=1).astype(int)
    succ: list[list[int]] = [[] for _ in range(n)]
    for e, (s, _) in enumerate(pairs):
        succ[s].append(e)
    prev = [pos[id(runs[r.car][r.index - 1])] if r.index else -1 for r in flat]
    nxt = [-1] * n
    for k, p in enumerate(prev):
        if p >= 0:
            nxt[p] = k
    for _ in range(MAX_ROUNDS):
        f = np.array([r.factor for r in flat])
        if len(src):
            w_all = alpha / f[src] - beta / f[dst]
            weight = np.maximum.reduceat(w_all, cut)
        else:
            weight = np.zeros(0)
        start, cycle = _longest(flat, pairs, weight, succ, nxt)
        if cycle is None:
            return {id(r): start[k] for k, r in enumerate(flat)}
        _untie(flat, cycle, runs, rec)
    raise RuntimeError("the runs' orders could not be kept: too many ties to resolve")


def _longest(flat: list[Run], pairs: np.ndarray, weight: np.ndarray, succ: list[list[int]],
             nxt: list[int]) -> tuple[list[float], list[int] | None]:
    """Earliest starts by label correcting from every run's lower bound (its plan's start
    and late start), in plan order; a cycle of runs that gains time (no schedule keeps it)
    as the runs on it, found by the parents of the last run to gain too often."""
    n = len(flat)
    start = [r.t0 + r.late for r in flat]
    parent = [-1] * n
    gains = [0] * n
    work = sorted(range(n), key=lambda k: (flat[k].t0, k))
    queued = [True] * n
    head = 0
    while head < len(work):
        u = work[head]
        head += 1
        queued[u] = False
        outs = [(int(pairs[e][1]), float(weight[e])) for e in succ[u]]
        if nxt[u] >= 0:
            outs.append((nxt[u], flat[u].duration + flat[nxt[u]].stall))
        for v, w in outs:
            t = start[u] + w
            if t > start[v] + EPS:  # (a late start is only a lower bound: start[v] holds it)
                start[v] = t
                parent[v] = u
                gains[v] += 1
                if gains[v] > n + 1:
                    return start, _cycle(parent, v)
                if not queued[v]:
                    queued[v] = True
                    work.append(v)
    return start, None


def _cycle(parent: list[int], v: int) -> list[int]:
    """The cycle of the parent pointers that ``v`` leads into."""
    seen: dict[int, int] = {}
    k = 0
    while v >= 0 and v not in seen:
        seen[v] = k
        v = parent[v]
        k += 1
    if v < 0:
        return []
    out = [v]
    u = parent[v]
    while u != v:
        out.append(u)
        u = parent[u]
    return out


def _untie(flat: list[Run], cycle: list[int], runs: list[list[Run]], rec: Execution) -> None:
    """Resolve a cycle that gains time: slow its runs to the slowest of them, or, when
    they are all as slow, move the stall on it to its car's next standstill."""
    if not cycle:
        raise RuntimeError("a run's order could not be kept")
    on = [flat[k] for k in cycle]
    slowest = min(r.factor for r in on)
    faster = [r for r in on if r.factor > slowest + 1e-12]
    if faster:
        for r in faster:
            r.factor = slowest
        rec.slowed += len(faster)
        return
    stalled = next((r for r in on if r.stall > 0), None)
    if stalled is None:
        raise RuntimeError("a run's order could not be kept")
    rs = runs[stalled.car]
    later = next((r for r in rs[stalled.index + 1:] if not r.in_slot), None)
    if later is None:
        rec.dropped += len(stalled.stalls)
    else:
        later.stall += stalled.stall
        later.stalls.extend(stalled.stalls)
        rec.moved += len(stalled.stalls)
    stalled.stall, stalled.stalls = 0.0, []


def retimed(v: VehicleRun, rs: list[Run], starts: dict[int, float]) -> VehicleRun:
    """``v`` with its moves driven from the executed ``starts`` of its runs (by ``id`` of
    the run): each run's moves slowed by its factor and shifted to its start; the car
    stands still (waiting, parked, or outside its gate before it first sets off) from the
    end of one run to the start of the next."""
    if not rs:
        return replace(v, moves=list(v.moves))
    moves: list[Move] = []
    out = replace(v, moves=moves)
    ends: list[float] = []
    for r in rs:
        s, f = starts[id(r)], r.factor
        if r.index == 0:
            head = [m for m in v.moves[:r.first] if m.kind == "outside"]
            if head or s > r.t0 + EPS:
                t_from = head[0].t0 if head else r.t0
                m0 = v.moves[r.first]
                moves.append(Move("outside", t_from, s, m0.node_from, m0.node_from, 0, 0))
        else:
            moves.extend(_standing(v, v.moves[rs[r.index - 1].last + 1:r.first], moves[-1], s))
        for m in v.moves[r.first:r.last + 1]:
            moves.append(replace(m, t0=s + (m.t0 - r.t0) / f, t1=s + (m.t1 - r.t0) / f,
                                 motion=None if m.motion is None else slowed(m.motion, f)))
        ends.append(moves[-1].t1)
    # what came after the last run in the plan (a car that stays holds its pose)
    tail = v.moves[rs[-1].last + 1:]
    if tail:
        last = moves[-1]
        for m in tail:
            moves.append(replace(m, t0=last.t1, t1=last.t1 + (m.t1 - m.t0)))
            last = moves[-1]
    park = next((k for k, m in enumerate(moves) if m.kind == "park"), None)
    if park is not None:
        out.parked_at = moves[park].t1
    leave = next((m for m in moves if m.kind == "leave"), None)
    if leave is not None:
        out.depart_at = leave.t0
    if v.left_at is not None:
        out.left_at = moves[-1].t1
    return out


def _standing(v: VehicleRun, between: list[Move], last: Move, until: float) -> list[Move]:
    """The car standing from the end of its executed move ``last`` until ``until`` [s]:
    the plan's standing moves ``between`` kept at their times where the car is there by
    then, the last stretched to ``until``; a wait when the plan had none."""
    out = []
    for m in between:
        t0, t1 = max(m.t0, last.t1), min(max(m.t1, last.t1), until)
        if t1 > t0 + EPS:
            out.append(replace(m, t0=t0, t1=t1))
    if out:
        out[0] = replace(out[0], t0=last.t1)
        out[-1] = replace(out[-1], t1=until)
    elif until > last.t1 + EPS:
        out.append(Move("wait", last.t1, until, last.node_to, last.node_to, 0, 0,
                        end_pose=last.end_pose, steer=_end_steer(last, v)))
    return out


def _end_steer(m: Move, v: VehicleRun) -> float:
    """The road-wheel angle ``m`` ends with [rad]."""
    if m.motion is None:
        return m.steer
    _, _, steer, _ = m.motion.at(np.array([m.motion.duration]), wheelbase=v.vehicle.wheelbase)
    return float(steer[0])


def _stood(v: VehicleRun) -> float:
    """Seconds ``v`` stood waiting or outside its gate."""
    return sum(m.t1 - m.t0 for m in v.moves if m.kind in ("wait", "outside"))
