"""What became of each lot of an import: written (where) or skipped (why), with its figures."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from lotsim.io.imports.draft import PlotDraft


@dataclass(frozen=True)
class ImportedLot:
    """One lot of the source.

    Attributes
    ----------
    id : str
        The lot's id in the source (``way/123``, ``relation/9``, ``node/5``, or the map's).
    area : float
        Its area [m²] (0 for a lot mapped as a point).
    mapped, inferred : int
        Slots mapped in the source, and slots lotsim laid out along its aisles.
    capacity : int or None
        The source's own count of spaces, where it gives one.
    aisles, gates : int
        Aisles and gates (entrance and exit pairs) of the scenario.
    path : Path or None
        The scenario written, None when skipped.
    reason : str
        Why it was skipped, or a remark on a written lot ("" when there is none).
    projection_error : float
        Bound of the projection's error over the lot [m] (:meth:`TangentPlane.error_over`).
    plot : PlotDraft or None
        For a lot that maps no aisles, when asked for: its plot, for ``lotsim layout``.
    """

    id: str
    area: float
    mapped: int = 0
    inferred: int = 0
    capacity: int | None = None
    aisles: int = 0
    gates: int = 0
    path: Path | None = None
    reason: str = ""
    projection_error: float = 0.0
    plot: PlotDraft | None = field(default=None, compare=False, repr=False)

    @property
    def written(self) -> bool:
        return self.path is not None

    def line(self) -> str:
        """One line for the command's summary."""
        cap = "-" if self.capacity is None else str(self.capacity)
        what = f"written {self.path}" if self.path is not None else "skipped"
        why = f" ({self.reason})" if self.reason else ""
        return (f"{self.id}: {self.area:.0f} m², slots {self.mapped} mapped / "
                f"{self.inferred} inferred, capacity {cap}, {self.aisles} aisles, "
                f"{self.gates} gates: {what}{why}")


@dataclass(frozen=True)
class ImportReport:
    """Every lot found in ``source``, in the source's order of ids."""

    source: Path
    lots: tuple[ImportedLot, ...]

    @property
    def written(self) -> tuple[ImportedLot, ...]:
        return tuple(lot for lot in self.lots if lot.written)

    def text(self) -> str:
        """One line per lot, then a total."""
        lines = [lot.line() for lot in self.lots]
        lines.append(f"{len(self.written)} of {len(self.lots)} lots written")
        return "\n".join(lines)
