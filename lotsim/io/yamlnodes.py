"""A strict, located reader for YAML documents.

PyYAML's safe loader is used only to *compose* the node tree, so every value
keeps the line and column it came from. Values are then read through
:class:`YNode`, whose typed accessors raise :class:`~lotsim.errors.ScenarioError`
as ``file:line:col: key.path: expected ..., found ...``. It also catches what
PyYAML lets through silently: duplicate keys (last one wins), ``yes``/``on``
read as booleans, ``1e3`` read as a string, ``012`` read as octal, NaN and inf.
"""

from __future__ import annotations

import contextlib
import difflib
import math
import re
from collections.abc import Iterable
from pathlib import Path

import yaml

from lotsim.core.units import LENGTH_UNITS
from lotsim.errors import Location, ScenarioError

_STR = "tag:yaml.org,2002:str"
_INT = "tag:yaml.org,2002:int"
_FLOAT = "tag:yaml.org,2002:float"
_BOOL = "tag:yaml.org,2002:bool"
_NULL = "tag:yaml.org,2002:null"

_DECIMAL_INT = re.compile(r"^[-+]?(0|[1-9][0-9]*)$")
_DECIMAL_FLOAT = re.compile(r"^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$")
_MAX_DEPTH = 64
_FILE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,99}")
COORD_LIMIT = 1e6
"""Largest coordinate a point may have [m]: a lot is not a continent."""


class _ComposeLoader(yaml.SafeLoader):
    """Safe loader used for composition only; no Python objects are ever built."""


_FastLoader = getattr(yaml, "CSafeLoader", None)
"""libyaml's safe loader, when PyYAML was built with it: it composes the same tree, with the
same tags and marks, some ten times faster (plain scalars have style ``""`` instead of
None). A document it cannot read is read again by :class:`_ComposeLoader`, whose errors
are the ones reported."""


def describe(node: yaml.Node) -> str:
    """How a node reads to a person: ``string 'abc'``, ``a list``, ``nothing (null)``."""
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return "a list"
    raw = node.value
    shown = raw if len(raw) <= 40 else raw[:37] + "..."
    kind = {
        _STR: "string",
        _INT: "integer",
        _FLOAT: "number",
        _BOOL: "boolean",
        _NULL: "nothing (null)",
    }.get(node.tag, node.tag)
    return kind if node.tag == _NULL else f"{kind} {shown!r}"


