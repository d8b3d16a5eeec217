"""Laying a plot out: candidates drawn, the bays lotsim's planner finds unusable dropped,
the best run at the plot's demand, ranked (:func:`lay_out`).

1. Every candidate of the plot is drawn (:mod:`lotsim.design.candidates`: each module kind
   the plot allows, each orientation, each offset, either order of rows); drawing is
   geometry only and quick.
2. The candidates are taken in order of the bays their circulation serves, judged roughly
   from their aisles before any maneuver is planned
   (:func:`~lotsim.design.circulation.circulation`: the bays along aisles a gate leads to,
   where every junction has room for its turns) less what their dead ends cost, most first,
   then of bays drawn, and each
   is *prepared*: its
   scenario is built and every bay's parking maneuver planned for every vehicle type, the
   lot's graph built, and reachability worked out, as ``lotsim validate`` does (with the
   on-disk cache as ``lotsim validate`` uses it: laying the same plot out again loads its
   candidates' lots). The bays
   some type cannot reach, park in or leave for an exit are dropped and the rest prepared
   again, until every bay is usable (``lotsim validate --strict`` passes). Candidates are
   independent: they are prepared on the worker pool (:func:`lotsim.core.workers.fork_map`),
   or on a Dask cluster when a client is given (one candidate a task, each on one core of
   the worker that takes it), a batch at a time, and the search stops when no candidate
   left is judged to serve more bays than the ones it keeps have usable
   (:attr:`~lotsim.design.settings.LayoutSettings.compared`), or after
   :attr:`~lotsim.design.settings.LayoutSettings.prepared` candidates.
3. Each candidate, once every bay left is usable, is run with the plot's demand
   (:class:`~lotsim.design.plot.DemandSpec`, by the planner of the settings): mean time
   to park and throughput, and whether ``lotsim check`` passes the run.
4. Ranked by usable bays less what their dead ends cost
   (:attr:`~lotsim.design.settings.LayoutSettings.dead_end_cost`: a loop before a dead end
   of a few bays more), then the length of their dead ends, then mean time to park, then
   throughput, then the order they were drawn in.

How the search searches is :mod:`~lotsim.design.settings`'; a candidate prepared and run
(steps 2 and 3), :mod:`~lotsim.design.preparing`'s; what it finds and how it ranks (step
4), :mod:`~lotsim.design.results`'. This module draws the candidates, orders them and
prepares them until no candidate left is judged to do better.
"""

from __future__ import annotations

import dataclasses
import itertools
import os
import time
from collections.abc import Callable
from typing import Any

from shapely.geometry import Polygon

from lotsim.core.workers import fork_map
from lotsim.design.candidates import draw, draw_spine, modules_of, orientations, pitch
from lotsim.design.circulation import circulation
from lotsim.design.drawn import Candidate, Module
from lotsim.design.gates import gate_edges
from lotsim.design.plot import PlotSpec
from lotsim.design.preparing import evaluate
from lotsim.design.results import Evaluation, LayoutResult
from lotsim.design.settings import LayoutSettings
from lotsim.errors import ScenarioError


def candidates(plot: PlotSpec, settings: LayoutSettings) -> list[Candidate]:
    """Every candidate of ``plot`` (drawn, not checked), in a fixed order: ring candidates by
    module kind, orientation, offset, order of rows, islands ringed or not, the ring inside
    perimeter rows everywhere or beside the boundary along the gates' edges
    (:func:`~lotsim.design.gates.gate_edges`); then spine
    candidates by gate, offset of branches, order of rows; a candidate drawn alike by other
    choices, once. Each candidate that draws nothing with the gates' aisles square to the
    boundary is drawn again, after all those, with the aisles of the gates where the square
    one cannot be drawn turned, straight or bent once (``turned`` of
    :func:`~lotsim.design.candidates.draw` and
    :func:`~lotsim.design.candidates.draw_spine`).

    Examples
    --------
    >>> from lotsim.design.plot_yaml import read_plot
    >>> plot = read_plot("boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]\\n"
    ...                  "gates: [{id: in, at: [30, 0]}]\\nbays: {angles_deg: [90]}\\n")
    >>> drawn = candidates(plot, LayoutSettings(orientations=1, offsets=1))
    >>> [(c.bays, "spine" if c.spine else "along" if c.along else "ring") for c in drawn]
    [(73, 'ring'), (70, 'along'), (24, 'spine'), (74, 'spine'), (72, 'spine')]
    """
    out = []
    seen: set[tuple] = set()

    def keep(c: Candidate | None) -> None:
        """``c`` among the candidates, unless it holds no bay or looks like one kept."""
        if c is None or c.bays == 0:
            return
        shape = _shape(c)
        if shape not in seen:
            seen.add(shape)
            out.append(c)

    along = ((), gate_edges(plot))
    drawings = []  # (how it is drawn, its choices), in the order drawn
    for module in modules_of(plot):
        step = pitch(module, plot)
        for theta in orientations(plot, settings.orientations):
            for i, inner_first, ringed, edges in itertools.product(
                    range(settings.offsets), (False, True), (True, False), along):
                drawings.append((draw, (plot, module, theta, step * i / settings.offsets,
                                        inner_first, ringed, edges)))
    # spines from each gate, for plots too small or too narrow for a ring
    step = pitch(Module(90, False, plot.circulation_width), plot)
    for gate in range(len(plot.gates)):
        for i, branches, first in itertools.product(range(settings.offsets), (False, True),
                                                    (True, False)):
            if not branches and (i or not first):
                continue
            drawings.append((draw_spine, (plot, gate, step * i / settings.offsets, branches,
                                          first)))
    # with the gates' aisles square to the boundary; those that draw nothing, again with
    # the aisles turned where they cannot be square (a gate at an acute corner, in a
    # spike, on the edge of a notch), after
    failed = []
    for how, choices in drawings:
        c = how(*choices)
        if c is None or c.bays == 0:
            failed.append((how, choices))
        keep(c)
    for how, choices in failed:
        keep(how(*choices, turned=True))
    return out


