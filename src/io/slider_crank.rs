//! The slider-crank problem file: its raw sections and their resolution into a checked
//! [`crate::synth::slider_crank::Scene`]. Every field is documented in
//! `docs/problem-files.md`.

use super::problem::{
    check_name, non_negative, positive, resolve_paper, Ctx, FieldError, ProblemError, RawFile,
    RawVar, Scene, SceneKind,
};
use crate::mech::slider_crank::{Crank, Kinematics, Rod, SliderCrank};
use crate::synth::counterweight::Settings;
use crate::synth::slider_crank::{self as sc, CounterweightSpec, Objective, Prefer};
use crate::synth::Var;
use crate::units::{Angle, AngularSpeed, Force, Inertia, Length, Mass, Qty, Unbalance};
use serde::Deserialize;
use std::f64::consts::{PI, TAU};

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
