"""Scenarios in, prepared lots out: the example scenario, preparing a scenario's lot
(:func:`prepare`, or only for a picture: :func:`prepare_for_drawing`) and what ``lotsim
validate`` reports (:func:`validate`). Reading a scenario is :mod:`lotsim.io.scenario_yaml`'s
(``load_scenario``, ``load_animation``, ``read_scenario``), offered by :mod:`lotsim.api`."""

from __future__ import annotations

import dataclasses
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from lotsim.errors import ScenarioError, SettingsError
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.settings import LotSettings
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.roadmap.settings import RoadmapSettings, as_settings
from lotsim.scenario import Scenario
from lotsim.sim import preparation
from lotsim.sim.preparation import PreparedLot
from lotsim.sim.validation import ValidationReport, validate_prepared

ScenarioLike = Scenario | str | os.PathLike
"""A :class:`~lotsim.scenario.Scenario`, a path to its file, or its YAML text."""

EXAMPLE = """\
name: example
description: One one-way aisle, 2 x 4 perpendicular slots, two taken; three cars, one leaves.
seed: 1
lot:
  boundary: [[0, 0], [32, 0], [32, 20], [0, 20]]
  aisles:
    - {id: main, centerline: [[0, 10], [32, 10]], width: 7.0, direction: one-way}
  rows:
    - {aisle: main, side: left, kind: perpendicular, count: 4, slot_width: 2.5,
       slot_length: 5.0, start: 8.0, id_prefix: N}
    - {aisle: main, side: right, kind: perpendicular, count: 4, slot_width: 2.5,
       slot_length: 5.0, start: 8.0, id_prefix: S}
  entrances: [{id: in, x: 3.0, y: 10.0, heading_deg: 0}]
  exits: [{id: out, x: 24.0, y: 10.0, heading_deg: 0}]
  occupied: [N2, S3]
traffic:
  vehicles:
    - {id: ada, arrival: 0}
    - {id: bob, arrival: 3, dwell: 20}
    - {id: cy, arrival: 6}
"""
"""A small scenario's YAML text, for examples and first steps: it prepares and runs in
about a second."""


def scenario_of(scenario: ScenarioLike | PreparedLot) -> Scenario:
    """The :class:`Scenario` of what a caller gave: a prepared lot's, the scenario itself,
    or one read from a path or YAML text."""
    if isinstance(scenario, PreparedLot):
        return scenario.scenario
    if isinstance(scenario, Scenario):
        return scenario
    if isinstance(scenario, (str, os.PathLike)):
        return load_scenario(scenario)
    raise SettingsError("scenario", f"expected a Scenario, a PreparedLot, a path or YAML "
                                    f"text, found {type(scenario).__name__}")


def source_of(scenario: ScenarioLike | PreparedLot) -> str:
    """How a scenario was named, for messages: its path as given, else its source."""
    if isinstance(scenario, os.PathLike) or (isinstance(scenario, str) and "\n" not in scenario):
        return os.fspath(scenario)
    return scenario_of(scenario).source


def with_settings(scenario: Scenario, *, roadmap: RoadmapSettings | None = None,
                  maneuvers: ManeuverSettings | None = None, lot: LotSettings | None = None
                  ) -> Scenario:
    """``scenario`` with ``roadmap``, ``maneuvers`` and ``lot`` (how its lot is built: its
    spec's settings) in place of its own settings (None: its own), each checked to be what
    it says (:class:`~lotsim.errors.SettingsError`).

    >>> sc = with_settings(load_scenario(EXAMPLE), maneuvers=ManeuverSettings(margin=0.2))
    >>> sc.maneuvers.margin, sc.roadmap == RoadmapSettings()
    (0.2, True)
    """
    changes = {}
    if roadmap is not None:
        changes["roadmap"] = as_settings(roadmap, RoadmapSettings, "roadmap")
    if maneuvers is not None:
        changes["maneuvers"] = as_settings(maneuvers, ManeuverSettings, "maneuvers")
    if lot is not None:
        changes["lot"] = dataclasses.replace(scenario.lot,
                                             settings=as_settings(lot, LotSettings, "lot"))
    return dataclasses.replace(scenario, **changes) if changes else scenario


