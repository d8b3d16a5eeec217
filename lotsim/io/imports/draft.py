"""A lot as an importer builds it, written as a scenario YAML a person can read and edit.

An importer fills a :class:`LotDraft` (aisles, rows and single slots, areas, gates, what is
paved, a default traffic) in local metres and calls :meth:`LotDraft.to_yaml`; for a lot that
maps no aisles, a :class:`PlotDraft` (outline, islands, gates), written as a plot file for
``lotsim layout``. The text is
deterministic: the same draft gives the same bytes (numbers to the centimetre, or the
hundredth of a degree, in the order the draft holds them), and it says in comments where
each item came from.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from lotsim.core.units import LENGTH_UNITS

Point = tuple[float, float]

_PLAIN = re.compile(r"[A-Za-z_][A-Za-z0-9_.-]*")
_RESERVED = {"true", "false", "yes", "no", "on", "off", "null", "y", "n", "~"}


def num(value: float, places: int = 2) -> str:
    """A number as a scenario writes it: at most ``places`` decimals, no trailing zeros,
    never ``-0``, always read by YAML as a number.

    >>> num(3.0), num(-0.001), num(2.345), num(1e5)
    ('3', '0', '2.35', '100000')
    """
    if not math.isfinite(value):
        raise ValueError(f"not a finite number: {value!r}")
    text = f"{round(value, places):.{places}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def text(value: str) -> str:
    """A string as YAML reads it back unchanged: bare when plain, else double-quoted.

    >>> text("A1"), text("way 12"), text("yes"), text("12")
    ('A1', '"way 12"', '"yes"', '"12"')
    """
    if _PLAIN.fullmatch(value) and value.lower() not in _RESERVED:
        return value
    return json.dumps(value, ensure_ascii=False)


def points(pts: Sequence[Point], places: int = 2) -> str:
    """``[[x, y], ...]`` in one flow line, to ``places`` decimals."""
    return "[" + ", ".join(f"[{num(x, places)}, {num(y, places)}]" for x, y in pts) + "]"


def comment(line: str) -> str:
    """``line`` as one YAML comment line (line breaks folded)."""
    return "# " + " ".join(line.split())


@dataclass
class AisleDraft:
    """An aisle: its centre line [m], width [m], one-way or two-way; ``note`` says where it
    came from."""

    id: str
    centerline: list[Point]
    width: float
    one_way: bool = False
    note: str = ""


@dataclass
class RowDraft:
    """A row of slots along one side of an aisle (``docs/scenario.md``, ``rows``)."""

    aisle: str
    side: str
    kind: str
    count: int
    slot_width: float
    slot_length: float
    start: float
    id_prefix: str
    angle_deg: float | None = None
    gap: float = 0.0
    note: str = ""
    first_number: int = 1
    use: str = "standard"
    """What its bays are for (``docs/scenario.md``, bays by use)."""


@dataclass
class SlotDraft:
    """A free-standing slot: its centre [m] and the heading of a car that drove in forward
    [degrees]; an angled one also its angle to the aisle it opens onto [degrees]."""

    id: str
    kind: str
    width: float
    length: float
    center: Point
    heading_deg: float
    note: str = ""
    angle_deg: float | None = None

    def __post_init__(self) -> None:
        if (self.kind == "angled") != (self.angle_deg is not None):
            raise ValueError(f"slot {self.id}: an angled slot, and only one, has an angle")


@dataclass
class AreaDraft:
    """A polygon: a wall, an obstacle, a no-go zone or a paved area."""

    id: str
    polygon: list[Point]
    note: str = ""


@dataclass
class GateDraft:
    """An entrance or an exit: a pose on a lane, heading its way [m, m, degrees]."""

    id: str
    x: float
    y: float
    heading_deg: float
    note: str = ""


@dataclass
class LotDraft:
    """One imported lot, ready to be written as a scenario.

    ``header`` lines open the file as comments (the source, its id and tags, the projection
    and its error). ``paved`` is None for a lot paved wall to wall; else the lot's aisles
    (``paved_aisles``) and slots plus the ``paved`` areas are its pavement.
    ``traffic`` is the ``traffic`` section as plain data (None: none).
    """

    name: str
    description: str
    boundary: list[Point]
    header: list[str] = field(default_factory=list)
    vehicle_types: list[str] = field(default_factory=lambda: ["valet"])
    speed_limit_kmh: float | None = None
    aisles: list[AisleDraft] = field(default_factory=list)
    rows: list[RowDraft] = field(default_factory=list)
    slots: list[SlotDraft] = field(default_factory=list)
    walls: list[AreaDraft] = field(default_factory=list)
    obstacles: list[AreaDraft] = field(default_factory=list)
    no_go: list[AreaDraft] = field(default_factory=list)
    paved: list[AreaDraft] | None = None
    paved_aisles: bool = True
    entrances: list[GateDraft] = field(default_factory=list)
    exits: list[GateDraft] = field(default_factory=list)
    occupied: list[str] = field(default_factory=list)
    traffic: dict | None = None
    building_entrances: list[tuple[str, Point]] = field(default_factory=list)
    """(id, point): the doors of the buildings the lot serves."""
    units: str | None = None
    """The unit the file states (``units: ft``, of :data:`~lotsim.core.units.LENGTH_UNITS`)
    and writes its lengths in; None: metres, unstated. The draft holds metres either way."""
    places: int = 2
    """Decimals of the lengths written (2, the centimetre, in metres)."""

    @property
    def slot_count(self) -> int:
        """Slots drawn: the rows' and the single ones."""
        return sum(r.count for r in self.rows) + len(self.slots)

    def to_yaml(self) -> str:
        """The scenario text (``docs/scenario.md``), deterministic, ending in a line break,
        its lengths in :attr:`units`.

        >>> d = LotDraft("p", "", [(0, 0), (3.048, 0), (3.048, 3.048)], units="ft")
        >>> for line in d.to_yaml().splitlines()[:6]:
        ...     print(line)
        units: ft
        name: p
        description: ""
        vehicle_types: [valet]
        lot:
          boundary: [[0, 0], [10, 0], [10, 10]]
        """
        k = 1.0 / LENGTH_UNITS[self.units or "m"]

        def n(value: float) -> str:
            return num(value * k, self.places)

        def pts(ring: Sequence[Point]) -> str:
            return points([(x * k, y * k) for x, y in ring], self.places)

        def areas(items: Sequence[AreaDraft], indent: str) -> list[str]:
            return _areas([AreaDraft(a.id, [(x * k, y * k) for x, y in a.polygon], a.note)
                           for a in items], indent, self.places)

        out = [comment(h) for h in self.header]
        if self.units is not None:
            out.append(f"units: {self.units}")
        out += [f"name: {text(self.name)}", f"description: {text(self.description)}",
                "vehicle_types: [" + ", ".join(text(v) for v in self.vehicle_types) + "]",
                "lot:", f"  boundary: {pts(self.boundary)}"]
        if self.speed_limit_kmh is not None:
            out.append(f"  speed_limit_kmh: {num(self.speed_limit_kmh)}")
        if self.paved is not None:
            out.append("  paved:")
            out.append(f"    aisles: {'true' if self.paved_aisles else 'false'}")
            if self.paved:
                out.append("    areas:")
                out += areas(self.paved, "      ")
        out.append("  aisles:")
        for a in self.aisles:
            if a.note:
                out.append("    " + comment(a.note))
            out.append(f"    - {{id: {text(a.id)}, width: {n(a.width)}, direction: "
                       f"{'one-way' if a.one_way else 'two-way'},")
            out.append(f"       centerline: {pts(a.centerline)}}}")
        if self.rows:
            out.append("  rows:")
            for r in self.rows:
                if r.note:
                    out.append("    " + comment(r.note))
                angle = f", angle_deg: {num(r.angle_deg)}" if r.angle_deg is not None else ""
                gap = f", gap: {n(r.gap)}" if r.gap else ""
                first = f", first_number: {r.first_number}" if r.first_number != 1 else ""
                use = f", use: {r.use}" if r.use != "standard" else ""
                out.append(f"    - {{aisle: {text(r.aisle)}, side: {r.side}, kind: {r.kind}"
                           f"{angle}, count: {r.count}, slot_width: {n(r.slot_width)}, "
                           f"slot_length: {n(r.slot_length)}, start: {n(r.start)}{gap}, "
                           f"id_prefix: {text(r.id_prefix)}{first}{use}}}")
        if self.slots:
            out.append("  slots:")
            for s in self.slots:
                if s.note:
                    out.append("    " + comment(s.note))
                angle = f", angle_deg: {num(s.angle_deg)}" if s.angle_deg is not None else ""
                out.append(f"    - {{id: {text(s.id)}, kind: {s.kind}{angle}, "
                           f"width: {n(s.width)}, length: {n(s.length)}, "
                           f"center: {pts([s.center])[1:-1]}, "
                           f"heading_deg: {num(s.heading_deg)}}}")
        for key, items in (("walls", self.walls), ("obstacles", self.obstacles),
                           ("no_go", self.no_go)):
            if items:
                out.append(f"  {key}:")
                out += areas(items, "    ")
        for key, gates in (("entrances", self.entrances), ("exits", self.exits)):
            if gates:
                out.append(f"  {key}:")
                for g in gates:
                    if g.note:
                        out.append("    " + comment(g.note))
                    out.append(f"    - {{id: {text(g.id)}, x: {n(g.x)}, y: {n(g.y)}, "
                               f"heading_deg: {num(g.heading_deg)}}}")
        if self.building_entrances:
            out.append("  building_entrances:")
            for ident, (x, y) in self.building_entrances:
                out.append(f"    - {{id: {text(ident)}, x: {n(x)}, y: {n(y)}}}")
        if self.occupied:
            out.append("  occupied: [" + ", ".join(text(s) for s in self.occupied) + "]")
        if self.traffic is not None:
            out.append("traffic:")
            out += _plain_yaml(self.traffic, "  ")
        return "\n".join(out) + "\n"


