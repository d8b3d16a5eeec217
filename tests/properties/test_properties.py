"""Property-based tests: random valid lots and traffic, planned and checked end to end.

A hypothesis strategy draws a scenario as YAML text, valid by construction: a rectangular
boundary holding one or two straight parallel aisles (one-way, or two-way with an entrance and
an exit at each end); beside each aisle an optional row of perpendicular, parallel or angled
slots (10° to 89.9°) on either side, sized for the catalogue cars drawn; walls along the outer
edges, between back-to-back rows and across a one-way aisle's far end; walls, obstacles and
no-go zones in the corners beside the rows; a speed bump, a lot speed limit, slots taken at
start (listed, or drawn by fraction) — the whole layout turned by a random angle — and
traffic: a stream (some cars dwell, then leave), cars listed one by one, or both, at
entrances with a free slot to go to. Each scenario is read by the YAML loader, prepared, run
with a random planner, assignment and seed (sometimes booked, in a random order), written as
``result.json`` and handed to the independent checker (``lotsim check``), which must accept
it. The test also asserts what the checker does not: every arrival is listed once, as drawn;
the slots taken at start are those ``docs/scenario.md`` defines; moving cars start at their
entrance; parked cars end inside their own slot, one per slot; a car leaves only after its
dwell; the same run gives the same file again.

A second strategy draws lots laid out the way real ones are (:func:`networks`: two-way
aisles between back-to-back rows of bays that start right at the junctions, cross aisles
making L and T junctions and crossroads, dead ends, a gate spur meeting the first aisle at a
T); the same properties hold, and the slow profile prints how much of such lots is served
(free slots reachable and left again, and usable by each type; junction turns dropped; dead
ends with no turnaround).

Two profiles: ``lotsim-fast`` runs a few small lots (derandomized: the same ones every time,
some 10 s), in the default run for the first strategy; ``lotsim-slow`` runs many larger lots
with more cars (some six minutes), left out like every ``slow`` test unless asked for with
``pytest -m slow`` (as are the few small real-style lots of the fast profile): with
``-s`` it prints how many of each kind of aisle, row, angle and obstacle it drew, how the
cars ended and why lotsim refused a lot, if it did.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from collections import Counter

import numpy as np
import pytest
import shapely
import yaml
from hypothesis import HealthCheck, assume, given, note, settings
from hypothesis import strategies as st

from conftest import time_limit
from lotsim.errors import ScenarioError
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import parse_scenario
from lotsim.io.yamlnodes import parse_text
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.running import simulate
from lotsim.sim.settings import RunSettings
from lotsim.traffic.demand import arrivals
from lotsim.vehicles.catalogue import CATALOGUE
from lotsim.verify import check_result
from single_track import assert_reproduced

_COMMON = dict(deadline=None, database=None, print_blob=True,
               suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
settings.register_profile("lotsim-fast", max_examples=10, derandomize=True, **_COMMON)
settings.register_profile("lotsim-slow", max_examples=200, **_COMMON)
SMALL = {"types": 2, "slots": 3, "cars": 6}
LARGE = {"types": 3, "slots": 10, "cars": 24}
"""Most vehicle types, slots per row and cars of a drawn scenario, by profile."""
TIME_LIMIT = 300.0
"""Seconds one scenario may take (planned twice, checked) before it counts as a hang."""
MOST_REFUSED = 0.1
"""Largest share of drawn scenarios lotsim may refuse: the generator means them all valid."""
SEEN: Counter = Counter()
"""What was drawn and how it ended, over a test's examples."""

KINDS = ("perpendicular", "parallel", "angled")
WALL = 0.2  # thickness of the drawn walls [m]


@dataclasses.dataclass(frozen=True)
class Case:
    """A drawn scenario, how to run it, and what the test knows about it."""

    text: str = dataclasses.field(repr=False)  # noted in full on failure
    settings: RunSettings
    booked: tuple | None  # (a permutation of the arrivals, the horizon [s]) or None: online
    taken: frozenset  # the slots taken at start
    tags: tuple  # what was drawn, for the statistics


