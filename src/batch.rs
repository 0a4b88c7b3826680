//! Batch design: many machines at once (`cwsynth batch`), with streaming fleets, rayon
//! across machines, resumable atomic output, deterministic sharding and merged reports.
//!
//! An input is a problem file, a directory of them, or a **fleet**
//! `TEMPLATE.toml:FLEET.csv`: every CSV row overrides dotted keys of the template
//! (`mechanism.speed`, `design.radius`, …). Units are never guessed: a dimensional cell
//! carries its unit (`35 mm`), or its column header does (`mechanism.speed [rpm]`: a bare
//! number in that column is in rpm); a bare number with neither is an error naming the
//! file, line and column. The template
//! is parsed once; a row sets its cells in a copy of the parsed table and resolves that with
//! [`parse_table`] (the checks of `cwsynth solve`, no TOML printed or re-parsed). A row that
//! fails there is redone the slow way, editing the template text with `toml_edit` and running
//! [`parse_str`], so its message is the one `cwsynth solve` gives, reported as
//! `fleet.csv:LINE: field `x.y`: reason`.
//!
//! Machines are numbered in input order (0-based `index`, across all inputs). The work is
//! streamed in chunks of [`CHUNK`] machines: each chunk is solved in parallel on a dedicated
//! rayon pool, then its summary rows are appended in input order to the summary CSV, so
//! memory is bounded by one chunk whatever the fleet size. `--shard i/n` keeps the machines
//! with `index % n == i`.
//!
//! Re-runs skip a machine whose result is present and whose input hash matches: with
//! per-machine files, `<name>.json` carries `batch.input_hash`; with `--summary-only`, the
//! previous summary row (completed `summary.csv` or the `.partial` of an interrupted run)
//! carries it. The summary is written to `<summary>.partial` and renamed when complete.

use crate::families::{parse_str, parse_table, solve_scene, Scene};
use crate::problem::ProblemError;
use crate::report::{
    fmt_num, json_path, md_escape, report_files, truncate, write_atomic, write_replace,
};
use crate::units::Unit;
use anyhow::{bail, Context};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Machines solved per chunk (the memory bound: one chunk of summary rows).
pub const CHUNK: usize = 2048;
/// Rows shown in the tables of `summary.md` and `index.html` (all rows are in `summary.csv`).
pub const REPORT_ROWS: usize = 1000;
/// Machines whose plots are inlined in `index.html`.
pub const REPORT_PLOTS: usize = 40;

/// One batch input.
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    /// A problem file.
    File(PathBuf),
    /// A template and a fleet CSV.
    Fleet {
        /// The template problem file.
        template: PathBuf,
        /// The CSV of overrides, one row per machine.
        csv: PathBuf,
    },
}

impl Input {
    /// Parses `FILE`, `DIR` (expanded later) or `TEMPLATE.toml:FLEET.csv`.
    pub fn parse(s: &str) -> Input {
        if let Some(i) = s.find(".toml:") {
            let (t, c) = (&s[..i + 5], &s[i + 6..]);
            if !c.is_empty() {
                return Input::Fleet {
                    template: t.into(),
                    csv: c.into(),
                };
            }
        }
        Input::File(s.into())
    }
}

/// Expands directories into their `*.toml` files (sorted).
/// Expands directories into their `*.toml` files (sorted), keeps files as given. A path
/// that does not exist, or a directory without a problem file, is a usage error (exit 2).
pub fn expand_inputs(inputs: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in inputs {
        if !p.exists() {
            bail!("{}: no such file or directory", p.display());
        }
        if p.is_dir() {
            let mut v: Vec<PathBuf> = std::fs::read_dir(p)
                .with_context(|| format!("cannot list {}", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|q| q.extension().is_some_and(|x| x == "toml"))
                .collect();
            v.sort();
            if v.is_empty() {
                bail!(
                    "{}: no problem files (*.toml) in this directory",
                    p.display()
                );
            }
            out.extend(v);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

pub fn expand(args: &[String]) -> anyhow::Result<Vec<Input>> {
    let mut out = Vec::new();
    for a in args {
        match Input::parse(a) {
            Input::File(p) if p.is_dir() => {
                for f in expand_inputs(&[p])? {
                    out.push(Input::File(f));
                }
            }
            i => out.push(i),
        }
    }
    Ok(out)
}

/// Batch options.
#[derive(Debug, Clone)]
pub struct Options {
    /// Output directory.
    pub out: PathBuf,
    /// Worker threads (default: available parallelism).
    pub threads: Option<usize>,
    /// `(i, n)`: only machines with `index % n == i`.
    pub shard: Option<(u64, u64)>,
    /// No progress output (errors are still in the summary).
    pub quiet: bool,
    /// Write only the summary (no per-machine JSON, Markdown, plots).
    pub summary_only: bool,
}

/// Parses `i/n`.
pub fn parse_shard(s: &str) -> anyhow::Result<(u64, u64)> {
    let (a, b) = s
        .split_once('/')
        .context("--shard: expected i/n, e.g. 0/4")?;
    let (i, n): (u64, u64) = (
        a.trim().parse().context("--shard: i is not a number")?,
        b.trim().parse().context("--shard: n is not a number")?,
    );
    if n == 0 || i >= n {
        bail!("--shard {s}: need 0 ≤ i < n");
    }
    Ok((i, n))
}

/// One line of `summary.csv` (columns documented in `docs/batch.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// Position in the input order (0-based, across all inputs).
    pub index: u64,
    /// Machine name (result file stem).
    pub name: String,
    /// Family, empty when the input could not be read.
    pub family: String,
    /// `optimal`, `analysed`, `inaccurate`, `infeasible`, `failed`, or `error` (bad input).
    pub status: String,
    /// The family's key objective (a result key).
    pub objective: String,
    /// Its value (SI).
    pub value: Option<f64>,
    /// Its estimated absolute error.
    pub error: Option<f64>,
    /// The best classical baseline, where the family has baselines.
    pub baseline: String,
    /// The baseline's value of the key objective.
    pub baseline_value: Option<f64>,
    /// Improvement of the optimum over that baseline, %.
    pub improvement_pct: Option<f64>,
    /// Design values `key=value;…` (SI).
    pub design: String,
    /// All objectives `key=value;…` (SI).
    pub objectives: String,
    /// Wall time of the solve, s (the only column that differs between identical runs).
    pub time_s: f64,
    /// Content hash of the machine's input (file text, or template text, CSV header and the
    /// row's name and cells) and the cwsynth build.
    pub input_hash: String,
    /// Where the machine came from: file, or `fleet.csv:LINE`.
    pub source: String,
    /// Why it failed (errors, warnings of a failed solve), else empty.
    pub message: String,
}

/// Every status a summary row can carry: the result vocabulary plus `error` (bad input).
pub const ROW_STATUSES: [&str; 8] = [
    "optimal",
    "best_found",
    "degenerate",
    "analysed",
    "inaccurate",
    "infeasible",
    "failed",
    "error",
];

/// First characters that make a spreadsheet read a cell as a formula (OWASP, "CSV
/// injection"); a text cell starting with one, or with the escape `'` itself, is written with
/// a leading `'`.
const FORMULA_START: [char; 7] = ['=', '+', '-', '@', '\t', '\r', '\''];

impl Row {
    /// The text columns (every column but the numbers `index`, `value`, `error`,
    /// `baseline_value`, `improvement_pct`, `time_s`).
    fn texts(&mut self) -> [&mut String; 10] {
        [
            &mut self.name,
            &mut self.family,
            &mut self.status,
            &mut self.objective,
            &mut self.baseline,
            &mut self.design,
            &mut self.objectives,
            &mut self.input_hash,
            &mut self.source,
            &mut self.message,
        ]
    }

    /// The row as written to a summary CSV: a text cell starting with `=`, `+`, `-`, `@`, a
    /// tab, a carriage return or `'` gets a leading `'`, so no spreadsheet runs it as a
    /// formula. Numeric columns are numbers and never escaped (`-3.5` stays). Undone by
    /// [`Row::csv_unescaped`].
    pub fn csv_escaped(&self) -> Row {
        let mut r = self.clone();
        for t in r.texts() {
            if t.starts_with(FORMULA_START) {
                t.insert(0, '\'');
            }
        }
        r
    }

    /// A row read from a summary CSV with [`Row::csv_escaped`] undone: one leading `'` of a
    /// text cell is dropped.
    pub fn csv_unescaped(mut self) -> Row {
        for t in self.texts() {
            if t.starts_with('\'') {
                t.remove(0);
            }
        }
        self
    }

    /// Checks a row read back from a summary CSV (a resumed run's checkpoint, or a shard
    /// given to `merge`): a file written by someone else is input like any other. The status
    /// must be one of [`ROW_STATUSES`], the family a known one, the name a valid machine name
    /// (for an error row: no path separator, control character or leading `.`), so nothing
    /// from the file can name a path outside the folder or reach a report as markup.
    pub fn validate(&self) -> Result<(), String> {
        if !ROW_STATUSES.contains(&self.status.as_str()) {
            return Err(format!(
                "status `{}` is not one of {}",
                self.status.escape_debug(),
                ROW_STATUSES.join(", ")
            ));
        }
        if !(self.family.is_empty() || crate::families::by_name(&self.family).is_some()) {
            return Err(format!("unknown family `{}`", self.family.escape_debug()));
        }
        let plain_name = !self.name.starts_with('.')
            && !self
                .name
                .chars()
                .any(|c| c.is_control() || matches!(c, '/' | '\\' | ':'));
        if self.status == "error" {
            if !plain_name {
                return Err(format!(
                    "name `{}` is not a plain name",
                    self.name.escape_debug()
                ));
            }
        } else {
            crate::problem::check_name(&self.name).map_err(|e| e.to_string())?;
        }
        if !self.input_hash.chars().all(|c| c.is_ascii_hexdigit()) {
            return Err("input_hash is not hexadecimal".into());
        }
        Ok(())
    }
}

/// Counts of one batch run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    /// Machines in this run (this shard).
    pub total: u64,
    /// Optimal, analysed or inaccurate.
    pub ok: u64,
    /// Bad input, infeasible or failed.
    pub failed: u64,
    /// Reused from a previous run (content hash unchanged).
    pub skipped: u64,
}

/// A 128-bit content hash being computed (two FNV-1a 64 streams), started with the cwsynth
/// version and a hash of its source (`CWSYNTH_SOURCE_HASH`, from `build.rs`), so a changed
/// program re-solves everything instead of keeping results the old code computed.
#[derive(Clone)]
struct Hasher {
    a: u64,
    b: u64,
}

impl Hasher {
    /// A hash of the cwsynth build so far.
    fn new() -> Hasher {
        let mut h = Hasher {
            a: 0xcbf2_9ce4_8422_2325,
            b: 0x6c62_272e_07bb_0142,
        };
        h.bytes(env!("CARGO_PKG_VERSION").as_bytes());
        h.bytes(b"\0");
        h.bytes(env!("CWSYNTH_SOURCE_HASH").as_bytes());
        h.bytes(b"\0");
        h
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &x in bytes {
            self.a = (self.a ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3);
            self.b = (self.b ^ x as u64 ^ 0x5a).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// One string of a sequence: its length, then its bytes (so no two sequences run together).
    fn field(&mut self, s: &str) {
        self.bytes(&(s.len() as u64).to_le_bytes());
        self.bytes(s.as_bytes());
    }

    fn hex(&self) -> String {
        format!("{:016x}{:016x}", self.a, self.b)
    }
}

/// The content hash of a problem file's text and the cwsynth build, hex.
pub fn content_hash(text: &str) -> String {
    let mut h = Hasher::new();
    h.bytes(text.as_bytes());
    h.hex()
}

fn kv(m: Option<&serde_json::Value>) -> String {
    m.and_then(|v| v.as_object())
        .map(|o| {
            o.iter()
                .filter_map(|(k, v)| v.as_f64().map(|x| format!("{k}={x:?}")))
                .collect::<Vec<_>>()
                .join(";")
        })
        .unwrap_or_default()
}

/// The summary row of a result JSON (fresh or read back from `<name>.json`).
pub fn row_from_json(index: u64, source: &str, hash: &str, v: &serde_json::Value) -> Row {
    let s = |k: &str| v.get(k).and_then(|x| x.as_str()).unwrap_or("").to_string();
    let empty = serde_json::Map::new();
    let objs = v
        .get("objectives")
        .and_then(|o| o.as_object())
        .unwrap_or(&empty);
    let family = s("family");
    let objective = v
        .get("objective")
        .and_then(|x| x.as_str())
        .filter(|k| objs.contains_key(*k))
        .map(str::to_string)
        // Every result names its key objective (its family's headline); a result without
        // one is judged on its first objective.
        .unwrap_or_else(|| objs.keys().next().cloned().unwrap_or_default());
    let value = objs.get(&objective).and_then(|x| x.as_f64());
    let error = v
        .get("errors")
        .and_then(|e| e.get(&objective))
        .and_then(|x| x.as_f64());
    // Best classical baseline: the smallest improvement (the hardest one to beat).
    let mut best: Option<(String, Option<f64>, f64)> = None;
    if let Some(b) = v.get("baselines").and_then(|b| b.as_object()) {
        for (name, m) in b {
            if let Some(imp) = m.get("improvement_pct").and_then(|x| x.as_f64()) {
                if best.as_ref().is_none_or(|(_, _, i)| imp < *i) {
                    best = Some((
                        name.clone(),
                        m.get(&objective).and_then(|x| x.as_f64()),
                        imp,
                    ));
                }
            }
        }
    }
    let status = s("status");
    let message = if status == "degenerate" {
        s("status_detail")
    } else if matches!(status.as_str(), "failed" | "infeasible" | "inaccurate") {
        v.get("warnings")
            .and_then(|w| w.as_array())
            .map(|w| {
                w.iter()
                    .filter_map(|x| x.as_str())
                    .collect::<Vec<_>>()
                    .join(" | ")
            })
            .unwrap_or_default()
    } else {
        String::new()
    };
    Row {
        index,
        name: s("name"),
        family,
        status,
        objective,
        value,
        error,
        baseline: best.as_ref().map(|b| b.0.clone()).unwrap_or_default(),
        baseline_value: best.as_ref().and_then(|b| b.1),
        improvement_pct: best.as_ref().map(|b| b.2),
        design: kv(v.get("design")),
        objectives: kv(v.get("objectives")),
        time_s: v
            .get("timing")
            .and_then(|t| t.get("total_s"))
            .and_then(|x| x.as_f64())
            .unwrap_or(0.0),
        input_hash: hash.into(),
        source: source.into(),
        message,
    }
}

/// Bytes of a message or an error row's name kept in the summary (a 10 MB cell is not echoed
/// whole).
pub const MESSAGE_BYTES: usize = 2000;
/// Bytes of an error row's name kept in the summary (a valid name has at most 128).
const NAME_BYTES: usize = 200;

fn error_row(index: u64, name: &str, source: &str, hash: &str, message: String) -> Row {
    Row {
        index,
        name: truncate(name, NAME_BYTES).into_owned(),
        family: String::new(),
        status: "error".into(),
        objective: String::new(),
        value: None,
        error: None,
        baseline: String::new(),
        baseline_value: None,
        improvement_pct: None,
        design: String::new(),
        objectives: String::new(),
        time_s: 0.0,
        input_hash: hash.into(),
        source: truncate(source, MESSAGE_BYTES).into_owned(),
        message: truncate(&message, MESSAGE_BYTES).into_owned(),
    }
}

/// The row of a machine whose pipeline panicked: `failed`, the panic as the reason, and no
/// input hash (so a re-run tries it again).
fn panic_row(index: u64, name: &str, source: &str, panic: &str) -> Row {
    let mut row = error_row(
        index,
        name,
        source,
        "",
        format!("{source}: internal error (a panic, please report it): {panic}"),
    );
    row.status = "failed".into();
    row
}

thread_local! {
    /// Set while [`isolate`] runs on this thread: the panic hook records instead of printing.
    static CATCHING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    /// The last panic [`isolate`] caught on this thread: message and location.
    static CAUGHT: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

/// Runs `f`; a panic inside it is returned as `Err("message at file:line")` instead of
/// unwinding further, and the default hook's report on stderr is replaced by that value
/// (the caller reports it once, as the machine's reason). Panics on other threads, or
/// outside `isolate`, are reported by the previous hook as before. This is how one machine
/// of a batch (or one file of `cwsynth solve`) cannot take the others down: whatever its
/// parse, solve, report or plot does, the run finishes and says why that machine failed.
/// (An abort, e.g. an allocation failure, cannot be caught; input limits prevent those.)
pub fn isolate<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if CATCHING.with(|c| c.get()) {
                let at = info
                    .location()
                    .map(|l| format!(" at {}:{}", l.file(), l.line()))
                    .unwrap_or_default();
                let message = panic_message(info.payload());
                CAUGHT.with(|c| *c.borrow_mut() = Some(format!("{message}{at}")));
            } else {
                previous(info)
            }
        }));
    });
    let was = CATCHING.with(|c| c.replace(true));
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    CATCHING.with(|c| c.set(was));
    r.map_err(|payload| {
        CAUGHT
            .with(|c| c.borrow_mut().take())
            .unwrap_or_else(|| panic_message(&*payload))
    })
}

