"""Candidate layouts of a plot, drawn by geometry alone: where the aisles and the bays go.

A candidate is drawn in a frame turned by ``orientation``, in which its module aisles run
along x:

* **Circulation.** The plot, less its islands, shrunk by one bay length plus half the
  circulation width, is the inside of a two-way *ring* aisle: every edge of the shrunk
  outline (and of each island's grown one) is one straight aisle, and the aisles of a ring
  meet end to end at its corners. Bays line the ring on both sides: between it and the
  boundary (perimeter rows), and inside.
* **Modules.** Inside the ring, aisles run along x every *module pitch* (a row of bays,
  the aisle, a row of bays), shifted by ``offset``; each is the part of its line inside the
  ring and ends on the ring at both ends (a T). 90° modules are two-way (or one-way where
  the designer asks for it); 60° and 45° modules are one-way, alternately east and west,
  their bays leaning the way the aisle runs.
* **Gates.** From each gate a straight two-way aisle runs in, square to the boundary,
  until it meets the first aisle it crosses; its entrance and exit stand near the
  boundary, on its inward and outward lanes.
* **Bays.** Along each side of each aisle, bays are packed from its first end: a bay is
  kept where it lies inside the plot, clear of the islands, of every aisle and of the bays
  kept before it (perimeter rows first, then the modules' rows, then the ring's inner
  rows, or the ring's inner rows before the modules': ``inner_first``). Each unbroken run
  of bays is one row of the scenario.

A *spine* candidate (:func:`draw_spine`), for a plot too small or too narrow for a ring,
runs a two-way aisle straight in from a gate, as far as the plot allows, with bays along
both sides, and perhaps branches off it at right angles, lined with bays too.

Which bays are *usable* is not decided here: :mod:`lotsim.design.preparing` prepares the
candidate's scenario with lotsim's maneuver planner and reachability, and drops the bays
some vehicle type cannot reach, park in or leave.

What a candidate is drawn as is :mod:`~lotsim.design.drawn`'s; the ring's inside and how
module aisles meet it, :mod:`~lotsim.design.ring`'s; the gates' aisles, entrances, exits
and mouths, :mod:`~lotsim.design.gates`'; the bays packed into rows along the aisles,
:mod:`~lotsim.design.packing`'s. This module draws the whole from them.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from shapely.geometry import LineString, Polygon
from shapely.ops import unary_union

from lotsim.design.drawn import (
    CLEAR,
    EPS,
    Candidate,
    DrawnAisle,
    DrawnGate,
    DrawnRow,
    Module,
    Point2,
    strip,
)
from lotsim.design.gates import (
    GATE_MIN,
    _bends,
    _gate_aisles,
    _gate_on_ring,
    _gate_poses,
    _inward,
    _mouths,
    _ways_in,
    edge_of,
)
from lotsim.design.packing import _compact_rows, _pack, _Things
from lotsim.design.plot import PlotSpec
from lotsim.design.ring import _beside_ring, _meets_ring, _ring_region, _rings, _side_is_inner

MIN_MODULE = 12.0
"""A module aisle shorter than this is not drawn [m]."""
DEAD_END_ROOM = 1.0
"""A module aisle that ends short of an island ends this much further from it than its
half-width [m]."""


def modules_of(plot: PlotSpec) -> list[Module]:
    """The module kinds a plot allows, 90° two-way first; 90° one-way modules only where
    their aisle is narrower than the two-way one (else they would only lose a way)."""
    out = []
    for angle in plot.angles:
        if angle == 90:
            two, one = plot.aisle_width(90, "two-way"), plot.aisle_width(90, "one-way")
            out.append(Module(90, False, two))
            if plot.one_way and one < two:
                out.append(Module(90, True, one))
        elif plot.one_way:
            out.append(Module(angle, True, plot.aisle_width(angle, "one-way")))
    return out


def orientations(plot: PlotSpec, most: int) -> list[float]:
    """The directions module aisles may run [degrees, 0 ≤ θ < 180]: along each edge of the
    boundary and square to it, the longest edges' first, alike ones (within 1°) once."""
    pts = np.asarray(plot.boundary, dtype=float)
    d = np.roll(pts, -1, axis=0) - pts
    lengths = np.hypot(d[:, 0], d[:, 1])
    out: list[float] = []
    for k in np.argsort(-lengths, kind="stable"):
        base = math.degrees(math.atan2(d[k, 1], d[k, 0])) % 180.0
        for a in (base, (base + 90.0) % 180.0):
            if all(min(abs(a - b), 180 - abs(a - b)) > 1.0 for b in out):
                out.append(round(a, 6))
    return out[: max(1, most)]


