"""Junction turns that use the junction's whole area (:func:`area_turns`): drift sideways
off the lane, turn the corner, drift back onto the other lane, as a driver does where the
turn between the lanes themselves would touch a corner slot."""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from lotsim.core.geometry import Segment, cc_polyline, sample_segments, wrap_angle
from lotsim.core.keys import inputs, key_of
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle, unit
from lotsim.lot.settings import DEFAULTS as LOT_DEFAULTS
from lotsim.roadmap.lanes import EPS
from lotsim.roadmap.model import Turn
from lotsim.roadmap.settings import DEFAULTS, AreaTurnSettings


def _approx_tangent(deflection, radius: float, sharpness: float):
    """The tangent length of a continuous-curvature turn
    (:func:`~lotsim.core.geometry.cc_turn`) by the road designers' formula,
    ``(R + p) tan(Δ/2) + L/2`` with the clothoids' shift ``p = L² / 24R`` (within 0.1 % of
    the exact one for the turns built here); ``deflection`` [rad] may be an array."""
    d = np.asarray(deflection, dtype=float)
    peak = np.minimum(1 / radius, np.sqrt(d * sharpness))
    ramp = peak / sharpness
    with np.errstate(divide="ignore", invalid="ignore"):
        out = (1 / peak + ramp * ramp * peak / 24) * np.tan(d / 2) + ramp / 2
    return np.where(d > 1e-12, out, 0.0)


def _area_designs(design, lot_speed: float, settings: AreaTurnSettings
                  ) -> list[tuple[float, float]]:
    """(radius multiple, design speed [m/s]) of the junction-area turns to try."""
    out = []
    for f in settings.radii:
        top = min(lot_speed, math.sqrt(design.max_lateral_accel * f * design.min_radius))
        out += [(f, v) for v in sorted({top, *(v for v in settings.speeds if v < top)},
                                       reverse=True)]
    return out


def area_turns(a, sa0, pa, b, sb0, pb, design, collider: Collider,
                lot_speed: float, via: tuple[Segment, ...] = (),
                shifts: tuple[float, ...] = (), *,
                settings: AreaTurnSettings = DEFAULTS.area_turns,
                sweep: float = LOT_DEFAULTS.sweep) -> list[Turn]:
    """Turns from ``pa`` into ``pb`` that use the junction's whole area, as a driver does
    where the turn between the lanes themselves touches a corner slot: drift sideways from
    the lane (wide of the corner, across the oncoming lane where need be), turn, drift back
    onto the other lane. Each line is shifted sideways by ``settings.shifts`` (positive:
    to the lane's left), the drifts take ``settings.leads``, the corners' arcs
    ``settings.radii`` (:class:`~lotsim.roadmap.settings.AreaTurnSettings`); every corner
    is continuous-curvature, sized for the arc's speed.
    With ``via`` (a lane's straight between two junctions close together) the path runs
    along that straight, shifted by ``shifts``, from one turn into the next without
    drifting back to its lane between them. A candidate is swept with footprints ``sweep``
    apart [m] (the lot's :attr:`LotSettings.sweep <lotsim.lot.settings.LotSettings.sweep>`).

    The quickest clear one (length over design speed) is built and, when it is another,
    the most compact clear one (the least lane used before and after: it starts latest and
    ends soonest, so it fits between two turns close together); none when none is clear.
    """
    lay = _Layout.of(pa, pb, via, shifts, settings)
    blocks = _candidate_blocks(lay, pa, pb, design, lot_speed, settings)
    if not blocks:
        return []
    found = _Candidates(blocks, design, collider, sweep)
    quick = found.first(np.lexsort((found.used, found.times)).tolist())
    if quick is None:
        return []
    compact = found.first(np.lexsort((found.times, found.used)).tolist())
    return [Turn(a.id, sa0 + float(found.starts[k]), b.id, sb0 + float(found.ends[k]),
                 tuple(found.paths[k]), True) for k in dict.fromkeys((quick, compact))]


