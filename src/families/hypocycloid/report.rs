//! The hypocycloid result: its outcome shaped into the common result — design,
//! objectives with their errors, baselines, paper checks, tables and plots (keys in
//! `docs/results.md`).

use super::balance::{DynamicsOutcome, RotatingOutcome};
use super::file::*;
use super::solve::{kebab, Analyses, Solution};
use crate::families::family::Scene;
use crate::families::hypocycloid::synth::{self as hy, Outcome, ZeroStatus};
use crate::geom::P2;
use crate::report::drawing::{Drawing, DrawingError, Layer, Sheet};
use crate::report::plot::{self, Grid, Panel, PlotError, Series};
use crate::report::{number_map, Plot, SolveResult, Status, Table};
use serde_json::json;
use std::collections::BTreeMap;
use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;

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
    r.design = number_map(&out.design);
    r.objectives = number_map(&out.objectives);
    r.errors = number_map(&out.errors);
    r.derived = number_map(&out.derived);
    sections(r, out);
    r.paper = out.paper.clone();
    closed_form_numbers(r, s, out);
    if let Some(d) = &sol.dynamics {
        dynamics_numbers(r, d);
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

/// No analyses beyond the solution's own documents.
pub fn analysis_documents(
    _: &Scene,
    _: &HypocycloidProblem,
    _: &Solution,
    _: &Analyses,
    _: &mut SolveResult,
) {
}

/// The tables, plots and drawing of a solved scene, in the order the report lists them.
pub fn documents(scene: &Scene, s: &HypocycloidProblem, sol: &Solution, r: &mut SolveResult) {
    let out = &sol.out;
    mechanism_drawing(r, &scene.name, &out.design, s.scene.alpha0);
    r.tables = tables(out);
    closed_form_table(r, s, out);
    if let Some(Ok(d)) = &sol.dynamics {
        dynamics_documents(r, &scene.name, d);
    }
    let order = out.zero_search.as_ref().map(|z| z.order);
    let shared = std::sync::Arc::new((scene.clone(), out.clone()));
    if let Some(order) = order {
        let d = shared.clone();
        r.plots.push(Plot::new(
            "c4-map",
            format!("a{order} over (λ, θ) with its zero curve"),
            move || map_plot(&d.0, &d.1),
        ));
    }
    let d = shared.clone();
    r.plots.push(Plot::new(
        "coefficients",
        "Coefficients of S/R: exact against the paper-style truncated series (values below the error estimate not drawn)",
        move || coefficient_plot(&d.0, &d.1),
    ));
    let d = shared;
    r.plots.push(Plot::new(
        "force",
        "Inertia force of the reciprocating mass over one turn, and the piston path",
        move || force_plot(&d.0, &d.1),
    ));
}

fn csv_num(v: f64) -> String {
    if v.is_finite() {
        format!("{v:e}")
    } else {
        String::new()
    }
}

fn tables(out: &Outcome) -> Vec<Table> {
    let mut t = Vec::new();
    let c = &out.coefficients;
    let mut csv = String::from(
        "order,a,b,error,a_series,b_series,a_series_minus_a,b_series_minus_b,force_amplitude_n,balanced\n",
    );
    for row in &c.rows {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{}",
            row.order,
            csv_num(row.a),
            csv_num(row.b),
            csv_num(row.error),
            csv_num(row.a_series),
            csv_num(row.b_series),
            csv_num(row.a_series - row.a),
            csv_num(row.b_series - row.b),
            csv_num(row.force_amplitude),
            row.balanced
        );
    }
    t.push(Table {
        suffix: "coefficients".into(),
        caption: format!(
            "Fourier coefficients of S/R by order: exact (FFT, n = {}) and the binomial series to power {}",
            c.n_fft, c.series_power
        ),
        csv,
    });
    let fc = &out.force_curves;
    let mut csv = String::from("phi_rad,unbalanced_force_n,residual_force_n,piston_position_m\n");
    for j in 0..fc.phi.len() {
        let _ = writeln!(
            csv,
            "{},{},{},{}",
            csv_num(fc.phi[j]),
            csv_num(fc.unbalanced[j]),
            csv_num(fc.residual[j]),
            csv_num(fc.position[j])
        );
    }
    t.push(Table {
        suffix: "force".into(),
        caption: "Inertia force of m_B over one turn, unbalanced and after the Lanchester pairs"
            .into(),
        csv,
    });
    if let Some(z) = &out.zero_search {
        let mut csv = String::from(
            "lambda,theta,value,value_error,bracket_theta_lo,bracket_theta_hi,value_lo,value_hi,series_theta,series_value\n",
        );
        for r in &z.roots {
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{},{},{},{},{}",
                csv_num(r.lambda),
                csv_num(r.theta),
                csv_num(r.value),
                csv_num(r.value_error),
                csv_num(r.bracket.0),
                csv_num(r.bracket.1),
                csv_num(r.f_bracket.0),
                csv_num(r.f_bracket.1),
                r.series_theta.map(csv_num).unwrap_or_default(),
                csv_num(r.series_value)
            );
        }
        t.push(Table {
            suffix: "zero-curve".into(),
            caption: format!(
                "Zero set of a{} over (λ, θ): each root with its bracket and the truncated series' root",
                z.order
            ),
            csv,
        });
        let mut csv = format!("lambda,theta,a{}\n", z.order);
        for (i, l) in z.map.lambda.iter().enumerate() {
            for (j, th) in z.map.theta.iter().enumerate() {
                let _ = writeln!(
                    csv,
                    "{},{},{}",
                    csv_num(*l),
                    csv_num(*th),
                    z.map.value[i][j].map(csv_num).unwrap_or_default()
                );
            }
        }
        t.push(Table {
            suffix: "map".into(),
            caption: format!(
                "a{} on the search grid (empty where the mechanism cannot assemble)",
                z.order
            ),
            csv,
        });
    }
    t
}

