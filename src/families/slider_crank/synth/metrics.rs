//! The refined figures of one counterweight ([`metrics`]): the peaks of |F|, F_x and |T|
//! refined from the scan grid, the RMS, and their errors.

use super::fields::{
    drive_torque, scene_force, torque_independent_of_counterweight, Grid, Sampled,
};
use super::outcome::Metrics;
use super::round_off::round_off_bounds;
use super::scene::{Scene, SolveError};
use crate::geom::P2;
use crate::numeric::{periodic_rms_sampled, Extremum, PeriodicPeak, Refine, Shape};
use crate::synth::counterweight::{self as cw};

/// Refined figures of the counterweight `u` (kg·m).
pub fn metrics(scene: &Scene, u: P2) -> Result<Metrics, SolveError> {
    metrics_sampled(scene, u, &Sampled::new(scene))
}

pub(super) fn metrics_sampled(scene: &Scene, u: P2, tab: &Sampled) -> Result<Metrics, SolveError> {
    let (omega, s) = (scene.omega, &scene.settings);
    let w2 = omega * omega;
    let g = scene.loads.gravity;
    let f = |phi: f64| scene_force(scene, u, phi);
    // The sampled figures in one pass: F_x, |F| and |T| on the scan grid.
    let n = tab.scan.len();
    // The three columns in one buffer kept by the table (no allocation per counterweight);
    // every element is written before it is read.
    let mut cols = tab.scratch.borrow_mut();
    cols.resize(3 * n, 0.0);
    let (fx, rest) = cols.split_at_mut(n);
    let (norms, ts) = rest.split_at_mut(n);
    for k in 0..n {
        let v = tab.scan.force(k, u, w2);
        fx[k] = v.x;
        norms[k] = (v.x * v.x + v.y * v.y).sqrt();
        ts[k] = tab.scan.torque(k, g, u).abs();
    }
    let scale = norms.iter().fold(0.0, |a: f64, &b| a.max(b));
    let (pk, _) = grid_extremes(norms, |p| f(p).norm(), scale, false, s)?;
    let (xmax, xmin) = grid_extremes(fx, |p| f(p).x, scale, true, s)?;
    let xmin = xmin.expect("asked");
    // F_y is one harmonic: max F_y = −min F_y in closed form, exact (no sampling error).
    let y_amp = w2 * scene.mech.force_y_amplitude(u);
    // Without gravity the drive torque does not depend on the counterweight (its weight is
    // its only path into the torque): every counterweight of the table has the same peak,
    // computed once (the same numbers bit for bit: the weight term adds ±0).
    let torque_peak = || -> Result<(f64, f64, f64), SolveError> {
        let tscale = ts.iter().fold(0.0, |a: f64, &b| a.max(b));
        let (tq, _) = grid_extremes(ts, |p| drive_torque(scene, u, p).abs(), tscale, false, s)?;
        Ok((tq.peak.fx, tq.peak.x, tq.error))
    };
    let fixed = torque_independent_of_counterweight(scene);
    let (tq_peak, tq_angle, tq_error) = match tab.torque_peak.get().filter(|_| fixed) {
        Some(t) => *t,
        None => {
            let t = torque_peak()?;
            if fixed {
                let _ = tab.torque_peak.set(t);
            }
            t
        }
    };
    let rms = if tab.rms.is_none() {
        periodic_rms_sampled(norms)
    } else {
        periodic_rms_sampled(
            &(0..tab.rms().len())
                .map(|k| tab.rms().force(k, u, w2).norm())
                .collect::<Vec<f64>>(),
        )
    };
    // Round-off of each evaluation (conditioning), on top of sampling and refinement.
    let [ro_f, ro_t, _] = round_off_bounds(scene, u);
    Ok(Metrics {
        unbalance: [u.x, u.y],
        peak: pk.peak.fx,
        peak_angle: pk.peak.x,
        peak_error: pk.error + ro_f,
        rms: rms.rms,
        rms_error: rms.error + ro_f,
        ptp_x: xmax.peak.fx + xmin.peak.fx,
        ptp_y: 2.0 * y_amp,
        peak_x: xmax.peak.fx.max(xmin.peak.fx),
        peak_y: y_amp,
        peak_torque: tq_peak,
        peak_torque_angle: tq_angle,
        peak_torque_error: tq_error + ro_t,
        energy_fluctuation: None,
        worst_case: None,
    })
}

/// The peak of a periodic function from its samples on the scan grid, refined by `f` to
/// `peak_xtol`, but not below 1e-8 rad (√ε: the value is then exact to round-off), and with
/// `minima` also the peak of −f (the negated minimum). `scale` is the size of the figure
/// the function is part of (e.g. the peak |F| for a component of F): a function whose
/// samples vary by less than 1e-12 of it is zero or constant up to round-off (F_y with the
/// y force zeroed, the torque of a balanced rotor), so its best sample is the peak, with
/// that variation as the error, and the round-off wiggles are not refined one by one.
pub(super) fn grid_extremes(
    ys: &[f64],
    f: impl Fn(f64) -> f64,
    scale: f64,
    minima: bool,
    s: &cw::Settings,
) -> Result<(PeriodicPeak, Option<PeriodicPeak>), SolveError> {
    let num = |e: crate::numeric::SearchError| SolveError::Numeric(e.to_string());
    let shape = Shape::of(ys, minima, Refine::PeakOnly).map_err(num)?;
    let spread = shape.best - shape.worst;
    let peak = |sign: f64| -> Result<PeriodicPeak, SolveError> {
        if spread <= 1e-12 * scale {
            let target = if sign > 0.0 { shape.best } else { shape.worst };
            let k = ys.iter().position(|&y| y == target).unwrap_or(0);
            let best = Extremum {
                x: k as f64 * shape.h,
                fx: sign * target,
            };
            return Ok(PeriodicPeak {
                maxima: vec![best],
                peak: best,
                error: spread,
                evals: 0,
            });
        }
        shape.peak(ys, sign, &f, Some(value_xtol(s))).map_err(num)
    };
    Ok((peak(1.0)?, if minima { Some(peak(-1.0)?) } else { None }))
}

/// The angle tolerance of a refined figure: `peak_xtol`, but not below 1e-8 rad. A value
/// needs its maximum located only to √ε (≈ 1e-8 rad): closer, the values differ by
/// round-off (½|f''|δ² < ε|f|).
pub(super) fn value_xtol(s: &cw::Settings) -> f64 {
    s.peak_xtol.max(1e-8)
}

/// The largest and smallest F_x(φₖ) = ω²(f₀ₓ(φₖ) − κ cos φₖ) of U = −κ e_x on the grid
/// `g`, each with its index, in one tight pass.
pub(super) fn grid_x_extremes(g: &Grid, kappa: f64, w2: f64) -> ((f64, usize), (f64, usize)) {
    let (mut hi, mut lo) = ((f64::NEG_INFINITY, 0), (f64::INFINITY, 0));
    for (k, (f0, [c, _])) in g.f0.iter().zip(&g.cs).enumerate() {
        let x = w2 * (f0.x - kappa * c);
        if x > hi.0 {
            hi = (x, k);
        }
        if x < lo.0 {
            lo = (x, k);
        }
    }
    (hi, lo)
}
