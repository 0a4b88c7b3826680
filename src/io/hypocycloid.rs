//! The hypocycloid problem file — its raw sections and their resolution into a checked
//! [`crate::synth::hypocycloid::HypocycloidScene`] with its [`Settings`] (every field
//! documented in `docs/problem-files.md`) — and the shaping of its outcome into a result
//! (keys in `docs/results.md`): the order coefficients of S/R, the Lanchester balancing, the
//! (λ, θ) optimisation and the zero search of the fourth-order coefficient.

use super::limits;
use super::plot::{self, Grid, Panel, Series};
use super::problem::Family;
use super::problem::{
    check_name, positive, Ctx, FieldError, Input, ProblemError, RawFile, RawVar, Scene, SceneKind,
};
use super::result::{PaperCheck, Plot, SolveResult, Status, Table};
use crate::mech::hypocycloid::{ALPHA0_VARIANT1, ALPHA0_VARIANT2};
use crate::synth::hypocycloid::{
    self as hy, CoefficientModel, HypocycloidScene, OptStatus, Outcome, Settings, ZeroSearch,
    ZeroStatus,
};
use crate::synth::Var;
use crate::units::{Angle, AngularSpeed, Dimensionless, Length, Mass, Qty};
use serde::Deserialize;
use serde_json::json;
use std::collections::BTreeMap;
use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;
use std::time::Instant;

/// `[mechanism]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MechanismRaw {
    /// The paper's variant: 1 (α0 = 0) or 2 (α0 = 270°).
    pub variant: Option<i64>,
    /// α0, the orientation of the curve, instead of `variant`.
    pub orientation: Option<Qty<Angle>>,
    /// R = OO1.
    pub carrier_radius: Qty<Length>,
    /// m_B.
    pub reciprocating_mass: Qty<Mass>,
    /// n or ω of the carrier.
    pub speed: Qty<AngularSpeed>,
}

/// `[model]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ModelRaw {
    /// Highest order in the tables (default 8).
    pub orders: Option<usize>,
    /// Power of z = λ²y² of the paper-style series (default 3, the paper's y⁶).
    pub series_power: Option<usize>,
    /// Coefficients used for balancing and objectives: "exact" (default) or "series" (the
    /// paper's truncated series of power `series_power`).
    pub coefficients: Option<CoefficientModel>,
}

/// `[design]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct DesignRaw {
    /// λ = R/L.
    pub lambda: Option<RawVar<Dimensionless>>,
    /// θ = r/R.
    pub theta: Option<RawVar<Dimensionless>>,
}

/// What `objective.minimize` can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Minimize {
    /// Peak over φ of the inertia force left after the Lanchester pairs.
    PeakResidualForce,
}

/// A `{ min = …, max = … }` range of a pure number.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RangeRaw {
    /// Lower end.
    pub min: Qty<Dimensionless>,
    /// Upper end.
    pub max: Qty<Dimensionless>,
}

/// `[objective.zero_search]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ZeroSearchRaw {
    /// Order whose cosine coefficient is searched (default 4).
    pub order: Option<usize>,
    /// λ range.
    pub lambda: RangeRaw,
    /// θ range.
    pub theta: RangeRaw,
}

/// `[objective]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectiveRaw {
    /// What to minimise over the free (λ, θ).
    pub minimize: Minimize,
    /// Orders cancelled by Lanchester pairs (default [1, 2, 3]).
    pub balance_orders: Option<Vec<usize>>,
    /// Required 1 − λ·max|y_A/R| (default 1e-3).
    pub assembly_margin: Option<f64>,
    /// Minimum stroke.
    pub min_stroke: Option<Qty<Length>>,
    /// Minimum suction-phase gain (suction angle/π − 1).
    pub min_suction_gain: Option<f64>,
    /// The zero search, if wanted.
    pub zero_search: Option<ZeroSearchRaw>,
}

/// `[accuracy]`: the family's solver [`Settings`] read directly (every key optional, unknown
/// keys rejected), then validated; errors name `accuracy.<key>`.
pub type AccuracyRaw = Settings;

/// Validates the `[accuracy]` section.
fn resolve_accuracy(s: &Settings) -> Result<Settings, FieldError> {
    let s = s.clone();
    limits::check_section(Family::Hypocycloid, "accuracy", &s)?;
    s.validate().map_err(map_synth_error)?;
    Ok(s)
}

