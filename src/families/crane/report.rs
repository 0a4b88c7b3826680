//! The crane's documents: the tables, plots and drawings of a solved scene, drawn from its
//! solution and the result's numbers, calling no solver; the driver makes them only when a
//! result's files are asked for (`SolveResult::draw`, `complete`). The numbers themselves are
//! `numbers.rs`'.

use super::file::*;
use super::motion::CounterweightMotion;
use super::solve::{Analyses, Solution};
use crate::families::crane::balance::{self, CounterweightPath};
use crate::families::crane::lever::boom_point_at;
use crate::families::crane::model::{synthesize, Boom, Guide, HoistRope, Level};
use crate::families::crane::synth::{self as cr, Outcome, TiePinLimit};
use crate::families::family::Scene;
use crate::geom::P2;
use crate::report::drawing::{Drawing, Layer, Sheet};
use crate::report::plot::{self, Grid, Panel, PlotError, Series};
use crate::report::{Plot, SolveResult, Table};
use serde_json::json;

/// The tables, plots and drawings of a solved scene, in the order the report lists them: the
/// path, the balance, the drawing (the landscape goes before them: [`analysis_documents`]).
pub fn documents(scene: &Scene, s: &CraneProblem, sol: &Solution, r: &mut SolveResult) {
    let out = &sol.out;
    let rope = s.scene.balance.as_ref().and_then(|b| b.rope);
    if !out.path.is_empty() {
        let load = rope.map(|r| load_heights(&r, &out.path));
        let mut csv = String::from("phi_rad,head_x_m,head_y_m,tail_x_m,tail_y_m");
        csv += if load.is_some() { ",load_y_m\n" } else { "\n" };
        for (i, ((phi, c), e)) in out
            .path_phi_rad
            .iter()
            .zip(&out.path)
            .zip(&out.tail_path)
            .enumerate()
        {
            csv += &format!(
                "{phi:.12e},{:.12e},{:.12e},{:.12e},{:.12e}",
                c[0], c[1], e[0], e[1]
            );
            csv += &match &load {
                Some(y) => format!(",{:.12e}\n", y[i]),
                None => "\n".into(),
            };
        }
        r.tables.push(Table {
            suffix: "path".into(),
            caption: "Jib-head and jib-tail paths over the luffing range".into(),
            csv,
        });
        let (scene, out) = (scene.clone(), out.clone());
        r.plots.push(Plot::of_panels(
            "path",
            "Jib-head path over the luffing range and its height against the boom angle",
            640,
            520,
            move || path_plot(&scene, &out, rope),
        ));
    }
    if let Some(bal) = sol.balance() {
        balance_documents(r, scene, s, bal);
    }
    // A counterweight on the boom is drawn on its lever from A; a hung or lever one from its
    // path (`balance.counterweight_path`), at both reaches; all three move in the motion view.
    let moving = counterweight_motion(s, sol);
    let cw = match moving {
        Some(CounterweightMotion::Boom { u, m }) => Some((u, m)),
        _ => None,
    };
    let other = sol.balance().and_then(|b| {
        let m = b.counterweight.as_ref()?.mass_kg;
        b.counterweight_path.clone().map(|p| (p, m))
    });
    crane_drawing(r, &scene.name, out, cw, other);
    r.motion = super::motion::motion(s, out, moving).and_then(|m| serde_json::to_value(m).ok());
}

/// The designed counterweight as the motion view moves it, by its kind.
fn counterweight_motion(s: &CraneProblem, sol: &Solution) -> Option<CounterweightMotion> {
    let b = sol.balance()?;
    let c = b.counterweight.as_ref()?;
    let (u, m) = (c.static_moment_kgm, c.mass_kg);
    Some(match s.scene.balance?.counterweight?.kind {
        balance::CounterweightKind::Boom => CounterweightMotion::Boom { u, m },
        balance::CounterweightKind::Hanging { hang_length_m } => CounterweightMotion::Hanging {
            u,
            m,
            hang: hang_length_m,
        },
        balance::CounterweightKind::Lever(_) => CounterweightMotion::Lever {
            u,
            m,
            lever: b.counterweight_path.as_ref()?.lever?,
        },
    })
}

