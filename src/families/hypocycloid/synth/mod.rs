//! Synthesis for the hypocycloidal (3:1 planetary gear + rod) reciprocating machine of paper
//! `004`: the resolved scene, the design vector (λ, θ), the Lanchester balancing of chosen
//! orders, the optimisation of the residual inertia force, and the search that settles the
//! paper's conjecture about a (λ, θ) where the fourth-order coefficient vanishes.
//!
//! Everything here is built on the pure model in [`crate::families::hypocycloid::model`]; the
//! one entry point is [`solve`], whose [`Outcome`] is serialisable and holds every number and
//! series a report needs. The scene, settings and result types are here; the design's
//! evaluation and search in `optimise.rs` (on the shared [`crate::synth::search`]), the zero
//! search in `zero.rs`, the solve and the paper's checks in `solve.rs`.

// `!(x > 0.0)` is deliberate: a NaN must fail every range check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::f64::consts::PI;

use crate::families::hypocycloid::model::{
    max_abs_y, Coefficients, Hypocycloid, LanchesterPair, ALPHA0_VARIANT1, ALPHA0_VARIANT2,
};
use crate::problem::FieldError;
use crate::report::numbers::key;
use crate::synth::{ActiveBound, SearchEvidence};
use serde::Serialize;

mod optimise;
mod solve;
mod zero;

pub use optimise::{residual_rate, residual_rel};
pub use solve::solve;
pub use zero::zero_search;

/// A bad field of a scene or of the settings names its problem-file key (`design.lambda`,
/// `accuracy.root_tol`): one [`FieldError`] from the file layer to the solver.
fn field(key: &str, value: impl std::fmt::Debug, allowed: &str) -> FieldError {
    FieldError::new(key, format!("got {value:?}; allowed: {allowed}"))
}

pub use crate::synth::Var;

/// Whether the optimiser may move `v`.
fn is_free(v: &Var) -> bool {
    matches!(v, Var::Free { .. })
}

/// Range check of a design variable: every value finite and above `lo` (strictly if
/// `lo_open`), and min < max for a free one.
fn check_var(v: &Var, key: &str, lo: f64, lo_open: bool, allowed: &str) -> Result<(), FieldError> {
    let ok = |v: f64| v.is_finite() && if lo_open { v > lo } else { v >= lo };
    match *v {
        Var::Fixed(x) if !ok(x) => Err(field(key, x, allowed)),
        Var::Free { min, max } if !ok(min) || !ok(max) || !(min < max) => Err(field(
            key,
            (min, max),
            &format!("{allowed}, with min < max"),
        )),
        _ => Ok(()),
    }
}

/// The domain and order of the zero search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ZeroSearch {
    /// Order i whose cosine coefficient a_i is searched for zeros (the paper: 4).
    pub order: usize,
    /// λ range [min, max] (`hypocycloid.zero_search.lambda`).
    pub lambda: (f64, f64),
    /// θ range [min, max] (`hypocycloid.zero_search.theta`).
    pub theta: (f64, f64),
}

