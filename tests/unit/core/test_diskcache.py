"""The on-disk cache of prepared lots (:mod:`lotsim.core.diskcache`): a lot prepared before is
loaded, not planned again, and gives exactly what planning it gives; anything else is planned."""

from __future__ import annotations

import functools
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import lotsim.core.diskcache
from conftest import ONE_AISLE, ROOT, scenario_from_text
from lotsim.io.result import result_dict
from lotsim.sim.preparation import prepare_graph, prepare_lot
from lotsim.sim.running import simulate

TRAFFIC = """\
traffic:
  vehicles:
    - {id: a, arrival: 0, dwell: 20}
    - {id: b, arrival: 3}
"""


@pytest.fixture
def folder(tmp_path, monkeypatch):
    where = tmp_path / "cache"
    monkeypatch.setenv("LOTSIM_CACHE_DIR", str(where))
    return where


def _doc(scenario, lg) -> str:
    return json.dumps(result_dict(simulate(scenario, lot_graph=lg)), sort_keys=True)


def test_a_lot_prepared_before_is_loaded_and_runs_exactly_as_planned(folder):
    sc = scenario_from_text(ONE_AISLE + TRAFFIC)
    cold = prepare_graph(sc)
    assert not cold.from_cache and len(list(folder.glob("prepared-*.pickle"))) == 1
    warm = prepare_graph(sc)
    assert warm.from_cache
    assert warm.infeasible == cold.infeasible
    assert warm.facts() == cold.facts()
    # the graph, made from its dicts when first asked for: nodes, edges and each node's
    # predecessors in the same order, one data dict for an edge both ways
    assert "graph" not in vars(warm)
    g, h = cold.graph, warm.graph
    assert list(h.nodes(data=True)) == list(g.nodes(data=True))
    assert list(h.edges) == list(g.edges) and [list(h.pred[n]) for n in h] == [
        list(g.pred[n]) for n in g]
    assert all(h.succ[u][v] is h.pred[v][u] for u, v in h.edges)
    assert _doc(sc, warm) == _doc(sc, cold) == _doc(sc, prepare_graph(sc, cache=False))


def test_a_changed_lot_or_lotsim_is_planned_again(folder, monkeypatch):
    prepare_graph(scenario_from_text(ONE_AISLE + TRAFFIC))
    wider = ONE_AISLE.replace("slot_width: 2.5,\n       slot_length: 5.0, start: 12, id_prefix: S",
                              "slot_width: 2.6,\n       slot_length: 5.0, start: 12, id_prefix: S")
    assert wider != ONE_AISLE
    assert not prepare_graph(scenario_from_text(wider + TRAFFIC)).from_cache
    # the cars' stays decide which maneuvers are kept: other traffic, other entry
    stay = TRAFFIC.replace(", dwell: 20", "")
    assert not prepare_graph(scenario_from_text(ONE_AISLE + stay)).from_cache
    assert prepare_graph(scenario_from_text(ONE_AISLE + stay)).from_cache
    monkeypatch.setattr(lotsim.core.diskcache, "code_version", lambda: "another lotsim")
    assert not prepare_graph(scenario_from_text(ONE_AISLE + TRAFFIC)).from_cache


def test_a_damaged_entry_is_planned_again_and_replaced(folder):
    sc = scenario_from_text(ONE_AISLE + TRAFFIC)
    cold = prepare_graph(sc)
    (entry,) = folder.glob("prepared-*.pickle")
    entry.write_bytes(entry.read_bytes()[:1000])  # cut short, as a full disk leaves it
    again = prepare_graph(sc)
    assert not again.from_cache
    assert _doc(sc, again) == _doc(sc, cold)
    assert prepare_graph(sc).from_cache


