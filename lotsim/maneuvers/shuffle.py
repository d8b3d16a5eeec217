"""The way into a perpendicular or angled slot, searched outward from the parked pose.

The car is parked centred in the slot, nose-in or nose-out. The search works *outward* from
the parked pose (the departure, which is the constrained end): drive out straight some
distance, then shuffle — full lock turning toward the lane's heading until the next motion
would touch something, the other gear with the opposite lock (which keeps turning the same
way), and so on, as a driver does in a narrow aisle. From every probe spacing of every
stroke it tries an exact closing move onto the lane (:mod:`~lotsim.maneuvers.closing`). The
fewest direction changes wins, then the shortest path; the parking maneuver is that path
reversed in time. A corner bay where the strokes must not all be at full lock falls back to
a multi-point search (:func:`any_way_out`).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np

from lotsim.core.geometry import FloatArray, Pose, Segment, advance, wrap_angle
from lotsim.core.outcome import Outcome, Status
from lotsim.lot.clearance import RigidSweeps
from lotsim.lot.model import unit
from lotsim.maneuvers.closing import closing_segments, closings, first_clear, park_path
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.maneuvers.validity import LocalChecks, Validity
from lotsim.roadmap.multipoint import plan_onto
from lotsim.vehicles.model import VehicleType

STROKE_BLOCK = 8
"""Sweeps of a stroke checked first as one hull (:class:`~lotsim.lot.clearance.RigidSweeps`):
what finds how far a lot's strokes run quickest; the answers are the same for any."""


def park_across(checks: Validity, style: str, settings: ManeuverSettings, *,
                fewer_than: int | None = None
                ) -> Outcome[tuple[tuple[Segment, ...], float]]:
    """The parking maneuver into a perpendicular or angled slot (local frame) and the local
    x where it starts: the way out of the parked pose (:func:`shuffle`, nose-in and
    nose-out as ``style`` allows; the fewest direction changes, then the shortest), else
    :func:`any_way_out`, driven backwards in time. With ``fewer_than``, only a way out of
    the shuffle with fewer direction changes than that (the same answer as without, when
    it has fewer), else NO_PATH."""
    p = checks.problem
    v, s = p.vehicle, p.slot
    heading_in = float(p.frame.poses_to_local(np.array([0.0, 0.0, s.heading]))[0, 2])
    centre = p.frame.points_to_local(np.asarray(s.center))
    best = None
    for nose_in in (True, False):
        if style == ("reverse" if nose_in else "forward"):
            continue
        h = heading_in if nose_in else heading_in + math.pi
        axle = centre - unit(h) * (v.front - v.rear) / 2
        root = (float(axle[0]), float(axle[1]), float(wrap_angle(h)))
        if checks.poses_blocked(np.array([root]))[0]:
            continue
        # leave-time: a nose-in car backs out, a nose-out car drives out
        bound = best[:2] if best else (None if fewer_than is None else (fewer_than, 0.0))
        found = shuffle(checks, root, -1 if nose_in else 1, settings, bound=bound)
        if found.found and (best is None or found.value[:2] < best[:2]):
            best = found.value
    if best is not None:
        return Outcome.of(park_path(best[2]))
    if fewer_than is not None:
        return Outcome.failed(Status.NO_PATH, f"no way out with fewer than {fewer_than} "
                              "direction changes at full lock")
    way_out = any_way_out(checks, style, heading_in, settings,
                          axle_of=lambda h: centre - unit(h) * (v.front - v.rear) / 2)
    if not way_out.found:
        return Outcome.failed(Status.NO_PATH, (
            f"no way out with up to {settings.max_changes} direction changes "
            f"keeping {settings.margin:g} m from the neighbours and the aisle's far side"))
    return Outcome.of(park_path(way_out.value))


