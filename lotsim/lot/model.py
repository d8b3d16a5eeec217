"""The built lot: slots as polygons, aisles with their lanes, areas, zones.

Everything here is geometry in metres and radians, made by
:func:`lotsim.lot.build.build_lot` from a :class:`~lotsim.lot.spec.LotSpec`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon
from shapely.geometry.base import BaseGeometry

from lotsim.core.geometry import (
    FloatArray,
    Pose,
    Segment,
    cc_turn,
    rectangle_footprints,
    wrap_angle,
)
from lotsim.errors import Location
from lotsim.lot.kinds import KINDS
from lotsim.lot.settings import LotSettings
from lotsim.lot.uses import STANDARD, USES


@dataclass(frozen=True, slots=True)
class DesignVehicle:
    """The envelope of a scenario's vehicle types: what every aisle must carry.

    Attributes
    ----------
    width, front, rear : float
        Largest body width and rear-axle→bumper distances [m].
    min_radius : float
        Largest minimum turning radius [m]: every lane curve is at least this.
    max_curvature_rate : float
        Smallest ``max_steer_rate / wheelbase`` [1/(m·s)]: how fast every type can
        change its path's curvature, steering from straight ahead. A clothoid of
        sharpness ``σ`` driven at ``v`` asks for ``σ · v`` of it.
    max_lateral_accel : float
        Smallest lateral-acceleration limit [m/s²].
    """

    width: float
    front: float
    rear: float
    min_radius: float
    max_curvature_rate: float
    max_lateral_accel: float

    @classmethod
    def envelope(cls, vehicle_types) -> DesignVehicle:  # any VehicleType-like
        """The smallest envelope that holds every one of ``vehicle_types``."""
        types = list(vehicle_types)
        return cls(
            width=max(v.width for v in types),
            front=max(v.front for v in types),
            rear=max(v.rear for v in types),
            min_radius=max(v.min_turning_radius for v in types),
            max_curvature_rate=min(v.limits.max_steer_rate / v.wheelbase for v in types),
            max_lateral_accel=min(v.limits.max_lateral_accel for v in types),
        )

    def sharpness(self, speed: float) -> float:
        """Sharpness [1/m²] of the clothoids every type can drive at ``speed`` [m/s] within
        its steering rate."""
        return self.max_curvature_rate / speed

    def footprints(self, poses: FloatArray) -> FloatArray:
        """Envelope rectangles at poses (N, 3) → (N, 4, 2)."""
        h = self.width / 2
        body = [[-self.rear, -h], [self.front, -h], [self.front, h], [-self.rear, h]]
        return rectangle_footprints(poses, body)


@dataclass(frozen=True, eq=False)
class Slot:
    """A parking slot.

    Attributes
    ----------
    id : str
    kind : str
        ``perpendicular``, ``parallel`` or ``angled``: what it decides is its
        :class:`~lotsim.lot.kinds.SlotKind` (:func:`~lotsim.lot.kinds.kind_of`).
    polygon : ndarray, shape (4, 2)
        Corners, counter-clockwise [m].
    entry : ndarray, shape (2, 2)
        The side a car crosses to get in, facing the aisle [m].
    heading : float
        Heading of a car parked nose-in (perpendicular, angled: from the entry
        into the slot) or parked in the direction of the adjacent lane's
        traffic (parallel) [rad].
    aisle : str
        The aisle the slot opens onto.
    side : str
        ``left`` or ``right`` of the aisle's polyline direction.
    station : float
        Position of the entry's midpoint along the aisle centreline [m].
    angle : float
        Angle between the aisle direction and the slot's long axis [rad].
    width, length : float
        [m]
    use : str
        What the bay is for (:data:`~lotsim.lot.uses.USES`): ``standard`` unless the
        scenario names another.
    """

    id: str
    kind: str
    polygon: FloatArray
    entry: FloatArray
    heading: float
    aisle: str
    side: str
    station: float
    angle: float
    width: float
    length: float
    where: Location | None = field(default=None, repr=False, compare=False)
    use: str = STANDARD

    @property
    def center(self) -> tuple[float, float]:
        c = self.polygon.mean(axis=0)
        return (float(c[0]), float(c[1]))

    @cached_property
    def shape(self) -> Polygon:
        return Polygon(self.polygon)

    def __getstate__(self) -> dict:
        # without its shape, made again from the corners when asked for (quicker than
        # pickling it)
        return {k: v for k, v in self.__dict__.items() if k != "shape"}

    def centered_pose(self, front: float, rear: float) -> Pose:
        """Rear-axle pose of a car (``front``, ``rear`` overhangs from the axle [m]) parked
        centred in the slot, facing :attr:`heading`."""
        cx, cy = self.center
        shift = (front - rear) / 2
        return (cx - shift * math.cos(self.heading), cy - shift * math.sin(self.heading),
                self.heading)


@dataclass(frozen=True, eq=False)
class AccessAisle:
    """The access aisle beside one or two accessible bays (ADA 2010 §502.3): ground no car
    parks or drives on.

    Attributes
    ----------
    id : str
    polygon : ndarray, shape (4, 2)
        Corners, counter-clockwise, to the centrelines of its markings [m].
    slots : tuple of str
        The bays it serves (two bays may share one).
    width : float
        Across, to the markings' centrelines [m].
    """

    id: str
    polygon: FloatArray
    slots: tuple[str, ...]
    width: float
    where: Location | None = field(default=None, repr=False, compare=False)

    @cached_property
    def shape(self) -> Polygon:
        return Polygon(self.polygon)

    def __getstate__(self) -> dict:
        return {k: v for k, v in self.__dict__.items() if k != "shape"}


@dataclass(frozen=True, eq=False)
class Lane:
    """One direction of travel along an aisle: tangent-continuous forward segments.

    ``offset`` is the lane's distance to the right of the aisle centreline,
    seen in the lane's own direction [m]; ``with_polyline`` says whether the
    lane runs in the order of the aisle's points.
    """

    id: str
    aisle: str
    segments: tuple[Segment, ...]
    offset: float
    with_polyline: bool

    @cached_property
    def starts(self) -> FloatArray:
        """Station at which each segment starts [m]."""
        return np.concatenate([[0.0], np.cumsum([s.length for s in self.segments])[:-1]])

    @property
    def length(self) -> float:
        return float(self.starts[-1] + self.segments[-1].length)

    def locate(self, station: float) -> tuple[int, float]:
        """Segment index and distance into it for a lane station [m]."""
        i = int(np.searchsorted(self.starts, station, side="right") - 1)
        i = min(max(i, 0), len(self.segments) - 1)
        return i, min(max(station - float(self.starts[i]), 0.0), self.segments[i].length)

    def locate_all(self, stations: FloatArray) -> tuple[np.ndarray, FloatArray]:
        """:meth:`locate` of each of ``stations`` [m], at once: segment indices and distances
        into them."""
        stations = np.asarray(stations, dtype=float)
        i = np.clip(np.searchsorted(self.starts, stations, side="right") - 1, 0,
                    len(self.segments) - 1)
        lengths = np.array([seg.length for seg in self.segments])
        return i, np.minimum(np.maximum(stations - self.starts[i], 0.0), lengths[i])

    def pose_at(self, station: float) -> Pose:
        i, d = self.locate(station)
        x, y, t = self.segments[i].poses_at(d)[0]
        return (float(x), float(y), float(t))

    def poses_at(self, stations: FloatArray) -> list[Pose]:
        """:meth:`pose_at` of each of ``stations`` [m], the same floats: the stations on a
        straight or an arc at once."""
        i, d = self.locate_all(stations)
        out: list = [None] * len(i)
        for j in np.unique(i).tolist():
            at = np.flatnonzero(i == j)
            seg = self.segments[j]
            if seg.sharpness == 0.0:
                poses = seg.poses_at(d[at]).tolist()
            else:  # a clothoid's quadrature depends on the farthest station: one at a time
                poses = [seg.poses_at(float(x))[0].tolist() for x in d[at]]
            for k, pose in zip(at.tolist(), poses, strict=True):
                out[k] = tuple(pose)
        return out

    def curvature_at(self, station: float) -> float:
        """Signed curvature of the lane at ``station`` [1/m] (continuous along it)."""
        i, d = self.locate(station)
        return float(self.segments[i].curvature_at(d))

    def trimmed(self, s0: float, s1: float) -> Lane:
        """The part of the lane between stations ``s0 < s1`` [m]."""
        pieces = []
        for start, seg in zip(self.starts, self.segments, strict=True):
            a, b = max(s0 - start, 0.0), min(s1 - start, seg.length)
            if b - a > 1e-9:
                pieces.append(seg.piece(float(a), float(b)))
        return Lane(self.id, self.aisle, tuple(pieces), self.offset, self.with_polyline)

    def sample(self, step: float = 0.1) -> FloatArray:
        """Poses along the whole lane, at most ``step`` apart; (N, 3)."""
        parts = [s.sample(step) for s in self.segments]
        return np.concatenate([parts[0]] + [p[1:] for p in parts[1:]])

    @cached_property
    def line(self) -> LineString:
        """The lane as a polyline: straights by their ends, arcs every 0.1 m.

        Straights are not sampled, so projecting a point costs as much on a 2 km aisle as on a
        20 m one (a lane sampled every 0.1 m made building a long row quadratic in its slots).
        """
        parts = [s.sample(0.1 if s.max_curvature else max(s.length, 0.1))
                 for s in self.segments]
        return LineString(np.concatenate([parts[0]] + [p[1:] for p in parts[1:]])[:, :2])

    def project(self, point: tuple[float, float]) -> tuple[float, float]:
        """Station [m] of the lane point nearest ``point`` and its distance [m]."""
        p = shapely.Point(point)
        return float(self.line.project(p)), float(self.line.distance(p))


@dataclass(frozen=True, eq=False)
class Aisle:
    """A built aisle: its polygon, centreline and lanes."""

    id: str
    centerline: FloatArray  # (N, 2) polyline as given
    width: float
    one_way: bool
    bend_radius: float
    bend_sharpness: float  # of the clothoids into and out of its bends [1/m²]
    polygon: Polygon
    lanes: tuple[Lane, ...]
    where: Location | None = field(default=None, repr=False, compare=False)
    corner_sharpness: tuple[float, ...] = ()  # per corner where not bend_sharpness; inf: arc

    @cached_property
    def line(self) -> LineString:
        return LineString(self.centerline)

    @property
    def corners(self) -> tuple[float, ...]:
        """The sharpness of each corner's clothoids [1/m²] (``inf``: a plain arc, the car
        stopping to steer): :attr:`bend_sharpness` unless the corners were too close."""
        n = max(len(self.centerline) - 2, 0)
        return self.corner_sharpness or (self.bend_sharpness,) * n

    @cached_property
    def legs(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Per leg of the centreline: start station, heading, and the station range
        (lo, hi) of its straight part between the corner arcs [m, rad, m, m]."""
        vec = np.diff(self.centerline, axis=0)
        length = np.hypot(vec[:, 0], vec[:, 1])
        start = np.concatenate([[0.0], np.cumsum(length)[:-1]])
        heading = np.arctan2(vec[:, 1], vec[:, 0])
        turns = np.abs(np.atleast_1d(wrap_angle(np.diff(heading)))) if len(vec) > 1 else np.zeros(0)
        cut = np.array([(self.bend_radius * math.tan(t / 2) if math.isinf(sigma) else
                         cc_turn(float(t), 1 / self.bend_radius, sigma)[1])
                        if t > 1e-12 else 0.0 for t, sigma in zip(turns, self.corners,
                                                                  strict=True)])
        lo = start + np.concatenate([[0.0], cut])
        hi = start + length - np.concatenate([cut, [0.0]])
        return start, heading, lo, hi


