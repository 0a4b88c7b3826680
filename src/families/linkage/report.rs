//! The linkage's documents: the tables, plots and drawings of a solved scene, drawn from its
//! solution and the result's numbers, calling no solver; the driver makes them only when a
//! result's files are asked for (`SolveResult::draw`, `complete`). The numbers themselves are
//! `numbers.rs`'.

use super::file::{LinkageProblem, LinkageScene};
use super::model::tip_of;
use super::solve::{Analyses, Solution as Solved};
use super::synth::{self as ls};
use crate::families::family::Scene;
use crate::families::linkage::model::{Dyad, Linkage, Point};
use crate::geom::outline::Edge;
use crate::geom::P2;
use crate::report::drawing::{Drawing, DrawingError, Layer, Sheet};
use crate::report::plot::{self, Panel, PlotError, Series};
use crate::report::{Plot, SolveResult, Table};
use std::f64::consts::TAU;

use super::numbers::{joint_rows, Front};

/// No analyses beyond the solution's own documents.
pub fn analysis_documents(
    _: &Scene,
    _: &LinkageProblem,
    _: &Solved,
    _: &Analyses,
    _: &mut SolveResult,
) {
}

/// The tables, plots and drawing of a solved scene, in the order the report lists them.
pub fn documents(scene: &Scene, p: &LinkageProblem, sol: &Solved, r: &mut SolveResult) {
    if let Some(Ok(env)) = &sol.envelope {
        r.tables.push(Table {
            suffix: "envelope".into(),
            caption: "The design over the operating envelope: the nominal scene, then every vertex of the box in every load case (the worst case over it is at one)".into(),
            csv: super::numbers::envelope_csv(env),
        });
        if let Some(rows) = &env.sensitivities {
            r.tables
                .push(crate::report::envelope::sensitivity_table(rows));
        }
    }
    if let Some(front) = &sol.out.pareto {
        pareto_documents(r, &Front::of(front, &sol.out));
    }
    if let Some(shape) = &p.shape {
        shape_documents(r, p, shape);
    }
    joint_table(r, p, sol);
    curves(r, scene, p, sol);
    let bodies = (&sol.sectors[..], &sol.out.plates[..]);
    let mut motion = super::motion::motion(&p.scene, sol.design_x(), bodies);
    motion.marks = super::motion::requirement_marks(p);
    if p.shape.is_some() {
        // The geometry drawn is the shape search's, not the file's: a drag of a pivot or a
        // length would write the file's value, the search's seed, not what is drawn.
        motion.handles.retain(|h| !h.key.starts_with("mechanism."));
    }
    r.motion = serde_json::to_value(motion).ok();
    crate::report::drive::drive_documents(r, sol.drive.as_ref(), "crank");
    // The load case that governs the flywheel, where it is not the nominal one: its turn and
    // its steady state with the flywheel of all the cases.
    let lc = sol.load_cases.as_ref();
    if let Some(lc) = lc {
        super::load_cases::table(r, lc, super::numbers::drive_peak_force(sol));
    }
    if let Some(lc) = lc.filter(|lc| lc.flywheel.is_some()) {
        let every = lc
            .cases
            .iter()
            .filter_map(|c| match c.at_flywheel.as_ref() {
                Some(Ok(d)) => Some((c.name.clone(), d.clone())),
                _ => None,
            })
            .collect();
        crate::report::drive::cases_plot(r, every, "crank");
    }
    let governing = lc.and_then(|lc| Some(&lc.cases[lc.flywheel?.governing?]));
    if let Some(c) = governing.filter(|c| c.name != super::envelope::NOMINAL) {
        let case = Some(("governing", c.name.as_str()));
        crate::report::drive::drive_documents_of(r, c.at_flywheel.as_ref(), "crank", case);
    }
    linkage_drawing(r, scene, p, sol);
}

