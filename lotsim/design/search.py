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
   a batch at a time, and the search stops when no candidate left is judged to serve more
   bays than the ones it keeps have usable (:attr:`LayoutSettings.compared`), or after
   :attr:`LayoutSettings.prepared` candidates.
3. Each candidate, once every bay left is usable, is run with the plot's demand
   (:class:`~lotsim.design.plot.DemandSpec`, by the planner of the settings): mean time
   to park and throughput, and whether ``lotsim check`` passes the run.
4. Ranked by usable bays less what their dead ends cost
   (:attr:`LayoutSettings.dead_end_cost`: a loop before a dead end of a few bays more),
   then the length of their dead ends, then mean time to park, then throughput, then the
   order they were drawn in.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass

from shapely.geometry import Polygon

from lotsim import __version__
from lotsim.core.checks import range_problem
from lotsim.core.units import LENGTH_UNITS
from lotsim.core.workers import fork_map
from lotsim.design.allocation import Allocation, Key, Stretch, allocate, stretches
from lotsim.design.candidates import draw, draw_spine, modules_of, orientations, pitch
from lotsim.design.circulation import circulation
from lotsim.design.drawn import Candidate, Module
from lotsim.design.gates import gate_edges
from lotsim.design.plot import PlotSpec
from lotsim.errors import ScenarioError, SettingsError
from lotsim.io.imports.draft import (
    AisleDraft,
    AreaDraft,
    GateDraft,
    LotDraft,
    RowDraft,
    comment,
    num,
    text,
)
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import parse_scenario
from lotsim.io.yamlnodes import parse_text
from lotsim.lot.uses import MARKS, USES
from lotsim.sim.orders import plan_run
from lotsim.sim.preparation import prepare_lot
from lotsim.sim.settings import PLANNERS, RunSettings
from lotsim.sim.validation import validate_prepared
from lotsim.verify import check_result

ROUNDS = 4
"""A candidate is prepared at most this many times while unusable bays are dropped."""


@dataclass(frozen=True, slots=True)
class LayoutSettings:
    """How :func:`lay_out` searches (each field changes what it may find; the written lot
    names them).

    Attributes
    ----------
    orientations : int
        Most directions module aisles are tried in: along and square to the boundary's
        edges, longest edges first.
    offsets : int
        Module offsets tried per orientation, spread evenly over one module pitch.
    prepared : int
        Most candidates prepared (their bays checked by the maneuver planner) and run at
        the plot's demand.
    compared : int
        The search stops early once no candidate left is judged to beat this many
        candidates it holds (or as many as are written; or all it holds with a usable bay,
        when fewer): a candidate's circulation serves fewer bays than they have usable.
        The candidates set side by side.
    planner : str
        The cooperative planner of those runs (:data:`lotsim.sim.settings.PLANNERS`).
    workers : int or None
        Worker processes (None: one per core).
    dead_end_cost : float
        What 100 m of dead-end aisle costs a layout in the ranking, in bays [bays per
        100 m]: a layout ranks by its usable bays less this for its dead ends, so that a
        loop comes before a dead end of a few bays more (0: bays alone).

    Examples
    --------
    >>> LayoutSettings(offsets=2).describe()
    'orientations 4, offsets 2, prepared 8, compared 4, planner hca, dead ends 2 bays per 100 m'
    >>> LayoutSettings(orientations=0)
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: orientations: expected 1 to 64, found 0
    """

    orientations: int = 4
    offsets: int = 3
    prepared: int = 8
    compared: int = 4
    planner: str = "hca"
    workers: int | None = None
    dead_end_cost: float = 2.0

    def __post_init__(self) -> None:
        for name, lo, hi in (("orientations", 1, 64), ("offsets", 1, 32),
                             ("prepared", 1, 1000), ("compared", 1, 1000)):
            value = getattr(self, name)
            problem = range_problem(value, lo, hi, "") if isinstance(value, int) and \
                not isinstance(value, bool) else f"expected an integer, found {value!r}"
            if problem:
                raise SettingsError(name, problem)
        if self.planner not in PLANNERS:
            raise SettingsError("planner", f"expected one of {', '.join(PLANNERS)}, found "
                                           f"{self.planner!r}")
        cost = self.dead_end_cost
        if isinstance(cost, bool) or not isinstance(cost, (int, float)) or \
                not 0.0 <= cost <= 1000.0:
            raise SettingsError("dead_end_cost", f"expected 0 to 1000 bays per 100 m, found "
                                                 f"{cost!r}")
        if self.workers is not None and not (isinstance(self.workers, int)
                                             and 1 <= self.workers <= 256):
            raise SettingsError("workers", f"expected 1 to 256, found {self.workers!r}")

    def describe(self) -> str:
        return (f"orientations {self.orientations}, offsets {self.offsets}, prepared "
                f"{self.prepared}, compared {self.compared}, planner {self.planner}, "
                f"dead ends {self.dead_end_cost:g} bays per 100 m")


