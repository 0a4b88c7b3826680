//! Synthesis for the eccentric cycloidal non-circular gear pair: the resolved scene, the
//! consistency checks of the gear data (paper's Table 1), the full-cycle analysis that a
//! report needs, and the design of the eccentricity e.
//!
//! Exists to turn the pure model of [`crate::families::gear::model`] into one call, [`solve`], whose
//! [`Outcome`] serialises to the JSON contract of issue 6 (`design.eccentricity_m`,
//! `derived.center_distance_m`, `derived.ratio_min`, `derived.ratio_max`,
//! `objectives.peak_sliding_coefficient`, `poles`).
//!
//! Design problem: maximise the speed-ratio variation i12max/i12min over e subject to
//! (optional) gear 2 convex, peak |µ| on the working window ≤ a limit, and pitch pressure
//! angle asin(e/R) ≤ a limit. The search is a sweep over the bounds followed by argmin's
//! Brent (root of the worst constraint margin at a constraint boundary, or a bounded
//! maximisation of the objective for an interior optimum).

use crate::families::gear::model::{
    closing_center_distance, closure_integral, min_gear2_curvature, peak_mu_with,
    periodic_integral, singularities_with, Alpha2Map, Closure, EccentricCircle, GearError,
    GearPair, MuPeak, Pole, Singularities, Which, Zero, ZeroKind,
};
use crate::families::gear::teeth::{
    certified_pole_arches, circular_cycloidal_mu, contact_kinematics, flank_wear, involute,
    profiles, ContactKinematics, FlankWear, Involute, Profiles,
};
use crate::geom::P2;
use crate::numeric::{brent_max, brent_root, SearchError};
use crate::report::numbers::key;
use crate::synth::SearchEvidence;
use serde::Serialize;
use std::f64::consts::{PI, TAU};

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
}

