"""The rules on a run that met disturbances: every stall the result records was honoured
(the stalled car stood still throughout it), no car but those already in it used a closed
aisle or gate while it was closed, and no car met a car parked in a bay taken from
outside."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import shapely

from lotsim.verify.reading import _is_number, _kind, _polygon, _Vehicle
from lotsim.verify.report import Violation, _add
from lotsim.verify.tolerances import (
    GEAR_SPEED_TOL,
    GRID_DT,
    SHRINK,
    STILL_TOL,
    STILL_TURN,
    TIME_TOL,
)


def _check_disturbances(raw: Any, vehicles: list[_Vehicle], out: list[Violation]) -> None:
    """``stall``: for each of ``disturbances.stalls`` (``car``, ``t0``, ``t1``), the car has
    samples over the whole of ``[t0, t1]`` and stands still there: its pose, interpolated
    at both ends and read at every sample between, the same within ``STILL_TOL`` and
    ``STILL_TURN``, and its speed within ``GEAR_SPEED_TOL`` of 0."""
    if not isinstance(raw, dict):
        _add(out, "structure", None, None, f"disturbances: expected an object, found "
                                           f"{_kind(raw)}")
        return
    stalls = raw.get("stalls", [])
    if not isinstance(stalls, list):
        _add(out, "structure", None, None, "disturbances.stalls: expected a list")
        return
    _check_lot_changes(raw, vehicles, out)
    by_id = {v.id: v for v in vehicles}
    for k, st in enumerate(stalls):
        where = f"disturbances.stalls[{k}]"
        if not (isinstance(st, dict) and isinstance(st.get("car"), str)
                and _is_number(st.get("t0")) and _is_number(st.get("t1"))
                and st["t0"] <= st["t1"]):
            _add(out, "structure", None, None,
                 f"{where}: expected car, t0 and t1 (t0 <= t1)")
            continue
        veh = by_id.get(st["car"])
        if veh is None:
            _add(out, "structure", st["car"], None, f"{where}: no vehicle {st['car']!r}")
            continue
        _check_stall(veh, float(st["t0"]), float(st["t1"]), out)


def _check_stall(veh: _Vehicle, t0: float, t1: float, out: list[Violation]) -> None:
    name = veh.id
    if not veh.n or veh.t[0] > t0 + TIME_TOL or veh.t[-1] < t1 - TIME_TOL:
        _add(out, "stall", name, t0, f"{name} stalls over {t0:.3f}–{t1:.3f} s but is not in "
                                     f"the lot throughout")
        return
    inside = (veh.t > t0) & (veh.t < t1)
    ts = np.concatenate([[t0], veh.t[inside], [t1]])
    x = np.interp(ts, veh.t, veh.x)
    y = np.interp(ts, veh.t, veh.y)
    th = np.interp(ts, veh.t, np.unwrap(veh.theta))
    v = np.interp(ts, veh.t, veh.v)
    moved = ((np.abs(x - x[0]) > STILL_TOL) | (np.abs(y - y[0]) > STILL_TOL)
             | (np.abs(th - th[0]) > STILL_TURN) | (np.abs(v) > GEAR_SPEED_TOL))
    if moved.any():
        at = float(ts[np.argmax(moved)])
        _add(out, "stall", name, at, f"{name} moves at {at:.3f} s during its stall "
                                     f"({t0:.3f}–{t1:.3f} s)")


def _check_lot_changes(raw: dict, vehicles: list[_Vehicle], out: list[Violation]) -> None:
    """``closure``: no car but those ``inside`` a closure when it began has its footprint
    (shrunk by ``SHRINK``) on the closed ground from ``t0`` to (not at) ``t1``; ``taken``: no
    car's footprint meets the car in a bay taken from outside, from its time ``t`` on."""
    for rule, key in (("closure", "closures"), ("taken", "taken")):
        items = raw.get(key, [])
        if not isinstance(items, list):
            _add(out, "structure", None, None, f"disturbances.{key}: expected a list")
            continue
        for k, item in enumerate(items):
            where = f"disturbances.{key}[{k}]"
            if not isinstance(item, dict):
                _add(out, "structure", None, None, f"{where}: expected an object")
                continue
            if key == "taken" and item.get("polygon") is None:
                continue  # refused: nothing stood there
            poly = _polygon(item.get("polygon"), where, out)
            t0 = item.get("t0", item.get("t"))
            t1 = item.get("t1", math.inf)
            if poly is None or not _is_number(t0) or not (_is_number(t1) or t1 == math.inf):
                _add(out, "structure", None, None, f"{where}: expected a polygon and times")
                continue
            inside = set(item.get("inside", []))
            what = (f"closed {item.get('kind', '')} {item.get('id', '')!r}".strip()
                    if key == "closures" else f"the car in bay {item.get('slot')!r}")
            for veh in vehicles:
                if veh.id in inside or not veh.n:
                    continue
                hit = _first_on(veh, poly, float(t0), float(t1))
                if hit is not None:
                    _add(out, rule, veh.id, hit, f"{veh.id} is on the {what} at {hit:.2f} s "
                                                 f"({float(t0):.2f}–{float(t1):.2f} s)")


def _first_on(veh: _Vehicle, poly: shapely.Polygon, t0: float, t1: float) -> float | None:
    """The first instant of ``[t0, t1)`` (the common grid and the samples) at which
    ``veh``'s shrunk footprint meets ``poly``, or None. A vehicle that has not departed
    stands at its last pose after its last sample."""
    end = veh.t[-1] if veh.status == "departed" else max(veh.t[-1], min(t1, veh.t[-1] + 1.0))
    lo, hi = max(t0, veh.t[0]), min(t1, end)
    if lo > hi or lo >= t1:
        return None
    grid = np.arange(math.ceil(lo / GRID_DT), math.floor(hi / GRID_DT) + 1) * GRID_DT
    ts = np.unique(np.concatenate([[lo, hi], grid, veh.t[(veh.t >= lo) & (veh.t <= hi)]]))
    ts = ts[ts < t1]  # from t0 up to (not at) t1: a car may come on the ground as it opens
    x = np.interp(ts, veh.t, veh.x)
    y = np.interp(ts, veh.t, veh.y)
    th = np.interp(ts, veh.t, np.unwrap(veh.theta))
    reach = math.hypot(max(veh.front, veh.rear), veh.width / 2)
    x0, y0, x1, y1 = poly.bounds
    near = (x > x0 - reach) & (x < x1 + reach) & (y > y0 - reach) & (y < y1 + reach)
    if not near.any():
        return None
    ts, x, y, th = ts[near], x[near], y[near], th[near]
    c, s = np.cos(th), np.sin(th)
    f, r, w = veh.front - SHRINK, veh.rear - SHRINK, veh.width / 2 - SHRINK
    along = np.array([f, f, -r, -r])
    side = np.array([w, -w, -w, w])
    cx = x[:, None] + along * c[:, None] - side * s[:, None]
    cy = y[:, None] + along * s[:, None] + side * c[:, None]
    rects = shapely.polygons(np.stack([cx, cy], axis=-1))
    hit = shapely.intersects(rects, poly)
    return float(ts[np.argmax(hit)]) if hit.any() else None
