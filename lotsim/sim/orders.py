"""Priority orders for prioritised planning: arrival order, shortest first, and a genetic
algorithm over orders (the G-JHCA* of the modelling-contest paper on unmanned-car
parking path planning, 2022).

A vehicle planned earlier never yields to one planned later, so the order matters when
vehicles meet. With the traffic booked in advance (:attr:`lotsim.sim.settings.RunSettings.order`)
any order can be planned; the fitness of an order is the run's total time to park (a
vehicle that never parks counts as
:attr:`~lotsim.sim.settings.GASettings.unparked_penalty` seconds plus the traffic's
patience). The GA evaluates an order by planning the whole run with it.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from lotsim.sim.assignment import SlotAssigner
from lotsim.sim.results import RunResult
from lotsim.sim.running import require_traffic, simulate
from lotsim.sim.settings import GASettings, RunSettings
from lotsim.traffic.demand import arrivals
from lotsim.traffic.searchgraph import SearchGraphMemo
from lotsim.traffic.settings import SearchSettings


def fitness(rr: RunResult) -> float:
    """Total time to park of a run [s]: arrival to standing in the slot, summed over the
    vehicles; one that never parks counts as its patience plus the run's
    ``settings.ga.unparked_penalty``."""
    patience = rr.scenario.traffic.patience if rr.scenario.traffic else 0.0
    penalty = rr.settings.ga.unparked_penalty
    return float(sum(v.parked_at - v.arrival.time if v.parked_at is not None
                     else patience + penalty for v in rr.vehicles))


def shortest_first(scenario, lot_graph, seed: int | None = None, *,
                   search: SearchSettings | None = None,
                   memo: SearchGraphMemo | None = None) -> tuple[str, ...]:
    """Vehicle ids by their least static time from their entrance into a free slot they
    can use (travel along the graph plus the maneuver, on the search graphs of ``search``
    settings, from ``memo`` when given), ties by arrival."""
    seed = scenario.seed if seed is None else seed
    traffic = arrivals(scenario.traffic, seed)
    assigner = SlotAssigner(lot_graph, scenario.vehicle_types, search=search, memo=memo)
    free = {s.id for s in lot_graph.lot.free_slots}
    best = {}
    for a in traffic:
        times = assigner.slot_times(a.entrance, a.vehicle, a.dwell is not None)
        best[a.id] = min((times[s] for s in free if s in times), default=math.inf)
    rank = {a.id: k for k, a in enumerate(traffic)}
    return tuple(sorted(best, key=lambda vid: (best[vid], rank[vid])))


def _order_crossover(a: np.ndarray, b: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """OX1: a slice of ``a`` kept in place, the rest filled in ``b``'s order."""
    n = len(a)
    i, j = sorted(rng.choice(n + 1, size=2, replace=False))
    child = np.full(n, -1)
    child[i:j] = a[i:j]
    kept = set(a[i:j].tolist())
    rest = [x for x in b.tolist() if x not in kept]
    child[:i] = rest[:i]
    child[j:] = rest[i:]
    return child


