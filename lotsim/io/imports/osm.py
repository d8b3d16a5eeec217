"""OpenStreetMap lots as scenarios: :func:`osm_scenarios` (``lotsim import osm FILE -o DIR``).

Every ``amenity=parking`` object of the file is a lot. An area (a closed way, or a
multipolygon relation of one outer ring and inner rings, the islands) becomes one scenario
``<out_dir>/<kind>-<id>.yaml`` in local metres (:class:`~lotsim.io.imports.frame.TangentPlane`
at the lot's centroid); a lot mapped as a point, an open way, a lot the extract clips (a
member way or node missing), and a lot with no parking aisle are reported, with the reason,
and not written.

What a scenario holds, and where it comes from:

* aisles: the lot's ``service=parking_aisle`` ways and the service roads that meet them
  inside it (:mod:`.osm_aisles`, :mod:`.osm_chains`: clipped, joined, ``oneway``
  honoured, width from the ``width`` tag or a default);
* gates: where a road reaches an aisle at the lot's edge (:mod:`.osm_gates`), an entrance
  on the aisle's inward lane and an exit on its outward lane; a lot no road reaches gets an
  assumed gate at the aisle end nearest its edge, and says so;
* slots: mapped ``amenity=parking_space`` areas, else bays inferred along the aisles
  (:mod:`.osm_slots`); a ``capacity`` tag is compared with their count;
* the boundary: the lot with its aisles (an aisle drawn along the lot's edge reaches past
  it) and a car standing at each gate, simplified; the paved ground: the aisles, the slots
  and the lot's outline; islands (inner rings) and mapped green areas are no-go zones,
  buildings and barriers obstacles (:mod:`.osm_near`);
* a stream of as many cars as there are slots the lanes lead to from a gate (at most 20),
  60 an hour, through the entrances that lead to one, staying 5 to 15 minutes where such a
  slot can be left for an exit.

Each file is checked by building its lot as ``lotsim validate`` does: an inferred bay that
the build refuses is dropped, an aisle whose bends are too tight for its legs is cut at its
sharpest corner, and a lot that still does not build is reported, not written. Whether a car
can park in each slot (its maneuver) is what ``lotsim validate`` then says.
"""

from __future__ import annotations

import math
import os
import re
import textwrap
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import networkx as nx
import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon
from shapely.ops import unary_union

from lotsim.core.atomic import atomic_write
from lotsim.errors import LotsimError, ScenarioError, SettingsError
from lotsim.io.imports.draft import AisleDraft, AreaDraft, GateDraft, LotDraft
from lotsim.io.imports.frame import TangentPlane
from lotsim.io.imports.osm_aisles import (
    CLIP_GROW,
    ONE_WAY_WIDTH,
    TWO_WAY_WIDTH,
    AisleRules,
    clip_network,
    merge_short_legs,
)
from lotsim.io.imports.osm_chains import (
    Chain,
    build_chains,
    join_ends,
    junctions,
    sharpest_corner,
    split_chains,
    tidy_chains,
)
from lotsim.io.imports.osm_gates import Gate, assumed_gate, find_gates
from lotsim.io.imports.osm_near import (
    MapIndex,
    NearLot,
    frame_at_centroid,
    lot_outline,
    ring_points,
)
from lotsim.io.imports.osm_plot import plot_of
from lotsim.io.imports.osm_read import OsmData, read_osm
from lotsim.io.imports.osm_slots import (
    BAY_LENGTH,
    BAY_WIDTH,
    infer_bays,
    mapped_slots,
    rows_of,
)
from lotsim.io.imports.report import ImportedLot, ImportReport
from lotsim.io.lot_yaml import MAX_LOT_SIZE
from lotsim.io.scenario_yaml import read_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle, Lot
from lotsim.lot.settings import DEFAULTS as LOT_DEFAULTS
from lotsim.roadmap.assemble import build_graph
from lotsim.roadmap.lanes import portal_station
from lotsim.vehicles.catalogue import CATALOGUE, DEFAULT_VEHICLE

NO_AISLE = ("no parking aisle mapped; lotsim import osm --layout lays such lots out "
            "(docs/layout.md)")
