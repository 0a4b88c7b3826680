//! The slider-crank problem file — its raw sections and their resolution into a checked
//! [`crate::synth::slider_crank::Scene`] (every field documented in
//! `docs/problem-files.md`) — and the shaping of its outcome into a result (keys in
//! `docs/results.md`).

use super::plot::{self, Panel, Series};
use super::problem::{
    check_name, non_negative, positive, resolve_paper, Ctx, FieldError, ProblemError, RawFile,
    RawVar, Scene, SceneKind,
};
use super::result::{Plot, SolveResult, Status};
use crate::geom::P2;
use crate::mech::slider_crank::{Crank, Kinematics, Rod, SliderCrank};
use crate::synth::counterweight::Settings;
use crate::synth::counterweight::Status as CwStatus;
use crate::synth::slider_crank::shaking_force;
use crate::synth::slider_crank::{self as sc, CounterweightSpec, Objective, Prefer};
use crate::synth::Var;
use crate::units::{Angle, AngularSpeed, Force, Inertia, Length, Mass, Qty, Unbalance};
use serde::Deserialize;
use serde_json::json;
use std::collections::BTreeMap;
use std::f64::consts::{PI, TAU};
use std::time::Instant;

/// `[mechanism]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MechanismRaw {
    /// R.
    pub crank_radius: Qty<Length>,
    /// L.
    pub rod_length: Qty<Length>,
    /// e (default 0).
    #[serde(default)]
    pub offset: Option<Qty<Length>>,
    /// n or ω.
    pub speed: Qty<AngularSpeed>,
    /// m2.
    pub crank_mass: Qty<Mass>,
    /// r2 (default R/2).
    #[serde(default)]
    pub crank_centroid: Option<Qty<Length>>,
    /// m3.
    pub rod_mass: Qty<Mass>,
    /// m4.
    pub slider_mass: Qty<Mass>,
}

/// How the rod's mass is modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Masses {
    /// Two point masses (rod split).
    #[default]
    Lumped,
    /// A rigid rod with centre of mass and moment of inertia.
    Rigid,
}

/// `[model]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ModelRaw {
    /// `exact` (default) or `two-harmonic`.
    #[serde(default)]
    pub kinematics: Option<Kinematics>,
    /// `lumped` (default) or `rigid`.
    #[serde(default)]
    pub masses: Masses,
    /// Lumped: fraction of the rod mass at the crank pin (default 0.5).
    #[serde(default)]
    pub rod_split: Option<f64>,
    /// Rigid: rod centre of mass from the crank pin (default L/2).
    #[serde(default)]
    pub rod_centroid: Option<Qty<Length>>,
    /// Rigid: rod moment of inertia about its centre of mass (default m3 L²/12).
    #[serde(default)]
    pub rod_inertia: Option<Qty<Inertia>>,
}

/// `[design]`: the counterweight.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct DesignRaw {
    /// |U| = m r.
    #[serde(default)]
    pub unbalance: Option<RawVar<Unbalance>>,
    /// β from the crank line.
    #[serde(default)]
    pub angle: Option<RawVar<Angle>>,
    /// m.
    #[serde(default)]
    pub mass: Option<RawVar<Mass>>,
    /// r.
    #[serde(default)]
    pub radius: Option<RawVar<Length>>,
    /// Split preference.
    #[serde(default)]
    pub prefer: Prefer,
}

/// What `objective.minimize` can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Minimize {
    /// Peak |F|.
    PeakForce,
    /// RMS |F|.
    RmsForce,
    /// Counterweight mass under `max_peak_force`.
    Mass,
    /// Counterweight radius under `max_peak_force`.
    Radius,
}

/// `[objective]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectiveRaw {
    /// What to minimise.
    pub minimize: Minimize,
    /// Peak shaking-force limit.
    #[serde(default)]
    pub max_peak_force: Option<Qty<Force>>,
}

