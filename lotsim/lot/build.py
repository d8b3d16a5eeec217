"""LotSpec → Lot: aisle lanes, areas, zones, and every geometric check (the bays are placed
by :mod:`lotsim.lot.placing`).

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
from lotsim.core.geometry import FloatArray, cc_polyline, wrap_angle
from lotsim.errors import ScenarioError
from lotsim.lot.clearance import Collider
from lotsim.lot.model import (
    PAVEMENT_EDGE,
    AccessAisle,
    Aisle,
    Area,
    DesignVehicle,
    Lane,
    Lot,
    Portal,
    Slot,
    SpeedZone,
    edge_of,
)
from lotsim.lot.pavement import HEAL, pave
from lotsim.lot.placing import place_slots
from lotsim.lot.settings import LotSettings
from lotsim.lot.spec import AisleSpec, LotSpec, OccupancySpec

AREA_TOL = 1e-6
"""Overlaps smaller than this [m²] are touching, not overlapping."""


def build_lot(spec: LotSpec, design: DesignVehicle) -> Lot:
    """Build and check a lot for vehicles no larger than ``design``, with the spec's
    settings (:attr:`LotSpec.settings`: the lanes' clearance, the sweeps' spacing, the
    crawl speed of bends), which the lot keeps (:attr:`Lot.settings`).

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
    settings = spec.settings
    boundary = _polygon(spec.boundary, spec.boundary_where, "the lot boundary")
    aisles = {a.id: _build_aisle(a, design, boundary, spec.speed_limit, settings)
              for a in spec.aisles}
    areas = tuple(
        Area(a.id, a.kind, _polygon(a.polygon, a.where, f"{a.kind} {a.id!r}"), a.where)
        for a in spec.areas
    )
    slots, access = place_slots(spec, aisles)
    _check_slots(slots, aisles, areas, boundary)
    _check_access_aisles(access, slots, aisles, areas, boundary)
    pavement = None
    if spec.paved is not None:
        paved = [_polygon(a.polygon, a.where, f"paved area {a.id!r}") for a in spec.paved.areas]
        pavement = pave(spec.paved, boundary, aisles, slots, paved)
    ground = boundary if pavement is None else pavement
    collider = Collider(obstacle_polygons(areas, slots, access),
                        drivable_region(boundary, aisles, design, ground), edge=edge_of(pavement))
    aisles = {k: _fit_lanes(a, design, collider, settings.sweep) for k, a in aisles.items()}
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
        access_aisles=access,
        settings=settings,
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
    areas: tuple[Area, ...], slots: tuple[Slot, ...], access: tuple[AccessAisle, ...] = ()
) -> list[tuple[str, Polygon]]:
    """What a vehicle driving on the lanes must not touch, labelled for messages: the
    areas, the slots and the access aisles (ground no car drives on)."""
    out = [(f"{a.kind.replace('_', '-')} {a.id!r}", a.polygon) for a in areas]
    out += [(f"slot {s.id!r}", s.shape) for s in slots]
    out += [(f"access aisle {a.id!r}", a.shape) for a in access]
    return out


def lane_collider(lot: Lot) -> Collider:
    """A validity checker for driving on ``lot``'s lanes: slots count as occupied."""
    return Collider(
        obstacle_polygons(lot.areas, lot.slots, lot.access_aisles),
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
                 speed_limit: float, settings: LotSettings) -> Aisle:
    line = np.asarray(spec.centerline, dtype=float)
    if not boundary.buffer(1e-6).covers(LineString(line)):
        raise ScenarioError(spec.where, f"aisle {spec.id!r} leaves the lot boundary")
    lanes_n = 1 if spec.one_way else 2
    clearance = settings.lane_clearance
    need = lanes_n * (design.width + 2 * clearance)
    if spec.width < need - 1e-9:
        kind = "one-way" if spec.one_way else "two-way"
        raise ScenarioError(
            spec.where,
            f"aisle {spec.id!r} is too narrow: a {kind} aisle needs {lanes_n} × "
            f"({design.width:.2f} m widest vehicle + 2 × {clearance:.2f} m lane clearance)"
            f" = {need:.2f} m, found {spec.width:g} m",
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
    sharpest = design.sharpness(settings.crawl_speed)
    try:
        for k, (pts, radii) in enumerate([(line, radius), *drawn]):
            need = corner_sharpness(pts, radii, sharpness, sharpest)
            corners = np.maximum(corners, need[::-1] if k == 2 else need)
    except ValueError as exc:
        raise ScenarioError(
            spec.where, f"aisle {spec.id!r}: curves too tight for a {radius:.2f} m bend: "
            f"{exc}, even at a crawl of {settings.crawl_speed * 3.6:.1f} km/h: lengthen the "
            f"leg"
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


def _check_access_aisles(
    access: tuple[AccessAisle, ...], slots: tuple[Slot, ...], aisles: dict[str, Aisle],
    areas: tuple[Area, ...], boundary: Polygon,
) -> None:
    """Each access aisle lies within the boundary and overlaps no aisle of the vehicular
    way, no area, no bay and no other access aisle (ADA 2010 §502.3.4: an access aisle
    does not overlap the vehicular way); a problem is located at the row or slot whose bay
    it serves."""
    if not access:
        return
    inside = boundary.buffer(1e-6)
    others: list[tuple[str, BaseGeometry]] = [(f"aisle {a.id!r} (the vehicular way)",
                                               a.polygon) for a in aisles.values()]
    others += [(f"{a.kind.replace('_', '-')} {a.id!r}", a.polygon) for a in areas]
    others += [(f"slot {s.id!r}", s.shape) for s in slots]
    for k, a in enumerate(access):
        what = f"the access aisle of slot{'s' if len(a.slots) > 1 else ''} " \
               f"{', '.join(map(repr, a.slots))}"
        if not inside.covers(a.shape):
            raise ScenarioError(a.where, f"{what} lies partly outside the lot boundary")
        for label, geom in [*others, *((f"the access aisle {b.id!r}", b.shape)
                                       for b in access[:k])]:
            overlap = a.shape.intersection(geom).area
            if overlap > AREA_TOL:
                raise ScenarioError(a.where, f"{what} overlaps {label} by {overlap:.2f} m²: "
                                             f"leave room beside the bay for it")


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


def _fit_lanes(aisle: Aisle, design: DesignVehicle, collider: Collider, step: float
               ) -> Aisle:
    """Shorten each lane where its ends cannot hold the vehicle (a dead end, a wall).

    Within one vehicle length of a lane's ends the lane is cut back to where the
    design vehicle's sweep (footprints ``step`` apart [m]) is clear; anything blocked
    further in means the aisle is too narrow or its curves too tight for the vehicle.
    """
    lanes = []
    reach = design.front + design.rear + step
    for lane in aisle.lanes:
        poses = lane.sample(step)
        st = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(poses[:, :2], axis=0).T))])
        blocked = collider.blocked(Collider.sweeps(design.footprints(poses)))
        head = st[1:] <= reach  # pair i spans stations st[i]..st[i+1]
        tail = st[:-1] >= lane.length - reach
        s0 = float(st[np.flatnonzero(blocked & head).max() + 1]) if (blocked & head).any() else 0.0
        s1 = float(st[np.flatnonzero(blocked & tail).min()]) if (blocked & tail).any() else None
        inner = np.flatnonzero(blocked & ~head & ~tail)
        if inner.size or (s1 is not None and s1 - s0 < step):
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

