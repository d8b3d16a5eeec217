"""LotSpec → Lot: slot polygons, aisle lanes, areas, zones, and every geometric check.

Each problem is a :class:`~lotsim.errors.ScenarioError` located at the spec
item it comes from: overlapping slots, slots on an aisle or obstacle or outside
the boundary, slots that open onto no aisle, entrances and exits off every
aisle, aisles too narrow or curves too tight for the scenario's vehicles.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry
from shapely.ops import unary_union

from lotsim.core.corners import corner_sharpness
from lotsim.core.geometry import FloatArray, cc_polyline, ccw, wrap_angle
from lotsim.errors import ScenarioError
from lotsim.lot.clearance import Collider
from lotsim.lot.kinds import KINDS
from lotsim.lot.model import (
    PAVEMENT_EDGE,
    Aisle,
    Area,
    DesignVehicle,
    Lane,
    Lot,
    Portal,
    Slot,
    SpeedZone,
    edge_of,
    unit,
)
from lotsim.lot.pavement import HEAL, pave
from lotsim.lot.spec import AisleSpec, LotSpec, OccupancySpec, RowSpec, SlotSpec

LANE_CLEARANCE = 0.15
"""Free space each side of the widest vehicle within its lane [m]."""
AREA_TOL = 1e-6
"""Overlaps smaller than this [m²] are touching, not overlapping."""
SWEEP_STEP = 0.2
"""Spacing of footprints when checking that a lane can be driven [m]."""
CRAWL_SPEED = 0.25
"""The slowest speed a bend of a lane is driven at [m/s] (0.9 km/h): corners too close for
the clothoids the steering rate allows at that speed are refused."""


def build_lot(spec: LotSpec, design: DesignVehicle) -> Lot:
    """Build and check a lot for vehicles no larger than ``design``.

    Parameters
    ----------
    spec : LotSpec
    design : DesignVehicle
        Envelope of the scenario's vehicle types (:meth:`DesignVehicle.envelope`).

    Raises
    ------
    ScenarioError
        The first problem found, located in the scenario file.
    """
    boundary = _polygon(spec.boundary, spec.boundary_where, "the lot boundary")
    aisles = {a.id: _build_aisle(a, design, boundary, spec.speed_limit) for a in spec.aisles}
    areas = tuple(
        Area(a.id, a.kind, _polygon(a.polygon, a.where, f"{a.kind} {a.id!r}"), a.where)
        for a in spec.areas
    )
    slots = _build_slots(spec, aisles)
    _check_slots(slots, aisles, areas, boundary)
    pavement = None
    if spec.paved is not None:
        paved = [_polygon(a.polygon, a.where, f"paved area {a.id!r}") for a in spec.paved.areas]
        pavement = pave(spec.paved, boundary, aisles, slots, paved)
    ground = boundary if pavement is None else pavement
    collider = Collider(obstacle_polygons(areas, slots),
                        drivable_region(boundary, aisles, design, ground), edge=edge_of(pavement))
    aisles = {k: _fit_lanes(a, design, collider) for k, a in aisles.items()}
    zones = tuple(
        SpeedZone(b.id, "bump", LineString(b.line).buffer(b.reach), b.limit, LineString(b.line))
        for b in spec.speed_bumps
    ) + tuple(
        SpeedZone(z.id, "zone", _polygon(z.polygon, z.where, f"speed zone {z.id!r}"), z.limit)
        for z in spec.speed_zones
    )
    if not spec.entrances:
        raise ScenarioError(spec.where, "expected at least one entry under lot.entrances")
    entrances = tuple(_portal(p, aisles, "entrance") for p in spec.entrances)
    exits = tuple(_portal(p, aisles, "exit") for p in spec.exits)
    lot = Lot(
        boundary=boundary,
        aisles=aisles,
        slots=slots,
        areas=areas,
        zones=zones,
        entrances=entrances,
        exits=exits,
        occupied=_occupancy(spec.occupancy, slots),
        speed_limit=spec.speed_limit,
        design=design,
        pavement=pavement,
    )
    return lot


# -- primitives --------------------------------------------------------------------------------
def _polygon(points, where, what: str) -> Polygon:
    poly = Polygon(points)
    if not poly.is_valid or poly.area <= AREA_TOL:
        reason = shapely.is_valid_reason(poly) if not poly.is_valid else "it has no area"
        raise ScenarioError(where, f"expected {what} to be a simple polygon, but {reason}")
    return poly


def obstacle_polygons(
    areas: tuple[Area, ...], slots: tuple[Slot, ...]
) -> list[tuple[str, Polygon]]:
    """What a vehicle driving on the lanes must not touch, labelled for messages."""
    out = [(f"{a.kind.replace('_', '-')} {a.id!r}", a.polygon) for a in areas]
    out += [(f"slot {s.id!r}", s.shape) for s in slots]
    return out


def lane_collider(lot: Lot) -> Collider:
    """A validity checker for driving on ``lot``'s lanes: slots count as occupied."""
    return Collider(
        obstacle_polygons(lot.areas, lot.slots),
        drivable_region(lot.boundary, lot.aisles, lot.design, lot.ground),
        edge=lot.edge,
    )


