//! Synthesis and optimisation of the level-luffing four-bar jib crane (thesis `003`).
//!
//! The thesis chooses the step-1 angles by trial and k1, k2 by rule of thumb, then checks the
//! jib-head height variation Δh. This module does that job for given values, and searches the
//! same choices to minimise Δh: a deterministic global stage (Halton points over the box of
//! free variables) followed by a trust-region SQP from the best distinct points. The tie pin
//! B must be confined by the scene: without a limit the problem is degenerate (a tie of
//! unbounded length is a straight guide and drives Δh to ~0), and [`CraneScene::validate`]
//! refuses it.
//!
//! A [`FieldError`] names the problem-file key: `mechanism.reach_max`, `mechanism.reach_min`,
//! `mechanism.foot_offset` (r), `mechanism.lift_height` (H), `mechanism.foot_height` (h),
//! `mechanism.load_mass`, `design.k1`, `design.k2`, `design.phi_min`, `design.gamma1..3`,
//! `design.boom_length`, `objective.tie_pin` (and its `.max_distance`, `.x_range`,
//! `.y_range`), `objective.max_delta_h`, `accuracy.*`.

use crate::families::crane::model::{
    head_extrema, head_heights_with, load_moment, synthesize, Angles, Boom, Branch, CraneGeomError,
    Guide, HeadHeights, PathError, Synthesis,
};
use crate::geom::P2;
use crate::problem::FieldError;
use crate::report::numbers::key;
use serde::Serialize;
use std::collections::BTreeMap;
use std::f64::consts::FRAC_PI_2;
use std::sync::atomic::{AtomicUsize, Ordering};

pub use crate::synth::Var;

/// Whether a variable is searched.
fn is_free(v: &Var) -> bool {
    v.fixed().is_none()
}

/// How the boom length L_c follows from the step-1 angles.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum SizingRule {
    /// L_c = (R_min − r)/(sin γ1 + k sin γ2): the minimum reach is met exactly (the thesis's
    /// rule; its 22.8 m is this value, 22.819 m, rounded down).
    MinReach,
    /// L_c = (R_max − r)/(cos φ_min + k cos γ3): the maximum reach is met exactly.
    MaxReach,
    /// L_c given (m).
    Given(f64),
}

impl SizingRule {
    fn describe(&self) -> String {
        match self {
            SizingRule::MinReach => "min-reach: L_c = (R_min - r)/(sin g1 + k sin g2)".into(),
            SizingRule::MaxReach => "max-reach: L_c = (R_max - r)/(cos phi_min + k cos g3)".into(),
            SizingRule::Given(l) => format!("given: L_c = {l} m"),
        }
    }
}

/// Where the tie pin B may be (m, frame of the boom-foot pin A; x positive = behind the foot).
/// Every limit given must hold. At least `max_distance`, or both ranges, make it bounded.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct TiePinLimit {
    /// |AB| ≤ max_distance.
    pub max_distance: Option<f64>,
    /// x_B within [min, max] (e.g. `[0, 12]`: behind the boom foot).
    pub x_range: Option<[f64; 2]>,
    /// y_B within [min, max].
    pub y_range: Option<[f64; 2]>,
}

impl TiePinLimit {
    /// Whether the limit confines B to a bounded set.
    pub fn is_bounded(&self) -> bool {
        self.max_distance.is_some() || (self.x_range.is_some() && self.y_range.is_some())
    }

    /// Distance (m) by which B violates the limit (0 inside): the largest single violation.
    pub fn violation(&self, b: P2) -> f64 {
        let mut v: f64 = 0.0;
        if let Some(r) = self.max_distance {
            v = v.max(b.x.hypot(b.y) - r);
        }
        if let Some([lo, hi]) = self.x_range {
            v = v.max(lo - b.x).max(b.x - hi);
        }
        if let Some([lo, hi]) = self.y_range {
            v = v.max(lo - b.y).max(b.y - hi);
        }
        v.max(0.0)
    }
}

/// A resolved crane scene (SI: m, rad, kg), the input of [`solve`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CraneScene {
    /// R_max, largest reach from the slewing axis (m). Key `reach_max`.
    pub reach_max: f64,
    /// R_min, smallest reach from the slewing axis (m). Key `reach_min`.
    pub reach_min: f64,
    /// r, slewing axis to boom-foot pin A (m). Key `foot_offset`.
    pub foot_offset: f64,
    /// H, lift height above the rail (m). Key `lift_height`.
    pub lift_height: f64,
    /// h, rail to boom-foot pin (m). Key `foot_height`.
    pub foot_height: f64,
    /// k1 = C1C2/C1C3, in (0, 1).
    pub k1: Var,
    /// k2 = a/L_v, in (0, 5].
    pub k2: Var,
    /// φ_min (rad), boom elevation at maximum reach, in (0, π/2).
    pub phi_min: Var,
    /// γ1 (rad), boom from vertical at minimum reach, in (0, π/2).
    pub gamma1: Var,
    /// γ2 (rad), jib from vertical at minimum reach, in [0, π/2).
    pub gamma2: Var,
    /// γ3 (rad), jib below horizontal at maximum reach, in [0, π/2).
    pub gamma3: Var,
    /// Rule for the boom length.
    pub sizing: SizingRule,
    /// Where the tie pin may be.
    pub tie_pin: TiePinLimit,
    /// Allowed Δh (m); `None` = the thesis's 0.1·H. Key `max_delta_h`.
    pub max_delta_h: Option<f64>,
    /// Rated load Q (kg) for the unbalanced load moment; optional. Key `load_mass`.
    pub load_mass: Option<f64>,
    /// Masses of the boom system and the boom counterweight to design (keys
    /// `mechanism.self_weight`, `design.counterweight`); `None`: no statics.
    pub balance: Option<crate::families::crane::balance::BalanceScene>,
}

/// A field error names its problem-file key (`design.k1`, `accuracy.path_samples`): one
/// [`FieldError`] from the file layer to the solver, no key translated on the way.
fn field(key: &str, message: String) -> FieldError {
    FieldError::new(key, message)
}

fn check_var(
    key: &str,
    v: &Var,
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
    unit: &str,
) -> Result<(), FieldError> {
    let inside = |x: f64| {
        x.is_finite()
            && (if lo_open { x > lo } else { x >= lo })
            && (if hi_open { x < hi } else { x <= hi })
    };
    let range = format!(
        "{}{lo}, {hi}{}{unit}",
        if lo_open { "(" } else { "[" },
        if hi_open { ")" } else { "]" }
    );
    // An angle's range also in degrees (the file usually gives degrees).
    let deg = if unit == " rad" {
        format!(
            "; in degrees: allowed {} {} angle < {} deg",
            (lo.to_degrees() * 1e9).round() / 1e9,
            if lo_open { "<" } else { "≤" },
            (hi.to_degrees() * 1e9).round() / 1e9
        )
    } else {
        String::new()
    };
    match *v {
        Var::Fixed(x) if !inside(x) => Err(field(key, format!("must be in {range}, got {x}{deg}"))),
        Var::Free { min, max } if !(inside(min) && inside(max)) => Err(field(
            key,
            format!("bounds must lie in {range}, got [{min}, {max}]{deg}"),
        )),
        Var::Free { min, max } if min >= max => Err(field(
            key,
            format!("free bounds need min < max, got [{min}, {max}]{deg}"),
        )),
        _ => Ok(()),
    }
}

impl CraneScene {
    /// Check every field; the error names the problem-file key and what is allowed.
    pub fn validate(&self) -> Result<(), FieldError> {
        let pos = |key: &str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(field(
                    key,
                    format!("must be a finite positive length in m, got {x}"),
                ))
            }
        };
        pos("mechanism.reach_max", self.reach_max)?;
        pos("mechanism.reach_min", self.reach_min)?;
        pos("mechanism.lift_height", self.lift_height)?;
        if !(self.foot_offset.is_finite() && self.foot_offset >= 0.0) {
            return Err(field(
                "mechanism.foot_offset",
                format!("must be a finite length >= 0 m, got {}", self.foot_offset),
            ));
        }
        if !(self.foot_height.is_finite() && self.foot_height >= 0.0) {
            return Err(field(
                "mechanism.foot_height",
                format!("must be a finite length >= 0 m, got {}", self.foot_height),
            ));
        }
        if self.reach_min <= self.foot_offset {
            return Err(field(
                "mechanism.reach_min",
                format!("must exceed foot_offset ({} m): the jib head must reach beyond the boom foot, got {}", self.foot_offset, self.reach_min),
            ));
        }
        if self.reach_max <= self.reach_min {
            return Err(field(
                "mechanism.reach_max",
                format!(
                    "must exceed reach_min ({} m), got {}",
                    self.reach_min, self.reach_max
                ),
            ));
        }
        check_var("design.k1", &self.k1, 0.0, 1.0, true, true, "")?;
        check_var("design.k2", &self.k2, 0.0, 5.0, true, false, "")?;
        // The angles, each in (0, 90°) (γ2 and γ3 may be 0).
        for (key, v, lo_open) in [
            ("design.phi_min", &self.phi_min, true),
            ("design.gamma1", &self.gamma1, true),
            ("design.gamma2", &self.gamma2, false),
            ("design.gamma3", &self.gamma3, false),
        ] {
            check_var(key, v, 0.0, FRAC_PI_2, lo_open, true, " rad")?;
        }
        if let SizingRule::Given(l) = self.sizing {
            pos("design.boom_length", l)?;
        }
        if let Some(r) = self.tie_pin.max_distance {
            pos("objective.tie_pin.max_distance", r)?;
        }
        for (key, r) in [
            ("objective.tie_pin.x_range", self.tie_pin.x_range),
            ("objective.tie_pin.y_range", self.tie_pin.y_range),
        ] {
            if let Some([lo, hi]) = r {
                if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                    return Err(field(
                        key,
                        format!("must be [min, max] with finite min < max (m), got [{lo}, {hi}]"),
                    ));
                }
            }
        }
        if let Some(d) = self.max_delta_h {
            pos("objective.max_delta_h", d)?;
        }
        if let Some(q) = self.load_mass {
            if !(q.is_finite() && q >= 0.0) {
                return Err(field(
                    "mechanism.load_mass",
                    format!("must be a finite mass >= 0 kg, got {q}"),
                ));
            }
        }
        if self.vars().iter().any(is_free) && !self.tie_pin.is_bounded() {
            return Err(field(
                "objective.tie_pin",
                "an optimisation needs a tie-pin limit (max_distance, or both x_range and y_range): without one the \
                 problem is degenerate, since a tie pin sent far away makes the tie a straight-line guide and drives \
                 delta h towards zero with a tie of unbounded length"
                    .into(),
            ));
        }
        Ok(())
    }

    /// The six design variables in the order k1, k2, φ_min, γ1, γ2, γ3.
    pub fn vars(&self) -> [Var; 6] {
        [
            self.k1,
            self.k2,
            self.phi_min,
            self.gamma1,
            self.gamma2,
            self.gamma3,
        ]
    }

    /// Allowed Δh (m): `max_delta_h` or 0.1·H.
    pub fn allowed_delta_h(&self) -> f64 {
        self.max_delta_h.unwrap_or(0.1 * self.lift_height)
    }

    /// Length scale of the scene (m): the maximum reach from the boom foot, R_max − r.
    pub fn length_scale(&self) -> f64 {
        self.reach_max - self.foot_offset
    }

    /// Boom length for the angles by the scene's sizing rule (m).
    pub fn boom_length(&self, angles: &Angles, k: f64) -> f64 {
        match self.sizing {
            SizingRule::MinReach => (self.reach_min - self.foot_offset) / angles.unit_reach_min(k),
            SizingRule::MaxReach => (self.reach_max - self.foot_offset) / angles.unit_reach_max(k),
            SizingRule::Given(l) => l,
        }
    }
}

