"""Timed trajectories: limits hold, cusps stop, and times match the closed form."""

import math

import numpy as np
import pytest

from conftest import scenario_from_text
from lotsim.core.geometry import Segment, wrap_angle
from lotsim.sim.preparation import prepare_lot
from lotsim.vehicles import CATALOGUE, KMH
from lotsim.vehicles.motion import Piece, drive, speed_cap, standing_still, timed_path

CAR = CATALOGUE["valet"]
LIM = CAR.limits
A, B, J = LIM.max_accel, LIM.max_brake, LIM.max_jerk


def double_s_time(length, vmax):
    """Textbook rest-to-rest double-S time (Biagiotti & Melchiorri, 2008, §3.4), written
    out independently: the ramps' times first, then either a cruise at vmax or, when the
    length is too short for one, the highest peak found by bisection on the distance."""
    def ramp(v, acc):  # time of a 0 → v change and its distance
        tj = min(acc / J, math.sqrt(v / J))
        ta = tj + v / (J * tj)  # = 2 tj on a triangle, tj + v / acc on a trapezoid
        return ta, ta * v / 2

    ta, da = ramp(vmax, A)
    td, dd = ramp(vmax, B)
    if da + dd <= length:
        return ta + td + (length - da - dd) / vmax
    lo, hi = 0.0, vmax
    for _ in range(200):
        mid = (lo + hi) / 2
        if ramp(mid, A)[1] + ramp(mid, B)[1] <= length:
            lo = mid
        else:
            hi = mid
    return ramp(lo, A)[0] + ramp(lo, B)[0]


@pytest.mark.parametrize("length", [0.05, 0.5, 3.0, 20.0, 80.0])
@pytest.mark.parametrize("gear", [1, -1])
def test_straight_takes_the_double_s_time(length, gear):
    tr = drive([Piece(Segment((0.0, 0.0, 0.0), gear * length, 0.0))], CAR, dt=0.01)
    top = LIM.max_forward_speed if gear > 0 else LIM.max_reverse_speed
    assert tr.end_time == pytest.approx(double_s_time(length, top), abs=1e-6)
    assert tr.x[-1] == pytest.approx(gear * length, abs=1e-9)
    assert tr.v[0] == 0 and tr.v[-1] == 0
    _check_limits(tr)


def _spaced(t, h=0.02):
    keep, last = [0], t[0]
    for i in range(1, len(t)):
        if t[i] - last >= h - 1e-12:
            keep.append(i)
            last = t[i]
    return np.array(keep)


def _check_limits(tr):
    """Every limit, from the samples alone (divided differences bound the derivatives)."""
    dt = np.diff(tr.t)
    assert np.all(dt > 0) and dt.max() <= 0.1 + 1e-9
    step = np.hypot(np.diff(tr.x), np.diff(tr.y))
    assert step.max() <= 0.5
    assert np.all(tr.v <= LIM.max_forward_speed + 1e-9)
    assert np.all(tr.v >= -LIM.max_reverse_speed - 1e-9)
    speed = np.abs(tr.v)
    acc = np.diff(speed) / dt
    assert acc.max() <= A + 1e-6 and acc.min() >= -B - 1e-6
    k = _spaced(tr.t)
    a = np.diff(tr.v[k]) / np.diff(tr.t[k])
    jerk = 2 * np.diff(a) / (tr.t[k][2:] - tr.t[k][:-2])
    assert np.abs(jerk).max(initial=0) <= J * (1 + 1e-6) + 1e-6
    # continuous steering within its rate, lateral acceleration within its bound
    assert np.all(np.abs(np.diff(tr.steer)) <= LIM.max_steer_rate * dt + 1e-9)
    kappa = np.tan(tr.steer) / CAR.wheelbase
    assert np.all(tr.v ** 2 * np.abs(kappa) <= LIM.max_lateral_accel + 1e-9)
    # no jumps: between samples the car covers no more than its speed allows
    fastest = np.maximum(speed[1:], speed[:-1]) + max(A, B) * dt
    assert np.all(step <= fastest * dt + 1e-9)


def test_a_slow_piece_is_driven_within_its_limit_and_the_rest_faster():
    slow = 10 * KMH
    p1 = Segment((0.0, 0.0, 0.0), 30.0, 0.0)
    p2 = Segment(p1.end, 10.0, 0.0)
    p3 = Segment(p2.end, 30.0, 0.0)
    tr = drive([Piece(p1), Piece(p2, slow), Piece(p3)], CAR)
    _check_limits(tr)
    on_slow = (tr.x >= 30.0) & (tr.x <= 40.0)
    assert np.abs(tr.v[on_slow]).max() <= slow + 1e-9
    assert tr.v.max() > 19 * KMH


def test_every_cusp_and_every_change_of_curvature_is_a_stop_to_steer():
    a = Segment((0.0, 0.0, 0.0), 6.0, 0.2)
    b = Segment(a.end, -4.0, -0.2)
    c = Segment(b.end, 5.0, 0.0)
    motion = timed_path([Piece(a), Piece(b), Piece(c)], CAR)
    tr = drive([Piece(a), Piece(b), Piece(c)], CAR, dt=0.01)
    _check_limits(tr)
    # steer in place to 0.2 rad of curvature, drive, steer across to -0.2, back, steer to
    # straight, drive, and nothing at the end (the last piece is straight)
    stops = motion.steering_stops
    assert [s[0] for s in stops] == [(0.0, 0.0, 0.0), a.end, b.end]
    lock = math.atan(0.2 * CAR.wheelbase)
    assert [d for _, d in stops] == pytest.approx(
        [lock / LIM.max_steer_rate, 2 * lock / LIM.max_steer_rate, lock / LIM.max_steer_rate])
    # the car stands while it steers: no motion where the wheels turn
    turning = np.abs(np.diff(tr.steer)) > 1e-12
    assert np.all(np.hypot(np.diff(tr.x), np.diff(tr.y))[turning] < 1e-12)
    assert math.dist((tr.x[-1], tr.y[-1]), c.end[:2]) < 1e-9


