"""The ``traffic`` section's streams, rate profiles and dwell laws: each bad input is a
ScenarioError at its line and column saying what was expected, and what runs validates."""

import re
from pathlib import Path

import pytest

import lotsim
from conftest import ONE_AISLE, ROOT, position
from lotsim.cli import main
from lotsim.traffic.demand import (
    HistogramDwell,
    LognormalDwell,
    RateProfile,
    UniformDwell,
)

DAY = """\
traffic:
  vehicles:
    - {id: ada, arrival: 0}
  streams:
    - prefix: c
      rate_per_hour: [[6, 0], [7.5, 30], [9, 0]]
      dwell: {lognormal: {median_min: 480, sigma: 0.1}, clip_min: [360, 600]}
    - prefix: s
      rate_per_hour: [{from_h: 9, to_h: 12, rate_per_hour: 20},
                      {from_h: 13, to_h: 17, rate_per_hour: 10}]
      dwell: {histogram: {edges_min: [20, 30, 60, 90], weights: [3, 2, 1]}}
    - prefix: e
      count: 5
      rate_per_hour: [0, 5, 10]
      start: 64800
      dwell: {uniform: {low_min: 30, high_min: 90}}
"""


def test_a_day_of_streams_reads_into_frozen_specs():
    sc = lotsim.load_scenario(ONE_AISLE + DAY)
    c, s, e = sc.traffic.streams
    assert c.rate == RateProfile(((21600.0, 27000.0, 0.0, 30 / 3600),
                                  (27000.0, 32400.0, 30 / 3600, 0.0)))
    assert c.count is None and c.prefix == "c"
    assert c.dwell == LognormalDwell(28800.0, 0.1, (21600.0, 36000.0))
    assert s.rate == RateProfile(((32400.0, 43200.0, 20 / 3600, 20 / 3600),
                                  (46800.0, 61200.0, 10 / 3600, 10 / 3600)))
    assert s.dwell == HistogramDwell((1200.0, 1800.0, 3600.0, 5400.0), (3.0, 2.0, 1.0))
    assert e.rate.segments[0] == (64800.0, 68400.0, 0.0, 0.0) and e.count == 5
    assert e.dwell == UniformDwell(1800.0, 5400.0)
    assert lotsim.validate(ONE_AISLE + DAY).warnings == []


def test_the_single_stream_reads_as_it_did_with_its_seconds():
    sc = lotsim.load_scenario(ONE_AISLE + "traffic:\n  stream: {count: 3, rate_per_hour: 60, "
                              "dwell: 90}\n")
    (s,) = sc.traffic.streams
    assert (s.count, s.rate, s.dwell, s.prefix) == (3, 60 / 3600, UniformDwell(90.0, 90.0), "s")


