"""The scenario: a lot layout, the vehicle types that use it, and a seed."""

from __future__ import annotations

from dataclasses import dataclass

from lotsim.lot.spec import LotSpec
from lotsim.traffic import TrafficSpec
from lotsim.vehicles.model import VehicleType


@dataclass(frozen=True, slots=True)
class AnimationSpec:
    """The scenario's ``animation`` section: ``lotsim run`` also writes a GIF.

    Attributes
    ----------
    gif : str
        File name of the GIF, written beside ``result.json``.
    fps, speed, size, start, end, max_frames, trail
        As :class:`lotsim.render.animation.GifSettings`; ``None`` for the default.
    """

    gif: str = "run.gif"
    fps: float | None = None
    speed: float | None = None
    size: tuple[int, int] | None = None
    start: float | None = None
    end: float | None = None
    max_frames: int | None = None
    trail: float | None = None


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
    animation : AnimationSpec or None
        Present when ``lotsim run`` should also write a GIF.
    """

    name: str
    lot: LotSpec
    vehicle_types: tuple[VehicleType, ...]
    parked_vehicle: VehicleType
    seed: int = 0
    source: str = "<memory>"
    description: str = ""
    traffic: TrafficSpec | None = None
    animation: AnimationSpec | None = None

    def vehicle_type(self, name: str) -> VehicleType:
        """The vehicle type called ``name``; KeyError if the scenario has none."""
        for v in self.vehicle_types:
            if v.name == name:
                return v
        raise KeyError(name)
