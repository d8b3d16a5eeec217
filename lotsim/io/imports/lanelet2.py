"""Lanelet2 maps in Autoware's valet-parking convention as lotsim scenarios:
:func:`import_lanelet2`.

The map (:mod:`.lanelet2_map`) is read with the standard library and projected into a local
east-north plane (:class:`~lotsim.io.imports.frame.TangentPlane`). Its lanelets become roads
(:mod:`.lanelet2_roads`), the roads aisles widened over the ``parking_access`` ground to the
spots' entries (:mod:`.lanelet2_layout`), its ``parking_spot`` areas free-standing slots
(:mod:`.lanelet2_spots`); open road ends at the map's edge become gates. What is paved is
what the map draws (lanelets, access areas, spots) and the aisles laid on it
(:mod:`.lanelet2_ground`). ``docs/import.md`` says what is read, what is inferred and what
is dropped.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

from lotsim.core.atomic import atomic_write
from lotsim.core.geometry import FloatArray
from lotsim.errors import LotsimError, ScenarioError
from lotsim.io.imports.draft import AisleDraft, GateDraft, LotDraft, SlotDraft
from lotsim.io.imports.lanelet2_ground import (
    blocking,
    boundary_of,
    corner_areas,
    drawn_areas,
    ring,
    swept_areas,
)
from lotsim.io.imports.lanelet2_layout import (
    MARGIN,
    AisleLayout,
    assign,
    beside_bends,
    cut_at_corners,
    fit,
    join_corner,
    legs_of,
    written_slots,
)
from lotsim.io.imports.lanelet2_lines import (
    Bends,
    as_written,
    drivable,
    end_on,
    extend_to,
    inside_part,
)
from lotsim.io.imports.lanelet2_map import Lanelet, Lanelet2Map, id_key, read_lanelet2
from lotsim.io.imports.lanelet2_roads import carriageways, network
from lotsim.io.imports.lanelet2_spots import fit_spot
from lotsim.io.imports.report import ImportedLot, ImportReport
from lotsim.io.scenario_yaml import read_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.vehicles.catalogue import get_vehicle

GATE_IN = 5.0
"""Gates stand this far in from an open road end [m]."""
EDGE_PROBE = 3.0
"""An open road end is at the map's edge when the ground this far beyond it holds no spot
or access area [m]."""
TRAFFIC = {"stream": {"count": 20, "rate_per_hour": 60, "dwell": [300, 900]}}
"""The default traffic: a stream of 20 cars, one a minute, each parked 5 to 15 minutes."""
VEHICLE_TYPES = ("altis", "zoe")
"""The vehicle types the scenario lists."""
GUESS_STRIP = 1.4
"""Access ground each side of a carriageway guessed before the aisles are fitted, to see
which of a road's corners lotsim can round [m]."""
DEFAULT_SPEED_KMH = 20.0
"""lotsim's speed limit when the map gives none [km/h]."""


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
    return ImportReport(path, (replace(lot, path=target),))


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
    """The map's lot as a draft, built as lotsim will build it, and its line of the report:
    roads from the lanelets, aisles fitted to the spots that open onto them (a road cut
    into an L at a corner where that serves more), their ends joined, carried on or made
    gates, the slots, the ground and what blocks it."""
    parts = carriageways(m.lanelets)
    net = network(parts)
    say(f"{len(parts)} carriageways: {len(net.roads)} roads, {len(net.junctions)} junctions")
    lanelet_ground = unary_union([ll.polygon for ll in m.lanelets])
    access = unary_union([a.polygon for a in m.accesses]) if m.accesses else Polygon()
    ground = unary_union([lanelet_ground, access])
    spots = sorted((fit_spot(a, ground) for a in m.spots), key=lambda s: id_key(s.id))
    speed = (_speed_limit(m) or DEFAULT_SPEED_KMH) / 3.6
    design = DesignVehicle.envelope([get_vehicle(v) for v in VEHICLE_TYPES])
    roads = []
    for road in net.roads:
        guess = Bends(road.width + 2 * GUESS_STRIP, road.two_way, design, speed)
        roads.append(AisleLayout(road, legs_of(road, guess.short)))
    reasons = assign(spots, roads)
    aisles, of_road = [], []  # the pieces, and the road of each
    for r, road in enumerate(roads):
        pieces = cut_at_corners(road, lambda w, rd=road.road: Bends(w, rd.two_way, design,
                                                                         speed))
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
    boundary = boundary_of(drawn)
    gates_at = []
    for a, aisle in enumerate(aisles):
        for e, (kind, _) in enumerate(aisle.ends):
            if kind == "open" and _at_edge(aisle, e, parking):
                aisle.line = drivable(extend_to(aisle.line, e, boundary, 0.02), needs[a])
                gates_at.append((a, e))
    ids = []
    for k, r in enumerate(of_road):
        first = of_road.index(r)
        ids.append(f"L{roads[r].road.lanelets[0]}" + (f"-{k - first + 1}"
                                                       if of_road.count(r) > 1 else ""))
    kept, remarks = _inside(aisles, ids, boundary, reasons)
    gates_at = [(kept.index(a), e) for a, e in gates_at if a in kept]
    aisles, ids, bends, needs = ([xs[k] for k in kept] for xs in (aisles, ids, bends, needs))
    for aisle, bend in zip(aisles, bends, strict=True):
        reasons.update(beside_bends(aisle, bend))
    if not gates_at:
        raise ScenarioError(None, f"{m.source}: no road of the map ends at its edge"
                                  + (" inside the lot's boundary" if remarks else "")
                                  + ": the lot has nowhere for cars to come in")
    slots = written_slots(aisles, ids, reasons, boundary)
    drawn_map = unary_union([ground, spot_ground])
    blocks, dropped_lines = blocking(m, ground, spot_ground)
    entrances, exits = [], []
    for a, e in gates_at:
        entrance, exit_ = _gates(aisles[a], e, {ll.id: ll for ll in m.lanelets})
        entrances += [entrance] if entrance else []
        exits += [exit_] if exit_ else []
    draft = LotDraft(
        name=_name(m.source.stem),
        description=f"{m.source.name}: {_n(len(slots), 'slot')} from the map's parking_spot "
                    f"areas, {_n(len(aisles), 'aisle')} from its lanelets.",
        boundary=ring(boundary),
        vehicle_types=list(VEHICLE_TYPES),
        speed_limit_kmh=_speed_limit(m),
        aisles=[AisleDraft(ids[k], [tuple(map(float, p)) for p in a.line], a.width,
                           not a.road.two_way, _aisle_note(a)) for k, a in enumerate(aisles)],
        slots=[s for s, _ in slots],
        obstacles=blocks,
        paved=(drawn_areas(drawn_map) + corner_areas(aisles, ids)
               + swept_areas(aisles, ids, bends, drawn_map)),
        paved_aisles=True,
        entrances=entrances,
        exits=exits,
        traffic=TRAFFIC,
    )
    _builds(draft, reasons, design, m.source)
    if not draft.slots:  # nowhere to park: the lot is written to be drawn and edited
        draft.traffic = None
    draft.header = _header(m, parts, len(net.connectors), aisles, draft.slots, reasons,
                           dropped_lines, remarks)
    draft.description = (f"{m.source.name}: {_n(len(draft.slots), 'slot')} from the map's "
                         f"parking_spot areas, {_n(len(aisles), 'aisle')} from its lanelets.")
    lot = ImportedLot(m.source.stem, float(drawn_map.area), mapped=len(draft.slots),
                      aisles=len(aisles), gates=len(gates_at),
                      reason="; ".join(
                          remarks + ([f"{len(reasons)} of {len(m.spots)} parking spots not "
                                      "imported (why: in the file's header)"] if reasons else [])
                          + (["no slot: no traffic written"] if not draft.slots else [])),
                      projection_error=m.error)
    return draft, lot


