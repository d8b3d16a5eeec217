"""A car's visit to the lot as a result document tells it: the one reader of when each
vehicle arrived, entered, stood in its bay, moved off again, left or was turned away, used
by the replay and every export (``docs/result.md``).

* ``start`` and ``end`` are its first and last samples;
* ``park`` is when it came to rest in its bay for its dwell and ``leave`` when it began
  to leave (``leave`` is None for a car that stays to the end of the run): the dwell is
  the longest stretch of samples at rest at one pose with its wheels still (within the
  file's rounding), the centre of its body inside its bay, a stretch that runs to the end
  of a car that did not depart counting as the longest. (A car that straightens its wheels
  standing, after it stopped in the bay, parks when its wheels are straight: when its
  parking maneuver ends, as the run's times to park count.)
* ``rejected`` is when a turned-away car gave up: its arrival plus the run's patience.

Examples
--------
>>> doc = {"lot": {"slots": [{"id": "P1", "polygon": [[8, -1], [14, -1], [14, 1], [8, 1]]}],
...                "exits": []},
...        "settings": {"patience": None},
...        "vehicles": [{"id": "a", "slot": "P1", "status": "parked", "arrival": 0.0,
...                      "entrance": "in", "type": {"front": 3.9, "rear": 1.0},
...                      "samples": {"t": [0.0, 2.0, 4.0, 9.0], "x": [0.0, 5.0, 9.5, 9.5],
...                                  "y": [0.0] * 4, "theta": [0.0] * 4,
...                                  "v": [0.0, 2.5, 0.0, 0.0], "steer": [0.0] * 4,
...                                  "gear": [0, 1, 0, 0]}}]}
>>> v = visits(doc)["a"]
>>> v.start, v.park, v.leave, v.end
(0.0, 4.0, None, 9.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

POSE_TOLERANCE = 2e-4
"""Two samples at rest closer than this [m, rad] stand at one pose (the file's rounding:
0.1 mm, 1 µrad)."""


@dataclass(frozen=True, slots=True)
class Visit:
    """A vehicle's visit in times [s]: see the module's docstring."""

    vehicle: str
    slot: str | None
    status: str
    arrival: float
    """When it arrived at its entrance (it may wait outside before its first sample)."""
    entrance: str
    start: float | None
    """Its first sample (None: it never entered)."""
    park: float | None
    """It came to rest in its slot (None: it never stood in it)."""
    leave: float | None
    """It moved off from its slot (None: it stayed)."""
    end: float | None
    """Its last sample."""
    exit: str | None
    """The exit it left by (``departed`` vehicles only)."""
    in_bay: bool = False
    """It stood in its slot when it came (``inside``), from its first sample."""
    rejected: float | None = None
    """When it was turned away (``rejected`` vehicles only): its arrival and the run's
    patience."""


def visits(doc: dict) -> dict[str, Visit]:
    """Each vehicle's :class:`Visit`, by id (every vehicle, those without samples too),
    from a result document as :func:`lotsim.load_result` reads it."""
    slots = {s["id"]: shapely.Polygon(s["polygon"]) for s in doc["lot"]["slots"]}
    exits = doc["lot"].get("exits", [])
    patience = (doc.get("settings") or {}).get("patience")
    out = {}
    for v in doc["vehicles"]:
        vid, slot, status = str(v["id"]), v.get("slot"), str(v["status"])
        s = v.get("samples") or {}
        t = np.asarray(s.get("t", ()), dtype=float)
        start = end = park = leave = rejected = None
        exit_id = None
        if len(t):
            x, y, th = (np.asarray(s[k], dtype=float) for k in ("x", "y", "theta"))
            start, end = float(t[0]), float(t[-1])
            stand = _dwell(t, x, y, th, np.asarray(s["steer"], dtype=float),
                           np.asarray(s["v"], dtype=float), np.asarray(s["gear"]), v["type"],
                           slots.get(slot), stays=status != "departed")
            if stand is not None:
                park, leave = stand
            if status == "departed" and exits:
                d = [math.hypot(e["pose"][0] - x[-1], e["pose"][1] - y[-1]) for e in exits]
                exit_id = str(exits[int(np.argmin(d))]["id"])
        if status == "rejected":
            rejected = float(v["arrival"]) + (float(patience) if patience is not None else 0.0)
        out[vid] = Visit(vid, slot, status, float(v["arrival"]), str(v.get("entrance") or ""),
                         start, park, leave, end, exit_id, "slot" in (v.get("inside") or {}),
                         rejected)
    return out


def _dwell(t, x, y, th, steer, v, gear, typ: dict, bay: shapely.Polygon | None, *,
           stays: bool) -> tuple[float, float | None] | None:
    """``(park, leave)`` of the longest stretch of samples at rest at one pose, the wheels
    still, with the body's centre inside ``bay`` (``leave`` None when it runs to the last
    sample of a car that ``stays``); None when there is none."""
    if bay is None:
        return None
    rest = np.flatnonzero((v == 0) & (gear == 0))
    if not len(rest):
        return None
    shift = (float(typ["front"]) - float(typ["rear"])) / 2
    inside = shapely.contains_xy(bay, x[rest] + shift * np.cos(th[rest]),
                                 y[rest] + shift * np.sin(th[rest]))
    best = None
    for i, j in _runs(rest, x, y, th, steer):
        if not inside[np.searchsorted(rest, i)]:
            continue
        span = math.inf if stays and j == len(t) - 1 else t[j] - t[i]
        if best is None or span > best[2]:
            best = (i, j, span)
    if best is None:
        return None
    i, j, span = best
    return float(t[i]), (None if span == math.inf else float(t[j]))


def _runs(rest: np.ndarray, x, y, th, steer) -> list[tuple[int, int]]:
    """Index ranges ``[i, j]`` of consecutive samples at rest (``rest``: their indices) at
    one pose and one road-wheel angle, those of each range's first sample."""
    runs = []
    k, n = 0, len(rest)
    while k < n:
        i = j = int(rest[k])
        k += 1
        while (k < n and rest[k] == j + 1 and abs(x[j + 1] - x[i]) <= POSE_TOLERANCE
               and abs(y[j + 1] - y[i]) <= POSE_TOLERANCE
               and abs(th[j + 1] - th[i]) <= POSE_TOLERANCE
               and abs(steer[j + 1] - steer[i]) <= POSE_TOLERANCE):
            j += 1
            k += 1
        runs.append((i, j))
    return runs