def _areas(items: Sequence[AreaDraft], indent: str, places: int = 2) -> list[str]:
    out = []
    for a in items:
        if a.note:
            out.append(indent + comment(a.note))
        out.append(f"{indent}- {{id: {text(a.id)}, polygon: {points(a.polygon, places)}}}")
    return out


def _scalar(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return num(value)
    if isinstance(value, str):
        return text(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_scalar(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{text(k)}: {_scalar(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"cannot write {type(value).__name__} into a scenario")


def _plain_yaml(data: dict, indent: str) -> list[str]:
    """A mapping of plain data as block YAML: mappings as blocks, lists in flow."""
    out = []
    for key, value in data.items():
        if isinstance(value, dict):
            out.append(f"{indent}{text(key)}:")
            out += _plain_yaml(value, indent + "  ")
        else:
            out.append(f"{indent}{text(key)}: {_scalar(value)}")
    return out


@dataclass
class PlotDraft:
    """A lot's plot, for a source that maps no aisles: its outline, the islands to keep
    clear and its gates, in local metres, written as a plot file (``docs/layout.md``) that
    ``lotsim layout`` lays out. ``header`` lines open the file as comments; ``demand`` is the
    plot's ``demand`` section as plain data (None: the default)."""

    name: str
    description: str
    boundary: list[Point]
    gates: list[tuple[str, Point, str]] = field(default_factory=list)
    """(id, point on the boundary, where it came from)."""
    islands: list[AreaDraft] = field(default_factory=list)
    header: list[str] = field(default_factory=list)
    demand: dict | None = None
    building_entrances: list[tuple[str, Point, str]] = field(default_factory=list)
    """(id, point, where it came from)."""
    places: int = 2
    """Decimals of the coordinates written: 2 (the centimetre) for a map's plot, 3 (the
    millimetre, or the thousandth of a foot) for a CAD drawing's."""
    units: str | None = None
    """The unit the file states (``units: ft``, of :data:`~lotsim.core.units.LENGTH_UNITS`)
    and writes its coordinates in; None: metres, unstated. The draft holds metres either
    way."""

    def to_yaml(self) -> str:
        """The plot text, deterministic, ending in a line break.

        >>> print(PlotDraft("p", "", [(0, 0), (3.048, 0), (3.048, 3.048)],
        ...                 units="ft").to_yaml(), end="")
        units: ft
        name: p
        description: ""
        boundary: [[0, 0], [10, 0], [10, 10]]
        gates:
        """
        k = 1.0 / LENGTH_UNITS[self.units or "m"]

        def pts(ring: Sequence[Point]) -> str:
            return points([(x * k, y * k) for x, y in ring], self.places)

        out = [comment(h) for h in self.header]
        if self.units is not None:
            out.append(f"units: {self.units}")
        out += [f"name: {text(self.name)}", f"description: {text(self.description)}",
                f"boundary: {pts(self.boundary)}"]
        if self.islands:
            out.append("islands:")
            out += _areas([AreaDraft(a.id, [(x * k, y * k) for x, y in a.polygon], a.note)
                           for a in self.islands], "  ", self.places)
        for key, items in (("gates", self.gates),
                           ("building_entrances", self.building_entrances)):
            if not items and key != "gates":
                continue
            out.append(f"{key}:")
            for ident, (x, y), note in items:
                if note:
                    out.append("  " + comment(note))
                out.append(f"  - {{id: {text(ident)}, at: [{num(x * k, self.places)}, "
                           f"{num(y * k, self.places)}]}}")
        if self.demand is not None:
            out.append("demand:")
            out += _plain_yaml(self.demand, "  ")
        return "\n".join(out) + "\n"