/// The six design variables, in the order of the design vector `x` (keys of `design`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Vars {
    /// k1 = C1C2/C1C3: where the middle design position C2 lies between C1 and C3.
    pub k1: f64,
    /// k2 = a/L_v: the jib tail |DE| over the jib head length.
    pub k2: f64,
    /// φ_min (rad): boom elevation at maximum reach.
    pub phi_min_rad: f64,
    /// γ1 (rad): the boom from vertical at minimum reach.
    pub gamma1_rad: f64,
    /// γ2 (rad): the jib from vertical at minimum reach.
    pub gamma2_rad: f64,
    /// γ3 (rad): the jib below horizontal at maximum reach.
    pub gamma3_rad: f64,
}

impl Vars {
    /// The variables of the design vector `x`.
    pub fn of(x: &[f64; 6]) -> Vars {
        Vars {
            k1: x[0],
            k2: x[1],
            phi_min_rad: x[2],
            gamma1_rad: x[3],
            gamma2_rad: x[4],
            gamma3_rad: x[5],
        }
    }

    /// The variables `free` (indices into `x`) by their keys.
    fn named(&self, free: &[usize]) -> BTreeMap<String, f64> {
        let all = crate::report::number_map(self);
        crate::report::numbers::declared_keys(self)
            .into_iter()
            .enumerate()
            .filter(|(i, _)| free.contains(i))
            .map(|(_, k)| {
                let v = all[&k];
                (k, v)
            })
            .collect()
    }
}

/// The design of a crane result (keys of `design`, SI).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Design {
    /// The design variables.
    #[serde(flatten)]
    pub vars: Vars,
    /// φ_max = π/2 − γ1 (rad): boom elevation at minimum reach.
    pub phi_max_rad: f64,
    /// L_c = |AD| (m): the boom (absent without a crane geometry).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub boom_length_m: Option<f64>,
    /// L_v = |DC| = k·L_c (m): the jib head length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jib_length_m: Option<f64>,
    /// a = k2·L_v = |DE| (m): the jib tail.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jib_tail_m: Option<f64>,
    /// x of the tie pin B, the circumcentre of E1 E2 E3 (m; absent in the straight-guide limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tie_pin_x_m: Option<f64>,
    /// y of the tie pin B (m; absent in the straight-guide limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tie_pin_y_m: Option<f64>,
    /// b = |BE| (m): the tie (absent in the straight-guide limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tie_length_m: Option<f64>,
}

/// The objectives of a crane result (keys of `objectives`); the same type holds their
/// absolute errors (keys of `errors`).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Objectives {
    /// Δh = max − min of the jib-head height y_C over [φ_min, φ_max] on the followed branch
    /// (m); absent on a branch defect or when the linkage cannot assemble.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delta_h_m: Option<f64>,
}

impl Objectives {
    /// The key objective of every crane scene: Δh.
    pub const KEY: &'static str = key!(Objectives, delta_h_m);
}

/// Other figures of a crane result (keys of `derived`, SI); absent where the design has no
/// geometry or the figure does not apply.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Derived {
    /// k = L_v/L_c.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k: Option<f64>,
    /// L_c by the min-reach rule (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub boom_length_min_reach_rule_m: Option<f64>,
    /// L_c by the max-reach rule (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub boom_length_max_reach_rule_m: Option<f64>,
    /// H1: the head above A at both extremes (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub head_height_m: Option<f64>,
    /// y_C3: the head above A at minimum reach (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub head_height_min_reach_m: Option<f64>,
    /// H1 + h: the head above the rail (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub head_height_above_rail_m: Option<f64>,
    /// Reach from the slewing axis at φ_min (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reach_max_m: Option<f64>,
    /// Reach from the slewing axis at φ_max (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reach_min_m: Option<f64>,
    /// Boom angle of the middle design position (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phi2_rad: Option<f64>,
    /// [Δh]: the allowed Δh (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub allowed_delta_h_m: Option<f64>,
    /// |AB| (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tie_pin_distance_m: Option<f64>,
    /// Error bound of the tie pin B (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tie_pin_error_m: Option<f64>,
    /// Direction of the straight guide (rad; straight-guide limit only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub guide_angle_rad: Option<f64>,
    /// Violation of the tie-pin limit (m, 0 inside; `f64::MAX` when B is at infinity).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tie_pin_violation_m: Option<f64>,
    /// Refined maximum of the head height y_C (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub head_y_max_m: Option<f64>,
    /// Refined minimum of the head height y_C (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub head_y_min_m: Option<f64>,
    /// φ at the maximum head height (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phi_at_head_max_rad: Option<f64>,
    /// φ at the minimum head height (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phi_at_head_min_rad: Option<f64>,
    /// Smallest angle between tie and jib tail over the samples (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_transmission_angle_rad: Option<f64>,
    /// φ at the smallest transmission angle (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phi_at_min_transmission_rad: Option<f64>,
    /// Largest |M_A| = Q g |dy_C/dφ| (N·m; with `mechanism.load_mass`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_load_moment_nm: Option<f64>,
    /// Error of `max_load_moment_nm` (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_load_moment_error_nm: Option<f64>,
    /// φ at the largest load moment (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phi_at_max_load_moment_rad: Option<f64>,
}

/// Solver and sampling settings (one flat struct; see [`Settings::validate`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// Samples of the luffing range for the head path (every one must assemble); each sampled
    /// extremum is refined. Default 32 (the thesis example's Δh agrees with 400 samples to 1e-14 m).
    pub path_samples: usize,
    /// Abscissa tolerance of the extremum refinement (rad). Default 1e-7 (the value error ½|y''|·xtol² is ~1e-13 m).
    #[serde(with = "crate::units::angle_setting")]
    #[schemars(with = "crate::units::Qty<crate::units::Angle>")]
    pub xtol: f64,
    /// Refine each sampled extremum of the head height by Brent to `xtol`. Default true;
    /// false takes the extreme samples (each low by at most |y_C''|h²/8, h the sample
    /// spacing) — cheaper and coarser, for speed-against-error studies.
    pub refine_peaks: bool,
    /// Points of the path written for plots. Default 121.
    pub plot_points: usize,
    /// Halton points of the global stage per free variable. Default 64.
    pub global_samples: usize,
    /// SQP local searches from the best distinct global points. Default 6.
    pub local_starts: usize,
    /// SQP iteration limit per local search. Default 150.
    pub local_max_iters: u64,
    /// SQP stop: predicted gain of the merit below this fraction of the merit. Default 1e-10.
    pub local_tol: f64,
    /// Landscape grid points along k1 and k2 (0 = no landscape). Default 41 × 41.
    pub landscape_k1: usize,
    /// See `landscape_k1`.
    pub landscape_k2: usize,
    /// Penalty weight on constraint violations (per unit of length scale). Default 100.
    pub penalty: f64,
    /// Constraint violation accepted as met (m, relative to the length scale). Default 1e-7.
    pub constraint_tol: f64,
    /// Step of the finite difference for the load moment (rad). Default 1e-3.
    #[serde(with = "crate::units::angle_setting")]
    #[schemars(with = "crate::units::Qty<crate::units::Angle>")]
    pub moment_step: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            path_samples: 32,
            xtol: 1e-7,
            refine_peaks: true,
            plot_points: 121,
            global_samples: 64,
            local_starts: 6,
            local_max_iters: 150,
            local_tol: 1e-10,
            landscape_k1: 41,
            landscape_k2: 41,
            penalty: 100.0,
            constraint_tol: 1e-7,
            moment_step: 1e-3,
        }
    }
}

impl Settings {
    /// Check every field (keys `accuracy.<name>`).
    pub fn validate(&self) -> Result<(), FieldError> {
        let min_count = |key: &str, v: usize, min: usize| {
            if v >= min {
                Ok(())
            } else {
                Err(field(key, format!("must be at least {min}, got {v}")))
            }
        };
        min_count("accuracy.path_samples", self.path_samples, 8)?;
        min_count("accuracy.plot_points", self.plot_points, 2)?;
        min_count("accuracy.global_samples", self.global_samples, 1)?;
        min_count("accuracy.local_starts", self.local_starts, 1)?;
        if self.local_max_iters == 0 {
            return Err(field(
                "accuracy.local_max_iters",
                "must be at least 1".into(),
            ));
        }
        if (self.landscape_k1 == 0) != (self.landscape_k2 == 0)
            || self.landscape_k1 == 1
            || self.landscape_k2 == 1
        {
            return Err(field(
                "accuracy.landscape_k1",
                "landscape sizes must both be 0 (off) or both >= 2".into(),
            ));
        }
        for (key, v) in [
            ("accuracy.xtol", self.xtol),
            ("accuracy.local_tol", self.local_tol),
            ("accuracy.penalty", self.penalty),
            ("accuracy.constraint_tol", self.constraint_tol),
            ("accuracy.moment_step", self.moment_step),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(field(key, format!("must be finite and positive, got {v}")));
            }
        }
        Ok(())
    }
}