impl Default for TeethOptions {
    fn default() -> Self {
        Self {
            points_per_arch: 48,
            involute_pressure_angle: 20f64.to_radians(),
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
#[derive(Debug, Clone, PartialEq, Serialize)]
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
    /// (µ1, µ2) of the circular cycloidal equivalent on the addendum and the dedendum arch.
    pub circular: [(f64, f64); 2],
    /// Arches of gear 1 with a certified pole of µ1 and µ2 (for every r).
    pub certified_pole_arches: Vec<usize>,
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

/// Build and analyse the pair of `scene` at eccentricity `e`: closing centre distance,
/// all poles and zeros, peak |µ| on the working window, gear 2's minimum curvature.
pub fn analyse(scene: &GearScene, e: f64, settings: &Settings) -> Result<Analysis, SolveError> {
    let c = EccentricCircle::new(scene.pitch_radius, e)?;
    let closure = closing_center_distance(&c, scene.turns_gear1, scene.turns_gear2)?;
    let pair = GearPair::new(c, scene.generating_radius, closure.a, scene.omega1)?;
    let sing = singularities_with(
        &pair,
        settings.samples_per_arch,
        settings.refine_poles.then_some(settings.pole_tol),
    )?;
    let peak = peak_mu_with(
        &pair,
        &sing,
        scene.pole_window,
        settings.peak_samples_per_arch,
        settings.refine_peaks.then_some(settings.peak_xtol),
    )?;
    let curvature = min_gear2_curvature(&pair, settings.curvature_samples)?;
    let evals = sing.evals + peak.evals + settings.curvature_samples;
    Ok(Analysis {
        pair,
        closure,
        sing,
        peak,
        curvature,
        evals,
    })
}

/// Constraint margins (≤ 0 feasible), dimensionless.
fn margins(scene: &GearScene, an: &Analysis) -> Vec<(&'static str, f64)> {
    let mut m = Vec::new();
    if let Some(lim) = scene.max_sliding_coefficient {
        m.push((
            "objective.max_sliding_coefficient",
            an.peak.value / lim - 1.0,
        ));
    }
    if scene.require_gear2_convex {
        m.push((
            "objective.require_gear2_convex",
            -an.curvature.0 * scene.pitch_radius,
        ));
    }
    if let Some(lim) = scene.max_pressure_angle {
        m.push((
            "objective.max_pressure_angle",
            an.max_pitch_pressure_angle() / lim - 1.0,
        ));
    }
    m
}

fn worst_margin(scene: &GearScene, e: f64, settings: &Settings) -> f64 {
    match analyse(scene, e, settings) {
        Ok(an) => margins(scene, &an)
            .iter()
            .map(|x| x.1)
            .fold(f64::NEG_INFINITY, f64::max)
            .max(-1e300),
        Err(_) => 1.0,
    }
}

/// Solve the scene: analyse the given e, or design e when it is free.
///
/// Returns `Err` only for impossible input (a field error such as e ≥ R, or settings out
/// of range); an infeasible design is an `Ok` with [`Status::Infeasible`].
pub fn solve(scene: &GearScene, settings: &Settings) -> Result<Outcome, SolveError> {
    scene.validate()?;
    settings.validate()?;
    let mut method = String::new();
    let mut sweep = Vec::new();
    let mut design_error = 0.0;
    let mut search: Option<SearchEvidence> = None;
    let (e, status) = match scene.eccentricity {
        Var::Fixed(e) => (e, Status::Analysed),
        Var::Free { min, max } => {
            let n = settings.sweep_points;
            let mut rows: Vec<(f64, Option<(f64, f64)>)> = Vec::new();
            for k in 0..n {
                let e = min + (max - min) * k as f64 / (n - 1) as f64;
                match analyse(scene, e, settings) {
                    Ok(an) => {
                        let ms = margins(scene, &an);
                        let worst = ms.iter().map(|x| x.1).fold(f64::NEG_INFINITY, f64::max);
                        let feasible = worst <= 0.0;
                        sweep.push(SweepRow {
                            eccentricity_m: e,
                            center_distance_m: an.pair.a,
                            ratio_min: an.pair.ratio_range().0,
                            ratio_max: an.pair.ratio_range().1,
                            ratio_variation: an.ratio_variation(),
                            peak_sliding_coefficient: an.peak.value,
                            min_gear2_curvature_per_m: an.curvature.0,
                            max_pitch_pressure_angle_rad: an.max_pitch_pressure_angle(),
                            feasible,
                        });
                        rows.push((e, Some((an.ratio_variation(), worst))));
                    }
                    Err(_) => rows.push((e, None)),
                }
            }
            let best = rows
                .iter()
                .enumerate()
                .filter_map(|(k, r)| r.1.filter(|x| x.1 <= 0.0).map(|x| (k, x.0)))
                .max_by(|a, b| a.1.total_cmp(&b.1));
            // The sweep's evidence: the best objective of each maximal run of feasible
            // samples (a run is a basin of the 1-D search), best first.
            let mut run_best: Vec<f64> = Vec::new();
            let mut in_run = false;
            for r in &rows {
                match r.1.filter(|x| x.1 <= 0.0) {
                    Some((o, _)) if in_run => {
                        let last = run_best.last_mut().expect("in a run");
                        *last = last.max(o);
                    }
                    Some((o, _)) => {
                        run_best.push(o);
                        in_run = true;
                    }
                    None => in_run = false,
                }
            }
            run_best.sort_by(|a, b| b.total_cmp(a));
            search = Some(SearchEvidence {
                method: format!(
                    "sweep of {n} equally spaced eccentricities over [{min:e}, {max:e}] m, then Brent \
                     (Brent 1973) on the best sample's neighbourhood; no bound on the constraints \
                     between samples, so a feasible e between two infeasible samples can be missed"
                ),
                starts: 1,
                distinct_basins: run_best.len(),
                evaluations: n,
                best_values: run_best.iter().take(5).copied().collect(),
                starts_at_best: 1,
                spread_rel: (run_best.len() > 1)
                    .then(|| (run_best[0] - run_best[1]) / run_best[0].abs()),
            });
            let tol = settings.design_rtol * scene.pitch_radius;
            match best {
                None => {
                    let k = rows
                        .iter()
                        .enumerate()
                        .filter_map(|(k, r)| r.1.map(|x| (k, x.1)))
                        .min_by(|a, b| a.1.total_cmp(&b.1))
                        .map(|x| x.0)
                        .unwrap_or(0);
                    method.push_str(&format!("sweep of {n} eccentricities: none feasible; reporting the least violating. "));
                    (rows[k].0, Status::Infeasible)
                }
                Some((k, obj)) => {
                    // A neighbour with a larger objective but infeasible: the optimum is on
                    // the constraint boundary between them.
                    let nb = [k.checked_sub(1), (k + 1 < n).then_some(k + 1)];
                    let mut cand = None;
                    for j in nb.into_iter().flatten() {
                        if let Some((o, w)) = rows[j].1 {
                            if w > 0.0 && o > obj {
                                cand = Some(j);
                            }
                        } else {
                            cand = Some(j);
                        }
                    }
                    if let Some(j) = cand {
                        let count = std::cell::Cell::new(0usize);
                        let f = |x: f64| {
                            count.set(count.get() + 1);
                            worst_margin(scene, x, settings)
                        };
                        let root = brent_root(f, rows[k].0, rows[j].0, tol)?;
                        // Keep the feasible side of the boundary.
                        let mut x = root.x;
                        let step = if rows[j].0 > rows[k].0 { -tol } else { tol };
                        let mut guard = 0;
                        while f(x) > 0.0 && guard < 8 {
                            x += step;
                            guard += 1;
                        }
                        design_error = 2.0 * tol;
                        if let Some(ev) = search.as_mut() {
                            ev.evaluations += count.get();
                        }
                        method.push_str(&format!(
                            "sweep of {n} eccentricities, then Brent root of the worst constraint margin on [{:.6e}, {:.6e}] m ({} analyses, tol {:.1e} m). ",
                            rows[k].0.min(rows[j].0),
                            rows[k].0.max(rows[j].0),
                            count.get(),
                            tol
                        ));
                        (x, Status::ConstraintBound)
                    } else if k == 0 || k + 1 == n {
                        method
                            .push_str(&format!("sweep of {n} eccentricities: best at the bound. "));
                        (rows[k].0, Status::AtBound)
                    } else {
                        let count = std::cell::Cell::new(0usize);
                        let g = |x: f64| {
                            count.set(count.get() + 1);
                            analyse(scene, x, settings)
                                .map(|a| a.ratio_variation())
                                .unwrap_or(f64::NEG_INFINITY)
                        };
                        let ext = brent_max(g, rows[k - 1].0, rows[k + 1].0, tol)?;
                        design_error = tol;
                        if let Some(ev) = search.as_mut() {
                            ev.evaluations += count.get();
                        }
                        method.push_str(&format!(
                            "sweep of {n} eccentricities, then Brent maximisation ({} analyses). ",
                            count.get()
                        ));
                        (ext.x, Status::Optimal)
                    }
                }
            }
        }
    };
    let an = analyse(scene, e, settings)?;
    let mut out = report(scene, &an, settings)?;
    out.status = status;
    out.sweep = sweep;
    if let Some(ev) = search.as_mut() {
        // The refined design heads the list (it is at least the best sample).
        let v = out.objectives.ratio_variation;
        if status != Status::Infeasible && ev.best_values.first().is_none_or(|&b| v >= b) {
            ev.best_values.insert(0, v);
            ev.best_values.truncate(5);
        }
    }
    out.search = search;
    out.method = format!(
        "{method}Analysis: closure a by Brent on the trapezoid closure integral ({} integrals); poles: {} samples/arch + Brent (argmin BrentRoot) to {:.0e} rad; peak |µ|: {} samples/arch + Brent (argmin BrentOpt) to {:.0e} rad; {} contact evaluations.",
        an.closure.evals, settings.samples_per_arch, settings.pole_tol, settings.peak_samples_per_arch, settings.peak_xtol, an.evals
    );
    if design_error > 0.0 {
        out.derived.eccentricity_error_m = Some(design_error);
    }
    out.derived.sweep_best_feasible_eccentricity_m = out
        .sweep
        .iter()
        .filter(|s| s.feasible)
        .max_by(|a, b| a.ratio_variation.total_cmp(&b.ratio_variation))
        .map(|best| best.eccentricity_m);
    if !out.sweep.is_empty() {
        out.derived.sweep_feasible_points =
            Some(out.sweep.iter().filter(|s| s.feasible).count() as f64);
    }
    Ok(out)
}

/// Assemble the outcome (objectives, errors, derived values, checks, series) of an analysis.
pub fn report(
    scene: &GearScene,
    an: &Analysis,
    settings: &Settings,
) -> Result<Outcome, SolveError> {
    let pair = &an.pair;
    let (r, e, rg) = (pair.c.r_pitch, pair.c.e, pair.r_gen);
    let (n1, n2) = (scene.turns_gear1, scene.turns_gear2);
    let ratio = n1 as f64 / n2 as f64;
    let mut warnings = Vec::new();
    let mut paper = Vec::new();
    let (imin, imax) = pair.ratio_range();
    // Error of i12 extremes through a: d i/da = 1/ρ1.
    let di_min = an.closure.a_error / (r + e);
    let di_max = an.closure.a_error / (r - e);
    let var = imax / imin;
    let var_err = var * (di_min / imin + di_max / imax) + 4.0 * f64::EPSILON * var;

    let design = Design {
        eccentricity_m: e,
        pitch_radius_m: r,
        generating_radius_m: rg,
    };
    let psi_max = (e / r).asin();
    let objectives = Objectives {
        peak_sliding_coefficient: an.peak.value,
        ratio_variation: var,
        max_pitch_pressure_angle_rad: psi_max,
        min_gear2_curvature_per_m: an.curvature.0,
    };
    let errors = Objectives {
        peak_sliding_coefficient: an.peak.error,
        ratio_variation: var_err,
        max_pitch_pressure_angle_rad: 4.0 * f64::EPSILON * psi_max.max(f64::MIN_POSITIVE),
        min_gear2_curvature_per_m: an.curvature.2,
    };

    let n_arch = pair.n_arches;
    let z1 = n_arch / 2;
    let z2 = (n_arch as f64 * ratio / 2.0).round();
    let a2map = Alpha2Map::new(&pair.c, pair.a);
    let perim1 = TAU * r;
    // Gear 2's perimeter from its own polar description: ∫ sqrt(ρ2² + ρ̇2²) dα2.
    let perim2_turn = periodic_integral(
        |al| {
            let r1 = pair.c.rho1(al);
            let r2 = pair.a - r1;
            let q = r2 / r1;
            let r2d = -pair.c.rho1_d1(al) * q;
            (r2 * r2 + r2d * r2d).sqrt() / q
        },
        1e-14,
    );
    let perim2 = perim2_turn.value * ratio;

    let n_mu1 = an
        .sing
        .poles
        .iter()
        .filter(|p| p.which == Which::Mu1)
        .count();
    let n_mu2 = an.sing.poles.len() - n_mu1;
    let max_pole_err = an
        .sing
        .poles
        .iter()
        .map(|p| p.error_rad)
        .fold(0.0, f64::max);
    // Smallest distance between a µ1 pole and a µ2 pole.
    let mut min_sep = f64::INFINITY;
    for p in an.sing.poles.iter().filter(|p| p.which == Which::Mu1) {
        for q in an.sing.poles.iter().filter(|p| p.which == Which::Mu2) {
            let d = (p.alpha1_rad - q.alpha1_rad).rem_euclid(TAU);
            min_sep = min_sep.min(d.min(TAU - d));
        }
    }
    let psi_at_zeros = an
        .sing
        .zeros
        .iter()
        .map(|z| pair.c.psi_sin_cos(z.alpha1_rad).0.abs().asin())
        .fold(0.0, f64::max);
    let mut derived = Derived {
        center_distance_m: pair.a,
        center_distance_error_m: an.closure.a_error,
        ratio_min: imin,
        ratio_max: imax,
        ratio_min_error: di_min,
        ratio_max_error: di_max,
        gear2_turn_per_gear1_turn_rad: a2map.per_turn(),
        gear2_turn_per_gear1_turn_error_rad: a2map.error,
        gear1_perimeter_m: perim1,
        gear2_perimeter_m: perim2,
        gear2_perimeter_error_m: perim2_turn.error * ratio + an.closure.a_error * TAU,
        arches_gear1: n_arch as f64,
        teeth_gear1: z1 as f64,
        teeth_gear2: z2,
        pitch_m: 4.0 * PI * rg,
        arch_length_m: TAU * rg,
        arch_span_rad: TAU * rg / r,
        poles_mu1_per_turn: n_mu1 as f64,
        poles_mu2_per_turn: n_mu2 as f64,
        pole_window_rad: scene.pole_window,
        peak_sliding_alpha1_rad: an.peak.alpha1,
        max_mu_asymmetry: an.peak.max_asymmetry,
        min_gear2_curvature_alpha1_rad: an.curvature.1,
        rho1_min_m: r - e,
        rho1_max_m: r + e,
        max_pole_error_rad: max_pole_err,
        min_mu1_mu2_pole_separation_rad: min_sep.is_finite().then_some(min_sep),
        ratio_at_stated_center_distance: None,
        max_obliquity_at_pitch_point_contact_rad: psi_at_zeros,
        tooth_profile_closure_gap_m: None,
        sliding_distance_max_gear1_m: None,
        sliding_distance_min_gear1_m: None,
        sliding_distance_max_gear2_m: None,
        sliding_distance_min_gear2_m: None,
        sliding_distance_error_m: None,
        involute_peak_sliding_coefficient: None,
        involute_contact_ratio: None,
        circular_cycloidal_sliding_coefficient: None,
        arches_with_certified_pole: None,
        min_abs_cos_beta_sampled: None,
        pole_band_from_cusp_rad: None,
        eccentricity_error_m: None,
        sweep_best_feasible_eccentricity_m: None,
        sweep_feasible_points: None,
    };

    // --- warnings ---------------------------------------------------------------------
    if e / r > 0.9 {
        warnings.push(format!(
            "design.eccentricity: e/R = {:.4} is close to 1: ρ1 min = {:.3e} m, i12 max = {:.4}; the pair degenerates as e → R",
            e / r,
            r - e,
            imax
        ));
    }
    if r - e <= 2.0 * rg {
        warnings.push(format!(
            "design.eccentricity: ρ1 min = R − e = {:.3e} m ≤ 2r = {:.3e} m: the generating circle is as large as gear 1's radius there, hypocycloid flanks run through the pivot and µ1 poles spread over whole arches",
            r - e,
            2.0 * rg
        ));
    }
    if !an.peak.value.is_finite() {
        warnings.push(format!(
            "model.pole_window = 0: no window is left out, and |µ| is unbounded at the {} poles of µ1, µ2 (the first at α1 = {:.6} rad); objectives.peak_sliding_coefficient has no finite value (null)",
            an.sing.poles.len(),
            an.peak.alpha1
        ));
    }
    if an.curvature.0 <= 0.0 {
        warnings.push(format!(
            "gear 2's pitch curve is not convex (min curvature {:.4e} 1/m at α1 = {:.4} rad): it cannot be cut as an external gear there",
            an.curvature.0, an.curvature.1
        ));
    }
    let indet: Vec<&Zero> = an
        .sing
        .zeros
        .iter()
        .filter(|z| z.kind == ZeroKind::Indeterminate)
        .collect();
    if !indet.is_empty() {
        warnings.push(format!(
            "{} cusp(s) fall where ψ = 0 (α1 = {}): µ is 0/0 there (a pole merged with the zero, one-sided limits differ); excluded by the pole window",
            indet.len(),
            indet.iter().map(|z| format!("{:.6}", z.alpha1_rad)).collect::<Vec<_>>().join(", ")
        ));
    }
    if min_sep.is_finite() && min_sep < 2.0 * scene.pole_window {
        warnings.push(format!(
            "µ1 and µ2 poles are as close as {min_sep:.3e} rad (< twice the pole window {:.3e} rad): their windows overlap",
            scene.pole_window
        ));
    }
    let at_edge = an.sing.poles.iter().any(|p| {
        let d = (p.alpha1_rad - an.peak.alpha1).rem_euclid(TAU);
        (d.min(TAU - d) - scene.pole_window).abs() < 1e-6
    });
    if at_edge {
        warnings.push(format!(
            "the peak |µ| = {:.4} is attained at the edge of a pole window: it is set by model.pole_window (|µ| grows like 1/distance to the pole)",
            an.peak.value
        ));
    }

    // --- consistency of the stated data -------------------------------------------------
    let pitch = 4.0 * PI * rg;
    if let Some(m) = scene.module {
        if ((PI * m) - pitch).abs() > 1e-6 * pitch {
            warnings.push(format!("mechanism.module: πm = {:.4e} m but the teeth (arch 2πr, tooth = space) give a pitch 4πr = {pitch:.4e} m", PI * m));
        }
    }
    if let Some((tz1, tz2)) = scene.teeth {
        if tz1 as usize != z1 {
            warnings.push(format!(
                "mechanism.teeth_gear1: stated z1 = {tz1}, but the pitch circle (2πR = {:.4} mm) holds R/(2r) = {z1} teeth of pitch 4πr = {:.4} mm; z1 = {tz1} would need R = {:.4} mm or r = {:.4} mm. The model uses {z1} teeth",
                perim1 * 1e3,
                pitch * 1e3,
                2.0 * tz1 as f64 * rg * 1e3,
                r / (2.0 * tz1 as f64) * 1e3
            ));
            paper.push(PaperCheck::new(
                "teeth of gear 1, z1",
                key!("derived", Derived, teeth_gear1),
                tz1 as f64,
                z1 as f64,
                format!(
                    "2πR/(4πr) = R/(2r); with the stated module, 2πR/(πm) = {:.4}",
                    scene.module.map_or(f64::NAN, |m| 2.0 * r / m)
                ),
            ));
            paper.push(PaperCheck::new(
                "arch span of eq. (2), π/z1 (rad of the pitch circle)",
                key!("derived", Derived, arch_span_rad),
                PI / tz1 as f64,
                TAU * rg / r,
                "eq. (2) spans each arch over π/z1 of the pitch circle, but one turn of the r = 1.25 mm generating circle covers 2πr/R; with z1 = 12 the arches would not end in cusps",
            ));
        }
        if tz2 as f64 != z2 {
            warnings.push(format!(
                "mechanism.teeth_gear2: stated z2 = {tz2}, closure gives (n1/n2)·z1 = {z2}"
            ));
            paper.push(PaperCheck::new(
                "teeth of gear 2, z2",
                key!("derived", Derived, teeth_gear2),
                tz2 as f64,
                z2,
                "z2 = (n1/n2)·z1 with z1 from the pitch circle; the stated 36 = 3 × 12 keeps the ratio but inherits the wrong z1",
            ));
        }
        if let Some(p) = scene.tooth_pitch {
            let stated_perim2 = tz2 as f64 * p;
            paper.push(PaperCheck::new(
                "perimeter of gear 2's pitch curve (z2 × pitch)",
                key!("derived", Derived, gear2_perimeter_m),
                stated_perim2,
                perim2,
                format!("paper value = z2 × pitch; computed from gear 2's polar curve ∫sqrt(ρ2² + ρ2'²)dα2; must equal (n1/n2)·2πR = {:.4} mm", ratio * perim1 * 1e3),
            ));
        }
    }
    if let Some(p) = scene.tooth_pitch {
        if (p - pitch).abs() > 0.005 * pitch {
            warnings.push(format!(
                "mechanism.tooth_pitch: stated {:.4} mm, teeth give 4πr = {:.4} mm",
                p * 1e3,
                pitch * 1e3
            ));
        }
        paper.push(PaperCheck::new(
                "pitch on the pitch curve",
                key!("derived", Derived, pitch_m),
                p,
                pitch,
                "4πr (= πm for m = 4r); agrees to the printed rounding. The pitch 2πR/z1 with the stated z1 would be different",
            ));
    }
    for (k, v) in [
        ("mechanism.tooth_thickness", scene.tooth_thickness),
        ("mechanism.space_width", scene.space_width),
    ] {
        if let Some(t) = v {
            let arch = TAU * rg;
            if (t - arch).abs() > 0.005 * arch {
                warnings.push(format!(
                    "{k}: stated {:.4} mm, one arch 2πr = {:.4} mm",
                    t * 1e3,
                    arch * 1e3
                ));
            }
            paper.push(PaperCheck::new(
                format!("{} on the pitch curve", if k.ends_with("thickness") { "tooth thickness" } else { "space width" }),
                key!("derived", Derived, arch_length_m),
                t,
                arch,
                "one cycloid arch = one turn of the generating circle, 2πr; agrees to the printed rounding",
            ));
        }
    }
    if let Some(a_st) = scene.center_distance {
        let j = closure_integral(&pair.c, a_st, 1e-15);
        if a_st > r + e && j.value.is_finite() {
            let ratio_st = TAU / j.value;
            let miss = (n1 as f64 * j.value - TAU * n2 as f64).to_degrees();
            derived.ratio_at_stated_center_distance = Some(ratio_st);
            paper.push(PaperCheck::new(
                "centre distance a12",
                key!("derived", Derived, center_distance_m),
                a_st,
                pair.a,
                format!(
                    "closing centre distance for n1/n2 = {n1}/{n2} (±{:.1e} mm); the stated value gives n1/n2 = {ratio_st:.6}, gear 2 missing closure by {miss:.4}° per cycle{}",
                    an.closure.a_error * 1e3,
                    if (a_st - pair.a).abs() <= 0.05e-3 { " — the stated value is the closing one rounded to 0.1 mm" } else { " — the stated value belongs to a different design" }
                ),
            ));
            if (a_st - pair.a).abs() > 1e-9 * pair.a {
                warnings.push(format!(
                    "mechanism.center_distance: stated {:.4} mm, closure gives {:.6} mm; the stated value would give n1/n2 = {ratio_st:.6}",
                    a_st * 1e3,
                    pair.a * 1e3
                ));
            }
        } else {
            warnings.push(format!("mechanism.center_distance: stated {:.4} mm is not above R + e: the pair cannot mesh there", a_st * 1e3));
        }
    }
    paper.push(PaperCheck::new(
                "max |µ1 + µ2| on the working window (paper: µ2 = −µ1, symmetric)",
                key!("derived", Derived, max_mu_asymmetry),
                0.0,
                an.peak.max_asymmetry,
                "by definition µ2 = −µ1/(1 − µ1) exactly, which is −µ1 only to first order; the curves are mirror images only where |µ| ≪ 1",
            ));
    if min_sep.is_finite() {
        paper.push(PaperCheck::new(
                "separation of µ1 and µ2 poles in α1 (paper: both at points 2, 4)",
                key!("derived", Derived, min_mu1_mu2_pole_separation_rad),
                0.0,
                min_sep,
                "µ1 is infinite where the common tangent passes through O1, µ2 where it passes through O2: distinct points (the paper's eq. 11 itself keeps cos β2 ≠ 0)",
            ));
    }
    paper.push(PaperCheck::new(
                "angle between the common tangent and O1O2 at K = P",
                key!("derived", Derived, max_obliquity_at_pitch_point_contact_rad),
                PI / 2.0,
                psi_at_zeros,
                "at K = P the contact is at a cusp, whose tangent is the pitch-curve normal: it deviates from O1O2 by the obliquity |ψ| (max shown), it is not perpendicular to it",
            ));

    // --- series -------------------------------------------------------------------------
    let mut series = Series::default();
    let ns = settings.series_points;
    let near_pole = |x: f64, w: Which| {
        an.sing.poles.iter().filter(|p| p.which == w).any(|p| {
            let d = (x - p.alpha1_rad).rem_euclid(TAU);
            d.min(TAU - d) <= scene.pole_window + p.error_rad
        }) || indet.iter().any(|z| {
            let d = (x - z.alpha1_rad).rem_euclid(TAU);
            d.min(TAU - d) <= scene.pole_window
        })
    };
    for k in 0..ns {
        let x = TAU * k as f64 / ns as f64;
        let ct = pair.contact(x);
        series.alpha1_rad.push(x);
        series.i12.push(pair.i12(x));
        series.mu1.push(if near_pole(x, Which::Mu1) {
            None
        } else {
            ct.mu1
        });
        series.mu2.push(if near_pole(x, Which::Mu2) {
            None
        } else {
            ct.mu2
        });
        series.sliding_velocity_m_per_s.push(ct.v_slide);
        series.pressure_angle_rad.push(ct.pressure_angle);
        series.contact_point_m.push([ct.k.x, ct.k.y]);
    }
    let pitch_curves = pitch_curves(pair, &a2map, ratio, settings.curve_points);
    let teeth = scene.tooth_outputs.map(|t| {
        let out = teeth_outcome(pair, &a2map, n1, n2, &t, ns);
        let wear_ext = |v: &[(f64, f64)], max: bool| {
            v.iter()
                .map(|x| x.0)
                .fold(if max { 0.0 } else { f64::INFINITY }, |a, b| {
                    if max {
                        a.max(b)
                    } else {
                        a.min(b)
                    }
                })
        };
        derived.tooth_profile_closure_gap_m = Some(out.profiles.gear2_closure_gap_m);
        derived.sliding_distance_max_gear1_m = Some(wear_ext(&out.wear.gear1, true));
        derived.sliding_distance_min_gear1_m = Some(wear_ext(&out.wear.gear1, false));
        derived.sliding_distance_max_gear2_m = Some(wear_ext(&out.wear.gear2, true));
        derived.sliding_distance_min_gear2_m = Some(wear_ext(&out.wear.gear2, false));
        derived.sliding_distance_error_m = Some(
            out.wear
                .gear1
                .iter()
                .chain(&out.wear.gear2)
                .map(|x| x.1)
                .fold(0.0, f64::max),
        );
        let inv = &out.involute;
        derived.involute_peak_sliding_coefficient = Some(
            [inv.mu1_start, inv.mu1_end, inv.mu2_start, inv.mu2_end]
                .iter()
                .fold(0.0, |a: f64, b| a.max(b.abs())),
        );
        derived.involute_contact_ratio = Some(inv.contact_ratio);
        derived.circular_cycloidal_sliding_coefficient = Some(
            out.circular
                .iter()
                .fold(0.0, |a: f64, b| a.max(b.0.abs()).max(b.1.abs())),
        );
        derived.arches_with_certified_pole = Some(out.certified_pole_arches.len() as f64);
        derived.pole_band_from_cusp_rad = Some(
            an.sing
                .poles
                .iter()
                .map(|p| p.phi_rad.min(TAU - p.phi_rad))
                .fold(0.0, f64::max),
        );
        derived.min_abs_cos_beta_sampled = Some(out.contact.iter().fold(f64::INFINITY, |a, c| {
            a.min(c.cos_beta1.abs()).min(c.cos_beta2.abs())
        }));
        out
    });
    let poles = an.sing.poles.clone();
    let zeros = an
        .sing
        .zeros
        .iter()
        .map(|z| ZeroOut {
            alpha1_rad: z.alpha1_rad,
            kind: z.kind,
        })
        .collect();
    Ok(Outcome {
        status: Status::Analysed,
        design,
        objectives,
        errors,
        derived,
        warnings,
        paper,
        method: String::new(),
        poles,
        zeros,
        series,
        pitch_curves,
        sweep: Vec::new(),
        search: None,
        teeth,
    })
}

/// The tooth-level outputs of one analysed pair: outlines (`t.points_per_arch` per arch),
/// the contact series at `ns` points of one turn of gear 1, the sliding distance per flank
/// (Simpson to 1e-12 relative), the circular cycloidal and the involute equivalents (module
/// 4r, z1 = N/2, z2 = z1·n1/n2, standard addendum 1·m) and the pole certificate.
pub fn teeth_outcome(
    pair: &GearPair,
    a2map: &Alpha2Map,
    n1: u32,
    n2: u32,
    t: &TeethOptions,
    ns: usize,
) -> TeethOutcome {
    let ratio = n1 as f64 / n2 as f64;
    let z1 = (pair.n_arches / 2) as f64;
    TeethOutcome {
        profiles: profiles(pair, a2map, n1, n2, t.points_per_arch),
        contact: (0..ns)
            .map(|k| contact_kinematics(pair, TAU * k as f64 / ns as f64))
            .collect(),
        wear: flank_wear(pair, n1, n2, 1e-12),
        involute: involute(
            4.0 * pair.r_gen,
            z1,
            z1 * ratio,
            t.involute_pressure_angle,
            1.0,
        ),
        circular: circular_cycloidal_mu(pair.c.r_pitch, pair.r_gen, ratio),
        certified_pole_arches: certified_pole_arches(pair),
    }
}

/// Both pitch curves in the fixed frame at α1 = 0: gear 1's points ρ1(α)(cos α, sin α);
/// gear 2's points O2 + ρ2 (cos(π − α2), sin(π − α2)) over α1 ∈ [0, 2π n1/n2), which is one
/// full turn of gear 2.
pub fn pitch_curves(pair: &GearPair, a2: &Alpha2Map, ratio: f64, n: usize) -> PitchCurves {
    let o2 = P2::new(pair.a, 0.0);
    let gear1_m = (0..n)
        .map(|k| {
            let p = pair.c.point(TAU * k as f64 / n as f64);
            [p.x, p.y]
        })
        .collect();
    let m = ((n as f64) * ratio).ceil() as usize;
    let gear2_m = (0..m)
        .map(|k| {
            let al = TAU * ratio * k as f64 / m as f64;
            let r2 = pair.a - pair.c.rho1(al);
            let ang = PI - a2.alpha2(al);
            let p = o2 + P2::new(ang.cos(), ang.sin()) * r2;
            [p.x, p.y]
        })
        .collect();
    PitchCurves {
        center1_m: [0.0, 0.0],
        center2_m: [pair.a, 0.0],
        gear1_m,
        gear2_m,
    }
}