fn map_plot(scene: &Scene, out: &Outcome) -> Result<String, PlotError> {
    let z = out
        .zero_search
        .as_ref()
        .ok_or(PlotError::Data("no zero search".into()))?;
    let m = &z.map;
    let grid = Grid {
        x: m.lambda.clone(),
        y: m.theta.clone(),
        values: (0..m.theta.len())
            .map(|j| {
                (0..m.lambda.len())
                    .map(|i| m.value[i][j].unwrap_or(f64::NAN))
                    .collect()
            })
            .collect(),
    };
    let pts = |v: &[hy::ZeroPoint]| -> Vec<(f64, f64)> {
        // Break the line where consecutive roots are not neighbours of one branch.
        let mut p = Vec::new();
        let dl = if m.lambda.len() > 1 {
            m.lambda[1] - m.lambda[0]
        } else {
            1.0
        };
        for (k, q) in v.iter().enumerate() {
            if k > 0 {
                let prev = v[k - 1];
                if (q.lambda - prev.lambda).abs() > 1.5 * dl || (q.theta - prev.theta).abs() > 0.1 {
                    p.push((f64::NAN, f64::NAN));
                }
            }
            p.push((q.lambda, q.theta));
        }
        p
    };
    // Fixed slots, so that each item keeps its colour (red, white, black, magenta) whether
    // or not there is a zero curve.
    let mut series = vec![
        Series::line(
            if out.zero_curve.is_empty() {
                format!("a{} = 0 (exact): none in the box", z.order)
            } else {
                format!("a{} = 0 (exact)", z.order)
            },
            pts(&out.zero_curve),
        ),
        Series::line(
            format!(
                "a{} = 0 (paper's series to z^{}){}",
                z.order,
                out.coefficients.series_power,
                if out.zero_curve_series.is_empty() {
                    ": none"
                } else {
                    ""
                }
            ),
            pts(&out.zero_curve_series),
        ),
    ];
    let (l, t) = (out.design.lambda, out.design.theta);
    series.push(Series::marker(
        format!("design of least residual force (λ = {l:.3}, θ = {t:.3})"),
        vec![(l, t)],
    ));
    if z.status != ZeroStatus::Found {
        if let Some(g) = z.grid_min_abs {
            series.push(Series::marker(
                format!(
                    "min |a{}| = {:.2e} at (λ, θ) = ({}, {})",
                    z.order,
                    g.value.abs(),
                    g.lambda,
                    g.theta
                ),
                vec![(g.lambda, g.theta)],
            ));
        }
    }
    let svg = plot::heat_map(
        &Panel {
            title: format!(
                "{}: a{o} of S/R, colour sign(a{o})·log10(1 + |a{o}|/1e-4)",
                scene.name,
                o = z.order
            ),
            x_label: "λ = R/L (–)".into(),
            y_label: "θ = r/R (–)".into(),
            series,
            equal_aspect: false,
        },
        &grid,
        Some(1e-4),
        900,
        620,
    )?;
    Ok(svg)
}

