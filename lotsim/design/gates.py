"""The gates of a candidate (:mod:`lotsim.design.candidates`): each gate's straight aisle
in from the boundary, or its opening straight onto a ring leg beside its edge; where the
aisle square to the boundary cannot be drawn (a gate at an acute corner, in a spike, on
the edge of a notch), an aisle turned so that its strip stays in the plot, straight or
bent once, to the aisle it meets; its entrance and exit on that aisle; and its mouth, the
stretch of boundary where the aisle meets it, with the zone round it that no bay's centre
may lie in."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

from lotsim.design.drawn import (
    CLEAR,
    EPS,
    MIN_JUNCTION_DEG,
    DrawnAisle,
    DrawnGate,
    strip,
)
from lotsim.design.plot import PlotSpec

GATE_INSET = 0.02
"""A gate's aisle begins this far inside the boundary [m]: written to the centimetre, its
first point stays inside."""
GATE_MIN = 7.0
"""A gate aisle is at least this long [m]: room for its entrance and exit."""
GATE_MAX = 80.0
"""A gate aisle meets another aisle within this distance of its gate [m]."""
GATE_REACH = 30.0
"""A turned gate aisle's mouth lies at most this far from its gate [m]: deep enough into a
spike of 15° for the aisle's width."""
FAN_DEG = 5.0
"""A turned gate aisle is tried in directions this far apart [degrees]."""
REACH_STEP = 0.25
"""A turned gate aisle's mouth is looked for in steps of this along its line [m]."""
BEND_STEP = 2.0
"""A bent gate aisle's bend is tried in steps of this along its first piece [m]."""
BEND_COST = 10.0
"""A bend costs a gate aisle as much as this much more length [m]: a straight aisle comes
before a bent one a little shorter."""
MAX_BEND_DEG = 90.0
"""A bent gate aisle turns at most this much at its bend [degrees]."""
APPROACH_SLACK = 0.5
"""The way from a gate to its turned aisle's mouth keeps within this of the plot [m] (a
gate lies within it of the boundary)."""


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


def _gate_aisles(plot: PlotSpec, gid: str, at: np.ndarray, outline: Polygon,
                 lines: list[tuple[LineString, DrawnAisle]], *, turned: bool = False,
                 islands: list[Polygon] = ()) -> tuple[list[DrawnAisle], DrawnGate] | None:
    """A gate's aisle (its pieces) to the first aisle of ``lines`` it meets, with its
    entrance and exit: square to its edge (:func:`_gate`) where that can be drawn, else,
    with ``turned``, turned, straight or bent once, clear of the ``islands``
    (:func:`_turned_gate`); None when neither can."""
    drawn = _gate(plot, gid, at, outline, lines)
    if drawn is not None:
        return [drawn[0]], drawn[1]
    return _turned_gate(plot, gid, at, outline, lines, islands) if turned else None


