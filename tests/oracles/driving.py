"""A path driven step by step by the kinematic bicycle model, sharing nothing with lotsim's
geometry: each piece is read as its signed length, its curvature at its start and the rate
that curvature changes per metre (a clothoid's sharpness), and integrated by the midpoint
rule (x' = cos θ, y' = sin θ, θ' = κ) in millimetre steps; car bodies are rectangles built
here from the car's width and overhangs, for shapely to judge."""

from __future__ import annotations

import math

import numpy as np
import shapely

STEP = 1e-3
"""Integration step [m]."""
EVERY = 40
"""Steps between the poses :func:`drive` hands back (4 cm)."""


def min_radius(vehicle) -> float:
    """The tightest turn of a car [m], from its wheelbase and steering lock: ``b / tan φ``."""
    return vehicle.wheelbase / math.tan(vehicle.max_steer)


def drive(path, start) -> tuple[np.ndarray, list[np.ndarray], np.ndarray]:
    """Drive ``path`` (pieces with ``distance``, ``curvature``, ``sharpness``) from pose
    ``start``, ignoring where each piece says it starts.

    Returns the poses at each piece's start as driven (one a piece, and the end), the poses
    along each piece (a few centimetres apart), and the curvature at each step [1/m].
    """
    x, y, th = (float(v) for v in start)
    at, along, bends = [], [], []
    for seg in path:
        at.append((x, y, th))
        n = max(1, math.ceil(abs(seg.distance) / STEP))
        h = seg.distance / n
        kappa = seg.curvature + seg.sharpness * abs(h) * (np.arange(n) + 0.5)
        turn = np.concatenate([[0.0], np.cumsum(h * kappa)])
        mid = th + turn[:-1] + 0.5 * h * kappa
        xs = x + np.concatenate([[0.0], np.cumsum(h * np.cos(mid))])
        ys = y + np.concatenate([[0.0], np.cumsum(h * np.sin(mid))])
        ths = th + turn
        poses = np.column_stack([xs, ys, ths])
        along.append(np.vstack([poses[:-1:EVERY], poses[-1:]]))
        bends.append(kappa)
        x, y, th = float(xs[-1]), float(ys[-1]), float(ths[-1])
    at.append((x, y, th))
    return np.array(at), along, np.concatenate(bends) if bends else np.zeros(0)


def heading_gap(a: float, b: float) -> float:
    """|a - b| as an angle [rad], in [0, π]."""
    return abs(math.remainder(a - b, math.tau))


def breaks(path, start, tol: float = 1e-3) -> list[str]:
    """Where ``path`` driven from ``start`` does not meet a piece where that piece says it
    starts (a jump in position or heading), as strings; [] when it is continuous."""
    at, _, _ = drive(path, start)
    out = []
    for k, (seg, pose) in enumerate(zip(path, at, strict=False)):
        if (math.dist(seg.start[:2], pose[:2]) > tol
                or heading_gap(seg.start[2], pose[2]) > tol):
            out.append(f"piece {k} starts at {seg.start}, driven to {tuple(pose)}")
    return out


def curvature_jumps(path, tol: float = 1e-9) -> list[int]:
    """Indices of the pieces whose curvature at their start differs from the curvature the
    piece before ends with (a jump of the steering wheel)."""
    out = []
    for k in range(1, len(path)):
        before = path[k - 1]
        end = before.curvature + before.sharpness * abs(before.distance)
        if abs(end - path[k].curvature) > tol:
            out.append(k)
    return out


def bodies(poses: np.ndarray, width: float, front: float, rear: float) -> np.ndarray:
    """The car's rectangle at each rear-axle pose (N, 3), as shapely polygons."""
    poses = np.asarray(poses, dtype=float)
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    corners = [(-rear, -width / 2), (front, -width / 2), (front, width / 2),
               (-rear, width / 2)]
    rings = np.stack([np.column_stack([poses[:, 0] + c * a - s * b,
                                       poses[:, 1] + s * a + c * b]) for a, b in corners],
                     axis=1)
    return shapely.polygons(rings)


def on_line(pose, line: tuple[float, float, float], tol: float = 1e-3) -> float | None:
    """How far along ``line`` (a point and heading) ``pose`` lies [m], when it stands on the
    line heading its way; None when it does not."""
    x0, y0, h = line
    dx, dy = pose[0] - x0, pose[1] - y0
    along = dx * math.cos(h) + dy * math.sin(h)
    across = -dx * math.sin(h) + dy * math.cos(h)
    if abs(across) > tol or heading_gap(pose[2], h) > tol:
        return None
    return along
