"""Settings that check themselves: how a run plans, how the GA searches orders, how a GIF
is drawn, how finely the minimum-slot table is searched.

Each is a frozen dataclass that validates on construction and raises
:class:`~lotsim.errors.SettingsError` (``window: expected 1 to 600 seconds, found 0``) for
the first value out of range or not one of its choices. Python callers, the CLI (which
takes its defaults and choices from here and prints ``--window: ...``) and the bench suite
reader (``file:line:col: planners[0].whca[1]: ...``) thus get the same checks and the same
messages. Like :mod:`lotsim.errors`, this module needs only the standard library, so any
layer may import it and ``lotsim --help`` stays quick.

Examples
--------
>>> RunSettings(planner="whca", window=5).window
5.0
>>> RunSettings(planner="whca", window=0)
Traceback (most recent call last):
...
lotsim.errors.SettingsError: window: expected 1 to 600 seconds, found 0
"""

from __future__ import annotations

import difflib
import math
import numbers
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from typing import Any

from lotsim.errors import SettingsError

PLANNERS = ("ca", "hca", "whca")
"""Cooperative A* variants (:func:`lotsim.traffic.search.search`)."""
ASSIGNMENTS = ("nearest", "shortest")
"""Slot choice: straight-line distance from the entrance, or travel time."""
PRIORITIES = ("arrival", "shortest_first", "ga")
"""``arrival``: online, each vehicle planned when it arrives; ``shortest_first``: booked,
the vehicle with the least static time to a slot first; ``ga``: booked, the order a
genetic algorithm finds (:mod:`lotsim.sim.orders`)."""
OMEGA = 10.0
"""Fuse: a search stops after expanding ``OMEGA`` × its reverse search's closed nodes."""
BOOKING_HORIZON = 60.0
"""Default of :attr:`RunSettings.horizon` [s]."""
MAX_SEED = 2**63 - 1
MAX_WINDOW = 600.0
"""Longest WHCA* window [s]."""
MAX_FPS = 50
"""GIF delays are whole centiseconds and players slow down delays under 2 cs."""
MARGIN = 0.1
"""Default clearance of a parking maneuver to parked cars, walls and the aisle's far side
[m] (seed 004)."""
STYLES = ("any", "forward", "reverse")
"""Parking maneuvers: ``forward``: nose-in; ``reverse``: nose-out (backed in); ``any``: the
better one."""


