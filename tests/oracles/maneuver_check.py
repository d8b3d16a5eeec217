"""An oracle for a parking maneuver that shares nothing with the planner: the car's
footprint every 5 cm of travel against shapely's neighbouring parked cars, walls, obstacles
and no-go areas and the lot's outline; curvature recomputed from the sampled poses; the
final footprint in the slot; the start on the lane."""

import math

import numpy as np
import shapely

from lotsim.core.geometry import wrap_angle

STEP = 0.05


def parked_bodies(slots, vehicles):
    """Polygons of cars of each type parked centred in ``slots``, nose along the slot
    (either way round), slot by slot; a parallel slot is taken whole."""
    bays = [s for s in slots if s.kind != "parallel"]
    centres = np.array([s.center for s in bays], dtype=float).reshape(-1, 2)
    headings = np.array([[s.heading, s.heading + math.pi] for s in bays]).reshape(-1)
    ahead = np.column_stack([np.cos(headings), np.sin(headings)])
    bodies = []  # per type: a body for each bay and way round, in the order of ``bays``
    for v in vehicles:
        axles = np.repeat(centres, 2, axis=0) - ahead * (v.front - v.rear) / 2
        poses = np.column_stack([axles, headings]) if len(bays) else np.empty((0, 3))
        bodies.append(shapely.polygons(v.footprints(poses)) if len(bays) else [])
    out, k = [], 0
    for s in slots:
        if s.kind == "parallel":
            out.append(s.shape)
            continue
        for b in bodies:
            out += [b[2 * k], b[2 * k + 1]]
        k += 1
    return out


def check_maneuver(lot, m, vehicle, cars, *, clearance=0.05):
    """Every problem found with maneuver ``m``, as strings; [] when it is sound."""
    problems = []
    segs = m.segments
    for a, b in zip(segs[:-1], segs[1:], strict=True):
        if (math.dist(a.end[:2], b.start[:2]) > 1e-6
                or abs(wrap_angle(a.end[2] - b.start[2])) > 1e-6):
            problems.append("pieces do not meet")
    poses, _ = m.sample(STEP)
    ds = np.hypot(*np.diff(poses[:, :2], axis=0).T)
    assert ds.max() <= STEP + 1e-9
    turn = np.abs(wrap_angle(np.diff(poses[:, 2])))
    moving = ds > 1e-9
    # turn over chord exceeds curvature by (arc / chord - 1) ≈ Δθ²/24 < 1e-4 at 5 cm
    if np.any(turn[moving] / ds[moving] > vehicle.max_curvature * (1 + 1e-4)):
        problems.append("tighter than the minimum turning radius")
    # motion along the heading: no sideways jumps
    # (a chord of an arc leaves the heading by half the turn: ds · Δθ / 2 at most)
    step = np.diff(poses[:, :2], axis=0)
    sideways = np.abs(np.cos(poses[:-1, 2]) * step[:, 1] - np.sin(poses[:-1, 2]) * step[:, 0])
    if np.any(sideways > 0.5 * STEP * STEP * vehicle.max_curvature + 1e-9):
        problems.append("sideways motion")
    bodies = shapely.polygons(vehicle.footprints(poses))
    if not shapely.covers(lot.boundary, bodies).all():
        problems.append("leaves the lot")
    tree = shapely.STRtree(cars)
    near = tree.query(bodies, predicate="dwithin", distance=clearance)
    if near.size:  # (a body that touches a car is also within the clearance of it)
        hit = tree.query(bodies, predicate="intersects")
        if hit.size:
            problems.append(f"touches a parked car at sample {hit[0][0]}")
        problems.append(f"passes within {clearance} m of a parked car")
    areas = [a.polygon for a in lot.areas]
    if areas and shapely.STRtree(areas).query(bodies, predicate="dwithin", distance=clearance).size:
        problems.append("touches or grazes a wall, obstacle or no-go area")
    slot = lot.slot_by_id[m.slot]
    end = shapely.Polygon(vehicle.footprints([m.end])[0])
    if not slot.shape.buffer(1e-6).covers(end):
        problems.append("does not end inside its slot")
    lane = next(lane for lane in lot.lanes if lane.id == m.lane)
    station, off = lane.project(m.start[:2])
    if off > 1e-3 or abs(wrap_angle(lane.pose_at(station)[2] - m.start[2])) > 1e-3:
        problems.append("does not start on its lane heading its way")
    return problems