def test_speed_on_a_curve_respects_lateral_acceleration_and_on_a_clothoid_the_steering_rate():
    arc = Segment((0.0, 0.0, 0.0), 30.0, 0.2)  # R 5 m
    assert speed_cap(arc, CAR) == pytest.approx(math.sqrt(LIM.max_lateral_accel * 5.0))
    sigma = 0.05
    clothoid = Segment((0.0, 0.0, 0.0), 4.0, 0.0, sigma)
    # dφ/dt = v σ b / (1 + (κ b)²), largest at κ = 0
    assert speed_cap(clothoid, CAR) == pytest.approx(
        min(LIM.max_steer_rate / (sigma * CAR.wheelbase),
            math.sqrt(LIM.max_lateral_accel / clothoid.end_curvature)))
    tr = drive([Piece(clothoid), Piece(Segment(clothoid.end, 10.0, 0.2))], CAR, dt=0.01)
    _check_limits(tr)
    # within each piece's own cap, and no slower than the arc's where there is room for it
    travelled = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(tr.x), np.diff(tr.y)))])
    assert tr.v[travelled < 4.0 - 1e-3].max() <= speed_cap(clothoid, CAR) + 1e-9
    assert tr.v.max() == pytest.approx(speed_cap(arc, CAR))


def test_a_planned_maneuver_is_driven_on_its_exact_path():
    prepared = prepare_lot(scenario_from_text("""
        vehicle_types: [valet]
        lot:
          boundary: [[0, 0], [60, 0], [60, 30], [0, 30]]
          aisles:
            - {id: main, centerline: [[0, 10], [60, 10]], width: 4.6, direction: one-way}
          rows:
            - {aisle: main, side: left, kind: perpendicular, count: 10, slot_width: 2.5,
               slot_length: 5.0, start: 15}
          entrances:
            - {id: in, x: 2, y: 10, heading_deg: 0}
    """))
    # a 4.6 m aisle is too narrow to swing in at once
    m = prepared.maneuver_planner.best(CAR, prepared.lot.slot_by_id["main-left-5"])
    assert m.changes >= 1
    tr = drive([Piece(s, 10 * KMH) for s in m.segments], CAR, t0=5.0)
    _check_limits(tr)
    assert tr.start_time == 5.0
    assert np.abs(tr.v).max() <= 10 * KMH + 1e-9
    fine, _ = m.sample(0.01)
    d = np.hypot(tr.x[:, None] - fine[None, :, 0], tr.y[:, None] - fine[None, :, 1]).min(axis=1)
    assert d.max() < 0.01
    assert abs(wrap_angle(tr.theta[-1] - m.end[2])) < 1e-9
    # duration agrees with the maneuver's own estimate
    assert tr.end_time - 5.0 == pytest.approx(m.duration(CAR, 10 * KMH), abs=1e-9)


def test_standing_then_driving_joins_seamlessly():
    wait = standing_still((1.0, 2.0, 0.5), 0.0, 3.0)
    go = drive([Piece(Segment((1.0, 2.0, 0.5), 5.0, 0.0))], CAR, t0=3.0)
    tr = wait.then(go)
    assert np.all(np.diff(tr.t) > 0)
    assert np.all(tr.gear[tr.t < 3.0] == 0) and np.all(tr.v[tr.t <= 3.0] == 0)
    with pytest.raises(ValueError):
        go.then(wait)


@pytest.mark.parametrize("length", [0.001, 0.02, 0.0353, 0.049, 0.05, 0.07])
def test_a_stroke_of_a_few_centimetres_is_driven_too(length):
    """Found by the property tests: a last stroke under the 5 cm grid step was timed at 0 s,
    so a car's samples stopped 3.5 cm short of its parked pose and out of its slot. A short
    stroke after a cusp takes the double-S time and ends where its path ends."""
    back = Segment((0.0, 0.0, 0.0), -2.0, 0.0)
    end = back.poses_at(2.0)[0]
    tiny = Segment((float(end[0]), float(end[1]), float(end[2])), length, 0.2)
    tr = drive([Piece(back), Piece(tiny)], CAR)
    want = tiny.poses_at(length)[0]
    assert np.allclose([tr.x[-1], tr.y[-1], tr.theta[-1]], want, atol=1e-9)
    last = timed_path([Piece(back), Piece(tiny)], CAR).strokes[-1]
    assert last.segments == (tiny,)
    assert last.duration == pytest.approx(double_s_time(length, speed_cap(tiny, CAR)), abs=1e-9)


def test_speed_profiles_are_kept_read_only_and_as_computed():
    from lotsim.vehicles.motion import scurve

    args = (7.5, 5 * KMH, 10 * KMH, 20 * KMH, A, B, J)
    kept = scurve(*args)
    fresh = scurve.__wrapped__(*args)  # computed anew, not the kept one
    assert scurve(*args) is kept
    for col in "tsva":
        assert np.array_equal(getattr(kept, col), getattr(fresh, col))
        with pytest.raises(ValueError):
            getattr(kept, col)[0] = 1.0  # shared by every edge of that length: not writable