/// What the run achieved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// All variables fixed: the design was evaluated.
    Evaluated,
    /// Searched: the best design the multistart found; not proven globally optimal (the
    /// evidence is in [`Outcome::search`]).
    BestFound,
    /// The best design found violates a constraint (tie pin, reach or height).
    Infeasible,
    /// The design positions lie on different assembly branches.
    BranchDefect,
    /// The linkage cannot assemble somewhere in the luffing range.
    CannotAssemble,
    /// No geometry: the angles give no jib ratio, or no middle position exists.
    NoGeometry,
    /// The design is so ill-conditioned that Δh has no correct digit (its rounding bound
    /// exceeds Δh itself).
    Degenerate,
}

/// A thesis check, pass or fail.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Check {
    /// Name, e.g. `"reach_max"`.
    pub name: String,
    /// The computed value (SI).
    pub value: f64,
    /// The limit it is compared with (SI).
    pub limit: f64,
    /// Whether it passes.
    pub pass: bool,
    /// What is compared.
    pub note: String,
}

/// The design positions for drawing (m).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Positions {
    /// Boom angles of the design positions (rad).
    pub phi_rad: [f64; 3],
    /// C1, C2, C3.
    pub c: [[f64; 2]; 3],
    /// D1, D2, D3.
    pub d: [[f64; 2]; 3],
    /// E1, E2, E3.
    pub e: [[f64; 2]; 3],
    /// Tie pin B (`None` in the straight-guide limit).
    pub tie_pin: Option<[f64; 2]>,
}

/// One local search of the multistart.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Basin {
    /// Free variables at the start (names as in `design`).
    pub start: BTreeMap<String, f64>,
    /// Free variables at the end.
    pub end: BTreeMap<String, f64>,
    /// Δh at the end (m), `None` when the end is not a valid design.
    pub delta_h_m: Option<f64>,
    /// Penalised cost at the end (Δh and violations over the length scale).
    pub cost: f64,
    /// Whether the SQP met its stopping test (predicted gain or trust region below tolerance).
    pub converged: bool,
    /// Whether the end meets every constraint within `constraint_tol`.
    pub feasible: bool,
    /// Iterations.
    pub iterations: u64,
}

/// Δh over a (k1, k2) grid, other variables at the reported design.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Landscape {
    /// k1 values (columns).
    pub k1: Vec<f64>,
    /// k2 values (rows).
    pub k2: Vec<f64>,
    /// `delta_h_m[j][i]` at (`k1[i]`, `k2[j]`) in m; `None` where the linkage cannot be built,
    /// assemble over the range, or has a branch defect.
    pub delta_h_m: Vec<Vec<Option<f64>>>,
    /// Tie-pin limit violation (m, 0 inside; `None` as above), for drawing the boundary as
    /// its zero contour.
    pub tie_pin_violation_m: Vec<Vec<Option<f64>>>,
    /// (k1, k2) of the reported design.
    pub optimum: [f64; 2],
}

impl Landscape {
    /// The grid as CSV: `k1,k2,delta_h_m,tie_pin_violation_m` (empty field = no value).
    pub fn to_csv(&self) -> String {
        let opt = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:.12e}"));
        let mut s = String::from("k1,k2,delta_h_m,tie_pin_violation_m\n");
        for (j, k2) in self.k2.iter().enumerate() {
            for (i, k1) in self.k1.iter().enumerate() {
                s += &format!(
                    "{k1},{k2},{},{}\n",
                    opt(self.delta_h_m[j][i]),
                    opt(self.tie_pin_violation_m[j][i])
                );
            }
        }
        s
    }
}

/// Everything a report needs.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Outcome {
    /// What was achieved.
    pub status: Status,
    /// The boom-length rule, as a formula.
    pub sizing_rule: String,
    /// The design.
    pub design: Design,
    /// The objectives.
    pub objectives: Objectives,
    /// Estimated absolute error of each objective.
    pub errors: Objectives,
    /// Derived quantities.
    pub derived: Derived,
    /// The thesis's checks, pass/fail.
    pub checks: Vec<Check>,
    /// Anything the reader must know.
    pub warnings: Vec<String>,
    /// Solver and evaluation count.
    pub method: String,
    /// Objective evaluations (Δh over the whole range) spent.
    pub evaluations: usize,
    /// Design positions.
    pub positions: Option<Positions>,
    /// Jib-head path C over the luffing range (m).
    pub path: Vec<[f64; 2]>,
    /// Jib-tail path E (m).
    pub tail_path: Vec<[f64; 2]>,
    /// Boom angles of the path points (rad).
    pub path_phi_rad: Vec<f64>,
    /// Local searches of the multistart.
    pub basins: Vec<Basin>,
    /// The design vector evaluated, in the order of [`Vars`] (what [`landscape`] is
    /// computed around).
    pub x: [f64; 6],
    /// What the multistart did (`None` when nothing is free).
    pub search: Option<crate::synth::SearchEvidence>,
}

/// Relative distance in Δh under which two local searches' ends count as the same basin.
pub const SAME_BASIN: f64 = 1e-6;

/// Reach and height shortfalls below this fraction of the length scale R_max − r are counted
/// as 0: the sizing rule meets one reach exactly, and its rounding (a few ε of the scale)
/// must not read as a violation. Far below `settings.constraint_tol` (1e-7), so it never
/// decides feasibility by itself.
pub const REACH_ROUNDING: f64 = 1e-12;

/// Step (in the unit box of the free variables) of the SQP's central differences. The
/// heights are accurate to ~1e-15 of the scale, so the derivative's rounding is ~1e-9
/// relative and its truncation ~H² = 1e-12: the QP's model is good to ~1e-9, far below what
/// moves the merit; the reported Δh never depends on it (it is evaluated, not modelled).
const JACOBIAN_STEP: f64 = 1e-6;

/// Initial trust-region radius of the SQP (∞-norm, unit box) and its cap: a tenth and a
/// half of the box's side.
const TRUST_INITIAL: f64 = 0.1;
/// See [`TRUST_INITIAL`].
const TRUST_MAX: f64 = 0.5;

/// The SQP stops when the trust region or the step falls below this (unit box): 1e-12 of
/// the box is ~1e-13 rad in an angle, beyond what moves Δh by more than round-off.
const TRUST_MIN: f64 = 1e-12;

/// Initial ℓ1 merit weight of the SQP (raised to twice the largest multiplier).
const MU_INITIAL: f64 = 1e-2;

/// Initial Hessian of the SQP's Lagrangian, a multiple of the identity (Δh/L is ~1e-2, its
/// curvature over the unit box of that order or less).
const HESSIAN_INITIAL: f64 = 1e-3;

/// Linearised constraint values (over L) within this of 0 count as active in the QP's
/// step, for the second-order correction.
const ACTIVE_TOL: f64 = 1e-9;

/// A constraint's derivative (over L, per unit box) below this is rounding noise (a real
/// limit moves by ~0.1–1 of the scale across the box; the noise of an exactly met one is
/// ~ε/JACOBIAN_STEP ≈ 1e-10).
const FLAT_ROW: f64 = 1e-6;

/// Tolerance (rad) of the Brent refinement of the largest load moment: its value error
/// ½|M''|·tol² is ~1e-18 of |M| per rad², far below the moment's finite-difference error,
/// which is what `max_load_moment_error_nm` carries.
const MOMENT_PEAK_XTOL: f64 = 1e-9;

/// The jib head is at equal heights at both extremes by construction (the choice of k); the
/// check passes when they differ by less than this fraction of L_c (the rounding of k and of
/// the two head positions is a few ε·L_c).
const EQUAL_HEIGHTS_TOL: f64 = 1e-9;

/// A stated relative error of Δh above this draws the digits-left warning (well-conditioned
/// designs state ~1e-10 or less).
const DIGITS_WARNING: f64 = 1e-6;

/// One design point evaluated: boom, synthesis, heights and constraint violations.
#[derive(Debug, Clone)]
pub struct Evaluation {
    /// Step 1.
    pub boom: Boom,
    /// Step 2.
    pub synthesis: Synthesis,
    /// Δh and the extrema, or why the path fails.
    pub heights: Result<HeadHeights, PathError>,
    /// Tie-pin violation (m); infinite for the straight-guide limit.
    pub tie_pin_violation: f64,
    /// Shortfall of the maximum reach (m, 0 when met).
    pub reach_max_violation: f64,
    /// Excess of the minimum reach (m, 0 when met).
    pub reach_min_violation: f64,
    /// Shortfall of the head height (m, 0 when met).
    pub height_violation: f64,
}

impl Evaluation {
    /// Sum of the finite constraint violations (m).
    pub fn violation(&self) -> f64 {
        self.tie_pin_violation
            + self.reach_max_violation
            + self.reach_min_violation
            + self.height_violation
    }

    /// Δh if the linkage is valid (no branch defect, assembles over the range).
    pub fn delta_h(&self) -> Option<f64> {
        match (&self.synthesis.branch, &self.heights) {
            (Branch::Consistent(_), Ok(h)) => Some(h.delta_h),
            _ => None,
        }
    }
}

