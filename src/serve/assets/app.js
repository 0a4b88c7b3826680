// The designer's page: open a problem file, edit it, and see it re-solved (debounced) on
// every edit. Every element is built with textContent (nothing from a file or a result is
// parsed as HTML); the plots are drawn in the page by plots.js (uPlot), those without data
// (a heat map, a drawing) shown as the server's SVG images (an image runs no script).
"use strict";

const token = new URLSearchParams(location.hash.slice(1)).get("token");
const $ = (id) => document.getElementById(id);
let fileName = "request.toml";
let generation = 0;
let editedAt = null; // when the edit being solved was made (performance.now())
let inFlight = false; // a solve is on its way
let pending = false; // an edit came in meanwhile: solve the text again when it is back

function api(path, init = {}) {
  const headers = Object.assign({}, init.headers || {});
  if (token) headers["Authorization"] = "Bearer " + token;
  return fetch(path, Object.assign({}, init, { headers }));
}

function cell(row, text, cls) {
  const td = document.createElement("td");
  td.textContent = text;
  if (cls) td.className = cls;
  row.appendChild(td);
}

function fmt(v) {
  return typeof v === "number" ? v.toPrecision(6) : String(v);
}

// A table of numbers in workshop units (`units`: key → [words, unit, factor from SI], from
// /api/report); the SI key is each row's tooltip.
function fill(id, map, errors, units) {
  const body = $(id).querySelector("tbody");
  body.replaceChildren();
  for (const [k, v] of Object.entries(map || {})) {
    const [words, unit, f] = (units && units[k]) || [k, "", 1];
    const scaled = (x) => (typeof x === "number" ? x * f : x);
    const tr = document.createElement("tr");
    tr.title = k;
    cell(tr, words);
    cell(tr, fmt(scaled(v)), "num");
    cell(tr, unit === "–" ? "" : unit);
    if (errors) cell(tr, errors[k] === undefined ? "" : fmt(scaled(errors[k])), "num");
    body.appendChild(tr);
  }
}

function showError(e) {
  const p = $("problem-error");
  if (!e) { p.hidden = true; p.textContent = ""; return; }
  const where = [e.file, e.line ? "line " + e.line : null, e.field ? "field " + e.field : null]
    .filter(Boolean).join(", ");
  p.textContent = where + ": " + e.message;
  p.hidden = false;
  const s = $("status");
  s.textContent = "error";
  s.className = "status error";
}

function show(answer) {
  const r = answer.result;
  showError(null);
  const s = $("status");
  s.textContent = r.status;
  s.className = "status " + r.status;
  $("status-detail").textContent = r.status_detail || "";
  fill("objectives", r.objectives, r.errors || {}, answer.units);
  fill("design", r.design, null, answer.units);
  const w = $("warnings");
  w.replaceChildren();
  for (const text of r.warnings || []) {
    const li = document.createElement("li");
    li.textContent = text;
    w.appendChild(li);
  }
  $("method").textContent = r.method || "";
  // What kind of solve it was (the edit-to-redraw classes of the browser test).
  document.body.dataset.kind = JSON.stringify(r.pareto ? "front" : r.search ? "search" : "");
  showMotion(answer.motion || null);
  // The plots' share of the page's time: built (or updated) and drawn, which uPlot does in
  // a microtask after this task's code.
  const t0 = performance.now();
  cwPlots.show($("plots"), answer.plots, hoverAngle);
  queueMicrotask(() => { document.body.dataset.plotMs = (performance.now() - t0).toFixed(1); });
}

// The pointer over a plot's angle axis at `deg`: the frame nearest that angle (a turn apart
// the same angle) shown, the animation paused.
function hoverAngle(deg) {
  if (!motion || !motion.frames.length) return;
  const apart = (f) => Math.abs(((((f.theta * 180) / Math.PI - deg) % 360) + 540) % 360 - 180);
  let best = 0;
  motion.frames.forEach((f, k) => { if (apart(f) < apart(motion.frames[best])) best = k; });
  pause();
  if (best !== frame) { frame = best; drawFrame(); }
}

function pause() {
  playing = false;
  $("play").textContent = "Play";
}

// The mechanism view: the frames of one turn, the crank angle on a slider (or playing), the
// bodies placed per frame, the handles (a pivot, a length along its axis, a counterweight on
// its part); a drag writes the handle's key through /api/edit and re-solves.
const SVG = "http://www.w3.org/2000/svg";
let motion = null;
let frame = 0;
let playing = false;
let scale = 1; // drawing units (mm) per metre
let bodyPaths = []; // each body's outline as an SVG path (drawing units, its own frame)