"""Why a lot without aisles is not written."""
STREAM_MAX = 20
"""The default stream brings at most this many cars."""
SIMPLIFY_BOUNDARY = 0.1
"""The boundary is grown by this much and simplified within it [m]."""
ATTRIBUTION = ("Map data © OpenStreetMap contributors, ODbL 1.0: "
               "https://www.openstreetmap.org/copyright")

_ID = re.compile(r"(node|way|relation)[/ ]?(\d+)|([nwr])(\d+)|(\d+)")
_KINDS = {"n": "node", "w": "way", "r": "relation"}
_ORDER = {"node": 0, "way": 1, "relation": 2}


def osm_scenarios(source: str | os.PathLike, out_dir: str | os.PathLike, *,
               lots: Sequence[str] | None = None, plots: bool = False,
               progress: Callable[[str], None] | None = None) -> ImportReport:
    """Write one scenario per parking lot of an OpenStreetMap file.

    Parameters
    ----------
    source : path
        An ``.osm`` XML file (also gzip- or bzip2-compressed) or an ``.osm.pbf`` file
        (needs ``pip install 'lotsim[osm]'``).
    out_dir : path
        Where the scenarios go, as ``<kind>-<id>.yaml`` (``way-123.yaml``); made if missing.
    lots : sequence of str, optional, keyword-only
        Only these lots: ``way/123``, ``relation/9``, ``node/5`` or a bare number (any
        kind with that id).
    plots : bool, keyword-only
        For a lot that maps no aisles, also draw its plot (outline, islands, gates:
        :mod:`.osm_plot`) into the report (``ImportedLot.plot``), for ``lotsim layout``.
    progress : callable, optional, keyword-only
        Called with a line of text as the file is read and as each lot is done (its
        :meth:`~lotsim.io.imports.report.ImportedLot.line`).

    Returns
    -------
    ImportReport
        Every lot, written or skipped, with its figures and why.

    Raises
    ------
    LotsimError
        The file is missing or not OpenStreetMap, the PBF reader is not installed, a lot
        asked for is not in the file, or ``out_dir`` cannot be made.
    SettingsError
        An id in ``lots`` is not one.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "one.osm").write_text(
    ...     '<osm version="0.6"><node id="1" lat="60.1" lon="24.9">'
    ...     '<tag k="amenity" v="parking"/></node></osm>')
    >>> print(osm_scenarios(d / "one.osm", d / "out").text())
    node/1: 0 m², slots 0 mapped / 0 inferred, capacity -, 0 aisles, 0 gates: skipped (a \
point, not an area: lotsim needs the lot's outline)
    0 of 1 lots written
    """
    wanted = _wanted(lots)
    data = read_osm(source, progress=progress)
    found = sorted(((kind, oid, tags) for kind, oid, tags in _parking(data)),
                   key=lambda t: (_ORDER[t[0]], t[1]))
    if wanted is not None:
        missing = [w for w in wanted
                   if not any(_matches(w, kind, oid) for kind, oid, _ in found)]
        if missing:
            raise LotsimError(f"{source}: no amenity=parking lot "
                              f"{', '.join(_show(w) for w in missing)} in the file")
        found = [f for f in found if any(_matches(w, f[0], f[1]) for w in wanted)]
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise LotsimError(f"{out}: cannot make the output folder: {exc.strerror}") from None
    index = MapIndex.of(data)
    results = []
    for kind, oid, tags in found:
        lot = _import_lot(kind, oid, tags, data, index, out, Path(source).name, plots)
        results.append(lot)
        if progress is not None:
            progress(lot.line())
    return ImportReport(Path(source), tuple(results))


# -- choosing lots ------------------------------------------------------------------------------
def _wanted(lots: Sequence[str] | None) -> list[tuple[str | None, int]] | None:
    if lots is None:
        return None
    if isinstance(lots, str):
        lots = [lots]
    out = []
    for text in lots:
        m = _ID.fullmatch(str(text).strip())
        if m is None:
            raise SettingsError("lots", f"{text!r}: expected way/ID, relation/ID, node/ID "
                                        "or a number")
        if m.group(1):
            out.append((m.group(1), int(m.group(2))))
        elif m.group(3):
            out.append((_KINDS[m.group(3)], int(m.group(4))))
        else:
            out.append((None, int(m.group(5))))
    return out


