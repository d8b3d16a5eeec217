"""Maneuvers for a whole lot: every slot, vehicle type and serving lane, the lot's distinct
problems searched ahead on worker processes (:class:`~lotsim.core.workers.ForkPool`), with
exactly the answers of searching them one after another."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterable

from lotsim.core.keys import inputs, key_of
from lotsim.core.reusecheck import ReuseCheck
from lotsim.core.workers import ForkPool, cores
from lotsim.maneuvers.maneuver import Maneuver
from lotsim.maneuvers.planner import ManeuverPlanner, search_maneuver
from lotsim.maneuvers.problem import exact_key
from lotsim.maneuvers.reuse import Found, fit_first, settle
from lotsim.vehicles.model import VehicleType

PARALLEL_FROM = 64
"""Fewest problems worth starting worker processes for (fewer are searched in this process
unless the caller asks for workers)."""
KNOWN_MOST = 60_000
"""Most entries :func:`prefetch` keeps in ``known``, most recently used last (answers under
1 kB each; how a problem was posed, and its exact key, under 200 bytes); older ones are
dropped."""


def _pool_size(workers: int | None, problems: int) -> int:
    """Worker processes for ``problems``: ``workers`` when given, else as many as the machine
    has (one in a process multiprocessing started: its parent shares the cores out) for at
    least :data:`PARALLEL_FROM` problems, each with a few dozen at least."""
    if workers is not None:
        return max(1, min(workers, problems))
    if problems < PARALLEL_FROM:
        return 1
    return min(cores(), max(1, problems // 16))


class _Batch:
    """What the workers of :func:`prefetch` do, on their copy of the planner: key the
    problems of ``triples`` (vehicle, slot, lane), search them, fit their classes' answers
    to them. With ``known``, a problem whose sources (:meth:`LotProblems.sources
    <lotsim.maneuvers.problem.LotProblems.sources>`) it holds is not posed again: its
    digest, and its exact key in each style, are looked up."""

    def __init__(self, planner: ManeuverPlanner, triples: list, known: dict | None) -> None:
        self.planner, self.triples, self.known = planner, triples, known

    def digests(self, part: tuple[int, int]) -> list:
        """The problem digest, frame, lane station, shape and sources (None without
        ``known``) of triples ``part[0]`` to ``part[1]`` (excluded), posed in one batch
        (those ``known`` holds by their sources looked up instead)."""
        triples = self.triples[part[0]:part[1]]
        problems = self.planner.problems
        if self.known is None:
            return [(*got, None) for got in problems.digests(triples)]
        sources = problems.sources(triples)
        got = [self.known.get(posed_key(src)) for src in sources]
        missing = [k for k, g in enumerate(got) if g is None]
        for k, g in zip(missing, problems.digests([triples[k] for k in missing]),
                        strict=True):
            got[k] = g
        return [(*g, src) for g, src in zip(got, sources, strict=True)]

    def _exact(self, k: int, style: str, source: bytes) -> tuple[bytes, object]:
        """The exact key of triple ``k``'s problem in ``style`` (looked up by its
        ``source`` when ``known`` holds it), and the problem when it had to be posed for
        it (else None)."""
        exact = self._exact_held(source, style)
        if exact is not None:
            return exact, None
        problem = self.planner.problems.pose(*self.triples[k])
        return exact_key(problem, style), problem

    def _exact_held(self, source: bytes | None, style: str) -> bytes | None:
        """The exact key ``known`` holds for the problem with ``source`` in ``style``, or
        None."""
        return None if self.known is None else self.known.get(exact_key_of(source, style))

    def _answer_held(self, exact: bytes) -> tuple | None:
        """:meth:`searched`'s answer when ``known`` holds the search of the problem with
        exact key ``exact``, else None."""
        found = self.known.get(exact)
        return None if found is None else (*found, exact, True)

    def _fit_held(self, exact: bytes, keys: list[bytes]) -> tuple | None:
        """:meth:`fitted`'s answer when ``known`` holds a fit of the problem with exact key
        ``exact`` by one of its :func:`fit_keys` ``keys``, else None."""
        for key in keys:
            if key in self.known:
                return self.known[key], key, True, exact
        return None

    def held(self, k: int, style: str, source: bytes | None) -> tuple | None:
        """What :meth:`searched` answers for ``(k, style, source)`` when ``known`` holds the
        problem's exact key and its answer (looked up without posing it), else None."""
        exact = self._exact_held(source, style)
        return None if exact is None else self._answer_held(exact)

    def fit_held(self, k: int, style: str, offers: list[Found], source: bytes | None
                 ) -> tuple | None:
        """What :meth:`fitted` answers for ``(k, style, offers, source)`` when ``known``
        holds the problem's exact key and a fit of it to ``offers`` (looked up without
        posing it), else None."""
        exact = self._exact_held(source, style)
        return None if exact is None else self._fit_held(exact, fit_keys(exact, offers))

    def searched(self, job: tuple[int, str, bytes | None]) -> tuple:
        """The problem of triple ``job[0]`` searched in style ``job[1]`` (posed here: it was
        keyed without being posed whole; ``job[2]``: its sources): (eased, as planned, its
        exact key, whether ``known`` held it). No exact key (None) when there is no
        ``known``."""
        k, st, source = job
        planner = self.planner
        if self.known is None:
            problem = planner.problems.pose(*self.triples[k])
            return *search_maneuver(problem, st, planner.settings), None, False
        exact, problem = self._exact(k, st, source)
        found = self._answer_held(exact)
        if found is not None:
            return found
        problem = problem if problem is not None else planner.problems.pose(*self.triples[k])
        return *search_maneuver(problem, st, planner.settings), exact, False

    def fitted(self, job: tuple[int, str, list[Found], bytes | None]) -> tuple:
        """The first of ``job[2]`` (maneuvers of its class) that fits the problem of triple
        ``job[0]`` in style ``job[1]``, or its own with fewer changes
        (:func:`~lotsim.maneuvers.reuse.fit_first`), None when none fits; the key
        ``known`` keeps that by (None when there is no ``known``), whether it held it, and
        the problem's exact key (``job[3]``: its sources)."""
        k, st, offers, source = job
        planner = self.planner
        if self.known is None:
            problem = planner.problems.pose(*self.triples[k])
            return (fit_first(problem, st, offers, planner.settings, planner.fewer)[0], None,
                    False, None)
        # the problem to the last bit, and the maneuvers of the offers it read
        exact, problem = self._exact(k, st, source)
        keys = fit_keys(exact, offers)
        found = self._fit_held(exact, keys)
        if found is not None:
            return found
        problem = problem if problem is not None else planner.problems.pose(*self.triples[k])
        pair, read = fit_first(problem, st, offers, planner.settings, planner.fewer)
        return pair, keys[read - 1 if pair is not None else -1], False, exact


    def afresh(self, job: tuple[int, str, list[Found] | None, bool]) -> tuple:
        """The problem of triple ``job[0]`` posed afresh, its exact key in style
        ``job[1]``, and (with ``job[3]``) its own search's answer (``job[2]`` None), or its
        fit to the offers ``job[2]`` with the key ``known`` keeps that by (None without
        ``job[3]``): what the reuse check compares with what ``known`` held."""
        k, st, offers, answer = job
        planner = self.planner
        problem = planner.problems.pose(*self.triples[k])
        exact = exact_key(problem, st)
        if not answer:
            return exact, None
        if offers is None:
            return exact, search_maneuver(problem, st, planner.settings)
        pair, read = fit_first(problem, st, offers, planner.settings, planner.fewer)
        return exact, (pair, fit_keys(exact, offers)[read - 1 if pair is not None else -1])


