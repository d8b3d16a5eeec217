"""The command line: cars, validate on every shipped scenario."""

import math
import re

import pytest

from conftest import ONE_AISLE, ROOT, SCENARIOS, SHIPPED
from lotsim.cli import main
from oracles.catalogue import DESIGN_TABLE


def test_cars_lists_the_catalogue_with_length_width_and_radius(capsys):
    assert main(["cars"]) == 0
    out = capsys.readouterr().out
    rows = {line.split()[0]: line.split() for line in out.splitlines()[1:] if line[:1].isalpha()}
    for name, (w, df, dr, b, deg) in DESIGN_TABLE.items():
        row = rows[name]
        assert float(row[1].rstrip("m")) == pytest.approx(df + dr, abs=1e-3)
        assert float(row[2].rstrip("m")) == pytest.approx(w, abs=1e-3)
        assert float(row[-1].rstrip("m")) == pytest.approx(b / math.tan(math.radians(deg)),
                                                           abs=0.01)
    assert "valet" in rows


@pytest.mark.parametrize("name", SHIPPED)
def test_validate_passes_on_every_shipped_scenario(shipped_graphs, name):
    import lotsim
    from lotsim.io.scenario_yaml import load_scenario

    prepared = lotsim.PreparedLot(load_scenario(ROOT / "scenarios" / f"{name}.yaml"),
                                  shipped_graphs[name])
    assert lotsim.validate(prepared).complete, name  # what --strict asks
    if name == "large_lot":
        assert len(prepared.lot.slots) == 1040


def test_validate_summary_counts_slots_by_kind():
    import lotsim

    path = next(p for p in SCENARIOS if p.stem == "mixed_lot")
    out = lotsim.validate(path).summary()
    assert "perpendicular 22, parallel 6, angled 12" in out
    assert "free 33, taken 7" in out
    assert "valet (L 4.90 m, W 1.80 m, R 4.97 m)" in out


