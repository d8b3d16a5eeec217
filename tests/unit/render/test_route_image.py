"""Service routes drawn over their lot: the envelopes change the picture where they are and
nowhere else (but the clearance tags), each route has its row in the legend, a failed
route says so and draws nothing it did not find."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from conftest import ROOT
from lotsim.core.outcome import Status
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.render.lot_image import draw_lot, lot_layout
from lotsim.render.maneuver_image import FORWARD, REVERSE
from lotsim.render.route_image import RouteOverlay, draw_routes, route_colour, route_label
from lotsim.roadmap.service_routes import RouteReport, plan_routes

SIZE = (600, 450)


@pytest.fixture(scope="module")
def storefront():
    sc = load_scenario(ROOT / "scenarios" / "lots" / "storefront.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    reports = plan_routes(lot, sc.routes)
    assert [r.passed for r in reports] == [True, True]
    return lot, reports


class Unpainted(RouteOverlay):
    """The same layout and legend as the routes', with nothing drawn over the lot."""

    def paint(self, img, canvas) -> None:
        pass


def world_of_pixels(canvas):
    """The world point [m] of every pixel's centre, (H, W, 2)."""
    w, h = canvas.size
    ys, xs = np.mgrid[0:h, 0:w]
    return canvas.to_world(np.stack([xs, ys], axis=-1).astype(float))


def test_the_envelopes_change_the_picture_where_they_are_and_nowhere_else(storefront):
    lot, reports = storefront
    drawn = np.asarray(draw_routes(lot, reports, size=SIZE))
    bare = np.asarray(draw_lot(lot, size=SIZE, overlay=Unpainted(reports)))
    canvas = lot_layout(lot, size=SIZE, overlay=RouteOverlay(reports)).canvas
    changed = np.any(drawn != bare, axis=2)
    world = world_of_pixels(canvas)
    envelopes = shapely.union_all([r.envelope for r in reports])
    grown = envelopes.buffer(3.0 / canvas.scale)  # the outline's width
    shrunk = envelopes.buffer(-3.0 / canvas.scale)
    inside = shapely.contains_xy(shrunk, world[..., 0], world[..., 1])
    near = shapely.contains_xy(grown, world[..., 0], world[..., 1])
    tags = np.zeros_like(changed)  # each clearance's ring and its tag beside it
    for r in reports:
        cx, cy = np.rint(canvas.to_px(np.array(r.clearance_at))).astype(int)
        tags[max(cy - 20, 0):cy + 20, max(cx - 20, 0):cx + 90] = True
    assert inside.sum() > 2000
    # every pixel under the translucent fill but the labels, entrances and exits drawn over it
    assert changed[inside].mean() > 0.85
    stray = changed & ~near & ~tags
    assert stray.sum() == 0, f"{stray.sum()} pixels changed outside the envelopes"
    # outside the lot's box there is only what the envelopes add
    assert changed.sum() > inside.sum()


def test_the_path_is_blue_forward_and_orange_in_reverse(storefront):
    lot, reports = storefront
    img = np.asarray(draw_routes(lot, reports, size=SIZE))
    colours = {tuple(c) for c in img.reshape(-1, 3)}
    assert FORWARD in colours and REVERSE in colours
    assert all(any(s.gear < 0 for s in r.segments) for r in reports)  # both reverse


def test_each_route_has_its_row_in_the_legend(storefront):
    _, reports = storefront
    labels = [e.label for e in RouteOverlay(reports).entries()]
    assert labels[:2] == [route_label(r) for r in reports]
    assert labels[0] == "fire_front (fire_pump): passes, 0.30 m clear"
    assert {"route forward", "route reverse", "tightest clearance"} <= set(labels)
    assert route_colour(0) != route_colour(1)


def test_a_failed_route_says_so_and_draws_nothing_it_did_not_find(storefront):
    lot, _ = storefront
    failed = RouteReport("bins", "refuse_26t", Status.NO_PATH, "no path to exit 'west_out'")
    overlay = RouteOverlay([failed])
    assert [e.label for e in overlay.entries()] == ["bins (refuse_26t): FAILS"]
    assert overlay.bounds() is None
    drawn = np.asarray(draw_routes(lot, [failed], size=SIZE))
    bare = np.asarray(draw_lot(lot, size=SIZE, overlay=Unpainted([failed])))
    canvas = lot_layout(lot, size=SIZE, overlay=overlay).canvas
    left, top, right, bottom = (int(v) for v in canvas.drawing_box)
    assert np.array_equal(drawn[top:bottom, left:right], bare[top:bottom, left:right])
