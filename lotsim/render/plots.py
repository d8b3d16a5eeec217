"""Plots beside the GIF: a run's timeline (:func:`plot_timeline`) and the shortest
parallel slot against direction changes (:func:`plot_minslot`, ``lotsim minslot --plot``).

matplotlib is an optional extra (``pip install 'lotsim[plot]'``). It is imported only when
a figure is made; without it, :class:`MatplotlibMissing` is raised. Figures are plain
:class:`matplotlib.figure.Figure` objects drawn by the Agg canvas, not :mod:`matplotlib.pyplot`
figures: no window opens and the backend of the program that imports lotsim (a notebook, say)
is left alone.

The ``*_figure`` functions build a figure to look at or adjust; the ``plot_*`` functions build
it and write it to a PNG with :func:`save_figure`, and return it too.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from lotsim.core.atomic import atomic_write
from lotsim.errors import LotsimError
from lotsim.render.replay import Replay, assign_colours

if TYPE_CHECKING:
    from matplotlib.figure import Figure

RGB = tuple[int, int, int]
"""A colour, 0–255 per channel."""

OUTSIDE: RGB = (205, 205, 205)
"""Timeline bars of vehicles waiting outside, at their entrance."""
REJECTED: RGB = (220, 0, 0)
"""The mark of a vehicle turned away."""
INK: RGB = (40, 40, 40)
MINUTES_AFTER = 600.0
"""Runs longer than this [s] get a time axis in minutes."""
MAX_LABELLED = 60
"""Timelines of at most this many vehicles name each row."""
HEIGHT_IN = (4.0, 14.0)
"""Smallest and largest timeline height [in]."""


class MatplotlibMissing(LotsimError, ImportError):
    """matplotlib, which every plot needs, is not installed (``pip install 'lotsim[plot]'``)."""


def require_matplotlib() -> None:
    """Raise :class:`MatplotlibMissing` unless matplotlib can be imported.

    Lets a caller fail before long computations whose result it means to plot.
    """
    try:
        import matplotlib  # noqa: F401
        from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: F401
        from matplotlib.figure import Figure  # noqa: F401
    except ImportError as exc:
        raise MatplotlibMissing("plots need matplotlib: pip install 'lotsim[plot]'") from exc


def _new_figure(**kwargs: Any) -> Figure:
    """A figure on its own Agg canvas (no pyplot, no global backend switch)."""
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(**kwargs)
    FigureCanvasAgg(fig)
    return fig


def _rgb(c: Sequence[float]) -> tuple[float, float, float]:
    return (c[0] / 255, c[1] / 255, c[2] / 255)


def save_figure(fig: Figure, path: str | os.PathLike) -> None:
    """Write ``fig`` to ``path`` as PNG, then close it.

    The PNG is written to a temporary file in the same directory and renamed over ``path``,
    so ``path`` is never half-written and nothing is left behind on failure (the
    :class:`OSError` is raised).
    """
    try:
        with atomic_write(path) as fh:
            fig.savefig(fh, format="png")
    finally:
        # our figures are not pyplot's; a caller's pyplot figure is released from pyplot
        pyplot = sys.modules.get("matplotlib.pyplot")
        if pyplot is not None:
            pyplot.close(fig)


# -- minimum slot length -----------------------------------------------------------------------
def minslot_figure(docs: Sequence[dict]) -> Figure:
    """Minimum parallel slot length [m] against the number of direction changes.

    Parameters
    ----------
    docs : sequence of dict
        One per (car, slot width), as ``lotsim minslot --json`` prints them: ``car``,
        ``width`` [m] and ``rows`` of ``changes`` and ``length`` [m] (``None`` where no
        length works; such rows are left out of the curve).

    Returns
    -------
    matplotlib.figure.Figure
        One axes; one line with markers per doc that has a length, labelled
        ``"zoe, 2.5 m slot"``. With several cars, a car keeps its colour and each width
        has its own line style; with one car, each width has its colour.

    Examples
    --------
    >>> doc = {"car": "zoe", "width": 2.5, "rows": [
    ...     {"changes": 0, "length": None}, {"changes": 1, "length": 6.1},
    ...     {"changes": 2, "length": 5.4}]}
    >>> fig = minslot_figure([doc])
    >>> line = fig.axes[0].lines[0]
    >>> line.get_xdata().tolist(), line.get_ydata().tolist()
    ([1, 2], [6.1, 5.4])
    """
    fig = _new_figure(figsize=(7.5, 4.5), dpi=120, layout="constrained")
    import matplotlib
    from matplotlib.ticker import MaxNLocator

    ax = fig.add_subplot()
    cars = list(dict.fromkeys(d["car"] for d in docs))
    widths = list(dict.fromkeys(float(d["width"]) for d in docs))
    several_cars = len(cars) > 1
    n_colours = len(cars) if several_cars else len(widths)
    colours = matplotlib.colormaps["tab10" if n_colours <= 10 else "tab20"].colors
    styles = ("-", "--", ":", "-.")
    markers = ("o", "s", "^", "D", "v")
    for doc in docs:
        pts = [(r["changes"], r["length"]) for r in doc["rows"] if r["length"] is not None]
        if not pts:
            continue
        changes, lengths = zip(*pts, strict=True)
        w = widths.index(float(doc["width"]))
        c = cars.index(doc["car"]) if several_cars else w
        style = w if several_cars else 0
        ax.plot(changes, lengths, color=colours[c % len(colours)],
                linestyle=styles[style % len(styles)], marker=markers[style % len(markers)],
                ms=4, label=f"{doc['car']}, {float(doc['width']):g} m slot")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("direction changes")
    ax.set_ylabel("minimum slot length [m]")
    ax.set_title("Shortest parallel slot")
    ax.grid(alpha=0.3)
    if ax.lines:
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    else:
        ax.text(0.5, 0.5, "no length works", transform=ax.transAxes, ha="center",
                va="center", color="0.4")
    return fig


def plot_minslot(docs: Sequence[dict], path: str | os.PathLike) -> Figure:
    """Draw :func:`minslot_figure` of ``docs`` to the PNG ``path`` (:func:`save_figure`)
    and return the (closed) figure."""
    fig = minslot_figure(docs)
    save_figure(fig, path)
    return fig


# -- timeline of a run -------------------------------------------------------------------------
def timeline_figure(doc: dict, *, colours: Sequence[RGB] | None = None) -> Figure:
    """A Gantt chart of a run: one row per vehicle, in arrival order, first at the top.

    Bars show each phase of :data:`lotsim.render.replay.PHASES`: waiting outside in light grey,
    driving and leaving in the vehicle's colour, standing parked in a pale version of it
    (:func:`lotsim.render.colour_key.pale`). A small tick marks each arrival and a red ×
    each vehicle turned away. Time runs in seconds, or in minutes for runs longer than
    :data:`MINUTES_AFTER`.

    Parameters
    ----------
    doc : dict
        A result document (``result.json`` read with :func:`json.load`).
    colours : sequence of (r, g, b), optional
        One colour (0–255) per vehicle of ``doc["vehicles"]``; by default the colours the
        GIF draws them in (:func:`lotsim.render.replay.assign_colours` over
        :func:`lotsim.render.colour_key.vehicle_palette`).

    Returns
    -------
    matplotlib.figure.Figure
        One axes, whose data coordinates are (time [s or min], row); row ``i`` is the
        ``i``-th vehicle to arrive.

    Raises
    ------
    lotsim.render.replay.ReplayError
        ``doc`` is not a result document.
    ValueError
        ``colours`` does not hold one colour per vehicle.
    """
    from lotsim.render.colour_key import pale, vehicle_palette

    replay = Replay(doc)
    tracks = replay.tracks
    n = len(tracks)
    if colours is None:
        palette = vehicle_palette()
        colours = [palette[k] for k in assign_colours(tracks, len(palette), replay.end)]
    elif len(colours) != n:
        raise ValueError(f"colours: expected one colour per vehicle ({n}), found {len(colours)}")
    own = np.asarray(colours, dtype=float).reshape(n, 3) / 255
    pale_own = np.asarray([pale(tuple(int(v) for v in c)) for c in colours],
                          dtype=float).reshape(n, 3) / 255

    order = sorted(range(n), key=lambda j: (tracks[j].arrival, j))
    row = np.empty(n, dtype=int)
    row[order] = np.arange(n)
    start, end = replay.start, replay.end
    scale, unit = (60.0, "min") if end - start > MINUTES_AFTER else (1.0, "s")

    height = float(np.clip(1.6 + 0.22 * n, *HEIGHT_IN))
    fig = _new_figure(figsize=(10.0, height), dpi=100, layout="constrained")
    from matplotlib.collections import PolyCollection
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    ax = fig.add_subplot()
    # every bar of every vehicle in one collection: one artist, however many vehicles
    bars = [(j, name, t0, t1) for j, tr in enumerate(tracks) for name, t0, t1 in tr.phases(end)]
    if bars:
        owner = np.array([b[0] for b in bars])
        phase = np.array([b[1] for b in bars])
        t = np.array([(b[2], b[3]) for b in bars]) / scale
        y = row[owner].astype(float)
        half = 0.36 if n <= 200 else 0.48  # many thin rows: close the gaps, or bars fade
        verts = np.stack([np.column_stack([t[:, 0], y - half]),
                          np.column_stack([t[:, 1], y - half]),
                          np.column_stack([t[:, 1], y + half]),
                          np.column_stack([t[:, 0], y + half])], axis=1)
        face = np.where((phase == "parked")[:, None], pale_own[owner], own[owner])
        face[phase == "outside"] = _rgb(OUTSIDE)
        ax.add_collection(PolyCollection(verts, facecolors=face, edgecolors="none"))

    # markers about as tall as a row
    row_pt = 72 * 0.85 * height / max(n, 1)
    ms = float(np.clip(0.8 * row_pt, 2.0, 9.0))
    arrival = np.array([tr.arrival for tr in tracks]) / scale
    ax.scatter(arrival, row, marker="|", s=ms**2, color=_rgb(INK), linewidths=0.8, zorder=3)
    turned = [j for j, tr in enumerate(tracks) if math.isfinite(tr.rejected_at)]
    if turned:
        ax.scatter([tracks[j].rejected_at / scale for j in turned], row[turned], marker="x",
                   s=ms**2, color=_rgb(REJECTED), linewidths=1.2, zorder=4)

    pad = max(end - start, 1.0) * 0.01
    ax.set_xlim((start - pad) / scale, (end + pad) / scale)
    ax.set_ylim(max(n, 1) - 0.5, -0.5)  # first arrival at the top
    ax.set_xlabel(f"run time [{unit}]")
    ax.set_ylabel("vehicles (in arrival order)")
    if 0 < n <= MAX_LABELLED:
        ax.set_yticks(range(n), [tracks[j].id for j in order],
                      fontsize=float(np.clip(0.7 * row_pt, 5, 9)))
    else:
        ax.set_yticks([])
    ax.grid(axis="x", alpha=0.3)
    ax.set_axisbelow(True)

    example = own[order[0]] if n else np.asarray(_rgb(vehicle_palette()[0]))
    example_pale = pale_own[order[0]] if n else np.asarray(_rgb(pale(vehicle_palette()[0])))
    handles = [
        Patch(facecolor=_rgb(OUTSIDE), label="waiting outside"),
        Patch(facecolor=example, label="driving, leaving\n(the vehicle's colour)"),
        Patch(facecolor=example_pale, label="parked (pale)"),
        Line2D([], [], color=_rgb(INK), marker="|", linestyle="none", label="arrival"),
    ]
    if turned:
        handles.append(Line2D([], [], color=_rgb(REJECTED), marker="x", linestyle="none",
                              label="turned away"))
    ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))

    settings = doc.get("settings") or {}
    name = settings.get("scenario") or doc.get("lot", {}).get("name") or "run"
    planner = settings.get("planner")
    ax.set_title(f"{name}: {n} vehicle{'s' * (n != 1)}"
                 + (f", planner {planner}" if planner else ""))
    return fig


def plot_timeline(doc: dict, path: str | os.PathLike, *,
                  colours: Sequence[RGB] | None = None) -> Figure:
    """Draw :func:`timeline_figure` of ``doc`` to the PNG ``path`` (:func:`save_figure`)
    and return the (closed) figure."""
    fig = timeline_figure(doc, colours=colours)
    save_figure(fig, path)
    return fig