def depth(module: Module, plot: PlotSpec) -> float:
    """How deep a bay of ``module`` reaches from its aisle's edge [m]."""
    a = math.radians(module.angle)
    return plot.bay_length * math.sin(a) + plot.bay_width * math.cos(a)


def pitch(module: Module, plot: PlotSpec) -> float:
    """The distance between neighbouring module aisles [m]: bays, aisle, bays, and
    :data:`CLEAR` between the bays of neighbouring modules."""
    return 2 * depth(module, plot) + module.width + CLEAR


class _Frame:
    """Plot coordinates ↔ a frame turned by ``theta`` about the plot's first point."""

    def __init__(self, origin: Point2, theta: float):
        self.o = np.asarray(origin, dtype=float)
        self.c, self.s = math.cos(theta), math.sin(theta)

    def to_local(self, pts) -> np.ndarray:
        p = np.asarray(pts, dtype=float) - self.o
        return np.column_stack([p[:, 0] * self.c + p[:, 1] * self.s,
                                -p[:, 0] * self.s + p[:, 1] * self.c])

    def to_plot(self, pts) -> np.ndarray:
        p = np.asarray(pts, dtype=float)
        return np.column_stack([p[:, 0] * self.c - p[:, 1] * self.s,
                                p[:, 0] * self.s + p[:, 1] * self.c]) + self.o




