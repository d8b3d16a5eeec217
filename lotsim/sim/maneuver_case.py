"""One slot's parking problem taken out of a scenario (``lotsim maneuver``): the lot built,
the slot, the vehicle type, the lane to start from, and the maneuver planner that solves it
as preparing the lot would (clear of the scenario's parked cars, starting only where a car
can arrive or leave)."""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import TYPE_CHECKING

from lotsim.core import checks
from lotsim.errors import InfeasibleManeuver, SettingsError
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle, Lot, Slot
from lotsim.maneuvers.planner import misfit
from lotsim.maneuvers.settings import STYLES
from lotsim.scenario import Scenario
from lotsim.sim.preparation import remembered_planner
from lotsim.sim.validation import id_ranges
from lotsim.vehicles.model import VehicleType

if TYPE_CHECKING:
    from lotsim.maneuvers.maneuver import Maneuver
    from lotsim.maneuvers.planner import ManeuverPlanner


@dataclass(frozen=True)
class ManeuverCase:
    """A checked one-slot problem: :meth:`plan` solves it, and the picture of its answer
    is drawn on ``lot`` for ``vehicle``.

    Attributes
    ----------
    scenario : Scenario
    lot : Lot
        The scenario's lot, built for its vehicle types.
    vehicle : VehicleType
    slot : Slot
    planner : ManeuverPlanner
        The planner with the scenario's maneuver settings (and the margin asked for) and
        parked cars.
    lane : str or None
        The lane to start from (None: the best of the slot's lanes).
    style : {"any", "forward", "reverse"}
    """

    scenario: Scenario
    lot: Lot
    vehicle: VehicleType
    slot: Slot
    planner: ManeuverPlanner
    lane: str | None
    style: str = "any"

    @classmethod
    def build(cls, scenario: Scenario, slot: str, *, vehicle: str | None = None,
              lane: str | None = None, style: str = "any", margin: float | None = None,
              source: str | None = None) -> ManeuverCase:
        """The case of slot ``slot`` in ``scenario`` (``source`` names it in messages).

        Raises
        ------
        SettingsError
            An unknown slot (with the closest ids), vehicle type, lane or style, or a
            margin outside 0 to 1 m.
        InfeasibleManeuver
            When the vehicle type is wider or longer than the slot (before any lane is
            worked out).
        """
        problem = checks.choice_problem(style, STYLES)
        if problem:
            raise SettingsError("style", problem)
        if margin is not None and not (checks.is_real(margin) and 0.0 <= margin <= 1.0):
            raise SettingsError("margin", f"expected 0 to 1 m, found {checks.shown(margin)}")
        names = [v.name for v in scenario.vehicle_types]
        vname = vehicle or names[0]
        if vname not in names:
            raise SettingsError("vehicle", f"expected one of {', '.join(names)}, found "
                                           f"{vname!r}")
        lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
        chosen = lot.slot_by_id.get(slot)
        if chosen is None:
            close = difflib.get_close_matches(str(slot), list(lot.slot_by_id), n=3)
            hint = f"; did you mean {', '.join(close)}?" if close else ""
            raise SettingsError("slot", f"no slot {slot!r} in {source or scenario.source}"
                                        f"{hint} (its slots: {id_ranges(lot.slot_by_id)}; "
                                        f"lotsim show draws them)")
        why = misfit(scenario.vehicle_type(vname), chosen)
        if why is not None:  # said at once: no lane can change it
            raise InfeasibleManeuver(f"{vname} cannot park in slot {chosen.id!r}: {why}")
        planner = remembered_planner(scenario, lot, margin=margin)
        lanes = [ln.id for ln in planner.lanes_for(chosen)]
        if lane is not None and lane not in lanes:
            raise SettingsError("lane", f"slot {chosen.id!r} is parked into from "
                                        f"{', '.join(lanes)}, not {lane!r}")
        return cls(scenario, lot, scenario.vehicle_type(vname), chosen, planner, lane, style)

    def plan(self, *, leave: bool = False) -> Maneuver:
        """The maneuver into the slot (out of it with ``leave``): from ``lane``, or the
        best of the slot's lanes; fewest direction changes, then shortest.

        Raises
        ------
        InfeasibleManeuver
            When the vehicle cannot park there, with the reason.
        """
        if self.lane is not None:
            lanes = {ln.id: ln for ln in self.planner.lanes_for(self.slot)}
            m = self.planner.plan(self.vehicle, self.slot, lanes[self.lane], style=self.style)
        else:
            m = self.planner.best(self.vehicle, self.slot, style=self.style)
        return m.reversed() if leave else m
