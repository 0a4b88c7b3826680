//! One line of the summary ([`Row`]): made from a machine's result JSON (fresh or read back),
//! or from why the machine was not solved; escaped against spreadsheet formulas when
//! written and checked when read back, since a summary on disk is input like any other.

use crate::report::truncate;
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

/// The numbers of a JSON object as `key=value;…` (shortest round-trip format).
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

/// The row of a machine that was not solved: status `error`, the reason as its message
/// (long names and messages cut, [`MESSAGE_BYTES`]).
pub(super) fn error_row(index: u64, name: &str, source: &str, hash: &str, message: String) -> Row {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
