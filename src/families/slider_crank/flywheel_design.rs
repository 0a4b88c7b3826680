//! The flywheel-inertia objective (issue 33, "design for the drive"): the counterweight whose
//! exact least flywheel for the drive's Cs is least, under the file's peak-force and
//! peak-torque limits.
//!
//! The least flywheel I_f(U) is the root of Cs(I_f; U) = Cs over the periodic steady state
//! ([`crate::dynamics::least_flywheel`]): U enters through the counterweight's weight in G(φ)
//! and its own inertia m·r² in J, and I_f(U) is not convex in U. So this is a search, and
//! the design is `best_found` with its evidence: argmin's Nelder–Mead
//! ([`crate::synth::search::nelder_mead`]) on U = (U_x, U_y) from the certified force optimum,
//! the certified ΔE optimum (where the weights make ΔE depend on U), no counterweight and
//! Halton points of the allowed disc. A point outside the allowed |U| range or direction
//! range, or over a limit, costs its projection's flywheel raised in proportion to how far
//! off it is, so the search stays where the design may go.

use super::file::SliderCrankProblem;
use super::synth::{self as sc, Objective};
use crate::dynamics::{self, Drive, DriveSettings};
use crate::geom::P2;
use crate::synth::search::{nelder_mead, starts, NelderMead, SameBasin, SearchEvidence};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// The search's result: the design and its least flywheel.
#[derive(Debug, Clone, PartialEq)]
pub struct FlywheelDesign {
    /// The best U found (kg·m, crank frame).
    pub u: P2,
    /// Its least flywheel (kg·m²).
    pub inertia: f64,
    /// What the search did.
    pub evidence: SearchEvidence,
}

/// Halton starts of the allowed disc beside the named ones.
const HALTON_STARTS: usize = 2;

/// The least flywheel of the design `u` for the drive `d` (kg·m²), the counterweight's own
/// inertia m·r² included where the scene sizes it; `None` where the drive fails.
pub fn least_flywheel_of(p: &SliderCrankProblem, d: &Drive, u: P2) -> Option<f64> {
    least_flywheel_with_error(p, d, u).map(|f| f.0)
}

/// [`least_flywheel_of`] with its error bound (kg·m²).
fn least_flywheel_with_error(p: &SliderCrankProblem, d: &Drive, u: P2) -> Option<(f64, f64)> {
    let s = &p.core;
    let cw = sc::realise(u.norm(), &s.counterweight, s.objective);
    let machine = sc::machine(s, u, cw.drive_inertia());
    let figures = dynamics::drive(&machine, s.omega, d, &DriveSettings::default()).ok()?;
    figures.flywheel.map(|f| (f.inertia, f.inertia_error))
}

/// How far `u` is outside what the design may be (kg·m): the |U| range and the direction
/// range; and `u` brought inside.
fn project(s: &sc::Scene, u: P2) -> (P2, f64) {
    let (lo, hi) = sc::unbalance_bounds(&s.counterweight);
    let n = u.norm();
    let mut beta = u.y.atan2(u.x).rem_euclid(TAU);
    let (b0, b1) = s.counterweight.angle.bounds();
    if b1 - b0 < TAU - 1e-9 {
        // A range at most 180° wide: the nearer end outside it.
        let inside = |b: f64| (b - b0).rem_euclid(TAU) <= b1 - b0;
        if !inside(beta) {
            let (d0, d1) = ((beta - b0).rem_euclid(TAU), (b1 - beta).rem_euclid(TAU));
            beta = if TAU - d0 < TAU - d1 { b0 } else { b1 };
        }
    }
    let m = n.clamp(lo, hi.min(f64::MAX));
    let v = P2::new(m * beta.cos(), m * beta.sin());
    (v, (v - u).norm())
}

/// How far the design `v` exceeds the peak-force and peak-torque limits (relative; 0 within
/// them), `None` where it cannot be evaluated.
fn over_limits(s: &sc::Scene, v: P2) -> Option<f64> {
    if s.max_peak_force.is_none() && s.max_peak_torque.is_none() {
        return Some(0.0);
    }
    let m = sc::metrics(s, v).ok()?;
    let over = |v: f64, lim: Option<f64>| lim.map_or(0.0, |l| ((v - l) / l).max(0.0));
    Some(over(m.peak, s.max_peak_force) + over(m.peak_torque, s.max_peak_torque))
}

