"""The HTML replay (``lotsim render --html``), tested in a real browser, and the MP4 video.

Browser tests drive one headless Chromium (Debian's ``chromium``) over the DevTools
protocol (``tests/chromium.py``), shared by the module. Without a browser they skip,
saying what is missing, unless ``LOTSIM_REQUIRE_BROWSER=1`` (set by ``.ci/run``), where
they fail. What the page shows is compared with what result.json says, computed here
independently of the page's own bookkeeping: where the lot is fitted into the window,
where a car's body is, which colour the GIF gives it.
"""

import base64
import json
import math
import os
import re
import time

import numpy as np
import pytest

from chromium import BrowserError, Chromium, find_browser
from conftest import ROOT
from lotsim.cli import main
from lotsim.errors import LotsimError, SettingsError
from lotsim.io.lot_json import lot_from_json
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import load_scenario
from lotsim.render.animation import (
    CLOSED,
    INK,
    LEGEND_CARS,
    TYRE,
    VEHICLE_COLOURS,
    WHITE,
    GifSettings,
    plan_frames,
    vehicle_palette,
)
from lotsim.render.html import UNITS, replay_data, thin, write_html
from lotsim.render.lot_image import lot_bounds
from lotsim.render.replay import Replay, assign_colours
from lotsim.scenario import AnimationSpec, HtmlSettings
from lotsim.sim.running import simulate
from lotsim.sim.settings import RunSettings

QUICKSTART = ROOT / "scenarios" / "quickstart.yaml"
WINDOW = (1000, 760)


@pytest.fixture(scope="module")
def doc():
    """quickstart's run (6 cars, two leave), through JSON as on disk."""
    rr = simulate(load_scenario(QUICKSTART), RunSettings())
    return json.loads(json.dumps(result_dict(rr)))


@pytest.fixture(scope="module")
def page(doc, tmp_path_factory):
    path = tmp_path_factory.mktemp("replay") / "replay.html"
    write_html(doc, path)
    return path


@pytest.fixture(scope="module")
def browser():
    if find_browser() is None:
        message = ("the replay's browser tests need Chromium: apt-get install chromium, or "
                   "set LOTSIM_CHROMIUM to a Chrome or Chromium binary (README)")
        if os.environ.get("LOTSIM_REQUIRE_BROWSER") == "1":
            pytest.fail(message)
        pytest.skip(message)
    with Chromium(WINDOW) as b:
        yield b


@pytest.fixture
def opened(browser, page):
    """The quickstart replay, freshly loaded, offline, paused at the start."""
    browser.send("Network.emulateNetworkConditions", {
        "offline": True, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1})
    browser.open(page.as_uri())
    return browser


def expected_view(bounds, width, height, margin=14):
    """Where the page must put the lot at first: as lotsim's LotCanvas fits a picture
    (aspect kept, centred, 14 px margins). Returns (scale, x0, y0): px = x0 + x s,
    py = y0 - y s."""
    minx, miny, maxx, maxy = bounds
    fw, fh = width - 2 * margin, height - 2 * margin
    s = min(fw / (maxx - minx), fh / (maxy - miny))
    return s, margin + (fw - (maxx - minx) * s) / 2 - minx * s, \
        margin + (fh - (maxy - miny) * s) / 2 + maxy * s


def body_point(tr, x, y, th, along, across=0.0):
    """A point of a car's body: ``along`` from the rear bumper (0) to the front (1),
    ``across`` metres to the left of its axis."""
    d = -tr.rear + along * (tr.front + tr.rear)
    return (x + d * math.cos(th) - across * math.sin(th),
            y + d * math.sin(th) + across * math.cos(th))


def hex_rgb(h):
    return [int(h[k:k + 2], 16) for k in (1, 3, 5)]


def rgb_hex(c):
    return "#" + bytes(c).hex()


# -- in the browser ---------------------------------------------------------------------------
def test_loads_offline_without_errors_or_requests(opened, page):
    assert opened.evaluate("lotsimReplay.frames()") >= 1
    assert opened.errors() == []
    assert opened.requests() == [page.as_uri()]  # nothing but the file itself
    text = page.read_text()
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:|//)""", text)
    assert "<script src" not in text and "<link" not in text


