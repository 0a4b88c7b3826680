//! The hypocycloid's numbers: the solution's figures into the result's maps — `model`, design,
//! objectives with their errors, derived figures, baselines, paper checks, sections and the
//! warnings of the result's own checks (keys in `docs/results.md`). Arithmetic on the solution
//! (sums, ratios, a limit compared), never a solve or a search: the driver runs it at solve
//! time for every result, `--summary-only` included, and `report.rs` draws from the same
//! solution.

use super::balance::{DynamicsOutcome, RotatingOutcome};
use super::file::*;
use super::load_cases::LoadCasesOutcome;
use super::solve::Solution;
use crate::families::family::Scene;
use crate::families::hypocycloid::synth::{self as hy, Outcome};
use crate::report::{number_map, SolveResult, Status};
use serde_json::json;
use std::collections::BTreeMap;

/// The result's `model` section: the kinematics, the coefficient model, the variant and the
/// masses the solve uses.
pub fn model(s: &HypocycloidProblem, _: Option<&Solution>) -> BTreeMap<String, serde_json::Value> {
    let h = &s.scene;
    BTreeMap::from([
        (
            "kinematics".into(),
            json!("exact (closed form, stable for λ → 0)"),
        ),
        (
            "coefficients".into(),
            json!(match h.coefficients {
                hy::CoefficientModel::Exact =>
                    "exact polynomial part + FFT of the O(λ³) remainder, size doubled until converged"
                        .to_string(),
                hy::CoefficientModel::Series => format!(
                    "the paper's binomial series truncated at z^{} (model.coefficients = \"series\")",
                    h.series_power
                ),
            }),
        ),
        ("variant".into(), json!(s.variant)),
        ("orientation_rad".into(), json!(h.alpha0)),
        ("orders".into(), json!(h.orders)),
        ("series_power".into(), json!(h.series_power)),
        ("balance_orders".into(), json!(h.balance_orders)),
        ("assembly_margin".into(), json!(h.assembly_margin)),
        (
            "masses".into(),
            json!(if s.dynamics.masses.is_some() {
                "reciprocating mass m_B (piston + the rod's share at B), and the rotating carrier, planet and the rod's share at A ([mechanism.carrier/planet/rod])"
            } else {
                "reciprocating mass m_B only (rotating masses assumed balanced)"
            }),
        ),
    ])
}

/// The result's numbers from the solution: status, design, objectives, errors, derived
/// figures, the coefficients, balancing, zero-curve, closed-form and dynamics sections.
pub fn numbers(_: &Scene, s: &HypocycloidProblem, sol: &Solution, r: &mut SolveResult) {
    let out = &sol.out;
    r.set_figures(&out.design, &out.objectives, &out.errors, &out.derived);
    sections(r, out);
    r.paper = out.paper.clone();
    closed_form_numbers(r, s, out);
    if let Some(d) = &sol.dynamics {
        dynamics_numbers(r, d, sol.load_cases.as_ref());
    }
}

/// The family's sections: the coefficients, the balancing pairs, the zero curves and the
/// zero search.
fn sections(r: &mut SolveResult, out: &Outcome) {
    let c = &out.coefficients;
    let amp: Vec<f64> = std::iter::once(0.0)
        .chain(c.rows.iter().map(|row| row.force_amplitude))
        .collect();
    r.extra.insert(
        "coefficients".into(),
        json!({
            "a": c.a, "b": c.b, "error": c.error,
            "a_series": c.a_series, "b_series": c.b_series,
            "force_amplitude_n": amp,
            "series_power": c.series_power, "n_fft": c.n_fft, "converged": c.converged,
        }),
    );
    r.extra.insert(
        "balancing".into(),
        json!(out
            .balancing
            .iter()
            .map(|p| json!({
                "order": p.order,
                "shaft_speed_rad_s": p.speed,
                "static_moment_kgm": p.static_moment,
                "phase_co_rad": p.phase_co,
                "phase_counter_rad": p.phase_counter,
            }))
            .collect::<Vec<_>>()),
    );
    r.extra.insert("zero_curve".into(), json!(out.zero_curve));
    r.extra
        .insert("zero_curve_series".into(), json!(out.zero_curve_series));
    if let Some(z) = &out.zero_search {
        r.extra.insert(
            "zero_search".into(),
            json!({
                "order": z.order,
                "status": z.status,
                "roots": z.roots.len(),
                "single_valued": z.single_valued,
                "sign": z.sign,
                "max_abs_at_root": z.max_abs_at_root,
                "min_abs": z.grid_min_abs.map(|g| g.value.abs()),
                "min_abs_lambda": z.grid_min_abs.map(|g| g.lambda),
                "min_abs_theta": z.grid_min_abs.map(|g| g.theta),
                "min_abs_value": z.grid_min_abs.map(|g| g.value),
                "reason": z.reason,
                "evaluations": z.evals,
            }),
        );
    }
}

