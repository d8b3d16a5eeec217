"""Limits and containment: absurd inputs are refused or stopped with a located message before
anything is written; a scenario reads and writes only where it is told; YAML is read safely."""

from __future__ import annotations

import os
import re
import textwrap

import pytest

import lotsim
from conftest import ONE_AISLE, ROOT, position, time_limit
from lotsim.cli import main
from lotsim.errors import Location
from lotsim.io.lot_yaml import MAX_AISLE_LENGTH, MAX_LOT_SIZE, MAX_SLOTS
from lotsim.sim.limits import WARMUP, Budget, LimitExceeded, Watchdog, parse_size

STREAM = "traffic: {stream: {count: COUNT, rate_per_hour: 3600, dwell: [20, 40]}}\n"


def _write(tmp_path, text: str, name: str = "s.yaml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def _located(capsys, path, text: str, needle: str) -> str:
    """The one stderr line, checked to start with ``path:line:col:`` of ``needle``."""
    err = capsys.readouterr().err.strip()
    line, col = position(text, needle)
    assert err.startswith(f"lotsim: {path}:{line}:{col}: "), err
    assert "\n" not in err and "Traceback" not in err
    return err


def _refused(path, text: str, needle: str, call=lotsim.validate) -> str:
    """The error ``call(path)`` raises, checked to start with ``path:line:col:`` of ``needle``
    and to be one line."""
    with pytest.raises(lotsim.ScenarioError) as err:
        call(path)
    line, col = position(text, needle)
    assert str(err.value).startswith(f"{path}:{line}:{col}: "), err.value
    assert "\n" not in str(err.value)
    return str(err.value)


def _nothing_in(folder) -> bool:
    return not folder.exists() or not any(folder.iterdir())


# -- lots too big are refused when read ------------------------------------------------------
def _stretched(length: float) -> str:
    """ONE_AISLE with its boundary and aisle ``length`` m long."""
    return (ONE_AISLE.replace("[[0, 0], [50, 0], [50, 22], [0, 22]]",
                              f"[[0, 0], [{length}, 0], [{length}, 22], [0, 22]]")
            .replace("[[0, 11], [50, 11]]", f"[[0, 11], [{length}, 11]]"))


@pytest.mark.parametrize(("text", "needle", "words"), [
    (_stretched(MAX_LOT_SIZE + 1), "boundary: |[[0, 0]", "2,001 m across; lotsim plans lots "
     "of at most 2,000 m"),
    # a zig-zag aisle inside a legal boundary: 11 legs of 1950 m
    (ONE_AISLE.replace("[[0, 0], [50, 0], [50, 22], [0, 22]]",
                       "[[0, 0], [1950, 0], [1950, 1950], [0, 1950]]")
     .replace("centerline: [[0, 11], [50, 11]]", "centerline: [" + ", ".join(
         f"[{1950 * (k % 2)}, {11 + 20 * k}]" for k in range(12)) + "]"),
     "- |{id: a, centerline", f"lotsim plans lots with at most {MAX_AISLE_LENGTH:,.0f} m"),
    (ONE_AISLE.replace("count: 6, slot_width: 2.5,\n       slot_length: 5.0, start: 12, "
                       "id_prefix: S", f"count: {MAX_SLOTS}, slot_width: 2.5,\n       "
                       "slot_length: 5.0, start: 12, id_prefix: S"),
     "- |{aisle: a, side: right", f"{MAX_SLOTS + 6:,} slots up to this row"),
])
def test_a_lot_too_big_to_plan_is_refused_where_it_crosses_the_limit(tmp_path, text, needle,
                                                                      words):
    path = _write(tmp_path, text)
    assert words in _refused(path, text, needle)


def test_a_million_vehicles_is_refused_when_read(tmp_path):
    text = ONE_AISLE + STREAM.replace("COUNT", "1000000")
    path = _write(tmp_path, text)
    assert "100000" in _refused(path, text, "count: |1000000", call=lotsim.load_scenario)


# -- runs too big are stopped while they plan ------------------------------------------------
@pytest.mark.slow
def test_a_run_projected_past_its_time_limit_stops_early_and_writes_nothing(tmp_path, capsys):
    """100 000 cars through a 12-slot lot: the projection stops it after a few seconds,
    located at the stream, long before the limit itself would."""
    text = ONE_AISLE + STREAM.replace("COUNT", "100000")
    path = _write(tmp_path, text)
    # the limit sits far below the projected need (about a minute on a fast machine, more
    # under load), so the projection and not the limit stops the run, whatever the pace
    code = main(["run", str(path), "-o", str(tmp_path / "out"), "--time-limit", "20"])
    err = _located(capsys, path, text, "stream: |{count")
    assert code == 2
    m = re.search(r"after planning (\d+) of 200000 trips in ([\d.]+) s: at this pace the "
                  r"run needs about ([\d.]+) (h|min|s), over the time limit of 20 s", err)
    assert m, err
    assert WARMUP <= int(m[1]) < 200000 and float(m[2]) < 20
    assert "nothing was written" in err and _nothing_in(tmp_path / "out")


def test_a_run_over_its_memory_limit_stops_and_writes_nothing(tmp_path, capsys):
    # enough cars that planning outlasts the watchdog's first check (POLL), however quick
    # (with 20, a warm process planned them all before it looked); it stops at that look
    text = ONE_AISLE + STREAM.replace("COUNT", "400")
    path = _write(tmp_path, text)
    code = main(["run", str(path), "-o", str(tmp_path / "out"), "--memory-limit", "5M",
                 "--no-gif"])
    err = _located(capsys, path, text, "stream: |{count")
    assert code == 2
    assert re.search(r"it holds \d+ MB of memory, over the budget of 5 MB \(--memory-limit\)",
                     err), err
    assert _nothing_in(tmp_path / "out")


@pytest.mark.parametrize(("args", "words"), [
    (["--memory-limit", "lots"], "--memory-limit: expected a size such as 500M"),
    (["--memory-limit", "10k"], "--memory-limit: expected at least 1M"),
    (["--time-limit", "-1"], "--time-limit: expected a number of seconds ≥ 0"),
    (["--time-limit", "nan"], "--time-limit: expected a number of seconds ≥ 0"),
])
def test_bad_limits_are_refused(tmp_path, capsys, args, words):
    path = _write(tmp_path, ONE_AISLE + STREAM.replace("COUNT", "2"))
    assert main(["run", str(path), "-o", str(tmp_path / "out"), *args]) == 2
    assert words in capsys.readouterr().err
    assert _nothing_in(tmp_path / "out")


def test_generous_limits_change_nothing(tmp_path):
    path = _write(tmp_path, ONE_AISLE + STREAM.replace("COUNT", "4"))
    a, b = tmp_path / "a", tmp_path / "b"
    assert main(["run", str(path), "-o", str(a), "--time-limit", "0"]) == 0
    assert main(["run", str(path), "-o", str(b), "--memory-limit", "64G",
                 "--time-limit", "600"]) == 0
    assert (a / "result.json").read_bytes() == (b / "result.json").read_bytes()


def _dog(memory=None, seconds=None):
    dog = Watchdog(Budget(memory, seconds), Location("s.yaml", 3, 4, "traffic"))
    dog.start = 0.0
    return dog


def test_projections_wait_for_the_warm_up_and_extrapolate_linearly(monkeypatch):
    """The decision rule on synthetic numbers: measured limits at once; the time projected
    after WARMUP trips and two seconds once the lot is built, from the pace of the latter
    half; never once everything is done."""
    import lotsim.sim.limits as limits

    mb = 2**20
    dog = _dog(memory=1000 * mb, seconds=100.0)
    assert "over the budget of 1000 MB" in dog.problem(1.0, 1001 * mb)
    assert "over the time limit of 100 s" in dog.problem(101.0, 10 * mb)
    assert dog.problem(50.0, 10 * mb) is None  # nothing dealt with yet: nothing to project
    clock = [10.0]
    monkeypatch.setattr(limits.time, "perf_counter", lambda: clock[0])
    monkeypatch.setattr(limits, "resident_memory", lambda: 100 * mb)
    dog.progress(1, 1000)  # the lot took 10 s and 100 MB to build
    clock[0] = 12.0
    dog.progress(WARMUP, 1000)
    assert dog.problem(15.0, 110 * mb) is None  # not yet WARMUP trips after the first
    clock[0] = 15.0
    dog.progress(1 + WARMUP, 1000)
    assert dog.problem(11.0, 110 * mb) is None  # not yet two seconds
    # the latter half: from trip 10 at 12 s to trip 11 at 15 s, 3 s a trip:
    # 15 + 3 * 989 = 2982 s needed; the memory is not projected yet (start-up)
    err = dog.problem(15.0, 110 * mb)
    assert "planning 11 of 1000 trips in 15 s" in err and "about 50 min" in err
    assert dog.projection(15.0, 110 * mb)[1] is None
    dog.progress(1000, 1000)
    assert dog.problem(15.0, 110 * mb) is None  # done: nothing left to project


def test_the_memory_projection_follows_a_growth_that_slows(monkeypatch):
    """A planner that grows as 2 MB · n^0.7 past the 100 MB of the built lot, n trips after
    the first (the closed form the fit must recover), over 2000 trips: once the start-up
    share is planned, the projection is 100 MB + DOC_FACTOR · 2 MB · 1999^0.7, where a
    straight line from the start would say far more."""
    import lotsim.sim.limits as limits

    mb = 2**20
    grown = {"rss": 100 * mb}
    clock = [0.0]
    monkeypatch.setattr(limits.time, "perf_counter", lambda: clock[0])
    monkeypatch.setattr(limits, "resident_memory", lambda: grown["rss"])
    dog = _dog(memory=None, seconds=None)
    dog.start = 0.0
    total = 2000
    for k in range(1, 401):
        clock[0] = 10.0 + 0.1 * k
        grown["rss"] = int(100 * mb + 2 * mb * (k - 1) ** 0.7)
        dog.progress(k, total)
        if k == limits.MEMORY_WARMUP[0] * total - 1:  # one short of the share
            assert dog.projection(clock[0], grown["rss"])[1] is None
    seconds, peak = dog.projection(clock[0], grown["rss"])
    want = 100 * mb + limits.DOC_FACTOR * 2 * mb * (total - 1) ** 0.7
    assert peak == pytest.approx(want, rel=1e-3)
    assert seconds == pytest.approx(clock[0] + 0.1 * (total - 400), rel=1e-6)
    line = 100 * mb + limits.DOC_FACTOR * (grown["rss"] - 100 * mb) * total / 399
    assert line > 1.5 * want


def test_the_watchdog_interrupts_the_main_thread_with_a_located_error():
    dog = Watchdog(Budget(None, 0.3), Location("s.yaml", 3, 4, "traffic"))
    with pytest.raises(LimitExceeded, match=r"^s\.yaml:3:4: traffic: stopped after 0\.\d s: over "
                                            r"the time limit of 0\.3 s"), dog:
        while True:
            sum(range(1000))


def test_parse_size():
    assert parse_size("1.5G") == 3 * 2**29 and parse_size(" 200 MB ") == 200 * 2**20
    for bad in ("", "G", "-1G", "1X", "1e3"):
        with pytest.raises(ValueError):
            parse_size(bad)


# -- containment ------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["../escape", "/tmp/abs", "a/b", "..", ".hidden", "x" * 101,
                                  "with space"])