def any_way_out(checks: Validity, style: str, heading_in: float, settings: ManeuverSettings,
                *, axle_of: Callable[[float], FloatArray]) -> Outcome[list[Segment]]:
    """The way out of a perpendicular or angled slot when the full-lock shuffle finds none
    (a corner bay against a closed end, where the strokes must not all be at full lock): a
    multi-point search over arcs and straights in either gear
    (:func:`~lotsim.roadmap.multipoint.plan_onto`) from the parked pose, nose-in or nose-out
    as ``style`` allows, onto the lane within its reachable stretch, inside the same window
    and clear of the same obstacles, tuned by ``settings.way_out`` (with at most
    ``settings.max_changes`` direction changes);
    in leave-time, local frame. ``axle_of(heading)``: the rear-axle centre of the car
    parked at that heading."""
    p = checks.problem
    roots = []
    for nose_in in (True, False):
        if style == ("reverse" if nose_in else "forward"):
            continue
        h = heading_in if nose_in else heading_in + math.pi
        axle = axle_of(h)
        root = (float(axle[0]), float(axle[1]), float(wrap_angle(h)))
        if not checks.poses_blocked(np.array([root]))[0]:
            roots.append(root)
    if not roots:
        return Outcome.failed(Status.INFEASIBLE, "the parked car would touch something")
    local = LocalChecks(checks)
    found = plan_onto(roots, (0.0, p.lane_y, 0.0), p.lane_x[0], p.lane_x[1], local, local,
                      p.vehicle.min_turning_radius, settings=settings.way_out,
                      max_changes=min(settings.max_changes, settings.way_out.max_changes))
    if not found.found:
        return Outcome.failed(Status.NO_PATH, "no multi-point way out within the budget")
    return Outcome.of(list(found.value[1]))


def shuffle(checks: Validity, root: Pose, gear0: int, settings: ManeuverSettings, *,
            bound: tuple[int, float] | None = None
            ) -> Outcome[tuple[int, float, list[Segment]]]:
    """The way out of a perpendicular or angled slot from the parked pose ``root``, in
    leave-time, as (direction changes, length, pieces).

    Drive out straight in ``gear0`` for ``d0`` (every probe spacing up to the first
    contact), then shuffle: full lock turning toward the lane heading until contact, the
    other gear with the opposite lock (which keeps turning the same way), and so on. From
    every probe spacing of every stroke try the closing move in either gear; the first
    level of direction changes with a clear closing gives the answer, the shortest at that
    level. With ``bound`` (changes, length), only a cheaper answer is looked for.
    """
    p = checks.problem
    kmax = p.vehicle.max_curvature
    theta = float(wrap_angle(root[2]))
    rho = -1.0 if theta > 0 else 1.0  # turn toward heading 0 the short way
    e0 = float(extents(checks, np.array([root]), gear0, 0.0, settings.sweep)[0])
    heads = []
    probe = settings.probe
    for d0 in np.arange(0.0, e0 + 1e-9, probe):
        segs = [Segment(root, gear0 * float(d0), 0.0)] if d0 > 0 else []
        heads.append((segs, segs[-1].end if segs else root, float(d0)))
    registry: list[tuple] = []  # per level: (heads, stops, poses, head of each pose)
    reached: dict[tuple[int, int], bool] = {}  # (level, stop) → the way there blocked

    def build(row: FloatArray) -> tuple[int, float, list[Segment]]:
        level, m = int(row[2]), int(row[3])
        close = (int(row[4]), float(row[5]), float(row[6]), float(row[7]))
        return int(row[0]), float(row[1]), way(registry, level, m) + closing_segments(
            tuple(map(float, registry[level][2][m])), close)

    pending = np.zeros((0, 8))  # rows: changes, length, level, m, gear, straight, κ, extend
    for k in range(settings.max_changes + 1):
        if bound is not None and k == bound[0] and bound[1] <= 0.0:
            break  # nothing at this level is cheaper
        g = gear0 if k % 2 == 0 else -gear0
        kappa = rho * g * kmax
        turn_cap = abs(theta) + settings.first_turn if k == 0 else math.pi / 2
        ends = (extents(checks, np.array([h[1] for h in heads]), g, kappa, settings.sweep,
                        turn_cap) if heads else np.zeros(0))
        stops = [np.unique(np.concatenate([np.arange(0.0, e, probe), [e]])) for e in ends]
        owner = np.repeat(np.arange(len(heads)), [len(st) for st in stops])
        flat = np.concatenate(stops) if stops else np.zeros(0)
        starts = np.array([h[1] for h in heads]).reshape(-1, 3)[owner]
        q = advance(starts, g * flat, kappa)
        base = np.array([h[2] for h in heads])[owner] + flat
        tab = closings(p, q, g, k, base, settings)
        registry.append((heads, flat, q, owner, g, kappa))
        table = np.concatenate([pending, np.column_stack(
            [tab[:, :2], np.full(len(tab), k), tab[:, 2:]])])
        now = table[:, 0] == k
        if bound is not None:
            now &= (table[:, 0] < bound[0]) | ((table[:, 0] == bound[0])
                                               & (table[:, 1] < bound[1]))
        level = table[now][np.argsort(table[now][:, 1], kind="stable")]
        pending = table[table[:, 0] > k]

        found = first_clear(checks, level[:settings.candidates], step=settings.rough,
                            build=build, rough=lambda rows: rough(checks, registry, rows,
                                                                  reached, settings.rough))
        if found is not None:
            return Outcome.of(found)
        if bound is not None and k >= bound[0]:
            break
        heads = []
        for (segs, pose, length), e in zip(registry[-1][0], ends, strict=True):
            if e >= settings.min_stroke:
                stroke = Segment(pose, g * float(e), kappa)
                heads.append((segs + [stroke], stroke.end, length + float(e)))
        if not heads and not len(pending):
            break
    return Outcome.failed(Status.NO_PATH, f"no way out with up to {settings.max_changes} "
                          "direction changes at full lock")


