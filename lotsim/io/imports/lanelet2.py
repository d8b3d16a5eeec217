"""Lanelet2 maps in Autoware's valet-parking convention as lotsim scenarios:
:func:`import_lanelet2`.

The map (:mod:`.lanelet2_map`) is read with the standard library and projected into a local
east-north plane (:class:`~lotsim.io.imports.frame.LocalFrame`). Its lanelets become roads
(:mod:`.lanelet2_roads`), the roads aisles widened over the ``parking_access`` ground to the
spots' entries (:mod:`.lanelet2_layout`), its ``parking_spot`` areas free-standing slots
(:mod:`.lanelet2_spots`); open road ends at the map's edge become gates. What is paved is
what the map draws: lanelets, access areas and spots. ``docs/import.md`` says what is read,
what is inferred and what is dropped.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import split, unary_union

from lotsim.core.atomic import atomic_write
from lotsim.core.geometry import FloatArray
from lotsim.errors import LotsimError, ScenarioError
from lotsim.io.imports.draft import AisleDraft, AreaDraft, GateDraft, LotDraft, SlotDraft
from lotsim.io.imports.lanelet2_layout import (
    ENTRY_REACH,
    MARGIN,
    AisleLayout,
    Bends,
    assign,
    beside_bends,
    cut_at_corners,
    drivable,
    end_on,
    extend_to,
    fit,
    join_corner,
    legs_of,
)
from lotsim.io.imports.lanelet2_map import Lanelet, Lanelet2Map, read_lanelet2
from lotsim.io.imports.lanelet2_roads import carriageways, network
from lotsim.io.imports.lanelet2_spots import fit_spot
from lotsim.io.imports.report import ImportedLot, ImportReport
from lotsim.lot.model import DesignVehicle
from lotsim.vehicles.catalogue import get_vehicle

BOUNDARY_GROW = 0.5
"""The boundary is the drawn ground grown by this [m]."""
GATE_IN = 5.0
"""Gates stand this far in from an open road end [m]."""
EDGE_PROBE = 3.0
"""An open road end is at the map's edge when the ground this far beyond it holds no spot
or access area [m]."""
TRAFFIC = {"stream": {"count": 20, "rate_per_hour": 60, "dwell": [300, 900]}}
"""The default traffic: a stream of 20 cars, one a minute, each parked 5 to 15 minutes."""
WRITE_PAVED = True
VEHICLE_TYPES = ("altis", "zoe")
"""The vehicle types the scenario lists."""
GUESS_STRIP = 1.4
"""Access ground each side of a carriageway guessed before the aisles are fitted, to see
which of a road's corners lotsim can round [m]."""
DEFAULT_SPEED_KMH = 20.0
"""lotsim's speed limit when the map gives none [km/h]."""
"""Write ``lot.paved`` (the map's drawn ground): on once the scenario format has the key."""


def import_lanelet2(source: str | os.PathLike, out_dir: str | os.PathLike, *,
                    origin: tuple[float, float] | None = None,
                    progress: Callable[[str], None] | None = None) -> ImportReport:
    """Write the lot of a Lanelet2 map as ``<out_dir>/<stem>.yaml``.

    Parameters
    ----------
    source : path
        A Lanelet2 OSM XML file in Autoware's valet-parking convention.
    out_dir : path
        Folder to write into (made if missing).
    origin : (lat, lon) or None
        Origin of the local frame [degrees]; default the ``map_config`` yaml beside the
        file (``<stem>.yaml``, Autoware's), else the centroid of the map's nodes.
    progress : callable or None
        Called with a line of text at each stage.

    Returns
    -------
    ImportReport
        One lot: the map.

    Raises
    ------
    LotsimError
        The file is missing, not XML, not OSM, holds no lanelets, or its lot cannot be
        laid out; nothing is written then.
    """
    say = progress or (lambda _line: None)
    path = Path(source)
    say(f"reading {path}")
    m = read_lanelet2(path, origin=origin)
    if not m.lanelets:
        raise ScenarioError(None, f"{path}: expected lanelets (type=lanelet relations), "
                                  "found none: there is no road to drive")
    say(f"{len(m.lanelets)} lanelets, {len(m.spots)} parking spots, "
        f"{len(m.accesses)} parking_access areas")
    draft, lot = _draft(m, say)
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
        target = out / f"{path.stem}.yaml"
        with atomic_write(target, "w", encoding="utf-8") as fh:
            fh.write(draft.to_yaml())
    except OSError as exc:
        raise LotsimError(f"{out}: cannot write the scenario: {exc.strerror or exc}") from None
    say(f"wrote {target}")
    done = ImportedLot(lot.id, lot.area, lot.mapped, 0, None, lot.aisles, lot.gates, target,
                       lot.reason, m.error)
    return ImportReport(path, (done,))


