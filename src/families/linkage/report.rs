//! The linkage result: the counterweights to build, the shaking force, shaking moment and input
//! torque with and without them (peaks and RMS with their error bounds), the Berkof–Lowen
//! closed form beside a four-bar's numeric full force balance, the force–moment front, the
//! curves over the cycle and a drawing of the linkage (keys in `docs/results.md`).

use super::file::{tip_of, Goal, LinkageProblem, LinkageScene};
use super::solve::{Analyses, JointLoads, Solution as Solved};
use super::synth::{self as ls, FORCE, MOMENT, TORQUE};
use crate::families::family::{cw_status, Scene};
use crate::families::linkage::model::{Dyad, JointKind, Linkage, Point};
use crate::geom::P2;
use crate::report::drawing::{Drawing, DrawingError, Layer, Sheet};
use crate::report::plot::{self, Panel, PlotError, Series};
use crate::report::{ActiveBound, Plot, SolveResult, Table};
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
    if let Some(front) = &out.pareto {
        r.extra.insert(
            "pareto".into(),
            Front::of(front, sc.objective.minimize).json(&r.name),
        );
    }
    berkof_lowen(r, p, sol);
    joint_numbers(r, p, sol);
    // The drive is the design's where there is one (the bare linkage's otherwise).
    let peaks = match &out.design {
        Some(d) if d.status != CwStatus::Infeasible && sol.design_x().is_some() => &d.peaks,
        _ => &out.bare,
    };
    let peak_force = peaks.first().map(|f| f.peak);
    crate::report::drive::drive_numbers(r, sol.drive.as_ref(), peak_force);
}

/// No analyses beyond the solution's own documents.
pub fn analysis_documents(
    _: &Scene,
    _: &LinkageProblem,
    _: &Solved,
    _: &Analyses,
    _: &mut SolveResult,
) {
}

