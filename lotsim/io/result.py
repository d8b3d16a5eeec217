"""``result.json``: a run written out for checking and drawing (``docs/result.md``)."""

from __future__ import annotations

import contextlib
import dataclasses
import gzip
import io
import itertools
import json
import math
from collections.abc import Iterator
from pathlib import Path
from typing import IO

import numpy as np
import shapely

from lotsim import __version__
from lotsim.core.atomic import atomic_write
from lotsim.io.lot_json import lot_to_json
from lotsim.lot.uses import STANDARD
from lotsim.roadmap.model import LotGraph
from lotsim.scenario import Scenario
from lotsim.sim.results import RunResult, VehicleRun
from lotsim.vehicles.motion import Trajectory, motions_at

FORMAT = "lotsim-result"
VERSION = 1
SAMPLE_DT = 0.05
"""Interval of the samples of a moving vehicle in a result [s] (its ``settings.dt``):
fine enough that the pose interpolated between two samples stays within millimetres of
the planned path, which is what ``lotsim check`` verifies."""
SAMPLE_DECIMALS = {"t": 6, "x": 4, "y": 4, "theta": 6, "v": 4, "steer": 6, "gear": 0}
"""The decimals each column of a vehicle's samples is written to (1 µs, 0.1 mm, 1 µrad,
0.1 mm/s, 1 µrad; the gear a whole number)."""


def _ring(poly: shapely.Polygon) -> list[list[float]]:
    return np.round(np.asarray(poly.exterior.coords)[:-1], 4).tolist()


def _rings(geom) -> list[list[list[list[float]]]]:
    """A polygon or multipolygon as GeoJSON MultiPolygon coordinates: per polygon its
    outline, then its holes, each ring ``[[x, y], ...]`` without the closing point."""
    polys = [geom] if geom.geom_type == "Polygon" else list(geom.geoms)
    return [[np.round(np.asarray(ring.coords)[:-1], 4).tolist()
             for ring in (p.exterior, *p.interiors)] for p in polys if not p.is_empty]


def result_dict(rr: RunResult, *, progress=None) -> dict:
    """The JSON document of a run; ``progress(done, total)`` is called as each vehicle's
    motion is sampled (a thousand cars take seconds). A long run is better written by
    :func:`write_run`, which never holds more than one car's samples."""
    _not_written(rr)
    vehicles = []
    for k, v in enumerate(rr.vehicles):
        if progress is not None:
            progress(k, len(rr.vehicles))
        vehicles.append(vehicle_doc(v))
    if progress is not None:
        progress(len(rr.vehicles), len(rr.vehicles))
    return {"format": FORMAT, "version": VERSION, "lot": lot_doc(rr), "vehicles": vehicles,
            **tail_doc(rr)}


def lot_doc(rr: RunResult) -> dict:
    """The lot of a run's document (its ``lot``)."""
    return _lot_doc(rr.scenario, rr.lot_graph)


def _lot_doc(scenario: Scenario, lg: LotGraph) -> dict:
    lot = lg.lot
    parked = scenario.parked_vehicle
    g = lg.graph

    def portal(name: str, node: int) -> dict:
        x, y, th = g.nodes[node]["pose"]
        return {"id": name, "pose": [round(float(x), 4), round(float(y), 4),
                                     round(float(th), 6)]}

    doc_lot = {
        "name": scenario.name,
        "boundary": _ring(lot.boundary),
        "slots": [{"id": s.id, "kind": s.kind, "polygon": np.round(s.polygon, 4).tolist(),
                   "occupied": s.id in lot.occupied} | (
                       {} if s.use == STANDARD else {"use": s.use}) for s in lot.slots],
        "obstacles": [_ring(a.polygon) for a in lot.areas],
        "parked": [np.round(parked.footprints(
            np.array([s.centered_pose(parked.front, parked.rear)]))[0], 4).tolist()
            for s in lot.slots if s.id in lot.occupied],
        "speed_limit": round(lot.speed_limit, 6),
        "speed_zones": [{"id": z.id, "polygon": _ring(z.polygon), "limit": round(z.limit, 6)}
                        for z in lot.zones],
        "entrances": [portal(k, n) for k, n in lg.entrances.items()],
        "exits": [portal(k, n) for k, n in lg.exits.items()],
        "drawing": lot_to_json(lot),
    }
    if lot.pavement is not None:
        doc_lot["paved"] = _rings(lot.pavement)
    if lot.access_aisles:  # ground no car parks or drives on
        doc_lot["access_aisles"] = [{"id": a.id, "polygon": np.round(a.polygon, 4).tolist()}
                                    for a in lot.access_aisles]
    return doc_lot


