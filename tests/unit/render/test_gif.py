"""Animated GIFs of runs (``lotsim render``, ``lotsim run --gif``) and the replay they draw.

Frames are read back with Pillow; what is drawn is compared with what the result file
says, independently of the renderer's own bookkeeping where it can be.
"""

import json
import math

import numpy as np
import pytest
from PIL import Image, ImageSequence

from conftest import ROOT, position, scenario_from_text
from lotsim.cli import main
from lotsim.errors import ScenarioError
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import load_scenario
from lotsim.render.animation import (
    WHEEL,
    GifRenderer,
    GifSettings,
    car_parts,
    plan_frames,
    split_gif,
    write_gif,
)
from lotsim.render.replay import PHASES, Replay, assign_colours
from lotsim.sim.running import simulate
from lotsim.sim.settings import RunSettings

QUICKSTART = ROOT / "scenarios" / "quickstart.yaml"
BARE = "".join(line for line in QUICKSTART.read_text().splitlines(keepends=True)
               if not line.startswith("animation:"))
"""quickstart without its animation section (it has one: speed 2)."""
SMALL = GifSettings(size=(400, 300))


@pytest.fixture(scope="module")
def doc():
    """quickstart's run: 6 cars, two of which leave; a round trip through JSON, as on disk."""
    rr = simulate(load_scenario(QUICKSTART), RunSettings())
    return json.loads(json.dumps(result_dict(rr)))


@pytest.fixture(scope="module")
def street():
    """street: parallel parking, so cars reverse; 14 cars of 3 types coming and going."""
    rr = simulate(load_scenario(ROOT / "scenarios" / "street.yaml"), RunSettings())
    return json.loads(json.dumps(result_dict(rr)))


def frames_of(path):
    """(RGB array, start [ms], duration [ms]) of each frame of a GIF."""
    out, t = [], 0
    with Image.open(path) as im:
        for f in ImageSequence.Iterator(im):
            d = f.info["duration"]
            out.append((np.asarray(f.convert("RGB")), t, d))
            t += d
    return out


def frame_at(frames, ms):
    """The frame shown at ``ms`` milliseconds into the GIF."""
    for img, t0, d in frames:
        if t0 <= ms < t0 + d:
            return img
    raise AssertionError(f"no frame at {ms} ms")


# -- the file -----------------------------------------------------------------------------------
def test_gif_loops_has_the_size_and_the_total_duration_asked(doc, tmp_path):
    settings = GifSettings(fps=20, speed=4, size=(400, 300), start=0.0, end=40.0)
    info = write_gif(doc, tmp_path / "a.gif", settings)
    with Image.open(tmp_path / "a.gif") as im:
        assert im.info["loop"] == 0  # 0: for ever
        assert im.size == (400, 300)
        durations = [f.info["duration"] for f in ImageSequence.Iterator(im)]
    # 40 s of run at 4x is 10 s of GIF: 200 frames of 50 ms, identical ones merged
    assert sum(durations) == 10_000
    assert info.duration == pytest.approx(10.0)
    assert len(durations) <= 200
    assert not list(tmp_path.glob(".*"))  # no temporary file left


def test_frame_delays_are_whole_centiseconds_that_add_up_for_any_fps(doc):
    replay = Replay(doc)
    for fps in (3, 7, 24, 30, 50):
        plan = plan_frames(replay, GifSettings(fps=fps, speed=2, start=0.0, end=17.3))
        assert all(d % 10 == 0 and d >= 20 for d in plan.durations)
        n = len(plan.times)
        assert n == math.ceil(17.3 * fps / 2)
        assert abs(sum(plan.durations) / 1000 - n / fps) <= 0.005
        assert np.allclose(np.diff(plan.times), 2 / fps)


def test_max_frames_plays_a_long_span_faster(doc):
    plan = plan_frames(Replay(doc), GifSettings(fps=10, speed=1, start=0.0, end=60.0,
                                                max_frames=100))
    assert len(plan.times) == 100
    assert plan.speed == pytest.approx(6.0)
    assert plan.times[-1] == pytest.approx(60.0 - 0.6)


def test_spliced_chunks_decode_to_the_same_frames_as_one_chunk(doc, tmp_path):
    settings = GifSettings(size=(320, 240), start=0.0, end=30.0)
    write_gif(doc, tmp_path / "one.gif", settings, chunk=10_000)
    write_gif(doc, tmp_path / "many.gif", settings, chunk=7)
    a, b = frames_of(tmp_path / "one.gif"), frames_of(tmp_path / "many.gif")
    # merging identical frames stops at chunk ends, so compare what is shown every 50 ms
    for ms in range(0, 7500, 50):
        assert np.array_equal(frame_at(a, ms), frame_at(b, ms)), ms
    assert sum(d for *_, d in a) == sum(d for *_, d in b)


def test_split_gif_cuts_at_the_first_frame():
    import imageio.v3 as iio

    frames = np.zeros((3, 8, 10), dtype=np.uint8)
    frames[1, 2:4, 2:4] = 1
    frames[2, 5:7, 3:9] = 2
    pal = bytes([0, 0, 0, 255, 0, 0, 0, 255, 0])
    data = iio.imwrite("<bytes>", frames, extension=".gif", mode="P", palette=pal, loop=0,
                       duration=[30, 40, 50])
    screen, pre, body = split_gif(data)
    assert data == data[:6] + screen + pre + body + b";"
    assert b"NETSCAPE2.0" in pre and b"NETSCAPE2.0" not in body
    assert body[:2] == b"\x21\xf9"  # the first frame's graphic control extension
    with pytest.raises(ValueError, match="not a GIF"):
        split_gif(b"PNG..." + data[6:])