class YNode:
    """A YAML node with its file position and key path, read through typed accessors.

    ``units`` is the length unit of the file it came from (``"m"`` or ``"ft"``, a key of
    :data:`LENGTH_UNITS`): :meth:`length`, :meth:`point` and :meth:`points` read in it and
    return metres; :meth:`number` reads a number as written.
    """

    __slots__ = ("node", "file", "key", "units")

    def __init__(self, node: yaml.Node, file: str, key: str = "", units: str = "m"):
        self.node = node
        self.file = file
        self.key = key
        self.units = units

    def in_units(self, units: str) -> YNode:
        """This node, its lengths read in ``units`` (a key of :data:`LENGTH_UNITS`)."""
        return YNode(self.node, self.file, self.key, units)

    # -- position -----------------------------------------------------------------------------
    @property
    def where(self) -> Location:
        """Location of this value."""
        mark = self.node.start_mark
        return Location(self.file, mark.line + 1, mark.column + 1, self.key)

    def error(self, message: str) -> ScenarioError:
        """A ScenarioError located at this value."""
        return ScenarioError(self.where, message)

    def _expected(self, what: str) -> ScenarioError:
        return self.error(f"expected {what}, found {describe(self.node)}")

    def _child(self, node: yaml.Node, key: str) -> YNode:
        return YNode(node, self.file, key, self.units)

    # -- containers ---------------------------------------------------------------------------
    @property
    def is_mapping(self) -> bool:
        return isinstance(self.node, yaml.MappingNode)

    @property
    def is_sequence(self) -> bool:
        return isinstance(self.node, yaml.SequenceNode)

    @property
    def is_null(self) -> bool:
        return isinstance(self.node, yaml.ScalarNode) and self.node.tag == _NULL

    def fields(
        self, required: Iterable[str] = (), optional: Iterable[str] = ()
    ) -> dict[str, YNode]:
        """Read a mapping with exactly these keys.

        Duplicate, unknown and missing keys are errors; the result holds the
        keys present, in document order.
        """
        if not self.is_mapping:
            raise self._expected("a mapping")
        required, optional = list(required), list(optional)
        allowed = required + optional
        out: dict[str, YNode] = {}
        first_line: dict[str, int] = {}
        for knode, vnode in self.node.value:
            if not isinstance(knode, yaml.ScalarNode):
                raise self._child(knode, self.key).error("a key must be a plain word")
            name = knode.value
            here = self._child(knode, f"{self.key}.{name}" if self.key else name)
            if name in out:
                raise here.error(
                    f"duplicate key {name!r} (first given on line {first_line[name]})"
                )
            if name not in allowed:
                hint = difflib.get_close_matches(name, allowed, n=1)
                also = f" (did you mean {hint[0]!r}?)" if hint else ""
                raise here.error(
                    f"unknown key {name!r}{also}; expected one of: {', '.join(allowed)}"
                )
            first_line[name] = knode.start_mark.line + 1
            out[name] = self._child(vnode, here.key)
        missing = [k for k in required if k not in out]
        if missing:
            raise self.error(f"missing key {missing[0]!r}; required: {', '.join(required)}")
        return out

    def items(self, *, min_len: int = 0, max_len: int | None = None) -> list[YNode]:
        """Read a list."""
        if not self.is_sequence:
            raise self._expected("a list")
        n = len(self.node.value)
        if n < min_len or (max_len is not None and n > max_len):
            size = f"exactly {min_len}" if max_len == min_len else f"at least {min_len}"
            if max_len is not None and max_len != min_len:
                size = f"{min_len} to {max_len}"
            raise self.error(f"expected a list of {size} items, found {n}")
        return [self._child(v, f"{self.key}[{i}]") for i, v in enumerate(self.node.value)]

    # -- scalars ------------------------------------------------------------------------------
    def _scalar(self) -> yaml.ScalarNode:
        if not isinstance(self.node, yaml.ScalarNode):
            raise self._expected("a single value")
        return self.node

    def number(
        self,
        *,
        positive: bool = False,
        min: float | None = None,
        max: float | None = None,
        open_min: bool = False,
        open_max: bool = False,
        what: str = "a number",
        unit: str | None = None,
        least: float | None = None,
    ) -> float:
        """Read a finite decimal number, optionally within bounds.

        ``unit`` ("m", "ft" or "deg") says what the number measures, for a hint where a
        value out of bounds is plausible in another unit: a length over ``max`` that would
        fit in millimetres or centimetres (in inches, for feet; a bound is then shown
        with its unit); an angle in degrees under ``least`` that is a
        plausible angle in radians (refused: no car steers 0.52°).
        """
        if not isinstance(self.node, yaml.ScalarNode):
            raise self._expected(what)
        node = self.node
        raw = node.value.strip()
        if node.tag in (_INT, _FLOAT) or (node.tag == _STR and not node.style):
            if node.tag == _INT and not _DECIMAL_INT.match(raw):
                raise self.error(
                    f"expected {what} in decimal, found {raw!r}, which YAML reads as "
                    f"{'octal' if raw.lstrip('+-').startswith('0') else 'a non-decimal integer'}"
                )
            if not _DECIMAL_FLOAT.match(raw):
                if node.tag == _FLOAT:
                    raise self.error(f"expected a finite {what[2:]}, found {raw!r}")
                raise self._expected(what)
            if node.tag == _STR:
                raise self.error(
                    f"expected {what}, found {raw!r}, which YAML reads as a string; "
                    f"write {_plain(raw)} or {_with_point(raw)}"
                )
            value = float(raw)
        else:
            raise self._expected(what)
        if not math.isfinite(value):
            raise self.error(f"expected a finite {what[2:]}, found {raw!r}")
        if positive and not value > 0:
            raise self.error(f"expected a positive {what[2:]}, found {raw}")
        shown = f" {unit}" if unit == "ft" else ""  # metric messages stay as they were
        if min is not None and (value < min or (open_min and value == min)):
            op = ">" if open_min else "≥"
            raise self.error(f"expected {what} {op} {min:g}{shown}, found {raw}")
        if max is not None and (value > max or (open_max and value == max)):
            op = "<" if open_max else "≤"
            raise self.error(f"expected {what} {op} {max:g}{shown}, found {raw}"
                             + (_metres_hint(value, max) if unit == "m" else "")
                             + (_feet_hint(value, max) if unit == "ft" else ""))
        if unit == "deg" and least is not None and 0 < value < least <= 90 \
                and value <= math.pi / 2:
            deg = math.degrees(value)
            raise self.error(f"expected degrees, found {raw}, which looks like radians "
                             f"({deg:.1f}°): write {deg:.0f}")
        return value

    def length(
        self,
        *,
        positive: bool = False,
        min: float | None = None,
        max: float | None = None,
        open_min: bool = False,
        open_max: bool = False,
    ) -> float:
        """Read a length in the file's unit → [m] (:func:`to_metres`); the bounds are in
        metres, and an error states them in the file's unit (``expected a number ≤ 164.042
        ft, found 2000``).

        Examples
        --------
        >>> node = parse_text("10", "f.yaml")
        >>> node.length(max=50), round(node.in_units("ft").length(max=50), 6)
        (10.0, 3.048)
        >>> parse_text("2000", "f.yaml").in_units("ft").length(max=50)
        Traceback (most recent call last):
        lotsim.errors.ScenarioError: f.yaml:1:1: expected a number ≤ 164.042 ft, found 2000
        """
        scale = LENGTH_UNITS[self.units]
        if scale == 1.0:
            return self.number(positive=positive, min=min, max=max, open_min=open_min,
                               open_max=open_max, unit="m")
        value = self.number(positive=positive,
                            min=None if min is None else min / scale,
                            max=None if max is None else max / scale,
                            open_min=open_min, open_max=open_max, unit=self.units)
        return to_metres(value, self.units)

    def integer(self, *, min: int | None = None, max: int | None = None) -> int:
        """Read a decimal integer, optionally within bounds."""
        node = self._scalar()
        raw = node.value.strip()
        if node.tag != _INT or not _DECIMAL_INT.match(raw):
            if node.tag == _INT:
                raise self.error(f"expected a decimal integer, found {raw!r}, read as octal")
            raise self._expected("an integer")
        value = int(raw)
        if min is not None and value < min:
            raise self.error(f"expected an integer ≥ {min}, found {value}")
        if max is not None and value > max:
            raise self.error(f"expected an integer ≤ {max}, found {value}")
        return value

    def string(self, *, choices: Iterable[str] | None = None, max_len: int = 200) -> str:
        """Read a string, optionally one of ``choices``."""
        node = self._scalar()
        options = list(choices) if choices is not None else None
        wanted = f"one of {', '.join(options)}" if options else "a string"
        if node.tag != _STR:
            hint = f" (quote it: \"{node.value}\")" if node.tag == _BOOL else ""
            raise self.error(f"expected {wanted}, found {describe(node)}{hint}")
        if options is not None and node.value not in options:
            hint = difflib.get_close_matches(node.value, options, n=1)
            also = f" (did you mean {hint[0]!r}?)" if hint else ""
            raise self.error(f"expected {wanted}, found {node.value!r}{also}")
        if len(node.value) > max_len:
            raise self.error(f"expected a string of at most {max_len} characters")
        return node.value

    def ident(self) -> str:
        """Read an identifier: a string or a decimal integer, returned as a string."""
        node = self._scalar()
        if node.tag == _INT and _DECIMAL_INT.match(node.value):
            return node.value
        if node.tag != _STR or not node.value.strip():
            raise self._expected("a name or number")
        if len(node.value) > 100:
            raise self.error("expected a name of at most 100 characters")
        return node.value

    def file_name(self, *, purpose: str, suffix: str = "") -> str:
        """Read a plain file or folder name (letters, digits, ``_ - .``; no ``/``, no ``..``).

        ``purpose`` says where the name is used, for the error message: a name from a
        scenario can only ever name something inside the folder lotsim was given.

        Examples
        --------
        >>> parse_text("runs-2", "f.yaml").file_name(purpose="it names a folder")
        'runs-2'
        >>> parse_text("../x", "f.yaml").file_name(purpose="it names a folder")
        Traceback (most recent call last):
        lotsim.errors.ScenarioError: f.yaml:1:1: expected letters, digits, '_', '-' or '.' ...
        """
        node = self._scalar()
        if node.tag != _STR:
            raise self._expected("a name")
        name = node.value
        if (not _FILE_NAME.fullmatch(name) or ".." in name
                or not name.lower().endswith(suffix)):
            ending = f", ending in {suffix}" if suffix else ""
            raise self.error(f"expected letters, digits, '_', '-' or '.'{ending} ({purpose}), "
                             f"found {name!r}")
        return name

    def boolean(self) -> bool:
        """Read ``true`` or ``false`` (not yes/no/on/off)."""
        node = self._scalar()
        if node.tag != _BOOL or node.value.lower() not in ("true", "false"):
            raise self._expected("true or false")
        return node.value.lower() == "true"

    def point(self) -> tuple[float, float]:
        """Read ``[x, y]`` in the file's unit → [m]."""
        x, y = self.items(min_len=2, max_len=2)
        return (x.length(min=-COORD_LIMIT, max=COORD_LIMIT),
                y.length(min=-COORD_LIMIT, max=COORD_LIMIT))

    def points(self, *, min_len: int) -> tuple[tuple[float, float], ...]:
        """Read a list of at least ``min_len`` points ``[[x, y], ...]`` in the file's
        unit → [m]."""
        return tuple(p.point() for p in self.items(min_len=min_len))


