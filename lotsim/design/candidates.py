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

Which bays are *usable* is not decided here: :mod:`lotsim.design.search` prepares the
candidate's scenario with lotsim's maneuver planner and reachability, and drops the bays
some vehicle type cannot reach, park in or leave.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

from lotsim.design.plot import PlotSpec
from lotsim.lot.kinds import KINDS

Point2 = tuple[float, float]

CLEAR = 0.05
"""Bays, aisles and islands are kept this far apart in the drawing [m], so that the
scenario's numbers, written to the centimetre, never make them overlap."""
EPS = 1e-6
"""Things drawn exactly :data:`CLEAR` apart are clear, whatever the rounding of a turned
frame [m]."""
PACK_STEP = 0.25
"""Where a bay does not fit, the next one is tried this much further along the aisle [m]."""
MIN_MODULE = 12.0
"""A module aisle shorter than this is not drawn [m]."""
MIN_JUNCTION_DEG = 30.0
"""A module or gate aisle meets the aisle it ends on at least at this angle [degrees]."""
SIMPLIFY = 0.3
"""The ring's outline is simplified within this [m]: no leg of a few centimetres."""
MIN_LEG = 4.0
"""A ring with a leg shorter than this is simplified further [m]."""
DEAD_END_ROOM = 1.0
"""A module aisle that ends short of an island ends this much further from it than its
half-width [m]."""
GATE_INSET = 0.02
"""A gate's aisle begins this far inside the boundary [m]: written to the centimetre, its
first point stays inside."""
GATE_MIN = 7.0
"""A gate aisle is at least this long [m]: room for its entrance and exit."""
GATE_MAX = 80.0
"""A gate aisle meets another aisle within this distance of its gate [m]."""


@dataclass(frozen=True, slots=True)
class Module:
    """A module kind: bays at ``angle`` [degrees] on aisles of ``width`` [m]; ``one_way``
    aisles are driven one way."""

    angle: int
    one_way: bool
    width: float

    @property
    def label(self) -> str:
        return f"{self.angle}° {'one-way' if self.one_way else 'two-way'}"


@dataclass
class DrawnAisle:
    """A straight aisle of a candidate, in plot coordinates: ``role`` is ``ring``,
    ``module`` or ``gate``."""

    id: str
    start: Point2
    end: Point2
    width: float
    one_way: bool
    role: str


@dataclass
class DrawnRow:
    """An unbroken run of equal bays along one side of an aisle; ``size`` (width, length
    [m]) is that of compact bays, None the plot's bays."""

    aisle: str
    side: str
    angle: int
    start: float
    count: int
    polygons: list[Polygon] = field(default_factory=list)
    size: tuple[float, float] | None = None


@dataclass
class DrawnGate:
    """A gate's entrance and exit: poses (x, y, heading [rad]) on its aisle; its ``mouth``,
    the stretch of boundary, as wide as the aisle, where the aisle meets it."""

    id: str
    aisle: str
    entrance: tuple[float, float, float]
    exit: tuple[float, float, float]
    mouth: tuple[Point2, Point2] | None = None


@dataclass
class Candidate:
    """One drawn layout: its aisles, rows and gates in plot coordinates, and the choices
    that drew it."""

    orientation_deg: float
    module: Module
    offset: float
    inner_first: bool
    aisles: list[DrawnAisle]
    rows: list[DrawnRow]
    gates: list[DrawnGate]
    ringed: bool = False
    """Whether the ring also runs round each island."""
    spine: tuple[str, bool] | None = None
    """For a spine candidate (:func:`draw_spine`): its gate, and whether it has branches."""
    along: tuple[int, ...] = ()
    """The boundary's edges the ring runs beside, with no perimeter row (:func:`draw`)."""

    @property
    def bays(self) -> int:
        return sum(r.count for r in self.rows)

    @property
    def aisle_length(self) -> float:
        """Total length of the aisles' centre lines [m]."""
        return float(sum(math.dist(a.start, a.end) for a in self.aisles))

    @property
    def label(self) -> str:
        if self.spine is not None:
            gate, branches = self.spine
            what = (f", branches from {self.offset:.2f} m, "
                    f"{'spine rows first' if self.inner_first else 'branches first'}"
                    if branches else "")
            return f"a 90° two-way spine from gate {gate}{what}"
        order = "inner rows first" if self.inner_first else "modules first"
        ring = ", islands ringed" if self.ringed else ""
        if self.along:
            ring += ", the ring along the gates' edges"
        return (f"{self.module.label} modules at {self.orientation_deg:.1f}°, offset "
                f"{self.offset:.2f} m, {order}{ring}")


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