/// `[accuracy]` for the counterweight solvers (see [`Settings`]).
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct AccuracyRaw {
    /// Relative optimality gap.
    pub rel_tol: Option<f64>,
    /// First SOCP's angles.
    pub initial_samples: Option<usize>,
    /// Scan density of the peak search.
    pub scan_samples: Option<usize>,
    /// Exchange rounds at most.
    pub max_rounds: Option<usize>,
    /// Angle tolerance of the peak refinement.
    pub peak_xtol: Option<f64>,
    /// RMS quadrature points.
    pub rms_samples: Option<usize>,
    /// Near-active band kept between rounds.
    pub keep_band: Option<f64>,
}

impl AccuracyRaw {
    /// Defaults overridden by the file, validated.
    pub fn resolve(&self) -> Result<Settings, FieldError> {
        let d = Settings::default();
        let s = Settings {
            rel_tol: self.rel_tol.unwrap_or(d.rel_tol),
            initial_samples: self.initial_samples.unwrap_or(d.initial_samples),
            scan_samples: self.scan_samples.unwrap_or(d.scan_samples),
            max_rounds: self.max_rounds.unwrap_or(d.max_rounds),
            peak_xtol: self.peak_xtol.unwrap_or(d.peak_xtol),
            rms_samples: self.rms_samples.unwrap_or(d.rms_samples),
            keep_band: self.keep_band.unwrap_or(d.keep_band),
        };
        s.validate()
            .map_err(|(f, m)| FieldError::new(format!("accuracy.{f}"), m))?;
        Ok(s)
    }
}

/// The whole slider-crank file.
pub type File = RawFile<MechanismRaw, ModelRaw, DesignRaw, ObjectiveRaw, AccuracyRaw>;

/// Parses and resolves a slider-crank problem file.
pub fn resolve(ctx: &Ctx, text: &str) -> Result<Scene, ProblemError> {
    let raw: File = ctx.parse(text)?;
    let scene = resolve_raw(&raw).map_err(|e| ctx.field_error(e))?;
    Ok(Scene {
        name: raw.name.clone(),
        family: raw.family,
        description: raw.description.clone(),
        source: ctx.file.into(),
        paper: resolve_paper(&raw.paper),
        kind: SceneKind::SliderCrank(scene),
    })
}

