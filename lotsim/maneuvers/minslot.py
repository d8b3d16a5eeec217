"""The minimum-slot planner for parallel slots, after "Minimization of parking slots for
parallel parking" (Vlasák, Sojka & Hanzálek, 2022).

Slot frame: the slot is ``[0, L] × [0, W]`` with the road above (``y > W``). Its frame
is three wall segments — the rear end ``x = 0``, the kerb ``y = 0`` and the front end
``x = L`` — and its entry side ``y = W`` is open. The car starts with its right-front
corner on the far entry corner ``p = (L, W)`` at heading ``theta0`` (0 ≤ theta0 ≤ 90°),
reverses at full left lock until the next motion would touch the frame, then drives
forward at full right lock, and so on, until its whole footprint is inside the slot.
Every stroke turns the car clockwise about one centre, so each corner moves on a circle
and the first contact — a car corner reaching a wall, or a wall end reaching a car side —
is a circle–segment intersection, solved exactly for all start headings at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from lotsim.core.geometry import FloatArray, Segment, advance
from lotsim.errors import SettingsError
from lotsim.vehicles.model import VehicleType

NO_SOLUTION = -1
"""``changes`` value of a start heading from which the car cannot be parked."""
_EPS_ANGLE = 1e-9
_BACKOFF = 1e-7  # stop this many radians short of contact, so the next stroke starts free


@dataclass(frozen=True, slots=True)
class SlotFrame:
    """A parallel slot ``[0, length] × [0, width]`` in its own frame [m]."""

    length: float
    width: float

    @property
    def walls(self) -> FloatArray:
        """The three wall segments, (3, 2, 2): rear end, kerb, front end."""
        L, W = self.length, self.width
        return np.array([[[0, W], [0, 0]], [[0, 0], [L, 0]], [[L, 0], [L, W]]], dtype=float)

    @property
    def wall_points(self) -> FloatArray:
        """Ends of the walls, (4, 2)."""
        L, W = self.length, self.width
        return np.array([[0, W], [0, 0], [L, 0], [L, W]], dtype=float)


def start_poses(vehicle: VehicleType, frame: SlotFrame, theta0: FloatArray) -> FloatArray:
    """Rear-axle poses (T, 3) with the right-front corner on ``(L, W)`` at headings ``theta0``."""
    t = np.asarray(theta0, dtype=float)
    c, s = np.cos(t), np.sin(t)
    x = frame.length - vehicle.front * c - vehicle.width / 2 * s
    y = frame.width - vehicle.front * s + vehicle.width / 2 * c
    return np.stack([x, y, t], axis=-1)


def _circle_axis_angles(
    center: FloatArray, point: FloatArray, segments: FloatArray, direction: float
) -> FloatArray:
    """Rotation angles (in ``direction``, ±1) that bring each point onto each segment.

    ``segments`` (S, 4) rows are ``(axis, value, lo, hi)``: the segment
    ``coord[axis] == value`` with the other coordinate in ``[lo, hi]``.
    ``center`` is (T, 1, 2), ``point`` (T, N, 2). Returns (T, N, S, 2) angles in
    (0, 2π], ``inf`` where the circle misses the segment; the last axis is the crossing
    at the lower other coordinate (``-h``), then at the higher (``+h``).

    Only the few circle-segment pairs that meet get an angle computed (a fifth, typically):
    the arithmetic on each of them is the same as on the whole array, so are the angles.
    """
    axis = segments[:, 0].astype(int)
    value, lo, hi = segments[:, 1], segments[:, 2], segments[:, 3]
    rel = point - center  # (T, N, 2)
    rho2 = (rel[..., 0] ** 2 + rel[..., 1] ** 2)[..., None]  # (T, N, 1)
    c_axis = np.take(center, axis, axis=-1)  # (T, 1, S)
    c_other = np.take(center, 1 - axis, axis=-1)
    off = value - c_axis  # (T, 1, S)
    h2 = rho2 - off * off  # (T, N, S)
    out = np.full((*h2.shape, 2), np.inf)
    t, n, s = np.nonzero(h2 >= 0)
    if not len(t):
        return out
    root = np.sqrt(h2[t, n, s])
    other = np.broadcast_to(c_other, h2.shape)[t, n, s]
    off = np.broadcast_to(off, h2.shape)[t, n, s]
    on_x = axis[s] == 0
    px, py = rel[t, n, 0], rel[t, n, 1]
    for r, sign in enumerate((-1.0, 1.0)):
        h = root * sign
        along = other + h
        ok = np.flatnonzero((along >= lo[s] - 1e-12) & (along <= hi[s] + 1e-12))
        qx = np.where(on_x[ok], off[ok], h[ok])
        qy = np.where(on_x[ok], h[ok], off[ok])
        ang = np.arctan2(px[ok] * qy - py[ok] * qx, px[ok] * qx + py[ok] * qy)
        ang = np.mod(direction * ang, 2 * math.pi)
        out[t[ok], n[ok], s[ok], r] = np.where(ang <= _EPS_ANGLE, ang + 2 * math.pi, ang)
    return out


def _rotate(points: FloatArray, center: FloatArray, angle: FloatArray) -> FloatArray:
    """Rotate ``points`` (T, ..., 2) about ``center`` (T, 2) by ``angle`` (T, ...) CCW."""
    c, s = np.cos(angle), np.sin(angle)
    rel = points - center.reshape(center.shape[0], *([1] * (points.ndim - 2)), 2)
    x = rel[..., 0] * c - rel[..., 1] * s
    y = rel[..., 0] * s + rel[..., 1] * c
    return np.stack([x, y], axis=-1) + center.reshape(
        center.shape[0], *([1] * (points.ndim - 2)), 2
    )


def _inside(corners: FloatArray, frame: SlotFrame, tol: float = 1e-9) -> np.ndarray:
    x, y = corners[..., 0], corners[..., 1]
    ok = (x >= -tol) & (x <= frame.length + tol) & (y >= -tol) & (y <= frame.width + tol)
    return ok.all(axis=-1)


def _stroke(vehicle: VehicleType, frame: SlotFrame, poses: FloatArray, k: int):
    """One full-lock stroke from ``poses`` (T, 3): reverse-left when k is even, else forward-right.

    Returns (rotation to contact (T,), rotation at which the car is first inside or inf (T,)).
    Both are clockwise angles [rad].
    """
    kappa = vehicle.max_curvature if k % 2 == 0 else -vehicle.max_curvature
    theta = poses[:, 2]
    normal = np.stack([-np.sin(theta), np.cos(theta)], axis=-1)
    center = poses[:, :2] + normal / kappa
    corners = vehicle.footprints(poses)  # (T, 4, 2)
    c1 = center[:, None, :]
    L, W = frame.length, frame.width
    # corners reaching walls (rear end, kerb, front end): corners turn clockwise; and
    # corners coming down through the entry line y = W. The car can only become inside
    # when its last corner comes down through the entry line: a corner below it but
    # beyond an end of the slot could only come back in through a wall, which is a
    # contact, not a motion. Turning clockwise, a point moves down where it is right of
    # the centre: the +h root.
    lines = np.array([[0, 0.0, 0.0, W], [1, 0.0, 0.0, L], [0, L, 0.0, W],
                      [1, W, -np.inf, np.inf]])
    angles = _circle_axis_angles(c1, corners, lines, -1.0)  # (T, 4, 4, 2)
    hit_a = angles[:, :, :3]
    # wall ends reaching car sides: in the car's own frame the sides are axis-aligned and
    # the wall ends turn counter-clockwise about the centre (0, 1/kappa)
    rel = frame.wall_points[None, :, :] - poses[:, None, :2]
    cth, sth = np.cos(theta)[:, None], np.sin(theta)[:, None]
    ends = np.stack([rel[..., 0] * cth + rel[..., 1] * sth,
                     -rel[..., 0] * sth + rel[..., 1] * cth], axis=-1)  # (T, 4, 2)
    c_body = np.broadcast_to(np.array([0.0, 1.0 / kappa]), (len(poses), 1, 2))
    h, r, f = vehicle.width / 2, vehicle.rear, vehicle.front
    sides = np.array([[0, -r, -h, h], [0, f, -h, h], [1, -h, -r, f], [1, h, -r, f]])
    hit_b = _circle_axis_angles(c_body, ends, sides, 1.0)
    contact = np.minimum(hit_a.reshape(len(poses), -1).min(axis=1),
                         hit_b.reshape(len(poses), -1).min(axis=1))
    # first angle (≤ contact) at which all corners are inside the slot
    events = np.concatenate([np.zeros((len(poses), 1)), angles[:, :, 3, 1], contact[:, None]],
                            axis=1)
    events = np.where(events <= contact[:, None], events, np.inf)
    # the car turned by each finite event angle (most are inf: a corner that never comes
    # down through the entry line before the contact)
    row, col = np.nonzero(np.isfinite(events))
    moved = _rotate(corners[row], center[row], -events[row, col][:, None])  # (E, 4, 2)
    fits = np.full(events.shape, np.inf)
    inside = _inside(moved, frame)
    fits[row[inside], col[inside]] = events[row[inside], col[inside]]
    return contact, fits.min(axis=1), kappa


def simulate_strokes(
    vehicle: VehicleType, frame: SlotFrame, theta0: FloatArray, *, max_changes: int = 10,
    record: bool = False, stop_at_first: bool = False,
):
    """Run the strategy from every start heading at once.

    Returns
    -------
    changes : ndarray of int, shape (T,)
        Direction changes needed from each start heading, or ``NO_SOLUTION``
        (with ``stop_at_first``, headings still unfinished when the first one
        parks are left at ``NO_SOLUTION``).
    strokes : list of list of Segment, only when ``record``
        The strokes driven from each start heading.
    """
    theta0 = np.atleast_1d(np.asarray(theta0, dtype=float))
    poses = start_poses(vehicle, frame, theta0)
    changes = np.full(len(theta0), NO_SOLUTION, dtype=int)
    active = _start_free(vehicle, frame, poses)
    strokes: list[list[Segment]] = [[] for _ in theta0] if record else []
    floor = -_fitting_heading(vehicle, frame)
    for k in range(max_changes + 1):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        contact, first, kappa = _stroke(vehicle, frame, poses[idx], k)
        done = np.isfinite(first)
        stuck = ~done & ~np.isfinite(contact)  # turns full circles without ever fitting
        angle = np.where(done, first, np.maximum(contact - _BACKOFF, 0.0))
        angle = np.where(stuck, 0.0, angle)
        distance = -angle / kappa  # clockwise rotation: reverse when kappa > 0
        if record:
            for j, i in enumerate(idx):
                if angle[j] > 0:
                    strokes[i].append(Segment(tuple(map(float, poses[i])), float(distance[j]),
                                              kappa))
        poses[idx] = advance(poses[idx], distance, kappa)
        changes[idx[done]] = k
        # every stroke turns the car clockwise: once it leans out further than any
        # heading at which it fits the slot, it never will
        hopeless = poses[idx, 2] < floor
        active[idx[done | stuck | hopeless]] = False
        if stop_at_first and done.any():
            break  # strokes run in lockstep: nobody can now need fewer changes
    return (changes, strokes) if record else changes


def _fitting_heading(vehicle: VehicleType, frame: SlotFrame) -> float:
    """A bound on |heading| [rad] beyond which the car cannot lie inside the slot.

    The car's extent across the slot, ``l·|sin θ| + w·cos θ = sqrt(l² + w²)·sin(|θ| + φ)``
    with ``φ = atan(w / l)``, exceeds ``W`` for every |θ| between the root of ``= W`` and
    90° when ``w ≤ W < l``; otherwise no bound is claimed.
    """
    length, w = vehicle.length, vehicle.width
    if not w <= frame.width < length:
        return math.inf
    return math.asin(frame.width / math.hypot(length, w)) - math.atan2(w, length)


def edges_cross_walls(corners: FloatArray, walls: FloatArray) -> np.ndarray:
    """(T,) whether any side of the bodies ``corners`` (T, 4, 2) meets any wall (S, 2, 2)."""
    edges = np.stack([corners, np.roll(corners, -1, axis=1)], axis=2)  # (T, 4, 2, 2)
    p, r = edges[:, :, None, 0, :], edges[:, :, None, 1, :] - edges[:, :, None, 0, :]
    q, s = walls[None, None, :, 0, :], walls[None, None, :, 1, :] - walls[None, None, :, 0, :]
    denom = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    qp = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (qp[..., 0] * s[..., 1] - qp[..., 1] * s[..., 0]) / denom
        u = (qp[..., 0] * r[..., 1] - qp[..., 1] * r[..., 0]) / denom
    return ((denom != 0) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)).any(axis=(1, 2))


def _start_free(vehicle: VehicleType, frame: SlotFrame, poses: FloatArray) -> np.ndarray:
    """Start poses whose body crosses no wall (touching the corner p is allowed)."""
    return ~edges_cross_walls(vehicle.footprints(poses) - np.array([1e-7, 0.0]), frame.walls)


def start_headings(step_deg: float = 0.1) -> FloatArray:
    """The swept start headings, 0 to 90° inclusive [rad]."""
    n = int(round(90 / step_deg))
    return np.radians(np.linspace(0.0, 90.0, n + 1))


def fewest_changes(
    vehicle: VehicleType, length: float, width: float, *, max_changes: int = 10,
    step_deg: float = 0.1,
) -> tuple[int, float]:
    """Fewest direction changes over all start headings, and the heading that needs them.

    Returns ``(NO_SOLUTION, nan)`` when no heading parks the car with ≤ ``max_changes``.
    """
    if length < vehicle.length or width < vehicle.width:
        return NO_SOLUTION, math.nan
    thetas = start_headings(step_deg)
    changes = simulate_strokes(vehicle, SlotFrame(length, width), thetas, max_changes=max_changes,
                       stop_at_first=True)
    ok = changes >= 0
    if not ok.any():
        return NO_SOLUTION, math.nan
    best = int(changes[ok].min())
    return best, float(thetas[np.flatnonzero(changes == best)[0]])


@dataclass(frozen=True, slots=True)
class MinSlotRow:
    """The shortest slot for at most ``changes`` direction changes.

    ``length`` [m] is ``None`` when no length up to the search limit works;
    ``theta0`` [rad] is a start heading that achieves it.
    """

    changes: int
    length: float | None
    theta0: float | None


def min_slot_lengths(
    vehicle: VehicleType, width: float, *, max_changes: int = 10, resolution: float = 0.01,
    step_deg: float = 0.2, max_length: float | None = None,
) -> list[MinSlotRow]:
    """Minimum parallel-slot length for each number of direction changes ``0..max_changes``.

    Lengths are searched on multiples of ``resolution`` [m] from one step above the
    car's length to ``max_length`` (default 2 car lengths). More length never needs more changes in
    this strategy, so the thresholds are found by bisection on the staircase
    ``changes(L)``, evaluating each length once.

    Examples
    --------
    >>> from lotsim.vehicles import CATALOGUE
    >>> rows = min_slot_lengths(CATALOGUE["altis"], 2.5, max_changes=1)
    >>> [(r.changes, round(r.length, 2)) for r in rows]
    [(0, 6.06), (1, 5.59)]
    """
    if max_changes < 0:
        raise SettingsError("max_changes", f"expected zero or more, found {max_changes}")
    if width < vehicle.width:
        return [MinSlotRow(g, None, None) for g in range(max_changes + 1)]
    unsolved = max_changes + 1
    first = math.ceil(vehicle.length / resolution - 1e-9)
    last = math.floor((max_length or 2.0 * vehicle.length) / resolution + 1e-9)
    cache: dict[int, tuple[int, float]] = {}

    def g(k: int, cap: int) -> int:
        if k not in cache:
            c, t = fewest_changes(vehicle, k * resolution, width, max_changes=min(cap, max_changes),
                                  step_deg=step_deg)
            cache[k] = (unsolved if c == NO_SOLUTION else c, t)
        return cache[k][0]

    answer: dict[int, int] = {}
    g_last = g(last, max_changes)
    # a slot within one length step of the car's own length leaves no room to turn in
    g_first = unsolved if first * resolution - vehicle.length < resolution else g(first, g_last)

    def solve(lo: int, hi: int, g_lo: int, g_hi: int) -> None:
        # invariant: g_lo > g_hi; thresholds for changes in [g_hi, g_lo) lie in (lo, hi]
        if hi - lo == 1:
            for c in range(g_hi, min(g_lo, unsolved)):
                answer[c] = hi
            return
        mid = (lo + hi) // 2
        g_mid = min(max(g(mid, g_lo), g_hi), g_lo)  # keep the staircase monotone
        if g_lo > g_mid:
            solve(lo, mid, g_lo, g_mid)
        if g_mid > g_hi:
            solve(mid, hi, g_mid, g_hi)

    for c in range(g_first, unsolved):
        answer[c] = first
    if g_first > g_last:
        solve(first, last, g_first, g_last)
    rows = []
    for c in range(max_changes + 1):
        k = answer.get(c)
        if k is None:
            rows.append(MinSlotRow(c, None, None))
        else:
            rows.append(MinSlotRow(c, round(k * resolution, 10), cache[k][1]))
    return rows
