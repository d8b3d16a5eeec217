"""What a search answers: a :class:`Plan` of timed :class:`Move` s, and how a plan is
written into the reservation table (:func:`reserve_moves`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from lotsim.core.outcome import Status
from lotsim.traffic.reservation import ReservationTable
from lotsim.traffic.searchgraph import SearchGraph
from lotsim.traffic.swept import standing_body
from lotsim.vehicles.motion import Motion

REASONS = {Status.OUT_OF_BUDGET: "expansion limit", Status.NO_PATH: "no path"}
"""Why a search found nothing, by how it ended: it reached its expansion limit (its budget
of expansions ran out), or every way within its horizon was searched."""


@dataclass(frozen=True, slots=True)
class Move:
    """One timed step of a plan.

    ``kind`` is ``drive``, ``park``, ``leave``, ``wait``, ``parked`` (standing in
    the slot until leaving) or ``outside`` (waiting to enter, taking no space).
    ``motion`` is set for moving kinds, in time from ``t0``; ``end_pose`` is where
    the move leaves the vehicle (None outside).
    """

    kind: str
    t0: float
    t1: float
    node_from: int
    node_to: int
    level_from: int
    level_to: int
    edge: int = -1
    motion: Motion | None = None
    end_pose: tuple[float, float, float] | None = None
    steer: float = 0.0  # road-wheel angle while standing [rad]


@dataclass
class Plan:
    """A search's answer: how it ended (:class:`~lotsim.core.outcome.Status`: ``FOUND``,
    ``OUT_OF_BUDGET`` when it reached its expansion limit, ``NO_PATH``), the moves (when
    found) and how many states it expanded.

    Examples
    --------
    >>> Plan(Status.OUT_OF_BUDGET, expansions=20001).reason
    'expansion limit'
    """

    status: Status
    moves: list[Move] = field(default_factory=list)
    expansions: int = 0

    @property
    def found(self) -> bool:
        """Whether the search found its way (the moves)."""
        return self.status is Status.FOUND

    @property
    def reason(self) -> str:
        """Why nothing was found (:data:`REASONS`; ``""`` when found)."""
        return REASONS.get(self.status, "")

    @property
    def end(self) -> float:
        """When the last move ends [s] (nan without moves)."""
        return self.moves[-1].t1 if self.moves else math.nan


def reserve_moves(table: ReservationTable, owner: str, sg: SearchGraph, moves: list[Move], *,
                  hold_end: bool) -> None:
    """Reserve everything ``moves`` sweep for ``owner``; with ``hold_end``, also the last
    pose from the end on, for ever (a parked car)."""
    slots = sg.slot_nodes
    for m in moves:
        if m.kind == "outside":
            continue
        if m.motion is None:
            table.reserve_standing(owner, standing_body(sg.vehicle, m.end_pose), m.t0, m.t1,
                                   in_slot=m.node_to in slots)
        else:
            em = sg.motion(m.edge, m.level_from, m.level_to)
            assert em is not None  # it was found by the search
            table.reserve(owner, em.swept, offset=m.t0)
    if hold_end and moves and moves[-1].end_pose is not None:
        table.reserve_standing(owner, standing_body(sg.vehicle, moves[-1].end_pose),
                               moves[-1].t1, in_slot=moves[-1].node_to in slots)
