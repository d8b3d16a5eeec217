"""Results in: reading a ``result.json`` (:func:`load_result`), writing one
(:func:`write_result`) and verifying a run independently of the planner (:func:`check`)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from lotsim.api.running import (
    RunResult,
    run,  # noqa: F401 (the examples)
)
from lotsim.api.scenarios import EXAMPLE  # noqa: F401 (the examples)
from lotsim.core import checks as _checks
from lotsim.errors import SettingsError
from lotsim.sim import results as _results

if TYPE_CHECKING:
    from lotsim.verify import CheckReport


def result_document(result: RunResult | dict | str | os.PathLike) -> dict:
    """The document of ``result``; a file is read packed (:func:`load_result`): what is
    done with it here reads the samples as arrays."""
    if isinstance(result, _results.RunResult):
        from lotsim.io.result import result_dict

        return result_dict(result)
    if isinstance(result, dict):
        return result
    if isinstance(result, (str, os.PathLike)):
        return load_result(result, packed=True)
    raise SettingsError("result", f"expected a RunResult, a result dict or a result.json "
                                  f"path, found {type(result).__name__}")


def load_result(path: str | os.PathLike, *, packed: bool = False) -> dict:
    """Read a ``result.json`` (:func:`lotsim.verify.read_result`).

    With ``packed``, each vehicle's sample columns are numpy float arrays, made as the file
    is read (a quarter of the memory of lists of floats), not lists.

    Raises
    ------
    ResultFormatError
        When it cannot be read or is not a lotsim result; a scenario or a bench suite is
        named as such.

    Examples
    --------
    >>> import tempfile
    >>> path = f"{tempfile.mkdtemp()}/example.yaml"
    >>> _ = Path(path).write_text(EXAMPLE)
    >>> load_result(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    lotsim.errors.ResultFormatError: /.../example.yaml: this is a lotsim scenario, not a result: ...
    """
    from lotsim.errors import ResultFormatError
    from lotsim.io.file_kinds import file_kind, wrong_kind
    from lotsim.verify import read_result

    try:
        return read_result(path, packed=packed)
    except ResultFormatError:
        found = file_kind(path)
        if found is None or found == "result":
            raise
    raise ResultFormatError(f"{os.fspath(path)}: {wrong_kind(found, 'result')}")


def check(result: RunResult | dict | str | os.PathLike, *, max_violations: int = 50
          ) -> CheckReport:
    """Verify a run independently of the planner, as ``lotsim check`` does: footprints never
    overlap each other, parked cars, obstacles or the boundary; no sideways motion;
    curvature, steering rate, speed, acceleration and jerk within the vehicle's limits;
    parked cars inside their slots (every rule of ``docs/result.md``).

    Parameters
    ----------
    result : RunResult, dict or path
        A run, its document (:func:`~lotsim.io.result.result_dict`) or a ``result.json``.
    max_violations : int, keyword-only
        How many violations to list (``.stats["violations"]`` counts them all).

    Returns
    -------
    CheckReport
        ``.ok``, ``.violations`` (rule, vehicle, time, message), ``.stats``, ``.summary()``.

    Raises
    ------
    ResultFormatError
        When a file named is not JSON or not a lotsim result.

    Examples
    --------
    >>> report = check(run(EXAMPLE))
    >>> report.ok, report.violations
    (True, [])
    >>> check({"format": "lotsim-result"}).violations[0].rule
    'structure'
    """
    from lotsim.verify import check_result

    if not (_checks.is_real(max_violations) and max_violations >= 1):
        raise SettingsError("max_violations", f"expected at least 1, found "
                                              f"{_checks.shown(max_violations)}")
    return check_result(result_document(result), max_violations=int(max_violations))


def write_result(result: RunResult | dict, path: str | os.PathLike, *,
                 progress=None) -> Path:
    """Write a run, or its document (:func:`~lotsim.io.result.result_dict`), to ``path`` as
    ``result.json`` (compressed when ``path`` ends in ``.gz``): atomically (nothing
    half-written), its folder made if need be; byte for byte what ``lotsim run`` writes for
    the same scenario and seed. A run is written one car at a time (a car's samples are let
    go once written: a day's cars would hold gigabytes as one document), with
    ``progress(done, total)`` called as each car is.

    Examples
    --------
    >>> import tempfile
    >>> from lotsim.io.result import result_dict
    >>> doc = result_dict(run(EXAMPLE))
    >>> write_result(doc, f"{tempfile.mkdtemp()}/out/result.json").name
    'result.json'
    """
    from lotsim.io.result import write_json, write_run

    Path(path).parent.mkdir(parents=True, exist_ok=True)
    if isinstance(result, _results.RunResult):
        write_run(result, path, progress=progress)
    else:
        write_json(result_document(result), path)
    return Path(path)
