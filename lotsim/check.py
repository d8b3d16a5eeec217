"""An independent verifier of ``result.json``, the output of ``lotsim run``.

The checker reads only the result (see ``docs/result.md``) and shares no code with the
planners, the simulator or the geometry of lotsim: it imports nothing from the package
but an error type (:class:`lotsim.errors.ResultFormatError`), and re-derives every quantity
it judges from the numbers in the file — footprint rectangles from the vehicle type's
``width``, ``front`` and ``rear`` and the rear-axle pose, headings, curvatures and speeds
from consecutive samples. A bug in the planners can therefore not hide itself by being
repeated here.

Rules and tolerances (module constants)
---------------------------------------
structure
    Top-level keys, ``format`` and ``version``; every lot and vehicle key with its type
    (numbers finite and at most ``MAX_MAGNITUDE`` = 1e9 in size, polygons valid);
    sample arrays of equal length, ``t`` strictly increasing, ``gear`` in {-1, 0, 1};
    known statuses and entrances; unique ids; vehicles in arrival order; one car in
    ``lot.parked`` per occupied slot; every limit of the vehicle type present and positive
    (the speeds, ``max_accel``, ``max_brake``, ``max_lateral_accel``, ``max_steer_rate``,
    ``max_jerk``). A vehicle whose structure is broken is skipped by every later rule.
sampling
    Consecutive samples at most ``MAX_DT`` = 0.05 s (+ ``TIME_TOL`` = 0.2 ms) apart unless
    the vehicle stands still between them (same pose within the rounding: ``STILL_TOL`` =
    0.15 mm in x and y, ``STILL_TURN`` = 1.5 µrad in heading,
    ``v`` = 0 and ``gear`` = 0 at both), and never more than ``MAX_STEP`` = 0.5 m
    (+ ``STEP_TOL`` = 0.2 mm) apart. The slacks absorb the rounding of times and
    positions to 0.1 ms and 0.1 mm in lotsim's writer.
sideways
    The chord ``d`` between two samples, resolved against the mean heading (interpolated
    the short way round), has a perpendicular part of at most ``SIDEWAYS_ABS`` = 5 mm
    + ``SIDEWAYS_REL`` = 1 % of ``|d|`` + ``|d|² / 4R``, the offset of an S-bend at the
    minimum turning radius ``R = wheelbase / tan(max_steer)``.
curvature
    ``|Δθ| ≤ |d| / R · CURVATURE_REL + CURVATURE_ABS`` (1.01 and 1e-4 rad).
heading
    The kinematic single-track model: the heading change between two samples is the
    curvature ``κ = tan(steer) / wheelbase`` integrated over the distance driven,
    ``Δθ ≈ dir · s · (κ₀ + κ₁) / 2`` with ``dir`` the sign of the chord along the mean
    heading and ``s = |d| / sinc(Δθ / 2)`` the arc length of the chord (exact for a
    curvature constant or linear in arc length, i.e. arcs and clothoids). Allowed:
    ``HEADING_ABS`` (1e-5 rad: headings rounded to 1 µrad) + ``HEADING_CHORD`` (0.15 mm:
    the chord's rounding) · mean ``|κ|`` + ``HEADING_KINK`` (0.5) · ``s · |κ₁ - κ₀|``
    (a kink of the curvature inside the interval), or ``s · K · Δt / 2`` when larger (a
    curvature that bends back inside the interval, within the steering rate: ``K`` =
    ``max_steer_rate / (b cos² φ)``), + ``HEADING_REL`` (1e-3) · the prediction.
    Standing still (``d`` = 0) the steer may change, the heading may not.
steer
    ``|steer| ≤ max_steer + STEER_TOL`` (1e-6 rad).
steer_rate
    ``|Δsteer| ≤ max_steer_rate · Δt + STEER_RATE_TOL`` between consecutive samples
    (5 µrad: two steers rounded to 1 µrad and ``Δt`` to 1 µs, with a margin), standing or
    moving.
gear
    ``v`` agrees with ``gear`` (+1: ``v ≥ -GEAR_SPEED_TOL``; -1: ``v ≤ GEAR_SPEED_TOL``;
    0: ``|v| ≤ GEAR_SPEED_TOL``, 1e-3 m/s). Where the chord's component along the mean
    heading exceeds ``GEAR_MIN_STEP`` = 1 mm, its sign is the direction of travel: an
    end sample that moves (``|v| > GEAR_SPEED_TOL``) must be in that gear and at least
    one end must be. A sample standing at a cusp may keep the gear of the stroke it ends.
speed
    ``|v| ≤ limit + SPEED_TOL`` (1e-3 m/s), the limit being the smallest of the type's
    forward (``v ≥ 0``) or reverse top speed, the lot's ``speed_limit`` and the limit of
    every speed zone strictly containing the rear-axle centre. The chord
    ``|d| ≤ (limit · CHORD_SPEED_REL + SPEED_TOL) · dt + CHORD_SLACK`` (1.01, 1 mm for
    rounded numbers), the limit of a pair being the looser of its two ends' lot and zone
    limits and the reverse top speed if either end is in reverse.
lateral
    ``v² · |tan(steer)| / wheelbase ≤ max_lateral_accel + LATERAL_TOL`` at every sample
    (1e-3 m/s², ten times what rounding ``v`` to 0.1 mm/s changes it by).
accel
    Between consecutive samples ``|v|`` grows by at most ``max_accel · Δt`` and shrinks by
    at most ``max_brake · Δt``, plus ``ACCEL_TOL`` (2e-4 m/s: two speeds rounded to
    0.1 mm/s, doubled). By the mean value theorem the chord's slope is the acceleration
    at some instant in between, so this is exact for any speed profile. A pair whose
    speeds have opposite signs must leave time to stop and start again:
    ``(|v₀| - ACCEL_TOL) / max_brake + (|v₁| - ACCEL_TOL) / max_accel ≤ Δt``.
jerk
    On the samples thinned to at least ``JERK_MIN_DT`` = 0.02 s apart (a sample closer
    than that to the one before it is left out; the last is always kept), twice the
    second divided difference of the signed speed, ``2 · v[t₀, t₁, t₂]``, is at most
    ``max_jerk`` in size plus what rounding can make of it: ``2 · (e₀₁ + e₁₂) / (t₂ - t₀)``,
    ``e = (2 · V_ROUND + 2 · T_ROUND · |slope|) / h`` the error of a first divided
    difference over ``h`` (``V_ROUND`` = 5e-5 m/s and ``T_ROUND`` = 5e-7 s, half the last
    digit written); about ``4 · V_ROUND / h²``, 0.08 m/s³ at 0.05 s and 0.5 m/s³ at
    0.02 s. For a speed with a continuous acceleration and a bounded jerk,
    ``2 · v[t₀, t₁, t₂]`` is a weighted mean of the jerk over ``[t₀, t₂]``.
overlap, parked, obstacle, boundary
    Footprints shrunk by ``SHRINK`` = 1 cm on every side are compared at the common
    instants ``k · GRID_DT`` (0.05 s) from the earliest to the latest sample, poses
    interpolated linearly between samples (heading the short way). A vehicle is present
    from its first to its last sample; a ``departed`` one is gone afterwards, any other
    stays at its last pose to the end. No two present footprints intersect (touching
    shrunk rectangles count: the true ones then overlap by 2 cm), none intersects a car
    parked at start (``parked``) or an obstacle (``obstacle``), each is covered by the
    lot boundary (``boundary``). Each pair is reported once, at its first instant.
slot
    A ``parked`` vehicle names a slot of the lot that was free at start, its last
    footprint (shrunk) lies within that slot, and it is at rest (``|v| ≤ REST_SPEED``).
    A vehicle holds its slot at every instant its shrunk footprint lies within it, and a
    ``parked`` one from its last sample to the end; no two vehicles hold one slot at once.
exit
    A ``departed`` vehicle's last pose is within ``EXIT_DISTANCE`` = 0.5 m and
    ``EXIT_HEADING`` = 0.1 rad of an exit's pose.
status, reason, arrival, metrics
    A ``rejected`` vehicle has no samples, a ``parked`` or ``departed`` one has some;
    ``waiting`` and ``rejected`` vehicles give a reason, the others none; no sample
    before the vehicle's arrival (``TIME_TOL``); the status counts (and ``makespan``, within
    ``MAKESPAN_TOL`` = 1e-3 s) in ``metrics`` match the vehicles.

A problem the checker itself runs into is reported as the rule ``internal``, never
raised. Vehicle-vehicle tests are exact separating-axis tests on the rectangles after a
sort-and-sweep (same instant) and a grid (standing vehicles) broad phase; tests against
the lot use shapely 2 on the footprints a vectorised point test cannot clear.

Examples
--------
>>> report = check_result({"format": "lotsim-result"})
>>> report.ok, report.violations[0].rule
(False, 'structure')
"""

from __future__ import annotations

import json
import math
import os
import time
import warnings
from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import shapely

from lotsim.errors import ResultFormatError  # an error type only: no code is shared

FORMAT = "lotsim-result"
VERSION = 1
TOP_LEVEL_KEYS = ("format", "version", "lot", "vehicles", "metrics", "settings")
LOT_KEYS = ("boundary", "slots", "obstacles", "parked", "speed_limit", "speed_zones",
            "entrances", "exits")