def _shape(c: Candidate) -> tuple:
    """What a candidate looks like, whatever choices drew it: its aisles (each way they
    are driven) and its bays, to the centimetre."""
    def pt(p) -> tuple[float, float]:
        return round(p[0], 2) + 0.0, round(p[1], 2) + 0.0

    aisles = sorted((pt(a.start), pt(a.end)) if a.one_way else tuple(sorted((pt(a.start),
                                                                             pt(a.end))))
                    for a in c.aisles)
    bays = sorted(pt(b.centroid.coords[0]) for r in c.rows for b in r.polygons)
    return tuple(aisles), tuple(bays)


def lay_out(plot: PlotSpec, settings: LayoutSettings | None = None, *, keep: int = 1,
            progress: Callable[[int, int], None] | None = None,
            client: Any = None) -> LayoutResult:
    """Lay ``plot`` out (the module's description): the prepared candidates, best first.

    The search stops early when no candidate left is judged to serve more bays than the
    best ``keep`` (or :attr:`~lotsim.design.settings.LayoutSettings.compared`, if more)
    found have usable (or the last of those found, when fewer hold a usable bay).
    ``progress(done, total)`` is called as candidates are prepared; ``total`` is the
    most that will be, and becomes ``done`` when the search ends. With ``client`` (a
    :class:`distributed.Client`, :func:`lotsim.bench.connect`) the candidates are prepared
    on its Dask cluster, as many at a time as it has worker threads, instead of on
    ``settings.workers`` local processes: the same candidates, the same answers.

    Raises
    ------
    ScenarioError
        When no candidate has a usable bay (the plot is too small or its gates meet no
        aisle).
    """
    settings = settings or LayoutSettings()
    clock = time.perf_counter()
    drawn = candidates(plot, settings)
    judged = [circulation(plot, c) for c in drawn]
    cost = settings.dead_end_cost / 100.0

    def judged_worth(k: int) -> float:
        return judged[k].served - cost * judged[k].dead_end_length

    order = sorted(range(len(drawn)), key=lambda k: (-round(judged_worth(k), 2),
                                                     -drawn[k].bays, k))
    area = Polygon(plot.boundary).area
    budget = min(settings.prepared, len(order))
    done: list[Evaluation] = []
    workers = settings.workers
    batch = max(1, _threads(client) if client is not None else workers or _cores())
    if progress is not None:
        progress(0, budget)
    pos = 0
    enough = max(keep, settings.compared)
    while pos < budget:
        # a candidate that misses the standard asked for ranks below every one that meets it
        # the ones kept: the best `enough`, or as many as hold a usable bay
        best = sorted((e.worth for e in done if e.met is not False and e.ok), reverse=True)
        if best and judged_worth(order[pos]) < best[min(enough, len(best)) - 1] - 1e-9:
            if progress is not None:  # done: no candidate left is judged to beat them
                progress(len(done), len(done))
            break
        picks = order[pos: min(budget, pos + batch)]
        if client is None:
            found = fork_map(lambda k: evaluate(plot, drawn[k], k, area, settings), picks,
                             workers=workers)
        else:
            found = _on_cluster(client, [(plot, drawn[k], k, area, settings) for k in picks])
        done += [dataclasses.replace(e, served=judged[k].served,
                                     dead_end_length=judged[k].dead_end_length,
                                     dead_end_cost=settings.dead_end_cost)
                 for k, e in zip(picks, found, strict=True)]
        pos += len(picks)
        if progress is not None:
            progress(len(done), budget if pos < budget else len(done))
    good = [e for e in done if e.ok]
    if not good:
        why = "; ".join(sorted({e.problem for e in done if e.problem}))[:400]
        raise ScenarioError(None, f"{plot.source}: no layout of this plot has a usable bay"
                            + (f" ({why})" if why else " (no room for a ring or a spine "
                               "aisle with a row of bays, or no gate meets an aisle)"))
    return LayoutResult(plot, settings, tuple(sorted(done, key=Evaluation.rank_key)),
                        len(drawn), time.perf_counter() - clock)


def _cores() -> int:
    return os.cpu_count() or 1


def _threads(client: Any) -> int:
    """How many tasks the cluster of ``client`` works on at once: its workers' threads."""
    return sum(client.nthreads().values())


def evaluate_job(job: tuple[PlotSpec, Candidate, int, float, LayoutSettings]) -> Evaluation:
    """:func:`~lotsim.design.preparing.evaluate` of one ``(plot, candidate, index, area,
    settings)``: a cluster worker's task (it pickles by name)."""
    return evaluate(*job)


def _on_cluster(client: Any, jobs: list[tuple]) -> list[Evaluation]:
    """:func:`evaluate_job` of each of ``jobs`` on the Dask cluster of ``client``, in their
    order; a candidate whose worker was lost fails, saying so."""
    from lotsim.bench.runner import run_all

    found: dict[int, Evaluation] = {}

    def take(k: int, e: Evaluation) -> None:
        found[k] = e

    def lost(k: int, exc: BaseException) -> Evaluation:
        plot, cand, index, area, _ = jobs[k]
        return Evaluation(index=index, label=cand.label, drawn=cand.bays, area=area,
                          aisle_length=cand.aisle_length, bays=0,
                          problem=f"its worker was lost ({exc!r})")

    run_all(evaluate_job, jobs, take, lost, client=client)
    return [found[k] for k in range(len(jobs))]


__all__ = ["lay_out", "candidates"]