def _speed_limit(m: Lanelet2Map) -> float | None:
    """The lowest ``speed_limit`` of the lanelets [km/h] ("10km/h", "10", "6 mph")."""
    found = []
    for ll in m.lanelets:
        value = ll.tags.get("speed_limit", "")
        hit = re.fullmatch(r"\s*([0-9.]+)\s*(km/h|kmh|kph|mph)?\s*", value)
        if hit:
            v = float(hit.group(1)) * (1.609344 if hit.group(2) == "mph" else 1.0)
            if 1 <= v <= 200:
                found.append(v)
    return min(found) if found else None


def _draft(m: Lanelet2Map, say: Callable[[str], None]) -> tuple[LotDraft, ImportedLot]:
    parts = carriageways(m.lanelets)
    net = network(parts)
    say(f"{len(parts)} carriageways: {len(net.roads)} roads, {len(net.junctions)} junctions")
    lanelet_ground = unary_union([ll.polygon for ll in m.lanelets])
    access = unary_union([a.polygon for a in m.accesses]) if m.accesses else Polygon()
    ground = unary_union([lanelet_ground, access])
    spots = sorted((fit_spot(a, ground) for a in m.spots), key=lambda s: _key(s.id))
    speed = (_speed_limit(m) or DEFAULT_SPEED_KMH) / 3.6
    design = DesignVehicle.envelope([get_vehicle(v) for v in VEHICLE_TYPES])
    roads = []
    for road in net.roads:
        guess = Bends(road.width + 2 * GUESS_STRIP, road.two_way, design, speed)
        roads.append(AisleLayout(road, legs_of(road, guess.short)))
    reasons = assign(spots, roads)
    aisles, of_road = [], []  # the pieces, and the road of each
    for r, road in enumerate(roads):
        pieces = cut_at_corners(road, lambda w, rd=road.road: Bends(w, rd.two_way, design, speed))
        aisles += pieces
        of_road += [r] * len(pieces)
    for aisle in aisles:
        reasons.update(fit(aisle))
    needs = [Bends(a.width, a.road.two_way, design, speed).short for a in aisles]
    for k, (aisle, need) in enumerate(zip(aisles, needs, strict=True)):
        aisle.line = drivable(aisle.line, need)
        if k and aisle.ends[0][0] == "corner":
            join_corner(aisles[k - 1], aisle)
    for aisle, need in zip(aisles, needs, strict=True):  # T ends on their hosts' lines
        for e, (kind, host) in enumerate(aisle.ends):
            if kind == "on":
                end = aisle.line[-1 if e else 0]
                near = min((k for k, r in enumerate(of_road) if r == host),
                           key=lambda k: LineString(aisles[k].line).distance(Point(end)))
                aisle.line = drivable(end_on(aisle.line, e, aisles[near].line), need)
    spot_ground = unary_union([s.polygon for s in spots]) if spots else Polygon()
    parking = unary_union([access, spot_ground])
    for aisle, need in zip(aisles, needs, strict=True):  # dead ends: on to the spots ahead
        for e, (kind, _) in enumerate(aisle.ends):
            if kind == "open" and not _at_edge(aisle, e, parking):
                aisle.line = drivable(_dead_end(aisle, e, spot_ground, ground), need)
    bends = [Bends(a.width, a.road.two_way, design, speed) for a in aisles]
    drawn = unary_union([ground, spot_ground] + [a.polygon for a in aisles]
                        + [b.sweep(np.round(a.line, 2)) for a, b in zip(aisles, bends,
                                                                        strict=True)])
    boundary = _boundary(drawn)
    gates_at = []
    for a, aisle in enumerate(aisles):
        for e, (kind, _) in enumerate(aisle.ends):
            if kind == "open" and _at_edge(aisle, e, parking):
                aisle.line = drivable(extend_to(aisle.line, e, boundary, 0.02), needs[a])
                gates_at.append((a, e))
    for aisle, bend in zip(aisles, bends, strict=True):
        reasons.update(beside_bends(aisle, bend))
    if not gates_at:
        raise ScenarioError(None, f"{m.source}: no road of the map ends at its edge: the lot "
                                  "has nowhere for cars to come in")
    ids = []
    for k, r in enumerate(of_road):
        first = of_road.index(r)
        ids.append(f"L{roads[r].road.lanelets[0]}" + (f"-{k - first + 1}"
                                                       if of_road.count(r) > 1 else ""))
    slots = _slots(aisles, ids, reasons, boundary)
    drawn_map = unary_union([ground, spot_ground])
    blocks, dropped_lines = _blocks(m, ground, spot_ground)
    entrances, exits = [], []
    for a, e in gates_at:
        entrance, exit_ = _gates(aisles[a], e, {ll.id: ll for ll in m.lanelets})
        entrances += [entrance] if entrance else []
        exits += [exit_] if exit_ else []
    header = [
        f"Imported by lotsim from the Lanelet2 map {m.source.name} (Autoware valet-parking "
        "convention).",
        f"Projection: {m.frame.describe()} ({m.origin_source}); its error over the map is "
        f"under {max(m.error, 1e-4) * 1000:.1f} mm.",
        f"{_n(len(m.lanelets), 'lanelet')} as {_n(len(parts), 'carriageway')} and "
        f"{_n(len(aisles), 'aisle')} ({_n(len(net.connectors), 'junction connector lanelet')} "
        f"dropped: lotsim builds its own turns); {_n(len(m.accesses), 'parking_access area')} "
        "widen the aisles to the spots.",
        f"{_n(len(m.spots), 'parking_spot area')}: {_n(len(slots), 'slot')}; "
        f"{len(reasons)} not imported" + (" (below, why)." if reasons else "."),
        "Gates: an entrance and an exit where each road ends at the map's edge, "
        f"{GATE_IN:g} m in; no gate tags are read.",
    ]
    header += [f"spot {sid} not imported: {why}" for sid, why in
               sorted(reasons.items(), key=lambda kv: _key(kv[0]))]
    if dropped_lines:
        header.append(dropped_lines)
    draft = LotDraft(
        name=_name(m.source.stem),
        description=f"{m.source.name}: {_n(len(slots), 'slot')} from the map's parking_spot "
                    f"areas, {_n(len(aisles), 'aisle')} from its lanelets.",
        boundary=_ring(boundary),
        vehicle_types=list(VEHICLE_TYPES),
        header=header,
        speed_limit_kmh=_speed_limit(m),
        aisles=[AisleDraft(ids[k], [tuple(map(float, p)) for p in a.line], a.width,
                           not a.road.two_way, _aisle_note(a)) for k, a in enumerate(aisles)],
        slots=[s for s, _ in slots],
        obstacles=blocks,
        paved=_paved(drawn_map) + _corners(aisles, ids) + _swept(aisles, ids, bends, drawn_map)
        if WRITE_PAVED
        else None,
        paved_aisles=True,
        entrances=entrances,
        exits=exits,
        traffic=TRAFFIC,
    )
    lot = ImportedLot(m.source.stem, float(drawn_map.area), mapped=len(slots),
                      aisles=len(aisles), gates=len(gates_at),
                      reason=f"{len(reasons)} of {len(m.spots)} parking spots not imported "
                             "(why: in the file's header)" if reasons else "",
                      projection_error=m.error)
    return draft, lot


