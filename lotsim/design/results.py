"""What a layout search finds (:mod:`lotsim.design.search`): each prepared candidate's
figures and how they rank (:class:`Evaluation`), and the candidates it prepared, best
first, side by side (:class:`LayoutResult`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from lotsim.design.plot import PlotSpec
from lotsim.design.settings import LayoutSettings
from lotsim.io.imports.draft import comment
from lotsim.lot.uses import USES


@dataclass(frozen=True, slots=True)
class Evaluation:
    """One candidate, prepared (and perhaps run).

    Attributes
    ----------
    index : int
        Its place in the order candidates were drawn.
    label : str
        How it was drawn (module kind, orientation, offset, order of rows).
    drawn : int
        Bays drawn.
    bays : int
        Bays every vehicle type can reach, park in and leave (0 when it failed).
    aisle_length : float
        Aisle centre lines in all [m].
    area : float
        The plot's area [m²].
    yaml : str
        The scenario of its usable bays (``""`` when it failed).
    problem : str
        Why it failed (``""`` when it did not).
    mean_time_to_park : float or None
        From the run at the plot's demand [s] (None: not run).
    throughput : float or None
        Cars parked per hour in that run: those parked over the time from the first
        arrival to the last parking.
    parked, vehicles : int
        Cars parked in that run, of those that came.
    checked : bool or None
        Whether ``lotsim check`` passed that run (None: not run).
    seconds : float
        Time spent on it.
    by_use : tuple of (use, bays)
        Its bays by use, every use (:data:`~lotsim.lot.uses.USES`), as ``lotsim validate``
        counts them; () where the plot asks for no uses.
    met : bool or None
        Whether its bays meet ADA 2010 (Table 208.2 and §208.2.4) as ``lotsim validate``
        checks them; None where the plot asks for no accessible bays.
    short : tuple of (use, bays)
        The bays by use asked for that it has no room for.
    served : int
        The bays its circulation was judged to serve before it was prepared
        (:func:`~lotsim.design.circulation.circulation`).
    dead_end_length : float
        Aisle a car comes back along after a dead end, in all [m].
    """

    index: int
    label: str
    drawn: int
    bays: int
    aisle_length: float
    area: float
    yaml: str = ""
    problem: str = ""
    mean_time_to_park: float | None = None
    throughput: float | None = None
    parked: int = 0
    vehicles: int = 0
    checked: bool | None = None
    seconds: float = 0.0
    by_use: tuple[tuple[str, int], ...] = ()
    met: bool | None = None
    short: tuple[tuple[str, int], ...] = ()
    served: int = 0
    dead_end_length: float = 0.0
    dead_end_cost: float = 0.0
    """What 100 m of its dead ends cost it in the ranking [bays]
    (:attr:`~lotsim.design.settings.LayoutSettings.dead_end_cost`)."""
    paved: float = 0.0
    """The ground its usable bays and aisles take [m²]: the aisles with their kerb
    corners and the bays, as a lot paved only there is
    (:func:`~lotsim.lot.pavement.pave`; 0 when it failed)."""

    @property
    def paved_per_bay(self) -> float:
        """Pavement per usable bay [m²] (:attr:`paved` over :attr:`bays`; 0: none)."""
        return self.paved / self.bays if self.bays else 0.0

    @property
    def worth(self) -> float:
        """Its usable bays less what its dead ends cost (:attr:`dead_end_cost`)."""
        return self.bays - self.dead_end_cost * self.dead_end_length / 100.0

    @property
    def ok(self) -> bool:
        return not self.problem and self.bays > 0

    @property
    def bays_per_100m2(self) -> float:
        return 100.0 * self.bays / self.area if self.area else 0.0

    def document(self) -> str:
        """The scenario's text as :func:`lotsim.layout` writes it: :attr:`yaml` with the
        candidate's figures in its header."""
        head, _, rest = self.yaml.partition("\n")
        run = ""
        if self.mean_time_to_park is not None and self.throughput is not None:
            run = (f"; a run of its demand: {self.parked} of {self.vehicles} cars parked, mean "
                   f"time to park {self.mean_time_to_park:.1f} s, {self.throughput:.0f} cars "
                   f"parked per hour, lotsim check {'passed' if self.checked else 'failed'}")
        paved = f", paved {self.paved_per_bay:.1f} m² a bay" if self.paved else ""
        figures = comment(f"{self.bays} bays, each usable by every vehicle type "
                          f"({self.bays_per_100m2:.2f} per 100 m²{paved}), aisles "
                          f"{self.aisle_length:.1f} m{run}.")
        if self.by_use:
            figures += "\n" + comment(f"Bays by use: {self.uses_text()}.")
        return f"{head}\n{figures}\n{rest}"

    def uses_text(self) -> str:
        """Its bays by use in words: ``standard 90, accessible 4, van-accessible 1, EV 10;
        ADA 2010 met``."""
        parts = ", ".join(f"{USES[u].label} {n}" for u, n in self.by_use if n) or "none"
        if self.met is not None:
            parts += f"; ADA 2010 {'met' if self.met else 'not met'}"
        if self.short:
            parts += "; no room for " + ", ".join(f"{n} {USES[u].label}" for u, n in
                                                  self.short)
        return parts

    def rank_key(self) -> tuple:
        """Whether its bays meet ADA 2010 where the plot asks for accessible bays (those
        that do first), then usable bays as laid out, access aisles and all, less what its
        dead ends cost (:attr:`worth`, most first, to the hundredth of a bay), then
        dead-end length (shortest first: a loop before a dead end of as many bays, to the
        decimetre), then mean time to park (shortest first; not run: last), then
        throughput (most first), then the order drawn."""
        t = self.mean_time_to_park if self.mean_time_to_park is not None else math.inf
        q = self.throughput if self.throughput is not None else -math.inf
        return (self.met is False, -round(self.worth, 2), round(self.dead_end_length, 1), t,
                -q, self.index)