def vehicle_doc(v: VehicleRun) -> dict:
    """One vehicle of a run's document (an item of its ``vehicles``), with its samples."""
    t = v.vehicle
    lim = t.limits
    tr = samples(v)
    cols: dict[str, list] = {key: [] for key in SAMPLE_DECIMALS}
    if tr is not None:
        cols = {key: (np.round(getattr(tr, key), k).tolist() if k else
                      getattr(tr, key).astype(int).tolist())
                for key, k in SAMPLE_DECIMALS.items()}
    doc = {
        "id": v.id,
        "type": {"name": t.name, "width": t.width, "front": t.front, "rear": t.rear,
                 "wheelbase": t.wheelbase, "max_steer": round(t.max_steer, 9),
                 "max_forward_speed": round(lim.max_forward_speed, 6),
                 "max_reverse_speed": round(lim.max_reverse_speed, 6),
                 "max_accel": lim.max_accel, "max_brake": lim.max_brake,
                 "max_jerk": lim.max_jerk, "max_steer_rate": round(lim.max_steer_rate, 9),
                 "max_lateral_accel": lim.max_lateral_accel} | (
                     {"marks": sorted(t.marks)} if t.marks else {}),
        "arrival": v.arrival.time,
        "entrance": v.arrival.entrance,
        "slot": v.slot,
        "status": v.status,
        "reason": v.reason,
        "samples": cols,
    }
    if v.arrival.inside:  # in the lot when it came: where it stood
        doc["inside"] = ({"slot": v.arrival.slot} if v.arrival.slot is not None
                         else {"pose": [round(float(c), 6) for c in v.arrival.pose]})
    return doc


def tail_doc(rr: RunResult) -> dict:
    """What a run's document holds after its vehicles: ``metrics``, ``settings`` and, when
    something met the plan, ``disturbances``."""
    s = rr.settings
    settings = {"planner": s.planner, "assignment": s.assignment, "seed": rr.seed,
                "dt": SAMPLE_DT, "omega": s.omega, "lotsim_version": __version__,
                "scenario": rr.scenario.name,
                "patience": rr.scenario.traffic.patience if rr.scenario.traffic else None}
    if s.planner == "whca":
        settings["window"] = s.window
    if s.order is not None:  # booked traffic, planned in this order
        settings["order"] = list(s.order)
        settings["horizon"] = s.horizon if math.isfinite(s.horizon) else None
    settings["tuning"] = dataclasses.asdict(s.tuning)
    settings["search"] = dataclasses.asdict(s.search)
    # how the lot was prepared: its build, its drivable graph and its parking maneuvers
    settings["lot"] = dataclasses.asdict(rr.scenario.lot.settings)
    settings["roadmap"] = dataclasses.asdict(rr.scenario.roadmap)
    settings["maneuvers"] = dataclasses.asdict(rr.scenario.maneuvers)
    # wall-clock timings differ run to run: they are printed, not written, so that the same
    # scenario and seed give the same file byte for byte
    metrics = {k: (round(v, 4) if isinstance(v, float) else v) for k, v in rr.metrics().items()
               if not k.startswith("planning_time")}
    doc = {"metrics": metrics, "settings": settings}
    if rr.execution is not None or rr.lot_changes is not None:  # what met the plan
        spec = rr.scenario.disturbances
        doc["disturbances"] = {"settings": spec.as_dict() if spec is not None else None,
                               **(rr.lot_changes.as_dict() if rr.lot_changes else {}),
                               **(rr.execution.as_dict() if rr.execution else {})}
    return doc


