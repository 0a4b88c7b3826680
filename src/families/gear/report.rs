//! The gear result: its outcome shaped into the common result — design,
//! objectives with their errors, baselines, paper checks, tables and plots (keys in
//! `docs/results.md`).

use super::file::*;
use crate::families::family::Scene;
use crate::families::gear::model::{EccentricCircle, GearPair, Which, ZeroKind};
use crate::families::gear::synth::{self as sg, GearScene, Outcome};
use crate::geom::P2;
use crate::report::drawing::{Drawing, Layer, Sheet};
use crate::report::plot::{self, Panel, PlotError, Series};
use crate::report::{number_map, Plot, SolveResult, Status, Table};
use serde_json::json;
use std::collections::BTreeMap;
use std::f64::consts::TAU;
use std::fmt::Write as _;
use std::time::Instant;

fn status_detail(s: sg::Status) -> &'static str {
    match s {
        sg::Status::Analysed => "analysed",
        sg::Status::Optimal => "interior-optimum",
        sg::Status::ConstraintBound => "constraint-bound",
        sg::Status::AtBound => "at-bound",
        sg::Status::Infeasible => "infeasible",
    }
}

/// The result of an eccentric-gear scene: solve, then shape keys, checks, plots and tables.
pub fn result(scene: &Scene, p: &GearProblem) -> SolveResult {
    let mut r = scene.new_result();
    let g = &p.gear;
    r.model = BTreeMap::from([
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
    ]);
    let t0 = Instant::now();
    let out = match sg::solve(g, &p.settings) {
        Ok(o) => o,
        Err(e) => {
            r.warnings.push(e.to_string());
            return r;
        }
    };
    r.timing.solve_s = t0.elapsed().as_secs_f64();
    r.status = match out.status {
        sg::Status::Analysed => Status::Analysed,
        // A sampled sweep + Brent is a heuristic search, not a certificate.
        sg::Status::Optimal | sg::Status::ConstraintBound | sg::Status::AtBound => {
            Status::BestFound
        }
        sg::Status::Infeasible => Status::Infeasible,
    };
    r.status_detail = Some(status_detail(out.status).into());
    r.search = out.search.clone();
    r.method = out.method.clone();
    r.design = number_map(&out.design);
    r.objectives = number_map(&out.objectives);
    r.errors = number_map(&out.errors);
    r.derived = number_map(&out.derived);
    r.warnings.extend(out.warnings.iter().cloned());
    r.paper = out.paper.clone();
    r.extra.insert(
        "poles".into(),
        serde_json::to_value(&out.poles).expect("plain data"),
    );
    r.extra.insert(
        "zeros".into(),
        serde_json::to_value(&out.zeros).expect("plain data"),
    );
    r.tables = tables(&out);
    let shared = std::sync::Arc::new((scene.clone(), g.clone(), out));
    let d = shared.clone();
    r.plots.push(Plot::new(
        "pitch-curves",
        "Pitch curves of both gears and the transmission function i12(α1)",
        move || ratio_and_curves_plot(&d.0, &d.2),
    ));
    let d = shared.clone();
    r.plots.push(Plot::new(
        "sliding",
        "Sliding coefficients µ1, µ2 against α1, poles marked, pole windows left empty",
        move || sliding_plot(&d.0, &d.1, &d.2),
    ));
    pitch_drawing(&mut r, &shared.0.name, &shared.2);
    if !shared.2.sweep.is_empty() {
        let d = shared.clone();
        r.plots.push(Plot::new(
            "sweep",
            "Design sweep over the eccentricity e",
            move || sweep_plot(&d.0, &d.1, &d.2),
        ));
    }
    r
}

fn closed(pts: &[[f64; 2]], scale: f64) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = pts.iter().map(|p| (p[0] * scale, p[1] * scale)).collect();
    if let Some(&f) = v.first() {
        v.push(f);
    }
    v
}

