"""lotsim bench: suite errors located at line:col, a tiny suite run in this process, in a
process pool and on a Dask cluster giving the same table, failed checks and crashes counted
as failures, the summary, the plots and the progress bar."""

import csv
import dataclasses
import io
import sys
import textwrap

import pytest

from conftest import ROOT, position
from lotsim import bench
from lotsim.bench import runner
from lotsim.cli import main
from lotsim.errors import Location, ScenarioError
from lotsim.io.scenario_yaml import load_scenario
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.running import simulate
from lotsim.sim.settings import RunSettings
from lotsim.verify import CheckReport, Violation

# the quickstart's lot with a stream of three cars (a tiny lot: prepared in about a second)
TINY = (ROOT / "scenarios" / "quickstart.yaml").read_text().split("traffic:")[0].replace(
    "name: quickstart", "name: tiny") + """\
traffic:
  stream: {count: 3, rate_per_hour: 360}
"""

SUITE = """\
name: tiny
description: two planners, two rates, two seeds
scenarios: [tiny.yaml]
planners: [hca, ca]
assignments: [shortest]
rates_per_hour: [360, 1440]
count: 3
seeds: [1, 2]
"""
RUNS = 8


def _write(folder, suite=SUITE):
    (folder / "tiny.yaml").write_text(TINY)
    (folder / "quickstart.yaml").write_text((ROOT / "scenarios" / "quickstart.yaml").read_text())
    path = folder / "suite.yaml"
    path.write_text(textwrap.dedent(suite))
    return path


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _without_timings(path):
    """The CSV text (or a CSV file's) less the timing and memory columns (the last ones)."""
    text = path if isinstance(path, str) else path.read_text()
    rows = list(csv.reader(io.StringIO(text)))
    keep = len(bench.COLUMNS) - len(bench.TIMING_COLUMNS)
    assert rows[0][keep:] == list(bench.TIMING_COLUMNS)
    return [r[:keep] for r in rows]


@pytest.fixture(scope="module")
def local(tmp_path_factory):
    """The tiny suite run in this process: (suite path, output folder, stdout)."""
    folder = tmp_path_factory.mktemp("bench")
    path = _write(folder)
    out = folder / "out"
    capture = io.StringIO()
    old, sys.stdout = sys.stdout, capture
    try:
        code = main(["bench", str(path), "--jobs", "1", "-o", str(out)])
    finally:
        sys.stdout = old
    assert code == 0, capture.getvalue()
    return path, out, capture.getvalue()


# -- the suite file ---------------------------------------------------------------------------
ERRORS = [
    ("unknown key", SUITE.replace("count: 3", "cont: 3"), "cont", "cont",
     "unknown key 'cont' (did you mean 'count'?)"),
    ("unknown planner", SUITE.replace("[hca, ca]", "[hca, cbs]"), "cbs", "planners[1]",
     "expected one of ca, hca, whca, found 'cbs'"),
    ("a window for hca", SUITE.replace("[hca, ca]", "[hca, {hca: [5]}]"), "hca: [5]",
     "planners[1].hca", "unknown key 'hca'"),
    ("a window of zero", SUITE.replace("[hca, ca]", "[{whca: [5, 0]}]"), "0]}",
     "planners[0].whca[1]", "expected 1 to 600 seconds, found 0"),
    ("a planner twice", SUITE.replace("[hca, ca]", "[whca, {whca: [10]}]"), "10]",
     "planners[1].whca[0]", "planner whca-10 is given twice"),
    ("a rate for listed vehicles", SUITE.replace("[tiny.yaml]", "[tiny.yaml, quickstart.yaml]"),
     "quickstart.yaml", "scenarios[1]", "has no traffic stream, so 'rates_per_hour' cannot"),
    ("a missing scenario", SUITE.replace("[tiny.yaml]", "[nowhere.yaml]"), "nowhere.yaml",
     "scenarios[0]", "no scenario file 'nowhere.yaml'"),
    ("an empty list", SUITE.replace("seeds: [1, 2]", "seeds: []"), "[]", "seeds",
     "expected at least one seed, found an empty list"),
    ("an empty planner list", SUITE.replace("[hca, ca]", "[]"), "[]", "planners",
     "expected at least one planner"),
    ("a seed twice", SUITE.replace("seeds: [1, 2]", "seeds: [1, 1]"), "1]", "seeds[1]",
     "seed 1 is given twice"),
    ("a negative rate", SUITE.replace("[360, 1440]", "[360, -5]"), "-5", "rates_per_hour[1]",
     "positive"),
    ("GA settings without ga", SUITE + "ga: {population: 4}\n", "{population", "ga",
     "'priorities' has no 'ga'"),
    ("an unknown priority", SUITE + "priorities: [arrival, fifo]\n", "fifo", "priorities[1]",
     "expected one of arrival, shortest_first, ga"),
    ("a name with a slash", SUITE.replace("name: tiny", "name: ../up"), "../up", "name",
     "names the output folder"),
    ("a missing key", SUITE.replace("seeds: [1, 2]\n", ""), "name", "",
     "missing key 'seeds'"),
]


