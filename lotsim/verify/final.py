"""The rules on how each vehicle ends (slot, exit, reason, status) and on the metrics."""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
import shapely

from lotsim.verify.motion import _wrap
from lotsim.verify.reading import _is_number, _Lot, _Vehicle
from lotsim.verify.report import Violation, _add
from lotsim.verify.tolerances import (
    BAY_USES,
    BODY_TOL,
    EXIT_DISTANCE,
    EXIT_HEADING,
    MAKESPAN_TOL,
    POSE_TOL,
    REST_SPEED,
    SHRINK,
    STATUSES,
    TIME_TOL,
)


def _check_final(vehicles: list[_Vehicle], lot: _Lot, out: list[Violation]) -> None:
    """Rule 7 per vehicle: slot, exit, reason, status."""
    for veh in vehicles:
        name, status = veh.id, veh.status
        if status in ("waiting", "rejected") and not veh.reason.strip():
            _add(out, "reason", name, None, f"{name} is {status} but gives no reason")
        if status in ("parked", "departed") and veh.reason.strip():
            _add(out, "reason", name, None,
                 f"{name} is {status} but gives a reason ({veh.reason!r}); it must be empty")
        if status == "rejected" and veh.n:
            _add(out, "status", name, veh.t[0],
                 f"{name} is rejected (never entered) but has {veh.n} samples")
        if status in ("parked", "departed") and not veh.n:
            _add(out, "status", name, None, f"{name} is {status} but has no samples")
        if veh.slot is not None and veh.slot not in lot.slots:
            _add(out, "slot", name, None, f"{name}: slot {veh.slot!r} is not a slot of the lot")
        if status in ("parked", "departed") and veh.slot in lot.slots:
            _check_bay_use(veh, lot.slots[veh.slot], out)
        if status == "parked" and veh.n:
            _check_parked(veh, lot, out)
        if status == "departed" and veh.n:
            _check_exit(veh, lot, out)
        if veh.inside is not None and veh.n:
            _check_inside(veh, lot, out)


def _check_bay_use(veh: _Vehicle, slot, out: list[Violation]) -> None:
    """No car parks in a bay its type may not use: a bay of a marked use (accessible,
    van-accessible, EV, motorcycle) takes only types marked so, a compact bay only a type
    no longer and no wider than itself."""
    need = BAY_USES[slot.use]
    if need is not None and need not in veh.marks:
        _add(out, "bay_use", veh.id, None, f"{veh.id} parks in {slot.use.replace('_', '-')} "
             f"bay {slot.id} but its type is not marked {need}")
    if slot.use == "compact":
        ring = np.asarray(slot.polygon.exterior.coords)[:4]
        sides = np.hypot(*np.diff(np.vstack([ring, ring[:1]]), axis=0).T)
        length = float(max(sides[0], sides[1]))
        width = float(slot.polygon.area) / length
        body = veh.front + veh.rear
        if body > length + BODY_TOL or veh.width > width + BODY_TOL:
            _add(out, "bay_use", veh.id, None, f"{veh.id} ({body:.2f} × {veh.width:.2f} m) "
                 f"parks in compact bay {slot.id} of {length:.2f} × {width:.2f} m")


def _footprint(veh: _Vehicle, k: int) -> shapely.Polygon:
    """``veh``'s footprint at its ``k``-th sample, shrunk by :data:`SHRINK`."""
    x, y, th = veh.x[k], veh.y[k], veh.theta[k]
    u, w = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th), math.cos(th)])
    a0, a1 = -veh.rear + SHRINK, veh.front - SHRINK
    b = veh.width / 2 - SHRINK
    return shapely.Polygon([np.array([x, y]) + u * a + w * c
                            for a, c in ((a0, -b), (a1, -b), (a1, b), (a0, b))])


