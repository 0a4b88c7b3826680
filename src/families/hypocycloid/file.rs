//! The hypocycloid problem file — its raw sections and their resolution into a checked
//! [`crate::families::hypocycloid::synth::HypocycloidScene`] with its [`Settings`] (every field
//! documented in `docs/problem-files.md`) — and the shaping of its outcome into a result
//! (keys in `docs/results.md`): the order coefficients of S/R, the Lanchester balancing, the
//! (λ, θ) optimisation and the zero search of the fourth-order coefficient.

use crate::families::hypocycloid::balance::{DynamicsSpec, RotatingDesign, RotatingGoal};
use crate::families::hypocycloid::dynamics::{RotatingMasses, ShaftLayout};
use crate::families::hypocycloid::gas::{GasCycle, LoadCase};
use crate::families::hypocycloid::load_cases::{MAX_CASE_NAME, MAX_LOAD_CASES};
use crate::families::hypocycloid::model::{ALPHA0_VARIANT1, ALPHA0_VARIANT2};
use crate::families::hypocycloid::synth::{
    CoefficientModel, HypocycloidScene, Settings, ZeroSearch,
};
use crate::problem::limits::{self, c, Count};
use crate::problem::{
    check_name, positive, Ctx, FieldError, Input, Pair, ProblemError, RawFile, RawVar, Resolved,
};
use crate::synth::Var;
use crate::units::{Angle, AngularSpeed, Dimensionless, Inertia, Length, Mass, Pressure, Qty};
use serde::Deserialize;
use std::f64::consts::TAU;

/// `[mechanism]`.
/// The `family = "…"` value of this family's files.
pub const FAMILY: &str = "hypocycloid";

/// The problem file `cwsynth new` prints: the shipped `problems/hypocycloid-compressor.toml`, a design with no
/// paper's numbers to check.
pub const TEMPLATE: &str = include_str!("../../../problems/hypocycloid-compressor.toml");

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
    /// The planet carrier OO1 as a body (for the rotating-mass counterweights).
    pub carrier: Option<BodyRaw>,
    /// The planet gear with its crank arm O1A as a body.
    pub planet: Option<BodyRaw>,
    /// The rod AB as a body.
    pub rod: Option<RodRaw>,
    /// The compressor cycle acting on the piston (gas force and drive torque).
    pub gas: Option<GasRaw>,
    /// Where the Lanchester shafts sit (their couples).
    pub lanchester: Option<ShaftsRaw>,
    /// The drive: motor, flywheel and the coefficient of speed fluctuation to meet
    /// (`[mechanism.drive]`, the machine as it runs).
    pub drive: Option<crate::problem::drive::DriveRaw>,
    /// Named load cases (`[[mechanism.load_cases]]`): other pressures of the gas cycle, each
    /// solved beside the nominal `[mechanism.gas]` (issue 33, `load_cases.rs`).
    #[serde(default)]
    #[schemars(length(max = MAX_LOAD_CASES))]
    pub load_cases: Vec<LoadCaseRaw>,
    /// The operating envelope (`[mechanism.envelope]`): a speed band, every load case solved
    /// at both its ends too (issue 33, `load_cases.rs`).
    pub envelope: Option<EnvelopeRaw>,
}

/// `[mechanism.envelope]` of the compressor: the speed band.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EnvelopeRaw {
    /// The speed band `{ min, max }`: every case (the nominal cycle and each load case) at
    /// both ends too; the flywheel then meets `cs` over the band.
    pub speed: Option<crate::problem::envelope::SpeedRangeRaw>,
}

/// `[[mechanism.load_cases]]`: a named case of the compressor cycle, the nominal
/// `[mechanism.gas]` with the pressures it changes (at least one of them).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LoadCaseRaw {
    /// Its name in the result: non-empty, unique, not `"nominal"` (the `[mechanism.gas]` case).
    #[schemars(length(max = MAX_CASE_NAME))]
    pub name: String,
    /// p_s of the case (absolute, > 0); default the nominal one.
    pub suction_pressure: Option<Qty<Pressure>>,
    /// p_d of the case (absolute, > p_s); default the nominal one.
    pub discharge_pressure: Option<Qty<Pressure>>,
}