/// The text of a panic's payload (`panic!("…")` gives a `&str` or a `String`).
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    let m = payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("(no message)");
    truncate(m, MESSAGE_BYTES).into_owned()
}

/// A debugging and test hook of debug builds only: `CWSYNTH_TEST_PANIC=NAME` makes the
/// machine named `NAME` panic just before it is solved (`cwsynth batch` and `cwsynth solve`),
/// to show that one machine's panic fails that machine only (`tests/batch.rs`). Release
/// builds ignore the variable.
pub fn test_panic(name: &str) {
    if cfg!(debug_assertions) && std::env::var_os("CWSYNTH_TEST_PANIC").is_some_and(|n| n == name) {
        panic!("CWSYNTH_TEST_PANIC: a test panic in machine `{name}`");
    }
}

/// A fleet template: its parsed table (the fast way), its document (the slow way, for a
/// bad row's message), name, path, the CSV header, and the input hash of the template text
/// and the header (each row's is finished by [`Template::input_hash`]).
pub struct Template {
    path: PathBuf,
    csv: PathBuf,
    table: toml::Table,
    doc: toml_edit::DocumentMut,
    name: String,
    /// The dotted keys of the columns (the header without its units).
    header: Vec<String>,
    /// The unit of each column's bare numbers (`mechanism.speed [rpm]`), if its header
    /// gives one.
    units: Vec<Option<&'static Unit>>,
    hash: Hasher,
}

