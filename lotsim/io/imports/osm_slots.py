"""Slots of an OpenStreetMap lot: its mapped ``amenity=parking_space`` areas, or bays
inferred along its aisles.

A mapped space becomes a free-standing slot (its centre and the heading of a car that
drove in) of the kind its long side's angle to the nearest aisle says (:func:`kind_at`):
perpendicular at 75° to 90°, parallel at 0° to 30°, angled between, at its angle; a space
drawn as a parallelogram (an angled bay painted along its aisle) is the rectangle inside it
(:mod:`.spot_shape`). A space whose entry (an angled bay's: its nearer end) lies within
:data:`SNAP` of the aisle's edge is moved onto it (lotsim wants it within 0.3 m); a space
still off every aisle, on an aisle, an island or another space, or smaller than the
scenario's car, is dropped.

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
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

from lotsim.core.geometry import FloatArray
from lotsim.io.imports.draft import RowDraft, SlotDraft
from lotsim.io.imports.osm_chains import Chain
from lotsim.io.imports.spot_shape import spot_shape

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
RIM = 0.01
"""An angled slot is drawn this much inside its mapped long sides [m], so that neighbours
that share them do not overlap once written to the centimetre."""
PARALLEL_DEG = 30.0
"""A mapped space whose long side lies within this of its aisle's direction is parallel
[degrees]."""
SQUARE_DEG = 75.0
"""One at this or more to its aisle is perpendicular; between, angled [degrees]."""
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
def mapped_slots(spaces: list[tuple[int, Polygon, str]], chains: list[Chain], lot: Polygon,
                 blocked: list[Polygon], car: tuple[float, float], notes: list[str]
                 ) -> list[tuple[SlotDraft, Polygon]]:
    """Free-standing slots from mapped spaces (way id, outline, ``parking:orientation``),
    with their outlines; those narrower or shorter than ``car`` (width, length [m]) are
    dropped."""
    aisles = unary_union([c.polygon for c in chains])
    out: list[tuple[SlotDraft, Polygon]] = []
    for wid, outline, orientation in spaces:
        got = _mapped_slot(wid, outline, chains, orientation)
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


def _rectangle(outline: Polygon) -> tuple[Polygon, FloatArray, float, float, bool] | str:
    """The rectangle of a mapped space (:mod:`.spot_shape`): a four-cornered parallelogram's
    inside it, else the smallest enclosing the outline; its long axis, width and length
    [m], and whether the outline is a parallelogram."""
    rect = outline.minimum_rotated_rectangle
    if not isinstance(rect, Polygon) or rect.area < 1.0:
        return "its outline has no area"
    ring = np.asarray(shapely.simplify(outline, 0.02).exterior.coords)[:-1]
    shape = spot_shape(ring) if len(ring) == 4 else None
    if shape is not None and shape.skew > 0:
        d = shape.axis
        n = np.array([-d[1], d[0]])
        hl, hw = shape.length / 2, shape.width / 2
        c = shape.center
        rect = Polygon([c - hl * d - hw * n, c + hl * d - hw * n, c + hl * d + hw * n,
                        c - hl * d + hw * n])
        return rect, d, shape.width, shape.length, True
    corners = np.asarray(rect.exterior.coords)[:4]
    sides = np.diff(np.vstack([corners, corners[:1]]), axis=0)
    lengths = np.hypot(*sides.T)
    k = int(np.argmax(lengths[:2]))
    return rect, sides[k] / lengths[k], float(lengths[1 - k]), float(lengths[k]), False


def kind_at(angle: float, orientation: str) -> str:
    """The kind of a mapped space whose long side makes ``angle`` [degrees] with its aisle:
    parallel to :data:`PARALLEL_DEG`, perpendicular from :data:`SQUARE_DEG`, angled between;
    tagged ``parking:orientation=diagonal``, angled from 5° to 85°.

    >>> kind_at(90, ""), kind_at(60, ""), kind_at(80, ""), kind_at(80, "diagonal")
    ('perpendicular', 'angled', 'perpendicular', 'angled')
    """
    low, high = (5.0, 85.0) if orientation == "diagonal" else (PARALLEL_DEG, SQUARE_DEG)
    return "parallel" if angle <= low else "perpendicular" if angle >= high else "angled"


def _mapped_slot(wid: int, outline: Polygon, chains: list[Chain], orientation: str = ""
                 ) -> tuple[SlotDraft, Polygon] | str:
    got = _rectangle(outline)
    if isinstance(got, str):
        return got
    rect, axis, width, length, skewed = got
    centre = np.asarray(rect.centroid.coords[0])
    chain = min(chains, key=lambda c: (c.polygon.distance(rect), c.id))
    line = chain.line
    s = line.project(Point(centre))
    a, b = line.interpolate(max(0.0, s - 0.5)), line.interpolate(min(line.length, s + 0.5))
    u = np.array([b.x - a.x, b.y - a.y])
    u = u / np.hypot(*u)
    on = np.array(line.interpolate(s).coords[0])
    away = centre - on
    angle = math.degrees(math.acos(min(1.0, abs(float(np.dot(axis, u))))))
    kind = kind_at(angle, orientation)
    if kind != "parallel":
        d = axis if np.dot(axis, away) > 0 else -axis  # from the entry into the bay
        heading = d
    else:
        d = np.array([-axis[1], axis[0]])
        d = d if np.dot(d, away) > 0 else -d
        right = float(u[0] * away[1] - u[1] * away[0]) < 0
        along = axis if np.dot(axis, u) > 0 else -axis
        heading = along if (right or chain.one_way) else -along
    depth = width if kind == "parallel" else length
    across = np.array([-d[1], d[0]]) * (width if kind != "parallel" else length) / 2
    ends = [centre - d * depth / 2 + across, centre - d * depth / 2 - across]
    # lotsim's reach: the entry's middle; an angled bay's nearer end (its front corner)
    mid = centre - d * depth / 2
    entry = min(ends, key=lambda p: line.distance(Point(p))) if kind == "angled" else mid
    reach = line.distance(Point(entry))
    ratio = max(abs(float(np.dot(d, np.array([-u[1], u[0]])))), 0.5)
    shift = (chain.width / 2 + 0.05 - reach) / ratio
    if kind == "angled" and reach <= chain.width / 2 + ENTRY_GAP - 0.05:
        # its front corner, a point, needs only keep off the aisle against rounding
        shift = max(chain.width / 2 + CLEARANCE - reach, 0.0) / ratio
    if abs(shift) > SNAP:
        return f"its entry is {abs(shift):.1f} m from aisle {chain.id}'s edge"
    centre = centre + d * shift
    opening = (LineString([p + d * shift for p in ends]) if kind == "angled"
               else Point(mid + d * shift))
    if chain.polygon.distance(opening) > ENTRY_GAP:
        return f"its entry does not open onto aisle {chain.id}"
    poly = translate(rect, *(d * shift))
    told = [f"at {angle:.0f}° to the aisle"] if kind == "angled" or orientation == "diagonal" \
        else []
    if skewed:
        told.append("a parallelogram: the rectangle inside it")
    if orientation == "diagonal" and kind != "angled":
        told.append(f"tagged parking:orientation=diagonal, drawn {kind}")
    if kind == "angled":  # neighbours share long sides that slant across the centimetres
        width = math.floor(round((width - 2 * RIM) * 100, 2)) / 100
    slot = SlotDraft(id=f"w{wid}", kind=kind, width=round(width, 2), length=round(length, 2),
                     center=(float(centre[0]), float(centre[1])),
                     heading_deg=math.degrees(math.atan2(heading[1], heading[0])),
                     angle_deg=round(angle, 2) if kind == "angled" else None,
                     note=f"parking_space way {wid}" + (f" ({'; '.join(told)})" if told
                                                        else ""))
    return slot, poly
