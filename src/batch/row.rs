//! One line of the summary ([`Row`]): made from a machine's result JSON (fresh or read back),
//! or from why the machine was not solved; escaped against spreadsheet formulas when
//! written and checked when read back, since a summary on disk is input like any other.

use crate::report::{truncate, SolveResult};
use serde::{Deserialize, Serialize};

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

/// A text cell starting with one of [`FORMULA_START`] gets a leading `'`, so that no
/// spreadsheet runs it as a formula.
pub(super) fn escape_formula(t: &mut String) {
    if t.starts_with(FORMULA_START) {
        t.insert(0, '\'');
    }
}

/// Whether a row of status `status` is a failure: bad input (`error`), `infeasible` or
/// `failed` (the run then exits with status 1).
pub fn is_failure(status: &str) -> bool {
    matches!(status, "error" | "failed" | "infeasible")
}

impl Row {
    /// Whether this machine failed ([`is_failure`]).
    pub fn failed(&self) -> bool {
        is_failure(&self.status)
    }

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
            escape_formula(t);
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

/// The numbers of a result map as `key=value;…` (shortest round-trip format; a value JSON
/// cannot hold — NaN, ±∞ — is left out, as it is null in the JSON).
fn kv(m: &[(&str, Option<f64>)]) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    for (k, x) in m.iter().filter_map(|(k, x)| Some((k, (*x)?))) {
        let sep = if out.is_empty() { "" } else { ";" };
        let _ = write!(out, "{sep}{k}={x:?}");
    }
    out
}

/// A result map's numbers in key order (`None`: null in the JSON).
type Numbers<'a> = Vec<(&'a str, Option<f64>)>;

/// What a summary row reads from a result, borrowed, maps in key order, a number `None`
/// where the JSON has null: from a result JSON read back ([`row_from_json`]) or from a fresh
/// [`SolveResult`] ([`row_from_result`], without building its JSON). [`row_of`] makes the
/// row from it, so both give the same row.
struct RowInput<'a> {
    name: &'a str,
    family: &'a str,
    status: &'a str,
    status_detail: &'a str,
    objective: Option<&'a str>,
    design: Numbers<'a>,
    objectives: Numbers<'a>,
    errors: Numbers<'a>,
    baselines: Vec<(&'a str, Numbers<'a>)>,
    warnings: Vec<&'a str>,
    total_s: f64,
}

/// The numbers of a JSON object (empty when absent or not an object).
fn json_numbers(v: Option<&serde_json::Value>) -> Vec<(&str, Option<f64>)> {
    v.and_then(|v| v.as_object())
        .map(|o| o.iter().map(|(k, x)| (k.as_str(), x.as_f64())).collect())
        .unwrap_or_default()
}

/// A result map's numbers as the JSON reads them back (non-finite: null).
fn map_numbers(m: &std::collections::BTreeMap<String, f64>) -> Vec<(&str, Option<f64>)> {
    m.iter()
        .map(|(k, x)| (k.as_str(), Some(*x).filter(|x| x.is_finite())))
        .collect()
}

/// The value of `key` in a row input's map.
fn lookup(m: &[(&str, Option<f64>)], key: &str) -> Option<f64> {
    m.iter().find(|(k, _)| *k == key).and_then(|(_, x)| *x)
}

/// The summary row of a result JSON (fresh or read back from `<name>.json`).
pub fn row_from_json(index: u64, source: &str, hash: &str, v: &serde_json::Value) -> Row {
    let s = |k: &str| v.get(k).and_then(|x| x.as_str()).unwrap_or("");
    let input = RowInput {
        name: s("name"),
        family: s("family"),
        status: s("status"),
        status_detail: s("status_detail"),
        objective: v.get("objective").and_then(|x| x.as_str()),
        design: json_numbers(v.get("design")),
        objectives: json_numbers(v.get("objectives")),
        errors: json_numbers(v.get("errors")),
        baselines: v
            .get("baselines")
            .and_then(|b| b.as_object())
            .map(|b| {
                b.iter()
                    .map(|(name, m)| (name.as_str(), json_numbers(Some(m))))
                    .collect()
            })
            .unwrap_or_default(),
        warnings: v
            .get("warnings")
            .and_then(|w| w.as_array())
            .map(|w| w.iter().filter_map(|x| x.as_str()).collect())
            .unwrap_or_default(),
        total_s: v
            .get("timing")
            .and_then(|t| t.get("total_s"))
            .and_then(|x| x.as_f64())
            .unwrap_or(0.0),
    };
    row_of(index, source, hash, input)
}