VEHICLE_KEYS = ("id", "type", "arrival", "entrance", "slot", "status", "reason", "samples")
TYPE_NUMBERS = ("width", "front", "rear", "wheelbase", "max_steer", "max_forward_speed",
                "max_reverse_speed", "max_accel", "max_brake", "max_lateral_accel",
                "max_steer_rate", "max_jerk")
SAMPLE_KEYS = ("t", "x", "y", "theta", "v", "steer", "gear")
STATUSES = ("parked", "departed", "waiting", "rejected")
SLOT_KINDS = ("perpendicular", "parallel", "angled")

MAX_DT = 0.05
"""Longest interval between samples of a moving vehicle [s]."""
TIME_TOL = 2e-4
"""Slack on ``MAX_DT`` and on arrival times [s]: two times rounded to 0.1 ms."""
MAX_STEP = 0.5
"""Longest distance between consecutive samples [m]."""
STEP_TOL = 2e-4
"""Slack on ``MAX_STEP`` [m]: two positions rounded to 0.1 mm."""
STILL_TOL = 1.5e-4
"""Two positions closer than this in x and in y [m] are the same place: the writer rounds
to 0.1 mm, so one pose computed along two paths (a node's pose, a motion's first sample)
may be written one unit apart when it lies on a half unit (found by the property tests)."""
STILL_TURN = 1.5e-6
"""... and two headings closer than this [rad] the same (written to 1 µrad)."""
SIDEWAYS_ABS = 0.005
"""Allowed sideways part of a chord, absolute [m] ..."""
SIDEWAYS_REL = 0.01
"""... plus this fraction of the chord length."""
CURVATURE_REL = 1.01
"""Allowed heading change per metre of chord, as a multiple of 1 / R_min."""
CURVATURE_ABS = 1e-4
"""Slack on the heading change between two samples [rad]."""
STEER_TOL = 1e-6
"""Slack on ``max_steer`` [rad]."""
STEER_RATE_TOL = 5e-6
"""Slack on the steer change between two samples [rad]: both steers are rounded to 1 µrad
(together up to 1 µrad off) and the times to 1 µs (``max_steer_rate`` · 1 µs, below
1 µrad); five times that, so two samples 2 µs apart differing by rounding pass."""
HEADING_ABS = 1e-5
"""Slack on the heading change predicted from the steer [rad]: both headings rounded to
1 µrad, the steers to 1 µrad (a curvature off by under 1e-6 / m over at most 0.5 m), and
the trapezoid rule's error ``s³ |κ''| / 12`` for a smoothly varying curvature."""
HEADING_CHORD = 1.5e-4
"""... plus this [m] times the mean ``|κ|``: the chord length is computed from positions
rounded to 0.1 mm, so it is up to 2 · √2 · 0.05 mm = 0.14 mm off."""
HEADING_KINK = 0.5
"""... plus this times ``s · |κ₁ - κ₀|``: where the curvature has a kink inside the
interval (an arc meets a clothoid) the trapezoid rule is no longer exact, but for any
curvature monotone between its end values the integral lies between ``s · κ₀`` and
``s · κ₁``, so the trapezoid errs by at most half their difference. A quarter, the error
of a kink halfway, is not enough: a kink with the arc over the fraction ``f`` of the
interval errs by ``f / 2 · s · |Δκ|`` (0.45 at ``f`` = 0.9), and with 0.25 a result
planned by lotsim (``scenarios/mixed_lot.yaml``) failed this rule."""
HEADING_REL = 1e-3
"""... plus this fraction of the predicted turn: the arc length is recovered from the
chord assuming a constant curvature, which a clothoid bends by a relative
``O((s · Δκ)²)``, and the rounding of the steer."""
LATERAL_TOL = 1e-3
"""Slack on ``max_lateral_accel`` [m/s²]: ``v`` rounded to 0.1 mm/s changes
``v² · |κ|`` by at most ``2 · |v| · 5e-5 · |κ|``, about 1e-4 m/s² at 5 m/s and
``|κ|`` = 0.2 / m."""
ACCEL_TOL = 2e-4
"""Slack on the speed change between two samples [m/s]: two speeds rounded to 0.1 mm/s
differ by up to 0.1 mm/s more or less than the true ones; twice that."""
JERK_MIN_DT = 0.02
"""Samples closer than this [s] to the sample before them are left out of the jerk test
(a stroke's end a few µs after a grid sample), so the kept ones are at least this far
apart: the rounding error of a second divided difference grows as ``1 / h²``."""
V_ROUND = 5e-5
"""Largest rounding error of a speed in the file [m/s] (half of 0.1 mm/s)."""
T_ROUND = 5e-7
"""Largest rounding error of a time in the file [s] (half of 1 µs)."""
GEAR_MIN_STEP = 1e-3
"""Chord component along the heading above which the direction of travel is judged [m]
(ten times the rounding of positions in the file)."""
GEAR_SPEED_TOL = 1e-3
"""Speeds within this of zero count as standing [m/s]."""
SPEED_TOL = 1e-3
"""Slack on every speed limit [m/s]."""
CHORD_SPEED_REL = 1.01
"""Allowed chord speed as a multiple of the limit."""
CHORD_SLACK = 1e-3
"""Slack on the chord length in the speed test [m]: samples a fraction of a millisecond
apart (a stroke's end) have their times and positions rounded to 0.1 ms and 0.1 mm."""
GRID_DT = 0.05
"""Spacing of the common instants the footprints are compared at [s]."""
SHRINK = 0.01
"""Inset of every side of a footprint before the overlap tests [m]."""
EXIT_DISTANCE = 0.5
"""Largest distance of a departed vehicle's last rear-axle position from an exit [m]."""
EXIT_HEADING = 0.1
"""Largest heading difference to that exit [rad]."""
REST_SPEED = 1e-3
"""A parked vehicle's last speed is at most this [m/s]."""
MAKESPAN_TOL = 1e-3
"""Slack on ``metrics.makespan`` [s]."""
MAX_MAGNITUDE = 1e9
"""Numbers beyond this in size overflow the geometry and are a structure violation."""
MAX_INSTANTS = 50_000_000
"""Vehicle-instants beyond which the footprint rules give up (memory) [-]."""

RULES = ("internal", "structure", "status", "arrival", "sampling", "sideways", "curvature",
         "heading", "steer", "steer_rate", "gear", "speed", "lateral", "accel", "jerk",
         "overlap", "parked", "obstacle", "boundary", "slot", "exit", "reason", "metrics")
"""Every rule tag, in the order violations are listed."""

_PAIR_BUDGET = 2_000_000  # candidate pairs tested per numpy batch (bounds memory)
_SAME = 1e-9  # interpolated poses closer than this are one standing footprint [m, rad]

FloatArray = np.ndarray
Pose = tuple[float, float, float]
_T = TypeVar("_T")


@dataclass(frozen=True, slots=True)
class Violation:
    """One broken rule.

    Attributes
    ----------
    rule : str
        Short tag, one of :data:`RULES`.
    vehicle : str or None
        Id of the vehicle concerned (the first one of a pair), None for the whole file.
    t : float or None
        When it happens [s], None when it is not tied to a time.
    message : str
        One line a person understands.
    """

    rule: str
    vehicle: str | None
    t: float | None
    message: str

    def __str__(self) -> str:
        return f"{self.rule}: {self.message}"


@dataclass
class CheckReport:
    """What :func:`check_result` found.

    Attributes
    ----------
    violations : list of Violation
        The first violations (at most ``max_violations``), by rule, then time.
    stats : dict
        ``vehicles``, ``vehicles_checked``, ``samples``, ``intervals`` (consecutive sample
        pairs), ``instants`` (common instants), ``footprints`` (distinct footprints:
        one per moving vehicle-instant, one per standing stretch), ``vehicle_instants``,
        ``footprint_tests`` (exact rectangle and polygon tests), ``violations`` (all
        found, also those left out of the list) and ``seconds`` (checking time).
    """

    violations: list[Violation]
    stats: dict

    @property
    def ok(self) -> bool:
        """True when no rule is broken."""
        return not self.violations and not self.stats.get("violations", 0)

    def summary(self) -> str:
        """One line: what was checked and how many violations were found."""
        s = self.stats
        what = (f"{s.get('vehicles_checked', 0)} of {s.get('vehicles', 0)} vehicles, "
                f"{s.get('samples', 0)} samples, {s.get('instants', 0)} instants")
        if self.ok:
            return f"ok: {what}"
        total = s.get("violations", len(self.violations))
        shown = "" if total == len(self.violations) else f" (first {len(self.violations)})"
        return f"{total} violation{'s' if total != 1 else ''}{shown}: {what}"


def load_result(path: str | os.PathLike[str]) -> dict:
    """Read a ``result.json``.

    Parameters
    ----------
    path : str or path-like
        The file.

    Returns
    -------
    dict
        The parsed result, recognised by its ``format``, ``version`` and top-level keys;
        its content is judged by :func:`check_result`.

    Raises
    ------
    ResultFormatError
        The file cannot be read, is not JSON or is not a lotsim result; the message
        names the file and says why.

    Examples
    --------
    >>> load_result("/no/result.json")
    Traceback (most recent call last):
    ...
    lotsim.errors.ResultFormatError: /no/result.json: cannot read it (No such file or directory)
    """
    name = os.fspath(path)
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise ResultFormatError(f"{name}: cannot read it ({exc.strerror or exc})") from None
    try:
        data = json.loads(raw)
    except json.JSONDecodeError as exc:
        raise ResultFormatError(
            f"{name}: not JSON (line {exc.lineno}, column {exc.colno}: {exc.msg})") from None
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise ResultFormatError(f"{name}: not JSON ({exc})") from None
    problem = _format_problem(data)
    if problem is not None:
        raise ResultFormatError(f"{name}: {problem}")
    return data


