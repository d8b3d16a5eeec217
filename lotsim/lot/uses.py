"""Bays by use: standard, compact, accessible, van-accessible, EV, motorcycle — one closed
registry, :data:`USES`, with each use's least size, its access aisle, and the rule of which
vehicle types may park in a bay of it (``docs/scenario.md``).

The sizes of accessible bays are the US 2010 ADA Standards' (§502.2, §502.3): a car space
at least 96 in (2.44 m) wide, a van space at least 132 in (3.35 m) wide, or 96 in with an
access aisle of 96 in; an access aisle at least 60 in (1.52 m) wide over the bay's full
length, which two bays may share. Widths are to the centrelines of the markings.

Examples
--------
>>> list(USES)
['standard', 'compact', 'accessible', 'van_accessible', 'ev', 'motorcycle']
>>> round(USES["accessible"].least_aisle(2.5), 3), round(USES["van_accessible"].least_aisle(2.5), 3)
(1.524, 2.438)
>>> USES["van_accessible"].least_aisle(3.4) == ACCESS_AISLE
True
>>> USES["standard"].least_aisle(2.5) is None
True
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Protocol

INCH = 0.0254
"""One inch [m]."""
ACCESSIBLE_WIDTH = 96 * INCH
"""Least width of an accessible car space, ADA 2010 §502.2 [m] (96 in)."""
VAN_WIDTH = 132 * INCH
"""Least width of a van space with a 60 in access aisle, ADA 2010 §502.2 [m] (132 in)."""
ACCESS_AISLE = 60 * INCH
"""Least width of an access aisle, ADA 2010 §502.3.1 [m] (60 in)."""
VAN_AISLE = 96 * INCH
"""Least width of the access aisle of a van space narrower than :data:`VAN_WIDTH`, ADA
2010 §502.2 exception [m] (96 in)."""
SIZE_TOL = 5e-4
"""Slack on the least sizes [m]: a width written to the centimetre (2.44 for 96 in) is
not refused for the tenths of a millimetre of the inch."""

MARKS = ("accessible", "ev", "motorcycle")
"""What a vehicle type can be marked as in a scenario (``accessible: true``, ...): the
marks the bays' rules ask for."""


class _TypeLike(Protocol):
    name: str
    width: float
    marks: frozenset[str]

    @property
    def length(self) -> float: ...


@dataclass(frozen=True, slots=True)
class BayUse:
    """What one use of bay decides (one instance per use in :data:`USES`).

    Attributes
    ----------
    name : str
        The use's name in scenario files, results and schedules.
    mark : str or None
        The mark (:data:`MARKS`) a vehicle type needs to park in a bay of this use; None:
        any type may.
    least_width : float
        Least width of a bay of this use [m] (0: no least).
    aisle : float or None
        Least width of the access aisle a bay of this use carries beside it [m]; None: it
        carries none.
    wide : float or None
        The bay width from which :attr:`aisle` suffices; a narrower bay needs an aisle of
        :attr:`narrow_aisle` (a van space).
    narrow_aisle : float or None
        The access aisle a bay narrower than :attr:`wide` needs [m].
    body_fits : bool
        A type whose body is longer or wider than the bay may not use it (a compact bay),
        whether or not a maneuver would squeeze it in.
    """

    name: str
    mark: str | None = None
    least_width: float = 0.0
    aisle: float | None = None
    wide: float | None = None
    narrow_aisle: float | None = None
    body_fits: bool = False

    @property
    def label(self) -> str:
        """The use as a person reads it: ``van-accessible``, ``EV``."""
        return "EV" if self.name == "ev" else self.name.replace("_", "-")

    @property
    def accessible(self) -> bool:
        """A bay of this use counts as an accessible space (it carries an access aisle)."""
        return self.aisle is not None

    def least_aisle(self, width: float) -> float | None:
        """Least width [m] of the access aisle of a bay ``width`` wide [m]; None: none."""
        if self.aisle is None:
            return None
        if self.wide is not None and width < self.wide - SIZE_TOL:
            return self.narrow_aisle
        return self.aisle

    def size_problem(self, width: float, aisle: float | None) -> str | None:
        """What is wrong with a bay of this use ``width`` wide whose access aisle is
        ``aisle`` wide [m] (None: the least), or None."""
        if width < self.least_width - SIZE_TOL:
            return (f"{_a(self.label)} bay is at least {self.least_width:.2f} m wide "
                    f"({self.least_width / INCH:.0f} in), found {width:g} m")
        need = self.least_aisle(width)
        if need is not None and aisle is not None and aisle < need - SIZE_TOL:
            why = (f" (a bay narrower than {self.wide:.2f} m needs the wider aisle)"
                   if self.wide is not None and need == self.narrow_aisle else "")
            return (f"the access aisle of {_a(self.label)} bay {width:g} m wide is at least "
                    f"{need:.2f} m ({need / INCH:.0f} in){why}, found {aisle:g} m")
        return None

    def refusal(self, vehicle: _TypeLike, width: float, length: float) -> str | None:
        """Why ``vehicle``'s type may not park in a bay of this use ``width`` by ``length``
        [m], or None when it may."""
        if self.mark is not None and self.mark not in vehicle.marks:
            return (f"it is {_a(self.label)} bay and {vehicle.name!r} is not marked "
                    f"{self.mark}: true")
        if self.body_fits and (vehicle.length > length + 1e-9 or vehicle.width > width + 1e-9):
            return (f"it is {_a(self.label)} bay of {length:g} × {width:g} m and "
                    f"{vehicle.name!r} is {vehicle.length:.2f} × {vehicle.width:.2f} m")
        return None


