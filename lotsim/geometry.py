"""Planar geometry shared by every layer: poses, exact arc motion, path segments.

Poses are ``(x, y, theta)`` of a vehicle's rear-axle centre in metres and
radians, held as ``(N, 3)`` arrays when there are many. Motion at constant
curvature is solved in closed form (a line or a circle), never stepped.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

Pose = tuple[float, float, float]
"""A pose ``(x [m], y [m], theta [rad])``."""

FloatArray = NDArray[np.float64]


def wrap_angle(a: ArrayLike) -> FloatArray | float:
    """Wrap angles to ``[-pi, pi)`` [rad].

    >>> round(wrap_angle(3 * math.pi / 2), 6)
    -1.570796
    """
    out = (np.asarray(a, dtype=float) + np.pi) % (2 * np.pi) - np.pi
    return float(out) if out.ndim == 0 else out


def advance(poses: ArrayLike, distance: ArrayLike, curvature: ArrayLike) -> FloatArray:
    """Poses after driving a signed distance at constant curvature, exactly.

    Parameters
    ----------
    poses : array_like, shape (..., 3)
        Start poses ``(x, y, theta)`` [m, m, rad].
    distance : array_like
        Signed distance travelled by the reference point [m]; negative is reverse.
    curvature : array_like
        Signed path curvature ``kappa = tan(steer) / wheelbase`` [1/m]; positive
        turns left when driving forward. Zero drives straight.

    Returns
    -------
    ndarray, shape broadcast of the inputs + (3,)

    Notes
    -----
    With ``dtheta = kappa * s`` the chord is ``s * sin(dtheta/2) / (dtheta/2)``
    along heading ``theta + dtheta/2``; written with ``sinc`` it is exact for
    circles and stays accurate as ``kappa -> 0`` (a line).

    >>> advance([0.0, 0.0, 0.0], math.pi / 2, 1.0).round(12).tolist()
    [1.0, 1.0, 1.570796326795]
    """
    p = np.asarray(poses, dtype=float)
    s = np.asarray(distance, dtype=float)
    k = np.asarray(curvature, dtype=float)
    dtheta = k * s
    chord = s * np.sinc(dtheta / (2 * np.pi))
    mid = p[..., 2] + dtheta / 2
    out = np.empty(np.broadcast_shapes(p.shape[:-1], s.shape, k.shape) + (3,))
    out[..., 0] = p[..., 0] + chord * np.cos(mid)
    out[..., 1] = p[..., 1] + chord * np.sin(mid)
    out[..., 2] = p[..., 2] + dtheta
    return out


@dataclass(frozen=True, slots=True)
class Segment:
    """A piece of path driven at constant curvature: a straight or a circular arc.

    Attributes
    ----------
    start : Pose
        Pose at the start [m, m, rad].
    distance : float
        Signed distance driven [m]: positive forward, negative reverse.
    curvature : float
        Signed curvature of the reference point's path [1/m] (0 = straight).
    """

    start: Pose
    distance: float
    curvature: float

    @property
    def length(self) -> float:
        """Path length [m]."""
        return abs(self.distance)

    @property
    def gear(self) -> int:
        """+1 forward, -1 reverse."""
        return 1 if self.distance >= 0 else -1

    @property
    def radius(self) -> float:
        """Turning radius [m]; ``inf`` for a straight."""
        return math.inf if self.curvature == 0 else 1.0 / abs(self.curvature)

    @property
    def end(self) -> Pose:
        """Pose at the end."""
        x, y, t = advance(self.start, self.distance, self.curvature)
        return (float(x), float(y), float(t))

    def poses_at(self, s: ArrayLike) -> FloatArray:
        """Poses after travelling path lengths ``s`` (0 ≤ s ≤ length) [m]; shape (N, 3)."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        return advance(self.start, self.gear * s, self.curvature)

    def sample(self, step: float) -> FloatArray:
        """Poses every ``step`` metres or closer, both ends included; shape (N, 3)."""
        n = max(1, math.ceil(self.length / step - 1e-9))
        return self.poses_at(np.linspace(0.0, self.length, n + 1))

    def piece(self, s0: float, s1: float) -> Segment:
        """The part between path lengths ``s0 < s1`` [m]."""
        x, y, t = self.poses_at(s0)[0]
        return Segment((float(x), float(y), float(t)), self.gear * (s1 - s0), self.curvature)

    def offset(self, right: float) -> Segment:
        """The parallel path shifted ``right`` metres to the right of the heading.

        Arcs stay concentric: a left turn offset right gets a larger radius.
        """
        x, y, t = self.start
        grow = 1.0 + self.curvature * right
        if grow <= 0:
            raise ValueError("offset reaches past the centre of the arc")
        start = (x + right * math.sin(t), y - right * math.cos(t), t)
        return Segment(start, self.distance * grow, self.curvature / grow)

    def reversed(self) -> Segment:
        """The same curve driven the other way (same gear, heading flipped)."""
        x, y, t = self.end
        return Segment((x, y, float(wrap_angle(t + math.pi))), self.distance, -self.curvature)