def test_no_cache_where_it_cannot_be_written_or_is_turned_off(tmp_path, monkeypatch):
    sc = scenario_from_text(ONE_AISLE + TRAFFIC)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("LOTSIM_CACHE_DIR", str(blocker / "cache"))
    assert not prepare_graph(sc).from_cache and not prepare_graph(sc).from_cache
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setenv("LOTSIM_CACHE_DIR", "off")
    assert not prepare_graph(sc).from_cache and not prepare_graph(sc).from_cache
    assert not (tmp_path / "xdg").exists()
    monkeypatch.delenv("LOTSIM_CACHE_DIR")
    prepare_graph(sc)
    assert prepare_graph(sc).from_cache
    assert len(list((tmp_path / "xdg" / "lotsim").glob("prepared-*.pickle"))) == 1


def test_the_least_recently_used_entries_go_first(folder):
    for k in range(3):
        assert lotsim.core.diskcache.store(f"e{k}.pickle", k, most_entries=2)
        os.utime(folder / f"e{k}.pickle", (1000 + k, 1000 + k))
    assert lotsim.core.diskcache.load("e0.pickle") is None  # removed when e2 came
    assert lotsim.core.diskcache.load("e1.pickle") == 1  # now the most recently used
    assert lotsim.core.diskcache.store("e3.pickle", 3, most_entries=2)
    assert sorted(p.name for p in folder.glob("*.pickle")) == ["e1.pickle", "e3.pickle"]
    assert not list(folder.glob(".*.tmp"))


def _prepare_after(barrier, text: str, out) -> None:
    sc = scenario_from_text(text)
    barrier.wait()
    lg = prepare_graph(sc)
    out.put((lg.from_cache, _doc(sc, lg)))


def test_two_processes_asking_for_one_lot_at_once_plan_it_once(folder):
    """Both miss the cache at first; the one that gets the lock plans and stores the lot, the
    other waits, then loads it: one plans, and both run alike. Without the lock both plan."""
    import multiprocessing

    ctx = multiprocessing.get_context("fork")
    barrier, out = ctx.Barrier(2), ctx.Queue()
    procs = [ctx.Process(target=_prepare_after, args=(barrier, ONE_AISLE + TRAFFIC, out))
             for _ in range(2)]
    for proc in procs:
        proc.start()
    got = sorted(out.get(timeout=120) for _ in procs)
    for proc in procs:
        proc.join(timeout=60)
    assert [from_cache for from_cache, _ in got] == [False, True]
    assert got[0][1] == got[1][1]


def test_the_lock_of_an_entry_goes_with_it_unless_it_is_held(folder):
    store = functools.partial(lotsim.core.diskcache.store, most_entries=1)
    with lotsim.core.diskcache.making("e0.pickle"):
        assert store("e0.pickle", 0)
    with lotsim.core.diskcache.making("e1.pickle"):
        # e0 and its lock go; e1's lock is held while e1 is made and stays with it
        assert store("e1.pickle", 1)
        with lotsim.core.diskcache.making("e2.pickle"):
            assert store("e9.pickle", 9)  # e2 not made yet: its lock stays
    assert sorted(p.name for p in folder.iterdir()) == [".e1.pickle.lock", ".e2.pickle.lock",
                                                        "e9.pickle"]
    assert store("e8.pickle", 8)  # nothing holds e1 and e2 now
    assert sorted(p.name for p in folder.iterdir()) == ["e8.pickle"]


@pytest.mark.slow
def test_validate_from_another_folder_and_process_finds_the_lot(tmp_path):
    """The key is the lot as written, not where the file lies nor the process's hash seed."""
    cache = tmp_path / "cache"
    text = (ROOT / "scenarios" / "quickstart.yaml").read_text()
    outs = []
    for k, seed in enumerate((1, 2)):
        (tmp_path / f"d{k}").mkdir()
        path = tmp_path / f"d{k}" / "lot.yaml"
        path.write_text(text)
        env = {**os.environ, "LOTSIM_CACHE_DIR": str(cache), "PYTHONHASHSEED": str(seed)}
        outs.append(subprocess.run([sys.executable, "-m", "lotsim", "validate", str(path),
                                    "--verbose"],
                                   env=env, capture_output=True, text=True, timeout=300))
    assert [o.returncode for o in outs] == [0, 0], outs
    assert lotsim.core.diskcache.LOADED not in outs[0].stdout
    assert lotsim.core.diskcache.LOADED in outs[1].stdout
    said = [o.stdout.replace(str(tmp_path / f"d{k}"), "") for k, o in enumerate(outs)]
    assert said[1].replace(lotsim.core.diskcache.LOADED, "") == said[0]


