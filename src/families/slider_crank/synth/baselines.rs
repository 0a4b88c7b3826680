//! The classical counterweights (none, y force zeroed, 50 %, equal x and y ranges) and
//! their figures, for comparison with the optimum.

use super::drive::energy_fluctuation;
use super::fields::{scene_force, Sampled};
use super::metrics::{grid_extremes, grid_x_extremes, metrics_sampled, value_xtol};
use super::outcome::Metrics;
use super::scene::{check, Objective, Scene, SolveError};
use crate::geom::P2;
use crate::numeric::{newton_polish, newton_root, refine_periodic_sample};
use std::collections::BTreeMap;

/// The classical counterweights, opposite the crank pin (β = π), as unbalances (kg·m).
///
/// * `none`: U = 0;
/// * `y_force_zeroed`: U = −m_tq R e_x, which cancels F_y exactly (every link's y motion
///   is proportional to sin φ);
/// * `fifty_percent`: U = −(m_tq + ½ m_ct) R e_x;
/// * `equal_ranges`: U = −κ e_x with κ ∈ [m_tq R, (m_tq + m_ct) R] such that the
///   peak-to-peak ranges of F_x and F_y are equal (Brent on κ).
pub fn baselines(scene: &Scene) -> Result<BTreeMap<String, Metrics>, SolveError> {
    check(scene)?;
    baselines_sampled(scene, &Sampled::new(scene))
}

/// Completes a baseline's figures `m` (of its unbalance, on `scene` without balancers) with
/// what the scene judges it on beyond [`metrics_sampled`]: its ΔE with the energy-fluctuation
/// objective, its worst case over an operating envelope.
pub fn judge_baseline(scene: &Scene, m: &mut Metrics) -> Result<(), SolveError> {
    let u = P2::from(m.unbalance);
    if scene.objective == Objective::MinEnergyFluctuation {
        m.energy_fluctuation = Some(energy_fluctuation(scene, u)?);
    }
    if !scene.envelope.is_empty() {
        m.worst_case = Some(scene.envelope.worst_of(scene, u, scene.objective)?);
    }
    Ok(())
}

pub(super) fn baselines_sampled(
    scene: &Scene,
    tab: &Sampled,
) -> Result<BTreeMap<String, Metrics>, SolveError> {
    let mech = &scene.mech;
    let (mt, mc, r) = (mech.m_rot(), mech.m_rec(), mech.r);
    let mut out = BTreeMap::new();
    for (name, k) in [
        ("none", 0.0),
        ("y_force_zeroed", mt * r),
        ("fifty_percent", (mt + 0.5 * mc) * r),
    ] {
        out.insert(
            name.to_string(),
            metrics_sampled(scene, P2::new(-k, 0.0), tab)?,
        );
    }
    // For U = −κ e_x every link's y motion is proportional to sin φ, so F_y = ω²(m_tq R − κ)
    // sin φ and its range is 2ω²|m_tq R − κ| in closed form; only the x range needs peaks.
    // F_x = ω²(f₀ₓ(φ) − κ cos φ), so by the envelope theorem d(range)/dκ = ω²(cos φ₋ − cos φ₊)
    // (φ₊, φ₋ the angles of the max and the min), and D(κ) = range − 2ω²(κ − m_tq R) is
    // found by safeguarded Newton on [m_tq R, (m_tq + m_ct) R].
    // The root of the sampled D (extremes of the scan grid, piecewise linear in κ, cheap)
    // is within O(h²) of the refined one; a few Newton steps on the refined D from there
    // finish it (the full safeguarded search again if they do not converge).
    let w2 = scene.omega * scene.omega;
    let diff = |refined: bool| {
        move |k: f64| {
            x_range_sampled(scene, k, tab, refined)
                .map(|(x, cp, cm)| (x - 2.0 * w2 * (k - mt * r), w2 * (cm - cp) - 2.0 * w2))
                .unwrap_or((f64::NAN, f64::NAN))
        }
    };
    let (lo, hi) = (mt * r, (mt + mc) * r);
    let tol = 1e-12 * hi.max(1e-300);
    // The polish first refines only the grid extremes of the sampled root (no scan for
    // other candidates: ~12 evaluations a step instead of a scan and ~12); the root's
    // figures below are computed with the full scan, and if their range is not the one the
    // polish converged on (another extreme took over), the polish runs again with the full
    // scan at every step.
    let near = |k: (usize, usize)| {
        move |kappa: f64| {
            x_range_near(scene, kappa, tab, k)
                .map(|(x, cp, cm)| (x - 2.0 * w2 * (kappa - mt * r), w2 * (cm - cp) - 2.0 * w2))
                .unwrap_or((f64::NAN, f64::NAN))
        }
    };
    let full = |x0: f64| {
        newton_polish(diff(true), x0, lo, hi, tol, 6)
            .map_or_else(|| newton_root(diff(true), lo, hi, tol), Ok)
    };
    let root = newton_root(diff(false), lo, hi, 1e-6 * hi).and_then(|sampled| {
        let ((_, k_hi), (_, k_lo)) = grid_x_extremes(&tab.scan, sampled.x, w2);
        let k = (k_hi, k_lo);
        match newton_polish(near(k), sampled.x, lo, hi, tol, 6) {
            Some(r) => Ok((r, Some(k))),
            None => full(sampled.x).map(|r| (r, None)),
        }
    });
    if let Ok((mut root, k)) = root {
        let mut m = metrics_sampled(scene, P2::new(-root.x, 0.0), tab)?;
        let local = k
            .and_then(|k| x_range_near(scene, root.x, tab, k))
            .map(|(x, _, _)| x);
        if k.is_some() && local != Some(m.ptp_x) {
            if let Ok(r) = full(root.x) {
                root = r;
                m = metrics_sampled(scene, P2::new(-root.x, 0.0), tab)?;
            }
        }
        out.insert("equal_ranges".to_string(), m);
    }
    Ok(out)
}