# (name, old text of DAY, new text, needle marking the position, key path, words expected)
CASES = [
    ("stream and streams", "  streams:\n", "  stream: {count: 1, rate_per_hour: 5}\n  streams:\n",
     "- prefix: c", "traffic.streams", "'stream' (one) or 'streams' (a list), not both"),
    ("no prefix in a list", "    - prefix: e\n      count: 5\n", "    - count: 5\n", "count: 5",
     "traffic.streams[2]", "missing key 'prefix'"),
    ("two prefixes alike", "    - prefix: e\n", "    - prefix: c\n", "c\n      count",
     "traffic.streams[2].prefix", "may give the same ids as the prefix 'c'"),
    ("a prefix that begins another", "    - prefix: e\n", "    - prefix: c1\n", "c1",
     "traffic.streams[2].prefix", "may give the same ids as the prefix 'c'"),
    ("a car with a stream's id", "{id: ada,", "{id: s12,", "s12", "traffic.vehicles[0].id",
     "may clash with the stream's ids (s01, ...)"),
    ("constant rate without count", "rate_per_hour: [{from_h: 9, to_h: 12, rate_per_hour: 20},\n"
     "                      {from_h: 13, to_h: 17, rate_per_hour: 10}]", "rate_per_hour: 12",
     "prefix: s",
     "traffic.streams[1]",
     "missing key 'count': a stream at a constant rate_per_hour needs how many cars"),
    ("hourly rate negative", "[0, 5, 10]", "[0, -5, 10]", "-5",
     "traffic.streams[2].rate_per_hour[1]", "expected a number ≥ 0, found -5"),
    ("no car at all", "[0, 5, 10]", "[0, 0]", "rate_per_hour: |[0, 0]",
     "traffic.streams[2].rate_per_hour", "brings no car"),
    ("too many cars", "[0, 5, 10]", "[0, 500000]", "[0, 500000]",
     "traffic.streams[2].rate_per_hour", "at most 100000 cars, found one bringing 500000"),
    ("mixed forms", "[0, 5, 10]", "[0, [5, 10]]", "[5, 10]",
     "traffic.streams[2].rate_per_hour[1]",
     "expected a number (a rate for each hour), as the first item of the profile, found a list"),
    ("pieces overlap", "{from_h: 13, to_h: 17", "{from_h: 11, to_h: 17", "from_h: |11",
     "traffic.streams[1].rate_per_hour[1].from_h", "expected an hour ≥ 12, where the piece "
     "before ends"),
    ("a piece ending before it begins", "from_h: 9, to_h: 12", "from_h: 9, to_h: 9", "to_h: |9",
     "traffic.streams[1].rate_per_hour[0].to_h", "expected an hour after from_h (9), found 9"),
    ("a piece without a rate", ", to_h: 17, rate_per_hour: 10}", ", to_h: 17, rate: 10}",
     "rate: 10", "traffic.streams[1].rate_per_hour[1].rate", "unknown key 'rate'"),
    ("curve out of order", "[7.5, 30], [9, 0]", "[7.5, 30], [7, 0]", "7, 0",
     "traffic.streams[0].rate_per_hour[2][0]", "expected an hour after 7.5 (the point before"),
    ("a curve of one point", "[[6, 0], [7.5, 30], [9, 0]]", "[[6, 10]]", "[|[6, 10]]",
     "traffic.streams[0].rate_per_hour[0]", "at least 2 points"),
    ("a point of three numbers", "[7.5, 30]", "[7.5, 30, 1]", "[7.5, 30, 1]",
     "traffic.streams[0].rate_per_hour[1]", "expected a list of exactly 2 items, found 3"),
    ("an hour past the limit", "[9, 0]]", "[3000, 0]]", "3000",
     "traffic.streams[0].rate_per_hour[2][0]", "expected a time in hours ≤ 2400"),
    ("unknown dwell law", "{uniform: {", "{uniformly: {", "uniformly",
     "traffic.streams[2].dwell.uniformly", "did you mean 'uniform'"),
    ("two dwell laws", "{uniform: {low_min: 30, high_min: 90}}",
     "{uniform: {low_min: 30, high_min: 90}, lognormal: {median_min: 5, sigma: 1}}",
     "{uniform: {low_min: 30, high_min: 90}, l", "traffic.streams[2].dwell",
     "expected one of uniform, lognormal, histogram (the law dwell times are drawn from), "
     "found uniform and lognormal"),
    ("clip alone", "{uniform: {low_min: 30, high_min: 90}}", "{clip_min: [1, 2]}",
     "{clip_min", "traffic.streams[2].dwell", "expected one of uniform, lognormal, histogram"),
    ("lognormal without sigma", "median_min: 480, sigma: 0.1", "median_min: 480",
     "{median_min: 480}", "traffic.streams[0].dwell.lognormal", "missing key 'sigma'"),
    ("lognormal spread too wide", "sigma: 0.1", "sigma: 4", "4}",
     "traffic.streams[0].dwell.lognormal.sigma", "expected a number ≤ 3, found 4"),
    ("median in text", "median_min: 480", "median_min: 8h", "8h",
     "traffic.streams[0].dwell.lognormal.median_min",
     "expected a time in minutes, found string '8h'"),
    ("median zero", "median_min: 480", "median_min: 0", "median_min: |0",
     "traffic.streams[0].dwell.lognormal.median_min",
     "expected a positive time in minutes, found 0"),
    ("clip upside down", "clip_min: [360, 600]", "clip_min: [600, 360]", "[600, 360]",
     "traffic.streams[0].dwell.clip_min", "expected [min, max] with min <= max"),
    ("edges out of order", "edges_min: [20, 30, 60, 90]", "edges_min: [20, 30, 30, 90]",
     "30, 90", "traffic.streams[1].dwell.histogram.edges_min[2]",
     "expected an edge after 30 (edges in increasing order), found 30"),
    ("weights short", "weights: [3, 2, 1]", "weights: [3, 2]", "[3, 2]",
     "traffic.streams[1].dwell.histogram.weights",
     "expected 3 weights, one for each bin between the 4 edges, found 2"),
    ("weights all zero", "weights: [3, 2, 1]", "weights: [0, 0, 0]", "[0, 0, 0]",
     "traffic.streams[1].dwell.histogram.weights", "expected a positive weight for some bin"),
    ("uniform upside down", "low_min: 30, high_min: 90", "low_min: 30, high_min: 20",
     "high_min: |20",
     "traffic.streams[2].dwell.uniform.high_min", "expected at least low_min (30), found 20"),
    ("seconds dwell upside down", "{uniform: {low_min: 30, high_min: 90}}", "[900, 300]",
     "[900, 300]", "traffic.streams[2].dwell", "expected [min, max] with min <= max"),
    ("a count of a profile not a number", "count: 5", "count: many", "many",
     "traffic.streams[2].count", "expected an integer, found string 'many'"),
    ("start 1e3", "start: 64800", "start: 6e4", "6e4", "traffic.streams[2].start",
     "which YAML reads as a string"),
]