/// The whole hypocycloid file.
pub type File = RawFile<MechanismRaw, ModelRaw, DesignRaw, ObjectiveRaw, AccuracyRaw>;

/// A resolved hypocycloid scene: the synthesis scene and its numerical settings.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Resolved {
    /// The paper's variant (1 or 2), when the file names one.
    pub variant: Option<u8>,
    /// The scene.
    pub scene: HypocycloidScene,
    /// The settings (from `[accuracy]`).
    pub settings: Settings,
}

/// The problem-file key of a synthesis key (`hypocycloid.lambda` → `design.lambda`).
pub fn file_key(synth_key: &str) -> String {
    let k = synth_key;
    let mapped = match k {
        "hypocycloid.alpha0" => "mechanism.orientation",
        "hypocycloid.R" => "mechanism.carrier_radius",
        "hypocycloid.m_B" => "mechanism.reciprocating_mass",
        "hypocycloid.omega" => "mechanism.speed",
        "hypocycloid.lambda" => "design.lambda",
        "hypocycloid.theta" => "design.theta",
        "hypocycloid.orders" => "model.orders",
        "hypocycloid.series_power" => "model.series_power",
        "hypocycloid.balance_orders" => "objective.balance_orders",
        "hypocycloid.assembly_margin" => "objective.assembly_margin",
        "hypocycloid.min_stroke" => "objective.min_stroke",
        "hypocycloid.min_suction_gain" => "objective.min_suction_gain",
        "hypocycloid.zero_search.order" => "objective.zero_search.order",
        "hypocycloid.zero_search.lambda" => "objective.zero_search.lambda",
        "hypocycloid.zero_search.theta" => "objective.zero_search.theta",
        _ => {
            if let Some(rest) = k.strip_prefix("settings.") {
                return format!("accuracy.{rest}");
            }
            return k.to_string();
        }
    };
    mapped.to_string()
}

/// A synthesis value error as a problem-file error.
fn map_synth_error(e: hy::FieldError) -> FieldError {
    FieldError::new(
        file_key(&e.key),
        format!("got {}; allowed: {}", e.value, e.allowed),
    )
}

/// Reads and resolves a hypocycloid problem file (its text or its table).
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Scene, ProblemError> {
    File::resolve(ctx, input, resolve_raw, SceneKind::Hypocycloid)
}

/// A pure-number design variable: equal bounds collapse to a fixed value.
fn ratio_var(v: &Option<RawVar<Dimensionless>>, f: &str) -> Result<Var, FieldError> {
    let Some(v) = v else {
        return Err(FieldError::new(
            f,
            "missing; allowed: a pure number (fixed) or { min = …, max = … } (free)",
        ));
    };
    Ok(match v.resolve(f)? {
        Var::Free { min, max } if min == max => Var::Fixed(min),
        other => other,
    })
}

fn range(r: &RangeRaw, f: &str, lo_open: bool) -> Result<(f64, f64), FieldError> {
    let (a, b) = (r.min.si(), r.max.si());
    let lo_ok = if lo_open { a > 0.0 } else { a >= 0.0 };
    if !(lo_ok && a < b) {
        return Err(FieldError::new(
            f,
            format!(
                "got {{ min = {a}, max = {b} }}; allowed: {} min < max",
                if lo_open { "0 <" } else { "0 ≤" }
            ),
        ));
    }
    Ok((a, b))
}

