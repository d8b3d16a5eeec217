"""A bay's maneuver fitted from another bay of its shape: clear where it is used (by the
oracle that shares nothing with the planner), on its own start grid, never with more
direction changes than the bay's own search finds, and the same answers however the lot is
asked."""

import dataclasses
import math

import numpy as np
import pytest
import shapely

from conftest import scenario_from_text
from lotsim.core.geometry import Segment
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.maneuvers.batch import plan_lot
from lotsim.maneuvers.planner import search_maneuver
from lotsim.maneuvers.reuse import STRIDE, Found, changes, fitted, settle
from lotsim.sim.preparation import maneuver_planner
from oracles.maneuver_check import check_maneuver, parked_bodies

# bays on two pitches (2.6 and 2.75 m, as a real lot's rows are), off the 0.5 m start grid,
# across a narrow aisle; a pillar past the end of one row and the walls at the aisle's ends
# make bays of one shape differ around them
IRREGULAR = """
vehicle_types: [valet, corsa]
lot:
  boundary: [[0, 0], [62, 0], [62, 22], [0, 22]]
  aisles: [{id: a, centerline: [[0, 11], [62, 11]], width: 6.2}]
  rows:
    - {aisle: a, side: right, kind: perpendicular, count: 20, slot_width: 2.75,
       slot_length: 5.3, start: 3.1}
    - {aisle: a, side: left, kind: perpendicular, count: 21, slot_width: 2.6,
       slot_length: 5.3, start: 4.35}
  obstacles: [{id: pillar, polygon: [[58.6, 6.0], [59.2, 6.0], [59.2, 7.6], [58.6, 7.6]]}]
  entrances: [{id: in, x: 2, y: 9.45, heading_deg: 0}]
  exits: [{id: out, x: 4.5, y: 12.55, heading_deg: 180}]
traffic: {vehicles: [{id: x, arrival: 0}]}
"""


@pytest.fixture(scope="module")
def irregular():
    sc = scenario_from_text(IRREGULAR)
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    planner = maneuver_planner(sc, lot)
    found, infeasible, park_only = plan_lot(planner, sc.vehicle_types, workers=2)
    return lot, sc, planner, found, infeasible, park_only


def _problems(planner, sc, lot):
    """Each distinct problem the planner answered: key → (problem, style)."""
    types = {v.name: v for v in sc.vehicle_types}
    lanes = {lane.id: lane for lane in lot.lanes}
    out = {}
    for (vname, sid, lid, style), (key, _, _) in planner._posed.items():
        if key not in out:
            out[key] = planner.problems.pose(types[vname], lot.slot_by_id[sid], lanes[lid]), style
    return out


@pytest.mark.slow
def test_most_bays_are_fitted_and_none_has_more_direction_changes_than_its_own_search(
        irregular):
    lot, sc, planner, *_ = irregular
    fitted_keys = planner._fitted
    problems = _problems(planner, sc, lot)
    assert len(fitted_keys) > len(problems) / 2  # (the point of it)
    longer = []
    for key in fitted_keys:
        problem, style = problems[key]
        own, _ = search_maneuver(problem, style, planner.settings)
        got = planner._cache[key]
        assert own.found and got.found
        assert changes(got.value[0]) <= changes(own.value[0]), problem.slot.id
        longer.append(sum(s.length for s in got.value[0])
                      - sum(s.length for s in own.value[0]))
    assert np.mean(longer) < 0.5  # a fit may be a little longer, on average not much


def test_every_fitted_maneuver_passes_the_independent_check_and_starts_on_the_grid(irregular):
    lot, sc, planner, found, infeasible, park_only = irregular
    kinds = {v.name: v for v in sc.vehicle_types}
    everyone = [*sc.vehicle_types, sc.parked_vehicle]
    fitted_triples = {(v, s, ln) for (v, s, ln, _), (key, _, _) in planner._posed.items()
                      if key in planner._fitted}
    checked = 0
    for (vname, sid, lid), m in [*found.items(), *park_only.items()]:
        if (vname, sid, lid) not in fitted_triples:
            continue
        slot = lot.slot_by_id[sid]
        cars = parked_bodies([s for s in lot.slots if s.id != sid
                              and shapely.distance(s.shape, slot.shape) < 12.0], everyone)
        assert not check_maneuver(lot, m, kinds[vname], cars), (vname, sid, lid)
        assert abs(m.station / 0.5 - round(m.station / 0.5)) < 1e-6, (vname, sid, lid)
        checked += 1
    assert checked > 20
    assert not any(infeasible.values())


