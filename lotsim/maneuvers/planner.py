"""Parking maneuvers: from a pose on an aisle lane into a slot, and back out.

A maneuver (:class:`~lotsim.maneuvers.maneuver.Maneuver`) is a chain of straights and arcs
from a pose on a lane to the parked pose inside the slot; leaving is the same path driven
backwards in time. The planner poses each (vehicle type, slot, lane) as a
:class:`~lotsim.maneuvers.problem.ManeuverProblem` in a frame attached to the slot and its
lane, checks it with :class:`~lotsim.maneuvers.validity.Validity` and searches it by what
its slot's kind decides: a shuffle out of a perpendicular or angled bay
(:mod:`~lotsim.maneuvers.shuffle`), the minimum-slot strokes into a parallel slot
(:mod:`~lotsim.maneuvers.strokes`), then eases the answer (:mod:`~lotsim.maneuvers.easing`).
Every search answers with an :class:`~lotsim.core.outcome.Outcome`.

Answers are cached per lot by the problem's rounded local geometry (its digest,
:meth:`~lotsim.maneuvers.problem.LotProblems.digest`) and the style: same geometry, same
maneuver, moved rigidly. Bays of one shape that differ around them share maneuvers where
one fits another (:mod:`~lotsim.maneuvers.reuse`): a few of each shape are searched, the
rest checked. :mod:`~lotsim.maneuvers.batch` answers a whole lot's distinct problems ahead
on worker processes.
"""

from __future__ import annotations

import dataclasses
import math

from lotsim.core.checks import choice_problem
from lotsim.core.geometry import Segment, same_pose
from lotsim.core.keys import inputs, key_of
from lotsim.core.lazy import LoadedBy
from lotsim.core.outcome import Outcome, Status
from lotsim.core.packed import pack, unpack
from lotsim.errors import InfeasibleManeuver, SettingsError
from lotsim.lot.kinds import kind_of
from lotsim.lot.model import Lane, Lot, Slot
from lotsim.maneuvers.easing import eased
from lotsim.maneuvers.maneuver import Maneuver, direction_changes, path_length, shortest_run
from lotsim.maneuvers.problem import LocalFrame, LotProblems, ManeuverProblem
from lotsim.maneuvers.reuse import fit_first, settle
from lotsim.maneuvers.settings import STYLES, ManeuverSettings
from lotsim.maneuvers.shuffle import park_across
from lotsim.maneuvers.strokes import park_along
from lotsim.maneuvers.validity import Validity
from lotsim.vehicles.model import VehicleType

COMMON_STYLES = ("forward", "reverse")
"""The ways of parking tried for a pose shared by a slot's lanes, in the order tried."""

Answer = Outcome[tuple[tuple[Segment, ...], float]]
"""A search's answer in the problem's local frame: the maneuver's pieces and the local x
where it starts, or why there is none."""


def misfit(vehicle: VehicleType, slot: Slot) -> str | None:
    """Why ``vehicle`` cannot park in ``slot`` whatever the maneuver — wider or longer than
    it — or None: known before any lane is looked at.

    >>> from lotsim.vehicles import CATALOGUE
    >>> class Bay:
    ...     width, length = 2.5, 5.0
    >>> misfit(CATALOGUE["vclass"], Bay()), misfit(CATALOGUE["valet"], Bay())
    ('the car is 5.37 m long, the slot 5.00 m', None)
    """
    if vehicle.width > slot.width:
        return f"the car is {vehicle.width:.2f} m wide, the slot {slot.width:.2f} m"
    if vehicle.length > slot.length:
        return f"the car is {vehicle.length:.2f} m long, the slot {slot.length:.2f} m"
    return None


@inputs
class ProblemAsked:
    """What the planner keeps an answer by (:meth:`ManeuverPlanner.key`): the problem's
    digest (:meth:`~lotsim.maneuvers.problem.LotProblems.digest`), the style, and how
    many lanes serve the slot (which class of :mod:`~lotsim.maneuvers.reuse` it is in)."""

    digest: bytes
    style: str
    lanes: int


