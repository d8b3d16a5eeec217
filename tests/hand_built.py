"""A hand-built ``result.json`` whose every path is computed in closed form, for the
checker's tests (``tests/unit/verify/``).

The lot (40 × 20 m) is small enough to check by eye::

    y=20 +----------------------------------------+
         |                   |P1 |P2 |P3 |        |   P3 occupied (a car parked at start)
    14.5 |      v5 (6, 12)   +---+---+---+   [ob] |   obstacle at x 30-31, y 10-11
         |                ,-'                     |
         | v1, v2 -> y=5 |   [ zone 18-24 x 2-8 ]  -> exit (34, 5)
    y=0  +----------------------------------------+
         x=0                                      x=40

``v1`` drives straight through (departed), ``v2`` turns left on a quarter circle of exactly
the minimum radius into P1 (parked), ``v5`` drives forward, stops, reverses and waits,
``v3`` is rejected and ``v4`` queued (waiting, no samples). Every path is computed here in
closed form, at a constant 0.9 m/s (below the zone's 1 m/s), sampled every 0.05 s.
"""

from __future__ import annotations

import math

import numpy as np

DT = 0.05
SPEED = 0.9
# The paths here are kinematic sketches: constant speed, steering by jumps, stops in one
# sample. Their dynamic limits are set out of reach so each test sees only the rule it
# breaks; tests/unit/verify/test_dynamics.py checks those limits on a car that drives like one.
TYPE = {"name": "valet", "width": 1.8, "front": 3.9, "rear": 1.0, "wheelbase": 2.8,
        "max_steer": 0.5, "max_forward_speed": 5.0, "max_reverse_speed": 2.0,
        "max_accel": 1e3, "max_brake": 1e3, "max_jerk": 1e6, "max_steer_rate": 1e3,
        "max_lateral_accel": 1e3}
R = TYPE["wheelbase"] / math.tan(TYPE["max_steer"])  # 5.12 m
SLOT_X = 21.3  # centre line of P1
PARK_Y = 15.8  # rear axle of a car parked nose-in in P1


