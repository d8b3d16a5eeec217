"""A digest of every candidate ``lotsim layout`` draws for each shipped plot: to check that
a change to the drawing leaves the shipped plots' candidates as they were.

Run: ``python benchmarks/candidate_digest.py [PLOT.yaml ...]`` (default every plot in
``scenarios/plots``) on two trees (``PYTHONPATH=<tree>``) and compare what they print.

For each plot it prints the number of candidates drawn (with the default
:class:`~lotsim.design.settings.LayoutSettings`) and a SHA-256 of their scenario texts
(:func:`lotsim.design.preparing.scenario_text`, in the order they are drawn), then one
line a candidate: its digest, bays and label. Nothing is prepared; the output is the same
on every machine.
"""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

from lotsim.design.plot_yaml import read_plot
from lotsim.design.preparing import scenario_text
from lotsim.design.search import candidates
from lotsim.design.settings import LayoutSettings

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    paths = [Path(p) for p in (sys.argv[1:] if argv is None else argv)] or \
        sorted((ROOT / "scenarios" / "plots").glob("*.yaml"))
    settings = LayoutSettings()
    for path in paths:
        plot = read_plot(path)
        drawn = candidates(plot, settings)
        texts = [scenario_text(plot, c, settings=settings)[0] for c in drawn]
        whole = hashlib.sha256("\0".join(texts).encode()).hexdigest()[:16]
        print(f"{path.stem}: {len(texts)} candidates, {whole}", flush=True)
        for c, text in zip(drawn, texts, strict=True):
            print(f"  {hashlib.sha256(text.encode()).hexdigest()[:16]} {c.bays:4d} {c.label}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
