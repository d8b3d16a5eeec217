"""Closed-form motion against fine numerical integration; segment and fillet properties."""

import math

import numpy as np
import pytest

from lotsim.core.geometry import (
    Segment,
    advance,
    cc_polyline,
    cc_turn,
    ccw,
    ease_joints,
    signed_area,
    travel,
    wrap_angle,
)


def integrate(pose, distance, curvature, steps=20_000):
    """RK4 on x' = cos t, y' = sin t, t' = k, over arc length: an independent oracle."""
    return integrate_clothoid(pose, distance, curvature, 0.0, steps)


@pytest.mark.parametrize("seed", range(6))
def test_advance_matches_numerical_integration(seed):
    rng = np.random.default_rng(seed)
    pose = rng.uniform([-10, -10, -math.pi], [10, 10, math.pi])
    distance = rng.uniform(-15, 15)
    curvature = rng.choice([0.0, rng.uniform(-0.4, 0.4), 1e-9])
    exact = advance(pose, distance, curvature)
    numeric = integrate(pose, distance, curvature, steps=2000)
    assert np.allclose(exact, numeric, atol=1e-9)


def test_advance_is_vectorised_over_poses_distances_and_curvatures():
    rng = np.random.default_rng(1)
    poses = rng.uniform(-5, 5, size=(50, 3))
    dist = rng.uniform(-5, 5, size=50)
    curv = rng.uniform(-0.3, 0.3, size=50)
    batch = advance(poses, dist, curv)
    one_by_one = np.array([advance(p, d, k) for p, d, k in zip(poses, dist, curv, strict=True)])
    assert batch.shape == (50, 3)
    assert np.allclose(batch, one_by_one)


def test_full_circle_returns_to_start():
    r = 4.2
    end = advance([1.0, 2.0, 0.3], 2 * math.pi * r, 1 / r)
    assert np.allclose(end[:2], [1.0, 2.0], atol=1e-9)
    assert math.isclose(wrap_angle(end[2] - 0.3), 0.0, abs_tol=1e-9)


def test_segment_pieces_add_up_and_join():
    seg = Segment((0.0, 0.0, 0.5), -7.0, 0.2)
    a, b = seg.piece(0.0, 3.0), seg.piece(3.0, 7.0)
    assert a.length + b.length == pytest.approx(seg.length)
    assert np.allclose(a.end, b.start)
    assert np.allclose(b.end, seg.end)
    assert a.gear == b.gear == -1


def test_a_polyline_rounded_by_arcs_is_tangent_continuous_and_hits_the_ends():
    pts = [[0, 0], [20, 0], [20, 15], [5, 30]]
    segs = cc_polyline(pts, 4.0, math.inf)
    for a, b in zip(segs[:-1], segs[1:], strict=True):
        assert np.allclose(a.end[:2], b.start[:2], atol=1e-9)
        assert math.isclose(wrap_angle(a.end[2] - b.start[2]), 0.0, abs_tol=1e-9)
    assert np.allclose(segs[0].start[:2], [0, 0])
    assert np.allclose(segs[-1].end[:2], [5, 30], atol=1e-9)
    arcs = [s for s in segs if s.curvature]
    assert len(arcs) == 2 and all(math.isclose(s.radius, 4.0) for s in arcs)


def test_a_polyline_rounded_by_arcs_refuses_corners_without_room():
    with pytest.raises(ValueError, match="leg 1"):
        cc_polyline([[0, 0], [10, 0], [10, 3], [0, 3]], 4.0, math.inf)


def test_ccw_orients_rings():
    cw = [[0, 0], [0, 1], [1, 1], [1, 0]]
    assert signed_area(cw) < 0
    assert signed_area(ccw(cw)) == pytest.approx(1.0)