def test_a_maneuver_fits_only_where_it_is_clear_and_begins_on_the_grid(irregular):
    """A maneuver offered to the next bay of its shape fits it, begun on that bay's own
    start grid with the rest of it as it was; a post set down on its path makes it not fit."""
    lot, sc, planner, *_ = irregular
    v = sc.vehicle_types[0]
    row = [s for s in lot.slots if s.id.startswith("a-left")]
    a, b = row[3], row[4]
    lane = planner.lanes_for(a)[0]
    assert planner.problems.shape(v, a, lane) == planner.problems.shape(v, b, lane)
    offer = Found.of(search_maneuver(planner.problems.pose(v, a, lane), "forward",
                                     planner.settings))
    at_b = planner.problems.pose(v, b, lane)
    got = fitted(at_b, offer, planner.settings)
    assert got is not None
    segs, x = got[0].value
    assert (at_b.lane_s0 + x) / 0.5 == pytest.approx(round((at_b.lane_s0 + x) / 0.5), abs=1e-9)
    assert segs[-len(offer.answer.value[0]) + 1:] == offer.answer.value[0][1:]
    world = at_b.frame.segments_to_world(segs)
    mid = world[len(world) // 2].start
    post = shapely.Point(mid[:2]).buffer(0.2)
    obstacles = np.append(at_b.obstacles, post)
    blocked = dataclasses.replace(at_b, obstacles=obstacles, tree=shapely.STRtree(obstacles))
    assert fitted(blocked, offer, planner.settings) is None


@pytest.mark.slow
def test_planned_on_two_processes_or_one_problem_at_a_time_the_answers_are_the_same(irregular):
    """prefetch answers each class in rounds on the workers; solving slot after slot on a
    fresh planner answers each class in this process, as its first problem is asked for."""
    lot, sc, _, found, infeasible, park_only = irregular
    alone = maneuver_planner(sc, lot)
    want = {}
    for v in sc.vehicle_types:
        for slot in reversed(lot.slots):  # in another order: the answers do not depend on it
            got, own, _ = alone.solve_lanes(v, slot)
            want.update({(v.name, slot.id, k): m.segments for k, m in got.items()})
    assert {k: m.segments for k, m in found.items()} == want


def test_the_rounds_search_every_stride_then_the_first_of_each_run_left():
    """Members fit an offer from a member up to STRIDE places away when they are even;
    odd ones never fit, and are searched one run after another."""
    members = list(range(3 * STRIDE + 3))
    searched = []

    def search(ms):
        searched.append(sorted(ms))
        return [(f"own {m}", "raw") for m in ms]

    def fit(jobs):
        for m, offers in jobs:
            assert offers and all(abs(int(f.split()[1]) - m) <= STRIDE for f in offers)
        return [(f"fit {m}", "raw") if m % 2 == 0 else None for m, _ in jobs]

    class Offer(str):
        changes, length = 0, 0.0

    out = settle([members], search, fit, offer=lambda _, pair: Offer(pair[0]))
    assert searched[0] == list(range(0, len(members), STRIDE))
    odd = [m for m in members if m % 2 and m % STRIDE]
    assert [m for ms in searched[1:] for m in ms] == sorted(odd)
    assert all(out[m] == ((f"own {m}", "raw"), True) for m in odd)
    assert all(out[m][1] is False for m in members if m % 2 == 0 and m % STRIDE)


def test_a_fit_is_kept_by_the_offers_it_read_so_it_holds_when_later_ones_change(monkeypatch):
    """A fit reads the offers up to the first that fits: ``fit_first`` says how many it
    read, and ``fit_keys`` keeps it by those alone, so an edit that changes only offers
    after it finds it kept; a problem no offer fits is kept by them all."""
    from lotsim.maneuvers import reuse
    from lotsim.maneuvers.batch import fit_keys

    offers = [Found(0, 5.0 + k, None, None, bytes([k])) for k in range(4)]
    monkeypatch.setattr(reuse, "fitted", lambda problem, found, settings: (
        ("pair", found.source) if found.source == bytes([2]) else None))
    pair, read = reuse.fit_first(None, "any", offers, None, None)
    assert pair == ("pair", bytes([2])) and read == 3
    assert reuse.fit_first(None, "any", offers[:2], None, None) == (None, 2)
    keys = fit_keys(b"exact", offers)
    later = fit_keys(b"exact", [*offers[:3], Found(0, 9.0, None, None, b"new")])
    earlier = fit_keys(b"exact", [offers[0], Found(0, 9.0, None, None, b"new"), *offers[2:]])
    assert len(keys) == 5 and len(set(keys)) == 5
    assert later[:3] == keys[:3] and later[3:] != keys[3:]  # the fit at the third holds
    assert earlier[0] == keys[0] and not set(earlier[1:]) & set(keys)
    assert fit_keys(b"other", offers)[2] != keys[2]


def test_an_offer_is_named_by_its_maneuver_alone_to_the_last_bit():
    """Fits are kept by the maneuvers of the offers they read (``answer_key``): a problem
    searched again that finds the same maneuver names it alike, so the fits of it stand;
    a maneuver one bit longer, or begun elsewhere, is named otherwise."""
    import pickle

    from lotsim.core.outcome import Outcome
    from lotsim.maneuvers.reuse import answer_key

    segs = (Segment((-3.0, 1.75, 0.0), 4.5, 0.0), Segment((1.5, 1.75, 0.0), 3.2, -0.2))
    pair = (Outcome.of((segs, -3.0)), Outcome.of((segs, -3.0)))
    again = pickle.loads(pickle.dumps(pair))  # the same maneuver, found again
    assert again is not pair and answer_key(again) == answer_key(pair)
    assert Found.of(pair, named=True).source == answer_key(pair)
    assert Found.of(pair).source is None
    longer = (Segment(segs[0].start, math.nextafter(4.5, 5.0), 0.0), segs[1])
    for other in ((Outcome.of((longer, -3.0)), pair[1]), (pair[0], Outcome.of((segs, -2.5)))):
        assert answer_key(other) != answer_key(pair)
