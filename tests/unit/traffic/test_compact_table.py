"""A reservation table made compact (the entries dropped and forgotten let go, the live ones
numbered again) answers every query as one that keeps every entry: checked against such a
table over a random stream of reservations, releases and a clock that moves on, and on a
whole run with departures."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import box

import lotsim
from lotsim.io.result import result_dict
from lotsim.sim import loop as loop_module
from lotsim.traffic.reservation import ReservationTable
from lotsim.traffic.swept import Swept


def _moving(rng, t0: float) -> list[tuple[float, float, object]]:
    """A body moving along x in short chunks from ``t0`` [s]."""
    x, y = rng.uniform(0, 60), rng.uniform(0, 30)
    out = []
    for k in range(int(rng.integers(2, 8))):
        out.append((t0 + 0.5 * k, t0 + 0.5 * (k + 1), box(x + k, y, x + k + 4.5, y + 2)))
    return out


def test_a_compact_table_answers_as_one_that_keeps_everything():
    rng = np.random.default_rng(4)
    compact, whole = ReservationTable(compact_from=20), ReservationTable(compact_from=10**12)
    standing = [Swept.of([(0.0, 0.0, box(x, 10, x + 4.5, 12))]) for x in range(0, 60, 7)]
    slots = [box(x, 0, x + 2.4, 5) for x in range(0, 60, 3)]
    now = 0.0
    for step in range(400):
        now += float(rng.uniform(0.0, 1.5))
        for table in (compact, whole):
            table.forget_before(now)
        owner = f"c{step % 37}"
        kind = rng.integers(0, 4)
        for table in (compact, whole):
            r = np.random.default_rng(step)  # the same draw for both
            if kind == 0:
                table.reserve(owner, _moving(r, now + float(r.uniform(0, 5))))
            elif kind == 1:
                table.reserve_standing(owner, slots[int(r.integers(len(slots)))], now,
                                       in_slot=True)
            elif kind == 2:
                table.release(owner, after=now + float(r.uniform(0, 3)))
            else:
                table.reserve_standing(owner, box(*r.uniform(0, 50, 2), 70, 25), now,
                                       now + float(r.uniform(1, 20)))
        q = _moving(rng, now + float(rng.uniform(0, 4)))
        sw = Swept.of(q)
        ignore = f"c{int(rng.integers(37))}"
        assert compact.first_conflict(q, ignore=ignore) == whole.first_conflict(q, ignore=ignore)
        assert (compact.blocked(sw, now, now + 30, ignore=ignore)
                == whole.blocked(sw, now, now + 30, ignore=ignore))
        body = slots[int(rng.integers(len(slots)))]
        later = [a.taken_until(body, ignore=ignore) for a in (compact, whole)]
        assert later[0] == later[1] or max(later) < now  # (forgotten: over before now)
        for st in standing:
            assert (compact.blocked_standing(st, now, now + 20, ignore=ignore)
                    == whole.blocked_standing(st, now, now + 20, ignore=ignore))
    assert compact.compactions >= 5  # it was made compact again and again
    assert compact._store.n < whole._store.n / 3  # and holds what is live
    assert len(compact) == len(whole)
    assert compact.releases == whole.releases


@pytest.fixture
def compacting(monkeypatch):
    made = []

    def table():
        made.append(ReservationTable(compact_from=200))
        return made[-1]

    monkeypatch.setattr(loop_module, "ReservationTable", table)
    return made


def test_a_run_whose_table_is_made_compact_plans_as_before(compacting):
    scenario = "scenarios/mixed_lot.yaml"
    prepared = lotsim.prepare(scenario)
    with_compact = result_dict(lotsim.run(prepared))
    assert compacting and max(t.compactions for t in compacting) > 0
    compacting.clear()
    loop_module.ReservationTable = ReservationTable  # (the fixture undoes it too)
    assert result_dict(lotsim.run(prepared)) == with_compact
    assert not compacting


def test_a_table_is_made_compact_only_when_its_clock_moves_on():
    table = ReservationTable(compact_from=1)
    for k in range(50):
        table.reserve(f"c{k}", [(0.0, 1.0, box(k, 0, k + 1, 1))])
        table.release(f"c{k}")
    assert table.compactions == 0 and table._store.n == 50
    table.forget_before(100.0)
    assert table.compactions == 1 and table._store.n == 0
