"""The ``lot`` section of a scenario YAML → a validated, frozen :class:`~lotsim.lot.spec.LotSpec`
(boundary, pavement, aisles, rows and slots, areas, speed bumps and zones, entrances and exits,
occupancy), with the limits on a lot's size. Part of :mod:`lotsim.io.scenario_yaml`.
"""

from __future__ import annotations

import itertools
import math

from lotsim.core.units import shown_length
from lotsim.errors import ErrorCollector, ScenarioError
from lotsim.io.settings_yaml import parse_lot_settings
from lotsim.io.yamlnodes import YNode
from lotsim.lot.kinds import KINDS
from lotsim.lot.settings import LotSettings
from lotsim.lot.spec import (
    SIDES,
    SLOT_KINDS,
    AisleSpec,
    AreaSpec,
    BuildingEntranceSpec,
    LotSpec,
    OccupancySpec,
    PavementSpec,
    PortalSpec,
    Requirement,
    RowSpec,
    SlotSpec,
    SpeedBumpSpec,
    SpeedZoneSpec,
    StandardSpec,
)
from lotsim.lot.uses import ADA_2010, STANDARD, USES
from lotsim.vehicles.model import KMH

MAX_ITEMS = 100_000
"""Largest list a scenario may hold (slots in a row, polygon points, ...)."""


def _polygon(node: YNode) -> tuple[tuple[float, float], ...]:
    pts = node.points(min_len=3)
    if len(pts) > MAX_ITEMS:
        raise node.error(f"expected at most {MAX_ITEMS} points")
    return pts


def speed(node: YNode) -> float:
    """Read a speed in km/h → m/s."""
    return node.number(positive=True, max=200) * KMH


def parse_lot(node: YNode) -> LotSpec:
    """Validate the ``lot`` mapping."""
    f = node.fields(
        required=["boundary", "aisles"],
        optional=[
            "speed_limit_kmh",
            "rows",
            "slots",
            "walls",
            "obstacles",
            "no_go",
            "speed_bumps",
            "speed_zones",
            "entrances",
            "exits",
            "occupied",
            "paved",
            "building_entrances",
            "standard",
            "build",
        ],
    )

    errors = ErrorCollector()  # each item on its own: a user sees every broken one at once

    def each(key: str, parse, min_len: int = 0):  # type: ignore[no-untyped-def]
        if key not in f:
            return ()
        items = errors.attempt(lambda: f[key].items(min_len=min_len, max_len=MAX_ITEMS),
                               default=[])
        return tuple(errors.attempt(parse, n) for n in items)

    def one(key: str, parse, default):  # type: ignore[no-untyped-def]
        return errors.attempt(parse, f[key], default=default) if key in f else default

    areas = (
        each("walls", lambda n: _area(n, "wall"))
        + each("obstacles", lambda n: _area(n, "obstacle"))
        + each("no_go", lambda n: _area(n, "no_go"))
    )
    parts = dict(
        boundary=one("boundary", _polygon, ()),
        aisles=each("aisles", _aisle, min_len=1),
        rows=each("rows", _row),
        slots=each("slots", _slot),
        areas=areas,
        speed_bumps=each("speed_bumps", _bump),
        speed_zones=each("speed_zones", _zone),
        entrances=each("entrances", _portal),
        exits=each("exits", _portal),
        occupancy=one("occupied", _occupancy, OccupancySpec()),
        speed_limit=one("speed_limit_kmh", speed, 20 * KMH),
        paved=one("paved", _pavement, None),
        building_entrances=each("building_entrances", _building_entrance),
        standard=one("standard", _standard, None),
        settings=one("build", parse_lot_settings, LotSettings()),
    )
    errors.check()
    spec = LotSpec(**parts, where=node.where, boundary_where=f["boundary"].where)
    _check_unique_ids(f, spec)
    _check_size(f, spec)
    return spec


