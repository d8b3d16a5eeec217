"""Would a compiled planning core pay? A measured spike of numba kernels against the
cooperative space-time search of today, on a real day's work.

Run with::

    pip install numba                                  # not a lotsim dependency
    python benchmarks/spike_compiled.py                # 400 cars at 250/h on dlp_like
    python benchmarks/spike_compiled.py --count 200    # a shorter day
    python benchmarks/spike_compiled.py --validate     # also cold validate of surface364

What it does, all in one process and on the same inputs:

1. runs the day once untouched (the search's seconds and expansions: today's cost per
   expansion), once under cProfile (the share of the search's time in state expansion and
   the heap, the reservation table's queries, the exact shapely tests, the heuristic, and
   working out the edge motions), and once recording what the search asks the table;
2. kernel A: every pair (moving hull, reserved body) the run tested with
   ``shapely.intersects``, tested again by a separating-axis test on convex polygons as flat
   coordinate arrays (numba); the answers must agree on every pair (a pair within 1e-9 m
   of touching is left to shapely, and counted);
3. kernel B: recorded ``candidates.pairs`` and ``blocked_among`` queries answered by numba
   loops over the entries' and hulls' rows as arrays (the same pairs in the same order; the
   same departure intervals, float for float);
4. the whole search: Amdahl's estimate from the profile's shares, each part sped up by the
   ratio measured for its kernel (the bookkeeping of expansions by a numba heap against
   ``heapq``), working out edge motions left in Python;
5. with ``--validate``: cold ``lotsim validate scenarios/lots/surface364.yaml``
   (``LOTSIM_CACHE_DIR=off``) in one process under cProfile: the share in the maneuver
   searches' collision checks and in shapely, and what compiling them could give at most.

Each timing is the minimum of ``--repeat`` passes, today's code and the kernel taking turns
on the same inputs; compile seconds (numba's ``cache=True``: the first run in a fresh
checkout compiles, later ones load) are reported apart. Ratios, not seconds, are the
machine-independent figures.
"""

from __future__ import annotations

import argparse
import cProfile
import heapq
import math
import multiprocessing as mp
import os
import pstats
import random
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

try:
    import numba
except ImportError:  # (the profiles still run; the kernels need it)
    numba = None

import shapely  # noqa: E402
from bench_day import day_text  # noqa: E402

EPS = 1e-9  # lotsim.traffic.grid.EPS: the slack of every time comparison [s]
TOUCH = 1e-9  # a pair closer than this to touching [m] is left to shapely
SEED = 0


def _jit(fn):
    """``fn`` compiled by numba (cached on disk), or as it is without numba."""
    return numba.njit(cache=True)(fn) if numba is not None else fn


# -- kernel A: separating axes of convex polygons ------------------------------------------------
def _gap(xy, e0, en, a0, an, b0, bn):
    """The largest gap between polygons a and b along the normals of polygon e's edges
    (positive: apart), and the least threshold below which it is too close to call."""
    best = -np.inf
    thr = 0.0
    for k in range(en):
        x1, y1 = xy[e0 + k, 0], xy[e0 + k, 1]
        k2 = k + 1 if k + 1 < en else 0
        nx, ny = y1 - xy[e0 + k2, 1], xy[e0 + k2, 0] - x1
        amin, amax = np.inf, -np.inf
        for m in range(an):
            v = nx * xy[a0 + m, 0] + ny * xy[a0 + m, 1]
            amin = min(amin, v)
            amax = max(amax, v)
        bmin, bmax = np.inf, -np.inf
        for m in range(bn):
            v = nx * xy[b0 + m, 0] + ny * xy[b0 + m, 1]
            bmin = min(bmin, v)
            bmax = max(bmax, v)
        g = max(bmin - amax, amin - bmax)
        t = TOUCH * (abs(nx) + abs(ny))
        if g > t:
            return g, t
        if g > best:
            best, thr = g, t
    return best, thr


_gap = _jit(_gap)


def _meet(xy, a0, an, b0, bn):
    """1: convex polygons a and b (vertex runs of ``xy``) meet (touching counts), 0: apart,
    2: within :data:`TOUCH` of touching (left to an exact test)."""
    g1, t1 = _gap(xy, a0, an, a0, an, b0, bn)
    if g1 > t1:
        return 0
    g2, t2 = _gap(xy, b0, bn, a0, an, b0, bn)
    if g2 > t2:
        return 0
    if g1 > -t1 or g2 > -t2:
        return 2
    return 1


