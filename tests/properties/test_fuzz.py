"""A fuzzer for scenario files: mutations of the shipped YAML must end in a valid scenario
or a clean ``path:line:col:`` error — never another exception, a hang, or a written file.

Two fuzzers share the mutations:

* reading: each mutant is read and built as ``lotsim validate`` does, without planning
  maneuvers (that is what takes seconds; the slow profile plans them for a sample), each
  distinct lot built once (most valid mutants changed only the traffic or the animation);
  :data:`QUICK` mutants by default, :data:`SLOW` with ``pytest -m slow``;
* running: each mutant goes through ``lotsim run`` itself, which must exit 0 or 1 with a
  result.json that passes ``lotsim check`` (and a whole GIF when one is asked for), or exit
  2 with one located line and nothing in the output folder; :data:`QUICK_RUN` mutants by
  default, :data:`SLOW_RUN` with ``pytest -m slow``.
"""

from __future__ import annotations

import dataclasses
import json
import re

import numpy as np
import pytest
from PIL import Image

from conftest import ROOT, time_limit
from lotsim.cli import main
from lotsim.errors import ScenarioError
from lotsim.io.scenario_yaml import load_scenario
from lotsim.scenario import GifSettings
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.running import check_traffic
from lotsim.traffic.demand import arrivals
from lotsim.verify import check_result

FILES = ("quickstart.yaml", "street.yaml", "two_rows.yaml", "mixed_lot.yaml")
QUICK = 240
SLOW = 2000
LIMIT = 20.0
"""Seconds a mutant may take to be read and built before it counts as a hang."""
QUICK_RUN = 20
SLOW_RUN = 1000
RUN_LIMIT = 120.0
"""Seconds ``lotsim run`` may take on a mutant (it is given ``--time-limit 30``)."""
GIF_FILES = ("quickstart.yaml", "street.yaml")
"""Mutants of these keep their animation section (the others run with ``--no-gif``)."""

VALUES = [
    "0", "-1", "-1e9", "1e308", "1.0e+308", "9" * 400, "-0.0", ".nan", ".NaN", ".inf", "-.inf",
    "nan", "inf", "1e3", "012", "0x1F", "yes", "no", "on", "null", "~", "''", '""', "[]", "{}",
    "[1, 2]", "[[1, 2], [3, 4]]", "{a: 1}", "x" * 5000, "é€𝄞", "'quoted'",
    "!!python/object:os.system ls",
    "!!binary aGVsbG8=", "&a 1", "*a", "? complex", "- item", "|", ">", "%YAML 1.1", "@", "`",
    "\t1", "1:2", "[" * 200 + "]" * 200, "{" * 60 + "}" * 60, "2.5.5", "1_000", "+5", "true",
]
GARBAGE = [
    "garbage", ":", "- - -", "key: [unclosed", "key: {unclosed", "\t- tab", "---", "...",
    "&anchor", "*alias", "!!python/name:os.system", "? ", "!!str", "a: b: c", "\x00",
    "x: " + "[" * 500, "deep: " + "[" * 3000 + "]" * 3000, "long: " + "y" * 200_000,
]
_SCALAR = re.compile(r"(:\s+|-\s+|\[\s*|,\s*)([^\s,\[\]{}#][^,\[\]{}#]*?)(\s*(?:[,\]}#]|$))")


def mutate(text: str, rng: np.random.Generator) -> str:
    """One to three random edits of a YAML text."""
    lines = text.split("\n")
    for _ in range(int(rng.integers(1, 4))):
        if not lines:
            lines = [""]
        k = int(rng.integers(len(lines)))
        op = int(rng.integers(7))
        if op == 0:  # delete a line
            del lines[k]
        elif op == 1:  # duplicate a line
            lines.insert(k, lines[k])
        elif op == 2:  # swap two lines
            j = int(rng.integers(len(lines)))
            lines[k], lines[j] = lines[j], lines[k]
        elif op == 3:  # insert garbage
            lines.insert(k, GARBAGE[int(rng.integers(len(GARBAGE)))])
        elif op in (4, 5):  # replace a scalar value
            hits = list(_SCALAR.finditer(lines[k]))
            if hits:
                m = hits[int(rng.integers(len(hits)))]
                new = VALUES[int(rng.integers(len(VALUES)))]
                lines[k] = lines[k][: m.start(2)] + new + lines[k][m.end(2):]
        else:  # change the indentation of a line
            lines[k] = " " * int(rng.integers(0, 9)) + lines[k].lstrip()
    return "\n".join(lines)


def outcome(path, *, maneuvers: bool = False, built: set | None = None) -> str:
    """``ok`` or ``error``; raises AssertionError for anything a user must never see.

    ``built`` holds the lots (with their vehicle types) built so far: a mutant that changed
    only what building does not read (its traffic, its animation) is read, and its lot not
    built a second time, since building is a function of these alone (what the on-disk
    cache keys a prepared lot by)."""
    try:
        with time_limit(LIMIT):
            sc = load_scenario(path)
            seen = repr((sc.lot, sc.vehicle_types))
            if maneuvers or built is None or seen not in built:
                lg = prepare_graph(sc, maneuvers=maneuvers)
                if built is not None:
                    built.add(seen)
            if maneuvers and sc.traffic is not None:
                check_traffic(lg, arrivals(sc.traffic, sc.seed))
    except ScenarioError as exc:
        message = str(exc)
        assert re.match(rf"{re.escape(str(path))}:\d+:\d+: ", message), message
        assert "\n" not in message.strip() or "Traceback" not in message
        return "error"
    return "ok"