def check_result(data: dict, *, max_violations: int = 50) -> CheckReport:
    """Verify a result against every rule of ``docs/result.md``.

    Parameters
    ----------
    data : dict
        A parsed ``result.json`` (any value is accepted: what is not a result is reported
        as a ``structure`` violation, never raised).
    max_violations : int, keyword-only
        How many violations to list; ``stats["violations"]`` counts them all.

    Returns
    -------
    CheckReport
        ``report.ok`` is True when every rule holds.

    Examples
    --------
    >>> check_result([]).violations[0].message
    'not a lotsim result: expected a JSON object, found list'
    """
    started = time.perf_counter()
    out: list[Violation] = []
    stats: dict[str, Any] = {"vehicles": 0, "vehicles_checked": 0, "samples": 0,
                             "intervals": 0, "instants": 0, "footprints": 0,
                             "vehicle_instants": 0, "footprint_tests": 0}
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # overflows are judged, not printed
        _guard(out, "the result", _check, data, out, stats)
    order = {rule: i for i, rule in enumerate(RULES)}
    out.sort(key=lambda v: (order.get(v.rule, len(RULES)), v.t is not None, v.t or 0.0,
                            v.vehicle or ""))
    stats["violations"] = len(out)
    stats["seconds"] = round(time.perf_counter() - started, 4)
    return CheckReport(out[:max(0, int(max_violations))], stats)


# --------------------------------------------------------------------------- parsing


@dataclass(frozen=True, slots=True)
class _Slot:
    id: str
    polygon: shapely.Polygon
    occupied: bool


@dataclass(slots=True)
class _Lot:
    boundary: shapely.Polygon | None = None
    slots: dict[str, _Slot] = field(default_factory=dict)
    obstacles: list[shapely.Polygon] = field(default_factory=list)
    parked: list[shapely.Polygon] = field(default_factory=list)
    speed_limit: float = math.inf
    zones: list[tuple[str, shapely.Polygon, float]] = field(default_factory=list)
    entrances: dict[str, Pose] | None = None  # None: unknown, do not cross-check
    exits: dict[str, Pose] = field(default_factory=dict)


@dataclass(slots=True)
class _Vehicle:
    index: int
    id: str
    status: str
    slot: str | None
    reason: str
    arrival: float
    width: float
    front: float
    rear: float
    wheelbase: float
    max_steer: float
    max_forward_speed: float
    max_reverse_speed: float
    max_accel: float
    max_brake: float
    max_lateral_accel: float
    max_steer_rate: float
    max_jerk: float
    t: FloatArray
    x: FloatArray
    y: FloatArray
    theta: FloatArray
    v: FloatArray
    steer: FloatArray
    gear: FloatArray

    @property
    def n(self) -> int:
        return len(self.t)

    @property
    def min_radius(self) -> float:
        return self.wheelbase / math.tan(self.max_steer)


def _add(out: list[Violation], rule: str, vehicle: str | None, t: float | None,
         message: str) -> None:
    out.append(Violation(rule, vehicle, None if t is None else float(t), message))


def _guard(out: list[Violation], what: str, fn: Callable[..., _T], *args: Any) -> _T | None:
    """Run one stage; a failure of the checker becomes an ``internal`` violation."""
    try:
        return fn(*args)
    except Exception as exc:  # the checker must never raise on its input
        _add(out, "internal", None, None,
             f"the checker failed on {what}: {type(exc).__name__}: {exc}")
        return None


def _is_number(value: Any) -> bool:
    """A JSON number (not a boolean) of at most ``MAX_MAGNITUDE`` in size."""
    return (isinstance(value, int | float) and not isinstance(value, bool)
            and abs(value) <= MAX_MAGNITUDE)


def _kind(value: Any) -> str:
    names = {dict: "object", list: "list", str: "string", bool: "boolean", type(None): "null"}
    return names.get(type(value), type(value).__name__)


def _format_problem(data: Any) -> str | None:
    """Why ``data`` is not a lotsim result at all, or None."""
    if not isinstance(data, dict):
        return f"not a lotsim result: expected a JSON object, found {_kind(data)}"
    if data.get("format") != FORMAT:
        return (f"not a lotsim result: 'format' is {data.get('format')!r}, "
                f"expected {FORMAT!r}")
    missing = [k for k in TOP_LEVEL_KEYS if k not in data]
    if missing:
        keys = ", ".join(repr(k) for k in missing)
        return f"not a lotsim result: missing top-level key{'s' if len(missing) > 1 else ''} {keys}"
    version = data.get("version")
    if version != VERSION or isinstance(version, bool):
        return f"unsupported result version {version!r} (this checker reads version {VERSION})"
    return None


def _points(value: Any) -> np.ndarray | None:
    """A list of ``[x, y]`` finite numbers as an (N, 2) array, else None."""
    if not isinstance(value, list):
        return None
    for p in value:
        if not (isinstance(p, list) and len(p) == 2 and _is_number(p[0]) and _is_number(p[1])):
            return None
    return np.array(value, dtype=float).reshape(-1, 2)


def _polygon(value: Any, where: str, out: list[Violation]) -> shapely.Polygon | None:
    pts = _points(value)
    if pts is None or len(pts) < 3:
        _add(out, "structure", None, None,
             f"{where}: expected a polygon [[x, y], ...] of at least 3 finite points")
        return None
    poly = shapely.Polygon(pts)
    if not poly.is_valid or poly.area <= 0:
        _add(out, "structure", None, None,
             f"{where}: not a valid polygon ({shapely.is_valid_reason(poly)})")
        return None
    return poly


def _pose(value: Any) -> Pose | None:
    if isinstance(value, list) and len(value) == 3 and all(_is_number(c) for c in value):
        return (float(value[0]), float(value[1]), float(value[2]))
    return None


def _parse_lot(raw: Any, out: list[Violation]) -> _Lot:
    lot = _Lot()
    if not isinstance(raw, dict):
        _add(out, "structure", None, None, f"lot: expected an object, found {_kind(raw)}")
        return lot
    for key in LOT_KEYS:
        if key not in raw:
            _add(out, "structure", None, None, f"lot: missing key {key!r}")
    if "boundary" in raw:
        lot.boundary = _polygon(raw["boundary"], "lot.boundary", out)

    slots = raw.get("slots", [])
    if not isinstance(slots, list):
        _add(out, "structure", None, None, "lot.slots: expected a list")
        slots = []
    occupied = 0
    for i, s in enumerate(slots):
        where = f"lot.slots[{i}]"
        if not isinstance(s, dict):
            _add(out, "structure", None, None, f"{where}: expected an object")
            continue
        sid = s.get("id")
        if not isinstance(sid, str) or not sid:
            _add(out, "structure", None, None, f"{where}.id: expected a non-empty string")
            continue
        where = f"slot {sid}"
        if sid in lot.slots:
            _add(out, "structure", None, None, f"{where}: the id is used twice")
        if s.get("kind") not in SLOT_KINDS:
            _add(out, "structure", None, None,
                 f"{where}: kind {s.get('kind')!r} is not one of {', '.join(SLOT_KINDS)}")
        if not isinstance(s.get("occupied"), bool):
            _add(out, "structure", None, None, f"{where}: 'occupied' must be true or false")
        poly = _polygon(s.get("polygon"), f"{where}.polygon", out)
        if poly is not None:
            lot.slots[sid] = _Slot(sid, poly, s.get("occupied") is True)
        occupied += s.get("occupied") is True

    for key in ("obstacles", "parked"):
        polys = raw.get(key, [])
        if not isinstance(polys, list):
            _add(out, "structure", None, None, f"lot.{key}: expected a list of polygons")
            continue
        for i, p in enumerate(polys):
            poly = _polygon(p, f"lot.{key}[{i}]", out)
            if poly is not None:
                getattr(lot, key).append(poly)
        if key == "parked" and len(polys) != occupied:
            _add(out, "structure", None, None,
                 f"lot.parked holds {len(polys)} cars but {occupied} slots are occupied")

    if "speed_limit" in raw:
        if _is_number(raw["speed_limit"]) and raw["speed_limit"] > 0:
            lot.speed_limit = float(raw["speed_limit"])
        else:
            _add(out, "structure", None, None,
                 f"lot.speed_limit: expected a positive number, found {raw['speed_limit']!r}")

    zones = raw.get("speed_zones", [])
    if not isinstance(zones, list):
        _add(out, "structure", None, None, "lot.speed_zones: expected a list")
        zones = []
    for i, z in enumerate(zones):
        where = f"lot.speed_zones[{i}]"
        if not isinstance(z, dict):
            _add(out, "structure", None, None, f"{where}: expected an object")
            continue
        zid = z.get("id")
        if not isinstance(zid, str):
            _add(out, "structure", None, None, f"{where}.id: expected a string, found {zid!r}")
        limit = z.get("limit")
        if not (_is_number(limit) and limit > 0):
            _add(out, "structure", None, None,
                 f"{where}.limit: expected a positive number, found {limit!r}")
            continue
        poly = _polygon(z.get("polygon"), f"{where}.polygon", out)
        if poly is not None:
            lot.zones.append((str(zid), poly, float(limit)))

    for key in ("entrances", "exits"):
        portals = raw.get(key, [])
        found: dict[str, Pose] = {}
        if not isinstance(portals, list):
            _add(out, "structure", None, None, f"lot.{key}: expected a list")
            portals = []
        for i, p in enumerate(portals):
            pid = p.get("id") if isinstance(p, dict) else None
            pose = _pose(p.get("pose")) if isinstance(p, dict) else None
            if not isinstance(pid, str) or pose is None:
                _add(out, "structure", None, None,
                     f"lot.{key}[{i}]: expected {{\"id\": ..., \"pose\": [x, y, theta]}}")
                continue
            found[pid] = pose
        if key == "entrances":
            lot.entrances = found if isinstance(raw.get(key), list) else None
        else:
            lot.exits = found
    return lot


