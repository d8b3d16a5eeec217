"""Frozen specs of a lot layout, as read from a scenario file.

Specs hold what the user wrote, in SI units and radians, with the
:class:`~lotsim.errors.Location` of each item so that problems found later
(when the lot is built) still point at the right line. They are built once,
at the YAML boundary (:mod:`lotsim.io.scenario_yaml`); :func:`lotsim.lot.build.build_lot`
turns them into geometry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from lotsim.core.checks import raise_first
from lotsim.core.geometry import Pose
from lotsim.errors import Location
from lotsim.lot.kinds import KINDS
from lotsim.lot.settings import LotSettings
from lotsim.lot.uses import STANDARD

Point = tuple[float, float]
Points = tuple[Point, ...]

SLOT_KINDS = tuple(KINDS)
SIDES = ("left", "right")


def _loc() -> Location | None:
    return field(default=None, compare=False, repr=False)  # type: ignore[return-value]


@dataclass(frozen=True, slots=True)
class AisleSpec:
    """A driving aisle along a centre polyline.

    ``one_way`` aisles are driven in the order of the polyline's points.
    ``bend_radius`` is the radius of the centreline at the polyline's corners
    [m]; ``None`` lets the builder pick one that the vehicles can drive.
    """

    id: str
    centerline: Points
    width: float
    one_way: bool = False
    bend_radius: float | None = None
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class RowSpec:
    """``count`` equal slots side by side along one side of an aisle.

    ``side`` is seen when driving along the aisle polyline. ``angle`` is the
    angle between the aisle direction and the slot's long axis [rad]: pi/2 for
    perpendicular, 0 for parallel, strictly between for angled (an angled slot
    leans toward the direction of the polyline). ``start`` is the station along
    the aisle centreline [m] where the first slot's entry begins; ``gap`` is
    the free space between neighbours along the aisle [m].
    """

    aisle: str
    side: str
    kind: str
    angle: float
    count: int
    slot_width: float
    slot_length: float
    start: float
    gap: float = 0.0
    id_prefix: str = ""
    first_number: int = 1
    where: Location | None = _loc()
    angle_where: Location | None = _loc()
    use: str = STANDARD
    access_aisle_width: float | None = None


@dataclass(frozen=True, slots=True)
class SlotSpec:
    """A single slot: either along an aisle (``aisle``, ``side``, ``at``) or
    free-standing (``center``, ``heading``: the direction a car faces when it
    has driven in forward [rad]). For a free-standing slot the builder finds
    the aisle its entry side opens onto."""

    id: str
    kind: str
    width: float
    length: float
    angle: float
    aisle: str | None = None
    side: str | None = None
    at: float | None = None
    center: Point | None = None
    heading: float | None = None
    where: Location | None = _loc()
    use: str = STANDARD
    access_aisle_width: float | None = None
    access_side: str = "right"


@dataclass(frozen=True, slots=True)
class AreaSpec:
    """A polygon that is not drivable: a wall, an obstacle (island, pillar) or a no-go zone."""

    id: str
    kind: str  # "wall" | "obstacle" | "no_go"
    polygon: Points
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class PavementSpec:
    """What is paved in a lot that is not paved wall to wall: with ``aisles``, the aisles,
    their kerb corners (of ``corner_radius`` [m]) where they join, and the slots; and the
    ``areas`` (``kind`` ``"paved"``). Cars drive only on it."""

    aisles: bool = True
    corner_radius: float = 3.0
    areas: tuple[AreaSpec, ...] = ()
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class SpeedBumpSpec:
    """A speed bump across the lanes; within ``reach`` metres of it the limit applies."""

    id: str
    line: Points
    limit: float  # [m/s]
    reach: float = 5.0
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class SpeedZoneSpec:
    """A polygon in which the speed ``limit`` [m/s] applies."""

    id: str
    polygon: Points
    limit: float
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class PortalSpec:
    """An entrance or exit: a pose on an aisle lane; heading is the driving direction."""

    id: str
    pose: Pose
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class OccupancySpec:
    """Slots taken at start: listed ``ids``, or each taken with probability
    ``fraction`` drawn from ``numpy.random.default_rng(seed)`` in slot order,
    keeping at least ``min_free`` free."""

    ids: tuple[str, ...] = ()
    fraction: float | None = None
    seed: int = 0
    min_free: int = 1
    where: Location | None = _loc()
    id_where: tuple[Location | None, ...] = field(default=(), compare=False, repr=False)


@dataclass(frozen=True, slots=True)
class BuildingEntranceSpec:
    """A door of a building the lot serves, at ``point`` [m]: what the walking distances
    of the accessible bays are measured to."""

    id: str
    point: Point
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class Requirement:
    """What a standard asks of one use of bay: at least ``count`` bays, or at least the
    ``share`` (0 to 1, rounded up) of the facility's bays."""

    use: str
    count: int | None = None
    share: float | None = None

    def least(self, total: int) -> int:
        """The bays of the use asked of a facility of ``total`` bays."""
        if self.count is not None:
            return self.count
        return math.ceil(round((self.share or 0.0) * total, 9))


@dataclass(frozen=True, slots=True)
class StandardSpec:
    """The standard a lot's bays by use are counted against: the built-in ADA 2010 Table
    208.2 (``requirements`` empty), or a table the scenario states."""

    name: str
    requirements: tuple[Requirement, ...] = ()
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class LotSpec:
    """Everything the scenario says about the lot; ``settings``: how it is built (the
    scenario's ``lot.build``), part of the prepared lot's cache key."""

    boundary: Points
    aisles: tuple[AisleSpec, ...]
    rows: tuple[RowSpec, ...] = ()
    slots: tuple[SlotSpec, ...] = ()
    areas: tuple[AreaSpec, ...] = ()
    speed_bumps: tuple[SpeedBumpSpec, ...] = ()
    speed_zones: tuple[SpeedZoneSpec, ...] = ()
    entrances: tuple[PortalSpec, ...] = ()
    exits: tuple[PortalSpec, ...] = ()
    occupancy: OccupancySpec = OccupancySpec()
    speed_limit: float = 20 / 3.6
    paved: PavementSpec | None = None  # None: all the ground inside the boundary
    where: Location | None = _loc()
    boundary_where: Location | None = _loc()
    building_entrances: tuple[BuildingEntranceSpec, ...] = ()
    standard: StandardSpec | None = None  # None: the built-in one (ADA 2010)
    settings: LotSettings = field(default_factory=LotSettings)

    def __post_init__(self) -> None:
        if not isinstance(self.settings, LotSettings):
            raise_first([("settings", f"expected LotSettings, found "
                                      f"{type(self.settings).__name__}")])
