"""Preparing a scenario's lot once for any number of runs: the lot built, every slot's
maneuvers planned for every vehicle type, the drivable graph through them
(:func:`prepare`, :class:`PreparedLot`), loaded from the on-disk cache when it was prepared
before."""

from __future__ import annotations

from dataclasses import dataclass

import lotsim.core.diskcache
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle, Lot
from lotsim.maneuvers.planner import MARGIN, ManeuverPlanner, plan_lot
from lotsim.roadmap.graph import LotGraph, Reachability, build_graph, plan_turnarounds_ahead
from lotsim.scenario import Scenario
from lotsim.traffic.demand import arrivals

REMEMBER_FROM = 64
"""Fewest slots times vehicle types for which :func:`prepare` keeps a lot's maneuver answers
for its later edits (a smaller lot is planned in a second or two, about what reading and
writing them would take)."""


def prepare(scenario: Scenario, *, node_spacing: float = 4.0, maneuvers: bool = True,
            margin: float = MARGIN, cache: bool = True, progress=None) -> LotGraph:
    """Build the scenario's lot for its vehicle types, plan every slot's parking maneuver
    for every type, and build the lot's drivable graph through them.

    The slots a type cannot use are in ``LotGraph.infeasible`` (type → slot → reason).
    A slot served by two lanes is parked on one pose from both, so that a car can leave
    towards either (:meth:`~lotsim.maneuvers.planner.ManeuverPlanner.solve_lanes`); where
    a lane's own best maneuver parks the other way round, it is kept too (a park edge's
    ``stays``) for cars that will not leave. Which are kept follows the scenario's traffic:
    with no car that stays, only the shared pose; with no car that leaves, only each lane's
    own best (where the others begin would only be lane nodes in the way); without
    traffic, the shared pose.
    With ``maneuvers=False`` slots hang off placeholder links (quick, for pictures).

    With ``cache`` (the default), a lot prepared before — same lot, vehicle types and
    settings, same lotsim — is loaded from the on-disk cache instead (:mod:`lotsim.core.diskcache`;
    ``LOTSIM_CACHE_DIR=off`` turns it off), and a new one is stored there;
    ``LotGraph.from_cache`` says which; a process that asks for a lot another is preparing
    waits for it and loads it (:func:`lotsim.core.diskcache.making`). A new one also reads and adds
    to the answers to the maneuver problems searched before in lots of the scenario's name,
    keyed by each problem's exact geometry
    (:meth:`~lotsim.maneuvers.planner.ManeuverPlanner.prefetch`; lots of
    :data:`REMEMBER_FROM` slot-types or more): an edited lot searches only the problems its
    edit changed, and the answers are the same.
    ``progress(done, total)`` is called as the maneuvers' distinct problems are searched
    (not when the lot comes from the cache).

    Raises
    ------
    ScenarioError
        When the layout does not hold together (overlaps, narrow aisles, ...).
    """
    if not maneuvers:
        lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
        return build_graph(lot, node_spacing=node_spacing, vehicles=scenario.vehicle_types)
    leaves = ({a.dwell is not None for a in arrivals(scenario.traffic, scenario.seed)}
              if scenario.traffic is not None else {True})
    if not cache:
        return _prepared(scenario, leaves, None, node_spacing, margin, progress)
    name = lotsim.core.diskcache.key("prepared", scenario.lot, scenario.vehicle_types,
                            scenario.parked_vehicle, sorted(leaves), node_spacing, margin)
    lg = _cached(name)
    if lg is None:
        with lotsim.core.diskcache.making(name):
            # another process may have made it while this one waited for the lock
            lg = _cached(name)
            if lg is None:
                lg = _prepared(scenario, leaves, name, node_spacing, margin, progress)
    return lg


def _cached(name: str) -> LotGraph | None:
    lg = lotsim.core.diskcache.load(name)
    if not isinstance(lg, LotGraph):
        return None
    lg.from_cache = True
    return lg


def _prepared(scenario: Scenario, leaves: set[bool], name: str | None, node_spacing: float,
              margin: float, progress) -> LotGraph:
    """:func:`prepare` a lot not in the cache, and store it there as ``name`` (when not
    None)."""
    lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
    # the dead ends' turnarounds, planned in time no other step wants (the graphs need them)
    with plan_turnarounds_ahead(lot, scenario.vehicle_types):
        planner = maneuver_planner(scenario, lot, margin=margin)
        known = known_name = None
        if (name is not None and lotsim.core.diskcache.cache_dir() is not None
                and len(lot.slots) * len(scenario.vehicle_types) >= REMEMBER_FROM):
            # the maneuvers of this lot as prepared before (by its name), whatever has changed
            # since: an edited lot searches again only the problems its edit changed
            known_name = lotsim.core.diskcache.key("maneuvers", scenario.name, planner.settings)
            known = lotsim.core.diskcache.load(known_name)
            known = known if isinstance(known, dict) else {}
        planned, infeasible, stays = plan_lot(planner, scenario.vehicle_types, progress=progress,
                                              known=known)
        if known_name is not None and planner.stats["planned"] > planner.stats["remembered"]:
            lotsim.core.diskcache.store(known_name, known)  # it learnt something
        if leaves == {False}:  # no car leaves: each lane's own best only
            planned, stays = {**planned, **stays}, {}
        elif leaves == {True}:  # no car stays: where those begin would only be nodes in the way
            stays = {}
        lg = build_graph(lot, node_spacing=node_spacing, maneuvers=planned,
                         vehicles=scenario.vehicle_types, stays=stays)
        lg.infeasible = infeasible
        lg.maneuver_planner = planner
        if name is not None:
            lg.reachability()  # every run and validate asks: kept with the lot
            lg.facts()
            lotsim.core.diskcache.store(name, lg)
        return lg


@dataclass(frozen=True, slots=True)
class PreparedLot:
    """A scenario with its lot built and every maneuver planned (:func:`lotsim.prepare`):
    reusable across runs, which then skip the preparation (seconds to a minute on a large
    lot) and drive the edge motions earlier runs on it worked out
    (:func:`~lotsim.traffic.searchgraph.search_graph`).

    Attributes
    ----------
    scenario : Scenario
    lot_graph : LotGraph
        The built lot (``.lot``), its drivable graph (``.graph``) and the slots each vehicle
        type cannot use with the reason (``.infeasible``). Runs read it and do not change
        what they read, so one prepared lot serves any number of runs.
    """

    scenario: Scenario
    lot_graph: LotGraph

    @property
    def lot(self) -> Lot:
        """The built lot: slots as polygons, aisles, lanes, obstacles, zones."""
        return self.lot_graph.lot

    @property
    def infeasible(self) -> dict[str, dict[str, str]]:
        """Vehicle type → slot id → why that type cannot park there."""
        return self.lot_graph.infeasible

    def reachability(self) -> Reachability:
        """The free slots that cannot be reached or left (:class:`Reachability`)."""
        return self.lot_graph.reachability()


def maneuver_planner(scenario: Scenario, lot: Lot, *, margin: float = MARGIN) -> ManeuverPlanner:
    """The maneuver planner for ``lot``: clear of the scenario's parked cars, starting only
    where a car can arrive from an entrance or leave for an exit (along lanes)."""
    return ManeuverPlanner(lot, margin=margin, parked_width=scenario.parked_vehicle.width,
                           lane_ranges=build_graph(
                               lot, vehicles=scenario.vehicle_types).maneuver_ranges())


