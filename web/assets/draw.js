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

  // The extent of everything received, kept up to date as it comes.
  let extent = null;

  function take(p) {
    if (!extent) { extent = { minH: p[0], maxH: p[0], minV: p[1], maxV: p[1] }; return; }
    if (p[0] < extent.minH) { extent.minH = p[0]; }
    if (p[0] > extent.maxH) { extent.maxH = p[0]; }
    if (p[1] < extent.minV) { extent.minV = p[1]; }
    if (p[1] > extent.maxV) { extent.maxV = p[1]; }
  }

  function takeElement(e) {
    take(e.from); take(e.to);
    if (e.arc) {
      const dh = e.from[0] - e.arc[0][0], dv = e.from[1] - e.arc[0][1];
      const r = Math.sqrt(dh * dh + dv * dv);
      take([e.arc[0][0] - r, e.arc[0][1] - r]);
      take([e.arc[0][0] + r, e.arc[0][1] + r]);
    }
  }

  function bounds() {
    if (!extent && !machine) { return null; }
    const b = extent ? Object.assign({}, extent) : { minH: machine[0], maxH: machine[0], minV: machine[1], maxV: machine[1] };
    if (machine) {
      b.minH = Math.min(b.minH, machine[0]); b.maxH = Math.max(b.maxH, machine[0]);
      b.minV = Math.min(b.minV, machine[1]); b.maxV = Math.max(b.maxV, machine[1]);
    }
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

  // Whether an arc is less than half a circle and strays less than half
  // a pixel from its chord (sagitta = chord² / 8r): drawn as its chord.
  function flat(e) {
    const c = e.arc[0];
    const ah = e.from[0] - c[0], av = e.from[1] - c[1];
    const bh = e.to[0] - c[0], bv = e.to[1] - c[1];
    const cross = ah * bv - av * bh;
    if (e.arc[1] ? cross <= 0 : cross >= 0) { return false; }
    const r = Math.sqrt(ah * ah + av * av) * view.scale;
    const ch = (bh - ah) * view.scale, cv = (bv - av) * view.scale;
    return (ch * ch + cv * cv) / (8 * r) < 0.5;
  }

  function stroke(ctx, look) {
    ctx.strokeStyle = look.colour;
    ctx.lineWidth = look.width;
    ctx.setLineDash(look.dash);
    ctx.lineJoin = "round";
    ctx.lineCap = "round";
  }

  // Draws spooled elements from index `from`, thinned, one stroke per run
  // of elements of one kind. Distances are compared squared, and a line
  // is taken without building a list of its points: 100,000 elements are
  // drawn again in a few tens of milliseconds when the picture is
  // rescaled.
  function drawSpooled(ctx, from) {
    let lastH = NaN, lastV = NaN, look = null;
    const pixel2 = PIXEL * PIXEL;
    function lineTo(h, v, always) {
      const dh = h - lastH, dv = v - lastV;
      if (always || dh * dh + dv * dv >= pixel2) {
        ctx.lineTo(h, v);
        lastH = h; lastV = v;
      }
    }
    for (let i = from; i < spooled.length; i++) {
      const e = spooled[i];
      const want = e.rapid ? RAPID : CORRECTED;
      const sh = view.width / 2 + (e.from[0] - view.cH) * view.scale;
      const sv = view.height / 2 - (e.from[1] - view.cV) * view.scale;
      const gh = sh - lastH, gv = sv - lastV;
      if (look !== want || !(gh * gh + gv * gv <= pixel2)) {
        if (look) { ctx.stroke(); }
        look = want;
        stroke(ctx, look);
        ctx.beginPath();
        ctx.moveTo(sh, sv);
        lastH = sh; lastV = sv;
      }
      const last = i === spooled.length - 1;
      if (!e.arc) {
        lineTo(view.width / 2 + (e.to[0] - view.cH) * view.scale,
               view.height / 2 - (e.to[1] - view.cV) * view.scale, last);
        continue;
      }
      if (flat(e)) {
        lineTo(view.width / 2 + (e.to[0] - view.cH) * view.scale,
               view.height / 2 - (e.to[1] - view.cV) * view.scale, last);
        continue;
      }
      const pts = points(e);
      for (let k = 1; k < pts.length; k++) {
        lineTo(pts[k][0], pts[k][1], last && k === pts.length - 1);
      }
    }
    if (look) { ctx.stroke(); }
  }

  function drawExecuted(ctx, from) {
    if (executed.length - from < 1) { return; }
    const start = Math.max(0, from - 1);
    const pixel2 = PIXEL * PIXEL;
    stroke(ctx, EXECUTED);
    ctx.beginPath();
    const first = px(executed[start]);
    let lastH = first[0], lastV = first[1];
    ctx.moveTo(lastH, lastV);
    for (let i = start + 1; i < executed.length; i++) {
      const h = view.width / 2 + (executed[i][0] - view.cH) * view.scale;
      const v = view.height / 2 - (executed[i][1] - view.cV) * view.scale;
      const dh = h - lastH, dv = v - lastV;
      if (dh * dh + dv * dv >= pixel2 || i === executed.length - 1) {
        ctx.lineTo(h, v);
        lastH = h; lastV = v;
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

  // The time the last frame took to draw (ms) and whether it redrew the
  // whole picture, kept on the canvas for a measuring script.
  function frame() {
    pending = false;
    const t0 = window.performance.now();
    const whole = needsRefit();
    if (whole) {
      redraw();
    } else {
      const ctx = canvas.getContext("2d");
      drawSpooled(ctx, drawnSpooled);
      drawExecuted(ctx, drawnExecuted);
      drawnSpooled = spooled.length;
      drawnExecuted = executed.length;
    }
    drawMarker();
    canvas.dataset.frameMs = (window.performance.now() - t0).toFixed(2);
    canvas.dataset.frameWhole = String(whole);
    canvas.dataset.frames = String(Number(canvas.dataset.frames || 0) + 1);
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
      newSpooled.forEach(function (e) { spooled.push(e); takeElement(e); });
      newExecuted.forEach(function (p) { executed.push(p); take(p); });
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
