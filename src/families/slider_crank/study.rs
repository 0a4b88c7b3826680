//! What `cwsynth study` varies for a slider-crank scene — its ladder of accuracy and model
//! settings — and the effects its model leaves out or includes, each with a bound computed
//! from the scene as resolved.

use super::model::Kinematics;
use crate::families::family::{relative, Effect, Ladder, Rung};
use crate::problem::edit::{v_f, v_int, v_s, Edit};
use crate::report::SolveResult;
use crate::units::rad_text;
use crate::units::STANDARD_GRAVITY as G;
use std::f64::consts::TAU;
use toml_edit::Value;

/// The headline: the dotted result key a design is judged on (see
/// [`crate::families::family::Machine::headline`]).
pub fn headline(p: &super::file::SliderCrankProblem) -> String {
    if p.flywheel_objective {
        return format!("objectives.{}", super::numbers::FLYWHEEL_KEY);
    }
    super::synth::headline(p.core.objective)
}

/// The reference edits (tightest settings) and the ladder of settings.
pub fn ladder(s: &super::file::SliderCrankProblem) -> Ladder {
    use Edit::{Remove, Set};
    let reference = vec![
        Set("accuracy.rel_tol", v_f(1e-11)),
        Set("accuracy.initial_samples", v_int(64)),
        Set("accuracy.scan_samples", v_int(2880)),
        Set("accuracy.max_rounds", v_int(100)),
        Set("accuracy.peak_xtol", v_s(&rad_text(1e-12))),
        Set("accuracy.rms_samples", v_int(4096)),
    ];
    let mut l = Vec::new();
    for n in [8i64, 32, 128, 512] {
        l.push(Rung::new(
            &format!("{n} samples, no exchange"),
            "accuracy",
            vec![
                Set("accuracy.initial_samples", v_int(n)),
                Set("accuracy.max_rounds", v_int(1)),
                Set("accuracy.presolve", Value::from(false)),
            ],
        ));
    }
    l.push(Rung::new(
        "no presolve (exchange from 8 samples)",
        "accuracy",
        vec![Set("accuracy.presolve", Value::from(false))],
    ));
    l.push(Rung::new(
        "presolve, no exchange",
        "accuracy",
        vec![Set("accuracy.max_rounds", v_int(1))],
    ));
    l.push(Rung::new(
        "presolve, clarabel SOCP rounds (no exact disc)",
        "accuracy",
        vec![Set("accuracy.exact_disc", Value::from(false))],
    ));
    for n in [64i64, 1440] {
        l.push(Rung::new(
            &format!("scan {n}, exchange"),
            "accuracy",
            vec![Set("accuracy.scan_samples", v_int(n))],
        ));
    }
    for t in [1e-3, 1e-6] {
        l.push(Rung::new(
            &format!("rel_tol {t:e}"),
            "accuracy",
            vec![Set("accuracy.rel_tol", v_f(t))],
        ));
    }
    let m = &s.core.mech;
    // Obliquity neglected with no rod length: no other kinematics or rod model exists.
    if s.rod_length_given {
        model_rungs(&mut l, m);
    }
    if s.core.loads.gravity.norm() > 0.0 {
        l.push(Rung::new(
            "no gravity",
            "model",
            vec![
                Remove("model.gravity_acceleration"),
                Set("model.gravity", Value::from(false)),
            ],
        ));
    } else {
        l.push(Rung::new(
            "with gravity",
            "model",
            vec![Set("model.gravity", Value::from(true))],
        ));
    }
    Ladder {
        reference,
        rungs: l,
    }
}

/// The model rungs: the other kinematics, the other rod model.
fn model_rungs(l: &mut Vec<Rung>, m: &crate::families::slider_crank::model::SliderCrank) {
    use Edit::{Remove, Set};
    if m.kinematics == Kinematics::Exact {
        l.push(Rung::new(
            "two-harmonic kinematics",
            "model",
            vec![Set("model.kinematics", v_s("two-harmonic"))],
        ));
    } else {
        l.push(Rung::new(
            "exact kinematics",
            "model",
            vec![Set("model.kinematics", v_s("exact"))],
        ));
    }
    let lumped = (m.rod.inertia - m.rod.mass * (m.l - m.rod.centroid) * m.rod.centroid).abs()
        <= 1e-12 * (m.rod.mass * m.l * m.l).max(1e-300);
    if lumped {
        l.push(Rung::new(
            "rigid uniform rod",
            "model",
            vec![Remove("model.rod_split"), Set("model.masses", v_s("rigid"))],
        ));
    } else {
        l.push(Rung::new(
            "lumped rod (½ + ½)",
            "model",
            vec![
                Remove("model.rod_centroid"),
                Remove("model.rod_inertia"),
                Set("model.masses", v_s("lumped")),
            ],
        ));
    }
}

