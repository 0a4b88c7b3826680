//! The hypocycloid's documents: the tables, plots and drawings of a solved scene, drawn from its
//! solution and the result's numbers, calling no solver; the driver makes them only when a
//! result's files are asked for (`SolveResult::draw`, `complete`). The numbers themselves are
//! `numbers.rs`'.

use super::balance::DynamicsOutcome;
use super::file::*;
use super::solve::{kebab, Analyses, Solution};
use crate::families::family::Scene;
use crate::families::hypocycloid::synth::{self as hy, Outcome, ZeroStatus};
use crate::geom::P2;
use crate::report::drawing::{Drawing, DrawingError, Layer, Sheet};
use crate::report::plot::{self, Grid, Panel, PlotError, Series};
use crate::report::{Plot, SolveResult, Table};
use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;

use super::motion::{lanchester_masses, speed_name, ShaftMass};
use super::numbers::closed_form_rows;

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
    let shafts = (s.dynamics.shafts)
        .map(|l| lanchester_masses(&l, &out.balancing))
        .unwrap_or_default();
    mechanism_drawing(r, &scene.name, &out.design, s.scene.alpha0, shafts);
    let cws = sol.dynamics.as_ref().and_then(|d| d.as_ref().ok());
    let cws = cws.and_then(|d| d.rotating.as_ref()?.design_pair());
    let motion = super::motion::motion(s, &out.design, cws, &out.balancing);
    r.motion = motion.and_then(|m| serde_json::to_value(m).ok());
    r.tables = tables(out);
    closed_form_table(r, s, out);
    if let Some(Ok(d)) = &sol.dynamics {
        dynamics_documents(r, &scene.name, d);
        if let Some(lc) = &sol.load_cases {
            let peak = d.rotating.as_ref().map(|rot| rot.design_peak());
            super::load_cases::table(r, lc, peak);
            if lc.flywheel.is_some() {
                // A band's end is a case of its own, named with its speed.
                let every = lc
                    .cases
                    .iter()
                    .filter_map(|c| match c.at_flywheel.as_ref() {
                        Some(Ok(d)) => Some((c.case.name.clone(), d.clone())),
                        _ => None,
                    })
                    .collect();
                crate::report::drive::cases_plot(r, every, "carrier");
            }
            // The case that governs the flywheel, where it is not the nominal one: its turn
            // and its steady state with the flywheel of all the cases.
            if let Some(c) = (lc.flywheel.and_then(|f| f.governing))
                .filter(|&k| k > 0)
                .map(|k| &lc.cases[k])
            {
                let case = Some(("governing", c.case.name.as_str()));
                crate::report::drive::drive_documents_of(
                    r,
                    c.at_flywheel.as_ref(),
                    "carrier",
                    case,
                );
            }
        }
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
    r.plots.push(Plot::of_panels(
        "coefficients",
        "Coefficients of S/R: exact against the paper-style truncated series (values below the error estimate not drawn)",
        560,
        460,
        move || coefficient_plot(&d.0, &d.1),
    ));
    let d = shared;
    r.plots.push(Plot::of_panels(
        "force",
        "Inertia force of the reciprocating mass over one turn, and the piston path",
        560,
        460,
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

fn coefficient_plot(scene: &Scene, out: &Outcome) -> Result<Vec<Panel>, PlotError> {
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
    Ok(vec![
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
    ])
}

fn force_plot(scene: &Scene, out: &Outcome) -> Result<Vec<Panel>, PlotError> {
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
    Ok(vec![
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
    ])
}

/// The mechanism's drawing (`<name>-drawing.dxf`/`.svg`) at φ = 0: the fixed ring gear
/// (pitch radius 3R/2) about O, the carrier OO₁ = R, the planet (pitch radius R/2) about O₁,
/// the crank arm O₁A = r = θR at α0 − 2φ, the rod AB = L = R/λ to the piston B on the x axis
/// (B = (x_A + √(L² − y_A²), 0), the model's S), with R, r, L dimensioned; the path of A over
/// a turn, A/R = (cos φ + θ cos(α0 − 2φ), sin φ + θ sin(α0 − 2φ)), on `PATH`; the
/// Lanchester shafts with their masses at φ = 0 where the file places them ([`shafts`]).
fn mechanism_drawing(
    r: &mut SolveResult,
    name: &str,
    d: &hy::Design,
    alpha0: f64,
    masses: Vec<ShaftMass>,
) {
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
        // Below the ring where the Lanchester shafts are above it (their masses reach over
        // its top), else above it.
        let ring_label = match masses.first() {
            Some(m) if m.centre.y > 0.0 => -(1.5 * big_r + 4.0 * pin),
            _ => 1.5 * big_r + 2.0 * pin,
        };
        dr.label(P2::new(0.0, ring_label), "ring gear (fixed)");
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
        shafts(&mut dr, &masses, pin, off);
        Ok(dr)
    }));
}

