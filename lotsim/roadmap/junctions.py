"""Junction turns: continuous-curvature turns (clothoid, arc, clothoid) from one aisle's
lane into another's where the aisles meet, sized for a design speed, swept clear with each
vehicle type they are for; where none between the lanes is clear, one through the
junction's area (:mod:`lotsim.roadmap.area_turns`) or through a short stretch of lane
(:mod:`lotsim.roadmap.through`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from lotsim.core.geometry import Segment, cc_turn, sample_segments, wrap_angle
from lotsim.core.keys import key_of
from lotsim.core.outcome import Outcome, Status
from lotsim.core.workers import fork_map
from lotsim.lot.clearance import NOTHING_READ, Collider, Watched
from lotsim.lot.model import DesignVehicle, Lot, unit
from lotsim.roadmap.area_turns import area_turns, candidates_shape
from lotsim.roadmap.lanes import EPS, portal_station, straights
from lotsim.roadmap.memo import RoadmapMemo, types_key
from lotsim.roadmap.model import Turn
from lotsim.roadmap.remembered import (
    MISSING,
    JunctionTurns,
    ThroughTurns,
    TurnSuits,
    keep,
    recall,
    verified,
    worked_out,
)
from lotsim.roadmap.settings import DEFAULTS, RoadmapSettings
from lotsim.roadmap.through import through_chains, through_turn


def _turn_designs(design, lot_speed: float, speeds: tuple[float, ...]
                  ) -> list[tuple[float, float]]:
    """(design speed [m/s], arc radius [m]) of the junction turns to try, fastest first,
    tightest first at each speed: the tightest arc the speed allows, and twice and three
    times the design radius (a wide arc clears a corner that a tight one's body sweeps
    over). ``speeds``: the design speeds, fastest first; those above ``lot_speed`` are
    left out but for the slowest."""
    out = []
    for speed in speeds:
        if speed > lot_speed + 1e-9 and speed != speeds[-1]:
            continue
        least = max(design.min_radius, speed * speed / design.max_lateral_accel)
        for r in sorted({least, 2 * design.min_radius, 3 * design.min_radius}):
            if r >= least:
                out.append((speed, r))
    return out


def lane_crossing(pa: Segment, pb: Segment, aisle_a, aisle_b, reach: float
            ) -> tuple[float, float, float, np.ndarray] | None:
    """Where straights ``pa`` and ``pb`` (of lanes of two aisles) meet, if they cross at
    10° to 170° within ``reach`` of both aisles' centre lines: the turn's deflection [rad],
    the distances along each to the crossing [m], and the crossing point."""
    ta, tb = pa.start[2], pb.start[2]
    delta = float(wrap_angle(tb - ta))
    if abs(math.sin(delta)) < math.sin(math.radians(10)) or abs(delta) > math.radians(170):
        return None
    ua, ub = unit(ta), unit(tb)
    pa_xy, pb_xy = np.array(pa.start[:2]), np.array(pb.start[:2])
    # pa_xy + t ua = pb_xy + s ub
    t, s = np.linalg.solve(np.column_stack([ua, -ub]), pb_xy - pa_xy)
    x = pa_xy + t * ua
    pt = shapely.Point(x)
    if aisle_a.line.distance(pt) > reach or aisle_b.line.distance(pt) > reach:
        return None
    return delta, float(t), float(s), x


def _fillet_between(a, sa0, pa, b, sb0, pb, aisle_a, aisle_b, reach, design,
                    collider: Collider, lot_speed: float, step: float,
                    gates: tuple[tuple[float, ...], tuple[float, ...]] = ((), ()), *,
                    settings: RoadmapSettings = DEFAULTS) -> Outcome[list[Turn]]:
    """The turns from straight ``pa`` of lane ``a`` into straight ``pb`` of lane ``b``, each
    swept with footprints ``step`` apart [m] (the lot's :attr:`LotSettings.sweep
    <lotsim.lot.settings.LotSettings.sweep>`): the
    fastest that is clear and, when it is another, the tightest that is clear (the shortest
    tangent: it starts later and ends sooner, so it can reach a node the wide one passes
    by); and for each station of ``gates`` — entrances on ``a``, exits on ``b`` — the
    fastest clear turn that starts after that entrance or ends before that exit, when the
    fastest does not: a car from the entrance can take it, a car can reach the exit by it
    (the fastest may start behind the one or end past the other, and the tightest is
    driven at a crawl).

    Returns an :class:`~lotsim.core.outcome.Outcome`: the turns; ``infeasible`` when the
    two straights do not meet; ``no path`` when they meet but no turn between them has
    room or is clear, with the reason (then a turn through the junction's area is
    searched: :func:`_wide_between`).
    """
    corner = lane_crossing(pa, pb, aisle_a, aisle_b, reach)
    if corner is None:
        return Outcome.failed(Status.INFEASIBLE, "the lanes' straights do not meet")
    delta, t, s, x = corner
    reason = None
    fits = []  # (speed, radius, tangent) of the turns with room on both lanes
    for speed, r in _turn_designs(design, lot_speed, settings.turns.speeds):
        _, tangent = cc_turn(delta, 1 / r, design.sharpness(speed))
        da, db = t - tangent, s + tangent  # distances into pa and pb
        if -EPS <= da <= pa.length + EPS and -EPS <= db <= pb.length + EPS:
            fits.append((speed, r, tangent))
        else:
            reason = reason or f"no room for a turn at {speed * 3.6:.1f} km/h"
    clear: dict[int, Turn | None] = {}

    def sweep(k: int) -> Turn | None:
        """The k-th fitting turn if its swept body touches nothing (each swept once)."""
        nonlocal reason
        if k not in clear:
            speed, r, tangent = fits[k]
            da = t - tangent
            start = tuple(float(v) for v in pa.poses_at(min(max(da, 0.0), pa.length))[0])
            segs, _ = cc_turn(delta, 1 / r, design.sharpness(speed), start)
            hit = collider.sweep_hit(design.footprints(sample_segments(segs, step)[0]))
            if hit is not None:
                reason = f"touches {hit.what}"
            clear[k] = None if hit is not None else Turn(a.id, sa0 + da, b.id,
                                                          sb0 + s + tangent, tuple(segs))
        return clear[k]

    # the fastest clear turn, and the tightest (shortest tangent: starts latest, ends soonest)
    first = next((k for k in range(len(fits)) if sweep(k) is not None), None)
    tight = sorted(range(len(fits)), key=lambda k: fits[k][2])
    picked = [k for k in (first, next((k for k in tight if sweep(k) is not None), None))
              if k is not None]
    # and the fastest clear turn each gate's cars can use, when the fastest is not
    entrances, exits = gates
    for usable in ([lambda k, g=g: sa0 + t - fits[k][2] >= g - EPS for g in entrances]
                   + [lambda k, g=g: sb0 + s + fits[k][2] <= g + EPS for g in exits]):
        if first is not None and usable(first):
            continue
        picked.append(next((k for k in range(len(fits)) if usable(k) and sweep(k) is not None),
                           None))
    found = [clear[k] for k in dict.fromkeys(k for k in picked if k is not None)]
    if found:
        return Outcome.of(found)
    return Outcome.failed(Status.NO_PATH, reason or "no turn design")


def _wide_between(a, sa0, pa, b, sb0, pb, aisle_a, aisle_b, reach, design,
                  lot_speed: float, reason: str, settings: RoadmapSettings) -> _Wide:
    """The turn through the junction's area to search from straight ``pa`` of lane ``a``
    into ``pb`` of lane ``b``, where :func:`_fillet_between` found none between them for
    ``reason`` (said of the junction when it touches something and none is found)."""
    _, _, _, x = lane_crossing(pa, pb, aisle_a, aisle_b, reach)
    frame = (float(x[0]), float(x[1]), pa.start[2])
    return _Wide(a.id, sa0, pa, b.id, sb0, pb, design, frame,
                 candidates_shape(pa, pb, design, lot_speed, frame,
                                  settings=settings.area_turns),
                 f"turn {a.id} → {b.id} near ({x[0]:.1f}, {x[1]:.1f}) skipped: {reason}"
                 if "touches" in reason else None)


@dataclass(frozen=True)
class _Wide:
    """A junction turn through the junction's area to search (:func:`area_turns`), where
    no turn between the lanes is clear: from straight ``pa`` of lane ``a`` (at station
    ``sa0``) into ``pb`` of lane ``b``, for ``design``. ``frame``: the lanes' crossing and
    ``pa``'s heading, where ``shape`` (:func:`candidates_shape`) is seen; ``note``: what is
    said of the junction when none is found."""

    a: str
    sa0: float
    pa: Segment
    b: str
    sb0: float
    pb: Segment
    design: DesignVehicle
    frame: tuple[float, float, float]
    shape: bytes
    note: str | None


def wide_turns(lot: Lot, wides: list[_Wide], collider: Collider, *, run=fork_map,
               settings: RoadmapSettings = DEFAULTS
               ) -> list[tuple[list[Turn], tuple[float, float, float, float]]]:
    """The turns :func:`area_turns` finds for each of ``wides``, with the box its checks
    read (:class:`~lotsim.lot.clearance.Watched`).

    Junctions alike (a regular lot's, most of them) ask the same search: the same
    candidate paths (:attr:`_Wide.shape`) near the same obstacles. The first of each shape
    is searched; where it finds nothing, so does each other whose obstacles about it, in
    the box the first's checks read, are the first's to the micrometre
    (:meth:`~lotsim.lot.clearance.Collider.local_digest`), without a search (its box: that
    box about it). The others are searched on their own. Which is first is the order of
    ``wides``, so the answers are the same on any number of cores (``run``: a map, on
    forked workers by default)."""
    lanes = {lane.id: lane for lane in lot.lanes}

    def search(k: int) -> tuple[list[Turn], tuple]:
        w = wides[k]
        eye = Watched(collider)
        turns = area_turns(lanes[w.a], w.sa0, w.pa, lanes[w.b], w.sb0, w.pb, w.design, eye,
                           lot.speed_limit, settings=settings.area_turns,
                           sweep=lot.settings.sweep)
        return turns, eye.box

    groups: dict[bytes, list[int]] = {}
    for k, w in enumerate(wides):
        groups.setdefault(w.shape, []).append(k)
    out: list = [None] * len(wides)
    firsts = [ks[0] for ks in groups.values()]
    for k, got in zip(firsts, run(search, firsts), strict=True):
        out[k] = got
    alone = []
    for first, *others in groups.values():
        turns, box = out[first]
        if turns or not others:
            alone += others
            continue
        if box == NOTHING_READ:  # no candidate could be built: none anywhere alike
            for k in others:
                out[k] = ([], NOTHING_READ)
            continue
        local = _seen_from(wides[first].frame, box)
        mark = collider.local_digest(wides[first].frame, local)
        for k in others:
            if collider.local_digest(wides[k].frame, local) == mark:
                out[k] = ([], _box_about(wides[k].frame, local))
            else:
                alone.append(k)
    alone.sort()
    for k, got in zip(alone, run(search, alone), strict=True):
        out[k] = got
    return out


def _corners(box: tuple[float, float, float, float]) -> list[tuple[float, float]]:
    x0, y0, x1, y1 = box
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def _seen_from(frame: tuple[float, float, float], box: tuple[float, float, float, float]
               ) -> tuple[float, float, float, float]:
    """The box, square to ``frame``, holding the world ``box``, a millimetre wider."""
    ox, oy, heading = frame
    c, s = math.cos(heading), math.sin(heading)
    pts = [(c * (x - ox) + s * (y - oy), c * (y - oy) - s * (x - ox)) for x, y in _corners(box)]
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    return min(xs) - 0.001, min(ys) - 0.001, max(xs) + 0.001, max(ys) + 0.001


def _box_about(frame: tuple[float, float, float], local: tuple[float, float, float, float]
               ) -> tuple[float, float, float, float]:
    """The world box holding ``local`` (a box in ``frame``)."""
    ox, oy, heading = frame
    c, s = math.cos(heading), math.sin(heading)
    pts = [(ox + c * x - s * y, oy + s * x + c * y) for x, y in _corners(local)]
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    return min(xs), min(ys), max(xs), max(ys)


def _joined(box: tuple, other: tuple) -> tuple[float, float, float, float]:
    return (min(box[0], other[0]), min(box[1], other[1]), max(box[2], other[2]),
            max(box[3], other[3]))


def _assembled(entries: list, answers) -> tuple[list[Turn], list[str], list[tuple]]:
    """A lane's junction turns and notes from its ``entries`` (:func:`_lane_junctions`),
    each :class:`_Wide` answered by the next of ``answers`` (:func:`wide_turns`), with the
    boxes those read."""
    turns: list[Turn] = []
    skipped: list[str] = []
    boxes = []
    for entry in entries:
        if isinstance(entry, _Wide):
            wide, box = next(answers)
            boxes.append(box)
            if wide:
                turns.extend(wide)
            elif entry.note:
                skipped.append(entry.note)
        elif isinstance(entry, list):
            turns.extend(entry)
        else:
            skipped.append(entry)
    return turns, skipped, boxes


def gate_stations(lot: Lot) -> dict[tuple[str, str], list[float]]:
    """(lane id, ``"in"`` or ``"out"``) → the stations of the entrances (exits) on it."""
    gates: dict[tuple[str, str], list[float]] = {}
    for way, portals in (("in", lot.entrances), ("out", lot.exits)):
        for p in portals:
            lid, st = portal_station(lot, p)
            gates.setdefault((lid, way), []).append(st)
    return gates


def junction_turns(lot: Lot, collider: Collider, design: DesignVehicle | None = None, *,
                   lanes_a=None, gates: dict[tuple[str, str], list[float]] | None = None,
                   settings: RoadmapSettings = DEFAULTS) -> tuple[list[Turn], list[str]]:
    """Arcs between lanes of aisles that meet, each swept clear with ``design`` (default
    the lot's design vehicle): out of ``lanes_a`` (default every lane); where none between
    two lanes is clear, through the junction's area (:func:`wide_turns`). ``gates``: the
    lot's :func:`gate_stations`, when the caller has them; ``settings``: the design speeds
    and the area turns' candidates."""
    design = design or lot.design
    gates = gate_stations(lot) if gates is None else gates
    entries = [e for a in (lot.lanes if lanes_a is None else lanes_a)
               for e in _lane_junctions(lot, collider, design, a, gates, settings)]
    wides = [e for e in entries if isinstance(e, _Wide)]
    answers = wide_turns(lot, wides, collider, run=lambda fn, items: [fn(k) for k in items],
                         settings=settings)
    turns, skipped, _ = _assembled(entries, iter(answers))
    return turns, skipped


def _lane_junctions(lot: Lot, collider: Collider, design: DesignVehicle, a,
                    gates: dict[tuple[str, str], list[float]],
                    settings: RoadmapSettings = DEFAULTS) -> list:
    """The turns out of lane ``a`` into each lane of another aisle it meets
    (:func:`_fillet_between`), in order: for each pair of straights that meet, the turns
    found, a note of why none is, or the turn through the junction's area to search."""
    out: list = []
    for b in lot.lanes:
        if a.aisle == b.aisle:
            continue
        aisle_a, aisle_b = lot.aisles[a.aisle], lot.aisles[b.aisle]
        reach = max(aisle_a.width, aisle_b.width) / 2 + 1.0
        for sa0, pa in straights(a):
            for sb0, pb in straights(b):
                turn = _fillet_between(a, sa0, pa, b, sb0, pb, aisle_a, aisle_b, reach,
                                       design, collider, lot.speed_limit, lot.settings.sweep,
                                       (tuple(gates.get((a.id, "in"), ())),
                                        tuple(gates.get((b.id, "out"), ()))),
                                       settings=settings)
                if turn.found:
                    out.append(turn.value)
                elif turn.status is Status.NO_PATH:
                    out.append(_wide_between(a, sa0, pa, b, sb0, pb, aisle_a, aisle_b,
                                             reach, design, lot.speed_limit, turn.reason,
                                             settings))
    return out


def turns_of(lot: Lot, collider: Collider, designs: dict[str, DesignVehicle] | None,
             memo: RoadmapMemo, *, settings: RoadmapSettings = DEFAULTS
             ) -> tuple[list[tuple[Turn, frozenset | None]], list[str]]:
    """The lot's junction turns (:func:`junction_turns`, and the turns through short
    stretches of lane, :mod:`lotsim.roadmap.through`), each with the vehicle types that can
    drive it (None: every type), and the reasons of those skipped; worked out once per set
    of types and kept in ``memo``.

    With ``designs`` (vehicle type → its own outline and limits, for two types or more)
    turns are built for each type on its own — a small car turns where the envelope of all
    the types could not — and a turn built for several types is kept once; without, for
    the lot's design vehicle (the envelope), for every type.
    """
    key = types_key(designs)
    cache = memo.check(lot, settings).turns
    if key not in cache:
        per = turns_per_design(lot, collider, list(designs.values()) if designs else [None],
                               memo, settings=settings)
        if not designs:
            turns, skipped = per[0]
            cache[key] = ([(t, None) for t in turns], skipped)
        else:
            found: dict[Turn, None] = {}
            why: dict[str, list[str]] = {}
            for name, (turns, skipped) in zip(designs, per, strict=True):
                found.update(dict.fromkeys(turns))
                for reason in skipped:
                    why.setdefault(reason, []).append(name)
            # every turn for every type it suits, on the workers, each taken from the
            # memo's store where what its sweeps read is unchanged
            turns = list(found)
            base = memo.lot_key if memo.known is not None else b""
            kinds = tuple(sorted(designs.items()))
            suits = worked_out(memo, [key_of(TurnSuits(base, kinds, t)) for t in turns],
                               collider, lambda k, eye: _suited(turns[k], designs, eye,
                                                                lot.settings.sweep))
            tagged = {t: names for t, names in zip(turns, suits, strict=True) if names}
            every = len(designs)
            notes = [reason if len(names) == every else f"{reason} (for {', '.join(names)})"
                     for reason, names in why.items()]
            cache[key] = ([(t, None if len(n) == every else frozenset(n))
                           for t, n in tagged.items()], notes)
    turns, skipped = cache[key]
    return list(turns), list(skipped)


def _lane_turns(lot: Lot, collider: Collider, job: tuple, gates: dict,
                settings: RoadmapSettings = DEFAULTS) -> tuple[list[Turn], list[str]]:
    """The junction turns out of one lane for one design (``job``: the design and the
    lane) and their notes, worked out alone: what :func:`turns_per_design` keeps of it."""
    entries = _lane_junctions(lot, collider, *job, gates, settings)
    answers = iter(wide_turns(lot, [e for e in entries if isinstance(e, _Wide)], collider,
                              run=lambda fn, items: [fn(x) for x in items],
                              settings=settings))
    turns, skipped, _ = _assembled(entries, answers)
    return turns, skipped


def _suited(turn: Turn, designs: dict[str, DesignVehicle], collider: Collider, step: float
            ) -> set[str]:
    """The vehicle types (of ``designs``) ``turn`` suits: no tighter than the type's
    radius, and its swept body (footprints ``step`` apart [m]) clear of ``collider``."""
    poses = sample_segments(turn.segments, step)[0]
    bend = max(seg.max_curvature for seg in turn.segments)
    return {name for name, design in designs.items()
            if bend <= 1 / design.min_radius + 1e-9
            and collider.sweep_hit(design.footprints(poses)) is None}


def turns_per_design(lot: Lot, collider: Collider, designs: list,
                     memo: RoadmapMemo | None = None, *, settings: RoadmapSettings = DEFAULTS
                     ) -> list[tuple[list[Turn], list[str]]]:
    """:func:`junction_turns` and the turns through short stretches
    (:func:`~lotsim.roadmap.through.through_turn`) for each of ``designs`` (None: the
    lot's design vehicle), as each would find them on its own: the junction turns out of
    each lane, then each design's turns through short stretches, on the workers
    (:func:`~lotsim.core.workers.fork_map`; the same answers in the same order), each
    taken from ``memo``'s store of an earlier preparation where what it read is the same
    (:mod:`~lotsim.roadmap.remembered`)."""
    jobs = [(design or lot.design, a) for design in designs for a in lot.lanes]
    gates = gate_stations(lot)
    if memo is not None:
        memo.check(lot, settings)
    known = memo.known if memo is not None else None
    base = memo.lot_key if known is not None else b""
    stations = tuple((at, tuple(st)) for at, st in sorted(gates.items()))
    keys = [key_of(JunctionTurns(base, design, a.id, stations)) for design, a in jobs]
    found = [recall(known, key, collider) for key in keys]
    todo = [k for k, got in enumerate(found) if got is MISSING]

    def lane(k: int) -> tuple[list, tuple | None, bytes | None]:
        eye = Watched(collider) if known is not None else collider
        entries = _lane_junctions(lot, eye, *jobs[k], gates, settings)
        if known is None:
            return entries, None, None
        return entries, eye.box, collider.around(eye.box)

    verified(memo, keys, found, lambda k: _lane_turns(lot, collider, jobs[k], gates, settings))
    parts = fork_map(lane, todo)
    answers = iter(wide_turns(lot, [e for entries, _, _ in parts for e in entries
                                    if isinstance(e, _Wide)], collider, settings=settings))
    for k, (entries, box, digest) in zip(todo, parts, strict=True):
        turns, skipped, boxes = _assembled(entries, answers)
        found[k] = (turns, skipped)
        if known is not None:
            if boxes:  # what its turns through the junction's area read, too
                for other in boxes:
                    box = _joined(box, other)
                digest = collider.around(box)
            keep(known, keys[k], (found[k], box, digest))
    if memo is not None:
        memo.recalled += len(keys) - len(todo)
        memo.worked += len(todo)
    per = []
    for k in range(len(designs)):
        mine = found[k * len(lot.lanes):(k + 1) * len(lot.lanes)]
        per.append(([t for turns, _ in mine for t in turns], [r for _, why in mine for r in why]))
    # then each design's turns through short stretches, a stretch a task (a large type's
    # take longest)
    chains = [(k, chain) for k in range(len(designs))
              for chain in through_chains(lot, per[k][0], settings=settings)]
    got = worked_out(
        memo, [key_of(ThroughTurns(base, designs[k] or lot.design,
                                   tuple(x.id if hasattr(x, "id") else x for x in chain)))
               for k, chain in chains], collider,
        lambda j, eye: through_turn(lot, eye, designs[chains[j][0]], chains[j][1],
                                    settings=settings))
    through: list[list[Turn]] = [[] for _ in designs]
    for (k, _), turns in zip(chains, got, strict=True):
        through[k] += turns
    return [(turns + extra, why) for (turns, why), extra in zip(per, through, strict=True)]