/// A resolved, SI scene for the hypocycloidal machine.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HypocycloidScene {
    /// Curve orientation α0 (rad): 0 for variant 1, 3π/2 for variant 2
    /// (`hypocycloid.alpha0`).
    pub alpha0: f64,
    /// Carrier length R = OO1 (m) (`hypocycloid.R`).
    pub r_carrier: f64,
    /// λ = R/L (`hypocycloid.lambda`).
    pub lambda: Var,
    /// θ = r/R (`hypocycloid.theta`).
    pub theta: Var,
    /// Reciprocating mass m_B (piston + rod share) (kg) (`hypocycloid.m_B`).
    pub m_b: f64,
    /// Carrier speed ω (rad/s) (`hypocycloid.omega`).
    pub omega: f64,
    /// Orders cancelled by Lanchester pairs, e.g. [1, 2, 3] (`hypocycloid.balance_orders`).
    pub balance_orders: Vec<usize>,
    /// Highest order in the coefficient tables (`hypocycloid.orders`, ≥ 6).
    pub orders: usize,
    /// Power of z = λ²y² at which the paper-style series is truncated
    /// (`hypocycloid.series_power`; the paper: 3, i.e. y⁶).
    pub series_power: usize,
    /// Which coefficients C_i the balancing and the objectives use
    /// (`hypocycloid.coefficients`): the exact ones, or the paper's series truncated at
    /// z^`series_power`.
    pub coefficients: CoefficientModel,
    /// Required 1 − λ·max|y/R| (`hypocycloid.assembly_margin`, in (0, 0.5)).
    pub assembly_margin: f64,
    /// Minimum stroke (m) for the optimisation (`hypocycloid.min_stroke`).
    pub min_stroke: Option<f64>,
    /// Minimum suction-phase gain (suction angle/π − 1) (`hypocycloid.min_suction_gain`).
    pub min_suction_gain: Option<f64>,
    /// Shortest crank arm r = θR (m), already folded into `theta`'s lower bound
    /// (`objective.min_crank_arm`); kept to name the bound.
    pub min_crank_arm: Option<f64>,
    /// Longest rod L = R/λ (m), already folded into `lambda`'s lower bound
    /// (`objective.max_rod_length`); kept to name the bound.
    pub max_rod_length: Option<f64>,
    /// The zero search, if asked for (`hypocycloid.zero_search.*`).
    pub zero_search: Option<ZeroSearch>,
}

/// The coefficients a design is balanced and judged with.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum CoefficientModel {
    /// Exact: polynomial part + converged FFT of the remainder.
    #[default]
    Exact,
    /// The paper's method: sqrt(1 − z) expanded binomially to z^P, P = `series_power`.
    Series,
}

/// Which of the paper's two orientations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum PaperVariant {
    /// Fig. 1: α0 = 0, suction lengthened by a dwell.
    Variant1,
    /// Fig. 3: α0 = 270°, suction lengthened by a longer path.
    Variant2,
}

impl PaperVariant {
    /// α0 of the variant.
    pub fn alpha0(self) -> f64 {
        match self {
            PaperVariant::Variant1 => ALPHA0_VARIANT1,
            PaperVariant::Variant2 => ALPHA0_VARIANT2,
        }
    }
}

/// The analysis scene: λ = 0.25, θ = 0.5 (the true three-cusped hypocycloid), with a
/// small compressor's data chosen here (the paper gives none): R = 25 mm, m_B = 0.35 kg,
/// ω = 1450 rpm; orders I–III balanced as in the paper's Figs. 2 and 4.
pub fn paper_example(v: PaperVariant) -> HypocycloidScene {
    HypocycloidScene {
        alpha0: v.alpha0(),
        r_carrier: 0.025,
        lambda: Var::Fixed(0.25),
        theta: Var::Fixed(0.5),
        m_b: 0.35,
        omega: 1450.0 * PI / 30.0,
        balance_orders: vec![1, 2, 3],
        orders: 8,
        series_power: 3,
        coefficients: CoefficientModel::Exact,
        assembly_margin: 1e-3,
        min_stroke: None,
        min_suction_gain: None,
        min_crank_arm: None,
        max_rod_length: None,
        zero_search: None,
    }
}

/// The C4-search scene: the paper example with λ ∈ [0.02, 0.5], θ ∈ [0, 0.9] free, limited
/// to a buildable machine — a rod of at most 125 mm (λ ≥ 0.2) and a crank arm of at least
/// 5 mm (θ ≥ 0.2) — a minimum stroke 45 mm = 1.8 R; in variant 2 also a suction-phase gain
/// ≥ 0.1, i.e. a suction stroke of at least 198° (in variant 1 S is even in φ, the gain jumps
/// between 0 and 1/3 when the dwell splits the bottom dead centre, so it is not
/// constrained), and the zero search of a_4 over the whole box.
pub fn c4_search_example(v: PaperVariant) -> HypocycloidScene {
    HypocycloidScene {
        lambda: Var::Free { min: 0.2, max: 0.5 },
        theta: Var::Free { min: 0.2, max: 0.9 },
        min_crank_arm: Some(0.005),
        max_rod_length: Some(0.125),
        min_stroke: Some(0.045),
        min_suction_gain: if v == PaperVariant::Variant2 {
            Some(0.1)
        } else {
            None
        },
        zero_search: Some(ZeroSearch {
            order: 4,
            lambda: (0.02, 0.5),
            theta: (0.0, 0.9),
        }),
        ..paper_example(v)
    }
}

