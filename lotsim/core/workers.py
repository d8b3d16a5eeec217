"""The one place lotsim forks: ``[fn(item) for item in items]`` on forked worker processes,
the same answers in the same order as in this process (:func:`fork_map`); several such maps
on one set of workers forked once (:class:`ForkPool`); one background process at the
lowest priority (:class:`Background`); and one task done on a forked process while this one
goes on (:class:`Aside`).

The workers are forked from this process as it is when the map starts, so ``fn`` and the
items reach them by reference (nothing but an index goes down a pipe, the answers come back
pickled): ``fn`` may close over a lot, its trees and caches. Needs the ``fork`` start method
(Linux); elsewhere, in a process that :mod:`multiprocessing` started (a worker of the bench,
of Dask, of the caller: its parent already shares the cores out), for fewer than two items
or with ``workers=1``, it works in this process.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
from collections.abc import Callable, Iterable, Sequence

_TASK: tuple = ()  # (task, parent pid) for the forked workers


def _default_workers() -> int:
    """As many workers as the machine has cores; one in a process multiprocessing started
    (a worker of the bench, of Dask, of the caller: its parent already shares the cores
    out)."""
    return (1 if multiprocessing.parent_process() else os.cpu_count()) or 1


def cores() -> int:
    """How many processes :func:`fork_map` and :class:`ForkPool` share work among by
    default: the machine's cores, or one in a process multiprocessing started."""
    return _default_workers()


class ForkPool:
    """Worker processes forked once, from this process as it is when the pool opens, each
    holding ``task`` by reference; :meth:`map` calls one of ``task``'s methods on items.

    Successive maps on one pool share what the workers built in the earlier ones (a lot's
    trees, a planner's problems posed), where a pool a map would work it out again. Only
    the items go down a pipe and the answers come back, pickled. With fewer than two
    ``workers``, or without the ``fork`` start method (Linux), it works in this process.

    Examples
    --------
    >>> class Squares:
    ...     def square(self, x):
    ...         return x * x
    >>> task = Squares()
    >>> with ForkPool(task, workers=2) as pool:
    ...     pool.map(task.square, [1, 2, 3]), pool.map(task.square, [4])
    ([1, 4, 9], [16])
    """

    def __init__(self, task: object, *, workers: int | None = None) -> None:
        self.task = task
        self.count = _default_workers() if workers is None else workers
        self.pool = None
        self._outer: tuple = ()

    def __enter__(self) -> ForkPool:
        global _TASK
        # a pool opened inside a worker's task works in that process; the worker's own
        # task must outlive it, for the items the worker takes next
        self._outer = _TASK
        if self.count >= 2 and "fork" in multiprocessing.get_all_start_methods():
            _TASK = (self.task, os.getpid())
            self.pool = multiprocessing.get_context("fork").Pool(
                self.count, initializer=quiet_worker, initargs=(os.getpid(),))
        return self

    def __exit__(self, *exc: object) -> None:
        global _TASK
        _TASK = self._outer
        if self.pool is not None:  # done, or Ctrl-C here: its workers end
            self.pool.terminate()
            self.pool.join()

    def map(self, method: Callable, items: Sequence, *, chunk: int = 1,
            progress: Callable[[int, int], None] | None = None,
            meanwhile: Callable[[], object] | None = None) -> list:
        """``[method(item) for item in items]`` for a bound method of the pool's task, the
        items handed out ``chunk`` at a time as workers come free; ``progress(done, total)``
        is called as answers come (in order). ``meanwhile()`` is called in this process
        while the workers work (before the map in this process, where it works here)."""
        if getattr(method, "__self__", None) is not self.task:
            raise ValueError("a ForkPool maps methods of its own task")
        if self.pool is None:
            if meanwhile is not None:
                meanwhile()
            return _counted(map(method, items), len(items), progress)
        jobs = [(method.__name__, item) for item in items]
        answers = self.pool.imap(_call, jobs, chunksize=chunk)
        if meanwhile is not None:
            meanwhile()
        return _counted(answers, len(items), progress)


def _call(job: tuple[str, object]) -> object:
    name, item = job
    return getattr(_TASK[0], name)(item)


class _Indexed:
    """``fn`` over ``items`` by index, for :func:`fork_map`: the items reach the workers by
    reference, only their indices go down the pipe."""

    def __init__(self, fn: Callable, items: Sequence) -> None:
        self.fn, self.items = fn, items

    def at(self, k: int) -> object:
        return self.fn(self.items[k])


def fork_map(fn: Callable, items: Sequence, *, workers: int | None = None, chunk: int = 1,
             progress: Callable[[int, int], None] | None = None,
             meanwhile: Callable[[], object] | None = None) -> list:
    """``[fn(item) for item in items]``, on up to ``workers`` forked processes (default: as
    many as the machine has), the items handed out ``chunk`` at a time as workers come free;
    ``progress(done, total)`` is called as answers come (in order); ``meanwhile()`` is
    called in this process while they work (:meth:`ForkPool.map`).

    Examples
    --------
    >>> fork_map(lambda x: x * x, [1, 2, 3], workers=2)
    [1, 4, 9]
    """
    task = _Indexed(fn, items)
    count = min(workers or _default_workers(), len(items))
    with ForkPool(task, workers=count) as pool:
        return pool.map(task.at, range(len(items)), chunk=chunk, progress=progress,
                        meanwhile=meanwhile)


