"""Slot-choice policies: who chooses the slot a car tries when it arrives, or when it tries
again after waiting.

A policy is any callable taking a :class:`SlotRequest` and returning a slot id (the car
tries that slot), a sequence of slot ids (a ranking: the car first probes the few best
of it, as :class:`~lotsim.sim.settings.RunTuning` says, then searches fully where a probe
ran out), or None (the car waits outside and asks again ``settings.retry`` seconds later,
within its patience). The rankings of :data:`~lotsim.sim.settings.ASSIGNMENTS` are
policies of that kind (:class:`Ranked`): a run without a policy of its own uses
``Ranked(settings.assignment)``. :data:`ASK` leaves each choice to the code stepping the
run (:meth:`lotsim.sim.live.Live.decide`).

A choice the lot cannot honour (an unknown slot, one that is taken, one the car's type
cannot use or cannot reach from its entrance) raises :class:`~lotsim.errors.DecisionError`
naming the slot and why.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from lotsim.errors import DecisionError

ASK = "ask"
"""The policy that leaves every choice to the caller: the run pauses at each
(:attr:`lotsim.sim.live.Live.pending`) until :meth:`~lotsim.sim.live.Live.decide`."""


@dataclass(frozen=True)
class SlotRequest:
    """A car asking for a slot.

    Attributes
    ----------
    car, vehicle : str
        The car's id and its type's name.
    entrance : str or None
        The entrance it waits at (None: it stands inside the lot, on a lane).
    time : float
        When it asks [s].
    leaving : bool
        Whether it will leave again (it has a dwell).
    slots : tuple of str
        The free slots it can park in (and leave again, if it will), best first by the
        run's ``assignment``.
    static_times : mapping of str to float
        Each of those slots' static time from the entrance (or where it stands) [s]: the
        way in along the lanes and the maneuver, and the way out to the nearest exit for a
        car that will leave.
    """

    car: str
    vehicle: str
    entrance: str | None
    time: float
    leaving: bool
    slots: tuple[str, ...]
    static_times: Mapping[str, float]
    _rank: Callable[[str], list[str]] = field(repr=False, compare=False)
    _state: Callable[[], dict] = field(repr=False, compare=False)

    def ranked(self, by: str) -> list[str]:
        """:attr:`slots` ranked by one of :data:`~lotsim.sim.settings.ASSIGNMENTS`."""
        return self._rank(by)

    def state(self) -> dict:
        """The run's state now, as plain data (:meth:`lotsim.sim.live.Live.state`)."""
        return self._state()


@dataclass(frozen=True)
class Ranked:
    """The policy that ranks the free slots a car can use ``by`` one of
    :data:`~lotsim.sim.settings.ASSIGNMENTS`; ``Ranked(settings.assignment)`` is what a run
    without a policy of its own does."""

    by: str = "shortest"

    def __call__(self, request: SlotRequest) -> list[str]:
        return request.ranked(self.by)


def choices(answer, request: SlotRequest, why_not: Callable[[str], str]) -> list[str] | None:
    """A policy's ``answer`` to ``request`` as the slots to try in order (None: wait).

    Raises
    ------
    DecisionError
        For an answer that is no slot id, or a slot the car cannot take: ``why_not(slot)``
        says why.
    """
    if answer is None:
        return None
    picked = [answer] if isinstance(answer, str) else answer
    if not isinstance(picked, Sequence) or not all(isinstance(s, str) for s in picked):
        raise DecisionError(request.car, f"expected a slot id, a sequence of slot ids or "
                                         f"None, found {answer!r}")
    usable = set(request.slots)
    for sid in picked:
        if sid not in usable:
            raise DecisionError(request.car, f"cannot take slot {sid!r}: {why_not(sid)}")
    return list(dict.fromkeys(picked)) or None
