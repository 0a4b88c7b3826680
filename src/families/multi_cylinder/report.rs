//! The multi-cylinder's documents: the tables (cylinders, harmonics, front), the plots (force
//! and couple over a turn, bare and designed; the force's locus) and the drawing of the crank
//! layout (the throws and cylinder axes seen along the shaft, the planes along it), drawn
//! from the solution, calling no solver.

use super::file::MultiCylinderProblem;
use super::solve::{value_at, Analyses, Fields, Solution, COUPLE, FORCE};
use crate::families::family::Scene;
use crate::geom::{rot, P2};
use crate::report::drawing::{Drawing, Layer, Sheet};
use crate::report::plot::{Panel, PlotError, Series};
use crate::report::{Plot, SolveResult, Table};
use crate::synth::minimax::var_u;
use serde_json::json;
use std::f64::consts::TAU;
use std::sync::Arc;

/// No analyses beyond the solution's own documents.
pub fn analysis_documents(
    _: &Scene,
    _: &MultiCylinderProblem,
    _: &Solution,
    _: &Analyses,
    _: &mut SolveResult,
) {
}

/// The tables, plots, drawing and motion of a solved scene.
pub fn documents(scene: &Scene, p: &MultiCylinderProblem, sol: &Solution, r: &mut SolveResult) {
    let p = sol.scene(p);
    if let Some(rows) = r.extra.get("phases").and_then(|v| v.as_array()) {
        r.tables.push(Table::of_rows(
            "phases",
            "Every layout of the phase search, best first (its headline value and error)",
            rows,
        ));
    }
    r.tables.push(cylinders_table(p));
    if let Some(rows) = r.extra.get("harmonics").and_then(|v| v.as_array()) {
        r.tables.push(Table::of_rows(
            "harmonics",
            "Forward and backward amplitudes of the force and couple, order by order (FFT)",
            rows,
        ));
    }
    if let Some(rows) = r.extra.get("pareto").and_then(|v| v.as_array()) {
        r.tables.push(Table::of_rows(
            "pareto",
            "Least peak force for each limit on the peak couple",
            rows,
        ));
    }
    let x = sol.x(p);
    let shared = Arc::new((
        scene.name.clone(),
        p.clone(),
        x.clone(),
        sol.design.is_some(),
    ));
    let d = shared.clone();
    r.plots.push(Plot::of_panels(
        "shaking",
        "Shaking force and couple over a turn, bare and with the design",
        560,
        420,
        move || shaking_plot(&d.0, &d.1, &d.2, d.3),
    ));
    layout_drawing(r, &scene.name, p, &x);
    r.motion = serde_json::to_value(super::motion::motion(p, &x)).ok();
}

/// The `cylinders` table: each cylinder's phase, bank, outer dead centre (the crank angle φ
/// of its TDC), plane and masses.
fn cylinders_table(p: &MultiCylinderProblem) -> Table {
    let rows: Vec<serde_json::Value> = (p.layout.cylinders.iter().enumerate())
        .map(|(i, c)| {
            json!({
                "cylinder": i + 1,
                "phase_deg": c.phase.to_degrees(),
                "bank_deg": c.bank.to_degrees(),
                "tdc_deg": super::firing::tdc(c).to_degrees(),
                "position_m": c.z,
                "offset_m": c.sc.e,
                "rotating_mass_kg": c.sc.m_rot(),
                "reciprocating_mass_kg": c.sc.m_rec(),
            })
        })
        .collect();
    Table::of_rows("cylinders", "The cylinders on the shaft", &rows)
}

/// |g| of a field over a turn at the design x (N or N·m), 361 points, φ in degrees.
fn magnitude(p: &MultiCylinderProblem, which: usize, x: &[f64]) -> Vec<(f64, f64)> {
    let f = Fields { p, which };
    turn()
        .map(|phi| (phi.to_degrees(), value_at(&f, phi, x).norm()))
        .collect()
}

/// The force's tip over a turn (N, N), 361 points.
fn locus(p: &MultiCylinderProblem, x: &[f64]) -> Vec<(f64, f64)> {
    let f = Fields { p, which: FORCE };
    turn()
        .map(|phi| {
            let g = value_at(&f, phi, x);
            (g.x, g.y)
        })
        .collect()
}

/// 361 angles over a turn, both ends included.
fn turn() -> impl Iterator<Item = f64> {
    (0..=360).map(|k| TAU * k as f64 / 360.0)
}

