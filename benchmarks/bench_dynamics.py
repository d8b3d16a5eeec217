"""How real the planned motion is: steering rate, lateral acceleration, acceleration and jerk
of every car of every shipped scenario, measured from result.json alone.

Run: ``python benchmarks/bench_dynamics.py [RESULT_JSON ...]`` — with no argument it plans
every shipped scenario (``scenarios/*.yaml``, seed as in the file) into a temporary folder.
It prints, per scenario, the largest value over all cars and the number of cars over each of
their own limits, plus the mean and max time to park and the total waiting; the ratios
``max / limit`` are machine-independent. Speeds are differentiated on samples at least
0.02 s apart (the writer rounds v to 0.1 mm/s).
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def spaced(t: np.ndarray, h: float = 0.02) -> np.ndarray:
    """Indices of samples at least ``h`` apart (the last always kept)."""
    keep, last = [0], t[0]
    for i in range(1, len(t)):
        if t[i] - last >= h:
            keep.append(i)
            last = t[i]
    if keep[-1] != len(t) - 1:
        keep[-1] = len(t) - 1
    return np.array(keep)


def car_figures(veh: dict) -> dict[str, float]:
    s, ty = veh["samples"], veh["type"]
    t = np.array(s["t"])
    if len(t) < 3:
        return {}
    v, steer = np.array(s["v"]), np.array(s["steer"])
    lateral = v * v * np.abs(np.tan(steer)) / ty["wheelbase"]
    k = spaced(t)
    tk, vk = t[k], v[k]
    rate = np.abs(np.diff(steer[k])) / np.diff(tk)
    acc = np.diff(vk) / np.diff(tk)
    jerk = 2 * np.diff(acc) / (tk[2:] - tk[:-2])
    return {"steer_rate": float(rate.max(initial=0)), "lateral": float(lateral.max()),
            "accel": float(np.abs(acc).max(initial=0)), "jerk": float(np.abs(jerk).max(initial=0)),
            # results written before the limits were recorded: the defaults
            "lim_steer_rate": ty.get("max_steer_rate", np.radians(25)),
            "lim_lateral": ty.get("max_lateral_accel", 2.0),
            "lim_jerk": ty.get("max_jerk", 20.0)}


def summarise(name: str, data: dict) -> str:
    cars = [f for f in (car_figures(v) for v in data["vehicles"]) if f]
    m = data["metrics"]
    if not cars:
        return f"| {name} | – | – | – | – | 0 | – | – | – |"
    mx = {k: max(c[k] for c in cars) for k in ("steer_rate", "lateral", "accel", "jerk")}
    # over a limit by more than the rounding of the file allows (steer to 1 µrad, v to
    # 0.1 mm/s, differentiated over at least 0.02 s)
    over = sum(1 for c in cars if c["steer_rate"] > c["lim_steer_rate"] + 1e-3
               or c["lateral"] > c["lim_lateral"] + 1e-3 or c["jerk"] > c["lim_jerk"] + 0.6)
    return (f"| {name} | {np.degrees(mx['steer_rate']):.0f} | {mx['lateral']:.2f} | "
            f"{mx['accel']:.2f} | {mx['jerk']:.0f} | {len(cars)} ({over} over) | "
            f"{m['mean_time_to_park']:.1f} | {m['max_time_to_park']:.1f} | "
            f"{m['total_waiting']:.0f} |")


def main(argv: list[str]) -> int:
    print("| scenario | max steer rate [°/s] | max lateral [m/s²] | max accel [m/s²] | "
          "max jerk [m/s³] | cars moving (over a limit) | mean park [s] | max park [s] | "
          "total waiting [s] |")
    print("|---|---|---|---|---|---|---|---|---|")
    if argv:
        for path in argv:
            print(summarise(Path(path).parent.name, json.loads(Path(path).read_text())))
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        for scenario in sorted((ROOT / "scenarios").glob("*.yaml")):
            out = Path(tmp) / scenario.stem
            subprocess.run([sys.executable, "-m", "lotsim", "run", str(scenario), "-o", str(out),
                            "--no-gif"], check=False, capture_output=True)
            result = out / "result.json"
            if result.exists():
                print(summarise(scenario.stem, json.loads(result.read_text())))
            else:
                print(f"| {scenario.stem} | (run failed) |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
