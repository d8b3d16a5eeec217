"""What a suite run writes and prints: ``summary.md`` (:func:`summary_markdown`), the
terminal table (:func:`table_text`) and its tables by hour (:func:`hours_text`), and every
output (:func:`write_outputs`)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from lotsim import __version__
from lotsim.bench.suite import Suite
from lotsim.bench.table import (
    SATURATED,
    _num,
    aggregate,
    aggregate_hours,
    csv_text,
    ga_gains,
    hour_rows,
    hours_csv_text,
    planner_label,
    saturation,
)
from lotsim.core.atomic import atomic_write
from lotsim.sim.results import HOURLY_FROM

_TABLE = (  # (summary key, heading, digits)
    ("parked", "parked", 1), ("departed", "departed", 1), ("rejected", "rejected", 1),
    ("waiting", "waiting", 1), ("mean_time_to_park_s", "time to park mean [s]", 1),
    ("max_time_to_park_s", "max [s]", 1), ("total_waiting_s", "total waiting [s]", 1),
    ("makespan_s", "makespan [s]", 0), ("arrival_rate_per_h", "arriving [veh/h]", 0),
    ("throughput_per_h", "throughput [veh/h]", 0), ("expansions", "expansions", 0),
    ("planning_median_ms", "planning median [ms]", 1), ("planning_p95_ms", "p95 [ms]", 1),
    ("peak_memory_mb", "peak memory [MB]", 0),
)
_DISTURBED = (("median_time_to_park_s", "time to park median [s]", 1),
              ("p90_time_to_park_s", "p90 [s]", 1), ("standing_per_car_s", "standing/car [s]", 1),
              ("replans", "replans", 1), ("stalls", "stalls", 1))
_ORDERED = (("fitness_s", "total time to park [s]", 1), ("evaluations", "evaluations", 0),
            ("order_time_s", "order time [s]", 2))
_IDENT = (("scenario", "scenario"), ("planner_label", "planner"), ("assignment", "assignment"),
          ("priority", "priority"), ("rate_per_h", "rate [veh/h]"),
          ("disturbance", "disturbances"))


def _varying(groups: Sequence[dict]) -> tuple[list[tuple[str, str]], list[str]]:
    """The identity columns that differ between groups, and ``key value`` for the others."""
    vary, fixed = [], []
    for key, head in _IDENT:
        values = list(dict.fromkeys(g[key] for g in groups))
        if len(values) > 1 or key in ("scenario", "planner_label"):
            vary.append((key, head))
        else:
            fixed.append(f"{head} {_ident(values[0])}")
    return vary, fixed


def _ident(value: Any) -> str:
    if value is None:
        return "as in the scenario"
    return f"{value:g}" if isinstance(value, float) else str(value)


PLOTTED = (("throughput_per_h", "throughput.png", "throughput"),
           ("mean_time_to_park_s", "time_to_park.png", "time to park"),
           ("expansions", "expansions.png", "expansions"),
           ("planning_time_s", "planning_time.png", "planning time"))
"""Each plot of a suite's outputs: the column of means it draws, its file and its title.
Planners that tie on what the cars get (throughput, time to park) differ in what the
planning cost (expansions, planning time)."""
PLOTS = tuple(name for _, name, _ in PLOTTED)
"""The plots a suite's outputs hold (with matplotlib)."""


