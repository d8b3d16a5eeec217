"""Corners too close for the clothoids of cruising speed (:func:`corner_sharpness`): legs
long enough keep the sharpness asked for; short legs get sharper clothoids that fill them
exactly, checked against a numerical integration of the path's curvature; legs too short
even for plain arcs are refused."""

from __future__ import annotations

import math

import numpy as np
import pytest
from small_lots import SHORT_LEGS

from conftest import scenario_from_text
from lotsim.core.corners import corner_sharpness
from lotsim.core.geometry import cc_polyline
from lotsim.errors import ScenarioError
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle


def integrate(kappa_at, length: float, n: int = 200_000) -> np.ndarray:
    """Points of a path from the origin heading east whose curvature at arc length s is
    ``kappa_at(s)``, by the trapezoidal rule (heading) and the midpoint rule (position)."""
    s = np.linspace(0.0, length, n + 1)
    k = kappa_at(s)
    theta = np.concatenate([[0.0], np.cumsum((k[1:] + k[:-1]) / 2 * np.diff(s))])
    mid = (theta[1:] + theta[:-1]) / 2
    x = np.concatenate([[0.0], np.cumsum(np.cos(mid) * np.diff(s))])
    y = np.concatenate([[0.0], np.cumsum(np.sin(mid) * np.diff(s))])
    return np.column_stack([x, y, theta])


def tangent_length(radius: float, sigma: float, deflection: float) -> float:
    """Distance from a clothoid-arc-clothoid turn's start to where its end's tangent line
    meets the start's, from an integration of its curvature."""
    peak = 1 / radius
    ramp = peak / sigma
    arc = (deflection - peak * ramp) / peak
    total = 2 * ramp + arc

    def kappa(s):
        return np.minimum.reduce([s * sigma, np.full_like(s, peak), (total - s) * sigma])

    x, y, theta = integrate(kappa, total)[-1]
    return float(x - y / math.tan(theta))


def test_legs_long_enough_keep_the_sharpness_asked_for():
    square = [[0, 0], [40, 0], [40, 40], [0, 40]]
    assert corner_sharpness(square, 5.0, 0.05, 1.0) == [0.05, 0.05]


@pytest.mark.parametrize("leg", [10.5, 11.0, 12.5])
def test_the_corners_of_a_short_leg_share_it_exactly(leg):
    """A leg between two equal right-angle corners: each corner's turn takes half of it."""
    pts = [[0, 0], [30, 0], [30, leg], [0, leg]]
    sigma = corner_sharpness(pts, 4.97, 0.05, 10.0)
    assert sigma[0] == pytest.approx(sigma[1]) and sigma[0] > 0.05
    assert tangent_length(4.97, sigma[0], math.pi / 2) == pytest.approx(leg / 2, abs=1e-4)
    # and the lane made with them is continuous in curvature, from the first to the last point
    segs = cc_polyline(pts, 4.97, sigma)
    for a, b in zip(segs[:-1], segs[1:], strict=True):
        assert a.end_curvature == pytest.approx(b.curvature, abs=1e-9)
        assert np.allclose(a.end[:2], b.start[:2], atol=1e-9)
    assert np.allclose(segs[-1].end[:2], [0, leg], atol=1e-6)


def test_the_legs_at_the_ends_are_the_corners_own():
    pts = [[0, 0], [5.5, 0], [5.5, 30]]  # a first leg shorter than the turn at its end
    (sigma,) = corner_sharpness(pts, 4.97, 0.05, 10.0)
    assert tangent_length(4.97, sigma, math.pi / 2) == pytest.approx(5.5, abs=1e-4)


def test_a_leg_too_short_even_for_plain_arcs_is_refused_with_what_it_needs():
    with pytest.raises(ValueError, match=r"leg 1 is 9\.90 m long.*9\.94 m"):
        corner_sharpness([[0, 0], [20, 0], [20, 9.9], [0, 9.9]], 4.97, 0.05, 10.0)




def test_an_aisle_with_short_legs_is_built_and_its_lane_driven_slower():
    sc = scenario_from_text(SHORT_LEGS.replace("LEG", "16"))  # an 11 m leg
    design = DesignVehicle.envelope(sc.vehicle_types)
    aisle = build_lot(sc.lot, design).aisles["ring"]
    assert all(c > aisle.bend_sharpness for c in aisle.corners)
    # the speed the steering rate allows on those clothoids, above the crawl
    speed = design.max_curvature_rate / max(aisle.corners)
    assert sc.lot.settings.crawl_speed < speed < math.sqrt(design.max_lateral_accel * 4.97)


def test_an_aisle_no_car_can_drive_is_refused_where_it_is_written():
    sc_text = SHORT_LEGS.replace("LEG", "14.9")  # a 9.9 m leg: arcs alone need 9.94 m
    with pytest.raises(ScenarioError) as err:
        sc = scenario_from_text(sc_text)
        build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    assert err.value.where.key == "lot.aisles[0]"
    assert "too short for its corners" in str(err.value)
    assert "even at a crawl" in str(err.value)


def test_the_drawing_of_a_lot_keeps_each_corners_sharpness():
    import json

    from lotsim.io.lot_json import lot_from_json, lot_to_json

    sc = scenario_from_text(SHORT_LEGS.replace("LEG", "16"))
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    back = lot_from_json(json.loads(json.dumps(lot_to_json(lot))))
    assert back.aisles["ring"].corners == lot.aisles["ring"].corners
    assert np.allclose(back.aisles["ring"].legs[2], lot.aisles["ring"].legs[2], atol=1e-6)
