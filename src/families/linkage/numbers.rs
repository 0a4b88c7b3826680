//! The linkage's numbers: the solution's figures into the result's maps — `model`, design,
//! objectives with their errors, derived figures, baselines, paper checks, sections and the
//! warnings of the result's own checks (keys in `docs/results.md`). Arithmetic on the solution
//! (sums, ratios, a limit compared), never a solve or a search: the driver runs it at solve
//! time for every result, `--summary-only` included, and `report.rs` draws from the same
//! solution.

use super::file::{Goal, LinkageProblem};
use super::solve::{JointLoads, Solution as Solved};
use super::synth::{self as ls, FORCE, MOMENT, TORQUE};
use crate::families::family::{cw_status, Scene};
use crate::families::linkage::model::JointKind;
use crate::families::linkage::shape::Requirement;
use crate::geom::plate::{PlateShape, Realised};
use crate::geom::P2;
use crate::report::{ActiveBound, SolveResult};
use crate::synth::counterweight::Status as CwStatus;
use crate::synth::minimax::{FieldPeak, Solution};
use serde_json::json;
use std::collections::BTreeMap;
use std::f64::consts::TAU;

/// The objective keys of the three fields' peaks and RMS.
const PEAK_KEYS: [&str; 3] = [
    "peak_shaking_force_n",
    "peak_shaking_moment_nm",
    "peak_input_torque_nm",
];

/// See [`PEAK_KEYS`].
const RMS_KEYS: [&str; 3] = [
    "rms_shaking_force_n",
    "rms_shaking_moment_nm",
    "rms_input_torque_nm",
];

/// The key of `objectives` the scene's goal is judged on.
pub fn objective_key(g: Goal) -> &'static str {
    match g {
        Goal::PeakForce => PEAK_KEYS[FORCE],
        Goal::PeakMoment => PEAK_KEYS[MOMENT],
        Goal::PeakTorque => PEAK_KEYS[TORQUE],
        Goal::RmsForce => RMS_KEYS[FORCE],
        Goal::RmsMoment => RMS_KEYS[MOMENT],
        Goal::RmsTorque => RMS_KEYS[TORQUE],
        Goal::CounterweightMass => "counterweight_mass_kg",
        Goal::EnergyFluctuation => "energy_fluctuation_j",
    }
}

fn put_fields(
    m: &mut BTreeMap<String, f64>,
    e: Option<&mut BTreeMap<String, f64>>,
    peaks: &[FieldPeak],
    rms: &[(f64, f64); 3],
) {
    let mut errs = Vec::new();
    // An infeasible or failed solve has no peaks (and its RMS are NaN, dropped as such).
    for (k, pk) in peaks.iter().enumerate().take(3) {
        m.insert(PEAK_KEYS[k].into(), pk.peak);
        errs.push((PEAK_KEYS[k], pk.error));
    }
    for k in 0..3 {
        m.insert(RMS_KEYS[k].into(), rms[k].0);
        // The quadrature's estimate plus the field's evaluation error (an RMS is off by at
        // most the largest pointwise error; the peak's bound stands for it).
        let eval = peaks.get(k).map_or(0.0, |p| p.error);
        errs.push((RMS_KEYS[k], rms[k].1 + eval));
    }
    if let Some(e) = e {
        for (k, v) in errs {
            e.insert(k.into(), v);
        }
    }
}

/// The result's `model` section: the links, the moment's reference point, the speed and
/// what gravity enters.
pub fn model(p: &LinkageProblem, _: Option<&Solved>) -> BTreeMap<String, serde_json::Value> {
    let sc = &p.scene;
    BTreeMap::from([
        ("links".into(), json!(sc.link_names)),
        (
            "moment_about_m".into(),
            json!([sc.moment_about.x, sc.moment_about.y]),
        ),
        ("speed_rad_s".into(), json!(sc.linkage.omega())),
        (
            "gravity".into(),
            if sc.linkage.gravity().norm() > 0.0 {
                json!({"acceleration_m_s2": sc.linkage.gravity().norm(), "enters": "input torque only"})
            } else {
                json!("not modelled")
            },
        ),
    ])
    .into_iter()
    .chain((!sc.linkage.loads().is_empty()).then(|| {
        (
            "process_loads".into(),
            json!({
                "count": sc.linkage.loads().len(),
                "enter": "input torque, drive and joint loads (reacted by the frame: not the shaking force or moment)"
            }),
        )
    }))
    .collect()
}

/// The result's numbers from the solution: the unbalanced baseline, status, design,
/// objectives with their errors, the front, Berkof–Lowen and the joint loads.
pub fn numbers(_: &Scene, p: &LinkageProblem, sol: &Solved, r: &mut SolveResult) {
    let (sc, out) = (&p.scene, &sol.out);
    let mut bare = BTreeMap::new();
    put_fields(&mut bare, None, &out.bare, &out.bare_rms);
    r.baselines.insert("unbalanced".into(), bare);
    r.derived
        .insert("max_dyad_conditioning".into(), out.kappa_max);
    let key = objective_key(sc.objective.minimize);
    r.objective = Some(key.into());
    match (&out.design, out.balance_residual) {
        // A balance out of reach, an analysis, or no design within the limits: the bare
        // linkage's figures (the claim says which).
        (Some(d), None) if d.status != CwStatus::Infeasible => design_keys(r, p, sol, d, key),
        _ => put_fields(
            &mut r.objectives,
            Some(&mut r.errors),
            &out.bare,
            &out.bare_rms,
        ),
    }
    energy_numbers(r, sol);
    if let Some(front) = &out.pareto {
        if let Some(why) = front.stopped() {
            r.warnings.push(why);
        }
        r.extra
            .insert("pareto".into(), Front::of(front, out).json(&r.name));
    }
    envelope_numbers(r, p, sol);
    path_numbers(r, p, sol);
    berkof_lowen(r, p, sol);
    joint_numbers(r, p, sol);
    let peak_force = drive_peak_force(sol);
    crate::report::drive::drive_numbers(r, sol.drive.as_ref(), peak_force);
    if let Some(lc) = &sol.load_cases {
        super::load_cases::numbers(r, lc, peak_force);
    }
}

