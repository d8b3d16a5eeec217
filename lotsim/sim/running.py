"""A run from scenario to result: refuse traffic the lot cannot serve (:func:`check_traffic`,
:func:`require_traffic`), then plan it (:func:`run`); :func:`collector_tuned` is the
garbage-collector setting a caller may ask for while it runs many cars."""

from __future__ import annotations

import gc
from collections.abc import Iterable, Iterator
from contextlib import contextmanager

from lotsim.errors import Location, ScenarioError
from lotsim.roadmap.model import LotGraph
from lotsim.roadmap.reach import Reachability
from lotsim.scenario import Scenario
from lotsim.sim.preparation import PreparedLot, prepare_graph
from lotsim.sim.results import RunResult
from lotsim.sim.settings import RunSettings
from lotsim.traffic.demand import Arrival
from lotsim.traffic.searchgraph import SearchGraphMemo

RUN_GC_THRESHOLDS = (20_000, 20, 1000)
"""The cycle collector's thresholds in :func:`collector_tuned` (Python's are 700, 10, 10):
planning, and preparing a lot, make millions of objects and almost no cycles, so it still
collects, in larger batches, and seldom scans everything."""


@contextmanager
def collector_tuned() -> Iterator[None]:
    """Within this block, what the process held before (a prepared lot, earlier runs'
    results) is left out of the garbage collections, and collections come in larger
    batches (:data:`RUN_GC_THRESHOLDS`); both are restored after it, also when it raises.

    A full collection scans every object it tracks: one that fell in a short run of a
    process holding several lots took longer than the run's own work, skewing the
    planning times runs are compared by; preparing a lot kept from the cache and edited
    spent a tenth of its time in them. This changes process-wide state, so the library
    never does it unasked; ``lotsim run`` asks for it around preparing the lot and around
    planning, ``lotsim validate`` and ``lotsim layout`` around preparing. Objects frozen
    before the block stay frozen (nothing more is frozen then).

    Examples
    --------
    >>> import gc
    >>> before = gc.get_threshold()
    >>> with collector_tuned():
    ...     gc.get_threshold() == RUN_GC_THRESHOLDS
    True
    >>> gc.get_threshold() == before
    True
    """
    thresholds = gc.get_threshold()
    freeze = gc.get_freeze_count() == 0
    if freeze:
        gc.freeze()
    gc.set_threshold(*RUN_GC_THRESHOLDS)
    try:
        yield
    finally:
        gc.set_threshold(*thresholds)
        if freeze:
            gc.unfreeze()


def turned_away(lg: LotGraph, traffic: list[Arrival], reach: Reachability | None = None
                ) -> dict[str, str]:
    """The cars of the traffic the lot cannot serve, by vehicle id, and why: a type that
    fits no free slot, that can reach none of those it fits, or (for a car that will leave)
    can leave none of those it reaches for an exit. This is the designer's question "does
    my van fit?", not a broken file: ``validate`` warns of it and ``run`` turns such cars
    away with the reason. ``reach`` is ``lg.reachability()`` when the caller has it."""
    facts = lg.facts()
    reach = reach or lg.reachability()
    why: dict[str, str] = {}
    leave_why: dict[str, str] = {}
    for name in sorted({a.vehicle for a in traffic}):
        no_in, no_out = reach.by_type.get(name, ([], []))
        fits = {sid for sid in (s.id for s in lg.lot.free_slots)
                if sid not in lg.infeasible.get(name, {})}
        if name not in facts.parks:
            reasons = sorted(set(lg.infeasible.get(name, {}).values()))
            why[name] = (f"vehicle type {name!r} fits no slot of this lot"
                         + (f" ({reasons[0]})" if reasons else ""))
        elif fits and fits <= set(no_in):
            why[name] = (f"vehicle type {name!r} can reach none of the free slots it fits "
                         f"(no turns it can make lead there)")
        elif lg.exits and fits and fits <= set(no_in) | set(no_out):
            leave_why[name] = (f"vehicle type {name!r} can leave none of the free slots it "
                               f"reaches for an exit")
    out = {}
    for a in traffic:
        if a.vehicle in why:
            out[a.id] = why[a.vehicle]
        elif a.vehicle in leave_why and a.dwell is not None:
            out[a.id] = leave_why[a.vehicle]
    return out


def unfit(lg: LotGraph, names: Iterable[str]) -> set[str]:
    """The free slots that none of the vehicle types ``names`` can park in (too short, too
    narrow, no maneuver found): they are not reached by any car of those types however the
    lanes run, and the reason is the type's, not the lanes' (``lg.infeasible``). Empty
    for a graph planned without maneuvers, or for no types."""
    names = list(names)
    if not names:
        return set()
    return {s.id for s in lg.lot.free_slots
            if all(s.id in lg.infeasible.get(name, {}) for name in names)}


