"""A plot file (``docs/layout.md``) → a validated, frozen :class:`~lotsim.design.plot.PlotSpec`.

Read as scenarios are (:mod:`lotsim.io.yamlnodes`): unknown, missing and duplicate keys,
wrong types and numbers YAML misreads are errors, each reported as
``file:line:col: key.path: what was expected, what was found``, every independent one at
once, in file order.
"""

from __future__ import annotations

import math
import os

from shapely.geometry import Point as ShapelyPoint
from shapely.geometry import Polygon
from shapely.validation import explain_validity

from lotsim.core.units import in_units, shown_length
from lotsim.design.plot import (
    ANGLES,
    BAY_LENGTH,
    BAY_WIDTH,
    DEFAULT_WIDTHS,
    GATE_CLEARANCE,
    BuildingEntranceSpec,
    DemandSpec,
    GateSpec,
    IslandSpec,
    PlotSpec,
    UsesSpec,
)
from lotsim.errors import ErrorCollector, ScenarioError
from lotsim.io.lot_yaml import MAX_ITEMS
from lotsim.io.scenario_yaml import name_from_file, parse_vehicle
from lotsim.io.traffic_yaml import parse_dwell
from lotsim.io.yamlnodes import YNode, parse_text, read_yaml, units_of
from lotsim.lot.uses import USES
from lotsim.vehicles.catalogue import CATALOGUE, DEFAULT_VEHICLE

TEXT_FILE = "<plot>"
"""The file name errors give for a plot read from text."""
GATE_TOLERANCE = 0.5
"""A gate lies on the boundary within this distance [m]."""
MAX_SPAN = 2000.0
"""Largest plot, across [m] (as for a scenario's lot)."""
DIRECTIONS = ("two-way", "one-way")
BY_STANDARD = "ada_2010"
"""``uses.accessible`` for as many accessible bays as ADA 2010 Table 208.2 asks."""
MAX_USE_COUNT = 1000
"""Most accessible or EV bays a plot may ask for."""


def read_plot(source: str | os.PathLike) -> PlotSpec:
    """Read and validate a plot file, or plot text (a ``str`` holding a line break; errors
    then name the file ``<plot>``).

    Raises
    ------
    ScenarioError
        Every problem of the file, located (a :class:`~lotsim.errors.ScenarioErrors` when
        there are several).

    Examples
    --------
    >>> plot = read_plot("boundary: [[0, 0], [40, 0], [40, 30], [0, 30]]\\n"
    ...                  "gates: [{id: in, at: [20, 0]}]\\n")
    >>> plot.name, plot.angles, plot.aisle_width(90, "two-way")
    ('plot', (90, 60, 45), 7.0)
    >>> read_plot("boundary: [[0, 0], [40, 0], [40, 30]]\\ngates: [{id: in, at: [20, 5]}]\\n")
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    lotsim.errors.ScenarioError: <plot>:2:22: gates[0].at: expected a point on the boundary ...
    """
    if isinstance(source, str) and "\n" in source:
        return parse_plot(parse_text(source, TEXT_FILE))
    return parse_plot(read_yaml(source))


