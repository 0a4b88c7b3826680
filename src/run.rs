//! From a resolved scene to its result: dispatch to the family's solver, then shape the
//! outcome into the common [`SolveResult`] (keys, errors, baselines, paper checks, plots).

use crate::geom::P2;
use crate::io::plot::{self, Panel, Series};
use crate::io::problem::{Scene, SceneKind};
use crate::io::result::{Plot, SolveResult, Status, Timing};
use crate::mech::slider_crank::Kinematics;
use crate::synth::counterweight::Status as CwStatus;
use crate::synth::slider_crank::{self as sc, shaking_force};
use serde_json::json;
use std::collections::BTreeMap;
use std::time::Instant;

/// Solves a scene. Never panics on a valid scene; a solver failure becomes
/// `status = failed` with the reason in `warnings`.
pub fn solve_scene(scene: &Scene) -> SolveResult {
    let t0 = Instant::now();
    let mut r = match &scene.kind {
        SceneKind::SliderCrank(s) => slider_crank_result(scene, s),
    };
    r.timing.total_s = t0.elapsed().as_secs_f64();
    r.compare_with_paper(&scene.paper);
    r
}

fn empty(scene: &Scene) -> SolveResult {
    SolveResult {
        name: scene.name.clone(),
        family: scene.family.as_str().into(),
        status: Status::Failed,
        source: scene.source.display().to_string(),
        model: BTreeMap::new(),
        design: BTreeMap::new(),
        objectives: BTreeMap::new(),
        errors: BTreeMap::new(),
        derived: BTreeMap::new(),
        baselines: BTreeMap::new(),
        paper: Vec::new(),
        warnings: Vec::new(),
        method: String::new(),
        timing: Timing::default(),
        extra: serde_json::Map::new(),
        plots: Vec::new(),
    }
}

fn slider_crank_result(scene: &Scene, s: &sc::Scene) -> SolveResult {
    let mut r = empty(scene);
    let m = &s.mech;
    r.model = BTreeMap::from([
        (
            "kinematics".into(),
            json!(match m.kinematics {
                Kinematics::Exact => "exact",
                Kinematics::TwoHarmonic => "two-harmonic",
            }),
        ),
        (
            "rod_centroid_from_crank_pin_m".into(),
            json!(m.rod.centroid),
        ),
        ("rod_inertia_kgm2".into(), json!(m.rod.inertia)),
        ("offset_m".into(), json!(m.e)),
        ("gravity".into(), json!("not modelled")),
    ]);
    let t0 = Instant::now();
    let out = match sc::solve(s) {
        Ok(o) => o,
        Err(e) => {
            r.warnings.push(e.to_string());
            return r;
        }
    };
    r.timing.solve_s = t0.elapsed().as_secs_f64();
    let free =
        s.counterweight.angle.fixed().is_none() || s.counterweight.unbalance.fixed().is_none();
    r.status = match out.status {
        CwStatus::Optimal if !free => Status::Analysed,
        CwStatus::Optimal => Status::Optimal,
        CwStatus::Inaccurate => Status::Inaccurate,
        CwStatus::Infeasible => Status::Infeasible,
        CwStatus::Failed => Status::Failed,
    };
    r.method = out.method.clone();
    r.warnings.extend(out.warnings.iter().cloned());
    let d = &out.design;
    let u = P2::new(d.unbalance[0], d.unbalance[1]);
    r.design
        .insert("counterweight_unbalance_kgm".into(), u.norm());
    r.design.insert(
        "counterweight_angle_rad".into(),
        if u.norm() > 0.0 {
            u.y.atan2(u.x).rem_euclid(std::f64::consts::TAU)
        } else {
            0.0
        },
    );
    r.design.insert("counterweight_unbalance_x_kgm".into(), u.x);
    r.design.insert("counterweight_unbalance_y_kgm".into(), u.y);
    if let Some(mass) = out.mass {
        r.design.insert("counterweight_mass_kg".into(), mass);
    }
    if let Some(rad) = out.radius {
        r.design.insert("counterweight_radius_m".into(), rad);
    }
    r.objectives.insert("peak_shaking_force_n".into(), d.peak);
    r.objectives.insert("rms_shaking_force_n".into(), d.rms);
    r.objectives
        .insert("peak_drive_torque_nm".into(), out.peak_drive_torque);
    r.objectives
        .insert("peak_shaking_moment_nm".into(), out.peak_shaking_moment);
    r.errors
        .insert("peak_shaking_force_n".into(), out.gap + d.peak_error);
    r.errors.insert("rms_shaking_force_n".into(), d.rms_error);
    // Torque and moment are refined like the force; their scan error bound is of the same
    // (round-off) order and reported as the force's relative refinement error.
    let rel = d.peak_error / d.peak.max(1e-300);
    r.errors
        .insert("peak_drive_torque_nm".into(), rel * out.peak_drive_torque);
    r.errors.insert(
        "peak_shaking_moment_nm".into(),
        rel * out.peak_shaking_moment,
    );
    let (mt, mc) = (m.m_rot(), m.m_rec());
    r.derived = BTreeMap::from([
        ("lambda".into(), m.lambda()),
        ("omega_rad_s".into(), s.omega),
        ("rotating_mass_kg".into(), mt),
        ("reciprocating_mass_kg".into(), mc),
        (
            "reciprocating_fraction_balanced".into(),
            if mc > 0.0 {
                (-u.x / m.r - mt) / mc
            } else {
                0.0
            },
        ),
        ("peak_angle_rad".into(), d.peak_angle),
        ("peak_to_peak_x_n".into(), d.ptp_x),
        ("peak_to_peak_y_n".into(), d.ptp_y),
        ("optimality_gap_n".into(), out.gap),
    ]);
    if let Some(ex) = out.exact_peak {
        r.derived
            .insert("peak_shaking_force_exact_kinematics_n".into(), ex);
        r.errors
            .insert("model_two_harmonic_n".into(), (ex - d.peak).abs());
    }
    for (name, b) in &out.baselines {
        let mut map = b.to_map();
        map.insert(
            "improvement_pct".into(),
            100.0 * (b.peak - d.peak) / b.peak.max(1e-300),
        );
        r.baselines.insert(name.clone(), map);
    }
    match slider_crank_plot(scene, s, &out) {
        Ok(p) => r.plots.push(p),
        Err(e) => r.warnings.push(format!("plot failed: {e}")),
    }
    r
}

