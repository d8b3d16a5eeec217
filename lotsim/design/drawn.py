"""What a candidate layout is drawn as (:mod:`lotsim.design.candidates`): its straight
aisles, its rows of bays and its gates, in plot coordinates, the module kind that drew it,
and the clearances everything is drawn with."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from shapely.geometry import LineString, Polygon

Point2 = tuple[float, float]


def strip(a, b, width: float) -> Polygon:
    """The pavement of an aisle of ``width`` [m] from ``a`` to ``b``, square at its ends."""
    return LineString([a, b]).buffer(width / 2, cap_style="flat")

CLEAR = 0.05
"""Bays, aisles and islands are kept this far apart in the drawing [m], so that the
scenario's numbers, written to the centimetre, never make them overlap."""
EPS = 1e-6
"""Things drawn exactly :data:`CLEAR` apart are clear, whatever the rounding of a turned
frame [m]."""
MIN_JUNCTION_DEG = 30.0
"""A module or gate aisle meets the aisle it ends on at least at this angle [degrees]."""


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
    the stretch of boundary, as wide as the aisle, where the aisle meets it (for an aisle
    turned from square to the boundary, its first cross-section, which lies in the plot);
    and for such an aisle its ``approach``, from the gate to the middle of its mouth."""

    id: str
    aisle: str
    entrance: tuple[float, float, float]
    exit: tuple[float, float, float]
    mouth: tuple[Point2, Point2] | None = None
    approach: tuple[Point2, Point2] | None = None


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
    """For a spine candidate (:func:`~lotsim.design.candidates.draw_spine`): its gate, and
    whether it has branches."""
    along: tuple[int, ...] = ()
    """The boundary's edges the ring runs beside, with no perimeter row
    (:func:`~lotsim.design.candidates.draw`)."""

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