def parse_plot(root: YNode) -> PlotSpec:
    """Validate a composed plot document."""
    if root.is_mapping:
        for key, _ in root.node.value:
            if getattr(key, "value", None) == "lot":  # a scenario given where a plot belongs
                where = YNode(key, root.file, "lot")
                raise where.error("expected a plot file (docs/layout.md: boundary, gates, "
                                  "...), found a scenario's lot section: lotsim layout lays "
                                  "out a plot, lotsim validate and run read a scenario")
    root = units_of(root)
    f = root.fields(required=["boundary", "gates"],
                    optional=["units", "name", "description", "seed", "islands", "vehicle_types",
                              "bays", "aisles", "demand", "building_entrances", "uses"])
    errors = ErrorCollector()
    name = (errors.attempt(lambda: f["name"].file_name(
        purpose="it names the written scenario"), default="plot")
            if "name" in f else (name_from_file(root.file) if root.file != TEXT_FILE
                                 else "plot"))
    description = (errors.attempt(lambda: f["description"].string(max_len=2000), default="")
                   if "description" in f else "")
    seed = (errors.attempt(lambda: f["seed"].integer(min=0, max=2**63 - 1), default=0)
            if "seed" in f else 0)
    boundary = errors.attempt(_boundary, f["boundary"])
    islands = (tuple(i for i in errors.attempt(_islands, f["islands"], boundary, default=())
                     if i is not None) if "islands" in f else ())
    gates = errors.attempt(_gates, f["gates"], boundary, default=())
    entrances = (errors.attempt(_building_entrances, f["building_entrances"], default=())
                 if "building_entrances" in f else ())
    types, names = (CATALOGUE[DEFAULT_VEHICLE],), (DEFAULT_VEHICLE,)
    if "vehicle_types" in f:
        got = errors.attempt(_vehicle_types, f["vehicle_types"])
        if got is not None:
            types, names = got
    bays = errors.attempt(_bays, f["bays"], default=None) if "bays" in f else None
    angles, width, length, clearance = bays or (ANGLES, BAY_WIDTH, BAY_LENGTH, GATE_CLEARANCE)
    aisles = errors.attempt(_aisles, f["aisles"], default=None) if "aisles" in f else None
    one_way, widths, circulation = aisles or (True, dict(DEFAULT_WIDTHS),
                                              DEFAULT_WIDTHS[(90, "two-way")])
    if bays is not None and not one_way and not any(a == 90 for a in angles):
        errors.attempt(_refuse, f["bays"], "expected 90 among angles_deg when aisles.one_way "
                                           "is false (angled bays need one-way aisles)")
    if "vehicle_types" in f and ("bays" not in f or bays is not None):
        for n, v in zip(f["vehicle_types"].items(), types, strict=False):
            errors.attempt(_fits_bays, n, v, width, length, "bays" in f)
    elif "vehicle_types" not in f and bays is not None:
        errors.attempt(_default_fits_bays, f["bays"], types[0], width, length)
    demand = errors.attempt(_demand, f["demand"], default=None) if "demand" in f else None
    uses = (errors.attempt(_uses, f["uses"], types, width, length, entrances,
                           default=None) if "uses" in f else None)
    errors.check()
    return PlotSpec(name=name, boundary=boundary, gates=gates, vehicle_types=types,
                    islands=islands, angles=angles, bay_width=width, bay_length=length,
                    gate_clearance=clearance,
                    one_way=one_way, aisle_widths=tuple(sorted(widths.items(),
                                                               key=lambda kv: (-kv[0][0],
                                                                               kv[0][1]))),
                    circulation_width=circulation, demand=demand or DemandSpec(),
                    seed=seed, description=description, source=root.file,
                    vehicle_names=names, building_entrances=entrances,
                    uses=uses or UsesSpec(), units=root.units)


def _fits_bays(node: YNode, vehicle, width: float, length: float, given: bool) -> None:
    """Refuse a vehicle type wider or longer than the plot's bays before any layout is
    searched: no bay of any layout would be usable for it."""
    which = "" if given else " (the default)"
    for what, car, bay, key in (("wide", vehicle.width, width, "width"),
                                ("long", vehicle.length, length, "length")):
        if car > bay:
            need = math.ceil(car * 10 - 1e-9) / 10
            raise node.error(f"vehicle type {vehicle.name!r} is {car:.2f} m {what} and the "
                             f"plot's bays {bay:.2f} m{which}: no bay of any layout would "
                             f"be usable for it; it needs bays of at least {car:.2f} m "
                             f"(bays: {{{key}: {need:g}}})")