/// The load's height along the head path `path` on the inclined `rope`, for a rope whose load
/// hangs at the jib head at maximum reach (the path's first point):
/// y_C + (|S − C| − |S − C1|)/n (m above A; the hook's real height is lower by the hanging
/// length there, a constant).
fn load_heights(rope: &HoistRope, path: &[[f64; 2]]) -> Vec<f64> {
    let c = |p: &[f64; 2]| P2::new(p[0], p[1]);
    let y1 = path.first().map_or(0.0, |p| rope.load_height(c(p)) - p[1]);
    path.iter().map(|p| rope.load_height(c(p)) - y1).collect()
}

/// The Δh landscape (an analysis only the files carry): its section `extra.landscape`, its
/// table and plot, first among the tables and plots.
pub fn analysis_documents(
    scene: &Scene,
    s: &CraneProblem,
    sol: &Solution,
    landscape: &Analyses,
    r: &mut SolveResult,
) {
    let Some(l) = landscape.clone() else { return };
    r.extra
        .insert("landscape".into(), landscape_summary(&scene.name, &l));
    r.tables.insert(
        0,
        Table {
            suffix: "landscape".into(),
            caption: "Δh over the (k1, k2) grid with the tie-pin violation".into(),
            csv: l.to_csv(),
        },
    );
    let (scene, cs, out) = (scene.clone(), s.scene.clone(), sol.out.clone());
    r.plots.insert(0, Plot::new(
        "landscape",
        "Δh over (k1, k2) (angles and L_c at the reported design; grey: no linkage or branch defect), tie-pin limit boundary and the design",
        move || landscape_plot(&scene, &cs, &out, &l),
    ));
}

/// The balance's table (`<name>-balance.csv`) and plot.
fn balance_documents(r: &mut SolveResult, scene: &Scene, s: &CraneProblem, bal: &balance::Balance) {
    let bs = s
        .scene
        .balance
        .as_ref()
        .expect("a balance only for a scene with one");
    // With a luffing time, the drive power T·φ̇ at the constant boom speed φ̇ = Δφ/t_l.
    let speed = match (s.luffing_time, bal.series.first(), bal.series.last()) {
        (Some(t), Some(a), Some(b)) => Some((b.phi - a.phi) / t),
        _ => None,
    };
    let mut csv = String::from("phi_rad,reach_m,drive_torque_empty_unbalanced_nm,drive_torque_loaded_unbalanced_nm,drive_torque_empty_nm,drive_torque_loaded_nm,tie_tension_n,boom_compression_n,boom_shear_n,pin_a_n,pin_b_n,pin_d_n,pin_e_n,head_force_n,head_force_angle_rad");
    if speed.is_some() {
        csv += ",drive_power_empty_w,drive_power_loaded_w";
    }
    csv += "\n";
    for p in &bal.series {
        let s = &p.loaded;
        csv += &format!(
            "{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e}",
            p.phi,
            p.reach,
            p.bare[0],
            p.bare[1],
            p.balanced[0],
            p.balanced[1],
            s.tie_tension,
            s.boom_compression,
            s.boom_shear,
            s.pin_a.norm(),
            s.pin_b.norm(),
            s.pin_d.norm(),
            s.pin_e.norm(),
            s.head_force,
            s.head_force_angle
        );
        if let Some(w) = speed {
            csv += &format!(",{:.12e},{:.12e}", p.balanced[0] * w, p.balanced[1] * w);
        }
        csv += "\n";
    }
    r.tables.push(Table {
        suffix: "balance".into(),
        caption: format!(
            "Luffing drive torque (empty and loaded, without and with the counterweight){} and the loaded case's member forces over the luffing range",
            if speed.is_some() {
                ", the drive power at the luffing speed (with the counterweight)"
            } else {
                ""
            }
        ),
        csv,
    });
    let (name, series, loaded) = (
        scene.name.clone(),
        bal.series.clone(),
        bs.load_mass.is_some(),
    );
    let designed = bal.counterweight.is_some();
    r.plots.push(Plot::of_panels(
        "balance",
        "Luffing drive torque and member forces against the reach",
        640,
        420,
        move || balance_plot(&name, &series, loaded, designed),
    ));
}