# -- the strategy ------------------------------------------------------------------------------
@st.composite
def rows(draw, width: float, length: float, most: int) -> dict:
    """A row of slots for cars up to ``width`` × ``length`` [m]: its YAML mapping (without
    aisle, side and start), its ``depth`` away from the aisle and its ``span`` along it."""
    kind = draw(st.sampled_from(KINDS))
    count = draw(st.integers(1, most))
    gap = draw(st.sampled_from([0.0, 0.0, 0.3]))
    row = {"kind": kind}
    if kind == "parallel":
        w = round(width + draw(st.floats(0.5, 0.9)), 3)
        ln = round(length + draw(st.floats(2.0, 3.0)), 3)
        depth, pitch, extent = w, ln, ln
    else:
        w = round(width + draw(st.floats(0.5, 1.2)), 3)
        ln = round(length + draw(st.floats(0.3, 1.0)), 3)
        # BUG: angled_more_room_infeasible: below 10° lotsim misses ways out; from 0.5° once fixed
        deg = round(draw(st.floats(10.0, 89.9)), 2) if kind == "angled" else 90.0
        if kind == "angled":
            row["angle_deg"] = deg
        a = math.radians(deg)
        depth = w * math.cos(a) + ln * math.sin(a)
        pitch, extent = w / math.sin(a), w * math.sin(a) + ln * math.cos(a)
        count = min(count, max(1, int(40 / pitch)))  # shallow angles: far apart
    row |= {"count": count, "gap": gap, "slot_width": w, "slot_length": ln}
    return {"row": row, "depth": depth, "span": (count - 1) * (pitch + gap) + extent}


@st.composite
def aisles(draw, width: float, length: float, most: int, *, row: bool) -> dict:
    """An aisle for cars up to ``width`` × ``length`` [m]: direction, width, and the rows on
    its ``left`` (always one if ``row``) and ``right``, or None."""
    one_way = draw(st.booleans())
    some = rows(width, length, most)
    left, right = draw(some if row else st.none() | some), draw(st.none() | some)
    least = width + 0.3 if one_way else 2 * (width + 0.3)
    return {"one_way": one_way, "reverse": draw(st.booleans()),
            "width": round(max(least, draw(st.floats(5.0, 8.0))), 3), "left": left,
            "right": right}


@dataclasses.dataclass(frozen=True)
class Frame:
    """The lot's frame: x along the aisles (``long`` m), y across, turned by ``turn``°."""

    long: float
    turn: float

    def world(self, x: float, y: float) -> list[float]:
        c, s = math.cos(math.radians(self.turn)), math.sin(math.radians(self.turn))
        return [round(x * c - y * s, 4), round(x * s + y * c, 4)]

    def at(self, a: dict, s: float, t: float) -> list[float]:
        """The point ``s`` along aisle ``a`` from its first point and ``t`` to its left."""
        return self.world(self.long - s, a["y"] - t) if a["reverse"] else \
            self.world(s, a["y"] + t)

    def box(self, a: dict, s0: float, s1: float, t0: float, t1: float) -> list[list[float]]:
        return [self.at(a, s0, t0), self.at(a, s1, t0), self.at(a, s1, t1), self.at(a, s0, t1)]


def serves(aisle: dict, lane: int, kind: str, side: str) -> bool:
    """Whether a car on ``lane`` (0: along the polyline, 1: against it) surely reaches the
    slots of a row: on a two-way aisle angled slots from the lane they lean with, the others
    from the lane on their side (the far lane may be too close for a perpendicular slot)."""
    if aisle["one_way"]:
        return True
    return lane == (0 if kind == "angled" or side == "right" else 1)


