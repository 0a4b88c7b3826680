//! The slider-crank's numbers: the solution's figures into the result's maps — `model`, design,
//! objectives with their errors, derived figures, baselines, paper checks, sections and the
//! warnings of the result's own checks (keys in `docs/results.md`). Arithmetic on the solution
//! (sums, ratios, a limit compared), never a solve or a search: the driver runs it at solve
//! time for every result, `--summary-only` included, and `report.rs` draws from the same
//! solution.

use super::file::*;
use super::solve::Solution;
use crate::families::family::Scene;
use crate::families::slider_crank::model::Kinematics;
use crate::families::slider_crank::model::ProcessForce;
use crate::families::slider_crank::synth::{self as sc, Objective};
use crate::geom::P2;
use crate::report::{number_map, SolveResult};
use serde_json::json;
use std::collections::BTreeMap;

/// The result's `model` section: the kinematics, the rod, the offset, gravity and the process
/// force the solve uses, and where each drawn mass item's mass came from.
pub fn model(p: &SliderCrankProblem, _: Option<&Solution>) -> BTreeMap<String, serde_json::Value> {
    let s = &p.core;
    let m = &s.mech;
    let g = s.loads.gravity;
    let rod = if p.rod_length_given {
        vec![
            (
                "rod_centroid_from_crank_pin_m".into(),
                json!(m.rod.centroid),
            ),
            ("rod_inertia_kgm2".into(), json!(m.rod.inertia)),
        ]
    } else {
        vec![(
            "rod_length".into(),
            json!("not given: obliquity neglected, no figure depends on it"),
        )]
    };
    let mut model = BTreeMap::from([
        (
            "kinematics".into(),
            json!(match m.kinematics {
                Kinematics::Exact => "exact",
                Kinematics::TwoHarmonic => "two-harmonic",
                Kinematics::Primary => "primary (obliquity neglected)",
            }),
        ),
        ("offset_m".into(), json!(m.e)),
        (
            "gravity".into(),
            if g.norm() > 0.0 {
                json!({"acceleration_m_s2": g.norm(), "x_m_s2": g.x, "y_m_s2": g.y})
            } else {
                json!("not modelled")
            },
        ),
        (
            "process_force".into(),
            json!(match &s.loads.process {
                ProcessForce::None => "none".to_string(),
                ProcessForce::Constant(f) => format!("constant {f} N"),
                ProcessForce::Table { angles, .. } => format!("table of {} points", angles.len()),
            }),
        ),
    ]);
    model.extend(rod);
    // Only beside a drawn mass item: a file of typed masses keeps its `model` as it was.
    if !p.drawn_masses.is_empty() {
        model.insert("mass_items_from_drawings".into(), json!(p.drawn_masses));
    }
    model
}

/// The result's numbers from the solution: status, design, objectives with their errors,
/// derived figures, baselines, the sections and the warnings (what `--json` prints).
pub fn numbers(_: &Scene, p: &SliderCrankProblem, sol: &Solution, r: &mut SolveResult) {
    let (s, out) = (&p.core, &sol.out);
    r.objective = Some(if sol.flywheel.is_some() {
        FLYWHEEL_KEY.into()
    } else if s.envelope.is_empty() {
        sc::Objectives::key(s.objective).into()
    } else {
        sc::Objectives::worst_case_key(s.objective).into()
    });
    let mut derived = derived(p, out);
    paper_design_checks(r, &mut derived, p, sol);
    baselines(r, s, sol);
    pareto_numbers(r, &mut derived, out);
    shape_numbers(r, s, out);
    balancer_numbers(r, sol);
    comparison_numbers(r, sol);
    joint_load_numbers(r, s, out);
    r.set_figures(&sol.design, &objectives(out), &errors(s, out), &derived);
    flywheel_numbers(r, sol);
    crate::report::drive::drive_numbers(r, sol.drive.as_ref(), Some(sol.out.design.peak));
    envelope_numbers(r, out, sol.sensitivities.as_ref());
    if let Some(j) = &sol.real_joint_loads {
        r.derived.extend(crate::report::number_map(j));
    }
    if !sol.at_angles.is_empty() {
        r.extra.insert(
            "at_angles".into(),
            serde_json::to_value(&sol.at_angles).expect("plain data"),
        );
    }
    if let Some((pts, warnings)) = &sol.sweep {
        r.warnings.extend(warnings.iter().cloned());
        r.extra.insert(
            "speed_sweep".into(),
            serde_json::to_value(pts).expect("plain data"),
        );
    }
}