def candidates_shape(pa: Segment, pb: Segment, design, lot_speed: float,
                     frame: tuple[float, float, float], *,
                     settings: AreaTurnSettings = DEFAULTS.area_turns) -> bytes:
    """What a search of :func:`area_turns` from ``pa`` into ``pb`` (no ``via``) tries, in
    ``frame`` (origin x, y [m], heading [rad]) to the micrometre: the car and every
    candidate's polyline, corner radius and clothoid sharpness. At two junctions with the
    same shape, and the same obstacles about them
    (:meth:`~lotsim.lot.clearance.Collider.local_digest`), the searches try the same
    paths against the same obstacles."""
    blocks = _candidate_blocks(_Layout.of(pa, pb, (), (), settings), pa, pb, design,
                               lot_speed, settings)
    ox, oy, heading = frame
    c, s = math.cos(heading), math.sin(heading)
    tried = []
    for pts, *_, r, sharp in blocks:
        dx, dy = pts[..., 0] - ox, pts[..., 1] - oy
        local = np.round(np.stack([c * dx + s * dy, c * dy - s * dx], axis=-1), 6) + 0.0
        tried.append((r, sharp, local))
    return key_of(AreaTurnsTried(design, lot_speed, tuple(tried)))


@inputs
class AreaTurnsTried:
    """What a search of :func:`area_turns` tries (:func:`candidates_shape`): the car, the
    lot's speed limit [m/s], and each block of candidates' corner radius [m], clothoid
    sharpness [1/m²] and polylines in the junction's frame to the micrometre."""

    design: DesignVehicle
    lot_speed: float
    blocks: tuple


@dataclass(frozen=True)
class _Layout:
    """The lines of an area turn (``pa``, the stretches ``via``, ``pb``) and, for every
    sideways shift of them and every pair of drift lengths
    (:attr:`~lotsim.roadmap.settings.AreaTurnSettings.leads`), the
    corners where the shifted lines meet and where the drifts leave and rejoin the lanes:
    arrays over the candidates, ``oi`` each one's shift."""

    via: bool
    dirs: np.ndarray
    origins: np.ndarray
    bends: np.ndarray
    params: list[np.ndarray]
    oi: np.ndarray
    ta: np.ndarray
    tb: np.ndarray
    la: np.ndarray
    lb: np.ndarray
    u: np.ndarray
    w: np.ndarray
    a1: np.ndarray
    b1: np.ndarray
    corners: list[np.ndarray]
    first_turn: np.ndarray
    last_turn: np.ndarray
    legs: list[np.ndarray]

    @classmethod
    def of(cls, pa: Segment, pb: Segment, via: tuple[Segment, ...],
           shifts: tuple[float, ...], settings: AreaTurnSettings = DEFAULTS.area_turns) -> _Layout:
        lines = (pa, *via, pb)
        dirs = np.array([unit(seg.start[2]) for seg in lines])  # (L, 2)
        normals = np.column_stack([-dirs[:, 1], dirs[:, 0]])
        origins = np.array([seg.start[:2] for seg in lines])
        heads = np.array([seg.start[2] for seg in lines])
        bends = np.abs(np.asarray(wrap_angle(np.diff(heads)), dtype=float))  # (L-1,)
        grids = [settings.shifts, *([shifts or (0.0,)] * len(via)), settings.shifts]
        offs = np.array(list(itertools.product(*grids)))  # (N, L)
        if not via:
            offs = offs[np.any(offs != 0.0, axis=1)]  # (0, 0) is the plain turn, already tried
        # corner k: where line k shifted by offs[:, k] meets line k+1 shifted by offs[:, k+1]
        corners, params = [], []
        for k in range(len(lines) - 1):
            inv = np.linalg.inv(np.column_stack([dirs[k], -dirs[k + 1]]))
            rhs = (origins[k + 1] - origins[k] + offs[:, k + 1, None] * normals[k + 1]
                   - offs[:, k, None] * normals[k])  # (N, 2)
            ts = rhs @ inv.T  # (N, 2): along line k, along line k+1
            corners.append(origins[k] + offs[:, k, None] * normals[k] + ts[:, :1] * dirs[k])
            params.append(ts)
        ta, tb = params[0][:, 0], params[-1][:, 1]
        # leads (la, lb) for every shift: index arrays over (N × leads²)
        leads = np.array(list(itertools.product(settings.leads, settings.leads)))
        n_off, n_lead = len(offs), len(leads)
        oi = np.repeat(np.arange(n_off), n_lead)
        la, lb = np.tile(leads[:, 0], n_off), np.tile(leads[:, 1], n_off)
        u, w = offs[oi, 0], offs[oi, -1]
        a1 = origins[0] + (ta[oi] - la)[:, None] * dirs[0]
        b1 = origins[-1] + (tb[oi] + lb)[:, None] * dirs[-1]
        corners_n = [c[oi] for c in corners]
        h1 = np.arctan2(*(corners_n[0] - a1).T[::-1])
        h2 = np.arctan2(*(b1 - corners_n[-1]).T[::-1])
        first_turn = np.abs(np.asarray(wrap_angle((heads[1] if via else h2) - h1), dtype=float))
        last_turn = np.abs(np.asarray(wrap_angle(h2 - (heads[-2] if via else h1)), dtype=float))
        return cls(bool(via), dirs, origins, bends, params, oi, ta, tb, la, lb, u, w, a1, b1,
                   corners_n, first_turn, last_turn, [np.hypot(la, u), np.hypot(lb, w)])


