"""lotsim as a Python library: the flat API of ``import lotsim``, its settings' checks, its
errors, and that it does what the CLI does."""

import importlib
import shutil
import subprocess
import sys
import textwrap

import pytest

import lotsim
from conftest import ROOT, position
from lotsim.cli import main
from lotsim.errors import (
    InfeasibleManeuver,
    LimitExceeded,
    LotsimError,
    ReplayError,
    ResultFormatError,
    ScenarioError,
    SettingsError,
)
from lotsim.io.lot_json import LotFormatError
from lotsim.sim.orders import plan_run

QUICKSTART = ROOT / "scenarios" / "quickstart.yaml"


@pytest.fixture(scope="module")
def prepared() -> lotsim.PreparedLot:
    return lotsim.prepare(QUICKSTART)


# -- settings check themselves -----------------------------------------------------------------
@pytest.mark.parametrize(("cls", "values", "message"), [
    (lotsim.RunSettings, {"planner": "whca", "window": 0.0},
     "window: expected 1 to 600 seconds, found 0"),
    (lotsim.RunSettings, {"window": float("nan")}, "window: expected 1 to 600 seconds"),
    (lotsim.RunSettings, {"planner": "whac"}, "planner: expected one of ca, hca, whca, found "
                                              "'whac' (did you mean 'whca'?)"),
    (lotsim.RunSettings, {"assignment": "random"}, "assignment: expected one of nearest"),
    (lotsim.RunSettings, {"priority": "fifo"}, "priority: expected one of arrival"),
    (lotsim.RunSettings, {"seed": -1}, "seed: expected 0 to 2**63-1, found -1"),
    (lotsim.RunSettings, {"omega": 0.5}, "omega: expected a number of at least 1, found 0.5"),
    (lotsim.RunSettings, {"retry": 0}, "retry: expected a positive number of seconds"),
    (lotsim.RunSettings, {"horizon": 0}, "horizon: expected a positive number of seconds"),
    (lotsim.RunSettings, {"order": ("a", "a")}, "order: expected every vehicle id"),
    (lotsim.GASettings, {"population": 1}, "population: expected 2 to 10000, found 1"),
    (lotsim.GASettings, {"mutation": 2}, "mutation: expected 0 to 1, found 2"),
    (lotsim.GifSettings, {"fps": 60}, "fps: expected 1 to 50 frames per second, found 60"),
    (lotsim.GifSettings, {"start": 10, "end": 5}, "end: expected a time after the start"),
    (lotsim.MinSlotSettings, {"resolution": 5}, "resolution: expected 0.001 to 1 m, found 5"),
])
def test_settings_refuse_bad_values_on_construction(cls, values, message):
    with pytest.raises(SettingsError) as info:
        cls(**values)
    assert str(info.value).startswith(message)
    assert isinstance(info.value, LotsimError) and isinstance(info.value, ValueError)
    assert info.value.name == message.split(":")[0]


def test_the_default_settings_are_accepted_and_numbers_normalised():
    s = lotsim.RunSettings(window=6, horizon=float("inf"), order=["b", "a"])
    assert (s.window, type(s.window), s.horizon, s.order) == (6.0, float, float("inf"),
                                                              ("b", "a"))
    for cls in (lotsim.RunSettings, lotsim.GASettings, lotsim.GifSettings,
                lotsim.MinSlotSettings):
        cls()


def test_cli_run_prints_the_settings_message_for_its_option_and_exits_2():
    done = subprocess.run([sys.executable, "-m", "lotsim", "run", str(QUICKSTART),
                           "--planner", "whca", "--window", "0"], cwd=ROOT,
                          capture_output=True, text=True, check=False, timeout=120)
    with pytest.raises(SettingsError) as info:
        lotsim.RunSettings(planner="whca", window=0.0)
    assert done.returncode == 2
    assert done.stderr == f"lotsim: --window: {info.value.message}\n"
    assert "Traceback" not in done.stderr and done.stdout == ""


