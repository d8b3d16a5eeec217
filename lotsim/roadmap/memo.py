"""What building a lot's graph works out that another build of the same lot asks again
(:class:`RoadmapMemo`), and the vehicle types' designs it is keyed by."""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

from lotsim.errors import SettingsError
from lotsim.lot.model import DesignVehicle, Lot
from lotsim.roadmap.remembered import keep, lot_key
from lotsim.roadmap.settings import RoadmapSettings

if TYPE_CHECKING:
    from lotsim.core.reusecheck import ReuseCheck
    from lotsim.core.workers import Background


class RoadmapMemo:
    """The answers building ``lot``'s graph with ``settings`` works out, for the next build
    of the same lot with the same settings.

    Preparing a lot builds its graph twice (the lanes alone, for where each slot's maneuver
    may begin, then the graph through the maneuvers); the junction turns, the multi-point
    junction turns and U-turns, and the dead ends' turnarounds do not depend on the
    maneuvers (or only through a few stations), so the second build takes them from here.
    Every answer is a function of its arguments alone: a graph is the same built with a
    memo as without. The caller creates one for a lot and passes it to each build
    (:func:`~lotsim.roadmap.assemble.build_graph`); it lives as long as the caller keeps it.

    Attributes
    ----------
    lot : Lot
        The lot the answers are for (a build of another lot refuses the memo).
    settings : RoadmapSettings
        The roadmap's tuning the answers were worked out with (a build with other settings
        refuses the memo); part of every piece's key in :attr:`known`.
    turns : dict
        :func:`types_key` → the junction turns with the types each suits, and the notes of
        those skipped (:func:`~lotsim.roadmap.junctions.turns_of`).
    multipoints, uturns : dict
        :func:`types_key` → multi-point junction turns, U-turns at junctions, each with the
        types it suits.
    turnarounds : dict
        (types, dead ends with where cars arrive on them) → the dead ends' turnarounds and
        notes (:func:`~lotsim.roadmap.turnarounds.dead_end_turnarounds`).
    plans : dict
        The turnaround searches made so far, by lane, design and arguments.
    ahead : tuple or None
        The keys of :attr:`plans` being planned ahead, the background process planning
        them and their piece keys (:func:`~lotsim.roadmap.turnarounds.plan_turnarounds_ahead`).
    known : dict or None
        Pieces of the roadmap worked out when the lot (or an earlier version of it) was
        prepared before, by what each read (:mod:`~lotsim.roadmap.remembered`); those
        worked out now are added. None: none kept.
    recalled, worked : int
        How many pieces were taken from :attr:`known`, and how many worked out.
    reuse_check : ReuseCheck or None
        The reuse check (:class:`~lotsim.core.reusecheck.ReuseCheck`): every piece taken
        from :attr:`known` is also worked out again and compared. None: none.
    """

    @functools.cached_property
    def lot_key(self) -> bytes:
        """:func:`~lotsim.roadmap.remembered.lot_key` of the memo's lot and settings, worked
        out once."""
        return lot_key(self.lot, self.settings)

    def __init__(self, lot: Lot, known: dict | None = None, *,
                 settings: RoadmapSettings | None = None,
                 reuse_check: ReuseCheck | None = None):
        self.lot = lot
        self.settings = RoadmapSettings() if settings is None else settings
        self.known = known
        self.reuse_check = reuse_check
        self.recalled = self.worked = 0
        self.touched: set[bytes] = set()  # keys added to known (by a forked worker)
        self.turns: dict = {}
        self.multipoints: dict = {}
        self.uturns: dict = {}
        self.turnarounds: dict = {}
        self.plans: dict = {}
        self.ahead: tuple[list, Background] | None = None

    def check(self, lot: Lot, settings: RoadmapSettings | None = None) -> RoadmapMemo:
        """This memo, when it is ``lot``'s and ``settings``' (a memo holds the answers of one
        lot, worked out with one tuning; None: the defaults)."""
        if lot is not self.lot:
            raise SettingsError("memo", "a RoadmapMemo serves the one lot it was made for")
        if (RoadmapSettings() if settings is None else settings) != self.settings:
            raise SettingsError("memo", "a RoadmapMemo serves the roadmap settings it was "
                                        "made with")
        return self

    def take_ahead(self) -> None:
        """Move the plans the background process has finished so far into :attr:`plans`."""
        if self.ahead is not None:
            keys, background, pieces = self.ahead
            for k, version in background.take().items():
                if keys[k] not in self.plans:
                    self.plans[keys[k]] = version[0]
                    if keys[k] in pieces:
                        keep(self.known, pieces[keys[k]], version)
                    self.worked += 1


def types_key(designs: dict[str, DesignVehicle] | None) -> tuple | None:
    """What a :class:`RoadmapMemo` keys a set of vehicle types by (None: the lot's design
    vehicle for every type)."""
    return tuple(sorted(designs.items())) if designs else None


def designs_of(vehicles) -> dict[str, DesignVehicle] | None:
    """Vehicle type → its own outline and limits, for two types or more (None: the lot's
    design vehicle serves every type): what a lot's graph plans turns and turnarounds for."""
    names = sorted({v.name for v in vehicles})
    return ({v.name: DesignVehicle.envelope([v]) for v in vehicles} if len(names) > 1
            else None)
