"""Settings of one car's parking maneuver and of the minimum-slot table: the clearance
kept to parked cars and walls, the maneuver styles, how finely ``lotsim minslot`` searches."""

from __future__ import annotations

from dataclasses import dataclass

from lotsim.core.checks import raise_first, range_problem

MARGIN = 0.1
"""Default clearance of a parking maneuver to parked cars, walls and the aisle's far side
[m] (seed 004)."""
STYLES = ("any", "forward", "reverse")
"""Parking maneuvers: ``forward``: nose-in; ``reverse``: nose-out (backed in); ``any``: the
better one."""


# -- the minimum-slot table ---------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class MinSlotSettings:
    """How finely :func:`lotsim.minslot` searches; checked on construction.

    Attributes
    ----------
    max_changes : int
        Largest number of direction changes reported, 0 to 50.
    resolution : float
        Length step, 0.001 to 1 [m].
    step_deg : float
        Start-heading sweep step, 0.01 to 5 [deg].
    """

    max_changes: int = 10
    resolution: float = 0.01
    step_deg: float = 0.1

    def __post_init__(self) -> None:
        raise_first([(k, m) for k, m in (
            ("max_changes", range_problem(self.max_changes, 0, 50, integer=True)),
            ("resolution", range_problem(self.resolution, 0.001, 1.0, " m")),
            ("step_deg", range_problem(self.step_deg, 0.01, 5.0, " degrees")),
        ) if m is not None])
