//! The slider-crank's documents: the tables, plots and drawings of a solved scene, drawn from its
//! solution and the result's numbers, calling no solver; the driver makes them only when a
//! result's files are asked for (`SolveResult::draw`, `complete`). The numbers themselves are
//! `numbers.rs`'.

use super::file::*;
use super::solve::{Analyses, Solution};
use crate::families::family::Scene;
use crate::families::slider_crank::model::Kinematics;
use crate::families::slider_crank::model::ProcessForce;
use crate::families::slider_crank::model::SliderCrank;
use crate::families::slider_crank::synth::{self as sc, Objective, SweepPoint};
use crate::geom::P2;
use crate::report::drawing::{Drawing, DrawingError, Layer, Sheet};
use crate::report::plot::{self, Panel, PlotError, Series};
use crate::report::{Plot, SolveResult, Table};
use crate::synth::shape::Sector;
use std::collections::BTreeMap;
use std::f64::consts::TAU;

use super::numbers::joint_rows;

/// No analyses beyond the solution's own documents.
pub fn analysis_documents(
    _: &Scene,
    _: &SliderCrankProblem,
    _: &Solution,
    _: &Analyses,
    _: &mut SolveResult,
) {
}

/// The tables, plots and drawings of a solved scene, in the order the report lists them.
pub fn documents(scene: &Scene, p: &SliderCrankProblem, sol: &Solution, r: &mut SolveResult) {
    let out = &sol.out;
    if !out.pareto.is_empty() {
        pareto_documents(r, scene, sol);
    }
    balancer_table(r, sol);
    comparison_table(r);
    cycle_table(r, &p.core, out);
    joint_load_table(r, &p.core, out);
    envelope_table(r, out);
    sensitivity_table(r, sol.sensitivities.as_ref());
    if out.joint_loads.is_some() {
        let (name, out) = (scene.name.clone(), out.clone());
        r.plots.push(Plot::of_panels(
            "joint-loads",
            "Joint loads over the cycle",
            600,
            420,
            move || joint_load_plot(&name, &out),
        ));
    }
    if let Some((pts, _)) = &sol.sweep {
        speed_sweep_documents(r, scene, &p.core, pts);
    }
    let design = &sol.design;
    plate_drawing(
        r,
        scene,
        p,
        out.counterweight.plate,
        design.counterweight_angle_rad,
    );
    mechanism_drawing(r, scene, p, design);
    let motion =
        super::motion::motion(&p.core, design, out.counterweight.plate, p.rod_length_given);
    r.motion = serde_json::to_value(motion).ok();
    crate::report::drive::drive_documents(r, sol.drive.as_ref(), "crank");
    let (scene, s, out) = (scene.clone(), p.core.clone(), out.clone());
    let label = sol.claim.status.design_label();
    r.plots.push(Plot::of_panels(
        "shaking-force",
        "Shaking force (and drive torque) with and without counterweight",
        560,
        480,
        move || slider_crank_plot(&scene, &s, &out, label),
    ));
}

/// The sensitivity table as `<name>-envelope-sensitivity.csv`.
fn sensitivity_table(r: &mut SolveResult, rows: Option<&Result<Vec<sc::Sensitivity>, String>>) {
    if let Some(Ok(rows)) = rows {
        r.tables
            .push(crate::report::envelope::sensitivity_table(rows));
    }
}

/// The design at every scenario of the envelope as `<name>-envelope.csv`.
fn envelope_table(r: &mut SolveResult, out: &sc::Outcome) {
    let Some(e) = &out.envelope else { return };
    let mut csv = e.parameters.join(",");
    csv += ",peak_shaking_force_n,peak_shaking_force_error_n,peak_drive_torque_nm,peak_drive_torque_error_nm,energy_fluctuation_j,energy_fluctuation_error_j\n";
    for v in &e.vertices {
        let opt = |x: Option<f64>| x.map(|x| x.to_string()).unwrap_or_default();
        let vals: Vec<String> = v.values.iter().map(|x| x.to_string()).collect();
        csv += &format!(
            "{},{},{},{},{},{},{}\n",
            vals.join(","),
            v.peak_shaking_force_n,
            v.peak_shaking_force_error_n,
            v.peak_drive_torque_nm,
            v.peak_drive_torque_error_nm,
            opt(v.energy_fluctuation_j),
            opt(v.energy_fluctuation_error_j)
        );
    }
    r.tables.push(Table {
        suffix: "envelope".into(),
        caption: "The design over the operating envelope: the nominal scene, then every vertex"
            .into(),
        csv,
    });
}

