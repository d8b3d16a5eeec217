"""An interactive replay of a run: one self-contained HTML file (``lotsim render --html``).

The file holds the lot as SVG (:mod:`lotsim.render.lot_svg`: vectors, sharp at any zoom),
the vehicles' samples as JSON and the viewer's script (``replay.js`` beside this module);
it loads nothing else, so it opens from disk, offline, in any current browser. The viewer
draws every car on a canvas over the lot as the GIF does (:mod:`lotsim.render.animation`:
its footprint, wheels turned by the steer, windscreen, the white band while reversing, a
trail, its target slot; the GIF's colours, handed over from the same constants of
:mod:`lotsim.render.colour_key`), marks what the run met as the GIF does
(:attr:`~lotsim.render.replay.Replay.met`: stalled cars ringed, closed ground hatched over
its interval, the cars in bays taken from outside), and offers the GIF's colour key, play
and pause, ×1 to ×60, a time slider with a timeline of the counters under it, skip to the
next event, skip quiet stretches, zoom and pan, and a car's details on a click.

**Keeping the file small.** A result samples a moving car every 0.05 s. Here a sample is
left out wherever linear interpolation in time between the samples kept on either side
puts every corner of the car's body within ``tolerance`` (default 1 cm) of where
``result.json``'s own samples put it (its rear-axle position error plus the heading error
times the distance of the farthest corner from the rear axle), its wheels within 0.02 rad
and its speed within 0.05 m/s; samples where the gear changes are kept. Straight and
steady motion keeps two samples, a standing car its first and last. Kept numbers are
rounded (1 ms, 1 mm, 1e-4 rad for the heading, 1 mrad for the steer, 1 cm/s) and stored as
differences from the previous sample, which are short numbers in JSON. Thinning is a
Douglas–Peucker split on the largest error, done for all vehicles at once level by level.

Same result, same file: nothing in it depends on the time or the machine.
"""

from __future__ import annotations

import json
import math
import os
import string
from collections.abc import Collection
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from lotsim.core.atomic import atomic_write
from lotsim.render import lot_image as li
from lotsim.render.animation import REVERSE_BAND, WHEEL
from lotsim.render.colour_key import (
    CLOSED,
    GLASS,
    HATCH,
    INK,
    LEGEND_CARS,
    TYRE,
    VEHICLE_COLOURS,
    WHITE,
    legend_entries,
    pale,
    vehicle_palette,
)
from lotsim.render.lot_svg import lot_svg, rgb
from lotsim.render.replay import COUNTERS, PHASES, MetDisturbances, Replay, assign_colours
from lotsim.scenario import REPLAY_SPEEDS, HtmlSettings

STEER_TOLERANCE = 0.02
"""Largest error of the drawn wheel angle a left-out sample may cause [rad]."""
SPEED_TOLERANCE = 0.05
"""Largest error of the shown speed a left-out sample may cause [m/s]."""
UNITS = {"t": 1e-3, "x": 1e-3, "y": 1e-3, "theta": 1e-4, "steer": 1e-3, "v": 1e-2}
"""Unit of each stored column (its rounding)."""
VIEWER = Path(__file__).with_name("replay.js")
"""The viewer's script."""
PAGE = Path(__file__).with_name("replay_page.html")
"""The page around it (a :class:`string.Template`: ``${data}``, ``${svg}``, ...)."""
TRAIL = 8.0
"""Seconds of path drawn behind a moving car, as the GIF's default."""


