"""The rules on footprints over the common instants: overlap, parked, obstacle,
access_aisle, boundary, and no two vehicles holding one slot at once."""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely

from lotsim.verify.reading import _Lot, _Vehicle
from lotsim.verify.report import Violation, _add
from lotsim.verify.tolerances import GRID_DT, MAX_INSTANTS, SHRINK, FloatArray

_PAIR_BUDGET = 500_000  # candidate pairs tested per numpy batch (bounds memory)
_SAME = 1e-9  # interpolated poses closer than this are one standing footprint [m, rad]
_SURE = 1e-6  # margin [m] by which a quick test must clear a footprint before trusting it


@dataclass(slots=True)
class _Items:
    """Footprints over the instant grid: one per moving vehicle-instant, one per standing
    stretch ``[ka, kb]`` (instant indices, ``ka == kb`` for a moving one)."""

    veh: np.ndarray  # index into the vehicle list
    ka: np.ndarray
    kb: np.ndarray
    cx: FloatArray  # rectangle centre [m]
    cy: FloatArray
    ux: FloatArray  # heading unit vector
    uy: FloatArray
    hx: FloatArray  # true half length and half width [m]
    hy: FloatArray

    def __len__(self) -> int:
        return len(self.veh)

    @property
    def reach(self) -> FloatArray:
        """Circumradius of the shrunk rectangle [m]."""
        return np.hypot(self.hx - SHRINK, self.hy - SHRINK)

    def corners(self, idx: np.ndarray, inset: float = SHRINK) -> np.ndarray:
        """(N, 4, 2) corners of footprints ``idx``, each side moved in by ``inset`` [m]."""
        cx, cy, ux, uy = self.cx[idx], self.cy[idx], self.ux[idx], self.uy[idx]
        ax, ay = ux * (self.hx[idx] - inset), uy * (self.hx[idx] - inset)
        bx, by = -uy * (self.hy[idx] - inset), ux * (self.hy[idx] - inset)
        xs = np.stack([cx - ax - bx, cx + ax - bx, cx + ax + bx, cx - ax + bx], axis=1)
        ys = np.stack([cy - ay - by, cy + ay - by, cy + ay + by, cy - ay + by], axis=1)
        return np.stack([xs, ys], axis=-1)

    def polygons(self, idx: np.ndarray, inset: float = SHRINK) -> np.ndarray:
        return shapely.polygons(self.corners(idx, inset))


def _instant_range(t0: float, t1: float) -> tuple[int, int]:
    """First and last grid instant index within [t0, t1] [s] (empty when first > last)."""
    return math.ceil(t0 / GRID_DT - 1e-9), math.floor(t1 / GRID_DT + 1e-9)


def _first_instant_from(t: FloatArray) -> np.ndarray:
    """The first instant ``k`` with ``k · GRID_DT >= t`` (computed as the caller computes
    ``k · GRID_DT``), for each time ``t`` [s]."""
    k = np.ceil(t / GRID_DT).astype(np.int64)
    k -= (k - 1) * GRID_DT >= t
    k += k * GRID_DT < t
    return k


def _kept_instants(t: FloatArray, x: FloatArray, y: FloatArray, th: FloatArray, k0: int,
                   k1: int) -> np.ndarray:
    """The instants ``k0..k1`` a vehicle's footprints are interpolated at: all but those
    strictly inside a run of instants that fall between two samples of the same pose.

    Between two samples with equal ``x``, ``y`` and ``th`` linear interpolation gives that
    pose exactly at every instant, so the instants left out would only repeat it: the
    stretches found from the kept instants are the ones every instant gives. (A car
    parked for half an hour is sampled a few times but spans 36 000 instants.)
    """
    flat = np.flatnonzero((x[1:] == x[:-1]) & (y[1:] == y[:-1]) & (th[1:] == th[:-1]))
    lo = np.maximum(_first_instant_from(t[flat]), k0) + 1
    hi = np.minimum(_first_instant_from(t[flat + 1]) - 1, k1) - 1
    inside = hi >= lo
    lo, hi = lo[inside], hi[inside]  # the instants left out, [lo, hi]: disjoint, in order
    if not len(lo):
        return np.arange(k0, k1 + 1)
    start = np.concatenate([[k0], hi + 1])
    count = np.concatenate([lo, [k1 + 1]]) - start
    return np.repeat(start - np.cumsum(count) + count, count) + np.arange(int(count.sum()))


