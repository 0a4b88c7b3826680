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

use crate::report::plot::{self, Panel, Series};
use crate::problem::{parse_str, Family, Scene, SceneKind};
use crate::report::SolveResult;
use crate::families::slider_crank::model::Kinematics;
use crate::run::solve_scene;
use std::fmt::Write as _;
use std::path::Path;
use toml_edit::{DocumentMut, Item, Value};

pub mod effects;
pub use effects::effects;

/// One change of the problem text.
#[derive(Debug, Clone)]
pub enum Edit {
    /// Set `section.key` to a value.
    Set(&'static str, Value),
    /// Remove `section.key` if present.
    Remove(&'static str),
}

/// A rung of the ladder.
#[derive(Debug, Clone)]
pub struct Rung {
    /// Short label.
    pub label: String,
    /// `accuracy` or `model`.
    pub kind: &'static str,
    /// Edits applied to the file as written.
    pub edits: Vec<Edit>,
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

fn v_int(x: i64) -> Value {
    Value::from(x)
}
fn v_f(x: f64) -> Value {
    Value::from(x)
}
fn v_s(x: &str) -> Value {
    Value::from(x)
}

/// The problem text with `edits` applied (tables created as needed).
pub fn apply(text: &str, edits: &[Edit]) -> Result<String, String> {
    let mut doc: DocumentMut = text.parse().map_err(|e| format!("{e}"))?;
    for e in edits {
        match e {
            Edit::Set(path, v) => {
                let (sec, key) = path.split_once('.').expect("section.key");
                if doc.get(sec).is_none() {
                    doc.insert(sec, Item::Table(toml_edit::Table::new()));
                }
                let t = doc[sec]
                    .as_table_like_mut()
                    .ok_or_else(|| format!("`{sec}` is not a table"))?;
                t.insert(key, Item::Value(v.clone()));
            }
            Edit::Remove(path) => {
                let (sec, key) = path.split_once('.').expect("section.key");
                if let Some(t) = doc.get_mut(sec).and_then(Item::as_table_like_mut) {
                    t.remove(key);
                }
            }
        }
    }
    Ok(doc.to_string())
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

fn rung(label: &str, kind: &'static str, edits: Vec<Edit>) -> Rung {
    Rung {
        label: label.into(),
        kind,
        edits,
    }
}

/// The headline result key of a scene.
fn headline(scene: &Scene, doc: &DocumentMut) -> String {
    match scene.family {
        Family::SliderCrank => {
            match doc
                .get("objective")
                .and_then(|o| o.get("minimize"))
                .and_then(|m| m.as_str())
            {
                Some("rms-force") => "objectives.rms_shaking_force_n",
                Some("peak-torque") => "objectives.peak_drive_torque_nm",
                Some("mass") => "design.counterweight_mass_kg",
                Some("radius") => "design.counterweight_radius_m",
                _ => "objectives.peak_shaking_force_n",
            }
        }
        Family::LuffingCrane => "objectives.delta_h_m",
        // A design of e holds the peak |µ| at its limit: the objective is the ratio variation.
        Family::EccentricGear => match &scene.kind {
            SceneKind::EccentricGear(g)
                if matches!(g.gear.eccentricity, crate::synth::Var::Free { .. }) =>
            {
                "objectives.ratio_variation"
            }
            _ => "objectives.peak_sliding_coefficient",
        },
        // A scene asking the paper's C4 question is judged on C4 (a4 of S/R) itself.
        Family::Hypocycloid => match &scene.kind {
            SceneKind::Hypocycloid(h) if h.scene.zero_search.is_some() => "objectives.c4",
            _ => "objectives.residual_force_peak_n",
        },
    }
    .to_string()
}

/// The reference edits (tightest settings) and the ladder of a scene.
pub fn ladder(scene: &Scene) -> (Vec<Edit>, Vec<Rung>) {
    use Edit::{Remove, Set};
    match &scene.kind {
        SceneKind::SliderCrank(s) => {
            let reference = vec![
                Set("accuracy.rel_tol", v_f(1e-11)),
                Set("accuracy.initial_samples", v_int(64)),
                Set("accuracy.scan_samples", v_int(2880)),
                Set("accuracy.max_rounds", v_int(100)),
                Set("accuracy.peak_xtol", v_f(1e-12)),
                Set("accuracy.rms_samples", v_int(4096)),
            ];
            let mut l = Vec::new();
            for n in [8i64, 32, 128, 512] {
                l.push(rung(
                    &format!("{n} samples, no exchange"),
                    "accuracy",
                    vec![
                        Set("accuracy.initial_samples", v_int(n)),
                        Set("accuracy.max_rounds", v_int(1)),
                        Set("accuracy.presolve", Value::from(false)),
                    ],
                ));
            }
            l.push(rung(
                "no presolve (exchange from 8 samples)",
                "accuracy",
                vec![Set("accuracy.presolve", Value::from(false))],
            ));
            l.push(rung(
                "presolve, no exchange",
                "accuracy",
                vec![Set("accuracy.max_rounds", v_int(1))],
            ));
            l.push(rung(
                "presolve, clarabel SOCP rounds (no exact disc)",
                "accuracy",
                vec![Set("accuracy.exact_disc", Value::from(false))],
            ));
            for n in [64i64, 1440] {
                l.push(rung(
                    &format!("scan {n}, exchange"),
                    "accuracy",
                    vec![Set("accuracy.scan_samples", v_int(n))],
                ));
            }
            for t in [1e-3, 1e-6] {
                l.push(rung(
                    &format!("rel_tol {t:e}"),
                    "accuracy",
                    vec![Set("accuracy.rel_tol", v_f(t))],
                ));
            }
            let m = &s.core.mech;
            if m.kinematics == Kinematics::Exact {
                l.push(rung(
                    "two-harmonic kinematics",
                    "model",
                    vec![Set("model.kinematics", v_s("two-harmonic"))],
                ));
            } else {
                l.push(rung(
                    "exact kinematics",
                    "model",
                    vec![Set("model.kinematics", v_s("exact"))],
                ));
            }
            let lumped = (m.rod.inertia - m.rod.mass * (m.l - m.rod.centroid) * m.rod.centroid)
                .abs()
                <= 1e-12 * (m.rod.mass * m.l * m.l).max(1e-300);
            if lumped {
                l.push(rung(
                    "rigid uniform rod",
                    "model",
                    vec![Remove("model.rod_split"), Set("model.masses", v_s("rigid"))],
                ));
            } else {
                l.push(rung(
                    "lumped rod (½ + ½)",
                    "model",
                    vec![
                        Remove("model.rod_centroid"),
                        Remove("model.rod_inertia"),
                        Set("model.masses", v_s("lumped")),
                    ],
                ));
            }
            if s.core.loads.gravity.norm() > 0.0 {
                l.push(rung(
                    "no gravity",
                    "model",
                    vec![
                        Remove("model.gravity_acceleration"),
                        Set("model.gravity", Value::from(false)),
                    ],
                ));
            } else {
                l.push(rung(
                    "with gravity",
                    "model",
                    vec![Set("model.gravity", Value::from(true))],
                ));
            }
            (reference, l)
        }
        SceneKind::Hypocycloid(_) => {
            let reference = vec![
                Set("accuracy.n_fft_min", v_int(8192)),
                Set("accuracy.n_fft_max", v_int(1 << 18)),
                Set("accuracy.peak_samples", v_int(4096)),
                Set("accuracy.peak_xtol", v_f(1e-12)),
                Set("accuracy.root_tol", v_f(1e-14)),
            ];
            let mut l = Vec::new();
            // One fixed FFT size, no adaptive doubling (orders ≥ n/2 of the remainder left out).
            for n in [16i64, 32, 64] {
                l.push(rung(
                    &format!("FFT {n} fixed"),
                    "accuracy",
                    vec![
                        Set("accuracy.fft_adaptive", Value::from(false)),
                        Set("accuracy.n_fft_min", v_int(n)),
                    ],
                ));
            }
            // Odd counts: φ = 0, π/2, π, 3π/2 (where peaks of these scenes sit) are not all
            // samples, so the sampled peak converges like h².
            for n in [31i64, 97, 257, 1021] {
                l.push(rung(
                    &format!("peak scan {n}, unrefined"),
                    "accuracy",
                    vec![
                        Set("accuracy.refine_peaks", Value::from(false)),
                        Set("accuracy.peak_samples", v_int(n)),
                    ],
                ));
            }
            l.push(rung(
                "peak scan 32, refined",
                "accuracy",
                vec![Set("accuracy.peak_samples", v_int(32))],
            ));
            // The paper's method: coefficients from the binomial series truncated at z^p.
            for p in [1i64, 2, 3, 6] {
                l.push(rung(
                    &format!("paper series, power {p}"),
                    "model",
                    vec![
                        Set("model.coefficients", v_s("series")),
                        Set("model.series_power", v_int(p)),
                    ],
                ));
            }
            (reference, l)
        }
        SceneKind::LuffingCrane(_) => {
            let reference = vec![
                Set("accuracy.path_samples", v_int(1024)),
                Set("accuracy.xtol", v_f(1e-12)),
            ];
            let mut l = Vec::new();
            // Counts that do not divide one another, so no grid contains a coarser one.
            for n in [8i64, 20, 50, 130, 330] {
                l.push(rung(
                    &format!("path {n}, unrefined"),
                    "accuracy",
                    vec![
                        Set("accuracy.refine_peaks", Value::from(false)),
                        Set("accuracy.path_samples", v_int(n)),
                    ],
                ));
            }
            for n in [8i64, 64] {
                l.push(rung(
                    &format!("path {n}, refined"),
                    "accuracy",
                    vec![Set("accuracy.path_samples", v_int(n))],
                ));
            }
            for t in [1e-4, 1e-10] {
                l.push(rung(
                    &format!("xtol {t:e}"),
                    "accuracy",
                    vec![Set("accuracy.xtol", v_f(t))],
                ));
            }
            (reference, l)
        }
        SceneKind::EccentricGear(_) => {
            let reference = vec![
                Set("accuracy.samples_per_arch", v_int(96)),
                Set("accuracy.peak_samples_per_arch", v_int(512)),
                Set("accuracy.peak_xtol", v_f(1e-12)),
                Set("accuracy.pole_tol", v_f(1e-13)),
            ];
            let mut l = Vec::new();
            // Poles placed by one false-position step in their sampled bracket (no Brent).
            for n in [8i64, 24, 96] {
                l.push(rung(
                    &format!("poles unrefined, {n} samples/arch"),
                    "accuracy",
                    vec![
                        Set("accuracy.refine_poles", Value::from(false)),
                        Set("accuracy.samples_per_arch", v_int(n)),
                    ],
                ));
            }
            l.push(rung(
                "8 samples/arch, refined",
                "accuracy",
                vec![Set("accuracy.samples_per_arch", v_int(8))],
            ));
            for n in [8i64, 32, 128] {
                l.push(rung(
                    &format!("peak {n}/arch, unrefined"),
                    "accuracy",
                    vec![
                        Set("accuracy.refine_peaks", Value::from(false)),
                        Set("accuracy.peak_samples_per_arch", v_int(n)),
                    ],
                ));
            }
            l.push(rung(
                "pole_tol 1e-12",
                "accuracy",
                vec![Set("accuracy.pole_tol", v_f(1e-12))],
            ));
            l.push(rung(
                "peak_xtol 1e-5",
                "accuracy",
                vec![Set("accuracy.peak_xtol", v_f(1e-5))],
            ));
            for w in ["0.001 rad", "0.05 rad"] {
                l.push(rung(
                    &format!("pole window {w}"),
                    "model",
                    vec![Set("model.pole_window", v_s(w))],
                ));
            }
            (reference, l)
        }
    }
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
) -> Result<(SolveResult, f64, f64, usize), String> {
    let scene = parse_str(text, path).map_err(|e| e.to_string())?;
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
pub fn study(text: &str, path: &Path, repeats: usize) -> Result<Study, String> {
    let scene = parse_str(text, path).map_err(|e| e.to_string())?;
    let doc: DocumentMut = text.parse().map_err(|e| format!("{e}"))?;
    let key = headline(&scene, &doc);
    let (ref_edits, rungs) = ladder(&scene);
    let ref_text = apply(text, &ref_edits)?;
    let (rr, rs, rt, rn) = timed(&ref_text, path, 1)?;
    let reference = rr
        .lookup(&key)
        .ok_or_else(|| format!("the reference has no `{key}`"))?;
    let mut out = Vec::new();
    let mut one = |label: &str, kind: &str, edits: &[Edit]| {
        let t = apply(text, edits);
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
                status: format!("rejected: {}", e.replace('\n', " ")),
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
        family: scene.family.as_str().into(),
        key,
        reference,
        rungs: out,
        effects: effects(&scene, &rr, reference),
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
pub fn svg(s: &Study) -> Result<String, String> {
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
            x_label: "log10 solve time / s".into(),
            y_label: "log10 relative error (floor 1e-16)".into(),
            series,
            equal_aspect: false,
        }],
        800,
        520,
    )
}
