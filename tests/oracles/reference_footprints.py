"""The footprint rules checked the straightforward way, one instant at a time.

:mod:`lotsim.verify.footprints` batches the footprints of a whole run into arrays, sorts and
sweeps them, and clears most pairs with numpy before shapely sees them. This module checks
the same rules (overlap, parked, obstacle, boundary, slot sharing) as they are written in
:mod:`lotsim.verify`: at each common instant it places every present vehicle's shrunk
footprint as a shapely polygon and tests it against the others, the cars parked at start,
the obstacles, the boundary and the slot it names. It shares nothing with the fast path but
the reading of the result and the constants; it is slow (a polygon per vehicle per instant)
and is kept as the reference the fast path is tested against and as the baseline of
``benchmarks/bench_targets.py``.

Examples
--------
>>> reference_footprints({"format": "lotsim-result"})
set()
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
import shapely

from lotsim.verify.reading import _format_problem, _Lot, _parse_lot, _parse_vehicle, _Vehicle
from lotsim.verify.report import CheckReport, Violation
from lotsim.verify.tolerances import GRID_DT, SHRINK

Finding = tuple
"""``("overlap", a, b, k)`` (ids sorted), ``("parked" | "obstacle", id, j, k)`` (``j`` the
index in ``lot.parked`` or ``lot.obstacles``), ``("boundary", id, k)``, ``("slot", slot, a, b,
k)`` (ids sorted): a rule broken first at instant ``k`` (``t = k · GRID_DT``)."""


def reference_footprints(data: Any) -> set[Finding]:
    """The footprint findings of a result, one instant at a time.

    Parameters
    ----------
    data : dict
        A parsed ``result.json``; vehicles whose structure is broken are left out (as
        :func:`~lotsim.verify.check_result` leaves them out of these rules).

    Returns
    -------
    set of tuple
        One :data:`Finding` per pair (or vehicle) and rule, at its first instant.
    """
    if _format_problem(data) is not None or not isinstance(data["vehicles"], list):
        return set()
    lot = _parse_lot(data["lot"], [])
    vehicles = [v for v in (_parse_vehicle(i, raw, lot, [])
                            for i, raw in enumerate(data["vehicles"])) if v is not None and v.n]
    if not vehicles:
        return set()
    k_first = min(_first_instant(v.t[0]) for v in vehicles)
    # to the first instant at or after the last sample: a vehicle that stays is checked at
    # its last pose also when that sample comes after every instant before it
    k_end = max(_first_instant(v.t[-1]) for v in vehicles)
    env = [("parked", j, p) for j, p in enumerate(lot.parked)]
    env += [("obstacle", j, p) for j, p in enumerate(lot.obstacles)]
    env_tree = shapely.STRtree([p for _, _, p in env])
    if lot.boundary is not None:
        shapely.prepare(lot.boundary)
    found: dict[tuple, int] = {}

    def note(key: tuple, k: int) -> None:
        found.setdefault(key, k)  # instants come in order: the first one stays

    arriving = sorted(vehicles, key=lambda v: _first_instant(v.t[0]))
    here: list[_Vehicle] = []
    for k in range(k_first, k_end + 1):
        while arriving and _first_instant(arriving[0].t[0]) <= k:
            here.append(arriving.pop(0))
        here = [v for v in here if v.status != "departed" or k <= _last_instant(v.t[-1])]
        present = [(v, pose) for v in here if (pose := _pose_at(v, k)) is not None]
        if not present:
            continue
        polys = [_footprint(v, pose) for v, pose in present]
        tree = shapely.STRtree(polys)
        for i, j in zip(*tree.query(polys, predicate="intersects"), strict=True):
            if i < j:
                a, b = sorted((present[i][0].id, present[j][0].id))
                note(("overlap", a, b), k)
        for i, e in zip(*env_tree.query(polys, predicate="intersects"), strict=True):
            kind, j, _ = env[e]
            note((kind, present[i][0].id, j), k)
        for (v, _), poly in zip(present, polys, strict=True):
            if lot.boundary is not None and not lot.boundary.covers(poly):
                note(("boundary", v.id), k)
        _slot_holders(lot, present, polys, k, note)
    return {(*key, k) for key, k in found.items()}


def _slot_holders(lot: _Lot, present: list, polys: list, k: int, note) -> None:
    """Note every two vehicles that hold one slot at instant ``k``.

    A ``parked`` vehicle holds its slot from the first instant at or after its last sample
    (the run's instants reach the first one at or after its last sample).
    """
    holders: dict[str, list[str]] = {}
    for (v, _), poly in zip(present, polys, strict=True):
        slot = lot.slots.get(v.slot) if v.slot is not None else None
        if slot is None:
            continue
        parked_now = v.status == "parked" and k >= _first_instant(v.t[-1])
        if parked_now or slot.polygon.covers(poly):
            holders.setdefault(slot.id, []).append(v.id)
    for sid, ids in holders.items():
        ids = sorted(ids)
        for n, a in enumerate(ids):
            for b in ids[n + 1:]:
                note(("slot", sid, a, b), k)


def _first_instant(t: float) -> int:
    return math.ceil(t / GRID_DT - 1e-9)


def _last_instant(t: float) -> int:
    return math.floor(t / GRID_DT + 1e-9)


def _pose_at(v: _Vehicle, k: int) -> tuple[float, float, float] | None:
    """The rear-axle pose at instant ``k``: interpolated between samples, the last one after
    them (to the end of the run unless the vehicle departed), None when absent."""
    if k < _first_instant(v.t[0]):
        return None
    t = k * GRID_DT
    if k > _last_instant(v.t[-1]) or t >= v.t[-1]:
        if v.status == "departed" and k > _last_instant(v.t[-1]):
            return None
        return float(v.x[-1]), float(v.y[-1]), float(v.theta[-1])
    j = max(int(np.searchsorted(v.t, t, side="right")) - 1, 0)
    f = min(max((t - v.t[j]) / (v.t[j + 1] - v.t[j]), 0.0), 1.0)
    turn = (v.theta[j + 1] - v.theta[j] + math.pi) % (2 * math.pi) - math.pi
    return (float(v.x[j] + f * (v.x[j + 1] - v.x[j])), float(v.y[j] + f * (v.y[j + 1] - v.y[j])),
            float(v.theta[j] + f * turn))


def _footprint(v: _Vehicle, pose: tuple[float, float, float]) -> shapely.Polygon:
    """The footprint at ``pose``, every side moved in by ``SHRINK``."""
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    back, front, half = -v.rear + SHRINK, v.front - SHRINK, v.width / 2 - SHRINK
    return shapely.Polygon([(x + c * a - s * b, y + s * a + c * b)
                            for a, b in ((back, -half), (front, -half), (front, half),
                                         (back, half))])


_PATTERNS = {
    "overlap": re.compile(r"^(\S+) and (\S+) overlap at "),
    "parked": re.compile(r"^(\S+) overlaps the car parked at start lot\.parked\[(\d+)\]"),
    "obstacle": re.compile(r"^(\S+) overlaps obstacle lot\.obstacles\[(\d+)\]"),
    "boundary": re.compile(r"^(\S+) leaves the lot boundary"),
    "slot": re.compile(r"^slot (\S+) is held by (\S+) and (\S+) at once"),
}


def report_findings(report: CheckReport) -> set[Finding]:
    """The footprint findings of a report of :func:`~lotsim.verify.check_result`, in the
    form of :func:`reference_footprints` (give the report every violation:
    ``max_violations`` large enough)."""
    out: set[Finding] = set()
    for v in report.violations:
        pattern = _PATTERNS.get(v.rule)
        match = pattern.match(v.message) if pattern else None
        if match is None:
            continue
        k = round(v.t / GRID_DT)
        out.add(_finding(v, match.groups(), k))
    return out


def _finding(v: Violation, groups: tuple, k: int) -> Finding:
    if v.rule == "overlap":
        return ("overlap", *sorted(groups), k)
    if v.rule in ("parked", "obstacle"):
        return (v.rule, groups[0], int(groups[1]), k)
    if v.rule == "boundary":
        return ("boundary", groups[0], k)
    return ("slot", groups[0], *sorted(groups[1:]), k)