/// The value checks of a slider-crank file.
pub fn resolve_raw(raw: &File) -> Result<sc::Scene, FieldError> {
    check_name(&raw.name)?;
    let m = &raw.mechanism;
    let r = positive("mechanism.crank_radius", m.crank_radius.si())?;
    let l = positive("mechanism.rod_length", m.rod_length.si())?;
    let e = m.offset.map_or(0.0, |q| q.si());
    let omega = positive("mechanism.speed", m.speed.si())?;
    let m2 = non_negative("mechanism.crank_mass", m.crank_mass.si())?;
    let m3 = non_negative("mechanism.rod_mass", m.rod_mass.si())?;
    let m4 = non_negative("mechanism.slider_mass", m.slider_mass.si())?;
    let r2 = non_negative(
        "mechanism.crank_centroid",
        m.crank_centroid.map_or(0.5 * r, |q| q.si()),
    )?;
    let ratio = (r + e.abs()) / l;
    if ratio >= 1.0 {
        return Err(FieldError::new(
            "mechanism.rod_length",
            format!(
                "the crank cannot turn a full revolution: (R + |e|)/L = {ratio:.6} ≥ 1 (λ = R/L = {:.6}); allowed: rod_length > crank_radius + |offset| = {} m",
                r / l,
                r + e.abs()
            ),
        ));
    }
    if m2 + m3 + m4 <= 0.0 {
        return Err(FieldError::new(
            "mechanism.slider_mass",
            "all link masses are zero: nothing to balance; allowed: some mass > 0",
        ));
    }
    let md = &raw.model;
    let kinematics = md.kinematics.unwrap_or(Kinematics::Exact);
    if kinematics == Kinematics::TwoHarmonic && e != 0.0 {
        return Err(FieldError::new(
            "model.kinematics",
            "the two-harmonic series is the in-line slider's; with an offset use \"exact\"",
        ));
    }
    let rod = match md.masses {
        super::slider_crank::Masses::Lumped => {
            if md.rod_centroid.is_some() || md.rod_inertia.is_some() {
                let f = if md.rod_centroid.is_some() {
                    "model.rod_centroid"
                } else {
                    "model.rod_inertia"
                };
                return Err(FieldError::new(
                    f,
                    "only used with masses = \"rigid\"; a lumped rod takes rod_split",
                ));
            }
            let s = md.rod_split.unwrap_or(0.5);
            if !(0.0..=1.0).contains(&s) {
                return Err(FieldError::new(
                    "model.rod_split",
                    format!("got {s}; allowed: 0 ≤ rod_split ≤ 1 (fraction at the crank pin)"),
                ));
            }
            Rod::lumped(m3, s, l)
        }
        super::slider_crank::Masses::Rigid => {
            if md.rod_split.is_some() {
                return Err(FieldError::new("model.rod_split", "only used with masses = \"lumped\"; a rigid rod takes rod_centroid and rod_inertia"));
            }
            let c = md.rod_centroid.map(|q| q.si());
            if let Some(c) = c {
                if !(0.0..=l).contains(&c) {
                    return Err(FieldError::new(
                        "model.rod_centroid",
                        format!("got {c} m; allowed: 0 ≤ rod_centroid ≤ rod_length = {l} m"),
                    ));
                }
            }
            let i = md.rod_inertia.map(|q| q.si());
            if let Some(i) = i {
                non_negative("model.rod_inertia", i)?;
            }
            Rod::rigid(m3, l, c, i)
        }
    };
    let mech = SliderCrank {
        r,
        l,
        e,
        kinematics,
        crank: Crank {
            mass: m2,
            centroid: r2,
        },
        rod,
        slider_mass: m4,
    };

    let d = &raw.design;
    let var = |v: &Option<RawVar<_>>, f: &str, default: Var| -> Result<Var, FieldError> {
        let v = v.map(|v| v.resolve(f)).transpose()?.unwrap_or(default);
        let (lo, _) = v.bounds();
        non_negative(f, lo)?;
        Ok(v)
    };
    let unbalance = var(
        &d.unbalance,
        "design.unbalance",
        Var::Free {
            min: 0.0,
            max: f64::INFINITY,
        },
    )?;
    let mass = d.mass.map(|v| v.resolve("design.mass")).transpose()?;
    let radius = d.radius.map(|v| v.resolve("design.radius")).transpose()?;
    for (v, f) in [(mass, "design.mass"), (radius, "design.radius")] {
        if let Some(v) = v {
            non_negative(f, v.bounds().0)?;
        }
    }
    if let (Some(Var::Fixed(mm)), Some(Var::Fixed(rr))) = (mass, radius) {
        if !unbalance.contains(mm * rr) {
            return Err(FieldError::new(
                "design.unbalance",
                format!(
                    "mass × radius = {} kg·m is outside the unbalance bounds {:?}",
                    mm * rr,
                    unbalance.bounds()
                ),
            ));
        }
    }
    let angle = match d.angle.map(|v| v.resolve("design.angle")).transpose()? {
        None => Var::Free { min: 0.0, max: TAU },
        Some(Var::Free { min, max }) if max - min < TAU - 1e-9 && max - min > PI + 1e-12 => {
            return Err(FieldError::new(
                "design.angle",
                format!(
                    "a range {:.3}° wide is not convex; allowed: a fixed angle, a range at most 180° wide, or the full circle (360°)",
                    (max - min).to_degrees()
                ),
            ))
        }
        Some(v) => v,
    };
    let o = &raw.objective;
    let objective = match o.minimize {
        Minimize::PeakForce => Objective::MinPeakForce,
        Minimize::RmsForce => Objective::MinRmsForce,
        Minimize::Mass => Objective::MinMass,
        Minimize::Radius => Objective::MinRadius,
    };
    let max_peak_force = o
        .max_peak_force
        .map(|q| positive("objective.max_peak_force", q.si()))
        .transpose()?;
    if matches!(objective, Objective::MinMass | Objective::MinRadius) {
        if max_peak_force.is_none() {
            return Err(FieldError::new(
                "objective.max_peak_force",
                "missing: minimize = \"mass\" or \"radius\" needs a peak-force limit (e.g. \"400 N\")",
            ));
        }
        if mass.is_none() || radius.is_none() {
            return Err(FieldError::new(
                "objective.minimize",
                "minimizing the counterweight's mass or radius needs design.mass and design.radius (fixed or ranges)",
            ));
        }
    }
    let settings = raw.accuracy.resolve()?;
    Ok(sc::Scene {
        mech,
        omega,
        counterweight: CounterweightSpec {
            unbalance,
            angle,
            mass,
            radius,
            prefer: d.prefer,
        },
        objective,
        max_peak_force,
        settings,
    })
}