/// The torque–force front as `<name>-pareto.csv` and its plot; with balancers each pair's
/// B_n = (B_c, B_s) of every point as `balancer_<n>_c_kgm`, `balancer_<n>_s_kgm`.
fn pareto_documents(r: &mut SolveResult, scene: &Scene, sol: &Solution) {
    let out = &sol.out;
    let energy = out.pareto.iter().any(|p| p.energy_fluctuation_j.is_some());
    let (traded, caption) = if energy {
        ("energy_fluctuation_j,gap_j", "ΔE–force Pareto front")
    } else {
        ("gap_nm", "Torque–force Pareto front")
    };
    let pairs: String = (sol.balancers.iter())
        .map(|b| format!(",balancer_{0}_c_kgm,balancer_{0}_s_kgm", b.order))
        .collect();
    let mut csv = format!("force_limit_n,peak_shaking_force_n,peak_drive_torque_nm,{traded},unbalance_x_kgm,unbalance_y_kgm{pairs},status\n");
    for p in &out.pareto {
        let traded = match p.energy_fluctuation_j {
            Some(e) => format!("{e},{}", p.gap()),
            None => format!("{}", p.gap()),
        };
        let b: String = (p.balancers_kgm.iter())
            .map(|[c, s]| format!(",{c},{s}"))
            .collect();
        csv += &format!(
            "{},{},{},{},{},{}{b},{}\n",
            p.force_limit_n,
            p.peak_shaking_force_n,
            p.peak_drive_torque_nm,
            traded,
            p.unbalance_x_kgm,
            p.unbalance_y_kgm,
            serde_json::to_value(p.status)
                .unwrap()
                .as_str()
                .unwrap_or("")
        );
    }
    r.tables.push(Table {
        suffix: "pareto".into(),
        caption: caption.into(),
        csv,
    });
    let baselines: BTreeMap<String, sc::Metrics> = sol
        .baselines()
        .map(|(k, m)| (k.into(), m.clone()))
        .collect();
    let (scene, out) = (scene.clone(), out.clone());
    r.plots
        .push(Plot::of_panels("pareto", caption, 700, 520, move || {
            pareto_plot(&scene, &out, &baselines)
        }));
}

/// The "Lanchester balancers" table (`<name>-balancers.csv`): per pair its order, unbalance
/// |B_n|, phase, the mass × radius on each shaft, its mid-line offset, the peak of its force
/// and of its couple ([`super::solve::BalancerFigures`]).
fn balancer_table(r: &mut SolveResult, sol: &Solution) {
    if sol.balancers.is_empty() {
        return;
    }
    let mut csv = String::from(
        "order,unbalance_kgm,phase_deg,shaft_unbalance_kgm,offset_m,peak_force_n,peak_couple_nm\n",
    );
    for b in &sol.balancers {
        csv += &format!(
            "{},{},{},{},{},{},{}\n",
            b.order,
            b.unbalance_kgm,
            b.phase_rad.to_degrees(),
            b.shaft_unbalance_kgm,
            b.offset_m,
            b.peak_force_n,
            b.peak_couple_nm
        );
    }
    r.tables.push(Table {
        suffix: "balancers".into(),
        caption: "Lanchester balancers (pairs of counter-rotating shafts at n·ω; the couple is offset × force about the crank axis, 0 for a pair on the line through it)".into(),
        csv,
    });
}

