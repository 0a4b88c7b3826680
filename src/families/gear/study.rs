//! What `cwsynth study` varies for a eccentric-gear scene — its ladder of accuracy and model
//! settings — and the effects its model leaves out or includes, each with a bound computed
//! from the scene as resolved.

use super::model::{GearPair, Pole, Singularities, Which};
use super::synth::{Derived, Design};
use crate::families::family::{relative, Effect, Ladder, Rung};
use crate::problem::edit::{v_int, v_s, Edit};
use crate::report::numbers::key;
use crate::report::SolveResult;
use crate::units::rad_text;
use std::f64::consts::TAU;
use toml_edit::Value;

/// The headline: the dotted result key a design is judged on (see
/// [`crate::families::Machine::headline`]).
pub fn headline(p: &super::file::GearProblem) -> String {
    format!(
        "objectives.{}",
        super::synth::Objectives::key(&p.gear.eccentricity)
    )
}

/// The reference edits (tightest settings) and the ladder of settings.
pub fn ladder(_s: &super::file::GearProblem) -> Ladder {
    use Edit::Set;
    let reference = vec![
        Set("accuracy.samples_per_arch", v_int(96)),
        Set("accuracy.peak_samples_per_arch", v_int(512)),
        Set("accuracy.peak_xtol", v_s(&rad_text(1e-12))),
        Set("accuracy.pole_tol", v_s(&rad_text(1e-13))),
    ];
    let mut l = Vec::new();
    // Poles placed by one false-position step in their sampled bracket (no Brent).
    for n in [8i64, 24, 96] {
        l.push(Rung::new(
            &format!("poles unrefined, {n} samples/arch"),
            "accuracy",
            vec![
                Set("accuracy.refine_poles", Value::from(false)),
                Set("accuracy.samples_per_arch", v_int(n)),
            ],
        ));
    }
    l.push(Rung::new(
        "8 samples/arch, refined",
        "accuracy",
        vec![Set("accuracy.samples_per_arch", v_int(8))],
    ));
    for n in [8i64, 32, 128] {
        l.push(Rung::new(
            &format!("peak {n}/arch, unrefined"),
            "accuracy",
            vec![
                Set("accuracy.refine_peaks", Value::from(false)),
                Set("accuracy.peak_samples_per_arch", v_int(n)),
            ],
        ));
    }
    l.push(Rung::new(
        "pole_tol 1e-12",
        "accuracy",
        vec![Set("accuracy.pole_tol", v_s(&rad_text(1e-12)))],
    ));
    l.push(Rung::new(
        "peak_xtol 1e-5",
        "accuracy",
        vec![Set("accuracy.peak_xtol", v_s(&rad_text(1e-5)))],
    ));
    for w in ["0.001 rad", "0.05 rad"] {
        l.push(Rung::new(
            &format!("pole window {w}"),
            "model",
            vec![Set("model.pole_window", v_s(w))],
        ));
    }
    Ladder {
        reference,
        rungs: l,
    }
}

fn mu_at(pair: &GearPair, which: Which, x: f64) -> Option<f64> {
    let ct = pair.contact(x.rem_euclid(TAU));
    match which {
        Which::Mu1 => ct.mu1,
        Which::Mu2 => ct.mu2,
    }
    .map(f64::abs)
}

/// max |µ| at distance `d` from every pole of its own coefficient (both sides), skipping
/// points inside another window of half-width `window` (the same coefficient's other poles,
/// or the 0/0 cusps). With `d = window` this is the largest |µ| on the edges of
/// the working window, which is the peak when the peak is set by the window.
pub fn window_edge_mu(pair: &GearPair, sing: &Singularities, window: f64, d: f64) -> f64 {
    let cusps = sing.singular_cusps();
    let near = |x: f64, c: f64| {
        let t = (x - c).rem_euclid(TAU);
        t.min(TAU - t)
    };
    let inside = |x: f64, p: &Pole| {
        sing.poles
            .iter()
            .filter(|q| q.which == p.which && !std::ptr::eq(*q, p))
            .any(|q| near(x, q.alpha1_rad) < window)
            || cusps.iter().any(|&c| near(x, c) < window)
    };
    let mut best = 0.0f64;
    for p in &sing.poles {
        for x in [p.alpha1_rad - d, p.alpha1_rad + d] {
            if inside(x, p) {
                continue;
            }
            if let Some(v) = mu_at(pair, p.which, x) {
                best = best.max(v);
            }
        }
    }
    best
}