/// With `[objective.path]`: `objectives.path_error_m` (its error in `errors`) and the
/// section `path` (each point's distance); with a shape search, the section `synthesis`:
/// the parameters, the file's geometry, "synthesise first, balance afterwards", the front
/// and the design's gain over the former (keys in `docs/results.md`).
fn path_numbers(r: &mut SolveResult, p: &LinkageProblem, sol: &Solved) {
    match (&sol.path, &p.path) {
        (Some(Ok(e)), Some(spec)) => {
            let lim = spec.max_error;
            let section = json!({
                "max_error_m": lim,
                "point_errors_m": e.points,
                "timing": spec.angles.is_some(),
            });
            requirement_figure(
                r,
                ("path_error_m", "path"),
                (e.max, e.error, lim),
                section,
                || {
                    format!(
                        "the path error {:e} m exceeds objective.path.max_error = {lim:e} m",
                        e.max
                    )
                },
            );
        }
        (Some(Err(why)), _) => r.warnings.push(format!("the path error: {why}")),
        _ => {}
    }
    swing_numbers(r, p, sol);
    let Some(shape) = &p.shape else { return };
    if let Some(chosen) = shape.chosen() {
        // The geometry to build: "length of crank" → `length_of_crank_m`.
        for (name, x) in shape.parameters.iter().zip(&chosen.x) {
            r.design.insert(format!("{}_m", name.replace(' ', "_")), *x);
        }
    }
    let mut v = serde_json::to_value(shape).unwrap_or_default();
    v["objective_key"] = json!(objective_key(p.scene.objective.minimize));
    let (kin, design) = (
        shape.kinematic_first.objective,
        shape.chosen().and_then(|c| c.objective),
    );
    if let (Some(k), Some(d)) = (kin, design) {
        v["gain_over_kinematic_first"] = json!(1.0 - d / k);
    }
    r.extra.insert("synthesis".into(), v);
}

/// With `[objective.dwell]`: `objectives.dwell_error_m` for a slider, `dwell_error_rad` for a
/// rocker (max(travel in the window, |stroke or swing − target|), its error in `errors`) and
/// the section `dwell`, its figures in the same unit: `travel_m`, `travel_bound_m`,
/// `stroke_m`, `stroke_bound_m`, `target_m`, `max_error_m` for a slider; `travel_rad`,
/// `travel_bound_rad`, `swing_rad`, `swing_bound_rad`, `target_rad`, `max_error_rad` for a
/// rocker; with `output` ("slider" or "rocker") and `crank_angles_deg`.
fn dwell_numbers(r: &mut SolveResult, p: &LinkageProblem, sol: &Solved) {
    match (&sol.dwell, &p.dwell) {
        (Some(Ok(w)), Some(spec)) => {
            let e = w.error(spec);
            let (u, range) = (spec.of.si_unit(), spec.of.range_key());
            let section = json!({
                "output": spec.of.name(),
                format!("travel_{u}"): w.travel.value,
                format!("travel_bound_{u}"): w.travel.error,
                format!("{range}_{u}"): w.range.value,
                format!("{range}_bound_{u}"): w.range.error,
                format!("target_{u}"): spec.range,
                "crank_angles_deg": [spec.from.to_degrees(), spec.to.to_degrees()],
                format!("max_error_{u}"): spec.max_error,
            });
            let key = format!("dwell_error_{u}");
            let figure = (e, w.error_bound(), spec.max_error);
            requirement_figure(r, (&key, "dwell"), figure, section, || {
                // In the report's unit (mm or deg), as the front's table shows it.
                let shown = |v| Requirement::Dwell(spec).named(v).shown();
                let ((_, e, unit), (_, limit, _)) = (shown(e), shown(spec.max_error));
                format!(
                    "the dwell error {e:.6} {unit} exceeds objective.dwell.max_error = {limit:.6} {unit}"
                )
            });
        }
        (Some(Err(why)), _) => r.warnings.push(format!("the dwell: {why}")),
        _ => {}
    }
}

