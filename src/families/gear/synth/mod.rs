//! Synthesis for the eccentric cycloidal non-circular gear pair: the resolved scene, the
//! consistency checks of the gear data (paper's Table 1), the full-cycle analysis that a
//! report needs, and the design of the eccentricity e.
//!
//! Exists to turn the pure model of [`crate::families::gear::model`] into one call, [`solve`],
//! whose [`Outcome`] serialises to the JSON contract of issue 6 (`design.eccentricity_m`,
//! `derived.center_distance_m`, `derived.ratio_min`, `derived.ratio_max`,
//! `objectives.peak_sliding_coefficient`, `poles`). The scene, settings and result types are
//! here; the analysis and the design of e in `design.rs`, the outcome of an analysis in
//! `outcome.rs`.
//!
//! Design problem: maximise the speed-ratio variation i12max/i12min over e subject to
//! (optional) gear 2 convex, peak |µ| on the working window ≤ a limit, and pitch pressure
//! angle asin(e/R) ≤ a limit. The search is a sweep over the bounds followed by argmin's
//! Brent (root of the worst constraint margin at a constraint boundary, or a bounded
//! maximisation of the objective for an interior optimum).

use crate::families::gear::model::{
    Closure, GearError, GearPair, MuPeak, Pole, Singularities, ZeroKind,
};
use crate::families::gear::stress::{FlankStress, ToothLoad};
use crate::families::gear::teeth::{
    BalancedShift, ContactKinematics, FlankWear, Involute, Profiles,
};
use crate::numeric::SearchError;
use crate::report::numbers::key;
use crate::synth::SearchEvidence;
use serde::Serialize;
use std::f64::consts::PI;

mod design;
mod outcome;

pub use design::{analyse, solve};
pub use outcome::{pitch_curves, report, teeth_outcome};

pub use crate::synth::Var;

/// A problem-file field that is not acceptable, named by its problem-file key
/// (e.g. `design.eccentricity`): the one [`crate::problem::FieldError`].
pub use crate::problem::FieldError;

fn field(key: &str, message: impl Into<String>) -> FieldError {
    FieldError::new(key, message)
}

/// Why [`solve`] returned no outcome: the input is impossible, not merely infeasible.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// A field of the scene is not acceptable.
    #[error(transparent)]
    Field(#[from] FieldError),
    /// The pair cannot be built (e.g. e ≥ R).
    #[error(transparent)]
    Gear(#[from] GearError),
    /// A settings value is not acceptable: the key of `[accuracy]` and what is allowed.
    #[error("accuracy.{key} {message}")]
    Settings {
        /// The settings key (`samples_per_arch`).
        key: &'static str,
        /// What is allowed (`must be ≥ 8`).
        message: &'static str,
    },
    /// A 1-D search failed on the analysed design.
    #[error("search failed: {0}")]
    Search(#[from] SearchError),
}

/// The resolved, SI scene of one gear-pair problem. Problem-file keys in brackets.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GearScene {
    /// Pitch-circle radius R of gear 1 (m) (`mechanism.pitch_radius`).
    pub pitch_radius: f64,
    /// Generating (rolling) circle radius r (m) (`mechanism.generating_radius`); R/r must be an
    /// even integer (one arch per turn of the circle, addendum and dedendum alternating).
    pub generating_radius: f64,
    /// Eccentricity e (m), 0 ≤ e < R (`design.eccentricity`); the design variable.
    pub eccentricity: Var,
    /// Turns of gear 1 per cycle n1 (`mechanism.turns_gear1`).
    pub turns_gear1: u32,
    /// Turns of gear 2 per cycle n2 (`mechanism.turns_gear2`).
    pub turns_gear2: u32,
    /// Driving speed ω1 (rad/s) (`mechanism.speed`).
    pub omega1: f64,
    /// Stated module m (m), checked against the pitch 4πr (`mechanism.module`).
    pub module: Option<f64>,
    /// Stated tooth counts (z1, z2), checked [`mechanism.teeth_gear1`, `mechanism.teeth_gear2`].
    pub teeth: Option<(u32, u32)>,
    /// Stated pitch on the pitch curve (m), checked (`mechanism.tooth_pitch`).
    pub tooth_pitch: Option<f64>,
    /// Stated tooth thickness on the pitch curve (m), checked (`mechanism.tooth_thickness`).
    pub tooth_thickness: Option<f64>,
    /// Stated space width on the pitch curve (m), checked (`mechanism.space_width`).
    pub space_width: Option<f64>,
    /// Stated centre distance (m) (`mechanism.center_distance`): checked and the ratio it gives
    /// reported; the pair itself is always built with the closing centre distance.
    pub center_distance: Option<f64>,
    /// Half-width (rad of α1) of the window excluded around every pole of µ and every 0/0
    /// cusp, for plots and the peak (`model.pole_window`).
    pub pole_window: f64,
    /// Upper limit of the peak |µ| on the working window (`objective.max_sliding_coefficient`).
    pub max_sliding_coefficient: Option<f64>,
    /// Require gear 2's pitch curve to be convex (`objective.require_gear2_convex`).
    pub require_gear2_convex: bool,
    /// Upper limit of the pressure angle at pitch-point contact, max |ψ| = asin(e/R) (rad)
    /// (`objective.max_pressure_angle`).
    pub max_pressure_angle: Option<f64>,
    /// The tooth-level outputs of issue 19 (`model.tooth_profiles`): tooth outlines, contact
    /// series, sliding distance per flank, involute comparison; `None`: off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tooth_outputs: Option<TeethOptions>,
}

/// What `model.tooth_profiles = true` computes, and how finely.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TeethOptions {
    /// Points per arch of the tooth outlines, ϕ = 2πk/m (`model.profile_points_per_arch`).
    pub points_per_arch: usize,
    /// Pressure angle of the involute pair compared with (rad)
    /// (`model.involute_pressure_angle`).
    pub involute_pressure_angle: f64,
    /// The stated driving torque and tooth material (`mechanism.load`): the Hertz contact
    /// stress and Archard wear per flank; `None`: not computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load: Option<ToothLoad>,
}

