"""What a CAD program shows of lotsim's DXF export, and how long the export and the drawing
take: the lot of ``scenarios/mixed_lot.yaml`` exported to DXF, read back and drawn by
ezdxf's own drawing add-on (``ezdxf.addons.drawing``, its matplotlib backend), written as
``docs/img/dxf-mixed-lot.png`` (the picture of ``docs/export.md``).

Run with::

    pip install -e '.[dxf,plot]'
    python benchmarks/dxf_picture.py            # or: SCENARIO [PNG]

It prints the entities on each layer, the time the export took (building the lot from the
scenario included) and the time ezdxf took to read and draw the file, each the best of
three. The picture is the same for the same lot (matplotlib's ``Agg`` backend, a fixed
size and resolution, no date in the file).
"""

from __future__ import annotations

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
"""Its resolution: 1200 x 660 pixels."""


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
    scenario = Path(argv[0]) if argv else ROOT / "scenarios" / "mixed_lot.yaml"
    png = Path(argv[1]) if len(argv) > 1 else ROOT / "docs" / "img" / "dxf-mixed-lot.png"
    dxf = Path(tempfile.mkdtemp()) / f"{scenario.stem}.dxf"
    export_s, info = best_of(3, lambda: lotsim.export_dxf(scenario, dxf))
    draw_s, _ = best_of(3, lambda: draw(dxf, png))
    print(f"{scenario}: {info.bays} bays, {info.bytes / 1e3:.0f} kB of DXF")
    for layer, count in info.entities:
        print(f"  {layer:<12} {count:5d} entities")
    print(f"export {export_s:.2f} s, ezdxf reading and drawing it {draw_s:.2f} s "
          f"(best of 3); wrote {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