/// With `[objective.stroke]`: `objectives.stroke_error_m` (|stroke − target|, its error in
/// `errors`) and the section `stroke`; with `max_crank_ratio`: `derived.crank_ratio` (a
/// warning above the limit); with `joint_box`: `derived.joint_box_margin_m` and its error (a
/// warning where a joint leaves the box beyond its error).
fn stroke_numbers(r: &mut SolveResult, p: &LinkageProblem, sol: &Solved) {
    match (&sol.stroke, &p.stroke) {
        (Some(Ok(w)), Some(spec)) => {
            let e = (w.value - spec.stroke).abs();
            let section = json!({
                "stroke_m": w.value,
                "stroke_bound_m": w.error,
                "target_m": spec.stroke,
                "max_error_m": spec.max_error,
            });
            let figure = (e, w.error, spec.max_error);
            requirement_figure(r, ("stroke_error_m", "stroke"), figure, section, || {
                format!(
                    "the stroke error {:.6} mm exceeds objective.stroke.max_error = {:.6} mm",
                    e * 1e3,
                    spec.max_error * 1e3
                )
            });
        }
        (Some(Err(why)), _) => r.warnings.push(format!("the stroke: {why}")),
        _ => {}
    }
    match &sol.box_margin {
        Some(Ok(m)) => {
            r.derived.insert("joint_box_margin_m".into(), m.value);
            r.errors.insert("joint_box_margin_m".into(), m.error);
            if m.value + m.error < 0.0 {
                r.warnings.push(format!(
                    "a joint leaves design.synthesis.joint_box by {:.6} mm at the crank angle {:.3}°",
                    -m.value * 1e3,
                    m.angle.to_degrees()
                ));
            }
        }
        Some(Err(why)) => r.warnings.push(format!("the joint box: {why}")),
        None => {}
    }
    let limit = (p.synthesis.as_ref()).and_then(|s| s.max_crank_ratio);
    if let (Some(lambda), Some(c)) = (sol.crank_ratio, limit) {
        r.derived.insert("crank_ratio".into(), lambda);
        if lambda > c.max {
            r.warnings.push(format!(
                "the crank ratio {lambda:.6} is above design.synthesis.max_crank_ratio = {}",
                c.max
            ));
        }
    }
}

/// With `[objective.swing]`: `objectives.swing_error_rad` (|swing − angle|, its error in
/// `errors`) and the section `swing`; with `[objective.function]`:
/// `objectives.function_error_rad` and the section `function`; with
/// `min_transmission_angle`: `derived`'s
/// `min_transmission_angle_rad` and its error. A requirement missed beyond its error is a
/// warning.
fn swing_numbers(r: &mut SolveResult, p: &LinkageProblem, sol: &Solved) {
    match (&sol.swing, &p.swing) {
        (Some(Ok(w)), Some(spec)) => {
            let e = (w.value - spec.angle).abs();
            let section = json!({
                "swing_rad": w.value,
                "swing_bound_rad": w.error,
                "angle_rad": spec.angle,
                "max_error_rad": spec.max_error,
            });
            let figure = (e, w.error, spec.max_error);
            requirement_figure(r, ("swing_error_rad", "swing"), figure, section, || {
                format!(
                    "the swing error {:.6}° exceeds objective.swing.max_error = {:.6}°",
                    e.to_degrees(),
                    spec.max_error.to_degrees()
                )
            });
        }
        (Some(Err(why)), _) => r.warnings.push(format!("the swing: {why}")),
        _ => {}
    }
    match (&sol.function, &p.function) {
        (Some(Ok((e, each))), Some(spec)) => {
            let section = json!({ "point_errors_rad": each, "max_error_rad": spec.max_error });
            let figure = (e.value, e.error, spec.max_error);
            requirement_figure(
                r,
                ("function_error_rad", "function"),
                figure,
                section,
                || {
                    format!(
                        "the function error {:.6}° exceeds objective.function.max_error = {:.6}°",
                        e.value.to_degrees(),
                        spec.max_error.to_degrees()
                    )
                },
            );
        }
        (Some(Err(why)), _) => r.warnings.push(format!("the function: {why}")),
        _ => {}
    }
    stroke_numbers(r, p, sol);
    dwell_numbers(r, p, sol);
    let limit = p.synthesis.as_ref().and_then(|s| s.min_transmission);
    match (&sol.transmission, limit) {
        (Some(Ok(t)), Some(mu)) => {
            r.derived
                .insert("min_transmission_angle_rad".into(), t.value);
            r.errors
                .insert("min_transmission_angle_rad".into(), t.error);
            if t.value + t.error < mu {
                r.warnings.push(format!(
                    "the least transmission angle {:.4}° is below design.synthesis.min_transmission_angle = {:.4}°",
                    t.value.to_degrees(),
                    mu.to_degrees()
                ));
            }
        }
        (Some(Err(why)), _) => r.warnings.push(format!("the transmission angle: {why}")),
        _ => {}
    }
}

/// One kinematic requirement's figure in the result: `objectives[key]` = `value`, its
/// `error` in `errors`, the section `name`, and the warning `exceeded()` where the value is
/// above `limit` beyond its error.
fn requirement_figure(
    r: &mut SolveResult,
    (key, name): (&str, &str),
    (value, error, limit): (f64, f64, f64),
    section: serde_json::Value,
    exceeded: impl FnOnce() -> String,
) {
    r.objectives.insert(key.into(), value);
    r.errors.insert(key.into(), error);
    r.extra.insert(name.into(), section);
    if value > limit + error {
        r.warnings.push(exceeded());
    }
}

/// The keys of the worst cases over an operating envelope: force, moment, torque, ΔE.
pub const WORST_KEYS: [&str; 4] = [
    "worst_case_peak_shaking_force_n",
    "worst_case_peak_shaking_moment_nm",
    "worst_case_peak_input_torque_nm",
    "worst_case_energy_fluctuation_j",
];

