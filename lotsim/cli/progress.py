"""Progress on one terminal line of stderr (silent when stderr is not a terminal), and
noting Ctrl-C where a library may swallow it."""

from __future__ import annotations

import contextlib
import signal
import sys
import time
from collections.abc import Iterator


class ProgressBar:
    """``label [#####-----] done/total, ~N s left`` on a terminal; silent otherwise."""

    def __init__(self, label: str):
        self.label = label
        self.on = sys.stderr.isatty()
        self.t0 = time.perf_counter()
        self.shown = False

    def __call__(self, done: int, total: int) -> None:
        if not self.on or total <= 0:
            return
        frac = done / total
        bar = "#" * int(24 * frac) + "-" * (24 - int(24 * frac))
        spent = time.perf_counter() - self.t0
        left = f", ~{spent / frac * (1 - frac):.0f} s left" if 0 < frac < 1 else ""
        print(f"\r{self.label} [{bar}] {done}/{total}{left}   ", end="", file=sys.stderr,
              flush=True)
        self.shown = True

    def close(self) -> None:
        if self.shown:
            print("\r" + " " * 79 + "\r", end="", file=sys.stderr, flush=True)


class Preparing(ProgressBar):
    """A lot being prepared, on one terminal line: ``preparing the lot …``, then
    ``planning maneuvers [###---] 412/2080``, then ``building the lot graph …``; silent
    when stderr is not a terminal (and when the lot comes from the cache, quick)."""

    def __init__(self):
        super().__init__("planning maneuvers")
        self.note("preparing the lot …")

    def note(self, text: str) -> None:
        if self.on:
            print(f"\r{text:<79}", end="", file=sys.stderr, flush=True)
            self.shown = True

    def __call__(self, done: int, total: int) -> None:
        super().__call__(done, total)
        if done >= total:
            self.note("building the lot graph …")

    def __enter__(self) -> Preparing:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


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
