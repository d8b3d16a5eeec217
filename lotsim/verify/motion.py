"""The rules on one vehicle's samples: arrival, sampling, sideways, curvature, heading,
steer, steer_rate, gear, speed, lateral, accel and jerk."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely

from lotsim.verify.reading import _Lot, _Vehicle
from lotsim.verify.report import Violation, _add
from lotsim.verify.tolerances import (
    ACCEL_TOL,
    CHORD_SLACK,
    CHORD_SPEED_REL,
    CURVATURE_ABS,
    CURVATURE_REL,
    GEAR_MIN_STEP,
    GEAR_SPEED_TOL,
    HEADING_ABS,
    HEADING_CHORD,
    HEADING_KINK,
    HEADING_REL,
    JERK_MIN_DT,
    LATERAL_TOL,
    MAX_DT,
    MAX_STEP,
    SIDEWAYS_ABS,
    SIDEWAYS_REL,
    SPEED_TOL,
    STEER_RATE_TOL,
    STEER_TOL,
    STEP_TOL,
    STILL_TOL,
    STILL_TURN,
    T_ROUND,
    TIME_TOL,
    V_ROUND,
    FloatArray,
)


def _wrap(a: FloatArray) -> FloatArray:
    """Angles wrapped to [-pi, pi) [rad]."""
    return (a + np.pi) % (2 * np.pi) - np.pi


def _first(out: list[Violation], rule: str, veh: _Vehicle, mask: np.ndarray,
           describe: Callable[[int], str], what: str = "samples") -> None:
    """Report the first index where ``mask`` holds, and how many more there are."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return
    i = int(idx[0])
    more = f" ({idx.size - 1} more {what})" if idx.size > 1 else ""
    _add(out, rule, veh.id, veh.t[i], f"{veh.id}: {describe(i)}{more}")


