"""Parking maneuvers, checked by an oracle that shares nothing with the planner.

The check samples the car's footprint every 5 cm of travel and asks shapely
whether it touches a neighbouring parked car (every vehicle type, parked centred
in every other perpendicular or angled slot; a whole parallel slot), a wall,
obstacle or no-go area, or leaves the lot; it recomputes curvature from the
sampled poses; and it asks whether the final footprint lies in the slot.
"""

import math
import pickle
import re

import numpy as np
import pytest
import shapely

from conftest import HEAVY, ROOT, SCENARIOS, graph_from_text, scenario_from_text
from lotsim.cli import main
from lotsim.core.geometry import wrap_angle
from lotsim.errors import InfeasibleManeuver, SettingsError
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.maneuvers.closing import first_clear
from lotsim.maneuvers.maneuver import Maneuver
from lotsim.maneuvers.minslot import fewest_changes
from lotsim.maneuvers.planner import ManeuverPlanner
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.maneuvers.validity import Validity
from lotsim.roadmap.settings import MultipointSettings
from lotsim.vehicles import CATALOGUE
from oracles.maneuver_check import check_maneuver, parked_bodies


# the large lot's 1040 bays are the other lots' perpendicular rows over again: -m slow
@pytest.mark.parametrize("path", [
    pytest.param(p, marks=pytest.mark.slow) if p.stem in HEAVY else p for p in SCENARIOS
], ids=lambda p: p.stem)
def test_every_maneuver_of_every_shipped_slot_passes_the_independent_check(path, shipped_graphs):
    lg = shipped_graphs[path.stem]
    scenario = load_scenario(path)
    lot = lg.lot
    kinds = {v.name: v for v in scenario.vehicle_types}
    everyone = [*scenario.vehicle_types, scenario.parked_vehicle]
    checked = 0
    tree = shapely.STRtree([s.shape for s in lot.slots])
    for k, slot in enumerate(lot.slots):
        node = lg.slot_nodes[slot.id]
        near = tree.query(slot.shape, predicate="dwithin", distance=12.0)
        others = [lot.slots[i] for i in sorted(near) if i != k]
        cars = parked_bodies(others, everyone)
        for _, _, d in lg.graph.in_edges(node, data=True):
            for vname, m in d["maneuvers"].items():
                assert m.slot == slot.id
                problems = check_maneuver(lot, m, kinds[vname], cars)
                assert not problems, (slot.id, vname, m.lane, problems)
                checked += 1
    assert checked >= len(lot.slots)


def test_leaving_is_the_parking_path_driven_backwards():
    lg = graph_from_text(QUICK)
    g = lg.graph
    for u, v, d in g.edges(data=True):
        if d["kind"] != "park":
            continue
        for vname, m in d["maneuvers"].items():
            out = g.edges[v, u]["maneuvers"][vname]
            assert out.leaving and not m.leaving
            assert out.start == pytest.approx(m.end) and out.end == pytest.approx(m.start)
            assert out.gears == tuple(-x for x in reversed(m.gears))
            assert out.length == pytest.approx(m.length)
            a, _ = m.sample(0.1)
            b, _ = out.sample(0.1)
            assert np.allclose(a[::-1, :2], b[:, :2], atol=1e-7)
            assert np.allclose(wrap_angle(a[::-1, 2] - b[:, 2]), 0.0, atol=1e-7)


def test_a_way_out_reads_the_same_before_its_pieces_are_built_and_after():
    """A reversed maneuver builds its pieces on first use; its start, length, gears and
    shapes read before then are those of the pieces, to the bit, and so is a copy through
    pickle."""
    lg = graph_from_text(QUICK)
    mans = [m for _, _, d in lg.graph.edges(data=True) if d["kind"] == "park"
            for m in d["maneuvers"].values()]
    assert mans
    for m in mans:
        built = Maneuver(tuple(s.backwards() for s in reversed(m.segments)), m.vehicle,
                         m.slot, m.lane, m.station, not m.leaving)
        for out in (m.reversed(), pickle.loads(pickle.dumps(m.reversed()))):
            early = (out.start, out.length, out.gears, out.shapes())
            assert early == (built.start, built.length, built.gears,
                             tuple((s.distance, s.curvature, s.sharpness)
                                   for s in built.segments))
            assert out == built  # now built
            assert (out.start, out.length, out.gears, out.shapes()) == early
            assert pickle.loads(pickle.dumps(out)) == built



def test_a_placed_way_in_reads_the_same_before_its_pieces_are_put_in_the_world_and_after():
    """A maneuver planned in its slot's frame is put in the world on first use; its start,
    end, length, gears and shapes read before then (and its way out's) are those of the
    pieces put in the world at once, to the bit, in a mirrored frame and an unmirrored one,
    and so is a copy through pickle."""
    from lotsim.maneuvers.problem import LocalFrame

    lg = graph_from_text(QUICK)
    paths = [m.segments for _, _, d in lg.graph.edges(data=True) if d["kind"] == "park"
             for m in d["maneuvers"].values()]
    assert paths
    for mirror in (False, True):
        frame = LocalFrame(31.5, -7.25, 2.4, mirror)
        for local in paths:
            eager = Maneuver(frame.segments_to_world(local), "valet", "s", "l", 4.5)
            for lazy in (Maneuver.placed(frame, local, "valet", "s", "l", 4.5),
                         pickle.loads(pickle.dumps(Maneuver.placed(frame, local, "valet",
                                                                   "s", "l", 4.5)))):
                back = lazy.reversed()
                early = (lazy.start, lazy.end, lazy.length, lazy.gears, lazy.shapes(),
                         back.start, back.length, back.gears, back.shapes())
                want = eager.reversed()
                assert early == (eager.start, eager.end, eager.length, eager.gears,
                                 eager.shapes(), want.start, want.length, want.gears,
                                 tuple((s.distance, s.curvature, s.sharpness)
                                       for s in want.segments))
                assert "segments" not in lazy.__dict__  # nothing above put it in the world
                assert lazy == eager and back == want  # now put there
                assert (lazy.start, lazy.end, lazy.length, lazy.gears, lazy.shapes()) == \
                    early[:5]


