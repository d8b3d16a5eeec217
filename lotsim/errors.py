"""Typed errors of lotsim.

A user's mistake is a :class:`ScenarioError` (exit code 2, no traceback); the
CLI prints ``str(error)``, which starts with ``path:line:col:``.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Location:
    """Where a value sits in an input file.

    ``line`` and ``col`` are 1-based, as editors show them; ``key`` is the
    dotted path of the value in the document, e.g. ``lot.rows[1].angle_deg``.
    """

    file: str
    line: int
    col: int
    key: str = ""

    def __str__(self) -> str:
        head = f"{self.file}:{self.line}:{self.col}"
        return f"{head}: {self.key}" if self.key else head


class LotsimError(Exception):
    """Base class of every error lotsim raises on purpose."""


class ScenarioError(LotsimError):
    """A problem in a user's input, located in the file it came from.

    Parameters
    ----------
    where : Location or None
        The file position and key path of the offending value; ``None`` when
        the problem has no single place (the message then says why).
    message : str
        What was expected and what was found.
    """

    def __init__(self, where: Location | None, message: str):
        self.where = where
        self.message = message
        super().__init__(f"{where}: {message}" if where is not None else message)


class InfeasibleManeuver(LotsimError):
    """A vehicle type cannot enter or leave a slot."""