def _build_items(vehicles: list[_Vehicle], kmax: int) -> _Items | None:
    """The footprints of ``vehicles`` over the instants up to ``kmax``; None when they are
    interpolated at more than ``MAX_INSTANTS`` vehicle-instants (memory)."""
    cols: dict[str, list[np.ndarray]] = {k: [] for k in ("veh", "ka", "kb", "x", "y", "th")}
    interpolated = 0
    for j, veh in enumerate(vehicles):
        k0, k1 = _instant_range(veh.t[0], veh.t[-1])
        kend = k1 if veh.status == "departed" else kmax
        theta = np.unwrap(veh.theta)
        last = (veh.x[-1], veh.y[-1], theta[-1])
        if k1 >= k0:
            ks = _kept_instants(veh.t, veh.x, veh.y, theta, k0, k1)
            interpolated += len(ks)
            if interpolated > MAX_INSTANTS:
                return None
            tk = ks * GRID_DT
            px, py = np.interp(tk, veh.t, veh.x), np.interp(tk, veh.t, veh.y)
            pth = np.interp(tk, veh.t, theta)
            change = ((np.abs(np.diff(px)) > _SAME) | (np.abs(np.diff(py)) > _SAME)
                      | (np.abs(np.diff(pth)) > _SAME))
            starts = np.concatenate([[0], np.flatnonzero(change) + 1])
            ends = np.concatenate([starts[1:] - 1, [len(ks) - 1]])
            ka, kb = ks[starts], ks[ends].copy()
            x, y, th = px[starts], py[starts], pth[starts]
            if kend > k1:
                if max(abs(px[-1] - last[0]), abs(py[-1] - last[1]),
                       abs(pth[-1] - last[2])) <= _SAME:
                    kb[-1] = kend
                else:
                    ka, kb = np.append(ka, k1 + 1), np.append(kb, kend)
                    x, y, th = np.append(x, last[0]), np.append(y, last[1]), np.append(th,
                                                                                       last[2])
        elif kend >= k0:  # no instant while sampled, but it stays at its last pose
            ka, kb = np.array([k0]), np.array([kend])
            x, y, th = np.array([last[0]]), np.array([last[1]]), np.array([last[2]])
        else:
            continue
        cols["veh"].append(np.full(len(ka), j))
        for key, arr in (("ka", ka), ("kb", kb), ("x", x), ("y", y), ("th", th)):
            cols[key].append(arr)
    if not cols["veh"]:
        empty = np.zeros(0)
        return _Items(*(empty.astype(int),) * 3, *(empty,) * 6)
    # each column joined and its pieces let go at once: a run's footprints fill arrays of
    # millions, and the pieces of all six at once would double the peak
    veh_idx, ka, kb, x, y, th = (np.concatenate(cols.pop(key))
                                 for key in ("veh", "ka", "kb", "x", "y", "th"))
    front = np.array([v.front for v in vehicles])
    rear = np.array([v.rear for v in vehicles])
    width = np.array([v.width for v in vehicles])
    ux, uy = np.cos(th), np.sin(th)
    del th
    off = ((front - rear) / 2)[veh_idx]
    return _Items(veh_idx, ka, kb, x + ux * off, y + uy * off, ux, uy,
                  ((front + rear) / 2)[veh_idx], (width / 2)[veh_idx])