/// With an operating envelope: the worst cases in `objectives` (the objective's own is the
/// result's objective, its error the binding scenario's plus the certified gap), the
/// section `envelope`, and a warning where a Monte Carlo sample exceeds a worst case.
fn envelope_numbers(r: &mut SolveResult, p: &LinkageProblem, sol: &Solved) {
    let env = match &sol.envelope {
        None => return,
        Some(Err(why)) => {
            let why =
                format!("the design over the operating envelope could not be evaluated: {why}");
            return r.warnings.push(why);
        }
        Some(Ok(e)) => e,
    };
    let goal = p.scene.objective.minimize;
    let own = match goal {
        Goal::PeakForce => Some(0),
        Goal::PeakMoment => Some(1),
        Goal::PeakTorque => Some(2),
        Goal::EnergyFluctuation => Some(3),
        _ => None,
    };
    let gap = sol.out.design.as_ref().map_or(0.0, |d| d.error.total);
    for (c, w) in env.worst.iter().enumerate() {
        let Some(w) = w else { continue };
        r.objectives.insert(WORST_KEYS[c].into(), w.value);
        let e = w.error + if own == Some(c) { gap } else { 0.0 };
        r.errors.insert(WORST_KEYS[c].into(), e);
    }
    if let Some(c) = own {
        r.objective = Some(WORST_KEYS[c].into());
    }
    if let Some(mc) = env.monte_carlo.as_ref().filter(|m| m.beyond_worst_case > 0) {
        r.warnings.push(format!(
            "{} of {} Monte Carlo samples of the envelope exceed a worst case beyond both errors",
            mc.beyond_worst_case, mc.samples
        ));
    }
    if let Some(why) = &env.sensitivity_error {
        r.warnings.push(format!(
            "the envelope's sensitivities could not be computed: {why}"
        ));
    }
    let mut v = serde_json::to_value(env).unwrap_or_default();
    v["certified"] = json!(p.scene.envelope.certified());
    v["csv"] = json!(format!("{}-envelope.csv", r.name));
    r.extra.insert("envelope".into(), v);
}

/// The envelope's table: one row per scenario (the nominal first), its load case (with
/// `[[mechanism.load_cases]]`), the parameters' values, then each figure and its error.
pub(super) fn envelope_csv(
    env: &crate::families::linkage::solve_envelope::EnvelopeOutcome,
) -> String {
    let cases = env.scenarios.first().is_some_and(|f| f.case.is_some());
    let mut head: Vec<String> = cases.then(|| "case".to_string()).into_iter().collect();
    head.extend(env.parameters.iter().cloned());
    head.extend(
        [
            "peak_shaking_force_n",
            "peak_shaking_moment_nm",
            "peak_input_torque_nm",
            "energy_fluctuation_j",
        ]
        .iter()
        .flat_map(|k| [k.to_string(), format!("{k}_error")]),
    );
    let mut csv = head.join(",") + "\n";
    for f in &env.scenarios {
        let mut row: Vec<String> = f.case.iter().cloned().collect();
        row.extend(f.values.iter().map(|v| format!("{v:.9e}")));
        for (v, e) in [
            f.peak_shaking_force_n,
            f.peak_shaking_moment_nm,
            f.peak_input_torque_nm,
            f.energy_fluctuation_j.unwrap_or((f64::NAN, f64::NAN)),
        ] {
            row.push(if v.is_nan() {
                String::new()
            } else {
                format!("{v:.12e}")
            });
            row.push(if e.is_nan() {
                String::new()
            } else {
                format!("{e:.3e}")
            });
        }
        csv += &(row.join(",") + "\n");
    }
    csv
}

/// ΔE with `minimize = "energy-fluctuation"`: the unbalanced baseline's and the result's
/// (the design's, else the bare linkage's), each from the drive's own quadrature; the error
/// is the larger of that quadrature's and the engine's certificate (set by `design_keys`).
fn energy_numbers(r: &mut SolveResult, sol: &Solved) {
    let key = "energy_fluctuation_j";
    let e = match &sol.energy {
        None => return,
        Some(Err(why)) => {
            r.warnings.push(format!(
                "the energy fluctuation could not be computed: {why}"
            ));
            return;
        }
        Some(Ok(e)) => e,
    };
    if let Some(b) = r.baselines.get_mut("unbalanced") {
        b.insert(key.into(), e.bare.0);
    }
    let designed = sol
        .out
        .design
        .as_ref()
        .is_some_and(|d| d.status != CwStatus::Infeasible);
    let (v, err) = match e.design {
        Some(d) if designed => d,
        _ => e.bare,
    };
    r.objectives.insert(key.into(), v);
    let own = r.errors.get(key).copied().unwrap_or(0.0);
    r.errors.insert(key.into(), own.max(err));
}

/// The thickness of the plate of density `rho` cut as the sector (rᵢ, rₒ, θ) that carries
/// mass `m`: t = m / (ρ θ (rₒ² − rᵢ²)/2), as `design.<link>_counterweight_plate_thickness_m`;
/// a plate thicker than its envelope radius is no plate (a sliver of a sector: the optimum's
/// inertia, free where the objective does not see it, sits at its bound), and the result
/// says so.
fn plate_thickness(
    r: &mut SolveResult,
    n: &str,
    m: f64,
    rho: f64,
    (ri, ro, th): (f64, f64, f64),
    envelope: f64,
) {
    let area = 0.5 * th * (ro * ro - ri * ri);
    let t = m / (rho * area);
    r.design
        .insert(format!("{n}_counterweight_plate_thickness_m"), t);
    if !(t <= envelope) {
        r.warnings.push(format!(
            "the {n} counterweight's sector (rᵢ {:.2} mm, rₒ {:.2} mm, {:.2}°) would be a plate {:.1} mm thick, more than its envelope radius {:.2} mm: not a plate to cut; a heavier material, a larger envelope or a limit on its inertia changes it",
            ri * 1e3,
            ro * 1e3,
            th.to_degrees(),
            t * 1e3,
            envelope * 1e3
        ));
    }
}

