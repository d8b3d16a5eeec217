"""A lot's bays by use, counted against a standard (:func:`bay_report`), and its bay
schedule (:func:`bay_schedule`): what ``lotsim validate`` reports for a lot designer.

The built-in standard is the 2010 ADA Standards for Accessible Design, Table 208.2 (the
accessible spaces a facility of so many spaces needs) and §208.2.4 (one in six of those, or
fraction of six, van-accessible), counted per facility: a scenario's lot is one facility.
Every bay counts toward the total but motorcycle bays; accessible bays count toward it too,
and a van-accessible bay is an accessible one. Another standard is a table the scenario
states (``lot.standard``: a count or a share of the total per use).
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from lotsim.core.geometry import FloatArray
from lotsim.core.units import in_units, shown_length
from lotsim.lot.model import Lot
from lotsim.lot.spec import Requirement, StandardSpec
from lotsim.lot.uses import ADA_2010, USES, ada_accessible, ada_van
from lotsim.lot.walks import shortest_walk, walk_start, walking_ground


@dataclass(frozen=True, slots=True)
class UseCheck:
    """What a standard asks of one use of bay, and what the lot holds.

    Attributes
    ----------
    use : str
        The use (``accessible`` counts the van-accessible bays too).
    required, found : int
        Bays asked for and bays the lot has.
    rule : str
        Where the number comes from (``Table 208.2``, ``a share of 10 %``).
    """

    use: str
    required: int
    found: int
    rule: str

    @property
    def met(self) -> bool:
        return self.found >= self.required

    @property
    def short(self) -> int:
        """How many bays are missing (0 when met)."""
        return max(self.required - self.found, 0)

    def as_dict(self) -> dict:
        return {"use": self.use, "required": self.required, "found": self.found,
                "met": self.met, "short": self.short, "rule": self.rule}


@dataclass(frozen=True, slots=True)
class Walk:
    """An accessible bay's walk to the nearest building entrance [m]: from the middle of the
    bay's side that opens onto its access aisle (the side opening onto the driving aisle for
    a bay without one) over the paved ground, round the other bays, islands, obstacles and
    buildings (:func:`~lotsim.lot.walks.shortest_walk`).

    Attributes
    ----------
    slot, entrance : str
    distance : float
        The walk's length [m] (``inf``: no way on foot).
    straight : float
        The straight line from the same start to the entrance [m]: at most ``distance``.
    path : ndarray, shape (N, 2)
        The walk's corners, from the start to the entrance [m].
    """

    slot: str
    entrance: str
    distance: float
    straight: float = math.nan
    path: FloatArray = field(default_factory=lambda: np.zeros((0, 2)), compare=False,
                             repr=False)


@dataclass(frozen=True, slots=True)
class BayReport:
    """A lot's bays by use and the standard's check of them.

    Attributes
    ----------
    by_use : dict
        Use → bays of it, every use listed (:data:`~lotsim.lot.uses.USES`, in order).
    total : int
        The bays counted toward the standard's total (all but motorcycle bays).
    standard : str
        The standard's name (``ADA 2010``, or the one the scenario states).
    checks : tuple of UseCheck
    walks : tuple of Walk
        One per accessible or van-accessible bay when the lot names building entrances.
    """

    by_use: dict[str, int]
    total: int
    standard: str
    checks: tuple[UseCheck, ...]
    walks: tuple[Walk, ...] = ()

    @property
    def met(self) -> bool:
        """Every count the standard asks for is met."""
        return all(c.met for c in self.checks)

    def as_dict(self) -> dict:
        return {"by_use": dict(self.by_use), "total": self.total, "standard": self.standard,
                "met": self.met, "checks": [c.as_dict() for c in self.checks],
                "walks": [{"slot": w.slot, "entrance": w.entrance,
                           "distance": round(w.distance, 2) if math.isfinite(w.distance)
                           else None, "straight": round(w.straight, 2),
                           "over": "pavement"} for w in self.walks]}

    def lines(self, units: str = "m") -> list[str]:
        """The report as ``lotsim validate`` prints it (indented lines), lengths in
        ``units`` (the scenario file's)."""
        uses = ", ".join(f"{USES[u].label} {n}" for u, n in self.by_use.items() if n)
        out = [f"  bays by use: {uses or 'none'}"]
        if not self.total:
            return out
        parts = []
        for c in self.checks:
            verdict = "met" if c.met else f"not met, {c.short} short"
            parts.append(f"{USES[c.use].label} {c.found} of {c.required} required "
                         f"({c.rule}): {verdict}")
        head = "met" if self.met else "not met"
        out.append(f"  {self.standard} for {self.total} bays: {head} — " + "; ".join(parts))
        for w in self.walks:
            straight = shown_length(w.straight, units, '.1f')
            if math.isfinite(w.distance):
                out.append(f"    {w.slot}: {shown_length(w.distance, units, '.1f')} walk to "
                           f"{w.entrance} over the pavement (straight line {straight})")
            else:
                out.append(f"    {w.slot}: no walk to {w.entrance} over the pavement "
                           f"(straight line {straight})")
        return out


def bay_report(lot: Lot, standard: StandardSpec | None = None,
               entrances: Iterable[tuple[str, tuple[float, float]]] = ()) -> BayReport:
    """``lot``'s bays by use, checked against ``standard`` (None: ADA 2010), with each
    accessible bay's walk to the nearest of ``entrances`` (``(id, (x, y))``,
    :func:`bay_walks`).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> lot = NS(slots=[NS(id=f"P{k}", use="standard") for k in range(30)]
    ...         + [NS(id="H1", use="accessible")])
    >>> r = bay_report(lot)
    >>> r.total, [(c.use, c.required, c.found, c.met) for c in r.checks], r.walks
    (31, [('accessible', 2, 1, False), ('van_accessible', 1, 0, False)], ())
    """
    by_use = dict.fromkeys(USES, 0)
    for s in lot.slots:
        by_use[s.use] += 1
    total = sum(n for u, n in by_use.items() if u != "motorcycle")
    accessible = by_use["accessible"] + by_use["van_accessible"]
    if standard is None or not standard.requirements:
        need = ada_accessible(total)
        checks = (UseCheck("accessible", need, accessible, "Table 208.2"),
                  UseCheck("van_accessible", ada_van(need), by_use["van_accessible"],
                           "§208.2.4, 1 in 6"))
        name = ADA_2010
    else:
        checks = tuple(_check(r, total, by_use) for r in standard.requirements)
        name = standard.name
    walks = bay_walks(lot, entrances)
    return BayReport(by_use, total, name, checks, tuple(walks))


def bay_walks(lot: Lot, entrances: Iterable[tuple[str, tuple[float, float]]]
              ) -> tuple[Walk, ...]:
    """Each accessible bay's walk over ``lot``'s paved ground to the nearest of
    ``entrances`` (``(id, (x, y))``), by the length walked (:class:`Walk`)."""
    doors = list(entrances)
    bays = [s for s in lot.slots if USES[s.use].accessible]
    if not doors or not bays:
        return ()
    ground = walking_ground(lot.ground, [s.polygon for s in lot.slots],
                            [a.polygon for a in lot.areas])
    out = []
    for s in bays:
        start = walk_start(s, [a.polygon for a in lot.access_aisles if s.id in a.slots])
        best = min(((shortest_walk(ground, start, p, opened=s.shape), n) for n, p in doors),
                   key=lambda wn: (wn[0].length, wn[0].straight))
        out.append(Walk(s.id, best[1], best[0].length, best[0].straight, best[0].points))
    return tuple(out)


def _check(req: Requirement, total: int, by_use: dict[str, int]) -> UseCheck:
    found = by_use[req.use] + (by_use["van_accessible"] if req.use == "accessible" else 0)
    rule = f"{req.count} bays" if req.count is not None else f"{req.share:.0%} of the total"
    return UseCheck(req.use, req.least(total), found, rule)


SCHEDULE_COLUMNS = ("row", "use", "kind", "count", "bays", "length_m", "width_m",
                    "angle_deg", "access_aisles")
"""The columns of a bay schedule (:func:`bay_schedule`)."""
LENGTHS = ("length_m", "width_m")
"""Its columns of lengths, written in the scenario file's unit."""


def bay_schedule(lot: Lot, rows: dict[str, str]) -> list[dict]:
    """The lot's bay schedule: a line per row, use and size (``rows``: slot id → its row,
    as :func:`lotsim.sim.validation.rows_of` names them), in the lot's order of bays, with
    how many bays, their ids, length and width [m], angle to the aisle [°] and the access
    aisles beside them."""
    served = {}
    for a in lot.access_aisles:
        for sid in a.slots:
            served.setdefault(sid, a.id)
    out: dict[tuple, dict] = {}
    for s in lot.slots:
        key = (rows[s.id], s.use, s.kind, round(s.length, 3), round(s.width, 3),
               round(math.degrees(s.angle), 1))
        line = out.setdefault(key, {"row": key[0], "use": s.use, "kind": s.kind, "count": 0,
                                    "bays": [], "length_m": key[3], "width_m": key[4],
                                    "angle_deg": key[5], "access_aisles": set()})
        line["count"] += 1
        line["bays"].append(s.id)
        if s.id in served:
            line["access_aisles"].add(served[s.id])
    return [{**line, "access_aisles": len(line["access_aisles"])} for line in out.values()]


def schedule_csv(lines: list[dict], ids, units: str = "m") -> str:
    """A bay schedule as CSV text; ``ids(list)`` writes a line's bay ids (runs as
    ``N1–N6``); lengths in ``units`` (the scenario file's), named in their columns
    (``length_ft``)."""
    text = io.StringIO()
    w = csv.writer(text, lineterminator="\n")
    w.writerow([k.replace("_m", f"_{units}") if k in LENGTHS else k
                for k in SCHEDULE_COLUMNS])
    for line in lines:
        w.writerow([ids(line["bays"]) if k == "bays" else
                    round(in_units(line[k], units), 3) if k in LENGTHS else line[k]
                    for k in SCHEDULE_COLUMNS])
    return text.getvalue()
