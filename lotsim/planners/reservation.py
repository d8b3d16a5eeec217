"""The reservation table: where every planned vehicle is, step by step in time.

Time is cut into steps of ``dt`` seconds. A vehicle that moves during step ``k``
(the interval ``[k·dt, (k+1)·dt]``) reserves the convex hull of its footprints
over that interval — a conservative cover of its swept area, so two vehicles
whose reservations do not touch cannot touch at any instant of the step, not
only at the samples. A parked vehicle reserves its footprint from the step it
arrives in onward, for ever.

Queries ask whether a set of per-step bodies is free, ignoring one owner (the
vehicle being replanned). Each step's reservations sit in a
:class:`shapely.STRtree`, rebuilt lazily when the step changes.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from lotsim.geometry import FloatArray
from lotsim.trajectory import Trajectory
from lotsim.vehicles.model import VehicleType


@dataclass(frozen=True, slots=True)
class Conflict:
    """A clash with an existing reservation: at ``step``, with ``owner``."""

    step: int
    owner: str


def swept_by_step(trajectory: Trajectory, vehicle: VehicleType, dt: float
                  ) -> dict[int, BaseGeometry]:
    """Step → hull of the vehicle's footprints over that step [m].

    The pose at each step boundary is interpolated (linearly between samples, a
    cover the hull absorbs), so each step's hull includes where the vehicle is
    when the step begins and ends.
    """
    t = trajectory.t
    poses = trajectory.poses
    k0 = math.floor(t[0] / dt + 1e-9)
    k1 = max(k0, math.ceil(t[-1] / dt - 1e-9) - 1)
    bounds = np.arange(k0, k1 + 2) * dt
    inner = bounds[(bounds > t[0]) & (bounds < t[-1])]
    extra = np.column_stack([np.interp(inner, t, poses[:, 0]), np.interp(inner, t, poses[:, 1]),
                             np.interp(inner, t, np.unwrap(poses[:, 2]))])
    all_t = np.concatenate([t, inner])
    all_p = np.concatenate([poses, extra])
    order = np.argsort(all_t, kind="stable")
    all_t, all_p = all_t[order], all_p[order]
    bodies = vehicle.footprints(all_p)
    out: dict[int, BaseGeometry] = {}
    for k in range(k0, k1 + 1):
        lo, hi = k * dt, (k + 1) * dt
        sel = (all_t >= lo - 1e-9) & (all_t <= hi + 1e-9)
        if not sel.any():
            continue
        out[k] = shapely.convex_hull(shapely.multipoints(bodies[sel].reshape(-1, 2)))
    return out


class ReservationTable:
    """Space-time reservations of vehicles' bodies.

    Parameters
    ----------
    dt : float
        Length of a time step [s].

    Examples
    --------
    >>> from shapely.geometry import box
    >>> table = ReservationTable(dt=0.5)
    >>> table.reserve_steps("a", {0: box(0, 0, 2, 2), 1: box(1, 0, 3, 2)})
    >>> table.first_conflict({1: box(2.5, 0, 4, 1)}), table.first_conflict({0: box(2.5, 0, 4, 1)})
    (Conflict(step=1, owner='a'), None)
    """

    def __init__(self, dt: float = 0.5):
        if not dt > 0:
            raise ValueError("dt must be positive")
        self.dt = dt
        self._steps: dict[int, list[tuple[str, BaseGeometry]]] = defaultdict(list)
        self._trees: dict[int, tuple[shapely.STRtree, list[str]]] = {}
        self._parked: list[tuple[str, int, BaseGeometry]] = []
        self._parked_tree: tuple[shapely.STRtree, np.ndarray, list[str]] | None = None

    # -- reserving ----------------------------------------------------------------------------
    def reserve_steps(self, owner: str, bodies: dict[int, BaseGeometry]) -> None:
        """Reserve ``bodies`` (step → geometry) for ``owner``."""
        for k, geom in bodies.items():
            self._steps[k].append((owner, geom))
            self._trees.pop(k, None)

    def reserve_trajectory(self, owner: str, trajectory: Trajectory, vehicle: VehicleType,
                           *, park: bool = False) -> None:
        """Reserve what ``vehicle`` sweeps along ``trajectory``; with ``park``, also its
        final footprint from the last step on, for ever."""
        self.reserve_steps(owner, swept_by_step(trajectory, vehicle, self.dt))
        if park:
            end = shapely.Polygon(vehicle.footprints(trajectory.poses[-1:])[0])
            self.reserve_parked(owner, end, trajectory.end_time)

    def reserve_parked(self, owner: str, body: BaseGeometry, since: float = 0.0) -> None:
        """A body standing from time ``since`` [s] on, for ever (a parked car)."""
        self._parked.append((owner, math.floor(since / self.dt + 1e-9), body))
        self._parked_tree = None

    def release(self, owner: str, *, after: float | None = None) -> None:
        """Drop ``owner``'s reservations (those of steps from ``after`` on, if given);
        a parked body then stands until ``after`` only."""
        k_after = -math.inf if after is None else math.floor(after / self.dt + 1e-9)
        for k in [k for k in self._steps if k >= k_after]:
            kept = [(o, g) for o, g in self._steps[k] if o != owner]
            if len(kept) != len(self._steps[k]):
                self._steps[k] = kept
                self._trees.pop(k, None)
        parked = [(o, s, g) for o, s, g in self._parked if o == owner]
        if parked:
            self._parked = [(o, s, g) for o, s, g in self._parked if o != owner]
            self._parked_tree = None
            if after is not None:
                for _, since, body in parked:
                    self.reserve_steps(owner, {k: body for k in range(since, int(k_after))})

    # -- asking -------------------------------------------------------------------------------
    def first_conflict(self, bodies: dict[int, BaseGeometry], *, ignore: str | None = None
                       ) -> Conflict | None:
        """The earliest step at which ``bodies`` (step → geometry) touch someone else's."""
        parked = self._parked_index()
        for k in sorted(bodies):
            geom = bodies[k]
            tree = self._tree(k)
            if tree is not None:
                for i in tree[0].query(geom, predicate="intersects"):
                    if tree[1][i] != ignore:
                        return Conflict(k, tree[1][i])
            if parked is not None:
                for i in parked[0].query(geom, predicate="intersects"):
                    if parked[1][i] <= k and parked[2][i] != ignore:
                        return Conflict(k, parked[2][i])
        return None

    def is_free(self, bodies: dict[int, BaseGeometry], *, ignore: str | None = None) -> bool:
        return self.first_conflict(bodies, ignore=ignore) is None

    def owners(self) -> set[str]:
        return {o for items in self._steps.values() for o, _ in items} | {
            o for o, _, _ in self._parked}

    def _tree(self, k: int) -> tuple[shapely.STRtree, list[str]] | None:
        items = self._steps.get(k)
        if not items:
            return None
        if k not in self._trees:
            self._trees[k] = (shapely.STRtree([g for _, g in items]), [o for o, _ in items])
        return self._trees[k]

    def _parked_index(self) -> tuple[shapely.STRtree, np.ndarray, list[str]] | None:
        if not self._parked:
            return None
        if self._parked_tree is None:
            self._parked_tree = (shapely.STRtree([g for _, _, g in self._parked]),
                                 np.array([s for _, s, _ in self._parked]),
                                 [o for o, _, _ in self._parked])
        return self._parked_tree


def bodies_at_rest(vehicle: VehicleType, pose: FloatArray, steps: Iterable[int]
                   ) -> dict[int, BaseGeometry]:
    """The same standing footprint for each of ``steps``."""
    body = shapely.Polygon(vehicle.footprints(np.asarray(pose)[None, :])[0])
    return {k: body for k in steps}
