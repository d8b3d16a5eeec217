"""lotsim as a Python library: the functions ``import lotsim`` offers (``docs/python.md``).

Everything the command line does goes through these, with the same checks and the same
errors (:class:`~lotsim.errors.LotsimError` and its kinds); the CLI only parses its options,
calls them and prints. Scenarios may be given as a :class:`~lotsim.scenario.Scenario`, a
path, or YAML text (a ``str`` holding a line break).

Examples
--------
>>> import lotsim
>>> prepared = lotsim.prepare(lotsim.EXAMPLE)
>>> result = lotsim.run(prepared, planner="whca", window=10)
>>> result.metrics()["parked"], lotsim.check(result).ok
(2, True)
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

from lotsim.core import checks as _checks
from lotsim.errors import ReplayError, SettingsError
from lotsim.io.scenario_yaml import read_scenario
from lotsim.maneuvers.settings import MARGIN, STYLES, MinSlotSettings
from lotsim.scenario import AnimationSpec, GifSettings, HtmlSettings, Scenario, size_problem
from lotsim.sim import preparation as _preparation
from lotsim.sim import results as _results
from lotsim.sim.preparation import PreparedLot
from lotsim.sim.settings import RunSettings
from lotsim.sim.validation import ValidationReport, validate_prepared

if TYPE_CHECKING:
    from PIL import Image

    from lotsim.lot.model import Lot, Slot
    from lotsim.maneuvers.maneuver import Maneuver
    from lotsim.maneuvers.minslot import MinSlotRow
    from lotsim.maneuvers.planner import ManeuverPlanner
    from lotsim.render.animation import GifInfo
    from lotsim.render.html import HtmlInfo
    from lotsim.render.video import VideoInfo
    from lotsim.vehicles.model import VehicleType
    from lotsim.verify import CheckReport

ScenarioLike = Scenario | str | os.PathLike
"""A :class:`~lotsim.scenario.Scenario`, a path to its file, or its YAML text."""

EXAMPLE = """\
name: example
description: One one-way aisle, 2 x 4 perpendicular slots, two taken; three cars, one leaves.
seed: 1
lot:
  boundary: [[0, 0], [32, 0], [32, 20], [0, 20]]
  aisles:
    - {id: main, centerline: [[0, 10], [32, 10]], width: 7.0, direction: one-way}
  rows:
    - {aisle: main, side: left, kind: perpendicular, count: 4, slot_width: 2.5,
       slot_length: 5.0, start: 8.0, id_prefix: N}
    - {aisle: main, side: right, kind: perpendicular, count: 4, slot_width: 2.5,
       slot_length: 5.0, start: 8.0, id_prefix: S}
  entrances: [{id: in, x: 3.0, y: 10.0, heading_deg: 0}]
  exits: [{id: out, x: 24.0, y: 10.0, heading_deg: 0}]
  occupied: [N2, S3]
traffic:
  vehicles:
    - {id: ada, arrival: 0}
    - {id: bob, arrival: 3, dwell: 20}
    - {id: cy, arrival: 6}