impl Default for TeethOptions {
    fn default() -> Self {
        Self {
            points_per_arch: 48,
            involute_pressure_angle: 20f64.to_radians(),
            load: None,
        }
    }
}

impl GearScene {
    /// Check every field; the error names the problem-file key and what is allowed.
    pub fn validate(&self) -> Result<(), FieldError> {
        let pos = |key: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(field(key, format!("must be a finite length > 0, got {v}")))
            }
        };
        pos("mechanism.pitch_radius", self.pitch_radius)?;
        pos("mechanism.generating_radius", self.generating_radius)?;
        let r = self.pitch_radius;
        let nf = r / self.generating_radius;
        let n = nf.round();
        if (nf - n).abs() > 1e-9 * nf || n < 2.0 || n % 2.0 != 0.0 {
            return Err(field(
                "mechanism.generating_radius",
                format!("R/r = {nf:.6} must be an even integer (twice the teeth of gear 1) for the cycloid arches (length 2πr each) to close around the pitch circle"),
            ));
        }
        let check_e = |v: f64, what: &str| {
            if !v.is_finite() || v < 0.0 {
                Err(field(
                    "design.eccentricity",
                    format!("{what} must be finite and ≥ 0, got {v}"),
                ))
            } else if v >= r {
                Err(field(
                    "design.eccentricity",
                    format!("{what} = {v} m must be < mechanism.pitch_radius = {r} m: with e ≥ R the pivot is outside gear 1's pitch circle and the polar pitch curve does not exist"),
                ))
            } else {
                Ok(())
            }
        };
        match self.eccentricity {
            Var::Fixed(e) => check_e(e, "e")?,
            Var::Free { min, max } => {
                check_e(min, "min")?;
                check_e(max, "max")?;
                if min >= max {
                    return Err(field(
                        "design.eccentricity",
                        format!("min = {min} must be < max = {max}"),
                    ));
                }
            }
        }
        if self.turns_gear1 == 0 {
            return Err(field("mechanism.turns_gear1", "must be an integer ≥ 1"));
        }
        if self.turns_gear2 == 0 {
            return Err(field("mechanism.turns_gear2", "must be an integer ≥ 1"));
        }
        let arches2 = n * self.turns_gear1 as f64 / self.turns_gear2 as f64;
        if (arches2 - arches2.round()).abs() > 1e-9 || arches2.round() % 2.0 != 0.0 {
            return Err(field(
                "mechanism.turns_gear2",
                format!("gear 2 would carry N·n1/n2 = {arches2} arches; it must be an even integer for its teeth to close"),
            ));
        }
        if !(self.omega1.is_finite() && self.omega1 > 0.0) {
            return Err(field(
                "mechanism.speed",
                format!("must be a finite speed > 0, got {}", self.omega1),
            ));
        }
        for (k, v) in [
            ("mechanism.module", self.module),
            ("mechanism.tooth_pitch", self.tooth_pitch),
            ("mechanism.tooth_thickness", self.tooth_thickness),
            ("mechanism.space_width", self.space_width),
            ("mechanism.center_distance", self.center_distance),
        ] {
            if let Some(v) = v {
                pos(k, v)?;
            }
        }
        if let Some((z1, z2)) = self.teeth {
            if z1 == 0 {
                return Err(field("mechanism.teeth_gear1", "must be ≥ 1"));
            }
            if z2 == 0 {
                return Err(field("mechanism.teeth_gear2", "must be ≥ 1"));
            }
        }
        if !(self.pole_window.is_finite() && self.pole_window >= 0.0 && self.pole_window < PI / n) {
            return Err(field(
                "model.pole_window",
                format!(
                    "must be in [0, π/N) = [0, {:.4}) rad, got {}",
                    PI / n,
                    self.pole_window
                ),
            ));
        }
        if let Some(m) = self.max_sliding_coefficient {
            if !(m.is_finite() && m > 0.0) {
                return Err(field(
                    "objective.max_sliding_coefficient",
                    format!("must be > 0, got {m}"),
                ));
            }
        }
        if let Some(g) = self.max_pressure_angle {
            if !(g.is_finite() && g > 0.0 && g < PI / 2.0) {
                return Err(field(
                    "objective.max_pressure_angle",
                    format!("must be in (0, 90°), got {g} rad"),
                ));
            }
        }
        Ok(())
    }
}