def _counted(answers: Iterable, total: int, progress: Callable[[int, int], None] | None
             ) -> list:
    """``list(answers)``, calling ``progress(done, total)`` as they come."""
    if progress is None:
        return list(answers)
    out = []
    for answer in answers:
        out.append(answer)
        progress(len(out), total)
    return out


def quiet_worker(parent: int) -> None:
    """A forked pool worker's initializer: it leaves Ctrl-C to the process that started it
    (``parent``, which ends it), and ends when that ends, however it ends (Linux:
    ``PR_SET_PDEATHSIG``), instead of working on with nobody to answer."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # not Linux: ended by the pool only
        pass
    if os.getppid() != parent:  # it ended before that was set
        os._exit(0)


class Background:
    """``fn(item)`` for each of ``items``, in order, on one forked process at the lowest
    priority (nice 19): it works when a core would otherwise idle (this process working
    alone between its parallel steps) and yields it to the rest; :meth:`take` returns the
    answers it has finished so far, by index. Nothing is started where :func:`fork_map`
    would work in this process (one core, no ``fork``, a process multiprocessing started):
    :meth:`take` then returns nothing, and the caller works them out itself. An item whose
    ``fn`` raises ends the process quietly: it and the items after it have no answer.

    Examples
    --------
    >>> import time
    >>> with Background(lambda x: x * x, [1, 2, 3]) as bg:
    ...     for _ in range(500):  # (about 5 s at most)
    ...         if not bg.started or len(bg.take()) == 3:
    ...             break
    ...         time.sleep(0.01)
    ...     sorted(bg.take().items()) in ([(0, 1), (1, 4), (2, 9)], [])
    True
    """

    def __init__(self, fn: Callable, items: Sequence):
        self.answers: dict[int, object] = {}
        self._conn = self._proc = None
        if (not items or _default_workers() < 2
                or "fork" not in multiprocessing.get_all_start_methods()):
            return
        ctx = multiprocessing.get_context("fork")
        self._conn, send = ctx.Pipe(duplex=False)
        proc = ctx.Process(target=_background, args=(fn, items, send, os.getpid()),
                           daemon=True)
        try:
            proc.start()
            self._proc = proc
        except OSError:  # no process to be had (a limit): the caller works them all out
            self._conn.close()
            self._conn = None
        send.close()

    @property
    def started(self) -> bool:
        """Whether a process works on the items (until :meth:`close`); when not,
        :meth:`take` has no answers to give."""
        return self._proc is not None

    def take(self) -> dict[int, object]:
        """The answers finished so far (index → answer), without waiting."""
        while self._conn is not None and self._conn.poll():
            try:
                k, answer = self._conn.recv()
            except (EOFError, OSError):  # done, or it failed
                self._conn.close()
                self._conn = None
                break
            self.answers[k] = answer
        return self.answers

    def close(self) -> None:
        """End the process, whatever it is doing."""
        if self._proc is not None:
            self._proc.terminate()
            self._proc.join()
            self._proc = None
        if self._conn is not None:
            self._conn.close()
            self._conn = None

    def __enter__(self) -> Background:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _background(fn: Callable, items: Sequence, conn, parent: int) -> None:
    quiet_worker(parent)
    os.nice(19)
    try:
        for k, item in enumerate(items):
            conn.send((k, fn(item)))
    except Exception:  # noqa: BLE001 - the caller works out what has no answer
        pass
    finally:
        conn.close()


class Aside:
    """``fn()`` on a forked process while this one goes on (writing a cache entry, packing
    what will be written); :meth:`wait` (or leaving the ``with`` block) waits for it to
    end and returns its answer (pickled back), None when it raised: an exception ends it
    quietly. It runs in this process at once where :func:`fork_map` would work in this
    process (one core, no ``fork``, a process multiprocessing started) or no process can
    be had. Ctrl-C is left to this process; the forked one finishes what it is doing.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "note.txt"
    >>> with Aside(lambda: path.write_text("written")):
    ...     pass
    >>> path.read_text()
    'written'
    >>> Aside(lambda: 6 * 7).wait(), Aside(lambda: 1 / 0).wait()
    (42, None)
    """

    def __init__(self, fn: Callable[[], object]):
        self._proc = self._conn = None
        self._answer = None
        if _default_workers() >= 2 and "fork" in multiprocessing.get_all_start_methods():
            ctx = multiprocessing.get_context("fork")
            self._conn, send = ctx.Pipe(duplex=False)
            proc = ctx.Process(target=_aside, args=(fn, send))
            try:
                proc.start()
                self._proc = proc
                send.close()
                return
            except OSError:  # no process to be had (a limit): done here
                send.close()
                self._conn.close()
                self._conn = None
        with contextlib.suppress(Exception):
            self._answer = fn()

    def wait(self) -> object:
        """Wait for it to be done; its answer (None when it raised). Interrupted while it
        waits, it ends the forked process (which would wait for its answer to be read)."""
        if self._proc is not None:
            try:
                self._answer = self._conn.recv()
            except (EOFError, OSError):  # it ended without one
                self._answer = None
            except BaseException:
                self._proc.terminate()
                raise
            finally:
                self._conn.close()
                self._proc.join()
                self._proc = self._conn = None
        return self._answer

    def __enter__(self) -> Aside:
        return self

    def __exit__(self, *exc: object) -> None:
        self.wait()


def _aside(fn: Callable[[], object], conn) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    answer = None
    with contextlib.suppress(Exception):  # ended quietly: no answer
        answer = fn()
    with contextlib.suppress(Exception):
        conn.send(answer)
    conn.close()
