//! The gear's numbers: the solution's figures into the result's maps — `model`, design,
//! objectives with their errors, derived figures, baselines, paper checks, sections and the
//! warnings of the result's own checks (keys in `docs/results.md`). Arithmetic on the solution
//! (sums, ratios, a limit compared), never a solve or a search: the driver runs it at solve
//! time for every result, `--summary-only` included, and `report.rs` draws from the same
//! solution.

use super::file::*;
use super::solve::Solution;
use crate::families::family::Scene;
use crate::families::gear::stress::{flank_name, FlankStress, ToothLoad};
use crate::families::gear::synth::{Derived, Outcome, TeethOutcome};
use crate::families::gear::teeth::Involute;
use crate::report::SolveResult;
use serde_json::json;
use std::collections::BTreeMap;

/// The result's `model` section: the teeth, the centre distance, the pole window, the turns
/// and the speed.
pub fn model(p: &GearProblem, _: Option<&Solution>) -> BTreeMap<String, serde_json::Value> {
    let g = &p.gear;
    BTreeMap::from([
        (
            "teeth".into(),
            json!("cycloidal: epicycloid and hypocycloid arches of the generating circle, alternating"),
        ),
        (
            "center_distance".into(),
            json!("closing: solved from the closure integral for n1/n2"),
        ),
        ("pole_window_rad".into(), json!(g.pole_window)),
        ("turns_gear1".into(), json!(g.turns_gear1)),
        ("turns_gear2".into(), json!(g.turns_gear2)),
        ("omega1_rad_s".into(), json!(g.omega1)),
    ])
}

/// The result's numbers from the solution: status, design, objectives, errors, derived
/// figures, the paper's checks, the poles and zeros, the flank wear.
pub fn numbers(_: &Scene, p: &GearProblem, sol: &Solution, r: &mut SolveResult) {
    let out = &sol.out;
    r.set_figures(&out.design, &out.objectives, &out.errors, &out.derived);
    r.paper = out.paper.clone();
    r.extra.insert(
        "poles".into(),
        serde_json::to_value(&out.poles).expect("plain data"),
    );
    r.extra.insert(
        "zeros".into(),
        serde_json::to_value(&out.zeros).expect("plain data"),
    );
    if let Some(t) = &out.teeth {
        r.extra.insert("flank_wear".into(), flank_wear_rows(t));
        r.extra
            .insert("sliding_comparison".into(), sliding_comparison_rows(out, t));
        if let Some(b) = &t.balanced_shift {
            let inv = &t.involute;
            r.warnings.push(format!(
                "involute comparison: the unshifted involute pair peaks at |µ| = {:.2} only because its {}-tooth pinion, unshifted, is below its undercut limit (x ≥ {:.3} needed: the path starts {:.3} mm from N1); a designer shifts its profile. With the routine shift x1 = +0.5, x2 = −0.5 gear 1's root slides at {:.3} and gear 2's at {:.3}, so the pair peaks at {:.3}; the balanced shift x1 = {:+.4} gives {:.3} (`sliding_comparison`). This pair's peak, {:.3}, is on its working window only: µ has poles at its cusps",
                inv.peak_mu(),
                inv.z1,
                crate::families::gear::teeth::undercut_limit(inv.z1, inv.pressure_angle_rad, 1.0),
                inv.x_start_m * 1e3,
                t.routine_shift.mu1_start.abs(),
                t.routine_shift.mu2_end.abs(),
                t.routine_shift.peak_mu(),
                b.pair.shift[0],
                b.pair.peak_mu(),
                out.objectives.peak_sliding_coefficient,
            ));
        }
        if let (Some(st), Some(load)) = (&t.stress, p.gear.tooth_outputs.and_then(|o| o.load)) {
            r.extra.insert("contact_stress".into(), stress_rows(st));
            r.warnings.push(stress_note(st, &load, &out.derived));
        }
        if !t.certified_pole_arches.is_empty() {
            r.warnings.push(format!(
                "pole correction (the paper's proposal after its eq. 12): not possible by the design parameters. On {} of the {} arches of gear 1 the pole function (K − O_j)·d of µ1 and of µ2 tends to ∓ρ_j sin ψ at one cusp and ±ρ_j sin ψ at the other with ψ of one sign, so it changes sign inside the arch for every generating radius r, pitch radius R and centre distance a (derived.arches_with_certified_pole); only e = 0 (ψ ≡ 0) is free of poles. Removing them needs a profile that is not a full cusp-to-cusp cycloid (e.g. relieved cusps with overlapping contact)",
                t.certified_pole_arches.len(),
                out.derived.arches_gear1
            ));
        }
    }
}