# -- checks (each returns the message of a problem, or None) ----------------------------------
def is_real(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _integral(value: Any) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _num(x: float) -> str:
    """``600``, ``0.01``, ``1000000``, ``inf``."""
    if math.isfinite(x) and float(x).is_integer() and abs(x) < 1e15:
        return str(int(x))
    return f"{x:g}"


def shown(value: Any) -> str:
    return _num(value) if is_real(value) else repr(value)


def choice_problem(value: Any, choices: Sequence[str]) -> str | None:
    if isinstance(value, str) and value in choices:
        return None
    close = difflib.get_close_matches(value, choices, n=1) if isinstance(value, str) else []
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    return f"expected one of {', '.join(choices)}, found {value!r}{hint}"


def _range(value: Any, lo: float, hi: float, unit: str = "", *, integer: bool = False
           ) -> str | None:
    """``expected lo to hi unit, found value`` unless ``lo ≤ value ≤ hi`` (finite)."""
    if not (_integral(value) if integer else is_real(value)):
        return f"expected {'an integer' if integer else 'a number'}, found {value!r}"
    if math.isfinite(value) and lo <= value <= hi:
        return None
    return f"expected {_num(lo)} to {_num(hi)}{unit}, found {shown(value)}"


def _raise_first(problems: list[tuple[str, str]]) -> None:
    if problems:
        raise SettingsError(*problems[0])


def _set(obj: object, name: str, value: Any) -> None:
    """Normalise a field of a frozen dataclass while it is being built (an int window to a
    float, a list order to a tuple): the same settings then write the same result."""
    object.__setattr__(obj, name, value)


def names(cls: type) -> tuple[str, ...]:
    """The field names of a settings dataclass, e.g. for ``**overrides``."""
    return tuple(f.name for f in fields(cls))


def replace(settings: Any, overrides: dict[str, Any]) -> Any:
    """``settings`` with ``overrides`` (field → value), checked; an unknown field is a
    :class:`~lotsim.errors.SettingsError` that names the fields there are.

    >>> replace(RunSettings(), {"windw": 5})
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: windw: no such setting of RunSettings (did you mean 'window'?)
    """
    known = names(type(settings))
    for key in overrides:
        if key not in known:
            close = difflib.get_close_matches(key, known, n=1)
            hint = (f" (did you mean {close[0]!r}?)" if close
                    else f"; expected one of {', '.join(known)}")
            raise SettingsError(key, f"no such setting of {type(settings).__name__}{hint}")
    if not overrides:
        return settings
    values = {f.name: getattr(settings, f.name) for f in fields(settings)}
    return type(settings)(**{**values, **overrides})


# -- the genetic algorithm over planning orders -----------------------------------------------
@dataclass(frozen=True, slots=True)
class GASettings:
    """The genetic algorithm over planning orders (:func:`lotsim.sim.orders.genetic_order`).

    Attributes
    ----------
    population : int
        Orders per generation, 2 to 10000; the first holds the arrival order, shortest
        first, and random orders.
    generations : int
        Generations bred after the first, 0 to 100000.
    seed : int
        Seed of the GA's ``numpy.random.Generator`` (independent of the traffic's).
    mutation : float
        Chance that a child has two of its vehicles swapped (once more with the same
        chance, and so on), 0 to 1.
    elite : int
        Best orders carried over unchanged, 0 to ``population``.
    tournament : int
        Orders drawn for each parent (at least 1); the fittest is taken.
    """

    population: int = 12
    generations: int = 10
    seed: int = 0
    mutation: float = 0.5
    elite: int = 2
    tournament: int = 3

    def __post_init__(self) -> None:
        checks = [("population", _range(self.population, 2, 10_000, integer=True)),
                  ("generations", _range(self.generations, 0, 100_000, integer=True)),
                  ("seed", _range(self.seed, 0, MAX_SEED, integer=True)),
                  ("mutation", _range(self.mutation, 0, 1)),
                  ("tournament", _range(self.tournament, 1, 10_000, integer=True))]
        if checks[0][1] is None:
            checks.append(("elite", _range(self.elite, 0, self.population, integer=True)))
        _raise_first([(k, m) for k, m in checks if m is not None])


# -- a run --------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class RunSettings:
    """How :func:`lotsim.run` plans; checked on construction.

    Attributes
    ----------
    planner : {"ca", "hca", "whca"}
        The cooperative A* variant (:data:`PLANNERS`).
    assignment : {"nearest", "shortest"}
        Slot choice: straight-line distance from the entrance, or travel time
        along the graph plus the maneuver's time.
    seed : int or None
        Seed of the traffic stream, 0 to 2**63-1 (None: the scenario's).
    window : float
        WHCA*: the vehicle replans every ``window / 2`` seconds while it drives and keeps
        the new plan when it arrives sooner, 1 to 600 [s].
    omega : float
        The search fuse factor, at least 1.
    retry : float
        Wait before a vehicle whose search failed tries again [s], positive; it doubles
        with each failure in a row, up to a minute.
    order : tuple of str or None
        None: each vehicle is planned when it arrives, earlier arrivals first (online).
        Otherwise every vehicle id once: the traffic is booked ``horizon`` seconds ahead.
        Arrivals are cut into batches ``horizon`` long from the first one; the vehicles of
        a batch are planned at its start, in this order (their priority), each from its
        own arrival time, against the reservations of those planned before it — later
        arrivals of the batch included. Slots freed by departures go to queued vehicles
        in this order. An order given is planned as given, whatever ``priority`` says:
        a run's result holds the settings with the order its priority chose, so running
        them again plans the same run without searching again.
    horizon : float
        How far ahead booked traffic is known [s], positive (``inf``: all of it, one
        batch). Slots are assigned when a batch is planned, so slots freed by departures
        during a batch go unseen by its vehicles: a long horizon can cost more than a
        better order gains.
    priority : {"arrival", "shortest_first", "ga"}
        How the planning order is chosen when ``order`` is None (:data:`PRIORITIES`):
        online in arrival order, or booked (``horizon``) shortest static time first, or
        booked in the best order the genetic algorithm finds (total time to park).
    ga : GASettings
        The genetic algorithm, for ``priority="ga"``.
    """

    planner: str = "hca"
    assignment: str = "shortest"
    seed: int | None = None
    window: float = 10.0
    omega: float = OMEGA
    retry: float = 5.0
    order: tuple[str, ...] | None = None
    horizon: float = BOOKING_HORIZON
    priority: str = "arrival"
    ga: GASettings = field(default_factory=GASettings)

    def __post_init__(self) -> None:
        _raise_first(self._problems())
        for name in ("window", "omega", "retry", "horizon"):
            _set(self, name, float(getattr(self, name)))
        if self.seed is not None:
            _set(self, "seed", int(self.seed))
        if self.order is not None:
            _set(self, "order", tuple(self.order))

    def _problems(self) -> list[tuple[str, str]]:
        out = []
        for name, choices in (("planner", PLANNERS), ("assignment", ASSIGNMENTS),
                              ("priority", PRIORITIES)):
            problem = choice_problem(getattr(self, name), choices)
            if problem:
                out.append((name, problem))
        if self.seed is not None and not _integral(self.seed):
            out.append(("seed", f"expected an integer, found {self.seed!r}"))
        elif self.seed is not None and not 0 <= self.seed <= MAX_SEED:
            out.append(("seed", f"expected 0 to 2**63-1, found {self.seed}"))
        problem = _range(self.window, 1, MAX_WINDOW, " seconds")
        if problem:
            out.append(("window", problem))
        if not (is_real(self.omega) and math.isfinite(self.omega) and self.omega >= 1):
            out.append(("omega", f"expected a number of at least 1, found "
                                  f"{shown(self.omega)}"))
        if not (is_real(self.retry) and math.isfinite(self.retry) and self.retry > 0):
            out.append(("retry", f"expected a positive number of seconds, found "
                                  f"{shown(self.retry)}"))
        if not (is_real(self.horizon) and self.horizon > 0):  # inf: all of it; nan fails
            out.append(("horizon", f"expected a positive number of seconds, found "
                                    f"{shown(self.horizon)}"))
        if self.order is not None:
            if isinstance(self.order, str) or not isinstance(self.order, Sequence) or not all(
                    isinstance(v, str) for v in self.order):
                out.append(("order", f"expected a sequence of vehicle ids, found "
                                      f"{self.order!r}"))
            elif len(set(self.order)) != len(self.order):
                twice = next(v for v in self.order if self.order.count(v) > 1)
                out.append(("order", f"expected every vehicle id of the traffic exactly "
                                      f"once, found {twice!r} twice"))
        if not isinstance(self.ga, GASettings):
            out.append(("ga", f"expected GASettings, found {self.ga!r}"))
        return out


# -- pictures -----------------------------------------------------------------------------------
MIN_SIZE = (160, 120)
MAX_SIZE = (4000, 4000)
"""Smallest and largest picture [pixels], for every picture lotsim draws: a lot
(``lotsim show``), a maneuver, a GIF."""


def size_problem(size: Any) -> str | None:
    """What is wrong with a picture size ``(width, height)`` in pixels, or None.

    >>> size_problem((800, 600)) is None, size_problem((100, 100))
    (True, 'expected 160x120 to 4000x4000 pixels, found 100x100')
    """
    if not (isinstance(size, tuple) and len(size) == 2 and all(map(_integral, size))):
        return f"expected (width, height) in pixels, found {size!r}"
    if not (MIN_SIZE[0] <= size[0] <= MAX_SIZE[0] and MIN_SIZE[1] <= size[1] <= MAX_SIZE[1]):
        return (f"expected {MIN_SIZE[0]}x{MIN_SIZE[1]} to {MAX_SIZE[0]}x{MAX_SIZE[1]} pixels, "
                f"found {size[0]}x{size[1]}")
    return None


# -- a GIF --------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class GifSettings:
    """How :func:`lotsim.render_gif` turns run time into frames; checked on construction.

    Attributes
    ----------
    fps : float
        Frames per second of the GIF (1 to :data:`MAX_FPS`).
    speed : float
        Seconds of run time per second of GIF (0.01 to 10000).
    size : (width, height)
        Pixels (160x120 to 4000x4000).
    start, end : float or None
        Run time shown [s]; default from the first arrival to the last event.
    max_frames : int
        At most this many frames: a longer span is played faster (``FramePlan.speed``).
    trail : float
        Seconds of path drawn behind a moving vehicle (0 to 3600).
    skip_quiet : bool
        Leave out the stretches in which no vehicle moves (those of
        :meth:`lotsim.render.replay.Replay.quiet`, a second kept at each end); a frame after a
        skip says how much run time was skipped.
    legend : bool
        Draw a key of what the cars' colours mean in the footer, right of the scale bar.
    """

    fps: float = 20.0
    speed: float = 4.0
    size: tuple[int, int] = (800, 600)
    start: float | None = None
    end: float | None = None
    max_frames: int = 3000
    trail: float = 8.0
    skip_quiet: bool = False
    legend: bool = True

    def __post_init__(self) -> None:
        if isinstance(self.size, list):
            _set(self, "size", tuple(self.size))
        _raise_first(self.problems())

    def problems(self) -> list[tuple[str, str]]:
        """``(field, what is wrong)`` for each unusable setting (empty when all are fine)."""
        out = []
        if not (is_real(self.fps) and math.isfinite(self.fps) and 1 <= self.fps <= MAX_FPS):
            out.append(("fps", f"expected 1 to {MAX_FPS} frames per second, found "
                               f"{shown(self.fps)}"))
        problem = _range(self.speed, 0.01, 10_000)
        if problem:
            out.append(("speed", problem))
        problem = size_problem(self.size)
        if problem:
            out.append(("size", problem))
        for name in ("start", "end"):
            v = getattr(self, name)
            if v is not None and not (is_real(v) and math.isfinite(v)):
                out.append((name, f"expected a time in seconds, found {v}"))
        if (is_real(self.start) and is_real(self.end)
                and math.isfinite(self.start) and math.isfinite(self.end)
                and self.end <= self.start):
            out.append(("end", f"expected a time after the start ({self.start:g} s), "
                               f"found {self.end:g}"))
        problem = _range(self.max_frames, 1, 1_000_000, integer=True)
        if problem:
            out.append(("max_frames", problem))
        problem = _range(self.trail, 0, 3600, " seconds")
        if problem:
            out.append(("trail", problem))
        if not isinstance(self.skip_quiet, bool):
            out.append(("skip_quiet", f"expected true or false, found {self.skip_quiet!r}"))
        if not isinstance(self.legend, bool):
            out.append(("legend", f"expected true or false, found {self.legend!r}"))
        return out


# -- an HTML replay ------------------------------------------------------------------------------
REPLAY_SPEEDS = (1, 2, 4, 10, 30, 60)
"""Playback speeds the HTML replay offers (run seconds per second)."""


@dataclass(frozen=True, slots=True)
class HtmlSettings:
    """How :func:`lotsim.render_html` writes a replay; checked on construction.

    Attributes
    ----------
    speed : float
        Playback speed the page opens with, one of :data:`REPLAY_SPEEDS`.
    skip_quiet : bool
        Whether "skip quiet stretches" is on when the page opens.
    tolerance : float
        Largest position error of a car's body corner that leaving out samples may cause,
        0.001 to 0.1 [m] (:mod:`lotsim.render.html`).
    """

    speed: float = 4
    skip_quiet: bool = True
    tolerance: float = 0.01

    def __post_init__(self) -> None:
        out = []
        if not (is_real(self.speed) and self.speed in REPLAY_SPEEDS):
            out.append(("speed", f"expected one of {', '.join(map(str, REPLAY_SPEEDS))}, "
                                 f"found {shown(self.speed)}"))
        if not isinstance(self.skip_quiet, bool):
            out.append(("skip_quiet", f"expected true or false, found {self.skip_quiet!r}"))
        problem = _range(self.tolerance, 0.001, 0.1, " m")
        if problem:
            out.append(("tolerance", problem))
        _raise_first(out)


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
        _raise_first([(k, m) for k, m in (
            ("max_changes", _range(self.max_changes, 0, 50, integer=True)),
            ("resolution", _range(self.resolution, 0.001, 1.0, " m")),
            ("step_deg", _range(self.step_deg, 0.01, 5.0, " degrees")),
        ) if m is not None])


# -- a scenario file's output options -----------------------------------------------------------
@dataclass(frozen=True, slots=True)
class AnimationSpec:
    """A scenario file's ``animation`` section: ``lotsim run`` also writes a GIF (and an HTML
    replay, an MP4 video, when it names them). Read with
    the scenario (:func:`lotsim.io.scenario_yaml.read_scenario`) but kept apart from it: how a run
    is drawn is not part of the problem.

    Attributes
    ----------
    gif : str
        File name of the GIF, written beside ``result.json``.
    html : str or None
        File name of the HTML replay written beside it (None: none).
    mp4 : str or None
        File name of the MP4 video of the GIF's frames written beside it (None: none).
    fps, speed, size, start, end, max_frames, trail, skip_quiet, legend
        As :class:`GifSettings` (for the GIF and the video; ``skip_quiet`` also sets the
        replay's toggle); ``None`` for the default.
    """

    gif: str = "run.gif"
    html: str | None = None
    mp4: str | None = None
    fps: float | None = None
    speed: float | None = None
    size: tuple[int, int] | None = None
    start: float | None = None
    end: float | None = None
    max_frames: int | None = None
    trail: float | None = None
    skip_quiet: bool | None = None
    legend: bool | None = None

    def gif_settings(self) -> GifSettings:
        """The :class:`GifSettings` this section asks for (defaults where it says nothing).

        >>> AnimationSpec(speed=2).gif_settings().speed
        2
        """
        return GifSettings(**{f.name: getattr(self, f.name) for f in fields(GifSettings)
                              if getattr(self, f.name) is not None})

    def html_settings(self) -> HtmlSettings:
        """The :class:`HtmlSettings` this section asks for.

        >>> AnimationSpec(skip_quiet=False).html_settings().skip_quiet
        False
        """
        return HtmlSettings() if self.skip_quiet is None else HtmlSettings(
            skip_quiet=self.skip_quiet)
