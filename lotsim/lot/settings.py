"""The built lot's tuning (:class:`LotSettings`): the values that shape a lot as it is built
from its spec and, through its lanes, the drivable graph — the free space kept beside the
widest car in its lane, the footprint spacing of every sweep that checks a lane or a
junction turn can be driven, and the slowest a lane's bend is driven. Checked on
construction (:class:`~lotsim.errors.SettingsError`); a scenario's ``lot.build`` mapping
sets them (``docs/scenario.md``), the lot's spec carries them
(:attr:`lotsim.lot.spec.LotSpec.settings`) into the prepared lot's cache key, the built lot
keeps them (:attr:`lotsim.lot.model.Lot.settings`) and ``result.json`` writes them.

The defaults are the values lotsim has always built lots with: a lot built with
``LotSettings()`` is the lot built without.

Examples
--------
>>> LotSettings().lane_clearance
0.15
>>> LotSettings(sweep=0)
Traceback (most recent call last):
  ...
lotsim.errors.SettingsError: sweep: expected 0.01 to 1 m, found 0
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from lotsim.core.checks import is_real, raise_first, range_problem, shown

CRAWL_RANGE = (0.05, 5.0)
"""The crawl speeds a lot may be built with [m/s] (0.18 to 18 km/h): slower, a bend's
clothoids would need more steering than a driver gives a corner; faster, it is no crawl."""


def _crawl_problem(value: Any) -> str | None:
    """What is wrong with a crawl speed [m/s], said in m/s and in km/h (a scenario file
    gives it in km/h), or None."""
    lo, hi = CRAWL_RANGE
    if is_real(value) and math.isfinite(value) and lo <= value <= hi:
        return None
    found = f"{shown(value)} m/s ({value * 3.6:g} km/h)" if is_real(value) else repr(value)
    return f"expected {lo:g} to {hi:g} m/s ({lo * 3.6:g} to {hi * 3.6:g} km/h), found {found}"


@dataclass(frozen=True, slots=True)
class LotSettings:
    """How a lot is built and checked (:func:`lotsim.lot.build.build_lot`); checked on
    construction.

    Attributes
    ----------
    lane_clearance : float
        Free space each side of the widest vehicle within its lane [m], 0 to 1: an aisle
        narrower than its lanes × (the widest vehicle + twice this) is refused.
    sweep : float
        Spacing of the footprints whose hulls cover a lane when checking it can be driven
        (and where its ends are cut back), and a junction turn or a turn through a
        junction's area when checking it is clear [m], 0.01 to 1.
    crawl_speed : float
        The slowest speed a bend of a lane is driven at [m/s], 0.05 to 5: corners too close
        together for the clothoids the steering rate allows at this speed are refused.

    Examples
    --------
    >>> LotSettings(crawl_speed=0.5) == LotSettings()
    False
    >>> LotSettings(lane_clearance=-0.1)
    Traceback (most recent call last):
      ...
    lotsim.errors.SettingsError: lane_clearance: expected 0 to 1 m, found -0.1
    """

    lane_clearance: float = 0.15
    sweep: float = 0.2
    crawl_speed: float = 0.25

    def __post_init__(self) -> None:
        raise_first([(k, m) for k, m in (
            ("lane_clearance", range_problem(self.lane_clearance, 0.0, 1.0, " m")),
            ("sweep", range_problem(self.sweep, 0.01, 1.0, " m")),
            ("crawl_speed", _crawl_problem(self.crawl_speed)),
        ) if m is not None])


DEFAULTS = LotSettings()
"""The lot's settings when a caller gives none: the values lotsim has always built its lots
with (what a lot drawn by an importer, which writes no ``lot.build``, is built with)."""