def _strip(a: Point2, b: Point2, width: float) -> Polygon:
    return LineString([a, b]).buffer(width / 2, cap_style="flat")


def _rings(region: Polygon) -> list[np.ndarray]:
    """The closed outlines (exterior, then holes) of ``region``, counter-clockwise, without
    the repeated last point."""
    out = []
    for ring in [region.exterior, *region.interiors]:
        pts = np.asarray(ring.coords)[:-1]
        out.append(pts)
    return out


def draw(plot: PlotSpec, module: Module, orientation_deg: float, offset: float,
         inner_first: bool, ring_islands: bool = True, along: tuple[int, ...] = ()
         ) -> Candidate | None:
    """One candidate of ``plot`` (see the module's description); None where the plot has no
    room for a ring, or a gate's aisle meets none. Without ``ring_islands``, the ring runs
    round the plot only, and a module aisle that meets an island ends short of it (a dead
    end, where cars turn round; two-way modules only). Along the boundary's edges
    ``along`` (their indices: edge ``k`` runs from point ``k`` to the next), the ring runs
    beside the boundary, with no perimeter row, and a gate on such an edge opens straight
    onto the ring (:func:`_gate_on_ring`).

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
    ring_strips = unary_union([_strip(a, b, ring_w) for a, b in legs])
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
            core = _strip((ax + ta, y), (bx - tb, y), module.width + 2 * CLEAR)
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
        drawn = _gate(plot, g.id, at, outline, lines)
        if drawn is None:
            return None
        aisle, gate = drawn
        gate_aisles.append(aisle)
        gates.append(gate)
    aisles += gate_aisles

    strips = [_strip(a.start, a.end, a.width) for a in aisles]
    things = _Things(strips + islands, [a.id for a in aisles] + [""] * len(islands),
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


BESIDE_DEG = 15.0
"""A module aisle runs beside a ring leg that makes less than this angle with it
[degrees]."""


def _beside_ring(ax: float, bx: float, y: float, legs: list[tuple[Point2, Point2]],
                 room: float) -> bool:
    """Whether the module aisle along x from ``ax`` to ``bx`` at ``y`` runs beside a ring leg
    (within :data:`BESIDE_DEG` of its direction, alongside it for a metre or more) closer
    than ``room`` [m], measured at the middle of the stretch they run alongside: two aisles
    side by side with no room for a row of bays each between them."""
    lo, hi = min(ax, bx), max(ax, bx)
    for (px, py), (qx, qy) in legs:
        dx, dy = qx - px, qy - py
        if abs(dy) > math.sin(math.radians(BESIDE_DEG)) * math.hypot(dx, dy):
            continue
        a, b = max(lo, min(px, qx)), min(hi, max(px, qx))
        if b - a < 1.0:
            continue
        mid = (a + b) / 2
        if abs(py + (mid - px) * dy / dx - y) < room - EPS:
            return True
    return False


def _ring_region(outline: Polygon, islands: list[Polygon], d: float,
                 along: tuple[int, ...] = (), near: float = 0.0) -> Polygon | None:
    """The inside of the ring aisle: the outline shrunk by ``d`` (by ``near`` along the
    edges ``along``), less the islands grown by ``d``; its largest part, simplified so that
    no leg is very short."""
    if along:
        inner = outline.buffer(-near, join_style="mitre")
        pts = np.asarray(outline.exterior.coords)[:-1]
        turn = 1.0 if outline.exterior.is_ccw else -1.0
        for k in range(len(pts)):
            if k in along:
                continue
            a, b = pts[k], pts[(k + 1) % len(pts)]
            u = (b - a) / np.hypot(*(b - a))
            n = turn * np.array([-u[1], u[0]])  # inward
            inner = inner.difference(Polygon([a - u * d, b + u * d, b + u * d + n * d,
                                              a - u * d + n * d]))
    else:
        inner = outline.buffer(-d, join_style="mitre")
    for isl in islands:
        inner = inner.difference(isl.buffer(d, join_style="mitre"))
    if inner.is_empty:
        return None
    if inner.geom_type != "Polygon":
        parts = [g for g in getattr(inner, "geoms", []) if g.geom_type == "Polygon"]
        if not parts:
            return None
        inner = max(parts, key=lambda g: (g.area, g.bounds))
    tol = SIMPLIFY
    for _ in range(6):
        simple = inner.simplify(tol, preserve_topology=True)
        if simple.is_valid and not simple.is_empty and simple.geom_type == "Polygon":
            legs = [np.hypot(*np.diff(r, axis=0, append=r[:1]).T) for r in _rings(simple)]
            if min(float(x.min()) for x in legs) >= MIN_LEG:
                return shapely.geometry.polygon.orient(simple)
        tol *= 2
    return None


def _meets_ring(p: Point2, ring_lines: list[LineString]) -> float | None:
    """The angle [rad] at which a line along x through ``p`` meets the ring leg ``p`` lies
    on, where it is at least :data:`MIN_JUNCTION_DEG`; else None."""
    pt = Point(p)
    for line in ring_lines:
        if line.distance(pt) < 1e-6:
            (ax, ay), (bx, by) = line.coords
            ang = abs(math.degrees(math.atan2(by - ay, bx - ax))) % 180
            ang = min(ang, 180 - ang)
            if ang >= MIN_JUNCTION_DEG:
                return math.radians(ang)
    return None


def _side_is_inner(a: DrawnAisle, side: str, inside: Polygon) -> bool:
    """Whether ``side`` of ring aisle ``a`` faces the inside of the ring."""
    mx, my = (a.start[0] + a.end[0]) / 2, (a.start[1] + a.end[1]) / 2
    ux, uy = a.end[0] - a.start[0], a.end[1] - a.start[1]
    n = math.hypot(ux, uy)
    lx, ly = -uy / n, ux / n
    s = 1.0 if side == "left" else -1.0
    return inside.contains(Point(mx + s * lx * 0.5, my + s * ly * 0.5))


def _gate(plot: PlotSpec, gid: str, at: np.ndarray, outline: Polygon,
          lines: list[tuple[LineString, DrawnAisle]]) -> tuple[DrawnAisle, DrawnGate] | None:
    """The aisle from a gate square to its boundary edge into the lot, to the first aisle
    it meets, with the gate's entrance and exit on it; None when it meets none in reach."""
    start, n = _inward(outline, at, plot.circulation_width)
    ray = LineString([start, start + n * GATE_MAX])
    best = None
    for line, _ in lines:
        hit = ray.intersection(line)
        if hit.is_empty or hit.geom_type != "Point":
            continue
        t = float(np.dot(np.asarray(hit.coords[0]) - start, n))
        (ax, ay), (bx, by) = line.coords
        ang = abs(math.degrees(math.atan2(by - ay, bx - ax) - math.atan2(n[1], n[0]))) % 180
        if min(ang, 180 - ang) < MIN_JUNCTION_DEG:
            continue
        if t >= GATE_MIN and (best is None or t < best[0]):
            best = (t, np.asarray(hit.coords[0]))
    if best is None:
        return None
    end = best[1]
    if not outline.buffer(1e-6).covers(LineString([start, end])):
        return None
    aisle = DrawnAisle(f"gate-{gid}", tuple(start), tuple(end), plot.circulation_width, False,
                       "gate")
    return aisle, _gate_poses(plot, gid, aisle.id, start, n)