def test_a_car_is_drawn_where_result_json_puts_it(opened, doc):
    replay = Replay(doc)
    lot = lot_from_json(doc["lot"]["drawing"], root="lot.drawing")
    colour = assign_colours(replay.tracks, VEHICLE_COLOURS, replay.end)
    palette = vehicle_palette()
    view = opened.evaluate("lotsimReplay.view()")
    s, x0, y0 = expected_view(lot_bounds(lot), view["width"], view["height"])
    assert view["s"] == pytest.approx(s) and view["ox"] == pytest.approx(x0)
    assert view["oy"] == pytest.approx(y0)
    checked = 0
    for t in (8.0, 14.5, 20.0, 70.0):
        # the time slider, moved as a user moves it; drawn at the next animation frame
        opened.evaluate(f"(() => {{ const s = document.getElementById('slider'); "
                        f"s.value = {t}; s.dispatchEvent(new Event('input')); }})()")
        opened.evaluate("new Promise(r => requestAnimationFrame(() => "
                        "requestAnimationFrame(r)))")
        assert opened.evaluate("lotsimReplay.time()") == t
        st = replay.states(np.array([t]))
        moving = [j for j in range(len(replay.tracks))
                  if st["visible"][0, j] and st["phase"][0, j] in (1, 3)]
        for j in moving:
            tr = replay.tracks[j]
            x, y, th = (float(st[k][0, j]) for k in ("x", "y", "theta"))
            pose = opened.evaluate(f"lotsimReplay.pose({json.dumps(tr.id)})")
            assert math.hypot(pose["x"] - x, pose["y"] - y) < 0.01, (tr.id, t)
            assert abs(pose["theta"] - th) < 0.003
            # just inside its outline it has its colour, just outside it does not
            rgb = list(palette[colour[j]])
            length, half = tr.front + tr.rear, tr.width / 2
            inside = [body_point(tr, x, y, th, 1 - 0.15 / length),
                      body_point(tr, x, y, th, 0.45, half - 0.15),
                      body_point(tr, x, y, th, 0.45, -half + 0.15)]
            outside = [body_point(tr, x, y, th, 1 + 0.25 / length),
                       body_point(tr, x, y, th, 0.45, half + 0.25),
                       body_point(tr, x, y, th, 0.45, -half - 0.25)]
            for (wx, wy), want in [(p, True) for p in inside] + [(p, False) for p in outside]:
                got = opened.evaluate(f"lotsimReplay.pixel({x0 + wx * s}, {y0 - wy * s})")
                assert (got == [*rgb, 255]) == want, (tr.id, t, wx, wy, got)
            checked += 1
    assert checked >= 4


def test_clicking_a_car_shows_its_id_and_status(opened, doc):
    replay = Replay(doc)
    t = 70.0
    opened.evaluate(f"lotsimReplay.setTime({t})")
    st = replay.states(np.array([t]))
    view = opened.evaluate("lotsimReplay.view()")
    for j in (0, 2):
        tr = replay.tracks[j]
        assert st["visible"][0, j]
        x, y, th = (float(st[k][0, j]) for k in ("x", "y", "theta"))
        cx, cy = body_point(tr, x, y, th, 0.4)
        opened.click(view["ox"] + cx * view["s"], view["oy"] - cy * view["s"])
        assert opened.evaluate("lotsimReplay.selected()") == tr.id
        panel = opened.evaluate("lotsimReplay.panel()")
        assert panel.startswith(f"car {tr.id} ({tr.type_name})")
        assert f"status: {tr.status}" in panel
        assert f"slot: {tr.slot}" in panel
    opened.click(5, 5)  # outside the lot: nothing selected, no panel
    assert opened.evaluate("lotsimReplay.selected()") is None
    assert opened.evaluate("lotsimReplay.panel()") == ""
    assert opened.errors() == []


def test_play_advances_time_and_pause_stops_it(opened):
    start = opened.evaluate("lotsimReplay.setTime(2)")
    opened.click(*opened.evaluate(
        "(() => { const r = document.getElementById('play').getBoundingClientRect(); "
        "return [r.left + r.width / 2, r.top + r.height / 2]; })()"))
    assert opened.evaluate("lotsimReplay.playing()")
    opened.wait_for(f"lotsimReplay.time() > {start} + 0.2")
    opened.evaluate("lotsimReplay.pause()")
    paused = opened.evaluate("lotsimReplay.time()")
    frames = opened.evaluate("lotsimReplay.frames()")
    time.sleep(0.2)
    opened.evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    assert opened.evaluate("lotsimReplay.time()") == paused
    assert opened.evaluate("lotsimReplay.frames()") == frames  # nothing redrawn either
    assert opened.errors() == []