/// Drive torque (kN·m) and forces (kN) against the reach (m).
fn balance_plot(
    name: &str,
    series: &[balance::Sample],
    loaded: bool,
    designed: bool,
) -> Result<Vec<Panel>, PlotError> {
    let pts = |f: &dyn Fn(&balance::Sample) -> f64| -> Vec<(f64, f64)> {
        series.iter().map(|p| (p.reach, f(p) / 1e3)).collect()
    };
    let mut torque = vec![Series::line("empty, no counterweight", pts(&|p| p.bare[0]))];
    if loaded {
        torque.push(Series::line(
            "loaded, no counterweight",
            pts(&|p| p.bare[1]),
        ));
    }
    if designed {
        torque.push(Series::line(
            "empty, with the counterweight",
            pts(&|p| p.balanced[0]),
        ));
        if loaded {
            torque.push(Series::line(
                "loaded, with the counterweight",
                pts(&|p| p.balanced[1]),
            ));
        }
    }
    let case = if loaded { "loaded" } else { "empty" };
    let forces = vec![
        Series::line("tie tension K", pts(&|p| p.loaded.tie_tension)),
        Series::line("boom compression at D", pts(&|p| p.loaded.boom_compression)),
        Series::line("boom-foot pin load |F_A|", pts(&|p| p.loaded.pin_a.norm())),
        Series::line(
            "jib's force on the boom head N",
            pts(&|p| p.loaded.head_force),
        ),
    ];
    Ok(vec![
        Panel {
            title: format!("{name}: luffing drive torque"),
            x_label: "reach from the slewing axis (m)".into(),
            y_label: "drive torque about A (kN·m, + raises the boom)".into(),
            series: torque,
            equal_aspect: false,
        },
        Panel {
            title: format!(
                "Member forces ({case}{})",
                if designed {
                    ", with the counterweight"
                } else {
                    ""
                }
            ),
            x_label: "reach from the slewing axis (m)".into(),
            y_label: "force (kN)".into(),
            series: forces,
            equal_aspect: false,
        },
    ])
}

/// Compact facts of the landscape (the grid itself is in the CSV).
fn landscape_summary(name: &str, l: &cr::Landscape) -> serde_json::Value {
    let mut best: Option<(f64, f64, f64)> = None;
    let mut no_linkage = 0usize;
    for (j, row) in l.delta_h_m.iter().enumerate() {
        for (i, v) in row.iter().enumerate() {
            match (v, l.tie_pin_violation_m[j][i]) {
                (Some(dh), Some(viol)) if viol <= 0.0 && best.is_none_or(|b| *dh < b.0) => {
                    best = Some((*dh, l.k1[i], l.k2[j]));
                }
                (None, _) => no_linkage += 1,
                _ => {}
            }
        }
    }
    json!({
        "k1_range": [l.k1[0], l.k1[l.k1.len() - 1]],
        "k2_range": [l.k2[0], l.k2[l.k2.len() - 1]],
        "k1_points": l.k1.len(),
        "k2_points": l.k2.len(),
        "cells_without_linkage": no_linkage,
        "grid_min_delta_h_m": best.map(|b| b.0),
        "grid_min_at": best.map(|b| [b.1, b.2]),
        "csv": format!("{name}-landscape.csv"),
    })
}

/// Signed tie-pin margin (m): the largest of |AB| − R, lo − x, x − hi, …; negative inside.
fn signed_margin(t: &TiePinLimit, b: P2) -> f64 {
    let mut v = f64::NEG_INFINITY;
    if let Some(r) = t.max_distance {
        v = v.max(b.norm() - r);
    }
    if let Some([lo, hi]) = t.x_range {
        v = v.max(lo - b.x).max(b.x - hi);
    }
    if let Some([lo, hi]) = t.y_range {
        v = v.max(lo - b.y).max(b.y - hi);
    }
    v
}

/// Zero contour of `f` on the grid (marching squares, linear interpolation), as line
/// segments separated by NaN points.
fn zero_contour(x: &[f64], y: &[f64], f: &[Vec<f64>]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for j in 0..y.len().saturating_sub(1) {
        for i in 0..x.len().saturating_sub(1) {
            let c = [
                (x[i], y[j], f[j][i]),
                (x[i + 1], y[j], f[j][i + 1]),
                (x[i + 1], y[j + 1], f[j + 1][i + 1]),
                (x[i], y[j + 1], f[j + 1][i]),
            ];
            if c.iter().any(|p| !p.2.is_finite()) {
                continue;
            }
            let mut pts = Vec::new();
            for k in 0..4 {
                let (a, b) = (c[k], c[(k + 1) % 4]);
                if (a.2 < 0.0) != (b.2 < 0.0) {
                    let t = a.2 / (a.2 - b.2);
                    pts.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
                }
            }
            for pair in pts.chunks_exact(2) {
                out.extend_from_slice(pair);
                out.push((f64::NAN, f64::NAN));
            }
        }
    }
    out
}