def test_the_bench_suite_reader_gives_the_settings_message(tmp_path):
    from lotsim.bench import load_suite

    shutil.copy(QUICKSTART, tmp_path / "q.yaml")
    text = "scenarios: [q.yaml]\nplanners: [{whca: [0.5]}]\nseeds: [1]\n"
    (tmp_path / "suite.yaml").write_text(text)
    with pytest.raises(ScenarioError) as info:
        load_suite(tmp_path / "suite.yaml")
    with pytest.raises(SettingsError) as direct:
        lotsim.RunSettings(window=0.5)
    assert info.value.message == direct.value.message
    line, col = position(text, "[|0.5")
    assert str(info.value).startswith(f"{tmp_path / 'suite.yaml'}:{line}:{col}: "
                                      "planners[0].whca[0]: ")


# -- run -----------------------------------------------------------------------------------------
def test_run_takes_the_settings_fields_as_keywords(prepared):
    a = lotsim.run(prepared, planner="whca", window=6)
    b = lotsim.run(prepared, lotsim.RunSettings(planner="whca", window=6.0))
    c = lotsim.run(prepared, lotsim.RunSettings(planner="ca"), planner="whca", window=6.0)
    assert a.settings == b.settings == c.settings
    assert a.settings.planner == "whca" and lotsim.result_dict(a)["settings"]["window"] == 6.0
    assert lotsim.result_dict(a) == lotsim.result_dict(b) == lotsim.result_dict(c)
    with pytest.raises(SettingsError, match="windw: no such setting of RunSettings "
                                            r"\(did you mean 'window'\?\)"):
        lotsim.run(prepared, windw=6)
    with pytest.raises(SettingsError, match="window: expected 1 to 600 seconds, found 0"):
        lotsim.run(prepared, planner="whca", window=0)


def test_a_scenario_and_its_prepared_lot_run_alike_and_as_the_cli_does(prepared, tmp_path):
    by_path = lotsim.run(QUICKSTART, assignment="nearest")
    by_scenario = lotsim.run(lotsim.load_scenario(QUICKSTART), assignment="nearest")
    by_prepared = lotsim.run(prepared, assignment="nearest")
    docs = [lotsim.result_dict(r) for r in (by_path, by_scenario, by_prepared)]
    assert docs[0] == docs[1] == docs[2]
    lotsim.write_result(by_prepared, tmp_path / "lib" / "result.json")
    assert main(["run", str(QUICKSTART), "-o", str(tmp_path / "cli"), "--assign", "nearest",
                 "--no-gif"]) == 0
    assert ((tmp_path / "lib" / "result.json").read_bytes()
            == (tmp_path / "cli" / "result.json").read_bytes())


def test_the_priority_is_a_setting_and_a_result_settings_replay_it(prepared):
    sc, lg = prepared.scenario, prepared.lot_graph
    for priority in ("arrival", "shortest_first"):
        rr = lotsim.run(prepared, priority=priority)
        old = plan_run(sc, lotsim.RunSettings(priority=priority), lot_graph=lg)
        assert lotsim.result_dict(rr) == lotsim.result_dict(old)
        assert (rr.settings.order is None) == (priority == "arrival")
        assert lotsim.result_dict(lotsim.run(prepared, rr.settings)) == lotsim.result_dict(rr)
        assert rr.ordering["fitness"] > 0


def test_running_a_scenario_without_traffic_is_a_located_scenario_error():
    text = QUICKSTART.read_text()
    lot_only = text[:text.index("traffic:")]
    with pytest.raises(ScenarioError, match=r"^<scenario>:1:1: the scenario has no 'traffic' "
                                            "section to run"):
        lotsim.run(lot_only)


# -- errors --------------------------------------------------------------------------------------
def test_one_error_hierarchy_under_lotsim_error():
    from lotsim.bench import DaskMissing, SchedulerUnreachable

    for cls in (ScenarioError, SettingsError, ResultFormatError, ReplayError, LimitExceeded,
                InfeasibleManeuver, LotFormatError, DaskMissing, SchedulerUnreachable):
        assert issubclass(cls, LotsimError), cls
    assert lotsim.LotsimError is LotsimError and lotsim.ScenarioError is ScenarioError
    assert issubclass(LimitExceeded, ScenarioError)
    # the classes stay where callers imported them from
    assert importlib.import_module("lotsim.verify").ResultFormatError is ResultFormatError
    assert importlib.import_module("lotsim.render.replay").ReplayError is ReplayError
    assert importlib.import_module("lotsim.sim.limits").LimitExceeded is LimitExceeded


