"""How a layout search searches (:mod:`lotsim.design.search`): the directions, offsets
and number of candidates it tries, the planner of their runs, and what a dead end costs
in the ranking (:class:`LayoutSettings`)."""

from __future__ import annotations

from dataclasses import dataclass

from lotsim.core.checks import range_problem
from lotsim.errors import SettingsError
from lotsim.sim.settings import PLANNERS


@dataclass(frozen=True, slots=True)
class LayoutSettings:
    """How :func:`~lotsim.design.search.lay_out` searches (each field changes what it may
    find; the written lot names them).

    Attributes
    ----------
    orientations : int
        Most directions module aisles are tried in: along and square to the boundary's
        edges, longest edges first.
    offsets : int
        Module offsets tried per orientation, spread evenly over one module pitch.
    prepared : int
        Most candidates prepared (their bays checked by the maneuver planner) and run at
        the plot's demand.
    compared : int
        The search stops early once no candidate left is judged to beat this many
        candidates it holds (or as many as are written; or all it holds with a usable bay,
        when fewer): a candidate's circulation serves fewer bays than they have usable.
        The candidates set side by side.
    planner : str
        The cooperative planner of those runs (:data:`lotsim.sim.settings.PLANNERS`).
    workers : int or None
        Worker processes (None: one per core).
    dead_end_cost : float
        What 100 m of dead-end aisle costs a layout in the ranking, in bays [bays per
        100 m]: a layout ranks by its usable bays less this for its dead ends, so that a
        loop comes before a dead end of a few bays more (0: bays alone).

    Examples
    --------
    >>> LayoutSettings(offsets=2).describe()
    'orientations 4, offsets 2, prepared 8, compared 4, planner hca, dead ends 2 bays per 100 m'
    >>> LayoutSettings(orientations=0)
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: orientations: expected 1 to 64, found 0
    """

    orientations: int = 4
    offsets: int = 3
    prepared: int = 8
    compared: int = 4
    planner: str = "hca"
    workers: int | None = None
    dead_end_cost: float = 2.0

    def __post_init__(self) -> None:
        for name, lo, hi in (("orientations", 1, 64), ("offsets", 1, 32),
                             ("prepared", 1, 1000), ("compared", 1, 1000)):
            value = getattr(self, name)
            problem = range_problem(value, lo, hi, "") if isinstance(value, int) and \
                not isinstance(value, bool) else f"expected an integer, found {value!r}"
            if problem:
                raise SettingsError(name, problem)
        if self.planner not in PLANNERS:
            raise SettingsError("planner", f"expected one of {', '.join(PLANNERS)}, found "
                                           f"{self.planner!r}")
        cost = self.dead_end_cost
        if isinstance(cost, bool) or not isinstance(cost, (int, float)) or \
                not 0.0 <= cost <= 1000.0:
            raise SettingsError("dead_end_cost", f"expected 0 to 1000 bays per 100 m, found "
                                                 f"{cost!r}")
        if self.workers is not None and not (isinstance(self.workers, int)
                                             and 1 <= self.workers <= 256):
            raise SettingsError("workers", f"expected 1 to 256, found {self.workers!r}")

    def describe(self) -> str:
        return (f"orientations {self.orientations}, offsets {self.offsets}, prepared "
                f"{self.prepared}, compared {self.compared}, planner {self.planner}, "
                f"dead ends {self.dead_end_cost:g} bays per 100 m")
