"""Bays by use in a layout, checked on the scenario written, read back by lotsim's scenario
reader and built as ``lotsim validate`` builds it, against oracles of its own: the counts
asked for, ADA 2010 Table 208.2 as printed (written out here, not lotsim's function), the
walk to the door as the straight line from each bay's centre, and shapely for the access
aisles. Geometry only (no maneuver is planned), so quick; ``tests/e2e/test_layout.py``
lays a plot with uses out in full (``-m slow``)."""

from __future__ import annotations

import math

import pytest
import shapely
from shapely.geometry import Polygon
from unit.design.test_candidates import _violations

from lotsim.design.allocation import allocate, group_span, stretches
from lotsim.design.plot_yaml import read_plot
from lotsim.design.preparing import scenario_text
from lotsim.design.results import Evaluation, LayoutResult
from lotsim.design.search import candidates
from lotsim.design.settings import LayoutSettings
from lotsim.io.scenario_yaml import parse_scenario
from lotsim.io.yamlnodes import parse_text
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.sim.bays import bay_walks

TYPES = """\
vehicle_types:
  - valet
  - {name: blue_badge, width: 1.8, front: 3.7, rear: 1.0, wheelbase: 2.7, max_steer_deg: 33,
     accessible: true}
  - {name: ev_hatch, width: 1.771, front: 3.427, rear: 0.657, wheelbase: 2.588,
     max_steer_deg: 33, ev: true}
"""
PLOT = """\
name: shop
boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]
gates: [{id: south, at: [30, 0]}]
building_entrances: [{id: door, at: [22, 41]}]
bays: {angles_deg: [90]}
aisles: {one_way: false}
""" + TYPES


def table_208_2(total: int) -> int:
    """ADA 2010 Table 208.2 as printed: total parking spaces → minimum accessible."""
    rows = [(25, 1), (50, 2), (75, 3), (100, 4), (150, 5), (200, 6), (300, 7), (400, 8),
            (500, 9)]
    for most, need in rows:
        if total <= most:
            return need
    if total <= 1000:
        return math.ceil(0.02 * total)
    return 20 + math.ceil((total - 1000) / 100)


def _laid(uses: str, plot_text: str = PLOT, most: int = 3):
    """The written lots of the ``most`` candidates with most bays drawn, each as (plot,
    allocation, scenario, built lot)."""
    plot = read_plot(plot_text + uses)
    drawn = sorted(candidates(plot, LayoutSettings(orientations=2, offsets=1)),
                   key=lambda c: -c.bays)[:most]
    out = []
    for cand in drawn:
        alloc = allocate(plot, stretches(plot, cand.rows, None))
        text, ids = scenario_text(plot, cand, allocation=alloc)
        sc = parse_scenario(parse_text(text, "shop.yaml"))
        lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
        assert len(ids) == len(lot.slots) == alloc.total
        out.append((plot, alloc, sc, lot))
    return out


def _by_use(lot) -> dict[str, int]:
    out: dict[str, int] = {}
    for s in lot.slots:
        out[s.use] = out.get(s.use, 0) + 1
    return out


def _walk(slot, door=(22.0, 41.0)) -> float:
    return math.dist(slot.center, door)


@pytest.mark.slow
@pytest.mark.parametrize("uses", ["uses: {accessible: ada_2010}\n",
                                  "uses: {accessible: ada_2010, ev: 10%}\n"])
def test_as_the_standard_requires_meets_table_208_2_for_the_total_laid_out(uses):
    for _, alloc, _, lot in _laid(uses):
        n = _by_use(lot)
        total = len(lot.slots)
        accessible = n.get("accessible", 0) + n.get("van_accessible", 0)
        need = table_208_2(total)
        assert need <= accessible <= need + 1, (total, n)  # +1: only where fewer cannot be
        assert n.get("van_accessible", 0) >= math.ceil(need / 6)
        assert alloc.short == {}
        if "ev" in uses:
            assert n["ev"] == math.ceil(0.1 * total)


def test_counts_the_plot_states_are_the_counts_read_back():
    for _, alloc, sc, lot in _laid("uses: {accessible: 5, van_accessible: 2, ev: 7}\n"):
        n = _by_use(lot)
        assert (n["accessible"], n["van_accessible"], n["ev"]) == (3, 2, 7)
        # the rows the scenario reader holds say the same
        rows = {u: sum(r.count for r in sc.lot.rows if r.use == u)
                for u in ("accessible", "van_accessible", "ev")}
        assert rows == {"accessible": 3, "van_accessible": 2, "ev": 7}
        assert alloc.short == {}


