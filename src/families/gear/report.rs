//! The gear's documents: the tables, plots and drawings of a solved scene, drawn from its
//! solution and the result's numbers, calling no solver; the driver makes them only when a
//! result's files are asked for (`SolveResult::draw`, `complete`). The numbers themselves are
//! `numbers.rs`'.

use super::file::*;
use super::solve::{Analyses, Solution};
use crate::families::family::Scene;
use crate::families::gear::model::{EccentricCircle, GearPair, Which, ZeroKind};
use crate::families::gear::stress::{flank_name, ArchStress, FlankStress, StressPoint};
use crate::families::gear::synth::{self as sg, GearScene, Outcome, TeethOutcome};
use crate::families::gear::teeth::Arch;
use crate::geom::P2;
use crate::report::drawing::{Drawing, Layer, Sheet};
use crate::report::plot::{self, Panel, PlotError, Series};
use crate::report::{Plot, SolveResult, Table};
use std::f64::consts::TAU;
use std::fmt::Write as _;

/// No analyses beyond the solution's own documents.
pub fn analysis_documents(
    _: &Scene,
    _: &GearProblem,
    _: &Solution,
    _: &Analyses,
    _: &mut SolveResult,
) {
}

/// The tables, plots and drawing of a solved scene, in the order the report lists them.
pub fn documents(scene: &Scene, p: &GearProblem, sol: &Solution, r: &mut SolveResult) {
    let out = &sol.out;
    r.tables = tables(out);
    if let Some(t) = &out.teeth {
        r.tables.extend(teeth_tables(t));
    }
    let shared = std::sync::Arc::new((scene.clone(), p.gear.clone(), out.clone()));
    let d = shared.clone();
    r.plots.push(Plot::of_panels(
        "pitch-curves",
        "Pitch curves of both gears and the transmission function i12(α1)",
        560,
        480,
        move || ratio_and_curves_plot(&d.0, &d.2),
    ));
    let d = shared.clone();
    r.plots.push(Plot::of_panels(
        "sliding",
        "Sliding coefficients µ1, µ2 against α1, poles marked, pole windows left empty",
        640,
        480,
        move || sliding_plot(&d.0, &d.1, &d.2),
    ));
    if shared.2.teeth.is_some() {
        let d = shared.clone();
        r.plots.push(Plot::of_panels(
            "contact",
            "Contact point: radii ρ_K1, ρ_K2 and velocities V_K1, V_K2, v_t1, v_t2, v_s against α1",
            640,
            420,
            move || contact_plot(&d.0, &d.2),
        ));
    }
    if shared.2.teeth.as_ref().is_some_and(|t| t.stress.is_some()) {
        let d = shared.clone();
        r.plots.push(Plot::of_panels(
            "contact-stress",
            "Hertz pressure p0 along the loaded flanks against α1 (working windows only), and the Archard load-weighted sliding per flank over a cycle",
            640,
            420,
            move || stress_plot(&d.0, &d.2),
        ));
    }
    pitch_drawing(r, &shared.0.name, &shared.2);
    r.motion = super::motion::motion(&p.gear, out).and_then(|m| serde_json::to_value(m).ok());
    if !shared.2.sweep.is_empty() {
        let d = shared.clone();
        r.plots.push(Plot::of_panels(
            "sweep",
            "Design sweep over the eccentricity e",
            480,
            420,
            move || sweep_plot(&d.0, &d.1, &d.2),
        ));
    }
}

fn closed(pts: &[[f64; 2]], scale: f64) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = pts.iter().map(|p| (p[0] * scale, p[1] * scale)).collect();
    if let Some(&f) = v.first() {
        v.push(f);
    }
    v
}

