//! What `cwsynth study` varies for a luffing-crane scene — its ladder of accuracy and model
//! settings — and the effects its model leaves out or includes, each with a bound computed
//! from the scene as resolved.

use super::model::{level_heights_with, Level, Linkage};
use super::synth::{Derived, Vars};
use crate::families::family::{relative, Effect, Ladder, Rung};
use crate::problem::edit::{v_int, v_s, Edit};
use crate::report::numbers::key;
use crate::report::SolveResult;
use crate::units::rad_text;
use toml_edit::Value;

/// The headline: the dotted result key a design is judged on (see
/// [`crate::families::Machine::headline`]).
pub fn headline(p: &super::file::CraneProblem) -> String {
    format!(
        "objectives.{}",
        super::synth::Objectives::key(&p.scene.level)
    )
}

/// The reference edits (tightest settings) and the ladder of settings.
pub fn ladder(_s: &super::file::CraneProblem) -> Ladder {
    use Edit::Set;
    let reference = vec![
        Set("accuracy.path_samples", v_int(1024)),
        Set("accuracy.xtol", v_s(&rad_text(1e-12))),
    ];
    let mut l = Vec::new();
    // Counts that do not divide one another, so no grid contains a coarser one.
    for n in [8i64, 20, 50, 130, 330] {
        l.push(Rung::new(
            &format!("path {n}, unrefined"),
            "accuracy",
            vec![
                Set("accuracy.refine_peaks", Value::from(false)),
                Set("accuracy.path_samples", v_int(n)),
            ],
        ));
    }
    for n in [8i64, 64] {
        l.push(Rung::new(
            &format!("path {n}, refined"),
            "accuracy",
            vec![Set("accuracy.path_samples", v_int(n))],
        ));
    }
    for t in [1e-4, 1e-10] {
        l.push(Rung::new(
            &format!("xtol {t:e}"),
            "accuracy",
            vec![Set("accuracy.xtol", v_s(&rad_text(t)))],
        ));
    }
    Ladder {
        reference,
        rungs: l,
    }
}

/// |y_C''| near a head-height extremum at `phi`: the largest three-point second difference
/// (step h/4) centred within h/2 of it; 0 at an end of the range, where an extremum is a
/// sample itself. `None` if a pose fails.
pub fn extremum_curvature(link: &Linkage, level: &Level, phi: f64, h: f64) -> Option<f64> {
    let [p0, p1] = link.phi_range;
    let tol = 1e-9 * (p1 - p0);
    if phi <= p0 + tol || phi >= p1 - tol {
        return Some(0.0);
    }
    let d = 0.25 * h;
    let y = |p: f64| link.pose(p).map(|q| level.height(q.c));
    let mut k = 0.0f64;
    for c in [phi - 0.5 * h, phi, phi + 0.5 * h] {
        let c = c.clamp(p0 + d, p1 - d);
        k = k.max(((y(c - d)? - 2.0 * y(c)? + y(c + d)?) / (d * d)).abs());
    }
    Some(k)
}

/// Bound on the error of Δh from `n` samples without refinement: an interior extremum at φ*
/// lies within h/2 of a sample, so the sampled extreme is off by at most |y_C''(φ*)|·h²/8;
/// for both, (|y''|_max-pt + |y''|_min-pt)·h²/8, h = (φ_max − φ_min)/n, |y''| from
/// [`extremum_curvature`] at the refined extrema. `None` if the path fails.
pub fn unrefined_path_bound(link: &Linkage, n: usize, xtol: f64) -> Option<f64> {
    level_path_bound(link, &Level::Head, n, xtol)
}

/// [`unrefined_path_bound`] of the height `level` measures (the head's or the load's).
pub fn level_path_bound(link: &Linkage, level: &Level, n: usize, xtol: f64) -> Option<f64> {
    let [p0, p1] = link.phi_range;
    let h = (p1 - p0) / n as f64;
    let hh = level_heights_with(link, level, n.max(64), Some(xtol)).ok()?;
    let k = extremum_curvature(link, level, hh.phi_at_max, h)?
        + extremum_curvature(link, level, hh.phi_at_min, h)?;
    Some(k * h * h / 8.0)
}

