"""The rows of a sweep: the columns of ``runs.csv`` (written by :func:`csv_text`, read back
by :func:`read_csv`), and their means over seeds (:func:`aggregate`), with what they say
of the GA and of saturation; each run's hours, the rows of ``hours.csv`` (:func:`hour_rows`,
written by :func:`hours_csv_text`, read back by :func:`read_hours_csv`), pooled over seeds
by :func:`aggregate_hours`."""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Sequence
from typing import Any

import numpy as np

SATURATED = 0.9
"""A load is saturated when the throughput is below this fraction of the arrival rate."""
SATURATION_VEHICLES = 20
"""Fewest vehicles per run for :func:`saturation` to judge: rates estimated from a handful
of arrivals are noise."""


COLUMNS = (
    "run", "scenario", "planner", "window_s", "assignment", "priority", "rate_per_h", "count",
    "disturbance", "seed", "ok", "solved", "violations", "problem", "vehicles", "served",
    "parked", "departed", "waiting", "rejected", "makespan_s", "mean_time_to_park_s",
    "max_time_to_park_s", "median_time_to_park_s", "p90_time_to_park_s",
    "median_time_to_leave_s", "p90_time_to_leave_s", "standing_per_car_s",
    "standing_outside_per_car_s", "standing_in_per_car_s", "standing_out_per_car_s",
    "total_waiting_s", "arrival_rate_per_h", "throughput_per_h", "searches", "expansions",
    "late_starts", "stalls", "replans", "stood_more_s", "evaluations", "fitness_s",
    "ga_arrival_fitness_s", "ga_shortest_first_fitness_s", "planning_time_s",
    "planning_median_ms", "planning_p95_ms", "motions_s", "order_time_s", "wall_time_s",
    "peak_memory_mb",
)
"""Columns of ``runs.csv``, in order (``docs/bench.md`` defines each)."""
TIMING_COLUMNS = ("planning_time_s", "planning_median_ms", "planning_p95_ms", "motions_s",
                  "order_time_s", "wall_time_s", "peak_memory_mb")
"""The columns that depend on the machine and the moment; all the others depend only on
the suite."""
DIGITS = {"window_s": 3, "rate_per_h": 3, "makespan_s": 3, "mean_time_to_park_s": 3,
           "max_time_to_park_s": 3, "median_time_to_park_s": 3, "p90_time_to_park_s": 3,
           "median_time_to_leave_s": 3, "p90_time_to_leave_s": 3, "standing_per_car_s": 3,
           "standing_outside_per_car_s": 3, "standing_in_per_car_s": 3,
           "standing_out_per_car_s": 3, "total_waiting_s": 3, "arrival_rate_per_h": 2,
           "throughput_per_h": 2, "fitness_s": 3, "ga_arrival_fitness_s": 3,
           "ga_shortest_first_fitness_s": 3, "planning_time_s": 4,
           "planning_median_ms": 2, "planning_p95_ms": 2, "motions_s": 4, "order_time_s": 4,
           "wall_time_s": 3, "peak_memory_mb": 1, "stood_more_s": 3}
"""Decimal places of each column of numbers that are not counts: one precision a column
(``hours.csv``'s figures of the same names too)."""
RUN_KEYS = ("run", "scenario", "planner", "window_s", "assignment", "priority", "rate_per_h",
            "count", "disturbance", "seed")
"""The columns of ``runs.csv`` that say which run a row is: its place in the grid and the
grid point."""
HOUR_FIGURES = ("hour", "arrivals", "parked", "rejected", "median_time_to_park_s",
                "p90_time_to_park_s", "standing_per_car_s")
"""What ``hours.csv`` holds for an hour of a run: :meth:`lotsim.sim.results.RunResult.hourly`,
its times named as ``runs.csv`` names them [s]."""
HOURS_COLUMNS = (*RUN_KEYS, *HOUR_FIGURES)
"""Columns of ``hours.csv``, in order: one row per run and hour of its clock."""