/// An invisible one-point series that raises the top of a panel by a third of its span,
/// so that the legend (upper right) does not cover the data. A line with one point draws
/// nothing and has no legend entry.
fn headroom(series: &[Series]) -> Series {
    let ys = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (lo, hi, x) = ys.fold((f64::INFINITY, f64::NEG_INFINITY, 0.0), |(lo, hi, _), p| {
        (lo.min(p.1), hi.max(p.1), p.0)
    });
    let top = if hi > lo {
        hi + 0.4 * (hi - lo)
    } else {
        f64::NAN
    };
    Series::line("", vec![(x, top)])
}

fn coefficient_plot(scene: &Scene, out: &Outcome) -> Result<String, PlotError> {
    let c = &out.coefficients;
    // Values below the coefficient's own error estimate are zero to working accuracy (e.g.
    // the b_i of variant 1, the odd a_i of variant 2): not drawn.
    let lg = |v: f64, i: usize| {
        if v.abs() > c.error[i] {
            v.abs().log10()
        } else {
            f64::NAN
        }
    };
    let by_order = |f: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> {
        (1..c.a.len()).map(|i| (i as f64, lg(f(i), i))).collect()
    };
    let p = c.series_power;
    // Series crosses first, exact dots after: a dot inside its cross is agreement.
    let mut left = vec![Series::marker(
        format!("|a_i| series to z^{p}"),
        by_order(&|i| c.a_series[i]),
    )];
    let has_b = (1..c.b.len()).any(|i| c.b[i].abs() > c.error[i]);
    if has_b {
        left.push(Series::marker(
            format!("|b_i| series to z^{p}"),
            by_order(&|i| c.b_series[i]),
        ));
    }
    left.push(Series::points("|a_i| exact", by_order(&|i| c.a[i])));
    if has_b {
        left.push(Series::points("|b_i| exact", by_order(&|i| c.b[i])));
    }
    left.push(headroom(&left));
    let mut right = vec![Series::marker(
        "|a_i series − a_i|",
        by_order(&|i| c.a_series[i] - c.a[i]),
    )];
    if has_b {
        right.push(Series::marker(
            "|b_i series − b_i|",
            by_order(&|i| c.b_series[i] - c.b[i]),
        ));
    }
    right.push(Series::line(
        "error estimate of the exact a_i, b_i",
        (1..c.a.len())
            .map(|i| (i as f64, c.error[i].log10()))
            .collect(),
    ));
    right.push(headroom(&right));
    let svg = plot::panels(
        &[
            Panel {
                title: format!("{}: Fourier coefficients of S/R", scene.name),
                x_label: "order i (–)".into(),
                y_label: "log10 |coefficient| (–)".into(),
                series: left,
                equal_aspect: false,
            },
            Panel {
                title: format!("paper's series (to z^{p}) − exact"),
                x_label: "order i (–)".into(),
                y_label: "log10 |difference| (–)".into(),
                series: right,
                equal_aspect: false,
            },
        ],
        560,
        460,
    )?;
    Ok(svg)
}