def _metres_hint(value: float, most: float) -> str:
    """A hint for a length too long in metres that is plausible in mm or cm."""
    for factor, name in ((1000, "millimetres"), (100, "centimetres")):
        if value / factor <= most:
            return (f" (in {name}? lotsim's lengths are metres: {value:g} {name[:1]}m is "
                    f"{value / factor:g} m)")
    return ""


def _feet_hint(value: float, most: float) -> str:
    """A hint for a length too long in feet that is plausible in inches."""
    if value / 12 <= most:
        return (f" (in inches? this file's lengths are feet (units: ft): {value:g} in is "
                f"{value / 12:g} ft)")
    return ""


def to_metres(value: float, units: str) -> float:
    """A length in ``units`` → [m], rounded to the nanometre.

    The foot is exactly 0.3048 m, so a length in feet with ``k`` decimals is one in
    metres with at most ``k + 4``: rounding takes away only the float's error in the
    product, and a metric length written in feet with enough digits reads back as the
    very same number (a lot drawn in feet is the lot drawn in metres, bit for bit).

    >>> to_metres(9, "ft"), to_metres(3 / 0.3048, "ft"), 3 / 0.3048 * 0.3048
    (2.7432, 3.0, 3.0000000000000004)
    """
    scale = LENGTH_UNITS[units]
    return float(value) if scale == 1.0 else round(value * scale, 9)