def test_a_scenario_name_cannot_lead_outside_the_runs_folder(tmp_path, capsys, monkeypatch,
                                                              name):
    monkeypatch.chdir(tmp_path)
    text = f"name: '{name}'\n" + ONE_AISLE.replace("name: small\n", "") + \
        STREAM.replace("COUNT", "1")
    path = _write(tmp_path, text)
    assert main(["run", str(path)]) == 2
    err = _located(capsys, path, text, "name: |'")
    assert "it names the output folder runs/NAME" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.yaml"]


def test_a_scenario_without_a_name_is_named_after_its_file_safely(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    text = ONE_AISLE.replace("name: small\n", "") + STREAM.replace("COUNT", "1")
    path = _write(tmp_path, text, name="..my lot (v2).yaml")
    assert main(["run", str(path), "--no-gif"]) == 0
    assert (tmp_path / "runs" / "my_lot_v2" / "result.json").is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["..my lot (v2).yaml", "runs"]


@pytest.mark.slow
def test_a_run_writes_only_inside_its_output_folder(tmp_path, monkeypatch):
    """Every file a run of a shipped scenario with an animation creates is in -o OUTDIR
    (quickstart, its animation section drawing a small GIF)."""
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    text = (ROOT / "scenarios" / "quickstart.yaml").read_text()
    assert "\nanimation: {speed: 2}" in text
    scenario = tmp_path / "quickstart.yaml"
    scenario.write_text(text.replace("\nanimation: {speed: 2}",
                                     "\nanimation: {speed: 2, size: [160, 120]}"))
    before = {p for p in tmp_path.rglob("*")}
    assert main(["run", str(scenario), "-o", "out"]) == 0
    created = {p for p in tmp_path.rglob("*")} - before
    assert created == {work / "out", work / "out" / "result.json", work / "out" / "run.gif",
                       work / "out" / ".lotsim-run"}  # the pictures a run wrote there


# -- safe YAML ---------------------------------------------------------------------------------
@pytest.mark.parametrize("tag", ["!!python/object/apply:os.system ['touch PWNED']",
                                 "!!python/name:os.system", "!!python/object:object {}",
                                 "!!binary aGVsbG8="])
def test_yaml_tags_that_would_run_code_are_refused(tmp_path, monkeypatch, tag):
    monkeypatch.chdir(tmp_path)
    text = ONE_AISLE.replace("name: small", f"name: {tag}")
    path = _write(tmp_path, text)
    _refused(path, text, "name: |!!", call=lotsim.load_scenario)  # 1:7
    assert not os.path.exists(tmp_path / "PWNED")


def test_aliases_are_not_expanded(tmp_path):
    """A billion-laughs document (aliases nested ten deep: 10¹⁰ leaves if expanded) is walked
    in linear time, up to the first error."""
    lines = ["a0: &a0 [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]"]
    lines += [f"a{k}: &a{k} [" + ", ".join([f"*a{k - 1}"] * 10) + "]" for k in range(1, 10)]
    text = "\n".join(lines) + "\n" + ONE_AISLE.replace("[[0, 0], [50, 0], [50, 22], [0, 22]]",
                                                       "*a9")
    path = _write(tmp_path, text)
    with time_limit(20.0):
        err = _refused(path, text, "a0", call=lotsim.load_scenario)
    assert err.startswith(f"{path}:1:1: a0: unknown key 'a0'"), err


def test_aliases_of_valid_values_are_used(tmp_path):
    """An anchored boundary reused as walls: read as the same polygon each time."""
    text = ONE_AISLE.replace("boundary: [[0, 0]", "boundary: &b [[0, 0]").replace(
        "  occupied: [N1, N2, N3, N4, N5, S1, S2, S3, S4]",
        "  walls:\n    - {id: w0, polygon: *b}")
    with pytest.raises(lotsim.ScenarioError, match="slot 'N1' overlaps wall 'w0' by 12.50 m²"):
        lotsim.validate(text)