def test_validate_reports_each_bad_file_and_goes_on(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("lot: 3\n")
    good = next(p for p in SCENARIOS if p.stem == "quickstart")
    assert main(["validate", str(bad), str(good)]) == 2
    cap = capsys.readouterr()
    assert f"{bad}:1:6: lot: expected a mapping, found integer '3'" in cap.err
    assert ": ok — quickstart" in cap.out


def test_a_command_given_another_kind_of_lotsim_file_says_which_kind_it_is(tmp_path, capsys):
    # not "format: unknown key 'format'", "not JSON" or "did you mean 'seeds'?"
    files = {"scenario": next(p for p in SCENARIOS if p.stem == "quickstart"),
             "result": tmp_path / "result.json",
             "bench suite": ROOT / "scenarios" / "bench" / "priority.yaml"}
    files["result"].write_text('{"format": "lotsim-result", "version": 1, "vehicles": []}')
    gif = str(tmp_path / "x.gif")
    commands = {"scenario": [["run", "{}", "-o", str(tmp_path / "o")], ["validate", "{}"],
                             ["show", "{}", "-o", str(tmp_path / "s.png")],
                             ["maneuver", "{}", "--slot", "N1"]],
                "result": [["check", "{}"], ["render", "{}", "--gif", gif]],
                "bench suite": [["bench", "{}", "-o", str(tmp_path / "b")]]}
    for expected, argvs in commands.items():
        for found, path in files.items():
            if found == expected:
                continue
            for argv in argvs:
                assert main([str(path) if a == "{}" else a for a in argv]) == 2, (argv, found)
                err = capsys.readouterr().err
                assert f"{path}" in err and "Traceback" not in err
                assert f"this is a lotsim {found}, not a {expected}: " in err, err
    assert not any((tmp_path / name).exists() for name in ("o", "s.png", "x.gif", "b"))


QUICK = ROOT / "scenarios" / "quickstart.yaml"  # vehicles listed one by one, no stream


@pytest.mark.parametrize("argv,words", [
    (["run", str(QUICK), "--horizon", "30"], "--horizon: only booked orders"),
    (["run", str(QUICK), "--planner", "hca", "--window", "30"],
     "--window: only --planner whca plans in windows"),
    (["run", str(QUICK), "--window", "30"], "--window: only --planner whca"),
    (["run", str(QUICK), "--seed", "5"], "--seed: seeds the traffic stream, and this "
                                         "scenario has none"),
    (["check", "{result}", "--max", "-3"], "--max: expected at least 1, found -3"),
    (["check", "{result}", "--max", "0"], "--max: expected at least 1, found 0"),
    (["show", str(QUICK), "-o", "{tmp}/s.jpg"], "-o: expected a file name ending in .png"),
    (["maneuver", str(QUICK), "--slot", "N1", "-o", "{tmp}/m.jpg"],
     "-o: expected a file name ending in .png"),
])
def test_an_option_that_would_change_nothing_or_be_changed_is_refused(argv, words, tmp_path,
                                                                      capsys):
    # each was taken without a word: ignored (--horizon, --window, --seed), changed
    # (--max -3 listed one) or written as PNG bytes under a .jpg name
    result = tmp_path / "result.json"
    result.write_text('{"format": "lotsim-result"}')
    out = tmp_path / "o"
    argv = [a.format(result=result, tmp=tmp_path) for a in argv]
    assert main([*argv, "-o", str(out)] if argv[0] == "run" else argv) == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err
    assert not out.exists() and not list(tmp_path.glob("*.jpg"))


def test_a_seed_on_a_stream_with_its_own_seed_is_refused_by_the_library():
    import lotsim

    text = QUICK.read_text().split("traffic:")[0] + (
        "traffic:\n  stream: {count: 2, rate_per_hour: 60, seed: 4}\n")
    # no lot graph: the seed is refused before anything is planned
    prepared = lotsim.PreparedLot(lotsim.load_scenario(text), None)
    with pytest.raises(lotsim.SettingsError, match=r"seed: the scenario's stream has its own "
                                                   r"seed \(4, <scenario>:\d+:\d+: "
                                                   r"traffic.stream\)"):
        lotsim.run(prepared, seed=5)


def test_the_scenario_page_example_is_a_shipped_scenario_that_validates_and_runs():
    # the page's example did not run (angle_deg on a perpendicular row, a slot opening onto
    # no aisle, one overlapping N9, an empty 'slots:', ...); it is now scenarios/example.yaml,
    # which the tests over every shipped scenario validate (--strict), run and check
    page = (ROOT / "docs" / "scenario.md").read_text()
    block = re.search(r"```yaml\n(.*?)```", page, re.S).group(1)
    path = ROOT / "scenarios" / "example.yaml"
    assert path in SCENARIOS
    assert block == path.read_text()


def test_preparing_a_lot_shows_its_progress_on_a_terminal(tmp_path, capsys, monkeypatch):
    # validate and run of a big lot said nothing for 20 s while its maneuvers were planned
    import lotsim

    monkeypatch.setenv("LOTSIM_CACHE_DIR", "off")  # planned, not loaded
    path = next(p for p in SCENARIOS if p.stem == "quickstart")
    calls = []
    report = lotsim.validate(path, progress=lambda done, total: calls.append((done, total)))
    stats = report.prepared.maneuver_planner.stats
    searched = stats["planned"]
    assert calls == [(k, searched) for k in range(1, searched + 1)] and searched > 1
    assert main(["validate", str(path)]) == 0
    assert capsys.readouterr().err == ""  # a pipe: quick work writes nothing there
    monkeypatch.setattr("sys.stderr.isatty", lambda: True)
    assert main(["validate", str(path), "--verbose"]) == 0
    cap = capsys.readouterr()
    fitted = stats["fitted"]
    assert (f"{searched} distinct problems: {searched - fitted} searched, {fitted} fitted"
            in cap.out)
    shown = re.findall(r"planning maneuvers \[[#-]+\] (\d+)/(\d+)", cap.err)
    assert shown[-1] == (str(searched), str(searched)) and "\n" not in cap.err
    assert cap.err.endswith("\r")  # the line is wiped when done
    assert main(["run", str(path), "-o", str(tmp_path / "o"), "--no-gif"]) == 0
    assert f"] {searched}/{searched}" in capsys.readouterr().err


def test_what_a_shipped_scenario_says_of_its_aisles_is_true():
    # quickstart.yaml said "one two-way aisle" of its one-way aisle
    import yaml

    for path in [*SCENARIOS, *sorted((ROOT / "scenarios" / "lots").glob("*.yaml"))]:
        text = path.read_text()
        doc = yaml.safe_load(text)
        header = [line for line in text.splitlines() if line.startswith("#")]
        said = " ".join([doc.get("description", ""), *header[:5]])
        ways = {a.get("direction", "two-way") for a in doc["lot"]["aisles"]}
        for way in ("one-way", "two-way"):
            if way in said:
                assert way in ways, (path.name, way, ways)


def test_every_picture_takes_the_same_sizes(tmp_path, capsys):
    # show took 64 to 8000 pixels, render 160x120 to 4000x4000
    import lotsim

    result = tmp_path / "result.json"
    result.write_text('{"format": "lotsim-result"}')
    commands = [["show", str(QUICK), "-o", str(tmp_path / "s.png")],
                ["maneuver", str(QUICK), "--slot", "N1"],
                ["render", str(result), "--gif", str(tmp_path / "r.gif")]]
    for argv in commands:
        for size, shown in (("100x100", "100x100"), ("8000x6000", "8000x6000"),
                            ("160x119", "160x119")):
            assert main([*argv, "--size", size]) == 2
            assert (f"--size: expected 160x120 to 4000x4000 pixels, found {shown}"
                    in capsys.readouterr().err), argv
    for bad in ((100, 100), (8000, 6000)):
        with pytest.raises(lotsim.SettingsError) as lot_err:
            lotsim.render_lot(QUICK, size=bad)
        with pytest.raises(lotsim.SettingsError) as gif_err:
            lotsim.GifSettings(size=bad)
        assert str(lot_err.value) == str(gif_err.value)
    assert not list(tmp_path.glob("*.png")) + list(tmp_path.glob("*.gif"))


def test_each_command_s_help_says_what_it_does_its_arguments_and_exit_codes(capsys):
    # commands had no description, positionals no help, exit codes appeared nowhere
    from lotsim.cli.parser import build_parser

    parser = build_parser()
    commands = parser.commands
    assert set(commands) == {"cars", "validate", "minslot", "maneuver", "run", "render",
                             "check", "show", "bench", "export", "import", "layout"}
    for name, command in commands.items():
        with pytest.raises(SystemExit) as exc:
            main([name, "--help"])
        assert exc.value.code == 0
        text = capsys.readouterr().out
        assert command.description and command.description in " ".join(text.split())
        assert "exit codes: 0 " in text, name
        for action in command._actions:
            assert action.help, (name, action.dest)
    with pytest.raises(SystemExit):
        main(["--help"])
    assert "exit codes: 0 ok, 1 incomplete" in capsys.readouterr().out


def test_an_extra_argument_gets_the_command_s_usage_and_one_name_serves_a_car(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["cars", "extra"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: lotsim cars") and "unrecognized arguments: extra" in err
    # --car names a vehicle type for maneuver as for minslot (--vehicle still works)
    assert main(["maneuver", str(QUICK), "--slot", "N1", "--car", "valet"]) == 0
    by_car = capsys.readouterr().out
    assert main(["maneuver", str(QUICK), "--slot", "N1", "--vehicle", "valet"]) == 0
    assert capsys.readouterr().out == by_car and by_car.startswith("valet into slot N1")


def test_slot_and_lane_ids_can_be_found(tmp_path, capsys):
    # a big lot's picture had no labels and 'maneuver --slot X' said only "no slot 'X'"
    import numpy as np
    from PIL import Image, ImageDraw

    from lotsim.io.scenario_yaml import load_scenario
    from lotsim.render.lot_image import draw_lot, lot_layout
    from lotsim.sim.preparation import prepare_graph

    assert main(["maneuver", str(QUICK), "--slot", "Q7"]) == 2
    assert "no slot 'Q7'" in capsys.readouterr().err
    assert main(["maneuver", str(QUICK), "--slot", "Q7"]) == 2
    assert "(its slots: N1–N10, S1–S10; " in capsys.readouterr().err
    assert main(["maneuver", str(QUICK), "--slot", "N3", "--leave"]) == 0
    assert re.match(r"valet out of slot N3 to lane main> ", capsys.readouterr().out)

    out = tmp_path / "lot.png"
    assert main(["show", str(QUICK), "-o", str(out), "--size", "200x150"]) == 0
    text = capsys.readouterr().out
    assert "  slots: N1–N10, S1–S10\n  lanes: main>\n" in text
    size = tuple(map(int, re.search(r"drawn: 0 of 20 at 200x150 \(--size (\d+)x(\d+) draws "
                                    r"them all\)", text).groups()))
    # at that size each slot holds its id: pixels inside it differ with labels and without
    lg = prepare_graph(load_scenario(QUICK), maneuvers=False)
    on, off = (np.asarray(draw_lot(lg, size=size, labels=flag)) for flag in (True, False))
    canvas = lot_layout(lg, size=size).canvas
    for slot in lg.lot.slots:
        mask = Image.new("1", size)
        ImageDraw.Draw(mask).polygon([tuple(p) for p in canvas.to_px(slot.polygon)], fill=1)
        inside = np.asarray(mask)
        assert (on[inside] != off[inside]).any(), slot.id
    assert main(["show", str(QUICK), "-o", str(out)]) == 0
    assert "slot ids drawn" not in capsys.readouterr().out


def test_the_maneuver_picture_title_counts_its_changes_in_words(tmp_path, monkeypatch,
                                                                  capsys):
    # it read "1 changes"
    from lotsim.render import maneuver_image

    titles = []
    draw = maneuver_image.draw_maneuver

    def noting(*args, title, **kwargs):
        titles.append(title)
        return draw(*args, title=title, **kwargs)

    monkeypatch.setattr(maneuver_image, "draw_maneuver", noting)
    assert main(["maneuver", str(QUICK), "--slot", "N3", "-o", str(tmp_path / "m.png")]) == 0
    changes = int(re.search(r": (\d+) direction change", capsys.readouterr().out).group(1))
    word = "change" if changes == 1 else "changes"
    assert titles == [f"quickstart: valet into N3, {changes} {word} of direction, "
                      + titles[0].rsplit(", ", 1)[1]]


def test_validate_says_how_many_free_slots_each_type_can_use_and_which(capsys):
    """"Does my van fit?": the answer is the positive fact, per type, with the slots."""
    text = ONE_AISLE.replace("vehicle_types: [valet]", "vehicle_types: [valet, vclass]").replace(
        "slot_length: 5.0, start: 12, id_prefix: S", "slot_length: 6.0, start: 12, id_prefix: S"
    ).replace("occupied: [N1, N2, N3, N4, N5, S1, S2, S3, S4]", "occupied: [N1]")
    import lotsim

    report = lotsim.validate(text)
    usable = report.usable()
    assert usable["valet"] == ["N2", "N3", "N4", "N5", "N6", "S1", "S2", "S3", "S4", "S5", "S6"]
    # the 5.37 m van is refused the 5 m bays, with the reason, and fits the 6 m ones
    assert usable["vclass"] == ["S1", "S2", "S3", "S4", "S5", "S6"]
    assert set(report.prepared.lot_graph.infeasible["vclass"]) == {f"N{k}" for k in range(1, 7)}
    line = next(ln for ln in report.summary().splitlines() if "usable" in ln)
    assert line.strip() == ("usable free slots per type: valet 11 of 11; vclass 6 of 11 "
                            "(S1–S6)")


def test_import_writes_the_lots_and_says_what_became_of_each(tmp_path, capsys):
    # a few lots of the file, picked by id: two written and three skipped, each for its own
    # reason (what becomes of every lot of the file: tests/unit/io/test_import_osm.py)
    source = ROOT / "tests" / "data" / "osm" / "lots.osm"
    out = tmp_path / "lots"
    picked = ["way/100", "way/110", "way/140", "way/160", "node/1500"]
    assert main(["import", "osm", str(source), "-o", str(out),
                 *[arg for lot in picked for arg in ("--lot", lot)]]) == 0
    said = capsys.readouterr().out.splitlines()
    written = sorted(p.name for p in out.glob("*.yaml"))
    assert written == ["way-100.yaml", "way-110.yaml"]
    assert said[-1] == f"{len(written)} of {len(said) - 1} lots written" == "2 of 5 lots written"
    assert sorted(line.split(":")[0] for line in said[:-1]) == sorted(picked)
    for name in written:  # each written lot has its line, naming its file
        assert any(f"written {out / name}" in line for line in said)
    # a lot picked that is not in the file, a missing file: bad input, nothing written
    assert main(["import", "osm", str(source), "-o", str(tmp_path / "x"), "--lot",
                 "way/1"]) == 2
    assert main(["import", "osm", str(tmp_path / "none.osm"), "-o", str(tmp_path / "y")]) == 2
    err = capsys.readouterr().err
    assert "way/1" in err and "none.osm" in err and "Traceback" not in err
    assert not (tmp_path / "x").exists() and not (tmp_path / "y").exists()


@pytest.mark.slow
def test_import_lanelet2_writes_the_map_and_refuses_options_it_does_not_take(tmp_path, capsys):
    source = ROOT / "tests" / "data" / "lanelet2" / "autonomoustuff_parking_lot.osm"
    out = tmp_path / "map"
    assert main(["import", "lanelet2", str(source), "-o", str(out)]) == 0
    said = capsys.readouterr().out.splitlines()
    assert said[-1] == "1 of 1 lots written"
    assert (out / "autonomoustuff_parking_lot.yaml").is_file()
    assert main(["import", "lanelet2", str(source), "-o", str(out), "--lot", "1"]) == 2
    assert main(["import", "osm", str(source), "-o", str(out), "--origin", "1,2"]) == 2
    assert main(["import", "lanelet2", str(source), "-o", str(out), "--origin", "91,0"]) == 2
    err = capsys.readouterr().err
    assert "--lot is for OpenStreetMap" in err and "--origin is for Lanelet2" in err
    assert "latitude within ±90" in err


def test_o_names_a_folder_or_a_file_alike_for_every_command(tmp_path, capsys):
    """-o of show and maneuver may name a folder, as it does for run and bench (the picture
    is named for the scenario), or a PNG; any other file is refused."""
    folder = tmp_path / "pics"
    folder.mkdir()
    quick = next(p for p in SCENARIOS if p.stem == "quickstart")
    assert main(["show", str(quick), "-o", str(folder)]) == 0
    assert main(["maneuver", str(quick), "--slot", "N1", "-o", f"{folder}/"]) == 0
    assert sorted(p.name for p in folder.iterdir()) == ["quickstart-N1.png", "quickstart.png"]
    assert main(["show", str(quick), "-o", str(folder / "lot.jpg")]) == 2
    assert "expected a file name ending in .png" in capsys.readouterr().err


def test_where_stderr_is_not_a_terminal_long_work_writes_a_line_every_few_seconds(
        capsys, monkeypatch):
    import io
    import time

    from lotsim.cli.progress import Preparing, ProgressBar

    stream = io.StringIO()  # a pipe, a log file: not a terminal
    bar = ProgressBar("runs", stream=stream, every=0.05)
    bar(0, 10)
    time.sleep(0.3)
    bar(4, 10)
    time.sleep(0.3)
    bar(10, 10)
    bar.close()
    lines = stream.getvalue().splitlines()
    assert len(lines) >= 4 and "\r" not in stream.getvalue()
    assert all(re.fullmatch(r"runs(: \d+/10(, ~\d+ s left)?| …|: done) \(\d+ s\)", line)
               for line in lines), lines
    assert any(line.startswith("runs: 4/10, ~") for line in lines)
    assert lines[-1].startswith("runs: done")
    time.sleep(0.2)
    assert stream.getvalue().splitlines() == lines  # closed: it has stopped
    quick = io.StringIO()
    with ProgressBar("runs", stream=quick, every=5.0) as fast:
        fast(1, 1)
    assert quick.getvalue() == ""  # quick work writes nothing there
    # a lot being prepared says which step it is at
    import lotsim.cli.progress as progress

    monkeypatch.setattr(progress, "PIPE_EVERY", 0.05)
    capsys.readouterr()
    with Preparing() as prep:
        prep(3, 3)
        time.sleep(0.2)
    said = capsys.readouterr().err
    assert "building the lot graph … (" in said
    assert said.endswith("preparing the lot: done (0 s)\n")


def test_the_time_left_goes_by_the_pace_since_the_step_began(monkeypatch):
    """A step that starts well after its bar (a lot's maneuvers, after its lanes) is timed
    from its first news: 40 of 100 done in 2 s leaves some 3 s, however long the bar had
    been up before."""
    import io

    import lotsim.cli.progress as progress

    clock = [100.0]
    monkeypatch.setattr(progress.time, "perf_counter", lambda: clock[0])
    bar = progress.ProgressBar("maneuvers", stream=io.StringIO())
    clock[0] += 60.0  # the lanes
    bar(0, 100)
    assert bar.status == "maneuvers: 0/100"
    clock[0] += 2.0
    bar(40, 100)
    assert bar.status == "maneuvers: 40/100, ~3 s left"
    clock[0] += 1.0
    bar(2, 7)  # another step: its own pace
    clock[0] += 1.0
    bar(4, 7)
    assert bar.status == "maneuvers: 4/7, ~2 s left"


def test_a_bar_interrupted_as_its_beat_starts_closes_cleanly(monkeypatch):
    """Ctrl-C may land while a bar not on a terminal starts the thread that writes its
    status (seen while ``lotsim render`` wrote a GIF): closing it then raises nothing."""
    import io
    import threading

    import lotsim.cli.progress as progress

    def interrupted(self):
        raise KeyboardInterrupt

    monkeypatch.setattr(threading.Thread, "start", interrupted)
    bar = progress.ProgressBar("frames", stream=io.StringIO())
    with pytest.raises(KeyboardInterrupt):
        bar(1, 10)
    bar.close()


def test_a_run_on_a_pipe_tells_its_trips_and_the_writing_of_its_result(tmp_path, capsys,
                                                                       monkeypatch):
    import lotsim.cli.progress as progress

    monkeypatch.setattr(progress, "PIPE_EVERY", 0.001)
    path = next(p for p in SCENARIOS if p.stem == "quickstart")
    assert main(["run", str(path), "-o", str(tmp_path / "o"), "--no-gif"]) == 0
    err = capsys.readouterr().err
    assert "\r" not in err
    assert re.search(r"^trips in and out planned: \d+/\d+", err, re.M)
    assert "trips in and out planned: done" in err
    # its cars were written as the run went: no step after it
    assert "writing the result" not in err
    # a run driven through disturbances is written after it ends, and says so
    assert main(["run", str(path), "-o", str(tmp_path / "d"), "--no-gif",
                 "--late", "0.5,3"]) == 0
    err = capsys.readouterr().err
    assert re.search(r"^writing the result: \d+/\d+", err, re.M)
    assert "writing the result: done" in err


@pytest.mark.slow
def test_validate_takes_several_files_at_once_and_says_what_one_after_another_says(
        tmp_path, capsys):
    import lotsim

    bad_file = tmp_path / "bad.yaml"
    bad_file.write_text("name: bad\nlot:\n  boundary: [[0, 0], [10, 0]]\n")
    paths = [str(ROOT / "scenarios" / "example.yaml"), str(bad_file),
             str(ROOT / "scenarios" / "quickstart.yaml")]
    serial = main(["validate", *paths, "--strict"])
    one_by_one = capsys.readouterr()
    assert serial == 2 and "bad.yaml:" in one_by_one.err
    for many in (["--jobs", "2"], ["--jobs", "1"]):
        assert main(["validate", *paths, "--strict", *many]) == serial
        at_once = capsys.readouterr()
        assert (at_once.out, at_once.err) == (one_by_one.out, one_by_one.err)
    found = lotsim.validate_files(paths, jobs=2)
    assert [f.source for f in found] == paths
    assert [(f.valid, f.complete) for f in found] == [(True, True), (False, False),
                                                      (True, True)]
    assert found[1].problems and all(p.startswith(str(bad_file)) for p in found[1].problems)
    assert found[0].summary == lotsim.validate(paths[0]).summary()
    assert main(["validate", paths[0], "--jobs", "0"]) == 2
    assert "--jobs: expected 1 to" in capsys.readouterr().err


@pytest.mark.slow
def test_validate_on_a_dask_cluster_says_the_same(capsys):
    distributed = pytest.importorskip("distributed")
    paths = [str(ROOT / "scenarios" / "example.yaml"),
             str(ROOT / "scenarios" / "quickstart.yaml")]
    assert main(["validate", *paths]) == 0
    here = capsys.readouterr().out
    with distributed.LocalCluster(n_workers=1, processes=False, threads_per_worker=1,
                                  dashboard_address=None) as cluster:
        assert main(["validate", *paths, "--scheduler", cluster.scheduler_address]) == 0
    assert capsys.readouterr().out == here
    assert main(["validate", paths[0], "--scheduler", "tcp://127.0.0.1:1"]) == 2
    assert "cannot reach a Dask scheduler" in capsys.readouterr().err


def test_validate_and_run_prepare_with_the_collector_tuned_and_leave_it_as_it_was(
        tmp_path, monkeypatch, capsys):
    # preparing makes many objects and almost no cycles: the commands ask for larger
    # batches of collection while they prepare, and put the collector back after
    import gc

    from lotsim.sim import preparation
    from lotsim.sim.running import RUN_GC_THRESHOLDS

    seen = []
    prepare_lot = preparation.prepare_lot

    def spy(*args, **kwargs):
        seen.append(gc.get_threshold())
        return prepare_lot(*args, **kwargs)

    monkeypatch.setattr(preparation, "prepare_lot", spy)
    monkeypatch.setenv("LOTSIM_CACHE_DIR", "off")
    path = ROOT / "scenarios" / "quickstart.yaml"
    before = gc.get_threshold()
    assert before != RUN_GC_THRESHOLDS
    assert main(["validate", str(path)]) == 0
    assert main(["run", str(path), "-o", str(tmp_path / "out"), "--no-gif"]) == 0
    assert seen == [RUN_GC_THRESHOLDS, RUN_GC_THRESHOLDS]
    assert gc.get_threshold() == before

    class Seen(Exception):
        pass

    def layout(*args, **kwargs):  # laying out prepares lots too
        seen.append(gc.get_threshold())
        raise Seen

    monkeypatch.setattr("lotsim.api.layout", layout)
    plot = ROOT / "scenarios" / "plots" / "rect60x100.yaml"
    with pytest.raises(Seen):
        main(["layout", str(plot), "-o", str(tmp_path / "lot.yaml")])
    assert seen[-1] == RUN_GC_THRESHOLDS and gc.get_threshold() == before


@pytest.mark.parametrize("command", ["run", "validate", "layout"])
def test_work_stopped_by_ctrl_c_ends_its_progress_interrupted_not_done(
        command, tmp_path, capsys, monkeypatch):
    """Ctrl-C after 120 of 1000 trips ended with 'trips in and out planned: done (11 s)'
    and then 'interrupted; nothing was written'."""
    import time

    import lotsim.cli.progress as progress

    monkeypatch.setattr(progress, "PIPE_EVERY", 0.01)

    def stopped(*args, progress=None, **kwargs):
        progress(120, 1000)
        time.sleep(0.1)  # long enough for lines of its own
        raise KeyboardInterrupt

    quickstart = str(next(p for p in SCENARIOS if p.stem == "quickstart"))
    plot = tmp_path / "plot.yaml"
    plot.write_text("boundary: [[0, 0], [36, 0], [36, 30], [0, 30]]\n"
                    "gates: [{id: south, at: [18, 0]}]\n")
    argv, label, last = {  # the bar's label, and that of its last line
        "run": (["run", quickstart, "-o", str(tmp_path / "o"), "--no-gif"],
                "trips in and out planned", "trips in and out planned"),
        "validate": (["validate", quickstart], "planning maneuvers", "preparing the lot"),
        "layout": (["layout", str(plot), "-o", str(tmp_path / "lot.yaml")], "laying out",
                   "laying out"),
    }[command]
    monkeypatch.setattr({"run": "lotsim.api.run", "validate": "lotsim.api.validate",
                         "layout": "lotsim.api.layout"}[command], stopped)
    assert main(argv) == 130
    err = capsys.readouterr().err
    assert re.search(rf"^{label}: 120/1000", err, re.M), err
    assert re.search(rf"^{last}: interrupted \(\d+ s\)$", err, re.M), err
    assert f"{last}: done" not in err, err
    assert err.endswith("lotsim: interrupted; nothing was written\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plot.yaml"]


def test_a_bar_ended_by_an_error_says_stopped():
    import io
    import time

    from lotsim.cli.progress import ProgressBar

    stream = io.StringIO()
    with pytest.raises(MemoryError), ProgressBar("runs", stream=stream, every=0.01) as bar:
        bar(3, 10)
        time.sleep(0.05)
        raise MemoryError
    assert stream.getvalue().splitlines()[-1].startswith("runs: stopped (")