@dataclass(frozen=True, slots=True)
class Evaluation:
    """One candidate, prepared (and perhaps run).

    Attributes
    ----------
    index : int
        Its place in the order candidates were drawn.
    label : str
        How it was drawn (module kind, orientation, offset, order of rows).
    drawn : int
        Bays drawn.
    bays : int
        Bays every vehicle type can reach, park in and leave (0 when it failed).
    aisle_length : float
        Aisle centre lines in all [m].
    area : float
        The plot's area [m²].
    yaml : str
        The scenario of its usable bays (``""`` when it failed).
    problem : str
        Why it failed (``""`` when it did not).
    mean_time_to_park : float or None
        From the run at the plot's demand [s] (None: not run).
    throughput : float or None
        Cars parked per hour in that run: those parked over the time from the first
        arrival to the last parking.
    parked, vehicles : int
        Cars parked in that run, of those that came.
    checked : bool or None
        Whether ``lotsim check`` passed that run (None: not run).
    seconds : float
        Time spent on it.
    by_use : tuple of (use, bays)
        Its bays by use, every use (:data:`~lotsim.lot.uses.USES`), as ``lotsim validate``
        counts them; () where the plot asks for no uses.
    met : bool or None
        Whether its bays meet ADA 2010 (Table 208.2 and §208.2.4) as ``lotsim validate``
        checks them; None where the plot asks for no accessible bays.
    short : tuple of (use, bays)
        The bays by use asked for that it has no room for.
    served : int
        The bays its circulation was judged to serve before it was prepared
        (:func:`~lotsim.design.circulation.circulation`).
    dead_end_length : float
        Aisle a car comes back along after a dead end, in all [m].
    """

    index: int
    label: str
    drawn: int
    bays: int
    aisle_length: float
    area: float
    yaml: str = ""
    problem: str = ""
    mean_time_to_park: float | None = None
    throughput: float | None = None
    parked: int = 0
    vehicles: int = 0
    checked: bool | None = None
    seconds: float = 0.0
    by_use: tuple[tuple[str, int], ...] = ()
    met: bool | None = None
    short: tuple[tuple[str, int], ...] = ()
    served: int = 0
    dead_end_length: float = 0.0
    dead_end_cost: float = 0.0
    """What 100 m of its dead ends cost it in the ranking [bays]
    (:attr:`LayoutSettings.dead_end_cost`)."""

    @property
    def worth(self) -> float:
        """Its usable bays less what its dead ends cost (:attr:`dead_end_cost`)."""
        return self.bays - self.dead_end_cost * self.dead_end_length / 100.0

    @property
    def ok(self) -> bool:
        return not self.problem and self.bays > 0

    @property
    def bays_per_100m2(self) -> float:
        return 100.0 * self.bays / self.area if self.area else 0.0

    def document(self) -> str:
        """The scenario's text as :func:`lotsim.layout` writes it: :attr:`yaml` with the
        candidate's figures in its header."""
        head, _, rest = self.yaml.partition("\n")
        run = ""
        if self.mean_time_to_park is not None and self.throughput is not None:
            run = (f"; a run of its demand: {self.parked} of {self.vehicles} cars parked, mean "
                   f"time to park {self.mean_time_to_park:.1f} s, {self.throughput:.0f} cars "
                   f"parked per hour, lotsim check {'passed' if self.checked else 'failed'}")
        figures = comment(f"{self.bays} bays, each usable by every vehicle type "
                          f"({self.bays_per_100m2:.2f} per 100 m²), aisles "
                          f"{self.aisle_length:.1f} m{run}.")
        if self.by_use:
            figures += "\n" + comment(f"Bays by use: {self.uses_text()}.")
        return f"{head}\n{figures}\n{rest}"

    def uses_text(self) -> str:
        """Its bays by use in words: ``standard 90, accessible 4, van-accessible 1, EV 10;
        ADA 2010 met``."""
        parts = ", ".join(f"{USES[u].label} {n}" for u, n in self.by_use if n) or "none"
        if self.met is not None:
            parts += f"; ADA 2010 {'met' if self.met else 'not met'}"
        if self.short:
            parts += "; no room for " + ", ".join(f"{n} {USES[u].label}" for u, n in
                                                  self.short)
        return parts

    def rank_key(self) -> tuple:
        """Whether its bays meet ADA 2010 where the plot asks for accessible bays (those
        that do first), then usable bays as laid out, access aisles and all, less what its
        dead ends cost (:attr:`worth`, most first, to the hundredth of a bay), then
        dead-end length (shortest first: a loop before a dead end of as many bays, to the
        decimetre), then mean time to park (shortest first; not run: last), then
        throughput (most first), then the order drawn."""
        t = self.mean_time_to_park if self.mean_time_to_park is not None else math.inf
        q = self.throughput if self.throughput is not None else -math.inf
        return (self.met is False, -round(self.worth, 2), round(self.dead_end_length, 1), t,
                -q, self.index)