/// A plate counterweight's keys: its thickness and area, and the shape cut (a ring centred
/// at the centroid: `plate_inner_radius_m`, `plate_outer_radius_m`; a lens, the envelope
/// cut by a disc: `plate_cut_radius_m`, `plate_cut_centre_distance_m` from the joint along
/// the centroid's direction, and `plate_chord_distance_m`, where the two circles cross — a
/// cut radius of many envelope radii is a straight cut there).
fn plate_keys(r: &mut SolveResult, n: &str, plate: &Realised, t: f64) {
    let mut put = |k: &str, v: f64| {
        r.design.insert(format!("{n}_counterweight_plate_{k}"), v);
    };
    put("thickness_m", t);
    put("area_m2", plate.shape.moments().area);
    match plate.shape {
        PlateShape::Ring { inner, outer, .. } => {
            put("inner_radius_m", inner);
            put("outer_radius_m", outer);
        }
        PlateShape::Lens {
            envelope,
            disc_centre,
            disc_radius,
        } => {
            // The chord where the two circles cross: x = (R² − ρ² + D²)/(2D).
            let dd = disc_centre.norm();
            let chord =
                (envelope * envelope - (disc_radius - dd) * (disc_radius + dd)) / (2.0 * dd);
            put("cut_radius_m", disc_radius);
            put("cut_centre_distance_m", dd);
            put("chord_distance_m", chord);
        }
    }
}

/// Design, objectives, errors and solver facts of a solved design.
fn design_keys(
    r: &mut SolveResult,
    p: &LinkageProblem,
    solution: &Solved,
    sol: &Solution,
    key: &str,
) {
    let (sc, out) = (&p.scene, &solution.out);
    let mut total_mass = 0.0;
    for j in 0..sc.counterweights.len() {
        total_mass += counterweight_keys(r, p, solution, sol, j);
    }
    let rms = out.design_rms.unwrap_or([(f64::NAN, f64::NAN); 3]);
    put_fields(&mut r.objectives, Some(&mut r.errors), &sol.peaks, &rms);
    r.objectives
        .insert("counterweight_mass_kg".into(), total_mass);
    // The optimised figure's bound covers its distance from the true optimum too.
    let own = r.errors.get(key).copied().unwrap_or(0.0);
    r.errors.insert(key.into(), own.max(sol.error.total));
    solver_facts(r, p, out, sol);
}

/// Counterweight j's keys: its mass, centroid, angle, first moment and inertias, the annular
/// sector that realises it, and the bounds it sits on; returns its mass.
fn counterweight_keys(
    r: &mut SolveResult,
    p: &LinkageProblem,
    solution: &Solved,
    sol: &Solution,
    j: usize,
) -> f64 {
    let cw = &p.scene.counterweights[j];
    let d = sol.counterweight(j);
    let n = &cw.link_name;
    r.design
        .insert(format!("{n}_counterweight_mass_kg"), d.mass);
    r.design
        .insert(format!("{n}_counterweight_radius_m"), d.radius);
    r.design.insert(
        format!("{n}_counterweight_angle_rad"),
        d.angle.rem_euclid(TAU),
    );
    r.design.insert(
        format!("{n}_counterweight_first_moment_x_kgm"),
        d.first_moment[0],
    );
    r.design.insert(
        format!("{n}_counterweight_first_moment_y_kgm"),
        d.first_moment[1],
    );
    r.design.insert(
        format!("{n}_counterweight_inertia_about_joint_kgm2"),
        d.inertia,
    );
    r.design.insert(
        format!("{n}_counterweight_centroidal_inertia_kgm2"),
        d.centroidal_inertia,
    );
    // One body with this mass, centroid and inertia about the joint, within the
    // envelope: the plate of the given thickness, else an annular sector about the joint,
    // symmetric about u (any thickness of areal density m/area).
    if let (Some(plate), Some(t)) = (solution.out.plates.get(j).copied().flatten(), cw.thickness) {
        plate_keys(r, n, &plate, t);
    } else if d.mass > 0.0 {
        match solution.sectors[j] {
            Some((ri, ro, th)) => {
                for (k, v) in [("inner_radius_m", ri), ("outer_radius_m", ro), ("angle_rad", th)] {
                    r.design.insert(format!("{n}_counterweight_sector_{k}"), v);
                }
                if let Some(rho) = cw.density {
                    plate_thickness(r, n, d.mass, rho, (ri, ro, th), cw.radius);
                }
            }
            None => r.warnings.push(format!(
                "the {n} counterweight (m {:.4} kg, centroid {:.2} mm, I {:.4e} kg·m² about its joint) is no annular sector within the envelope {:.2} mm",
                d.mass,
                d.radius * 1e3,
                d.inertia,
                cw.radius * 1e3
            )),
        }
    }
    // A counterweight at its largest mass or radius: the limit, not the balance, sizes it.
    if d.mass > 0.0 {
        let (m_lo, m_hi) = cw.mass.bounds();
        let field = format!("design.counterweights[{j}]");
        if m_hi > m_lo {
            r.bounds.extend(ActiveBound::check(
                &format!("design.{n}_counterweight_mass_kg"),
                d.mass,
                (m_lo, m_hi),
                1e-7,
                (&format!("{field}.mass"), "the least mass allowed"),
                (
                    &format!("{field}.mass"),
                    "the largest mass allowed: the limit, not the balance, sizes this counterweight",
                ),
            ));
        }
        r.bounds.extend(ActiveBound::check(
            &format!("design.{n}_counterweight_radius_m"),
            d.radius,
            (0.0, cw.radius),
            1e-7,
            (&format!("{field}.radius"), "at the joint"),
            (
                &format!("{field}.radius"),
                "the centroid at the envelope radius: as far out as allowed, the least mass for its first moment",
            ),
        ));
    }
    d.mass
}

