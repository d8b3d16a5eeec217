"""The lot picture: layout, what is drawn where, and the atomic PNG write."""

from __future__ import annotations

import dataclasses
import math
import os

import numpy as np
import pytest
from PIL import Image

from lotsim.io.scenario_yaml import parse_scenario
from lotsim.io.yamlnodes import parse_text
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.render import LotCanvas, centered_footprints, draw_lot, lot_layout, save_lot_png
from lotsim.render import lot_image as li
from lotsim.roadmap.assemble import build_graph

LOT_YAML = """
name: render-test
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [40, 0], [40, 20], [0, 20]]
  aisles:
    - {id: main, centerline: [[0, 10], [40, 10]], width: 7.0}
  rows:
    - {aisle: main, side: left, kind: perpendicular, count: 8, slot_width: 2.5,
       slot_length: 5.0, start: 8.0, id_prefix: N}
    - {aisle: main, side: right, kind: perpendicular, count: 8, slot_width: 2.5,
       slot_length: 5.0, start: 8.0, id_prefix: S}
  no_go:
    - {id: hatch, polygon: [[1, 14], [6, 14], [6, 19], [1, 19]]}
  speed_bumps:
    - {id: bump, line: [[31, 6.5], [31, 13.5]], limit_kmh: 10}
  speed_zones:
    - {id: slow, polygon: [[34, 7], [38, 7], [38, 13], [34, 13]], limit_kmh: 5}
  entrances:
    - {id: in, x: 3.0, y: 8.25, heading_deg: 0}
  exits:
    - {id: out, x: 5.0, y: 11.75, heading_deg: 180}
  occupied: [N2, S5]
"""

SIZE = (800, 600)


def build(text: str = LOT_YAML):
    sc = parse_scenario(parse_text(text, "t.yaml"))
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    return sc, build_graph(lot)


@pytest.fixture(scope="module")
def scene():
    return build()


def rgb(img: Image.Image, xy) -> tuple[int, int, int]:
    x, y = np.rint(np.asarray(xy, dtype=float)).astype(int)
    return img.getpixel((int(x), int(y)))


def pixels(img: Image.Image) -> np.ndarray:
    return np.asarray(img.convert("RGB"))


# -- the world → pixel transform ---------------------------------------------------------------
def test_canvas_flips_y_keeps_aspect_and_centres() -> None:
    c = LotCanvas((0, 0, 20, 10), (300, 300), frame=(0, 0, 300, 300))
    assert c.scale == pytest.approx(15.0)  # width-limited: 300 px / 20 m
    # world top-left is image top-left of the centred drawing; y grows downwards
    assert c.to_px([0, 10]).tolist() == pytest.approx([0.0, 75.0])
    assert c.to_px([20, 0]).tolist() == pytest.approx([300.0, 225.0])
    pts = np.array([[[1.0, 2.0], [3.0, 4.0]]])
    assert c.to_px(pts).shape == (1, 2, 2)
    assert c.to_world(c.to_px(pts)) == pytest.approx(pts)
    assert c.drawing_box == pytest.approx((0.0, 75.0, 300.0, 225.0))


# -- what the picture shows --------------------------------------------------------------------
def test_image_has_the_requested_size(scene) -> None:
    _, g = scene
    for size in [(800, 600), (333, 777), (200, 150)]:
        img = draw_lot(g, size=size, title="t")
        assert img.size == size
        assert img.mode == "RGB"


def test_parked_cars_fill_taken_slots_only(scene) -> None:
    sc, g = scene
    img = draw_lot(g, size=SIZE, parked_vehicle=sc.parked_vehicle, labels=False)
    canvas = lot_layout(g, size=SIZE).canvas
    slots = g.lot.slot_by_id
    assert rgb(img, canvas.to_px(slots["N2"].center)) == li.PARKED_CAR
    assert rgb(img, canvas.to_px(slots["S5"].center)) == li.PARKED_CAR
    for sid in ("N1", "N3", "S3", "S4"):  # (S8 is tinted by the bump's reach)
        assert rgb(img, canvas.to_px(slots[sid].center)) != li.PARKED_CAR
        assert rgb(img, canvas.to_px(slots[sid].center)) == li.SLOT_PAVING


