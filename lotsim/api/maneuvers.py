"""One car, one slot: a vehicle type by name or file (:func:`car`), the shortest parallel
slot for each number of direction changes (:func:`minslot`), and one slot's parking
maneuver (:func:`maneuver_case`, :func:`plan_maneuver`)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lotsim.api.scenarios import (
    EXAMPLE,  # noqa: F401 (the examples)
    ScenarioLike,
    scenario_of,
    source_of,
    with_settings,
)
from lotsim.core import checks as _checks
from lotsim.errors import SettingsError
from lotsim.maneuvers.settings import ManeuverSettings, MinSlotSettings
from lotsim.maneuvers.slot_table import MinSlotTable, min_slot_table
from lotsim.sim.maneuver_case import ManeuverCase

if TYPE_CHECKING:
    from lotsim.maneuvers.maneuver import Maneuver
    from lotsim.vehicles.model import VehicleType


def car(name_or_path: str | os.PathLike) -> VehicleType:
    """A vehicle type: a catalogue name (``lotsim cars``) or a vehicle YAML file.

    >>> car("altis").min_turning_radius > 5
    True
    """
    from lotsim.vehicles.catalogue import CATALOGUE

    if isinstance(name_or_path, str) and name_or_path in CATALOGUE:
        return CATALOGUE[name_or_path]
    p = Path(name_or_path)
    if p.suffix in (".yaml", ".yml") or p.exists():
        from lotsim.io.scenario_yaml import load_vehicle

        return load_vehicle(p)
    raise SettingsError("car", f"unknown vehicle {os.fspath(name_or_path)!r}; expected one "
                               f"of {', '.join(CATALOGUE)} (lotsim cars lists them) or a "
                               "vehicle YAML file")


def minslot(vehicle: VehicleType | str | os.PathLike, width: float,
            settings: MinSlotSettings | None = None, *, narrow_ok: bool = False,
            **overrides: Any) -> MinSlotTable:
    """The shortest parallel slot for each number of direction changes (``lotsim minslot``):
    the minimum-slot strategy (Vlasák, Sojka & Hanzálek 2022), swept over start headings,
    lengths bisected.

    Parameters
    ----------
    vehicle : VehicleType, str or path-like
        A vehicle type, a catalogue name or a vehicle YAML file (:func:`car`).
    width : float
        Slot width [m], positive, at least the car's width
        (:func:`~lotsim.maneuvers.slot_table.check_slot_width`).
    settings : MinSlotSettings, optional
    narrow_ok : bool, keyword-only
        Give a slot narrower than the car a table with no length (None) for every number of
        changes, as ``lotsim minslot --all-cars`` lists such cars, instead of the error.
    **overrides
        Fields of :class:`MinSlotSettings`: ``max_changes``, ``resolution`` [m],
        ``step_deg`` [deg].

    Raises
    ------
    SettingsError
        For a setting out of range, an unknown car or a width it cannot use.

    Examples
    --------
    >>> table = minslot("altis", 2.5, max_changes=1, step_deg=0.2)
    >>> [(r.changes, round(r.length, 2)) for r in table.rows]
    [(0, 6.06), (1, 5.59)]
    """
    s = _checks.replace(settings or MinSlotSettings(), overrides)
    v = vehicle if not isinstance(vehicle, (str, os.PathLike)) else car(vehicle)
    return min_slot_table(v, width, s, narrow_ok=narrow_ok)


def maneuver_case(scenario: ScenarioLike, slot: str, *, vehicle: str | None = None,
                  lane: str | None = None, style: str = "any", margin: float | None = None,
                  maneuvers: ManeuverSettings | None = None) -> ManeuverCase:
    """The checked problem :func:`plan_maneuver` solves: the lot built, the slot, the
    vehicle type, the lane and the planner; ``.plan()`` solves it, and
    :func:`render_maneuver` draws the answer. Parameters as :func:`plan_maneuver`.

    Only that slot's maneuvers are planned, on the lot's lanes (where a car can arrive
    or leave, with the turns and turnarounds kept when the lot was last prepared, when it
    was); a type wider or longer than the slot is refused at once
    (:class:`~lotsim.errors.InfeasibleManeuver`).

    Examples
    --------
    >>> case = maneuver_case(EXAMPLE, "N3", style="reverse")
    >>> case.slot.id, case.vehicle.name, case.plan().strokes()[0][0]
    ('N3', 'valet', -1)
    """
    sc = with_settings(scenario_of(scenario), maneuvers=maneuvers)
    return ManeuverCase.build(sc, slot, vehicle=vehicle, lane=lane, style=style,
                              margin=margin, source=source_of(scenario))


def plan_maneuver(scenario: ScenarioLike, slot: str, *, vehicle: str | None = None,
                  lane: str | None = None, style: str = "any", leave: bool = False,
                  margin: float | None = None, maneuvers: ManeuverSettings | None = None
                  ) -> Maneuver:
    """One slot's parking (or leaving) maneuver (``lotsim maneuver``): fewest direction
    changes, then shortest, clear of the parked cars, walls and the aisle's far side.

    Parameters
    ----------
    scenario : Scenario, path or YAML text
    slot : str
        Slot id.
    vehicle : str, optional, keyword-only
        A vehicle type of the scenario (default its first).
    lane : str, optional, keyword-only
        The lane to start from (default the best).
    style : {"any", "forward", "reverse"}, keyword-only
        Nose-in, backed in, or the better.
    leave : bool, keyword-only
        The way out instead of the way in.
    margin : float, optional, keyword-only
        Clearance kept [m], 0 to 1; default the maneuver settings'.
    maneuvers : ManeuverSettings, optional, keyword-only
        The maneuver planner's tuning; default the scenario's (its file's ``maneuvers``
        section).

    Returns
    -------
    Maneuver
        ``.strokes()``, ``.changes``, ``.length`` [m], ``.duration(vehicle)`` [s],
        ``.sample()``.

    Raises
    ------
    SettingsError
        An unknown slot, vehicle type or lane, or a margin out of range.
    InfeasibleManeuver
        When the vehicle cannot park there, with the reason.

    Examples
    --------
    >>> m = plan_maneuver(EXAMPLE, "N3")
    >>> m.slot, m.changes >= 0
    ('N3', True)
    >>> plan_maneuver(EXAMPLE, "N9")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: slot: no slot 'N9' in <scenario> (its slots: N1–N4, S1–S4; ...
    """
    case = maneuver_case(scenario, slot, vehicle=vehicle, lane=lane, style=style,
                         margin=margin, maneuvers=maneuvers)
    return case.plan(leave=leave)
