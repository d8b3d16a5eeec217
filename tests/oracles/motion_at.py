"""A motion sampled phase by phase, each phase's samples on their own: how
:meth:`lotsim.vehicles.motion.Motion.at` worked out a motion before it sampled many in one
batch, kept as the reference its numbers are compared with, bit for bit."""

from __future__ import annotations

import numpy as np

from lotsim.core.geometry import travel
from lotsim.vehicles.motion import Motion, Profile, Steering, Stroke


def profile_at(profile: Profile, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Path length and speed at times ``tau`` along ``profile``."""
    t, s, v, a = profile.t, profile.s, profile.v, profile.a
    tau = np.asarray(tau, dtype=float)
    k = np.clip(np.searchsorted(t, tau, side="right") - 1, 0, len(t) - 2)
    cell = t[k + 1] - t[k]
    jerk = np.where(cell > 0, (a[k + 1] - a[k]) / np.where(cell > 0, cell, 1.0), 0.0)
    d = np.clip(tau - t[k], 0.0, cell)
    pos = s[k] + v[k] * d + a[k] * d * d / 2 + jerk * d ** 3 / 6
    speed = v[k] + a[k] * d + jerk * d * d / 2
    done = tau >= t[-1]
    pos, speed = np.where(done, s[-1], pos), np.where(done, v[-1], speed)
    return np.clip(pos, 0.0, s[-1]), np.maximum(speed, 0.0)


def stroke_poses(stroke: Stroke, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Poses and curvatures after path lengths ``s`` along ``stroke``."""
    segs = stroke.segments
    lengths = np.array([g.length for g in segs])
    starts = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
    pid = np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(segs) - 1)
    into = np.clip(s - starts[pid], 0.0, lengths[pid])
    seg_start = np.array([g.start for g in segs])[pid]
    kappa = np.array([g.curvature for g in segs])[pid]
    sigma = np.array([g.sharpness for g in segs])[pid]
    return travel(seg_start, stroke.gear * into, kappa, sigma), kappa + sigma * into


def motion_at(motion: Motion, tau: np.ndarray, wheelbase: float) -> tuple[np.ndarray, ...]:
    """Poses, signed speeds, steering angles and gears at times ``tau``."""
    tau = np.asarray(tau, dtype=float)
    off = motion.offsets
    which = np.clip(np.searchsorted(off, tau, side="left") - 1, 0, len(off) - 1)
    poses = np.zeros((len(tau), 3))
    v = np.zeros(len(tau))
    steer = np.zeros(len(tau))
    gear = np.zeros(len(tau), dtype=int)
    for i, ph in enumerate(motion.phases):
        sel = which == i
        if not sel.any():
            continue
        if isinstance(ph, Steering):
            poses[sel] = ph.pose
            frac = np.clip((tau[sel] - off[i]) / ph.duration, 0.0, 1.0) if ph.duration \
                else np.ones(int(sel.sum()))
            steer[sel] = ph.start + (ph.end - ph.start) * frac
            continue
        s, speed = profile_at(ph.profile, tau[sel] - off[i])
        poses[sel], kappa = stroke_poses(ph, s)
        v[sel] = ph.gear * speed
        steer[sel] = np.arctan(kappa * wheelbase)
        gear[sel] = ph.gear
    return poses, v, steer, gear
