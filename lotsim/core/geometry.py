"""Planar geometry shared by every layer: poses, exact arc motion, path segments.

Poses are ``(x, y, theta)`` of a vehicle's rear-axle centre in metres and
radians, held as ``(N, 3)`` arrays when there are many. Motion at constant
curvature is solved in closed form (a line or a circle), never stepped; along a
clothoid (curvature changing linearly with distance, the transition a car drives
while it turns its wheels) positions are Fresnel-type integrals, evaluated by
Gauss–Legendre quadrature to machine precision.
"""

from __future__ import annotations

import functools
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


_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
_GL_PHASE = 0.5  # most heading change one quadrature cell integrates [rad]


def _gl_nodes(phase: float) -> tuple[FloatArray, FloatArray]:
    """Gauss–Legendre nodes as fractions of a path length, in enough cells that none turns
    by more than :data:`_GL_PHASE` over a path turning by ``phase`` [rad], and their
    weights per metre of that length."""
    return _gl_cells(max(1, math.ceil(phase / _GL_PHASE)))


@functools.lru_cache(maxsize=64)
def _gl_cells(cells: int) -> tuple[FloatArray, FloatArray]:
    """:func:`_gl_nodes` for ``cells`` cells, kept (read-only arrays: shared by callers)."""
    frac = (np.arange(cells)[:, None] + (_GL_X[None, :] + 1) / 2).ravel() / cells
    weight = np.tile(_GL_W, cells) / (2 * cells)
    frac.flags.writeable = weight.flags.writeable = False
    return frac, weight


def travel(poses: ArrayLike, distance: ArrayLike, curvature: ArrayLike,
           sharpness: ArrayLike = 0.0) -> FloatArray:
    """Poses after driving a signed distance along a clothoid, exactly.

    Like :func:`advance`, with the curvature changing linearly along the path:
    after a path length ``u`` it is ``curvature + sharpness * u``. Where the
    sharpness is zero this is :func:`advance`.

    Parameters
    ----------
    poses : array_like, shape (..., 3)
    distance : array_like
        Signed distance [m]; negative is reverse.
    curvature : array_like
        Signed curvature at the start [1/m].
    sharpness : array_like
        Change of curvature per metre of path [1/m²].

    Returns
    -------
    ndarray, shape broadcast of the inputs + (3,)

    Notes
    -----
    The heading is ``theta + g (k u + sigma u² / 2)`` for gear ``g``; the position
    integrates its cosine and sine with 8-point Gauss–Legendre quadrature on cells
    over which the heading turns at most 0.5 rad (error far below a micrometre).

    >>> p = travel([0.0, 0.0, 0.0], 2.0, 0.0, 0.25)   # curvature 0 → 0.5 over 2 m
    >>> round(float(p[2]), 12), bool(p[1] > 0)
    (0.5, True)
    """
    p = np.asarray(poses, dtype=float)
    s = np.asarray(distance, dtype=float)
    k = np.asarray(curvature, dtype=float)
    g = np.asarray(sharpness, dtype=float)
    if not np.any(g):
        return advance(p, s, k)
    shape = np.broadcast_shapes(p.shape[:-1], s.shape, k.shape, g.shape)
    p = np.broadcast_to(p, shape + (3,)).reshape(-1, 3)
    s, k, g = (np.broadcast_to(a, shape).ravel() for a in (s, k, g))
    u = np.abs(s)
    gear = np.where(s < 0, -1.0, 1.0)
    frac, unit = _gl_nodes(float(np.max(np.abs(k) * u + np.abs(g) * u * u / 2, initial=0.0)))
    w = u[:, None] * frac[None, :]  # quadrature points in [0, u], (N, cells * 8)
    head = p[:, 2:3] + gear[:, None] * (k[:, None] * w + g[:, None] * w * w / 2)
    weight = unit[None, :] * u[:, None]
    out = np.empty((len(p), 3))
    out[:, 0] = p[:, 0] + gear * np.sum(weight * np.cos(head), axis=1)
    out[:, 1] = p[:, 1] + gear * np.sum(weight * np.sin(head), axis=1)
    out[:, 2] = p[:, 2] + gear * (k * u + g * u * u / 2)
    return out.reshape(shape + (3,))