/// Pitch curves (equal axes, mm) and i12(α1).
fn ratio_and_curves_plot(scene: &Scene, out: &Outcome) -> Result<String, PlotError> {
    let pc = &out.pitch_curves;
    let mm = 1e3;
    let curves = Panel {
        title: format!("{}: pitch curves at α1 = 0", scene.name),
        x_label: "x (mm), O1 at the origin".into(),
        y_label: "y (mm)".into(),
        series: vec![
            Series::line("gear 1", closed(&pc.gear1_m, mm)),
            Series::line("gear 2", closed(&pc.gear2_m, mm)),
            Series::marker(
                "pivots O1, O2",
                vec![
                    (pc.center1_m[0] * mm, pc.center1_m[1] * mm),
                    (pc.center2_m[0] * mm, pc.center2_m[1] * mm),
                ],
            ),
        ],
        equal_aspect: true,
    };
    let s = &out.series;
    let i12: Vec<(f64, f64)> = s
        .alpha1_rad
        .iter()
        .zip(&s.i12)
        .map(|(&a, &i)| (a.to_degrees(), i))
        .collect();
    let (lo, hi) = (out.derived.ratio_min, out.derived.ratio_max);
    let ratio = Panel {
        title: format!("i12 = ω1/ω2: min {lo:.4}, max {hi:.4}"),
        x_label: "α1, angle of gear 1 (deg)".into(),
        y_label: "i12 (–)".into(),
        series: vec![Series::line("i12(α1)", i12)],
        equal_aspect: false,
    };
    let svg = plot::panels(&[curves, ratio], 560, 480)?;
    Ok(svg)
}

/// Vertical lines at the given x between y0 and y1, broken between lines.
fn verticals(xs: &[f64], y0: f64, y1: f64) -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for &x in xs {
        v.extend([(x, y0), (x, y1), (f64::NAN, f64::NAN)]);
    }
    v
}