_meet = _jit(_meet)


def _meet_pairs(xy, start, count, ja, jb, out):
    """:func:`_meet` of polygons ``ja[k]`` and ``jb[k]`` into ``out[k]``."""
    for k in range(len(ja)):
        a, b = ja[k], jb[k]
        out[k] = _meet(xy, start[a], count[a], start[b], count[b])


_meet_pairs = _jit(_meet_pairs)


# -- kernel B: candidate pairs and departure intervals ------------------------------------------
def _pairs(srows, erows, eids, offset, timed, out_j, out_i):
    """candidates.pairs: the (hull j, entry id) pairs whose boxes meet and, if ``timed``,
    whose times overlap with the hulls shifted by ``offset``: hull by hull, entries in the
    given (ascending) order. Returns how many were written."""
    n = 0
    for j in range(srows.shape[0]):
        a, z = srows[j, 0] + offset, srows[j, 1] + offset
        x0, y0, x1, y1 = srows[j, 2], srows[j, 3], srows[j, 4], srows[j, 5]
        for k in range(erows.shape[0]):
            if timed and not (erows[k, 0] <= z + EPS and erows[k, 1] >= a - EPS):
                continue
            if (erows[k, 2] <= x1 and erows[k, 4] >= x0 and erows[k, 3] <= y1
                    and erows[k, 5] >= y0):
                out_j[n] = j
                out_i[n] = eids[k]
                n += 1
    return n


_pairs = _jit(_pairs)


def _blocked(srows, erows, trows, since, until, xy, hs, hn, es, en, lo, hi, undecided):
    """candidates.blocked_among: the departure times at which hulls ``srows`` meet entries
    ``erows`` (their times ``trows``), as sorted disjoint intervals written to ``lo, hi``;
    the exact test by :func:`_meet` on hull j's vertices ``hs[j], hn[j]`` and entry k's
    ``es[k], en[k]``. Returns how many intervals, or -1 when a pair was too close to call
    (its index in ``undecided[0]``: the caller answers it exactly)."""
    first = since + srows[:, 0].min()
    last = until + srows[:, 1].max()
    lo_t, hi_t = first - EPS, last + EPS
    m = 0
    for k in range(erows.shape[0]):
        if not (erows[k, 0] <= hi_t and erows[k, 1] >= lo_t):
            continue
        for j in range(srows.shape[0]):
            if not (erows[k, 2] <= srows[j, 4] and erows[k, 4] >= srows[j, 2]
                    and erows[k, 3] <= srows[j, 5] and erows[k, 5] >= srows[j, 3]):
                continue
            a, z = srows[j, 0], srows[j, 1]
            t0, t1 = trows[k, 0], trows[k, 1]
            if t1 - a + EPS >= since and t0 - z - EPS <= until:
                met = _meet(xy, hs[j], hn[j], es[k], en[k])
                if met == 2:
                    undecided[0] = j
                    undecided[1] = k
                    return -1
                if met == 1:
                    lo[m] = t0 - z - EPS
                    hi[m] = t1 - a + EPS
                    m += 1
    if m < 2:
        return m
    order = np.argsort(lo[:m])
    sl, sh = lo[:m][order], hi[:m][order]  # (copies: the union is written over lo, hi)
    a0, z0 = sl[0], sh[0]
    n = 0
    for q in range(1, m):
        a, z = sl[q], sh[q]
        if a <= z0:
            z0 = max(z0, z)
        else:
            lo[n], hi[n] = a0, z0
            n += 1
            a0, z0 = a, z
    lo[n], hi[n] = a0, z0
    return n + 1


_blocked = _jit(_blocked)