/// Evaluate the design x = (k1, k2, φ_min, γ1, γ2, γ3) of a scene.
pub fn evaluate(
    scene: &CraneScene,
    x: &[f64; 6],
    settings: &Settings,
) -> Result<Evaluation, CraneGeomError> {
    let (boom, synthesis) = build(scene, x)?;
    let (angles, k) = (boom.angles, boom.k);
    // The tie pin's rounding (its condition, see `tie_circle`) moves the tail by at most
    // |δB| + |δb| over sin μ (μ the smallest transmission angle) and the head by that over
    // k2, each extremum: Δh by twice that.
    let heights = head_heights_with(
        &synthesis.linkage,
        settings.path_samples,
        settings.refine_peaks.then_some(settings.xtol),
    )
    .map(|mut h| {
        let tangency = h.min_transmission.sin().max(f64::EPSILON.sqrt());
        h.error += 4.0 * synthesis.guide_error / (x[1] * tangency);
        h
    });
    let tie_pin_violation = match synthesis.guide {
        Guide::Circle { centre, .. } => scene.tie_pin.violation(centre),
        Guide::Line { .. } if scene.tie_pin.is_bounded() => f64::INFINITY,
        Guide::Line { .. } => 0.0,
    };
    let r_max = boom.l_c * angles.unit_reach_max(k);
    let r_min = boom.l_c * angles.unit_reach_min(k);
    let tol = REACH_ROUNDING * scene.length_scale();
    let pos = |v: f64| if v > tol { v } else { 0.0 };
    Ok(Evaluation {
        boom,
        synthesis,
        heights,
        tie_pin_violation,
        reach_max_violation: pos(scene.reach_max - scene.foot_offset - r_max),
        reach_min_violation: pos(r_min - (scene.reach_min - scene.foot_offset)),
        height_violation: pos(scene.lift_height - scene.foot_height - boom.head_height()),
    })
}

/// Cost of an infeasible geometry (in units of the length scale; a valid Δh is ~1e-2).
const NO_GEOMETRY_COST: f64 = 10.0;

/// The design problem over the unit box of the free variables: the penalised cost of the
/// global stage and the pieces of the local SQP.
struct Objective<'a> {
    scene: &'a CraneScene,
    settings: &'a Settings,
    free: Vec<usize>,
    base: [f64; 6],
    lo: [f64; 6],
    hi: [f64; 6],
    evals: AtomicUsize,
}

/// One design seen by the local search: Δh and every local extremum of the head height
/// (normalised boom angle t = (φ − φ_min)/(φ_max − φ_min), height over the length scale L),
/// and the signed constraints over L (≤ 0 met).
#[derive(Debug, Clone)]
struct Probe {
    /// Δh/L.
    dh: f64,
    /// (t, y/L) of the local maxima.
    maxima: Vec<(f64, f64)>,
    /// (t, y/L) of the local minima.
    minima: Vec<(f64, f64)>,
    /// Signed constraints over L.
    cons: Vec<f64>,
}

impl Probe {
    /// Exact L1 merit Δh/L + μ Σ max(0, c).
    fn merit(&self, mu: f64) -> f64 {
        self.dh + mu * self.cons.iter().map(|c| c.max(0.0)).sum::<f64>()
    }
}

/// Signed constraints of a built design over the length scale (≤ 0 met): each tie-pin limit
/// (|AB| − R, lo − x_B, x_B − hi, lo − y_B, y_B − hi), the reach shortfall at maximum reach,
/// the reach excess at minimum reach and the head-height shortfall. `None` for the
/// straight-guide limit under a bounded tie-pin limit (B at infinity).
fn signed_constraints(scene: &CraneScene, boom: &Boom, syn: &Synthesis) -> Option<Vec<f64>> {
    let l = scene.length_scale();
    let mut c = Vec::with_capacity(8);
    let t = &scene.tie_pin;
    if t != &TiePinLimit::default() {
        let Guide::Circle { centre: b, .. } = syn.guide else {
            return None;
        };
        if let Some(r) = t.max_distance {
            c.push((b.norm() - r) / l);
        }
        if let Some([lo, hi]) = t.x_range {
            c.extend([(lo - b.x) / l, (b.x - hi) / l]);
        }
        if let Some([lo, hi]) = t.y_range {
            c.extend([(lo - b.y) / l, (b.y - hi) / l]);
        }
    }
    let (a, k) = (&boom.angles, boom.k);
    c.push((scene.reach_max - scene.foot_offset - boom.l_c * a.unit_reach_max(k)) / l);
    c.push((boom.l_c * a.unit_reach_min(k) - (scene.reach_min - scene.foot_offset)) / l);
    c.push((scene.lift_height - scene.foot_height - boom.head_height()) / l);
    Some(c)
}

/// The load's unbalanced moment about A at φ, M_A = W dy_C/dφ, and its error (N·m): from
/// the statics of a weightless boom system with the load W at the jib head (thesis §2.2,
/// M_Ah = N L_c sin α; exact up to the rounding and conditioning it states) when the tie is a
/// circle, by the finite difference [`load_moment`] for the straight-guide limit.
fn load_moment_at(
    link: &crate::families::crane::model::Linkage,
    w: f64,
    phi: f64,
    h: f64,
) -> Option<(f64, f64)> {
    use crate::families::crane::statics::{statics, Loads, SelfWeight};
    if let Guide::Circle { .. } = link.guide {
        let pose = link.pose(phi)?;

        let loads = Loads {
            load_mass: w / crate::units::STANDARD_GRAVITY,
            ..Loads::default()
        };
        let s = statics(link, phi, &pose, &SelfWeight::NONE, &loads)?;
        return Some((s.drive_torque, s.drive_torque_error));
    }
    load_moment(link, w, phi, h)
}

/// Boom and synthesis of the design x (steps 1 and 2).
pub(crate) fn build(scene: &CraneScene, x: &[f64; 6]) -> Result<(Boom, Synthesis), CraneGeomError> {
    let angles = Angles {
        phi_min: x[2],
        gamma1: x[3],
        gamma2: x[4],
        gamma3: x[5],
    };
    let k = Boom::new(1.0, angles)?.k;
    let boom = Boom::new(scene.boom_length(&angles, k), angles)?;
    let synthesis = synthesize(&boom, x[0], x[1])?;
    Ok((boom, synthesis))
}

impl Objective<'_> {
    /// Design point of unit coordinates u (clamped to the box) and the distance outside it.
    fn point(&self, u: &[f64]) -> ([f64; 6], f64) {
        let mut x = self.base;
        let mut outside = 0.0;
        for (&i, &ui) in self.free.iter().zip(u) {
            let c = ui.clamp(0.0, 1.0);
            outside += (ui - c).abs();
            x[i] = self.lo[i] + c * (self.hi[i] - self.lo[i]);
        }
        (x, outside)
    }

    /// Δh/L + penalty·(violations/L + distance outside the box); a geometry that fails costs
    /// [`NO_GEOMETRY_COST`] more. The screening cost of the global stage.
    fn value(&self, u: &[f64]) -> f64 {
        self.evals.fetch_add(1, Ordering::Relaxed);
        let (x, outside) = self.point(u);
        let l = self.scene.length_scale();
        let w = self.settings.penalty;
        match evaluate(self.scene, &x, self.settings) {
            Ok(ev) => match ev.delta_h() {
                Some(dh) if ev.tie_pin_violation.is_finite() => {
                    dh / l + w * (ev.violation() / l + outside)
                }
                _ => NO_GEOMETRY_COST + w * outside,
            },
            Err(_) => NO_GEOMETRY_COST + w * outside,
        }
    }

    /// The built design at u if it is a valid linkage on one branch.
    fn linkage(&self, u: &[f64]) -> Option<(Boom, Synthesis)> {
        let (x, _) = self.point(u);
        let (boom, syn) = build(self.scene, &x).ok()?;
        matches!(syn.branch, Branch::Consistent(_)).then_some((boom, syn))
    }

    /// Δh, the local extrema and the constraints at u (`None`: no valid linkage there).
    fn probe(&self, u: &[f64]) -> Option<Probe> {
        self.evals.fetch_add(1, Ordering::Relaxed);
        let (boom, syn) = self.linkage(u)?;
        let cons = signed_constraints(self.scene, &boom, &syn)?;
        let link = &syn.linkage;
        let [p0, p1] = link.phi_range;
        let ext = head_extrema(link, self.settings.path_samples, self.settings.xtol).ok()?;
        let l = self.scene.length_scale();
        let pieces = |m: bool| -> Vec<(f64, f64)> {
            ext.iter()
                .filter(|e| e.is_max == m)
                .map(|e| ((e.phi - p0) / (p1 - p0), e.y / l))
                .collect()
        };
        let (maxima, minima) = (pieces(true), pieces(false));
        let top = maxima.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let bottom = minima.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        Some(Probe {
            dh: top - bottom,
            maxima,
            minima,
            cons,
        })
    }

    /// y/L at the normalised boom angles `ts` and the constraints, for finite differences.
    fn values(&self, u: &[f64], ts: &[f64]) -> Option<Vec<f64>> {
        let (boom, syn) = self.linkage(u)?;
        let mut v = signed_constraints(self.scene, &boom, &syn)?;
        let link = &syn.linkage;
        let [p0, p1] = link.phi_range;
        let l = self.scene.length_scale();
        for &t in ts {
            v.push(link.pose(p0 + t * (p1 - p0))?.c.y / l);
        }
        Some(v)
    }

    /// Jacobian (rows: constraints, then maxima, then minima; columns: free variables) by
    /// central differences at fixed t (one-sided at the box faces or where one side fails).
    fn jacobian(&self, u: &[f64], p: &Probe) -> Option<Vec<Vec<f64>>> {
        let ts: Vec<f64> = p.maxima.iter().chain(&p.minima).map(|q| q.0).collect();
        let rows = p.cons.len() + ts.len();
        let mut centre: Option<Vec<f64>> = None;
        let mut jac = vec![vec![0.0; u.len()]; rows];
        const H: f64 = JACOBIAN_STEP;
        for j in 0..u.len() {
            let step = |s: f64| {
                let mut w = u.to_vec();
                w[j] = (u[j] + s).clamp(0.0, 1.0);
                let dw = w[j] - u[j];
                (w, dw)
            };
            let (wp, hp) = step(H);
            let (wm, hm) = step(-H);
            self.evals.fetch_add(2, Ordering::Relaxed);
            let (fp, fm) = (self.values(&wp, &ts), self.values(&wm, &ts));
            let (a, b, h) = match (fp, fm) {
                (Some(a), Some(b)) if hp > hm => (a, b, hp - hm),
                (a, b) => {
                    if centre.is_none() {
                        centre = Some(self.values(u, &ts)?);
                    }
                    let c = centre.clone()?;
                    match (a, b) {
                        (Some(a), _) if hp > 0.0 => (a, c, hp),
                        (_, Some(b)) if hm < 0.0 => (c, b, -hm),
                        _ => return None,
                    }
                }
            };
            for r in 0..rows {
                jac[r][j] = (a[r] - b[r]) / h;
            }
        }
        Some(jac)
    }
}