@st.composite
def lots(draw, names: list[str], most: int) -> tuple[dict, list[str], dict, list[str]]:
    """A lot for the catalogue cars ``names`` with at most ``most`` slots a row: its YAML
    mapping, its slot ids, the slot ids a car from each entrance can park in, and tags."""
    cars = [CATALOGUE[n] for n in names]
    width, length = max(c.width for c in cars), max(c.front + c.rear for c in cars)
    plan = [draw(aisles(width, length, most, row=k == 0)) for k in range(draw(st.integers(1, 2)))]
    spans = [r["span"] for a in plan for r in (a["left"], a["right"]) if r]
    before, after = draw(st.floats(10.0, 13.0)), draw(st.floats(10.0, 13.0))  # room to turn in
    f = Frame(max(20.0, before + max(spans) + after), draw(st.floats(0.0, 360.0)))
    # stack the aisles and their rows across the lot, gaps between and at the edges
    gap = st.floats(0.4, 1.5)
    behind = [(0.0, y := draw(gap))]
    for a in plan:
        below, above = (a["left"], a["right"]) if a["reverse"] else (a["right"], a["left"])
        a["y"] = y + (below["depth"] if below else 0.0) + a["width"] / 2
        top = a["y"] + a["width"] / 2 + (above["depth"] if above else 0.0)
        y = top + draw(gap)
        behind.append((top, y))
    lot: dict = {"boundary": [f.world(-0.01, 0), f.world(f.long + 0.01, 0),
                              f.world(f.long + 0.01, y), f.world(-0.01, y)],
                 "aisles": [], "rows": [], "walls": [], "obstacles": [], "no_go": [],
                 "entrances": [], "exits": []}
    slots: list[str] = []
    served: dict[str, list[str]] = {}
    tags = [f"{len(plan)} aisle(s)"]
    for k, a in enumerate(plan):
        gates = draw(aisle_items(f, k, a, max(c.front for c in cars), lot, tags))
        served |= {g: [] for g in gates}
        for side in ("left", "right"):
            if a[side] is not None:
                start = before + draw(st.floats(0.0, 1.0)) * (max(spans) - a[side]["span"])
                ids = draw(row_items(f, f"a{k}", a, side, start, lot, tags))
                slots += ids
                for j, g in enumerate(gates):
                    if serves(a, j, a[side]["row"]["kind"], side):
                        served[g] += ids
    for lo, hi in behind:  # walls behind the rows: along the edges and between the aisles
        if draw(st.booleans()):
            y0, y1 = (lo + hi - WALL) / 2, (lo + hi + WALL) / 2
            lot["walls"].append({"polygon": [f.world(0, y0), f.world(f.long, y0),
                                             f.world(f.long, y1), f.world(0, y1)]})
            tags.append("edge wall" if lo == 0 or hi == y else "middle wall")
    if draw(st.booleans()):
        a, s = plan[0], before + draw(st.floats(0.0, 1.0)) * max(spans)
        lot["speed_bumps"] = [{"id": "bump", "line": [f.at(a, s, -a["width"] / 2),
                                                      f.at(a, s, a["width"] / 2)],
                               "limit_kmh": draw(st.sampled_from([5, 10, 15])),
                               "reach": draw(st.sampled_from([1, 3, 5]))}]
        tags.append("speed bump")
    if draw(st.booleans()):
        lot["speed_limit_kmh"] = draw(st.sampled_from([8, 12, 20, 25]))
    return lot, slots, served, tags


