"""Many motions sampled in one batch give each motion's numbers as sampled alone, phase by
phase (the reference in tests/oracles/motion_at.py), bit for bit."""

import numpy as np
import pytest

from lotsim.core.geometry import Segment
from lotsim.vehicles import CATALOGUE, KMH
from lotsim.vehicles.motion import Piece, motions_at, timed_path
from oracles.motion_at import motion_at

CAR = CATALOGUE["valet"]


def _random_motion(rng: np.random.Generator):
    """A path of a few strokes of straights, arcs and clothoids, forward and back, with
    curvature jumps (stops to steer) between some pieces, timed."""
    pose = (float(rng.uniform(-50, 50)), float(rng.uniform(-50, 50)),
            float(rng.uniform(-np.pi, np.pi)))
    kappa_max = np.tan(CAR.max_steer) / CAR.wheelbase * 0.9
    pieces = []
    gear = 1
    kappa = 0.0
    for _ in range(int(rng.integers(1, 7))):
        if rng.random() < 0.3:
            gear = -gear
        length = float(rng.uniform(0.3, 9.0))
        kind = rng.integers(3)
        if kind == 0:
            kappa, sigma = 0.0, 0.0
        elif kind == 1:
            kappa, sigma = float(rng.uniform(-kappa_max, kappa_max)), 0.0
        else:  # a clothoid from the curvature reached to another within the limit
            to = float(rng.uniform(-kappa_max, kappa_max))
            sigma = (to - kappa) / length
        seg = Segment(pose, gear * length, kappa, sigma)
        pieces.append(Piece(seg, float(rng.choice([5.0, 10.0, 20.0])) * KMH))
        pose = seg.end
        kappa = kappa + sigma * length
    return timed_path(pieces, CAR)


def _times(motion, rng: np.random.Generator) -> np.ndarray:
    """Times in the motion, its cusps and ends among them, a few outside it."""
    d = motion.duration
    tau = np.concatenate([rng.uniform(-0.5, d + 0.5, 40), motion.cusps, [0.0, d],
                          np.linspace(0.0, d, 25)])
    return np.sort(tau)


@pytest.mark.parametrize("seed", range(6))
def test_a_batch_of_motions_gives_each_ones_samples_as_alone(seed):
    rng = np.random.default_rng(seed)
    motions = [_random_motion(rng) for _ in range(12)]
    assert any(g.sharpness != 0 for m in motions for st in m.strokes for g in st.segments)
    assert any(len(m.phases) > len(m.strokes) for m in motions)  # stops to steer
    taus = [_times(m, rng) for m in motions]
    got = motions_at(motions, taus, wheelbase=CAR.wheelbase)
    ends = np.cumsum([len(t) for t in taus])[:-1]
    for k, (m, tau) in enumerate(zip(motions, taus, strict=True)):
        alone = motion_at(m, tau, CAR.wheelbase)
        mine = m.at(tau, wheelbase=CAR.wheelbase)
        for col, ref, single in zip(got, alone, mine, strict=True):
            np.testing.assert_array_equal(np.split(col, ends)[k], ref)
            np.testing.assert_array_equal(single, ref)


def test_a_batch_with_no_times_and_a_motion_with_one_time():
    rng = np.random.default_rng(7)
    a, b = _random_motion(rng), _random_motion(rng)
    poses, v, steer, gear = motions_at([a, b], [np.zeros(0), np.array([b.duration])],
                                       wheelbase=CAR.wheelbase)
    assert poses.shape == (1, 3) and v.shape == steer.shape == gear.shape == (1,)
    np.testing.assert_array_equal(poses, motion_at(b, np.array([b.duration]),
                                                   CAR.wheelbase)[0])
    np.testing.assert_allclose(poses[0], b.end, atol=1e-9)