/// The bearing loads' table `<name>-joints.csv`.
fn joint_table(r: &mut SolveResult, p: &LinkageProblem, solved: &Solved) {
    let Ok(loads) = &solved.joints else { return };
    let steady = matches!(loads.steady, Some(Ok(_)));
    let mut csv = String::from(
        "joint,kind,unbalanced_peak_n,unbalanced_error_n,unbalanced_angle_rad,peak_n,error_n,angle_rad",
    );
    if steady {
        csv += ",steady_peak_n,steady_error_n,steady_angle_rad";
    }
    csv.push('\n');
    let cell = |v: Option<f64>, f: fn(f64) -> String| v.map_or(String::new(), f);
    let e12 = |v: f64| format!("{v:.12e}");
    let e3 = |v: f64| format!("{v:.3e}");
    for row in joint_rows(p, loads) {
        let (b, d) = (row.bare, row.design);
        csv += &format!(
            "{},{},{:.12e},{:.3e},{:.12e},{},{},{}",
            row.label,
            row.kind,
            b.peak,
            b.error,
            b.angle,
            cell(d.map(|d| d.peak), e12),
            cell(d.map(|d| d.error), e3),
            cell(d.map(|d| d.angle), e12),
        );
        if steady {
            let s = row.steady;
            csv += &format!(
                ",{},{},{}",
                cell(s.map(|s| s.peak), e12),
                cell(s.map(|s| s.error), e3),
                cell(s.map(|s| s.angle), e12)
            );
        }
        csv.push('\n');
    }
    r.tables.push(Table {
        suffix: "joints".into(),
        caption: "Joint (bearing) loads: peak over the cycle without and with the counterweights"
            .into(),
        csv,
    });
}

/// The front's table `<name>-pareto.csv` and its plot.
fn pareto_documents(r: &mut SolveResult, front: &Front) {
    let (caption, alt, title, x_label, y_label) = if front.energy() {
        (
            "Energy fluctuation ΔE against peak shaking force: each point its own certified solve",
            "Energy fluctuation ΔE against peak shaking force (ε-constraint front, each point certified)",
            "ΔE–force front",
            "peak shaking force (N)",
            "energy fluctuation ΔE (J)",
        )
    } else {
        (
            "Peak shaking force against peak shaking moment: each point its own certified solve",
            "Peak shaking force against peak shaking moment (ε-constraint front, each point certified)",
            "Force–moment front",
            "peak shaking moment (N·m)",
            "peak shaking force (N)",
        )
    };
    r.tables.push(Table {
        suffix: "pareto".into(),
        caption: caption.into(),
        csv: front.csv(),
    });
    let line = front.line();
    r.plots
        .push(Plot::of_panels("pareto", alt, 640, 420, move || {
            Ok(vec![Panel {
                title: title.into(),
                x_label: x_label.into(),
                y_label: y_label.into(),
                series: vec![
                    Series::line("front", line.clone()),
                    Series::points("points", line.clone()),
                ],
                equal_aspect: false,
            }])
        }));
}

/// A shape search's table `<name>-synthesis.csv` — the file's geometry, "synthesise first,
/// balance afterwards" and the front, each with its path error, certified objective and
/// parameters (mm) — and its plot: the front of path error against the objective, with the
/// two others beside it.
fn shape_documents(r: &mut SolveResult, p: &LinkageProblem, shape: &super::shape::ShapeOutcome) {
    let key = super::numbers::objective_key(p.scene.objective.minimize);
    // The requirement's name and unit as the points show them: "path error", mm.
    let (what, _, unit) = shape.kinematic_first.error.shown();
    let column = format!("{}_{unit}", what.replace(' ', "_"));
    let row = |design: String, pt: &super::shape::ShapePoint| {
        let mut v = serde_json::json!({
            "design": design,
            column.as_str(): pt.error.shown().1,
            key: pt.objective,
        });
        for (name, x) in shape.parameters.iter().zip(&pt.x) {
            v[format!("{}_mm", name.replace(' ', "_"))] = serde_json::json!(x * 1e3);
        }
        v
    };
    let mut rows = Vec::new();
    if let Some(n) = &shape.nominal {
        rows.push(row("the file's geometry".into(), n));
    }
    rows.push(row(
        "synthesise first, balance afterwards".into(),
        &shape.kinematic_first,
    ));
    for pt in &shape.front {
        let eps = pt
            .held_to
            .map_or(f64::NAN, |h| pt.error.with(h.value()).shown().1);
        rows.push(row(format!("front: {what} ≤ {eps:.4} {unit}"), pt));
    }
    r.tables.push(Table::of_rows(
        "synthesis",
        &format!("The shape search: the file's geometry, the least {what} balanced afterwards, and the front of {what} against the certified objective (each geometry a multistart's best, its counterweights certified)"),
        &rows,
    ));
    let pts = |it: &mut dyn Iterator<Item = &super::shape::ShapePoint>| -> Vec<(f64, f64)> {
        it.filter_map(|pt| Some((pt.error.shown().1, pt.objective?)))
            .collect()
    };
    let front = pts(&mut shape.front.iter());
    let first = pts(&mut std::iter::once(&shape.kinematic_first));
    let file = pts(&mut shape.nominal.iter());
    let y_label = format!("{key} (certified)");
    let x_label = format!("{what} ({unit})");
    let title = format!("{}{} against balance", what[..1].to_uppercase(), &what[1..]);
    r.plots.push(Plot::of_panels(
        "synthesis",
        &format!("{}{} against the certified objective: the front of the shape search, the least {what} balanced afterwards, and the file's geometry", what[..1].to_uppercase(), &what[1..]),
        640,
        420,
        move || {
            Ok(vec![Panel {
                title: title.clone(),
                x_label: x_label.clone(),
                y_label: y_label.clone(),
                series: vec![
                    Series::line("front", front.clone()),
                    Series::points("front points", front.clone()),
                    Series::points("the file's geometry", file.clone()),
                    Series::points("synthesise first, balance afterwards", first.clone()),
                ],
                equal_aspect: false,
            }])
        },
    ));
}

