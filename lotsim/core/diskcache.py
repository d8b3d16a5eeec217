"""An on-disk cache of prepared lots: a second ``validate`` or ``run`` of a lot that has not
changed since the last one loads it instead of planning it again.

An entry is keyed by everything the prepared lot depends on — the lot as written (not
where in which file it was written), the vehicle types, the preparation's settings — and
by the code that prepared it (a hash of lotsim's own source files, so that a changed
lotsim never reads an older lotsim's answers) and the versions of the libraries whose
objects it holds. A loaded entry is the very object that was stored (pickle round-trips
floats exactly), so a run from the cache is byte-identical to one without.

Where: ``$LOTSIM_CACHE_DIR``, else ``$XDG_CACHE_HOME/lotsim``, else ``~/.cache/lotsim``.
``LOTSIM_CACHE_DIR=off`` turns the cache off. The cache is only ever a shortcut: an entry
that cannot be read or written is planned as if there were none, and the oldest entries
are removed once there are more than :data:`MOST_ENTRIES` or :data:`MOST_BYTES`.

Entries are pickles, and loading a pickle runs what it says: the cache loads only what the
user alone could have written. Its folder is made private (``0700``); an entry is loaded
only when it and the folder are owned by the user and neither can be written by anyone
else (:func:`trusted`). Anything else — a cache folder shared with others, an entry
another user left — is planned afresh, not loaded (and, in the user's own folder, replaced
by the user's own entry).

Processes that ask for the same missing entry at once (a test suite on every core, jobs
started together on one machine) make it once: the first holds a lock on it
(:func:`making`, a hidden ``.lock`` file beside the entries) while it plans, the others
wait, then load what it stored.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib.util
import os
import pickle
import stat
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

from lotsim.core.keys import key_of
from lotsim.core.packed import no_cycle_collection

try:
    import fcntl
except ImportError:  # not on POSIX: no locks, two processes may plan one lot at once
    fcntl = None

OFF = ("off", "0", "no", "false", "")
LOADED = "; loaded from the cache: the lot, its types and lotsim are as when planned"
"""What ``lotsim validate`` adds to its maneuver counts when the lot came from the cache."""
MOST_ENTRIES = 64
MOST_BYTES = 1 << 30
"""The cache holds at most this many entries and bytes by default (:func:`store`); the least
recently used go first."""


def cache_dir() -> Path | None:
    """The cache's folder, or None when ``LOTSIM_CACHE_DIR`` turns it off."""
    chosen = os.environ.get("LOTSIM_CACHE_DIR")
    if chosen is not None:
        return None if chosen.strip().lower() in OFF else Path(chosen).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "lotsim"