/// The value checks of a hypocycloid file.
pub fn resolve_raw(raw: &File) -> Result<Resolved, FieldError> {
    check_name(&raw.name)?;
    let m = &raw.mechanism;
    // `mechanism.variant`, `model.*` and `objective.*` integers keep the scene's own checks
    // (the ranges of `io::limits`, with messages that say what each value means).
    let (variant, alpha0) =
        match (m.variant, m.orientation) {
            (Some(_), Some(_)) => {
                return Err(FieldError::new(
                    "mechanism.orientation",
                    "give either `variant` or `orientation`, not both",
                ))
            }
            (Some(1), None) => (Some(1), ALPHA0_VARIANT1),
            (Some(2), None) => (Some(2), ALPHA0_VARIANT2),
            (Some(v), None) => {
                return Err(FieldError::new(
                    "mechanism.variant",
                    format!(
                        "got {v}; allowed: 1 (α0 = 0, paper Fig. 1) or 2 (α0 = 270°, paper Fig. 3)"
                    ),
                ))
            }
            (None, Some(q)) => {
                let a = q.si();
                let v = if a.rem_euclid(TAU) == ALPHA0_VARIANT1 {
                    Some(1)
                } else if (a.rem_euclid(TAU) - ALPHA0_VARIANT2).abs() < 1e-12 {
                    Some(2)
                } else {
                    None
                };
                (v, if v == Some(2) { ALPHA0_VARIANT2 } else { a })
            }
            (None, None) => return Err(FieldError::new(
                "mechanism.variant",
                "missing; allowed: variant = 1 or 2, or orientation = an angle (e.g. \"270 deg\")",
            )),
        };
    let r = positive("mechanism.carrier_radius", m.carrier_radius.si())?;
    let m_b = positive("mechanism.reciprocating_mass", m.reciprocating_mass.si())?;
    let omega = positive("mechanism.speed", m.speed.si())?;
    let lambda = ratio_var(&raw.design.lambda, "design.lambda")?;
    let theta = ratio_var(&raw.design.theta, "design.theta")?;
    let md = &raw.model;
    let o = &raw.objective;
    let zero_search = o
        .zero_search
        .as_ref()
        .map(|z| -> Result<ZeroSearch, FieldError> {
            Ok(ZeroSearch {
                order: z.order.unwrap_or(4),
                lambda: range(&z.lambda, "objective.zero_search.lambda", true)?,
                theta: range(&z.theta, "objective.zero_search.theta", false)?,
            })
        })
        .transpose()?;
    let min_stroke = o
        .min_stroke
        .map(|q| {
            let v = q.si();
            if v >= 0.0 {
                Ok(v)
            } else {
                Err(FieldError::new(
                    "objective.min_stroke",
                    format!("must not be negative, got {v} m; allowed: a length ≥ 0"),
                ))
            }
        })
        .transpose()?;
    let balance_orders = o.balance_orders.clone().unwrap_or(vec![1, 2, 3]);
    let mut sorted = balance_orders.clone();
    sorted.sort_unstable();
    sorted.dedup();
    if sorted.len() != balance_orders.len() {
        return Err(FieldError::new(
            "objective.balance_orders",
            format!(
                "{balance_orders:?} repeats an order; allowed: distinct orders in 1..=model.orders"
            ),
        ));
    }
    let scene = HypocycloidScene {
        alpha0,
        r_carrier: r,
        lambda,
        theta,
        m_b,
        omega,
        balance_orders: sorted,
        orders: md.orders.unwrap_or(8),
        series_power: md.series_power.unwrap_or(3),
        coefficients: md.coefficients.unwrap_or_default(),
        assembly_margin: o.assembly_margin.unwrap_or(1e-3),
        min_stroke,
        min_suction_gain: o.min_suction_gain,
        zero_search,
    };
    scene.validate().map_err(map_synth_error)?;
    let settings = resolve_accuracy(&raw.accuracy)?;
    check_work(&scene, &settings)?;
    Ok(Resolved {
        variant: variant.map(|v| v as u8),
        scene,
        settings,
    })
}