def draw(plot: PlotSpec, module: Module, orientation_deg: float, offset: float,
         inner_first: bool, ring_islands: bool = True, along: tuple[int, ...] = (), *,
         turned: bool = False) -> Candidate | None:
    """One candidate of ``plot`` (see the module's description); None where the plot has no
    room for a ring, or a gate's aisle meets none. Without ``ring_islands``, the ring runs
    round the plot only, and a module aisle that meets an island ends short of it (a dead
    end, where cars turn round; two-way modules only). Along the boundary's edges
    ``along`` (their indices: edge ``k`` runs from point ``k`` to the next), the ring runs
    beside the boundary, with no perimeter row, and a gate on such an edge opens straight
    onto the ring (:func:`~lotsim.design.gates._gate_on_ring`). With ``turned``, a gate
    whose aisle cannot be drawn square to its edge gets one turned, straight or bent once
    (:func:`~lotsim.design.gates._gate_aisles`).

    Examples
    --------
    >>> from lotsim.design.plot_yaml import read_plot
    >>> plot = read_plot("boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]\\n"
    ...                  "gates: [{id: in, at: [30, 0]}]\\nbays: {angles_deg: [90]}\\n")
    >>> c = draw(plot, modules_of(plot)[0], 0.0, 0.0, False)
    >>> c.bays > 0, [a.role for a in c.aisles].count("ring")
    (True, 4)
    """
    theta = math.radians(orientation_deg)
    frame = _Frame(plot.boundary[0], theta)
    outline = Polygon(frame.to_local(plot.boundary))
    islands = [Polygon(frame.to_local(i.polygon)) for i in plot.islands]
    ring_w = plot.circulation_width
    perimeter = plot.bay_length + ring_w / 2 + CLEAR
    inside = _ring_region(outline, islands if ring_islands else [], perimeter, along,
                          ring_w / 2 + CLEAR)
    if inside is None:
        return None
    if not ring_islands and (module.one_way or not islands):
        return None
    aisles: list[DrawnAisle] = []
    legs: list[tuple[Point2, Point2]] = []
    for k, ring in enumerate(_rings(inside)):
        n = len(ring)
        for i in range(n):
            a, b = tuple(ring[i]), tuple(ring[(i + 1) % n])
            legs.append((a, b))
            aisles.append(DrawnAisle(f"r{k + 1}-{i + 1}", a, b, ring_w, False, "ring"))
    ring_lines = [LineString(leg) for leg in legs]
    ring_strips = unary_union([strip(a, b, ring_w) for a, b in legs])
    kept_clear = unary_union([i.buffer(CLEAR) for i in islands]) if islands else None
    if kept_clear is not None and ring_strips.intersects(kept_clear):
        return None
    # where module aisles may run: inside the ring, and short of the islands by the
    # turnaround room of a dead end (without ring_islands)
    room_for_modules = inside
    if not ring_islands:
        room_for_modules = inside.difference(unary_union(
            [i.buffer(module.width / 2 + CLEAR + DEAD_END_ROOM, join_style="mitre")
             for i in islands]))

    # module aisles: the parts inside the ring of lines along x, one pitch apart, each at
    # least a ring's inner row and its own row of bays from a ring leg it runs beside
    p = pitch(module, plot)
    beside = ring_w / 2 + plot.bay_length + CLEAR + depth(module, plot) + module.width / 2
    x0, y0, x1, y1 = inside.bounds
    first = y0 + (offset % p)
    modules: list[tuple[Point2, Point2]] = []
    y = first
    k = 0
    while y < y1:
        cut = LineString([(x0 - 1, y), (x1 + 1, y)]).intersection(room_for_modules)
        for seg in sorted(getattr(cut, "geoms", [cut]), key=lambda g: g.bounds):
            if seg.geom_type != "LineString" or seg.length < MIN_MODULE:
                continue
            (ax, _), (bx, _) = seg.coords[0], seg.coords[-1]
            a, b = (ax, y), (bx, y)
            ends = _meets_ring(a, ring_lines), _meets_ring(b, ring_lines)
            if ends == (None, None) or (None in ends and (ring_islands or module.one_way)):
                continue
            ends = tuple(math.pi / 2 if e is None else e for e in ends)  # a dead end
            # clear of the ring except where it ends on it: the strip of a ring leg met at
            # φ reaches ring_w / 2 / sin φ + width / 2 / tan φ along the module's centre line
            ta, tb = (ring_w / 2 / math.sin(phi) + module.width / 2 / abs(math.tan(phi)) + 0.5
                      for phi in ends)
            if seg.length <= ta + tb + 1.0:
                continue
            core = strip((ax + ta, y), (bx - tb, y), module.width + 2 * CLEAR)
            if core.intersects(ring_strips) or _beside_ring(ax, bx, y, legs, beside):
                continue
            if module.one_way and k % 2 == 1:
                a, b = b, a
            modules.append((a, b))
            k += 1
        y += p
    for i, (a, b) in enumerate(modules):
        aisles.append(DrawnAisle(f"m{i + 1}", a, b, module.width, module.one_way, "module"))

    # gate aisles
    gates: list[DrawnGate] = []
    gate_aisles: list[DrawnAisle] = []
    local_gates = frame.to_local([g.at for g in plot.gates])
    lines = [(LineString([a.start, a.end]), a) for a in aisles]
    for g, at in zip(plot.gates, local_gates, strict=True):
        if edge_of(outline, at) in along:
            gate = _gate_on_ring(plot, g.id, at, aisles)
            if gate is None:
                return None
            gates.append(gate)
            continue
        drawn = _gate_aisles(plot, g.id, at, outline, lines, turned=turned,
                             islands=islands)
        if drawn is None:
            return None
        gate_aisles += drawn[0]
        gates.append(drawn[1])
    aisles += gate_aisles

    strips = [strip(a.start, a.end, a.width) for a in aisles]
    bends = _bends(gate_aisles)
    things = _Things(strips + islands + bends,
                     [a.id for a in aisles] + [""] * (len(islands) + len(bends)),
                     _mouths(plot, gates))
    room = outline.buffer(-(CLEAR - EPS), join_style="mitre")
    rows: list[DrawnRow] = []
    ring90 = Module(90, False, ring_w)
    order = ([("ring", "outer", ring90), ("ring", "inner", ring90), ("module", "", module)]
             if inner_first else
             [("ring", "outer", ring90), ("module", "", module), ("ring", "inner", ring90)])
    sides = []
    for role, which, mod in order:
        for a in aisles:
            if a.role != role:
                continue
            for side in ("left", "right"):
                if role == "ring" and _side_is_inner(a, side, inside) != (which == "inner"):
                    continue
                sides.append((a, side, mod))
                rows += _pack(plot, a, side, mod, room, things)
    rows += _compact_rows(plot, sides, room, things, rows)
    cand = Candidate(orientation_deg, module, offset, inner_first, aisles, rows, gates,
                     ring_islands and bool(islands), along=tuple(along))
    return _to_plot(cand, frame)