function el(name, attrs, parent) {
  const e = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}

function showMotion(m) {
  motion = m;
  $("view").hidden = !m;
  if (!m || !m.frames.length) { cwPlots.setAngle(null); return; }
  scale = 1000;
  bodyPaths = (m.bodies || []).map((b) => b.loops.map((l) => "M" + l.map((p) => p[0] * scale + " " + p[1] * scale).join(" L") + " Z").join(" "));
  const pts = [];
  for (const f of m.frames) {
    for (const [a, b] of f.links) pts.push(a, b);
    for (const c of f.counterweights) pts.push(c);
    (m.bodies || []).forEach((b, i) => {
      for (const l of b.loops) {
        const step = Math.max(1, Math.floor(l.length / 24));
        for (let k = 0; k < l.length; k += step) pts.push(placed(f.poses[i], l[k]));
      }
    });
  }
  for (const h of m.handles) pts.push(handleAt(h, 0));
  for (const [a, b] of m.guides || []) pts.push(a, b);
  for (const mk of m.marks || []) pts.push(...mk.points.map((p) => placed(mk.poses && mk.poses.length ? mk.poses[0] : null, p)));
  let [x0, x1, y0, y1] = [Infinity, -Infinity, Infinity, -Infinity];
  for (const p of pts) {
    x0 = Math.min(x0, p[0] * scale); x1 = Math.max(x1, p[0] * scale);
    y0 = Math.min(y0, p[1] * scale); y1 = Math.max(y1, p[1] * scale);
  }
  const pad = 0.08 * Math.max(x1 - x0, y1 - y0, 1);
  // y up: the drawing is flipped inside a group, so the view box's y is −y.
  $("mech").setAttribute("viewBox", [x0 - pad, -y1 - pad, x1 - x0 + 2 * pad, y1 - y0 + 2 * pad].join(" "));
  $("theta").max = String(m.frames.length - 1);
  frame = Math.min(frame, m.frames.length - 1);
  showLegend(m);
  drawFrame();
}

// A point p of a part's frame placed at pose [x, y, angle] (m); no pose: p itself.
function placed(pose, p) {
  if (!pose) return p;
  const [c, s] = [Math.cos(pose[2]), Math.sin(pose[2])];
  return [pose[0] + c * p[0] - s * p[1], pose[1] + s * p[0] + c * p[1]];
}

// The world point w in a part's frame at pose (the inverse of placed).
function local(pose, w) {
  if (!pose) return w;
  const [c, s] = [Math.cos(pose[2]), Math.sin(pose[2])];
  const [dx, dy] = [w[0] - pose[0], w[1] - pose[1]];
  return [c * dx + s * dy, -s * dx + c * dy];
}

// Where handle h is in frame k (m, world).
function handleAt(h, k) {
  return placed(h.poses && h.poses.length ? h.poses[k] : null, h.at);
}

// The bodies' legend: each body's name and where its shape comes from (the assumed discs
// say so), with its colour.
function showLegend(m) {
  const ul = $("legend");
  ul.replaceChildren();
  const item = (kind, text) => {
    const li = document.createElement("li");
    const sw = document.createElement("span");
    sw.className = "swatch " + kind;
    li.append(sw, text);
    ul.appendChild(li);
  };
  for (const b of m.bodies || []) item(b.kind, b.name + ": " + b.note);
  // The kinematic requirement drawn over the mechanism (a path's points, a dwell's window).
  for (const mk of m.marks || []) item("mark", mk.label);
  ul.hidden = !ul.children.length;
}

