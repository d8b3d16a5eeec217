"""Which kind of lotsim file a document is: a scenario, a result or a bench suite.

A command given the wrong kind says so (``this is a lotsim result, not a scenario``)
instead of reporting the first key it does not expect.

Examples
--------
>>> document_kind({"format": "lotsim-result", "lot": {}})
'result'
>>> document_kind({"lot": {}, "traffic": {}}), document_kind({"scenarios": [], "planners": []})
('scenario', 'suite')
>>> print(document_kind({"width": 2.0}))
None
>>> wrong_kind("result", "scenario")
'this is a lotsim result, not a scenario: results are read by lotsim check and lotsim render'
"""

from __future__ import annotations

import gzip
import json
import os
import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from lotsim.errors import Location, ScenarioError

if TYPE_CHECKING:
    from lotsim.io.yamlnodes import YNode

RESULT_FORMAT = "lotsim-result"
"""The ``format`` of a ``result.json`` (``docs/result.md``)."""

READERS = {
    "scenario": "scenarios are read by lotsim run, validate, show and maneuver, and "
                "lotsim export --dxf draws their lot (docs/scenario.md)",
    "result": "results are read by lotsim check and lotsim render",
    "suite": "suites are read by lotsim bench (docs/bench.md)",
}
"""What reads each kind of file."""


def document_kind(document: Any) -> str | None:
    """``"scenario"``, ``"result"`` or ``"suite"`` by a document's top-level keys (None:
    none of them, or not a mapping)."""
    if not isinstance(document, Mapping):
        return None
    if document.get("format") == RESULT_FORMAT:
        return "result"
    if "lot" in document:
        return "scenario"
    if "scenarios" in document and "planners" in document:
        return "suite"
    return None


NAMES = {"scenario": "scenario", "result": "result", "suite": "bench suite"}


def wrong_kind(found: str, expected: str) -> str:
    """The message for a ``found`` file where an ``expected`` one belongs."""
    return f"this is a lotsim {NAMES[found]}, not a {NAMES[expected]}: {READERS[found]}"


def refuse_other_kind(document: Any, expected: str, file: str) -> None:
    """Raise :class:`ScenarioError` at the top of ``file`` when ``document`` (its parsed
    top level) is another kind of lotsim file than ``expected``."""
    found = document_kind(document)
    if found is not None and found != expected:
        raise ScenarioError(Location(file, 1, 1), wrong_kind(found, expected))


def top_level(root: YNode) -> dict[str, str | None]:
    """A composed YAML document's top-level keys with their scalar values (None for a
    list or mapping), for :func:`document_kind`; empty when it is not a mapping."""
    if not root.is_mapping:
        return {}
    return {k.value: (v.value if isinstance(v, yaml.ScalarNode) else None)
            for k, v in root.node.value if isinstance(k, yaml.ScalarNode)}


def json_kind(raw: bytes) -> str | None:
    """The kind of a file's bytes when they are a JSON object (quick: a ``result.json``
    runs to megabytes, too slow to compose as YAML only to learn what it is); a result in
    its compact form (gzip) too."""
    if raw[:2] == b"\x1f\x8b":
        try:
            raw = gzip.decompress(raw)
        except (OSError, EOFError, zlib.error):
            return None
    if raw.lstrip()[:1] != b"{":
        return None
    try:
        return document_kind(json.loads(raw))
    except (ValueError, RecursionError):
        return None


def file_kind(path: str | os.PathLike) -> str | None:
    """The kind of lotsim file at ``path``, JSON or YAML (None: unreadable, or none of
    them). For messages only: a YAML file over 2 MB is not composed to find out."""
    try:
        raw = Path(path).read_bytes()
    except OSError:
        return None
    found = json_kind(raw)
    if found is not None or len(raw) > 2_000_000:
        return found
    try:
        return document_kind(yaml.safe_load(raw))
    except (yaml.YAMLError, ValueError, RecursionError):
        return None