fn force_plot(scene: &Scene, out: &Outcome) -> Result<String, PlotError> {
    let fc = &out.force_curves;
    let deg: Vec<f64> = fc.phi.iter().map(|p| p * 180.0 / PI).collect();
    let zip =
        |v: &[f64]| -> Vec<(f64, f64)> { deg.iter().copied().zip(v.iter().copied()).collect() };
    let orders: Vec<String> = out.balancing.iter().map(|p| p.order.to_string()).collect();
    let pos_mm: Vec<f64> = fc.position.iter().map(|x| x * 1e3).collect();
    let mut force_series = vec![
        Series::line("unbalanced", zip(&fc.unbalanced)),
        Series::line(
            if orders.is_empty() {
                "residual (nothing balanced)".to_string()
            } else {
                format!("after balancing orders {}", orders.join(", "))
            },
            zip(&fc.residual),
        ),
    ];
    force_series.push(headroom(&force_series));
    let mut pos_series = vec![Series::line("S − L", zip(&pos_mm))];
    pos_series.push(headroom(&pos_series));
    let svg = plot::panels(
        &[
            Panel {
                title: format!("{}: inertia force of m_B", scene.name),
                x_label: "carrier angle φ (deg)".into(),
                y_label: "force (N)".into(),
                series: force_series,
                equal_aspect: false,
            },
            Panel {
                title: "piston position".into(),
                x_label: "carrier angle φ (deg)".into(),
                y_label: "S − L (mm)".into(),
                series: pos_series,
                equal_aspect: false,
            },
        ],
        560,
        460,
    )?;
    Ok(svg)
}

/// The mechanism's drawing (`<name>-drawing.dxf`/`.svg`) at φ = 0: the fixed ring gear
/// (pitch radius 3R/2) about O, the carrier OO₁ = R, the planet (pitch radius R/2) about O₁,
/// the crank arm O₁A = r = θR at α0 − 2φ, the rod AB = L = R/λ to the piston B on the x axis
/// (B = (x_A + √(L² − y_A²), 0), the model's S), with R, r, L dimensioned; the path of A over
/// a turn, A/R = (cos φ + θ cos(α0 − 2φ), sin φ + θ sin(α0 − 2φ)), on `PATH`.
fn mechanism_drawing(r: &mut SolveResult, name: &str, d: &hy::Design, alpha0: f64) {
    let (name, d) = (name.to_string(), d.clone());
    let caption = "planetary mechanism at φ = 0 and the path of the crank pin A";
    r.drawings.push(Sheet::new("drawing", caption, move || {
        let model = crate::families::hypocycloid::model::Hypocycloid::new(d.lambda, d.theta, alpha0)
            .map_err(|e| DrawingError::Data(e.to_string()))?;
        let big_r = d.carrier_radius_m;
        let at = |phi: f64| {
            let (x, y) = model.point_a(phi);
            big_r * P2::new(x, y)
        };
        let piston = |phi: f64| big_r * (model.piston(phi).s_rel + 1.0 / d.lambda);
        let (o, o1, a) = (P2::zeros(), P2::new(big_r, 0.0), at(0.0));
        let b = P2::new(piston(0.0), 0.0);
        let pin = 0.05 * big_r;
        let mut dr = Drawing::new(format!(
            "{name}: planetary (3:1) mechanism at φ = 0, path of A in blue"
        ));
        let n = 720;
        let path: Vec<P2> = (0..n).map(|k| at(TAU * k as f64 / n as f64)).collect();
        let (s_min, s_max) = (0..n)
            .map(|k| piston(TAU * k as f64 / n as f64))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(s), hi.max(s))
            });
        dr.polyline(Layer::Path, path, true);
        dr.line(
            Layer::Centre,
            P2::new(s_min - 4.0 * pin, 0.0),
            P2::new(s_max + 4.0 * pin, 0.0),
        );
        dr.mark(o).mark(o1).mark(a).mark(b);
        dr.circle(Layer::Outline, o, 1.5 * big_r)
            .circle(Layer::Outline, o1, 0.5 * big_r);
        dr.line(Layer::Outline, o, o1)
            .line(Layer::Outline, o1, a)
            .line(Layer::Outline, a, b);
        for p in [o1, a, b] {
            dr.circle(Layer::Outline, p, pin);
        }
        let (w, h) = (3.0 * pin, 2.0 * pin);
        dr.polyline(
            Layer::Outline,
            vec![
                b + P2::new(-w, -h),
                b + P2::new(w, -h),
                b + P2::new(w, h),
                b + P2::new(-w, h),
            ],
            true,
        );
        let off = 0.25 * big_r;
        dr.linear(o, o1, -off, "R");
        // r on the side away from O (below when O, O₁, A are in line).
        let away = (0.5 * (o1 + a) + off * crate::geom::perp((a - o1) / (a - o1).norm())).norm()
            > (0.5 * (o1 + a)).norm() + 0.5 * off;
        dr.linear(o1, a, if away { off } else { -off }, "r");
        dr.linear(a, b, -off, "L");
        dr.label(P2::new(0.0, 1.5 * big_r + 2.0 * pin), "ring gear (fixed)");
        dr.note(format!(
            "λ = R/L = {:.4}, θ = r/R = {:.4}, orientation α0 = {:.2}°",
            d.lambda,
            d.theta,
            alpha0.to_degrees()
        ));
        dr.note(format!(
            "ring gear pitch radius 3R/2 = {:.2} mm (fixed), planet pitch radius R/2 = {:.2} mm, turning at −2φ",
            1.5 * big_r * 1e3,
            0.5 * big_r * 1e3
        ));
        dr.note("O: carrier axis; O₁: planet axis; A: crank pin on the planet; B: piston on the x axis; dimensions in mm");
        Ok(dr)
    }));
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
struct ClosedFormRow {
    order: usize,
    label: String,
    closed: f64,
    exact: f64,
    error: f64,
    verdict: crate::families::hypocycloid::closed_form::Verdict,
}