/// The work budget ([`limits::check_work`]): W = E·(1 + n_grid^n + n_starts·n_iter·(n + 1) +
/// n_curve·(n_scan + 60)) + n_plot·orders, E = n_fft·log2(n_fft) + n_peak·orders the work of
/// one evaluation at the first FFT size (n_fft = `n_fft_min`; the adaptive doublings stop at
/// `n_fft_max`), n the free variables (grid, then Nelder–Mead), the zero search's columns
/// each scanned and refined (at most 60 Brent steps); the zero-search term only with a zero
/// search.
fn check_work(scene: &HypocycloidScene, s: &Settings) -> Result<(), FieldError> {
    let d = Settings::default();
    let f = |v: usize| v as f64;
    let n = [&scene.lambda, &scene.theta]
        .iter()
        .filter(|v| matches!(v, crate::synth::Var::Free { .. }))
        .count() as f64;
    let fft = f(s.n_fft_min) * f(s.n_fft_min).log2();
    let eval = fft + f(s.peak_samples) * f(scene.orders);
    let search = if n > 0.0 {
        f(s.opt_grid).powf(n) + f(s.opt_starts) * s.nm_max_iters as f64 * (n + 1.0)
    } else {
        0.0
    };
    let zeros = if scene.zero_search.is_some() {
        f(s.curve_points) * (f(s.theta_scan) + 60.0)
    } else {
        0.0
    };
    let estimate = eval * (1.0 + search + zeros) + f(s.plot_samples) * f(scene.orders);
    let t = |k, v: f64, d: f64| limits::term(k, v, d);
    limits::check_work(
        Family::Hypocycloid,
        estimate,
        "(n_fft_min·log2(n_fft_min) + peak_samples·orders)·(1 + opt_grid^n + opt_starts·nm_max_iters·(n + 1) + curve_points·(theta_scan + 60)) + plot_samples·orders",
        &[
            t("accuracy.n_fft_min", f(s.n_fft_min), f(d.n_fft_min)),
            t("accuracy.peak_samples", f(s.peak_samples), f(d.peak_samples)),
            t("model.orders", f(scene.orders), 8.0),
            t("accuracy.opt_grid", f(s.opt_grid), f(d.opt_grid)),
            t("accuracy.opt_starts", f(s.opt_starts), f(d.opt_starts)),
            t("accuracy.nm_max_iters", s.nm_max_iters as f64, d.nm_max_iters as f64),
            t("accuracy.curve_points", f(s.curve_points), f(d.curve_points)),
            t("accuracy.theta_scan", f(s.theta_scan), f(d.theta_scan)),
            t("accuracy.plot_samples", f(s.plot_samples), f(d.plot_samples)),
        ],
    )
}

/// `residual_force_peak_N` → `residual_force_peak_n` (the results' unit suffixes).
fn key(k: &str) -> String {
    match k {
        "R_m" => "carrier_radius_m".into(),
        "r_m" => "crank_arm_m".into(),
        "L_m" => "rod_length_m".into(),
        _ => match k.strip_suffix("_N") {
            Some(s) => format!("{s}_n"),
            None => k.to_string(),
        },
    }
}

fn kebab<T: serde::Serialize>(v: T) -> String {
    serde_json::to_value(v)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}