@inputs
class FitOf:
    """Where ``known`` keeps a fit of a problem (by its exact key,
    :func:`~lotsim.maneuvers.problem.exact_key`) to a class's offers: the maneuvers of the
    offers it read (:attr:`Found.source`, in order), and whether the last of them fits
    (else none of them does)."""

    exact: bytes
    offers: tuple[bytes, ...]
    fits: bool


@inputs
class PosedBy:
    """Where ``known`` keeps the digest, frame, lane station and shape of the problem made
    from ``sources`` (:meth:`~lotsim.maneuvers.problem.LotProblems.sources`)."""

    sources: bytes


@inputs
class ExactBy:
    """Where ``known`` keeps the exact key (:func:`~lotsim.maneuvers.problem.exact_key`)
    of the problem made from ``sources`` in ``style``."""

    sources: bytes
    style: str


def fit_keys(exact: bytes, offers: list[Found]) -> list[bytes]:
    """Where ``known`` keeps a fit of the problem with exact key ``exact`` to ``offers``
    (:class:`FitOf`): by the maneuvers the offers up to the one that fits hold (a fit reads
    no offer after it, so it holds when those after change), one key for each offer it may
    be; and where none fits, by them all (the last key)."""
    sources = tuple(found.source for found in offers)
    return [*(key_of(FitOf(exact, sources[:k + 1], True)) for k in range(len(sources))),
            key_of(FitOf(exact, sources, False))]


