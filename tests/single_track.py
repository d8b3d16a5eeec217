"""An independent oracle for planned motion: the kinematic single-track (bicycle) model.

A planner's samples must be reproducible by integrating the vehicle model from the
result's own steering angle and speed: starting from the first sample's rear-axle pose and
driving ``v`` and ``steer`` as recorded, the model has to arrive at the recorded poses.
This module does that integration, sharing no code with lotsim (numpy only), so tests can
hold a result — hand-built or planned — against it::

    ẋ = v cos θ,   ẏ = v sin θ,   θ̇ = v tan(φ) / b

with ``v`` the signed speed, ``φ`` the road-wheel angle and ``b`` the wheelbase.

Known error sources, all small for a faithful result: under a millimetre over the 25 m of
the hand-built car in ``test_check_dynamics.py``, a few millimetres over lotsim's
quickstart routes, but growing with the distance driven (5 cm were seen over a 190 m
route with 7.9 rad of turning), so a test allows about a centimetre on a short path and
proportionally more on a long one:

- between samples ``v`` and ``φ`` are interpolated linearly in time, whereas a planner's
  jerk-limited speed is a cubic in time and its steering along a clothoid driven at a
  changing speed is not linear in time either. Interpolating a speed with jerk ``J`` over
  ``Δt`` misplaces the car by about ``J · Δt³ / 12`` per interval (2e-5 m at 2 m/s³ and
  0.05 s), partly cancelling between speeding up and slowing down; a steer off by
  ``δφ`` over an interval turns the car by ``v · Δt · δφ / (b cos² φ)`` too much or little,
  and a heading error grows into a sideways error along the rest of the path;
- the samples themselves are rounded (positions to 0.1 mm, speeds to 0.1 mm/s, angles to
  1 µrad) and integration starts from the first, rounded, pose only: nothing is re-synced
  later, so errors add up along the trajectory;
- the fourth-order Runge-Kutta steps (``substeps`` per sample interval) err by
  ``O(h⁵)`` per step, negligible at 20 steps per 0.05 s.
"""

from __future__ import annotations

import numpy as np


def _column(samples: dict, key: str) -> np.ndarray:
    return np.asarray(samples[key], dtype=float)


def integrate(samples: dict, wheelbase: float, *, substeps: int = 20) -> np.ndarray:
    """Integrate the single-track model through the samples' speeds and steering angles.

    Parameters
    ----------
    samples : dict
        ``t``, ``x``, ``y``, ``theta``, ``v``, ``steer`` sequences of equal length, as in
        ``result.json``; only the first pose is read, and ``t``, ``v``, ``steer`` throughout.
    wheelbase : float
        Rear to front axle [m].
    substeps : int, keyword-only
        RK4 steps per sample interval.

    Returns
    -------
    numpy.ndarray
        (N, 3): the integrated rear-axle pose ``x, y, theta`` at every sample time, the
        heading unwrapped (it continues past ±pi).
    """
    t, v, phi = _column(samples, "t"), _column(samples, "v"), _column(samples, "steer")
    n = len(t)
    out = np.empty((n, 3))
    if n == 0:
        return out
    out[0] = (samples["x"][0], samples["y"][0], samples["theta"][0])
    if n == 1:
        return out
    # The model is the same in every rigid frame, so each interval is integrated from the
    # origin, all intervals at once (RK4, ``substeps`` steps), and the local moves are then
    # chained: the same arithmetic as integrating interval after interval, in numpy.
    dt = np.diff(t)
    v0, dv, p0, dp = v[:-1], np.diff(v), phi[:-1], np.diff(phi)
    h = dt / substeps
    pose = np.zeros((n - 1, 3))

    def rate(f: np.ndarray, p: np.ndarray) -> np.ndarray:
        speed, steer = v0 + f * dv, p0 + f * dp
        return np.column_stack([speed * np.cos(p[:, 2]), speed * np.sin(p[:, 2]),
                                speed * np.tan(steer) / wheelbase])

    for k in range(substeps):
        f0, fh, f1 = k / substeps, (k + 0.5) / substeps, (k + 1) / substeps
        k1 = rate(f0, pose)
        k2 = rate(fh, pose + (h / 2)[:, None] * k1)
        k3 = rate(fh, pose + (h / 2)[:, None] * k2)
        k4 = rate(f1, pose + h[:, None] * k3)
        pose = pose + (h / 6)[:, None] * (k1 + 2 * k2 + 2 * k3 + k4)
    heading = out[0, 2] + np.concatenate([[0.0], np.cumsum(pose[:, 2])])
    c, s_ = np.cos(heading[:-1]), np.sin(heading[:-1])
    out[1:, 0] = out[0, 0] + np.cumsum(c * pose[:, 0] - s_ * pose[:, 1])
    out[1:, 1] = out[0, 1] + np.cumsum(s_ * pose[:, 0] + c * pose[:, 1])
    out[:, 2] = heading
    return out


def max_error(samples: dict, wheelbase: float) -> tuple[float, float]:
    """The largest distance [m] and heading difference [rad] between the recorded poses
    and those :func:`integrate` reaches from the first one (headings compared the short
    way round)."""
    poses = integrate(samples, wheelbase)
    if not len(poses):
        return 0.0, 0.0
    x, y, th = _column(samples, "x"), _column(samples, "y"), _column(samples, "theta")
    position = np.hypot(poses[:, 0] - x, poses[:, 1] - y)
    heading = np.abs((poses[:, 2] - th + np.pi) % (2 * np.pi) - np.pi)
    return float(position.max()), float(heading.max())


def assert_reproduced(doc: dict) -> None:
    """Every vehicle of a result is reproduced by integrating the model from its first
    sample: within 1 cm plus 0.05 % of the distance it drove, and a heading within
    2 mrad plus 0.01 mrad per metre (errors add up along a route: see the module's notes)."""
    for veh in doc["vehicles"]:
        s = veh["samples"]
        if len(s["t"]) < 2:
            continue
        driven = float(np.sum(np.hypot(np.diff(s["x"]), np.diff(s["y"]))))
        pos, head = max_error(s, veh["type"]["wheelbase"])
        assert pos <= 0.01 + 5e-4 * driven, (veh["id"], pos, driven)
        assert head <= 2e-3 + 1e-5 * driven, (veh["id"], head, driven)
