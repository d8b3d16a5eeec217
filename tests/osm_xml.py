"""OSM XML files written by the tests, laid out in local metres and written as WGS84
degrees (:func:`write_osm`): OpenStreetMap extracts and Lanelet2 maps in Autoware's
valet-parking convention (:func:`road_with_bays`); rows of angled bays as lotsim lays them
(:func:`angled_row`) and as they are painted (:func:`painted_row`)."""

from __future__ import annotations

import math
from pathlib import Path

A, F = 6378137.0, 1 / 298.257223563  # WGS84
E2 = F * (2 - F)


def write_osm(path: Path, ways, relations, origin=(48.0, 11.0)) -> Path:
    """An OSM XML file: ``ways`` as (id, points [m], tags), ``relations`` as (id,
    [(way id, role)], tags); metres east and north of ``origin`` turned into degrees by the
    ellipsoid's meridian and prime-vertical radii there."""
    lat0, lon0 = origin
    la = math.radians(lat0)
    m_r = A * (1 - E2) / (1 - E2 * math.sin(la) ** 2) ** 1.5
    n_r = A / math.sqrt(1 - E2 * math.sin(la) ** 2)
    nodes: dict[tuple[float, float], int] = {}
    lines = ["<?xml version='1.0' encoding='UTF-8'?>", "<osm version='0.6'>"]
    body = []
    for wid, pts, tags in ways:
        body.append(f"  <way id='{wid}'>")
        for x, y in pts:
            key = (round(x, 6), round(y, 6))
            nodes.setdefault(key, -(len(nodes) + 1))
            body.append(f"    <nd ref='{nodes[key]}' />")
        body += [f"    <tag k='{k}' v='{v}' />" for k, v in tags.items()]
        body.append("  </way>")
    for rid, members, tags in relations:
        body.append(f"  <relation id='{rid}'>")
        body += [f"    <member type='way' ref='{w}' role='{role}' />" for w, role in members]
        body += [f"    <tag k='{k}' v='{v}' />" for k, v in tags.items()]
        body.append("  </relation>")
    for (x, y), nid in nodes.items():
        lat = lat0 + math.degrees(y / m_r)
        lon = lon0 + math.degrees(x / (n_r * math.cos(la)))
        lines.append(f"  <node id='{nid}' lat='{lat:.11f}' lon='{lon:.11f}' />")
    path.write_text("\n".join(lines + body + ["</osm>"]) + "\n")
    return path


def road_with_bays(ways, relations, width: float, *, x0=0.0, y0=0.0, length=40.0,
                   bays=8, first_id=1000):
    """A two-way road ``width`` wide from (x0, y0) east ``length`` m (two lanelets side by
    side sharing their middle bound, both ends open), a 1 m access strip along its north
    edge and ``bays`` 2.5 × 5 m spots behind it."""
    def way(pts, **tags):
        wid = -(first_id + len(ways))
        ways.append((wid, [(x0 + x, y0 + y) for x, y in pts], tags))
        return wid

    south = way([(0, 0), (length, 0)], type="line_thin", subtype="solid")
    middle = way([(0, width / 2), (length, width / 2)], type="line_thin", subtype="dashed")
    north = way([(0, width), (length, width)], type="line_thin", subtype="solid")
    n = len(relations)
    relations.append((-(first_id + n + 1), [(middle, "left"), (south, "right")],
                      {"type": "lanelet", "subtype": "lane"}))
    relations.append((-(first_id + n + 2), [(middle, "left"), (north, "right")],
                      {"type": "lanelet", "subtype": "lane"}))
    start = (length - 2.5 * bays) / 2
    way([(start - 2, width), (length - start + 2, width), (length - start + 2, width + 1),
         (start - 2, width + 1), (start - 2, width)], type="area", subtype="parking_access")
    for k in range(bays):
        x = start + 2.5 * k
        way([(x, width + 1), (x + 2.5, width + 1), (x + 2.5, width + 6), (x, width + 6),
             (x, width + 1)], type="area", subtype="parking_spot")


def angled_row(alpha_deg: float, count: int, start: float, edge: float, *, width=2.5,
               length=5.0, side=1, lean=-1):
    """A row of ``count`` rectangular bays at ``alpha_deg`` to an aisle along x whose edge is
    the line y = ``edge``, on the side ``side`` (+1 north, -1 south), a car driving in
    heading ``lean`` (+1 east, -1 west) along the aisle, laid as lotsim's angled rows are:
    each bay's front entry corner on the edge, the first at x = ``start``, the next
    width / sin α on, neighbours sharing long sides. Returns each bay's corners (entry
    front, entry back, far back, far front) and the points of their entries by x, east
    first: the saw-tooth edge of the ground in front of them."""
    a = math.radians(alpha_deg)
    d = (lean * math.cos(a), side * math.sin(a))  # into the bay
    e = (d[1], -d[0])  # across the entry, front corner to back, away from the aisle
    if e[1] * side < 0:
        e = (-e[0], -e[1])
    step = math.copysign(width / math.sin(a), e[0])
    bays = []
    for k in range(count):
        front = (start + k * step, edge)
        back = (front[0] + width * e[0], edge + width * e[1])
        bays.append([front, back, (back[0] + length * d[0], back[1] + length * d[1]),
                     (front[0] + length * d[0], front[1] + length * d[1])])
    saw = sorted((p for b in bays for p in b[:2]), key=lambda p: -p[0])
    return bays, saw


def painted_row(alpha_deg: float, count: int, start: float, edge: float, *, width=2.5,
                depth=5.5, side=-1, lean=1):
    """A row of ``count`` angled bays painted along an aisle whose edge is y = ``edge``:
    parallelograms with their entry on the edge (``width`` / sin α long, from x = ``start``
    + k · width / sin α), ``depth`` deep on the side ``side``, leaning ``lean``; the corners
    of each (entry start, entry end, back end, back start)."""
    a = math.radians(alpha_deg)
    run = width / math.sin(a)
    shift = lean * depth / math.tan(a)
    out = []
    for k in range(count):
        x = start + k * run
        y = edge + side * depth
        out.append([(x, edge), (x + run, edge), (x + run + shift, y), (x + shift, y)])
    return out
