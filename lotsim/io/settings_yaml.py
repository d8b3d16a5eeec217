"""A scenario file's ``roadmap`` and ``maneuvers`` sections, and its lot's ``build``
mapping, → the frozen settings that prepare its lot
(:class:`~lotsim.roadmap.settings.RoadmapSettings`,
:class:`~lotsim.maneuvers.settings.ManeuverSettings`,
:class:`~lotsim.lot.settings.LotSettings`). Each key is read as what it measures
(lengths in the file's unit, speeds in km/h, angles in degrees), then the settings check
their values as they do from Python: a value they refuse is reported at its key, with their
message (``file:line:col: roadmap.turnarounds.margin: expected 0 to 1 m, found 2``). The keys
are documented in ``docs/scenario.md``."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

from lotsim.errors import SettingsError
from lotsim.io.yamlnodes import YNode
from lotsim.lot.settings import LotSettings
from lotsim.maneuvers.settings import WAY_OUT, ManeuverSettings
from lotsim.roadmap.settings import (
    GROUPS,
    KMH_PER_MS,
    AreaTurnSettings,
    MultipointSettings,
    RoadmapSettings,
    TurnaroundSettings,
    TurnSettings,
)

Reader = Callable[[YNode], Any]


def _length(n: YNode) -> float:
    return n.length()


def _lengths(n: YNode) -> tuple[float, ...]:
    return tuple(x.length() for x in n.items(min_len=1))


def _number(n: YNode) -> float:
    return n.number()


def _numbers(n: YNode) -> tuple[float, ...]:
    return tuple(x.number() for x in n.items(min_len=1))


def _integer(n: YNode) -> int:
    return n.integer()


def _kmh(n: YNode) -> float:
    return n.number(what="a speed in km/h") / KMH_PER_MS


def _speeds_kmh(n: YNode) -> tuple[float, ...]:
    return tuple(_kmh(x) for x in n.items(min_len=1))


def _radians(n: YNode) -> float:
    return math.radians(n.number(what="an angle in degrees"))


def _degrees(n: YNode) -> float:
    return n.number(what="an angle in degrees")


def _pair(n: YNode) -> tuple[float, float]:
    a, b = (x.length() for x in n.items(min_len=2, max_len=2))
    return a, b


KEYS: dict[type, dict[str, tuple[str, Reader]]] = {
    LotSettings: {"lane_clearance": ("lane_clearance", _length), "sweep": ("sweep", _length),
                  "crawl_speed_kmh": ("crawl_speed", _kmh)},
    TurnSettings: {"speeds_kmh": ("speeds", _speeds_kmh),
                   "through_overlap": ("through_overlap", _length)},
    AreaTurnSettings: {"shifts": ("shifts", _lengths), "leads": ("leads", _lengths),
                       "radii": ("radii", _numbers), "speeds_kmh": ("speeds", _speeds_kmh)},
    MultipointSettings: {
        "move": ("move", _length), "step": ("step", _length), "cell": ("cell", _length),
        "headings": ("headings", _integer), "cusp": ("cusp", _length),
        "steer": ("steer", _length), "reverse": ("reverse", _number),
        "max_changes": ("max_changes", _integer),
        "expansion_limit": ("expansion_limit", _integer), "weight": ("weight", _number),
        "improve": ("improve", _integer), "closing_radii": ("closing_radii", _numbers),
        "s_radii": ("s_radii", _numbers), "grid": ("grid", _length),
        "junction_starts": ("junction_starts", _lengths),
        "junction_room": ("junction_room", _length), "uturn_land": ("uturn_land", _pair)},
    TurnaroundSettings: {
        "margin": ("margin", _length), "max_changes": ("max_changes", _integer),
        "probe": ("probe", _length), "step": ("step", _length),
        "starts": ("starts", _lengths), "min_stroke": ("min_stroke", _length),
        "dead_end": ("dead_end", _length)},
    ManeuverSettings: {
        "margin": ("margin", _length), "max_changes": ("max_changes", _integer),
        "probe": ("probe", _length), "first_turn_deg": ("first_turn", _radians),
        "candidates": ("candidates", _integer), "closing_radii": ("closing_radii", _numbers),
        "sweep": ("sweep", _length), "min_stroke": ("min_stroke", _length),
        "parallel_extra": ("parallel_extra", _length),
        "parallel_heading_step_deg": ("parallel_heading_step", _degrees),
        "ease_ramps": ("ease_ramps", _lengths), "ease_drift": ("ease_drift", _length),
        "start_grid": ("start_grid", _length), "approach": ("approach", _length),
        "rough": ("rough", _length), "creep": ("creep", _length),
        "way_out": ("way_out", lambda n: _way_out(n))},
}
"""For each settings class, its keys in a scenario file → (its field, how the value is
read). Every field of each class has a key: a test holds them to it."""
WAY_OUT_KEYS = {k: v for k, v in KEYS[MultipointSettings].items()
                if k not in ("junction_starts", "junction_room", "uturn_land")}
"""The keys of ``maneuvers.way_out``: the multi-point search's but those of junctions and
U-turns, which a way out of a slot does not read."""


def _way_out(node: YNode) -> MultipointSettings:
    return parse_settings(node, MultipointSettings, keys=WAY_OUT_KEYS, base=WAY_OUT)


def parse_settings(node: YNode, cls: type, *, keys: dict | None = None,
                   base: Any = None) -> Any:
    """A ``cls`` (one of :data:`KEYS`) from a mapping of its keys (``keys``: those of
    :data:`KEYS` unless given); a key left out keeps its value in ``base`` (default: the
    class's default). Unknown keys, and values the settings refuse, are errors at their
    key."""
    base = cls() if base is None else base
    if node.is_null:
        return base
    keys = KEYS[cls] if keys is None else keys
    f = node.fields(optional=list(keys))
    values = {keys[k][0]: keys[k][1](n) for k, n in f.items()}
    try:
        return dataclasses.replace(base, **values)
    except SettingsError as exc:
        key = next((k for k, (name, _) in keys.items() if name == exc.name), None)
        if key in f:
            raise f[key].error(exc.message) from None
        raise node.error(str(exc)) from None


def parse_roadmap(node: YNode) -> RoadmapSettings:
    """A scenario's ``roadmap`` section: its groups (``turns``, ``area_turns``,
    ``multipoint``, ``turnarounds``), each a mapping of that group's keys.

    >>> from lotsim.io.yamlnodes import parse_text
    >>> parse_roadmap(parse_text("turnarounds: {margin: 0.2}", "f.yaml")).turnarounds.margin
    0.2
    >>> parse_roadmap(parse_text("multipoint: {headings: 2}", "f.yaml"))
    Traceback (most recent call last):
      ...
    lotsim.errors.ScenarioError: f.yaml:1:24: multipoint.headings: expected 4 to 720, found 2
    """
    if node.is_null:
        return RoadmapSettings()
    f = node.fields(optional=list(GROUPS))
    return RoadmapSettings(**{name: parse_settings(n, GROUPS[name]) for name, n in f.items()})


def parse_lot_settings(node: YNode) -> LotSettings:
    """A scenario's ``lot.build`` mapping: the keys of :data:`KEYS` for
    :class:`~lotsim.lot.settings.LotSettings`.

    >>> from lotsim.io.yamlnodes import parse_text
    >>> parse_lot_settings(parse_text("crawl_speed_kmh: 1.8", "f.yaml")).crawl_speed
    0.5
    >>> parse_lot_settings(parse_text("sweep: 2", "f.yaml"))
    Traceback (most recent call last):
      ...
    lotsim.errors.ScenarioError: f.yaml:1:8: sweep: expected 0.01 to 1 m, found 2
    """
    return parse_settings(node, LotSettings)


def parse_maneuvers(node: YNode) -> ManeuverSettings:
    """A scenario's ``maneuvers`` section: the keys of :data:`KEYS` for
    :class:`~lotsim.maneuvers.settings.ManeuverSettings`."""
    return parse_settings(node, ManeuverSettings)
