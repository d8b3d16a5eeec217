"""``lotsim layout`` from plot to scenario: the lot written validates strictly (lotsim's own
validation), runs, and is checked by shapely; on the 100 x 60 m rectangle it holds at least
the hand count of the standard module; the same plot gives the same bytes; a bad plot is
an error at its file, line and column."""

from __future__ import annotations

import math

import pytest
import shapely
from shapely.geometry import Polygon

import lotsim
from conftest import ONE_AISLE, ROOT, scenario_from_text
from lotsim.cli import main
from lotsim.design.plot_yaml import read_plot
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle

PLOTS = ROOT / "scenarios" / "plots"

SMALL = """\
name: small
boundary: [[0, 0], [36, 0], [36, 30], [0, 30]]
gates: [{id: south, at: [18, 0]}]
bays: {angles_deg: [90]}
demand: {count: 4, rate_per_hour: 360}
"""
QUICK = lotsim.LayoutSettings(orientations=1, offsets=1, prepared=1, compared=1)


def hand_count(length: float, depth: float, *, bay_width: float = 2.5,
               bay_length: float = 5.0, aisle: float = 7.0) -> int:
    """What two-way 90° double-loaded modules give by hand on a ``length`` × ``depth``
    rectangle: modules (bays, aisle, bays) stacked across the depth as many as fit, their
    aisles along the length, joined at both ends by a cross aisle of the same width that
    also takes the gate; rows of whole bays between the cross aisles."""
    modules = math.floor(depth / (2 * bay_length + aisle))
    per_row = math.floor((length - 2 * aisle) / bay_width)
    return 2 * modules * per_row


def test_the_hand_count_of_the_standard_module():
    # 60 m holds 3 modules of 17 m (51 m; 9 m left, too little for another row and its
    # aisle); the 100 m less two 7 m cross aisles holds 34 bays a row; 6 rows
    assert hand_count(100, 60) == 204


def _slots_are_clear(scenario) -> list[str]:
    """shapely's word on the built lot: every slot inside the boundary, clear of the no-go
    zones, the aisles and every other slot."""
    lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
    return _problems(Polygon(scenario.lot.boundary),
                     {a.id: Polygon(a.polygon) for a in scenario.lot.areas},
                     {a.id: a.polygon for a in lot.aisles.values()},
                     [(s.id, Polygon(s.polygon)) for s in lot.slots])


def _problems(outline, areas, aisles, slots) -> list[str]:
    # shapes overlap when one shrunk by a millimetre still meets the other: slots that only
    # touch their aisle or their neighbours do not
    def overlaps(a, b) -> bool:
        return a.buffer(-1e-3, join_style="mitre").intersects(b)

    wrong = [f"{sid} leaves the plot" for sid, p in slots
             if not outline.buffer(1e-6).covers(p)]
    for name, geom in [*areas.items(), *aisles.items()]:
        wrong += [f"{sid} overlaps {name}" for sid, p in slots if overlaps(p, geom)]
    polys = [p for _, p in slots]
    tree = shapely.STRtree(polys)
    left, right = tree.query(polys, predicate="intersects")
    wrong += [f"{slots[i][0]} overlaps {slots[j][0]}" for i, j in zip(left, right, strict=True)
              if i < j and overlaps(polys[i], polys[j])]
    return wrong


