"""The rule on a run driven through disturbances: every stall the result records was
honoured (the stalled car stood still throughout it)."""

from __future__ import annotations

from typing import Any

import numpy as np

from lotsim.verify.reading import _is_number, _kind, _Vehicle
from lotsim.verify.report import Violation, _add
from lotsim.verify.tolerances import GEAR_SPEED_TOL, STILL_TOL, STILL_TURN, TIME_TOL


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
