"""lotsim.render.plots: the run timeline, the minimum slot curves, their PNGs and the CLI."""

import json
import math
import sys

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from PIL import Image

from lotsim.cli import main
from lotsim.render import plots
from lotsim.render.animation import pale
from lotsim.render.plots import (
    OUTSIDE,
    MatplotlibMissing,
    minslot_figure,
    plot_minslot,
    plot_timeline,
    save_figure,
    timeline_figure,
)

CAR = {"name": "car", "width": 1.8, "front": 3.5, "rear": 1.0, "wheelbase": 2.6}


def _vehicle(vid, arrival, status, slot, t=(), x=(), v=()):
    n = len(t)
    return {"id": vid, "type": CAR, "arrival": arrival, "status": status, "slot": slot,
            "samples": {"t": list(t), "x": list(x), "y": [1.25] * n, "theta": [0.0] * n,
                        "v": list(v), "steer": [0.0] * n,
                        "gear": [int(speed != 0) for speed in v]}}  # at rest: gear 0


def _doc(vehicles, patience=None):
    settings = {"scenario": "by-hand", "planner": "hca"}
    if patience is not None:
        settings["patience"] = patience
    return {"lot": {"slots": [{"id": "S1", "polygon": [[0, 0], [5, 0], [5, 2.5], [0, 2.5]]},
                              {"id": "S2", "polygon": [[6, 0], [11, 0], [11, 2.5], [6, 2.5]]}]},
            "vehicles": vehicles, "settings": settings}


# Listed out of arrival order; rows run ada, bob, cy, dee. Over 0..30 s:
#   ada  outside 0-2, driving 2-10, parked 10-30 (stays)
#   bob  outside 1-3, driving 3-8, parked in S2 8-20, leaving 20-30
#   cy   outside 5-15, then turned away (patience 10 s); never parks
#   dee  outside 12-30 (still waiting at the end); never parks
BY_HAND = _doc([
    _vehicle("bob", 1.0, "departed", "S2", t=[3, 8, 20, 30], x=[-10, 7, 7, 20], v=[2, 0, 0, 2]),
    _vehicle("dee", 12.0, "waiting", None),
    _vehicle("ada", 0.0, "parked", "S1", t=[2, 6, 10], x=[-10, -4, 1], v=[2, 2, 0]),
    _vehicle("cy", 5.0, "rejected", None),
], patience=10.0)
COLOURS = [(30, 110, 220), (150, 60, 200), (200, 30, 30), (30, 150, 60)]  # bob, dee, ada, cy
ROW = {"ada": 0, "bob": 1, "cy": 2, "dee": 3}


def _pixels(fig, path):
    """The saved PNG as an (H, W, 3) array and a function from data (t, row) to its pixel."""
    with Image.open(path) as img:
        assert img.format == "PNG"
        rgb = np.asarray(img.convert("RGB"))
    assert rgb.shape[:2] == (round(fig.bbox.height), round(fig.bbox.width))
    ax = fig.axes[0]

    def at(t, row):
        x, y = ax.transData.transform((t, row))
        return tuple(int(c) for c in rgb[rgb.shape[0] - 1 - int(y), int(x)])

    return rgb, at


def _has(rgb, colour):
    return bool(np.all(rgb == np.asarray(colour, dtype=np.uint8), axis=-1).any())


def test_timeline_bars_have_each_phase_colour_in_arrival_order(tmp_path):
    path = tmp_path / "timeline.png"
    fig = plot_timeline(BY_HAND, path, colours=COLOURS)
    rgb, at = _pixels(fig, path)
    ada, bob, cy, dee = COLOURS[2], COLOURS[0], COLOURS[3], COLOURS[1]
    assert at(5, ROW["ada"]) == ada  # driving
    assert at(20, ROW["ada"]) == pale(ada)  # parked until the end
    assert at(2.0, ROW["bob"]) == OUTSIDE
    assert at(14, ROW["bob"]) == pale(bob)  # stands in S2
    assert at(25, ROW["bob"]) == bob  # leaving
    assert at(10, ROW["cy"]) == OUTSIDE
    assert at(22, ROW["cy"]) == (255, 255, 255)  # turned away at 15 s
    assert at(20, ROW["dee"]) == OUTSIDE
    # neither cy nor dee ever stands parked: their pale colours appear nowhere
    assert _has(rgb, pale(ada)) and _has(rgb, pale(bob))
    assert not _has(rgb, pale(cy)) and not _has(rgb, pale(dee))
    # a red cross where cy is turned away
    x, y = fig.axes[0].transData.transform((15, ROW["cy"]))
    box = rgb[rgb.shape[0] - 1 - int(y) - 4:rgb.shape[0] - int(y) + 4, int(x) - 4:int(x) + 5]
    red = (box[..., 0] > 180) & (box[..., 1] < 90) & (box[..., 2] < 90)
    assert red.any()