@pytest.mark.slow
def test_the_rectangle_beats_the_hand_count_and_validates_strictly(tmp_path):
    out = tmp_path / "lot.yaml"
    # the candidate with the most bays drawn, along the long side, prepared alone
    settings = lotsim.LayoutSettings(orientations=1, offsets=3, prepared=1, compared=1)
    found = lotsim.layout(PLOTS / "rect60x100.yaml", out, settings=settings)
    best = found.best
    assert best.bays >= hand_count(100, 60)
    assert best.bays_per_100m2 == pytest.approx(100 * best.bays / 6000)
    assert out.read_text() == best.document()
    assert out.read_text().splitlines()[1] == (
        f"# {best.bays} bays, each usable by every vehicle type ({best.bays_per_100m2:.2f} per "
        f"100 m², paved {best.paved / best.bays:.1f} m² a bay), aisles "
        f"{best.aisle_length:.1f} m; a run of its demand: 30 of 30 cars "
        f"parked, mean time to park {best.mean_time_to_park:.1f} s, {best.throughput:.0f} "
        "cars parked per hour, lotsim check passed.")
    report = lotsim.validate(out)
    assert report.complete, report.summary()
    assert len(report.prepared.lot.slots) == best.bays
    assert _slots_are_clear(report.prepared.scenario) == []
    # the run at the plot's demand parked every car, and lotsim check passed it
    assert best.checked and best.parked == best.vehicles == 30
    assert best.mean_time_to_park > 0 and best.throughput > 0


def test_the_shapely_check_of_a_written_lot_can_fail():
    # the check on a lot of slots beside an aisle; that the lots layout writes pass it is
    # checked on the rectangle above and on every shipped plot (-m slow)
    sc = scenario_from_text(ONE_AISLE)
    assert _slots_are_clear(sc) == []
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    slots = [(s.id, Polygon(s.polygon)) for s in lot.slots]
    aisles = {a.id: a.polygon for a in lot.aisles.values()}
    outline = Polygon(sc.lot.boundary)
    kiosk = {"kiosk": slots[1][1].centroid.buffer(0.5)}
    assert _problems(outline, kiosk, aisles, slots) == [f"{slots[1][0]} overlaps kiosk"]
    moved = [*slots[:1], (slots[1][0], shapely.affinity.translate(slots[0][1], 1.0))]
    assert f"{slots[0][0]} overlaps {slots[1][0]}" in _problems(outline, {}, aisles, moved)
    outside = [(slots[0][0], shapely.affinity.translate(slots[0][1], -40.0))]
    assert _problems(outline, {}, {}, outside) == [f"{slots[0][0]} leaves the plot"]


@pytest.mark.slow
def test_progress_ends_at_its_total_when_the_search_stops_early():
    # four may be prepared; the search stops after two, the rest drawing fewer bays
    calls: list[tuple[int, int]] = []
    settings = lotsim.LayoutSettings(orientations=1, offsets=1, prepared=4, compared=1)
    found = lotsim.layout(SMALL, settings=settings,
                          progress=lambda done, total: calls.append((done, total)))
    assert len(found.ranked) < 4
    assert calls[0] == (0, 4)
    assert calls[-1] == (len(found.ranked), len(found.ranked))
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)


@pytest.mark.slow
@pytest.mark.cores  # on the machine's cores, and on one (--jobs 1)
def test_the_same_plot_gives_the_same_bytes(tmp_path, monkeypatch):
    monkeypatch.setenv("LOTSIM_CACHE_DIR", "off")  # both worked out, neither remembered
    plot = tmp_path / "small.yaml"  # 20 x 24 m: a spine from the gate, 18 bays
    plot.write_text(SMALL.replace("[[0, 0], [36, 0], [36, 30], [0, 30]]",
                                  "[[0, 0], [20, 0], [20, 24], [0, 24]]")
                    .replace("[18, 0]", "[10, 0]"))
    a, b = tmp_path / "a.yaml", tmp_path / "b.yaml"
    assert main(["layout", str(plot), "-o", str(a), "--orientations", "1", "--offsets",
                 "1", "--prepared", "1"]) == 0
    assert main(["layout", str(plot), "-o", str(b), "--orientations", "1", "--offsets",
                 "1", "--prepared", "1", "--jobs", "1"]) == 0
    assert a.read_bytes() == b.read_bytes()
    assert b"Laid out by lotsim" in a.read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.yaml", "b.yaml", "small.yaml"]


