"""Closed forms for parallel parking (J. White, "Parallel Parking Optimization", parts 1
and 2, 2009).

White's radius ``r`` is measured from the centre of rotation to the outer wall of the
outer front tyre. With the body's side taken as the tyre wall, the centre lies on the
rear-axle line at ``R = b / tan(max_steer)`` from the rear-axle centre, so

    r_b = sqrt(r² - b²) = R + w / 2,    i.e.    r = sqrt((b / tan φmax + w / 2)² + b²).

Pt. 1 gives the least extra length ``d`` beyond the car's length for one reverse arc
and one forward arc; it is exactly the minimum-slot strategy of
:mod:`lotsim.maneuvers.minslot` with one direction change when the car in front
protrudes the slot's width (``w1 = W``) and the car ends with its outer side on the
entry line (``d_c = W - w``). Pt. 2 gives the sideways gain of one forward–reverse
cycle of four equal arcs in a slot ``d`` longer than the car.
"""

from __future__ import annotations

import math

from lotsim.vehicles.model import VehicleType


def white_radius(vehicle: VehicleType) -> float:
    """White's kerb-to-kerb radius ``r`` [m] from the wheelbase, max steer and width."""
    return math.hypot(vehicle.min_turning_radius + vehicle.width / 2, vehicle.wheelbase)


def one_change_excess(vehicle: VehicleType, slot_width: float) -> tuple[float, float]:
    """White Pt. 1: least extra slot length ``d`` [m] and switch angle ``alpha`` [rad].

    For the minimum-slot strategy in a slot ``slot_width`` wide (``w1 = W``,
    ``d_c = W - w``). The slot must be at least ``d + length`` long.

    >>> from lotsim.vehicles import CATALOGUE
    >>> round(one_change_excess(CATALOGUE["altis"], 2.5)[0], 3)
    1.258
    """
    b, w0 = vehicle.wheelbase, vehicle.width
    k = vehicle.front - b  # front axle to front bumper
    j = vehicle.rear
    r_b = math.sqrt(white_radius(vehicle) ** 2 - b**2)
    r_c = 2 * r_b - w0
    d_c, w1 = slot_width - w0, slot_width
    m = r_b - w0 - d_c + w1
    n = b + k
    alpha = math.asin((r_b**2 - r_c**2 - m**2) / (2 * r_c * math.hypot(m, n))) + math.atan2(m, n)
    return r_b * math.sin(alpha) - j * (1 - math.cos(alpha)), alpha


def sideways_gain(vehicle: VehicleType, excess: float) -> float:
    """White Pt. 2: sideways displacement [m] of one forward–reverse cycle of four arcs.

    ``excess`` is the slot length beyond the car's length [m]; each arc turns by
    ``alpha = asin(excess / (2 R))`` about a centre ``R`` from the rear-axle centre,
    and the four arcs move the car ``4 R (1 - cos alpha)`` sideways.
    """
    r_d = vehicle.min_turning_radius
    if not 0 <= excess <= 2 * r_d:
        raise ValueError("excess must lie between 0 and twice the turning radius")
    return 4 * r_d - 2 * math.sqrt(4 * r_d**2 - excess**2)
