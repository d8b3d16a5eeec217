"""lotsim.lot.clearance on a small hand-built lot: Collider's answers against shapely body by
body, and the coarse-to-fine first_blocked and RigidSweeps against checking every body on its
own."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from lotsim.core.geometry import advance, rectangle_footprints
from lotsim.lot.clearance import Collider, RigidSweeps, first_blocked

# a 30 m x 20 m lot holding a parked car (a box) and a pillar (a triangle)
BOUNDARY = shapely.box(0.0, 0.0, 30.0, 20.0)
OBSTACLES = [("car P1", shapely.box(10.0, 12.0, 12.0, 17.0)),
             ("pillar", shapely.Polygon([(20.0, 4.0), (22.0, 4.0), (21.0, 6.0)]))]


@pytest.fixture(scope="module")
def collider() -> Collider:
    return Collider(OBSTACLES, BOUNDARY)


def rectangles(rng: np.random.Generator, n: int) -> np.ndarray:
    """(n, 4, 2) car-sized rectangles at random poses, some poking out of the lot."""
    x, y = rng.uniform(-2.0, 32.0, n), rng.uniform(-2.0, 22.0, n)
    th = rng.uniform(-np.pi, np.pi, n)
    corners = np.array([[-1.0, -0.9], [3.9, -0.9], [3.9, 0.9], [-1.0, 0.9]])
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    return np.stack([x[:, None] + c * corners[:, 0] - s * corners[:, 1],
                     y[:, None] + s * corners[:, 0] + c * corners[:, 1]], axis=-1)


def path(rng: np.random.Generator, n: int) -> np.ndarray:
    """(n, 4, 2) footprints along a random walk: consecutive ones overlap, as a path's do."""
    x0, y0 = rng.uniform(6.0, 24.0), rng.uniform(6.0, 14.0)
    x, y = np.cumsum(rng.normal(0, 0.6, n)) + x0, np.cumsum(rng.normal(0, 0.6, n)) + y0
    th = np.cumsum(rng.normal(0, 0.2, n))
    corners = np.array([[-1.0, -0.9], [3.9, -0.9], [3.9, 0.9], [-1.0, 0.9]])
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    return np.stack([x[:, None] + c * corners[:, 0] - s * corners[:, 1],
                     y[:, None] + s * corners[:, 0] + c * corners[:, 1]], axis=-1)


def brute_blocked(bodies: np.ndarray) -> np.ndarray:
    """Body by body with shapely: its hull leaves the lot or touches an obstacle."""
    out = []
    for points in bodies:
        hull = shapely.MultiPoint(points).convex_hull
        out.append(not BOUNDARY.covers(hull)
                   or any(hull.intersects(g) for _, g in OBSTACLES))
    return np.array(out, dtype=bool)


def test_a_body_by_hand(collider) -> None:
    inside = np.array([[[2.0, 2.0], [6.0, 2.0], [6.0, 4.0], [2.0, 4.0]]])
    on_the_car = inside + [9.0, 10.0]  # (11, 12)-(15, 14): over the car's corner
    out_of_the_lot = inside - [3.0, 0.0]
    bodies = np.concatenate([inside, on_the_car, out_of_the_lot])
    assert collider.blocked(bodies).tolist() == [False, True, True]
    hit = collider.first_hit(bodies)
    assert (hit.index, hit.what) == (1, "car P1")
    assert collider.first_hit(bodies[2:]).what == "the lot boundary"
    assert collider.first_hit(inside) is None
    assert collider.first_hit(np.zeros((0, 4, 2))) is None


def test_blocked_and_first_hit_agree_with_shapely(collider) -> None:
    rng = np.random.default_rng(17)
    bodies = rectangles(rng, 400)
    want = brute_blocked(bodies)
    assert 0.2 < want.mean() < 0.8  # both kinds are tested
    assert np.array_equal(collider.blocked(bodies), want)
    for start in range(0, 400, 40):
        hit = collider.first_hit(bodies[start:start + 40])
        bad = np.flatnonzero(want[start:start + 40])
        if not bad.size:
            assert hit is None
            continue
        assert hit.index == bad[0]
        hull = shapely.MultiPoint(bodies[start + hit.index]).convex_hull
        if BOUNDARY.covers(hull):
            assert hull.intersects(dict(OBSTACLES)[hit.what])
        else:
            assert hit.what == "the lot boundary"