def thin(t: np.ndarray, cols: dict[str, np.ndarray], reach: np.ndarray,
         starts: np.ndarray, tolerance: float) -> np.ndarray:
    """Which samples to keep so that linear interpolation between kept ones stays within
    the tolerances (module docstring); samples of many vehicles at once.

    Parameters
    ----------
    t : (N,) array
        Sample times [s], increasing within each vehicle.
    cols : dict
        ``x``, ``y`` [m], ``theta`` (unwrapped) [rad], ``steer`` [rad], ``v`` [m/s],
        ``gear``; (N,) each.
    reach : (N,) array
        Distance from the rear axle to the body's farthest corner of each sample's vehicle
        [m].
    starts : (V + 1,) int array
        Where each vehicle's samples begin (and, last, ``N``).
    tolerance : float
        Largest position error of any body corner [m].

    Returns
    -------
    (N,) bool array

    Examples
    --------
    >>> t = np.arange(5.0)
    >>> c = {"x": np.array([0, 1, 2, 3, 5.0]), "y": np.zeros(5), "theta": np.zeros(5),
    ...      "steer": np.zeros(5), "v": np.ones(5), "gear": np.ones(5)}
    >>> thin(t, c, np.zeros(5), np.array([0, 5]), 0.01).tolist()
    [True, False, False, True, True]
    """
    n = len(t)
    keep = np.zeros(n, dtype=bool)
    if n == 0:
        return keep
    first, last = starts[:-1], starts[1:] - 1
    nonempty = last >= first
    keep[first[nonempty]] = keep[last[nonempty]] = True
    gear = cols["gear"]
    change = np.flatnonzero(gear[1:] != gear[:-1])
    keep[change] = keep[change + 1] = True
    idx = np.flatnonzero(keep)
    same = np.searchsorted(starts, idx[:-1], side="right") == np.searchsorted(
        starts, idx[1:], side="right")
    a, b = idx[:-1][same], idx[1:][same]
    x, y, th, st, v = (cols[k] for k in ("x", "y", "theta", "steer", "v"))
    while len(a):
        inner = b - a - 1
        a, b, inner = a[inner > 0], b[inner > 0], inner[inner > 0]
        if not len(a):
            break
        seg = np.repeat(np.arange(len(a)), inner)
        offsets = np.concatenate([[0], np.cumsum(inner)[:-1]])
        i = a[seg] + 1 + (np.arange(len(seg)) - offsets[seg])
        ia, ib = a[seg], b[seg]
        f = (t[i] - t[ia]) / (t[ib] - t[ia])

        def miss(c: np.ndarray, i=i, ia=ia, ib=ib, f=f) -> np.ndarray:
            return np.abs(c[ia] + f * (c[ib] - c[ia]) - c[i])

        err = np.maximum.reduce([
            (np.hypot(miss(x), miss(y)) + reach[i] * miss(th)) / tolerance,
            miss(st) / STEER_TOLERANCE,
            miss(v) / SPEED_TOLERANCE,
        ])
        worst = np.maximum.reduceat(err, offsets)
        split = worst > 1.0
        if not split.any():
            break
        # the first sample of each segment where its largest error is reached
        at = err >= worst[seg] - 0.0
        hit = np.flatnonzero(at & split[seg])
        segs, first_hit = np.unique(seg[hit], return_index=True)
        m = i[hit[first_hit]]
        keep[m] = True
        a = np.concatenate([a[segs], m])
        b = np.concatenate([m, b[segs]])
    return keep


def _ints(values: np.ndarray, unit: float) -> np.ndarray:
    return np.rint(np.asarray(values, dtype=float) / unit).astype(np.int64)


def _deltas(values: np.ndarray, unit: float) -> list[int]:
    q = _ints(values, unit)
    return np.diff(q, prepend=0).tolist()


def _finite(v: float) -> float | None:
    return round(float(v), 3) if math.isfinite(v) else None


@dataclass(frozen=True)
class HtmlInfo:
    """What :func:`write_html` wrote."""

    path: Path
    bytes: int
    vehicles: int
    samples: int
    """Samples in the result."""
    kept: int
    """Samples kept in the file (the rest are within the tolerance of these)."""


def replay_data(doc: dict, settings: HtmlSettings) -> dict:
    """The viewer's data for the result ``doc``: bounds, colours, vehicles (thinned
    samples), events, quiet stretches (what the HTML file embeds as JSON)."""
    return _replay_data(doc, settings)[0]