/// The result of a slider-crank scene: solve, then shape keys, errors, baselines, plot.
pub fn result(scene: &Scene, s: &sc::Scene) -> SolveResult {
    let mut r = SolveResult::new(scene);
    let m = &s.mech;
    r.model = BTreeMap::from([
        (
            "kinematics".into(),
            json!(match m.kinematics {
                Kinematics::Exact => "exact",
                Kinematics::TwoHarmonic => "two-harmonic",
            }),
        ),
        (
            "rod_centroid_from_crank_pin_m".into(),
            json!(m.rod.centroid),
        ),
        ("rod_inertia_kgm2".into(), json!(m.rod.inertia)),
        ("offset_m".into(), json!(m.e)),
        ("gravity".into(), json!("not modelled")),
    ]);
    let t0 = Instant::now();
    let out = match sc::solve(s) {
        Ok(o) => o,
        Err(e) => {
            r.warnings.push(e.to_string());
            return r;
        }
    };
    r.timing.solve_s = t0.elapsed().as_secs_f64();
    let free =
        s.counterweight.angle.fixed().is_none() || s.counterweight.unbalance.fixed().is_none();
    r.status = match out.status {
        CwStatus::Optimal if !free => Status::Analysed,
        CwStatus::Optimal => Status::Optimal,
        CwStatus::Inaccurate => Status::Inaccurate,
        CwStatus::Infeasible => Status::Infeasible,
        CwStatus::Failed => Status::Failed,
    };
    r.method = out.method.clone();
    r.warnings.extend(out.warnings.iter().cloned());
    let d = &out.design;
    let u = P2::new(d.unbalance[0], d.unbalance[1]);
    r.design
        .insert("counterweight_unbalance_kgm".into(), u.norm());
    r.design.insert(
        "counterweight_angle_rad".into(),
        if u.norm() > 0.0 {
            u.y.atan2(u.x).rem_euclid(std::f64::consts::TAU)
        } else {
            0.0
        },
    );
    r.design.insert("counterweight_unbalance_x_kgm".into(), u.x);
    r.design.insert("counterweight_unbalance_y_kgm".into(), u.y);
    if let Some(mass) = out.mass {
        r.design.insert("counterweight_mass_kg".into(), mass);
    }
    if let Some(rad) = out.radius {
        r.design.insert("counterweight_radius_m".into(), rad);
    }
    r.objectives.insert("peak_shaking_force_n".into(), d.peak);
    r.objectives.insert("rms_shaking_force_n".into(), d.rms);
    r.objectives
        .insert("peak_drive_torque_nm".into(), out.peak_drive_torque);
    r.objectives
        .insert("peak_shaking_moment_nm".into(), out.peak_shaking_moment);
    r.errors
        .insert("peak_shaking_force_n".into(), out.gap + d.peak_error);
    r.errors.insert("rms_shaking_force_n".into(), d.rms_error);
    // Torque and moment are refined like the force; their scan error bound is of the same
    // (round-off) order and reported as the force's relative refinement error.
    let rel = d.peak_error / d.peak.max(1e-300);
    r.errors
        .insert("peak_drive_torque_nm".into(), rel * out.peak_drive_torque);
    r.errors.insert(
        "peak_shaking_moment_nm".into(),
        rel * out.peak_shaking_moment,
    );
    let (mt, mc) = (m.m_rot(), m.m_rec());
    r.derived = BTreeMap::from([
        ("lambda".into(), m.lambda()),
        ("omega_rad_s".into(), s.omega),
        ("rotating_mass_kg".into(), mt),
        ("reciprocating_mass_kg".into(), mc),
        (
            "reciprocating_fraction_balanced".into(),
            if mc > 0.0 {
                (-u.x / m.r - mt) / mc
            } else {
                0.0
            },
        ),
        ("peak_angle_rad".into(), d.peak_angle),
        ("peak_to_peak_x_n".into(), d.ptp_x),
        ("peak_to_peak_y_n".into(), d.ptp_y),
        ("optimality_gap_n".into(), out.gap),
    ]);
    if let Some(ex) = out.exact_peak {
        r.derived
            .insert("peak_shaking_force_exact_kinematics_n".into(), ex);
        r.errors
            .insert("model_two_harmonic_n".into(), (ex - d.peak).abs());
    }
    for (name, b) in &out.baselines {
        let mut map = b.to_map();
        map.insert(
            "improvement_pct".into(),
            100.0 * (b.peak - d.peak) / b.peak.max(1e-300),
        );
        r.baselines.insert(name.clone(), map);
    }
    match slider_crank_plot(scene, s, &out) {
        Ok(p) => r.plots.push(p),
        Err(e) => r.warnings.push(format!("plot failed: {e}")),
    }
    r
}

