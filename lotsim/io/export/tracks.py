"""What every export reads from a ``result.json``: each car's timed track and its visit.

A :class:`CarTrack` is one vehicle's samples as numpy arrays (rear-axle centre pose, signed
speed, road-wheel steer, gear; ``docs/result.md``) with the dimensions of its type. A
:class:`~lotsim.io.visits.Visit` (:func:`~lotsim.io.visits.visits`, the replay's reader
too) says when it came, when it stood in its slot and when it left.

:func:`resample` puts a track on a uniform clock (the CommonRoad step) by the same linear
interpolation that ``docs/result.md`` defines between samples (heading the short way round),
and :func:`resample_error` measures how far the resampled track strays from the samples it
skips: that is the whole approximation of the step. :func:`offset_line` draws a lane beside
its aisle's centreline.

Examples
--------
>>> import numpy as np
>>> tr = CarTrack("a", VehicleShape("car", 1.8, 3.9, 1.0, 2.8, 0.5, 0.4),
...            *np.array([[0.0, 0.1, 0.2], [0.0, 0.1, 0.2], [0.0, 0.0, 0.0], [0.0] * 3,
...                       [1.0] * 3, [0.0] * 3, [1, 1, 1]]))
>>> resample(tr, np.array([0.05, 0.15]))["x"].round(3).tolist()
[0.05, 0.15]
>>> round(tr.shape.length, 1), forward(tr.x, tr.y, tr.theta, 1.4)[0].round(1).tolist()
(4.9, [1.4, 1.5, 1.6])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from lotsim.core.geometry import FloatArray
from lotsim.errors import LotsimError
from lotsim.io.visits import Visit as Visit  # the one reader of a car's visit
from lotsim.io.visits import visits as visits


class ExportError(LotsimError, ValueError):
    """A result that cannot be exported (the message says why)."""


class ExportUnavailable(LotsimError):
    """An export's optional packages are not installed (the message names the extra)."""


def require(module: str, extra: str) -> Any:
    """Import ``module`` or raise :class:`ExportUnavailable` naming ``pip install
    'lotsim[extra]'``."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise ExportUnavailable(
            f"the {extra} export needs the {module.split('.')[0]} "
            f"package: pip install 'lotsim[{extra}]'"
        ) from None


@dataclass(frozen=True, slots=True)
class VehicleShape:
    """A vehicle type as ``result.json`` gives it (``vehicles[i].type``)."""

    name: str
    width: float
    """[m]"""
    front: float
    """Rear axle to front bumper [m]."""
    rear: float
    """Rear axle to rear bumper [m]."""
    wheelbase: float
    """[m]"""
    max_steer: float
    """Road-wheel angle [rad]."""
    max_steer_rate: float
    """Road-wheel angle rate [rad/s]."""
    max_forward_speed: float = math.inf
    """[m/s]"""
    max_reverse_speed: float = math.inf
    """[m/s]"""
    max_accel: float = math.inf
    """[m/s²]"""
    max_brake: float = math.inf
    """[m/s²]"""

    @property
    def length(self) -> float:
        """Bumper to bumper [m]."""
        return self.front + self.rear

    @classmethod
    def from_json(cls, t: dict) -> VehicleShape:
        return cls(
            str(t["name"]),
            *(
                float(t[k])
                for k in (
                    "width",
                    "front",
                    "rear",
                    "wheelbase",
                    "max_steer",
                    "max_steer_rate",
                    "max_forward_speed",
                    "max_reverse_speed",
                    "max_accel",
                    "max_brake",
                )
            ),
        )


@dataclass(frozen=True, slots=True)
class CarTrack:
    """One vehicle's samples: time [s], rear-axle centre ``x``, ``y`` [m], heading
    ``theta`` [rad], signed speed ``v`` [m/s], road-wheel ``steer`` [rad], ``gear``."""

    id: str
    shape: VehicleShape
    t: FloatArray
    x: FloatArray
    y: FloatArray
    theta: FloatArray
    v: FloatArray
    steer: FloatArray
    gear: FloatArray

    def __len__(self) -> int:
        return len(self.t)


def tracks(doc: dict) -> list[CarTrack]:
    """Every vehicle with samples, in the file's (arrival) order."""
    out = []
    for v in doc["vehicles"]:
        s = v.get("samples") or {}
        if len(s.get("t", ())) == 0:
            continue
        cols = [
            np.asarray(s[k], dtype=float) for k in ("t", "x", "y", "theta", "v", "steer", "gear")
        ]
        out.append(CarTrack(str(v["id"]), VehicleShape.from_json(v["type"]), *cols))
    return out


def forward(
    x: FloatArray, y: FloatArray, theta: FloatArray, d: float
) -> tuple[FloatArray, FloatArray]:
    """Points ``d`` metres ahead of ``(x, y)`` along ``theta`` (behind when negative)."""
    return x + d * np.cos(theta), y + d * np.sin(theta)


def offset_line(points, d: float) -> np.ndarray:
    """``points`` moved ``d`` metres to the left of their direction (mitred at corners):
    a lane's line from its aisle's centreline and the lane's offset, the same for every
    export that draws lanes (CommonRoad's lanelets, SUMO's edges).

    >>> offset_line([[0, 0], [10, 0], [10, 10]], 1.0).tolist()
    [[0.0, 1.0], [9.0, 1.0], [9.0, 10.0]]
    """
    p = np.asarray(points, dtype=float)
    seg = np.diff(p, axis=0)
    n = np.stack([-seg[:, 1], seg[:, 0]], axis=1) / np.hypot(*seg.T)[:, None]
    normals = np.concatenate([n[:1], n[:-1] + n[1:], n[-1:]])
    normals /= np.hypot(*normals.T)[:, None]
    cos_half = np.ones(len(p))
    cos_half[1:-1] = np.einsum("ij,ij->i", normals[1:-1], n[:-1])
    return p + d * normals / cos_half[:, None]


def resample(tr: CarTrack, times: FloatArray) -> dict[str, FloatArray]:
    """The track at ``times`` [s] (within its first and last sample): pose, speed and steer
    interpolated linearly between samples, the heading the short way round.

    Returns
    -------
    dict
        ``x``, ``y``, ``theta`` (unwrapped: continuous, not wrapped into a range), ``v``,
        ``steer``: arrays like ``times``.
    """
    theta = np.unwrap(tr.theta)
    return {
        "x": np.interp(times, tr.t, tr.x),
        "y": np.interp(times, tr.t, tr.y),
        "theta": np.interp(times, tr.t, theta),
        "v": np.interp(times, tr.t, tr.v),
        "steer": np.interp(times, tr.t, tr.steer),
    }


def resample_error(tr: CarTrack, times: FloatArray) -> tuple[float, float]:
    """How far the track resampled at ``times`` (linear between them) strays from the
    samples it skips within ``[times[0], times[-1]]``: the largest distance of the
    rear-axle centre [m] and of the heading [rad]."""
    keep = (tr.t >= times[0]) & (tr.t <= times[-1])
    if not keep.any():
        return 0.0, 0.0
    r = resample(tr, times)
    t = tr.t[keep]
    x, y = np.interp(t, times, r["x"]), np.interp(t, times, r["y"])
    th = np.interp(t, times, r["theta"])
    dp = np.hypot(x - tr.x[keep], y - tr.y[keep])
    dth = np.abs((th - tr.theta[keep] + np.pi) % (2 * np.pi) - np.pi)
    return float(dp.max()), float(dth.max())
