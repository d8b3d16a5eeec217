"""Keys of remembered work: lotsim's one way of naming a piece of work by what it reads.

Every store that recalls earlier work instead of doing it again (the maneuver answers, the
roadmap's pieces, the prepared lots on disk) names each piece by the key of a **declared
input type**: a frozen dataclass made with :func:`inputs`, whose fields are everything the
work reads, built where the work is asked for. :func:`key_of` hashes every field of it,
exactly (floats to the last bit and the sign of zero, arrays by dtype, shape and bytes,
geometries by their WKB, nested dataclasses field by field but those left out of their
equality (``compare=False``: where a thing was read, a memo), the type's own name first), and
refuses a value it cannot encode exactly rather than hashing its ``repr`` (which cuts
numpy's long arrays and shapely's long WKT short). So a key holds all its type declares;
that the type declares all the work reads is what the reuse check
(:mod:`lotsim.core.reusecheck`) tries, by doing recalled work again.

A field that is a set of things (obstacles, whose order an edit elsewhere in a lot
changes) is given as :func:`unordered` of them: each thing's encoding, sorted.

Examples
--------
>>> @inputs
... class Sum:
...     terms: tuple
>>> key_of(Sum((1.0, 2.0))) == key_of(Sum((1.0, 2.0)))
True
>>> key_of(Sum((0.0,))) == key_of(Sum((-0.0,)))
False
>>> key_of(Sum(([1.0],)))
Traceback (most recent call last):
...
TypeError: Sum.terms[0]: a list cannot be part of a key (give a tuple)
"""

from __future__ import annotations

import dataclasses
import enum
import hashlib
import struct
from collections.abc import Iterable
from typing import Any, TypeVar

import numpy as np
from shapely.geometry.base import BaseGeometry
from shapely.io import to_wkb

T = TypeVar("T")

DIGEST_SIZE = 20
"""Bytes of a key (BLAKE2b)."""
_DECLARED = "__key_inputs__"


def inputs(cls: type[T]) -> type[T]:
    """``cls`` as a declared input type: a frozen, slotted dataclass whose instances
    :func:`key_of` keys. Its fields are what the work it names reads."""
    made = dataclasses.dataclass(frozen=True, slots=True)(cls)
    setattr(made, _DECLARED, True)
    return made


def key_of(value: Any) -> bytes:
    """The key of ``value``, an instance of a type made with :func:`inputs`: a BLAKE2b
    digest of its type's name and every field, exactly (see the module's docstring).

    Raises
    ------
    TypeError
        ``value`` is not of a declared input type, or a field holds what cannot be
        encoded exactly (a list, a set, an object that is not a dataclass), named by its
        path.
    """
    if not getattr(type(value), _DECLARED, False):
        raise TypeError(f"{type(value).__name__} is not a declared input type "
                        "(make it with lotsim.core.keys.inputs)")
    out: list[bytes] = []
    _encode(value, out, (type(value).__name__,))
    return hashlib.blake2b(b"".join(out), digest_size=DIGEST_SIZE).digest()


def unordered(items: Iterable[Any]) -> tuple[bytes, ...]:
    """``items`` as a set (repeats kept): each one's encoding, sorted, for a field whose
    order the work does not read."""
    encoded = []
    for k, item in enumerate(items):
        out: list[bytes] = []
        _encode(item, out, (("item",), k))
        encoded.append(b"".join(out))
    return tuple(sorted(encoded))


def _float(x: float) -> bytes:
    return b"n" if x != x else b"f" + _DOUBLE(x)  # (every NaN alike: no sum reads its payload)


def _int(i: int) -> bytes:
    text = str(i).encode()
    return b"i%d:" % len(text) + text


def _str(text: str) -> bytes:
    raw = text.encode()
    return b"s%d:" % len(raw) + raw


_DOUBLE = struct.Struct("<d").pack
_PLAIN = {float: _float, int: _int, str: _str, bytes: lambda b: b"b%d:" % len(b) + b,
          bool: lambda b: b"T" if b else b"F", type(None): lambda _: b"N"}
"""The encoding of a value of each plain type, by its exact type (the quick way)."""


def _encode(value: Any, out: list[bytes], where: tuple) -> None:
    """Append the encoding of ``value`` to ``out``: a tag, a length where the size varies,
    and the content. ``where``: the path to it (a chain of (parent, step) pairs), for
    errors."""
    plain = _PLAIN.get(type(value))
    if plain is not None:
        out.append(plain(value))
    elif isinstance(value, tuple):
        out.append(b"(%d:" % len(value))
        for k, item in enumerate(value):
            plain = _PLAIN.get(type(item))
            if plain is not None:
                out.append(plain(item))
            else:
                _encode(item, out, (where, k))
    elif isinstance(value, bool | np.bool_):
        out.append(b"T" if value else b"F")
    elif isinstance(value, int | np.integer) and not isinstance(value, enum.Enum):
        out.append(_int(int(value)))
    elif isinstance(value, float | np.floating):
        out.append(_float(float(value)))
    elif isinstance(value, str) and not isinstance(value, enum.Enum):
        out.append(_str(value))
    elif isinstance(value, bytes):
        out.append(b"b%d:" % len(value) + value)
    elif isinstance(value, enum.Enum):
        out.append(b"e")
        _encode(type(value).__qualname__, out, where)
        _encode(value.value, out, where)
    elif isinstance(value, frozenset):
        out.append(b"{")
        _encode(unordered(value), out, where)
    elif isinstance(value, np.ndarray):
        if value.dtype == object:
            out.append(b"(%d:" % value.size)
            for k, item in enumerate(value.ravel().tolist()):
                _encode(item, out, (where, k))
            return
        data = np.ascontiguousarray(value)
        head = f"{data.dtype.str}{data.shape}".encode()
        out.append(b"a%d:" % len(head) + head + b"%d:" % data.nbytes + data.tobytes())
    elif isinstance(value, BaseGeometry):
        wkb = to_wkb(value)
        out.append(b"g%d:" % len(wkb) + wkb)
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        out.append(b"D")
        out.append(_str(f"{type(value).__module__}.{type(value).__qualname__}"))
        for f in dataclasses.fields(value):
            if f.compare:  # (a field left out of equality, such as where it was read, is
                # not part of what the value is)
                item = getattr(value, f.name)
                plain = _PLAIN.get(type(item))
                if plain is not None:
                    out.append(plain(item))
                else:
                    _encode(item, out, (where, f.name))
    else:
        kind = type(value).__name__
        hint = " (give a tuple)" if isinstance(value, list) else (
            " (give a frozenset or unordered())" if isinstance(value, set) else (
                " (give a tuple of its items)" if isinstance(value, dict) else ""))
        raise TypeError(f"{_path(where)}: a {kind} cannot be part of a key{hint}")


def _path(where: tuple) -> str:
    """``where`` (:func:`_encode`) as it is written: ``Work.items[0].size``."""
    steps = []
    while len(where) == 2:
        where, step = where
        steps.append(f"[{step}]" if isinstance(step, int) else f".{step}")
    return where[0] + "".join(reversed(steps))
