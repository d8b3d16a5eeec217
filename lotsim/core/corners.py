"""Corners of a polyline too close together for the clothoids wanted: how sharp each
corner's clothoids must be for every corner to fit on its legs (:func:`corner_sharpness`).

A lane turns at each corner of its aisle's centre line by a continuous-curvature turn
(:func:`~lotsim.core.geometry.cc_turn`): a clothoid, an arc, a clothoid. At cruising speed
the clothoids are long (the steering rate spread over the time the car takes), and two
corners on a short leg overlap. A driver takes such corners slower, turning the wheel
faster for the distance: a sharper clothoid, which the steering rate allows at that lower
speed (:func:`~lotsim.vehicles.motion.speed_cap` caps the speed on it accordingly), down
to a crawl; corners that would need sharper clothoids than a car can steer at a crawl are
refused.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from lotsim.core.geometry import _cc_corner, wrap_angle


def corner_sharpness(points: ArrayLike, radii: ArrayLike, sharpness: float, sharpest: float
                     ) -> list[float]:
    """The sharpness [1/m²] of each corner's clothoids along a polyline whose legs may be
    too short for corners of ``sharpness``: where two corners' turns would overlap on a leg
    (or a corner's turn would run past an end), the leg is shared between them in
    proportion to what each needs beyond a plain arc, and each such corner gets the least
    sharpness that fits its share.

    Parameters
    ----------
    points : array_like, shape (N, 2)
    radii : float or array_like of N - 2 floats
        Each corner's arc radius [m].
    sharpness : float
        The sharpness wanted [1/m²].
    sharpest : float
        The sharpest clothoid allowed [1/m²].

    Raises
    ------
    ValueError
        When a leg's corners do not fit with clothoids of ``sharpest`` (the message names
        the leg, its length and what its corners need as plain arcs).

    >>> square = [[0, 0], [11, 0], [11, 11], [0, 11]]    # legs of 11 m, radius 4.97 m
    >>> [round(s, 3) for s in corner_sharpness(square, 4.97, 0.05, 1.0)]
    [0.193, 0.193]
    """
    p = np.asarray(points, dtype=float)
    legs = np.diff(p, axis=0)
    lengths = np.hypot(legs[:, 0], legs[:, 1])
    headings = np.arctan2(legs[:, 1], legs[:, 0])
    turns = np.abs(np.atleast_1d(wrap_angle(np.diff(headings)))) if len(legs) > 1 \
        else np.zeros(0)
    radii = np.broadcast_to(np.asarray(radii, dtype=float), turns.shape)
    n = len(turns)

    def tangent(i: int, sigma: float) -> float:
        if turns[i] <= 1e-12:
            return 0.0
        if math.isinf(sigma):
            return float(radii[i] * math.tan(turns[i] / 2))
        return _cc_corner(float(turns[i]), float(1 / radii[i]), float(sigma))[1]

    want = np.array([tangent(i, sharpness) for i in range(n)])
    arc = np.array([tangent(i, math.inf) for i in range(n)])
    budget = want.copy()
    tight = [0] * n  # the leg that cut each corner's budget
    for j, length in enumerate(lengths):
        ends = [k for k in (j - 1, j) if 0 <= k < n]  # the corners at the leg's two ends
        if sum(want[k] for k in ends) <= length + 1e-9:
            continue
        least = sum(arc[k] for k in ends)
        excess = sum(want[k] - arc[k] for k in ends)
        for k in ends:
            share = arc[k] + max(length - least, 0.0) * (want[k] - arc[k]) / excess
            if share < budget[k]:
                budget[k], tight[k] = share, j
    out = []
    for i in range(n):
        if budget[i] >= want[i] - 1e-12:
            out.append(sharpness)
            continue
        if tangent(i, sharpest) > budget[i] + 1e-9:
            j = tight[i]
            raise ValueError(
                f"leg {j} is {lengths[j]:.2f} m long, too short for its corners: as plain "
                f"arcs they need {sum(arc[k] for k in (j - 1, j) if 0 <= k < n):.2f} m, and "
                f"a car needs more to turn its wheels into and out of them")
        lo, hi = sharpness, sharpest  # tangent(lo) > budget >= tangent(hi)
        for _ in range(60):
            mid = math.sqrt(lo * hi)
            lo, hi = (mid, hi) if tangent(i, mid) > budget[i] else (lo, mid)
        out.append(hi)
    return out