def rough(checks: Validity, registry: list[tuple], rows: FloatArray,
          reached: dict[tuple[int, int], bool], step: float) -> np.ndarray:
    """(R,) whether a footprint ``step`` apart along the path of each of :func:`shuffle`'s
    ``rows`` touches anything — what ``checks.paths_blocked(paths, step=step, sweep=False)``
    finds of the paths its ``build`` makes, without making them. A footprint lies on one
    piece of a path, so a path is blocked when a piece is: the way to each stop (the
    strokes before it and the part of its own up to it) is checked once a search
    (``reached``: (level, stop) → blocked), and the closing moves from the stops, in one
    batch."""
    level, m = rows[:, 2].astype(int), rows[:, 3].astype(int)
    stops = list(zip(level.tolist(), m.tolist(), strict=True))
    new = [k for k in dict.fromkeys(stops) if k not in reached]
    if new:
        ways = [way(registry, a, b) for a, b in new]
        reached.update(zip(new, checks.footprints_blocked(ways, step).tolist(), strict=True))
    bad = np.array([reached[k] for k in stops], dtype=bool)
    # the closing moves (:func:`~lotsim.maneuvers.closing.closing_segments`, as arrays): a
    # straight, an arc onto the lane and a straight along it
    c = np.flatnonzero(rows[:, 6] != 0.0)
    if not c.size:
        return bad
    q = np.empty((len(c), 3))
    for a in np.unique(level[c]).tolist():
        at = level[c] == a
        q[at] = registry[a][2][m[c][at]]
    g, d, kappa, extend = rows[c, 4], rows[c, 5], rows[c, 6], rows[c, 7]
    straight = d > 1e-9
    mid = np.where(straight[:, None], advance(q, g * d, 0.0), q)
    arc = -np.asarray(wrap_angle(mid[:, 2])) / kappa
    end = advance(mid, arc, kappa)
    on = extend > 1e-9
    piece_of = np.concatenate([c[straight], c, c[on]])
    hit = checks.pieces_blocked(
        np.concatenate([q[straight], mid, end[on]]),
        np.concatenate([(g * d)[straight], arc, (g * extend)[on]]),
        np.concatenate([np.zeros(int(straight.sum())), kappa, np.zeros(int(on.sum()))]),
        step)
    bad[piece_of[hit]] = True
    return bad


def extents(checks: Validity, poses: FloatArray, gear: int, kappa: float, sweep: float,
            turn_cap: float = math.pi) -> FloatArray:
    """How far strokes from ``poses`` (H, 3) run clear [m], to the ``sweep`` step; (H,)."""
    p = checks.problem
    cap = 1.5 * p.vehicle.length + 2.0
    if kappa:
        cap = min(cap, turn_cap / abs(kappa))
    n = max(1, math.ceil(cap / sweep))
    first = _strokes(p.vehicle, gear, kappa, cap, n).first_blocked(checks.local_blocked, poses)
    return np.linspace(0.0, cap, n + 1)[first[:, 0]]


@functools.lru_cache(maxsize=256)
def _strokes(vehicle: VehicleType, gear: int, kappa: float, cap: float, n: int
             ) -> RigidSweeps:
    """The sweeps of a stroke ``cap`` long in ``gear`` at curvature ``kappa`` from the
    origin, ``n`` of them, checked first in blocks of :data:`STROKE_BLOCK` (a stroke's
    shape is the same for every problem of a vehicle type: made once)."""
    along = advance(np.zeros(3), gear * np.linspace(0.0, cap, n + 1), kappa)
    return RigidSweeps([vehicle.footprints(along)], STROKE_BLOCK)


def way(registry: list[tuple], level: int, m: int) -> list[Segment]:
    """The way to stop ``m`` of ``level`` of :func:`shuffle`'s ``registry``: the strokes
    before it, and the part of its own stroke up to it."""
    heads, flat, _, owner, g, kappa = registry[level]
    segs, pose, _ = heads[owner[m]]
    return segs + ([Segment(pose, g * float(flat[m]), kappa)] if flat[m] > 1e-9 else [])