def drivable_region(
    boundary: Polygon, aisles: dict[str, Aisle], design: DesignVehicle,
    ground: BaseGeometry | None = None,
) -> BaseGeometry:
    """The ground cars may drive on (default: all within ``boundary``) plus a car-length
    gate beyond each aisle end that meets the boundary.

    Vehicles enter and leave through those ends, so their bodies may poke out there.
    """
    depth = design.front + design.rear
    gates = []
    outside = boundary.exterior
    for aisle in aisles.values():
        line = aisle.centerline
        for end, prev in ((line[0], line[1]), (line[-1], line[-2])):
            if outside.distance(Point(end)) > 0.5:
                continue
            d = (end - prev) / np.linalg.norm(end - prev)
            n = np.array([-d[1], d[0]]) * aisle.width / 2
            far = end + d * depth
            # on a pavement, the gate reaches into it: their edges, computed apart, may
            # leave a crack between them
            near = end - d * HEAL if ground is not None and ground is not boundary else end
            gates.append(Polygon([near - n, far - n, far + n, near + n]))
    ground = boundary if ground is None else ground
    return unary_union([ground, *gates]) if gates else ground


# -- aisles ------------------------------------------------------------------------------------
def lane_offset(aisle: AisleSpec | Aisle) -> float:
    """Distance of each lane from the centreline [m]: a quarter width on two-way aisles."""
    return 0.0 if aisle.one_way else aisle.width / 4


def bend_sharpness(radius: float, offset: float, design: DesignVehicle,
                   speed_limit: float) -> float:
    """Sharpness [1/m²] of the clothoids into and out of an aisle's bends: what every type
    can steer at the speed the tightest lane's arc allows (lateral acceleration, the lot's
    limit)."""
    speed = min(speed_limit, math.sqrt(design.max_lateral_accel * max(radius - offset, 1e-9)))
    return design.sharpness(speed)


def offset_polyline(points: FloatArray, right: float) -> FloatArray:
    """The polyline shifted ``right`` metres to the right of its direction, corners mitred."""
    p = np.asarray(points, dtype=float)
    d = np.diff(p, axis=0)
    d = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    n = np.column_stack([d[:, 1], -d[:, 0]])  # right normals of the legs
    out = np.empty_like(p)
    out[0], out[-1] = p[0] + right * n[0], p[-1] + right * n[-1]
    for i in range(1, len(p) - 1):
        a, b = n[i - 1], n[i]
        out[i] = p[i] + right * (a + b) / (1 + float(np.dot(a, b)))
    return out