function drawFrame() {
  const m = motion;
  const svg = $("mech");
  svg.replaceChildren();
  const box = svg.viewBox.baseVal;
  const w = Math.max(box.width, box.height) / 250; // a line about 1/250 of the view
  const g = el("g", { transform: "scale(1,-1)", id: "world" }, svg);
  // The path of every link's tip over the turn.
  const n = m.frames[0].links.length;
  for (let i = 0; i < n; i++) {
    const d = m.frames.map((f, k) => (k ? "L" : "M") + f.links[i][1][0] * scale + " " + f.links[i][1][1] * scale).join(" ");
    el("path", { d: d + " Z", class: "path", "stroke-width": w / 2 }, g);
  }
  for (const [a, b] of m.guides || []) {
    el("line", { x1: a[0] * scale, y1: a[1] * scale, x2: b[0] * scale, y2: b[1] * scale, class: "guide", "stroke-width": w, "stroke-dasharray": 4 * w + " " + 2 * w }, g);
  }
  const f = m.frames[frame];
  (m.bodies || []).forEach((b, i) => {
    const [x, y, a] = f.poses[i];
    const path = el("path", { d: bodyPaths[i], class: "body " + b.kind, "fill-rule": "evenodd", "stroke-width": w / 2, transform: "translate(" + x * scale + " " + y * scale + ") rotate(" + a * 180 / Math.PI + ")" }, g);
    if (b.kind === "pitch") path.setAttribute("stroke-dasharray", 4 * w + " " + 2 * w);
    el("title", {}, path).textContent = b.name + ": " + b.note;
  });
  // Over the bodies (a crank's window lies inside its counterweight), under the links.
  drawMarks(m, g, svg, w);
  for (const [a, b] of f.links) {
    el("line", { x1: a[0] * scale, y1: a[1] * scale, x2: b[0] * scale, y2: b[1] * scale, class: "link", "stroke-width": 2.5 * w }, g);
  }
  for (const [a, b] of f.links) {
    for (const p of [a, b]) el("circle", { cx: p[0] * scale, cy: p[1] * scale, r: 2.5 * w, class: "joint", "stroke-width": w }, g);
  }
  // Each link's name beside its middle, on its left (outside the flipped group, so the text
  // reads upright).
  f.links.forEach(([a, b], i) => {
    const [dx, dy] = [b[0] - a[0], b[1] - a[1]];
    const n = Math.hypot(dx, dy);
    // A link without a tip (a slider): below its joint.
    const [nx, ny] = n ? [-dy / n, dx / n] : [0, -1.4];
    const x = (a[0] + b[0]) / 2 * scale + 5 * w * nx;
    const y = (a[1] + b[1]) / 2 * scale + 5 * w * ny;
    const t = el("text", { x: x, y: -y, class: "label", "font-size": 7 * w, "text-anchor": "middle", "dominant-baseline": "middle" }, svg);
    t.textContent = m.names[i] || "";
  });
  for (const c of f.counterweights) {
    el("circle", { cx: c[0] * scale, cy: c[1] * scale, r: 1.5 * w, class: "cw" }, g);
  }
  // A ring handle (a reference point that may sit on another handle: a drawn outline's
  // origin at its link's joint) is drawn first and larger, so the handle it surrounds stays
  // on top and the ring is grabbed by its rim.
  const rings = m.handles.filter((h) => h.ring);
  for (const h of rings.concat(m.handles.filter((h) => !h.ring))) {
    const p = handleAt(h, frame);
    const c = el("circle", { cx: p[0] * scale, cy: p[1] * scale, r: (h.ring ? 9 : 5) * w, class: h.ring ? "handle ring" : "handle", "stroke-width": 1.5 * w, "data-key": h.key }, g);
    if (h.ring) c.setAttribute("stroke-dasharray", 3 * w + " " + 1.5 * w);
    const t = el("title", {}, c);
    t.textContent = h.key + (h.scalar ? " = " + h.scalar.value.toPrecision(6) + " " + h.scalar.unit : "");
    c.addEventListener("pointerdown", (e) => drag(e, c, h));
  }
  $("drag-hint").hidden = !m.handles.length;
  $("theta").value = String(frame);
  $("theta-label").textContent = "θ = " + (f.theta * 180 / Math.PI).toFixed(0) + "°";
  cwPlots.setAngle((f.theta * 180) / Math.PI);
}

