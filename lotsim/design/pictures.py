"""Pictures of a layout search (``lotsim layout --pictures``): the winning lot, and a strip
of the best candidates side by side, each headed by its figures (bays, bays per 100 m²,
aisle length, mean time to park, cars parked per hour)."""

from __future__ import annotations

from PIL import Image

from lotsim.design.results import Evaluation, LayoutResult
from lotsim.io.scenario_yaml import parse_scenario
from lotsim.io.yamlnodes import parse_text
from lotsim.render.lot_image import draw_lot
from lotsim.sim.preparation import prepare_graph


def figures(rank: int, e: Evaluation) -> str:
    """A candidate's figures on one line, as the strip heads it."""
    run = (f", park {e.mean_time_to_park:.0f} s, {e.throughput:.0f} cars/h"
           if e.mean_time_to_park is not None and e.throughput is not None else "")
    # the pictures' font has no superscript two
    return (f"#{rank} {e.bays} bays, {e.bays_per_100m2:.2f} per 100 sq m, "
            f"aisles {e.aisle_length:.0f} m{run}")


def lot_picture(e: Evaluation, *, size: tuple[int, int] = (1200, 900),
                title: str | None = None, labels: bool = True, legend: bool = True
                ) -> Image.Image:
    """The lot of candidate ``e`` (its usable bays), drawn as ``lotsim show`` draws a lot."""
    sc = parse_scenario(parse_text(e.yaml, "<layout>"))
    return draw_lot(prepare_graph(sc, maneuvers=False), size=size,
                    title=title or sc.name, labels=labels, legend=legend,
                    parked_vehicle=sc.parked_vehicle)


def candidate_strip(found: LayoutResult, *, most: int = 4,
                    cell: tuple[int, int] = (600, 450)) -> Image.Image:
    """The best ``most`` candidates side by side, best on the left, each headed by its
    figures (:func:`figures`)."""
    good = [e for e in found.ranked if e.ok][:most]
    pictures = [lot_picture(e, size=cell, title=figures(k + 1, e), labels=False,
                            legend=False)
                for k, e in enumerate(good)]
    strip = Image.new("RGB", (cell[0] * len(pictures), cell[1]), "white")
    for k, img in enumerate(pictures):
        strip.paste(img, (k * cell[0], 0))
    return strip
