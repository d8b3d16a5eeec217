"""A plot file is read strictly: every bad input is an error naming file:line:col and what
was expected, and every independent problem is reported at once."""

from __future__ import annotations

import pytest

from lotsim.design.plot_yaml import read_plot
from lotsim.errors import ScenarioError, ScenarioErrors

GOOD = """\
name: yard
boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]
islands: [{id: tree, polygon: [[20, 20], [24, 20], [24, 24], [20, 24]]}]
gates: [{id: main, at: [30, 0]}]
vehicle_types:
  - valet
  - {name: van, width: 2.0, front: 4.2, rear: 1.0, wheelbase: 3.3, max_steer_deg: 30}
bays: {angles_deg: [90, 45], width: 2.4, length: 5.3, gate_clearance: 7.5}
aisles:
  one_way: true
  widths: {90: {two-way: 6.5}, 45: {one-way: 4.0}}
  circulation: 6.5
demand: {count: 12, rate_per_hour: 240, dwell: [60, 120]}
building_entrances: [{id: lobby, at: [30, 45]}, {id: side, at: [65, 20]}]
"""


def test_a_good_plot_reads_every_key():
    plot = read_plot(GOOD)
    assert plot.name == "yard" and len(plot.islands) == 1
    assert [v.name for v in plot.vehicle_types] == ["valet", "van"]
    assert plot.vehicle_names == ("valet", "")
    assert plot.angles == (90, 45) and (plot.bay_width, plot.bay_length) == (2.4, 5.3)
    assert plot.gate_clearance == 7.5
    assert plot.aisle_width(90, "two-way") == 6.5 and plot.aisle_width(45, "one-way") == 4.0
    assert plot.aisle_width(60, "one-way") == 5.5  # the default, untouched
    assert plot.circulation_width == 6.5
    assert (plot.demand.count, plot.demand.rate_per_hour, plot.demand.dwell) == (12, 240,
                                                                                (60, 120))
    assert [(e.id, e.at) for e in plot.building_entrances] == [("lobby", (30, 45)),
                                                                ("side", (65, 20))]


def test_defaults():
    plot = read_plot("boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]\n"
                     "gates: [{id: g, at: [0, 20]}]\n")
    assert plot.angles == (90, 60, 45) and plot.one_way
    assert (plot.bay_width, plot.bay_length) == (2.5, 5.0)
    assert plot.gate_clearance == 10.0  # two lengths of the valet car, 4.9 m
    assert plot.aisle_width(90, "two-way") == 7.0 and plot.circulation_width == 7.0
    assert [v.name for v in plot.vehicle_types] == ["valet"]
    assert plot.building_entrances == ()


@pytest.mark.parametrize("old, new, where, says", [
    ("at: [30, 0]", "at: [30, 3]", "4:24: gates[0].at", "on the boundary"),
    ("[60, 40], [0, 40]]\nislands", "[0, 40], [60, 40]]\nislands", "2:11: boundary",
     "simple polygon"),
    ("angles_deg: [90, 45]", "angles_deg: [90, 30]", "8:25: bays.angles_deg[1]",
     "expected one of 90, 60, 45, found 30"),
    ("width: 2.4", "width: -2", "8:37: bays.width", "expected a number ≥ 1.5"),
    ("gate_clearance: 7.5", "gate_clearance: -1", "8:71: bays.gate_clearance",
     "expected a number ≥ 0"),
    ("45: {one-way: 4.0}", "45: {two-way: 4.0}", "11:37: aisles.widths.45.two-way",
     "unknown key 'two-way'"),
    ("one_way: true", "one_way: yes", "10:12: aisles.one_way", "true or false"),
    ("count: 12", "count: 012", "13:17: demand.count", "decimal"),
    ("name: yard", "name: ../yard", "1:7: name", "letters, digits"),
    ("circulation: 6.5", "circulaton: 6.5", "12:3: aisles.circulaton",
     "did you mean 'circulation'"),
    ("[[20, 20], [24, 20]", "[[70, 20], [74, 20]", "3:31: islands[0].polygon",
     "inside the boundary"),
    ("  - valet\n", "  - valet\n  - valet\n", "7:5: vehicle_types[1]", "given twice"),
    # a type the bays cannot hold is told before any layout is searched, with what it needs
    ("  - valet\n", "  - valet\n  - vclass\n", "7:5: vehicle_types[1]",
     "vehicle type 'vclass' is 5.37 m long and the plot's bays 5.30 m: no bay of any layout "
     "would be usable for it; it needs bays of at least 5.37 m (bays: {length: 5.4})"),
    ("width: 2.4", "width: 1.9", "7:5: vehicle_types[1]", "'van' is 2.00 m wide"),
    ("{id: side,", "{id: lobby,", "14:54: building_entrances[1].id",
     "building entrance id 'lobby' is used twice"),
    ("at: [65, 20]", "at: 65", "14:64: building_entrances[1].at", "expected a list"),
])
def test_a_bad_input_is_located(old, new, where, says):
    assert old in GOOD
    with pytest.raises(ScenarioError) as err:
        read_plot(GOOD.replace(old, new, 1))
    text = str(err.value)
    assert text.startswith(f"<plot>:{where}"), text
    assert says in text, text


