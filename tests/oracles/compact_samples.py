"""A second reader of a result's compact samples (docs/result.md): each column's whole
numbers summed up as many times as its ``encoding`` says, in plain Python, then divided
by ten to its decimals."""

from __future__ import annotations

import itertools


def decoded(doc: dict) -> dict:
    """``doc`` (a compact result as the standard library's ``json`` reads it) with every
    vehicle's samples as the plain form writes them."""
    vehicles = []
    for v in doc["vehicles"]:
        cols = dict(v["samples"])
        enc = cols.pop("encoding")
        for key, k in enc["decimals"].items():
            n = cols[key]
            for _ in range(enc["differences"]):
                n = list(itertools.accumulate(n))
            cols[key] = [m / 10 ** k for m in n] if k else n
        vehicles.append(v | {"samples": cols})
    return doc | {"vehicles": vehicles}
