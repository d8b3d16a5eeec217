"""The way into a parallel slot: the minimum-slot planner's strokes (:mod:`.minslot`) for the
real slot, shrunk by the safety margin on its three closed sides, over start headings
0…90° in order of (changes, length), joined to the lane by the closing move from its start
pose (:mod:`~lotsim.maneuvers.closing`)."""

from __future__ import annotations

import itertools
import math

import numpy as np

from lotsim.core.geometry import Segment, wrap_angle
from lotsim.core.outcome import Outcome, Status
from lotsim.maneuvers.closing import closing_segments, closings, first_clear, park_path
from lotsim.maneuvers.minslot import SlotFrame, simulate_strokes, start_headings
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.maneuvers.validity import Validity
from lotsim.vehicles.model import VehicleType


def park_along(checks: Validity, settings: ManeuverSettings
               ) -> Outcome[tuple[tuple[Segment, ...], float]]:
    """The parking maneuver into a parallel slot (local frame) and the local x where it
    starts: fewest direction changes, then parked parallel to the kerb, then shortest."""
    p = checks.problem
    v, s = p.vehicle, p.slot
    m = settings.margin + settings.parallel_extra
    frame = SlotFrame(s.length - 2 * m, s.width - m)
    if frame.length <= v.length or frame.width < v.width:
        return Outcome.failed(Status.INFEASIBLE, (
            f"with {settings.margin:g} m margins the slot leaves "
            f"{frame.length:.2f} × {frame.width:.2f} m for a "
            f"{v.length:.2f} × {v.width:.2f} m car"))
    thetas = start_headings(settings.parallel_heading_step)
    changes, strokes = simulate_strokes(v, frame, thetas, max_changes=settings.max_changes,
                                record=True)
    ok = np.flatnonzero(changes >= 0)
    if not ok.size:
        return Outcome.failed(Status.NO_PATH, (
            f"the minimum-slot maneuver needs more than {settings.max_changes} direction "
            f"changes in a {s.length:.2f} m slot"))
    shift = np.array([-s.length / 2 + m, -s.width + m])  # minslot frame → local frame
    ok = [k for k in ok if strokes[k]]
    inside = [[Segment((x.start[0] + shift[0], x.start[1] + shift[1], x.start[2]),
                       x.distance, x.curvature)
               for x in strokes[k] + straighten(v, frame, strokes[k])] for k in ok]
    starts = np.array([segs[0].start for segs in inside]).reshape(-1, 3)
    paths = []
    for row in closings(p, starts, 0, 0, np.zeros(len(starts)), settings):
        j, close = int(row[2]), (int(row[3]), float(row[4]), float(row[5]), float(row[6]))
        path = park_path(closing_segments(inside[j][0].start, close))[0] + tuple(inside[j])
        c = sum(1 for a, b in zip(path[:-1], path[1:], strict=True) if a.gear != b.gear)
        askew = abs(float(wrap_angle(path[-1].end[2]))) > math.radians(1.0)
        paths.append((c, askew, sum(x.length for x in path), list(path)))
    # fewest changes, then parked parallel to the kerb, then shortest
    paths.sort(key=lambda c: c[:3])
    found = first_clear(checks, [(c[0], c[2], c[3]) for c in paths], step=settings.rough)
    if found is None:
        return Outcome.failed(Status.NO_PATH, "no start heading of the minimum-slot maneuver "
                              "joins the lane clear")
    return Outcome.of((tuple(found[2]), found[2][0].start[0]))


def straighten(vehicle: VehicleType, frame: SlotFrame, strokes: list[Segment]
               ) -> list[Segment]:
    """One full-lock arc that turns a car parked by the minimum-slot strategy (which stops
    the moment it is inside, often askew) parallel to the kerb, staying inside ``frame``;
    in the gear it was in if that fits, else the other. Nothing if neither fits."""
    end = strokes[-1].end
    th = float(wrap_angle(end[2]))
    if abs(th) < math.radians(0.5):
        return []
    for g, f in itertools.product((strokes[-1].gear, -strokes[-1].gear), (1.0, 0.5, 0.25)):
        kappa = vehicle.max_curvature * f
        arc = Segment(end, g * abs(th) / kappa, -math.copysign(kappa, th * g))
        corners = vehicle.footprints(arc.sample(0.05))
        x, y = corners[..., 0], corners[..., 1]
        if (x.min() >= 0 and x.max() <= frame.length and y.min() >= 0
                and y.max() <= frame.width):
            return [arc]
    return []