"""
"""A small scenario's YAML text, for examples and first steps: it prepares and runs in
about a second."""


# -- scenarios ----------------------------------------------------------------------------------
def load_scenario(path_or_text: str | os.PathLike) -> Scenario:
    """Read and validate a scenario: the lot, its vehicle types and traffic.

    Parameters
    ----------
    path_or_text : str or path-like
        A scenario file (``docs/scenario.md``), or its YAML text: a ``str`` holding a line
        break is read as text, and errors then name the file ``<scenario>``.

    Returns
    -------
    Scenario
        Frozen; the file's ``animation`` section is not part of it (:func:`load_animation`).

    Raises
    ------
    ScenarioError
        On the first problem, as ``file:line:col: key: what was expected``.

    Examples
    --------
    >>> sc = load_scenario(EXAMPLE)
    >>> sc.name, [v.name for v in sc.vehicle_types], len(sc.traffic.vehicles)
    ('example', ['valet'], 3)
    >>> load_scenario(EXAMPLE.replace("width: 7.0", "width: wide"))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    lotsim.errors.ScenarioError: <scenario>:7:58: lot.aisles[0].width: expected a number, ...
    """
    return read_scenario(path_or_text).scenario


def load_animation(path_or_text: str | os.PathLike) -> AnimationSpec | None:
    """A scenario file's ``animation`` section: how ``lotsim run`` draws the run's GIF
    (None when it has none). Give it to :func:`render_gif` as its settings.

    Raises
    ------
    ScenarioError
        On the first problem in the file (the whole scenario is checked).

    Examples
    --------
    >>> load_animation(EXAMPLE + "animation: {speed: 2}\\n").gif_settings().speed
    2.0
    >>> load_animation(EXAMPLE) is None
    True
    """
    return read_scenario(path_or_text).animation


def _scenario(scenario: ScenarioLike | PreparedLot) -> Scenario:
    if isinstance(scenario, PreparedLot):
        return scenario.scenario
    if isinstance(scenario, Scenario):
        return scenario
    if isinstance(scenario, (str, os.PathLike)):
        return load_scenario(scenario)
    raise SettingsError("scenario", f"expected a Scenario, a PreparedLot, a path or YAML "
                                    f"text, found {type(scenario).__name__}")


def _source(scenario: ScenarioLike | PreparedLot) -> str:
    """How a scenario was named, for messages: its path as given, else its source."""
    if isinstance(scenario, os.PathLike) or (isinstance(scenario, str) and "\n" not in scenario):
        return os.fspath(scenario)
    return _scenario(scenario).source


def prepare(scenario: ScenarioLike, *, cache: bool = True, progress=None) -> PreparedLot:
    """Build the scenario's lot for its vehicle types, plan every slot's maneuvers and the
    drivable graph through them, once, for any number of runs.

    Parameters
    ----------
    scenario : Scenario, path or YAML text
    cache : bool, keyword-only
        Load a lot prepared before (same lot, vehicle types and lotsim) from the on-disk
        cache (``LOTSIM_CACHE_DIR``; ``off`` turns it off) and store a new one there.
    progress : callable, optional, keyword-only
        Called as ``progress(done, total)`` as the maneuvers' distinct problems are searched
        (the longest part of preparing a large lot; not called for a lot from the cache).

    Returns
    -------
    PreparedLot
        Frozen: the scenario and its ``lot_graph``; hand it to :func:`run`.

    Raises
    ------
    ScenarioError
        When the layout does not hold together (overlaps, narrow aisles, ...).

    Examples
    --------
    >>> prepared = prepare(EXAMPLE)
    >>> len(prepared.lot.free_slots), prepared.infeasible
    (6, {'valet': {}})
    """
    sc = _scenario(scenario)
    return _preparation.prepare_lot(sc, cache=cache, progress=progress)


def validate(scenario: ScenarioLike | PreparedLot, *, progress=None) -> ValidationReport:
    """What ``lotsim validate`` checks and prints, as data: the scenario is read, its lot
    prepared, its traffic checked as :func:`run` checks it. ``progress`` is passed to
    :func:`prepare`.

    Returns
    -------
    ValidationReport
        ``.summary()`` is the text ``lotsim validate`` prints; ``.complete`` is what
        ``--strict`` requires (every free slot and exit reachable, every slot usable by
        every type); ``.reachability``, ``.infeasible`` and ``.warnings`` hold the details;
        ``.prepared`` is ready for :func:`run`.

    Raises
    ------
    ScenarioError
        For anything ``lotsim validate`` reports as an error (exit 2).

    Examples
    --------
    >>> report = validate(EXAMPLE)
    >>> report.complete, report.warnings
    (True, [])
    >>> print(report.summary().splitlines()[1])
      slots: 8 (perpendicular 8, parallel 0, angled 0); free 6, taken 2
    """
    prepared = (scenario if isinstance(scenario, PreparedLot)
                else prepare(scenario, progress=progress))
    return validate_prepared(prepared, _source(scenario))


# -- running --------------------------------------------------------------------------------------
@dataclasses.dataclass
class RunResult(_results.RunResult):
    """What :func:`run` returns: the lot, the settings and every vehicle's story.

    ``metrics()`` counts the vehicles by status and gives the timing figures of
    ``docs/result.md``; ``vehicles`` holds each one's arrival, slot, status, reason and
    moves; ``settings`` the :class:`RunSettings` it was planned with (the order its
    priority chose included: running them again plans the same run); ``ordering`` how the
    order was chosen.
    """

    def to_dict(self) -> dict:
        """The run as the JSON document ``lotsim run`` writes (``docs/result.md``).

        >>> doc = run(EXAMPLE).to_dict()
        >>> doc["format"], [v["status"] for v in doc["vehicles"]]
        ('lotsim-result', ['parked', 'departed', 'parked'])
        """
        from lotsim.io.result import result_dict

        return result_dict(self)

    def write(self, path: str | os.PathLike) -> Path:
        """Write the run to ``path`` as ``result.json`` (atomically: nothing half-written;
        its folder is made if need be); byte for byte what ``lotsim run`` writes for the
        same scenario and seed.

        >>> import tempfile
        >>> folder = tempfile.mkdtemp()
        >>> run(EXAMPLE).write(f"{folder}/result.json").name
        'result.json'
        """
        from lotsim.io.result import write_json

        Path(path).parent.mkdir(parents=True, exist_ok=True)
        write_json(self.to_dict(), path)
        return Path(path)


def run(scenario_or_prepared: ScenarioLike | PreparedLot, settings: RunSettings | None = None,
        *, progress=None, **overrides: Any) -> RunResult:
    """Plan the scenario's traffic: assign slots, plan every vehicle in, and out again.

    Parameters
    ----------
    scenario_or_prepared : PreparedLot, Scenario, path or YAML text
        A :class:`PreparedLot` is run as it is; anything else is prepared first
        (:func:`prepare`, from the cache when it can): prepare once to run many times.
    settings : RunSettings, optional
        How to plan (the defaults of ``lotsim run`` when not given).
    progress : callable, optional, keyword-only
        Called as ``progress(done, total)``: trips planned, or, with ``priority="ga"``,
        orders the genetic algorithm has tried.
    **overrides
        Fields of :class:`RunSettings` to change: ``planner``, ``assignment``, ``seed``,
        ``window``, ``omega``, ``retry``, ``order``, ``horizon``, ``priority``, ``ga``,
        ``tuning``.

    Returns
    -------
    RunResult
        ``.metrics()``, ``.vehicles``, ``.to_dict()``, ``.write(path)``.

    Raises
    ------
    SettingsError
        For a setting out of range or unknown (``window: expected 1 to 600 seconds,
        found 0``).
    ScenarioError
        For a bad scenario, one without traffic, or traffic the lot cannot serve at all.

    Examples
    --------
    >>> prepared = prepare(EXAMPLE)
    >>> a = run(prepared, planner="hca")
    >>> b = run(prepared, RunSettings(planner="hca", priority="shortest_first"))
    >>> a.metrics()["vehicles"], b.settings.order
    (3, ('ada', 'cy', 'bob'))
    >>> run(prepared, planner="whca", window=0)
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: window: expected 1 to 600 seconds, found 0
    """
    if settings is not None and not isinstance(settings, RunSettings):
        raise SettingsError("settings", f"expected RunSettings, found "
                                        f"{type(settings).__name__}")
    settings = _checks.replace(settings or RunSettings(), overrides)
    prepared = (scenario_or_prepared if isinstance(scenario_or_prepared, PreparedLot)
                else prepare(scenario_or_prepared))
    traffic = prepared.scenario.traffic
    if settings.seed is not None and traffic is not None:
        stream = traffic.stream
        if stream is None:
            raise SettingsError("seed", "seeds the traffic stream, and this scenario has "
                                        "none (its vehicles are listed): it would change "
                                        "nothing")
        if stream.seed is not None:
            raise SettingsError("seed", f"the scenario's stream has its own seed "
                                        f"({stream.seed}, {stream.where}): it would change "
                                        f"nothing")
    from lotsim.sim.orders import plan_run

    rr = plan_run(prepared.scenario, settings, lot_graph=prepared.lot_graph,
                  progress=progress)
    return RunResult(**{f.name: getattr(rr, f.name) for f in dataclasses.fields(rr)})


# -- results --------------------------------------------------------------------------------------
def _document(result: RunResult | dict | str | os.PathLike) -> dict:
    """The document of ``result``; a file is read packed (:func:`load_result`): what is
    done with it here reads the samples as arrays."""
    if isinstance(result, _results.RunResult):
        from lotsim.io.result import result_dict

        return result_dict(result)
    if isinstance(result, dict):
        return result
    if isinstance(result, (str, os.PathLike)):
        return load_result(result, packed=True)
    raise SettingsError("result", f"expected a RunResult, a result dict or a result.json "
                                  f"path, found {type(result).__name__}")


def load_result(path: str | os.PathLike, *, packed: bool = False) -> dict:
    """Read a ``result.json`` (:func:`lotsim.verify.load_result`).

    With ``packed``, each vehicle's sample columns are numpy float arrays, made as the file
    is read (a quarter of the memory of lists of floats), not lists.

    Raises
    ------
    ResultFormatError
        When it cannot be read or is not a lotsim result; a scenario or a bench suite is
        named as such.

    Examples
    --------
    >>> import tempfile
    >>> path = f"{tempfile.mkdtemp()}/example.yaml"
    >>> _ = Path(path).write_text(EXAMPLE)
    >>> load_result(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    lotsim.errors.ResultFormatError: /.../example.yaml: this is a lotsim scenario, not a result: ...
    """
    from lotsim.errors import ResultFormatError
    from lotsim.io.kinds import file_kind, wrong_kind
    from lotsim.verify import load_result as load

    try:
        return load(path, packed=packed)
    except ResultFormatError:
        found = file_kind(path)
        if found is None or found == "result":
            raise
    raise ResultFormatError(f"{os.fspath(path)}: {wrong_kind(found, 'result')}")


def check(result: RunResult | dict | str | os.PathLike, *, max_violations: int = 50
          ) -> CheckReport:
    """Verify a run independently of the planner, as ``lotsim check`` does: footprints never
    overlap each other, parked cars, obstacles or the boundary; no sideways motion;
    curvature, steering rate, speed, acceleration and jerk within the vehicle's limits;
    parked cars inside their slots (every rule of ``docs/result.md``).

    Parameters
    ----------
    result : RunResult, dict or path
        A run, its document (:meth:`RunResult.to_dict`) or a ``result.json``.
    max_violations : int, keyword-only
        How many violations to list (``.stats["violations"]`` counts them all).

    Returns
    -------
    CheckReport
        ``.ok``, ``.violations`` (rule, vehicle, time, message), ``.stats``, ``.summary()``.

    Raises
    ------
    ResultFormatError
        When a file named is not JSON or not a lotsim result.

    Examples
    --------
    >>> report = check(run(EXAMPLE))
    >>> report.ok, report.violations
    (True, [])
    >>> check({"format": "lotsim-result"}).violations[0].rule
    'structure'
    """
    from lotsim.verify import check_result

    if not (_checks.is_real(max_violations) and max_violations >= 1):
        raise SettingsError("max_violations", f"expected at least 1, found "
                                              f"{_checks.shown(max_violations)}")
    return check_result(_document(result), max_violations=int(max_violations))


def render_gif(result: RunResult | dict | str | os.PathLike, path: str | os.PathLike,
               settings: GifSettings | AnimationSpec | None = None, *, progress=None,
               **overrides: Any) -> GifInfo:
    """Draw a run as an animated GIF (``lotsim render --gif``, ``lotsim run``'s GIF).

    Parameters
    ----------
    result : RunResult, dict or path
        A run, its document or a ``result.json``.
    path : str or path-like
        The GIF to write (atomically; its folder is made if need be).
    settings : GifSettings or AnimationSpec, optional
        How to draw it; a scenario's animation section (:func:`load_animation`) works.
    progress : callable, optional, keyword-only
        Called as ``progress(frames done, frames)``.
    **overrides
        Fields of :class:`GifSettings`: ``fps``, ``speed``, ``size`` (pixels, a
        ``(width, height)`` pair), ``start``, ``end``, ``max_frames``, ``trail``.

    Returns
    -------
    GifInfo
        ``.path``, ``.frames``, ``.duration`` [s], ``.speed``, ``.start``, ``.end``, ``.bytes``.

    Raises
    ------
    SettingsError
        A setting out of range, or a span outside the run.
    ReplayError, ResultFormatError
        When the result cannot be drawn.

    Examples
    --------
    >>> import tempfile
    >>> gif = f"{tempfile.mkdtemp()}/run.gif"
    >>> info = render_gif(run(EXAMPLE), gif, size=(320, 240), end=20)
    >>> info.path.name, info.duration
    ('run.gif', 5.0)
    """
    settings = _gif_settings(settings, overrides)
    _suffix(path, ".gif")
    doc = _drawable(result)
    from lotsim.render.animation import write_gif

    Path(path).parent.mkdir(parents=True, exist_ok=True)
    return write_gif(doc, path, settings, progress=progress)


def _drawable(result: RunResult | dict | str | os.PathLike) -> dict:
    doc = _document(result)
    if not isinstance(doc.get("lot"), dict) or "drawing" not in doc["lot"]:
        raise ReplayError("no lot.drawing: written by an older lotsim? run the scenario again")
    return doc


def _gif_settings(settings: GifSettings | AnimationSpec | None, overrides: dict
                  ) -> GifSettings:
    if isinstance(settings, AnimationSpec):
        settings = settings.gif_settings()
    if settings is not None and not isinstance(settings, GifSettings):
        raise SettingsError("settings", f"expected GifSettings or AnimationSpec, found "
                                        f"{type(settings).__name__}")
    return _checks.replace(settings or GifSettings(), overrides)


def render_html(result: RunResult | dict | str | os.PathLike, path: str | os.PathLike,
                settings: HtmlSettings | AnimationSpec | None = None, **overrides: Any
                ) -> HtmlInfo:
    """Write a run as an interactive replay: one self-contained HTML file that opens from
    disk in a browser (``lotsim render --html``; ``lotsim/render/html.py`` says what it
    holds and how it is kept small).

    Parameters
    ----------
    result : RunResult, dict or path
        A run, its document or a ``result.json``.
    path : str or path-like
        The ``.html`` file to write (atomically; its folder is made if need be).
    settings : HtmlSettings or AnimationSpec, optional
    **overrides
        Fields of :class:`HtmlSettings`: ``speed`` (1, 2, 4, 10, 30 or 60), ``skip_quiet``,
        ``tolerance`` [m].

    Returns
    -------
    HtmlInfo
        ``.path``, ``.bytes``, ``.vehicles``, ``.samples`` (in the result), ``.kept`` (in
        the file).

    Examples
    --------
    >>> import tempfile
    >>> info = render_html(run(EXAMPLE), f"{tempfile.mkdtemp()}/replay.html")
    >>> info.path.name, info.vehicles, info.kept < info.samples
    ('replay.html', 3, True)
    """
    if isinstance(settings, AnimationSpec):
        settings = settings.html_settings()
    if settings is not None and not isinstance(settings, HtmlSettings):
        raise SettingsError("settings", f"expected HtmlSettings or AnimationSpec, found "
                                        f"{type(settings).__name__}")
    settings = _checks.replace(settings or HtmlSettings(), overrides)
    _suffix(path, ".html")
    doc = _drawable(result)
    from lotsim.render.html import write_html

    Path(path).parent.mkdir(parents=True, exist_ok=True)
    return write_html(doc, path, settings)


def render_mp4(result: RunResult | dict | str | os.PathLike, path: str | os.PathLike,
               settings: GifSettings | AnimationSpec | None = None, *, progress=None,
               **overrides: Any) -> VideoInfo:
    """Draw a run as an H.264 MP4 video: the GIF's frames (``lotsim render --mp4``).

    Needs the optional ``imageio-ffmpeg`` package (``pip install 'lotsim[video]'``).
    Parameters as :func:`render_gif`; ``size`` must be even in both directions.

    Returns
    -------
    VideoInfo
        ``.path``, ``.frames``, ``.duration`` [s], ``.speed``, ``.start``, ``.end``,
        ``.skipped`` [s], ``.bytes``.

    Raises
    ------
    VideoUnavailable
        (a :class:`LotsimError`) without ``imageio-ffmpeg``.
    SettingsError, ReplayError, ResultFormatError
        As :func:`render_gif`.
    """
    settings = _gif_settings(settings, overrides)
    _suffix(path, ".mp4")
    doc = _drawable(result)
    from lotsim.render.video import write_mp4

    Path(path).parent.mkdir(parents=True, exist_ok=True)
    return write_mp4(doc, path, settings, progress=progress)


def render_lot(scenario: ScenarioLike | PreparedLot, path: str | os.PathLike | None = None,
               *, size: tuple[int, int] = (1200, 900), graph: bool = False) -> Image.Image:
    """A picture of the lot (``lotsim show``): slots, aisles, walls, gates, cars parked at
    start; with ``graph``, the drivable graph over it.

    Parameters
    ----------
    scenario : PreparedLot, Scenario, path or YAML text
        A scenario is built without its maneuvers (quick) unless ``graph`` is asked for.
    path : str or path-like, optional
        Also write the picture there as PNG (atomically; its folder is made if need be).
    size : (width, height), keyword-only
        Pixels, 160x120 to 4000x4000 (as every picture lotsim draws).
    graph : bool, keyword-only

    Returns
    -------
    PIL.Image.Image
        A notebook shows it as it is.

    Examples
    --------
    >>> render_lot(EXAMPLE, size=(400, 300)).size
    (400, 300)
    """
    problem = size_problem(size)
    if problem:
        raise SettingsError("size", problem)
    _suffix(path, ".png")
    if isinstance(scenario, PreparedLot):
        sc, lg = scenario.scenario, scenario.lot_graph
    else:
        sc = _scenario(scenario)
        lg = _preparation.prepare(sc, maneuvers=graph)
    from lotsim.render.lot_image import draw_lot, save_png

    img = draw_lot(lg, size=size, show_graph=graph, parked_vehicle=sc.parked_vehicle,
                   title=sc.name)
    if path is not None:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        save_png(img, path)
    return img


def _suffix(path: str | os.PathLike | None, suffix: str) -> None:
    """Refuse to write a picture under another file type's name (PNG bytes in ``.jpg``)."""
    if path is not None and Path(path).suffix.lower() != suffix:
        raise SettingsError("path", f"expected a file name ending in {suffix}, found "
                                    f"{os.fspath(path)!r}")


# -- one car, one slot ----------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class MinSlotTable:
    """The shortest parallel slot of a given width for each number of direction changes."""

    car: VehicleType
    width: float
    """Slot width [m]."""
    rows: tuple[MinSlotRow, ...]
    """``changes``, ``length`` [m] (None: no length up to twice the car's works) and a start
    heading ``theta0`` [rad] that achieves it."""

    def to_dict(self) -> dict:
        """What ``lotsim minslot --json`` prints for one car and width."""
        c = self.car
        return {"car": c.name, "car_length": round(c.length, 4), "width": self.width,
                "rows": [{"changes": r.changes, "length": r.length,
                          "ratio": None if r.length is None else round(r.length / c.length, 4)}
                         for r in self.rows]}


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
    raise SettingsError("car", f"unknown car {os.fspath(name_or_path)!r}; expected one of "
                               f"{', '.join(CATALOGUE)} or a vehicle YAML file")


def check_slot_width(vehicle: VehicleType, width: float, *, narrow_ok: bool = False) -> None:
    """Refuse a slot width :func:`minslot` cannot use for ``vehicle``: not a positive number
    of metres, or (unless ``narrow_ok``) narrower than the car, where no length works.

    Raises
    ------
    SettingsError
        Named ``width``.

    Examples
    --------
    >>> check_slot_width(car("altis"), 1.5)
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: width: a 1.5 m slot is narrower than altis (1.78 m wide)
    """
    if not (_checks.is_real(width) and 0 < width < math.inf):
        raise SettingsError("width", f"expected a positive slot width in metres, found "
                                     f"{_checks.shown(width)}")
    if width < vehicle.width and not narrow_ok:
        raise SettingsError("width", f"a {width:g} m slot is narrower than {vehicle.name} "
                                     f"({vehicle.width:g} m wide)")


def minslot(vehicle: VehicleType | str | os.PathLike, width: float,
            settings: MinSlotSettings | None = None, *, narrow_ok: bool = False,
            **overrides: Any) -> MinSlotTable:
    """The shortest parallel slot for each number of direction changes (``lotsim minslot``):
    seed 000's strategy, swept over start headings, lengths bisected.

    Parameters
    ----------
    vehicle : VehicleType, str or path-like
        A vehicle type, a catalogue name or a vehicle YAML file (:func:`car`).
    width : float
        Slot width [m], positive, at least the car's width (:func:`check_slot_width`).
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
    from lotsim.maneuvers.minslot import min_slot_lengths

    s = _checks.replace(settings or MinSlotSettings(), overrides)
    v = vehicle if not isinstance(vehicle, (str, os.PathLike)) else car(vehicle)
    check_slot_width(v, width, narrow_ok=narrow_ok)
    rows = min_slot_lengths(v, width, max_changes=s.max_changes, resolution=s.resolution,
                            step_deg=s.step_deg)
    return MinSlotTable(v, width, tuple(rows))


class _ManeuverCase(NamedTuple):
    scenario: Scenario
    lot: Lot
    vehicle: VehicleType
    slot: Slot
    planner: ManeuverPlanner
    lane: str | None


def maneuver_case(scenario: ScenarioLike, slot: str, *, vehicle: str | None = None,
                  lane: str | None = None, style: str = "any", margin: float = MARGIN
                  ) -> _ManeuverCase:
    """The checked problem :func:`plan_maneuver` solves (the CLI draws it too)."""
    problem = _checks.choice_problem(style, STYLES)
    if problem:
        raise SettingsError("style", problem)
    if not (_checks.is_real(margin) and 0.0 <= margin <= 1.0):
        raise SettingsError("margin", f"expected 0 to 1 m, found {_checks.shown(margin)}")
    from lotsim.lot.build import build_lot
    from lotsim.lot.model import DesignVehicle

    sc = _scenario(scenario)
    names = [v.name for v in sc.vehicle_types]
    vname = vehicle or names[0]
    if vname not in names:
        raise SettingsError("vehicle", f"expected one of {', '.join(names)}, found {vname!r}")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    chosen = lot.slot_by_id.get(slot)
    if chosen is None:
        from lotsim.sim.validation import id_ranges

        close = difflib.get_close_matches(str(slot), list(lot.slot_by_id), n=3)
        hint = f"; did you mean {', '.join(close)}?" if close else ""
        raise SettingsError("slot", f"no slot {slot!r} in {_source(scenario)}{hint} (its "
                                    f"slots: {id_ranges(lot.slot_by_id)}; lotsim show draws "
                                    f"them)")
    planner = _preparation.maneuver_planner(sc, lot, margin=margin)
    lanes = [ln.id for ln in planner.lanes_for(chosen)]
    if lane is not None and lane not in lanes:
        raise SettingsError("lane", f"slot {chosen.id!r} is parked into from "
                                    f"{', '.join(lanes)}, not {lane!r}")
    return _ManeuverCase(sc, lot, sc.vehicle_type(vname), chosen, planner, lane)


def plan_maneuver(scenario: ScenarioLike, slot: str, *, vehicle: str | None = None,
                  lane: str | None = None, style: str = "any", leave: bool = False,
                  margin: float = MARGIN) -> Maneuver:
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
    margin : float, keyword-only
        Clearance kept [m], 0 to 1.

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
                         margin=margin)
    if case.lane is not None:
        lanes = {ln.id: ln for ln in case.planner.lanes_for(case.slot)}
        m = case.planner.plan(case.vehicle, case.slot, lanes[case.lane], style=style)
    else:
        m = case.planner.best(case.vehicle, case.slot, style=style)
    return m.reversed() if leave else m


# -- exports ---------------------------------------------------------------------------------------
def export_commonroad(result: RunResult | dict | str | os.PathLike, folder: str | os.PathLike,
                      *, dt: float = 0.1):
    """Write a run as CommonRoad files (``lotsim export --commonroad``, ``docs/export.md``):
    ``scenario.xml`` (the lot's boundary, walls, islands and parked cars as obstacles, each
    car's dwell in its slot, one planning problem per trip in or out) and ``solution.xml``
    (a kinematic single-track trajectory per planning problem, on the uniform step ``dt``
    [s], positions at the CommonRoad vehicle's centre).

    Needs ``pip install 'lotsim[commonroad]'``; raises ``ExportUnavailable`` (a
    :class:`LotsimError`) without it. Returns a ``CommonRoadInfo`` (files, counts, the
    resampling error [m, rad], bytes).
    """
    if not (_checks.is_real(dt) and 0.01 <= dt <= 1.0):
        raise SettingsError("dt", f"expected 0.01 to 1 s, found {_checks.shown(dt)}")
    from lotsim.io.export import export_commonroad as write

    return write(_document(result), folder, dt=dt)



def export_sumo(result: RunResult | dict | str | os.PathLike, folder: str | os.PathLike,
                *, step: float = 0.1):
    """Write a run as a SUMO simulation (``lotsim export --sumo``, ``docs/export.md``): the
    aisles as a network built by ``netconvert`` (``lot.net.xml``), a parking area per slot
    with one space at the pose a car stands in it (``lot.add.xml``), each car as a trip from
    its entrance at its arrival time through a stop in its slot until it moved off, to its
    exit (``lot.rou.xml``), and ``lot.sumocfg`` to run them on the step ``step`` [s].

    Needs ``pip install 'lotsim[sumo]'``; raises ``ExportUnavailable`` (a
    :class:`LotsimError`) without it. Returns a ``SumoInfo`` (files, spaces, trips, bytes).
    """
    if not (_checks.is_real(step) and 0.001 <= step <= 1.0):
        raise SettingsError("step", f"expected 0.001 to 1 s, found {_checks.shown(step)}")
    from lotsim.io.export import export_sumo as write

    return write(_document(result), folder, step=step)


def export_openscenario(result: RunResult | dict | str | os.PathLike,
                        folder: str | os.PathLike):
    """Write a run as OpenSCENARIO and OpenDRIVE (``lotsim export --openscenario``,
    ``docs/export.md``): ``lot.xodr`` (OpenDRIVE 1.7: a road per aisle, a ``parkingSpace``
    object per slot) and ``lot.xosc`` (OpenSCENARIO 1.2: a vehicle per car following a
    timed polyline of its rear-axle centre, within 1 cm and 2 mrad of every sample).

    Needs ``pip install 'lotsim[openscenario]'``; raises ``ExportUnavailable`` (a
    :class:`LotsimError`) without it. Returns an ``OpenScenarioInfo`` (files, counts, the
    polylines' error [m, rad], bytes).
    """
    from lotsim.io.export import export_openscenario as write

    return write(_document(result), folder)
