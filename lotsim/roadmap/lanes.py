"""Where things stand on a lot's lanes: their straights, how far along one a point lies,
the two lanes of a two-way aisle, which lanes may begin a slot's maneuver, and the lane a
gate stands on."""

from __future__ import annotations

import math

import numpy as np
import shapely

from lotsim.core.geometry import Segment, wrap_angle
from lotsim.errors import ScenarioError
from lotsim.lot.kinds import kind_of
from lotsim.lot.model import Lane, Lot, Portal, Slot, unit

EPS = 1e-6
"""Tolerance on stations and lengths along lanes [m]."""


def straights(lane: Lane) -> list[tuple[float, Segment]]:
    return [(float(s0), seg) for s0, seg in zip(lane.starts, lane.segments, strict=True)
            if seg.curvature == 0.0 and seg.sharpness == 0.0]


def straight_at(lane: Lane, station: float) -> tuple[float, Segment] | None:
    """The straight of ``lane`` that holds ``station`` (its start station and itself)."""
    for s0, seg in straights(lane):
        if s0 - EPS <= station <= s0 + seg.length + EPS:
            return s0, seg
    return None


def along(seg: Segment, pose) -> float:
    """How far along straight ``seg``'s line ``pose`` lies from its start [m]."""
    return float(np.dot(np.subtract(pose[:2], seg.start[:2]), unit(seg.start[2])))


def two_way_lanes(lot: Lot) -> list[tuple[Lane, Lane]]:
    """Each lane of a two-way aisle with the aisle's other lane, the one a car turning back
    lands on."""
    return [(lane, back) for aisle in lot.aisles.values()
            if not aisle.one_way and len(aisle.lanes) == 2
            for lane, back in (aisle.lanes, aisle.lanes[::-1])]


def lane_serves(lane: Lane, station: float, slot: Slot) -> bool:
    """Whether a car on ``lane`` can begin this slot's maneuver: its kind decides by the
    lane's direction there (:meth:`~lotsim.lot.kinds.SlotKind.serves`)."""
    return kind_of(slot).serves_lane(slot, lane, station)


PORTAL_HEADING_TOLERANCE = math.radians(15)
"""How far a portal's heading may differ from its lane's there [rad]: the car stands on
the lane, heading its way; more is refused rather than turned without a word."""


def portal_station(lot: Lot, portal: Portal) -> tuple[str, float]:
    """The lane (and station on it) a portal pose stands on: nearest lane heading its way."""
    pose = portal.pose
    best = None
    near = None  # the nearest lane the portal stands on, whichever way it heads
    under = None  # the lane right under the portal, when it heads another way
    for aisle in lot.aisles.values():
        half = aisle.width / (2 if aisle.one_way else 4)  # of a lane's own strip
        for lane in aisle.lanes:
            s, dist = lane.project(pose[:2])
            if dist > aisle.width / 2 + 0.01:
                continue
            heading = lane.pose_at(s)[2]
            off = abs(wrap_angle(heading - pose[2]))
            if near is None or (off, dist) < near[:2]:
                near = (off, dist, lane.id, heading)
            if off <= PORTAL_HEADING_TOLERANCE and (best is None or dist < best[0]):
                best = (dist, lane.id, s, half)
            elif off > PORTAL_HEADING_TOLERANCE and dist <= half + 0.01 and (
                    under is None or dist < under[0]):
                under = (dist, lane.id, heading)
    if best is not None and under is not None and best[0] > best[3] + 0.01:
        # standing on one lane, heading the way of another one beside it: a slip of the
        # heading, more likely than a car meant for the far lane
        raise ScenarioError(
            portal.where,
            f"{portal.id!r} at ({pose[0]:g}, {pose[1]:g}) heading "
            f"{math.degrees(pose[2]):.0f}° stands on lane {under[1]!r}, which heads "
            f"{math.degrees(under[2]) % 360:.0f}° (give heading_deg within "
            f"{math.degrees(PORTAL_HEADING_TOLERANCE):.0f}° of it); lane {best[1]!r}, "
            f"{best[0]:.2f} m away, heads {math.degrees(pose[2]) % 360:.0f}°: to stand on "
            f"it, move the portal onto it",
        )
    if best is None:
        there = (f"; lane {near[2]!r} there heads {math.degrees(near[3]) % 360:.0f}° (give "
                 f"heading_deg within {math.degrees(PORTAL_HEADING_TOLERANCE):.0f}° of it)"
                 if near is not None else "")
        raise ScenarioError(
            portal.where,
            f"{portal.id!r} at ({pose[0]:g}, {pose[1]:g}) heading "
            f"{math.degrees(pose[2]):.0f}° is on no lane driven that way{there}",
        )
    lane = next(ln for ln in lot.lanes if ln.id == best[1])
    body = shapely.Polygon(lot.design.footprints(np.array([lane.pose_at(best[2])]))[0])
    # (on the pavement it is: its lane was fitted to the ground, and the gates beyond the
    # aisle ends lie outside the lot)
    out = body.difference(lot.boundary).area
    if out > 1e-6:
        raise ScenarioError(
            portal.where,
            f"a car standing at {portal.id!r} sticks out of the lot boundary "
            f"({out:.2f} m²); cars appear and vanish at portals, so move it inward",
        )
    return best[1], best[2]


ZONE_STEP = 0.25
"""Spacing of the points along a path at which the lot's speed zones are read [m]."""


def path_speed_limit(lot: Lot, sample) -> float:
    """The speed limit along a path whose poses ``sample(step)`` gives (N, 3 or more), read
    at :data:`ZONE_STEP` (the lot's limit, unsampled, when the lot has no zones) [m/s]."""
    if not lot.zones:
        return lot.speed_limit
    return speed_limit_along(lot, sample(ZONE_STEP)[:, :2])


def speed_limit_along(lot: Lot, points: np.ndarray) -> float:
    """The speed limit along a path through ``points`` (N, 2): the lowest of the lot's
    zones it runs in [m/s]."""
    limit = lot.speed_limit
    line = shapely.LineString(points) if lot.zones else None
    for zone in lot.zones:
        if zone.polygon.intersects(line) and zone.polygon.intersection(line).length > EPS:
            limit = min(limit, zone.limit)
    return limit