def test_a_failed_render_leaves_nothing_behind(doc, tmp_path, monkeypatch):
    calls = []

    def broken(self, times):
        calls.append(len(times))
        if len(calls) == 2:
            raise KeyboardInterrupt
        return np.zeros((len(times), 300, 400), dtype=np.uint8)

    monkeypatch.setattr(GifRenderer, "frames", broken)
    (tmp_path / "old.gif").write_bytes(b"keep me")
    with pytest.raises(KeyboardInterrupt):
        write_gif(doc, tmp_path / "old.gif", SMALL, chunk=5)
    assert len(calls) == 2
    assert (tmp_path / "old.gif").read_bytes() == b"keep me"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.gif"]


# -- what is drawn --------------------------------------------------------------------------------
def _moving_sample(doc, frame_dt, phase="driving"):
    """(vehicle index, sample index) of a sample on the frame clock where a vehicle drives
    forward in the middle of its way in (not at a stop)."""
    replay = Replay(doc)
    for j, tr in enumerate(replay.tracks):
        for k in range(len(tr.t) // 3, len(tr.t)):
            on_grid = abs(tr.t[k] / frame_dt - round(tr.t[k] / frame_dt)) < 1e-6
            if on_grid and tr.v[k] > 1.0 and tr.entered < tr.t[k] < tr.parked_from:
                return j, k
    raise AssertionError("no vehicle drives on the frame clock")


def _centre_px(renderer, v, k):
    s = v["samples"]
    x, y, th = s["x"][k], s["y"][k], s["theta"][k]
    shift = (v["type"]["front"] - v["type"]["rear"]) / 2
    c = renderer.canvas.to_px([x + shift * math.cos(th), y + shift * math.sin(th)])
    return int(round(c[0])), int(round(c[1]))


@pytest.mark.slow
def test_a_vehicle_s_colour_is_under_its_footprint_centre(doc, tmp_path):
    settings = GifSettings(fps=20, speed=4, size=(800, 600), start=0.0)
    j, k = _moving_sample(doc, 4 / 20)
    v = doc["vehicles"][j]
    t = v["samples"]["t"][k]
    write_gif(doc, tmp_path / "a.gif", settings)
    renderer = GifRenderer(doc, settings)
    frames = frames_of(tmp_path / "a.gif")
    img = frame_at(frames, round(t / 4 * 1000))
    col, row = _centre_px(renderer, v, k)
    assert tuple(img[row, col]) == renderer.vehicle_rgb(j)
    # every other vehicle's colour differs while both drive
    others = [renderer.vehicle_rgb(i) for i, tr in enumerate(renderer.replay.tracks)
              if i != j and any(a <= t < b for _, a, b in
                                [p for p in tr.phases(1e9) if p[0] in ("driving", "leaving")])]
    assert renderer.vehicle_rgb(j) not in others
    # at the end, a parked car is shown in the pale version of its colour
    last = frames[-1][0]
    parked = [i for i, w in enumerate(doc["vehicles"]) if w["status"] == "parked"]
    for i in parked:
        w = doc["vehicles"][i]
        col, row = _centre_px(renderer, w, len(w["samples"]["t"]) - 1)
        assert tuple(last[row, col]) == renderer.vehicle_rgb(i, parked=True)


def test_a_car_standing_on_a_gate_s_name_leaves_the_name_readable(doc):
    from lotsim.render.lot_image import paint_portals

    renderer = GifRenderer(doc, SMALL)
    canvas = renderer.canvas
    # the ids' pixels (text and halo), found on a black ground independently of the renderer
    plain = canvas.new_image((0, 0, 0))
    paint_portals(plain, canvas, renderer.lot, labels=False)
    named = plain.copy()
    paint_portals(named, canvas, renderer.lot, labels=True)
    ids = np.any(np.asarray(plain) != np.asarray(named), axis=2)
    # the entrance's id: the label pixels nearest to it
    ys, xs = np.nonzero(ids)
    gate = canvas.to_px(renderer.lot.entrances[0].pose[:2])
    near = np.hypot(xs - gate[0], ys - gate[1]) < 40
    label = np.zeros_like(ids)
    label[ys[near], xs[near]] = True
    assert label.sum() > 20
    centre = canvas.to_world(np.array([xs[near].mean(), ys[near].mean()]))
    # the first car to arrive, stood on that id along the gate's heading (as a car
    # queueing at the gate stands)
    t = 1.0
    state = renderer.replay.states(np.array([t]))
    j = int(np.flatnonzero(state["visible"][0])[0])
    tr = renderer.replay.tracks[j]
    heading = renderer.lot.entrances[0].pose[2]
    mid = (tr.front - tr.rear) / 2
    state["x"][0, j] = centre[0] - mid * math.cos(heading)
    state["y"][0, j] = centre[1] - mid * math.sin(heading)
    state["theta"][0, j] = heading
    state["v"][0, j] = 0.0
    img = np.asarray(renderer.frame(t, state).convert("RGB"))
    bg = np.asarray(renderer.background.convert("RGB"))
    changed = np.any(img != bg, axis=2)
    box = np.zeros_like(ids)
    box[ys[near].min() - 2:ys[near].max() + 3, xs[near].min() - 2:xs[near].max() + 3] = True
    assert (changed & box & ~label).sum() > 20  # the car is there, around the id
    assert not (changed & label).any()  # and every pixel of the id shows as without it


def test_the_legend_shows_the_colours_the_cars_are_drawn_in_and_can_be_left_out(doc):
    from lotsim.errors import SettingsError
    from lotsim.render.lot_image import PARKED_CAR

    on = GifRenderer(doc, GifSettings(size=(800, 600)))
    off = GifRenderer(doc, GifSettings(size=(800, 600), legend=False))
    img = np.asarray(on.frame(30.0).convert("RGB"))
    bare = np.asarray(off.frame(30.0).convert("RGB"))
    assert set(on.legend_boxes) == {"driving", "parked", "parked at start", "reversing",
                                    "its slot"}
    assert off.legend_boxes == {}

    def inside(name):
        x0, y0, x1, y1 = on.legend_boxes[name]
        return img[y0 + 2:y1 - 1, x0 + 5:x1 - 1].reshape(-1, 3)

    j = on.colour.index(0)  # a car drawn in the legend's colour
    # each car has its own colour: "driving" and "parked" show three cars' colours, not one
    # (a red swatch said "driving" was red)
    first = [on.colour.index(k) for k in range(3)]
    x0, y0, x1, y1 = on.legend_boxes["driving"]
    assert {tuple(c) for c in img[y0 + 2:y1 - 1, x0 + 1:x1 - 1].reshape(-1, 3)} == {
        on.vehicle_rgb(i) for i in first}
    x0, y0, x1, y1 = on.legend_boxes["parked"]
    assert {tuple(c) for c in img[y0 + 2:y1 - 1, x0 + 1:x1 - 1].reshape(-1, 3)} == {
        on.vehicle_rgb(i, parked=True) for i in first}
    assert np.all(inside("reversing") == on.vehicle_rgb(j))
    x0, y0, x1, y1 = on.legend_boxes["reversing"]
    assert tuple(img[(y0 + y1) // 2, x0 + 2]) == (255, 255, 255)  # its white rear band
    x0, y0, x1, y1 = on.legend_boxes["its slot"]
    assert tuple(img[(y0 + y1) // 2, x0]) == on.vehicle_rgb(j)
    # a car parked at the start: the colour of such a car's body in the frame
    body = np.asarray(doc["lot"]["parked"][0], dtype=float).reshape(4, 2)
    rear = on.canvas.to_px(body[[0, 3]].mean(axis=0) * 0.8 + body[[1, 2]].mean(axis=0) * 0.2)
    x, y = np.rint(rear).astype(int)
    colours, counts = np.unique(img[y - 1:y + 2, x - 1:x + 2].reshape(-1, 3), axis=0,
                                return_counts=True)
    start = inside("parked at start")
    assert np.all(start == start[0])
    assert np.abs(start[0].astype(int) - np.array(PARKED_CAR)).max() < 12
    assert any(np.all(c == start[0]) for c in colours)
    # without it, the footer right of the scale bar is bare, and the lot is the same
    assert len(np.unique(bare[600 - 20:, 400:].reshape(-1, 3), axis=0)) == 1
    assert np.array_equal(img[:560], bare[:560])
    with pytest.raises(SettingsError, match="legend"):
        GifSettings(legend="yes")
    from lotsim.api import load_animation

    assert load_animation(BARE + "animation: {legend: false}\n").gif_settings().legend is False
    assert load_animation(BARE + "animation: {speed: 2}\n").gif_settings().legend is True


def test_a_reversing_car_shows_a_white_bar_across_its_rear(street):
    renderer = GifRenderer(street, GifSettings(size=(1200, 900)))
    found = {True: 0, False: 0}
    for tr in renderer.replay.tracks:
        for k in range(1, len(tr.t) - 1, 7):
            if abs(tr.v[k]) < 0.3 or found[bool(tr.v[k] < 0)] >= 6:
                continue
            img = np.asarray(renderer.frame(float(tr.t[k])).convert("RGB"))
            # a point 0.1 m inside the rear bumper, on the centre line
            p = renderer.canvas.to_px([tr.x[k] - (tr.rear - 0.1) * math.cos(tr.theta[k]),
                                       tr.y[k] - (tr.rear - 0.1) * math.sin(tr.theta[k])])
            rgb = tuple(img[int(round(p[1])), int(round(p[0]))])
            reversing = tr.v[k] < 0
            assert (rgb == (255, 255, 255)) == reversing, (tr.id, tr.t[k], rgb)
            found[reversing] += 1
    assert found == {True: 6, False: 6}


def test_car_parts_put_the_wheels_on_the_axles_and_turn_the_front_ones():
    rng = np.random.default_rng(5)
    n = 40
    x, y = rng.uniform(-50, 50, n), rng.uniform(-50, 50, n)
    th, steer = rng.uniform(-np.pi, np.pi, n), rng.uniform(-0.6, 0.6, n)
    wb = rng.uniform(2.3, 3.3, n)
    body = np.array([[[-1.0, -0.9], [3.7, -0.9], [3.7, 0.9], [-1.0, 0.9]]] * n)
    parts = car_parts(x, y, th, steer, body, wb)
    wheels = parts["wheels"]
    centres = wheels.mean(axis=2)  # (V, 4, 2)
    front_axle = np.stack([x + wb * np.cos(th), y + wb * np.sin(th)], -1)
    rear_axle = np.stack([x, y], -1)
    assert np.allclose(centres[:, :2].mean(axis=1), rear_axle)
    assert np.allclose(centres[:, 2:].mean(axis=1), front_axle)
    for w, turn in ((0, 0.0), (1, 0.0), (2, steer), (3, steer)):
        long_axis = wheels[:, w, 1] - wheels[:, w, 0]
        ang = np.arctan2(long_axis[:, 1], long_axis[:, 0])
        assert np.allclose(np.angle(np.exp(1j * (ang - th - turn))), 0, atol=1e-9)
        assert np.allclose(np.hypot(*long_axis.T), WHEEL[0])
    # the body is the footprint: rear bumper 1 m behind the axle, 1.8 m wide
    b = parts["body"]
    assert np.allclose(np.hypot(*(b[:, 1] - b[:, 0]).T), 4.7)
    assert np.allclose(np.hypot(*(b[:, 3] - b[:, 0]).T), 1.8)
    assert np.allclose(b.mean(axis=1), np.stack([x + 1.35 * np.cos(th), y + 1.35 * np.sin(th)],
                                                -1))


# -- the replay -----------------------------------------------------------------------------------
def test_replay_states_hit_the_samples_and_turn_the_short_way():
    v = {"id": "a", "arrival": 0.0, "status": "departed", "slot": None, "reason": "",
         "type": {"name": "t", "width": 1.8, "front": 3.7, "rear": 1.0, "wheelbase": 2.7},
         "samples": {"t": [0.0, 1.0, 2.0], "x": [0.0, 1.0, 3.0], "y": [0.0, 0.0, 0.0],
                     "theta": [3.1, -3.1, -3.1], "v": [0.0, 1.0, 0.0],
                     "steer": [0.0, 0.2, 0.0], "gear": [0, 1, 0]}}
    r = Replay({"lot": {"slots": []}, "vehicles": [v], "settings": {}})
    st = r.states(np.array([-1.0, 0.0, 0.5, 1.0, 1.5, 2.0, 2.5]))
    assert st["visible"][:, 0].tolist() == [False, True, True, True, True, True, False]
    assert st["x"][1:6, 0] == pytest.approx([0.0, 0.5, 1.0, 2.0, 3.0])
    # from 3.1 to -3.1 rad the short way is across ±pi, not through 0
    assert abs(math.cos(st["theta"][2, 0]) + 1) < 1e-3
    assert st["steer"][2, 0] == pytest.approx(0.1)


def test_the_replay_reads_what_the_run_met_from_the_result(disturbed_doc, doc):
    from lotsim.errors import ReplayError

    met = Replay(disturbed_doc).met
    recorded = disturbed_doc["disturbances"]
    assert met.kinds == {"stalled", "closed", "taken"}
    (c,), (b,), (st,) = met.closures, met.strangers, met.stalls
    assert (c.label, c.t0, c.t1) == ("gate out closed", recorded["closures"][0]["t0"], 90.0)
    assert c.closed_at(c.t0) and c.closed_at(c.t1) and not c.closed_at(c.t1 + 1e-6)
    assert np.array_equal(c.polygon, recorded["closures"][0]["polygon"])
    assert (b.slot, b.t) == ("S4", 20.0) and b.polygon.shape == (4, 2)
    tracks = Replay(disturbed_doc).tracks
    assert tracks[st.vehicle].id == st.car == "ada"
    assert (st.t0, st.t1) == (recorded["stalls"][0]["t0"], recorded["stalls"][0]["t1"])
    # a bay whose taking was refused has no car to draw; a run without the section, nothing
    refused = {**recorded, "taken": [{**recorded["taken"][0], "polygon": None,
                                      "refused": "a car was parking in it"}]}
    assert Replay({**disturbed_doc, "disturbances": refused}).met.kinds == {"stalled",
                                                                            "closed"}
    assert Replay(doc).met.kinds == frozenset()
    broken = {**recorded, "closures": [{"kind": "gate", "id": "out"}]}
    with pytest.raises(ReplayError, match="disturbances: .*KeyError: 't0'"):
        _ = Replay({**disturbed_doc, "disturbances": broken}).met


def test_counters_account_for_every_vehicle_and_agree_with_the_statuses(doc, street):
    for d in (doc, street):
        r = Replay(d)
        for t in np.linspace(r.start - 1, r.end + 1, 60):
            c = r.counts(t)
            assert c["waiting"] + c["driving"] + c["parked"] + c["departed"] + c["rejected"] \
                == c["arrived"] == sum(v["arrival"] <= t for v in d["vehicles"])
        end = r.counts(r.end + 1)
        assert end["departed"] == d["metrics"]["departed"]
        assert end["parked"] == d["metrics"]["parked"]
        # a car stands in its slot from its arrival there: the phase at its last sample
        for tr in r.tracks:
            if tr.status == "parked":
                st = r.states(np.array([tr.t[-1] + 1.0]))
                j = r.tracks.index(tr)
                assert st["phase"][0, j] == PHASES.index("parked")


def test_a_turned_away_car_waits_outside_for_its_patience_then_counts_as_rejected():
    rr = simulate(load_scenario(ROOT / "scenarios" / "two_rows.yaml"), RunSettings())
    d = json.loads(json.dumps(result_dict(rr)))
    r = Replay(d)
    patience = d["settings"]["patience"]
    rejected = [tr for tr in r.tracks if tr.status == "rejected"]
    assert rejected and patience > 0
    for tr in rejected:
        before = r.counts(tr.arrival + patience - 0.5)
        after = r.counts(tr.arrival + patience + 0.5)
        assert after["rejected"] == before["rejected"] + 1
        assert [p[0] for p in tr.phases(r.end)] == ["outside"]
    assert r.counts(r.end)["rejected"] == d["metrics"]["rejected"]


def test_vehicles_that_move_at_the_same_time_get_different_colours(street):
    r = Replay(street)
    for n in (24, 3):
        colour = assign_colours(r.tracks, n, r.end)
        clashes = 0
        for a in range(len(r.tracks)):
            for b in range(a):
                overlap = any(a0 < b1 and b0 < a1 for a0, a1 in r.tracks[a].active(r.end)
                              for b0, b1 in r.tracks[b].active(r.end))
                clashes += overlap and colour[a] == colour[b]
        if n == 24:
            assert clashes == 0
            assert len(set(colour)) == len(r.tracks)  # enough colours: none repeats
        assert all(0 <= c < n for c in colour)


# -- the command line ---------------------------------------------------------------------------
def test_the_readme_s_main_gif_shows_cars_moving_not_an_empty_lot(mixed_lot_doc):
    # runs/mixed-lot/run.gif was 1800 frames of which about 125 showed a car moving
    from lotsim.api import load_animation

    settings = load_animation(ROOT / "scenarios" / "mixed_lot.yaml").gif_settings()
    plan = plan_frames(Replay(mixed_lot_doc), settings)

    def moving(t: float) -> bool:  # some car rolls at t, by the samples of result.json
        for v in mixed_lot_doc["vehicles"]:
            s = v["samples"]
            if s["t"] and s["t"][0] <= t <= s["t"][-1]:
                k = int(np.searchsorted(s["t"], t))
                if abs(s["v"][max(k - 1, 0)]) > 0 or abs(s["v"][min(k, len(s["t"]) - 1)]) > 0:
                    return True
        return False

    shown = [moving(float(t)) for t in plan.times]
    assert sum(shown) > 0.5 * len(shown), (sum(shown), len(shown))


@pytest.mark.slow
def test_render_writes_what_run_gif_wrote(tmp_path, capsys):
    # quickstart, its animation section asking for speed 2 (as it does) at a small size
    path = tmp_path / "s.yaml"
    path.write_text(BARE + "\nanimation: {speed: 2, size: [320, 240]}\n")
    out = tmp_path / "run"
    assert main(["run", str(path), "-o", str(out), "--gif", str(tmp_path / "a.gif")]) == 0
    assert "a.gif" in capsys.readouterr().out
    # run --gif takes the animation section, render is told
    assert main(["render", str(out / "result.json"), "--gif", str(tmp_path / "b.gif"),
                 "--speed", "2", "--size", "320x240"]) == 0
    with Image.open(tmp_path / "a.gif") as im:
        assert im.size == (320, 240)
    assert (tmp_path / "a.gif").read_bytes() == (tmp_path / "b.gif").read_bytes()
    assert not list(tmp_path.glob(".*"))


def test_run_writes_the_gif_the_scenario_asks_for_unless_told_not_to(tmp_path):
    text = BARE + "\nanimation: {gif: cars.gif, fps: 10, speed: 8, " \
        "size: [320, 240]}\n"
    path = tmp_path / "s.yaml"
    path.write_text(text)
    assert main(["run", str(path), "-o", str(tmp_path / "a")]) == 0
    with Image.open(tmp_path / "a" / "cars.gif") as im:
        assert im.size == (320, 240)
        total = sum(f.info["duration"] for f in ImageSequence.Iterator(im))
    span = Replay(json.loads((tmp_path / "a" / "result.json").read_text())).end
    assert abs(total / 1000 - span / 8) <= 0.1 + 1e-9
    assert main(["run", str(path), "-o", str(tmp_path / "b"), "--no-gif"]) == 0
    assert sorted(p.name for p in (tmp_path / "b").iterdir()) == ["result.json"]


@pytest.mark.parametrize(("text", "needle", "message"), [
    ("animation: {fps: 0}\n", "fps: |0", "expected a number ≥ 1"),
    ("animation: {gif: ../up.gif}\n", "gif: |../up.gif", "ending in .gif (it is written beside"),
    ("animation: {gif: out.png}\n", "gif: |out.png", "ending in .gif"),
    ("animation: {size: [800]}\n", "size: |[800]", "exactly 2 items"),
    ("animation: {from: 50, to: 10}\n", "to: |10", "after 'from'"),
    ("animation: {frames: 3}\n", "|frames", "unknown key 'frames'"),
])
def test_animation_section_errors_are_located(text, needle, message):
    base = BARE + "\n"
    full = base + text
    with pytest.raises(ScenarioError) as err:
        scenario_from_text(full, "s.yaml")
    line, col = position(full, needle)
    assert f"s.yaml:{line}:{col}:" in str(err.value)
    assert message in str(err.value)


@pytest.mark.parametrize(("args", "message"), [
    (["--fps", "60"], "--fps: expected 1 to 50"),
    (["--speed", "0"], "--speed: expected"),
    (["--size", "800by600"], "--size: expected WxH"),
    (["--size", "100x100"], "--size: expected 160x120"),
    (["--from", "30", "--to", "10"], "--to: expected a time after"),
    (["--max-frames", "0"], "--max-frames: expected 1"),
    (["--from", "nan"], "--from: expected a time"),
    (["--from", "5000"], "--from: nothing to show from 5000 s"),
    (["--to", "-5"], "--to: nothing to show from 0 s to -5 s"),
])
def test_render_option_errors(doc, tmp_path, capsys, args, message):
    (tmp_path / "r.json").write_text(json.dumps(doc))
    code = main(["render", str(tmp_path / "r.json"), "--gif", str(tmp_path / "x.gif"), *args])
    err = capsys.readouterr().err
    assert code == 2 and message in err and "Traceback" not in err
    assert not (tmp_path / "x.gif").exists()


def test_render_timeline_writes_a_png_of_the_run(doc, tmp_path, capsys):
    pytest.importorskip("matplotlib")
    (tmp_path / "r.json").write_text(json.dumps(doc))
    assert main(["render", str(tmp_path / "r.json"), "--timeline", str(tmp_path / "t.png")]) == 0
    with Image.open(tmp_path / "t.png") as im:
        assert im.format == "PNG"
        colours = {c for _, c in im.convert("RGB").getcolors(1 << 20)}
    renderer = GifRenderer(doc, SMALL)
    for j, v in enumerate(doc["vehicles"]):  # each car's parked bar, in the GIF's pale colour
        if v["status"] in ("parked", "departed"):
            assert renderer.vehicle_rgb(j, parked=True) in colours
    assert main(["render", str(tmp_path / "r.json"), "--timeline", str(tmp_path / "t.gif")]) == 2
    assert "ending in .png" in capsys.readouterr().err


def test_progress_shows_on_a_terminal_only(doc, tmp_path, capsys, monkeypatch):
    (tmp_path / "r.json").write_text(json.dumps(doc))
    argv = ["render", str(tmp_path / "r.json"), "--gif", str(tmp_path / "x.gif"),
            "--size", "320x240", "--to", "20"]
    assert main(argv) == 0
    assert capsys.readouterr().err == ""  # a pipe: quiet
    monkeypatch.setattr("sys.stderr.isatty", lambda: True)
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "rendering frames [" in err and "100/100" in err
    assert err.endswith("\r")  # the bar is wiped when done


def test_render_input_errors(doc, tmp_path, capsys):
    cases = []
    (tmp_path / "bad.json").write_text("{not json")
    cases.append(([str(tmp_path / "bad.json"), "--gif", str(tmp_path / "x.gif")], "not JSON"))
    old = json.loads(json.dumps(doc))
    del old["lot"]["drawing"]
    (tmp_path / "old.json").write_text(json.dumps(old))
    cases.append(([str(tmp_path / "old.json"), "--gif", str(tmp_path / "x.gif")],
                  "no lot.drawing"))
    (tmp_path / "r.json").write_text(json.dumps(doc))
    cases.append(([str(tmp_path / "r.json")], "nothing to do"))
    cases.append(([str(tmp_path / "r.json"), "--gif", str(tmp_path / "x.png")], "ending in .gif"))
    cases.append(([str(tmp_path / "r.json"), "--gif", str(tmp_path / "r.json" / "x.gif")],
                  "--gif " + str(tmp_path / "r.json" / "x.gif") + ": '"
                  + str(tmp_path / "r.json") + "' is a file, not a folder"))
    cases.append(([str(tmp_path / "missing.json"), "--gif", str(tmp_path / "x.gif")],
                  "missing.json"))
    for argv, message in cases:
        assert main(["render", *argv]) == 2, argv
        err = capsys.readouterr().err
        assert message in err and "Traceback" not in err, (argv, err)
    assert not (tmp_path / "x.gif").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.json", "old.json", "r.json"]



def test_front_wheels_turn_gradually_within_the_steering_rate(street):
    """The GIF draws each car's front wheels at the replayed steer: between frames 0.1 s
    apart they turn no faster than the car can steer, and they do turn (parallel parking)."""
    replay = Replay(street)
    times = np.arange(replay.start, replay.end, 0.1)
    st = replay.states(times)
    rates = np.array([v["type"]["max_steer_rate"] for v in street["vehicles"]])
    turn = np.abs(np.diff(st["steer"], axis=0))
    both = st["visible"][1:] & st["visible"][:-1]
    assert turn[both].max() > 0.02  # the wheels move
    assert np.all(turn[both] <= rates[None, :].repeat(len(turn), 0)[both] * 0.1 + 1e-5)


@pytest.mark.slow
def test_a_run_leaves_no_gif_of_an_earlier_run_beside_its_result(tmp_path, capsys,
                                                                 monkeypatch):
    # run --no-gif into a folder holding an earlier run's GIF left it beside the new
    # result.json without a word; so did a run interrupted while its GIF was drawn
    path = tmp_path / "s.yaml"
    path.write_text(BARE + "\nanimation: {gif: cars.gif, size: [320, 240]}\n")
    out = tmp_path / "a"
    assert main(["run", str(path), "-o", str(out)]) == 0  # an earlier run, with its GIF
    old = out / "cars.gif"
    assert old.is_file()
    capsys.readouterr()
    assert main(["run", str(path), "-o", str(out), "--no-gif"]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["result.json"]
    assert f"removed {old}: it showed an earlier run" in capsys.readouterr().out
    old.write_bytes(b"GIF89a, an earlier run")

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    # interrupted while its GIF is drawn, a run leaves the folder as it was: the earlier
    # result beside the file put there, no new result.json without its GIF
    before = (out / "result.json").read_bytes()
    monkeypatch.setattr("lotsim.api.render_gif", interrupted)
    assert main(["run", str(path), "-o", str(out)]) == 130
    assert sorted(p.name for p in out.iterdir()) == ["cars.gif", "result.json"]
    assert (out / "result.json").read_bytes() == before
    assert old.read_bytes() == b"GIF89a, an earlier run"


def test_a_run_leaves_the_users_own_files_in_its_folder_alone(tmp_path, capsys):
    """A run removes from its folder only the pictures a run wrote there, not a
    replay.html of the user's."""
    path = tmp_path / "s.yaml"
    path.write_text(BARE + "\nanimation: {gif: cars.gif, size: [320, 240]}\n")
    out = tmp_path / "a"
    out.mkdir()
    mine = out / "replay.html"
    mine.write_text("<p>my notes on this lot</p>")
    assert main(["run", str(path), "-o", str(out), "--no-gif"]) == 0
    assert mine.read_text() == "<p>my notes on this lot</p>"
    assert "removed" not in capsys.readouterr().out


def test_a_gif_that_skips_quiet_time_says_how_much(doc, tmp_path, capsys):
    """"12.8 s at 10× run time, 0.0–900.0 s" did not say that quiet time was left out."""
    result = tmp_path / "r.json"
    result.write_text(json.dumps(doc))
    gif = tmp_path / "run.gif"
    argv = ["render", str(result), "--gif", str(gif), "--size", "320x240", "--speed", "20"]
    assert main([*argv, "--skip-quiet"]) == 0
    said = capsys.readouterr().out
    plan = plan_frames(Replay(doc), GifSettings(size=(320, 240), speed=20, skip_quiet=True))
    quiet = sum(b - a for a, b in plan.skips)
    assert quiet >= 1
    assert f"of the run, {quiet:.0f} s of quiet run time skipped, " in said, said
    assert main(argv) == 0
    assert "skipped" not in capsys.readouterr().out


def test_the_gif_shows_closed_ground_a_taken_bay_and_a_stalled_car():
    import lotsim
    from lotsim.render.animation import GifRenderer
    from lotsim.scenario import GifSettings
    from lotsim.traffic.disturbances import Closure, Disturbances, Stall, TakenBay

    prepared = lotsim.prepare(lotsim.EXAMPLE)
    rr = lotsim.run(prepared, disturbances=Disturbances(
        closures=(Closure("gate", "out", 30.0, 90.0),), taken=(TakenBay("S4", 20.0),),
        stalls=(Stall("ada", 0.0, 20.0),)))
    doc = result_dict(rr)
    # the same picture with and without each: the key and the frame of the traffic follow
    # what the run met (the key has its own test)
    settings = GifSettings(size=(480, 320), legend=False, view="lot")
    r = GifRenderer(doc, settings)

    def without(key):  # the same run, drawn as if that had not been met
        return GifRenderer({**doc, "disturbances": {**doc["disturbances"], key: []}}, settings)

    def count(img, index):
        return int((np.asarray(img) == index).sum())

    # the closed exit is hatched while it is closed, and only then
    open_ = without("closures")
    assert count(r.frame(60.0), r.closed) > count(open_.frame(60.0), open_.closed)
    assert count(r.frame(10.0), r.closed) == count(open_.frame(10.0), open_.closed)
    # the stranger's car stands in S4 from 20 s on
    free = without("taken")
    assert count(r.frame(25.0), r.tyre) > count(free.frame(25.0), free.tyre)
    assert count(r.frame(15.0), r.tyre) == count(free.frame(15.0), free.tyre)
    # the stalled car is ringed in white through its stall
    (stall,) = doc["disturbances"]["stalls"]
    mid = (stall["t0"] + stall["t1"]) / 2
    going = without("stalls")
    assert count(r.frame(mid), r.white) > count(going.frame(mid), going.white)
    assert count(r.frame(stall["t1"] + 5), r.white) == \
        count(going.frame(stall["t1"] + 5), going.white)


def test_the_gif_frames_the_ground_the_cars_use_unless_asked_for_the_whole_lot():
    import lotsim
    from lotsim.errors import SettingsError
    from lotsim.render.animation import GifRenderer, traffic_bounds
    from lotsim.render.lot_image.canvas import lot_bounds
    from lotsim.scenario import GifSettings

    prepared = lotsim.prepare("scenarios/mixed_lot.yaml")
    doc = result_dict(lotsim.run(prepared))
    traffic = GifRenderer(doc, GifSettings(size=(640, 480)))
    whole = GifRenderer(doc, GifSettings(size=(640, 480), view="lot"))
    lot = lot_bounds(whole.lot)
    box = traffic_bounds(traffic.replay.tracks, lot)
    assert lot[0] <= box[0] < box[2] <= lot[2] and lot[1] <= box[1] < box[3] <= lot[3]
    for tr in traffic.replay.tracks:  # every footprint's corners are in the frame
        c, s = np.cos(tr.theta)[:, None], np.sin(tr.theta)[:, None]
        along = np.array([tr.front, tr.front, -tr.rear, -tr.rear])
        side = np.array([1, -1, -1, 1]) * tr.width / 2
        cx = tr.x[:, None] + along * c - side * s
        cy = tr.y[:, None] + along * s + side * c
        assert box[0] - 1e-6 <= cx.min() and cx.max() <= box[2] + 1e-6
        assert box[1] - 1e-6 <= cy.min() and cy.max() <= box[3] + 1e-6
    assert traffic.canvas.px(1.0) >= whole.canvas.px(1.0)
    # the first car alone uses a corner of the lot: it is drawn larger
    one = {**doc, "vehicles": doc["vehicles"][:1]}
    assert GifRenderer(one, GifSettings(size=(640, 480))).canvas.px(1.0) > \
        1.5 * whole.canvas.px(1.0)
    with pytest.raises(SettingsError, match="view: expected one of traffic, lot, found 'all'"):
        GifSettings(view="all")
    with pytest.raises(ScenarioError, match="animation.view"):
        load_scenario(lotsim.EXAMPLE + "animation: {view: all}\n")


def test_the_gif_s_key_names_what_the_run_met_on_a_line_of_its_own(disturbed_doc, doc):
    from lotsim.render.animation import CLOSED, FOOTER, INK, TYRE, WHITE, legend_entries

    r = GifRenderer(disturbed_doc, GifSettings(size=(800, 600)))
    img = np.asarray(r.frame(1.0).convert("RGB"))
    cars = ["driving", "parked", "parked at start", "reversing", "its slot"]
    met = ["stalled", "closed", "bay taken"]
    assert list(r.legend_boxes) == cars + met == [
        label for label, _ in legend_entries(True, {"stalled", "closed", "taken"})]
    # the whole key does not fit right of the scale bar: what the run met takes the bottom
    # line, the cars' key the line above it, and the lot ends above both
    assert r.footer == 2 * FOOTER
    assert r.canvas.to_px(r.canvas.bounds[:2])[1] <= 600 - 2 * FOOTER
    upper = {r.legend_boxes[k][3] for k in cars}
    lower = {r.legend_boxes[k][1] for k in met}
    assert max(upper) < min(lower) and min(lower) > 600 - FOOTER
    for label, (x0, y0, x1, y1) in r.legend_boxes.items():
        assert 0 <= x0 < x1 < 800 and 600 - 2 * FOOTER < y0 < y1 < 600, label

    def box(label):
        x0, y0, x1, y1 = r.legend_boxes[label]
        return x0, y0, x1, y1, (y0 + y1) // 2

    x0, y0, x1, y1, mid = box("bay taken")  # the stranger's car: as the frame draws it
    assert {tuple(c) for c in img[y0 + 1:y1, x0 + 1:x1].reshape(-1, 3)} == {TYRE}
    x0, y0, x1, y1, mid = box("closed")  # outlined and hatched in the closed ground's colour
    assert tuple(img[mid, x0]) == CLOSED and tuple(img[y0, (x0 + x1) // 2]) == CLOSED
    inner = {tuple(c) for c in img[y0 + 2:y1 - 1, x0 + 2:x1 - 1].reshape(-1, 3)}
    assert CLOSED in inner and len(inner) == 2  # hatching on the footer's ground
    x0, y0, x1, y1, mid = box("stalled")  # white ring on ink, round cars' own colours
    assert tuple(img[mid, x0 - 1]) == INK and tuple(img[mid, x0 + 1]) == WHITE
    stripes = {tuple(c) for c in img[mid - 2:mid + 3, x0 + 3:x1 - 2].reshape(-1, 3)}
    assert stripes == {r.vehicle_rgb(r.colour.index(k)) for k in range(3)}
    # a run that met nothing: no such entries, one line
    plain = GifRenderer(doc, GifSettings(size=(800, 600)))
    assert list(plain.legend_boxes) == cars and plain.footer == FOOTER
    # an entry only for what the run met
    only = {**disturbed_doc, "disturbances": {**disturbed_doc["disturbances"], "stalls": [],
                                              "taken": []}}
    assert list(GifRenderer(only, GifSettings(size=(800, 600))).legend_boxes) == cars + [
        "closed"]


def test_the_traffic_s_frame_holds_what_the_run_closed_and_took(disturbed_doc):
    from lotsim.render.animation import traffic_bounds
    from lotsim.render.lot_image.canvas import lot_bounds
    from lotsim.render.replay import MetDisturbances, StrangerCar

    r = GifRenderer(disturbed_doc, GifSettings(size=(640, 480)))
    lot = lot_bounds(r.lot)
    tracks = [tr for tr in r.replay.tracks if tr.id == "ada"]  # one car, in one corner
    corner = np.array([[lot[2] - 2.0, lot[3] - 5.0], [lot[2] - 0.2, lot[3] - 5.0],
                       [lot[2] - 0.2, lot[3] - 0.2], [lot[2] - 2.0, lot[3] - 0.2]])
    alone = traffic_bounds(tracks, lot)
    assert alone[2] < lot[2] - 2.0 or alone[3] < lot[3] - 5.0  # the corner is not in it
    box = traffic_bounds(tracks, lot, MetDisturbances(strangers=(StrangerCar("X", 5.0,
                                                                             corner),)))
    assert box[0] <= alone[0] and box[1] <= alone[1]
    assert box[2] >= lot[2] - 0.2 and box[3] >= lot[3] - 0.2
    for c in r.replay.met.closures:  # and the run's own closed ground
        b = traffic_bounds(tracks, lot, r.replay.met)
        lo, hi = c.polygon.min(axis=0), c.polygon.max(axis=0)
        assert b[0] <= lo[0] and b[1] <= lo[1] and hi[0] <= b[2] and hi[1] <= b[3]
