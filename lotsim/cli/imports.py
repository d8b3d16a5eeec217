"""``lotsim import``: lots from other sources as scenario files (``docs/import.md``)."""

from __future__ import annotations

import argparse
import sys

from lotsim import api
from lotsim.cli.output import EXIT_INCOMPLETE, EXIT_OK, bad
from lotsim.errors import LotsimError, SettingsError

HELP = ("turn OpenStreetMap parking lots or a Lanelet2 valet-parking map into scenarios "
        "(docs/import.md)")
EXITS = ("0 at least one lot written (each lot's line says written or skipped, and why); "
         "1 no lot written; 2 bad input")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("format", choices=("osm", "lanelet2"),
                        help="osm: an OpenStreetMap extract, .osm (.gz, .bz2) or .osm.pbf "
                        "(pip install 'lotsim[osm]'); lanelet2: a Lanelet2 map (OSM XML) in "
                        "Autoware's valet-parking convention")
    parser.add_argument("source", metavar="FILE", help="the file to read")
    parser.add_argument("-o", "--output", metavar="DIR", required=True,
                        help="the folder the scenarios are written to (made if missing), "
                        "one per lot")
    parser.add_argument("--lot", metavar="ID", action="append",
                        help="osm: import only this lot: way/123, relation/9, node/5 or the "
                        "number (may be given again)")
    parser.add_argument("--layout", action="store_true",
                        help="osm: lay out the lots that map no aisles with lotsim layout "
                        "(their plots written beside, as NAME.plot.yaml; docs/layout.md)")
    parser.add_argument("--origin", metavar="LAT,LON",
                        help="lanelet2: where local metres start (default: the map's own, from "
                        "Autoware's map_config YAML beside it, else the middle of its nodes)")


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
