"""The ``lotsim`` argument parser: one sub-command per module of :mod:`lotsim.cli`, each
adding its own arguments (``add_arguments``) and saying what it does (``HELP``) and what its
exit codes mean (``EXITS``)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from lotsim import api
from lotsim.cli import (
    bench,
    cars,
    check,
    export,
    imports,
    layout,
    maneuver,
    minslot,
    render,
    run,
    show,
    validate,
)
from lotsim.cli.output import EXIT_BAD_INPUT

COMMANDS = {"cars": cars, "validate": validate, "minslot": minslot, "maneuver": maneuver,
            "run": run, "render": render, "check": check, "show": show, "bench": bench,
            "export": export, "import": imports, "layout": layout}
"""Command name → its module (``HELP``, ``EXITS``, ``add_arguments``, ``execute``), in the
order ``lotsim --help`` lists them."""


class Parser(argparse.ArgumentParser):
    """argparse that exits with 2 and a one-line message, as every other bad input does."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


def build_parser(argv: Sequence[str] | None = None) -> Parser:
    """The whole command line; ``.commands`` maps each command's name to its own parser
    (for errors in the command's own words).

    Given the command line ``argv``, only the command it names gets its arguments (every
    command keeps its name and help for ``lotsim --help``): some commands take their
    defaults from the library, and a quick command need not import what another needs."""
    named = _named(argv)
    p = Parser(prog="lotsim", description="Plan many car-like vehicles in a parking lot.",
               epilog="exit codes: 0 ok, 1 incomplete (something could not be planned, "
               "reached or checked), 2 bad input, 130 interrupted; 'lotsim COMMAND --help' "
               "says what each command does and its own")
    p.add_argument("--version", action="version", version=f"lotsim {api.__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=Parser,
                           metavar="COMMAND")
    for name, module in COMMANDS.items():
        command = sub.add_parser(name, help=module.HELP,
                                 description=module.HELP[0].upper() + module.HELP[1:],
                                 epilog=f"exit codes: {module.EXITS}")
        if argv is None or name == named:
            module.add_arguments(command)
    p.commands = sub.choices
    return p


def _named(argv: Sequence[str] | None) -> str | None:
    """The command ``argv`` names (its first word that is not an option), if any."""
    word = next((a for a in argv or () if not a.startswith("-")), None)
    return word if word in COMMANDS else None
