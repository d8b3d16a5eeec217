"""What a CAD program shows of lotsim's DXF export, and how long the export and the drawing
take: the lot of ``scenarios/mixed_lot.yaml`` exported to DXF, read back and drawn by
ezdxf's own drawing add-on (``ezdxf.addons.drawing``, its matplotlib backend), written as
``docs/img/dxf-mixed-lot.png`` (a picture of ``docs/export.md``).

Run with::

    pip install -e '.[dxf,plot]'
    python benchmarks/dxf_picture.py            # or: SCENARIO [PNG] [--units m|ft]

``docs/export.md``'s other picture is the storefront lot drawn in feet, its service routes
and bays by use on their layers::

    python benchmarks/dxf_picture.py scenarios/lots/storefront.yaml \
        docs/img/dxf-storefront.png --units ft

It prints the entities on each layer, the time the export took (building the lot from the
scenario included) and the time ezdxf took to read and draw the file, each the best of
three. The picture is the same for the same lot (matplotlib's ``Agg`` backend, a fixed
size and resolution, a fixed seed, no date in the file).
"""

from __future__ import annotations

import argparse
import random
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import lotsim  # noqa: E402

SIZE = (12.0, 6.6)
"""The figure's size [inches]."""
DPI = 100
"""Its resolution [dots per inch]."""
SEED = 0
"""The seed of the jiggle ezdxf gives a hatch pattern (an access aisle's lines)."""


def draw(dxf: Path, png: Path) -> None:
    """Draw ``dxf`` with ezdxf's drawing add-on on a white background into ``png``."""
    import ezdxf
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from ezdxf.addons.drawing import Frontend, RenderContext
    from ezdxf.addons.drawing.config import BackgroundPolicy, Configuration
    from ezdxf.addons.drawing.matplotlib import MatplotlibBackend

    doc = ezdxf.readfile(dxf)
    random.seed(SEED)  # ezdxf moves a hatch pattern's origin by a random hair
    fig = plt.figure(figsize=SIZE)
    ax = fig.add_axes((0, 0, 1, 1))
    config = Configuration(background_policy=BackgroundPolicy.WHITE)
    Frontend(RenderContext(doc), MatplotlibBackend(ax), config=config).draw_layout(
        doc.modelspace())
    ax.margins(0.02)
    fig.savefig(png, dpi=DPI, metadata={"Software": None})
    plt.close(fig)


def best_of(n: int, work) -> tuple[float, object]:
    """The shortest of ``n`` runs of ``work()`` [s], and what it returned."""
    best, out = float("inf"), None
    for _ in range(n):
        start = time.perf_counter()
        out = work()
        best = min(best, time.perf_counter() - start)
    return best, out


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description="draw a scenario's DXF as ezdxf does")
    parser.add_argument("scenario", nargs="?", type=Path,
                        default=ROOT / "scenarios" / "mixed_lot.yaml")
    parser.add_argument("png", nargs="?", type=Path,
                        default=ROOT / "docs" / "img" / "dxf-mixed-lot.png")
    parser.add_argument("--units", choices=("m", "ft"),
                        help="the drawing's units (default: the scenario's)")
    args = parser.parse_args(argv)
    scenario, png = args.scenario, args.png
    dxf = Path(tempfile.mkdtemp()) / f"{scenario.stem}.dxf"
    export_s, info = best_of(3, lambda: lotsim.export_dxf(scenario, dxf, units=args.units))
    draw_s, _ = best_of(3, lambda: draw(dxf, png))
    print(f"{scenario}: {info.bays} bays, {info.bytes / 1e3:.0f} kB of DXF in {info.units}")
    for layer, count in info.entities:
        print(f"  {layer:<12} {count:5d} entities")
    print(f"export {export_s:.2f} s, ezdxf reading and drawing it {draw_s:.2f} s "
          f"(best of 3); wrote {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