/// µ1 and µ2 against α1: a full turn of gear 1 (the outcome's series) and a zoom on the
/// arches around the peak, evaluated afresh on a fine grid that includes the exact window
/// edges (so that the plotted curve reaches the reported peak).
fn sliding_plot(scene: &Scene, g: &GearScene, out: &Outcome) -> Result<String, PlotError> {
    let s = &out.series;
    let n_arch = out.derived.arches_gear1.max(1.0);
    let arch = TAU / n_arch;
    let w = out.derived.pole_window_rad;
    let peak_at = out.derived.peak_sliding_alpha1_rad;
    let peak = out.objectives.peak_sliding_coefficient;
    // Zoom: two arches starting half an arch before the arch holding the peak.
    let z0 = (peak_at / arch).floor() * arch - 0.5 * arch;
    let z1 = z0 + 2.0 * arch;
    let wrap = |x: f64| {
        [x - TAU, x, x + TAU]
            .into_iter()
            .find(|y| (z0..=z1).contains(y))
    };
    let excluded = |x: f64, which: Which| {
        let near = |c: f64, tol: f64| {
            let d = (x - c).rem_euclid(TAU);
            d.min(TAU - d) < tol
        };
        out.poles
            .iter()
            .any(|p| p.which == which && near(p.alpha1_rad, w + p.error_rad))
            || out
                .zeros
                .iter()
                .any(|z| z.kind == ZeroKind::Indeterminate && near(z.alpha1_rad, w))
    };
    let pair = EccentricCircle::new(g.pitch_radius, out.design.eccentricity_m)
        .and_then(|c| {
            GearPair::new(
                c,
                g.generating_radius,
                out.derived.center_distance_m,
                g.omega1,
            )
        })
        .map_err(PlotError::data)?;
    // Fine grid plus both edges of every window in the zoom range (nudged inside the
    // working region by 1e-9 rad).
    let mut xs: Vec<f64> = (0..=1200)
        .map(|k| z0 + (z1 - z0) * k as f64 / 1200.0)
        .collect();
    for p in &out.poles {
        for x in [
            p.alpha1_rad - w - p.error_rad - 1e-9,
            p.alpha1_rad + w + p.error_rad + 1e-9,
        ] {
            if let Some(x) = wrap(x) {
                xs.push(x);
            }
        }
    }
    xs.sort_by(f64::total_cmp);
    let zoom_mu = |which: Which| -> Vec<(f64, f64)> {
        xs.iter()
            .map(|&x| {
                let ct = pair.contact(x.rem_euclid(TAU));
                let m = match which {
                    Which::Mu1 => ct.mu1,
                    Which::Mu2 => ct.mu2,
                };
                let m = if excluded(x, which) { None } else { m };
                (x.to_degrees(), m.unwrap_or(f64::NAN))
            })
            .collect()
    };
    let full_mu = |v: &[Option<f64>]| -> Vec<(f64, f64)> {
        s.alpha1_rad
            .iter()
            .zip(v)
            .map(|(&a, m)| (a.to_degrees(), m.unwrap_or(f64::NAN)))
            .collect()
    };
    let ylim = peak * 1.05;
    let pole_x = |which: Which, zoom: bool| -> Vec<f64> {
        out.poles
            .iter()
            .filter(|p| p.which == which)
            .filter_map(|p| {
                if zoom {
                    wrap(p.alpha1_rad)
                } else {
                    Some(p.alpha1_rad)
                }
            })
            .map(f64::to_degrees)
            .collect()
    };
    let zeros = |kind: ZeroKind, zoom: bool| -> Vec<(f64, f64)> {
        out.zeros
            .iter()
            .filter(|z| z.kind == kind)
            .filter_map(|z| {
                if zoom {
                    wrap(z.alpha1_rad)
                } else {
                    Some(z.alpha1_rad)
                }
            })
            .map(|x| (x.to_degrees(), 0.0))
            .collect()
    };
    // The peak, signed as the coefficient that attains it.
    let ct = pair.contact(peak_at);
    let peak_pt = [ct.mu1, ct.mu2]
        .into_iter()
        .flatten()
        .min_by(|a, b| (a.abs() - peak).abs().total_cmp(&(b.abs() - peak).abs()))
        .unwrap_or(peak);
    let panel = |zoom: bool| {
        let mut series = vec![
            Series::line(
                "µ1",
                if zoom {
                    zoom_mu(Which::Mu1)
                } else {
                    full_mu(&s.mu1)
                },
            ),
            Series::line(
                "µ2",
                if zoom {
                    zoom_mu(Which::Mu2)
                } else {
                    full_mu(&s.mu2)
                },
            ),
            Series::line(
                "poles of µ1",
                verticals(&pole_x(Which::Mu1, zoom), -ylim, ylim),
            ),
            Series::line(
                "poles of µ2",
                verticals(&pole_x(Which::Mu2, zoom), -ylim, ylim),
            ),
            Series::points("µ = 0 (K = P)", zeros(ZeroKind::PitchPoint, zoom)),
            Series::marker(
                format!("peak |µ| = {peak:.4}"),
                [peak_at]
                    .into_iter()
                    .filter_map(|x| if zoom { wrap(x) } else { Some(x) })
                    .map(|x| (x.to_degrees(), peak_pt))
                    .collect(),
            ),
            Series::points("0/0 cusp, left out", zeros(ZeroKind::Indeterminate, zoom)),
        ];
        series.retain(|s| s.points.iter().any(|p| p.0.is_finite() && p.1.is_finite()));
        Panel {
            title: if zoom {
                "zoom: two arches around the peak".into()
            } else {
                format!(
                    "{}: µ1, µ2 (pole windows ±{:.3}° left out)",
                    scene.name,
                    w.to_degrees()
                )
            },
            x_label: "α1, angle of gear 1 (deg)".into(),
            y_label: "sliding coefficient µ (–)".into(),
            series,
            equal_aspect: false,
        }
    };
    let svg = plot::panels(&[panel(false), panel(true)], 640, 480)?;
    Ok(svg)
}