@dataclass(frozen=True, eq=False)
class Area:
    """A non-drivable polygon: ``wall``, ``obstacle`` or ``no_go``."""

    id: str
    kind: str
    polygon: Polygon
    where: Location | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True, eq=False)
class SpeedZone:
    """Where the speed ``limit`` [m/s] applies; ``source`` is ``bump`` or ``zone``.

    For a bump, ``polygon`` is the region within its reach and ``line`` the bump.
    """

    id: str
    source: str
    polygon: Polygon
    limit: float
    line: LineString | None = None


@dataclass(frozen=True, slots=True)
class Portal:
    """An entrance or exit pose [m, m, rad]."""

    id: str
    pose: Pose
    where: Location | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True, eq=False)
class Lot:
    """A parking lot ready to be turned into a graph; ``settings``: those it was built
    with, which the roadmap's sweeps of junction turns read too."""

    boundary: Polygon
    aisles: dict[str, Aisle]
    slots: tuple[Slot, ...]
    areas: tuple[Area, ...]
    zones: tuple[SpeedZone, ...]
    entrances: tuple[Portal, ...]
    exits: tuple[Portal, ...]
    occupied: frozenset[str]
    speed_limit: float
    design: DesignVehicle
    pavement: BaseGeometry | None = None  # None: paved wall to wall
    access_aisles: tuple[AccessAisle, ...] = ()
    settings: LotSettings = field(default_factory=LotSettings)

    @property
    def ground(self) -> BaseGeometry:
        """Where cars may drive: the pavement, or the whole boundary when it is all paved."""
        return self.boundary if self.pavement is None else self.pavement

    @property
    def edge(self) -> str:
        """What a car leaving :attr:`ground` runs into, in messages."""
        return edge_of(self.pavement)

    @cached_property
    def slot_by_id(self) -> dict[str, Slot]:
        return {s.id: s for s in self.slots}

    @property
    def free_slots(self) -> tuple[Slot, ...]:
        return tuple(s for s in self.slots if s.id not in self.occupied)

    @property
    def lanes(self) -> tuple[Lane, ...]:
        return tuple(lane for a in self.aisles.values() for lane in a.lanes)

    def use_counts(self) -> dict[str, int]:
        """Number of bays of each use (:data:`~lotsim.lot.uses.USES`, in its order)."""
        out = dict.fromkeys(USES, 0)
        for s in self.slots:
            out[s.use] += 1
        return out

    def slot_counts(self) -> dict[str, int]:
        """Number of slots of each kind."""
        out = dict.fromkeys(KINDS, 0)
        for s in self.slots:
            out[s.kind] += 1
        return out


PAVEMENT_EDGE = "the edge of the pavement"
"""What a car leaving a lot's pavement runs into, in messages."""


def edge_of(pavement: BaseGeometry | None) -> str:
    """What a car leaving the ground runs into, in messages: the boundary of a lot paved
    wall to wall, else :data:`PAVEMENT_EDGE`."""
    return "the lot boundary" if pavement is None else PAVEMENT_EDGE


def unit(theta: float) -> FloatArray:
    """Unit vector at heading ``theta`` [rad]."""
    return np.array([math.cos(theta), math.sin(theta)])