def _matches(w: tuple[str | None, int], kind: str, oid: int) -> bool:
    return w[1] == oid and w[0] in (None, kind)


def _show(w: tuple[str | None, int]) -> str:
    return f"{w[0]}/{w[1]}" if w[0] else str(w[1])


def _parking(data: OsmData):
    for nid, tags in data.node_tags.items():
        if tags.get("amenity") == "parking":
            yield "node", nid, tags
    for wid, way in data.ways.items():
        if way.tags.get("amenity") == "parking":
            yield "way", wid, way.tags
    for rid, rel in data.relations.items():
        if rel.tags.get("amenity") == "parking":
            yield "relation", rid, rel.tags


# -- one lot -----------------------------------------------------------------------------------
def _import_lot(kind: str, oid: int, tags: dict[str, str], data: OsmData, index: MapIndex,
                out: Path, source_name: str, plots: bool = False) -> ImportedLot:
    lid = f"{kind}/{oid}"
    capacity = _capacity(tags)
    outline = lot_outline(kind, oid, data)
    if isinstance(outline, str):
        return ImportedLot(lid, 0.0, capacity=capacity, reason=outline)
    outer, inners = outline
    frame = frame_at_centroid(data, outer)
    near = NearLot(data, index, frame, outer, inners)
    lot = Polygon(near.xy_of(outer), [near.xy_of(r) for r in inners])
    if not lot.is_valid or lot.area <= 1.0:
        why = shapely.is_valid_reason(lot) if not lot.is_valid else "it has no area"
        return ImportedLot(lid, 0.0, capacity=capacity,
                           reason=f"its outline is not a simple polygon: {why}")
    area = float(lot.area)
    x0, y0, x1, y1 = lot.bounds
    if max(x1 - x0, y1 - y0) > MAX_LOT_SIZE:  # before laying it out, which would take long
        return ImportedLot(lid, area, capacity=capacity,
                           reason=f"the lot is {max(x1 - x0, y1 - y0):,.0f} m across; lotsim "
                                  f"plans lots of at most {MAX_LOT_SIZE:,.0f} m (are its "
                                  "nodes' coordinates right?)")
    splits: set[int] = set()
    while True:
        drawn = _Drawn.of(lot, near, kind, oid, tags, splits)
        if drawn is None:
            plot = None
            if plots:
                bx, by = lot.exterior.xy
                error = frame.error_over(np.array(bx), np.array(by))
                head = [f"OpenStreetMap {kind} {oid} of {source_name}: its plot, for lotsim "
                        "layout (imported by lotsim import osm --layout, docs/import.md)",
                        ATTRIBUTION,
                        "tags: " + ", ".join(f"{k}={v}" for k, v in sorted(tags.items())),
                        f"projection: {frame.describe()}; x east, y north [m]; distances "
                        f"within {_small(error)} of the ground's over the lot"]
                plot = plot_of(f"{kind}-{oid}", _description(kind, oid, tags), lot, near,
                               oid if kind == "way" else None, head)
            return ImportedLot(lid, area, capacity=capacity, reason=NO_AISLE, plot=plot)
        outcome = drawn.settle(lot)
        if not isinstance(outcome, int) or outcome in splits:
            break
        splits.add(outcome)
    if isinstance(outcome, int):
        outcome = "lotsim finds an aisle's bends too tight, cut where it may"
    if isinstance(outcome, str):
        return ImportedLot(lid, area, mapped=len(drawn.spaces), capacity=capacity,
                           aisles=len(drawn.chains), gates=drawn.real_gates, reason=outcome)
    draft = drawn.draft
    n_slots = draft.slot_count
    bx, by = zip(*draft.boundary, strict=True)
    error = frame.error_over(np.array(bx), np.array(by))
    serving = _Serving.of(drawn.built)
    draft.traffic = serving.traffic()
    draft.header = _header(kind, oid, tags, source_name, frame, error, drawn, capacity)
    path = out / f"{kind}-{oid}.yaml"
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write(draft.to_yaml())
    return ImportedLot(lid, area, mapped=len(drawn.spaces),
                       inferred=n_slots - len(drawn.spaces), capacity=capacity,
                       aisles=len(drawn.chains), gates=drawn.real_gates, path=path,
                       reason=_remarks(capacity, n_slots, drawn, serving),
                       projection_error=error)


