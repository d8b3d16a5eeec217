"""A benchmark suite: :func:`load_suite` reads and checks ``SUITE.yaml`` (``docs/bench.md``),
:meth:`Suite.specs` expands its grid into :class:`RunSpec` in a fixed order."""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from lotsim.errors import SettingsError
from lotsim.io.file_kinds import refuse_other_kind, top_level
from lotsim.io.scenario_yaml import (
    DISTURBANCE_KEYS,
    MAX_ITEMS,
    load_scenario,
    name_from_file,
    parse_disturbances,
)
from lotsim.io.yamlnodes import YNode, read_yaml
from lotsim.scenario import Scenario
from lotsim.sim.settings import (
    ASSIGNMENTS,
    BOOKING_HORIZON,
    PLANNERS,
    PRIORITIES,
    GASettings,
    RunSettings,
)
from lotsim.traffic.demand import StreamSpec
from lotsim.traffic.disturbances import Disturbances

GA_KEYS = ("population", "generations", "seed")
MAX_RUNS = 100_000
"""Largest grid a suite may expand to."""


@dataclass(frozen=True, slots=True)
class PlannerVariant:
    """A planner and, for WHCA*, its window [s] (None for CA* and HCA*)."""

    planner: str
    window: float | None = None

    @property
    def label(self) -> str:
        """How rows and tables name it.

        >>> PlannerVariant("hca").label, PlannerVariant("whca", 10.0).label
        ('hca', 'whca-10')
        """
        return self.planner if self.window is None else f"{self.planner}-{self.window:g}"


@dataclass(frozen=True, slots=True)
class SuiteScenario:
    """A scenario of the suite: its name, the file as given, and its YAML text (so a
    worker on another machine needs no file system)."""

    name: str
    file: str
    text: str = field(repr=False)
    stream_rate: float | None
    """The scenario's own stream rate [vehicles/h], None without a stream."""
    stream_count: int | None


@dataclass(frozen=True, slots=True)
class RunSpec:
    """One grid point: what :func:`run_spec` plans.

    ``rate_per_hour`` and ``count`` replace the scenario's stream rate and count when not
    None; ``ga`` holds the suite's GA settings as ``(key, value)`` pairs.
    """

    index: int
    scenario: SuiteScenario
    planner: PlannerVariant
    assignment: str
    priority: str
    rate_per_hour: float | None
    count: int | None
    seed: int
    ga: tuple[tuple[str, int], ...] = ()
    horizon: float = BOOKING_HORIZON
    disturbance: str = "none"
    """The name of the suite's disturbances variant (``none``: driven as planned)."""
    disturbances: Disturbances | None = None


@dataclass(frozen=True, slots=True)
class Suite:
    """A validated suite file (see ``docs/bench.md``)."""

    name: str
    description: str
    source: str
    scenarios: tuple[SuiteScenario, ...]
    planners: tuple[PlannerVariant, ...]
    assignments: tuple[str, ...]
    priorities: tuple[str, ...]
    rates_per_hour: tuple[float, ...] | None
    count: int | None
    seeds: tuple[int, ...]
    ga: tuple[tuple[str, int], ...] = ()
    horizon: float = BOOKING_HORIZON
    """How far ahead booked priorities (shortest_first, ga) know the arrivals [s]."""
    disturbances: tuple[tuple[str, Disturbances | None], ...] = (("none", None),)
    """The named disturbances each run is driven through (``none``: as planned)."""

    @property
    def size(self) -> int:
        """Number of runs in the grid."""
        rates = len(self.rates_per_hour) if self.rates_per_hour else 1
        return (len(self.scenarios) * len(self.planners) * len(self.assignments)
                * len(self.priorities) * rates * len(self.disturbances) * len(self.seeds))

    def specs(self) -> list[RunSpec]:
        """The grid in its fixed order: scenario, planner, assignment, priority, rate,
        disturbances, seed (the last varies fastest)."""
        rates = self.rates_per_hour or (None,)
        out = []
        for sc in self.scenarios:
            for pv in self.planners:
                for asg in self.assignments:
                    for prio in self.priorities:
                        for rate in rates:
                            for name, dist in self.disturbances:
                                for seed in self.seeds:
                                    out.append(RunSpec(len(out), sc, pv, asg, prio, rate,
                                                       self.count, seed,
                                                       self.ga if prio == "ga" else (),
                                                       self.horizon, name, dist))
        return out