def test_parked_car_windscreen_is_on_the_heading_side(scene) -> None:
    sc, g = scene
    img = draw_lot(g, size=SIZE, parked_vehicle=sc.parked_vehicle, labels=False)
    canvas = lot_layout(g, size=SIZE).canvas
    length = sc.parked_vehicle.length
    for sid in ("N2", "S5"):  # N faces +y (up in the image), S faces -y
        slot = g.lot.slot_by_id[sid]
        u = np.array([math.cos(slot.heading), math.sin(slot.heading)])
        c = np.array(slot.center)
        assert rgb(img, canvas.to_px(c + 0.19 * length * u)) == li.PARKED_CAR_FRONT
        assert rgb(img, canvas.to_px(c - 0.19 * length * u)) == li.PARKED_CAR
    # the N row is above the aisle in the world, so above it in the image
    n2, s5 = g.lot.slot_by_id["N2"], g.lot.slot_by_id["S5"]
    assert canvas.to_px(n2.center)[1] < canvas.to_px(s5.center)[1]


def test_centered_footprints_sit_in_the_slot_facing_its_heading(scene) -> None:
    sc, g = scene
    slot = g.lot.slot_by_id["N2"]
    v = sc.parked_vehicle
    fp = centered_footprints([slot], v)[0]
    assert fp.mean(axis=0) == pytest.approx(np.array(slot.center))
    front = (fp[1] + fp[2]) / 2 - (fp[0] + fp[3]) / 2  # rear → front
    assert math.atan2(front[1], front[0]) == pytest.approx(slot.heading)
    assert np.hypot(*front) == pytest.approx(v.length)
    box = centered_footprints([slot], None)[0]
    assert box.mean(axis=0) == pytest.approx(np.array(slot.center))
    assert np.hypot(*(box[1] - box[0])) == pytest.approx(4.5)
    assert np.hypot(*(box[3] - box[0])) == pytest.approx(1.8)


def test_no_go_zone_is_hatched(scene) -> None:
    _, g = scene
    img = pixels(draw_lot(g, size=SIZE))
    canvas = lot_layout(g, size=SIZE).canvas
    (x0, y0), (x1, y1) = np.rint(canvas.to_px([[1.5, 18.5], [5.5, 14.5]])).astype(int)
    inside = img[y0:y1, x0:x1].reshape(-1, 3)
    hatch = np.all(inside == li.NO_GO_HATCH, axis=1)
    assert 0.1 < hatch.mean() < 0.6  # lines, not a solid fill
    # and nowhere outside the zone's surroundings
    (ox0, oy0), (ox1, oy1) = np.rint(canvas.to_px([[10, 9], [30, 1]])).astype(int)
    outside = img[oy0:oy1, ox0:ox1].reshape(-1, 3)
    assert not np.any(np.all(outside == li.NO_GO_HATCH, axis=1))


def test_speed_bump_is_striped_yellow_and_black(scene) -> None:
    _, g = scene
    img = draw_lot(g, size=SIZE, labels=False)
    canvas = lot_layout(g, size=SIZE).canvas
    line = canvas.to_px(np.column_stack([np.full(60, 31.0), np.linspace(7, 13, 60)]))
    colors = {rgb(img, p) for p in line}
    assert li.BUMP_YELLOW in colors
    assert li.BUMP_BLACK in colors


def test_entrance_green_exit_red(scene) -> None:
    _, g = scene
    img = draw_lot(g, size=SIZE)
    canvas = lot_layout(g, size=SIZE).canvas
    assert rgb(img, canvas.to_px([3.0, 8.25])) == li.ENTRANCE
    assert rgb(img, canvas.to_px([5.0, 11.75])) == li.EXIT