@dataclass
class _Drawn:
    """A lot as drawn from the map: its aisles, gates, slots and areas, and the draft."""

    chains: list[Chain]
    gates: list[Gate]
    real_gates: int
    spaces: list
    bays: list
    draft: LotDraft
    notes: list[str]
    built: Lot | None = None

    @classmethod
    def of(cls, lot: Polygon, near: NearLot, kind: str, oid: int, tags: dict[str, str],
           splits: set[int]) -> _Drawn | None:
        """Draw the lot; ``splits``: vertices where aisles are cut in two. None when it has
        no aisle."""
        notes: list[str] = []
        design = DesignVehicle.envelope([CATALOGUE[DEFAULT_VEHICLE]])
        # the lot written has no lot.build: it is built with the default lane clearance
        clearance = LOT_DEFAULTS.lane_clearance
        rules = AisleRules(least_two_way=2 * (design.width + 2 * clearance),
                           least_one_way=design.width + 2 * clearance)
        driveways = near.driveways(lot)
        ways = sorted(near.aisles + driveways)
        vertices, edges = clip_network(ways, near.xy, lot.buffer(CLIP_GROW), rules,
                                       near.index.road_nodes, notes)
        edges = merge_short_legs(vertices, edges)
        chains = tidy_chains(build_chains(vertices, edges), vertices)
        if not chains:
            return None
        notes += join_ends(chains, vertices)
        if splits:
            chains = split_chains(chains, splits, vertices)
        gates = find_gates(chains, vertices, lot, near.road_lines(), near.road_name)
        real_gates = len(gates)
        if not any(g.entrance for g in gates):
            gates += assumed_gate(chains, lot)
        for c in chains:
            c.pts = [(round(x, 2), round(y, 2)) for x, y in c.pts]
        obstacles, no_go = near.areas(lot, chains, oid if kind == "way" else None)
        for i, ring in enumerate(lot.interiors):
            no_go.append(AreaDraft(f"island{i + 1}", ring_points(ring),
                                   note=f"inner ring {i + 1} of the lot"))
        blocked = [Polygon(a.polygon) for a in obstacles + no_go]
        spaces = mapped_slots(near.spaces(lot), chains, lot, blocked,
                              (design.width, design.front + design.rear), notes)
        bays = [] if spaces else infer_bays(chains, junctions(chains, vertices), lot,
                                                blocked)
        draft = LotDraft(name=f"{kind}-{oid}", description=_description(kind, oid, tags),
                         boundary=[],
                         aisles=[AisleDraft(c.id, c.pts, c.width, c.one_way,
                                            _aisle_note(c, {w for w, _ in driveways}))
                                 for c in chains],
                         slots=[s for s, _ in spaces], obstacles=obstacles, no_go=no_go,
                         paved=[AreaDraft("lot", ring_points(lot.exterior),
                                          note=f"the lot's outline ({kind} {oid})")])
        _set_gates(draft, gates)
        return cls(chains, gates, real_gates, spaces, bays, draft, notes)

    def settle(self, lot: Polygon) -> str | int | None:
        """Lay the bays out as rows and check that lotsim builds the lot, dropping each bay
        it refuses. None when it builds; the vertex to cut an aisle at where its bends are
        too tight; else why it cannot be built."""
        draft, bays = self.draft, list(self.bays)
        design = DesignVehicle.envelope([CATALOGUE[DEFAULT_VEHICLE]])
        cars = [Polygon(design.footprints(np.array([[g.x, g.y, math.radians(g.heading_deg)]]))[0])
                for g in draft.entrances + draft.exits]
        while True:
            rows, ids = rows_of(bays)
            draft.rows = rows
            draft.boundary = _boundary(lot, self.chains, [p for _, p in self.spaces] + cars)
            try:
                sc = read_scenario(draft.to_yaml()).scenario
                built = build_lot(sc.lot, design)
                for portal in built.entrances + built.exits:
                    portal_station(built, portal)
                self.bays, self.built = bays, built
                return None
            except ScenarioError as exc:
                message = exc.message
            named = re.findall(r"slot '([^']+)'", message)
            bay = next((ids[n] for n in named if n in ids), None)
            if bay is not None:
                bays.remove(bay)
                continue
            space = next((i for i, (sd, _) in enumerate(self.spaces) if sd.id in named), None)
            if space is not None:
                gone = self.spaces.pop(space)[0]
                draft.slots = [sd for sd, _ in self.spaces]
                self.notes.append(f"{gone.note} dropped: {message}")
                continue
            tight = re.match(r"aisle '([^']+)': curves too tight", message)
            chain = next((c for c in self.chains if tight and c.id == tight.group(1)), None)
            if chain is not None and len(chain.pts) > 2:
                return sharpest_corner(chain)
            return f"lotsim cannot build the lot drawn from it: {message}"