def search_maneuver(problem: ManeuverProblem, style: str, settings: ManeuverSettings, *,
                    fewer_than: int | None = None) -> tuple[Answer, Answer]:
    """The parking maneuver of ``problem`` in ``style``, eased
    (:func:`~lotsim.maneuvers.easing.eased`) and as planned, in the problem's local frame
    (a search reads nothing but its problem and the settings). With ``fewer_than`` (a
    perpendicular or angled slot), only one with fewer direction changes than that: the
    same answer as without when it has fewer, else NO_PATH."""
    v, s = problem.vehicle, problem.slot
    why = None
    if not math.isfinite(problem.lane_y):
        why = "the lane bends beside the slot"
    elif misfit(v, s) is not None:
        why = misfit(v, s)
    elif problem.lane_x[0] > problem.lane_x[1]:
        why = ("no car can reach the lanes beside it (no way along them from an entrance "
               "or to an exit)")
    if why is not None:
        refused = Outcome.failed(Status.INFEASIBLE, why)
        return refused, refused
    checks = Validity(problem)
    raw = (park_along(checks, settings) if kind_of(s).parks_along
           else park_across(checks, style, settings, fewer_than=fewer_than))
    if not raw.found:
        return raw, raw
    local, x0 = raw.value
    return Outcome.of((eased(checks, local, settings), x0)), raw


class _Answer:
    """A problem's answer (eased or as planned) in its slot's frame, with the frame and the
    lane station at x = 0: its direction changes and length (the same in any frame), and
    its maneuver put in the world when first asked for."""

    __slots__ = ("hit", "frame", "s0", "ids", "key", "_value")

    def __init__(self, hit: Answer, frame: LocalFrame, s0: float, key: tuple, *ids: str
                 ) -> None:
        self.hit, self.frame, self.s0, self.key, self.ids = hit, frame, s0, key, ids
        self._value = None

    @property
    def found(self) -> bool:
        return self.hit.found

    @property
    def reason(self) -> str:
        return self.hit.reason

    @property
    def changes(self) -> int:
        """Direction changes (as :attr:`Maneuver.changes`)."""
        return direction_changes(self.hit.value[0])

    @property
    def length(self) -> float:
        """Path length [m] (as :attr:`Maneuver.length`)."""
        return path_length(self.hit.value[0])

    def shortest_run(self, known: dict) -> float:
        """:meth:`Maneuver.shortest_run` (the same in any frame; ``known``: by answer)."""
        got = known.get(("run", self.key))
        if got is None:
            got = known["run", self.key] = shortest_run(self.hit.value[0])
        return got

    def ends_as(self, other: _Answer, known: dict) -> bool:
        """Whether it parks where ``other`` does (:func:`same_pose`, in the slot's frame;
        ``known``: by answer)."""
        got = known.get(("end", self.key, other.key))
        if got is None:
            got = known["end", self.key, other.key] = same_pose(self.hit.value[0][-1].end,
                                                                other.hit.value[0][-1].end)
        return got

    @property
    def value(self) -> Maneuver:
        if self._value is None:
            local, x0 = self.hit.value
            vehicle, slot, lane = self.ids
            self._value = Maneuver.placed(self.frame, local, vehicle, slot, lane, self.s0 + x0)
        return self._value


_ANSWERS = ("_cache", "_raw", "_posed", "_fresh", "_fitted", "_classes")
"""What a :class:`ManeuverPlanner` has answered, pickled apart from the rest of it."""
_FOUND_AGAIN = ("_lanes", "_traits")
"""What a :class:`ManeuverPlanner` works out again rather than pickle (the lot's own lanes)."""