@pytest.mark.slow
def test_a_warm_validate_does_not_load_the_graph_library(tmp_path):
    """Importing networkx took a fifth of a warm ``validate``: a lot from the cache makes
    its graph only when asked for it, and validate reads the counts kept with the lot."""
    code = ("import sys\nfrom lotsim.cli import main\ntry:\n"
            "    main(['validate', sys.argv[1], '--verbose'])\n"
            "except SystemExit as e:\n    assert not e.code\nprint('networkx' in sys.modules)")
    env = {**os.environ, "LOTSIM_CACHE_DIR": str(tmp_path)}
    said = [subprocess.run([sys.executable, "-c", code, str(ROOT / "scenarios" / "street.yaml")],
                           env=env, capture_output=True, text=True, timeout=300).stdout
            for _ in range(2)]
    assert said[0].endswith("True\n") and lotsim.core.diskcache.LOADED not in said[0]
    assert said[1].endswith("False\n") and lotsim.core.diskcache.LOADED in said[1]
    assert said[1].replace(lotsim.core.diskcache.LOADED, "")[:-6] == said[0][:-5]


def test_a_lot_from_the_cache_unpickles_its_graph_and_answers_only_when_used(folder):
    """A warm ``validate`` reads the counts kept with the lot: the graph and the maneuver
    planner's answers stay bytes until something asks for them, then are what was stored."""
    import pickle

    import lotsim

    sc = scenario_from_text(ONE_AISLE + TRAFFIC)
    cold = prepare_lot(sc)
    warm = prepare_lot(sc)
    assert lotsim.validate(warm).summary(verbose=True)
    assert "_graph_packed" in vars(warm.lot_graph)
    assert "_answers_packed" in vars(warm.maneuver_planner)
    # passed on unread (to a worker, say), then read
    again = pickle.loads(pickle.dumps(warm))
    for lp in (warm, again):
        planner, mine = lp.maneuver_planner, cold.maneuver_planner
        v = sc.vehicle_types[0]
        slot = lp.lot.slots[2]
        lane = planner.lanes_for(slot)[0]
        assert planner.solve(v, slot, lane) == mine.solve(v, slot, lane)
        for name in ("_cache", "_raw", "_posed", "_fitted"):
            assert getattr(planner, name) == getattr(mine, name)
        assert "_answers_packed" not in vars(planner)
        assert _graph(lp.lot_graph) == _graph(cold.lot_graph)
        assert "_graph_packed" not in vars(lp.lot_graph)


@pytest.mark.parametrize("entry", [b"not a pickle", None])
def test_loading_leaves_the_cycle_collector_as_it_was(tmp_path, entry):
    # the collector is off while an entry is read (a prepared lot is many objects and no
    # garbage), and must be back as it was whether the entry was read, damaged or missing
    import gc

    if entry is not None:
        (tmp_path / "x.pickle").write_bytes(entry)
    else:
        lotsim.core.diskcache.store("x.pickle", {"a": [1.0, 2.0]}, tmp_path)
    try:
        for before in (True, False):
            (gc.enable if before else gc.disable)()
            lotsim.core.diskcache.load("x.pickle", tmp_path)
            lotsim.core.diskcache.load("missing.pickle", tmp_path)
            assert gc.isenabled() is before
    finally:
        gc.enable()