def _clothoid_end(start: Pose, distance: float, curvature: float, sharpness: float) -> Pose:
    """:func:`travel` for one pose and one distance, without broadcasting: the same
    quadrature (a segment's end is asked for often)."""
    x, y, t = start
    u = abs(distance)
    gear = -1.0 if distance < 0 else 1.0
    frac, unit = _gl_nodes(abs(curvature) * u + abs(sharpness) * u * u / 2)
    w = u * frac
    head = t + gear * (curvature * w + sharpness * w * w / 2)
    weight = unit * u
    return (float(x + gear * np.dot(weight, np.cos(head))),
            float(y + gear * np.dot(weight, np.sin(head))),
            float(t + gear * (curvature * u + sharpness * u * u / 2)))


@dataclass(frozen=True, slots=True)
class Segment:
    """A piece of path: a straight, a circular arc or a clothoid.

    Attributes
    ----------
    start : Pose
        Pose at the start [m, m, rad].
    distance : float
        Signed distance driven [m]: positive forward, negative reverse.
    curvature : float
        Signed curvature ``tan(steer) / wheelbase`` at the start [1/m] (0 = straight).
    sharpness : float
        Change of curvature per metre of path driven [1/m²]: 0 on straights and
        arcs; on a clothoid the curvature after a path length ``u`` is
        ``curvature + sharpness * u``.
    """

    start: Pose
    distance: float
    curvature: float
    sharpness: float = 0.0

    @property
    def length(self) -> float:
        """Path length [m]."""
        return abs(self.distance)

    @property
    def gear(self) -> int:
        """+1 forward, -1 reverse."""
        return 1 if self.distance >= 0 else -1

    def __reduce__(self) -> tuple:
        # by its fields, not by dataclass's slot state: three times quicker to load, which
        # is most of loading a prepared lot from the cache
        return Segment, (self.start, self.distance, self.curvature, self.sharpness)

    @property
    def end_curvature(self) -> float:
        """Signed curvature at the end [1/m]."""
        return self.curvature + self.sharpness * self.length

    @property
    def max_curvature(self) -> float:
        """Largest ``|curvature|`` along the segment [1/m]."""
        return max(abs(self.curvature), abs(self.end_curvature))

    @property
    def radius(self) -> float:
        """Tightest turning radius along the segment [m]; ``inf`` for a straight."""
        k = self.max_curvature
        return math.inf if k == 0 else 1.0 / k

    @property
    def end(self) -> Pose:
        """Pose at the end."""
        if self.sharpness == 0.0:  # a line or a circle: :func:`advance`, in scalars
            x, y, t = self.start
            half = self.curvature * self.distance / 2
            chord = self.distance * (math.sin(half) / half if half else 1.0)
            return (x + chord * math.cos(t + half), y + chord * math.sin(t + half),
                    t + 2 * half)
        return _clothoid_end(self.start, self.distance, self.curvature, self.sharpness)

    def poses_at(self, s: ArrayLike) -> FloatArray:
        """Poses after travelling path lengths ``s`` (0 ≤ s ≤ length) [m]; shape (N, 3)."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        return travel(self.start, self.gear * s, self.curvature, self.sharpness)

    def curvature_at(self, s: ArrayLike) -> FloatArray:
        """Signed curvature after travelling path lengths ``s`` [m] [1/m]."""
        return self.curvature + self.sharpness * np.asarray(s, dtype=float)

    def sample(self, step: float) -> FloatArray:
        """Poses every ``step`` metres or closer, both ends included; shape (N, 3)."""
        n = max(1, math.ceil(self.length / step - 1e-9))
        return self.poses_at(np.linspace(0.0, self.length, n + 1))

    def piece(self, s0: float, s1: float) -> Segment:
        """The part between path lengths ``s0 < s1`` [m]."""
        x, y, t = self.poses_at(s0)[0]
        return Segment((float(x), float(y), float(t)), self.gear * (s1 - s0),
                       self.curvature + self.sharpness * s0, self.sharpness)

    def backwards(self) -> Segment:
        """The same path driven backwards in time: from the end to the start, the other
        gear, the same steering at every point."""
        return Segment(self.end, -self.distance, self.end_curvature, -self.sharpness)


def same_pose(a: Pose | None, b: Pose | None) -> bool:
    """Whether two poses are one (a micrometre, a microradian); two Nones are too."""
    if a is None or b is None:
        return a is b
    return math.dist(a[:2], b[:2]) < 1e-6 and abs(math.remainder(a[2] - b[2], math.tau)) < 1e-6


def sample_segments(segments: Sequence[Segment], step: float) -> tuple[FloatArray, np.ndarray]:
    """Poses along many segments at once, each every ``step`` metres or closer, ends included.

    Returns the poses (N, 3) and the index of the segment each belongs to (N,).
    Like ``[s.sample(step) for s in segments]`` concatenated, in one ``advance``.
    """
    if not segments:
        return np.zeros((0, 3)), np.zeros(0, dtype=int)
    return sample_pieces(np.array([s.start for s in segments], dtype=float),
                         np.array([s.distance for s in segments], dtype=float),
                         np.array([s.curvature for s in segments], dtype=float), step,
                         np.array([s.sharpness for s in segments], dtype=float))


def sample_pieces(starts: FloatArray, distance: FloatArray, curvature: FloatArray,
                  step: float, sharpness: FloatArray | float = 0.0
                  ) -> tuple[FloatArray, np.ndarray]:
    """:func:`sample_segments` of segments given as arrays: start poses (N, 3), signed
    distances, curvatures and sharpnesses (N,)."""
    length = np.abs(distance)
    gear = np.where(distance >= 0, 1.0, -1.0)
    n = np.maximum(1, np.ceil(length / step - 1e-9).astype(int)) + 1
    owner = np.repeat(np.arange(len(length)), n)
    first = np.concatenate([[0], np.cumsum(n)[:-1]])
    k = np.arange(owner.size) - first[owner]
    dist = length[owner] * k / (n[owner] - 1) * gear[owner]
    sharp = np.broadcast_to(np.asarray(sharpness, dtype=float), length.shape)
    return travel(starts[owner], dist, curvature[owner], sharp[owner]), owner


def cc_turn(deflection: float, max_curvature: float, sharpness: float,
            start: Pose = (0.0, 0.0, 0.0)) -> tuple[list[Segment], float]:
    """A symmetric continuous-curvature turn (Fraichard & Scheuer 2004), driven forward.

    The curvature rises linearly from 0 (a clothoid of the given ``sharpness``) to
    at most ``max_curvature``, holds there on an arc, and falls back to 0: the
    path a car drives when it turns its wheels at a steady rate while it rolls.
    A small ``deflection`` never reaches ``max_curvature``: two clothoids meet
    at the peak curvature ``sqrt(|deflection| * sharpness)``.

    Parameters
    ----------
    deflection : float
        Signed heading change [rad], ``0 < |deflection| < pi``; positive turns left.
    max_curvature : float
        Curvature of the arc [1/m], > 0.
    sharpness : float
        Rate of change of curvature along the clothoids [1/m²], > 0.
    start : Pose
        Where the turn starts.

    Returns
    -------
    segments : list of Segment
        Clothoid, arc (when long enough to exist), clothoid.
    tangent : float
        Distance from the start to where the straight lines through the start and
        the end meet, the same as from there to the end [m].

    >>> segs, tangent = cc_turn(math.pi / 2, 0.2, 0.05)
    >>> [round(s.length, 6) for s in segs], round(segs[-1].end[2], 12)
    ([4.0, 3.853982, 4.0], 1.570796326795)
    >>> abs(segs[-1].end_curvature) < 1e-12
    True
    """
    d = abs(deflection)
    if not 0 < d < math.pi or max_curvature <= 0 or sharpness <= 0:
        raise ValueError("cc_turn needs 0 < |deflection| < pi and positive curvature "
                         "and sharpness")
    sign = math.copysign(1.0, deflection)
    peak = min(max_curvature, math.sqrt(d * sharpness))
    ramp = peak / sharpness
    arc = (d - peak * ramp) / peak
    parts = [(0.0, sharpness, ramp)]
    if arc > 1e-12:
        parts.append((peak, 0.0, arc))
    parts.append((peak, -sharpness, ramp))
    segments: list[Segment] = []
    pose = start
    for k0, sig, length in parts:
        seg = Segment(pose, float(length), float(sign * k0), float(sign * sig))
        segments.append(seg)
        pose = seg.end
    # the end in the start's frame: the tangent lines meet at x = xe - ye / tan(d)
    x0, y0, t0 = start
    dx, dy = pose[0] - x0, pose[1] - y0
    xe = dx * math.cos(t0) + dy * math.sin(t0)
    ye = abs(-dx * math.sin(t0) + dy * math.cos(t0))
    return segments, xe - ye / math.tan(d)


@functools.lru_cache(maxsize=1 << 14)
def _cc_corner(deflection: float, max_curvature: float, sharpness: float
               ) -> tuple[tuple[Segment, ...], float]:
    """:func:`cc_turn` from the origin, kept: the corners of a search's candidate polylines
    repeat a few shapes (segments are immutable, so they can be shared)."""
    segments, tangent = cc_turn(deflection, max_curvature, sharpness)
    return tuple(segments), tangent


def cc_polyline(points: ArrayLike, radius: ArrayLike, sharpness: float) -> list[Segment]:
    """Forward segments along a polyline with every corner rounded by a continuous-curvature
    turn (:func:`cc_turn`): straights, clothoids and arcs, curvature-continuous.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Polyline vertices [m], N ≥ 2, no two consecutive equal.
    radius : float or array_like of N - 2 floats
        Radius of each corner's arc [m].
    sharpness : float or array_like of N - 2 floats
        Rate of change of curvature along the clothoids [1/m²], or each corner's; ``inf``
        rounds a corner by a plain arc.

    Raises
    ------
    ValueError
        When a corner turns by 179° or more, or two corners' turns overlap on a leg
        (the message names the vertex index).

    >>> segs = cc_polyline([[0, 0], [20, 0], [20, 20]], 5.0, 0.05)
    >>> [round(s.curvature, 3) for s in segs], round(segs[-1].end[0], 9)
    ([0.0, 0.0, 0.2, 0.2, 0.0], 20.0)
    """
    p = np.asarray(points, dtype=float)
    legs = np.diff(p, axis=0)
    lengths = np.hypot(legs[:, 0], legs[:, 1])
    headings = np.arctan2(legs[:, 1], legs[:, 0])
    turns = np.atleast_1d(wrap_angle(np.diff(headings))) if len(legs) > 1 else np.zeros(0)
    radii = np.broadcast_to(np.asarray(radius, dtype=float), turns.shape)
    sharp = np.broadcast_to(np.asarray(sharpness, dtype=float), turns.shape)
    if np.any(np.abs(turns) >= math.radians(179)):
        i = int(np.argmax(np.abs(turns) >= math.radians(179))) + 1
        raise ValueError(f"the polyline turns back on itself at vertex {i}")
    corners = []
    for turn, r, sigma in zip(turns, radii, sharp, strict=True):
        if abs(turn) <= 1e-12:
            corners.append(([], 0.0))
        elif math.isinf(sigma):
            t = r * math.tan(abs(turn) / 2)
            corners.append(([Segment((0.0, 0.0, 0.0), float(r * abs(turn)),
                                     math.copysign(1 / float(r), turn))], t))
        else:
            corners.append(_cc_corner(float(turn), float(1 / r), float(sigma)))
    tangents = np.array([t for _, t in corners])
    cut_in = np.concatenate([[0.0], tangents])
    cut_out = np.concatenate([tangents, [0.0]])
    for i in np.flatnonzero(cut_in + cut_out > lengths + 1e-9):
        raise ValueError(
            f"leg {i} is {lengths[i]:.2f} m long but its corner turns need "
            f"{cut_in[i] + cut_out[i]:.2f} m"
        )
    segments: list[Segment] = []
    for i, (leg_len, h) in enumerate(zip(lengths, headings, strict=True)):
        a = p[i] + cut_in[i] * np.array([math.cos(h), math.sin(h)])
        straight = leg_len - cut_in[i] - cut_out[i]
        if straight > 1e-9:
            segments.append(Segment((float(a[0]), float(a[1]), float(h)), float(straight), 0.0))
        if i < len(turns) and corners[i][0]:
            b = p[i + 1] - cut_out[i] * np.array([math.cos(h), math.sin(h)])
            pose = (float(b[0]), float(b[1]), float(h))
            for seg in corners[i][0]:
                moved = Segment(pose, seg.distance, seg.curvature, seg.sharpness)
                segments.append(moved)
                pose = moved.end
    return segments


def ease_joints(segments: Sequence[Segment], ramp: float, *,
                min_ramp: float = 0.1) -> list[Segment]:
    """The path with its jumps of curvature inside each stroke smoothed into clothoids.

    Within a run of one gear, the curvature (piecewise constant: straights and
    arcs) is replaced by its moving average over ``ramp`` metres of path: each
    jump becomes a linear ramp ``ramp`` long centred on it, and ramps closer than
    that merge, so a short straight between two arcs becomes one smooth swing
    instead of two tight steering ramps. The car then turns its wheels while it
    rolls instead of while it stands. Curvature is averaged with the ends held,
    so the start pose, and the curvature and heading at each stroke's ends, are
    kept; the path is displaced by about ``|Δκ| ramp² / 24`` per jump, so the end
    moves a little (check it). Strokes whose first or last piece is shorter than
    ``ramp / 2`` get a shorter ramp; none shorter than ``min_ramp`` [m].

    >>> segs = [Segment((0.0, 0.0, 0.0), 5.0, 0.0), Segment((5.0, 0.0, 0.0), 5.0, 0.2)]
    >>> eased = ease_joints(segs, 1.5)
    >>> [round(s.sharpness, 3) for s in eased], round(eased[-1].end[2] - segs[-1].end[2], 12)
    ([0.0, 0.133, 0.0], 0.0)
    """
    out: list[Segment] = []
    stroke: list[Segment] = []
    pose = segments[0].start if segments else (0.0, 0.0, 0.0)
    for seg in [s for s in segments if s.length > 0] + [None]:
        if seg is not None and (not stroke or stroke[-1].gear == seg.gear):
            stroke.append(seg)
            continue
        for piece in _eased_stroke(stroke, ramp, min_ramp):
            moved = Segment(pose, piece.distance, piece.curvature, piece.sharpness)
            out.append(moved)
            pose = moved.end
        stroke = [seg] if seg is not None else []
    return out


def _eased_stroke(stroke: list[Segment], ramp: float, min_ramp: float) -> list[Segment]:
    """One stroke's pieces with the curvature averaged over ``ramp`` [m] (poses unset)."""
    lengths = np.array([s.length for s in stroke])
    kappa = np.array([s.curvature for s in stroke])
    jumps = np.abs(np.diff(kappa)) > 1e-12
    width = min(ramp, 2 * lengths[0], 2 * lengths[-1])
    if not jumps.any() or any(s.sharpness for s in stroke) or width < min_ramp:
        return list(stroke)
    knots = np.concatenate([[0.0], np.cumsum(lengths)])
    total = float(knots[-1])
    area = np.concatenate([[0.0], np.cumsum(kappa * lengths)])  # ∫κ at the knots

    def integral(u: FloatArray) -> FloatArray:  # ∫κ from 0 to u, κ held beyond the ends
        inside = np.interp(u, knots, area)
        return inside + np.where(u < 0, kappa[0] * u, 0.0) \
            + np.where(u > total, kappa[-1] * (u - total), 0.0)

    inner = knots[1:-1][jumps]
    cuts = np.unique(np.clip(np.concatenate([[0.0, total], inner - width / 2,
                                             inner + width / 2]), 0.0, total))
    avg = (integral(cuts + width / 2) - integral(cuts - width / 2)) / width
    # a window within one piece (or past an end) averages nothing: its curvature exactly
    lo = np.clip(np.searchsorted(knots, cuts - width / 2 + 1e-12, side="right") - 1, 0,
                 len(kappa) - 1)
    hi = np.clip(np.searchsorted(knots, cuts + width / 2 - 1e-12, side="right") - 1, 0,
                 len(kappa) - 1)
    avg = np.where(lo == hi, kappa[lo], avg)
    g = stroke[0].gear
    out = []
    for a, b, ka, kb in zip(cuts[:-1], cuts[1:], avg[:-1], avg[1:], strict=True):
        if b - a > 1e-12:
            sigma = (kb - ka) / (b - a)
            out.append(Segment((0.0, 0.0, 0.0), float(g * (b - a)), float(ka),
                               float(sigma) if abs(sigma) > 1e-12 else 0.0))
    return out


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
    # the next vertex of each, as np.roll(-1) gives it (in a fifth of the time)
    return 0.5 * float(np.dot(x, np.concatenate((y[1:], y[:1])))
                       - np.dot(np.concatenate((x[1:], x[:1])), y))


def ccw(ring: ArrayLike) -> FloatArray:
    """The ring's vertices in counter-clockwise order."""
    r = np.asarray(ring, dtype=float)
    return r if signed_area(r) >= 0 else r[::-1].copy()