/// The key objective of `minimize = "flywheel-inertia"` (in `objectives` and `errors`).
pub const FLYWHEEL_KEY: &str = "flywheel_inertia_kgm2";

/// With `minimize = "flywheel-inertia"`: the design's least flywheel as the key objective,
/// its error the drive's (the baselines' flywheels are written with the baselines).
fn flywheel_numbers(r: &mut SolveResult, sol: &Solution) {
    let Some((found, _)) = &sol.flywheel else {
        return;
    };
    let error = sol
        .drive
        .as_ref()
        .and_then(|d| d.as_ref().ok())
        .and_then(|d| d.flywheel.as_ref())
        .map_or(f64::NAN, |f| f.inertia_error);
    r.objectives.insert(FLYWHEEL_KEY.into(), found.inertia);
    r.errors.insert(FLYWHEEL_KEY.into(), error);
}

/// The design's objective values.
fn objectives(out: &sc::Outcome) -> sc::Objectives {
    let d = &out.design;
    sc::Objectives {
        peak_shaking_force_n: d.peak,
        rms_shaking_force_n: d.rms,
        peak_drive_torque_nm: d.peak_torque,
        peak_shaking_moment_nm: out.peak_shaking_moment,
        energy_fluctuation_j: d.energy_fluctuation.map(|e| e[0]),
        worst_case_peak_shaking_force_n: out
            .envelope
            .as_ref()
            .map(|e| e.worst_peak_shaking_force.value),
        worst_case_peak_drive_torque_nm: out
            .envelope
            .as_ref()
            .map(|e| e.worst_peak_drive_torque.value),
        worst_case_energy_fluctuation_j: out
            .envelope
            .as_ref()
            .and_then(|e| e.worst_energy_fluctuation.map(|w| w.value)),
    }
}

/// The objectives' errors: each figure's evaluation error, plus the optimality gap on the
/// objective the scene optimised (a degenerate torque or moment objective was solved as the
/// minimax force: its gap is in N).
fn errors(s: &sc::Scene, out: &sc::Outcome) -> sc::Errors {
    let d = &out.design;
    let torque_objective = s.objective == Objective::MinPeakTorque && out.degenerate.is_none();
    let moment_objective = s.objective == Objective::MinPeakMoment && out.degenerate.is_none();
    let energy_objective =
        s.objective == Objective::MinEnergyFluctuation && out.degenerate.is_none();
    let env = out.envelope.as_ref();
    // Over an envelope the gap is that of the worst case, not of the nominal figures.
    let gap_w = |on: bool| if on { out.gap.max(0.0) } else { 0.0 };
    let (gap_f, gap_t, gap_m, gap_e) = if env.is_some() {
        (0.0, 0.0, 0.0, 0.0)
    } else if torque_objective {
        (0.0, out.gap, 0.0, 0.0)
    } else if moment_objective {
        (0.0, 0.0, out.gap, 0.0)
    } else if energy_objective {
        (0.0, 0.0, 0.0, out.gap)
    } else {
        (out.gap, 0.0, 0.0, 0.0)
    };
    sc::Errors {
        objectives: sc::Objectives {
            peak_shaking_force_n: gap_f + d.peak_error,
            rms_shaking_force_n: d.rms_error,
            peak_drive_torque_nm: gap_t + d.peak_torque_error,
            peak_shaking_moment_nm: gap_m + out.peak_shaking_moment_error,
            energy_fluctuation_j: d.energy_fluctuation.map(|e| gap_e + e[1]),
            worst_case_peak_shaking_force_n: env.map(|e| {
                e.worst_peak_shaking_force.error
                    + gap_w(!torque_objective && !energy_objective && !moment_objective)
            }),
            worst_case_peak_drive_torque_nm: env
                .map(|e| e.worst_peak_drive_torque.error + gap_w(torque_objective)),
            worst_case_energy_fluctuation_j: env.and_then(|e| {
                e.worst_energy_fluctuation
                    .map(|w| w.error + gap_w(energy_objective))
            }),
        },
        model_two_harmonic_n: out.exact_peak.map(|ex| (ex - d.peak).abs()),
        joint_loads: sc::JointLoadFigures::of(out.joint_loads.as_ref(), true),
    }
}