# -- the bookkeeping of expansions: a binary heap over arrays -----------------------------------
def _heap_walk(keys, ties, children, out):
    """Pop the least ``(key, tie)`` state and push ``children`` new ones, ``len(out)``
    times (the keys drawn in advance); each pop's state id into ``out``."""
    cap = len(keys)
    hk = np.empty(cap)
    ht = np.empty(cap)
    hid = np.empty(cap, dtype=np.int64)
    size = 1
    hk[0], ht[0], hid[0] = keys[0], ties[0], 0
    made = 1
    for step in range(len(out)):
        if size == 0:
            return step
        out[step] = hid[0]
        size -= 1
        k, t, i = hk[size], ht[size], hid[size]
        p = 0
        while True:  # sift the last one down from the root
            c = 2 * p + 1
            if c >= size:
                break
            if c + 1 < size and (hk[c + 1] < hk[c] or (hk[c + 1] == hk[c] and ht[c + 1] < ht[c])):
                c += 1
            if hk[c] < k or (hk[c] == k and ht[c] < t):
                hk[p], ht[p], hid[p] = hk[c], ht[c], hid[c]
                p = c
            else:
                break
        hk[p], ht[p], hid[p] = k, t, i
        for _ in range(children):
            if made >= cap:
                break
            k, t, i = keys[made], ties[made], made
            made += 1
            p = size
            size += 1
            while p > 0:  # sift up
                q = (p - 1) // 2
                if k < hk[q] or (k == hk[q] and t < ht[q]):
                    hk[p], ht[p], hid[p] = hk[q], ht[q], hid[q]
                    p = q
                else:
                    break
            hk[p], ht[p], hid[p] = k, t, i
    return len(out)


_heap_walk = _jit(_heap_walk)


def _heap_walk_py(keys, ties, children, out):
    """:func:`_heap_walk` with ``heapq`` and tuples, as the search keeps its open states."""
    heap = [(keys[0], ties[0], 0)]
    made = 1
    pop, push = heapq.heappop, heapq.heappush
    cap = len(keys)
    for step in range(len(out)):
        if not heap:
            return step
        out[step] = pop(heap)[2]
        for _ in range(children):
            if made >= cap:
                break
            push(heap, (keys[made], ties[made], made))
            made += 1
    return len(out)