QUICK = """
    vehicle_types: [valet]
    lot:
      boundary: [[0, 0], [60, 0], [60, 30], [0, 30]]
      aisles:
        - {id: main, centerline: [[0, 10], [60, 10]], width: AISLE}
      rows:
        - {aisle: main, side: left, kind: perpendicular, count: 12, slot_width: 2.5,
           slot_length: 5.0, start: 15}
      entrances:
        - {id: in, x: 2, y: 8.25, heading_deg: 0}
      exits:
        - {id: out, x: 5, y: 11.75, heading_deg: 180}
""".replace("AISLE", "7.0")


def plan_maneuver(vehicle, slot, lot, *, style="any"):
    """The best maneuver into ``slot`` over its lanes, by a planner of its own."""
    return ManeuverPlanner(lot).best(vehicle, slot, style=style)


def _lot(text):
    scenario = scenario_from_text(text)
    return build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types)), scenario


@pytest.mark.slow
def test_a_wide_aisle_needs_no_direction_change_and_a_narrow_one_needs_some():
    car = CATALOGUE["valet"]
    changes = {}
    for width in (4.6, 6.0, 12.0):
        lot, _ = _lot(QUICK.replace("width: 7.0", f"width: {width}"))
        slot = lot.slot_by_id["main-left-6"]
        changes[width] = plan_maneuver(car, slot, lot).changes
    assert changes[12.0] == 0
    assert changes[4.6] >= 1
    assert changes[4.6] >= changes[6.0] >= changes[12.0]


@pytest.mark.slow
def test_forward_and_reverse_styles_park_nose_in_and_nose_out():
    lot, _ = _lot(QUICK)
    slot = lot.slot_by_id["main-left-6"]
    car = CATALOGUE["valet"]
    into = np.array([math.cos(slot.heading), math.sin(slot.heading)])
    for style, sign in (("forward", 1), ("reverse", -1)):
        m = plan_maneuver(car, slot, lot, style=style)
        nose = np.array([math.cos(m.end[2]), math.sin(m.end[2])])
        assert float(np.dot(nose, into)) == pytest.approx(sign, abs=1e-6)
    best = plan_maneuver(car, slot, lot)
    both = [plan_maneuver(car, slot, lot, style=s) for s in ("forward", "reverse")]
    assert (best.changes, best.length) == min((m.changes, m.length) for m in both)


def test_a_parallel_slot_uses_no_more_changes_than_the_minimum_slot_planner_says():
    """Oracle: minslot in the slot less the margins (0.12 m at each closed side)."""
    lot, _ = _lot("""
        vehicle_types: [altis]
        lot:
          boundary: [[0, 0], [80, 0], [80, 12], [0, 12]]
          aisles:
            - {id: s, centerline: [[0, 6], [80, 6]], width: 5.0, direction: one-way}
          rows:
            - {aisle: s, side: right, kind: parallel, count: 6, slot_width: 2.5,
               slot_length: 6.2, start: 10.0}
          entrances:
            - {id: in, x: 2, y: 6, heading_deg: 0}
    """)
    car = CATALOGUE["altis"]
    m = plan_maneuver(car, lot.slot_by_id["s-right-3"], lot)
    inner, _ = fewest_changes(car, 6.2 - 0.24, 2.5 - 0.12, step_deg=0.5)
    # the approach from the lane may add one change on top of the strategy's own
    assert inner <= m.changes <= inner + 1
    assert abs(wrap_angle(m.end[2])) < math.radians(1.0)


PARALLEL = """
    vehicle_types: [{car}]
    lot:
      boundary: [[0, 0], [40, 0], [40, 30], [0, 30]]
      aisles:
        - {{id: a, centerline: [[0, 15], [40, 15]], width: {aisle}, direction: one-way}}
      rows:
        - {{aisle: a, side: right, kind: parallel, count: 2, slot_width: {w}, slot_length: {l},
           start: 12}}
      entrances:
        - {{id: in, x: 2, y: 15, heading_deg: 0}}
"""


@pytest.mark.parametrize("car", sorted(CATALOGUE))
def test_a_roomier_aisle_never_makes_a_parallel_slot_unusable(car):
    """Found by the property tests: a fixed search window cut off the long closing straight
    from a parallel slot to a lane 3 m or more away, so an msv could park beside a 5 m aisle
    but not beside a 7 m one. Every car parks in a slot 0.5 m wider and 1.5 m longer than
    itself beside aisles from 4 to 8 m, and the maneuver passes the independent check."""
    v = CATALOGUE[car]
    for aisle in (4.0, 6.0, 8.0):
        lot, _ = _lot(PARALLEL.format(car=car, aisle=aisle, w=round(v.width + 0.5, 2),
                                      l=round(v.length + 1.5, 2)))
        slot = lot.slots[1]
        m = plan_maneuver(v, slot, lot)
        others = [s for s in lot.slots if s.id != slot.id]
        assert check_maneuver(lot, m, v, parked_bodies(others, [v])) == [], (car, aisle)


def test_a_turned_row_of_parallel_slots_is_planned():
    """Found by the property tests: GEOS threw a TopologyException when rounding a
    neighbour's thin margin strip for the geometry cache key, at some turns of the layout."""
    lot, _ = _lot("""
        vehicle_types: [vw]
        lot:
          boundary: [[0.0044, 0.009], [-16.2734, -33.0738], [-4.8821, -38.6787],
                     [11.3957, -5.5959]]
          aisles:
            - {id: a0, centerline: [[5.5947, -2.7528], [-10.6742, -35.8176]], width: 5.257,
               direction: one-way}
          rows:
            - {aisle: a0, side: right, start: 10.089, kind: parallel, count: 3,
               slot_width: 2.578, slot_length: 6.0}
          entrances:
            - {id: en00, x: 4.9325, y: -4.0987, heading_deg: 243.8014}
    """)
    planner = ManeuverPlanner(lot)
    v = CATALOGUE["vw"]
    for slot in lot.slots:
        m = planner.best(v, slot)
        others = [s for s in lot.slots if s.id != slot.id]
        assert check_maneuver(lot, m, v, parked_bodies(others, [v])) == [], slot.id