def _candidate_blocks(lay: _Layout, pa: Segment, pb: Segment, design, lot_speed: float,
                      settings: AreaTurnSettings = DEFAULTS.area_turns) -> list[tuple]:
    """The candidate area turns with room on both lanes, a block per design and shape:
    (points (M, P, 2) of their polylines, rough time [s], lane used [m], start along ``pa``
    [m], end along ``pb`` [m], corner radius [m], clothoid sharpness)."""
    blocks = []
    oi, u, w, la, lb, dirs = lay.oi, lay.u, lay.w, lay.la, lay.lb, lay.dirs
    a1, b1 = lay.a1, lay.b1
    c_first, c_last = lay.corners[0], lay.corners[-1]

    def add(ok, points, speed, da, db, r, sharp) -> None:
        # ``points(rows)``: the polylines' vertices of the candidates ``rows``
        rows = np.flatnonzero(ok)
        if len(rows):
            pts = np.stack(points(rows), axis=1)
            rough = np.hypot(*np.diff(pts, axis=1).transpose(2, 0, 1)).sum(axis=1)
            blocks.append((pts, rough / speed, db[rows] - da[rows], da[rows], db[rows], r,
                           sharp))

    ta, tb = lay.ta[oi], lay.tb[oi]
    shift_a, shift_b = u != 0.0, w != 0.0
    drift_a, drift_b = np.arctan2(np.abs(u), la), np.arctan2(np.abs(w), lb)
    # every design (radius, speed) at once, a row each: the same sums element by element
    designs = _area_designs(design, lot_speed, settings)
    radii = [f * design.min_radius for f, _ in designs]
    sharps = [design.sharpness(speed) for _, speed in designs]
    r, sharp = np.array(radii)[:, None], np.array(sharps)[:, None]
    pre = np.where(shift_a, _approx_tangent(drift_a, r, sharp) + 0.05, 0.0)
    post = np.where(shift_b, _approx_tangent(drift_b, r, sharp) + 0.05, 0.0)
    da, db = ta - la - pre, tb + lb + post
    ok = ((da >= -EPS) & (da <= pa.length + EPS) & (db >= -EPS) & (db <= pb.length + EPS)
          # the corners' turns must leave room for the drifts' (road designers' estimate
          # of the tangents; cc_polyline checks exactly)
          & (_approx_tangent(lay.first_turn, r, sharp) + pre <= lay.legs[0] * 1.01)
          & (_approx_tangent(lay.last_turn, r, sharp) + post <= lay.legs[1] * 1.01))
    if lay.via:  # the corners on the stretch in order, with room for both turns
        gap = lay.params[1][oi, 0] - lay.params[0][oi, 1]
        ok &= gap >= (_approx_tangent(lay.bends[0], r, sharp)
                      + _approx_tangent(lay.bends[1], r, sharp))
    else:
        # or: drift onto the shifted line, run along it, turn the corner, run along the
        # other shifted line, drift back (the drift ends before the corner's turn begins,
        # so a wide shift does not sharpen the corner: a big car's way round a corner slot)
        corner = _approx_tangent(lay.bends[0], r, sharp)
        g1 = np.where(shift_a, corner + pre + 0.05, 0.0)
        g2 = np.where(shift_b, corner + post + 0.05, 0.0)
        run_a, run_b = ta - g1 - la, tb + g2 + lb
        da2, db2 = run_a - pre, run_b + post
        ok2 = ((shift_a | shift_b) & (da2 >= -EPS) & (da2 <= pa.length + EPS)
               & (db2 >= -EPS) & (db2 <= pb.length + EPS)
               & (2 * pre <= lay.legs[0] * 1.01) & (2 * post <= lay.legs[1] * 1.01))
    for k, (_, speed) in enumerate(designs):
        pk, qk = pre[k], post[k]
        add(ok[k], lambda i, pk=pk, qk=qk: [
            a1[i] - dirs[0] * pk[i, None], a1[i], *(c[i] for c in lay.corners), b1[i],
            b1[i] + dirs[-1] * qk[i, None]], speed, da[k], db[k], radii[k], sharps[k])
        if lay.via:
            continue

        def shifted(i, k=k, pk=pk, qk=qk):
            on_a = lay.origins[0] + run_a[k][i, None] * dirs[0]
            on_b = lay.origins[-1] + run_b[k][i, None] * dirs[-1]
            return [on_a - dirs[0] * pk[i, None], on_a, c_first[i] - dirs[0] * g1[k][i, None],
                    c_first[i], c_last[i] + dirs[-1] * g2[k][i, None], on_b,
                    on_b + dirs[-1] * qk[i, None]]

        add(ok2[k], shifted, speed, da2[k], db2[k], radii[k], sharps[k])
    return blocks