def _n(count: int, what: str) -> str:
    """``3 aisles``, ``1 aisle``."""
    return f"{count} {what}" if count == 1 else f"{count} {what}s"


def _aisle_note(aisle: AisleLayout) -> str:
    ids = aisle.road.lanelets
    shown = ", ".join(ids[:8]) + (", ..." if len(ids) > 8 else "")
    kind = "two-way" if aisle.road.two_way else "one-way"
    return (f"lanelets {shown} ({kind}, carriageway {aisle.road.width:.2f} m): "
            f"{len(aisle.slots)} spots open onto it")


SHRINK = 0.01
"""Each slot is drawn this much inside the mapped spot's long sides and ends [m], so that
neighbours that share a side do not overlap once written to the centimetre."""


def _rounded(spot, shrink: float) -> tuple[SlotDraft, Polygon]:
    from lotsim.io.imports.lanelet2_spots import rectangle

    cx, cy = (round(float(v), 2) for v in spot.center)
    heading = round(math.degrees(spot.heading), 2)
    # to the centimetre below: a spot a hair under 2.5 m is 2.5 m less the rim, not 2.47
    width = math.floor(round((spot.width - 2 * shrink) * 100, 2)) / 100
    length = math.floor(round((spot.length - 2 * SHRINK) * 100, 2)) / 100
    draft = SlotDraft(f"P{spot.id}", "perpendicular", width, length, (cx, cy), heading)
    return draft, rectangle((cx, cy), math.radians(heading), width, length)


