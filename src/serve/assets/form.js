// The designer's form: every field of the open problem file, generated from the problem
// file's JSON Schema (GET /api/schema: the family's branch) and filled with the file's values
// (POST /api/fields). A change writes one key through POST /api/edit (the file's comments
// and layout kept) and re-solves as the text editor does; the text stays the source of
// truth, and the form is rebuilt from it after every answer. An error's field is shown at
// its row. Every element is built with textContent (no markup from a file or the schema).
"use strict";

(() => {
const form = {
  schema: null, // the whole schema, fetched once
  builtFrom: null, // the text the form shows
  values: {}, // that text's values
  lines: {}, // and the line of every dotted key
  order: {}, // and its place in the file
};

function h(tag, attrs, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === "text") e.textContent = v;
    else if (k === "class") e.className = v;
    else e.setAttribute(k, v);
  }
  for (const c of children) if (c) e.appendChild(c);
  return e;
}

// The schema of one family: its `then` branch (all keys), else the root's.
function familySchema(family) {
  const s = form.schema || {};
  for (const b of s.allOf || []) {
    const c = b.if && b.if.properties && b.if.properties.family;
    if (c && c.const === family) return b.then;
  }
  return s;
}

// A schema with its one-element allOf merged in.
function flat(s) {
  if (s && s.allOf && s.allOf.length === 1) return Object.assign({}, s.allOf[0], s, { allOf: undefined });
  return s || {};
}

function alternatives(s) {
  return (s.anyOf || s.oneOf || []).map(flat);
}

function jsonType(v) {
  if (Array.isArray(v)) return "array";
  if (v === null || v === undefined) return null;
  return typeof v === "object" ? "object" : typeof v;
}

function fits(s, v) {
  const t = jsonType(v);
  if (s.const !== undefined) return s.const === v;
  if (s.type === "integer" || s.type === "number") return t === "number";
  return s.type === t || (s.type === undefined && t !== null);
}

// The schema that describes `v`: for an anyOf/oneOf the branch it fits (the first one
// where it is absent), with the parent's description.
function branch(s, v) {
  s = flat(s);
  const alts = alternatives(s);
  if (!alts.length || alts.every((a) => a.const !== undefined)) return s;
  const pick = alts.find((a) => fits(a, v)) || alts.find((a) => a.const === undefined) || alts[0];
  return Object.assign({}, pick, { description: s.description || pick.description, alts, default: s.default });
}

// The choices of an enum (`enum`, or every branch a `const`), else null.
function choices(s) {
  if (s.enum) return s.enum.map((v) => ({ value: v, description: "" }));
  const alts = alternatives(s);
  if (alts.length && alts.every((a) => a.const !== undefined)) {
    return alts.map((a) => ({ value: a.const, description: a.description || "" }));
  }
  return null;
}

// The units a dimensional string takes, from its schema's title ("… one of the units: m,
// mm, cm (e.g. "1 m")"): [units, example].
function units(s) {
  const m = /units: (.*?) \(e\.g\. "([^"]*)"\)/.exec(s.title || "");
  return m ? [m[1], m[2]] : null;
}

function firstSentence(text) {
  const t = (text || "").split("\n\n")[0].replace(/\s+/g, " ");
  const i = t.search(/\.\s/);
  return i > 0 ? t.slice(0, i + 1) : t;
}

function childKey(path, name) {
  return path ? path + "." + name : name;
}

// Every type a field's schema allows (its branches' included).
function allowed(s) {
  const alts = s.alts || alternatives(s);
  const ts = new Set([s.type, ...alts.map((a) => a.type)]);
  return ts;
}

