// The report's plots in the page: every plot of x–y panels (its `panels` from /api/report)
// drawn with uPlot (/vendor/uPlot.iife.min.js, MIT), one chart per panel; a plot without
// panels (a heat map, a drawing) as the server's SVG in an <img>. A panel over the
// mechanism's angle (`angle_x`) draws a cursor at the angle slider's angle, and hovering it
// sets the slider. A new answer with the same plots updates their charts in place (setData)
// instead of building them anew, and only those in sight (the others when they come into
// sight). Nothing is parsed as HTML; uPlot sets styles through the
// CSSOM only and evaluates no strings, which the page's Content-Security-Policy allows.
"use strict";

const cwPlots = (() => {
  // The SVG plots' colours (src/report/plot.rs PALETTE), by series index.
  const PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"];
  const PEAK = "#141414";
  const CURSOR = "#c00";
  const FONT = "12px system-ui, sans-serif";
  const LABEL_FONT = "bold 12px system-ui, sans-serif";
  // Fixed axis sizes and padding (CSS px): the plotting area is known before the ticks are,
  // which an equal-aspect panel needs.
  const Y_AXIS = 62;
  const X_AXIS = 34;
  const AXIS_LABEL = 20;
  const PADDING = [12, 16, 4, 4];

  let charts = new Map(); // "suffix/panel index" → chart state (below)
  let angle = null; // the slider's angle (deg), or null
  let onHover = null; // called with the angle (deg) under the pointer of an angle panel

  // A tick label: at most 6 significant digits, trailing zeros dropped, no -0 (plot::tick).
  function tick(v) {
    if (v === 0 || Math.abs(v) < 1e-300) return "0";
    const s = String(Number(v.toPrecision(6)));
    return s === "-0" ? "0" : s;
  }

  // The finite data bounds of a panel's series, padded 5 % each side (plot::bounds). A
  // series without a name is an SVG's room for its legend (it draws nothing): the page's
  // legend is under the plot, so it is left out.
  function bounds(p) {
    let [x0, x1, y0, y1] = [Infinity, -Infinity, Infinity, -Infinity];
    for (const s of p.series) {
      if (!s.name) continue;
      for (let i = 0; i < s.x.length; i++) {
        const [x, y] = [s.x[i], s.y[i]];
        if (x === null || y === null) continue;
        if (x < x0) x0 = x;
        if (x > x1) x1 = x;
        if (y < y0) y0 = y;
        if (y > y1) y1 = y;
      }
    }
    if (!(x0 <= x1)) return { x: [0, 1], y: [0, 1] };
    const pad = (a, b) => {
      const w = Math.max(Math.abs(b - a), 1e-12 * Math.max(Math.abs(a), Math.abs(b)), 1e-300);
      return [a - 0.05 * w, b + 0.05 * w];
    };
    return { x: pad(x0, x1), y: pad(y0, y1), raw: [x0, x1] };
  }

  // An angle axis over about one turn (270° to 720° of data) on whole quarter turns
  // (plot::angle_ticks); else the padded data range.
  function xRange(p, b) {
    if (!p.angle_x || p.equal_aspect) return b.x;
    const [lo, hi] = b.raw || b.x;
    if (!(hi - lo >= 270 && hi - lo <= 720 + 1e-9)) return b.x;
    return [Math.floor(lo / 90 + 1e-9) * 90, Math.ceil(hi / 90 - 1e-9) * 90];
  }

  // Both ranges widened so that a unit has the same length on both axes of the plotting
  // area (a circle drawn round; plot::equal_scale).
  function equalRange(u, b, axis) {
    const [w, h] = [Math.max(u.bbox.width, 1), Math.max(u.bbox.height, 1)];
    const c = Math.max((b.x[1] - b.x[0]) / w, (b.y[1] - b.y[0]) / h);
    const r = axis === "x" ? b.x : b.y;
    const mid = 0.5 * (r[0] + r[1]);
    const n = axis === "x" ? w : h;
    return [mid - 0.5 * c * n, mid + 0.5 * c * n];
  }

  // uPlot's mode-2 data: [null, [xs, ys] per series].
  function dataOf(p) {
    return [null, ...p.series.map((s) => [s.x, s.y])];
  }

  // The canvas position of data (x, y) on chart u: linear scales, as u.valToPos(v, k, true)
  // computes them, without its per-call overhead.
  function toCanvas(u) {
    const { left, top, width, height } = u.bbox;
    const [sx, sy] = [u.scales.x, u.scales.y];
    const kx = width / (sx.max - sx.min);
    const ky = height / (sy.max - sy.min);
    return [(x) => left + (x - sx.min) * kx, (y) => top + height - (y - sy.min) * ky];
  }

  // A polyline broken at every null point (an excluded window, a pole; a locus need not be
  // sorted in x), as a uPlot path builder. A point within half a pixel of the last one drawn
  // is skipped (a curve of 4097 points over 400 px draws a few hundred), the last of each
  // run kept.
  function brokenLine(u, si) {
    const [xs, ys] = u.data[si];
    const [X, Y] = toCanvas(u);
    const path = new Path2D();
    const near = 0.5 * uPlot.pxRatio;
    let [pen, lx, ly, skipped] = [false, 0, 0, false];
    for (let i = 0; i < xs.length; i++) {
      if (xs[i] === null || ys[i] === null) {
        if (skipped) path.lineTo(X(xs[i - 1]), Y(ys[i - 1]));
        [pen, skipped] = [false, false];
        continue;
      }
      const [x, y] = [X(xs[i]), Y(ys[i])];
      if (pen && Math.abs(x - lx) < near && Math.abs(y - ly) < near) { skipped = true; continue; }
      if (pen) path.lineTo(x, y); else path.moveTo(x, y);
      [pen, lx, ly, skipped] = [true, x, y, false];
    }
    if (skipped) path.lineTo(X(xs[xs.length - 1]), Y(ys[ys.length - 1]));
    return { stroke: path, fill: null, clip: null, band: null, gaps: null, flags: 0 };
  }

  // A uPlot points builder drawing `shape(path, x, y, r)` at every point of the series (in
  // mode 2 uPlot's own draws none without a filter), r its points' radius in canvas px.
  function marks(shape) {
    return (u, si) => {
      const [xs, ys] = u.data[si];
      const r = (u.series[si].points.size / 2) * uPlot.pxRatio;
      const path = new Path2D();
      for (let i = 0; i < xs.length; i++) {
        if (xs[i] === null || ys[i] === null) continue;
        shape(path, u.valToPos(xs[i], "x", true), u.valToPos(ys[i], "y", true), r);
      }
      const { left, top, width, height } = u.bbox;
      const clip = new Path2D();
      clip.rect(left - r, top - r, width + 2 * r, height + 2 * r);
      return { stroke: path, fill: path, clip, flags: 0 };
    };
  }
  const dots = marks((p, x, y, r) => { p.moveTo(x + r, y); p.arc(x, y, r, 0, 2 * Math.PI); });
  const crosses = marks((p, x, y, r) => {
    p.moveTo(x - r, y - r); p.lineTo(x + r, y + r);
    p.moveTo(x - r, y + r); p.lineTo(x + r, y - r);
  });

  // One series' uPlot options by its style: a line, dots, a marker (crosses, in the
  // legend) or a peak (a ring, labelled in the plot by the draw hook, not in the legend).
  function seriesOpts(s, i) {
    const c = PALETTE[i % PALETTE.length];
    const none = () => null;
    // A series without a name (room above the data, see bounds) is not listed.
    const base = { label: s.name, class: s.name ? undefined : "unnamed" };
    switch (s.style) {
      case "line":
        return Object.assign(base, { stroke: c, width: 2, paths: brokenLine, points: { show: false } });
      case "points":
        return Object.assign(base, { stroke: c, fill: c, width: 0, paths: none, points: { show: true, size: 5, width: 0, fill: c, stroke: c, paths: dots } });
      case "marker":
        return Object.assign(base, { stroke: c, fill: c, width: 0, paths: none, points: { show: true, size: 12, width: 2.5, fill: "rgba(0,0,0,0)", stroke: c, paths: crosses } });
      default: // "peak"
        return Object.assign(base, { class: "peak", stroke: PEAK, width: 0, paths: none, points: { show: true, size: 13, width: 1.2, stroke: PEAK, fill: "rgba(0,0,0,0)", paths: dots } });
    }
  }

  // The box [left, top, right, bottom] of a peak's label beside its ring at (x, y), as the
  // report's plots place it (src/report/plot.rs, peak_label_box): right of the point where
  // the text fits, else left of it, else as far right as the area lets it start; below a
  // point in the upper half of the area, above one in the lower half; a box overlapping one
  // already placed moves a line further (down below, up above), at most four times, never
  // out of the area.
  function labelBox(x, y, w, h, area, placed, gap) {
    const [l, t, r, b] = area;
    const left = x + gap + w <= r ? x + gap : x - gap - w >= l ? x - gap - w : Math.max(r - w, l);
    const below = y < t + 0.5 * (b - t);
    const clamp = (v) => Math.max(Math.min(v, b - h), t);
    let top = clamp(below ? y + gap : y - gap - h);
    const overlaps = (v) => placed.some((p) => left < p[2] && left + w > p[0] && v < p[3] && v + h > p[1]);
    for (let k = 0; k < 4 && overlaps(top); k++) top = clamp(below ? top + h : top - h);
    return [left, top, left + w, top + h];
  }

  // The peaks' labels beside their rings (labelBox), taken from the top of the plot down so
  // that stacked labels keep their points' order, clear of every ring and of the labels
  // before them (as plot.rs's label_peaks); then the angle cursor.
  function drawOver(u, st) {
    const ctx = u.ctx;
    const { left, top, width, height } = u.bbox;
    const px = uPlot.pxRatio;
    ctx.save();
    ctx.font = 12 * px + "px system-ui, sans-serif";
    ctx.fillStyle = PEAK;
    ctx.textAlign = "left";
    ctx.textBaseline = "top";
    const area = [left, top, left + width, top + height];
    const peaks = [];
    st.panel.series.forEach((s) => {
      if (s.style !== "peak") return;
      for (let i = 0; i < s.x.length; i++) {
        if (s.x[i] === null || s.y[i] === null) continue;
        peaks.push({ x: u.valToPos(s.x[i], "x", true), y: u.valToPos(s.y[i], "y", true), name: s.name });
      }
    });
    peaks.sort((a, b) => a.y - b.y);
    const r = 7 * px;
    const placed = peaks.map((p) => [p.x - r, p.y - r, p.x + r, p.y + r]);
    for (const p of peaks) {
      const box = labelBox(p.x, p.y, ctx.measureText(p.name).width, 15 * px, area, placed, 9 * px);
      placed.push(box);
      ctx.fillText(p.name, box[0], box[1] + 1.5 * px);
    }
    const a = cursorAt(u, st.panel);
    if (a !== null) {
      const x = Math.round(u.valToPos(a, "x", true)) + 0.5;
      ctx.strokeStyle = CURSOR;
      ctx.lineWidth = 1.5 * px;
      ctx.setLineDash([5 * px, 3 * px]);
      ctx.beginPath();
      ctx.moveTo(x, top);
      ctx.lineTo(x, top + height);
      ctx.stroke();
    }
    ctx.restore();
  }

  // Where the slider's angle is on an angle panel's x axis (deg; a turn later or earlier
  // where the axis covers one turn and the angle is past it), or null off the axis.
  function cursorAt(u, p) {
    if (!p.angle_x || angle === null) return null;
    const { min, max } = u.scales.x;
    let a = angle;
    if (max - min <= 360 + 1e-9) a = min + (((a - min) % 360) + 360) % 360;
    return a >= min && a <= max ? a : null;
  }

  // The pointer over an angle panel sets the slider to the angle under it.
  function hovered(u, st) {
    const left = u.cursor.left;
    if (!st.panel.angle_x || !onHover || left === undefined || left < 0) return;
    onHover(u.posToVal(left, "x"));
  }

  // What must match for an answer's panel to reuse a chart: everything but the numbers
  // (the title and the peaks' labels are set afresh).
  function shapeOf(plot, p, w, h) {
    const series = p.series.map((s) => (s.style === "peak" ? "peak" : s.style + ":" + s.name));
    return JSON.stringify([plot.width, plot.height, w, h, p.x_label, p.y_label, p.equal_aspect, p.angle_x, series]);
  }

  // uPlot's options for panel p, w×h CSS px (its canvas; the title and legend add to it).
  function options(st, p, w, h) {
    const scale = (axis) => ({
      time: false,
      range: (u) => (p.equal_aspect ? equalRange(u, st.bounds, axis) : axis === "x" ? xRange(st.panel, st.bounds) : st.bounds.y),
    });
    const axis = (label, size) => ({
      label,
      size,
      labelSize: AXIS_LABEL,
      font: FONT,
      labelFont: LABEL_FONT,
      stroke: "#333",
      grid: { stroke: "#e4e4e4", width: 1 },
      ticks: { stroke: "#999", width: 1, size: 4 },
      values: (u, splits) => splits.map(tick),
    });
    const x = axis(p.x_label, X_AXIS);
    if (p.angle_x && !p.equal_aspect) x.splits = (u, ai, min, max) => angleSplits(min, max);
    return {
      mode: 2,
      title: p.title,
      width: w,
      height: h,
      padding: PADDING,
      pxAlign: 0,
      scales: { x: scale("x"), y: scale("y") },
      axes: [x, axis(p.y_label, Y_AXIS)],
      series: [{}, ...p.series.map(seriesOpts)],
      legend: { live: false },
      cursor: { y: false, points: { show: false }, drag: { x: false, y: false, setScale: false } },
      hooks: { draw: [(u) => drawOver(u, st)], setCursor: [(u) => hovered(u, st)] },
    };
  }

  // An angle axis's ticks: every quarter turn (dead centres, quadrature) where that gives
  // at least 3, else uPlot-like steps of 30°, 15°, 5°, 1°.
  function angleSplits(min, max) {
    const step = [90, 30, 15, 5, 1, 0.5, 0.1].find((s) => (max - min) / s >= 3) || (max - min) / 4;
    const out = [];
    for (let v = Math.ceil(min / step - 1e-9) * step; v <= max + 1e-9 * step; v += step) out.push(v);
    return out;
  }

  // Each panel's chart size (CSS px): the nominal panel size, narrowed to fit the column
  // (two side by side where both fit), the height scaled alike less the title's share.
  function panelSize(plot, n, avail) {
    // Each panel's border and the gap between two (app.css).
    const per = n > 1 && avail >= 2 * 320 ? Math.floor((avail - 20) / 2) : avail - 4;
    const w = Math.max(260, Math.min(plot.width, per));
    const h = Math.round(((plot.height - 40) * w) / plot.width);
    return [w, h];
  }

  // A chart out of sight (beyond a few hundred pixels of the viewport) is not drawn: an
  // answer's data, or the cursor's move, waits until it comes into sight, and its div is
  // marked `data-stale` meanwhile. The plots are under the numbers, so an edit usually
  // draws none of them until the page is scrolled to them.
  const byDiv = new WeakMap();
  const seen = new IntersectionObserver(
    (entries) => {
      for (const e of entries) {
        const st = byDiv.get(e.target);
        if (!st) continue;
        st.visible = e.isIntersecting;
        if (st.visible) refresh(st);
      }
    },
    { rootMargin: "300px 0px" },
  );

  // A printed page shows every chart as it is now.
  window.addEventListener("beforeprint", () => charts.forEach(refresh));

  // Draws what a chart has waiting: the latest answer's panel (its title and data), else
  // the cursor at the slider's angle.
  function refresh(st) {
    if (st.next) {
      st.panel = st.next;
      st.next = null;
      st.bounds = bounds(st.panel);
      st.u.root.querySelector(".u-title").textContent = st.panel.title;
      st.u.setData(dataOf(st.panel));
    } else if (st.dirty) {
      st.u.redraw(false, false);
    }
    st.dirty = false;
    delete st.div.dataset.stale;
  }

  // A chart no longer shown.
  function forget(st) {
    seen.unobserve(st.div);
    st.u.destroy();
  }

  // A plot of panels: one figure, a chart per panel (reused where the shape matches).
  function panelFigure(plot, avail, keep) {
    const fig = document.createElement("figure");
    fig.className = "panels";
    fig.dataset.suffix = plot.suffix;
    const row = document.createElement("div");
    row.className = "panel-row";
    plot.panels.forEach((p, i) => {
      const key = plot.suffix + "/" + i;
      const [w, h] = panelSize(plot, plot.panels.length, avail);
      const shape = shapeOf(plot, p, w, h);
      let st = charts.get(key);
      if (st && st.shape === shape) {
        st.next = p;
        if (st.visible) refresh(st); else st.div.dataset.stale = "";
      } else {
        if (st) forget(st);
        st = { shape, panel: p, bounds: bounds(p), next: null, dirty: false, visible: true };
        const div = document.createElement("div");
        div.className = "panel" + (p.angle_x ? " angle" : "");
        st.u = new uPlot(options(st, p, w, h), dataOf(p), div);
        st.div = div;
        charts.set(key, st);
        byDiv.set(div, st);
        seen.observe(div);
      }
      keep.add(key);
      row.appendChild(st.div);
    });
    const cap = document.createElement("figcaption");
    cap.textContent = plot.caption;
    fig.append(row, cap);
    return fig;
  }

  // A plot without panels: the server's SVG as an image (an image runs no script).
  function svgFigure(plot) {
    const fig = document.createElement("figure");
    fig.dataset.suffix = plot.suffix;
    const img = document.createElement("img");
    img.alt = plot.caption;
    img.src = "data:image/svg+xml;base64," + btoa(unescape(encodeURIComponent(plot.svg || "")));
    const cap = document.createElement("figcaption");
    cap.textContent = plot.caption;
    fig.append(img, cap);
    return fig;
  }

  // The plots' column width (CSS px), kept by a ResizeObserver so that showing an answer
  // forces no layout; a change of more than a few pixels draws the last answer again.
  let width = null;
  let last = null;
  let observed = null;
  function watch(box) {
    if (observed === box) return;
    observed = box;
    new ResizeObserver((entries) => {
      const w = Math.floor(entries[entries.length - 1].contentRect.width);
      const redraw = width !== null && Math.abs(w - width) > 4 && last;
      width = w;
      if (redraw) show(last.box, last.plots, last.hover);
    }).observe(box);
  }

  // Shows an answer's plots in `box`; `hover(deg)` is called when the pointer is over an
  // angle panel.
  function show(box, plots, hover) {
    watch(box);
    last = { box, plots, hover };
    onHover = hover;
    if (width === null) width = box.clientWidth;
    const avail = width || 800;
    const keep = new Set();
    const figs = (plots || []).map((p) => (p.panels ? panelFigure(p, avail, keep) : svgFigure(p)));
    for (const [key, st] of charts) {
      if (!keep.has(key)) { forget(st); charts.delete(key); }
    }
    box.replaceChildren(...figs);
  }

  // The slider's angle (deg; null: none): every angle panel in sight redraws its cursor
  // (its paths kept), the others when they come into sight.
  function setAngle(deg) {
    if (deg === angle) return;
    angle = deg;
    for (const st of charts.values()) {
      if (!st.panel.angle_x) continue;
      st.dirty = true;
      if (st.visible) refresh(st); else st.div.dataset.stale = "";
    }
  }

  return { show, setAngle };
})();
