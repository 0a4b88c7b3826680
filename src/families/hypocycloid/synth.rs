//! Synthesis for the hypocycloidal (3:1 planetary gear + rod) reciprocating machine of paper
//! `004`: the resolved scene, the design vector (λ, θ), the Lanchester balancing of chosen
//! orders, the optimisation of the residual inertia force, and the search that settles the
//! paper's conjecture about a (λ, θ) where the fourth-order coefficient vanishes.
//!
//! Everything here is built on the pure model in [`crate::families::hypocycloid::model`]; the one entry
//! point is [`solve`], whose [`Outcome`] is serialisable and holds every number and series a
//! report needs.

// `!(x > 0.0)` is deliberate: a NaN must fail every range check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::f64::consts::PI;

use crate::report::numbers::key;
use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::neldermead::NelderMead;
use serde::Serialize;

use crate::families::hypocycloid::model::{
    lanchester_pair, max_abs_y, Coefficients, CosBin, Hypocycloid, LanchesterPair, MechError,
    ALPHA0_VARIANT1, ALPHA0_VARIANT2,
};
use crate::numeric::{brent_root, periodic_peak_with, periodic_rms};
use crate::problem::FieldError;
use crate::synth::{ActiveBound, SearchEvidence};

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

/// The issue's analysis scene: λ = 0.25, θ = 0.5 (the true three-cusped hypocycloid), with a
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

// ---------------------------------------------------------------------------------------
// Zero search
// ---------------------------------------------------------------------------------------

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
fn theta_limit(lambda: f64, alpha0: f64, t0: f64, t1: f64, margin: f64) -> Option<f64> {
    let g = |t: f64| lambda * max_abs_y(t, alpha0).unwrap_or(f64::INFINITY) - (1.0 - margin);
    if g(t0) > 0.0 {
        return None;
    }
    if g(t1) <= 0.0 {
        return Some(t1);
    }
    brent_root(g, t0, t1, 1e-13)
        .ok()
        .map(|r| if g(r.x) > 0.0 { r.x - 1e-13 } else { r.x })
}

/// FFT size at which all orders ≤ `order` converge at (λ, θ) (see
/// [`Hypocycloid::coefficients`]) and the error of order `order` there.
fn column_size(lambda: f64, theta: f64, alpha0: f64, order: usize, s: &Settings) -> (usize, f64) {
    let m = Hypocycloid {
        lambda,
        theta,
        alpha0,
    };
    let c = s.coefficients(&m, order);
    (c.n_fft, c.err[order])
}