@dataclass(frozen=True, slots=True)
class LayoutResult:
    """What :func:`~lotsim.design.search.lay_out` found: the candidates it prepared, best
    first, and how many it drew, with the settings that made them."""

    plot: PlotSpec
    settings: LayoutSettings
    ranked: tuple[Evaluation, ...]
    drawn: int
    seconds: float

    @property
    def best(self) -> Evaluation:
        return self.ranked[0]

    def table(self, most: int = 5) -> str:
        """The best ``most`` candidates side by side, a line each: where the plot asks for
        uses, with the bays of each use asked for, and whether ADA 2010 is met (``yes``,
        ``no``; ``-``: no accessible bays asked for)."""
        asked = _columns(self.plot)
        uses = "".join(f"  {title:>{len(title)}}" for _, title in asked)
        head = (f"{'#':>2}  {'bays':>5}  {'drawn':>5}{uses}  {'ADA':>3}  {'per 100 m²':>10}  "
                f"{'paved/bay':>9}  {'aisles [m]':>10}  {'dead ends':>9}  {'park [s]':>8}  "
                f"{'cars/h':>7}  layout")
        lines = [head]
        for k, e in enumerate(self.ranked[:most]):
            park = f"{e.mean_time_to_park:8.1f}" if e.mean_time_to_park is not None else \
                f"{'-':>8}"
            rate = f"{e.throughput:7.0f}" if e.throughput is not None else f"{'-':>7}"
            paved = f"{e.paved_per_bay:9.1f}" if e.ok and e.paved else f"{'-':>9}"
            what = e.label if e.ok else f"{e.label}: {e.problem}"
            counts = dict(e.by_use)
            cells = "".join(f"  {_use_cell(counts, u, e.ok):>{len(title)}}"
                            for u, title in asked)
            ada = "-" if e.met is None or not e.ok else ("yes" if e.met else "no")
            lines.append(f"{k + 1:>2}  {e.bays:>5}  {e.drawn:>5}{cells}  {ada:>3}  "
                         f"{e.bays_per_100m2:>10.2f}  {paved}  {e.aisle_length:>10.1f}  "
                         f"{e.dead_end_length:>9.1f}  {park}  "
                         f"{rate}  {what}")
        return "\n".join(lines)


def _columns(plot: PlotSpec) -> list[tuple[str, str]]:
    """The table's columns of bays by use for ``plot``: (use, title), those it asks for."""
    u = plot.uses
    out = []
    if u.accessible_wanted:
        out += [("accessible", "access."), ("van_accessible", "van")]
    if u.ev_wanted:
        out.append(("ev", "EV"))
    if u.compact is not None:
        out.append(("compact", "compact"))
    return out


def _use_cell(counts: dict[str, int], use: str, ok: bool) -> str:
    """A candidate's bays of ``use``; accessible ones with the van-accessible among them, as
    the standard counts them."""
    if not ok:
        return "-"
    n = counts.get(use, 0)
    return str(n + counts.get("van_accessible", 0) if use == "accessible" else n)