/// The summary row of a fresh result: the same row as [`row_from_json`] of its JSON
/// (`tests/batch.rs` holds them equal), without building the JSON.
pub fn row_from_result(index: u64, source: &str, hash: &str, r: &SolveResult) -> Row {
    let input = RowInput {
        name: &r.name,
        family: &r.family,
        status: r.status.as_str(),
        status_detail: r.status_detail.as_deref().unwrap_or(""),
        objective: r.objective.as_deref(),
        design: map_numbers(&r.design),
        objectives: map_numbers(&r.objectives),
        errors: map_numbers(&r.errors),
        baselines: r
            .baselines
            .iter()
            .map(|(name, m)| (name.as_str(), map_numbers(m)))
            .collect(),
        warnings: r.warnings.iter().map(String::as_str).collect(),
        total_s: if r.timing.total_s.is_finite() {
            r.timing.total_s
        } else {
            0.0
        },
    };
    row_of(index, source, hash, input)
}

/// The summary row of a result's fields.
fn row_of(index: u64, source: &str, hash: &str, v: RowInput) -> Row {
    let objective = v
        .objective
        .filter(|k| v.objectives.iter().any(|(o, _)| o == k))
        // Every result names its key objective (its family's headline); a result without
        // one is judged on its first objective.
        .or_else(|| v.objectives.first().map(|(k, _)| *k))
        .unwrap_or("")
        .to_string();
    let value = lookup(&v.objectives, &objective);
    let error = lookup(&v.errors, &objective);
    // Best classical baseline: the smallest improvement (the hardest one to beat).
    let mut best: Option<(&str, Option<f64>, f64)> = None;
    for (name, m) in &v.baselines {
        if let Some(imp) = lookup(m, "improvement_pct") {
            if best.as_ref().is_none_or(|(_, _, i)| imp < *i) {
                best = Some((name, lookup(m, &objective), imp));
            }
        }
    }
    let status = v.status.to_string();
    let message = if status == "degenerate" {
        v.status_detail.to_string()
    } else if matches!(status.as_str(), "failed" | "infeasible" | "inaccurate") {
        // The detail first: an infeasible result's says how far off each limit is.
        (!v.status_detail.is_empty())
            .then_some(v.status_detail)
            .into_iter()
            .chain(v.warnings.iter().copied())
            .collect::<Vec<&str>>()
            .join(" | ")
    } else {
        String::new()
    };
    Row {
        index,
        name: v.name.to_string(),
        family: v.family.to_string(),
        status,
        objective,
        value,
        error,
        baseline: best.map(|b| b.0.to_string()).unwrap_or_default(),
        baseline_value: best.and_then(|b| b.1),
        improvement_pct: best.map(|b| b.2),
        design: kv(&v.design),
        objectives: kv(&v.objectives),
        time_s: v.total_s,
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

/// The row of a machine that was not solved: status `error`, the reason as its message
/// (long names and messages cut, [`MESSAGE_BYTES`]).
pub fn error_row(index: u64, name: &str, source: &str, hash: &str, message: String) -> Row {
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
pub(super) fn panic_row(index: u64, name: &str, source: &str, panic: &str) -> Row {
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

impl Counts {
    /// Counts one machine's row (`skipped`: reused from a previous run); returns whether it
    /// failed.
    pub(super) fn add(&mut self, row: &Row, skipped: bool) -> bool {
        self.total += 1;
        self.skipped += u64::from(skipped);
        let failed = row.failed();
        if failed {
            self.failed += 1;
        } else {
            self.ok += 1;
        }
        failed
    }
}