def _build_aisle(spec: AisleSpec, design: DesignVehicle, boundary: Polygon,
                 speed_limit: float) -> Aisle:
    line = np.asarray(spec.centerline, dtype=float)
    if not boundary.buffer(1e-6).covers(LineString(line)):
        raise ScenarioError(spec.where, f"aisle {spec.id!r} leaves the lot boundary")
    lanes_n = 1 if spec.one_way else 2
    need = lanes_n * (design.width + 2 * LANE_CLEARANCE)
    if spec.width < need - 1e-9:
        kind = "one-way" if spec.one_way else "two-way"
        raise ScenarioError(
            spec.where,
            f"aisle {spec.id!r} is too narrow: a {kind} aisle needs {lanes_n} × "
            f"({design.width:.2f} m widest vehicle + 2 × {LANE_CLEARANCE:.2f} m) = "
            f"{need:.2f} m, found {spec.width:g} m",
        )
    offset = lane_offset(spec)
    radius = spec.bend_radius if spec.bend_radius is not None else design.min_radius + offset
    if radius - offset < design.min_radius - 1e-9 and len(line) > 2:
        raise ScenarioError(
            spec.where,
            f"aisle {spec.id!r}: curves too tight: bend_radius {radius:g} m puts its inner lane "
            f"on a {radius - offset:.2f} m radius, below the {design.min_radius:.2f} m minimum "
            f"turning radius of the largest vehicle type",
        )
    sharpness = bend_sharpness(radius, offset, design, speed_limit)
    paths = [(line, 0.0)] if spec.one_way else [(line, offset), (line[::-1], offset)]
    # concentric corners: a lane right of the centreline is outside a left turn
    drawn = []
    for pts, right in paths:
        heading = np.arctan2(*np.diff(pts, axis=0).T[::-1])
        drawn.append((offset_polyline(pts, right),
                      radius + right * np.sign(np.atleast_1d(wrap_angle(np.diff(heading))))))
    # corners too close for the clothoids of cruising speed are driven slower, with
    # sharper ones: the sharpness each corner needs on the centre line and on every lane
    corners = np.full(max(len(line) - 2, 0), sharpness)
    sharpest = design.sharpness(CRAWL_SPEED)
    try:
        for k, (pts, radii) in enumerate([(line, radius), *drawn]):
            need = corner_sharpness(pts, radii, sharpness, sharpest)
            corners = np.maximum(corners, need[::-1] if k == 2 else need)
    except ValueError as exc:
        raise ScenarioError(
            spec.where, f"aisle {spec.id!r}: curves too tight for a {radius:.2f} m bend: "
            f"{exc}, even at a crawl of {CRAWL_SPEED * 3.6:.1f} km/h: lengthen the leg"
            + (f", or give a smaller bend_radius (no less than "
               f"{design.min_radius + offset:.2f} m)" if radius > design.min_radius + offset
               + 1e-9 else "")
        ) from None
    lanes = []
    for k, (pts, radii) in enumerate(drawn):
        segs = cc_polyline(pts, radii, corners if k == 0 else corners[::-1])
        lanes.append(Lane(f"{spec.id}{'>' if k == 0 else '<'}", spec.id, tuple(segs),
                          paths[k][1], k == 0))
    polygon = LineString(line).buffer(spec.width / 2, cap_style="flat", join_style="round")
    return Aisle(spec.id, line, spec.width, spec.one_way, radius, sharpness, polygon,
                 tuple(lanes), spec.where,
                 corner_sharpness=tuple(map(float, corners)) if (corners != sharpness).any()
                 else ())


