"""A problem's local frame (:class:`~lotsim.maneuvers.problem.LocalFrame`): its two ways of
moving a path into the world agree to the last bit."""

from __future__ import annotations

import numpy as np

from lotsim.core.geometry import Segment
from lotsim.maneuvers.problem import LocalFrame


def test_segments_move_into_the_world_as_their_starts_do_to_the_last_bit():
    """``segments_to_world`` (Python floats) gives each segment's start exactly as
    ``poses_to_world`` (numpy) moves it, and mirrors curvature and sharpness with the frame."""
    rng = np.random.default_rng(7)
    for _ in range(2000):
        frame = LocalFrame(*map(float, rng.uniform(-500, 500, 2)), float(rng.uniform(-7, 7)),
                           bool(rng.integers(2)))
        segs = [Segment(tuple(map(float, (*rng.uniform(-30, 30, 2), rng.uniform(-7, 7)))),
                        float(rng.uniform(-6, 6)), float(rng.uniform(-0.2, 0.2)),
                        float(rng.uniform(-0.05, 0.05))) for _ in range(5)]
        got = frame.segments_to_world(segs)
        want = frame.poses_to_world(np.array([s.start for s in segs])).tolist()
        sign = -1.0 if frame.mirror else 1.0
        for g, w, s in zip(got, want, segs, strict=True):
            assert g.start == tuple(w)
            assert (g.distance, g.curvature, g.sharpness) == (s.distance, sign * s.curvature,
                                                              sign * s.sharpness)


def test_points_go_into_the_world_where_poses_do_and_come_back() -> None:
    rng = np.random.default_rng(7)
    pts = rng.uniform(-10.0, 10.0, (5, 4, 2))
    for mirror in (False, True):
        frame = LocalFrame(12.5, -3.0, 2.1, mirror)
        world = frame.points_to_world(pts)
        assert world.shape == pts.shape
        as_poses = frame.poses_to_world(np.column_stack([pts.reshape(-1, 2), np.zeros(20)]))
        np.testing.assert_allclose(world.reshape(-1, 2), as_poses[:, :2], atol=1e-12)
        np.testing.assert_allclose(frame.points_to_local(world), pts, atol=1e-12)
