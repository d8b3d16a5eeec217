"""Is a swept footprint free? A validity checker over a lot's fixed obstacles."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from lotsim.core.geometry import FloatArray
from lotsim.core.keys import inputs, key_of, unordered


@dataclass(frozen=True, slots=True)
class Hit:
    """The first place along a sweep where the body is not free."""

    index: int  # index of the first offending sample pair
    what: str  # label of what was hit, or the collider's edge ("the lot boundary")
    point: tuple[float, float]  # a point of the offending body [m]


@inputs
class CheckedAround:
    """What a check of a body inside a box reads (:meth:`Collider.around`): what a body
    leaving the allowed region runs into, the obstacles whose bounds meet the box in the
    tree's order (a hit names the first) with their labels and shapes (WKB), and the
    allowed region cut at the box (WKB, normalized)."""

    edge: str
    labels: tuple[str, ...]
    shapes: tuple[bytes, ...]
    allowed: bytes | None


@inputs
class SeenAround:
    """What a check of a body inside a box reads, seen from a frame to the micrometre
    (:meth:`Collider.local_digest`): the allowed region and the obstacles (a set), each cut
    at the box (WKB, normalized); what an obstacle is called left out."""

    allowed: bytes
    obstacles: tuple[bytes, ...]


def hulls(bodies: FloatArray, convex: bool = False) -> np.ndarray:
    """The hull of each body (N, K, 2 points): as it is when a footprint (K = 4, a
    rectangle's corners in order) or ``convex`` (rings already convex, in order, as
    :class:`RigidSweeps` places them), else made (:func:`shapely.convex_hull`, three times
    dearer)."""
    if convex or bodies.shape[1] == 4:
        return shapely.polygons(bodies)
    return shapely.convex_hull(shapely.linestrings(bodies))


def hulls_blocked(hulls: np.ndarray, allowed: BaseGeometry, tree: shapely.STRtree
                  ) -> np.ndarray:
    """Boolean mask of the ``hulls`` not inside ``allowed`` (prepared) or meeting something
    in ``tree`` (queried only for those inside)."""
    bad = ~shapely.covers(allowed, hulls)
    free = np.flatnonzero(~bad)
    bad[free[tree.query(hulls[free], predicate="intersects")[0]]] = True
    return bad


class Collider:
    """Checks bodies against fixed obstacles (an :class:`shapely.STRtree`) and an allowed region.

    Parameters
    ----------
    obstacles : list of (label, geometry)
        What a body must not touch.
    allowed : geometry
        The region a body must stay inside.
    edge : str
        What a body leaving ``allowed`` runs into, for messages.
    """

    def __init__(self, obstacles: list[tuple[str, BaseGeometry]], allowed: BaseGeometry,
                 *, edge: str = "the lot boundary"):
        self.labels = [label for label, _ in obstacles]
        self.edge = edge
        self.tree = shapely.STRtree([g for _, g in obstacles])
        self.allowed = allowed
        shapely.prepare(self.allowed)

    def blocked(self, bodies: FloatArray, convex: bool = False) -> np.ndarray:
        """Boolean mask of the ``bodies`` (N, K, 2 point sets, taken as hulls; ``convex``:
        convex rings already, see :func:`hulls`) that are not free."""
        return hulls_blocked(hulls(bodies, convex), self.allowed, self.tree)

    def around(self, box: tuple[float, float, float, float]) -> bytes:
        """A digest of all that a check of a body lying inside ``box`` (x min, y min, x max,
        y max) reads: the obstacles whose bounds meet the box, with their labels, in the
        tree's order (a hit names the first), and the allowed region within the box. Two
        colliders with equal digests for a box answer every check inside it alike."""
        return self.around_many([box])[0]

    def around_many(self, boxes: Sequence[tuple[float, float, float, float]]
                    ) -> list[bytes]:
        """:meth:`around` of each of ``boxes``, the shapes of all of them cut at once."""
        out = [key_of(CheckedAround(self.edge, (), (), None))] * len(boxes)
        read = [i for i, b in enumerate(boxes) if b[0] <= b[2] and b[1] <= b[3]]
        if read:  # (an empty box: nothing was checked)
            areas = shapely.box(*np.array([boxes[i] for i in read], dtype=float).T)
            of, at = self.tree.query(areas)
            order = np.lexsort((at, of))
            of, at = of[order], at[order]
            seen = np.unique(at)
            wkb = dict(zip(seen.tolist(), shapely.to_wkb(self.tree.geometries.take(seen)),
                           strict=True))
            cuts = shapely.to_wkb(shapely.normalize(shapely.intersection(self.allowed, areas)))
            ends = np.searchsorted(of, np.arange(len(read) + 1))
            for j, i in enumerate(read):
                mine = at[ends[j]:ends[j + 1]].tolist()
                out[i] = key_of(CheckedAround(self.edge, tuple(self.labels[k] for k in mine),
                                              tuple(wkb[k] for k in mine), cuts[j]))
        return out

    def local_digest(self, frame: tuple[float, float, float],
                     box: tuple[float, float, float, float]) -> bytes:
        """A digest of what a check of a body inside ``box`` (x min, y min, x max, y max in
        ``frame``: origin x, y [m], heading [rad]) reads, seen from ``frame`` to the
        micrometre: the obstacles and the allowed region cut at the box. Two places of one
        lot (or two lots) with equal digests hold the same shapes about them, so bodies
        placed alike in each are found free alike (but at a micrometre's noise). What an
        obstacle is called is left out."""
        ox, oy, heading = frame
        c, s = math.cos(heading), math.sin(heading)
        x0, y0, x1, y1 = box
        region = shapely.Polygon([(ox + c * x - s * y, oy + s * x + c * y)
                                  for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))])
        near = self.tree.geometries.take(self.tree.query(region, predicate="intersects"))
        cut = shapely.intersection(np.append(near, self.allowed), region)

        def seen(xy: FloatArray) -> FloatArray:
            dx, dy = xy[:, 0] - ox, xy[:, 1] - oy
            return np.round(np.column_stack([c * dx + s * dy, c * dy - s * dx]), 6) + 0.0

        wkb = shapely.to_wkb(shapely.normalize(shapely.transform(cut, seen))).tolist()
        return key_of(SeenAround(wkb[-1], unordered(wkb[:-1])))

    @staticmethod
    def sweeps(footprints: FloatArray) -> FloatArray:
        """Point sets (N-1, 8, 2) of consecutive footprint pairs: their hulls cover the sweep."""
        if len(footprints) == 1:
            return footprints
        return np.concatenate([footprints[:-1], footprints[1:]], axis=1)

    def first_hit(self, bodies: FloatArray) -> Hit | None:
        """The first of ``bodies`` (N, K, 2 rings or hull point sets) that is not free."""
        if len(bodies) == 0:
            return None
        bad = np.flatnonzero(self.blocked(bodies))
        if not bad.size:
            return None
        i = int(bad[0])
        poly = shapely.convex_hull(shapely.linestrings(bodies[i]))
        if not self.allowed.covers(poly):
            what = self.edge
        else:
            what = self.labels[int(self.tree.query(poly, predicate="intersects")[0])]
        c = poly.centroid
        return Hit(i, what, (float(c.x), float(c.y)))

    def sweep_hit(self, footprints: FloatArray) -> Hit | None:
        """First hit of the hulls of consecutive footprints (N, 4, 2): a sweep, not just samples.

        The hull of two consecutive rectangles covers a straight motion
        exactly and an arc up to its sagitta (about 1 mm at 0.2 m steps).
        """
        return self.first_hit(self.sweeps(footprints))


NOTHING_READ = (math.inf, math.inf, -math.inf, -math.inf)
"""The :attr:`Watched.box` of checks that checked no body."""


class Watched(Collider):
    """``collider``'s checks, noting the box every body checked lies in (:attr:`box`):
    what an answer worked out with it can depend on (:meth:`Collider.around`)."""

    def __init__(self, collider: Collider):
        self.__dict__.update(collider.__dict__)
        self.box = NOTHING_READ

    def blocked(self, bodies: FloatArray, convex: bool = False) -> np.ndarray:
        if len(bodies):
            pts = np.asarray(bodies).reshape(-1, 2)
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            x0, y0, x1, y1 = self.box
            self.box = (min(x0, float(lo[0])), min(y0, float(lo[1])),
                        max(x1, float(hi[0])), max(y1, float(hi[1])))
        return super().blocked(bodies, convex)


def first_blocked(blocked: Callable[[FloatArray], np.ndarray], prints: FloatArray,
                  run: np.ndarray, span: int = 2, block: int = 4) -> np.ndarray:
    """Bodies made of ``span`` consecutive footprints (``prints`` (N, K, 2)): body ``i``
    the hull of footprints ``i .. i + span - 1`` (span 2: the sweep between two
    footprints; span 1: a footprint) belongs to run ``run[i]`` (``run`` (N - span + 1,)
    ints: a path, a stroke, its bodies in order; < 0: not asked). True at the first body
    that ``blocked`` (bodies (M, P, 2) → (M,) bool, each taken as its hull) finds not free
    in each run, False everywhere else: what a path's check (is any body blocked?) and a
    stroke's extent (where is the first?) need.

    Coarse to fine, with the same answers as checking every body: ``block`` bodies are
    checked first as the hull of all their footprints, which holds each body, so a free
    block has every body free; the bodies of a run's blocked blocks are then checked one by
    one, in order, until one is blocked.
    """
    out = np.zeros(len(run), dtype=bool)
    asked = np.flatnonzero(run >= 0)
    if not asked.size:
        return out
    # blocks: each stretch of consecutive bodies of a run cut into pieces block long
    at = np.arange(len(asked))
    new_run = np.ones(len(asked), dtype=bool)
    new_run[1:] = run[asked[1:]] != run[asked[:-1]]
    new_piece = new_run.copy()
    new_piece[1:] |= asked[1:] != asked[:-1] + 1
    piece_start = np.maximum.accumulate(np.where(new_piece, at, 0))
    first = np.flatnonzero(new_piece | ((at - piece_start) % block == 0))
    last = np.append(first[1:], len(asked)) - 1  # in ``asked``
    a, b = asked[first], asked[last] + 1  # bodies a..b-1 of each block
    idx = np.minimum(a[:, None] + np.arange(block + span - 1)[None, :],
                     b[:, None] + span - 2)  # their footprints
    bad = np.flatnonzero(blocked(prints[idx].reshape(len(a), -1, 2)))
    if not bad.size:
        return out
    of = (np.cumsum(new_run) - 1)[first[bad]]  # the run of each blocked block, in order
    rank = np.arange(len(bad)) - np.searchsorted(of, of)  # its place in its run
    done = np.zeros(int(of.max(initial=-1)) + 1, dtype=bool)
    for r in range(int(rank.max(initial=-1)) + 1):
        blocks = bad[(rank == r) & ~done[of]]
        if not blocks.size:
            break
        size = last[blocks] - first[blocks] + 1  # asked bodies in each
        owner = np.repeat(np.arange(len(blocks)), size)
        fine = asked[first[blocks][owner] + np.arange(len(owner))
                     - np.repeat(np.cumsum(size) - size, size)]
        hit = (blocked(np.concatenate([prints[fine + k] for k in range(span)], axis=1))
               if (size > 1).any() else np.ones(len(fine), dtype=bool))  # one: known
        found = np.flatnonzero(hit)
        found = found[np.flatnonzero(np.diff(owner[found], prepend=-1))]  # first per block
        out[fine[found]] = True
        done[of[np.searchsorted(bad, blocks[owner[found]])]] = True
    return out


class RigidSweeps:
    """A body's sweeps along fixed motions from the origin pose, as :func:`first_blocked`
    checks them, made once: the hull of each pair of consecutive footprints and of each
    block of ``block`` pairs, as convex rings in the frame of the motions' start.

    The same motions driven from any pose sweep these rings moved rigidly, so checking them
    from many poses (a search's states, the strokes of a shuffle) places rings instead of
    making footprints and hulls again each time: the answers are those of
    :func:`first_blocked` (but at a rounding's noise in the coordinates).

    Parameters
    ----------
    footprints : sequence of (n_r + 1, K, 2) arrays
        The footprints along each motion ``r`` from the origin pose, in order.
    block : int
        Sweeps a block holds (:func:`first_blocked`'s ``block``).
    """

    def __init__(self, footprints: Sequence[FloatArray], block: int = 4):
        self.counts = np.array([len(f) - 1 for f in footprints])  # sweeps of each motion
        fine, coarse, motion, first, last = [], [], [], [], []
        at = 0
        for r, prints in enumerate(footprints):
            n = len(prints) - 1
            fine += [np.concatenate([prints[i], prints[i + 1]]) for i in range(n)]
            for a in range(0, n, block):
                b = min(a + block, n)  # sweeps a..b-1: footprints a..b
                coarse.append(prints[a:b + 1].reshape(-1, 2))
                motion.append(r)
                first.append(at + a)
                last.append(at + b)
            at += n
        self.fine = _convex_rings(fine)
        self.coarse = _convex_rings(coarse)
        self.motion = np.array(motion, dtype=int)  # the motion of each block
        self.first = np.array(first, dtype=int)  # its fine sweeps first .. last - 1
        self.last = np.array(last, dtype=int)
        self.start = np.concatenate([[0], np.cumsum(self.counts)[:-1]])  # each motion's first

    def first_blocked(self, blocked: Callable[..., np.ndarray], poses: FloatArray
                      ) -> np.ndarray:
        """(P, R) ints: for each pose of ``poses`` (P, 3) and each motion driven from it, the
        index of its first sweep ``blocked`` (rings (N, K, 2) → (N,) bool, called with
        ``convex=True``) finds not free, or its count of sweeps when none is."""
        poses = np.atleast_2d(np.asarray(poses, dtype=float))
        n_poses, n_blocks = len(poses), len(self.coarse)
        out = np.tile(self.counts, (n_poses, 1))
        if not n_poses:
            return out
        rings = _placed(np.broadcast_to(self.coarse, (n_poses, *self.coarse.shape)), poses)
        bad = np.flatnonzero(blocked(rings.reshape(-1, *self.coarse.shape[1:]), convex=True))
        if not bad.size:
            return out
        at, block = np.divmod(bad, n_blocks)
        run = at * len(self.counts) + self.motion[block]  # in order, blocks in order in each
        rank = np.arange(len(bad)) - np.searchsorted(run, run)
        done = np.zeros(n_poses * len(self.counts), dtype=bool)
        for r in range(int(rank.max()) + 1):
            now = np.flatnonzero((rank == r) & ~done[run])
            if not now.size:
                break
            size = self.last[block[now]] - self.first[block[now]]
            owner = np.repeat(now, size)
            fine = self.first[block[owner]] + np.arange(len(owner)) - np.repeat(
                np.cumsum(size) - size, size)
            hit = blocked(_placed(self.fine[fine], poses[at[owner]]), convex=True)
            found = np.flatnonzero(hit)
            found = found[np.flatnonzero(np.diff(owner[found], prepend=-1))]  # first of each
            who = owner[found]
            out[at[who], self.motion[block[who]]] = (
                fine[found] - self.start[self.motion[block[who]]])
            done[run[who]] = True
        return out


def _convex_rings(point_sets: Sequence[FloatArray]) -> FloatArray:
    """The hull of each point set as a closed ring, all padded to one length with their
    closing point: (N, K, 2)."""
    sizes = [len(x) for x in point_sets]
    hull = shapely.convex_hull(shapely.multipoints(
        np.concatenate(point_sets), indices=np.repeat(np.arange(len(sizes)), sizes)))
    xy, of = shapely.get_coordinates(shapely.get_exterior_ring(hull), return_index=True)
    size = np.bincount(of, minlength=len(point_sets))
    out = np.empty((len(point_sets), int(size.max()), 2))
    ends = np.cumsum(size)
    for i in range(len(point_sets)):
        ring = xy[ends[i] - size[i]:ends[i]]
        out[i, :len(ring)] = ring
        out[i, len(ring):] = ring[-1]
    return out


def _placed(rings: FloatArray, poses: FloatArray) -> FloatArray:
    """Rings ``rings[i]`` (N, ..., 2, in a pose's frame) placed at ``poses[i]`` (N, 3)."""
    shape = (-1,) + (1,) * (rings.ndim - 2)
    c, s = np.cos(poses[:, 2]).reshape(shape), np.sin(poses[:, 2]).reshape(shape)
    x, y = rings[..., 0], rings[..., 1]
    return np.stack([poses[:, 0].reshape(shape) + c * x - s * y,
                     poses[:, 1].reshape(shape) + s * x + c * y], axis=-1)