def _expand(lo: np.ndarray, hi: np.ndarray) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Batches of (row, position) for every position in ``[lo[row], hi[row])``."""
    counts = np.maximum(hi - lo, 0)
    cum = np.cumsum(counts)
    start = 0
    while start < len(lo):
        base = cum[start - 1] if start else 0
        stop = max(int(np.searchsorted(cum, base + _PAIR_BUDGET, side="right")), start + 1)
        n = counts[start:stop]
        if n.sum():
            row = np.repeat(np.arange(start, stop), n)
            pos = (np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
                   + np.repeat(lo[start:stop], n))
            yield row, pos
        start = stop


def _rects_overlap(items: _Items, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Whether shrunk footprints ``a[i]`` and ``b[i]`` intersect (separating axes)."""
    tx, ty = items.cx[b] - items.cx[a], items.cy[b] - items.cy[a]
    uax, uay, ubx, uby = items.ux[a], items.uy[a], items.ux[b], items.uy[b]
    hax, hay = items.hx[a] - SHRINK, items.hy[a] - SHRINK
    hbx, hby = items.hx[b] - SHRINK, items.hy[b] - SHRINK
    cos = np.abs(uax * ubx + uay * uby)  # |ua·ub| = |va·vb|
    sin = np.abs(uax * uby - uay * ubx)  # |ua·vb| = |va·ub|
    apart = np.abs(tx * uax + ty * uay) > hax + hbx * cos + hby * sin
    apart |= np.abs(-tx * uay + ty * uax) > hay + hbx * sin + hby * cos
    apart |= np.abs(tx * ubx + ty * uby) > hbx + hax * cos + hay * sin
    apart |= np.abs(-tx * uby + ty * ubx) > hby + hax * sin + hay * cos
    return ~apart


class _FirstOverlaps:
    """The first instant found so far at which each pair of vehicles overlaps.

    Pairs are keyed ``low · n + high`` by vehicle index; a candidate at an instant no
    earlier than the one known for its pair is dropped before the exact test, so a result
    whose vehicles overlap for minutes costs little more than a clean one.
    """

    def __init__(self, n_vehicles: int):
        self.n = n_vehicles
        self.key = np.zeros(0, dtype=np.int64)  # sorted
        self.k = np.zeros(0, dtype=np.int64)
        self.a = np.zeros(0, dtype=np.int64)  # the two footprints (item indices)
        self.b = np.zeros(0, dtype=np.int64)

    def pair_key(self, va: np.ndarray, vb: np.ndarray) -> np.ndarray:
        return np.minimum(va, vb).astype(np.int64) * self.n + np.maximum(va, vb)

    def news(self, key: np.ndarray, k: np.ndarray) -> np.ndarray:
        """Which candidates could still be the first overlap of their pair."""
        if not len(self.key):
            return np.ones(len(key), dtype=bool)
        pos = np.minimum(np.searchsorted(self.key, key), len(self.key) - 1)
        return ~((self.key[pos] == key) & (self.k[pos] <= k))

    def add(self, key: np.ndarray, k: np.ndarray, a: np.ndarray, b: np.ndarray) -> None:
        key, k = np.concatenate([self.key, key]), np.concatenate([self.k, k])
        a, b = np.concatenate([self.a, a]), np.concatenate([self.b, b])
        keep = _first_per_key(key[:, None], k)
        keep = keep[np.argsort(key[keep], kind="stable")]
        self.key, self.k, self.a, self.b = key[keep], k[keep], a[keep], b[keep]


def _test_pairs(items: _Items, a: np.ndarray, b: np.ndarray, k: np.ndarray,
                found: _FirstOverlaps, stats: dict[str, Any], reach: FloatArray) -> None:
    """Record the candidate pairs ``(a, b)`` at instants ``k`` that overlap in ``found``
    (``reach``: :attr:`_Items.reach`, computed once)."""
    va, vb = items.veh[a], items.veh[b]
    keep = (va != vb) & (np.hypot(items.cx[a] - items.cx[b], items.cy[a] - items.cy[b])
                         <= reach[a] + reach[b])
    a, b, k = a[keep], b[keep], k[keep]
    key = found.pair_key(items.veh[a], items.veh[b])
    keep = found.news(key, k)
    a, b, k, key = a[keep], b[keep], k[keep], key[keep]
    stats["footprint_tests"] += len(a)
    hit = _rects_overlap(items, a, b)
    if hit.any():
        found.add(key[hit], k[hit], a[hit], b[hit])


