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


def kerb_circle_steer(diameter: float, wheelbase: float, track: float) -> float:
    """The maximum road-wheel steer [rad] of a vehicle whose turning circle between kerbs
    is ``diameter`` [m]: the circle the outer front tyre draws at full lock.

    With the bicycle model the rear-axle centre turns on ``R = b / tan(φmax)``, and the
    outer front tyre, ``track / 2`` outside it and ``b`` ahead, on
    ``√((R + track/2)² + b²)``; a published kerb-to-kerb circle gives ``R``, and so
    ``φmax``, the way the cars' maximum steer gives their radius.

    Examples
    --------
    >>> round(math.degrees(kerb_circle_steer(16.8, 4.3, 2.5)), 2)
    35.78
    """
    outer = diameter / 2
    if not outer > wheelbase:
        raise ValueError(f"a {diameter} m circle is too tight for a {wheelbase} m wheelbase")
    radius = math.sqrt(outer * outer - wheelbase * wheelbase) - track / 2
    if not radius > 0:
        raise ValueError(f"a {diameter} m circle is too tight for a {track} m track")
    return math.atan(wheelbase / radius)


# Service vehicles: the design vehicles a lot designer checks a site's access for. They
# drive the scenario's ``routes`` (lotsim.roadmap.service_routes), not its traffic; they
# are kept apart from CATALOGUE, the cars that park.
#
# fire_pump: a UK pumping appliance. Its turning circle is the 16.8 m between kerbs of
# "Approved Document B (Fire safety), Volume 2" (HM Government, 2019 edition), Table 15.1,
# "Typical fire and rescue service vehicle access route specification" (pump: 3.7 m road,
# 16.8 m between kerbs, 19.2 m between walls). Its body is Strathclyde Fire Brigade's
# Rescue Pump Ladder (Scania chassis-cab, 4.3 m wheelbase, 2.5 m wide; its Aerial Rescue
# Pump is 9.5 m long, "almost 4 feet longer", so the pump is taken as 8.3 m long): G.
# Kirkwood, "Strathclyde Fire Brigade: Rescue Pump Ladder" and "Aerial Rescue Pump".
# Assumed: a 1.4 m front overhang (a crew cab over the front axle), so 2.6 m behind the
# rear axle; the tyres' outer track is the body's 2.5 m width.
#
# refuse_26t: a three-axle 26 t refuse collection vehicle (6x2, rear-steer), from Douglas
# Borough Council, "Waste Management Guidelines: Vehicle Dimensions" (2020): 2.524 m wide,
# 10.564 m long, 4.2 m from the first axle to the second, 1.35 m to the third (which
# steers, so the second is the rear axle the bicycle model turns about), 17.0 m turning
# circle between kerbs. Assumed: a 1.45 m front overhang (a low-entry cab), so 4.914 m
# behind the rear axle; the outer track is the body's width.
_SERVICE = {
    # name: (width, front overhang, wheelbase, length, kerb-to-kerb circle)
    "fire_pump": (2.5, 1.4, 4.3, 8.3, 16.8),
    "refuse_26t": (2.524, 1.45, 4.2, 10.564, 17.0),
}

SERVICE_VEHICLES: dict[str, VehicleType] = {
    name: VehicleType(name, w, overhang + b, length - overhang - b, b,
                      kerb_circle_steer(circle, b, w))
    for name, (w, overhang, b, length, circle) in _SERVICE.items()
}
"""The service vehicles a scenario's routes may name: a fire appliance and a refuse truck."""


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


def route_vehicle(name: str) -> VehicleType:
    """The service vehicle or catalogue car called ``name``: what a route may name.

    Examples
    --------
    >>> v = route_vehicle("fire_pump")
    >>> round(v.length, 2), round(v.min_turning_radius, 2)
    (8.3, 5.97)
    """
    if name in SERVICE_VEHICLES:
        return SERVICE_VEHICLES[name]
    if name in CATALOGUE:
        return CATALOGUE[name]
    raise KeyError(f"unknown vehicle {name!r}; known: "
                   f"{', '.join([*SERVICE_VEHICLES, *CATALOGUE])}")