# -- the day -------------------------------------------------------------------------------------
class Recorder:
    """What the search asks while it runs: its seconds and expansions, and (when
    ``record``) the pairs it tests exactly and a sample of its candidate queries."""

    def __init__(self, record: bool, every: int = 5, most: int = 20_000):
        self.record, self.every, self.most = record, every, most
        self.prepared = None
        self.inside = False
        self.seconds = 0.0
        self.expansions = 0
        self.searches = 0
        self.exact: list[tuple[np.ndarray, np.ndarray]] = []
        self.pairs: list[tuple] = []
        self.blocked: list[tuple] = []
        self._calls = {"pairs": 0, "blocked": 0}

    def install(self):
        """Wrap the search and, when recording, the table's tests; returns the undo."""
        import lotsim.sim.loop as loop
        import lotsim.traffic.candidates as cand
        import lotsim.traffic.reservation as res

        undo = []

        def patch(mod, name, new):
            undo.append((mod, name, getattr(mod, name)))
            setattr(mod, name, new)

        search = loop.search

        def timed_search(*a, **k):
            self.inside = True
            clock = time.perf_counter()
            try:
                plan = search(*a, **k)
            finally:
                self.seconds += time.perf_counter() - clock
                self.inside = False
            self.expansions += plan.expansions
            self.searches += 1
            return plan

        patch(loop, "search", timed_search)
        if self.record:
            intersects = shapely.intersects

            def recorded_intersects(a, b, **k):
                if self.inside:
                    a2, b2 = np.broadcast_arrays(np.asarray(a, dtype=object),
                                                 np.asarray(b, dtype=object))
                    self.exact.append((a2.copy(), b2.copy()))
                return intersects(a, b, **k)

            patch(shapely, "intersects", recorded_intersects)
            pairs = cand.pairs

            def recorded_pairs(sw, near, offset, ordered=True, *, few=cand.FEW_PAIRS):
                got = pairs(sw, near, offset, ordered, few=few)
                self._calls["pairs"] += 1
                if (self.inside and self._calls["pairs"] % self.every == 0
                        and len(self.pairs) < self.most):
                    self.pairs.append((sw, near, offset, ordered, got))
                return got

            patch(cand, "pairs", recorded_pairs)
            patch(res, "pairs", recorded_pairs)
            blocked_among = cand.blocked_among

            def recorded_blocked(st, sw, among, since, until, *, few=cand.FEW_PAIRS):
                got = blocked_among(st, sw, among, since, until, few=few)
                self._calls["blocked"] += 1
                if (self.inside and self._calls["blocked"] % 2 == 0
                        and len(self.blocked) < self.most // 2):
                    rows = [st.rows[i] for i in among.ids]
                    geoms = [st.geom[i] for i in among.ids]
                    self.blocked.append((sw, among.rows, rows, geoms, since, until, got))
                return got

            patch(res, "blocked_among", recorded_blocked)
        return lambda: [setattr(m, n, old) for m, n, old in reversed(undo)]


def run_day(path: Path, *, record: bool = False, profile: bool = False):
    """One run of the day on a lot prepared afresh (edge motions worked out as a run of its
    own does): the recorder, and the profile when asked."""
    import lotsim

    prepared = lotsim.prepare(str(path))
    rec = Recorder(record)
    rec.prepared = prepared
    undo = rec.install()
    prof = cProfile.Profile() if profile else None
    try:
        if prof:
            prof.enable()
        lotsim.run(prepared)
    finally:
        if prof:
            prof.disable()
        undo()
    return rec, prof


# -- profile shares ------------------------------------------------------------------------------
def _where(key) -> tuple[str, str]:
    file, _, name = key
    return Path(file).name if "/lotsim/" in file else file, name


def search_shares(prof: cProfile.Profile) -> dict[str, float]:
    """Seconds of the search (under cProfile) in each part: the edges from the search's own
    code (search.py) into each module, the exact tests taken out of the table's."""
    stats = pstats.Stats(prof).stats
    ct = {}
    into: dict[str, float] = {}  # part → seconds spent in calls from search.py
    parts = {"reservation.py": "table", "candidates.py": "table", "grid.py": "table",
             "heuristic.py": "heuristic", "searchgraph.py": "motions", "swept.py": "motions"}
    table_by: dict[str, float] = {}
    for key, (_, _, _tt, cum, callers) in stats.items():
        where, name = _where(key)
        ct[(where, name)] = ct.get((where, name), 0.0) + cum
        part = parts.get(where)
        if part is None:
            continue
        for caller, (_, _, _, c_cum) in callers.items():
            cw, cname = _where(caller)
            if cw == "search.py" and cname != "weighted":
                into[part] = into.get(part, 0.0) + c_cum
                if part == "table":
                    table_by[name] = table_by.get(name, 0.0) + c_cum
    exact = sum(cum for key, (_, _, _, cum, _) in stats.items()
                if key[2] == "intersects" and "shapely" in key[0] and "predicates" in key[0])
    total = ct[("search.py", "search")]
    out = {"total": total,
           "exact tests (shapely.intersects)": exact,
           "table queries (nearby, is_free, blocked, pairs, grid)": into.get("table", 0.0)
           - exact,
           "heuristic (RRA*)": into.get("heuristic", 0.0) + ct.get(("search.py", "weighted"), 0),
           "edge motions and hulls (searchgraph, swept)": into.get("motions", 0.0)}
    out["expansion and heap (search.py's own)"] = total - sum(
        v for k, v in out.items() if k != "total")
    out["table_by"] = table_by
    return out


def validate_shares(path: str) -> dict:
    """Cold ``lotsim validate`` of ``path`` in this process (one worker: run it in a
    process multiprocessing started) under cProfile: seconds in all, in the maneuver
    searches, in their collision checks and in shapely."""
    os.environ["LOTSIM_CACHE_DIR"] = "off"
    from lotsim.cli import main

    prof = cProfile.Profile()
    clock = time.perf_counter()
    prof.enable()
    main(["validate", path])
    prof.disable()
    wall = time.perf_counter() - clock
    stats = pstats.Stats(prof).stats
    ct: dict[tuple[str, str], float] = {}
    shapely_tt = 0.0
    for key, (_, _, tt, cum, _) in stats.items():
        where, name = _where(key)
        ct[(where, name)] = max(ct.get((where, name), 0.0), cum)
        if "shapely" in key[0] or ("built-in" in key[2] and "shapely" in key[2]):
            shapely_tt += tt
    checks = sum(v for (w, n), v in ct.items() if w == "validity.py" and n in (
        "bodies_blocked", "pieces_blocked", "footprints_blocked", "paths_blocked",
        "poses_blocked"))
    clearance = sum(v for (w, n), v in ct.items() if w == "clearance.py"
                    and n in ("hulls_blocked",))
    top = sorted(((v, w, n) for (w, n), v in ct.items() if w.endswith(".py")
                  and not w.startswith("/")), reverse=True)[:25]
    return {"wall": wall, "total": sum(tt for (_, _, tt, _, _) in stats.values()),
            "checks": checks, "hulls_blocked": clearance, "shapely": shapely_tt,
            "top": [(round(v, 2), w, n) for v, w, n in top]}


def _validate_child(path: str, queue) -> None:
    queue.put(validate_shares(path))


# -- kernel A ------------------------------------------------------------------------------------
class Polygons:
    """Every geometry met, once, as runs of vertices (closing point dropped) in one
    (N, 2) array: ``start[g], count[g]`` for geometry g; ``convex[g]`` false where a
    geometry is not a convex polygon (its pairs are left to shapely)."""

    def __init__(self) -> None:
        self.index: dict[int, int] = {}
        self.geoms: list = []

    def of(self, g) -> int:
        k = self.index.get(id(g))
        if k is None:
            k = self.index[id(g)] = len(self.geoms)
            self.geoms.append(g)
        return k

    def build(self) -> None:
        geoms = np.array(self.geoms, dtype=object)
        rings = shapely.get_exterior_ring(geoms)
        kinds = shapely.get_type_id(geoms)
        xy, idx = shapely.get_coordinates(rings, return_index=True)
        count = np.bincount(idx, minlength=len(geoms))
        start = np.concatenate([[0], np.cumsum(count)[:-1]])
        hull_area = shapely.area(shapely.convex_hull(geoms))
        area = shapely.area(geoms)
        holes = shapely.get_num_interior_rings(geoms)
        self.convex = (kinds == 3) & (holes == 0) & (np.abs(hull_area - area) <= 1e-9
                                                     * np.maximum(area, 1.0))
        # counter-clockwise or not does not matter to the axes; the closing point goes
        self.xy = np.ascontiguousarray(xy)
        self.start = start.astype(np.int64)
        self.count = np.maximum(count - 1, 0).astype(np.int64)


def _best(fn, repeat: int) -> float:
    best = math.inf
    for _ in range(repeat):
        clock = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - clock)
    return best