def _header(m: Lanelet2Map, parts: list, connectors: int, aisles: list[AisleLayout],
            slots: list[SlotDraft], reasons: dict[str, str], dropped_lines: str,
            remarks: list[str]) -> list[str]:
    """The scenario's opening comments: the source, the projection and its error, what
    became of the map's lanelets and spots (each spot not imported, with why), the gates'
    rule, what of the map was dropped."""
    header = [
        f"Imported by lotsim from the Lanelet2 map {m.source.name} (Autoware valet-parking "
        "convention).",
        f"Projection: {m.frame.describe()} ({m.origin_source}); its error over the map is "
        f"under {max(m.error, 1e-4) * 1000:.1f} mm.",
        f"{_n(len(m.lanelets), 'lanelet')} as {_n(len(parts), 'carriageway')} and "
        f"{_n(len(aisles), 'aisle')} ({_n(connectors, 'junction connector lanelet')} "
        f"dropped: lotsim builds its own turns); {_n(len(m.accesses), 'parking_access area')} "
        "widen the aisles to the spots.",
        f"{_n(len(m.spots), 'parking_spot area')}: {_n(len(slots), 'slot')}; "
        f"{len(reasons)} not imported" + (" (below, why)." if reasons else ".")
        + ("" if slots else " With no slot, no traffic is written."),
        "Gates: an entrance and an exit where each road ends at the map's edge, "
        f"{GATE_IN:g} m in; no gate tags are read.",
        *remarks,
    ]
    written = {s.id for s in slots}
    skewed = sorted((f"P{s.id}" for a in aisles for s in a.slots
                     if s.skewed and f"P{s.id}" in written), key=id_key)
    if skewed:
        header.append("Spots drawn as parallelograms (angled bays painted along the aisle), "
                      "each written as the largest rectangle along its long sides inside it, "
                      f"its front corner on the painted entry: {', '.join(skewed)}.")
    header += [f"spot {sid} not imported: {why}" for sid, why in
               sorted(reasons.items(), key=lambda kv: id_key(kv[0]))]
    if dropped_lines:
        header.append(dropped_lines)
    return header