/// The derived figures (the paper's and the front's are filled in later).
fn derived(p: &SliderCrankProblem, out: &sc::Outcome) -> sc::Derived {
    let s = &p.core;
    let (m, d) = (&s.mech, &out.design);
    let u = P2::from(d.unbalance);
    let (mt, mc) = (m.m_rot(), m.m_rec());
    sc::Derived {
        lambda: p.rod_length_given.then(|| m.lambda()),
        omega_rad_s: s.omega,
        rotating_mass_kg: mt,
        reciprocating_mass_kg: mc,
        reciprocating_fraction_balanced: if mc > 0.0 {
            (-u.x / m.r - mt) / mc
        } else {
            0.0
        },
        peak_angle_rad: d.peak_angle,
        peak_torque_angle_rad: d.peak_torque_angle,
        peak_to_peak_x_n: d.ptp_x,
        peak_to_peak_y_n: d.ptp_y,
        optimality_gap: out.gap,
        gravity_ratio: 9.80665 / (m.r * s.omega * s.omega),
        scan_samples: s.resolved_settings().scan_samples,
        static_weight_n: (out.static_weight > 0.0).then_some(out.static_weight),
        peak_shaking_force_exact_kinematics_n: out.exact_peak,
        formula6_counterweight_mass_kg: None,
        formula6_counterweight_mass_printed_inputs_kg: None,
        paper_counterweight_torque_reduction_pct: None,
        pareto_force_span_n: None,
        pareto_torque_span_nm: None,
        pareto_energy_span_j: None,
        plate_max_unbalance_kgm: s.counterweight.shape.as_ref().map(|sh| sh.max_unbalance()),
        joint_loads: sc::JointLoadFigures::of(out.joint_loads.as_ref(), false),
        joint_load_angles: sc::JointLoadAngles::of(out.joint_loads.as_ref()),
    }
}

/// Every baseline with its improvement over it, in the scene's objective (peak torque or peak
/// force).
fn baselines(r: &mut SolveResult, s: &sc::Scene, sol: &Solution) {
    let d = &sol.out.design;
    let torque_objective = s.objective == Objective::MinPeakTorque;
    let energy = |m: &sc::Metrics| m.energy_fluctuation.map(|e| e[0]);
    // Over an envelope each baseline is judged on its worst case, as the design is.
    let worst = sol
        .out
        .envelope
        .as_ref()
        .map(|e| e.worst_for(s.objective).map_or(f64::NAN, |w| w.value));
    for (name, b) in sol.baselines() {
        // With the flywheel objective: its least flywheel (none where its drive failed).
        let flywheel = sol.flywheel.as_ref().map(|(found, bases)| {
            let own = bases.iter().find(|(n, _)| n == name).map(|(_, i)| *i);
            (own, found.inertia)
        });
        let (base, ours) = match (flywheel, energy(b), energy(d), b.worst_case.zip(worst)) {
            (Some((own, ours)), ..) => (own.unwrap_or(f64::NAN), ours),
            (None, _, _, Some(pair)) => pair,
            (None, Some(base), Some(ours), None)
                if s.objective == Objective::MinEnergyFluctuation =>
            {
                (base, ours)
            }
            _ if torque_objective => (b.peak_torque, d.peak_torque),
            _ => (b.peak, d.peak),
        };
        let mut figures = sc::Baseline {
            improvement_pct: Some(100.0 * (base - ours) / base.max(1e-300)).filter(|v| !v.is_nan()),
            ..b.baseline()
        };
        if let Some(w) = b.worst_case {
            figures
                .worst_case
                .insert(sc::Objectives::worst_case_key(s.objective).into(), w);
        }
        let mut map = number_map(&figures);
        if let Some((Some(own), _)) = flywheel {
            map.insert(FLYWHEEL_KEY.into(), own);
        }
        r.baselines.insert(name.into(), map);
    }
}