/// The tables, plots and drawing of a solved scene, in the order the report lists them.
pub fn documents(scene: &Scene, p: &LinkageProblem, sol: &Solved, r: &mut SolveResult) {
    if let Some(front) = &sol.out.pareto {
        pareto_documents(r, &Front::of(front, p.scene.objective.minimize));
    }
    joint_table(r, p, sol);
    curves(r, scene, p, sol);
    crate::report::drive::drive_documents(r, sol.drive.as_ref(), "crank");
    linkage_drawing(r, scene, p, sol);
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
    // envelope: an annular sector about the joint, symmetric about u (any thickness of
    // areal density m/area).
    if d.mass > 0.0 {
        match solution.sectors[j] {
            Some((ri, ro, th)) => {
                for (k, v) in [("inner_radius_m", ri), ("outer_radius_m", ro), ("angle_rad", th)] {
                    r.design.insert(format!("{n}_counterweight_sector_{k}"), v);
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

/// One row per joint: (label, kind, the bare linkage's peak, the design's peak).
fn joint_rows<'a>(
    p: &'a LinkageProblem,
    loads: &'a JointLoads,
) -> impl Iterator<Item = (String, &'static str, ls::JointPeak, Option<ls::JointPeak>)> + 'a {
    let sc = &p.scene;
    let design = loads.design.as_ref().and_then(|d| d.as_ref().ok());
    sc.linkage
        .joints()
        .into_iter()
        .enumerate()
        .map(move |(k, j)| {
            let kind = match j.kind {
                JointKind::Revolute => "revolute",
                JointKind::Prismatic => "prismatic",
            };
            (
                ls::joint_label(&j, &sc.link_names),
                kind,
                loads.bare[k],
                design.map(|d| d[k]),
            )
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
    // The largest of several peaks is off by at most the largest of their errors.
    let worst = |v: &[ls::JointPeak]| {
        (
            v.iter().map(|j| j.peak).fold(0.0, f64::max),
            v.iter().map(|j| j.error).fold(0.0, f64::max),
        )
    };
    if let Some(b) = r.baselines.get_mut("unbalanced") {
        b.insert("peak_joint_force_n".into(), worst(&loads.bare).0);
    }
    // The figure of the result: the design's, or the bare linkage's for an analysis.
    if !r.objectives.is_empty() {
        let (w, e) = worst(design.map_or(&loads.bare, |d| d.as_slice()));
        r.objectives.insert("peak_joint_force_n".into(), w);
        r.errors.insert("peak_joint_force_n".into(), e);
    }
    let mut rows = Vec::new();
    for (label, kind, b, d) in joint_rows(p, loads) {
        let mut row = json!({
            "joint": label,
            "kind": kind,
            "unbalanced_peak_n": b.peak,
            "unbalanced_peak_error_n": b.error,
            "unbalanced_angle_rad": b.angle,
        });
        if let Some(d) = d {
            row["peak_n"] = json!(d.peak);
            row["peak_error_n"] = json!(d.error);
            row["angle_rad"] = json!(d.angle);
            if let Some(lim) = sc.objective.max_joint_force {
                if d.peak > lim * (1.0 + p.settings.rel_tol) + d.error {
                    r.warnings.push(format!(
                        "joint {label} peak load {:.6e} N exceeds its limit {lim:.6e} N",
                        d.peak
                    ));
                }
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

/// The bearing loads' table `<name>-joints.csv`.
fn joint_table(r: &mut SolveResult, p: &LinkageProblem, solved: &Solved) {
    let Ok(loads) = &solved.joints else { return };
    let mut csv = String::from(
        "joint,kind,unbalanced_peak_n,unbalanced_error_n,unbalanced_angle_rad,peak_n,error_n,angle_rad\n",
    );
    for (label, kind, b, d) in joint_rows(p, loads) {
        let cell = |v: Option<f64>, f: fn(f64) -> String| v.map_or(String::new(), f);
        csv += &format!(
            "{label},{kind},{:.12e},{:.3e},{:.12e},{},{},{}\n",
            b.peak,
            b.error,
            b.angle,
            cell(d.map(|d| d.peak), |v| format!("{v:.12e}")),
            cell(d.map(|d| d.error), |v| format!("{v:.3e}")),
            cell(d.map(|d| d.angle), |v| format!("{v:.12e}")),
        );
    }
    r.tables.push(Table {
        suffix: "joints".into(),
        caption: "Joint (bearing) loads: peak over the cycle without and with the counterweights"
            .into(),
        csv,
    });
}

/// A force–moment front as the result shows it: the points with a design, ordered by their
/// limited field, each marked dominated or not.
struct Front<'a> {
    front: &'a crate::synth::minimax::ParetoFront,
    /// The points with a design (infeasible or failed points have no peaks: left out).
    ok: Vec<&'a crate::synth::minimax::ParetoPoint>,
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
    fn of(front: &'a crate::synth::minimax::ParetoFront, goal: Goal) -> Front<'a> {
        let ok: Vec<_> = front
            .points
            .iter()
            .filter(|p| p.solution.peaks.len() == 3)
            .collect();
        let (opt, lim) = match goal {
            Goal::PeakMoment => (MOMENT, FORCE),
            _ => (FORCE, MOMENT),
        };
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
        Front {
            front,
            ok,
            order,
            dominated,
        }
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
                json!({
                    "eps": pt.eps,
                    "peak_shaking_force_n": s.peaks[FORCE].peak,
                    "peak_shaking_moment_nm": s.peaks[MOMENT].peak,
                    "error_total": s.error.total,
                    "status": cw_status(s.status).as_str(),
                })
            })
            .collect();
        let certified = self
            .front
            .points
            .iter()
            .filter(|p| p.solution.status == CwStatus::Optimal)
            .count();
        json!({"points": pts, "certified": certified, "without_design": self.front.points.len() - self.ok.len(), "dominated": self.dominated.iter().filter(|d| **d).count(), "csv": format!("{name}-pareto.csv")})
    }

    /// The front's CSV: every point with a design, dominated ones marked.
    fn csv(&self) -> String {
        let mut csv = String::from("eps,peak_shaking_force_n,peak_shaking_moment_nm,error_force_n,error_moment_nm,gap,status,dominated\n");
        for (pt, dominated) in self.ok.iter().zip(&self.dominated) {
            let s = &pt.solution;
            csv += &format!(
                "{:.12e},{:.12e},{:.12e},{:.3e},{:.3e},{:.3e},{},{dominated}\n",
                pt.eps,
                s.peaks[FORCE].peak,
                s.peaks[MOMENT].peak,
                s.peaks[FORCE].error,
                s.peaks[MOMENT].error,
                s.error.total,
                cw_status(s.status).as_str(),
            );
        }
        csv
    }

    /// (peak moment, peak force) of the front's points, by increasing limited field.
    fn line(&self) -> Vec<(f64, f64)> {
        self.order
            .iter()
            .filter(|&&i| !self.dominated[i])
            .map(|&i| {
                let p = &self.ok[i].solution.peaks;
                (p[MOMENT].peak, p[FORCE].peak)
            })
            .collect()
    }
}

/// The front's table `<name>-pareto.csv` and its plot.
fn pareto_documents(r: &mut SolveResult, front: &Front) {
    r.tables.push(Table {
        suffix: "pareto".into(),
        caption:
            "Peak shaking force against peak shaking moment: each point its own certified solve"
                .into(),
        csv: front.csv(),
    });
    let line = front.line();
    r.plots.push(Plot::new(
        "pareto",
        "Peak shaking force against peak shaking moment (ε-constraint front, each point certified)",
        move || {
            plot::panels(
                &[Panel {
                    title: "Force–moment front".into(),
                    x_label: "peak shaking moment (N·m)".into(),
                    y_label: "peak shaking force (N)".into(),
                    series: vec![
                        Series::line("front", line.clone()),
                        Series::points("points", line.clone()),
                    ],
                    equal_aspect: false,
                }],
                640,
                420,
            )
        },
    ));
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

/// The fields over the cycle with and without the counterweights (`<name>-cycle.csv`, the
/// `fields` plot) and the linkage at four crank angles: the model evaluated for drawing.
fn curves(r: &mut SolveResult, scene: &Scene, p: &LinkageProblem, solved: &Solved) {
    let x = solved.design_x().map(<[f64]>::to_vec);
    let rows = cycle_rows(&p.scene, x.as_deref(), p.settings.scan_samples.max(16));
    let mut csv = String::from("theta_deg,bare_fx_n,bare_fy_n,bare_moment_nm,bare_torque_nm,fx_n,fy_n,moment_nm,torque_nm\n");
    for row in &rows {
        csv += &row
            .iter()
            .map(|v| format!("{v:.9e}"))
            .collect::<Vec<_>>()
            .join(",");
        csv += "\n";
    }
    r.tables.push(Table {
        suffix: "cycle".into(),
        caption: "Shaking force, shaking moment and input torque over one crank turn, without and with the counterweights".into(),
        csv,
    });
    let with_cw = x.is_some();
    r.plots.push(Plot::new(
        "fields",
        "|F|, M_O and T over one crank turn: bare linkage and with the counterweights",
        move || fields_plot(&rows, with_cw),
    ));
    let (sc, name) = (p.scene.clone(), scene.name.clone());
    r.plots.push(Plot::new(
        "linkage",
        "The linkage at four crank angles (0°, 90°, 180°, 270°), with its counterweights' centroids",
        move || drawing(&name, &sc, x.as_deref()),
    ));
}

/// θ (deg) and the bare and balanced Fx, Fy, M_O, T at n + 1 angles over the turn (angles where
/// the linkage does not assemble are left out).
fn cycle_rows(sc: &LinkageScene, x: Option<&[f64]>, n: usize) -> Vec<[f64; 9]> {
    let extra = x.map(|x| ls::extras(&sc.counterweights, x));
    (0..=n)
        .filter_map(|k| {
            let th = TAU * k as f64 / n as f64;
            let pose = sc.linkage.pose(th).ok()?;
            let map = sc.linkage.balance_map(&pose, sc.moment_about);
            let b = map.base;
            let d = extra.as_ref().map_or(b, |e| map.fields(e));
            Some([
                th.to_degrees(),
                b.force.x,
                b.force.y,
                b.moment,
                b.torque,
                d.force.x,
                d.force.y,
                d.moment,
                d.torque,
            ])
        })
        .collect()
}

/// |F|, M_O and T against θ from [`cycle_rows`], bare and (with counterweights) balanced.
fn fields_plot(rows: &[[f64; 9]], with_cw: bool) -> Result<String, PlotError> {
    let col = |i: usize, j: Option<usize>| -> Vec<(f64, f64)> {
        rows.iter()
            .map(|r| (r[0], j.map_or(r[i], |j| r[i].hypot(r[j]))))
            .collect()
    };
    // The largest |value| of a curve, marked and labelled.
    let peak = |pts: &[(f64, f64)], unit: &str, what: &str| -> Option<Series> {
        let &(x, y) = pts
            .iter()
            .filter(|q| q.1.is_finite())
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
        Some(Series::peak(
            format!(
                "{what} {} {unit} at {}°",
                plot::tick(&((y.abs() * 1e4).round() / 1e4)),
                plot::tick(&((x * 10.0).round() / 10.0))
            ),
            vec![(x, y)],
        ))
    };
    let pane = |title: &str, y: &str, unit: &str, bare: Vec<(f64, f64)>, bal: Vec<(f64, f64)>| {
        let mut series = vec![];
        series.extend(peak(&bare, unit, "bare peak"));
        if with_cw {
            series.extend(peak(&bal, unit, "balanced peak"));
            series.insert(0, Series::line("balanced", bal));
        }
        series.insert(0, Series::line("bare", bare));
        Panel {
            title: title.into(),
            x_label: "crank angle θ (deg)".into(),
            y_label: format!("{y} ({unit})"),
            series,
            equal_aspect: false,
        }
    };
    plot::panels(
        &[
            pane(
                "Shaking force |F|",
                "|F|",
                "N",
                col(1, Some(2)),
                col(5, Some(6)),
            ),
            pane(
                "Shaking moment M_O",
                "M_O",
                "N·m",
                col(3, None),
                col(7, None),
            ),
            pane("Input torque T", "T", "N·m", col(4, None), col(8, None)),
        ],
        420,
        340,
    )
}

/// The links as segments (reference joint to tip) at four crank angles; the counterweights'
/// centroids as markers.
fn drawing(name: &str, sc: &LinkageScene, x: Option<&[f64]>) -> Result<String, PlotError> {
    let l: &Linkage = &sc.linkage;
    let mut series = Vec::new();
    for q in 0..4 {
        let th = TAU * q as f64 / 4.0;
        let Ok(pose) = l.pose(th) else { continue };
        let mut pts = Vec::new();
        for (i, st) in pose.links.iter().enumerate() {
            let a = st.p[0];
            let b = tip_of(l.dyads(), sc.crank_length, i)
                .map(|at| pose.point(&Point::On { link: i, at })[0])
                .unwrap_or(a);
            pts.push((a.x * 1e3, a.y * 1e3));
            pts.push((b.x * 1e3, b.y * 1e3));
            pts.push((f64::NAN, f64::NAN));
        }
        series.push(Series::line(format!("θ = {}°", 90 * q), pts));
        if let Some(x) = x {
            let cw: Vec<(f64, f64)> = ls::extras(&sc.counterweights, x)
                .iter()
                .filter(|(_, p)| p[0] > 0.0)
                .map(|(link, p)| {
                    let at = P2::new(p[1] / p[0], p[2] / p[0]);
                    let c = pose.point(&Point::On { link: *link, at })[0];
                    (c.x * 1e3, c.y * 1e3)
                })
                .collect();
            if q == 0 && !cw.is_empty() {
                series.push(Series::marker("counterweights (θ = 0°)", cw));
            }
        }
    }
    plot::panels(
        &[Panel {
            title: format!("{name}: positions"),
            x_label: "x (mm)".into(),
            y_label: "y (mm)".into(),
            series,
            equal_aspect: true,
        }],
        720,
        560,
    )
}

/// The linkage's drawing (`<name>-drawing.dxf`/`.svg`, [`linkage_sheet`]).
fn linkage_drawing(r: &mut SolveResult, scene: &Scene, p: &LinkageProblem, sol: &Solved) {
    let x = sol.design_x().map(<[f64]>::to_vec);
    let (sc, name, sectors) = (p.scene.clone(), scene.name.clone(), sol.sectors.clone());
    let caption = "linkage at θ = 0 and its counterweights";
    r.drawings.push(Sheet::new("drawing", caption, move || {
        linkage_sheet(&name, &sc, x.as_deref(), &sectors)
    }));
}

/// The links (reference joint to tip) at the design position θ = 0 with their joints, and at
/// 90°, 180°, 270° (layer `PATH`); the ground pivots marked, a slider's line as a centre line;
/// each counterweight of the design `x` as a disc at its centroid (a symbolic size), its
/// radius from the link's reference joint dimensioned, its mass and angle in a note; its
/// annular sector (`sectors`, from the solve) where there is one.
fn linkage_sheet(
    name: &str,
    sc: &LinkageScene,
    x: Option<&[f64]>,
    sectors: &[Option<(f64, f64, f64)>],
) -> Result<Drawing, DrawingError> {
    let l: &Linkage = &sc.linkage;
    let pin = 0.04 * sc.crank_length;
    let mut d = Drawing::new(format!("{name}: linkage at θ = 0 (blue: 90°, 180°, 270°)"));
    let frame = |pt: &Point| match pt {
        Point::Frame(f) => Some(*f),
        Point::On { .. } => None,
    };
    let mut ground = vec![l.pivot()];
    for dy in l.dyads() {
        match dy {
            Dyad::Rrr { p, q, .. } | Dyad::Rpr { p, q, .. } => {
                ground.extend(frame(p).into_iter().chain(frame(q)));
            }
            Dyad::Rrp { p, .. } => ground.extend(frame(p)),
        }
    }
    for g in &ground {
        d.mark(*g).circle(Layer::Centre, *g, 1.5 * pin);
    }
    let poses: Vec<_> = (0..4)
        .filter_map(|q| l.pose(TAU * q as f64 / 4.0).ok())
        .collect();
    // A slider's line, over the positions drawn.
    for (k, dy) in l.dyads().iter().enumerate() {
        if let Dyad::Rrp { origin, angle, .. } = *dy {
            let u = P2::new(angle.cos(), angle.sin());
            let t = poses.iter().map(|p| (p.dyads[k].joint[0] - origin).dot(&u));
            let (t0, t1) = t.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
                (a.min(t), b.max(t))
            });
            if t0 <= t1 {
                d.line(
                    Layer::Centre,
                    origin + (t0 - 4.0 * pin) * u,
                    origin + (t1 + 4.0 * pin) * u,
                );
            }
        }
    }
    for pose in poses.iter().rev() {
        let design = pose.theta == 0.0;
        let layer = if design { Layer::Outline } else { Layer::Path };
        for (i, st) in pose.links.iter().enumerate() {
            let a = st.p[0];
            if let Some(at) = tip_of(l.dyads(), sc.crank_length, i) {
                let b = pose.point(&Point::On { link: i, at })[0];
                d.line(layer, a, b);
                if design {
                    d.circle(layer, a, pin).circle(layer, b, pin);
                }
            } else {
                // A slider or a block: a square about its reference joint, along the link.
                let (u, v) = (st.e * (2.0 * pin), crate::geom::perp(st.e) * (2.0 * pin));
                d.polyline(
                    layer,
                    vec![a + u + v, a - u + v, a - u - v, a + u - v],
                    true,
                );
            }
        }
    }
    if let (Some(pose), Some(x)) = (poses.first().filter(|p| p.theta == 0.0), x) {
        for (j, (link, m)) in ls::extras(&sc.counterweights, x).iter().enumerate() {
            if m[0] <= 0.0 {
                continue;
            }
            let at = P2::new(m[1] / m[0], m[2] / m[0]);
            let (p0, c) = (
                pose.links[*link].p[0],
                pose.point(&Point::On { link: *link, at })[0],
            );
            let on = &sc.counterweights[j].link_name;
            // The annular sector that is this counterweight, about its joint (none: a ring).
            match sectors.get(j).copied().flatten() {
                Some((ri, ro, th)) if ro > 0.0 && th > 0.0 => {
                    let mid = (c - p0).y.atan2((c - p0).x);
                    let (a0, a1) = (mid - 0.5 * th, mid + 0.5 * th);
                    d.arc(Layer::Outline, p0, ro, a0, a1);
                    if ri > 0.0 {
                        d.arc(Layer::Outline, p0, ri, a0, a1);
                    }
                    if th < TAU - 1e-9 {
                        for a in [a0, a1] {
                            let v = P2::new(a.cos(), a.sin());
                            d.line(Layer::Outline, p0 + ri * v, p0 + ro * v);
                        }
                    }
                    d.mark(c);
                }
                _ => {
                    d.circle(Layer::Outline, c, 1.5 * pin).mark(c);
                }
            }
            d.linear(p0, c, 6.0 * pin, &format!("r ({on})"));
            d.note(format!(
                "counterweight on {on}: {:.4} kg, centroid at {:.2} mm, {:.2}° from the link's axis",
                m[0],
                at.norm() * 1e3,
                at.y.atan2(at.x).rem_euclid(TAU).to_degrees()
            ));
        }
    }
    if poses.is_empty() {
        let why = "the linkage does not assemble at θ = 0, 90°, 180°, 270°";
        return Err(DrawingError::Data(why.into()));
    }
    d.note("a link's axis: from its reference joint towards its tip; dimensions in mm");
    d.note("crosses in circles: ground pivots; annular sectors about their joints: the counterweights (the sector with their mass, centroid and inertia within the envelope; a small ring where none is)");
    Ok(d)
}