def draw_spine(plot: PlotSpec, gate: int, offset: float, branches: bool,
               branches_first: bool = True, *, turned: bool = False) -> Candidate | None:
    """A candidate for a plot too small or too narrow for a ring: a two-way *spine* aisle
    from gate ``gate`` straight in, square to its edge, as far as the plot allows (a dead
    end, where cars turn round), with bays along both sides; with ``branches``, two-way
    aisles off it at right angles, one 90° module pitch apart from ``offset`` past the
    gate's entrance and exit, each as long as the plot allows (dead ends too). With
    ``turned``, where the square spine has no room or no bay along it (a gate at a corner,
    in a spike, on the edge of a notch), the spine is turned: of the ways in of
    :func:`~lotsim.design.gates._ways_in`, the one that runs furthest; and the other
    gates' aisles may turn (:func:`~lotsim.design.gates._gate_aisles`). The plot's other
    gates each get an aisle to the first aisle they meet. None where the spine has no room.

    Examples
    --------
    >>> from lotsim.design.plot_yaml import read_plot
    >>> plot = read_plot("boundary: [[0, 0], [24, 0], [24, 30], [0, 30]]\\n"
    ...                  "gates: [{id: in, at: [12, 0]}]\\n")
    >>> c = draw_spine(plot, 0, 0.0, False)
    >>> [a.role for a in c.aisles], c.bays  # none within 10 m of the gate's mouth
    (['gate'], 16)
    """
    cand = _spine(plot, gate, offset, branches, branches_first, False, turned)
    if turned and (cand is None or cand.bays == 0):
        return _spine(plot, gate, offset, branches, branches_first, True, True) or cand
    return cand