/// Find, bracket, refine and trace the zeros of a_i over the feasible part of the box.
///
/// Columns λ_j (`curve_points`, evenly spaced) × a common θ grid (`theta_scan` points): a
/// sign change between neighbouring θ samples is refined by Brent to `root_tol`; the FFT
/// size of a column is the converged size at its most demanding (largest feasible) θ.
/// Sign changes along λ between columns that no θ-root explains are reported as possible
/// folds in `reason`.
pub fn zero_search(
    alpha0: f64,
    zs: &ZeroSearch,
    series_power: usize,
    margin: f64,
    s: &Settings,
) -> ZeroSearchResult {
    let k = zs.order;
    let nl = s.curve_points;
    let nt = s.theta_scan;
    let lam: Vec<f64> = (0..nl)
        // The last sample is the bound itself (rounding must not push it out of the box).
        .map(|j| {
            (zs.lambda.0 + (zs.lambda.1 - zs.lambda.0) * j as f64 / (nl - 1) as f64)
                .min(zs.lambda.1)
        })
        .collect();
    let th: Vec<f64> = (0..nt)
        .map(|j| {
            (zs.theta.0 + (zs.theta.1 - zs.theta.0) * j as f64 / (nt - 1) as f64).min(zs.theta.1)
        })
        .collect();
    let mut value = vec![vec![None; nt]; nl];
    let mut roots = Vec::new();
    let mut evals = 0usize;
    let mut bins: Vec<CosBin> = Vec::new();
    let mut single = true;
    for (r, &l) in lam.iter().enumerate() {
        let Some(tmax) = theta_limit(l, alpha0, zs.theta.0, zs.theta.1, margin) else {
            continue;
        };
        let (n, err) = column_size(l, tmax, alpha0, k, s);
        let bin = match bins.iter().position(|b| b.n() == n) {
            Some(i) => &bins[i],
            None => {
                bins.push(CosBin::new(k, alpha0, n));
                bins.last().unwrap()
            }
        };
        // Feasible θ samples of this column, plus the limit itself when it cuts the grid.
        let mut ts: Vec<(Option<usize>, f64)> = th
            .iter()
            .enumerate()
            .filter(|(_, &t)| t <= tmax)
            .map(|(c, &t)| (Some(c), t))
            .collect();
        if tmax < zs.theta.1 {
            ts.push((None, tmax));
        }
        let fs: Vec<f64> = ts.iter().map(|&(_, t)| bin.eval(l, t)).collect();
        evals += fs.len();
        // The truncated series' own roots anywhere in the column's feasible θ range (they
        // need not lie in the exact roots' brackets).
        let ser = |t: f64| {
            Hypocycloid {
                lambda: l,
                theta: t,
                alpha0,
            }
            .series_a(series_power, k)
        };
        let ss: Vec<f64> = ts.iter().map(|&(_, t)| ser(t)).collect();
        let series_roots: Vec<f64> = (0..ss.len().saturating_sub(1))
            .filter(|&w| ss[w] == 0.0 || ss[w].signum() != ss[w + 1].signum())
            .filter_map(|w| brent_root(ser, ts[w].1, ts[w + 1].1, s.root_tol).ok())
            .map(|r| r.x)
            .collect();
        for (&(c, _), &f) in ts.iter().zip(&fs) {
            if let Some(c) = c {
                value[r][c] = Some(f);
            }
        }
        let mut count = 0;
        for w in 0..fs.len().saturating_sub(1) {
            let (ta, tb, fa, fb) = (ts[w].1, ts[w + 1].1, fs[w], fs[w + 1]);
            // A sign change, or an exact zero at the left sample.
            if !(fa == 0.0 || fa.signum() != fb.signum()) || fb == 0.0 && w + 2 < fs.len() {
                continue;
            }
            let cnt = std::cell::Cell::new(0usize);
            let f = |t: f64| {
                cnt.set(cnt.get() + 1);
                bin.eval(l, t)
            };
            if let Ok(rt) = brent_root(f, ta, tb, s.root_tol) {
                evals += cnt.get();
                let series_theta = series_roots
                    .iter()
                    .copied()
                    .min_by(|a, b| (a - rt.x).abs().total_cmp(&(b - rt.x).abs()));
                roots.push(ZeroRoot {
                    lambda: l,
                    theta: rt.x,
                    value: rt.fx,
                    bracket: (ta, tb),
                    f_bracket: (fa, fb),
                    value_error: err,
                    series_value: ser(rt.x),
                    series_theta,
                });
                count += 1;
            }
        }
        if count > 1 {
            single = false;
        }
    }
    // Sign bookkeeping over the feasible grid.
    let mut pos = 0usize;
    let mut neg = 0usize;
    let mut best: Option<GridMin> = None;
    for (r, row) in value.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            if let Some(v) = *v {
                if v > 0.0 {
                    pos += 1;
                } else if v < 0.0 {
                    neg += 1;
                }
                if best.is_none_or(|b| v.abs() < b.value.abs()) {
                    best = Some(GridMin {
                        lambda: lam[r],
                        theta: th[c],
                        value: v,
                    });
                }
            }
        }
    }
    // Sign changes along λ not explained by a root in either neighbouring column.
    let mut folds = 0;
    for r in 0..nl.saturating_sub(1) {
        for c in 0..nt {
            if let (Some(a), Some(b)) = (value[r][c], value[r + 1][c]) {
                if a.signum() != b.signum() {
                    let near = roots.iter().any(|z| {
                        (z.lambda == lam[r] || z.lambda == lam[r + 1])
                            && (z.theta - th[c]).abs() <= 1.5 * (th[1] - th[0])
                    });
                    if !near {
                        folds += 1;
                    }
                }
            }
        }
    }
    let max_abs_at_root = roots.iter().fold(0.0f64, |m, z| m.max(z.value.abs()));
    let sign = if neg == 0 && pos > 0 {
        1
    } else if pos == 0 && neg > 0 {
        -1
    } else {
        0
    };
    let status = if pos + neg == 0 {
        ZeroStatus::Infeasible
    } else if roots.is_empty() {
        ZeroStatus::NoZero
    } else {
        ZeroStatus::Found
    };
    let mut reason = match status {
        ZeroStatus::Infeasible => "no (λ, θ) of the search box assembles with the required margin".to_string(),
        ZeroStatus::Found => format!(
            "a_{k} changes sign on the feasible grid ({pos} samples > 0, {neg} < 0); {} bracketed roots refined to \
             {:e} in θ; the zero set is {}",
            roots.len(),
            s.root_tol,
            if single { "a single-valued curve θ*(λ)" } else { "multi-valued in some columns (several branches)" }
        ),
        ZeroStatus::NoZero => {
            let b = best.unwrap();
            let lead = leading_terms_keep_sign(alpha0, k, &th);
            format!(
                "a_{k} keeps one sign ({}) at all {} feasible grid samples; min |a_{k}| = {:e} at λ = {}, θ = {} \
                 (on the boundary of the box: |a_{k}| grows with λ). {}",
                if sign > 0 { "> 0" } else { "< 0" },
                pos + neg,
                b.value.abs(),
                b.lambda,
                b.theta,
                lead
            )
        }
    };
    if folds > 0 {
        reason.push_str(&format!(
            "; {folds} sign changes along λ are not explained by a θ-root nearby (possible fold of the zero set)"
        ));
    }
    ZeroSearchResult {
        order: k,
        status,
        roots,
        single_valued: single,
        grid_min_abs: best,
        sign,
        reason,
        max_abs_at_root,
        evals,
        map: CoefficientMap {
            order: k,
            lambda: lam,
            theta: th,
            value,
        },
    }
}