def _vehicle_overlaps(items: _Items, n_vehicles: int, stats: dict[str, Any]) -> _FirstOverlaps:
    """The first instant, and the footprints, of every pair of vehicles that overlap."""
    found = _FirstOverlaps(n_vehicles)
    if len(items) < 2:
        return found
    radius = items.reach
    reach = 2 * float(radius.max())
    moving = np.flatnonzero(items.ka == items.kb)
    standing = np.flatnonzero(items.ka < items.kb)
    kmin = int(items.ka.min())

    # moving with moving: sort and sweep along x within bands `reach` high, each band and
    # instant shifted far apart along x; a footprint meets its own band and the next one
    if len(moving) > 1:
        cx = items.cx[moving]
        width = float(cx.max() - cx.min()) + 2 * reach + 1.0
        band = np.floor((items.cy[moving] - items.cy[moving].min()) / reach)
        bands = float(band.max()) + 2
        key = ((items.ka[moving] - kmin) * bands + band) * width + cx
        order = np.argsort(key, kind="stable")
        sorted_key, ids = key[order], moving[order]
        own = (np.arange(len(ids)) + 1,
               np.searchsorted(sorted_key, sorted_key + reach, side="right"))
        above = (np.searchsorted(sorted_key, sorted_key + width - reach, side="left"),
                 np.searchsorted(sorted_key, sorted_key + width + reach, side="right"))
        for lo, hi in (own, above):
            for row, pos in _expand(lo, hi):
                a = ids[row]
                _test_pairs(items, a, ids[pos], items.ka[a], found, stats, radius)

    # standing with moving: moving footprints binned in cells of size `reach`, sorted by
    # (cell, instant), so each standing stretch meets a contiguous run per neighbour cell
    if len(standing) and len(moving):
        x0, y0 = float(items.cx.min()), float(items.cy.min())
        ix = np.floor((items.cx - x0) / reach).astype(np.int64)
        iy = np.floor((items.cy - y0) / reach).astype(np.int64)
        rows = int(iy.max()) + 3
        span = int(items.kb.max()) - kmin + 1
        cell = (ix + 1) * rows + (iy + 1)
        key = cell[moving] * span + (items.ka[moving] - kmin)
        order = np.argsort(key, kind="stable")
        sorted_key, ids = key[order], moving[order]
        shifts = np.array([dx * rows + dy for dx in (-1, 0, 1) for dy in (-1, 0, 1)])
        near_cells = (cell[standing][:, None] + shifts[None, :]).ravel()
        owner = np.repeat(standing, len(shifts))
        lo = np.searchsorted(sorted_key, near_cells * span + (items.ka[owner] - kmin), "left")
        hi = np.searchsorted(sorted_key, near_cells * span + (items.kb[owner] - kmin), "right")
        for row, pos in _expand(lo, hi):
            b = ids[pos]
            _test_pairs(items, owner[row], b, items.ka[b], found, stats, radius)

    # standing with standing: sweep along x, then the stretches must share an instant
    if len(standing) > 1:
        cx = items.cx[standing]
        order = np.argsort(cx, kind="stable")
        sorted_cx, ids = cx[order], standing[order]
        hi = np.searchsorted(sorted_cx, sorted_cx + reach, side="right")
        lo = np.arange(len(ids)) + 1
        for row, pos in _expand(lo, hi):
            a, b = ids[row], ids[pos]
            start = np.maximum(items.ka[a], items.ka[b])
            together = start <= np.minimum(items.kb[a], items.kb[b])
            _test_pairs(items, a[together], b[together], start[together], found, stats,
                        radius)
    return found


def _extents(items: _Items, idx: np.ndarray) -> tuple[FloatArray, FloatArray]:
    """Half the width and height [m] of the axis-aligned box around each shrunk footprint
    ``idx``, widened by ``_SURE`` so that rounding cannot make it smaller than the box of
    the corners :meth:`_Items.corners` computes."""
    a, b = items.hx[idx] - SHRINK, items.hy[idx] - SHRINK
    ux, uy = np.abs(items.ux[idx]), np.abs(items.uy[idx])
    return ux * a + uy * b + _SURE, uy * a + ux * b + _SURE