// The kinematic requirement's marks: a trace as a thick line (the output's path over a dwell
// window, a tracer's path), points as numbered circles (a path's precision points Q1, Q2, …),
// both fixed in the world; a tracer as a dot on its moving link; the label as the title.
function drawMarks(m, g, svg, w) {
  for (const mk of m.marks || []) {
    if (mk.kind === "trace") {
      const d = mk.points.map((p, k) => (k ? "L" : "M") + p[0] * scale + " " + p[1] * scale).join(" ");
      // Thick, with round ends: a dwell's output stands nearly still, its trace a blob.
      const path = el("path", { d: d, class: "mark", "stroke-width": 3 * w }, g);
      el("title", {}, path).textContent = mk.label;
      // A trace shorter than a few line widths (an output that dwells) is ringed too.
      const xs = mk.points.map((p) => p[0] * scale), ys = mk.points.map((p) => p[1] * scale);
      if (xs.length && Math.max(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys)) < 6 * w) {
        const c = el("circle", { cx: xs[0], cy: ys[0], r: 5 * w, class: "mark-point", "stroke-width": w }, g);
        el("title", {}, c).textContent = mk.label;
      }
      continue;
    }
    if (mk.kind === "tracer") {
      // A point of a moving part, with a line to the part's reference joint (the tracer on
      // its coupler): placed in this frame.
      const pose = mk.poses[frame];
      const p = placed(pose, mk.points[0]);
      el("line", { x1: pose[0] * scale, y1: pose[1] * scale, x2: p[0] * scale, y2: p[1] * scale, class: "mark", "stroke-width": w }, g);
      const c = el("circle", { cx: p[0] * scale, cy: p[1] * scale, r: 2.5 * w, class: "mark-point tracer", "stroke-width": w }, g);
      el("title", {}, c).textContent = mk.label;
      continue;
    }
    mk.points.forEach((p, k) => {
      const c = el("circle", { cx: p[0] * scale, cy: p[1] * scale, r: 4 * w, class: "mark-point", "stroke-width": w }, g);
      el("title", {}, c).textContent = mk.label;
      const t = el("text", { x: p[0] * scale + 5 * w, y: -p[1] * scale - 5 * w, class: "mark-label", "font-size": 7 * w }, svg);
      t.textContent = "Q" + (k + 1);
    });
  }
}

function drag(e, c, h) {
  e.preventDefault();
  pause();
  c.classList.add("dragging");
  c.setPointerCapture(e.pointerId);
  const world = $("world");
  const pose = h.poses && h.poses.length ? h.poses[frame] : null;
  // The pointer in the handle's frame (m).
  const pointer = (ev) => {
    const p = $("mech").createSVGPoint();
    p.x = ev.clientX;
    p.y = ev.clientY;
    const q = p.matrixTransform(world.getScreenCTM().inverse());
    return local(pose, [q.x / scale, q.y / scale]);
  };
  // Where the handle was grabbed, from its point (a ring is grabbed by its rim): kept
  // through the drag, so a press and release in place writes the value unchanged.
  const g = pointer(e);
  const grab = [g[0] - h.at[0], g[1] - h.at[1]];
  // The handle's point under the pointer (its frame, m); a scalar handle's along its axis.
  const at = (ev) => {
    const p = pointer(ev);
    const l = [p[0] - grab[0], p[1] - grab[1]];
    if (!h.scalar) return l;
    const u = h.scalar.axis;
    const t = (l[0] - h.at[0]) * u[0] + (l[1] - h.at[1]) * u[1];
    return [h.at[0] + t * u[0], h.at[1] + t * u[1], t];
  };
  const move = (ev) => {
    const p = placed(pose, at(ev));
    c.setAttribute("cx", p[0] * scale);
    c.setAttribute("cy", p[1] * scale);
  };
  const up = async (ev) => {
    const released = performance.now();
    c.removeEventListener("pointermove", move);
    c.removeEventListener("pointerup", up);
    const res = await api("/api/edit", {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ text: $("toml").value, key: h.key, value: dragged(h, at(ev)) }),
    });
    const answer = await res.json();
    if (answer.error) { showError(answer.error); return; }
    $("toml").value = answer.text;
    editedAt = released;
    solve();
  };
  c.addEventListener("pointermove", move);
  c.addEventListener("pointerup", up);
}

// The value a drag writes: a point as [x, y] in mm (its frame), a scalar as its value in
// its unit, rounded to its step (at least its minimum).
function dragged(h, p) {
  const s = h.scalar;
  if (!s) {
    const mm = (v) => (Math.round(v * 1e4) / 10).toString() + " mm";
    return [mm(p[0]), mm(p[1])];
  }
  let v = Math.round((s.value + s.per_metre * p[2]) / s.step) * s.step;
  if (s.min !== undefined && v < s.min) v = s.min;
  const digits = Math.max(0, -Math.floor(Math.log10(s.step) + 1e-9));
  return s.unit ? v.toFixed(digits) + " " + s.unit : Number(v.toFixed(digits));
}

