"""A parking maneuver: a chain of :class:`~lotsim.core.geometry.Segment` pieces — straights
and arcs no tighter than the car's minimum turning radius, each driven forward or in
reverse — from a pose on a lane (on its centreline, heading its way) to the parked pose
inside the slot. Leaving is the same path driven backwards in time
(:meth:`Maneuver.reversed`): each piece flips gear, so a car that reversed in drives out
forward."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from lotsim.core.geometry import FloatArray, Pose, Segment
from lotsim.core.lazy import LoadedBy
from lotsim.vehicles.model import VehicleType
from lotsim.vehicles.motion import Motion, Piece, runs, timed_path

if TYPE_CHECKING:
    from lotsim.maneuvers.problem import LocalFrame


def path_length(segments: Sequence[Segment]) -> float:
    """Length [m] of a path of ``segments``."""
    return float(sum(s.length for s in segments))


def direction_changes(segments: Sequence[Segment]) -> int:
    """Direction changes (cusps) along a path of ``segments``."""
    g = [s.gear for s in segments]
    return sum(1 for a, b in zip(g[:-1], g[1:], strict=True) if a != b)


def shortest_run(segments: Sequence[Segment]) -> float:
    """The shortest stretch [m] a car drives between two stops on a path of ``segments``:
    the runs the timing drives without stopping (:func:`~lotsim.vehicles.motion.runs`)."""
    return min(sum(p.segment.length for p in run)
               for run in runs([Piece(s, math.inf) for s in segments]))


@dataclass(frozen=True)
class Maneuver:
    """A path from a lane pose into a slot (or, reversed, out of it).

    Attributes
    ----------
    segments : tuple of Segment
        In driving order; consecutive pieces meet exactly.
    vehicle : str
        Name of the vehicle type it was planned for.
    slot : str
    lane : str
        The lane it starts on (parking) or ends on (leaving).
    station : float
        Station on ``lane`` where it starts or ends [m].
    leaving : bool
        False for the way in, True for the way out.
    """

    segments: tuple[Segment, ...] = LoadedBy("load_segments")  # type: ignore[assignment]
    vehicle: str
    slot: str
    lane: str
    station: float
    leaving: bool = False

    @property
    def start(self) -> Pose:
        d = self.__dict__
        if "segments" in d:
            return self.segments[0].start
        if "_at" in d:
            frame, local = d["_at"]
            return frame.segments_to_world(local[:1])[0].start
        return d["_of"].end  # where its first piece, backwards, starts

    @property
    def end(self) -> Pose:
        d = self.__dict__
        if "segments" not in d and "_at" in d:
            frame, local = d["_at"]
            return frame.segments_to_world(local[-1:])[0].end
        return self.segments[-1].end

    @property
    def length(self) -> float:
        """Path length [m]."""
        of = self._unbuilt()
        if of is not None:
            return path_length(of._pieces()[0][::-1])  # each piece as long either way
        return path_length(self._pieces()[0])

    @property
    def gears(self) -> tuple[int, ...]:
        """Each piece's gear: +1 forward, -1 reverse (as :meth:`shapes`' distances give it)."""
        of = self._unbuilt()
        if of is not None:
            return tuple(1 if -s.distance >= 0 else -1 for s in reversed(of._pieces()[0]))
        return tuple(1 if s.distance >= 0 else -1 for s in self._pieces()[0])

    @property
    def changes(self) -> int:
        """Direction changes (cusps) within the maneuver."""
        return direction_changes(self.segments)

    @property
    def cusps(self) -> tuple[Pose, ...]:
        """Poses where the car stops and changes direction."""
        return tuple(a.end for a, b in zip(self.segments[:-1], self.segments[1:], strict=True)
                     if a.gear != b.gear)

    def strokes(self) -> list[tuple[int, float]]:
        """Maximal runs of one gear as ``(gear, length)``: the car stops between them."""
        out: list[tuple[int, float]] = []
        for s in self.segments:
            if out and out[-1][0] == s.gear:
                out[-1] = (s.gear, out[-1][1] + s.length)
            else:
                out.append((s.gear, s.length))
        return out

    def sample(self, step: float = 0.05) -> tuple[FloatArray, np.ndarray]:
        """Poses (N, 3) at most ``step`` apart along the path, and the gear of each (N,).

        Cusps appear once, with the gear of the stroke they end.
        """
        parts, gears = [], []
        for k, seg in enumerate(self.segments):
            p = seg.sample(step)
            if k:
                p = p[1:]
            parts.append(p)
            gears.append(np.full(len(p), seg.gear))
        return np.concatenate(parts), np.concatenate(gears)

    def reversed(self) -> Maneuver:
        """The same path driven backwards in time: each piece with the other gear.

        Its pieces are worked out when first asked for: a lot's ways out are built for
        every slot, and most are only timed and measured (:meth:`shapes`, :attr:`length`),
        which read this maneuver's pieces."""
        return _unmade(vehicle=self.vehicle, slot=self.slot, lane=self.lane,
                       station=self.station, leaving=not self.leaving, _of=self)

    @classmethod
    def placed(cls, frame: LocalFrame, local: Sequence[Segment], vehicle: str, slot: str,
               lane: str, station: float) -> Maneuver:
        """The way in whose pieces are ``local`` in ``frame``'s coordinates, put in the world
        (``frame.segments_to_world``) when first asked for: a lot's maneuvers are planned
        in their slots' frames, and most are only timed and measured before they are
        driven. Its start, end, length, gears and shapes read before then are those of the
        pieces in the world, to the bit."""
        return _unmade(vehicle=vehicle, slot=slot, lane=lane, station=station, leaving=False,
                       _at=(frame, tuple(local)))

    def _unbuilt(self) -> Maneuver | None:
        """The maneuver this one reverses while its own pieces are not built yet, else
        None: what its start, length and shapes are read from, to the bit as from its
        pieces."""
        return None if "segments" in self.__dict__ else self.__dict__.get("_of")

    def _pieces(self) -> tuple[Sequence[Segment], float]:
        """Its pieces as built, or while a placed one's are not, in its frame, with the sign
        their curvatures and sharpnesses take in the world (-1 in a mirrored frame): the
        same distances, and the same curvatures but for that sign, to the bit."""
        d = self.__dict__
        if "segments" not in d and "_at" in d:
            frame, local = d["_at"]
            return local, -1.0 if frame.mirror else 1.0
        return self.segments, 1.0

    def load_segments(self) -> None:
        """Work out the pieces of a placed maneuver (:meth:`placed`) or a reversed one
        (:meth:`reversed`) if they are not yet: what reading :attr:`segments` does first."""
        d = self.__dict__
        if "segments" in d or ("_at" not in d and "_of" not in d):
            return
        if "_at" in d:
            frame, local = d["_at"]
            segs = frame.segments_to_world(local)
        else:
            segs = tuple(s.backwards() for s in reversed(d["_of"].segments))
        object.__setattr__(self, "segments", segs)

    def shapes(self) -> tuple[tuple[float, float, float], ...]:
        """Each piece's (distance, curvature, sharpness): the path's shape, not where it
        lies (what its timing depends on)."""
        of = self._unbuilt()
        if of is not None:
            pieces, sy = of._pieces()
            return tuple((-s.distance, sy * s.end_curvature, -(sy * s.sharpness))
                         for s in reversed(pieces))
        pieces, sy = self._pieces()
        return tuple((s.distance, sy * s.curvature, sy * s.sharpness) for s in pieces)

    def motion(self, vehicle: VehicleType, speed_limit: float = math.inf) -> Motion:
        """The maneuver timed from rest, wheels straight, to rest, wheels straight
        (:func:`~lotsim.vehicles.motion.timed_path`): the car stops at every cusp and wherever
        the curvature changes, and turns its wheels there standing."""
        return timed_path([Piece(s, speed_limit) for s in self.segments], vehicle)

    def duration(self, vehicle: VehicleType, speed_limit: float = math.inf) -> float:
        """Time to drive it (:meth:`motion`) [s]: jerk-limited rest-to-rest runs within the
        vehicle's limits and ``speed_limit`` [m/s], and the steering between them."""
        return self.motion(vehicle, speed_limit).duration


    def shortest_run(self) -> float:
        """The shortest stretch [m] a car drives between two stops on it: the runs the timing
        drives without stopping (:func:`~lotsim.vehicles.motion.runs`)."""
        return shortest_run(self.segments)


def _unmade(**fields) -> Maneuver:
    """A maneuver of ``fields`` whose pieces are worked out on first use
    (:meth:`Maneuver.placed`, :meth:`Maneuver.reversed`)."""
    out = object.__new__(Maneuver)
    for name, value in fields.items():
        object.__setattr__(out, name, value)
    return out