def _turned_gate(plot: PlotSpec, gid: str, at: np.ndarray, outline: Polygon,
                 lines: list[tuple[LineString, DrawnAisle]], islands: list[Polygon] = ()
                 ) -> tuple[list[DrawnAisle], DrawnGate] | None:
    """A gate's aisle turned from square to its edge, for a gate where the square one
    leaves the plot or meets no aisle: from a mouth of :func:`_ways_in` along its way,
    straight to the first aisle it meets at :data:`MIN_JUNCTION_DEG` or more, or to a bend
    (:data:`BEND_STEP` apart, at least :data:`GATE_MIN` from the mouth) and from there
    square to a nearby aisle (its foot clear of the aisle's ends; the bend at most
    :data:`MAX_BEND_DEG`; each piece :data:`GATE_MIN` or longer; :data:`GATE_MAX` in all).
    Of these the shortest, from the gate, a bend counting :data:`BEND_COST`, whose strips
    (and the disc that rounds the bend) lie in the plot, clear of every aisle but the one
    met, and of that one short of where it is met: the aisle's pieces (the first named
    ``gate-<id>``, the second ``bend1-<id>``), and the gate's entrance and exit on the
    first; None where there is none."""
    if not lines:
        return None
    w = plot.circulation_width
    g = np.asarray(at, dtype=float)
    aisles = [a for _, a in lines]
    a0 = np.array([a.start for a in aisles], dtype=float)
    e = np.array([a.end for a in aisles], dtype=float) - a0
    span = np.hypot(e[:, 0], e[:, 1])
    widths = np.array([a.width for a in aisles])
    edges = np.asarray(outline.exterior.coords)
    options = []  # (cost, pieces, index of the aisle met)
    for p0, d in _ways_in(outline, g, w):
        t, u = _crossings(p0, d, a0, e)
        hit = (t > 1e-6) & (u >= 0.0) & (u <= 1.0)
        t_hit = float(t[hit].min()) if hit.any() else math.inf
        tb, ub = _crossings(p0, d, edges[:-1], np.diff(edges, axis=0))
        out = (tb > 1e-3) & (ub >= 0.0) & (ub <= 1.0)
        t_out = float(tb[out].min()) if out.any() else math.inf
        app = float(np.hypot(*(p0 - g)))
        if GATE_MIN <= t_hit <= min(t_out, GATE_MAX):
            end, met = _met(p0 + d * t_hit, a0, e)
            k = list(met)
            sin = np.abs(d[0] * e[k, 1] - d[1] * e[k, 0]) / span[k]
            if met and sin.min() >= math.sin(math.radians(MIN_JUNCTION_DEG)):
                options.append((app + float(np.hypot(*(end - p0))), [(p0, end)], met))
        bends = np.arange(GATE_MIN, min(t_hit, t_out, GATE_MAX) - w / 2, BEND_STEP)
        if not bends.size:
            continue
        q = p0 + bends[:, None] * d  # (B, 2)
        rel = q[:, None, :] - a0[None]  # (B, K, 2)
        along = (rel * e[None]).sum(axis=2) / span  # how far along each aisle its foot is
        foot = a0[None] + e[None] * (along / span)[..., None]
        leg = foot - q[:, None, :]
        second = np.hypot(leg[..., 0], leg[..., 1])
        margin = w / 2 + widths / 2 + 2 * CLEAR + 0.5
        turn = (leg @ d) / np.maximum(second, EPS)
        ok = ((along >= margin) & (along <= span - margin) & (second >= GATE_MIN)
              & (bends[:, None] + second <= GATE_MAX)
              & (turn >= math.cos(math.radians(MAX_BEND_DEG)) - EPS))
        for b, j in zip(*np.nonzero(ok), strict=True):
            options.append((app + bends[b] + second[b, j] + BEND_COST,
                            [(p0, q[b]), (q[b], foot[b, j])], (int(j),)))
    options.sort(key=lambda o: o[0])
    room = outline.buffer(EPS)
    if islands:  # (which a square gate aisle meets the ring round first)
        room = room.difference(unary_union(islands))
    shapely.prepare(room)
    strips = [strip(a.start, a.end, a.width) for a in aisles]
    way_in = outline.buffer(APPROACH_SLACK)
    for _, pieces, met in options:
        if _clear(pieces, met, aisles, strips, room, w) and \
                way_in.covers(LineString([g, pieces[0][0]])):
            return _turned(plot, gid, g, pieces)
    return None


def _turned(plot: PlotSpec, gid: str, g: np.ndarray, pieces: list[tuple[np.ndarray,
            np.ndarray]]) -> tuple[list[DrawnAisle], DrawnGate]:
    """A turned gate aisle of ``pieces`` (start, end) and its gate's entrance, exit, mouth
    and approach from the gate ``g``."""
    w = plot.circulation_width
    # the pieces after the first are "bend1-<id>", ...: no other aisle is named so
    ids = [f"gate-{gid}"] + [f"bend{k + 1}-{gid}" for k in range(len(pieces) - 1)]
    aisles = [DrawnAisle(i, tuple(map(float, a)), tuple(map(float, b)), w, False, "gate")
              for i, (a, b) in zip(ids, pieces, strict=True)]
    p0, p1 = pieces[0]
    d = (p1 - p0) / np.hypot(*(p1 - p0))
    gate = _gate_poses(plot, gid, ids[0], p0, d)
    return aisles, dataclasses.replace(gate, approach=(tuple(map(float, g)),
                                                       tuple(map(float, p0))))


