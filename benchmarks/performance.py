"""lotsim's performance in one command: writes ``docs/performance.md``.

Run from the repository root::

    python benchmarks/performance.py            # every row, 2 runs each (about 40 minutes
                                                # on 2 cores)
    python benchmarks/performance.py --quick    # 1 run each; no 364-bay lot, no 1000 cars,
                                                # no real-demand suite (a few minutes on a
                                                # quiet machine)
    python benchmarks/performance.py --runs 3 -o /tmp/perf.md

Every figure is measured by running a ``lotsim`` command as a process, as a user runs it,
and each row of the page names that command. Rows:

* where users wait: ``lotsim validate`` of the large lot (1040 slots), of the 364-bay lot
  and of a generated 5000-bay grid (not in ``--quick``), cold (empty cache: the lot is
  prepared) and warm (loaded from the on-disk cache), and of the 364-bay lot again after
  shortening one of its rows;
  ``lotsim run`` of the large lot's 100 cars; 1000 cars arriving at 1200 an hour and
  staying 10-30 minutes, and ``lotsim check`` of their result; the minimum-slot table of
  every catalogue car; ``lotsim validate`` of the lots of an OpenStreetMap extract one
  after another, two at once and on a local Dask cluster of one and two workers, and
  ``lotsim layout`` of the 100 x 60 m example plot and of a 1 ha square, cold (not in
  ``--quick``);
* the shipped suites (``scenarios/bench/*.yaml``): the wall time of ``lotsim bench`` with
  two workers, and the comparisons they exist for, read from their ``runs.csv``: the
  planners (CA*, HCA*, WHCA*) and the slot assignments (shortest, nearest) head to head,
  the priority orders (arrival, shortest first, the genetic algorithm), the large lot's
  load sweep;
* traffic at real demand (``scenarios/bench/real_demand.yaml``, run once, its lots
  prepared first; not in ``--quick``): what the cars of three one-gate lots pay at 200 to
  700 arrivals an hour with each slot choice;
* runs that meet the real world (``scenarios/bench/faults.yaml``, run once, not in
  ``--quick``): the two 364-bay lots at 350 arrivals an hour driven through late starts,
  stalls and a closed aisle, against the same runs driven as planned;
* a day at a real lot (``benchmarks/bench_day.py``, not in ``--quick``): 3000 cars over 12
  hours through the 364-bay one-gate lot, its figures against their targets;
* the learning environment's decisions per second (``benchmarks/bench_envs.py``, when the
  ``learn`` extra is installed).

For each figure the page gives how many values it is made of and their spread (min /
median / max): repeated runs of a timing, or the seeds (and scenarios, assignments) of a
suite's outcome, which do not change from one run to the next. The page states the commit,
date and machine (cores, CPU, Python and library versions). Times depend on the machine
and on what else runs on it; compare ratios between rows of one page.
"""

from __future__ import annotations

import argparse
import datetime
import importlib.metadata
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
LOTSIM = (sys.executable, "-m", "lotsim")
LARGE = "scenarios/large_lot.yaml"
SURFACE = "scenarios/lots/surface364.yaml"
SUITES = ("valet", "head_to_head", "priority", "large_lot_load")
BIG = {"count": 1000, "rate_per_hour": 1200, "dwell": [600, 1800], "seed": 11}
"""The 1000-car traffic on the large lot: arrivals, departures and queues at once."""
PLANNING = re.compile(r"planning ([\d.]+) s \((\d+) searches, (\d+) expansions; per vehicle "
                      r"median (\d+) ms, p95 (\d+) ms\)")


# --- running and summarising ------------------------------------------------------------

