"""The bench plots (matplotlib), beside the run's plots (:mod:`lotsim.render.plots`): a
metric per scenario against the arrival rate or per planner (:func:`bench_figure`, also
``lotsim.bench.bench_figure``). matplotlib and the bench's table are imported only when a
figure is made."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure



_YLABEL = {"throughput_per_h": "throughput [vehicles/h]",
           "mean_time_to_park_s": "mean time to park [s]",
           "expansions": "search expansions per run", "planning_time_s": "planning time [s]"}


def bench_figure(rows: Sequence[dict], metric: str) -> Figure:
    """``metric`` (a column of :data:`MEANS`) per scenario, one axes each, mean over seeds
    with min–max whiskers.

    Against the arrival rate (one line per planner; per assignment and priority too when
    the suite has several, told apart by line style) where a scenario is run at two rates
    or more; otherwise as bars per planner, side by side per assignment and priority.
    A throughput plot against the rate also draws the arrival rate itself (dotted): a line
    below it is a lot that does not keep up.

    Raises
    ------
    lotsim.render.plots.MatplotlibMissing
    """
    from lotsim.bench.table import aggregate
    from lotsim.render.plots import require_matplotlib

    require_matplotlib()
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    groups = aggregate(rows)
    scenarios = list(dict.fromkeys(g["scenario"] for g in groups))
    fig = Figure(figsize=(6.0 * len(scenarios) + 1.5, 4.5), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)  # our own canvas: no pyplot, no backend switch (as lotsim.render.plots)
    axes = fig.subplots(1, len(scenarios), squeeze=False)[0]
    planners = list(dict.fromkeys(g["planner_label"] for g in groups))
    ways = list(dict.fromkeys((g["assignment"], g["priority"]) for g in groups))
    several = len(ways) > 1
    ways = _way_labels(ways)
    colours = matplotlib.colormaps["tab10"].colors
    styles = ("-", "--", ":", "-.")
    for ax, name in zip(axes, scenarios, strict=True):
        gs = [g for g in groups if g["scenario"] == name]
        rates = {g["rate_per_h"] for g in gs}
        if len(rates) > 1 and None not in rates:
            _lines(ax, gs, metric, planners, ways, colours, styles, several)
        else:
            _bars(ax, gs, metric, planners, ways, colours, several)
        ax.set_title(name)
        ax.set_ylabel(_YLABEL.get(metric, metric))
        ax.grid(alpha=0.3)
        ax.set_axisbelow(True)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
    return fig


def _way_labels(ways: Sequence[tuple[str, str]]) -> dict[tuple[str, str], str]:
    """``shortest``, ``nearest, ga``: the parts of (assignment, priority) that vary."""
    vary = [k for k in range(2) if len({w[k] for w in ways}) > 1]
    return {w: ", ".join(w[k] for k in vary) for w in ways}


def _spread(gs: Sequence[dict], metric: str) -> tuple[np.ndarray, np.ndarray]:
    mean = np.array([np.nan if g[metric] is None else g[metric] for g in gs], dtype=float)
    lo = np.array([np.nan if g[f"{metric}_min"] is None else g[f"{metric}_min"] for g in gs])
    hi = np.array([np.nan if g[f"{metric}_max"] is None else g[f"{metric}_max"] for g in gs])
    # a mean can land a rounding error outside its own min and max: whiskers never negative
    return mean, np.clip(np.vstack([mean - lo, hi - mean]), 0.0, None)


def _lines(ax, gs, metric, planners, ways, colours, styles, several) -> None:
    for p in planners:
        for w in ways:
            line = sorted((g for g in gs if g["planner_label"] == p
                           and (g["assignment"], g["priority"]) == w),
                          key=lambda g: g["rate_per_h"])
            if not line:
                continue
            x = np.array([g["rate_per_h"] for g in line])
            mean, err = _spread(line, metric)
            ax.errorbar(x, mean, yerr=err, color=colours[planners.index(p) % len(colours)],
                        linestyle=styles[list(ways).index(w) % len(styles)], marker="o", ms=4,
                        capsize=3, label=p + (f" ({ways[w]})" if several else ""))
    x_all = sorted({g["rate_per_h"] for g in gs})
    if metric == "throughput_per_h":
        ax.plot(x_all, x_all, color="0.5", linestyle=":", label="arrival rate")
    if x_all[-1] / x_all[0] >= 8:
        ax.set_xscale("log")
        ax.set_xticks(x_all, [f"{x:g}" for x in x_all])
        ax.minorticks_off()
    values = [g[metric] for g in gs if g[metric]]
    if metric != "throughput_per_h" and values and max(values) / min(values) > 50:
        ax.set_yscale("log")
    ax.set_xlabel("arrival rate [vehicles/h]")


def _bars(ax, gs, metric, planners, ways, colours, several) -> None:
    width = 0.8 / len(ways)
    for k, w in enumerate(ways):
        bars = [next((g for g in gs if g["planner_label"] == p
                      and (g["assignment"], g["priority"]) == w), None) for p in planners]
        xs = [i + (k - (len(ways) - 1) / 2) * width for i, b in enumerate(bars) if b]
        have = [b for b in bars if b]
        if not have:
            continue
        mean, err = _spread(have, metric)
        colour = (colours[k % len(colours)] if several
                  else [colours[planners.index(b["planner_label"]) % len(colours)]
                        for b in have])
        ax.bar(xs, mean, width=width * 0.9, yerr=err, capsize=3, color=colour,
               label=ways[w] if several else None)
    ax.set_xticks(range(len(planners)), planners)
    rates = {g["rate_per_h"] for g in gs}
    rate = next(iter(rates)) if len(rates) == 1 else None
    ax.set_xlabel("planner" + (f" (arrival rate {rate:g} vehicles/h)" if rate else ""))