def test_access_aisles_cost_bays_and_the_total_says_so():
    plot = read_plot(PLOT)
    cand = max(candidates(plot, LayoutSettings(orientations=1, offsets=1)), key=lambda c: c.bays)
    with_uses = read_plot(PLOT + "uses: {accessible: 4, van_accessible: 0}\n")
    alloc = allocate(with_uses, stretches(with_uses, cand.rows, None))
    # two pairs, each two bays and a 1.52 m aisle in the place of three 2.5 m bays
    assert alloc.total == cand.bays - 2
    assert group_span("accessible", 2.5, 2) == pytest.approx(2 * 2.5 + 60 * 0.0254)


def test_accessible_bays_are_nearest_the_door_within_a_group_s_span():
    # on this open plot (the door just beyond its edge, the rows hardly in the way), placing
    # by the walk over the pavement keeps the straight lines' property: no standard bay on a
    # 90° row is nearer the door than an accessible bay by more than the span of a group
    for _, _, _, lot in _laid("uses: {accessible: 6, ev: 4}\n"):
        acc = [_walk(s) for s in lot.slots if s.use in ("accessible", "van_accessible")]
        std = [_walk(s) for s in lot.slots if s.use == "standard"]
        ev = [_walk(s) for s in lot.slots if s.use == "ev"]
        assert len(acc) == 6 and len(ev) == 4
        assert max(acc) - min(std) <= 3 * 2.5 + 1e-9, (sorted(acc), min(std))
        # EV bays: the standard bays nearest the door once the accessible ones stand
        assert max(ev) <= min(std) + 1e-9


def test_the_property_s_oracle_can_fail():
    # a lot whose accessible bays were put farthest from the door breaks it
    for _, _, _, lot in _laid("uses: {accessible: 6}\n", PLOT.replace("[22, 41]", "[22, -1]"),
                              most=1):
        far = [math.dist(s.center, (22.0, 41.0)) for s in lot.slots
               if s.use in ("accessible", "van_accessible")]
        std = [math.dist(s.center, (22.0, 41.0)) for s in lot.slots if s.use == "standard"]
        assert max(far) - min(std) > 3 * 2.5


def test_access_aisles_keep_off_the_way_and_the_bays_and_are_wide_enough():
    for plot, _, _, lot in _laid("uses: {accessible: 7, van_accessible: 3}\n"):
        outline = Polygon(plot.boundary)
        bays = [Polygon(s.polygon) for s in lot.slots]
        ways = [a.polygon for a in lot.aisles.values()]
        uses = {s.id: s.use for s in lot.slots}
        assert len(lot.access_aisles) == 4  # one per group: a van pair, a van bay, 2 pairs
        for a in lot.access_aisles:
            p = Polygon(a.polygon)
            assert outline.buffer(1e-6).covers(p)
            for other in [*bays, *ways, *(Polygon(b.polygon) for b in lot.access_aisles
                                          if b is not a)]:
                assert shapely.area(p.intersection(other)) < 1e-6
            least = 96 if uses[a.slots[0]] == "van_accessible" else 60
            assert a.width >= least * 0.0254 - 1e-9
            # and it lies beside each bay it serves, over the bay's full length
            for sid in a.slots:
                bay = Polygon(next(s.polygon for s in lot.slots if s.id == sid))
                assert bay.intersection(p).length == pytest.approx(5.0, abs=1e-6)


@pytest.mark.slow
def test_compact_bays_fill_what_full_bays_leave_and_never_take_their_place():
    plain = read_plot(PLOT.replace("[60, 0], [60, 40]", "[59, 0], [59, 40]"))
    compact = read_plot(PLOT.replace("[60, 0], [60, 40]", "[59, 0], [59, 40]")
                        + "uses: {compact: {width: 2.3, length: 4.6}}\n")
    settings = LayoutSettings(orientations=2, offsets=1)
    found = 0
    for a, b in zip(candidates(plain, settings), candidates(compact, settings), strict=True):
        full = [p.wkb for r in b.rows if r.size is None for p in r.polygons]
        assert full == [p.wkb for r in a.rows for p in r.polygons], b.label
        small = [p for r in b.rows if r.size is not None for p in r.polygons]
        found += len(small)
        assert _violations(compact, b) == [], b.label
        for p in small:
            x0, y0, x1, y1 = p.bounds
            assert sorted((round(x1 - x0, 6), round(y1 - y0, 6))) == [2.3, 4.6]
    assert found > 0
    # written and read back with their use and size; a car longer than them is refused
    cand = max(candidates(compact, settings), key=lambda c: sum(
        r.count for r in c.rows if r.size))
    text, _ = scenario_text(compact, cand)
    sc = parse_scenario(parse_text(text, "shop.yaml"))
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    small = [s for s in lot.slots if s.use == "compact"]
    assert small and all((s.width, s.length) == (2.3, 4.6) for s in small)
    from lotsim.lot.uses import refused_bays
    refused = refused_bays(lot.slots, sc.vehicle_types)
    assert all(s.id in refused["valet"] for s in small)  # 4.90 m long
    assert not any(s.id in refused["ev_hatch"] for s in small)  # 4.08 m


