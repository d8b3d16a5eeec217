"""The static world: lot specs read from YAML (:mod:`~lotsim.lot.spec`), the built lot with
its slots, aisles, lanes, obstacles and zones (:mod:`~lotsim.lot.build`,
:mod:`~lotsim.lot.model`) and the clearance checks against it
(:mod:`~lotsim.lot.clearance`)."""

from lotsim.lot.build import build_lot
from lotsim.lot.model import Aisle, Area, DesignVehicle, Lane, Lot, Portal, Slot, SpeedZone

__all__ = [
    "Aisle",
    "Area",
    "DesignVehicle",
    "Lane",
    "Lot",
    "Portal",
    "Slot",
    "SpeedZone",
    "build_lot",
]