/// The paper's Table 1 (R = 37.5 mm, r = 1.25 mm, e = 15 mm, m = 5 mm, z = 12/36,
/// pitch 15.71 mm, tooth = space = 7.85 mm, a12 = 148 mm, n1/n2 = 3/1, ω1 = 15 rad/s),
/// analysed as stated (e fixed), pole window 0.01 rad.
pub fn paper_table1() -> GearScene {
    GearScene {
        pitch_radius: 37.5e-3,
        generating_radius: 1.25e-3,
        eccentricity: Var::Fixed(15e-3),
        turns_gear1: 3,
        turns_gear2: 1,
        omega1: 15.0,
        module: Some(5e-3),
        teeth: Some((12, 36)),
        tooth_pitch: Some(15.71e-3),
        tooth_thickness: Some(7.85e-3),
        space_width: Some(7.85e-3),
        center_distance: Some(148e-3),
        pole_window: 0.01,
        max_sliding_coefficient: None,
        require_gear2_convex: true,
        max_pressure_angle: None,
        tooth_outputs: None,
    }
}

/// The paper's pair with e free in [0, 30 mm]: largest ratio variation with gear 2 convex,
/// peak |µ| ≤ 0.6 on the working window and pitch pressure angle ≤ 30°.
pub fn paper_table1_design() -> GearScene {
    GearScene {
        eccentricity: Var::Free {
            min: 0.0,
            max: 30e-3,
        },
        max_sliding_coefficient: Some(0.6),
        max_pressure_angle: Some(30f64.to_radians()),
        ..paper_table1()
    }
}