/// Where one local search ended.
#[derive(Debug, Clone)]
struct LocalRun {
    u: Vec<f64>,
    probe: Option<Probe>,
    converged: bool,
    iterations: u64,
}

/// Solution of the SQP subproblem: step, model value and the multipliers of the maxima,
/// minima and constraints.
struct QpStep {
    d: Vec<f64>,
    model: f64,
    lam_max: Vec<f64>,
    lam_min: Vec<f64>,
    lam_con: Vec<f64>,
    /// Σ v beyond the violation already present at d = 0 (the QP leaned on a slack).
    slack: f64,
}

/// The SQP subproblem of the minimax Δh = max_i y_i − min_k y_k (elastic ℓ1 form, trust
/// region Δ in the ∞-norm, inside the unit box), solved by clarabel:
///
/// min ½dᵀBd + s − r + μ Σ v  s.t.  y_i + g_i·d ≤ s,  y_k + g_k·d ≥ r,
/// c_m + a_m·d ≤ v_m,  v ≥ 0,  max(−Δ, −u) ≤ d ≤ min(Δ, 1 − u).
#[allow(clippy::needless_range_loop)]
fn qp_step(
    u: &[f64],
    p: &Probe,
    jac: &[Vec<f64>],
    b: &[Vec<f64>],
    delta: f64,
    mu: f64,
) -> Option<QpStep> {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{
        DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
    };
    let n = u.len();
    let (nc, nx, nn) = (p.cons.len(), p.maxima.len(), p.minima.len());
    let nv = n + 2 + nc;
    let (is, ir) = (n, n + 1);
    let y0 = 0.5
        * (p.maxima.iter().map(|q| q.1).fold(f64::MIN, f64::max)
            + p.minima.iter().map(|q| q.1).fold(f64::MAX, f64::min));
    let (mut pi, mut pj, mut pv) = (vec![], vec![], vec![]);
    for i in 0..n {
        for j in i..n {
            if b[i][j] != 0.0 {
                pi.push(i);
                pj.push(j);
                pv.push(b[i][j]);
            }
        }
    }
    let mut q = vec![0.0; nv];
    q[is] = 1.0;
    q[ir] = -1.0;
    for m in 0..nc {
        q[n + 2 + m] = mu;
    }
    let (mut ai, mut aj, mut av, mut rhs) = (vec![], vec![], vec![], vec![]);
    let mut row = 0;
    let mut push = |coefs: &[(usize, f64)], r: f64, rhs: &mut Vec<f64>| {
        for &(j, v) in coefs {
            ai.push(row);
            aj.push(j);
            av.push(v);
        }
        rhs.push(r);
        row += 1;
    };
    for (m, c) in p.cons.iter().enumerate() {
        let mut co: Vec<(usize, f64)> = (0..n).map(|j| (j, jac[m][j])).collect();
        co.push((n + 2 + m, -1.0));
        push(&co, -c, &mut rhs);
    }
    for (i, (_, y)) in p.maxima.iter().enumerate() {
        let mut co: Vec<(usize, f64)> = (0..n).map(|j| (j, jac[nc + i][j])).collect();
        co.push((is, -1.0));
        push(&co, -(y - y0), &mut rhs);
    }
    for (k, (_, y)) in p.minima.iter().enumerate() {
        let mut co: Vec<(usize, f64)> = (0..n).map(|j| (j, -jac[nc + nx + k][j])).collect();
        co.push((ir, 1.0));
        push(&co, y - y0, &mut rhs);
    }
    for m in 0..nc {
        push(&[(n + 2 + m, -1.0)], 0.0, &mut rhs);
    }
    for j in 0..n {
        push(&[(j, 1.0)], delta.min(1.0 - u[j]), &mut rhs);
        push(&[(j, -1.0)], delta.min(u[j]), &mut rhs);
    }
    let a = CscMatrix::new_from_triplets(row, nv, ai, aj, av);
    let pm = CscMatrix::new_from_triplets(nv, nv, pi, pj, pv);
    let cones = [SupportedConeT::NonnegativeConeT(row)];
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-13)
        .tol_gap_rel(1e-11)
        .tol_feas(1e-11)
        .max_iter(60)
        .build()
        .ok()?;
    let mut solver = DefaultSolver::new(&pm, &q, &a, &rhs, &cones, settings).ok()?;
    solver.solve();
    let sol = &solver.solution;
    if !matches!(
        sol.status,
        SolverStatus::Solved | SolverStatus::AlmostSolved
    ) {
        return None;
    }
    let z = &sol.z;
    let v0: f64 = p.cons.iter().map(|c| c.max(0.0)).sum();
    let v: f64 = sol.x[n + 2..].iter().sum();
    Some(QpStep {
        slack: (v - v0).max(0.0).max(if v0 == 0.0 { v } else { 0.0 }),
        d: sol.x[..n].to_vec(),
        model: sol.obj_val,
        lam_con: z[..nc].to_vec(),
        lam_max: z[nc..nc + nx].to_vec(),
        lam_min: z[nc + nx..nc + nx + nn].to_vec(),
    })
}

/// Gradient of the Lagrangian Σ λ_i g_i − Σ λ_k g_k + Σ ν_m a_m at a probe, each multiplier
/// of a maximum (minimum) given to the piece of the probe nearest in t.
fn lagrangian_gradient(p: &Probe, jac: &[Vec<f64>], old: &Probe, st: &QpStep) -> Vec<f64> {
    let n = jac.first().map_or(0, |r| r.len());
    let nc = p.cons.len();
    let mut g = vec![0.0; n];
    let nearest = |set: &[(f64, f64)], t: f64| {
        (0..set.len())
            .min_by(|&a, &b| (set[a].0 - t).abs().total_cmp(&(set[b].0 - t).abs()))
            .unwrap_or(0)
    };
    for (m, lam) in st.lam_con.iter().enumerate() {
        for j in 0..n {
            g[j] += lam * jac[m][j];
        }
    }
    for (i, lam) in st.lam_max.iter().enumerate() {
        let r = nc + nearest(&p.maxima, old.maxima[i].0);
        for j in 0..n {
            g[j] += lam * jac[r][j];
        }
    }
    for (k, lam) in st.lam_min.iter().enumerate() {
        let r = nc + p.maxima.len() + nearest(&p.minima, old.minima[k].0);
        for j in 0..n {
            g[j] -= lam * jac[r][j];
        }
    }
    g
}

impl Objective<'_> {
    /// Local search from u0: trust-region SQP on the minimax form of Δh (every local extremum
    /// of the head height a piece, the constraints linearised with elastic slacks, damped
    /// BFGS for the Hessian of the Lagrangian, exact ℓ1 merit; Fletcher's Sℓ1QP, Practical
    /// Methods of Optimization, 1987, §14.5). The tie-pin limit is followed as a constraint,
    /// not a penalty, so the search slides along it when it is active.
    fn sqp(&self, u0: &[f64]) -> LocalRun {
        let n = u0.len();
        // The ℓ1 weight: above the largest constraint multiplier seen (so the merit is exact),
        // but no larger, since a large weight lets the constraints' curvature eat the gain of
        // a step along them (the Maratos effect). Raised when the QP leans on a slack.
        let mut mu: f64 = MU_INITIAL;
        let mut u = u0.to_vec();
        let fail = |u: Vec<f64>, it| LocalRun {
            u,
            probe: None,
            converged: false,
            iterations: it,
        };
        let Some(mut p) = self.probe(&u) else {
            return fail(u, 0);
        };
        let Some(mut jac) = self.jacobian(&u, &p) else {
            return fail(u, 0);
        };
        let mut b: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| if i == j { HESSIAN_INITIAL } else { 0.0 })
                    .collect()
            })
            .collect();
        let mut delta: f64 = TRUST_INITIAL;
        let mut converged = false;
        let mut it = 0;
        while it < self.settings.local_max_iters {
            it += 1;
            let Some(mut st) = qp_step(&u, &p, &jac, &b, delta, mu) else {
                break;
            };
            while st.slack > 1e-13 && mu < self.settings.penalty {
                mu = (10.0 * mu).min(self.settings.penalty);
                match qp_step(&u, &p, &jac, &b, delta, mu) {
                    Some(s2) => st = s2,
                    None => break,
                }
            }
            let lam = st.lam_con.iter().fold(0.0f64, |a, &l| a.max(l));
            if 2.0 * lam > mu {
                mu = (2.0 * lam).min(self.settings.penalty);
            }
            let m0 = p.merit(mu);
            // s − r does not depend on the shift y0 of the QP: the model at d = 0 is m0.
            let pred = m0 - st.model;
            let dn = st.d.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            if pred <= self.settings.local_tol * m0.abs().max(1e-12) || dn < TRUST_MIN {
                converged = true;
                break;
            }
            let un: Vec<f64> = u
                .iter()
                .zip(&st.d)
                .map(|(a, d)| (a + d).clamp(0.0, 1.0))
                .collect();
            let un = self.second_order_correction(un, &p, &jac, &st);
            let pn = self.probe(&un);
            let rho = pn.as_ref().map_or(-1.0, |q| (m0 - q.merit(mu)) / pred);
            if rho >= 0.1 {
                let (pn, jn) = match pn.and_then(|q| self.jacobian(&un, &q).map(|j| (q, j))) {
                    Some(v) => v,
                    None => {
                        delta = 0.25 * dn;
                        continue;
                    }
                };
                // Damped BFGS (Powell 1978) on the Lagrangian's gradient.
                let g1 = lagrangian_gradient(&pn, &jn, &p, &st);
                let g0 = lagrangian_gradient(&p, &jac, &p, &st);
                let s: Vec<f64> = un.iter().zip(&u).map(|(a, c)| a - c).collect();
                let mut yv: Vec<f64> = g1.iter().zip(&g0).map(|(a, c)| a - c).collect();
                let bs: Vec<f64> = (0..n)
                    .map(|i| (0..n).map(|j| b[i][j] * s[j]).sum())
                    .collect();
                let sbs: f64 = s.iter().zip(&bs).map(|(a, c)| a * c).sum();
                let sy: f64 = s.iter().zip(&yv).map(|(a, c)| a * c).sum();
                if sbs > 0.0 {
                    if sy < 0.2 * sbs {
                        let th = 0.8 * sbs / (sbs - sy);
                        for i in 0..n {
                            yv[i] = th * yv[i] + (1.0 - th) * bs[i];
                        }
                    }
                    let sy: f64 = s.iter().zip(&yv).map(|(a, c)| a * c).sum();
                    if sy > 0.0 {
                        for i in 0..n {
                            for j in 0..n {
                                b[i][j] += yv[i] * yv[j] / sy - bs[i] * bs[j] / sbs;
                            }
                        }
                    }
                }
                if rho > 0.75 && dn > 0.8 * delta {
                    delta = (2.0 * delta).min(TRUST_MAX);
                }
                u = un;
                p = pn;
                jac = jn;
            } else {
                delta = 0.25 * dn;
            }
            if delta < TRUST_MIN {
                converged = true;
                break;
            }
        }
        LocalRun {
            u,
            probe: Some(p),
            converged,
            iterations: it,
        }
    }
}