fn slider_crank_plot(scene: &Scene, s: &sc::Scene, out: &sc::Outcome) -> Result<Plot, String> {
    let n = 361;
    let curves: Vec<(String, P2)> = [
        ("no counterweight".to_string(), P2::zeros()),
        ("optimum".to_string(), P2::from(out.design.unbalance)),
    ]
    .into_iter()
    .chain(
        out.baselines
            .get("fifty_percent")
            .map(|b| ("50 % rule".to_string(), P2::from(b.unbalance))),
    )
    .collect();
    let mut locus = Vec::new();
    let mut mag = Vec::new();
    for (name, u) in &curves {
        let pts: Vec<P2> = (0..n)
            .map(|k| {
                let phi = k as f64 * std::f64::consts::TAU / (n - 1) as f64;
                shaking_force(&s.mech, s.omega, *u, phi).unwrap_or(P2::new(f64::NAN, f64::NAN))
            })
            .collect();
        locus.push(Series::line(
            name.clone(),
            pts.iter().map(|p| (p.x, p.y)).collect(),
        ));
        mag.push(Series::line(
            name.clone(),
            pts.iter()
                .enumerate()
                .map(|(k, p)| (k as f64, p.norm()))
                .collect(),
        ));
    }
    let f_opt = shaking_force(
        &s.mech,
        s.omega,
        P2::from(out.design.unbalance),
        out.design.peak_angle,
    )
    .unwrap_or(P2::zeros());
    locus.push(Series::marker("peak of optimum", vec![(f_opt.x, f_opt.y)]));
    mag.push(Series::marker(
        "peak of optimum",
        vec![(out.design.peak_angle.to_degrees(), out.design.peak)],
    ));
    let svg = plot::panels(
        &[
            Panel {
                title: format!("{}: shaking force locus", scene.name),
                x_label: "Fx (N)".into(),
                y_label: "Fy (N)".into(),
                series: locus,
                equal_aspect: true,
            },
            Panel {
                title: "|F| against crank angle".into(),
                x_label: "crank angle φ (deg)".into(),
                y_label: "|F| (N)".into(),
                series: mag,
                equal_aspect: false,
            },
        ],
        560,
        480,
    )?;
    Ok(Plot {
        suffix: "shaking-force".into(),
        caption: "Shaking force with and without counterweight".into(),
        svg,
    })
}