// The value a field's text stands for: "" removes the key (null); a number or a boolean
// where the schema allows one; an array split at commas (where the field is one, or may be
// one and has a comma); JSON where it looks like an object; else the text (a wrong one is
// sent as it is: the server names the error at its field).
function parse(text, s) {
  const t = text.trim();
  if (t === "") return null;
  const ts = allowed(s);
  if (t.startsWith("{")) {
    try { return JSON.parse(t); } catch (_) { return t; }
  }
  if (s.type === "array" || (ts.has("array") && t.includes(","))) {
    const item = flat(s.items || (s.alts || []).find((a) => a.type === "array")?.items || {});
    return t.split(",").map((x) => parse(x, item)).filter((x) => x !== null);
  }
  if ((ts.has("number") || ts.has("integer")) && /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/.test(t)) return Number(t);
  if (ts.has("boolean") && (t === "true" || t === "false")) return t === "true";
  return t;
}

function shown(v) {
  if (v === undefined || v === null) return "";
  if (Array.isArray(v) && v.every((x) => jsonType(x) !== "object" && jsonType(x) !== "array")) return v.join(", ");
  return typeof v === "object" ? JSON.stringify(v) : String(v);
}

// The value at a dotted key of the file's values (undefined where absent).
function valueAt(key) {
  let v = form.values;
  for (const part of key.split(".")) {
    const m = /^([^[]+)(?:\[(\d+)\])?$/.exec(part);
    v = v && v[m[1]];
    if (m[2] !== undefined) v = v && v[Number(m[2])];
    if (v === undefined) return undefined;
  }
  return v;
}

// Writes `value` (null: removes) at `key`. Where the key's table is absent, the outermost
// absent table is written with the value inside it (one edit: a new `[table]`).
async function formEdit(key, value) {
  const t0 = performance.now(); // the edit-to-redraw clock starts at the change
  let at = key;
  let v = value;
  const parts = key.split(".");
  for (let i = 1; i < parts.length && value !== null; i++) {
    const parent = parts.slice(0, i).join(".");
    if (valueAt(parent) === undefined) {
      at = parent;
      v = parts.slice(i).reduceRight((inner, name) => ({ [name]: inner }), value);
      break;
    }
  }
  const res = await api("/api/edit", {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ text: $("toml").value, key: at, value: v }),
  });
  const answer = await res.json();
  if (answer.error) { showError(answer.error); markError(Object.assign({}, answer.error, { field: key })); return; }
  $("toml").value = answer.text;
  if (editedAt === null) editedAt = t0;
  edited();
}

// One field's row: its name (a `*` where required), its line, the input, its unit and the
// first sentence of its description (all of it on hover).
function fieldRow(name, s, v, key, required) {
  s = branch(s, v);
  const u = units(s) || (s.items && units(flat(s.items)));
  const known = Object.keys(s).length > 0;
  const row = h("div", { class: known ? "field" : "field unknown", "data-key": key });
  const label = h("label", { class: "name", text: name + (required ? " *" : "") });
  label.title = key + (s.description ? "\n\n" + s.description : "");
  const line = form.lines[key];
  const lineLink = line ? h("button", { type: "button", class: "line", text: "L" + line, title: "show line " + line + " in the text" }) : null;
  if (lineLink) lineLink.addEventListener("click", () => showLine(line));
  const input = fieldInput(s, v, key);
  input.id = "field:" + key;
  label.htmlFor = input.id;
  const hint = [u ? "unit: " + u[0] : null, firstSentence(s.description)].filter(Boolean).join(" — ");
  row.append(label, input, lineLink || h("span"));
  row.appendChild(h("small", { class: "hint", text: hint }));
  row.appendChild(h("p", { class: "field-error", hidden: "" }));
  return row;
}

function fieldInput(s, v, key) {
  const opts = choices(s) || (s.type === "boolean" ? [{ value: true }, { value: false }] : null);
  let input;
  if (opts) {
    input = h("select", {});
    const dflt = s.default !== undefined ? "(default " + shown(s.default) + ")" : "(none)";
    input.add(new Option(dflt, ""));
    for (const o of opts) {
      const opt = new Option(String(o.value), String(o.value));
      opt.title = o.description || "";
      input.add(opt);
    }
    input.value = v === undefined ? "" : String(v);
  } else {
    input = h("input", { type: "text", spellcheck: "false" });
    input.value = shown(v);
    const u = units(s) || (s.items && units(flat(s.items)));
    if (s.default !== undefined) input.placeholder = "default " + shown(s.default);
    else if (u) input.placeholder = "e.g. " + u[1];
  }
  input.dataset.key = key;
  input.dataset.orig = input.value;
  input.addEventListener("change", () => formEdit(key, parse(input.value, s)));
  return input;
}