def _samples(raw: Any, problems: list[str]) -> dict[str, np.ndarray] | None:
    if not isinstance(raw, dict):
        problems.append(f"samples: expected an object, found {_kind(raw)}")
        return None
    cols: dict[str, np.ndarray] = {}
    for key in SAMPLE_KEYS:
        col = raw.get(key)
        if not isinstance(col, list):
            problems.append(f"samples.{key}: expected a list of numbers, found {_kind(col)}")
            continue
        try:
            arr = np.asarray(col) if col else np.zeros(0)
        except (ValueError, TypeError):
            arr = np.zeros((0, 0))
        if arr.ndim != 1 or arr.dtype.kind not in "iuf":
            problems.append(f"samples.{key}: expected a list of numbers")
            continue
        arr = arr.astype(float)
        bad = np.flatnonzero(~(np.abs(arr) <= MAX_MAGNITUDE))
        if bad.size:
            problems.append(f"samples.{key}[{bad[0]}] is {arr[bad[0]]}, not a finite number"
                            + ("" if not np.isfinite(arr[bad[0]]) else
                               f" of at most {MAX_MAGNITUDE:g}"))
            continue
        cols[key] = arr
    if len(cols) < len(SAMPLE_KEYS):
        return None
    lengths = {key: len(arr) for key, arr in cols.items()}
    if len(set(lengths.values())) > 1:
        problems.append("samples: arrays of unequal length ("
                        + ", ".join(f"{k} {n}" for k, n in lengths.items()) + ")")
        return None
    t = cols["t"]
    step = np.flatnonzero(np.diff(t) <= 0)
    if step.size:
        i = int(step[0])
        problems.append(f"samples.t is not strictly increasing at index {i + 1} "
                        f"({t[i]:.6g} s, then {t[i + 1]:.6g} s)")
    gear = np.flatnonzero(~np.isin(cols["gear"], (-1.0, 0.0, 1.0)))
    if gear.size:
        problems.append(f"samples.gear[{gear[0]}] is {cols['gear'][gear[0]]:g}, "
                        "not -1, 0 or 1")
    return None if step.size or gear.size else cols


def _parse_vehicle(i: int, raw: Any, lot: _Lot, out: list[Violation]) -> _Vehicle | None:
    """The vehicle, or None (after reporting why) when its structure is broken."""
    if not isinstance(raw, dict):
        _add(out, "structure", None, None, f"vehicles[{i}]: expected an object")
        return None
    vid = raw.get("id")
    name = vid if isinstance(vid, str) and vid else f"vehicles[{i}]"
    problems: list[str] = [f"missing key {k!r}" for k in VEHICLE_KEYS if k not in raw]
    if "id" in raw and not (isinstance(vid, str) and vid):
        problems.append(f"id: expected a non-empty string, found {vid!r}")
    vtype = raw.get("type")
    dims: dict[str, float] = {}
    if isinstance(vtype, dict):
        if not isinstance(vtype.get("name"), str):
            problems.append("type.name: expected a string")
        for key in TYPE_NUMBERS:
            value = vtype.get(key)
            if not _is_number(value):
                problems.append(f"type.{key}: expected a number, found {value!r}")
            else:
                dims[key] = float(value)
        if len(dims) == len(TYPE_NUMBERS):
            if not 0 < dims["max_steer"] < math.pi / 2:
                problems.append(f"type.max_steer {dims['max_steer']} is not in (0, pi/2)")
            if dims["width"] <= 2 * SHRINK or dims["front"] + dims["rear"] <= 2 * SHRINK:
                problems.append("type: the footprint is empty")
            for key in TYPE_NUMBERS[3:]:
                if key != "max_steer" and dims[key] <= 0:
                    problems.append(f"type.{key} must be positive")
    elif "type" in raw:
        problems.append(f"type: expected an object, found {_kind(vtype)}")
    arrival = raw.get("arrival")
    if "arrival" in raw and not _is_number(arrival):
        problems.append(f"arrival: expected a number, found {arrival!r}")
    entrance = raw.get("entrance")
    if "entrance" in raw:
        if not isinstance(entrance, str):
            problems.append(f"entrance: expected a string, found {entrance!r}")
        elif lot.entrances is not None and entrance not in lot.entrances:
            problems.append(f"entrance {entrance!r} is not an entrance of the lot")
    slot = raw.get("slot")
    if "slot" in raw and slot is not None and not isinstance(slot, str):
        problems.append(f"slot: expected a string or null, found {slot!r}")
    status = raw.get("status")
    if "status" in raw and status not in STATUSES:
        problems.append(f"status {status!r} is not one of {', '.join(STATUSES)}")
    reason = raw.get("reason")
    if "reason" in raw and not isinstance(reason, str):
        problems.append(f"reason: expected a string, found {reason!r}")
    cols = _samples(raw["samples"], problems) if "samples" in raw else None
    for p in problems:
        _add(out, "structure", name, None, f"{name}: {p}")
    if problems or cols is None:
        return None
    return _Vehicle(i, name, status, slot, reason, float(arrival),
                    **{key: dims[key] for key in TYPE_NUMBERS}, **cols)


# ----------------------------------------------------------------------------- rules


def _check(data: Any, out: list[Violation], stats: dict[str, Any]) -> None:
    problem = _format_problem(data)
    if problem is not None:
        _add(out, "structure", None, None, problem)
        return
    lot = _guard(out, "the lot", _parse_lot, data["lot"], out) or _Lot()
    raw_vehicles = data["vehicles"]
    if not isinstance(raw_vehicles, list):
        _add(out, "structure", None, None,
             f"vehicles: expected a list, found {_kind(raw_vehicles)}")
        raw_vehicles = []
    stats["vehicles"] = len(raw_vehicles)
    vehicles: list[_Vehicle] = []
    seen: set[str] = set()
    last_arrival: tuple[str, float] | None = None
    for i, raw in enumerate(raw_vehicles):
        veh = _guard(out, f"vehicles[{i}]", _parse_vehicle, i, raw, lot, out)
        if isinstance(raw, dict) and isinstance(raw.get("id"), str):
            if raw["id"] in seen:
                _add(out, "structure", raw["id"], None,
                     f"{raw['id']}: the id is used by more than one vehicle")
            seen.add(raw["id"])
        if isinstance(raw, dict) and _is_number(raw.get("arrival")):
            name = raw["id"] if isinstance(raw.get("id"), str) else f"vehicles[{i}]"
            if last_arrival is not None and raw["arrival"] < last_arrival[1]:
                _add(out, "structure", name, None,
                     f"vehicles are not in arrival order: {name} (arrival "
                     f"{raw['arrival']:.2f} s) follows {last_arrival[0]} "
                     f"({last_arrival[1]:.2f} s)")
            last_arrival = (name, float(raw["arrival"]))
        if veh is not None:
            vehicles.append(veh)
    stats["vehicles_checked"] = len(vehicles)
    stats["samples"] = sum(v.n for v in vehicles)
    stats["intervals"] = sum(max(v.n - 1, 0) for v in vehicles)
    if not isinstance(data["metrics"], dict):
        _add(out, "structure", None, None, "metrics: expected an object")
    if not isinstance(data["settings"], dict):
        _add(out, "structure", None, None, "settings: expected an object")

    for veh in vehicles:
        if veh.n:
            _guard(out, f"the motion of {veh.id}", _check_motion, veh, lot, out)
    _guard(out, "the footprints", _check_footprints,
           [v for v in vehicles if v.n], lot, out, stats)
    _guard(out, "the final states", _check_final, vehicles, lot, out)
    if isinstance(data["metrics"], dict) and len(vehicles) == len(raw_vehicles):
        _guard(out, "the metrics", _check_metrics, data["metrics"], vehicles, out)


def _wrap(a: FloatArray) -> FloatArray:
    """Angles wrapped to [-pi, pi) [rad]."""
    return (a + np.pi) % (2 * np.pi) - np.pi