def _rounded(row: dict) -> dict:
    out = {k: row.get(k) for k in COLUMNS}
    for k, nd in DIGITS.items():
        if isinstance(out[k], float):
            out[k] = round(out[k], nd)
    return out


_INTS = ("run", "count", "seed", "violations", "vehicles", "served", "parked", "departed",
         "waiting", "rejected", "searches", "expansions", "evaluations", "late_starts",
         "stalls", "replans")
_TEXTS = ("scenario", "planner", "assignment", "priority", "problem", "disturbance")
_HOUR_INTS = ("run", "count", "seed", "hour", "arrivals", "parked", "rejected")


def read_csv(path: str | os.PathLike) -> list[dict]:
    """The rows of a ``runs.csv``, typed as :func:`run_suite` returns them (to tabulate or
    plot a sweep again without running it; they hold no ``hours``: see
    :func:`read_hours_csv`)."""
    return _read(path, COLUMNS, _INTS)


def read_hours_csv(path: str | os.PathLike) -> list[dict]:
    """The rows of an ``hours.csv``, typed as :func:`hour_rows` gives them (to pool or print
    a sweep's hours again without running it: :func:`aggregate_hours`)."""
    return _read(path, HOURS_COLUMNS, _HOUR_INTS)


def _read(path: str | os.PathLike, columns: Sequence[str], ints: Sequence[str]) -> list[dict]:
    with open(path, newline="", encoding="utf-8") as fh:
        raw = list(csv.DictReader(fh))
    rows = []
    for r in raw:
        row: dict[str, Any] = {}
        for k in columns:
            v = r.get(k, "")
            if k in _TEXTS:
                row[k] = v
            elif k in ("ok", "solved"):
                row[k] = v == "true"
            elif v == "":
                row[k] = None
            else:
                row[k] = int(v) if k in ints else float(v)
        rows.append(row)
    return rows


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return str(value)


GROUP = ("scenario", "planner_label", "assignment", "priority", "rate_per_h", "disturbance")
"""What a row of the summary is: the grid point less the seed."""
MEANS = ("vehicles", "parked", "departed", "rejected", "waiting", "mean_time_to_park_s",
         "max_time_to_park_s", "median_time_to_park_s", "p90_time_to_park_s",
         "median_time_to_leave_s", "p90_time_to_leave_s", "standing_per_car_s",
         "standing_outside_per_car_s", "standing_in_per_car_s", "standing_out_per_car_s",
         "total_waiting_s", "makespan_s", "arrival_rate_per_h",
         "throughput_per_h", "expansions", "late_starts", "stalls", "replans", "stood_more_s",
         "evaluations", "fitness_s", "ga_arrival_fitness_s",
         "ga_shortest_first_fitness_s", "planning_time_s", "planning_median_ms",
         "planning_p95_ms", "order_time_s", "wall_time_s", "peak_memory_mb")


def planner_label(row: dict) -> str:
    """``hca``, ``whca-10``: the planner of a row with its window."""
    w = row["window_s"]
    return row["planner"] if w in (None, "") else f"{row['planner']}-{float(w):g}"


def aggregate(rows: Sequence[dict]) -> list[dict]:
    """One dict per :data:`GROUP` (in grid order): ``runs``, ``ok`` and ``solved``
    (counts), ``failed`` (run numbers), ``served`` (mean of parked + departed: the
    vehicles that got a slot), and for each of :data:`MEANS` the mean over the
    seeds (None where no run has a value), ``<name>_min`` and ``<name>_max``."""
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        key = (r["scenario"], planner_label(r), r["assignment"], r["priority"], r["rate_per_h"],
               r.get("disturbance") or "none")
        groups.setdefault(key, []).append(r)
    out = []
    for key, rs in groups.items():
        g: dict[str, Any] = dict(zip(GROUP, key, strict=True))
        g["runs"] = len(rs)
        g["ok"] = sum(bool(r["ok"]) for r in rs)
        g["solved"] = sum(bool(r["solved"]) for r in rs)
        g["failed"] = [r["run"] for r in rs if not r["ok"]]
        served = [float(r["served"]) if r.get("served") is not None
                  else float(r["parked"]) + float(r["departed"])
                  for r in rs if r.get("parked") is not None]
        g["served"] = float(np.mean(served)) if served else None
        for k in MEANS:
            vals = [float(r[k]) for r in rs if r.get(k) is not None]
            g[k] = float(np.mean(vals)) if vals else None
            g[f"{k}_min"] = min(vals) if vals else None
            g[f"{k}_max"] = max(vals) if vals else None
        out.append(g)
    return out