@functools.cache
def code_version() -> str:
    """A hash of lotsim's source files and of the versions of Python and of the libraries
    whose objects a prepared lot holds."""
    import numpy
    import shapely

    h = hashlib.blake2b(digest_size=16)
    h.update(repr((sys.version, numpy.__version__, shapely.__version__)).encode())
    # networkx's version as its package's first file states it (importing networkx would
    # cost more than a warm validate spends on anything else: a lot loaded from the cache
    # imports it only when its graph is asked for)
    spec = importlib.util.find_spec("networkx")
    h.update(Path(spec.origin).read_bytes() if spec is not None and spec.origin else b"")
    root = PACKAGE_ROOT
    for path in source_files():
        h.update(path.relative_to(root).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()


PACKAGE_ROOT = Path(__file__).resolve().parents[1]
"""The folder of the lotsim package."""


def source_files() -> list[Path]:
    """Every source file of the lotsim package, sorted: what :func:`code_version` hashes."""
    return sorted(PACKAGE_ROOT.rglob("*.py"))


def key(kind: str, made_from: object) -> str:
    """The entry name under ``kind`` of what is made from ``made_from``, an instance of a
    declared input type (:func:`lotsim.core.keys.inputs`), with this lotsim
    (:func:`code_version`)."""
    h = hashlib.blake2b(digest_size=20)
    h.update(code_version().encode())
    h.update(key_of(made_from))
    return f"{kind}-{h.hexdigest()}.pickle"


def trusted(path: Path) -> bool:
    """Whether ``path`` can only have been written by this user: owned by them and not
    writable by group or others (on systems without owners, always)."""
    if not hasattr(os, "getuid"):
        return True
    try:
        st = path.stat()
    except OSError:
        return False
    return st.st_uid == os.getuid() and not st.st_mode & (stat.S_IWGRP | stat.S_IWOTH)


def _make_private(folder: Path) -> None:
    """Make the cache folder (and its missing parents), the folder itself private."""
    if not folder.is_dir():
        folder.mkdir(parents=True, exist_ok=True)
        os.chmod(folder, 0o700)


def load(name: str, folder: Path | None = None) -> object | None:
    """The entry ``name`` (:func:`key`), or None when there is none that can be read, or it
    or its folder could have been written by someone else (:func:`trusted`)."""
    folder = folder if folder is not None else cache_dir()
    if folder is None:
        return None
    path = folder / name
    if not (trusted(folder) and trusted(path)):
        return None
    try:
        with open(path, "rb") as f, no_cycle_collection():
            value = pickle.load(f)
    except OSError:  # none, or none that can be read
        return None
    except Exception:  # a damaged entry (cut short, another format) is a miss
        with contextlib.suppress(OSError):
            path.unlink()
        return None
    with contextlib.suppress(OSError):  # recently used (a read-only cache is still read)
        os.utime(path)
    return value


@contextlib.contextmanager
def making(name: str, folder: Path | None = None) -> Iterator[None]:
    """Held while this process makes the entry ``name``: another process that asks for it
    meanwhile waits here, and should then :func:`load` it before making it itself. Nothing
    is held where there is no cache or the folder cannot be locked (another system, a file
    system without locks): then the two make it both, as without the lock."""
    folder = folder if folder is not None else cache_dir()
    lock = None
    if folder is not None and fcntl is not None:
        try:
            _make_private(folder)
            lock = open(folder / f".{name}.lock", "wb")  # noqa: SIM115 - closed below
            fcntl.flock(lock, fcntl.LOCK_EX)
        except OSError:
            pass
    try:
        yield
    finally:
        if lock is not None:
            lock.close()  # and the lock with it


def store(name: str, value: object, folder: Path | None = None, *,
          most_entries: int = MOST_ENTRIES, most_bytes: int = MOST_BYTES) -> bool:
    """Write ``value`` as the entry ``name`` (whole or not at all); whether it was. Then
    the least recently used entries go, beyond ``most_entries`` entries and ``most_bytes``
    bytes in all."""
    folder = folder if folder is not None else cache_dir()
    if folder is None:
        return False
    tmp = None
    try:
        _make_private(folder)
        if not trusted(folder):  # others could swap the entry: not worth writing
            return False
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".", suffix=".tmp")
        with os.fdopen(fd, "wb") as f:
            pickle.dump(value, f, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(tmp, folder / name)
        tmp = None
        _prune(folder, most_entries, most_bytes)
    except (OSError, pickle.PicklingError, TypeError, AttributeError):
        return False
    finally:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)
    return True


def _prune(folder: Path, most_entries: int, most_bytes: int) -> None:
    """Remove the least recently used entries beyond ``most_entries`` and ``most_bytes``."""
    entries = []
    for path in folder.glob("*.pickle"):
        try:
            st = path.stat()
        except FileNotFoundError:  # removed by another process meanwhile
            continue
        entries.append((st.st_mtime, st.st_size, path))
    entries.sort(reverse=True)
    total = 0
    for k, (_, size, path) in enumerate(entries):
        total += size
        if k >= most_entries or total > most_bytes:
            path.unlink(missing_ok=True)
    # the locks of entries gone, unless held (one removed just as a process opens it only
    # lets a second one make that entry at the same time)
    for lock in folder.glob(".*.pickle.lock"):
        if (folder / lock.name[1:-5]).exists() or fcntl is None:
            continue
        with contextlib.suppress(OSError), open(lock, "rb") as f:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
            lock.unlink()
