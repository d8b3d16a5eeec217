"""Animated GIF of a run, drawn from its ``result.json`` alone (``lotsim render``).

The lot is drawn once (the picture of ``lotsim show``) and reduced to a palette;
each frame is a copy of it on which Pillow draws, with palette indices, every
vehicle in the lot as its real footprint at its interpolated pose: wheels (front
wheels turned by the steer angle), a windscreen, a white bar across the rear
while reversing, a faint trail, and its target slot outlined in its colour until
it stands there; what the run met (:attr:`Replay.met`): closed ground hatched, the cars in
bays taken from outside, stalled cars ringed. A header holds the clock and the counters, a
footer the scale and the key (:mod:`lotsim.render.colour_key`: the colours and the key,
:data:`~lotsim.render.colour_key.LEGEND`, shared with the HTML replay).

Frames are drawn in chunks of :data:`CHUNK` and written chunk by chunk, each chunk's frames
spliced into the one file (:mod:`lotsim.render.gif_file`), so memory does not grow with the
length of the run.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageChops, ImageDraw

from lotsim.errors import SettingsError
from lotsim.render.colour_key import (
    CLOSED,
    GLASS,
    HATCH,
    INK,
    TYRE,
    VEHICLE_COLOURS,
    WHITE,
    KeyInks,
    key_room,
    key_width,
    legend_entries,
    paint_key,
    pale,
    scale_bar_width,
    vehicle_palette,
)

# re-exported: the key's entries and the GIF splitting, as the tests and users take them
from lotsim.render.colour_key import LEGEND as LEGEND
from lotsim.render.colour_key import LEGEND_CARS as LEGEND_CARS
from lotsim.render.gif_file import split_gif as split_gif
from lotsim.render.gif_file import write_gif_chunks
from lotsim.render.lot_image import (
    PAD_PX,
    PARKED_CAR,
    LotCanvas,
    font,
    lot_bounds,
    paint_lot,
    paint_portals,
    paint_scale_bar,
)
from lotsim.render.replay import (
    COUNTERS,
    PHASES,
    MetDisturbances,
    Replay,
    assign_colours,
)
from lotsim.scenario import VIEW_MARGIN, GifSettings

CHUNK = 48
"""Frames encoded at a time: bounds memory to about ``CHUNK`` × width × height × 3 bytes."""
HEADER = 26
"""Pixel height of the clock and counters band."""
FOOTER = 22
"""Pixel height of the band holding the scale bar."""
BACKGROUND_COLOURS = 32
"""Palette entries for the lot picture (median cut); the rest hold vehicles and text."""
WHEEL = (0.62, 0.22)
"""Tyre length and width drawn [m]."""
REVERSE_BAND = 0.45
"""Depth of the white band drawn across the rear of a reversing car [m]."""

HEADER_BG = (250, 250, 248)


@dataclass(frozen=True)
class FramePlan:
    """The run times drawn and how long each frame shows."""

    times: np.ndarray
    """Run time of each frame [s]."""
    durations: list[int]
    """Display time of each frame [ms], whole centiseconds adding up to ``len / fps``."""
    speed: float
    """Run seconds per GIF second actually used (raised when ``max_frames`` bites)."""
    start: float
    end: float
    skips: tuple[tuple[float, float], ...] = ()
    """Run time left out (``skip_quiet``): ``(from, to)`` stretches [s]."""
    skipped: tuple[float, ...] | None = None
    """Per frame, the run time skipped just before it (shown for a second of the
    animation after each skip; 0 elsewhere) [s]; None without skips."""


def plan_frames(replay: Replay, settings: GifSettings) -> FramePlan:
    """Frame times from ``settings.start`` (default the first arrival) up to ``end``
    (default the last event), ``speed / fps`` run seconds apart; with ``skip_quiet``, the
    quiet stretches of the run (:meth:`Replay.quiet`) are left out."""
    start = replay.start if settings.start is None else settings.start
    end = replay.end if settings.end is None else settings.end
    if end <= start:
        what = "start" if settings.start is not None else "end"
        raise SettingsError(what, f"nothing to show from {start:g} s to {end:g} s (the run "
                                  f"goes from {replay.start:g} s to {replay.end:g} s)")
    skips = []
    if settings.skip_quiet:
        skips = [(max(a, start), min(b, end)) for a, b in replay.quiet()
                 if min(b, end) > max(a, start)]
    # shown time u runs from 0 to span; run time is u plus the skips before it
    span = (end - start) - sum(b - a for a, b in skips)
    speed = settings.speed
    n = max(1, math.ceil(span * settings.fps / speed - 1e-9))
    if n > settings.max_frames:
        n = settings.max_frames
        speed = span * settings.fps / n
    u = np.arange(n) * (speed / settings.fps)
    times = start + u
    skipped = None
    if skips:
        lost = np.zeros(n)
        skipped = np.zeros(n)
        shown = 0.0  # shown time at which each skip happens
        prev = start
        for a, b in skips:
            shown += a - prev
            prev = b
            after = u >= shown - 1e-9
            lost[after] += b - a
            recent = after & (u < shown + speed)  # a second of the animation
            skipped[recent] = np.maximum(skipped[recent], b - a)
        times = start + u + lost
        skipped = tuple(skipped.tolist())
    cs = np.round(np.arange(n + 1) * (100.0 / settings.fps)).astype(int)
    return FramePlan(times, (10 * np.diff(cs)).tolist(), speed, start, end, tuple(skips),
                     skipped)


def _clock(t: float) -> str:
    sign = "-" if t < 0 else ""
    t = abs(t)
    h, rest = divmod(t, 3600)
    m, s = divmod(rest, 60)
    return f"{sign}{int(h)}:{int(m):02d}:{s:04.1f}" if h >= 1 else f"{sign}{int(m):02d}:{s:04.1f}"


def car_parts(
    x: np.ndarray, y: np.ndarray, theta: np.ndarray, steer: np.ndarray,
    body: np.ndarray, wheelbase: np.ndarray,
) -> dict[str, np.ndarray]:
    """World corners of the drawn parts of cars at rear-axle poses ``(x, y, theta)``.

    ``body`` (V, 4, 2) are the body corners in the car frame (rear right first, counter-
    clockwise). Returns ``body`` (V, 4, 2), ``glass`` (V, 4, 2) — the windscreen, 60–78 %
    of the way from the rear bumper to the front —, ``tail`` (V, 4, 2), the band across
    the rear lit while reversing, and ``wheels`` (V, 4, 4, 2): rear right,
    rear left, front right, front left tyres, :data:`WHEEL` in size, the rear ones centred
    on the rear axle, the front ones on the front axle and turned by ``steer``.
    """
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]

    def world(local: np.ndarray) -> np.ndarray:  # (V, K, 2) car frame → world
        wx = x[:, None] + c * local[..., 0] - s * local[..., 1]
        wy = y[:, None] + s * local[..., 0] + c * local[..., 1]
        return np.stack([wx, wy], axis=-1)

    rear, front, half = body[:, 0, 0], body[:, 1, 0], body[:, 2, 1]
    span = front - rear
    t0, t1 = rear + 0.60 * span, rear + 0.78 * span
    glass = np.stack([np.stack([t0, -0.76 * half], -1), np.stack([t1, -0.76 * half], -1),
                      np.stack([t1, 0.76 * half], -1), np.stack([t0, 0.76 * half], -1)], axis=1)
    d0, d1 = rear + 0.02, rear + REVERSE_BAND
    tail = np.stack([np.stack([d0, -0.9 * half], -1), np.stack([d1, -0.9 * half], -1),
                     np.stack([d1, 0.9 * half], -1), np.stack([d0, 0.9 * half], -1)], axis=1)
    wl, ww = WHEEL
    inset = half - ww / 2 - 0.05
    tyre = np.array([[-wl / 2, -ww / 2], [wl / 2, -ww / 2], [wl / 2, ww / 2], [-wl / 2, ww / 2]])
    wheels = []
    for axle, side, turned in ((0.0, -1, False), (0.0, 1, False), (1.0, -1, True),
                               (1.0, 1, True)):
        ang = steer if turned else np.zeros_like(steer)
        ca, sa = np.cos(ang)[:, None], np.sin(ang)[:, None]
        lx = axle * wheelbase[:, None] + ca * tyre[:, 0] - sa * tyre[:, 1]
        ly = side * inset[:, None] + sa * tyre[:, 0] + ca * tyre[:, 1]
        wheels.append(world(np.stack([lx, ly], axis=-1)))
    return {"body": world(body), "glass": world(glass), "tail": world(tail),
            "wheels": np.stack(wheels, axis=1)}


def traffic_bounds(tracks, lot: tuple[float, float, float, float],
                   met: MetDisturbances | None = None) -> tuple[float, float, float, float]:
    """The box ``(x0, y0, x1, y1)`` [m] holding every footprint of ``tracks`` (each
    rear-axle position with the car's longest reach from it), the ground the run closed and
    the cars in bays taken from outside (``met``), and :data:`VIEW_MARGIN` around it, within
    the lot's box ``lot``; the lot's box when no car moves."""
    boxes = []
    for tr in tracks:
        if len(tr.x):
            reach = math.hypot(max(tr.front, tr.rear), tr.width / 2) + VIEW_MARGIN
            boxes.append((float(np.min(tr.x)) - reach, float(np.min(tr.y)) - reach,
                          float(np.max(tr.x)) + reach, float(np.max(tr.y)) + reach))
    if not boxes:
        return lot
    if met is not None:
        for poly in [c.polygon for c in met.closures] + [b.polygon for b in met.strangers]:
            if len(poly):
                lo, hi = poly.min(axis=0) - VIEW_MARGIN, poly.max(axis=0) + VIEW_MARGIN
                boxes.append((float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])))
    b = np.array(boxes)
    return (max(lot[0], b[:, 0].min()), max(lot[1], b[:, 1].min()),
            min(lot[2], b[:, 2].max()), min(lot[3], b[:, 3].max()))


class GifRenderer:
    """Draws frames of one result.

    Parameters
    ----------
    doc : dict
        The result document (``result.json``), holding ``lot.drawing``.
    settings : GifSettings
    """

    def __init__(self, doc: dict, settings: GifSettings):
        from lotsim.io.lot_json import lot_from_json

        self.settings = settings
        self.replay = Replay(doc)
        self.lot = lot_from_json(doc["lot"]["drawing"], root="lot.drawing")
        w, h = settings.size
        self._font = font(13)
        self._clock_font = font(15)
        met = self.replay.met
        bounds = lot_bounds(self.lot)
        if settings.view == "traffic":
            bounds = traffic_bounds(self.replay.tracks, bounds, met)
        # the footer's height: a second line for the key of what the run met when the whole
        # key does not fit on one
        self.footer = FOOTER
        if settings.legend and met.kinds:
            one_line = legend_entries(len(doc["lot"]["parked"]) > 0, met.kinds)
            if key_width(one_line, self._font) > key_room(w):
                self.footer = 2 * FOOTER
        self.canvas = LotCanvas(bounds, (w, h), frame=(PAD_PX, HEADER + PAD_PX // 2,
                                                       w - PAD_PX, h - self.footer))
        self._stamps: dict = {}
        self._build_palette(doc)
        tracks = self.replay.tracks
        self.colour = assign_colours(tracks, VEHICLE_COLOURS, self.replay.end)
        self.slot_ring = {}  # closed pixel outline of each slot, as Pillow takes it
        for s in self.lot.slots:
            ring = np.rint(self.canvas.to_px(np.asarray(s.polygon, dtype=float))).astype(int)
            self.slot_ring[s.id] = np.vstack([ring, ring[:1]]).ravel().tolist()
        # trails: each vehicle's samples in pixels, runs of the same pixel cut to one
        self._trail_t, self._trail_px = [], []
        for tr in tracks:
            px = np.rint(self.canvas.to_px(np.column_stack([tr.x, tr.y]))).astype(int)
            keep = np.ones(len(px), dtype=bool)
            keep[1:] = np.any(px[1:] != px[:-1], axis=1)
            self._trail_t.append(tr.t[keep])
            self._trail_px.append(px[keep])
        self._body = np.array([[[-tr.rear, -tr.width / 2], [tr.front, -tr.width / 2],
                                [tr.front, tr.width / 2], [-tr.rear, tr.width / 2]]
                               for tr in tracks]).reshape(-1, 4, 2)
        self._wheelbase = np.array([tr.wheelbase for tr in tracks], dtype=float)
        self._met()

    def _met(self) -> None:
        """What the run met (:attr:`Replay.met`) in pixels: each closure's hatching (a
        mask) and outline, each bay taken from outside and its car's body, each stall."""
        met = self.replay.met
        w, h = self.settings.size
        hatch = Image.new("L", (w, h), 0)
        dh = ImageDraw.Draw(hatch)
        for k in range(-h, w, HATCH):
            dh.line((k, h, k + h, 0), fill=255, width=1)
        self.closures = []
        for c in met.closures:
            ring = np.rint(self.canvas.to_px(c.polygon)).astype(int)
            mask = Image.new("L", (w, h), 0)
            ImageDraw.Draw(mask).polygon(ring.ravel().tolist(), fill=255)
            self.closures.append((c.t0, c.t1, ImageChops.multiply(mask, hatch),
                                  np.vstack([ring, ring[:1]]).ravel().tolist(), c.label))
        self.strangers = [(b.t, np.rint(self.canvas.to_px(b.polygon)).astype(int).ravel()
                           .tolist()) for b in met.strangers]
        self.stalls = [(st.vehicle, st.t0, st.t1) for st in met.stalls]

    # -- the fixed picture ---------------------------------------------------------------------
    def _build_palette(self, doc: dict) -> None:
        w, h = self.settings.size
        canvas = self.canvas
        img = canvas.new_image()
        parked = np.asarray(doc["lot"]["parked"], dtype=float).reshape(-1, 4, 2)
        paint_lot(img, canvas, self.lot, parked_bodies=parked, labels=True)
        paint_portals(img, canvas, self.lot, labels=True)
        d = ImageDraw.Draw(img)
        d.rectangle((0, 0, w, HEADER - 1), fill=HEADER_BG)
        d.line((0, HEADER - 1, w, HEADER - 1), fill=(200, 200, 200))
        paint_scale_bar(img, canvas, PAD_PX, h - 6, scale_bar_width(w))
        body = np.all(np.asarray(img) == np.array(PARKED_CAR), axis=2)
        bg = img.quantize(colors=BACKGROUND_COLOURS, method=Image.Quantize.MEDIANCUT,
                          dither=Image.Dither.NONE)
        # the quantised image uses indices below BACKGROUND_COLOURS; Pillow versions differ
        # in how long a palette they report, so take exactly that many entries
        pal = list(bg.getpalette() or [])[:3 * BACKGROUND_COLOURS]
        pal += [0] * (3 * BACKGROUND_COLOURS - len(pal))
        colours = [tuple(pal[3 * k: 3 * k + 3]) for k in range(BACKGROUND_COLOURS)]
        fixed = [INK, GLASS, WHITE, TYRE, CLOSED]
        cars = vehicle_palette()
        base = len(colours)
        self.ink, self.glass, self.white, self.tyre, self.closed = range(base,
                                                                       base + len(fixed))
        self.car_index = np.arange(base + len(fixed), base + len(fixed) + len(cars))
        self.pale_index = self.car_index + len(cars)
        colours += fixed + cars + [pale(c) for c in cars]
        self.rgb = [tuple(int(v) for v in c) for c in colours]
        self.palette = bytes(np.asarray(self.rgb, dtype=np.uint8).ravel())
        bg.putpalette(self.palette)
        self.background = bg
        self.legend_boxes: dict[str, tuple[int, int, int, int]] = {}
        if self.settings.legend:
            # cars parked at start: the palette entry most of their bodies' pixels took
            at_start = (int(np.bincount(np.asarray(bg)[body]).argmax()) if body.any()
                        else None)
            self._paint_legend(bg, at_start)
        self._labels = self._portal_labels(bg)

    def _paint_legend(self, bg: Image.Image, at_start: int | None) -> None:
        """The key (:func:`~lotsim.render.colour_key.paint_key`) in the footer, on one
        line or, in a footer of two (:attr:`footer`), on two; its swatch boxes go to
        :attr:`legend_boxes`. ``at_start``: the colour of cars parked at the start."""
        entries = legend_entries(at_start is not None, self.replay.met.kinds)
        inks = KeyInks(self.ink, self.white, self.tyre, self.closed,
                       tuple(int(c) for c in self.car_index),
                       tuple(int(c) for c in self.pale_index), at_start)
        self.legend_boxes = paint_key(bg, entries, inks, font=self._font, stamp=self._stamp,
                                      line_height=FOOTER, two_lines=self.footer > FOOTER)

    def _portal_labels(self, bg: Image.Image) -> list[tuple[tuple[int, int], Image.Image,
                                                          Image.Image]]:
        """The entrance and exit ids (text and halo) as pieces of ``bg`` to paste back over
        the cars of each frame, so a car standing at a gate does not hide its name:
        ``(corner, pixels, mask)`` of the box holding them (empty without ids)."""
        mask = Image.new("1", self.settings.size, 0)
        for base in ((0, 0, 0), (255, 255, 255)):  # what the ids change on either ground
            plain = self.canvas.new_image(base)
            paint_portals(plain, self.canvas, self.lot, labels=False)
            named = plain.copy()
            paint_portals(named, self.canvas, self.lot, labels=True)
            diff = ImageChops.difference(plain, named).convert("L").point(
                lambda v: 255 if v else 0).convert("1")
            mask = ImageChops.logical_or(mask, diff)
        box = mask.getbbox()
        if box is None:
            return []
        return [(box[:2], bg.crop(box), mask.crop(box))]

    def vehicle_rgb(self, j: int, *, parked: bool = False) -> tuple[int, int, int]:
        """The colour vehicle ``j`` is drawn in while it moves (or pale, standing parked)."""
        idx = (self.pale_index if parked else self.car_index)[self.colour[j]]
        return self.rgb[int(idx)]

    # -- frames --------------------------------------------------------------------------------
    def frame(self, t: float, state: dict[str, np.ndarray] | None = None,
              column: int = 0, skipped: float = 0.0) -> Image.Image:
        """The frame at run time ``t`` (``state``: :meth:`Replay.states` rows, if at hand;
        ``skipped``: run time left out just before it, said in the header) [s]."""
        if state is None:
            state = self.replay.states(np.array([t]))
        img = self.background.copy()
        d = ImageDraw.Draw(img)
        canvas = self.canvas
        for t0, t1, mask, ring, _ in self.closures:
            if t0 <= t <= t1:
                img.paste(self.closed, (0, 0), mask)
                d.line(ring, fill=self.closed, width=2)
        for t0, ring in self.strangers:
            if t >= t0:
                d.polygon(ring, fill=self.tyre, outline=self.ink)
        vis = np.flatnonzero(state["visible"][column])
        phase = state["phase"][column, vis]
        parked_phase = PHASES.index("parked")
        still = phase == parked_phase
        moving = vis[~still]
        # trails and target slots under every car
        lw = 2 if canvas.px(0.25) >= 1.5 else 1
        trail = self.settings.trail
        here = np.rint(canvas.to_px(np.stack([state["x"][column], state["y"][column]],
                                             axis=-1))).astype(int)
        for j in moving:
            if trail > 0:
                tt, pts = self._trail_t[j], self._trail_px[j]
                a = int(np.searchsorted(tt, t - trail, side="left"))
                b = int(np.searchsorted(tt, t, side="right"))
                flat = pts[a:b].ravel().tolist() + here[j].tolist()
                if len(flat) >= 4:
                    d.line(flat, fill=int(self.pale_index[self.colour[j]]), width=lw)
            tr = self.replay.tracks[j]
            if tr.slot is not None and t < tr.parked_from and tr.slot in self.slot_ring:
                d.line(self.slot_ring[tr.slot], fill=int(self.car_index[self.colour[j]]),
                       width=2)
        # bodies: parked ones first, moving ones on top
        order = np.concatenate([vis[still], moving])
        if len(order):
            self._paint_cars(d, state, column, order, n_still=int(still.sum()))
            self._paint_stalled(d, state, column, t, set(vis.tolist()))
            for corner, pixels, mask in self._labels:  # gate names over the cars
                img.paste(pixels, corner, mask)
        self._paint_header(img, t, skipped)
        return img

    def _paint_cars(self, d: ImageDraw.ImageDraw, state: dict, column: int,
                    order: np.ndarray, n_still: int) -> None:
        canvas = self.canvas
        x, y, th = (state[k][column, order] for k in ("x", "y", "theta"))
        steer, v = state["steer"][column, order], state["v"][column, order]
        wheelbase = self._wheelbase[order]
        parts = car_parts(x, y, th, steer, self._body[order], wheelbase)

        def px(a: np.ndarray) -> np.ndarray:
            return np.rint(canvas.to_px(a)).astype(int)

        body = px(parts["body"])
        short = float(np.min(self._body[order, 1, 0] - self._body[order, 0, 0]))
        glass = px(parts["glass"]) if canvas.px(short) >= 16 else None
        wheels = px(parts["wheels"]) if canvas.px(WHEEL[0]) >= 2.5 else None
        tail = px(parts["tail"])
        for k, j in enumerate(order):
            parked = k < n_still
            fill = int((self.pale_index if parked else self.car_index)[self.colour[j]])
            d.polygon(body[k].ravel().tolist(), fill=fill, outline=self.ink, width=1)
            if wheels is not None:
                for w in wheels[k]:
                    d.polygon(w.ravel().tolist(), fill=self.tyre)
            if glass is not None:
                d.polygon(glass[k].ravel().tolist(), fill=self.glass)
            if v[k] < -1e-3:  # reversing: a white band across the rear
                d.polygon(tail[k].ravel().tolist(), fill=self.white)

    def _paint_stalled(self, d: ImageDraw.ImageDraw, state: dict, column: int, t: float,
                       visible: set[int]) -> None:
        """Outline each car stalled at ``t`` [s]."""
        stalled = np.array(sorted({j for j, t0, t1 in self.stalls
                                   if t0 <= t <= t1 and j in visible}), dtype=int)
        if not len(stalled):
            return
        x, y, th = (state[k][column, stalled] for k in ("x", "y", "theta"))
        parts = car_parts(x, y, th, state["steer"][column, stalled], self._body[stalled],
                          self._wheelbase[stalled])
        for ring in np.rint(self.canvas.to_px(parts["body"])).astype(int):
            flat = np.vstack([ring, ring[:1]]).ravel().tolist()
            d.line(flat, fill=self.ink, width=5)  # a halo that no car's colour hides
            d.line(flat, fill=self.white, width=2)

    def _paint_header(self, img: Image.Image, t: float, skipped: float = 0.0) -> None:
        counts = self.replay.counts(t)
        shown = [k for k in COUNTERS if k != "rejected" or counts[k]]
        text = "   ".join(f"{k} {counts[k]}" for k in shown)
        stalled = sum(t0 <= t <= t1 for _, t0, t1 in self.stalls)
        if stalled:
            text += f"   stalled {stalled}"
        closed = [what for t0, t1, _, _, what in self.closures if t0 <= t <= t1]
        if closed:
            text += "   " + ", ".join(closed)
        if skipped > 0:
            text += f"   >> skipped {_clock(skipped)}"
        x = PAD_PX
        for ch in _clock(t):  # the clock changes every frame: stamped glyph by glyph
            x += self._stamp(img, (x, HEADER // 2), ch, self._clock_font)
        self._stamp(img, (PAD_PX + 90, HEADER // 2), text, self._font)

    def _stamp(self, img: Image.Image, xy: tuple[int, int], text: str, f) -> int:
        """Paste ``text`` in ink, vertically centred on ``xy``; returns its advance [px].

        Rendered once per string into a two-level mask (palette frames take no
        anti-aliasing) and cached."""
        key = (text, id(f))
        hit = self._stamps.get(key)
        if hit is None:
            if len(self._stamps) > 512:
                self._stamps.clear()
            left, top, right, bottom = f.getbbox(text)
            mask = Image.new("L", (max(1, right - left + 2), max(1, bottom - top + 2)), 0)
            ImageDraw.Draw(mask).text((-left + 1, -top + 1), text, fill=255, font=f)
            mask = mask.point(lambda v: 255 if v >= 110 else 0)
            digit = f.getbbox("0")  # one centre line per font keeps glyphs on a baseline
            hit = (mask, left - 1, top - 1, (digit[1] + digit[3]) / 2,
                   int(round(f.getlength(text))))
            self._stamps[key] = hit
        mask, dx, dy, mid, advance = hit
        y = int(round(xy[1] - mid)) + dy
        img.paste(self.ink, (int(xy[0]) + dx, y), mask)
        return advance

    def frames(self, times: np.ndarray, skipped: Sequence[float] | None = None
               ) -> np.ndarray:
        """Frames at ``times`` as palette indices, shaped (len(times), height, width)
        (``skipped``: per frame, run time left out just before it [s])."""
        state = self.replay.states(times)
        w, h = self.settings.size
        out = np.empty((len(times), h, w), dtype=np.uint8)
        for k, t in enumerate(times):
            out[k] = np.asarray(self.frame(float(t), state, k,
                                           skipped[k] if skipped is not None else 0.0))
        return out

    def chunks(self, plan: FramePlan, chunk: int = CHUNK
               ) -> Iterator[tuple[int, int, np.ndarray]]:
        """The frames of ``plan`` (:meth:`frames`) ``chunk`` at a time: ``(a, b, frames)``,
        frames ``a`` to ``b - 1`` of the plan."""
        n = len(plan.times)
        for a in range(0, n, chunk):
            b = min(n, a + chunk)
            yield a, b, (self.frames(plan.times[a:b]) if plan.skipped is None
                         else self.frames(plan.times[a:b], plan.skipped[a:b]))


# -- writing -----------------------------------------------------------------------------------
@dataclass(frozen=True)
class GifInfo:
    """What :func:`write_gif` wrote."""

    path: Path
    frames: int
    """Frames drawn (identical consecutive ones are merged in the file)."""
    duration: float
    """Total display time [s]."""
    speed: float
    start: float
    end: float
    bytes: int
    skipped: float = 0.0
    """Quiet run time left out (``skip_quiet``) [s]."""


def write_gif(
    doc: dict,
    path: str | os.PathLike,
    settings: GifSettings | None = None,
    *,
    progress: Callable[[int, int], None] | None = None,
    chunk: int = CHUNK,
) -> GifInfo:
    """Render the run in ``doc`` (a result document) to the animated GIF ``path``.

    The GIF loops for ever. Nothing is left at ``path`` or beside it if this fails
    or is interrupted. ``progress(done, total)`` is called after each chunk of frames.

    Raises
    ------
    SettingsError
        When ``settings`` asks for a span outside the run (``start``/``end``).
    ReplayError, LotFormatError
        When ``doc`` is not a result that can be drawn.
    """
    settings = settings or GifSettings()
    renderer = GifRenderer(doc, settings)
    plan = plan_frames(renderer.replay, settings)
    target = Path(path)
    n = len(plan.times)

    def chunks() -> Iterator[tuple[np.ndarray, list[int]]]:
        for a, b, frames in renderer.chunks(plan, chunk):
            yield frames, plan.durations[a:b]
            if progress is not None:  # the writer asks for the next chunk once this is in
                progress(b, n)

    write_gif_chunks(target, chunks(), renderer.palette)
    return GifInfo(target, n, sum(plan.durations) / 1000.0, plan.speed, plan.start, plan.end,
                   target.stat().st_size, sum(b - a for a, b in plan.skips))