def test_show_graph_draws_along_the_lanes(scene) -> None:
    _, g = scene
    plain = pixels(draw_lot(g, size=SIZE, labels=False, legend=False))
    graph = pixels(draw_lot(g, size=SIZE, labels=False, legend=False, show_graph=True))
    canvas = lot_layout(g, size=SIZE, show_graph=True, legend=False).canvas
    # with no legend (whose rows differ) the lot sits in the same place
    assert canvas.to_px([1.0, 2.0]) == pytest.approx(
        lot_layout(g, size=SIZE, legend=False).canvas.to_px([1.0, 2.0])
    )
    for lane in g.lot.lanes:
        px = np.rint(canvas.to_px(lane.sample(0.5)[:, :2])).astype(int)
        changed = np.any(plain[px[:, 1], px[:, 0]] != graph[px[:, 1], px[:, 0]], axis=1)
        assert changed.mean() > 0.5, lane.id
    # an edge's pixels carry the lane-edge colour
    lane = g.lot.lanes[0]
    px = np.rint(canvas.to_px(lane.sample(0.5)[:, :2])).astype(int)
    assert np.any(np.all(graph[px[:, 1], px[:, 0]] == li.GRAPH_EDGE["lane"], axis=1))


def test_multi_point_turns_have_their_own_colour_and_key() -> None:
    """The cul-de-sac's turnarounds are drawn in their own colour, and the key names them;
    a graph without any has no such entry."""
    from pathlib import Path

    from lotsim.io.scenario_yaml import load_scenario
    from lotsim.render.lot_image.legend import _legend_entries

    lots = Path(__file__).resolve().parents[3] / "scenarios" / "lots"
    sc = load_scenario(lots / "culdesac.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    g = build_graph(lot, vehicles=sc.vehicle_types)
    turnarounds = [d["path"] for *_, d in g.graph.edges(data=True) if d["kind"] == "turnaround"]
    assert turnarounds
    colour = li.GRAPH_EDGE["turnaround"]
    assert colour not in [c for k, c in li.GRAPH_EDGE.items() if k != "turnaround"]
    img = pixels(draw_lot(g, size=SIZE, labels=False, legend=False, show_graph=True))
    canvas = lot_layout(g, size=SIZE, show_graph=True, legend=False).canvas
    for path in turnarounds:
        pts = np.concatenate([s.sample(0.25) for s in path])[:, :2]
        px = np.rint(canvas.to_px(pts)).astype(int)
        assert np.all(img[px[:, 1], px[:, 0]] == colour, axis=1).mean() > 0.3
    assert "multi-point turn" in [e.label for e in _legend_entries(g, lot, True)]
    bare = g.graph.copy()
    bare.remove_edges_from([(u, v) for u, v, d in g.graph.edges(data=True)
                            if d["kind"] == "turnaround"])
    plain = dataclasses.replace(g, graph=bare)
    assert "multi-point turn" not in [e.label for e in _legend_entries(plain, lot, True)]


def test_labels_can_be_turned_off_and_a_bare_lot_draws(scene) -> None:
    _, g = scene
    with_labels = pixels(draw_lot(g, size=SIZE))
    without = pixels(draw_lot(g, size=SIZE, labels=False))
    assert np.any(with_labels != without)
    bare = pixels(draw_lot(g.lot, size=SIZE))
    assert np.array_equal(bare, with_labels)
    with pytest.raises(TypeError):
        draw_lot(g.lot, show_graph=True)


def test_title_and_legend_sit_outside_the_lot(scene) -> None:
    _, g = scene
    layout = lot_layout(g, size=SIZE, title="render-test")
    left, top, right, bottom = layout.canvas.drawing_box
    assert layout.title_xy is not None and layout.title_xy[1] < top
    assert layout.legend_xy is not None
    lx, ly = layout.legend_xy
    assert lx >= right or ly >= bottom
    w, h = layout.legend.size(layout.legend_columns)
    assert lx + w <= SIZE[0] and ly + h <= SIZE[1]
    assert left >= 0 and right <= SIZE[0] and top >= 0 and bottom <= SIZE[1]


def test_slot_labels_are_skipped_when_slots_are_tiny(scene) -> None:
    _, g = scene
    big = lot_layout(g, size=(2000, 1500), legend=False)
    tiny = lot_layout(g, size=(200, 150), legend=False)
    assert big.canvas.px(2.5) > 14 > tiny.canvas.px(2.5)
    a = pixels(draw_lot(g, size=(200, 150), legend=False, labels=True))
    b = pixels(draw_lot(g, size=(200, 150), legend=False, labels=False))
    # only the portal ids and the speed limits differ, not slot ids
    canvas = tiny.canvas
    for slot in g.lot.slots:
        x, y = np.rint(canvas.to_px(slot.center)).astype(int)
        assert np.array_equal(a[y - 1 : y + 2, x - 1 : x + 2], b[y - 1 : y + 2, x - 1 : x + 2])


# -- the PNG file ------------------------------------------------------------------------------
def test_save_lot_png_writes_a_png_and_no_temp_file(scene, tmp_path) -> None:
    sc, g = scene
    out = tmp_path / "lot.png"
    save_lot_png(g, out, size=(640, 480), show_graph=True, parked_vehicle=sc.parked_vehicle,
                 title=sc.name)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with Image.open(out) as im:
        im.verify()
    with Image.open(out) as im:
        assert im.format == "PNG" and im.size == (640, 480)
    assert sorted(os.listdir(tmp_path)) == ["lot.png"]
    # overwriting keeps it a single, complete file
    save_lot_png(g, str(out), size=(320, 240))
    with Image.open(out) as im:
        assert im.size == (320, 240)
    assert sorted(os.listdir(tmp_path)) == ["lot.png"]


def test_save_lot_png_cleans_up_when_the_move_fails(scene, tmp_path, monkeypatch) -> None:
    _, g = scene

    def broken(src, dst):
        raise OSError("disk on fire")

    monkeypatch.setattr(li.os, "replace", broken)
    with pytest.raises(OSError, match="disk on fire"):
        save_lot_png(g, tmp_path / "lot.png", size=(200, 150))
    assert os.listdir(tmp_path) == []


# -- a large lot ------------------------------------------------------------------------------
def test_a_thousand_slot_lot_draws_every_slot() -> None:
    rows = "\n".join(
        f"    - {{aisle: a{k}, side: {side}, kind: perpendicular, count: 125, slot_width: 2.5,"
        f" slot_length: 5.0, start: 2.0, id_prefix: {side[0].upper()}{k}-}}"
        for k in range(4)
        for side in ("left", "right")
    )
    aisles = "\n".join(
        f"    - {{id: a{k}, centerline: [[0, {8.5 + 17 * k}], [316.5, {8.5 + 17 * k}]],"
        f" width: 7.0}}"
        for k in range(4)
    )
    text = f"""
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [316.5, 0], [316.5, 68], [0, 68]]
  aisles:
{aisles}
  rows:
{rows}
  entrances:
    - {{id: in, x: 1.0, y: 6.75, heading_deg: 0}}
  exits:
    - {{id: out, x: 5.0, y: 10.25, heading_deg: 180}}
  occupied: {{fraction: 0.3, seed: 1}}
"""
    sc, g = build(text)
    assert len(g.lot.slots) == 1000
    # how long it takes is benchmarks/bench_pictures.py's to measure
    img = draw_lot(g, parked_vehicle=sc.parked_vehicle, labels=False)
    assert img.size == (1200, 900)
    canvas = lot_layout(g, size=img.size).canvas
    seen = {s.id: rgb(img, canvas.to_px(s.center)) for s in g.lot.slots}
    taken = {sid for sid, colour in seen.items() if colour == li.PARKED_CAR}
    assert taken == set(g.lot.occupied) and 250 < len(taken) < 350
    assert all(colour == li.SLOT_PAVING for sid, colour in seen.items() if sid not in taken)


def test_the_pixel_padding_is_not_named_like_the_safety_margin_in_metres() -> None:
    # lot_image.MARGIN (14 px) read like lotsim.maneuvers.settings.MARGIN (0.1 m)
    import lotsim.render.animation as anim
    import lotsim.render.maneuver_image as mi
    from lotsim.maneuvers import settings

    for module in (li, anim, mi):
        assert not hasattr(module, "MARGIN")
    assert li.PAD_PX == 14 and settings.MARGIN == 0.1


def _text_box(c, w: float, h: float, angle: float) -> np.ndarray:
    """Corners [px] of a ``w`` x ``h`` text box centred at ``c`` and turned ``angle`` degrees
    counter-clockwise as seen (the image's y axis points down)."""
    a = math.radians(angle)
    along, down = np.array([math.cos(a), -math.sin(a)]), np.array([math.sin(a), math.cos(a)])
    return np.array([np.asarray(c) + sx * w / 2 * along + sy * h / 2 * down
                     for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))])