@st.composite
def aisle_items(draw, f: Frame, k: int, a: dict, front: float, lot: dict,
                tags: list) -> list[str]:
    """Add aisle ``a`` (number ``k``) to ``lot`` with an entrance and an exit on each lane,
    at opposite ends, and maybe a wall across a one-way aisle's far end; its entrances, one
    per lane (along the polyline first)."""
    aid, half = f"a{k}", a["width"] / 2
    lot["aisles"].append({"id": aid, "centerline": [f.at(a, 0, 0), f.at(a, f.long, 0)],
                          "width": a["width"],
                          "direction": "one-way" if a["one_way"] else "two-way"})
    tags.append("one-way" if a["one_way"] else "two-way")
    closed = a["one_way"] and draw(st.booleans())
    out = f.long - front - 0.6 - (WALL if closed else 0.0)
    lanes = [(0.0, 1.5, out)] if a["one_way"] else [
        (-half / 2, 1.5, out), (half / 2, f.long - 1.5, front + 0.6)]
    for j, (t, s_in, s_out) in enumerate(lanes):
        heading = (f.turn + (180.0 if j != a["reverse"] else 0.0)) % 360.0
        for group, s in (("entrances", s_in), ("exits", s_out)):
            x, y = f.at(a, s, t)
            lot[group].append({"id": f"{group[:2]}{k}{j}", "x": x, "y": y,
                               "heading_deg": round(heading, 4)})
    if closed:
        lot["walls"].append({"id": f"end-{aid}",
                             "polygon": f.box(a, f.long - WALL, f.long, -half, half)})
        tags.append("end wall")
    return [f"en{k}{j}" for j in range(len(lanes))]


@st.composite
def row_items(draw, f: Frame, aid: str, a: dict, side: str, start: float, lot: dict,
              tags: list) -> list[str]:
    """Add the row on ``side`` of aisle ``a`` to ``lot``, from station ``start``, and maybe
    a wall, obstacle or no-go zone in the corners beside it, off the aisle; its slot ids."""
    r, sign, half = a[side], 1 if side == "left" else -1, a["width"] / 2
    row = {"aisle": aid, "side": side, "start": round(start, 3), **r["row"]}
    if draw(st.booleans()):
        row["id_prefix"] = f"{aid}{side[0].upper()}"
    if draw(st.booleans()):
        row["first_number"] = draw(st.integers(0, 3))
    lot["rows"].append(row)
    deg = int(row.get("angle_deg", 0)) // 10 * 10
    tags.append(f"angled {deg}-{deg + 9}°" if row["kind"] == "angled" else row["kind"])
    for s0, s1 in ((0.0, start - 1.0), (start + r["span"] + 1.0, f.long)):
        if s1 - s0 > 1.5 and draw(st.booleans()):
            kind = draw(st.sampled_from(["walls", "obstacles", "no_go"]))
            back = half + draw(st.floats(0.2, 1.0))
            lot[kind].append({"polygon": f.box(a, s0, s1, sign * back,
                                               sign * (half + r["depth"]))})
            tags.append(f"corner {kind}")
    return [f"{row.get('id_prefix', f'{aid}-{side}-')}{row.get('first_number', 1) + i}"
            for i in range(row["count"])]


def drawn_occupancy(n: int, fraction: float, seed: int, min_free: int) -> np.ndarray:
    """Which of ``n`` slots ``{fraction, seed, min_free}`` takes, as docs/scenario.md says."""
    rng = np.random.default_rng(seed)
    taken = rng.random(n) < fraction
    short = min_free - int((~taken).sum())
    if short > 0:
        taken[rng.choice(np.flatnonzero(taken), size=short, replace=False)] = False
    return taken


@st.composite
def occupancies(draw, slots: list[str]) -> tuple[object, list[str]]:
    """``lot.occupied``, listed or drawn by fraction (at least one slot stays free), and the
    slots it takes."""
    if draw(st.booleans()):
        taken = draw(st.lists(st.sampled_from(slots), unique=True, max_size=len(slots) - 1))
        return taken, taken
    occ = {"fraction": draw(st.sampled_from([0.0, 0.2, 0.5, 0.8])),
           "seed": draw(st.integers(0, 99)), "min_free": draw(st.integers(1, len(slots)))}
    return occ, [s for s, t in zip(slots, drawn_occupancy(len(slots), **occ), strict=True) if t]


