"""The shortest parallel slot of one width for each number of direction changes, as one
table (:class:`MinSlotTable`: what ``lotsim minslot`` prints), and the slot widths such a
table cannot be made for (:func:`check_slot_width`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from lotsim.core import checks
from lotsim.errors import SettingsError
from lotsim.maneuvers import minslot
from lotsim.maneuvers.minslot import MinSlotRow
from lotsim.maneuvers.settings import MinSlotSettings
from lotsim.vehicles.model import VehicleType


@dataclass(frozen=True)
class MinSlotTable:
    """The shortest parallel slot of a given width for each number of direction changes."""

    car: VehicleType
    width: float
    """Slot width [m]."""
    rows: tuple[MinSlotRow, ...]
    """``changes``, ``length`` [m] (None: no length up to twice the car's works) and a start
    heading ``theta0`` [rad] that achieves it."""

    def to_dict(self) -> dict:
        """What ``lotsim minslot --json`` prints for one car and width."""
        c = self.car
        return {"car": c.name, "car_length": round(c.length, 4), "width": self.width,
                "rows": [{"changes": r.changes, "length": r.length,
                          "ratio": None if r.length is None else round(r.length / c.length, 4)}
                         for r in self.rows]}


def check_slot_width(vehicle: VehicleType, width: float, *, narrow_ok: bool = False) -> None:
    """Refuse a slot width no table can be made for: not a positive number of metres, or
    (unless ``narrow_ok``) narrower than the car, where no length works.

    Raises
    ------
    SettingsError
        Named ``width``.

    Examples
    --------
    >>> from lotsim.vehicles.catalogue import CATALOGUE
    >>> check_slot_width(CATALOGUE["altis"], 1.5)
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: width: a 1.5 m slot is narrower than altis (1.78 m wide)
    """
    if not (checks.is_real(width) and 0 < width < math.inf):
        raise SettingsError("width", f"expected a positive slot width in metres, found "
                                     f"{checks.shown(width)}")
    if width < vehicle.width and not narrow_ok:
        raise SettingsError("width", f"a {width:g} m slot is narrower than {vehicle.name} "
                                     f"({vehicle.width:g} m wide)")


def min_slot_table(vehicle: VehicleType, width: float, settings: MinSlotSettings, *,
                   narrow_ok: bool = False) -> MinSlotTable:
    """The table for ``vehicle`` and a slot ``width`` [m] wide: the minimum-slot strategy
    (Vlasák, Sojka & Hanzálek 2022) swept over start headings, each length bisected
    (:func:`~lotsim.maneuvers.minslot.min_slot_lengths`), after :func:`check_slot_width`.
    """
    check_slot_width(vehicle, width, narrow_ok=narrow_ok)
    rows = minslot.min_slot_lengths(vehicle, width, max_changes=settings.max_changes,
                                    resolution=settings.resolution, step_deg=settings.step_deg)
    return MinSlotTable(vehicle, width, tuple(rows))
