"""Lots from other sources as scenario files (``lotsim import``, ``docs/import.md``):
OpenStreetMap extracts and Lanelet2 maps in Autoware's valet-parking convention."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence

from lotsim.io.imports.report import ImportReport


def import_osm(source: str | os.PathLike, folder: str | os.PathLike, *,
               lots: Sequence[str] | None = None,
               progress: Callable[[str], None] | None = None) -> ImportReport:
    """Write each parking lot of an OpenStreetMap file (``.osm`` XML or ``.osm.pbf``) as a
    scenario in ``folder`` (``lotsim import osm``, ``docs/import.md``): the lot's outline,
    its parking aisles, gates where a road reaches them, its mapped spaces or bays laid out
    along the aisles, what is paved, and a default traffic. ``lots`` picks lots by id
    (``way/123``, ``relation/9``, or the number); ``progress`` is told of each lot.

    Reading ``.osm.pbf`` needs ``pip install 'lotsim[osm]'``. Returns the
    :class:`~lotsim.io.imports.report.ImportReport`: per lot, written (where) or skipped
    (why), with its figures. Raises :class:`~lotsim.errors.LotsimError` on a file that is
    not OpenStreetMap.
    """
    from lotsim.io.imports.osm import import_osm as run

    return run(source, folder, lots=lots, progress=progress)


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