@pytest.mark.slow
def test_slot_ids_of_a_big_lot_are_drawn_along_the_slots_where_they_fit_only_so() -> None:
    # show of the large lot drew no id at its largest size (4000 px): they fit only turned
    import shapely

    from lotsim.io.scenario_yaml import load_scenario
    from lotsim.render.lot_image.layers import _slot_label_spots
    from lotsim.render.lot_image.theme import text_size

    sc = load_scenario(os.path.join(os.path.dirname(__file__), "..", "..", "..", "scenarios",
                                    "large_lot.yaml"))
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))  # no graph: not drawn
    size = (4000, 3000)
    canvas = lot_layout(lot, size=size).canvas
    spots = _slot_label_spots(canvas, lot, 0.0)
    assert len(spots) == len(lot.slots) == 1040
    turned = 0
    for sid, c, f, angle in spots:
        slot = lot.slot_by_id[sid]
        poly = shapely.Polygon(canvas.to_px(np.asarray(slot.polygon, dtype=float)))
        w, h = text_size(sid, f)
        assert poly.contains(shapely.Polygon(_text_box(c, w, h, angle))), sid
        if angle:
            turned += 1
            # along the slot's long side, read from the left or from below
            long_side = canvas.px(max(slot.width, slot.length))
            assert w > canvas.px(min(slot.width, slot.length)) - 2 and w < long_side
            assert -90 < angle <= 90
    assert turned > 1000
    # drawn alone on a white page, every pixel of the ids lies in a slot, and each slot has ink
    from lotsim.render.lot_image.layers import _label_slots

    page = Image.new("RGB", size, (255, 255, 255))
    _label_slots(page, canvas, lot, 0.0)
    ink = np.argwhere(np.any(pixels(page) != 255, axis=2))
    polys = [shapely.Polygon(canvas.to_px(np.asarray(s.polygon, dtype=float)))
             for s in lot.slots]
    x, y = ink[:, 1] + 0.5, ink[:, 0] + 0.5
    assert shapely.contains_xy(shapely.union_all(polys).buffer(1.0), x, y).all()
    for poly in polys[::97]:
        assert shapely.contains_xy(poly, x, y).sum() > 10


