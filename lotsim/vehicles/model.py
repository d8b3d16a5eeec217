"""The Ackermann vehicle type: dimensions, limits, footprints and exact motion."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from lotsim.core.geometry import FloatArray, advance, rectangle_footprints

KMH = 1 / 3.6
"""One km/h in m/s."""


@dataclass(frozen=True, slots=True)
class VehicleLimits:
    """Driving limits; the defaults are the valet car's, from "Path planning in automatic
    parking of unmanned vehicles" (a modelling-contest paper, 2022).

    Attributes
    ----------
    max_forward_speed : float
        [m/s], default 20 km/h.
    max_reverse_speed : float
        [m/s], default 10 km/h.
    max_accel : float
        Throttle acceleration [m/s²].
    max_brake : float
        Braking deceleration, positive [m/s²].
    max_jerk : float
        Rate of change of acceleration [m/s³], default 20 (the valet paper's).
    max_steer_rate : float
        Road-wheel steering rate [rad/s]; default 400°/s at the steering wheel at
        16:1 (the valet paper's), i.e. 25°/s: lock to lock takes 2.35 s.
    max_lateral_accel : float
        Sideways acceleration ``v² · |curvature|`` [m/s²], default 2.0 (0.2 g): a
        comfort bound for passengers of a car driven for them at parking speeds.
        Human drivers take low-speed turns at up to 3–4 m/s²; the valet paper gives
        no figure. At the valet car's tightest radius (4.97 m) it allows 11.4 km/h.
    """

    max_forward_speed: float = 20 * KMH
    max_reverse_speed: float = 10 * KMH
    max_accel: float = 3.0
    max_brake: float = 6.0
    max_jerk: float = 20.0
    max_steer_rate: float = math.radians(400 / 16)
    max_lateral_accel: float = 2.0

    def __post_init__(self) -> None:
        for key in ("max_forward_speed", "max_reverse_speed", "max_accel", "max_brake",
                    "max_jerk", "max_steer_rate", "max_lateral_accel"):
            value = getattr(self, key)
            if not (value > 0 and math.isfinite(value)):
                raise ValueError(f"{key} must be positive and finite, got {value!r}")


@dataclass(frozen=True, slots=True)
class VehicleType:
    """A car-like vehicle with rear-axle reference point.

    Attributes
    ----------
    name : str
    width : float
        Body width [m].
    front : float
        Rear axle to front bumper [m].
    rear : float
        Rear axle to rear bumper [m].
    wheelbase : float
        [m].
    max_steer : float
        Maximum road-wheel steering angle [rad], 0 < max_steer < pi/2.
    limits : VehicleLimits
    marks : frozenset of str
        What the type is marked as in its scenario (``accessible``, ``ev``,
        ``motorcycle``): the bays of which uses it may park in
        (:data:`lotsim.lot.uses.USES`). Unmarked by default.

    Examples
    --------
    >>> car = VehicleType("box", width=2.0, front=3.0, rear=1.0, wheelbase=2.5,
    ...                   max_steer=math.radians(45))
    >>> round(car.length, 3), round(car.min_turning_radius, 3)
    (4.0, 2.5)
    >>> car.footprints([[0.0, 0.0, 0.0]]).tolist()
    [[[-1.0, -1.0], [3.0, -1.0], [3.0, 1.0], [-1.0, 1.0]]]
    """

    name: str
    width: float
    front: float
    rear: float
    wheelbase: float
    max_steer: float
    limits: VehicleLimits = field(default_factory=VehicleLimits)
    marks: frozenset[str] = frozenset()

    def __post_init__(self) -> None:
        for key in ("width", "front", "wheelbase", "max_steer"):
            if not getattr(self, key) > 0:
                raise ValueError(f"{key} must be positive, got {getattr(self, key)!r}")
        if not self.rear >= 0:
            raise ValueError(f"rear must be zero or positive, got {self.rear!r}")
        if not self.max_steer < math.pi / 2:
            raise ValueError("max_steer must be below 90°")

    @property
    def length(self) -> float:
        """Bumper to bumper [m]."""
        return self.front + self.rear

    @property
    def min_turning_radius(self) -> float:
        """Radius of the rear-axle centre's tightest circle, ``b / tan(max_steer)`` [m]."""
        return self.wheelbase / math.tan(self.max_steer)

    @property
    def max_curvature(self) -> float:
        """``1 / min_turning_radius`` [1/m]."""
        return math.tan(self.max_steer) / self.wheelbase

    @property
    def outline(self) -> FloatArray:
        """Body corners in the vehicle frame, counter-clockwise from rear right; (4, 2)."""
        h = self.width / 2
        return np.array(
            [[-self.rear, -h], [self.front, -h], [self.front, h], [-self.rear, h]], dtype=float
        )

    def curvature(self, steer: ArrayLike) -> FloatArray:
        """Path curvature of the rear-axle centre at road-wheel angle ``steer`` [1/m]."""
        return np.tan(np.asarray(steer, dtype=float)) / self.wheelbase

    def footprints(self, poses: ArrayLike) -> FloatArray:
        """Body rectangles at many poses in one operation.

        Parameters
        ----------
        poses : array_like, shape (N, 3) or (3,)

        Returns
        -------
        ndarray, shape (N, 4, 2)
            Corners in world coordinates, counter-clockwise from rear right.
        """
        return rectangle_footprints(poses, self.outline)

    def drive(self, poses: ArrayLike, distance: ArrayLike, steer: ArrayLike) -> FloatArray:
        """Poses after driving a signed ``distance`` [m] at constant ``steer`` [rad], exactly."""
        return advance(poses, distance, self.curvature(steer))