def _near_polygons(items: _Items, polys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The (footprint, polygon) pairs that may intersect: every other pair is apart.

    Broad phase: footprint centres binned in a grid of cells as large as the largest
    footprint box, so a polygon's box, widened by that, meets a run of cells per column;
    then the pairs whose boxes meet; then the pairs that no side of the footprint separates
    from the polygon's vertices (a separating line proves two shapes apart, so no pair
    that intersects is ever left out; the rest are tested exactly by the caller).
    """
    none = np.zeros(0, dtype=np.int64)
    every = np.arange(len(items))
    ex, ey = _extents(items, every)
    bounds = shapely.bounds(polys)  # (P, 4)
    size = max(float(ex.max()), float(ey.max()))
    x0, y0 = float(items.cx.min()), float(items.cy.min())
    ix = np.floor((items.cx - x0) / size).astype(np.int64)
    iy = np.floor((items.cy - y0) / size).astype(np.int64)
    rows = int(iy.max()) + 1
    order = np.argsort(ix * rows + iy, kind="stable")
    sorted_key = (ix * rows + iy)[order]
    # each polygon's box, widened by the largest footprint box, in cells (clipped)
    lo_x = np.floor((bounds[:, 0] - size - x0) / size).astype(np.int64)
    hi_x = np.floor((bounds[:, 2] + size - x0) / size).astype(np.int64)
    lo_y = np.clip(np.floor((bounds[:, 1] - size - y0) / size).astype(np.int64), 0, rows - 1)
    hi_y = np.clip(np.floor((bounds[:, 3] + size - y0) / size).astype(np.int64), 0, rows - 1)
    width = np.maximum(hi_x - lo_x + 1, 0)
    poly = np.repeat(np.arange(len(polys)), width)
    column = lo_x[poly] + np.arange(int(width.sum())) - np.repeat(np.cumsum(width) - width,
                                                                   width)
    start = np.searchsorted(sorted_key, column * rows + lo_y[poly], side="left")
    stop = np.searchsorted(sorted_key, column * rows + hi_y[poly], side="right")
    found_item, found_poly = [none], [none]
    for row, pos in _expand(start, stop):
        it, p = order[pos], poly[row]
        apart = ((items.cx[it] + ex[it] < bounds[p, 0]) | (items.cx[it] - ex[it] > bounds[p, 2])
                 | (items.cy[it] + ey[it] < bounds[p, 1])
                 | (items.cy[it] - ey[it] > bounds[p, 3]))
        found_item.append(it[~apart])
        found_poly.append(p[~apart])
    item, p = np.concatenate(found_item), np.concatenate(found_poly)
    if not len(item):
        return item, p
    # the footprint's own axes: the polygon's vertices all beyond one of its sides
    coords, which = shapely.get_coordinates(polys, return_index=True)
    count = np.bincount(which, minlength=len(polys))
    first = np.cumsum(count) - count
    most = int(count.max())
    pad = np.minimum(first[:, None] + np.arange(most)[None, :], (first + count - 1)[:, None])
    vx, vy = coords[pad, 0][p], coords[pad, 1][p]  # (pairs, most): repeats pad the short
    dx, dy = vx - items.cx[item][:, None], vy - items.cy[item][:, None]
    ux, uy = items.ux[item][:, None], items.uy[item][:, None]
    along, across = dx * ux + dy * uy, dy * ux - dx * uy
    a = (items.hx[item] - SHRINK + _SURE)[:, None]
    b = (items.hy[item] - SHRINK + _SURE)[:, None]
    apart = ((along > a).all(axis=1) | (along < -a).all(axis=1)
             | (across > b).all(axis=1) | (across < -b).all(axis=1))
    return item[~apart], p[~apart]


def _surely_covered(items: _Items, idx: np.ndarray, boundary) -> np.ndarray:
    """Which footprints ``idx`` certainly lie within ``boundary``: their box (widened by
    ``_SURE``) lies within the boundary's box and meets the box of no piece of that box
    outside the boundary. False says nothing: those are tested exactly."""
    ex, ey = _extents(items, idx)
    cx, cy = items.cx[idx], items.cy[idx]
    bx0, by0, bx1, by1 = boundary.bounds
    sure = (cx - ex >= bx0) & (cx + ex <= bx1) & (cy - ey >= by0) & (cy + ey <= by1)
    pieces = shapely.get_parts(shapely.difference(shapely.box(bx0, by0, bx1, by1), boundary))
    for x0, y0, x1, y1 in shapely.bounds(pieces[~shapely.is_empty(pieces)]):
        sure &= (cx + ex < x0) | (cx - ex > x1) | (cy + ey < y0) | (cy - ey > y1)
    return sure


def _first_per_key(keys: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Indices of the smallest ``k`` for each distinct row of ``keys`` (N, m)."""
    if len(k) == 0:
        return np.zeros(0, dtype=int)
    order = np.lexsort((k, *keys.T[::-1]))
    sk = keys[order]
    first = np.ones(len(order), dtype=bool)
    first[1:] = np.any(sk[1:] != sk[:-1], axis=1)
    return order[first]