def kernel_a(rec: Recorder, repeat: int) -> dict:
    polys = Polygons()
    ja, jb = [], []
    for a, b in rec.exact:
        ja += [polys.of(g) for g in a]
        jb += [polys.of(g) for g in b]
    polys.build()
    ja, jb = np.array(ja, dtype=np.int64), np.array(jb, dtype=np.int64)
    n = len(ja)
    truth = np.concatenate([shapely.intersects(a, b) for a, b in rec.exact])
    clock = time.perf_counter()
    out = np.empty(n, dtype=np.int8)
    _meet_pairs(polys.xy, polys.start, polys.count, ja[:1], jb[:1], out[:1])
    compile_s = time.perf_counter() - clock
    _meet_pairs(polys.xy, polys.start, polys.count, ja, jb, out)
    odd = ~(polys.convex[ja] & polys.convex[jb])
    decided = (out != 2) & ~odd
    wrong = int(np.sum(decided & ((out == 1) != truth)))
    # per call as the run made them (batches of its size), and all in one call
    calls = [(a, b) for a, b in rec.exact]
    bounds = np.cumsum([0] + [len(a) for a, _ in calls])
    slices = [(ja[s:e], jb[s:e], out[s:e]) for s, e in zip(bounds[:-1], bounds[1:],
                                                           strict=True)]
    all_a = np.concatenate([a for a, _ in calls])
    all_b = np.concatenate([b for _, b in calls])
    xy, st, ct = polys.xy, polys.start, polys.count
    intersects = shapely.intersects
    t_py, t_nb, t_py1, t_nb1 = (math.inf,) * 4
    for _ in range(repeat):  # (taking turns, so both meet the same load on the cores)
        t_py = min(t_py, _best(lambda: [intersects(a, b) for a, b in calls], 1))
        t_nb = min(t_nb, _best(lambda: [_meet_pairs(xy, st, ct, x, y, o)
                                        for x, y, o in slices], 1))
        t_py1 = min(t_py1, _best(lambda: intersects(all_a, all_b), 1))
        t_nb1 = min(t_nb1, _best(lambda: _meet_pairs(xy, st, ct, ja, jb, out), 1))
    return {"pairs": n, "calls": len(calls), "polygons": len(polys.geoms),
            "not convex": int(np.sum(~polys.convex)), "met": float(np.mean(truth)),
            "vertices": float(np.mean(polys.count[ja] + polys.count[jb])),
            "undecided": int(np.sum(out == 2)),
            "wrong": wrong, "compile": compile_s,
            "py_call": 1e6 * t_py / n, "nb_call": 1e6 * t_nb / n,
            "py_batch": 1e6 * t_py1 / n, "nb_batch": 1e6 * t_nb1 / n,
            "py_per_call": 1e6 * t_py / len(calls), "nb_per_call": 1e6 * t_nb / len(calls)}


