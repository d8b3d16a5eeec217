"""Write a file so that a reader never sees half of it (:func:`atomic_write`), and a set
of files so that a reader finds all of them or none (:class:`OutputSet`)."""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO

from lotsim.errors import OutputError

STAGE_PREFIX = ".lotsim-"
"""How an :class:`OutputSet`'s staging folder is named (a hidden folder, removed when the
set is moved into place or given up)."""


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, mode: str = "wb",
                 encoding: str | None = None) -> Iterator[IO]:
    """Open a temporary file beside ``path`` for writing; when the block ends without an
    error, make it readable by all (0644) and rename it over ``path``. On any error, or an
    interrupt, the temporary file is removed and ``path`` is left as it was.

    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic_write(d / "a.txt", "w") as fh:
    ...     _ = fh.write("hello")
    >>> (d / "a.txt").read_text(), sorted(p.name for p in d.iterdir())
    ('hello', ['a.txt'])
    """
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, mode, encoding=encoding) as fh:
            yield fh
        os.chmod(tmp, 0o644)  # mkstemp makes it private; an output is not
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


class OutputSet:
    """The files and folders one piece of work writes, as one set: each is checked before
    the work starts, written to a staging folder beside it, and moved into place with the
    others only when all are done (:meth:`commit`).

    Checking an output makes its folder (with its parents) if need be and makes the
    hidden staging folder in it, so a folder that cannot be made or written is told at
    once, as an :class:`~lotsim.errors.OutputError` naming the output as it was given.
    Left without a commit (an error, an interrupt), the set leaves nothing: no staged file,
    no staging folder, no folder made for it.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> root = pathlib.Path(tempfile.mkdtemp())
    >>> with OutputSet() as outputs:
    ...     a = outputs.file(root / "out" / "a.txt")
    ...     b = outputs.file(root / "out" / "b.txt")
    ...     _ = a.write_text("a"), b.write_text("b")
    ...     sorted(p.name for p in (root / "out").iterdir() if not p.name.startswith("."))
    ...     outputs.commit()
    []
    >>> sorted(p.name for p in (root / "out").iterdir())
    ['a.txt', 'b.txt']
    >>> OutputSet().file(root / "out" / "a.txt" / "c.txt", name="-o a.txt/c.txt")
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    lotsim.errors.OutputError: -o a.txt/c.txt: '.../out/a.txt' is a file, not a folder
    """

    def __init__(self) -> None:
        self._stages: dict[Path, Path] = {}  # target folder (absolute) → its staging folder
        self._made: list[Path] = []  # folders made for the set, outermost first
        self._files: set[Path] = set()
        self._removed: list[Path] = []
        self.committed = False

    def file(self, path: str | os.PathLike, *, name: str | None = None) -> Path:
        """Check that the file ``path`` can be written; where to write it instead (in the
        staging folder of its folder, under its own name). ``name``: the output as the
        user gave it, for errors (default ``path``)."""
        target = Path(path)
        shown = os.fspath(path) if name is None else name
        if target.is_dir():
            raise OutputError(shown, f"'{os.fspath(path)}' is a folder, not a file")
        key = Path(os.path.abspath(target))
        if key in self._files:
            raise OutputError(shown, "named twice among the files to write")
        staged = self._stage(target.parent, shown) / target.name
        self._files.add(key)
        return staged

    def folder(self, path: str | os.PathLike, *, name: str | None = None) -> Path:
        """Check that files can be written into the folder ``path`` (made if need be);
        the staging folder to write them into instead: at :meth:`commit` its files (and
        folders) are moved into ``path``, beside what ``path`` already holds."""
        target = Path(path)
        shown = os.fspath(path) if name is None else name
        if target.exists() and not target.is_dir():
            raise OutputError(shown, f"'{os.fspath(path)}' is a file, not a folder")
        return self._stage(target, shown)

    def remove(self, path: str | os.PathLike) -> None:
        """At :meth:`commit`, remove the file ``path`` if it is there (one an earlier run
        wrote, which this set replaces with nothing)."""
        self._removed.append(Path(path))

    def _stage(self, folder: Path, shown: str) -> Path:
        key = Path(os.path.abspath(folder))
        if key in self._stages:
            return self._stages[key]
        self._make(folder, shown)
        try:
            stage = Path(tempfile.mkdtemp(prefix=STAGE_PREFIX, dir=key))
        except OSError as exc:
            raise OutputError(shown, f"cannot write in the folder '{folder}' "
                                     f"({_why(exc)})") from None
        self._stages[key] = stage
        return stage

    def _make(self, folder: Path, shown: str) -> None:
        """Make ``folder`` and its missing parents, noting each one made."""
        missing = []
        p = folder
        while not (p.exists() or p.is_symlink()) and p != p.parent:
            missing.append(p)
            p = p.parent
        if p.exists() and not p.is_dir():
            raise OutputError(shown, f"'{p}' is a file, not a folder")
        for m in reversed(missing):
            try:
                m.mkdir()
            except OSError as exc:
                raise OutputError(shown, f"cannot make the folder '{m}' ({_why(exc)})") from None
            self._made.append(Path(os.path.abspath(m)))

    def commit(self) -> None:
        """Move every staged file into place (each by a rename, so a reader sees it whole)
        and remove the staging folders and the files given to :meth:`remove`."""
        for p in self._removed:
            p.unlink(missing_ok=True)
        for folder, stage in self._stages.items():
            _move_into(stage, folder)
            stage.rmdir()
        self._stages.clear()
        self.committed = True

    def discard(self) -> None:
        """Give the set up: remove what was staged and the folders made for it."""
        for stage in self._stages.values():
            shutil.rmtree(stage, ignore_errors=True)
        self._stages.clear()
        for m in reversed(self._made):
            with contextlib.suppress(OSError):  # not empty: something else wrote there
                m.rmdir()
        self._made.clear()

    def __enter__(self) -> OutputSet:
        return self

    def __exit__(self, *exc: object) -> None:
        if not self.committed:
            self.discard()


def _move_into(source: Path, target: Path) -> None:
    """Move what ``source`` holds into the folder ``target``, merging into a folder that
    is already there."""
    target.mkdir(exist_ok=True)
    for p in source.iterdir():
        there = target / p.name
        if p.is_dir() and not p.is_symlink() and there.is_dir():
            _move_into(p, there)
            p.rmdir()
        else:
            os.replace(p, there)


def _why(exc: OSError) -> str:
    return exc.strerror or str(exc)