def _first(out: list[Violation], rule: str, veh: _Vehicle, mask: np.ndarray,
           describe: Callable[[int], str], what: str = "samples") -> None:
    """Report the first index where ``mask`` holds, and how many more there are."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return
    i = int(idx[0])
    more = f" ({idx.size - 1} more {what})" if idx.size > 1 else ""
    _add(out, rule, veh.id, veh.t[i], f"{veh.id}: {describe(i)}{more}")


def _check_motion(veh: _Vehicle, lot: _Lot, out: list[Violation]) -> None:
    """Rules 2-5 on one vehicle's samples: sampling, kinematics, speed, dynamics."""
    t, x, y, th, v, steer, gear = veh.t, veh.x, veh.y, veh.theta, veh.v, veh.steer, veh.gear
    if t[0] < veh.arrival - TIME_TOL:
        _add(out, "arrival", veh.id, t[0], f"{veh.id}: first sample at t={t[0]:.2f} s, "
             f"before its arrival at {veh.arrival:.2f} s")

    _first(out, "steer", veh, np.abs(steer) > veh.max_steer + STEER_TOL,
           lambda i: f"steer {steer[i]:.4f} rad at t={t[i]:.2f} s exceeds max_steer "
                     f"{veh.max_steer:.4f} rad")
    bad_v = (((gear == 1) & (v < -GEAR_SPEED_TOL)) | ((gear == -1) & (v > GEAR_SPEED_TOL))
             | ((gear == 0) & (np.abs(v) > GEAR_SPEED_TOL)))
    _first(out, "gear", veh, bad_v,
           lambda i: f"v={v[i]:.3f} m/s in gear {gear[i]:+.0f} at t={t[i]:.2f} s")

    # speed limit at every sample: type, lot, zones holding the rear axle
    zone = np.full(len(t), lot.speed_limit)
    for _zid, poly, limit in lot.zones:
        inside = shapely.contains_xy(poly, x, y)
        zone = np.where(inside, np.minimum(zone, limit), zone)
    top = np.where(v >= 0, veh.max_forward_speed, veh.max_reverse_speed)
    limit = np.minimum(top, zone)
    _first(out, "speed", veh, np.abs(v) > limit + SPEED_TOL,
           lambda i: f"|v|={abs(v[i]):.3f} m/s at t={t[i]:.2f} s exceeds the limit "
                     f"{limit[i]:.3f} m/s at ({x[i]:.2f}, {y[i]:.2f})")

    kappa = np.tan(steer) / veh.wheelbase  # signed curvature the steer drives [1/m]
    lateral = v * v * np.abs(kappa)
    _first(out, "lateral", veh, lateral > veh.max_lateral_accel + LATERAL_TOL,
           lambda i: f"v={v[i]:.3f} m/s at steer {steer[i]:.4f} rad (radius "
                     f"{1 / max(abs(kappa[i]), 1e-12):.2f} m) at t={t[i]:.2f} s: lateral "
                     f"acceleration {lateral[i]:.3f} m/s² exceeds max_lateral_accel "
                     f"{veh.max_lateral_accel:.3f} m/s²")
    if len(t) < 2:
        return

    dt, dx, dy = np.diff(t), np.diff(x), np.diff(y)
    dth = _wrap(np.diff(th))
    d = np.hypot(dx, dy)
    mean = th[:-1] + dth / 2
    c, s = np.cos(mean), np.sin(mean)
    along, across = dx * c + dy * s, -dx * s + dy * c

    still = ((np.abs(dx) <= STILL_TOL) & (np.abs(dy) <= STILL_TOL)
             & (np.abs(dth) <= STILL_TURN) & (v[:-1] == 0) & (v[1:] == 0)
             & (gear[:-1] == 0) & (gear[1:] == 0))
    _first(out, "sampling", veh, (dt > MAX_DT + TIME_TOL) & ~still,
           lambda i: f"samples {dt[i]:.3f} s apart from t={t[i]:.2f} s although it does "
                     f"not stand still (at most {MAX_DT} s)", "intervals")
    _first(out, "sampling", veh, d > MAX_STEP + STEP_TOL,
           lambda i: f"samples {d[i]:.3f} m apart from t={t[i]:.2f} s (at most {MAX_STEP} m)",
           "intervals")

    radius = veh.min_radius
    side_tol = SIDEWAYS_ABS + SIDEWAYS_REL * d + d * d / (4 * radius)
    _first(out, "sideways", veh, np.abs(across) > side_tol,
           lambda i: f"moves {abs(across[i]):.3f} m sideways between t={t[i]:.2f} and "
                     f"{t[i + 1]:.2f} s (allowed {side_tol[i]:.3f} m)", "intervals")
    turn_tol = d / radius * CURVATURE_REL + CURVATURE_ABS
    _first(out, "curvature", veh, np.abs(dth) > turn_tol,
           lambda i: f"turns {abs(dth[i]):.4f} rad over {d[i]:.3f} m between t={t[i]:.2f} "
                     f"and {t[i + 1]:.2f} s: radius {d[i] / max(abs(dth[i]), 1e-12):.2f} m "
                     f"< minimum {radius:.2f} m", "intervals")

    direction = np.sign(along)
    judged = np.abs(along) > GEAR_MIN_STEP
    g0, g1 = gear[:-1], gear[1:]
    moving0, moving1 = np.abs(v[:-1]) > GEAR_SPEED_TOL, np.abs(v[1:]) > GEAR_SPEED_TOL
    wrong = judged & ((moving0 & (g0 != direction)) | (moving1 & (g1 != direction))
                      | ((g0 != direction) & (g1 != direction)))
    _first(out, "gear", veh, wrong,
           lambda i: f"travels {'forward' if direction[i] > 0 else 'backward'} between "
                     f"t={t[i]:.2f} and {t[i + 1]:.2f} s in gear {g0[i]:+.0f}/{g1[i]:+.0f}",
           "intervals")

    reverse = (g0 == -1) | (g1 == -1)
    pair_top = np.where(reverse, veh.max_reverse_speed, veh.max_forward_speed)
    pair_limit = np.minimum(pair_top, np.maximum(zone[:-1], zone[1:]))
    chord_speed = d / dt
    allowed = (pair_limit * CHORD_SPEED_REL + SPEED_TOL) * dt + CHORD_SLACK
    _first(out, "speed", veh, d > allowed,
           lambda i: f"covers {d[i]:.3f} m in {dt[i]:.3f} s from t={t[i]:.2f} s "
                     f"({chord_speed[i]:.3f} m/s), limit {pair_limit[i]:.3f} m/s",
           "intervals")

    _check_dynamics(veh, out, kappa, d, dth, direction)


def _check_dynamics(veh: _Vehicle, out: list[Violation], kappa: FloatArray, d: FloatArray,
                    dth: FloatArray, direction: FloatArray) -> None:
    """Rules heading, steer_rate, accel and jerk on consecutive samples (rules 3 and 5).

    ``kappa`` is the curvature the steer drives at each sample, ``d``, ``dth`` and
    ``direction`` the chord length, the wrapped heading change and the sign of the chord
    along the mean heading of each interval.
    """
    t, v, steer = veh.t, veh.v, veh.steer
    dt = np.diff(t)

    # heading: the single-track model turns by the curvature integrated over the arc
    # driven. The arc length is recovered from the chord as for a circular arc,
    # s = d / sinc(Δθ / 2) (Δθ is wrapped, so the factor is at most π / 2); the trapezoid
    # rule on the end curvatures is exact for a curvature linear in arc length.
    s = d / np.sinc(dth / (2 * np.pi))
    k0, k1 = kappa[:-1], kappa[1:]
    predicted = direction * s * (k0 + k1) / 2
    # between samples the curvature may also bend back (a V: a clothoid down, one up), so
    # the trapezoid may miss a dip; a steer within its rate moves the curvature at most
    # K = max_steer_rate / (b cos² φ) per second, and any curvature with |dκ/dt| ≤ K
    # stays within K·Δt/2 of the straight line between its end values
    reach = np.maximum(np.abs(steer[:-1]), np.abs(steer[1:])) + veh.max_steer_rate * dt / 2
    k_rate = veh.max_steer_rate / (veh.wheelbase * np.cos(np.minimum(reach, 1.5)) ** 2)
    turn_tol = (HEADING_ABS + HEADING_CHORD * (np.abs(k0) + np.abs(k1)) / 2
                + s * np.maximum(HEADING_KINK * np.abs(k1 - k0), k_rate * dt / 2)
                + HEADING_REL * np.abs(predicted))
    _first(out, "heading", veh, np.abs(dth - predicted) > turn_tol,
           lambda i: f"turns {dth[i]:+.5f} rad over {d[i]:.3f} m between t={t[i]:.2f} and "
                     f"{t[i + 1]:.2f} s, but its steer ({steer[i]:.4f}, {steer[i + 1]:.4f} "
                     f"rad) turns it {predicted[i]:+.5f} rad (allowed ±{turn_tol[i]:.5f})",
           "intervals")

    # steer_rate: the road wheels turn at most max_steer_rate, standing or moving
    dsteer = np.diff(steer)
    fast = np.abs(dsteer) > veh.max_steer_rate * dt + STEER_RATE_TOL
    _first(out, "steer_rate", veh, fast,
           lambda i: f"steer changes {dsteer[i]:+.5f} rad in {dt[i]:.6f} s from t={t[i]:.2f} "
                     f"s ({abs(dsteer[i]) / dt[i]:.3f} rad/s), more than max_steer_rate "
                     f"{veh.max_steer_rate:.3f} rad/s", "intervals")

    # accel: by the mean value theorem (|v1| - |v0|) / dt is d|v|/dt somewhere in between,
    # where the car speeds up (limit max_accel) or slows down (max_brake)
    speed = np.abs(v)
    dspeed = np.diff(speed)
    flips = v[:-1] * v[1:] < 0
    up = ~flips & (dspeed > veh.max_accel * dt + ACCEL_TOL)
    down = ~flips & (-dspeed > veh.max_brake * dt + ACCEL_TOL)
    _first(out, "accel", veh, up,
           lambda i: f"speeds up from |v|={speed[i]:.4f} to {speed[i + 1]:.4f} m/s in "
                     f"{dt[i]:.6f} s from t={t[i]:.2f} s ({dspeed[i] / dt[i]:.3f} m/s²), "
                     f"more than max_accel {veh.max_accel:.3f} m/s²", "intervals")
    _first(out, "accel", veh, down,
           lambda i: f"slows from |v|={speed[i]:.4f} to {speed[i + 1]:.4f} m/s in "
                     f"{dt[i]:.6f} s from t={t[i]:.2f} s ({-dspeed[i] / dt[i]:.3f} m/s²), "
                     f"more than max_brake {veh.max_brake:.3f} m/s²", "intervals")
    # a change of direction between two samples passes through a stop
    need = (np.maximum(speed[:-1] - ACCEL_TOL, 0) / veh.max_brake
            + np.maximum(speed[1:] - ACCEL_TOL, 0) / veh.max_accel)
    _first(out, "accel", veh, flips & (need > dt),
           lambda i: f"goes from v={v[i]:.4f} to {v[i + 1]:.4f} m/s in {dt[i]:.6f} s from "
                     f"t={t[i]:.2f} s; stopping and starting again takes at least "
                     f"{need[i]:.4f} s at max_brake and max_accel", "intervals")

    # jerk: for a speed with a continuous acceleration whose derivative (the jerk) is
    # bounded, 2 · v[t0, t1, t2] is a weighted mean of the jerk over [t0, t2] (the Peano
    # kernel of a second divided difference is a positive B-spline of integral 1/2), hence
    # at most max_jerk in size. Samples a few µs apart would let rounding dominate (its
    # error grows as 1 / h²), so the speeds are thinned to at least JERK_MIN_DT apart.
    keep = _thin(t, JERK_MIN_DT)
    if len(keep) < 3:
        return
    tk, vk = t[keep], v[keep]
    h = np.diff(tk)
    slope = np.diff(vk) / h
    span = tk[2:] - tk[:-2]
    jerk = 2 * np.diff(slope) / span
    # rounding: each speed is off by up to V_ROUND and each time by up to T_ROUND, so a
    # slope over h is off by up to (2 V_ROUND + 2 T_ROUND |slope|) / h (to first order)
    # and twice the difference of two slopes over the span by 2 (e01 + e12) / span
    err = (2 * V_ROUND + 2 * T_ROUND * np.abs(slope)) / h
    jerk_tol = 2 * (err[:-1] + err[1:]) / (span - 2 * T_ROUND)
    mask = np.zeros(len(t), dtype=bool)
    bad = np.abs(jerk) > veh.max_jerk + jerk_tol
    middle = keep[1:-1]
    mask[middle[bad]] = True

    def describe(i: int) -> str:
        j = int(np.searchsorted(middle, i))
        return (f"jerk about {jerk[j]:+.2f} m/s³ around t={t[i]:.2f} s (from v="
                f"{vk[j]:.4f}, {vk[j + 1]:.4f}, {vk[j + 2]:.4f} m/s at t={tk[j]:.6f}, "
                f"{tk[j + 1]:.6f}, {tk[j + 2]:.6f} s), more than max_jerk "
                f"{veh.max_jerk:.3f} m/s³ (+{jerk_tol[j]:.3f} for rounding)")

    _first(out, "jerk", veh, mask, describe)