def test_timeline_axes_title_and_labels():
    fig = timeline_figure(BY_HAND, colours=COLOURS)
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_yticklabels()] == ["ada", "bob", "cy", "dee"]
    assert ax.get_xlabel() == "run time [s]"
    assert ax.get_title() == "by-hand: 4 vehicles, planner hca"
    assert ax.get_ylim()[0] > ax.get_ylim()[1]  # first arrival at the top
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[0] == "waiting outside" and labels[-1] == "turned away"
    assert 4.0 <= fig.get_figheight() <= 14.0


def test_long_crowded_runs_are_in_minutes_without_row_labels():
    vehicles = [_vehicle(f"w{k}", 15.0 * k, "waiting", None) for k in range(80)]
    fig = timeline_figure(_doc(vehicles))
    ax = fig.axes[0]
    assert ax.get_xlabel() == "run time [min]"
    lo, hi = ax.get_xlim()
    assert lo < 0 < 19.75 < hi < 21  # the last arrival at 1185 s = 19.75 min
    assert ax.get_yticklabels() == [] and ax.get_ylabel() == "vehicles (in arrival order)"
    assert fig.get_figheight() == 14.0


def test_timeline_needs_one_colour_per_vehicle():
    with pytest.raises(ValueError, match="one colour per vehicle"):
        timeline_figure(BY_HAND, colours=COLOURS[:3])


@pytest.fixture(scope="module")
def quickstart_doc():
    from conftest import ROOT
    from lotsim.io.result import result_dict
    from lotsim.io.scenario_yaml import load_scenario
    from lotsim.sim.running import simulate
    from lotsim.sim.settings import RunSettings

    rr = simulate(load_scenario(ROOT / "scenarios" / "quickstart.yaml"), RunSettings())
    return json.loads(json.dumps(result_dict(rr)))  # as read back from result.json


def test_timeline_of_a_run_uses_the_gif_colours(quickstart_doc, tmp_path):
    from lotsim.render.animation import GifRenderer, GifSettings
    from lotsim.render.replay import Replay

    path = tmp_path / "run.png"
    fig = plot_timeline(quickstart_doc, path)
    _, at = _pixels(fig, path)
    gif = GifRenderer(quickstart_doc, GifSettings())
    replay = Replay(quickstart_doc)
    order = sorted(range(len(replay.tracks)), key=lambda j: (replay.tracks[j].arrival, j))
    parked = 0
    for row, j in enumerate(order):
        tr = replay.tracks[j]
        for name, t0, t1 in tr.phases(replay.end):
            if name in ("driving", "parked") and t1 - t0 > 2.0:
                assert at((t0 + t1) / 2, row) == gif.vehicle_rgb(j, parked=name == "parked")
                parked += name == "parked"
    assert parked >= 3