def _clear(pieces, met: tuple[int, ...], aisles: list[DrawnAisle], strips: list[Polygon],
           room, width: float) -> bool:
    """Whether a gate aisle of ``pieces`` that ends on the aisles ``met`` (one, or those
    meeting at a corner) lies in ``room`` as strips of ``width`` (and the disc of that width
    at each bend), :data:`CLEAR` from every other aisle's strip, and from the one it meets
    short of where it meets it: the strip of one met at φ reaches its half-width / sin φ
    and this one's / tan φ along the centre line, and half a metre more. An aisle that
    meets a corner (along the bisector of a corner of the boundary, to the ring's corner
    inside it) runs into the corner's pavement: the strips of the aisles met there may
    take in all of it but its first metre."""
    bends = [Point(b) for _, b in pieces[:-1]]
    drawn = unary_union([strip(a, b, width) for a, b in pieces] +
                        [p.buffer(width / 2) for p in bends])
    if not room.covers(drawn):
        return False
    a, b = pieces[-1]
    length = float(np.hypot(*(b - a)))
    d = (b - a) / length
    if len(met) > 1:  # at a corner of the aisles met, whose pavement takes it in
        trim = length - 1.0
    else:
        f = np.subtract(aisles[met[0]].end, aisles[met[0]].start)
        sin = abs(float(d[0] * f[1] - d[1] * f[0])) / float(np.hypot(*f))
        trim = (aisles[met[0]].width / 2 / sin
                + width / 2 * math.sqrt(max(0.0, 1 - sin * sin)) / sin + 0.5)
        if length <= trim + 1.0:
            return False
    kept = width + 2 * CLEAR
    core = unary_union([strip(p, q, kept) for p, q in pieces[:-1]] +
                       [strip(a, b - d * trim, kept)] +
                       [p.buffer(kept / 2) for p in bends])
    whole = core.union(strip(b - d * trim, b, width))
    return not any((core if k in met else whole).intersects(strip)
                   for k, strip in enumerate(strips))


def _met(p: np.ndarray, a: np.ndarray, e: np.ndarray) -> tuple[np.ndarray, tuple[int, ...]]:
    """The aisles (from ``a`` along ``e``) a gate aisle ending at ``p`` on one of them
    meets: those within a micrometre of ``p``; and ``p``, moved to the corner where it lies
    that close to one (a gate aisle along a corner's bisector meets the ring's corner)."""
    ends = np.vstack([a, a + e])
    gap = np.hypot(*(ends - p).T)
    if gap.min() < 1e-6:
        p = ends[int(gap.argmin())]
    u = np.clip(((p - a) * e).sum(axis=1) / (e * e).sum(axis=1), 0.0, 1.0)
    near = np.hypot(*(a + e * u[:, None] - p).T) < 1e-6
    return p, tuple(int(k) for k in np.flatnonzero(near))


def _bends(aisles: list[DrawnAisle]) -> list[Polygon]:
    """The discs, as wide as the aisle, that round the bends of bent gate aisles (where one
    piece ends and the next begins), which bays keep clear of as of the aisles."""
    starts = {a.start for a in aisles if a.role == "gate"}
    return [Point(a.end).buffer(a.width / 2) for a in aisles
            if a.role == "gate" and a.end in starts]