def _a(word: str) -> str:
    return f"{'an' if word[0].lower() in 'aeiou' else 'a'} {word}"


STANDARD = "standard"
"""The use of a bay that names none."""

USES: dict[str, BayUse] = {u.name: u for u in (
    BayUse(STANDARD),
    BayUse("compact", body_fits=True),
    BayUse("accessible", mark="accessible", least_width=ACCESSIBLE_WIDTH,
           aisle=ACCESS_AISLE),
    BayUse("van_accessible", mark="accessible", least_width=ACCESSIBLE_WIDTH,
           aisle=ACCESS_AISLE, wide=VAN_WIDTH, narrow_aisle=VAN_AISLE),
    BayUse("ev", mark="ev"),
    BayUse("motorcycle", mark="motorcycle"),
)}
"""Every use of bay by name, in the order scenario files, counts and schedules list them."""


def use_of(name: str) -> BayUse:
    """The use called ``name`` (:data:`USES`); a KeyError naming those there are."""
    try:
        return USES[name]
    except KeyError:
        raise KeyError(f"no use of bay {name!r}: expected one of {', '.join(USES)}") from None


# -- the code's counts ------------------------------------------------------------------------
ADA_2010 = "ADA 2010"
"""The built-in standard: the 2010 ADA Standards for Accessible Design, Table 208.2 and
§208.2.4."""

_ADA_ROWS = ((25, 1), (50, 2), (75, 3), (100, 4), (150, 5), (200, 6), (300, 7), (400, 8),
             (500, 9))


def ada_accessible(total: int) -> int:
    """Least accessible spaces ADA 2010 Table 208.2 asks of a facility of ``total``
    parking spaces.

    >>> [ada_accessible(n) for n in (0, 1, 25, 26, 500, 501, 1000, 1001, 1100, 1101)]
    [0, 1, 1, 2, 9, 11, 20, 21, 21, 22]
    """
    if total <= 0:
        return 0
    for most, need in _ADA_ROWS:
        if total <= most:
            return need
    if total <= 1000:
        return math.ceil(total * 2 / 100)
    return 20 + math.ceil((total - 1000) / 100)


def ada_van(accessible: int) -> int:
    """Least van-accessible spaces among ``accessible`` ones, ADA 2010 §208.2.4: one in
    six, or fraction of six.

    >>> [ada_van(n) for n in (0, 1, 6, 7, 12, 13)]
    [0, 1, 1, 2, 2, 3]
    """
    return math.ceil(accessible / 6)


class _BayLike(Protocol):
    id: str
    use: str
    width: float
    length: float


def refused_bays(slots: Iterable[_BayLike], vehicle_types: Iterable[_TypeLike]
                 ) -> dict[str, dict[str, str]]:
    """Vehicle type name → bay id → why the scenario's rule keeps that type out of that
    bay (:meth:`BayUse.refusal`); every type is a key.

    >>> from types import SimpleNamespace as NS
    >>> bay = NS(id="H1", use="accessible", width=2.5, length=5.0)
    >>> car = NS(name="car", width=1.8, length=4.5, marks=frozenset())
    >>> refused_bays([bay], [car])
    {'car': {'H1': "it is an accessible bay and 'car' is not marked accessible: true"}}
    """
    slots = list(slots)
    return {v.name: {s.id: why for s in slots
                     if (why := USES[s.use].refusal(v, s.width, s.length)) is not None}
            for v in vehicle_types}
