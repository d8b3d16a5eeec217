"""The ``lotsim`` command line: one module per command, each calling only :mod:`lotsim.api`.

Exit codes: 0 ok, 1 incomplete (something could not be planned or reached, with
``--strict``), 2 bad input, or a run stopped by its memory or time limit. Errors go to
stderr as ``file:line:col: key: message``; results go to files; a one-screen summary goes
to stdout.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence

from lotsim.cli.output import EXIT_BAD_INPUT, EXIT_INTERRUPTED, bad, located, option
from lotsim.cli.parser import COMMANDS, build_parser
from lotsim.errors import OutputError, ScenarioError, SettingsError

EXIT_BROKEN_PIPE = 141
"""stdout closed before the summary was all written (``lotsim ... | head``): 128 + SIGPIPE."""


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; returns the exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(argv)
    args, extra = parser.parse_known_args(argv)
    if extra:  # the command's usage, not lotsim's
        parser.commands[args.command].error(f"unrecognized arguments: {' '.join(extra)}")
    try:
        return COMMANDS[args.command].execute(args)
    except ScenarioError as exc:
        print(located(exc), file=sys.stderr)
        return EXIT_BAD_INPUT
    except OutputError as exc:  # an output that cannot be written, found before the work
        return bad(str(exc))
    except SettingsError as exc:  # the library's check of an option: name the option
        return bad(f"{option(exc.name, argv)}: {exc.message}")
    except KeyboardInterrupt:
        print("lotsim: interrupted; nothing was written", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # stdout closed early (| head): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