def test_angled_slots_on_a_one_way_aisle_are_driven_into_forward_without_stopping():
    lot, _ = _lot("""
        vehicle_types: [valet]
        lot:
          boundary: [[0, 0], [80, 0], [80, 16], [0, 16]]
          aisles:
            - {id: a, centerline: [[0, 10], [80, 10]], width: 5.0, direction: one-way}
          rows:
            - {aisle: a, side: right, kind: angled, angle_deg: 45, count: 8, slot_width: 2.5,
               slot_length: 5.3, start: 20.0}
          entrances:
            - {id: in, x: 2, y: 10, heading_deg: 0}
    """)
    car = CATALOGUE["valet"]
    for slot in lot.slots[1:-1]:
        m = plan_maneuver(car, slot, lot)
        assert m.changes == 0 and m.gears[0] == 1, slot.id


def test_same_geometry_is_planned_once_and_moved_rigidly():
    lot, _ = _lot(QUICK.replace("count: 12", "count: 22").replace("[60, 0], [60, 30]",
                                                                    "[90, 0], [90, 30]")
                  .replace("[60, 10]", "[90, 10]"))
    planner = ManeuverPlanner(lot)
    car = CATALOGUE["valet"]
    a, b = lot.slot_by_id["main-left-10"], lot.slot_by_id["main-left-12"]
    lane = planner.lanes_for(a)[0]
    ma, mb = planner.plan(car, a, lane), planner.plan(car, b, lane)
    assert (planner.stats["planned"], planner.stats["reused"]) == (1, 1)
    shift = np.subtract(b.center, a.center)
    pa, _ = ma.sample(0.1)
    pb, _ = mb.sample(0.1)
    assert np.allclose(pa[:, :2] + shift, pb[:, :2], atol=1e-9)
    assert np.allclose(pa[:, 2], pb[:, 2], atol=1e-9)
    assert mb.station - ma.station == pytest.approx(float(np.linalg.norm(shift)))


def test_a_car_longer_than_the_slot_is_an_explicit_infeasible_maneuver():
    lot, _ = _lot(QUICK)
    long_car = CATALOGUE["vclass"]
    assert long_car.length > 5.0
    with pytest.raises(InfeasibleManeuver, match=r"vclass.*long"):
        plan_maneuver(long_car, lot.slot_by_id["main-left-3"], lot)


def test_validate_lists_slots_a_vehicle_type_cannot_use_and_strict_fails():
    import lotsim

    report = lotsim.validate(QUICK.replace("vehicle_types: [valet]",
                                           "vehicle_types: [valet, vclass]"))
    assert any(w.startswith("vclass cannot park in 12 free slots") for w in report.warnings)
    assert not any(w.startswith("valet cannot park") for w in report.warnings)
    assert "warning: vclass cannot park in 12 free slots" in report.summary()
    assert not report.complete  # what --strict refuses


def test_cli_maneuver_draws_one_and_reports_bad_input(tmp_path, capsys):
    path = tmp_path / "q.yaml"
    path.write_text(QUICK)
    png = tmp_path / "m.png"
    assert main(["maneuver", str(path), "--slot", "main-left-5", "-o", str(png)]) == 0
    out = capsys.readouterr().out
    assert "direction change" in out and png.stat().st_size > 1000
    assert re.search(r"steers (standing \d+ times?, [\d.]+ s in all|only while rolling)", out)
    from PIL import Image

    assert Image.open(png).size == (900, 700)
    assert main(["maneuver", str(path), "--slot", "main-left-99"]) == 2
    assert "did you mean" in capsys.readouterr().err
    assert main(["maneuver", str(path), "--slot", "main-left-5", "--vehicle", "zoe"]) == 2
    path.write_text(QUICK.replace("vehicle_types: [valet]", "vehicle_types: [vclass]"))
    assert main(["maneuver", str(path), "--slot", "main-left-5"]) == 1
    assert "cannot park" in capsys.readouterr().err


@pytest.mark.slow
def test_the_maneuver_picture_rings_every_place_the_car_stops_to_steer():
    from lotsim.render.maneuver_image import KEY_BAND, STEER, draw_maneuver, maneuver_canvas

    lot, _ = _lot(QUICK.replace("width: 7.0", "width: 4.6"))  # narrow: it shuffles
    car = CATALOGUE["valet"]
    m = ManeuverPlanner(lot).best(car, lot.slot_by_id["main-left-5"])
    stops = m.motion(car).steering_stops
    assert m.changes and stops  # it turns its wheels standing at the cusps
    img = np.asarray(draw_maneuver(lot, m, car).convert("RGB")).astype(int)
    ring = np.all(np.abs(img - np.array(STEER)) <= 2, axis=2)
    assert ring.any()
    # the rings' pixels lie around the stops and nowhere else
    ys, xs = np.nonzero(ring)
    canvas = maneuver_canvas(m, car)
    centres = np.array([canvas.to_px(np.array(p[:2])) for p, _ in stops])
    legend = ys >= 700 - KEY_BAND
    dist = np.hypot(xs[:, None] - centres[None, :, 0], ys[:, None] - centres[None, :, 1])
    assert np.all((dist.min(axis=1) < 20) | legend)  # nowhere else
    assert np.all(dist[~legend].min(axis=0) < 20)  # and around every stop


def _edge_share(img: np.ndarray, corners: np.ndarray, colour) -> float:
    """Share of 48 points along the pixel polygon ``corners`` that have ``colour`` within
    a pixel of them."""
    near = np.all(np.abs(img - np.array(colour)) <= 3, axis=2)
    ring = np.vstack([corners, corners[:1]])
    hits = 0
    for a, b in zip(ring[:-1], ring[1:], strict=True):
        for f in np.linspace(0.1, 0.9, 12):
            x, y = np.rint(a + f * (b - a)).astype(int)
            hits += bool(near[y - 1:y + 2, x - 1:x + 2].any())
    return hits / 48