function tick() {
  if (playing && motion) {
    frame = (frame + 1) % motion.frames.length;
    drawFrame();
  }
  setTimeout(() => requestAnimationFrame(tick), 60);
}

async function solve() {
  const mine = ++generation;
  const t0 = editedAt === null ? performance.now() : editedAt;
  editedAt = null;
  inFlight = true;
  let answer;
  try {
    // plots=data: a plot of panels comes as its data only (drawn here), not as SVG too;
    // digits=7: the drawing's and the plots' numbers to 7 significant digits (the result's
    // stay exact), half the bytes of a scene with long outlines.
    const res = await api("/api/report?plots=data&digits=7&name=" + encodeURIComponent(fileName), {
      method: "POST",
      headers: { "Content-Type": "text/plain" },
      body: $("toml").value,
    });
    answer = await res.json();
  } finally {
    inFlight = false;
  }
  if (pending) {
    // Edits came in while this one was solved: solve the latest text now.
    pending = false;
    solve();
    return;
  }
  if (mine !== generation) return; // a later edit's answer is on its way
  if (answer.error) showError(answer.error); else show(answer);
  // The form (form.js) follows the text and shows the error at its field.
  document.dispatchEvent(new CustomEvent("cwsynth:answer", { detail: answer.error || null }));
  // Edit to redraw: from the edit (the last keystroke, the drag's release) to this answer
  // drawn, the debounce included.
  const ms = performance.now() - t0;
  $("timing").textContent = "edit to redraw " + ms.toFixed(0) + " ms";
  document.body.dataset.redrawMs = ms.toFixed(1);
  document.body.dataset.solved = String(mine);
}

// An edit solves as soon as no solve is on its way (the events of one change, dispatched
// together, coalesced into one solve), else once that one is back, with the latest text:
// no fixed debounce delay, and at most one request in flight. (A timer's turn: a microtask
// instead, measured again on 2026-11-27, put 29–44 ms between the edit and the request
// against 6–9 ms.)
let scheduled = false;
function edited() {
  if (editedAt === null) editedAt = performance.now();
  if (inFlight) { pending = true; return; }
  if (scheduled) return;
  scheduled = true;
  setTimeout(() => { scheduled = false; solve(); }, 0);
}

async function open(value) {
  let text;
  if (value.startsWith("file:")) {
    fileName = value.slice(5);
    text = await (await api("/api/file/" + encodeURIComponent(fileName))).text();
  } else {
    const family = value.slice(9);
    fileName = "my-" + family + ".toml";
    const all = (await (await api("/api/templates")).json()).templates;
    text = all.find((t) => t.family === family).text;
  }
  $("toml").value = text;
  solve();
}

function download(blob, name) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.click();
  URL.revokeObjectURL(a.href);
}

function save() {
  download(new Blob([$("toml").value], { type: "application/toml" }), fileName);
}

// The result's report page (self-contained) or its drawing's DXF, solved from the text as
// it is, named as the server names it.
async function exportFile(what) {
  const res = await api("/api/export?what=" + what + "&name=" + encodeURIComponent(fileName), {
    method: "POST",
    headers: { "Content-Type": "text/plain" },
    body: $("toml").value,
  });
  if (!res.ok) { showError((await res.json()).error); return; }
  const cd = res.headers.get("Content-Disposition") || "";
  const m = cd.match(/filename="([^"]+)"/);
  download(await res.blob(), m ? m[1] : "cwsynth." + what);
}

async function start() {
  const sel = $("open");
  const files = (await (await api("/api/files")).json()).files || [];
  const templates = (await (await api("/api/templates")).json()).templates || [];
  for (const f of files) sel.add(new Option(f, "file:" + f));
  for (const t of templates) sel.add(new Option("new " + t.family, "template:" + t.family));
  sel.addEventListener("change", () => open(sel.value));
  $("toml").addEventListener("input", edited);
  $("save").addEventListener("click", save);
  $("export-html").addEventListener("click", () => exportFile("html"));
  $("export-dxf").addEventListener("click", () => exportFile("dxf"));
  $("play").addEventListener("click", () => { playing = !playing; $("play").textContent = playing ? "Pause" : "Play"; });
  $("theta").addEventListener("input", () => { frame = Number($("theta").value); pause(); if (motion) drawFrame(); });
  tick();
  if (sel.options.length) open(sel.options[0].value);
}

start();