def _check_footprints(vehicles: list[_Vehicle], lot: _Lot, out: list[Violation],
                      stats: dict[str, Any]) -> None:
    """Rule 6 (overlap, parked, obstacle, boundary, pavement) and slot sharing (rule 7)."""
    if not vehicles:
        return
    first, last = min(v.t[0] for v in vehicles), max(v.t[-1] for v in vehicles)
    kmin = _instant_range(first, first)[0]
    # up to the first instant at or after the last sample: a vehicle that stays holds its
    # last pose from then on, also when that sample comes after the last instant before it
    kmax = _instant_range(last, last)[0]
    items = _build_items(vehicles, kmax)
    if items is None:
        _add(out, "internal", None, None, f"the vehicles' poses differ at more than "
             f"{MAX_INSTANTS} vehicle-instants, more than the footprint rules handle")
        return
    stats["instants"] = max(kmax - kmin + 1, 0)
    stats["footprints"] = len(items)
    stats["vehicle_instants"] = int((items.kb - items.ka + 1).sum())
    if not len(items):
        return
    ids = [v.id for v in vehicles]

    # vehicle with vehicle
    found = _vehicle_overlaps(items, len(vehicles), stats)
    for i in np.argsort(found.k, kind="stable"):
        k = int(found.k[i])
        first, second = sorted((int(found.a[i]), int(found.b[i])),
                               key=lambda it: ids[items.veh[it]])
        area = shapely.area(shapely.intersection(
            *items.polygons(np.array([first, second]), inset=0.0)))
        _add(out, "overlap", ids[items.veh[first]], k * GRID_DT,
             f"{ids[items.veh[first]]} and {ids[items.veh[second]]} overlap at "
             f"t={k * GRID_DT:.2f} s ({area:.2f} m²)")

    reach = float(items.reach.max())
    margin = reach * 1.05 + 0.05  # covers the polygonal approximation of buffer arcs
    # with the cars parked at start and the obstacles
    env = [("parked", i, p) for i, p in enumerate(lot.parked)]
    env += [("obstacle", i, p) for i, p in enumerate(lot.obstacles)]
    env += [("access_aisle", i, p) for i, (_, p) in enumerate(lot.access_aisles)]
    if env:
        polys = np.array([p for _, _, p in env], dtype=object)
        item, q_env = _near_polygons(items, polys)
        stats["footprint_tests"] += len(item)
        hit = shapely.intersects(items.polygons(item), polys[q_env])
        item, q_env = item[hit], q_env[hit]
        keys = np.stack([items.veh[item], q_env], axis=1)
        for i in _first_per_key(keys, items.ka[item]):
            it, (kind, j, poly) = int(item[i]), env[int(q_env[i])]
            k = int(items.ka[it])
            foot = items.polygons(np.array([it]), inset=0.0)[0]
            area = shapely.area(shapely.intersection(foot, poly))
            what = (f"the car parked at start lot.parked[{j}]" if kind == "parked"
                    else f"access aisle {lot.access_aisles[j][0]} (lot.access_aisles[{j}])"
                    if kind == "access_aisle" else f"obstacle lot.obstacles[{j}]")
            name = ids[items.veh[it]]
            _add(out, kind, name, k * GRID_DT,
                 f"{name} overlaps {what} at t={k * GRID_DT:.2f} s ({area:.2f} m²)")

    # inside the boundary, and on the pavement where the lot says what is paved
    for rule, region, what in (("boundary", lot.boundary, "the lot boundary"),
                               ("pavement", lot.paved, "the pavement")):
        if region is not None:
            _check_within(items, region, margin, rule, what, ids, out, stats)

    _check_slot_sharing(vehicles, items, lot, kmax, out, stats)