impl HypocycloidScene {
    /// Check every field; the error names the problem-file key and what is allowed.
    pub fn validate(&self) -> Result<(), FieldError> {
        if !self.alpha0.is_finite() {
            return Err(field(
                "mechanism.orientation",
                self.alpha0,
                "a finite angle",
            ));
        }
        if !(self.r_carrier.is_finite() && self.r_carrier > 0.0) {
            return Err(field(
                "mechanism.carrier_radius",
                self.r_carrier,
                "a finite length > 0",
            ));
        }
        check_var(
            &self.lambda,
            "design.lambda",
            0.0,
            true,
            "finite and > 0 (λ = R/L)",
        )?;
        check_var(
            &self.theta,
            "design.theta",
            0.0,
            false,
            "finite and ≥ 0 (θ = r/R)",
        )?;
        if !(self.m_b.is_finite() && self.m_b > 0.0) {
            return Err(field(
                "mechanism.reciprocating_mass",
                self.m_b,
                "a finite mass > 0",
            ));
        }
        if !(self.omega.is_finite() && self.omega > 0.0) {
            return Err(field("mechanism.speed", self.omega, "a finite speed > 0"));
        }
        if !(6..=64).contains(&self.orders) {
            return Err(field("model.orders", self.orders, "an integer in 6..=64"));
        }
        if let Some(&o) = self
            .balance_orders
            .iter()
            .find(|&&o| o == 0 || o > self.orders)
        {
            return Err(field(
                "objective.balance_orders",
                o,
                "orders in 1..=hypocycloid.orders",
            ));
        }
        if !(1..=32).contains(&self.series_power) {
            return Err(field(
                "model.series_power",
                self.series_power,
                "an integer in 1..=32",
            ));
        }
        if !(self.assembly_margin > 0.0 && self.assembly_margin < 0.5) {
            return Err(field(
                "objective.assembly_margin",
                self.assembly_margin,
                "in (0, 0.5)",
            ));
        }
        if let Some(s) = self.min_stroke {
            if !(s.is_finite() && s >= 0.0) {
                return Err(field("objective.min_stroke", s, "a finite length ≥ 0"));
            }
        }
        if let Some(g) = self.min_suction_gain {
            if !(g.is_finite() && g > -1.0 && g < 1.0) {
                return Err(field("objective.min_suction_gain", g, "in (−1, 1)"));
            }
        }
        if let Some(z) = &self.zero_search {
            if !(1..=self.orders).contains(&z.order) {
                return Err(field(
                    "objective.zero_search.order",
                    z.order,
                    "an order in 1..=hypocycloid.orders",
                ));
            }
            let (a, b) = z.lambda;
            if !(a.is_finite() && b.is_finite() && a > 0.0 && a < b) {
                return Err(field(
                    "objective.zero_search.lambda",
                    z.lambda,
                    "0 < min < max, finite",
                ));
            }
            let (a, b) = z.theta;
            if !(a.is_finite() && b.is_finite() && a >= 0.0 && a < b) {
                return Err(field(
                    "objective.zero_search.theta",
                    z.theta,
                    "0 ≤ min < max, finite",
                ));
            }
        }
        // A fixed design must assemble.
        if let (Var::Fixed(l), Var::Fixed(t)) = (self.lambda, self.theta) {
            if let Err(e) = Hypocycloid::new(l, t, self.alpha0) {
                return Err(field("design.lambda", l, &format!("{e}")));
            }
            let ym =
                max_abs_y(t, self.alpha0).map_err(|e| field("design.theta", t, &e.to_string()))?;
            if l * ym > 1.0 - self.assembly_margin {
                return Err(field(
                    "design.lambda",
                    l,
                    &format!(
                        "λ·max|y/R| = {} exceeds 1 − assembly_margin = {}; λ must be ≤ {}",
                        l * ym,
                        1.0 - self.assembly_margin,
                        (1.0 - self.assembly_margin) / ym
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Numerical settings (one flat struct; see [`Settings::validate`]).
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// Smallest FFT size for the coefficients (power of two, ≥ 16).
    pub n_fft_min: usize,
    /// Largest FFT size; beyond it the coefficients are reported unconverged.
    pub n_fft_max: usize,
    /// Absolute tolerance in θ of every root (the issue: 1e-12).
    pub root_tol: f64,
    /// Number of λ columns of the zero curve / C4 map.
    pub curve_points: usize,
    /// θ samples per column for the sign-change scan.
    pub theta_scan: usize,
    /// φ samples for the peak of the residual force (refined by Brent).
    pub peak_samples: usize,
    /// Refine each sampled maximum by Brent to `peak_xtol` (default true); false takes the
    /// largest sample, low by at most |f''|h²/8, h = 2π/`peak_samples` (a cheaper, coarser
    /// setting for speed-against-error studies).
    pub refine_peaks: bool,
    /// Double the FFT size until the coefficients converge (default true); false uses the one
    /// size `n_fft_min` (its error estimated from the n/2 rule) — coarser and cheaper.
    pub fft_adaptive: bool,
    /// Tolerance in φ of the peak refinement.
    #[serde(with = "crate::units::angle_setting")]
    #[schemars(with = "crate::units::Qty<crate::units::Angle>")]
    pub peak_xtol: f64,
    /// Samples per free variable of the optimiser's start grid.
    pub opt_grid: usize,
    /// Nelder–Mead runs, from the best mutually distant grid points (the search evidence).
    pub opt_starts: usize,
    /// Nelder–Mead iteration limit.
    pub nm_max_iters: u64,
    /// Nelder–Mead stop: standard deviation of the simplex costs (relative to the best).
    pub nm_sd_tol: f64,
    /// Samples per turn of the force curves returned for plots.
    pub plot_samples: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            n_fft_min: 64,
            n_fft_max: 1 << 16,
            root_tol: 1e-12,
            curve_points: 100,
            theta_scan: 48,
            peak_samples: 256,
            refine_peaks: true,
            fft_adaptive: true,
            peak_xtol: 1e-9,
            opt_grid: 15,
            opt_starts: 4,
            nm_max_iters: 300,
            nm_sd_tol: 1e-12,
            plot_samples: 181,
        }
    }
}

impl Settings {
    /// The refinement tolerance of the peaks, `None` when `refine_peaks` is off.
    pub fn peak_tol(&self) -> Option<f64> {
        self.refine_peaks.then_some(self.peak_xtol)
    }

    /// The coefficients of `m` to `order`: adaptive (converged) or on the one size `n_fft_min`.
    pub fn coefficients(&self, m: &Hypocycloid, order: usize) -> Coefficients {
        if self.fft_adaptive {
            m.coefficients(order, self.n_fft_min, self.n_fft_max)
        } else {
            m.coefficients_fixed(order, self.n_fft_min)
        }
    }

    /// Check every setting; the key is `accuracy.<name>`.
    pub fn validate(&self) -> Result<(), FieldError> {
        if !(self.n_fft_min >= 16 && self.n_fft_min.is_power_of_two()) {
            return Err(field(
                "accuracy.n_fft_min",
                self.n_fft_min,
                "a power of two ≥ 16",
            ));
        }
        if !(self.n_fft_max >= self.n_fft_min && self.n_fft_max <= 1 << 22) {
            return Err(field(
                "accuracy.n_fft_max",
                self.n_fft_max,
                "n_fft_min ≤ n_fft_max ≤ 2^22",
            ));
        }
        if !(self.root_tol > 0.0 && self.root_tol < 1e-3) {
            return Err(field("accuracy.root_tol", self.root_tol, "in (0, 1e-3)"));
        }
        if !(2..=10_000).contains(&self.curve_points) {
            return Err(field(
                "accuracy.curve_points",
                self.curve_points,
                "2..=10000",
            ));
        }
        if !(4..=10_000).contains(&self.theta_scan) {
            return Err(field("accuracy.theta_scan", self.theta_scan, "4..=10000"));
        }
        if !(16..=1 << 20).contains(&self.peak_samples) {
            return Err(field(
                "accuracy.peak_samples",
                self.peak_samples,
                "16..=2^20",
            ));
        }
        if !(self.peak_xtol > 0.0 && self.peak_xtol < 1e-3) {
            return Err(field("accuracy.peak_xtol", self.peak_xtol, "in (0, 1e-3)"));
        }
        if !(3..=1000).contains(&self.opt_grid) {
            return Err(field("accuracy.opt_grid", self.opt_grid, "3..=1000"));
        }
        if !(1..=64).contains(&self.opt_starts) {
            return Err(field("accuracy.opt_starts", self.opt_starts, "1..=64"));
        }
        if self.nm_max_iters == 0 {
            return Err(field("accuracy.nm_max_iters", self.nm_max_iters, "≥ 1"));
        }
        if !(self.nm_sd_tol > 0.0) {
            return Err(field("accuracy.nm_sd_tol", self.nm_sd_tol, "> 0"));
        }
        if !(8..=100_000).contains(&self.plot_samples) {
            return Err(field(
                "accuracy.plot_samples",
                self.plot_samples,
                "8..=100000",
            ));
        }
        Ok(())
    }
}

/// A point of the zero set.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ZeroPoint {
    /// λ of the column.
    pub lambda: f64,
    /// θ* with a_i(λ, θ*) = 0 (to `root_tol`).
    pub theta: f64,
}

/// A refined root with its evidence.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ZeroRoot {
    /// λ of the column.
    pub lambda: f64,
    /// θ* (refined by Brent to `root_tol`).
    pub theta: f64,
    /// a_i(λ, θ*) as evaluated.
    pub value: f64,
    /// Bracket [θ_lo, θ_hi] of the sign change found on the scan.
    pub bracket: (f64, f64),
    /// a_i at the two ends of the bracket (opposite signs).
    pub f_bracket: (f64, f64),
    /// Estimated absolute error of a_i values in this column (aliasing + rounding).
    pub value_error: f64,
    /// The paper-style truncated series a_i^(P)(λ, θ*) at the exact root.
    pub series_value: f64,
    /// The truncated series' root nearest to θ* in the same λ column (searched over the
    /// column's whole feasible θ range), if the series has one there.
    pub series_theta: Option<f64>,
}

/// Whether a zero set was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ZeroStatus {
    /// At least one bracketed, refined root.
    Found,
    /// No sign change anywhere on the feasible grid.
    NoZero,
    /// No feasible point in the search box.
    Infeasible,
}

/// The map of a_i over (λ, θ) (rows by λ, `None` where the mechanism cannot assemble with
/// the scene's margin).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoefficientMap {
    /// Order i.
    pub order: usize,
    /// λ of each row.
    pub lambda: Vec<f64>,
    /// θ of each column.
    pub theta: Vec<f64>,
    /// a_i(λ_r, θ_c).
    pub value: Vec<Vec<Option<f64>>>,
}