/// The `flank_wear` section: the sliding distance per arch of gear 1 (one row per arch; gear
/// 2's arches in `<name>-flank-wear.csv`).
fn flank_wear_rows(t: &TeethOutcome) -> serde_json::Value {
    let rows: Vec<serde_json::Value> = t
        .wear
        .gear1
        .iter()
        .enumerate()
        .map(|(i, (v, e))| {
            json!({
                "arch": i,
                "tooth": i / 2,
                "flank": flank_name(i),
                "sliding_distance_per_engagement_m": t.wear.per_engagement[i].value,
                "sliding_distance_per_cycle_m": v,
                "error_m": e,
            })
        })
        .collect();
    serde_json::Value::Array(rows)
}

/// The `contact_stress` section: per arch of gear 1, its loaded stretch, the extremes of p0
/// on its working window and W over a cycle (gear 2's arches in `<name>-contact-stress.csv`).
fn stress_rows(st: &FlankStress) -> serde_json::Value {
    let rows: Vec<serde_json::Value> = st
        .arches
        .iter()
        .zip(&st.gear1)
        .map(|(a, (w, we))| {
            json!({
                "arch": a.arch,
                "tooth": a.arch / 2,
                "flank": flank_name(a.arch),
                "loaded_from_rad": a.loaded.0,
                "loaded_to_rad": a.loaded.1,
                "peak_p0_pa": a.peak.map(|p| p.p0_pa),
                "peak_alpha1_rad": a.peak.map(|p| p.alpha1),
                "least_p0_pa": a.least.map(|p| p.p0_pa),
                "least_alpha1_rad": a.least.map(|p| p.alpha1),
                "p0_error_pa": a.p0_error(),
                "archard_per_engagement_nm": a.archard.value,
                "archard_per_cycle_nm": w,
                "archard_error_nm": we,
            })
        })
        .collect();
    serde_json::Value::Array(rows)
}

/// The contact-stress finding in plain words: the driving fraction, the stress along the
/// flanks, and the load-weighted wear against the paper's "even wear".
fn stress_note(st: &FlankStress, load: &ToothLoad, d: &Derived) -> String {
    let argmax = |v: &[(f64, f64)], max: bool| {
        (0..v.len())
            .reduce(|b, k| {
                if (v[k].0 > v[b].0) == max && v[k].0 != v[b].0 {
                    k
                } else {
                    b
                }
            })
            .unwrap_or(0)
    };
    let (hi, lo) = (argmax(&st.gear1, true), argmax(&st.gear1, false));
    let mpa = |v: Option<f64>| v.unwrap_or(f64::NAN) * 1e-6;
    format!(
        "contact stress and wear (mechanism.load: T1 = {} N·m on gear 1, face width {} mm, E = {} GPa, ν = {}; one contact at a time as in the paper's construction, frictionless): the contact can drive gear 2 only on the driving flanks, {:.2} % of each turn (`derived.driving_contact_fraction`); on the rest it is on the back flanks, so under load the teeth part and re-engage once a pitch. Teeth that are single cycloid arches have a transverse contact ratio of 0.5: this pair cannot carry a steady torque without a second pair of flanks in contact. On the driving flanks p0 is least mid-flank, {:.1} to {:.1} MPa depending on where in the turn, and grows without bound towards the pitch point (both flanks' radii of curvature vanish) and the tooth tip (the normal's arm about O1 vanishes): {:.1} MPa at the ends of the working windows (±{} rad). The paper finds the wear even because µ1 and µ2 are symmetric; weighted by the load (Archard, W = ∫F|v_s|dt over the working windows) it is not: gear 1's most worn flank, arch {hi} (tooth {}, {}), takes {:.2} times the least worn, arch {lo} (tooth {}, {}) ({:.4} against {:.4} N·m a cycle, `contact_stress`); the sliding distance alone differs {:.2}-fold. W grows like the logarithm of 1/window at the tip, so the ratio depends on the window; the least mid-flank stress ({:.2}-fold) does not",
        round6(load.torque),
        round6(load.face_width * 1e3),
        round6(load.youngs_modulus * 1e-9),
        round6(load.poisson_ratio),
        100.0 * st.driving_fraction.0,
        mpa(d.hertz_least_stress_min_pa),
        mpa(d.hertz_least_stress_max_pa),
        mpa(d.hertz_peak_stress_pa),
        st.window_rad,
        hi / 2,
        flank_name(hi),
        st.gear1[hi].0 / st.gear1[lo].0,
        lo / 2,
        flank_name(lo),
        st.gear1[hi].0,
        st.gear1[lo].0,
        d.sliding_distance_max_gear1_m.unwrap_or(f64::NAN) / d.sliding_distance_min_gear1_m.unwrap_or(f64::NAN),
        d.hertz_least_stress_max_pa.unwrap_or(f64::NAN) / d.hertz_least_stress_min_pa.unwrap_or(f64::NAN),
    )
}