@dataclass(frozen=True)
class _Serving:
    """Which slots of a built lot cars can reach from each entrance and leave for an exit,
    along its lanes, junction turns and turnarounds (slots linked to their lanes as
    placeholders: a parking maneuver that cannot be found is what ``validate`` says)."""

    slots: tuple[str, ...]
    by_entrance: dict[str, frozenset[str]]
    leavable: frozenset[str]
    exits: bool

    @classmethod
    def of(cls, lot: Lot) -> _Serving:
        lg = build_graph(lot, vehicles=[CATALOGUE[DEFAULT_VEHICLE]])
        g = lg.graph
        slot_nodes = set(lg.slot_nodes.values())
        lanes = g.subgraph(n for n in g.nodes if n not in slot_nodes)
        by_entrance = {}
        for gate, node in sorted(lg.entrances.items()):
            seen = nx.descendants(lanes, node) | {node}
            by_entrance[gate] = frozenset(
                sid for sid, n in lg.slot_nodes.items() if any(p in seen for p in g.pred[n]))
        out: set = set()
        for node in lg.exits.values():
            out |= nx.ancestors(lanes, node) | {node}
        leavable = frozenset(sid for sid, n in lg.slot_nodes.items()
                             if any(q in out for q in g.succ[n]))
        return cls(tuple(sorted(lg.slot_nodes)), by_entrance, leavable, bool(lg.exits))

    @property
    def reached(self) -> frozenset[str]:
        return frozenset().union(*self.by_entrance.values())

    def traffic(self) -> dict | None:
        """The default stream: as many cars as slots a car can reach, at most
        :data:`STREAM_MAX`, 60 an hour, through the entrances that lead to a slot, staying
        5 to 15 minutes where a slot can be left for an exit; None when none can be
        reached."""
        if not self.reached:
            return None
        stream: dict = {"count": min(STREAM_MAX, len(self.reached)), "rate_per_hour": 60}
        gates = [g for g, s in self.by_entrance.items() if s]
        if len(gates) < len(self.by_entrance):
            stream["entrances"] = gates
        if self.exits and self.reached & self.leavable:
            stream["dwell"] = [300, 900]
        return {"stream": stream}


def _capacity(tags: dict[str, str]) -> int | None:
    value = tags.get("capacity", "").strip()
    return int(value) if value.isdigit() else None


# -- the draft -------------------------------------------------------------------------------
def _set_gates(draft: LotDraft, gates: list[Gate]) -> None:
    for i, g in enumerate(gates, start=1):
        if g.entrance:
            x, y, t = g.entrance
            draft.entrances.append(GateDraft(f"in{i}", x, y, math.degrees(t), g.note))
        if g.exit:
            x, y, t = g.exit
            draft.exits.append(GateDraft(f"out{i}", x, y, math.degrees(t),
                                         g.note if not g.entrance else ""))