def gate_edges(plot: PlotSpec) -> tuple[int, ...]:
    """The boundary's edges a ring may run beside so that the gates open straight onto it:
    each gate's edge, and the edge beyond the nearer corner of a gate closer to it than a
    perimeter row and half the ring (its aisle would meet the ring at that corner)."""
    outline = Polygon(plot.boundary)
    pts = np.asarray(plot.boundary, dtype=float)
    reach = plot.bay_length + plot.circulation_width / 2 + CLEAR
    out: set[int] = set()
    for g in plot.gates:
        k = edge_of(outline, g.at)
        a, b = pts[k], pts[(k + 1) % len(pts)]
        s = float(np.dot(np.asarray(g.at) - a, (b - a) / np.hypot(*(b - a))))
        out.add(k)
        if s < reach:
            out.add((k - 1) % len(pts))
        if np.hypot(*(b - a)) - s < reach:
            out.add((k + 1) % len(pts))
    return tuple(sorted(out))


def edge_of(outline: Polygon, at) -> int:
    """The index of the boundary's edge nearest the point ``at`` (edge ``k`` runs from
    point ``k`` to the next)."""
    ring = np.asarray(outline.exterior.coords)
    g = Point(at)
    return int(np.argmin([LineString(ring[i:i + 2]).distance(g) for i in range(len(ring) - 1)]))


