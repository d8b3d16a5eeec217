"""Length units a scenario or plot file may give its lengths in (``units: ft``), and a
length as a person reads it in them. lotsim works in metres inside; a file's unit says
how it reads its lengths and how lotsim reports them back.

>>> shown_length(3.048, "ft"), shown_length(6.7, "m", ".1f"), shown_area(9.290304, "ft")
('10 ft', '6.7 m', '100.0 ft²')
"""

from __future__ import annotations

FOOT = 0.3048
"""The international foot [m], exactly."""
LENGTH_UNITS = {"m": 1.0, "ft": FOOT}
"""The length units a file may state (``units: ft``) and their size [m]."""


def in_units(metres: float, units: str) -> float:
    """A length [m] as a number of ``units``."""
    return metres / LENGTH_UNITS[units]


def shown_length(metres: float, units: str, spec: str = "g") -> str:
    """A length [m] as a person reads it in ``units``: ``shown_length(3.048, "ft")`` is
    ``'10 ft'``."""
    return f"{in_units(metres, units):{spec}} {units}"


def shown_area(square_metres: float, units: str, spec: str = ".1f") -> str:
    """An area [m²] in square ``units``: ``'120.9 m²'``, ``'1301.4 ft²'``."""
    return f"{square_metres / LENGTH_UNITS[units] ** 2:{spec}} {units}²"