def prepare(scenario: ScenarioLike, *, roadmap: RoadmapSettings | None = None,
            maneuvers: ManeuverSettings | None = None, lot: LotSettings | None = None,
            cache: bool = True, progress=None) -> PreparedLot:
    """Build the scenario's lot for its vehicle types, plan every slot's maneuvers and the
    drivable graph through them, once, for any number of runs.

    Parameters
    ----------
    scenario : Scenario, path or YAML text
    roadmap : RoadmapSettings, optional, keyword-only
        How the drivable graph is made (junction turns' design speeds, turns through a
        junction's area, the multi-point search, turnarounds); default the scenario's
        (its file's ``roadmap`` section).
    maneuvers : ManeuverSettings, optional, keyword-only
        How the parking maneuvers are planned (clearance, direction changes, probes,
        easing); default the scenario's (its file's ``maneuvers`` section).
    lot : LotSettings, optional, keyword-only
        How the lot is built (the free space beside the widest car in its lane, the
        sweeps' spacing, the slowest a bend is driven); default the scenario's (its file's
        ``lot.build``). All three are kept in the prepared lot's scenario, and a run's
        ``result.json`` writes them.
    cache : bool, keyword-only
        Load a lot prepared before (same lot, vehicle types, settings and lotsim) from the
        on-disk cache (``LOTSIM_CACHE_DIR``; ``off`` turns it off) and store a new one
        there.
    progress : callable, optional, keyword-only
        Called as ``progress(done, total)`` as the maneuvers' distinct problems are searched
        (the longest part of preparing a large lot; not called for a lot from the cache).

    Returns
    -------
    PreparedLot
        Frozen: the scenario and its ``lot_graph``; hand it to :func:`run`.

    Raises
    ------
    ScenarioError
        When the layout does not hold together (overlaps, narrow aisles, ...).
    SettingsError
        When ``roadmap``, ``maneuvers`` or ``lot`` is not a settings object of its kind.

    Examples
    --------
    >>> prepared = prepare(EXAMPLE)
    >>> len(prepared.lot.free_slots), prepared.infeasible
    (6, {'valet': {}})
    >>> prepare(EXAMPLE, maneuvers=ManeuverSettings(margin=0.15)).scenario.maneuvers.margin
    0.15
    """
    sc = with_settings(scenario_of(scenario), roadmap=roadmap, maneuvers=maneuvers, lot=lot)
    if progress is None:  # in a notebook, the cell shows it
        from lotsim.api.notebook import progress_for

        progress = progress_for("planning maneuvers")
    return preparation.prepare_lot(sc, cache=cache, progress=progress)


def validate(scenario: ScenarioLike | PreparedLot, *, progress=None) -> ValidationReport:
    """What ``lotsim validate`` checks and prints, as data: the scenario is read, its lot
    prepared, its traffic checked as :func:`run` checks it. ``progress`` is passed to
    :func:`prepare`.

    Returns
    -------
    ValidationReport
        ``.summary()`` is the text ``lotsim validate`` prints; ``.complete`` is what
        ``--strict`` requires (every free slot and exit reachable, every slot usable by
        every type); ``.reachability``, ``.infeasible`` and ``.warnings`` hold the details;
        ``.prepared`` is ready for :func:`run`.

    Raises
    ------
    ScenarioError
        For anything ``lotsim validate`` reports as an error (exit 2).

    Examples
    --------
    >>> report = validate(EXAMPLE)
    >>> report.complete, report.warnings
    (True, [])
    >>> print(report.summary().splitlines()[1])
      slots: 8 (perpendicular 8, parallel 0, angled 0); free 6, taken 2
    """
    prepared = (scenario if isinstance(scenario, PreparedLot)
                else prepare(scenario, progress=progress))
    return validate_prepared(prepared, source_of(scenario))


