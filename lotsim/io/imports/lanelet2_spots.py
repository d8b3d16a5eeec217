"""A Lanelet2 map's ``parking_spot`` areas as slots: the rectangle each outline is, and the
side a car enters by.

A spot is drawn as a four-cornered area; :func:`fit_spot` takes the rectangle it is (centre,
long axis, width across, length along: the means of its opposite sides; inside a
parallelogram, the largest along its long sides, :mod:`.spot_shape`) and finds its
entry: the side that lies along the drivable ground the map draws in front of it (its
``parking_access`` area or a lanelet), the one with most of its length within
:data:`ENTRY_TOL` of it. A short side there is a bay entered head- or tail-first; a long
side, a kerbside (parallel) space.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from lotsim.core.geometry import FloatArray
from lotsim.io.imports.lanelet2_map import MapArea
from lotsim.io.imports.spot_shape import spot_shape

ENTRY_TOL = 0.1
"""A side lies along the drivable ground where it is within this of it [m]."""
ENTRY_SHARE = 0.5
"""A spot opens onto the ground by a side at least this share of which lies along it."""


@dataclass(frozen=True)
class Spot:
    """A mapped spot as a rectangle.

    Attributes
    ----------
    center : ndarray (2,)
        [m].
    heading : float
        Of a car that drove in forward [rad]: out of the entry, into the spot (along a
        parallel spot's long side, either way).
    width, length : float
        Across and along a parked car [m].
    entry : ndarray (2, 2)
        The entry side's ends [m].
    outward : ndarray (2,)
        Unit normal of the entry, pointing out of the spot onto the ground.
    parallel : bool
        The entry is a long side.
    reason : str
        Why the spot opens onto nothing ("" when it opens onto the ground).
    kind : str
        The slot kind, once the aisle it opens onto is known (:func:`classified`).
    angle : float
        The angle between its long side and that aisle [degrees].
    skewed : bool
        Its outline is a parallelogram (:mod:`.spot_shape`): the rectangle lies inside it,
        its front entry corner on the outline's entry side.
    """

    id: str
    polygon: Polygon
    center: FloatArray
    heading: float
    width: float
    length: float
    entry: FloatArray
    outward: FloatArray
    parallel: bool
    reason: str = ""
    kind: str = "perpendicular"
    angle: float = 90.0
    skewed: bool = False

    @property
    def rectangle(self) -> Polygon:
        """The rectangle the slot will be [m]."""
        return rectangle(self.center, self.heading, self.width, self.length)

    @property
    def entry_mid(self) -> FloatArray:
        return self.entry.mean(axis=0)


ANGLED_DEG = 15.0
"""A spot entered by a short side whose long side is more than this off square to its
aisle is angled [degrees]."""


def classified(spot: Spot, along: float) -> Spot:
    """``spot`` with its kind and angle against an aisle heading ``along`` [rad] beside it:
    parallel (entered by a long side; a car in it faces the way the traffic beside it runs,
    right-hand traffic), else perpendicular, or angled when its long side is more than
    :data:`ANGLED_DEG` off square to the aisle."""
    u = np.array([math.cos(along), math.sin(along)])
    axis = np.array([math.cos(spot.heading), math.sin(spot.heading)])
    angle = math.degrees(math.acos(min(1.0, abs(float(np.dot(u, axis))))))
    if spot.parallel:
        left = float(u[0] * spot.outward[1] - u[1] * spot.outward[0]) < 0  # the spot's side
        heading = along + math.pi if left else along
        heading = math.atan2(math.sin(heading), math.cos(heading))
        return replace(spot, kind="parallel", angle=angle, heading=heading)
    kind = "perpendicular" if angle >= 90 - ANGLED_DEG else "angled"
    return replace(spot, kind=kind, angle=angle)


def rectangle(center, heading: float, width: float, length: float) -> Polygon:
    """A ``length`` × ``width`` rectangle centred on ``center``, long axis at ``heading``."""
    c = np.asarray(center, dtype=float)
    d = np.array([math.cos(heading), math.sin(heading)])
    n = np.array([-d[1], d[0]])
    hl, hw = length / 2, width / 2
    return Polygon([c - hl * d - hw * n, c + hl * d - hw * n, c + hl * d + hw * n,
                    c - hl * d + hw * n])


def corners(poly: Polygon) -> FloatArray:
    """The four corners of a spot's outline (points on its straight sides dropped); a shape
    that is not four-cornered gives the corners of its smallest enclosing rectangle."""
    ring = np.asarray(shapely.simplify(poly, 0.02).exterior.coords)[:-1]
    if len(ring) != 4:
        ring = np.asarray(poly.minimum_rotated_rectangle.exterior.coords)[:-1]
    return ring


def fit_spot(area: MapArea, ground) -> Spot:
    """The rectangle of ``area`` and its entry onto ``ground`` (a shapely geometry: the
    mapped drivable ground, spots left out)."""
    c = corners(area.polygon)
    sides = [(c[i], c[(i + 1) % 4]) for i in range(4)]
    lengths = np.array([float(np.hypot(*(b - a))) for a, b in sides])
    shape = spot_shape(c)
    long_pair, u, center = shape.long_pair, shape.axis, shape.center
    near = ground.buffer(ENTRY_TOL)
    share = np.array([LineString([a, b]).intersection(near).length / max(lengths[i], 1e-9)
                      for i, (a, b) in enumerate(sides)])
    short = {1 - long_pair, 3 - long_pair}
    # the side most along the ground; a short side wins a tie (a bay at a row's end)
    k = max(range(4), key=lambda i: (round(float(share[i]), 2), i in short, -i))
    a, b = sides[k]
    t = (b - a) / float(np.hypot(*(b - a)))
    out = np.array([t[1], -t[0]])
    if float(np.dot(center - (a + b) / 2, out)) > 0:
        out = -out
    parallel = k not in short
    heading = math.atan2(u[1], u[0])
    if not parallel and float(np.dot(u, -out)) < 0:
        heading += math.pi  # a car drives in through the entry, away from the ground
    heading = math.atan2(math.sin(heading), math.cos(heading))
    reason = ""
    if share[k] < ENTRY_SHARE:
        gap = min(float(LineString(s).distance(ground)) for s in sides)
        reason = ("no side of it lies along the mapped drivable ground (lanelets, "
                  f"parking_access areas): {share[k] * 100:.0f}% of its best side, "
                  f"{gap:.2f} m away" if gap > 0.005 else
                  "no side of it lies along the mapped drivable ground (lanelets, "
                  "parking_access areas): it touches it only at a corner")
    return Spot(area.id, area.polygon, center, heading, shape.width, shape.length,
                np.array([a, b]), out, parallel, reason, skewed=shape.skew > 0)
