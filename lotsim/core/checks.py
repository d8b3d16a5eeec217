"""Checks that settings objects run on construction: each returns the message of a
problem, or None, so that every caller (Python, the CLI, the bench suite reader) gets the
same checks and the same messages, raised as :class:`~lotsim.errors.SettingsError`."""

from __future__ import annotations

import difflib
import math
import numbers
from collections.abc import Sequence
from dataclasses import fields
from typing import Any

from lotsim.errors import SettingsError


def is_real(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def is_integral(value: Any) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def number_text(x: float) -> str:
    """``600``, ``0.01``, ``1000000``, ``inf``."""
    if math.isfinite(x) and float(x).is_integer() and abs(x) < 1e15:
        return str(int(x))
    return f"{x:g}"


def shown(value: Any) -> str:
    return number_text(value) if is_real(value) else repr(value)


def choice_problem(value: Any, choices: Sequence[str]) -> str | None:
    if isinstance(value, str) and value in choices:
        return None
    close = difflib.get_close_matches(value, choices, n=1) if isinstance(value, str) else []
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    return f"expected one of {', '.join(choices)}, found {value!r}{hint}"


def range_problem(value: Any, lo: float, hi: float, unit: str = "", *, integer: bool = False
           ) -> str | None:
    """``expected lo to hi unit, found value`` unless ``lo ≤ value ≤ hi`` (finite)."""
    if not (is_integral(value) if integer else is_real(value)):
        return f"expected {'an integer' if integer else 'a number'}, found {value!r}"
    if math.isfinite(value) and lo <= value <= hi:
        return None
    return f"expected {number_text(lo)} to {number_text(hi)}{unit}, found {shown(value)}"


def raise_first(problems: list[tuple[str, str]]) -> None:
    if problems:
        raise SettingsError(*problems[0])


def set_field(obj: object, name: str, value: Any) -> None:
    """Normalise a field of a frozen dataclass while it is being built (an int window to a
    float, a list order to a tuple): the same settings then write the same result."""
    object.__setattr__(obj, name, value)


def names(cls: type) -> tuple[str, ...]:
    """The field names of a settings dataclass, e.g. for ``**overrides``."""
    return tuple(f.name for f in fields(cls))


def replace(settings: Any, overrides: dict[str, Any]) -> Any:
    """``settings`` with ``overrides`` (field → value), checked; an unknown field is a
    :class:`~lotsim.errors.SettingsError` that names the fields there are.

    >>> from lotsim.sim.settings import RunSettings
    >>> replace(RunSettings(), {"windw": 5})
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: windw: no such setting of RunSettings (did you mean 'window'?)
    """
    known = names(type(settings))
    for key in overrides:
        if key not in known:
            close = difflib.get_close_matches(key, known, n=1)
            hint = (f" (did you mean {close[0]!r}?)" if close
                    else f"; expected one of {', '.join(known)}")
            raise SettingsError(key, f"no such setting of {type(settings).__name__}{hint}")
    if not overrides:
        return settings
    values = {f.name: getattr(settings, f.name) for f in fields(settings)}
    return type(settings)(**{**values, **overrides})