# -- slots -------------------------------------------------------------------------------------
def _slot_frame(
    aisle: Aisle, side: str, s0: float, s1: float, where, what: str
) -> tuple[FloatArray, FloatArray, FloatArray, float]:
    """Origin of station 0 on the aisle edge, along-aisle unit u, outward unit n, leg heading.

    The entry of a slot spans stations ``s0..s1``; it must lie on one straight
    part of the centreline (not on a bend).
    """
    start, heading, lo, hi = aisle.legs
    total = float(start[-1] + np.hypot(*(aisle.centerline[-1] - aisle.centerline[-2])))
    for i in range(len(start)):
        if lo[i] - 1e-9 <= s0 and s1 <= hi[i] + 1e-9:
            u = unit(float(heading[i]))
            left = np.array([-u[1], u[0]])
            n = left if side == "left" else -left
            origin = aisle.centerline[i] + (0 - start[i]) * u + n * aisle.width / 2
            return origin, u, n, float(heading[i])
    if s1 > total + 1e-9:
        raise ScenarioError(
            where,
            f"{what} runs to station {s1:.2f} m, past the end of aisle {aisle.id!r} "
            f"({total:.2f} m long)",
        )
    raise ScenarioError(
        where,
        f"{what} spans stations {s0:.2f}..{s1:.2f} m of aisle {aisle.id!r}, which are not on "
        f"one straight part of it (a slot's entry must not sit on a bend)",
    )


def _slot_on_aisle(
    sid: str, kind: str, angle: float, width: float, length: float,
    aisle: Aisle, side: str, station: float, where, what: str,
) -> Slot:
    """One slot whose entry begins at aisle ``station`` (its lowest station) [m]."""
    rules = KINDS[kind]
    along = rules.frontage(width, length, angle)
    origin, u, n, heading = _slot_frame(aisle, side, station, station + along, where, what)
    poly, entry, into = rules.place(origin, u, n, heading, station, width, length, angle,
                                    toward_traffic=side == "right" or aisle.one_way)
    return Slot(
        id=sid, kind=kind, polygon=ccw(poly), entry=entry,
        heading=float(wrap_angle(into)), aisle=aisle.id, side=side,
        station=station + along / 2, angle=angle, width=width, length=length, where=where,
    )


def _row_slots(row: RowSpec, index: int, aisles: dict[str, Aisle]) -> list[Slot]:
    aisle = _aisle_ref(aisles, row.aisle, row.where)
    pitch = KINDS[row.kind].pitch(row.slot_width, row.slot_length, row.angle) + row.gap
    prefix = row.id_prefix or f"{row.aisle}-{row.side}-"
    out = []
    for k in range(row.count):
        sid = f"{prefix}{row.first_number + k}"
        out.append(
            _slot_on_aisle(
                sid, row.kind, row.angle, row.slot_width, row.slot_length, aisle, row.side,
                row.start + k * pitch, row.where, f"slot {sid!r} of lot.rows[{index}]",
            )
        )
    return out


def _aisle_ref(aisles: dict[str, Aisle], name: str, where) -> Aisle:
    if name not in aisles:
        raise ScenarioError(
            where, f"expected the id of an aisle ({', '.join(aisles)}), found {name!r}"
        )
    return aisles[name]


def _single_slot(spec: SlotSpec, aisles: dict[str, Aisle]) -> Slot:
    if spec.aisle is not None:
        aisle = _aisle_ref(aisles, spec.aisle, spec.where)
        return _slot_on_aisle(
            spec.id, spec.kind, spec.angle, spec.width, spec.length, aisle, spec.side or "left",
            spec.at or 0.0, spec.where, f"slot {spec.id!r}",
        )
    return _free_slot(spec, aisles)


ANGLE_TOL = math.radians(1.0)
"""A free-standing angled slot's ``angle_deg`` and the angle its heading makes with its aisle
agree within this [rad]."""


