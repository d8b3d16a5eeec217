"""Lots from other sources as scenario files (``lotsim import``, ``docs/import.md``):
OpenStreetMap extracts and Lanelet2 maps in Autoware's valet-parking convention; and plots
drawn in CAD (DXF) as plot files for ``lotsim layout``."""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Sequence
from pathlib import Path

from lotsim.design.settings import LayoutSettings
from lotsim.errors import ScenarioError
from lotsim.io.imports.dxf import DxfLayers, DxfPlot
from lotsim.io.imports.report import ImportedLot, ImportReport


def import_osm(source: str | os.PathLike, folder: str | os.PathLike, *,
               lots: Sequence[str] | None = None, layout: bool = False,
               settings: LayoutSettings | None = None,
               progress: Callable[[str], None] | None = None) -> ImportReport:
    """Write each parking lot of an OpenStreetMap file (``.osm`` XML or ``.osm.pbf``) as a
    scenario in ``folder`` (``lotsim import osm``, ``docs/import.md``): the lot's outline,
    its parking aisles, gates where a road reaches them, its mapped spaces or bays laid out
    along the aisles, what is paved, and a default traffic. ``lots`` picks lots by id
    (``way/123``, ``relation/9``, or the number); ``progress`` is told of each lot.

    With ``layout``, a lot that maps no aisles is laid out by :func:`lotsim.layout` (with
    ``settings``) on its plot — its outline, its islands, buildings and green areas kept
    clear, gates where roads meet its edge — and the best layout written as its scenario;
    its plot file is written beside it (``way-123.plot.yaml``), for ``lotsim layout``.

    Reading ``.osm.pbf`` needs ``pip install 'lotsim[osm]'``. Returns the
    :class:`~lotsim.io.imports.report.ImportReport`: per lot, written (where) or skipped
    (why), with its figures. Raises :class:`~lotsim.errors.LotsimError` on a file that is
    not OpenStreetMap.
    """
    from lotsim.io.imports.osm import osm_scenarios as run

    report = run(source, folder, lots=lots, plots=layout, progress=progress)
    if not layout:
        return report
    done = []
    for lot in report.lots:
        if lot.plot is not None:
            lot = _laid_out(lot, Path(folder), settings)
            if progress is not None:
                progress(lot.line())
        done.append(lot)
    return ImportReport(report.source, tuple(done))


def _laid_out(lot: ImportedLot, folder: Path, settings: LayoutSettings | None
              ) -> ImportedLot:
    """``lot``, which maps no aisles, laid out on its plot: its plot file and, where a layout
    has a usable bay, its scenario written."""
    from lotsim.core.atomic import atomic_write
    from lotsim.design.plot_yaml import read_plot
    from lotsim.design.search import lay_out
    from lotsim.io.imports.osm import NO_AISLE
    from lotsim.io.scenario_yaml import load_scenario

    plot = lot.plot
    text = plot.to_yaml()
    plot_path = folder / f"{plot.name}.plot.yaml"
    with atomic_write(plot_path, "w", encoding="utf-8") as fh:
        fh.write(text)
    try:
        found = lay_out(read_plot(plot_path), settings)
    except ScenarioError as exc:
        why = " ".join(str(exc).split()).removeprefix(f"{plot_path}: ")
        return dataclasses.replace(lot, reason=f"{NO_AISLE}; lotsim layout found none for its "
                                               f"plot {plot_path}: {why}")
    best = found.best
    header = "".join(line + "\n" for line in text.splitlines() if line.startswith("#"))
    path = folder / f"{plot.name}.yaml"
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write(header + best.document())
    aisles = len(load_scenario(best.yaml).lot.aisles)
    return dataclasses.replace(
        lot, inferred=best.bays, aisles=aisles, gates=len(plot.gates), path=path,
        reason=f"no parking aisle mapped: laid out by lotsim layout on {plot_path.name} "
               f"({best.label}; {best.bays_per_100m2:.2f} bays per 100 m²)")


def import_lanelet2(source: str | os.PathLike, folder: str | os.PathLike, *,
                    origin: tuple[float, float] | None = None,
                    progress: Callable[[str], None] | None = None) -> ImportReport:
    """Write a Lanelet2 map in Autoware's valet-parking convention as a scenario in
    ``folder`` (``lotsim import lanelet2``, ``docs/import.md``): its parking spots as slots,
    its lanelets widened over the parking-access ground as aisles, its drawn ground as the
    pavement, gates at its open road ends, and a default traffic. ``origin`` (latitude,
    longitude) is where the local metres start; by default the map's own (Autoware's
    map_config YAML beside it), else the middle of its nodes.

    Returns the :class:`~lotsim.io.imports.report.ImportReport` (one lot); raises
    :class:`~lotsim.errors.LotsimError` on a file that is not such a map.
    """
    from lotsim.io.imports.lanelet2 import import_lanelet2 as run

    return run(source, folder, origin=origin, progress=progress)


def import_dxf(source: str | os.PathLike, output: str | os.PathLike, *,
               layers: DxfLayers | None = None, units: str | None = None) -> DxfPlot:
    """Read a plot drawn in CAD from a DXF file and write it as a plot file ``output`` for
    :func:`lotsim.layout` (``lotsim import dxf``, ``docs/import.md``): the one closed
    outline on the boundary layer, the closed outlines on the island layers, the points
    where roads meet the boundary on the gate layers and the building entrances on the
    entrance layers (``layers``, a :class:`~lotsim.io.imports.dxf.DxfLayers`; by default
    the layers ``lotsim export --dxf`` writes), in metres from the drawing's ``$INSUNITS``
    (mm, cm, m, in, ft), or from ``units`` when given.

    Needs ``pip install 'lotsim[dxf]'``. Returns a :class:`~lotsim.io.imports.dxf.DxfPlot`
    (the plot, the units read, the boundary's entity and area, what the layers hold that is
    not read, the path written).

    Raises
    ------
    DxfImportError
        (a :class:`~lotsim.errors.LotsimError`) Every problem of the drawing, each naming
        its layer and entity and what was expected; then nothing is written.
    """
    from lotsim.core.atomic import atomic_write
    from lotsim.design.plot_yaml import read_plot
    from lotsim.io.imports.dxf import DxfImportError, read_dxf_plot

    plot = read_dxf_plot(source, layers=layers or DxfLayers(), units=units)
    text = plot.draft.to_yaml()
    try:  # what lotsim layout will read: refused here rather than there
        read_plot(text)
    except ScenarioError as exc:
        raise DxfImportError([f"{source}: the plot read from it is not one lotsim layout "
                              f"takes: {exc}"]) from None
    path = Path(output)
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write(text)
    return dataclasses.replace(plot, path=path)