/// The figures of the rotating counterweights, the drive torque and the Lanchester couples
/// (keys of `derived`; absent when the file does not ask for them).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct DynamicsDerived {
    /// |U1|: first moment of the parts turning with the carrier (kg·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotating_unbalance_carrier_kgm: Option<f64>,
    /// |U2|: first moment of the parts turning with the planet, about O1 (kg·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotating_unbalance_planet_kgm: Option<f64>,
    /// Peak of the rotating parts' inertia force without counterweights (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotating_force_peak_n: Option<f64>,
    /// Peak of the whole shaking force (rotating + reciprocating after the pairs) without
    /// rotating counterweights (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shaking_force_bare_peak_n: Option<f64>,
    /// Error bound of the shaking-force peaks (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shaking_force_peak_error_n: Option<f64>,
    /// Closed form: m1ρ1 of the carrier counterweight (kg·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub carrier_counterweight_first_moment_kgm: Option<f64>,
    /// Closed form: its angle in the carrier frame (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub carrier_counterweight_angle_rad: Option<f64>,
    /// Closed form: its mass at `design.rotating.carrier_radius` (kg).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub carrier_counterweight_mass_kg: Option<f64>,
    /// Closed form: m2ρ2 of the planet counterweight (kg·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub planet_counterweight_first_moment_kgm: Option<f64>,
    /// Closed form: its angle in the planet frame (x along O1A) (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub planet_counterweight_angle_rad: Option<f64>,
    /// Closed form: its mass at `design.rotating.planet_radius` (kg).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub planet_counterweight_mass_kg: Option<f64>,
    /// Peak of the rotating force left with the closed-form counterweights (N): round-off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotating_force_residual_peak_n: Option<f64>,
    /// Peak of the whole shaking force with the closed-form counterweights (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shaking_force_peak_n: Option<f64>,
    /// Minimax: the peak of the whole shaking force with its counterweights (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub minimax_shaking_force_peak_n: Option<f64>,
    /// Minimax: the certified lower bound of the optimum (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub minimax_lower_bound_n: Option<f64>,
    /// Minimax: |peak − optimum| ≤ this (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub minimax_error_n: Option<f64>,
    /// Peak |T| of the drive torque (gas + inertia) (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive_torque_peak_nm: Option<f64>,
    /// Its error bound (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive_torque_peak_error_nm: Option<f64>,
    /// Mean drive torque over a turn (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive_torque_mean_nm: Option<f64>,
    /// Error bound of the means (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive_torque_mean_error_nm: Option<f64>,
    /// Mean of the gas torque (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gas_torque_mean_nm: Option<f64>,
    /// Mean of the inertia torque (N·m): 0 up to the quadrature error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inertia_torque_mean_nm: Option<f64>,
    /// Indicated work per turn, −∮p dV = 2π × the mean gas torque (J = N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub indicated_work_nm: Option<f64>,
    /// Peak gas force on the piston (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gas_force_peak_n: Option<f64>,
    /// Peak over φ of the sum of the Lanchester pairs' couples (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lanchester_couple_peak_nm: Option<f64>,
    /// Its error bound (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lanchester_couple_peak_error_nm: Option<f64>,
}

/// One row of the closed-form comparison: order, coefficient, closed form, exact, the exact
/// one's error and the verdict.
pub(super) struct ClosedFormRow {
    pub(super) order: usize,
    pub(super) label: String,
    pub(super) closed: f64,
    pub(super) exact: f64,
    pub(super) error: f64,
    pub(super) verdict: crate::families::hypocycloid::closed_form::Verdict,
}

/// The paper's closed-form C_i against the exact ones (variants 1 and 2 only: the paper gives
/// no other).
pub(super) fn closed_form_rows(
    s: &HypocycloidProblem,
    out: &Outcome,
) -> Option<(
    crate::families::hypocycloid::closed_form::PaperCoefficients,
    Vec<ClosedFormRow>,
)> {
    use crate::families::hypocycloid::closed_form::{paper_coefficients, verdict};
    let pc = paper_coefficients(s.variant, out.design.lambda, out.design.theta)?;
    let c = &out.coefficients;
    let name = |i: usize, sine: bool| match (pc.variant, sine) {
        (1, _) => format!("C{i}"),
        (_, false) => format!("C{i}^I"),
        (_, true) => format!("C{i}^II"),
    };
    let mut rows = Vec::new();
    for i in 0..=6usize.min(c.a.len() - 1) {
        // a_0 of the exact table includes 1/λ; the closed form's C0 does not.
        let ea = if i == 0 {
            c.a[0] - 1.0 / out.design.lambda
        } else {
            c.a[i]
        };
        let mut parts = vec![(name(i, false), pc.a[i], ea)];
        if pc.variant == 2 && i > 0 {
            parts.push((name(i, true), pc.b[i], c.b[i]));
        }
        for (label, cf, ex) in parts {
            rows.push(ClosedFormRow {
                order: i,
                label,
                closed: cf,
                exact: ex,
                error: c.error[i],
                verdict: verdict(cf, ex, c.error[i]),
            });
        }
    }
    Some((pc, rows))
}

