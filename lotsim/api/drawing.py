"""Pictures of runs and lots: a run as an animated GIF (:func:`render_gif`), an interactive
replay (:func:`render_html`) or a video (:func:`render_mp4`); a lot (:func:`render_lot`),
with its service routes (:func:`render_routes`); one slot's maneuver
(:func:`render_maneuver`)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lotsim.api.results import result_document
from lotsim.api.running import (
    RunResult,
    run,  # noqa: F401 (the examples)
)
from lotsim.api.scenarios import (
    EXAMPLE,  # noqa: F401 (the examples)
    ScenarioLike,
    prepare_for_drawing,
)
from lotsim.core import checks as _checks
from lotsim.errors import ReplayError, SettingsError
from lotsim.scenario import AnimationSpec, GifSettings, HtmlSettings, size_problem
from lotsim.sim.preparation import PreparedLot

if TYPE_CHECKING:
    from PIL import Image

    from lotsim.maneuvers.maneuver import Maneuver
    from lotsim.render.animation import GifInfo
    from lotsim.render.html import HtmlInfo
    from lotsim.render.video import VideoInfo
    from lotsim.roadmap.service_routes import RouteReport, RouteSettings
    from lotsim.sim.maneuver_case import ManeuverCase


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
    doc = result_document(result)
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
    prepared = _lot_to_draw(scenario, path, size, graph)
    sc, lg = prepared.scenario, prepared.lot_graph
    from lotsim.render.lot_image import draw_lot

    return _saved(draw_lot(lg, size=size, show_graph=graph,
                           parked_vehicle=sc.parked_vehicle, title=sc.name), path)


def render_routes(scenario: ScenarioLike | PreparedLot, path: str | os.PathLike | None = None,
                  *, size: tuple[int, int] = (1200, 900), graph: bool = False,
                  reports: Sequence[RouteReport] | None = None,
                  settings: RouteSettings | None = None) -> Image.Image:
    """A picture of the lot with the scenario's service routes over it (``lotsim show
    --routes``): each route's swept envelope filled in its colour and outlined, its path
    (the rear-axle line, blue forward and orange in reverse), a ring at its tightest
    clearance with the value, and a legend naming each route and whether it passes
    (:mod:`lotsim.render.route_image`).

    Parameters
    ----------
    scenario : PreparedLot, Scenario, path or YAML text
        A scenario with a ``routes`` section (docs/scenario.md).
    path : str or path-like, optional
        Also write the picture there as PNG (atomically; its folder is made if need be).
    size, graph : keyword-only
        As :func:`render_lot`.
    reports : sequence of RouteReport, optional, keyword-only
        The routes as planned already (``ValidationReport.routes``); planned here otherwise.
    settings : RouteSettings, optional, keyword-only
        How they are planned, when they are planned here.

    Raises
    ------
    SettingsError
        For a scenario without routes, or a size out of range.

    Examples
    --------
    >>> import lotsim
    >>> storefront = Path(lotsim.__file__).parents[1] / "scenarios/lots/storefront.yaml"
    >>> render_routes(storefront, size=(400, 300)).size
    (400, 300)
    """
    prepared = _lot_to_draw(scenario, path, size, graph)
    sc = prepared.scenario
    if not sc.routes:
        raise SettingsError("routes", f"scenario {sc.name!r} has no routes to draw (a "
                                      f"'routes' section: docs/scenario.md)")
    if reports is None:
        from lotsim.roadmap.service_routes import plan_routes

        reports = plan_routes(prepared.lot, sc.routes, settings)
    from lotsim.render.route_image import draw_routes

    return _saved(draw_routes(prepared.lot_graph, reports, size=size, show_graph=graph,
                              parked_vehicle=sc.parked_vehicle, title=sc.name), path)


def _lot_to_draw(scenario: ScenarioLike | PreparedLot, path: str | os.PathLike | None,
                 size: tuple[int, int], graph: bool) -> PreparedLot:
    """The lot a picture of ``scenario`` is drawn from, once its size and file name are
    found fit (:func:`render_lot`, :func:`render_routes`)."""
    problem = size_problem(size)
    if problem:
        raise SettingsError("size", problem)
    _suffix(path, ".png")
    return prepare_for_drawing(scenario, graph=graph)


def _saved(img: Image.Image, path: str | os.PathLike | None) -> Image.Image:
    """``img``, also written to ``path`` as PNG when one is given (its folder made)."""
    from lotsim.render.lot_image import save_png

    if path is not None:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        save_png(img, path)
    return img


def _suffix(path: str | os.PathLike | None, suffix: str) -> None:
    """Refuse to write a picture under another file type's name (PNG bytes in ``.jpg``)."""
    if path is not None and Path(path).suffix.lower() != suffix:
        raise SettingsError("path", f"expected a file name ending in {suffix}, found "
                                    f"{os.fspath(path)!r}")


def render_maneuver(case: ManeuverCase, maneuver: Maneuver, path: str | os.PathLike | None = None,
                    *, size: tuple[int, int] = (900, 700), title: str | None = None
                    ) -> Image.Image:
    """A picture of one slot's maneuver (``lotsim maneuver -o``): the lot around the slot,
    the car at its start and end, each stroke coloured by its gear, the cusps.

    Parameters
    ----------
    case : ManeuverCase
        The problem (:func:`maneuver_case`): its lot, vehicle and the scenario's parked cars.
    maneuver : Maneuver
        Its answer (``case.plan()``).
    path : str or path-like, optional
        Also write the picture there as PNG (atomically; its folder is made if need be).
    size : (width, height), keyword-only
        Pixels, 160x120 to 4000x4000.
    title : str, optional, keyword-only
        The line drawn above the lot.

    Examples
    --------
    >>> from lotsim.api.maneuvers import maneuver_case
    >>> case = maneuver_case(EXAMPLE, "N3")
    >>> render_maneuver(case, case.plan(), size=(400, 300)).size
    (400, 300)
    """
    problem = size_problem(size)
    if problem:
        raise SettingsError("size", problem)
    _suffix(path, ".png")
    from lotsim.render.lot_image import save_png
    from lotsim.render.maneuver_image import draw_maneuver

    img = draw_maneuver(case.lot, maneuver, case.vehicle,
                        parked_vehicle=case.scenario.parked_vehicle, size=size, title=title)
    if path is not None:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        save_png(img, path)
    return img
