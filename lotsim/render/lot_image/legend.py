"""The title, the legend and the scale bar around a lot picture."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from PIL import Image, ImageDraw

from lotsim.lot.kinds import KINDS
from lotsim.render.lot_image.canvas import (
    LotCanvas,
    _flat,
    arrow_polygon,
    dashed_line,
    triangle_polygon,
)
from lotsim.render.lot_image.theme import (
    ARROW,
    ARROW_EDGE,
    ASPHALT,
    BUMP_BLACK,
    BUMP_REACH_TINT,
    BUMP_YELLOW,
    ENTRANCE,
    EXIT,
    GRAPH_EDGE,
    GRAPH_NODE,
    GROUND,
    NO_GO_HATCH,
    NO_GO_TINT,
    OBSTACLE,
    OBSTACLE_EDGE,
    PARKED_CAR,
    PARKED_CAR_EDGE,
    PARKED_CAR_FRONT,
    PAVED,
    SLOT_LINE,
    SLOT_PAVING,
    WALL,
    ZONE_TINT,
    Color,
    draw_text,
    font,
    text_size,
)


# -- title, legend, scale bar ------------------------------------------------------------------
@dataclass(frozen=True)
class _Entry:
    label: str
    swatch: Callable[[Image.Image, tuple[int, int, int, int]], None]


def _swatch_rect(fill: Color, outline: Color | None = None, width: int = 1):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        ImageDraw.Draw(img).rectangle(box, fill=fill, outline=outline, width=width)

    return paint


def _swatch_slot(color: Color):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        d = ImageDraw.Draw(img)
        x0, y0, x1, y1 = box
        d.rectangle(box, fill=SLOT_PAVING)
        d.line([(x0 + 2, y1), (x0 + 2, y0 + 2), (x1 - 2, y0 + 2), (x1 - 2, y1)], fill=color,
               width=2)
        dashed_line(d, np.array([[x0 + 2, y1 - 1], [x1 - 2, y1 - 1]]), color, on=2, off=3)

    return paint


def _swatch_arrow(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    d.rectangle(box, fill=ASPHALT)
    c = np.array([(box[0] + box[2]) / 2, (box[1] + box[3]) / 2])
    d.polygon(_flat(arrow_polygon(c, 0.0, box[2] - box[0] - 6, box[3] - box[1] - 3)),
              fill=ARROW, outline=ARROW_EDGE)


def _swatch_hatch(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    sub = Image.new("RGB", (box[2] - box[0] + 1, box[3] - box[1] + 1), GROUND)
    overlay = Image.new("RGB", sub.size, NO_GO_TINT[:3])
    sub = Image.blend(sub, overlay, NO_GO_TINT[3] / 255)
    d = ImageDraw.Draw(sub)
    w, h = sub.size
    for c in range(-h, w, 8):
        d.line([(c, h), (c + h, 0)], fill=NO_GO_HATCH, width=2)
    d.rectangle([0, 0, w - 1, h - 1], outline=NO_GO_HATCH, width=2)
    img.paste(sub, box[:2])


def _swatch_bump(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    _swatch_tint(BUMP_REACH_TINT)(img, box)
    d = ImageDraw.Draw(img)
    y = (box[1] + box[3]) / 2
    line = np.array([[box[0], y], [box[2], y]], dtype=float)
    d.line(_flat(line), fill=BUMP_YELLOW, width=7)
    dashed_line(d, line, BUMP_BLACK, width=7, on=5, off=5)


def _swatch_tint(tint: tuple[int, int, int, int]):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        ImageDraw.Draw(img, "RGBA").rectangle(box, fill=ASPHALT)
        ImageDraw.Draw(img, "RGBA").rectangle(box, fill=tint, outline=tint[:3])

    return paint


def _swatch_triangle(color: Color):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        c = np.array([(box[0] + box[2]) / 2, (box[1] + box[3]) / 2])
        tri = triangle_polygon(c, 0.0, min(box[2] - box[0], box[3] - box[1]) * 1.25)
        ImageDraw.Draw(img).polygon(_flat(tri), fill=color, outline=(0, 0, 0))

    return paint


def _swatch_car(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    x0, y0, x1, y1 = box
    d.rectangle([x0 + 1, y0 + 2, x1 - 1, y1 - 2], fill=PARKED_CAR, outline=PARKED_CAR_EDGE)
    w = x1 - x0
    d.rectangle([x0 + 0.6 * w, y0 + 3, x0 + 0.78 * w, y1 - 3], fill=PARKED_CAR_FRONT)


def _swatch_graph(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    x0, y0, x1, y1 = box
    y = (y0 + y1) / 2
    d.rectangle(box, fill=ASPHALT)
    d.line([(x0 + 3, y), (x1 - 3, y)], fill=GRAPH_EDGE["lane"], width=1)
    for x in (x0 + 4, x1 - 4):
        d.ellipse([x - 2.5, y - 2.5, x + 2.5, y + 2.5], fill=GRAPH_NODE, outline=(0, 0, 0))


def _swatch_turn(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    x0, y0, x1, y1 = box
    d.rectangle(box, fill=ASPHALT)
    d.arc((x0 + 3, y0 + 3, x0 + 3 + 2 * (x1 - x0 - 6), y1 + (y1 - y0)), 180, 270,
          fill=GRAPH_EDGE["turn"], width=2)


def _swatch_park(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    x0, y0, x1, y1 = box
    d.rectangle(box, fill=ASPHALT)
    y = (y0 + y1) / 2
    dashed_line(d, np.array([[x0 + 3, y], [x1 - 3, y]]), GRAPH_EDGE["park"], on=3, off=2)


def _swatch_multipoint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    x0, y0, x1, y1 = box
    d.rectangle(box, fill=ASPHALT)
    d.line([(x0 + 3, y1 - 4), ((x0 + x1) / 2, y0 + 4), (x1 - 3, y1 - 4)],
           fill=GRAPH_EDGE["turnaround"], width=1)


def _swatch_ground(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    x0, y0, x1, y1 = box
    mid = (x0 + x1) // 2
    draw = ImageDraw.Draw(img)
    draw.rectangle((x0, y0, mid, y1), fill=PAVED)
    draw.rectangle((mid + 1, y0, x1, y1), fill=GROUND, outline=(120, 130, 110))


def _legend_entries(lot_graph, lot, show_graph: bool) -> list[_Entry]:
    out = [_Entry("aisle, lane direction", _swatch_arrow)]
    kinds = {s.kind for s in lot.slots}
    for kind in KINDS:
        if kind in kinds:
            out.append(_Entry(f"{kind} slot", _swatch_slot(SLOT_LINE[kind])))
    if lot.occupied:
        out.append(_Entry("parked car", _swatch_car))
    if lot.pavement is not None:
        out.append(_Entry("paved, unpaved ground", _swatch_ground))
    area_kinds = {a.kind for a in lot.areas}
    if "wall" in area_kinds:
        out.append(_Entry("wall", _swatch_rect(WALL)))
    if "obstacle" in area_kinds:
        out.append(_Entry("obstacle", _swatch_rect(OBSTACLE, OBSTACLE_EDGE, 2)))
    if "no_go" in area_kinds:
        out.append(_Entry("no-go zone", _swatch_hatch))
    sources = {z.source for z in lot.zones}
    if "bump" in sources:
        out.append(_Entry("speed bump, its reach", _swatch_bump))
    if "zone" in sources:
        out.append(_Entry("speed zone", _swatch_tint(ZONE_TINT)))
    if lot.entrances:
        out.append(_Entry("entrance", _swatch_triangle(ENTRANCE)))
    if lot.exits:
        out.append(_Entry("exit", _swatch_triangle(EXIT)))
    if show_graph and lot_graph is not None:
        out.append(_Entry("graph node, lane edge", _swatch_graph))
        kinds = {d["kind"] for *_, d in lot_graph.graph.edges(data=True)}
        if "turn" in kinds:
            out.append(_Entry("junction turn", _swatch_turn))
        if kinds & {"park", "leave"}:
            out.append(_Entry("park link (to a slot)", _swatch_park))
        if any(d["kind"] == "turnaround" for *_, d in lot_graph.graph.edges(data=True)):
            out.append(_Entry("multi-point turn", _swatch_multipoint))
    return out


_SW, _ROW, _PAD = 26, 18, 8  # swatch width, row height, legend padding [px]


class _Legend:
    """The legend box: a summary line, one row per entry, then the scale bar."""

    def __init__(self, entries: list[_Entry], summary: str):
        self.entries = entries
        self.summary = summary
        self.font = font(12)
        self.text_w = max([text_size(e.label, self.font)[0] for e in entries] + [0])
        self.col_w = _SW + 6 + self.text_w + 14
        self.summary_w = text_size(summary, self.font)[0]

    def size(self, columns: int) -> tuple[int, int]:
        rows = math.ceil(len(self.entries) / columns)
        w = max(columns * self.col_w - 14, self.summary_w, 150) + 2 * _PAD
        h = 2 * _PAD + _ROW + rows * _ROW + 8 + 30  # summary, rows, gap, scale bar
        return int(w), int(h)

    def columns_for(self, width: float) -> int:
        """The fewest columns that make the fewest rows within ``width`` px."""
        n = max(len(self.entries), 1)
        cols = int(max(1, min(n, (width - 2 * _PAD + 14) // self.col_w)))
        return math.ceil(n / math.ceil(n / cols))

    def paint(self, img: Image.Image, x: int, y: int, columns: int, canvas: LotCanvas) -> None:
        w, h = self.size(columns)
        d = ImageDraw.Draw(img)
        d.rectangle([x, y, x + w, y + h], fill=(255, 255, 255), outline=(90, 90, 90))
        draw_text(d, (x + _PAD, y + _PAD + _ROW / 2), self.summary, self.font, anchor="lm")
        rows = math.ceil(len(self.entries) / columns)
        for i, e in enumerate(self.entries):
            cx = x + _PAD + (i // rows) * self.col_w
            cy = y + _PAD + _ROW * (1 + i % rows)
            e.swatch(img, (cx, cy + 2, cx + _SW, cy + _ROW - 3))
            draw_text(d, (cx + _SW + 6, cy + _ROW / 2), e.label, self.font, anchor="lm")
        paint_scale_bar(img, canvas, x + _PAD, y + h - _PAD - 6, w - 2 * _PAD)


def _nice_length(max_m: float) -> float:
    """The largest 1-2-5 length not above ``max_m`` [m] (at least 0.1 m)."""
    best = 0.1
    for e in range(-1, 6):
        for m in (1, 2, 5):
            v = m * 10.0**e
            if v <= max_m:
                best = v
    return best


def paint_scale_bar(img: Image.Image, canvas: LotCanvas, x: float, y: float, width: float) -> None:
    """A black/white bar of a round length with its value, bottom-left at (x, y)."""
    d = ImageDraw.Draw(img)
    f = font(12)
    metres = _nice_length((min(width, 260) - 50) / canvas.scale)
    length = canvas.px(metres)
    parts = 5 if metres >= 5 and length >= 50 else 2
    for k in range(parts):
        x0, x1 = x + k * length / parts, x + (k + 1) * length / parts
        d.rectangle([x0, y - 6, x1, y], fill=(0, 0, 0) if k % 2 == 0 else (255, 255, 255),
                    outline=(0, 0, 0))
    label = f"{metres:g} m"
    draw_text(d, (x + length + 6, y - 3), label, f, anchor="lm")
    draw_text(d, (x, y - 9), "0", f, anchor="mb")


def _grid(img: Image.Image, canvas: LotCanvas, step: float) -> None:
    """Faint world grid every ``step`` metres with coordinates along the left and top."""
    d = ImageDraw.Draw(img, "RGBA")
    f = font(10)
    left, top, right, bottom = canvas.drawing_box
    minx, miny, maxx, maxy = canvas.bounds
    for gx in np.arange(math.ceil(minx / step) * step, maxx + 1e-9, step):
        px = canvas.to_px([gx, 0.0])[0]
        d.line([(px, top), (px, bottom)], fill=(0, 0, 0, 40))
        draw_text(d, (px, top - 2), f"{gx:g}", f, anchor="mb")
    for gy in np.arange(math.ceil(miny / step) * step, maxy + 1e-9, step):
        py = canvas.to_px([0.0, gy])[1]
        d.line([(left, py), (right, py)], fill=(0, 0, 0, 40))
        draw_text(d, (left - 3, py), f"{gy:g}", f, anchor="rm")