/// A column header: its dotted key and, if written `key [unit]`, its unit (an unknown unit
/// is an error).
fn column(h: &str) -> Result<(String, Option<&'static Unit>), String> {
    let h = h.trim();
    let Some((key, rest)) = h.split_once('[') else {
        return Ok((h.to_string(), None));
    };
    let Some(symbol) = rest.trim().strip_suffix(']') else {
        return Err(format!(
            "column `{h}`: a unit is written `key [unit]`, e.g. `mechanism.speed [rpm]`"
        ));
    };
    match crate::units::unit(symbol) {
        Some(u) => Ok((key.trim().to_string(), Some(u))),
        None => Err(format!(
            "column `{h}`: unknown unit `{}`; allowed: {}",
            symbol.trim(),
            crate::units::UNITS
                .iter()
                .map(|u| u.symbol)
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// The TOML value of a CSV cell: integer, float, boolean, else a string (quantities with
/// units stay strings, as in a problem file); a number in a column whose header has a unit
/// is that quantity (`1500` under `mechanism.speed [rpm]` is `"1500 rpm"`).
enum Cell<'a> {
    Int(i64),
    Float(f64),
    Bool(bool),
    Str(&'a str),
    Qty(&'a str, &'static str),
}

impl Cell<'_> {
    /// The value of a cell as written in the CSV, in a column of unit `unit`.
    fn of<'a>(cell: &'a str, unit: Option<&'static Unit>) -> Cell<'a> {
        let c = cell.trim();
        if let Some(u) = unit {
            if c.parse::<f64>().is_ok_and(f64::is_finite) {
                return Cell::Qty(c, u.symbol);
            }
        }
        if let Ok(i) = c.parse::<i64>() {
            return Cell::Int(i);
        }
        if let Ok(x) = c.parse::<f64>() {
            if x.is_finite() {
                return Cell::Float(x);
            }
        }
        match c {
            "true" => Cell::Bool(true),
            "false" => Cell::Bool(false),
            _ => Cell::Str(c),
        }
    }

    /// The cell as a value of `toml` or `toml_edit`.
    fn value<V>(self) -> V
    where
        V: From<i64> + From<f64> + From<bool> + for<'s> From<&'s str>,
    {
        match self {
            Cell::Int(i) => i.into(),
            Cell::Float(x) => x.into(),
            Cell::Bool(b) => b.into(),
            Cell::Str(s) => s.into(),
            Cell::Qty(x, unit) => format!("{x} {unit}").as_str().into(),
        }
    }
}

/// The parts of a dotted key (`mechanism.speed`), each trimmed and not empty.
fn key_parts(key: &str) -> Result<Vec<&str>, String> {
    let parts: Vec<&str> = key.split('.').map(str::trim).collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err("empty key part".into());
    }
    Ok(parts)
}

/// Sets the dotted `key` of `table` to `v`, creating tables as needed; `None` where a part
/// of the key is a value, not a table.
fn set_dotted_table(table: &mut toml::Table, key: &str, v: toml::Value) -> Option<()> {
    let parts = key_parts(key).ok()?;
    let (last, path) = parts.split_last()?;
    let mut t = table;
    for p in path {
        t = t
            .entry(*p)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            .as_table_mut()?;
    }
    t.insert(last.to_string(), v);
    Some(())
}

/// Sets the dotted `key` of `doc` to `v`, creating tables as needed.
fn set_dotted(
    doc: &mut toml_edit::DocumentMut,
    key: &str,
    v: toml_edit::Value,
) -> Result<(), String> {
    let parts = key_parts(key)?;
    let mut t: &mut dyn toml_edit::TableLike = doc.as_table_mut();
    for (k, p) in parts[..parts.len() - 1].iter().enumerate() {
        if t.get(p).is_none() {
            t.insert(p, toml_edit::Item::Table(toml_edit::Table::new()));
        }
        let item = t.get_mut(p).expect("just inserted");
        t = item.as_table_like_mut().ok_or_else(|| {
            format!(
                "`{}` is a value in the template, not a table",
                parts[..=k].join(".")
            )
        })?;
    }
    let last = parts[parts.len() - 1];
    match t.get_mut(last) {
        Some(item) if item.is_value() => {
            // Keep the template's comment and spacing around the value.
            let decor = item.as_value().map(|x| x.decor().clone());
            let mut nv = v;
            if let Some(d) = decor {
                *nv.decor_mut() = d;
            }
            *item = toml_edit::Item::Value(nv);
        }
        _ => {
            t.insert(last, toml_edit::Item::Value(v));
        }
    }
    Ok(())
}

impl Template {
    /// Reads the template and the CSV header.
    pub fn open(template: &Path, csv: &Path) -> anyhow::Result<Template> {
        let bytes = std::fs::read(template)
            .with_context(|| format!("{}: cannot read", template.display()))?;
        let text = crate::problem::text_of(&bytes, template)
            .map_err(|e| anyhow::anyhow!("template {e}"))?
            .to_string();
        // The template itself must be valid (without overrides).
        parse_str(&text, template).map_err(|e| anyhow::anyhow!("template {e}"))?;
        let doc: toml_edit::DocumentMut = text
            .parse()
            .with_context(|| format!("{}: not TOML", template.display()))?;
        let table: toml::Table =
            toml::from_str(&text).with_context(|| format!("{}: not TOML", template.display()))?;
        let name = doc
            .get("name")
            .and_then(|n| n.as_str())
            .unwrap_or("machine")
            .to_string();
        let mut rdr = csv_reader(csv)?;
        let columns: Vec<String> = rdr
            .headers()
            .with_context(|| format!("{}: cannot read the header", csv.display()))?
            .iter()
            .map(|h| h.trim().to_string())
            .collect();
        let (header, units) = columns
            .iter()
            .map(|h| column(h))
            .collect::<Result<(Vec<_>, Vec<_>), String>>()
            .map_err(|e| anyhow::anyhow!("{}:1: {e}", csv.display()))?;
        // A key set by two columns: which cell wins would be a guess.
        let mut seen: std::collections::HashMap<String, usize> = Default::default();
        for (k, key) in header.iter().enumerate() {
            let canonical = key_parts(key).map_or_else(|_| key.clone(), |p| p.join("."));
            if let Some(first) = seen.insert(canonical.clone(), k) {
                bail!(
                    "{}:1: columns {} (`{}`) and {} (`{}`) both set `{canonical}`; keep one",
                    csv.display(),
                    first + 1,
                    truncate(&columns[first], 200),
                    k + 1,
                    truncate(&columns[k], 200)
                );
            }
        }
        let mut hash = Hasher::new();
        hash.bytes(b"fleet row\0");
        hash.field(&text);
        hash.field(&columns.len().to_string());
        for h in &columns {
            hash.field(h);
        }
        Ok(Template {
            path: template.into(),
            csv: csv.into(),
            table,
            doc,
            name,
            header,
            units,
            hash,
        })
    }

    /// The input hash of a row named `name` with these cells: the template text, the CSV
    /// header, the name and the cells (as they are in the CSV), and the cwsynth build.
    pub fn input_hash(&self, name: &str, cells: &[String]) -> String {
        let mut h = self.hash.clone();
        h.field(name);
        h.field(&cells.len().to_string());
        for c in cells {
            h.field(c);
        }
        h.hex()
    }

    /// The (dotted key, cell value) pairs a row overrides: every column but `name`, without
    /// the empty cells (which keep the template's value).
    fn overrides<'a>(&'a self, cells: &'a [String]) -> impl Iterator<Item = (&'a str, Cell<'a>)> {
        self.header
            .iter()
            .zip(&self.units)
            .zip(cells)
            .filter(|((h, _), c)| *h != "name" && !c.trim().is_empty())
            .map(|((h, u), c)| (h.as_str(), Cell::of(c, *u)))
    }

    /// The scene of one CSV row (its source `fleet.csv:LINE`), the fast way: the row's
    /// cells set in a copy of the template's table, resolved by [`parse_table`]. `None` for
    /// a row that cannot be read this way; [`Template::scene`] then takes the slow way.
    pub fn fast_scene(&self, name: &str, line: u64, cells: &[String]) -> Option<Scene> {
        if cells.len() != self.header.len() {
            return None;
        }
        let mut table = self.table.clone();
        table.insert("name".into(), name.into());
        for (key, cell) in self.overrides(cells) {
            set_dotted_table(&mut table, key, cell.value())?;
        }
        parse_table(table, Path::new(&self.source(line))).ok()
    }

    /// The machine of one CSV row: (name, its scene) or `fleet.csv:LINE: reason`. A good row
    /// takes the fast way ([`Template::fast_scene`]); a bad one is read again as the
    /// template's edited text ([`Template::machine`], [`parse_str`]) for the message of
    /// `cwsynth solve`, with the CSV line and the template line.
    pub fn scene(&self, row: u64, line: u64, cells: &[String]) -> (String, Result<Scene, String>) {
        let name = self.row_name(row, cells);
        match self.fast_scene(&name, line, cells) {
            Some(scene) => (name, Ok(scene)),
            None => self.slow_scene(row, line, cells),
        }
    }

    /// The machine of one CSV row the slow way: the template's text edited
    /// ([`Template::machine`]) and read by [`parse_str`]; an error is phrased for the row.
    pub fn slow_scene(
        &self,
        row: u64,
        line: u64,
        cells: &[String],
    ) -> (String, Result<Scene, String>) {
        let (name, text) = self.machine(row, line, cells);
        let src = self.source(line);
        let scene =
            text.and_then(|t| parse_str(&t, Path::new(&src)).map_err(|e| row_error(self, line, e)));
        (name, scene)
    }

    /// Where CSV line `line` comes from, `fleet.csv:LINE`: a row's scene source and the
    /// start of its messages.
    pub fn source(&self, line: u64) -> String {
        format!("{}:{line}", self.csv.display())
    }

    /// The name of the machine of CSV row `row` (1-based): its `name` cell, else
    /// `<template name>-<row>`.
    pub fn row_name(&self, row: u64, cells: &[String]) -> String {
        self.header
            .iter()
            .position(|h| h == "name")
            .and_then(|i| cells.get(i))
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| format!("{}-{}", self.name, row))
    }

    /// The machine of one CSV row: (name, resolved problem text) or `csv:LINE: reason`.
    pub fn machine(
        &self,
        row: u64,
        line: u64,
        cells: &[String],
    ) -> (String, Result<String, String>) {
        let at = self.source(line);
        let name = self.row_name(row, cells);
        if cells.len() != self.header.len() {
            return (
                name,
                Err(format!(
                    "{at}: {} cells, the header has {}",
                    cells.len(),
                    self.header.len()
                )),
            );
        }
        let mut doc = self.doc.clone();
        if let Err(e) = set_dotted(&mut doc, "name", name.as_str().into()) {
            return (name, Err(format!("{at}: field `name`: {e}")));
        }
        for (h, c) in self.overrides(cells) {
            if let Err(e) = set_dotted(&mut doc, h, c.value()) {
                return (name, Err(format!("{at}: field `{h}`: {e}")));
            }
        }
        (name, Ok(doc.to_string()))
    }
}

fn csv_reader(csv: &Path) -> anyhow::Result<csv::Reader<FleetFile>> {
    let f = std::fs::File::open(csv).with_context(|| format!("{}: cannot read", csv.display()))?;
    Ok(csv::ReaderBuilder::new()
        .flexible(true)
        .comment(Some(b'#'))
        .from_reader(std::io::Read::chain(f, &b"\n"[..])))
}

/// A fleet CSV as read: the file, then one line break. The `csv` reader takes a `#` comment
/// on a last line without a line break for a record; with the break it is a comment like any
/// other, and no other line changes (a last line is the same line with its break).
type FleetFile = std::io::Chain<std::fs::File, &'static [u8]>;

/// What a worker gets: where the machine's text comes from.
enum Work {
    /// A problem file of the input (in this shard or not).
    Path(PathBuf),
    /// A problem file of this shard and its text (read once, in input order, when the job is
    /// made), or why it could not be read.
    File {
        path: PathBuf,
        text: Result<String, String>,
    },
    Row {
        tpl: Arc<Template>,
        row: u64,
        line: u64,
        cells: Vec<String>,
    },
    /// The CSV itself could not be read at this point.
    Broken { name: String, message: String },
}

impl Work {
    /// Reads a file's text (other work is returned as it is).
    fn read(self) -> Work {
        match self {
            Work::Path(path) => {
                let text = std::fs::read(&path)
                    .map_err(|e| format!("{}: cannot read: {e}", path.display()))
                    .and_then(|b| {
                        crate::problem::text_of(&b, &path)
                            .map(str::to_string)
                            .map_err(|e| e.to_string())
                    });
                Work::File { path, text }
            }
            w => w,
        }
    }

    /// The machine's name as far as it is known before solving (a file's `name` key, a
    /// row's name), which names its result files.
    fn name(&self) -> Option<String> {
        match self {
            Work::File { text, .. } => {
                let t: toml::Table = toml::from_str(text.as_ref().ok()?).ok()?;
                t.get("name")?.as_str().map(str::to_string)
            }
            Work::Row {
                tpl, row, cells, ..
            } => Some(tpl.row_name(*row, cells)),
            Work::Path(_) | Work::Broken { .. } => None,
        }
    }

    /// The machine's name and source for its row before it is read: a file's stem, a row's
    /// name (the row of a machine that panicked).
    fn label(&self) -> (String, String) {
        match self {
            Work::Path(path) | Work::File { path, .. } => (
                path.file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                path.display().to_string(),
            ),
            Work::Row {
                tpl,
                row,
                line,
                cells,
            } => (tpl.row_name(*row, cells), tpl.source(*line)),
            Work::Broken { name, .. } => (name.clone(), String::new()),
        }
    }

    fn source(&self) -> String {
        match self {
            Work::Path(path) | Work::File { path, .. } => path.display().to_string(),
            Work::Row { tpl, line, .. } => tpl.source(*line),
            Work::Broken { .. } => String::new(),
        }
    }
}

/// Names already taken in this run, keyed by a 64-bit hash (SipHash with fixed keys, so the
/// same in every run) instead of the name: 16 bytes per machine plus the table's overhead
/// (≈ 3 MB for 100 000), and the source only for files (few). Two different names colliding
/// (probability ~n²/2⁶⁵) would be reported as a duplicate, never silently overwritten. Each
/// shard checks its own machines only.
#[derive(Default)]
struct Names {
    index: std::collections::HashMap<u64, u64>,
    file: std::collections::HashMap<u64, String>,
}

impl Names {
    /// Claims `name` (compared without case) for machine `index` (from the file `file`, if
    /// any); a name already claimed gives the first claimant's index and file ("" for a fleet row).
    fn claim(&mut self, name: &str, index: u64, file: Option<String>) -> Option<(u64, String)> {
        use std::hash::{Hash, Hasher};
        // Without case: names equal but for case clash on case-insensitive file systems.
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for b in name.bytes() {
            b.to_ascii_lowercase().hash(&mut h);
        }
        let key = h.finish();
        match self.index.entry(key) {
            std::collections::hash_map::Entry::Occupied(e) => {
                Some((*e.get(), self.file.get(&key).cloned().unwrap_or_default()))
            }
            std::collections::hash_map::Entry::Vacant(v) => {
                v.insert(index);
                if let Some(f) = file {
                    self.file.insert(key, f);
                }
                None
            }
        }
    }
}

struct Job {
    index: u64,
    work: Work,
    /// The previous summary row of this index, if any (for `--summary-only` re-runs).
    old: Option<Row>,
}

/// Streams every machine of the inputs in order, as `(index, work)`.
struct Jobs {
    inputs: std::vec::IntoIter<Input>,
    fleet: Option<(
        Arc<Template>,
        csv::StringRecordsIntoIter<FleetFile>,
        u64,
        Lines,
    )>,
    next: u64,
    /// Error rows still to emit for the lines an unterminated quote swallowed.
    swallowed: std::collections::VecDeque<Work>,
    /// A fleet whose template or header is broken: each of its rows is an error row.
    dead: Option<DeadFleet>,
}

/// A fleet that cannot be read (broken template or header): its rows are still streamed,
/// each an error row with the reason, so rows in = rows out.
struct DeadFleet {
    recs: csv::StringRecordsIntoIter<FleetFile>,
    lines: Lines,
    csv: PathBuf,
    /// The name stem of its rows (the CSV's file stem): `<stem>-<row>`.
    stem: String,
    reason: String,
    row: u64,
}

impl Jobs {
    fn new(inputs: Vec<Input>) -> Jobs {
        Jobs {
            inputs: inputs.into_iter(),
            fleet: None,
            next: 0,
            swallowed: Default::default(),
            dead: None,
        }
    }
}

/// The real line numbers of a fleet CSV's records. The `csv` crate's own line count is off
/// with CRLF line endings, and a record's position is where its reading started, which is
/// before any comment or blank lines the reader skipped: so the line is counted here, from
/// the record's byte position, in a second sequential pass over the file (streamed with the
/// records: every byte is read once more, nothing is kept).
struct Lines {
    rdr: std::io::BufReader<std::fs::File>,
    /// Bytes consumed so far.
    pos: u64,
    /// The (1-based) line of byte `pos`.
    line: u64,
}