impl Objective<'_> {
    /// Signed constraints over L at u (no head path: cheap).
    fn constraints(&self, u: &[f64]) -> Option<Vec<f64>> {
        let (boom, syn) = self.linkage(u)?;
        signed_constraints(self.scene, &boom, &syn)
    }

    /// Second-order correction of an SQP trial point (Fletcher, Practical Methods of
    /// Optimization, 1987, §14.4): the active constraints are curved (the tie pin moves on
    /// a curve as the variables change), so the full step d leaves them by O(|d|²) and the
    /// merit gains less than the model predicted — the Maratos effect, which pins the trust
    /// region and makes the search creep along an active tie-pin limit. Up to two chord
    /// Gauss–Newton steps δ = −Aᵀ(AAᵀ)⁻¹c(u + d), A the constraints' Jacobian at u (rows:
    /// active in the QP, or violated at the trial point; columns: variables not on a face
    /// of the box), bring the trial point back onto them. (Activity is read from the
    /// linearisation, not the multipliers: clarabel's interior-point multipliers are
    /// positive on every row.) Unchanged when the correction
    /// cannot be computed.
    fn second_order_correction(
        &self,
        mut un: Vec<f64>,
        p: &Probe,
        jac: &[Vec<f64>],
        st: &QpStep,
    ) -> Vec<f64> {
        let n = un.len();
        let lin = |m: usize| p.cons[m] + (0..n).map(|j| jac[m][j] * st.d[j]).sum::<f64>();
        let free: Vec<usize> = (0..n).filter(|&j| un[j] > 0.0 && un[j] < 1.0).collect();
        for _ in 0..2 {
            let Some(c) = self.constraints(&un) else {
                break;
            };
            // A constraint the free variables cannot move (e.g. the reach met exactly by the
            // sizing rule) has a row of rounding noise only and is left out.
            let moves = |m: usize| free.iter().any(|&j| jac[m][j].abs() > FLAT_ROW);
            let rows: Vec<usize> = (0..p.cons.len())
                .filter(|&m| c[m] > 0.0 || lin(m) > -ACTIVE_TOL)
                .filter(|&m| moves(m))
                .collect();
            if rows.is_empty() || rows.len() > free.len() {
                break;
            }
            if rows.iter().all(|&m| c[m].abs() <= f64::EPSILON) {
                break;
            }
            let a = |r: usize, j: usize| jac[rows[r]][free[j]];
            let k = rows.len();
            let gram: Vec<Vec<f64>> = (0..k)
                .map(|r| {
                    (0..k)
                        .map(|q| (0..free.len()).map(|j| a(r, j) * a(q, j)).sum())
                        .collect()
                })
                .collect();
            let rhs: Vec<f64> = rows.iter().map(|&m| c[m]).collect();
            let Some(w) = solve_small(gram, rhs) else {
                break;
            };
            for (j, &col) in free.iter().enumerate() {
                let dj: f64 = (0..k).map(|r| a(r, j) * w[r]).sum();
                un[col] = (un[col] - dj).clamp(0.0, 1.0);
            }
        }
        un
    }
}

/// Solves the small dense system M w = b by Gaussian elimination with partial pivoting;
/// `None` when M is singular to working precision.
#[allow(clippy::needless_range_loop)]
fn solve_small(mut m: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let k = b.len();
    let scale = m.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    for col in 0..k {
        let piv = (col..k).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))?;
        m.swap(col, piv);
        b.swap(col, piv);
        if !(m[col][col].abs() > 1e-12 * scale) {
            return None;
        }
        for r in col + 1..k {
            let f = m[r][col] / m[col][col];
            for c in col..k {
                m[r][c] -= f * m[col][c];
            }
            b[r] -= f * b[col];
        }
    }
    let mut w = vec![0.0; k];
    for r in (0..k).rev() {
        let s: f64 = (r + 1..k).map(|c| m[r][c] * w[c]).sum();
        w[r] = (b[r] - s) / m[r][r];
    }
    w.iter().all(|v| v.is_finite()).then_some(w)
}

/// Radical inverse of `i` in base `b` (the Halton sequence).
fn halton(mut i: usize, b: usize) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f /= b as f64;
        r += f * (i % b) as f64;
        i /= b;
    }
    r
}

const PRIMES: [usize; 6] = [2, 3, 5, 7, 11, 13];

/// Solve a crane scene: evaluate it when every variable is fixed, otherwise minimise Δh over
/// the free variables (Halton global stage + trust-region SQP from the best distinct points),
/// then evaluate the best design in full (path, checks, landscape, thesis comparison).
///
/// `Err` only for a scene or settings field that is not allowed (including an optimisation
/// without a tie-pin limit, which is degenerate); every mechanism failure is a [`Status`].
pub fn solve(scene: &CraneScene, settings: &Settings) -> Result<Outcome, FieldError> {
    scene.validate()?;
    settings.validate()?;
    let vars = scene.vars();
    let mut base = [0.0; 6];
    let (mut lo, mut hi) = ([0.0; 6], [0.0; 6]);
    for i in 0..6 {
        (lo[i], hi[i]) = vars[i].bounds();
        base[i] = 0.5 * (lo[i] + hi[i]);
    }
    let free: Vec<usize> = (0..6).filter(|&i| is_free(&vars[i])).collect();
    let obj = Objective {
        scene,
        settings,
        free: free.clone(),
        base,
        lo,
        hi,
        evals: AtomicUsize::new(0),
    };
    let mut basins = Vec::new();
    let mut warnings = Vec::new();
    let (x, method, status_opt) = if free.is_empty() {
        (
            base,
            "evaluation of the given design (all variables fixed)".to_string(),
            None,
        )
    } else {
        let n = free.len();
        // Global stage: Halton points (index from 1) over the unit box.
        let mut pts: Vec<(Vec<f64>, f64)> = (1..=settings.global_samples * n)
            .map(|i| {
                let u: Vec<f64> = (0..n).map(|d| halton(i, PRIMES[d])).collect();
                let c = obj.value(&u);
                (u, c)
            })
            .collect();
        pts.sort_by(|a, b| a.1.total_cmp(&b.1));
        let min_sep = 0.15 * (n as f64).sqrt();
        let mut starts: Vec<Vec<f64>> = Vec::new();
        for (u, _) in &pts {
            if starts.len() >= settings.local_starts {
                break;
            }
            if starts.iter().all(|s| {
                s.iter()
                    .zip(u)
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum::<f64>()
                    .sqrt()
                    >= min_sep
            }) {
                starts.push(u.clone());
            }
        }
        let name = |u: &[f64]| {
            let (x, _) = obj.point(u);
            Vars::of(&x).named(&free)
        };
        let tol = settings.constraint_tol;
        let l = scene.length_scale();
        let mut best: Option<(Vec<f64>, f64, bool, bool)> = None;
        for s in starts {
            let run = obj.sqp(&s);
            let (dh, feasible, merit) = match &run.probe {
                Some(p) => (
                    Some(p.dh * l),
                    p.cons.iter().all(|&c| c <= tol),
                    p.merit(settings.penalty),
                ),
                None => (None, false, NO_GEOMETRY_COST),
            };
            basins.push(Basin {
                start: name(&s),
                end: name(&run.u),
                delta_h_m: dh,
                cost: merit,
                converged: run.converged,
                feasible,
                iterations: run.iterations,
            });
            // Feasible ends first, then the smaller merit.
            let better = best
                .as_ref()
                .is_none_or(|b| (feasible && !b.3) || (feasible == b.3 && merit < b.1));
            if better {
                best = Some((run.u, merit, run.converged, feasible));
            }
        }
        let (u, _, converged, _) = best.expect("at least one start");
        let (x, _) = obj.point(&u);
        let method = format!(
            "multistart: {} Halton points (global stage, penalised cost), then trust-region SQP (Fletcher's Sl1QP: \
             minimax of the head-height extrema, constraints linearised with elastic slacks, damped BFGS, clarabel QP, \
             second-order correction onto the active constraints) \
             from the {} best distinct points (at most {} iterations each, stop at a predicted gain below {:e} of the \
             merit); l1 penalty {} in the merit",
            settings.global_samples * n,
            basins.len(),
            settings.local_max_iters,
            settings.local_tol,
            settings.penalty
        );
        (x, method, Some(converged))
    };
    let mut out = report(scene, settings, &x, &mut warnings);
    out.evaluations += obj.evals.load(Ordering::Relaxed);
    out.method = format!("{method}; {} evaluations of delta h", out.evaluations);
    out.basins = basins;
    if let Some(converged) = status_opt {
        if out.status == Status::Evaluated {
            out.status = Status::BestFound;
        }
        if !converged {
            warnings.push("the best local search stopped at its iteration limit".into());
        }
        let search = crate::synth::SearchEvidence::of_minima(
            "Halton global stage + trust-region SQP (Fletcher's Sl1QP) from the best distinct points".into(),
            out.basins
                .iter()
                .filter(|b| b.feasible)
                .filter_map(|b| b.delta_h_m)
                .collect(),
            out.basins.len(),
            out.evaluations,
            SAME_BASIN,
        );
        if search.distinct_basins > 1 {
            warnings.push(format!(
                "the local searches ended in {} different feasible basins (delta h from {:.6} to {:.6} m)",
                search.distinct_basins,
                search.best_values[0],
                search.best_values[search.best_values.len() - 1]
            ));
        }
        out.search = Some(search);
    }
    out.warnings = warnings;
    Ok(out)
}