def _replay_data(doc: dict, settings: HtmlSettings) -> tuple:
    """:func:`replay_data`, the lot model, the cars parked at start, the lot's bounds, the
    samples kept and in the result, and what the run met."""
    from lotsim.io.lot_json import lot_from_json

    replay = Replay(doc)
    lot = lot_from_json(doc["lot"]["drawing"], root="lot.drawing")
    bounds = li.lot_bounds(lot)
    tracks = replay.tracks
    parked = np.asarray(doc["lot"]["parked"], dtype=float).reshape(-1, 4, 2)
    colour = assign_colours(tracks, VEHICLE_COLOURS, replay.end)
    cars = vehicle_palette()

    # thin every vehicle's samples in one pass
    lens = np.array([len(tr.t) for tr in tracks], dtype=int)
    starts = np.concatenate([[0], np.cumsum(lens)]).astype(int)
    cat = (lambda k: np.concatenate([getattr(tr, k) for tr in tracks])  # noqa: E731
           if tracks else np.zeros(0))
    theta = (np.concatenate([np.unwrap(tr.theta) for tr in tracks]) if tracks
             else np.zeros(0))
    cols = {"x": cat("x"), "y": cat("y"), "theta": theta, "steer": cat("steer"),
            "v": cat("v"), "gear": cat("gear").astype(float)}
    reach = np.repeat([math.hypot(max(tr.front, tr.rear), tr.width / 2) for tr in tracks],
                      lens) if tracks else np.zeros(0)
    t_all = cat("t")
    keep = thin(t_all, cols, reach, starts, settings.tolerance)

    by_slot = {s.id: s for s in lot.slots}
    vehicles = []
    for j, (tr, v) in enumerate(zip(tracks, doc["vehicles"], strict=True)):
        k = np.flatnonzero(keep[starts[j]:starts[j + 1]]) + starts[j]
        samples = {name: _deltas(t_all[k] if name == "t" else cols[name][k], unit)
                   for name, unit in UNITS.items()}
        samples["gear"] = cols["gear"][k].astype(int).tolist()
        slot = by_slot.get(tr.slot) if tr.slot is not None else None
        vehicles.append({
            "id": tr.id, "type": tr.type_name, "status": tr.status,
            "reason": v.get("reason", ""), "slot": tr.slot, "entrance": v.get("entrance"),
            "arrival": round(tr.arrival, 3),
            "size": [round(tr.width, 3), round(tr.front, 3), round(tr.rear, 3),
                     round(tr.wheelbase, 3)],
            "colour": colour[j],
            "phase": [_finite(tr.entered), _finite(tr.parked_from),
                      _finite(tr.parked_until), _finite(tr.gone), _finite(tr.rejected_at)],
            "slotPolygon": (np.round(np.asarray(slot.polygon, dtype=float), 3).tolist()
                            if slot is not None else None),
            "waits": [[round(a, 3), round(b, 3)] for a, b in replay.waits(tr)],
            "s": samples,
        })
    return {
        "format": "lotsim-replay", "version": 1,
        "name": doc["lot"].get("name", ""),
        "scenario": doc.get("settings", {}).get("scenario", ""),
        "bounds": [round(float(b), 3) for b in bounds],
        "start": round(replay.start, 3), "end": round(replay.end, 3),
        "units": UNITS, "tolerance": settings.tolerance,
        "speed": settings.speed, "speeds": list(REPLAY_SPEEDS),
        "skipQuiet": settings.skip_quiet, "trail": TRAIL,
        "phases": list(PHASES), "counters": list(COUNTERS),
        "colours": {
            "car": [rgb(c) for c in cars], "pale": [rgb(pale(c)) for c in cars],
            "ink": rgb(INK), "glass": rgb(GLASS), "white": rgb(WHITE), "tyre": rgb(TYRE),
            "closed": rgb(CLOSED),
        },
        "drawing": {"wheel": list(WHEEL), "reverseBand": REVERSE_BAND, "hatch": HATCH},
        "met": _met_data(replay.met),
        "events": [round(float(e), 3) for e in replay.events()],
        "quiet": [[round(a, 3), round(b, 3)] for a, b in replay.quiet()],
        "vehicles": vehicles,
    }, lot, parked, bounds, int(keep.sum()), int(len(keep)), replay.met


def _met_data(met: MetDisturbances) -> dict:
    """What the run met, as the viewer draws it: closures (``label`` as the GIF's header
    says it, ``t0`` to ``t1`` [s], ``polygon`` [m]), the cars in bays taken from outside
    (``slot``, from ``t`` [s], their body's ``polygon``) and stalls (``car``, ``t0`` to
    ``t1`` [s])."""
    def poly(p: np.ndarray) -> list:
        return np.round(p, 3).tolist()

    return {
        "closures": [{"label": c.label, "t0": round(c.t0, 3), "t1": round(c.t1, 3),
                      "polygon": poly(c.polygon)} for c in met.closures],
        "taken": [{"slot": b.slot, "t": round(b.t, 3), "polygon": poly(b.polygon)}
                  for b in met.strangers],
        "stalls": [{"car": st.car, "t0": round(st.t0, 3), "t1": round(st.t1, 3)}
                   for st in met.stalls],
    }


def _json(obj: dict) -> str:
    """Compact JSON safe inside ``<script>`` (no ``</`` in it)."""
    text = json.dumps(obj, separators=(",", ":"), ensure_ascii=True, allow_nan=False)
    return text.replace("</", "<\\/")


HELP = ("Drag to pan, wheel to zoom; click a car for its details and path; space plays and "
        "pauses. Samples thinned within {tol:g} cm of result.json.")