def prepare_for_drawing(scenario: ScenarioLike | PreparedLot, *, graph: bool = False
                        ) -> PreparedLot:
    """The scenario's lot ready to be drawn (``lotsim show``): with ``graph``, prepared as
    :func:`prepare` does (every maneuver planned, from the cache when it can); without, the
    lot alone with its slots on placeholder links (quick) — a picture's lot, not one to
    :func:`run`. A :class:`PreparedLot` is returned as it is.

    Examples
    --------
    >>> len(prepare_for_drawing(EXAMPLE).lot.slots)
    8
    """
    if isinstance(scenario, PreparedLot):
        return scenario
    sc = scenario_of(scenario)
    return PreparedLot(sc, preparation.prepare_graph(sc, maneuvers=graph))


@dataclass(frozen=True)
class FileValidation:
    """What :func:`validate_files` found of one file.

    Attributes
    ----------
    source : str
        The file, as given.
    summary : str
        What ``lotsim validate`` prints of its lot (``""`` when it is not a valid
        scenario).
    complete : bool
        What ``--strict`` requires (:attr:`ValidationReport.complete`); False for a file
        that is not a valid scenario.
    problems : tuple of str
        Each problem of a file that is not a valid scenario, located (``file:line:col:
        ...``); empty for a valid one.
    seconds : float
        How long preparing and checking it took, where it was done.
    answer : dict
        :meth:`ValidationReport.as_dict` of its lot: per vehicle type the free slots it
        can use and those it cannot, by row, with why (empty for a file that is not a
        valid scenario).
    """

    source: str
    summary: str
    complete: bool
    problems: tuple[str, ...]
    seconds: float
    answer: dict = field(default_factory=dict)

    @property
    def valid(self) -> bool:
        """Whether the file is a valid scenario."""
        return not self.problems


def validate_file(job: tuple[str, bool]) -> FileValidation:
    """:func:`validate` one ``(path, verbose)``, its outcome as plain data (a worker's job
    in :func:`validate_files`: it pickles, where the prepared lot would be heavy)."""
    path, verbose = job
    clock = time.perf_counter()
    try:
        report = validate(path)
    except ScenarioError as exc:
        problems = tuple(str(e) for e in getattr(exc, "errors", (exc,)))
        return FileValidation(path, "", False, problems, time.perf_counter() - clock)
    return FileValidation(path, report.summary(verbose=verbose), report.complete, (),
                          time.perf_counter() - clock, report.as_dict())


def validate_files(paths: Sequence[str | os.PathLike], *, verbose: bool = False,
                   jobs: int | None = None, client: Any = None,
                   progress: Callable[[int, int], None] | None = None
                   ) -> list[FileValidation]:
    """:func:`validate` each of ``paths`` — the lots of a city's extract, a designer's
    variants — several at once: on ``jobs`` local processes (default 1: in this process,
    one after another, each lot on every core), or on a Dask cluster (``client``,
    :func:`~lotsim.bench.connect`, as ``lotsim bench`` uses). A file is one job: its lot
    is prepared on one core of the process that takes it. ``progress(done, total)`` is
    called as files are done.

    Returns
    -------
    list of FileValidation
        In the order of ``paths``; a file that is not a valid scenario says why in its
        ``problems`` (it does not stop the others).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "lot.yaml"
    >>> _ = path.write_text(EXAMPLE)
    >>> [(f.valid, f.complete) for f in validate_files([path])]
    [(True, True)]
    """
    from lotsim.bench.runner import run_all

    jobs_ = [(os.fspath(p), verbose) for p in paths]
    found: dict[int, FileValidation] = {}

    def take(k: int, outcome: FileValidation) -> None:
        found[k] = outcome
        if progress is not None:
            progress(len(found), len(jobs_))

    def lost(k: int, exc: BaseException) -> FileValidation:
        return FileValidation(jobs_[k][0], "", False,
                              (f"{jobs_[k][0]}: its worker was lost ({exc!r})",), 0.0)

    if progress is not None:
        progress(0, len(jobs_))
    run_all(validate_file, jobs_, take, lost, jobs=jobs or 1, client=client)
    return [found[k] for k in range(len(jobs_))]