/// The paper's closed-form C_i beside the exact ones: the `closed_form` section.
fn closed_form_numbers(r: &mut SolveResult, s: &HypocycloidProblem, out: &Outcome) {
    let Some((pc, rows)) = closed_form_rows(s, out) else {
        return;
    };
    let rows: Vec<serde_json::Value> = rows
        .iter()
        .map(|w| {
            json!({
                "order": w.order, "coefficient": w.label, "closed_form": w.closed, "exact": w.exact,
                "difference": w.closed - w.exact, "exact_error": w.error, "verdict": w.verdict,
            })
        })
        .collect();
    r.extra.insert(
        "closed_form".into(),
        json!({
            "variant": pc.variant,
            "a": pc.a, "b": pc.b,
            "rows": rows,
        }),
    );
}

/// The dynamics' numbers: the counterweights to build in `design`, the rotating force, drive
/// torque and couple figures in `derived`, the `dynamics` section, the load cases'; a failure
/// fails the result.
fn dynamics_numbers(
    r: &mut SolveResult,
    d: &Result<DynamicsOutcome, String>,
    load_cases: Option<&LoadCasesOutcome>,
) {
    let d = match d {
        Ok(d) => d,
        Err(e) => {
            r.warnings.push(e.clone());
            r.status = Status::Failed;
            return;
        }
    };
    r.warnings.extend(d.warnings.iter().cloned());
    let mut k = DynamicsDerived::default();
    if let Some(rot) = &d.rotating {
        rotating_numbers(r, &mut k, rot);
    }
    if let Some(t) = &d.torque {
        k.drive_torque_peak_nm = Some(t.peak);
        k.drive_torque_peak_error_nm = Some(t.peak_error);
        k.drive_torque_mean_nm = Some(t.mean);
        k.drive_torque_mean_error_nm = Some(t.mean_error);
        k.gas_torque_mean_nm = Some(t.gas_mean);
        k.inertia_torque_mean_nm = Some(t.inertia_mean);
        k.indicated_work_nm = t.indicated_work;
        k.gas_force_peak_n = t.gas_force_peak;
    }
    if let Some(cp) = &d.couples {
        k.lanchester_couple_peak_nm = Some(cp.peak);
        k.lanchester_couple_peak_error_nm = Some(cp.peak_error);
    }
    r.derived.extend(number_map(&k));
    r.extra.insert("dynamics".into(), json!(d));
    let peak = d.rotating.as_ref().map(|rot| rot.design_peak());
    crate::report::drive::drive_numbers(r, d.drive.as_ref(), peak);
    if let Some(lc) = load_cases {
        super::load_cases::numbers(r, lc, peak);
    }
}

/// The rotating counterweights' figures, and the pair to build in `design`: the minimax pair
/// when it was asked for and certified, else the closed-form pair that cancels the rotating
/// force.
fn rotating_numbers(r: &mut SolveResult, k: &mut DynamicsDerived, rot: &RotatingOutcome) {
    k.rotating_unbalance_carrier_kgm = Some(rot.u1[0].hypot(rot.u1[1]));
    k.rotating_unbalance_planet_kgm = Some(rot.u2[0].hypot(rot.u2[1]));
    k.rotating_force_peak_n = Some(rot.rotating_peak);
    k.shaking_force_bare_peak_n = Some(rot.bare_total_peak);
    k.shaking_force_peak_error_n = Some(rot.peak_error);
    if let Some((c1, c2)) = &rot.closed {
        k.carrier_counterweight_first_moment_kgm = Some(c1.first_moment);
        k.carrier_counterweight_angle_rad = Some(c1.angle);
        k.carrier_counterweight_mass_kg = Some(c1.mass);
        k.planet_counterweight_first_moment_kgm = Some(c2.first_moment);
        k.planet_counterweight_angle_rad = Some(c2.angle);
        k.planet_counterweight_mass_kg = Some(c2.mass);
        k.rotating_force_residual_peak_n = rot.closed_rotating_residual;
        k.shaking_force_peak_n = rot.closed_total_peak;
    }
    if let Some(mm) = &rot.minimax {
        k.minimax_shaking_force_peak_n = Some(mm.peak);
        k.minimax_lower_bound_n = Some(mm.lower_bound);
        k.minimax_error_n = Some(mm.error);
    }
    let built = match (&rot.minimax, &rot.closed) {
        (Some(mm), _) if mm.status == crate::synth::counterweight::Status::Optimal => {
            Some((&mm.carrier, &mm.planet))
        }
        (_, Some((c1, c2))) => Some((c1, c2)),
        _ => None,
    };
    if let Some((c1, c2)) = built {
        for (body, c) in [("carrier", c1), ("planet", c2)] {
            r.design
                .insert(format!("{body}_counterweight_mass_kg"), c.mass);
            r.design
                .insert(format!("{body}_counterweight_radius_m"), c.radius);
            r.design
                .insert(format!("{body}_counterweight_angle_rad"), c.angle);
        }
    }
}
