"""Typed errors of lotsim: every error it raises on purpose is a :class:`LotsimError`.

A user's mistake is one of these, never a bare ``ValueError``, and the CLI prints
``str(error)`` (no traceback) and exits 2:

* :class:`ScenarioError` — a problem in an input file, ``path:line:col: key: message``;
  :class:`LimitExceeded` (a run that outgrows its memory or time budget) is one, located at
  the scenario's traffic;
* :class:`SettingsError` — a setting or argument out of range or not one of its choices
  (``window: expected 1 to 600 seconds, found 0``); the CLI names the option instead;
* :class:`ResultFormatError` — a file that is not a lotsim result at all;
* :class:`ReplayError` — a result document that cannot be replayed (drawn);
* :class:`InfeasibleManeuver` — a vehicle type cannot enter or leave a slot (exit 1);
* :class:`OutputError` — an output file or folder that cannot be written, named as given;
* :class:`ReuseMismatch` — with the reuse check on (``LOTSIM_VERIFY_REUSE=1``), a piece of
  work recalled from a store that differs from the same work done afresh.

Examples
--------
>>> from lotsim.errors import LotsimError, ScenarioError, SettingsError
>>> issubclass(ScenarioError, LotsimError), issubclass(SettingsError, ValueError)
(True, True)
>>> str(SettingsError("window", "expected 1 to 600 seconds, found 0"))
'window: expected 1 to 600 seconds, found 0'
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

    def __reduce__(self):  # two arguments survive pickling between processes
        return (type(self), (self.where, self.message))


class ScenarioErrors(ScenarioError):
    """Several independent problems in one input, in file order: each a
    :class:`ScenarioError` of its own (``errors``); the first is this error's ``where`` and
    ``message``, and its text is every one's, a line each."""

    def __init__(self, errors):
        self.errors = tuple(errors)
        first = self.errors[0]
        self.where, self.message = first.where, first.message
        Exception.__init__(self, "\n".join(str(e) for e in self.errors))

    def __reduce__(self):
        return (type(self), (self.errors,))


class ErrorCollector:
    """Gathers the independent problems of an input, so that a user sees them all at once.

    ``attempt(fn, *args)`` runs ``fn`` and returns its value, or keeps the
    :class:`ScenarioError` it raised and returns ``default``; :meth:`check` then raises
    what was kept: the one error, or a :class:`ScenarioErrors` of them in file order.
    """

    def __init__(self):
        self.errors: list[ScenarioError] = []

    def attempt(self, fn, *args, default=None):
        try:
            return fn(*args)
        except ScenarioErrors as exc:
            self.errors.extend(exc.errors)
        except ScenarioError as exc:
            self.errors.append(exc)
        return default

    def check(self) -> None:
        if not self.errors:
            return
        def place(e: ScenarioError) -> tuple:  # file order; the unlocated last
            w = e.where
            return (1, "", 0, 0) if w is None else (0, w.file, w.line, w.col)

        order = sorted(self.errors, key=place)
        raise order[0] if len(order) == 1 else ScenarioErrors(order)


class LimitExceeded(ScenarioError):
    """A run stopped because it needs more memory or time than its budget
    (:mod:`lotsim.sim.limits`)."""


class SettingsError(LotsimError, ValueError):
    """A setting or argument out of range or not one of its choices.

    Parameters
    ----------
    name : str
        The setting, as its dataclass field or keyword is called (``window``); the CLI
        prints its option (``--window``) instead.
    message : str
        What was expected and what was found.
    """

    def __init__(self, name: str, message: str):
        self.name = name
        self.message = message
        super().__init__(f"{name}: {message}")

    def __reduce__(self):
        return (type(self), (self.name, self.message))


class ResultFormatError(LotsimError):
    """The file is not JSON, or not a lotsim result at all."""


class ReplayError(LotsimError, ValueError):
    """A result document that cannot be replayed (a message naming the key)."""


class InfeasibleManeuver(LotsimError):
    """A vehicle type cannot enter or leave a slot."""


class DecisionError(LotsimError, ValueError):
    """A decision taken from outside a run that the lot cannot honour (a slot-choice
    policy's answer: a slot that is taken, unknown, or that the car cannot use or reach):
    ``car: message``."""

    def __init__(self, car: str, message: str):
        super().__init__(f"car {car!r} {message}")
        self.car = car
        self.message = message

    def __reduce__(self):
        return (type(self), (self.car, self.message))


class OutputError(LotsimError):
    """An output that cannot be written: ``name`` as the user gave it (``-o runs/x``) and
    why (``cannot make the folder 'runs/x' (Permission denied)``).

    Parameters
    ----------
    name : str
        The output as given (a path, or an option and its path).
    why : str
        What stops it being written.
    """

    def __init__(self, name: str, why: str):
        self.name = name
        self.why = why
        super().__init__(f"{name}: {why}")

    def __reduce__(self):
        return (type(self), (self.name, self.why))


class ReuseMismatch(LotsimError):
    """A piece of work recalled from one of lotsim's stores (the on-disk cache, the roadmap
    store, the maneuver answers, a search graph) that differs from the same work done
    afresh: the store's key for it misses something the work reads. Raised only with the
    reuse check on (:class:`lotsim.core.reusecheck.ReuseCheck`).

    Parameters
    ----------
    store : str
        The store (``roadmap``, ``maneuver answers``, ...).
    key : str
        The recalled piece's key in that store, as text.
    what : str
        Where the recalled piece and the fresh one first differ, and how.
    """

    def __init__(self, store: str, key: str, what: str):
        self.store = store
        self.key = key
        self.what = what
        super().__init__(f"{store}: the piece recalled as {key} differs from the same work "
                         f"done afresh: {what}")

    def __reduce__(self):
        return (type(self), (self.store, self.key, self.what))