// The place of a key in the file (an array of tables: its first entry's).
function placeOf(key) {
  const i = form.order[key] ?? form.order[key + "[0]"];
  return i === undefined ? 1e9 : i;
}

// A table's rows: the keys the file has, in its order, then the schema's other keys folded
// under "more fields"; keys the schema does not know are shown too (their error lands there).
function tableRows(s, values, path) {
  s = flat(s);
  const props = s.properties || {};
  const box = h("div", { class: "rows" });
  const present = Object.keys(values || {});
  present.sort((a, b) => placeOf(childKey(path, a)) - placeOf(childKey(path, b)));
  for (const name of present) box.appendChild(member(name, props[name] || {}, values[name], childKey(path, name), s));
  const absent = Object.keys(props).filter((n) => !(n in (values || {})));
  if (absent.length) {
    const more = h("details", { class: "more", "data-key": path + "#more" }, h("summary", { text: absent.length + " more field" + (absent.length > 1 ? "s" : "") + " (absent: the default)" }));
    for (const name of absent) more.appendChild(member(name, props[name], undefined, childKey(path, name), s));
    box.appendChild(more);
  }
  return box;
}

// One member of a table: a field, a sub-table, an array of tables or a map of named tables.
function member(name, s, v, key, parent) {
  const required = (parent.required || []).includes(name);
  const b = branch(s, v);
  if (b.type === "array" && flat(b.items).type === "object") return entries(name, b, v || [], key);
  if (b.type === "object" && b.properties && jsonType(v) !== "string") return group(name, b, v, key, required);
  if (b.type === "object" && typeof b.additionalProperties === "object" && jsonType(v) === "object") {
    const g = groupBox(name, b, key, true);
    for (const [k, x] of Object.entries(v)) g.appendChild(group(k, b.additionalProperties, x, key + "." + k, false));
    return g;
  }
  return fieldRow(name, s, v, key, required);
}

function groupBox(name, s, key, open) {
  const g = h("details", { class: "group", "data-key": key });
  g.open = open;
  const sum = h("summary", { text: name });
  sum.title = key + (s.description ? "\n\n" + s.description : "");
  g.appendChild(sum);
  g.appendChild(h("p", { class: "field-error", hidden: "" }));
  return g;
}

function group(name, s, v, key, required) {
  const g = groupBox(name + (required ? " *" : ""), s, key, v !== undefined);
  if (v === undefined) g.appendChild(h("small", { class: "hint", text: "absent: a field written here adds the table" }));
  g.appendChild(tableRows(s, v || {}, key));
  return g;
}

// An array of tables (`[[mechanism.dyads]]`): each entry with "Remove", and "Add" (a copy of
// the last entry, or an empty one whose missing fields the check then names).
function entries(name, s, list, key) {
  const g = groupBox(name + " (" + list.length + ")", s, key, list.length > 0);
  list.forEach((entry, i) => {
    const k = key + "[" + i + "]";
    const sub = group(name + "[" + i + "]", flat(s.items), entry, k, false);
    const rm = h("button", { type: "button", class: "remove", text: "Remove", "data-key": k });
    rm.addEventListener("click", () => formEdit(k, null));
    sub.querySelector("summary").after(rm);
    g.appendChild(sub);
  });
  const add = h("button", { type: "button", class: "add", text: "Add " + name + " entry", "data-key": key });
  add.addEventListener("click", () => formEdit(key + "[" + list.length + "]", list.length ? list[list.length - 1] : {}));
  g.appendChild(add);
  return g;
}

// Selects line `n` of the text (the field's place in the file).
function showLine(n) {
  const ta = $("toml");
  const lines = ta.value.split("\n");
  const start = lines.slice(0, n - 1).reduce((a, l) => a + l.length + 1, 0);
  ta.focus();
  ta.setSelectionRange(start, start + (lines[n - 1] || "").length);
  const lh = ta.scrollHeight / Math.max(lines.length, 1);
  ta.scrollTop = Math.max(0, (n - 3) * lh);
}

