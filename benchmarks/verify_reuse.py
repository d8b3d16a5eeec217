"""Does every store lotsim recalls from give what the work would give afresh? The reuse
check (``LOTSIM_VERIFY_REUSE=1``, :class:`lotsim.core.reusecheck.ReuseCheck`) over the
shipped lots.

Run: ``python benchmarks/verify_reuse.py [--quick] [SCENARIO ...]``

Each lot of ``benchmarks/fingerprint.py``'s list (default: every scenario in
``scenarios/`` and ``scenarios/lots/``; ``--quick``: the small ones of ``scenarios/``
alone, seconds in all; or those named) is prepared in a cache folder of the run's own with
its stores kept (every lot, however small), then prepared again — loaded from the cache,
and compared with the lot prepared from scratch. After ``scenarios/lots/surface364.yaml``
(when it is among them) comes an edit of it, one row a bay shorter, which recalls the
roadmap's pieces and the maneuver answers the edit did not touch and compares each with
the work done afresh. For each preparation it prints, per store, the pieces recalled,
those verified, and the mismatches (each mismatch is printed too, and the exit status is 1
when there is any). The output holds counts only, no times, so it is the same on any
machine.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
QUICK = ("quickstart.yaml", "two_rows.yaml", "example.yaml", "street.yaml", "mixed_lot.yaml")
"""The lots of ``--quick``: small ones, prepared in seconds."""
EDITED = "surface364.yaml"
EDIT = ("count: 24, slot_width: 2.65, slot_length: 5.4, start: 70, id_prefix: A1NE-",
        "count: 23, slot_width: 2.65, slot_length: 5.4, start: 70, id_prefix: A1NE-")
"""The edit of :data:`EDITED`: its first aisle's north-eastern row one bay shorter."""


def lots(argv: list[str]) -> list[Path]:
    """The scenarios to check (as ``benchmarks/fingerprint.py`` lists them)."""
    named = [Path(a) for a in argv if not a.startswith("--")]
    if named:
        return named
    if "--quick" in argv:
        return [ROOT / "scenarios" / name for name in QUICK]
    return sorted([*ROOT.glob("scenarios/*.yaml"), *ROOT.glob("scenarios/lots/*.yaml")])


def checked(label: str, text: str) -> int:
    """Prepare the scenario ``text`` with a reuse check that counts and keeps every
    mismatch; print its counts; how many mismatches it found."""
    from lotsim.core.reusecheck import ReuseCheck
    from lotsim.io.scenario_yaml import load_scenario
    from lotsim.sim.preparation import prepare_lot

    check = ReuseCheck(strict=False)
    prepare_lot(load_scenario(text), remember_from=1, check=check)
    print(f"{label}:", flush=True)
    for store, (recalled, verified, mismatches) in sorted(check.counts.items()):
        print(f"  {store:24s} {recalled:6d} recalled {verified:6d} verified "
              f"{mismatches:3d} mismatches", flush=True)
    if not check.counts:
        print("  nothing recalled", flush=True)
    for error in check.mismatches:
        print(f"  MISMATCH {error}", flush=True)
    return len(check.mismatches)


def main(argv: list[str]) -> int:
    import os

    bad = 0
    with tempfile.TemporaryDirectory() as cache:
        os.environ["LOTSIM_CACHE_DIR"] = cache  # the run's own: what it recalls, it stored
        for path in lots(argv):
            text = path.read_text()
            name = path.name
            bad += checked(f"{name} (first)", text)
            bad += checked(f"{name} (again, from the cache)", text)
            if name == EDITED:
                edited = text.replace(*EDIT)
                assert edited != text, "the edit no longer matches the lot's rows"
                bad += checked(f"{name} (one row edited)", edited)
    print(f"{bad} mismatches in all")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