def _check_motion(veh: _Vehicle, lot: _Lot, out: list[Violation]) -> None:
    """Rules 2-5 on one vehicle's samples: sampling, kinematics, speed, dynamics."""
    t, x, y, th, v, steer, gear = veh.t, veh.x, veh.y, veh.theta, veh.v, veh.steer, veh.gear
    if t[0] < veh.arrival - TIME_TOL:
        _add(out, "arrival", veh.id, t[0], f"{veh.id}: first sample at t={t[0]:.2f} s, "
             f"before its arrival at {veh.arrival:.2f} s")

    _first(out, "steer", veh, np.abs(steer) > veh.max_steer + STEER_TOL,
           lambda i: f"steer {steer[i]:.4f} rad at t={t[i]:.2f} s exceeds max_steer "
                     f"{veh.max_steer:.4f} rad")
    bad_v = (((gear == 1) & (v < -GEAR_SPEED_TOL)) | ((gear == -1) & (v > GEAR_SPEED_TOL))
             | ((gear == 0) & (np.abs(v) > GEAR_SPEED_TOL)))
    _first(out, "gear", veh, bad_v,
           lambda i: f"v={v[i]:.3f} m/s in gear {gear[i]:+.0f} at t={t[i]:.2f} s")

    # speed limit at every sample: type, lot, zones holding the rear axle
    zone = np.full(len(t), lot.speed_limit)
    for _zid, poly, limit in lot.zones:
        inside = shapely.contains_xy(poly, x, y)
        zone = np.where(inside, np.minimum(zone, limit), zone)
    top = np.where(v >= 0, veh.max_forward_speed, veh.max_reverse_speed)
    limit = np.minimum(top, zone)
    _first(out, "speed", veh, np.abs(v) > limit + SPEED_TOL,
           lambda i: f"|v|={abs(v[i]):.3f} m/s at t={t[i]:.2f} s exceeds the limit "
                     f"{limit[i]:.3f} m/s at ({x[i]:.2f}, {y[i]:.2f})")

    kappa = np.tan(steer) / veh.wheelbase  # signed curvature the steer drives [1/m]
    lateral = v * v * np.abs(kappa)
    _first(out, "lateral", veh, lateral > veh.max_lateral_accel + LATERAL_TOL,
           lambda i: f"v={v[i]:.3f} m/s at steer {steer[i]:.4f} rad (radius "
                     f"{1 / max(abs(kappa[i]), 1e-12):.2f} m) at t={t[i]:.2f} s: lateral "
                     f"acceleration {lateral[i]:.3f} m/s² exceeds max_lateral_accel "
                     f"{veh.max_lateral_accel:.3f} m/s²")
    if len(t) < 2:
        return

    dt, dx, dy = np.diff(t), np.diff(x), np.diff(y)
    dth = _wrap(np.diff(th))
    d = np.hypot(dx, dy)
    mean = th[:-1] + dth / 2
    c, s = np.cos(mean), np.sin(mean)
    along, across = dx * c + dy * s, -dx * s + dy * c

    still = ((np.abs(dx) <= STILL_TOL) & (np.abs(dy) <= STILL_TOL)
             & (np.abs(dth) <= STILL_TURN) & (v[:-1] == 0) & (v[1:] == 0)
             & (gear[:-1] == 0) & (gear[1:] == 0))
    _first(out, "sampling", veh, (dt > MAX_DT + TIME_TOL) & ~still,
           lambda i: f"samples {dt[i]:.3f} s apart from t={t[i]:.2f} s although it does "
                     f"not stand still (at most {MAX_DT} s)", "intervals")
    _first(out, "sampling", veh, d > MAX_STEP + STEP_TOL,
           lambda i: f"samples {d[i]:.3f} m apart from t={t[i]:.2f} s (at most {MAX_STEP} m)",
           "intervals")

    radius = veh.min_radius
    side_tol = SIDEWAYS_ABS + SIDEWAYS_REL * d + d * d / (4 * radius)
    _first(out, "sideways", veh, np.abs(across) > side_tol,
           lambda i: f"moves {abs(across[i]):.3f} m sideways between t={t[i]:.2f} and "
                     f"{t[i + 1]:.2f} s (allowed {side_tol[i]:.3f} m)", "intervals")
    turn_tol = d / radius * CURVATURE_REL + CURVATURE_ABS
    _first(out, "curvature", veh, np.abs(dth) > turn_tol,
           lambda i: f"turns {abs(dth[i]):.4f} rad over {d[i]:.3f} m between t={t[i]:.2f} "
                     f"and {t[i + 1]:.2f} s: radius {d[i] / max(abs(dth[i]), 1e-12):.2f} m "
                     f"< minimum {radius:.2f} m", "intervals")

    direction = np.sign(along)
    judged = np.abs(along) > GEAR_MIN_STEP
    g0, g1 = gear[:-1], gear[1:]
    moving0, moving1 = np.abs(v[:-1]) > GEAR_SPEED_TOL, np.abs(v[1:]) > GEAR_SPEED_TOL
    wrong = judged & ((moving0 & (g0 != direction)) | (moving1 & (g1 != direction))
                      | ((g0 != direction) & (g1 != direction)))
    _first(out, "gear", veh, wrong,
           lambda i: f"travels {'forward' if direction[i] > 0 else 'backward'} between "
                     f"t={t[i]:.2f} and {t[i + 1]:.2f} s in gear {g0[i]:+.0f}/{g1[i]:+.0f}",
           "intervals")

    reverse = (g0 == -1) | (g1 == -1)
    pair_top = np.where(reverse, veh.max_reverse_speed, veh.max_forward_speed)
    pair_limit = np.minimum(pair_top, np.maximum(zone[:-1], zone[1:]))
    chord_speed = d / dt
    allowed = (pair_limit * CHORD_SPEED_REL + SPEED_TOL) * dt + CHORD_SLACK
    _first(out, "speed", veh, d > allowed,
           lambda i: f"covers {d[i]:.3f} m in {dt[i]:.3f} s from t={t[i]:.2f} s "
                     f"({chord_speed[i]:.3f} m/s), limit {pair_limit[i]:.3f} m/s",
           "intervals")

    _check_dynamics(veh, out, kappa, d, dth, direction)