def _graph(lg) -> tuple:
    return (sorted(lg.graph.nodes(data=True), key=lambda n: n[0]),
            sorted(lg.graph.edges(data=True), key=lambda e: e[:2]), lg.infeasible)


def _longer(text: str) -> str:
    """ONE_AISLE 22 m longer, with fourteen slots a row."""
    for old, new in (("name: small", "name: long"), ("[50, 0], [50, 22]", "[72, 0], [72, 22]"),
                     ("[50, 11]]", "[72, 11]]"), ("count: 6,", "count: 14,"),
                     ("x: 44.0", "x: 66.0")):
        assert old in text
        text = text.replace(old, new)
    return text


LONG_AISLE = _longer(ONE_AISLE)
"""A one-way aisle between two rows of fourteen slots, 35 m long: a maneuver's problem (its
window some 30 m across) near one end does not reach the other."""


def test_an_edited_lot_searches_only_what_the_edit_changed(folder):
    """The maneuver problems of a lot prepared before are kept by their exact geometry: the
    lot with one slot fewer at one end searches again only the problems near that end, and
    is prepared exactly as without the cache. A lot of another name does not read them, nor
    does a small lot keep them."""
    assert not prepare_graph(scenario_from_text(LONG_AISLE + TRAFFIC)).from_cache
    assert not list(folder.glob("maneuvers-*.pickle"))  # 28 slots, one type: too small
    folder.joinpath(next(folder.glob("prepared-*.pickle"))).unlink()
    before = prepare_lot(scenario_from_text(LONG_AISLE + TRAFFIC), remember_from=1)
    assert before.maneuver_planner.stats["remembered"] == 0
    assert len(list(folder.glob("maneuvers-*.pickle"))) == 1
    shorter = LONG_AISLE.replace("count: 14, slot_width: 2.5,\n       slot_length: 5.0, "
                                 "start: 12, id_prefix: S", "count: 13, slot_width: 2.5,\n"
                                 "       slot_length: 5.0, start: 12, id_prefix: S")
    assert shorter != LONG_AISLE
    sc = scenario_from_text(shorter + TRAFFIC)
    edited = prepare_lot(sc, remember_from=1)
    stats = edited.maneuver_planner.stats
    assert not edited.lot_graph.from_cache
    assert 0 < stats["remembered"] < stats["planned"]  # some answers kept, some searched
    cold = prepare_lot(sc, cache=False, remember_from=1)
    assert cold.maneuver_planner.stats["remembered"] == 0
    assert _graph(edited.lot_graph) == _graph(cold.lot_graph)
    assert _doc(sc, edited.lot_graph) == _doc(sc, cold.lot_graph)
    again = shorter.replace("count: 13, slot_width: 2.5,\n       slot_length: 5.0, start: 12, "
                            "id_prefix: S", "count: 12, slot_width: 2.5,\n       slot_length: "
                            "5.0, start: 12, id_prefix: S")
    assert again != shorter
    other = prepare_lot(scenario_from_text(again.replace("name: long", "name: other")
                                           + TRAFFIC), remember_from=1)
    assert not other.lot_graph.from_cache and other.maneuver_planner.stats["remembered"] == 0
    same = prepare_lot(scenario_from_text(again.replace("count: 12, slot_width", "count: 11, "
                                                        "slot_width") + TRAFFIC),
                       remember_from=1)
    assert not same.lot_graph.from_cache and same.maneuver_planner.stats["remembered"] > 0


def _problems(text: str):
    """The maneuver planner of the lot in ``text`` and its (vehicle, slot, lane) triples."""
    from lotsim.lot.build import build_lot
    from lotsim.lot.model import DesignVehicle
    from lotsim.sim.preparation import maneuver_planner

    sc = scenario_from_text(text + TRAFFIC)
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    planner = maneuver_planner(sc, lot)
    return planner, [(v, slot, lane) for v in sc.vehicle_types for slot in lot.slots
                     for lane in planner.lanes_for(slot)]


