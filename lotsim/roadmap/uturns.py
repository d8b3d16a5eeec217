"""U-turns at junctions (:func:`junction_uturns`): from a lane of a two-way aisle back onto
its opposite lane, in a few strokes that use the mouth of an aisle crossing or meeting it."""

from __future__ import annotations

import numpy as np

from lotsim.core.geometry import Segment, wrap_angle
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle, Lane, Lot
from lotsim.roadmap.junctions import lane_crossing
from lotsim.roadmap.lanes import EPS, along, straight_at, straights
from lotsim.roadmap.memo import RoadmapMemo, types_key
from lotsim.roadmap.multipoint import segment_to_world, to_local
from lotsim.roadmap.remembered import plan_onto_remembered
from lotsim.roadmap.settings import DEFAULTS, RoadmapSettings
from lotsim.roadmap.turnarounds import (
    Turnaround,
    fits_a_slot,
    suits,
    turnaround_clear,
    turnaround_collider,
)


def junction_uturns(lot: Lot, designs: dict[str, DesignVehicle] | None, memo: RoadmapMemo,
                    *, settings: RoadmapSettings = DEFAULTS
                    ) -> list[tuple[Turnaround, frozenset | None]]:
    """U-turns at junctions: from a lane of a two-way aisle, where another aisle crosses
    or meets it, back onto its opposite lane, in a few strokes that use the other aisle's
    mouth (:func:`~lotsim.roadmap.multipoint.plan_onto`) — how a driver turns back whose way
    is blocked, or who leaves the way they came. Each begins at or up to 6 m
    (:attr:`~lotsim.roadmap.settings.MultipointSettings.junction_starts`) before the
    crossing and lands within
    :attr:`~lotsim.roadmap.settings.MultipointSettings.uturn_land` of it; it needs
    :attr:`~lotsim.roadmap.settings.MultipointSettings.junction_room` of lane before the
    crossing on the lane it leaves and past it on the one it joins (all ``settings``'). Each
    is tagged with the vehicle types it suits (None: all); only types that fit a slot are
    planned for, largest first.

    Junctions of one shape share a plan: one found at a junction is moved onto the next
    (the same place relative to the crossing) and kept when it lands on that junction's
    opposite lane and is clear there, so a lot of many alike junctions plans a few.
    Worked out once per set of types and kept in ``memo``."""
    key = types_key(designs)
    cache = memo.check(lot, settings).uturns
    if key in cache:
        return list(cache[key])
    search, step = settings.multipoint, settings.turnarounds.step
    per = designs or {"": lot.design}
    bodies = {name: turnaround_collider(lot, design, settings.turnarounds.margin)
              for name, design in per.items()}
    parks = sorted((n for n, d in per.items() if fits_a_slot(lot, d)),
                   key=lambda n: (-per[n].min_radius, -(per[n].front + per[n].rear), n))
    known: list[tuple[str, tuple[Segment, ...]]] = []  # (type, path relative to a crossing)
    found: dict[Turnaround, set[str]] = {}
    for aisle in lot.aisles.values():
        if aisle.one_way or len(aisle.lanes) != 2:
            continue
        for a, back in (aisle.lanes, aisle.lanes[::-1]):
            for sa0, pa, x in _crossings(lot, a):
                ta = along(pa, x)
                sb, _ = back.project((float(x[0]), float(x[1])))
                got = straight_at(back, sb)
                if got is None or sa0 + ta < search.junction_room:
                    continue
                sb0, pb = got
                tb = sb - sb0
                lo = max(tb - search.uturn_land[0], 0.0)
                hi = min(tb + search.uturn_land[1], pb.length)
                if hi - tb < search.junction_room:
                    continue
                frame = np.array(pa.start, dtype=float)
                frame[:2] = x
                end = min(ta, pa.length)
                mine: list[Turnaround] = []
                for name in parks:
                    fitting = [t for t in mine
                               if suits(t, per[name], bodies[name], step=step)]
                    if fitting:  # one planned for a larger type here serves this one
                        found[fitting[0]].add(name)
                        continue
                    t = _moved_uturn(known, name, frame, a, sa0, pa, end, back, sb0, pb,
                                     lo, hi, bodies[name], step)
                    if t is None:
                        starts = sorted({max(end - k, 0.0) for k in search.junction_starts},
                                        reverse=True)
                        plan = plan_onto_remembered(memo, "uturn", a, sa0, pa, back, sb0, pb,
                                                    starts, lo, hi, bodies[name],
                                                    per[name].min_radius, settings=search)
                        if not plan.found:
                            continue
                        k, segs = plan.value
                        t = Turnaround(a.id, sa0 + starts[k], back.id,
                                       sb0 + along(pb, segs[-1].end), segs)
                        known.append((name, tuple(_segment_to_local(frame, g) for g in segs)))
                    found.setdefault(t, set()).add(name)
                    mine.append(t)
    for t, names in found.items():  # and every other type it suits
        names.update(n for n in per
                     if n not in names and suits(t, per[n], bodies[n], step=step))
    out = [(t, None if len(n) == len(per) else frozenset(n)) for t, n in found.items()]
    cache[key] = out
    return list(out)


def _crossings(lot: Lot, lane: Lane) -> list[tuple[float, Segment, np.ndarray]]:
    """Where other aisles cross or meet ``lane``'s straights: (the straight's start
    station, the straight, the crossing point with the nearest of the other aisle's lanes'
    lines), once per other aisle and straight."""
    out = []
    aisle = lot.aisles[lane.aisle]
    for sa0, pa in straights(lane):
        for other in lot.aisles.values():
            if other.id == aisle.id:
                continue
            reach = max(aisle.width, other.width) / 2 + 1.0
            hits = [corner[3] for c in other.lanes for _, pc in straights(c)
                    if (corner := lane_crossing(pa, pc, aisle, other, reach)) is not None]
            if hits:
                out.append((sa0, pa, min(hits, key=lambda h: along(pa, h))))
    return out


def _moved_uturn(known, name: str, frame: np.ndarray, a: Lane, sa0: float, pa: Segment,
                 end: float, back: Lane, sb0: float, pb: Segment, lo: float, hi: float,
                 checks: tuple[Collider, DesignVehicle], step: float) -> Turnaround | None:
    """The first U-turn found earlier for type ``name`` (``known``: paths relative to
    their crossing) that, moved to the crossing ``frame``, begins on straight ``pa`` at
    most at ``end``, lands on ``pb``'s line heading along it between ``lo`` and ``hi``,
    and is clear (``checks``: collider and body); None when none is."""
    for owner, local in known:
        if owner != name:
            continue
        segs = tuple(segment_to_world(frame, g) for g in local)
        start = along(pa, segs[0].start)
        if not 0.0 <= start <= end + EPS:
            continue
        ex, ey, eh = segs[-1].end
        off = to_local(np.array(pb.start, dtype=float), np.array([ex, ey, eh]))
        at = float(off[0])
        if (abs(off[1]) > 1e-6 or abs(wrap_angle(off[2])) > 1e-6
                or not lo - EPS <= at <= hi + EPS):
            continue
        t = Turnaround(a.id, sa0 + start, back.id, sb0 + at, segs)
        if turnaround_clear(t, *checks, step=step):
            return t
    return None


def _segment_to_local(frame: np.ndarray, seg: Segment) -> Segment:
    x, y, t = to_local(frame, np.array(seg.start, dtype=float))
    return Segment((float(x), float(y), float(t)), seg.distance, seg.curvature, seg.sharpness)
