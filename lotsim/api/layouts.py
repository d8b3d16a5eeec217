"""Laying a lot out on a plot (``lotsim layout``, ``docs/layout.md``): :func:`layout` reads
the plot, searches its layouts (:mod:`lotsim.design.search`) and writes the best as
scenarios."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from lotsim.core.atomic import atomic_write
from lotsim.design.plot import PlotSpec
from lotsim.design.plot_yaml import read_plot
from lotsim.design.results import LayoutResult
from lotsim.design.search import lay_out
from lotsim.design.settings import LayoutSettings
from lotsim.errors import SettingsError

PlotLike = PlotSpec | str | os.PathLike
"""A :class:`~lotsim.design.plot.PlotSpec`, a path to a plot file, or its YAML text."""


def layout(plot: PlotLike, output: str | os.PathLike | None = None, *, keep: int = 1,
           settings: LayoutSettings | None = None, pictures: bool = False,
           progress: Callable[[int, int], None] | None = None,
           client: Any = None) -> LayoutResult:
    """Lay a lot out on ``plot``: the layout with the most bays that every vehicle type
    can reach, park in and leave (lotsim's maneuver planner and reachability decide, as
    ``lotsim validate --strict`` does), then the shortest mean time to park and the most
    cars parked per hour in a run at the plot's demand.

    Parameters
    ----------
    plot : PlotSpec, path or YAML text
        The plot (``docs/layout.md``): boundary, islands, gates, vehicle types, the bays and
        aisles allowed, the demand.
    output : path, optional
        Where to write the best layout's scenario (``docs/scenario.md``); with ``keep`` N,
        the next best go beside it as ``NAME-2.yaml`` ... ``NAME-N.yaml``. Each file is
        written whole or not at all. None: nothing is written.
    keep : int, keyword-only
        How many of the best to write (1 to 20).
    pictures : bool, keyword-only
        Also draw, beside ``output``, the best lot (``NAME.png``) and the best few
        candidates side by side with their figures (``NAME-candidates.png``).
    settings : LayoutSettings, optional, keyword-only
        How to search (orientations, offsets, how many candidates are prepared and run at
        most, the planner of the runs, the workers).
    progress : callable, optional, keyword-only
        Called as ``progress(done, total)`` as candidates are prepared and run;
        ``total`` is the most that will be, and becomes ``done`` when the search ends.
    client : distributed.Client, optional, keyword-only
        Prepare the candidates on this Dask cluster (:func:`lotsim.bench.connect`, as
        ``lotsim bench`` and ``lotsim validate`` use it), as many at a time as its workers
        have threads, each on one core of the worker that takes it, instead of on
        ``settings.workers`` local processes. The workers need lotsim installed, not the
        plot file; the layout found is the same.

    Returns
    -------
    LayoutResult
        ``.ranked``: the candidates prepared, best first, each with its usable bays,
        bays per 100 m², aisle length, mean time to park, throughput and its scenario's
        YAML (``.yaml``); ``.table()`` sets the best side by side.

    Raises
    ------
    ScenarioError
        A bad plot file (``file:line:col: key: ...``), or a plot no layout has a usable bay
        in.
    SettingsError
        ``keep`` or a setting out of range, or an ``output`` not ending in ``.yaml``.

    Examples
    --------
    >>> import lotsim
    >>> plot = ("boundary: [[0, 0], [20, 0], [20, 24], [0, 24]]\\n"
    ...         "gates: [{id: in, at: [10, 0]}]\\nbays: {angles_deg: [90]}\\n"
    ...         "demand: {count: 3}\\n")
    >>> found = lotsim.layout(plot, settings=lotsim.LayoutSettings(offsets=1, prepared=1))
    >>> found.best.bays > 0, found.best.checked
    (True, True)
    """
    if isinstance(keep, bool) or not isinstance(keep, int) or not 1 <= keep <= 20:
        raise SettingsError("keep", f"expected 1 to 20, found {keep!r}")
    if pictures and output is None:
        raise SettingsError("pictures", "are drawn beside the output: give output too")
    paths: list[Path] = []
    if output is not None:
        out = Path(output)
        if out.suffix.lower() != ".yaml":
            raise SettingsError("output", f"expected a file name ending in .yaml, found "
                                          f"{os.fspath(output)!r}")
        paths = [out] + [out.with_name(f"{out.stem}-{k}{out.suffix}") for k in
                         range(2, keep + 1)]
    spec = plot if isinstance(plot, PlotSpec) else read_plot(plot)
    found = lay_out(spec, settings, keep=keep, progress=progress, client=client)
    good = [e for e in found.ranked if e.ok]
    for path, e in zip(paths, good, strict=False):
        with atomic_write(path, "w", encoding="utf-8") as fh:
            fh.write(e.document())
    if pictures:
        from lotsim.design.pictures import candidate_strip, figures, lot_picture
        from lotsim.render.lot_image import save_png

        best = paths[0]
        save_png(lot_picture(good[0], title=f"{found.plot.name}: {figures(1, good[0])}"),
                 best.with_suffix(".png"))
        save_png(candidate_strip(found), best.with_name(f"{best.stem}-candidates.png"))
    return found


def layout_files(output: str | os.PathLike, found: LayoutResult, keep: int = 1, *,
                 pictures: bool = False) -> list[Path]:
    """The files :func:`layout` wrote for ``output``, ``keep`` and ``pictures``, the
    scenarios best first, then the pictures."""
    out = Path(output)
    good = [e for e in found.ranked if e.ok][:keep]
    files = [out if k == 0 else out.with_name(f"{out.stem}-{k + 1}{out.suffix}")
             for k in range(len(good))]
    if pictures:
        files += [out.with_suffix(".png"), out.with_name(f"{out.stem}-candidates.png")]
    return files
