"""The CAD layer table is closed and NCS-shaped: every name once, in the standard's
discipline-major-minor form; one bay layer per use, standard use on ``C-PRKG``; the page
that lists them lists the code's; the figures of a lot (no CAD package needed) put each
thing on its layer."""

from __future__ import annotations

import re

import pytest
from shapely.geometry import Point

from conftest import ROOT
from lotsim.api import EXAMPLE
from lotsim.api.exports import lot_of
from lotsim.io.cad_layers import BAY_LAYERS, BAY_USES, LAYER_NAMES, LAYERS, bay_layer
from lotsim.io.export.cad_drawing import (
    gates,
    lot_drawing,
    number_height,
    reading_angle,
    stripes,
)

NCS_NAME = re.compile(r"[A-Z]-[A-Z]{4}(-[A-Z]{4})?")
"""An NCS layer name: discipline, major group, an optional minor group."""


def test_each_layer_is_named_once_in_the_standard_s_form():
    names = [layer.name for layer in LAYERS]
    assert len(names) == len(set(names)) == len(LAYER_NAMES)
    assert all(NCS_NAME.fullmatch(n) for n in names), names
    assert {layer.origin for layer in LAYERS} == {"NCS", "lotsim"}
    assert LAYER_NAMES["stripe"] == "C-PRKG-STRP" and LAYER_NAMES["bay_number"] == "C-PRKG-IDEN"


def test_each_use_of_bay_has_its_own_parking_layer_and_no_other_use_passes():
    assert [u for u, _, _ in BAY_USES] == ["standard", "compact", "accessible",
                                           "van_accessible", "ev", "motorcycle"]
    assert bay_layer("standard") == "C-PRKG"
    others = set(BAY_LAYERS.values()) - {"C-PRKG"}
    assert len(others) == 5 and all(n.startswith("C-PRKG-") for n in others)
    assert all(LAYER_NAMES[f"bay:{use}"] == name for use, name in BAY_LAYERS.items())
    with pytest.raises(KeyError, match="no bay layer for the use 'Accessible'"):
        bay_layer("Accessible")


def test_stripes_skip_the_entry_and_draw_a_shared_side_once():
    lot = lot_of(EXAMPLE)  # two rows of 4 perpendicular bays side by side
    row = [s for s in lot.slots if s.id.startswith("N")]
    lines = stripes(tuple(row))
    assert len(lines) == 3 * len(row) - (len(row) - 1)
    for slot in row:
        entry = Point(slot.entry.mean(axis=0))
        assert all(Point((a[0] + b[0]) / 2, (a[1] + b[1]) / 2).distance(entry) > 1.0
                   for a, b in lines)


def test_texts_read_left_to_right_or_upwards():
    assert [reading_angle(t) for t in (0.0, 1.5707963267948966, 3.141592653589793,
                                       -1.5707963267948966, 4.0)] == pytest.approx(
        [0.0, 90.0, 0.0, 90.0, 49.18310577])


def test_the_gate_is_where_the_entrance_and_exit_lanes_cross_the_boundary():
    lot = lot_of(EXAMPLE)  # a one-way aisle along y = 10: in at x = 3, out at x = 24, east
    assert [(g, tuple(round(v, 6) for v in at)) for g, at in gates(lot)] == [
        ("in", (0.0, 10.0)), ("out", (32.0, 10.0))]


def test_every_figure_is_on_a_layer_of_the_table():
    drawing = lot_drawing(lot_of(EXAMPLE))
    used = {f.layer for group in (drawing.polylines, drawing.segments, drawing.marks,
                                  drawing.labels) for f in group}
    assert used <= set(LAYER_NAMES.values())
    assert sum(p.layer == "C-PRKG" for p in drawing.polylines) == 8
    assert sum(p.layer == LAYER_NAMES["taken"] for p in drawing.polylines) == 2


def test_the_table_of_docs_export_md_is_the_code_s():
    page = (ROOT / "docs" / "export.md").read_text(encoding="utf-8")
    section = page[page.index("### Layers"):]
    rows = re.findall(r"^\| [^|]+ \| `([A-Z-]+)` \| (NCS|lotsim) \|", section, re.M)
    assert rows == [(layer.name, layer.origin) for layer in LAYERS]


def test_the_lot_of_a_scenario_is_the_lot_of_its_prepared_lot_and_of_its_run():
    import lotsim

    prepared = lotsim.prepare(EXAMPLE)
    shapes = [[s.id, s.polygon.round(6).tolist()] for s in lot_of(EXAMPLE).slots]
    for source in (prepared, lotsim.run(prepared), lotsim.result_dict(lotsim.run(prepared))):
        assert [[s.id, s.polygon.round(6).tolist()] for s in lot_of(source).slots] == shapes
    with pytest.raises(lotsim.SettingsError, match="expected a scenario or a run"):
        lot_of(3)


def test_a_bay_s_number_fits_along_the_bay_however_long_its_id():
    import dataclasses

    slot = lot_of(EXAMPLE).slots[0]  # 2.5 x 5.0 m
    assert number_height(slot) == 0.625  # a quarter of its width
    long = dataclasses.replace(slot, id="gate-gate-inL10")
    assert number_height(long) * 0.75 * len(long.id) <= 0.85 * slot.length + 1e-5  # to 1 µm