def _slots(aisles: list[AisleLayout], ids: list[str], reasons: dict[str, str],
           boundary: Polygon) -> list[tuple[SlotDraft, str]]:
    """The kept spots as slots, as lotsim will build them from the written numbers: drawn
    inside their outlines so that neighbours do not overlap, each opening onto an aisle's
    edge within reach and covered by none; a spot that does not is reported."""
    spots = sorted(((s, ids[k]) for k, a in enumerate(aisles) for s in a.slots),
                   key=lambda sa: _key(sa[0].id))
    shrink = {s.id: SHRINK for s, _ in spots}
    while True:
        built = [_rounded(s, shrink[s.id]) for s, _ in spots]
        polys = np.array([p for _, p in built])
        tree = shapely.STRtree(polys)
        left, right = tree.query(polys, predicate="intersects")
        keep = left < right
        left, right = left[keep], right[keep]
        area = shapely.area(shapely.intersection(polys[left], polys[right]))
        bad = sorted({int(i) for k in np.flatnonzero(area > 1e-7) for i in (left[k],
                                                                            right[k])})
        if not bad:
            break
        for i in bad:
            shrink[spots[i][0].id] += 0.01
    rounded = [np.round(a.line, 2) for a in aisles]
    shapes = [LineString(line).buffer(a.width / 2, cap_style="flat", join_style="round")
              for line, a in zip(rounded, aisles, strict=True)]
    out = []
    for (spot, aid), (draft, poly) in zip(spots, built, strict=True):
        covered = [ids[k] for k, sh in enumerate(shapes) if poly.intersection(sh).area > 1e-7]
        c = np.asarray(draft.center)
        d = np.array([math.cos(math.radians(draft.heading_deg)),
                      math.sin(math.radians(draft.heading_deg))])
        entry = shapely.Point(c - d * draft.length / 2)
        gap = min(sh.distance(entry) for sh in shapes)
        if covered:
            reasons[spot.id] = f"aisle {covered[0]} covers part of it"
        elif gap > ENTRY_REACH - 1e-3:
            reasons[spot.id] = f"its entry is {gap:.2f} m from the nearest aisle"
        elif not boundary.covers(poly):
            reasons[spot.id] = "it lies partly outside the lot's boundary"
        else:
            out.append((draft, aid))
    return out


BLOCKING = ("Walls", "Columns", "Kerbs")
"""The map's line features that block a car where they cross its drawn ground."""


def _blocks(m: Lanelet2Map, ground, spots) -> tuple[list[AreaDraft], str]:
    """Walls, columns and kerbs that cross the ground driven on (lanelets and access areas,
    clear of the spots: a row's kerb runs along its spots' backs), as thin obstacles; a
    line saying what of the map's lines is left out."""
    out = []
    left = 0
    inner = ground.buffer(-0.05).difference(spots.buffer(0.1))
    for ln in m.lines:
        if ln.subtype not in BLOCKING:
            continue
        inside = LineString(ln.points).intersection(inner)
        if inside.is_empty or inside.length < 0.2:
            left += 1
            continue
        shape = inside.buffer(0.05, cap_style="flat", join_style="mitre")
        for piece in getattr(shape, "geoms", [shape]):
            out.append(AreaDraft(f"{ln.subtype.lower()}-{ln.id}", _ring(piece),
                                 f"{ln.subtype} way {ln.id} across the ground driven on"))
    kinds = sorted({ln.subtype for ln in m.lines} - set(BLOCKING))
    note = (f"Dropped: {left} wall, column and kerb lines that stay off the ground driven on, "
            f"and the map's {', '.join(kinds)} lines.") if left or kinds else ""
    return out, note