/// The search's cost at `u`: the least flywheel of its projection, raised by how far `u` is
/// outside and by how far its peaks exceed the limits (relative).
fn cost(p: &SliderCrankProblem, d: &Drive, u: P2, scale: f64) -> f64 {
    let s = &p.core;
    let (v, off) = project(s, u);
    let (Some(i_f), Some(over)) = (least_flywheel_of(p, d, v), over_limits(s, v)) else {
        return f64::MAX.sqrt();
    };
    let penalty = off / scale + over;
    (i_f + 1e-12) * (1.0 + 10.0 * penalty) + penalty
}

/// The search from the certified force optimum `u_force` (and the ΔE optimum, no
/// counterweight, Halton points of the allowed disc).
pub fn design(p: &SliderCrankProblem, d: &Drive, u_force: P2) -> Result<FlywheelDesign, String> {
    let s = &p.core;
    let (_, hi) = sc::unbalance_bounds(&s.counterweight);
    let scale = if hi.is_finite() {
        hi
    } else {
        2.0 * u_force.norm().max(1e-9)
    };
    let mut named = vec![u_force, P2::zeros()];
    if s.loads.gravity.norm() > 0.0 {
        let energy = sc::Scene {
            objective: Objective::MinEnergyFluctuation,
            ..s.clone()
        };
        if let Ok(out) = sc::solve(&energy) {
            if out.degenerate.is_none() {
                named.push(P2::from(out.design.unbalance));
            }
        }
    }
    let halton = starts::halton_points(HALTON_STARTS, 2)
        .into_iter()
        .map(|h| {
            let (r, a) = (scale * h[0].sqrt(), TAU * h[1]);
            P2::new(r * a.cos(), r * a.sin())
        });
    let all: Vec<P2> = named.into_iter().chain(halton).collect();
    let f = |x: &[f64]| cost(p, d, P2::new(x[0], x[1]), scale);
    // The simplex stops when its costs spread less than the force optimum's least-flywheel
    // error bound or 1e-7 of it, whichever is larger (a reported least flywheel's error is
    // typically 1e-9 to 1e-5 of it; polishing further cost 1.2-1.5× the evaluations for no
    // visible digit), and ends that close are one basin.
    let (i0, e0) = least_flywheel_with_error(p, d, project(s, u_force).0)
        .ok_or("flywheel-inertia: the drive of the force optimum fails")?;
    let noise = e0.max(1e-7 * i0.abs()).max(1e-12);
    let step = 0.1 * scale;
    // The starts run in parallel; each is deterministic and the ends are kept in the
    // starts' order, so the result does not depend on the thread count.
    let runs: Vec<Result<(Option<(Vec<f64>, f64)>, usize), String>> = all
        .par_iter()
        .map(|u0| {
            let x0 = vec![u0.x, u0.y];
            let simplex = vec![x0.clone(), vec![u0.x + step, u0.y], vec![u0.x, u0.y + step]];
            let settings = NelderMead {
                simplex,
                sd_tolerance: noise,
                max_iters: 80,
            };
            let end = nelder_mead(&f, &settings)?;
            // The end brought inside the allowed set, kept where it meets the limits.
            let (v, _) = project(s, P2::new(end.x[0], end.x[1]));
            let kept = (over_limits(s, v) == Some(0.0))
                .then(|| least_flywheel_of(p, d, v).map(|value| (vec![v.x, v.y], value)))
                .flatten();
            Ok((kept, end.evaluations + 1))
        })
        .collect();
    let (mut ends, mut evaluations) = (Vec::new(), 1);
    for r in runs {
        let (kept, n) = r?;
        ends.extend(kept);
        evaluations += n;
    }
    let spans = [scale, scale];
    let same = SameBasin {
        rel: (2.0 * noise / i0.abs().max(f64::MIN_POSITIVE)).max(1e-6),
        point: Some((&spans, 1e-4)),
    };
    let evidence = SearchEvidence::of_ends(
        format!(
            "argmin Nelder–Mead (Nelder & Mead 1965) on U = (U_x, U_y) from {} starts (the certified force optimum, no counterweight{}, {HALTON_STARTS} Halton points of the allowed disc); each cost the exact least flywheel for Cs by Brent on the periodic steady state",
            all.len(),
            if all.len() > 2 + HALTON_STARTS { ", the certified ΔE optimum" } else { "" },
        ),
        ends.clone(),
        all.len(),
        evaluations,
        &same,
        1.0,
    );
    let best = ends
        .iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or("flywheel-inertia: no search ended on a design within the limits")?;
    Ok(FlywheelDesign {
        u: P2::new(best.0[0], best.0[1]),
        inertia: best.1,
        evidence,
    })
}
