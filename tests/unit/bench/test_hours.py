"""lotsim bench hour by hour: hours.csv holds each run's RunResult.hourly() (the same numbers
as the run planned again), the table by hour pools hours.csv over the seeds, and it is
printed for traffic over three hours or more only."""

import csv
import dataclasses
import io
import re
import sys
import textwrap
from statistics import mean

import pytest

from conftest import ROOT
from lotsim import bench
from lotsim.cli import main
from lotsim.io.scenario_yaml import load_scenario
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.results import HOURLY_FROM
from lotsim.sim.running import simulate
from lotsim.sim.settings import RunSettings

# the quickstart's lot (15 free bays) with a stream of five cars that stay
TINY = (ROOT / "scenarios" / "quickstart.yaml").read_text().split("traffic:")[0].replace(
    "name: quickstart", "name: tiny") + """\
traffic:
  stream: {count: 5, rate_per_hour: 360}
"""

# five cars at 1.5 an hour: over three hours of the clock or more
LONG = """\
name: long
scenarios: [tiny.yaml]
planners: [hca, ca]
rates_per_hour: [1.5]
count: 5
seeds: [1, 2, 3]
"""
SHORT = LONG.replace("[1.5]", "[360]")


def _bench(folder, text, name):
    """Run the suite ``text`` in this process: (suite path, output folder, stdout)."""
    (folder / "tiny.yaml").write_text(TINY)
    path = folder / f"{name}.yaml"
    path.write_text(textwrap.dedent(text))
    out = folder / name
    capture = io.StringIO()
    old, sys.stdout = sys.stdout, capture
    try:
        code = main(["bench", str(path), "--jobs", "1", "-o", str(out)])
    finally:
        sys.stdout = old
    assert code == 0, capture.getvalue()
    return path, out, capture.getvalue()


@pytest.fixture(scope="module")
def long(tmp_path_factory):
    return _bench(tmp_path_factory.mktemp("hours"), LONG, "long")


def _csv(path):
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def test_hours_csv_holds_each_run_s_hourly_as_planned_again(long):
    path, out, _ = long
    hours = _csv(out / "hours.csv")
    runs = _csv(out / "runs.csv")
    assert list(hours[0]) == list(bench.HOURS_COLUMNS)
    assert bench.COLUMNS[:len(bench.RUN_KEYS)] == bench.RUN_KEYS  # as runs.csv names them
    assert sorted({int(h["run"]) for h in hours}) == list(range(6))  # every run has hours
    scenario = load_scenario(path.parent / "tiny.yaml")
    lg = prepare_graph(scenario)
    for r in runs:
        stream = dataclasses.replace(scenario.traffic.streams[0],
                                     rate=float(r["rate_per_h"]) / 3600, count=int(r["count"]))
        sc = dataclasses.replace(scenario, traffic=dataclasses.replace(scenario.traffic,
                                                                       streams=(stream,)))
        rr = simulate(sc, RunSettings(planner=r["planner"], assignment=r["assignment"],
                                      seed=int(r["seed"])), lot_graph=lg)
        expected = rr.hourly()
        mine = [h for h in hours if h["run"] == r["run"]]
        assert len(mine) == len(expected) >= 1
        for h, e in zip(mine, expected, strict=True):
            assert {k: h[k] for k in bench.RUN_KEYS} == {k: r[k] for k in bench.RUN_KEYS}
            assert [int(h[k]) for k in ("hour", "arrivals", "parked", "rejected")] == [
                e["hour"], e["arrivals"], e["parked"], e["rejected"]]
            for k in ("median_time_to_park", "p90_time_to_park", "standing_per_car"):
                assert float(h[f"{k}_s"]) == pytest.approx(e[k], abs=5e-4)  # 3 places
        assert sum(int(h["arrivals"]) for h in mine) == int(r["vehicles"])
    # the suite is long: some run's cars came over three hours or more
    assert max(sum(h["run"] == r["run"] for h in hours) for r in runs) >= HOURLY_FROM


_CELL = re.compile(r"^(?P<mean>[\d.]+)(?: \((?P<lo>[\d.]+)–(?P<hi>[\d.]+)\))?$")


def _figures(cell):
    """``(mean, min, max)`` of a printed cell (min and max the mean when alone); None for
    ``–``."""
    if cell == "–":
        return None
    m = _CELL.match(cell)
    assert m, cell
    x = float(m["mean"])
    return x, float(m["lo"] or x), float(m["hi"] or x)