class ManeuverPlanner:
    """Plans and caches parking maneuvers for one lot.

    Parameters
    ----------
    lot : Lot
    settings : ManeuverSettings, keyword-only
        The tuning; ``margin`` and ``max_changes``, when given, replace its own.
    margin : float, keyword-only
        Clearance kept to parked cars, walls, obstacles and the edges of the
        drivable area [m] (:attr:`ManeuverSettings.margin`).
    parked_width : float, keyword-only
        Width of the widest car that may stand in a perpendicular or angled
        slot [m]; default the lot's design width.
    max_changes : int, keyword-only
        Most direction changes a maneuver may have (:attr:`ManeuverSettings.max_changes`).
    lane_ranges : dict, keyword-only
        Lane id → (first, last) station [m] where a maneuver may start, or several such
        ranges (:class:`~lotsim.maneuvers.problem.LotProblems`). Default (None): every lane,
        whole. :meth:`LotGraph.maneuver_ranges` gives the parts a car can reach or leave by.

    Notes
    -----
    The shape is OMPL's: a frozen problem per slot and lane (its cache key derived
    from it without side effects), a state validity checker and a motion validator
    on the problem, and :meth:`solve`, which returns an :class:`~lotsim.core.outcome.Outcome`
    with a status and the maneuver or the reason instead of raising.
    """

    # its answers: unpacked from a pickled planner's when first read (:meth:`load_answers`)
    _cache = LoadedBy("load_answers")
    _raw = LoadedBy("load_answers")
    _posed = LoadedBy("load_answers")
    _fresh = LoadedBy("load_answers")
    _fitted = LoadedBy("load_answers")
    _classes = LoadedBy("load_answers")

    def __init__(self, lot: Lot, *, settings: ManeuverSettings | None = None,
                 margin: float | None = None, parked_width: float | None = None,
                 max_changes: int | None = None,
                 lane_ranges: dict[str, tuple] | None = None):
        settings = ManeuverSettings() if settings is None else settings
        if not isinstance(settings, ManeuverSettings):
            raise SettingsError("settings", f"expected ManeuverSettings, found "
                                            f"{type(settings).__name__}")
        changes = {k: v for k, v in (("margin", margin), ("max_changes", max_changes))
                   if v is not None}
        if changes:
            settings = dataclasses.replace(settings, **changes)
        self.settings = settings
        self.lot = lot
        self.problems = LotProblems(lot, settings, parked_width=parked_width,
                                    lane_ranges=lane_ranges)
        self._cache: dict[bytes, Answer] = {}
        self._raw: dict[bytes, Answer] = {}  # not eased
        self.stats = {"planned": 0, "reused": 0, "remembered": 0, "fitted": 0}
        self._posed: dict[tuple[str, str, str, str], tuple[bytes, LocalFrame, float]] = {}
        self._fresh: set[bytes] = set()  # answered ahead of time, not yet asked for
        self._fitted: set[bytes] = set()  # answered by a maneuver of their class
        self._classes: dict[str, dict] = {}  # vehicle → (shape, lanes) → slots and lanes
        self._lanes: dict[str, list[Lane]] = {}  # slot → :meth:`lanes_for` it
        self._traits: dict[tuple, object] = {}  # what an answer is, in any frame (_Answer)

    def __getstate__(self) -> dict:
        # its answers pickled apart: a lot loaded from the cache unpickles them only when a
        # maneuver is asked for (:meth:`load_answers`); a planner never asked passes them on
        # as they came
        state = self._unanswered()
        if "_answers_packed" not in state:
            state["_answers_packed"] = self.packed_answers()
        return state

    def _unanswered(self) -> dict:
        """Its attributes but its answers, and what it works out again left empty."""
        state = {k: v for k, v in self.__dict__.items() if k not in _ANSWERS + _FOUND_AGAIN}
        state.update({k: {} for k in _FOUND_AGAIN})
        return state

    def packed_answers(self) -> bytes:
        """Its answers as pickling it packs them (:meth:`with_answers_packed`)."""
        return pack({k: self.__dict__[k] for k in _ANSWERS})

    def with_answers_packed(self, packed: bytes) -> ManeuverPlanner:
        """It as pickled with its answers packed already (:meth:`packed_answers`, made
        elsewhere meanwhile): what pickling it writes, without packing them again. The copy
        reads them when first asked for, as a planner loaded from the cache does."""
        out = object.__new__(ManeuverPlanner)
        out.__dict__.update(self._unanswered(), _answers_packed=packed)
        return out

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)

    def load_answers(self) -> None:
        """Unpack the answers of a planner loaded from pickle, if they are still packed:
        what reading any of them does first."""
        packed = self.__dict__.pop("_answers_packed", None)
        if packed is not None:
            self.__dict__.update(unpack(packed))

    @property
    def margin(self) -> float:
        """Clearance kept [m] (:attr:`ManeuverSettings.margin`)."""
        return self.settings.margin

    @property
    def max_changes(self) -> int:
        return self.settings.max_changes

    # -- public API ---------------------------------------------------------------------------
    def lanes_for(self, slot: Slot) -> list[Lane]:
        """The lanes a car can park into ``slot`` from: by kind and direction of travel."""
        got = self._lanes.get(slot.id)
        if got is None:
            mid = slot.entry.mean(axis=0)
            kind = kind_of(slot)
            got = self._lanes[slot.id] = [
                lane for lane in self.lot.aisles[slot.aisle].lanes
                if kind.serves_lane(slot, lane, lane.project((float(mid[0]), float(mid[1])))[0])]
        return list(got)

    def solve(self, vehicle: VehicleType, slot: Slot, lane: Lane, *,
              style: str = "any", eased: bool = True) -> Outcome[Maneuver]:
        """Search for the parking maneuver into ``slot`` starting on ``lane``.

        With ``eased`` (the default) its curvature jumps inside strokes are smoothed where
        that stays clear (the car steers as it rolls; the parked pose moves by at most
        :attr:`ManeuverSettings.ease_drift`); without, the car stops to steer at every jump
        and parks exactly centred.

        Returns
        -------
        Outcome
            FOUND with the maneuver, or why there is none (INFEASIBLE: it cannot fit or
            reach; NO_PATH: no way in within the settings).

        Examples
        --------
        >>> from lotsim.io.scenario_yaml import parse_scenario
        >>> from lotsim.io.yamlnodes import parse_text
        >>> from lotsim.lot.build import build_lot
        >>> from lotsim.lot.model import DesignVehicle
        >>> from lotsim.vehicles import CATALOGUE
        >>> sc = parse_scenario(parse_text('''
        ... lot:
        ...   boundary: [[0, 0], [40, 0], [40, 20], [0, 20]]
        ...   aisles: [{id: a, centerline: [[0, 10], [40, 10]], width: 7.0}]
        ...   rows: [{aisle: a, side: left, kind: perpendicular, count: 4, slot_width: 2.5,
        ...           slot_length: 5.0, start: 10}]
        ...   entrances: [{id: in, x: 2, y: 8.25, heading_deg: 0}]
        ... traffic: {vehicles: [{id: x, arrival: 0}]}
        ... ''', "doc.yaml"))
        >>> lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
        >>> planner = ManeuverPlanner(lot)
        >>> slot = lot.slot_by_id["a-left-2"]
        >>> result = planner.solve(CATALOGUE["valet"], slot, planner.lanes_for(slot)[0])
        >>> result.status.value, result.value.slot
        ('found', 'a-left-2')
        >>> planner.solve(CATALOGUE["vclass"], slot, planner.lanes_for(slot)[0]).reason
        'the car is 5.37 m long, the slot 5.00 m'
        """
        problem = choice_problem(style, STYLES)
        if problem:
            raise SettingsError("style", problem)
        answer = self._answer(vehicle, slot, lane, style, eased)
        if not answer.found:
            return Outcome.failed(answer.hit.status, answer.hit.reason)
        return Outcome.of(answer.value)

    def _answer(self, vehicle: VehicleType, slot: Slot, lane: Lane, style: str,
                eased: bool) -> _Answer:
        """:meth:`solve`'s answer, before its maneuver is put in the world."""
        key, frame, s0 = self._pose(vehicle, slot, lane, style)[:3]
        hit = self._cache.get(key)
        if hit is None:  # this problem's class answered, one problem after another
            self.settle_class(vehicle, slot, lane, style)
            hit = self._cache[key]
        if key in self._fresh:  # answered ahead of time (batch.prefetch): first use
            self._fresh.discard(key)
            self.stats["planned"] += 1
            self.stats["fitted"] += key in self._fitted
        else:
            self.stats["reused"] += 1
        if not eased:
            hit = self._raw[key]
        return _Answer(hit, frame, s0, (key, eased), vehicle.name, slot.id, lane.id)

    def plan(self, vehicle: VehicleType, slot: Slot, lane: Lane, *,
             style: str = "any") -> Maneuver:
        """The parking maneuver into ``slot`` starting on ``lane`` (:meth:`solve`).

        Raises
        ------
        InfeasibleManeuver
            When no maneuver within the limits exists, with the reason.
        """
        result = self.solve(vehicle, slot, lane, style=style)
        if not result.found:
            raise InfeasibleManeuver(f"{vehicle.name} cannot park in slot {slot.id!r} from lane "
                                     f"{lane.id!r}: {result.reason}")
        return result.value

    def best(self, vehicle: VehicleType, slot: Slot, *, style: str = "any") -> Maneuver:
        """The best maneuver into ``slot`` over its lanes: fewest changes, then shortest."""
        return min(self.plan_all(vehicle, slot, style=style, shared=False).values(),
                   key=lambda m: (m.changes, m.length))

    def plan_all(self, vehicle: VehicleType, slot: Slot, *, style: str = "any",
                 shared: bool = True) -> dict[str, Maneuver]:
        """Maneuvers into ``slot`` from every lane that has one (lane id → Maneuver)
        (:meth:`solve_all`).

        Raises
        ------
        InfeasibleManeuver
            When no lane has one; the message gives each lane's reason.
        """
        out, why = self.solve_all(vehicle, slot, style=style, shared=shared)
        if not out:
            raise InfeasibleManeuver(f"{vehicle.name} cannot park in slot {slot.id!r}: {why}")
        return out

    def solve_all(self, vehicle: VehicleType, slot: Slot, *, style: str = "any",
                  shared: bool = True) -> tuple[dict[str, Maneuver], str]:
        """Maneuvers into ``slot`` from every lane that has one, and, when none has, why
        (each lane's reason, once; empty when some lane has one).

        With ``shared`` (and ``style`` "any"), a perpendicular or angled slot served by
        several lanes is parked on one pose from all of them where it can be, so that the
        car may leave towards any (:meth:`_solve_common`); without, each lane's best.
        """
        out, _, why = self.solve_lanes(vehicle, slot, style=style, shared=shared)
        return out, why

    def solve_lanes(self, vehicle: VehicleType, slot: Slot, *, style: str = "any",
                    shared: bool = True) -> tuple[dict[str, Maneuver], dict[str, Maneuver], str]:
        """:meth:`solve_all`, and each lane's own best maneuver where it parks the other way
        round (nose-in or backed in) than the shared pose: a car that will not leave again
        need not park so that it could leave towards every lane (lane id → Maneuver)."""
        lanes = self.lanes_for(slot)
        if self._shares(slot, lanes, style, shared):
            return self._solve_common(vehicle, slot, lanes)
        out, reasons = {}, []
        for lane in lanes:
            result = self.solve(vehicle, slot, lane, style=style)
            if result.found:
                out[lane.id] = result.value
            else:
                reasons.append(result.reason)
        if out:
            return out, {}, ""
        return out, {}, "; ".join(dict.fromkeys(reasons)) or "no lane of its aisle leads to it"

    @staticmethod
    def _shares(slot: Slot, lanes: list[Lane], style: str, shared: bool) -> bool:
        """Whether :meth:`solve_lanes` parks ``slot`` on one pose from all its ``lanes`` (a
        car parked along the kerb leaves towards the lane it came by)."""
        return shared and style == "any" and len(lanes) > 1 and not kind_of(slot).parks_along

    def searches(self, slot: Slot, style: str, shared: bool) -> list[tuple[str, Lane]]:
        """(style, lane) of every search :meth:`solve_lanes` makes for ``slot``, in order (the
        same whatever the answers)."""
        lanes = self.lanes_for(slot)
        styles = COMMON_STYLES if self._shares(slot, lanes, style, shared) else (style,)
        return [(st, lane) for st in styles for lane in lanes]

    def _solve_common(self, vehicle: VehicleType, slot: Slot, lanes: list[Lane]
                      ) -> tuple[dict[str, Maneuver], dict[str, Maneuver], str]:
        """:meth:`solve_lanes` for a slot served by several lanes: nose-in from every lane, or
        backed in from every lane — whichever costs fewer direction changes (then less path)
        on the worst lane and parks the car on the one pose from every lane — so the car
        can leave towards any of them; each lane's own best when no way of parking serves
        them all."""
        # (each maneuver put in the world only when it is kept: its changes and length are
        # the same in any frame)
        tried = {st: [self._answer(vehicle, slot, lane, st, True) for lane in lanes]
                 for st in COMMON_STYLES}

        def cost(results: list[_Answer]) -> tuple[int, float]:
            return max(r.changes for r in results), sum(r.length for r in results)

        plain = {st: [self._answer(vehicle, slot, lane, st, False) for lane in lanes]
                 for st in tried}
        # each lane's best as planned (fewest changes, then shortest; nose-in on a tie)
        own = {}
        for k, lane in enumerate(lanes):
            ok = [st for st in tried if tried[st][k].found]
            if ok:
                own[lane.id] = min(ok, key=lambda x, k=k: (plain[x][k].changes,
                                                            plain[x][k].length))
        common = [st for st, results in tried.items() if all(r.found for r in results)]
        for st in sorted(common, key=lambda k: cost(tried[k])):
            # an eased path may park a few millimetres off the planned pose (when no two
            # straights could take the drift up): drive that lane's path as planned, stopping
            # to steer — and no path that has the car creep from stop to stop
            chosen = [r if r.ends_as(q, self._traits) else q
                      for r, q in zip(tried[st], plain[st], strict=True)]
            if min(a.shortest_run(self._traits) for a in chosen) >= self.settings.min_stroke:
                found = [a.value for a in chosen]
                park_only = {lane.id: tried[own[lane.id]][k].value
                             for k, lane in enumerate(lanes) if own[lane.id] != st}
                return {lane.id: m for lane, m in zip(lanes, found, strict=True)}, park_only, ""
        # no one way of parking serves every lane: each lane's best, eased — left the way it
        # came in
        out = {lane.id: tried[own[lane.id]][k].value
               for k, lane in enumerate(lanes) if lane.id in own}
        if out:
            return out, {}, ""
        reasons = [tried[st][k].reason for k in range(len(lanes)) for st in tried]
        return out, {}, "; ".join(dict.fromkeys(reasons))

    def key(self, p: ManeuverProblem, style: str, digest: bytes | None = None, *,
            lanes: int = 1) -> bytes:
        """The problem, the style and how many lanes serve the slot (which class of
        :mod:`~lotsim.maneuvers.reuse` it is in): equal keys plan equal maneuvers.
        ``digest`` is :meth:`~lotsim.maneuvers.problem.LotProblems.digest` of ``p`` when the
        caller has it."""
        return key_of(ProblemAsked(digest if digest is not None else self.problems.digest(p),
                                   style, lanes))

    def _pose(self, vehicle: VehicleType, slot: Slot, lane: Lane, style: str
              ) -> tuple[bytes, LocalFrame, float, ManeuverProblem | None]:
        """The cache key, frame and lane station at x = 0 of a problem, and the problem
        when it had to be posed for them."""
        posed = self._posed.get((vehicle.name, slot.id, lane.id, style))
        if posed is not None:
            return *posed, None
        problem = self.problems.pose(vehicle, slot, lane)
        key = self.key(problem, style, lanes=len(self.lanes_for(slot)))
        self._posed[(vehicle.name, slot.id, lane.id, style)] = (key, problem.frame,
                                                                 problem.lane_s0)
        return key, problem.frame, problem.lane_s0, problem

    def class_of(self, vehicle: VehicleType, slot: Slot, lane: Lane
                 ) -> list[tuple[Slot, Lane]]:
        """The slots and lanes of the lot whose problems for ``vehicle`` are in one class
        with that of ``slot`` from ``lane`` (:mod:`~lotsim.maneuvers.reuse`), in slot order
        (it alone for a problem that shares with none)."""
        classes = self._classes.get(vehicle.name)
        if classes is None:  # every class of this vehicle's problems, worked out once
            classes = self._classes[vehicle.name] = {}
            for other in self.lot.slots:
                lanes = self.lanes_for(other)
                for x in lanes:
                    shape = self.problems.shape(vehicle, other, x)
                    if shape is not None:
                        classes.setdefault((shape, len(lanes)), []).append((other, x))
        shape = self.problems.shape(vehicle, slot, lane)
        if shape is None:
            return [(slot, lane)]
        return classes[shape, len(self.lanes_for(slot))]

    def settle_class(self, vehicle: VehicleType, slot: Slot, lane: Lane, style: str) -> None:
        """Answer every problem of the class of ``vehicle`` into ``slot`` from ``lane`` in
        ``style`` (:func:`~lotsim.maneuvers.reuse.settle`, in this process): what
        :func:`~lotsim.maneuvers.batch.prefetch` answers on workers, the same answers."""
        problems: dict[bytes, ManeuverProblem] = {}
        for other, x in self.class_of(vehicle, slot, lane):
            key, _, _, problem = self._pose(vehicle, other, x, style)
            if key not in self._cache and key not in problems:
                problems[key] = problem or self.problems.pose(vehicle, other, x)
        settled = settle(
            [list(problems)],
            lambda keys: [search_maneuver(problems[k], style, self.settings) for k in keys],
            lambda jobs: [fit_first(problems[k], style, offers, self.settings, self.fewer)[0]
                          for k, offers in jobs])
        for key, ((answer, raw), searched) in settled.items():
            self.learn(key, answer, raw, searched=searched)

    def fewer(self, problem: ManeuverProblem, style: str, changes: int
              ) -> tuple[Answer, Answer]:
        """``problem``'s own maneuver when it has fewer than ``changes`` direction changes
        (:func:`search_maneuver`)."""
        return search_maneuver(problem, style, self.settings, fewer_than=changes)

    # -- what a batch search (:func:`~lotsim.maneuvers.batch.prefetch`) needs ----------------
    def pose_key(self, vehicle: VehicleType, slot: Slot, lane: Lane, style: str,
                 digest: bytes, frame: LocalFrame, s0: float, *, lanes: int) -> bytes:
        """Record the problem of ``vehicle`` in ``slot`` (served by ``lanes`` lanes) from
        ``lane`` in ``style`` as keyed elsewhere (its digest, frame and lane station at
        x = 0): :meth:`solve` then needs not pose it. Its cache key."""
        key = self.key(None, style, digest, lanes=lanes)
        self._posed[(vehicle.name, slot.id, lane.id, style)] = (key, frame, s0)
        return key

    def answers(self) -> tuple[dict[bytes, Answer], dict[bytes, Answer]]:
        """Every answer it holds, eased and as planned, by cache key (:meth:`key`), in the
        order learnt: what two planners of one lot are compared by."""
        return self._cache, self._raw

    def knows(self, key: bytes) -> bool:
        """Whether the answer of the problem with cache ``key`` is known."""
        return key in self._cache

    def learn(self, key: bytes, answer: Answer, raw: Answer, *, searched: bool = True
              ) -> None:
        """Keep the answer of a problem answered ahead of time (eased and as planned; by
        its own search or fitted from its class): the first :meth:`solve` that asks for it
        counts it as planned."""
        self._cache[key], self._raw[key] = answer, raw
        self._fresh.add(key)
        if not searched:
            self._fitted.add(key)
