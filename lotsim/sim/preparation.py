"""Preparing a scenario's lot once for any number of runs: the lot built, every slot's
maneuvers planned for every vehicle type, the drivable graph through them
(:func:`prepare`, :class:`PreparedLot`), loaded from the on-disk cache when it was prepared
before."""

from __future__ import annotations

import contextlib
import dataclasses
from dataclasses import dataclass, field

import lotsim.core.diskcache
from lotsim.core.keys import inputs
from lotsim.core.reusecheck import ReuseCheck
from lotsim.core.workers import Aside
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle, Lot
from lotsim.lot.spec import LotSpec
from lotsim.lot.uses import refused_bays
from lotsim.maneuvers.batch import plan_lot
from lotsim.maneuvers.links import parking_links
from lotsim.maneuvers.planner import ManeuverPlanner
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.roadmap.assemble import build_graph, lane_graph
from lotsim.roadmap.memo import RoadmapMemo
from lotsim.roadmap.model import LotGraph
from lotsim.roadmap.reach import Reachability, maneuver_ranges
from lotsim.roadmap.settings import RoadmapSettings
from lotsim.roadmap.turnarounds import plan_turnarounds_ahead
from lotsim.scenario import Scenario
from lotsim.traffic.demand import arrivals
from lotsim.traffic.searchgraph import SearchGraphMemo
from lotsim.vehicles.model import VehicleType

REMEMBER_FROM = 64
"""Fewest slots times vehicle types for which :func:`prepare` keeps a lot's maneuver answers
for its later edits, by default (a smaller lot is planned in a second or two, about what
reading and writing them would take)."""


@inputs
class PreparedFrom:
    """What a prepared lot is made from (its name in the on-disk cache): the lot as
    described, the vehicle types, the parked vehicle, whether cars leave and/or stay, the
    graph's node spacing [m] and the maneuver and roadmap settings."""

    lot: LotSpec
    vehicle_types: tuple[VehicleType, ...]
    parked_vehicle: VehicleType
    leaves: tuple[bool, ...]
    node_spacing: float
    maneuvers: ManeuverSettings
    roadmap: RoadmapSettings


@inputs
class StoreOf:
    """The name of a store of remembered work on disk: the scenario's name and the
    settings the work was done with (other settings, another store)."""

    scenario: str
    settings: ManeuverSettings | RoadmapSettings


def prepare_graph(scenario: Scenario, *, node_spacing: float = 4.0, maneuvers: bool = True,
            margin: float | None = None, cache: bool = True, progress=None,
            remember_from: int = REMEMBER_FROM) -> LotGraph:
    """The lot graph of :func:`prepare_lot`: the scenario's lot built for its vehicle
    types, every slot's parking maneuver planned for every type, and the lot's drivable
    graph through them."""
    return prepare_lot(scenario, node_spacing=node_spacing, maneuvers=maneuvers,
                       margin=margin, cache=cache, progress=progress,
                       remember_from=remember_from).lot_graph