/// The series a_k = −Σ_p c_p λ^{2p−1} [y^{2p}]_k: report whether the first two terms
/// (λ¹ and λ³) have the same sign at every θ of the grid, which is why a_k cannot vanish for
/// small λ.
fn leading_terms_keep_sign(alpha0: f64, k: usize, th: &[f64]) -> String {
    // [y²]_k and [y⁴]_k from the series with λ = 1 (power 1 and power 2 differences).
    let mut same = true;
    let mut sgn = 0.0;
    for &t in th {
        let m = Hypocycloid {
            lambda: 1.0,
            theta: t,
            alpha0,
        };
        let p0 = m.series_coefficients(1, k).0[k] - if k == 1 { 1.0 } else { 0.0 };
        let x2 = if k == 2 { t * alpha0.cos() } else { 0.0 };
        let t1 = p0 - x2; // −½[y²]_k
        let t3 = m.series_coefficients(2, k).0[k] - m.series_coefficients(1, k).0[k]; // −⅛[y⁴]_k
        for v in [t1, t3] {
            if v != 0.0 && v.abs() > 1e-15 {
                if sgn == 0.0 {
                    sgn = v.signum();
                } else if v.signum() != sgn {
                    same = false;
                }
            }
        }
    }
    if same {
        format!(
            "The λ¹ and λ³ terms of the binomial series, −½λ[y²]_{k} and −⅛λ³[y⁴]_{k}, have the same sign at every \
             θ of the grid, so they add instead of cancelling"
        )
    } else {
        "The λ¹ and λ³ terms of the series change sign over θ; no zero was found on the grid nevertheless".to_string()
    }
}

// ---------------------------------------------------------------------------------------
// Design evaluation and optimisation
// ---------------------------------------------------------------------------------------

/// Evaluation of one design.
#[derive(Debug, Clone, PartialEq)]
struct Eval {
    coef: Coefficients,
    residual_peak: f64,
    residual_peak_err: f64,
    stroke: f64,
    stroke_err: f64,
    suction_gain: f64,
    ratio_ymax: f64,
}

/// Peak over φ of |residual inertia force| / (m_B R ω²):
/// F_res/(m_B R ω²) = −(S/R)'' − Σ_{i∈K} i² (a_i cos iφ + b_i sin iφ), with (S/R)'' in closed
/// form (independent of the coefficients). Error: refinement + Σ i² err_i.
fn residual_peak(
    m: &Hypocycloid,
    c: &Coefficients,
    orders: &[usize],
    s: &Settings,
) -> Result<(f64, f64), MechError> {
    let f = |p: f64| residual_rel(m, c, orders, p).abs();
    let pk = periodic_peak_with(f, s.peak_samples, s.peak_tol())?;
    let cerr: f64 = orders.iter().map(|&i| (i * i) as f64 * c.err[i]).sum();
    Ok((pk.peak.fx, pk.error + cerr))
}

/// The residual inertia force of m_B after the Lanchester pairs of `orders`, over m_B R ω²:
/// −(S/R)'' − Σ_{i∈K} i² (a_i cos iφ + b_i sin iφ).
pub fn residual_rel(m: &Hypocycloid, c: &Coefficients, orders: &[usize], p: f64) -> f64 {
    let mut f = -m.piston(p).dds;
    for &i in orders {
        let k = i as f64;
        let (sn, cs) = (k * p).sin_cos();
        f -= k * k * (c.a[i] * cs + c.b[i] * sn);
    }
    f
}

fn evaluate(scene: &HypocycloidScene, l: f64, t: f64, s: &Settings) -> Result<Eval, MechError> {
    let m = Hypocycloid::new(l, t, scene.alpha0)?;
    let ratio_ymax = m.lambda_ymax();
    let order = scene
        .orders
        .max(*scene.balance_orders.iter().max().unwrap_or(&0));
    let mut coef = s.coefficients(&m, order);
    if scene.coefficients == CoefficientModel::Series {
        (coef.a, coef.b) = m.series_coefficients(scene.series_power, order);
    }
    let (rp, rpe) = residual_peak(&m, &coef, &scene.balance_orders, s)?;
    let st = m.stroke()?;
    Ok(Eval {
        coef,
        residual_peak: rp,
        residual_peak_err: rpe,
        stroke: st.stroke,
        stroke_err: st.error,
        suction_gain: st.suction_angle / PI - 1.0,
        ratio_ymax,
    })
}