/// The result of a hypocycloid scene: solve, then shape keys, errors, sections, plots.
pub fn result(scene: &Scene, s: &Resolved) -> SolveResult {
    let mut r = SolveResult::new(scene);
    let h = &s.scene;
    r.model = BTreeMap::from([
        (
            "kinematics".into(),
            json!("exact (closed form, stable for λ → 0)"),
        ),
        (
            "coefficients".into(),
            json!(match h.coefficients {
                hy::CoefficientModel::Exact =>
                    "exact polynomial part + FFT of the O(λ³) remainder, size doubled until converged"
                        .to_string(),
                hy::CoefficientModel::Series => format!(
                    "the paper's binomial series truncated at z^{} (model.coefficients = \"series\")",
                    h.series_power
                ),
            }),
        ),
        ("variant".into(), json!(s.variant)),
        ("orientation_rad".into(), json!(h.alpha0)),
        ("orders".into(), json!(h.orders)),
        ("series_power".into(), json!(h.series_power)),
        ("balance_orders".into(), json!(h.balance_orders)),
        ("assembly_margin".into(), json!(h.assembly_margin)),
        (
            "masses".into(),
            json!("reciprocating mass m_B only (rotating masses assumed balanced)"),
        ),
    ]);
    let t0 = Instant::now();
    let out = match hy::solve(h, &s.settings) {
        Ok(o) => o,
        Err(e) => {
            r.warnings.push(map_synth_error(e).to_string());
            return r;
        }
    };
    r.timing.solve_s = t0.elapsed().as_secs_f64();
    // Nelder–Mead from a few starts is a heuristic search: `best_found` with its evidence.
    r.status = match out.status {
        OptStatus::Analysis => Status::Analysed,
        OptStatus::Converged => Status::BestFound,
        OptStatus::MaxIterations => Status::Inaccurate,
        OptStatus::Infeasible => Status::Infeasible,
    };
    if !out.coefficients.converged && matches!(r.status, Status::Analysed | Status::BestFound) {
        r.status = Status::Inaccurate;
    }
    r.search = out.search.clone();
    let mut detail = kebab(out.status);
    if let Some(d) = &out.degenerate {
        r.status = Status::Degenerate;
        let _ = write!(detail, "; degenerate: {d}");
    }
    if let Some(z) = &out.zero_search {
        let _ = write!(detail, "; zero search: {}", kebab(z.status));
    }
    r.status_detail = Some(detail);
    r.method = if out.zero_search.is_some() {
        out.method.clone()
    } else {
        // No zero search ran: drop its part of the method text.
        out.method
            .split("; ")
            .filter(|p| !p.starts_with("zero search"))
            .collect::<Vec<_>>()
            .join("; ")
    };
    r.warnings.extend(out.warnings.iter().cloned());
    for (k, v) in &out.design {
        r.design.insert(key(k), *v);
    }
    for (k, v) in &out.objectives {
        r.objectives.insert(key(k), *v);
    }
    for (k, v) in &out.errors {
        r.errors.insert(key(k), *v);
    }
    for (k, v) in &out.derived {
        r.derived.insert(key(k), *v);
    }
    r.derived.insert("omega_rad_s".into(), h.omega);
    let c = &out.coefficients;
    let max_b = c.b[1..=6.min(h.orders)]
        .iter()
        .fold(0.0f64, |m, b| m.max(b.abs()));
    r.derived.insert("max_abs_b1_b6".into(), max_b);
    let f1 = c.a[1].hypot(c.b[1]);
    let f3 = 9.0 * c.a[3].hypot(c.b[3]);
    r.derived
        .insert("force_ratio_order3_to_order1".into(), f3 / f1);

    // Family sections.
    let amp: Vec<f64> = std::iter::once(0.0)
        .chain(c.rows.iter().map(|row| row.force_amplitude))
        .collect();
    r.extra.insert(
        "coefficients".into(),
        json!({
            "a": c.a, "b": c.b, "error": c.error,
            "a_series": c.a_series, "b_series": c.b_series,
            "force_amplitude_n": amp,
            "series_power": c.series_power, "n_fft": c.n_fft, "converged": c.converged,
        }),
    );
    r.extra.insert(
        "balancing".into(),
        json!(out
            .balancing
            .iter()
            .map(|p| json!({
                "order": p.order,
                "shaft_speed_rad_s": p.speed,
                "static_moment_kgm": p.static_moment,
                "phase_co_rad": p.phase_co,
                "phase_counter_rad": p.phase_counter,
            }))
            .collect::<Vec<_>>()),
    );
    r.extra.insert("zero_curve".into(), json!(out.zero_curve));
    r.extra
        .insert("zero_curve_series".into(), json!(out.zero_curve_series));
    if let Some(z) = &out.zero_search {
        r.extra.insert(
            "zero_search".into(),
            json!({
                "order": z.order,
                "status": z.status,
                "roots": z.roots.len(),
                "single_valued": z.single_valued,
                "sign": z.sign,
                "max_abs_at_root": z.max_abs_at_root,
                "min_abs": z.grid_min_abs.map(|g| g.value.abs()),
                "min_abs_lambda": z.grid_min_abs.map(|g| g.lambda),
                "min_abs_theta": z.grid_min_abs.map(|g| g.theta),
                "min_abs_value": z.grid_min_abs.map(|g| g.value),
                "reason": z.reason,
                "evaluations": z.evals,
            }),
        );
    }
    r.paper = paper_checks(&out);

    // Tables and plots.
    r.tables = tables(&out);
    for p in [coefficient_plot(scene, &out), force_plot(scene, &out)] {
        match p {
            Ok(p) => r.plots.push(p),
            Err(e) => r.warnings.push(format!("plot failed: {e}")),
        }
    }
    if out.zero_search.is_some() {
        match map_plot(scene, &out) {
            Ok(p) => r.plots.insert(0, p),
            Err(e) => r.warnings.push(format!("plot failed: {e}")),
        }
    }
    r
}