fn landscape_plot(
    scene: &Scene,
    cs: &cr::CraneScene,
    out: &Outcome,
    l: &cr::Landscape,
) -> Result<String, PlotError> {
    let values: Vec<Vec<f64>> = l
        .delta_h_m
        .iter()
        .map(|row| {
            row.iter()
                .map(|v| v.filter(|d| *d > 0.0).map_or(f64::NAN, f64::log10))
                .collect()
        })
        .collect();
    let mut series = Vec::new();
    let bounded = cs.tie_pin != TiePinLimit::default();
    if bounded {
        // The tie pin B of every grid point (cheap: step 2 only, no path), at the reported
        // angles and boom length, for the signed margin whose zero contour is the boundary.
        let v = &out.design.vars;
        let boom = Boom::levelled(
            out.design.boom_length_m.unwrap_or(f64::NAN),
            v.angles(),
            cs.level,
        )
        .map_err(PlotError::data)?;
        let margin: Vec<Vec<f64>> =
            l.k2.iter()
                .map(|&k2| {
                    l.k1.iter()
                        .map(|&k1| match synthesize(&boom, k1, k2).map(|s| s.guide) {
                            Ok(Guide::Circle { centre, .. }) => signed_margin(&cs.tie_pin, centre),
                            Ok(Guide::Line { .. }) => f64::INFINITY,
                            Err(_) => f64::NAN,
                        })
                        .collect()
                })
                .collect();
        series.push(Series::line(
            "tie-pin limit boundary (white dots: B outside)",
            zero_contour(&l.k1, &l.k2, &margin),
        ));
        // Every fourth grid point with B outside the limit: shows the infeasible side
        // without hiding the colours.
        let mut dots = Vec::new();
        for (j, row) in l.tie_pin_violation_m.iter().enumerate().step_by(4) {
            for (i, v) in row.iter().enumerate().step_by(4) {
                if v.is_some_and(|v| v > 0.0) {
                    dots.extend([(l.k1[i], l.k2[j]), (f64::NAN, f64::NAN)]);
                }
            }
        }
        series.push(Series::points("grid points with B outside the limit", dots));
    } else {
        series.push(Series::line("no tie-pin limit in this scene", vec![]));
        series.push(Series::points("no grid point outside a limit", vec![]));
    }
    let ends: Vec<(f64, f64)> = out
        .basins
        .iter()
        .filter_map(|b| Some((*b.end.get("k1")?, *b.end.get("k2")?)))
        .collect();
    series.push(Series::marker(
        if ends.is_empty() {
            "local-search ends: none (k1, k2 not searched)"
        } else {
            "ends of the local searches (each at its own angles)"
        },
        ends,
    ));
    let (k1, k2) = (l.optimum[0], l.optimum[1]);
    let design_name = if cs.k1.fixed().is_some() && cs.k2.fixed().is_some() {
        format!("given design (k1 {k1:.3}, k2 {k2:.3})")
    } else {
        format!("optimum (k1 {k1:.3}, k2 {k2:.3})")
    };
    series.push(Series::marker(design_name, vec![(k1, k2)]));
    let svg = plot::heat_map(
        &Panel {
            title: format!(
                "{}: log10({} / 1 m) over (k1, k2) (−1: 0.1 m, 0: 1 m)",
                scene.name,
                match cs.level {
                    Level::Head => "Δh",
                    Level::Load(_) => "the load's Δh",
                }
            ),
            x_label: "k1 = C1C2/C1C3 (–)".into(),
            y_label: "k2 = a/L_v (–)".into(),
            series,
            equal_aspect: false,
        },
        &Grid {
            x: l.k1.clone(),
            y: l.k2.clone(),
            values,
        },
        None,
        760,
        620,
    )?;
    Ok(svg)
}