impl Lines {
    fn open(csv: &Path) -> anyhow::Result<Lines> {
        let f =
            std::fs::File::open(csv).with_context(|| format!("{}: cannot read", csv.display()))?;
        Ok(Lines {
            rdr: std::io::BufReader::new(f),
            pos: 0,
            line: 1,
        })
    }

    /// The line where the record whose reading started at byte `byte` begins: the line of
    /// that byte, past the rest of a line already ended (a CRLF's `\n`), blank lines and
    /// comment lines (`#`), as the CSV reader skips them. Bytes must not decrease from call
    /// to call.
    fn record_line(&mut self, byte: u64) -> u64 {
        use std::io::BufRead;
        while self.pos < byte {
            let Ok(buf) = self.rdr.fill_buf() else { break };
            if buf.is_empty() {
                break;
            }
            let n = buf.len().min((byte - self.pos) as usize);
            self.line += buf[..n].iter().filter(|&&b| b == b'\n').count() as u64;
            self.rdr.consume(n);
            self.pos += n as u64;
        }
        // Skip what the reader skipped: line ends, blank lines and comments.
        let mut comment = false;
        while let Some(&b) = self.rdr.fill_buf().ok().and_then(|buf| buf.first()) {
            match b {
                b'\n' => {
                    self.line += 1;
                    comment = false;
                }
                _ if comment => {}
                b'\r' => {}
                b'#' => comment = true,
                _ => break,
            }
            self.rdr.consume(1);
            self.pos += 1;
        }
        self.line
    }
}

/// Lines of the file a CSV record spans beyond its first: a line break can only be inside a
/// record through a quoted cell, which in a fleet is always an unterminated `"` (no cell of
/// a fleet holds a line break). Each such line is a machine the user wrote, so each is
/// reported (rows in = rows out); [`count_machines`] counts them the same way.
fn swallowed_lines(r: &csv::StringRecord) -> u64 {
    r.iter()
        // (An unterminated quote on the last line runs to the end of the file and takes its
        // final line break along: that one starts no line.)
        .map(|c| {
            c.trim_end_matches(['\n', '\r'])
                .bytes()
                .filter(|&b| b == b'\n')
                .count() as u64
        })
        .sum()
}