def check_traffic(lg: LotGraph, traffic: list[Arrival], reach: Reachability | None = None
                  ) -> None:
    """Refuse traffic the lot cannot serve at all: an entrance with no route to a free
    slot that its cars fit, dwell times in a lot with no exit (cars of a type the lot
    cannot serve are turned away with that type's reason, not refused:
    :func:`turned_away`). ``reach`` is ``lg.reachability()`` when the caller has it
    already.

    Raises
    ------
    ScenarioError
        Located at the vehicle or stream that asks for it.
    """
    facts = lg.facts()
    reach = reach or lg.reachability()
    unreachable = reach.unreachable
    # slots no car of the traffic fits are no question of routes: those cars are turned
    # away with the reason they do not fit
    fitting = {s.id for s in lg.lot.free_slots} - unfit(lg, {a.vehicle for a in traffic})
    for gate in sorted({a.entrance for a in traffic}):
        # a full lot is no bad input: its cars are turned away ("the lot is full")
        if fitting and fitting <= set(unreachable[gate]):
            who = next(a for a in traffic if a.entrance == gate)
            raise ScenarioError(who.where, f"no route from entrance {gate!r} to a free slot")
    leaving = [a for a in traffic if a.dwell is not None]
    if leaving and not lg.exits:
        raise ScenarioError(leaving[0].where, "vehicles have dwell times but the lot has no "
                                              "exit to leave by")
    if leaving and fitting and not facts.leavable:
        raise ScenarioError(leaving[0].where, "vehicles have dwell times but no slot can "
                                              "be left for an exit along the lanes")


def require_traffic(scenario: Scenario) -> None:
    """Refuse to run a scenario that only describes a lot.

    Raises
    ------
    ScenarioError
        At the top of its file, when the scenario has no ``traffic`` section.
    """
    if scenario.traffic is None:
        raise ScenarioError(Location(scenario.source, 1, 1), "the scenario has no 'traffic' "
                                                              "section to run (see "
                                                              "docs/scenario.md)")



def simulate(scenario: Scenario, settings: RunSettings | None = None, *, lot_graph=None,
        progress=None, memo: SearchGraphMemo | None = None, release=None) -> RunResult:
    """Plan the scenario's traffic: assign slots, plan every vehicle in, and out again.

    Vehicles are planned one after another in arrival order (their priority),
    or in ``settings.order`` when the traffic is booked in advance, each against
    the reservations of those before it. A vehicle that finds no
    free slot queues at its entrance and gets the next slot freed; one whose
    search fails (expansion limit, no path) waits outside and tries again. After the
    traffic's patience it is turned away, with the reason. Nothing is dropped:
    every vehicle ends parked, departed, waiting or rejected.

    Parameters
    ----------
    scenario : Scenario
        Must have ``traffic``.
    settings : RunSettings, optional
    lot_graph : LotGraph, optional
        The prepared lot (made with :func:`~lotsim.sim.preparation.prepare_graph` if not given).
    progress : callable, optional
        Called as ``progress(done, total)`` as trips are dealt with: a vehicle's way in when
        it is planned, its way out (if it has a dwell) when that is, or both when it is
        turned away or the run ends. It may raise (e.g.
        :class:`lotsim.sim.limits.LimitExceeded`) to stop the run.
    memo : SearchGraphMemo, optional
        The lot's search graphs, shared by the runs on it (a prepared lot's
        ``search_graphs``): later runs drive the edge motions the first worked out, and plan
        the same.
    release : callable, optional
        Given each car once it is done, in the result's order, while the run goes on; the
        car then keeps only its figures (:class:`~lotsim.sim.live.Live`'s ``release``).

    The garbage collector is left as it is; a caller that runs many cars may ask for
    :func:`collector_tuned` around the call.

    Raises
    ------
    ScenarioError
        For a scenario without traffic, or traffic the lot cannot serve at all (see
        :func:`check_traffic`); cars of a type it cannot serve are turned away with the
        reason (:func:`turned_away`).
    SettingsError
        For an ``order`` that does not hold every vehicle of the traffic once.
    """
    from lotsim.sim.live import Live

    require_traffic(scenario)
    lg = lot_graph or prepare_graph(scenario)
    prepared = (PreparedLot(scenario, lg) if memo is None
                else PreparedLot(scenario, lg, search_graphs=memo))
    return Live(prepared, settings, progress=progress, release=release).finish()
