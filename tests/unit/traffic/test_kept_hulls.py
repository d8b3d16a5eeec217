"""The swept hulls a search graph keeps are bounded (:class:`~lotsim.traffic.searchgraph.
Tally`): past the bound the least used are let go and worked out again when asked for,
and a run plans exactly as with every hull kept."""

from __future__ import annotations

import pytest

import lotsim
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import load_scenario
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.running import simulate
from lotsim.traffic.searchgraph import SearchGraphMemo, Tally


class _Motion:  # what Tally reads of an edge motion: its hulls and whether it was asked for
    def __init__(self, n: int):
        self._swept = [None] * n
        self._asked = False


def test_the_hulls_kept_stay_within_the_bound_and_the_asked_for_stay():
    tally = Tally(100)
    groups = [[_Motion(6), _Motion(4)] for _ in range(40)]
    for k, group in enumerate(groups):
        tally.keep(group)
        assert tally.hulls <= 100
        assert tally.hulls == sum(len(m._swept) for g in groups[: k + 1] for m in g
                                  if m._swept is not None)
        groups[0][0]._asked = True  # the first group is asked for all along
        if k == 10:
            assert groups[0][0]._swept is not None
    assert groups[0][0]._swept is not None and groups[1][0]._swept is None
    assert tally.let_go == sum(10 for g in groups if g[0]._swept is None)


@pytest.fixture(scope="module")
def mixed():
    scenario = load_scenario("scenarios/mixed_lot.yaml")
    return scenario, prepare_graph(scenario)


def test_a_run_that_lets_hulls_go_plans_as_one_that_keeps_them_all(mixed):
    tight = SearchGraphMemo(kept_hulls=400)
    scenario, lg = mixed
    kept = simulate(scenario, lot_graph=lg, memo=SearchGraphMemo(kept_hulls=10**9))
    let_go = simulate(scenario, lot_graph=lg, memo=tight)
    assert sum(sg.tally.let_go for sg in tight._graphs.values()) > 1000  # it let many go
    assert all(sg.tally.hulls <= 400 + 50 for sg in tight._graphs.values())
    assert result_dict(let_go) == result_dict(kept)
    assert let_go.metrics()["expansions"] == kept.metrics()["expansions"]


def test_the_bound_goes_with_a_prepared_lot():
    prepared = lotsim.prepare("scenarios/quickstart.yaml")
    assert prepared.search_graphs.kept_hulls > 10_000