def test_the_ground_is_drawn_as_it_is_paved_or_not() -> None:
    """A lot paved wall to wall is paved between its rows and the boundary; one that says
    what is paved shows the rest as unpaved ground, and its kerb corners paved."""
    whole_sc, whole = build()
    paved_text = LOT_YAML.replace("  aisles:\n", "  paved: {}\n  aisles:\n", 1)
    _, paved = build(paved_text)
    verge = (20.0, 0.5)  # between the south row's backs and the boundary
    for g, expected in ((whole, li.PAVED), (paved, li.GROUND)):
        img = draw_lot(g, size=SIZE, labels=False, legend=False)
        canvas = lot_layout(g, size=SIZE, legend=False).canvas
        assert rgb(img, canvas.to_px(verge)) == expected
        assert rgb(img, canvas.to_px((20.0, 10.0))) != li.GROUND  # the aisle


def test_the_graph_legend_gives_each_kind_of_link_its_own_colour(scene) -> None:
    """Junction turns and park links each have a swatch in the colour they are drawn in."""
    from lotsim.render.lot_image.legend import _legend_entries

    _, g = scene
    entries = {e.label: e for e in _legend_entries(g, g.lot, True)}
    assert "park link (to a slot)" in entries
    swatches = {}
    for label in ("park link (to a slot)", "junction turn"):
        if label in entries:
            img = Image.new("RGB", (30, 20), (0, 0, 0))
            entries[label].swatch(img, (0, 0, 29, 19))
            swatches[label] = {c for _, c in img.getcolors(600)}
    assert li.GRAPH_EDGE["park"] in swatches["park link (to a slot)"]
    assert li.GRAPH_EDGE["turn"] not in swatches["park link (to a slot)"]