/// Full evaluation of one design for the report.
fn report(
    scene: &CraneScene,
    settings: &Settings,
    x: &[f64; 6],
    warnings: &mut Vec<String>,
) -> Outcome {
    let mut out = Outcome {
        status: Status::Evaluated,
        sizing_rule: scene.sizing.describe(),
        design: Design {
            vars: Vars::of(x),
            phi_max_rad: FRAC_PI_2 - x[3],
            boom_length_m: None,
            jib_length_m: None,
            jib_tail_m: None,
            tie_pin_x_m: None,
            tie_pin_y_m: None,
            tie_length_m: None,
        },
        objectives: Objectives::default(),
        errors: Objectives::default(),
        derived: Derived::default(),
        checks: Vec::new(),
        warnings: Vec::new(),
        method: String::new(),
        evaluations: 1,
        positions: None,
        path: Vec::new(),
        tail_path: Vec::new(),
        path_phi_rad: Vec::new(),
        basins: Vec::new(),
        x: *x,
        search: None,
    };
    let ev = match evaluate(scene, x, settings) {
        Ok(ev) => ev,
        Err(e) => {
            out.status = Status::NoGeometry;
            warnings.push(format!("no crane geometry for this design: {e}"));
            return out;
        }
    };
    let (boom, syn) = (ev.boom, ev.synthesis);
    let angles = boom.angles;
    let l = &syn.linkage;
    out.design.boom_length_m = Some(boom.l_c);
    out.design.jib_length_m = Some(boom.l_v());
    out.design.jib_tail_m = Some(l.a);
    let rule_lc = SizingRule::MinReach;
    let lc_min_reach = CraneScene {
        sizing: rule_lc,
        ..scene.clone()
    }
    .boom_length(&angles, boom.k);
    out.derived.k = Some(boom.k);
    out.derived.boom_length_min_reach_rule_m = Some(lc_min_reach);
    out.derived.boom_length_max_reach_rule_m =
        Some((scene.reach_max - scene.foot_offset) / angles.unit_reach_max(boom.k));
    let h1 = boom.head_height();
    let c3 = boom.c3();
    let r_max = scene.foot_offset + boom.l_c * angles.unit_reach_max(boom.k);
    let r_min = scene.foot_offset + boom.l_c * angles.unit_reach_min(boom.k);
    out.derived.head_height_m = Some(h1);
    out.derived.head_height_min_reach_m = Some(c3.y);
    out.derived.head_height_above_rail_m = Some(h1 + scene.foot_height);
    out.derived.reach_max_m = Some(r_max);
    out.derived.reach_min_m = Some(r_min);
    out.derived.phi2_rad = Some(syn.positions.phi[1]);
    out.derived.allowed_delta_h_m = Some(scene.allowed_delta_h());
    let p2 = |p: P2| [p.x, p.y];
    out.positions = Some(Positions {
        phi_rad: syn.positions.phi,
        c: syn.positions.c.map(p2),
        d: syn.positions.d.map(p2),
        e: syn.positions.e.map(p2),
        tie_pin: match syn.guide {
            Guide::Circle { centre, .. } => Some(p2(centre)),
            Guide::Line { .. } => None,
        },
    });
    match syn.guide {
        Guide::Circle { centre, radius } => {
            out.design.tie_pin_x_m = Some(centre.x);
            out.design.tie_pin_y_m = Some(centre.y);
            out.design.tie_length_m = Some(radius);
            out.derived.tie_pin_distance_m = Some(centre.norm());
            out.derived.tie_pin_error_m = Some(syn.guide_error);
        }
        Guide::Line { dir, .. } => {
            warnings.push(
                "E1, E2, E3 are collinear: the tie pin is at infinity; the tail runs on the straight-guide limit \
                 (tie_pin_* and tie_length_m omitted)"
                    .into(),
            );
            out.derived.guide_angle_rad = Some(dir.y.atan2(dir.x));
        }
    }
    out.derived.tie_pin_violation_m = Some(if ev.tie_pin_violation.is_finite() {
        ev.tie_pin_violation
    } else {
        f64::MAX
    });
    let tol = settings.constraint_tol * scene.length_scale();
    let mut check = |name: &str, value: f64, limit: f64, pass: bool, note: &str| {
        out.checks.push(Check {
            name: name.into(),
            value,
            limit,
            pass,
            note: note.into(),
        });
    };
    check(
        "equal_head_heights",
        (c3.y - h1).abs(),
        EQUAL_HEIGHTS_TOL * boom.l_c,
        (c3.y - h1).abs() <= EQUAL_HEIGHTS_TOL * boom.l_c,
        "|y_C3 - y_C1| (m)",
    );
    check(
        "reach_max",
        r_max,
        scene.reach_max,
        ev.reach_max_violation <= tol,
        "reach at phi_min from the slewing axis >= R_max (m)",
    );
    check(
        "reach_min",
        r_min,
        scene.reach_min,
        ev.reach_min_violation <= tol,
        "reach at phi_max from the slewing axis <= R_min (m)",
    );
    check(
        "head_height",
        h1 + scene.foot_height,
        scene.lift_height,
        ev.height_violation <= tol,
        "jib head above the rail at the extremes >= H (m)",
    );
    check(
        "jib_not_horizontal_at_max_reach",
        angles.gamma3,
        0.0,
        angles.gamma3 > 0.0,
        "gamma3 > 0 (rad)",
    );
    check(
        "jib_not_vertical_at_min_reach",
        angles.gamma2,
        0.0,
        angles.gamma2 > 0.0,
        "gamma2 > 0 (rad)",
    );
    let pin_ok = ev.tie_pin_violation <= tol;
    if scene.tie_pin != TiePinLimit::default() {
        check(
            "tie_pin_limit",
            if ev.tie_pin_violation.is_finite() {
                ev.tie_pin_violation
            } else {
                f64::MAX
            },
            0.0,
            pin_ok,
            "violation of the tie-pin limit (m)",
        );
    }
    let in_range =
        |v: f64, a: f64, b: f64| v >= a.to_radians() - 1e-12 && v <= b.to_radians() + 1e-12;
    for (name, v, a, b) in [
        ("phi_min", angles.phi_min, 30.0, 45.0),
        ("gamma1", angles.gamma1, 5.0, 15.0),
        ("gamma2", angles.gamma2, 5.0, 10.0),
        ("gamma3", angles.gamma3, 10.0, 25.0),
    ] {
        if !in_range(v, a, b) {
            warnings.push(format!(
                "{name} = {:.3} deg is outside the thesis's recommended {a}-{b} deg",
                v.to_degrees()
            ));
        }
    }
    if let Branch::Defect(sides) = syn.branch {
        out.status = Status::BranchDefect;
        warnings.push(format!(
            "branch defect: the design positions lie on different assembly branches ({sides:?}); the linkage cannot \
             luff through all three without being taken apart. The path below follows the branch of position 1."
        ));
    }
    // Path for plots (on the followed branch, points that assemble).
    let [p0, p1] = l.phi_range;
    let m = settings.plot_points;
    for i in 0..m {
        let phi = p0 + (p1 - p0) * i as f64 / (m - 1) as f64;
        if let Some(pose) = l.pose(phi) {
            out.path.push(p2(pose.c));
            out.tail_path.push(p2(pose.e));
            out.path_phi_rad.push(phi);
        }
    }
    match &ev.heights {
        Ok(hh) => {
            out.evaluations = 1;
            if out.status != Status::BranchDefect {
                out.objectives.delta_h_m = Some(hh.delta_h);
                out.errors.delta_h_m = Some(hh.error);
                let rel = hh.error / hh.delta_h.abs();
                if rel >= 1.0 {
                    out.status = Status::Degenerate;
                    warnings.push(format!(
                        "ill-conditioned design: the rounding bound of delta h ({:.1e} m) exceeds delta h itself; no \
                         digit is certain (smallest angle of the triangle E1 E2 E3 {:.2e} rad, tie-pin error bound {:.1e} m)",
                        hh.error, syn.min_angle, syn.guide_error
                    ));
                } else if rel > DIGITS_WARNING {
                    warnings.push(format!(
                        "ill-conditioned design: delta h is good to {:.1e} m, about {:.0} significant digits (smallest \
                         angle of the triangle E1 E2 E3 {:.2e} rad, tie-pin error bound {:.1e} m)",
                        hh.error,
                        (-rel.log10()).floor(),
                        syn.min_angle,
                        syn.guide_error
                    ));
                }
                check(
                    "delta_h_allowed",
                    hh.delta_h,
                    scene.allowed_delta_h(),
                    hh.delta_h <= scene.allowed_delta_h(),
                    "delta h <= [delta h] (0.1 H unless given) (m)",
                );
            }
            out.derived.head_y_max_m = Some(hh.y_max);
            out.derived.head_y_min_m = Some(hh.y_min);
            out.derived.phi_at_head_max_rad = Some(hh.phi_at_max);
            out.derived.phi_at_head_min_rad = Some(hh.phi_at_min);
            out.derived.min_transmission_angle_rad = Some(hh.min_transmission);
            out.derived.phi_at_min_transmission_rad = Some(hh.phi_at_min_transmission);
            if hh.min_transmission < 10f64.to_radians() {
                warnings.push(format!(
                    "the tie and the jib tail come within {:.2} deg of alignment (at phi = {:.2} deg): the linkage is \
                     near its singular pose",
                    hh.min_transmission.to_degrees(),
                    hh.phi_at_min_transmission.to_degrees()
                ));
            }
            if let Some(q) = scene.load_mass {
                let w = q * 9.80665;
                let h = settings.moment_step;
                // With a tie, the moment from the statics (closed form, its rounding and
                // conditioning bounded); a straight guide by the finite difference.
                let load_moment =
                    |l: &crate::families::crane::model::Linkage, w: f64, phi: f64, h: f64| {
                        load_moment_at(l, w, phi, h)
                    };
                let mut worst = (0.0f64, 0.0f64, p0);
                let n = settings.path_samples;
                for i in 0..=n {
                    let phi = p0 + (p1 - p0) * i as f64 / n as f64;
                    if let Some((mm, e)) = load_moment(l, w, phi, h) {
                        if mm.abs() > worst.0.abs() {
                            worst = (mm, e, phi);
                        }
                    }
                }
                // Refine the largest |M| by Brent around the best sample.
                let dphi = (p1 - p0) / n as f64;
                let f = |phi: f64| load_moment(l, w, phi, h).map_or(0.0, |(mm, _)| mm.abs());
                if let Ok(e) = crate::numeric::brent_max(
                    f,
                    (worst.2 - dphi).max(p0),
                    (worst.2 + dphi).min(p1),
                    MOMENT_PEAK_XTOL,
                ) {
                    let err = load_moment(l, w, e.x, h).map_or(worst.1, |(_, er)| er);
                    out.derived.max_load_moment_nm = Some(e.fx);
                    out.derived.max_load_moment_error_nm = Some(err);
                    out.derived.phi_at_max_load_moment_rad = Some(e.x);
                }
            }
        }
        Err(e) => {
            if out.status != Status::BranchDefect {
                out.status = Status::CannotAssemble;
            }
            warnings.push(format!("delta h not available: {e}"));
        }
    }
    let feasible = ev.violation() <= tol && ev.tie_pin_violation.is_finite();
    if !feasible && out.status == Status::Evaluated {
        out.status = Status::Infeasible;
    }
    if scene.vars().iter().all(|v| !is_free(v)) && out.status == Status::Infeasible {
        // A given design that misses a check is still an evaluated design: the checks say which.
        out.status = Status::Evaluated;
        warnings.push("the given design fails at least one check (see checks)".into());
    }
    out
}