def test_next_event_and_skipping_quiet_stretches(opened, doc):
    replay = Replay(doc)
    events = replay.events()
    opened.evaluate("lotsimReplay.setTime(10.001)")
    opened.evaluate("document.getElementById('next').click()")
    after = events[events > 10.001 + 1e-6][0]
    assert opened.evaluate("lotsimReplay.time()") == pytest.approx(after, abs=1e-3)
    (a, b), = replay.quiet()  # quickstart: one stretch in which nobody moves
    b = round(b, 3)  # as the page keeps it, to the millisecond
    assert opened.evaluate("document.getElementById('quiet').checked")
    opened.evaluate(f"lotsimReplay.setTime({a + 1})")
    opened.evaluate("lotsimReplay.play()")
    opened.wait_for(f"lotsimReplay.time() > {a + 1}")
    opened.evaluate("lotsimReplay.pause()")
    assert opened.evaluate("lotsimReplay.time()") >= b
    assert "skipped" in opened.evaluate("document.getElementById('skipped').textContent")
    opened.evaluate("document.getElementById('quiet').click()")  # off: time runs through
    opened.evaluate(f"lotsimReplay.setTime({a + 1})")
    opened.evaluate("lotsimReplay.play()")
    opened.wait_for(f"lotsimReplay.time() > {a + 1}")
    opened.evaluate("lotsimReplay.pause()")
    assert opened.evaluate("lotsimReplay.time()") < b
    assert opened.errors() == []


def test_wheel_zooms_about_the_pointer(opened):
    before = opened.evaluate("lotsimReplay.view()")
    opened.send("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": 300, "y": 200,
                                             "deltaX": 0, "deltaY": -300})
    opened.wait_for(f"lotsimReplay.view().s > {before['s']} * 1.2")
    after = opened.evaluate("lotsimReplay.view()")
    # the world point under the pointer stays under it
    wx = (300 - before["ox"]) / before["s"]
    assert after["ox"] + wx * after["s"] == pytest.approx(300)
    box = opened.evaluate("document.getElementById('lot').getAttribute('viewBox')")
    assert float(box.split()[2]) == pytest.approx(after["width"] / after["s"], rel=1e-4)


# -- the file ----------------------------------------------------------------------------------
def decoded(vehicle):
    """A vehicle's samples as stored in the page, decoded as the viewer does."""
    return {k: np.cumsum(vehicle["s"][k]) * UNITS[k] for k in UNITS}


def test_thinned_samples_stay_within_the_tolerance(doc):
    data = replay_data(doc, HtmlSettings())
    replay = Replay(doc)
    kept = total = 0
    for v, tr in zip(data["vehicles"], replay.tracks, strict=True):
        d = decoded(v)
        total += len(tr.t)
        kept += len(d["t"])
        if not len(tr.t):
            continue
        # interpolate the kept samples at every original sample time, as the viewer does
        x = np.interp(tr.t, d["t"], d["x"])
        y = np.interp(tr.t, d["t"], d["y"])
        th = np.interp(tr.t, d["t"], d["theta"])
        dth = (th - tr.theta + math.pi) % (2 * math.pi) - math.pi
        reach = math.hypot(max(tr.front, tr.rear), tr.width / 2)
        corner = np.hypot(x - tr.x, y - tr.y) + reach * np.abs(dth)
        assert corner.max() <= 0.01 + 0.002  # the tolerance, plus the rounding
        assert np.abs(np.interp(tr.t, d["t"], d["steer"]) - tr.steer).max() <= 0.021
    assert kept < 0.5 * total


def test_thin_keeps_what_a_straight_line_cannot_carry():
    t = np.linspace(0, 10, 201)
    x = 0.5 * t ** 2  # accelerating: a chord misses the middle by up to 12.5 m
    cols = {"x": x, "y": np.zeros_like(t), "theta": np.zeros_like(t),
            "steer": np.zeros_like(t), "v": t, "gear": np.ones_like(t)}
    keep = thin(t, cols, np.zeros_like(t), np.array([0, len(t)]), 0.01)
    k = np.flatnonzero(keep)
    assert 2 < len(k) < len(t)
    assert np.abs(np.interp(t, t[k], x[k]) - x).max() <= 0.01


def test_same_result_same_file_and_the_colours_of_the_gif(doc, tmp_path):
    a, b = tmp_path / "a.html", tmp_path / "b.html"
    write_html(doc, a)
    write_html(json.loads(json.dumps(doc)), b)
    assert a.read_bytes() == b.read_bytes()
    data = replay_data(doc, HtmlSettings())
    assert data["colours"]["car"] == ["#" + bytes(c).hex() for c in vehicle_palette()]
    replay = Replay(doc)
    assert [v["colour"] for v in data["vehicles"]] == assign_colours(
        replay.tracks, VEHICLE_COLOURS, replay.end)


