"""The rectangle a car parks in inside a mapped spot's four-cornered outline.

A spot is mapped as a rectangle (a bay or a kerbside space, at whatever angle to its aisle)
or, for an angled bay painted along its aisle, as a parallelogram: two sides along the
aisle's edge and the kerb, two slanted. lotsim's slots are rectangles (an angled one is
the rectangle of an angled row, ``docs/scenario.md``), so :func:`spot_shape` takes the
outline's rectangle: for a rectangle, its centre and its opposite sides averaged; for a
parallelogram, the largest rectangle along its long sides that fits inside it, whose front
entry corner lies on the painted entry line, as in an angled row.

>>> import numpy as np
>>> s = spot_shape(np.array([[0, 0], [2.5, 0], [2.5, 5], [0, 5]]))
>>> float(s.width), float(s.length), float(s.skew)
(2.5, 5.0, 0.0)
>>> r = 2 ** 0.5 / 2  # a 45° bay 2.5 m wide painted along the x axis, 5.5 m deep
>>> p = spot_shape(np.array([[0, 0], [2.5 / r, 0], [2.5 / r + 5.5, 5.5], [5.5, 5.5]]))
>>> round(p.width, 3), round(p.length, 3), round(float(np.degrees(p.skew)), 1)
(2.5, 5.278, 45.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from lotsim.core.geometry import FloatArray

SKEW_DEG = 5.0
"""An outline whose sides meet more than this off square [degrees] is a parallelogram, not a
rectangle drawn a little out of true."""


@dataclass(frozen=True)
class SpotShape:
    """A spot's rectangle.

    Attributes
    ----------
    center : ndarray (2,)
        [m].
    axis : ndarray (2,)
        Unit vector along its long sides (either way).
    width, length : float
        Across and along the long sides [m].
    skew : float
        How far the outline's sides meet off square [rad]: 0 for a rectangle; for a
        parallelogram, the rectangle lies inside it and is smaller.
    long_pair : int
        Which pair of the outline's sides (0: sides 0 and 2, 1: sides 1 and 3) is long.
    """

    center: FloatArray
    axis: FloatArray
    width: float
    length: float
    skew: float
    long_pair: int


def spot_shape(corners: FloatArray) -> SpotShape:
    """The rectangle of a four-cornered outline (``corners`` in order, (4, 2) [m]): the
    means of its opposite sides for one within :data:`SKEW_DEG` of square; for a
    parallelogram, ``width = across · cos(skew)`` and ``length = along - across ·
    sin(skew)``, ``across`` and ``along`` the mean lengths of its short and long sides."""
    c = np.asarray(corners, dtype=float)
    sides = [(c[i], c[(i + 1) % 4]) for i in range(4)]
    lengths = np.array([float(np.hypot(*(b - a))) for a, b in sides])
    long_pair = 0 if lengths[0] + lengths[2] >= lengths[1] + lengths[3] else 1
    s1 = sides[long_pair][1] - sides[long_pair][0]
    s2 = sides[long_pair + 2][0] - sides[long_pair + 2][1]  # the opposite side, same way
    u = s1 + s2
    u = u / float(np.hypot(*u))
    t1 = sides[1 - long_pair][1] - sides[1 - long_pair][0]
    t2 = sides[3 - long_pair][0] - sides[3 - long_pair][1]
    v = t1 + t2
    v = v / float(np.hypot(*v))
    along = float(lengths[long_pair] + lengths[long_pair + 2]) / 2
    across = float(lengths[1 - long_pair] + lengths[3 - long_pair]) / 2
    off = abs(float(np.dot(u, v)))  # sin(skew)
    center = c.mean(axis=0)
    if off <= math.sin(math.radians(SKEW_DEG)):
        return SpotShape(center, u, across, along, 0.0, long_pair)
    return SpotShape(center, u, across * math.sqrt(1 - off * off), along - across * off,
                     math.asin(off), long_pair)
