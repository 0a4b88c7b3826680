//! What `cwsynth study` varies for a hypocycloid scene — its ladder of accuracy and model
//! settings — and the effects its model leaves out or includes, each with a bound computed
//! from the scene as resolved.

use super::model::{max_abs_y, Hypocycloid};
use super::synth::{CoefficientModel, Design, Objectives};
use crate::families::family::{relative, Effect, Ladder, Rung};
use crate::problem::edit::{v_f, v_int, v_s, Edit};
use crate::report::numbers::key;
use crate::report::SolveResult;
use crate::units::rad_text;
use crate::units::STANDARD_GRAVITY as G;
use std::f64::consts::TAU;
use toml_edit::Value;

/// The headline: the dotted result key a design is judged on (see
/// [`crate::families::Machine::headline`]).
pub fn headline(p: &super::file::HypocycloidProblem) -> String {
    format!(
        "objectives.{}",
        super::synth::Objectives::key(p.scene.zero_search.is_some())
    )
}

/// The reference edits (tightest settings) and the ladder of settings.
pub fn ladder(_s: &super::file::HypocycloidProblem) -> Ladder {
    use Edit::Set;
    let reference = vec![
        Set("accuracy.n_fft_min", v_int(8192)),
        Set("accuracy.n_fft_max", v_int(1 << 18)),
        Set("accuracy.peak_samples", v_int(4096)),
        Set("accuracy.peak_xtol", v_s(&rad_text(1e-12))),
        Set("accuracy.root_tol", v_f(1e-14)),
    ];
    let mut l = Vec::new();
    // One fixed FFT size, no adaptive doubling (orders ≥ n/2 of the remainder left out).
    for n in [16i64, 32, 64] {
        l.push(Rung::new(
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
        l.push(Rung::new(
            &format!("peak scan {n}, unrefined"),
            "accuracy",
            vec![
                Set("accuracy.refine_peaks", Value::from(false)),
                Set("accuracy.peak_samples", v_int(n)),
            ],
        ));
    }
    l.push(Rung::new(
        "peak scan 32, refined",
        "accuracy",
        vec![Set("accuracy.peak_samples", v_int(32))],
    ));
    // The paper's method: coefficients from the binomial series truncated at z^p.
    for p in [1i64, 2, 3, 6] {
        l.push(Rung::new(
            &format!("paper series, power {p}"),
            "model",
            vec![
                Set("model.coefficients", v_s("series")),
                Set("model.series_power", v_int(p)),
            ],
        ));
    }
    Ladder {
        reference,
        rungs: l,
    }
}

/// c_k of sqrt(1 − z) = 1 − Σ_k c_k z^k: c_1 = ½, c_{k+1} = c_k (2k − 1)/(2k + 2).
fn binomial_c(k: usize) -> f64 {
    (1..k).fold(0.5, |c, j| {
        c * (2.0 * j as f64 - 1.0) / (2.0 * j as f64 + 2.0)
    })
}

/// Bound T_P on the tail of the paper's series left out at power P:
/// |S/R − (S/R)^(P)| = (1/λ)·Σ_{k>P} c_k z^k ≤ c_{P+1} z_max^{P+1} / (λ (1 − z_max)),
/// z_max = (λ·max|y_A/R|)² (the c_k decrease). Every Fourier coefficient of the tail then
/// has hypot(Δa_i, Δb_i) ≤ 2·T_P. `None` when the mechanism cannot assemble (z_max ≥ 1).
pub fn series_tail_bound(lambda: f64, theta: f64, alpha0: f64, power: usize) -> Option<f64> {
    let ym = max_abs_y(theta, alpha0).ok()?;
    let z = (lambda * ym).powi(2);
    if !(z < 1.0) || lambda <= 0.0 {
        return None;
    }
    Some(binomial_c(power + 1) * z.powi(power as i32 + 1) / (lambda * (1.0 - z)))
}

/// Σ_{i∈K} i²·hypot(Δa_i, Δb_i) between the paper's series of power `power` and the exact
/// coefficients, and |Δa_4|: the residual force (per m_B R ω²) can change by at most the
/// first (triangle inequality), C4 by the second.
pub fn series_change(m: &Hypocycloid, power: usize, orders: &[usize]) -> (f64, f64) {
    let n = orders.iter().copied().max().unwrap_or(0).max(4);
    let c = m.coefficients(n, 64, 1 << 16);
    let (sa, sb) = m.series_coefficients(power, n);
    let force = orders
        .iter()
        .map(|&i| (i * i) as f64 * (sa[i] - c.a[i]).hypot(sb[i] - c.b[i]))
        .sum();
    (force, (sa[4] - c.a[4]).abs())
}

/// What the model leaves out or includes, with a bound for each effect (see
/// [`crate::families::Machine::effects`]).
pub fn effects(
    h: &crate::families::hypocycloid::file::HypocycloidProblem,
    reference: &SolveResult,
    headline: f64,
) -> Vec<Effect> {
    let sc = &h.scene;
    let (Some(lambda), Some(theta)) = (
        reference.lookup(key!("design", Design, lambda)),
        reference.lookup(key!("design", Design, theta)),
    ) else {
        return vec![(
            "model limits".into(),
            "the reference has no design (λ, θ): no bound computed".into(),
        )];
    };
    let m = Hypocycloid {
        lambda,
        theta,
        alpha0: sc.alpha0,
    };
    let p = sc.series_power;
    let fscale = sc.m_b * sc.r_carrier * sc.omega * sc.omega;
    let sum_i2: f64 = sc.balance_orders.iter().map(|&i| (i * i) as f64).sum();
    let c4_headline = sc.zero_search.is_some();
    let residual = reference
        .lookup(key!("objectives", Objectives, residual_force_peak_n))
        .unwrap_or(f64::NAN);
    let mut out = Vec::new();
    // Series truncation.
    if let Some(t) = series_tail_bound(lambda, theta, sc.alpha0, p) {
        let (df, da4) = series_change(&m, p, &sc.balance_orders);
        let z = (lambda * max_abs_y(theta, sc.alpha0).unwrap_or(f64::NAN)).powi(2);
        let head = if c4_headline {
            format!(
                "C4 changes by |Δa4| = {da4:.3e} ≤ 2T = {:.3e} ({:.2e} of the headline C4)",
                2.0 * t,
                relative(2.0 * t, headline)
            )
        } else {
            format!(
                "the residual force peak changes by at most m_B R ω²·Σ_(i∈K) i²·hypot(Δa_i, Δb_i) = {:.4e} N ≤ m_B R ω²·2T·Σ_(i∈K) i² = {:.4e} N ({:.2e} of the headline)",
                fscale * df,
                fscale * 2.0 * t * sum_i2,
                relative(fscale * 2.0 * t * sum_i2, headline)
            )
        };
        let what = match sc.coefficients {
            CoefficientModel::Exact => format!(
                "exact coefficients (nothing left out); the paper's series truncated at z^{p} would leave out"
            ),
            CoefficientModel::Series => format!(
                "the paper's series truncated at z^{p} (model.coefficients = \"series\") leaves out"
            ),
        };
        out.push((
            "series truncation".into(),
            format!(
                "{what} the tail (1/λ)·Σ_(k>{p}) c_k z^k ≤ T = c_{} z_max^{}/(λ(1 − z_max)) = {t:.3e} (z_max = (λ·max|y_A/R|)² = {z:.4}, λ = {lambda:.6}, θ = {theta:.6}); each hypot(Δa_i, Δb_i) ≤ 2T; {head}",
                p + 1,
                p + 1
            ),
        ));
    }
    // Weights against inertia.
    let w = sc.m_b * G;
    let ratio = G / (sc.r_carrier * sc.omega * sc.omega);
    let ds_max = (0..720)
        .map(|k| m.piston(k as f64 * TAU / 720.0).ds.abs())
        .fold(0.0f64, f64::max);
    let c_sum: f64 = sc
        .balance_orders
        .iter()
        .map(|&i| {
            let c = m.coefficients(i, 64, 1 << 16);
            c.a[i].hypot(c.b[i])
        })
        .sum();
    out.push((
        "weights".into(),
        format!(
            "left out (kinematic balancing of the reciprocating mass only): g/(Rω²) = {ratio:.3e}. The weight W = m_B g = {w:.4} N is constant, so it changes no order's force nor the Lanchester pairs; as a frame load it is {:.2e} of the residual force peak {residual:.4e} N. Left out of the drive torque: the pairs' weights, ≤ m_B R g·Σ_(i∈K) C_i = {:.4e} N·m, and, were the cylinder vertical, the piston's, W·R·max|dS/dφ|/R = {:.4e} N·m",
            relative(w, residual),
            sc.m_b * sc.r_carrier * G * c_sum,
            w * sc.r_carrier * ds_max
        ),
    ));
    out.push((
        "other masses, friction".into(),
        "left out, no bound: the scene gives only m_B (no rod, carrier, planet or counter-mass inertias, no friction data), so their effect cannot be computed from it".into(),
    ));
    out
}

// ---------------------------------------------------------------------------------------
// Luffing crane
// ---------------------------------------------------------------------------------------