/// The Lanchester shafts at φ = 0 ([`lanchester_masses`]): each shaft's centre (a mark and
/// a journal circle of the drawing's pin size), each mass's half-disc outline towards its
/// phase (the arc and its diameter), the offset e from the piston line (beside the right
/// shaft's masses) and the spacing d (beyond their reach, away from the piston line)
/// dimensioned where not 0, a label per shaft beyond that and a note per order. Nothing
/// without masses.
fn shafts(dr: &mut Drawing, masses: &[ShaftMass], pin: f64, off: f64) {
    let Some(first) = masses.first() else {
        return;
    };
    let (e, half) = (first.centre.y, first.centre.x.abs());
    let reach = masses.iter().map(|m| m.radius).fold(0.0, f64::max);
    // Away from the piston line: up where the shafts are above it.
    let out = if e >= 0.0 { 1.0 } else { -1.0 };
    for sense in [1.0, -1.0] {
        let on: Vec<&ShaftMass> = masses.iter().filter(|m| m.sense == sense).collect();
        let Some(m0) = on.first() else { continue };
        let c = m0.centre;
        dr.mark(c).circle(Layer::Outline, c, pin);
        for m in &on {
            let a = m.angle(0.0);
            let end = |t: f64| c + m.radius * P2::new(t.cos(), t.sin());
            dr.arc(Layer::Outline, c, m.radius, a - 0.5 * PI, a + 0.5 * PI)
                .line(Layer::Outline, end(a - 0.5 * PI), end(a + 0.5 * PI));
        }
        let speeds: Vec<String> = on.iter().map(|m| speed_name(m.order, sense)).collect();
        let at = c + P2::new(0.0, out * (reach + 1.5 * off + 2.0 * pin));
        dr.label(at, format!("shaft {}", speeds.join(", ")));
    }
    if e != 0.0 {
        // e from the piston line, beside the co-rotating shaft's masses.
        let x = half + reach + off;
        dr.linear(P2::new(x, 0.0), P2::new(x, e), 0.0, "e");
    }
    if half > 0.0 {
        // Left to right, a positive offset is above the line.
        dr.linear(
            P2::new(-half, e),
            P2::new(half, e),
            out * (reach + 0.5 * off),
            "d",
        );
    }
    dr.note(format!(
        "Lanchester shafts (the file's [mechanism.lanchester]): e = {:.1} mm from the piston line, d = {:.1} mm apart, centred about O (the file gives no place along the line; no figure depends on it); every order's masses on the same two shafts, drawn over each other",
        e * 1e3,
        2.0 * half * 1e3
    ));
    for m in masses.iter().filter(|m| m.sense > 0.0) {
        dr.note(format!(
            "order {}: m′r′ = {:.4e} kg·m each, drawn as a steel half-disc {:.0} mm thick (assumed), radius {:.1} mm, {:.3} kg; at φ = 0 the {} mass at {:.1}°, the {} mass at {:.1}°",
            m.order,
            m.static_moment,
            crate::report::motion::DISC_THICKNESS * 1e3,
            m.radius * 1e3,
            m.mass,
            speed_name(m.order, 1.0),
            m.phase.to_degrees(),
            speed_name(m.order, -1.0),
            masses
                .iter()
                .find(|n| n.sense < 0.0 && n.order == m.order)
                .map_or(f64::NAN, |n| n.phase)
                .to_degrees()
        ));
    }
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
        r.plots.push(Plot::of_panels(
            "torque",
            "Drive torque over a turn: gas, inertia and their sum",
            560,
            460,
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
) -> Result<Vec<Panel>, PlotError> {
    let deg: Vec<f64> = t.phi.iter().map(|p| p * 180.0 / PI).collect();
    let zip =
        |v: &[f64]| -> Vec<(f64, f64)> { deg.iter().copied().zip(v.iter().copied()).collect() };
    let mut series = vec![
        Series::line("gas torque", zip(&t.gas)),
        Series::line("inertia torque", zip(&t.inertia)),
        Series::line("drive torque", zip(&t.total)),
    ];
    series.push(headroom(&series));
    Ok(vec![Panel {
        title: format!("{name}: drive torque at constant speed"),
        x_label: "carrier angle φ (deg)".into(),
        y_label: "torque (N·m)".into(),
        series,
        equal_aspect: false,
    }])
}
