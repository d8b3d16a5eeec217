"""What a run gives back: each vehicle's story (:class:`VehicleRun`) and the run as a whole
(:class:`RunResult`, with its :meth:`~RunResult.metrics`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lotsim.roadmap.model import LotGraph
from lotsim.scenario import Scenario
from lotsim.sim.settings import RunSettings
from lotsim.traffic.demand import Arrival
from lotsim.traffic.plans import Move
from lotsim.vehicles.model import VehicleType

STATUSES = ("parked", "departed", "waiting", "rejected")
"""What became of a vehicle when the run ended: it parked (and stays), it parked and left
again, it is still waiting (to get in or out), or it was turned away after its patience."""
HOURLY_FROM = 3
"""Traffic whose cars came over this many hours of the run's clock or more is also told hour
by hour (:meth:`RunResult.hourly`): ``lotsim run`` prints the run's hours, ``lotsim bench``
a table by hour for each row of its table."""


@dataclass
class VehicleRun:
    """One vehicle's part of a run."""

    arrival: Arrival
    vehicle: VehicleType
    slot: str | None = None
    status: str = "waiting"
    reason: str = ""
    moves: list[Move] = field(default_factory=list)
    parked_at: float | None = None
    parked_pose: tuple[float, float, float] | None = None
    depart_at: float | None = None
    leaving: bool = False
    left_at: float | None = None
    searches: int = 0
    failures: int = 0  # failed searches in a row
    expansions: int = 0
    planning_time: float = 0.0
    done: bool = False  # nothing more will happen to it
    waited_outside: float = 0.0  # before it was rejected [s]; 0 when rejected on arrival
    seen: int = 0  # the reservation table's releases when it last searched
    written: Written | None = None
    """What the run's figures read of its moves, once they were written out as the run went
    and let go (:func:`let_go`; its ``moves`` are then empty); None while it has them."""

    @property
    def id(self) -> str:
        return self.arrival.id

    @property
    def end(self) -> float | None:
        """When its last move ends [s] (None: it has none), its moves let go or not."""
        if self.written is not None:
            return self.written.end
        return self.moves[-1].t1 if self.moves else None


@dataclass(frozen=True, slots=True)
class Written:
    """What :meth:`RunResult.metrics`, :meth:`~RunResult.trip_figures` and
    :meth:`~RunResult.hourly` read of a car's moves, kept when the moves are let go: the
    length of each of its waits (inside and outside, in order) [s], when its plan began
    (None: never), when its last move ended (None: no move) and its standing
    (:func:`standing_times`) [s]. The same floats as the moves give."""

    waits: tuple[float, ...]
    start: float | None
    end: float | None
    standing: tuple[float, float, float]


def let_go(v: VehicleRun) -> None:
    """Keep of ``v``'s moves only what the run's figures read (:class:`Written`), and let
    the moves go: for a car done and written out while the run goes on (a day's run then
    holds the cars present, not those served)."""
    if v.written is not None:
        return
    v.written = Written(tuple(_waits(v)), _start(v), v.end, standing_times(v))
    v.moves = []