@pytest.mark.parametrize(("name", "old", "new", "needle", "key", "words"), CASES,
                         ids=[c[0] for c in CASES])
def test_traffic_errors_are_located(tmp_path, name, old, new, needle, key, words):
    assert DAY.count(old) == 1, name
    text = ONE_AISLE + DAY.replace(old, new)
    path = tmp_path / "day.yaml"
    path.write_text(text)
    with pytest.raises(lotsim.ScenarioError) as err:
        lotsim.validate(path)
    line, col = position(text, needle)
    message = str(err.value)
    assert message.startswith(f"{path}:{line}:{col}: {key}: "), message
    assert words in message and "\n" not in message, message


def test_every_problem_of_the_streams_is_reported_at_once(tmp_path):
    text = ONE_AISLE + DAY.replace("sigma: 0.1", "sigma: -1").replace(
        "weights: [3, 2, 1]", "weights: [3, 2]").replace("[0, 5, 10]", "[0, x]")
    path = tmp_path / "day.yaml"
    path.write_text(text)
    with pytest.raises(lotsim.ScenarioErrors) as err:
        lotsim.validate(path)
    lines = str(err.value).splitlines()
    assert [ln.split(": ")[1] for ln in lines] == [
        "traffic.streams[0].dwell.lognormal.sigma", "traffic.streams[1].dwell.histogram.weights",
        "traffic.streams[2].rate_per_hour[1]"], lines


PAGE = ROOT / "docs" / "scenario.md"


def _day_section() -> str:
    return PAGE.read_text().split("## A day of traffic", 1)[1].split("\n## ", 1)[0]


def test_the_scenario_page_shows_the_days_traffic_as_shipped():
    shown = re.search(r"```yaml\n(.*?)```", _day_section(), re.S).group(1)
    shipped = (ROOT / "scenarios" / "day.yaml").read_text()
    assert shown == "traffic:" + shipped.split("\ntraffic:", 1)[1]


def test_the_scenario_page_shows_what_validate_says_of_a_day_with_mistakes(
        tmp_path, monkeypatch, capsys):
    said = re.search(r"\n```\n(lotsim: .*?)```", _day_section(), re.S).group(1)
    text = (ROOT / "scenarios" / "day.yaml").read_text()
    for old, new in (("[10, 15, 25, 40,", "[10, 15, 25, -40,"), ("sigma: 0.5", "sigma: five"),
                     ("weights: [4, 3, 2, 1]", "weights: [4, 3, 2]")):
        assert text.count(old) == 1
        text = text.replace(old, new)
    monkeypatch.chdir(tmp_path)
    Path("day.yaml").write_text(text)
    assert main(["validate", "day.yaml"]) == 2
    assert capsys.readouterr().err == said