def test_bad_scenario_text_raises_a_lotsim_error_at_its_line_and_column():
    text = textwrap.dedent(QUICKSTART.read_text()).replace("count: 10, slot_width",
                                                           "count: ten, slot_width", 1)
    line, col = position(text, "count: |ten")
    with pytest.raises(LotsimError) as info:
        lotsim.load_scenario(text)
    assert str(info.value).startswith(f"<scenario>:{line}:{col}: lot.rows[0].count: ")


def test_errors_survive_pickling():
    import pickle

    for exc in (SettingsError("window", "expected 1 to 600 seconds, found 0"),
                ScenarioError(None, "no")):
        again = pickle.loads(pickle.dumps(exc))
        assert type(again) is type(exc) and str(again) == str(exc)


# -- results -------------------------------------------------------------------------------------
def test_check_takes_a_run_its_document_or_its_file(prepared, tmp_path):
    rr = lotsim.run(prepared)
    path = lotsim.write_result(rr, tmp_path / "result.json")
    reports = [lotsim.check(rr), lotsim.check(lotsim.result_dict(rr)), lotsim.check(path),
               lotsim.check(str(path))]
    assert all(r.ok and not r.violations for r in reports)
    broken = lotsim.result_dict(rr)
    broken["vehicles"][1]["samples"]["x"] = broken["vehicles"][0]["samples"]["x"]
    assert not lotsim.check(broken).ok
    with pytest.raises(ResultFormatError, match="cannot read"):
        lotsim.check(tmp_path / "none.json")


def test_render_gif_accepts_a_run_its_document_or_its_file(prepared, tmp_path):
    rr = lotsim.run(prepared)
    path = lotsim.write_result(rr, tmp_path / "result.json")
    small = {"size": (200, 160), "end": 12.0}
    infos = [lotsim.render_gif(r, tmp_path / f"{k}.gif", **small)
             for k, r in enumerate((rr, lotsim.result_dict(rr), path))]
    assert infos[0].frames > 1
    data = {(tmp_path / f"{k}.gif").read_bytes() for k in range(3)}
    assert len(data) == 1
    anim = lotsim.load_animation(QUICKSTART)
    info = lotsim.render_gif(rr, tmp_path / "anim.gif", anim, **small)
    assert info.speed == anim.speed
    with pytest.raises(SettingsError, match="start: nothing to show"):
        lotsim.render_gif(rr, tmp_path / "late.gif", start=1e6)


# -- validate, the package ------------------------------------------------------------------------
def test_validate_is_what_the_cli_prints(capsys):
    report = lotsim.validate(str(QUICKSTART))
    assert main(["validate", str(QUICKSTART)]) == 0
    assert capsys.readouterr().out == report.summary() + "\n"
    assert report.complete and report.prepared.scenario.name == "quickstart"


def test_import_lotsim_loads_nothing_heavy_until_asked():
    code = ("import sys, lotsim; heavy = [m for m in ('numpy', 'lotsim.sim.running', "
            "'lotsim.api') "
            "if m in sys.modules]; lotsim.RunSettings; print(heavy, 'lotsim.api' in "
            "sys.modules, sorted(set(lotsim.__all__) - set(dir(lotsim))))")
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, check=True, timeout=120)
    assert done.stdout.strip() == "[] False []"


def test_lotsim_check_stays_the_function_when_the_checker_module_is_imported():
    importlib.import_module("lotsim.verify")
    from lotsim.verify import check_result  # noqa: F401

    assert lotsim.check is lotsim.api.check and callable(lotsim.check)


def test_a_run_and_a_prepared_lot_have_a_short_repr():
    """A plain repr (a notebook cell's last line without the formatters, a debugger) was
    the whole dataclass: 55 kB for the quickstart's run."""
    prepared = lotsim.prepare(QUICKSTART)
    result = lotsim.run(prepared)
    assert repr(result) == ("<RunResult quickstart: 6 vehicles, 6 served, 0 waiting, "
                            "0 rejected; planner hca, seed 1>")
    assert repr(prepared) == ("<PreparedLot quickstart: 20 slots (15 free), 35 nodes, "
                              "54 edges>")
