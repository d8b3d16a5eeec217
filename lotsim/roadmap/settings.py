"""The roadmap's tuning (:class:`RoadmapSettings`): every value that shapes a lot's drivable
graph — the design speeds of junction turns, the turns through a junction's area, the
multi-point search, the turnarounds at dead ends. Each group is a frozen dataclass checked
on construction (:class:`~lotsim.errors.SettingsError`); a scenario's ``roadmap`` section
sets them (``docs/scenario.md``), the prepared lot's cache key holds them and
``result.json`` writes them.

The defaults are the values lotsim has always planned with: a lot prepared with
``RoadmapSettings()`` is the lot prepared without.

Examples
--------
>>> RoadmapSettings().turnarounds.margin
0.1
>>> TurnaroundSettings(margin=-0.1)
Traceback (most recent call last):
  ...
lotsim.errors.SettingsError: margin: expected 0 to 1 m, found -0.1
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from lotsim.core.checks import is_real, raise_first, range_problem, set_field

KMH_PER_MS = 3.6
"""km/h in one m/s (a speed in km/h over this is in m/s, to the last bit as lotsim has
always divided; :data:`lotsim.vehicles.KMH` is the other way round, m/s in one km/h)."""


def _tuples(obj: object, names: Sequence[str]) -> None:
    """A list given for a tuple field kept as a tuple: the same settings, the same key."""
    for name in names:
        value = getattr(obj, name)
        if isinstance(value, list):
            set_field(obj, name, tuple(value))


def _positive(value: Any, unit: str = "") -> str | None:
    if is_real(value) and value > 0 and value < float("inf"):
        return None
    return f"expected a positive number{unit}, found {value!r}"


def _at_least_zero(value: Any, unit: str = "") -> str | None:
    if is_real(value) and 0 <= value < float("inf"):
        return None
    return f"expected zero or more{unit}, found {value!r}"


def _count(value: Any, lo: int, hi: int) -> str | None:
    return range_problem(value, lo, hi, integer=True)


def _numbers(value: Any, *, least: float | None = None, positive: bool = False,
             falling: bool = False, what: str = "numbers") -> str | None:
    """What is wrong with a non-empty tuple of finite numbers (each ≥ ``least``, or > 0
    with ``positive``; fastest first with ``falling``), or None."""
    if not (isinstance(value, tuple) and value and all(is_real(v) for v in value)
            and all(abs(v) < float("inf") for v in value)):
        return f"expected a list of {what}, found {value!r}"
    if positive and min(value) <= 0:
        return f"expected positive {what}, found {list(value)!r}"
    if least is not None and min(value) < least:
        return f"expected {what} of at least {least:g}, found {list(value)!r}"
    if falling and any(b >= a for a, b in zip(value[:-1], value[1:], strict=True)):
        return f"expected {what} from the largest down, found {list(value)!r}"
    return None


def _checked(problems: list[tuple[str, str | None]]) -> None:
    raise_first([(k, m) for k, m in problems if m is not None])


# -- junction turns -------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class TurnSettings:
    """How junction turns are sized (:mod:`lotsim.roadmap.junctions`,
    :mod:`lotsim.roadmap.through`); checked on construction.

    Attributes
    ----------
    speeds : tuple of float
        Design speeds a junction turn tries, fastest first [m/s]: a turn for speed ``v``
        has an arc of radius ``max(R, v² / a_lat)`` (or 2 R, 3 R) and clothoids every type
        can steer at ``v``; those above the lot's speed limit are skipped, but for the
        slowest, which is always tried.
    through_overlap : float
        Longest stretch of lane [m] by which a turn into it may overrun the start of a
        turn out of it for the two to be joined into one turn through the stretch.
    """

    speeds: tuple[float, ...] = tuple(k / KMH_PER_MS
                                      for k in (15.0, 12.5, 10.0, 7.5, 5.0, 3.0, 1.5))
    through_overlap: float = 15.0

    def __post_init__(self) -> None:
        _tuples(self, ("speeds",))
        _checked([("speeds", _numbers(self.speeds, positive=True, falling=True,
                                      what="speeds")),
                  ("through_overlap", _at_least_zero(self.through_overlap, " m"))])


# -- turns through a junction's area ------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class AreaTurnSettings:
    """The candidates of a junction turn that uses the junction's whole area
    (:mod:`lotsim.roadmap.area_turns`), tried where the turn between the lanes touches
    something; checked on construction.

    Attributes
    ----------
    shifts : tuple of float
        Sideways shifts [m] of the turn's corner from each lane's line (positive: to the
        lane's left, across the oncoming lane), in the order tried; also the shifts of a
        turn through a short stretch of lane.
    leads : tuple of float
        Lengths [m] of the drift from a lane to the shifted corner's line, and back.
    radii : tuple of float
        Multiples (at least 1) of the design radius the corner's arc tries.
    speeds : tuple of float
        Design speeds [m/s] tried below the fastest the arc allows: a slower turn has
        shorter clothoids, so it fits a tighter corner.
    """

    shifts: tuple[float, ...] = (0.0, 1.0, -1.0, 2.0, -2.0, 3.0, -3.0, 4.0)
    leads: tuple[float, ...] = (1.5, 3.0, 4.5, 6.0, 9.0, 12.0)
    radii: tuple[float, ...] = (1.0, 1.5)
    speeds: tuple[float, ...] = (5.0 / KMH_PER_MS, 3.0 / KMH_PER_MS, 1.5 / KMH_PER_MS)

    def __post_init__(self) -> None:
        _tuples(self, ("shifts", "leads", "radii", "speeds"))
        _checked([("shifts", _numbers(self.shifts, what="shifts in metres")),
                  ("leads", _numbers(self.leads, positive=True, what="lengths in metres")),
                  ("radii", _numbers(self.radii, least=1.0, what="multiples of the radius")),
                  ("speeds", _numbers(self.speeds, positive=True, what="speeds"))])


# -- the multi-point search ------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class MultipointSettings:
    """The multi-point search (a Hybrid A*, :func:`lotsim.roadmap.multipoint.plan_onto`) of
    multi-point junction turns, U-turns at junctions and the turnarounds that must land
    before a lane's last exit, and where those begin and land; checked on construction.

    Attributes
    ----------
    move : float
        Length of one search move [m].
    step : float
        Spacing of the footprints whose hulls cover a move when checking it [m].
    cell : float
        Side of the grid cells in which the search keeps one state [m].
    headings : int
        Heading bins of the grid (48: 7.5° each).
    cusp : float
        Price of a change of direction, in metres of path (a stop, the wheels turned at
        rest).
    steer : float
        Price of a change of steering between moves in one direction [m].
    reverse : float
        Cost of a metre driven in reverse, per metre driven forward (at least 1).
    max_changes : int
        Most direction changes a path may have.
    expansion_limit : int
        Most states a search expands.
    weight : float
        The heuristic's weight (at least 1): a path found is at most this much dearer than
        the cheapest.
    improve : int
        Once a path is found, how many more states the search expands looking for a cheaper
        one.
    closing_radii : tuple of float
        Multiples (at least 1) of the design radius the last move's arc tries (also a
        turnaround's last move).
    s_radii : tuple of float
        Multiples of the design radius a last move that is an S (a right arc, then a left
        arc onto the lane) tries.
    grid : float
        Multi-point turns and turnarounds end on lane stations that are multiples of this
        [m], at least this far past where the last arc meets the lane.
    junction_starts : tuple of float
        How far before the crossing of two lanes [m] a multi-point junction turn or a
        U-turn at a junction may begin.
    junction_room : float
        Lane such a turn needs before the crossing on the lane it leaves, and after it on
        the lane it joins [m].
    uturn_land : tuple of float
        Where a U-turn at a junction may land on the opposite lane: from the first [m]
        before the crossing to the second past it.
    """

    move: float = 1.0
    step: float = 0.1
    cell: float = 0.5
    headings: int = 48
    cusp: float = 4.0
    steer: float = 1.5
    reverse: float = 1.2
    max_changes: int = 8
    expansion_limit: int = 3000
    weight: float = 1.5
    improve: int = 300
    closing_radii: tuple[float, ...] = (1.0, 1.25, 1.5, 2.0)
    s_radii: tuple[float, ...] = (2.0, 3.0, 4.0, 6.0)
    grid: float = 0.5
    junction_starts: tuple[float, ...] = (0.0, 3.0, 6.0)
    junction_room: float = 3.0
    uturn_land: tuple[float, float] = (2.0, 8.0)

    def __post_init__(self) -> None:
        _tuples(self, ("closing_radii", "s_radii", "junction_starts", "uturn_land"))
        land = self.uturn_land
        _checked([
            ("move", range_problem(self.move, 0.05, 10.0, " m")),
            ("step", range_problem(self.step, 0.01, 1.0, " m")),
            ("cell", range_problem(self.cell, 0.05, 5.0, " m")),
            ("headings", _count(self.headings, 4, 720)),
            ("cusp", _at_least_zero(self.cusp, " m")),
            ("steer", _at_least_zero(self.steer, " m")),
            ("reverse", range_problem(self.reverse, 1.0, 100.0)),
            ("max_changes", _count(self.max_changes, 0, 50)),
            ("expansion_limit", _count(self.expansion_limit, 1, 10_000_000)),
            ("weight", range_problem(self.weight, 1.0, 100.0)),
            ("improve", _count(self.improve, 0, 10_000_000)),
            ("closing_radii", _numbers(self.closing_radii, least=1.0,
                                       what="multiples of the radius")),
            ("s_radii", _numbers(self.s_radii, least=1.0, what="multiples of the radius")),
            ("grid", _positive(self.grid, " m")),
            ("junction_starts", _numbers(self.junction_starts, least=0.0,
                                         what="distances in metres")),
            ("junction_room", _at_least_zero(self.junction_room, " m")),
            ("uturn_land", None if (isinstance(land, tuple) and len(land) == 2
                                    and _numbers(land, least=0.0) is None)
             else f"expected two distances in metres (before, past), found {land!r}"),
        ])


# -- turnarounds ---------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class TurnaroundSettings:
    """The turnarounds at dead ends (:mod:`lotsim.roadmap.turnarounds`) and the clearance of
    every multi-point turn; checked on construction.

    Attributes
    ----------
    margin : float
        Clearance kept to slots, walls and the boundary by every multi-point turn (a
        turnaround, a multi-point junction turn, a U-turn) [m], 0 to 1: the body checked is
        the design vehicle grown by it. It is the roadmap's own, apart from the parking
        maneuvers' (:attr:`lotsim.maneuvers.settings.ManeuverSettings.margin`).
    max_changes : int
        Most direction changes a turnaround by strokes at full lock may have.
    probe : float
        Spacing of the places along each stroke where the last move onto the lane is
        tried [m].
    step : float
        Spacing of the footprints whose hulls cover a stroke when checking it [m].
    starts : tuple of float
        How far before a lane's end a turnaround may begin [m], in the order tried: a
        driver who knows the street ends starts turning before it does.
    min_stroke : float
        Shorter strokes are not worth a stop [m].
    dead_end : float
        A lane whose last turn off it begins more than this before its end [m], and which
        does not continue as another, ends in a dead end: a car turns round there.
    """

    margin: float = 0.1
    max_changes: int = 8
    probe: float = 0.25
    step: float = 0.1
    starts: tuple[float, ...] = (0.0, 2.0, 4.0, 6.0)
    min_stroke: float = 0.3
    dead_end: float = 15.0

    def __post_init__(self) -> None:
        _tuples(self, ("starts",))
        _checked([("margin", range_problem(self.margin, 0.0, 1.0, " m")),
                  ("max_changes", _count(self.max_changes, 0, 50)),
                  ("probe", range_problem(self.probe, 0.01, 10.0, " m")),
                  ("step", range_problem(self.step, 0.01, 1.0, " m")),
                  ("starts", _numbers(self.starts, least=0.0, what="distances in metres")),
                  ("min_stroke", _at_least_zero(self.min_stroke, " m")),
                  ("dead_end", _at_least_zero(self.dead_end, " m"))])


# -- all of it -------------------------------------------------------------------------------------
GROUPS = {"turns": TurnSettings, "area_turns": AreaTurnSettings,
          "multipoint": MultipointSettings, "turnarounds": TurnaroundSettings}
"""The groups of :class:`RoadmapSettings`, as a scenario's ``roadmap`` section names them."""


@dataclass(frozen=True, slots=True)
class RoadmapSettings:
    """Everything that shapes a lot's drivable graph, by group; checked on construction.

    Attributes
    ----------
    turns : TurnSettings
    area_turns : AreaTurnSettings
    multipoint : MultipointSettings
    turnarounds : TurnaroundSettings

    Examples
    --------
    >>> s = RoadmapSettings(multipoint=MultipointSettings(expansion_limit=500))
    >>> s.multipoint.expansion_limit, s == RoadmapSettings()
    (500, False)
    >>> RoadmapSettings(turns=0.5)
    Traceback (most recent call last):
      ...
    lotsim.errors.SettingsError: turns: expected TurnSettings, found 0.5
    """

    turns: TurnSettings = field(default_factory=TurnSettings)
    area_turns: AreaTurnSettings = field(default_factory=AreaTurnSettings)
    multipoint: MultipointSettings = field(default_factory=MultipointSettings)
    turnarounds: TurnaroundSettings = field(default_factory=TurnaroundSettings)

    def __post_init__(self) -> None:
        _checked([(name, None if isinstance(getattr(self, name), cls)
                   else f"expected {cls.__name__}, found {getattr(self, name)!r}")
                  for name, cls in GROUPS.items()])


DEFAULTS = RoadmapSettings()
"""The roadmap's settings when a caller gives none: the values lotsim has always made its
graphs with (each function's default is this, or its group)."""


def as_settings(value: Any, cls: type, name: str) -> Any:
    """``value`` when it is a ``cls`` (None: the defaults); else a
    :class:`~lotsim.errors.SettingsError` naming ``name``."""
    if value is None:
        return cls()
    if not isinstance(value, cls):
        raise_first([(name, f"expected {cls.__name__}, found {type(value).__name__}")])
    return value