def process(*args: str, env: dict | None = None) -> tuple[float, float, int, str]:
    """Run ``args`` in the repository root; its wall time [s], peak memory [MB], exit code
    and output."""
    t = time.perf_counter()
    proc = subprocess.Popen(args, cwd=ROOT, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    code = os.waitstatus_to_exitcode(status)
    return time.perf_counter() - t, usage.ru_maxrss / 1024, code, out


def environment(cache: str) -> dict:
    """The environment of a measured process: its own cache folder, and Python keeping the
    modules it compiles (as after ``pip install``)."""
    env = {**os.environ, "LOTSIM_CACHE_DIR": cache}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    return env


def spread(values: list[float], fmt: str = "{:.2f}") -> str:
    """``min / median / max`` of ``values`` (one value alone as itself)."""
    if not values:
        return "—"
    if len(values) == 1:
        return fmt.format(values[0])
    return " / ".join(fmt.format(v) for v in (min(values), statistics.median(values),
                                              max(values)))


class Page:
    """The rows of docs/performance.md, kept as they are measured."""

    def __init__(self) -> None:
        self.sections: list[tuple[str, str, list[str]]] = []

    def section(self, title: str, text: str, header: str) -> None:
        cols = header.count("|") - 1
        self.sections.append((title, text, [header, "|" + "---|" * cols]))
        print(f"\n## {title}", flush=True)

    def row(self, *cells: object) -> None:
        line = "| " + " | ".join(str(c) for c in cells) + " |"
        self.sections[-1][2].append(line)
        print(line, flush=True)


# --- where users wait -----------------------------------------------------------------

def validate_rows(page: Page, runs: int, lots: list[tuple[str, str]], tmp: Path) -> None:
    page.section("Where users wait",
                 "Wall time of each command as a process (Python's start included). *Cold*: "
                 "an empty cache, the lot is prepared (its maneuvers, turns and graph); "
                 "*warm*: the same command again, the prepared lot loaded from the cache; "
                 "*after an edit*: the lot with one row a bay shorter, validated after the "
                 "lot as it was (its maneuvers and the pieces of its roadmap are remembered "
                 "by the scenario's name: what the edit reached is planned again).",
                 "| what | command | runs | min / median / max |")
    for name, path in lots:
        cold, warm, edited = [], [], []
        shorter = _one_row_shorter(path, tmp) if path == SURFACE else None
        for _ in range(runs):
            with tempfile.TemporaryDirectory() as cache:
                env = environment(cache)
                cold.append(checked(process(*LOTSIM, "validate", path, env=env))[0])
                warm.append(checked(process(*LOTSIM, "validate", path, env=env))[0])
                if shorter is not None:
                    edited.append(checked(process(*LOTSIM, "validate", shorter,
                                                  env=env))[0])
        cmd = f"`LOTSIM_CACHE_DIR=$(mktemp -d) lotsim validate {path}`"
        if Path(path).parent == tmp:  # generated here
            cmd = (f"`{Path(path).name}` as `bench_scaling.py`'s `grid_lot(25, 100)` writes "
                   f"it, then `LOTSIM_CACHE_DIR=$(mktemp -d) lotsim validate "
                   f"{Path(path).name}`")
        page.row(f"validate {name}, cold", cmd, runs, spread(cold) + " s")
        page.row(f"validate {name}, warm", "the same again", runs, spread(warm) + " s")
        if shorter is not None:
            page.row(f"validate {name} after an edit", "then the lot with its row "
                     f"`{EDITED_ROW}` a bay shorter", runs, spread(edited) + " s")


EDITED_ROW = "A1SE-"
"""The row of the 364-bay lot that the edit row shortens by one bay."""


def _one_row_shorter(path: str, tmp: Path) -> str:
    """A copy of the lot at ``path`` (same name) with its row :data:`EDITED_ROW` one bay
    shorter."""
    doc = yaml.safe_load((ROOT / path).read_text(encoding="utf-8"))
    row = next(r for r in doc["lot"]["rows"] if r.get("id_prefix") == EDITED_ROW)
    row["count"] -= 1
    out = tmp / "surface364_edited.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return str(out)


def _grid_5000(tmp: Path) -> str:
    """The generated 5000-bay regular lot of ``benchmarks/bench_scaling.py``, written to
    ``tmp``."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from bench_scaling import LOTS, grid_lot

    out = tmp / "grid5000.yaml"
    out.write_text(grid_lot(*LOTS[5000]), encoding="utf-8")
    return str(out)


def checked(measured: tuple[float, float, int, str], ok: tuple[int, ...] = (0,)):
    if measured[2] not in ok:
        raise SystemExit(f"a measured command failed (exit {measured[2]}):\n{measured[3]}")
    return measured


def run_rows(page: Page, runs: int, big: bool, cache: str, tmp: Path) -> None:
    env = environment(cache)
    checked(process(*LOTSIM, "validate", LARGE, env=env), (0, 1))  # prepared once, kept
    cases = [("100 cars in ten minutes, large lot, HCA*", LARGE)]
    if big:
        doc = yaml.safe_load((ROOT / LARGE).read_text(encoding="utf-8"))
        doc["traffic"] = {"stream": dict(BIG), "patience": 900}
        doc["name"] = "large-lot-1000"
        path = tmp / "large_lot_1000.yaml"
        path.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
        cases.append(("1000 cars at 1200/h staying 10–30 min, large lot, HCA*", str(path)))
    for what, path in cases:
        walls, plans, p95s, peaks = [], [], [], []
        for i in range(runs):
            out = tmp / f"run{i}"
            wall, peak, _, text = checked(process(*LOTSIM, "run", path, "-o", str(out),
                                                  "--no-gif", env=env), (0, 1))
            m = PLANNING.search(text)
            walls.append(wall)
            peaks.append(peak)
            if m:
                plans.append(float(m.group(1)))
                p95s.append(float(m.group(5)))
        shown = LARGE if path == LARGE else "the large lot, traffic " + ", ".join(
            f"{k} {v}" for k, v in BIG.items())
        cmd = f"`lotsim run {shown} --no-gif`" if path == LARGE else f"`lotsim run` of {shown}"
        page.row(f"{what}: planning", cmd + " (prints it)", runs, spread(plans) + " s")
        page.row(f"{what}: per car p95", "the same", runs, spread(p95s, "{:.0f}") + " ms")
        page.row(f"{what}: whole command", "the same (lot prepared before)", runs,
                 spread(walls) + " s")
        page.row(f"{what}: peak memory", "the same", runs, spread(peaks, "{:.0f}") + " MB")
        if path != LARGE:
            walls, peaks = [], []
            for _ in range(runs):
                wall, peak, _, _ = checked(process(*LOTSIM, "check",
                                                   str(tmp / "run0" / "result.json"), env=env))
                walls.append(wall)
                peaks.append(peak)
            page.row("`lotsim check` of the 1000 cars' result", "`lotsim check result.json`",
                     runs, f"{spread(walls)} s, peak {spread(peaks, '{:.0f}')} MB")


def many_rows(page: Page, runs: int) -> None:
    """``lotsim validate`` of every lot of the OpenStreetMap test extract: one after
    another, ``--jobs 2``, and on a local Dask cluster of one and two workers."""
    from bench_validate_many import DEFAULT_SOURCE, measure

    lots, times = measure(DEFAULT_SOURCE, runs)
    serial = statistics.median(times["one after another"])
    source = DEFAULT_SOURCE.relative_to(ROOT)
    for how, ts in times.items():
        ratio = statistics.median(ts) / serial
        page.row(f"validate the {lots} lots of {source}, {how}, cold",
                 f"`python benchmarks/bench_validate_many.py` ({ratio:.2f} × one after "
                 "another)", runs, spread(ts) + " s")


def minslot_row(page: Page, runs: int) -> None:
    args = ("minslot", "--all-vehicles", "--width", "2.2", "2.5", "2.8", "--max-changes", "10")
    walls = [checked(process(*LOTSIM, *args))[0] for _ in range(runs)]
    page.row("minimum-slot table: 7 cars × 3 widths × 0–10 direction changes",
             "`lotsim " + " ".join(args) + "`", runs, spread(walls) + " s")


def layout_rows(page: Page, runs: int, tmp: Path) -> None:
    """``lotsim layout`` of the 100 x 60 m example plot and of a 1 ha square, cold."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from bench_layout import HECTARE

    square = tmp / "hectare.yaml"
    square.write_text(HECTARE, encoding="utf-8")
    for what, plot, cmd in (
            ("the 100 × 60 m example plot", "scenarios/plots/rect60x100.yaml",
             "`LOTSIM_CACHE_DIR=$(mktemp -d) lotsim layout scenarios/plots/rect60x100.yaml "
             "-o lot.yaml`"),
            ("a 1 ha square, one gate", str(square),
             "`python benchmarks/bench_layout.py`'s 1 ha square, as the row above")):
        walls = []
        for _ in range(runs):
            with tempfile.TemporaryDirectory() as cache:
                walls.append(checked(process(*LOTSIM, "layout", plot, "-o",
                                             str(tmp / "lot.yaml"),
                                             env=environment(cache)))[0])
        page.row(f"lay out {what}, cold", cmd, runs, spread(walls) + " s")


# --- the suites -------------------------------------------------------------------------

def suite_rows(page: Page, runs: int, tmp: Path) -> dict[str, list[list[dict]]]:
    """Run every shipped suite ``runs`` times; its rows of each run, by suite."""
    sys.path.insert(0, str(ROOT))
    from lotsim.bench import read_csv

    page.section("Benchmark suites",
                 "Wall time of `lotsim bench scenarios/bench/SUITE.yaml --jobs 2` (every lot "
                 "prepared from the on-disk cache, every result checked).",
                 "| suite | runs in the suite | times run | wall time min / median / max |")
    found: dict[str, list[list[dict]]] = {}
    with tempfile.TemporaryDirectory() as cache:
        env = environment(cache)
        for name in SUITES:
            path = f"scenarios/bench/{name}.yaml"
            walls = []
            for i in range(runs + 1):  # the first prepares the lots into the cache
                out = tmp / f"{name}{i}"
                wall, _, _, _ = checked(process(*LOTSIM, "bench", path, "-o", str(out),
                                                "--jobs", "2", env=env))
                if i:
                    walls.append(wall)
                    found.setdefault(name, []).append(read_csv(out / "runs.csv"))
            summary = (tmp / f"{name}1" / "summary.md").read_text(encoding="utf-8")
            found[name].append([{"summary": summary}])
            page.row(f"`{name}`", len(found[name][0]), runs, spread(walls, "{:.1f}") + " s")
    return found


def label(r: dict) -> str:
    return r["planner"] + (f"-{r['window_s']:g}" if r.get("window_s") else "")


def planners_section(page: Page, runs: list[list[dict]]) -> None:
    rows = [r for one in runs[:-1] for r in one]
    page.section("Planners head to head",
                 "`lotsim bench scenarios/bench/head_to_head.yaml`: each scenario's own "
                 "traffic, 3 seeds × 2 assignments per planner. Time to park and expansions "
                 "do not change from run to run (spread over the 6 runs of the grid); "
                 "planning time spreads over those and the times the suite was run.",
                 "| scenario | planner | mean time to park [s] | expansions per run | "
                 "planning per run [s] |")
    for scen in dict.fromkeys(r["scenario"] for r in rows):
        for plan in dict.fromkeys(label(r) for r in rows):
            g = [r for r in rows if r["scenario"] == scen and label(r) == plan]
            once = g[:len(g) // (len(runs) - 1)]
            page.row(scen, plan, spread([r["mean_time_to_park_s"] for r in once], "{:.1f}"),
                     spread([r["expansions"] for r in once], "{:.0f}"),
                     spread([r["planning_time_s"] for r in g], "{:.2f}"))
    page.section("Slot assignment",
                 "The same suite: `shortest` (least travel plus maneuver time) against "
                 "`nearest` (least straight-line distance), over 5 planners × 3 seeds.",
                 "| scenario | assignment | mean time to park [s] | max time to park [s] |")
    once = runs[0]
    for scen in dict.fromkeys(r["scenario"] for r in once):
        for asg in ("shortest", "nearest"):
            g = [r for r in once if r["scenario"] == scen and r["assignment"] == asg]
            page.row(scen, asg, spread([r["mean_time_to_park_s"] for r in g], "{:.1f}"),
                     spread([r["max_time_to_park_s"] for r in g], "{:.1f}"))


def priority_section(page: Page, runs: list[list[dict]]) -> None:
    once = runs[0]
    page.section("Priority orders",
                 "`lotsim bench scenarios/bench/priority.yaml`, HCA\\*, 3 seeds: the total "
                 "time to park of all cars (`fitness_s`). `arrival` plans each car as it "
                 "arrives; `shortest_first` and `ga` book the traffic a minute ahead. The "
                 "GA's gain is against arrival order booked the same way in the same run "
                 "(`ga_arrival_fitness_s`); negative is worse.",
                 "| scenario | arrival [s] | shortest first [s] | GA [s] | GA's gain [%] | "
                 "orders planned | ordering time [s] |")
    for scen in dict.fromkeys(r["scenario"] for r in once):
        by = {p: [r for r in once if r["scenario"] == scen and r["priority"] == p]
              for p in ("arrival", "shortest_first", "ga")}
        gains = [100 * (1 - r["fitness_s"] / r["ga_arrival_fitness_s"]) for r in by["ga"]]
        times = [r["order_time_s"] for one in runs[:-1] for r in one
                 if r["scenario"] == scen and r["priority"] == "ga"]
        page.row(scen, *(spread([r["fitness_s"] for r in by[p]], "{:.1f}") for p in by),
                 spread(gains, "{:+.1f}"),
                 spread([r["evaluations"] for r in by["ga"]], "{:.0f}"),
                 spread(times, "{:.1f}"))


def load_section(page: Page, runs: list[list[dict]]) -> None:
    once = runs[0]
    summary = runs[-1][0]["summary"]
    knee = re.findall(r"keeps up[^|\n]*|saturated[^|\n]*", summary)
    page.section("Load on the large lot",
                 "`lotsim bench scenarios/bench/large_lot_load.yaml`: 150 cars that stay, "
                 "HCA\\*, 2 seeds per rate. The suite's summary says: "
                 + ("; ".join(dict.fromkeys(k.strip() for k in knee)) or "no saturation found")
                 + ".",
                 "| arrival rate [veh/h] | throughput [veh/h] | mean time to park [s] | "
                 "total waiting [s] |")
    for rate in dict.fromkeys(r["rate_per_h"] for r in once):
        g = [r for r in once if r["rate_per_h"] == rate]
        page.row(f"{rate:g}", spread([r["throughput_per_h"] for r in g], "{:.0f}"),
                 spread([r["mean_time_to_park_s"] for r in g], "{:.1f}"),
                 spread([r["total_waiting_s"] for r in g], "{:.0f}"))


def valet_section(page: Page, runs: list[list[dict]]) -> None:
    once = runs[0]
    page.section("The valet setting",
                 "`lotsim bench scenarios/bench/valet.yaml`: 30 cars within an hour on the "
                 "mixed lot, 3 seeds per planner.",
                 "| planner | mean time to park [s] | expansions per run | planning p95 per "
                 "car [ms] |")
    for plan in dict.fromkeys(label(r) for r in once):
        g = [r for r in once if label(r) == plan]
        allg = [r for one in runs[:-1] for r in one if label(r) == plan]
        page.row(plan, spread([r["mean_time_to_park_s"] for r in g], "{:.1f}"),
                 spread([r["expansions"] for r in g], "{:.0f}"),
                 spread([r["planning_p95_ms"] for r in allg], "{:.0f}"))


FAULTS = "scenarios/bench/faults.yaml"
REAL_DEMAND = "scenarios/bench/real_demand.yaml"


def real_demand_rows(page: Page, tmp: Path) -> None:
    """The real-demand suite, run once after its lots are prepared into the cache."""
    sys.path.insert(0, str(ROOT))
    from lotsim.bench import read_csv

    suite = yaml.safe_load((ROOT / REAL_DEMAND).read_text(encoding="utf-8"))
    with tempfile.TemporaryDirectory() as cache:
        env = environment(cache)
        for lot in suite["scenarios"]:
            checked(process(*LOTSIM, "validate", str(Path(REAL_DEMAND).parent / lot),
                            env=env), (0, 1))
        out = tmp / "real_demand"
        wall, _, _, _ = checked(process(*LOTSIM, "bench", REAL_DEMAND, "-o", str(out),
                                        "--jobs", "2", env=env))
        rows = read_csv(out / "runs.csv")
        summary = (out / "summary.md").read_text(encoding="utf-8")
    seeds = len(suite["seeds"])
    knee = re.findall(r"\n\s*[-*]?\s*([^\n]*(?:keeps up|saturated)[^\n]*)", summary)
    page.section("Traffic at real demand",
                 rf"`lotsim bench {REAL_DEMAND} --jobs 2` ({wall / 60:.0f} min, HCA\*): 100 "
                 "cars staying 5 to 15 minutes at each rate, through the one gate of three "
                 "lots, each slot chosen by its static time (`shortest`) or by that time "
                 "plus the delay it is expected to cause the others (`priced`). Each cell is "
                 f"the median over the {seeds} seeds (for two, their mean). *Standing*: per "
                 "car, queued outside / on the way in / on the way out. Every result passed "
                 "`lotsim check`. The suite's summary says: "
                 + ("; ".join(dict.fromkeys(k.strip(" -*") for k in knee))
                    or "no saturation found") + ".",
                 "| lot | assignment | rate [veh/h] | time to park median / p90 [s] | time to "
                 "leave median [s] | standing per car [s] | throughput [veh/h] | planning "
                 "[s] (median per car [ms]) | served |")
    for scen in dict.fromkeys(r["scenario"] for r in rows):
        for asg in dict.fromkeys(r["assignment"] for r in rows):
            for rate in dict.fromkeys(r["rate_per_h"] for r in rows):
                g = [r for r in rows if (r["scenario"], r["assignment"], r["rate_per_h"])
                     == (scen, asg, rate)]
                if not g:
                    continue

                def med(key: str, g=g) -> float:
                    return statistics.median(r[key] for r in g)

                page.row(scen, asg, f"{rate:g}",
                         f"{med('median_time_to_park_s'):.1f} / "
                         f"{med('p90_time_to_park_s'):.1f}",
                         f"{med('median_time_to_leave_s'):.1f}",
                         f"{med('standing_per_car_s'):.1f} "
                         f"({med('standing_outside_per_car_s'):.1f} / "
                         f"{med('standing_in_per_car_s'):.1f} / "
                         f"{med('standing_out_per_car_s'):.1f})",
                         f"{med('throughput_per_h'):.0f}",
                         f"{med('planning_time_s'):.1f} ({med('planning_median_ms'):.0f})",
                         f"{sum(r['served'] for r in g)}/{sum(r['vehicles'] for r in g)}")


def faults_rows(page: Page, tmp: Path) -> None:
    """The faults suite, run once after its lots are prepared into the cache."""
    sys.path.insert(0, str(ROOT))
    from lotsim.bench import read_csv

    suite = yaml.safe_load((ROOT / FAULTS).read_text(encoding="utf-8"))
    with tempfile.TemporaryDirectory() as cache:
        env = environment(cache)
        for lot in suite["scenarios"]:
            checked(process(*LOTSIM, "validate", str(Path(FAULTS).parent / lot), env=env),
                    (0, 1))
        out = tmp / "faults"
        wall, _, _, _ = checked(process(*LOTSIM, "bench", FAULTS, "-o", str(out),
                                        "--jobs", "2", env=env))
        rows = read_csv(out / "runs.csv")
    seeds = len(suite["seeds"])
    page.section("Runs that meet the real world",
                 rf"`lotsim bench {FAULTS} --jobs 2` ({wall / 60:.0f} min, HCA\*, "
                 "`shortest`): 100 cars at 350 an hour staying 5 to 15 minutes on each "
                 "364-bay lot, planned, then driven through each variant's disturbances "
                 "keeping the plan's order at every piece of the lot. Each cell is the "
                 f"median over the {seeds} seeds (for two, their mean); *against planned*: "
                 "the median time to park over that of the same lot and seed driven as "
                 "planned (`none`). *Violations*: what `lotsim check` found in all the "
                 "variant's runs (overlaps, limits, stalls stood through, closed ground).",
                 "| lot | disturbances | time to park median / p90 [s] | against planned | "
                 "standing per car [s] | throughput [veh/h] | late starts | stalls | "
                 "replans | served / rejected / waiting | violations |")
    for scen in dict.fromkeys(r["scenario"] for r in rows):
        base = {r["seed"]: r for r in rows
                if r["scenario"] == scen and r["disturbance"] == "none"}
        for dist in dict.fromkeys(r["disturbance"] for r in rows):
            g = [r for r in rows if (r["scenario"], r["disturbance"]) == (scen, dist)]
            if not g:
                continue

            def med(key: str, g=g) -> float:
                return statistics.median(r[key] for r in g if r[key] is not None)

            vs = statistics.median(r["median_time_to_park_s"]
                                   / base[r["seed"]]["median_time_to_park_s"]
                                   for r in g if r["seed"] in base)
            page.row(scen, dist, f"{med('median_time_to_park_s'):.1f} / "
                     f"{med('p90_time_to_park_s'):.1f}", f"{100 * (vs - 1):+.1f} %",
                     f"{med('standing_per_car_s'):.1f}", f"{med('throughput_per_h'):.0f}",
                     f"{med('late_starts'):.0f}", f"{med('stalls'):.0f}",
                     f"{med('replans'):.0f}",
                     f"{sum(r['served'] for r in g)} / {sum(r['rejected'] for r in g)} / "
                     f"{sum(r['waiting'] for r in g)}",
                     f"{sum(r['violations'] for r in g)}")


def day_rows(page: Page, runs: int, tmp: Path) -> None:
    """A day at a real lot against its targets (``benchmarks/bench_day.py``)."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import bench_day

    count, rate = 3000, 250.0
    days = [bench_day.day(count, rate, tmp, per_car=k == 0) for k in range(runs)]
    page.section("A day at a real lot",
                 f"`python benchmarks/bench_day.py --repeat {runs}`: {count} cars over "
                 f"{count / rate:.0f} h at {rate:g} an hour through `scenarios/lots/"
                 f"{bench_day.LOT}.yaml` (364 bays, a little over half taken, one gate), "
                 "each staying a lognormal 20 minutes (median; spread 0.8, 5 min to 4 h), "
                 "`lotsim run --compact --no-gif` with the default limits on the lot "
                 "prepared before, in a process of its own, and `lotsim check` of its "
                 "result. *Late / early per car*: the last full hour's mean planning per "
                 "car over the second hour's, from one run.",
                 "| figure | runs | min / median / max | target |")
    for name, (target, unit, _) in bench_day.TARGETS.items():
        xs = [d[name] for d in days if name in d]
        page.row(name, len(xs), spread(xs) + (f" {unit}" if unit else ""),
                 f"≤ {target:g} {unit}".rstrip())


ENV_LOTS = ("quickstart", "surface364", "large_lot")
"""The lots the learning environment is timed on."""


def envs_rows(page: Page, runs: int) -> None:
    """The learning environment's decisions per second (``benchmarks/bench_envs.py``),
    when the ``learn`` extra is installed."""
    rounds = max(runs, 2)
    cmd = [sys.executable, "benchmarks/bench_envs.py", "--rounds", str(rounds), "--lots",
           *ENV_LOTS]
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    table = [line for line in proc.stdout.splitlines() if line.startswith("|")]
    if proc.returncode != 0 or len(table) < 3:
        print(f"learning environments: not measured ({proc.stderr.strip()[-200:]})",
              flush=True)
        return
    page.section("Learning environments",
                 f"`python benchmarks/bench_envs.py --rounds {rounds} --lots "
                 f"{' '.join(ENV_LOTS)}` (the `learn` extra): "
                 "decisions per CPU second of `lotsim/ParkingOperator-v0` stepped by the "
                 "shortest and the random baselines and without its rankings, and of the "
                 "bare stepped run (`lotsim.Live(policy=lotsim.ASK)`) making the same "
                 f"choices; median of {rounds} rounds (min–max) over the episodes of seeds "
                 "0, 1, 2 (docs/learning.md).", table[0])
    for line in table[2:]:
        page.row(*[c.strip() for c in line.strip("|").split("|")])


# --- the page -------------------------------------------------------------------------

def machine() -> list[str]:
    cpu = platform.processor() or "?"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    libs = ", ".join(f"{n} {importlib.metadata.version(n)}"
                     for n in ("numpy", "shapely", "networkx", "PyYAML", "Pillow"))
    return [f"{os.cpu_count()} cores, {cpu}", f"{platform.system()} {platform.release()}",
            f"Python {platform.python_version()}; {libs}"]


def commit() -> str:
    def git(*a: str) -> str:
        return subprocess.run(("git", *a), cwd=ROOT, capture_output=True, text=True).stdout
    head = git("rev-parse", "--short=12", "HEAD").strip() or "unknown"
    dirty = git("status", "--porcelain", "--untracked-files=no", "lotsim").strip()
    return head + (" (with changes not committed in lotsim/)" if dirty else "")


def write(page: Page, path: Path, args: argparse.Namespace, took: float) -> None:
    mode = "quick" if args.quick else "full"
    cmd = "python benchmarks/performance.py" + (" --quick" if args.quick else "")
    cores, system, versions = machine()
    lines = [
        "# Performance",
        "",
        f"Written by `{cmd}`; do not edit by hand, run it again.",
        "Each row names the command that measures it; a figure is *min / median / max* over",
        "the runs or seeds counted beside it.",
        "",
        f"- commit: {commit()}",
        f"- date: {datetime.datetime.now().astimezone():%Y-%m-%d %H:%M %Z}",
        f"- machine: {cores}; {system}",
        f"- software: {versions}",
        f"- load average (1 min) when it started and ended: {args.load[0]:.1f}, "
        f"{os.getloadavg()[0]:.1f}",
        f"- mode: {mode}, {args.runs} run(s) of each timing; the whole command took "
        f"{took / 60:.1f} min",
        "",
        "All figures come from one machine, at the load above (this command's own work is a",
        "load of 1 to 2 on 2 cores; more means other jobs shared the machine while it measured):",
        "times on another machine (or another moment) differ; the outcomes of the suites",
        "(times to park, expansions, gains) do not, and ratios between rows of this page",
        "carry over better than seconds.",
    ]
    for title, text, table in page.sections:
        lines += ["", f"## {title}", "", text, "", *table]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    print(f"\nwrote {path}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="1 run each, no 364-bay lot, no 1000 cars, no real-demand suite")
    ap.add_argument("--runs", type=int, help="runs of each timing (default 2, quick 1)")
    ap.add_argument("-o", "--output", default=str(ROOT / "docs" / "performance.md"))
    args = ap.parse_args()
    args.runs = args.runs or (1 if args.quick else 2)
    args.load = os.getloadavg()
    started = time.perf_counter()
    page = Page()
    with tempfile.TemporaryDirectory() as tmp, tempfile.TemporaryDirectory() as cache:
        lots = [("large lot (1040 slots)", LARGE)]
        if not args.quick:
            lots += [("364-bay lot (four vehicle types)", SURFACE),
                     ("a generated 5000-bay grid", _grid_5000(Path(tmp)))]
        validate_rows(page, args.runs, lots, Path(tmp))
        run_rows(page, args.runs, not args.quick, cache, Path(tmp))
        minslot_row(page, args.runs)
        if not args.quick:
            many_rows(page, args.runs)
            layout_rows(page, args.runs, Path(tmp))
        suites = suite_rows(page, args.runs, Path(tmp))
        planners_section(page, suites["head_to_head"])
        priority_section(page, suites["priority"])
        valet_section(page, suites["valet"])
        load_section(page, suites["large_lot_load"])
        if not args.quick:
            real_demand_rows(page, Path(tmp))
            faults_rows(page, Path(tmp))
            day_rows(page, args.runs, Path(tmp))
        envs_rows(page, args.runs)
    write(page, Path(args.output), args, time.perf_counter() - started)


if __name__ == "__main__":
    main()
