"""Parts of an object kept pickled until first used: a prepared lot loaded from the cache
holds its drivable graph and its maneuver planner's answers as bytes, so a command that
only reads its summary (``lotsim validate``) does not unpickle them."""

from __future__ import annotations

import contextlib
import gc
import pickle
from collections.abc import Iterator


@contextlib.contextmanager
def no_cycle_collection() -> Iterator[None]:
    """The cycle collector held off while the block runs. Unpickling makes some 10^5 small
    objects and no garbage (a large lot's maneuvers alone are 30 000 path pieces): the
    collector's passes over them while they are made would take about as long as making
    them."""
    collecting = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if collecting:
            gc.enable()


def pack(value: object) -> bytes:
    """``value`` pickled, for :func:`unpack` when it is first needed."""
    return pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL)


def unpack(blob: bytes) -> object:
    """What :func:`pack` made of ``blob``'s value (only ever bytes lotsim itself packed,
    inside an object it stored or sent: the on-disk cache loads only the user's own
    entries)."""
    with no_cycle_collection():
        return pickle.loads(blob)