def _default_fits_bays(node: YNode, vehicle, width: float, length: float) -> None:
    """Refuse bays too small for the default vehicle type (the plot names none) at its
    ``bays`` section, before any layout is searched, with the size they need."""
    for what, car, bay, key in (("wide", vehicle.width, width, "width"),
                                ("long", vehicle.length, length, "length")):
        if car > bay:
            need = math.ceil(in_units(car, node.units) * 10 - 1e-9) / 10
            shown = shown_length(car, node.units, ".2f")
            raise node.error(f"expected bays at least {shown} {what} for the default vehicle "
                             f"type {vehicle.name!r} (the plot names no vehicle_types), found "
                             f"{shown_length(bay, node.units, '.2f')}: no bay of any layout "
                             f"would be usable for it; give bays: {{{key}: {need:g}}}, or "
                             f"vehicle_types that fit")


def _refuse(node: YNode, message: str) -> None:
    raise node.error(message)


def _simple(node: YNode, what: str) -> Polygon:
    pts = node.points(min_len=3)
    if len(pts) > MAX_ITEMS:
        raise node.error(f"expected at most {MAX_ITEMS} points")
    poly = Polygon(pts)
    if not poly.is_valid or poly.area <= 0:
        reason = explain_validity(poly) if poly.area > 0 else "it has no area"
        raise node.error(f"expected {what} to be a simple polygon, but {reason}")
    return poly


def _boundary(node: YNode):
    poly = _simple(node, "the boundary")
    x0, y0, x1, y1 = poly.bounds
    if max(x1 - x0, y1 - y0) > MAX_SPAN:
        u = node.units
        raise node.error(f"expected a plot at most {shown_length(MAX_SPAN, u)} across, found "
                         f"{shown_length(max(x1 - x0, y1 - y0), u, '.0f')} "
                         f"(is the unit {'metres' if u == 'm' else 'feet'}?)")
    return tuple(node.points(min_len=3))


def _islands(node: YNode, boundary) -> tuple[IslandSpec | None, ...]:
    errors = ErrorCollector()
    seen: set[str] = set()
    outline = Polygon(boundary) if boundary is not None else None

    def one(k: int, n: YNode) -> IslandSpec:
        g = n.fields(required=["polygon"], optional=["id"])
        ident = g["id"].ident() if "id" in g else f"island-{k + 1}"
        if ident in seen:
            raise g["id"].error(f"island id {ident!r} is used twice")
        seen.add(ident)
        poly = _simple(g["polygon"], "an island")
        if outline is not None and not outline.contains(poly):
            raise g["polygon"].error("expected an island inside the boundary")
        return IslandSpec(ident, tuple(g["polygon"].points(min_len=3)), n.where)

    items = node.items(max_len=MAX_ITEMS)
    out = tuple(errors.attempt(one, k, n) for k, n in enumerate(items))
    errors.check()
    return out


def _gates(node: YNode, boundary) -> tuple[GateSpec, ...]:
    errors = ErrorCollector()
    seen: set[str] = set()
    edge = Polygon(boundary).exterior if boundary is not None else None

    def one(n: YNode) -> GateSpec:
        g = n.fields(required=["id", "at"])
        ident = g["id"].ident()
        if ident in seen:
            raise g["id"].error(f"gate id {ident!r} is used twice")
        seen.add(ident)
        at = g["at"].point()
        if edge is not None:
            d = edge.distance(ShapelyPoint(at))
            if d > GATE_TOLERANCE:
                u = g["at"].units
                raise g["at"].error(f"expected a point on the boundary (within "
                                    f"{shown_length(GATE_TOLERANCE, u)}), found one "
                                    f"{shown_length(d, u, '.2f')} from it")
        return GateSpec(ident, at, n.where)

    out = tuple(errors.attempt(one, n) for n in node.items(min_len=1, max_len=100))
    errors.check()
    return tuple(g for g in out if g is not None)


