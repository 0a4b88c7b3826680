//! Speed against error (`cwsynth study`): one scene solved along a ladder of accuracy and
//! fidelity settings, each rung timed (median of repeats) and compared with a reference
//! computed by the program at its tightest settings.
//!
//! Every rung is the problem text edited with `toml_edit` (keys of `[accuracy]` and
//! `[model]` set or removed) and parsed again, so every family goes through the same path
//! as a file would, and a rung the resolver rejects is reported, not hidden. The error of a
//! rung is the relative difference of the family's headline objective from the reference's.
//! Accuracy rungs measure numerical error; model rungs (`model.*`) measure the size of the
//! effect the model adds or leaves out (their "error" is a modelling difference).

use crate::families::{parse_str, solve_scene};
use crate::problem::edit::{apply, Edit, EditError};
use crate::problem::ProblemError;
use crate::report::plot::{self, Panel, Series};
use crate::report::SolveResult;
use std::fmt::Write as _;
use std::path::Path;

/// Why a study could not be made (a rung that fails is a row of the study, not an error).
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The problem text (or its reference rung) does not resolve.
    #[error("{0}")]
    Problem(ProblemError),
    /// The reference rung's edits cannot be applied.
    #[error("{0}")]
    Edit(EditError),
    /// The reference result has no value of the headline key.
    #[error("the reference has no `{0}`")]
    NoReference(String),
    /// The plot could not be drawn.
    #[error("plot: {0}")]
    Plot(crate::report::plot::PlotError),
}

// The causes are in the messages, not chained as sources: the CLI prints each once.
impl From<ProblemError> for StudyError {
    fn from(e: ProblemError) -> StudyError {
        StudyError::Problem(e)
    }
}

impl From<EditError> for StudyError {
    fn from(e: EditError) -> StudyError {
        StudyError::Edit(e)
    }
}

/// The outcome of one rung.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RungResult {
    /// Label.
    pub label: String,
    /// `default`, `accuracy`, `model` or `reference`.
    pub kind: String,
    /// The edits, as `key = value` text.
    pub settings: String,
    /// Median of the family's solve time (s).
    pub solve_s: f64,
    /// Median of the whole solve including baselines and report data (s).
    pub total_s: f64,
    /// Repeats timed.
    pub repeats: usize,
    /// The headline objective.
    pub value: Option<f64>,
    /// |value − reference|/|reference|.
    pub rel_error: Option<f64>,
    /// Result status, or the rejection.
    pub status: String,
}

/// A whole study.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Study {
    /// Scene name.
    pub name: String,
    /// Family.
    pub family: String,
    /// The result key compared.
    pub key: String,
    /// The reference value.
    pub reference: f64,
    /// Rungs, the default first and the reference last.
    pub rungs: Vec<RungResult>,
    /// Effects the scene's model leaves out, with a bound (text).
    pub effects: Vec<(String, String)>,
}