def _gate_on_ring(plot: PlotSpec, gid: str, at: np.ndarray, aisles: list[DrawnAisle]
                  ) -> DrawnGate | None:
    """A gate that opens straight onto the ring leg running beside its edge: its entrance
    on the leg's lane nearer the boundary, heading the way that lane runs, and its exit on
    the other lane, heading the other way, both abeam of the gate (moved along the leg, at
    most half its width and :data:`CLEAR`, where the gate lies beyond the leg's end); None
    where no leg runs beside it."""
    w = plot.circulation_width
    g = np.asarray(at, dtype=float)
    for a in aisles:
        if a.role != "ring":
            continue
        p0, p1 = np.asarray(a.start, dtype=float), np.asarray(a.end, dtype=float)
        length = float(np.hypot(*(p1 - p0)))
        u = (p1 - p0) / length
        s = float(np.dot(g - p0, u))
        off = float(u[0] * (g - p0)[1] - u[1] * (g - p0)[0])  # > 0: the gate is left of it
        if abs(abs(off) - (w / 2 + CLEAR)) > 0.5 or not -(w / 2 + CLEAR) - EPS <= s <= \
                length + w / 2 + CLEAR + EPS:
            continue
        s = min(max(s, 0.0), length)
        heading = math.atan2(u[1], u[0])
        if off > 0:  # the lane nearer the gate runs against the leg
            heading += math.pi
        side = math.copysign(w / 4, off)
        left = np.array([-u[1], u[0]])
        inward = p0 + u * s + left * side
        outward = p0 + u * s - left * side
        edge = p0 + u * s + left * math.copysign(w / 2 + CLEAR, off)
        mouth = (tuple(map(float, edge - u * w / 2)), tuple(map(float, edge + u * w / 2)))
        return DrawnGate(gid, a.id, (*map(float, inward), heading),
                         (*map(float, outward), heading + math.pi), mouth)
    return None


