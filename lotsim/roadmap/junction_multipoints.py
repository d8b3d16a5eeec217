"""Multi-point turns between the lanes of two aisles at a junction too small to turn in at
one go (:func:`junction_multipoints`): a short arm, a spur meeting a narrow aisle."""

from __future__ import annotations

import math

from lotsim.lot.model import DesignVehicle, Lot
from lotsim.roadmap.junctions import lane_crossing
from lotsim.roadmap.lanes import EPS, along, straights
from lotsim.roadmap.memo import RoadmapMemo, types_key
from lotsim.roadmap.model import Turn
from lotsim.roadmap.remembered import plan_onto_remembered
from lotsim.roadmap.settings import DEFAULTS, RoadmapSettings
from lotsim.roadmap.turnarounds import Turnaround, fits_a_slot, suits, turnaround_collider


def junction_multipoints(lot: Lot, tagged: list[tuple[Turn, frozenset | None]],
                         designs: dict[str, DesignVehicle] | None, exits: dict[str, float],
                         memo: RoadmapMemo, *, settings: RoadmapSettings = DEFAULTS
                         ) -> list[tuple[Turnaround, frozenset | None]]:
    """Multi-point turns between lanes of aisles that meet, where no turn joins them for
    some vehicle type (``tagged``: the junction turns, each with the types that can drive
    it, None for all): a junction too small to turn in at one go — a short arm, a spur
    meeting a narrow aisle — is turned in as a driver does, in a few strokes
    (:func:`~lotsim.roadmap.multipoint.plan_onto`), beginning at or a little before the
    crossing and landing on the other lane past it, driven from rest to rest like a
    turnaround. So too where every turn lands past an exit on the other lane (``exits``:
    lane → its last exit's station) that the crossing is before: an exit close to the
    junction, which the multi-point turn lands before. Each is tagged with the types it
    suits (None: all); worked out once per set of types and kept in ``memo``.

    Each begins at or up to :attr:`~lotsim.roadmap.settings.MultipointSettings.junction_starts`
    before the crossing, or where the lane's straight ends, and needs
    :attr:`~lotsim.roadmap.settings.MultipointSettings.junction_room` of lane before the
    crossing on the lane it leaves and after it on the lane it joins (where a lane begins
    or ends at the crossing, a car comes from or goes on to another turn instead);
    ``settings`` tune the search and its clearance."""
    key = types_key(designs)
    cache = memo.check(lot, settings).multipoints
    if key in cache:
        return list(cache[key])
    search, margin, step = (settings.multipoint, settings.turnarounds.margin,
                            settings.turnarounds.step)
    per = designs or {"": lot.design}
    every = frozenset(per)
    lands: dict[tuple[str, str], dict[str, float]] = {}  # (a, b) → type → first landing
    for t, types in tagged:
        pair = lands.setdefault((t.lane_a, t.lane_b), {})
        for name in every if types is None else types:
            pair[name] = min(pair.get(name, math.inf), t.station_b)
    bodies = {name: turnaround_collider(lot, design, margin) for name, design in per.items()}
    found: dict[Turnaround, set[str]] = {}
    parks = [n for n, design in per.items() if fits_a_slot(lot, design)]  # others never park
    for a in lot.lanes:
        for b in lot.lanes:
            if a.aisle == b.aisle:
                continue
            landed = lands.get((a.id, b.id), {})
            out_at = exits.get(b.id, math.inf)
            lacking = [n for n in parks if n not in landed or landed[n] > out_at + EPS]
            if not lacking:
                continue
            aisle_a, aisle_b = lot.aisles[a.aisle], lot.aisles[b.aisle]
            reach = max(aisle_a.width, aisle_b.width) / 2 + 1.0
            for sa0, pa in straights(a):
                for sb0, pb in straights(b):
                    corner = lane_crossing(pa, pb, aisle_a, aisle_b, reach)
                    if corner is None:
                        continue
                    _, ta, tb, _ = corner
                    hi = min(pb.length, out_at - sb0)  # land before the exit, if any
                    if sa0 + ta < search.junction_room or hi - tb < search.junction_room:
                        continue  # a lane that begins, or one that ends, at the crossing
                    end = min(ta, pa.length)
                    starts = sorted({max(end - k, 0.0) for k in search.junction_starts}
                                    | {pa.length}, reverse=True)
                    for name in lacking:
                        if any(name in n for t, n in found.items()
                               if (t.lane_a, t.lane_b) == (a.id, b.id)):
                            continue
                        lo = max(tb - 1.0, 0.0)
                        got = plan_onto_remembered(memo, "multipoint", a, sa0, pa, b, sb0,
                                                   pb, starts, lo, hi, bodies[name],
                                                   per[name].min_radius, settings=search)
                        if got.found:
                            k, segs = got.value
                            t = Turnaround(a.id, sa0 + starts[k], b.id,
                                           sb0 + along(pb, segs[-1].end), segs)
                            found.setdefault(t, set()).add(name)
    for t, names in found.items():  # and every other type it suits
        names.update(n for n in per
                     if n not in names and suits(t, per[n], bodies[n], step=step))
    out = [(t, None if len(n) == len(per) else frozenset(n)) for t, n in found.items()]
    cache[key] = out
    return list(out)
