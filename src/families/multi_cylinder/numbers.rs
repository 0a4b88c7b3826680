//! The multi-cylinder's numbers: the solution's figures into the result's maps — `model`,
//! design, objectives with their errors, the bare layout's baseline, derived figures (the
//! certificate's parts, the primary and secondary harmonics by FFT and by the textbook's
//! sums) and the sections `harmonics` and `pareto` (keys in `docs/results.md`). Arithmetic on
//! the solution, never a solve.

use super::file::{Goal, MultiCylinderProblem};
use super::firing;
use super::model::{polar, Harmonic};
use super::phases::PhaseSearch;
use super::solve::{axial_mounts, normal_mounts, roll_index, Solution, Spectrum, COUPLE, FORCE};
use crate::families::family::Scene;
use crate::report::SolveResult;
use crate::synth::minimax::{self, var_u, FieldPeak};
use crate::synth::ActiveBound;
use serde_json::json;
use std::collections::BTreeMap;

/// The result's `model` section.
pub fn model(
    p: &MultiCylinderProblem,
    sol: Option<&Solution>,
) -> BTreeMap<String, serde_json::Value> {
    let p = sol.map_or(p, |s| s.scene(p));
    let c = &p.layout.cylinders[0].sc;
    let mut out = BTreeMap::from([
        ("cylinders".into(), json!(p.layout.cylinders.len())),
        ("kinematics".into(), json!(c.kinematics)),
        ("couple_reference_m".into(), json!(p.layout.z0)),
        ("omega_rad_s".into(), json!(p.omega)),
        ("orders".into(), json!(p.orders)),
        (
            "harmonics".into(),
            json!(format!(
                "FFT (rustfft) of {} samples of a turn",
                super::solve::FFT_SAMPLES
                    .max(4 * p.orders as usize)
                    .next_power_of_two()
            )),
        ),
        ("frame".into(), json!(frame_text(p))),
    ]);
    if let Some(text) = firing_text(p) {
        out.insert("firing".into(), json!(text));
    }
    out
}

/// The firing the layout admits, in words (with `mechanism.cycle`).
fn firing_text(p: &MultiCylinderProblem) -> Option<String> {
    let cycle = p.cycle?;
    let (orders, count) = firing::even_orders(&p.layout, cycle);
    let dt = (cycle.period() / p.layout.cylinders.len() as f64).to_degrees();
    let head = format!("{}: ", cycle.as_str());
    let text = if count == 0 {
        format!("{head}no even firing order (the throws' dead centres are not {dt:.4}° apart in any order)")
    } else {
        let list: Vec<String> = orders.iter().map(|o| firing::order_text(o)).collect();
        let more = if count > orders.len() { ", …" } else { "" };
        format!(
            "{head}{count} even firing order{}, every {dt:.4}°: {}{more}",
            if count == 1 { "" } else { "s" },
            list.join(", ")
        )
    };
    Some(text)
}

/// The firing figures (with `mechanism.cycle`): `even_firing_orders` and, when there is one,
/// `firing_interval_rad`; a warning when the layout does not fire evenly in the given order.
fn firing_numbers(p: &MultiCylinderProblem, r: &mut SolveResult) {
    let Some(cycle) = p.cycle else { return };
    let (_, count) = firing::even_orders(&p.layout, cycle);
    r.derived.insert("even_firing_orders".into(), count as f64);
    if count > 0 {
        r.derived.insert(
            "firing_interval_rad".into(),
            cycle.period() / p.layout.cylinders.len() as f64,
        );
    }
    if let Some(o) = &p.firing_order {
        if !firing::fires_evenly_in(&p.layout, cycle, o) {
            r.warnings.push(format!(
                "the layout does not fire evenly in the order {} ({} cycle): `model.firing` lists the orders it does fire evenly in",
                firing::order_text(o),
                cycle.as_str()
            ));
        }
    }
}