/// `[mechanism.carrier]` / `[mechanism.planet]`: a body turning with its frame.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BodyRaw {
    /// Its mass (≥ 0).
    pub mass: Qty<Mass>,
    /// Its centroid in the body's frame, [x, y]: the carrier's from O with x along OO1, the
    /// planet's from O1 with x along the crank arm O1A.
    pub centroid: Pair<Qty<Length>>,
}

/// `[mechanism.rod]`: the rod AB. Its share at B, mass·centroid/L, is part of
/// `reciprocating_mass` (which must be at least that); the rest, at A, turns with the planet.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RodRaw {
    /// Its mass (≥ 0).
    pub mass: Qty<Mass>,
    /// AG, the distance of its centroid from the crank pin A along AB (0 ≤ AG ≤ L).
    pub centroid: Qty<Length>,
    /// I_G, its inertia about its centroid (> 0); absent: the two-point rod, I_G = m·AG·GB.
    pub inertia: Option<Qty<Inertia>>,
}

/// `[mechanism.gas]`: an ideal single-acting compressor cycle, head at +x (top dead centre
/// at the largest S).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GasRaw {
    /// Bore D of the cylinder.
    pub bore: Qty<Length>,
    /// Clearance volume over the swept volume, ε = V_c/V_s (> 0).
    pub clearance_ratio: f64,
    /// Suction pressure p_s (absolute, > 0).
    pub suction_pressure: Qty<Pressure>,
    /// Discharge pressure p_d (absolute, > p_s).
    pub discharge_pressure: Qty<Pressure>,
    /// Polytropic exponent n of compression and re-expansion, 1 ≤ n ≤ 2.
    pub polytropic_exponent: f64,
    /// Pressure behind the piston (absolute); default the suction pressure.
    pub back_pressure: Option<Qty<Pressure>>,
}

/// `[mechanism.lanchester]`: the position of every Lanchester pair's two shafts.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ShaftsRaw {
    /// e, the offset of the shafts from the piston line (signed, +y).
    pub offset: Qty<Length>,
    /// d, the distance between a pair's two shafts along the piston line (≥ 0; default 0).
    /// Shafts one above the other, symmetric about the offset line, are d = 0.
    pub spacing: Option<Qty<Length>>,
}

/// `[design.rotating]`: the counterweights of the rotating masses.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RotatingRaw {
    /// ρ1, the centroid radius of the carrier counterweight from O (> 0).
    pub carrier_radius: Qty<Length>,
    /// ρ2, the centroid radius of the planet counterweight from O1 (> 0).
    pub planet_radius: Qty<Length>,
    /// "rotating-force" (default: cancel the rotating parts' force exactly, closed form) or
    /// "peak-shaking-force" (also minimise the peak of the whole shaking force with the
    /// reciprocating force left after the Lanchester pairs: certified minimax).
    pub minimize: Option<RotatingGoal>,
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
    /// The counterweights of the rotating masses (needs `[mechanism.carrier]`,
    /// `[mechanism.planet]` or `[mechanism.rod]`).
    pub rotating: Option<RotatingRaw>,
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
    /// The rotating masses, counterweights, gas cycle and shafts, if the file gives them.
    pub dynamics: DynamicsSpec,
}

/// Reads and resolves a hypocycloid problem file (its text or its table).
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Resolved<HypocycloidProblem>, ProblemError> {
    File::resolve(ctx, input, resolve_raw)
}