@st.composite
def traffics(draw, names: list[str], gates: list[str], everywhere: bool, most: int
             ) -> tuple[dict, int]:
    """Traffic of at most ``most`` cars of types ``names`` at entrances ``gates`` (all the
    lot's if ``everywhere``): cars listed, a stream, or both; and how many cars."""
    traffic: dict = {"patience": draw(st.sampled_from([0, 30, 120, 600]))}
    dwell = st.none() | st.integers(5, 120)
    listed = draw(st.integers(0, 3))
    count = draw(st.integers(0 if listed else 1, most - listed))
    if listed:
        traffic["vehicles"] = [
            {"id": f"car{i}", "arrival": draw(st.integers(0, 90)),
             "type": draw(st.sampled_from(names)), "entrance": draw(st.sampled_from(gates)),
             **({"dwell": d} if (d := draw(dwell)) is not None else {})}
            for i in range(listed)]
    if count:
        stream = {"count": count, "rate_per_hour": draw(st.sampled_from([30, 240, 900, 3600])),
                  "mix": {n: draw(st.integers(1, 3)) for n in names}}
        if not everywhere or draw(st.booleans()):
            stream["entrances"] = gates
        if (d := draw(dwell)) is not None:
            stream["dwell"] = [d, d + draw(st.integers(0, 60))]
        if draw(st.booleans()):
            stream["seed"] = draw(st.integers(0, 2**31))
        traffic["stream"] = stream
    return traffic, listed + count


@st.composite
def scenarios(draw, size: dict) -> Case:
    """A valid scenario of at most ``size`` (:data:`SMALL`, :data:`LARGE`), and a run of it."""
    names = draw(st.lists(st.sampled_from(sorted(CATALOGUE)), min_size=1,
                          max_size=size["types"], unique=True))
    lot, slots, served, tags = draw(lots(names, size["slots"]))
    lot["occupied"], taken = draw(occupancies(slots))
    gates = [g for g, ids in served.items() if set(ids) - set(taken)]  # a free slot to go to
    traffic, cars = draw(traffics(names, gates, len(gates) == len(served), size["cars"]))
    doc = {"name": "prop", "seed": draw(st.integers(0, 2**31)), "vehicle_types": names,
           "parked_vehicle": draw(st.sampled_from(names)),
           "lot": {k: v for k, v in lot.items() if v}, "traffic": traffic}
    setting = RunSettings(planner=draw(st.sampled_from(["ca", "hca", "whca"])),
                          assignment=draw(st.sampled_from(["nearest", "shortest", "priced"])),
                          seed=draw(st.none() | st.integers(0, 2**31)),
                          window=draw(st.sampled_from([4.0, 10.0, 20.0])))
    booked = draw(st.none() | st.tuples(st.permutations(range(cars)),
                                        st.sampled_from([30.0, 60.0, math.inf])))
    text = yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=100)
    return Case(text, setting, booked, frozenset(taken), tuple(tags))


