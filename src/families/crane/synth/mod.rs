//! Synthesis and optimisation of the level-luffing four-bar jib crane (thesis `003`).
//!
//! The thesis chooses the step-1 angles by trial and k1, k2 by rule of thumb, then checks the
//! jib-head height variation Δh. This module does that job for given values, and searches the
//! same choices to minimise Δh: a deterministic global stage (Halton points over the box of
//! free variables) followed by the shared trust-region SQP ([`crate::synth::search::sqp`])
//! from the best distinct points. The scene, settings and result types are here; one design's
//! evaluation in `evaluate.rs`, the search in `search.rs`, the full evaluation for the result
//! in `outcome.rs`.
//!
//! The tie pin B must be confined by the scene: without a limit the problem is degenerate (a
//! tie of unbounded length is a straight guide and drives Δh to ~0), and
//! [`CraneScene::validate`] refuses it.
//!
//! A [`FieldError`] names the problem-file key: `mechanism.reach_max`, `mechanism.reach_min`,
//! `mechanism.foot_offset` (r), `mechanism.lift_height` (H), `mechanism.foot_height` (h),
//! `mechanism.load_mass`, `design.k1`, `design.k2`, `design.phi_min`, `design.gamma1..3`,
//! `design.boom_length`, `objective.tie_pin` (and its `.max_distance`, `.x_range`,
//! `.y_range`), `objective.max_delta_h`, `accuracy.*`.

use crate::families::crane::model::{Angles, Level};
use crate::geom::P2;
use crate::problem::FieldError;
use crate::report::numbers::key;
use serde::Serialize;
use std::collections::BTreeMap;
use std::f64::consts::FRAC_PI_2;

mod evaluate;
mod outcome;
mod search;

pub(crate) use evaluate::build;
pub use evaluate::{evaluate, Evaluation};
pub use outcome::landscape;
pub use search::solve;

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
    /// What the synthesis puts level and Δh measures: the jib head, or with
    /// `objective.minimize = "load-delta-h"` the load on `mechanism.hoist_rope`.
    pub level: crate::families::crane::model::Level,
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
    /// The step-1 angles.
    pub fn angles(&self) -> Angles {
        Angles {
            phi_min: self.phi_min_rad,
            gamma1: self.gamma1_rad,
            gamma2: self.gamma2_rad,
            gamma3: self.gamma3_rad,
        }
    }

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
    /// Δh_L = max − min of the load's height y_L over [φ_min, φ_max] on the inclined hoist
    /// rope (m): the objective of `minimize = "load-delta-h"`, present only there; absent as
    /// `delta_h_m` is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_delta_h_m: Option<f64>,
}

impl Objectives {
    /// The key objective of a crane scene that levels the head: Δh.
    pub const KEY: &'static str = key!(Objectives, delta_h_m);
    /// The key objective of a scene that levels the load: Δh_L.
    pub const LOAD_KEY: &'static str = key!(Objectives, load_delta_h_m);

    /// The key objective of a scene levelling `level`.
    pub fn key(level: &Level) -> &'static str {
        match level {
            Level::Head => Self::KEY,
            Level::Load(_) => Self::LOAD_KEY,
        }
    }
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
    /// The thesis's h2 = y_C2 − y_C1 (§2.2, Fig 2.3): how much higher the jib head is put at
    /// the middle precision point than at maximum reach so that the load on the inclined rope
    /// is level there, (|S − C1| − |S − C2|)/n (m; `minimize = "load-delta-h"` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h2_m: Option<f64>,
    /// The thesis's h3 = y_C3 − y_C1, the same at minimum reach (m; load level only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h3_m: Option<f64>,
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
        level: Level::Head,
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
        level: Level::Head,
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