def _free_slot(spec: SlotSpec, aisles: dict[str, Aisle]) -> Slot:
    """A slot placed by centre and heading; its entry is the side that opens onto an aisle."""
    c = np.asarray(spec.center, dtype=float)
    d = unit(spec.heading)
    n = np.array([-d[1], d[0]])
    hl, hw = spec.length / 2, spec.width / 2
    rr, fr = c - hl * d - hw * n, c + hl * d - hw * n
    fl, rl = c + hl * d + hw * n, c - hl * d + hw * n
    candidates = KINDS[spec.kind].entry_sides(rr, fr, fl, rl)
    best = None
    for edge in candidates:
        for aisle in aisles.values():
            gap = KINDS[spec.kind].entry_gap(edge, aisle.polygon)
            if best is None or gap < best[0]:
                best = (gap, edge, aisle)
    assert best is not None
    gap, edge, aisle = best
    if gap > 0.3:
        raise ScenarioError(
            spec.where,
            f"slot {spec.id!r} opens onto no aisle: its entry side is {gap:.2f} m from the "
            f"nearest aisle {aisle.id!r}",
        )
    mid = edge.mean(axis=0)
    station = float(aisle.line.project(Point(mid)))
    start, heading, _, _ = aisle.legs
    leg = int(np.clip(np.searchsorted(start, station, side="right") - 1, 0, len(start) - 1))
    u = unit(float(heading[leg]))
    on_line = np.asarray(aisle.line.interpolate(station).coords[0])
    away = c - on_line
    side = "left" if u[0] * away[1] - u[1] * away[0] > 0 else "right"
    angle = math.acos(min(1.0, abs(float(np.dot(d, u)))))
    if KINDS[spec.kind].fixed_angle is None and abs(angle - spec.angle) > ANGLE_TOL:
        raise ScenarioError(
            spec.where,
            f"slot {spec.id!r}: angle_deg is {math.degrees(spec.angle):g}, but its heading "
            f"makes {math.degrees(angle):.1f}° with aisle {aisle.id!r}, which it opens onto",
        )
    return Slot(
        id=spec.id, kind=spec.kind, polygon=ccw(np.array([rr, fr, fl, rl])), entry=edge,
        heading=float(wrap_angle(spec.heading)), aisle=aisle.id, side=side, station=station,
        angle=angle, width=spec.width, length=spec.length, where=spec.where,
    )


def _build_slots(spec: LotSpec, aisles: dict[str, Aisle]) -> tuple[Slot, ...]:
    slots: list[Slot] = []
    for i, row in enumerate(spec.rows):
        slots.extend(_row_slots(row, i, aisles))
    slots.extend(_single_slot(s, aisles) for s in spec.slots)
    seen: dict[str, Slot] = {}
    for s in slots:
        if s.id in seen:
            raise ScenarioError(s.where, f"slot id {s.id!r} is used twice")
        seen[s.id] = s
    return tuple(slots)


def _check_slots(
    slots: tuple[Slot, ...], aisles: dict[str, Aisle], areas: tuple[Area, ...], boundary: Polygon
) -> None:
    if not slots:
        return
    polys = np.array([s.shape for s in slots])
    inside = shapely.covers(boundary.buffer(1e-6), polys)
    for i in np.flatnonzero(~inside):
        s = slots[i]
        raise ScenarioError(s.where, f"slot {s.id!r} lies partly outside the lot boundary")
    others: list[tuple[str, Polygon]] = [(f"aisle {a.id!r}", a.polygon) for a in aisles.values()]
    others += [(f"{a.kind.replace('_', '-')} {a.id!r}", a.polygon) for a in areas]
    for label, geom in others:
        idx = np.flatnonzero(shapely.intersects(polys, geom))
        if idx.size:
            area = shapely.area(shapely.intersection(polys[idx], geom))
            bad = idx[area > AREA_TOL]
            if bad.size:
                s = slots[bad[0]]
                overlap = float(area[area > AREA_TOL][0])
                raise ScenarioError(
                    s.where, f"slot {s.id!r} overlaps {label} by {overlap:.2f} m²"
                )
    tree = shapely.STRtree(polys)
    left, right = tree.query(polys, predicate="intersects")
    keep = left < right
    left, right = left[keep], right[keep]
    if left.size:
        area = shapely.area(shapely.intersection(polys[left], polys[right]))
        bad = np.flatnonzero(area > AREA_TOL)
        if bad.size:
            k = bad[np.argmin(right[bad])]
            a, b = slots[left[k]], slots[right[k]]
            raise ScenarioError(
                b.where, f"slot {b.id!r} overlaps slot {a.id!r} by {float(area[k]):.2f} m²"
            )


