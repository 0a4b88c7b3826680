//! The torque–force Pareto front (ε-constraint) and the speed sweep: the scene solved again
//! with other limits or at other speeds.

use super::drive::energy_fluctuation;
use super::fields::Sampled;
use super::metrics::{metrics, metrics_sampled};
use super::optimise::{optimise, optimise_with};
use super::outcome::{Metrics, Optimum, ParetoPoint};
use super::scene::{check, Objective, Scene, SolveError};
use crate::geom::P2;

/// The Pareto front of the peak drive torque (or, with the energy-fluctuation objective, of
/// ΔE) against the peak shaking force by the ε-constraint method: the force optimum F* and
/// the other objective's optimum (whose peak force is F_T) bound the front; for `n` limits ε
/// spaced evenly in [F*, F_T], minimise the other objective subject to peak force ≤ ε.
pub fn pareto(scene: &Scene, n: usize) -> Result<Vec<ParetoPoint>, SolveError> {
    check(scene)?;
    pareto_sampled(scene, n, &Sampled::new(scene))
}

pub(super) fn pareto_sampled(
    scene: &Scene,
    n: usize,
    tab: &Sampled,
) -> Result<Vec<ParetoPoint>, SolveError> {
    let g = &tab.scan;
    let energy = scene.objective == Objective::MinEnergyFluctuation;
    let traded = if energy {
        Objective::MinEnergyFluctuation
    } else {
        Objective::MinPeakTorque
    };
    // The torque limit stays on every point of a ΔE front (and on the force optimum).
    let torque_limit = if energy { scene.max_peak_torque } else { None };
    let f_opt = optimise_with(
        scene,
        Objective::MinPeakForce,
        None,
        scene.max_peak_torque,
        g,
    )?;
    let t_opt = optimise_with(scene, traded, scene.max_peak_force, torque_limit, g)?;
    // Each design on its own scene: a joint design's with its balancers (the scene passed
    // in carries the main design's), else the scene's table.
    let figures = |o: &Optimum| -> Result<(Metrics, Option<[f64; 2]>), SolveError> {
        let designed = (!o.balancers.is_empty()).then(|| scene.with_balancers(&o.balancers));
        let on = designed.as_ref().unwrap_or(scene);
        let m = match &designed {
            Some(d) => metrics(d, o.u)?,
            None => metrics_sampled(scene, o.u, tab)?,
        };
        let de = energy.then(|| energy_fluctuation(on, o.u)).transpose()?;
        Ok((m, de))
    };
    let fmin = figures(&f_opt)?.0.peak;
    let fmax = figures(&t_opt)?.0.peak;
    let n = n.max(2);
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        // Slightly above F* so that the first point is feasible despite the gap.
        let eps = if k == 0 {
            fmin * (1.0 + 10.0 * scene.settings.rel_tol)
        } else {
            fmin + (fmax - fmin) * k as f64 / (n - 1) as f64
        };
        let o = optimise_with(scene, traded, Some(eps), torque_limit, g)?;
        let (m, de) = figures(&o)?;
        out.push(ParetoPoint {
            force_limit_n: eps,
            peak_shaking_force_n: m.peak,
            peak_drive_torque_nm: m.peak_torque,
            gap_nm: (!energy).then_some(o.gap),
            energy_fluctuation_j: de.map(|e| e[0]),
            gap_j: de.map(|e| o.gap + e[1]),
            unbalance_x_kgm: o.u.x,
            unbalance_y_kgm: o.u.y,
            balancers_kgm: o.balancers.clone(),
            status: o.status,
        });
    }
    Ok(out)
}

/// A resolved speed sweep (rad/s).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SpeedSweep {
    /// Lowest ω.
    pub min: f64,
    /// Highest ω.
    pub max: f64,
    /// Number of speeds.
    pub points: usize,
}

/// One speed of a sweep: the optimum there, and the scene's design evaluated there.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SweepPoint {
    /// Speed (rad/s).
    pub omega_rad_s: f64,
    /// Speed (rpm), for reading.
    pub speed_rpm: f64,
    /// |U| of the optimum at this speed (kg·m).
    pub optimal_unbalance_kgm: f64,
    /// Objective value of that optimum (N or N·m).
    pub optimal_objective: f64,
    /// The same objective for the design found at the scene's own speed.
    pub design_objective: f64,
    /// The same objective without counterweight.
    pub none_objective: f64,
    /// Solver status at this speed.
    pub status: crate::report::Status,
}

/// Re-optimises the scene at each speed of the sweep and evaluates the design `u` (found at
/// the scene's own speed) and no counterweight there, in the scene's objective; a speed whose
/// solve fails is left out with a warning.
pub fn speed_sweep(s: &Scene, sw: &SpeedSweep, u: P2) -> (Vec<SweepPoint>, Vec<String>) {
    let value = |at: &Scene, u: P2, m: &Metrics| -> Result<f64, SolveError> {
        Ok(match s.objective {
            Objective::MinPeakTorque => m.peak_torque,
            Objective::MinRmsForce => m.rms,
            Objective::MinEnergyFluctuation => energy_fluctuation(at, u)?[0],
            _ => m.peak,
        })
    };
    let mut pts = Vec::with_capacity(sw.points);
    let mut warnings = Vec::new();
    for k in 0..sw.points {
        let omega = sw.min + (sw.max - sw.min) * k as f64 / (sw.points - 1) as f64;
        let at = Scene { omega, ..s.clone() };
        let point = optimise(&at).and_then(|o| {
            let opt = metrics(&at, o.u)?;
            let des = metrics(&at, u)?;
            let none = metrics(&at, P2::zeros())?;
            Ok(SweepPoint {
                omega_rad_s: omega,
                speed_rpm: omega * 60.0 / std::f64::consts::TAU,
                optimal_unbalance_kgm: o.u.norm(),
                optimal_objective: value(&at, o.u, &opt)?,
                design_objective: value(&at, u, &des)?,
                none_objective: value(&at, P2::zeros(), &none)?,
                status: crate::families::family::cw_status(o.status),
            })
        });
        match point {
            Ok(p) => pts.push(p),
            Err(e) => warnings.push(format!("speed sweep at {omega:.3} rad/s: {e}")),
        }
    }
    (pts, warnings)
}