def draw_spine(plot: PlotSpec, gate: int, offset: float, branches: bool,
               branches_first: bool = True) -> Candidate | None:
    """A candidate for a plot too small or too narrow for a ring: a two-way *spine* aisle
    from gate ``gate`` straight in, square to its edge, as far as the plot allows (a dead
    end, where cars turn round), with bays along both sides; with ``branches``, two-way
    aisles off it at right angles, one 90° module pitch apart from ``offset`` past the
    gate's entrance and exit, each as long as the plot allows (dead ends too). The plot's
    other gates each get an aisle to the first aisle they meet. None where the spine has no
    room.

    Examples
    --------
    >>> from lotsim.design.plot_yaml import read_plot
    >>> plot = read_plot("boundary: [[0, 0], [24, 0], [24, 30], [0, 30]]\\n"
    ...                  "gates: [{id: in, at: [12, 0]}]\\n")
    >>> c = draw_spine(plot, 0, 0.0, False)
    >>> [a.role for a in c.aisles], c.bays  # none within 10 m of the gate's mouth
    (['gate'], 16)
    """
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
            strip = _strip(tuple(p0 + u * first), tuple(p0 + u * t), w)
            return outline.covers(strip) and (blocked is None or strip.disjoint(blocked))
        if not fits(first + 0.5):
            return 0.0
        while hi - lo > 0.05:
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if fits(mid) else (lo, mid)
        return lo - DEAD_END_ROOM

    length = reach(start, n, 1.0)
    if length < GATE_MIN:
        return None
    heading = math.atan2(n[1], n[0])
    aisles = [DrawnAisle(f"gate-{g.id}", tuple(map(float, start)),
                         tuple(map(float, start + n * length)), w, False, "gate")]
    gates = [_gate_poses(plot, g.id, aisles[0].id, start, n)]
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
        drawn = _gate(plot, other.id, np.asarray(other.at, dtype=float), outline, lines)
        if drawn is None:
            return None
        aisles.append(drawn[0])
        gates.append(drawn[1])
    strips = [_strip(a.start, a.end, a.width) for a in aisles]
    things = _Things(strips + islands, [a.id for a in aisles] + [""] * len(islands),
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


def _inward(outline: Polygon, at: np.ndarray, width: float) -> tuple[np.ndarray, np.ndarray]:
    """Where a gate's aisle of ``width`` [m] begins: :data:`GATE_INSET` inside the boundary
    from the point of it nearest ``at``, moved along that edge, where the gate lies near one
    of its ends, until the aisle's mouth lies on the edge with :data:`CLEAR` to spare (at
    most half the width and that: the mouth still takes the gate in); and the unit square
    to the edge, inward."""
    ring = np.asarray(outline.exterior.coords)
    g = Point(at)
    k = int(np.argmin([LineString(ring[i:i + 2]).distance(g) for i in range(len(ring) - 1)]))
    e = ring[k + 1] - ring[k]
    span = float(np.hypot(*e))
    e = e / span
    n = np.array([-e[1], e[0]])  # left of a counter-clockwise edge is inward
    if not outline.exterior.is_ccw:
        n = -n
    s = float(np.dot(np.asarray(at, dtype=float) - ring[k], e))
    room = width / 2 + CLEAR
    s = min(max(s, room), span - room) if span >= 2 * room else span / 2
    start = ring[k] + e * s
    return start + n * GATE_INSET, n


def _gate_poses(plot: PlotSpec, gid: str, aisle: str, start: np.ndarray, n: np.ndarray
                ) -> DrawnGate:
    """A gate's entrance and exit near the boundary, on the inward and outward lanes of its
    aisle, which runs from ``start`` along ``n``."""
    width = plot.circulation_width
    heading = math.atan2(n[1], n[0])
    right = np.array([n[1], -n[0]])
    longest = max(v.front for v in plot.vehicle_types)
    rear = max(v.rear for v in plot.vehicle_types)
    inward = start + n * (rear + 0.5) + right * width / 4
    outward = start + n * (longest + 0.5) - right * width / 4
    edge = start - n * GATE_INSET
    mouth = (tuple(map(float, edge - right * width / 2)),
             tuple(map(float, edge + right * width / 2)))
    return DrawnGate(gid, aisle, (*map(float, inward), heading),
                     (*map(float, outward), heading + math.pi), mouth)


def _mouths(plot: PlotSpec, gates: list[DrawnGate]):
    """Where no bay's centre may lie: within :attr:`PlotSpec.gate_clearance` of a gate's
    mouth (None: nowhere)."""
    if plot.gate_clearance <= 0:
        return None
    zones = [LineString(g.mouth).buffer(plot.gate_clearance) for g in gates
             if g.mouth is not None]
    if not zones:
        return None
    zone = unary_union(zones)
    shapely.prepare(zone)
    return zone


class _Things:
    """What bays keep :data:`CLEAR` from: aisle strips (by aisle id), islands (id ``""``)
    and the bays kept so far (each with its aisle and side); and ``mouths``, what their
    centres keep out of (:func:`_mouths`)."""

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
    """Bays packed along one side of aisle ``a`` from its first end (module docstring),
    of the plot's size or of ``size`` (width, length [m]: compact bays, which may touch the
    bays along the same side, and are tried at the stations of ``seeds`` too); ``things``
    gains them."""
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
                       None if g.mouth is None else (pt(g.mouth[0]), pt(g.mouth[1])))
             for g in c.gates]
    return Candidate(c.orientation_deg, c.module, c.offset, c.inner_first, aisles, rows, gates,
                     c.ringed, c.spine, c.along)
