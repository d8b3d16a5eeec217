"""fork_map: the answers of a plain loop, in the items' order, from forked workers."""

import os
import time

from lotsim.forkmap import fork_map


def test_answers_in_order_whatever_finishes_first():
    # the first items take longest, so the workers finish them last
    items = [0.2, 0.15, 0.1, 0.05, 0.0, 0.0]

    def slow_square(x: float) -> tuple[float, int]:
        time.sleep(x)
        return x * x, os.getpid()

    got = fork_map(slow_square, items, workers=2)
    assert [a for a, _ in got] == [x * x for x in items]
    assert len({pid for _, pid in got}) == 2  # both workers answered
    assert os.getpid() not in {pid for _, pid in got}


def test_one_worker_or_one_item_works_here():
    assert fork_map(lambda x: (x, os.getpid()), [1], workers=2) == [(1, os.getpid())]
    assert fork_map(lambda x: (x, os.getpid()), [1, 2], workers=1) == [(1, os.getpid()),
                                                                       (2, os.getpid())]


def test_closures_reach_the_workers_unpickled():
    lookup = {"a": object()}  # not picklable by value into a lambda's closure
    assert fork_map(lambda k: k in lookup, ["a", "b"], workers=2) == [True, False]