@pytest.mark.parametrize("text, needle, key, words", [e[1:] for e in ERRORS],
                         ids=[e[0] for e in ERRORS])
def test_suite_errors_are_located(tmp_path, text, needle, key, words):
    path = _write(tmp_path, text)
    with pytest.raises(ScenarioError) as err:
        bench.load_suite(path)
    line, col = position(text, needle)
    head = f"{path}:{line}:{col}: {key}: " if key else f"{path}:{line}:{col}: "
    assert str(err.value).startswith(head) and words in str(err.value), err.value


def test_a_bad_scenario_is_located_in_its_own_file(tmp_path, capsys):
    path = _write(tmp_path)
    (tmp_path / "tiny.yaml").write_text(TINY.replace("width: 7.0", "width: wide"))
    assert main(["bench", str(path), "-o", str(tmp_path / "out")]) == 2
    line, col = position(TINY.replace("width: 7.0", "width: wide"), "wide")
    assert f"{tmp_path / 'tiny.yaml'}:{line}:{col}: lot.aisles[0].width" in \
        capsys.readouterr().err


def test_the_grid_is_expanded_in_a_fixed_order(tmp_path):
    suite = bench.load_suite(_write(tmp_path, SUITE.replace("[hca, ca]",
                                                            "[hca, {whca: [5, 20]}]")))
    specs = suite.specs()
    assert suite.size == len(specs) == 12
    assert [s.index for s in specs] == list(range(12))
    assert [(s.planner.label, s.rate_per_hour, s.seed) for s in specs[:6]] == [
        ("hca", 360, 1), ("hca", 360, 2), ("hca", 1440, 1), ("hca", 1440, 2),
        ("whca-5", 360, 1), ("whca-5", 360, 2)]
    assert bench.spec_settings(specs[-1]) == RunSettings(planner="whca", window=20.0, seed=2)
    assert suite.scenarios[0].stream_rate == pytest.approx(360)


def test_options_are_checked(tmp_path, capsys):
    path = _write(tmp_path)
    (tmp_path / "file").write_text("")
    assert main(["bench", str(path), "--jobs", "0"]) == 2
    assert "--jobs: expected 1 to 1024" in capsys.readouterr().err
    assert main(["bench", str(path), "-o", str(tmp_path / "file")]) == 2
    assert "is a file, not a folder" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["bench", str(path), "--jobs", "2", "--scheduler", "tcp://x:1"])
    assert exc.value.code == 2
    assert "not allowed with" in capsys.readouterr().err