def _building_entrances(node: YNode) -> tuple[BuildingEntranceSpec, ...]:
    errors = ErrorCollector()
    seen: set[str] = set()

    def one(n: YNode) -> BuildingEntranceSpec:
        g = n.fields(required=["id", "at"])
        ident = g["id"].ident()
        if ident in seen:
            raise g["id"].error(f"building entrance id {ident!r} is used twice")
        seen.add(ident)
        return BuildingEntranceSpec(ident, g["at"].point(), n.where)

    out = tuple(errors.attempt(one, n) for n in node.items(max_len=100))
    errors.check()
    return tuple(e for e in out if e is not None)


def _vehicle_types(node: YNode):
    errors = ErrorCollector()
    items = node.items(min_len=1, max_len=20)
    types, names = [], []
    for n in items:
        t = errors.attempt(parse_vehicle, n)
        if t is None:
            continue
        if t.name in {v.name for v in types}:
            errors.attempt(_refuse, n, f"vehicle type {t.name!r} is given twice")
            continue
        types.append(t)
        names.append("" if n.is_mapping else t.name)
    errors.check()
    return tuple(types), tuple(names)


def _bays(node: YNode):
    f = node.fields(optional=["angles_deg", "width", "length", "gate_clearance"])
    angles = ANGLES
    if "angles_deg" in f:
        got = []
        for n in f["angles_deg"].items(min_len=1, max_len=3):
            a = n.integer()
            if a not in ANGLES:
                raise n.error(f"expected one of {', '.join(map(str, ANGLES))}, found {a}")
            if a in got:
                raise n.error(f"angle {a} is given twice")
            got.append(a)
        angles = tuple(sorted(got, reverse=True))
    width = f["width"].length(min=1.5, max=5.0) if "width" in f else BAY_WIDTH
    length = f["length"].length(min=3.0, max=12.0) if "length" in f else BAY_LENGTH
    clearance = (f["gate_clearance"].length(min=0.0, max=100.0) if "gate_clearance" in f
                 else GATE_CLEARANCE)
    return angles, width, length, clearance


def _aisles(node: YNode):
    f = node.fields(optional=["one_way", "widths", "circulation"])
    one_way = f["one_way"].boolean() if "one_way" in f else True
    widths = dict(DEFAULT_WIDTHS)
    if "widths" in f:
        per_angle = f["widths"].fields(optional=[str(a) for a in ANGLES])
        for key, n in per_angle.items():
            angle = int(key)
            allowed = DIRECTIONS if angle == 90 else ("one-way",)
            g = n.fields(optional=list(allowed))
            for direction, w in g.items():
                widths[(angle, direction)] = w.length(min=3.0, max=20.0)
    circulation = (f["circulation"].length(min=4.0, max=20.0) if "circulation" in f
                   else widths[(90, "two-way")])
    return one_way, widths, circulation


