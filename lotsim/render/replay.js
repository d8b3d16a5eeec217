"use strict";
// lotsim's HTML replay viewer. Its data (the JSON above) is made by lotsim/render/html.py;
// the lot is the SVG above it. Nothing is loaded from anywhere else.
(function () {
  const D = JSON.parse(document.getElementById("replay-data").textContent);
  const C = D.colours;
  const INF = Infinity;
  const num = (v) => (v === null ? INF : v);

  function decode(a, unit) {
    const out = new Float64Array(a.length);
    let acc = 0;
    for (let i = 0; i < a.length; i++) { acc += a[i]; out[i] = acc * unit; }
    return out;
  }

  const U = D.units;
  const cars = D.vehicles.map((v) => {
    const s = v.s;
    const [w, front, rear, wb] = v.size;
    const p = v.phase.map(num);
    return {
      id: v.id, type: v.type, status: v.status, reason: v.reason, slot: v.slot,
      entrance: v.entrance, arrival: v.arrival, colour: v.colour, waits: v.waits,
      w: w, front: front, rear: rear, wb: wb, slotPolygon: v.slotPolygon,
      entered: p[0], parkedFrom: p[1], parkedUntil: p[2], gone: p[3], rejectedAt: p[4],
      t: decode(s.t, U.t), x: decode(s.x, U.x), y: decode(s.y, U.y),
      th: decode(s.theta, U.theta), st: decode(s.steer, U.steer), v: decode(s.v, U.v),
      gear: s.gear,
    };
  });

  // what the run met (as lotsim.render.replay.MetDisturbances): closed ground, the cars in
  // bays taken from outside, and each car's stalls (both ends included)
  const M = D.met;
  const byId = new Map(cars.map((c) => [c.id, c]));
  for (const c of cars) c.stalls = [];
  for (const st of M.stalls) { const c = byId.get(st.car); if (c) c.stalls.push([st.t0, st.t1]); }
  const stallAt = (c, t) => c.stalls.find(([a, b]) => a <= t && t <= b) || null;
  const closedAt = (t) => M.closures.filter((g) => g.t0 <= t && t <= g.t1);

  // -- where is everybody (as lotsim.render.replay.Replay) ------------------------------------------
  function phaseAt(c, t) {
    const leaveFrom = isFinite(c.parkedFrom) ? c.parkedUntil : c.gone;
    if (t >= c.arrival && t < Math.min(c.entered, c.rejectedAt)) return "outside";
    if (t >= c.entered && t < Math.min(c.parkedFrom, c.gone)) return "driving";
    if (t >= c.parkedFrom && t < c.parkedUntil) return "parked";
    if (t >= leaveFrom && t < c.gone) return "leaving";
    return null;
  }

  function poseAt(c, t) {
    const T = c.t, n = T.length;
    if (!n) return null;
    const last = c.status === "departed" ? T[n - 1] : INF;
    const visible = t >= T[0] && t <= last;
    let lo = 0, hi = n - 1;
    if (t <= T[0]) hi = 0;
    else if (t >= T[n - 1]) lo = hi = n - 1;
    else {
      while (hi - lo > 1) { const m = (lo + hi) >> 1; if (T[m] <= t) lo = m; else hi = m; }
    }
    const span = T[hi] - T[lo];
    const f = span > 0 ? Math.min(Math.max((t - T[lo]) / span, 0), 1) : 0;
    const at = (a) => a[lo] + f * (a[hi] - a[lo]);
    return { visible: visible, i: lo, x: at(c.x), y: at(c.y), theta: at(c.th),
      steer: at(c.st), v: at(c.v), gear: f < 1 && span > 0 ? c.gear[lo] : c.gear[hi] };
  }

  function counts(t) {
    const out = {};
    for (const k of D.counters) out[k] = 0;
    for (const c of cars) {
      if (c.arrival > t) continue;
      out.arrived++;
      if (c.rejectedAt <= t) out.rejected++;
      else if (c.gone <= t) out.departed++;
      else if (c.entered > t) out.waiting++;
      else if (c.parkedFrom <= t && t < c.parkedUntil) out.parked++;
      else out.driving++;
    }
    return out;
  }

  // -- the page ----------------------------------------------------------------------------------
  const $ = (id) => document.getElementById(id);
  const view = $("view"), svg = $("lot"), canvas = $("cars"), ctx = canvas.getContext("2d");
  const panel = $("panel"), tip = $("tip"), slider = $("slider"), clock = $("clock");
  const tl = $("timeline"), tctx = tl.getContext("2d");
  const playBtn = $("play"), speedSel = $("speed"), quietBox = $("quiet");
  const skippedEl = $("skipped"), countsEl = $("counts");
  const state = {
    t: D.start, playing: false, speed: D.speed, skipQuiet: D.skipQuiet, selected: null,
    s: 1, ox: 0, oy: 0, W: 0, H: 0, dpr: 1, dirty: true, last: null, frames: 0,
    skippedUntil: 0, skippedText: "",
  };
  slider.min = D.start; slider.max = D.end; slider.value = D.start;
  for (const sp of D.speeds) {
    const o = document.createElement("option");
    o.value = sp; o.textContent = "\u00d7" + sp;
    if (sp === D.speed) o.selected = true;
    speedSel.appendChild(o);
  }
  quietBox.checked = D.skipQuiet;

  function clockText(t) {
    const sign = t < 0 ? "-" : "";
    t = Math.abs(t);
    const h = Math.floor(t / 3600), m = Math.floor((t % 3600) / 60), s = t % 60;
    const ss = (s < 10 ? "0" : "") + s.toFixed(1);
    const mm = (m < 10 ? "0" : "") + m;
    return h >= 1 ? sign + h + ":" + mm + ":" + ss : sign + mm + ":" + ss;
  }

  // -- the view: metres to CSS pixels ------------------------------------------------------------
  const toPx = (x, y) => [state.ox + x * state.s, state.oy - y * state.s];
  const toWorld = (px, py) => [(px - state.ox) / state.s, (state.oy - py) / state.s];

  function resize() {
    const r = view.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    const fitBefore = state.W === 0;
    state.W = Math.max(1, r.width); state.H = Math.max(1, r.height); state.dpr = dpr;
    canvas.width = Math.round(state.W * dpr); canvas.height = Math.round(state.H * dpr);
    const tr = tl.getBoundingClientRect();
    tl.width = Math.max(1, Math.round(tr.width * dpr));
    tl.height = Math.max(1, Math.round(tr.height * dpr));
    if (fitBefore) fit(); else applyView();
    drawTimelineBase();
  }

  function fit() {
    // as lotsim's LotCanvas: the lot's rectangle, aspect kept, centred, 14 px margins
    const [minx, miny, maxx, maxy] = D.bounds, M = 14;
    const bw = Math.max(maxx - minx, 1e-9), bh = Math.max(maxy - miny, 1e-9);
    const fw = Math.max(state.W - 2 * M, 1), fh = Math.max(state.H - 2 * M, 1);
    state.s = Math.min(fw / bw, fh / bh);
    state.ox = M + (fw - bw * state.s) / 2 - minx * state.s;
    state.oy = M + (fh - bh * state.s) / 2 + maxy * state.s;
    applyView();
  }

  function applyView() {
    const s = state.s;
    svg.setAttribute("viewBox", [-state.ox / s, -state.oy / s, state.W / s, state.H / s]
      .map((v) => v.toFixed(6)).join(" "));
    state.dirty = true;
  }

  function zoomAt(px, py, factor) {
    const s = Math.min(Math.max(state.s * factor, 0.05), 2000);
    const [wx, wy] = toWorld(px, py);
    state.s = s;
    state.ox = px - wx * s; state.oy = py + wy * s;
    applyView();
  }

  // -- drawing the cars (as lotsim.render.animation's GIF frames) --------------------------
  function poly(pts) {
    ctx.beginPath();
    ctx.moveTo(pts[0], pts[1]);
    for (let k = 2; k < pts.length; k += 2) ctx.lineTo(pts[k], pts[k + 1]);
    ctx.closePath();
  }

  function carPx(c, p, local) {  // car-frame points [[x, y], ...] to flat pixel coordinates
    const co = Math.cos(p.theta), si = Math.sin(p.theta), out = [];
    for (const [lx, ly] of local) {
      const wx = p.x + co * lx - si * ly, wy = p.y + si * lx + co * ly;
      out.push(state.ox + wx * state.s, state.oy - wy * state.s);
    }
    return out;
  }

  function drawCar(c, p, parked) {
    const h = c.w / 2, s = state.s;
    const body = carPx(c, p, [[-c.rear, -h], [c.front, -h], [c.front, h], [-c.rear, h]]);
    poly(body);
    ctx.fillStyle = parked ? C.pale[c.colour] : C.car[c.colour];
    ctx.fill();
    ctx.lineWidth = 1; ctx.strokeStyle = C.ink; ctx.stroke();
    const [wl, ww] = D.drawing.wheel;
    if (s * wl >= 2.5) {
      const inset = h - ww / 2 - 0.05;
      ctx.fillStyle = C.tyre;
      for (const [axle, side, turned] of [[0, -1, 0], [0, 1, 0], [1, -1, 1], [1, 1, 1]]) {
        const a = turned ? p.steer : 0, ca = Math.cos(a), sa = Math.sin(a);
        const tyre = [[-wl / 2, -ww / 2], [wl / 2, -ww / 2], [wl / 2, ww / 2], [-wl / 2, ww / 2]]
          .map(([x, y]) => [axle * c.wb + ca * x - sa * y, side * inset + sa * x + ca * y]);
        poly(carPx(c, p, tyre)); ctx.fill();
      }
    }
    const span = c.front + c.rear;
    if (s * span >= 16) {
      const t0 = -c.rear + 0.60 * span, t1 = -c.rear + 0.78 * span, g = 0.76 * h;
      poly(carPx(c, p, [[t0, -g], [t1, -g], [t1, g], [t0, g]]));
      ctx.fillStyle = C.glass; ctx.fill();
    }
    if (p.v < -1e-3) {  // reversing: a white band across the rear
      const d0 = -c.rear + 0.02, d1 = -c.rear + D.drawing.reverseBand, g = 0.9 * h;
      poly(carPx(c, p, [[d0, -g], [d1, -g], [d1, g], [d0, g]]));
      ctx.fillStyle = C.white; ctx.fill();
    }
  }

  function groundPx(polygon) {  // world polygon [[x, y], ...] to flat pixel coordinates
    const out = [];
    for (const [x, y] of polygon) out.push(...toPx(x, y));
    return out;
  }

  function drawClosed(g) {  // hatched and outlined, as the GIF draws closed ground
    const pts = groundPx(g.polygon), h = D.drawing.hatch;
    let x0 = INF, y0 = INF, x1 = -INF, y1 = -INF;
    for (let k = 0; k < pts.length; k += 2) {
      x0 = Math.min(x0, pts[k]); x1 = Math.max(x1, pts[k]);
      y0 = Math.min(y0, pts[k + 1]); y1 = Math.max(y1, pts[k + 1]);
    }
    ctx.save();
    poly(pts); ctx.clip();
    // lines x + y = c on the screen, h pixels apart, anchored to the ground as it is panned
    const base = state.ox + state.oy;
    ctx.beginPath();
    for (let c = base + Math.ceil((x0 + y0 - base) / h) * h; c <= x1 + y1; c += h) {
      ctx.moveTo(c - y1, y1); ctx.lineTo(c - y0, y0);
    }
    ctx.strokeStyle = C.closed; ctx.lineWidth = 1; ctx.stroke();
    ctx.restore();
    poly(pts); ctx.strokeStyle = C.closed; ctx.lineWidth = 2; ctx.stroke();
  }

  function drawStalled(c, p) {  // ringed in white on an ink halo that no car's colour hides
    const h = c.w / 2;
    poly(carPx(c, p, [[-c.rear, -h], [c.front, -h], [c.front, h], [-c.rear, h]]));
    ctx.strokeStyle = C.ink; ctx.lineWidth = 5; ctx.stroke();
    ctx.strokeStyle = C.white; ctx.lineWidth = 2; ctx.stroke();
  }

  function pathLine(c, i0, i1, p) {  // samples i0..i1 (and the current pose) as one line
    ctx.beginPath();
    let started = false;
    for (let i = i0; i <= i1; i++) {
      const [px, py] = toPx(c.x[i], c.y[i]);
      if (started) ctx.lineTo(px, py); else { ctx.moveTo(px, py); started = true; }
    }
    if (p) { const [px, py] = toPx(p.x, p.y); if (started) ctx.lineTo(px, py); }
  }

  function lowerIndex(T, t) {  // first index with T[i] >= t
    let lo = 0, hi = T.length;
    while (lo < hi) { const m = (lo + hi) >> 1; if (T[m] < t) lo = m + 1; else hi = m; }
    return lo;
  }

  function draw() {
    const t = state.t, dpr = state.dpr;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.lineJoin = "round";
    const [x0, y1] = toWorld(-20, -20), [x1, y0] = toWorld(state.W + 20, state.H + 20);
    const still = [], moving = [];
    for (const c of cars) {
      const ph = phaseAt(c, t);
      const p = poseAt(c, t);
      if (!p || !p.visible) continue;
      const r = c.front + c.rear;
      if (p.x < x0 - r || p.x > x1 + r || p.y < y0 - r || p.y > y1 + r) continue;
      (ph === "parked" ? still : moving).push([c, p]);
    }
    for (const g of closedAt(t)) drawClosed(g);
    for (const b of M.taken) {  // the car the plan does not know, in its bay from its time
      if (t < b.t) continue;
      poly(groundPx(b.polygon));
      ctx.fillStyle = C.tyre; ctx.fill(); ctx.lineWidth = 1; ctx.strokeStyle = C.ink; ctx.stroke();
    }
    const lw = state.s * 0.25 >= 1.5 ? 2 : 1;
    for (const [c, p] of moving) {  // trails and target slots under every car
      if (D.trail > 0) {
        const a = lowerIndex(c.t, t - D.trail);
        pathLine(c, a, p.i, p);
        ctx.strokeStyle = C.pale[c.colour]; ctx.lineWidth = lw; ctx.stroke();
      }
      if (c.slotPolygon && t < c.parkedFrom) {
        const pts = [];
        for (const [x, y] of c.slotPolygon) pts.push(...toPx(x, y));
        poly(pts); ctx.strokeStyle = C.car[c.colour]; ctx.lineWidth = 2; ctx.stroke();
      }
    }
    const sel = state.selected;
    if (sel && sel.t.length) {  // the selected car's whole path
      pathLine(sel, 0, sel.t.length - 1, null);
      ctx.strokeStyle = C.ink; ctx.lineWidth = 4; ctx.globalAlpha = 0.35; ctx.stroke();
      ctx.globalAlpha = 1; ctx.strokeStyle = C.car[sel.colour]; ctx.lineWidth = 2; ctx.stroke();
    }
    for (const [c, p] of still) drawCar(c, p, true);
    for (const [c, p] of moving) drawCar(c, p, false);
    for (const [c, p] of still.concat(moving)) if (stallAt(c, t)) drawStalled(c, p);
    if (sel) {
      const p = poseAt(sel, t);
      if (p && p.visible) {
        const h = sel.w / 2 + 0.3;
        poly(carPx(sel, p, [[-sel.rear - 0.3, -h], [sel.front + 0.3, -h], [sel.front + 0.3, h],
          [-sel.rear - 0.3, h]]));
        ctx.setLineDash([4, 3]); ctx.strokeStyle = C.ink; ctx.lineWidth = 1.5; ctx.stroke();
        ctx.setLineDash([]);
      }
    }
    state.frames++;
    // clock, counters, slider, timeline cursor, panel
    clock.textContent = clockText(t);
    const n = counts(t);
    const shown = D.counters.filter((k) => k !== "rejected" || n[k]);
    const said = shown.map((k) => (k === "rejected" ? "turned away" : k) + " " + n[k]);
    const stalled = M.stalls.filter((st) => st.t0 <= t && t <= st.t1).length;
    if (stalled) said.push("stalled " + stalled);  // as the GIF's header
    const closed = closedAt(t).map((g) => g.label);
    if (closed.length) said.push(closed.join(", "));
    countsEl.textContent = said.join("   ");
    if (document.activeElement !== slider) slider.value = t;
    skippedEl.textContent = performance.now() < state.skippedUntil ? state.skippedText : "";
    drawTimelineCursor();
    showPanel();
  }

  // -- the timeline under the slider: cars driving, parked, waiting; events; quiet stretches --
  let timelineBase = null;
  function drawTimelineBase() {
    const W = tl.width, H = tl.height;
    if (W < 2) return;
    tctx.setTransform(1, 0, 0, 1, 0, 0);
    tctx.clearRect(0, 0, W, H);
    tctx.fillStyle = "#ffffff"; tctx.fillRect(0, 0, W, H);
    const span = Math.max(D.end - D.start, 1e-9);
    const X = (t) => ((t - D.start) / span) * (W - 1);
    tctx.fillStyle = "#ecebe4";
    for (const [a, b] of D.quiet) tctx.fillRect(X(a), 0, Math.max(1, X(b) - X(a)), H);
    const cols = [], peak = [1];
    for (let k = 0; k < W; k++) {
      const n = counts(D.start + (k / Math.max(W - 1, 1)) * span);
      cols.push(n); peak.push(n.driving + n.parked + n.waiting);
    }
    const top = Math.max(...peak), sy = (H - 8) / top;
    const layers = [["parked", C.pale[0]], ["driving", C.car[0]], ["waiting", C.car[3]]];
    for (let k = 0; k < W; k++) {
      let y = H;
      for (const [key, colour] of layers) {
        const h = cols[k][key] * sy;
        if (h > 0) { tctx.fillStyle = colour; tctx.fillRect(k, y - h, 1, h); y -= h; }
      }
    }
    tctx.fillStyle = C.ink;
    for (const e of D.events) tctx.fillRect(Math.round(X(e)), 0, 1, 4);
    timelineBase = tctx.getImageData(0, 0, W, H);
  }

  function drawTimelineCursor() {
    if (!timelineBase) return;
    tctx.putImageData(timelineBase, 0, 0);
    const W = tl.width, H = tl.height;
    const x = ((state.t - D.start) / Math.max(D.end - D.start, 1e-9)) * (W - 1);
    tctx.fillStyle = "#d00000"; tctx.fillRect(Math.round(x) - 1, 0, 2 * state.dpr, H);
  }

  // -- a car's details -------------------------------------------------------------------------
  function waitedBy(c, t) {
    let queued = 0, standing = 0;
    if (t >= c.arrival) queued = Math.max(0, Math.min(t, c.entered, c.rejectedAt) - c.arrival);
    for (const [a, b] of c.waits) if (t > a) standing += Math.min(t, b) - a;
    return [queued, standing];
  }

  function panelText(c) {
    const t = state.t, ph = phaseAt(c, t), p = poseAt(c, t);
    const stall = p && p.visible ? stallAt(c, t) : null;
    const now = stall ? "stalled (" + clockText(stall[0]) + " to " + clockText(stall[1]) + ")"
      : ph || (c.rejectedAt <= t ? "turned away" : c.gone <= t ? "gone"
        : t < c.arrival ? "not arrived yet" : c.status);
    const [q, st] = waitedBy(c, t);
    const park = isFinite(c.parkedFrom)
      ? (t >= c.parkedFrom ? (c.parkedFrom - c.arrival).toFixed(1) + " s" : "not yet")
      : "never";
    const lines = [
      "car " + c.id + " (" + c.type + ")",
      "status: " + c.status + (c.reason ? " \u2014 " + c.reason : ""),
      "now: " + now,
      "slot: " + (c.slot === null ? "none" : c.slot) + "   entrance: " + c.entrance,
      "arrival: " + clockText(c.arrival),
      "time waited: " + (q + st).toFixed(1) + " s (queued " + q.toFixed(1) + ", standing "
        + st.toFixed(1) + ")",
      "time to park: " + park,
    ];
    if (p && p.visible && (ph === "driving" || ph === "leaving" || ph === "parked")) {
      const gear = p.gear > 0 ? "forward" : p.gear < 0 ? "reverse" : "standing";
      lines.push("speed: " + (Math.abs(p.v) * 3.6).toFixed(1) + " km/h   gear: " + gear);
      lines.push("steer: " + (p.steer * 180 / Math.PI).toFixed(1) + "\u00b0");
    } else {
      lines.push("speed: \u2014   gear: \u2014", "steer: \u2014");
    }
    return lines.join("\n");
  }

  function showPanel() {
    const c = state.selected;
    if (!c) { panel.style.display = "none"; return; }
    const text = panelText(c);
    if (panel.textContent !== text) panel.textContent = text;
    panel.style.display = "block";
  }

  function carAt(px, py) {  // the car drawn on top at this pixel, if any
    const [wx, wy] = toWorld(px, py), t = state.t;
    let hit = null, hitMoving = false;
    for (const c of cars) {
      const p = poseAt(c, t);
      if (!p || !p.visible) continue;
      const dx = wx - p.x, dy = wy - p.y, co = Math.cos(p.theta), si = Math.sin(p.theta);
      const lx = co * dx + si * dy, ly = -si * dx + co * dy;
      if (lx >= -c.rear && lx <= c.front && Math.abs(ly) <= c.w / 2) {
        const moving = phaseAt(c, t) !== "parked";
        if (!hit || moving || !hitMoving) { hit = c; hitMoving = moving; }
      }
    }
    return hit;
  }

  // -- time ---------------------------------------------------------------------------------------
  function setTime(t) {
    state.t = Math.min(Math.max(t, D.start), D.end);
    state.dirty = true;
  }

  function quietEnd(t) {  // the end of the quiet stretch t is in, or null
    for (const [a, b] of D.quiet) if (t >= a && t < b) return b;
    return null;
  }

  function setPlaying(on) {
    if (on && state.t >= D.end) setTime(D.start);
    state.playing = on;
    state.last = null;
    playBtn.innerHTML = on ? "&#10073;&#10073; pause" : "&#9654; play";
  }

  function nextEvent() {
    for (const e of D.events) if (e > state.t + 1e-6) { setTime(e); return; }
    setTime(D.end);
  }

  function tick(now) {
    if (state.playing) {
      if (state.last !== null) {
        let t = state.t + ((now - state.last) / 1000) * state.speed;
        if (state.skipQuiet) {
          const b = quietEnd(t);
          if (b !== null) {
            state.skippedText = "skipped " + clockText(b - t) + " in which no car moved";
            state.skippedUntil = now + 1500;
            t = b;
          }
        }
        setTime(t);
        if (t >= D.end) setPlaying(false);
      }
      state.last = now;
    }
    if (state.dirty || (state.skippedUntil && now >= state.skippedUntil)) {
      if (now >= state.skippedUntil) state.skippedUntil = 0;
      state.dirty = false;
      draw();
    }
    requestAnimationFrame(tick);
  }

  // -- input ---------------------------------------------------------------------------------------
  playBtn.addEventListener("click", () => setPlaying(!state.playing));
  speedSel.addEventListener("change", () => { state.speed = Number(speedSel.value); });
  quietBox.addEventListener("change", () => { state.skipQuiet = quietBox.checked; });
  $("next").addEventListener("click", nextEvent);
  $("fit").addEventListener("click", fit);
  slider.addEventListener("input", () => setTime(Number(slider.value)));
  tl.addEventListener("pointerdown", (e) => {
    const r = tl.getBoundingClientRect();
    setTime(D.start + ((e.clientX - r.left) / Math.max(r.width, 1)) * (D.end - D.start));
  });
  document.addEventListener("keydown", (e) => {
    // a focused control takes its own keys (space on a button clicks it)
    if (e.target && ["SELECT", "BUTTON", "INPUT"].includes(e.target.tagName)) return;
    if (e.key === " ") { setPlaying(!state.playing); e.preventDefault(); }
    else if (e.key === "n") nextEvent();
    else if (e.key === "f") fit();
  });
  view.addEventListener("wheel", (e) => {
    const r = view.getBoundingClientRect();
    zoomAt(e.clientX - r.left, e.clientY - r.top, Math.exp(-e.deltaY * 0.0015));
    e.preventDefault();
  }, { passive: false });
  let drag = null;
  view.addEventListener("pointerdown", (e) => {
    if (e.target === panel) return;
    drag = { x: e.clientX, y: e.clientY, ox: state.ox, oy: state.oy, moved: false };
    view.setPointerCapture(e.pointerId);
  });
  view.addEventListener("pointermove", (e) => {
    const r = view.getBoundingClientRect(), px = e.clientX - r.left, py = e.clientY - r.top;
    if (drag) {
      const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      if (Math.abs(dx) + Math.abs(dy) > 3) { drag.moved = true; view.classList.add("drag"); }
      if (drag.moved) { state.ox = drag.ox + dx; state.oy = drag.oy + dy; applyView(); }
      return;
    }
    const c = carAt(px, py);
    if (c) {
      tip.textContent = c.id + " \u2014 " + (stallAt(c, state.t) ? "stalled"
        : phaseAt(c, state.t) || c.status);
      tip.style.left = px + 12 + "px"; tip.style.top = py + 12 + "px";
      tip.style.display = "block"; view.style.cursor = "pointer";
    } else { tip.style.display = "none"; view.style.cursor = ""; }
  });
  view.addEventListener("pointerup", (e) => {
    if (!drag) return;
    const r = view.getBoundingClientRect();
    if (!drag.moved) {
      state.selected = carAt(e.clientX - r.left, e.clientY - r.top);
      draw();
    }
    drag = null;
    view.classList.remove("drag");
  });
  view.addEventListener("pointerleave", () => { tip.style.display = "none"; });
  window.addEventListener("resize", resize);

  // -- for scripts and tests: inert unless called --------------------------------------------
  window.lotsimReplay = {
    time: () => state.t,
    setTime: (t) => { setTime(t); draw(); state.dirty = false; return state.t; },
    play: () => setPlaying(true),
    pause: () => setPlaying(false),
    playing: () => state.playing,
    select: (id) => { state.selected = cars.find((c) => c.id === id) || null; draw(); },
    selected: () => (state.selected ? state.selected.id : null),
    panel: () => (panel.style.display === "none" ? "" : panel.textContent),
    pose: (id) => { const c = cars.find((k) => k.id === id); return c ? poseAt(c, state.t) : null; },
    toScreen: (x, y) => toPx(x, y),
    view: () => ({ s: state.s, ox: state.ox, oy: state.oy, width: state.W, height: state.H }),
    counts: () => counts(state.t),
    pixel: (px, py) => Array.from(ctx.getImageData(Math.floor(px * state.dpr),
      Math.floor(py * state.dpr), 1, 1).data),
    frames: () => state.frames,
    readyAt: 0,
  };
  resize();
  draw();
  window.lotsimReplay.readyAt = performance.now();  // since the page began to load [ms]
  requestAnimationFrame(tick);
})();