def prepare_lot(scenario: Scenario, *, node_spacing: float = 4.0, maneuvers: bool = True,
                margin: float | None = None, cache: bool = True, progress=None,
                remember_from: int = REMEMBER_FROM, check: ReuseCheck | None = None
                ) -> PreparedLot:
    """Build the scenario's lot for its vehicle types, plan every slot's parking maneuver
    for every type, and build the lot's drivable graph through them; with the maneuver
    planner they came from (``PreparedLot.maneuver_planner``, None with
    ``maneuvers=False``).

    The graph is made with the scenario's roadmap settings (``scenario.roadmap``) and the
    maneuvers with its maneuver settings (``scenario.maneuvers``); ``margin``, when given,
    replaces their clearance (and the prepared lot's scenario says so).

    The slots a type cannot use are in ``LotGraph.infeasible`` (type → slot → reason).
    A slot served by two lanes is parked on one pose from both, so that a car can leave
    towards either (:meth:`~lotsim.maneuvers.planner.ManeuverPlanner.solve_lanes`); where
    a lane's own best maneuver parks the other way round, it is kept too (a park edge's
    ``park_only``) for cars that will not leave. Which are kept follows the scenario's traffic:
    with no car that stays, only the shared pose; with no car that leaves, only each lane's
    own best (where the others begin would only be lane nodes in the way); without
    traffic, the shared pose.
    With ``maneuvers=False`` slots hang off placeholder links (quick, for pictures).

    With ``cache`` (the default), a lot prepared before — same lot, vehicle types, roadmap
    and maneuver settings, same lotsim — is loaded from the on-disk cache instead
    (:mod:`lotsim.core.diskcache`; ``LOTSIM_CACHE_DIR=off`` turns it off), and a new one
    is stored there; ``LotGraph.from_cache`` says which; a process that asks for a lot
    another is preparing waits for it and loads it (:func:`lotsim.core.diskcache.making`).
    A new one also reads and adds to the answers to the maneuver problems searched before
    in lots of the scenario's name, keyed by each problem's exact geometry
    (:func:`~lotsim.maneuvers.batch.prefetch`; lots of ``remember_from``
    slot-types or more): an edited lot searches only the problems its edit changed, and the
    answers are the same.
    ``progress(done, total)`` is called as the maneuvers' distinct problems are searched
    (not when the lot comes from the cache).

    With a reuse check (``check``; by default one when ``LOTSIM_VERIFY_REUSE=1``:
    :meth:`ReuseCheck.from_environment <lotsim.core.reusecheck.ReuseCheck.from_environment>`),
    everything recalled — the prepared lot from the cache, the roadmap's pieces, the
    maneuver answers, and later the search graphs the runs on it share — is worked out
    again and compared (docs/caching.md); the prepared lot is the same as without.

    Raises
    ------
    ScenarioError
        When the layout does not hold together (overlaps, narrow aisles, ...).
    SettingsError
        When ``margin`` is out of range.
    """
    if margin is not None:
        scenario = dataclasses.replace(scenario, maneuvers=dataclasses.replace(
            scenario.maneuvers, margin=margin))
    check = ReuseCheck.from_environment() if check is None else check
    graphs = SearchGraphMemo(check)
    if not maneuvers:
        lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
        lg = build_graph(lot, node_spacing=node_spacing, vehicles=scenario.vehicle_types,
                         settings=scenario.roadmap)
        lg.infeasible = refused_bays(lot.slots, scenario.vehicle_types)
        return PreparedLot(scenario, lg, search_graphs=graphs)
    leaves = ({a.dwell is not None for a in arrivals(scenario.traffic, scenario.seed)}
              if scenario.traffic is not None else {True})
    if not cache:
        lg, planner = _prepared(scenario, leaves, None, node_spacing, progress,
                                remember_from, check)
        return PreparedLot(scenario, lg, planner, graphs)
    name = lotsim.core.diskcache.key("prepared", PreparedFrom(
        scenario.lot, tuple(scenario.vehicle_types), scenario.parked_vehicle,
        tuple(sorted(leaves)), node_spacing, scenario.maneuvers, scenario.roadmap))
    got = _cached(name)
    if got is None:
        with lotsim.core.diskcache.making(name):
            # another process may have made it while this one waited for the lock
            got = _cached(name)
            if got is None:
                got = _prepared(scenario, leaves, name, node_spacing, progress,
                                remember_from, check)
            elif check is not None:
                _verify_cached(check, name, got, scenario, leaves, node_spacing)
    elif check is not None:
        _verify_cached(check, name, got, scenario, leaves, node_spacing)
    return PreparedLot(scenario, *got, graphs)


CACHE_STORE = "prepared lots"
"""The on-disk cache of prepared lots, as a reuse check names it."""


def _verify_cached(check: ReuseCheck, name: str, got: tuple[LotGraph, ManeuverPlanner],
                   scenario: Scenario, leaves: set[bool], node_spacing: float) -> None:
    """The reuse check of a prepared lot loaded from the cache as ``name``: the lot
    prepared again from scratch (no cache, no stores) and compared with it
    (:func:`prepared_parts`)."""
    fresh = _prepared(scenario, leaves, None, node_spacing, None, REMEMBER_FROM, None)
    check.compare(CACHE_STORE, name, prepared_parts(*got), prepared_parts(*fresh))


def prepared_parts(lg: LotGraph, planner: ManeuverPlanner) -> dict:
    """What a prepared lot is, for comparing two: every node and edge of the graph with
    its data, in the graph's order; the entrances, exits, slot nodes, attachments, skipped
    turns and the slots each type cannot use; and the maneuver planner's answers."""
    g = lg.graph
    return {"nodes": list(g.nodes(data=True)), "edges": list(g.edges(data=True)),
            "entrances": lg.entrances, "exits": lg.exits, "slot nodes": lg.slot_nodes,
            "attachments": lg.attachments, "skipped turns": lg.skipped_turns,
            "infeasible": lg.infeasible, "answers": planner.answers()}


