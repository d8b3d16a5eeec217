"""A plot to lay a lot out on, as frozen specs (``docs/layout.md``): its outline, the islands
to keep clear, its gates, the building entrances it serves, the vehicle types to serve, the
bays and aisles a designer allows, and the demand the candidates are compared at. Read from
YAML by :mod:`lotsim.design.plot_yaml`; laid out by :func:`lotsim.design.search.lay_out`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from lotsim.errors import Location
from lotsim.vehicles.model import VehicleType

Point = tuple[float, float]
Points = tuple[Point, ...]

ANGLES = (90, 60, 45)
"""The bay angles a layout may use [degrees]: 90° bays on two-way (or one-way) aisles,
60° and 45° bays on one-way aisles, leaning the way the aisle runs."""

DEFAULT_WIDTHS: dict[tuple[int, str], float] = {
    (90, "two-way"): 7.0,
    (90, "one-way"): 7.0,
    (60, "one-way"): 5.5,
    (45, "one-way"): 4.5,
}
"""Default aisle widths [m] per bay angle and direction (their sources: ``docs/layout.md``).
Angled bays are entered one way only, so their aisles are one-way."""

BAY_WIDTH = 2.5
"""Default bay width [m] (``docs/layout.md``)."""
BAY_LENGTH = 5.0
"""Default bay length [m] (``docs/layout.md``)."""
GATE_CLEARANCE = 10.0
"""Default distance from a gate's mouth within which no bay's centre lies [m]
(``docs/layout.md``): two lengths of the valet car (4.9 m), so that a car coming in is
through the gate and straight before it meets a car backing out of a bay, and a car
leaving does not back out across the lane of those coming in."""


def _loc() -> Location | None:
    return field(default=None, compare=False, repr=False)  # type: ignore[return-value]


@dataclass(frozen=True, slots=True)
class GateSpec:
    """Where a road meets the plot: a point on its boundary [m]; cars come in and leave
    there."""

    id: str
    at: Point
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class BuildingEntranceSpec:
    """Where people walk into a building the lot serves: a point [m], in the plot or
    beside it. The layout puts the accessible and EV bays nearest it (:class:`UsesSpec`),
    and the lot it writes names it for the walks ``lotsim validate`` reports."""

    id: str
    at: Point
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class IslandSpec:
    """A polygon inside the plot that the lot keeps clear (a planted island, a kiosk, a
    tree): no bay or aisle touches it, and cars do not drive on it."""

    id: str
    polygon: Points
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class UsesSpec:
    """The bays by use a plot asks its layouts for (``docs/layout.md``, ``uses``).

    Attributes
    ----------
    accessible : int or None
        Accessible bays in all, the van-accessible ones among them; None: as many as ADA
        2010 Table 208.2 asks for the layout's total (:func:`lotsim.lot.uses.ada_accessible`).
    van_accessible : int or None
        How many of those are van-accessible; None: one in six, or fraction of six
        (ADA 2010 §208.2.4, :func:`lotsim.lot.uses.ada_van`).
    ev : int
        EV bays, when :attr:`ev_share` is None.
    ev_share : float or None
        EV bays as a share of the layout's total, 0 to 1, rounded up.
    compact : (width, length) or None
        The size of the compact bays laid where a full bay does not fit [m]; None: none.

    Examples
    --------
    >>> UsesSpec().asked, UsesSpec(ev=2).asked
    (False, True)
    >>> UsesSpec(ev_share=0.1).ev_count(95)
    10
    """

    accessible: int | None = 0
    van_accessible: int | None = None
    ev: int = 0
    ev_share: float | None = None
    compact: tuple[float, float] | None = None
    where: Location | None = _loc()

    @property
    def asked(self) -> bool:
        """Whether the plot asks for any bay but standard ones."""
        return self.accessible != 0 or self.ev_wanted or self.compact is not None

    @property
    def ev_wanted(self) -> bool:
        return bool(self.ev) or bool(self.ev_share)

    @property
    def accessible_wanted(self) -> bool:
        return self.accessible != 0

    def ev_count(self, total: int) -> int:
        """EV bays for a layout of ``total`` bays."""
        if self.ev_share is None:
            return self.ev
        return math.ceil(self.ev_share * total - 1e-9)


@dataclass(frozen=True, slots=True)
class DemandSpec:
    """The traffic the candidates are run with and the written lot carries: ``count`` cars
    arriving at ``rate_per_hour`` (exponential gaps, seeded), each staying ``dwell`` seconds
    (``(min, max)``, uniform) or for good (None)."""

    count: int = 30
    rate_per_hour: float = 360.0
    dwell: tuple[float, float] | None = None
    where: Location | None = _loc()


@dataclass(frozen=True, slots=True)
class PlotSpec:
    """Everything a layout is made from.

    Attributes
    ----------
    name : str
        Names the written scenario (a plain file name).
    boundary : tuple of (x, y)
        The plot's outline, a simple polygon [m].
    islands : tuple of IslandSpec
        What to keep clear inside it.
    gates : tuple of GateSpec
        Where roads meet it (at least one).
    building_entrances : tuple of BuildingEntranceSpec
        Where people walk into the buildings it serves (none: not given).
    vehicle_types : tuple of VehicleType
        The types every bay must serve: each must reach it, park in it and leave it.
    angles : tuple of int
        The bay angles allowed [degrees], of :data:`ANGLES`.
    bay_width, bay_length : float
        The bay's size [m].
    gate_clearance : float
        No bay's centre lies within this distance of a gate's mouth [m] (0: bays may stand
        at the mouth).
    one_way : bool
        Whether one-way aisles may be used (the angled modules are one-way).
    aisle_widths : tuple of ((angle, direction), width)
        The aisle width for each bay angle and direction [m].
    circulation_width : float
        The width of the two-way aisles that join the modules to each other and to the
        gates [m].
    demand : DemandSpec
        The traffic the candidates are compared at.
    uses : UsesSpec
        The bays by use asked for (none: standard bays only).
    seed : int
        Seeds the demand's arrivals.
    """

    name: str
    boundary: Points
    gates: tuple[GateSpec, ...]
    vehicle_types: tuple[VehicleType, ...]
    islands: tuple[IslandSpec, ...] = ()
    angles: tuple[int, ...] = ANGLES
    bay_width: float = BAY_WIDTH
    bay_length: float = BAY_LENGTH
    gate_clearance: float = GATE_CLEARANCE
    one_way: bool = True
    aisle_widths: tuple[tuple[tuple[int, str], float], ...] = tuple(DEFAULT_WIDTHS.items())
    circulation_width: float = DEFAULT_WIDTHS[(90, "two-way")]
    demand: DemandSpec = DemandSpec()
    seed: int = 0
    description: str = ""
    source: str = "<plot>"
    vehicle_names: tuple[str, ...] = ()
    """How each vehicle type was given: a catalogue name, or "" for a definition."""
    building_entrances: tuple[BuildingEntranceSpec, ...] = ()
    uses: UsesSpec = UsesSpec()
    units: str = "m"
    """The unit the plot file gives its lengths in (``units: ft``); its layouts are written
    in it. The spec holds metres either way."""

    def aisle_width(self, angle: int, direction: str) -> float:
        """The aisle width for bays at ``angle`` [degrees] on a ``direction`` aisle [m]."""
        return dict(self.aisle_widths)[(angle, direction)]