/// The torque–force front (`pareto`), its spans, and a warning where it is too narrow to
/// choose along.
fn pareto_numbers(r: &mut SolveResult, derived: &mut sc::Derived, out: &sc::Outcome) {
    if out.pareto.is_empty() {
        return;
    }
    r.extra.insert(
        "pareto".into(),
        serde_json::to_value(&out.pareto).expect("plain data"),
    );
    if let (Some(a), Some(b)) = (out.pareto.first(), out.pareto.last()) {
        let (df, dt) = (
            b.peak_shaking_force_n - a.peak_shaking_force_n,
            a.traded() - b.traded(),
        );
        derived.pareto_force_span_n = Some(df);
        let (what, unit) = if a.energy_fluctuation_j.is_some() {
            derived.pareto_energy_span_j = Some(dt);
            ("ΔE", "J")
        } else {
            derived.pareto_torque_span_nm = Some(dt);
            ("torque", "N·m")
        };
        if df < 0.01 * a.peak_shaking_force_n && dt < 0.01 * b.traded() {
            r.warnings.push(format!(
                "the force optimum and the {what} optimum nearly coincide (the front spans {df:.3} N and {dt:.4} {unit}): one counterweight serves both"
            ));
        }
    }
}

/// The counterweight plate (`shape`), where the scene shapes one.
fn shape_numbers(r: &mut SolveResult, s: &sc::Scene, out: &sc::Outcome) {
    if s.counterweight.shape.is_none() {
        return;
    }
    let cw = &out.counterweight;
    let note = cw.plate_note.clone().unwrap_or_default();
    match &cw.plate {
        Some(sector) => {
            r.extra
                .insert("shape".into(), json!({"sector": sector, "method": note}));
        }
        None => {
            r.warnings.push(format!("counterweight plate: {note}"));
            r.extra.insert(
                "shape".into(),
                json!({"status": "infeasible", "reason": note}),
            );
        }
    }
}

/// The operating envelope (`envelope`): the vertices, the worst cases and the quasi-Monte
/// Carlo check; a warning where a sample beats the vertices' worst case.
fn envelope_numbers(
    r: &mut SolveResult,
    out: &sc::Outcome,
    sensitivities: Option<&Result<Vec<sc::Sensitivity>, String>>,
) {
    let Some(e) = &out.envelope else { return };
    let mut json = serde_json::to_value(e).expect("plain data");
    match sensitivities {
        Some(Ok(rows)) => {
            json["sensitivities"] = serde_json::to_value(rows).expect("plain data");
        }
        Some(Err(why)) => r.warnings.push(format!(
            "the envelope's sensitivities could not be computed: {why}"
        )),
        None => {}
    }
    r.extra.insert("envelope".into(), json);
    if let Some(mc) = e.monte_carlo.as_ref().filter(|m| m.beyond_worst_case > 0) {
        r.warnings.push(format!(
            "{} of {} quasi-Monte Carlo samples of the envelope exceed the vertices' worst case beyond its error{}",
            mc.beyond_worst_case,
            mc.samples,
            if e.certified {
                " although it is proven there: please report this scene"
            } else {
                ": the length tolerances' worst case lies inside their band"
            }
        ));
    }
}