MAX_LOT_SIZE = 2000.0
"""Longest side of the boundary's bounding box lotsim plans [m] (16 × the large lot)."""
MAX_AISLE_LENGTH = 20_000.0
"""Total length of the aisles' centrelines lotsim plans [m]."""
MAX_SLOTS = 20_000
"""Slots lotsim plans in one lot: 20 × the large lot, about 80 s and 300 MB to build."""


def _check_size(f: dict[str, YNode], spec: LotSpec) -> None:
    """Refuse lots too big to build and plan on one machine in reasonable time, with the
    first value that crosses a limit (the limits are measured, see docs/scenario.md)."""
    xs, ys = zip(*spec.boundary, strict=True)
    size = max(max(xs) - min(xs), max(ys) - min(ys))
    if size > MAX_LOT_SIZE:
        u = f["boundary"].units
        raise f["boundary"].error(f"the lot is {shown_length(size, u, ',.0f')} across; lotsim "
                                  f"plans lots of at most {shown_length(MAX_LOT_SIZE, u, ',.0f')}"
                                  f" (is the unit {'metres' if u == 'm' else 'feet'}?)")
    total = 0.0
    for a in spec.aisles:
        total += sum(math.dist(p, q) for p, q in itertools.pairwise(a.centerline))
        if total > MAX_AISLE_LENGTH:
            u = f["aisles"].units
            raise ScenarioError(a.where, f"the aisles are {shown_length(total, u, ',.0f')} long "
                                f"up to here; lotsim plans lots with at most "
                                f"{shown_length(MAX_AISLE_LENGTH, u, ',.0f')} of aisle")
    slots = len(spec.slots)
    for r in spec.rows:
        slots += r.count
        if slots > MAX_SLOTS:
            raise ScenarioError(r.where, f"the lot has {slots:,} slots up to this row; lotsim "
                                f"plans lots of at most {MAX_SLOTS:,} slots")


def _check_unique_ids(f: dict[str, YNode], spec: LotSpec) -> None:
    for key, items in (("aisles", spec.aisles), ("entrances", spec.entrances),
                       ("exits", spec.exits), ("building_entrances", spec.building_entrances)):
        seen: set[str] = set()
        for item in items:
            if item.id in seen:
                raise ScenarioError(item.where, f"{key[:-1]} id {item.id!r} is used twice")
            seen.add(item.id)


def _aisle(node: YNode) -> AisleSpec:
    f = node.fields(
        required=["id", "centerline", "width"], optional=["direction", "bend_radius"]
    )
    line = f["centerline"].points(min_len=2)
    for i in range(1, len(line)):
        if math.dist(line[i - 1], line[i]) < 1e-6:
            raise f["centerline"].items()[i].error("expected a point apart from the one before")
    direction = (
        f["direction"].string(choices=["two-way", "one-way"]) if "direction" in f else "two-way"
    )
    return AisleSpec(
        id=f["id"].ident(),
        centerline=line,
        width=f["width"].length(positive=True, max=100),
        one_way=direction == "one-way",
        bend_radius=f["bend_radius"].length(positive=True) if "bend_radius" in f else None,
        where=node.where,
    )


def _kind_angle(f: dict[str, YNode], node: YNode) -> float:
    """The slot angle [rad]: fixed by the ``kind`` (:attr:`SlotKind.fixed_angle`), or given
    as ``angle_deg`` for a kind that does not fix it (angled)."""
    kind = KINDS[f["kind"].string(choices=SLOT_KINDS)]
    if kind.fixed_angle is None:
        if "angle_deg" not in f:
            raise node.error(f"missing key 'angle_deg': an {kind.name} slot needs its angle "
                             f"(0 to 90)")
        return math.radians(
            f["angle_deg"].number(min=0, max=90, open_min=True, open_max=True,
                                  unit="deg", least=10)
        )
    if "angle_deg" in f:
        raise f["angle_deg"].error(
            f"angle_deg applies to angled slots only; a {kind.name} slot's angle is fixed"
        )
    return kind.fixed_angle


