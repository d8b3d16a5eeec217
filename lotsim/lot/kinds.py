"""Slot kinds: what differs between a perpendicular, an angled and a parallel slot, in one
place per kind.

A kind decides how a slot of it sits on its aisle (how much aisle edge it takes, where its
entry is, which way a car parked nose-in faces), which lanes can serve it, the gear a car
enters in, what a car parked in it keeps other cars out of, and how its parking maneuver
is searched. Code elsewhere asks the slot's kind (:func:`kind_of`) instead of comparing
``slot.kind`` with a string. The registry :data:`KINDS` is closed: an unknown kind is an
error, not a silent default.

Examples
--------
>>> [k for k in KINDS]
['perpendicular', 'parallel', 'angled']
>>> KINDS["angled"].entry_gear, KINDS["perpendicular"].entry_gear
(1, -1)
>>> KINDS["parallel"].parks_along
True
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np
from shapely.geometry import LineString, Point, Polygon

from lotsim.core.geometry import FloatArray


def _unit(theta: float) -> FloatArray:
    return np.array([math.cos(theta), math.sin(theta)])


class _SlotLike(Protocol):
    kind: str
    polygon: FloatArray
    entry: FloatArray
    heading: float
    width: float
    length: float

    @property
    def center(self) -> tuple[float, float]: ...


class _LaneLike(Protocol):
    def pose_at(self, station: float) -> FloatArray: ...


class SlotKind:
    """What one kind of slot decides (a strategy; one instance per kind in :data:`KINDS`).

    Attributes
    ----------
    name : str
        The kind's name in scenario files and results.
    parks_along : bool
        A car parks along the aisle (parallel): it is parked by the minimum-slot strokes,
        may stand anywhere in its slot, and leaves towards the lane it came by; otherwise
        it parks across the aisle, centred in its bay, by a shuffle out of it.
    entry_gear : int
        The gear a car enters in (+1 forward, -1 reverse) before its maneuver is planned.
    fixed_angle : float or None
        The angle between the slot's long side and its aisle [rad] when the kind fixes it
        (perpendicular: pi/2, parallel: 0); None when a row gives it (angled).
    every_lane : bool
        Every lane beside the slot serves it, whichever way it runs (perpendicular).
    """

    name: str = ""
    parks_along: bool = False
    entry_gear: int = -1
    fixed_angle: float | None = math.pi / 2
    every_lane: bool = False

    def __repr__(self) -> str:
        return f"SlotKind({self.name!r})"

    # -- placing the slot on its aisle ----------------------------------------------------
    def frontage(self, width: float, length: float, angle: float) -> float:
        """Length of aisle edge the slot's entry takes [m]."""
        return width * math.sin(angle)

    def pitch(self, width: float, length: float, angle: float) -> float:
        """Distance along the aisle from one slot of a row to the next, without gap [m]."""
        return width / math.sin(angle)

    def place(self, origin: FloatArray, u: FloatArray, n: FloatArray, heading: float,
              station: float, width: float, length: float, angle: float, *,
              toward_traffic: bool) -> tuple[FloatArray, FloatArray, float]:
        """The slot's corners, its entry side and the heading of a car parked nose-in, for a
        slot whose entry begins at aisle ``station``: ``origin`` is station 0 on the aisle
        edge, ``u`` the unit along the aisle, ``n`` the unit away from it and ``heading``
        the aisle leg's heading. ``toward_traffic``: the lane next to the slot runs along
        ``u`` (used by kinds parked along the aisle)."""
        d = math.cos(angle) * u + math.sin(angle) * n
        b = origin + station * u  # back entry corner, recessed by width·cos(angle)
        b = b + width * math.cos(angle) * n
        a = b + width * (math.sin(angle) * u - math.cos(angle) * n)  # on the aisle edge
        poly = np.array([a, b, b + length * d, a + length * d])
        return poly, np.array([b, a]), math.atan2(d[1], d[0])

    def entry_sides(self, rear_right: FloatArray, front_right: FloatArray,
                    front_left: FloatArray, rear_left: FloatArray) -> list[FloatArray]:
        """The sides of a slot placed by centre and heading that may be its entry (the one
        nearest an aisle is), from its corners as a car parked nose-in sees them."""
        return [np.array([rear_left, rear_right])]

    def entry_gap(self, entry: FloatArray, aisle: Polygon) -> float:
        """How far the entry side ``entry`` of a slot placed by centre and heading lies from
        the ``aisle``'s ground [m] (lotsim's rule wants it within 0.3 m): its middle."""
        return float(aisle.distance(Point(entry.mean(axis=0))))

    # -- serving lanes ----------------------------------------------------------------------
    def serves(self, slot: _SlotLike, lane_heading: float) -> bool:
        """Whether a car on a lane heading ``lane_heading`` [rad] beside ``slot`` can begin
        its parking maneuver: a slot angled one way is entered in that direction of
        travel."""
        return self.every_lane or float(np.dot(_unit(lane_heading), _unit(slot.heading))) > 1e-9

    def serves_lane(self, slot: _SlotLike, lane: _LaneLike, station: float) -> bool:
        """:meth:`serves`, asked of ``lane`` at ``station`` [m]: its heading there is read
        only where the kind depends on it."""
        return self.every_lane or self.serves(slot, lane.pose_at(station)[2])

    # -- parked cars ------------------------------------------------------------------------
    def taken(self, slot: _SlotLike, width: float, margin: float) -> Polygon:
        """What a maneuver must keep out of because of a car parked in ``slot``: a strip
        ``width`` wide centred across the slot along its whole length (cars park centred),
        grown by ``margin``."""
        c = np.asarray(slot.center)
        u = _unit(slot.heading)
        n = np.array([-u[1], u[0]])
        hl, hw = slot.length / 2, min(width, slot.width) / 2
        strip = Polygon([c - hl * u - hw * n, c + hl * u - hw * n, c + hl * u + hw * n,
                         c - hl * u + hw * n])
        return strip.buffer(margin, join_style="mitre") if margin else strip