/// The solver's figures (bound, gaps, rounds, angles) and the limit violations.
fn solver_facts(r: &mut SolveResult, p: &LinkageProblem, out: &ls::Outcome, sol: &Solution) {
    let sc = &p.scene;
    for (k, v) in [
        ("lower_bound", sol.lower_bound),
        ("gap_sampling", sol.error.sampling),
        ("error_solver", sol.error.solver),
        ("error_evaluation", sol.error.evaluation),
        ("error_refinement", sol.error.refinement),
        ("error_quadrature", sol.error.quadrature),
        ("design_constraint_violation", sol.design_violation),
        ("socp_rounds", sol.rounds as f64),
        ("sampled_angles", sol.angles as f64),
        ("ipm_iterations", f64::from(sol.ipm_iterations)),
        ("balance_equalities", out.balance_rows as f64),
    ] {
        r.derived.insert(k.into(), v);
    }
    for (f, pk) in sol.peaks.iter().enumerate().take(3) {
        if pk.violation > 0.0 {
            r.warnings.push(format!(
                "{} peak {:.6e} exceeds its limit {:.6e} by {:.3e}",
                PEAK_KEYS[f],
                pk.peak,
                pk.limit.unwrap_or(f64::NAN),
                pk.violation
            ));
        }
    }
    if sc.objective.full_force_balance && !sol.peaks.is_empty() {
        let bare = out.bare[FORCE].peak.max(f64::MIN_POSITIVE);
        r.derived.insert(
            "balanced_force_relative".into(),
            sol.peaks[FORCE].peak / bare,
        );
    }
}

/// One joint's row of the bearing loads.
pub(super) struct JointRow {
    /// The joint's label (`frame–crank`).
    pub label: String,
    /// `revolute` or `prismatic`.
    pub kind: &'static str,
    /// The bare linkage's peak at constant speed.
    pub bare: ls::JointPeak,
    /// The design's peak at constant speed, where there is a design.
    pub design: Option<ls::JointPeak>,
    /// The peak at real speed (the design's, else the bare linkage's), where there is a
    /// drive's steady state.
    pub steady: Option<ls::JointPeak>,
}

impl JointRow {
    /// The constant-speed peak the real-speed one is compared with: the design's, else the
    /// bare linkage's (as [`JointRow::steady`]).
    pub fn constant(&self) -> ls::JointPeak {
        self.design.unwrap_or(self.bare)
    }
}

/// One row per joint ([`JointRow`]).
pub(super) fn joint_rows<'a>(
    p: &'a LinkageProblem,
    loads: &'a JointLoads,
) -> impl Iterator<Item = JointRow> + 'a {
    let sc = &p.scene;
    let design = loads.design.as_ref().and_then(|d| d.as_ref().ok());
    let steady = loads.steady.as_ref().and_then(|d| d.as_ref().ok());
    sc.linkage
        .joints()
        .into_iter()
        .enumerate()
        .map(move |(k, j)| JointRow {
            label: ls::joint_label(&j, &sc.link_names),
            kind: match j.kind {
                JointKind::Revolute => "revolute",
                JointKind::Prismatic => "prismatic",
            },
            bare: loads.bare[k],
            design: design.map(|d| d[k]),
            steady: steady.map(|d| d[k]),
        })
}

