// Plots on canvas: line plots, the polar lobe and the slice image with its colour bar.
// They draw the numbers the server computed; nothing here evaluates a model.
"use strict";

const plot = (() => {
  const INK = "#222", GRID = "#e3e3e3", FONT = "12px system-ui, sans-serif";
  const CHANNEL_COLOURS = ["#d62728", "#2ca02c", "#1f77b4"];

  function begin(canvas) {
    const ctx = canvas.getContext("2d");
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = "#fff";
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    ctx.font = FONT;
    ctx.lineJoin = "round";
    return ctx;
  }

  function message(canvas, text) {
    const ctx = begin(canvas);
    ctx.fillStyle = "#777";
    ctx.textAlign = "center";
    ctx.fillText(text, canvas.width / 2, canvas.height / 2);
    canvas.dataset.message = text;  // what the view says instead of a plot (tests, scripts)
  }

  const fmt = (v) => (v === 0 ? "0" : Math.abs(v) >= 1e4 || Math.abs(v) < 1e-3 ? v.toExponential(2) : +v.toPrecision(3) + "");

  // Line plot. opts: xRange, yRange, xLabel, yLabel, xTicks, series [{x, y, color, dash,
  // width, label}], markers [{x, label, color}].
  function lines(canvas, opts) {
    const ctx = begin(canvas);
    const L = 52, R = 12, T = 12, B = 40;
    const w = canvas.width - L - R, h = canvas.height - T - B;
    const [x0, x1] = opts.xRange, [y0, y1] = opts.yRange;
    const X = (x) => L + ((x - x0) / (x1 - x0)) * w;
    const Y = (y) => T + h - ((y - y0) / (y1 - y0)) * h;
    ctx.strokeStyle = GRID;
    ctx.fillStyle = INK;
    ctx.textAlign = "center";
    for (const x of opts.xTicks || [0, 15, 30, 45, 60, 75, 90]) {
      ctx.beginPath(); ctx.moveTo(X(x), T); ctx.lineTo(X(x), T + h); ctx.stroke();
      ctx.fillText(x + "°", X(x), T + h + 14);
    }
    ctx.textAlign = "right";
    for (let i = 0; i <= 5; ++i) {
      const y = y0 + ((y1 - y0) * i) / 5;
      ctx.beginPath(); ctx.moveTo(L, Y(y)); ctx.lineTo(L + w, Y(y)); ctx.stroke();
      ctx.fillText(fmt(y), L - 4, Y(y) + 4);
    }
    ctx.strokeStyle = INK;
    ctx.strokeRect(L, T, w, h);
    ctx.textAlign = "center";
    ctx.fillText(opts.xLabel || "", L + w / 2, canvas.height - 6);
    ctx.save(); ctx.translate(12, T + h / 2); ctx.rotate(-Math.PI / 2); ctx.fillText(opts.yLabel || "", 0, 0); ctx.restore();
    ctx.save();
    ctx.beginPath(); ctx.rect(L, T, w, h); ctx.clip();
    for (const m of opts.markers || []) {
      ctx.strokeStyle = m.color || "#888";
      ctx.setLineDash([2, 3]);
      ctx.beginPath(); ctx.moveTo(X(m.x), T); ctx.lineTo(X(m.x), T + h); ctx.stroke();
      ctx.setLineDash([]);
    }
    for (const s of opts.series) {
      ctx.strokeStyle = s.color || INK;
      ctx.lineWidth = s.width || 1.5;
      ctx.setLineDash(s.dash || []);
      ctx.beginPath();
      s.x.forEach((x, i) => (i ? ctx.lineTo(X(x), Y(s.y[i])) : ctx.moveTo(X(x), Y(s.y[i]))));
      ctx.stroke();
    }
    ctx.setLineDash([]);
    // The markers' labels over the curves, one row each (18 px apart) on a light backing,
    // so that neither two labels nor a label and a curve run into each other.
    for (const m of opts.markers || []) {
      const right = X(m.x) > L + 0.6 * w;  // labels near the right edge run leftwards
      const x = X(m.x) + (right ? -3 : 3), y = T + h - 8 - 18 * (m.row || 0);
      const tw = ctx.measureText(m.label).width;
      ctx.fillStyle = "rgba(255, 255, 255, 0.85)";
      ctx.fillRect(right ? x - tw - 2 : x - 2, y - 11, tw + 4, 15);
      ctx.fillStyle = m.color || "#555";
      ctx.textAlign = right ? "right" : "left";
      ctx.fillText(m.label, x, y);
    }
    ctx.restore();
    ctx.setLineDash([]);
    ctx.lineWidth = 1;
    // Legend: one entry per distinct label.
    const seen = new Set();
    let ly = T + 14, widest = 0;
    for (const s of opts.series) if (s.label) widest = Math.max(widest, ctx.measureText(s.label).width);
    const lx = L + w - widest - 36;
    const entries = new Set(opts.series.filter((s) => s.label).map((s) => s.label)).size;
    if (entries) {  // a light backing, so that the curves under the legend don't cross its text
      ctx.fillStyle = "rgba(255, 255, 255, 0.85)";
      ctx.fillRect(lx - 4, T + 2, widest + 36, 15 * entries + 2);
    }
    ctx.textAlign = "left";
    for (const s of opts.series) {
      if (!s.label || seen.has(s.label)) continue;
      seen.add(s.label);
      ctx.strokeStyle = s.legendColor || s.color || INK;
      ctx.setLineDash(s.dash || []);
      ctx.beginPath(); ctx.moveTo(lx, ly - 4); ctx.lineTo(lx + 24, ly - 4); ctx.stroke();
      ctx.setLineDash([]);
      ctx.fillStyle = INK;
      ctx.fillText(s.label, lx + 28, ly);
      ly += 15;
    }
  }

  // Whether every row of per-channel values holds one value (a grey material): drawn once.
  const grey = (rows) => rows.every((v) => v.every((x) => x === v[0]));

  // Polar plot of the lobe: radius ∝ value along θo in [−90°, 90°] (up is the normal),
  // the light at +θi and the mirror direction −θi marked. `below` (a material that
  // transmits): the values under the surface at the same θo from the inward normal, drawn
  // in the lower half.
  function lobe(canvas, data, values, channels, other, below) {
    const ctx = begin(canvas);
    const both = !!below || !!(other && other.below);
    const cx = canvas.width / 2, cy = both ? canvas.height / 2 : canvas.height - 24;
    const r = Math.min(cx - 90, both ? cy - 14 : cy - 30);
    let max = 0;
    for (const set of [values, below, other && other.values, other && other.below])
      if (set) for (const v of set) for (const c of v) max = Math.max(max, c);
    ctx.strokeStyle = GRID;
    for (const f of [0.25, 0.5, 0.75, 1]) {
      ctx.beginPath(); ctx.arc(cx, cy, r * f, Math.PI, 2 * Math.PI); ctx.stroke();
      if (both) { ctx.beginPath(); ctx.arc(cx, cy, r * f, 0, Math.PI); ctx.stroke(); }
    }
    for (let a = -90; a <= 90; a += 30) {
      const t = (a * Math.PI) / 180;
      ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(cx + r * Math.sin(t), cy - r * Math.cos(t)); ctx.stroke();
      if (both) { ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(cx + r * Math.sin(t), cy + r * Math.cos(t)); ctx.stroke(); }
    }
    ctx.strokeStyle = INK;
    ctx.beginPath(); ctx.moveTo(cx - r - 10, cy); ctx.lineTo(cx + r + 10, cy); ctx.stroke();
    const ray = (deg, colour, dash, label) => {
      const t = (deg * Math.PI) / 180;
      ctx.strokeStyle = colour; ctx.fillStyle = colour; ctx.setLineDash(dash);
      ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(cx + r * Math.sin(t), cy - r * Math.cos(t)); ctx.stroke();
      ctx.setLineDash([]);
      ctx.textAlign = deg >= 0 ? "left" : "right";
      ctx.fillText(label, cx + (r + 4) * Math.sin(t), cy - (r + 4) * Math.cos(t));
    };
    ray(data.theta_i, "#e69500", [], "light θi = " + data.theta_i + "°");
    ray(data.mirror, "#7a3db8", [5, 4], "mirror");
    ctx.fillStyle = INK; ctx.textAlign = "left";
    if (!(max > 0)) {
      ctx.fillText(data.delta_only ? "delta lobe: all of it along the mirror direction" : "f = 0 in this plane", 8, 16);
      return;
    }
    ctx.fillText("outer circle: " + fmt(max) + " (1/sr)", 8, 16);
    // side −1: below the surface (y grows downwards on the canvas).
    const curves = (vals, n, dash, side = 1) => {
      if (grey(vals)) n = 1;
      const colours = n === 1 ? [INK] : CHANNEL_COLOURS;
      ctx.setLineDash(dash);
      for (let c = 0; c < n; ++c) {
        ctx.strokeStyle = colours[c];
        ctx.lineWidth = 1.5;
        ctx.beginPath();
        data.theta_o.forEach((deg, i) => {
          const t = (deg * Math.PI) / 180, rr = (r * vals[i][c]) / max;
          const x = cx + rr * Math.sin(t), y = cy - side * rr * Math.cos(t);
          i ? ctx.lineTo(x, y) : ctx.moveTo(x, y);
        });
        ctx.stroke();
      }
      ctx.setLineDash([]);
      ctx.lineWidth = 1;
    };
    curves(values, channels, []);
    if (below) curves(below, channels, [], -1);
    if (both) { ctx.fillStyle = INK; ctx.fillText("below: transmitted", 8, canvas.height - 6); }
    if (other) {
      curves(other.values, other.channels, [6, 4]);
      if (other.below) curves(other.below, other.channels, [6, 4], -1);
      ctx.fillStyle = INK;
      ctx.fillText("A solid, B dashed", 8, 32);
    }
  }

  // The lobe over the hemisphere as a wire mesh: radius ∝ value along each wo, rings of
  // constant θo and spokes of constant φo, coloured by value; turned by yaw (about the
  // normal) and pitch (towards the viewer), drawn in orthographic projection with the
  // normal up. The light's direction (+θi in x–z) and its mirror image are drawn too.
  function lobe3d(canvas, data, values, yaw, pitch) {
    const ctx = begin(canvas);
    const rings = data.count_theta, spokes = data.count_phi;
    let max = 0;
    for (const v of values) max = Math.max(max, v);
    const cx = canvas.width / 2, cy = canvas.height * 0.68, s = Math.min(canvas.width, canvas.height) * 0.55;
    const cy_ = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
    const project = (x, y, z) => {
      const x1 = cy_ * x - sy * y, y1 = sy * x + cy_ * y;  // about the normal
      const y2 = cp * y1 - sp * z, z2 = sp * y1 + cp * z;  // tilt
      return [cx + s * x1, cy - s * z2, y2];
    };
    const dir = (t, p) => [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
    ctx.strokeStyle = GRID;
    ctx.beginPath();
    for (let k = 0; k <= 64; ++k) {
      const [x, y] = project(Math.cos((k / 64) * 2 * Math.PI), Math.sin((k / 64) * 2 * Math.PI), 0);
      k ? ctx.lineTo(x, y) : ctx.moveTo(x, y);
    }
    ctx.stroke();
    const ti = (data.theta_i * Math.PI) / 180;
    const arrow = (v, colour, label) => {
      const [x0, y0] = project(0, 0, 0), [x1, y1] = project(v[0], v[1], v[2]);
      ctx.strokeStyle = colour; ctx.fillStyle = colour;
      ctx.beginPath(); ctx.moveTo(x0, y0); ctx.lineTo(x1, y1); ctx.stroke();
      ctx.textAlign = "left";
      ctx.fillText(label, x1 + 3, y1);
    };
    arrow([0, 0, 1.05], "#999", "n");
    arrow([Math.sin(ti), 0, Math.cos(ti)], "#e69500", "light");
    arrow([-Math.sin(ti), 0, Math.cos(ti)], "#7a3db8", "mirror");
    ctx.fillStyle = INK; ctx.textAlign = "left";
    if (!(max > 0)) { ctx.fillText("nothing finite to draw (a delta lobe)", 8, 16); return; }
    ctx.fillText("largest: " + fmt(max), 8, 16);
    const point = (r, p) => {
      const v = values[r * spokes + (p % spokes)] / max;
      const d = dir(((r / rings) * Math.PI) / 2, (p / spokes) * 2 * Math.PI);
      return project(v * d[0], v * d[1], v * d[2]);
    };
    const segment = (a, b, value) => {
      const c = colour(0.15 + 0.85 * value);
      ctx.strokeStyle = `rgb(${c[0]},${c[1]},${c[2]})`;
      ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
    };
    for (let r = 1; r <= rings; ++r)
      for (let p = 0; p < spokes; ++p) segment(point(r, p), point(r, p + 1), values[r * spokes + p] / max);
    for (let p = 0; p < spokes; p += 2)
      for (let r = 0; r < rings; ++r) segment(point(r, p), point(r + 1, p), values[r * spokes + p] / max);
  }

  // A sequential colour map for the log scale: dark blue → purple → orange → pale yellow.
  const STOPS = [[0, [13, 8, 60]], [0.3, [100, 30, 130]], [0.6, [220, 80, 70]], [0.85, [250, 170, 50]], [1, [252, 250, 190]]];
  function colour(t) {
    t = Math.min(1, Math.max(0, t));
    for (let i = 1; i < STOPS.length; ++i) {
      if (t <= STOPS[i][0]) {
        const [a, ca] = STOPS[i - 1], [b, cb] = STOPS[i];
        const u = (t - a) / (b - a);
        return ca.map((v, k) => Math.round(v + (cb[k] - v) * u));
      }
    }
    return STOPS[STOPS.length - 1][1];
  }

  // The slice: pixel values (row 0 at θd = 90°, -1 below the horizon) on the log scale
  // [lo, hi], axes and colour bar. Returns the panel rectangle for the cursor.
  // The relative difference (B − A) / A of two slices, and its scale: the smallest of
  // 1 %, 2 %, 5 %, … 100 % holding every difference (as gonio slice --compare).
  function sliceDifference(a, b) {
    const d = a.map((ya, i) => (ya < 0 || b[i] < 0 ? NaN : ya > 0 ? (b[i] - ya) / ya : b[i] > 0 ? Infinity : 0));
    let max = 0;
    for (const v of d) if (Number.isFinite(v)) max = Math.max(max, Math.abs(v));
    if (d.some((v) => v === Infinity)) max = Infinity;
    const range = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1].find((r) => max <= r * (1 + 1e-6)) || 1;
    return { d, range };
  }
  // Diverging map for t in [−1, 1]: blue, white, red.
  const diverging = (t) => {
    t = Math.max(-1, Math.min(1, t));
    return t < 0 ? [Math.round(255 * (1 + t)), Math.round(255 * (1 + t)), 255] : [255, Math.round(255 * (1 - t)), Math.round(255 * (1 - t))];
  };

  function panel(ctx, P, n, pixel) {
    const img = ctx.createImageData(n, n);
    for (let i = 0; i < n * n; ++i) {
      const c = pixel(i);
      img.data.set([c[0], c[1], c[2], 255], 4 * i);
    }
    const off = document.createElement("canvas");
    off.width = n; off.height = n;
    off.getContext("2d").putImageData(img, 0, 0);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(off, P.x, P.y, P.s, P.s);
    ctx.strokeStyle = INK;
    ctx.strokeRect(P.x - 0.5, P.y - 0.5, P.s + 1, P.s + 1);
  }

  function slice(canvas, data) {
    const ctx = begin(canvas);
    const compare = !!data.values_compare;
    const n = data.size;
    const s = compare ? Math.min(canvas.height - 48, (canvas.width - 230) / 3) : Math.min(canvas.height - 48, canvas.width - 170);
    const P = { x: 44, y: 10, s };
    const llo = Math.log10(data.lo), lhi = Math.log10(data.hi);
    const logColour = (v) => (v < 0 ? [140, 140, 140] : v > 0 ? colour((Math.log10(v) - llo) / (lhi - llo)) : colour(0));
    panel(ctx, P, n, (i) => logColour(data.values[i]));
    const panels = [P];
    let diff = null;
    if (compare) {
      const PB = { x: P.x + s + 10, y: P.y, s };
      panel(ctx, PB, n, (i) => logColour(data.values_compare[i]));
      diff = sliceDifference(data.values, data.values_compare);
      const PD = { x: PB.x + s + 60, y: P.y, s };
      panel(ctx, PD, n, (i) => (Number.isNaN(diff.d[i]) ? [140, 140, 140] : diverging(diff.d[i] / diff.range)));
      panels.push(PB, PD);
      ctx.fillStyle = INK;
      ctx.textAlign = "left";
      ctx.fillText("(B − A) / A: ±" + +(100 * diff.range).toPrecision(3) + " %", PD.x, P.y + s + 30);
    }
    ctx.fillStyle = INK;
    ctx.textAlign = "center";
    for (const Q of panels.slice(0, compare ? 2 : 1)) {
      for (const d of [0, 30, 60, 90]) {
        const u = data.sqrt_theta_h ? Math.sqrt(d / 90) : d / 90;
        ctx.fillText(d + "", Q.x + u * Q.s, Q.y + Q.s + 14);
      }
    }
    if (compare) {
      ctx.fillText("A", P.x + s / 2, P.y + s + 30);
      ctx.fillText("B  (θh across, θd up)", panels[1].x + s / 2, P.y + s + 30);
    } else {
      ctx.fillText("θh (deg)", P.x + P.s / 2, P.y + P.s + 30);
    }
    ctx.textAlign = "right";
    for (const d of [0, 30, 60, 90]) ctx.fillText(d + "", P.x - 4, P.y + P.s - (d / 90) * P.s + 4);
    ctx.save(); ctx.translate(12, P.y + P.s / 2); ctx.rotate(-Math.PI / 2); ctx.textAlign = "center";
    ctx.fillText("θd (deg)", 0, 0); ctx.restore();
    // Colour bar with its decades.
    const B = { x: (compare ? panels[1].x : P.x) + P.s + 8, y: P.y, w: 12, h: P.s };
    for (let row = 0; row < B.h; ++row) {
      const c = colour(1 - (row + 0.5) / B.h);
      ctx.fillStyle = `rgb(${c[0]},${c[1]},${c[2]})`;
      ctx.fillRect(B.x, B.y + row, B.w, 1);
    }
    ctx.strokeRect(B.x - 0.5, B.y - 0.5, B.w + 1, B.h + 1);
    ctx.fillStyle = INK;
    ctx.textAlign = "left";
    for (let e = Math.ceil(llo - 1e-9); e <= Math.floor(lhi + 1e-9); ++e) {
      const y = B.y + B.h - ((e - llo) / (lhi - llo)) * B.h;
      ctx.fillRect(B.x + B.w, y, 4, 1);
      ctx.fillText(e >= -2 && e <= 2 ? String(10 ** e) : "1e" + e, B.x + B.w + 6, y + 4);
    }
    if (!compare) ctx.fillText("f (1/sr)", B.x - 4, B.y + B.h + 30);
    P.diff = diff;
    return P;
  }

  // A linear RGB image (the mean of `samples`-weighted sums in `acc`, row 0 at the top),
  // scaled by 2^exposure, clamped and sRGB-encoded, drawn over the whole canvas.
  function image(canvas, acc, samples, size, exposure) {
    const ctx = begin(canvas);
    const img = ctx.createImageData(size, size);
    const k = Math.pow(2, exposure) / samples;
    const encode = (c) => 255 * (c <= 0.0031308 ? 12.92 * c : 1.055 * Math.pow(c, 1 / 2.4) - 0.055);
    for (let i = 0; i < size * size; ++i) {
      for (let c = 0; c < 3; ++c) img.data[4 * i + c] = encode(Math.min(1, Math.max(0, acc[3 * i + c] * k)));
      img.data[4 * i + 3] = 255;
    }
    const off = document.createElement("canvas");
    off.width = size; off.height = size;
    off.getContext("2d").putImageData(img, 0, 0);
    ctx.drawImage(off, 0, 0, canvas.width, canvas.height);
  }

  function exportPNG(canvas, name) {
    canvas.toBlob((blob) => {
      const a = document.createElement("a");
      a.href = URL.createObjectURL(blob);
      a.download = name + ".png";
      a.click();
      setTimeout(() => URL.revokeObjectURL(a.href), 1000);
    }, "image/png");
  }

  return { lines, lobe, lobe3d, slice, image, message, exportPNG, fmt, grey, CHANNEL_COLOURS };
})();
