"""Progress where a user waits: on one terminal line of stderr, or, when stderr is not a
terminal (a pipe, a log file, a batch job), a plain line every few seconds once the work
has taken that long; and noting Ctrl-C where a library may swallow it."""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
import time
from collections.abc import Iterator

PIPE_EVERY = 5.0
"""Seconds between the progress lines written where stderr is not a terminal."""


class ProgressBar:
    """``label [#####-----] done/total, ~N s left`` on one terminal line; where stderr is
    not a terminal, ``label: done/total, ~N s left (M s)`` on a line of its own every
    ``every`` seconds from its first news on while the work goes on, and a last line when
    it is done (only for work that took that long: quick work writes nothing there).

    Parameters
    ----------
    label : str
    stream : file, optional
        Where to write (default ``sys.stderr`` as it is when the bar is made).
    every : float, optional
        Seconds between the lines written where the stream is not a terminal (default
        :data:`PIPE_EVERY`).
    """

    def __init__(self, label: str, *, stream=None, every: float | None = None):
        self.label = label
        self.stream = sys.stderr if stream is None else stream
        self.on = self.stream.isatty()
        self.t0 = time.perf_counter()
        self.shown = False
        self.status = f"{label} …"
        self.lines = 0  # written as lines of their own (not a terminal)
        self.every = PIPE_EVERY if every is None else every
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._beats: threading.Thread | None = None
        self._since: tuple[int, float, int] | None = None  # total, when and done at its first news

    def _start(self) -> None:
        """Not a terminal: from the first news on, write the status every ``every``
        seconds."""
        if not self.on and self._beats is None and not self._stop.is_set():
            beats = threading.Thread(target=self._beat_on, daemon=True)
            beats.start()
            self._beats = beats  # once started: an interrupt before leaves none to join

    def __call__(self, done: int, total: int, what: str = "") -> None:
        """``done`` of ``total``; ``what``: the one being done now, to show beside."""
        self._start()
        if total <= 0:
            return
        frac = done / total
        left = self._left(done, total)
        now = f" … {what}" if what else ""
        if not self.on:
            self.status = f"{self.label}: {done}/{total}{left}{now}"
            return
        bar = "#" * int(24 * frac) + "-" * (24 - int(24 * frac))
        print(f"\r{self.label} [{bar}] {done}/{total}{left}{now}   ", end="",
              file=self.stream, flush=True)
        self.shown = True

    def _left(self, done: int, total: int) -> str:
        """``, ~N s left`` at the pace since the first news of this ``total`` (not since the
        bar was made: a step may start well after it, as the maneuvers of a lot do after
        its lanes), or nothing before there is a pace to go by."""
        now = time.perf_counter()
        if self._since is None or self._since[0] != total or done < self._since[2]:
            self._since = (total, now, done)
        _, since, first = self._since
        if not first < done < total:
            return ""
        return f", ~{(now - since) / (done - first) * (total - done):.0f} s left"

    def beat(self) -> None:
        """Write the status as a line of its own, with the time spent so far."""
        with self._lock:
            spent = time.perf_counter() - self.t0
            print(f"{self.status} ({spent:.0f} s)", file=self.stream, flush=True)
            self.lines += 1

    def _beat_on(self) -> None:
        while not self._stop.wait(self.every):
            self.beat()

    def close(self, outcome: str = "done") -> None:
        """Stop; where lines were written, the last says how the work ended (``outcome``:
        ``done``, ``interrupted``, ``stopped``)."""
        self._stop.set()
        if self._beats is not None:
            self._beats.join()
            self._beats = None
            if self.lines:  # it wrote while it ran: say that it is over, and how
                self.status = f"{self.label}: {outcome}"
                self.beat()
        if self.shown:
            print("\r" + " " * 79 + "\r", end="", file=self.stream, flush=True)

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, kind: type[BaseException] | None, *exc: object) -> None:
        self.close(ended(kind))


class Preparing(ProgressBar):
    """A lot being prepared: ``preparing the lot …``, then ``planning maneuvers [###---]
    412/2080``, then ``building the lot graph …``, on one terminal line, or (not a
    terminal) every few seconds while it lasts (a lot from the cache is quick: nothing)."""

    def __init__(self):
        super().__init__("planning maneuvers")
        self.note("preparing the lot …")

    def close(self, outcome: str = "done") -> None:
        self.label = "preparing the lot"
        super().close(outcome)

    def note(self, text: str) -> None:
        if self.on:
            print(f"\r{text:<79}", end="", file=self.stream, flush=True)
            self.shown = True
        else:
            self._start()
            self.status = text

    def __call__(self, done: int, total: int) -> None:
        super().__call__(done, total)
        if done >= total:
            self.note("building the lot graph …")

    def __enter__(self) -> Preparing:
        return self


def ended(kind: type[BaseException] | None) -> str:
    """How a piece of work ended, for its last progress line: ``done``, ``interrupted``
    (Ctrl-C) or ``stopped`` (an error), by the kind of exception that ended it (None:
    none)."""
    if kind is None:
        return "done"
    return "interrupted" if issubclass(kind, KeyboardInterrupt) else "stopped"


@contextlib.contextmanager
def noting_sigint(seen: list[bool]) -> Iterator[None]:
    """Within: Ctrl-C raises KeyboardInterrupt as usual and is also noted in ``seen`` (a
    library may catch the interrupt and raise an error of its own)."""

    def on_sigint(signum, frame):
        seen.append(True)
        raise KeyboardInterrupt

    try:
        old = signal.signal(signal.SIGINT, on_sigint)
    except ValueError:  # not the main thread: leave Ctrl-C alone
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)