/// The balancer comparison as `<name>-balancer-comparison.csv`, from the result's
/// `balancer_comparison` rows (numbers.rs wrote them; nothing is computed here).
fn comparison_table(r: &mut SolveResult) {
    let Some(rows) = r
        .extra
        .get("balancer_comparison")
        .and_then(|v| v.as_array())
    else {
        return;
    };
    let mut csv = String::from("orders,status,peak_shaking_force_n,peak_shaking_force_error_n,peak_drive_torque_nm,peak_drive_torque_error_nm,counterweight_unbalance_kgm,counterweight_mass_kg,balancer_unbalance_kgm,balancer_shafts_mass_kg\n");
    let text = |v: &serde_json::Value| match v {
        serde_json::Value::Null => String::new(),
        serde_json::Value::String(s) => s.clone(),
        serde_json::Value::Array(a) => a
            .iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(" "),
        v => v.to_string(),
    };
    for row in rows {
        let cells: Vec<String> = [
            "orders",
            "status",
            "peak_shaking_force_n",
            "peak_shaking_force_error_n",
            "peak_drive_torque_nm",
            "peak_drive_torque_error_nm",
            "counterweight_unbalance_kgm",
            "counterweight_mass_kg",
            "balancer_unbalance_kgm",
            "balancer_shafts_mass_kg",
        ]
        .iter()
        .map(|k| text(&row[*k]))
        .collect();
        csv += &(cells.join(",") + "\n");
    }
    r.tables.push(Table {
        suffix: "balancer-comparison".into(),
        caption: "Balancer comparison: the scene solved with no pair (crank counterweight only), then with its first 1, 2, … balancer orders (the same objective and limits); the shafts' mass is that of their eccentric masses at the given radius".into(),
        csv,
    });
}

/// The "Joint loads" table (`<name>-joint-loads.csv`): the peak of each joint load over the
/// cycle, its crank angle, error and limit.
fn joint_load_table(r: &mut SolveResult, s: &sc::Scene, out: &sc::Outcome) {
    let Some(jl) = &out.joint_loads else { return };
    let mut csv = String::from("joint,peak_load_n,angle_deg,error_n,limit_n\n");
    for (name, p, lim) in joint_rows(s, jl) {
        csv += &format!(
            "{name},{},{},{},{}\n",
            p.peak,
            p.angle.to_degrees(),
            p.error,
            lim.map_or(String::new(), |l| l.to_string())
        );
    }
    r.tables.push(Table {
        suffix: "joint-loads".into(),
        caption: "Joint loads (Newton–Euler of the rigid links at constant speed)".into(),
        csv,
    });
}

/// The machine over one turn at 1° steps (`<name>-cycle.csv`), without counterweight (the
/// scene as read, U = 0) and with the design (its balancers too): F_x, F_y, |F|, the drive
/// torque at constant speed and the shaking moment about the crank pivot. The moment is the
/// same with and without a crank counterweight (its centrifugal force passes through O), not
/// with balancers.
fn cycle_table(r: &mut SolveResult, s: &sc::Scene, out: &sc::Outcome) {
    let d = &out.designed;
    let u = P2::from(out.design.unbalance);
    let w2 = s.omega * s.omega;
    let mut csv = String::from(
        "crank_angle_deg,bare_fx_n,bare_fy_n,bare_force_n,bare_torque_nm,bare_moment_nm,fx_n,fy_n,force_n,torque_nm,moment_nm\n",
    );
    for k in 0..=360 {
        let phi = (k as f64).to_radians();
        let (Some(st0), Some(st)) = (s.mech.state(phi), d.mech.state(phi)) else {
            continue;
        };
        let (f0, f) = (
            sc::scene_force(s, P2::zeros(), phi),
            sc::scene_force(d, u, phi),
        );
        csv += &format!(
            // Debug notation: the shortest round trip, in exponent form for tiny values.
            "{k},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?}\n",
            f0.x,
            f0.y,
            f0.norm(),
            sc::drive_torque(s, P2::zeros(), phi),
            sc::moment0(s, &st0) * w2,
            f.x,
            f.y,
            f.norm(),
            sc::drive_torque(d, u, phi),
            sc::moment0(d, &st) * w2,
        );
    }
    r.tables.push(Table {
        suffix: "cycle".into(),
        caption: "One turn at constant speed without and with the design: shaking force, drive torque, shaking moment about O".into(),
        csv,
    });
}