@st.composite
def networks(draw, size: dict) -> Case:
    """A lot laid out the way real ones are, valid by construction: one to three two-way
    aisles (6 to 7.5 m) between back-to-back rows of perpendicular bays (2.4 to 2.8 m by 4.8
    to 5.8 m) that start right at every junction (corner bays); a cross aisle at the west
    end (L corners, T junctions) or none (a dead end), maybe one in the middle (T junctions,
    crossroads); the east ends dead ends or joined by a cross aisle; one gate: a two-way
    spur from the south boundary meeting the first aisle at a T, the entrance on its way in
    and the exit on its way out; two aisles or more are joined by at least one cross aisle.
    Every car dwells and leaves by the gate."""
    names = draw(st.lists(st.sampled_from(sorted(CATALOGUE)), min_size=1,
                          max_size=size["types"], unique=True))
    w = round(draw(st.floats(6.0, 7.5)), 2)
    sw, sl = round(draw(st.floats(2.4, 2.8)), 2), round(draw(st.floats(4.8, 5.8)), 2)
    n = draw(st.integers(1, 3))
    west = n > 1 and draw(st.booleans())
    middle = n > 1 and draw(st.booleans())
    east = n > 1 and (draw(st.booleans()) or not (west or middle))  # every aisle joined
    per_block = draw(st.integers(2, size["slots"] + 2))
    tags = ["network", f"{n} aisles"] + ["west cross"] * west + ["middle cross"] * middle \
        + (["east cross"] if east else ["dead ends"])
    y0 = sl + w / 2 + round(draw(st.floats(0.0, 1.5)), 2)  # the first aisle's centre
    ys = [round(y0 + k * (w + 2 * sl), 3) for k in range(n)]
    x0 = w / 2 if west else 1.0  # where the aisles begin
    gate_block = per_block * sw + 2.0  # bays west of the spur on the first aisle's south
    xg = round(x0 + (w / 2 if west else 0.0) + gate_block + w / 2, 3)
    blocks = [(round(x0 + (w / 2 if west else 0.0), 3), None)]
    xm = round(xg + w / 2 + 1.0 + per_block * sw + w / 2, 3) if middle else None
    x_end = round((xm if middle else xg + w / 2 + 1.0) + w / 2 * middle + per_block * sw
                  + (w / 2 if east else 0.6), 3)
    top = round(ys[-1] + w / 2 + sl, 3)
    lot: dict = {"boundary": [[0, 0], [x_end + (w / 2 if east else 1.0), 0],
                              [x_end + (w / 2 if east else 1.0), top], [0, top]],
                 "aisles": [{"id": "spur", "centerline": [[xg, 0], [xg, ys[0]]], "width": w}],
                 "rows": [],
                 "entrances": [{"id": "gate-in", "x": round(xg + w / 4, 3), "y": 1.5,
                                "heading_deg": 90}],
                 "exits": [{"id": "gate-out", "x": round(xg - w / 4, 3), "y": 4.5,
                            "heading_deg": -90}]}
    for k, y in enumerate(ys):
        lot["aisles"].append({"id": f"a{k}", "centerline": [[x0, y], [x_end, y]], "width": w})
    for name, x, on in (("west", x0, west), ("mid", xm, middle), ("east", x_end, east)):
        if on:
            lot["aisles"].append({"id": name, "centerline": [[x, ys[0]], [x, ys[-1]]],
                                  "width": w})
    # bays along each aisle, in blocks between the junctions, starting right at them
    starts = [blocks[0][0]]
    if middle:
        starts.append(xm + w / 2)
    slots = []
    for k in range(n):
        for side in ("right", "left"):
            if side == "left" and k == n - 1 and draw(st.booleans()):
                continue  # no bays along the north boundary
            for j, x in enumerate(starts):
                stops = [(x, xm - w / 2 if (middle and j == 0) else x_end
                          - (w / 2 if east else 0.0))]
                if k == 0 and side == "right" and j == 0:  # around the gate spur
                    stops = [(x, xg - w / 2 - 0.5), (xg + w / 2 + 0.5, stops[0][1])]
                for a, b in stops:
                    count = min(int((b - a) / sw + 1e-9), per_block)
                    if count < 1:
                        continue
                    prefix = f"{k}{side[0]}{len(lot['rows'])}-"
                    lot["rows"].append({"aisle": f"a{k}", "side": side,
                                        "kind": "perpendicular", "count": count,
                                        "slot_width": sw, "slot_length": sl,
                                        "start": round(a - x0, 3), "id_prefix": prefix})
                    slots += [f"{prefix}{i + 1}" for i in range(count)]
    lot["occupied"], taken = draw(occupancies(slots))
    cars = draw(st.integers(1, size["cars"]))
    traffic = {"patience": 600, "stream": {
        "count": cars, "rate_per_hour": draw(st.sampled_from([60, 240, 900])),
        "mix": {nm: 1 for nm in names}, "dwell": [30, 30 + draw(st.integers(0, 120))]}}
    doc = {"name": "net", "seed": draw(st.integers(0, 2**31)), "vehicle_types": names,
           "lot": lot, "traffic": traffic}
    setting = RunSettings(planner=draw(st.sampled_from(["hca", "whca"])),
                          assignment=draw(st.sampled_from(["nearest", "shortest", "priced"])))
    text = yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=100)
    return Case(text, setting, None, frozenset(taken), tuple(tags))