# -- clothoids ---------------------------------------------------------------------------------
def integrate_clothoid(pose, distance, curvature, sharpness, steps=4000):
    """RK4 with the curvature a function of the path length driven (``curvature +
    sharpness · u``), signed by the gear: an independent oracle."""
    y = np.array(pose, dtype=float)
    g = 1.0 if distance >= 0 else -1.0
    h = abs(distance) / steps

    def f(state, u):
        return np.array([g * math.cos(state[2]), g * math.sin(state[2]),
                         g * (curvature + sharpness * u)])

    for i in range(steps):
        u = i * h
        k1 = f(y, u)
        k2 = f(y + h / 2 * k1, u + h / 2)
        k3 = f(y + h / 2 * k2, u + h / 2)
        k4 = f(y + h * k3, u + h)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return y


@pytest.mark.parametrize("seed", range(8))
def test_travel_along_a_clothoid_matches_numerical_integration(seed):
    rng = np.random.default_rng(seed)
    pose = rng.uniform([-5, -5, -math.pi], [5, 5, math.pi])
    distance = rng.uniform(-12, 12)
    k0, sigma = rng.uniform(-0.3, 0.3), rng.uniform(-0.1, 0.1)
    got = travel(pose, distance, k0, sigma)
    want = integrate_clothoid(pose, distance, k0, sigma)
    assert np.allclose(got, want, atol=1e-9)


def test_clothoid_pieces_and_backwards_driving_retrace_the_same_path():
    seg = Segment((1.0, -2.0, 0.4), -7.0, 0.05, 0.03)
    a, b = seg.piece(0.0, 2.5), seg.piece(2.5, 7.0)
    assert np.allclose(b.start, a.end) and np.allclose(b.end, seg.end, atol=1e-12)
    assert b.curvature == pytest.approx(a.end_curvature)
    back = seg.backwards()
    assert np.allclose(back.end, seg.start, atol=1e-12)
    u = np.linspace(0, 7, 15)
    # the same points, with the same steering, visited in the opposite order
    assert np.allclose(back.poses_at(u)[::-1], seg.poses_at(u), atol=1e-12)
    assert np.allclose(back.curvature_at(u)[::-1], seg.curvature_at(u))


@pytest.mark.parametrize("deflection", [0.05, 0.3, 1.0, math.pi / 2, 2.5, -0.4, -math.pi / 2])
def test_cc_turns_are_curvature_continuous_and_end_on_their_tangent_lines(deflection):
    kmax, sigma = 0.2, 0.04
    segs, tangent = cc_turn(deflection, kmax, sigma, start=(3.0, 4.0, 0.7))
    assert segs[0].curvature == 0 and abs(segs[-1].end_curvature) < 1e-12
    for a, b in zip(segs[:-1], segs[1:], strict=True):
        assert np.allclose(a.end, b.start) and b.curvature == pytest.approx(a.end_curvature)
    assert all(s.max_curvature <= kmax + 1e-12 for s in segs)
    assert all(abs(s.sharpness) <= sigma + 1e-12 for s in segs)
    end = segs[-1].end
    assert wrap_angle(end[2] - 0.7 - deflection) == pytest.approx(0.0, abs=1e-12)
    # the corner: tangent metres along the start heading, then tangent metres along the end
    corner = np.array([3.0, 4.0]) + tangent * np.array([math.cos(0.7), math.sin(0.7)])
    back = np.array(end[:2]) - tangent * np.array([math.cos(end[2]), math.sin(end[2])])
    assert np.allclose(corner, back, atol=1e-9)
    # and the numerically integrated path ends at the same place
    pose = (3.0, 4.0, 0.7)
    for s in segs:
        pose = integrate_clothoid(pose, s.distance, s.curvature, s.sharpness, steps=2000)
    assert np.allclose(pose, end, atol=1e-9)