# -- kernel B ------------------------------------------------------------------------------------
class _Store:
    """The few columns of an entry store ``blocked_among`` reads, for a recorded query."""

    def __init__(self, rows, geoms):
        self.rows = rows
        self.geom = np.empty(len(geoms), dtype=object)
        self.geom[:] = geoms


def kernel_b(rec: Recorder, repeat: int) -> dict:
    from lotsim.traffic.candidates import Near, blocked_among, pairs

    # pairs: each query's hulls and entries as arrays, made before timing (as a table
    # kept in arrays would hold them)
    qs = []
    for sw, near, offset, ordered, got in rec.pairs:
        srows = np.array(sw.rows, dtype=float).reshape(-1, 6)
        erows = np.array(near.rows, dtype=float).reshape(-1, 6)
        cap = max(1, len(srows) * len(erows))
        qs.append((sw, near, offset, ordered, got, srows, erows,
                   np.array(near.ids, dtype=np.int64), np.empty(cap, np.int64),
                   np.empty(cap, np.int64)))
    clock = time.perf_counter()
    q = qs[0]
    _pairs(q[5], q[6], q[7], 0.0, True, q[8], q[9])
    compile_p = time.perf_counter() - clock
    same = 0
    for _sw, _near, offset, ordered, got, srows, erows, ids, oj, oi in qs:
        m = _pairs(srows, erows, ids, 0.0 if offset is None else offset, offset is not None,
                   oj, oi)
        mine = (oj[:m].tolist(), oi[:m].tolist())
        if ordered:
            same += mine == (list(got[0]), list(got[1]))
        else:  # (any order asked for: the same pairs)
            same += sorted(zip(*mine, strict=True)) == sorted(zip(*got, strict=True))
    t_py = t_nb = math.inf
    for _ in range(repeat):
        t_py = min(t_py, _best(lambda: [pairs(q[0], q[1], q[2], q[3]) for q in qs], 1))
        t_nb = min(t_nb, _best(lambda: [_pairs(q[5], q[6], q[7], 0.0 if q[2] is None
                                               else q[2], q[2] is not None, q[8], q[9])
                                        for q in qs], 1))
    # blocked_among: the entries as they were at the query, numbered from 0
    polys = Polygons()
    bq = []
    for sw, among_rows, rows, geoms, since, until, got in rec.blocked:
        hs = [polys.of(g) for g in sw.geoms]
        es = [polys.of(g) for g in geoms]
        k = len(rows)
        bq.append((sw, Near(list(range(k)), among_rows), _Store(rows, geoms), since, until,
                   got, np.array(sw.rows, dtype=float).reshape(-1, 6),
                   np.array(among_rows, dtype=float).reshape(-1, 6),
                   np.array([r[:2] for r in rows], dtype=float).reshape(-1, 2), hs, es))
    polys.build()
    xy = polys.xy
    prepared = []
    for sw, near, st, since, until, got, srows, erows, trows, hs, es in bq:
        cap = max(1, len(srows) * len(erows))
        prepared.append((sw, near, st, since, until, got, srows, erows, trows,
                         polys.start[hs], polys.count[hs], polys.start[es], polys.count[es],
                         np.empty(cap), np.empty(cap), np.zeros(2, np.int64)))
    clock = time.perf_counter()
    p = prepared[0]
    _blocked(p[6], p[7], p[8], p[3], p[4], xy, *p[9:])
    compile_b = time.perf_counter() - clock
    same_b = undecided = 0
    for p in prepared:
        m = _blocked(p[6], p[7], p[8], p[3], p[4], xy, *p[9:])
        if m < 0:
            undecided += 1
            continue
        same_b += list(zip(p[13][:m].tolist(), p[14][:m].tolist(), strict=True)) == p[5]
    t_pyb = t_nbb = math.inf
    for _ in range(repeat):
        t_pyb = min(t_pyb, _best(lambda: [blocked_among(p[2], p[0], p[1], p[3], p[4])
                                          for p in prepared], 1))
        t_nbb = min(t_nbb, _best(lambda: [_blocked(p[6], p[7], p[8], p[3], p[4], xy, *p[9:])
                                          for p in prepared], 1))
    return {"pairs queries": len(qs), "pairs same": same, "compile pairs": compile_p,
            "py pairs": 1e6 * t_py / len(qs), "nb pairs": 1e6 * t_nb / len(qs),
            "blocked queries": len(prepared), "blocked same": same_b,
            "blocked undecided": undecided, "compile blocked": compile_b,
            "py blocked": 1e6 * t_pyb / len(prepared), "nb blocked": 1e6 * t_nbb / len(prepared),
            "pairs mean": float(np.mean([len(q[4][0]) for q in qs]))}


