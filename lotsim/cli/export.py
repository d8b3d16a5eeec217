"""``lotsim export``: a result.json in other tools' formats, and a lot as a DXF drawing for
CAD (``docs/export.md``)."""

from __future__ import annotations

import argparse
import time

from lotsim import api
from lotsim.cli.output import EXIT_OK, bad, cannot_write, given, name_problem
from lotsim.errors import LotsimError, SettingsError

HELP = ("write a result.json as CommonRoad, SUMO or OpenSCENARIO files, or the lot of a "
        "scenario or a result as a DXF drawing for CAD (docs/export.md)")
EXITS = ("0 written; 2 bad input, a result that cannot be exported, or the format's "
         "packages missing")

FORMATS = ("commonroad", "sumo", "openscenario")
"""The formats of a run, each an option ``--<name> DIR`` and an ``api.export_<name>``."""
DXF_UNITS = ("m", "ft")
"""The units ``--dxf-units`` takes (:data:`lotsim.io.export.dxf.DRAWING_UNITS`)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("result", metavar="FILE", help="a result.json of lotsim run; for "
                        "--dxf alone also a scenario (its lot, built as lotsim show builds "
                        "it)")
    parser.add_argument("--commonroad", metavar="DIR", help="CommonRoad scenarios and KS "
                        "solutions, one per trip (pip install 'lotsim[commonroad]')")
    parser.add_argument("--sumo", metavar="DIR", help="a SUMO network, a parking area per "
                        "slot and a trip per car, with lot.sumocfg (pip install "
                        "'lotsim[sumo]')")
    parser.add_argument("--openscenario", metavar="DIR", help="OpenSCENARIO (a timed "
                        "trajectory per car) on an OpenDRIVE lot with a parking space per "
                        "slot (pip install 'lotsim[openscenario]')")
    parser.add_argument("--dxf", metavar="LOT.dxf", help="the lot as a DXF drawing in "
                        "the scenario's units (a result's in metres), each kind of thing on "
                        "its named layer: boundary, aisles, bays, stripes, bay numbers, "
                        "islands, gates (pip install 'lotsim[dxf]')")
    parser.add_argument("--dxf-units", choices=DXF_UNITS, help="--dxf: draw in metres or "
                        "feet, whatever the scenario's units")


def execute(args: argparse.Namespace) -> int:
    asked = [(name, getattr(args, name)) for name in FORMATS if getattr(args, name)]
    if args.dxf_units and not args.dxf:
        return bad("export: --dxf-units is for the drawing of --dxf LOT.dxf")
    if not asked and not args.dxf:
        return bad(f"export: give at least one of "
                   f"{', '.join(f'--{name} DIR' for name in FORMATS)} or --dxf LOT.dxf")
    if args.dxf:
        problem = name_problem("--dxf", args.dxf, ".dxf")
        if problem:
            return bad(problem)
    source = args.result
    if asked:  # a run's formats read the result; --dxf then draws that result's lot
        try:
            source = api.load_result(args.result)
        except LotsimError as exc:
            return bad(str(exc))
        except OSError as exc:
            return bad(f"{exc.filename or args.result}: {exc.strerror}")
    said = []
    with api.OutputSet() as outputs:  # checked before the work, written whole or not at all
        staged = [(name, folder, outputs.folder(folder, name=given(f"--{name}", folder)))
                  for name, folder in asked]
        if args.dxf:
            staged.append(("dxf", args.dxf, outputs.file(args.dxf,
                                                         name=given("--dxf", args.dxf))))
        for name, target, into in staged:
            start = time.perf_counter()
            try:
                info = (api.export_dxf(source, into, units=args.dxf_units) if name == "dxf"
                        else getattr(api, f"export_{name}")(source, into))
            except SettingsError:
                raise
            except LotsimError as exc:
                return bad(str(exc))
            except OSError as exc:
                return cannot_write(given(f"--{name}", target), exc)
            what = (f"{info.bays} bays, {info.bytes / 1e3:.0f} kB, in "
                    f"{'feet' if info.units == 'ft' else 'metres'}" if name == "dxf"
                    else f"{info.bytes / 1e6:.1f} MB")
            said.append(f"{name}: wrote {target} ({what}, "
                        f"{time.perf_counter() - start:.1f} s)")
        outputs.commit()
    print("\n".join(said))
    return EXIT_OK
