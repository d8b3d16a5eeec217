"""Easing a planned maneuver: its curvature jumps inside strokes smoothed by clothoids, so the
car steers as it rolls instead of stopping to steer, where that stays clear and parks where
planned."""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np
from shapely.geometry import Polygon

from lotsim.core.geometry import FloatArray, Segment, ease_joints, wrap_angle
from lotsim.lot.kinds import kind_of
from lotsim.lot.model import unit
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.maneuvers.validity import Validity


def eased(checks: Validity, local: tuple[Segment, ...], settings: ManeuverSettings
          ) -> tuple[Segment, ...]:
    """``local`` (a parking maneuver in the problem's local frame) with its curvature jumps
    inside strokes eased by clothoids (:func:`~lotsim.core.geometry.ease_joints`: the car
    steers as it rolls instead of stopping to steer), with the longest ramp of
    ``settings.ease_ramps`` whose path is as clear as the original, ends inside the slot and
    within ``settings.ease_drift`` of the original end; else ``local``."""
    p = checks.problem
    was = np.array(local[-1].end)
    for ramp in settings.ease_ramps:
        smooth = tuple(ease_joints(local, ramp))
        if len(smooth) == len(local):
            return local  # nothing to ease
        end = np.array(smooth[-1].end)
        if (math.dist(end[:2], was[:2]) > settings.ease_drift
                or abs(wrap_angle(end[2] - was[2])) > 1e-9):
            continue
        # two straights at right angles take up the drift, so the car parks exactly where
        # planned, whichever lane it came by (a car parked along the kerb may stand anywhere
        # in its slot)
        fixed = None if kind_of(p.slot).parks_along else anchored(smooth, was)
        for path in (fixed, smooth):
            if path is None or checks.paths_blocked([path])[0]:
                continue
            body = Polygon(p.vehicle.footprints(p.frame.poses_to_world(
                np.array(path[-1].end)))[0])
            if p.slot.shape.buffer(1e-9).covers(body):
                return path
    return local


def anchored(segments: Sequence[Segment], target: FloatArray) -> tuple[Segment, ...] | None:
    """``segments`` with two of its straights lengthened or shortened (the pair most nearly
    at right angles; what follows each moves with it) so that it ends exactly on ``target``
    (same heading, a few centimetres off); None when there is no such pair, or a straight
    would get shorter than 5 cm."""
    straights = [k for k, x in enumerate(segments) if x.curvature == 0.0 and x.sharpness == 0.0]
    pairs = [(abs(math.sin(segments[i].start[2] - segments[j].start[2])), i, j)
             for i, j in itertools.combinations(straights, 2)]
    if not pairs or max(pairs)[0] < 0.3:
        return None
    _, i, j = max(pairs)
    miss = np.asarray(target[:2], dtype=float) - np.asarray(segments[-1].end[:2], dtype=float)
    # miss = a * gi * u(θi) + b * gj * u(θj)
    m = np.column_stack([segments[i].gear * unit(segments[i].start[2]),
                         segments[j].gear * unit(segments[j].start[2])])
    a, b = np.linalg.solve(m, miss)
    lengths = [x.length for x in segments]
    lengths[i] += float(a)
    lengths[j] += float(b)
    if min(lengths[i], lengths[j]) < 0.05:
        return None
    out, pose = [], segments[0].start
    for x, length in zip(segments, lengths, strict=True):
        seg = Segment(pose, x.gear * length, x.curvature, x.sharpness)
        out.append(seg)
        pose = seg.end
    return tuple(out)