def test_every_independent_problem_is_reported_in_file_order():
    bad = GOOD.replace("at: [30, 0]", "at: [30, 3]").replace("width: 2.4", "width: -1")
    with pytest.raises(ScenarioErrors) as err:
        read_plot(bad)
    lines = str(err.value).splitlines()
    assert [line.split(":")[1] for line in lines] == ["4", "8"]


def test_a_missing_key_and_a_file_are_named(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text("boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]\n")
    with pytest.raises(ScenarioError, match=r"p\.yaml:1:1: missing key 'gates'"):
        read_plot(path)
    with pytest.raises(ScenarioError, match="cannot read"):
        read_plot(tmp_path / "none.yaml")


def test_default_bays_too_short_for_a_van_are_said_to_be_the_default():
    with pytest.raises(ScenarioError, match=r"<plot>:3:24: vehicle_types\[1\]: vehicle type "
                                            r"'vclass' is 5\.37 m long and the plot's bays "
                                            r"5\.00 m \(the default\)"):
        read_plot("boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]\n"
                  "gates: [{id: g, at: [0, 20]}]\n"
                  "vehicle_types: [valet, vclass]\n")


@pytest.mark.parametrize("units, bays, where, says", [
    # the valet car (the default type) is 4.9 m long and 1.8 m wide (seed 004's valet car)
    ("m", "{length: 4.5}", "3:7", "at least 4.90 m long for the default vehicle type 'valet'"
     " (the plot names no vehicle_types), found 4.50 m: no bay of any layout would be "
     "usable for it; give bays: {length: 4.9}"),
    ("m", "{width: 1.7, length: 6}", "3:7", "at least 1.80 m wide for the default vehicle "
     "type 'valet' (the plot names no vehicle_types), found 1.70 m: no bay of any layout "
     "would be usable for it; give bays: {width: 1.8}, or vehicle_types that fit"),
    # 4.9 m is 16.076 ft: a bay of 16.1 ft holds it
    ("ft", "{length: 15}", "3:7", "at least 16.08 ft long for the default vehicle type "
     "'valet' (the plot names no vehicle_types), found 15.00 ft: no bay of any layout would "
     "be usable for it; give bays: {length: 16.1}"),
])
def test_bays_too_small_for_the_default_type_are_refused_at_once(units, bays, where, says):
    side = 200 if units == "ft" else 60
    text = (f"boundary: [[0, 0], [{side}, 0], [{side}, {side}], [0, {side}]]\n"
            f"gates: [{{id: g, at: [0, 20]}}]\nbays: {bays}\n")
    if units == "ft":
        text = "units: ft\n" + text
        where = "4:7"
    with pytest.raises(ScenarioError) as err:
        read_plot(text)
    message = str(err.value)
    assert message.startswith(f"<plot>:{where}: bays: expected bays "), message
    assert says in message, message
    read_plot(text.replace(bays, "{length: 4.9}" if units == "m" else "{length: 16.1}"))


def test_a_scenario_given_for_a_plot_is_named_as_one():
    from lotsim.api import EXAMPLE

    with pytest.raises(ScenarioError, match=r"<plot>:4:1: lot: expected a plot file"):
        read_plot(EXAMPLE)


USES = """\
boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]
gates: [{id: main, at: [30, 0]}]
building_entrances: [{id: door, at: [22, 41]}]
vehicle_types:
  - valet
  - {name: badge, width: 1.8, front: 3.7, rear: 1.0, wheelbase: 2.7, max_steer_deg: 33,
     accessible: true}
  - {name: hatch, width: 1.77, front: 3.43, rear: 0.66, wheelbase: 2.59, max_steer_deg: 33,
     ev: true}
uses:
  accessible: ada_2010
  van_accessible: 2
  ev: 10%
  compact: {width: 2.3, length: 4.6}
"""


def test_uses_read_every_key():
    u = read_plot(USES).uses
    assert (u.accessible, u.van_accessible, u.ev_share, u.compact) == (None, 2, 0.1,
                                                                       (2.3, 4.6))
    assert u.ev_count(81) == 9 and u.asked
    stated = read_plot(USES.replace("ada_2010", "5").replace("10%", "3")).uses
    assert (stated.accessible, stated.ev, stated.ev_share) == (5, 3, None)
    assert not read_plot(GOOD).uses.asked


@pytest.mark.parametrize("old, new, where, says", [
    ("accessible: ada_2010", "accessible: ADA 2010", "11:15: uses.accessible",
     "expected ada_2010 (as ADA 2010 Table 208.2 asks) or a count, found 'ADA 2010'"),
    ("accessible: ada_2010", "accessible: -3", "11:15: uses.accessible", "≥ 0"),
    ("accessible: ada_2010", "accessible: 1", "12:19: uses.van_accessible",
     "expected at most the 1 accessible bays asked for"),
    ("van_accessible: 2", "van_accessible: 2.5", "12:19: uses.van_accessible",
     "an integer"),
    ("ev: 10%", "ev: 150%", "13:7: uses.ev", "a share of 0% to 100%"),
    ("ev: 10%", "ev: ten", "13:7: uses.ev", 'a count or a share of the total ("10%")'),
    ("ev: 10%", "ev: yes", "13:7: uses.ev", "a count or a share"),
    ("width: 2.3", "width: 2.6", "14:12: uses.compact",
     "a compact bay smaller than the plot's bays (2.5 × 5 m), found 2.6 × 4.6 m"),
    ("length: 4.6", "length: 4.0", "14:12: uses.compact",
     "no vehicle type of the plot fits a compact bay of 4 × 2.3 m"),
    ("compact: {width: 2.3, length: 4.6}", "compact: {width: 2.3}", "14:12: uses.compact",
     "missing key 'length'"),
    ("  ev: 10%\n", "  ev: 10%\n  motorcycle: 2\n", "14:3: uses.motorcycle",
     "unknown key 'motorcycle'"),
    ("accessible: true}", "accessible: false}", "11:15: uses.accessible",
     "no vehicle type of the plot is marked accessible: true"),
    ("ev: true}", "ev: false}", "13:7: uses.ev", "no vehicle type of the plot is marked ev"),
    ("building_entrances: [{id: door, at: [22, 41]}]\n", "", "10:15: uses.accessible",
     "the plot names no building_entrances"),
    ("gates: [{id: main, at: [30, 0]}]\n",
     "gates: [{id: main, at: [30, 0]}]\nbays: {width: 2.4}\n", "12:15: uses.accessible",
     "an accessible bay is at least 2.44 m wide"),
])
def test_a_bad_use_is_located(old, new, where, says):
    assert old in USES
    with pytest.raises(ScenarioError) as err:
        read_plot(USES.replace(old, new, 1))
    text = str(err.value)
    assert text.startswith(f"<plot>:{where}"), text
    assert says in text, text


def test_every_bad_use_is_reported_at_once_in_file_order():
    bad = USES.replace("ada_2010", "many").replace("10%", "-1")
    with pytest.raises(ScenarioErrors) as err:
        read_plot(bad)
    assert [line.split(":")[1:3] for line in str(err.value).splitlines()] == [
        ["11", "15"], ["13", "7"]]