# -- running ----------------------------------------------------------------------------------
def test_a_tiny_suite_writes_one_checked_row_per_grid_point(local):
    _, out, stdout = local
    rows = _rows(out / "runs.csv")
    assert list(rows[0]) == list(bench.COLUMNS)
    assert len(rows) == RUNS
    assert [int(r["run"]) for r in rows] == list(range(RUNS))
    assert {(r["planner"], r["rate_per_h"], r["seed"]) for r in rows} == {
        (p, rate, s) for p in ("hca", "ca") for rate in ("360", "1440") for s in ("1", "2")}
    for r in rows:
        assert r["ok"] == "true" and r["violations"] == "0" and r["problem"] == ""
        assert r["solved"] == "true" and r["waiting"] == "0"
        assert r["count"] == "3" and r["vehicles"] == "3"
        assert int(r["parked"]) == 3 and float(r["mean_time_to_park_s"]) > 0
        assert float(r["throughput_per_h"]) > 0 and int(r["expansions"]) > 0
        assert float(r["peak_memory_mb"]) > 10
    assert "tiny: 8 runs in this process" in stdout
    assert "all runs: assignment shortest; priority arrival" in stdout
    assert f"wrote {out / 'runs.csv'}" in stdout


def test_each_column_of_runs_csv_has_one_precision(local):
    """runs.csv mixed rounded figures with 16-digit ones (median_time_to_park_s,
    standing_per_car_s, ...)."""
    from lotsim.bench.table import DIGITS

    _, out, _ = local
    rows = _rows(out / "runs.csv")
    fractions = {k for r in rows for k in bench.COLUMNS if "." in r[k]
                 and r[k].replace(".", "").replace("-", "").isdigit()}
    assert "median_time_to_park_s" in fractions and fractions <= set(DIGITS)
    for k in DIGITS:
        for r in rows:
            assert len(r[k].partition(".")[2]) <= DIGITS[k], (k, r[k])


def test_rows_agree_with_a_direct_run(local):
    path, out, _ = local
    rows = _rows(out / "runs.csv")
    scenario = load_scenario(path.parent / "tiny.yaml")
    lg = prepare_graph(scenario)
    for r in (rows[0], rows[-1]):
        stream = dataclasses.replace(scenario.traffic.streams[0],
                                     rate=float(r["rate_per_h"]) / 3600, count=3)
        sc = dataclasses.replace(scenario,
                                 traffic=dataclasses.replace(scenario.traffic,
                                                                     streams=(stream,)))
        rr = simulate(sc, RunSettings(planner=r["planner"], assignment=r["assignment"],
                                 seed=int(r["seed"])), lot_graph=lg)
        m = rr.metrics()
        assert int(r["parked"]) == m["parked"] and int(r["departed"]) == m["departed"]
        assert float(r["makespan_s"]) == pytest.approx(m["makespan"], abs=1e-3)
        assert int(r["expansions"]) == m["expansions"]
        parked = sorted(v.parked_at for v in rr.vehicles)
        assert float(r["throughput_per_h"]) == pytest.approx(
            2 / (parked[-1] - parked[0]) * 3600, abs=0.01)


@pytest.mark.slow
def test_a_process_pool_gives_the_same_table(local):
    path, out, _ = local
    rows = bench.run_suite(bench.load_suite(path), jobs=2)
    assert _without_timings(bench.csv_text(rows)) == _without_timings((out / "runs.csv")
                                                                      .read_text())
    # the workers send each run's hours back with its row
    assert bench.hours_csv_text(bench.hour_rows(rows)) == (out / "hours.csv").read_text()


def _dies(spec):
    if spec.index == 1:
        raise RuntimeError("worker lost")
    return _real_run_spec(spec)


_real_run_spec = bench.run_spec