/// The bearing loads: every joint's peak load over the cycle without and with the
/// counterweights (`joints`), the largest of them as `peak_joint_force_n` in the objectives
/// and the unbalanced baseline, a warning for each limit exceeded.
fn joint_numbers(r: &mut SolveResult, p: &LinkageProblem, solved: &Solved) {
    let sc = &p.scene;
    let loads = match &solved.joints {
        Ok(l) => l,
        Err(e) => {
            r.warnings.push(format!("joint loads not computed: {e}"));
            return;
        }
    };
    if let Some(Err(e)) = &loads.design {
        r.warnings
            .push(format!("joint loads of the design not computed: {e}"));
    }
    let design = loads.design.as_ref().and_then(|d| d.as_ref().ok());
    if let Some(b) = r.baselines.get_mut("unbalanced") {
        b.insert("peak_joint_force_n".into(), worst(&loads.bare).0);
    }
    // The figure of the result: the design's, or the bare linkage's for an analysis.
    if !r.objectives.is_empty() {
        let (w, e) = worst(design.unwrap_or(&loads.bare));
        r.objectives.insert("peak_joint_force_n".into(), w);
        r.errors.insert("peak_joint_force_n".into(), e);
    }
    if let Some(Err(e)) = &loads.steady {
        r.warnings
            .push(format!("joint loads at real speed not computed: {e}"));
    }
    let joint_rows: Vec<JointRow> = joint_rows(p, loads).collect();
    steady_joint_numbers(r, &joint_rows);
    // A peak over the joint-load limit (beyond its error and the solve's tolerance).
    let over = |pk: &ls::JointPeak| {
        sc.objective
            .max_joint_force
            .filter(|lim| pk.peak > lim * (1.0 + p.settings.rel_tol) + pk.error)
    };
    let mut rows = Vec::new();
    for row_of in &joint_rows {
        let (label, b) = (&row_of.label, row_of.bare);
        let mut row = json!({
            "joint": label,
            "kind": row_of.kind,
            "unbalanced_peak_n": b.peak,
            "unbalanced_peak_error_n": b.error,
            "unbalanced_angle_rad": b.angle,
        });
        if let Some(st) = row_of.steady {
            row["steady_peak_n"] = json!(st.peak);
            row["steady_peak_error_n"] = json!(st.error);
            row["steady_angle_rad"] = json!(st.angle);
            row["steady_change_pct"] = json!(100.0 * (st.peak / row_of.constant().peak - 1.0));
            if let Some(lim) = over(&st) {
                r.warnings.push(format!(
                    "joint {label} peak load at real speed {:.6e} N exceeds its limit {lim:.6e} N (the limit holds at the nominal constant speed)",
                    st.peak
                ));
            }
        }
        if let Some(d) = row_of.design {
            row["peak_n"] = json!(d.peak);
            row["peak_error_n"] = json!(d.error);
            row["angle_rad"] = json!(d.angle);
            if let Some(lim) = over(&d) {
                r.warnings.push(format!(
                    "joint {label} peak load {:.6e} N exceeds its limit {lim:.6e} N",
                    d.peak
                ));
            }
        }
        rows.push(row);
    }
    r.extra.insert(
        "joints".into(),
        json!({
            "load": "peak over the cycle of |R| (a pin) or of the force normal to the slide (a slide), Newton–Euler",
            "limit_n": sc.objective.max_joint_force,
            "joints": rows,
            "csv": format!("{}-joints.csv", r.name),
        }),
    );
}

/// The largest of several joint peaks, and its error: the largest of theirs (the largest of
/// several peaks is off by at most the largest of their errors).
fn worst<'a>(peaks: impl IntoIterator<Item = &'a ls::JointPeak>) -> (f64, f64) {
    peaks.into_iter().fold((0.0_f64, 0.0_f64), |(p, e), j| {
        (p.max(j.peak), e.max(j.error))
    })
}

/// The largest joint load at real speed (`derived.steady_peak_joint_force_n`, with its error
/// and its change from the constant-speed figure), where the drive's steady state gave them.
fn steady_joint_numbers(r: &mut SolveResult, rows: &[JointRow]) {
    let Some(steady) = rows.iter().map(|j| j.steady).collect::<Option<Vec<_>>>() else {
        return;
    };
    let (peak, error) = worst(&steady);
    let constant: Vec<ls::JointPeak> = rows.iter().map(JointRow::constant).collect();
    r.derived.insert("steady_peak_joint_force_n".into(), peak);
    r.derived
        .insert("steady_peak_joint_force_error_n".into(), error);
    r.derived.insert(
        "steady_peak_joint_force_change_pct".into(),
        100.0 * (peak / worst(&constant).0 - 1.0),
    );
}

/// A front as the result shows it — peak force against peak moment, or ΔE against peak
/// force — the points with a design, ordered by their limited field, each marked dominated or
/// not.
pub(super) struct Front<'a> {
    front: &'a crate::synth::minimax::ParetoFront,
    /// The points with a design (infeasible or failed points have no peaks: left out).
    ok: Vec<&'a crate::synth::minimax::ParetoPoint>,
    /// The optimised field (engine index).
    opt: usize,
    /// The optimised field's peak times this is the figure shown: 2 for the energy curve
    /// (its peak is max|E − c| = ΔE/2), else 1.
    scale: f64,
    /// Indices into `ok` by increasing limited field.
    order: Vec<usize>,
    /// Does a point fail to trade off?
    dominated: Vec<bool>,
}

