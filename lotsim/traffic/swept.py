"""Swept volumes: what a moving vehicle's body covers, chunk by chunk of its motion.

For each short chunk of a motion (at most ``chunk`` seconds) the convex hull of the
vehicle's footprints over that chunk is a cover of what it sweeps then, so two vehicles
whose hulls over overlapping times do not touch cannot touch at any instant, not only at
samples. A :class:`Swept` holds a motion's hulls ready for the reservation table's batched
queries: each hull's times, bounding box and grid cells.
"""

from __future__ import annotations

import functools
import math
import operator
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from lotsim.core.geometry import FloatArray
from lotsim.traffic.grid import EPS, Cells, cells_of_all
from lotsim.traffic.settings import SearchSettings
from lotsim.vehicles.model import VehicleType
from lotsim.vehicles.motion import Motion, Profile, Stroke

_DEFAULT = SearchSettings()

Interval = tuple[float, float, BaseGeometry]
"""A body held from ``t0`` to ``t1`` [s]."""


def chunk_edges(t0: float, t1: float, chunk: float = _DEFAULT.chunk) -> FloatArray:
    """Boundaries of the chunks ``[t0, t1]`` is cut into, none longer than ``chunk`` [s]."""
    n = max(1, math.ceil((t1 - t0) / chunk - 1e-9))
    return np.linspace(t0, t1, n + 1)


def swept(poses: FloatArray, times: FloatArray, vehicle: VehicleType, *,
          chunk: float = _DEFAULT.chunk) -> list[Interval]:
    """Hulls of the footprints at ``poses`` (N, 3) sampled at ``times`` (N,) [s], one per
    chunk of at most ``chunk`` seconds: ``[(t0, t1, hull), ...]``.

    The samples must include the chunk boundaries (:func:`chunk_edges`; missing
    ones are interpolated linearly) and be dense enough that consecutive
    footprints cover the swept area's bulge (a few millimetres at 0.2 m steps
    on the tightest arc).
    """
    times = np.asarray(times, dtype=float)
    poses = np.asarray(poses, dtype=float)
    if len(times) == 1 or times[-1] - times[0] <= 0:
        body = shapely.Polygon(vehicle.footprints(poses[:1])[0])
        return [(float(times[0]), float(times[-1]), body)]
    edges = chunk_edges(float(times[0]), float(times[-1]), chunk)
    missing = edges[~np.isin(edges, times)]
    if missing.size:
        theta = np.unwrap(poses[:, 2])
        extra = np.column_stack([np.interp(missing, times, poses[:, 0]),
                                 np.interp(missing, times, poses[:, 1]),
                                 np.interp(missing, times, theta)])
        order = np.argsort(np.concatenate([times, missing]), kind="stable")
        times = np.concatenate([times, missing])[order]
        poses = np.concatenate([np.column_stack([poses[:, :2], theta]), extra])[order]
    n = len(edges) - 1
    # chunk i takes the samples in [edges[i], edges[i+1]]; boundary samples belong to both
    lo = np.searchsorted(times, edges[:-1] - EPS, side="left")
    hi = np.searchsorted(times, edges[1:] + EPS, side="right")
    idx = np.concatenate([np.arange(a, b) for a, b in zip(lo, hi, strict=True)])
    owner = np.repeat(np.arange(n), hi - lo)
    pts = vehicle.footprints(poses[idx]).reshape(-1, 2)
    # hulls of linestrings through the corners: cheaper to build than of multipoints
    hulls = shapely.convex_hull(shapely.linestrings(pts, indices=np.repeat(owner, 4)))
    return [(float(edges[i]), float(edges[i + 1]), hulls[i]) for i in range(n)]


def swept_motion(motion: Motion, vehicle: VehicleType, *, chunk: float = _DEFAULT.chunk,
                 sample: float = _DEFAULT.sample) -> list[Interval]:
    """:func:`swept` for a timed motion, in the motion's own time (from 0) [s], with its
    footprints at most ``sample`` metres apart along curves (at the vehicle's top speed)."""
    edges = chunk_edges(0.0, motion.duration, chunk)
    if all(g.curvature == 0 and g.sharpness == 0 for st in motion.strokes for g in st.segments):
        # along straights the hull of the ends is the exact sweep
        tau = np.union1d(edges, motion.cusps)
    else:
        top = max(vehicle.limits.max_forward_speed, vehicle.limits.max_reverse_speed)
        tau = np.union1d(motion.times(sample / top), edges)
    poses = motion.at(tau, wheelbase=vehicle.wheelbase)[0]
    return swept(poses, tau, vehicle, chunk=chunk)


