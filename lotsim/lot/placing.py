"""Placing a lot's bays: the rows and single slots of a :class:`~lotsim.lot.spec.LotSpec`
as slot polygons on their aisles, each with its use, and the access aisles beside the
accessible bays (:func:`place_slots`). The checks that need the whole lot (overlaps, the
boundary) are :mod:`lotsim.lot.build`'s.

In a row of accessible or van-accessible bays, two neighbours share one access aisle
between them: bay, aisle, bay, then the row's ``gap``, bay, aisle, bay, ...; the last bay
of an odd count has its own aisle after it. A parallel bay's aisle runs behind it, along
its far long side (the side away from its aisle); a single slot's on the side it names
(``access_side``, seen facing into the bay).
"""

from __future__ import annotations

import math

import numpy as np
from shapely.geometry import Point

from lotsim.core.geometry import FloatArray, ccw, wrap_angle
from lotsim.errors import ScenarioError
from lotsim.lot.kinds import KINDS
from lotsim.lot.model import AccessAisle, Aisle, Slot, unit
from lotsim.lot.spec import LotSpec, RowSpec, SlotSpec
from lotsim.lot.uses import use_of


def place_slots(spec: LotSpec, aisles: dict[str, Aisle]
                ) -> tuple[tuple[Slot, ...], tuple[AccessAisle, ...]]:
    """The lot's bays, rows first in file order then the single slots, and the access
    aisles of its accessible bays.

    Raises
    ------
    ScenarioError
        A bay off its aisle or on a bend, an id used twice, an accessible bay or its
        access aisle narrower than its use asks (located at the row or slot).
    """
    slots: list[Slot] = []
    access: list[AccessAisle] = []
    for i, row in enumerate(spec.rows):
        placed, beside = _row_slots(row, i, aisles)
        slots.extend(placed)
        access.extend(beside)
    for s in spec.slots:
        slot = _single_slot(s, aisles)
        slots.append(slot)
        width = _aisle_width(s.use, s.width, s.access_aisle_width, s.where)
        if width is not None:
            sign = 1.0 if s.access_side == "left" else -1.0
            access.append(AccessAisle(f"access-{slot.id}", _beside(slot, width, sign),
                                      (slot.id,), width, s.where))
    seen: dict[str, Slot] = {}
    for s in slots:
        if s.id in seen:
            raise ScenarioError(s.where, f"slot id {s.id!r} is used twice")
        seen[s.id] = s
    return tuple(slots), tuple(access)


def _aisle_width(use: str, width: float, given: float | None, where) -> float | None:
    """The access aisle's width [m] of a bay of ``use`` ``width`` wide (``given``, or the
    least its use asks); None for a use that carries none. A bay or aisle too narrow for
    its use is refused."""
    rules = use_of(use)
    problem = rules.size_problem(width, given)
    if problem is not None:
        raise ScenarioError(where, problem)
    least = rules.least_aisle(width)
    if least is None:
        if given is not None:
            raise ScenarioError(where, f"a {rules.label} bay carries no access aisle: "
                                       f"access_aisle_width is for accessible and "
                                       f"van-accessible bays")
        return None
    return given if given is not None else least


def _beside(slot: Slot, width: float, sign: float) -> FloatArray:
    """The rectangle ``width`` wide [m] along the long side of ``slot`` to its left
    (``sign`` +1, seen facing :attr:`Slot.heading`) or right (-1), over its full length."""
    d = unit(slot.heading)
    left = np.array([-d[1], d[0]]) * sign
    across = slot.polygon @ left
    edge = slot.polygon[np.argsort(across)[-2:]]  # the two corners on that side
    p, q = sorted(edge, key=lambda c: float(c @ d))
    return ccw(np.array([p, q, q + width * left, p + width * left]))