@pytest.mark.slow
def test_a_timeline_of_1000_vehicles_is_one_collection_of_bars(quickstart_doc):
    base = quickstart_doc["vehicles"]
    vehicles = []
    for k in range(1000):
        v = json.loads(json.dumps(base[k % len(base)]))
        shift = 30.0 * (k // len(base))
        v["id"], v["arrival"] = f"v{k}", v["arrival"] + shift
        v["samples"]["t"] = [t + shift for t in v["samples"]["t"]]
        vehicles.append(v)
    ax = timeline_figure(dict(quickstart_doc, vehicles=vehicles)).axes[0]
    few = timeline_figure(quickstart_doc).axes[0]
    # as many artists for 1000 vehicles as for 6: every bar in one collection, which is
    # what keeps a long run quick to draw (its time is measured by benchmarks/bench_pictures.py)
    assert (len(ax.collections), len(ax.patches), len(ax.lines)) == (
        len(few.collections), len(few.patches), len(few.lines))
    bars = ax.collections[0].get_paths()
    rows = {float(np.mean(path.vertices[:4, 1])) for path in bars}
    assert rows == {float(k) for k in range(1000)}  # every vehicle has its bars
    assert ax.figure.get_figheight() == 14.0


def test_minslot_lines_are_the_lengths_against_changes(tmp_path):
    docs = [
        {"car": "zoe", "width": 2.5, "rows": [{"changes": 0, "length": None},
                                              {"changes": 1, "length": 6.1},
                                              {"changes": 2, "length": 5.4},
                                              {"changes": 3, "length": 5.05}]},
        {"car": "zoe", "width": 2.2, "rows": [{"changes": 0, "length": 6.6},
                                              {"changes": 1, "length": 6.3}]},
        {"car": "msv", "width": 1.5, "rows": [{"changes": 0, "length": None}]},
    ]
    path = tmp_path / "minslot.png"
    fig = plot_minslot(docs, path)
    with Image.open(path) as img:
        assert img.format == "PNG"
    ax = fig.axes[0]
    got = {ln.get_label(): (list(ln.get_xdata()), list(ln.get_ydata())) for ln in ax.lines}
    assert got == {"zoe, 2.5 m slot": ([1, 2, 3], [6.1, 5.4, 5.05]),
                   "zoe, 2.2 m slot": ([0, 1], [6.6, 6.3])}
    assert ax.get_xlabel() == "direction changes"
    assert ax.get_ylabel() == "minimum slot length [m]"
    ticks = [t for t in ax.get_xticks() if ax.get_xlim()[0] <= t <= ax.get_xlim()[1]]
    assert ticks and all(float(t).is_integer() for t in ticks)


def test_save_figure_leaves_nothing_behind_when_it_fails(tmp_path):
    (tmp_path / "taken.png").mkdir()  # a directory cannot be replaced by a file
    with pytest.raises(OSError):
        save_figure(minslot_figure([]), tmp_path / "taken.png")
    with pytest.raises(FileNotFoundError):
        save_figure(minslot_figure([]), tmp_path / "missing" / "out.png")
    assert [p.name for p in tmp_path.iterdir()] == ["taken.png"]
    assert list((tmp_path / "taken.png").iterdir()) == []


MINSLOT = ["minslot", "--car", "zoe", "--width", "2.2", "2.5", "--max-changes", "3",
           "--step-deg", "0.5", "--resolution", "0.05"]


def test_cli_plots_one_curve_per_width(tmp_path, capsys, monkeypatch):
    drawn = []

    def spy(docs, path):
        drawn.append(real(docs, path))
        return drawn[-1]

    real = plots.plot_minslot
    monkeypatch.setattr(plots, "plot_minslot", spy)
    out = tmp_path / "out.png"
    assert main([*MINSLOT, "--json", "--plot", str(out)]) == 0
    captured = capsys.readouterr()
    docs = json.loads(captured.out)  # "wrote" goes to stderr beside JSON
    assert f"wrote {out}" in captured.err
    assert [(d["car"], d["width"]) for d in docs] == [("zoe", 2.2), ("zoe", 2.5)]
    with Image.open(out) as img:
        assert img.format == "PNG"
    lines = drawn[0].axes[0].lines
    assert [ln.get_label() for ln in lines] == ["zoe, 2.2 m slot", "zoe, 2.5 m slot"]
    for ln, doc in zip(lines, docs, strict=True):
        assert list(ln.get_ydata()) == [r["length"] for r in doc["rows"]]
        assert list(ln.get_xdata()) == [0, 1, 2, 3]
    assert [p.name for p in tmp_path.iterdir()] == ["out.png"]


@pytest.mark.parametrize("where", ["missing/out.png", "taken.png"])
def test_cli_cannot_write_the_plot(tmp_path, capsys, where):
    (tmp_path / "taken.png").mkdir()
    target = tmp_path / where
    assert main([*MINSLOT, "--plot", str(target)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"lotsim: {target}: cannot write: ")
    assert [p.name for p in tmp_path.iterdir()] == ["taken.png"]
    assert list((tmp_path / "taken.png").iterdir()) == []


def test_without_matplotlib_the_cli_says_how_to_get_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)

    def sweep(*args, **kwargs):
        raise AssertionError("the sweep ran before matplotlib was looked for")

    monkeypatch.setattr("lotsim.maneuvers.minslot.min_slot_lengths", sweep)
    assert main([*MINSLOT, "--plot", str(tmp_path / "out.png")]) == 2
    err = capsys.readouterr().err
    assert err == "lotsim: --plot needs matplotlib: pip install 'lotsim[plot]'\n"
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(MatplotlibMissing, match=r"pip install 'lotsim\[plot\]'"):
        timeline_figure(BY_HAND)
    with pytest.raises(ImportError):  # what callers of an optional extra catch
        minslot_figure([])


def test_row_heights_stay_finite_without_vehicles():
    fig = timeline_figure(_doc([]))
    assert fig.get_figheight() == 4.0 and math.isfinite(fig.axes[0].get_xlim()[1])