def swept_motions(motions: Sequence[Motion], vehicle: VehicleType, *,
                  chunk: float = _DEFAULT.chunk, sample: float = _DEFAULT.sample
                  ) -> list[Swept]:
    """:func:`swept_motion` of each of ``motions``, as :class:`Swept`.

    Motions that drive the same straight path in one stroke (one lane edge between
    different speeds) are done together, each step one numpy call for all of them: the
    same numbers, element by element, at a fraction of the cost per motion.
    """
    first = motions[0].phases if motions else ()
    if not (first and all(len(m.phases) == 1 and isinstance(m.phases[0], Stroke)
                          and m.phases[0].segments == first[0].segments and m.duration > 0
                          for m in motions)
            and all(g.curvature == 0 and g.sharpness == 0 for g in first[0].segments)):
        return [Swept.of(swept_motion(m, vehicle, chunk=chunk, sample=sample))
                for m in motions]
    # as swept_motion and swept do for each: samples at the chunk edges only (along
    # straights the hull of the ends is the exact sweep), each chunk the hull of the
    # footprints at its two ends
    edges, s, spans = zip(*(_chunk_samples(m.phases[0].profile, chunk) for m in motions),
                          strict=True)
    s = np.concatenate(s)
    pts = vehicle.footprints(first[0].poses(s)[0])
    # chunk i of a motion takes its samples i and i + 1 (a motion's samples start after the
    # previous motion's): the indices as a Python list, a few motions' worth
    idx: list[int] = []
    start = 0
    for e in edges:
        for i in range(start, start + len(e) - 1):
            idx += (i, i + 1)
        start += len(e)
    # one linestring of 8 corners a chunk: as an (N, 8, 2) array, not by indices (the
    # same points, several times quicker to build)
    hulls = shapely.convex_hull(shapely.linestrings(pts[idx].reshape(-1, 8, 2)))
    bounds = shapely.bounds(hulls)
    cells = cells_of_all(bounds)
    out = []
    c = 0
    for e, span in zip(edges, spans, strict=True):
        k = len(e) - 1
        b = bounds[c: c + k]
        # rows share their times' float objects with every hull of the profile
        out.append(Swept(hulls[c: c + k], cells[c: c + k],
                         tuple((*ab, *xy) for ab, xy in zip(span, b.tolist(), strict=True))))
        c += k
    return out


@functools.lru_cache(maxsize=1 << 14)
def _chunk_samples(profile: Profile, chunk: float
                   ) -> tuple[FloatArray, FloatArray, tuple[tuple[float, float], ...]]:
    """A profile's chunk edges [s], path lengths there [m] and each chunk's ``(t0, t1)``
    (kept: profiles are shared by every edge of a length driven between the same
    speeds)."""
    edges = chunk_edges(0.0, profile.duration, chunk)
    s = profile.at(edges)[0]
    edges.flags.writeable = s.flags.writeable = False
    e = edges.tolist()
    return edges, s, tuple(zip(e[:-1], e[1:], strict=True))


@dataclass(frozen=True, slots=True)
class Swept:
    """Intervals for batched queries: hulls (N,), each one's grid cells, and each one's
    times and bounds as rows of Python floats; :attr:`t` (N, 2) [s] and :attr:`bounds`
    (N, 4) [m] as arrays, made from the rows when asked.

    (Slots, and no arrays of times and bounds kept: a run keeps one for every edge motion
    it has checked, some 60 000 for 1000 cars on the large lot, and the searches read the
    rows.)"""

    geoms: np.ndarray
    cells: tuple[Cells, ...] = ()
    rows: tuple[tuple[float, ...], ...] = ()
    """Each interval's ``(t0, t1, x0, y0, x1, y1)`` as Python floats (for loops over a few
    pairs, where numpy's fixed cost per call is more than the work)."""

    @classmethod
    def of(cls, intervals: Sequence[Interval]) -> Swept:
        geoms = np.empty(len(intervals), dtype=object)
        geoms[:] = [g for _, _, g in intervals]
        t = np.array([(a, b) for a, b, _ in intervals], dtype=float).reshape(-1, 2)
        bounds = shapely.bounds(geoms).reshape(-1, 4)
        return cls(geoms, cells_of_all(bounds),
                   tuple(map(tuple, np.hstack([t, bounds]).tolist())))

    @property
    def t(self) -> np.ndarray:
        """(N, 2) each interval's start and end [s] (the rows' floats)."""
        return np.array([r[:2] for r in self.rows], dtype=float).reshape(-1, 2)

    @property
    def bounds(self) -> np.ndarray:
        """(N, 4) each hull's ``(x0, y0, x1, y1)`` [m] (the rows' floats)."""
        return np.array([r[2:] for r in self.rows], dtype=float).reshape(-1, 4)

    extent: tuple[float, ...] = field(init=False, repr=False, compare=False)
    """``(t0, t1, x0, y0, x1, y1)`` of all the intervals together: the earliest start and
    latest end [s], and the box holding every hull [m] (empty with no intervals)."""
    in_order: bool = field(init=False, repr=False, compare=False)
    """Whether the intervals' starts and their ends each never decrease (a motion's chunks
    do)."""

    def __post_init__(self) -> None:
        # the rows' columns (zip in C), each reduced by min or max and compared with itself
        # one step on: the same floats and answers as pair by pair, for the ~60 000 made
        a, z, x0, y0, x1, y1 = zip(*self.rows, strict=True) if self.rows else ((),) * 6
        extent = (min(a), max(z), min(x0), min(y0), max(x1), max(y1)) if a else ()
        object.__setattr__(self, "extent", extent)
        object.__setattr__(self, "in_order", all(map(operator.le, a, a[1:]))
                           and all(map(operator.le, z, z[1:])))

    def __len__(self) -> int:
        return len(self.geoms)

    def __iter__(self):
        for r, g in zip(self.rows, self.geoms, strict=True):
            yield r[0], r[1], g


def standing_body(vehicle: VehicleType, pose: FloatArray) -> BaseGeometry:
    """The footprint polygon of ``vehicle`` standing at ``pose``."""
    return shapely.Polygon(vehicle.footprints(np.asarray(pose, dtype=float)[None, :])[0])

