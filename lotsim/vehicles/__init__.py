"""Vehicle types: Ackermann kinematics, footprints, the built-in catalogue."""

from lotsim.vehicles.catalogue import CATALOGUE, DEFAULT_VEHICLE, get_vehicle
from lotsim.vehicles.model import KMH, VehicleLimits, VehicleType

__all__ = ["CATALOGUE", "DEFAULT_VEHICLE", "KMH", "VehicleLimits", "VehicleType", "get_vehicle"]