@pytest.mark.slow
def test_a_dask_cluster_gives_the_same_table(local, tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed")
    path, out, _ = local
    with distributed.LocalCluster(n_workers=1, processes=False, threads_per_worker=1,
                                  dashboard_address=None) as cluster:
        code = main(["bench", str(path), "--scheduler", cluster.scheduler_address,
                     "-o", str(tmp_path / "dask")])
        assert code == 0
        assert _without_timings(tmp_path / "dask" / "runs.csv") == _without_timings(
            out / "runs.csv")
        # a task that raises on the cluster (a lost worker) is a failed row, not a traceback
        monkeypatch.setattr(runner, "run_spec", _dies)
        one = _write(tmp_path, SUITE.replace("[360, 1440]", "[360]").replace("[1, 2]", "[1]"))
        code = main(["bench", str(one), "--scheduler", cluster.scheduler_address,
                     "-o", str(tmp_path / "lost")])
    assert code == 1
    rows = _rows(tmp_path / "lost" / "runs.csv")
    assert [r["ok"] for r in rows] == ["true", "false"]
    assert rows[1]["problem"] == "crash: RuntimeError: worker lost"
    assert rows[1]["planner"] == "ca" and rows[1]["seed"] == "1"
    # the cluster's workers send each run's hours back with its row; a lost run has none
    assert (tmp_path / "dask" / "hours.csv").read_text() == (out / "hours.csv").read_text()
    assert {r["run"] for r in _rows(tmp_path / "lost" / "hours.csv")} == {"0"}


def test_an_unreachable_scheduler_is_one_line_and_exit_2(local, tmp_path, capsys,
                                                           monkeypatch):
    pytest.importorskip("distributed")
    monkeypatch.setattr(bench, "CONNECT_TIMEOUT", 1.0)
    path, _, _ = local
    for address, words in (("tcp://127.0.0.1:1", "cannot reach a Dask scheduler"),
                           ("no-port", "is not the address of a Dask scheduler")):
        assert main(["bench", str(path), "--scheduler", address,
                     "-o", str(tmp_path / "x")]) == 2
        err = capsys.readouterr().err
        assert err.startswith("lotsim: --scheduler: ") and words in err, err
        assert "Traceback" not in err and err.count("\n") == 1
    assert not (tmp_path / "x").exists()


def test_without_distributed_the_scheduler_asks_for_the_extra(local, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import fails
    path, _, _ = local
    assert main(["bench", str(path), "--scheduler", "tcp://127.0.0.1:8786"]) == 2
    assert capsys.readouterr().err == ("lotsim: --scheduler needs dask.distributed: "
                                       "pip install 'lotsim[dask]'\n")


def test_a_run_that_fails_its_check_counts_as_failed(tmp_path, capsys, monkeypatch):
    path = _write(tmp_path, SUITE.replace("[360, 1440]", "[360]").replace("[1, 2]", "[1]"))
    calls = []

    def failing(doc, **kw):
        calls.append(doc)
        if len(calls) == 2:  # the second run (ca) breaks a rule
            return CheckReport([Violation("overlap", "s1", 3.0, "s1 and s2 overlap")],
                               {"violations": 4})
        return CheckReport([], {"violations": 0})

    monkeypatch.setattr(runner, "check_result", failing)
    assert main(["bench", str(path), "--jobs", "1", "-o", str(tmp_path / "out")]) == 1
    out = capsys.readouterr().out
    assert "run 1 failed (seed 1): check: overlap: s1 and s2 overlap" in out
    rows = _rows(tmp_path / "out" / "runs.csv")
    assert [(r["ok"], r["solved"], r["violations"]) for r in rows] == [
        ("true", "true", "0"), ("false", "false", "4")]
    summary = (tmp_path / "out" / "summary.md").read_text()
    assert "2 runs: 1 pass `lotsim check`, 1 fail" in summary
    assert "- run 1 (tiny, ca, shortest, arrival, rate 360, seed 1): check: overlap" in summary


def test_a_run_that_crashes_is_a_failed_row(tmp_path, monkeypatch):
    path = _write(tmp_path, SUITE.replace("[360, 1440]", "[360]").replace("[1, 2]", "[1]"))

    def crash(spec, scenario, lg, memo):
        if spec.planner.planner == "ca":
            raise RuntimeError("the planner fell over")
        return real(spec, scenario, lg, memo)

    real = runner._plan
    monkeypatch.setattr(runner, "_plan", crash)
    rows = bench.run_suite(bench.load_suite(path), jobs=1)
    assert [r["ok"] for r in rows] == [True, False]
    assert rows[1]["problem"] == "crash: RuntimeError: the planner fell over"
    assert rows[0]["hours"][0]["arrivals"] == 3 and rows[1]["hours"] == []
    assert {h["run"] for h in bench.hour_rows(rows)} == {0}


def test_a_lot_that_does_not_build_is_bad_input(tmp_path, capsys, monkeypatch):
    path = _write(tmp_path)

    def broken(scenario):
        raise ScenarioError(Location("tiny.yaml", 3, 5, "lot.aisles[0]"), "aisle too narrow")

    monkeypatch.setattr(runner, "prepare_graph", broken)
    monkeypatch.setattr(runner, "_PREPARED", {})
    assert main(["bench", str(path), "--jobs", "1", "-o", str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err == "lotsim: tiny.yaml:3:5: lot.aisles[0]: aisle too narrow\n"
    assert not (tmp_path / "out").exists()


# -- outputs ----------------------------------------------------------------------------------
def test_the_summary_aggregates_over_seeds(local):
    _, out, _ = local
    text = (out / "summary.md").read_text()
    assert text.startswith("# Benchmark `tiny`\n\ntwo planners, two rates, two seeds\n")
    assert "- 8 runs: 8 pass `lotsim check`, 0 fail; 8 solved" in text
    table = [line for line in text.splitlines() if line.startswith("| tiny |")]
    assert [line.split(" | ")[1:4] for line in table] == [
        ["hca", "360", "2"], ["hca", "1440", "2"], ["ca", "360", "2"], ["ca", "1440", "2"]]
    rows = _rows(out / "runs.csv")
    mean = (float(rows[0]["mean_time_to_park_s"]) + float(rows[1]["mean_time_to_park_s"])) / 2
    head = next(line for line in text.splitlines() if line.startswith("| scenario |"))
    k = head.split(" | ").index("time to park mean [s]")
    assert table[0].split(" | ")[k] == f"{mean:.1f}"
    assert "## Saturation" not in text  # three cars a run say nothing about saturation
    assert "None: every run passes `lotsim check`." in text


def test_the_plots_are_pngs(local):
    pytest.importorskip("matplotlib")
    _, out, _ = local
    # where planners tie on what the cars get, the plots of what the planning cost tell
    # them apart
    plots = ("throughput.png", "time_to_park.png", "expansions.png", "planning_time.png")
    for name in plots:
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert f"]({name})" in (out / "summary.md").read_text()
    assert sorted(p.name for p in out.iterdir()) == sorted(["runs.csv", "hours.csv",
                                                            "summary.md", *plots])


def test_a_single_rate_is_drawn_as_bars_per_planner(local):
    pytest.importorskip("matplotlib")
    _, out, _ = local
    rows = bench.read_csv(out / "runs.csv")
    fig = bench.bench_figure([r for r in rows if r["rate_per_h"] == 360], "throughput_per_h")
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["hca", "ca"]
    assert len(ax.patches) == 2
    ax = bench.bench_figure(rows, "mean_time_to_park_s").axes[0]
    series = {c.get_label(): c.lines[0] for c in ax.containers}  # errorbar: line, whiskers
    assert sorted(series) == ["ca", "hca"]
    assert series["hca"].get_xdata().tolist() == [360, 1440]
    hca = [r["mean_time_to_park_s"] for r in rows if r["planner"] == "hca"]
    assert series["hca"].get_ydata().tolist() == pytest.approx(
        [(hca[0] + hca[1]) / 2, (hca[2] + hca[3]) / 2])


def test_progress_shows_on_a_terminal_only(tmp_path, capsys, monkeypatch):
    path = _write(tmp_path, SUITE.replace("[360, 1440]", "[360]").replace("[1, 2]", "[1]"))
    assert main(["bench", str(path), "--jobs", "1", "-o", str(tmp_path / "a")]) == 0
    assert capsys.readouterr().err == ""  # a pipe: quiet
    monkeypatch.setattr("sys.stderr.isatty", lambda: True)
    assert main(["bench", str(path), "--jobs", "1", "-o", str(tmp_path / "b")]) == 0
    err = capsys.readouterr().err
    assert "runs [" in err and "] 1/2" in err and "] 2/2" in err
    assert err.endswith("\r")  # the bar is wiped when done


def test_priority_orders_fill_their_columns(tmp_path):
    text = (SUITE.replace("[hca, ca]", "[hca]").replace("[360, 1440]", "[1440]")
            .replace("[1, 2]", "[1]")
            + "priorities: [arrival, shortest_first, ga]\n"
            + "ga: {population: 2, generations: 1, seed: 3}\n")
    suite = bench.load_suite(_write(tmp_path, text))
    assert [s.ga for s in suite.specs()] == [(), (), (("population", 2), ("generations", 1),
                                                      ("seed", 3))]
    rows = bench.run_suite(suite, jobs=1)
    assert [r["priority"] for r in rows] == ["arrival", "shortest_first", "ga"]
    assert all(r["ok"] for r in rows)
    assert [r["evaluations"] for r in rows][:2] == [0, 0] and rows[2]["evaluations"] >= 1
    # the GA's order, which runs its evaluations, takes longer to choose than the others
    assert rows[2]["order_time_s"] > max(rows[0]["order_time_s"], rows[1]["order_time_s"], 0)
    for r in rows:
        # fitness: the total time to park of the planned order
        assert r["fitness_s"] == pytest.approx(3 * r["mean_time_to_park_s"], abs=0.01)
    assert rows[2]["fitness_s"] <= min(rows[0]["fitness_s"], rows[1]["fitness_s"]) + 1e-6
    text = bench.summary_markdown(suite, rows)
    assert "total time to park [s]" in text and "evaluations" in text


@pytest.mark.parametrize("name, runs", [("valet", 9), ("large_lot_load", 12),
                                        ("head_to_head", 60), ("real_demand", 48),
                                        ("faults", 40), ("day_hours", 6)])
def test_the_shipped_suites_are_valid(name, runs):
    suite = bench.load_suite(ROOT / "scenarios" / "bench" / f"{name}.yaml")
    assert suite.size == runs == len(suite.specs())


def test_the_booking_horizon_reaches_the_runs_and_needs_a_booked_priority(tmp_path):
    base = SUITE.replace("[hca, ca]", "[hca]").replace("[360, 1440]", "[1440]")
    suite = bench.load_suite(_write(tmp_path, base + "priorities: [arrival, shortest_first]\n"
                                    + "horizon: 15\n"))
    assert {s.horizon for s in suite.specs()} == {15.0}
    assert bench.spec_settings(suite.specs()[0]).horizon == 15.0
    with pytest.raises(ScenarioError, match="no booked order"):
        bench.load_suite(_write(tmp_path, base + "horizon: 15\n"))


def test_without_plots_the_summary_links_no_missing_picture(local, tmp_path, capsys,
                                                           monkeypatch):
    # without matplotlib, summary.md linked throughput.png and time_to_park.png, not written
    import re

    from lotsim.render import plots

    def missing():
        raise plots.MatplotlibMissing("no matplotlib")

    path = _write(tmp_path, SUITE.replace("[360, 1440]", "[360]").replace("[1, 2]", "[1]"))
    out = tmp_path / "out"
    out.mkdir()
    (out / "throughput.png").write_bytes(b"an earlier suite run's plot")
    monkeypatch.setattr(plots, "require_matplotlib", missing)
    assert main(["bench", str(path), "--jobs", "1", "-o", str(out)]) == 0
    assert "no plots: they need matplotlib" in capsys.readouterr().out
    text = (out / "summary.md").read_text()
    assert "need matplotlib" in text and not re.findall(r"!\[[^]]*\]\(([^)]+)\)", text)
    assert sorted(p.name for p in out.iterdir()) == ["hours.csv", "runs.csv", "summary.md"]
    # with them, every picture linked is there
    _, out, _ = local
    links = re.findall(r"!\[[^]]*\]\(([^)]+)\)", (out / "summary.md").read_text())
    assert links and all((out / name).is_file() for name in links)


def test_the_bench_plots_load_only_when_drawn():
    import subprocess

    from lotsim.bench import plots as bench_plots

    assert bench.bench_figure is bench_plots.bench_figure
    # reading a suite and running it loads no picture code (matplotlib is optional)
    code = ("import sys, lotsim.bench; print(sorted(m for m in sys.modules if "
            "m.startswith(('lotsim.render', 'lotsim.bench.plots', 'matplotlib', 'PIL'))))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT)
    assert done.stdout.strip() == "[]"


@pytest.mark.slow
def test_the_real_demand_suite_in_small_reports_what_its_cars_paid(tmp_path):
    """The real-demand suite cut to 8 cars on the gate-spur lot, at its slowest and fastest
    rates: every run checks, and each row has the trip figures it is read for."""
    text = (ROOT / "scenarios" / "bench" / "real_demand.yaml").read_text()
    text = (text.replace("scenarios: [../lots/gate_spur.yaml, ../lots/surface364.yaml, "
                         "../lots/dlp_like.yaml]",
                         f"scenarios: [{ROOT / 'scenarios' / 'lots' / 'gate_spur.yaml'}]")
            .replace("rates_per_hour: [200, 350, 500, 700]", "rates_per_hour: [200, 700]")
            .replace("count: 100", "count: 8").replace("seeds: [1, 2]", "seeds: [1]"))
    rows = bench.run_suite(bench.load_suite(_write(tmp_path, text)), jobs=1)
    assert [(r["assignment"], r["rate_per_h"]) for r in rows] == [
        ("shortest", 200), ("shortest", 700), ("priced", 200), ("priced", 700)]
    assert all(r["ok"] for r in rows)
    for r in rows:
        parts = (r["standing_outside_per_car_s"] + r["standing_in_per_car_s"]
                 + r["standing_out_per_car_s"])
        assert r["standing_per_car_s"] == pytest.approx(parts, abs=2e-3)  # 3 places each
        assert 0 < r["median_time_to_park_s"] <= r["p90_time_to_park_s"]
        assert r["median_time_to_leave_s"] > 0


DISTURBED = """\
name: tiny
scenarios: [tiny.yaml]
planners: [hca]
count: 3
seeds: [1, 2]
disturbances:
  - {name: none}
  - {name: late, late_starts: {probability: 1, max: 6}}
  - {name: shut, closures: [{gate: in, from: 0, to: 40}]}
"""


def test_each_disturbances_variant_is_a_row_driven_through_it_and_checked(tmp_path):
    path = _write(tmp_path, DISTURBED)
    suite = bench.load_suite(path)
    assert suite.size == 6
    assert [(s.disturbance, s.seed) for s in suite.specs()] == [
        ("none", 1), ("none", 2), ("late", 1), ("late", 2), ("shut", 1), ("shut", 2)]
    rows = bench.run_suite(suite, jobs=1)
    by = {(r["disturbance"], r["seed"]): r for r in rows}
    assert all(r["ok"] and r["violations"] == 0 for r in rows)
    for seed in (1, 2):
        none, late, shut = (by[k, seed] for k in ("none", "late", "shut"))
        assert none["late_starts"] == 0 and none["stood_more_s"] == 0
        # every start late (probability 1): each car sets off from its gate at least once
        assert late["late_starts"] >= late["vehicles"] and late["stood_more_s"] > 0
        assert late["median_time_to_park_s"] > none["median_time_to_park_s"]
        # the gate shut for 40 s: no car is in before it opens
        assert shut["mean_time_to_park_s"] > none["mean_time_to_park_s"]
    csv_rows = list(csv.DictReader(io.StringIO(bench.csv_text(rows))))
    assert [r["disturbance"] for r in csv_rows] == [r["disturbance"] for r in rows]


def test_a_disturbances_variant_is_named_once_and_read_as_a_scenario_section(tmp_path):
    twice = DISTURBED.replace("{name: shut,", "{name: late,")
    with pytest.raises(ScenarioError, match="disturbances 'late' are given twice"):
        bench.load_suite(_write(tmp_path, twice))
    bad = DISTURBED.replace("probability: 1,", "probability: 3,")
    with pytest.raises(ScenarioError, match=r"disturbances\[1\].late_starts.probability: "
                                            r"expected a number ≤ 1"):
        bench.load_suite(_write(tmp_path, bad))
