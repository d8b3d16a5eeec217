"""Validity checks of a maneuver problem, OMPL's state validity checker and motion
validator: is this footprint free, is this motion free (inside the allowed region, clear of
every obstacle of the problem). Sweeps are checked as hulls of consecutive footprints."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from lotsim.core.geometry import FloatArray, Segment, sample_pieces, sample_segments
from lotsim.lot.clearance import first_blocked, hulls, hulls_blocked
from lotsim.maneuvers.problem import ManeuverProblem

SWEEP_BLOCK = 4
"""Consecutive sweeps a path's check takes at once, as the hull of their footprints, before
it looks at them one by one (:meth:`Validity.first_blocked`): a free block clears them all,
so the answer is that of checking them one by one. (Footprints alone, as the cheap first
pass checks them, are cheaper one by one.)"""


class Validity:
    """The validity checks of one :class:`~lotsim.maneuvers.problem.ManeuverProblem`, in
    its local frame where poses and paths are concerned.

    It remembers which segments it found blocked (a search's paths share their first
    strokes), so it lives as long as one search of its problem.
    """

    def __init__(self, problem: ManeuverProblem):
        self.problem = problem
        # (segment, step) → whether a footprint along it is blocked (:meth:`footprints_blocked`)
        self._seen: dict[tuple[Segment, float], bool] = {}

    def bodies_blocked(self, bodies: FloatArray, convex: bool = False) -> np.ndarray:
        """(N,) whether each body (N, K, 2 points, taken as their hull; ``convex``: convex
        rings already, :func:`~lotsim.lot.clearance.hulls`) is not free."""
        return hulls_blocked(hulls(bodies, convex), self.problem.allowed, self.problem.tree)

    def local_blocked(self, bodies: FloatArray, convex: bool = False) -> np.ndarray:
        """:meth:`bodies_blocked` of bodies given in the problem's local frame."""
        return self.bodies_blocked(self.problem.frame.points_to_world(bodies), convex)

    def first_blocked(self, prints: FloatArray, run: np.ndarray, span: int = 2
                      ) -> np.ndarray:
        """:func:`~lotsim.lot.clearance.first_blocked` of this problem's bodies, coarse to
        fine in blocks of :data:`SWEEP_BLOCK`."""
        return first_blocked(self.bodies_blocked, prints, run, span, SWEEP_BLOCK)

    def poses_blocked(self, local_poses: FloatArray) -> np.ndarray:
        """(N-1,) whether each sweep between consecutive local poses (N, 3) is not free
        ((1,) for a single pose)."""
        bodies = self.problem.vehicle.footprints(self.problem.frame.poses_to_world(local_poses))
        if len(bodies) > 1:
            bodies = np.concatenate([bodies[:-1], bodies[1:]], axis=1)
        return self.bodies_blocked(bodies)

    def pieces_blocked(self, starts: FloatArray, distance: FloatArray, curvature: FloatArray,
                       step: float, sharpness: FloatArray | float = 0.0) -> np.ndarray:
        """(N,) whether a footprint ``step`` apart along each segment, given as arrays
        (:func:`~lotsim.core.geometry.sample_pieces`, local frame), touches anything."""
        poses, of = sample_pieces(starts, distance, curvature, step, sharpness)
        bodies = self.problem.vehicle.footprints(self.problem.frame.poses_to_world(poses))
        return np.bincount(of[self.bodies_blocked(bodies)], minlength=len(starts)) > 0

    def footprints_blocked(self, paths: Sequence[Sequence[Segment]], step: float
                           ) -> np.ndarray:
        """(P,) whether a footprint ``step`` apart along each path touches anything
        (:meth:`paths_blocked` without ``sweep``), each segment checked once in this problem
        (a search's paths share their first strokes): a footprint lies on one segment, so
        a path is blocked when one of its segments is."""
        seen = self._seen
        new = list({seg: None for path in paths for seg in path if (seg, step) not in seen})
        if new:
            bad = self.pieces_blocked(np.array([seg.start for seg in new], dtype=float),
                                      np.array([seg.distance for seg in new], dtype=float),
                                      np.array([seg.curvature for seg in new], dtype=float),
                                      step, np.array([seg.sharpness for seg in new]))
            seen.update(zip(((seg, step) for seg in new), bad.tolist(), strict=True))
        return np.array([any(seen[seg, step] for seg in path) for path in paths], dtype=bool)

    def paths_blocked(self, paths: Sequence[Sequence[Segment]], *, step: float | None = None,
                      sweep: bool = True) -> np.ndarray:
        """(P,) whether each path (pieces in order, local frame) touches anything.

        With ``sweep``, the hulls of consecutive footprints ``step`` apart (default
        the problem's sweep step) are checked (the whole swept area); without, only
        the footprints.
        """
        flat = [seg for path in paths for seg in path]
        if not flat:
            return np.zeros(len(paths), dtype=bool)
        path_of = np.repeat(np.arange(len(paths)), [len(path) for path in paths])
        poses, seg_of = sample_segments(flat, step or self.problem.sweep)
        own = path_of[seg_of]
        bodies = self.problem.vehicle.footprints(self.problem.frame.poses_to_world(poses))
        if sweep:
            own = own[:-1]
            bad = self.first_blocked(bodies, np.where(own == path_of[seg_of][1:], own, -1))
        else:
            bad = self.bodies_blocked(bodies)  # one by one: cheaper than in blocks
        return np.bincount(own[bad], minlength=len(paths)) > 0



class LocalChecks:
    """A problem's validity checks as :func:`~lotsim.roadmap.multipoint.plan_onto` asks them,
    all in the problem's local frame: footprints of local poses, and whether bodies are
    free."""

    def __init__(self, checks: Validity):
        self._p = checks.problem
        self.blocked = checks.local_blocked

    def footprints(self, local_poses: FloatArray) -> FloatArray:
        return self._p.vehicle.footprints(local_poses)