@pytest.mark.parametrize("old, new", [
    ("count: 14, slot_width", "count: 13, slot_width"),  # a slot fewer at one end
    ("start: 12, id_prefix: S", "start: 12.01, id_prefix: S"),  # a row moved by 1 cm
    ("width: 7.0", "width: 7.01"),  # the aisle 1 cm wider
    ("[72, 0], [72, 22]", "[72, 0], [72, 21.99]"),  # a corner of the wall moved by 1 cm
    ("x: 3.0, y: 11.0", "x: 9.0, y: 11.0"),  # the entrance further in
])
def test_problems_with_the_same_sources_in_a_lot_and_its_edit_are_posed_alike(old, new):
    """A problem's sources name what it is made from without posing it: where a lot and an
    edit of it give a slot the same sources, posing the problem in each gives the same
    digest and the same exact key, whatever the edit was."""
    from lotsim.maneuvers.problem import exact_key

    edited = LONG_AISLE.replace(old, new, 1)
    assert edited != LONG_AISLE
    (a, ta), (b, tb) = _problems(LONG_AISLE), _problems(edited)
    sa = dict(zip([(v.name, s.id, x.id) for v, s, x in ta], a.problems.sources(ta),
                  strict=True))
    same = 0
    for (v, slot, lane), source in zip(tb, b.problems.sources(tb), strict=True):
        if sa.get((v.name, slot.id, lane.id)) != source:
            continue
        was = a.lot.slot_by_id[slot.id]
        pa = a.problems.pose(v, was, next(x for x in a.lanes_for(was) if x.id == lane.id))
        pb = b.problems.pose(v, slot, lane)
        assert a.problems.digest(pa) == b.problems.digest(pb), slot.id
        assert exact_key(pa, "any") == exact_key(pb, "any"), slot.id
        same += 1
    assert same < len(tb)  # the edit reached some problems


def test_an_edited_lot_poses_only_the_problems_its_edit_reached(folder, monkeypatch):
    """A lot prepared before keeps how it posed each problem, by its sources: prepared again
    (its prepared entry gone) it poses no problem at all; with one slot fewer at one end of
    a 120 m aisle it digests again only the problems near that end; and either is prepared
    as without the cache."""
    import lotsim.maneuvers.batch
    from lotsim.maneuvers.problem import LotProblems

    text = LONG_AISLE
    for old, new in (("[72, 0], [72, 22]", "[122, 0], [122, 22]"), ("[72, 11]]", "[122, 11]]"),
                     ("count: 14,", "count: 34,"), ("x: 66.0", "x: 116.0")):
        assert old in text
        text = text.replace(old, new)
    monkeypatch.setattr(lotsim.maneuvers.batch, "PARALLEL_FROM", 10**6)  # in this process
    prepare_lot(scenario_from_text(text + TRAFFIC), remember_from=1)
    digested, posed = [], []
    pose, digests = LotProblems.pose, LotProblems.digests

    def counted_pose(self, *triple):
        posed.append(triple[1].id)
        return pose(self, *triple)

    def counted_digests(self, triples):
        digested.extend(slot.id for _, slot, _ in triples)
        return digests(self, triples)

    monkeypatch.setattr(LotProblems, "pose", counted_pose)
    monkeypatch.setattr(LotProblems, "digests", counted_digests)
    next(folder.glob("prepared-*.pickle")).unlink()
    again = prepare_lot(scenario_from_text(text + TRAFFIC), remember_from=1)
    assert not again.lot_graph.from_cache
    assert again.maneuver_planner.stats["remembered"] > 0
    assert digested == posed == []
    sc = scenario_from_text(text.replace("count: 34, slot_width", "count: 33, slot_width", 1)
                            + TRAFFIC)
    edited = prepare_lot(sc, remember_from=1)
    assert digested and {int(slot[1:]) for slot in digested} <= set(range(20, 35))
    monkeypatch.setattr(LotProblems, "pose", pose)
    monkeypatch.setattr(LotProblems, "digests", digests)
    for got, lot in ((again, text), (edited, None)):
        cold = prepare_lot(got.scenario, cache=False)
        assert _graph(got.lot_graph) == _graph(cold.lot_graph), lot


