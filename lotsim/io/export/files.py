"""How every export puts its files into its folder: all or nothing.

An export writes several files that only make sense together (a scenario and its solution,
a network and the routes on it). :func:`staged_folder` gives the writer a temporary folder
beside the target; when the writer is done, :func:`replace_folder` moves each file in by a
rename, so a reader of the target sees each file whole or not at all, and a writer that
fails leaves the target as it was.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


def replace_folder(tmp: Path, target: Path) -> None:
    """Move the finished files of ``tmp`` into ``target`` (each by a rename), then remove
    ``tmp``: a reader sees each file whole or not at all."""
    target.mkdir(parents=True, exist_ok=True)
    for p in tmp.iterdir():
        os.replace(p, target / p.name)
    tmp.rmdir()


@contextmanager
def staged_folder(target: Path) -> Iterator[Path]:
    """A temporary folder beside ``target`` (made with its parents if need be) to write
    the export's files into: on leaving the block they are moved into ``target``
    (:func:`replace_folder`); on an error the temporary folder is removed and ``target``
    keeps what it had.

    >>> import tempfile
    >>> root = Path(tempfile.mkdtemp())
    >>> with staged_folder(root / "out") as tmp:
    ...     _ = (tmp / "a.txt").write_text("a")
    >>> sorted(p.name for p in (root / "out").iterdir()), sorted(p.name for p in root.iterdir())
    (['a.txt'], ['out'])
    """
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    try:
        yield tmp
        replace_folder(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
