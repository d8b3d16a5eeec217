"""The static time to a search's goals, the true-distance heuristic of HCA*: a Reverse
Resumable A* (RRA*, Silver 2005) run backwards from the goals over a
:class:`~lotsim.traffic.searchgraph.SearchGraph`'s edges, each at its static time (its
length at its speed limit, a maneuver's or turnaround's duration), and resumed only as
far as each question needs. A search also sizes its expansion limit by how many nodes its reverse
search closed.
"""

from __future__ import annotations

import heapq
import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from lotsim.traffic.searchgraph import SearchGraph


class ReverseResumable:
    """Reverse Resumable A*: true static time [s] from any node to the goals, computed
    backwards from the goals and resumed only as far as each query needs.

    Slot nodes other than the goals are not passed through, nor the edges ``shut`` (edge
    indices of ``sg``: those a closure blocks while it lasts).
    """

    def __init__(self, sg: SearchGraph, goals: dict[int, float], *,
                 shut: frozenset[int] = frozenset()):
        self.sg = sg
        self.shut = shut
        self.dist: dict[int, float] = {}
        self.best = dict(goals)
        self.heap = [(c, n) for n, c in goals.items()]
        heapq.heapify(self.heap)
        self.goals = set(goals)

    @property
    def closed(self) -> int:
        """How many nodes it has closed so far."""
        return len(self.dist)

    def closed_at(self, node: int) -> int:
        """How many nodes a new RRA* towards the same goals closes to answer ``node`` (one
        that has answered it; its answers do not depend on what it was asked before, only
        how far it has got): ``node``'s place in the order nodes were closed, from 1."""
        d = self.dist.get(node)
        if d is None or d == math.inf:
            return self.closed
        # nodes are closed in the order of dist's keys (unreachable ones asked for come last)
        return next(k for k, n in enumerate(self.dist, 1) if n == node)

    def __call__(self, node: int) -> float:
        """The static time [s] from ``node`` to the nearest goal (``inf``: none reached)."""
        dist = self.dist
        d = dist.get(node)
        if d is not None:
            return d
        heap, best, goals, passable = self.heap, self.best, self.goals, self.sg.passable
        pop, push, inf = heapq.heappop, heapq.heappush, math.inf
        shut, sg = self.shut, self.sg
        while heap:
            d, v = pop(heap)
            if v in dist:
                continue
            dist[v] = d
            if shut:
                into = (sg.back_avoiding(v, shut) if v in passable or v in goals else None)
            else:
                into = passable.get(v)
                if into is None and v in goals:
                    into = sg.back(v)
            if into:
                for u, w in into:
                    nd = d + w
                    if nd < best.get(u, inf) and u not in dist:
                        best[u] = nd
                        push(heap, (nd, u))
            if v == node:
                return d
        dist.setdefault(node, inf)
        return dist[node]
