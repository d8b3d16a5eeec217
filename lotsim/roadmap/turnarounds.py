"""Turnarounds: a multi-point turn from the end of a lane into the opposite lane of its aisle,
and which lanes of a lot end in a dead end that needs one (:func:`dead_end_turnarounds`).

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

Where every turnaround found this way lands past the last place a car can leave the
opposite lane, or begins before where cars arrive on the lane, one is also looked for by
multi-point search (:func:`~lotsim.roadmap.multipoint.plan_onto`). The turnarounds of every
two-way lane can be planned ahead on a background process (:func:`plan_turnarounds_ahead`)
while the lot's maneuvers are planned: the graph finds its dead ends' plans made.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from lotsim.core.geometry import FloatArray, Segment, advance, sample_segments
from lotsim.core.keys import key_of
from lotsim.core.outcome import Outcome, Status
from lotsim.core.workers import Background, cores
from lotsim.lot.build import obstacle_polygons
from lotsim.lot.clearance import Collider, first_blocked
from lotsim.lot.model import DesignVehicle, Lane, Lot
from lotsim.roadmap.lanes import EPS, along, two_way_lanes
from lotsim.roadmap.memo import RoadmapMemo, designs_of, types_key
from lotsim.roadmap.model import Turn
from lotsim.roadmap.multipoint import (
    closing_moves,
    plan_onto,
    segment_to_world,
    to_local,
    to_world,
)
from lotsim.roadmap.remembered import (
    MISSING,
    STORE,
    ReachingSearch,
    TurnaroundPlan,
    TurnaroundSuits,
    recall,
    recall_all,
    verified,
    watched,
    worked_out,
)
from lotsim.roadmap.settings import DEFAULTS, RoadmapSettings


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


def turnaround_collider(lot: Lot, design: DesignVehicle | None = None,
                        margin: float = DEFAULTS.turnarounds.margin
                        ) -> tuple[Collider, DesignVehicle]:
    """A checker for turnarounds on ``lot``: every slot, area and the ground it may drive on
    (no gates beyond aisle ends: a car turns back inside the lot), and ``design`` (default
    the lot's design vehicle) grown by ``margin`` [m]
    (:attr:`~lotsim.roadmap.settings.TurnaroundSettings.margin`)."""
    d = design or lot.design
    grown = dataclasses.replace(d, width=d.width + 2 * margin, front=d.front + margin,
                                rear=d.rear + margin)
    return (Collider(obstacle_polygons(lot.areas, lot.slots, lot.access_aisles), lot.ground,
                     edge=lot.edge), grown)


def turnaround_clear(t: Turnaround, collider: Collider, body: DesignVehicle, *,
                     step: float = DEFAULTS.turnarounds.step) -> bool:
    """Whether ``body`` (see :func:`turnaround_collider`) drives turnaround ``t`` clear of
    everything ``collider`` holds (hulls of footprints ``step`` apart [m],
    :attr:`~lotsim.roadmap.settings.TurnaroundSettings.step`)."""
    return not _blocked(np.zeros(3), list(t.segments), collider, body, step)  # world = local


def plan_turnaround(lane: Lane, back: Lane, collider: Collider, body: DesignVehicle,
                    radius: float, *, starts: tuple[float, ...] = (),
                    settings: RoadmapSettings = DEFAULTS) -> Outcome[Turnaround]:
    """A turnaround from the end of ``lane`` onto ``back`` (the opposite lane of the aisle,
    straight where it begins), for a car whose outline is ``body`` and whose tightest arc
    has ``radius`` [m], beginning
    :attr:`~lotsim.roadmap.settings.TurnaroundSettings.starts` (or ``starts``) metres before
    the lane's end: an :class:`~lotsim.core.outcome.Outcome` holding it, or why
    there is none (``infeasible``: the lanes do not allow one; ``no path``: none within the
    direction changes and clearance of ``settings.turnarounds``).

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
    >>> t = plan_turnaround(east, west, Collider([], street), car, 4.97).value
    >>> t.changes, t.lane_b, t.station_a
    (2, 'w', 30.0)
    """
    seg = back.segments[0]
    if seg.curvature != 0.0 or seg.sharpness != 0.0:
        return Outcome.failed(Status.INFEASIBLE, "the opposite lane bends where it begins")
    tune = settings.turnarounds
    frame = np.array(seg.start)  # local frame: the opposite lane runs along +x from 0
    found = []
    for back_off in starts or tune.starts:
        station = lane.length - back_off
        i, _ = lane.locate(max(station, 0.0))
        if station < 0 or lane.segments[i].curvature or lane.segments[i].sharpness:
            break  # the lane bends (or ends) there: start no further back
        start = to_local(frame, np.array(lane.pose_at(station)))
        if start[1] <= 0.0:
            return Outcome.failed(Status.INFEASIBLE, "the opposite lane is not on the left")
        start[2] = math.pi  # heading the other way, up to rounding
        best = _multipoint(frame, start, seg.length, collider, body, radius, settings)
        if best is not None:
            found.append((best[0], best[1], station, best[2]))
    if not found:
        return Outcome.failed(Status.NO_PATH, f"no multi-point turn with up to "
                                              f"{tune.max_changes} direction changes keeping "
                                              f"{tune.margin:g} m clear")
    _, _, station, local = min(found, key=lambda c: c[:3])
    segs = tuple(segment_to_world(frame, x) for x in local)
    return Outcome.of(Turnaround(lane.id, station, back.id, float(local[-1].end[0]), segs))


def plan_turnarounds(lane: Lane, back: Lane, collider: Collider, body: DesignVehicle,
                     radius: float, *, settings: RoadmapSettings = DEFAULTS
                     ) -> Outcome[list[Turnaround]]:
    """The best turnaround at the end of ``lane`` (:func:`plan_turnaround`) and, when that
    begins before the lane's last stretch, the best one that begins last: a car that parks
    or comes out of a slot past the first's start must still be able to turn. An
    :class:`~lotsim.core.outcome.Outcome` holding them, or the first's reason."""
    best = plan_turnaround(lane, back, collider, body, radius, settings=settings)
    if not best.found:
        return Outcome.failed(best.status, best.reason)
    out = [best.value]
    starts = settings.turnarounds.starts
    for k in range(len(starts)):
        if lane.length - starts[k] <= best.value.station_a + 1e-9:
            break
        last = plan_turnaround(lane, back, collider, body, radius, starts=starts[k : k + 1],
                               settings=settings)
        if last.found:
            out.append(last.value)
            break
    return Outcome.of(out)


def _multipoint(frame: FloatArray, start: FloatArray, lane_length: float, collider: Collider,
                body: DesignVehicle, radius: float, settings: RoadmapSettings
                ) -> tuple[int, float, list[Segment]] | None:
    """The fewest-changes, then shortest, turnaround from local ``start`` onto the line
    y = 0 heading +x (local frame ``frame``), as ``(changes, length, segments)``."""
    tune = settings.turnarounds
    kmax = 1.0 / radius
    pose, done = start, []  # strokes so far
    best = None
    for k in range(tune.max_changes + 1):
        gear = 1 if k % 2 == 0 else -1
        kappa = gear * kmax  # forward at left lock, reverse at right lock: turning left
        left = 2 * math.pi - pose[2]  # heading still to turn
        extent = _extent(frame, pose, gear, kappa, min(left, math.pi / 2) / kmax, collider, body,
                         tune.step)
        probes = np.unique(np.append(np.arange(0.0, extent, tune.probe), extent)) if gear > 0 \
            else np.array([extent])
        poses = advance(pose, gear * probes, kappa) if len(probes) else np.zeros((0, 3))
        changes = k + (1 if gear < 0 else 0)
        order = sorted(zip(poses, probes, strict=True), key=lambda c: c[1])
        options = [closing_moves(q, lane_length, radius, settings=settings.multipoint)
                   for q, _ in order]
        # the shortest clear closing from each pose is enough
        for (_, s), paths, clear in zip(order, options,
                                        _first_clear(frame, options, collider, body, tune.step),
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
        if left <= 1e-6 or extent < tune.min_stroke and k > 0:
            break
        if extent < tune.min_stroke:
            continue  # no room ahead at the lane's end: begin by reversing
        stroke = Segment(tuple(map(float, pose)), gear * float(extent), kappa)
        done.append(stroke)
        pose = np.array(stroke.end)
    return best


def _extent(frame: FloatArray, pose: FloatArray, gear: int, kappa: float, cap: float,
            collider: Collider, body: DesignVehicle, step: float) -> float:
    """How far a stroke from local ``pose`` runs clear, to ``step`` [m]."""
    n = max(1, math.ceil(cap / step))
    s = np.linspace(0.0, cap, n + 1)
    local = advance(pose, gear * s, kappa)
    bad = first_blocked(collider.blocked, body.footprints(to_world(frame, local)),
                        np.zeros(n, dtype=int))
    first = int(bad.argmax()) if bad.any() else n
    return float(s[first])


def _first_clear(frame: FloatArray, options: list[list[list[Segment]]], collider: Collider,
                 body: DesignVehicle, step: float = DEFAULTS.turnarounds.step
                 ) -> list[int | None]:
    """For each list of paths (local, in ``frame``) in ``options``, the index of the first
    not :func:`_blocked`, or None: the first paths of all checked in one batch, then the
    second paths of those whose first was blocked, and so on."""
    out: list[int | None] = [None] * len(options)
    todo = [i for i, paths in enumerate(options) if paths]
    k = 0
    while todo:
        hit = _blocked_each(frame, [options[i][k] for i in todo], collider, body, step)
        for i, blocked in zip(todo, hit, strict=True):
            if not blocked:
                out[i] = k
        k += 1
        todo = [i for i, blocked in zip(todo, hit, strict=True) if blocked and k < len(options[i])]
    return out


def _blocked_each(frame: FloatArray, paths: list[list[Segment]], collider: Collider,
                  body: DesignVehicle, step: float) -> list[bool]:
    """Whether each of ``paths`` (local, in ``frame``) touches anything: the hulls of its
    consecutive footprints ``step`` apart [m], a path a run of its own in
    :func:`~lotsim.lot.clearance.first_blocked` (so checking them together tests the same
    bodies as one by one); a path that is a point, its footprint."""
    sampled = [sample_segments(segs, step)[0] for segs in paths]
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
             body: DesignVehicle, step: float = DEFAULTS.turnarounds.step) -> bool:
    return _blocked_each(frame, [segs], collider, body, step)[0]


def dead_end_turnarounds(lot: Lot, turns: list[Turn], joins: list[tuple[str, str]],
                         exits: dict[str, float], designs: dict[str, DesignVehicle] | None,
                         stops: dict[str, float], multis: list[Turnaround], memo: RoadmapMemo,
                         *, settings: RoadmapSettings = DEFAULTS
                         ) -> tuple[list[tuple[Turnaround, frozenset | None]], list[str]]:
    """Turnarounds at the dead ends of two-way aisles, each with the vehicle types that can
    drive it (None: every type), and a note for each dead end where none fits (naming the
    types, when only some have none); each planned once per lot, lane and type.

    A lane that does not continue as another ends in a dead end when its last turn off it
    begins more than :attr:`~lotsim.roadmap.settings.TurnaroundSettings.dead_end` before
    its end and it leads to no exit past that turn,
    or when a car parks or unparks on it past its last turn and exit (``stops``: lane → the
    last such station; a corner bay): a car there could not get on otherwise. ``exits`` maps a
    lane to its last exit's station.

    With ``designs`` (vehicle type → its own outline and limits, for two types or more)
    turnarounds are planned for each type on its own — a small car turns round where the
    envelope of all the types, or a van that fits no bay, could not — and each is tagged
    with every type it suits: no tighter than its radius, clear for its body and margin.

    Where every turnaround found lands past the last place the opposite lane can be left
    (a turn off it, an exit, its continuation), or begins before where a car arrives on the
    lane (a turn or a multi-point junction turn, ``multis``, landing near its end, or a
    car unparking onto it: ``stops``), one is also looked for by multi-point search
    (:func:`_reaching_turnarounds`).
    """
    dead_end = settings.turnarounds.dead_end
    last = {lane.id: exits.get(lane.id, -math.inf) + dead_end for lane in lot.lanes}
    turned = {lane.id: exits.get(lane.id, -math.inf) for lane in lot.lanes}  # last way off
    for t in turns:
        last[t.lane_a] = max(last[t.lane_a], t.station_a)
        turned[t.lane_a] = max(turned[t.lane_a], t.station_a)
    joined = {a for a, _ in joins}
    ends = [(lane, back) for lane, back in two_way_lanes(lot)
            if lane.id not in joined and (last[lane.id] < lane.length - dead_end
                                          or stops.get(lane.id, -math.inf) > turned[lane.id])]
    # where a car arrives on each lane, and the last place it can leave each lane from
    arrive: dict[str, set[float]] = {}
    go_on = {lane.id: (lane.length if lane.id in joined else turned[lane.id])
             for lane in lot.lanes}
    for x in [*turns, *multis]:
        arrive.setdefault(x.lane_b, set()).add(x.station_b)
        go_on[x.lane_a] = max(go_on[x.lane_a], x.station_a)
    for lid, st in stops.items():  # a car unparks onto the lane there
        arrive.setdefault(lid, set()).add(st)
    key = (types_key(designs),
           tuple((lane.id, tuple(sorted(arrive.get(lane.id, ()))), go_on[back.id])
                 for lane, back in ends))
    cache = memo.check(lot, settings).turnarounds
    if key not in cache:
        per = designs or {"": lot.design}
        bodies = {name: turnaround_collider(lot, design, settings.turnarounds.margin)
                  for name, design in per.items()}
        tagged, why = _dead_end_plans(lot, per, bodies, ends, arrive, go_on, memo, settings)
        cache[key] = ([(t, None if len(n) == len(per) else frozenset(n))
                       for t, n in tagged.items()], _dead_end_notes(per, ends, tagged, why))
    found, notes = cache[key]
    return list(found), list(notes)


def _dead_end_plans(lot: Lot, per: dict[str, DesignVehicle], bodies: dict[str, tuple],
                    ends: list[tuple[Lane, Lane]], arrive: dict[str, set[float]],
                    go_on: dict[str, float], memo: RoadmapMemo, settings: RoadmapSettings
                    ) -> tuple[dict[Turnaround, set[str]], dict[tuple[str, str], str]]:
    """The turnarounds of :func:`dead_end_turnarounds`' ``ends``, each with the types of
    ``per`` it suits, and why a lane has none for a type ((lane, type) → reason): the
    searches not in ``memo`` (made by an earlier build of the lot's graph, or ahead) on both
    cores, each a function of its arguments alone, so the answers are the same."""
    tagged: dict[Turnaround, set[str]] = {}  # each with the types it was planned for
    why: dict[tuple[str, str], str] = {}  # (lane, type) → why it has none
    memo.take_ahead()
    planned = memo.plans  # (lane, design) → plan_turnarounds, and the reaching ones
    todo = {key: job for key, job in _turnaround_plans(per, bodies, ends).items()
            if key not in planned}
    pieces, jobs = _plan_keys(memo, todo), list(todo.values())
    planned.update(zip(todo, worked_out(
        memo, [pieces.get(key) for key in todo], [job[2] for job in jobs],
        lambda k, eye: plan_turnarounds(*jobs[k][:2], eye, *jobs[k][3:], settings=settings)),
        strict=True))
    reach = {}  # reach key → (lane, back, found, collider, body, radius, arrive, go on)

    def reach_key(lane: Lane, back: Lane, design: DesignVehicle) -> tuple:
        # what _reaching_turnarounds depends on: of the arrivals, only the last
        return (lane.id, design, max(arrive.get(lane.id, ()), default=-math.inf),
                go_on[back.id], "reach")

    for name, design in per.items():
        for lane, back in ends:
            t = planned[lane.id, design]
            if reach_key(lane, back, design) not in planned and fits_a_slot(lot, design):
                reach[reach_key(lane, back, design)] = (
                    lane, back, t.value or [], *bodies[name],
                    design.min_radius, arrive.get(lane.id, ()), go_on[back.id])
    planned.update(_reaching_all(reach, planned, memo, settings=settings))
    for name, design in per.items():
        for lane, back in ends:
            t = planned[lane.id, design]
            more = planned.get(reach_key(lane, back, design), [])
            if not t.found and not more:
                why[lane.id, name] = t.reason
            for x in (t.value or []) + more:
                tagged.setdefault(x, set()).add(name)
    # and every other type it suits, each check on the workers or taken from the memo's
    # store where what it read is unchanged
    checks = [(t, n) for t, names in tagged.items() for n in per if n not in names]
    base = memo.lot_key if memo.known is not None else b""
    fits = worked_out(memo, [key_of(TurnaroundSuits(base, t, per[n])) for t, n in checks],
                      [bodies[n][0] for _, n in checks],
                      lambda k, eye: suits(checks[k][0], per[checks[k][1]],
                                           (eye, bodies[checks[k][1]][1]),
                                           step=settings.turnarounds.step))
    for (t, n), ok in zip(checks, fits, strict=True):
        if ok:
            tagged[t].add(n)
    return tagged, why


def _dead_end_notes(per: dict[str, DesignVehicle], ends: list[tuple[Lane, Lane]],
                    tagged: dict[Turnaround, set[str]], why: dict[tuple[str, str], str]
                    ) -> list[str]:
    """A note for each dead end of ``ends`` with no turnaround for some type of ``per``."""
    notes = []
    for lane, _ in ends:
        lacking = [name for name in per if not any(
            t.lane_a == lane.id and name in names for t, names in tagged.items())]
        if lacking:
            x, y, _ = lane.pose_at(lane.length)
            reason = next((why[lane.id, n] for n in lacking if (lane.id, n) in why),
                          "none clear for it")
            some = f" (for {', '.join(lacking)})" if len(lacking) < len(per) else ""
            notes.append(f"dead end of lane {lane.id} at ({x:.1f}, {y:.1f}): no "
                         f"turnaround{some}: {reason}")
    return notes


def _turnaround_plans(per: dict[str, DesignVehicle], bodies: dict[str, tuple],
                      ends: list[tuple[Lane, Lane]]) -> dict[tuple[str, DesignVehicle], tuple]:
    """(lane id, design) → the arguments of :func:`plan_turnarounds` for each of ``ends``
    (lane, opposite lane) and each type's design in ``per`` (``bodies``: its
    :func:`turnaround_collider`)."""
    return {(lane.id, per[name]): (lane, back, *bodies[name], per[name].min_radius)
            for name in per for lane, back in ends}


def plan_turnarounds_ahead(memo: RoadmapMemo, vehicles=(), *,
                           settings: RoadmapSettings = DEFAULTS) -> Background:
    """Begin planning the turnaround at the end of every lane of a two-way aisle of the
    memo's lot (for ``vehicles``' designs, as :func:`~lotsim.roadmap.assemble.build_graph`
    will want them), on a background process that takes only CPU time nothing else wants
    (:class:`~lotsim.core.workers.Background`), and hand them to ``memo``: the lanes that
    turn out to be dead ends are then planned already when a graph of the lot is built with
    that memo. Each plan is a function of its arguments alone, so the graph is the same with
    it as without; one it has not finished is planned when needed, as without. Close it (or
    use it as a context manager) when the lot is built."""
    lot = memo.check(memo.lot, settings).lot
    per = designs_of(vehicles) or {"": lot.design}
    bodies = {name: turnaround_collider(lot, design, settings.turnarounds.margin)
              for name, design in per.items()}
    jobs = _turnaround_plans(per, bodies, two_way_lanes(lot))
    pieces = _plan_keys(memo, jobs)
    for key, args in jobs.items():  # those an earlier preparation planned, where unchanged
        if key not in memo.plans:
            got = recall(memo.known, pieces.get(key), args[2])
            if got is not MISSING:
                memo.plans[key] = got
                memo.recalled += 1
                if memo.reuse_check is not None:
                    memo.reuse_check.compare(STORE, pieces[key], got, plan_turnarounds(
                        *args[:2], args[2], *args[3:], settings=settings))
    keys = [key for key in jobs if key not in memo.plans]
    watch = memo.known is not None
    ahead = Background(lambda key: watched(
        lambda eye: plan_turnarounds(*jobs[key][:2], eye, *jobs[key][3:], settings=settings),
        jobs[key][2], watch), keys)
    memo.ahead = (keys, ahead, pieces)
    return ahead


def _plan_keys(memo: RoadmapMemo, jobs: dict) -> dict:
    """The piece key (:mod:`~lotsim.roadmap.remembered`) of each of :func:`_turnaround_plans`'
    ``jobs`` (empty when ``memo`` keeps none)."""
    if memo.known is None:
        return {}
    base = memo.lot_key
    return {key: key_of(TurnaroundPlan(base, lane.id, back.id, body, radius))
            for key, (lane, back, _, body, radius) in jobs.items()}


def fits_a_slot(lot: Lot, design: DesignVehicle) -> bool:
    """Whether a car of outline ``design`` fits some slot of ``lot`` (length and width)."""
    return any(design.front + design.rear <= s.length + EPS and design.width <= s.width + EPS
               for s in lot.slots)


def _reaching_all(jobs: dict, memo: dict, roads: RoadmapMemo | None = None, *,
                  settings: RoadmapSettings = DEFAULTS) -> dict:
    """:func:`_reaching_turnarounds` of each of ``jobs`` (key → its arguments), by key; its
    multi-point searches on the workers, each once: ``memo`` holds (and is given) those
    done before, by lane, design and arguments (an earlier build of the lot's graph made
    some). A job's second search waits for its first (whether it is made depends on what
    the first found), so the searches go in rounds, each round's on the workers (a round
    that would leave a core idle makes a second search that may be wanted too); each taken
    from ``roads``' store of an earlier preparation where what it read is the same
    (:mod:`~lotsim.roadmap.remembered`). ``settings``: the multi-point search's tuning and
    the turnarounds' starts."""
    base = roads.lot_key if roads is not None and roads.known is not None else b""
    wanted: dict[tuple, tuple] = {}  # the searches the jobs need that are not done
    spare: dict[tuple, tuple] = {}  # and those they may need next

    def onto(lane, back, starts, hi, collider, body, radius, *, maybe=False):
        key = (lane.id, back.id, body, radius, tuple(starts), hi, "onto")
        if key not in memo:
            (spare if maybe else wanted)[key] = (lane, back, starts, hi, collider, body,
                                                 radius)
            if not maybe:
                raise _Pending
        return memo.get(key)

    while True:
        wanted.clear()
        spare.clear()
        out = {}
        for key, job in jobs.items():
            with contextlib.suppress(_Pending):
                out[key] = _reaching_turnarounds(*job, onto=onto, settings=settings)
        if not wanted:
            return out
        pieces = {key: key_of(ReachingSearch(base, lane.id, back.id, tuple(starts), hi, body,
                                             radius))
                  for key, (lane, back, starts, hi, _, body, radius) in {**wanted,
                                                                         **spare}.items()}
        known = roads.known if roads is not None else None
        held = dict(zip(wanted, recall_all(known, [pieces[key] for key in wanted],
                                           [job[4] for job in wanted.values()]), strict=True))
        asked = list(wanted.values())
        verified(roads, [pieces[key] for key in held], list(held.values()),
                 lambda k, asked=asked: _reaching_onto(*asked[k][:4], asked[k][4],
                                                       *asked[k][5:], settings=settings))
        todo = {key: wanted[key] for key, got in held.items() if got is MISSING}
        # a round that leaves a core idle makes the searches the next may want too
        for key in list(spare)[:max(0, cores() - len(todo)) if todo else 0]:
            todo.setdefault(key, spare[key])
        memo.update((key, got) for key, got in held.items() if got is not MISSING)
        if roads is not None:
            roads.recalled += len(wanted) - len(held.keys() & todo.keys())
        jobs_now = list(todo.values())
        memo.update(zip(todo, worked_out(
            roads, [pieces[key] for key in todo], [job[4] for job in jobs_now],
            lambda k, eye, jobs=jobs_now: _reaching_onto(*jobs[k][:4], eye, *jobs[k][5:],
                                                         settings=settings)),
            strict=True))


class _Pending(Exception):
    """A search :func:`_reaching_all` has not made yet."""


def _reaching_onto(lane: Lane, back: Lane, starts: list[float], hi: float,
                   collider: Collider, body: DesignVehicle, radius: float, *,
                   settings: RoadmapSettings = DEFAULTS) -> Outcome[Turnaround]:
    """A turnaround from ``lane`` (from the first of ``starts`` that has one, [m]) onto the
    straight beginning ``back``, landing at or before ``hi`` along it
    (:func:`~lotsim.roadmap.multipoint.plan_onto` with ``settings.multipoint``), or why
    there is none."""
    seg = back.segments[0]
    got = plan_onto([lane.pose_at(st) for st in starts], seg.start, 0.0, hi, collider, body,
                    radius, settings=settings.multipoint)
    if not got.found:
        return Outcome.failed(got.status, got.reason)
    k, segs = got.value
    return Outcome.of(Turnaround(lane.id, starts[k], back.id, along(seg, segs[-1].end), segs))


def _reaching_turnarounds(lane: Lane, back: Lane, found: list[Turnaround],
                          collider: Collider, body: DesignVehicle, radius: float,
                          arrive, go_on: float, *, onto=_reaching_onto,
                          settings: RoadmapSettings = DEFAULTS) -> list[Turnaround]:
    """Turnarounds from ``lane`` onto ``back`` by multi-point search
    (:func:`~lotsim.roadmap.multipoint.plan_onto`) that land at or before ``go_on`` (the last
    station ``back`` can be left from), where those ``found`` leave a car stranded: one from
    as near the lane's end as there is room when every one found lands past ``go_on`` (or
    none was found), and one from the last station in ``arrive`` (where turns land on
    ``lane`` and cars unpark onto it) when that is past where every one found begins (a car
    arriving earlier drives on to it). ``onto`` makes each search
    (:func:`_reaching_onto`'s arguments and answer)."""
    seg = back.segments[0]
    if seg.curvature != 0.0 or seg.sharpness != 0.0 or go_on < 0:
        return []
    hi = min(go_on, seg.length)
    out: list[Turnaround] = []

    def plan(starts, **maybe) -> None:
        starts = [st for st in starts if st >= 0 and _on_straight(lane, st)]
        got = onto(lane, back, starts, hi, collider, body, radius, **maybe) if starts else None
        if got is not None and got.found and not maybe:
            out.append(got.value)

    last = max(arrive, default=-math.inf)
    if all(t.station_b > go_on + EPS for t in found):
        try:
            plan([lane.length - k for k in settings.turnarounds.starts])
        except _Pending:  # (:func:`_reaching_all`) and the next, if it may be wanted
            if last > max((t.station_a for t in found), default=-math.inf) + EPS:
                plan([last], maybe=True)
            raise
    # a car arriving past every start drives on to the last arrival and turns there
    latest = max((t.station_a for t in [*found, *out]), default=-math.inf)
    if last > latest + EPS:
        plan([last])
    return out


def _on_straight(lane: Lane, station: float) -> bool:
    seg = lane.segments[lane.locate(station)[0]]
    return seg.curvature == 0.0 and seg.sharpness == 0.0


def suits(t: Turnaround, design: DesignVehicle, checks: tuple[Collider, DesignVehicle], *,
          step: float = DEFAULTS.turnarounds.step) -> bool:
    """Whether a car of ``design`` can drive ``t``: no tighter than its radius, and clear
    (``checks``: collider and grown body, :func:`turnaround_collider`; footprints ``step``
    apart [m])."""
    bend = max(seg.max_curvature for seg in t.segments)
    return bend <= 1 / design.min_radius + 1e-9 and turnaround_clear(t, *checks, step=step)