def _thin(t: FloatArray, min_dt: float) -> np.ndarray:
    """Indices of the samples kept for the jerk test: the first and every one at least
    ``min_dt`` after the sample before it, so consecutive kept samples are at least
    ``min_dt`` apart; the last is always kept, in place of the kept one before it when
    it was dropped (``t`` strictly increasing)."""
    keep = np.concatenate([[0], np.flatnonzero(np.diff(t) >= min_dt) + 1])
    last = len(t) - 1
    if keep[-1] != last:
        if len(keep) > 1:
            keep[-1] = last  # further from keep[-2] than the one it replaces
        else:
            keep = np.append(keep, last)
    return keep.astype(int)


# ------------------------------------------------------------------------ footprints


@dataclass(slots=True)
class _Items:
    """Footprints over the instant grid: one per moving vehicle-instant, one per standing
    stretch ``[ka, kb]`` (instant indices, ``ka == kb`` for a moving one)."""

    veh: np.ndarray  # index into the vehicle list
    ka: np.ndarray
    kb: np.ndarray
    cx: FloatArray  # rectangle centre [m]
    cy: FloatArray
    ux: FloatArray  # heading unit vector
    uy: FloatArray
    hx: FloatArray  # true half length and half width [m]
    hy: FloatArray

    def __len__(self) -> int:
        return len(self.veh)

    @property
    def reach(self) -> FloatArray:
        """Circumradius of the shrunk rectangle [m]."""
        return np.hypot(self.hx - SHRINK, self.hy - SHRINK)

    def corners(self, idx: np.ndarray, inset: float = SHRINK) -> np.ndarray:
        """(N, 4, 2) corners of footprints ``idx``, each side moved in by ``inset`` [m]."""
        cx, cy, ux, uy = self.cx[idx], self.cy[idx], self.ux[idx], self.uy[idx]
        ax, ay = ux * (self.hx[idx] - inset), uy * (self.hx[idx] - inset)
        bx, by = -uy * (self.hy[idx] - inset), ux * (self.hy[idx] - inset)
        xs = np.stack([cx - ax - bx, cx + ax - bx, cx + ax + bx, cx - ax + bx], axis=1)
        ys = np.stack([cy - ay - by, cy + ay - by, cy + ay + by, cy - ay + by], axis=1)
        return np.stack([xs, ys], axis=-1)

    def polygons(self, idx: np.ndarray, inset: float = SHRINK) -> np.ndarray:
        return shapely.polygons(self.corners(idx, inset))


def _instant_range(t0: float, t1: float) -> tuple[int, int]:
    """First and last grid instant index within [t0, t1] [s] (empty when first > last)."""
    return math.ceil(t0 / GRID_DT - 1e-9), math.floor(t1 / GRID_DT + 1e-9)


def _build_items(vehicles: list[_Vehicle], kmax: int) -> _Items:
    cols: dict[str, list[np.ndarray]] = {k: [] for k in ("veh", "ka", "kb", "x", "y", "th")}
    for j, veh in enumerate(vehicles):
        k0, k1 = _instant_range(veh.t[0], veh.t[-1])
        kend = k1 if veh.status == "departed" else kmax
        theta = np.unwrap(veh.theta)
        last = (veh.x[-1], veh.y[-1], theta[-1])
        if k1 >= k0:
            ks = np.arange(k0, k1 + 1)
            tk = ks * GRID_DT
            px, py = np.interp(tk, veh.t, veh.x), np.interp(tk, veh.t, veh.y)
            pth = np.interp(tk, veh.t, theta)
            change = ((np.abs(np.diff(px)) > _SAME) | (np.abs(np.diff(py)) > _SAME)
                      | (np.abs(np.diff(pth)) > _SAME))
            starts = np.concatenate([[0], np.flatnonzero(change) + 1])
            ends = np.concatenate([starts[1:] - 1, [len(ks) - 1]])
            ka, kb = ks[starts], ks[ends].copy()
            x, y, th = px[starts], py[starts], pth[starts]
            if kend > k1:
                if max(abs(px[-1] - last[0]), abs(py[-1] - last[1]),
                       abs(pth[-1] - last[2])) <= _SAME:
                    kb[-1] = kend
                else:
                    ka, kb = np.append(ka, k1 + 1), np.append(kb, kend)
                    x, y, th = np.append(x, last[0]), np.append(y, last[1]), np.append(th,
                                                                                       last[2])
        elif kend >= k0:  # no instant while sampled, but it stays at its last pose
            ka, kb = np.array([k0]), np.array([kend])
            x, y, th = np.array([last[0]]), np.array([last[1]]), np.array([last[2]])
        else:
            continue
        cols["veh"].append(np.full(len(ka), j))
        for key, arr in (("ka", ka), ("kb", kb), ("x", x), ("y", y), ("th", th)):
            cols[key].append(arr)
    if not cols["veh"]:
        empty = np.zeros(0)
        return _Items(*(empty.astype(int),) * 3, *(empty,) * 6)
    veh_idx = np.concatenate(cols["veh"])
    ka, kb = np.concatenate(cols["ka"]), np.concatenate(cols["kb"])
    x, y, th = (np.concatenate(cols[k]) for k in ("x", "y", "th"))
    front = np.array([v.front for v in vehicles])[veh_idx]
    rear = np.array([v.rear for v in vehicles])[veh_idx]
    width = np.array([v.width for v in vehicles])[veh_idx]
    ux, uy = np.cos(th), np.sin(th)
    off = (front - rear) / 2
    return _Items(veh_idx, ka, kb, x + ux * off, y + uy * off, ux, uy, (front + rear) / 2,
                  width / 2)


