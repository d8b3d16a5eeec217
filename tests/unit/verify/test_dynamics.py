"""The checker's dynamics rules (heading, steer_rate, lateral, accel, jerk) against
results built by hand, and the single-track oracle (``tests/single_track.py``).

One car, built here without any planner code: it stands at the entrance and steers in
place to 0.3 rad at its steering rate, then drives forward on a jerk-limited S-curve speed
profile (jerk ``J`` up to acceleration ``A``, ..., up to 3 m/s) on the arc that steer
drives, steers back to straight at its steering rate while cruising (a clothoid, almost:
the steer is linear in time at a constant speed), brakes to rest on another S-curve,
steers in place to -0.2 rad and reverses 1.5 m on an arc before it stops and departs::

       ,-'  (clothoid, then straight)
      (   arc at 0.3 rad
    --'  entrance (3, 5), heading 0

The pose is integrated from the controls ``v(t)`` (piecewise cubic) and ``steer(t)``
(piecewise linear) with fine RK4 steps that never straddle a break of the controls, then
sampled every 0.05 s plus at each start and stop and rounded as lotsim's writer rounds.
The valid car sits on its limits: the steering rate, acceleration, braking and jerk are
the type's own, and the lateral acceleration on the arc is 99 % of it. Each test changes
one thing and expects exactly one rule.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import single_track
from lotsim.verify import check_result

DT = 0.05
TYPE = {"name": "test-car", "width": 1.8, "front": 3.9, "rear": 1.0, "wheelbase": 2.8,
        "max_steer": 0.5, "max_forward_speed": 5.0, "max_reverse_speed": 2.0,
        "max_accel": 1.5, "max_brake": 2.0, "max_lateral_accel": 1.0,
        "max_steer_rate": 0.436, "max_jerk": 2.0}
B = TYPE["wheelbase"]
START = (3.0, 5.0, 0.0)
ARC_STEER = 0.3
BACK_STEER = -0.2
CRUISE = 3.0
DRIVE_START = 0.700002  # 2 µs after a grid sample: the writer's closest pair
BRAKE_START = 6.0
NEW_KEYS = ("max_lateral_accel", "max_steer_rate", "max_jerk")


# ----------------------------------------------------------------- building a result


def scurve(v0, v1, accel, jerk):
    """Pieces ``(duration, jerk)`` from speed ``v0`` to ``v1``, starting and ending at zero
    acceleration: jerk up to ``accel``, hold, jerk back to zero (``|v1 - v0|`` must allow
    the hold)."""
    dv = v1 - v0
    ramp = accel / jerk
    hold = abs(dv) / accel - ramp
    assert hold >= -1e-12, "the speed change is too small to reach that acceleration"
    sign = math.copysign(1.0, dv)
    return [(ramp, sign * jerk), (max(hold, 0.0), 0.0), (ramp, -sign * jerk)]


class Speed:
    """A signed speed made of strokes of constant-jerk pieces, at rest between them."""

    def __init__(self):
        self.pieces = []  # (t0, t1, v0, a0, jerk)
        self.strokes = []  # (t0, t1, sign)

    def stroke(self, t0, pieces):
        t, v, a = t0, 0.0, 0.0
        for duration, jerk in pieces:
            self.pieces.append((t, t + duration, v, a, jerk))
            v += a * duration + jerk * duration**2 / 2
            a += jerk * duration
            t += duration
        assert abs(v) < 1e-9 and abs(a) < 1e-9, "a stroke ends at rest"
        sign = math.copysign(1.0, pieces[0][1])
        self.strokes.append((t0, t, sign))
        return t

    def __call__(self, t):
        for t0, t1, v0, a0, jerk in self.pieces:
            if t0 <= t <= t1:
                tau = t - t0
                return v0 + a0 * tau + jerk * tau**2 / 2
        return 0.0

    def gear(self, t):
        for t0, t1, sign in self.strokes:
            if t0 + 1e-9 < t < t1 - 1e-9:
                return int(sign)
        return 0

    def breaks(self):
        return [t for piece in self.pieces for t in piece[:2]]


def build(*, steer_rate=TYPE["max_steer_rate"], cruise=CRUISE, accel=TYPE["max_accel"],
          brake=TYPE["max_brake"], jerk=TYPE["max_jerk"], kink=0.045, cusp=False):
    """The samples of the car described in the module docstring.

    ``steer_rate`` is the rate it steers in place at, ``cruise``, ``accel``, ``brake`` and
    ``jerk`` shape the forward stroke (the reverse one uses 1 m/s² and ``jerk``), ``kink``
    is how long after a grid sample [s] the steer starts back from the arc. With ``cusp``
    the car reverses straight from the instant it stops, without steering in place.
    """
    speed = Speed()
    steer_knots = [(0.0, 0.0), (DRIVE_START - ARC_STEER / steer_rate, 0.0),
                   (DRIVE_START, ARC_STEER)]
    forward = scurve(0.0, cruise, accel, jerk) + scurve(cruise, 0.0, brake, jerk)
    accelerating = sum(d for d, _ in forward[:3])
    forward.insert(3, (BRAKE_START - DRIVE_START - accelerating, 0.0))
    stop = speed.stroke(DRIVE_START, forward)
    back_at = 4.2 + kink  # at cruise speed, on the arc
    steer_knots += [(back_at, ARC_STEER),
                    (back_at + ARC_STEER / TYPE["max_steer_rate"], 0.0)]
    if cusp:
        reverse_at = stop
    else:
        turn_at = stop + 0.3
        reverse_at = turn_at + abs(BACK_STEER) / steer_rate + 0.1
        steer_knots += [(turn_at, 0.0), (turn_at + abs(BACK_STEER) / steer_rate, BACK_STEER)]
    end = speed.stroke(reverse_at, scurve(0.0, -1.0, 1.0, jerk) + scurve(-1.0, 0.0, 1.0, jerk))
    end += 0.3
    steer_knots.append((end, steer_knots[-1][1]))
    kt, kv = zip(*steer_knots, strict=True)
    assert all(np.diff(kt) > 0)

    def steer(t):
        return float(np.interp(t, kt, kv))

    # sample times: the grid, plus each start and stop, at 1 µs
    times = {round(k * DT, 6) for k in range(int(end / DT) + 1)}
    times |= {round(t, 6) for t0, t1, _ in speed.strokes for t in (t0, t1)}
    times.add(round(end, 6))
    times = sorted(times)
    assert min(np.diff(times)) > 1.9e-6

    # integrate the model between every sample and every break of the controls
    knots = sorted(set(times) | set(kt) | set(speed.breaks()))
    knots = [t for t in knots if t <= times[-1]]

    def rate(t, p):
        v, phi = speed(t), steer(t)
        return np.array([v * math.cos(p[2]), v * math.sin(p[2]), v * math.tan(phi) / B])

    pose = np.array(START, dtype=float)
    poses = {knots[0]: pose}
    for ta, tb in zip(knots[:-1], knots[1:], strict=True):
        n = max(1, math.ceil((tb - ta) / 1e-3))
        h = (tb - ta) / n
        # evaluate strictly inside [ta, tb]: the controls are smooth there
        for k in range(n):
            t = ta + k * h
            k1 = rate(t, pose)
            k2 = rate(t + h / 2, pose + h / 2 * k1)
            k3 = rate(t + h / 2, pose + h / 2 * k2)
            k4 = rate(t + h, pose + h * k3)
            pose = pose + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        poses[tb] = pose
    out = {key: [] for key in ("t", "x", "y", "theta", "v", "steer", "gear")}
    for t in times:
        x, y, th = poses[t]
        out["t"].append(t)
        out["x"].append(round(float(x), 4) + 0.0)
        out["y"].append(round(float(y), 4) + 0.0)
        out["theta"].append(round(float(th), 6) + 0.0)
        out["v"].append(round(speed(t), 4) + 0.0)
        out["steer"].append(round(steer(t), 6) + 0.0)
        out["gear"].append(speed.gear(t))
    return out


def box(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def result_for(samples):
    """A whole result: a large empty lot, the car departing where its samples end."""
    end = [samples[k][-1] for k in ("x", "y", "theta")]
    lot = {"name": "open", "boundary": box(-30, -30, 60, 60), "slots": [], "obstacles": [],
           "parked": [], "speed_limit": 5.0, "speed_zones": [],
           "entrances": [{"id": "gate-in", "pose": list(START)}],
           "exits": [{"id": "gate-out", "pose": end}]}
    car = {"id": "c1", "type": dict(TYPE), "arrival": 0.0, "entrance": "gate-in",
           "slot": None, "status": "departed", "reason": "", "samples": samples}
    metrics = {"parked": 0, "departed": 1, "waiting": 0, "rejected": 0, "vehicles": 1,
               "makespan": samples["t"][-1]}
    return {"format": "lotsim-result", "version": 1, "lot": lot, "vehicles": [car],
            "metrics": metrics, "settings": {"planner": "hand", "seed": 0}}


_VALID = build()


@pytest.fixture
def samples():
    return copy.deepcopy(_VALID)


def rules(report):
    return {v.rule for v in report.violations}


def assert_only(samples_or_result, rule):
    result = (samples_or_result if "format" in samples_or_result
              else result_for(samples_or_result))
    report = check_result(result)
    assert not report.ok
    assert rules(report) == {rule}, [str(v) for v in report.violations]
    return report


def index_at(samples, t):
    return int(np.argmin(np.abs(np.array(samples["t"]) - t)))


# ----------------------------------------------------------------- the valid result


def test_valid_result_passes(samples):
    report = check_result(result_for(samples))
    assert report.ok, [str(v) for v in report.violations]
    assert report.stats["samples"] == len(samples["t"])


@pytest.mark.slow
@pytest.mark.parametrize("kink", [0.0, 0.001, 0.025, 0.045, 0.049])
def test_a_curvature_kink_anywhere_in_an_interval_passes(kink):
    assert check_result(result_for(build(kink=kink))).ok


def test_a_cusp_passes():
    """Forward to rest and straight on backwards: the signed speed goes through zero with
    zero acceleration, its second derivative jumps from +J to -J."""
    samples = build(cusp=True)
    cusp = index_at(samples, 8.5)
    assert samples["v"][cusp] == 0 and samples["gear"][cusp] == 0
    assert samples["v"][cusp - 1] > 0 > samples["v"][cusp + 1]
    assert check_result(result_for(samples)).ok


def test_heading_uses_the_arc_length_not_the_chord():
    """A fast car on a tight circle (0.5 m and 0.2 rad per sample): its chord is 0.17 %
    shorter than the arc, more than the relative slack of 0.1 %; closed form, rounded."""
    steer, v = 0.85, 10.0
    r = B / math.tan(steer)
    t = np.round(np.arange(0, 1.0001, DT), 6)
    th = v * t / r
    samples = {"t": list(t), "x": list(np.round(3.0 + r * np.sin(th), 4)),
               "y": list(np.round(5.0 + r * (1 - np.cos(th)), 4)),
               "theta": list(np.round(th, 6)), "v": [v] * len(t), "steer": [steer] * len(t),
               "gear": [1] * len(t)}
    result = result_for(samples)
    result["lot"]["speed_limit"] = 10.0
    result["vehicles"][0]["type"] |= {"max_steer": 0.9, "max_forward_speed": 10.0,
                                      "max_lateral_accel": 50.0}
    assert check_result(result).ok, [str(x) for x in check_result(result).violations]
    # between samples 0.05 s apart the steer could swing within its rate and back, which the
    # rule allows for (s · K · Δt / 2, 4.6 mrad here): a steer 3 % off turns 9.6 mrad less
    result["vehicles"][0]["samples"]["steer"] = [0.97 * steer] * len(t)
    assert_only(result, "heading")


def test_the_valid_result_is_tight(samples):
    """Worked out from the samples, not the checker: the car steers, speeds up, brakes
    and jerks at its limits, so the tolerances of the rules are what keeps it valid."""
    t, v, steer = (np.array(samples[k]) for k in ("t", "v", "steer"))
    dt = np.diff(t)
    standing = (v[:-1] == 0) & (v[1:] == 0)
    rate = np.abs(np.diff(steer)) / dt
    assert rate[standing & (dt > 0.01)].max() == pytest.approx(TYPE["max_steer_rate"],
                                                               rel=1e-3)
    slope = np.diff(np.abs(v)) / dt
    assert slope.max() == pytest.approx(TYPE["max_accel"], abs=0.01)
    assert -slope.min() == pytest.approx(TYPE["max_brake"], abs=0.01)
    grid = np.abs(t / DT - np.round(t / DT)) < 1e-6  # second differences at 0.05 s
    tg, vg = t[grid], v[grid]
    jerk = 2 * np.diff(np.diff(vg) / np.diff(tg)) / (tg[2:] - tg[:-2])
    assert np.abs(jerk).max() == pytest.approx(TYPE["max_jerk"], abs=0.1)
    lateral = v**2 * np.abs(np.tan(steer)) / B
    assert lateral.max() == pytest.approx(CRUISE**2 * math.tan(ARC_STEER) / B, rel=1e-3)
    assert 0.98 * TYPE["max_lateral_accel"] < lateral.max() < TYPE["max_lateral_accel"]
    # the writer's closest pair: 2 µs apart, steering in place, steers one rounding apart
    i = index_at(samples, 0.7)
    assert t[i + 1] - t[i] == pytest.approx(2e-6, abs=1e-9)
    assert abs(steer[i + 1] - steer[i]) == pytest.approx(1e-6, abs=1e-9)
    assert abs(steer[i + 1] - steer[i]) > TYPE["max_steer_rate"] * (t[i + 1] - t[i])
    # it reverses on an arc: the heading turns against the sign of the steer
    rev = np.flatnonzero(np.array(samples["gear"]) == -1)
    assert np.all(np.array(steer)[rev] < 0)
    assert samples["theta"][rev[-1]] - samples["theta"][rev[0]] > 0.02


# ------------------------------------------------------------------------ steer_rate


def test_steer_jump_standing(samples):
    i = index_at(samples, 0.4)  # steering in place at the limit: 0.0218 rad per 0.05 s
    assert samples["v"][i] == 0 and samples["steer"][i - 1] < samples["steer"][i]
    samples["steer"][i] += 0.01
    report = assert_only(samples, "steer_rate")
    assert report.violations[0].t == pytest.approx(samples["t"][i - 1])
    assert "max_steer_rate 0.436" in report.violations[0].message


def test_steering_in_place_too_fast():
    assert_only(build(steer_rate=1.1 * TYPE["max_steer_rate"]), "steer_rate")


def test_steer_jump_two_microseconds_apart(samples):
    i = index_at(samples, 0.7)
    samples["steer"][i + 1] += 1e-4  # 0.1 mrad in 2 µs
    assert_only(samples, "steer_rate")


# --------------------------------------------------------------------------- lateral


def test_too_fast_on_the_arc():
    report = assert_only(build(cruise=3.3), "lateral")  # 1.20 m/s² on the arc
    assert "max_lateral_accel 1.000" in report.violations[0].message


def test_lower_lateral_limit(samples):
    result = result_for(samples)
    result["vehicles"][0]["type"]["max_lateral_accel"] = 0.95  # below the arc's 0.99
    assert_only(result, "lateral")


# ----------------------------------------------------------------------------- accel


def test_speeding_up_too_hard():
    report = assert_only(build(accel=1.1 * TYPE["max_accel"]), "accel")
    assert "max_accel" in report.violations[0].message


def test_speeding_up_is_judged_by_max_accel_not_max_brake():
    accel = (TYPE["max_accel"] + TYPE["max_brake"]) / 2  # fine for braking, not here
    assert_only(build(accel=accel), "accel")


def test_braking_too_hard():
    report = assert_only(build(brake=1.1 * TYPE["max_brake"]), "accel")
    assert "max_brake" in report.violations[0].message


def test_a_change_of_direction_must_leave_time_to_stop():
    """Standing cars that 'move' at ±5 cm/s: forward to backward within 0.05 s needs
    0.05 / 2 + 0.05 / 1.5 = 0.058 s; the jerk of such a flip is huge too."""
    stand = {"t": [0.0, 0.05, 0.10, 0.15], "x": [3.0] * 4, "y": [5.0] * 4,
             "theta": [0.0] * 4, "v": [0.0, 0.05, -0.05, 0.0], "steer": [0.0] * 4,
             "gear": [0, 1, -1, 0]}
    report = check_result(result_for(stand))
    assert rules(report) == {"accel", "jerk"}, [str(v) for v in report.violations]
    (flip,) = [v for v in report.violations if v.rule == "accel"]
    assert "stopping and starting again" in flip.message
    stand["v"] = [0.0, 0.04, -0.04, 0.0]  # 0.047 s: possible, and still a jerk
    assert rules(check_result(result_for(stand))) == {"jerk"}


# ------------------------------------------------------------------------------ jerk


def test_jerk_is_judged_on_the_signed_speed():
    """From +4 to -4 mm/s in 0.05 s: |v| is smooth, v is not (a jerk of 4 m/s³)."""
    stand = {"t": [0.0, 0.05, 0.10, 0.15, 0.20, 0.25], "x": [3.0] * 6, "y": [5.0] * 6,
             "theta": [0.0] * 6, "v": [0.0, 0.002, 0.004, -0.004, -0.002, 0.0],
             "steer": [0.0] * 6, "gear": [0, 1, 1, -1, -1, 0]}
    assert_only(stand, "jerk")


def test_jerk_spike(samples):
    i = index_at(samples, 5.5)  # cruising straight at 3 m/s
    assert samples["v"][i] == CRUISE and samples["steer"][i] == 0
    samples["v"][i] += 0.02  # 0.4 m/s² for one interval: fine, but 16 m/s³
    report = assert_only(samples, "jerk")
    # the three second differences that hold it see 8, -16 and 8 m/s³
    assert report.violations[0].t == pytest.approx(5.45)
    assert "(2 more samples)" in report.violations[0].message


def test_jerk_above_the_limit():
    assert_only(build(jerk=1.1 * TYPE["max_jerk"]), "jerk")


# --------------------------------------------------------------------------- heading


@pytest.mark.parametrize(("t", "error"), [(5.5, 0.005), (2.5, 0.001), (10.2, -0.001)])
def test_heading_that_does_not_match_the_steer(samples, t, error):
    """One heading off: on the straight, on the forward arc, on the reverse arc."""
    i = index_at(samples, t)
    assert abs(samples["v"][i]) > 0.5
    samples["theta"][i] += error
    report = assert_only(samples, "heading")
    assert report.violations[0].t == pytest.approx(samples["t"][i - 1])


def test_steer_recorded_short_of_what_was_driven(samples):
    samples["steer"] = [round(0.9 * s, 6) for s in samples["steer"]]
    assert_only(samples, "heading")


def test_reversing_turns_against_the_steer(samples):
    """Recorded with the steer's sign flipped during the reverse stroke and the steering
    in place before it: the rates and the lateral acceleration stay the same, the heading
    turns the wrong way."""
    t = np.array(samples["t"])
    stop = t[index_at(samples, 8.5)]
    samples["steer"] = [-s if ti > stop else s
                        for ti, s in zip(t, samples["steer"], strict=True)]
    assert_only(samples, "heading")


# ------------------------------------------------------------------------- structure


@pytest.mark.parametrize("key", NEW_KEYS)
@pytest.mark.parametrize("value", ["missing", 0.0, -1.0, "2.0", None])
def test_new_type_keys_are_required_and_positive(samples, key, value):
    result = result_for(samples)
    car_type = result["vehicles"][0]["type"]
    if value == "missing":
        del car_type[key]
    else:
        car_type[key] = value
    report = assert_only(result, "structure")
    assert f"type.{key}" in report.violations[0].message


# ------------------------------------------------------------------ the oracle itself


def test_single_track_reproduces_a_circle_exactly():
    """Constant speed and steer: a circle of radius b / tan(steer), in closed form."""
    steer, v, r = 0.25, 2.0, B / math.tan(0.25)
    t = np.arange(0, 3.0001, DT)
    th = v * t / r
    samples = {"t": t, "x": r * np.sin(th), "y": r * (1 - np.cos(th)), "theta": th,
               "v": np.full(len(t), v), "steer": np.full(len(t), steer)}
    position, heading = single_track.max_error(samples, B)
    assert position < 1e-9 and heading < 1e-9
    samples["steer"] = np.full(len(t), 0.26)
    assert single_track.max_error(samples, B)[0] > 0.05


def test_single_track_reproduces_the_valid_car(samples):
    position, heading = single_track.max_error(samples, B)
    assert position < 0.01  # 1 cm over about 25 m driven
    assert heading < 1e-3


def test_single_track_finds_a_steer_set_to_zero_on_the_arc(samples):
    samples["steer"] = [0.0 if abs(s - ARC_STEER) < 1e-9 else s for s in samples["steer"]]
    assert single_track.max_error(samples, B)[0] > 1.0


def test_single_track_finds_a_steer_short_of_what_was_driven(samples):
    samples["steer"] = [0.9 * s for s in samples["steer"]]
    assert single_track.max_error(samples, B)[0] > 0.1


def test_single_track_finds_a_wrong_heading(samples):
    i = index_at(samples, 5.5)
    samples["theta"][i] += 0.005
    position, heading = single_track.max_error(samples, B)
    assert position < 0.01  # the integration never reads it
    assert heading > 0.004
