"""``lotsim export``: a result.json in other tools' formats (``docs/export.md``)."""

from __future__ import annotations

import argparse
import time

from lotsim import api
from lotsim.cli.output import EXIT_OK, bad, cannot_write, given
from lotsim.errors import LotsimError, SettingsError

HELP = "write a result.json as CommonRoad, SUMO or OpenSCENARIO files (docs/export.md)"
EXITS = ("0 written; 2 bad input, a result that cannot be exported, or the format's "
         "packages missing")

FORMATS = ("commonroad", "sumo", "openscenario")
"""The formats of ``lotsim export``, each an option and an ``api.export_<name>``."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("result", metavar="RESULT_JSON", help="a result.json of lotsim run")
    parser.add_argument("--commonroad", metavar="DIR", help="CommonRoad scenarios and KS "
                        "solutions, one per trip (pip install 'lotsim[commonroad]')")
    parser.add_argument("--sumo", metavar="DIR", help="a SUMO network, a parking area per "
                        "slot and a trip per car, with lot.sumocfg (pip install "
                        "'lotsim[sumo]')")
    parser.add_argument("--openscenario", metavar="DIR", help="OpenSCENARIO (a timed "
                        "trajectory per car) on an OpenDRIVE lot with a parking space per "
                        "slot (pip install 'lotsim[openscenario]')")


def execute(args: argparse.Namespace) -> int:
    asked = [(name, getattr(args, name)) for name in FORMATS if getattr(args, name)]
    if not asked:
        return bad(f"export: give at least one of "
                   f"{', '.join(f'--{name} DIR' for name in FORMATS)}")
    try:
        doc = api.load_result(args.result)
    except LotsimError as exc:
        return bad(str(exc))
    except OSError as exc:
        return bad(f"{exc.filename or args.result}: {exc.strerror}")
    said = []
    with api.OutputSet() as outputs:  # checked before the work, written whole or not at all
        staged = [(name, folder, outputs.folder(folder, name=given(f"--{name}", folder)))
                  for name, folder in asked]
        for name, folder, into in staged:
            start = time.perf_counter()
            try:
                info = getattr(api, f"export_{name}")(doc, into)
            except SettingsError:
                raise
            except LotsimError as exc:
                return bad(str(exc))
            except OSError as exc:
                return cannot_write(given(f"--{name}", folder), exc)
            said.append(f"{name}: wrote {folder} ({info.bytes / 1e6:.1f} MB, "
                        f"{time.perf_counter() - start:.1f} s)")
        outputs.commit()
    print("\n".join(said))
    return EXIT_OK