def test_cc_polyline_ends_on_the_last_point_and_keeps_curvature_continuous():
    pts = [[0, 0], [30, 0], [30, 25], [60, 40]]
    segs = cc_polyline(pts, [6.0, 8.0], 0.05)
    assert np.allclose(segs[0].start, (0, 0, 0))
    assert np.allclose(segs[-1].end[:2], (60, 40), atol=1e-9)
    for a, b in zip(segs[:-1], segs[1:], strict=True):
        assert np.allclose(a.end, b.start, atol=1e-9)
        assert b.curvature == pytest.approx(a.end_curvature, abs=1e-12)
    # plain arcs when the sharpness is infinite: straights and arcs of radius 6 whose
    # lengths are the closed form's (legs less r·tan(|turn|/2) at each corner, r·|turn|)
    plain = cc_polyline(pts, 6.0, math.inf)
    turns = [math.pi / 2, math.atan2(15, 30) - math.pi / 2]  # left, then right
    cut = [6.0 * math.tan(abs(t) / 2) for t in turns]
    want = [30 - cut[0], 6.0 * abs(turns[0]), 25 - cut[0] - cut[1], 6.0 * abs(turns[1]),
            math.hypot(30, 15) - cut[1]]
    assert [s.length for s in plain] == pytest.approx(want)
    assert all(s.sharpness == 0 for s in plain)


@pytest.mark.parametrize("ramp", [0.5, 1.5, 3.0])
@pytest.mark.parametrize("gear", [1, -1])
def test_eased_joints_turn_like_the_corners_they_replace_within_the_stated_offset(gear, ramp):
    a = Segment((1.0, 2.0, 0.3), gear * 4.0, 0.1)
    b = Segment(a.end, gear * 0.6, 0.0)  # shorter than the ramp: its two ramps merge
    c = Segment(b.end, gear * 6.0, -0.2)
    eased = ease_joints([a, b, c], ramp)
    for p, q in zip(eased[:-1], eased[1:], strict=True):
        assert np.allclose(p.end, q.start, atol=1e-12)
        assert q.curvature == pytest.approx(p.end_curvature, abs=1e-12)  # no jump left
        assert p.gear == gear
    assert eased[0].start == a.start
    assert eased[0].curvature == a.curvature and eased[-1].end_curvature == c.curvature
    assert wrap_angle(eased[-1].end[2] - c.end[2]) == pytest.approx(0.0, abs=1e-12)
    assert sum(s.length for s in eased) == pytest.approx(10.6)
    # no ramp is steeper than the jumps within one ramp's length spread over it
    assert max(abs(s.sharpness) for s in eased) <= (0.1 + 0.2) / ramp + 1e-12
    # each jump's ramp shifts the path sideways by |Δκ| ramp² / 24 (to first order)
    assert math.dist(eased[-1].end[:2], c.end[:2]) <= 1.1 * (0.1 + 0.2) * ramp ** 2 / 24


def test_strokes_are_eased_one_by_one_and_cusps_left_for_steering_standing():
    a = Segment((0.0, 0.0, 0.0), 3.0, 0.0)
    b = Segment(a.end, 3.0, 0.2)
    c = Segment(b.end, -4.0, -0.2)  # a cusp: the car stops there anyway
    eased = ease_joints([a, b, c], 1.0)
    gears = [s.gear for s in eased]
    assert gears == sorted(gears, reverse=True)  # forward pieces, then reverse ones
    fwd = [s for s in eased if s.gear > 0]
    assert sum(s.length for s in fwd) == pytest.approx(6.0)
    assert fwd[-1].end_curvature == pytest.approx(0.2)  # the stroke ends as it did
    back = [s for s in eased if s.gear < 0]
    assert len(back) == 1 and back[0].curvature == -0.2 and back[0].length == 4.0
    # too short a first piece for any ramp: the stroke is left alone
    short = [Segment((0.0, 0.0, 0.0), 0.05, 0.0), Segment((0.05, 0.0, 0.0), 3.0, 0.2)]
    assert ease_joints(short, 1.0, min_ramp=0.2) == short