def ga_gains(groups: Sequence[dict]) -> list[str]:
    """One line per GA group: its total time to park against its own arrival-order and
    shortest-first starting points (same booking, same run), and the order search's cost."""
    out = []
    for g in groups:
        if g["priority"] != "ga" or not g.get("ga_arrival_fitness_s") or g["fitness_s"] is None:
            continue
        base, sf, got = g["ga_arrival_fitness_s"], g["ga_shortest_first_fitness_s"], g["fitness_s"]
        out.append(f"{g['scenario']}, {g['planner_label']}, {g['assignment']}"
                   + (f", rate {g['rate_per_h']:g}/h" if g["rate_per_h"] is not None else "")
                   + f": {got:.1f} s against {base:.1f} s in arrival order "
                   f"({100 * (got - base) / base:+.1f} %) and {sf:.1f} s shortest first "
                   f"({100 * (got - sf) / sf:+.1f} %); {g['evaluations']:.0f} orders planned "
                   f"in {g['order_time_s']:.1f} s")
    return out


def saturation(groups: Sequence[dict]) -> list[str]:
    """For each scenario × planner × assignment × priority swept over two or more rates
    with at least :data:`SATURATION_VEHICLES` vehicles a run, one line: the highest rate
    the lot keeps up with and the lowest it does not (throughput below :data:`SATURATED`
    × the arrival rate, both means over seeds)."""
    lines = []
    series: dict[tuple, list[dict]] = {}
    for g in groups:
        if g["rate_per_h"] is not None and (g["vehicles"] or 0) >= SATURATION_VEHICLES:
            series.setdefault(tuple(g[k] for k in GROUP[:4]), []).append(g)
    for key, gs in series.items():
        if len(gs) < 2:
            continue
        gs = sorted(gs, key=lambda g: g["rate_per_h"])

        def keeps_up(g: dict) -> bool:
            thr, arr = g["throughput_per_h"], g["arrival_rate_per_h"]
            return thr is not None and arr is not None and thr >= SATURATED * arr

        def says(g: dict) -> str:
            return (f"{g['rate_per_h']:g}/h (throughput {_num(g['throughput_per_h'], 0)}/h "
                    f"for {_num(g['arrival_rate_per_h'], 0)}/h arriving, mean time to park "
                    f"{_num(g['mean_time_to_park_s'], 1)} s, mean total waiting "
                    f"{_num(g['total_waiting_s'], 0)} s)")

        first_bad = next((g for g in gs if not keeps_up(g)), None)
        what = " ".join(str(k) for k in key)
        if first_bad is None:
            lines.append(f"{what}: keeps up at every rate, up to {says(gs[-1])}")
            continue
        ok = [g for g in gs if g["rate_per_h"] < first_bad["rate_per_h"] and keeps_up(g)]
        head = f"keeps up at {says(ok[-1])}; " if ok else ""
        lines.append(f"{what}: {head}saturated from {says(first_bad)}")
    return lines


def _num(value: float | None, nd: int) -> str:
    return "–" if value is None else f"{value:.{nd}f}"


def csv_text(rows: Sequence[dict]) -> str:
    """``runs.csv``: a header of :data:`COLUMNS`, one line per run."""
    return _csv(rows, COLUMNS)