def test_a_sweep_is_checked_between_samples(collider) -> None:
    # two footprints either side of the pillar, both free: the motion between them is not
    start = np.array([[[14.0, 4.0], [18.0, 4.0], [18.0, 6.0], [14.0, 6.0]]])
    prints = np.concatenate([start, start + [10.0, 0.0]])
    assert not collider.blocked(prints).any()
    hit = collider.sweep_hit(prints)
    assert (hit.index, hit.what) == (0, "pillar")
    prints = path(np.random.default_rng(1), 60)
    sweeps = Collider.sweeps(prints)
    assert sweeps.shape == (59, 8, 2)
    want = brute_blocked(sweeps)
    assert np.flatnonzero(want)[0] > 0  # free at first, then blocked
    assert collider.sweep_hit(prints).index == np.flatnonzero(want)[0]


@pytest.mark.parametrize("span", [1, 2])
@pytest.mark.parametrize("block", [1, 3, 4])
def test_first_blocked_finds_what_checking_every_body_finds(collider, span, block) -> None:
    rng = np.random.default_rng(100 * span + block)
    found = 0
    for _ in range(20):
        n = int(rng.integers(1, 60))
        prints = path(rng, n + span - 1)
        # runs of consecutive bodies, some not asked (-1)
        run = np.repeat(np.arange(8), rng.integers(0, 12, 8))[:n]
        run = np.concatenate([run, np.full(n - len(run), 8)])
        run[rng.random(n) < 0.1] = -1
        bodies = np.concatenate([prints[k:k + n] for k in range(span)], axis=1)
        bad = brute_blocked(bodies)
        want = np.zeros(n, dtype=bool)
        for r in set(run.tolist()) - {-1}:
            mine = np.flatnonzero((run == r) & bad)
            if mine.size:
                want[mine[0]] = True
        got = first_blocked(collider.blocked, prints, run, span=span, block=block)
        assert np.array_equal(got, want), (run, bad)
        found += int(want.sum())
    assert found >= 10  # runs blocked part way, not only free ones


@pytest.mark.slow
@pytest.mark.parametrize("block", [1, 3, 4])
def test_rigid_sweeps_find_the_first_sweep_checking_every_one_finds(collider, block) -> None:
    # arcs at full lock and a straight, either gear, 1 m and 3 m long, from 150 random poses;
    # the oracle makes each footprint at its own pose and checks each sweep's hull alone
    corners = np.array([[-1.0, -0.9], [3.9, -0.9], [3.9, 0.9], [-1.0, 0.9]])
    motions = [(g * d, k) for g in (1, -1) for k in (0.2, 0.0, -0.2) for d in (1.0, 3.0)]
    steps = [np.linspace(0.0, d, round(abs(d) / 0.1) + 1) for d, _ in motions]
    sweeps = RigidSweeps([rectangle_footprints(advance(np.zeros(3), s, k), corners)
                          for s, (_, k) in zip(steps, motions, strict=True)], block)
    rng = np.random.default_rng(block)
    poses = np.column_stack([rng.uniform(-2.0, 32.0, 150), rng.uniform(-2.0, 22.0, 150),
                             rng.uniform(-np.pi, np.pi, 150)])
    got = sweeps.first_blocked(collider.blocked, poses)
    assert got.shape == (150, len(motions))
    part_way = 0
    for m, (s, (_, k)) in enumerate(zip(steps, motions, strict=True)):
        along = advance(np.repeat(poses[:, None, :], len(s), axis=1), s[None, :], k)
        prints = rectangle_footprints(along.reshape(-1, 3), corners).reshape(150, len(s), 4, 2)
        for i in range(150):
            bad = brute_blocked(np.concatenate([prints[i, :-1], prints[i, 1:]], axis=1))
            want = int(np.argmax(bad)) if bad.any() else len(s) - 1
            assert got[i, m] == want, (i, m)
            part_way += 0 < want < len(s) - 1
    assert part_way >= 20  # sweeps blocked part way along, not only at once or never
