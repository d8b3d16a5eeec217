"""Memory and time budgets: stop a run that would outgrow the machine, saying so.

A lot's size is bounded when the scenario is read (:data:`lotsim.io.lot_yaml.MAX_SLOTS` and
its neighbours). How much a run needs depends on its traffic and can only be seen while it
plans, so :class:`Watchdog` watches it: a thread samples the process's resident memory and
the clock four times a second and, from the trips (a vehicle's way in, and out if it leaves)
planned so far, projects what the whole run will need. When the memory in use or projected
passes the memory budget, or the time spent or projected passes the time budget, it
interrupts the main thread with :class:`LimitExceeded` — a
:class:`~lotsim.errors.ScenarioError` located at the scenario's traffic, so the CLI prints
one line and exits 2, before anything is written.

The default memory budget is 80 % of the memory available when the run starts; projections
need :data:`WARMUP` trips and two seconds of planning before they count.
"""

from __future__ import annotations

import _thread
import inspect
import os
import re
import signal
import sys
import threading
import time
from dataclasses import dataclass

from lotsim.errors import LimitExceeded, Location

WARMUP = 10
"""Trips (a vehicle's way in, or out) planned before a projection is trusted ..."""
MEMORY_WARMUP = (0.1, 500)
"""The memory is projected only once this share of a run's trips, or at most this many, are
planned (and :data:`WARMUP`): its start-up, where the lot's first cars work out the edge
motions and hulls the later ones reuse, is then behind it."""
POLL = 0.25
"""Seconds between two looks at memory and clock."""
DOC_FACTOR = 2.0
"""A run's peak memory growth (planning, then the result document and its JSON) as a multiple
of the planner's own growth: measured 1.6 with 1000 cars on ``surface364`` and 2.1 to 2.65
on the large lot (``benchmarks/bench_limits.py``); the projection is within 1.35 times of
either."""
GROWTH_POWER = (0.5, 1.0)
"""The planner's memory grows with the trips planned as a power of them (the run keeps every
car's moves, while what the lot's first cars work out is reused): the power fitted to what
the run has shown is held within these bounds."""
_UNITS = {"": 1, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}


def available_memory() -> int | None:
    """Bytes of memory available to a new process now (Linux ``MemAvailable``), or None."""
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def resident_memory() -> int:
    """Bytes of memory this process holds now (its peak where the current is unknown)."""
    try:
        with open("/proc/self/statm", encoding="ascii") as fh:
            return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        import resource

        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        return peak if sys.platform == "darwin" else peak * 1024


def parse_size(text: str) -> int:
    """Bytes from ``500M``, ``4G``, ``1.5g``, ``2048`` (binary units).

    >>> parse_size("4G"), parse_size("512m"), parse_size("1000")
    (4294967296, 536870912, 1000)
    """
    m = re.fullmatch(r"\s*(\d+(?:\.\d+)?)\s*([kmgt]?)i?b?\s*", text.lower())
    if not m:
        raise ValueError(f"expected a size such as 500M or 4G, found {text!r}")
    return int(float(m.group(1)) * _UNITS[m.group(2)])


def human(n: float) -> str:
    """``1.5 GB``, ``300 MB``: a byte count for a message.

    >>> human(1.5 * 2**30), human(3e8), human(2**40 * 49)
    ('1.5 GB', '286 MB', '50176 GB')
    """
    if n >= 2**30:
        return f"{n / 2**30:.1f} GB" if n < 100 * 2**30 else f"{n / 2**30:.0f} GB"
    return f"{n / 2**20:.0f} MB"


def duration(s: float) -> str:
    """``0.3 s``, ``45 s``, ``12 min``, ``3.2 h``.

    >>> duration(0.3), duration(45), duration(720), duration(11520)
    ('0.3 s', '45 s', '12 min', '3.2 h')
    """
    if s < 10:
        return f"{s:.1f} s"
    if s < 120:
        return f"{s:.0f} s"
    return f"{s / 60:.0f} min" if s < 7200 else f"{s / 3600:.1f} h"


@dataclass(frozen=True, slots=True)
class Budget:
    """At most ``memory`` bytes held by the process and ``seconds`` of work; None: no limit.

    ``memory_note`` says where the memory figure came from, for messages.
    """

    memory: int | None = None
    seconds: float | None = None
    memory_note: str = "--memory-limit"

    @classmethod
    def default(cls, *, memory: int | None = None, seconds: float | None = None) -> Budget:
        """``memory`` if given, else 80 % of the memory available now."""
        if memory is not None:
            return cls(memory, seconds)
        free = available_memory()
        if free is None:
            return cls(None, seconds)
        return cls(int(0.8 * free), seconds,
                   memory_note=f"80 % of the {human(free)} available; --memory-limit")


def takes_three(progress) -> bool:
    """Whether a progress callback takes a third positional argument (what is being done,
    as text), besides ``done`` and ``total``."""
    if progress is None:
        return False
    try:
        params = inspect.signature(progress).parameters.values()
    except (TypeError, ValueError):  # (a builtin without a signature: two, as documented)
        return False
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    return len(positional) >= 3 or any(p.kind is p.VAR_POSITIONAL for p in params)