def summary_markdown(suite: Suite, rows: Sequence[dict], *, where: str = "",
                     plots: bool = True) -> str:
    """``summary.md``: the suite, the means over seeds, saturation, failed runs, and the
    plots when they are drawn (``plots``)."""
    groups = aggregate(rows)
    vary, fixed = _varying(groups)
    failed = [r for r in rows if not r["ok"]]
    unsolved = sum(not r["solved"] for r in rows)
    rates = ("as in each scenario" if suite.rates_per_hour is None
             else ", ".join(f"{r:g}" for r in suite.rates_per_hour) + " vehicles/h")
    lines = [f"# Benchmark `{suite.name}`", ""]
    if suite.description:
        lines += [suite.description, ""]
    ga = ", ".join(f"{k} {v}" for k, v in suite.ga)
    lines += [
        f"- suite: `{suite.source}`",
        f"- scenarios: {', '.join(f'{s.name} (`{Path(s.file).name}`)' for s in suite.scenarios)}",
        f"- planners: {', '.join(p.label for p in suite.planners)}; assignments: "
        f"{', '.join(suite.assignments)}; priorities: {', '.join(suite.priorities)}"
        + (f" (GA: {ga})" if ga else "")
        + (f"; booked orders know arrivals {suite.horizon:g} s ahead"
           if set(suite.priorities) & {"shortest_first", "ga"} else ""),
        f"- arrival rates: {rates}" + (f"; {suite.count} vehicles" if suite.count else ""),
        f"- seeds: {', '.join(str(s) for s in suite.seeds)}",
        f"- {len(rows)} runs: {len(rows) - len(failed)} pass `lotsim check`, "
        f"{len(failed)} fail; {len(rows) - unsolved} solved (no vehicle left waiting)",
        f"- lotsim {__version__}" + (f"; {where}" if where else ""),
        "",
        "## Means over seeds",
        "",
    ]
    if fixed:
        lines += ["All runs: " + "; ".join(fixed) + ".", ""]
    extra = _ORDERED if any(p != "arrival" for p in suite.priorities) else ()
    if any(d is not None for _, d in suite.disturbances):
        extra = (*extra, *_DISTURBED)
    cols = [*_TABLE, *extra]
    head = [h for _, h in vary] + ["runs", "ok", "solved"] + [h for _, h, _ in cols]
    lines.append("| " + " | ".join(head) + " |")
    lines.append("|" + "|".join("---" if i < len(vary) else "---:"
                                for i in range(len(head))) + "|")
    for g in groups:
        cells = [_ident(g[k]) for k, _ in vary] + [str(g["runs"]), str(g["ok"]),
                                                   str(g["solved"])]
        cells += [_num(g[k], nd) for k, _, nd in cols]
        lines.append("| " + " | ".join(cells) + " |")
    gains = ga_gains(groups)
    if gains:
        lines += ["", "## The GA's gain", "",
                  "Total time to park of the GA's order against the arrival and shortest-first "
                  "orders it started from, planned with the same booking horizon in the same "
                  "run (means over seeds), and what the search cost:", ""]
        lines += [f"- {s}" for s in gains]
    sat = saturation(groups)
    if sat:
        lines += ["", "## Saturation", "",
                  f"Saturated: throughput below {SATURATED:.0%} of the arrival rate "
                  "(means over seeds).", ""]
        lines += [f"- {s}" for s in sat]
    lines += ["", "## Failed runs", ""]
    if not failed:
        lines.append("None: every run passes `lotsim check`.")
    for r in failed:
        lines.append(f"- run {r['run']} ({r['scenario']}, {planner_label(r)}, {r['assignment']}, "
                     f"{r['priority']}, rate {_ident(r['rate_per_h'])}, seed {r['seed']}): "
                     f"{r['problem'] or 'failed'}")
    lines += ["", "## Plots", ""]
    lines += ([line for _, name, title in PLOTTED for line in (f"![{title}]({name})", "")][:-1]
              if plots else ["None: they need matplotlib (`pip install 'lotsim[plot]'`)."])
    lines += ["", "Columns and definitions: `docs/bench.md` in lotsim.", ""]
    return "\n".join(lines)


def table_text(rows: Sequence[dict]) -> str:
    """The means over seeds as a compact plain-text table for the terminal."""
    groups = aggregate(rows)
    vary, fixed = _varying(groups)
    cols = (("ok", "ok", None), ("served", "served", 1), ("rejected", "rej", 1),
            ("waiting", "wait", 1), ("mean_time_to_park_s", "park s", 1),
            ("max_time_to_park_s", "max s", 1), ("total_waiting_s", "waited s", 0),
            ("throughput_per_h", "veh/h", 0), ("planning_p95_ms", "p95 ms", 0))
    head = [h for _, h in vary] + [h for _, h, _ in cols]
    body = []
    for g in groups:
        cells = [_ident(g[k]) for k, _ in vary]
        for k, _, nd in cols:
            cells.append(f"{g['ok']}/{g['runs']}" if k == "ok" else _num(g[k], nd))
        body.append(cells)
    widths = [max(len(x) for x in col) for col in zip(head, *body, strict=True)]
    n_id = len(vary)

    def line(cells: list[str]) -> str:
        return "  ".join(c.ljust(w) if i < n_id else c.rjust(w)
                         for i, (c, w) in enumerate(zip(cells, widths, strict=True))).rstrip()

    out = ["  " + line(head)] + ["  " + line(c) for c in body]
    if fixed:
        out.insert(0, "  all runs: " + "; ".join(fixed))
    return "\n".join(out)