/// The magnitudes of the joint loads of the design against the crank angle, with the peaks
/// marked (`<name>-joint-loads.svg`).
fn joint_load_plot(name: &str, out: &sc::Outcome) -> Result<Vec<Panel>, PlotError> {
    let s = &out.designed;
    let u = P2::from(out.design.unbalance);
    let mcw = out.counterweight.mass.unwrap_or(0.0);
    let n = 721;
    let loads: Vec<(f64, crate::families::slider_crank::model::JointLoads)> = (0..n)
        .filter_map(|k| {
            let phi = k as f64 * TAU / (n - 1) as f64;
            let st = s.mech.state(phi)?;
            Some((
                phi.to_degrees(),
                s.mech.joint_loads(&st, s.omega, &s.loads, u, mcw),
            ))
        })
        .collect();
    type Pick = fn(&crate::families::slider_crank::model::JointLoads) -> f64;
    let curves: [(&str, Pick); 4] = [
        ("main bearing O", |j| j.main.norm()),
        ("crank pin A", |j| j.crank_pin.norm()),
        ("wrist pin B", |j| j.wrist_pin.norm()),
        ("guide |N|", |j| j.guide.abs()),
    ];
    let mut series: Vec<Series> = curves
        .iter()
        .map(|(label, f)| Series::line(*label, loads.iter().map(|(a, j)| (*a, f(j))).collect()))
        .collect();
    if let Some(jl) = &out.joint_loads {
        series.push(Series::marker(
            "peaks",
            [jl.main_bearing, jl.crank_pin, jl.wrist_pin, jl.guide]
                .iter()
                .map(|p| (p.angle.to_degrees(), p.peak))
                .collect(),
        ));
    }
    Ok(vec![Panel {
        title: format!("{name}: joint loads"),
        x_label: "crank angle φ (deg)".into(),
        y_label: "load (N)".into(),
        series,
        equal_aspect: false,
    }])
}

/// The speed sweep's table `<name>-speed-sweep.csv` and plot (the optimum at each speed, the
/// scene's own design and no counterweight there; its numbers are the section `speed_sweep`).
fn speed_sweep_documents(r: &mut SolveResult, scene: &Scene, s: &sc::Scene, pts: &[SweepPoint]) {
    let torque = s.objective == Objective::MinPeakTorque;
    let unit = if torque { "N·m" } else { "N" };
    let mut csv = String::from("speed_rpm,omega_rad_s,optimal_unbalance_kgm,optimal_objective,design_objective,none_objective,status\n");
    for p in pts {
        csv += &format!(
            "{},{},{},{},{},{},{}\n",
            p.speed_rpm,
            p.omega_rad_s,
            p.optimal_unbalance_kgm,
            p.optimal_objective,
            p.design_objective,
            p.none_objective,
            serde_json::to_value(p.status)
                .unwrap()
                .as_str()
                .unwrap_or("")
        );
    }
    r.tables.push(Table {
        suffix: "speed-sweep".into(),
        caption: "Optimum against speed".into(),
        csv,
    });
    let (name, y_label, pts_plot) = (
        scene.name.clone(),
        {
            // The key in words: `peak_drive_torque_nm` → "peak drive torque (N·m)".
            let key = r.objective.clone().unwrap_or_default();
            let words = key
                .strip_suffix(if torque { "_nm" } else { "_n" })
                .unwrap_or(&key);
            format!("{} ({unit})", words.replace('_', " "))
        },
        pts.to_vec(),
    );
    r.plots.push(Plot::of_panels(
        "speed-sweep",
        "Optimum against speed",
        600,
        460,
        move || {
            let pts = &pts_plot;
            let line = |f: &dyn Fn(&SweepPoint) -> f64| {
                pts.iter().map(|p| (p.speed_rpm, f(p))).collect::<Vec<_>>()
            };
            Ok(vec![
                Panel {
                    title: format!("{name}: objective against speed"),
                    x_label: "speed (rpm)".into(),
                    y_label: y_label.clone(),
                    series: vec![
                        Series::line("optimum at each speed", line(&|p| p.optimal_objective)),
                        Series::line(
                            "this design (optimised at the scene's speed)",
                            line(&|p| p.design_objective),
                        ),
                        Series::line("no counterweight", line(&|p| p.none_objective)),
                    ],
                    equal_aspect: false,
                },
                Panel {
                    title: "optimal unbalance against speed".into(),
                    x_label: "speed (rpm)".into(),
                    y_label: "|U| (kg·m)".into(),
                    series: vec![Series::line(
                        "optimal |U|",
                        line(&|p| p.optimal_unbalance_kgm),
                    )],
                    equal_aspect: false,
                },
            ])
        },
    ));
}

