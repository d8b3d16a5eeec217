"""What ``lotsim validate`` finds about a scenario, as data (:class:`ValidationReport`)."""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field

from lotsim.core.diskcache import LOADED
from lotsim.core.units import shown_length
from lotsim.lot.model import PAVEMENT_EDGE
from lotsim.lot.pavement import loose_ends
from lotsim.lot.uses import USES, refused_bays
from lotsim.roadmap.reach import Reachability
from lotsim.roadmap.service_routes import RouteReport, RouteSettings, plan_routes
from lotsim.sim.bays import BayReport, bay_report, bay_schedule, schedule_csv
from lotsim.sim.preparation import PreparedLot
from lotsim.sim.repairs import check_lot_events
from lotsim.sim.running import check_traffic, turned_away, unfit
from lotsim.traffic.demand import Arrival, StreamSpec, arrivals


@dataclass(frozen=True, slots=True)
class ValidationReport:
    """A valid scenario's lot: what it holds, what cannot be reached or used, and why.

    A scenario that is not valid raises :class:`~lotsim.errors.ScenarioError` instead.

    Attributes
    ----------
    source : str
        The scenario's file as it was named (``<scenario>`` for text).
    prepared : PreparedLot
        The prepared lot, ready for :func:`lotsim.run`.
    reachability : Reachability
        The free slots that cannot be reached from an entrance or left for an exit, in
        all and per vehicle type.
    turned_away : dict
        Vehicle type → why ``lotsim run`` turns away its cars of the traffic (a type that
        fits no free slot, reaches none, or can leave none for an exit).
    routes : tuple of RouteReport
        The scenario's service routes as planned, in its order
        (:func:`~lotsim.roadmap.service_routes.plan_route`).
    """

    source: str
    prepared: PreparedLot
    reachability: Reachability
    turned_away: dict[str, str] = field(default_factory=dict)
    routes: tuple[RouteReport, ...] = ()

    @property
    def name(self) -> str:
        return self.prepared.scenario.name

    @property
    def slot_counts(self) -> dict[str, int]:
        """Slots by kind (perpendicular, parallel, angled)."""
        return self.prepared.lot.slot_counts()

    @property
    def infeasible(self) -> dict[str, dict[str, str]]:
        """Vehicle type → slot id → why that type cannot park there."""
        return self.prepared.infeasible

    @property
    def bays(self) -> BayReport:
        """The lot's bays by use, checked against its standard (``lot.standard``, ADA 2010
        by default), with each accessible bay's walk to the nearest building entrance
        (:func:`~lotsim.sim.bays.bay_report`)."""
        spec = self.prepared.scenario.lot
        return bay_report(self.prepared.lot, spec.standard,
                          [(b.id, b.point) for b in spec.building_entrances])

    def schedule(self) -> list[dict]:
        """The lot's bay schedule: a line per row, use and size
        (:func:`~lotsim.sim.bays.bay_schedule`)."""
        return bay_schedule(self.prepared.lot, rows_of(self.prepared))

    def schedule_csv(self) -> str:
        """:meth:`schedule` as the CSV ``lotsim validate --schedule`` writes."""
        return schedule_csv(self.schedule(), lambda ids: id_ranges(ids, most=len(ids)),
                            self.prepared.scenario.units)

    @property
    def refused(self) -> dict[str, dict[str, str]]:
        """Vehicle type → bay id → why the scenario's rule of uses keeps the type out of the
        bay (an accessible bay and a type not marked so, ...): part of :attr:`infeasible`,
        by design, not a fault of the layout."""
        return refused_bays(self.prepared.lot.slots, self.prepared.scenario.vehicle_types)

    @property
    def misfits(self) -> dict[str, dict[str, str]]:
        """:attr:`infeasible` without :attr:`refused`: the bays a type may use but cannot
        park in."""
        refused = self.refused
        return {name: {sid: why for sid, why in slots.items()
                       if sid not in refused.get(name, {})}
                for name, slots in self.infeasible.items()}

    @property
    def complete(self) -> bool:
        """Every free slot and exit can be reached and every type can park in every slot
        its use lets it use, and every service route passes: what ``lotsim validate
        --strict`` requires."""
        return (self.reachability.ok and not any(self.misfits.values())
                and not self.turned_away and all(r.passed for r in self.routes))

    @property
    def verdict(self) -> str:
        """The summary's heading: ``ok`` for a :attr:`complete` lot, else ``valid but
        incomplete`` (``lotsim validate --strict`` exits 1 for it)."""
        return "ok" if self.complete else "valid but incomplete"

    @property
    def warnings(self) -> list[str]:
        """The summary's warnings, without their ``warning:`` tag."""
        return [line.strip()[len("warning: "):] for line in self.summary().splitlines()
                if line.strip().startswith("warning: ")]

    def usable(self) -> dict[str, list[str]]:
        """Per vehicle type, the free slots it can use: fits, can reach from an entrance,
        park in and (where the lot has exits) leave for one; natural order."""
        lg, reach = self.prepared.lot_graph, self.reachability
        free = [s.id for s in lg.lot.free_slots]
        out = {}
        for v in self.prepared.scenario.vehicle_types:
            no_in, no_out = reach.by_type.get(v.name, ([], []))
            bad = (set(lg.infeasible.get(v.name, {})) | set(no_in) | set(no_out)
                   | set(reach.no_way_in) | set(reach.no_way_out))
            out[v.name] = sorted((sid for sid in free if sid not in bad), key=natural)
        return out

    def unusable(self) -> dict[str, dict[str, dict[str, str]]]:
        """Per vehicle type, the free slots it cannot use, by row, each with why: the
        answer to "which bays can my van not use, and why?", in full.

        A row is one of the lot's ``rows`` (``lot.rows[2] (aisle A, left)``), or the
        side of an aisle its single slots open onto (``aisle A, left``); rows in the
        order of the file, slots in natural order. Why is the first that holds of: the
        type does not fit (``the car is 5.37 m long, the slot 5.00 m``), no entrance
        reaches the slot, none of its turns lead there, no exit can be reached from it,
        it cannot leave it for an exit. A type that can use every free slot maps to
        ``{}``; taken slots are not listed (cars parked at start never move). These are
        the free slots :meth:`usable` leaves out (docs/python.md shows both).
        """
        lg, reach = self.prepared.lot_graph, self.reachability
        free = sorted((s.id for s in lg.lot.free_slots), key=natural)
        row_of = rows_of(self.prepared)
        out: dict[str, dict[str, dict[str, str]]] = {}
        for v in self.prepared.scenario.vehicle_types:
            no_in, no_out = (set(ids) for ids in reach.by_type.get(v.name, ([], [])))
            misfits = lg.infeasible.get(v.name, {})
            rows: dict[str, dict[str, str]] = {}
            for sid in free:
                why = (misfits.get(sid)
                       or ("no entrance reaches it" if sid in reach.no_way_in else None)
                       or ("none of the turns it can make lead there" if sid in no_in
                           else None)
                       or ("no exit can be reached from it" if sid in reach.no_way_out
                           else None)
                       or ("it can park in it but not leave it for an exit" if sid in no_out
                           else None))
                if why is not None:
                    rows.setdefault(row_of[sid], {})[sid] = why
            order = list(dict.fromkeys(row_of.values()))
            out[v.name] = {row: rows[row] for row in order if row in rows}
        return out

    def unusable_text(self) -> str:
        """:meth:`unusable` as ``lotsim validate --unusable`` prints it
        (:func:`unusable_text`)."""
        return unusable_text(self.as_dict())

    def as_dict(self) -> dict:
        """What ``lotsim validate --json`` writes of this lot, as plain data: the file,
        the scenario's name, :attr:`complete`, the slots free, per type the free slots it
        can use (:meth:`usable`) and those it cannot, by row, with why (:meth:`unusable`),
        why cars of a type would be turned away, the bays by use and their standard's
        check (:attr:`bays`), the service routes (:attr:`routes`, each envelope as WKT),
        and the summary's warnings."""
        return {"source": self.source, "scenario": self.name, "complete": self.complete,
                "free_slots": len(self.prepared.lot.free_slots), "usable": self.usable(),
                "unusable": self.unusable(), "turned_away": dict(self.turned_away),
                "bays": self.bays.as_dict(),
                "routes": [r.to_json() for r in self.routes], "warnings": self.warnings}

    def summary(self, *, verbose: bool = False) -> str:
        """What ``lotsim validate`` prints for this scenario (``verbose``: also how the
        maneuvers were found: problems searched, repeats, the cache)."""
        lg, reach = self.prepared.lot_graph, self.reachability
        scenario = self.prepared.scenario
        lot = lg.lot
        planner = self.prepared.maneuver_planner
        kinds = ", ".join(f"{k} {n}" for k, n in self.slot_counts.items())
        facts = lg.facts()
        kinds_of = Counter(facts.kinds)
        taken = len(lot.occupied)
        # slots no type fits are unreached for that reason, given first, not the lanes'
        unfit_ids = unfit(lg, [v.name for v in scenario.vehicle_types])
        no_way_in = [sid for sid in reach.no_way_in if sid not in unfit_ids]
        u = scenario.units  # lengths as the scenario file gives them
        lines = [
            f"{self.source}: {self.verdict} — {scenario.name}",
            f"  slots: {len(lot.slots)} ({kinds}); free {len(lot.slots) - taken}, taken {taken}",
            "  vehicle types: "
            + "; ".join(
                f"{v.name} (L {shown_length(v.length, u, '.2f')}, "
                f"W {shown_length(v.width, u, '.2f')}, "
                f"R {shown_length(v.min_turning_radius, u, '.2f')})"
                for v in scenario.vehicle_types
            ),
            f"  aisles: {len(lot.aisles)}, lanes: {len(lot.lanes)}, "
            f"graph: {facts.nodes} nodes, {facts.edges} edges "
            f"({_n(kinds_of['turn'], 'junction turn')}, "
            f"{_n(kinds_of['turnaround'], 'turnaround')})",
            f"  entrances: {', '.join(lg.entrances) or 'none'}; "
            f"exits: {', '.join(lg.exits) or 'none (vehicles cannot leave)'}",
            *self.bays.lines(u),
        ]
        if taken == len(lot.slots) and scenario.traffic is not None:
            lines.append("  warning: no slot is free: every car will be turned away (the lot "
                         "is full)")
        free_ids = {s.id for s in lot.free_slots}
        for vname, slots in self.refused.items():
            bays = [sid for sid in slots if sid in free_ids]
            if bays:
                uses = ", ".join(dict.fromkeys(USES[lot.slot_by_id[sid].use].label
                                               for sid in sorted(bays, key=natural)))
                lines.append(f"  note: {vname} may not use {_n(bays, 'free bay')} by their "
                             f"use ({uses}): {_ids(bays)}")
        if planner is not None:
            for vname, slots in self.misfits.items():
                if not slots:
                    continue
                lines.append(f"  warning: {vname} cannot park in "
                             f"{_misfits(slots, {s.id for s in lot.free_slots})}")
                for why in sorted(set(slots.values()))[:3]:
                    lines.append(f"    because {why}")
        for why in self.turned_away.values():
            lines.append(f"  warning: {why}: its cars in the traffic will be turned away")
        if reach.ok:
            lines.append("  unreachable: none")
        if no_way_in:
            lines.append(f"  warning: {_n(no_way_in, 'free slot')} cannot be reached from "
                         f"any entrance: {_ids(no_way_in)}")
        if reach.no_way_out:
            lines.append(f"  warning: from {len(reach.no_way_out)} free slots no exit can be "
                         f"reached: {_ids(reach.no_way_out)}")
        for vname, (no_in, no_out) in reach.by_type.items():
            if no_in:
                lines.append(f"  warning: {vname} fits but cannot reach "
                             f"{_n(no_in, 'free slot')} (no turns it can make lead there): "
                             f"{_ids(no_in)}")
            if no_out:
                lines.append(f"  warning: {vname} can park in but not leave "
                             f"{_n(no_out, 'free slot')} for an exit: {_ids(no_out)}")
        # with several gates, what each one serves (every slot may still be served by some)
        if len(reach.unreachable) > 1:
            for name, slots in reach.unreachable.items():
                slots = [sid for sid in slots if sid not in unfit_ids]
                if slots and len(slots) > len(no_way_in):
                    lines.append(f"  note: from entrance {name!r}, {len(slots)} free slots "
                                 f"cannot be reached: {_ids(slots)}")
        if len(reach.stranded) > 1:
            for name, slots in reach.stranded.items():
                if slots:
                    lines.append(f"  note: exit {name!r} cannot be reached from {len(slots)} "
                                 f"slots: {_ids(slots)}")
        free = len(lot.slots) - taken
        usable = "; ".join(
            f"{name} {len(ids)} of {free}" + (f" ({id_ranges(ids, most=4)})"
                                              if 0 < len(ids) < free else "")
            for name, ids in self.usable().items())
        lines.append(f"  usable free slots per type: {usable}")
        if planner is not None and verbose:
            remembered = planner.stats.get("remembered", 0)
            fitted = planner.stats.get("fitted", 0)
            searched = planner.stats["planned"] - remembered - fitted
            lines.append(f"  maneuvers: {facts.park_maneuvers} kept (per type, slot and lane); "
                         f"{planner.stats['planned']} distinct problems: {searched} searched, "
                         f"{fitted} fitted from a bay of the same shape"
                         + (f", {remembered} answered as in a lot prepared before"
                            if remembered else "")
                         + f" ({planner.stats['reused']} repeats answered from them; "
                         f"margin {planner.margin:g} m)"
                         + (LOADED if lg.from_cache else ""))
        for r in self.routes:
            lines.append(f"  {r.line(u)}" if r.passed else f"  warning: {r.line(u)}")
        for end in loose_ends(lot.aisles, lot.pavement):
            lines.append(f"  warning: {end}")
        for note in lg.skipped_turns:
            # a turn the ground is not paved for is the lot's drawing, not its design
            tag = "warning" if PAVEMENT_EDGE in note else "note"
            lines.append(f"  {tag}: {note}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


def unusable_text(answer: dict) -> str:
    """A lot's :meth:`ValidationReport.as_dict` as ``lotsim validate --unusable`` prints
    it: per vehicle type, a line per row and reason naming every free slot it cannot use
    (runs of numbers as ``N1–N6``)."""
    free = answer["free_slots"]
    lines = [f"{answer['source']}: the free slots each vehicle type cannot use, by row, "
             "and why"]
    for name, rows in answer["unusable"].items():
        n = sum(len(slots) for slots in rows.values())
        if not n:
            lines.append(f"  {name}: can use every free slot ({free})")
            continue
        lines.append(f"  {name}: cannot use {n} of {free} free slots")
        for row, slots in rows.items():
            for why in dict.fromkeys(slots.values()):
                ids = [sid for sid, w in slots.items() if w == why]
                lines.append(f"    {row}: {id_ranges(ids, most=len(ids))} — {why}")
    return "\n".join(lines)


def rows_of(prepared: PreparedLot) -> dict[str, str]:
    """Slot id → the row it belongs to, as :meth:`ValidationReport.unusable` names rows:
    ``lot.rows[2] (aisle A, left)`` for a slot of the file's ``rows``, ``aisle A, left``
    for a single slot along an aisle."""
    spec, lot = prepared.scenario.lot, prepared.lot
    out = {}
    for k, row in enumerate(spec.rows):
        prefix = row.id_prefix or f"{row.aisle}-{row.side}-"
        for n in range(row.count):
            out[f"{prefix}{row.first_number + n}"] = (f"lot.rows[{k}] (aisle {row.aisle}, "
                                                      f"{row.side})")
    return {s.id: out.get(s.id, f"aisle {s.aisle}, {s.side}") for s in lot.slots}


def validate_prepared(prepared: PreparedLot, source: str,
                      routes: RouteSettings | None = None) -> ValidationReport:
    """Check that the scenario's traffic can be served as ``lotsim run`` would (refusing
    what it would refuse) and report on its lot, and plan its service routes (with
    ``routes``, default :class:`~lotsim.roadmap.service_routes.RouteSettings`).

    Raises
    ------
    ScenarioError
        For traffic the lot cannot serve at all (:func:`lotsim.sim.running.check_traffic`).
    """
    scenario, lg = prepared.scenario, prepared.lot_graph
    reach = lg.reachability()
    away: dict[str, str] = {}
    if scenario.traffic is not None:
        traffic = arrivals(scenario.traffic, scenario.seed)
        every = traffic + [a for s in scenario.traffic.streams for a in _any_draw(s)]
        check_traffic(lg, every, reach)
        check_lot_events(lg, scenario.disturbances)
        # why each type's cars would be turned away (the scenario's own draw, and any car
        # of that type another seed may draw)
        ids = turned_away(lg, every, reach)
        for a in every:
            if a.id in ids:
                away.setdefault(a.vehicle, ids[a.id])
    planned = plan_routes(prepared.lot, scenario.routes, routes)
    return ValidationReport(source, prepared, reach, away, planned)


def _any_draw(stream: StreamSpec) -> list[Arrival]:
    """A vehicle of each type and at each entrance the stream may draw: ``run --seed``
    draws other vehicles than the scenario's seed, and must not be refused for a type or
    an entrance that ``validate`` let pass."""
    dwell = None if stream.dwell is None else stream.dwell.least
    return [Arrival(f"{stream.prefix}?{name}@{gate}", name, gate, stream.start, dwell,
                    stream.where)
            for name, weight in stream.mix if weight > 0 for gate in stream.entrances]


def _misfits(slots: dict[str, str], free: set[str]) -> str:
    """``"3 free slots (and 1 taken): N1, N3, N4"``: the slots a type cannot park in, the
    free ones named (a car parked at start never moves), the rest counted."""
    bad = [sid for sid in slots if sid in free]
    taken = len(slots) - len(bad)
    if not bad:
        return _n(taken, "taken slot")
    return (_n(bad, "free slot") + (f" (and {taken} taken)" if taken else "")
            + f": {_ids(bad)}" + (" (all, by row: lotsim validate --unusable)"
                                  if len(bad) > 12 else ""))


def _n(items, what: str) -> str:
    """``"1 free slot"``, ``"3 free slots"`` (``items``: the things, or how many)."""
    n = items if isinstance(items, int) else len(items)
    return f"{n} {what}{'' if n == 1 else 's'}"


def natural(slot_id: str) -> tuple:
    """Sort key that puts ``N2`` before ``N10``: runs of digits compare as numbers.

    >>> sorted(["N10", "N2", "S1", "N1"], key=natural)
    ['N1', 'N2', 'N10', 'S1']
    """
    return tuple((0, int(part), "") if part.isdigit() else (1, 0, part)
                 for part in re.split(r"(\d+)", slot_id) if part)


def _ids(ids: list[str], most: int = 12) -> str:
    ids = sorted(ids, key=natural)
    head = ", ".join(ids[:most])
    return head + (f", … (+{len(ids) - most})" if len(ids) > most else "")


def id_ranges(ids: Iterable[str], most: int = 12) -> str:
    """Ids in natural order, runs of one prefix with consecutive numbers as ``N1–N10``; at
    most ``most`` runs shown.

    >>> id_ranges(["S2", "N10", "S1", "X1"] + [f"N{k}" for k in range(1, 10)])
    'N1–N10, S1–S2, X1'
    """
    runs: list[list] = []  # [prefix, first, last, first id, last id]
    for sid in sorted(ids, key=natural):
        m = re.fullmatch(r"(.*?)(\d+)", sid)
        prefix, number = (m.group(1), int(m.group(2))) if m else (sid, None)
        last = runs[-1] if runs else None
        if (last is not None and number is not None and last[0] == prefix
                and last[2] is not None and number == last[2] + 1):
            last[2], last[4] = number, sid
        else:
            runs.append([prefix, number, number, sid, sid])
    shown = [r[3] if r[3] == r[4] else f"{r[3]}–{r[4]}" for r in runs]
    return _ids(shown, most) if len(shown) > most else ", ".join(shown)
