"""``units: ft``: the unit is checked and located, and errors state lengths in feet."""

from __future__ import annotations

import pytest

from lotsim.api import EXAMPLE
from lotsim.design.plot_yaml import read_plot
from lotsim.errors import ScenarioError
from lotsim.io.scenario_yaml import load_scenario


def _message(text: str, read=load_scenario) -> str:
    with pytest.raises(ScenarioError) as err:
        read(text)
    return str(err.value)


def test_only_metres_and_feet_are_units():
    assert _message("units: yd\n" + EXAMPLE) == \
        "<scenario>:1:8: units: expected one of m, ft, found 'yd'"
    assert _message("units: 3\n" + EXAMPLE).startswith("<scenario>:1:8: units: expected one")
    assert load_scenario("units: m\n" + EXAMPLE) == load_scenario(EXAMPLE)
    assert load_scenario(EXAMPLE).units == "m"


def test_a_bound_is_stated_in_feet():
    text = "units: ft\n" + EXAMPLE.replace("width: 7.0", "width: 400", 1)
    assert "lot.aisles[0].width: expected a number ≤ 328.084 ft, found 400" in _message(text)


def test_a_length_in_inches_gets_a_hint():
    text = "units: ft\n" + EXAMPLE.replace("width: 7.0", "width: 3600", 1)
    assert "(in inches? this file's lengths are feet (units: ft): 3600 in is 300 ft)" \
        in _message(text)


def test_a_lot_too_big_is_measured_in_feet():
    plot = ("units: ft\nboundary: [[0, 0], [9000, 0], [9000, 100], [0, 100]]\n"
            "gates: [{id: g, at: [100, 0]}]\n")
    assert "expected a plot at most 6561.68 ft across, found 9000 ft (is the unit feet?)" \
        in _message(plot, read_plot)


def test_a_plot_in_feet_reads_its_lengths_in_metres():
    plot = read_plot("units: ft\nboundary: [[0, 0], [200, 0], [200, 100], [0, 100]]\n"
                     "gates: [{id: g, at: [100, 0]}]\nbays: {width: 9, length: 18}\n"
                     "demand: {count: 12, rate_per_hour: 240}\n")
    assert plot.boundary[2] == (60.96, 30.48) and plot.gates[0].at == (30.48, 0.0)
    assert (plot.bay_width, plot.bay_length) == (2.7432, 5.4864)
    assert (plot.demand.count, plot.demand.rate_per_hour) == (12, 240)