def write_run(rr: RunResult, path: str | Path, *, progress=None) -> None:
    """Write a run's document to ``path`` as :func:`write_json` writes
    :func:`result_dict`'s, byte for byte, but one vehicle at a time: a car's samples are
    made, written and let go before the next car's (a day's cars hold gigabytes as one
    document). Atomically, and compressed for a ``.gz`` path, as :func:`write_json`;
    ``progress(done, total)`` as :func:`result_dict`'s."""
    _not_written(rr)
    with ResultWriter(path, rr.scenario, rr.lot_graph) as out:
        n = len(rr.vehicles)
        for k, v in enumerate(rr.vehicles):
            if progress is not None:
                progress(k, n)
            out.add(v)
        if progress is not None:
            progress(n, n)
        out.finish(rr)


class ResultWriter:
    """A run's document written car by car, as :func:`write_run` writes it, byte for byte:
    the lot first, then each car as :meth:`add` is given it (in the result's order), and
    the metrics and settings once the run has ended (:meth:`finish`). Atomic: the file is
    at ``path`` only once the ``with`` block (or :meth:`close`) ends after :meth:`finish`;
    nothing is left there otherwise.

    For a run written as it goes, ``add`` is the run's ``release``
    (:class:`lotsim.sim.live.Live`): each car is written once it is done, and the run keeps
    only its figures (``lotsim.run(..., write=path)``).
    """

    def __init__(self, path: str | Path, scenario: Scenario, lot_graph: LotGraph):
        self._stack = contextlib.ExitStack()
        self._fh = self._stack.enter_context(_json_file(path))
        self._compact = str(path).endswith(COMPACT_SUFFIX)
        self.written = 0
        """Cars written so far."""
        self._ended = False
        self._fh.write(f'{{"format":{_dumps(FORMAT)},"version":{_dumps(VERSION)},'
                       f'"lot":{_dumps(_lot_doc(scenario, lot_graph))},"vehicles":[')

    def add(self, v: VehicleRun) -> None:
        """Write car ``v`` (made from its moves: before they are let go)."""
        doc = vehicle_doc(v)
        self._fh.write(("," if self.written else "")
                       + _dumps(compact_vehicle(doc) if self._compact else doc))
        self.written += 1

    def finish(self, rr: RunResult) -> None:
        """Write what follows the cars (:func:`tail_doc`) of the run whose cars were
        added, every one of them."""
        if self.written != len(rr.vehicles):
            raise ValueError(f"{self.written} cars written of the run's "
                             f"{len(rr.vehicles)}")
        tail = _dumps(tail_doc(rr))
        self._fh.write("]," + tail[1:] + "\n")  # the tail's keys, after the vehicles'
        self._ended = True

    def close(self) -> None:
        """Put the document at its path; before :meth:`finish`, leave nothing there and
        raise ``ValueError``."""
        if self._ended:
            self._stack.close()
            return
        unfinished = ValueError("the result was closed before the run ended (finish): "
                                "nothing is written")
        self._stack.__exit__(ValueError, unfinished, None)
        raise unfinished

    def __enter__(self) -> ResultWriter:
        return self

    def __exit__(self, kind, value, tb) -> None:
        if kind is not None:
            self._stack.__exit__(kind, value, tb)
        else:
            self.close()


def _not_written(rr: RunResult) -> None:
    """Refuse a run whose cars were written as it went (their moves let go)."""
    if any(v.written is not None for v in rr.vehicles):
        raise ValueError("this run's cars were written as it went (lotsim.run(..., write=)); "
                         "its moves are gone: read the file it wrote")