def _crossings(p: np.ndarray, d: np.ndarray, a: np.ndarray, e: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """Where the line ``p + t d`` crosses the lines ``a + u e`` (rows of ``a`` and ``e``):
    ``t`` and ``u`` for each (inf where they are parallel)."""
    denom = d[0] * e[:, 1] - d[1] * e[:, 0]
    rel = a - p
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (rel[:, 0] * e[:, 1] - rel[:, 1] * e[:, 0]) / denom
        u = (rel[:, 0] * d[1] - rel[:, 1] * d[0]) / denom
    bad = np.abs(denom) < 1e-12
    t[bad], u[bad] = math.inf, math.inf
    return t, u


def _ways_in(outline: Polygon, at: np.ndarray, width: float
             ) -> list[tuple[np.ndarray, np.ndarray]]:
    """Where an aisle of ``width`` [m] from a gate at ``at`` may begin, and the unit way it
    runs, for an aisle turned from square: on the line square to the gate's edge from where
    :func:`_inward` puts it, on lines through the gate every :data:`FAN_DEG`, and on the
    bisector of each corner of the gate's edge within :data:`GATE_REACH` of it (a corner's
    or a spike's), each from its first cross-section (the aisle's width square to the line)
    from which the next :data:`GATE_MIN` of cross-sections lie in the plot, where that is
    :data:`GATE_REACH` or less from the gate. The aisle begins :data:`GATE_INSET` past it."""
    g = np.asarray(at, dtype=float)
    pts = np.asarray(outline.exterior.coords)[:-1]
    k = edge_of(outline, g)
    fan = np.radians(np.arange(0.0, 360.0, FAN_DEG))
    start, n = _inward(outline, g, width)
    origins = [start[None], np.repeat(g[None], len(fan), axis=0)]
    ways = [n[None], np.column_stack([np.cos(fan), np.sin(fan)])]
    for c in (k, (k + 1) % len(pts)):
        if math.dist(pts[c], g) <= GATE_REACH:
            origins.append(pts[c][None])
            ways.append(_bisector(outline, pts, c)[None])
    o, d = np.vstack(origins), np.vstack(ways)
    s = np.arange(0.0, GATE_REACH + GATE_MIN + REACH_STEP / 2, REACH_STEP)
    right = np.column_stack([d[:, 1], -d[:, 0]])
    mid = o[:, None, :] + d[:, None, :] * s[None, :, None]  # (M, S, 2)
    ends = np.stack([mid - right[:, None, :] * width / 2, mid + right[:, None, :] * width / 2],
                    axis=2)
    shapely.prepare(outline)
    inside = shapely.covers(outline, shapely.linestrings(ends.reshape(-1, 2, 2)))
    need = math.ceil(GATE_MIN / REACH_STEP) + 1
    misses = np.cumsum(np.pad(~inside.reshape(len(o), len(s)), ((0, 0), (1, 0))), axis=1)
    runs = misses[:, need:] == misses[:, :-need]  # the `need` cross-sections from i all in
    out = []
    for m in range(len(o)):
        first = np.flatnonzero(runs[m])
        if not first.size:
            continue
        p0 = mid[m, first[0]] + d[m] * GATE_INSET
        if math.dist(p0, g) <= GATE_REACH:
            out.append((p0, d[m]))
    return out


def _bisector(outline: Polygon, pts: np.ndarray, c: int) -> np.ndarray:
    """The unit bisector of the boundary's corner ``c``, into the plot."""
    a = pts[c - 1] - pts[c]
    b = pts[(c + 1) % len(pts)] - pts[c]
    v = a / np.hypot(*a) + b / np.hypot(*b)
    if np.hypot(*v) < 1e-9:  # a straight corner: square to it
        v = np.array([-a[1], a[0]])
    v = v / np.hypot(*v)
    return v if outline.contains(Point(pts[c] + v * 1e-3)) else -v



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
    mouth, or of the approach to it of a turned aisle (None: nowhere)."""
    if plot.gate_clearance <= 0:
        return None
    zones = [LineString(way).buffer(plot.gate_clearance) for g in gates
             for way in (g.mouth, g.approach) if way is not None]
    if not zones:
        return None
    zone = unary_union(zones)
    shapely.prepare(zone)
    return zone
