"""A lot graph packed for pickling and made again through networkx's public API
(:func:`lotsim.roadmap.model.pack_graph`, :func:`unpack_graph`): the same nodes, edges and
data, each node's successors and predecessors in the same order (what the searches and the
reachability walk), on shipped lots and on a graph whose edges were added in an order no
node-by-node rebuild would repeat; and the graph of a pickled lot unpacked only when read."""

from __future__ import annotations

import pickle

import networkx as nx
import numpy as np
import pytest

from lotsim.api import prepare
from lotsim.roadmap.model import LotGraph, pack_graph, unpack_graph


def _orders(g: nx.DiGraph) -> tuple:
    return (list(g.nodes(data=True)), [list(g.succ[n]) for n in g],
            [list(g.pred[n]) for n in g], g.graph)


def _same(a: nx.DiGraph, b: nx.DiGraph) -> None:
    assert _orders(a) == _orders(b)
    assert all(a.edges[u, v] == b.edges[u, v] for u, v in a.edges)


@pytest.mark.parametrize("name", [
    "scenarios/mixed_lot.yaml", "scenarios/street.yaml",
    pytest.param("scenarios/lots/ladder.yaml", marks=pytest.mark.slow)])  # (its preparation)
def test_a_shipped_lot_graph_comes_back_in_the_same_order(name):
    g = prepare(name).lot_graph.graph
    back = unpack_graph(pack_graph(g))
    _same(g, back)
    # the order matters: adding the edges node by node would not give the predecessors'
    naive = nx.DiGraph(g.graph)
    naive.add_nodes_from(g.nodes(data=True))
    naive.add_edges_from(g.edges(data=True))
    assert [list(naive.pred[n]) for n in g] != [list(g.pred[n]) for n in g]


def test_edges_added_in_any_order_come_back_in_it():
    rng = np.random.default_rng(7)
    g = nx.DiGraph(name="random")
    g.add_nodes_from((int(n), {"k": int(n) % 3}) for n in rng.permutation(40))
    pairs = {(int(u), int(v)) for u, v in rng.integers(0, 40, size=(300, 2)) if u != v}
    for u, v in rng.permutation(sorted(pairs)):
        g.add_edge(int(u), int(v), w=float(rng.random()))
    for u, v in list(g.edges)[::7]:  # removed and added again: last in both orders
        g.remove_edge(u, v)
        g.add_edge(u, v, w=-1.0)
    _same(g, unpack_graph(pack_graph(g)))


def test_a_pickled_lot_unpacks_its_graph_when_it_is_read():
    lg = prepare("scenarios/quickstart.yaml").lot_graph
    copy = pickle.loads(pickle.dumps(lg))
    assert "graph" not in copy.__dict__ and "_graph_packed" in copy.__dict__
    assert copy.entrances == lg.entrances  # the rest is there at once
    _same(copy.graph, lg.graph)
    assert "_graph_packed" not in copy.__dict__  # unpacked once, then kept
    # a copy pickled again before its graph was read passes the packed graph on as it came
    unread = pickle.loads(pickle.dumps(lg))
    again = pickle.loads(pickle.dumps(unread))
    assert again.__dict__["_graph_packed"] == unread.__dict__["_graph_packed"]
    _same(again.graph, lg.graph)


def test_a_lot_graph_without_one_says_so():
    lg = object.__new__(LotGraph)
    with pytest.raises(AttributeError, match="'LotGraph' object has no attribute 'graph'"):
        lg.graph  # noqa: B018