/// Δh over a (k1, k2) grid: the free bounds of k1 and k2, or [0.05, 0.95] × [0.2, 1.0] for a
/// fixed one; the other variables at `x`. `None` when the settings ask for no landscape.
/// A diagnostic of the design, not part of the solve: `landscape_k1`·`landscape_k2` full
/// evaluations (41 × 41 by default, ~99 % of an analysis), so the report computes it only
/// when a result's files are written.
pub fn landscape(scene: &CraneScene, settings: &Settings, x: &[f64; 6]) -> Option<Landscape> {
    let (n1, n2) = (settings.landscape_k1, settings.landscape_k2);
    if n1 == 0 {
        return None;
    }
    let range = |v: &Var, d: (f64, f64)| if is_free(v) { v.bounds() } else { d };
    let (a1, b1) = range(&scene.k1, (0.05, 0.95));
    let (a2, b2) = range(&scene.k2, (0.2, 1.0));
    let k1: Vec<f64> = (0..n1)
        .map(|i| a1 + (b1 - a1) * i as f64 / (n1 - 1) as f64)
        .collect();
    let k2: Vec<f64> = (0..n2)
        .map(|j| a2 + (b2 - a2) * j as f64 / (n2 - 1) as f64)
        .collect();
    let mut dh = vec![vec![None; n1]; n2];
    let mut viol = vec![vec![None; n1]; n2];
    for (j, &v2) in k2.iter().enumerate() {
        for (i, &v1) in k1.iter().enumerate() {
            let mut y = *x;
            y[0] = v1;
            y[1] = v2;
            if let Ok(ev) = evaluate(scene, &y, settings) {
                if let Some(d) = ev.delta_h() {
                    dh[j][i] = Some(d);
                    viol[j][i] = ev
                        .tie_pin_violation
                        .is_finite()
                        .then_some(ev.tie_pin_violation);
                }
            }
        }
    }
    Some(Landscape {
        k1,
        k2,
        delta_h_m: dh,
        tie_pin_violation_m: viol,
        optimum: [x[0], x[1]],
    })
}

/// The thesis's worked example (§3.4.2): R_max 35 m, R_min 10 m, r 5 m, H 22 m, h 12 m,
/// k1 0.2, k2 0.4, φ_min 35°, γ1 10°, γ2 5°, γ3 12°, L_c = 22.8 m (all fixed, no tie-pin
/// limit: nothing is searched).
pub fn thesis_example() -> CraneScene {
    let d = f64::to_radians;
    CraneScene {
        reach_max: 35.0,
        reach_min: 10.0,
        foot_offset: 5.0,
        lift_height: 22.0,
        foot_height: 12.0,
        k1: Var::Fixed(0.2),
        k2: Var::Fixed(0.4),
        phi_min: Var::Fixed(d(35.0)),
        gamma1: Var::Fixed(d(10.0)),
        gamma2: Var::Fixed(d(5.0)),
        gamma3: Var::Fixed(d(12.0)),
        sizing: SizingRule::Given(22.8),
        tie_pin: TiePinLimit::default(),
        max_delta_h: None,
        load_mass: None,
        balance: None,
    }
}

/// The thesis example with k1 ∈ [0.05, 0.95], k2 ∈ [0.2, 1.0] free and the tie pin confined
/// behind the boom foot within 15 m of it (|AB| ≤ 15 m, x_B ≥ 0; the thesis's own B, at
/// 12.56 m, is inside).
pub fn thesis_optimisation() -> CraneScene {
    CraneScene {
        k1: Var::Free {
            min: 0.05,
            max: 0.95,
        },
        k2: Var::Free { min: 0.2, max: 1.0 },
        tie_pin: TiePinLimit {
            max_distance: Some(15.0),
            x_range: Some([0.0, 15.0]),
            y_range: None,
        },
        ..thesis_example()
    }
}

/// The thesis's recommended step-1 ranges (§2): φ_min 30–45°, γ1 5–15°, γ2 5–10°,
/// γ3 10–25°, in degrees.
pub struct Recommended {
    phi_min: (f64, f64),
    gamma1: (f64, f64),
    gamma2: (f64, f64),
    gamma3: (f64, f64),
}

/// See [`Recommended`].
pub const RECOMMENDED: Recommended = Recommended {
    phi_min: (30.0, 45.0),
    gamma1: (5.0, 15.0),
    gamma2: (5.0, 10.0),
    gamma3: (10.0, 25.0),
};

impl Recommended {
    fn free((lo, hi): (f64, f64)) -> Var {
        Var::Free {
            min: lo.to_radians(),
            max: hi.to_radians(),
        }
    }
    /// φ_min free in its range.
    pub fn phi_min(&self) -> Var {
        Self::free(self.phi_min)
    }
    /// γ1 free in its range.
    pub fn gamma1(&self) -> Var {
        Self::free(self.gamma1)
    }
    /// γ2 free in its range.
    pub fn gamma2(&self) -> Var {
        Self::free(self.gamma2)
    }
    /// γ3 free in its range.
    pub fn gamma3(&self) -> Var {
        Self::free(self.gamma3)
    }
}

/// The thesis example with k1, k2 and the four step-1 angles free (the thesis's recommended
/// ranges: φ_min 30–45°, γ1 5–15°, γ2 5–10°, γ3 10–25°), L_c by the min-reach rule, and the
/// tie-pin limit of [`thesis_optimisation`].
pub fn thesis_optimisation_with_angles() -> CraneScene {
    CraneScene {
        phi_min: RECOMMENDED.phi_min(),
        gamma1: RECOMMENDED.gamma1(),
        gamma2: RECOMMENDED.gamma2(),
        gamma3: RECOMMENDED.gamma3(),
        sizing: SizingRule::MinReach,
        ..thesis_optimisation()
    }
}

/// Tukan 40T at Hoàng Diệu port (thesis §3.5): Q = 40 t, R_max 30 m, R_min 8 m, r 2.5 m,
/// H 25 m, h 16 m; k1 0.2 and k2 0.4 by the thesis's rule of thumb; the step-1 angles are
/// searched in the recommended ranges (the thesis's step-1 trial), L_c by the min-reach rule,
/// tie pin behind the boom foot within 12 m of it.
pub fn tukan_40t() -> CraneScene {
    CraneScene {
        reach_max: 30.0,
        reach_min: 8.0,
        foot_offset: 2.5,
        lift_height: 25.0,
        foot_height: 16.0,
        k1: Var::Fixed(0.2),
        k2: Var::Fixed(0.4),
        phi_min: RECOMMENDED.phi_min(),
        gamma1: RECOMMENDED.gamma1(),
        gamma2: RECOMMENDED.gamma2(),
        gamma3: RECOMMENDED.gamma3(),
        sizing: SizingRule::MinReach,
        tie_pin: TiePinLimit {
            max_distance: Some(12.0),
            x_range: Some([0.0, 12.0]),
            y_range: None,
        },
        max_delta_h: None,
        load_mass: Some(40_000.0),
        balance: None,
    }
}

/// Tukan 40T with k1 ∈ [0.05, 0.95] and k2 ∈ [0.2, 1.0] free as well (six variables).
pub fn tukan_40t_optimisation() -> CraneScene {
    CraneScene {
        k1: Var::Free {
            min: 0.05,
            max: 0.95,
        },
        k2: Var::Free { min: 0.2, max: 1.0 },
        ..tukan_40t()
    }
}