# -- the colour key -------------------------------------------------------------------------------
def page_key(text: str) -> list[tuple[str, list[tuple[str, str]]]]:
    """The page's colour key as written: (label, [(swatch part, colour)...]) per entry."""
    from html.parser import HTMLParser

    entries: list[tuple[str, list[tuple[str, str]]]] = []

    class Reader(HTMLParser):
        depth = 0

        def handle_starttag(self, tag, attrs):
            a = dict(attrs)
            if a.get("id") == "legend":
                self.depth = 1
            elif self.depth and a.get("class") == "key":
                entries.append((a["data-key"], []))
            elif self.depth and entries and a.get("data-part"):
                fill = a.get("fill", "none")
                entries[-1][1].append((a["data-part"], a["stroke"] if fill == "none" else fill))

        def handle_endtag(self, tag):
            if self.depth and tag == "div":
                self.depth = 0

    Reader().feed(text)
    return entries


def test_the_page_has_the_gif_s_colour_key(doc, page):
    # the GIF has a key of its colours (GifSettings.legend); the replay page had none
    from lotsim.render.animation import GifRenderer

    gif = GifRenderer(doc, GifSettings(size=(800, 600)))
    img = np.asarray(gif.background.convert("RGB"))
    key = dict(page_key(page.read_text()))
    assert list(key) == list(gif.legend_boxes) == ["driving", "parked", "parked at start",
                                                  "reversing", "its slot"]
    for label, (x0, y0, x1, y1) in gif.legend_boxes.items():
        parts = dict(key[label])
        # the swatch's main colour is the one the GIF paints in the middle of its swatch
        # (the slot's outline on its left edge; of the several cars' colours of driving and
        # parked, the first, on the left)
        y = (y0 + y1) // 2
        x = {"its slot": x0, "driving": x0 + 2, "parked": x0 + 2}.get(label, (x0 + x1) // 2)
        want = img[y, x]
        main = hex_rgb(parts["outline" if label == "its slot" else "body"])
        if label == "parked at start":  # the page draws the lot's own colour for them, the
            # GIF the nearest of its palette
            assert np.abs(np.array(main) - want).max() <= 12
        else:
            assert main == list(want), label
    assert hex_rgb(dict(key["reversing"])["band"]) == [255, 255, 255]
    # each car has its own colour: "driving" and "parked" show the GIF's several colours,
    # side by side, not one (one red swatch said driving cars were red)
    for label, parked in (("driving", False), ("parked", True)):
        x0, y0, x1, y1 = gif.legend_boxes[label]
        shown = [c for part, c in key[label] if part == "car"]
        assert len(shown) == LEGEND_CARS > 1
        assert [tuple(hex_rgb(c)) for c in shown] == [
            gif.vehicle_rgb(gif.colour.index(k), parked=parked) for k in range(LEGEND_CARS)]
        assert {tuple(c) for c in img[y0 + 2:y1 - 1, x0 + 1:x1 - 1].reshape(-1, 3)} == {
            tuple(hex_rgb(c)) for c in shown}
    # no car parked at the start, no such entry (as in the GIF)
    bare = json.loads(json.dumps(doc))
    bare["lot"]["parked"] = []
    path = page.with_name("bare.html")
    write_html(bare, path)
    assert [k for k, _ in page_key(path.read_text())] == ["driving", "parked", "reversing",
                                                           "its slot"]


def test_the_colour_key_is_shown_beside_the_controls(opened, page):
    shown = opened.evaluate("""Array.from(document.querySelectorAll('#legend .key')).map(e => {
        const r = e.getBoundingClientRect(), v = document.getElementById('view')
            .getBoundingClientRect(), body = e.querySelector('[data-part]');
        return [e.dataset.key, e.textContent.trim(), r.left, r.top, r.right, r.bottom, v.bottom,
                getComputedStyle(body).fill === 'none' ? getComputedStyle(body).stroke
                                                       : getComputedStyle(body).fill]; })""")
    key = page_key(page.read_text())
    assert len(shown) == 5 and [(k, text) for k, text, *_ in shown] == [(k, k) for k, _ in key]
    for (label, _, left, top, right, bottom, view_bottom, colour), (_, parts) in zip(
            shown, key, strict=True):
        assert 0 <= left < right <= WINDOW[0] and view_bottom <= top < bottom <= WINDOW[1], label
        assert colour == "rgb({}, {}, {})".format(*hex_rgb(parts[0][1])), label


def test_render_html_from_the_command_line(doc, tmp_path, capsys):
    result = tmp_path / "result.json"
    result.write_text(json.dumps(doc))
    out = tmp_path / "replay.html"
    assert main(["render", str(result), "--html", str(out)]) == 0
    assert "wrote" in capsys.readouterr().out and out.stat().st_size > 10_000
    # bad input: a clear message, exit 2, nothing written
    for args, message in (
            (["--html", str(tmp_path / "r.htm")], "--html: expected a file name ending in .html"),
            (["--html", str(result / "r.html")], "is a file, not a folder"),
            (["--html", str(tmp_path / "x.html"), "--gif", str(tmp_path / "x.html")],
             "expected a file name ending in .gif")):
        assert main(["render", str(result), *args]) == 2
        assert message in capsys.readouterr().err
    old = dict(doc, lot={k: v for k, v in doc["lot"].items() if k != "drawing"})
    result.write_text(json.dumps(old))
    assert main(["render", str(result), "--html", str(tmp_path / "old.html")]) == 2
    assert "no lot.drawing" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["replay.html", "result.json"]


def test_html_settings_check_themselves():
    with pytest.raises(SettingsError, match="speed: expected one of 1, 2, 4, 10, 30, 60"):
        HtmlSettings(speed=5)
    with pytest.raises(SettingsError, match="tolerance: expected 0.001 to 0.1 m"):
        HtmlSettings(tolerance=1)
    assert AnimationSpec(skip_quiet=False).html_settings() == HtmlSettings(skip_quiet=False)


def test_run_writes_the_replay_the_scenario_asks_for(tmp_path, capsys):
    text = QUICKSTART.read_text().replace(
        "animation: {speed: 2}", "animation: {speed: 2, gif: a.gif, html: replay.html, "
        "size: [320, 240], to: 10}")
    sc = tmp_path / "q.yaml"
    sc.write_text(text)
    out = tmp_path / "out"
    assert main(["run", str(sc), "-o", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == [".lotsim-run", "a.gif", "replay.html",
                                                     "result.json"]
    assert (out / ".lotsim-run").read_text().split() == ["a.gif", "replay.html"]
    capsys.readouterr()
    # given on the command line (--no-gif): the earlier replay in the folder goes
    assert main(["run", str(sc), "-o", str(out), "--no-gif", "--html",
                 str(tmp_path / "elsewhere.html")]) == 0
    said = capsys.readouterr().out
    assert f"removed {out / 'replay.html'}" in said and f"removed {out / 'a.gif'}" in said
    assert (tmp_path / "elsewhere.html").is_file()
    # the README's main command: the replay into the output folder the run makes
    fresh = tmp_path / "fresh"
    assert main(["run", str(sc), "-o", str(fresh), "--html", str(fresh / "r.html")]) == 0
    assert sorted(p.name for p in fresh.iterdir()) == [".lotsim-run", "a.gif", "r.html",
                                                       "result.json"]
    before = {p.name: p.read_bytes() for p in fresh.iterdir()}
    assert main(["run", str(sc), "-o", str(fresh), "--html", str(sc / "r.html")]) == 2
    assert f"--html {sc / 'r.html'}: '{sc}' is a file, not a folder" in capsys.readouterr().err
    assert {p.name: p.read_bytes() for p in fresh.iterdir()} == before
    sc.write_text(text.replace("html: replay.html", "html: a.gif"))
    assert main(["run", str(sc), "-o", str(out)]) == 2
    assert "ending in .html" in capsys.readouterr().err


# -- skipping quiet stretches in the GIF, and the MP4 video ----------------------------------------
def test_gif_frames_skip_quiet_stretches(doc):
    replay = Replay(doc)
    (a, b), = replay.quiet()
    plain = plan_frames(replay, GifSettings(speed=4))
    plan = plan_frames(replay, GifSettings(speed=4, skip_quiet=True))
    assert not np.any((plan.times > a + 1e-9) & (plan.times < b - 1e-9))
    assert np.any((plain.times > a) & (plain.times < b))
    assert len(plain.times) - len(plan.times) == pytest.approx((b - a) * 20 / 4, abs=1)
    k = int(np.searchsorted(plan.times, b))
    assert plan.skipped[k] == pytest.approx(b - a) and plan.skipped[k - 1] == 0
    assert plan.skipped[k + 20] == 0  # said for one second of the GIF


def test_mp4_has_the_asked_size_and_duration_and_the_gifs_frames(doc, tmp_path):
    ffmpeg = pytest.importorskip("imageio_ffmpeg", reason="MP4 NOT TESTED: pip install "
                                 "'lotsim[video]' (imageio-ffmpeg)")
    from PIL import Image, ImageSequence

    import lotsim

    settings = lotsim.GifSettings(size=(320, 240), fps=10, speed=4, start=0, end=16)
    lotsim.render_mp4(doc, tmp_path / "v.mp4", settings)
    lotsim.render_gif(doc, tmp_path / "v.gif", settings)
    reader = ffmpeg.read_frames(str(tmp_path / "v.mp4"))
    meta = next(reader)
    video = [np.frombuffer(f, np.uint8).reshape(240, 320, 3) for f in reader]
    assert meta["size"] == (320, 240) and meta["fps"] == 10 and meta["codec"] == "h264"
    assert len(video) == 40  # 16 s of run at 4x: 4 s at 10 frames a second
    assert meta["duration"] == pytest.approx(4.0, abs=0.15)
    gif, at = {}, 0
    with Image.open(tmp_path / "v.gif") as im:
        for f in ImageSequence.Iterator(im):
            frame = np.asarray(f.convert("RGB")).astype(int)
            for ms in range(at, at + f.info["duration"], 100):
                gif[ms // 100] = frame
            at += f.info["duration"]
    for k in (0, 13, 26, 39):
        err = np.abs(video[k].astype(int) - gif[k])
        assert err.mean() < 4 and np.percentile(err, 99) < 40, k
        other = np.abs(video[k].astype(int) - gif[(k + 12) % 40]).mean()
        assert other > err.mean() + 0.3  # the cars moved: a frame at another time differs


def test_mp4_without_ffmpeg_or_with_an_odd_size_is_refused(doc, tmp_path, monkeypatch,
                                                           capsys):
    import builtins

    from lotsim import render_mp4

    result = tmp_path / "result.json"
    result.write_text(json.dumps(doc))
    assert main(["render", str(result), "--mp4", str(tmp_path / "v.mp4"), "--size",
                 "321x240"]) == 2
    assert "even width and height" in capsys.readouterr().err
    real = builtins.__import__

    def no_ffmpeg(name, *args, **kwargs):
        if name == "imageio_ffmpeg":
            raise ImportError(name)
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_ffmpeg)
    with pytest.raises(LotsimError, match=r"pip install 'lotsim\[video\]'"):
        render_mp4(doc, tmp_path / "v.mp4")
    assert main(["render", str(result), "--mp4", str(tmp_path / "v.mp4")]) == 2
    assert "lotsim[video]" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result.json"]


def test_the_harness_sees_errors_in_the_page(opened):
    # what test_loads_offline_without_errors_or_requests relies on: an error is seen
    opened.evaluate("setTimeout(() => { throw new Error('boom'); }, 0); 1")
    opened.evaluate("new Promise(r => setTimeout(r, 50))")
    assert any("boom" in e for e in opened.errors())
    with pytest.raises(BrowserError, match="bang"):
        opened.evaluate("(() => { throw new Error('bang'); })()")


def test_render_honours_the_options_the_replay_takes_and_refuses_the_others(doc, tmp_path,
                                                                             capsys):
    """The replay opens at --speed; the options only the GIF and the video have are refused
    when only --html or --timeline is written."""
    import re

    result = tmp_path / "result.json"
    result.write_text(json.dumps(doc))
    pages = {}
    for speed in ("4", "30"):
        out = tmp_path / f"r{speed}.html"
        assert main(["render", str(result), "--html", str(out), "--speed", speed]) == 0
        pages[speed] = out.read_text()
    opening = {k: float(re.search(r'"speed": *([0-9.]+)', v).group(1))
               for k, v in pages.items()}
    assert opening == {"4": 4, "30": 30}
    capsys.readouterr()
    for args, message in (
            (["--html", str(tmp_path / "a.html"), "--fps", "5"], "--fps: only --gif and --mp4"),
            (["--html", str(tmp_path / "a.html"), "--size", "640x480"], "--size: only --gif"),
            (["--html", str(tmp_path / "a.html"), "--skip-quiet"], "--skip-quiet: only"),
            (["--html", str(tmp_path / "a.html"), "--speed", "5"],
             "--speed: the replay opens at one of 1, 2, 4, 10, 30, 60, found 5"),
            (["--timeline", str(tmp_path / "t.png"), "--speed", "10"], "--speed: the timeline")):
        assert main(["render", str(result), *args]) == 2
        assert message in capsys.readouterr().err
    assert not (tmp_path / "a.html").exists() and not (tmp_path / "t.png").exists()


# -- what the run met: a stall, a closed gate, a bay taken --------------------------------------
@pytest.fixture(scope="module")
def met_pages(disturbed_doc, tmp_path_factory):
    """The replay of the disturbed example run, and of the same run drawn as if it had not
    met each of its disturbances (``closures``, ``stalls``, ``taken`` emptied)."""
    folder = tmp_path_factory.mktemp("met")
    pages = {"all": folder / "all.html"}
    write_html(disturbed_doc, pages["all"])
    for key in ("closures", "stalls", "taken"):
        pages[key] = folder / f"no-{key}.html"
        write_html({**disturbed_doc, "disturbances": {**disturbed_doc["disturbances"],
                                                      key: []}}, pages[key])
    return pages


def drawn(browser, page, t):
    """The cars' canvas of ``page`` at run time ``t``, seeking as a user does (the slider),
    as an (H, W, 4) RGBA array read back from the canvas."""
    from io import BytesIO

    from PIL import Image

    browser.open(page.as_uri())
    browser.evaluate(f"(() => {{ const s = document.getElementById('slider'); s.value = {t}; "
                     f"s.dispatchEvent(new Event('input')); }})()")
    browser.evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    assert browser.evaluate("lotsimReplay.time()") == t
    assert browser.errors() == []
    url = browser.evaluate("document.getElementById('cars').toDataURL('image/png')")
    png = base64.b64decode(url.split(",", 1)[1])
    return np.asarray(Image.open(BytesIO(png)).convert("RGBA")).astype(int)


def changed(a, b):
    """Where two drawings differ: the pixel box (x0, y0, x1, y1) holding every difference,
    and how many pixels differ (None, 0 when they are the same)."""
    diff = np.any(a != b, axis=-1)
    if not diff.any():
        return None, 0
    ys, xs = np.nonzero(diff)
    return (xs.min(), ys.min(), xs.max(), ys.max()), int(diff.sum())


def px_box(browser, polygon, pad):
    """The pixel box of a world polygon in the page's view, ``pad`` pixels wider."""
    v = browser.evaluate("lotsimReplay.view()")
    p = np.asarray(polygon, dtype=float)
    x, y = v["ox"] + p[:, 0] * v["s"], v["oy"] - p[:, 1] * v["s"]
    return x.min() - pad, y.min() - pad, x.max() + pad, y.max() + pad


def within(box, outer):
    return (outer[0] <= box[0] and outer[1] <= box[1] and box[2] <= outer[2]
            and box[3] <= outer[3])


def counts_text(browser):
    return browser.evaluate("document.getElementById('counts').textContent")


def test_a_closed_gate_is_hatched_while_it_is_closed_and_only_then(browser, met_pages,
                                                                    disturbed_doc):
    (closure,) = disturbed_doc["disturbances"]["closures"]
    t0, t1 = closure["t0"], closure["t1"]
    assert 30 < t0 < 60 < t1 < 95
    for t in (30.0, 95.0):  # before it closes and after it opens: as if it never had
        a, b = drawn(browser, met_pages["all"], t), drawn(browser, met_pages["closures"], t)
        assert changed(a, b) == (None, 0), t
        assert "closed" not in counts_text(browser)
    a = drawn(browser, met_pages["all"], 60.0)
    assert counts_text(browser).endswith("   gate out closed")  # as the GIF's header
    box = px_box(browser, closure["polygon"], pad=2)
    b = drawn(browser, met_pages["closures"], 60.0)
    where, n = changed(a, b)
    assert n > 100 and within(where, box)  # drawn on the closed ground and nowhere else
    # hatched: the closed ground's colour, in lines, with the lot showing between them
    inside = a[int(box[1]) + 6:int(box[3]) - 6, int(box[0]) + 6:int(box[2]) - 6]
    red = (np.abs(inside[..., :3] - np.array(CLOSED)).max(axis=-1) < 40) & (inside[..., 3] > 128)
    assert 0.05 < red.mean() < 0.5
    assert (inside[..., 3] == 0).mean() > 0.3


def test_a_stalled_car_is_ringed_only_through_its_stall(browser, met_pages, disturbed_doc):
    (stall,) = disturbed_doc["disturbances"]["stalls"]
    car, t0, t1 = stall["car"], stall["t0"], stall["t1"]
    mid = round((t0 + t1) / 2, 1)
    tr = next(tr for tr in Replay(disturbed_doc).tracks if tr.id == car)
    assert tr.t[0] < t0 - 1 and t1 + 5 < tr.parked_from  # in the lot before and after it
    for t in (round(t0 - 1, 1), round(t1 + 4, 1)):
        a, b = drawn(browser, met_pages["all"], t), drawn(browser, met_pages["stalls"], t)
        assert changed(a, b) == (None, 0), t
        assert "stalled" not in counts_text(browser)
        browser.evaluate(f"lotsimReplay.select({json.dumps(car)})")
        assert "now: driving" in browser.evaluate("lotsimReplay.panel()")
    a = drawn(browser, met_pages["all"], mid)
    assert "   stalled 1" in counts_text(browser)
    browser.evaluate(f"lotsimReplay.select({json.dumps(car)})")
    assert "now: stalled (00:03.8 to 00:23.8)" in browser.evaluate("lotsimReplay.panel()")
    pose = browser.evaluate(f"lotsimReplay.pose({json.dumps(car)})")
    view = browser.evaluate("lotsimReplay.view()")
    # hovering over it says so
    cx, cy = body_point(tr, pose["x"], pose["y"], pose["theta"], 0.4)
    browser.send("Input.dispatchMouseEvent", {"type": "mouseMoved", "button": "none",
                                              "x": view["ox"] + cx * view["s"],
                                              "y": view["oy"] - cy * view["s"]})
    assert browser.evaluate("document.getElementById('tip').textContent") == f"{car} \u2014 stalled"
    b = drawn(browser, met_pages["stalls"], mid)
    corners = [body_point(tr, pose["x"], pose["y"], pose["theta"], u, w)
               for u in (0, 1) for w in (-tr.width / 2, tr.width / 2)]
    box = px_box(browser, corners, pad=4)
    where, n = changed(a, b)
    assert n > 50 and within(where, box)  # a ring round the car, nothing else
    # white on its outline, in the middle of a long side; its own colour just inside
    for across, want in ((tr.width / 2, WHITE), (tr.width / 2 - 0.25, None)):
        wx, wy = body_point(tr, pose["x"], pose["y"], pose["theta"], 0.5, across)
        x, y = view["ox"] + wx * view["s"], view["oy"] - wy * view["s"]
        got = a[int(y), int(x), :3]
        if want is not None:
            assert tuple(got) == want
        else:
            assert tuple(got) == tuple(b[int(y), int(x), :3])


def test_a_bay_taken_from_outside_holds_a_dark_car_from_its_time_on(browser, met_pages,
                                                                     disturbed_doc):
    (taken,) = disturbed_doc["disturbances"]["taken"]
    before = drawn(browser, met_pages["all"], round(taken["t"] - 5, 1))
    assert changed(before, drawn(browser, met_pages["taken"], round(taken["t"] - 5, 1))) == (
        None, 0)
    a = drawn(browser, met_pages["all"], 25.0)
    box = px_box(browser, taken["polygon"], pad=2)
    where, n = changed(a, drawn(browser, met_pages["taken"], 25.0))
    assert n > 100 and within(where, box)
    x = int((box[0] + box[2]) / 2)
    y = int((box[1] + box[3]) / 2)
    assert tuple(a[y, x]) == (*TYRE, 255)


def test_the_key_names_what_the_run_met_in_the_gif_s_words(browser, met_pages, page, doc,
                                                           disturbed_doc):
    from lotsim.render.animation import GifRenderer

    gif = GifRenderer(disturbed_doc, GifSettings(size=(800, 600)))
    key = page_key(met_pages["all"].read_text())
    assert [k for k, _ in key] == list(gif.legend_boxes)
    assert [k for k, _ in key][-3:] == ["stalled", "closed", "bay taken"]
    parts = {label: p for label, p in key}
    assert ("ring", rgb_hex(WHITE)) in parts["stalled"] and ("halo", rgb_hex(INK)) in \
        parts["stalled"]
    assert ("outline", rgb_hex(CLOSED)) in parts["closed"]
    assert ("hatch", rgb_hex(CLOSED)) in parts["closed"]
    assert parts["bay taken"] == [("body", rgb_hex(TYRE))]
    # an entry for each thing the run met, and only for those
    assert [k for k, _ in page_key(met_pages["stalls"].read_text())][-2:] == ["closed",
                                                                           "bay taken"]
    # in the browser, every entry is shown inside the window
    browser.open(met_pages["all"].as_uri())
    shown = browser.evaluate("""Array.from(document.querySelectorAll('#legend .key')).map(e => {
        const r = e.getBoundingClientRect(); return [e.dataset.key, r.left, r.top, r.right,
        r.bottom, r.width > 0 && r.height > 0]; })""")
    assert [s[0] for s in shown] == [k for k, _ in key]
    for label, left, top, right, bottom, visible in shown:
        assert visible and 0 <= left < right <= WINDOW[0] and 0 <= top < bottom <= WINDOW[1], label


def test_a_run_that_met_nothing_has_no_such_key_entries_or_marks(opened, page, doc):
    met = {"stalled", "closed", "bay taken"}
    assert not met & {k for k, _ in page_key(page.read_text())}
    assert "disturbances" not in doc
    assert replay_data(doc, HtmlSettings())["met"] == {"closures": [], "taken": [],
                                                         "stalls": []}
    keys = opened.evaluate(
        "Array.from(document.querySelectorAll('#legend .key')).map(e => e.dataset.key)")
    assert keys and not met & set(keys)
    for t in (10.0, 40.0, 70.0):
        opened.evaluate(f"lotsimReplay.setTime({t})")
        text = opened.evaluate("document.getElementById('counts').textContent")
        assert "stalled" not in text and "closed" not in text