impl Iterator for Jobs {
    type Item = (u64, Work);
    fn next(&mut self) -> Option<(u64, Work)> {
        loop {
            if let Some(w) = self.swallowed.pop_front() {
                let i = self.next;
                self.next += 1;
                return Some((i, w));
            }
            if let Some(d) = &mut self.dead {
                match d.recs.next() {
                    Some(rec) => {
                        d.row += 1;
                        let line = rec
                            .ok()
                            .and_then(|r| r.position().map(|p| d.lines.record_line(p.byte())))
                            .unwrap_or(d.row + 1);
                        let i = self.next;
                        self.next += 1;
                        let message = format!(
                            "{}:{line}: this row was not read: {}",
                            d.csv.display(),
                            truncate(&d.reason, 500)
                        );
                        let name = format!("{}-{}", d.stem, d.row);
                        return Some((i, Work::Broken { name, message }));
                    }
                    None => {
                        let d = self.dead.take().expect("matched");
                        if d.row == 0 {
                            // No data rows: the reason is one row.
                            let i = self.next;
                            self.next += 1;
                            let w = Work::Broken {
                                name: d.stem,
                                message: d.reason,
                            };
                            return Some((i, w));
                        }
                    }
                }
            }
            if let Some((tpl, recs, row, lines)) = &mut self.fleet {
                match recs.next() {
                    Some(rec) => {
                        *row += 1;
                        let i = self.next;
                        self.next += 1;
                        let w = match rec {
                            Ok(r) => {
                                let line = r
                                    .position()
                                    .map(|p| lines.record_line(p.byte()))
                                    .unwrap_or(*row + 1);
                                match swallowed_lines(&r) {
                                    0 => Work::Row {
                                        tpl: tpl.clone(),
                                        row: *row,
                                        line,
                                        cells: r.iter().map(str::to_string).collect(),
                                    },
                                    extra => {
                                        let csv = tpl.csv.display();
                                        for k in 1..=extra {
                                            *row += 1;
                                            self.swallowed.push_back(Work::Broken {
                                                name: format!("{}-{}", tpl.name, row),
                                                message: format!(
                                                    "{csv}:{}: this line is inside the quoted cell opened on line {line} (an unterminated `\"`); it was not read",
                                                    line + k
                                                ),
                                            });
                                        }
                                        Work::Broken {
                                            name: format!("{}-{}", tpl.name, *row - extra),
                                            message: format!(
                                                "{csv}:{line}: a `\"` opens a quoted cell that is never closed on its line: it runs over lines {line}–{}, so those {} rows are lost; close the quote",
                                                line + extra,
                                                extra + 1
                                            ),
                                        }
                                    }
                                }
                            }
                            Err(e) => Work::Broken {
                                name: format!("{}-{}", tpl.name, row),
                                message: match e.position() {
                                    Some(p) => {
                                        let line = lines.record_line(p.byte());
                                        format!("{}: {e}", tpl.source(line))
                                    }
                                    None => format!("{}: {e}", tpl.csv.display()),
                                },
                            },
                        };
                        return Some((i, w));
                    }
                    None => self.fleet = None,
                }
            }
            let input = self.inputs.next()?;
            match input {
                Input::File(p) => {
                    let i = self.next;
                    self.next += 1;
                    return Some((i, Work::Path(p)));
                }
                Input::Fleet { template, csv } => {
                    let opened = Template::open(&template, &csv)
                        .and_then(|t| Ok((t, csv_reader(&csv)?, Lines::open(&csv)?)));
                    match opened {
                        Ok((t, rdr, lines)) => {
                            self.fleet = Some((Arc::new(t), rdr.into_records(), 0, lines));
                        }
                        Err(e) => {
                            let stem = csv
                                .file_stem()
                                .map(|s| s.to_string_lossy().into_owned())
                                .unwrap_or_default();
                            let reason = format!("{e:#}");
                            // Every data row is reported (rows in = rows out); a fleet that
                            // cannot be opened, or has no rows, is one error row.
                            let rows = csv_reader(&csv)
                                .ok()
                                .and_then(|r| Some((r.into_records(), Lines::open(&csv).ok()?)));
                            match rows {
                                Some((recs, lines)) => {
                                    self.dead = Some(DeadFleet {
                                        recs,
                                        lines,
                                        csv,
                                        stem,
                                        reason,
                                        row: 0,
                                    });
                                }
                                None => {
                                    let i = self.next;
                                    self.next += 1;
                                    let w = Work::Broken {
                                        name: stem,
                                        message: reason,
                                    };
                                    return Some((i, w));
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Counts the machines of the inputs (a streaming pass over each CSV) for the progress bar.
fn count_machines(inputs: &[Input]) -> u64 {
    inputs
        .iter()
        .map(|i| match i {
            Input::File(_) => 1,
            Input::Fleet { csv, .. } => csv_reader(csv)
                .map(|r| {
                    r.into_records()
                        .map(|rec| 1 + rec.map_or(0, |r| swallowed_lines(&r)))
                        .sum::<u64>()
                })
                .unwrap_or(1),
        })
        .sum()
}

/// Re-formats a problem error of a fleet row as `fleet.csv:LINE: field …` (with the
/// template line where the key is).
fn row_error(tpl: &Template, line: u64, e: ProblemError) -> String {
    match e {
        ProblemError::Invalid {
            line: tl,
            field,
            message,
            ..
        } => {
            // A field set by a column: name the column (1-based, as written in the header).
            let col = field
                .as_ref()
                .and_then(|f| tpl.header.iter().position(|h| h == f))
                .map(|k| format!(" (column {})", k + 1))
                .unwrap_or_default();
            format!(
                "{}: {}{message}{}",
                tpl.source(line),
                field
                    .map(|f| format!("field `{f}`{col}: "))
                    .unwrap_or_default(),
                tl.map(|l| format!(" (template {}:{l})", tpl.path.display()))
                    .unwrap_or_default()
            )
        }
        e => format!("{}: {e}", tpl.source(line)),
    }
}

/// A machine's input, before it is resolved (only if the machine is not skipped): a file's
/// text, or a fleet row (whose error is phrased for the row).
enum Ready {
    Text(String, PathBuf),
    Row {
        tpl: Arc<Template>,
        row: u64,
        line: u64,
        cells: Vec<String>,
    },
}

/// Solves (or skips) one machine; writes its files unless `summary_only`.
fn process(job: Job, opts: &Options) -> (Row, bool) {
    let index = job.index;
    let (name, source, input) = match job.work.read() {
        Work::Path(_) => unreachable!("`read` turns a path into a file"),
        Work::File { path, text } => {
            let name = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let source = path.display().to_string();
            let input = text.map(|t| (content_hash(&t), Ready::Text(t, path)));
            (name, source, input)
        }
        Work::Row {
            tpl,
            row,
            line,
            cells,
        } => {
            let (name, source) = (tpl.row_name(row, &cells), tpl.source(line));
            let hash = tpl.input_hash(&name, &cells);
            let ready = Ready::Row {
                tpl,
                row,
                line,
                cells,
            };
            (name, source, Ok((hash, ready)))
        }
        Work::Broken { name, message } => {
            return (error_row(index, &name, "", "", message), false);
        }
    };
    let (hash, ready) = match input {
        Ok(x) => x,
        Err(m) => return (error_row(index, &name, &source, "", m), false),
    };
    if opts.summary_only {
        if let Some(old) = job.old {
            if old.input_hash == hash && old.status != "error" {
                return (old, true);
            }
        }
    }
    // A bad file's error row keeps its hash; a bad row's has none (as when it was read).
    let scene = match ready {
        Ready::Text(text, path) => parse_str(&text, &path).map_err(|e| (e.to_string(), &*hash)),
        Ready::Row {
            tpl,
            row,
            line,
            cells,
        } => tpl.scene(row, line, &cells).1.map_err(|m| (m, "")),
    };
    let scene = match scene {
        Ok(s) => s,
        Err((m, h)) => return (error_row(index, &name, &source, h, m), false),
    };
    if !opts.summary_only {
        let jp = opts.out.join(format!("{}.json", scene.name));
        if let Some(v) = complete_result(&jp, &hash, &opts.out) {
            return (row_from_json(index, &source, &hash, &v), true);
        }
    }
    test_panic(&scene.name);
    let mut r = solve_scene(&scene);
    if !opts.summary_only {
        // What only the files carry (e.g. the crane's landscape grid).
        r.complete();
    }
    let mut batch = serde_json::json!({
        "input_hash": hash,
        "plots": r.plots.iter().map(|p| p.suffix.clone()).collect::<Vec<_>>(),
    });
    if opts.summary_only {
        // Without result files only the row is needed: its fields, not the whole JSON.
        r.extra.insert("batch".into(), batch);
        return (
            row_from_json(index, &source, &hash, &r.summary_json()),
            false,
        );
    }
    // The report files first, each listed in the JSON with its size and hash; the JSON
    // last: a machine is done when its JSON and every file it lists are whole.
    let files = report_files(&r, &opts.out);
    let mut written = Ok(());
    let mut listed = serde_json::Map::new();
    for (path, bytes) in &files {
        let file = path.file_name().map(|n| n.to_string_lossy().into_owned());
        listed.insert(
            file.unwrap_or_default(),
            serde_json::json!({"bytes": bytes.len(), "hash": file_hash(bytes)}),
        );
        if written.is_ok() {
            written = write_replace(path, bytes);
        }
    }
    batch["files"] = listed.into();
    r.extra.insert("batch".into(), batch);
    let v = r.to_json();
    let mut row = row_from_json(index, &source, &hash, &v);
    let json = serde_json::to_string_pretty(&v).expect("plain data") + "\n";
    if let Err(e) = written.and_then(|()| write_replace(&json_path(&r, &opts.out), json.as_bytes()))
    {
        row.status = "error".into();
        row.input_hash.clear();
        row.message = format!("writing the results: {e}");
    }
    (row, false)
}

/// A content hash of a result file, 128 bits in hex, to tell a whole file from a torn one at
/// resume: two multiply-rotate streams over 8-byte words (fast, not cryptographic), the
/// length folded in.
pub fn file_hash(bytes: &[u8]) -> String {
    let (mut a, mut b) = (0x9e37_79b9_7f4a_7c15u64, 0xc2b2_ae3d_27d4_eb4fu64);
    let mut words = bytes.chunks_exact(8);
    for w in words.by_ref() {
        let x = u64::from_le_bytes(w.try_into().expect("8 bytes"));
        a = (a ^ x).wrapping_mul(0xff51_afd7_ed55_8ccd).rotate_left(29);
        b = (b ^ x.rotate_left(32))
            .wrapping_mul(0xc4ce_b9fe_1a85_ec53)
            .rotate_left(31);
    }
    let mut tail = [0u8; 8];
    tail[..words.remainder().len()].copy_from_slice(words.remainder());
    let x = u64::from_le_bytes(tail) ^ ((bytes.len() as u64) << 3);
    a = (a ^ x).wrapping_mul(0xff51_afd7_ed55_8ccd);
    b = (b ^ x.rotate_left(32) ^ a).wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    a ^= a >> 33;
    b ^= b >> 29;
    format!("{a:016x}{b:016x}")
}

/// The result JSON at `json` if the machine is done: the JSON parses, its `batch.input_hash`
/// is `hash`, and every file it lists in `batch.files` (name: size and [`file_hash`]) is in
/// `dir` with that size and hash. Anything else (a file missing, torn by a crash, edited, a
/// JSON of an older cwsynth without the list) means the machine is solved again.
fn complete_result(json: &Path, hash: &str, dir: &Path) -> Option<serde_json::Value> {
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(json).ok()?).ok()?;
    let batch = v.get("batch")?;
    if batch.get("input_hash")?.as_str()? != hash {
        return None;
    }
    for (name, f) in batch.get("files")?.as_object()? {
        // Only plain file names of this directory (the JSON is input like any other).
        if Path::new(name).file_name() != Some(std::ffi::OsStr::new(name)) {
            return None;
        }
        let bytes = std::fs::read(dir.join(name)).ok()?;
        if f.get("bytes")?.as_u64()? != bytes.len() as u64
            || f.get("hash")?.as_str()? != file_hash(&bytes)
        {
            return None;
        }
    }
    Some(v)
}

/// Reads a summary CSV in index order: a resumed run's checkpoint (merge-join with the
/// current run) or a shard given to `merge`. A file written by someone else is input like
/// any other: the header must be cwsynth's and every row must parse, validate
/// ([`Row::validate`]) and come in increasing index order. Reading stops at the first row
/// that does not, and [`OldRows::stopped`] says where and why: a resumed run re-solves
/// from there (as after a truncated tail), `merge` refuses the shard.
struct OldRows {
    path: PathBuf,
    rdr: Option<csv::StringRecordsIntoIter<std::fs::File>>,
    header: csv::StringRecord,
    peek: Option<Row>,
    last: Option<u64>,
    /// `FILE:LINE: what is wrong`, when reading stopped before the end of the file.
    stopped: Option<String>,
}

impl OldRows {
    fn open(path: &Path) -> OldRows {
        let mut o = OldRows {
            path: path.to_path_buf(),
            rdr: None,
            header: csv::StringRecord::new(),
            peek: None,
            last: None,
            stopped: None,
        };
        match csv::Reader::from_path(path) {
            Ok(mut r) => match r.headers() {
                Ok(h) if h.iter().eq(HEADER.iter().copied()) => {
                    o.header = h.clone();
                    o.rdr = Some(r.into_records());
                }
                _ => {
                    o.stopped = Some(format!(
                        "{}:1: the header is not a cwsynth summary header ({})",
                        path.display(),
                        HEADER.join(",")
                    ))
                }
            },
            Err(e) if e.is_io_error() && !path.exists() => {}
            Err(e) => o.stopped = Some(format!("{}: {e}", path.display())),
        }
        o.advance();
        o
    }
    fn advance(&mut self) {
        self.peek = None;
        let Some(rec) = self.rdr.as_mut().and_then(|r| r.next()) else {
            return;
        };
        let row = rec.map_err(|e| e.to_string()).and_then(|rec| {
            let line = rec.position().map_or(0, |p| p.line());
            let row = rec
                .deserialize::<Row>(Some(&self.header))
                .map_err(|e| format!("{line}: {e}"))?
                .csv_unescaped();
            row.validate().map_err(|e| format!("{line}: {e}"))?;
            if self.last.is_some_and(|l| row.index <= l) {
                return Err(format!("{line}: index {} is out of order", row.index));
            }
            Ok(row)
        });
        match row {
            Ok(r) => {
                self.last = Some(r.index);
                self.peek = Some(r);
            }
            Err(e) => {
                self.stopped = Some(format!("{}:{e}", self.path.display()));
                self.rdr = None;
            }
        }
    }
    /// The old row with this index, if any.
    fn take(&mut self, index: u64) -> Option<Row> {
        while let Some(p) = &self.peek {
            if p.index < index {
                self.advance();
            } else if p.index == index {
                let r = self.peek.take();
                self.advance();
                return r;
            } else {
                return None;
            }
        }
        None
    }
}

/// Progress output: a bar on a terminal, plain lines otherwise, nothing with `--quiet`.
enum Progress {
    Bar(indicatif::ProgressBar),
    Lines {
        total: u64,
        last: Instant,
        t0: Instant,
    },
    Quiet,
}

impl Progress {
    fn new(total: u64, quiet: bool) -> Progress {
        if quiet {
            Progress::Quiet
        } else if std::io::stderr().is_terminal() {
            let pb = indicatif::ProgressBar::new(total);
            pb.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} machines  {per_sec}  ETA {eta}  {msg}",
                )
                .expect("valid template"),
            );
            Progress::Bar(pb)
        } else {
            Progress::Lines {
                total,
                last: Instant::now(),
                t0: Instant::now(),
            }
        }
    }
    fn error(&self, m: &str) {
        match self {
            Progress::Bar(pb) => pb.println(format!("error {m}")),
            Progress::Lines { .. } => eprintln!("error {m}"),
            Progress::Quiet => {}
        }
    }
    fn update(&mut self, done: u64, c: &Counts, force: bool) {
        match self {
            Progress::Bar(pb) => {
                pb.set_position(done);
                pb.set_message(format!("{} failed, {} skipped", c.failed, c.skipped));
            }
            Progress::Lines { total, last, t0 } => {
                if force || last.elapsed().as_secs_f64() >= 2.0 {
                    *last = Instant::now();
                    let t = t0.elapsed().as_secs_f64();
                    eprintln!(
                        "batch: {done}/{total} machines, {} failed, {} skipped, {:.0}/s, {:.1} s",
                        c.failed,
                        c.skipped,
                        done as f64 / t.max(1e-9),
                        t
                    );
                }
            }
            Progress::Quiet => {}
        }
    }
    fn finish(&self) {
        if let Progress::Bar(pb) = self {
            pb.finish();
        }
    }
}

/// The summary file name of a run: `summary.csv`, or `summary-shard-i-of-n.csv`.
pub fn summary_name(shard: Option<(u64, u64)>) -> String {
    match shard {
        Some((i, n)) => format!("summary-shard-{i}-of-{n}.csv"),
        None => "summary.csv".into(),
    }
}

/// Locks `<out>/.<summary>.lock` for this process: one writer per summary. A second batch
/// (or merge) on the same --out and shard does not wait, it stops with a clear message. The
/// OS releases the lock when the process ends, even by kill -9, so a crash never leaves a
/// stale lock. The lock is held while the returned file lives.
fn lock_out(out: &Path, summary: &str) -> anyhow::Result<std::fs::File> {
    let lock_path = out.join(format!(".{summary}.lock"));
    let lock = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&lock_path)
        .with_context(|| format!("cannot create {}", lock_path.display()))?;
    match lock.try_lock() {
        Ok(()) => Ok(lock),
        Err(std::fs::TryLockError::WouldBlock) => bail!(
            "{} is in use by another cwsynth batch or merge (lock {}); wait for it to finish or choose another --out",
            out.display(),
            lock_path.display()
        ),
        Err(std::fs::TryLockError::Error(e)) => {
            Err(e).with_context(|| format!("cannot lock {}", lock_path.display()))
        }
    }
}

/// Runs a batch; writes the summary (and, unsharded, `summary.md` and `index.html`).
pub fn run(inputs: Vec<Input>, opts: &Options) -> anyhow::Result<Counts> {
    std::fs::create_dir_all(&opts.out)
        .with_context(|| format!("cannot create {}", opts.out.display()))?;
    let threads = opts
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
        .context("cannot start the worker threads")?;
    let (si, sn) = opts.shard.unwrap_or((0, 1));
    let _lock = lock_out(&opts.out, &summary_name(opts.shard))?;
    remove_stale_tmp(&opts.out);
    let all = count_machines(&inputs);
    let mine = all / sn + u64::from(all % sn > si);

    let final_path = opts.out.join(summary_name(opts.shard));
    let partial = opts
        .out
        .join(format!("{}.partial", summary_name(opts.shard)));
    let resume = opts
        .out
        .join(format!("{}.resume", summary_name(opts.shard)));
    // The checkpoint never goes backwards: after a second interruption the earlier
    // checkpoint may hold more rows than the newer partial one, and the larger is kept.
    if partial.exists() {
        let rows =
            |p: &Path| std::fs::read(p).map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count());
        if resume.exists() && rows(&resume) > rows(&partial) {
            std::fs::remove_file(&partial).context("cannot remove the smaller checkpoint")?;
        } else {
            std::fs::rename(&partial, &resume).context("cannot move the interrupted summary")?;
        }
    }
    let mut old_resume = OldRows::open(&resume);
    let mut old_final = OldRows::open(&final_path);

    let file = std::fs::File::create(&partial)
        .with_context(|| format!("cannot write {}", partial.display()))?;
    let writing = || format!("writing {}", partial.display());
    let mut w = csv::Writer::from_writer(std::io::BufWriter::new(file));
    let mut counts = Counts::default();
    let mut progress = Progress::new(mine, opts.quiet);
    let done = AtomicU64::new(0);

    let mut jobs = Jobs::new(inputs).filter(|(i, _)| i % sn == si);
    // Two machines with one name would write the same result files: the first (in input
    // order) keeps the name, every later one is reported and not solved. Decided here, in
    // input order before the parallel solve, so the outcome does not depend on threads.
    let mut names = Names::default();
    loop {
        let chunk: Vec<Job> = jobs
            .by_ref()
            .take(CHUNK)
            .map(|(index, work)| {
                let old = old_resume.take(index).or_else(|| old_final.take(index));
                let work = work.read();
                let work = match work.name() {
                    Some(name) => {
                        let file = match &work {
                            Work::File { .. } => Some(work.source()),
                            _ => None,
                        };
                        match names.claim(&name, index, file) {
                            Some((first, first_src)) => Work::Broken {
                                message: format!(
                                    "{}: duplicate name `{name}`: machine {first}{} already has it, and both would write `{name}.json`; give this machine another name",
                                    work.source(),
                                    if first_src.is_empty() {
                                        String::new()
                                    } else {
                                        format!(" ({first_src})")
                                    }
                                ),
                                name,
                            },
                            None => work,
                        }
                    }
                    None => work,
                };
                Job { index, work, old }
            })
            .collect();
        if chunk.is_empty() {
            break;
        }
        let rows: Vec<(Row, bool)> = pool.install(|| {
            chunk
                .into_par_iter()
                .map(|j| {
                    // Whatever one machine does, the others finish (a panic is its row).
                    let (index, (name, source)) = (j.index, j.work.label());
                    let r = isolate(|| process(j, opts))
                        .unwrap_or_else(|m| (panic_row(index, &name, &source, &m), false));
                    done.fetch_add(1, Ordering::Relaxed);
                    r
                })
                .collect()
        });
        for (row, skipped) in rows {
            counts.total += 1;
            counts.skipped += u64::from(skipped);
            if matches!(row.status.as_str(), "error" | "failed" | "infeasible") {
                counts.failed += 1;
                progress.error(&if row.message.is_empty() {
                    format!("{}: {}", row.name, row.status)
                } else {
                    format!("{}: {}: {}", row.name, row.status, row.message)
                });
            } else {
                counts.ok += 1;
            }
            w.serialize(row.csv_escaped()).with_context(writing)?;
        }
        w.flush().with_context(writing)?;
        progress.update(done.load(Ordering::Relaxed), &counts, false);
    }
    if counts.total == 0 {
        // An empty run still gets a header line.
        w.write_record(HEADER).with_context(writing)?;
    }
    progress.update(done.load(Ordering::Relaxed), &counts, true);
    progress.finish();
    if !opts.summary_only {
        // The per-machine files were written without a sync each: made durable here at once,
        // before the summary that lists them is committed.
        sync_filesystem(&opts.out)?;
    }
    commit(w, &partial, &final_path)?;
    let _ = std::fs::remove_file(&resume);
    if opts.shard.is_none() {
        write_reports(&opts.out)?;
    }
    Ok(counts)
}

/// Commits a summary: flushes and syncs `partial`, renames it to `summary`, and syncs the
/// directory, so the summary is durable once this returns (the run's one commit point).
fn commit(
    w: csv::Writer<std::io::BufWriter<std::fs::File>>,
    partial: &Path,
    summary: &Path,
) -> anyhow::Result<()> {
    let writing = || format!("writing {}", partial.display());
    let file = w
        .into_inner()
        .map_err(|e| anyhow::anyhow!("{}", e.error()))
        .with_context(writing)?
        .into_inner()
        .map_err(|e| anyhow::anyhow!("{}", e.error()))
        .with_context(writing)?;
    file.sync_all().with_context(writing)?;
    std::fs::rename(partial, summary).with_context(|| {
        format!(
            "cannot rename {} to {}",
            partial.display(),
            summary.display()
        )
    })?;
    sync_dir(summary.parent().unwrap_or(Path::new(".")))
}

/// Syncs a directory (its entries: a rename in it becomes durable). Unix only; elsewhere a
/// no-op.
fn sync_dir(dir: &Path) -> anyhow::Result<()> {
    #[cfg(unix)]
    std::fs::File::open(dir)
        .and_then(|d| d.sync_all())
        .with_context(|| format!("cannot sync {}", dir.display()))?;
    let _ = dir;
    Ok(())
}

/// Makes every file written to the file system of `dir` durable at once (Linux `syncfs`,
/// one call instead of one sync per file; `sync` on other Unix systems; elsewhere each file
/// was left to the operating system and a crash is caught at resume by [`complete_result`]).
fn sync_filesystem(dir: &Path) -> anyhow::Result<()> {
    #[cfg(target_os = "linux")]
    {
        use std::os::fd::AsRawFd;
        let d =
            std::fs::File::open(dir).with_context(|| format!("cannot open {}", dir.display()))?;
        // SAFETY: `syncfs` reads only the descriptor, which `d` keeps open.
        if unsafe { libc::syncfs(d.as_raw_fd()) } != 0 {
            return Err(std::io::Error::last_os_error())
                .with_context(|| format!("cannot sync the files in {}", dir.display()));
        }
    }
    #[cfg(all(unix, not(target_os = "linux")))]
    // SAFETY: `sync` takes no arguments and cannot fail.
    unsafe {
        libc::sync()
    };
    let _ = dir;
    Ok(())
}

/// Removes the temporary files (`.NAME.PID.tmp`) a killed run left in `dir`: those whose
/// process is gone (Unix: `kill(PID, 0)` fails), so a live run sharing the directory (another
/// shard) keeps its own. Elsewhere every leftover of another process id is removed.
fn remove_stale_tmp(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(pid) = name
            .to_str()
            .filter(|n| n.starts_with('.'))
            .and_then(|n| n.strip_suffix(".tmp"))
            .and_then(|n| n.rsplit_once('.'))
            .and_then(|(_, pid)| pid.parse::<u32>().ok())
        else {
            continue;
        };
        if !process_alive(pid) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Whether process `pid` runs (this one always does).
fn process_alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    #[cfg(unix)]
    {
        let Ok(p) = libc::pid_t::try_from(pid) else {
            return false;
        };
        // SAFETY: signal 0 only checks that the process exists; nothing is sent.
        let r = unsafe { libc::kill(p, 0) };
        r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
    }
    #[cfg(not(unix))]
    false
}

/// The summary columns, in order.
pub const HEADER: [&str; 16] = [
    "index",
    "name",
    "family",
    "status",
    "objective",
    "value",
    "error",
    "baseline",
    "baseline_value",
    "improvement_pct",
    "design",
    "objectives",
    "time_s",
    "input_hash",
    "source",
    "message",
];

/// Joins the shard summaries found in `dirs` (`summary-shard-i-of-n.csv`) into
/// `out/summary.csv` (in index order, a streaming k-way merge) and writes the reports.
pub fn merge(dirs: &[PathBuf], out: &Path) -> anyhow::Result<Counts> {
    let mut files = Vec::new();
    let mut ns = std::collections::BTreeSet::new();
    let mut seen = std::collections::BTreeSet::new();
    for d in dirs {
        for e in std::fs::read_dir(d).with_context(|| format!("cannot list {}", d.display()))? {
            let p = e?.path();
            let n = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if let Some(rest) = n
                .strip_prefix("summary-shard-")
                .and_then(|r| r.strip_suffix(".csv"))
            {
                if let Some((i, n)) = rest.split_once("-of-") {
                    if let (Ok(i), Ok(n)) = (i.parse::<u64>(), n.parse::<u64>()) {
                        ns.insert(n);
                        seen.insert(i);
                        files.push(p);
                    }
                }
            }
        }
    }
    files.sort();
    if files.is_empty() {
        bail!("no shard summaries (summary-shard-i-of-n.csv) found");
    }
    if ns.len() != 1 {
        bail!("shard summaries of different splits: n = {ns:?}");
    }
    let n = *ns.iter().next().unwrap();
    let missing: Vec<u64> = (0..n).filter(|i| !seen.contains(i)).collect();
    if !missing.is_empty() {
        bail!("shards {missing:?} of {n} are missing");
    }
    std::fs::create_dir_all(out)?;
    let _lock = lock_out(out, "summary.csv")?;
    let mut readers: Vec<OldRows> = files.iter().map(|f| OldRows::open(f)).collect();
    let tmp = out.join("summary.csv.partial");
    let mut w = csv::Writer::from_writer(std::io::BufWriter::new(
        std::fs::File::create(&tmp).with_context(|| format!("cannot write {}", tmp.display()))?,
    ));
    let writing = || format!("writing {}", tmp.display());
    let mut counts = Counts::default();
    loop {
        let k = readers
            .iter()
            .enumerate()
            .filter_map(|(k, r)| r.peek.as_ref().map(|p| (p.index, k)))
            .min();
        let Some((_, k)) = k else { break };
        let row = readers[k].peek.take().expect("peeked");
        readers[k].advance();
        counts.total += 1;
        if matches!(row.status.as_str(), "error" | "failed" | "infeasible") {
            counts.failed += 1;
        } else {
            counts.ok += 1;
        }
        w.serialize(row.csv_escaped()).with_context(writing)?;
    }
    if counts.total == 0 {
        w.write_record(HEADER).with_context(writing)?;
    }
    // Shard summaries are input: a row that did not parse, validate or keep the index
    // order stopped its reader, and the merge is refused.
    if let Some(e) = readers.iter().find_map(|r| r.stopped.clone()) {
        drop(w);
        let _ = std::fs::remove_file(&tmp);
        bail!(e);
    }
    commit(w, &tmp, &out.join("summary.csv"))?;
    write_reports(out)?;
    Ok(counts)
}

fn opt(v: Option<f64>) -> String {
    v.map(fmt_num).unwrap_or_else(|| "–".into())
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Per-family aggregate of a summary.
#[derive(Default)]
struct Agg {
    n: u64,
    by_status: BTreeMap<String, u64>,
    imp_sum: f64,
    imp_n: u64,
    imp_min: f64,
    imp_max: f64,
}

/// Writes `summary.md` and `index.html` from `DIR/summary.csv` (streaming; tables capped at
/// [`REPORT_ROWS`] rows, plots inlined for the first [`REPORT_PLOTS`] machines that have
/// them).
pub fn write_reports(dir: &Path) -> anyhow::Result<()> {
    let path = dir.join("summary.csv");
    let mut rdr =
        csv::Reader::from_path(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut shown: Vec<Row> = Vec::new();
    let mut failures: Vec<Row> = Vec::new();
    let mut n_fail = 0u64;
    let mut families: BTreeMap<String, Agg> = BTreeMap::new();
    let mut total = 0u64;
    let mut imp_hist = [0u64; 20];
    // Only the first rows and the first failures are shown whole; the rest only count, so
    // they are not deserialised (100 000 rows take a fraction of a second).
    let headers = rdr.headers()?.clone();
    let col = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .with_context(|| format!("{}: no column `{name}`", path.display()))
    };
    let (c_family, c_status, c_imp) = (col("family")?, col("status")?, col("improvement_pct")?);
    let mut rec = csv::StringRecord::new();
    while rdr.read_record(&mut rec)? {
        total += 1;
        let family = match &rec[c_family] {
            "" => "(unread)",
            f => f,
        };
        let status = &rec[c_status];
        let bad = matches!(status, "error" | "failed" | "infeasible");
        let whole = || -> anyhow::Result<Row> {
            Ok(rec.deserialize::<Row>(Some(&headers))?.csv_unescaped())
        };
        if bad {
            n_fail += 1;
            if failures.len() < REPORT_ROWS {
                failures.push(whole()?);
            }
        }
        if shown.len() < REPORT_ROWS {
            shown.push(whole()?);
        }
        if !families.contains_key(family) {
            families.insert(family.to_string(), Agg::default());
        }
        let a = families.get_mut(family).expect("inserted");
        a.n += 1;
        match a.by_status.get_mut(status) {
            Some(k) => *k += 1,
            None => {
                a.by_status.insert(status.to_string(), 1);
            }
        }
        let imp = match &rec[c_imp] {
            "" => None,
            t => Some(t.parse::<f64>().with_context(|| {
                format!("{}: improvement_pct `{t}` is not a number", path.display())
            })?),
        };
        if let Some(i) = imp {
            if a.imp_n == 0 {
                a.imp_min = i;
                a.imp_max = i;
            }
            a.imp_sum += i;
            a.imp_n += 1;
            a.imp_min = a.imp_min.min(i);
            a.imp_max = a.imp_max.max(i);
            imp_hist[(i.floor().clamp(0.0, 19.0)) as usize] += 1;
        }
    }

    // Markdown.
    let mut md = String::new();
    md += &format!(
        "# Batch summary\n\n{total} machines, {n_fail} failed. Every row is in `summary.csv`"
    );
    md += if total as usize > REPORT_ROWS {
        " (this page shows the first rows only).\n\n"
    } else {
        ".\n\n"
    };
    md += "| family | machines | by status | improvement over best baseline (mean, min–max) |\n|---|---|---|---|\n";
    for (f, a) in &families {
        md += &format!(
            "| {f} | {} | {} | {} |\n",
            a.n,
            a.by_status
                .iter()
                .map(|(s, n)| format!("{s} {n}"))
                .collect::<Vec<_>>()
                .join(", "),
            if a.imp_n > 0 {
                format!(
                    "{:.2} % ({:.2}–{:.2})",
                    a.imp_sum / a.imp_n as f64,
                    a.imp_min,
                    a.imp_max
                )
            } else {
                "–".into()
            }
        );
    }
    md += "\n## Machines\n\n| # | name | family | status | objective | value | ± error | best baseline | baseline value | improvement % | time (ms) |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in &shown {
        md += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |\n",
            r.index,
            md_escape(&r.name),
            md_escape(&r.family),
            md_escape(&r.status),
            md_escape(&r.objective),
            opt(r.value),
            r.error.map(|e| format!("{e:.1e}")).unwrap_or("–".into()),
            if r.baseline.is_empty() {
                "–".to_string()
            } else {
                md_escape(&r.baseline)
            },
            opt(r.baseline_value),
            r.improvement_pct
                .map(|i| format!("{i:.2}"))
                .unwrap_or("–".into()),
            r.time_s * 1e3
        );
    }
    if n_fail > 0 {
        md += &format!("\n## Failures ({n_fail})\n\n");
        for r in &failures {
            md += &format!(
                "- {} ({}): {}\n",
                md_escape(&r.name),
                md_escape(&r.status),
                md_escape(&truncate(&r.message, 2000))
            );
        }
        if n_fail as usize > failures.len() {
            md += &format!(
                "- … {} more: `grep -E ',(error|failed|infeasible),' summary.csv`\n",
                n_fail as usize - failures.len()
            );
        }
    }
    write_atomic(&dir.join("summary.md"), md.as_bytes())?;

    // HTML.
    let mut h = String::new();
    h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>cwsynth batch</title>\n<style>\n";
    h += "body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;margin:24px;color:#222;max-width:1350px}\n";
    h += "h1{font-size:24px}h2{font-size:19px;margin-top:32px;border-bottom:1px solid #ccc}h3{font-size:16px;margin:20px 0 6px}\n";
    h += "table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #ddd;padding:3px 7px;text-align:right}\n";
    h += "th{background:#f2f2f2;position:sticky;top:0}td.l,th.l{text-align:left}tr:nth-child(even){background:#fafafa}\n";
    h += ".optimal{color:#1a7f37}.best_found{color:#1a7f37;font-style:italic}.analysed{color:#0550ae}.inaccurate,.degenerate{color:#9a6700}.infeasible,.failed,.error{color:#cf222e;font-weight:600}\n";
    h += ".plots svg{max-width:100%;height:auto;border:1px solid #eee;margin:4px 0}.cap{font-size:12px;color:#555}\n";
    h += ".scroll{max-height:640px;overflow:auto;border:1px solid #ddd}\n</style></head><body>\n";
    h += &format!(
        "<h1>cwsynth batch</h1>\n<p>{total} machines, <b>{n_fail}</b> failed. Every row is in <a href=\"summary.csv\">summary.csv</a>{}.</p>\n",
        if total as usize > REPORT_ROWS {
            format!("; the table shows the first {REPORT_ROWS}")
        } else {
            String::new()
        }
    );
    h += "<table><tr><th class=l>family</th><th>machines</th><th class=l>by status</th><th>mean improvement %</th><th>min–max %</th></tr>\n";
    for (f, a) in &families {
        h += &format!(
            "<tr><td class=l>{}</td><td>{}</td><td class=l>{}</td><td>{}</td><td>{}</td></tr>\n",
            esc(f),
            a.n,
            a.by_status
                .iter()
                .map(|(s, n)| format!("<span class=\"{}\">{}</span> {n}", esc(s), esc(s)))
                .collect::<Vec<_>>()
                .join(", "),
            if a.imp_n > 0 {
                format!("{:.2}", a.imp_sum / a.imp_n as f64)
            } else {
                "–".into()
            },
            if a.imp_n > 0 {
                format!("{:.2}–{:.2}", a.imp_min, a.imp_max)
            } else {
                "–".into()
            }
        );
    }
    h += "</table>\n";
    if imp_hist.iter().any(|&c| c > 0) {
        h += "<h2>Improvement over the best classical baseline</h2>\n";
        h += &histogram_svg(&imp_hist);
    }
    h += "<h2>Machines</h2>\n<div class=scroll><table><tr><th>#</th><th class=l>name</th><th class=l>family</th><th class=l>status</th><th class=l>objective</th><th>value</th><th>± error</th><th class=l>best baseline</th><th>baseline</th><th>improvement %</th><th class=l>design</th><th>time ms</th></tr>\n";
    for r in &shown {
        h += &format!(
            "<tr><td>{}</td><td class=l><a href=\"#m-{}\">{}</a></td><td class=l>{}</td><td class=\"l {}\">{}</td><td class=l>{}</td><td>{}</td><td>{}</td><td class=l>{}</td><td>{}</td><td>{}</td><td class=l>{}</td><td>{:.2}</td></tr>\n",
            r.index,
            esc(&r.name),
            esc(&r.name),
            esc(&r.family),
            esc(&r.status),
            esc(&r.status),
            esc(&r.objective),
            opt(r.value),
            r.error.map(|e| format!("{e:.1e}")).unwrap_or("–".into()),
            esc(&r.baseline),
            opt(r.baseline_value),
            r.improvement_pct.map(|i| format!("{i:.2}")).unwrap_or("–".into()),
            esc(&r
                .design
                .split(';')
                .filter(|s| !s.is_empty())
                .map(|kv| match kv.split_once('=') {
                    Some((k, v)) => format!("{k} = {}", v.parse::<f64>().map(fmt_num).unwrap_or(v.into())),
                    None => kv.into(),
                })
                .collect::<Vec<_>>()
                .join(", ")),
            r.time_s * 1e3
        );
    }
    h += "</table></div>\n";
    if n_fail > 0 {
        h += &format!("<h2>Failures ({n_fail})</h2>\n<ul>\n");
        for r in &failures {
            h += &format!(
                "<li><code>{}</code> <span class=\"{}\">{}</span>: {}</li>\n",
                esc(&r.name),
                esc(&r.status),
                esc(&r.status),
                esc(&r.message)
            );
        }
        h += "</ul>\n";
    }
    // Plots of the first machines that have them (listed in their JSON's `batch.plots`).
    let mut n_plots = 0;
    let mut plot_html = String::new();
    for r in &shown {
        if n_plots >= REPORT_PLOTS {
            break;
        }
        if crate::problem::check_name(&r.name).is_err() {
            continue;
        }
        let Ok(b) = std::fs::read(dir.join(format!("{}.json", r.name))) else {
            continue;
        };
        let Ok(v) = serde_json::from_slice::<serde_json::Value>(&b) else {
            continue;
        };
        let suffixes: Vec<String> = v
            .pointer("/batch/plots")
            .and_then(|p| p.as_array())
            .map(|a| {
                a.iter()
                    .filter_map(|s| s.as_str().map(String::from))
                    .collect()
            })
            .unwrap_or_default();
        let mut svgs = String::new();
        for s in &suffixes {
            if let Ok(svg) = std::fs::read_to_string(dir.join(format!("{}-{s}.svg", r.name))) {
                let svg = match svg.find("<svg") {
                    Some(i) => &svg[i..],
                    None => continue,
                };
                svgs += &format!("<div class=cap>{}</div>\n{svg}\n", esc(s));
            }
        }
        if svgs.is_empty() {
            continue;
        }
        n_plots += 1;
        plot_html += &format!(
            "<h3 id=\"m-{}\">{} <span class=\"{}\">({}, {})</span> · <a href=\"{}.md\">report</a> · <a href=\"{}.json\">JSON</a></h3>\n<div class=plots>\n{svgs}</div>\n",
            esc(&r.name),
            esc(&r.name),
            esc(&r.status),
            esc(&r.family),
            esc(&r.status),
            esc(&r.name),
            esc(&r.name)
        );
    }
    if n_plots > 0 {
        h += &format!(
            "<h2>Plots</h2>\n<p class=cap>The first {n_plots} machines with plots; every machine's plots are beside its JSON.</p>\n{plot_html}"
        );
    }
    h += "</body></html>\n";
    write_atomic(&dir.join("index.html"), h.as_bytes())?;
    Ok(())
}

/// A bar chart of improvements in 1 % bins (0–1, …, 19+), as inline SVG.
fn histogram_svg(bins: &[u64; 20]) -> String {
    let (w, hgt, left, bottom) = (760.0, 220.0, 50.0, 40.0);
    let max = *bins.iter().max().unwrap_or(&1) as f64;
    let bw = (w - left - 10.0) / 20.0;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{hgt}\" viewBox=\"0 0 {w} {hgt}\" font-family=\"sans-serif\" font-size=\"11\">\n"
    );
    let ph = hgt - bottom - 10.0;
    for (k, &c) in bins.iter().enumerate() {
        let bh = if max > 0.0 { ph * c as f64 / max } else { 0.0 };
        let x = left + k as f64 * bw;
        s += &format!(
            "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"#1f77b4\"/>\n",
            x + 2.0,
            10.0 + ph - bh,
            bw - 4.0,
            bh
        );
        s += &format!(
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{c}</text>\n",
            x + bw / 2.0,
            (10.0 + ph - bh - 3.0).max(10.0)
        );
        s += &format!(
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}{}</text>\n",
            x + bw / 2.0,
            hgt - bottom + 15.0,
            k,
            if k == 19 { "+" } else { "" }
        );
    }
    s += &format!(
        "<line x1=\"{left}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#333\"/>\n<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">improvement of the optimum over the best classical baseline (%)</text>\n<text x=\"12\" y=\"{:.1}\" transform=\"rotate(-90 12 {:.1})\" text-anchor=\"middle\">machines</text>\n</svg>\n",
        10.0 + ph,
        w - 10.0,
        10.0 + ph,
        left + (w - left) / 2.0,
        hgt - 5.0,
        10.0 + ph / 2.0,
        10.0 + ph / 2.0
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn template_path() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/piston-1000rpm.toml")
    }