/// Pitch curves (equal axes, mm) and i12(α1).
fn ratio_and_curves_plot(scene: &Scene, out: &Outcome) -> Result<Vec<Panel>, PlotError> {
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
    Ok(vec![curves, ratio])
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
fn sliding_plot(scene: &Scene, g: &GearScene, out: &Outcome) -> Result<Vec<Panel>, PlotError> {
    let v = Sliding::new(g, out)?;
    Ok(vec![
        v.panel(&scene.name, false),
        v.panel(&scene.name, true),
    ])
}

/// What the sliding plot draws: µ1 and µ2 over the turn and zoomed on two arches around the
/// peak, the pole windows left empty, poles, zeros and the peak marked.
struct Sliding<'a> {
    out: &'a Outcome,
    pair: GearPair,
    /// The zoom range: two arches from half an arch before the arch holding the peak.
    zoom: (f64, f64),
    /// The pole window's half-width (rad).
    window: f64,
    /// The peak |µ| and where it is (α1).
    peak: (f64, f64),
    /// The peak, signed as the coefficient that attains it.
    peak_signed: f64,
    /// The zoom's angles: a fine grid plus both edges of every window (nudged inside the
    /// working region by 1e-9 rad).
    xs: Vec<f64>,
}

impl<'a> Sliding<'a> {
    fn new(g: &GearScene, out: &'a Outcome) -> Result<Sliding<'a>, PlotError> {
        let arch = TAU / out.derived.arches_gear1.max(1.0);
        let window = out.derived.pole_window_rad;
        let peak = (
            out.objectives.peak_sliding_coefficient,
            out.derived.peak_sliding_alpha1_rad,
        );
        let z0 = (peak.1 / arch).floor() * arch - 0.5 * arch;
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
        let ct = pair.contact(peak.1);
        let peak_signed = [ct.mu1, ct.mu2]
            .into_iter()
            .flatten()
            .min_by(|a, b| {
                (a.abs() - peak.0)
                    .abs()
                    .total_cmp(&(b.abs() - peak.0).abs())
            })
            .unwrap_or(peak.0);
        let mut v = Sliding {
            out,
            pair,
            zoom: (z0, z0 + 2.0 * arch),
            window,
            peak,
            peak_signed,
            xs: Vec::new(),
        };
        v.xs = v.zoom_grid();
        Ok(v)
    }

    /// The fine grid of the zoom and the windows' edges in it, sorted.
    fn zoom_grid(&self) -> Vec<f64> {
        let (z0, z1) = self.zoom;
        let w = self.window;
        let mut xs: Vec<f64> = (0..=1200)
            .map(|k| z0 + (z1 - z0) * k as f64 / 1200.0)
            .collect();
        for p in &self.out.poles {
            for x in [
                p.alpha1_rad - w - p.error_rad - 1e-9,
                p.alpha1_rad + w + p.error_rad + 1e-9,
            ] {
                if let Some(x) = self.wrap(x) {
                    xs.push(x);
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        xs
    }

    /// x moved by a turn into the zoom range, if it falls there.
    fn wrap(&self, x: f64) -> Option<f64> {
        let (z0, z1) = self.zoom;
        [x - TAU, x, x + TAU]
            .into_iter()
            .find(|y| (z0..=z1).contains(y))
    }

    /// Is x inside a window left out of `which` (a pole's, or a 0/0 cusp's)?
    fn excluded(&self, x: f64, which: Which) -> bool {
        let near = |c: f64, tol: f64| {
            let d = (x - c).rem_euclid(TAU);
            d.min(TAU - d) < tol
        };
        let w = self.window;
        self.out
            .poles
            .iter()
            .any(|p| p.which == which && near(p.alpha1_rad, w + p.error_rad))
            || self
                .out
                .zeros
                .iter()
                .any(|z| z.kind == ZeroKind::Indeterminate && near(z.alpha1_rad, w))
    }

    /// µ of `which` on the zoom's angles (deg), NaN in the windows.
    fn zoom_mu(&self, which: Which) -> Vec<(f64, f64)> {
        self.xs
            .iter()
            .map(|&x| {
                let ct = self.pair.contact(x.rem_euclid(TAU));
                let m = match which {
                    Which::Mu1 => ct.mu1,
                    Which::Mu2 => ct.mu2,
                };
                let m = if self.excluded(x, which) { None } else { m };
                (x.to_degrees(), m.unwrap_or(f64::NAN))
            })
            .collect()
    }

    /// µ of `which` over the turn, from the analysis's series.
    fn full_mu(&self, which: Which) -> Vec<(f64, f64)> {
        let s = &self.out.series;
        let v = match which {
            Which::Mu1 => &s.mu1,
            Which::Mu2 => &s.mu2,
        };
        s.alpha1_rad
            .iter()
            .zip(v)
            .map(|(&a, m)| (a.to_degrees(), m.unwrap_or(f64::NAN)))
            .collect()
    }

    /// The angles (deg) of `which`'s poles, in the zoom or over the turn.
    fn pole_x(&self, which: Which, zoom: bool) -> Vec<f64> {
        self.out
            .poles
            .iter()
            .filter(|p| p.which == which)
            .filter_map(|p| self.place(p.alpha1_rad, zoom))
            .map(f64::to_degrees)
            .collect()
    }

    /// The zeros of `kind` at (deg, 0), in the zoom or over the turn.
    fn zeros(&self, kind: ZeroKind, zoom: bool) -> Vec<(f64, f64)> {
        self.out
            .zeros
            .iter()
            .filter(|z| z.kind == kind)
            .filter_map(|z| self.place(z.alpha1_rad, zoom))
            .map(|x| (x.to_degrees(), 0.0))
            .collect()
    }

    /// x in the zoom (if it falls there), or as it is.
    fn place(&self, x: f64, zoom: bool) -> Option<f64> {
        if zoom {
            self.wrap(x)
        } else {
            Some(x)
        }
    }

    /// The panel over the turn, or the zoom.
    fn panel(&self, name: &str, zoom: bool) -> Panel {
        let (peak, peak_at) = self.peak;
        let ylim = peak * 1.05;
        let mu = |which| {
            if zoom {
                self.zoom_mu(which)
            } else {
                self.full_mu(which)
            }
        };
        let mut series = vec![
            Series::line("µ1", mu(Which::Mu1)),
            Series::line("µ2", mu(Which::Mu2)),
            Series::line(
                "poles of µ1",
                verticals(&self.pole_x(Which::Mu1, zoom), -ylim, ylim),
            ),
            Series::line(
                "poles of µ2",
                verticals(&self.pole_x(Which::Mu2, zoom), -ylim, ylim),
            ),
            Series::points("µ = 0 (K = P)", self.zeros(ZeroKind::PitchPoint, zoom)),
            Series::marker(
                format!("peak |µ| = {peak:.4}"),
                self.place(peak_at, zoom)
                    .map(|x| (x.to_degrees(), self.peak_signed))
                    .into_iter()
                    .collect(),
            ),
            Series::points(
                "0/0 cusp, left out",
                self.zeros(ZeroKind::Indeterminate, zoom),
            ),
        ];
        series.retain(|s| s.points.iter().any(|p| p.0.is_finite() && p.1.is_finite()));
        Panel {
            title: if zoom {
                "zoom: two arches around the peak".into()
            } else {
                format!(
                    "{name}: µ1, µ2 (pole windows ±{:.3}° left out)",
                    self.window.to_degrees()
                )
            },
            x_label: "α1, angle of gear 1 (deg)".into(),
            y_label: "sliding coefficient µ (–)".into(),
            series,
            equal_aspect: false,
        }
    }
}

/// The eccentricity sweep: ratio variation, peak |µ|, gear 2's curvature.
fn sweep_plot(scene: &Scene, g: &GearScene, out: &Outcome) -> Result<Vec<Panel>, PlotError> {
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
    Ok(vec![
        p(
            format!("{}: speed-ratio variation", scene.name),
            "i12max/i12min (–)",
            var,
        ),
        p("peak sliding coefficient".into(), "peak |µ| (–)", mu),
        p("convexity of gear 2".into(), "κmin·R (–)", curv),
        p("pitch pressure angle".into(), "max |ψ| (deg)", psi),
    ])
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
/// distance a = |O1O2|, R and e dimensioned, and with `model.tooth_profiles` the tooth
/// outlines of both gears.
fn pitch_drawing(r: &mut SolveResult, name: &str, out: &Outcome) {
    let pc = &out.pitch_curves;
    if pc.gear2_m.is_empty() {
        return;
    }
    let p2 = |p: [f64; 2]| P2::new(p[0], p[1]);
    let (o1, o2) = (p2(pc.center1_m), p2(pc.center2_m));
    let (big_r, e) = (out.design.pitch_radius_m, out.design.eccentricity_m);
    let gear2: Vec<P2> = pc.gear2_m.iter().map(|p| p2(*p)).collect();
    // Tooth outlines (with `model.tooth_profiles`), gear 2's moved to O2: one closed
    // polyline per gear, each arch's first point dropped after the first arch (it repeats
    // the previous arch's last).
    let outline = |arches: &[Arch], at: P2| -> Vec<P2> {
        arches
            .iter()
            .enumerate()
            .flat_map(|(k, a)| {
                a.points
                    .iter()
                    .skip(usize::from(k > 0))
                    .map(move |p| at + p)
            })
            .collect()
    };
    let teeth: Option<(Vec<P2>, Vec<P2>)> = out.teeth.as_ref().map(|t| {
        let mut g1 = outline(&t.profiles.gear1, o1);
        let mut g2 = outline(&t.profiles.gear2, o2);
        // The last point closes onto the first.
        g1.pop();
        g2.pop();
        (g1, g2)
    });
    let name = name.to_string();
    r.drawings
        .push(Sheet::new("drawing", "pitch curves", move || {
            let c = o1 + P2::new(e, 0.0);
            let mut d = Drawing::new(format!("{name}: pitch curves at α1 = 0"));
            d.mark(o1).mark(o2).mark(c).line(Layer::Centre, o1, o2);
            d.circle(Layer::Outline, c, big_r);
            d.polyline(Layer::Outline, gear2.clone(), true);
            if let Some((g1, g2)) = &teeth {
                d.polyline(Layer::Outline, g1.clone(), true);
                d.polyline(Layer::Outline, g2.clone(), true);
                d.note(format!(
                    "tooth outlines: cycloidal arches ({} + {} points), epicycloid addenda and hypocycloid dedenda",
                    g1.len(),
                    g2.len()
                ));
            }
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

/// The tooth-level CSVs: both outlines (each in its own frame) and the contact series.
fn teeth_tables(t: &TeethOutcome) -> Vec<Table> {
    let mut csv = String::from("gear,arch,flank,phi_rad,x_m,y_m\n");
    for (gear, arches) in [(1, &t.profiles.gear1), (2, &t.profiles.gear2)] {
        for a in arches.iter() {
            let flank = if a.epicycloid {
                "addendum_epicycloid"
            } else {
                "dedendum_hypocycloid"
            };
            for (ph, p) in a.phi.iter().zip(&a.points) {
                let _ = writeln!(
                    csv,
                    "{gear},{},{flank},{},{},{}",
                    a.index,
                    num(*ph),
                    num(p.x),
                    num(p.y)
                );
            }
        }
    }
    let mut out = vec![Table {
        suffix: "tooth-profiles".into(),
        caption: "Tooth outlines, arch by arch: gear 1 in its frame (origin O1, x towards the pitch circle's centre), gear 2 in its frame (origin O2, axes of the fixed frame at α1 = 0)".into(),
        csv,
    }];
    let mut csv = String::from("alpha1_rad,rho_k1_m,rho_k2_m,v_k1_m_per_s,v_k2_m_per_s,v_t1_m_per_s,v_t2_m_per_s,v_slide_m_per_s,cos_beta1,cos_beta2\n");
    for c in &t.contact {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{}",
            num(c.alpha1),
            num(c.rho_k1),
            num(c.rho_k2),
            num(c.v_k1),
            num(c.v_k2),
            num(c.v_t1),
            num(c.v_t2),
            num(c.v_slide),
            num(c.cos_beta1),
            num(c.cos_beta2)
        );
    }
    out.push(Table {
        suffix: "contact".into(),
        caption: "Contact point over one turn of gear 1: radii ρ_K = |O_jK|, speeds V_K = ω_j ρ_K, tangential components v_t, sliding velocity v_s = v_t1 − v_t2, cos β_j = v_tj/V_Kj".into(),
        csv,
    });
    let mut csv = String::from(
        "gear,arch,flank,engagements_per_cycle,sliding_distance_per_cycle_m,error_m\n",
    );
    for (gear, rows, eng, own_epi) in [
        (1, &t.wear.gear1, t.wear.engagements.0, true),
        (2, &t.wear.gear2, t.wear.engagements.1, false),
    ] {
        for (i, (v, e)) in rows.iter().enumerate() {
            let epi = i.is_multiple_of(2) == own_epi;
            let _ = writeln!(
                csv,
                "{gear},{i},{},{eng},{},{}",
                if epi { "addendum" } else { "dedendum" },
                num(*v),
                num(*e)
            );
        }
    }
    out.push(Table {
        suffix: "flank-wear".into(),
        caption: "Sliding distance ∫|v_t1 − v_t2| dt per tooth flank (arch) over one cycle".into(),
        csv,
    });
    if let Some(st) = &t.stress {
        out.push(stress_table(st));
    }
    out
}

/// `<name>-contact-stress.csv`: per arch of both gears, the Archard load-weighted sliding
/// over a cycle; for gear 1's arches also the loaded stretch and the extremes of p0.
fn stress_table(st: &FlankStress) -> Table {
    let mut csv = String::from("gear,arch,flank,loaded_from_rad,loaded_to_rad,peak_p0_pa,peak_alpha1_rad,least_p0_pa,least_alpha1_rad,p0_error_pa,archard_per_cycle_nm,archard_error_nm\n");
    let opt = |v: Option<f64>| v.map_or(String::new(), num);
    for (a, (w, we)) in st.arches.iter().zip(&st.gear1) {
        let _ = writeln!(
            csv,
            "1,{},{},{},{},{},{},{},{},{},{},{}",
            a.arch,
            flank_name(a.arch),
            num(a.loaded.0),
            num(a.loaded.1),
            opt(a.peak.map(|p| p.p0_pa)),
            opt(a.peak.map(|p| p.alpha1)),
            opt(a.least.map(|p| p.p0_pa)),
            opt(a.least.map(|p| p.alpha1)),
            opt(a.p0_error()),
            num(*w),
            num(*we)
        );
    }
    for (g, (w, we)) in st.gear2.iter().enumerate() {
        let flank = if g.is_multiple_of(2) {
            "dedendum"
        } else {
            "addendum"
        };
        let _ = writeln!(csv, "2,{g},{flank},,,,,,,,{},{}", num(*w), num(*we));
    }
    Table {
        suffix: "contact-stress".into(),
        caption: "Contact stress and Archard wear per tooth flank (arch): the loaded stretch of each arch of gear 1 (α1), the largest p0 (at a working window's end) and the least, and W = ∫F|v_s|dt over a cycle for both gears".into(),
        csv,
    }
}

/// p0 (MPa) along the loaded flanks against α1 (deg), gaps outside the working windows,
/// with each window's largest and least marked; and W per arch of both gears over a cycle.
fn stress_plot(scene: &Scene, out: &Outcome) -> Result<Vec<Panel>, PlotError> {
    let Some(st) = out.teeth.as_ref().and_then(|t| t.stress.as_ref()) else {
        return Err(PlotError::data("no contact-stress outputs"));
    };
    let mpa = 1e-6;
    let mut line = Vec::new();
    for a in &st.arches {
        line.extend(a.samples.iter().map(|&(x, p)| (x.to_degrees(), p * mpa)));
        line.push((f64::NAN, f64::NAN));
    }
    let mark = |f: &dyn Fn(&ArchStress) -> Option<StressPoint>| {
        st.arches
            .iter()
            .filter_map(|a| f(a).map(|p| (p.alpha1.to_degrees(), p.p0_pa * mpa)))
            .collect::<Vec<_>>()
    };
    let stress = Panel {
        title: format!("{}: Hertz pressure along the driving flanks", scene.name),
        x_label: "α1, angle of gear 1 (deg)".into(),
        y_label: "p0 (MPa)".into(),
        series: vec![
            Series::line("p0 on the working windows", line),
            Series::points("largest (window's end)", mark(&|a| a.peak)),
            Series::points("least", mark(&|a| a.least)),
        ],
        equal_aspect: false,
    };
    let bars = |v: &[(f64, f64)]| {
        v.iter()
            .enumerate()
            .map(|(i, w)| (i as f64, w.0))
            .collect::<Vec<_>>()
    };
    let wear = Panel {
        title: "Archard load-weighted sliding per flank over a cycle".into(),
        x_label: "arch index (–)".into(),
        y_label: "W = ∫F|v_s|dt (N·m)".into(),
        series: vec![
            Series::points("gear 1", bars(&st.gear1)),
            Series::points("gear 2", bars(&st.gear2)),
        ],
        equal_aspect: false,
    };
    for p in [&stress, &wear] {
        plot::has_unit(&p.x_label)?;
        plot::has_unit(&p.y_label)?;
    }
    Ok(vec![stress, wear])
}

/// ρ_K1, ρ_K2 (mm) and V_K1, V_K2, v_t1, v_t2, v_s (m/s) against α1, over one turn and on
/// two arches (the paper's Fig. 5 and 6).
fn contact_plot(scene: &Scene, out: &Outcome) -> Result<Vec<Panel>, PlotError> {
    let Some(t) = &out.teeth else {
        return Err(PlotError::data("no tooth-level outputs"));
    };
    // Zoom on the addendum arch k and the dedendum arch k + 1, k = N/4 made even, between
    // their cusps (the zeros of µ).
    let n_arch = out.derived.arches_gear1.max(2.0) as usize;
    let k = (n_arch / 4) & !1;
    let cusp = |i: usize| {
        if i >= n_arch {
            TAU
        } else {
            // The zeros are the cusps in α1 order: zero i starts arch i.
            out.zeros
                .get(i)
                .map_or(TAU * i as f64 / n_arch as f64, |z| z.alpha1_rad)
        }
    };
    let (z0, z1) = (cusp(k), cusp(k + 2));
    let pts = |f: &dyn Fn(&crate::families::gear::teeth::ContactKinematics) -> f64, zoom: bool| {
        t.contact
            .iter()
            .filter(|c| !zoom || (z0..=z1).contains(&c.alpha1))
            .map(|c| (c.alpha1.to_degrees(), f(c)))
            .collect::<Vec<_>>()
    };
    let x_label = "α1, angle of gear 1 (deg)".to_string();
    let radii = Panel {
        title: format!("{}: contact-point radii", scene.name),
        x_label: x_label.clone(),
        y_label: "ρ_K (mm)".into(),
        series: vec![
            Series::line("ρ_K1 = |O1K|", pts(&|c| c.rho_k1 * 1e3, false)),
            Series::line("ρ_K2 = |O2K|", pts(&|c| c.rho_k2 * 1e3, false)),
        ],
        equal_aspect: false,
    };
    let vel = |zoom: bool| Panel {
        title: if zoom {
            format!(
                "zoom: arches {k} (addendum) and {} (dedendum) of gear 1",
                k + 1
            )
        } else {
            "contact-point velocities".into()
        },
        x_label: x_label.clone(),
        y_label: "velocity (m/s)".into(),
        series: vec![
            Series::line("V_K1", pts(&|c| c.v_k1, zoom)),
            Series::line("V_K2", pts(&|c| c.v_k2, zoom)),
            Series::line("v_t1", pts(&|c| c.v_t1, zoom)),
            Series::line("v_t2", pts(&|c| c.v_t2, zoom)),
            Series::line("v_s = v_t1 − v_t2", pts(&|c| c.v_slide, zoom)),
        ],
        equal_aspect: false,
    };
    for p in [&radii, &vel(false)] {
        plot::has_unit(&p.x_label)?;
        plot::has_unit(&p.y_label)?;
    }
    Ok(vec![radii, vel(false), vel(true)])
}