def _check_inside(veh: _Vehicle, lot: _Lot, out: list[Violation]) -> None:
    """A car in the lot when it came starts there at its arrival, at rest: within the slot
    it stood in (free at the start), or at the pose it stood at."""
    name, t0 = veh.id, veh.t[0]
    if abs(t0 - veh.arrival) > TIME_TOL:
        _add(out, "inside", name, t0, f"{name} was in the lot at {veh.arrival:.2f} s but its "
             f"first sample is at {t0:.2f} s")
    if abs(veh.v[0]) > REST_SPEED:
        _add(out, "inside", name, t0, f"{name} stood in the lot when it came but moves at "
             f"its first sample (v={veh.v[0]:.3f} m/s)")
    if "slot" in veh.inside:
        slot = lot.slots.get(veh.inside["slot"])
        if slot is None:
            return  # reported when read
        if slot.occupied:
            _add(out, "inside", name, t0, f"{name} stood in slot {slot.id}, which was "
                 f"occupied at start")
        foot = _footprint(veh, 0)
        if not shapely.covers(slot.polygon, foot):
            outside = shapely.area(shapely.difference(foot, slot.polygon))
            _add(out, "inside", name, t0, f"{name} stood in slot {slot.id} when it came, but "
                 f"its first footprint is not within it ({outside:.2f} m² outside)")
        return
    x, y, th = veh.inside["pose"]
    off = math.hypot(veh.x[0] - x, veh.y[0] - y)
    turn = abs(float(_wrap(np.array(veh.theta[0] - th))))
    if off > POSE_TOL or turn > POSE_TOL:
        _add(out, "inside", name, t0, f"{name} stood at ({x:.3f}, {y:.3f}, {th:.4f}) when it "
             f"came, but its first sample is {off:.4f} m and {turn:.4f} rad from there")


def _check_parked(veh: _Vehicle, lot: _Lot, out: list[Violation]) -> None:
    name, t_end = veh.id, veh.t[-1]
    if veh.slot is None:
        _add(out, "slot", name, t_end, f"{name} is parked but has no slot")
        return
    slot = lot.slots.get(veh.slot)
    if slot is None:
        return  # reported by _check_final
    if slot.occupied:
        _add(out, "slot", name, t_end,
             f"{name} is parked in slot {slot.id}, which was occupied at start")
    x, y, th = veh.x[-1], veh.y[-1], veh.theta[-1]
    foot = _footprint(veh, -1)
    if not shapely.covers(slot.polygon, foot):
        outside = shapely.area(shapely.difference(foot, slot.polygon))
        _add(out, "slot", name, t_end,
             f"{name} ends at ({x:.2f}, {y:.2f}, {th:.3f}) with its footprint not within "
             f"slot {slot.id} ({outside:.2f} m² outside)")
    if abs(veh.v[-1]) > REST_SPEED:
        _add(out, "slot", name, t_end,
             f"{name} is parked but still moves at its last sample (v={veh.v[-1]:.3f} m/s)")


def _check_exit(veh: _Vehicle, lot: _Lot, out: list[Violation]) -> None:
    name = veh.id
    x, y, th = veh.x[-1], veh.y[-1], veh.theta[-1]
    best: tuple[float, str, float] | None = None
    for eid, (ex, ey, eth) in lot.exits.items():
        dist = math.hypot(x - ex, y - ey)
        turn = abs(float(_wrap(np.array(th - eth))))
        if dist <= EXIT_DISTANCE and turn <= EXIT_HEADING:
            return
        if best is None or dist < best[0]:
            best = (dist, eid, turn)
    where = (f"{best[0]:.2f} m and {best[2]:.3f} rad from exit {best[1]}" if best
             else "the lot has no exit")
    _add(out, "exit", name, veh.t[-1],
         f"{name} departed at ({x:.2f}, {y:.2f}, {th:.3f}), {where} "
         f"(at most {EXIT_DISTANCE} m and {EXIT_HEADING} rad)")


def _check_metrics(metrics: dict, vehicles: list[_Vehicle], out: list[Violation]) -> None:
    counts = Counter(v.status for v in vehicles)
    expected = {s: counts[s] for s in STATUSES} | {"vehicles": len(vehicles)}
    if "served" in metrics:  # parked and departed: the cars that got a slot
        expected["served"] = counts["parked"] + counts["departed"]
    for key, n in expected.items():
        got = metrics.get(key)
        if not (isinstance(got, int) and not isinstance(got, bool)):
            _add(out, "metrics", None, None, f"metrics.{key}: expected a count, found {got!r}")
        elif got != n:
            what = ("vehicles" if key == "vehicles" else "vehicles parked or departed"
                    if key == "served" else f"vehicles with status {key!r}")
            _add(out, "metrics", None, None, f"metrics.{key} is {got} but there are {n} {what}")
    makespan = metrics.get("makespan")
    ends = [v.t[-1] for v in vehicles if v.n]
    if "makespan" in metrics and not _is_number(makespan):
        _add(out, "metrics", None, None,
             f"metrics.makespan: expected a number of seconds, found {makespan!r}")
    elif _is_number(makespan) and ends and abs(makespan - max(ends)) > MAKESPAN_TOL:
        _add(out, "metrics", None, None,
             f"metrics.makespan is {makespan:.3f} s but the last sample is at "
             f"{max(ends):.3f} s")