def _printed(stdout):
    """The tables by hour printed: {planner: [(hour, [cells])]}."""
    tables, current = {}, None
    for line in stdout.splitlines():
        head = re.match(r"^  tiny, (\S+): by the hour the cars came, means over (\d) seeds",
                        line)
        if head:
            current = tables.setdefault(head[1], [])
            continue
        row = re.match(r"^    (\d\d)–\d\d h  (.*)$", line)
        if row and current is not None:
            current.append((int(row[1]), re.split(r"\s{2,}", row[2].strip())))
        elif not line.startswith("    "):
            current = None
    return tables


def test_the_table_by_hour_pools_hours_csv_over_the_seeds(long):
    _, out, stdout = long
    with open(out / "hours.csv", newline="", encoding="utf-8") as fh:
        hours = list(csv.DictReader(fh))
    tables = _printed(stdout)
    assert list(tables) == ["hca", "ca"]
    for planner, printed in tables.items():
        mine = [h for h in hours if h["planner"] == planner]
        runs = sorted({h["run"] for h in mine})
        assert len(runs) == 3  # the seeds
        at = {(h["run"], int(h["hour"])): h for h in mine}
        hours_seen = [int(h["hour"]) for h in mine]
        assert [hour for hour, _ in printed] == list(range(min(hours_seen),
                                                           max(hours_seen) + 1))
        for hour, cells in printed:
            here = [at.get((run, hour)) for run in runs]
            cars = [int(h["arrivals"]) if h else 0 for h in here]  # none outside a run's span
            parked = [h for h in here if h and int(h["parked"])]
            came = [h for h in here if h and int(h["arrivals"])]
            wanted = [cars] + [[float(h[k]) for h in parked] for k in (
                "median_time_to_park_s", "p90_time_to_park_s")] + [
                [float(h["standing_per_car_s"]) for h in came]]
            for cell, values in zip(cells, wanted, strict=True):
                got = _figures(cell)
                if not values:
                    assert got is None, (planner, hour, cell)
                    continue
                assert got[0] == pytest.approx(mean(values), abs=0.051), (planner, hour, cell)
                assert got[1:] == pytest.approx((min(values), max(values)), abs=0.051)
    # the same table from hours.csv read back
    assert bench.hours_text(bench.read_hours_csv(out / "hours.csv")) in stdout


def test_a_short_suite_prints_no_table_by_hour_and_writes_its_one_hour(tmp_path, long):
    _, out, stdout = _bench(tmp_path, SHORT, "short")
    assert "by the hour" not in stdout
    hours = _csv(out / "hours.csv")
    assert [(h["run"], h["hour"], h["arrivals"]) for h in hours] == [
        (str(run), "0", "5") for run in range(6)]  # five cars within the first hour
    assert f"wrote {out / 'hours.csv'}" in stdout
    # the long one prints a table for each planner after the table of means
    _, _, stdout = long
    assert stdout.count("by the hour the cars came") == 2
    assert stdout.index("  scenario") < stdout.index("by the hour") < stdout.index("wrote")


def test_a_group_is_told_by_the_hour_when_one_of_its_runs_is_long():
    def hour(run, h, planner="hca"):
        return {"run": run, "scenario": "s", "planner": planner, "window_s": None,
                "assignment": "shortest", "priority": "arrival", "rate_per_h": 1.0,
                "count": 3, "disturbance": "none", "seed": run, "hour": h, "arrivals": 1,
                "parked": 1, "rejected": 0, "median_time_to_park_s": 10.0 + run,
                "p90_time_to_park_s": 12.0, "standing_per_car_s": 0.0}

    # run 0: hours 0 and 1; run 1: hours 1 to 3 (long); run 2 (ca): hours 0 and 1
    rows = [hour(0, 0), hour(0, 1), hour(1, 1), hour(1, 2), hour(1, 3),
            hour(2, 0, "ca"), hour(2, 1, "ca")]
    hca, ca = bench.aggregate_hours(rows)
    assert (hca["runs"], hca["longest"], ca["longest"]) == (2, 3, 2)
    assert [h["hour"] for h in hca["by_hour"]] == [0, 1, 2, 3]
    zero = hca["by_hour"][0]
    assert (zero["cars"], zero["cars_min"], zero["cars_max"]) == (0.5, 0, 1)
    assert zero["median_time_to_park_s"] == 10.0  # run 1 parked no car in hour 0
    assert hca["by_hour"][1]["median_time_to_park_s"] == 10.5
    text = bench.hours_text(rows)
    assert "s, hca: by the hour the cars came, means over 2 seeds" in text
    assert "ca:" not in text.replace("hca:", "")  # two hours: not told
    assert bench.hours_text([r for r in rows if r["planner"] == "ca"]) == ""
