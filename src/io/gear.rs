//! The eccentric-gear problem file — its raw sections and their resolution into a checked
//! [`crate::synth::gear::GearScene`] with its [`Settings`] (every field documented in
//! `docs/problem-files.md`) — and the shaping of its outcome into a result (keys in
//! `docs/results.md`): pitch curves, i12(α1), µ1 and µ2 with their poles, the design sweep.

use super::limits;
use super::plot::{self, Panel, Series};
use super::problem::Family;
use super::problem::{
    check_name, non_negative, positive, Ctx, FieldError, Input, ProblemError, RawFile, RawVar,
    Scene, SceneKind,
};
use super::result::{PaperCheck, Plot, SolveResult, Status, Table};
use crate::mech::gear::{EccentricCircle, GearPair, Which, ZeroKind};
use crate::synth::gear::{self as sg, GearScene, Outcome, Settings, SolveError};
use crate::units::{Angle, AngularSpeed, Length, Qty};
use serde::Deserialize;
use serde_json::json;
use std::collections::BTreeMap;
use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;
use std::time::Instant;

/// `[mechanism]`: the pair and the stated gear data (checked, never silently used).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MechanismRaw {
    /// R, gear 1's pitch-circle radius.
    pub pitch_radius: Qty<Length>,
    /// r, the generating (rolling) circle radius.
    pub generating_radius: Qty<Length>,
    /// n1.
    pub turns_gear1: u32,
    /// n2.
    pub turns_gear2: u32,
    /// ω1.
    pub speed: Qty<AngularSpeed>,
    /// Stated module m (checked).
    pub module: Option<Qty<Length>>,
    /// Stated z1 (checked).
    pub teeth_gear1: Option<u32>,
    /// Stated z2 (checked).
    pub teeth_gear2: Option<u32>,
    /// Stated pitch on the pitch curve (checked).
    pub tooth_pitch: Option<Qty<Length>>,
    /// Stated tooth thickness (checked).
    pub tooth_thickness: Option<Qty<Length>>,
    /// Stated space width (checked).
    pub space_width: Option<Qty<Length>>,
    /// Stated centre distance (checked; the pair uses the closing one).
    pub center_distance: Option<Qty<Length>>,
}

/// `[model]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ModelRaw {
    /// Half-width in α1 of the window left out around every pole (and 0/0 cusp).
    pub pole_window: Option<Qty<Angle>>,
}

/// `[design]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct DesignRaw {
    /// e: fixed (analysis) or a range (design).
    pub eccentricity: Option<RawVar<Length>>,
}

/// What `objective.maximize` can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Maximize {
    /// i12max/i12min.
    RatioVariation,
}

/// `[objective]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectiveRaw {
    /// What to maximise over a free e.
    pub maximize: Maximize,
    /// Limit of the peak |µ| on the working window.
    pub max_sliding_coefficient: Option<f64>,
    /// Gear 2's pitch curve must stay convex (default true).
    pub require_gear2_convex: Option<bool>,
    /// Limit of the pitch pressure angle asin(e/R).
    pub max_pressure_angle: Option<Qty<Angle>>,
}

/// `[accuracy]`: the family's solver [`Settings`] read directly (every key optional, unknown
/// keys rejected), then validated; errors name `accuracy.<key>`.
pub type AccuracyRaw = Settings;

/// Validates the `[accuracy]` section.
fn resolve_accuracy(s: &Settings) -> Result<Settings, FieldError> {
    let s = s.clone();
    // Above the maxima the analysis is slow and the files huge: a typo, not a wish.
    limits::check_section(Family::EccentricGear, "accuracy", &s)?;
    match s.validate() {
        Ok(()) => {}
        Err(SolveError::Settings(m)) => {
            let key = m.split_whitespace().next().unwrap_or("").to_string();
            return Err(FieldError::new(
                format!("accuracy.{key}"),
                format!(
                    "{m}; got {}",
                    serde_json::to_value(&s)
                        .ok()
                        .and_then(|v| v.get(&key).map(|x| x.to_string()))
                        .unwrap_or_else(|| "?".into())
                ),
            ));
        }
        Err(e) => return Err(FieldError::new("accuracy", e.to_string())),
    }
    Ok(s)
}

