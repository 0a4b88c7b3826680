//! The eccentric-gear problem file — its raw sections and their resolution into a checked
//! [`crate::families::gear::synth::GearScene`] with its [`Settings`] (every field documented in
//! `docs/problem-files.md`) — and the shaping of its outcome into a result (keys in
//! `docs/results.md`): pitch curves, i12(α1), µ1 and µ2 with their poles, the design sweep.

use crate::families::gear::stress::ToothLoad;
use crate::families::gear::synth::{GearScene, Settings, SolveError, TeethOptions};
use crate::problem::limits::{self, c, Count};
use crate::problem::{
    check_name, non_negative, positive, Ctx, FieldError, Input, ProblemError, RawFile, RawVar,
    Resolved,
};
use crate::units::{Angle, AngularSpeed, Length, Pressure, Qty, Torque};
use serde::Deserialize;
use std::f64::consts::PI;

/// `[mechanism]`: the pair and the stated gear data (checked, never silently used).
/// The `family = "…"` value of this family's files.
pub const FAMILY: &str = "eccentric-gear";

/// The problem file `cwsynth new` prints: the shipped `problems/gear-eccentricity-design.toml`, a design with no
/// paper's numbers to check.
pub const TEMPLATE: &str = include_str!("../../../problems/gear-eccentricity-design.toml");

/// The work budget of one scene (see [`limits::check_work`] and `check_work` below):
/// every single integer setting at its maximum passes on the shipped files, their products
/// do not, so one machine runs in seconds and can neither stall a batch nor exhaust memory.
pub const WORK_BUDGET: f64 = 3e7;

/// The integer keys of this family's file and their ranges (see [`limits`]).
pub const COUNTS: &[Count] = &[
    c("mechanism.turns_gear1", 1, 100),
    c("mechanism.turns_gear2", 1, 100),
    c("mechanism.teeth_gear1", 1, 10_000),
    c("mechanism.teeth_gear2", 1, 10_000),
    c("accuracy.samples_per_arch", 8, 1000),
    c("accuracy.peak_samples_per_arch", 8, 1000),
    c("accuracy.curvature_samples", 64, 50_000),
    c("accuracy.series_points", 16, 20_000),
    c("accuracy.curve_points", 16, 10_000),
    c("accuracy.sweep_points", 3, 101),
    c("model.profile_points_per_arch", 4, 2000),
];

#[derive(Debug, Deserialize, schemars::JsonSchema)]
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
    /// The driving torque and the teeth's material: Hertz stress and Archard wear per flank
    /// (only with `model.tooth_profiles = true`).
    pub load: Option<LoadRaw>,
}

/// `[mechanism.load]`: what the teeth carry (see [`crate::families::gear::stress`]).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LoadRaw {
    /// T1, the driving torque on gear 1 (constant), > 0.
    pub torque: Qty<Torque>,
    /// b, the face width of both gears, > 0.
    pub face_width: Qty<Length>,
    /// E, Young's modulus of both gears, > 0.
    pub youngs_modulus: Qty<Pressure>,
    /// ν, Poisson's ratio of both gears, in [0, 0.5).
    pub poisson_ratio: f64,
}

/// `[model]`.
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelRaw {
    /// Half-width in α1 of the window left out around every pole (and 0/0 cusp).
    pub pole_window: Option<Qty<Angle>>,
    /// Tooth-level outputs (default false): the tooth outlines of both gears (drawn and
    /// written as `<name>-tooth-profiles.csv`), the contact-point radii ρ_K and velocities
    /// V_K, v_t, v_s over a turn (`<name>-contact.csv`, plot `contact`), the sliding distance
    /// ∫|v_t1 − v_t2| dt per tooth flank over a cycle (table `flank_wear`), the sliding
    /// coefficients of the circular cycloidal and involute equivalents (table
    /// `sliding_comparison`) and the pole certificate. Off: the result is that of a file
    /// without the key.
    pub tooth_profiles: Option<bool>,
    /// Points per arch of the tooth outlines (default 48; only with `tooth_profiles = true`).
    pub profile_points_per_arch: Option<u32>,
    /// Pressure angle of the standard involute pair compared with (default "20 deg"; only
    /// with `tooth_profiles = true`), in (0, 45°).
    pub involute_pressure_angle: Option<Qty<Angle>>,
}

