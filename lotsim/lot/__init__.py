"""Lot layouts: specs read from YAML, the built lot (slots, aisles, lanes), its graph."""

from lotsim.lot.build import build_lot
from lotsim.lot.graph import LotGraph, Reachability, build_graph
from lotsim.lot.model import Aisle, Area, DesignVehicle, Lane, Lot, Portal, Slot, SpeedZone

__all__ = [
    "Aisle",
    "Area",
    "DesignVehicle",
    "Lane",
    "Lot",
    "LotGraph",
    "Portal",
    "Reachability",
    "Slot",
    "SpeedZone",
    "build_graph",
    "build_lot",
]
