"""``lotsim show --routes``: the picture differs from the lot's inside the envelopes and not
far from them; a scenario without routes is refused (exit 2) and nothing is written."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from PIL import Image

from conftest import ROOT
from lotsim.cli import main
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.render.lot_image import PAVED, lot_layout
from lotsim.render.route_image import RouteOverlay
from lotsim.roadmap.service_routes import plan_routes

STOREFRONT = ROOT / "scenarios" / "lots" / "storefront.yaml"
SIZE = (600, 450)


def colour(img: Image.Image, canvas, xy) -> tuple[int, int, int]:
    x, y = np.rint(canvas.to_px(np.array(xy, dtype=float))).astype(int)
    return img.getpixel((int(x), int(y)))


@pytest.mark.slow
def test_show_routes_draws_the_envelopes_over_the_lot(tmp_path, capsys):
    plain, routed = tmp_path / "lot.png", tmp_path / "routes.png"
    size = f"{SIZE[0]}x{SIZE[1]}"
    assert main(["show", str(STOREFRONT), "-o", str(plain), "--size", size]) == 0
    assert main(["show", str(STOREFRONT), "--routes", "-o", str(routed), "--size", size]) == 0
    out = capsys.readouterr().out
    assert "route fire_front (fire_pump): pass" in out and "route bin_collection" in out
    sc = load_scenario(STOREFRONT)
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    reports = plan_routes(lot, sc.routes)
    a, b = Image.open(plain).convert("RGB"), Image.open(routed).convert("RGB")
    ca = lot_layout(lot, size=SIZE, title=sc.name).canvas
    cb = lot_layout(lot, size=SIZE, title=sc.name, overlay=RouteOverlay(reports)).canvas
    paths = shapely.union_all([shapely.linestrings(r.poses[:, :2]) for r in reports])
    envelopes = shapely.union_all([r.envelope for r in reports])
    inner = envelopes.buffer(-0.5).difference(paths.buffer(0.6))
    points = [inner.representative_point()] + [
        r.envelope.buffer(-0.5).difference(paths.buffer(0.6)).representative_point()
        for r in reports]
    for p in points:
        assert colour(a, ca, (p.x, p.y)) != colour(b, cb, (p.x, p.y)), (p.x, p.y)
    x0, y0, x1, y1 = lot.boundary.bounds
    far = (x1 - 1.0, y1 - 1.0)  # the paved corner across the lot from the entrance
    assert envelopes.distance(shapely.Point(far)) > 10.0
    assert colour(a, ca, far) == colour(b, cb, far) == PAVED


def test_routes_of_a_scenario_without_routes_are_refused_and_nothing_written(tmp_path,
                                                                             capsys):
    out = tmp_path / "lot.png"
    assert main(["show", str(ROOT / "scenarios" / "example.yaml"), "--routes",
                 "-o", str(out)]) == 2
    assert "has no routes" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
