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

/// The crank layout at φ = 0: seen along the shaft (left: the throws, each labelled with the
/// cylinders on it, the cylinder axes — labelled where their banks differ —, a radial's
/// master and articulated rods, the crank-web counterweights' directions), from the side
/// (right: the shaft along z, each throw's plane and the rotors' planes, dimensioned) and the
/// frame's mounts in both.
fn layout_drawing(r: &mut SolveResult, name: &str, p: &MultiCylinderProblem, x: &[f64]) {
    let (name, p, x) = (name.to_string(), p.clone(), x.to_vec());
    r.drawings.push(Sheet::new("drawing", "crank layout", move || {
        let cyl = &p.layout.cylinders;
        let rr = cyl[0].sc.r;
        let reach = cyl.iter().map(|c| c.sc.l + c.sc.r).fold(0.0, f64::max);
        let mut d = Drawing::new(format!("{name}: crank layout at φ = 0"));
        d.mark(P2::zeros()).circle(Layer::Centre, P2::zeros(), rr);
        let throws = groups(cyl.iter().map(|c| c.phase));
        for (phase, who) in &throws {
            let a = rot(*phase, P2::new(rr, 0.0));
            d.line(Layer::Outline, P2::zeros(), a);
            // One throw: the axes' labels say which cylinder is which.
            if throws.len() > 1 {
                d.label(a * 1.25, who.clone());
            }
        }
        let banks = groups(cyl.iter().map(|c| c.bank));
        for c in cyl {
            let axis = |t: f64| rot(c.bank, P2::new(t, c.sc.e));
            d.line(Layer::Centre, axis(c.sc.l - c.sc.r), axis(reach * 1.1));
        }
        if banks.len() > 1 {
            for (bank, who) in &banks {
                d.label(rot(*bank, P2::new(reach * 1.18, 0.0)), who.clone());
            }
        }
        articulated_rods(&mut d, &p);
        d.radius(P2::zeros(), rr, cyl[0].phase, "R");
        for (j, rot_spec) in p.rotors.iter().enumerate().filter(|(_, s)| !s.shaft) {
            let u = P2::new(x[var_u(j)], x[var_u(j) + 1]);
            if u.norm() > 0.0 {
                let tip = u / u.norm() * rot_spec.radius_max;
                d.line(Layer::Path, P2::zeros(), tip);
                d.label(tip * 1.15, format!("cw {}", j + 1));
            }
        }
        // The side view starts right of everything the end view holds (the mounts too).
        let right = (p.frame.iter().flat_map(|f| f.mounts.iter().map(|m| m.at[0])))
            .fold(1.25 * reach, f64::max);
        let x0 = right + 1.25 * reach;
        side_view(&mut d, &p, x0);
        mounts(&mut d, &p, x0);
        d.note("left: seen along the shaft from +z (the cylinders on each throw and axis, the crank-web counterweights); right: the planes along the shaft");
        if p.frame.is_some() {
            d.note("M1, M2, …: the frame's mounts (springs and dampers) in both views; G: its centre of mass");
        }
        Ok(d)
    }));
}

/// The side view's origin: the lowest z of anything it draws (planes, rotors, mounts, the
/// frame's centre of mass), so that it starts where it is placed.
fn side_z0(p: &MultiCylinderProblem) -> f64 {
    let frame = p
        .frame
        .iter()
        .flat_map(|f| (f.mounts.iter().map(|m| m.at[2])).chain(std::iter::once(f.centroid[2])));
    (p.layout.cylinders.iter().map(|c| c.z))
        .chain(p.rotors.iter().map(|r| r.rotor.z))
        .chain(frame)
        .fold(f64::INFINITY, f64::min)
}

/// Equal angles (to 1e-9 rad) grouped in order of first appearance, each with the cylinder
/// numbers at it (`1, 4`).
fn groups(angles: impl Iterator<Item = f64>) -> Vec<(f64, String)> {
    groups_by(angles, |a, b| {
        (a - b).rem_euclid(TAU).min((b - a).rem_euclid(TAU)) < 1e-9
    })
}