# -- one bay -----------------------------------------------------------------------------------
def _slot_frame(
    aisle: Aisle, side: str, s0: float, s1: float, where, what: str
) -> tuple[FloatArray, FloatArray, FloatArray, float]:
    """Origin of station 0 on the aisle edge, along-aisle unit u, outward unit n, leg heading.

    The entry of a slot spans stations ``s0..s1``; it must lie on one straight
    part of the centreline (not on a bend).
    """
    start, heading, lo, hi = aisle.legs
    total = float(start[-1] + np.hypot(*(aisle.centerline[-1] - aisle.centerline[-2])))
    for i in range(len(start)):
        if lo[i] - 1e-9 <= s0 and s1 <= hi[i] + 1e-9:
            u = unit(float(heading[i]))
            left = np.array([-u[1], u[0]])
            n = left if side == "left" else -left
            origin = aisle.centerline[i] + (0 - start[i]) * u + n * aisle.width / 2
            return origin, u, n, float(heading[i])
    if s1 > total + 1e-9:
        raise ScenarioError(
            where,
            f"{what} runs to station {s1:.2f} m, past the end of aisle {aisle.id!r} "
            f"({total:.2f} m long)",
        )
    raise ScenarioError(
        where,
        f"{what} spans stations {s0:.2f}..{s1:.2f} m of aisle {aisle.id!r}, which are not on "
        f"one straight part of it (a slot's entry must not sit on a bend)",
    )


def _slot_on_aisle(
    sid: str, kind: str, angle: float, width: float, length: float,
    aisle: Aisle, side: str, station: float, where, what: str, use: str,
) -> Slot:
    """One slot whose entry begins at aisle ``station`` (its lowest station) [m]."""
    rules = KINDS[kind]
    along = rules.frontage(width, length, angle)
    origin, u, n, heading = _slot_frame(aisle, side, station, station + along, where, what)
    poly, entry, into = rules.place(origin, u, n, heading, station, width, length, angle,
                                    toward_traffic=side == "right" or aisle.one_way)
    return Slot(
        id=sid, kind=kind, polygon=ccw(poly), entry=entry,
        heading=float(wrap_angle(into)), aisle=aisle.id, side=side,
        station=station + along / 2, angle=angle, width=width, length=length, where=where,
        use=use,
    )


def _row_slots(row: RowSpec, index: int, aisles: dict[str, Aisle]
               ) -> tuple[list[Slot], list[AccessAisle]]:
    aisle = _aisle_ref(aisles, row.aisle, row.where)
    rules = KINDS[row.kind]
    pitch = rules.pitch(row.slot_width, row.slot_length, row.angle)
    prefix = row.id_prefix or f"{row.aisle}-{row.side}-"
    wide = _aisle_width(row.use, row.slot_width, row.access_aisle_width, row.where)
    shared = wide is not None and not rules.parks_along
    step = rules.pitch(wide, row.slot_length, row.angle) if shared else 0.0
    out: list[Slot] = []
    for k in range(row.count):
        sid = f"{prefix}{row.first_number + k}"
        # with shared access aisles: one between the bays of each pair, the gap between pairs
        at = (row.start + k * pitch + (k + 1) // 2 * step + k // 2 * row.gap if shared
              else row.start + k * (pitch + row.gap))
        out.append(
            _slot_on_aisle(
                sid, row.kind, row.angle, row.slot_width, row.slot_length, aisle, row.side,
                at, row.where, f"slot {sid!r} of lot.rows[{index}]", row.use,
            )
        )
    beside: list[AccessAisle] = []
    if wide is None:
        return out, beside
    if not shared:  # along the aisle: behind each bay
        for s in out:
            inward = np.asarray(s.center) - s.entry.mean(axis=0)
            d = unit(s.heading)
            away = 1.0 if float(d[0] * inward[1] - d[1] * inward[0]) > 0 else -1.0
            beside.append(AccessAisle(f"access-{s.id}", _beside(s, wide, away), (s.id,),
                                      wide, row.where))
        return out, beside
    for k in range(0, row.count, 2):
        pair = out[k:k + 2]
        at = row.start + k * pitch + (k + 1) // 2 * step + k // 2 * row.gap
        what = f"slot {pair[0].id!r} of lot.rows[{index}]"
        origin, u, n, heading = _slot_frame(
            aisle, row.side, at, at + rules.frontage(row.slot_width, row.slot_length,
                                                     row.angle), row.where, what)
        poly, _, _ = rules.place(origin, u, n, heading, at, row.slot_width, row.slot_length,
                                 row.angle, toward_traffic=row.side == "right" or aisle.one_way)
        # between this bay's far long side and the near long side of the next (as it
        # stands, or would): in an angled row the bays' ends are staggered, so is the aisle
        a, b, along = poly[0], poly[1], poly[3] - poly[0]
        nxt = b + (pitch + step) * u
        beside.append(AccessAisle(f"access-{pair[0].id}",
                                  ccw(np.array([a, a + along, nxt + along, nxt])),
                                  tuple(s.id for s in pair), wide, row.where))
    return out, beside