def units_of(root: YNode) -> YNode:
    """``root`` with its lengths read in the unit its top-level ``units`` key states
    (``m``, the default, or ``ft``); the caller reads ``units`` as one of its keys.

    Examples
    --------
    >>> units_of(parse_text("units: ft\\nx: 1\\n", "f.yaml")).units
    'ft'
    >>> units_of(parse_text("units: yd\\n", "f.yaml"))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    lotsim.errors.ScenarioError: f.yaml:1:8: units: expected one of m, ft, found 'yd'
    """
    if not root.is_mapping:
        return root
    for knode, vnode in root.node.value:
        if getattr(knode, "value", None) == "units":
            units = YNode(vnode, root.file, "units").string(choices=list(LENGTH_UNITS))
            return root.in_units(units)
    return root


def _with_point(raw: str) -> str:
    """``1e3`` as YAML 1.1 reads a float: a point in the mantissa, a signed exponent."""
    mantissa, _, exponent = raw.lower().partition("e")
    if "." not in mantissa:
        mantissa += ".0"
    if exponent and exponent[0] not in "+-":
        exponent = "+" + exponent
    return f"{mantissa}e{exponent}" if exponent else mantissa


def _plain(raw: str) -> str:
    value = float(raw)
    return str(int(value)) if value.is_integer() and abs(value) < 1e15 else repr(value)


