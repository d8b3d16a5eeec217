"""lotsim in a notebook: a run, a prepared lot and a validation report show themselves.

In Jupyter (or any IPython shell), ``import lotsim`` registers display formatters
(:func:`register`; ``%load_ext lotsim.api.notebook`` does the same by hand):

* a :class:`~lotsim.sim.results.RunResult` shows what became of its cars and its timing
  figures as a table, and its replay (``lotsim render --html``) inline, where the replay is
  small enough to embed (:data:`MOST_INLINE`);
* a :class:`~lotsim.sim.preparation.PreparedLot` shows the lot's picture with its graph;
* a :class:`~lotsim.sim.validation.ValidationReport` shows its summary, the free slots each
  vehicle type can use as a table, and its warnings;
* preparing a lot and running its traffic show their progress in the cell
  (:func:`progress_for`), when no ``progress`` is given.

The formatters draw only when the notebook asks for them; nothing is registered outside
IPython.
"""

from __future__ import annotations

import html
import io
import os
import tempfile
from pathlib import Path

MOST_INLINE = 8_000_000
"""Largest replay [bytes] embedded in a notebook cell; a bigger one is written with
``lotsim.render_html`` and opened in a browser."""


def _table(rows: list[tuple[str, str]], head: tuple[str, str]) -> str:
    cells = "".join(f"<tr><td>{html.escape(a)}</td><td style='text-align:right'>"
                    f"{html.escape(b)}</td></tr>" for a, b in rows)
    return (f"<table><thead><tr><th>{html.escape(head[0])}</th><th>{html.escape(head[1])}"
            f"</th></tr></thead><tbody>{cells}</tbody></table>")


def run_html(result) -> str:
    """A run as HTML: its name and settings, what became of its cars and its figures, and
    its replay in a frame when it is at most :data:`MOST_INLINE` bytes."""
    from lotsim.api.drawing import render_html

    m = result.metrics()
    rows = [(k, f"{int(m[k])}") for k in ("vehicles", "served", "parked", "departed",
                                         "waiting", "rejected")]
    rows += [("mean time to park", f"{m['mean_time_to_park']:.1f} s"),
             ("max time to park", f"{m['max_time_to_park']:.1f} s"),
             ("total waiting", f"{m['total_waiting']:.1f} s"),
             ("makespan", f"{m['makespan']:.1f} s"),
             ("planning", f"{m['planning_time']:.2f} s")]
    out = (f"<b>{html.escape(result.scenario.name)}</b>: planner "
           f"{html.escape(result.settings.planner)}, seed {result.seed}"
           + _table(rows, ("", "")))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "replay.html"
        info = render_html(result, path)
        if info.bytes <= MOST_INLINE:
            page = path.read_text(encoding="utf-8")
            out += (f"<iframe srcdoc=\"{html.escape(page, quote=True)}\" "
                    f"style='width:100%;height:640px;border:0'></iframe>")
        else:
            out += (f"<p>The replay is {info.bytes / 1e6:.0f} MB, too big to show here: "
                    f"write it with <code>lotsim.render_html(result, 'replay.html')</code> "
                    f"and open it in a browser.</p>")
    return out


def lot_png(prepared) -> bytes:
    """A prepared lot's picture with its graph, as PNG bytes."""
    from lotsim.api.drawing import render_lot

    buf = io.BytesIO()
    render_lot(prepared, size=(900, 600), graph=True).save(buf, format="PNG")
    return buf.getvalue()


def report_html(report) -> str:
    """A validation report as HTML: the summary, and per vehicle type the free slots it
    can use."""
    free = len(report.prepared.lot.free_slots)
    rows = [(name, f"{len(ids)} of {free}") for name, ids in report.usable().items()]
    return (f"<pre>{html.escape(report.summary())}</pre>"
            + _table(rows, ("vehicle type", "usable free slots")))


class _Line:
    """Plain text for a notebook cell, shown as it is (a ``str`` shows its quotes)."""

    def __init__(self, text: str):
        self.text = text

    def __repr__(self) -> str:
        return self.text


class NotebookProgress:
    """``progress(done, total)`` as one line in the notebook cell that updates in place
    (``label 412/2080, ~8 s left``), at most ten times a second. The line appears with the
    first news of work still to do (a lot from the cache shows nothing) and goes when the
    work is done: the cell keeps its answer, not the progress that led to it."""

    def __init__(self, label: str, display=None):
        import time

        if display is None:
            from IPython.display import display
        self.label, self._clock, self._t0 = label, time.perf_counter, time.perf_counter()
        self._display, self._handle = display, None
        self._last = -1.0

    def _text(self, done: int, total: int) -> str:
        if total <= 0:
            return f"{self.label} …"
        spent = self._clock() - self._t0
        left = (f", ~{spent / done * (total - done):.0f} s left" if 0 < done < total
                else "")
        return f"{self.label} {done}/{total}{left}"

    def __call__(self, done: int, total: int) -> None:
        if done >= total:  # over: the line goes
            if self._handle is not None:
                self._handle.update({}, raw=True)
                self._handle = None
            return
        now = self._clock()
        if now - self._last < 0.1:
            return
        self._last = now
        if self._handle is None:
            self._handle = self._display(_Line(self._text(done, total)), display_id=True)
        else:
            self._handle.update(_Line(self._text(done, total)))


def progress_for(label: str):
    """A progress callback for long work started from a notebook cell
    (:class:`NotebookProgress`), or None outside a notebook."""
    import sys

    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None else None
    if shell is None or not hasattr(shell, "kernel"):  # a terminal shows its own bars
        return None
    return NotebookProgress(label)


def register(shell) -> bool:
    """Register the formatters with an IPython ``shell``; whether it could."""
    formatters = getattr(getattr(shell, "display_formatter", None), "formatters", None)
    if not formatters:
        return False
    formatters["text/html"].for_type_by_name("lotsim.sim.results", "RunResult", run_html)
    formatters["text/html"].for_type_by_name("lotsim.sim.validation", "ValidationReport",
                                            report_html)
    formatters["image/png"].for_type_by_name("lotsim.sim.preparation", "PreparedLot",
                                            lot_png)
    return True


def load_ipython_extension(shell) -> None:  # %load_ext lotsim.api.notebook
    register(shell)


def register_if_interactive() -> bool:
    """Register with the running IPython shell, if there is one (``import lotsim`` does
    this); whether it did. ``LOTSIM_NO_NOTEBOOK=1`` turns it off."""
    import sys

    if "IPython" not in sys.modules or os.environ.get("LOTSIM_NO_NOTEBOOK") == "1":
        return False
    try:
        shell = sys.modules["IPython"].get_ipython()
    except AttributeError:
        return False
    return shell is not None and register(shell)