def _paved(drawn) -> list[AreaDraft]:
    """The drawn ground as simple polygons: each part cut across its holes, written to the
    centimetre."""
    healed = drawn.buffer(0.01, join_style="mitre").buffer(-0.01, join_style="mitre")
    parts = [p for p in shapely.get_parts(healed) if p.area > 0.01]
    out = []
    while parts:
        part = parts.pop()
        if part.interiors:
            x = Polygon(part.interiors[0]).centroid.x
            lo, hi = part.bounds[1] - 1, part.bounds[3] + 1
            parts.extend(p for p in split(part, LineString([(x, lo), (x, hi)])).geoms
                         if p.area > 0.01)
            continue
        out.extend(_simple(shapely.simplify(part, 0.005)))
    out.sort(key=lambda r: (round(Polygon(r).centroid.x, 2), round(Polygon(r).centroid.y, 2)))
    return [AreaDraft(f"drawn-{k + 1}", ring,
                      "lanelets, parking_access areas and spots of the map")
            for k, ring in enumerate(out)]


def _corners(aisles: list[AisleLayout], ids: list[str]) -> list[AreaDraft]:
    """The outside of each L where two pieces of a road meet, paved as the corner of a road
    is: the hull of their strips near the corner."""
    out = []
    for k in range(1, len(aisles)):
        a, b = aisles[k - 1], aisles[k]
        if b.ends[0][0] != "corner":
            continue
        p = shapely.Point(np.round(b.line[0], 2))
        near = p.buffer(max(a.width, b.width), quad_segs=4)
        strips = [LineString(np.round(x.line, 2)).buffer(x.width / 2, cap_style="flat",
                                                         join_style="round") for x in (a, b)]
        hull = shapely.union_all(strips).intersection(near).convex_hull
        extra = hull.difference(shapely.union_all(strips))
        for piece in shapely.get_parts(extra):
            if piece.area > 0.01:
                for ring in _simple(piece.buffer(0.02, join_style="mitre")):
                    out.append(AreaDraft(f"corner-{ids[k - 1]}-{ids[k]}", ring,
                                         f"the outside of the corner where {ids[k - 1]} "
                                         f"meets {ids[k]}"))
    return out


def _swept(aisles: list[AisleLayout], ids: list[str], bends: list[Bends],
           paved) -> list[AreaDraft]:
    """Ground a car driving an aisle's lanes covers beyond the aisle's strip and the map's
    drawn ground ``paved`` (the inside of a bend, which a car cuts): paved too."""
    out = []
    for aisle, aid, bend in zip(aisles, ids, bends, strict=True):
        line = np.round(aisle.line, 2)
        strip = LineString(line).buffer(aisle.width / 2, cap_style="flat",
                                        join_style="round")
        extra = bend.sweep(line).buffer(0.05, join_style="mitre").difference(
            shapely.union_all([strip, paved]))
        pieces = [p for p in shapely.get_parts(extra) if p.area > 0.01]
        pieces.sort(key=lambda p: (round(p.centroid.x, 2), round(p.centroid.y, 2)))
        for piece in pieces:
            for ring in _simple(shapely.simplify(piece.buffer(0.02, join_style="mitre"),
                                                 0.01)):
                out.append(AreaDraft(f"swept-{aid}-{len(out) + 1}", ring,
                                     f"where a car on a lane of aisle {aid} cuts a bend"))
    return out


def _simple(poly: Polygon) -> list[list[tuple[float, float]]]:
    """``poly`` as rings to the centimetre, each a simple polygon (a ring that rounding makes
    cross itself is split where it does)."""
    ring = [(round(float(x), 2), round(float(y), 2)) for x, y in poly.exterior.coords[:-1]]
    ring = [p for k, p in enumerate(ring) if p != ring[k - 1]]
    rounded = Polygon(ring)
    if len(ring) >= 3 and rounded.is_valid and rounded.area > 0.01:
        return [ring]
    fixed = shapely.make_valid(rounded) if len(ring) >= 3 else Polygon()
    out = []
    for piece in shapely.get_parts(fixed):
        if piece.geom_type == "Polygon" and piece.area > 0.01:
            out.extend(_simple(Polygon(piece.exterior)))
    return out


def _key(ident: str):
    return (0, int(ident)) if ident.lstrip("-").isdigit() else (1, ident)


def _name(stem: str) -> str:
    name = re.sub(r"[^A-Za-z0-9_.-]+", "-", stem).strip("-.")
    return name or "lanelet2-lot"


