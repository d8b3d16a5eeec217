"""The closing move onto the lane that ends every way out of a slot — a straight, one arc
of a few multiples of the minimum turning radius that lands on the lane line heading the
lane's way, and a straight along the lane to a station on the start grid — and the choice of
the first clear candidate path."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from lotsim.core.geometry import FloatArray, Pose, Segment, wrap_angle
from lotsim.maneuvers.problem import ManeuverProblem
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.maneuvers.validity import Validity


def closings(p: ManeuverProblem, q: FloatArray, gear: int, changes: int, base: FloatArray,
             settings: ManeuverSettings) -> FloatArray:
    """Closing moves from poses ``q`` (M, 3): a straight, one arc that lands on the
    lane line heading +x, and a straight along the lane to a station on the start grid
    (:attr:`ManeuverSettings.start_grid`, at least ``approach`` on), in leave-time.
    Unchecked for collisions.

    Returns rows ``(changes, length, m, gear, straight, curvature, extend)`` sorted by
    cost, where ``m`` indexes ``q``, ``base`` (M,) is the length already driven
    and ``gear`` the gear driven so far (0: none). Curvature 0 means the pose
    is already on the lane.
    """
    x, y = q[:, 0], q[:, 1]
    th = np.asarray(wrap_angle(q[:, 2]), dtype=float)
    sin, cos = np.sin(th), np.cos(th)
    kmax = p.vehicle.max_curvature
    grid, lead = settings.start_grid, settings.approach
    index = np.arange(len(q), dtype=float)
    turning = (np.abs(th) > 1e-9) & (np.abs(th) < math.pi - 1e-6)
    on_lane = (np.abs(th) <= 1e-9) & (np.abs(y - p.lane_y) < 1e-6)
    zeros = np.zeros(int(on_lane.sum()))
    parts = [np.column_stack([zeros + changes, base[on_lane], index[on_lane], zeros + 1,
                              zeros, zeros, zeros])]
    radii = np.array(settings.closing_radii, dtype=float)[:, None]  # every radius
    for g in (1, -1):  # at once: rows (radius, pose), in that order
        c = changes + (1 if gear and g != gear else 0)
        kappa = np.where(-th * g >= 0, kmax / radii, -kmax / radii)
        with np.errstate(divide="ignore", invalid="ignore"):
            d = (p.lane_y - y + (1 - cos) / kappa) / (g * sin)
        d0 = np.maximum(d, 0.0)
        end_x = x + g * d0 * cos - sin / kappa
        station = p.lane_s0 + end_x
        if grid > 0:  # on along the lane, in the same gear, to a grid station
            with np.errstate(invalid="ignore"):
                target = (np.ceil((station + lead) / grid - 1e-9) if g > 0
                          else np.floor((station - lead) / grid + 1e-9)) * grid
            extend = np.abs(target - station)
        else:
            extend = np.zeros(kappa.shape)
        last_x = end_x + g * extend
        # no straight of a few centimetres before the arc: where the curvature
        # jumps cannot be eased the car stops at both its ends (it would creep)
        ok = (turning & (d >= -1e-9) & ((d0 <= 1e-9) | (d0 >= settings.creep))
              & (end_x >= p.lane_x[0]) & (end_x <= p.lane_x[1])
              & (last_x >= p.lane_x[0] - 1e-9) & (last_x <= p.lane_x[1] + 1e-9))
        n = int(ok.sum())
        parts.append(np.column_stack([
            np.full(n, c), (base + d0 + np.abs(th / kappa) + extend)[ok],
            np.broadcast_to(index, ok.shape)[ok], np.full(n, g), d0[ok], kappa[ok],
            extend[ok]]))
    out = np.concatenate(parts)
    return out[np.lexsort((out[:, 1], out[:, 0]))]


def closing_segments(pose: Pose, close: tuple[int, float, float, float]) -> list[Segment]:
    """The pieces of a closing move ``(gear, straight, curvature, extend)`` from ``pose``:
    the straight, the arc onto the lane, and ``extend`` metres along the lane."""
    g, d, kappa, extend = close
    if kappa == 0.0:
        return []
    segs = []
    if d > 1e-9:
        segs.append(Segment(pose, g * d, 0.0))
        pose = segs[0].end
    segs.append(Segment(pose, -float(wrap_angle(pose[2])) / kappa, kappa))
    if extend > 1e-9:
        segs.append(Segment(segs[-1].end, g * extend, 0.0))
    return segs


def park_path(leave: Sequence[Segment]) -> tuple[tuple[Segment, ...], float]:
    """Leave-time pieces → parking pieces (time-reversed), and the start's local x."""
    segs = tuple(s.backwards() for s in reversed(leave))
    return segs, (segs[0].start[0] if segs else 0.0)


def first_clear(checks: Validity, rows: Sequence, *, step: float, build=None, rough=None,
                chunk: int = 8):
    """The first clear path of ``rows`` (in order), made by ``build(row)`` as
    ``(changes, length, segments)`` (default: rows are already such triples).

    A cheap pass over footprints ``step`` apart drops most blocked paths first:
    ``rough(rows)`` (a mask of the rows whose paths it finds blocked) when given,
    without making them. It looks at ``chunk`` rows first, then ``8 * chunk`` at a
    time: the first clear one is often among the first few (then the rest need not be
    made and checked), and when it is not, the larger batches cost less a row. The
    first clear row is the same whatever the batches.
    """
    build = build or (lambda r: r)
    i = 0
    while i < len(rows):
        size = chunk if i == 0 else 8 * chunk
        some = rows[i : i + size]
        i += size
        if rough is None:
            batch = [build(r) for r in some]
            bad = checks.paths_blocked([c[2] for c in batch], step=step, sweep=False)
            batch = [c for c, b in zip(batch, bad, strict=True) if not b]
        else:
            batch = [build(r) for r, b in zip(some, rough(some), strict=True) if not b]
        for j in range(0, len(batch), chunk):
            part = batch[j : j + chunk]
            ok = np.flatnonzero(~checks.paths_blocked([c[2] for c in part]))
            if ok.size:
                return part[int(ok[0])]
    return None