class _Candidates:
    """The candidate area turns of :func:`_candidate_blocks` as one list, with what is found
    of each: whether it is clear of ``collider`` for ``design`` (swept with footprints
    ``sweep`` apart [m]), and its path."""

    def __init__(self, blocks: list[tuple], design, collider: Collider, sweep: float):
        self.blocks, self.design, self.collider, self.sweep = blocks, design, collider, sweep
        self.times, self.used, self.starts, self.ends = (
            np.concatenate([b[k] for b in blocks]) for k in range(1, 5))
        self.offsets = np.cumsum([0] + [len(b[1]) for b in blocks])
        self.clear: dict[int, bool] = {}
        self.paths: dict[int, list[Segment]] = {}

    def candidate(self, k: int) -> tuple[np.ndarray, float, float]:
        """Candidate ``k``'s polyline without repeated points, corner radius, sharpness."""
        j = int(np.searchsorted(self.offsets, k, side="right")) - 1
        i = k - int(self.offsets[j])
        pts, *_, r, sharp = self.blocks[j]
        row = pts[i]
        keep = np.ones(len(row), dtype=bool)
        keep[1:] = np.hypot(*np.diff(row, axis=0).T) > 1e-6
        return row[keep], r, sharp

    def first(self, order: list[int], chunk: int = 24) -> int | None:
        """The first clear candidate of ``order``: a rough pass over footprints 1 m apart
        drops most blocked ones a chunk at a time, then the sweep, in order."""
        clear, paths, design, collider = self.clear, self.paths, self.design, self.collider
        for c0 in range(0, len(order), chunk):
            part = [k for k in order[c0 : c0 + chunk] if k not in clear]
            built = []
            for k in part:
                pts, r, sharp = self.candidate(k)
                try:
                    built.append((k, cc_polyline(pts, r, sharp)))
                except ValueError:  # no room for a corner's turn on a leg
                    clear[k] = False
            if built:
                poses, of = sample_segments([sg for _, path in built for sg in path], 1.0)
                owner = np.repeat(np.arange(len(built)), [len(path) for _, path in built])[of]
                bad = collider.blocked(design.footprints(poses))
                rough = np.bincount(owner[bad], minlength=len(built)) > 0
                for (k, path), hit in zip(built, rough, strict=True):
                    if hit:
                        clear[k] = False
                    else:
                        paths[k] = path
            for k in order[c0 : c0 + chunk]:
                if k not in clear:
                    clear[k] = collider.sweep_hit(
                        design.footprints(sample_segments(paths[k], self.sweep)[0])) is None
                if clear[k]:
                    return k
        return None