@dataclass
class RunResult:
    """What :func:`lotsim.sim.running.simulate` returns: the lot, the settings and every
    vehicle's story."""

    scenario: Scenario
    lot_graph: LotGraph
    settings: RunSettings
    seed: int
    vehicles: list[VehicleRun]
    planning_time: float
    """Seconds the run took to plan, less :attr:`motion_time`."""
    ordering: dict = field(default_factory=dict)
    """How the planning order was chosen (:func:`lotsim.sim.orders.plan_run`); empty when
    :func:`lotsim.sim.running.simulate` was called directly."""
    motion_time: float = 0.0
    """Seconds it spent (searching, or reserving what the searches found) working out edge
    motions and their swept hulls that no earlier run on the lot in this process had (the
    lot's search graphs keep them): a lot's first runs pay it, later ones little; planning
    times leave it out, so that runs are timed alike whatever ran before them."""
    lot_changes: Any = None
    """The closures and bays taken the run met, and the repairs they took
    (:class:`lotsim.sim.repairs.LotChanges`); None when the lot stayed as it was."""
    execution: Any = None
    """How the run was driven through its disturbances
    (:class:`lotsim.sim.execution.Execution`), its vehicles' moves being those executed;
    None for a run as planned."""

    def __repr__(self) -> str:
        """One line (the whole story is in :meth:`metrics`, ``.vehicles`` and
        :func:`~lotsim.io.result.result_dict`): ``<RunResult quickstart: 6 vehicles, 6
        served, 0 waiting, 0 rejected; planner hca, seed 1>``."""
        m = self.metrics()
        return (f"<RunResult {self.scenario.name}: {m['vehicles']} vehicles, {m['served']} "
                f"served, {m['waiting']} waiting, {m['rejected']} rejected; planner "
                f"{self.settings.planner}, seed {self.seed}>")

    def metrics(self) -> dict[str, float]:
        """Counts by status (``served``: parked and departed) and the timing figures of
        ``docs/result.md``."""
        out: dict[str, float] = {s: 0 for s in STATUSES}
        for v in self.vehicles:
            out[v.status] += 1
        out["served"] = out["parked"] + out["departed"]
        out["vehicles"] = len(self.vehicles)
        park = _times_to_park(self.vehicles)
        out["mean_time_to_park"] = float(np.mean(park)) if park else 0.0
        out["max_time_to_park"] = float(np.max(park)) if park else 0.0
        out["total_waiting"] = float(sum(w for v in self.vehicles for w in _waits(v))
                                     + sum(_queued(v) for v in self.vehicles)
                                     + sum(v.waited_outside for v in self.vehicles
                                           if v.status == "rejected"))
        ends = [e for v in self.vehicles if (e := v.end) is not None]
        out["makespan"] = float(max(ends)) if ends else 0.0
        out["planning_time"] = self.planning_time
        out["planning_time_motions"] = self.motion_time
        out["expansions"] = int(sum(v.expansions for v in self.vehicles))
        out["searches"] = int(sum(v.searches for v in self.vehicles))
        per = [v.planning_time for v in self.vehicles if v.searches]
        out["planning_time_median"] = float(np.median(per)) if per else 0.0
        out["planning_time_p95"] = float(np.percentile(per, 95)) if per else 0.0
        return out

    def trip_figures(self) -> dict[str, float]:
        """What a lot's traffic costs its cars, for benchmarks (``docs/bench.md``): median
        and 90th percentile of the time to park (arrival to standing in the slot) and of the
        time to leave (the end of the dwell to passing the exit), and the standing per car
        (:func:`standing_times`) in all and split into queued outside, on the way in and on the
        way out, over every car of the traffic [s]."""
        park = _times_to_park(self.vehicles)
        leave = [v.left_at - wanted for v in self.vehicles
                 if v.left_at is not None and (wanted := _wants_to_leave(v)) is not None]
        parts = np.array([standing_times(v) for v in self.vehicles]).reshape(-1, 3)
        n = max(len(self.vehicles), 1)
        out = {}
        for name, xs in (("time_to_park", park), ("time_to_leave", leave)):
            out[f"median_{name}"] = float(np.median(xs)) if xs else 0.0
            out[f"p90_{name}"] = float(np.percentile(xs, 90)) if xs else 0.0
        total = parts.sum(axis=0)
        out["standing_per_car"] = float(total.sum() / n)
        for k, where in enumerate(("outside", "in", "out")):
            out[f"standing_{where}_per_car"] = float(total[k] / n)
        return out


    def hourly(self) -> list[dict[str, float]]:
        """The run hour by hour of its clock, each car counted in the hour it arrived
        (``[h·3600, (h+1)·3600)`` s; a day's clock that starts at midnight gives hours of
        the day), from the first arrival's hour to the last's: ``hour``, ``arrivals``,
        ``parked`` (those that came to stand in a slot), ``rejected``, ``median`` and
        ``p90_time_to_park`` [s] and ``standing_per_car`` [s] (:func:`standing_times`, over the
        hour's cars). An hour no car arrived in has zeros.

        Examples
        --------
        >>> import lotsim
        >>> [(h["hour"], h["arrivals"]) for h in lotsim.run(lotsim.EXAMPLE).hourly()]
        [(0, 3)]
        """
        by: dict[int, list[VehicleRun]] = {}
        for v in self.vehicles:
            by.setdefault(int(np.floor(v.arrival.time / 3600.0)), []).append(v)
        if not by:
            return []
        out = []
        for hour in range(min(by), max(by) + 1):
            cars = by.get(hour, [])
            park = _times_to_park(cars)
            out.append({
                "hour": hour, "arrivals": len(cars),
                "parked": sum(v.parked_at is not None and v.arrival.slot is None for v in cars),
                "rejected": sum(v.status == "rejected" for v in cars),
                "median_time_to_park": float(np.median(park)) if park else 0.0,
                "p90_time_to_park": float(np.percentile(park, 90)) if park else 0.0,
                "standing_per_car": (float(sum(sum(standing_times(v)) for v in cars) / len(cars))
                                     if cars else 0.0)})
        return out