/// One row of `balancer_comparison`: a compared scene's design and figures, each error the
/// result's own for that scene ([`errors`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ComparisonRow {
    /// The balancer orders of the scene (empty: the crank counterweight alone).
    pub orders: Vec<u32>,
    /// Its status.
    pub status: crate::report::Status,
    /// Peak shaking force (N).
    pub peak_shaking_force_n: f64,
    /// Its error bound (N).
    pub peak_shaking_force_error_n: f64,
    /// Peak drive torque (N·m).
    pub peak_drive_torque_nm: f64,
    /// Its error bound (N·m).
    pub peak_drive_torque_error_nm: f64,
    /// |U| of the crank counterweight (kg·m).
    pub counterweight_unbalance_kgm: f64,
    /// The crank counterweight's mass (kg), where the scene sizes it (a plate, or a mass and
    /// radius).
    pub counterweight_mass_kg: Option<f64>,
    /// |B_n| of each pair (kg·m), in the order of `orders`.
    pub balancer_unbalance_kgm: Vec<f64>,
    /// The eccentric masses of all the balancer shafts together, Σ|B_n|/r_n (kg), where
    /// every pair has its `radius` (0 without pairs).
    pub balancer_shafts_mass_kg: Option<f64>,
}

/// The balancer comparison (`balancer_comparison`): one row per compared scene that solved,
/// a warning for one that did not.
fn comparison_numbers(r: &mut SolveResult, sol: &Solution) {
    if sol.comparison.is_empty() {
        return;
    }
    let mut rows = Vec::new();
    for c in &sol.comparison {
        let orders: Vec<u32> = c.scene.balancers.iter().map(|b| b.pair.order).collect();
        match &c.out {
            Ok(out) => rows.push(comparison_row(&c.scene, out, orders)),
            Err(e) => r
                .warnings
                .push(format!("balancer comparison with orders {orders:?}: {e}")),
        }
    }
    r.extra.insert(
        "balancer_comparison".into(),
        serde_json::to_value(&rows).expect("plain data"),
    );
}

/// The [`ComparisonRow`] of one compared scene's solve.
fn comparison_row(s: &sc::Scene, out: &sc::Outcome, orders: Vec<u32>) -> ComparisonRow {
    let (o, e) = (objectives(out), errors(s, out).objectives);
    let d = &out.designed;
    ComparisonRow {
        orders,
        status: crate::families::family::cw_status(out.status),
        peak_shaking_force_n: o.peak_shaking_force_n,
        peak_shaking_force_error_n: e.peak_shaking_force_n,
        peak_drive_torque_nm: o.peak_drive_torque_nm,
        peak_drive_torque_error_nm: e.peak_drive_torque_nm,
        counterweight_unbalance_kgm: P2::from(out.design.unbalance).norm(),
        counterweight_mass_kg: out.counterweight.mass,
        balancer_unbalance_kgm: d
            .balancers
            .iter()
            .map(|b| b.unbalance[0].hypot(b.unbalance[1]))
            .collect(),
        balancer_shafts_mass_kg: super::solve::balancers_mass(&d.balancers),
    }
}

/// The Lanchester balancers' section (`lanchester_balancers`).
fn balancer_numbers(r: &mut SolveResult, sol: &Solution) {
    if sol.balancers.is_empty() {
        return;
    }
    r.extra.insert(
        "lanchester_balancers".into(),
        serde_json::to_value(&sol.balancers).expect("plain data"),
    );
}