fn pareto_plot(
    scene: &Scene,
    out: &sc::Outcome,
    baselines: &BTreeMap<String, sc::Metrics>,
) -> Result<Vec<Panel>, PlotError> {
    // The objective traded against the force: the peak torque, or ΔE.
    let energy = out.pareto.iter().any(|p| p.energy_fluctuation_j.is_some());
    let (what, least, y_label) = if energy {
        ("ΔE", "ΔE", "energy fluctuation ΔE (J)")
    } else {
        ("torque", "peak torque", "peak drive torque (N·m)")
    };
    let of = |m: &sc::Metrics| {
        if energy {
            m.energy_fluctuation.map_or(f64::NAN, |e| e[0])
        } else {
            m.peak_torque
        }
    };
    let front: Vec<(f64, f64)> = out
        .pareto
        .iter()
        .map(|p| (p.peak_shaking_force_n, p.traded()))
        .collect();
    let ends = |series: &mut Vec<Series>| {
        if let (Some(first), Some(last)) = (out.pareto.first(), out.pareto.last()) {
            series.push(Series::marker(
                "force optimum",
                vec![(first.peak_shaking_force_n, first.traded())],
            ));
            series.push(Series::marker(
                format!("{what} optimum"),
                vec![(last.peak_shaking_force_n, last.traded())],
            ));
        }
    };
    let mut series = vec![Series::line(
        format!("Pareto front (least {least} for a force limit)"),
        front.clone(),
    )];
    series.push(Series::points("front points", front.clone()));
    ends(&mut series);
    for (name, label) in [
        ("paper_counterweight", "paper's counterweight"),
        ("reference_counterweight", "reference counterweight"),
        ("fifty_percent", "formula (6) / 50 % rule"),
        ("none", "no counterweight"),
    ] {
        if let Some(b) = baselines.get(name).filter(|b| of(b).is_finite()) {
            series.push(Series::marker(label, vec![(b.peak, of(b))]));
        }
    }
    series.push(Series::marker(
        "this design",
        vec![(out.design.peak, of(&out.design))],
    ));
    // The front itself, at its own scale (the optima can be close together).
    let mut zoom = vec![
        Series::line("Pareto front", front.clone()),
        Series::points("front points", front),
    ];
    ends(&mut zoom);
    Ok(vec![
        Panel {
            title: format!(
                "{}: {} against peak shaking force",
                scene.name,
                if energy { "ΔE" } else { "peak drive torque" }
            ),
            x_label: "peak shaking force (N)".into(),
            y_label: y_label.into(),
            series,
            equal_aspect: false,
        },
        Panel {
            title: "the Pareto front at its own scale".into(),
            x_label: "peak shaking force (N)".into(),
            y_label: y_label.into(),
            series: zoom,
            equal_aspect: false,
        },
    ])
}