INSET = 0.02
"""An aisle's centre line that leaves the lot's boundary is cut back to this inside it [m]."""
LEAST_AISLE = 1.0
"""An aisle with no piece this long inside the lot's boundary is dropped [m]."""


def _inside(aisles: list[AisleLayout], ids: list[str], boundary: Polygon,
            reasons: dict[str, str]) -> tuple[list[int], list[str]]:
    """Keep every aisle's centre line inside the lot's boundary as the scenario writes both
    (to the centimetre): a line that leaves it is cut back to its longest piece inside
    (:data:`INSET` in), an aisle with no piece of :data:`LEAST_AISLE` inside is dropped and
    its spots reported. The aisles kept (their indices), and a remark on each cut or drop."""
    written = Polygon(as_written(ring(boundary)))
    kept, remarks = [], []
    for k, aisle in enumerate(aisles):
        line = inside_part(aisle.line, written, INSET, LEAST_AISLE)
        if line is None:
            remarks.append(f"aisle {ids[k]} dropped: its lanelets lie outside the lot's "
                           "boundary (the drawn ground it holds)")
            for spot in aisle.slots:
                reasons[spot.id] = f"it opens onto aisle {ids[k]}, dropped"
            aisle.slots = []
            if k + 1 < len(aisles) and aisles[k + 1].ends[0][0] == "corner":
                aisles[k + 1].ends[0] = ("cut", None)  # no L with the aisle dropped
            continue
        if line is not aisle.line:
            lost = LineString(aisle.line).length - LineString(line).length
            by = f"{lost:.2f} m" if lost >= 0.005 else "under 1 cm"
            remarks.append(f"aisle {ids[k]} cut back by {by}: its centre line left the lot's "
                           "boundary")
            aisle.line = line
        kept.append(k)
    return kept, remarks


def _builds(draft: LotDraft, reasons: dict[str, str], design: DesignVehicle,
            source: Path) -> None:
    """Build the draft's lot as ``lotsim validate`` does; a slot the build refuses is
    dropped, with lotsim's reason, and the lot built again.

    Raises
    ------
    LotsimError
        The lot does not build for another reason (nothing is written then).
    """
    for _ in range(len(draft.slots) + 1):
        try:
            build_lot(read_scenario(draft.to_yaml()).scenario.lot, design)
            return
        except ScenarioError as exc:
            named = set(re.findall(r"slot '([^']+)'", exc.message))
            gone = [sd for sd in draft.slots if sd.id in named]
            if not gone:
                raise LotsimError(f"{source}: the lot laid out from the map does not build: "
                                  f"{exc.message}") from None
            draft.slots = [sd for sd in draft.slots if sd is not gone[-1]]
            reasons[gone[-1].id[1:]] = f"lotsim refuses it: {exc.message}"


def _n(count: int, what: str) -> str:
    """``3 aisles``, ``1 aisle``."""
    return f"{count} {what}" if count == 1 else f"{count} {what}s"


def _aisle_note(aisle: AisleLayout) -> str:
    ids = aisle.road.lanelets
    shown = ", ".join(ids[:8]) + (", ..." if len(ids) > 8 else "")
    kind = "two-way" if aisle.road.two_way else "one-way"
    return (f"lanelets {shown} ({kind}, carriageway {aisle.road.width:.2f} m): "
            f"{len(aisle.slots)} spots open onto it")


def _name(stem: str) -> str:
    name = re.sub(r"[^A-Za-z0-9_.-]+", "-", stem).strip("-.")
    return name or "lanelet2-lot"


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