def load_suite(path: str | os.PathLike) -> Suite:
    """Read and validate a suite file; scenario paths are relative to it.

    Raises
    ------
    ScenarioError
        On the first problem, as ``file:line:col: key: message`` (problems inside a
        scenario file are located in that file).
    """
    return parse_suite(read_yaml(path, expect="suite"))


def parse_suite(root: YNode) -> Suite:
    """Validate a composed suite document (:func:`load_suite`)."""
    refuse_other_kind(top_level(root), "suite", root.file)
    f = root.fields(required=["scenarios", "planners", "seeds"],
                    optional=["name", "description", "assignments", "priorities",
                              "rates_per_hour", "count", "ga", "horizon", "disturbances"])
    base = Path(root.file).parent
    if "name" in f:
        name = f["name"].file_name(purpose="it names the output folder runs/bench/NAME")
    else:
        name = name_from_file(root.file)
    rates = None
    if "rates_per_hour" in f:
        rates = tuple(_unique(f["rates_per_hour"], lambda n: n.number(positive=True, max=1e6),
                              "rate"))
    count = f["count"].integer(min=1, max=MAX_ITEMS) if "count" in f else None
    scenarios = []
    for n in _nonempty(f["scenarios"], "scenario"):
        sc = _suite_scenario(n, base, override=next((k for k in ("rates_per_hour", "count")
                                                     if k in f), None))
        if any(s.name == sc.name for s in scenarios):
            raise n.error(f"two scenarios are named {sc.name!r}: rows could not tell them "
                          "apart")
        scenarios.append(sc)
    planners = _planners(f["planners"])
    assignments = (tuple(_unique(f["assignments"], lambda n: n.string(choices=ASSIGNMENTS),
                                 "assignment"))
                   if "assignments" in f else ("shortest",))
    priorities = ("arrival",)
    if "priorities" in f:
        priorities = tuple(_unique(f["priorities"], lambda n: n.string(choices=PRIORITIES),
                                   "priority"))
    ga: tuple[tuple[str, int], ...] = ()
    if "ga" in f:
        if "ga" not in priorities:
            raise f["ga"].error("GA settings are given but 'priorities' has no 'ga'")
        g = f["ga"].fields(optional=GA_KEYS)
        ga = tuple((k, _checked(n, GASettings, k, n.integer())) for k, n in g.items())
        _checked(f["ga"], GASettings, "", None, **dict(ga))
    seeds = tuple(_unique(f["seeds"], lambda n: _checked(n, RunSettings, "seed", n.integer()),
                          "seed"))
    horizon = BOOKING_HORIZON
    if "horizon" in f:
        if not set(priorities) & {"shortest_first", "ga"}:
            raise f["horizon"].error("a booking horizon is given but 'priorities' has no "
                                     "booked order (shortest_first, ga)")
        horizon = _checked(f["horizon"], RunSettings, "horizon", f["horizon"].number())
    disturbances: tuple[tuple[str, Disturbances | None], ...] = (("none", None),)
    if "disturbances" in f:
        read: list[tuple[str, Disturbances | None]] = []
        for n in _nonempty(f["disturbances"], "disturbances"):
            name, spec = _disturbance(n)
            if any(name == k for k, _ in read):
                raise n.error(f"disturbances {name!r} are given twice: rows could not tell "
                              "them apart")
            read.append((name, spec))
        disturbances = tuple(read)
    suite = Suite(
        name=name,
        description=f["description"].string(max_len=2000) if "description" in f else "",
        source=root.file,
        scenarios=tuple(scenarios),
        planners=planners,
        assignments=assignments,
        priorities=priorities,
        rates_per_hour=rates,
        count=count,
        seeds=seeds,
        ga=ga,
        horizon=horizon,
        disturbances=disturbances,
    )
    if suite.size > MAX_RUNS:
        raise root.error(f"the grid has {suite.size} runs; at most {MAX_RUNS}")
    return suite