/// The fields over the cycle with and without the counterweights (`<name>-cycle.csv`, the
/// `fields` plot) and the linkage at four crank angles: the model evaluated for drawing.
fn curves(r: &mut SolveResult, scene: &Scene, p: &LinkageProblem, solved: &Solved) {
    let x = solved.design_x().map(<[f64]>::to_vec);
    let rows = cycle_rows(&p.scene, x.as_deref(), p.settings.scan_samples.max(16));
    let mut csv = String::from("theta_deg,bare_fx_n,bare_fy_n,bare_moment_nm,bare_torque_nm,fx_n,fy_n,moment_nm,torque_nm\n");
    for row in &rows {
        csv += &row
            .iter()
            .map(|v| format!("{v:.9e}"))
            .collect::<Vec<_>>()
            .join(",");
        csv += "\n";
    }
    r.tables.push(Table {
        suffix: "cycle".into(),
        caption: "Shaking force, shaking moment and input torque over one crank turn, without and with the counterweights".into(),
        csv,
    });
    let with_cw = x.is_some();
    r.plots.push(Plot::of_panels(
        "fields",
        "|F|, M_O and T over one crank turn: bare linkage and with the counterweights",
        420,
        340,
        move || fields_plot(&rows, with_cw),
    ));
    let (sc, name) = (p.scene.clone(), scene.name.clone());
    r.plots.push(Plot::new(
        "linkage",
        "The linkage at four crank angles (0°, 90°, 180°, 270°), with its counterweights' centroids",
        move || drawing(&name, &sc, x.as_deref()),
    ));
}

/// θ (deg) and the bare and balanced Fx, Fy, M_O, T at n + 1 angles over the turn (angles where
/// the linkage does not assemble are left out).
fn cycle_rows(sc: &LinkageScene, x: Option<&[f64]>, n: usize) -> Vec<[f64; 9]> {
    let extra = x.map(|x| ls::extras(&sc.counterweights, x));
    (0..=n)
        .filter_map(|k| {
            let th = TAU * k as f64 / n as f64;
            let pose = sc.linkage.pose(th).ok()?;
            let map = sc.linkage.balance_map(&pose, sc.moment_about);
            let b = map.base;
            let d = extra.as_ref().map_or(b, |e| map.fields(e));
            Some([
                th.to_degrees(),
                b.force.x,
                b.force.y,
                b.moment,
                b.torque,
                d.force.x,
                d.force.y,
                d.moment,
                d.torque,
            ])
        })
        .collect()
}

