"""search_graph and its memo: one SearchGraph per lot, type and settings, shared by the runs
on a lot when its holder passes the memo, new otherwise."""

import pickle

import networkx as nx
import pytest

from lotsim.core.geometry import Segment
from lotsim.roadmap.model import LotGraph
from lotsim.traffic.searchgraph import SearchGraph, SearchGraphMemo, search_graph
from lotsim.traffic.settings import SearchSettings
from lotsim.vehicles import CATALOGUE

CAR = CATALOGUE["valet"]


def _lane(xs):
    """A lot graph of one one-way lane along the x axis, nodes at ``xs`` [m]."""
    g = nx.DiGraph()
    for k, x in enumerate(xs):
        g.add_node(k, pose=(float(x), 0.0, 0.0), kind="lane")
    for k in range(len(xs) - 1):
        length = float(xs[k + 1] - xs[k])
        g.add_edge(k, k + 1, kind="lane", length=length, gear=1, speed_limit=20 / 3.6,
                   path=(Segment((float(xs[k]), 0.0, 0.0), length, 0.0),), placeholder=False)
    return LotGraph(None, g, {}, {}, {})


def test_a_memo_keeps_one_graph_per_type_and_settings_and_serves_one_lot():
    lg = _lane([0.0, 1.0, 2.0, 3.0, 10.0])
    memo = SearchGraphMemo()
    sg = search_graph(lg, CAR, memo)
    assert search_graph(lg, CAR, memo) is sg and len(memo) == 1
    assert search_graph(lg, CAR, memo, settings=SearchSettings()) is sg  # equal settings
    slow = search_graph(lg, CAR, memo, settings=SearchSettings(speed_step=0.5))
    assert slow is not sg and len(memo) == 2 and len(slow.levels) > len(sg.levels)
    assert search_graph(lg, CATALOGUE["zoe"], memo).vehicle is CATALOGUE["zoe"]
    # without a memo: a new graph each time
    assert search_graph(lg, CAR) is not search_graph(lg, CAR)
    with pytest.raises(ValueError, match="one lot graph"):
        search_graph(_lane([0.0, 5.0]), CAR, memo)
    # a pickled memo is an empty one (its graphs live in their process)
    assert len(pickle.loads(pickle.dumps(memo))) == 0


def test_express_edges_follow_the_settings():
    # lane nodes 1 m apart up to 3 m, then 7 m on: an express edge from each of the first
    # nodes to the first node at least ``express`` ahead; none with express 0
    lg = _lane([0.0, 1.0, 2.0, 3.0, 10.0])

    def express(settings):
        sg = SearchGraph(lg, CAR, settings=settings)
        return sorted((e.u, e.v) for e in sg.edges[4:])

    assert express(SearchSettings()) == [(0, 4), (1, 4), (2, 4)]
    assert express(SearchSettings(express=2.5)) == [(0, 3), (1, 4), (2, 4)]
    assert express(SearchSettings(express=0)) == []


def test_a_turn_too_tight_to_pass_at_speed_is_driven_rest_to_rest_each_piece_at_its_own():
    """A junction turn whose clothoids are sharp enough that the steering rate allows
    1.5 km/h on them, around a 5.5 m arc that allows 12 km/h: a car stops before it (no
    speed level is that slow), crawls the clothoids and speeds up on the arc; not the whole
    turn at the clothoids' crawl. Oracles: the pieces' own caps (closed form), and the
    steering rate and lateral acceleration of the sampled motion, differentiated."""
    import math

    import numpy as np

    from lotsim.core.geometry import cc_turn
    from lotsim.vehicles.motion import sampled, speed_cap

    radius, slow = 5.5, 1.5 / 3.6
    sharpness = CAR.limits.max_steer_rate / (slow * CAR.wheelbase)
    segs, _ = cc_turn(math.pi / 2, 1 / radius, sharpness)
    end = segs[-1].end
    g = nx.DiGraph()
    g.add_node(0, pose=(0.0, 0.0, 0.0), kind="lane")
    g.add_node(1, pose=tuple(map(float, end)), kind="lane")
    length = sum(s.length for s in segs)
    g.add_edge(0, 1, kind="turn", length=length, gear=1, speed_limit=20 / 3.6, path=tuple(segs),
               placeholder=False)
    sg = SearchGraph(LotGraph(None, g, {}, {}, {}), CAR)
    (e,) = sg.edges
    caps = [min(speed_cap(s, CAR), CAR.limits.max_forward_speed) for s in segs]
    assert sg.crawls(e) and e.cap == pytest.approx(min(caps)) and e.cap < 5 / 3.6
    assert all(sg.motion(0, 0, b) is None for b in range(1, len(sg.levels)))
    em = sg.motion(0, 0, 0)
    assert em.duration == pytest.approx(sg.static_time(0))
    floor = sum(s.length / c for s, c in zip(segs, caps, strict=True))
    assert floor < em.duration < 0.5 * length / e.cap  # far quicker than crawling it all
    tr = sampled(em.motion, CAR, 0.0, em.motion.times(0.01))
    assert tr.v[0] == 0 and tr.v[-1] == 0 and tr.v.max() > 2 * e.cap
    rate = np.abs(np.diff(tr.steer)) / np.diff(tr.t)
    assert rate.max() <= CAR.limits.max_steer_rate * (1 + 1e-6)
    lateral = tr.v ** 2 * np.abs(np.tan(tr.steer)) / CAR.wheelbase
    assert lateral.max() <= CAR.limits.max_lateral_accel * (1 + 1e-6)