/// The family's paper checks with result keys (the paper prints no numbers: each check is
/// the paper's method or claim against the exact computation).
fn paper_checks(out: &Outcome) -> Vec<PaperCheck> {
    out.paper
        .iter()
        .map(|p| {
            let q = p.quantity.as_str();
            let key = if q.contains("conjecture") {
                match out.zero_search.as_ref().map(|z| z.status) {
                    Some(ZeroStatus::Found) => "zero_search.max_abs_at_root".into(),
                    _ => "zero_search.min_abs".into(),
                }
            } else if let Some(i) = q
                .strip_prefix('a')
                .and_then(|t| t.chars().next())
                .and_then(|ch| ch.to_digit(10))
            {
                format!("coefficients.a.{i}")
            } else if q.starts_with("C1^I ") {
                "coefficients.a.1".into()
            } else if q.starts_with("C2^II") {
                "coefficients.b.2".into()
            } else if q.starts_with("b1..b6") {
                "derived.max_abs_b1_b6".into()
            } else if q.starts_with("|Φ3|/|Φ1|") {
                "derived.force_ratio_order3_to_order1".into()
            } else {
                String::new()
            };
            PaperCheck {
                quantity: q.to_string(),
                key,
                paper: p.paper,
                computed: Some(p.computed),
                diff_pct: (p.paper != 0.0).then(|| 100.0 * (p.computed - p.paper) / p.paper.abs()),
                note: p.note.clone(),
            }
        })
        .collect()
}

fn csv_num(v: f64) -> String {
    if v.is_finite() {
        format!("{v:e}")
    } else {
        String::new()
    }
}

fn tables(out: &Outcome) -> Vec<Table> {
    let mut t = Vec::new();
    let c = &out.coefficients;
    let mut csv = String::from(
        "order,a,b,error,a_series,b_series,a_series_minus_a,b_series_minus_b,force_amplitude_n,balanced\n",
    );
    for row in &c.rows {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{}",
            row.order,
            csv_num(row.a),
            csv_num(row.b),
            csv_num(row.error),
            csv_num(row.a_series),
            csv_num(row.b_series),
            csv_num(row.a_series - row.a),
            csv_num(row.b_series - row.b),
            csv_num(row.force_amplitude),
            row.balanced
        );
    }
    t.push(Table {
        suffix: "coefficients".into(),
        caption: format!(
            "Fourier coefficients of S/R by order: exact (FFT, n = {}) and the binomial series to power {}",
            c.n_fft, c.series_power
        ),
        csv,
    });
    let fc = &out.force_curves;
    let mut csv = String::from("phi_rad,unbalanced_force_n,residual_force_n,piston_position_m\n");
    for j in 0..fc.phi.len() {
        let _ = writeln!(
            csv,
            "{},{},{},{}",
            csv_num(fc.phi[j]),
            csv_num(fc.unbalanced[j]),
            csv_num(fc.residual[j]),
            csv_num(fc.position[j])
        );
    }
    t.push(Table {
        suffix: "force".into(),
        caption: "Inertia force of m_B over one turn, unbalanced and after the Lanchester pairs"
            .into(),
        csv,
    });
    if let Some(z) = &out.zero_search {
        let mut csv = String::from(
            "lambda,theta,value,value_error,bracket_theta_lo,bracket_theta_hi,value_lo,value_hi,series_theta,series_value\n",
        );
        for r in &z.roots {
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{},{},{},{},{}",
                csv_num(r.lambda),
                csv_num(r.theta),
                csv_num(r.value),
                csv_num(r.value_error),
                csv_num(r.bracket.0),
                csv_num(r.bracket.1),
                csv_num(r.f_bracket.0),
                csv_num(r.f_bracket.1),
                r.series_theta.map(csv_num).unwrap_or_default(),
                csv_num(r.series_value)
            );
        }
        t.push(Table {
            suffix: "zero-curve".into(),
            caption: format!(
                "Zero set of a{} over (λ, θ): each root with its bracket and the truncated series' root",
                z.order
            ),
            csv,
        });
        let mut csv = format!("lambda,theta,a{}\n", z.order);
        for (i, l) in z.map.lambda.iter().enumerate() {
            for (j, th) in z.map.theta.iter().enumerate() {
                let _ = writeln!(
                    csv,
                    "{},{},{}",
                    csv_num(*l),
                    csv_num(*th),
                    z.map.value[i][j].map(csv_num).unwrap_or_default()
                );
            }
        }
        t.push(Table {
            suffix: "map".into(),
            caption: format!(
                "a{} on the search grid (empty where the mechanism cannot assemble)",
                z.order
            ),
            csv,
        });
    }
    t
}

