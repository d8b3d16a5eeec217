"""What is paved: the ground cars may drive on, and aisles drawn near one another without
joining.

A lot is paved wall to wall unless its scenario says otherwise (``lot.paved``,
:class:`~lotsim.lot.spec.PavementSpec`): then the pavement is its aisles (each with the inside of
its bends, where its lanes round the corners of its centre line), the kerb corners where
aisles join and its slots (unless ``aisles: false``), and the paved areas listed, all
within the boundary. Kerb corners round the inside corners where two aisles' strips
meet, with the kerb radius given (a morphological closing of the two strips, kept near
where they overlap), so a car turning from one onto the other has the ground a kerb
return gives it. Two aisles whose strips do not overlap are not joined: the ground between
them stays unpaved.
"""

from __future__ import annotations

import itertools

import shapely
from shapely.geometry import Point
from shapely.geometry.base import BaseGeometry
from shapely.ops import unary_union

from lotsim.lot.model import Aisle, Slot
from lotsim.lot.spec import PavementSpec

HEAL = 0.01
"""Cracks narrower than this between paved pieces that touch (slots along an aisle's
edge, up to rounding) are closed [m]."""
NEAR_MISS = 3.0
"""An aisle end this close to another aisle's strip without joining it is reported [m]."""


def kerb_corners(aisles: dict[str, Aisle], radius: float) -> list[BaseGeometry]:
    """The ground that rounds the inside corners where two aisles' strips overlap, each
    corner an arc of ``radius`` [m] tangent to both strips' edges."""
    if radius <= 0:
        return []
    out = []
    for a, b in itertools.combinations(aisles.values(), 2):
        if not a.polygon.intersects(b.polygon):
            continue
        both = a.polygon.union(b.polygon)
        closed = both.buffer(radius, quad_segs=16).buffer(-radius, quad_segs=16)
        near = a.polygon.intersection(b.polygon).buffer(radius + max(a.width, b.width))
        corner = closed.difference(both).intersection(near)
        if not corner.is_empty:
            out.append(corner)
    return out


def bend_insides(aisles: dict[str, Aisle]) -> list[BaseGeometry]:
    """The ground inside an aisle's bends that its lanes, rounding the corners of its centre
    line, run over: each lane's strip (its own share of the aisle's width) along its path."""
    out = []
    for a in aisles.values():
        if len(a.centerline) < 3:
            continue  # straight: its lanes run within its strip
        half = a.width / (2 if a.one_way else 4)
        out += [lane.line.buffer(half, cap_style="flat") for lane in a.lanes]
    return out


def pave(spec: PavementSpec, boundary: BaseGeometry, aisles: dict[str, Aisle],
         slots: tuple[Slot, ...], areas: list[BaseGeometry]) -> BaseGeometry:
    """The pavement of a lot whose scenario says what is paved: the aisles with their kerb
    corners (``spec.aisles``), the slots, the paved ``areas``, within ``boundary``."""
    pieces = [s.shape for s in slots] + list(areas)
    if spec.aisles:
        pieces += [a.polygon for a in aisles.values()]
        pieces += bend_insides(aisles)
        pieces += kerb_corners(aisles, spec.corner_radius)
    ground = unary_union(pieces)
    ground = ground.buffer(HEAL / 2, join_style="mitre").buffer(-HEAL / 2, join_style="mitre")
    parts = shapely.get_parts(ground.intersection(boundary))
    return unary_union([p for p in parts if p.geom_type == "Polygon" and p.area > 0])


def loose_ends(aisles: dict[str, Aisle], ground: BaseGeometry | None = None) -> list[str]:
    """Aisle ends drawn near another aisle without joining it: within ``NEAR_MISS`` of its
    strip, off its centre line (a join puts the end on it). With ``ground`` (a lot not
    paved wall to wall), also whether the gap is paved."""
    out = []
    for a in aisles.values():
        for end in (a.centerline[0], a.centerline[-1]):
            p = Point(end)
            if any(b is not a and b.line.distance(p) <= 1e-3 for b in aisles.values()):
                continue  # it joins an aisle: others near it are that junction's business
            for b in aisles.values():
                if b is a:
                    continue
                gap = b.polygon.distance(p)
                off = b.line.distance(p)
                if off <= 1e-3 or gap > NEAR_MISS:
                    continue
                if b.polygon.covers(p) and a.polygon.intersects(b.polygon) and off <= 0.5:
                    continue  # on the strip, nearly on the line: drawn as a join
                where = f"({end[0]:.1f}, {end[1]:.1f})"
                if gap > 1e-9:
                    what = f"ends {gap:.2f} m short of aisle {b.id!r} at {where}"
                else:
                    what = f"ends {off:.2f} m off the centre line of aisle {b.id!r} at {where}"
                paved = ""
                if ground is not None and gap > 1e-9:
                    bridge = shapely.shortest_line(p, b.polygon).buffer(a.width / 2)
                    paved = (" (the ground between is paved)"
                             if ground.covers(bridge) else " (the ground between is not paved)")
                out.append(f"aisle {a.id!r} {what} without joining it: put its end on "
                           f"the centre line of {b.id!r} to join them{paved}")
    return out

