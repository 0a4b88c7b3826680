// The designer's page: open a problem file, edit it, and see it re-solved (debounced) on
// every edit. Every element is built with textContent (nothing from a file or a result is
// parsed as HTML); the plots are the server's SVG shown as images (an image runs no script).
"use strict";

const token = new URLSearchParams(location.hash.slice(1)).get("token");
const $ = (id) => document.getElementById(id);
let fileName = "request.toml";
let timer = null;
let generation = 0;

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

function fill(id, map, errors) {
  const body = $(id).querySelector("tbody");
  body.replaceChildren();
  for (const [k, v] of Object.entries(map || {})) {
    const tr = document.createElement("tr");
    cell(tr, k);
    cell(tr, fmt(v), "num");
    if (errors) cell(tr, errors[k] === undefined ? "" : fmt(errors[k]), "num");
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
  fill("objectives", r.objectives, r.errors || {});
  fill("design", r.design);
  const w = $("warnings");
  w.replaceChildren();
  for (const text of r.warnings || []) {
    const li = document.createElement("li");
    li.textContent = text;
    w.appendChild(li);
  }
  $("method").textContent = r.method || "";
  const plots = $("plots");
  plots.replaceChildren();
  for (const p of answer.plots || []) {
    const fig = document.createElement("figure");
    const img = document.createElement("img");
    img.alt = p.caption;
    img.src = "data:image/svg+xml;base64," + btoa(unescape(encodeURIComponent(p.svg)));
    const cap = document.createElement("figcaption");
    cap.textContent = p.caption;
    fig.append(img, cap);
    plots.appendChild(fig);
  }
}

async function solve() {
  const mine = ++generation;
  const t0 = performance.now();
  const res = await api("/api/report?name=" + encodeURIComponent(fileName), {
    method: "POST",
    headers: { "Content-Type": "text/plain" },
    body: $("toml").value,
  });
  const answer = await res.json();
  if (mine !== generation) return; // a later edit's answer is on its way
  if (answer.error) showError(answer.error); else show(answer);
  $("timing").textContent = "edit to redraw " + (performance.now() - t0).toFixed(0) + " ms";
  document.body.dataset.solved = String(mine);
}

function edited() {
  clearTimeout(timer);
  timer = setTimeout(solve, 150);
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

function save() {
  const blob = new Blob([$("toml").value], { type: "application/toml" });
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = fileName;
  a.click();
  URL.revokeObjectURL(a.href);
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
  if (sel.options.length) open(sel.options[0].value);
}

start();