class Watchdog:
    """Watch a run's memory and time against ``budget``; a context manager.

    Pass :meth:`progress` as the run's progress callback (it chains to ``then``). Inside the
    ``with`` block the main thread may be interrupted with :class:`LimitExceeded`, located
    at ``where`` (the scenario's traffic). Outside the main thread, or without a budget, it
    only chains the progress.
    """

    def __init__(self, budget: Budget, where: Location | None, *,
                 then=None) -> None:
        self.budget = budget
        self.where = where
        self.then = then
        self._then_says = takes_three(then)  # it shows what is being done too
        self.done = 0
        self.total = 0
        self.message: str | None = None
        self.first: tuple[float, int, int] | None = None
        self.seen: list[tuple[float, int, int]] = []  # (clock, trips done, bytes held)
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._old = None

    # -- the main thread ----------------------------------------------------------------------
    def __enter__(self) -> Watchdog:
        self.start = time.perf_counter()
        watched = self.budget.memory is not None or self.budget.seconds is not None
        if (watched and hasattr(signal, "SIGUSR1")
                and threading.current_thread() is threading.main_thread()):
            self._old = signal.signal(signal.SIGUSR1, self._raise)
            self._thread = threading.Thread(target=self._watch, name="lotsim-watchdog",
                                            daemon=True)
            self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
            signal.signal(signal.SIGUSR1, self._old)

    def progress(self, done: int, total: int, what: str = "") -> None:
        if self.done == 0 and done > 0:  # the lot is built: projections count from here
            self.first = (time.perf_counter(), resident_memory(), done)
        if done > self.done:
            self.seen.append((time.perf_counter(), done, resident_memory()))
        self.done, self.total = done, total
        if self._then_says:
            self.then(done, total, what)
        elif self.then is not None:
            self.then(done, total)

    def _raise(self, signum, frame) -> None:
        if self.message is not None:
            raise LimitExceeded(self.where, self.message)

    # -- the watching thread ------------------------------------------------------------------
    def _watch(self) -> None:
        while not self._stop.wait(POLL):
            problem = self.problem(time.perf_counter() - self.start, resident_memory())
            if problem is not None:
                self.message = problem
                _thread.interrupt_main(signal.SIGUSR1)
                return

    def problem(self, elapsed: float, rss: int) -> str | None:
        """What is over budget after ``elapsed`` seconds holding ``rss`` bytes, or None."""
        b = self.budget
        done, total = self.done, self.total
        so_far = (f"after planning {done} of {total} trips in {duration(elapsed)}"
                  if total else f"after {duration(elapsed)}")
        tail = "; nothing was written. Plan fewer vehicles or raise the limit"
        if b.memory is not None and rss > b.memory:
            return (f"stopped {so_far}: it holds {human(rss)} of memory, over the budget of "
                    f"{human(b.memory)} ({b.memory_note}){tail}")
        if b.seconds is not None and elapsed > b.seconds:
            return (f"stopped {so_far}: over the time limit of {duration(b.seconds)} "
                    f"(--time-limit){tail}")
        need = self.projection(elapsed, rss)
        if need is None:
            return None
        if b.seconds is not None and need[0] > b.seconds:
            return (f"stopped {so_far}: at this pace the run needs about {duration(need[0])}, "
                    f"over the time limit of {duration(b.seconds)} (--time-limit){tail}")
        if b.memory is not None and need[1] is not None and need[1] > b.memory:
            return (f"stopped {so_far}: at this pace the run needs about {human(need[1])} of "
                    f"memory, over the budget of {human(b.memory)} ({b.memory_note}){tail}")
        return None

    def projection(self, elapsed: float, rss: int) -> tuple[float, float | None] | None:
        """Seconds and peak bytes the whole run will take: the time from the pace of the
        latter half of the trips planned so far; the memory from the planner's growth since
        the lot was built, fitted as a power of the trips (:data:`GROWTH_POWER`) over the
        latter three quarters of them, times :data:`DOC_FACTOR` (None until its start-up is
        over, :data:`MEMORY_WARMUP`). None before :data:`WARMUP` trips and two seconds, or
        once all are done."""
        done, total = self.done, self.total
        if self.first is None or done >= total:
            return None
        t1, rss1, done1 = self.first
        now = self.start + elapsed
        if done - done1 < WARMUP or now - t1 < 2.0 or not self.seen:
            return None
        seen = self.seen
        half = next(x for x in seen if x[1] >= (done1 + done) / 2)
        if half[1] < done and now > half[0]:
            each = (now - half[0]) / (done - half[1])
        else:
            each = (now - t1) / (done - done1)
        share, most = MEMORY_WARMUP
        if done - done1 < max(WARMUP, min(share * total, most)):
            return elapsed + each * (total - done), None
        planned = rss1 + _growth(seen, rss1, done1, done, total, rss)
        return elapsed + each * (total - done), rss1 + DOC_FACTOR * (planned - rss1)


def _growth(seen: list[tuple[float, int, int]], rss1: int, done1: int, done: int,
            total: int, rss: int) -> float:
    """The planner's growth in bytes since the lot was built (``rss1`` bytes, ``done1``
    trips) once ``total`` trips are planned, from the growth ``seen`` (clock, trips, bytes)
    over the latter three quarters of the trips planned since, fitted as ``a · n ** c``
    for ``n`` trips (``c`` within :data:`GROWTH_POWER`; least squares in logs), and at
    least what it holds now (``rss``)."""
    import math

    pts = [(math.log(d - done1), math.log(r - rss1)) for _, d, r in seen
           if d - done1 >= (done - done1) / 4 and r > rss1 and d > done1]
    now = max(rss - rss1, 0)
    total -= done1
    if len(pts) < 3:
        return now * total / max(done - done1, 1)
    n = len(pts)
    mx = sum(x for x, _ in pts) / n
    my = sum(y for _, y in pts) / n
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    c = sum((x - mx) * (y - my) for x, y in pts) / sxx if sxx > 0 else 1.0
    c = min(max(c, GROWTH_POWER[0]), GROWTH_POWER[1])
    # through the points' centre, with the power held
    a = math.exp(my - c * mx)
    return max(a * total ** c, now)