def test_a_barred_group_stands_elsewhere():
    plot = read_plot(PLOT + "uses: {accessible: 2, van_accessible: 0}\n")
    cand = max(candidates(plot, LayoutSettings(orientations=1, offsets=1)), key=lambda c: c.bays)
    runs = stretches(plot, cand.rows, None)
    first = allocate(plot, runs)
    (span,) = first.groups.values()
    again = allocate(plot, runs, barred=set(span))
    (other,) = again.groups.values()
    assert not set(span) & set(other)


def test_a_plot_without_uses_writes_the_lot_it_wrote_before():
    plot = read_plot(PLOT)
    for cand in candidates(plot, LayoutSettings(orientations=1, offsets=1)):
        text, ids = scenario_text(plot, cand)
        assert "use:" not in text and "building_entrances" not in text
        assert "accessible: true" not in text or "blue_badge" in text
        assert len(ids) == cand.bays


def _evaluation(index, bays, met, by_use=()):
    return Evaluation(index=index, label=f"candidate {index}", drawn=bays + 2, bays=bays,
                      aisle_length=100.0, area=2400.0, yaml="x", by_use=by_use, met=met,
                      mean_time_to_park=20.0, throughput=300.0)


def test_the_ranking_puts_the_standard_met_first_then_the_bays_laid_out():
    plot = read_plot(PLOT + "uses: {accessible: ada_2010, ev: 3}\n")
    counts = (("standard", 60), ("accessible", 2), ("van_accessible", 1), ("ev", 3))
    ranked = sorted([_evaluation(0, 70, False, counts), _evaluation(1, 66, True, counts),
                     _evaluation(2, 68, True, counts)], key=Evaluation.rank_key)
    assert [e.index for e in ranked] == [2, 1, 0]
    table = LayoutResult(plot, LayoutSettings(), tuple(ranked), 3, 1.0).table()
    head, *lines = table.splitlines()
    assert head.split()[:7] == ["#", "bays", "drawn", "access.", "van", "EV", "ADA"]
    assert lines[0].split()[:7] == ["1", "68", "70", "3", "1", "3", "yes"]
    assert lines[2].split()[6] == "no"
    plain = LayoutResult(read_plot(PLOT), LayoutSettings(), (_evaluation(0, 70, None),), 1,
                         1.0).table()
    assert plain.splitlines()[0].split()[:4] == ["#", "bays", "drawn", "ADA"]
    assert plain.splitlines()[1].split()[3] == "-"



@pytest.mark.slow
@pytest.mark.parametrize("door", ["[22, 20]", "[45, 28]"])
def test_a_group_stands_where_its_walk_is_least_and_validate_walks_it_so(door):
    # against every place the group could stand, walked the allocator's way; and the walks
    # lotsim validate reports for the bays placed are those the allocator ranked them by
    from lotsim.design.allocation import _Walks
    # bays up to the gate's mouth, as the walks here were worked out on: with the default
    # clearance, the door at (45, 28) finds the gap an accessible group leaves in its row
    # (6.52 m in the place of three 7.5 m bays), which the allocator's walks do not open
    text = PLOT.replace("[22, 41]", door).replace("{angles_deg: [90]}",
                                                  "{angles_deg: [90], gate_clearance: 0}")
    uses = "uses: {accessible: 2, van_accessible: 0}\n"
    drawn = sorted(candidates(read_plot(text + uses), LayoutSettings(orientations=2,
                                                                      offsets=1)),
                   key=lambda c: -c.bays)[:3]  # the candidates _laid lays, in its order
    for (plot, alloc, _, lot), cand in zip(_laid(uses, text), drawn, strict=True):
        cand_runs = stretches(plot, cand.rows, None)
        assert allocate(plot, cand_runs) == alloc
        walks = _Walks(plot, cand_runs)
        k = math.ceil(group_span("accessible", 2.5, 2) / 2.5 - 1e-9)
        every = [max(walks.group(s, (i, j), "accessible", 2))
                 for i, s in enumerate(cand_runs) if s.angle == 90 and s.count >= k
                 for j in range(s.count - k + 1)]
        doors = [(e.id, e.at) for e in plot.building_entrances]
        reported = [w.distance for w in bay_walks(lot, doors)]
        assert len(reported) == 2
        assert max(reported) == pytest.approx(min(every), abs=1e-3)
        assert len({round(w, 6) for w in every}) > 1  # the places differ