def _aisle_ref(aisles: dict[str, Aisle], name: str, where) -> Aisle:
    if name not in aisles:
        raise ScenarioError(
            where, f"expected the id of an aisle ({', '.join(aisles)}), found {name!r}"
        )
    return aisles[name]


def _single_slot(spec: SlotSpec, aisles: dict[str, Aisle]) -> Slot:
    if spec.aisle is not None:
        aisle = _aisle_ref(aisles, spec.aisle, spec.where)
        return _slot_on_aisle(
            spec.id, spec.kind, spec.angle, spec.width, spec.length, aisle, spec.side or "left",
            spec.at or 0.0, spec.where, f"slot {spec.id!r}", spec.use,
        )
    return _free_slot(spec, aisles)


ANGLE_TOL = math.radians(1.0)
"""A free-standing angled slot's ``angle_deg`` and the angle its heading makes with its aisle
agree within this [rad]."""


def _free_slot(spec: SlotSpec, aisles: dict[str, Aisle]) -> Slot:
    """A slot placed by centre and heading; its entry is the side that opens onto an aisle."""
    c = np.asarray(spec.center, dtype=float)
    d = unit(spec.heading)
    n = np.array([-d[1], d[0]])
    hl, hw = spec.length / 2, spec.width / 2
    rr, fr = c - hl * d - hw * n, c + hl * d - hw * n
    fl, rl = c + hl * d + hw * n, c - hl * d + hw * n
    candidates = KINDS[spec.kind].entry_sides(rr, fr, fl, rl)
    best = None
    for edge in candidates:
        for aisle in aisles.values():
            gap = KINDS[spec.kind].entry_gap(edge, aisle.polygon)
            if best is None or gap < best[0]:
                best = (gap, edge, aisle)
    assert best is not None
    gap, edge, aisle = best
    if gap > 0.3:
        raise ScenarioError(
            spec.where,
            f"slot {spec.id!r} opens onto no aisle: its entry side is {gap:.2f} m from the "
            f"nearest aisle {aisle.id!r}",
        )
    mid = edge.mean(axis=0)
    station = float(aisle.line.project(Point(mid)))
    start, heading, _, _ = aisle.legs
    leg = int(np.clip(np.searchsorted(start, station, side="right") - 1, 0, len(start) - 1))
    u = unit(float(heading[leg]))
    on_line = np.asarray(aisle.line.interpolate(station).coords[0])
    away = c - on_line
    side = "left" if u[0] * away[1] - u[1] * away[0] > 0 else "right"
    angle = math.acos(min(1.0, abs(float(np.dot(d, u)))))
    if KINDS[spec.kind].fixed_angle is None and abs(angle - spec.angle) > ANGLE_TOL:
        raise ScenarioError(
            spec.where,
            f"slot {spec.id!r}: angle_deg is {math.degrees(spec.angle):g}, but its heading "
            f"makes {math.degrees(angle):.1f}° with aisle {aisle.id!r}, which it opens onto",
        )
    return Slot(
        id=spec.id, kind=spec.kind, polygon=ccw(np.array([rr, fr, fl, rl])), entry=edge,
        heading=float(wrap_angle(spec.heading)), aisle=aisle.id, side=side, station=station,
        angle=angle, width=spec.width, length=spec.length, where=spec.where, use=spec.use,
    )
