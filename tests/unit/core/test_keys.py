"""Keys of declared input types: every field reaches the key, exactly; what cannot be encoded
exactly is refused; a set's order does not matter; keys are the same in every process."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest
import shapely

from lotsim.core.keys import inputs, key_of, unordered


@dataclasses.dataclass(frozen=True)
class Part:
    size: float
    where: str = dataclasses.field(default="file.yaml:3:4", compare=False)


@inputs
class Work:
    name: str
    count: int
    ratio: float
    flag: bool
    blob: bytes
    items: tuple
    points: np.ndarray
    shape: shapely.Polygon
    part: Part
    maybe: float | None
    names: frozenset


@inputs
class Other:
    name: str
    count: int
    ratio: float
    flag: bool
    blob: bytes
    items: tuple
    points: np.ndarray
    shape: shapely.Polygon
    part: Part
    maybe: float | None
    names: frozenset


def work(**changed) -> Work:
    fields = dict(name="a", count=3, ratio=0.25, flag=False, blob=b"xy", items=(1, "b", 2.0),
                  points=np.array([[0.0, 1.0], [2.0, 3.0]]),
                  shape=shapely.box(0.0, 0.0, 2.0, 5.0), part=Part(1.5), maybe=None,
                  names=frozenset({"p", "q"}))
    fields.update(changed)
    return Work(**fields)


# each field changed in the smallest way its kind allows
CHANGES = {
    "name": "b", "count": 4, "ratio": math.nextafter(0.25, 1.0), "flag": True, "blob": b"xz",
    "items": (1, "b", 2.0, None), "points": np.array([[0.0, 1.0], [2.0, 3.0000000000000004]]),
    "shape": shapely.box(0.0, 0.0, 2.0, 5.000000000000001), "part": Part(1.25), "maybe": 0.0,
    "names": frozenset({"p"}),
}


def test_equal_inputs_have_equal_keys():
    assert key_of(work()) == key_of(work())
    assert len(key_of(work())) == 20


@pytest.mark.parametrize("field", sorted(CHANGES))
def test_every_field_reaches_the_key(field):
    assert {f.name for f in dataclasses.fields(Work)} == set(CHANGES)
    assert key_of(work(**{field: CHANGES[field]})) != key_of(work())


def test_a_field_left_out_of_equality_is_not_part_of_the_key():
    assert key_of(work(part=Part(1.5, where="other.yaml:9:1"))) == key_of(work())


def test_the_type_is_part_of_the_key():
    w = work()
    assert key_of(Other(**{f.name: getattr(w, f.name) for f in dataclasses.fields(w)})) \
        != key_of(w)


@pytest.mark.parametrize("a, b", [
    (0.0, -0.0),                                  # the sign of zero
    (1, 1.0), (1, True), (0, None), ("1", 1),     # kinds told apart
    (("ab", "c"), ("a", "bc")),                   # where one item ends
    ((1, (2,)), ((1,), 2)),                       # nesting
    (b"", ""),
    (np.zeros(2), np.zeros(2, dtype=np.int64)),   # the same bytes, another dtype
    (np.zeros((2, 3)), np.zeros((3, 2))),         # the same bytes, another shape
    (shapely.box(0, 0, 1, 1), shapely.box(0, 0, 1, 1).exterior),
])
def test_values_that_differ_have_different_keys(a, b):
    assert key_of(work(items=(a,))) != key_of(work(items=(b,)))


def test_values_that_are_the_same_have_the_same_key():
    assert key_of(work(items=(np.float64(0.5), np.int64(2)))) == key_of(work(items=(0.5, 2)))
    assert key_of(work(maybe=math.nan)) == key_of(work(maybe=-math.nan))
    # a column of an array is read in its order, whatever its memory layout
    a = np.arange(6.0).reshape(2, 3)
    assert key_of(work(points=a.T)) == key_of(work(points=np.ascontiguousarray(a.T)))


def test_a_set_does_not_depend_on_its_order_but_counts_repeats():
    shapes = [shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 1), shapely.Point(4, 4)]
    assert unordered(shapes) == unordered(shapes[::-1])
    assert unordered(shapes) != unordered(shapes + shapes[:1])
    assert key_of(work(items=(unordered(shapes),))) == \
        key_of(work(items=(unordered(shapes[::-1]),)))


@pytest.mark.parametrize("value, said", [
    ([1.0], "Work.items[0]: a list cannot be part of a key (give a tuple)"),
    ({1.0}, "Work.items[0]: a set cannot be part of a key (give a frozenset or unordered())"),
    ({"a": 1}, "Work.items[0]: a dict cannot be part of a key (give a tuple of its items)"),
    (object(), "Work.items[0]: a object cannot be part of a key"),
    ((1, [2]), "Work.items[0][1]: a list cannot be part of a key (give a tuple)"),
])
def test_what_cannot_be_encoded_exactly_is_refused_by_its_path(value, said):
    with pytest.raises(TypeError) as caught:
        key_of(work(items=(value,)))
    assert str(caught.value) == said


def test_only_a_declared_type_is_keyed():
    with pytest.raises(TypeError, match="Part is not a declared input type"):
        key_of(Part(1.0))
    with pytest.raises(TypeError, match="tuple is not a declared input type"):
        key_of((1, 2))


def test_declared_types_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        work().count = 5


def test_keys_are_the_same_in_another_process():
    """No key depends on the process (Python's hash of strings changes with each)."""
    code = ("from lotsim.core.keys import inputs, key_of\n"
            "@inputs\nclass K:\n    names: frozenset\n    n: float\n"
            "print(key_of(K(frozenset({'alpha', 'beta', 'gamma', 'delta'}), 0.1)).hex())")
    got = {subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, env={"PYTHONHASHSEED": seed, "PATH": ""}).stdout
           for seed in ("1", "2", "3")}
    assert len(got) == 1 and len(got.pop().strip()) == 40


def test_the_declared_types_docs_caching_names_are_declared_where_it_says():
    """docs/caching.md's table of declared input types: each name is a declared type of
    the module named after it."""
    import importlib
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[3] / "docs" / "caching.md").read_text()
    table = text.split("## How a key is made")[1].split("## ")[0]
    found = 0
    for names, path in re.findall(r"((?:`[A-Z]\w+`(?:, )?)+) \(`(lotsim/[\w/]+)\.py`\)",
                                  table):
        module = importlib.import_module(path.replace("/", "."))
        for name in re.findall(r"`(\w+)`", names):
            assert getattr(getattr(module, name), "__key_inputs__", False), (path, name)
            found += 1
    assert found >= 20