fn slider_crank_plot(scene: &Scene, s: &sc::Scene, out: &sc::Outcome) -> Result<Plot, String> {
    let n = 361;
    let curves: Vec<(String, P2)> = [
        ("no counterweight".to_string(), P2::zeros()),
        ("optimum".to_string(), P2::from(out.design.unbalance)),
    ]
    .into_iter()
    .chain(
        out.baselines
            .get("fifty_percent")
            .map(|b| ("50 % rule".to_string(), P2::from(b.unbalance))),
    )
    .collect();
    let mut locus = Vec::new();
    let mut mag = Vec::new();
    for (name, u) in &curves {
        let pts: Vec<P2> = (0..n)
            .map(|k| {
                let phi = k as f64 * std::f64::consts::TAU / (n - 1) as f64;
                shaking_force(&s.mech, s.omega, *u, phi).unwrap_or(P2::new(f64::NAN, f64::NAN))
            })
            .collect();
        locus.push(Series::line(
            name.clone(),
            pts.iter().map(|p| (p.x, p.y)).collect(),
        ));
        mag.push(Series::line(
            name.clone(),
            pts.iter()
                .enumerate()
                .map(|(k, p)| (k as f64, p.norm()))
                .collect(),
        ));
    }
    let f_opt = shaking_force(
        &s.mech,
        s.omega,
        P2::from(out.design.unbalance),
        out.design.peak_angle,
    )
    .unwrap_or(P2::zeros());
    locus.push(Series::marker("peak of optimum", vec![(f_opt.x, f_opt.y)]));
    mag.push(Series::marker(
        "peak of optimum",
        vec![(out.design.peak_angle.to_degrees(), out.design.peak)],
    ));
    let svg = plot::panels(
        &[
            Panel {
                title: format!("{}: shaking force locus", scene.name),
                x_label: "Fx (N)".into(),
                y_label: "Fy (N)".into(),
                series: locus,
                equal_aspect: true,
            },
            Panel {
                title: "|F| against crank angle".into(),
                x_label: "crank angle φ (deg)".into(),
                y_label: "|F| (N)".into(),
                series: mag,
                equal_aspect: false,
            },
        ],
        560,
        480,
    )?;
    Ok(Plot {
        suffix: "shaking-force".into(),
        caption: "Shaking force with and without counterweight".into(),
        svg,
    })
}