/// Penalised objective of the optimiser (dimensionless residual peak; +1e3·violation and
/// +1e6 when the mechanism cannot be built).
fn penalised(scene: &HypocycloidScene, x: [f64; 2], s: &Settings) -> f64 {
    let (lb, tb) = (scene.lambda.bounds(), scene.theta.bounds());
    let mut viol = 0.0;
    let l = x[0].clamp(lb.0, lb.1);
    let t = x[1].clamp(tb.0, tb.1);
    viol += (x[0] - l).abs() + (x[1] - t).abs();
    let ym = max_abs_y(t, scene.alpha0).unwrap_or(f64::INFINITY);
    let over = l * ym - (1.0 - scene.assembly_margin);
    if over > 0.0 {
        return 1e6 + over + viol;
    }
    match evaluate(scene, l, t, s) {
        Ok(e) => {
            if let Some(ms) = scene.min_stroke {
                viol += (ms / scene.r_carrier - e.stroke).max(0.0);
            }
            if let Some(g) = scene.min_suction_gain {
                viol += (g - e.suction_gain).max(0.0);
            }
            e.residual_peak + 1e3 * viol
        }
        Err(_) => 1e6 + viol,
    }
}

struct Objective<'a> {
    scene: &'a HypocycloidScene,
    s: &'a Settings,
    count: std::cell::Cell<usize>,
}
impl CostFunction for Objective<'_> {
    /// (λ, θ).
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> Result<f64, ArgminError> {
        self.count.set(self.count.get() + 1);
        Ok(penalised(self.scene, [p[0], p[1]], self.s))
    }
}

/// How the optimiser ended.
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

