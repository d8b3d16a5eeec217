"""An independent verifier of ``result.json``, the output of ``lotsim run``.

The checker reads only the result (see ``docs/result.md``) and shares no code with the
planners, the simulator or the geometry of lotsim: it imports nothing from the package
but an error type (:class:`lotsim.errors.ResultFormatError`), and re-derives every quantity
it judges from the numbers in the file — footprint rectangles from the vehicle type's
``width``, ``front`` and ``rear`` and the rear-axle pose, headings, curvatures and speeds
from consecutive samples. A bug in the planners can therefore not hide itself by being
repeated here.

The package holds the checker in the order it works: :mod:`~lotsim.verify.tolerances` (the
format and the constants below), :mod:`~lotsim.verify.reading` (:func:`read_result` and the
``structure`` rule), :mod:`~lotsim.verify.motion` (the rules on one vehicle's samples),
:mod:`~lotsim.verify.footprints` (the rules on footprints over the common instants),
:mod:`~lotsim.verify.final` (how each vehicle ends, the metrics),
:mod:`~lotsim.verify.report` (:class:`Violation`, :class:`CheckReport`) and
:mod:`~lotsim.verify.checker` (:func:`check_result`, the stages in order).
:mod:`~oracles.reference_footprints` checks the footprint rules the straightforward way, one
instant at a time, for the tests and the benchmark to hold the fast path against.

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
overlap, parked, obstacle, access_aisle, boundary, pavement
    Footprints shrunk by ``SHRINK`` = 1 cm on every side are compared at the common
    instants ``k · GRID_DT`` (0.05 s) from the earliest to the latest sample, poses
    interpolated linearly between samples (heading the short way). A vehicle is present
    from its first to its last sample; a ``departed`` one is gone afterwards, any other
    stays at its last pose to the end. No two present footprints intersect (touching
    shrunk rectangles count: the true ones then overlap by 2 cm), none intersects a car
    parked at start (``parked``), an obstacle (``obstacle``) or an access aisle beside an
    accessible bay (``access_aisle``, ``lot.access_aisles``), each is covered by the
    lot boundary (``boundary``) and, where the lot says what is paved (``lot.paved``), by
    the pavement (``pavement``). Each pair is reported once, at its first instant.
slot
    A ``parked`` vehicle names a slot of the lot that was free at start, its last
    footprint (shrunk) lies within that slot, and it is at rest (``|v| ≤ REST_SPEED``).
    A vehicle holds its slot at every instant its shrunk footprint lies within it, and a
    ``parked`` one from its last sample to the end; no two vehicles hold one slot at once.
bay_use
    A ``parked`` or ``departed`` vehicle's slot is one its type may use
    (``docs/scenario.md``): an accessible or van-accessible bay takes only a type whose
    ``type.marks`` hold ``accessible``, an EV bay ``ev``, a motorcycle bay
    ``motorcycle``; a compact bay only a type no longer (``front + rear``) and no wider
    than the bay (its longer side, and its area over that).
exit
    A ``departed`` vehicle's last pose is within ``EXIT_DISTANCE`` = 0.5 m and
    ``EXIT_HEADING`` = 0.1 rad of an exit's pose.
stall
    In a run driven through disturbances (``disturbances.stalls``), a stalled car has
    samples over the whole stall and stands still throughout it: its pose at the stall's
    ends and at every sample between the same within ``STILL_TOL`` and ``STILL_TURN``,
    its speed within ``GEAR_SPEED_TOL`` of 0.
closure, taken
    No car but those listed ``inside`` a closure (``disturbances.closures``) has its
    footprint, shrunk by ``SHRINK``, on the closed ground from the closure's ``t0`` up to
    its ``t1`` (not at it: a car may come on as it opens); no car's footprint meets the car
    in a bay taken from outside (``disturbances.taken``) from its ``t`` on. Both at the
    common instants and at every sample, a vehicle that has not departed standing at its
    last pose after its last sample.
status, reason, arrival, metrics
    A ``rejected`` vehicle has no samples, a ``parked`` or ``departed`` one has some;
    ``waiting`` and ``rejected`` vehicles give a reason, the others none; no sample
    before the vehicle's arrival (``TIME_TOL``); the status counts (and ``makespan``, within
    ``MAKESPAN_TOL`` = 1e-3 s) in ``metrics`` match the vehicles.

A problem the checker itself runs into is reported as the rule ``internal``, never
raised. Vehicle-vehicle tests are exact separating-axis tests on the rectangles after a
sort-and-sweep (same instant) and a grid (standing vehicles) broad phase; tests against
the lot use shapely 2 on the footprints that vectorised tests cannot clear (a grid of
footprint centres, boxes, a footprint side with every vertex of a parked car or obstacle
beyond it, a footprint box inside the boundary's box and away from what of it lies
outside the boundary): a quick test only ever clears, with a 1 µm margin.

Examples
--------
>>> report = check_result({"format": "lotsim-result"})
>>> report.ok, report.violations[0].rule
(False, 'structure')
"""

