"""SUMO export: ``sumo`` runs the exported files headless (validating them against its XSDs)
with no warning or error; every car that parked in lotsim stops in its own slot's parking
area, at the space's pose, which is the pose lotsim parked it at; it enters at its arrival
time, moves off when lotsim says and reaches its exit within the stated tolerances."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from export_runs import need, result_path, run_params
from lotsim.api import load_result
from lotsim.io.export.sumo import FILES
from lotsim.io.export.tracks import forward, tracks, visits

STEP = 0.1
"""The simulation's step [s]."""
DEPART = 5.0
"""SUMO inserts each car at its arrival time, or when the lane at its entrance is clear;
lotsim holds a car at its gate until its way is reserved: its first sample and SUMO's
insertion agree within this [s] ..."""
LEAVE = 0.15
"""... and ends its stop when lotsim's car moved off, likewise [s]."""
PARK = 45.0
"""SUMO's car stops at its slot's area within this of lotsim's coming to rest in the slot
[s]: it drives the aisles at its own speeds, takes its own route to the area's lane and
makes no parking maneuver."""
EXIT = 30.0
"""It reaches its exit within this of lotsim's last sample [s]: it pulls out of its space
at once, where lotsim's car makes a maneuver."""
FCD_PERIOD = 5.0
"""Positions are written every this many seconds [s]."""
POSE = (0.01, 0.01)
"""A parked car stands at its space within 1 cm [m] and 0.01° [deg] (the output's
rounding) ..."""
LOTSIM_POSE = (0.02, 0.05)
"""... and at lotsim's parked front-bumper centre within 2 cm [m] and 0.05° [deg]."""


@pytest.fixture(scope="module", params=run_params())
def simulated(request, tmp_path_factory):
    """The run exported, and SUMO's stops, trips, positions and error log of it."""
    need("sumo")
    import lotsim

    doc = load_result(result_path(request.param))
    folder = tmp_path_factory.mktemp(f"sumo-{request.param}")
    info = lotsim.export_sumo(doc, folder / "export", step=STEP)
    return doc, info, *simulate(info.config, folder / "out")