/// Solve a scene: optimise (λ, θ) if free, evaluate, balance, compare with the paper, and run
/// the zero search if asked. Invalid input is the only error; solver trouble is a status.
pub fn solve(scene: &HypocycloidScene, settings: &Settings) -> Result<Outcome, FieldError> {
    scene.validate()?;
    settings.validate()?;
    let s = settings;
    let mut warnings = Vec::new();
    let mut evals = 0usize;
    let mut search: Option<SearchEvidence> = None;
    let fscale = scene.m_b * scene.r_carrier * scene.omega * scene.omega;
    let (lb, tb) = (scene.lambda.bounds(), scene.theta.bounds());
    let free = is_free(&scene.lambda) || is_free(&scene.theta);
    let (mut x, status, method) = if !free {
        (
            [lb.0, tb.0],
            OptStatus::Analysis,
            "analysis of the fixed design".to_string(),
        )
    } else {
        // Grid start over the free box.
        let g = s.opt_grid;
        let pts = |b: (f64, f64), f: bool| -> Vec<f64> {
            if f {
                (0..g)
                    .map(|j| b.0 + (b.1 - b.0) * j as f64 / (g - 1) as f64)
                    .collect()
            } else {
                vec![b.0]
            }
        };
        let mut best = ([lb.0, tb.0], f64::INFINITY);
        let mut grid = Vec::new();
        for &l in &pts(lb, is_free(&scene.lambda)) {
            for &t in &pts(tb, is_free(&scene.theta)) {
                let v = penalised(scene, [l, t], s);
                evals += 1;
                grid.push(([l, t], v));
                if v < best.1 {
                    best = ([l, t], v);
                }
            }
        }
        if best.1 >= 1e3 {
            warnings.push(format!(
                "no grid point satisfies the assembly margin, stroke and suction constraints (best penalised value {:e}); \
                 the least-violating point is reported",
                best.1
            ));
            (
                best.0,
                OptStatus::Infeasible,
                format!("grid {g}×{g}: infeasible"),
            )
        } else {
            let step = |b: (f64, f64), f: bool| if f { (b.1 - b.0) / (g - 1) as f64 } else { 0.0 };
            let (dl, dt) = (
                step(lb, is_free(&scene.lambda)),
                step(tb, is_free(&scene.theta)),
            );
            // Starts: the best grid points that are at least two grid steps apart.
            grid.sort_by(|a, b| a.1.total_cmp(&b.1));
            let mut starts: Vec<[f64; 2]> = Vec::new();
            for (p, v) in &grid {
                if *v >= 1e3 || starts.len() >= s.opt_starts {
                    continue;
                }
                let far = starts.iter().all(|q| {
                    let dx = if dl > 0.0 {
                        (p[0] - q[0]).abs() / dl
                    } else {
                        0.0
                    };
                    let dy = if dt > 0.0 {
                        (p[1] - q[1]).abs() / dt
                    } else {
                        0.0
                    };
                    dx.max(dy) >= 2.0 - 1e-9
                });
                if far {
                    starts.push(*p);
                }
            }
            let mut runs: Vec<([f64; 2], f64, u64, bool)> = Vec::new();
            let mut total_iters = 0;
            for x0 in starts {
                let mut simplex = vec![x0.to_vec()];
                if dl > 0.0 {
                    simplex.push(vec![
                        x0[0] + dl * if x0[0] + dl > lb.1 { -1.0 } else { 1.0 },
                        x0[1],
                    ]);
                }
                if dt > 0.0 {
                    simplex.push(vec![
                        x0[0],
                        x0[1] + dt * if x0[1] + dt > tb.1 { -1.0 } else { 1.0 },
                    ]);
                }
                let obj = Objective {
                    scene,
                    s,
                    count: std::cell::Cell::new(0),
                };
                let nm = NelderMead::new(simplex)
                    .with_sd_tolerance(s.nm_sd_tol)
                    .expect("positive tolerance");
                let res = Executor::new(obj, nm)
                    .configure(|c| c.max_iters(s.nm_max_iters))
                    .run();
                match res {
                    Ok(r) => {
                        let st = r.state();
                        let p = st.get_best_param().map_or(x0, |p| [p[0], p[1]]);
                        let iters = st.get_iter();
                        total_iters += iters;
                        evals += r
                            .problem()
                            .problem
                            .as_ref()
                            .map(|o| o.count.get())
                            .unwrap_or(0);
                        let px = [p[0].clamp(lb.0, lb.1), p[1].clamp(tb.0, tb.1)];
                        let v = penalised(scene, px, s);
                        evals += 1;
                        runs.push((px, v, iters, iters < s.nm_max_iters));
                    }
                    Err(e) => warnings.push(format!(
                        "Nelder–Mead from ({:.6}, {:.6}) failed ({e})",
                        x0[0], x0[1]
                    )),
                }
            }
            if runs.is_empty() {
                warnings
                    .push("every Nelder–Mead run failed; the best grid point is reported".into());
                runs.push((best.0, best.1, 0, false));
            }
            runs.sort_by(|a, b| a.1.total_cmp(&b.1));
            let (px, fbest, _, converged) = runs[0];
            if !converged {
                warnings.push(format!(
                    "the best Nelder–Mead run stopped at its iteration limit ({})",
                    s.nm_max_iters
                ));
            }
            // Basins: runs whose end points differ by more than 1e-6 of the box (or whose
            // values differ by more than 1e-9 relative) are distinct local optima.
            let rel = |v: f64| (v - fbest) / fbest.abs().max(f64::MIN_POSITIVE);
            let mut basins: Vec<([f64; 2], f64)> = Vec::new();
            for (p, v, _, _) in &runs {
                let same = basins.iter().any(|(q, w)| {
                    let dx = (p[0] - q[0]).abs() / (lb.1 - lb.0).max(f64::MIN_POSITIVE);
                    let dy = (p[1] - q[1]).abs() / (tb.1 - tb.0).max(f64::MIN_POSITIVE);
                    dx.max(dy) <= 1e-6 || (v - w).abs() <= 1e-9 * w.abs()
                });
                if !same {
                    basins.push((*p, *v));
                }
            }
            let at_best = runs.iter().filter(|r| rel(r.1) <= 1e-9).count();
            search = Some(SearchEvidence {
                method: format!(
                    "grid {g} per free variable, then argmin Nelder–Mead (Nelder & Mead 1965) from the {} best \
                     grid points at least two steps apart; penalised residual-force peak",
                    runs.len()
                ),
                starts: runs.len(),
                distinct_basins: basins.len(),
                evaluations: evals,
                best_values: basins.iter().take(5).map(|b| b.1 * fscale).collect(),
                starts_at_best: at_best,
                spread_rel: (basins.len() > 1).then(|| rel(basins[1].1)),
            });
            (
                px,
                if converged {
                    OptStatus::Converged
                } else {
                    OptStatus::MaxIterations
                },
                format!(
                    "grid {g}-per-free-variable start + argmin Nelder–Mead from {} starts ({total_iters} iterations)",
                    runs.len()
                ),
            )
        }
    };
    // Keep the reported design feasible.
    let ym = max_abs_y(x[1], scene.alpha0).unwrap_or(f64::INFINITY);
    if x[0] * ym > 1.0 - scene.assembly_margin {
        x[0] = (1.0 - scene.assembly_margin) / ym;
    }
    let (l, t) = (x[0], x[1]);
    let e = match evaluate(scene, l, t, s) {
        Ok(e) => e,
        Err(err) => return Err(field("design.lambda", l, &err.to_string())),
    };
    evals += 1;
    let m = Hypocycloid {
        lambda: l,
        theta: t,
        alpha0: scene.alpha0,
    };
    let r = scene.r_carrier;
    let c = &e.coef;
    // A design that the search pushed onto a bound, and one that lost what makes the machine
    // hypocycloidal (the suction lengthening of paper 004), are said so.
    let mut degenerate = None;
    let mut bounds = Vec::new();
    if free {
        // The bound each variable sits on, and who set it: a machine limit
        // (θ ≥ r_min/R, λ ≥ R/L_max) or the design range.
        let set_by = |name: &str, lo: f64| -> (String, String) {
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-300);
            match name {
                "lambda" => match scene.max_rod_length.filter(|&lm| close(lo, r / lm)) {
                    Some(lm) => ("objective.max_rod_length".into(), format!(
                        "the residual force falls as the rod L = R/λ grows: the rod limit ({:.4} mm) sets L = {:.4} mm",
                        lm * 1e3, r / l * 1e3
                    )),
                    None => ("design.lambda".into(), format!(
                        "the residual force falls as λ → 0, i.e. as the rod L = R/λ = {:.4} m grows: the range, not an interior optimum, sets the rod (give objective.max_rod_length)",
                        r / l
                    )),
                },
                _ => match scene.min_crank_arm.filter(|&am| close(lo, am / r)) {
                    Some(am) => ("objective.min_crank_arm".into(), format!(
                        "the crank arm r = θR would shrink further: the arm limit ({:.4} mm) sets r",
                        am * 1e3
                    )),
                    None => ("design.theta".into(), format!(
                        "the range, not an interior optimum, sets the crank arm r = θR = {:.4} mm (give objective.min_crank_arm)",
                        t * r * 1e3
                    )),
                },
            }
        };
        for (name, v, b) in [("lambda", l, lb), ("theta", t, tb)] {
            let lower = set_by(name, b.0);
            let upper = (
                format!("design.{name}"),
                "the range's upper end, not an interior optimum, decides the design".to_string(),
            );
            if b.1 > b.0 {
                bounds.extend(ActiveBound::check(
                    &format!("design.{name}"),
                    v,
                    b,
                    1e-6,
                    (&lower.0, &lower.1),
                    (&upper.0, &upper.1),
                ));
            }
        }
        if status != OptStatus::Infeasible && e.suction_gain <= 1e-9 {
            degenerate = Some(format!(
                "the best design found has no suction lengthening (suction gain {:.1e}) with a crank arm \
                 r = θR = {:.4} mm ({:.2} % of R) and a rod L = {:.4} m: it is a plain slider-crank, not the \
                 hypocycloidal machine of paper 004; set hypocycloid.min_suction_gain (as variant 2 does) or a \
                 lower bound on θ to ask for one",
                e.suction_gain,
                t * r * 1e3,
                100.0 * t,
                r / l
            ));
        }
    }
    if scene.coefficients == CoefficientModel::Series {
        warnings.push(format!(
            "model.coefficients = \"series\": the balancing and the objectives use the paper's series truncated at \
             z^{} (y^{}), not the exact coefficients; the coefficient errors reported are the FFT's, not the \
             truncation's",
            scene.series_power,
            2 * scene.series_power
        ));
    }
    if !c.converged {
        warnings.push(format!(
            "the Fourier coefficients did not converge to the rounding floor at n_fft = {} (λ·max|y| = {:.6}); the \
             errors reported are the last change",
            c.n_fft, e.ratio_ymax
        ));
    }
    let n_ord = scene.orders;
    let (sa, sb) = m.series_coefficients(scene.series_power, n_ord);
    let rows: Vec<OrderRow> = (1..=n_ord)
        .map(|i| OrderRow {
            order: i,
            a: c.a[i],
            b: c.b[i],
            error: c.err[i],
            a_series: sa[i],
            b_series: sb[i],
            force_amplitude: fscale * (i * i) as f64 * c.amplitude(i),
            balanced: scene.balance_orders.contains(&i),
        })
        .collect();
    let balancing: Vec<LanchesterPair> = scene
        .balance_orders
        .iter()
        .map(|&i| lanchester_pair(i, c.a[i], c.b[i], scene.m_b, r, scene.omega))
        .collect();
    // Unbalanced peak and residual RMS.
    let unb = periodic_peak_with(|p| m.piston(p).dds.abs(), s.peak_samples, s.peak_tol())
        .map_err(|err| field("design.lambda", l, &err.to_string()))?;
    let rms = periodic_rms(
        |p| residual_rel(&m, c, &scene.balance_orders, p),
        2 * s.peak_samples,
    );
    let cerr: f64 = scene
        .balance_orders
        .iter()
        .map(|&i| (i * i) as f64 * c.err[i])
        .sum();

    let design = Design {
        lambda: l,
        theta: t,
        carrier_radius_m: r,
        crank_arm_m: t * r,
        rod_length_m: r / l,
    };
    let objectives = Objectives {
        c4: c.a[4],
        residual_force_peak_n: fscale * e.residual_peak,
        residual_force_rms_n: fscale * rms.rms,
        unbalanced_force_peak_n: fscale * unb.peak.fx,
        stroke_m: r * e.stroke,
        suction_gain: e.suction_gain,
    };
    let errors = Objectives {
        c4: c.err[4],
        residual_force_peak_n: fscale * e.residual_peak_err,
        residual_force_rms_n: fscale * (rms.error + cerr),
        unbalanced_force_peak_n: fscale * unb.error,
        stroke_m: r * e.stroke_err.max(f64::EPSILON * e.stroke),
        suction_gain: 1e-9 / PI,
    };
    let max_abs_b1_b6 = c.b[1..=6.min(n_ord)]
        .iter()
        .fold(0.0f64, |m, b| m.max(b.abs()));
    let mut derived = Derived {
        b4: c.b[4],
        c4_series: sa[4],
        c4_series_minus_exact: sa[4] - c.a[4],
        lambda_ymax: e.ratio_ymax,
        assembly_margin: 1.0 - e.ratio_ymax,
        n_fft: c.n_fft as f64,
        force_scale_n: fscale,
        force_order4_amplitude_n: fscale * 16.0 * c.amplitude(4),
        suction_angle_rad: (e.suction_gain + 1.0) * PI,
        evaluations: evals as f64,
        zero_curve_series_max_dtheta: None,
        zero_curve_series_worst_lambda: None,
        zero_roots: None,
        zero_max_abs_at_root: None,
        omega_rad_s: scene.omega,
        max_abs_b1_b6,
        force_ratio_order3_to_order1: 9.0 * c.a[3].hypot(c.b[3]) / c.a[1].hypot(c.b[1]),
    };

    // Zero search.
    let (zsr, zero_curve, zero_curve_series) = match &scene.zero_search {
        Some(zs) => {
            let z = zero_search(
                scene.alpha0,
                zs,
                scene.series_power,
                scene.assembly_margin,
                s,
            );
            evals += z.evals;
            let zc = z
                .roots
                .iter()
                .map(|r| ZeroPoint {
                    lambda: r.lambda,
                    theta: r.theta,
                })
                .collect();
            let zcs = z
                .roots
                .iter()
                .filter_map(|r| {
                    r.series_theta.map(|t| ZeroPoint {
                        lambda: r.lambda,
                        theta: t,
                    })
                })
                .collect();
            if !z.single_valued {
                warnings.push("the zero set has several branches in some λ columns".into());
            }
            if let Some(zb) = z
                .roots
                .iter()
                .map(|r| (r.series_theta.map(|t| (t - r.theta).abs()), r))
                .fold(None, |acc: Option<(f64, ZeroRoot)>, (d, r)| match d {
                    Some(d) if acc.is_none_or(|a| d > a.0) => Some((d, *r)),
                    _ => acc,
                })
            {
                derived.zero_curve_series_max_dtheta = Some(zb.0);
                derived.zero_curve_series_worst_lambda = Some(zb.1.lambda);
            }
            let missing = z.roots.iter().filter(|r| r.series_theta.is_none()).count();
            if missing > 0 {
                warnings.push(format!(
                    "the truncated series (power {}) has no zero in {missing} of the {} λ columns where the exact \
                     coefficient has one",
                    scene.series_power,
                    z.roots.len()
                ));
            }
            derived.zero_roots = Some(z.roots.len() as f64);
            derived.zero_max_abs_at_root = Some(z.max_abs_at_root);
            (Some(z), zc, zcs)
        }
        None => (None, Vec::new(), Vec::new()),
    };
    let paper = paper_checks(scene, &m, c, &sa, &sb, zsr.as_ref());

    // Curves for plots.
    let np = s.plot_samples;
    let phi: Vec<f64> = (0..np)
        .map(|j| 2.0 * PI * j as f64 / (np - 1) as f64)
        .collect();
    let force_curves = ForceCurves {
        unbalanced: phi.iter().map(|&p| -fscale * m.piston(p).dds).collect(),
        residual: phi
            .iter()
            .map(|&p| fscale * residual_rel(&m, c, &scene.balance_orders, p))
            .collect(),
        position: phi.iter().map(|&p| r * m.piston(p).s_rel).collect(),
        phi,
    };
    let method = format!(
        "{method}; coefficients: exact polynomial part + FFT of the O(λ³) remainder (n = {}); zero search: sign scan \
         + argmin Brent to {:e}; {evals} evaluations",
        c.n_fft, s.root_tol
    );
    Ok(Outcome {
        design,
        objectives,
        errors,
        derived,
        warnings,
        paper,
        method,
        status,
        search,
        degenerate,
        bounds,
        coefficients: CoefficientTable {
            a: c.a[..=n_ord].to_vec(),
            b: c.b[..=n_ord].to_vec(),
            error: c.err[..=n_ord].to_vec(),
            a_series: sa,
            b_series: sb,
            series_power: scene.series_power,
            n_fft: c.n_fft,
            converged: c.converged,
            rows,
        },
        balancing,
        zero_curve,
        zero_curve_series,
        zero_search: zsr,
        force_curves,
    })
}