def _row(node: YNode) -> RowSpec:
    f = node.fields(
        required=["aisle", "side", "kind", "count", "slot_width", "slot_length", "start"],
        optional=["angle_deg", "gap", "id_prefix", "first_number", "use",
                  "access_aisle_width"],
    )
    angle = _kind_angle(f, node)
    return RowSpec(
        aisle=f["aisle"].ident(),
        side=f["side"].string(choices=SIDES),
        kind=f["kind"].string(),
        angle=angle,
        count=f["count"].integer(min=1, max=MAX_ITEMS),
        slot_width=f["slot_width"].length(positive=True, max=50),
        slot_length=f["slot_length"].length(positive=True, max=50),
        start=f["start"].length(min=0),
        gap=f["gap"].length(min=0) if "gap" in f else 0.0,
        id_prefix=f["id_prefix"].string(max_len=40) if "id_prefix" in f else "",
        first_number=f["first_number"].integer(min=0) if "first_number" in f else 1,
        where=node.where,
        angle_where=f["angle_deg"].where if "angle_deg" in f else None,
        **_use(f),
    )


def _slot(node: YNode) -> SlotSpec:
    f = node.fields(
        required=["id", "kind", "width", "length"],
        optional=["angle_deg", "aisle", "side", "at", "center", "heading_deg", "use",
                  "access_aisle_width", "access_side"],
    )
    along = [k for k in ("aisle", "side", "at") if k in f]
    free = [k for k in ("center", "heading_deg") if k in f]
    if along and free:
        raise f[free[0]].error(
            "a slot is placed either along an aisle (aisle, side, at) "
            "or on its own (center, heading_deg), not both"
        )
    wanted = ("aisle", "side", "at") if along or not free else ("center", "heading_deg")
    missing = [k for k in wanted if k not in f]
    if missing:
        raise node.error(f"missing key {missing[0]!r}; a slot needs {', '.join(wanted)}")
    angle = _kind_angle(f, node)
    common = dict(
        id=f["id"].ident(),
        kind=f["kind"].string(),
        width=f["width"].length(positive=True, max=50),
        length=f["length"].length(positive=True, max=50),
        angle=angle,
        where=node.where,
        **_use(f),
    )
    if "access_side" in f:
        if not USES[common["use"]].accessible:
            raise f["access_side"].error("access_side is for accessible and van-accessible "
                                         "bays, which carry an access aisle")
        common["access_side"] = f["access_side"].string(choices=SIDES)
    if along:
        return SlotSpec(
            **common,
            aisle=f["aisle"].ident(),
            side=f["side"].string(choices=SIDES),
            at=f["at"].length(min=0),
        )
    return SlotSpec(
        **common,
        center=f["center"].point(),
        heading=math.radians(f["heading_deg"].number(min=-360, max=360)),
    )


def _use(f: dict[str, YNode]) -> dict:
    """A row's or slot's ``use`` (:data:`~lotsim.lot.uses.USES`) and the width of its
    access aisle, if given."""
    use = f["use"].string(choices=list(USES)) if "use" in f else STANDARD
    out: dict = {"use": use}
    if "access_aisle_width" in f:
        node = f["access_aisle_width"]
        if not USES[use].accessible:
            raise node.error(f"access_aisle_width is for accessible and van-accessible bays; "
                             f"this one's use is {use}")
        out["access_aisle_width"] = node.length(positive=True, max=20)
    return out


def _building_entrance(node: YNode) -> BuildingEntranceSpec:
    f = node.fields(required=["id", "x", "y"])
    return BuildingEntranceSpec(id=f["id"].ident(), point=(f["x"].length(), f["y"].length()),
                                where=node.where)


