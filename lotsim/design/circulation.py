"""How traffic can circulate in a drawn candidate, judged from its aisles' centre lines
alone, before any maneuver is planned (:func:`circulation`).

A car turns from one aisle into another where their centre lines meet (a *junction*: an L
corner, a T, a crossing). A turn at the tightest radius ``R`` of the plot's most cumbersome
vehicle type, from one lane into another, takes about ``R`` plus half the aisle's width of
each aisle's length to begin and to straighten out (:func:`turn_reach`). So a car that has
turned in at one junction of an aisle can turn out at another only where the two are
far enough apart along the aisle, or are the aisle's two ends (:data:`SPACING`); closer,
the turns overlap (a gate's T in the middle of a ring's 13 m leg cannot be turned at from
either corner). At a dead end a car turns round (a multi-point turn), so every junction
of an aisle with a dead end leads to every other.

From each gate's mouth the junctions it leads to are followed; a candidate's *served* bays
are those along an aisle some gate leads to. This is a bound drawn roughly, not a verdict:
the maneuver planner and reachability (:mod:`lotsim.design.preparing`) decide which bays are
usable; the bound decides only which candidates are worth preparing first.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from shapely.geometry import LineString
from shapely.ops import nearest_points

from lotsim.design.drawn import Candidate, DrawnAisle
from lotsim.design.plot import PlotSpec

MEET = 1e-3
"""Two centre lines closer than this meet [m]."""
SAME_JUNCTION = 0.5
"""Junctions closer than this along an aisle are one (a crossing, two branches off one
point of a spine) [m]."""
SPACING = 1.6
"""Two junctions of an aisle lead to each other where they are at least this many
:func:`turn_reach` apart along it, or are its two ends (a leg between two corners: a car
swings through both corners' area, so a ring's 13 m legs are driven corner to corner).
lotsim's junction turns at the valet car's radius straighten out 6 to 9.5 m past a corner
and begin 4.4 to 8.5 m before a T, so a T 6.45 m from the corners of a 13 m leg (0.76 of
its 8.47 m) cannot be turned at from either and T junctions a 17 m module pitch (2.0)
apart can; the factor sits between, erring towards the candidate."""


@dataclass(frozen=True, slots=True)
class Circulation:
    """What :func:`circulation` judged of a candidate.

    Attributes
    ----------
    served : int
        Bays along an aisle some gate leads to (at most the bays drawn).
    dead_end_length : float
        The length of aisle a car has to come back along after a dead end: for each aisle
        end that meets no other aisle (and is no gate's mouth), the distance from it to the
        aisle's nearest junction or mouth [m].
    junctions : int
        Junctions of the candidate.
    """

    served: int
    dead_end_length: float
    junctions: int


def turn_reach(plot: PlotSpec) -> float:
    """How much of an aisle's length a turn into or out of it takes [m]: the tightest
    turning radius of the plot's least manoeuvrable vehicle type plus half the
    circulation aisle's width.

    Examples
    --------
    >>> from lotsim.design.plot_yaml import read_plot
    >>> plot = read_plot("boundary: [[0, 0], [40, 0], [40, 30], [0, 30]]\\n"
    ...                  "gates: [{id: in, at: [20, 0]}]\\n")
    >>> round(turn_reach(plot), 2)  # the valet car's 4.97 m and half a 7 m aisle
    8.47
    """
    radius = max(v.min_turning_radius for v in plot.vehicle_types)
    return radius + plot.circulation_width / 2


def _station(a: DrawnAisle, p: np.ndarray) -> float:
    start, end = np.asarray(a.start, dtype=float), np.asarray(a.end, dtype=float)
    u = end - start
    return float(np.dot(p - start, u) / np.hypot(*u))


def circulation(plot: PlotSpec, cand: Candidate) -> Circulation:
    """Judge ``cand``'s circulation from its aisles (the module's description).

    Examples
    --------
    >>> from lotsim.design.plot_yaml import read_plot
    >>> from lotsim.design.candidates import draw_spine
    >>> plot = read_plot("boundary: [[0, 0], [24, 0], [24, 30], [0, 30]]\\n"
    ...                  "gates: [{id: in, at: [12, 0]}]\\n")
    >>> c = circulation(plot, draw_spine(plot, 0, 0.0, False))
    >>> c.served, round(c.dead_end_length)  # every bay served; the spine a 29 m dead end
    (16, 29)
    """
    aisles = cand.aisles
    lines = [LineString([a.start, a.end]) for a in aisles]
    # nodes: junctions (shared by the aisles that meet there) and gate mouths
    nodes: list[list[tuple[int, float]]] = []
    on_aisle: list[list[tuple[float, int]]] = [[] for _ in aisles]

    def node_at(i: int, s: float) -> int | None:
        for s0, k in on_aisle[i]:
            if abs(s0 - s) < SAME_JUNCTION:
                return k
        return None

    for i in range(len(aisles)):
        for j in range(i + 1, len(aisles)):
            if lines[i].distance(lines[j]) >= MEET:
                continue
            meet = lines[i].intersection(lines[j])
            if not meet.is_empty and meet.geom_type == "Point":
                pi = pj = np.asarray(meet.coords[0])
            else:  # touching short of crossing (to the last bit of a slanted leg), or along
                pi, pj = (np.asarray(q.coords[0]) for q in nearest_points(lines[i], lines[j]))
            si, sj = _station(aisles[i], pi), _station(aisles[j], pj)
            k = node_at(i, si)
            k = node_at(j, sj) if k is None else k
            if k is None:
                k = len(nodes)
                nodes.append([])
            for a, s in ((i, si), (j, sj)):
                if node_at(a, s) is None:
                    on_aisle[a].append((s, k))
                    nodes[k].append((a, s))
    junctions = len(nodes)
    index = {a.id: i for i, a in enumerate(aisles)}
    mouths = []
    for g in cand.gates:  # where the gate opens onto its aisle (a gate aisle's mouth)
        i = index[g.aisle]
        s = 0.0 if aisles[i].role == "gate" else _station(aisles[i], np.asarray(g.entrance[:2]))
        k = len(nodes)
        nodes.append([(i, s)])
        on_aisle[i].append((s, k))
        mouths.append(k)

    reach = turn_reach(plot)
    links: list[set[int]] = [set() for _ in nodes]
    dead = 0.0
    for i, a in enumerate(aisles):
        length = float(math.dist(a.start, a.end))
        points = sorted(on_aisle[i])
        ends = [s for s in (0.0, length) if all(abs(s - s0) >= SAME_JUNCTION
                                                for s0, _ in points)]
        for s in ends:
            dead += min((abs(s - s0) for s0, _ in points), default=length)
        for (s1, k1), (s2, k2) in ((p, q) for p in points for q in points if p < q):
            corners = abs(s1) < SAME_JUNCTION and abs(s2 - length) < SAME_JUNCTION
            if ends or corners or abs(s2 - s1) >= SPACING * reach or k1 in mouths or \
                    k2 in mouths:
                links[k1].add(k2)
                links[k2].add(k1)
    seen = set(mouths)
    todo = list(mouths)
    while todo:
        k = todo.pop()
        for m in links[k] - seen:
            seen.add(m)
            todo.append(m)
    served_aisles = {aisles[i].id for k in seen for i, _ in nodes[k]}
    served = sum(r.count for r in cand.rows if r.aisle in served_aisles)
    return Circulation(served, dead, junctions)


__all__ = ["Circulation", "circulation", "turn_reach"]
