"""The simulation pipeline, scenario in, results out (the planning stages land in later issues)."""

from __future__ import annotations

from lotsim.lot.build import build_lot
from lotsim.lot.graph import LotGraph, build_graph
from lotsim.lot.model import DesignVehicle, Lot
from lotsim.planners.maneuver import MARGIN, ManeuverPlanner, plan_lot
from lotsim.scenario import Scenario


def prepare(scenario: Scenario, *, node_spacing: float = 4.0, maneuvers: bool = True,
            margin: float = MARGIN) -> LotGraph:
    """Build the scenario's lot for its vehicle types, plan every slot's parking maneuver
    for every type, and build the lot's drivable graph through them.

    The slots a type cannot use are in ``LotGraph.infeasible`` (type → slot → reason).
    With ``maneuvers=False`` slots hang off placeholder links (quick, for pictures).

    Raises
    ------
    ScenarioError
        When the layout does not hold together (overlaps, narrow aisles, ...).
    """
    lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
    if not maneuvers:
        return build_graph(lot, node_spacing=node_spacing)
    planner = maneuver_planner(scenario, lot, margin=margin)
    planned, infeasible = plan_lot(planner, scenario.vehicle_types)
    lg = build_graph(lot, node_spacing=node_spacing, maneuvers=planned,
                     vehicles=scenario.vehicle_types)
    lg.infeasible = infeasible
    lg.maneuver_planner = planner
    return lg


def maneuver_planner(scenario: Scenario, lot: Lot, *, margin: float = MARGIN) -> ManeuverPlanner:
    """The maneuver planner for ``lot``: clear of the scenario's parked cars, starting only
    where a car can arrive from an entrance and leave for an exit."""
    return ManeuverPlanner(lot, margin=margin, parked_width=scenario.parked_vehicle.width,
                           lane_ranges=build_graph(lot).through())
