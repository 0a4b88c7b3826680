//! What `cwsynth study` varies for a linkage scene — its ladder of accuracy settings — and the
//! effects its model leaves out or includes, each with a bound computed from the scene.

use super::file::LinkageProblem;
use super::numbers::objective_key;
use crate::families::family::{relative, Effect, Ladder, Rung};
use crate::problem::edit::{v_f, v_int, v_s, Edit};
use crate::report::SolveResult;
use crate::units::rad_text;

/// The headline: the objective the scene's counterweights minimise (for an analysis, the same
/// key of the bare linkage) (see [`crate::families::Machine::headline`]).
pub fn headline(p: &LinkageProblem) -> String {
    format!("objectives.{}", objective_key(p.scene.objective.minimize))
}

/// The reference edits (tightest settings) and the ladder of settings.
pub fn ladder(_p: &LinkageProblem) -> Ladder {
    use Edit::Set;
    // The headline does not depend on a front: the reference solves without one, so that
    // its tighter sampling stays within the work budget (a 20-point front at 2880 samples
    // would not).
    let reference = vec![
        Set("accuracy.rel_tol", v_f(1e-11)),
        Set("accuracy.scan_samples", v_int(2880)),
        Set("accuracy.peak_xtol", v_s(&rad_text(1e-12))),
        Set("accuracy.rms_samples", v_int(2880)),
        Set("objective.pareto_points", v_int(0)),
    ];
    let mut rungs = Vec::new();
    for t in [1e-4, 1e-6, 1e-9] {
        rungs.push(Rung::new(
            &format!("rel_tol {t:e}"),
            "accuracy",
            vec![Set("accuracy.rel_tol", v_f(t))],
        ));
    }
    for n in [45i64, 90, 360] {
        rungs.push(Rung::new(
            &format!("scan {n}"),
            "accuracy",
            vec![Set("accuracy.scan_samples", v_int(n))],
        ));
    }
    rungs.push(Rung::new(
        "peak_xtol 1e-5",
        "accuracy",
        vec![Set("accuracy.peak_xtol", v_s(&rad_text(1e-5)))],
    ));
    Ladder { reference, rungs }
}

/// What the model leaves out or includes, with a bound for each effect.
pub fn effects(p: &LinkageProblem, reference: &SolveResult, headline: f64) -> Vec<Effect> {
    let mut out = Vec::new();
    let kappa = reference
        .lookup("derived.max_dyad_conditioning")
        .unwrap_or(1.0);
    out.push((
        "rigid links, ideal joints".into(),
        "no clearance, friction or elasticity: the fields are those of the rigid-body model (no bound computed here)".into(),
    ));
    out.push((
        "round-off near toggle positions".into(),
        format!(
            "dyad conditioning up to {kappa:.3e}: accelerations lose about ε·κ² ≈ {:.1e} relative, included in every stated error",
            f64::EPSILON * kappa * kappa
        ),
    ));
    if let Some(e) = reference
        .errors
        .get(objective_key(p.scene.objective.minimize))
    {
        out.push((
            "certificate of the optimum".into(),
            format!(
                "stated error {e:.3e} ({:.1e} of the headline): sampling gap, solver tolerance, evaluation and refinement",
                relative(*e, headline)
            ),
        ));
    }
    out
}
