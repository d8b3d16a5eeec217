"""``lotsim import``: lots from other sources as scenario files, and plots drawn in CAD as
plot files (``docs/import.md``)."""

from __future__ import annotations

import argparse
import sys

from lotsim import api
from lotsim.cli.output import (
    EXIT_BAD_INPUT,
    EXIT_INCOMPLETE,
    EXIT_OK,
    bad,
    cannot_write,
    given,
    into_folder,
    name_problem,
    problem_lines,
)
from lotsim.errors import LotsimError, SettingsError

HELP = ("turn OpenStreetMap parking lots or a Lanelet2 valet-parking map into scenarios, or "
        "a plot drawn in CAD (DXF) into a plot file for lotsim layout (docs/import.md)")
EXITS = ("0 at least one lot written (each lot's line says written or skipped, and why), or "
         "the plot written; 1 no lot written; 2 bad input")
UNITS = ("mm", "cm", "m", "in", "ft")
"""The units ``--units`` takes (:data:`lotsim.io.imports.dxf.UNITS`)."""
DXF_OPTIONS = ("boundary_layer", "island_layer", "gate_layer", "entrance_layer", "units")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("format", choices=("osm", "lanelet2", "dxf"),
                        help="osm: an OpenStreetMap extract, .osm (.gz, .bz2) or .osm.pbf "
                        "(pip install 'lotsim[osm]'); lanelet2: a Lanelet2 map (OSM XML) in "
                        "Autoware's valet-parking convention; dxf: a plot drawn in CAD "
                        "(pip install 'lotsim[dxf]')")
    parser.add_argument("source", metavar="FILE", help="the file to read")
    parser.add_argument("-o", "--output", metavar="DIR", required=True,
                        help="osm, lanelet2: the folder the scenarios are written to (made if "
                        "missing), one per lot; dxf: the plot file to write (PLOT.yaml; a "
                        "folder gets NAME.plot.yaml)")
    parser.add_argument("--lot", metavar="ID", action="append",
                        help="osm: import only this lot: way/123, relation/9, node/5 or the "
                        "number (may be given again)")
    parser.add_argument("--layout", action="store_true",
                        help="osm: lay out the lots that map no aisles with lotsim layout "
                        "(their plots written beside, as NAME.plot.yaml; docs/layout.md)")
    parser.add_argument("--origin", metavar="LAT,LON",
                        help="lanelet2: where local metres start (default: the map's own, from "
                        "Autoware's map_config YAML beside it, else the middle of its nodes)")
    layers = api.DxfLayers()
    parser.add_argument("--boundary-layer", metavar="LAYER",
                        help=f"dxf: the layer of the plot's one closed outline (default "
                        f"{layers.boundary})")
    parser.add_argument("--island-layer", metavar="LAYER", action="append",
                        help=f"dxf: a layer of islands to keep clear, closed outlines (may be "
                        f"given again; default {', '.join(layers.islands)})")
    parser.add_argument("--gate-layer", metavar="LAYER", action="append",
                        help=f"dxf: a layer of gates, points on the boundary where roads meet "
                        f"it (may be given again; default {', '.join(layers.gates)})")
    parser.add_argument("--entrance-layer", metavar="LAYER", action="append",
                        help=f"dxf: a layer of building entrances, points (may be given again; "
                        f"default {', '.join(layers.entrances)})")
    parser.add_argument("--units", choices=UNITS,
                        help="dxf: the drawing's units, over its $INSUNITS (needed when it "
                        "has none)")


def _origin(text: str) -> tuple[float, float]:
    try:
        lat, lon = (float(v) for v in text.split(","))
    except ValueError:
        raise SettingsError("origin", f"expected LAT,LON in degrees, found {text!r}") from None
    if not (-90 <= lat <= 90 and -180 <= lon <= 180):
        raise SettingsError("origin", f"expected a latitude within ±90 and a longitude "
                            f"within ±180, found {text!r}")
    return lat, lon


def execute(args: argparse.Namespace) -> int:
    def progress(line: str) -> None:  # each lot as it is done, where a user is watching
        if sys.stderr.isatty():
            print(line, file=sys.stderr, flush=True)

    if args.format == "dxf":
        return _dxf(args)
    given_dxf = [o for o in DXF_OPTIONS if getattr(args, o) is not None]
    if given_dxf:
        return bad(f"import {args.format}: --{given_dxf[0].replace('_', '-')} is for DXF "
                   f"drawings (lotsim import dxf)")

    if args.format == "osm" and args.origin:
        return bad("import osm: --origin is for Lanelet2 maps (each OpenStreetMap lot's "
                   "metres start at its own middle)")
    if args.format == "lanelet2" and args.layout:
        return bad("import lanelet2: --layout is for OpenStreetMap lots without aisles (a "
                   "Lanelet2 map draws its lanes)")
    if args.format == "lanelet2" and args.lot:
        return bad("import lanelet2: --lot is for OpenStreetMap files (a Lanelet2 map is "
                   "one lot)")
    try:
        if args.format == "osm":
            report = api.import_osm(args.source, args.output, lots=args.lot,
                                    layout=args.layout, progress=progress)
        else:
            report = api.import_lanelet2(args.source, args.output, progress=progress,
                                         origin=_origin(args.origin) if args.origin else None)
    except SettingsError:
        raise
    except LotsimError as exc:
        return bad(str(exc))
    except OSError as exc:
        return bad(f"{exc.filename or args.source}: {exc.strerror}")
    print(report.text())
    return EXIT_OK if report.written else EXIT_INCOMPLETE


def _dxf(args: argparse.Namespace) -> int:
    """``lotsim import dxf PLOT.dxf -o PLOT.yaml``."""
    for option in ("lot", "layout", "origin"):
        if getattr(args, option):
            return bad(f"import dxf: --{option} is for "
                       f"{'Lanelet2 maps' if option == 'origin' else 'OpenStreetMap files'}")
    from pathlib import Path

    output = into_folder(args.output, f"{Path(args.source).stem}.plot.yaml")
    problem = name_problem("-o", output, ".yaml")
    if problem:
        return bad(problem)
    usual = api.DxfLayers()
    layers = api.DxfLayers(boundary=args.boundary_layer or usual.boundary,
                           islands=tuple(args.island_layer or usual.islands),
                           gates=tuple(args.gate_layer or usual.gates),
                           entrances=tuple(args.entrance_layer or usual.entrances))
    with api.OutputSet() as outputs:  # nothing written unless the whole plot is read
        staged = outputs.file(output, name=given("-o", output))
        try:
            plot = api.import_dxf(args.source, staged, layers=layers, units=args.units)
        except SettingsError:
            raise
        except LotsimError as exc:
            print(problem_lines(getattr(exc, "errors", None) or (str(exc),)),
                  file=sys.stderr)
            return EXIT_BAD_INPUT
        except OSError as exc:
            return cannot_write(given("-o", output), exc)
        outputs.commit()
    print(f"{args.source}: {plot.line()}: wrote {output}")
    if plot.ignored:
        print(f"not read (a plot holds none of these): {', '.join(plot.ignored)}")
    return EXIT_OK
