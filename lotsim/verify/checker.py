"""The checker: :func:`check_result` runs the stages in order (reading, each vehicle's
motion, the footprints, the final states and the metrics), each guarded."""

from __future__ import annotations

import time
import warnings
from typing import Any

import numpy as np

from lotsim.verify.disturbances import _check_disturbances
from lotsim.verify.final import _check_final, _check_metrics
from lotsim.verify.footprints import _check_footprints
from lotsim.verify.motion import _check_motion
from lotsim.verify.reading import (
    _format_problem,
    _is_number,
    _kind,
    _Lot,
    _parse_lot,
    _parse_vehicle,
    _Vehicle,
)
from lotsim.verify.report import CheckReport, Violation, _add, _guard
from lotsim.verify.tolerances import RULES


def check_result(data: dict, *, max_violations: int = 50) -> CheckReport:
    """Verify a result against every rule of ``docs/result.md``.

    Parameters
    ----------
    data : dict
        A parsed ``result.json`` (any value is accepted: what is not a result is reported
        as a ``structure`` violation, never raised).
    max_violations : int, keyword-only
        How many violations to list; ``stats["violations"]`` counts them all.

    Returns
    -------
    CheckReport
        ``report.ok`` is True when every rule holds.

    Examples
    --------
    >>> check_result([]).violations[0].message
    'not a lotsim result: expected a JSON object, found list'
    """
    started = time.perf_counter()
    out: list[Violation] = []
    stats: dict[str, Any] = {"vehicles": 0, "vehicles_checked": 0, "samples": 0,
                             "intervals": 0, "instants": 0, "footprints": 0,
                             "vehicle_instants": 0, "footprint_tests": 0}
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # overflows are judged, not printed
        _guard(out, "the result", _check, data, out, stats)
    order = {rule: i for i, rule in enumerate(RULES)}
    out.sort(key=lambda v: (order.get(v.rule, len(RULES)), v.t is not None, v.t or 0.0,
                            v.vehicle or ""))
    stats["violations"] = len(out)
    stats["seconds"] = round(time.perf_counter() - started, 4)
    return CheckReport(out[:max(0, int(max_violations))], stats)


def _check(data: Any, out: list[Violation], stats: dict[str, Any]) -> None:
    problem = _format_problem(data)
    if problem is not None:
        _add(out, "structure", None, None, problem)
        return
    lot = _guard(out, "the lot", _parse_lot, data["lot"], out) or _Lot()
    raw_vehicles = data["vehicles"]
    if not isinstance(raw_vehicles, list):
        _add(out, "structure", None, None,
             f"vehicles: expected a list, found {_kind(raw_vehicles)}")
        raw_vehicles = []
    stats["vehicles"] = len(raw_vehicles)
    vehicles: list[_Vehicle] = []
    seen: set[str] = set()
    last_arrival: tuple[str, float] | None = None
    for i, raw in enumerate(raw_vehicles):
        veh = _guard(out, f"vehicles[{i}]", _parse_vehicle, i, raw, lot, out)
        if isinstance(raw, dict) and isinstance(raw.get("id"), str):
            if raw["id"] in seen:
                _add(out, "structure", raw["id"], None,
                     f"{raw['id']}: the id is used by more than one vehicle")
            seen.add(raw["id"])
        if isinstance(raw, dict) and _is_number(raw.get("arrival")):
            name = raw["id"] if isinstance(raw.get("id"), str) else f"vehicles[{i}]"
            if last_arrival is not None and raw["arrival"] < last_arrival[1]:
                _add(out, "structure", name, None,
                     f"vehicles are not in arrival order: {name} (arrival "
                     f"{raw['arrival']:.2f} s) follows {last_arrival[0]} "
                     f"({last_arrival[1]:.2f} s)")
            last_arrival = (name, float(raw["arrival"]))
        if veh is not None:
            vehicles.append(veh)
    stats["vehicles_checked"] = len(vehicles)
    stats["samples"] = sum(v.n for v in vehicles)
    stats["intervals"] = sum(max(v.n - 1, 0) for v in vehicles)
    if not isinstance(data["metrics"], dict):
        _add(out, "structure", None, None, "metrics: expected an object")
    if not isinstance(data["settings"], dict):
        _add(out, "structure", None, None, "settings: expected an object")

    for veh in vehicles:
        if veh.n:
            _guard(out, f"the motion of {veh.id}", _check_motion, veh, lot, out)
    _guard(out, "the footprints", _check_footprints,
           [v for v in vehicles if v.n], lot, out, stats)
    _guard(out, "the final states", _check_final, vehicles, lot, out)
    if "disturbances" in data:
        _guard(out, "the disturbances", _check_disturbances, data["disturbances"], vehicles,
               out)
    if isinstance(data["metrics"], dict) and len(vehicles) == len(raw_vehicles):
        _guard(out, "the metrics", _check_metrics, data["metrics"], vehicles, out)
