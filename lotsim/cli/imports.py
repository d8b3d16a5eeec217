"""``lotsim import``: lots from other sources as scenario files (``docs/import.md``)."""

from __future__ import annotations

import argparse
import sys

from lotsim import api
from lotsim.cli.output import EXIT_INCOMPLETE, EXIT_OK, bad
from lotsim.errors import LotsimError, SettingsError

HELP = "turn the parking lots of an OpenStreetMap file into scenarios (docs/import.md)"
EXITS = ("0 at least one lot written (each lot's line says written or skipped, and why); "
         "1 no lot written; 2 bad input")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("format", choices=("osm",),
                        help="osm: an OpenStreetMap extract, .osm (.gz, .bz2) or .osm.pbf "
                        "(pip install 'lotsim[osm]')")
    parser.add_argument("source", metavar="FILE", help="the file to read")
    parser.add_argument("-o", "--output", metavar="DIR", required=True,
                        help="the folder the scenarios are written to (made if missing), "
                        "one per lot")
    parser.add_argument("--lot", metavar="ID", action="append",
                        help="import only this lot: way/123, relation/9, node/5 or the number "
                        "(may be given again)")


def execute(args: argparse.Namespace) -> int:
    def progress(line: str) -> None:  # each lot as it is done, where a user is watching
        if sys.stderr.isatty():
            print(line, file=sys.stderr, flush=True)

    try:
        report = api.import_osm(args.source, args.output, lots=args.lot, progress=progress)
    except SettingsError:
        raise
    except LotsimError as exc:
        return bad(str(exc))
    except OSError as exc:
        return bad(f"{exc.filename or args.source}: {exc.strerror}")
    print(report.text())
    return EXIT_OK if report.written else EXIT_INCOMPLETE