def test_the_dead_end_cost_is_set_on_the_command_line_and_written_with_the_search(
        tmp_path, capsys):
    plot = tmp_path / "small.yaml"
    plot.write_text(SMALL)
    out = tmp_path / "lot.yaml"
    assert main(["layout", str(plot), "-o", str(out), "--orientations", "1", "--offsets",
                 "1", "--prepared", "1", "--dead-end-cost", "7.5"]) == 0
    assert "dead ends 7.5 bays per 100 m" in out.read_text()
    assert main(["layout", str(plot), "-o", str(tmp_path / "no.yaml"),
                 "--dead-end-cost", "-1"]) == 2
    assert "--dead-end-cost: expected 0 to 1000 bays per 100 m, found -1.0" in \
        capsys.readouterr().err
    assert not (tmp_path / "no.yaml").exists()


@pytest.mark.slow
def test_keep_writes_the_next_best_beside_the_best(tmp_path, capsys):
    plot = tmp_path / "small.yaml"
    plot.write_text(SMALL)
    out = tmp_path / "lot.yaml"
    assert main(["layout", str(plot), "-o", str(out), "--keep", "2", "--orientations", "1",
                 "--offsets", "1", "--prepared", "2", "--pictures"]) == 0
    said = capsys.readouterr().out
    assert "bays" in said and "per 100 m²" in said and "park [s]" in said
    first, second = out.read_text(), (tmp_path / "lot-2.yaml").read_text()
    assert first != second
    for text in (first, second):
        assert lotsim.validate(text).complete
    # the pictures: the best lot, and the two candidates side by side
    from PIL import Image

    assert Image.open(tmp_path / "lot.png").size == (1200, 900)
    assert Image.open(tmp_path / "lot-candidates.png").size == (2 * 600, 450)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "lot-2.yaml", "lot-candidates.png", "lot.png", "lot.yaml", "small.yaml"]


@pytest.mark.parametrize("edit, where", [
    ("at: [18, 0]", "at: [18, 4]"),
    ("angles_deg: [90]", "angles_deg: [80]"),
])
def test_a_bad_plot_is_an_error_at_its_place_and_nothing_is_written(tmp_path, capsys, edit,
                                                                    where):
    plot = tmp_path / "bad.yaml"
    plot.write_text(SMALL.replace(*[edit, where]))
    out = tmp_path / "lot.yaml"
    assert main(["layout", str(plot), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    line = next(k + 1 for k, text in enumerate(plot.read_text().splitlines()) if where in text)
    assert err.startswith(f"lotsim: {plot}:{line}:"), err
    assert "Traceback" not in err and not out.exists()


def test_bad_options_are_named():
    with pytest.raises(lotsim.SettingsError, match="keep"):
        lotsim.layout(SMALL, keep=0)
    with pytest.raises(lotsim.SettingsError, match="orientations"):
        lotsim.LayoutSettings(orientations=0)
    assert main(["layout", "x.yaml", "-o", "lot.txt"]) == 2
    with pytest.raises(lotsim.SettingsError, match="pictures"):
        lotsim.layout(SMALL, pictures=True)


def test_a_plot_too_small_for_a_ring_says_so():
    # 14 x 12 m: no ring inside a row of bays, and a spine from the gate leaves no room
    # for a bay beside it
    tiny = SMALL.replace("[[0, 0], [36, 0], [36, 30], [0, 30]]",
                         "[[0, 0], [14, 0], [14, 12], [0, 12]]").replace("[18, 0]", "[7, 0]")
    assert read_plot(tiny).boundary[2] == (14.0, 12.0)
    with pytest.raises(lotsim.ScenarioError, match="no layout of this plot"):
        lotsim.layout(tiny, settings=QUICK)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["rect60x100", "l_shape", "trapezoid", "island"])
def test_every_shipped_plot_lays_out_into_a_lot_that_validates_runs_and_checks(tmp_path, name):
    out = tmp_path / f"{name}.yaml"
    found = lotsim.layout(PLOTS / f"{name}.yaml", out)
    report = lotsim.validate(out)
    assert report.complete and _slots_are_clear(report.prepared.scenario) == []
    result = lotsim.run(report.prepared)
    assert lotsim.check(result).ok
    assert result.metrics()["parked"] == found.plot.demand.count


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(3))
def test_random_plots_lay_out_into_lots_that_validate_strictly(tmp_path, seed):
    from unit.design.test_candidates import _random_plots

    (plot,) = _random_plots(200 + seed, 1)
    settings = lotsim.LayoutSettings(orientations=2, offsets=1, prepared=2, compared=1)
    try:
        found = lotsim.layout(plot, tmp_path / "lot.yaml", settings=settings)
    except lotsim.ScenarioError as exc:  # a plot may have no room for a layout: say why
        assert "no layout of this plot" in str(exc)
        return
    report = lotsim.validate(tmp_path / "lot.yaml")
    assert report.complete and len(report.prepared.lot.slots) == found.best.bays
    assert _slots_are_clear(report.prepared.scenario) == []


