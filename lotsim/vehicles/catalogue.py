"""Built-in vehicle types.

Seven cars from the ``car_param`` appendix of the report "Minimization of parking
slots for parallel parking" (2022; width, rear axle→front bumper, rear axle→rear
bumper, wheelbase, max steer in degrees) and the valet car of "Path planning in
automatic parking of unmanned vehicles" (a modelling-contest paper, 2022). The
paper gives the valet car's length (4.9 m), width (1.8 m),
wheelbase (2.8 m) and steering (470° at the wheel, 16:1, so 29.375°) but not
its overhangs; we take a 1.0 m rear overhang, so front = 3.9 m. Its limits are
the defaults of :class:`~lotsim.vehicles.model.VehicleLimits`.
"""

from __future__ import annotations

import math

from lotsim.vehicles.model import VehicleType

_REPORT_CARS = {
    "msv": (1.8, 3.7, 1.0, 2.7, 45.0),
    "zoe": (1.771, 3.427, 0.657, 2.588, 33.0),
    "corsa": (1.532, 3.212, 0.410, 2.343, 32.0),
    "vw": (1.994, 3.308, 1.192, 3.400, 36.0),
    "benz": (1.939, 3.528, 1.016, 2.630, 32.0),
    "altis": (1.780, 3.515, 0.815, 2.700, 28.0),
    "vclass": (1.928, 4.400, 0.970, 3.430, 29.0),
}

CATALOGUE: dict[str, VehicleType] = {
    name: VehicleType(name, w, df, dr, b, math.radians(deg))
    for name, (w, df, dr, b, deg) in _REPORT_CARS.items()
}
CATALOGUE["valet"] = VehicleType("valet", 1.8, 3.9, 1.0, 2.8, math.radians(470 / 16))

DEFAULT_VEHICLE = "valet"


def get_vehicle(name: str) -> VehicleType:
    """The catalogue car called ``name``.

    Raises
    ------
    KeyError
        With the known names, if there is no such car.
    """
    try:
        return CATALOGUE[name]
    except KeyError:
        raise KeyError(f"unknown car {name!r}; known: {', '.join(CATALOGUE)}") from None