def simulate(config, out):
    """Run ``sumo`` on ``config`` headless: its process and its output folder (stops,
    trips, positions every :data:`FCD_PERIOD` and the log of warnings and errors)."""
    import sumo

    from lotsim.io.export.sumo import sumo_binary

    out.mkdir()
    # SUMO_HOME lets sumo find its XSDs and validate every file it reads
    env = dict(os.environ, SUMO_HOME=sumo.SUMO_HOME)
    done = subprocess.run(
        [
            sumo_binary("sumo"),
            "-c", str(config),
            "--no-step-log", "true",
            "--stop-output", str(out / "stops.xml"),
            "--tripinfo-output", str(out / "trips.xml"),
            "--fcd-output", str(out / "fcd.xml"),
            "--device.fcd.period", f"{FCD_PERIOD:g}",
            "--error-log", str(out / "log.txt"),
            "--xml-validation", "always",
        ],
        env=env, capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    return done, out


def elements(path, tag: str) -> list[ET.Element]:
    return list(ET.parse(path).getroot().iter(tag))


def test_sumo_runs_the_files_without_a_warning(simulated):
    doc, info, done, out = simulated
    assert done.returncode == 0, done.stderr
    assert (out / "log.txt").read_text() == ""
    assert "Warning" not in done.stderr and "Error" not in done.stderr, done.stderr
    assert info.left_out == () and info.vehicles == len(elements(out / "trips.xml", "tripinfo"))
    assert info.parked == len(doc["lot"]["parked"])


def wrong_stops(doc: dict, out) -> list[str]:
    """The cars that parked in lotsim but did not park in their own slot's area in SUMO."""
    stops = {s.get("id"): s for s in elements(out / "stops.xml", "stopinfo")}
    wrong = []
    for vid, v in visits(doc).items():
        s = stops.get(vid)
        if v.park is not None and (
            s is None or (s.get("parkingArea"), s.get("parking")) != (v.slot, "1")
        ):
            wrong.append(f"{vid}: {None if s is None else s.get('parkingArea')} for {v.slot}")
    return wrong


def test_every_car_parks_in_its_own_slot(simulated):
    doc, _, _, out = simulated
    assert wrong_stops(doc, out) == []


def test_parked_cars_stand_at_their_spaces_and_where_lotsim_parked_them(simulated):
    doc, info, _, out = simulated
    stops = {s.get("id"): s for s in elements(out / "stops.xml", "stopinfo")}
    vs = visits(doc)
    lotsim_pose = {}
    for tr in tracks(doc):
        v = vs[tr.id]
        if v.park is not None:
            i = int(np.searchsorted(tr.t, v.park))
            x, y = forward(tr.x[i], tr.y[i], tr.theta[i], tr.shape.front)
            lotsim_pose[tr.id] = (float(x), float(y), (90.0 - math.degrees(tr.theta[i])) % 360)
    checked = set()
    for step in elements(out / "fcd.xml", "timestep"):
        t = float(step.get("time"))
        for veh in step.iter("vehicle"):
            vid, s = veh.get("id"), stops.get(veh.get("id"))
            if vid.startswith("parked-") and t > 0:  # parked at start, in its space for good
                sx, sy, angle = info.spaces[vid.removeprefix("parked-")]
                assert math.hypot(float(veh.get("x")) - sx, float(veh.get("y")) - sy) <= POSE[0]
                assert _degrees(float(veh.get("angle")) - (180 - angle)) <= POSE[1]
                checked.add(vid)
            if s is None or not float(s.get("started")) < t < float(s.get("ended")):
                continue
            x, y, h = (float(veh.get(k)) for k in ("x", "y", "angle"))
            sx, sy, angle = info.spaces[vs[vid].slot]
            assert math.hypot(x - sx, y - sy) <= POSE[0], (vid, t, x, y, sx, sy)
            assert _degrees(h - (180 - angle)) <= POSE[1], (vid, t, h, angle)
            lx, ly, lh = lotsim_pose[vid]
            assert math.hypot(x - lx, y - ly) <= LOTSIM_POSE[0], (vid, x, y, lx, ly)
            assert _degrees(h - lh) <= LOTSIM_POSE[1], (vid, h, lh)
            checked.add(vid)
    long_enough = {
        vid for vid, s in stops.items()
        if float(s.get("ended")) - float(s.get("started")) > 2 * FCD_PERIOD
    }  # fmt: skip
    assert long_enough and long_enough <= checked
    assert len([v for v in checked if v.startswith("parked-")]) == info.parked


def test_cars_come_park_leave_and_exit_when_lotsim_says(simulated):
    doc, _, _, out = simulated
    stops = {s.get("id"): s for s in elements(out / "stops.xml", "stopinfo")}
    trips = {s.get("id"): s for s in elements(out / "trips.xml", "tripinfo")}
    d = timing(doc, stops, trips)
    assert np.abs(d["depart"]).max() <= DEPART, d["depart"]
    assert np.abs(d["leave"]).max() <= LEAVE, d["leave"]
    assert np.abs(d["park"]).max() <= PARK, d["park"]
    assert np.abs(d["exit"]).max() <= EXIT, d["exit"]
    assert (d["depart"] >= -DEPART).all()  # and never before its arrival:
    early = {
        vid: (trips[vid].get("depart"), v.arrival)
        for vid, v in visits(doc).items()
        if float(trips[vid].get("depart")) < v.arrival - 0.005
    }
    assert early == {}


def timing(doc: dict, stops: dict, trips: dict) -> dict[str, np.ndarray]:
    """SUMO's time minus lotsim's [s], per car: ``depart`` (inserted / first sample), ``park``
    (stop began / came to rest in its slot), ``leave`` (stop ended / moved off) and
    ``exit`` (reached its exit / last sample)."""
    out: dict[str, list[float]] = {"depart": [], "park": [], "leave": [], "exit": []}
    for vid, v in visits(doc).items():
        out["depart"].append(float(trips[vid].get("depart")) - v.start)
        if v.park is not None:
            out["park"].append(float(stops[vid].get("started")) - v.park)
        if v.leave is not None:
            out["leave"].append(float(stops[vid].get("ended")) - v.leave)
        if v.exit is not None:
            out["exit"].append(float(trips[vid].get("arrival")) - v.end)
    return {k: np.array(a) for k, a in out.items()}


def test_a_car_sent_to_another_slot_is_caught(simulated, tmp_path):
    """The oracle can fail: the first car's stop moved to a free slot's area."""
    doc, info, _, _ = simulated
    vs = visits(doc)
    routes = ET.parse(info.folder / "lot.rou.xml")
    stop = next(t for t in routes.getroot().iter("trip") if t.get("id") in vs).find("stop")
    used = {v.slot for v in vs.values()} | set(doc["lot"]["drawing"]["occupied"])
    stop.set("parkingArea", next(s for s in info.spaces if s not in used))
    bad = tmp_path / "bad"
    bad.mkdir()
    for f in info.files:
        (bad / f.name).write_bytes(f.read_bytes())
    routes.write(bad / "lot.rou.xml")
    done, out = simulate(bad / "lot.sumocfg", tmp_path / "out")
    assert done.returncode == 0
    assert len(wrong_stops(doc, out)) == 1


def _degrees(d: float) -> float:
    """``|d|`` [deg] the short way round."""
    return abs((d + 180.0) % 360.0 - 180.0)


def test_lotsim_export_sumo_writes_the_files_or_names_the_extra(tmp_path, capsys, monkeypatch):
    need("sumo")
    from lotsim.cli import main

    path = str(result_path("mixed_lot"))
    assert main(["export", path, "--sumo", str(tmp_path / "sumo")]) == 0
    assert "sumo: wrote" in capsys.readouterr().out
    assert sorted(p.name for p in (tmp_path / "sumo").iterdir()) == sorted(FILES)
    monkeypatch.setitem(sys.modules, "sumo", None)  # as if not installed
    assert main(["export", path, "--sumo", str(tmp_path / "again")]) == 2
    err = capsys.readouterr().err
    assert "pip install 'lotsim[sumo]'" in err and "Traceback" not in err
    assert not (tmp_path / "again").exists()