/// A pure-number design variable: equal bounds collapse to a fixed value.
fn ratio_var(v: &Option<RawVar<Dimensionless>>, f: &str, lo_open: bool) -> Result<Var, FieldError> {
    let Some(v) = v else {
        return Err(FieldError::new(
            f,
            "missing; allowed: a pure number (fixed) or { min = …, max = … } (free)",
        ));
    };
    let var = match v.resolve(f)? {
        Var::Free { min, max } if min == max => Var::Fixed(min),
        other => other,
    };
    // λ = R/L > 0, θ = r/R ≥ 0: a negative ratio is no machine.
    let lo = var.bounds().0;
    if (lo_open && lo <= 0.0) || lo < 0.0 {
        return Err(FieldError::new(
            f,
            format!(
                "{lo} is out of range; allowed: {}",
                if lo_open { "> 0" } else { "≥ 0" }
            ),
        ));
    }
    Ok(var)
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
        ratio_var(&raw.design.lambda, "design.lambda", true)?,
        max_rod_length.map(|l| r / l),
        "design.lambda",
        "objective.max_rod_length",
    )?;
    let theta = at_least(
        ratio_var(&raw.design.theta, "design.theta", false)?,
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
    let dynamics = resolve_dynamics(raw)?;
    Ok(HypocycloidProblem {
        variant: variant.map(|v| v as u8),
        scene,
        settings,
        dynamics,
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

/// A value ≥ 0.
fn non_negative(key: &str, v: f64) -> Result<f64, FieldError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(FieldError::new(key, format!("got {v}; allowed: ≥ 0")))
    }
}

/// The optional sections of the rotating masses, counterweights, gas cycle and shafts.
fn resolve_dynamics(raw: &File) -> Result<DynamicsSpec, FieldError> {
    let m = &raw.mechanism;
    let body = |b: &Option<BodyRaw>, key: &str| -> Result<(f64, [f64; 2]), FieldError> {
        match b {
            None => Ok((0.0, [0.0; 2])),
            Some(b) => Ok((
                non_negative(&format!("{key}.mass"), b.mass.si())?,
                [b.centroid[0].si(), b.centroid[1].si()],
            )),
        }
    };
    let (mc, cc) = body(&m.carrier, "mechanism.carrier")?;
    let (mp, cp) = body(&m.planet, "mechanism.planet")?;
    let masses = if m.carrier.is_some() || m.planet.is_some() || m.rod.is_some() {
        let (mr, ag, ig) = match &m.rod {
            None => (0.0, 0.0, None),
            Some(r) => (
                non_negative("mechanism.rod.mass", r.mass.si())?,
                non_negative("mechanism.rod.centroid", r.centroid.si())?,
                r.inertia
                    .map(|i| positive("mechanism.rod.inertia", i.si()))
                    .transpose()?,
            ),
        };
        Some(RotatingMasses {
            carrier_mass: mc,
            carrier_centroid: cc,
            planet_mass: mp,
            planet_centroid: cp,
            rod_mass: mr,
            rod_centroid: ag,
            rod_inertia: ig,
        })
    } else {
        None
    };
    let design = match &raw.design.rotating {
        None => None,
        Some(d) => {
            if masses.is_none() {
                return Err(FieldError::new(
                    "design.rotating",
                    "needs the rotating masses: give [mechanism.carrier], [mechanism.planet] or [mechanism.rod]",
                ));
            }
            Some(RotatingDesign {
                carrier_radius: positive("design.rotating.carrier_radius", d.carrier_radius.si())?,
                planet_radius: positive("design.rotating.planet_radius", d.planet_radius.si())?,
                minimize: d.minimize.unwrap_or_default(),
            })
        }
    };
    let gas = match &m.gas {
        None => None,
        Some(g) => {
            let (ps, pd) = pressures(
                ("mechanism.gas.suction_pressure", g.suction_pressure.si()),
                (
                    "mechanism.gas.discharge_pressure",
                    g.discharge_pressure.si(),
                ),
            )?;
            let n = g.polytropic_exponent;
            if !(1.0..=2.0).contains(&n) {
                return Err(FieldError::new(
                    "mechanism.gas.polytropic_exponent",
                    format!("got {n}; allowed: 1 ≤ n ≤ 2"),
                ));
            }
            let eps = g.clearance_ratio;
            if !(eps > 0.0 && eps <= 1.0) {
                return Err(FieldError::new(
                    "mechanism.gas.clearance_ratio",
                    format!("got {eps}; allowed: 0 < ε ≤ 1 (V_c over the swept volume)"),
                ));
            }
            Some(GasCycle {
                bore: positive("mechanism.gas.bore", g.bore.si())?,
                clearance_ratio: eps,
                suction: ps,
                discharge: pd,
                exponent: n,
                back: match g.back_pressure {
                    Some(b) => non_negative("mechanism.gas.back_pressure", b.si())?,
                    None => ps,
                },
            })
        }
    };
    let back_given = m.gas.as_ref().is_some_and(|g| g.back_pressure.is_some());
    let load_cases = resolve_load_cases(&m.load_cases, gas.as_ref(), back_given)?;
    let shafts = match &m.lanchester {
        None => None,
        Some(l) => {
            let e = l.offset.si();
            Some(ShaftLayout {
                offset: e,
                spacing: match l.spacing {
                    Some(d) => non_negative("mechanism.lanchester.spacing", d.si())?,
                    None => 0.0,
                },
            })
        }
    };
    let drive = m
        .drive
        .as_ref()
        .map(crate::problem::drive::resolve)
        .transpose()?;
    let speed_band =
        crate::problem::envelope::speed_band(m.envelope.as_ref().and_then(|e| e.speed.as_ref()))?;
    let line = drive
        .as_ref()
        .is_some_and(|d| d.motor != crate::dynamics::Motor::ConstantTorque);
    if speed_band.is_some() && line {
        return Err(FieldError::new(
            "mechanism.envelope.speed",
            "a speed band is the speed the machine is driven at (a variable-frequency drive, a constant-torque motor): with mechanism.drive.motor's torque–speed characteristic the motor sets the mean speed itself; leave `motor` out",
        ));
    }
    if speed_band.is_some() && gas.is_none() {
        return Err(FieldError::new(
            "mechanism.envelope.speed",
            "a speed band needs [mechanism.gas] (without a gas load every figure scales with ω², and the flywheel for a Cs does not depend on the speed)",
        ));
    }
    Ok(DynamicsSpec {
        masses,
        design,
        gas,
        shafts,
        drive,
        load_cases,
        speed_band,
    })
}

/// The pressures (p_s, p_d) of a cycle, each given as (its key, its value in Pa): p_s > 0 and
/// p_d > p_s, finite; an error names the key of the pressure that breaks it (p_d's when both
/// are given as keys).
fn pressures(ps: (&str, f64), pd: (&str, f64)) -> Result<(f64, f64), FieldError> {
    let s = positive(ps.0, ps.1)?;
    let d = pd.1;
    if !(d > s && d.is_finite()) {
        return Err(FieldError::new(
            pd.0,
            format!("got p_d = {d} Pa with p_s = {s} Pa; allowed: a discharge pressure above the suction pressure"),
        ));
    }
    Ok((s, d))
}

/// `[[mechanism.load_cases]]` over the nominal cycle: at most [`MAX_LOAD_CASES`], each named
/// (non-empty, at most [`MAX_CASE_NAME`] characters, no comma, quote or control character,
/// unique, not [`crate::problem::envelope::NOMINAL`]) and changing p_s, p_d or both (p_d > p_s > 0). The pressure behind
/// the piston stays the nominal `back_pressure` where the file gives one, else it is the
/// case's own suction pressure, as in `[mechanism.gas]`. Cases need `[mechanism.gas]`.
fn resolve_load_cases(
    raw: &[LoadCaseRaw],
    nominal: Option<&GasCycle>,
    back_given: bool,
) -> Result<Vec<LoadCase>, FieldError> {
    const KEY: &str = "mechanism.load_cases";
    if raw.is_empty() {
        return Ok(Vec::new());
    }
    // Errors of the whole array name its first entry (or the first one too many): an array
    // of tables has no line of its own.
    let Some(nominal) = nominal else {
        return Err(FieldError::new(
            format!("{KEY}[0]"),
            "load cases change the gas cycle's pressures; allowed: with [mechanism.gas], the nominal case",
        ));
    };
    crate::problem::envelope::case_count(raw.len())?;
    let mut cases: Vec<LoadCase> = Vec::with_capacity(raw.len());
    for (i, c) in raw.iter().enumerate() {
        let key = format!("{KEY}[{i}]");
        let taken = cases.iter().map(|k| k.name.as_str());
        let name =
            crate::problem::envelope::case_name(&key, &c.name, taken, "the [mechanism.gas] case")?;
        let (ks, kd) = (
            format!("{key}.suction_pressure"),
            format!("{key}.discharge_pressure"),
        );
        let (ps, pd) = match (c.suction_pressure, c.discharge_pressure) {
            (None, None) => {
                return Err(FieldError::new(
                    key,
                    "changes nothing; allowed: suction_pressure, discharge_pressure or both",
                ))
            }
            (Some(s), None) => pressures((&ks, s.si()), (&ks, nominal.discharge))?,
            (s, Some(d)) => pressures((&ks, s.map_or(nominal.suction, Qty::si)), (&kd, d.si()))?,
        };
        cases.push(LoadCase {
            name: name.to_string(),
            gas: GasCycle {
                suction: ps,
                discharge: pd,
                back: if back_given { nominal.back } else { ps },
                ..*nominal
            },
        });
    }
    Ok(cases)
}
