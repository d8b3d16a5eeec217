"""fork_map and ForkPool: the answers of a plain loop, in the items' order, from forked workers."""

import os
import time

import pytest

from lotsim.core.workers import ForkPool, fork_map

pytestmark = pytest.mark.cores  # lotsim's workers on the machine's cores


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


def test_progress_counts_the_answers_as_they_come_in_chunks_or_here():
    for workers in (1, 2):
        seen: list[tuple[int, int]] = []
        got = fork_map(lambda x: x + 1, list(range(10)), workers=workers, chunk=3,
                       progress=lambda done, total, seen=seen: seen.append((done, total)))
        assert got == list(range(1, 11))
        assert seen == [(k, 10) for k in range(1, 11)]


def _taken(bg, n: int, seconds: float = 20.0) -> dict:
    """``bg.take()`` once it holds ``n`` answers (or after ``seconds``)."""
    end = time.monotonic() + seconds
    while len(bg.take()) < n and time.monotonic() < end:
        time.sleep(0.01)
    return bg.take()


def test_a_background_works_on_another_process_at_the_lowest_priority():
    from lotsim.core.workers import Background

    with Background(lambda x: (x * x, os.getpid(), os.nice(0)), [3, 1, 2]) as bg:
        got = _taken(bg, 3)
    assert {k: a for k, (a, _, _) in got.items()} == {0: 9, 1: 1, 2: 4}
    assert {pid for _, pid, _ in got.values()} - {os.getpid()}  # not this process
    assert {nice for _, _, nice in got.values()} == {19}


def test_a_background_stops_quietly_at_an_item_that_fails(capfd):
    from lotsim.core.workers import Background

    with Background(lambda x: 1 / x, [1, 0, 2]) as bg:
        bg._proc.join(20)
        got = bg.take()
    assert got == {0: 1.0}  # the item that failed and those after it: no answer
    assert "Traceback" not in capfd.readouterr().err


def test_a_background_started_by_a_worker_starts_nothing():
    from lotsim.core.workers import Background

    def inside(_):
        with Background(lambda x: x, [1, 2]) as bg:
            time.sleep(0.3)
            return bg.take(), bg._proc is None

    assert fork_map(inside, [0, 1], workers=2) == [({}, True), ({}, True)]


class _Notes:
    """A task whose workers remember what they were given."""

    def __init__(self) -> None:
        self.notes: list[int] = []

    def note(self, x: int) -> int:
        self.notes.append(x)
        return x * x

    def count(self, _: int) -> int:
        return len(self.notes)

    def pid(self, _: int) -> int:
        return os.getpid()


def test_a_fork_pool_maps_on_workers_forked_once_that_keep_what_earlier_maps_built():
    task = _Notes()
    with ForkPool(task, workers=2) as pool:
        assert pool.map(task.note, range(8)) == [x * x for x in range(8)]
        counts = pool.map(task.count, range(8))
        pids = set(pool.map(task.pid, range(8)))
    assert task.notes == []  # the notes were taken on the workers
    assert sum(counts) > 0  # ... which the second map found there: not new workers
    assert os.getpid() not in pids
    with ForkPool(task, workers=1) as pool:  # one worker: this process
        assert pool.map(task.note, [3]) == [9] and task.notes == [3]
    with pytest.raises(ValueError), ForkPool(task, workers=2) as pool:
        pool.map(_Notes().note, [1])  # another task's method


def test_a_worker_whose_task_maps_too_takes_its_next_item():
    # each item's own map works in the worker's process; the worker must then still know
    # its task for the next item it takes (three items on two workers: one takes two)
    def inner(x: int) -> int:
        return sum(fork_map(lambda y: y * y, [x, x + 1]))

    assert fork_map(inner, [1, 2, 3, 4], workers=2) == [5, 13, 25, 41]


def test_aside_works_on_another_process_while_this_one_goes_on(tmp_path, monkeypatch):
    from lotsim.core.workers import Aside

    out = tmp_path / "pid"
    gate = tmp_path / "go"

    def write() -> None:  # waits for this process to have gone on past the start
        for _ in range(500):
            if gate.exists():
                break
            time.sleep(0.01)
        out.write_text(str(os.getpid()))

    with Aside(write):
        assert not out.exists()  # it has not waited for it
        gate.write_text("")
    assert int(out.read_text()) != os.getpid()  # done by then, elsewhere
    # where a process cannot be had, or would share one core: at once, here
    monkeypatch.setattr(os, "cpu_count", lambda: 1)
    with Aside(lambda: out.write_text(str(os.getpid()))):
        assert int(out.read_text()) == os.getpid()


def test_aside_an_error_ends_it_quietly_and_ctrl_c_is_left_here(tmp_path):
    import signal

    from lotsim.core.workers import Aside

    def fail() -> None:
        raise ValueError("nobody waits for this")

    Aside(fail).wait()  # nothing raised here
    seen = tmp_path / "seen"

    def interrupted() -> None:
        os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C, as the terminal sends it to both
        seen.write_text("went on")

    Aside(interrupted).wait()
    assert seen.read_text() == "went on"


def test_meanwhile_runs_here_while_the_workers_work(tmp_path):
    # the workers wait for what ``meanwhile`` does in this process: it must come between
    # handing the items out and collecting the answers (or before a map done here)
    gate = tmp_path / "gate"

    def waits(x: int) -> tuple[int, bool]:
        for _ in range(300):
            if gate.exists():
                return x, True
            time.sleep(0.01)
        return x, False

    for workers in (2, 1):
        gate.unlink(missing_ok=True)
        got = fork_map(waits, [1, 2, 3], workers=workers, meanwhile=lambda: gate.write_text(""))
        assert got == [(1, True), (2, True), (3, True)]


def test_aside_left_by_an_error_or_interrupted_while_it_waits_does_not_hang(tmp_path):
    # its answer is larger than a pipe holds, so the forked process waits for it to be read:
    # leaving the block by an error reads it; Ctrl-C while waiting for it ends the process
    import signal
    import threading

    from conftest import time_limit
    from lotsim.core.workers import Aside

    big = b"x" * (1 << 22)
    with time_limit(20), pytest.raises(ValueError), Aside(lambda: big):
        raise ValueError("the block failed before it waited")
    slow = Aside(lambda: (time.sleep(5), big)[1])
    # Ctrl-C reaches this process's main thread while it waits (sent to the thread itself:
    # one sent to the process may be taken by another of its threads); Python's own handler
    # for it, which a process started in the background of a shell does not have (it
    # inherits Ctrl-C ignored)
    handler = signal.signal(signal.SIGINT, signal.default_int_handler)
    threading.Timer(0.3, signal.pthread_kill,
                    (threading.main_thread().ident, signal.SIGINT)).start()
    started = time.perf_counter()
    try:
        with time_limit(20), pytest.raises(KeyboardInterrupt):
            slow.wait()
    finally:
        signal.signal(signal.SIGINT, handler)
    assert time.perf_counter() - started < 3  # not the 5 s it would take
    assert slow.wait() is None  # ended: nothing left to wait for