/// Smallest |a_i| on the feasible grid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GridMin {
    /// λ there.
    pub lambda: f64,
    /// θ there.
    pub theta: f64,
    /// a_i there.
    pub value: f64,
}

/// Result of the zero search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ZeroSearchResult {
    /// Order searched.
    pub order: usize,
    /// Found / no zero / infeasible.
    pub status: ZeroStatus,
    /// Every refined root.
    pub roots: Vec<ZeroRoot>,
    /// Whether every column has at most one root (the zero set is a curve θ*(λ)).
    pub single_valued: bool,
    /// Smallest |a_i| on the feasible grid (and its sign) — the answer when there is no zero.
    pub grid_min_abs: Option<GridMin>,
    /// Sign of a_i on the feasible grid when it keeps one (+1/−1), else 0.
    pub sign: i32,
    /// Why there is (no) zero, in words.
    pub reason: String,
    /// Largest |a_i| at a root (the issue requires < 1e-13).
    pub max_abs_at_root: f64,
    /// Coefficient evaluations spent.
    pub evals: usize,
    /// The map (for the heat map).
    pub map: CoefficientMap,
}

/// Largest θ in [t0, t1] with λ·max|y(θ)| ≤ 1 − margin (max|y| is convex in θ, so the
/// feasible θ form an interval containing 0); `None` if even t0 is infeasible.

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum OptStatus {
    /// Nothing free: the fixed design was evaluated.
    Analysis,
    /// Nelder–Mead met its simplex tolerance.
    Converged,
    /// Nelder–Mead hit its iteration limit (the best point is returned).
    MaxIterations,
    /// No feasible start point on the grid.
    Infeasible,
}