/// |F| and |M| against φ, bare and designed; the force's locus.
fn shaking_plot(
    name: &str,
    p: &MultiCylinderProblem,
    x: &[f64],
    designed: bool,
) -> Result<Vec<Panel>, PlotError> {
    let bare = vec![0.0; x.len()];
    let mut force = vec![Series::line("|F| bare", magnitude(p, FORCE, &bare))];
    let mut couple = vec![Series::line("|M| bare", magnitude(p, COUPLE, &bare))];
    let mut tip = vec![Series::line("F bare", locus(p, &bare))];
    if designed {
        force.push(Series::line("|F| with the design", magnitude(p, FORCE, x)));
        couple.push(Series::line("|M| with the design", magnitude(p, COUPLE, x)));
        tip.push(Series::line("F with the design", locus(p, x)));
    }
    Ok(vec![
        Panel {
            title: format!("{name}: shaking force"),
            x_label: "crank angle φ (deg)".into(),
            y_label: "|F| (N)".into(),
            series: force,
            equal_aspect: false,
        },
        Panel {
            title: "couple about the two axes normal to the shaft".into(),
            x_label: "crank angle φ (deg)".into(),
            y_label: "|M| (N·m)".into(),
            series: couple,
            equal_aspect: false,
        },
        Panel {
            title: "the force's tip over a turn".into(),
            x_label: "F_x (N)".into(),
            y_label: "F_y (N)".into(),
            series: tip,
            equal_aspect: true,
        },
    ])
}

/// The crank layout at φ = 0: seen along the shaft (left: the throws, each labelled, the
/// cylinder axes, the crank-web counterweights' directions) and from the side (right: the
/// shaft along z, each throw's plane and the rotors' planes, dimensioned).
fn layout_drawing(r: &mut SolveResult, name: &str, p: &MultiCylinderProblem, x: &[f64]) {
    let (name, p, x) = (name.to_string(), p.clone(), x.to_vec());
    r.drawings.push(Sheet::new("drawing", "crank layout", move || {
        let cyl = &p.layout.cylinders;
        let rr = cyl[0].sc.r;
        let reach = cyl.iter().map(|c| c.sc.l + c.sc.r).fold(0.0, f64::max);
        let mut d = Drawing::new(format!("{name}: crank layout at φ = 0"));
        d.mark(P2::zeros()).circle(Layer::Centre, P2::zeros(), rr);
        for (i, c) in cyl.iter().enumerate() {
            let a = rot(c.phase, P2::new(rr, 0.0));
            d.line(Layer::Outline, P2::zeros(), a);
            d.label(a * 1.25, format!("{}", i + 1));
            let axis = |t: f64| rot(c.bank, P2::new(t, c.sc.e));
            d.line(Layer::Centre, axis(c.sc.l - c.sc.r), axis(reach * 1.1));
        }
        d.radius(P2::zeros(), rr, cyl[0].phase, "R");
        for (j, rot_spec) in p.rotors.iter().enumerate().filter(|(_, s)| !s.shaft) {
            let u = P2::new(x[var_u(j)], x[var_u(j) + 1]);
            if u.norm() > 0.0 {
                let tip = u / u.norm() * rot_spec.radius_max;
                d.line(Layer::Path, P2::zeros(), tip);
                d.label(tip * 1.15, format!("cw {}", j + 1));
            }
        }
        side_view(&mut d, &p, 2.5 * reach);
        d.note("left: seen along the shaft from +z (throw numbers, cylinder axes); right: the planes along the shaft");
        Ok(d)
    }));
}

/// The side view: the shaft along z (drawn along x from `x0`), each throw's plane as a
/// line of length 2R, each rotor's plane as a short mark, the planes' spacing dimensioned.
fn side_view(d: &mut Drawing, p: &MultiCylinderProblem, x0: f64) {
    let cyl = &p.layout.cylinders;
    let rr = cyl[0].sc.r;
    let zs: Vec<f64> = cyl.iter().map(|c| c.z).collect();
    let lo = zs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = zs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let at = |z: f64, y: f64| P2::new(x0 + z - lo, y);
    let span = (hi - lo).max(rr);
    d.line(
        Layer::Centre,
        at(lo - 0.2 * span, 0.0),
        at(hi + 0.2 * span, 0.0),
    );
    for (i, c) in cyl.iter().enumerate() {
        d.line(Layer::Outline, at(c.z, -rr), at(c.z, rr));
        d.label(at(c.z, 1.4 * rr), format!("{}", i + 1));
    }
    for s in &p.rotors {
        d.line(
            Layer::Path,
            at(s.rotor.z, -0.5 * rr),
            at(s.rotor.z, 0.5 * rr),
        );
    }
    let mut sorted = zs.clone();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    for w in sorted.windows(2) {
        d.linear(at(w[0], -rr), at(w[1], -rr), -0.6 * rr, "Δz");
    }
}
