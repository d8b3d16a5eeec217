"""A scenario: what its file holds. :class:`Scenario` is the lot layout, the vehicle types
that use it, the traffic, a seed and how its lot is prepared (the roadmap's and the parking
maneuvers' settings); :class:`AnimationSpec` is the file's ``animation`` section, how
``lotsim run`` draws the run (:class:`GifSettings`, :class:`HtmlSettings`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Any

from lotsim.core.checks import is_integral, is_real, raise_first, range_problem, set_field, shown
from lotsim.lot.spec import LotSpec
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.roadmap.service_routes import RouteSpec
from lotsim.roadmap.settings import RoadmapSettings
from lotsim.traffic.demand import TrafficSpec
from lotsim.traffic.disturbances import Disturbances
from lotsim.vehicles.model import VehicleType


@dataclass(frozen=True, slots=True)
class Scenario:
    """A validated scenario file.

    Attributes
    ----------
    name : str
    lot : LotSpec
    vehicle_types : tuple of VehicleType
        The types that drive in this lot; the lot is checked against all of them.
    parked_vehicle : VehicleType
        The type drawn in slots that are taken at start.
    seed : int
        Seed of every random choice made for this scenario.
    source : str
        The file it was read from.
    description : str
    traffic : TrafficSpec or None
        The vehicles that come to the lot; None when the scenario only describes a lot.
    disturbances : Disturbances or None
        What departs from the plan when the traffic is driven (late starts, slow cars,
        stalls: :class:`~lotsim.traffic.disturbances.Disturbances`); None: nothing.
    routes : tuple of RouteSpec
        The service vehicles' routes the lot must carry
        (:class:`~lotsim.roadmap.service_routes.RouteSpec`), checked by ``lotsim
        validate``; they take no part in a run.
    units : str
        The length unit its file was written in (``"m"`` or ``"ft"``): every length above
        is in metres whatever it is; ``units`` says only how lotsim reports lengths back to
        the file's author (``lotsim validate``'s summary and schedule, the DXF export).
    roadmap : RoadmapSettings
        How the lot's drivable graph is made (:mod:`lotsim.roadmap.settings`: junction
        turns' design speeds, turns through a junction's area, the multi-point search, the
        turnarounds); the file's ``roadmap`` section.
    maneuvers : ManeuverSettings
        How the parking maneuvers are planned
        (:class:`~lotsim.maneuvers.settings.ManeuverSettings`: clearance, direction
        changes, probes, easing); the file's ``maneuvers`` section.

    A scenario is the problem, not how to draw it: its file's ``animation`` section is read
    apart (:func:`lotsim.io.scenario_yaml.read_scenario`, :class:`lotsim.scenario.AnimationSpec`).
    """

    name: str
    lot: LotSpec
    vehicle_types: tuple[VehicleType, ...]
    parked_vehicle: VehicleType
    seed: int = 0
    source: str = "<memory>"
    description: str = ""
    traffic: TrafficSpec | None = None
    disturbances: Disturbances | None = None
    routes: tuple[RouteSpec, ...] = ()
    units: str = "m"
    roadmap: RoadmapSettings = field(default_factory=RoadmapSettings)
    maneuvers: ManeuverSettings = field(default_factory=ManeuverSettings)

    def __post_init__(self) -> None:
        for name, cls in (("roadmap", RoadmapSettings), ("maneuvers", ManeuverSettings)):
            value = getattr(self, name)
            if not isinstance(value, cls):
                raise_first([(name, f"expected {cls.__name__}, found "
                                    f"{type(value).__name__}")])

    def vehicle_type(self, name: str) -> VehicleType:
        """The vehicle type called ``name``; KeyError if the scenario has none."""
        for v in self.vehicle_types:
            if v.name == name:
                return v
        raise KeyError(name)


VIEWS = ("traffic", "lot")
"""What a GIF's frame holds (:attr:`GifSettings.view`)."""
VIEW_MARGIN = 6.0
"""Margin around the ground the cars use in a GIF that shows the traffic [m]."""
MAX_FPS = 50
"""GIF delays are whole centiseconds and players slow down delays under 2 cs."""

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
    if not (isinstance(size, tuple) and len(size) == 2 and all(map(is_integral, size))):
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
    view : {"traffic", "lot"}
        What the frame holds: the part of the lot the cars use (every place a car's
        footprint reaches, a margin of :data:`VIEW_MARGIN` around it, within the lot), so a
        big lot's traffic in one corner fills the picture; or the whole lot.
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
    view: str = "traffic"

    def __post_init__(self) -> None:
        if isinstance(self.size, list):
            set_field(self, "size", tuple(self.size))
        raise_first(self.problems())

    def problems(self) -> list[tuple[str, str]]:
        """``(field, what is wrong)`` for each unusable setting (empty when all are fine)."""
        out = []
        if not (is_real(self.fps) and math.isfinite(self.fps) and 1 <= self.fps <= MAX_FPS):
            out.append(("fps", f"expected 1 to {MAX_FPS} frames per second, found "
                               f"{shown(self.fps)}"))
        problem = range_problem(self.speed, 0.01, 10_000)
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
        problem = range_problem(self.max_frames, 1, 1_000_000, integer=True)
        if problem:
            out.append(("max_frames", problem))
        problem = range_problem(self.trail, 0, 3600, " seconds")
        if problem:
            out.append(("trail", problem))
        if not isinstance(self.skip_quiet, bool):
            out.append(("skip_quiet", f"expected true or false, found {self.skip_quiet!r}"))
        if not isinstance(self.legend, bool):
            out.append(("legend", f"expected true or false, found {self.legend!r}"))
        if self.view not in VIEWS:
            out.append(("view", f"expected one of {', '.join(VIEWS)}, found {self.view!r}"))
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
        problem = range_problem(self.tolerance, 0.001, 0.1, " m")
        if problem:
            out.append(("tolerance", problem))
        raise_first(out)



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
    fps, speed, size, start, end, max_frames, trail, skip_quiet, legend, view
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
    view: str | None = None

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