/// Numerical settings, one flat struct.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// Samples of each pole function per arch before Brent (≥ 8).
    pub samples_per_arch: usize,
    /// Tolerance of every pole in α1 (rad), ≤ 1e-12.
    #[serde(with = "crate::units::angle_setting")]
    #[schemars(with = "crate::units::Qty<crate::units::Angle>")]
    pub pole_tol: f64,
    /// x-tolerance of Brent refinements of maxima (rad).
    #[serde(with = "crate::units::angle_setting")]
    #[schemars(with = "crate::units::Qty<crate::units::Angle>")]
    pub peak_xtol: f64,
    /// Samples per arch for the peak of |µ| (halved for the error estimate, ≥ 8).
    pub peak_samples_per_arch: usize,
    /// Refine each pole by Brent to `pole_tol` (default true); false places it by one
    /// false-position step in its sampled bracket (coarser, cheaper; the pole error grows and
    /// with it the window edges move).
    pub refine_poles: bool,
    /// Refine each sampled maximum of |µ| by Brent to `peak_xtol` (default true); false takes
    /// the largest sample (low by at most |µ''|h²/8).
    pub refine_peaks: bool,
    /// Samples of gear 2's curvature over a turn of gear 1 (≥ 64).
    pub curvature_samples: usize,
    /// Points of the α1 series for plots (≥ 16).
    pub series_points: usize,
    /// Points per pitch curve for plots (≥ 16).
    pub curve_points: usize,
    /// Points of the design sweep over e (≥ 3).
    pub sweep_points: usize,
    /// Tolerance of the design e, relative to R.
    pub design_rtol: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            samples_per_arch: 24,
            pole_tol: 1e-13,
            peak_xtol: 1e-10,
            peak_samples_per_arch: 32,
            refine_poles: true,
            refine_peaks: true,
            curvature_samples: 720,
            series_points: 1440,
            curve_points: 720,
            sweep_points: 31,
            design_rtol: 1e-10,
        }
    }
}

impl Settings {
    /// Check the settings.
    pub fn validate(&self) -> Result<(), SolveError> {
        let bad = |key, message| Err(SolveError::Settings { key, message });
        if self.samples_per_arch < 8 {
            return bad("samples_per_arch", "must be ≥ 8");
        }
        if !(self.pole_tol > 0.0 && self.pole_tol <= 1e-12) {
            return bad("pole_tol", "must be in (0, 1e-12] rad");
        }
        if !(self.peak_xtol > 0.0 && self.peak_xtol < 1e-3) {
            return bad("peak_xtol", "must be in (0, 1e-3) rad");
        }
        if self.peak_samples_per_arch < 8 {
            return bad("peak_samples_per_arch", "must be ≥ 8");
        }
        if self.curvature_samples < 64 {
            return bad("curvature_samples", "must be ≥ 64");
        }
        if self.series_points < 16 {
            return bad("series_points", "must be ≥ 16");
        }
        if self.curve_points < 16 {
            return bad("curve_points", "must be ≥ 16");
        }
        if self.sweep_points < 3 {
            return bad("sweep_points", "must be ≥ 3");
        }
        if !(self.design_rtol > 0.0 && self.design_rtol < 1e-2) {
            return bad("design_rtol", "must be in (0, 1e-2)");
        }
        Ok(())
    }
}

/// How the solve ended. A designed e comes from a sampled sweep refined by Brent, which is
/// not a certificate: `Optimal`, `ConstraintBound` and `AtBound` say where the best found e
/// lies and are all reported as `best_found` (with [`Outcome::search`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// e was fixed: analysis only.
    Analysed,
    /// Best found: an interior maximum of the ratio variation (Brent between samples).
    Optimal,
    /// Best found: on a constraint boundary (named in `method`).
    ConstraintBound,
    /// Best found: at a bound of e.
    AtBound,
    /// No sampled e satisfies the constraints; the least-violating one is reported.
    Infeasible,
}

pub use crate::report::PaperCheck;

/// Plot series over one turn of gear 1 (the pattern repeats n1/n2 times per turn of gear 2).
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Series {
    /// α1 (rad), equally spaced on [0, 2π).
    pub alpha1_rad: Vec<f64>,
    /// i12 = ω1/ω2.
    pub i12: Vec<f64>,
    /// µ1, `null` inside a pole window.
    pub mu1: Vec<Option<f64>>,
    /// µ2, `null` inside a pole window.
    pub mu2: Vec<Option<f64>>,
    /// Sliding velocity v_t1 − v_t2 (m/s).
    pub sliding_velocity_m_per_s: Vec<f64>,
    /// Pressure angle between the common normal and gear 2's velocity at K (rad).
    pub pressure_angle_rad: Vec<f64>,
    /// Contact point K in the fixed frame (m): the path of contact.
    pub contact_point_m: Vec<[f64; 2]>,
}

/// Pitch curves in the fixed frame at α1 = 0 (O1 at the origin, O2 on +x).
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct PitchCurves {
    /// Centre of gear 1 (m).
    pub center1_m: [f64; 2],
    /// Centre of gear 2 (m).
    pub center2_m: [f64; 2],
    /// Gear 1's pitch curve (m), closed by repeating no point.
    pub gear1_m: Vec<[f64; 2]>,
    /// Gear 2's pitch curve over its full turn (m).
    pub gear2_m: Vec<[f64; 2]>,
}