def _times_to_park(vehicles: list[VehicleRun]) -> list[float]:
    """From arrival to standing in the slot [s], for each car that parked (not those that
    stood in their bay when they came)."""
    return [v.parked_at - v.arrival.time for v in vehicles
            if v.parked_at is not None and v.arrival.slot is None]


def _waits(v: VehicleRun):
    """The length of each of ``v``'s waits, inside and outside, in order [s]."""
    if v.written is not None:
        return v.written.waits
    return (m.t1 - m.t0 for m in v.moves if m.kind in ("wait", "outside"))


def _start(v: VehicleRun) -> float | None:
    """When ``v``'s first move began [s] (None: it has none)."""
    if v.written is not None:
        return v.written.start
    return next((m.t0 for m in v.moves), None)


def _queued(v: VehicleRun) -> float:
    """Time spent queued outside before the plan that brought it in began [s]."""
    start = _start(v)
    if start is None:
        return 0.0
    return max(0.0, start - v.arrival.time)


def _wants_to_leave(v: VehicleRun) -> float | None:
    """When ``v`` wanted to leave: the end of its dwell after it parked [s]; None for a car
    that stays."""
    if v.parked_at is None or v.arrival.dwell is None:
        return None
    return v.parked_at + v.arrival.dwell


def standing_times(v: VehicleRun) -> tuple[float, float, float]:
    """The time ``v`` stood still when it wanted to move [s]: queued outside (before the
    plan that brought it in, or until it was turned away), standing on the way in (its
    waits before it parked), and on the way out (from the end of its dwell to the first
    move of its way out, and its waits after that)."""
    if v.written is not None:
        return v.written.standing
    outside = _queued(v) + v.waited_outside + sum(
        m.t1 - m.t0 for m in v.moves if m.kind == "outside")
    parked = v.parked_at if v.parked_at is not None else float("inf")
    way_in = sum(m.t1 - m.t0 for m in v.moves if m.kind == "wait" and m.t0 < parked)
    wanted = _wants_to_leave(v)
    if wanted is None:
        return outside, way_in, 0.0
    # standing in the slot (parked or waiting) from the end of the dwell to the first move
    # out, then every wait after that
    first_out = next((m.t0 for m in v.moves if m.t0 >= parked and m.kind not in
                      ("parked", "wait")), None)
    end = first_out if first_out is not None else max(
        [m.t1 for m in v.moves] + [wanted])  # never left: it stood to the run's end
    way_out = max(0.0, end - wanted) + sum(m.t1 - m.t0 for m in v.moves
                                           if m.kind == "wait" and m.t0 >= end)
    return outside, way_in, way_out