    /// Writes `rows` under `header` as `dir/name`, opens the fleet with `template`, and
    /// returns it with its records as [`Jobs`] reads them: (row, CSV line, cells).
    fn fleet(
        dir: &Path,
        name: &str,
        template: &Path,
        header: &[&str],
        rows: &[Vec<String>],
    ) -> (Template, Vec<(u64, u64, Vec<String>)>) {
        let csv = dir.join(name);
        let mut w = csv::WriterBuilder::new()
            .flexible(true)
            .from_path(&csv)
            .unwrap();
        w.write_record(header).unwrap();
        for r in rows {
            w.write_record(r).unwrap();
        }
        w.flush().unwrap();
        let tpl = Template::open(template, &csv).unwrap();
        let recs = csv_reader(&csv)
            .unwrap()
            .into_records()
            .enumerate()
            .map(|(k, r)| {
                let r = r.unwrap();
                let line = r.position().unwrap().line();
                (k as u64 + 1, line, r.iter().map(str::to_string).collect())
            })
            .collect();
        (tpl, recs)
    }

    /// Every row gives the same machine the fast way as the slow way (the template's text
    /// edited and re-parsed): equal scenes for a good row, and for a bad row the slow way's
    /// message from both [`Template::scene`] and the slow way. Returns (good, bad) counts.
    fn same_both_ways(tpl: &Template, recs: &[(u64, u64, Vec<String>)]) -> (usize, usize) {
        let (mut good, mut bad) = (0, 0);
        for (row, line, cells) in recs {
            let (slow_name, slow) = tpl.slow_scene(*row, *line, cells);
            let (name, scene) = tpl.scene(*row, *line, cells);
            assert_eq!(name, slow_name);
            let fast = tpl.fast_scene(&name, *line, cells);
            match slow {
                Ok(slow) => {
                    good += 1;
                    let fast = fast.unwrap_or_else(|| panic!("line {line}: no fast scene"));
                    let slow = format!("{slow:?}");
                    assert_eq!(format!("{fast:?}"), slow, "line {line}");
                    assert_eq!(format!("{:?}", scene.unwrap()), slow, "line {line}");
                    assert!(slow.contains(&format!("source: \"{}:{line}\"", tpl.csv.display())));
                }
                Err(m) => {
                    bad += 1;
                    assert!(fast.is_none(), "line {line}: fast scene of a bad row: {m}");
                    assert_eq!(scene.unwrap_err(), m, "line {line}");
                }
            }
        }
        (good, bad)
    }

