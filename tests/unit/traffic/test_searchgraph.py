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