@pytest.mark.slow
def test_a_plot_with_uses_lays_out_into_a_lot_validate_counts_alike(tmp_path):
    from unit.design.test_allocation import table_208_2

    out = tmp_path / "shop.yaml"
    settings = lotsim.LayoutSettings(orientations=1, offsets=1, prepared=2, compared=1)
    found = lotsim.layout(PLOTS / "storefront_plot.yaml", out, settings=settings)
    best = found.best
    report = lotsim.validate(out)
    assert report.complete, report.summary()
    bays = report.bays
    # the counts the layout reports are the counts lotsim validate finds in the lot written
    assert dict(best.by_use) == bays.by_use and best.met is True and bays.met
    total = len(report.prepared.lot.slots)
    assert total == best.bays
    accessible = bays.by_use["accessible"] + bays.by_use["van_accessible"]
    assert accessible >= table_208_2(total)
    assert bays.by_use["van_accessible"] >= math.ceil(table_208_2(total) / 6)
    assert bays.by_use["ev"] == math.ceil(0.1 * total)
    assert len(bays.walks) == accessible  # each accessible bay's walk to the shop door
    assert _slots_are_clear(report.prepared.scenario) == []
    result = lotsim.run(report.prepared)
    assert lotsim.check(result).ok  # no car on an access aisle; none in a bay its use bars
    assert "ADA" in found.table() and " yes " in found.table()


def test_the_pavement_a_layout_takes_is_its_aisles_and_bays(tmp_path, capsys):
    # shapely's count from the written lot: the union of the aisles' strips (square at
    # their ends, as wide as written) and the bays, within the plot; the pavement lotsim
    # reports adds the kerb corners where aisles join (at most four where two cross), each
    # less than r² (1 - π/4) for r = 3 m, and nothing else
    found = lotsim.layout(SMALL, settings=QUICK)
    best = found.best
    sc = scenario_from_text(best.yaml)
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    ground = shapely.union_all([a.polygon for a in lot.aisles.values()]
                               + [Polygon(s.polygon) for s in lot.slots])
    ground = ground.intersection(Polygon(sc.lot.boundary))
    joins = sum(1 for a in lot.aisles.values() for b in lot.aisles.values()
                if a.id < b.id and a.polygon.intersects(b.polygon))
    assert ground.area - 0.05 <= best.paved <= ground.area + joins * 4 * 9 * (1 - math.pi / 4)
    assert best.bays * 2.5 * 5.0 < best.paved < Polygon(sc.lot.boundary).area
    assert best.paved_per_bay == pytest.approx(best.paved / best.bays)
    # the table and the written lot say it
    assert f"paved {best.paved_per_bay:.1f} m² a bay" in best.document()
    table = found.table()
    assert "paved/bay" in table.splitlines()[0]
    assert f"{best.paved_per_bay:9.1f}" in table.splitlines()[1]