/// One row of the order table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OrderRow {
    /// Order i.
    pub order: usize,
    /// a_i (exact).
    pub a: f64,
    /// b_i (exact).
    pub b: f64,
    /// Estimated absolute error of (a_i, b_i).
    pub error: f64,
    /// a_i of the truncated series.
    pub a_series: f64,
    /// b_i of the truncated series.
    pub b_series: f64,
    /// Amplitude of the i-th order inertia force m_B R ω² i² hypot(a_i, b_i) (N).
    pub force_amplitude: f64,
    /// Whether a Lanchester pair cancels it.
    pub balanced: bool,
}

/// The `coefficients` JSON section.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoefficientTable {
    /// a_0 … a_n of S/R (cosine; a_0 includes 1/λ).
    pub a: Vec<f64>,
    /// b_0 … b_n of S/R (sine).
    pub b: Vec<f64>,
    /// Estimated absolute error of each order.
    pub error: Vec<f64>,
    /// Truncated-series a (the paper's method, power `series_power`).
    pub a_series: Vec<f64>,
    /// Truncated-series b.
    pub b_series: Vec<f64>,
    /// Power of z at which the series was truncated.
    pub series_power: usize,
    /// FFT size used.
    pub n_fft: usize,
    /// Whether the FFT converged to the rounding floor.
    pub converged: bool,
    /// Per-order rows for the tables.
    pub rows: Vec<OrderRow>,
}

