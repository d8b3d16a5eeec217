"""A run you can step: :class:`Live` holds a run's state and moves it forward, event by
event, while cars are added as they come and slot choices are taken from outside.

:func:`lotsim.sim.running.simulate` is a loop over it (every car of the scenario's
traffic added at the start, then :meth:`Live.advance` to the end): the same run, event for
event.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable

import numpy as np
import shapely

from lotsim.errors import DecisionError, ScenarioError, SettingsError
from lotsim.sim.loop import EventLoop
from lotsim.sim.policies import ASK, SlotRequest
from lotsim.sim.preparation import PreparedLot
from lotsim.sim.repairs import LotChanges, check_lot_events, lot_event_problem
from lotsim.sim.results import RunResult, VehicleRun, let_go
from lotsim.sim.settings import RunSettings
from lotsim.traffic.demand import Arrival, arrivals
from lotsim.traffic.disturbances import MAX_STALL, Closure, TakenBay

PHASES = ("coming", "queued", "driving", "parking", "parked", "leaving", "departed",
          "rejected", "waiting")
"""Where a car is in its story at an instant (:meth:`Live.state`): not arrived yet, queued
outside its entrance (taking no space), driving on the lanes (or standing on them), in a
parking maneuver, parked, in the maneuver out of its slot, gone by an exit, turned away, or
(when the run has ended) still waiting to get in."""


class Live:
    """A run of a prepared lot that moves forward when asked.

    Parameters
    ----------
    prepared : PreparedLot
        The lot (:func:`lotsim.prepare`).
    settings : RunSettings, optional
        How to plan (``RunSettings()`` when not given).
    policy : callable or ASK, optional, keyword-only
        Chooses the slots a car tries (:mod:`lotsim.sim.policies`); without one, the
        ranking of ``settings.assignment``. With :data:`~lotsim.sim.policies.ASK` the run
        pauses at each choice (:attr:`pending`) until :meth:`decide`.
    traffic : bool, keyword-only
        Whether the scenario's own traffic comes (default); without it, only the cars
        :meth:`add` brings.
    progress : callable, optional, keyword-only
        Called as ``progress(done, total)`` as trips are dealt with (with a third argument,
        if it takes one: the run's clock and the cars served, as text).
    release : callable, optional, keyword-only
        Called with each car of the traffic once it is done and every car before it (in
        the result's order: by arrival) has been released, while the run goes on (a
        writer of the result, :class:`lotsim.io.result.ResultWriter`); the car then keeps
        only the figures the run's metrics read (:func:`~lotsim.sim.results.let_go`). For a
        day's run, whose memory then follows the cars present, not those served. Not with
        disturbances or cars from outside (:meth:`add`): they can still change a car done.

    Raises
    ------
    ScenarioError
        For traffic the lot cannot serve at all (:func:`~lotsim.sim.running.check_traffic`).
    SettingsError
        For an ``order`` that does not hold every vehicle of the traffic once.

    Examples
    --------
    >>> import lotsim
    >>> live = lotsim.Live(lotsim.prepare(lotsim.EXAMPLE), traffic=False)
    >>> live.add("van", "valet", "in", at=5.0)
    >>> live.advance(12.0)
    >>> car = live.state()["cars"][0]
    >>> car["id"], car["phase"], car["slot"]
    ('van', 'parking', 'N1')
    >>> result = live.finish()
    >>> [(v.id, v.status) for v in result.vehicles]
    [('van', 'parked')]
    """

    def __init__(self, prepared: PreparedLot, settings: RunSettings | None = None, *,
                 policy: Callable | str | None = None, traffic: bool = True,
                 progress=None, release: Callable[[VehicleRun], None] | None = None
                 ) -> None:
        from lotsim.sim.running import check_traffic, turned_away

        if policy is not None and policy != ASK and not callable(policy):
            raise SettingsError("policy", f"expected a callable or {ASK!r}, found "
                                          f"{policy!r}")
        self.prepared = prepared
        self.settings = settings = settings or RunSettings()
        scenario = prepared.scenario
        lg = prepared.lot_graph
        self.seed = scenario.seed if settings.seed is None else settings.seed
        cars = (arrivals(scenario.traffic, self.seed)
                if traffic and scenario.traffic is not None else [])
        if settings.order is not None and sorted(settings.order) != sorted(a.id for a in cars):
            raise SettingsError("order", "expected every vehicle id of the traffic exactly once")
        if cars:
            check_traffic(lg, cars)
        self._reach = lg.reachability()
        self._loop = EventLoop(scenario, lg, settings, cars, progress, prepared.search_graphs,
                               turned_away=turned_away(lg, cars, self._reach), policy=policy)
        self._loop.state_of = lambda loop: self.state()
        spec = scenario.disturbances
        check_lot_events(lg, spec)
        for event in (() if spec is None else (*spec.closures, *spec.taken)):
            self._loop.add_lot_event(event)
        self._release = None
        if release is not None:
            if spec is not None and spec.active:
                raise SettingsError("release", "a run with disturbances can still change a "
                                               "car that is done: write it when it ends")
            self._release = _InOrder(self._loop.vehicles, release)
            self._loop.on_done = self._release.done
        self._tallies = {id(sg.tally): sg.tally for sg in self._loop.graphs.values()}.values()
        self._took = 0.0  # seconds spent dealing with events
        self._worked = 0.0  # of which working out edge motions first
        self._result: RunResult | None = None
        self._aisles = sorted(lg.lot.aisles)
        self._aisle_shapes = np.array([lg.lot.aisles[a].polygon for a in self._aisles],
                                      dtype=object)

    # -- the clock ----------------------------------------------------------------------------
    @property
    def now(self) -> float:
        """The time the run has reached [s] (``-inf`` before its first event)."""
        return self._loop.now

    @property
    def pending(self) -> SlotRequest | None:
        """The choice the run waits for (with the :data:`~lotsim.sim.policies.ASK`
        policy), or None: the request the car was asked, its slots those :meth:`decide`
        accepts (free, usable by its type, and not cut off by a closure)."""
        return None if self._loop.pending is None else self._loop.asked

    @property
    def done(self) -> bool:
        """Whether nothing is left to happen (every event dealt with) or the run was
        finished."""
        return self._result is not None or (not self._loop.events
                                            and self._loop.pending is None)

    def advance(self, until: float = math.inf) -> None:
        """Deal with every event up to ``until`` [s] (all, by default), or until a car
        waits for a choice (:attr:`pending`); the clock then reads ``until`` (or the
        choice's time)."""
        self._open()
        self._timed(lambda: self._loop.go(until))
        if self._loop.pending is None and math.isfinite(until):
            self._loop.now = max(self._loop.now, until)

    def next_decision(self) -> SlotRequest | None:
        """Go on to the next choice the run waits for (:attr:`pending`), or to the end:
        None when no choice is left."""
        self.advance()
        return self.pending

    def decide(self, answer) -> None:
        """Answer :attr:`pending`: a slot id, slot ids to try in order, or None to wait
        (as a policy answers, :mod:`lotsim.sim.policies`).

        Raises
        ------
        DecisionError
            When no choice is pending, or the lot cannot honour this one.
        """
        self._open()
        loop = self._loop
        if loop.pending is None:
            raise DecisionError("-", "no car waits for a choice")
        i, t = loop.pending
        loop.pending, loop.answer = None, (i, answer)
        try:
            self._timed(lambda: loop.on_retry(i, loop.vehicles[i], t))
        except DecisionError:
            loop.pending, loop.answer = (i, t), None
            raise

    # -- cars coming ----------------------------------------------------------------------------
    def add(self, car: str, vehicle: str, entrance: str | None = None, *,
            at: float | None = None, dwell: float | None = None, slot: str | None = None,
            pose=None) -> None:
        """A car ``car`` of type ``vehicle`` comes to ``entrance`` at time ``at`` [s] (now,
        if None), to stay ``dwell`` seconds once parked (None: it stays).

        Or it is inside the lot already, from now: standing in bay ``slot``, to be called
        out after ``dwell`` seconds (None: it stays); or standing on a lane at ``pose``
        ``(x, y, theta)`` [m, rad] (the nearest lane node of about that heading,
        :func:`~lotsim.sim.inside.lane_node_near`), from where it looks for a slot. Either
        holds its ground until it moves, where a car queued at a gate takes no space; the
        cars planned through its ground are planned again.

        Raises
        ------
        SettingsError
            For a car id already in the run, a type or entrance the lot does not have, a
            time before now, a dwell of a lot with no exit; for a car inside the lot, a
            time other than now, a bay that is not free or that its type cannot use or
            leave, a pose on no lane, or ground another car stands or drives on now.
        """
        self._open()
        if self._release is not None:
            raise SettingsError("release", "a run that releases its cars as they are done "
                                           "takes none from outside: one could come before "
                                           "a car released")
        loop = self._loop
        lg = loop.lg
        now = self.now if math.isfinite(self.now) else 0.0
        at = now if at is None else float(at)
        if car in loop.by_id:
            raise SettingsError("car", f"{car!r} is already in the run")
        if vehicle not in loop.types:
            raise SettingsError("vehicle", f"expected one of the scenario's vehicle types "
                                           f"({', '.join(sorted(loop.types))}), found "
                                           f"{vehicle!r}")
        given = [k for k, x in (("entrance", entrance), ("slot", slot), ("pose", pose))
                 if x is not None]
        if len(given) != 1:
            raise SettingsError("car", f"{car!r}: expected one of entrance, slot or pose "
                                       f"(where it comes), found "
                                       f"{' and '.join(given) or 'none'}")
        if entrance is not None and entrance not in lg.entrances:
            raise SettingsError("entrance", f"expected one of the lot's entrances "
                                            f"({', '.join(sorted(lg.entrances))}), found "
                                            f"{entrance!r}")
        if not math.isfinite(at) or at < max(self.now, 0.0) - 1e-9:
            raise SettingsError("at", f"expected a time from now ({max(self.now, 0.0):g} s) "
                                      f"on, found {at:g}")
        if entrance is None and abs(at - now) > 1e-9:
            raise SettingsError("at", f"a car inside the lot is added where it is now "
                                      f"({now:g} s), found {at:g} (advance first)")
        if dwell is not None and not (math.isfinite(dwell) and dwell >= 0):
            raise SettingsError("dwell", f"expected seconds, at least 0, found {dwell!r}")
        if dwell is not None and not lg.exits:
            raise SettingsError("dwell", f"{car!r} cannot leave: the lot has no exit")
        dwell = None if dwell is None else float(dwell)
        if slot is not None and slot not in lg.lot.slot_by_id:
            raise SettingsError("slot", f"expected a slot id, found {slot!r}: the lot has no "
                                        f"slot {slot!r}")
        if pose is not None:
            pose = self._lane_pose(pose)
        a = Arrival(car, vehicle, entrance, at, dwell, slot=slot, pose=pose)
        from lotsim.sim import inside
        from lotsim.sim.running import check_traffic, turned_away

        if a.inside:
            if pose is not None:
                loop.assigner.starts[car] = inside.lane_node_near(lg, pose)[0]
            why = inside.why_not_here(loop, VehicleRun(a, loop.types[vehicle]), at)
            if why is not None:
                loop.assigner.starts.pop(car, None)
                raise SettingsError("slot" if slot is not None else "pose",
                                    f"{car!r} cannot be there: {why}")
            i = loop.enter(a)
            self._timed(lambda: loop.on_arrive(i, loop.vehicles[i], at))
            return
        try:
            check_traffic(lg, [a], self._reach)
        except ScenarioError as err:
            raise SettingsError("car", f"{car!r}: {err.message}") from None
        loop.turned_away.update(turned_away(lg, [a], self._reach))
        i = loop.enter(a)
        loop.at(at, "arrive", i)

    def _lane_pose(self, pose) -> tuple[float, float, float]:
        """The lane node's pose ``pose`` means (:func:`~lotsim.sim.inside.lane_node_near`).
        """
        from lotsim.sim import inside

        try:
            x, y, th = (float(c) for c in pose)
        except (TypeError, ValueError):
            raise SettingsError("pose", f"expected (x, y, theta), found {pose!r}") from None
        if not all(map(math.isfinite, (x, y, th))):
            raise SettingsError("pose", f"expected finite numbers, found {pose!r}")
        node, why = inside.lane_node_near(self._loop.lg, (x, y, th))
        if node is None:
            raise SettingsError("pose", f"({x:g}, {y:g}, {th:g}) is on no lane: {why}")
        return tuple(map(float, self._loop.lg.graph.nodes[node]["pose"]))

    # -- the lot changing -----------------------------------------------------------------------
    def close(self, kind: str, name: str, until: float, *, at: float | None = None) -> None:
        """Close the aisle, lane or gate (``kind``) ``name`` from ``at`` (now, if None) until
        ``until`` [s] (:class:`~lotsim.traffic.disturbances.Closure`): the cars whose plans
        pass it then are planned again.

        Raises
        ------
        SettingsError
            For something the lot does not have, or a time before now.
        """
        self._open()
        start = self._when(at)
        self._add_event(Closure(kind, name, start, until))

    def take_bay(self, slot: str, *, at: float | None = None) -> None:
        """A car the plan does not know parks in ``slot`` at ``at`` [s] (now, if None) and
        stays (:class:`~lotsim.traffic.disturbances.TakenBay`): a car that was to park
        there is given another slot.

        Raises
        ------
        SettingsError
            For a slot the lot does not have, or a time before now.
        """
        self._open()
        self._add_event(TakenBay(slot, self._when(at)))

    def stall(self, car: str, duration: float, *, at: float | None = None) -> None:
        """Car ``car`` stalls at ``at`` [s] (now, if None) for ``duration`` seconds
        (:mod:`lotsim.sim.stalls`): it stops where its plan next brings it to rest on the
        lanes and stands there that long, then is planned again from there; the cars whose
        plans pass where it stands are planned round it at once. A stall that cannot be had
        (the car is not in the lot then, or parked, or the cars coming could not go round
        it anywhere on its way) is recorded with the reason (the result's
        ``disturbances.stalls_refused``).

        Raises
        ------
        SettingsError
            For a car not in the run, a duration that is not a positive number of seconds
            (at most a day), or a time before now.
        """
        self._open()
        loop = self._loop
        if car not in loop.by_id:
            raise SettingsError("car", f"expected a car of the run, found {car!r}")
        if not (isinstance(duration, (int, float)) and 0 < duration <= MAX_STALL):
            raise SettingsError("duration", f"expected seconds, more than 0 and at most "
                                            f"{MAX_STALL:g}, found {duration!r}")
        start = self._when(at)
        loop.stall_asks.append((loop.vehicles.index(loop.by_id[car]), float(duration)))
        loop.at(start, "stall", len(loop.stall_asks) - 1)

    def _when(self, at: float | None) -> float:
        now = max(self.now, 0.0) if math.isfinite(self.now) else 0.0
        if at is None:
            return now
        if not (isinstance(at, (int, float)) and math.isfinite(at)) or at < now - 1e-9:
            raise SettingsError("at", f"expected a time from now ({now:g} s) on, found {at!r}")
        return float(at)

    def _add_event(self, event: Closure | TakenBay) -> None:
        problem = lot_event_problem(self._loop.lg, event)
        if problem is not None:
            raise SettingsError(*problem)
        self._loop.add_lot_event(event)

    # -- reading it -----------------------------------------------------------------------------
    def state(self) -> dict:
        """The run now, as plain data (lists, dicts, numbers and strings).

        ``time`` [s]; ``cars``: each car that has come or will come, with ``id``, ``type``,
        ``entrance`` (None for a car that was inside the lot when it came), ``arrival``
        (when it came [s]), ``phase`` (:data:`PHASES`), ``slot`` (the one it took, or None),
        ``parked_at`` (when it came to stand in its slot [s], once it has; else None),
        ``pose`` ``[x, y, theta]`` [m, rad] and ``speed`` [m/s] while it is in the lot (else
        None);
        ``occupancy``: each slot's car (``"occupied"`` for one taken when the run began,
        None when free); ``queues``: each entrance's cars queued outside, first come
        first; ``aisles``: the cars whose rear-axle centre is on each aisle."""
        loop = self._loop
        t = self.now if math.isfinite(self.now) else 0.0
        lot = loop.lg.lot
        cars, queues = [], {g: [] for g in sorted(loop.lg.entrances)}
        occupancy: dict[str, str | None] = {s.id: ("occupied" if s.id in lot.occupied
                                                   else None) for s in lot.slots}
        on = []
        for v in loop.vehicles:
            phase, pose, speed = _at(v, t)
            if phase == "queued":
                queues[v.arrival.entrance].append(v.id)
            if v.slot is not None and phase in ("driving", "parking", "parked", "leaving") \
                    and not (phase == "driving" and v.leaving):
                occupancy[v.slot] = v.id
            if pose is not None:
                on.append((v.id, pose))
            parked = v.parked_at if v.parked_at is not None and v.parked_at <= t else None
            cars.append({"id": v.id, "type": v.vehicle.name, "entrance": v.arrival.entrance,
                         "arrival": v.arrival.time, "phase": phase, "slot": v.slot,
                         "parked_at": parked,
                         "pose": None if pose is None else [round(float(x), 4) for x in pose],
                         "speed": None if speed is None else round(float(speed), 4)})
        aisles: dict[str, list[str]] = {a: [] for a in self._aisles}
        if on and len(self._aisles):
            xy = np.array([p[:2] for _, p in on], dtype=float)
            inside = shapely.contains_xy(self._aisle_shapes[:, None], xy[:, 0], xy[:, 1])
            for k, name in enumerate(self._aisles):
                aisles[name] = [on[j][0] for j in np.flatnonzero(inside[k])]
        return {"time": t, "cars": cars, "occupancy": occupancy, "queues": queues,
                "aisles": aisles}

    # -- the end --------------------------------------------------------------------------------
    def finish(self) -> RunResult:
        """Deal with every event left and end the run: the same :class:`RunResult` as
        :func:`lotsim.run` gives (a second call gives the same one).

        Raises
        ------
        DecisionError
            When a car still waits for a choice (:attr:`pending`).
        """
        if self._result is not None:
            return self._result
        self.advance()
        if self._loop.pending is not None:
            raise DecisionError(self._loop.vehicles[self._loop.pending[0]].id,
                                "waits for a choice (Live.decide) before the run can end")
        self._loop.close()
        # in arrival order, as the traffic's own cars come (cars added later may arrive
        # before some of them)
        cars = sorted(self._loop.vehicles, key=lambda v: (v.arrival.time, v.id))
        loop = self._loop
        changes = (LotChanges(loop.closures, loop.taken_records, loop.replans, loop.stalls)
                   if loop.lot_events or loop.replans or loop.stalls else None)
        self._result = RunResult(self.prepared.scenario, self.prepared.lot_graph,
                                 self.settings, self.seed, cars,
                                 self._took - self._worked, motion_time=self._worked,
                                 lot_changes=changes)
        return self._result

    def snapshot(self) -> RunResult:
        """The run so far as a :class:`RunResult`, without ending it: each car as planned
        up to now, for a picture of the run at :attr:`now` (its plans after that may still
        change, and the cars still to come or to choose have no moves yet). The cars are
        copies: stepping the run on does not change the snapshot.

        Examples
        --------
        >>> import lotsim
        >>> live = lotsim.Live(lotsim.prepare(lotsim.EXAMPLE))
        >>> live.advance(4.0)
        >>> [(v.id, v.slot) for v in live.snapshot().vehicles]
        [('ada', 'N1'), ('bob', 'N3'), ('cy', None)]
        """
        if self._result is not None:
            return self._result
        loop = self._loop
        cars = sorted((dataclasses.replace(v, moves=list(v.moves)) for v in loop.vehicles),
                      key=lambda v: (v.arrival.time, v.id))
        changes = (LotChanges(list(loop.closures), list(loop.taken_records),
                              list(loop.replans), list(loop.stalls))
                   if loop.lot_events or loop.replans or loop.stalls else None)
        return RunResult(self.prepared.scenario, self.prepared.lot_graph, self.settings,
                         self.seed, cars, self._took - self._worked,
                         motion_time=self._worked, lot_changes=changes)

    def _open(self) -> None:
        if self._result is not None:
            raise SettingsError("live", "the run has ended (Live.finish)")

    def _timed(self, work: Callable[[], None]) -> None:
        """Do ``work``, counting its time, and apart the time it spent working out edge
        motions and hulls first (in searches, or reserving what they found); the time it
        spent handing cars on (``release``: writing them) is not counted."""
        worked = sum(t.seconds for t in self._tallies)
        released = self._release.seconds if self._release is not None else 0.0
        clock = time.perf_counter()
        try:
            work()
        finally:
            self._took += time.perf_counter() - clock - (
                self._release.seconds - released if self._release is not None else 0.0)
            self._worked += sum(t.seconds for t in self._tallies) - worked


def _at(v: VehicleRun, t: float) -> tuple[str, tuple | None, float | None]:
    """Where ``v`` is at ``t`` [s]: its phase (:data:`PHASES`), pose and speed (None
    outside the lot)."""
    if t < v.arrival.time:
        return "coming", None, None
    moves = [m for m in v.moves if m.kind != "outside"]
    if not moves or t < moves[0].t0:
        if v.done and v.status in ("rejected", "waiting"):
            return v.status, None, None
        return "queued", None, None
    if t >= moves[-1].t1:
        m = moves[-1]
        if v.left_at is not None:
            return "departed", None, None
        return ("parked" if v.parked_at is not None and t >= v.parked_at else "driving",
                m.end_pose, 0.0)
    m = next(m for m in moves if m.t1 > t)
    if m.motion is None:
        pose, speed = m.end_pose, 0.0
    else:
        poses, speeds, _, _ = m.motion.at(np.array([t - m.t0]), wheelbase=v.vehicle.wheelbase)
        pose, speed = tuple(poses[0]), float(speeds[0])
    phase = {"park": "parking", "leave": "leaving", "parked": "parked"}.get(m.kind, "driving")
    return phase, pose, speed


class _InOrder:
    """Hands each car to ``release`` once it is done and every car before it in the
    result's order (by arrival time, then id) has been handed on, then lets its moves go."""

    def __init__(self, cars: list[VehicleRun], release: Callable[[VehicleRun], None]):
        self._cars = sorted(cars, key=lambda v: (v.arrival.time, v.id))
        self._next = 0
        self._release = release
        self.seconds = 0.0
        """Spent in ``release`` (writing the cars: not planning)."""

    def done(self, _: VehicleRun) -> None:
        cars = self._cars
        clock = time.perf_counter()
        while self._next < len(cars) and cars[self._next].done:
            v = cars[self._next]
            self._release(v)
            let_go(v)
            self._next += 1
        self.seconds += time.perf_counter() - clock
