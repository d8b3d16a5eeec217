"""A lot's parking maneuvers handed to the roadmap as plain links
(:class:`~lotsim.roadmap.model.ParkingLink`): where each begins, its gears, lengths, the
speed limit along it and its time for its vehicle type, worked out here, so that the
roadmap only records them (:func:`~lotsim.roadmap.assemble.build_graph`)."""

from __future__ import annotations

from collections.abc import Iterable

from lotsim.core.keys import inputs, key_of
from lotsim.core.workers import fork_map
from lotsim.lot.model import Lot
from lotsim.maneuvers.maneuver import Maneuver
from lotsim.roadmap.lanes import path_speed_limit
from lotsim.roadmap.model import ParkingLink
from lotsim.vehicles.model import VehicleType


@inputs
class PathTiming:
    """What a maneuver's time for a vehicle type depends on: the type's whole description,
    the speed limit along it [m/s] and its pieces' shapes (distance [m], curvature [1/m],
    sharpness [1/m²] each), not where they lie."""

    vehicle: VehicleType
    limit: float
    shapes: tuple[tuple[float, float, float], ...]


def parking_links(lot: Lot, maneuvers: dict[tuple[str, str, str], Maneuver],
                  park_only: dict[tuple[str, str, str], Maneuver] | None = None,
                  vehicles: Iterable[VehicleType] = (), known: dict | None = None
                  ) -> list[ParkingLink]:
    """The links of ``maneuvers`` (``(vehicle name, slot id, lane id)`` → Maneuver, from
    :func:`~lotsim.maneuvers.batch.plan_lot`), each with its way out, then those of
    ``park_only`` (the same, for cars that will not leave: no way out), in their order.

    Each is timed for its type among ``vehicles`` (a type not among them: not timed). A
    lot's maneuvers repeat a few shapes: each shape is timed once for a type and limit,
    on the workers, or taken from ``known`` (the roadmap store: a duration is a function
    of the shape, the type and the limit, :class:`PathTiming`), where those timed now are
    kept."""
    park_only = park_only or {}
    types = {v.name: v for v in vehicles}
    leaving = {key: m.reversed() for key, m in maneuvers.items()}  # each way out
    limits = {id(m): _limit(lot, m) for m in (*maneuvers.values(), *park_only.values())}
    paths = [(path, key[0], limits[id(m)]) for key, m in maneuvers.items()
             for path in (m, leaving[key])]
    paths += [(m, key[0], limits[id(m)]) for key, m in park_only.items()]
    timed = _timed(paths, types, known)
    links = []
    for (vname, sid, lid), m in maneuvers.items():
        back = leaving[vname, sid, lid]
        links.append(ParkingLink(
            vname, sid, lid, m.station, limits[id(m)], m, m.gears[0], m.length,
            timed(m, vname), back, back.gears[0], back.length, timed(back, vname)))
    for (vname, sid, lid), m in park_only.items():
        links.append(ParkingLink(vname, sid, lid, m.station, limits[id(m)], m, m.gears[0],
                                 m.length, timed(m, vname)))
    return links


def _limit(lot: Lot, m: Maneuver) -> float:
    """The speed limit along ``m`` [m/s]: the lowest of the zones it runs in
    (:func:`~lotsim.roadmap.lanes.path_speed_limit`, as the roadmap reads its own paths)."""
    return path_speed_limit(lot, lambda step: m.sample(step)[0])


def _timed(paths: list[tuple[Maneuver, str, float]], types: dict[str, VehicleType],
           known: dict | None):
    """``timed(path, type name)`` [s] of each of ``paths`` (path, type name, limit) whose
    type is in ``types`` (else None), each shape timed once (:func:`parking_links`)."""
    # each path's key by its id and type (every path is held by the caller; one maneuver
    # may serve two types)
    keys: dict[tuple[int, str], tuple] = {}
    todo: dict[tuple, tuple] = {}
    for path, vname, limit in paths:
        if vname in types:
            key = keys[id(path), vname] = (vname, limit, path.shapes())
            todo.setdefault(key, (path, vname, limit))
    # each shape by its key in ``known``: the type's whole description, not its name
    stored = {}
    if known is not None:
        stored = {key: key_of(PathTiming(types[key[0]], key[1], key[2])) for key in todo}
    timed = {key: known[name] for key, name in stored.items() if name in known}
    jobs = [(key, job) for key, job in todo.items() if key not in timed]
    parts = [jobs[k::8] for k in range(8)] if len(jobs) >= 64 else [jobs]
    times = fork_map(lambda part: [p.duration(types[v], lim) for _, (p, v, lim) in part],
                     parts)
    for part, ts in zip(parts, times, strict=True):
        for (key, _), t in zip(part, ts, strict=True):
            timed[key] = t
            if known is not None:
                known[stored[key]] = t

    def time_of(path: Maneuver, vname: str) -> float | None:
        key = keys.get((id(path), vname))
        return None if key is None else timed[key]

    return time_of