/// What the model leaves out or includes, with a bound for each effect (see
/// [`crate::families::family::Machine::effects`]).
pub fn effects(
    s: &crate::families::slider_crank::file::SliderCrankProblem,
    _reference: &SolveResult,
    reference: f64,
) -> Vec<Effect> {
    let c = &s.core;
    let m = &c.mech;
    let w2 = c.omega * c.omega;
    let n = 3600;
    let phis: Vec<f64> = (0..n).map(|k| k as f64 * TAU / n as f64).collect();
    let mut out = Vec::new();
    // Gravity against inertia. The shaking force is the inertia force only (the weights are
    // a static load, reported as `derived` static weight); gravity enters the drive torque.
    let weight = (m.crank.mass + m.rod.mass + m.slider_mass) * G;
    let ratio = G / (m.r * w2);
    let mut tg = 0.0f64;
    for &p in &phis {
        if let Some(st) = m.state(p) {
            let v = m.crank.mass * m.crank.centroid
                + m.rod.mass * st.g3[1].norm()
                + m.slider_mass * st.x[1].abs();
            tg = tg.max(G * v);
        }
    }
    if c.loads.gravity.norm() > 0.0 {
        out.push((
            "gravity".into(),
            format!("modelled (g/(Rω²) = {ratio:.3}: weights matter for the torque; the link weights' torque reaches up to {tg:.4} N·m)"),
        ));
    } else {
        out.push((
            "gravity".into(),
            format!(
                "left out: g/(Rω²) = {ratio:.2e}. The shaking force is inertial and does not change; the link weights W = {weight:.4} N are a static load ({:.2e} of the headline value {reference:.6}); their torque, g·max(m2 r2 + m3|G3'| + m4|x'|) = {tg:.4} N·m, is left out of the drive torque (plus the counterweight's |U|·g = {:.4} N·m per kg·m of unbalance)",
                relative(weight, reference),
                G
            ),
        ));
    }
    // Rod inertia against the lumped split.
    let lumped_i = m.rod.mass * (m.l - m.rod.centroid) * m.rod.centroid;
    let uniform_i = m.rod.mass * m.l * m.l / 12.0;
    let centred = (m.rod.centroid - 0.5 * m.l).abs() <= 1e-12 * m.l;
    if (m.rod.inertia - lumped_i).abs() <= 1e-12 * uniform_i.max(1e-300) {
        let di = uniform_i - m.rod.inertia;
        let (mut psi2, mut tq) = (0.0f64, 0.0f64);
        for &p in &phis {
            if let Some(st) = m.state(p) {
                psi2 = psi2.max(st.dpsi[1].abs());
                tq = tq.max((st.dpsi[0] * st.dpsi[1]).abs());
            }
        }
        out.push((
            "rod inertia".into(),
            format!(
                "lumped split: the shaking force is {} for a uniform rod{}; the rod's inertia differs from the uniform bar's by ΔI = {di:.3e} kg·m², which changes the shaking moment by at most |ΔI|ω²·max|ψ''| = {:.4} N·m and the drive torque by at most |ΔI|ω²·max|ψ'ψ''| = {:.4} N·m",
                if centred { "exact" } else { "not exact" },
                if centred { " (the split puts the centroid at L/2)" } else { "" },
                di.abs() * w2 * psi2,
                di.abs() * w2 * tq
            ),
        ));
    } else {
        out.push((
            "rod inertia".into(),
            "modelled (rigid rod with centroid and moment of inertia)".into(),
        ));
    }
    // Series truncation of the kinematics.
    if m.kinematics == Kinematics::Primary && !s.rod_length_given {
        out.push((
            "kinematics".into(),
            format!(
                "primary only (obliquity neglected): the secondary force m_ct ω² λR cos 2φ is left out; its size, {:.4} N per unit of λ, is unknown without the rod length (λ = R/L)",
                m.m_rec() * w2 * m.r
            ),
        ));
    } else if m.e == 0.0 {
        let mut ex = *m;
        ex.kinematics = Kinematics::Exact;
        let mut th = *m;
        if th.kinematics == Kinematics::Exact {
            th.kinematics = Kinematics::TwoHarmonic;
        }
        let mut dx = 0.0f64;
        for &p in &phis {
            if let (Some(a), Some(b)) = (ex.state(p), th.state(p)) {
                dx = dx.max((a.x[2] - b.x[2]).abs());
            }
        }
        let bound = (m.slider_mass + m.rod.mass) * w2 * dx;
        let (series, order) = if th.kinematics == Kinematics::Primary {
            ("primary", "λ")
        } else {
            ("2h", "λ³")
        };
        let what = match m.kinematics {
            Kinematics::Exact => "exact (nothing left out); the two-harmonic series would change the shaking force by at most",
            Kinematics::TwoHarmonic => "two-harmonic: the harmonics of order ≥ 4 left out change the shaking force by at most",
            Kinematics::Primary => "primary only (obliquity neglected): the harmonics of order ≥ 2 left out change the shaking force by at most",
        };
        out.push((
            "kinematics".into(),
            format!(
                "{what} (m3 + m4)ω²·max|x''_exact − x''_{series}| = {bound:.4} N ({:.2e} of the headline value; λ = {:.4}, the first term left out is O({order}))",
                relative(bound, reference),
                m.lambda()
            ),
        ));
    } else {
        out.push((
            "kinematics".into(),
            "exact (an offset slider has no two-harmonic option)".into(),
        ));
    }
    out
}

// ---------------------------------------------------------------------------------------
// Hypocycloid
// ---------------------------------------------------------------------------------------