fn path_plot(
    scene: &Scene,
    out: &Outcome,
    rope: Option<HoistRope>,
) -> Result<Vec<Panel>, PlotError> {
    let nan = (f64::NAN, f64::NAN);
    let head: Vec<(f64, f64)> = out.path.iter().map(|p| (p[0], p[1])).collect();
    let tail: Vec<(f64, f64)> = out.tail_path.iter().map(|p| (p[0], p[1])).collect();
    let load = rope.map(|r| load_heights(&r, &out.path));
    let mut series = vec![
        Series::line("jib-head path C", head.clone()),
        Series::line("jib-tail path E", tail),
    ];
    const LOAD: &str = "load on the inclined rope (hung at C at max reach)";
    if let Some(y) = &load {
        let pts = out.path.iter().zip(y).map(|(p, y)| (p[0], *y)).collect();
        series.push(Series::line(LOAD, pts));
    }
    if let Some(p) = &out.positions {
        // The linkage at max reach (1) and min reach (3): boom A–D, jib E–D–C, tie B–E.
        for (i, name) in [(0, "linkage at max reach"), (2, "linkage at min reach")] {
            let mut pts = vec![(0.0, 0.0), (p.d[i][0], p.d[i][1]), nan];
            pts.extend([(p.e[i][0], p.e[i][1]), (p.c[i][0], p.c[i][1]), nan]);
            if let Some(b) = p.tie_pin {
                pts.extend([(b[0], b[1]), (p.e[i][0], p.e[i][1])]);
            }
            series.push(Series::line(name, pts));
        }
        series.push(Series::marker(
            "design positions C1, C2, C3",
            p.c.iter().map(|c| (c[0], c[1])).collect(),
        ));
        let mut pins = vec![(0.0, 0.0)];
        if let Some(b) = p.tie_pin {
            pins.push((b[0], b[1]));
        }
        series.push(Series::marker("boom foot A, tie pin B", pins));
    }
    let height: Vec<(f64, f64)> = out
        .path_phi_rad
        .iter()
        .zip(&out.path)
        .map(|(phi, c)| (phi.to_degrees(), c[1]))
        .collect();
    let d = &out.derived;
    let mut hs = vec![Series::line("head height y_C", height)];
    if let Some(y) = &load {
        let pts = out.path_phi_rad.iter().zip(y);
        hs.push(Series::line(
            LOAD,
            pts.map(|(phi, y)| (phi.to_degrees(), *y)).collect(),
        ));
    }
    if let (Some(a), Some(ya), Some(b), Some(yb)) = (
        d.phi_at_head_max_rad,
        d.head_y_max_m,
        d.phi_at_head_min_rad,
        d.head_y_min_m,
    ) {
        hs.push(Series::marker(
            "refined max and min",
            vec![(a.to_degrees(), ya), (b.to_degrees(), yb)],
        ));
    }
    if let Some(p) = &out.positions {
        hs.push(Series::marker(
            "design positions",
            (0..3)
                .map(|i| (p.phi_rad[i].to_degrees(), p.c[i][1]))
                .collect(),
        ));
    }
    let dh = out
        .objectives
        .delta_h_m
        .map_or("Δh not available".to_string(), |d| {
            format!("Δh = {d:.4} m")
        });
    let dh = match out.objectives.load_delta_h_m {
        Some(l) => format!("{dh}, the load's {l:.4} m"),
        None => dh,
    };
    Ok(vec![
        Panel {
            title: format!("{}: jib-head path ({dh})", scene.name),
            x_label: "x from the boom foot A (m; reach is −x)".into(),
            y_label: "y above A (m)".into(),
            series,
            equal_aspect: true,
        },
        Panel {
            title: format!("Jib-head height over the luffing range ({dh})"),
            x_label: "boom angle φ (deg)".into(),
            y_label: "jib-head height y_C above A (m)".into(),
            series: hs,
            equal_aspect: false,
        },
    ])
}

/// A hung counterweight (its suspension point on the boom's extension, the hanger, the
/// weight) or a lever one (the lever from its pivot O through the rod's lever pin, the rod
/// to the boom, the weight on the lever) at both reaches, from its path.
fn hung_or_lever(d: &mut Drawing, path: &CounterweightPath, m: f64, pin: f64) {
    let p2 = |p: &[f64; 2]| P2::new(p[0], p[1]);
    let a = P2::zeros();
    for i in 0..2 {
        let c = p2(&path.centroid_m[i]);
        if let Some(s) = &path.suspension_point_m {
            let s = p2(&s[i]);
            d.line(Layer::Outline, a, s);
            d.line(Layer::Outline, s, c);
            d.circle(Layer::Outline, s, pin);
        }
        if let (Some(lk), Some(pins)) = (&path.lever, &path.rod_pins_m) {
            let (l, k) = (p2(&pins[i][0]), p2(&pins[i][1]));
            d.line(Layer::Outline, lk.pivot, l);
            d.line(Layer::Outline, lk.pivot, c);
            d.line(Layer::Outline, l, k);
            for j in [l, k] {
                d.circle(Layer::Outline, j, pin);
            }
        }
        d.circle(Layer::Outline, c, 3.0 * pin);
    }
    if let Some(lk) = &path.lever {
        d.mark(lk.pivot)
            .label(lk.pivot + P2::new(0.0, 2.0 * pin), "O");
    }
    d.label(
        p2(&path.centroid_m[0]) - P2::new(0.0, 5.0 * pin),
        format!("counterweight {:.1} t ({})", m / 1e3, path.kind),
    );
}

