"""Slots of an OpenStreetMap lot: its mapped ``amenity=parking_space`` areas, or bays
inferred along its aisles.

A mapped space becomes a free-standing slot (its centre and the heading of a car that
drove in) of the kind its long side's angle to the nearest aisle says: perpendicular at
60° to 90°, parallel at 0° to 30°; between (angled) it is written as the nearer of the two,
since a free-standing angled slot needs its angle written, which imported slots do not
carry. A space whose entry lies within :data:`SNAP` of the aisle's edge is moved onto it
(lotsim wants it within 0.3 m); a space still off every aisle, on an aisle, an island or
another space, or smaller than the scenario's car, is dropped.

Without mapped spaces, perpendicular bays of :data:`BAY_WIDTH` × :data:`BAY_LENGTH` are
laid side by side along both sides of each straight leg of each aisle at least
:data:`PARKING_AISLE` wide, as rows: each bay
inside the lot, clear of every aisle, island and obstacle and of the other bays, and its
entry :data:`TURN_MARGIN` beyond the edge of any aisle that meets or crosses its own (room
for the turn there). Along each leg the bays' grid is shifted (in steps of 0.25 m) to hold
the most.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.affinity import translate
from shapely.geometry import Point, Polygon
from shapely.ops import unary_union

from lotsim.io.imports.draft import RowDraft, SlotDraft
from lotsim.io.imports.osm_chains import Chain

BAY_WIDTH = 2.5
"""Width of an inferred bay [m] (the common 2.5 m; lotsim's example lots use it)."""
BAY_LENGTH = 5.0
"""Depth of an inferred bay [m]: the 5.0 m bays of the 5.0 + 7.0 + 5.0 m module."""
TURN_MARGIN = 2.5
"""Bays keep this far beyond the edge of an aisle that meets theirs [m]."""
CLEARANCE = 0.02
"""Bays keep this far from what they must not touch [m]: the scenario rounds to 1 cm."""
SNAP = 1.0
"""A mapped space whose entry is this close to an aisle's edge [m] is moved onto it."""
ENTRY_GAP = 0.3
"""lotsim's rule: a free-standing slot's entry lies within this of an aisle [m]."""
PARKING_AISLE = 5.0
"""Bays are laid along aisles at least this wide [m]: cars back into 2.5 x 5.0 m bays from
a 5 m aisle (on lotsim's one-aisle cul-de-sac, every bay but the one at the closed end is
usable at 5.0 m; at 4.5 m two more are not)."""
_SHIFTS = np.arange(0.0, BAY_WIDTH - 1e-9, 0.25)


@dataclass(frozen=True)
class Bay:
    """An inferred bay: on aisle ``chain``, ``side``, leg ``leg``, the ``k``-th of the grid
    shifted by ``shift``; ``station`` is where its entry begins [m]."""

    chain: str
    side: str
    leg: int
    shift: float
    k: int
    station: float
    polygon: Polygon


def infer_bays(chains: list[Chain], joins: dict[str, list[tuple[float, float]]],
               lot: Polygon, blocked: list[Polygon]) -> list[Bay]:
    """Perpendicular bays along both sides of every straight leg of every aisle."""
    avoid = unary_union([c.polygon for c in chains] + blocked)
    shapely.prepare(avoid)
    inside = lot.buffer(-CLEARANCE, join_style="mitre")
    shapely.prepare(inside)
    placed: list[Polygon] = []
    bays: list[Bay] = []
    for c in chains:
        if c.width < PARKING_AISLE:
            continue
        pts = np.asarray(c.pts, dtype=float)
        station = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
        for i in range(len(pts) - 1):
            u = (pts[i + 1] - pts[i]) / (station[i + 1] - station[i])
            left = np.array([-u[1], u[0]])
            for side, n in (("left", left), ("right", -left)):
                taken = unary_union(placed) if placed else Polygon()
                shapely.prepare(taken)
                best: list[Bay] = []
                for shift in _SHIFTS:
                    row = _grid(c, i, side, shift, pts[i], u, n, station[i],
                                station[i + 1] - station[i])
                    row = [b for b in row if _clear(b, c, joins[c.id], inside, avoid, taken)]
                    if len(row) > len(best):
                        best = row
                bays += best
                placed += [b.polygon for b in best]
    return bays


def _grid(c: Chain, leg: int, side: str, shift: float, p: np.ndarray, u: np.ndarray,
          n: np.ndarray, lo: float, length: float) -> list[Bay]:
    count = int((length - shift + 1e-9) // BAY_WIDTH)
    edge = p + n * c.width / 2
    out = []
    for k in range(count):
        a = edge + u * (shift + k * BAY_WIDTH)
        b = a + u * BAY_WIDTH
        poly = Polygon([a, b, b + n * BAY_LENGTH, a + n * BAY_LENGTH])
        out.append(Bay(c.id, side, leg, float(shift), k, lo + shift + k * BAY_WIDTH, poly))
    return out


def _clear(b: Bay, c: Chain, joins: list[tuple[float, float]], inside, avoid, taken) -> bool:
    s0, s1 = b.station, b.station + BAY_WIDTH
    for s, half in joins:
        if s0 < s + half + TURN_MARGIN and s1 > s - half - TURN_MARGIN:
            return False
    core = b.polygon.buffer(-CLEARANCE, join_style="mitre")
    return inside.covers(b.polygon) and not avoid.intersects(core) \
        and not taken.intersects(core)


def rows_of(bays: list[Bay]) -> tuple[list[RowDraft], dict[str, Bay]]:
    """The bays as rows of neighbours, and each slot id's bay. A row is named by its aisle,
    side and number along it: ``a1L2-5`` is the fifth bay of the second row left of
    ``a1``."""
    rows: list[RowDraft] = []
    ids: dict[str, Bay] = {}
    runs: dict[tuple[str, str], int] = {}
    group: list[Bay] = []
    for b in [*bays, None]:
        if group and (b is None or (b.chain, b.side, b.leg, b.shift, b.k)
                      != (group[-1].chain, group[-1].side, group[-1].leg, group[-1].shift,
                          group[-1].k + 1)):
            first = group[0]
            n = runs[(first.chain, first.side)] = runs.get((first.chain, first.side), 0) + 1
            prefix = f"{first.chain}{first.side[0].upper()}{n}-"
            rows.append(RowDraft(aisle=first.chain, side=first.side, kind="perpendicular",
                                 count=len(group), slot_width=BAY_WIDTH,
                                 slot_length=BAY_LENGTH, start=first.station,
                                 id_prefix=prefix))
            ids.update({f"{prefix}{j + 1}": g for j, g in enumerate(group)})
            group = []
        if b is not None:
            group.append(b)
    return rows, ids


# -- mapped spaces ----------------------------------------------------------------------------
def mapped_slots(spaces: list[tuple[int, Polygon]], chains: list[Chain], lot: Polygon,
                 blocked: list[Polygon], car: tuple[float, float], notes: list[str]
                 ) -> list[tuple[SlotDraft, Polygon]]:
    """Free-standing slots from mapped spaces (way id, outline), with their outlines; those
    narrower or shorter than ``car`` (width, length [m]) are dropped."""
    aisles = unary_union([c.polygon for c in chains])
    out: list[tuple[SlotDraft, Polygon]] = []
    for wid, outline in spaces:
        got = _mapped_slot(wid, outline, chains)
        if isinstance(got, str):
            notes.append(f"parking_space way {wid} dropped: {got}")
            continue
        slot, poly = got
        if slot.width < car[0] or slot.length < car[1]:
            notes.append(f"parking_space way {wid} dropped: {slot.width:.2f} x "
                         f"{slot.length:.2f} m is smaller than the car ({car[0]:g} x "
                         f"{car[1]:g} m)")
            continue
        core = poly.buffer(-CLEARANCE, join_style="mitre")
        why = ("it lies on an aisle" if core.intersects(aisles) else
               "it lies on an island or obstacle" if any(core.intersects(b) for b in blocked)
               else "it overlaps another space" if any(core.intersects(p) for _, p in out)
               else "it lies outside the lot" if not lot.buffer(SNAP).covers(poly) else "")
        if why:
            notes.append(f"parking_space way {wid} dropped: {why}")
            continue
        out.append((slot, poly))
    return out


def _mapped_slot(wid: int, outline: Polygon, chains: list[Chain]
                 ) -> tuple[SlotDraft, Polygon] | str:
    rect = outline.minimum_rotated_rectangle
    if not isinstance(rect, Polygon) or rect.area < 1.0:
        return "its outline has no area"
    corners = np.asarray(rect.exterior.coords)[:4]
    sides = np.diff(np.vstack([corners, corners[:1]]), axis=0)
    lengths = np.hypot(*sides.T)
    k = int(np.argmax(lengths[:2]))
    length, width = float(lengths[k]), float(lengths[1 - k])
    axis = sides[k] / length
    centre = corners.mean(axis=0)
    chain = min(chains, key=lambda c: (c.polygon.distance(rect), c.id))
    line = chain.line
    s = line.project(Point(centre))
    a, b = line.interpolate(max(0.0, s - 0.5)), line.interpolate(min(line.length, s + 0.5))
    u = np.array([b.x - a.x, b.y - a.y])
    u = u / np.hypot(*u)
    on = np.array(line.interpolate(s).coords[0])
    away = centre - on
    angle = math.degrees(math.acos(min(1.0, abs(float(np.dot(axis, u))))))
    across = angle >= 45
    kind = "perpendicular" if across else "parallel"
    if across:
        d = axis if np.dot(axis, away) > 0 else -axis  # from the entry into the bay
        heading = d
    else:
        d = np.array([-axis[1], axis[0]])
        d = d if np.dot(d, away) > 0 else -d
        right = float(u[0] * away[1] - u[1] * away[0]) < 0
        along = axis if np.dot(axis, u) > 0 else -axis
        heading = along if (right or chain.one_way) else -along
    depth = length if across else width
    entry_mid = centre - d * depth / 2
    reach = chain.line.distance(Point(entry_mid))
    ratio = max(abs(float(np.dot(d, np.array([-u[1], u[0]])))), 0.5)
    shift = (chain.width / 2 + 0.05 - reach) / ratio
    if abs(shift) > SNAP:
        return f"its entry is {abs(shift):.1f} m from aisle {chain.id}'s edge"
    centre = centre + d * shift
    entry_mid = centre - d * depth / 2
    if chain.polygon.distance(Point(entry_mid)) > ENTRY_GAP:
        return f"its entry does not open onto aisle {chain.id}"
    poly = translate(rect, *(d * shift))
    slot = SlotDraft(id=f"w{wid}", kind=kind, width=round(width, 2), length=round(length, 2),
                     center=(float(centre[0]), float(centre[1])),
                     heading_deg=math.degrees(math.atan2(heading[1], heading[0])),
                     note=f"parking_space way {wid}" + (
                         f" (at {angle:.0f}° to the aisle, written {kind})"
                         if 30 < angle < 60 else ""))
    return slot, poly