from __future__ import annotations

from lotsim.errors import ResultFormatError  # an error type only: no code is shared
from lotsim.verify.checker import check_result
from lotsim.verify.reading import read_result
from lotsim.verify.report import CheckReport, Violation
from lotsim.verify.tolerances import (
    ACCEL_TOL,
    CHORD_SLACK,
    CHORD_SPEED_REL,
    CURVATURE_ABS,
    CURVATURE_REL,
    EXIT_DISTANCE,
    EXIT_HEADING,
    FORMAT,
    GEAR_MIN_STEP,
    GEAR_SPEED_TOL,
    GRID_DT,
    HEADING_ABS,
    HEADING_CHORD,
    HEADING_KINK,
    HEADING_REL,
    JERK_MIN_DT,
    LATERAL_TOL,
    LOT_KEYS,
    MAKESPAN_TOL,
    MAX_DT,
    MAX_INSTANTS,
    MAX_MAGNITUDE,
    MAX_STEP,
    REST_SPEED,
    RULES,
    SAMPLE_KEYS,
    SHRINK,
    SIDEWAYS_ABS,
    SIDEWAYS_REL,
    SLOT_KINDS,
    SPEED_TOL,
    STATUSES,
    STEER_RATE_TOL,
    STEER_TOL,
    STEP_TOL,
    STILL_TOL,
    STILL_TURN,
    T_ROUND,
    TIME_TOL,
    TOP_LEVEL_KEYS,
    TYPE_NUMBERS,
    V_ROUND,
    VEHICLE_KEYS,
    VERSION,
    FloatArray,
    Pose,
)

__all__ = [
    "ACCEL_TOL",
    "CHORD_SLACK",
    "CHORD_SPEED_REL",
    "CURVATURE_ABS",
    "CURVATURE_REL",
    "CheckReport",
    "EXIT_DISTANCE",
    "EXIT_HEADING",
    "FORMAT",
    "FloatArray",
    "GEAR_MIN_STEP",
    "GEAR_SPEED_TOL",
    "GRID_DT",
    "HEADING_ABS",
    "HEADING_CHORD",
    "HEADING_KINK",
    "HEADING_REL",
    "JERK_MIN_DT",
    "LATERAL_TOL",
    "LOT_KEYS",
    "MAKESPAN_TOL",
    "MAX_DT",
    "MAX_INSTANTS",
    "MAX_MAGNITUDE",
    "MAX_STEP",
    "Pose",
    "REST_SPEED",
    "RULES",
    "ResultFormatError",
    "SAMPLE_KEYS",
    "SHRINK",
    "SIDEWAYS_ABS",
    "SIDEWAYS_REL",
    "SLOT_KINDS",
    "SPEED_TOL",
    "STATUSES",
    "STEER_RATE_TOL",
    "STEER_TOL",
    "STEP_TOL",
    "STILL_TOL",
    "STILL_TURN",
    "TIME_TOL",
    "TOP_LEVEL_KEYS",
    "TYPE_NUMBERS",
    "T_ROUND",
    "VEHICLE_KEYS",
    "VERSION",
    "V_ROUND",
    "Violation",
    "check_result",
    "read_result",
]