def html_page(doc: dict, settings: HtmlSettings) -> tuple[str, int, int]:
    """The HTML replay of ``doc`` as text, with the samples in the result and kept."""
    data, lot, parked, bounds, kept, total, met = _replay_data(doc, settings)
    svg = lot_svg(lot, parked, bounds)
    title = data["scenario"] or data["name"] or "run"
    page = string.Template(PAGE.read_text(encoding="utf-8")).substitute(
                       title=_escape(title), svg=svg, data=_json(data),
                       script=VIEWER.read_text(encoding="utf-8").strip(),
                       ink=rgb(INK), page=rgb(li.BACKGROUND),
                       header=rgb((250, 250, 248)),
                       legend=legend_html(len(parked) > 0, met.kinds),
                       help=HELP.format(tol=settings.tolerance * 100))
    return page, total, kept


def legend_html(parked_at_start: bool, met: Collection[str] = ()) -> str:
    """The colour key of the page's bar: the GIF's entries (:func:`~lotsim.render.colour_key.
    legend_entries`, with what the run ``met``) as small SVG swatches in the colours the
    page draws with, each marked ``class="key" data-key=LABEL``, its parts ``data-part``
    (body, car — one of the cars' colours shown side by side as in the GIF —, band,
    outline, hatch, ring, halo)."""
    cars = vehicle_palette()
    car, ink = rgb(cars[0]), rgb(INK)

    def body(fill: str, stroke: str = ink) -> str:
        return (f'<rect data-part="body" x="0.5" y="1.5" width="17" height="9" '
                f'fill="{fill}" stroke="{stroke}"/>')

    def several(colours: list, x0: float = 1.0, x1: float = 17.0, y0: float = 2.0,
                y1: float = 10.0) -> str:  # each car has its own colour: a few side by side
        step = (x1 - x0) / len(colours)
        return "".join(f'<rect data-part="car" x="{x0 + k * step:.3g}" y="{y0:g}" '
                       f'width="{step:.3g}" height="{y1 - y0:g}" fill="{rgb(c)}"/>'
                       for k, c in enumerate(colours))

    hatch = "".join(  # lines x + y = c across the box (1, 1)-(17, 11), as the ground's
        f'<line data-part="hatch" x1="{max(1, c - 11):g}" y1="{c - max(1, c - 11):g}" '
        f'x2="{min(17, c - 1):g}" y2="{c - min(17, c - 1):g}" stroke="{rgb(CLOSED)}"/>'
        for c in range(5, 28, HATCH // 2 + 1))
    swatch = {
        "car": body(car) + several(cars[:LEGEND_CARS]),
        "pale": body(rgb(pale(cars[0]))) + several([pale(c) for c in cars[:LEGEND_CARS]]),
        "start": body(rgb(li.PARKED_CAR), rgb(li.PARKED_CAR_EDGE)),
        "reversing": body(car) + (f'<rect data-part="band" x="1" y="2" width="3" height="8" '
                                  f'fill="{rgb(WHITE)}"/>'),
        "slot": (f'<rect data-part="outline" x="5" y="1" width="8" height="10" fill="none" '
                 f'stroke="{car}" stroke-width="2"/>'),
        "stalled": (body(car) + several(cars[:LEGEND_CARS], 2, 16, 3, 9)
                    + f'<rect data-part="ring" x="2.5" y="3.5" width="13" height="5" '
                      f'fill="none" stroke="{rgb(WHITE)}"/>'
                    + f'<rect data-part="halo" x="1" y="1" width="16" height="10" '
                      f'fill="none" stroke="{ink}" stroke-width="2"/>'),
        "closed": (hatch + f'<rect data-part="outline" x="1" y="1" width="16" height="10" '
                           f'fill="none" stroke="{rgb(CLOSED)}" stroke-width="2"/>'),
        "taken": body(rgb(TYRE)),
    }
    return "".join(f'<span class="key" data-key="{label}"><svg width="18" height="12" '
                   f'viewBox="0 0 18 12">{swatch[kind]}</svg>{label}</span>'
                   for label, kind in legend_entries(parked_at_start, met))


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def write_html(doc: dict, path: str | os.PathLike,
               settings: HtmlSettings | None = None) -> HtmlInfo:
    """Write the HTML replay of the result ``doc`` to ``path`` (atomically).

    Raises
    ------
    ReplayError, LotFormatError
        When ``doc`` is not a result that can be drawn.
    """
    settings = settings or HtmlSettings()
    page, total, kept = html_page(doc, settings)
    data = page.encode("utf-8")
    target = Path(path)
    with atomic_write(target) as fh:
        fh.write(data)
    return HtmlInfo(target, len(data), len(doc["vehicles"]), total, kept)