def _expand(lo: np.ndarray, hi: np.ndarray) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Batches of (row, position) for every position in ``[lo[row], hi[row])``."""
    counts = np.maximum(hi - lo, 0)
    cum = np.cumsum(counts)
    start = 0
    while start < len(lo):
        base = cum[start - 1] if start else 0
        stop = max(int(np.searchsorted(cum, base + _PAIR_BUDGET, side="right")), start + 1)
        n = counts[start:stop]
        if n.sum():
            row = np.repeat(np.arange(start, stop), n)
            pos = (np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
                   + np.repeat(lo[start:stop], n))
            yield row, pos
        start = stop


def _rects_overlap(items: _Items, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Whether shrunk footprints ``a[i]`` and ``b[i]`` intersect (separating axes)."""
    tx, ty = items.cx[b] - items.cx[a], items.cy[b] - items.cy[a]
    uax, uay, ubx, uby = items.ux[a], items.uy[a], items.ux[b], items.uy[b]
    hax, hay = items.hx[a] - SHRINK, items.hy[a] - SHRINK
    hbx, hby = items.hx[b] - SHRINK, items.hy[b] - SHRINK
    cos = np.abs(uax * ubx + uay * uby)  # |ua·ub| = |va·vb|
    sin = np.abs(uax * uby - uay * ubx)  # |ua·vb| = |va·ub|
    apart = np.abs(tx * uax + ty * uay) > hax + hbx * cos + hby * sin
    apart |= np.abs(-tx * uay + ty * uax) > hay + hbx * sin + hby * cos
    apart |= np.abs(tx * ubx + ty * uby) > hbx + hax * cos + hay * sin
    apart |= np.abs(-tx * uby + ty * ubx) > hby + hax * sin + hay * cos
    return ~apart


class _FirstOverlaps:
    """The first instant found so far at which each pair of vehicles overlaps.

    Pairs are keyed ``low · n + high`` by vehicle index; a candidate at an instant no
    earlier than the one known for its pair is dropped before the exact test, so a result
    whose vehicles overlap for minutes costs little more than a clean one.
    """

    def __init__(self, n_vehicles: int):
        self.n = n_vehicles
        self.key = np.zeros(0, dtype=np.int64)  # sorted
        self.k = np.zeros(0, dtype=np.int64)
        self.a = np.zeros(0, dtype=np.int64)  # the two footprints (item indices)
        self.b = np.zeros(0, dtype=np.int64)

    def pair_key(self, va: np.ndarray, vb: np.ndarray) -> np.ndarray:
        return np.minimum(va, vb).astype(np.int64) * self.n + np.maximum(va, vb)

    def news(self, key: np.ndarray, k: np.ndarray) -> np.ndarray:
        """Which candidates could still be the first overlap of their pair."""
        if not len(self.key):
            return np.ones(len(key), dtype=bool)
        pos = np.minimum(np.searchsorted(self.key, key), len(self.key) - 1)
        return ~((self.key[pos] == key) & (self.k[pos] <= k))

    def add(self, key: np.ndarray, k: np.ndarray, a: np.ndarray, b: np.ndarray) -> None:
        key, k = np.concatenate([self.key, key]), np.concatenate([self.k, k])
        a, b = np.concatenate([self.a, a]), np.concatenate([self.b, b])
        keep = _first_per_key(key[:, None], k)
        keep = keep[np.argsort(key[keep], kind="stable")]
        self.key, self.k, self.a, self.b = key[keep], k[keep], a[keep], b[keep]


def _test_pairs(items: _Items, a: np.ndarray, b: np.ndarray, k: np.ndarray,
                found: _FirstOverlaps, stats: dict[str, Any]) -> None:
    """Record the candidate pairs ``(a, b)`` at instants ``k`` that overlap in ``found``."""
    va, vb = items.veh[a], items.veh[b]
    reach = items.reach
    keep = (va != vb) & (np.hypot(items.cx[a] - items.cx[b], items.cy[a] - items.cy[b])
                         <= reach[a] + reach[b])
    a, b, k = a[keep], b[keep], k[keep]
    key = found.pair_key(items.veh[a], items.veh[b])
    keep = found.news(key, k)
    a, b, k, key = a[keep], b[keep], k[keep], key[keep]
    stats["footprint_tests"] += len(a)
    hit = _rects_overlap(items, a, b)
    if hit.any():
        found.add(key[hit], k[hit], a[hit], b[hit])


def _vehicle_overlaps(items: _Items, n_vehicles: int, stats: dict[str, Any]) -> _FirstOverlaps:
    """The first instant, and the footprints, of every pair of vehicles that overlap."""
    found = _FirstOverlaps(n_vehicles)
    if len(items) < 2:
        return found
    reach = 2 * float(items.reach.max())
    moving = np.flatnonzero(items.ka == items.kb)
    standing = np.flatnonzero(items.ka < items.kb)
    kmin = int(items.ka.min())

    # moving with moving: sort and sweep along x within bands `reach` high, each band and
    # instant shifted far apart along x; a footprint meets its own band and the next one
    if len(moving) > 1:
        cx = items.cx[moving]
        width = float(cx.max() - cx.min()) + 2 * reach + 1.0
        band = np.floor((items.cy[moving] - items.cy[moving].min()) / reach)
        bands = float(band.max()) + 2
        key = ((items.ka[moving] - kmin) * bands + band) * width + cx
        order = np.argsort(key, kind="stable")
        sorted_key, ids = key[order], moving[order]
        own = (np.arange(len(ids)) + 1,
               np.searchsorted(sorted_key, sorted_key + reach, side="right"))
        above = (np.searchsorted(sorted_key, sorted_key + width - reach, side="left"),
                 np.searchsorted(sorted_key, sorted_key + width + reach, side="right"))
        for lo, hi in (own, above):
            for row, pos in _expand(lo, hi):
                a = ids[row]
                _test_pairs(items, a, ids[pos], items.ka[a], found, stats)

    # standing with moving: moving footprints binned in cells of size `reach`, sorted by
    # (cell, instant), so each standing stretch meets a contiguous run per neighbour cell
    if len(standing) and len(moving):
        x0, y0 = float(items.cx.min()), float(items.cy.min())
        ix = np.floor((items.cx - x0) / reach).astype(np.int64)
        iy = np.floor((items.cy - y0) / reach).astype(np.int64)
        rows = int(iy.max()) + 3
        span = int(items.kb.max()) - kmin + 1
        cell = (ix + 1) * rows + (iy + 1)
        key = cell[moving] * span + (items.ka[moving] - kmin)
        order = np.argsort(key, kind="stable")
        sorted_key, ids = key[order], moving[order]
        shifts = np.array([dx * rows + dy for dx in (-1, 0, 1) for dy in (-1, 0, 1)])
        near_cells = (cell[standing][:, None] + shifts[None, :]).ravel()
        owner = np.repeat(standing, len(shifts))
        lo = np.searchsorted(sorted_key, near_cells * span + (items.ka[owner] - kmin), "left")
        hi = np.searchsorted(sorted_key, near_cells * span + (items.kb[owner] - kmin), "right")
        for row, pos in _expand(lo, hi):
            b = ids[pos]
            _test_pairs(items, owner[row], b, items.ka[b], found, stats)

    # standing with standing: sweep along x, then the stretches must share an instant
    if len(standing) > 1:
        cx = items.cx[standing]
        order = np.argsort(cx, kind="stable")
        sorted_cx, ids = cx[order], standing[order]
        hi = np.searchsorted(sorted_cx, sorted_cx + reach, side="right")
        lo = np.arange(len(ids)) + 1
        for row, pos in _expand(lo, hi):
            a, b = ids[row], ids[pos]
            start = np.maximum(items.ka[a], items.ka[b])
            together = start <= np.minimum(items.kb[a], items.kb[b])
            _test_pairs(items, a[together], b[together], start[together], found, stats)
    return found