def sample_segments(segments: Sequence[Segment], step: float) -> tuple[FloatArray, np.ndarray]:
    """Poses along many segments at once, each every ``step`` metres or closer, ends included.

    Returns the poses (N, 3) and the index of the segment each belongs to (N,).
    Like ``[s.sample(step) for s in segments]`` concatenated, in one ``advance``.
    """
    if not segments:
        return np.zeros((0, 3)), np.zeros(0, dtype=int)
    length = np.array([s.length for s in segments])
    gear = np.array([s.gear for s in segments], dtype=float)
    n = np.maximum(1, np.ceil(length / step - 1e-9).astype(int)) + 1
    owner = np.repeat(np.arange(len(segments)), n)
    first = np.concatenate([[0], np.cumsum(n)[:-1]])
    k = np.arange(owner.size) - first[owner]
    dist = length[owner] * k / (n[owner] - 1) * gear[owner]
    starts = np.array([s.start for s in segments], dtype=float)
    curv = np.array([s.curvature for s in segments], dtype=float)
    return advance(starts[owner], dist, curv[owner]), owner


def fillet_polyline(points: ArrayLike, radius: float) -> list[Segment]:
    """Forward segments along a polyline with every corner rounded by an arc.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Polyline vertices [m], N ≥ 2, no two consecutive equal.
    radius : float
        Radius of every corner arc [m].

    Returns
    -------
    list of Segment
        Straights and arcs, tangent-continuous, from the first to the last point.

    Raises
    ------
    ValueError
        If a corner turns by 179° or more, or two corners' arcs overlap on a
        leg (the message names the vertex index).

    >>> segs = fillet_polyline([[0, 0], [10, 0], [10, 10]], 2.0)
    >>> [round(s.length, 4) for s in segs]
    [8.0, 3.1416, 8.0]
    """
    p = np.asarray(points, dtype=float)
    legs = np.diff(p, axis=0)
    lengths = np.hypot(legs[:, 0], legs[:, 1])
    headings = np.arctan2(legs[:, 1], legs[:, 0])
    turns = wrap_angle(np.diff(headings)) if len(legs) > 1 else np.zeros(0)
    turns = np.atleast_1d(turns)
    if np.any(np.abs(turns) >= math.radians(179)):
        i = int(np.argmax(np.abs(turns) >= math.radians(179))) + 1
        raise ValueError(f"the polyline turns back on itself at vertex {i}")
    tangents = radius * np.tan(np.abs(turns) / 2)
    cut_in = np.concatenate([[0.0], tangents])  # trimmed at the start of each leg
    cut_out = np.concatenate([tangents, [0.0]])  # trimmed at the end of each leg
    for i in np.flatnonzero(cut_in + cut_out > lengths + 1e-9):
        raise ValueError(
            f"leg {i} is {lengths[i]:.2f} m long but its corner arcs need "
            f"{cut_in[i] + cut_out[i]:.2f} m"
        )
    segments: list[Segment] = []
    for i, (leg_len, h) in enumerate(zip(lengths, headings, strict=True)):
        a = p[i] + cut_in[i] * np.array([math.cos(h), math.sin(h)])
        straight = leg_len - cut_in[i] - cut_out[i]
        if straight > 1e-9:
            segments.append(Segment((float(a[0]), float(a[1]), float(h)), float(straight), 0.0))
        if i < len(turns) and abs(turns[i]) > 1e-12:
            b = p[i + 1] - cut_out[i] * np.array([math.cos(h), math.sin(h)])
            k = math.copysign(1.0 / radius, turns[i])
            segments.append(
                Segment((float(b[0]), float(b[1]), float(h)), float(radius * abs(turns[i])), k)
            )
    return segments


def rectangle_footprints(poses: ArrayLike, outline: ArrayLike) -> FloatArray:
    """A body ``outline`` (K, 2, in the pose's frame) placed at many poses (N, 3) → (N, K, 2)."""
    p = np.atleast_2d(np.asarray(poses, dtype=float))
    body = np.asarray(outline, dtype=float)
    c, s = np.cos(p[:, 2])[:, None], np.sin(p[:, 2])[:, None]
    out = np.empty((len(p), len(body), 2))
    out[..., 0] = p[:, :1] + c * body[:, 0] - s * body[:, 1]
    out[..., 1] = p[:, 1:2] + s * body[:, 0] + c * body[:, 1]
    return out


def signed_area(ring: ArrayLike) -> float:
    """Signed area of a closed ring [m²]; positive when counter-clockwise."""
    r = np.asarray(ring, dtype=float)
    x, y = r[:, 0], r[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def ccw(ring: ArrayLike) -> FloatArray:
    """The ring's vertices in counter-clockwise order."""
    r = np.asarray(ring, dtype=float)
    return r if signed_area(r) >= 0 else r[::-1].copy()