@dataclass(frozen=True, slots=True)
class LayoutResult:
    """What :func:`lay_out` found: the candidates it prepared, best first, and how many it
    drew, with the settings that made them."""

    plot: PlotSpec
    settings: LayoutSettings
    ranked: tuple[Evaluation, ...]
    drawn: int
    seconds: float

    @property
    def best(self) -> Evaluation:
        return self.ranked[0]

    def table(self, most: int = 5) -> str:
        """The best ``most`` candidates side by side, a line each: where the plot asks for
        uses, with the bays of each use asked for, and whether ADA 2010 is met (``yes``,
        ``no``; ``-``: no accessible bays asked for)."""
        asked = _columns(self.plot)
        uses = "".join(f"  {title:>{len(title)}}" for _, title in asked)
        head = (f"{'#':>2}  {'bays':>5}  {'drawn':>5}{uses}  {'ADA':>3}  {'per 100 m²':>10}  "
                f"{'aisles [m]':>10}  {'dead ends':>9}  {'park [s]':>8}  {'cars/h':>7}  layout")
        lines = [head]
        for k, e in enumerate(self.ranked[:most]):
            park = f"{e.mean_time_to_park:8.1f}" if e.mean_time_to_park is not None else \
                f"{'-':>8}"
            rate = f"{e.throughput:7.0f}" if e.throughput is not None else f"{'-':>7}"
            what = e.label if e.ok else f"{e.label}: {e.problem}"
            counts = dict(e.by_use)
            cells = "".join(f"  {_use_cell(counts, u, e.ok):>{len(title)}}"
                            for u, title in asked)
            ada = "-" if e.met is None or not e.ok else ("yes" if e.met else "no")
            lines.append(f"{k + 1:>2}  {e.bays:>5}  {e.drawn:>5}{cells}  {ada:>3}  "
                         f"{e.bays_per_100m2:>10.2f}  {e.aisle_length:>10.1f}  "
                         f"{e.dead_end_length:>9.1f}  {park}  "
                         f"{rate}  {what}")
        return "\n".join(lines)


def _columns(plot: PlotSpec) -> list[tuple[str, str]]:
    """The table's columns of bays by use for ``plot``: (use, title), those it asks for."""
    u = plot.uses
    out = []
    if u.accessible_wanted:
        out += [("accessible", "access."), ("van_accessible", "van")]
    if u.ev_wanted:
        out.append(("ev", "EV"))
    if u.compact is not None:
        out.append(("compact", "compact"))
    return out


def _use_cell(counts: dict[str, int], use: str, ok: bool) -> str:
    """A candidate's bays of ``use``; accessible ones with the van-accessible among them, as
    the standard counts them."""
    if not ok:
        return "-"
    n = counts.get(use, 0)
    return str(n + counts.get("van_accessible", 0) if use == "accessible" else n)


