"""Vehicle types: catalogue figures, turning radius, footprints against shapely."""

import math

import numpy as np
import pytest
import shapely
from shapely import affinity
from shapely.geometry import box

from lotsim.vehicles import CATALOGUE, VehicleType
from oracles.catalogue import DESIGN_TABLE


@pytest.mark.parametrize("name", sorted(DESIGN_TABLE))
def test_catalogue_matches_the_reports_appendix(name):
    w, df, dr, b, deg = DESIGN_TABLE[name]
    car = CATALOGUE[name]
    assert (car.width, car.front, car.rear, car.wheelbase) == (w, df, dr, b)
    assert math.degrees(car.max_steer) == pytest.approx(deg)
    assert car.length == pytest.approx(df + dr)
    assert car.min_turning_radius == pytest.approx(b / math.tan(math.radians(deg)))


def test_valet_car_is_the_valet_papers_car():
    car = CATALOGUE["valet"]
    assert car.length == pytest.approx(4.9) and car.width == 1.8 and car.wheelbase == 2.8
    assert math.degrees(car.max_steer) == pytest.approx(470 / 16)
    # R = b / tan(phi), not the paper's L / (2 sin phi)
    assert car.min_turning_radius == pytest.approx(2.8 / math.tan(math.radians(29.375)))
    assert car.limits.max_forward_speed == pytest.approx(20 / 3.6)
    assert car.limits.max_reverse_speed == pytest.approx(10 / 3.6)


def test_footprints_match_shapely_rotation():
    car = CATALOGUE["vclass"]
    rng = np.random.default_rng(2)
    poses = rng.uniform([-20, -20, -math.pi], [20, 20, math.pi], size=(40, 3))
    fps = car.footprints(poses)
    assert fps.shape == (40, 4, 2)
    for (x, y, t), fp in zip(poses, fps, strict=True):
        ref = box(-car.rear, -car.width / 2, car.front, car.width / 2)
        ref = affinity.translate(affinity.rotate(ref, t, origin=(0, 0), use_radians=True), x, y)
        poly = shapely.Polygon(fp)
        assert poly.is_valid and poly.exterior.is_ccw
        assert poly.symmetric_difference(ref).area < 1e-9


def test_drive_at_full_steer_circles_with_min_radius():
    car = CATALOGUE["altis"]
    r = car.min_turning_radius
    quarter = car.drive([0.0, 0.0, 0.0], math.pi / 2 * r, car.max_steer)
    assert np.allclose(quarter, [r, r, math.pi / 2])
    back = car.drive([0.0, 0.0, 0.0], -math.pi / 2 * r, car.max_steer)
    assert np.allclose(back, [-r, r, -math.pi / 2])


def test_invalid_dimensions_are_rejected():
    with pytest.raises(ValueError, match="width"):
        VehicleType("x", width=-1, front=3, rear=1, wheelbase=2.5, max_steer=0.5)
    with pytest.raises(ValueError, match="90"):
        VehicleType("x", width=1.8, front=3, rear=1, wheelbase=2.5, max_steer=math.pi / 2)