def hours_csv_text(hours: Sequence[dict]) -> str:
    """``hours.csv``: a header of :data:`HOURS_COLUMNS`, one line per run and hour
    (``hours``: :func:`hour_rows`)."""
    return _csv(hours, HOURS_COLUMNS)


def _csv(rows: Sequence[dict], columns: Sequence[str]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(columns)
    for r in rows:
        w.writerow([_cell(r.get(k)) for k in columns])
    return buf.getvalue()


def hour_figures(hourly: Sequence[dict]) -> list[dict]:
    """A run's :meth:`~lotsim.sim.results.RunResult.hourly` keyed by :data:`HOUR_FIGURES`,
    rounded as ``runs.csv`` rounds the same figures: what a run's row holds as ``hours``."""
    out = []
    for h in hourly:
        row = {k: h[k.removesuffix("_s")] for k in HOUR_FIGURES}
        for k in HOUR_FIGURES:
            if k in DIGITS:
                row[k] = round(float(row[k]), DIGITS[k])
        out.append(row)
    return out


def hour_rows(rows: Sequence[dict]) -> list[dict]:
    """The rows of ``hours.csv`` (keys :data:`HOURS_COLUMNS`): for each run of ``rows`` (as
    :func:`run_suite` returns them), in grid order, one row per hour of its ``hours``. A run
    that crashed, or whose worker died, has none."""
    return [{**{k: r.get(k) for k in RUN_KEYS}, **h} for r in rows for h in r.get("hours", ())]


def aggregate_hours(hours: Sequence[dict]) -> list[dict]:
    """The hours of each :data:`GROUP` (in grid order) pooled over its seeds: ``hours``
    (:func:`hour_rows`, or :func:`read_hours_csv`) give one dict per group with the
    :data:`GROUP` keys, ``runs`` (how many runs gave hours), ``longest`` (the most hours
    one run spans) and ``by_hour``: for each hour from the group's first to its last, a dict
    of ``hour`` and, for ``cars`` (arrivals), ``median_time_to_park_s``,
    ``p90_time_to_park_s`` and ``standing_per_car_s``, the mean over the runs,
    ``<name>_min`` and ``<name>_max``. Cars are counted over every run (none in an hour
    outside a run's span); the times to park over the runs that parked a car that hour and
    the standing over those that had one come, None where no run did."""
    groups: dict[tuple, dict[int, list[dict]]] = {}
    for h in hours:
        key = (h["scenario"], planner_label(h), h["assignment"], h["priority"], h["rate_per_h"],
               h.get("disturbance") or "none")
        groups.setdefault(key, {}).setdefault(h["run"], []).append(h)
    out = []
    for key, runs in groups.items():
        by_run = {run: {h["hour"]: h for h in hs} for run, hs in runs.items()}
        first = min(min(hs) for hs in by_run.values())
        last = max(max(hs) for hs in by_run.values())
        table = []
        for hour in range(first, last + 1):
            rows = [hs.get(hour) for hs in by_run.values()]
            line: dict[str, Any] = {"hour": hour}
            _pool(line, "cars", [r["arrivals"] if r else 0 for r in rows])
            for k in ("median_time_to_park_s", "p90_time_to_park_s"):
                _pool(line, k, [r[k] for r in rows if r and r["parked"]])
            _pool(line, "standing_per_car_s",
                  [r["standing_per_car_s"] for r in rows if r and r["arrivals"]])
            table.append(line)
        out.append({**dict(zip(GROUP, key, strict=True)), "runs": len(by_run),
                    "longest": max(max(hs) - min(hs) + 1 for hs in by_run.values()),
                    "by_hour": table})
    return out


def _pool(line: dict, name: str, values: Sequence[float]) -> None:
    vals = [float(v) for v in values if v is not None]
    line[name] = float(np.mean(vals)) if vals else None
    line[f"{name}_min"] = min(vals) if vals else None
    line[f"{name}_max"] = max(vals) if vals else None