def _boundary(lot: Polygon, chains: list[Chain], held: list[Polygon]
              ) -> list[tuple[float, float]]:
    """A simple polygon holding the lot, its aisles and ``held`` (the mapped slots, a car
    standing at each gate)."""
    shapes = [Polygon(lot.exterior)] + held + [
        c.line.buffer(c.width / 2, cap_style="flat", join_style="mitre", mitre_limit=2.0)
        for c in chains]
    whole = unary_union(shapes)
    if isinstance(whole, MultiPolygon):
        whole = whole.buffer(CLIP_GROW, join_style="mitre").buffer(-CLIP_GROW,
                                                                   join_style="mitre")
    if isinstance(whole, MultiPolygon):
        whole = whole.convex_hull
    outline = Polygon(whole.exterior)
    grown = outline.buffer(SIMPLIFY_BOUNDARY, join_style="mitre").simplify(SIMPLIFY_BOUNDARY)
    if isinstance(grown, Polygon) and grown.is_valid and grown.covers(outline):
        outline = grown
    pts = ring_points(outline.exterior)
    rounded = Polygon(pts)
    if not rounded.is_valid or not rounded.buffer(0.01).covers(whole):
        pts = ring_points(outline.buffer(0.02, join_style="mitre").exterior)
    return pts


def _small(length: float) -> str:
    """A length of at most a few millimetres, readably.

    >>> _small(3e-9), _small(0.00042)
    ('0.001 mm', '0.42 mm')
    """
    return f"{max(length * 1000, 0.001):.2g} mm"


def _description(kind: str, oid: int, tags: dict[str, str]) -> str:
    name = f": {tags['name']}" if tags.get("name") else ""
    return f"OpenStreetMap {kind} {oid}{name}, a parking lot imported by lotsim"


def _aisle_note(c: Chain, driveways: set[int]) -> str:
    ways = ", ".join(f"{w} (a driveway, highway=service)" if w in driveways else str(w)
                     for w in c.ways)
    width = "width from its tag" if c.note else (
        f"default width for {'one' if c.one_way else 'two'}-way")
    return f"way{'s' if len(c.ways) > 1 else ''} {ways}: {width}"


def _remarks(capacity: int | None, n_slots: int, drawn: _Drawn, serving: _Serving) -> str:
    out = []
    if capacity is not None:
        diff = n_slots - capacity
        out.append(f"capacity tag {capacity}, {n_slots} slots laid out"
                   + ("" if diff == 0 else f" ({abs(diff)} {'more' if diff > 0 else 'fewer'})"))
    if not drawn.real_gates:
        out.append(f"no gate: no road reaches an aisle at the lot's edge; "
                   f"{drawn.gates[-1].note}")
    if not n_slots:
        out.append("no room for a slot")
    elif not serving.reached:
        out.append("no slot can be reached from a gate along its lanes: no traffic written")
    elif len(serving.reached) < n_slots:
        out.append(f"{n_slots - len(serving.reached)} of {n_slots} slots cannot be reached "
                   "from a gate along its lanes")
    return "; ".join(out)


def _header(kind: str, oid: int, tags: dict[str, str], source_name: str, frame: TangentPlane,
            error: float, drawn: _Drawn, capacity: int | None) -> list[str]:
    chains, spaces, n_slots = drawn.chains, drawn.spaces, drawn.draft.slot_count
    lines = [f"OpenStreetMap {kind} {oid} of {source_name}, imported by lotsim import osm "
             "(docs/import.md)", ATTRIBUTION,
             "tags: " + ", ".join(f"{k}={v}" for k, v in sorted(tags.items())),
             f"projection: {frame.describe()}; x east, y north [m]; distances within "
             f"{_small(error)} of the ground's over the lot",
             f"aisles: {len(chains)} from service=parking_aisle ways and the service roads "
             f"that meet them inside the lot; untagged widths "
             f"{TWO_WAY_WIDTH:g} m two-way, {ONE_WAY_WIDTH:g} m one-way"]
    if spaces:
        lines.append(f"slots: {len(spaces)} mapped amenity=parking_space areas")
    else:
        lines.append(f"slots: {n_slots} perpendicular bays {BAY_WIDTH:g} x {BAY_LENGTH:g} m "
                     "inferred along the aisles' straight legs")
    if capacity is not None:
        lines.append(f"capacity tag: {capacity}")
    lines += [g.note for g in drawn.gates]
    lines += drawn.notes
    out = []
    for line in lines:
        out += textwrap.wrap(line, 96, break_long_words=False, break_on_hyphens=False) or [""]
    return out
