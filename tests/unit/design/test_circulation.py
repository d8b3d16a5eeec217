"""The rough judge of a candidate's circulation, before any maneuver is planned: which bays
a gate leads to, and how long the dead ends are. Checked on candidates built by hand (a
person can see which junctions have room for their turns) and on the plots that showed
the need: a 30 m wide strip whose ring has 13 m legs."""

from __future__ import annotations

import math

import pytest

from lotsim.design.circulation import circulation
from lotsim.design.drawn import Candidate, DrawnAisle, DrawnGate, DrawnRow, Module
from lotsim.design.plot_yaml import read_plot
from lotsim.design.results import Evaluation
from lotsim.design.search import candidates
from lotsim.design.settings import LayoutSettings
from lotsim.errors import SettingsError

STRIP = """\
name: strip
boundary: [[0, 0], [30, 0], [30, 150], [0, 150]]
gates: [{id: south, at: [15, 0]}]
"""


def _ring(width: float, length: float, gate_x: float, bays_per_leg: dict[str, int]):
    """A hand-built ring candidate: a rectangle of legs ``width`` x ``length`` from (0, 10),
    a gate aisle from (gate_x, 0) up to the south leg, ``bays_per_leg`` bays along each
    leg (one row each)."""
    corners = [(0, 10), (width, 10), (width, 10 + length), (0, 10 + length)]
    legs = [DrawnAisle(f"r{i + 1}", corners[i], corners[(i + 1) % 4], 7.0, False, "ring")
            for i in range(4)]
    gate = DrawnAisle("gate", (gate_x, 0.0), (gate_x, 10.0), 7.0, False, "gate")
    rows = [DrawnRow(a, "left", 90, 0.0, n) for a, n in bays_per_leg.items()]
    return Candidate(0.0, Module(90, False, 7.0), 0.0, False, [*legs, gate], rows,
                     [DrawnGate("south", "gate", (gate_x, 1.0, 1.57), (gate_x, 4.0, -1.57))])


PLOT = read_plot("boundary: [[-10, -1], [200, -1], [200, 200], [-10, 200]]\n"
                 "gates: [{id: south, at: [20, -1]}]\n")


def test_a_ring_with_room_at_every_junction_serves_every_bay():
    # legs of 40 and 130 m, the gate's T 20 m from either corner: every turn has room
    cand = _ring(40.0, 130.0, 20.0, {"r1": 10, "r2": 50, "r3": 10, "r4": 50, "gate": 2})
    judged = circulation(PLOT, cand)
    assert judged.served == 122 == cand.bays
    assert judged.dead_end_length == 0.0


def test_a_gate_s_t_in_the_middle_of_a_13_m_leg_serves_only_that_leg():
    # 13 m legs: the gate's T 6.5 m from each corner; a car at the valet car's 4.97 m radius
    # cannot turn out of the corner and in at the T, or the other way (the 30 m strip): the
    # gate leads only to the south leg's bays and its own
    cand = _ring(13.0, 130.0, 6.5, {"r1": 4, "r2": 50, "r3": 4, "r4": 50, "gate": 0})
    assert circulation(PLOT, cand).served == 4


@pytest.mark.slow
def test_a_spine_is_one_dead_end_as_long_as_the_spine():
    plot = read_plot(STRIP)
    spine = next(c for c in candidates(plot, LayoutSettings(orientations=1, offsets=1))
                 if c.spine is not None and not c.spine[1])
    aisle = spine.aisles[0]
    judged = circulation(plot, spine)
    assert judged.served == spine.bays > 0
    assert judged.dead_end_length == pytest.approx(math.dist(aisle.start, aisle.end))
    # the spine runs to about a metre short of the far side
    assert 147.0 < judged.dead_end_length < 150.0


@pytest.mark.slow
def test_the_strip_s_best_judged_candidate_is_its_ring_along_the_gate_s_edge():
    # every ring inside perimeter rows all round the 30 m strip has 13 m short legs with the
    # gate's T in the middle: judged to serve a handful of bays; the ring beside the gate's
    # edge, the gate opening straight onto it, serves all it draws and comes first
    plot = read_plot(STRIP)
    drawn = candidates(plot, LayoutSettings(orientations=2, offsets=1))
    judged = sorted(((circulation(plot, c).served, c.bays, c) for c in drawn),
                    key=lambda t: (-t[0], -t[1]))
    best = judged[0][2]
    assert best.along == (0,) and judged[0][0] == best.bays
    assert not any(a.role == "gate" for a in best.aisles)
    rings = [(s, b) for s, b, c in judged if c.spine is None and not c.along]
    assert rings and all(s < b / 4 for s, b in rings)


def _judged(index: int, bays: int, dead: float, cost: float = 2.0) -> Evaluation:
    return Evaluation(index=index, label=f"#{index}", drawn=bays, bays=bays,
                      aisle_length=300.0, area=6000.0, yaml="x", dead_end_length=dead,
                      dead_end_cost=cost)


def test_a_loop_ranks_before_a_dead_end_of_a_few_bays_more():
    # 300 m of dead ends at 2 bays per 100 m cost 6 bays: a spine of 216 (worth 210) comes
    # after a loop of 214, before one of 209, and after a spine of as many bays with less
    spine, loop, small = _judged(0, 216, 300.0), _judged(1, 214, 0.0), _judged(2, 209, 0.0)
    shorter = _judged(3, 216, 150.0)
    ranked = sorted([spine, loop, small, shorter], key=Evaluation.rank_key)
    assert [e.index for e in ranked] == [1, 3, 0, 2]
    # with no cost, bays alone; then the shorter dead ends first among equals
    free = [_judged(e.index, e.bays, e.dead_end_length, 0.0) for e in (spine, loop, shorter)]
    assert [e.index for e in sorted(free, key=Evaluation.rank_key)] == [3, 0, 1]
    with pytest.raises(SettingsError, match="dead_end_cost"):
        LayoutSettings(dead_end_cost=-1.0)


def test_an_aisle_that_ends_a_hair_short_of_a_slanted_leg_meets_it_where_it_ends():
    # a module aisle square up to a ring leg at 30°, ending 1e-9 m short of it (touching,
    # not crossing, for shapely): it meets the leg there, and only its foot is a dead end;
    # 2 m short of the leg it meets nothing, both its ends dead, its bays served by none
    slope = math.tan(math.radians(30))
    leg = DrawnAisle("r1", (0.0, 10.0), (100.0, 10.0 + 100.0 * slope), 7.0, False, "ring")
    gate = DrawnAisle("gate", (20.0, 0.0), (20.0, 10.0 + 20.0 * slope), 7.0, False, "gate")
    x, y = 60.0, 10.0 + 60.0 * slope
    along = 1.0 / math.cos(math.radians(30))  # metres of leg a metre east
    for short, served, dead in (
            (1e-9, 5, 20.0 * along + 40.0 * along + y),  # the leg's ends, the module's foot
            (2.0, 0, 20.0 * along + 80.0 * along + 2 * (y - 2.0))):
        module = DrawnAisle("m1", (x, 0.0), (x, y - short), 7.0, False, "module")
        cand = Candidate(0.0, Module(90, False, 7.0), 0.0, False, [leg, gate, module],
                         [DrawnRow("m1", "left", 90, 0.0, 5)],
                         [DrawnGate("south", "gate", (20.0, 1.0, 1.57), (20.0, 4.0, -1.57))])
        judged = circulation(PLOT, cand)
        assert judged.dead_end_length == pytest.approx(dead, abs=1e-6), short
        assert judged.served == served, short