/// The chosen phases (`cylinder_<i>_phase_rad`), the headline's error over the search, and
/// the `phases` section (every layout, best first).
fn phase_numbers(p: &MultiCylinderProblem, search: &PhaseSearch, r: &mut SolveResult) {
    for (i, c) in p.layout.cylinders.iter().enumerate() {
        r.design
            .insert(format!("cylinder_{}_phase_rad", i + 1), c.phase);
    }
    r.derived
        .insert("phase_layouts".into(), search.candidates.len() as f64);
    r.derived.insert("phase_search_error".into(), search.error);
    let mut order: Vec<usize> = (0..search.candidates.len()).collect();
    order.sort_by(|a, b| {
        search.candidates[*a]
            .value
            .total_cmp(&search.candidates[*b].value)
    });
    let rows: Vec<serde_json::Value> = order
        .iter()
        .map(|&k| {
            let c = &search.candidates[k];
            let deg: Vec<String> = c
                .phases
                .iter()
                .map(|a| format!("{:.1}", a.to_degrees()))
                .collect();
            let mut row = json!({
                "phases_deg": deg.join(" "),
                "value": c.value,
                "error": c.error,
                "status": c.status.as_str(),
            });
            if let Some(cycle) = p.cycle {
                row["firing_order"] = json!(first_even_order(p, &c.phases, cycle));
            }
            row
        })
        .collect();
    r.extra
        .insert("phases".into(), serde_json::Value::Array(rows));
}

/// The first even firing order of the layout with `phases` (the given order when it fires
/// evenly in it), or `uneven`.
fn first_even_order(p: &MultiCylinderProblem, phases: &[f64], cycle: firing::Cycle) -> String {
    let mut layout = p.layout.clone();
    for (c, a) in layout.cylinders.iter_mut().zip(phases) {
        c.phase = *a;
    }
    if let Some(o) = p.firing_order.as_ref() {
        if firing::fires_evenly_in(&layout, cycle, o) {
            return firing::order_text(o);
        }
    }
    let (orders, _) = firing::even_orders(&layout, cycle);
    orders
        .first()
        .map_or_else(|| "uneven".into(), |o| firing::order_text(o))
}

/// The frame, in words: ground, or a rigid body on its mounts.
fn frame_text(p: &MultiCylinderProblem) -> String {
    match &p.frame {
        None => "rigid ground: the shaking force and couple are what the links and unbalances exert on it".into(),
        Some(f) => format!(
            "a rigid body of {} kg on {} mounts (linear springs and viscous dampers), its steady state order by order (orders 1–{} of the bare layout by FFT)",
            f.mass,
            f.mounts.len(),
            super::solve::MOUNT_ORDERS
        ),
    }
}

/// The key prefix of rotor j: `counterweight_<k>` or `shaft_<k>` (k from 1 within its kind).
pub fn rotor_key(p: &MultiCylinderProblem, j: usize) -> String {
    let r = &p.rotors[j];
    let k = p.rotors[..j].iter().filter(|o| o.shaft == r.shaft).count() + 1;
    if r.shaft {
        format!("shaft_{k}")
    } else {
        format!("counterweight_{k}")
    }
}

/// The result's numbers.
pub fn numbers(_: &Scene, p: &MultiCylinderProblem, sol: &Solution, r: &mut SolveResult) {
    let p = sol.scene(p);
    if let Some(search) = &sol.phases {
        phase_numbers(p, search, r);
    }
    firing_numbers(p, r);
    r.baselines.insert(
        "bare".into(),
        BTreeMap::from([
            ("peak_shaking_force_n".into(), sol.bare[FORCE].peak),
            ("peak_couple_nm".into(), sol.bare[COUPLE].peak),
        ]),
    );
    // An infeasible or failed design has no peaks (and no design): the bare layout's.
    let found =
        (sol.design.as_ref()).filter(|d| !d.peaks.is_empty() && d.x.iter().all(|v| v.is_finite()));
    if sol.design.is_some() && found.is_none() {
        // No design to report figures of: the bare layout's are its baseline.
        numbers_of_spectra(sol, r);
        return;
    }
    let peaks = found.map_or(&sol.bare, |d| &d.peaks);
    r.objectives
        .insert("peak_shaking_force_n".into(), peaks[FORCE].peak);
    r.objectives
        .insert("peak_couple_nm".into(), peaks[COUPLE].peak);
    r.errors
        .insert("peak_shaking_force_n".into(), peaks[FORCE].error);
    r.errors
        .insert("peak_couple_nm".into(), peaks[COUPLE].error);
    r.derived
        .insert("peak_shaking_force_angle_rad".into(), peaks[FORCE].angle);
    r.derived
        .insert("peak_couple_angle_rad".into(), peaks[COUPLE].angle);
    mount_numbers(p, peaks, &sol.bare, r);
    let roll = &peaks[roll_index(p)];
    r.derived.insert("peak_roll_moment_nm".into(), roll.peak);
    r.derived
        .insert("peak_roll_moment_error_nm".into(), roll.error);
    r.derived
        .insert("peak_roll_moment_angle_rad".into(), roll.angle);
    if let Some(d) = found {
        design_numbers(p, d, r);
    }
    numbers_of_spectra(sol, r);
    if let Some(search) = &sol.phases {
        let head = super::study::headline(p);
        if let Some(k) = head.strip_prefix("objectives.") {
            r.errors.insert(k.into(), search.error);
        }
    }
    if let Some(front) = &sol.front {
        if let Some(why) = front.stopped() {
            r.warnings.push(why);
        }
        r.extra.insert("pareto".into(), front_rows(front));
    }
}