def _depth_ok(node: yaml.Node, limit: int) -> bool:
    stack = [(node, 0)]
    seen: set[int] = set()
    while stack:
        n, d = stack.pop()
        if d > limit:
            return False
        if id(n) in seen:
            continue
        seen.add(id(n))
        if isinstance(n, yaml.SequenceNode):
            stack.extend((c, d + 1) for c in n.value)
        elif isinstance(n, yaml.MappingNode):
            stack.extend((v, d + 1) for _, v in n.value)
    return True


def parse_text(text: str, file: str) -> YNode:
    """Compose one YAML document from ``text`` into a located :class:`YNode`.

    Raises
    ------
    ScenarioError
        For a syntax error, an empty file, several documents, or nesting deeper than 64.
    """
    nodes = None
    if _FastLoader is not None:
        with contextlib.suppress(yaml.YAMLError, RecursionError):
            nodes = list(yaml.compose_all(text, Loader=_FastLoader))
    try:
        if nodes is None:
            nodes = list(yaml.compose_all(text, Loader=_ComposeLoader))
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = Location(file, mark.line + 1, mark.column + 1) if mark else Location(file, 1, 1)
        raise ScenarioError(where, f"invalid YAML: {exc.problem or exc.context}") from None
    except yaml.reader.ReaderError as exc:  # a character YAML does not allow: no mark
        before = text[: exc.position]
        where = Location(file, before.count("\n") + 1, exc.position - before.rfind("\n"))
        c = exc.character if isinstance(exc.character, int) else ord(exc.character)
        raise ScenarioError(where, f"invalid YAML: character U+{c:04X} is not allowed "
                                   "in a YAML file") from None
    except yaml.YAMLError as exc:
        message = " ".join(str(exc).split())
        raise ScenarioError(Location(file, 1, 1), f"invalid YAML: {message}") from None
    except RecursionError:
        raise ScenarioError(Location(file, 1, 1), "nesting is too deep") from None
    if not nodes:
        found = ("only comments" if any(line.strip() for line in text.splitlines())
                 else "an empty file")
        raise ScenarioError(Location(file, 1, 1), f"expected a YAML mapping, found {found}")
    if len(nodes) > 1:
        mark = nodes[1].start_mark
        raise ScenarioError(
            Location(file, mark.line + 1, mark.column + 1),
            "expected one YAML document, found several",
        )
    if not _depth_ok(nodes[0], _MAX_DEPTH):
        raise ScenarioError(Location(file, 1, 1), f"nesting is deeper than {_MAX_DEPTH} levels")
    return YNode(nodes[0], file)


def read_yaml(path: str | Path, *, expect: str | None = None) -> YNode:
    """Read and compose a YAML file; a missing or unreadable file is a ScenarioError, and
    so is a JSON file of another kind than ``expect`` (:mod:`lotsim.io.file_kinds`: a result
    given where a scenario belongs)."""
    file = str(path)
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise ScenarioError(None, f"{file}: cannot read: {exc.strerror or exc}") from None
    if expect is not None:
        from lotsim.io.file_kinds import json_kind, wrong_kind

        found = json_kind(raw)
        if found is not None and found != expect:
            raise ScenarioError(Location(file, 1, 1), wrong_kind(found, expect))
    if len(raw) > 20_000_000:
        raise ScenarioError(Location(file, 1, 1), "file is larger than 20 MB")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise ScenarioError(Location(file, line, 1), "expected UTF-8 text") from None
    return parse_text(text, file)