def kernel_heap(expansions: int, pushes: float, repeat: int) -> dict:
    """The heap's bookkeeping per expansion: ``pushes`` states opened per state expanded,
    keys as the search's (time + heuristic, ties by depth)."""
    rng = random.Random(SEED)
    n = int(expansions * pushes) + 1
    # f-values that grow as the search goes, each pushed within a spread of the frontier
    keys = np.array([k / pushes + 20.0 * rng.random() for k in range(n)])
    ties = -np.array([rng.random() for _ in range(n)])
    children = max(1, round(pushes))
    out = np.empty(expansions, dtype=np.int64)
    clock = time.perf_counter()
    _heap_walk(keys[:10], ties[:10], children, out[:2])
    compile_s = time.perf_counter() - clock
    keys_l, ties_l = keys.tolist(), ties.tolist()
    out_l = [0] * expansions
    t_py = t_nb = math.inf
    for _ in range(repeat):
        t_py = min(t_py, _best(lambda: _heap_walk_py(keys_l, ties_l, children, out_l), 1))
        t_nb = min(t_nb, _best(lambda: _heap_walk(keys, ties, children, out), 1))
    same = out.tolist() == out_l
    return {"compile": compile_s, "py": 1e6 * t_py / expansions,
            "nb": 1e6 * t_nb / expansions, "same": same, "children": children}


