"""Settings of one car's parking maneuver and of the minimum-slot table: the clearance
kept to parked cars and walls, the maneuver styles, the maneuver planner's tuning
(:class:`ManeuverSettings`: every value that can change a maneuver), how finely
``lotsim minslot`` searches."""

from __future__ import annotations

import math
from dataclasses import dataclass

from lotsim.core.checks import is_real, raise_first, range_problem, set_field, shown
from lotsim.roadmap.settings import MultipointSettings

MARGIN = 0.1
"""Default clearance of a parking maneuver to parked cars, walls and the aisle's far side
[m] (after the unmanned-parking path-planning paper of a 2022 modelling contest)."""
WAY_OUT = MultipointSettings(expansion_limit=1500)
"""Default tuning of the multi-point search for a way out of a slot: the roadmap's
multi-point search, expanding at most 1500 states (a slot with no way out costs them all)."""
STYLES = ("any", "forward", "reverse")
"""Parking maneuvers: ``forward``: nose-in; ``reverse``: nose-out (backed in); ``any``: the
better one."""


# -- one car into one slot --------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class ManeuverSettings:
    """The maneuver planner's tuning, checked on construction
    (:class:`~lotsim.errors.SettingsError`); a scenario's ``maneuvers`` section sets it
    (``docs/scenario.md``), the prepared lot's cache key holds it and ``result.json``
    writes it.

    Attributes
    ----------
    margin : float
        Clearance kept to parked cars, walls, obstacles and the edges of the
        drivable area [m], 0 to 1.
    max_changes : int
        Most direction changes a maneuver may have, 0 to 50.
    probe : float
        Spacing of the places along every stroke (and of the straight exits from a
        perpendicular or angled slot) where a closing move onto the lane is tried [m].
    first_turn : float
        The first full-lock stroke out of a slot turns at most the slot's angle to the
        lane plus this [rad] (20°).
    candidates : int
        Closing moves checked for collisions per number of direction changes, cheapest
        first.
    closing_radii : tuple of float
        Multiples of the minimum turning radius the closing arc tries.
    sweep : float
        Spacing of the footprints whose hulls cover a path when checking it [m].
    min_stroke : float
        Shorter strokes of the perpendicular search are not worth a stop [m].
    parallel_extra : float
        Parallel slots: the minimum-slot strokes run to contact, so they are kept
        this far inside the margin [m].
    parallel_heading_step : float
        Parallel slots: spacing of the start headings tried [°].
    ease_ramps : tuple of float
        Lengths of path over which a maneuver's curvature jumps are smoothed, longest
        first [m]: a longer ramp is driven faster (the steering rate caps ``v`` at
        ``φ̇ / (σ b)``) but moves the path further from the planned one.
    ease_drift : float
        Farthest an eased maneuver may end from the planned parked pose [m] (the clothoid
        ramps that let the car steer as it rolls shift the path by a few millimetres
        each).
    start_grid : float
        Maneuvers start (and leaving ends) on lane stations that are multiples of this
        [m]: every vehicle type's maneuvers into nearby slots share lane nodes, and no car
        creeps a few millimetres from one node to the next (0: anywhere).
    approach : float
        ... at least this far along the lane from where the closing arc meets it [m]: a
        straight on which the car turns its wheels as it rolls into the arc.
    rough : float
        Spacing of the footprints of the cheap first pass that drops most blocked candidate
        paths before their sweeps are checked [m].
    creep : float
        Shortest straight a closing move may begin with [m] (none at all is fine): where
        the curvature jumps cannot be eased the car stops at both ends of that straight.
    way_out : MultipointSettings
        The multi-point search for a way out of a perpendicular or angled slot, tried when
        the full-lock shuffle found none: its move, grid, prices, heuristic, last moves,
        direction changes (at most ``max_changes`` too) and expansion limit (default 1500
        states: a slot with no way out costs them all). Its junction and U-turn fields are
        not read.

    Examples
    --------
    >>> ManeuverSettings(margin=0.2).margin
    0.2
    >>> ManeuverSettings(probe=0.0)
    Traceback (most recent call last):
      ...
    lotsim.errors.SettingsError: probe: expected a positive number, found 0
    """

    margin: float = MARGIN
    max_changes: int = 8
    probe: float = 0.5
    first_turn: float = math.radians(20)
    candidates: int = 400
    closing_radii: tuple[float, ...] = (1.0, 1.25, 1.5, 2.0, 3.0)
    sweep: float = 0.2
    min_stroke: float = 0.3
    parallel_extra: float = 0.02
    parallel_heading_step: float = 0.5
    ease_ramps: tuple[float, ...] = (3.0, 2.2, 1.6, 1.1, 0.7, 0.4)
    ease_drift: float = 0.03
    start_grid: float = 0.5
    approach: float = 0.5
    rough: float = 1.0
    creep: float = 0.1
    way_out: MultipointSettings = WAY_OUT

    def __post_init__(self) -> None:
        for key in ("closing_radii", "ease_ramps"):  # a list kept as a tuple: hashable
            if isinstance(getattr(self, key), list):
                set_field(self, key, tuple(getattr(self, key)))
        problems = [("margin", range_problem(self.margin, 0.0, 1.0, " m")),
                    ("max_changes", range_problem(self.max_changes, 0, 50, integer=True))]
        if not isinstance(self.way_out, MultipointSettings):
            problems.append(("way_out", "expected the multi-point search's settings "
                             f"(MultipointSettings), found {self.way_out!r}"))
        for key in ("probe", "sweep", "parallel_heading_step", "candidates", "rough"):
            value = getattr(self, key)
            problems.append((key, None if is_real(value) and value > 0
                             else f"expected a positive number, found {shown(value)}"))
        for key in ("first_turn", "min_stroke", "parallel_extra", "ease_drift", "start_grid",
                    "approach", "creep"):
            value = getattr(self, key)
            problems.append((key, None if is_real(value) and value >= 0
                             else f"expected zero or more, found {shown(value)}"))
        radii, ramps = self.closing_radii, self.ease_ramps
        if not (isinstance(radii, tuple) and radii and all(is_real(r) for r in radii)
                and min(radii) >= 1.0 and max(radii) < math.inf):
            problems.append(("closing_radii", "expected multiples of at least 1, found "
                             f"{radii!r}"))
        if not (isinstance(ramps, tuple) and all(is_real(r) and 0 < r < math.inf
                                                 for r in ramps)):
            problems.append(("ease_ramps", f"expected positive lengths, found {ramps!r}"))
        raise_first([(k, m) for k, m in problems if m is not None])


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