def _check_dynamics(veh: _Vehicle, out: list[Violation], kappa: FloatArray, d: FloatArray,
                    dth: FloatArray, direction: FloatArray) -> None:
    """Rules heading, steer_rate, accel and jerk on consecutive samples (rules 3 and 5).

    ``kappa`` is the curvature the steer drives at each sample, ``d``, ``dth`` and
    ``direction`` the chord length, the wrapped heading change and the sign of the chord
    along the mean heading of each interval.
    """
    t, v, steer = veh.t, veh.v, veh.steer
    dt = np.diff(t)

    # heading: the single-track model turns by the curvature integrated over the arc
    # driven. The arc length is recovered from the chord as for a circular arc,
    # s = d / sinc(Δθ / 2) (Δθ is wrapped, so the factor is at most π / 2); the trapezoid
    # rule on the end curvatures is exact for a curvature linear in arc length.
    s = d / np.sinc(dth / (2 * np.pi))
    k0, k1 = kappa[:-1], kappa[1:]
    predicted = direction * s * (k0 + k1) / 2
    # between samples the curvature may also bend back (a V: a clothoid down, one up), so
    # the trapezoid may miss a dip; a steer within its rate moves the curvature at most
    # K = max_steer_rate / (b cos² φ) per second, and any curvature with |dκ/dt| ≤ K
    # stays within K·Δt/2 of the straight line between its end values
    reach = np.maximum(np.abs(steer[:-1]), np.abs(steer[1:])) + veh.max_steer_rate * dt / 2
    k_rate = veh.max_steer_rate / (veh.wheelbase * np.cos(np.minimum(reach, 1.5)) ** 2)
    turn_tol = (HEADING_ABS + HEADING_CHORD * (np.abs(k0) + np.abs(k1)) / 2
                + s * np.maximum(HEADING_KINK * np.abs(k1 - k0), k_rate * dt / 2)
                + HEADING_REL * np.abs(predicted))
    _first(out, "heading", veh, np.abs(dth - predicted) > turn_tol,
           lambda i: f"turns {dth[i]:+.5f} rad over {d[i]:.3f} m between t={t[i]:.2f} and "
                     f"{t[i + 1]:.2f} s, but its steer ({steer[i]:.4f}, {steer[i + 1]:.4f} "
                     f"rad) turns it {predicted[i]:+.5f} rad (allowed ±{turn_tol[i]:.5f})",
           "intervals")

    # steer_rate: the road wheels turn at most max_steer_rate, standing or moving
    dsteer = np.diff(steer)
    fast = np.abs(dsteer) > veh.max_steer_rate * dt + STEER_RATE_TOL
    _first(out, "steer_rate", veh, fast,
           lambda i: f"steer changes {dsteer[i]:+.5f} rad in {dt[i]:.6f} s from t={t[i]:.2f} "
                     f"s ({abs(dsteer[i]) / dt[i]:.3f} rad/s), more than max_steer_rate "
                     f"{veh.max_steer_rate:.3f} rad/s", "intervals")

    # accel: by the mean value theorem (|v1| - |v0|) / dt is d|v|/dt somewhere in between,
    # where the car speeds up (limit max_accel) or slows down (max_brake)
    speed = np.abs(v)
    dspeed = np.diff(speed)
    flips = v[:-1] * v[1:] < 0
    up = ~flips & (dspeed > veh.max_accel * dt + ACCEL_TOL)
    down = ~flips & (-dspeed > veh.max_brake * dt + ACCEL_TOL)
    _first(out, "accel", veh, up,
           lambda i: f"speeds up from |v|={speed[i]:.4f} to {speed[i + 1]:.4f} m/s in "
                     f"{dt[i]:.6f} s from t={t[i]:.2f} s ({dspeed[i] / dt[i]:.3f} m/s²), "
                     f"more than max_accel {veh.max_accel:.3f} m/s²", "intervals")
    _first(out, "accel", veh, down,
           lambda i: f"slows from |v|={speed[i]:.4f} to {speed[i + 1]:.4f} m/s in "
                     f"{dt[i]:.6f} s from t={t[i]:.2f} s ({-dspeed[i] / dt[i]:.3f} m/s²), "
                     f"more than max_brake {veh.max_brake:.3f} m/s²", "intervals")
    # a change of direction between two samples passes through a stop
    need = (np.maximum(speed[:-1] - ACCEL_TOL, 0) / veh.max_brake
            + np.maximum(speed[1:] - ACCEL_TOL, 0) / veh.max_accel)
    _first(out, "accel", veh, flips & (need > dt),
           lambda i: f"goes from v={v[i]:.4f} to {v[i + 1]:.4f} m/s in {dt[i]:.6f} s from "
                     f"t={t[i]:.2f} s; stopping and starting again takes at least "
                     f"{need[i]:.4f} s at max_brake and max_accel", "intervals")

    # jerk: for a speed with a continuous acceleration whose derivative (the jerk) is
    # bounded, 2 · v[t0, t1, t2] is a weighted mean of the jerk over [t0, t2] (the Peano
    # kernel of a second divided difference is a positive B-spline of integral 1/2), hence
    # at most max_jerk in size. Samples a few µs apart would let rounding dominate (its
    # error grows as 1 / h²), so the speeds are thinned to at least JERK_MIN_DT apart.
    keep = _thin(t, JERK_MIN_DT)
    if len(keep) < 3:
        return
    tk, vk = t[keep], v[keep]
    h = np.diff(tk)
    slope = np.diff(vk) / h
    span = tk[2:] - tk[:-2]
    jerk = 2 * np.diff(slope) / span
    # rounding: each speed is off by up to V_ROUND and each time by up to T_ROUND, so a
    # slope over h is off by up to (2 V_ROUND + 2 T_ROUND |slope|) / h (to first order)
    # and twice the difference of two slopes over the span by 2 (e01 + e12) / span
    err = (2 * V_ROUND + 2 * T_ROUND * np.abs(slope)) / h
    jerk_tol = 2 * (err[:-1] + err[1:]) / (span - 2 * T_ROUND)
    mask = np.zeros(len(t), dtype=bool)
    bad = np.abs(jerk) > veh.max_jerk + jerk_tol
    middle = keep[1:-1]
    mask[middle[bad]] = True

    def describe(i: int) -> str:
        j = int(np.searchsorted(middle, i))
        return (f"jerk about {jerk[j]:+.2f} m/s³ around t={t[i]:.2f} s (from v="
                f"{vk[j]:.4f}, {vk[j + 1]:.4f}, {vk[j + 2]:.4f} m/s at t={tk[j]:.6f}, "
                f"{tk[j + 1]:.6f}, {tk[j + 2]:.6f} s), more than max_jerk "
                f"{veh.max_jerk:.3f} m/s³ (+{jerk_tol[j]:.3f} for rounding)")

    _first(out, "jerk", veh, mask, describe)


def _thin(t: FloatArray, min_dt: float) -> np.ndarray:
    """Indices of the samples kept for the jerk test: the first and every one at least
    ``min_dt`` after the sample before it, so consecutive kept samples are at least
    ``min_dt`` apart; the last is always kept, in place of the kept one before it when
    it was dropped (``t`` strictly increasing)."""
    keep = np.concatenate([[0], np.flatnonzero(np.diff(t) >= min_dt) + 1])
    last = len(t) - 1
    if keep[-1] != last:
        if len(keep) > 1:
            keep[-1] = last  # further from keep[-2] than the one it replaces
        else:
            keep = np.append(keep, last)
    return keep.astype(int)
