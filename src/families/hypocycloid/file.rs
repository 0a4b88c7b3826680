//! The hypocycloid problem file — its raw sections and their resolution into a checked
//! [`crate::families::hypocycloid::synth::HypocycloidScene`] with its [`Settings`] (every field
//! documented in `docs/problem-files.md`) — and the shaping of its outcome into a result
//! (keys in `docs/results.md`): the order coefficients of S/R, the Lanchester balancing, the
//! (λ, θ) optimisation and the zero search of the fourth-order coefficient.

use crate::families::hypocycloid::model::{ALPHA0_VARIANT1, ALPHA0_VARIANT2};
use crate::families::hypocycloid::synth::{
    CoefficientModel, HypocycloidScene, Settings, ZeroSearch,
};
use crate::problem::limits::{self, c, Count};
use crate::problem::{
    check_name, positive, Ctx, FieldError, Input, ProblemError, RawFile, RawVar, Resolved,
};
use crate::synth::Var;
use crate::units::{Angle, AngularSpeed, Dimensionless, Length, Mass, Qty};
use serde::Deserialize;
use std::f64::consts::TAU;

/// `[mechanism]`.
/// The `family = "…"` value of this family's files.
pub const FAMILY: &str = "hypocycloid";

/// The work budget of one scene (see [`limits::check_work`] and `check_work` below):
/// every single integer setting at its maximum passes on the shipped files, their products
/// do not, so one machine runs in seconds and can neither stall a batch nor exhaust memory.
pub const WORK_BUDGET: f64 = 5e8;

/// The integer keys of this family's file and their ranges (see [`limits`]).
pub const COUNTS: &[Count] = &[
    c("mechanism.variant", 1, 2),
    c("model.orders", 6, 64),
    c("model.series_power", 1, 32),
    c("objective.balance_orders", 1, 64),
    c("objective.zero_search.order", 1, 64),
    c("accuracy.n_fft_min", 16, 1 << 20),
    c("accuracy.n_fft_max", 16, 1 << 20),
    c("accuracy.curve_points", 2, 400),
    c("accuracy.theta_scan", 4, 400),
    c("accuracy.peak_samples", 16, 4096),
    c("accuracy.opt_grid", 3, 40),
    c("accuracy.opt_starts", 1, 64),
    c("accuracy.nm_max_iters", 1, 5000),
    c("accuracy.plot_samples", 8, 100_000),
];

#[derive(Debug, Deserialize, schemars::JsonSchema)]
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
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
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
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignRaw {
    /// λ = R/L.
    pub lambda: Option<RawVar<Dimensionless>>,
    /// θ = r/R.
    pub theta: Option<RawVar<Dimensionless>>,
}

/// What `objective.minimize` can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Minimize {
    /// Peak over φ of the inertia force left after the Lanchester pairs.
    PeakResidualForce,
}

/// A `{ min = …, max = … }` range of a pure number.
#[derive(Debug, Clone, Copy, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RangeRaw {
    /// Lower end.
    pub min: Qty<Dimensionless>,
    /// Upper end.
    pub max: Qty<Dimensionless>,
}

/// `[objective.zero_search]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
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
#[derive(Debug, Deserialize, schemars::JsonSchema)]
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
    /// Shortest crank arm r = θR the machine may have: raises the lower bound of a free θ to
    /// r_min/R (a design below it is no longer a hypocycloidal machine).
    pub min_crank_arm: Option<Qty<Length>>,
    /// Longest rod L = R/λ the machine may have: raises the lower bound of a free λ to
    /// R/L_max.
    pub max_rod_length: Option<Qty<Length>>,
    /// The zero search, if wanted.
    pub zero_search: Option<ZeroSearchRaw>,
}

/// `[accuracy]`: the family's solver [`Settings`] read directly (every key optional, unknown
/// keys rejected), then validated; errors name `accuracy.<key>`.
pub type AccuracyRaw = Settings;

/// Validates the `[accuracy]` section.
fn resolve_accuracy(s: &Settings) -> Result<Settings, FieldError> {
    let s = s.clone();
    limits::check_section(COUNTS, "accuracy", &s)?;
    s.validate()?;
    Ok(s)
}

/// The whole hypocycloid file.
pub type File = RawFile<MechanismRaw, ModelRaw, DesignRaw, ObjectiveRaw, AccuracyRaw>;

/// A resolved hypocycloid scene: the synthesis scene and its numerical settings.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct HypocycloidProblem {
    /// The paper's variant (1 or 2), when the file names one.
    pub variant: Option<u8>,
    /// The scene.
    pub scene: HypocycloidScene,
    /// The settings (from `[accuracy]`).
    pub settings: Settings,
}

/// Reads and resolves a hypocycloid problem file (its text or its table).
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Resolved<HypocycloidProblem>, ProblemError> {
    File::resolve(ctx, input, resolve_raw)
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

/// A ratio raised to at least `lo` (from the machine limit `why`): a free range's lower bound
/// moves up; a fixed value or a range wholly below `lo` is an error naming both keys.
fn at_least(v: Var, lo: Option<f64>, f: &str, why: &str) -> Result<Var, FieldError> {
    let Some(lo) = lo else { return Ok(v) };
    match v {
        Var::Fixed(x) if x < lo => Err(FieldError::new(
            f,
            format!("{x} is below {lo:.6}, the least value {why} allows"),
        )),
        Var::Free { max, .. } if max < lo => Err(FieldError::new(
            f,
            format!("its range ends at {max}, below {lo:.6}, the least value {why} allows"),
        )),
        Var::Free { min, max } => Ok(if lo >= max {
            Var::Fixed(max)
        } else {
            Var::Free {
                min: min.max(lo),
                max,
            }
        }),
        fixed => Ok(fixed),
    }
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
pub fn resolve_raw(raw: &File) -> Result<HypocycloidProblem, FieldError> {
    check_name(&raw.name)?;
    let m = &raw.mechanism;
    // `mechanism.variant`, `model.*` and `objective.*` integers keep the scene's own checks
    // (the ranges of `problem::limits`, with messages that say what each value means).
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
    let o = &raw.objective;
    let min_crank_arm = o
        .min_crank_arm
        .map(|q| positive("objective.min_crank_arm", q.si()))
        .transpose()?;
    let max_rod_length = o
        .max_rod_length
        .map(|q| positive("objective.max_rod_length", q.si()))
        .transpose()?;
    // The machine's limits as lower bounds of the ratios: θ ≥ r_min/R, λ ≥ R/L_max.
    let lambda = at_least(
        ratio_var(&raw.design.lambda, "design.lambda")?,
        max_rod_length.map(|l| r / l),
        "design.lambda",
        "objective.max_rod_length",
    )?;
    let theta = at_least(
        ratio_var(&raw.design.theta, "design.theta")?,
        min_crank_arm.map(|a| a / r),
        "design.theta",
        "objective.min_crank_arm",
    )?;
    let md = &raw.model;
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
        min_crank_arm,
        max_rod_length,
        zero_search,
    };
    scene.validate()?;
    let settings = resolve_accuracy(&raw.accuracy)?;
    check_work(&scene, &settings)?;
    Ok(HypocycloidProblem {
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
        WORK_BUDGET,
        FAMILY,
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