fn map_plot(scene: &Scene, out: &Outcome) -> Result<Plot, String> {
    let z = out.zero_search.as_ref().ok_or("no zero search")?;
    let m = &z.map;
    let grid = Grid {
        x: m.lambda.clone(),
        y: m.theta.clone(),
        values: (0..m.theta.len())
            .map(|j| {
                (0..m.lambda.len())
                    .map(|i| m.value[i][j].unwrap_or(f64::NAN))
                    .collect()
            })
            .collect(),
    };
    let pts = |v: &[hy::ZeroPoint]| -> Vec<(f64, f64)> {
        // Break the line where consecutive roots are not neighbours of one branch.
        let mut p = Vec::new();
        let dl = if m.lambda.len() > 1 {
            m.lambda[1] - m.lambda[0]
        } else {
            1.0
        };
        for (k, q) in v.iter().enumerate() {
            if k > 0 {
                let prev = v[k - 1];
                if (q.lambda - prev.lambda).abs() > 1.5 * dl || (q.theta - prev.theta).abs() > 0.1 {
                    p.push((f64::NAN, f64::NAN));
                }
            }
            p.push((q.lambda, q.theta));
        }
        p
    };
    // Fixed slots, so that each item keeps its colour (red, white, black, magenta) whether
    // or not there is a zero curve.
    let mut series = vec![
        Series::line(
            if out.zero_curve.is_empty() {
                format!("a{} = 0 (exact): none in the box", z.order)
            } else {
                format!("a{} = 0 (exact)", z.order)
            },
            pts(&out.zero_curve),
        ),
        Series::line(
            format!(
                "a{} = 0 (paper's series to z^{}){}",
                z.order,
                out.coefficients.series_power,
                if out.zero_curve_series.is_empty() {
                    ": none"
                } else {
                    ""
                }
            ),
            pts(&out.zero_curve_series),
        ),
    ];
    let l = out.design.get("lambda").copied().unwrap_or(f64::NAN);
    let t = out.design.get("theta").copied().unwrap_or(f64::NAN);
    series.push(Series::marker(
        format!("design of least residual force (λ = {l:.3}, θ = {t:.3})"),
        vec![(l, t)],
    ));
    if z.status != ZeroStatus::Found {
        if let Some(g) = z.grid_min_abs {
            series.push(Series::marker(
                format!(
                    "min |a{}| = {:.2e} at (λ, θ) = ({}, {})",
                    z.order,
                    g.value.abs(),
                    g.lambda,
                    g.theta
                ),
                vec![(g.lambda, g.theta)],
            ));
        }
    }
    let svg = plot::heat_map(
        &Panel {
            title: format!(
                "{}: a{o} of S/R, colour sign(a{o})·log10(1 + |a{o}|/1e-4)",
                scene.name,
                o = z.order
            ),
            x_label: "λ = R/L (–)".into(),
            y_label: "θ = r/R (–)".into(),
            series,
            equal_aspect: false,
        },
        &grid,
        Some(1e-4),
        900,
        620,
    )?;
    Ok(Plot {
        suffix: "c4-map".into(),
        caption: format!("a{} over (λ, θ) with its zero curve", z.order),
        svg,
    })
}

/// An invisible one-point series that raises the top of a panel by a third of its span,
/// so that the legend (upper right) does not cover the data. A line with one point draws
/// nothing and has no legend entry.
fn headroom(series: &[Series]) -> Series {
    let ys = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (lo, hi, x) = ys.fold((f64::INFINITY, f64::NEG_INFINITY, 0.0), |(lo, hi, _), p| {
        (lo.min(p.1), hi.max(p.1), p.0)
    });
    let top = if hi > lo {
        hi + 0.4 * (hi - lo)
    } else {
        f64::NAN
    };
    Series::line("", vec![(x, top)])
}

