"""How the cooperative space-time search plans: :class:`SearchSettings`, the tuning that
can change a plan (speed levels, swept-volume chunks, the heuristic's weight, the expansion limit's
floor, ...), one frozen object passed to the search graph and through it to every search on
it, so that a graph and the searches on it cannot disagree.

It validates on construction and raises :class:`~lotsim.errors.SettingsError`
(``weight: expected 1 to 10, found 0.5``) for the first value out of range.

Examples
--------
>>> SearchSettings().weight
1.25
>>> SearchSettings(chunk=0)
Traceback (most recent call last):
...
lotsim.errors.SettingsError: chunk: expected a positive number up to 10 s, found 0
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from lotsim.core.checks import is_real, raise_first, range_problem, set_field, shown
from lotsim.vehicles.model import KMH

PLANNERS = ("ca", "hca", "whca")
"""Cooperative A* variants (:func:`lotsim.traffic.search.search`)."""
OMEGA = 10.0
"""Expansion limit: a search stops after expanding ``OMEGA`` × its reverse search's closed nodes."""


def _positive_problem(value: object, unit: str, hi: float | None = None) -> str | None:
    """``expected a positive number [up to hi] unit`` unless ``0 < value [≤ hi]``, finite."""
    if is_real(value) and math.isfinite(value) and value > 0 and (hi is None or value <= hi):
        return None
    most = "" if hi is None else f" up to {shown(hi)}"
    return f"expected a positive number{most}{unit}, found {shown(value)}"


@dataclass(frozen=True, slots=True)
class SearchSettings:
    """The tuning of the cooperative space-time search; checked on construction.

    Every field can change a plan. A :class:`~lotsim.traffic.searchgraph.SearchGraph` is
    built with one (its speed levels, express edges and swept volumes follow it) and every
    search on the graph reads the rest from it.

    Attributes
    ----------
    speed_step : float
        Spacing of the speed levels a vehicle may pass a node at [m/s] (0.1 to 10), plus
        its top speed.
    express : float
        Lane nodes closer than this [m] are also joined by one edge through them, 0 to
        100 (0: none; see :meth:`~lotsim.traffic.searchgraph.SearchGraph.express`).
    chunk : float
        Longest time one swept hull covers [s], positive, up to 10.
    sample : float
        Largest distance between the footprints a hull is made of along a curved motion
        [m], positive, up to 1 (along straights the hull of the ends is exact).
    weight : float
        Weight of the heuristic (weighted A*: plans within this factor of the best the
        heuristic allows), 1 to 10.
    min_budget : int
        A search may always expand at least this many states before it reaches the
        expansion limit, 0 to 10**9.
    passing : float
        A vehicle passing a node at a speed level within this long [s] after an earlier
        state of the search passed it at that level is taken for that state, 0 to 60.
    depart_after : float
        A vehicle that waits for a body to clear its way departs this long [s] after the
        last instant the two would meet, positive, up to 1.
    horizon : float
        A search gives up on states later than its start plus this [s], positive.
    """

    speed_step: float = 5 * KMH
    express: float = 6.0
    chunk: float = 0.5
    sample: float = 0.2
    weight: float = 1.25
    min_budget: int = 20000
    passing: float = 2.0
    depart_after: float = 1e-6
    horizon: float = 3600.0

    def __post_init__(self) -> None:
        raise_first([(name, problem) for name, problem in (
            ("speed_step", range_problem(self.speed_step, 0.1, 10, " m/s")),
            ("express", range_problem(self.express, 0, 100, " m")),
            ("chunk", _positive_problem(self.chunk, " s", 10)),
            ("sample", _positive_problem(self.sample, " m", 1)),
            ("weight", range_problem(self.weight, 1, 10)),
            ("min_budget", range_problem(self.min_budget, 0, 10**9, integer=True)),
            ("passing", range_problem(self.passing, 0, 60, " s")),
            ("depart_after", _positive_problem(self.depart_after, " s", 1)),
            ("horizon", _positive_problem(self.horizon, " of seconds")),
        ) if problem is not None])
        for name in ("speed_step", "express", "chunk", "sample", "weight", "passing",
                     "depart_after", "horizon"):
            set_field(self, name, float(getattr(self, name)))
        set_field(self, "min_budget", int(self.min_budget))