impl<'a> Front<'a> {
    /// A point trades off only if, against every point of smaller limited field, its
    /// optimised field is lower by more than both errors; past the knee (the limit slack) the
    /// points repeat the unlimited optimum with a larger other field: dominated, left out of
    /// the front (kept in the CSV, marked).
    pub(super) fn of(
        front: &'a crate::synth::minimax::ParetoFront,
        out: &ls::Outcome,
    ) -> Front<'a> {
        let (opt, lim) = out.pareto_fields;
        let ok: Vec<_> = front
            .points
            .iter()
            .filter(|p| p.solution.peaks.len() > opt.max(lim))
            .collect();
        let mut order: Vec<usize> = (0..ok.len()).collect();
        order.sort_by(|&i, &j| {
            ok[i].solution.peaks[lim]
                .peak
                .total_cmp(&ok[j].solution.peaks[lim].peak)
        });
        let mut dominated = vec![false; ok.len()];
        let mut best: Option<(f64, f64)> = None;
        for &i in &order {
            let pk = &ok[i].solution.peaks[opt];
            match best {
                Some((v, e)) if pk.peak >= v - (e + pk.error) => dominated[i] = true,
                _ => best = Some((pk.peak, pk.error)),
            }
        }
        let energy = opt > TORQUE && lim == FORCE;
        Front {
            front,
            ok,
            opt,
            scale: if energy { 2.0 } else { 1.0 },
            order,
            dominated,
        }
    }

    /// Is this the ΔE–force front?
    pub(super) fn energy(&self) -> bool {
        self.scale == 2.0
    }

    /// ΔE and its error bound at point `pt` (J): twice the energy field's peak.
    fn energy_of(&self, pt: &crate::synth::minimax::ParetoPoint) -> (f64, f64) {
        let pk = &pt.solution.peaks[self.opt];
        (self.scale * pk.peak, self.scale * pk.error)
    }

    /// The `pareto` section of the result `name`.
    fn json(&self, name: &str) -> serde_json::Value {
        let pts: Vec<serde_json::Value> = self
            .ok
            .iter()
            .zip(&self.dominated)
            .filter(|(_, d)| !**d)
            .map(|(pt, _)| {
                let s = &pt.solution;
                let mut v = json!({
                    "eps": pt.eps,
                    "peak_shaking_force_n": s.peaks[FORCE].peak,
                    "peak_shaking_moment_nm": s.peaks[MOMENT].peak,
                    "error_total": self.scale * s.error.total,
                    "status": cw_status(s.status).as_str(),
                });
                if self.energy() {
                    let (de, err) = self.energy_of(pt);
                    v["energy_fluctuation_j"] = json!(de);
                    v["energy_fluctuation_error_j"] = json!(err);
                }
                v
            })
            .collect();
        let certified = self
            .front
            .points
            .iter()
            .filter(|p| p.solution.status == CwStatus::Optimal)
            .count();
        json!({"points": pts, "certified": certified, "without_design": self.front.points.len() - self.ok.len(), "dominated": self.dominated.iter().filter(|d| **d).count(), "requested": self.front.requested, "not_solved": self.front.requested - self.front.points.len(), "csv": format!("{name}-pareto.csv")})
    }

    /// The front's CSV: every point with a design, dominated ones marked (with ΔE and its
    /// error after the moment's columns on a ΔE–force front).
    pub(super) fn csv(&self) -> String {
        let mut csv = String::from(
            "eps,peak_shaking_force_n,peak_shaking_moment_nm,error_force_n,error_moment_nm,",
        );
        if self.energy() {
            csv += "energy_fluctuation_j,error_energy_j,";
        }
        csv += "gap,status,dominated\n";
        for (pt, dominated) in self.ok.iter().zip(&self.dominated) {
            let s = &pt.solution;
            csv += &format!(
                "{:.12e},{:.12e},{:.12e},{:.3e},{:.3e},",
                pt.eps,
                s.peaks[FORCE].peak,
                s.peaks[MOMENT].peak,
                s.peaks[FORCE].error,
                s.peaks[MOMENT].error,
            );
            if self.energy() {
                let (de, err) = self.energy_of(pt);
                csv += &format!("{de:.12e},{err:.3e},");
            }
            csv += &format!(
                "{:.3e},{},{dominated}\n",
                self.scale * s.error.total,
                cw_status(s.status).as_str(),
            );
        }
        csv
    }

    /// The plot's points, by increasing limited field: (peak moment, peak force), or on a
    /// ΔE–force front (peak force, ΔE).
    pub(super) fn line(&self) -> Vec<(f64, f64)> {
        self.order
            .iter()
            .filter(|&&i| !self.dominated[i])
            .map(|&i| {
                let p = &self.ok[i].solution.peaks;
                match self.energy() {
                    true => (p[FORCE].peak, self.scale * p[self.opt].peak),
                    false => (p[MOMENT].peak, p[FORCE].peak),
                }
            })
            .collect()
    }
}

/// For a four-bar with counterweights on crank and rocker: the Berkof–Lowen first moments
/// beside the numeric ones.
fn berkof_lowen(r: &mut SolveResult, p: &LinkageProblem, solved: &Solved) {
    let sc = &p.scene;
    let Some(fb) = solved.berkof_lowen else {
        return;
    };
    let sol = solved
        .out
        .design
        .as_ref()
        .filter(|s| s.x.iter().all(|v| v.is_finite()));
    let mut v = json!({
        "crank_first_moment_kgm": [fb.crank.x, fb.crank.y],
        "rocker_first_moment_kgm": [fb.rocker.x, fb.rocker.y],
        "crank_counterweight_first_moment_kgm": [fb.crank_add.x, fb.crank_add.y],
        "rocker_counterweight_first_moment_kgm": [fb.rocker_add.x, fb.rocker_add.y],
    });
    if let (Some(sol), true) = (sol, sc.objective.full_force_balance) {
        let find = |link: usize| sc.counterweights.iter().position(|c| c.link == link);
        if let (Some(a), Some(b)) = (find(fb.links.0), find(fb.links.1)) {
            let (ca, cb) = (sol.counterweight(a), sol.counterweight(b));
            let diff = (P2::from(ca.first_moment) - fb.crank_add).norm()
                + (P2::from(cb.first_moment) - fb.rocker_add).norm();
            let scale = fb.crank_add.norm() + fb.rocker_add.norm();
            v["numeric_minus_closed_form_relative"] = json!(diff / scale.max(f64::MIN_POSITIVE));
            r.derived.insert(
                "berkof_lowen_relative_difference".into(),
                diff / scale.max(f64::MIN_POSITIVE),
            );
        }
    }
    r.extra.insert("berkof_lowen".into(), v);
}

/// The constant-speed peak shaking force the drive's figures compare with: the design's where
/// there is one (the drive is its), the bare linkage's otherwise (N).
pub(super) fn drive_peak_force(sol: &Solved) -> Option<f64> {
    let out = &sol.out;
    let peaks = match &out.design {
        Some(d) if d.status != CwStatus::Infeasible && sol.design_x().is_some() => &d.peaks,
        _ => &out.bare,
    };
    peaks.first().map(|f| f.peak)
}
