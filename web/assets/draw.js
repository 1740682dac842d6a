// The path on a canvas: the spooled (corrected) elements as a wide
// light-blue band, the executed trail as a thin red dashed line, the
// colours of `addipos plot`. Everything received is kept; what is drawn
// is thinned: a point closer than a pixel to the last one drawn is left
// out, arcs become as many chords as their size in pixels needs. New
// entries are drawn on top of what is there; the whole is redrawn only
// when the picture must be scaled anew (the path or the machine left the
// view, or the canvas changed size).
"use strict";

window.addiposDraw = (function () {
  const CORRECTED = { colour: "#8cf", width: 5, dash: [] };
  const RAPID = { colour: "#8cf", width: 4, dash: [6, 4] };
  const EXECUTED = { colour: "#d22", width: 1.2, dash: [5, 3] };
  const PIXEL = 1.0;
  const MARGIN = 24;

  const spooled = [];   // {from:[h,v], to:[h,v], arc:[[ch,cv],ccw]|null, rapid}
  const executed = [];  // [h, v]
  let machine = null;   // [h, v]
  let view = null;      // {minH, minV, scale, width, height}
  let drawnSpooled = 0;
  let drawnExecuted = 0;
  let pending = false;

  const canvas = document.getElementById("path");
  const marker = document.getElementById("path-marker");

  function bounds() {
    let b = null;
    function take(p) {
      if (!b) { b = { minH: p[0], maxH: p[0], minV: p[1], maxV: p[1] }; return; }
      if (p[0] < b.minH) { b.minH = p[0]; }
      if (p[0] > b.maxH) { b.maxH = p[0]; }
      if (p[1] < b.minV) { b.minV = p[1]; }
      if (p[1] > b.maxV) { b.maxV = p[1]; }
    }
    spooled.forEach(function (e) {
      take(e.from); take(e.to);
      if (e.arc) {
        const r = Math.hypot(e.from[0] - e.arc[0][0], e.from[1] - e.arc[0][1]);
        take([e.arc[0][0] - r, e.arc[0][1] - r]);
        take([e.arc[0][0] + r, e.arc[0][1] + r]);
      }
    });
    executed.forEach(take);
    if (machine) { take(machine); }
    return b;
  }

  function fitted() {
    const w = canvas.clientWidth || canvas.width;
    const h = canvas.clientHeight || canvas.height;
    const b = bounds();
    if (!b) { return null; }
    // A quarter more room each way, so that a path growing does not
    // rescale the picture at every step.
    const spanH = Math.max(b.maxH - b.minH, 1e-3);
    const spanV = Math.max(b.maxV - b.minV, 1e-3);
    const padH = spanH * 0.125, padV = spanV * 0.125;
    const scale = Math.min((w - 2 * MARGIN) / (spanH + 2 * padH), (h - 2 * MARGIN) / (spanV + 2 * padV));
    const cH = (b.minH + b.maxH) / 2, cV = (b.minV + b.maxV) / 2;
    return { cH: cH, cV: cV, scale: scale, width: w, height: h };
  }

  function px(p) {
    return [view.width / 2 + (p[0] - view.cH) * view.scale,
            view.height / 2 - (p[1] - view.cV) * view.scale];
  }

  function inside(p) {
    const q = px(p);
    return q[0] >= 2 && q[0] <= view.width - 2 && q[1] >= 2 && q[1] <= view.height - 2;
  }

  // The points of an element in pixels: its chords for an arc.
  function points(e) {
    if (!e.arc) { return [px(e.from), px(e.to)]; }
    const c = e.arc[0], ccw = e.arc[1];
    const r = Math.hypot(e.from[0] - c[0], e.from[1] - c[1]);
    let a0 = Math.atan2(e.from[1] - c[1], e.from[0] - c[0]);
    let a1 = Math.atan2(e.to[1] - c[1], e.to[0] - c[0]);
    let sweep = a1 - a0;
    if (ccw && sweep <= 0) { sweep += 2 * Math.PI; }
    if (!ccw && sweep >= 0) { sweep -= 2 * Math.PI; }
    const n = Math.max(1, Math.min(256, Math.ceil(Math.abs(sweep) * r * view.scale / 3)));
    const out = [];
    for (let i = 0; i <= n; i++) {
      const a = a0 + sweep * i / n;
      out.push(px([c[0] + r * Math.cos(a), c[1] + r * Math.sin(a)]));
    }
    out[n] = px(e.to);
    return out;
  }

  function stroke(ctx, look) {
    ctx.strokeStyle = look.colour;
    ctx.lineWidth = look.width;
    ctx.setLineDash(look.dash);
    ctx.lineJoin = "round";
    ctx.lineCap = "round";
  }

  // Draws spooled elements from index `from`, thinned, one stroke per run
  // of elements of one kind.
  function drawSpooled(ctx, from) {
    let last = null, look = null;
    for (let i = from; i < spooled.length; i++) {
      const e = spooled[i];
      const want = e.rapid ? RAPID : CORRECTED;
      const pts = points(e);
      if (look !== want || !last || Math.hypot(pts[0][0] - last[0], pts[0][1] - last[1]) > PIXEL) {
        if (look) { ctx.stroke(); }
        look = want;
        stroke(ctx, look);
        ctx.beginPath();
        ctx.moveTo(pts[0][0], pts[0][1]);
        last = pts[0];
      }
      for (let k = 1; k < pts.length; k++) {
        const p = pts[k];
        if (Math.hypot(p[0] - last[0], p[1] - last[1]) >= PIXEL || k === pts.length - 1 && i === spooled.length - 1) {
          ctx.lineTo(p[0], p[1]);
          last = p;
        }
      }
    }
    if (look) { ctx.stroke(); }
  }

  function drawExecuted(ctx, from) {
    if (executed.length - from < 1) { return; }
    const start = Math.max(0, from - 1);
    stroke(ctx, EXECUTED);
    ctx.beginPath();
    let last = px(executed[start]);
    ctx.moveTo(last[0], last[1]);
    for (let i = start + 1; i < executed.length; i++) {
      const p = px(executed[i]);
      if (Math.hypot(p[0] - last[0], p[1] - last[1]) >= PIXEL || i === executed.length - 1) {
        ctx.lineTo(p[0], p[1]);
        last = p;
      }
    }
    ctx.stroke();
  }

  function drawMarker() {
    const w = view ? view.width : canvas.width, h = view ? view.height : canvas.height;
    marker.width = w; marker.height = h;
    const ctx = marker.getContext("2d");
    ctx.clearRect(0, 0, w, h);
    if (!view || !machine) { return; }
    const p = px(machine);
    ctx.fillStyle = "#263238";
    ctx.beginPath();
    ctx.arc(p[0], p[1], 4.5, 0, 2 * Math.PI);
    ctx.fill();
  }

  function redraw() {
    view = fitted();
    if (!view) { return; }
    canvas.width = view.width;
    canvas.height = view.height;
    const ctx = canvas.getContext("2d");
    ctx.clearRect(0, 0, view.width, view.height);
    drawSpooled(ctx, 0);
    drawExecuted(ctx, 0);
    drawnSpooled = spooled.length;
    drawnExecuted = executed.length;
  }

  function needsRefit() {
    if (!view) { return true; }
    if ((canvas.clientWidth || canvas.width) !== view.width ||
        (canvas.clientHeight || canvas.height) !== view.height) { return true; }
    for (let i = drawnSpooled; i < spooled.length; i++) {
      if (!inside(spooled[i].from) || !inside(spooled[i].to)) { return true; }
    }
    for (let i = drawnExecuted; i < executed.length; i++) {
      if (!inside(executed[i])) { return true; }
    }
    return machine !== null && !inside(machine);
  }

  function frame() {
    pending = false;
    if (needsRefit()) {
      redraw();
    } else {
      const ctx = canvas.getContext("2d");
      drawSpooled(ctx, drawnSpooled);
      drawExecuted(ctx, drawnExecuted);
      drawnSpooled = spooled.length;
      drawnExecuted = executed.length;
    }
    drawMarker();
  }

  function later() {
    if (!pending) {
      pending = true;
      window.requestAnimationFrame(frame);
    }
  }

  window.addEventListener("resize", later);

  return {
    add: function (newSpooled, newExecuted) {
      newSpooled.forEach(function (e) { spooled.push(e); });
      newExecuted.forEach(function (p) { executed.push(p); });
      if (newSpooled.length || newExecuted.length) { later(); }
    },
    machine: function (h, v) {
      machine = [h, v];
      later();
    },
    counts: function () {
      return { spooled: spooled.length, executed: executed.length };
    }
  };
})();
