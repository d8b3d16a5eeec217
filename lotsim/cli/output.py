"""What every command shares: exit codes, one-line errors on stderr, the words of the
one-screen summary, and the checks of sizes and output file names given as options."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from pathlib import Path

from lotsim import api

EXIT_OK, EXIT_INCOMPLETE, EXIT_BAD_INPUT = 0, 1, 2
EXIT_INTERRUPTED = 130
"""Ctrl-C: 128 + SIGINT, as a shell reports it."""

OPTIONS = {"assignment": "--assignment", "start": "--from", "end": "--to",
           "max_violations": "--max", "path": "-o", "workers": "--jobs",
           "car": ("--vehicle", "--car")}
"""Setting (:mod:`lotsim.sim.settings`, :mod:`lotsim.api` keyword) → the option that sets it,
where the two are not named alike (several: the option and its aliases)."""


def option(name: str, argv: Sequence[str] = ()) -> str:
    """The option that sets the setting ``name``: ``window`` → ``--window``; of an option
    and its aliases, the one the command line ``argv`` gave (``car`` → ``--vehicle`` or
    ``--car``), else the first.

    >>> option("window"), option("car"), option("car", ["minslot", "--car=van"])
    ('--window', '--vehicle', '--car')
    """
    names = OPTIONS.get(name, "--" + name.replace("_", "-"))
    if isinstance(names, str):
        return names
    typed = {a.split("=", 1)[0] for a in argv}
    return next((n for n in names if n in typed), names[0])


def bad(message: str) -> int:
    """Say what is wrong on stderr, as ``lotsim: message``; the exit code of bad input."""
    print(f"lotsim: {message}", file=sys.stderr)
    return EXIT_BAD_INPUT


def cannot_write(path: str | os.PathLike, exc: OSError) -> int:
    """``lotsim: PATH: cannot write: why``; the exit code of bad input."""
    return bad(f"{path}: cannot write: {exc.strerror or exc}")


def plural(count: int, one: str, many: str | None = None) -> str:
    """``1 search``, ``3 searches``."""
    return f"{count} {one if count == 1 else many or one + 's'}"


def sizes() -> str:
    """The picture sizes every ``--size`` accepts, for the options' help."""
    return f"{api.MIN_SIZE[0]}x{api.MIN_SIZE[1]} to {api.MAX_SIZE[0]}x{api.MAX_SIZE[1]}"


def picture_size(text: str) -> tuple[int, int] | str:
    """``--size WxH`` as ``(w, h)`` pixels, or what is wrong with it (the same limits for
    every picture: :func:`lotsim.scenario.size_problem`)."""
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        return f"--size: expected WxH in pixels, such as 800x600, found {text!r}"
    problem = api.size_problem((w, h))
    return f"--size: {problem}" if problem else (w, h)


def name_problem(opt: str, path: str, suffix: str) -> str | None:
    """What is wrong with the name of an output file given to option ``opt`` (None if
    nothing): it must end in ``suffix``. Whether it can be written is for the command's
    :class:`~lotsim.core.atomic.OutputSet` to find, which makes a missing folder."""
    if Path(path).suffix.lower() != suffix:
        return f"{opt}: expected a file name ending in {suffix}, found {path!r}"
    return None


def output_problem(opt: str, path: str, suffix: str) -> str | None:
    """:func:`name_problem`, and the file's folder must exist (for a command that writes
    its file itself, not through an :class:`~lotsim.core.atomic.OutputSet`)."""
    problem = name_problem(opt, path, suffix)
    if problem is None and not Path(path).parent.is_dir():
        return f"{opt}: folder {str(Path(path).parent)!r} does not exist"
    return problem


def given(opt: str, path: str | os.PathLike) -> str:
    """An output as the user gave it, for errors: ``-o runs/x``."""
    return f"{opt} {os.fspath(path)}"


def into_folder(path: str, name: str) -> str:
    """``-o`` of a command that writes one file: a folder (one that exists, or a name ending
    in ``/``) gets the file ``name`` in it, as ``-o`` of ``run`` names the folder it writes
    into; anything else is the file itself."""
    if path.endswith(("/", os.sep)) or Path(path).is_dir():
        return str(Path(path) / name)
    return path


def located(exc) -> str:
    """A :class:`~lotsim.errors.ScenarioError` for stderr: ``lotsim: file:line:col: ...``,
    a line for each of several problems."""
    return problem_lines(getattr(exc, "errors", (exc,)))


def problem_lines(problems) -> str:
    """Located problems (or errors) for stderr, a ``lotsim: ...`` line each."""
    return "\n".join(f"lotsim: {p}" for p in problems)