/// One row of the eccentricity sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepRow {
    pub eccentricity_m: f64,
    pub center_distance_m: f64,
    pub ratio_min: f64,
    pub ratio_max: f64,
    pub ratio_variation: f64,
    pub peak_sliding_coefficient: f64,
    pub min_gear2_curvature_per_m: f64,
    pub max_pitch_pressure_angle_rad: f64,
    pub feasible: bool,
}

/// A zero of µ as written to JSON.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ZeroOut {
    /// α1 (rad).
    pub alpha1_rad: f64,
    /// "pitch_point" (µ1 = µ2 = 0) or "indeterminate" (0/0, ψ = 0).
    pub kind: ZeroKind,
}

/// The design of a gear result (keys of `design`, SI).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Design {
    /// e (m): the eccentricity of gear 1's pitch circle.
    pub eccentricity_m: f64,
    /// R (m): gear 1's pitch radius.
    pub pitch_radius_m: f64,
    /// r (m): the generating circle of the cycloidal teeth.
    pub generating_radius_m: f64,
}

/// The objectives of a gear result (keys of `objectives`); the same type holds their
/// absolute errors (keys of `errors`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Objectives {
    /// Peak |µ| of the sliding coefficients µ1, µ2 on the working window (pole windows left
    /// out); inf when the window is 0.
    pub peak_sliding_coefficient: f64,
    /// i12max/i12min: the speed-ratio variation.
    pub ratio_variation: f64,
    /// asin(e/R) (rad): the largest pitch pressure angle.
    pub max_pitch_pressure_angle_rad: f64,
    /// κ min (1/m) of gear 2's pitch curve (≤ 0: not convex).
    pub min_gear2_curvature_per_m: f64,
}

impl Objectives {
    /// The key objective of a scene: the ratio variation when e is designed (the peak |µ| is
    /// then held at its limit), else the peak sliding coefficient.
    pub fn key(eccentricity: &Var) -> &'static str {
        if matches!(eccentricity, Var::Free { .. }) {
            key!(Objectives, ratio_variation)
        } else {
            key!(Objectives, peak_sliding_coefficient)
        }
    }
}