/// The crane design of a solution, (k1, k2, φ_min, γ1, γ2, γ3) from its `design.*`,
/// evaluated again (linkage and head path) with the scene's settings.
pub fn crane_design(
    c: &crate::families::crane::file::CraneProblem,
    result: &SolveResult,
) -> Option<crate::families::crane::synth::Evaluation> {
    let keys = [
        key!("design", Vars, k1),
        key!("design", Vars, k2),
        key!("design", Vars, phi_min_rad),
        key!("design", Vars, gamma1_rad),
        key!("design", Vars, gamma2_rad),
        key!("design", Vars, gamma3_rad),
    ];
    let x: Vec<f64> = keys
        .iter()
        .map(|k| result.lookup(k))
        .collect::<Option<_>>()?;
    crate::families::crane::synth::evaluate(
        &c.scene,
        &[x[0], x[1], x[2], x[3], x[4], x[5]],
        &c.settings,
    )
    .ok()
}

/// What the model leaves out or includes, with a bound for each effect (see
/// [`crate::families::Machine::effects`]).
pub fn effects(
    c: &crate::families::crane::file::CraneProblem,
    reference: &SolveResult,
    headline: f64,
) -> Vec<Effect> {
    let sc = &c.scene;
    let s = &c.settings;
    let ev = crane_design(c, reference);
    let mut out = Vec::new();
    match ev {
        Some(ev) => {
            let link = &ev.synthesis.linkage;
            let n = s.path_samples;
            let tol = s.refine_peaks.then_some(s.xtol);
            let dense = level_heights_with(link, &sc.level, 4 * n, tol).ok();
            let own = level_heights_with(link, &sc.level, n, tol).ok();
            let bound = level_path_bound(link, &sc.level, n, s.xtol);
            let (err_key, y) = match sc.level {
                Level::Head => ("errors.delta_h_m", "y_C"),
                Level::Load(_) => ("errors.load_delta_h_m", "y_L"),
            };
            match (own, dense, bound) {
                (Some(a), Some(b), Some(bound)) => {
                    out.push((
                        "path sampling".into(),
                        format!(
                            "{n} samples of the luffing range (h = {:.4e} rad), each extremum {}: |Δh(n) − Δh(4n)| = {:.3e} m ({:.2e} of the headline); the refinement error is in `{err_key}`; unrefined, the two extremes would be off by at most (|{y}''(φ_max-pt)| + |{y}''(φ_min-pt)|)·h²/8 = {bound:.3e} m ({:.2e} of the headline)",
                            (link.phi_range[1] - link.phi_range[0]) / n as f64,
                            if s.refine_peaks { format!("refined by Brent to {:e} rad", s.xtol) } else { "taken at the samples (refine_peaks = false)".into() },
                            (a.delta_h - b.delta_h).abs(),
                            relative((a.delta_h - b.delta_h).abs(), headline),
                            relative(bound, headline)
                        ),
                    ));
                }
                _ => out.push((
                    "path sampling".into(),
                    "the head path of the reference design does not evaluate: no bound".into(),
                )),
            }
        }
        None => out.push((
            "path sampling".into(),
            "the reference design could not be rebuilt: no bound".into(),
        )),
    }
    if let (Some(q), Some(mm)) = (
        sc.load_mass,
        reference.lookup(key!("derived", Derived, max_load_moment_nm)),
    ) {
        out.push((
            "load".into(),
            format!(
                "the rated load Q = {q} kg enters only the unbalanced load moment about A, W·dy/dφ, max {mm:.4e} N·m (virtual work; y the head's height, or with an inclined hoist rope the load's, y_C + |S − C|/n); it does not move the head path of the rigid linkage"
            ),
        ));
    }
    let masses = sc.balance.as_ref().is_some_and(|b| b.masses);
    out.push((
        "link masses, elasticity".into(),
        if masses {
            "the links' masses (`mechanism.self_weight`) enter the statics (`balance`: drive torque, pin and member forces), not the head path, which is the rigid linkage's geometry; elasticity is left out, no bound: the scene gives no sections or stiffnesses, so the boom/jib deflection under load (which shifts Δh) cannot be computed from it"
        } else {
            "left out, no bound: the model is geometric (rigid links, no link masses); the scene gives no masses, sections or stiffnesses, so neither the links' weight moment nor the boom/jib deflection under load (which shifts Δh) can be computed from it"
        }
        .into(),
    ));
    out
}

// ---------------------------------------------------------------------------------------
// Eccentric gear
// ---------------------------------------------------------------------------------------