# -- the properties ----------------------------------------------------------------------------
def plan_and_check(case: Case) -> None:
    """Plan a drawn scenario, check its result and assert every property."""
    note(case.text)
    sc = parse_scenario(parse_text(case.text, "prop.yaml"))
    SEEN["drawn"] += 1
    setting = case.settings
    try:
        lg = prepare_graph(sc)
        drawn = arrivals(sc.traffic, sc.seed if setting.seed is None else setting.seed)
        if case.booked is not None:
            order, horizon = case.booked
            setting = dataclasses.replace(setting, order=tuple(drawn[i].id for i in order),
                                          horizon=horizon)
        note(repr(setting))
        rr = simulate(sc, setting, lot_graph=lg)
    except ScenarioError as exc:
        SEEN["refused"] += 1
        SEEN[f"refused: {str(exc).split(': ', 2)[-1]}"] += 1
        assume(False)
    SEEN.update(case.tags)
    if "network" in case.tags:  # how much of a real-style lot is served (measured, not asserted)
        reach = lg.reachability()
        free = [sl.id for sl in lg.lot.free_slots]
        bad = set(reach.no_way_in) | set(reach.no_way_out)
        SEEN["network: free slots"] += len(free)
        SEEN["network: free slots reachable and left again"] += len(set(free) - bad)
        for slots in lg.infeasible.values():
            SEEN["network: free slots x types"] += len(free)
            SEEN["network: ... usable by the type"] += len(set(free) - bad - set(slots))
        for car in sc.vehicle_types:  # every bay a car is short and narrow enough for
            fits = {sl.id for sl in lg.lot.free_slots
                    if car.length <= sl.length and car.width <= sl.width}
            no_in, no_out = reach.by_type.get(car.name, ([], []))
            SEEN["network: free slots x types that fit them"] += len(fits)
            SEEN["network: ... reached, parked in and left by that type"] += len(
                fits - set(lg.infeasible.get(car.name, {})) - set(no_in) - set(no_out))
        SEEN["network: junction turns dropped"] += sum("skipped" in t for t in lg.skipped_turns)
        SEEN["network: dead ends with no turnaround"] += sum("no turnaround" in t
                                                            for t in lg.skipped_turns)
    assert lg.lot.occupied == case.taken
    doc = json.loads(json.dumps(result_dict(rr), allow_nan=False))  # what the file holds
    report = check_result(doc)
    assert report.ok, "\n".join([report.summary(), *map(str, report.violations[:12])])
    assert_reproduced(doc)
    accounted_for(doc, drawn)
    parked_in_their_slots(doc)
    start_at_their_entrance(doc)
    SEEN.update(f"{v['status']}: {re.sub(r'[0-9.]+', 'N', v['reason'])}".rstrip(": ")
                for v in doc["vehicles"])
    again = result_dict(simulate(sc, setting, lot_graph=lg))
    assert json.dumps(again, sort_keys=True) == json.dumps(doc, sort_keys=True), "not repeatable"


def accounted_for(doc: dict, drawn: list) -> None:
    """Every arrival once, as drawn; a reason exactly where it neither parked nor left; a car
    leaves only after standing its dwell, and only if it has one."""
    got = [(v["id"], v["type"]["name"], v["entrance"], v["arrival"]) for v in doc["vehicles"]]
    assert sorted(got) == sorted((a.id, a.vehicle, a.entrance, a.time) for a in drawn)
    dwell = {a.id: a.dwell for a in drawn}
    for v in doc["vehicles"]:
        status, t = v["status"], v["samples"]["t"]
        assert status in ("parked", "departed", "waiting", "rejected")
        assert bool(v["reason"]) == (status in ("waiting", "rejected")), (v["id"], v["reason"])
        if status in ("parked", "departed"):
            assert v["slot"] is not None, v["id"]
        if status == "departed":
            stood = max(b - a for a, b in zip(t, t[1:], strict=False))
            assert dwell[v["id"]] is not None and stood >= dwell[v["id"]] - 1e-3, v["id"]


