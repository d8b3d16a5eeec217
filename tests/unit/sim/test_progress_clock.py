"""A run's progress with its clock: a callback that takes a third argument is told the
run's time of day and the cars served so far; one that takes two is called as before."""

from __future__ import annotations

import re

import lotsim
from lotsim.sim.limits import takes_three
from lotsim.sim.loop import clock_line


def test_a_callback_of_three_is_told_the_clock_and_the_cars_served():
    said: list[tuple[int, int, str]] = []
    rr = lotsim.run("scenarios/mixed_lot.yaml",
                    progress=lambda done, total, what: said.append((done, total, what)))
    plain: list[tuple[int, int]] = []
    lotsim.run("scenarios/mixed_lot.yaml", progress=lambda done, total: plain.append(
        (done, total)))
    assert [(d, n) for d, n, _ in said] == plain  # the same calls, with the clock beside
    clocks, served = [], []
    for _, _, what in said:
        m = re.fullmatch(r"(\d\d):(\d\d), (\d+) served", what)
        assert m, what
        clocks.append(60 * int(m[1]) + int(m[2]))
        served.append(int(m[3]))
    assert clocks == sorted(clocks) and served == sorted(served)
    # every car of the run parks before it leaves: the last count is all the cars parked
    assert served[-1] == sum(v.parked_at is not None for v in rr.vehicles) > 0
    # the last trip dealt with is the last car's way out, planned when it set off
    assert clocks[-1] == int(max(v.depart_at for v in rr.vehicles) // 60)


def test_the_clock_reads_as_a_day():
    assert clock_line(0.0, 0) == "00:00, 0 served"
    assert clock_line(86_399.0, 7) == "23:59, 7 served"
    assert clock_line(86_400.0, 7) == "day 2 00:00, 7 served"
    assert clock_line(3 * 86_400.0 + 3_600.0 * 13 + 61.0, 9) == "day 4 13:01, 9 served"


def test_which_callbacks_take_the_clock():
    assert takes_three(lambda d, n, w: None) and takes_three(lambda *a: None)
    assert takes_three(lambda d, n, w="": None)
    assert not takes_three(lambda d, n: None) and not takes_three(None)