/// The mounts' peaks normal to the shaft (each, and the largest as the objective
/// `peak_mount_force_n`), the bare layout's, each mount's peak along the shaft with its error,
/// and the frame's natural frequencies.
fn mount_numbers(
    p: &MultiCylinderProblem,
    peaks: &[FieldPeak],
    bare: &[FieldPeak],
    r: &mut SolveResult,
) {
    let Some(frame) = &p.frame else { return };
    let worst = |ps: &[FieldPeak]| {
        ps[normal_mounts(p)]
            .iter()
            .max_by(|a, b| a.peak.total_cmp(&b.peak))
            .map(|m| (m.peak, m.error))
    };
    if let (Some((v, e)), Some((b, _))) = (worst(peaks), worst(bare)) {
        r.objectives.insert("peak_mount_force_n".into(), v);
        r.errors.insert("peak_mount_force_n".into(), e);
        if let Some(m) = r.baselines.get_mut("bare") {
            m.insert("peak_mount_force_n".into(), b);
        }
    }
    for (k, m) in peaks[normal_mounts(p)].iter().enumerate() {
        r.derived
            .insert(format!("mount_{}_peak_force_n", k + 1), m.peak);
        r.derived
            .insert(format!("mount_{}_peak_force_angle_rad", k + 1), m.angle);
    }
    for (k, m) in peaks[axial_mounts(p)].iter().enumerate() {
        r.derived
            .insert(format!("mount_{}_peak_axial_force_n", k + 1), m.peak);
        r.derived
            .insert(format!("mount_{}_peak_axial_force_error_n", k + 1), m.error);
    }
    let modes = frame.natural_frequencies();
    for (i, w) in modes.iter().enumerate() {
        r.derived.insert(format!("frame_mode_{}_rad_s", i + 1), *w);
    }
    for n in [1.0, 2.0] {
        let speed = n * p.omega;
        if let Some(w) = modes.iter().find(|w| (speed / **w - 1.0).abs() < 0.15) {
            r.warnings.push(format!(
                "order {n} of the speed ({speed:.2} rad/s) is within 15 % of a natural frequency of the frame on its mounts ({w:.2} rad/s): the mount forces there rest on the damping, which is rarely known well"
            ));
        }
    }
}

/// The harmonics' figures and the `harmonics` section.
fn numbers_of_spectra(sol: &Solution, r: &mut SolveResult) {
    harmonic_numbers(&sol.bare_spectrum, "bare_", r);
    if let Some(s) = &sol.spectrum {
        harmonic_numbers(s, "", r);
    }
    textbook_numbers(&sol.textbook, r);
    r.extra.insert("harmonics".into(), harmonic_rows(sol));
}

/// The design's unbalances, the mass objective and the certificate's parts.
fn design_numbers(p: &MultiCylinderProblem, d: &minimax::Solution, r: &mut SolveResult) {
    let mut mass = 0.0;
    for (j, rot) in p.rotors.iter().enumerate() {
        let key = rotor_key(p, j);
        let u = [d.x[var_u(j)], d.x[var_u(j) + 1]];
        let (size, angle) = polar(u);
        let m = size / rot.radius_max;
        mass += m;
        r.design.insert(format!("{key}_unbalance_kgm"), size);
        r.design.insert(format!("{key}_angle_rad"), angle);
        r.design.insert(format!("{key}_mass_at_radius_max_kg"), m);
        r.bounds.extend(ActiveBound::check(
            &format!("design.{key}_mass_at_radius_max_kg"),
            m,
            (0.0, rot.mass_max),
            1e-6,
            ("no unbalance", "the unbalance is not needed"),
            ("mass_max", "the rotor's mass limit binds"),
        ));
    }
    r.objectives.insert("counterweight_mass_kg".into(), mass);
    let e = &d.error;
    for (k, v) in [
        ("lower_bound", d.lower_bound),
        ("gap_sampling", e.sampling),
        ("error_solver", e.solver),
        ("error_evaluation", e.evaluation),
        ("error_refinement", e.refinement),
        ("socp_rounds", d.rounds as f64),
        ("sampled_angles", d.angles as f64),
        ("ipm_iterations", d.ipm_iterations as f64),
        ("design_constraint_violation", d.design_violation),
    ] {
        r.derived.insert(k.into(), v);
    }
    let head = match p.goal {
        Goal::PeakForce => "peak_shaking_force_n",
        Goal::PeakCouple => "peak_couple_nm",
        Goal::CounterweightMass => "counterweight_mass_kg",
        Goal::PeakMountForce => "peak_mount_force_n",
    };
    r.errors.insert(head.into(), e.total);
}