def footprint(v: dict, k: int) -> shapely.Polygon:
    """Vehicle ``v``'s body at its sample ``k``."""
    t, s = v["type"], v["samples"]
    x, y, th = s["x"][k], s["y"][k], s["theta"][k]
    c, n = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th), math.cos(th)])
    h = t["width"] / 2
    return shapely.Polygon([np.array([x, y]) + a * c + b * n for a, b in (
        (-t["rear"], -h), (t["front"], -h), (t["front"], h), (-t["rear"], h))])


def parked_in_their_slots(doc: dict) -> None:
    """Parked cars end inside their own slot (within 2 mm), free at start, one per slot."""
    slots = {s["id"]: s for s in doc["lot"]["slots"]}
    parked = [v for v in doc["vehicles"] if v["status"] == "parked"]
    assert len({v["slot"] for v in parked}) == len(parked), "two cars in one slot"
    for v in parked:
        slot = slots[v["slot"]]
        assert not slot["occupied"], f"{v['id']} parked in {slot['id']}, taken at start"
        assert shapely.Polygon(slot["polygon"]).buffer(2e-3).covers(footprint(v, -1)), \
            f"{v['id']} ends outside its slot {slot['id']}"


def start_at_their_entrance(doc: dict) -> None:
    """A car that moves starts on its entrance's pose."""
    gates = {e["id"]: e["pose"] for e in doc["lot"]["entrances"]}
    for v in doc["vehicles"]:
        s = v["samples"]
        if s["t"]:
            x, y, th = gates[v["entrance"]]
            assert math.dist((x, y), (s["x"][0], s["y"][0])) < 1e-3, v["id"]
            assert abs(math.remainder(th - s["theta"][0], math.tau)) < 1e-3, v["id"]


# -- the two profiles --------------------------------------------------------------------------
def _run_profile(profile: str, size: dict, strategy=None, *,
                 most_refused: float = MOST_REFUSED, **more) -> None:
    SEEN.clear()

    @settings(settings.get_profile(profile), **more)
    @given((strategy or scenarios)(size))
    def holds(case: Case) -> None:
        with time_limit(TIME_LIMIT):
            plan_and_check(case)

    holds()
    assert SEEN["refused"] <= most_refused * SEEN["drawn"], dict(SEEN)


@pytest.mark.slow
def test_random_lots_and_traffic_pass_the_independent_check():
    _run_profile("lotsim-fast", SMALL)


# Real-style lots: lotsim may still refuse some (most: a type longer than every bay) — how
# many is measured (the slow profile prints it), not asserted; every lot it runs must pass
# the checks, and in those (slow profile) 97 in 100 of the bays each type fits are reached,
# parked in and left by it (measured on 40 drawn lots: 99.6 %, 1095 of 1099, since tiny
# lots are turned in by multi-point turns; what is left is four corner bays for a 5 m van).
USABLE = 0.97
# by default, lots drawn by the first strategy pass the checks (the test above) and every free
# bay of the shipped real-style lots is reached, parked in and left (tests/e2e/test_real_lots.py);
# the few small real-style lots drawn here, and the many larger ones below: -m slow
@pytest.mark.slow
def test_random_real_style_lots_pass_the_independent_check():
    _run_profile("lotsim-fast", SMALL, networks, most_refused=1.0, max_examples=3)
    assert SEEN["drawn"] > SEEN["refused"]


@pytest.mark.slow
def test_many_larger_real_style_lots_pass_the_independent_check():
    _run_profile("lotsim-slow", LARGE, networks, most_refused=1.0, max_examples=60)
    print("\n" + "\n".join(f"{n:6d}  {what}" for what, n in sorted(SEEN.items())))
    fits = SEEN["network: free slots x types that fit them"]
    assert SEEN["network: ... reached, parked in and left by that type"] >= USABLE * fits


@pytest.mark.slow
def test_many_larger_random_lots_pass_the_independent_check():
    _run_profile("lotsim-slow", LARGE)
    print("\n" + "\n".join(f"{n:6d}  {what}" for what, n in sorted(SEEN.items())))