def hours_text(hours: Sequence[dict]) -> str:
    """For each row of the terminal table whose runs' cars came over :data:`HOURLY_FROM`
    hours of the clock or more (one run is enough), a table by the hour the cars came,
    pooled over the seeds (:func:`~lotsim.bench.table.aggregate_hours`): the cars, the
    median and 90th percentile of the time to park and the standing per car [s], each the
    mean over the seeds with the smallest and the largest seed's figure in brackets where
    they differ (``–``: no car of that hour parked, or came). ``""`` when no row's traffic
    is that long. ``hours``: the rows of ``hours.csv``
    (:func:`~lotsim.bench.table.hour_rows` of the rows :func:`run_suite` returns, or
    :func:`~lotsim.bench.table.read_hours_csv`).

    Examples
    --------
    >>> hours_text([])
    ''
    """
    groups = aggregate_hours(hours)
    if not groups:
        return ""
    vary, _ = _varying(groups)
    out = []
    for g in groups:
        if g["longest"] < HOURLY_FROM:
            continue
        seeds = "1 seed" if g["runs"] == 1 else f"means over {g['runs']} seeds (min–max)"
        out.append(f"  {', '.join(_ident(g[k]) for k, _ in vary)}: by the hour the cars "
                   f"came, {seeds}")
        head = ["hour", "cars", "park median s", "park p90 s", "standing/car s"]
        body = [[f"{h['hour']:02d}–{h['hour'] + 1:02d} h", _spread(h, "cars", 1, 0)]
                + [_spread(h, k, 1, 1) for k in ("median_time_to_park_s", "p90_time_to_park_s",
                                                  "standing_per_car_s")]
                for h in g["by_hour"]]
        widths = [max(len(x) for x in col) for col in zip(head, *body, strict=True)]
        for cells in [head, *body]:
            out.append("    " + "  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w)
                                          in enumerate(zip(cells, widths, strict=True)))
                       .rstrip())
    return "\n".join(out)


def _spread(h: dict, name: str, nd: int, nd_ends: int) -> str:
    """``mean (min–max)`` of a pooled figure, the mean alone where the runs agree or there
    is one; ``–`` where no run had one."""
    mean, lo, hi = h[name], h[f"{name}_min"], h[f"{name}_max"]
    if mean is None:
        return "–"
    if lo == hi:
        return f"{mean:.{nd_ends}f}"
    return f"{mean:.{nd}f} ({lo:.{nd_ends}f}–{hi:.{nd_ends}f})"


def write_outputs(suite: Suite, rows: Sequence[dict], outdir: str | os.PathLike, *,
                  where: str = "", plots: bool = True) -> list[Path]:
    """Write ``runs.csv``, ``hours.csv`` (each run's ``hours``: none for rows that hold
    none, as those :func:`~lotsim.bench.table.read_csv` reads), ``summary.md`` and (with
    matplotlib and ``plots``) the :data:`PLOTS` to ``outdir``, each atomically; returns the
    paths written."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    with atomic_write(out / "runs.csv", "w", encoding="utf-8") as fh:
        fh.write(csv_text(rows))
    written.append(out / "runs.csv")
    with atomic_write(out / "hours.csv", "w", encoding="utf-8") as fh:
        fh.write(hours_csv_text(hour_rows(rows)))
    written.append(out / "hours.csv")
    with atomic_write(out / "summary.md", "w", encoding="utf-8") as fh:
        fh.write(summary_markdown(suite, rows, where=where, plots=plots))
    written.append(out / "summary.md")
    if plots:
        from lotsim.bench.plots import bench_figure
        from lotsim.render.plots import save_figure

        for metric, name, _ in PLOTTED:
            save_figure(bench_figure(rows, metric), out / name)
            written.append(out / name)
    else:  # the outputs are one set: no plot of an earlier suite run stays beside them
        for name in PLOTS:
            (out / name).unlink(missing_ok=True)
    return written