/// max F_x − min F_x (N) of the counterweight U = −κ e_x, from the remembered kinematics
/// (the part of [`metrics`] the `equal_ranges` root search needs), with cos φ at the maximum
/// and at the minimum (the envelope theorem gives the range's derivative in κ from them).
/// `refined`: the extremes refined as in [`metrics`]; else those of the scan grid, found by
/// one tight pass over F_x(φₖ) = ω²(f₀ₓ(φₖ) − κ cos φₖ).
pub(super) fn x_range_sampled(
    scene: &Scene,
    kappa: f64,
    tab: &Sampled,
    refined: bool,
) -> Result<(f64, f64, f64), SolveError> {
    let (omega, s) = (scene.omega, &scene.settings);
    let w2 = omega * omega;
    let g = &tab.scan;
    if !refined {
        let (hi, lo) = grid_x_extremes(g, kappa, w2);
        if !(hi.0 - lo.0).is_finite() {
            return Err(SolveError::Numeric(
                "F_x is not finite on the scan grid".into(),
            ));
        }
        return Ok((hi.0 - lo.0, g.cs[hi.1][0], g.cs[lo.1][0]));
    }
    let u = P2::new(-kappa, 0.0);
    let f = |phi: f64| scene_force(scene, u, phi).x;
    let xs: Vec<f64> = (0..g.len()).map(|k| g.force(k, u, w2).x).collect();
    let scale = xs.iter().fold(0.0, |a: f64, &b| a.max(b.abs()));
    let (xmax, xmin) = grid_extremes(&xs, f, scale, true, s)?;
    let xmin = xmin.expect("asked");
    Ok((
        xmax.peak.fx + xmin.peak.fx,
        xmax.peak.x.cos(),
        xmin.peak.x.cos(),
    ))
}

/// max F_x − min F_x (N) of U = −κ e_x, with cos φ at the maximum and at the minimum (as
/// [`x_range_sampled`]), refined only from the scan grid's samples `k` = (index of the
/// maximum, index of the minimum) as [`grid_extremes`] refines a candidate (the same
/// numbers when they are the global extremes). `None` when either sample is no longer a
/// sampled extreme at this κ.
pub(super) fn x_range_near(
    scene: &Scene,
    kappa: f64,
    tab: &Sampled,
    (k_hi, k_lo): (usize, usize),
) -> Option<(f64, f64, f64)> {
    let w2 = scene.omega * scene.omega;
    let u = P2::new(-kappa, 0.0);
    let g = &tab.scan;
    let n = g.len();
    let h = std::f64::consts::TAU / n as f64;
    let xtol = value_xtol(&scene.settings);
    let f = |phi: f64| scene_force(scene, u, phi).x;
    let refine = |k: usize, sign: f64| {
        let around = [(k + n - 1) % n, k, (k + 1) % n].map(|j| sign * g.force(j, u, w2).x);
        refine_periodic_sample(|p| sign * f(p), k as f64 * h, h, around, xtol).ok()
    };
    let ((hi, _), (lo, _)) = (refine(k_hi, 1.0)?, refine(k_lo, -1.0)?);
    Some((hi.fx + lo.fx, hi.x.cos(), lo.x.cos()))
}