def candidates(plot: PlotSpec, settings: LayoutSettings) -> list[Candidate]:
    """Every candidate of ``plot`` (drawn, not checked), in a fixed order: ring candidates by
    module kind, orientation, offset, order of rows, islands ringed or not, the ring inside
    perimeter rows everywhere or beside the boundary along the gates' edges
    (:func:`~lotsim.design.gates.gate_edges`); then spine
    candidates by gate, offset of branches, order of rows; a candidate drawn alike by other
    choices, once.

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
    for module in modules_of(plot):
        step = pitch(module, plot)
        for theta in orientations(plot, settings.orientations):
            for i, inner_first, ringed, edges in itertools.product(
                    range(settings.offsets), (False, True), (True, False), along):
                keep(draw(plot, module, theta, step * i / settings.offsets, inner_first,
                          ringed, edges))
    # spines from each gate, for plots too small or too narrow for a ring
    step = pitch(Module(90, False, plot.circulation_width), plot)
    for gate in range(len(plot.gates)):
        for i, branches, first in itertools.product(range(settings.offsets), (False, True),
                                                    (True, False)):
            if not branches and (i or not first):
                continue
            keep(draw_spine(plot, gate, step * i / settings.offsets, branches, first))
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
            progress: Callable[[int, int], None] | None = None) -> LayoutResult:
    """Lay ``plot`` out (the module's description): the prepared candidates, best first.

    The search stops early when no candidate left is judged to serve more bays than the
    best ``keep`` (or :attr:`LayoutSettings.compared`, if more) found have usable (or the
    last of those found, when fewer hold a usable bay).
    ``progress(done, total)`` is called as candidates are prepared; ``total`` is the
    most that will be, and becomes ``done`` when the search ends.

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
    batch = max(1, workers or _cores())
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
        done += [dataclasses.replace(e, served=judged[k].served,
                                     dead_end_length=judged[k].dead_end_length,
                                     dead_end_cost=settings.dead_end_cost)
                 for k, e in zip(picks, fork_map(
                     lambda k: evaluate(plot, drawn[k], k, area, settings), picks,
                     workers=workers), strict=True)]
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


def evaluate(plot: PlotSpec, cand: Candidate, index: int, area: float,
             settings: LayoutSettings) -> Evaluation:
    """Prepare ``cand``, dropping its unusable bays until every one left is usable, allot
    the bays by use the plot asks for (:func:`~lotsim.design.allocation.allocate`) and
    settle them likewise, and run it at the plot's demand (:class:`Evaluation`)."""
    clock = time.perf_counter()
    keep: set[Key] | None = None
    figures = dict(index=index, label=cand.label, drawn=cand.bays, area=area,
                   aisle_length=cand.aisle_length)
    for _ in range(ROUNDS):
        yaml_text, ids = scenario_text(plot, cand, keep, settings)
        got = _prepared_text(plot, yaml_text, ids, figures, clock)
        if isinstance(got, Evaluation):
            return got
        sc, prepared, report = got
        usable = _usable(report)
        if report.complete and usable == set(ids):
            if plot.uses.accessible_wanted or plot.uses.ev_wanted:
                return _allot(plot, cand, set(ids.values()), settings, figures, clock)
            return _run(sc, prepared, settings,
                        Evaluation(bays=len(ids), yaml=yaml_text, **figures,
                                   **_use_figures(plot, report)), clock)
        keep = {ids[s] for s in usable}
    return Evaluation(bays=0, problem="its bays did not settle",
                      seconds=time.perf_counter() - clock, **figures)


def _prepared_text(plot: PlotSpec, yaml_text: str, ids: dict, figures: dict, clock: float):
    """A candidate's scenario text prepared, ``(scenario, prepared, report)``, or the
    :class:`Evaluation` of why it cannot be: no bay in it, or a scenario lotsim refuses."""
    if not ids:
        return Evaluation(bays=0, problem="no bay is usable",
                          seconds=time.perf_counter() - clock, **figures)
    try:
        return _prepare(plot, yaml_text)
    except ScenarioError as exc:
        return Evaluation(bays=0, problem=_short(str(exc)),
                          seconds=time.perf_counter() - clock, **figures)


def _allot(plot: PlotSpec, cand: Candidate, keep: set[Key], settings: LayoutSettings,
           figures: dict, clock: float) -> Evaluation:
    """``cand``'s usable bays ``keep`` with the accessible and EV bays the plot asks for,
    prepared until every bay is usable: a bay unusable beside the access aisles is dropped,
    an accessible group unusable where it stands is allotted elsewhere."""
    barred: set[Key] = set()
    for _ in range(ROUNDS):
        alloc = allocate(plot, stretches(plot, cand.rows, keep), barred=barred)
        yaml_text, ids = scenario_text(plot, cand, keep, settings, allocation=alloc)
        got = _prepared_text(plot, yaml_text, ids, figures, clock)
        if isinstance(got, Evaluation):
            return got
        sc, prepared, report = got
        usable = _usable(report)
        if report.complete and usable == set(ids):
            return _run(sc, prepared, settings,
                        Evaluation(bays=len(ids), yaml=yaml_text, **figures,
                                   **_use_figures(plot, report, alloc)), clock)
        for sid in set(ids) - usable:
            key = ids[sid]
            if key in alloc.groups:
                barred |= set(alloc.groups[key])
            else:
                keep.discard(key)
    return Evaluation(bays=0, problem="its bays by use did not settle",
                      seconds=time.perf_counter() - clock, **figures)


def _prepare(plot: PlotSpec, yaml_text: str):
    sc = parse_scenario(parse_text(yaml_text, f"{plot.name}.yaml"))
    prepared = prepare_lot(sc)
    return sc, prepared, validate_prepared(prepared, f"{plot.name}.yaml")


def _usable(report) -> set[str]:
    """The bays usable by every vehicle type the scenario's rule of uses lets park in them
    (at least one): each such type can reach it, park in it and leave it."""
    per_type = {name: set(ids) for name, ids in report.usable().items()}
    refused = report.refused
    out = set()
    for s in report.prepared.lot.slots:
        allowed = [name for name in per_type if s.id not in refused.get(name, {})]
        if allowed and all(s.id in per_type[name] for name in allowed):
            out.add(s.id)
    return out


def _use_figures(plot: PlotSpec, report, alloc: Allocation | None = None) -> dict:
    """An evaluation's bays by use, as ``lotsim validate`` counts them, and whether they
    meet ADA 2010 (where the plot asks for accessible bays); nothing for a plot that asks
    for no uses."""
    if not plot.uses.asked:
        return {}
    bays = report.bays
    return dict(by_use=tuple(bays.by_use.items()),
                met=bays.met if plot.uses.accessible_wanted else None,
                short=tuple(alloc.short.items()) if alloc is not None else ())


def _run(sc, prepared, settings: LayoutSettings, e: Evaluation, clock: float) -> Evaluation:
    """``e`` with the figures of a run of its lot at the plot's demand: mean time to park,
    cars parked per hour, and whether ``lotsim check`` passes the run."""
    rr = plan_run(sc, RunSettings(planner=settings.planner), lot_graph=prepared.lot_graph)
    m = rr.metrics()
    parked = [v for v in rr.vehicles if v.parked_at is not None]
    if parked:
        first = min(v.arrival.time for v in rr.vehicles)
        span = max(v.parked_at for v in parked) - first
        rate = 3600.0 * len(parked) / span if span > 0 else 0.0
    else:
        rate = 0.0
    report = check_result(result_dict(rr))
    return dataclasses.replace(e, mean_time_to_park=float(m["mean_time_to_park"]),
                               throughput=rate, parked=len(parked),
                               vehicles=int(m["vehicles"]), checked=report.ok,
                               seconds=time.perf_counter() - clock)


def _short(message: str) -> str:
    return " ".join(message.split())[:300]


def scenario_text(plot: PlotSpec, cand: Candidate,
                  keep: set[tuple[str, str, float]] | None = None,
                  settings: LayoutSettings | None = None, *,
                  allocation: Allocation | None = None
                  ) -> tuple[str, dict[str, tuple[str, str, float]]]:
    """The scenario of ``cand`` with the bays of ``keep`` (aisle, side, station of the
    bay's entry; None: all), or those of ``allocation`` with their uses, and each slot id's
    bay (for an accessible bay, the first drawn bay its group stands on)."""
    draft = LotDraft(name=plot.name,
                     description=plot.description or f"A lot laid out on plot {plot.name}.",
                     boundary=list(plot.boundary),
                     units=None if plot.units == "m" else plot.units,
                     places=2 if plot.units == "m" else 4)
    draft.header = [f"Laid out by lotsim layout (lotsim {__version__}) on plot {plot.name}: "
                    f"{cand.label}."]
    if settings is not None:
        draft.header.append(f"Search: {settings.describe()}.")
    for a in cand.aisles:
        draft.aisles.append(AisleDraft(a.id, [a.start, a.end], a.width, a.one_way))
    ids: dict[str, tuple[str, str, float]] = {}
    numbers: dict[tuple[str, str], int] = {}
    runs: list[Stretch] = (list(allocation.stretches) if allocation is not None
                           else stretches(plot, cand.rows, keep))
    for run in runs:
        key = (run.aisle, run.side)
        first = numbers.get(key, 0) + 1
        prefix = f"{run.aisle}{'L' if run.side == 'left' else 'R'}"
        kind = "perpendicular" if run.angle == 90 else "angled"
        draft.rows.append(RowDraft(run.aisle, run.side, kind, run.count, run.width,
                                   run.length, run.start, prefix,
                                   angle_deg=None if run.angle == 90 else float(run.angle),
                                   first_number=first, use=run.use))
        for k in range(run.count):
            ids[f"{prefix}{first + k}"] = run.places[k][0]
        numbers[key] = first + run.count - 1
    if plot.uses.asked:
        draft.building_entrances = [(e.id, e.at) for e in plot.building_entrances]
    for isl in plot.islands:
        draft.no_go.append(AreaDraft(isl.id, list(isl.polygon)))
    for g in cand.gates:
        x, y, h = g.entrance
        draft.entrances.append(GateDraft(f"{g.id}-in", x, y, math.degrees(h)))
        x, y, h = g.exit
        draft.exits.append(GateDraft(f"{g.id}-out", x, y, math.degrees(h)))
    d = plot.demand
    stream: dict = {"count": d.count, "rate_per_hour": float(d.rate_per_hour)}
    if d.dwell is not None:
        stream["dwell"] = [float(d.dwell[0]), float(d.dwell[1])]
    draft.traffic = {"stream": stream}
    out = draft.to_yaml()
    out = out.replace("vehicle_types: [valet]\n", _vehicle_types(plot) + "\n", 1)
    out = out.replace("lot:\n", f"seed: {plot.seed}\nlot:\n", 1) if plot.seed else out
    return out, ids


def _vehicle_types(plot: PlotSpec) -> str:
    """The plot's vehicle types as a scenario writes them: catalogue names as names,
    definitions in full, with their marks (``accessible: true``, ...)."""
    items = []
    for v, name in zip(plot.vehicle_types, plot.vehicle_names, strict=True):
        if name:
            items.append(text(name))
            continue
        lim = v.limits
        k = 1.0 / LENGTH_UNITS[plot.units]  # lengths, and accelerations per length
        fields = [f"name: {text(v.name)}", f"width: {num(v.width * k, 6)}",
                  f"front: {num(v.front * k, 6)}", f"rear: {num(v.rear * k, 6)}",
                  f"wheelbase: {num(v.wheelbase * k, 6)}",
                  f"max_steer_deg: {num(math.degrees(v.max_steer), 6)}",
                  f"max_forward_speed_kmh: {num(lim.max_forward_speed * 3.6, 6)}",
                  f"max_reverse_speed_kmh: {num(lim.max_reverse_speed * 3.6, 6)}",
                  f"max_accel: {num(lim.max_accel * k, 6)}",
                  f"max_brake: {num(lim.max_brake * k, 6)}",
                  f"max_jerk: {num(lim.max_jerk * k, 6)}",
                  f"max_steer_rate_deg: {num(math.degrees(lim.max_steer_rate), 6)}",
                  f"max_lateral_accel: {num(lim.max_lateral_accel * k, 6)}"]
        fields += [f"{mark}: true" for mark in MARKS if mark in v.marks]
        items.append("{" + ", ".join(fields) + "}")
    return "vehicle_types:\n" + "\n".join(f"  - {i}" for i in items)


__all__ = ["LayoutSettings", "LayoutResult", "Evaluation", "lay_out", "candidates",
           "scenario_text"]