/// Other figures of a gear result (keys of `derived`, SI); `None` where they do not apply.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Derived {
    /// a (m): the closing centre distance for n1/n2.
    pub center_distance_m: f64,
    /// Error bound of a (m).
    pub center_distance_error_m: f64,
    /// i12 min = (a − (R + e))/(R + e).
    pub ratio_min: f64,
    /// i12 max = (a − (R − e))/(R − e).
    pub ratio_max: f64,
    /// Error bound of `ratio_min`.
    pub ratio_min_error: f64,
    /// Error bound of `ratio_max`.
    pub ratio_max_error: f64,
    /// Turn of gear 2 per turn of gear 1 (rad).
    pub gear2_turn_per_gear1_turn_rad: f64,
    /// Error bound of `gear2_turn_per_gear1_turn_rad` (rad).
    pub gear2_turn_per_gear1_turn_error_rad: f64,
    /// 2πR (m).
    pub gear1_perimeter_m: f64,
    /// Perimeter of gear 2's pitch curve, ∫ sqrt(ρ2² + ρ2'²) dα2 (m).
    pub gear2_perimeter_m: f64,
    /// Error bound of `gear2_perimeter_m` (m).
    pub gear2_perimeter_error_m: f64,
    /// Arches (tooth flanks) on gear 1.
    pub arches_gear1: f64,
    /// z1 = arches/2.
    pub teeth_gear1: f64,
    /// z2 = (n1/n2)·z1.
    pub teeth_gear2: f64,
    /// 4πr (m): the pitch on the pitch curve.
    pub pitch_m: f64,
    /// 2πr (m): one arch.
    pub arch_length_m: f64,
    /// 2πr/R (rad of the pitch circle): one arch's span.
    pub arch_span_rad: f64,
    /// Poles of µ1 over one turn of gear 1.
    pub poles_mu1_per_turn: f64,
    /// Poles of µ2 over one turn of gear 1.
    pub poles_mu2_per_turn: f64,
    /// Half-width of the window left out around each pole (rad).
    pub pole_window_rad: f64,
    /// α1 of the peak |µ| (rad).
    pub peak_sliding_alpha1_rad: f64,
    /// max |µ1 + µ2| on the working window.
    pub max_mu_asymmetry: f64,
    /// α1 of gear 2's smallest curvature (rad).
    pub min_gear2_curvature_alpha1_rad: f64,
    /// R − e (m).
    pub rho1_min_m: f64,
    /// R + e (m).
    pub rho1_max_m: f64,
    /// Largest error bound of a pole (rad).
    pub max_pole_error_rad: f64,
    /// Smallest distance between a µ1 and a µ2 pole (rad; absent without both).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_mu1_mu2_pole_separation_rad: Option<f64>,
    /// n1/n2 at the file's stated centre distance (when stated and above R + e).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ratio_at_stated_center_distance: Option<f64>,
    /// Largest obliquity |ψ| at a contact in the pitch point (rad).
    pub max_obliquity_at_pitch_point_contact_rad: f64,
    /// With `model.tooth_profiles`: how far gear 2's tooth outline misses closing after its
    /// full turn (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tooth_profile_closure_gap_m: Option<f64>,
    /// With `model.tooth_profiles`: largest sliding distance ∫|v_t1 − v_t2| dt of one arch
    /// (tooth flank) of gear 1 over a cycle (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sliding_distance_max_gear1_m: Option<f64>,
    /// Smallest per-arch sliding distance of gear 1 over a cycle (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sliding_distance_min_gear1_m: Option<f64>,
    /// Largest per-arch sliding distance of gear 2 over a cycle (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sliding_distance_max_gear2_m: Option<f64>,
    /// Smallest per-arch sliding distance of gear 2 over a cycle (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sliding_distance_min_gear2_m: Option<f64>,
    /// Error bound of every per-arch sliding distance (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sliding_distance_error_m: Option<f64>,
    /// Largest |µ| of the involute equivalent on its path of contact (closed form).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub involute_peak_sliding_coefficient: Option<f64>,
    /// Contact ratio of the involute equivalent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub involute_contact_ratio: Option<f64>,
    /// Largest |µ| of the involute equivalent with the routine shift x₁ = −x₂ = 0.5.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub involute_routine_shift_peak_sliding_coefficient: Option<f64>,
    /// x₁ (= −x₂) of the balanced profile-shifted involute pair.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub involute_balanced_shift_x1: Option<f64>,
    /// Largest |µ| of the balanced profile-shifted involute pair.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub involute_balanced_shift_peak_sliding_coefficient: Option<f64>,
    /// Contact ratio of the balanced profile-shifted involute pair.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub involute_balanced_shift_contact_ratio: Option<f64>,
    /// With `mechanism.load`: the fraction of a turn of gear 1 over which the one contact
    /// can carry the driving torque (the rest of the time it is on the back flanks).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub driving_contact_fraction: Option<f64>,
    /// Its error bound.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub driving_contact_fraction_error: Option<f64>,
    /// With `mechanism.load`: the largest Hertz pressure p0 on the working windows of the
    /// loaded flanks (Pa), at a window's end.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hertz_peak_stress_pa: Option<f64>,
    /// Its error bound (Pa).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hertz_peak_stress_error_pa: Option<f64>,
    /// α1 of the largest p0 (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hertz_peak_alpha1_rad: Option<f64>,
    /// Gear 1's arch of the largest p0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hertz_peak_arch: Option<f64>,
    /// The largest over gear 1's arches of each loaded flank's least p0 (Pa): the stress
    /// the most loaded flank cannot avoid anywhere on its working window.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hertz_least_stress_max_pa: Option<f64>,
    /// The smallest such least p0 (Pa).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hertz_least_stress_min_pa: Option<f64>,
    /// Error bound of both (Pa).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hertz_least_stress_error_pa: Option<f64>,
    /// Largest and smallest Archard load-weighted sliding W = ∫F|v_s|dt of one arch of
    /// gear 1 over a cycle, on the working windows (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub archard_max_gear1_nm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub archard_min_gear1_nm: Option<f64>,
    /// The same for gear 2's arches (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub archard_max_gear2_nm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub archard_min_gear2_nm: Option<f64>,
    /// The largest per-arch error bound of W (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub archard_error_nm: Option<f64>,
    /// |µ| of the circular cycloidal equivalent (e = 0), largest of its constant values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub circular_cycloidal_sliding_coefficient: Option<f64>,
    /// Arches of gear 1 (per turn) on which µ1 and µ2 must have a pole for every generating
    /// radius r (sign-change certificate, see `teeth::certified_pole_arches`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub arches_with_certified_pole: Option<f64>,
    /// Smallest |cos β1|, |cos β2| over the sampled contact series (0 at a pole).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_abs_cos_beta_sampled: Option<f64>,
    /// Largest rolling-angle distance min(ϕ, 2π − ϕ) of a pole from its arch's nearest cusp
    /// (rad): every pole lies within this band of a cusp, the band a relieved profile would
    /// have to leave out.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pole_band_from_cusp_rad: Option<f64>,
    /// Error bound of a designed e (m; absent when e is fixed or exact).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eccentricity_error_m: Option<f64>,
    /// The best feasible e of the sweep (m; with a designed e).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweep_best_feasible_eccentricity_m: Option<f64>,
    /// Feasible points of the sweep (with a designed e).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweep_feasible_points: Option<f64>,
}

