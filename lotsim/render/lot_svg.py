"""The lot as SVG, for the HTML replay: what ``lotsim show`` draws, as vectors.

Coordinates are world metres with y negated (SVG's y runs down), so a viewer zooms
and pans by changing the ``viewBox`` alone. Areas are filled paths, one per kind of
thing (all slots' paving in one path, all their lines in another), which keeps the
file small and the browser quick on a lot of a thousand slots. Line widths that are
pixels in ``lotsim show`` are pixels here too (``vector-effect: non-scaling-stroke``);
things of a real size (speed bumps, arrows, cars parked at start, gates, slot ids) are
metres and grow as one zooms in. The colours are :mod:`lotsim.render.lot_image`'s.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from xml.sax.saxutils import escape

import numpy as np

from lotsim.render import lot_image as li
from lotsim.render.lot_image import _kmh, _lane_width, _rings

FloatArray = np.ndarray


def rgb(c: tuple[int, ...]) -> str:
    """``#rrggbb`` of an RGB colour (the alpha of an RGBA one is left out)."""
    return "#" + "".join(f"{int(v):02x}" for v in c[:3])


def _opacity(c: tuple[int, ...]) -> str:
    return f"{c[3] / 255:.3f}" if len(c) == 4 else "1"


def _num(v: float) -> str:
    """A coordinate to the centimetre, without trailing zeros (``-0`` as ``0``)."""
    s = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _pts(xy: FloatArray) -> str:
    """``x,-y x,-y ...`` of world points (N, 2)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    return " ".join(f"{_num(x)},{_num(-y)}" for x, y in xy)


def _ring_d(xy: FloatArray, close: bool = True) -> str:
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if len(xy) < 2:
        return ""
    return "M" + _pts(xy[:1]) + "L" + _pts(xy[1:]) + ("Z" if close else "")


def _geom_d(geoms: Iterable) -> str:
    """Path data of shapely (multi)polygons, holes included (fill-rule evenodd)."""
    out = []
    for g in geoms:
        for ext, holes in _rings(g):
            for ring in (ext, *holes):
                if len(ring) >= 3:
                    out.append(_ring_d(ring))
    return "".join(out)


def _path(d: str, **attrs: str) -> str:
    if not d:
        return ""
    extra = "".join(f' {k.replace("_", "-")}="{v}"' for k, v in attrs.items())
    return f'<path d="{d}"{extra}/>'


_LINE = {"fill": "none", "vector_effect": "non-scaling-stroke", "stroke_linejoin": "round"}


def _arrow(x: float, y: float, t: float, length: float, width: float) -> FloatArray:
    """World corners (7, 2) of an arrow centred at ``(x, y)`` pointing along ``t``
    (:func:`lotsim.render.lot_image.arrow_polygon`, in metres)."""
    head, shaft = 0.45 * length, 0.36 * width
    local = np.array([[length / 2, 0.0], [length / 2 - head, width / 2],
                      [length / 2 - head, shaft / 2], [-length / 2, shaft / 2],
                      [-length / 2, -shaft / 2], [length / 2 - head, -shaft / 2],
                      [length / 2 - head, -width / 2]])
    c, s = math.cos(t), math.sin(t)
    return np.column_stack([x + c * local[:, 0] - s * local[:, 1],
                            y + s * local[:, 0] + c * local[:, 1]])


def _triangle(x: float, y: float, t: float, size: float) -> FloatArray:
    local = np.array([[0.6, 0.0], [-0.4, 0.45], [-0.4, -0.45]]) * size
    c, s = math.cos(t), math.sin(t)
    return np.column_stack([x + c * local[:, 0] - s * local[:, 1],
                            y + s * local[:, 0] + c * local[:, 1]])


PORTAL_SIZE = 3.0
"""Side of an entrance or exit triangle [m] (``lotsim show``: 3 m, at least 14 px)."""


def lot_svg(lot, parked: FloatArray, bounds: tuple[float, float, float, float]) -> str:
    """The static lot as the inner markup of an ``<svg>`` (``<defs>`` and one ``<g>``).

    Parameters
    ----------
    lot : lotsim.lot.model.Lot
        As read back from a result's ``lot.drawing``.
    parked : (N, 4, 2) array
        Bodies of the cars parked at start [m].
    bounds : (minx, miny, maxx, maxy)
        The world rectangle shown [m]; the hatching of no-go areas is laid out from it.
    """
    out = ['<defs><pattern id="hatch" patternUnits="userSpaceOnUse" width="1.2" '
           'height="1.2" patternTransform="rotate(45)"><rect width="0.3" height="1.2" '
           f'fill="{rgb(li.NO_GO_HATCH)}"/></pattern></defs><g>']
    add = out.append
    if lot.pavement is None:
        add(_path(_geom_d([lot.boundary]), fill=rgb(li.PAVED), fill_rule="evenodd"))
    else:
        add(_path(_geom_d([lot.boundary]), fill=rgb(li.GROUND), fill_rule="evenodd"))
        add(_path(_geom_d([lot.pavement]), fill=rgb(li.PAVED), fill_rule="evenodd"))
    add(_path(_geom_d(a.polygon for a in lot.aisles.values()), fill=rgb(li.ASPHALT),
              fill_rule="nonzero"))
    add(_path("".join(_ring_d(s.polygon) for s in lot.slots), fill=rgb(li.SLOT_PAVING)))
    for z in lot.zones:
        tint = li.ZONE_TINT if z.source == "zone" else li.BUMP_REACH_TINT
        add(_path(_geom_d([z.polygon.intersection(lot.boundary)]), fill=rgb(tint),
                  fill_opacity=_opacity(tint), fill_rule="evenodd"))
    no_go = _geom_d(a.polygon for a in lot.areas if a.kind == "no_go")
    add(_path(no_go, fill=rgb(li.NO_GO_TINT), fill_opacity=_opacity(li.NO_GO_TINT),
              fill_rule="evenodd"))
    add(_path(no_go, fill="url(#hatch)", fill_rule="evenodd"))
    add(_path(no_go, stroke=rgb(li.NO_GO_HATCH), stroke_width="2", **_LINE))
    add(_path(_geom_d(a.polygon for a in lot.areas if a.kind == "obstacle"),
              fill=rgb(li.OBSTACLE), stroke=rgb(li.OBSTACLE_EDGE), stroke_width="2",
              vector_effect="non-scaling-stroke", fill_rule="evenodd"))
    add(_path(_geom_d(a.polygon for a in lot.areas if a.kind == "wall"), fill=rgb(li.WALL),
              fill_rule="evenodd"))
    _lanes(lot, add)
    _slot_lines(lot, add)
    for z in lot.zones:
        if z.source == "bump" and z.line is not None:
            d = _ring_d(np.asarray(z.line.coords)[:, :2], close=False)
            add(_path(d, fill="none", stroke=rgb(li.BUMP_YELLOW), stroke_width="0.6"))
            add(_path(d, fill="none", stroke=rgb(li.BUMP_BLACK), stroke_width="0.6",
                      stroke_dasharray="0.6 0.6"))
    _parked(np.asarray(parked, dtype=float).reshape(-1, 4, 2), add)
    add(_path(_geom_d([lot.boundary]), stroke=rgb(li.BOUNDARY), stroke_width="3", **_LINE))
    _labels(lot, add)
    _portals(lot, add, bounds)
    add("</g>")
    return "".join(out)


def _lanes(lot, add) -> None:
    portals = np.array([p.pose[:2] for p in (*lot.entrances, *lot.exits)],
                       dtype=float).reshape(-1, 2)
    lines, arrows = [], []
    for aisle in lot.aisles.values():
        lane_w = _lane_width(aisle)
        length = float(np.clip(1.1 * lane_w, 1.5, 4.5))
        width = 0.55 * length
        spacing = max(4.0 * length, 12.0)
        for lane in aisle.lanes:
            lines.append(_ring_d(lane.sample(0.25)[:, :2], close=False))
            n = max(1, int(lane.length // spacing))
            for s in (np.arange(n) + 0.5) * lane.length / n:
                x, y, t = lane.pose_at(float(s))
                if len(portals) and np.min(np.hypot(*(portals - [x, y]).T)) < (
                        length / 2 + 0.6 * PORTAL_SIZE + 0.5):
                    continue  # an entrance or exit arrow stands there
                arrows.append(_ring_d(_arrow(x, y, t, length, width)))
    lane_rgba = li.LANE_LINE
    add(_path("".join(lines), stroke=rgb(lane_rgba), stroke_opacity=_opacity(lane_rgba),
              stroke_width="1", stroke_dasharray="8 8", **_LINE))
    add(_path("".join(arrows), fill=rgb(li.ARROW), stroke=rgb(li.ARROW_EDGE),
              stroke_width="1", vector_effect="non-scaling-stroke"))


def _slot_lines(lot, add) -> None:
    if not lot.slots:
        return
    for kind, color in li.SLOT_LINE.items():
        rings, entries = [], []
        for slot in lot.slots:
            if li.SLOT_LINE.get(slot.kind, li.SLOT_LINE["perpendicular"]) != color:
                continue
            poly = np.asarray(slot.polygon, dtype=float)
            entry = np.asarray(slot.entry, dtype=float)
            mids = (poly + np.roll(poly, -1, axis=0)) / 2
            k = int(np.argmin(np.hypot(*(mids - entry.mean(axis=0)).T)))
            rings.append(_ring_d(np.roll(poly, -(k + 1), axis=0), close=False))
            entries.append(_ring_d(entry, close=False))
        add(_path("".join(rings), stroke=rgb(color), stroke_width="1.5", data_kind=kind,
                  **_LINE))
        add(_path("".join(entries), stroke=rgb(color), stroke_width="1",
                  stroke_dasharray="2 3", **_LINE))


def _parked(bodies: FloatArray, add) -> None:
    if not len(bodies):
        return
    rr, fr, fl, rl = bodies[:, 0], bodies[:, 1], bodies[:, 2], bodies[:, 3]

    def at(t: float, s: float) -> FloatArray:
        right = rr + t * (fr - rr)
        left = rl + t * (fl - rl)
        return right + s * (left - right)

    screen = np.stack([at(0.60, 0.12), at(0.78, 0.12), at(0.78, 0.88), at(0.60, 0.88)],
                      axis=1)
    add(_path("".join(_ring_d(b) for b in bodies), fill=rgb(li.PARKED_CAR),
              stroke=rgb(li.PARKED_CAR_EDGE), stroke_width="1",
              vector_effect="non-scaling-stroke"))
    add(_path("".join(_ring_d(b) for b in screen), fill=rgb(li.PARKED_CAR_FRONT)))


def _text(x: float, y: float, text: str, size: float, fill: str, halo: bool = False) -> str:
    extra = (' stroke="#ffffff" stroke-width="0.25" paint-order="stroke"' if halo else "")
    return (f'<text x="{_num(x)}" y="{_num(-y)}" font-size="{_num(size)}" '
            f'fill="{fill}"{extra}>{escape(text)}</text>')


def _labels(lot, add) -> None:
    """Slot ids in their slots, speed limits in their zones."""
    parts = ['<g class="labels" text-anchor="middle" dominant-baseline="central" '
             'font-family="sans-serif">']
    if lot.slots:
        for slot in lot.slots:
            c = np.asarray(slot.polygon, dtype=float).mean(axis=0)
            size = 0.3 * min(slot.width, slot.length)
            parts.append(_text(c[0], c[1], slot.id, size, rgb(li.SLOT_LABEL)))
    for z in lot.zones:
        if z.source == "bump" and z.line is not None:
            mid = z.line.interpolate(0.5, normalized=True)
            a = z.line.interpolate(0.45, normalized=True)
            b = z.line.interpolate(0.55, normalized=True)
            d = np.array([b.x - a.x, b.y - a.y])
            n = np.array([-d[1], d[0]]) / (np.hypot(*d) or 1.0)
            x, y, color = mid.x + 1.6 * n[0], mid.y + 1.6 * n[1], rgb(li.TEXT)
        else:
            p = z.polygon.intersection(lot.boundary).representative_point()
            if p.is_empty:
                continue
            x, y, color = p.x, p.y, rgb((150, 70, 0))
        parts.append(_text(x, y, _kmh(z.limit), 1.0, color, halo=True))
    parts.append("</g>")
    add("".join(parts))


def _portals(lot, add, bounds) -> None:
    """Entrances as green, exits as red triangles pointing the way traffic goes; each id
    behind its triangle, or beside or ahead of it where that stays in the picture."""
    parts = ['<g class="portals" text-anchor="middle" dominant-baseline="central" '
             'font-family="sans-serif" font-weight="bold">']
    portals = [(p, li.ENTRANCE) for p in lot.entrances] + [(p, li.EXIT) for p in lot.exits]
    centres = np.array([p.pose[:2] for p, _ in portals], dtype=float).reshape(-1, 2)
    for p, color in portals:
        x, y, t = p.pose
        parts.append(f'<polygon points="{_pts(_triangle(x, y, t, PORTAL_SIZE))}" '
                     f'fill="{rgb(color)}" stroke="#000000" stroke-width="2" '
                     'vector-effect="non-scaling-stroke"/>')
    for p, color in portals:
        x, y, t = p.pose
        hw, hh = 0.45 * len(p.id) + 0.2, 0.9  # half the label's size at 1.4 m [m]
        fwd = np.array([math.cos(t), math.sin(t)])
        right = np.array([math.sin(t), -math.cos(t)])
        best = None
        for k, v in enumerate((-fwd, right, -right, fwd)):
            reach = 0.45 * PORTAL_SIZE + 0.5 + abs(v[0]) * hw + abs(v[1]) * hh
            c = np.array([x, y]) + v * reach
            inside = (bounds[0] <= c[0] - hw and c[0] + hw <= bounds[2]
                      and bounds[1] <= c[1] - hh and c[1] + hh <= bounds[3])
            near = np.hypot(*(centres - c).T)
            clear = bool(np.all(near[near > 1e-9] > 0.6 * PORTAL_SIZE + max(hw, hh)))
            score = (int(inside) + int(clear), -k)
            if best is None or score > best[0]:
                best = (score, c)
        c = best[1]
        parts.append(_text(c[0], c[1], p.id, 1.4, rgb(color), halo=True))
    parts.append("</g>")
    add("".join(parts))