def genetic_order(scenario, settings: RunSettings, *, lot_graph, ga: GASettings,
                  progress=None, memo: SearchGraphMemo | None = None
                  ) -> tuple[tuple[str, ...], dict]:
    """Search planning orders with a genetic algorithm; fitness :func:`fitness` of the run
    planned in that order (booked traffic).

    Returns the best order and a record: ``fitness`` (its total time to park),
    ``fitness_arrival`` and ``fitness_shortest_first`` (the two orders the first
    generation starts from, evaluated in the same run), ``evaluations`` (distinct orders
    planned), ``history`` (best fitness after each generation).
    """
    seed = scenario.seed if settings.seed is None else settings.seed
    ids = [a.id for a in arrivals(scenario.traffic, seed)]
    n = len(ids)
    rng = np.random.default_rng(ga.seed)
    cache: dict[tuple[int, ...], float] = {}

    def score(perm: np.ndarray) -> float:
        key = tuple(int(x) for x in perm)
        if key not in cache:
            order = tuple(ids[k] for k in key)
            rr = simulate(scenario, dataclasses.replace(settings, order=order), lot_graph=lot_graph,
                     memo=memo)
            cache[key] = fitness(rr)
            if progress is not None:
                progress(len(cache))
        return cache[key]

    arrival = np.arange(n)
    pos = {vid: k for k, vid in enumerate(ids)}
    sf = np.array([pos[v] for v in shortest_first(scenario, lot_graph, seed,
                                                  search=settings.search, memo=memo)])
    pop = [arrival, sf] + [rng.permutation(n) for _ in range(max(0, ga.population - 2))]
    pop = pop[: max(2, ga.population)]
    fit = [score(p) for p in pop]
    history = [min(fit)]
    for _ in range(ga.generations):
        order = np.argsort(fit, kind="stable")
        nxt = [pop[k] for k in order[: ga.elite]]
        while len(nxt) < len(pop):
            parents = []
            for _ in range(2):
                pick = rng.choice(len(pop), size=min(ga.tournament, len(pop)), replace=False)
                parents.append(pop[min(pick, key=lambda k: (fit[k], k))])
            child = _order_crossover(parents[0], parents[1], rng) if n > 1 else parents[0]
            while n > 1 and rng.random() < ga.mutation:
                i, j = rng.choice(n, size=2, replace=False)
                child = child.copy()
                child[i], child[j] = child[j], child[i]
            nxt.append(child)
        pop = nxt
        fit = [score(p) for p in pop]
        history.append(min(fit))
    best = min(range(len(pop)), key=lambda k: (fit[k], k))
    return tuple(ids[k] for k in pop[best]), {
        "fitness": fit[best],
        "fitness_arrival": cache[tuple(range(n))],
        "fitness_shortest_first": cache[tuple(int(x) for x in sf)],
        "evaluations": len(cache),
        "history": history,
    }


def plan_run(scenario, settings: RunSettings, *, lot_graph,
             progress=None, memo: SearchGraphMemo | None = None,
             release=None) -> RunResult:
    """Plan the scenario's traffic in the order ``settings`` asks for: ``settings.order`` if
    given, else chosen by ``settings.priority`` (:data:`PRIORITIES`; the GA with
    ``settings.ga``), then planned by :func:`lotsim.sim.running.simulate`.

    The run's ``settings`` hold the order chosen (None when online); its ``ordering`` is a
    record: ``order_time`` (seconds spent choosing the order, the GA's evaluation runs
    included), ``evaluations`` (runs planned to choose it), ``fitness`` (the run's total
    time to park, :func:`fitness`) and, for ``ga``, the fitness of the arrival and
    shortest-first orders from the same search and its ``history``.

    ``progress(done, most)`` is called after each order the GA plans (``most``: the
    population times the generations plus one; repeated orders are not planned again);
    otherwise, as :func:`lotsim.sim.running.simulate` calls it, as trips are dealt with.

    ``memo`` holds the lot's search graphs for every run on it (a prepared lot's
    ``search_graphs``); without one, the runs of this call share a new one. ``release``
    is given to the run planned in the order chosen (:func:`~lotsim.sim.running.simulate`).
    """
    require_traffic(scenario)
    memo = SearchGraphMemo() if memo is None else memo
    clock = time.perf_counter()
    record: dict = {"evaluations": 0}
    order, searching = settings.order, False
    if order is None and settings.priority == "shortest_first":
        order = shortest_first(scenario, lot_graph, settings.seed, search=settings.search,
                               memo=memo)
    elif order is None and settings.priority == "ga":
        ga, searching = settings.ga, True
        most = max(2, ga.population) * (ga.generations + 1)
        order, found = genetic_order(
            scenario, settings, lot_graph=lot_graph, ga=ga, memo=memo,
            progress=None if progress is None else (lambda k: progress(k, most)))
        record.update({k: v for k, v in found.items() if k != "fitness"})
    record["order_time"] = time.perf_counter() - clock
    rr = simulate(scenario, dataclasses.replace(settings, order=order), lot_graph=lot_graph,
             progress=None if searching else progress, memo=memo, release=release)
    record["fitness"] = fitness(rr)
    rr.ordering = record
    return rr