/// |F|, M_O and T against θ from [`cycle_rows`], bare and (with counterweights) balanced.
fn fields_plot(rows: &[[f64; 9]], with_cw: bool) -> Result<Vec<Panel>, PlotError> {
    let col = |i: usize, j: Option<usize>| -> Vec<(f64, f64)> {
        rows.iter()
            .map(|r| (r[0], j.map_or(r[i], |j| r[i].hypot(r[j]))))
            .collect()
    };
    // The largest |value| of a curve, marked and labelled.
    let peak = |pts: &[(f64, f64)], unit: &str, what: &str| -> Option<Series> {
        let &(x, y) = pts
            .iter()
            .filter(|q| q.1.is_finite())
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
        Some(Series::peak(
            format!(
                "{what} {} {unit} at {}°",
                plot::tick(&((y.abs() * 1e4).round() / 1e4)),
                plot::tick(&((x * 10.0).round() / 10.0))
            ),
            vec![(x, y)],
        ))
    };
    let pane = |title: &str, y: &str, unit: &str, bare: Vec<(f64, f64)>, bal: Vec<(f64, f64)>| {
        let mut series = vec![];
        series.extend(peak(&bare, unit, "bare peak"));
        if with_cw {
            series.extend(peak(&bal, unit, "balanced peak"));
            series.insert(0, Series::line("balanced", bal));
        }
        series.insert(0, Series::line("bare", bare));
        Panel {
            title: title.into(),
            x_label: "crank angle θ (deg)".into(),
            y_label: format!("{y} ({unit})"),
            series,
            equal_aspect: false,
        }
    };
    Ok(vec![
        pane(
            "Shaking force |F|",
            "|F|",
            "N",
            col(1, Some(2)),
            col(5, Some(6)),
        ),
        pane(
            "Shaking moment M_O",
            "M_O",
            "N·m",
            col(3, None),
            col(7, None),
        ),
        pane("Input torque T", "T", "N·m", col(4, None), col(8, None)),
    ])
}

/// The links as segments (reference joint to tip) at four crank angles; the counterweights'
/// centroids as markers.
fn drawing(name: &str, sc: &LinkageScene, x: Option<&[f64]>) -> Result<String, PlotError> {
    let l: &Linkage = &sc.linkage;
    let mut series = Vec::new();
    for q in 0..4 {
        let th = TAU * q as f64 / 4.0;
        let Ok(pose) = l.pose(th) else { continue };
        let mut pts = Vec::new();
        for (a, b) in super::motion::segments(l, sc.crank_length, &pose) {
            pts.push((a.x * 1e3, a.y * 1e3));
            pts.push((b.x * 1e3, b.y * 1e3));
            pts.push((f64::NAN, f64::NAN));
        }
        series.push(Series::line(format!("θ = {}°", 90 * q), pts));
        if let Some(x) = x {
            let cw: Vec<(f64, f64)> = super::motion::counterweights(sc, x, &pose)
                .iter()
                .map(|c| (c.x * 1e3, c.y * 1e3))
                .collect();
            if q == 0 && !cw.is_empty() {
                series.push(Series::marker("counterweights (θ = 0°)", cw));
            }
        }
    }
    plot::panels(
        &[Panel {
            title: format!("{name}: positions"),
            x_label: "x (mm)".into(),
            y_label: "y (mm)".into(),
            series,
            equal_aspect: true,
        }],
        720,
        560,
    )
}

/// The linkage's drawing (`<name>-drawing.dxf`/`.svg`, [`linkage_sheet`]).
fn linkage_drawing(r: &mut SolveResult, scene: &Scene, p: &LinkageProblem, sol: &Solved) {
    let x = sol.design_x().map(<[f64]>::to_vec);
    let (sc, name, sectors) = (p.scene.clone(), scene.name.clone(), sol.sectors.clone());
    let plates = sol.out.plates.clone();
    let path = p.path.clone();
    let caption = "linkage at θ = 0 and its counterweights";
    r.drawings.push(Sheet::new("drawing", caption, move || {
        let mut d = linkage_sheet(&name, &sc, x.as_deref(), (&sectors, &plates))?;
        if let Some(path) = &path {
            tracer_path(&mut d, &sc.linkage, path, 0.04 * sc.crank_length);
        }
        Ok(d)
    }));
}