def _first_per_key(keys: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Indices of the smallest ``k`` for each distinct row of ``keys`` (N, m)."""
    if len(k) == 0:
        return np.zeros(0, dtype=int)
    order = np.lexsort((k, *keys.T[::-1]))
    sk = keys[order]
    first = np.ones(len(order), dtype=bool)
    first[1:] = np.any(sk[1:] != sk[:-1], axis=1)
    return order[first]


def _check_footprints(vehicles: list[_Vehicle], lot: _Lot, out: list[Violation],
                      stats: dict[str, Any]) -> None:
    """Rule 6 (overlap, parked, obstacle, boundary) and slot sharing (rule 7)."""
    if not vehicles:
        return
    kmin, kmax = _instant_range(min(v.t[0] for v in vehicles), max(v.t[-1] for v in vehicles))
    spans = sum(max(k1 - k0 + 1, 0)
                for k0, k1 in (_instant_range(v.t[0], v.t[-1]) for v in vehicles))
    if spans > MAX_INSTANTS:
        _add(out, "internal", None, None, f"the vehicles are sampled over {spans} "
             f"vehicle-instants, more than the {MAX_INSTANTS} the footprint rules handle")
        return
    items = _build_items(vehicles, kmax)
    stats["instants"] = max(kmax - kmin + 1, 0)
    stats["footprints"] = len(items)
    stats["vehicle_instants"] = int((items.kb - items.ka + 1).sum())
    if not len(items):
        return
    ids = [v.id for v in vehicles]

    # vehicle with vehicle
    found = _vehicle_overlaps(items, len(vehicles), stats)
    for i in np.argsort(found.k, kind="stable"):
        k = int(found.k[i])
        first, second = sorted((int(found.a[i]), int(found.b[i])),
                               key=lambda it: ids[items.veh[it]])
        area = shapely.area(shapely.intersection(
            *items.polygons(np.array([first, second]), inset=0.0)))
        _add(out, "overlap", ids[items.veh[first]], k * GRID_DT,
             f"{ids[items.veh[first]]} and {ids[items.veh[second]]} overlap at "
             f"t={k * GRID_DT:.2f} s ({area:.2f} m²)")

    reach = float(items.reach.max())
    margin = reach * 1.05 + 0.05  # covers the polygonal approximation of buffer arcs
    # with the cars parked at start and the obstacles
    env = [("parked", i, p) for i, p in enumerate(lot.parked)]
    env += [("obstacle", i, p) for i, p in enumerate(lot.obstacles)]
    if env:
        region = shapely.union_all([p for _, _, p in env]).buffer(margin)
        shapely.prepare(region)
        near = np.flatnonzero(shapely.intersects_xy(region, items.cx, items.cy))
        tree = shapely.STRtree([p for _, _, p in env])
        q_item, q_env = tree.query(items.polygons(near), predicate="intersects")
        stats["footprint_tests"] += len(near)
        item = near[q_item]
        keys = np.stack([items.veh[item], q_env], axis=1)
        for i in _first_per_key(keys, items.ka[item]):
            it, (kind, j, poly) = int(item[i]), env[int(q_env[i])]
            k = int(items.ka[it])
            foot = items.polygons(np.array([it]), inset=0.0)[0]
            area = shapely.area(shapely.intersection(foot, poly))
            what = (f"the car parked at start lot.parked[{j}]" if kind == "parked"
                    else f"obstacle lot.obstacles[{j}]")
            name = ids[items.veh[it]]
            _add(out, kind, name, k * GRID_DT,
                 f"{name} overlaps {what} at t={k * GRID_DT:.2f} s ({area:.2f} m²)")

    # inside the boundary
    if lot.boundary is not None:
        inner = lot.boundary.buffer(-margin)
        sure = np.zeros(len(items), dtype=bool)
        if not inner.is_empty:
            shapely.prepare(inner)
            sure = shapely.contains_xy(inner, items.cx, items.cy)
        unsure = np.flatnonzero(~sure)
        shapely.prepare(lot.boundary)
        polys = items.polygons(unsure)
        stats["footprint_tests"] += len(unsure)
        outside = unsure[~shapely.covers(lot.boundary, polys)]
        for i in _first_per_key(items.veh[outside][:, None], items.ka[outside]):
            it = int(outside[i])
            k = int(items.ka[it])
            foot = items.polygons(np.array([it]), inset=0.0)[0]
            area = shapely.area(shapely.difference(foot, lot.boundary))
            name = ids[items.veh[it]]
            _add(out, "boundary", name, k * GRID_DT,
                 f"{name} leaves the lot boundary at t={k * GRID_DT:.2f} s "
                 f"({area:.2f} m² outside)")

    _check_slot_sharing(vehicles, items, lot, kmax, out, stats)


def _check_slot_sharing(vehicles: list[_Vehicle], items: _Items, lot: _Lot, kmax: int,
                        out: list[Violation], stats: dict[str, Any]) -> None:
    """No two vehicles hold one slot at the same instant."""
    holders: dict[str, list[int]] = {}
    for j, veh in enumerate(vehicles):
        if veh.slot in lot.slots:
            holders.setdefault(veh.slot, []).append(j)
    for sid, members in holders.items():
        if len(members) < 2:
            continue
        poly = lot.slots[sid].polygon
        shapely.prepare(poly)
        cand = np.flatnonzero(np.isin(items.veh, members)
                              & shapely.intersects_xy(poly, items.cx, items.cy))
        stats["footprint_tests"] += len(cand)
        inside = cand[shapely.covers(poly, items.polygons(cand))]
        held: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        for j in members:
            mine = inside[items.veh[inside] == j]
            ka, kb = items.ka[mine], items.kb[mine]
            veh = vehicles[j]
            if veh.status == "parked":
                k_end = min(_instant_range(veh.t[-1], veh.t[-1])[0], kmax)
                ka, kb = np.append(ka, k_end), np.append(kb, kmax)
            held[j] = (ka, kb)
        clashes = []
        for n, j in enumerate(members):
            for m in members[n + 1:]:
                (a0, a1), (b0, b1) = held[j], held[m]
                if not len(a0) or not len(b0):
                    continue
                lo = np.maximum(a0[:, None], b0[None, :])
                common = lo[lo <= np.minimum(a1[:, None], b1[None, :])]
                if common.size:
                    clashes.append((int(common.min()), j, m))
        for k, j, m in sorted(clashes):
            a, b = vehicles[j].id, vehicles[m].id
            _add(out, "slot", a, k * GRID_DT,
                 f"slot {sid} is held by {a} and {b} at once from t={k * GRID_DT:.2f} s")


# ---------------------------------------------------------------------- final states


def _check_final(vehicles: list[_Vehicle], lot: _Lot, out: list[Violation]) -> None:
    """Rule 7 per vehicle: slot, exit, reason, status."""
    for veh in vehicles:
        name, status = veh.id, veh.status
        if status in ("waiting", "rejected") and not veh.reason.strip():
            _add(out, "reason", name, None, f"{name} is {status} but gives no reason")
        if status in ("parked", "departed") and veh.reason.strip():
            _add(out, "reason", name, None,
                 f"{name} is {status} but gives a reason ({veh.reason!r}); it must be empty")
        if status == "rejected" and veh.n:
            _add(out, "status", name, veh.t[0],
                 f"{name} is rejected (never entered) but has {veh.n} samples")
        if status in ("parked", "departed") and not veh.n:
            _add(out, "status", name, None, f"{name} is {status} but has no samples")
        if veh.slot is not None and veh.slot not in lot.slots:
            _add(out, "slot", name, None, f"{name}: slot {veh.slot!r} is not a slot of the lot")
        if status == "parked" and veh.n:
            _check_parked(veh, lot, out)
        if status == "departed" and veh.n:
            _check_exit(veh, lot, out)


def _check_parked(veh: _Vehicle, lot: _Lot, out: list[Violation]) -> None:
    name, t_end = veh.id, veh.t[-1]
    if veh.slot is None:
        _add(out, "slot", name, t_end, f"{name} is parked but has no slot")
        return
    slot = lot.slots.get(veh.slot)
    if slot is None:
        return  # reported by _check_final
    if slot.occupied:
        _add(out, "slot", name, t_end,
             f"{name} is parked in slot {slot.id}, which was occupied at start")
    x, y, th = veh.x[-1], veh.y[-1], veh.theta[-1]
    u, w = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th), math.cos(th)])
    a0, a1 = -veh.rear + SHRINK, veh.front - SHRINK
    b = veh.width / 2 - SHRINK
    corners = [np.array([x, y]) + u * a + w * c for a, c in ((a0, -b), (a1, -b), (a1, b),
                                                               (a0, b))]
    foot = shapely.Polygon(corners)
    if not shapely.covers(slot.polygon, foot):
        outside = shapely.area(shapely.difference(foot, slot.polygon))
        _add(out, "slot", name, t_end,
             f"{name} ends at ({x:.2f}, {y:.2f}, {th:.3f}) with its footprint not within "
             f"slot {slot.id} ({outside:.2f} m² outside)")
    if abs(veh.v[-1]) > REST_SPEED:
        _add(out, "slot", name, t_end,
             f"{name} is parked but still moves at its last sample (v={veh.v[-1]:.3f} m/s)")


def _check_exit(veh: _Vehicle, lot: _Lot, out: list[Violation]) -> None:
    name = veh.id
    x, y, th = veh.x[-1], veh.y[-1], veh.theta[-1]
    best: tuple[float, str, float] | None = None
    for eid, (ex, ey, eth) in lot.exits.items():
        dist = math.hypot(x - ex, y - ey)
        turn = abs(float(_wrap(np.array(th - eth))))
        if dist <= EXIT_DISTANCE and turn <= EXIT_HEADING:
            return
        if best is None or dist < best[0]:
            best = (dist, eid, turn)
    where = (f"{best[0]:.2f} m and {best[2]:.3f} rad from exit {best[1]}" if best
             else "the lot has no exit")
    _add(out, "exit", name, veh.t[-1],
         f"{name} departed at ({x:.2f}, {y:.2f}, {th:.3f}), {where} "
         f"(at most {EXIT_DISTANCE} m and {EXIT_HEADING} rad)")


def _check_metrics(metrics: dict, vehicles: list[_Vehicle], out: list[Violation]) -> None:
    counts = Counter(v.status for v in vehicles)
    expected = {s: counts[s] for s in STATUSES} | {"vehicles": len(vehicles)}
    for key, n in expected.items():
        got = metrics.get(key)
        if not (isinstance(got, int) and not isinstance(got, bool)):
            _add(out, "metrics", None, None, f"metrics.{key}: expected a count, found {got!r}")
        elif got != n:
            what = "vehicles" if key == "vehicles" else f"vehicles with status {key!r}"
            _add(out, "metrics", None, None, f"metrics.{key} is {got} but there are {n} {what}")
    makespan = metrics.get("makespan")
    ends = [v.t[-1] for v in vehicles if v.n]
    if "makespan" in metrics and not _is_number(makespan):
        _add(out, "metrics", None, None,
             f"metrics.makespan: expected a number of seconds, found {makespan!r}")
    elif _is_number(makespan) and ends and abs(makespan - max(ends)) > MAKESPAN_TOL:
        _add(out, "metrics", None, None,
             f"metrics.makespan is {makespan:.3f} s but the last sample is at "
             f"{max(ends):.3f} s")