def _standard(node: YNode) -> StandardSpec:
    """``standard: ADA 2010`` (built in), or ``{name: ..., require: {USE: {count: N} or
    {share: S}, ...}}``: a table the user states."""
    if not node.is_mapping:
        name = node.string(choices=[ADA_2010])
        return StandardSpec(name, where=node.where)
    f = node.fields(required=["name", "require"])
    name = f["name"].string(max_len=100)
    rows = f["require"].fields(optional=list(USES))
    if not rows:
        raise f["require"].error(f"expected at least one use of bay: {', '.join(USES)}")
    out = []
    for use, n in rows.items():
        g = n.fields(optional=["count", "share"])
        if len(g) != 1:
            raise n.error("expected one of count (bays) or share (of all bays, 0 to 1)")
        out.append(Requirement(use, count=g["count"].integer(min=0, max=MAX_ITEMS))
                   if "count" in g else Requirement(use, share=g["share"].number(min=0, max=1)))
    return StandardSpec(name, tuple(out), where=node.where)


def _area(node: YNode, kind: str) -> AreaSpec:
    f = node.fields(required=["polygon"], optional=["id"])
    ident = f["id"].ident() if "id" in f else f"{kind}@{node.where.line}"
    return AreaSpec(id=ident, kind=kind, polygon=_polygon(f["polygon"]), where=node.where)


def _pavement(node: YNode) -> PavementSpec:
    f = node.fields(optional=["aisles", "corner_radius", "areas"])
    areas = tuple(_area(n, "paved") for n in f["areas"].items(max_len=MAX_ITEMS)) \
        if "areas" in f else ()
    aisles = f["aisles"].boolean() if "aisles" in f else True
    if not aisles and not areas:
        raise node.error("expected paved areas when the aisles are not paved "
                         "(aisles: false): list them under areas")
    return PavementSpec(
        aisles=aisles,
        corner_radius=f["corner_radius"].length(min=0, max=50) if "corner_radius" in f else 3.0,
        areas=areas, where=node.where)


def _bump(node: YNode) -> SpeedBumpSpec:
    f = node.fields(required=["line"], optional=["id", "limit_kmh", "reach"])
    line = f["line"].points(min_len=2)
    return SpeedBumpSpec(
        id=f["id"].ident() if "id" in f else f"bump@{node.where.line}",
        line=line,
        limit=speed(f["limit_kmh"]) if "limit_kmh" in f else 10 * KMH,
        reach=f["reach"].length(min=0, max=100) if "reach" in f else 5.0,
        where=node.where,
    )


def _zone(node: YNode) -> SpeedZoneSpec:
    f = node.fields(required=["polygon", "limit_kmh"], optional=["id"])
    return SpeedZoneSpec(
        id=f["id"].ident() if "id" in f else f"zone@{node.where.line}",
        polygon=_polygon(f["polygon"]),
        limit=speed(f["limit_kmh"]),
        where=node.where,
    )


def _portal(node: YNode) -> PortalSpec:
    f = node.fields(required=["id", "x", "y", "heading_deg"])
    return PortalSpec(
        id=f["id"].ident(),
        pose=(
            f["x"].length(),
            f["y"].length(),
            math.radians(f["heading_deg"].number(min=-360, max=360)),
        ),
        where=node.where,
    )


def _occupancy(node: YNode) -> OccupancySpec:
    if node.is_sequence:
        items = node.items(max_len=MAX_ITEMS)
        ids = tuple(n.ident() for n in items)
        return OccupancySpec(ids=ids, where=node.where, id_where=tuple(n.where for n in items))
    f = node.fields(required=["fraction"], optional=["seed", "min_free"])
    return OccupancySpec(
        fraction=f["fraction"].number(min=0, max=1),
        seed=f["seed"].integer(min=0, max=2**63 - 1) if "seed" in f else 0,
        min_free=f["min_free"].integer(min=0) if "min_free" in f else 1,
        where=node.where,
    )
