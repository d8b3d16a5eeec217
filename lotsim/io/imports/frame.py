"""Geographic coordinates into local metres: an east-north tangent plane of the WGS84
ellipsoid at a chosen origin.

A lot spans at most a few hundred metres, over which the plane is as good as the ground:
points are turned into Earth-centred coordinates on the ellipsoid and rotated into the
plane that touches it at the origin (east, north; the height above the plane is dropped).
Distances in the plane differ from those along the ground by the height dropped, about
``d² / 2R`` at ``d`` metres from the origin, which shortens a chord of length ``L`` there by
at most about ``L · (d / R)² / 2`` (:meth:`TangentPlane.error_over` says it for a lot: under a
millimetre for lots under 2 km across).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from lotsim.core.geometry import FloatArray

WGS84_A = 6378137.0
"""Semi-major axis of the WGS84 ellipsoid [m]."""
WGS84_F = 1 / 298.257223563
"""Flattening of the WGS84 ellipsoid."""
_E2 = WGS84_F * (2 - WGS84_F)


def _ecef(lat: FloatArray, lon: FloatArray) -> FloatArray:
    """Earth-centred, Earth-fixed coordinates [m] of points on the ellipsoid (height 0)."""
    la, lo = np.radians(lat), np.radians(lon)
    n = WGS84_A / np.sqrt(1 - _E2 * np.sin(la) ** 2)
    return np.stack([n * np.cos(la) * np.cos(lo), n * np.cos(la) * np.sin(lo),
                     n * (1 - _E2) * np.sin(la)], axis=-1)


@dataclass(frozen=True)
class TangentPlane:
    """The tangent plane at ``(lat0, lon0)`` [degrees]: x east, y north [m].

    >>> f = TangentPlane(60.0, 25.0)
    >>> x, y = f.to_local([60.0, 60.001], [25.0, 25.0])
    >>> round(float(x[1]), 6), round(float(y[1]), 3)     # 0.001° of latitude, north
    (0.0, 111.412)
    """

    lat0: float
    lon0: float

    def to_local(self, lat, lon) -> tuple[FloatArray, FloatArray]:
        """Points (degrees) → x east, y north [m] in the plane."""
        d = _ecef(np.asarray(lat, dtype=float), np.asarray(lon, dtype=float)) \
            - _ecef(np.array(self.lat0), np.array(self.lon0))
        la, lo = math.radians(self.lat0), math.radians(self.lon0)
        east = np.array([-math.sin(lo), math.cos(lo), 0.0])
        north = np.array([-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo),
                          math.cos(la)])
        return d @ east, d @ north

    def error_over(self, x: FloatArray, y: FloatArray) -> float:
        """A bound [m] on how much any distance between points within the plane's points
        ``x, y`` [m] differs from the distance along the ground: ``L (d/R)² / 2`` for the
        longest chord ``L`` and the farthest point ``d`` from the origin, plus the chord's
        own shortening against the arc, ``L³ / 24 R²``."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        if x.size == 0:
            return 0.0
        d = float(np.hypot(x, y).max())
        span = float(np.hypot(np.ptp(x), np.ptp(y)))
        r = WGS84_A
        return span * (d / r) ** 2 / 2 + span ** 3 / (24 * r * r)

    def describe(self) -> str:
        """One line for a scenario's header: the projection and its origin."""
        return (f"local east-north tangent plane of WGS84 at lat {self.lat0:.7f}, "
                f"lon {self.lon0:.7f}")