def _cached(name: str) -> tuple[LotGraph, ManeuverPlanner] | None:
    """The lot graph and maneuver planner stored as ``name``, or None."""
    got = lotsim.core.diskcache.load(name)
    if not (isinstance(got, tuple) and len(got) == 2 and isinstance(got[0], LotGraph)):
        return None
    got[0].from_cache = True
    return got


def _prepared(scenario: Scenario, leaves: set[bool], name: str | None, node_spacing: float,
              progress, remember_from: int, check: ReuseCheck | None
              ) -> tuple[LotGraph, ManeuverPlanner]:
    """:func:`prepare_lot` a lot not in the cache, and store it there (the lot graph and
    the maneuver planner) as ``name`` (when not None)."""
    lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
    remember = (name is not None and lotsim.core.diskcache.cache_dir() is not None
                and len(lot.slots) * len(scenario.vehicle_types) >= remember_from)
    # the pieces of this lot's roadmap (and below, its maneuvers) as prepared before (by its
    # name), whatever has changed since: an edited lot works out again only what its edit
    # touched
    roads_name = _roads_name(scenario) if remember else None
    roads = _known(roads_name)
    held = len(roads or ())
    # what the lanes' graph works out, for the graph through slots
    memo = RoadmapMemo(lot, roads, settings=scenario.roadmap, reuse_check=check)
    # the dead ends' turnarounds, planned in time no other step wants (the graphs need them)
    with plan_turnarounds_ahead(memo, scenario.vehicle_types, settings=scenario.roadmap):
        planner = maneuver_planner(scenario, lot, memo=memo)
        known_name = (lotsim.core.diskcache.key("maneuvers", StoreOf(scenario.name,
                                                                         planner.settings))
                      if remember else None)
        known = _known(known_name)
        planned, infeasible, park_only = plan_lot(planner, scenario.vehicle_types,
                                                  progress=progress, known=known,
                                                  check=check)
        planned, infeasible, park_only = _by_use(lot, scenario, planned, infeasible,
                                                 park_only)
        # what it learnt (if anything) written aside while the graph is built
        learnt = known_name is not None and planner.stats["planned"] > planner.stats["remembered"]
        with (Aside(lambda: lotsim.core.diskcache.store(known_name, known)) if learnt
              else contextlib.nullcontext()):
            if leaves == {False}:  # no car leaves: each lane's own best only
                planned, park_only = {**planned, **park_only}, {}
            elif leaves == {True}:
                park_only = {}  # no car stays: where those begin would only be nodes in the way
            links = parking_links(lot, planned, park_only, scenario.vehicle_types,
                                  known=memo.known)
            lg = build_graph(lot, node_spacing=node_spacing, links=links,
                             vehicles=scenario.vehicle_types, memo=memo,
                             settings=scenario.roadmap)
            lg.infeasible = infeasible
            if roads_name is not None and (memo.worked or len(roads) != held):
                lotsim.core.diskcache.store(roads_name, roads)  # it learnt something
            if name is not None:
                # the graph and the answers packed aside (a lot big enough to keep its
                # answers for) while every run and validate's questions are answered, kept
                # with the lot
                with (Aside(lambda: (lg.packed_graph(), planner.packed_answers()))
                      if remember else contextlib.nullcontext()) as packing:
                    lg.reachability()
                    lg.facts()
                    packed = packing.wait() if packing is not None else None
                lotsim.core.diskcache.store(name, (lg, planner) if packed is None else (
                    lg.with_graph_packed(packed[0]), planner.with_answers_packed(packed[1])))
        return lg, planner


def _by_use(lot: Lot, scenario: Scenario, planned: dict, infeasible: dict[str, dict[str, str]],
            park_only: dict) -> tuple[dict, dict[str, dict[str, str]], dict]:
    """The maneuvers and the slots each type cannot use, with the bays the scenario's rule
    keeps a type out of (:func:`~lotsim.lot.uses.refused_bays`) taken out of the first and
    put in the second, with the rule's reason: a type has no way into a bay it may not
    use, so no policy can send it there."""
    refused = refused_bays(lot.slots, scenario.vehicle_types)
    if not any(refused.values()):
        return planned, infeasible, park_only
    out = {name: {**bays, **refused.get(name, {})} for name, bays in infeasible.items()}

    def kept(maneuvers: dict) -> dict:
        return {k: m for k, m in maneuvers.items() if k[1] not in refused.get(k[0], {})}

    return kept(planned), out, kept(park_only)