/// The whole eccentric-gear file.
pub type File = RawFile<MechanismRaw, ModelRaw, DesignRaw, ObjectiveRaw, AccuracyRaw>;

/// A resolved eccentric-gear scene: the pair and the numerical settings.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GearProblem {
    /// The pair, the stated data and the design constraints (SI).
    pub gear: GearScene,
    /// Numerical settings.
    pub settings: Settings,
}

/// Reads and resolves an eccentric-gear problem file (its text or its table).
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Scene, ProblemError> {
    File::resolve(ctx, input, resolve_raw, SceneKind::EccentricGear)
}

/// Default pole window: 0.01 rad, at most a tenth of an arch's half span π/N.
pub fn default_pole_window(n_arches: f64) -> f64 {
    0.01f64.min(0.1 * PI / n_arches.max(1.0))
}

/// The value checks of an eccentric-gear file.
pub fn resolve_raw(raw: &File) -> Result<GearProblem, FieldError> {
    check_name(&raw.name)?;
    let m = &raw.mechanism;
    let r = positive("mechanism.pitch_radius", m.pitch_radius.si())?;
    let rg = positive("mechanism.generating_radius", m.generating_radius.si())?;
    let omega1 = positive("mechanism.speed", m.speed.si())?;
    let opt = |q: Option<Qty<Length>>, f: &str| q.map(|q| positive(f, q.si())).transpose();
    let module = opt(m.module, "mechanism.module")?;
    let tooth_pitch = opt(m.tooth_pitch, "mechanism.tooth_pitch")?;
    let tooth_thickness = opt(m.tooth_thickness, "mechanism.tooth_thickness")?;
    let space_width = opt(m.space_width, "mechanism.space_width")?;
    let center_distance = opt(m.center_distance, "mechanism.center_distance")?;
    for (key, v) in [
        ("mechanism.turns_gear1", Some(m.turns_gear1)),
        ("mechanism.turns_gear2", Some(m.turns_gear2)),
        ("mechanism.teeth_gear1", m.teeth_gear1),
        ("mechanism.teeth_gear2", m.teeth_gear2),
    ] {
        if let Some(v) = v {
            limits::check(Family::EccentricGear, key, v.into())?;
        }
    }
    let teeth = match (m.teeth_gear1, m.teeth_gear2) {
        (Some(z1), Some(z2)) => Some((z1, z2)),
        (None, None) => None,
        (Some(_), None) => {
            return Err(FieldError::new(
                "mechanism.teeth_gear2",
                "missing: the tooth counts are checked as a pair; allowed: both teeth_gear1 and teeth_gear2, or neither",
            ))
        }
        (None, Some(_)) => {
            return Err(FieldError::new(
                "mechanism.teeth_gear1",
                "missing: the tooth counts are checked as a pair; allowed: both teeth_gear1 and teeth_gear2, or neither",
            ))
        }
    };
    let Some(e) = raw.design.eccentricity else {
        return Err(FieldError::new(
            "design.eccentricity",
            "missing; allowed: a fixed length (\"15 mm\": analysis) or a range { min = \"0 mm\", max = \"30 mm\" } (design), 0 ≤ e < mechanism.pitch_radius",
        ));
    };
    let eccentricity = e.resolve("design.eccentricity")?;
    let (lo, hi) = eccentricity.bounds();
    non_negative("design.eccentricity", lo)?;
    if hi >= r {
        return Err(FieldError::new(
            "design.eccentricity",
            format!(
                "e = {hi} m is not below mechanism.pitch_radius = {r} m: with e ≥ R the pivot is outside gear 1's pitch circle and the polar pitch curve does not exist; allowed: 0 ≤ e < R"
            ),
        ));
    }
    let n_arches = (r / rg).round();
    let pole_window = match raw.model.pole_window {
        Some(q) => non_negative("model.pole_window", q.si())?,
        None => default_pole_window(n_arches),
    };
    let o = &raw.objective;
    let Maximize::RatioVariation = o.maximize;
    let gear = GearScene {
        pitch_radius: r,
        generating_radius: rg,
        eccentricity,
        turns_gear1: m.turns_gear1,
        turns_gear2: m.turns_gear2,
        omega1,
        module,
        teeth,
        tooth_pitch,
        tooth_thickness,
        space_width,
        center_distance,
        pole_window,
        max_sliding_coefficient: o.max_sliding_coefficient,
        require_gear2_convex: o.require_gear2_convex.unwrap_or(true),
        max_pressure_angle: o.max_pressure_angle.map(|q| q.si()),
    };
    gear.validate().map_err(|f| {
        let allowed = if f.message.contains("allowed") {
            String::new()
        } else {
            "; allowed: see docs/problem-files.md, family eccentric-gear".into()
        };
        FieldError::new(f.key, format!("{}{allowed}", f.message))
    })?;
    let settings = resolve_accuracy(&raw.accuracy)?;
    check_work(&gear, &settings)?;
    Ok(GearProblem { gear, settings })
}

