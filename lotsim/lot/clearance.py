"""Is a swept footprint free? A validity checker over a lot's fixed obstacles."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from lotsim.geometry import FloatArray


@dataclass(frozen=True, slots=True)
class Hit:
    """The first place along a sweep where the body is not free."""

    index: int  # index of the first offending sample pair
    what: str  # label of what was hit, or "the lot boundary"
    point: tuple[float, float]  # a point of the offending body [m]


class Collider:
    """Checks bodies against fixed obstacles (an :class:`shapely.STRtree`) and an allowed region.

    Parameters
    ----------
    obstacles : list of (label, geometry)
        What a body must not touch.
    allowed : geometry
        The region a body must stay inside.
    """

    def __init__(self, obstacles: list[tuple[str, BaseGeometry]], allowed: BaseGeometry):
        self.labels = [label for label, _ in obstacles]
        self.tree = shapely.STRtree([g for _, g in obstacles])
        self.allowed = allowed
        shapely.prepare(self.allowed)

    def blocked(self, bodies: FloatArray) -> np.ndarray:
        """Boolean mask of the ``bodies`` (N, K, 2 point sets, taken as hulls) that are not free."""
        polys = shapely.convex_hull(shapely.linestrings(bodies))
        bad = ~shapely.covers(self.allowed, polys)
        hit = self.tree.query(polys, predicate="intersects")[0]
        bad[hit] = True
        return bad

    @staticmethod
    def sweeps(footprints: FloatArray) -> FloatArray:
        """Point sets (N-1, 8, 2) of consecutive footprint pairs: their hulls cover the sweep."""
        if len(footprints) == 1:
            return footprints
        return np.concatenate([footprints[:-1], footprints[1:]], axis=1)

    def first_hit(self, bodies: FloatArray) -> Hit | None:
        """The first of ``bodies`` (N, K, 2 rings or hull point sets) that is not free."""
        if len(bodies) == 0:
            return None
        bad = np.flatnonzero(self.blocked(bodies))
        if not bad.size:
            return None
        i = int(bad[0])
        poly = shapely.convex_hull(shapely.linestrings(bodies[i]))
        if not self.allowed.covers(poly):
            what = "the lot boundary"
        else:
            what = self.labels[int(self.tree.query(poly, predicate="intersects")[0])]
        c = poly.centroid
        return Hit(i, what, (float(c.x), float(c.y)))

    def sweep_hit(self, footprints: FloatArray) -> Hit | None:
        """First hit of the hulls of consecutive footprints (N, 4, 2): a sweep, not just samples.

        The hull of two consecutive rectangles covers a straight motion
        exactly and an arc up to its sagitta (about 1 mm at 0.2 m steps).
        """
        return self.first_hit(self.sweeps(footprints))