function render() {
  const active = document.activeElement;
  const keep = active && active.dataset && active.closest("#form") && active.dataset.key
    ? { key: active.dataset.key, value: active.value, dirty: active.value !== active.dataset.orig }
    : null;
  const open = new Set([...$("form").querySelectorAll("details[open]")].map((d) => d.dataset.key));
  const s = familySchema(form.values.family);
  const root = tableRows(s, form.values, "");
  $("form").replaceChildren(root);
  for (const d of $("form").querySelectorAll("details")) if (open.has(d.dataset.key)) d.open = true;
  const fam = [...$("form").querySelectorAll("[data-key='family']")].find((e) => e.tagName !== "DIV");
  if (fam) fam.disabled = true; // another family: open its template
  if (keep) {
    const e = [...$("form").querySelectorAll("input, select")].find((x) => x.dataset.key === keep.key);
    if (e) { if (keep.dirty) e.value = keep.value; e.focus(); }
  }
}

// The row a dotted key names, or its nearest shown parent's.
function rowOf(field) {
  const rows = [...$("form").querySelectorAll(".field, .group")];
  for (let k = field; k; k = k.replace(/(\.[^.[]+|\[\d+\])$/, "")) {
    const r = rows.find((x) => x.dataset.key === k);
    if (r) return r;
    if (!/(\.[^.[]+|\[\d+\])$/.test(k)) break;
  }
  return null;
}

function markError(e) {
  for (const r of $("form").querySelectorAll(".has-error")) {
    r.classList.remove("has-error");
    const p = r.querySelector(":scope > .field-error");
    if (p) { p.hidden = true; p.textContent = ""; }
  }
  delete document.body.dataset.formError;
  if (!e) return;
  const r = (e.field && rowOf(e.field)) || null;
  if (!r) return;
  r.classList.add("has-error");
  const p = r.querySelector(":scope > .field-error");
  p.textContent = (e.line ? "line " + e.line + ": " : "") + e.message;
  p.hidden = false;
  for (let d = r.closest("details"); d; d = d.parentElement.closest("details")) d.open = true;
  if (document.activeElement !== $("toml")) r.scrollIntoView({ block: "nearest" }); // not while typing there
  document.body.dataset.formError = r.dataset.key;
}

// A note above the form (null: none), outside its scrolled box.
function note(text) {
  let p = $("form-view").querySelector(".form-note");
  if (!p) {
    p = h("p", { class: "form-note error" });
    $("form").before(p);
  }
  p.textContent = text || "";
  p.hidden = !text;
}

// After every answer: rebuild the form where the text changed, then show the error, if any.
async function formAnswered(error) {
  const text = $("toml").value;
  if (text !== form.builtFrom) {
    const res = await api("/api/fields?name=" + encodeURIComponent(fileName), {
      method: "POST",
      headers: { "Content-Type": "text/plain" },
      body: text,
    });
    const answer = await res.json();
    if (text !== $("toml").value) return; // a later text's answer follows
    if (answer.error) {
      note("The text does not parse" + (answer.error.line ? " (line " + answer.error.line + ")" : "") +
        ": the form shows the last text that did; fix it in the text.");
    } else {
      form.builtFrom = text;
      form.values = answer.values;
      form.lines = Object.fromEntries(answer.keys);
      form.order = Object.fromEntries(answer.keys.map(([k], i) => [k, i]));
      note(null);
      render();
    }
  } else {
    note(null); // back to the text the form shows
  }
  markError(error);
  document.body.dataset.form = String(Number(document.body.dataset.form || 0) + 1);
}

async function formStart() {
  form.schema = await (await api("/api/schema")).json();
  document.addEventListener("cwsynth:answer", (ev) => formAnswered(ev.detail));
  if (document.body.dataset.solved) formAnswered(null);
}

formStart();
})();