@pytest.mark.slow
@pytest.mark.parametrize("leave", [False, True], ids=["in", "out"])
def test_the_maneuver_picture_keeps_title_and_key_off_the_lot_and_marks_both_ends(leave):
    from lotsim.api import maneuver_case
    from lotsim.render.lot_image import NO_GO_HATCH
    from lotsim.render.maneuver_image import (
        BAND,
        KEY_BAND,
        PARKED_EDGE,
        START_EDGE,
        TITLE_BAND,
        draw_maneuver,
        maneuver_canvas,
    )

    # example.yaml: N1 is next to the hatched island, which the old key was drawn over
    case = maneuver_case(ROOT / "scenarios" / "example.yaml", "N1")
    m = case.planner.best(case.vehicle, case.slot)
    m = m.reversed() if leave else m
    img = np.asarray(draw_maneuver(case.lot, m, case.vehicle, title="a title").convert("RGB"))
    img = img.astype(int)
    h, w = img.shape[:2]
    for band in (img[: TITLE_BAND - 1], img[h - KEY_BAND + 1:]):
        hatch = np.all(np.abs(band - np.array(NO_GO_HATCH)) <= 5, axis=2)
        assert not hatch.any()  # no hatching (nor any of the lot) shows behind the text
        colours, counts = np.unique(band.reshape(-1, 3), axis=0, return_counts=True)
        assert tuple(colours[counts.argmax()]) == BAND
        assert np.all(band[:, w - 60:] == np.array(BAND))  # right of the text: only band
    # the car is outlined at the first pose and at the last, each in its own colour
    canvas = maneuver_canvas(m, case.vehicle, title=True)
    poses, _ = m.sample(0.05)
    bodies = case.vehicle.footprints(poses)
    first, last = canvas.to_px(bodies[0]), canvas.to_px(bodies[-1])
    lane_edge, slot_edge = (START_EDGE, PARKED_EDGE)
    at_first, at_last = (slot_edge, lane_edge) if leave else (lane_edge, slot_edge)
    assert _edge_share(img, first, at_first) > 0.8
    assert _edge_share(img, last, at_last) > 0.8
    assert _edge_share(img, first, at_last) < 0.3  # not the other way round
    # each is named in the key, in its colour
    key = img[h - KEY_BAND + 1:]
    for colour in (START_EDGE, PARKED_EDGE):
        assert np.all(np.abs(key - np.array(colour)) <= 3, axis=2).sum() > 20


# -- the planner's seams: settings, results with a status, a frozen problem ------------------
def test_settings_check_themselves():
    for bad in ({"margin": -0.1}, {"margin": 2.0}, {"max_changes": -1}, {"probe": 0.0},
                {"candidates": 0}, {"closing_radii": (0.5,)}, {"ease_ramps": (1.0, -1.0)},
                {"creep": -0.1}, {"max_changes": 2.5}):
        with pytest.raises(SettingsError) as caught:
            ManeuverSettings(**bad)
        (field,) = bad
        assert caught.value.name == field and str(caught.value).startswith(f"{field}: ")
    assert str(pytest.raises(SettingsError, ManeuverSettings, margin=2.0).value) == (
        "margin: expected 0 to 1 m, found 2")
    planner = ManeuverPlanner(_lot(QUICK)[0], margin=0.2, max_changes=3)
    assert (planner.settings.margin, planner.settings.max_changes) == (0.2, 3)


def test_solve_answers_with_a_status_and_the_reason_plan_lot_keeps_as_it_is():
    from lotsim.core.outcome import Status
    from lotsim.maneuvers.batch import plan_lot

    lot, _ = _lot(QUICK)
    planner = ManeuverPlanner(lot)
    slot = lot.slot_by_id["main-left-3"]
    lane = planner.lanes_for(slot)[0]
    found = planner.solve(CATALOGUE["valet"], slot, lane)
    assert found.status is Status.FOUND and found.found and found.value.slot == slot.id
    refused = planner.solve(CATALOGUE["vclass"], slot, lane)
    assert refused.status is Status.INFEASIBLE and refused.value is None
    assert refused.reason.startswith("the car is 5.37 m long")
    _, infeasible, _ = plan_lot(planner, [CATALOGUE["vclass"]])
    assert infeasible["vclass"][slot.id] == refused.reason  # no message parsed back


def test_the_problem_is_frozen_and_its_key_has_no_side_effects():
    import dataclasses

    lot, _ = _lot(QUICK)
    planner = ManeuverPlanner(lot)
    slot = lot.slot_by_id["main-left-4"]
    problem = planner.problems.pose(CATALOGUE["valet"], slot, planner.lanes_for(slot)[0])
    with pytest.raises(dataclasses.FrozenInstanceError):
        problem.half = 1.0
    keys = {planner.key(problem, "any") for _ in range(3)}
    assert len(keys) == 1 and planner.key(problem, "forward") not in keys


@pytest.mark.slow
@pytest.mark.parametrize("name", ["mixed_lot", "example"])
def test_problems_keyed_together_are_keyed_as_one_at_a_time(shipped_graphs, name):
    """prefetch keys its problems in batches (one shapely call a step over all of them):
    each digest, frame, lane station and shape is the one posing and keying that problem
    alone gives (perpendicular, angled and parallel bays, bends, neighbours cut at the window's
    edge and at the slot's lines), so the same problems share answers."""
    from lotsim.sim.preparation import maneuver_planner

    lg = shipped_graphs[name]
    sc = load_scenario(ROOT / "scenarios" / f"{name}.yaml")
    planner = maneuver_planner(sc, lg.lot)
    triples = [(v, slot, lane) for v in sc.vehicle_types for slot in lg.lot.slots
               for lane in planner.lanes_for(slot)]
    assert {slot.kind for _, slot, _ in triples} >= {"perpendicular", "parallel"}
    together = planner.problems.digests(triples)
    alone = [(planner.problems.digest(p), p.frame, p.lane_s0, planner.problems.shape(*t))
             for p, t in ((planner.problems.pose(*t), t) for t in triples)]
    assert together == alone
    assert len({d for d, *_ in alone}) > 5  # (not all one problem)


ROW_LOT = """\
name: rows
vehicle_types: [valet]
lot:
  boundary: [{a}, {b}, {c}, {d}]
  aisles:
    - {{id: a, centerline: [{m0}, {m1}], width: 7.0}}
  rows:
    - {{aisle: a, side: left, kind: perpendicular, count: 40, slot_width: 2.5,
       slot_length: 5.0, start: 12, id_prefix: N}}
    - {{aisle: a, side: right, kind: perpendicular, count: 40, slot_width: 2.5,
       slot_length: 5.0, start: 12, id_prefix: S}}
  entrances:
    - {{id: in, x: {ex}, y: {ey}, heading_deg: {eh}}}
  occupied: [N3, N4, S9]
traffic:
  vehicles: [{{id: x, arrival: 0}}]
"""


