"""One candidate prepared (:mod:`lotsim.design.search`): its scenario written
(:func:`scenario_text`), its bays some vehicle type cannot reach, park in or leave dropped
until every bay left is usable, its bays by use allotted and settled likewise, and the
lot run at the plot's demand (:func:`evaluate`)."""

from __future__ import annotations

import dataclasses
import math
import time

from lotsim import __version__
from lotsim.core.units import LENGTH_UNITS
from lotsim.design.allocation import Allocation, Key, Stretch, allocate, stretches
from lotsim.design.drawn import Candidate
from lotsim.design.plot import PlotSpec
from lotsim.design.results import Evaluation
from lotsim.design.settings import LayoutSettings
from lotsim.errors import ScenarioError
from lotsim.io.imports.draft import (
    AisleDraft,
    AreaDraft,
    GateDraft,
    LotDraft,
    RowDraft,
    num,
    text,
)
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import parse_scenario
from lotsim.io.yamlnodes import parse_text
from lotsim.lot.pavement import pave
from lotsim.lot.spec import PavementSpec
from lotsim.lot.uses import MARKS
from lotsim.sim.orders import plan_run
from lotsim.sim.preparation import prepare_lot
from lotsim.sim.settings import RunSettings
from lotsim.sim.validation import validate_prepared
from lotsim.verify import check_result

ROUNDS = 4
"""A candidate is prepared at most this many times while unusable bays are dropped."""


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
    cars parked per hour, and whether ``lotsim check`` passes the run; and the ground its
    aisles and bays take."""
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
    lot = prepared.lot
    paved = pave(PavementSpec(), lot.boundary, lot.aisles, lot.slots, []).area
    return dataclasses.replace(e, mean_time_to_park=float(m["mean_time_to_park"]),
                               throughput=rate, parked=len(parked),
                               vehicles=int(m["vehicles"]), checked=report.ok,
                               paved=float(paved), seconds=time.perf_counter() - clock)


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