/// The tracer's path over the turn (layer `PATH`, 360 samples) and each precision point as
/// a cross in a circle of radius `size`, numbered.
fn tracer_path(d: &mut Drawing, l: &Linkage, path: &super::shape::PathSpec, size: f64) {
    let pts: Vec<P2> = (0..360)
        .filter_map(|k| l.pose(TAU * k as f64 / 360.0).ok())
        .map(|pose| pose.links[path.link].point(path.at)[0])
        .collect();
    d.polyline(Layer::Path, pts, true);
    d.note("the tracer's path over the turn, and the precision points Q1, Q2, … it must pass near (circles)");
    for (i, q) in path.points.iter().enumerate() {
        d.mark(*q).circle(Layer::Dim, *q, size);
        d.label(*q + P2::new(size, size), format!("Q{}", i + 1));
    }
}

use super::motion::Bodies;

/// The links (reference joint to tip) at the design position θ = 0 with their joints, and at
/// 90°, 180°, 270° (layer `PATH`); the ground pivots marked, a slider's line as a centre line;
/// each counterweight of the design `x` as a disc at its centroid (a symbolic size), its
/// radius from the link's reference joint dimensioned, its mass and angle in a note; its
/// plate (`plates`, a counterweight with a thickness) or its annular sector (`sectors`, from
/// the solve) where there is one.
fn linkage_sheet(
    name: &str,
    sc: &LinkageScene,
    x: Option<&[f64]>,
    (sectors, plates): Bodies,
) -> Result<Drawing, DrawingError> {
    let l: &Linkage = &sc.linkage;
    let pin = 0.04 * sc.crank_length;
    let mut d = Drawing::new(format!("{name}: linkage at θ = 0 (blue: 90°, 180°, 270°)"));
    let frame = |pt: &Point| match pt {
        Point::Frame(f) => Some(*f),
        Point::On { .. } => None,
    };
    let mut ground = vec![l.pivot()];
    for dy in l.dyads() {
        match dy {
            Dyad::Rrr { p, q, .. } | Dyad::Rpr { p, q, .. } => {
                ground.extend(frame(p).into_iter().chain(frame(q)));
            }
            Dyad::Rrp { p, .. } => ground.extend(frame(p)),
        }
    }
    for g in &ground {
        d.mark(*g).circle(Layer::Centre, *g, 1.5 * pin);
    }
    let poses: Vec<_> = (0..4)
        .filter_map(|q| l.pose(TAU * q as f64 / 4.0).ok())
        .collect();
    // A slider's line, over the positions drawn.
    for (k, dy) in l.dyads().iter().enumerate() {
        if let Dyad::Rrp { origin, angle, .. } = *dy {
            let u = P2::new(angle.cos(), angle.sin());
            let t = poses.iter().map(|p| (p.dyads[k].joint[0] - origin).dot(&u));
            let (t0, t1) = t.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
                (a.min(t), b.max(t))
            });
            if t0 <= t1 {
                d.line(
                    Layer::Centre,
                    origin + (t0 - 4.0 * pin) * u,
                    origin + (t1 + 4.0 * pin) * u,
                );
            }
        }
    }
    for pose in poses.iter().rev() {
        let design = pose.theta == 0.0;
        let layer = if design { Layer::Outline } else { Layer::Path };
        for (i, st) in pose.links.iter().enumerate() {
            let a = st.p[0];
            if let Some(at) = tip_of(l.dyads(), sc.crank_length, i) {
                let b = pose.point(&Point::On { link: i, at })[0];
                d.line(layer, a, b);
                if design {
                    d.circle(layer, a, pin).circle(layer, b, pin);
                    // Its length, on the side away from the counterweight's dimension.
                    let name = sc.link_names.get(i).map_or("", String::as_str);
                    d.linear(a, b, -4.0 * pin, name);
                }
            } else {
                // A slider or a block: a square about its reference joint, along the link.
                let (u, v) = (st.e * (2.0 * pin), crate::geom::perp(st.e) * (2.0 * pin));
                d.polyline(
                    layer,
                    vec![a + u + v, a - u + v, a - u - v, a + u - v],
                    true,
                );
            }
        }
    }
    if let (Some(pose), Some(x)) = (poses.first().filter(|p| p.theta == 0.0), x) {
        for (j, (link, m)) in ls::extras(&sc.counterweights, x).iter().enumerate() {
            if m[0] <= 0.0 {
                continue;
            }
            let at = P2::new(m[1] / m[0], m[2] / m[0]);
            let (p0, c) = (
                pose.links[*link].p[0],
                pose.point(&Point::On { link: *link, at })[0],
            );
            let on = &sc.counterweights[j].link_name;
            // The plate or the annular sector that is this counterweight, about its joint
            // (none: a ring).
            let axis = pose.point(&Point::On {
                link: *link,
                at: P2::new(1.0, 0.0),
            })[0]
                - p0;
            let own = sc.counterweights[j].drawing.clone();
            let plate = plates.get(j).copied().flatten().map(|p| p.shape.loops());
            if let Some(loops) = own.or(plate) {
                draw_loops(&mut d, &loops, p0, axis.y.atan2(axis.x));
                d.mark(c);
            } else {
                match sectors.get(j).copied().flatten() {
                    Some((ri, ro, th)) if ro > 0.0 && th > 0.0 => {
                        let mid = (c - p0).y.atan2((c - p0).x);
                        let (a0, a1) = (mid - 0.5 * th, mid + 0.5 * th);
                        d.arc(Layer::Outline, p0, ro, a0, a1);
                        if ri > 0.0 {
                            d.arc(Layer::Outline, p0, ri, a0, a1);
                        }
                        if th < TAU - 1e-9 {
                            for a in [a0, a1] {
                                let v = P2::new(a.cos(), a.sin());
                                d.line(Layer::Outline, p0 + ri * v, p0 + ro * v);
                            }
                        }
                        d.mark(c);
                    }
                    _ => {
                        d.circle(Layer::Outline, c, 1.5 * pin).mark(c);
                    }
                }
            }
            d.linear(p0, c, 6.0 * pin, &format!("r ({on})"));
            d.note(format!(
                "counterweight on {on}: {:.4} kg, centroid at {:.2} mm, {:.2}° from the link's axis{}",
                m[0],
                at.norm() * 1e3,
                at.y.atan2(at.x).rem_euclid(TAU).to_degrees(),
                match (sc.counterweights[j].is_given(), &sc.counterweights[j].drawing) {
                    (_, Some(_)) => " (drawn as in its drawing)",
                    (true, None) => " (a given body, drawn as the sector with its mass, centroid and inertia: an equivalent, not its own outline)",
                    _ => "",
                }
            ));
        }
    }
    if poses.is_empty() {
        let why = "the linkage does not assemble at θ = 0, 90°, 180°, 270°";
        return Err(DrawingError::Data(why.into()));
    }
    if plates.iter().any(Option::is_some) {
        d.note("a counterweight with a thickness: the plate to cut (a ring centred at its centroid, or its envelope cut by a circle)");
    }
    d.note("a link's axis: from its reference joint towards its tip; dimensions in mm");
    d.note("crosses in circles: ground pivots; about their joints, the counterweights: a plate as cut, a drawn one as drawn, else the annular sector with their mass, centroid and inertia within the envelope (a small ring where none is)");
    Ok(d)
}

/// A body's outline (closed loops in its link's frame about the joint: a plate's
/// [`crate::geom::plate::PlateShape::loops`], a drawn counterweight's own) drawn at the joint
/// `p0` with the link's axis at angle `phi`.
fn draw_loops(d: &mut Drawing, loops: &[Vec<Edge>], p0: P2, phi: f64) {
    let w = |p: P2| p0 + crate::geom::rot(phi, p);
    for lp in loops {
        for &e in lp {
            match e.arc {
                Some(a) => {
                    let (s, t) = if a.sweep >= 0.0 {
                        (a.start, a.start + a.sweep)
                    } else {
                        (a.start + a.sweep, a.start)
                    };
                    if a.sweep.abs() >= TAU - 1e-12 {
                        d.circle(Layer::Outline, w(a.centre), a.radius);
                    } else {
                        d.arc(Layer::Outline, w(a.centre), a.radius, s + phi, t + phi);
                    }
                }
                None => {
                    d.line(Layer::Outline, w(e.from), w(e.to));
                }
            }
        }
    }
}