    /// A unit in a column header (`mechanism.speed [rpm]`) is the unit of that column's bare
    /// numbers; a cell's own unit still counts; a bare number in a dimensional column
    /// without a unit in its header is an error naming the file, line and column; an
    /// unknown header unit is an error of the header line.
    #[test]
    fn units_come_from_the_cell_or_the_header_never_guessed() {
        let dir = tempfile::tempdir().unwrap();
        let header = ["mechanism.speed [rpm]", "mechanism.crank_mass"];
        let cell = |a: &str, b: &str| vec![a.to_string(), b.to_string()];
        let rows = [
            cell("1000", "0.35 kg"),
            cell("104.71975511965977 rad/s", "350 g"),
            cell("1000", "0.35"),
        ];
        let (tpl, recs) = fleet(dir.path(), "f.csv", &template_path(), &header, &rows);
        assert_eq!(same_both_ways(&tpl, &recs), (2, 1));
        let speed = |k: usize| {
            let (_, s) = tpl.scene(recs[k].0, recs[k].1, &recs[k].2);
            format!("{:?}", s.unwrap().machine)
        };
        let omega = 1000.0 * std::f64::consts::TAU / 60.0;
        assert!(
            speed(0).contains(&format!("omega: {omega:?}")),
            "{}",
            speed(0)
        );
        let (_, bad) = tpl.scene(recs[2].0, recs[2].1, &recs[2].2);
        let bad = bad.unwrap_err();
        assert!(
            bad.starts_with(&format!(
                "{}:4: field `mechanism.crank_mass` (column 2): `0.35` has no unit",
                tpl.csv.display()
            )),
            "{bad}"
        );
        assert!(bad.contains("kg"), "{bad}");
        let csv = dir.path().join("g.csv");
        std::fs::write(&csv, "mechanism.speed [furlong]\n1\n").unwrap();
        let e = Template::open(&template_path(), &csv)
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("g.csv:1: column `mechanism.speed [furlong]`: unknown unit `furlong`"),
            "{e}"
        );
    }

    /// Many rows of the piston fleet: cells with units, plain numbers under a header with a
    /// unit, plain numbers without one (errors), integers, empty cells, a `name` column (given, empty, not a file name), a key inside an inline table,
    /// quoted text, and every broken row of `scripts/make_fleet.py` (negative length, rod
    /// shorter than the crank, unknown unit, not a quantity, negative mass).
    #[test]
    fn fast_rows_equal_slow_rows() {
        let dir = tempfile::tempdir().unwrap();
        let header = [
            "name",
            "mechanism.crank_radius [m]",
            "mechanism.rod_length",
            "mechanism.crank_mass [kg]",
            "mechanism.rod_mass",
            "mechanism.slider_mass [ kg ]",
            "mechanism.speed [rad/s]",
            "model.rod_split",
            "design.unbalance.max [kg·m]",
            "accuracy.rel_tol",
            "description",
        ];
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        let mut rows = Vec::new();
        for i in 0..400u64 {
            let r = 25.0 + next(20_000) as f64 / 1000.0;
            let l = r * (3.0 + next(2000) as f64 / 1000.0);
            let mut c: Vec<String> = vec![
                match next(4) {
                    0 => format!("m-{i}"),
                    1 if i % 50 == 1 => "not a name!".into(),
                    _ => String::new(),
                },
                match next(4) {
                    0 => format!("{r:.3} mm"),
                    1 => format!("{}", r / 1000.0),
                    2 => format!("{:.4} cm", r / 10.0),
                    _ => String::new(),
                },
                match next(3) {
                    0 => format!("{:.3}", l / 1000.0),
                    1 => String::new(),
                    _ => format!("{l:.3} mm"),
                },
                match next(4) {
                    0 => "1".into(),
                    1 => format!("{:.4}", 0.2 + next(300) as f64 / 1000.0),
                    2 => String::new(),
                    _ => format!("{} g", 200 + next(300)),
                },
                match next(3) {
                    0 => format!(" {:.4} kg ", 0.2 + next(250) as f64 / 1000.0),
                    _ => String::new(),
                },
                match next(3) {
                    0 => "2".into(),
                    1 => format!("{:.4} kg", 0.6 + next(900) as f64 / 1000.0),
                    _ => String::new(),
                },
                match next(4) {
                    0 => format!("{}", 60 + next(250)),
                    1 => format!("{:.1} rpm", 600.0 + next(24_000) as f64 / 10.0),
                    2 => format!("{}.5", 60 + next(250)),
                    _ => String::new(),
                },
                match next(4) {
                    0 => "0.5".into(),
                    1 => "0".into(),
                    2 => "1".into(),
                    _ => String::new(),
                },
                match next(3) {
                    0 => "0.3 kg*m".into(),
                    1 => "0.25".into(),
                    _ => String::new(),
                },
                match next(3) {
                    0 => "1e-8".into(),
                    1 => "0.000001".into(),
                    _ => String::new(),
                },
                match next(3) {
                    0 => format!("row {i}: a \"quoted\", \\ back\\slash, tab\t, é"),
                    1 if i % 40 == 3 => "true".into(),
                    _ => String::new(),
                },
            ];
            // The broken rows of scripts/make_fleet.py, about one in four.
            match next(20) {
                0 => c[1] = format!("-{r:.3} mm"),
                1 => c[2] = format!("{:.3} mm", 0.5 * r),
                2 => c[3] = "0.3 furlong".into(),
                3 => c[6] = "fast".into(),
                4 => c[5] = "-1 kg".into(),
                _ => {}
            }
            rows.push(c);
        }
        let (tpl, recs) = fleet(dir.path(), "fleet.csv", &template_path(), &header, &rows);
        let (good, bad) = same_both_ways(&tpl, &recs);
        assert_eq!(good + bad, 400);
        assert!(good > 200 && bad > 60, "good {good}, bad {bad}");
    }

    /// Rows broken by their shape: a wrong cell count, a key through a value or an array, an
    /// unknown key, an empty key part, a value of the wrong type, another family.
    #[test]
    fn broken_shapes_fail_both_ways_with_the_slow_message() {
        let dir = tempfile::tempdir().unwrap();
        let cases: [(&str, &[&str]); 9] = [
            ("mechanism.speed", &["1000 rpm", "x"]),
            ("mechanism.speed.x", &["3"]),
            ("paper.value", &["3 N"]),
            ("mechanism.colour", &["red"]),
            ("mechanism..speed", &["3"]),
            ("model.rod_split", &["true"]),
            ("objective.minimize", &["everything"]),
            ("family", &["hypocycloid"]),
            ("name", &["../x"]),
        ];
        for (k, (key, cells)) in cases.iter().enumerate() {
            let rows = vec![cells.iter().map(|c| c.to_string()).collect()];
            let csv = format!("f{k}.csv");
            let (tpl, recs) = fleet(dir.path(), &csv, &template_path(), &[key], &rows);
            assert_eq!(same_both_ways(&tpl, &recs), (0, 1), "{key}");
        }
    }

    /// The input hash of a row changes with the template text, the header, the name and each
    /// cell, and is the same for the same input read again.
    #[test]
    fn row_hash_follows_the_input() {
        let dir = tempfile::tempdir().unwrap();
        let header = ["mechanism.speed", "mechanism.crank_mass"];
        let rows = vec![vec!["1000 rpm".to_string(), "0.3 kg".to_string()]];
        let t = template_path();
        let (a, _) = fleet(dir.path(), "a.csv", &t, &header, &rows);
        let (a2, _) = fleet(dir.path(), "a2.csv", &t, &header, &rows);
        let (b, _) = fleet(
            dir.path(),
            "b.csv",
            &t,
            &["mechanism.speed", "model.rod_split"],
            &rows,
        );
        let t2 = dir.path().join("t2.toml");
        std::fs::write(&t2, std::fs::read_to_string(&t).unwrap() + "# edited\n").unwrap();
        let (c, _) = fleet(dir.path(), "c.csv", &t2, &header, &rows);
        let cells = |x: &[&str]| x.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let h = a.input_hash("m", &cells(&["1000 rpm", "0.3 kg"]));
        assert_eq!(h.len(), 32);
        assert_eq!(h, a.input_hash("m", &cells(&["1000 rpm", "0.3 kg"])));
        assert_eq!(h, a2.input_hash("m", &cells(&["1000 rpm", "0.3 kg"])));
        for other in [
            a.input_hash("n", &cells(&["1000 rpm", "0.3 kg"])),
            a.input_hash("m", &cells(&["1001 rpm", "0.3 kg"])),
            a.input_hash("m", &cells(&["1000 rpm", "0.4 kg"])),
            a.input_hash("m", &cells(&["1000 rpm0.3 kg", ""])),
            a.input_hash("m", &cells(&["1000 rpm", "0.3 kg", ""])),
            b.input_hash("m", &cells(&["1000 rpm", "0.3 kg"])),
            c.input_hash("m", &cells(&["1000 rpm", "0.3 kg"])),
        ] {
            assert_ne!(h, other);
        }
    }

    /// Formula escaping round-trips every text exactly, escapes only texts a spreadsheet
    /// would run, and never numbers.
    #[test]
    fn formula_escape_round_trips() {
        let texts = [
            "", "plain", "=1+2", "+x", "-x", "@x", "\tx", "\rx", "'x", "''=x", "'", "a=b", "-",
            "é=",
        ];
        for t in texts {
            let mut r = error_row(0, t, t, "", t.to_string());
            r.value = Some(-3.5);
            let e = r.csv_escaped();
            let risky = t.starts_with(['=', '+', '-', '@', '\t', '\r', '\'']);
            assert_eq!(
                e.name.starts_with('\'') && e.name.len() == t.len() + 1,
                risky,
                "{t:?}"
            );
            assert_eq!(e.value, Some(-3.5));
            let mut w = csv::Writer::from_writer(Vec::new());
            w.serialize(&e).unwrap();
            let bytes = w.into_inner().unwrap();
            let mut rdr = csv::Reader::from_reader(&bytes[..]);
            let hdr = rdr.headers().unwrap().clone();
            assert!(hdr.iter().eq(HEADER));
            let rec = rdr.records().next().unwrap().unwrap();
            let back: Row = rec.deserialize::<Row>(Some(&hdr)).unwrap().csv_unescaped();
            assert_eq!(back, r, "{t:?}");
        }
    }

    /// The line of each record from its byte position: past CRLF ends, blank lines and
    /// comments.
    #[test]
    fn record_lines_skip_what_the_reader_skips() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("l.csv");
        std::fs::write(&p, "h\r\na\r\n# c\r\n\r\nb\n\n#x\n#y\nc").unwrap();
        let mut rdr = csv_reader(&p).unwrap();
        let mut lines = Lines::open(&p).unwrap();
        let got: Vec<(String, u64)> = rdr
            .records()
            .map(|r| {
                let r = r.unwrap();
                (
                    r[0].to_string(),
                    lines.record_line(r.position().unwrap().byte()),
                )
            })
            .collect();
        assert_eq!(got, [("a".into(), 2), ("b".into(), 5), ("c".into(), 9)]);
    }

    /// A file hash changes with any byte and the length.
    #[test]
    fn file_hash_sees_torn_files() {
        let a: Vec<u8> = (0..1000u32).map(|i| (i * 7 % 251) as u8).collect();
        let h = file_hash(&a);
        assert_eq!(h.len(), 32);
        assert_ne!(h, file_hash(&a[..999]));
        assert_ne!(h, file_hash(&a[..500]));
        assert_ne!(file_hash(&[0; 8]), file_hash(&[0; 9]));
        for k in [0, 7, 8, 500, 999] {
            let mut b = a.clone();
            b[k] ^= 1;
            assert_ne!(h, file_hash(&b), "{k}");
        }
    }
}
