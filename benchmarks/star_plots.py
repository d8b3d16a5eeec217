"""Random star-shaped plots, one gate each: does ``lotsim layout`` draw a candidate for
every one?

Run: ``python benchmarks/star_plots.py [--seed 101] [--count 40] [--out DIR] [--all]``.

Each plot is a simple polygon of 4 to 10 corners at random angles round a centre, each
corner 0.35 to 1 times a radius of 30 to 60 m from it (60 to 120 m across; concave as
often as not, with spikes and notches), every gap between neighbouring corners' angles
under 160° so that the centre sees the whole outline; its gate stands at a random point
of the boundary, or (one plot in five) exactly on a corner. The plots come from
``numpy.random.default_rng(seed)``, so the same seed gives the same plots on every
machine. With ``--out``, each is written there as a plot file
(``star-<seed>-<k>.yaml``, as ``scenarios/plots/*.yaml``) that ``lotsim layout`` reads.

For each plot it prints its corners, its gate, where the gate stands (on a corner and
the corner's interior angle, or on an edge, whether a reflex corner is beside it), and
whether candidates are drawn (:func:`lotsim.design.search.candidates`'s drawing, with
no candidate prepared): by default it stops at the first candidate drawn, with
``--all`` it draws every one and counts them. Last, how many of the plots drew one. The
counts are the same on every machine; the times are not.
"""

from __future__ import annotations

import argparse
import inspect
import itertools
import math
import time
from pathlib import Path

import numpy as np
from shapely.geometry import Polygon

from lotsim.design.candidates import draw, draw_spine, modules_of, orientations, pitch
from lotsim.design.drawn import Module
from lotsim.design.gates import edge_of, gate_edges
from lotsim.design.plot import PlotSpec
from lotsim.design.plot_yaml import read_plot
from lotsim.design.search import candidates
from lotsim.design.settings import LayoutSettings

MAX_GAP_DEG = 160.0
"""Neighbouring corners are less than this apart in angle round the centre [degrees]."""


def star_plot_text(rng: np.random.Generator, name: str) -> str:
    """The text of one random star-shaped plot (the module's description)."""
    while True:
        n = int(rng.integers(4, 11))
        angles = np.sort(rng.uniform(0.0, 2 * math.pi, n))
        gaps = np.diff(angles, append=angles[0] + 2 * math.pi)
        radius = rng.uniform(30.0, 60.0)
        r = radius * rng.uniform(0.35, 1.0, n)
        pts = np.round(np.column_stack([r * np.cos(angles), r * np.sin(angles)]), 2)
        poly = Polygon(pts)
        if gaps.max() >= math.radians(MAX_GAP_DEG) or not poly.is_valid:
            continue
        if rng.random() < 0.2:
            gate = pts[int(rng.integers(n))]
        else:
            p = poly.exterior.interpolate(rng.uniform(0.0, poly.exterior.length))
            gate = np.array([p.x, p.y])
        corners = ", ".join(f"[{x:g}, {y:g}]" for x, y in pts)
        return (f"name: {name}\n"
                f"description: A random star-shaped plot of {n} corners, one gate.\n"
                f"boundary: [{corners}]\n"
                f"gates: [{{id: g, at: [{float(gate[0])!r}, {float(gate[1])!r}]}}]\n")


def where(plot: PlotSpec) -> str:
    """Where the plot's first gate stands: on a corner (its interior angle), or on an
    edge, how far from its nearer end and that corner's interior angle."""
    pts = np.asarray(plot.boundary, dtype=float)
    ccw = Polygon(pts).exterior.is_ccw
    g = np.asarray(plot.gates[0].at, dtype=float)

    def interior(k: int) -> float:
        (ax, ay), (bx, by) = pts[k] - pts[k - 1], pts[(k + 1) % len(pts)] - pts[k]
        turn = math.atan2(ax * by - ay * bx, ax * bx + ay * by)
        return 180.0 - math.degrees(turn if ccw else -turn)

    k = edge_of(Polygon(pts), g)
    ends = (k, (k + 1) % len(pts))
    d = [float(np.hypot(*(pts[e] - g))) for e in ends]
    near = ends[int(np.argmin(d))]
    if min(d) < 0.05:
        return f"on a {interior(near):.0f}° corner"
    return f"on an edge, {min(d):.1f} m from a {interior(near):.0f}° corner"


def first_drawn(plot: PlotSpec, settings: LayoutSettings) -> bool:
    """Whether any candidate of ``plot`` holds a bay, drawn in the order
    :func:`~lotsim.design.search.candidates` draws them, stopping at the first."""
    along = ((), gate_edges(plot))
    step90 = pitch(Module(90, False, plot.circulation_width), plot)
    for turned in (False, True):
        for module in modules_of(plot):
            step = pitch(module, plot)
            for theta in orientations(plot, settings.orientations):
                for i, inner_first, ringed, edges in itertools.product(
                        range(settings.offsets), (False, True), (True, False), along):
                    c = draw(plot, module, theta, step * i / settings.offsets, inner_first,
                             ringed, edges, **({"turned": True} if turned else {}))
                    if c is not None and c.bays:
                        return True
        for gate in range(len(plot.gates)):
            for i, branches in itertools.product(range(settings.offsets), (False, True)):
                c = draw_spine(plot, gate, step90 * i / settings.offsets, branches,
                               **({"turned": True} if turned else {}))
                if c is not None and c.bays:
                    return True
        if "turned" not in inspect.signature(draw).parameters:
            break  # a lotsim that draws every gate's aisle square
    return False


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=101)
    ap.add_argument("--count", type=int, default=40)
    ap.add_argument("--out", type=Path, help="write each plot here as a plot file")
    ap.add_argument("--all", action="store_true", help="draw and count every candidate")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    settings = LayoutSettings()
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
    drew = 0
    for k in range(args.count):
        name = f"star-{args.seed}-{k}"
        text = star_plot_text(rng, name)
        if args.out:
            (args.out / f"{name}.yaml").write_text(text)
        plot = read_plot(text)
        clock = time.perf_counter()
        if args.all:
            got = len(candidates(plot, settings))
            what = f"{got} candidates"
        else:
            got = first_drawn(plot, settings)
            what = "drawn" if got else "NONE drawn"
        drew += bool(got)
        print(f"{name:>14}  {len(plot.boundary):2d} corners  gate "
              f"({plot.gates[0].at[0]:7.2f}, {plot.gates[0].at[1]:7.2f}) "
              f"{where(plot):<38} {what:<15} {time.perf_counter() - clock:5.2f} s",
              flush=True)
    print(f"{drew} of {args.count} plots (seed {args.seed}) drew a candidate")
    return 0 if drew == args.count else 1


if __name__ == "__main__":
    raise SystemExit(main())