def _spine(plot: PlotSpec, gate: int, offset: float, branches: bool, branches_first: bool,
           turn: bool, turned: bool) -> Candidate | None:
    """:func:`draw_spine`'s candidate, its spine square to the gate's edge or, with
    ``turn``, turned; ``turned``: the other gates' aisles may turn."""
    w = plot.circulation_width
    outline = Polygon(plot.boundary)
    islands = [Polygon(i.polygon) for i in plot.islands]
    blocked = unary_union([i.buffer(CLEAR) for i in islands]) if islands else None
    g = plot.gates[gate]
    start, n = _inward(outline, np.asarray(g.at, dtype=float), w)

    def reach(p0: np.ndarray, u: np.ndarray, first: float) -> float:
        """How far an aisle from ``p0`` along ``u`` may run, its strip inside the plot and
        clear of the islands past ``first`` [m]."""
        top = 2.0 * math.dist(*np.asarray(outline.bounds).reshape(2, 2))
        lo, hi = first, top
        def fits(t: float) -> bool:
            band = strip(tuple(p0 + u * first), tuple(p0 + u * t), w)
            return outline.covers(band) and (blocked is None or band.disjoint(blocked))
        if not fits(first + 0.5):
            return 0.0
        while hi - lo > 0.05:
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if fits(mid) else (lo, mid)
        return lo - DEAD_END_ROOM

    length = reach(start, n, 1.0)
    approach = None
    if turn:  # as far in as the plot allows
        ways = _ways_in(outline, np.asarray(g.at, dtype=float), w)
        reaches = [reach(p0, d, 1.0) for p0, d in ways]
        if not ways:
            return None
        k = int(np.argmax(reaches))  # the first of the longest
        length, (start, n) = reaches[k], ways[k]
        approach = (tuple(map(float, g.at)), tuple(map(float, start)))
    if length < GATE_MIN:
        return None
    heading = math.atan2(n[1], n[0])
    aisles = [DrawnAisle(f"gate-{g.id}", tuple(map(float, start)),
                         tuple(map(float, start + n * length)), w, False, "gate")]
    gates = [dataclasses.replace(_gate_poses(plot, g.id, aisles[0].id, start, n),
                                 approach=approach)]
    if branches:
        right = np.array([n[1], -n[0]])
        step = pitch(Module(90, False, w), plot)
        s0 = max(v.front for v in plot.vehicle_types) + 1.5 + w / 2 + plot.bay_width + offset
        k = 0
        while s0 + k * step + w / 2 <= length - 1.0:
            at = start + n * (s0 + k * step)
            for side, u in (("R", right), ("L", -right)):
                t = reach(at, u, w / 2 + 0.5)
                if t >= MIN_MODULE + w / 2:
                    aisles.append(DrawnAisle(f"b{k + 1}{side}", tuple(map(float, at)),
                                             tuple(map(float, at + u * t)), w, False,
                                             "module"))
            k += 1
    lines = [(LineString([a.start, a.end]), a) for a in aisles]
    for other in plot.gates[:gate] + plot.gates[gate + 1:]:
        drawn = _gate_aisles(plot, other.id, np.asarray(other.at, dtype=float), outline,
                             lines, turned=turned, islands=islands)
        if drawn is None:
            return None
        aisles += drawn[0]
        gates.append(drawn[1])
    strips = [strip(a.start, a.end, a.width) for a in aisles]
    bends = _bends(aisles)
    things = _Things(strips + islands + bends,
                     [a.id for a in aisles] + [""] * (len(islands) + len(bends)),
                     _mouths(plot, gates))
    room = outline.buffer(-(CLEAR - EPS), join_style="mitre")
    rows: list[DrawnRow] = []
    spine90 = Module(90, False, w)
    order = ("module", "gate") if branches_first else ("gate", "module")
    sides = [(a, side, spine90) for role in order for a in aisles if a.role == role
             for side in ("left", "right")]
    for a, side, mod in sides:
        rows += _pack(plot, a, side, mod, room, things)
    rows += _compact_rows(plot, sides, room, things, rows)
    return Candidate(math.degrees(heading) % 180.0, spine90, offset, not branches_first,
                     aisles, rows, gates, spine=(g.id, branches))



def _to_plot(c: Candidate, frame: _Frame) -> Candidate:
    """``c`` with every point and polygon turned back into plot coordinates."""
    def pt(p):
        return tuple(float(v) for v in frame.to_plot([p])[0])

    def pose(q):
        x, y = frame.to_plot([q[:2]])[0]
        th = q[2] + math.atan2(frame.s, frame.c)
        return float(x), float(y), float(math.atan2(math.sin(th), math.cos(th)))

    aisles = [DrawnAisle(a.id, pt(a.start), pt(a.end), a.width, a.one_way, a.role)
              for a in c.aisles]
    rows = [DrawnRow(r.aisle, r.side, r.angle, r.start, r.count,
                     [Polygon(frame.to_plot(np.asarray(p.exterior.coords)))
                      for p in r.polygons], r.size) for r in c.rows]
    gates = [DrawnGate(g.id, g.aisle, pose(g.entrance), pose(g.exit),
                       None if g.mouth is None else (pt(g.mouth[0]), pt(g.mouth[1])),
                       None if g.approach is None else (pt(g.approach[0]),
                                                        pt(g.approach[1])))
             for g in c.gates]
    return Candidate(c.orientation_deg, c.module, c.offset, c.inner_first, aisles, rows, gates,
                     c.ringed, c.spine, c.along)