def _check_within(items: _Items, region, margin: float, rule: str, what: str,
                  ids: list[str], out: list[Violation], stats: dict[str, Any]) -> None:
    """Every footprint lies within ``region``; the first instant each vehicle leaves it is
    reported under ``rule``."""
    inner = region.buffer(-margin)
    sure = np.zeros(len(items), dtype=bool)
    if not inner.is_empty:
        shapely.prepare(inner)
        sure = shapely.contains_xy(inner, items.cx, items.cy)
    unsure = np.flatnonzero(~sure)
    unsure = unsure[~_surely_covered(items, unsure, region)]
    shapely.prepare(region)
    polys = items.polygons(unsure)
    stats["footprint_tests"] += len(unsure)
    outside = unsure[~shapely.covers(region, polys)]
    for i in _first_per_key(items.veh[outside][:, None], items.ka[outside]):
        it = int(outside[i])
        k = int(items.ka[it])
        foot = items.polygons(np.array([it]), inset=0.0)[0]
        area = shapely.area(shapely.difference(foot, region))
        name = ids[items.veh[it]]
        _add(out, rule, name, k * GRID_DT,
             f"{name} leaves {what} at t={k * GRID_DT:.2f} s ({area:.2f} m² outside)")


def _check_slot_sharing(vehicles: list[_Vehicle], items: _Items, lot: _Lot, kmax: int,
                        out: list[Violation], stats: dict[str, Any]) -> None:
    """No two vehicles hold one slot at the same instant."""
    holders: dict[str, list[int]] = {}
    for j, veh in enumerate(vehicles):
        if veh.slot in lot.slots:
            holders.setdefault(veh.slot, []).append(j)
    by_vehicle = np.argsort(items.veh, kind="stable")  # each vehicle's footprints, in order
    bounds = np.searchsorted(items.veh[by_vehicle], np.arange(len(vehicles) + 1))
    for sid, members in holders.items():
        if len(members) < 2:
            continue
        poly = lot.slots[sid].polygon
        shapely.prepare(poly)
        # the holders' footprints (not every footprint of the run) whose centre is in it
        theirs = np.sort(np.concatenate([by_vehicle[bounds[j]:bounds[j + 1]] for j in members]))
        cand = theirs[shapely.intersects_xy(poly, items.cx[theirs], items.cy[theirs])]
        stats["footprint_tests"] += len(cand)
        inside = cand[shapely.covers(poly, items.polygons(cand))]
        held: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        for j in members:
            mine = inside[items.veh[inside] == j]
            ka, kb = items.ka[mine], items.kb[mine]
            veh = vehicles[j]
            if veh.status == "parked":
                k_end = _instant_range(veh.t[-1], veh.t[-1])[0]  # <= kmax
                ka, kb = np.append(ka, k_end), np.append(kb, kmax)
            held[j] = (ka, kb)
        clashes = []
        for n, j in enumerate(members):
            for m in members[n + 1:]:
                (a0, a1), (b0, b1) = held[j], held[m]
                if not len(a0) or not len(b0):
                    continue
                lo = np.maximum(a0[:, None], b0[None, :])
                common = lo[lo <= np.minimum(a1[:, None], b1[None, :])]
                if common.size:
                    clashes.append((int(common.min()), j, m))
        for k, j, m in sorted(clashes):
            a, b = vehicles[j].id, vehicles[m].id
            _add(out, "slot", a, k * GRID_DT,
                 f"slot {sid} is held by {a} and {b} at once from t={k * GRID_DT:.2f} s")
