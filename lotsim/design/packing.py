"""Bays packed into rows along the sides of a candidate's aisles
(:mod:`lotsim.design.candidates`): each bay kept where it lies inside the plot, clear of
the islands, of every aisle and of the bays kept before it, with its centre out of the
gates' mouths; then compact bays in what the full ones left."""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import Polygon

from lotsim.design.drawn import CLEAR, EPS, DrawnAisle, DrawnRow, Module
from lotsim.design.plot import PlotSpec
from lotsim.lot.kinds import KINDS

PACK_STEP = 0.25
"""Where a bay does not fit, the next one is tried this much further along the aisle [m]."""


class _Things:
    """What bays keep :data:`CLEAR` from: aisle strips (by aisle id), islands (id ``""``)
    and the bays kept so far (each with its aisle and side); and ``mouths``, what their
    centres keep out of (:func:`~lotsim.design.gates._mouths`)."""

    def __init__(self, shapes: list[Polygon], owners: list[str], mouths=None):
        self.mouths = mouths
        self.fixed = shapes
        self.owners = owners
        self.fixed_tree = shapely.STRtree(shapes)
        self.bays: list[Polygon] = []
        self.bay_sides: list[tuple[str, str]] = []
        self.bay_tree = None

    def clear(self, bay: Polygon, aisle: str, beside: tuple[str, str] | None = None) -> bool:
        """Whether ``bay`` keeps clear of everything but its own aisle, which it may
        touch (its entry lies on the aisle's edge), and, with ``beside`` (aisle, side), the
        bays along that side, which it may touch as neighbours in a row do; and keeps its
        centre out of the gates' mouths."""
        if self.mouths is not None and self.mouths.intersects(bay.centroid):
            return False
        for i in self.fixed_tree.query(bay, predicate="dwithin", distance=CLEAR - EPS):
            if self.owners[i] != aisle or \
                    shapely.area(shapely.intersection(self.fixed[i], bay)) > 1e-6:
                return False
        if self.bay_tree is None:
            return True
        for i in self.bay_tree.query(bay, predicate="dwithin", distance=CLEAR - EPS):
            if beside is None or self.bay_sides[i] != beside or \
                    shapely.area(shapely.intersection(self.bays[i], bay)) > 1e-6:
                return False
        return True

    def add(self, bays: list[Polygon], side: tuple[str, str] = ("", "")) -> None:
        self.bays += bays
        self.bay_sides += [side] * len(bays)
        if self.bays:
            self.bay_tree = shapely.STRtree(self.bays)


def _compact_rows(plot: PlotSpec, sides: list[tuple[DrawnAisle, str, Module]],
                  room: Polygon, things: _Things, rows: list[DrawnRow]) -> list[DrawnRow]:
    """Compact bays (``plot.uses.compact``) packed, side by side in the order the full
    bays were, into what those left: a row's leftover length at its end, a stretch where
    a full bay did not fit; none where the plot asks for none."""
    size = plot.uses.compact
    if size is None:
        return []
    full: dict[tuple[str, str], list[float]] = {}
    for r in rows:
        step = KINDS["perpendicular" if r.angle == 90 else "angled"].pitch(
            plot.bay_width, plot.bay_length, math.radians(r.angle))
        full.setdefault((r.aisle, r.side), []).append(r.start + r.count * step)
    # tried first: right after each row of full bays, touching it as a neighbour does
    return [r for a, side, mod in sides
            for r in _pack(plot, a, side, mod, room, things, size,
                           seeds=full.get((a.id, side), []))]


def _pack(plot: PlotSpec, a: DrawnAisle, side: str, mod: Module, room: Polygon,
          things: _Things, size: tuple[float, float] | None = None,
          seeds: list[float] = ()) -> list[DrawnRow]:
    """Bays packed along one side of aisle ``a`` from its first end
    (:mod:`lotsim.design.candidates`), of the plot's size or of ``size`` (width, length [m]:
    compact bays, which may touch the bays along the same side, and are tried at the
    stations of ``seeds`` too); ``things`` gains them."""
    kind = KINDS["perpendicular" if mod.angle == 90 else "angled"]
    angle = math.radians(mod.angle)
    bay_w, bay_l = size or (plot.bay_width, plot.bay_length)
    beside = (a.id, side) if size is not None else None
    along = kind.frontage(bay_w, bay_l, angle)
    step = kind.pitch(bay_w, bay_l, angle)
    p0, p1 = np.asarray(a.start, dtype=float), np.asarray(a.end, dtype=float)
    length = float(np.hypot(*(p1 - p0)))
    u = (p1 - p0) / length
    left = np.array([-u[1], u[0]])
    n = left if side == "left" else -left
    origin = p0 + n * a.width / 2
    heading = math.atan2(u[1], u[0])
    placed: list[tuple[float, Polygon]] = []
    s = 0.0
    while s + along <= length + 1e-9:
        poly, _, _ = kind.place(origin, u, n, heading, s, bay_w, bay_l, angle,
                                toward_traffic=side == "right" or a.one_way)
        bay = Polygon(poly)
        ok = room.covers(bay) and things.clear(bay, a.id, beside)
        if ok and placed and abs(placed[-1][0] + step - s) > 1e-9:
            ok = placed[-1][1].distance(bay) >= CLEAR - EPS
        if ok:
            placed.append((s, bay))
            s += step
        else:
            later = [t for t in seeds if s + 1e-9 < t < s + PACK_STEP - 1e-9]
            s = min(later) if later else s + PACK_STEP
    rows: list[DrawnRow] = []
    for s, bay in placed:
        last = rows[-1] if rows else None
        if last is not None and abs(last.start + last.count * step - s) < 1e-6:
            last.count += 1
            last.polygons.append(bay)
        else:
            rows.append(DrawnRow(a.id, side, mod.angle, s, 1, [bay], size))
    things.add([b for _, b in placed], (a.id, side))
    return rows
