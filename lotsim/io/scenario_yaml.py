"""Scenario YAML → validated, frozen specs.

All schema checking happens here; the geometry checks that need the built lot
(overlaps, reachability, ...) happen in :mod:`lotsim.lot.build` and point back
at the locations stored in the specs. The format is documented in
``docs/scenario.md``.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import yaml

from lotsim.errors import ErrorCollector
from lotsim.io.file_kinds import refuse_other_kind, top_level
from lotsim.io.lot_yaml import MAX_ITEMS, parse_lot
from lotsim.io.routes_yaml import parse_routes
from lotsim.io.settings_yaml import parse_maneuvers, parse_roadmap
from lotsim.io.traffic_yaml import parse_traffic, traffic_ids
from lotsim.io.yamlnodes import YNode, parse_text, read_yaml, units_of
from lotsim.lot.uses import MARKS
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.roadmap.settings import RoadmapSettings
from lotsim.scenario import VIEWS, AnimationSpec, Scenario
from lotsim.traffic.demand import TrafficSpec
from lotsim.traffic.disturbances import (
    CLOSABLE,
    MAX_LATE,
    MAX_STALL,
    MAX_STALL_RATE,
    Closure,
    Disturbances,
    Stall,
    TakenBay,
)
from lotsim.vehicles.catalogue import CATALOGUE, DEFAULT_VEHICLE
from lotsim.vehicles.model import KMH, VehicleLimits, VehicleType

_VEHICLE_KEYS = ("name", "width", "front", "rear", "wheelbase", "max_steer_deg")
_LIMIT_KEYS = {
    "max_forward_speed_kmh": ("max_forward_speed", KMH),
    "max_reverse_speed_kmh": ("max_reverse_speed", KMH),
    "max_accel": ("max_accel", 1.0),
    "max_brake": ("max_brake", 1.0),
    "max_jerk": ("max_jerk", 1.0),
    "max_steer_rate_deg": ("max_steer_rate", math.pi / 180),
    "max_lateral_accel": ("max_lateral_accel", 1.0),
}
_PER_LENGTH = frozenset({"max_accel", "max_brake", "max_jerk", "max_lateral_accel"})
"""Limits measured in the file's length unit per second² (or ³ for the jerk): ft/s² in a
file in feet. The speeds name their unit (km/h) and keep it."""


TEXT_FILE = "<scenario>"
"""The file name errors give for a scenario read from text, not from a file."""


@dataclass(frozen=True, slots=True)
class ScenarioFile:
    """What a scenario file holds: the problem (lot, vehicles, traffic) and, apart from it,
    how ``lotsim run`` draws its run (the ``animation`` section, None without one)."""

    scenario: Scenario
    animation: AnimationSpec | None = None


def read_scenario(source: str | os.PathLike) -> ScenarioFile:
    """Read and validate a scenario file, or scenario text.

    Parameters
    ----------
    source : str or path-like
        A path; or, when a ``str`` holds a line break, the YAML text itself (errors then
        name the file ``<scenario>``).

    Raises
    ------
    ScenarioError
        On the first problem, located as ``file:line:col: key.path: ...``.
    """
    if isinstance(source, str) and "\n" in source:
        return parse_scenario_file(parse_text(source, TEXT_FILE))
    return parse_scenario_file(read_yaml(source, expect="scenario"))


def load_scenario(path_or_text: str | os.PathLike) -> Scenario:
    """Read and validate a scenario: the lot, its vehicle types and traffic, frozen; the
    file's ``animation`` section is not part of it (:func:`load_animation`).
    ``path_or_text`` is a scenario file (``docs/scenario.md``), or its YAML text: a ``str``
    holding a line break is read as text, and errors then name the file ``<scenario>``.

    Raises
    ------
    ScenarioError
        On the first problem, as ``file:line:col: key: what was expected``.

    Examples
    --------
    >>> from lotsim.api import EXAMPLE
    >>> sc = load_scenario(EXAMPLE)
    >>> sc.name, [v.name for v in sc.vehicle_types], len(sc.traffic.vehicles)
    ('example', ['valet'], 3)
    >>> load_scenario(EXAMPLE.replace("width: 7.0", "width: wide"))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    lotsim.errors.ScenarioError: <scenario>:7:58: lot.aisles[0].width: expected a number, ...
    """
    return read_scenario(path_or_text).scenario


def load_animation(path_or_text: str | os.PathLike) -> AnimationSpec | None:
    """A scenario file's ``animation`` section: how ``lotsim run`` draws the run's GIF
    (None when it has none). Give it to :func:`lotsim.render_gif` as its settings.

    Raises
    ------
    ScenarioError
        On the first problem in the file (the whole scenario is checked).

    Examples
    --------
    >>> from lotsim.api import EXAMPLE
    >>> load_animation(EXAMPLE + "animation: {speed: 2}\\n").gif_settings().speed
    2.0
    >>> load_animation(EXAMPLE) is None
    True
    """
    return read_scenario(path_or_text).animation


def load_vehicle(path: str | Path) -> VehicleType:
    """Read a vehicle type from a YAML file holding one vehicle mapping."""
    return parse_vehicle(read_yaml(path))


def parse_scenario(root: YNode) -> Scenario:
    """Validate a composed scenario document (its ``animation`` section too, which is left
    out: :func:`parse_scenario_file` keeps it)."""
    return parse_scenario_file(root).scenario


def parse_scenario_file(root: YNode) -> ScenarioFile:
    """Validate a composed scenario document: the scenario and its output options.

    Every independent problem is reported at once (:class:`~lotsim.errors.ScenarioErrors`,
    in file order): each section, and each item of a list, is read on its own; the traffic
    is checked against the vehicle types and entrances as written even where those have
    problems of their own.
    """
    refuse_other_kind(top_level(root), "scenario", root.file)
    root = units_of(root)
    f = root.fields(
        required=["lot"],
        optional=["units", "name", "description", "seed", "vehicle_types", "parked_vehicle",
                  "traffic", "disturbances", "animation", "routes", "roadmap", "maneuvers"],
    )
    errors = ErrorCollector()
    name = (errors.attempt(lambda: f["name"].file_name(
        purpose="it names the output folder runs/NAME"), default="scenario")
            if "name" in f else name_from_file(root.file))
    seed = errors.attempt(lambda: f["seed"].integer(min=0, max=2**63 - 1), default=0) \
        if "seed" in f else 0
    types = (CATALOGUE[DEFAULT_VEHICLE],)
    names = [DEFAULT_VEHICLE]
    if "vehicle_types" in f:
        nodes = errors.attempt(lambda: f["vehicle_types"].items(min_len=1), default=[])
        parsed = [errors.attempt(parse_vehicle, n) for n in nodes]
        seen: dict[str, YNode] = {}
        for n, t in zip(nodes, parsed, strict=True):
            if t is not None and t.name in seen:
                errors.attempt(_refuse, n, f"vehicle type {t.name!r} is given twice")
            elif t is not None:
                seen[t.name] = n
        types = tuple(t for t in parsed if t is not None)
        names = [t.name for t in types] + [_raw_name(n) for n, t in zip(nodes, parsed,
                                                                         strict=True)
                                           if t is None]
    parked = errors.attempt(_parked, f["parked_vehicle"], types) if "parked_vehicle" in f \
        else (types[0] if types else None)
    lot = errors.attempt(parse_lot, f["lot"])
    entrances = ([p.id for p in lot.entrances] if lot is not None
                 else _raw_ids(f["lot"], "entrances"))
    names = [n for n in names if n]
    traffic = (errors.attempt(parse_traffic, f["traffic"], names, entrances)
               if "traffic" in f and names else None)  # no type to check it against
    disturbances = (errors.attempt(lambda: parse_disturbances(f["disturbances"], traffic,
                                                              seed=seed))
                    if "disturbances" in f else None)
    if disturbances is not None and "traffic" not in f:
        errors.attempt(_refuse, f["disturbances"], "disturbances need traffic to disturb: the "
                                                   "scenario has no 'traffic' section")
    animation = errors.attempt(parse_animation, f["animation"]) if "animation" in f else None
    routes = (errors.attempt(parse_routes, f["routes"], lot, default=())
              if "routes" in f and lot is not None else ())
    description = (errors.attempt(lambda: f["description"].string(max_len=2000), default="")
                   if "description" in f else "")
    roadmap = (errors.attempt(parse_roadmap, f["roadmap"]) if "roadmap" in f
               else RoadmapSettings())
    maneuvers = (errors.attempt(parse_maneuvers, f["maneuvers"]) if "maneuvers" in f
                 else ManeuverSettings())
    errors.check()
    scenario = Scenario(
        name=name,
        lot=lot,
        traffic=traffic,
        disturbances=disturbances,
        vehicle_types=types,
        parked_vehicle=parked,
        seed=seed,
        source=root.file,
        description=description,
        routes=routes,
        units=root.units,
        roadmap=roadmap,
        maneuvers=maneuvers,
    )
    return ScenarioFile(scenario, animation)


def _refuse(node: YNode, message: str) -> None:
    raise node.error(message)


def _parked(node: YNode, types) -> VehicleType:
    wanted = node.string()
    pool = {t.name: t for t in types} | {k: v for k, v in CATALOGUE.items()}
    if wanted not in pool:
        raise node.error(
            f"expected a vehicle type of this scenario or the catalogue, found {wanted!r}")
    return pool[wanted]


def _raw_name(node: YNode) -> str:
    """The name a vehicle type item gives, as written, even when the item is broken."""
    raw = node.node
    if isinstance(raw, yaml.ScalarNode):
        return str(raw.value)
    if isinstance(raw, yaml.MappingNode):
        for k, v in raw.value:
            if getattr(k, "value", None) == "name" and isinstance(v, yaml.ScalarNode):
                return str(v.value)
    return ""


def _raw_ids(lot: YNode, key: str) -> list[str]:
    """The ids of the items of ``lot.<key>`` as written (for checking the traffic against
    them when the lot has problems of its own)."""
    out: list[str] = []
    if not isinstance(lot.node, yaml.MappingNode):
        return out
    for k, v in lot.node.value:
        if getattr(k, "value", None) == key and isinstance(v, yaml.SequenceNode):
            for item in v.value:
                if isinstance(item, yaml.MappingNode):
                    out += [str(iv.value) for ik, iv in item.value
                            if getattr(ik, "value", None) == "id"
                            and isinstance(iv, yaml.ScalarNode)]
    return out


def name_from_file(file: str) -> str:
    """A scenario's default name: its file name without the suffix, made a plain name.

    >>> name_from_file("lots/my lot (v2).yaml"), name_from_file("...yaml")
    ('my_lot_v2', 'scenario')
    """
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", Path(file).stem).strip("._")
    return name[:100] or "scenario"


def parse_animation(node: YNode) -> AnimationSpec:
    """Validate the ``animation`` mapping (``lotsim run`` writes a GIF beside result.json,
    and the HTML replay and MP4 video it names)."""
    if node.is_null:
        return AnimationSpec()
    f = node.fields(optional=["gif", "html", "mp4", "fps", "speed", "size", "from", "to",
                              "max_frames", "trail", "skip_quiet", "legend", "view"])
    names = {}
    for key, default in (("gif", "run.gif"), ("html", None), ("mp4", None)):
        names[key] = (f[key].file_name(purpose="it is written beside result.json",
                                       suffix=f".{key}") if key in f else default)
    if len({n for n in names.values() if n is not None}) < sum(
            n is not None for n in names.values()):
        raise node.error("expected different file names for gif, html and mp4")
    size = None
    if "size" in f:
        w, h = (n.integer(min=m, max=4000) for n, m in
                zip(f["size"].items(min_len=2, max_len=2), (160, 120), strict=True))
        size = (w, h)
    start = f["from"].number(what="a time in seconds") if "from" in f else None
    end = f["to"].number(what="a time in seconds") if "to" in f else None
    if start is not None and end is not None and end <= start:
        raise f["to"].error(f"expected a time after 'from' ({start:g} s), found {end:g}")
    return AnimationSpec(
        gif=names["gif"],
        html=names["html"],
        mp4=names["mp4"],
        skip_quiet=f["skip_quiet"].boolean() if "skip_quiet" in f else None,
        legend=f["legend"].boolean() if "legend" in f else None,
        view=f["view"].string(choices=VIEWS) if "view" in f else None,
        fps=f["fps"].number(min=1, max=50) if "fps" in f else None,
        speed=f["speed"].number(min=0.01, max=10_000) if "speed" in f else None,
        size=size,
        start=start,
        end=end,
        max_frames=f["max_frames"].integer(min=1, max=1_000_000) if "max_frames" in f else None,
        trail=f["trail"].number(min=0, max=3600) if "trail" in f else None,
    )


DISTURBANCE_KEYS = ("late_starts", "speed", "stalls", "closures", "taken", "repair_after",
                    "seed")
"""The keys of a ``disturbances`` section."""


def parse_disturbances(node: YNode, traffic: TrafficSpec | None, *,
                       also: tuple[str, ...] = (), seed: int = 0) -> Disturbances:
    """The ``disturbances`` mapping (``docs/scenario.md``); a given stall's car is checked
    against the traffic's ids (its streams drawn with ``seed``). ``also``: keys the caller
    reads itself (a suite's name)."""
    f = node.fields(optional=[*DISTURBANCE_KEYS, *also])
    kw: dict = {}
    if "late_starts" in f:
        late = f["late_starts"].fields(required=["probability", "max"])
        kw["late_probability"] = late["probability"].number(min=0, max=1)
        kw["late_max"] = late["max"].number(min=0, max=MAX_LATE)
    if "speed" in f:
        kw["speed"] = _range(f["speed"], 0.1, 1.0)
    if "stalls" in f:
        st = f["stalls"].fields(optional=["rate_per_hour", "duration", "at"])
        if "rate_per_hour" in st:
            kw["stall_rate"] = st["rate_per_hour"].number(min=0, max=MAX_STALL_RATE)
        if "duration" in st:
            kw["stall_duration"] = _range(st["duration"], 0.0, MAX_STALL)
        if "at" in st:
            ids = traffic_ids(traffic, seed) if traffic is not None else set()
            given = []
            for n in st["at"].items(min_len=1, max_len=MAX_ITEMS):
                g = n.fields(required=["car", "time", "duration"])
                car = g["car"].ident()
                if car not in ids:
                    raise g["car"].error(f"expected the id of a car of the traffic, found "
                                         f"{car!r}")
                given.append(Stall(car, g["time"].number(min=0, max=1e7),
                                   g["duration"].number(min=0, max=MAX_STALL)))
            kw["stalls"] = tuple(given)
    if "closures" in f:
        kw["closures"] = tuple(_closure(n) for n in f["closures"].items(min_len=1,
                                                                        max_len=MAX_ITEMS))
    if "taken" in f:
        bays = []
        for n in f["taken"].items(min_len=1, max_len=MAX_ITEMS):
            b = n.fields(required=["slot", "time"])
            bays.append(TakenBay(b["slot"].ident(), b["time"].number(min=0, max=1e7),
                                 where=b["slot"].where))
        kw["taken"] = tuple(bays)
    if "repair_after" in f:
        kw["repair_after"] = _repair_after(f["repair_after"])
    if "seed" in f:
        kw["seed"] = f["seed"].integer(min=0, max=2**63 - 1)
    return Disturbances(**kw)


def _repair_after(n: YNode) -> float | None:
    """``repair_after``: seconds, or ``never`` (None)."""
    if n.is_null or isinstance(n.node, yaml.ScalarNode) and n.node.value == "never":
        return None
    if isinstance(n.node, yaml.ScalarNode) and n.node.tag.endswith((":int", ":float")):
        return n.number(min=1, max=MAX_LATE)
    raise n.error(f"expected seconds (1 to {MAX_LATE:g}) or never, found "
                  f"{getattr(n.node, 'value', '…')!r}")


def _closure(n: YNode) -> Closure:
    """``{aisle: ID, from: T0, to: T1}`` or ``{gate: ID, ...}``."""
    c = n.fields(required=["from", "to"], optional=list(CLOSABLE))
    kinds = [k for k in CLOSABLE if k in c]
    if len(kinds) != 1:
        raise n.error(f"expected one of {' or '.join(CLOSABLE)} (the id of what is closed)")
    start = c["from"].number(min=0, max=1e7)
    end = c["to"].number(min=0, max=1e7)
    if end <= start:
        raise c["to"].error(f"expected a time after 'from' ({start:g} s), found {end:g}")
    return Closure(kinds[0], c[kinds[0]].ident(), start, end, where=c[kinds[0]].where)


def _range(node: YNode, lo: float, hi: float) -> tuple[float, float]:
    """One number or ``[low, high]`` within ``lo`` to ``hi``, as (low, high)."""
    if node.is_sequence:
        a, b = (n.number(min=lo, max=hi) for n in node.items(min_len=2, max_len=2))
        if b < a:
            raise node.error(f"expected [low, high] with low <= high, found [{a:g}, {b:g}]")
        return a, b
    x = node.number(min=lo, max=hi)
    return x, x


def parse_vehicle(node: YNode) -> VehicleType:
    """A catalogue name, or a mapping with the vehicle's dimensions and limits."""
    if not node.is_mapping:
        name = node.string(choices=list(CATALOGUE))
        return CATALOGUE[name]
    f = node.fields(required=_VEHICLE_KEYS, optional=[*_LIMIT_KEYS, *MARKS])
    limits = {
        attr: (f[key].length(positive=True) if key in _PER_LENGTH
               else f[key].number(positive=True) * scale)
        for key, (attr, scale) in _LIMIT_KEYS.items()
        if key in f
    }
    return VehicleType(
        name=f["name"].ident(),
        width=f["width"].length(positive=True, max=10),
        front=f["front"].length(positive=True, max=30),
        rear=f["rear"].length(min=0, max=30),
        wheelbase=f["wheelbase"].length(positive=True, max=30),
        max_steer=math.radians(
            f["max_steer_deg"].number(min=0, max=90, open_min=True, open_max=True,
                                     unit="deg", least=10)
        ),
        limits=VehicleLimits(**limits),
        marks=frozenset(m for m in MARKS if m in f and f[m].boolean()),
    )
