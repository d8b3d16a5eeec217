"""The scenario: a lot layout, the vehicle types that use it, the traffic and a seed."""

from __future__ import annotations

from dataclasses import dataclass

from lotsim.lot.spec import LotSpec
from lotsim.traffic.demand import TrafficSpec
from lotsim.vehicles.model import VehicleType


@dataclass(frozen=True, slots=True)
class Scenario:
    """A validated scenario file.

    Attributes
    ----------
    name : str
    lot : LotSpec
    vehicle_types : tuple of VehicleType
        The types that drive in this lot; the lot is checked against all of them.
    parked_vehicle : VehicleType
        The type drawn in slots that are taken at start.
    seed : int
        Seed of every random choice made for this scenario.
    source : str
        The file it was read from.
    description : str
    traffic : TrafficSpec or None
        The vehicles that come to the lot; None when the scenario only describes a lot.

    A scenario is the problem, not how to draw it: its file's ``animation`` section is read
    apart (:func:`lotsim.io.scenario_yaml.read_scenario`, :class:`lotsim.settings.AnimationSpec`).
    """

    name: str
    lot: LotSpec
    vehicle_types: tuple[VehicleType, ...]
    parked_vehicle: VehicleType
    seed: int = 0
    source: str = "<memory>"
    description: str = ""
    traffic: TrafficSpec | None = None

    def vehicle_type(self, name: str) -> VehicleType:
        """The vehicle type called ``name``; KeyError if the scenario has none."""
        for v in self.vehicle_types:
            if v.name == name:
                return v
        raise KeyError(name)