def _occupancy(spec: OccupancySpec, slots: tuple[Slot, ...]) -> frozenset[str]:
    ids = [s.id for s in slots]
    if spec.fraction is None:
        known = set(ids)
        seen: set[str] = set()
        for k, sid in enumerate(spec.ids):
            where = spec.id_where[k] if k < len(spec.id_where) else spec.where
            if sid not in known:
                raise ScenarioError(where, f"expected a slot id, found {sid!r}, which no slot has")
            if sid in seen:
                raise ScenarioError(where, f"slot {sid!r} is listed twice")
            seen.add(sid)
        return frozenset(spec.ids)
    if spec.min_free > len(ids):
        raise ScenarioError(
            spec.where, f"min_free is {spec.min_free} but the lot has only {len(ids)} slots"
        )
    rng = np.random.default_rng(spec.seed)
    taken = rng.random(len(ids)) < spec.fraction
    short = spec.min_free - int((~taken).sum())
    if short > 0:
        taken[rng.choice(np.flatnonzero(taken), size=short, replace=False)] = False
    return frozenset(sid for sid, t in zip(ids, taken, strict=True) if t)


# -- portals and lanes -------------------------------------------------------------------------
def _portal(spec, aisles: dict[str, Aisle], what: str) -> Portal:
    p = Point(spec.pose[:2])
    if not any(a.polygon.buffer(0.01).covers(p) for a in aisles.values()):
        near = min(aisles.values(), key=lambda a: a.polygon.distance(p))
        raise ScenarioError(
            spec.where,
            f"{what} {spec.id!r} at ({spec.pose[0]:g}, {spec.pose[1]:g}) is on no aisle; "
            f"the nearest, {near.id!r}, is {near.polygon.distance(p):.2f} m away",
        )
    return Portal(spec.id, spec.pose, spec.where)


def _fit_lanes(aisle: Aisle, design: DesignVehicle, collider: Collider) -> Aisle:
    """Shorten each lane where its ends cannot hold the vehicle (a dead end, a wall).

    Within one vehicle length of a lane's ends the lane is cut back to where the
    design vehicle's sweep is clear; anything blocked further in means the aisle
    is too narrow or its curves too tight for the vehicle.
    """
    lanes = []
    reach = design.front + design.rear + SWEEP_STEP
    for lane in aisle.lanes:
        poses = lane.sample(SWEEP_STEP)
        st = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(poses[:, :2], axis=0).T))])
        blocked = collider.blocked(Collider.sweeps(design.footprints(poses)))
        head = st[1:] <= reach  # pair i spans stations st[i]..st[i+1]
        tail = st[:-1] >= lane.length - reach
        s0 = float(st[np.flatnonzero(blocked & head).max() + 1]) if (blocked & head).any() else 0.0
        s1 = float(st[np.flatnonzero(blocked & tail).min()]) if (blocked & tail).any() else None
        inner = np.flatnonzero(blocked & ~head & ~tail)
        if inner.size or (s1 is not None and s1 - s0 < SWEEP_STEP):
            k = inner[0] if inner.size else int(np.flatnonzero(blocked)[0])
            hit = collider.first_hit(Collider.sweeps(design.footprints(poses[k : k + 2])))
            what = hit.what if hit is not None else "an obstacle"
            x, y = poses[k, :2]
            if what == PAVEMENT_EDGE:
                raise ScenarioError(
                    aisle.where,
                    f"aisle {aisle.id!r}: the largest vehicle driving lane {lane.id!r} leaves "
                    f"the pavement near ({x:.1f}, {y:.1f}): pave the aisle (lot.paved: "
                    f"aisles: true, or an area under it)",
                )
            raise ScenarioError(
                aisle.where,
                f"aisle {aisle.id!r} is too narrow or its curves too tight: the largest "
                f"vehicle driving lane {lane.id!r} touches {what} near ({x:.1f}, {y:.1f})",
            )
        if s0 > 0.0 or s1 is not None:
            lane = lane.trimmed(s0, s1 if s1 is not None else lane.length)
        lanes.append(lane)
    return dataclasses.replace(aisle, lanes=tuple(lanes))