def _row_lot(turn: bool) -> str:
    """ROW_LOT as drawn, or moved and turned a quarter ((x, y) → (1000 - y, 2000 + x): exact
    in floating point)."""
    def at(x: float, y: float) -> list[float]:
        return [1000.0 - y, 2000.0 + x] if turn else [float(x), float(y)]

    ex, ey = at(3.0, 11.0)
    return ROW_LOT.format(a=at(0, 0), b=at(124, 0), c=at(124, 22), d=at(0, 22), m0=at(0, 11),
                          m1=at(124, 11), ex=ex, ey=ey, eh=90 if turn else 0)


def test_a_digest_depends_on_the_problem_alone(monkeypatch):
    """Digests are worked out in the slot's frame: the lot moved and turned digests every
    problem alike, whichever problems are digested with it, and problems alike to the
    micrometre (the bays along a regular row) are posed once."""
    from lotsim.maneuvers.problem import LotProblems
    from lotsim.sim.preparation import maneuver_planner

    posed = []
    locally = LotProblems._posed_locally

    def counted(self, reps, *args):
        posed.append(len(reps))
        return locally(self, reps, *args)

    monkeypatch.setattr(LotProblems, "_posed_locally", counted)
    got = []
    for turn in (False, True):
        sc = scenario_from_text(_row_lot(turn))
        lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
        planner = maneuver_planner(sc, lot)
        triples = [(v, slot, lane) for v in sc.vehicle_types for slot in lot.slots
                   for lane in planner.lanes_for(slot)]
        got.append({(slot.id, lane.id): d[0] for (_, slot, lane), d
                    in zip(triples, planner.problems.digests(triples), strict=True)})
        assert [d[0] for d in planner.problems.digests(triples[::-1])] == [
            got[-1][slot.id, lane.id] for _, slot, lane in triples[::-1]]
    assert got[0] == got[1]
    assert len(got[0]) == 160 and posed[0] < 80  # 80 bays, each served by two lanes
    assert 5 < len(set(got[0].values())) <= posed[0]