def test_a_maneuver_problem_is_kept_by_everything_its_search_reads():
    """The exact key changes with anything a search reads (here moved by a nanometre), and
    not with the order of the obstacles, which a search only asks about as a set."""
    import dataclasses

    import numpy as np
    import shapely

    from lotsim.lot.build import build_lot
    from lotsim.lot.model import DesignVehicle
    from lotsim.maneuvers.planner import ManeuverPlanner
    from lotsim.maneuvers.problem import exact_key

    sc = scenario_from_text(ONE_AISLE + TRAFFIC)
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    planner = ManeuverPlanner(lot)
    slot = lot.slot_by_id["S3"]
    p = planner.problems.pose(sc.vehicle_types[0], slot, planner.lanes_for(slot)[0])
    key = exact_key(p, "any")
    assert len(p.obstacles) >= 3
    assert exact_key(dataclasses.replace(p, obstacles=p.obstacles[::-1]), "any") == key
    nudge = 1e-9

    def moved(g):
        return shapely.affinity.translate(g, xoff=nudge)

    changed = {
        "style": (p, "forward"),
        "an obstacle": (dataclasses.replace(p, obstacles=np.array(
            [moved(p.obstacles[0]), *p.obstacles[1:]], dtype=object)), "any"),
        "the allowed region": (dataclasses.replace(p, allowed=moved(p.allowed)), "any"),
        "the window": (dataclasses.replace(p, window=moved(p.window)), "any"),
        "the lane": (dataclasses.replace(p, lane_y=p.lane_y + nudge), "any"),
        "the lane's ends": (dataclasses.replace(p, lane_x=(p.lane_x[0] + nudge, p.lane_x[1])),
                            "any"),
        "the lane's station": (dataclasses.replace(p, lane_s0=p.lane_s0 + nudge), "any"),
        "the frame": (dataclasses.replace(p, frame=dataclasses.replace(
            p.frame, heading=p.frame.heading + nudge)), "any"),
        "the window's size": (dataclasses.replace(p, half=p.half + nudge), "any"),
        "the sweep step": (dataclasses.replace(p, sweep=p.sweep + nudge), "any"),
        "the car": (dataclasses.replace(p, vehicle=dataclasses.replace(
            p.vehicle, wheelbase=p.vehicle.wheelbase + nudge)), "any"),
        "the slot": (dataclasses.replace(p, slot=dataclasses.replace(
            slot, polygon=slot.polygon + nudge)), "any"),
    }
    for what, (q, style) in changed.items():
        assert exact_key(q, style) != key, what


def test_the_code_version_covers_every_source_file_of_lotsim():
    """A prepared lot is planned by every layer of lotsim, not only by the folder the cache
    lives in: a change to any of its files must make a new entry."""
    import lotsim

    package = Path(lotsim.__file__).resolve().parent
    expected = sorted(package.rglob("*.py"))
    hashed = lotsim.core.diskcache.source_files()
    assert hashed == expected
    assert package / "lot" / "build.py" in hashed and package / "cli" / "run.py" in hashed


def _entry(folder) -> Path:
    (entry,) = folder.glob("prepared-*.pickle")
    return entry


@pytest.mark.skipif(not hasattr(os, "getuid"), reason="owners and modes are POSIX's")
def test_the_cache_folder_is_private_and_entries_others_could_write_are_not_loaded(folder):
    """Loading a pickle runs what it says: an entry someone else could have written is
    planned afresh, not loaded (and replaced by the user's own)."""
    sc = scenario_from_text(ONE_AISLE + TRAFFIC)
    prepare_graph(sc)
    assert folder.stat().st_mode & 0o777 == 0o700
    entry = _entry(folder)
    assert entry.stat().st_mode & 0o077 == 0
    assert prepare_graph(sc).from_cache
    entry.chmod(0o666)  # anyone may write it
    assert not prepare_graph(sc).from_cache
    assert entry.stat().st_mode & 0o777 == 0o600  # planned again, stored privately
    assert prepare_graph(sc).from_cache
    folder.chmod(0o777)  # anyone may put an entry in the folder
    assert not prepare_graph(sc).from_cache
    folder.chmod(0o700)


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0,
                    reason="giving a file to another user needs root")