def _disturbance(node: YNode) -> tuple[str, Disturbances | None]:
    """A named variant of disturbances: ``{name: late, late_starts: {...}, ...}`` (the
    scenario section's keys, ``docs/scenario.md``); one with nothing else is ``none``."""
    name = node.fields(required=["name"], optional=DISTURBANCE_KEYS)["name"].ident()
    spec = parse_disturbances(node, None, also=("name",))
    return name, (spec if spec.active else None)


def _checked(node: YNode, cls: type, name: str, value: Any, **more: Any) -> Any:
    """``value`` of setting ``name`` (with ``more``), checked as ``cls`` checks it on
    construction (:mod:`lotsim.sim.settings`): the same message as from Python or the CLI,
    located at ``node``."""
    try:
        cls(**({name: value} if name else {}), **more)
    except SettingsError as exc:
        raise node.error(exc.message) from None
    return value


def _nonempty(node: YNode, what: str) -> list[YNode]:
    items = node.items()
    if not items:
        raise node.error(f"expected at least one {what}, found an empty list")
    return items


def _unique(node: YNode, read: Callable[[YNode], Any], what: str) -> list:
    """A non-empty list read item by item, no item given twice."""
    out: list = []
    for n in _nonempty(node, what):
        value = read(n)
        if value in out:
            raise n.error(f"{what} {value!r} is given twice")
        out.append(value)
    return out


def one_stream(scenario: Scenario) -> StreamSpec | None:
    """The scenario's traffic stream when it has one only, at a constant rate: the stream
    whose rate and count a suite may replace (None otherwise)."""
    streams = scenario.traffic.streams if scenario.traffic is not None else ()
    return streams[0] if len(streams) == 1 and streams[0].constant else None


def _suite_scenario(node: YNode, base: Path, *, override: str | None) -> SuiteScenario:
    given = node.string(max_len=1000)
    path = base / given
    if not path.is_file():
        raise node.error(f"no scenario file {given!r} (looked for {path})")
    scenario = load_scenario(path)
    if scenario.traffic is None:
        raise node.error(f"{given} has no 'traffic' section to run")
    stream = one_stream(scenario)
    if override is not None and stream is None:
        how = ("lists its vehicles one by one and has no traffic stream"
               if not scenario.traffic.streams else
               "has a stream whose rate is a profile over the day" if
               len(scenario.traffic.streams) == 1 else "has several traffic streams")
        raise node.error(f"{given} {how}, so '{override}' cannot apply to it")
    return SuiteScenario(
        name=scenario.name, file=str(path), text=path.read_text(encoding="utf-8"),
        stream_rate=None if stream is None else stream.rate * 3600.0,
        stream_count=None if stream is None else stream.count,
    )


def _planners(node: YNode) -> tuple[PlannerVariant, ...]:
    """``[ca, hca, whca, {whca: [5, 10, 20]}]``: a bare ``whca`` has the default window."""
    out: list[PlannerVariant] = []
    for n in _nonempty(node, "planner"):
        if n.is_mapping:
            w = n.fields(required=["whca"])["whca"]
            windows = _nonempty(w, "window") if w.is_sequence else [w]
            variants = [(x, PlannerVariant("whca", _checked(
                x, RunSettings, "window", x.number(what="a window in seconds"))))
                for x in windows]
        else:
            name = n.string(choices=PLANNERS)
            window = RunSettings().window if name == "whca" else None
            variants = [(n, PlannerVariant(name, window))]
        for where, pv in variants:
            if pv in out:
                raise where.error(f"planner {pv.label} is given twice")
            out.append(pv)
    return tuple(out)