/// The shaking-force locus, |F| and the drive torque over a turn: no counterweight, the
/// design (called what the status claims it is, `label`: the optimum, the given design, …)
/// and the 50 % rule.
fn slider_crank_plot(
    scene: &Scene,
    s: &sc::Scene,
    out: &sc::Outcome,
    label: &str,
) -> Result<Vec<Panel>, PlotError> {
    let n = 361;
    // The design with its balancers (if any), the others on the scene as read.
    let opt = |name: &str| name == label;
    let at = |name: &str| if opt(name) { &out.designed } else { s };
    let curves: Vec<(String, P2)> = [
        ("no counterweight".to_string(), P2::zeros()),
        (label.to_string(), P2::from(out.design.unbalance)),
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
    let mut torque = Vec::new();
    for (name, u) in &curves {
        let angles = (0..n).map(|k| k as f64 * TAU / (n - 1) as f64);
        let pts: Vec<P2> = angles
            .clone()
            .map(|phi| sc::scene_force(at(name), *u, phi))
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
        torque.push(Series::line(
            name.clone(),
            angles
                .map(|phi| (phi.to_degrees(), sc::drive_torque(at(name), *u, phi)))
                .collect(),
        ));
    }
    let f_opt = sc::scene_force(
        &out.designed,
        P2::from(out.design.unbalance),
        out.design.peak_angle,
    );
    locus.push(Series::marker(
        format!("peak of {label}"),
        vec![(f_opt.x, f_opt.y)],
    ));
    mag.push(Series::peak(
        format!(
            "peak {} N at {}°",
            plot::tick(&out.design.peak),
            plot::tick(&((out.design.peak_angle.to_degrees() * 10.0).round() / 10.0))
        ),
        vec![(out.design.peak_angle.to_degrees(), out.design.peak)],
    ));
    let ta = out.design.peak_torque_angle;
    torque.push(Series::peak(
        format!(
            "peak |T| {} N·m at {}°",
            plot::tick(&out.design.peak_torque),
            plot::tick(&((ta.to_degrees() * 10.0).round() / 10.0))
        ),
        vec![(
            ta.to_degrees(),
            sc::drive_torque(&out.designed, P2::from(out.design.unbalance), ta),
        )],
    ));
    let mut panels = vec![
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
    ];
    if s.loads.gravity.norm() > 0.0
        || s.objective == Objective::MinPeakTorque
        || !matches!(s.loads.process, ProcessForce::None)
    {
        panels.push(Panel {
            title: "drive torque against crank angle".into(),
            x_label: "crank angle φ (deg)".into(),
            y_label: "T (N·m)".into(),
            series: torque,
            equal_aspect: false,
        });
    }
    Ok(panels)
}

/// The counterweight plate's drawing (`<name>-drawing.dxf`/`.svg`), where the scene shapes
/// one: the design's plate (the result's `shape.sector`) about the crank axis O, its axis at
/// `angle` (rad) from the crank (the crank pin on +x), with rᵢ, rₒ, θ and the centroid radius
/// r_c dimensioned and the thickness in a note.
fn plate_drawing(
    r: &mut SolveResult,
    scene: &Scene,
    p: &SliderCrankProblem,
    plate: Option<Sector>,
    angle: f64,
) {
    let (Some(spec), Some(sector)) = (p.core.counterweight.shape, plate) else {
        return;
    };
    let (ri, ro, th, rc, m) = (
        sector.inner_radius_m,
        sector.outer_radius_m,
        sector.angle_rad,
        sector.centroid_radius_m,
        sector.mass_kg,
    );
    let (name, pin) = (scene.name.clone(), P2::new(p.core.mech.r, 0.0));
    r.drawings
        .push(Sheet::new("drawing", "counterweight plate", move || {
            let (o, u) = (P2::zeros(), P2::new(angle.cos(), angle.sin()));
            let (a0, a1) = (angle - 0.5 * th, angle + 0.5 * th);
            let mut d = Drawing::new(format!("{name}: counterweight plate (annular sector)"));
            d.mark(o).mark(pin).mark(rc * u);
            d.line(Layer::Centre, o, pin)
                .line(Layer::Centre, o, 1.1 * ro * u);
            d.arc(Layer::Outline, o, ro, a0, a1);
            if ri > 0.0 {
                d.arc(Layer::Outline, o, ri, a0, a1);
            }
            if th < TAU - 1e-9 {
                for a in [a0, a1] {
                    let v = P2::new(a.cos(), a.sin());
                    d.line(Layer::Outline, ri * v, ro * v);
                }
                d.angle(o, 1.03 * ro, 1.2 * ro, (a0, a1), "θ");
            }
            d.radius(o, ri, angle + 0.12 * th, "rᵢ");
            d.radius(o, ro, angle + 0.33 * th, "rₒ");
            d.linear(o, rc * u, -0.15 * ro, "r_c");
            d.label(pin - P2::new(0.0, 0.08 * ro), "crank pin");
            d.note(format!(
                "thickness t = {:.2} mm, density {} kg/m³, mass {:.3} kg; dimensions in mm",
                spec.thickness * 1e3,
                spec.density,
                m
            ));
            d.note(format!(
                "O: crank axis, crank pin on +x; the plate's axis at {:.2}° from the crank",
                angle.to_degrees()
            ));
            Ok(d)
        }));
}

/// The mechanism's drawing where no plate is drawn (`<name>-drawing.dxf`/`.svg`): crank axis
/// O, crank OA = R, rod AB = L to the slider B on its line y = e, at φ = 0 (`OUTLINE`) and
/// φ = 90° (`PATH`, with the crank circle), exact kinematics (B = A + (√(L² − (R sin φ −
/// e)²), e − R sin φ)). The counterweight C at its centroid radius r and angle β from the
/// crank (C = r(cos(φ + β), sin(φ + β))) as a disc of symbolic size, R, L and r dimensioned,
/// β as an angle; where the scene does not size m and r, the direction of U alone with a note
/// |U| = m·r.
fn mechanism_drawing(r: &mut SolveResult, scene: &Scene, p: &SliderCrankProblem, d: &sc::Design) {
    if r.extra.get("shape").and_then(|v| v.get("sector")).is_some() {
        return;
    }
    let mech = SliderCrank {
        kinematics: Kinematics::Exact,
        ..p.core.mech
    };
    let rod_given = p.rod_length_given;
    let (name, beta, u) = (
        scene.name.clone(),
        d.counterweight_angle_rad,
        d.counterweight_unbalance_kgm,
    );
    let sized = d.counterweight_mass_kg.zip(d.counterweight_radius_m);
    let caption = "mechanism at φ = 0 and 90° with its counterweight";
    r.drawings.push(Sheet::new("drawing", caption, move || {
        let (big_r, big_l, e) = (mech.r, mech.l, mech.e);
        let pin = 0.06 * big_r;
        let o = P2::zeros();
        let dir = |a: f64| P2::new(a.cos(), a.sin());
        let pose = |phi: f64| -> Result<(P2, P2), DrawingError> {
            let st = mech.state(phi).ok_or_else(|| {
                DrawingError::Data(format!(
                    "the rod does not reach the slider line at φ = {:.0}°",
                    phi.to_degrees()
                ))
            })?;
            Ok((st.a[0], P2::new(st.x[0], e)))
        };
        let mut dr = Drawing::new(format!(
            "{name}: slider-crank at φ = 0 (blue: φ = 90°) and its counterweight"
        ));
        // The slider's line over the stroke, the crank circle.
        let (x_min, x_max) = ((big_l - big_r).max(0.0), big_l + big_r);
        let (x_min, x_max) = (
            (x_min * x_min - e * e).max(0.0).sqrt(),
            (x_max * x_max - e * e).max(0.0).sqrt(),
        );
        dr.line(
            Layer::Centre,
            P2::new(x_min - 4.0 * pin, e),
            P2::new(x_max + 4.0 * pin, e),
        );
        dr.circle(Layer::Path, o, big_r).mark(o);
        let block = |b: P2| {
            let (w, h) = (3.0 * pin, 2.0 * pin);
            vec![
                b + P2::new(-w, -h),
                b + P2::new(w, -h),
                b + P2::new(w, h),
                b + P2::new(-w, h),
            ]
        };
        for (phi, layer) in [(0.5 * std::f64::consts::PI, Layer::Path), (0.0, Layer::Outline)] {
            let (a, b) = pose(phi)?;
            dr.line(layer, o, a).line(layer, a, b);
            dr.polyline(layer, block(b), true);
            dr.circle(layer, a, pin).circle(layer, b, pin);
            if let Some((m, rc)) = sized.filter(|(m, _)| *m > 0.0) {
                let c = rc * dir(phi + beta);
                dr.line(layer, o, c).circle(layer, c, 4.0 * pin);
                if phi == 0.0 {
                    dr.mark(c);
                    dr.linear(o, c, 8.0 * pin, "r");
                    dr.note(format!(
                        "counterweight: m = {m:.4} kg at r = {:.2} mm, β = {:.2}° from the crank (|U| = m·r = {u:.6} kg·m); disc of symbolic size",
                        rc * 1e3,
                        beta.to_degrees()
                    ));
                }
            }
            if phi == 0.0 {
                dr.mark(a).mark(b);
                dr.linear(o, a, -8.0 * pin, "R");
                if rod_given {
                    dr.linear(a, b, -8.0 * pin, "L");
                }
            }
        }
        match sized {
            Some((m, _)) if m > 0.0 => {}
            _ if u > 0.0 => {
                dr.line(Layer::Centre, o, 1.3 * big_r * dir(beta));
                dr.label(1.45 * big_r * dir(beta), "U");
                dr.note(format!(
                    "counterweight unbalance |U| = {u:.6} kg·m at β = {:.2}° from the crank: size by m·r = |U|",
                    beta.to_degrees()
                ));
            }
            _ => {
                dr.note("no counterweight (U = 0)");
            }
        }
        if u > 0.0 && beta.rem_euclid(TAU) > 1e-6 && beta.rem_euclid(TAU) < TAU - 1e-6 {
            dr.angle(o, 1.05 * big_r, 1.2 * big_r, (0.0, beta), "β");
        }
        if e != 0.0 {
            dr.note(format!("slider offset e = {:.2} mm", e * 1e3));
        }
        if !rod_given {
            dr.note("rod length not given (obliquity neglected): the rod is drawn at 4R, not to scale");
        }
        dr.note("O: crank axis; the slider runs on +x; φ = 0 with the crank pin towards the slider (inner dead centre), φ counter-clockwise; dimensions in mm");
        Ok(dr)
    }));
}