@pytest.mark.slow
@pytest.mark.parametrize("name", ["lots/culdesac", "lots/ring", "mixed_lot"])
def test_a_batch_of_framings_is_each_slots_own_to_the_bit(name):
    """:meth:`LotProblems.framings` works a lot's frames out a lane at a time; each is the
    one the lane's own methods give, to the bit: the heading where the slot's entry
    projects onto the lane, and the lane line and lane station in that frame (on curved
    lanes and clothoids too)."""
    from lotsim.maneuvers.problem import LocalFrame
    from lotsim.sim.preparation import maneuver_planner

    sc = load_scenario(ROOT / "scenarios" / f"{name}.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    planner = maneuver_planner(sc, lot)
    triples = [(sc.vehicle_types[0], slot, lane) for slot in lot.slots
               for lane in planner.lanes_for(slot)]
    for (_, slot, lane), (frame, lane_y, lane_x, s0, half) in zip(
            triples, planner.problems.framings(triples), strict=True):
        mid = slot.entry.mean(axis=0)
        station = lane.project((float(mid[0]), float(mid[1])))[0]
        heading = lane.pose_at(station)[2]
        assert (frame.x, frame.y, frame.heading) == (float(mid[0]), float(mid[1]), heading)
        i, _ = lane.locate(station)
        seg = lane.segments[i]
        assert not (seg.curvature or seg.sharpness)  # no shipped slot is beside a bend
        lo, y, _ = LocalFrame(frame.x, frame.y, heading, frame.mirror).poses_to_local(
            np.array(seg.start))[0]
        assert lane_y == y and s0 == float(lane.starts[i]) - lo
        assert lane_x[0] <= lane_x[1] and half >= lane_x[1]
    assert len(triples) > 10



def test_a_framing_is_worked_out_once_and_read_again_as_it_was(monkeypatch):
    """:meth:`LotProblems.framings` (and the windows' tops) keep what they work out: asked again
    (a problem keyed in a batch and posed later on its own), they work nothing out and give
    the same values, the same as a fresh set of the lot's problems gives them; a pickled
    copy keeps none."""
    from lotsim.maneuvers.problem import LotProblems
    from lotsim.sim.preparation import maneuver_planner

    sc = load_scenario(ROOT / "scenarios" / "mixed_lot.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    planner = maneuver_planner(sc, lot)
    triples = [(v, slot, lane) for v in sc.vehicle_types for slot in lot.slots
               for lane in planner.lanes_for(slot)]
    problems = planner.problems
    first = problems.framings(triples)
    fresh = pickle.loads(pickle.dumps(problems))
    assert not fresh._framings and not fresh._far and len(problems._framings) == len(triples)
    made = []
    real = LotProblems._made_framings
    monkeypatch.setattr(LotProblems, "_made_framings",
                        lambda self, some: made.append(len(some)) or real(self, some))
    some = triples[::3]
    assert problems.framings(some) == first[::3] and not made
    assert [problems.framing(*t) for t in some] == first[::3] and not made
    assert fresh.framings(some) == first[::3] and made == [len(some)]
    # and so for how far the window reaches across the aisle
    slots, frames = [t[1] for t in triples], [f[0] for f in first]
    halves = np.array([f[4] for f in first])
    tops = problems._tops(slots, frames, halves)
    monkeypatch.setattr(LotProblems, "_far_sides", lambda *_: pytest.fail("worked out again"))
    assert np.array_equal(problems._tops(slots[::2], frames[::2], halves[::2]), tops[::2])
    monkeypatch.undo()
    assert np.array_equal(fresh._tops(slots, frames, halves), tops)


def test_a_framing_beside_a_bend_has_the_lanes_heading_there_and_no_lane_line():
    """:meth:`LotProblems.framings` beside an arc or a clothoid: the frame's heading is the
    lane's own where the slot's entry projects onto it, to the bit; the lane line is NaN."""
    from lotsim.core.geometry import Segment
    from lotsim.lot.model import Lane
    from lotsim.sim.preparation import maneuver_planner

    sc = load_scenario(ROOT / "scenarios" / "mixed_lot.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    planner = maneuver_planner(sc, lot)
    slot = lot.slots[3]
    lane = planner.lanes_for(slot)[0]
    mid = slot.entry.mean(axis=0)
    start = lane.pose_at(lane.project((float(mid[0]), float(mid[1])))[0] - 6.0)
    bent = [Lane(f"bent{k}{g}", lane.aisle, (Segment(start, 12.0, k, g),), lane.offset,
                 lane.with_polyline) for k, g in ((0.02, 0.0), (0.0, 0.004), (0.01, -0.002))]
    framings = planner.problems.framings([(sc.vehicle_types[0], slot, b) for b in bent])
    for other, (frame, lane_y, lane_x, s0, _) in zip(bent, framings, strict=True):
        station = other.project((float(mid[0]), float(mid[1])))[0]
        assert 0.5 < station < 11.5
        assert frame.heading == other.pose_at(station)[2]
        assert math.isnan(lane_y) and (lane_x, s0) == ((0.0, 0.0), 0.0)


@pytest.mark.slow
def test_the_settings_are_used():
    narrow = QUICK.replace("width: 7.0", "width: 4.6")
    lot, _ = _lot(narrow)
    car, slot = CATALOGUE["valet"], lot.slot_by_id["main-left-5"]
    m = ManeuverPlanner(lot).best(car, slot)
    assert m.changes >= 1
    # (the multi-point way out keeps to no direction change too: a small budget for it)
    with pytest.raises(InfeasibleManeuver, match="up to 0 direction changes"):
        ManeuverPlanner(lot, settings=ManeuverSettings(
            max_changes=0, way_out=MultipointSettings(expansion_limit=100))).best(car, slot)
    # no easing: the car stands to steer at every change of curvature
    plain = ManeuverPlanner(lot, settings=ManeuverSettings(ease_ramps=())).best(car, slot)
    assert not any(s.sharpness for s in plain.segments)
    assert any(s.sharpness for s in m.segments)
    assert len(plain.motion(car).steering_stops) > len(m.motion(car).steering_stops)
    assert plain.duration(car) > m.duration(car)


def test_the_way_out_search_is_tuned_by_its_own_settings(monkeypatch):
    """A bay of the narrow aisle is left by the multi-point way-out search too: it is
    searched with ``way_out``'s tuning and at most both limits of direction changes."""
    import lotsim.maneuvers.shuffle as shuffle

    lot, _ = _lot(QUICK.replace("width: 7.0", "width: 4.6"))
    car, slot = CATALOGUE["valet"], lot.slot_by_id["main-left-1"]
    seen, real = [], shuffle.plan_onto

    def spy(*args, settings, max_changes, **kw):
        seen.append((settings, max_changes))
        return real(*args, settings=settings, max_changes=max_changes, **kw)

    monkeypatch.setattr(shuffle, "plan_onto", spy)
    # (a small expansion limit: what is asked of the search is what is checked)
    tuned = MultipointSettings(expansion_limit=60, max_changes=3, cell=0.25, weight=2.0)
    for limit, want in ((8, 3), (2, 2)):
        seen.clear()
        ManeuverPlanner(lot, settings=ManeuverSettings(max_changes=limit, way_out=tuned)
                        ).best(car, slot)
        assert seen and all(s == tuned and m == want for s, m in seen), seen


def test_maneuvers_start_on_a_half_metre_grid_of_lane_stations(shipped_graphs):
    """Every type's maneuvers into nearby slots share lane nodes (no node a few millimetres
    from the next, where a car would stop and creep), and each starts along its lane with
    straight wheels, turning them as it rolls."""
    for name in ("mixed_lot", "street", "quickstart"):
        lg = shipped_graphs[name]
        for _, _, e in lg.graph.edges(data=True):
            if e["kind"] != "park":
                continue
            for m in e["maneuvers"].values():
                assert abs(m.station / 0.5 - round(m.station / 0.5)) < 1e-6, (name, m.slot)
                # straight wheels at the start: the car steers into the arc as it rolls
                assert m.segments[0].curvature == 0, (name, m.slot)


def test_a_lot_planned_on_two_processes_gets_exactly_the_maneuvers_of_one_search_at_a_time():
    """plan_lot searches a lot's distinct problems ahead on worker processes; the answers,
    and what validate reports about them, must be those of solving slot after slot in this
    process (the second implementation here: solve_lanes alone, on a fresh planner)."""
    from lotsim.maneuvers.batch import plan_lot
    from lotsim.sim.preparation import maneuver_planner

    sc = load_scenario(ROOT / "scenarios" / "street.yaml")  # three types, both lanes
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    alone = maneuver_planner(sc, lot)
    want, why = {}, {}
    for v in sc.vehicle_types:
        for slot in lot.slots:
            found, own, reason = alone.solve_lanes(v, slot)
            want.update({(v.name, slot.id, k, "own"): m.segments for k, m in own.items()})
            want.update({(v.name, slot.id, k): m.segments for k, m in found.items()})
            if not found:
                why[(v.name, slot.id)] = reason
    ahead = maneuver_planner(sc, lot)
    # two workers asked for: forked even for a lot this small
    found, infeasible, park_only = plan_lot(ahead, sc.vehicle_types, workers=2)
    got = {k: m.segments for k, m in found.items()}
    got.update({(*k, "own"): m.segments for k, m in park_only.items()})
    assert got == want
    assert {(n, sid): r for n, slots in infeasible.items() for sid, r in slots.items()} == why
    assert ahead.stats == alone.stats and ahead.stats["reused"] > 0


@pytest.mark.parametrize("span", [1, 2])
def test_the_coarse_to_fine_check_finds_the_first_blocked_body_of_every_run(span):
    """``Validity.first_blocked`` against checking every body on its own (brute force):
    random poses in and around a slot, cut into runs of random lengths, some not asked."""
    lot, _ = _lot(QUICK)
    planner = ManeuverPlanner(lot)
    slot = lot.slot_by_id["main-left-4"]
    problem = planner.problems.pose(CATALOGUE["valet"], slot, planner.lanes_for(slot)[0])
    checks = Validity(problem)
    rng = np.random.default_rng(7)
    for _ in range(30):
        n = int(rng.integers(2, 60))
        walk = np.cumsum(rng.normal(0.0, [0.4, 0.4, 0.15], size=(n, 3)), axis=0)
        local = walk + [rng.uniform(-8, 8), rng.uniform(-5, 4), rng.uniform(-3, 3)]
        prints = problem.vehicle.footprints(problem.frame.poses_to_world(local))
        count = n - span + 1
        cuts = np.append(np.sort(rng.choice(np.arange(1, count + 1), size=min(count, 4),
                                            replace=False)), count)
        run = np.repeat(np.arange(len(cuts)), np.diff(np.concatenate([[0], cuts])))
        run = np.where(rng.random(count) < 0.15, -1, run)  # some bodies not asked
        bodies = np.concatenate([prints[k : k + count] for k in range(span)], axis=1)
        each = checks.bodies_blocked(bodies) & (run >= 0)
        want = np.zeros(count, dtype=bool)
        for r in np.unique(run[run >= 0]):
            hits = np.flatnonzero(each & (run == r))
            if hits.size:
                want[hits[0]] = True
        assert np.array_equal(checks.first_blocked(prints, run, span), want)


@pytest.mark.parametrize("before", [0, 3, 9, 70, 130])
def test_the_first_clear_path_is_the_first_row_that_passes_both_checks(before):
    """``first_clear`` against checking each row on its own, in order: a clear path after
    ``before`` rows of blocked ones (found in the first batch, a later one, or none)."""
    from lotsim.core.geometry import Segment

    lot, _ = _lot(QUICK)
    planner = ManeuverPlanner(lot)
    slot = lot.slot_by_id["main-left-4"]
    p = Validity(planner.problems.pose(CATALOGUE["valet"], slot, planner.lanes_for(slot)[0]))
    rng = np.random.default_rng(before)
    rows = []
    while len(rows) < 2 * before + 40:  # random arcs and straights near the slot
        start = (float(rng.uniform(-8, 8)), float(rng.uniform(-4, 4)),
                 float(rng.uniform(-math.pi, math.pi)))
        path = [Segment(start, float(rng.uniform(-6, 6)),
                        float(rng.choice([0.0, 0.15, -0.15])))]
        rows.append((0, path[0].length, path))

    def clear(row):
        return not (p.paths_blocked([row[2]], step=1.0, sweep=False)[0]
                    or p.paths_blocked([row[2]])[0])

    blocked = [r for r in rows if not clear(r)]
    free = [r for r in rows if clear(r)]
    assert len(blocked) >= before and len(free) >= 3
    order = blocked[:before] + free[:3] + blocked[before:]
    assert first_clear(p, order, step=1.0) is free[0]
    assert first_clear(p, blocked[:before], step=1.0) is None


@pytest.mark.slow
def test_the_rough_pass_over_a_searchs_candidates_finds_what_checking_each_path_finds(
        monkeypatch):
    """``rough`` (the ways to the stops checked once, the closing moves as arrays) against
    making each candidate's path and checking its footprints on its own
    (``paths_blocked(sweep=False)``): the rows of real searches in a narrow aisle (every
    level of direction changes), and those rows again with no straight before the arc, no
    run along the lane, or no closing move at all."""
    from lotsim.maneuvers import shuffle

    lot, _ = _lot(QUICK.replace("width: 7.0", "width: 5.0"))
    planner = ManeuverPlanner(lot)
    step = planner.settings.rough
    asked = []

    def spy(p, rows, *, step, build=None, rough=None, chunk=8):
        if rough is not None:
            asked.append((p, rows.copy(), build, rough))
        return first_clear(p, rows, step=step, build=build, rough=rough, chunk=chunk)

    monkeypatch.setattr(shuffle, "first_clear", spy)  # to see the rows the search makes
    for sid in ("main-left-1", "main-left-4"):
        slot = lot.slot_by_id[sid]
        for style in ("forward", "reverse"):
            assert planner.solve(CATALOGUE["valet"], slot, planner.lanes_for(slot)[0],
                                 style=style).found
    levels, blocked, clear = set(), 0, 0
    for p, rows, build, rough in asked:
        variants = [rows]
        for column, every in ((5, 3), (7, 4), (6, 5)):  # straight, run along, curvature
            v = rows.copy()
            v[::every, column] = 0.0
            variants.append(v)
        for v in variants:
            want = np.array([p.paths_blocked([build(r)[2]], step=step, sweep=False)[0]
                             for r in v], dtype=bool)
            assert np.array_equal(rough(v), want)
            blocked, clear = blocked + int(want.sum()), clear + int((~want).sum())
        levels |= set(rows[:, 2].astype(int).tolist())
    assert levels >= {0, 1, 2, 3} and blocked > 100 and clear > 100


def test_the_rough_pass_finds_blocked_ways_to_the_stops_and_runs_along_the_lane():
    """``rough`` on made-up levels of a search (random strokes near the slot, some through
    its neighbours; stops along them; closing moves with and without a straight, a run
    along the lane of up to 25 m (past the window) or none, or none at all) against making
    each row's path as the search does and checking its footprints on its own."""
    from lotsim.core.geometry import Segment, advance
    from lotsim.maneuvers.closing import closing_segments
    from lotsim.maneuvers.shuffle import rough

    lot, _ = _lot(QUICK)
    planner = ManeuverPlanner(lot)
    slot = lot.slot_by_id["main-left-4"]
    problem = planner.problems.pose(CATALOGUE["valet"], slot, planner.lanes_for(slot)[0])
    p, step = Validity(problem), planner.settings.rough
    kmax = CATALOGUE["valet"].max_curvature
    rng = np.random.default_rng(3)
    registry, rows = [], []
    for level in range(3):
        heads = []
        for k in range(4):  # half of them along the lane
            pose = ((float(rng.uniform(-6, 6)), float(rng.uniform(-5, 2)),
                     float(rng.uniform(-math.pi, math.pi))) if k % 2 else
                    (float(rng.uniform(-6, 6)), problem.lane_y, float(rng.normal(0.0, 0.1))))
            segs = [Segment(pose, float(rng.uniform(-3, 3)), float(rng.choice([0, kmax])))]
            heads.append((segs, segs[-1].end, segs[-1].length))
        g, kappa = int(rng.choice([-1, 1])), float(rng.choice([0.0, -kmax, kmax]))
        owner = rng.integers(0, len(heads), 12)
        flat = np.where(rng.random(12) < 0.2, 0.0, rng.uniform(0.0, 4.0, 12))
        q = advance(np.array([heads[o][1] for o in owner]), g * flat, kappa)
        registry.append((heads, flat, q, owner, g, kappa))
        for m in range(12):
            for _ in range(4):
                rows.append([level, 0.0, level, m, int(rng.choice([-1, 1])),
                             float(rng.choice([0.0, rng.uniform(0.1, 3.0)])),
                             float(rng.choice([0.0, 1.0, -1.0, 0.5]) * kmax),
                             float(rng.choice([0.0, rng.uniform(0.0, 25.0)]))])
    rows = np.array(rows)

    def path(row):  # as the search's ``build`` makes it
        heads, flat, q, owner, g, kappa = registry[int(row[2])]
        m = int(row[3])
        segs, pose, _ = heads[owner[m]]
        head = segs + ([Segment(pose, g * float(flat[m]), kappa)] if flat[m] > 1e-9 else [])
        close = (int(row[4]), float(row[5]), float(row[6]), float(row[7]))
        return head + closing_segments(tuple(map(float, q[m])), close)

    want = np.array([p.paths_blocked([path(r)], step=step, sweep=False)[0] for r in rows])
    reached = {}
    got = np.concatenate([rough(p, registry, rows[k : k + 50], reached, step)
                          for k in range(0, len(rows), 50)])
    assert np.array_equal(got, want)
    heads_blocked = sum(reached.values())
    assert 0 < heads_blocked < len(reached) and 0.2 < want.mean() < 0.9


ROW_OFF_GRID = """
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [60, 0], [60, 20], [0, 20]]
  aisles: [{id: a, centerline: [[0, 10], [60, 10]], width: 7.0}]
  rows: [{aisle: a, side: right, kind: perpendicular, count: 16, slot_width: 2.75,
          slot_length: 5.3, start: 5}]
  entrances: [{id: in, x: 4, y: 8.25, heading_deg: 0}]
  exits: [{id: out, x: 56, y: 8.25, heading_deg: 0}]
traffic: {vehicles: [{id: x, arrival: 0}]}
"""


def test_every_maneuver_starts_on_the_lanes_start_grid_when_bays_are_off_its_pitch():
    """Bays 2.75 m apart on a 0.5 m start grid: the middle ones look alike inside the
    search window, but every other one sits a quarter metre off the grid. Each maneuver
    (and each lane's own best) must still start on a multiple of the grid, as
    ``ManeuverSettings.start_grid`` promises; answers shared between bays whose grid falls
    differently started 0.25 m off it."""
    from lotsim.maneuvers.batch import plan_lot
    from lotsim.sim.preparation import maneuver_planner

    lot, sc = _lot(ROW_OFF_GRID)
    planner = maneuver_planner(sc, lot)
    grid = planner.settings.start_grid
    found, infeasible, park_only = plan_lot(planner, sc.vehicle_types, workers=1)
    assert len(found) == 32 and not infeasible["valet"]
    for m in [*found.values(), *park_only.values()]:
        off = m.station / grid - round(m.station / grid)
        assert abs(off) < 1e-6, (m.slot, m.lane, m.station)


def test_the_maneuver_picture_shows_which_end_of_the_car_is_its_front():
    """A triangle in each solid outline points to the car's front."""
    from lotsim.render.maneuver_image import (
        PARKED_EDGE,
        START_EDGE,
        draw_maneuver,
        maneuver_canvas,
    )

    lot, _ = _lot(QUICK)
    car = CATALOGUE["valet"]
    m = ManeuverPlanner(lot).best(car, lot.slot_by_id["main-left-5"])
    img = draw_maneuver(lot, m, car).convert("RGB")
    canvas = maneuver_canvas(m, car)
    poses = m.sample(0.05)[0]
    for pose, colour in ((poses[0], START_EDGE), (poses[-1], PARKED_EDGE)):
        x, y, th = pose
        u = np.array([np.cos(th), np.sin(th)])
        front = np.array([x, y]) + u * (car.front - 0.6)  # inside the nose triangle
        rear = np.array([x, y]) - u * (car.rear + 0.3 - 0.9)  # the tail's middle
        px = lambda p: tuple(int(v) for v in np.rint(canvas.to_px(p)))  # noqa: E731
        assert img.getpixel(px(front)) == colour
        assert img.getpixel(px(rear)) != colour


def test_a_stroke_runs_clear_as_far_as_its_first_blocked_sweep_checked_alone():
    """:func:`~lotsim.maneuvers.shuffle.extents` places a stroke's sweeps, made once, at each
    start; the oracle makes the footprints at every pose along each stroke and checks each
    sweep on its own (:meth:`Validity.poses_blocked`), in a mirrored frame and an unmirrored
    one."""
    from lotsim.core.geometry import advance
    from lotsim.maneuvers.shuffle import extents

    lot, _ = _lot(QUICK)
    planner = ManeuverPlanner(lot)
    rng = np.random.default_rng(3)
    mirrors = set()
    slot = lot.slot_by_id["main-left-4"]
    for lane in planner.lanes_for(slot):  # one each way along the aisle
        problem = planner.problems.pose(CATALOGUE["valet"], slot, lane)
        mirrors.add(problem.frame.mirror)
        checks = Validity(problem)
        poses = np.column_stack([rng.uniform(-6.0, 6.0, 30), rng.uniform(-3.0, 4.0, 30),
                                 rng.uniform(-np.pi, np.pi, 30)])
        kmax = problem.vehicle.max_curvature
        part_way = 0
        for gear, kappa, cap in ((1, kmax, 1.2), (-1, -kmax, math.pi), (1, 0.0, math.pi)):
            got = extents(checks, poses, gear, kappa, 0.1, cap)
            length = 1.5 * problem.vehicle.length + 2.0
            length = min(length, cap / abs(kappa)) if kappa else length
            s = np.linspace(0.0, length, max(1, math.ceil(length / 0.1)) + 1)
            for pose, e in zip(poses, got, strict=True):
                bad = checks.poses_blocked(advance(pose, gear * s, kappa))
                want = s[int(np.argmax(bad))] if bad.any() else s[-1]
                assert e == want
                part_way += 0.0 < e < s[-1]
        assert part_way >= 5
    assert mirrors == {False, True}