/// What the model leaves out or includes, with a bound for each effect (see
/// [`crate::families::Machine::effects`]).
pub fn effects(
    g: &crate::families::gear::file::GearProblem,
    reference: &SolveResult,
    headline: f64,
) -> Vec<Effect> {
    let sc = &g.gear;
    let s = &g.settings;
    let mut out = Vec::new();
    let Some(e) = reference.lookup(key!("design", Design, eccentricity_m)) else {
        return vec![(
            "pole windows".into(),
            "the reference has no eccentricity: no bound".into(),
        )];
    };
    let an = match crate::families::gear::synth::analyse(sc, e, s) {
        Ok(a) => a,
        Err(err) => {
            return vec![(
                "pole windows".into(),
                format!("the reference design does not analyse ({err}): no bound"),
            )]
        }
    };
    let w = sc.pole_window;
    let cusps = an.sing.singular_cusps();
    let np = an.sing.poles.len();
    let edge = window_edge_mu(&an.pair, &an.sing, w, w);
    let half = window_edge_mu(&an.pair, &an.sing, 0.5 * w, 0.5 * w);
    let count = |wh: Which| an.sing.poles.iter().filter(|p| p.which == wh).count();
    let per = count(Which::Mu1).max(count(Which::Mu2));
    let frac = ((per + cusps.len()) as f64 * 2.0 * w / TAU).min(1.0);
    let set_by = edge >= an.peak.value * (1.0 - 1e-9);
    let designed = if matches!(sc.eccentricity, crate::synth::Var::Free { .. }) {
        format!(
            "; e is designed with the peak |µ| as a constraint, so the window moves e and with it the headline ({headline:.6}): see the pole-window rungs"
        )
    } else {
        String::new()
    };
    out.push((
        "pole windows".into(),
        format!(
            "left out: |α1 − α_pole| < w = {w} rad around each of the {np} poles (and {} 0/0 cusps), at most (max(n_µ1-poles, n_µ2-poles) + n_cusps)·2w/2π = {:.2}% of the α1 range of each coefficient; |µ| → ∞ at a pole, so no window-free peak exists. At the window edges max|µ(α_pole ± w)| = {edge:.6} ({}); with windows of w/2, max|µ(α_pole ± w/2)| = {half:.6} = {:.3}× (|µ| ∝ 1/distance: ≈ 2× when the peak is set by the window); a window narrower by δw raises the peak by ≈ peak·δw/w{designed}",
            cusps.len(),
            100.0 * frac,
            if set_by {
                "= the peak |µ|: it is set by the window".to_string()
            } else {
                format!("< the peak {:.6}: the peak lies inside the working window", an.peak.value)
            },
            half / edge.max(1e-300)
        ),
    ));
    // The windows follow the poles: their location error moves the edges.
    let dmax = reference
        .lookup(key!("derived", Derived, max_pole_error_rad))
        .unwrap_or(f64::NAN);
    let slope = if set_by { edge / w } else { 0.0 };
    out.push((
        "pole location".into(),
        format!(
            "each pole is located to ≤ {dmax:.2e} rad; the window edges move with it, changing a peak set by the window by ≈ |µ|/w·δα = {:.2e} ({:.2e} of the peak |µ|)",
            slope * dmax,
            relative(slope * dmax, an.peak.value)
        ),
    ));
    // Closure of the centre distance (trapezoid quadrature): sensitivity by re-analysis.
    let da = an.closure.a_error.abs().max(f64::EPSILON * an.pair.a);
    let step = 1e-7 * an.pair.a;
    let sens = GearPair::new(an.pair.c, sc.generating_radius, an.pair.a + step, sc.omega1)
        .ok()
        .and_then(|p2| {
            let s2 =
                crate::families::gear::model::singularities(&p2, s.samples_per_arch, s.pole_tol)
                    .ok()?;
            let pk = crate::families::gear::model::peak_mu(
                &p2,
                &s2,
                w,
                s.peak_samples_per_arch,
                s.peak_xtol,
            )
            .ok()?;
            Some((pk.value - an.peak.value).abs() / step)
        });
    out.push((
        "centre distance".into(),
        match sens {
            Some(k) => format!(
                "a = {:.9} m closes gear 2 to δa = {da:.2e} m (trapezoid closure integral); |∂peak/∂a|·δa = {:.2e} (|∂peak/∂a| = {k:.3e} /m by re-analysis at a + 1e-7·a)",
                an.pair.a,
                k * da
            ),
            None => format!("a = {:.9} m closes gear 2 to δa = {da:.2e} m; the re-analysis at a + 1e-7·a failed: no bound on its effect", an.pair.a),
        },
    ));
    let loaded = sc.tooth_outputs.is_some_and(|t| t.load.is_some());
    out.push((
        "tooth deflection, backlash, load".into(),
        if loaded {
            "left out, no bound: µ is kinematic (rigid teeth, exact cycloidal profiles, no backlash); the stated load (`mechanism.load`) enters the Hertz stress and the Archard wear, not µ; the scene gives no stiffness or tolerance data, so the teeth's deflection under that load cannot be computed from it"
        } else {
            "left out, no bound: µ is kinematic (rigid teeth, exact cycloidal profiles, no backlash); the scene gives no load, stiffness or tolerance data, so their effect on µ cannot be computed from it"
        }
        .into(),
    ));
    out
}