pub use crate::report::PaperCheck;

/// Force over one turn for the plots (N).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForceCurves {
    /// φ (rad).
    pub phi: Vec<f64>,
    /// Inertia force of m_B without balancing.
    pub unbalanced: Vec<f64>,
    /// After the Lanchester pairs.
    pub residual: Vec<f64>,
    /// Piston position S − L (m).
    pub position: Vec<f64>,
}

/// The design of a hypocycloid result (keys of `design`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Design {
    /// λ = R/L: the carrier radius over the rod length.
    pub lambda: f64,
    /// θ = r/R: the crank arm over the carrier radius.
    pub theta: f64,
    /// R (m): the carrier radius.
    pub carrier_radius_m: f64,
    /// r = θR (m): the crank arm.
    pub crank_arm_m: f64,
    /// L = R/λ (m): the rod.
    pub rod_length_m: f64,
}

/// The objectives of a hypocycloid result (keys of `objectives`); the same type holds their
/// absolute errors (keys of `errors`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Objectives {
    /// C4 = a_4 of S/R: the fourth-order cosine coefficient of the piston path.
    pub c4: f64,
    /// Peak of the inertia force of m_B left after the Lanchester pairs (N).
    pub residual_force_peak_n: f64,
    /// RMS of that residual force over a turn (N).
    pub residual_force_rms_n: f64,
    /// Peak inertia force of m_B without balancing (N).
    pub unbalanced_force_peak_n: f64,
    /// Piston stroke (m).
    pub stroke_m: f64,
    /// Suction gain: the suction stroke's share of a turn beyond one half, over π.
    pub suction_gain: f64,
}