/// The linkage's drawing (`<name>-drawing.dxf`/`.svg`), where the design has a geometry: the
/// four-bar at maximum and minimum reach (boom A–D, jib E–D–C, tie B–E; A at the origin), the
/// jib-head and jib-tail paths over the luffing range, with the boom L_c = |AD|, the jib head
/// L_v = |DC|, the jib tail a = |DE| and the tie b = |BE| dimensioned at maximum reach.
fn crane_drawing(
    r: &mut SolveResult,
    name: &str,
    out: &Outcome,
    cw: Option<([f64; 2], f64)>,
    other: Option<(CounterweightPath, f64)>,
) {
    let Some(pos) = out.positions.clone() else {
        return;
    };
    let p2 = |p: &[f64; 2]| P2::new(p[0], p[1]);
    let head: Vec<P2> = out.path.iter().map(p2).collect();
    let tail: Vec<P2> = out.tail_path.iter().map(p2).collect();
    let name = name.to_string();
    r.drawings.push(Sheet::new(
        "drawing",
        "linkage at maximum and minimum reach",
        move || {
            let a = P2::zeros();
            let b = pos.tie_pin.as_ref().map(p2);
            let boom = (p2(&pos.d[0]) - a).norm();
            let pin = 0.012 * boom;
            let mut d = Drawing::new(format!(
                "{name}: luffing linkage at maximum and minimum reach"
            ));
            d.polyline(Layer::Path, head.clone(), false);
            d.polyline(Layer::Path, tail.clone(), false);
            d.mark(a);
            if let Some(b) = b {
                d.mark(b).label(b + P2::new(0.0, 2.0 * pin), "B");
            }
            d.label(a - P2::new(0.0, 2.5 * pin), "A");
            for (i, words) in [(0, "max reach"), (2, "min reach")] {
                let (dd, e, c) = (p2(&pos.d[i]), p2(&pos.e[i]), p2(&pos.c[i]));
                d.line(Layer::Outline, a, dd);
                d.polyline(Layer::Outline, vec![e, dd, c], false);
                if let Some(b) = b {
                    d.line(Layer::Outline, b, e);
                }
                for j in [dd, e, c] {
                    d.circle(Layer::Outline, j, pin);
                }
                d.label(c - P2::new(0.0, 3.0 * pin), format!("C ({words})"));
            }
            // The boom counterweight's centroid at both reaches, on its lever from A.
            if let Some((u, m)) = cw.filter(|&(_, m)| m > 0.0) {
                let at = |i: usize| boom_point_at(u, pos.phi_rad[i]) / m;
                for i in [0, 2] {
                    d.line(Layer::Outline, a, at(i));
                    d.circle(Layer::Outline, at(i), 3.0 * pin);
                }
                let p = at(0);
                d.label(
                    p - P2::new(0.0, 5.0 * pin),
                    format!("counterweight {:.1} t", m / 1e3),
                );
            }
            if let Some((path, m)) = other.as_ref().filter(|o| o.1 > 0.0) {
                hung_or_lever(&mut d, path, *m, pin);
            }
            let (dd, e, c) = (p2(&pos.d[0]), p2(&pos.e[0]), p2(&pos.c[0]));
            d.linear(a, dd, 0.06 * boom, "L_c");
            d.linear(dd, c, 0.06 * boom, "L_v");
            d.linear(dd, e, 0.06 * boom, "a");
            if let Some(b) = b {
                d.linear(b, e, -0.06 * boom, "b");
            }
            d.note("A: boom foot (origin); B: tie pin; D: boom head; C: jib head; E: jib tail");
            d.note(
                "blue: the jib-head and jib-tail paths over the luffing range; dimensions in mm",
            );
            Ok(d)
        },
    ));
}