/// Everything a report needs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Outcome {
    pub status: Status,
    /// The design.
    pub design: Design,
    /// The objectives.
    pub objectives: Objectives,
    /// Estimated absolute error of each objective.
    pub errors: Objectives,
    /// Derived figures.
    pub derived: Derived,
    pub warnings: Vec<String>,
    pub paper: Vec<PaperCheck>,
    /// Solver and evaluation counts.
    pub method: String,
    /// Poles of µ1, µ2 over one turn of gear 1.
    pub poles: Vec<Pole>,
    /// Zeros of µ (contact at the pitch point).
    pub zeros: Vec<ZeroOut>,
    pub series: Series,
    pub pitch_curves: PitchCurves,
    /// The eccentricity sweep (empty when e is fixed).
    pub sweep: Vec<SweepRow>,
    /// What the design search did (absent when e is fixed): a sampled sweep is not a proof
    /// of optimality, so a designed e is reported as `best_found` with this evidence.
    pub search: Option<SearchEvidence>,
    /// The tooth-level outputs (with `model.tooth_profiles`); written as tables, plots and
    /// drawing outlines by the report, not as JSON.
    #[serde(skip)]
    pub teeth: Option<TeethOutcome>,
}

/// The tooth-level outputs of issue 19 (see [`crate::families::gear::teeth`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TeethOutcome {
    /// Tooth outlines of both gears, each in its own frame.
    pub profiles: Profiles,
    /// ρ_K, V_K, v_t, v_s and cos β over one turn of gear 1 (the period of the contact).
    pub contact: Vec<ContactKinematics>,
    /// Sliding distance per arch of both gears over a cycle.
    pub wear: FlankWear,
    /// The involute pair with the same module and mean ratio.
    pub involute: Involute,
    /// The same with the routine profile shift x₁ = −x₂ = 0.5.
    pub routine_shift: Involute,
    /// The same with the shift that balances the roots' specific sliding, if any is
    /// admissible.
    pub balanced_shift: Option<BalancedShift>,
    /// (µ1, µ2) of the circular cycloidal equivalent on the addendum and the dedendum arch.
    pub circular: [(f64, f64); 2],
    /// Arches of gear 1 with a certified pole of µ1 and µ2 (for every r).
    pub certified_pole_arches: Vec<usize>,
    /// Hertz stress and Archard wear per flank under `mechanism.load` (absent without it).
    pub stress: Option<FlankStress>,
}

/// Full-cycle analysis of one design.
#[derive(Debug, Clone)]
pub struct Analysis {
    pub pair: GearPair,
    pub closure: Closure,
    pub sing: Singularities,
    pub peak: MuPeak,
    /// (κ min, α1, error) of gear 2's pitch curve.
    pub curvature: (f64, f64, f64),
    /// Contact-model evaluations spent.
    pub evals: usize,
}

impl Analysis {
    /// i12max/i12min.
    pub fn ratio_variation(&self) -> f64 {
        let (lo, hi) = self.pair.ratio_range();
        hi / lo
    }
    /// Pitch pressure angle max |ψ| = asin(e/R).
    pub fn max_pitch_pressure_angle(&self) -> f64 {
        (self.pair.c.e / self.pair.c.r_pitch).asin()
    }
}