/// The eccentricity sweep: ratio variation, peak |µ|, gear 2's curvature.
fn sweep_plot(scene: &Scene, g: &GearScene, out: &Outcome) -> Result<String, PlotError> {
    let mm = 1e3;
    let e_star = out.design.eccentricity_m * mm;
    let xs = |f: &dyn Fn(&sg::SweepRow) -> f64, feasible: Option<bool>| -> Vec<(f64, f64)> {
        out.sweep
            .iter()
            .filter(|s| feasible.is_none_or(|f| s.feasible == f))
            .map(|s| (s.eccentricity_m * mm, f(s)))
            .collect()
    };
    let mut var = vec![
        Series::line("i12max/i12min", xs(&|s| s.ratio_variation, None)),
        Series::points("feasible", xs(&|s| s.ratio_variation, Some(true))),
        Series::marker(
            format!("design e = {e_star:.3} mm"),
            vec![(e_star, out.objectives.ratio_variation)],
        ),
    ];
    var.retain(|s| !s.points.is_empty());
    let (e0, e1) = g.eccentricity.bounds();
    let mut mu = vec![
        Series::line(
            "peak |µ| on working window",
            xs(&|s| s.peak_sliding_coefficient, None),
        ),
        Series::marker(
            "design",
            vec![(e_star, out.objectives.peak_sliding_coefficient)],
        ),
    ];
    if let Some(lim) = g.max_sliding_coefficient {
        mu.push(Series::line(
            format!("limit {lim}"),
            vec![(e0 * mm, lim), (e1 * mm, lim)],
        ));
    }
    let curv = vec![
        Series::line(
            "min curvature of gear 2 × R",
            xs(&|s| s.min_gear2_curvature_per_m * g.pitch_radius, None),
        ),
        Series::line("convexity limit 0", vec![(e0 * mm, 0.0), (e1 * mm, 0.0)]),
        Series::marker(
            "design",
            vec![(
                e_star,
                out.objectives.min_gear2_curvature_per_m * g.pitch_radius,
            )],
        ),
    ];
    let mut psi = vec![
        Series::line(
            "pitch pressure angle asin(e/R)",
            xs(&|s| s.max_pitch_pressure_angle_rad.to_degrees(), None),
        ),
        Series::marker(
            "design",
            vec![(
                e_star,
                out.objectives.max_pitch_pressure_angle_rad.to_degrees(),
            )],
        ),
    ];
    if let Some(lim) = g.max_pressure_angle {
        psi.push(Series::line(
            format!("limit {:.1}°", lim.to_degrees()),
            vec![(e0 * mm, lim.to_degrees()), (e1 * mm, lim.to_degrees())],
        ));
    }
    let p = |title: String, y: &str, series| Panel {
        title,
        x_label: "eccentricity e (mm)".into(),
        y_label: y.into(),
        series,
        equal_aspect: false,
    };
    let svg = plot::panels(
        &[
            p(
                format!("{}: speed-ratio variation", scene.name),
                "i12max/i12min (–)",
                var,
            ),
            p("peak sliding coefficient".into(), "peak |µ| (–)", mu),
            p("convexity of gear 2".into(), "κmin·R (–)", curv),
            p("pitch pressure angle".into(), "max |ψ| (deg)", psi),
        ],
        480,
        420,
    )?;
    Ok(svg)
}

fn num(v: f64) -> String {
    if v.is_finite() {
        format!("{v:e}")
    } else {
        String::new()
    }
}