def _roads_name(scenario: Scenario) -> str:
    """The on-disk name of the store of roadmap pieces for lots of the scenario's name and
    roadmap settings (:mod:`~lotsim.roadmap.remembered`)."""
    return lotsim.core.diskcache.key("roadmap", StoreOf(scenario.name, scenario.roadmap))


def _known(name: str | None) -> dict | None:
    """The store of answers kept on disk as ``name`` (empty when there is none yet); None
    without a name."""
    if name is None:
        return None
    got = lotsim.core.diskcache.load(name)
    return got if isinstance(got, dict) else {}


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
    maneuver_planner : ManeuverPlanner or None
        The planner (and its answers) the maneuvers came from; None when the lot was
        prepared without maneuvers or handed in as a lot graph alone.
    search_graphs : SearchGraphMemo
        The lot's search graphs, one per vehicle type and search settings, made by the
        first run that needs each and driven by the later ones (they plan the same).
    """

    scenario: Scenario
    lot_graph: LotGraph
    maneuver_planner: ManeuverPlanner | None = None
    search_graphs: SearchGraphMemo = field(default_factory=SearchGraphMemo, repr=False,
                                           compare=False)

    def __repr__(self) -> str:
        """One line: ``<PreparedLot quickstart: 20 slots (15 free), 35 nodes, 54 edges>``."""
        lot, graph = self.lot, self.lot_graph.graph
        return (f"<PreparedLot {self.scenario.name}: {len(lot.slots)} slots "
                f"({len(lot.free_slots)} free), {graph.number_of_nodes()} nodes, "
                f"{graph.number_of_edges()} edges>")

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


def remembered_planner(scenario: Scenario, lot: Lot, *, margin: float | None = None,
                       check: ReuseCheck | None = None) -> ManeuverPlanner:
    """:func:`maneuver_planner` for one slot's question (``lotsim maneuver``), its lane
    graph's turns and turnarounds taken from those kept when the lot was last prepared or
    asked (by the scenario's name, as :func:`prepare_lot` keeps them for lots of
    :data:`REMEMBER_FROM` slot-types or more) where what they read is unchanged, and what
    it works out kept for the next: a question on a large lot prepared before is answered
    without working out its turns again. The planner is the same as without. ``margin``,
    when given, replaces the scenario's maneuver clearance. ``check``: the reuse check of
    the turns taken from the store (by default one when ``LOTSIM_VERIFY_REUSE=1``)."""
    remember = (lotsim.core.diskcache.cache_dir() is not None
                and len(lot.slots) * len(scenario.vehicle_types) >= REMEMBER_FROM)
    roads_name = _roads_name(scenario) if remember else None
    roads = _known(roads_name)
    held = len(roads or ())
    check = ReuseCheck.from_environment() if check is None else check
    memo = RoadmapMemo(lot, roads, settings=scenario.roadmap, reuse_check=check)
    planner = maneuver_planner(scenario, lot, margin=margin, memo=memo)
    if roads_name is not None and (memo.worked or len(roads) != held):
        lotsim.core.diskcache.store(roads_name, roads)
    return planner


def maneuver_planner(scenario: Scenario, lot: Lot, *, margin: float | None = None,
                     memo: RoadmapMemo | None = None) -> ManeuverPlanner:
    """The maneuver planner for ``lot``, tuned by the scenario's maneuver settings
    (``margin``, when given, replaces their clearance): clear of the scenario's parked
    cars, starting only where a car can arrive from an entrance or leave for an exit (along
    lanes: the ranges of the lot's lane graph, made with the scenario's roadmap settings,
    :func:`~lotsim.roadmap.reach.maneuver_ranges`; ``memo`` keeps what that graph works
    out for the graph through the maneuvers)."""
    lanes = lane_graph(lot, vehicles=scenario.vehicle_types, memo=memo,
                       settings=scenario.roadmap)
    return ManeuverPlanner(lot, settings=scenario.maneuvers, margin=margin,
                           parked_width=scenario.parked_vehicle.width,
                           lane_ranges=maneuver_ranges(lanes))


