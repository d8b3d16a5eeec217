"""The result format the checker reads and the tolerance of every rule (documented in
:mod:`lotsim.verify`)."""

from __future__ import annotations

import numpy as np

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
BAY_USES = {"standard": None, "compact": None, "accessible": "accessible",
            "van_accessible": "accessible", "ev": "ev", "motorcycle": "motorcycle"}
"""Each use of bay → the mark a vehicle type needs to park in it (None: any type may; a
compact bay takes a type no longer and no wider than itself), as ``docs/scenario.md``
states the rule."""
MARKS = ("accessible", "ev", "motorcycle")
"""What a vehicle type may be marked as."""
BODY_TOL = 1e-6
"""Slack on a body's length and width against a compact bay's [m]."""

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
POSE_TOL = 1e-3
"""How far a car in the lot when it came may start from the pose it stood at [m, rad]
(the result writes poses to 0.1 mm)."""
MAKESPAN_TOL = 1e-3
"""Slack on ``metrics.makespan`` [s]."""
MAX_MAGNITUDE = 1e9
"""Numbers beyond this in size overflow the geometry and are a structure violation."""
MAX_INSTANTS = 50_000_000
"""Vehicle-instants beyond which the footprint rules give up (memory) [-]: those the
footprints are interpolated at (a vehicle standing between two samples counts the two
ends of the stretch, not every instant of it)."""

RULES = ("internal", "structure", "status", "arrival", "sampling", "sideways", "curvature",
         "heading", "steer", "steer_rate", "gear", "speed", "lateral", "accel", "jerk",
         "overlap", "parked", "obstacle", "access_aisle", "boundary", "pavement", "slot",
         "bay_use", "inside", "exit", "reason",
         "stall", "closure", "taken", "metrics")
"""Every rule tag, in the order violations are listed."""

FloatArray = np.ndarray
Pose = tuple[float, float, float]