fn settings_text(edits: &[Edit]) -> String {
    edits
        .iter()
        .map(|e| match e {
            Edit::Set(k, v) => format!("{k} = {}", v.to_string().trim()),
            Edit::Remove(k) => format!("−{k}"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Solves `text` `repeats` times (at least; more while under 0.2 s in all, up to 4×).
fn timed(
    text: &str,
    path: &Path,
    repeats: usize,
) -> Result<(SolveResult, f64, f64, usize), StudyError> {
    let scene = parse_str(text, path)?;
    let mut solve = Vec::new();
    let mut total = Vec::new();
    let mut last = None;
    let t0 = std::time::Instant::now();
    while solve.len() < repeats
        || (t0.elapsed().as_secs_f64() < 0.2 && solve.len() < 4 * repeats.max(1))
    {
        let r = solve_scene(&scene);
        solve.push(r.timing.solve_s);
        total.push(r.timing.total_s);
        last = Some(r);
    }
    let n = solve.len();
    Ok((last.unwrap(), median(solve), median(total), n))
}

fn status_of(r: &SolveResult) -> String {
    serde_json::to_value(r.status)
        .ok()
        .and_then(|v| v.as_str().map(String::from))
        .unwrap_or_default()
}

/// Runs the study of a problem text.
pub fn study(text: &str, path: &Path, repeats: usize) -> Result<Study, StudyError> {
    let scene = parse_str(text, path)?;
    let key = scene.machine.headline();
    let ladder = scene.machine.ladder();
    let (ref_edits, rungs) = (ladder.reference, ladder.rungs);
    let ref_text = apply(text, &ref_edits)?;
    let (rr, rs, rt, rn) = timed(&ref_text, path, 1)?;
    let reference = rr
        .lookup(&key)
        .ok_or_else(|| StudyError::NoReference(key.clone()))?;
    let mut out = Vec::new();
    let mut one = |label: &str, kind: &str, edits: &[Edit]| {
        let t = apply(text, edits).map_err(StudyError::from);
        let res = t.and_then(|t| timed(&t, path, repeats));
        out.push(match res {
            Ok((r, s, tt, n)) => {
                let v = r.lookup(&key);
                RungResult {
                    label: label.into(),
                    kind: kind.into(),
                    settings: settings_text(edits),
                    solve_s: s,
                    total_s: tt,
                    repeats: n,
                    value: v,
                    rel_error: v.map(|v| (v - reference).abs() / reference.abs().max(1e-300)),
                    status: status_of(&r),
                }
            }
            Err(e) => RungResult {
                label: label.into(),
                kind: kind.into(),
                settings: settings_text(edits),
                solve_s: f64::NAN,
                total_s: f64::NAN,
                repeats: 0,
                value: None,
                rel_error: None,
                status: format!("rejected: {}", e.to_string().replace('\n', " ")),
            },
        });
    };
    one("default (file)", "default", &[]);
    for r in &rungs {
        one(&r.label, r.kind, &r.edits);
    }
    out.push(RungResult {
        label: "reference".into(),
        kind: "reference".into(),
        settings: settings_text(&ref_edits),
        solve_s: rs,
        total_s: rt,
        repeats: rn,
        value: Some(reference),
        rel_error: Some(0.0),
        status: status_of(&rr),
    });
    Ok(Study {
        name: scene.name.clone(),
        family: scene.family.name().into(),
        key,
        reference,
        rungs: out,
        effects: scene.machine.effects(&rr, reference),
    })
}

/// Ten decimals, or ten significant digits for values far from 1.
fn fmt_value(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:.9e}")
    } else {
        format!("{v:.10}")
    }
}

fn fmt_opt(v: Option<f64>) -> String {
    v.map(|v| format!("{v:.12e}")).unwrap_or_default()
}

/// CSV: one line per rung.
pub fn csv(s: &Study) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "rung",
        "kind",
        "settings",
        "solve_s",
        "total_s",
        "repeats",
        &s.key,
        "rel_error",
        "status",
    ])
    .unwrap();
    for r in &s.rungs {
        w.write_record([
            r.label.as_str(),
            &r.kind,
            &r.settings,
            &format!("{:.6e}", r.solve_s),
            &format!("{:.6e}", r.total_s),
            &r.repeats.to_string(),
            &fmt_opt(r.value),
            &r.rel_error.map(|e| format!("{e:.3e}")).unwrap_or_default(),
            &r.status,
        ])
        .unwrap();
    }
    String::from_utf8(w.into_inner().unwrap()).unwrap()
}

/// Markdown: the table and the effects left out.
pub fn markdown(s: &Study) -> String {
    let mut m = String::new();
    let _ = writeln!(
        m,
        "### {} ({})\n\nHeadline value `{}`; reference (tightest settings) {:.12e}. Times are medians of the family's solve (`timing.solve_s`) and of the whole solve with baselines and report data (`timing.total_s`).\n",
        s.name, s.family, s.key, s.reference
    );
    let _ = writeln!(
        m,
        "| rung | kind | settings | solve (ms) | total (ms) | n | value | rel. error | status |\n|---|---|---|---:|---:|---:|---:|---:|---|"
    );
    for r in &s.rungs {
        let _ = writeln!(
            m,
            "| {} | {} | {} | {:.3} | {:.3} | {} | {} | {} | {} |",
            r.label,
            r.kind,
            r.settings.replace('|', "\\|"),
            r.solve_s * 1e3,
            r.total_s * 1e3,
            r.repeats,
            r.value.map(fmt_value).unwrap_or("–".into()),
            r.rel_error
                .map(|e| format!("{e:.2e}"))
                .unwrap_or("–".into()),
            r.status.replace('|', "\\|")
        );
    }
    if !s.effects.is_empty() {
        let _ = writeln!(m, "\nLeft out or included by the scene's model:\n");
        for (k, v) in &s.effects {
            let _ = writeln!(m, "- **{k}**: {v}");
        }
    }
    m
}

/// SVG: log10 time against log10 error (errors below 1e-16 drawn at 1e-16), default marked.
pub fn svg(s: &Study) -> Result<String, StudyError> {
    let pt = |r: &RungResult| {
        r.rel_error
            .filter(|_| r.solve_s.is_finite() && r.solve_s > 0.0)
            .map(|e| (r.solve_s.log10(), e.max(1e-16).log10()))
    };
    let pick = |k: &str| -> Vec<(f64, f64)> {
        s.rungs
            .iter()
            .filter(|r| r.kind == k)
            .filter_map(pt)
            .collect()
    };
    let mut series = vec![
        Series::points("accuracy rungs", pick("accuracy")),
        Series::points("model rungs (modelling difference)", pick("model")),
        Series::marker("default (file)", pick("default")),
    ];
    series.retain(|x| !x.points.is_empty());
    plot::panels(
        &[Panel {
            title: format!("{}: time against error of {}", s.name, s.key),
            x_label: "log10 solve time (log10 s)".into(),
            y_label: "log10 relative error (–, floor 1e-16)".into(),
            series,
            equal_aspect: false,
        }],
        800,
        520,
    )
    .map_err(StudyError::Plot)
}