/// Values grouped by `same` in order of first appearance, each with the cylinder numbers at
/// it.
fn groups_by(
    values: impl Iterator<Item = f64>,
    same: impl Fn(f64, f64) -> bool,
) -> Vec<(f64, String)> {
    let mut out: Vec<(f64, Vec<usize>)> = Vec::new();
    for (i, a) in values.enumerate() {
        match out.iter_mut().find(|(b, _)| same(a, *b)) {
            Some((_, v)) => v.push(i + 1),
            None => out.push((a, vec![i + 1])),
        }
    }
    let text = |v: Vec<usize>| {
        (v.iter().map(usize::to_string))
            .collect::<Vec<_>>()
            .join(", ")
    };
    out.into_iter().map(|(a, v)| (a, text(v))).collect()
}

/// A radial's rods at φ = 0: each master rod from the crank pin to its piston pin, each
/// articulated rod from its knuckle pin (a small circle on the master rod) to its piston pin.
fn articulated_rods(d: &mut Drawing, p: &MultiCylinderProblem) {
    let cyl = &p.layout.cylinders;
    let pin_r = 0.08 * cyl[0].sc.r;
    let mut masters = Vec::new();
    for c in cyl {
        let Some(a) = &c.articulated else { continue };
        let Some(st) = a.state(c.sc.r, c.sc.l, c.bank, c.phase - a.master_bank) else {
            continue;
        };
        let world = |v: P2| rot(a.master_bank, v);
        let (k, b) = (world(st.k[0]), world(st.axis * st.s[0]));
        d.line(Layer::Outline, k, b)
            .circle(Layer::Outline, k, pin_r);
        d.line(Layer::Outline, world(st.c), k);
        let key = (a.master_bank, c.phase);
        if !masters.contains(&key) {
            masters.push(key);
            d.line(Layer::Outline, world(st.c), world(P2::new(st.master, 0.0)));
        }
    }
}

/// The frame's mounts and centre of mass in both views: a small square at each mount's (x, y)
/// seen along the shaft and at its (z, y) in the side view (drawn from `x0` as there), the
/// mounts at one point of a view labelled together.
fn mounts(d: &mut Drawing, p: &MultiCylinderProblem, x0: f64) {
    let Some(f) = &p.frame else { return };
    let rr = p.layout.cylinders[0].sc.r;
    let z0 = side_z0(p);
    let side = |z: f64, y: f64| P2::new(x0 + z - z0, y);
    let h = 0.15 * rr;
    let views: [Vec<P2>; 2] = [
        f.mounts.iter().map(|m| P2::new(m.at[0], m.at[1])).collect(),
        f.mounts.iter().map(|m| side(m.at[2], m.at[1])).collect(),
    ];
    for points in views {
        let mut done: Vec<P2> = Vec::new();
        for at in &points {
            if done.iter().any(|q| (q - at).norm() < 1e-9) {
                continue;
            }
            done.push(*at);
            let corners = [(-h, -h), (h, -h), (h, h), (-h, h)].map(|(a, b)| at + P2::new(a, b));
            d.polyline(Layer::Outline, corners.to_vec(), true);
            let who: Vec<String> = (points.iter().enumerate())
                .filter(|(_, q)| (*q - at).norm() < 1e-9)
                .map(|(k, _)| format!("M{}", k + 1))
                .collect();
            d.label(at + P2::new(1.5 * h, -2.5 * h), who.join(", "));
        }
    }
    let g = f.centroid;
    for at in [P2::new(g[0], g[1]), side(g[2], g[1])] {
        d.mark(at);
        d.label(at + P2::new(h, h), "G");
    }
}

/// The side view: the shaft along z (drawn along x from `x0`), each throw's plane as a
/// line of length 2R, each rotor's plane as a short mark, the planes' spacing dimensioned.
fn side_view(d: &mut Drawing, p: &MultiCylinderProblem, x0: f64) {
    let cyl = &p.layout.cylinders;
    let rr = cyl[0].sc.r;
    let zs: Vec<f64> = cyl.iter().map(|c| c.z).collect();
    let lo = zs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = zs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let z0 = side_z0(p);
    let at = |z: f64, y: f64| P2::new(x0 + z - z0, y);
    let span = (hi - lo).max(rr);
    d.line(
        Layer::Centre,
        at(lo - 0.2 * span, 0.0),
        at(hi + 0.2 * span, 0.0),
    );
    for (z, who) in groups_by(cyl.iter().map(|c| c.z), |a, b| (a - b).abs() < 1e-12) {
        d.line(Layer::Outline, at(z, -rr), at(z, rr));
        d.label(at(z, 1.4 * rr), who);
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