def _boundary(drawn) -> Polygon:
    """A simple polygon holding everything drawn: its outline grown, holes filled."""
    grown = drawn.buffer(BOUNDARY_GROW, join_style="mitre", mitre_limit=2.0)
    parts = getattr(grown, "geoms", [grown])
    outer = max(parts, key=lambda p: p.area)
    shell = Polygon(outer.exterior)
    simple = shapely.simplify(shell, 0.1)
    if not simple.covers(drawn.buffer(BOUNDARY_GROW / 2)):
        simple = shell
    return simple


def _ring(poly: Polygon) -> list[tuple[float, float]]:
    return [(float(x), float(y)) for x, y in np.asarray(poly.exterior.coords)[:-1]]


def _at_edge(aisle: AisleLayout, end: int, parking) -> bool:
    """Whether nothing parked lies just beyond the aisle's end ``end``."""
    pts = aisle.line if end == 1 else aisle.line[::-1]
    d = pts[-1] - pts[-2]
    d = d / float(np.hypot(*d))
    n = np.array([-d[1], d[0]]) * aisle.width / 2
    tip = pts[-1]
    box = Polygon([tip - n, tip + d * EDGE_PROBE - n, tip + d * EDGE_PROBE + n, tip + n])
    return box.intersection(parking).area < 0.05 * box.area


DEAD_END_REACH = 6.0
"""A dead end is carried on at most this far over the ground the map draws ahead of it
[m]."""


def _dead_end(aisle: AisleLayout, end: int, spots, ground) -> FloatArray:
    """The aisle's line with its dead end ``end`` carried on over the drawn ground ahead,
    short of the spots there by the margin (room to turn round at the end of a court)."""
    pts = aisle.line if end == 1 else aisle.line[::-1]
    tip = pts[-1]
    d = (tip - pts[-2]) / float(np.hypot(*(tip - pts[-2])))
    n = np.array([-d[1], d[0]]) * aisle.width / 2
    room = ground.buffer(0.05)
    best = 0.0
    for k in range(1, int(DEAD_END_REACH / 0.1) + 1):
        far = tip + d * (k * 0.1 + MARGIN)
        band = Polygon([tip - n, far - n, far + n, tip + n])
        if band.intersection(spots).area > 1e-6 or not room.covers(
                Polygon([tip, far, far + n * 0.5, tip + n * 0.5]).union(
                    Polygon([tip, far, far - n * 0.5, tip - n * 0.5]))):
            break
        best = k * 0.1
    if best <= 0:
        return aisle.line
    pts = np.vstack([pts[:-1], tip + d * best])
    return pts if end == 1 else pts[::-1]


def _gates(aisle: AisleLayout, end: int, lanelets: dict[str, Lanelet]
           ) -> tuple[GateDraft | None, GateDraft | None]:
    """An entrance on the lane heading in and an exit on the lane heading out,
    :data:`GATE_IN` from the aisle's end ``end``, each named after the map's lanelet that
    runs that way there (a one-way aisle: the one its traffic allows)."""
    line = LineString(aisle.line)
    s = GATE_IN if end == 0 else line.length - GATE_IN
    p = np.asarray(line.interpolate(s).coords[0])
    q = np.asarray(line.interpolate(s + (0.5 if end == 0 else -0.5)).coords[0])
    d_in = (q - p) / float(np.hypot(*(q - p)))
    right = np.array([d_in[1], -d_in[0]])
    off = 0.0 if not aisle.road.two_way else aisle.width / 4
    heading = math.degrees(math.atan2(d_in[1], d_in[0]))
    part = aisle.road.parts[0 if end == 0 else -1]

    def named(sign: float) -> str:
        """The end part's lanelet heading along ``sign * d_in``."""
        def along(ll: Lanelet) -> float:
            d = (ll.left[-1] + ll.right[-1] - ll.left[0] - ll.right[0]) / 2
            return float(np.dot(d, d_in)) * sign
        return max(part.lanelets, key=lambda i: along(lanelets[i]))

    entrance = exit_ = None
    if aisle.road.two_way or end == 0:
        ident = named(1.0)
        entrance = GateDraft(f"in-{ident}", *(p + right * off), heading,
                             f"where lanelet {ident} comes in from the map's edge")
    if aisle.road.two_way or end == 1:
        ident = named(-1.0)
        exit_ = GateDraft(f"out-{ident}", *(p - right * off),
                          heading + 180 if heading <= 0 else heading - 180,
                          f"where lanelet {ident} leaves at the map's edge")
    return entrance, exit_