def test_an_entry_another_user_owns_is_not_loaded(folder):
    sc = scenario_from_text(ONE_AISLE + TRAFFIC)
    prepare_graph(sc)
    os.chown(_entry(folder), 12345, -1)
    assert not prepare_graph(sc).from_cache


@pytest.mark.parametrize("lot", ["long aisle", "mixed_lot"])
def test_a_lot_prepared_again_takes_its_roadmap_and_maneuver_times_from_the_store(
        lot, folder, monkeypatch):
    """A lot prepared before (its prepared entry gone, its stores kept) takes every junction
    turn, the types each suits, turnaround and maneuver time from what the first
    preparation kept, and comes out the same (the mixed lot: junctions, three types)."""
    from lotsim.io.scenario_yaml import load_scenario
    from lotsim.maneuvers.maneuver import Maneuver
    from lotsim.roadmap import junctions

    sc = (scenario_from_text(LONG_AISLE + TRAFFIC) if lot == "long aisle"
          else load_scenario(ROOT / "scenarios" / "mixed_lot.yaml"))
    first = prepare_lot(sc, remember_from=1)
    assert len(list(folder.glob("roadmap-*.pickle"))) == 1
    folder.joinpath(next(folder.glob("prepared-*.pickle"))).unlink()

    def refused(*_a, **_k):
        raise AssertionError("worked out again")

    monkeypatch.setattr(Maneuver, "duration", refused)
    monkeypatch.setattr(junctions, "_lane_junctions", refused)
    monkeypatch.setattr(junctions, "_suited", refused)
    again = prepare_lot(sc, remember_from=1)
    assert not again.lot_graph.from_cache
    assert _graph(again.lot_graph) == _graph(first.lot_graph)


def test_a_lot_stored_with_its_graph_and_answers_packed_elsewhere_loads_as_one_stored_whole():
    # the cache stores a prepared lot with its graph and answers packed on another process
    # meanwhile: it must load as the lot pickled whole does, and leave the lot it copies as
    # it was
    import pickle

    from lotsim.sim.preparation import prepare_lot

    sc = scenario_from_text(ONE_AISLE)
    prepared = prepare_lot(sc, cache=False)
    lg, planner = prepared.lot_graph, prepared.maneuver_planner
    lg.reachability()
    whole = pickle.loads(pickle.dumps((lg, planner)))
    shells = (lg.with_graph_packed(lg.packed_graph()),
              planner.with_answers_packed(planner.packed_answers()))
    assert "graph" not in vars(shells[0]) and "_cache" not in vars(shells[1])
    parts = pickle.loads(pickle.dumps(shells))
    assert _graph(parts[0]) == _graph(whole[0]) == _graph(lg)
    assert parts[0].reachability() == whole[0].reachability()
    for name in ("_cache", "_raw", "_posed", "_fitted"):
        assert repr(getattr(parts[1], name)) == repr(getattr(whole[1], name))
    assert parts[1].stats == whole[1].stats and len(planner._cache) > 0
    assert "graph" in vars(lg) and "_graph_packed" not in vars(lg)  # the lot as it was
    assert "_answers_packed" not in vars(planner)
    slot = lg.lot.slots[0]
    lane = parts[1].lanes_for(slot)[0]
    assert repr(parts[1].solve(sc.vehicle_types[0], slot, lane)) == repr(
        planner.solve(sc.vehicle_types[0], slot, lane))