def _dumps(obj: object) -> str:
    """``obj`` as :func:`write_json` writes it."""
    return json.dumps(obj, separators=(",", ":"), allow_nan=False)


COMPACT_SUFFIX = ".gz"
"""A result file whose name ends so is written gzip-compressed (:func:`write_json`): the
compact form of a long run's result, which every reader of results reads as it reads
``result.json``."""


COMPACT_LEVEL = 6
"""gzip's level for the compact form: within 1 % of its smallest (level 9) at two thirds of
the time."""


def write_json(obj: dict, path: str | Path) -> None:
    """Write ``obj`` as JSON to ``path`` atomically: a temporary file in the same directory,
    renamed over the target; nothing is left behind on failure. A path ending in ``.gz``
    (:data:`COMPACT_SUFFIX`) is written gzip-compressed, with no time or name in its
    header, so that the same document gives the same bytes."""
    if str(path).endswith(COMPACT_SUFFIX) and isinstance(obj.get("vehicles"), list):
        obj = obj | {"vehicles": [compact_vehicle(v) for v in obj["vehicles"]]}
    with _json_file(path) as fh:
        json.dump(obj, fh, separators=(",", ":"), allow_nan=False)
        fh.write("\n")


SAMPLE_DIFFERENCES = 2
"""How many times the compact form differences each column's whole numbers: a moving car's
positions and clock change smoothly, so their second differences are small numbers that
repeat, which gzip then packs some three times tighter than the decimals themselves."""


def compact_vehicle(doc: dict) -> dict:
    """A vehicle of a run's document (:func:`vehicle_doc`) with its samples as the compact
    form writes them (docs/result.md): each column as whole numbers of its last decimal
    (:data:`SAMPLE_DECIMALS`) differenced :data:`SAMPLE_DIFFERENCES` times, each time with
    a zero before the first, and the ``encoding`` saying so. The numbers are those of the
    plain document: ``value = n / 10**decimals`` after summing up as many times.

    Examples
    --------
    >>> compact_vehicle({"id": "v1", "samples": {"t": [0.0, 0.05, 0.1], "x": [1.0, 1.1, 1.25],
    ...     "y": [0.0, 0.0, 0.0], "theta": [0.0, 0.0, 0.0], "v": [2.0, 2.0, 3.0],
    ...     "steer": [0.0, 0.0, 0.0], "gear": [1, 1, 1]}})["samples"]["x"]
    [10000, -9000, 500]
    """
    cols = doc["samples"]
    out: dict[str, object] = {"encoding": {"decimals": SAMPLE_DECIMALS,
                                           "differences": SAMPLE_DIFFERENCES}}
    for key, k in SAMPLE_DECIMALS.items():
        n = np.rint(np.asarray(cols[key], dtype=float) * 10.0 ** k).astype(np.int64)
        for _ in range(SAMPLE_DIFFERENCES):
            n = np.diff(n, prepend=0)
        out[key] = n.tolist()
    return doc | {"samples": out}


@contextlib.contextmanager
def _json_file(path: str | Path) -> Iterator[IO[str]]:
    """A text file to write JSON into, put at ``path`` when the block ends well (nothing
    otherwise): plain, or gzip-compressed for a ``.gz`` path, with no time in its header."""
    if not str(path).endswith(COMPACT_SUFFIX):
        with atomic_write(path, "w", encoding="utf-8") as fh:
            yield fh
        return
    with atomic_write(path, "wb") as raw, \
            gzip.GzipFile(filename="", mode="wb", fileobj=raw, mtime=0,
                          compresslevel=COMPACT_LEVEL) as gz, \
            io.TextIOWrapper(gz, encoding="utf-8") as fh:
        yield fh