def _keep(known: dict, key: bytes, value: object) -> None:
    """``known[key] = value``, as its most recently used entry (last)."""
    known.pop(key, None)
    known[key] = value


def posed_key(source: bytes) -> bytes:
    """The key of :class:`PosedBy` ``source``."""
    return key_of(PosedBy(source))


def exact_key_of(source: bytes, style: str) -> bytes:
    """The key of :class:`ExactBy` ``source`` and ``style``."""
    return key_of(ExactBy(source, style))


def prefetch(planner: ManeuverPlanner, vehicles: Iterable[VehicleType], *,
             style: str = "any", shared: bool = True, workers: int | None = None,
             progress: Callable[[int, int], None] | None = None,
             known: dict[bytes, tuple] | None = None, check: ReuseCheck | None = None
             ) -> None:
    """Answer every distinct problem :meth:`ManeuverPlanner.solve_lanes` will meet for
    ``vehicles`` in every slot, on ``workers`` processes (default: as many as the machine
    has, for a lot with :data:`PARALLEL_FROM` problems or more), so that it then only looks
    them up.

    The answers are exactly those of :meth:`~ManeuverPlanner.solve_lanes` alone: each
    distinct problem (by its rounded local geometry, as the planner's cache keys it) is
    answered as its class is (:mod:`~lotsim.maneuvers.reuse`: searched, or a maneuver
    found in its class fitted to it), the searches and fits of a round on the workers.
    Problems are posed (and keyed) on the workers too. Needs the ``fork`` start method
    (Linux); elsewhere it works in this process. ``progress(done, total)`` is called as
    the distinct problems are answered.

    ``known`` (exact problem key → answer, :func:`~lotsim.maneuvers.problem.exact_key`)
    holds answers searched before, for this planner's settings and this lotsim, in any lot
    (the on-disk cache keeps one per lot name: :func:`lotsim.sim.preparation.prepare_graph`):
    a problem it holds is not searched again, and those searched now are added to it, most
    recently used last, at most :data:`KNOWN_MOST`. A search reads nothing but its problem
    (to the last bit of every float) and the settings, so the answers are the same with it
    as without. With a reuse check (``check``, :class:`~lotsim.core.reusecheck.ReuseCheck`),
    everything taken from ``known`` is worked out again and compared (:func:`_verified`).
    """
    lanes = {slot.id: len(planner.lanes_for(slot)) for slot in planner.lot.slots}
    calls = [(v, slot, lane, st) for v in vehicles for slot in planner.lot.slots
             for st, lane in planner.searches(slot, style, shared)]  # solve_lanes' order
    where = {(v.name, slot.id, lane.id): (v, slot, lane) for v, slot, lane, _ in calls}
    triples = list(where.values())  # each problem posed once: the styles share it
    at = {name: k for k, name in enumerate(where)}
    count = _pool_size(workers, len(triples))
    # keyed in batches, a few per worker (each batch one shapely call a step)
    size = max(16, -(-len(triples) // (4 * count)))
    parts = [(k, min(k + size, len(triples))) for k in range(0, len(triples), size)]
    batch = _Batch(planner, triples, known)
    # one set of workers for every step: the searches reuse what keying built in them
    with ForkPool(batch, workers=count) as pool:
        posed = [x for part in pool.map(batch.digests, parts) for x in part]
        # key → (triple, style, its sources), first met first
        todo: dict[bytes, tuple[int, str, bytes | None]] = {}
        classes: dict[object, list[bytes]] = {}
        for v, slot, lane, st in calls:
            k = at[v.name, slot.id, lane.id]
            digest, frame, s0, shape, source = posed[k]
            n = lanes[slot.id]
            key = planner.pose_key(v, slot, lane, st, digest, frame, s0, lanes=n)
            if not planner.knows(key) and key not in todo:
                todo[key] = (k, st, source)
                classes.setdefault(key if shape is None else (shape, st, n), []).append(key)
        count_done = _Progress(progress, len(todo))
        # key → its exact key (where ``known`` is kept), and of those searched, whether
        # ``known`` held the answer
        exacts: dict[bytes, bytes] = {}
        remembered: dict[bytes, bool] = {}
        recalled: dict[bytes, list] = {}  # the searches and fits ``known`` answered

        def search(keys: list[bytes]) -> list[tuple]:
            # those ``known`` holds looked up here, the others searched on the workers
            got = [batch.held(*todo[k]) for k in keys]
            rest = [k for k, g in enumerate(got) if g is None]
            for k, g in zip(rest, pool.map(batch.searched, [todo[keys[k]] for k in rest],
                                           chunk=8, progress=count_done.part), strict=True):
                got[k] = g
            count_done.done += len(keys)  # (the map reported its own)
            for key, (hit, raw, exact, held) in zip(keys, got, strict=True):
                exacts[key], remembered[key] = exact, held
                if held:
                    recalled.setdefault(key, []).append((None, exact, (hit, raw)))
            return [(hit, raw) for hit, raw, _, _ in got]

        fits: dict[bytes, tuple | None] = {}  # what ``known`` is to keep of the fits

        def fit(jobs: list) -> list:
            asks = [(k, st, offers, source) for key, offers in jobs
                    for k, st, source in [todo[key]]]
            got = [batch.fit_held(*ask) for ask in asks]
            rest = [k for k, g in enumerate(got) if g is None]
            for k, g in zip(rest, pool.map(batch.fitted, [asks[k] for k in rest], chunk=16),
                            strict=True):
                got[k] = g
            for (key, offers), (pair, fit_key, held, exact) in zip(jobs, got, strict=True):
                if held:
                    recalled.setdefault(key, []).append((offers, fit_key, (pair, fit_key)))
                if fit_key is not None:
                    fits[fit_key] = pair
                    exacts[key] = exact
                if pair is not None:
                    count_done.add()
            return [pair for pair, _, _, _ in got]

        settled = settle(list(classes.values()), search, fit,
                         offer=lambda _, pair: Found.of(pair, named=True))
        if check is not None and known is not None:
            _verified(check, pool, batch, known, posed, todo, exacts, recalled)
    for key in todo:  # in the order first met
        (hit, raw), searched = settled[key]
        planner.learn(key, hit, raw, searched=searched)
        if known is not None and searched:
            _keep(known, exacts[key], (hit, raw))
            planner.stats["remembered"] += remembered[key]
    if known is not None:
        for key, pair in fits.items():
            _keep(known, key, pair)
        # how each problem was posed, by its sources: what an edited lot looks up
        for source, got in {p[4]: p[:4] for p in posed}.items():
            _keep(known, posed_key(source), got)
        for key, (_, st, source) in todo.items():
            if key in exacts:
                _keep(known, exact_key_of(source, st), exacts[key])
        for old in list(itertools.islice(known, max(0, len(known) - KNOWN_MOST))):
            del known[old]


def _verified(check: ReuseCheck, pool: ForkPool, batch: _Batch, known: dict, posed: list,
              todo: dict, exacts: dict, recalled: dict) -> None:
    """The reuse check of :func:`prefetch`: what ``known`` held and the batch took from it
    — how problems were posed (``posed``: digest, frame, station, shape and sources of each
    triple), their exact keys (``exacts``), their searches and fits (``recalled``: key →
    (offers or None for a search, the key ``known`` held it by, what it held)) — worked out
    again, posed afresh on the workers, and compared."""
    again = [k for k, p in enumerate(posed) if posed_key(p[4]) in known]
    fresh = batch.planner.problems.digests([batch.triples[k] for k in again])
    for k, got in zip(again, fresh, strict=True):
        check.compare("maneuver problems posed", posed_key(posed[k][4]), posed[k][:4], got)
    # each problem whose exact key was looked up, once, and each answer taken from known
    asks = [(key, None) for key in todo if key in exacts
            and exact_key_of(todo[key][2], todo[key][1]) in known]
    asks += [(key, held) for key in todo for held in recalled.get(key, ())]
    jobs = [(todo[key][0], todo[key][1], held[0] if held else None, held is not None)
            for key, held in asks]
    for (key, held), (exact, answer) in zip(asks, pool.map(batch.afresh, jobs, chunk=8),
                                            strict=True):
        _, st, source = todo[key]
        if held is None:
            check.compare("maneuver exact keys", exact_key_of(source, st), exacts[key], exact)
        else:
            check.compare("maneuver fits" if held[0] is not None else "maneuver answers",
                          held[1], held[2], answer)


class _Progress:
    """``progress(done, total)`` over the rounds of :func:`prefetch`: ``done`` counts the
    problems answered in earlier maps, and within a map as its answers come."""

    def __init__(self, progress: Callable[[int, int], None] | None, total: int) -> None:
        self.progress, self.total, self.done = progress, total, 0
        self.part = None if progress is None else self._part

    def _part(self, done: int, _: int) -> None:
        """A search map's answers so far (its own count, from 1)."""
        self.progress(self.done + done, self.total)

    def add(self) -> None:
        """One more answered."""
        self.done += 1
        if self.progress is not None:
            self.progress(self.done, self.total)


def plan_lot(planner: ManeuverPlanner, vehicles: Iterable[VehicleType], *,
             style: str = "any", workers: int | None = None,
             progress: Callable[[int, int], None] | None = None,
             known: dict[bytes, tuple] | None = None, check: ReuseCheck | None = None
             ) -> tuple[dict[tuple[str, str, str], Maneuver], dict[str, dict[str, str]],
                        dict[tuple[str, str, str], Maneuver]]:
    """Maneuvers for every slot, vehicle type and lane of a lot, searched on ``workers``
    processes (:func:`prefetch`; the same answers on any number).

    Returns
    -------
    maneuvers : dict
        ``(vehicle name, slot id, lane id)`` → Maneuver (:meth:`ManeuverPlanner.solve_all`).
    infeasible : dict
        vehicle name → {slot id: reason} for the slots it cannot use.
    park_only : dict
        ``(vehicle name, slot id, lane id)`` → that lane's own best Maneuver, where it parks
        the other way round than the one in ``maneuvers`` (for cars that will not leave;
        :meth:`ManeuverPlanner.solve_lanes`).

    ``progress(done, total)`` is called as the distinct problems are searched; ``known``:
    answers found before, and kept (:func:`prefetch`); ``check``: the reuse check of what
    is taken from ``known`` (:func:`prefetch`).
    """
    vehicles = list(vehicles)
    prefetch(planner, vehicles, style=style, workers=workers, progress=progress, known=known,
             check=check)
    maneuvers: dict[tuple[str, str, str], Maneuver] = {}
    park_only: dict[tuple[str, str, str], Maneuver] = {}
    infeasible: dict[str, dict[str, str]] = {}
    for v in vehicles:
        infeasible[v.name] = {}
        for slot in planner.lot.slots:
            found, own, why = planner.solve_lanes(v, slot, style=style)
            for lane, m in found.items():
                maneuvers[(v.name, slot.id, lane)] = m
            for lane, m in own.items():
                park_only[(v.name, slot.id, lane)] = m
            if not found:
                infeasible[v.name][slot.id] = why
    return maneuvers, infeasible, park_only