/// The peak of each joint load over the cycle, its crank angle, error and limit: (joint,
/// peak, limit) in the order the result lists them.
pub(super) fn joint_rows<'a>(
    s: &sc::Scene,
    jl: &'a sc::JointLoadPeaks,
) -> [(&'static str, &'a sc::LoadPeak, Option<f64>); 4] {
    let ll = &s.load_limits;
    [
        ("main bearing O", &jl.main_bearing, ll.main_bearing),
        ("crank pin A", &jl.crank_pin, ll.crank_pin),
        ("wrist pin B", &jl.wrist_pin, ll.wrist_pin),
        ("guide (normal force)", &jl.guide, ll.guide),
    ]
}

/// The joint loads' section (`joint_loads`).
fn joint_load_numbers(r: &mut SolveResult, s: &sc::Scene, out: &sc::Outcome) {
    let Some(jl) = &out.joint_loads else { return };
    let rows: Vec<serde_json::Value> = joint_rows(s, jl)
        .iter()
        .map(|(name, p, lim)| {
            json!({
                "joint": name,
                "peak_load_n": p.peak,
                "angle_rad": p.angle,
                "error_n": p.error,
                "limit_n": lim,
            })
        })
        .collect();
    r.extra.insert("joint_loads".into(), json!(rows));
}

/// Formula (6) at the lever radius, and the paper's classical design against its own inputs:
/// the printed masses against the itemised sums, the printed counterweight against formula
/// (6) on the printed inputs, and the paper's counterweight as a baseline
/// (`paper_counterweight`, evaluated in the solve).
fn paper_design_checks(
    r: &mut SolveResult,
    derived: &mut sc::Derived,
    p: &SliderCrankProblem,
    sol: &Solution,
) {
    if let Some(Err(e)) = &sol.reference_counterweight {
        r.warnings.push(format!(
            "the reference counterweight could not be evaluated: {e}"
        ));
    }
    // Formula (6) is the felling-head paper's: only beside its [design.paper].
    let Some(rad) = sol.lever.filter(|_| p.paper.is_some()) else {
        return;
    };
    let m = &p.core.mech;
    let (mt, mc) = (m.m_rot(), m.m_rec());
    // The classical formula (6) at the lever radius is the 50 % rule: m = (m_r + ½m_s)R/r_pr.
    derived.formula6_counterweight_mass_kg = Some((mt + 0.5 * mc) * m.r / rad);
    let Some(pd) = &p.paper else { return };
    let pct = |a: f64, b: f64| 100.0 * (a - b) / b;
    if let Some(pr) = pd.rotating_mass {
        if (pr - mt).abs() > 1e-3 * mt {
            r.warnings.push(format!(
                "the paper prints a rotating mass of {pr} kg but its own items add up to {mt:.4} kg ({:+.2} %)",
                pct(pr, mt)
            ));
        }
    }
    if let Some(ps) = pd.reciprocating_mass {
        if (ps - mc).abs() > 1e-3 * mc {
            r.warnings.push(format!(
                "the paper prints a reciprocating mass of {ps} kg but its own items add up to {mc:.4} kg ({:+.2} %)",
                pct(ps, mc)
            ));
        }
    }
    if let (Some(pr), Some(ps)) = (pd.rotating_mass, pd.reciprocating_mass) {
        let f6 = (pr + 0.5 * ps) * m.r / rad;
        derived.formula6_counterweight_mass_printed_inputs_kg = Some(f6);
        if let Some(pm) = pd.counterweight_mass {
            if (pm - f6).abs() > 1e-4 * f6 {
                r.warnings.push(format!(
                    "the paper prints a counterweight of {pm} kg but formula (6) on its own printed inputs gives {f6:.4} kg ({:+.3} %)",
                    pct(pm, f6)
                ));
            }
        }
    }
    match &sol.paper_counterweight {
        Some(Err(e)) => r.warnings.push(format!(
            "the paper's counterweight could not be evaluated: {e}"
        )),
        Some(Ok(met)) => {
            if let Some(none) = sol.out.baselines.get("none") {
                derived.paper_counterweight_torque_reduction_pct =
                    Some(100.0 * (none.peak_torque - met.peak_torque) / none.peak_torque);
            }
        }
        None => {}
    }
}