/// What the paper states (it prints no numbers, only structure and claims) against the
/// computation.
#[allow(clippy::needless_range_loop)] // indexes a, b, series a, series b together
fn paper_checks(
    scene: &HypocycloidScene,
    m: &Hypocycloid,
    c: &Coefficients,
    sa: &[f64],
    sb: &[f64],
    z: Option<&ZeroSearchResult>,
) -> Vec<PaperCheck> {
    let mut v = Vec::new();
    let p = scene.series_power;
    let v2 = (scene.alpha0 - ALPHA0_VARIANT2).rem_euclid(2.0 * PI) < 1e-12;
    let v1 = scene.alpha0.rem_euclid(2.0 * PI) < 1e-12;
    for i in 1..=6 {
        v.push(PaperCheck::new(
            format!("a{i} (C{i}{})", if v2 { "^I" } else { "" }),
            format!("coefficients.a.{i}"),
            sa[i],
            c.a[i],
            format!(
                "paper's method = binomial series to z^{p} (y^{}); difference {:.3e} (series truncation error; the \
                 exact value's error is {:.1e})",
                2 * p,
                sa[i] - c.a[i],
                c.err[i]
            ),
        ));
    }
    if v2 {
        v.push(PaperCheck::new(
            "C1^I (from m'_I r'_I = ½ m_B R)",
            "coefficients.a.1",
            1.0,
            c.a[1],
            "the root contributes no cos φ term in variant 2 (its cosine part has only even orders)",
        ));
        v.push(PaperCheck::new(
            "C2^II (sine part of order 2)",
            "coefficients.b.2",
            sb[2],
            c.b[2],
            "−θ exactly: only the crank term −θ sin 2φ contributes; the root's sine part has odd orders only",
        ));
        v.push(PaperCheck::new(
            "a3 (paper: the cosine part S^I has no 3rd order)",
            "coefficients.a.3",
            0.0,
            c.a[3],
            "zero by the symmetry y(π − φ) = y(φ)",
        ));
    }
    if v1 {
        v.push(PaperCheck::new(
            "b1..b6 (paper: only cosines in variant 1)",
            key!("derived", Derived, max_abs_b1_b6),
            0.0,
            c.b[1..=6].iter().fold(0.0f64, |a, &b| a.max(b.abs())),
            "S is even in φ because y is odd: max |b_i| shown",
        ));
    }
    // The paper calls the 3rd-order force negligible ("C3, C1^II, C3^II ~ λθ").
    let f1 = c.amplitude(1);
    let f3 = 9.0 * c.amplitude(3);
    v.push(PaperCheck::new(
        "|Φ3|/|Φ1| (paper: 3rd order negligible, ∝ λθ)",
        key!("derived", Derived, force_ratio_order3_to_order1),
        0.0,
        f3 / f1,
        format!(
            "the coefficient is O(λθ) = {:.3} but the force carries i² = 9: at λ = {}, θ = {} the 3rd-order force is \
             {:.0}% of the 1st",
            m.lambda * m.theta,
            m.lambda,
            m.theta,
            100.0 * f3 / f1
        ),
    ));
    if let Some(z) = z {
        let computed = match z.status {
            ZeroStatus::Found => z.max_abs_at_root,
            _ => z.grid_min_abs.map(|g| g.value.abs()).unwrap_or(f64::NAN),
        };
        v.push(PaperCheck::new(
            format!(
                "a{} = 0 for some (λ, θ) (paper's conjecture, variant 2)",
                z.order
            ),
            match z.status {
                ZeroStatus::Found => "zero_search.max_abs_at_root",
                _ => "zero_search.min_abs",
            },
            0.0,
            if computed.is_finite() { computed } else { -1.0 },
            match z.status {
                ZeroStatus::Found => format!(
                    "{} roots found; computed = max |a| at a root. {}",
                    z.roots.len(),
                    z.reason
                ),
                ZeroStatus::NoZero => {
                    format!("no zero; computed = min |a| on the grid. {}", z.reason)
                }
                ZeroStatus::Infeasible => z.reason.clone(),
            },
        ));
    }
    v
}