/// `v` to 6 significant digits, printed without trailing zeros (a stated input echoed).
fn round6(v: f64) -> f64 {
    format!("{v:.6e}").parse().unwrap_or(v)
}

/// The `sliding_comparison` section: the eccentric pair, its circular cycloidal equivalent
/// and the involute equivalent, side by side.
fn sliding_comparison_rows(out: &Outcome, t: &TeethOutcome) -> serde_json::Value {
    let d = &out.derived;
    let f = |x: f64| format!("{x:.6}");
    let [(m1a, m2a), (m1d, m2d)] = t.circular;
    let inv = &t.involute;
    let circ_max = [m1a, m2a, m1d, m2d]
        .iter()
        .fold(0.0, |a: f64, b| a.max(b.abs()));
    json!([
        {
            "compared": format!("eccentric cycloidal (this pair, e = {:.4} mm)", out.design.eccentricity_m * 1e3),
            "mu1": "poles on every arch with ψ ≠ 0 at its cusps",
            "mu2": "poles on every arch with ψ ≠ 0 at its cusps",
            "max_abs_mu": format!("{} on the working window (±{:.4} rad around poles)", f(out.objectives.peak_sliding_coefficient), d.pole_window_rad),
            "poles_per_turn": d.poles_mu1_per_turn + d.poles_mu2_per_turn,
        },
        {
            "compared": format!("circular cycloidal (e = 0, z1 = {}, z2 = {})", inv.z1, inv.z2),
            "mu1": format!("{} (addendum), {} (dedendum)", f(m1a), f(m1d)),
            "mu2": format!("{} (addendum), {} (dedendum)", f(m2a), f(m2d)),
            "max_abs_mu": f(circ_max),
            "poles_per_turn": 0,
        },
        involute_row(
            inv,
            format!("involute (m = {:.4} mm, α = {:.2}°, standard addendum, unshifted, contact ratio {:.4})", inv.module_m * 1e3, inv.pressure_angle_rad.to_degrees(), inv.contact_ratio),
        ),
        involute_row(
            &t.routine_shift,
            format!("involute, routine profile shift x1 = +{:.1}, x2 = −{:.1} (contact ratio {:.4})", t.routine_shift.shift[0], t.routine_shift.shift[0], t.routine_shift.contact_ratio),
        ),
        match &t.balanced_shift {
            Some(b) => involute_row(
                &b.pair,
                format!(
                    "involute, balanced profile shift x1 = {:+.4}, x2 = {:+.4} (roots' specific sliding equal{}; no undercut, tips {:.3} and {:.3} mm thick, contact ratio {:.4}; admissible x1 from {:+.4} to {:+.4})",
                    b.pair.shift[0],
                    b.pair.shift[1],
                    b.binding.map_or(String::new(), |w| format!(" as far as {w} allows")),
                    b.tip_thickness_m[0] * 1e3,
                    b.tip_thickness_m[1] * 1e3,
                    b.pair.contact_ratio,
                    b.interval[0],
                    b.interval[1],
                ),
            ),
            None => json!({
                "compared": "involute, balanced profile shift: no shift keeps both teeth free of undercut and pointed tips with a contact ratio ≥ 1.1",
                "mu1": "–", "mu2": "–", "max_abs_mu": "–", "poles_per_turn": "–",
            }),
        },
    ])
}

/// One involute pair's row of the `sliding_comparison` section.
fn involute_row(inv: &Involute, compared: String) -> serde_json::Value {
    let f = |x: f64| format!("{x:.6}");
    let span = |a: f64, b: f64| (a.min(b), a.max(b));
    let (i1, i1h) = span(inv.mu1_start, inv.mu1_end);
    let (i2, i2h) = span(inv.mu2_start, inv.mu2_end);
    json!({
        "compared": compared,
        "mu1": format!("{} … {} (root A … tip E of gear 1)", f(i1), f(i1h)),
        "mu2": format!("{} … {}", f(i2), f(i2h)),
        "max_abs_mu": f(inv.peak_mu()),
        "poles_per_turn": if inv.interference { "on the path (interference)" } else { "0 (N1, N2 off the path)" },
    })
}