impl Objectives {
    /// The key objective of a scene: C4 when it asks the paper's C4 question (a zero
    /// search), else the residual force peak.
    pub fn key(zero_search: bool) -> &'static str {
        if zero_search {
            key!(Objectives, c4)
        } else {
            key!(Objectives, residual_force_peak_n)
        }
    }
}

/// Other figures of a hypocycloid result (keys of `derived`); `None` without a zero search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Derived {
    /// b_4 of S/R.
    pub b4: f64,
    /// a_4 by the paper's truncated series.
    pub c4_series: f64,
    /// Series a_4 minus the exact a_4.
    pub c4_series_minus_exact: f64,
    /// λ·max|y|.
    pub lambda_ymax: f64,
    /// 1 − λ·max|y|: how far from failing to assemble.
    pub assembly_margin: f64,
    /// FFT size of the coefficients.
    pub n_fft: f64,
    /// m_B R ω² (N): the force scale.
    pub force_scale_n: f64,
    /// Amplitude of the order-4 inertia force, 16·m_B R ω²·hypot(a_4, b_4) (N).
    pub force_order4_amplitude_n: f64,
    /// (suction gain + 1)·π (rad): the suction stroke's crank angle.
    pub suction_angle_rad: f64,
    /// Model evaluations of the search and analysis (before the zero search).
    pub evaluations: f64,
    /// Largest |θ_series − θ_exact| on the zero curve.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zero_curve_series_max_dtheta: Option<f64>,
    /// λ of that largest difference.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zero_curve_series_worst_lambda: Option<f64>,
    /// Roots the zero search found.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zero_roots: Option<f64>,
    /// Largest |a_k| at a root of the zero search.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zero_max_abs_at_root: Option<f64>,
    /// ω (rad/s): the crank speed.
    pub omega_rad_s: f64,
    /// max |b_1..b_6|: the sine coefficients (0 for a symmetric path).
    pub max_abs_b1_b6: f64,
    /// |Φ3|/|Φ1| = 9·hypot(a_3, b_3)/hypot(a_1, b_1): order-3 against order-1 force.
    pub force_ratio_order3_to_order1: f64,
}

/// Everything a report needs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Outcome {
    /// The design.
    pub design: Design,
    /// The objectives.
    pub objectives: Objectives,
    /// Estimated absolute error of each objective.
    pub errors: Objectives,
    /// Secondary numbers.
    pub derived: Derived,
    /// Things the user should know.
    pub warnings: Vec<String>,
    /// The design variables the search left on a bound, and who set it.
    pub bounds: Vec<ActiveBound>,
    /// Comparison with the paper.
    pub paper: Vec<PaperCheck>,
    /// Solver and evaluation count.
    pub method: String,
    /// Optimiser status.
    pub status: OptStatus,
    /// What the Nelder–Mead search did (absent when nothing is free): a multi-start heuristic,
    /// so a converged search is `best_found`, never `optimal`.
    pub search: Option<SearchEvidence>,
    /// Why the best design found is degenerate (it is no longer the machine the scene asks
    /// for), if it is.
    pub degenerate: Option<String>,
    /// The coefficient tables.
    pub coefficients: CoefficientTable,
    /// The Lanchester pairs of the balanced orders.
    pub balancing: Vec<LanchesterPair>,
    /// The zero set of the searched order (empty without a zero search).
    pub zero_curve: Vec<ZeroPoint>,
    /// The truncated series' zero set: for each exact root, the series root nearest to it in
    /// the same λ column (where the series has one).
    pub zero_curve_series: Vec<ZeroPoint>,
    /// The full zero-search evidence.
    pub zero_search: Option<ZeroSearchResult>,
    /// Force curves over a turn.
    pub force_curves: ForceCurves,
}
