//! What `cwsynth study` varies for a multi-cylinder scene — the engine's accuracy and the
//! kinematic model — and the effects its model leaves out, each with a bound computed from
//! the scene as resolved.

use super::file::{Goal, MultiCylinderProblem};
use crate::families::family::{relative, Effect, Ladder, Rung};
use crate::problem::edit::{v_f, v_int, v_s, Edit};
use crate::report::SolveResult;

/// The headline: the objective the scene minimises, or the peak force of an analysis.
pub fn headline(p: &MultiCylinderProblem) -> String {
    let key = match (p.rotors.is_empty(), p.goal) {
        (true, _) | (false, Goal::PeakForce) => "peak_shaking_force_n",
        (false, Goal::PeakCouple) => "peak_couple_nm",
        (false, Goal::CounterweightMass) => "counterweight_mass_kg",
        (false, Goal::PeakMountForce) => "peak_mount_force_n",
    };
    format!("objectives.{key}")
}

/// The reference edits (tightest settings) and the ladder.
pub fn ladder(_: &MultiCylinderProblem) -> Ladder {
    use Edit::Set;
    let reference = vec![
        Set("accuracy.rel_tol", v_f(1e-11)),
        Set("accuracy.scan_samples", v_int(1440)),
    ];
    let mut rungs = Vec::new();
    for n in [90i64, 360] {
        rungs.push(Rung::new(
            &format!("scan {n}"),
            "accuracy",
            vec![Set("accuracy.scan_samples", v_int(n))],
        ));
    }
    for t in [1e-6, 1e-9] {
        rungs.push(Rung::new(
            &format!("rel_tol {t:e}"),
            "accuracy",
            vec![Set("accuracy.rel_tol", v_f(t))],
        ));
    }
    for k in ["two-harmonic", "primary"] {
        rungs.push(Rung::new(
            &format!("{k} kinematics"),
            "model",
            vec![Set("model.kinematics", v_s(k))],
        ));
    }
    Ladder { reference, rungs }
}

/// The effects the model leaves out, each with a bound from the scene.
pub fn effects(p: &MultiCylinderProblem, reference: &SolveResult, headline: f64) -> Vec<Effect> {
    let force = reference
        .lookup("objectives.peak_shaking_force_n")
        .unwrap_or(0.0);
    let weight: f64 = p
        .layout
        .cylinders
        .iter()
        .map(|c| c.sc.crank.mass + c.sc.rod.mass + c.sc.slider_mass)
        .sum::<f64>()
        * 9.80665;
    vec![
        (
            "gravity".into(),
            format!(
                "left out of the shaking force: the links' weight {weight:.4e} N is a constant load on the mounts, not a shaking force ({:.3e} of the headline)",
                relative(weight, headline)
            ),
        ),
        (
            "frame".into(),
            if p.frame.is_some() {
                "a rigid body on linear springs and viscous dampers: the frame's own bending and the mounts' frequency-dependent stiffness are left out".into()
            } else {
                format!("the frame is ground: on mounts it moves, and what the mounts transmit differs from the peak force {force:.4e} N by the frame's response (`[mechanism.frame]`, `[[mechanism.mounts]]`)")
            },
        ),
        (
            "constant speed".into(),
            "the crank turns at exactly ω: the speed's fluctuation adds α·p₀ to the force (the slider-crank family's drive models it for one cylinder)".into(),
        ),
        (
            "roll moment".into(),
            "the moment about the shaft is reported (derived.peak_roll_moment_nm: zero for lumped in-line cylinders, from rod inertia, offsets and articulated rods otherwise) and shakes the frame on its mounts about the shaft, but is no design target: crank-web counterweights and balance shafts at constant speed do not change it".into(),
        ),
    ]
}