fn coefficient_plot(scene: &Scene, out: &Outcome) -> Result<Plot, String> {
    let c = &out.coefficients;
    // Values below the coefficient's own error estimate are zero to working accuracy (e.g.
    // the b_i of variant 1, the odd a_i of variant 2): not drawn.
    let lg = |v: f64, i: usize| {
        if v.abs() > c.error[i] {
            v.abs().log10()
        } else {
            f64::NAN
        }
    };
    let by_order = |f: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> {
        (1..c.a.len()).map(|i| (i as f64, lg(f(i), i))).collect()
    };
    let p = c.series_power;
    // Series crosses first, exact dots after: a dot inside its cross is agreement.
    let mut left = vec![Series::marker(
        format!("|a_i| series to z^{p}"),
        by_order(&|i| c.a_series[i]),
    )];
    let has_b = (1..c.b.len()).any(|i| c.b[i].abs() > c.error[i]);
    if has_b {
        left.push(Series::marker(
            format!("|b_i| series to z^{p}"),
            by_order(&|i| c.b_series[i]),
        ));
    }
    left.push(Series::points("|a_i| exact", by_order(&|i| c.a[i])));
    if has_b {
        left.push(Series::points("|b_i| exact", by_order(&|i| c.b[i])));
    }
    left.push(headroom(&left));
    let mut right = vec![Series::marker(
        "|a_i series − a_i|",
        by_order(&|i| c.a_series[i] - c.a[i]),
    )];
    if has_b {
        right.push(Series::marker(
            "|b_i series − b_i|",
            by_order(&|i| c.b_series[i] - c.b[i]),
        ));
    }
    right.push(Series::line(
        "error estimate of the exact a_i, b_i",
        (1..c.a.len())
            .map(|i| (i as f64, c.error[i].log10()))
            .collect(),
    ));
    right.push(headroom(&right));
    let svg = plot::panels(
        &[
            Panel {
                title: format!("{}: Fourier coefficients of S/R", scene.name),
                x_label: "order i (–)".into(),
                y_label: "log10 |coefficient| (–)".into(),
                series: left,
                equal_aspect: false,
            },
            Panel {
                title: format!("paper's series (to z^{p}) − exact"),
                x_label: "order i (–)".into(),
                y_label: "log10 |difference| (–)".into(),
                series: right,
                equal_aspect: false,
            },
        ],
        560,
        460,
    )?;
    Ok(Plot {
        suffix: "coefficients".into(),
        caption: "Coefficients of S/R: exact against the paper-style truncated series (values below the error estimate not drawn)".into(),
        svg,
    })
}

fn force_plot(scene: &Scene, out: &Outcome) -> Result<Plot, String> {
    let fc = &out.force_curves;
    let deg: Vec<f64> = fc.phi.iter().map(|p| p * 180.0 / PI).collect();
    let zip =
        |v: &[f64]| -> Vec<(f64, f64)> { deg.iter().copied().zip(v.iter().copied()).collect() };
    let orders: Vec<String> = out.balancing.iter().map(|p| p.order.to_string()).collect();
    let pos_mm: Vec<f64> = fc.position.iter().map(|x| x * 1e3).collect();
    let mut force_series = vec![
        Series::line("unbalanced", zip(&fc.unbalanced)),
        Series::line(
            if orders.is_empty() {
                "residual (nothing balanced)".to_string()
            } else {
                format!("after balancing orders {}", orders.join(", "))
            },
            zip(&fc.residual),
        ),
    ];
    force_series.push(headroom(&force_series));
    let mut pos_series = vec![Series::line("S − L", zip(&pos_mm))];
    pos_series.push(headroom(&pos_series));
    let svg = plot::panels(
        &[
            Panel {
                title: format!("{}: inertia force of m_B", scene.name),
                x_label: "carrier angle φ (deg)".into(),
                y_label: "force (N)".into(),
                series: force_series,
                equal_aspect: false,
            },
            Panel {
                title: "piston position".into(),
                x_label: "carrier angle φ (deg)".into(),
                y_label: "S − L (mm)".into(),
                series: pos_series,
                equal_aspect: false,
            },
        ],
        560,
        460,
    )?;
    Ok(Plot {
        suffix: "force".into(),
        caption: "Inertia force of the reciprocating mass over one turn, and the piston path"
            .into(),
        svg,
    })
}
