"""One convention for how every search in lotsim ends: a :class:`Status` and, with it,
either the value found or the reason there is none.

The maneuver searches (one car into one slot), the turnaround and multi-point searches of
the roadmap and the cooperative space-time search all answer with an :class:`Outcome`, so a
caller asks ``outcome.found`` and reads ``outcome.value`` or ``outcome.reason`` the same way
everywhere, instead of telling ``None`` from a string from a list.

Examples
--------
>>> Outcome.of(3.5).found, Outcome.of(3.5).value
(True, 3.5)
>>> no = Outcome.failed(Status.INFEASIBLE, "no way in with up to 8 direction changes")
>>> no.found, no.status.value, no.reason
(False, 'infeasible', 'no way in with up to 8 direction changes')
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import Generic, TypeVar

T = TypeVar("T")


class Status(Enum):
    """How a search ended."""

    FOUND = "found"
    """It found what it looked for: the outcome holds the value."""
    INFEASIBLE = "infeasible"
    """What was asked cannot be done (the car does not fit, every way is blocked)."""
    OUT_OF_BUDGET = "out of budget"
    """It stopped at its budget (expansions: the expansion limit) before finding or ruling out."""
    NO_PATH = "no path"
    """It searched everything it may and found no way."""


@dataclass(frozen=True, slots=True)
class Outcome(Generic[T]):
    """How a search ended: ``status``, and ``value`` when found, else ``reason``.

    Attributes
    ----------
    status : Status
    value : T or None
        What was found (None unless ``status`` is :attr:`Status.FOUND`).
    reason : str
        Why nothing was found, in words a user can act on ("" when found).
    """

    status: Status
    value: T | None = None
    reason: str = ""

    def __post_init__(self) -> None:
        if (self.status is Status.FOUND) != (self.value is not None):
            raise ValueError("an outcome holds a value exactly when it is found")

    @property
    def found(self) -> bool:
        """Whether the search found its value."""
        return self.status is Status.FOUND

    @classmethod
    def of(cls, value: T) -> Outcome[T]:
        """A search that found ``value``."""
        return cls(Status.FOUND, value)

    @classmethod
    def failed(cls, status: Status, reason: str) -> Outcome[T]:
        """A search that ended with ``status`` (not FOUND) for ``reason``."""
        if status is Status.FOUND:
            raise ValueError("a failed outcome cannot be FOUND")
        return cls(status, None, reason)