class Perpendicular(SlotKind):
    """A bay at right angles to its aisle: served by every lane beside it, backed into."""

    name = "perpendicular"
    every_lane = True


class Angled(SlotKind):
    """A bay at an angle to its aisle: served by the lanes heading its way, driven into
    forward."""

    name = "angled"
    entry_gear = 1
    fixed_angle = None

    def entry_gap(self, entry: FloatArray, aisle: Polygon) -> float:
        """Its nearer end: the entry of a bay at an angle slants away from the aisle, its
        front corner on the aisle's edge and its back corner ``width·cos α`` behind, as in
        an angled row."""
        return float(aisle.distance(LineString(entry)))


class Parallel(SlotKind):
    """A slot along its aisle, its long side the entry."""

    name = "parallel"
    parks_along = True
    fixed_angle = 0.0

    def frontage(self, width: float, length: float, angle: float) -> float:
        return length

    def pitch(self, width: float, length: float, angle: float) -> float:
        return length

    def place(self, origin: FloatArray, u: FloatArray, n: FloatArray, heading: float,
              station: float, width: float, length: float, angle: float, *,
              toward_traffic: bool) -> tuple[FloatArray, FloatArray, float]:
        a = origin + station * u
        poly = np.array([a, a + length * u, a + length * u + width * n, a + width * n])
        return poly, np.array([a, a + length * u]), heading if toward_traffic \
            else heading + math.pi

    def entry_sides(self, rear_right: FloatArray, front_right: FloatArray,
                    front_left: FloatArray, rear_left: FloatArray) -> list[FloatArray]:
        return [np.array([rear_right, front_right]), np.array([rear_left, front_left])]

    def taken(self, slot: _SlotLike, width: float, margin: float) -> Polygon:
        """The whole slot (the car may stand anywhere in it) grown by ``margin`` at both
        ends and the kerb but not past the entry line: a car parking next to it starts with
        its corner on that line (the minimum-slot strategy), and the parked car does not
        reach over it."""
        c = np.asarray(slot.center)
        a, b = slot.entry
        u = (b - a) / np.linalg.norm(b - a)
        n = c - (a + b) / 2
        n = n / np.linalg.norm(n) * (slot.width + margin)
        a, b = a - u * margin, b + u * margin
        return Polygon([a, b, b + n, a + n])


KINDS: dict[str, SlotKind] = {k.name: k for k in (Perpendicular(), Parallel(), Angled())}
"""Every slot kind by name, in the order scenario files list them."""


def kind_of(slot: _SlotLike) -> SlotKind:
    """The kind of ``slot`` (:data:`KINDS`); a KeyError for a kind not registered."""
    return KINDS[slot.kind]
