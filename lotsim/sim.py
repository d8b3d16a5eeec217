"""The simulation pipeline, scenario in, results out (the planning stages land in later issues)."""

from __future__ import annotations

from lotsim.lot.build import build_lot
from lotsim.lot.graph import LotGraph, build_graph
from lotsim.lot.model import DesignVehicle
from lotsim.scenario import Scenario


def prepare(scenario: Scenario, *, node_spacing: float = 4.0) -> LotGraph:
    """Build the scenario's lot for its vehicle types, and the lot's drivable graph.

    Raises
    ------
    ScenarioError
        When the layout does not hold together (overlaps, narrow aisles, ...).
    """
    lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
    return build_graph(lot, node_spacing=node_spacing)
