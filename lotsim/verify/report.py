"""What the checker reports: :class:`Violation`, :class:`CheckReport`, and how a stage
records one (a failure of the checker itself becomes an ``internal`` violation)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar


@dataclass(frozen=True, slots=True)
class Violation:
    """One broken rule.

    Attributes
    ----------
    rule : str
        Short tag, one of :data:`RULES`.
    vehicle : str or None
        Id of the vehicle concerned (the first one of a pair), None for the whole file.
    t : float or None
        When it happens [s], None when it is not tied to a time.
    message : str
        One line a person understands.
    """

    rule: str
    vehicle: str | None
    t: float | None
    message: str

    def __str__(self) -> str:
        return f"{self.rule}: {self.message}"


@dataclass
class CheckReport:
    """What :func:`check_result` found.

    Attributes
    ----------
    violations : list of Violation
        The first violations (at most ``max_violations``), by rule, then time.
    stats : dict
        ``vehicles``, ``vehicles_checked``, ``samples``, ``intervals`` (consecutive sample
        pairs), ``instants`` (common instants), ``footprints`` (distinct footprints:
        one per moving vehicle-instant, one per standing stretch), ``vehicle_instants``,
        ``footprint_tests`` (exact rectangle and polygon tests), ``violations`` (all
        found, also those left out of the list) and ``seconds`` (checking time).
    """

    violations: list[Violation]
    stats: dict

    @property
    def ok(self) -> bool:
        """True when no rule is broken."""
        return not self.violations and not self.stats.get("violations", 0)

    def summary(self) -> str:
        """One line: what was checked and how many violations were found."""
        s = self.stats
        what = (f"{s.get('vehicles_checked', 0)} of {s.get('vehicles', 0)} vehicles, "
                f"{s.get('samples', 0)} samples, {s.get('instants', 0)} instants")
        if self.ok:
            return f"ok: {what}"
        total = s.get("violations", len(self.violations))
        shown = "" if total == len(self.violations) else f" (first {len(self.violations)})"
        return f"{total} violation{'s' if total != 1 else ''}{shown}: {what}"


_T = TypeVar("_T")


def _add(out: list[Violation], rule: str, vehicle: str | None, t: float | None,
         message: str) -> None:
    out.append(Violation(rule, vehicle, None if t is None else float(t), message))


def _guard(out: list[Violation], what: str, fn: Callable[..., _T], *args: Any) -> _T | None:
    """Run one stage; a failure of the checker becomes an ``internal`` violation."""
    try:
        return fn(*args)
    except Exception as exc:  # the checker must never raise on its input
        _add(out, "internal", None, None,
             f"the checker failed on {what}: {type(exc).__name__}: {exc}")
        return None