def _fuzz(tmp_path, count: int, seed: int, *, maneuvers_every: int = 0) -> dict:
    texts = {name: (ROOT / "scenarios" / name).read_text() for name in FILES}
    seen = {"ok": 0, "error": 0}
    built: set = set()
    for k in range(count):
        name = FILES[k % len(FILES)]
        text = mutate(texts[name], np.random.default_rng([seed, k]))  # as in _fuzz_run
        path = tmp_path / f"m{k}.yaml"
        path.write_text(text, encoding="utf-8", errors="surrogatepass")
        try:
            full = maneuvers_every and k % maneuvers_every == 0
            seen[outcome(path, maneuvers=bool(full), built=built)] += 1
        except BaseException as exc:
            raise AssertionError(f"mutant {k} of {name} (kept at {path}): "
                                 f"{type(exc).__name__}: {exc}") from exc
        path.unlink()
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # nothing written beside them
    return seen


@pytest.mark.slow
def test_mutated_scenarios_end_in_a_scenario_or_a_located_error(tmp_path):
    seen = _fuzz(tmp_path, QUICK, seed=2026)
    assert seen["error"] > QUICK // 4 and seen["ok"] > 5  # the mutations bite, and not all


@pytest.mark.slow
def test_many_mutated_scenarios_end_in_a_scenario_or_a_located_error(tmp_path):
    seen = _fuzz(tmp_path, SLOW, seed=7, maneuvers_every=25)
    print(f"{SLOW} mutations: {seen['ok']} valid, {seen['error']} located errors")


def run_outcome(path, out, capsys, *, gif: bool) -> int:
    """``lotsim run``'s exit code on a mutant, after checking everything it wrote or said."""
    args = ["run", str(path), "-o", str(out), "--time-limit", "30"] + ([] if gif else
                                                                       ["--no-gif"])
    capsys.readouterr()
    with time_limit(RUN_LIMIT):
        code = main(args)
    err = capsys.readouterr().err
    assert "Traceback" not in err
    written = sorted(p.name for p in out.iterdir()) if out.exists() else []
    if code == 2:  # every problem of the file, each located
        assert re.fullmatch(rf"(lotsim: {re.escape(str(path))}:\d+:\d+: [^\n]+\n)+", err), err
        assert written == [], written
        return code
    assert code in (0, 1), (code, err)
    doc = json.loads((out / "result.json").read_text(encoding="utf-8"))
    report = check_result(doc)
    assert report.ok, [v.message for v in report.violations[:5]]
    assert (code == 1) == (doc["metrics"]["waiting"] > 0)
    gifs = [name for name in written if name.endswith(".gif")]
    manifest = [".lotsim-run"] if gifs else []  # lists the pictures the run wrote
    assert written == sorted(["result.json", *gifs, *manifest]), written  # no temporary file
    assert len(gifs) <= (1 if gif else 0)
    for name in gifs:
        with Image.open(out / name) as im:
            im.seek(im.n_frames - 1)  # every frame is there and decodes
            assert 1 <= im.n_frames <= GIF_CAP["max_frames"] and im.size == GIF_CAP["size"]
    return code


GIF_CAP = {"size": (160, 120), "max_frames": 40}
"""The most a mutant's GIF is drawn at: whichever animation section the mutant has (and
whichever keys the shipped file has), a GIF costs a fraction of a second. That every frame
is written and decodes is what is checked, not how it looks."""


def _capped_gifs(monkeypatch) -> None:
    import lotsim.api

    real = lotsim.api.render_gif

    def capped(doc, path, settings=None, **kw):
        settings = settings or GifSettings()
        settings = dataclasses.replace(settings, size=GIF_CAP["size"], max_frames=min(
            settings.max_frames, GIF_CAP["max_frames"]))
        return real(doc, path, settings, **kw)

    monkeypatch.setattr(lotsim.api, "render_gif", capped)


def _fuzz_run(tmp_path, capsys, count: int, seed: int) -> dict:
    texts = {name: (ROOT / "scenarios" / name).read_text() for name in FILES}
    seen = {0: 0, 1: 0, 2: 0}
    for k in range(count):
        name = FILES[k % len(FILES)]
        path = tmp_path / f"m{k}.yaml"
        # each mutant drawn from its own stream: an edit of one shipped file changes its
        # mutants, not every later file's
        rng = np.random.default_rng([seed, k])
        path.write_text(mutate(texts[name], rng), encoding="utf-8", errors="surrogatepass")
        try:
            seen[run_outcome(path, tmp_path / f"out{k}", capsys, gif=name in GIF_FILES)] += 1
        except BaseException as exc:
            raise AssertionError(f"mutant {k} of {name} (kept at {path}): "
                                 f"{type(exc).__name__}: {exc}") from exc
    return seen


@pytest.mark.slow
def test_mutated_scenarios_run_or_fail_cleanly(tmp_path, capsys, monkeypatch):
    _capped_gifs(monkeypatch)
    seen = _fuzz_run(tmp_path, capsys, QUICK_RUN, seed=11)
    assert seen[2] > QUICK_RUN // 4 and seen[0] + seen[1] >= 2


@pytest.mark.slow
def test_many_mutated_scenarios_run_or_fail_cleanly(tmp_path, capsys, monkeypatch):
    _capped_gifs(monkeypatch)
    seen = _fuzz_run(tmp_path, capsys, SLOW_RUN, seed=12)
    with capsys.disabled():
        print(f"\nlotsim run on {SLOW_RUN} mutations: {seen[0]} exit 0, {seen[1]} exit 1 "
              f"(cars left waiting), {seen[2]} located errors")
