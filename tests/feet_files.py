"""Files in feet made from shipped metric files (``units: ft``): exactly the keys
docs/scenario.md and docs/layout.md list as lengths are converted, so a length lotsim failed
to convert, or a number it converted that is not a length, makes the two files differ."""

from __future__ import annotations

FOOT = 0.3048

LENGTHS = {"width", "length", "slot_width", "slot_length", "start", "gap", "at",
           "access_aisle_width", "bend_radius", "reach", "corner_radius", "x", "y", "within",
           "front", "rear", "wheelbase", "circulation", "two-way", "one-way",
           "lane_clearance", "sweep"}
"""Keys whose number is a length [m], in the sections below (docs/scenario.md, layout.md)."""
POINTS = {"boundary", "centerline", "polygon", "line", "center", "at"}
"""Keys whose value is a point or a list of points [m]."""
PER_LENGTH = {"max_accel", "max_brake", "max_lateral_accel", "max_jerk"}
"""Keys in the file's length unit per second² (³): ft/s² in feet."""
SECTIONS = {"lot", "vehicle_types", "routes", "boundary", "islands", "gates", "bays",
            "aisles", "building_entrances", "uses"}
"""Top-level sections that hold lengths; the others (traffic, disturbances, animation,
demand) hold none, though some of their keys share a length's name (a stream's
``start``, the animation's ``speed``)."""


def _feet(x):
    return x / FOOT


def _points(v):
    if isinstance(v[0], list):
        return [_points(p) for p in v]
    return [_feet(c) for c in v]


def to_feet(doc: dict) -> dict:
    """The same document in feet: ``units: ft`` and every length divided by 0.3048."""
    def walk(v):
        if isinstance(v, dict):
            out = {}
            for k, x in v.items():
                if k in POINTS and isinstance(x, list):
                    out[k] = _points(x)
                elif (k in LENGTHS and isinstance(x, int | float)
                      and not isinstance(x, bool)) or k in PER_LENGTH:
                    out[k] = _feet(x)
                else:
                    out[k] = walk(x)
            return out
        if isinstance(v, list):
            return [walk(x) for x in v]
        return v

    out = {"units": "ft"}
    for k, v in doc.items():
        if k == "boundary":
            out[k] = _points(v)
        else:
            out[k] = walk(v) if k in SECTIONS else v
    return out