# -- report --------------------------------------------------------------------------------------
def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=400, help="cars in the day (400)")
    ap.add_argument("--rate", type=float, default=250.0, help="cars an hour (250)")
    ap.add_argument("--repeat", type=int, default=5, help="passes of each timing (5)")
    ap.add_argument("--validate", action="store_true",
                    help="also profile cold lotsim validate of surface364")
    ap.add_argument("--validate-only", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if numba is None:
        print("numba is not installed (pip install numba): the kernels need it; "
              "only the profiles run", file=sys.stderr)
    else:
        print(f"numba {numba.__version__}, shapely {shapely.__version__}, "
              f"Python {sys.version.split()[0]}")
    if not args.validate_only:
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "day.yaml"
            path.write_text(day_text(args.count, args.rate))
            day_report(path, args)
    if args.validate or args.validate_only:
        validate_report()
    return 0


def day_report(path: Path, args) -> None:
    import lotsim

    lotsim.prepare(str(path))  # (into the cache: each run below prepares afresh from it)
    plain, _ = run_day(path)
    per_exp = 1e6 * plain.seconds / plain.expansions
    # (the graphs' own tally of working out edge motions: read, not changed)
    motions = sum(g.tally.seconds for g in plain.prepared.search_graphs._graphs.values())
    print(f"\nday: {args.count} cars at {args.rate:g}/h on dlp_like: {plain.searches} "
          f"searches, {plain.expansions} expansions, {plain.seconds:.1f} s in the search: "
          f"{per_exp:.0f} µs per expansion (untouched run); of it, working out edge "
          f"motions (the graphs' tally) {motions:.1f} s: "
          f"{1e6 * (plain.seconds - motions) / plain.expansions:.0f} µs per expansion without")
    _, prof = run_day(path, profile=True)
    sh = search_shares(prof)
    total = sh["total"]
    print(f"\nsearch under cProfile: {total:.1f} s; share of it in")
    shares = {}
    for k, v in sh.items():
        if k in ("total", "table_by"):
            continue
        shares[k] = v / total
        print(f"  {k:<55} {v:7.1f} s  {100 * v / total:5.1f} %")
    print("  the table's queries called from the search, by query (shapely included):")
    for k, v in sorted(sh["table_by"].items(), key=lambda kv: -kv[1]):
        if v / total >= 0.002:
            print(f"    {k:<30} {v:7.1f} s  {100 * v / total:5.1f} %")
    if numba is None:
        return
    rec, _ = run_day(path, record=True)
    a = kernel_a(rec, args.repeat)
    print(f"\nkernel A: {a['pairs']} pairs in {a['calls']} calls, {a['polygons']} polygons "
          f"({a['not convex']} not convex polygons: left to shapely); answers differing "
          f"from shapely: {a['wrong']}; within {TOUCH:g} m of touching (left to shapely): "
          f"{a['undecided']}; {100 * a['met']:.0f} % of pairs meet, "
          f"{a['vertices']:.1f} vertices a pair")
    b = kernel_b(rec, args.repeat)
    print(f"kernel B: pairs on {b['pairs queries']} queries ({b['pairs mean']:.1f} pairs "
          f"each): {b['pairs same']} the same; blocked_among on {b['blocked queries']}: "
          f"{b['blocked same']} the same intervals, {b['blocked undecided']} left to "
          "shapely")
    pushes = 1_009_871 / 174_136  # (overwritten below from the profile's counts)
    stats = pstats.Stats(prof).stats
    n_push = sum(v[1] for k, v in stats.items() if k[2] == "push" and "search.py" in k[0])
    n_exp = sum(v[1] for k, v in stats.items() if k[2] == "expand" and "search.py" in k[0])
    if n_exp:
        pushes = n_push / n_exp
    hp = kernel_heap(min(plain.expansions, 200_000), pushes, args.repeat)
    rows = [
        ("A exact test, per pair (run's batches)", a["py_call"], a["nb_call"], a["compile"]),
        ("A exact test, per pair (one batch)", a["py_batch"], a["nb_batch"], None),
        ("B candidates.pairs, per query", b["py pairs"], b["nb pairs"], b["compile pairs"]),
        ("B blocked_among (+A), per query", b["py blocked"], b["nb blocked"],
         b["compile blocked"]),
        (f"heap: pop + {hp['children']} pushes, per expansion", hp["py"], hp["nb"],
         hp["compile"]),
    ]
    print(f"\n{'kernel':<44} {'today µs':>9} {'numba µs':>9} {'ratio':>7} {'compile s':>10}")
    for name, py, nb, comp in rows:
        c = f"{comp:10.2f}" if comp is not None else f"{'':>10}"
        print(f"{name:<44} {py:9.3f} {nb:9.3f} {py / nb:7.1f} {c}")
    # Amdahl: each part's share divided by its kernel's ratio
    r_exact = a["py_call"] / a["nb_call"]
    r_table = b["py blocked"] / b["nb blocked"]
    r_heap = hp["py"] / hp["nb"]
    f = list(shares.values())
    f_exact, f_table, f_heur, f_motion, f_exp = f
    ab = f_exact / r_exact + f_table / r_table + f_heur + f_motion + f_exp
    full = f_exact / r_exact + f_table / r_table + (f_heur + f_exp) / r_heap + f_motion
    full_pre = f_exact / r_exact + f_table / r_table + (f_heur + f_exp) / r_heap
    print(f"\nwhole search per expansion (Amdahl over the profile's shares; today "
          f"{per_exp:.0f} µs):")
    for name, frac in (("A + B called from today's Python search", ab),
                       ("C: loop, heap, heuristic compiled too; edge motions in Python", full),
                       ("C with every edge motion worked out beforehand (bound)", full_pre)):
        print(f"  {name:<64} {per_exp * frac:6.0f} µs  {1 / frac:5.1f}×")
    print(f"  (at most, the edge motions alone left: {1 / f_motion:.1f}×)")


def validate_report() -> None:
    path = str(ROOT / "scenarios" / "lots" / "surface364.yaml")
    ctx = mp.get_context("spawn")  # (a child of multiprocessing plans with one worker)
    queue = ctx.Queue()
    proc = ctx.Process(target=_validate_child, args=(path, queue))
    proc.start()
    got = queue.get()
    proc.join()
    tot = got["total"]
    print(f"\ncold lotsim validate surface364 (LOTSIM_CACHE_DIR=off), one process under "
          f"cProfile: {got['wall']:.1f} s wall, {tot:.1f} s profiled")
    for name, key in (("maneuver collision checks (validity.*_blocked)", "checks"),
                      ("  of which clearance.hulls_blocked", "hulls_blocked"),
                      ("shapely (own time, any caller)", "shapely")):
        print(f"  {name:<52} {got[key]:7.1f} s  {100 * got[key] / tot:5.1f} %")
    f = max(got["checks"], got["shapely"]) / tot
    print(f"  compiling the collision checks entirely (infinitely fast) gives at most "
          f"{1 / (1 - f):.2f}×")
    print("  heaviest by cumulative time:")
    for v, w, n in got["top"]:
        print(f"    {v:8.2f} s  {w}:{n}")


if __name__ == "__main__":
    sys.exit(main())