/// The primary and secondary forward and backward amplitudes (`<prefix>primary_force_forward_n`,
/// …), from the FFT.
fn harmonic_numbers(s: &Spectrum, prefix: &str, r: &mut SolveResult) {
    for (h, name) in s.force.iter().zip(["primary", "secondary"]) {
        r.derived.insert(
            format!("{prefix}{name}_force_forward_n"),
            h.forward_amplitude(),
        );
        r.derived.insert(
            format!("{prefix}{name}_force_backward_n"),
            h.backward_amplitude(),
        );
    }
    for (h, name) in s.couple.iter().zip(["primary", "secondary"]) {
        r.derived.insert(
            format!("{prefix}{name}_couple_forward_nm"),
            h.forward_amplitude(),
        );
        r.derived.insert(
            format!("{prefix}{name}_couple_backward_nm"),
            h.backward_amplitude(),
        );
    }
    r.derived
        .insert(format!("{prefix}harmonic_force_error_n"), s.force_error);
    r.derived
        .insert(format!("{prefix}harmonic_couple_error_nm"), s.couple_error);
}

/// The textbook's sums of the bare layout (`textbook_primary_force_forward_n`, …).
fn textbook_numbers(t: &[Harmonic; 4], r: &mut SolveResult) {
    for (h, name) in t.iter().zip([
        "primary_force",
        "secondary_force",
        "primary_couple",
        "secondary_couple",
    ]) {
        let unit = if name.ends_with("couple") { "nm" } else { "n" };
        r.derived.insert(
            format!("textbook_{name}_forward_{unit}"),
            h.forward_amplitude(),
        );
        r.derived.insert(
            format!("textbook_{name}_backward_{unit}"),
            h.backward_amplitude(),
        );
    }
}

/// The `harmonics` section: one row per order, bare and with the design.
fn harmonic_rows(sol: &Solution) -> serde_json::Value {
    let rows: Vec<serde_json::Value> = (0..sol.bare_spectrum.force.len())
        .map(|k| {
            let b = &sol.bare_spectrum;
            let mut row = json!({
                "order": k + 1,
                "bare_force_forward_n": b.force[k].forward_amplitude(),
                "bare_force_backward_n": b.force[k].backward_amplitude(),
                "bare_couple_forward_nm": b.couple[k].forward_amplitude(),
                "bare_couple_backward_nm": b.couple[k].backward_amplitude(),
            });
            if let Some(s) = &sol.spectrum {
                row["force_forward_n"] = json!(s.force[k].forward_amplitude());
                row["force_backward_n"] = json!(s.force[k].backward_amplitude());
                row["couple_forward_nm"] = json!(s.couple[k].forward_amplitude());
                row["couple_backward_nm"] = json!(s.couple[k].backward_amplitude());
            }
            row
        })
        .collect();
    serde_json::Value::Array(rows)
}

/// The `pareto` section: each point's limit on the couple, its peaks and status.
fn front_rows(front: &minimax::ParetoFront) -> serde_json::Value {
    let rows: Vec<serde_json::Value> = front
        .points
        .iter()
        .map(|pt| {
            let s = &pt.solution;
            json!({
                "max_peak_couple_nm": pt.eps,
                "peak_shaking_force_n": s.peaks[FORCE].peak,
                "peak_shaking_force_error_n": s.error.total,
                "peak_couple_nm": s.peaks[COUPLE].peak,
                "peak_couple_error_nm": s.peaks[COUPLE].error,
                "status": crate::families::family::cw_status(s.status).as_str(),
            })
        })
        .collect();
    serde_json::Value::Array(rows)
}
