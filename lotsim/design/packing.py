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
LOOK_FITS = 64
LOOK_MISSES = 16
"""How many stations ahead a row's bays are tried at once (bookkeeping: the same bays
whatever they are): as many as the row holds if each fits, up to this many; and this many
steps of :data:`PACK_STEP` if none does."""


def _walked(s: float, step: float, last: float, most: int) -> list[float]:
    """``s`` and the stations after it by ``step``, each added to the one before as the
    packing walk adds them, up to ``last`` (within 1e-9) and at most ``most`` of them."""
    out = [s]
    while len(out) < most and out[-1] + step <= last + 1e-9:
        out.append(out[-1] + step)
    return out


class _Things:
    """What bays keep :data:`CLEAR` from: aisle strips (by aisle id), islands (id ``""``)
    and the bays kept so far (each with its aisle and side); and ``mouths``, what their
    centres keep out of (:func:`~lotsim.design.gates._mouths`)."""

    def __init__(self, shapes: list[Polygon], owners: list[str], mouths=None):
        self.mouths = mouths
        if mouths is not None:
            shapely.prepare(mouths)
        self.fixed = np.array(shapes, dtype=object)
        self.owners = np.array(owners, dtype=object)
        self.fixed_tree = shapely.STRtree(shapes)
        self.bays = np.array([], dtype=object)
        self.bay_sides: list[tuple[str, str]] = []
        self.bay_tree = None

    def clear(self, bays: np.ndarray, aisle: str, beside: tuple[str, str] | None = None
              ) -> np.ndarray:
        """Whether each of ``bays`` (an array of polygons) keeps clear of everything but
        its own aisle, which it may touch (its entry lies on the aisle's edge), and, with
        ``beside`` (aisle, side), the bays along that side, which it may touch as
        neighbours in a row do; and keeps its centre out of the gates' mouths."""
        ok = np.ones(len(bays), dtype=bool)
        if self.mouths is not None:
            ok &= ~shapely.intersects(self.mouths, shapely.centroid(bays))
        # a bay within CLEAR of a thing is clear of it only when the thing is its own
        # aisle (or, for a compact bay, a bay beside it along the same side) and they
        # overlap by no area
        for tree, shapes, own in ((self.fixed_tree, self.fixed, self._owned(aisle)),
                                  (self.bay_tree, self.bays, self._beside(beside))):
            if tree is None:
                continue
            i, j = tree.query(bays, predicate="dwithin", distance=CLEAR - EPS)
            near = own[j]
            ok[i[~near]] = False
            i, j = i[near], j[near]
            overlap = shapely.area(shapely.intersection(shapes[j], bays[i])) > 1e-6
            ok[i[overlap]] = False
        return ok

    def _owned(self, aisle: str) -> np.ndarray:
        """Which fixed things a bay of ``aisle`` may touch: its aisle's strips."""
        return self.owners == aisle

    def _beside(self, beside: tuple[str, str] | None) -> np.ndarray:
        """Which bays kept a bay may touch: those along side ``beside``, if given."""
        if beside is None:
            return np.zeros(len(self.bays), dtype=bool)
        return np.array([side == beside for side in self.bay_sides], dtype=bool)

    def add(self, bays: list[Polygon], side: tuple[str, str] = ("", "")) -> None:
        self.bays = np.concatenate([self.bays, np.array(bays, dtype=object)])
        self.bay_sides += [side] * len(bays)
        if len(self.bays):
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
    toward = side == "right" or a.one_way
    shapely.prepare(room)
    known: dict[float, tuple[bool, Polygon]] = {}

    def look(s: float) -> tuple[bool, Polygon]:
        """Whether a bay at station ``s`` fits, and the bay; worked out, when not yet, for
        the stations the walk below comes to next if it fits each time and if it fits
        none (the same floats it adds up), all at once."""
        got = known.get(s)
        if got is not None:
            return got
        ahead = _walked(s, step, length - along, LOOK_FITS)
        ahead += _walked(s, PACK_STEP, length - along, LOOK_MISSES)[1:]
        stations = np.array([t for t in ahead if t not in known])
        corners, _, _ = kind.place(origin, u, n, heading, stations[:, None], bay_w, bay_l,
                                   angle, toward_traffic=toward)
        bays = shapely.polygons(np.transpose(corners, (1, 0, 2)))
        fits = shapely.covers(room, bays) & things.clear(bays, a.id, beside)
        known.update(zip(stations.tolist(), zip(fits.tolist(), bays, strict=True),
                         strict=True))
        return known[s]

    placed: list[tuple[float, Polygon]] = []
    s = 0.0
    while s + along <= length + 1e-9:
        ok, bay = look(s)
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