def box(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def advance(pose, s, k):
    """Pose after ``s`` metres on curvature ``k`` (closed form)."""
    x, y, th = pose
    if k == 0:
        return x + s * math.cos(th), y + s * math.sin(th), th
    return (x + (math.sin(th + k * s) - math.sin(th)) / k,
            y - (math.cos(th + k * s) - math.cos(th)) / k, th + k * s)


def stroke(start, pieces, *, t0, gear=1, speed=SPEED, stop=True, steer_radius=None):
    """Samples every DT along ``pieces`` [(length, curvature)] driven at ``speed`` in
    ``gear``; the last sample stands (v = 0) when ``stop``. ``steer_radius`` overrides the
    radius the recorded steering angle is computed from."""
    total = sum(length for length, _ in pieces)
    n = math.floor(total / (speed * DT) + 1e-9)
    s = [j * speed * DT for j in range(n + 1)]
    if s[-1] < total - 1e-9:
        s.append(total)
    out = {k: [] for k in ("t", "x", "y", "theta", "v", "steer", "gear")}
    for si in s:
        pose, left = start, si
        for length, k in pieces:
            if left <= length + 1e-12:
                break
            pose, left = advance(pose, gear * length, gear * k), left - length
        pose = advance(pose, gear * left, gear * k)
        radius = steer_radius if (steer_radius and k) else (1 / k if k else math.inf)
        out["t"].append(t0 + si / speed)
        out["x"].append(pose[0])
        out["y"].append(pose[1])
        out["theta"].append(pose[2])
        out["v"].append(gear * speed)
        out["steer"].append(math.atan(TYPE["wheelbase"] / radius))
        out["gear"].append(gear)
    if stop:
        out["v"][-1] = 0.0
    return out


def join(first, second):
    """``second`` (which starts where ``first`` ends) appended to ``first``."""
    return {k: first[k] + second[k][1:] for k in first}


def stand(samples, duration):
    """The last pose held for ``duration`` seconds: one more sample, both standing."""
    out = {k: list(v) for k, v in samples.items()}
    out["gear"][-1] = 0
    out["v"][-1] = 0.0
    for k in out:
        out[k].append(out[k][-1])
    out["t"][-1] += duration
    return out


def v2_path(radius=R, final_y=PARK_Y, steer_radius=None):
    """From the entrance straight, a left quarter circle of ``radius``, straight into P1."""
    pieces = [(SLOT_X - radius - 3.0, 0.0), (radius * math.pi / 2, 1 / radius),
              (final_y - 5.0 - radius, 0.0)]
    return stand(stroke((3.0, 5.0, 0.0), pieces, t0=10.0, steer_radius=steer_radius), 30.0)


def vehicle(vid, arrival, status, samples=None, slot=None, reason=""):
    empty = {k: [] for k in ("t", "x", "y", "theta", "v", "steer", "gear")}
    return {"id": vid, "type": dict(TYPE), "arrival": arrival, "entrance": "gate-in",
            "slot": slot, "status": status, "reason": reason,
            "samples": samples if samples is not None else empty}


def refresh_metrics(result):
    vehicles = result["vehicles"]
    m = {s: sum(v["status"] == s for v in vehicles)
         for s in ("parked", "departed", "waiting", "rejected")}
    ends = [v["samples"]["t"][-1] for v in vehicles if v["samples"]["t"]]
    m |= {"vehicles": len(vehicles), "makespan": max(ends, default=0.0)}
    result["metrics"] = m
    return result


def valid_result():
    lot = {
        "name": "test-lot",
        "boundary": box(0, 0, 40, 20),
        "slots": [
            {"id": "P1", "kind": "perpendicular", "polygon": box(20, 14.5, 22.6, 20),
             "occupied": False},
            {"id": "P2", "kind": "perpendicular", "polygon": box(22.6, 14.5, 25.2, 20),
             "occupied": False},
            {"id": "P3", "kind": "perpendicular", "polygon": box(25.2, 14.5, 27.8, 20),
             "occupied": True},
        ],
        "obstacles": [box(30, 10, 31, 11)],
        "parked": [box(25.6, 15, 27.4, 19.9)],
        "speed_limit": 5.0,
        "speed_zones": [{"id": "bump", "polygon": box(18, 2, 24, 8), "limit": 1.0}],
        "entrances": [{"id": "gate-in", "pose": [3.0, 5.0, 0.0]}],
        "exits": [{"id": "gate-out", "pose": [34.0, 5.0, 0.0]}],
    }
    v1 = stroke((3.0, 5.0, 0.0), [(31.0, 0.0)], t0=0.0, stop=False)
    forward = stroke((6.0, 12.0, 0.0), [(3.0, 0.0)], t0=5.0)
    back = stroke((9.0, 12.0, 0.0), [(3.0, 0.0)], t0=forward["t"][-1], gear=-1)
    v5 = join(forward, back)
    v5["gear"][-1] = 0
    vehicles = [
        vehicle("v1", 0.0, "departed", v1),
        vehicle("v5", 5.0, "waiting", v5, reason="no free slot fits"),
        vehicle("v2", 10.0, "parked", v2_path(), slot="P1"),
        vehicle("v3", 12.0, "rejected", reason="the lot is full"),
        vehicle("v4", 20.0, "waiting", reason="queued at gate-in"),
    ]
    result = {"format": "lotsim-result", "version": 1, "lot": lot, "vehicles": vehicles,
              "metrics": {},
              "settings": {"planner": "hca", "assignment": "shortest", "seed": 1,
                           "lotsim_version": "0.1.0"}}
    return refresh_metrics(result)


def random_traffic(seed, n=12):
    """Vehicles on random arcs (headings crossing ±pi), at times off the 0.05 s grid,
    standing between strokes, departing or staying: a result full of overlaps."""
    rng = np.random.default_rng(seed)
    vehicles = []
    for i in range(n):
        pose = (rng.uniform(8, 32), rng.uniform(6, 14), rng.uniform(-math.pi, math.pi))
        t0 = round(rng.uniform(0, 6), 3)
        samples = None
        for _ in range(int(rng.integers(1, 3))):
            k = rng.choice([0.0, rng.uniform(-0.15, 0.15)])
            part = stroke(pose, [(rng.uniform(1, 6), k)], t0=t0, speed=1.0)
            part = stand(part, float(rng.choice([0.0, rng.uniform(0.01, 4)])) or 0.02)
            samples = part if samples is None else join(samples, part)
            pose = (samples["x"][-1], samples["y"][-1], samples["theta"][-1])
            t0 = samples["t"][-1]
        samples["theta"] = [(a + math.pi) % (2 * math.pi) - math.pi for a in samples["theta"]]
        status = "departed" if rng.random() < 0.5 else "waiting"
        vehicles.append(vehicle(f"c{i}", 0.0, status, samples, reason="x" * (status != "departed")))
    return vehicles