/// The work budget ([`limits::check_work`]): one analysis A = 2·N·n1·(s_arch + s_peak) +
/// n_curv + n_series + n_curve·(1 + n1/n2), N = R/r the arches of gear 1 (both pole functions
/// sampled over the N·n1 arches of a cycle); a design W = (n_sweep + 64)·A (the sweep, then at
/// most 64 Brent steps), an analysis W = A.
fn check_work(g: &GearScene, s: &Settings) -> Result<(), FieldError> {
    let d = Settings::default();
    let arches = (g.pitch_radius / g.generating_radius).round();
    let (n1, n2) = (f64::from(g.turns_gear1), f64::from(g.turns_gear2));
    let f = |v: usize| v as f64;
    let analysis = 2.0 * arches * n1 * f(s.samples_per_arch + s.peak_samples_per_arch)
        + f(s.curvature_samples + s.series_points)
        + f(s.curve_points) * (1.0 + n1 / n2);
    let free = matches!(g.eccentricity, crate::synth::Var::Free { .. });
    let estimate = if free {
        (f(s.sweep_points) + 64.0) * analysis
    } else {
        analysis
    };
    let t = |k, v: f64, d: usize| limits::term(k, v, d as f64);
    limits::check_work(
        Family::EccentricGear,
        estimate,
        "(sweep_points + 64, for a free eccentricity)·(2·(pitch_radius/generating_radius)·turns_gear1·(samples_per_arch + peak_samples_per_arch) + curvature_samples + series_points + curve_points·(1 + turns_gear1/turns_gear2))",
        &[
            t("mechanism.generating_radius", arches, 30),
            t("mechanism.turns_gear1", n1, 3),
            t("accuracy.sweep_points", if free { f(s.sweep_points) } else { 0.0 }, d.sweep_points),
            t("accuracy.samples_per_arch", f(s.samples_per_arch), d.samples_per_arch),
            t("accuracy.peak_samples_per_arch", f(s.peak_samples_per_arch), d.peak_samples_per_arch),
            t("accuracy.curvature_samples", f(s.curvature_samples), d.curvature_samples),
            t("accuracy.series_points", f(s.series_points), d.series_points),
            t("accuracy.curve_points", f(s.curve_points), d.curve_points),
        ],
    )
}

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
    let mut r = SolveResult::new(scene);
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
    r.design = out.design.clone();
    r.objectives = out.objectives.clone();
    r.errors = out.errors.clone();
    r.derived = out.derived.clone();
    r.warnings.extend(out.warnings.iter().cloned());
    r.paper = out
        .paper
        .iter()
        .map(|c| PaperCheck {
            quantity: c.quantity.clone(),
            key: c.key.clone(),
            paper: c.paper,
            computed: Some(c.computed),
            diff_pct: (c.paper != 0.0).then(|| 100.0 * (c.computed - c.paper) / c.paper.abs()),
            note: c.note.clone(),
        })
        .collect();
    r.extra.insert(
        "poles".into(),
        serde_json::to_value(&out.poles).expect("plain data"),
    );
    r.extra.insert(
        "zeros".into(),
        serde_json::to_value(&out.zeros).expect("plain data"),
    );
    if let Some(best) = out
        .sweep
        .iter()
        .filter(|s| s.feasible)
        .max_by(|a, b| a.ratio_variation.total_cmp(&b.ratio_variation))
    {
        r.derived.insert(
            "sweep_best_feasible_eccentricity_m".into(),
            best.eccentricity_m,
        );
    }
    if !out.sweep.is_empty() {
        r.derived.insert(
            "sweep_feasible_points".into(),
            out.sweep.iter().filter(|s| s.feasible).count() as f64,
        );
    }
    for res in [
        ratio_and_curves_plot(scene, &out),
        sliding_plot(scene, g, &out),
    ] {
        match res {
            Ok(pl) => r.plots.push(pl),
            Err(e) => r.warnings.push(format!("plot failed: {e}")),
        }
    }
    if !out.sweep.is_empty() {
        match sweep_plot(scene, g, &out) {
            Ok(pl) => r.plots.push(pl),
            Err(e) => r.warnings.push(format!("plot failed: {e}")),
        }
    }
    r.tables = tables(&out);
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
fn ratio_and_curves_plot(scene: &Scene, out: &Outcome) -> Result<Plot, String> {
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
    let (lo, hi) = (out.derived["ratio_min"], out.derived["ratio_max"]);
    let ratio = Panel {
        title: format!("i12 = ω1/ω2: min {lo:.4}, max {hi:.4}"),
        x_label: "α1, angle of gear 1 (deg)".into(),
        y_label: "i12 (–)".into(),
        series: vec![Series::line("i12(α1)", i12)],
        equal_aspect: false,
    };
    let svg = plot::panels(&[curves, ratio], 560, 480)?;
    Ok(Plot {
        suffix: "pitch-curves".into(),
        caption: "Pitch curves of both gears and the transmission function i12(α1)".into(),
        svg,
    })
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
fn sliding_plot(scene: &Scene, g: &GearScene, out: &Outcome) -> Result<Plot, String> {
    let s = &out.series;
    let n_arch = out.derived["arches_gear1"].max(1.0);
    let arch = TAU / n_arch;
    let w = out.derived["pole_window_rad"];
    let peak_at = out.derived["peak_sliding_alpha1_rad"];
    let peak = out.objectives["peak_sliding_coefficient"];
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
    let pair = EccentricCircle::new(g.pitch_radius, out.design["eccentricity_m"])
        .and_then(|c| {
            GearPair::new(
                c,
                g.generating_radius,
                out.derived["center_distance_m"],
                g.omega1,
            )
        })
        .map_err(|e| e.to_string())?;
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
    Ok(Plot {
        suffix: "sliding".into(),
        caption: "Sliding coefficients µ1, µ2 against α1, poles marked, pole windows left empty"
            .into(),
        svg,
    })
}

/// The eccentricity sweep: ratio variation, peak |µ|, gear 2's curvature.
fn sweep_plot(scene: &Scene, g: &GearScene, out: &Outcome) -> Result<Plot, String> {
    let mm = 1e3;
    let e_star = out.design["eccentricity_m"] * mm;
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
            vec![(e_star, out.objectives["ratio_variation"])],
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
            vec![(e_star, out.objectives["peak_sliding_coefficient"])],
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
                out.objectives["min_gear2_curvature_per_m"] * g.pitch_radius,
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
                out.objectives["max_pitch_pressure_angle_rad"].to_degrees(),
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
    Ok(Plot {
        suffix: "sweep".into(),
        caption: "Design sweep over the eccentricity e".into(),
        svg,
    })
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
