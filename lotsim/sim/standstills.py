"""A plan cut into *runs*: what a car drives from one standstill to the next (from its
gate, a wait, a cusp between maneuvers, its slot), the pieces a plan is driven in through
its disturbances (:mod:`lotsim.sim.execution`), and a plan so driven
(:class:`Driven`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from lotsim.sim.repairs import LotChanges
from lotsim.sim.results import VehicleRun
from lotsim.traffic.disturbances import Stall

EPS = 1e-9
"""Times closer than this are the same instant [s]."""


@dataclass
class Run:
    """What one car drives from one standstill to the next: its moves ``first`` to
    ``last`` (indices into the car's moves), planned from ``t0`` to ``t1`` [s]."""

    car: int
    index: int  # among the car's runs
    first: int
    last: int
    t0: float
    t1: float
    factor: float = 1.0  # speed factor it is driven with
    late: float = 0.0  # its start comes this late [s]
    stall: float = 0.0  # the car stands this long more before it [s]
    stalls: list[Stall] = field(default_factory=list)
    in_slot: bool = False  # it sets off from a slot (a stall does not stop it there)
    late_by: float = 0.0  # how late its start was drawn (kept when it is driven again) [s]
    gap: float = 0.0  # how long the first plan has the car stand before it [s]

    @property
    def duration(self) -> float:
        """Its executed duration [s]."""
        return (self.t1 - self.t0) / self.factor


def runs_of(v: VehicleRun, car: int) -> list[Run]:
    """``v``'s plan cut at every standstill. The first run begins where the car first
    stands in the lot: a car that waits inside its gate before it drives holds its space
    from then."""
    out: list[Run] = []
    moves = v.moves
    head = None  # the first of the waits inside the gate before the first run
    for k, m in enumerate(moves):
        if m.motion is None:
            if not out and m.kind == "wait" and head is None:
                head = k
            continue
        prev = moves[k - 1] if k else None
        if not out:
            first = k if head is None else head
            out.append(Run(car, 0, first, k, moves[first].t0, m.t1))
        elif prev.motion is None or m.level_from == 0:
            out.append(Run(car, len(out), k, k, m.t0, m.t1, in_slot=prev.kind == "parked",
                           gap=m.t0 - out[-1].t1))
        else:
            out[-1].last, out[-1].t1 = k, m.t1
    return out


def stop_after(rs: list[Run], t: float) -> Run | None:
    """The run that sets off from the first standstill on the lanes at or after ``t`` [s]
    (by the plan): not the car's first (it sets off from its gate) nor one out of its
    slot."""
    return next((r for r in rs[1:] if not r.in_slot and rs[r.index - 1].t1 >= t - EPS), None)


@dataclass
class Driven:
    """A plan driven once (:func:`_drive`): the plan (``plan``, its cars' moves; the first
    plan, or one driven before with cars planned again), its runs, the executed start of
    every run (by ``id``), the cars as executed, and the lot's changes as they met them."""

    plan: list[VehicleRun]
    runs: list[list[Run]]
    starts: dict[int, float]
    executed: list[VehicleRun]
    changes: LotChanges | None
    chunks: Any = None  # what the plan's moves sweep (execution._Chunks)
    meets: Any = None  # the pairs of chunks of two cars that meet, as index arrays
    repaired: int = 0  # cars planned again on their way (lotsim.sim.rerouting)
    stalls_dropped: int = 0  # stalls those cars' new ways had no place of rest for


def stretch(em, m) -> float:
    """How much slower move ``m`` was driven than its edge's motion ``em`` (1.0: as the
    motion, to within a nanosecond a second): a plan driven before holds retimed moves,
    which sweep the same hulls over times stretched alike."""
    k = (m.t1 - m.t0) / em.duration if em.duration > 0 else 1.0
    return 1.0 if abs(k - 1.0) < 1e-9 else k