def samples(v: VehicleRun, *, dt: float = SAMPLE_DT) -> Trajectory | None:
    """``v``'s motion sampled for a result: every ``dt`` [s] on a common clock (``k·dt``)
    while it moves, plus every start, stop and cusp; standing stretches only at their ends
    (gear 0). None when it never entered the lot."""
    moves = [m for m in v.moves if m.kind != "outside"]
    if not moves:
        return None
    # each move's sample times: the clock's instants k·dt within it, its start, its cusps and
    # its end, in its own time; all the moves' motions then sampled in one batch
    driven = [m for m in moves if m.motion is not None]
    taus = []
    if driven:
        t0 = np.array([m.t0 for m in driven])
        lo = np.floor(t0 / dt).astype(np.int64) + 1
        hi = np.ceil(np.array([m.t1 for m in driven]) / dt).astype(np.int64)
        n = np.maximum(hi - lo, 0)
        ks = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n - lo, n)
        # and each move's start, cusps and end, from its phases' running sums (as
        # Motion.cusps and Motion.duration make them)
        extra: list[float] = []
        owner: list[int] = []
        ends = []
        for j, m in enumerate(driven):
            acc = 0.0
            extra.append(acc)
            for ph in m.motion.phases:
                acc += ph.duration
                extra.append(acc)
            owner += [j] * (len(m.motion.phases) + 1)
            ends.append(acc)
        move = np.concatenate([np.repeat(np.arange(len(driven)), n), owner]).astype(np.int64)
        tau = np.concatenate([ks * dt - np.repeat(t0, n), extra])
        # sorted within each move, each instant once, and only those within the move
        order = np.lexsort((tau, move))
        move, tau = move[order], tau[order]
        first = np.ones(len(tau), dtype=bool)
        first[1:] = (move[1:] != move[:-1]) | (tau[1:] != tau[:-1])
        keep = first & (tau >= 0) & (tau <= np.array(ends)[move])
        move, tau = move[keep], tau[keep]
        bound = [0, *np.cumsum(np.bincount(move, minlength=len(driven))).tolist()]
        taus = [tau[a:z] for a, z in itertools.pairwise(bound)]
        p, speed, steer, gear = motions_at([m.motion for m in driven], taus,
                                           wheelbase=v.vehicle.wheelbase)
    parts: list[tuple[np.ndarray, ...]] = []
    k = 0
    for m in moves:
        if m.motion is None:  # standing
            pose = m.end_pose
            t = np.array([m.t0, m.t1])
            z = np.zeros(2)
            parts.append((t, z + pose[0], z + pose[1], z + pose[2], z, z + m.steer,
                          np.zeros(2, int)))
            continue
        a, z = bound[k], bound[k + 1]
        parts.append((m.t0 + taus[k], p[a:z, 0], p[a:z, 1], p[a:z, 2], speed[a:z],
                      steer[a:z], gear[a:z]))
        k += 1
    cols = [np.concatenate([p[k] for p in parts]) for k in range(7)]
    # one sample per instant: where moves meet the later move's first sample stays; two
    # samples microseconds apart (written to 1 µs) are one, at the earlier time
    # (a sample that stands for one at rest is at rest: a drive that sets off 2 µs before
    # a grid instant has rolled 1e-12 m/s by then, and the car stood until it set off)
    t = cols[0]
    near = np.append(np.diff(t) <= 2e-6, False)
    later = np.flatnonzero(near) + 1
    t[later] = t[later - 1]
    keep = ~near
    group = np.concatenate([[0], np.cumsum(keep[:-1])])  # the kept sample each one is
    rest = np.zeros(int(keep.sum()), dtype=bool)
    np.logical_or.at(rest, group, np.abs(cols[4]) < 1e-12)
    cols = [c[keep] for c in cols]
    # a sample at rest (a start, a stop, a cusp) is standing: gear 0
    cols[4] = np.where(rest, 0.0, cols[4])
    cols[6] = np.where(rest, 0, cols[6])
    return Trajectory(*cols)