/// The paper's closed-form C_i against the exact ones (variants 1 and 2 only: the paper gives
/// no other).
fn closed_form_rows(
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

/// The closed-form comparison's table `<name>-closed-form.csv`.
fn closed_form_table(r: &mut SolveResult, s: &HypocycloidProblem, out: &Outcome) {
    let Some((pc, rows)) = closed_form_rows(s, out) else {
        return;
    };
    let mut csv = String::from(
        "order,coefficient,closed_form,exact,closed_minus_exact,exact_error,verdict\n",
    );
    for w in &rows {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{}",
            w.order,
            w.label,
            csv_num(w.closed),
            csv_num(w.exact),
            csv_num(w.closed - w.exact),
            csv_num(w.error),
            kebab(w.verdict)
        );
    }
    r.tables.push(Table {
        suffix: "closed-form".into(),
        caption: format!(
            "The paper's closed-form coefficients (root expanded to y⁶, harmonics collected to the 6th; C0 without 1/λ) against the exact FFT ones, variant {}",
            pc.variant
        ),
        csv,
    });
}

/// The dynamics' numbers: the counterweights to build in `design`, the rotating force, drive
/// torque and couple figures in `derived`, the `dynamics` section; a failure fails the result.
fn dynamics_numbers(r: &mut SolveResult, d: &Result<DynamicsOutcome, String>) {
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
    crate::report::drive::drive_numbers(r, d.drive.as_ref(), None);
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

/// The dynamics' tables (rotating counterweights, drive torque, couples) and the torque plot.
fn dynamics_documents(r: &mut SolveResult, name: &str, d: &DynamicsOutcome) {
    if let Some(rot) = &d.rotating {
        let mut csv = String::from(
            "solution,counterweight,body_frame,first_moment_kgm,angle_deg,radius_m,mass_kg,shaking_force_peak_n,status\n",
        );
        let mut row = |sol: &str,
                       c: &crate::families::hypocycloid::dynamics::Counterweight,
                       body: &str,
                       which: &str,
                       peak: f64,
                       st: &str| {
            let _ = writeln!(
                csv,
                "{sol},{which},{body},{},{},{},{},{},{st}",
                csv_num(c.first_moment),
                csv_num(c.angle.to_degrees()),
                csv_num(c.radius),
                csv_num(c.mass),
                csv_num(peak)
            );
        };
        if let Some((c1, c2)) = &rot.closed {
            let p = rot.closed_total_peak.unwrap_or(f64::NAN);
            row(
                "cancel rotating (closed form)",
                c1,
                "carrier (x along OO1)",
                "carrier",
                p,
                "exact",
            );
            row(
                "cancel rotating (closed form)",
                c2,
                "planet (x along O1A)",
                "planet",
                p,
                "exact",
            );
        }
        if let Some(mm) = &rot.minimax {
            let st = kebab(mm.status);
            row(
                "minimax of the whole shaking force",
                &mm.carrier,
                "carrier (x along OO1)",
                "carrier",
                mm.peak,
                &st,
            );
            row(
                "minimax of the whole shaking force",
                &mm.planet,
                "planet (x along O1A)",
                "planet",
                mm.peak,
                &st,
            );
        }
        r.tables.push(Table {
            suffix: "rotating-counterweights".into(),
            caption: format!(
                "Rotating-mass counterweights: U1 = ({:.4e}, {:.4e}) kg·m (carrier), U2 = ({:.4e}, {:.4e}) kg·m (planet); rotating force {:.4} N without them; whole shaking force {:.4} N without them",
                rot.u1[0], rot.u1[1], rot.u2[0], rot.u2[1], rot.rotating_peak, rot.bare_total_peak
            ),
            csv,
        });
    }
    if let Some(t) = &d.torque {
        let mut csv =
            String::from("phi_rad,gas_torque_nm,inertia_torque_nm,drive_torque_nm,pressure_pa\n");
        for j in 0..t.phi.len() {
            let _ = writeln!(
                csv,
                "{},{},{},{},{}",
                csv_num(t.phi[j]),
                csv_num(t.gas[j]),
                csv_num(t.inertia[j]),
                csv_num(t.total[j]),
                t.pressure.get(j).map(|p| csv_num(*p)).unwrap_or_default()
            );
        }
        r.tables.push(Table {
            suffix: "torque".into(),
            caption: format!(
                "Drive torque over a turn: peak {:.4} N·m, mean {:.4} N·m (gas {:.4}, inertia {:.2e})",
                t.peak, t.mean, t.gas_mean, t.inertia_mean
            ),
            csv,
        });
        let curves = t.clone();
        let title = name.to_string();
        r.plots.push(Plot::new(
            "torque",
            "Drive torque over a turn: gas, inertia and their sum",
            move || torque_plot(&title, &curves),
        ));
    }
    if let Some(cp) = &d.couples {
        let mut csv = String::from("order,couple_amplitude_nm\n");
        for row in &cp.rows {
            let _ = writeln!(csv, "{},{}", row.order, csv_num(row.amplitude));
        }
        r.tables.push(Table {
            suffix: "lanchester-couples".into(),
            caption: format!(
                "Couples of the Lanchester pairs with shafts offset e = {} mm from the piston line and spaced d = {} mm along it: F_i·sqrt(e² + d²/4) per order; peak of their sum {:.4} N·m",
                cp.layout.offset * 1e3,
                cp.layout.spacing * 1e3,
                cp.peak
            ),
            csv,
        });
    }
    crate::report::drive::drive_documents(r, d.drive.as_ref(), "carrier");
}

fn torque_plot(
    name: &str,
    t: &crate::families::hypocycloid::balance::TorqueOutcome,
) -> Result<String, PlotError> {
    let deg: Vec<f64> = t.phi.iter().map(|p| p * 180.0 / PI).collect();
    let zip =
        |v: &[f64]| -> Vec<(f64, f64)> { deg.iter().copied().zip(v.iter().copied()).collect() };
    let mut series = vec![
        Series::line("gas torque", zip(&t.gas)),
        Series::line("inertia torque", zip(&t.inertia)),
        Series::line("drive torque", zip(&t.total)),
    ];
    series.push(headroom(&series));
    plot::panels(
        &[Panel {
            title: format!("{name}: drive torque at constant speed"),
            x_label: "carrier angle φ (deg)".into(),
            y_label: "torque (N·m)".into(),
            series,
            equal_aspect: false,
        }],
        560,
        460,
    )
}