def _uses(node: YNode, types, width: float, length: float, entrances) -> UsesSpec:
    """The ``uses`` section: each bad value an error at its place, every one at once; a use
    no vehicle type of the plot may park in, or one the plot's bays are too narrow for, is
    refused at once (no layout could verify its bays)."""
    f = node.fields(optional=["accessible", "van_accessible", "ev", "compact"])
    errors = ErrorCollector()
    marked = {m: [v.name for v in types if m in v.marks] for m in ("accessible", "ev")}

    def needs(key: str, mark: str) -> None:
        if not marked[mark]:
            raise f[key].error(f"no vehicle type of the plot is marked {mark}: true, so no "
                               f"car could park in these bays and no layout could check "
                               f"them: add one to vehicle_types (a definition with "
                               f"{mark}: true)")
        if not entrances:
            raise f[key].error("the plot names no building_entrances: the layout puts "
                               "these bays nearest one")

    def accessible() -> int | None:
        n = f["accessible"]
        value = _count(n, f"{BY_STANDARD} (as ADA 2010 Table 208.2 asks) or a count")
        if value == 0:
            return 0
        needs("accessible", "accessible")
        problem = USES["accessible"].size_problem(width, None)
        if problem is not None:
            raise n.error(f"{problem}: the plot's bays are too narrow (bays: {{width: 2.44}}"
                          f" or more)")
        return value

    failed = -1  # accessible is wrong already: said once, not again for van_accessible
    got = errors.attempt(accessible, default=failed) if "accessible" in f else 0

    def van() -> int:
        n = f["van_accessible"]
        value = n.integer(min=0, max=MAX_USE_COUNT)
        if got == failed:
            return value
        if got == 0 and value:
            raise n.error("expected van-accessible bays only among accessible ones: give "
                          "uses.accessible too")
        if got is not None and value > got:
            raise n.error(f"expected at most the {got} accessible bays asked for (a "
                          f"van-accessible bay is one of them), found {value}")
        return value

    vans = errors.attempt(van, default=None) if "van_accessible" in f else None

    def ev() -> tuple[int, float | None]:
        n = f["ev"]
        raw = n.node.value if not n.is_mapping and not n.is_sequence else None
        if isinstance(raw, str) and n.node.tag.endswith(":str") and raw.strip().endswith("%"):
            try:
                share = float(raw.strip()[:-1])
            except ValueError:
                share = math.nan
            if not 0 <= share <= 100:
                raise n.error(f"expected a share of 0% to 100% (\"10%\"), found {raw!r}")
            if share:
                needs("ev", "ev")
            return 0, share / 100
        value = _count(n, 'a count or a share of the total ("10%")', word=None)
        if value:
            needs("ev", "ev")
        return value, None

    ev_count, ev_share = errors.attempt(ev, default=(0, None)) if "ev" in f else (0, None)
    compact = (errors.attempt(_compact, f["compact"], types, width, length, default=None)
               if "compact" in f else None)
    errors.check()
    return UsesSpec(accessible=got, van_accessible=vans, ev=ev_count, ev_share=ev_share,
                    compact=compact, where=node.where)


def _count(node: YNode, what: str, word: str | None = BY_STANDARD) -> int | None:
    """A count of bays, or (``word``) None for as many as the standard asks."""
    if word is not None and node.node.tag.endswith(":str") and node.node.value == word:
        return None
    if not node.node.tag.endswith(":int"):
        raise node.error(f"expected {what}, found {node.node.value!r}")
    return node.integer(min=0, max=MAX_USE_COUNT)


def _compact(node: YNode, types, width: float, length: float) -> tuple[float, float]:
    f = node.fields(required=["width", "length"])
    w = f["width"].length(min=1.5, max=5.0)
    ln = f["length"].length(min=3.0, max=12.0)
    if w > width + 1e-9 or ln > length + 1e-9 or (w >= width - 1e-9 and ln >= length - 1e-9):
        raise node.error(f"expected a compact bay smaller than the plot's bays ({width:g} × "
                         f"{length:g} m), found {w:g} × {ln:g} m")
    fits = [v.name for v in types if v.width <= w + 1e-9 and v.length <= ln + 1e-9]
    if not fits:
        sizes = ", ".join(f"{v.name} {v.length:.2f} × {v.width:.2f} m" for v in types)
        raise node.error(f"no vehicle type of the plot fits a compact bay of {ln:g} × {w:g} "
                         f"m ({sizes}), so no car could park in one: add a smaller type to "
                         f"vehicle_types (zoe, corsa) or give a larger compact bay")
    return w, ln


def _demand(node: YNode) -> DemandSpec:
    f = node.fields(optional=["count", "rate_per_hour", "dwell"])
    dwell = parse_dwell(f["dwell"]) if "dwell" in f else None
    base = DemandSpec()
    return DemandSpec(
        count=f["count"].integer(min=1, max=1000) if "count" in f else base.count,
        rate_per_hour=(f["rate_per_hour"].number(positive=True, max=1e5)
                       if "rate_per_hour" in f else base.rate_per_hour),
        dwell=dwell, where=node.where)


__all__ = ["read_plot", "parse_plot", "ScenarioError"]