/// CSV tables: the α1 series, both pitch curves, and the sweep (design scenes).
fn tables(out: &Outcome) -> Vec<Table> {
    let s = &out.series;
    let mut csv = String::from(
        "alpha1_rad,i12,mu1,mu2,sliding_velocity_m_per_s,pressure_angle_rad,contact_x_m,contact_y_m\n",
    );
    for k in 0..s.alpha1_rad.len() {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{}",
            num(s.alpha1_rad[k]),
            num(s.i12[k]),
            s.mu1[k].map(num).unwrap_or_default(),
            s.mu2[k].map(num).unwrap_or_default(),
            num(s.sliding_velocity_m_per_s[k]),
            num(s.pressure_angle_rad[k]),
            num(s.contact_point_m[k][0]),
            num(s.contact_point_m[k][1]),
        );
    }
    let mut t = vec![Table {
        suffix: "series".into(),
        caption: "α1 series over one turn of gear 1 (µ empty inside pole windows)".into(),
        csv,
    }];
    let pc = &out.pitch_curves;
    let mut csv = String::from("gear,x_m,y_m\n");
    for (name, pts) in [("1", &pc.gear1_m), ("2", &pc.gear2_m)] {
        for p in pts.iter() {
            let _ = writeln!(csv, "{name},{},{}", num(p[0]), num(p[1]));
        }
    }
    t.push(Table {
        suffix: "pitch-curves".into(),
        caption: "Pitch curves at α1 = 0 (O1 at the origin, O2 on +x)".into(),
        csv,
    });
    let mut csv = String::from("alpha1_rad,which,arch,phi_rad,error_rad\n");
    for p in &out.poles {
        let _ = writeln!(
            csv,
            "{},{},{},{},{}",
            num(p.alpha1_rad),
            match p.which {
                Which::Mu1 => "mu1",
                Which::Mu2 => "mu2",
            },
            p.arch,
            num(p.phi_rad),
            num(p.error_rad)
        );
    }
    t.push(Table {
        suffix: "poles".into(),
        caption: "Poles of µ1 and µ2 over one turn of gear 1".into(),
        csv,
    });
    if !out.sweep.is_empty() {
        let mut csv = String::from("eccentricity_m,center_distance_m,ratio_min,ratio_max,ratio_variation,peak_sliding_coefficient,min_gear2_curvature_per_m,max_pitch_pressure_angle_rad,feasible\n");
        for r in &out.sweep {
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{},{},{},{}",
                num(r.eccentricity_m),
                num(r.center_distance_m),
                num(r.ratio_min),
                num(r.ratio_max),
                num(r.ratio_variation),
                num(r.peak_sliding_coefficient),
                num(r.min_gear2_curvature_per_m),
                num(r.max_pitch_pressure_angle_rad),
                r.feasible
            );
        }
        t.push(Table {
            suffix: "sweep".into(),
            caption: "Design sweep over the eccentricity".into(),
            csv,
        });
    }
    t
}

/// The pitch curves' drawing (`<name>-drawing.dxf`/`.svg`) at α1 = 0: gear 1's pitch circle
/// (radius R, centre C at e from its pivot O1), gear 2's pitch curve about O2, with the centre
/// distance a = |O1O2|, R and e dimensioned (the tooth outlines are not computed as curves).
fn pitch_drawing(r: &mut SolveResult, name: &str, out: &Outcome) {
    let pc = &out.pitch_curves;
    if pc.gear2_m.is_empty() {
        return;
    }
    let p2 = |p: [f64; 2]| P2::new(p[0], p[1]);
    let (o1, o2) = (p2(pc.center1_m), p2(pc.center2_m));
    let (big_r, e) = (out.design.pitch_radius_m, out.design.eccentricity_m);
    let gear2: Vec<P2> = pc.gear2_m.iter().map(|p| p2(*p)).collect();
    let name = name.to_string();
    r.drawings
        .push(Sheet::new("drawing", "pitch curves", move || {
            let c = o1 + P2::new(e, 0.0);
            let mut d = Drawing::new(format!("{name}: pitch curves at α1 = 0"));
            d.mark(o1).mark(o2).mark(c).line(Layer::Centre, o1, o2);
            d.circle(Layer::Outline, c, big_r);
            d.polyline(Layer::Outline, gear2.clone(), true);
            d.linear(o1, o2, -1.3 * big_r, "a");
            d.radius(c, big_r, 0.4 * std::f64::consts::PI, "R");
            if e > 0.0 {
                d.linear(o1, c, -0.25 * big_r, "e");
            }
            d.label(o1 + P2::new(0.0, 0.12 * big_r), "O1");
            d.label(o2 + P2::new(0.0, 0.12 * big_r), "O2");
            d.note("gear 1: pitch circle of radius R about C, pivot O1 at the eccentricity e");
            d.note(format!(
                "gear 2: pitch curve ({} points) about its pivot O2; dimensions in mm",
                gear2.len()
            ));
            Ok(d)
        }));
}