/// `[design]`.
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignRaw {
    /// e: fixed (analysis) or a range (design).
    pub eccentricity: Option<RawVar<Length>>,
}

/// What `objective.maximize` can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Maximize {
    /// i12max/i12min.
    RatioVariation,
}

/// `[objective]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
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
    limits::check_section(COUNTS, "accuracy", &s)?;
    match s.validate() {
        Ok(()) => {}
        Err(SolveError::Settings { key, message }) => {
            return Err(FieldError::new(
                format!("accuracy.{key}"),
                format!(
                    "{key} {message}; got {}",
                    serde_json::to_value(&s)
                        .ok()
                        .and_then(|v| v.get(key).map(|x| x.to_string()))
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
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Resolved<GearProblem>, ProblemError> {
    File::resolve(ctx, input, resolve_raw)
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
            limits::check(COUNTS, key, v.into())?;
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
    let tooth_outputs = resolve_teeth(&raw.model, m.load.as_ref())?;
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
        tooth_outputs,
    };
    gear.validate().map_err(|f| {
        let allowed = if f.message.contains("allowed") {
            String::new()
        } else {
            "; allowed: see docs/problem-files.md, family eccentric-gear".into()
        };
        FieldError::new(f.field, format!("{}{allowed}", f.message))
    })?;
    let settings = resolve_accuracy(&raw.accuracy)?;
    check_work(&gear, &settings)?;
    Ok(GearProblem { gear, settings })
}

/// The `model.tooth_profiles` options: `None` when off; the point count, the involute
/// pressure angle and the load only with it.
fn resolve_teeth(m: &ModelRaw, load: Option<&LoadRaw>) -> Result<Option<TeethOptions>, FieldError> {
    if m.tooth_profiles != Some(true) {
        for (key, given) in [
            ("mechanism.load", load.is_some()),
            (
                "model.profile_points_per_arch",
                m.profile_points_per_arch.is_some(),
            ),
            (
                "model.involute_pressure_angle",
                m.involute_pressure_angle.is_some(),
            ),
        ] {
            if given {
                return Err(FieldError::new(
                    key,
                    "applies only with model.tooth_profiles = true; allowed: set tooth_profiles = true or remove the key",
                ));
            }
        }
        return Ok(None);
    }
    let mut t = TeethOptions::default();
    if let Some(n) = m.profile_points_per_arch {
        limits::check(COUNTS, "model.profile_points_per_arch", n.into())?;
        t.points_per_arch = n as usize;
    }
    if let Some(q) = m.involute_pressure_angle {
        let a = q.si();
        if !(a.is_finite() && a > 0.0 && a < PI / 4.0) {
            return Err(FieldError::new(
                "model.involute_pressure_angle",
                format!("must be in (0, 45°), got {a} rad"),
            ));
        }
        t.involute_pressure_angle = a;
    }
    t.load = load.map(resolve_load).transpose()?;
    Ok(Some(t))
}

/// `[mechanism.load]` checked: positive torque, width and modulus, 0 ≤ ν < 0.5.
fn resolve_load(l: &LoadRaw) -> Result<ToothLoad, FieldError> {
    let nu = l.poisson_ratio;
    if !(nu.is_finite() && (0.0..0.5).contains(&nu)) {
        return Err(FieldError::new(
            "mechanism.load.poisson_ratio",
            format!("must be in [0, 0.5), got {nu}"),
        ));
    }
    Ok(ToothLoad {
        torque: positive("mechanism.load.torque", l.torque.si())?,
        face_width: positive("mechanism.load.face_width", l.face_width.si())?,
        youngs_modulus: positive("mechanism.load.youngs_modulus", l.youngs_modulus.si())?,
        poisson_ratio: nu,
    })
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
        WORK_BUDGET,
        FAMILY,
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
