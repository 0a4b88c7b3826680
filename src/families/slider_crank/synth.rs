//! Crank counterweight synthesis for a slider-crank machine.
//!
//! The scene fixes the mechanism and the speed; the design is the counterweight (unbalance
//! U = m·r at angle β from the crank line, and how |U| splits into mass and radius). The
//! objective is the peak or the RMS shaking force, or the lightest / smallest-radius
//! counterweight under a peak-force limit. The convex core is [`crate::synth::counterweight`];
//! this module maps the scene onto it, splits |U| into m and r, and evaluates the result
//! and the classical baselines (no counterweight, y force zeroed, the 50 % rule, equal x and
//! y ranges) with the same refined peaks.

use crate::families::slider_crank::model::{
    rot, rot_cs, weight_torque_cs, BalancerPair, Kinematics, Loads, ProcessForce, SliderCrank,
    State,
};
use crate::geom::P2;
use crate::numeric::{
    brent_max, newton_polish, newton_root, periodic_peak, periodic_rms, periodic_rms_sampled,
    refine_periodic_sample, Extremum, PeriodicPeak, Refine, Shape,
};
use crate::report::numbers::key;
use crate::synth::counterweight::{self as cw, Affine, Direction, Field, Goal, Problem, Status};
use crate::synth::shape::{self, Sector, ShapeGoal, ShapeOutcome, ShapeSpec};
use crate::synth::Var;
use serde::Serialize;
use std::collections::BTreeMap;

/// What the synthesis minimises.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Objective {
    /// The peak over φ of |F| (minimax, SOCP).
    MinPeakForce,
    /// The RMS over φ of |F| (QP).
    MinRmsForce,
    /// The lightest counterweight whose peak force stays under `max_peak_force`.
    MinMass,
    /// The smallest-radius counterweight whose peak force stays under `max_peak_force`.
    MinRadius,
    /// The peak over φ of the drive torque |T| (with gravity, the counterweight's weight
    /// makes T affine in U: an LP, solved as 2-D cones by clarabel).
    MinPeakTorque,
    /// The peak over φ of the shaking moment about the crank axis |M| under
    /// `max_peak_force` (the crank counterweight adds no moment at constant speed; offset
    /// balancer pairs do: [`BalancerPair`]). Solved jointly by [`crate::synth::minimax`].
    MinPeakMoment,
}

/// How a free |U| is split into mass and radius when both are free.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    Default,
    schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Prefer {
    /// The smallest radius the mass bound allows (the paper's aim: a compact machine).
    #[default]
    SmallestRadius,
    /// The lightest mass the radius bound allows.
    Lightest,
}

/// The counterweight's design variables (SI).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CounterweightSpec {
    /// |U| = m·r (kg·m).
    pub unbalance: Var,
    /// β, angle of U from the crank line (rad); π = opposite the crank pin.
    pub angle: Var,
    /// Mass m (kg), if the scene sizes it.
    pub mass: Option<Var>,
    /// Centroid radius r (m), if the scene sizes it.
    pub radius: Option<Var>,
    /// Split preference when mass and radius are both free.
    pub prefer: Prefer,
    /// The plate that is the counterweight (`[design.shape]`): its mass and centroid radius
    /// follow from |U| and the plate, and |U| is bounded by what the envelope holds,
    /// |U| ≤ U_max ([`ShapeSpec::max_unbalance`], a convex disc).
    pub shape: Option<ShapeSpec>,
}

/// A resolved, checked slider-crank scene.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Scene {
    /// Mechanism.
    pub mech: SliderCrank,
    /// ω (rad/s).
    pub omega: f64,
    /// Counterweight design variables.
    pub counterweight: CounterweightSpec,
    /// Objective.
    pub objective: Objective,
    /// Peak shaking-force limit (N), a constraint (required by `MinMass`/`MinRadius`).
    pub max_peak_force: Option<f64>,
    /// Peak drive-torque limit (N·m), a constraint.
    pub max_peak_torque: Option<f64>,
    /// Gravity and process force.
    pub loads: Loads,
    /// Points of the torque–force Pareto front to compute (0: none).
    pub pareto_points: usize,
    /// Accuracy.
    pub settings: cw::Settings,
    /// Lanchester balancer pairs designed with the counterweight (`[design.balancers]`).
    pub balancers: Vec<BalancerSpec>,
    /// Peak shaking-moment limit (N·m), a constraint.
    pub max_shaking_moment: Option<f64>,
    /// Limits on the joint loads (N).
    pub load_limits: LoadLimits,
    /// Report the joint (bearing) loads over the cycle.
    pub bearing_loads: bool,
}

/// One Lanchester balancer pair of a scene: its geometry, its bound and the unbalance at
/// which the scene is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BalancerSpec {
    /// Order and mid-line offset.
    pub pair: BalancerPair,
    /// Largest |B_n| of the pair (kg·m; infinite: none).
    pub max_unbalance: f64,
    /// B_n = (B_c, B_s) (kg·m): zero in the scene as read (the design variable), the
    /// design's value in the scene [`Outcome::designed`] evaluates.
    pub unbalance: [f64; 2],
}

/// Peak limits on the joint loads (N); `None`: no limit.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct LoadLimits {
    /// Main bearing O (affine in U: a cone constraint of the design).
    pub main_bearing: Option<f64>,
    /// Crank pin A (independent of the design: checked).
    pub crank_pin: Option<f64>,
    /// Wrist pin B (independent of the design: checked).
    pub wrist_pin: Option<f64>,
    /// Guide normal force (independent of the design: checked).
    pub guide: Option<f64>,
}

impl Scene {
    /// Whether the scene needs the joint design of [`crate::synth::minimax`]: balancers, a
    /// shaking-moment objective or limit, or a main-bearing limit.
    pub fn joint(&self) -> bool {
        !self.balancers.is_empty()
            || self.objective == Objective::MinPeakMoment
            || self.max_shaking_moment.is_some()
            || self.load_limits.main_bearing.is_some()
    }

    /// Σ_n F_n,x/ω² of the balancers at their `unbalance` (kg·m).
    fn balancer_force0(&self, phi: f64) -> f64 {
        self.balancers
            .iter()
            .map(|b| {
                let c = b.pair.force_coeffs(phi);
                c[0] * b.unbalance[0] + c[1] * b.unbalance[1]
            })
            .sum()
    }

    /// Σ_n M_n/ω² of the balancers (kg·m²).
    fn balancer_moment0(&self, phi: f64) -> f64 {
        self.balancers
            .iter()
            .map(|b| {
                let c = b.pair.moment_coeffs(phi);
                c[0] * b.unbalance[0] + c[1] * b.unbalance[1]
            })
            .sum()
    }

    /// Σ_n T_n of the balancers' weights (N·m).
    fn balancer_torque(&self, phi: f64) -> f64 {
        let g = self.loads.gravity;
        self.balancers
            .iter()
            .map(|b| {
                let c = b.pair.weight_torque_coeffs(phi, g);
                c[0] * b.unbalance[0] + c[1] * b.unbalance[1]
            })
            .sum()
    }

    /// The scene with the balancers at `b` (kg·m, in order).
    pub fn with_balancers(&self, b: &[[f64; 2]]) -> Scene {
        let mut s = self.clone();
        for (spec, &u) in s.balancers.iter_mut().zip(b) {
            spec.unbalance = u;
        }
        s
    }

    /// The scan's sample count when `accuracy.scan_samples = "auto"` (the default): enough
    /// angles for this scene's bandwidth, at least 64 and at most 360 (the former fixed
    /// default).
    ///
    /// Every figure is a smooth periodic function of φ built from the kinematics, which are
    /// analytic in the strip |Im φ| < ρ, ρ = arcosh((L − |e|)/R) (the branch points of
    /// ψ = asin((R sin φ + e)/L), where (R sin φ + e)/L = ±1: a ≈ λ/2 decay per harmonic,
    /// e^{−ρ} = 0.126 at the paper's λ = 1/4), so harmonic k is of relative size ≲ k e^{−kρ}.
    /// The scan takes 4 samples per period of harmonic K = ⌈ln(10¹²)/ρ⌉ (relative size
    /// ≤ 1e-12 · K), i.e. ≥ 16 per period of every harmonic above 1e-3, and 8 per period of
    /// the highest balancer order. A tabulated process force (piecewise linear, kinks at
    /// its points) and a mechanism near its toggle (ρ small) get the fixed 360, as before.
    /// The choice is tested against dense brute force on random and near-toggle machines
    /// (`tests/slider_crank.rs`).
    pub fn auto_samples(&self) -> usize {
        let m = &self.mech;
        let s = (m.l - m.e.abs()) / m.r;
        if matches!(self.loads.process, ProcessForce::Table { .. }) || !(s > 1.0) {
            return cw::FALLBACK_SAMPLES;
        }
        let rho = s.acosh();
        let k = (1e12f64.ln() / rho).ceil();
        let orders = self.balancers.iter().map(|b| 8.0 * b.pair.order as f64);
        let n = orders.fold((4.0 * k).max(64.0), f64::max);
        if n >= cw::FALLBACK_SAMPLES as f64 {
            cw::FALLBACK_SAMPLES
        } else {
            (n as usize).div_ceil(8) * 8
        }
    }

    /// The accuracy settings with every `"auto"` count chosen for this scene
    /// ([`Scene::auto_samples`]; the RMS quadrature then uses the scan's angles).
    pub fn resolved_settings(&self) -> cw::Settings {
        let mut s = self.settings;
        if s.scan_samples == cw::AUTO {
            s.scan_samples = self.auto_samples();
        }
        if s.rms_samples == cw::AUTO {
            s.rms_samples = s.scan_samples;
        }
        s
    }
}

/// The shaking force per ω² without counterweight (kg·m): the links' f₀ and the balancers.
pub fn force0(scene: &Scene, st: &State) -> P2 {
    let f = scene.mech.shaking_force0(st);
    if scene.balancers.is_empty() {
        f
    } else {
        f + P2::new(scene.balancer_force0(st.phi), 0.0)
    }
}

/// The shaking moment about O per ω² (kg·m²): the links' M₀ and the balancers' couples.
pub fn moment0(scene: &Scene, st: &State) -> f64 {
    let m = scene.mech.shaking_moment0(st);
    if scene.balancers.is_empty() {
        m
    } else {
        m + scene.balancer_moment0(st.phi)
    }
}

/// Shaking force (N) of the scene (links and balancers) at φ for the unbalance `u`.
pub fn scene_force(scene: &Scene, u: P2, phi: f64) -> P2 {
    let (cs, f0) = force0_at(scene, phi);
    (f0 + rot_cs(cs, u)) * (scene.omega * scene.omega)
}

/// (cos φ, sin φ) and [`force0`] at φ from the force-only evaluation
/// ([`SliderCrank::shaking_force0_at`]): the same numbers as from the whole state.
fn force0_at(scene: &Scene, phi: f64) -> ([f64; 2], P2) {
    let (cs, f) = scene.mech.shaking_force0_at(phi).expect("assembly checked");
    if scene.balancers.is_empty() {
        (cs, f)
    } else {
        (cs, f + P2::new(scene.balancer_force0(phi), 0.0))
    }
}

/// Force and torque figures of one counterweight, in SI.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// U in the crank frame (kg·m).
    pub unbalance: [f64; 2],
    /// max |F| (N), refined.
    pub peak: f64,
    /// Crank angle of the peak (rad).
    pub peak_angle: f64,
    /// Bound on the peak's evaluation error (N).
    pub peak_error: f64,
    /// RMS of |F| (N).
    pub rms: f64,
    /// Quadrature error estimate of the RMS (N).
    pub rms_error: f64,
    /// max Fx − min Fx (N).
    pub ptp_x: f64,
    /// max Fy − min Fy (N).
    pub ptp_y: f64,
    /// max |Fx| (N).
    pub peak_x: f64,
    /// max |Fy| (N).
    pub peak_y: f64,
    /// max |T| of the drive torque (N·m), refined.
    pub peak_torque: f64,
    /// Crank angle of the torque peak (rad).
    pub peak_torque_angle: f64,
    /// Bound on the torque peak's evaluation error (N·m).
    pub peak_torque_error: f64,
}

impl Metrics {
    /// |U| (kg·m) and its angle from the crank direction in [0, 2π) (rad; 0 for U = 0).
    pub fn unbalance_polar(&self) -> (f64, f64) {
        polar(self.unbalance)
    }

    /// The figures of a baseline (its `improvement_pct` left for the report).
    pub fn baseline(&self) -> Baseline {
        let (unbalance_kgm, unbalance_angle_rad) = self.unbalance_polar();
        Baseline {
            unbalance_kgm,
            unbalance_angle_rad,
            peak_shaking_force_n: self.peak,
            rms_shaking_force_n: self.rms,
            peak_to_peak_x_n: self.ptp_x,
            peak_to_peak_y_n: self.ptp_y,
            peak_x_n: self.peak_x,
            peak_y_n: self.peak_y,
            peak_drive_torque_nm: self.peak_torque,
            improvement_pct: None,
        }
    }
}

/// |U| (kg·m) and its angle from the crank direction in [0, 2π) (rad; 0 for U = 0).
fn polar(u: [f64; 2]) -> (f64, f64) {
    let u = P2::new(u[0], u[1]);
    let angle = if u.norm() > 0.0 {
        u.y.atan2(u.x).rem_euclid(std::f64::consts::TAU)
    } else {
        0.0
    };
    (u.norm(), angle)
}

/// The design of a slider-crank result (keys of `design`, SI).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Design {
    /// |U| = m_cw·r_cw (kg·m): the counterweight's unbalance.
    pub counterweight_unbalance_kgm: f64,
    /// Angle of U from the crank direction, in [0, 2π) (rad).
    pub counterweight_angle_rad: f64,
    /// U along the crank (kg·m).
    pub counterweight_unbalance_x_kgm: f64,
    /// U across the crank (kg·m).
    pub counterweight_unbalance_y_kgm: f64,
    /// m_cw (kg), where the scene sizes it (the plate's mass with `[design.shape]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub counterweight_mass_kg: Option<f64>,
    /// r_cw (m), where the scene sizes it (the plate's centroid radius with `[design.shape]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub counterweight_radius_m: Option<f64>,
    /// The plate's inner radius rᵢ (m; with `[design.shape]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plate_inner_radius_m: Option<f64>,
    /// The plate's outer radius rₒ (m; with `[design.shape]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plate_outer_radius_m: Option<f64>,
    /// The plate's sector angle θ, symmetric about U (rad; with `[design.shape]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plate_angle_rad: Option<f64>,
    /// The plate's thickness t (m; with `[design.shape]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plate_thickness_m: Option<f64>,
    /// The plate's moment of inertia about the crank axis, ρt(θ/4)(rₒ⁴ − rᵢ⁴) (kg·m²; with
    /// `[design.shape]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plate_inertia_kgm2: Option<f64>,
    /// |B_1| (kg·m): the unbalance of the order-1 Lanchester balancer pair (shafts at 1ω;
    /// with `[design.balancers]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer1_unbalance_kgm: Option<f64>,
    /// arg B_1 in [0, 2π) (rad): the pair's force is ω²·1·|B_1|·cos(1φ + arg B_1) along
    /// the slider axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer1_phase_rad: Option<f64>,
    /// |B_1|/2 (kg·m): mass × radius on each of the pair's two shafts.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer1_shaft_unbalance_kgm: Option<f64>,
    /// |B_2| (kg·m): the unbalance of the order-2 Lanchester balancer pair (shafts at 2ω;
    /// with `[design.balancers]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer2_unbalance_kgm: Option<f64>,
    /// arg B_2 in [0, 2π) (rad): the pair's force is ω²·4·|B_2|·cos(2φ + arg B_2) along
    /// the slider axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer2_phase_rad: Option<f64>,
    /// |B_2|/2 (kg·m): mass × radius on each of the pair's two shafts.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer2_shaft_unbalance_kgm: Option<f64>,
    /// |B_3| (kg·m): the unbalance of the order-3 Lanchester balancer pair (shafts at 3ω;
    /// with `[design.balancers]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer3_unbalance_kgm: Option<f64>,
    /// arg B_3 in [0, 2π) (rad): the pair's force is ω²·9·|B_3|·cos(3φ + arg B_3) along
    /// the slider axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer3_phase_rad: Option<f64>,
    /// |B_3|/2 (kg·m): mass × radius on each of the pair's two shafts.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer3_shaft_unbalance_kgm: Option<f64>,
    /// |B_4| (kg·m): the unbalance of the order-4 Lanchester balancer pair (shafts at 4ω;
    /// with `[design.balancers]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer4_unbalance_kgm: Option<f64>,
    /// arg B_4 in [0, 2π) (rad): the pair's force is ω²·16·|B_4|·cos(4φ + arg B_4) along
    /// the slider axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer4_phase_rad: Option<f64>,
    /// |B_4|/2 (kg·m): mass × radius on each of the pair's two shafts.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balancer4_shaft_unbalance_kgm: Option<f64>,
}

impl Design {
    /// The design of unbalance `u` (crank frame), realised as `cw` (mass, radius, plate).
    pub fn new(u: [f64; 2], cw: &Realised, shape: Option<&ShapeSpec>) -> Design {
        let (p, (norm, angle)) = (P2::new(u[0], u[1]), polar(u));
        let plate = cw.plate.as_ref();
        Design {
            counterweight_unbalance_kgm: norm,
            counterweight_angle_rad: angle,
            counterweight_unbalance_x_kgm: p.x,
            counterweight_unbalance_y_kgm: p.y,
            counterweight_mass_kg: cw.mass,
            counterweight_radius_m: cw.radius,
            plate_inner_radius_m: plate.map(|s| s.inner_radius_m),
            plate_outer_radius_m: plate.map(|s| s.outer_radius_m),
            plate_angle_rad: plate.map(|s| s.angle_rad),
            plate_thickness_m: plate.and(shape).map(|s| s.thickness),
            plate_inertia_kgm2: plate.map(|s| s.inertia_kgm2),
            balancer1_unbalance_kgm: None,
            balancer1_phase_rad: None,
            balancer1_shaft_unbalance_kgm: None,
            balancer2_unbalance_kgm: None,
            balancer2_phase_rad: None,
            balancer2_shaft_unbalance_kgm: None,
            balancer3_unbalance_kgm: None,
            balancer3_phase_rad: None,
            balancer3_shaft_unbalance_kgm: None,
            balancer4_unbalance_kgm: None,
            balancer4_phase_rad: None,
            balancer4_shaft_unbalance_kgm: None,
        }
    }

    /// The design with the balancers' unbalances (`BalancerSpec::unbalance`) filled in.
    pub fn with_balancers(mut self, balancers: &[BalancerSpec]) -> Design {
        for b in balancers {
            let (norm, phase) = polar(b.unbalance);
            let (m, p, h) = match b.pair.order {
                1 => (
                    &mut self.balancer1_unbalance_kgm,
                    &mut self.balancer1_phase_rad,
                    &mut self.balancer1_shaft_unbalance_kgm,
                ),
                2 => (
                    &mut self.balancer2_unbalance_kgm,
                    &mut self.balancer2_phase_rad,
                    &mut self.balancer2_shaft_unbalance_kgm,
                ),
                3 => (
                    &mut self.balancer3_unbalance_kgm,
                    &mut self.balancer3_phase_rad,
                    &mut self.balancer3_shaft_unbalance_kgm,
                ),
                _ => (
                    &mut self.balancer4_unbalance_kgm,
                    &mut self.balancer4_phase_rad,
                    &mut self.balancer4_shaft_unbalance_kgm,
                ),
            };
            (*m, *p, *h) = (Some(norm), Some(phase), Some(0.5 * norm));
        }
        self
    }
}

/// The objectives of a slider-crank result (keys of `objectives`, SI).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Objectives {
    /// max over φ of |F|, the shaking force on the frame (N).
    pub peak_shaking_force_n: f64,
    /// RMS over φ of |F| (N).
    pub rms_shaking_force_n: f64,
    /// max over φ of |T|, the drive torque (N·m).
    pub peak_drive_torque_nm: f64,
    /// max over φ of the shaking moment about the crank axis (N·m).
    pub peak_shaking_moment_nm: f64,
}

impl Objectives {
    /// The key objective of a scene: the one minimised (`peak_shaking_force_n` for the mass
    /// and radius objectives, whose peak force is their constraint).
    pub fn key(objective: Objective) -> &'static str {
        match objective {
            Objective::MinPeakTorque => key!(Objectives, peak_drive_torque_nm),
            Objective::MinPeakMoment => key!(Objectives, peak_shaking_moment_nm),
            Objective::MinRmsForce => key!(Objectives, rms_shaking_force_n),
            Objective::MinPeakForce | Objective::MinMass | Objective::MinRadius => {
                key!(Objectives, peak_shaking_force_n)
            }
        }
    }
}

/// The headline of a scene, the dotted result key its design is judged on: the key objective,
/// or for the mass and radius objectives the design figure minimised.
pub fn headline(objective: Objective) -> String {
    match objective {
        Objective::MinMass => key!("design", Design, counterweight_mass_kg).into(),
        Objective::MinRadius => key!("design", Design, counterweight_radius_m).into(),
        o => format!("objectives.{}", Objectives::key(o)),
    }
}

/// The absolute errors of a slider-crank result (keys of `errors`, SI): one per objective,
/// and the model error of two-harmonic kinematics.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Errors {
    /// The error of each objective (same keys).
    #[serde(flatten)]
    pub objectives: Objectives,
    /// |peak with exact kinematics − peak with two harmonics| (N; two-harmonic kinematics only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_two_harmonic_n: Option<f64>,
    /// The joint loads' errors (same keys as in `derived`).
    #[serde(flatten)]
    pub joint_loads: JointLoadFigures,
}

/// The peak joint loads (keys of `derived` and, for their errors, of `errors`; N).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct JointLoadFigures {
    /// max over φ of the load on the main bearing O (N; with `model.bearing_loads` or a load limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_main_bearing_load_n: Option<f64>,
    /// max over φ of the load on the crank pin A (N; with `model.bearing_loads` or a load limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_crank_pin_load_n: Option<f64>,
    /// max over φ of the load on the wrist pin B (N; with `model.bearing_loads` or a load limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_wrist_pin_load_n: Option<f64>,
    /// max over φ of the load on the guide (normal force on the slider) (N; with `model.bearing_loads` or a load limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_guide_load_n: Option<f64>,
}

impl JointLoadFigures {
    /// The peaks (`error` false) or their errors (true).
    pub fn of(jl: Option<&JointLoadPeaks>, error: bool) -> JointLoadFigures {
        let v = |p: &LoadPeak| if error { p.error } else { p.peak };
        JointLoadFigures {
            peak_main_bearing_load_n: jl.map(|j| v(&j.main_bearing)),
            peak_crank_pin_load_n: jl.map(|j| v(&j.crank_pin)),
            peak_wrist_pin_load_n: jl.map(|j| v(&j.wrist_pin)),
            peak_guide_load_n: jl.map(|j| v(&j.guide)),
        }
    }
}

/// The crank angles of the peak joint loads (keys of `derived`, rad).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct JointLoadAngles {
    /// Crank angle of the peak main bearing load (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub main_bearing_load_angle_rad: Option<f64>,
    /// Crank angle of the peak crank pin load (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crank_pin_load_angle_rad: Option<f64>,
    /// Crank angle of the peak wrist pin load (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wrist_pin_load_angle_rad: Option<f64>,
    /// Crank angle of the peak guide load (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub guide_load_angle_rad: Option<f64>,
}

impl JointLoadAngles {
    /// The angles of `jl`.
    pub fn of(jl: Option<&JointLoadPeaks>) -> JointLoadAngles {
        JointLoadAngles {
            main_bearing_load_angle_rad: jl.map(|j| j.main_bearing.angle),
            crank_pin_load_angle_rad: jl.map(|j| j.crank_pin.angle),
            wrist_pin_load_angle_rad: jl.map(|j| j.wrist_pin.angle),
            guide_load_angle_rad: jl.map(|j| j.guide.angle),
        }
    }
}

/// Other figures of a slider-crank result (keys of `derived`, SI); `None` where they do not
/// apply.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Derived {
    /// λ = r/l: crank over rod.
    pub lambda: f64,
    /// ω (rad/s).
    pub omega_rad_s: f64,
    /// m_r: the rotating mass reduced to the crank pin (kg).
    pub rotating_mass_kg: f64,
    /// m_s: the reciprocating mass (kg).
    pub reciprocating_mass_kg: f64,
    /// (−U_x/r − m_r)/m_s: the share of the reciprocating mass the counterweight balances.
    pub reciprocating_fraction_balanced: f64,
    /// Crank angle of the peak shaking force (rad).
    pub peak_angle_rad: f64,
    /// Crank angle of the peak drive torque (rad).
    pub peak_torque_angle_rad: f64,
    /// max F_x − min F_x (N).
    pub peak_to_peak_x_n: f64,
    /// max F_y − min F_y (N).
    pub peak_to_peak_y_n: f64,
    /// The objective's optimality gap in its unit (N, or N·m for the torque).
    pub optimality_gap: f64,
    /// g/(r ω²): gravity against the crank pin's acceleration.
    pub gravity_ratio: f64,
    /// The crank angles of the scan (and of the RMS quadrature, when it is `"auto"` too)
    /// the figures were computed on: `accuracy.scan_samples`, or the count chosen for
    /// `"auto"` ([`Scene::auto_samples`]).
    pub scan_samples: usize,
    /// Static weight of the links and the counterweight (N; with gravity).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub static_weight_n: Option<f64>,
    /// The design's peak force with exact kinematics (N; two-harmonic kinematics only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_shaking_force_exact_kinematics_n: Option<f64>,
    /// Formula (6), (m_r + ½m_s)·r/r_cw, at the fixed lever radius (kg).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub formula6_counterweight_mass_kg: Option<f64>,
    /// Formula (6) on the paper's printed masses (kg).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub formula6_counterweight_mass_printed_inputs_kg: Option<f64>,
    /// Peak-torque reduction of the paper's counterweight against none (%).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paper_counterweight_torque_reduction_pct: Option<f64>,
    /// Force span of the Pareto front (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pareto_force_span_n: Option<f64>,
    /// Torque span of the Pareto front (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pareto_torque_span_nm: Option<f64>,
    /// The largest |U| the plate envelope holds (kg·m; with `[design.shape]`): the bound the
    /// optimisation keeps.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plate_max_unbalance_kgm: Option<f64>,
    /// The peak joint loads.
    #[serde(flatten)]
    pub joint_loads: JointLoadFigures,
    /// Their crank angles.
    #[serde(flatten)]
    pub joint_load_angles: JointLoadAngles,
}

/// The figures of a classical design evaluated like the result (keys of `baselines.NAME`, SI).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Baseline {
    /// |U| (kg·m).
    pub unbalance_kgm: f64,
    /// Angle of U from the crank direction (rad).
    pub unbalance_angle_rad: f64,
    /// max |F| (N).
    pub peak_shaking_force_n: f64,
    /// RMS |F| (N).
    pub rms_shaking_force_n: f64,
    /// max F_x − min F_x (N).
    pub peak_to_peak_x_n: f64,
    /// max F_y − min F_y (N).
    pub peak_to_peak_y_n: f64,
    /// max |F_x| (N).
    pub peak_x_n: f64,
    /// max |F_y| (N).
    pub peak_y_n: f64,
    /// max |T| (N·m).
    pub peak_drive_torque_nm: f64,
    /// (baseline − result)/baseline of the key objective (%).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub improvement_pct: Option<f64>,
}

/// Everything the solve found.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Outcome {
    /// Convex-solver status (or `Optimal` for a pure analysis).
    pub status: Status,
    /// The counterweight found.
    pub design: Metrics,
    /// Its mass, radius and plate, where the scene sizes them.
    pub counterweight: Realised,
    /// Optimality gap of the objective in its SI unit (N, or N·m for the torque): true
    /// value of the design minus the sampled lower bound; 0 for RMS (exact QP) and analyses.
    pub gap: f64,
    /// Peak shaking moment about the crank axis (N·m).
    pub peak_shaking_moment: f64,
    /// Error bound of `peak_shaking_moment` (N·m).
    pub peak_shaking_moment_error: f64,
    /// The torque–force Pareto front (empty unless asked for).
    pub pareto: Vec<ParetoPoint>,
    /// Static weight of the links and the counterweight (N), 0 without gravity.
    pub static_weight: f64,
    /// Baselines by name.
    pub baselines: BTreeMap<String, Metrics>,
    /// For two-harmonic kinematics: the design's peak force with exact kinematics (N).
    pub exact_peak: Option<f64>,
    /// Solver description.
    pub method: String,
    /// Warnings.
    pub warnings: Vec<String>,
    /// Why the problem is degenerate as posed (the objective does not depend on the free
    /// counterweight), if it is: the result's status is then `degenerate`.
    pub degenerate: Option<String>,
    /// The scene with the balancers at their design (equal to the scene without balancers).
    pub designed: Scene,
    /// The peak joint loads (with `bearing_loads` or a load limit).
    pub joint_loads: Option<JointLoadPeaks>,
}

/// The peak of one joint load over the cycle.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LoadPeak {
    /// max over φ of |F| (N).
    pub peak: f64,
    /// Its crank angle (rad).
    pub angle: f64,
    /// Bound on its error (N): refinement and round-off.
    pub error: f64,
}

/// The peak joint loads of a design ([`SliderCrank::joint_loads`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct JointLoadPeaks {
    /// Main bearing O.
    pub main_bearing: LoadPeak,
    /// Crank pin A.
    pub crank_pin: LoadPeak,
    /// Wrist pin B.
    pub wrist_pin: LoadPeak,
    /// Guide normal force |N|.
    pub guide: LoadPeak,
}

/// One point of the torque–force Pareto front: the least peak torque with the peak
/// shaking force limited to `force_limit`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ParetoPoint {
    /// ε, the force limit (N).
    pub force_limit_n: f64,
    /// Peak shaking force of the point's design (N).
    pub peak_shaking_force_n: f64,
    /// Peak drive torque of the point's design (N·m).
    pub peak_drive_torque_nm: f64,
    /// Its optimality gap in torque (N·m).
    pub gap_nm: f64,
    /// Unbalance in the crank frame (kg·m).
    pub unbalance_x_kgm: f64,
    /// See `unbalance_x_kgm`.
    pub unbalance_y_kgm: f64,
    /// Solver status.
    pub status: Status,
}

/// Why a scene cannot be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// The crank cannot turn a full revolution.
    #[error("the rod cannot reach the slider line at every crank angle: (R + |e|)/L = {0:.6} ≥ 1")]
    CannotAssemble(f64),
    /// No moving mass at all.
    #[error("all link masses are zero: there is no shaking force to balance")]
    NoMass,
    /// A peak evaluation failed.
    #[error("{0}")]
    Numeric(String),
}

/// The normalised fields of a scene. Force: f̂(φ; û) = f₀(φ)/U_ref + Rot(φ)·û with
/// U_ref = (m_tq + m_ct)R; torque: T̂ = T(φ; U)/(ω² U_ref R), affine in û through the
/// counterweight's weight.
struct Normalised<'a> {
    scene: &'a Scene,
    u_ref: f64,
    t_ref: f64,
}

impl<'a> Normalised<'a> {
    fn new(scene: &'a Scene) -> Self {
        let m = &scene.mech;
        let u_ref = (m.m_rot() + m.m_rec()) * m.r;
        Normalised {
            scene,
            u_ref,
            t_ref: scene.omega * scene.omega * u_ref * m.r,
        }
    }
    fn state(&self, phi: f64) -> State {
        // Assembly was checked for the whole revolution before any field is evaluated.
        self.scene.mech.state(phi).expect("assembly checked")
    }
    fn force(&self, phi: f64) -> Affine {
        let (cs, f0) = force0_at(self.scene, phi);
        self.force_of(cs, f0)
    }
    /// f̂ from (cos φ, sin φ) and f₀(φ).
    fn force_of(&self, [c, s]: [f64; 2], f0: P2) -> Affine {
        let f0 = f0 / self.u_ref;
        Affine {
            a: [[c, -s], [s, c]],
            b: [f0.x, f0.y],
        }
    }
    fn torque(&self, phi: f64) -> Affine {
        let st = self.state(phi);
        self.torque_of(st.cs, torque0(self.scene, &st))
    }
    /// T̂ from (cos φ, sin φ) and T(φ; 0) (N·m).
    fn torque_of(&self, cs: [f64; 2], t0: f64) -> Affine {
        let g = self.scene.loads.gravity;
        let k = self.u_ref / self.t_ref;
        let ax = weight_torque_cs(cs, g, P2::new(1.0, 0.0)) * k;
        let ay = weight_torque_cs(cs, g, P2::new(0.0, 1.0)) * k;
        Affine {
            a: [[ax, ay], [0.0, 0.0]],
            b: [t0 / self.t_ref, 0.0],
        }
    }
}

/// Shaking force (N) at φ for the unbalance `u` (kg·m, crank frame).
pub fn shaking_force(mech: &SliderCrank, omega: f64, u: P2, phi: f64) -> Option<P2> {
    mech.shaking_force0_at(phi)
        .map(|(cs, f0)| (f0 + rot_cs(cs, u)) * (omega * omega))
}

/// Drive torque (N·m) at φ for the unbalance `u` at constant speed:
/// T = ω²·(dE_kin/dφ)/ω² − Σ mᵢ g·rᵢ' − F_p x' − g·Rot'(φ)U.
pub fn drive_torque(scene: &Scene, u: P2, phi: f64) -> f64 {
    let st = scene.mech.state(phi).expect("assembly checked");
    torque0(scene, &st) + weight_torque_cs(st.cs, scene.loads.gravity, u)
}

/// The drive torque without counterweight (N·m): ω²·T_drive0 + T_load0 (inertia, link
/// weights, process force).
fn torque0(scene: &Scene, st: &State) -> f64 {
    let m = &scene.mech;
    let t = scene.omega * scene.omega * m.drive_torque0(st) + m.load_torque0(st, &scene.loads);
    if scene.balancers.is_empty() {
        t
    } else {
        t + scene.balancer_torque(st.phi)
    }
}

/// The counterweight-independent parts of the shaking force (f₀, before the ω² factor) and
/// of the drive torque, with cos φ and sin φ, sampled on the scan grid and the RMS grid of
/// [`periodic_peak`] and [`periodic_rms`]. Evaluating many counterweights of one scene (the
/// design, the baselines, the `equal_ranges` root search, the Pareto points) then computes
/// the kinematics once per grid angle instead of once per angle, peak and counterweight;
/// the refinement of a peak between grid angles evaluates the mechanism directly. Values
/// are bit-identical to the direct evaluation: the same expressions on the same states,
/// only remembered.
struct Sampled {
    scan: Grid,
    /// The RMS grid when it differs from the scan grid.
    rms: Option<Grid>,
    /// Work space of [`metrics_sampled`] (3 columns of the scan grid).
    scratch: std::cell::RefCell<Vec<f64>>,
    /// The refined peak drive torque (value, angle, error) when it does not depend on the
    /// counterweight (no gravity), once computed.
    torque_peak: std::cell::OnceCell<(f64, f64, f64)>,
}

struct Grid {
    /// (cos φₖ, sin φₖ).
    cs: Vec<[f64; 2]>,
    /// f₀(φₖ) (kg·m).
    f0: Vec<P2>,
    /// ω²·T_drive0(φₖ) + T_load0(φₖ) (N·m); empty in a force-only grid.
    t0: Vec<f64>,
    /// Shaking moment per ω², M₀(φₖ) (kg·m²); empty in a force-only grid.
    m0: Vec<f64>,
}

/// What a [`Grid`] remembers besides the force.
#[derive(Clone, Copy, PartialEq)]
enum Columns {
    /// Only f₀ (the minimax of the force needs nothing else).
    Force,
    /// f₀, the torque and the moment (the figures of a design).
    All,
}

impl Grid {
    fn new(scene: &Scene, n: usize, columns: Columns) -> Grid {
        let m = &scene.mech;
        let h = std::f64::consts::TAU / n as f64;
        let all = columns == Columns::All;
        let cap = if all { n } else { 0 };
        let mut g = Grid {
            cs: Vec::with_capacity(n),
            f0: Vec::with_capacity(n),
            t0: Vec::with_capacity(cap),
            m0: Vec::with_capacity(cap),
        };
        for k in 0..n {
            let phi = k as f64 * h;
            if all {
                let st = m.state(phi).expect("assembly checked");
                g.cs.push(st.cs);
                g.f0.push(force0(scene, &st));
                g.t0.push(torque0(scene, &st));
                g.m0.push(moment0(scene, &st));
            } else {
                let (cs, f0) = force0_at(scene, phi);
                g.cs.push(cs);
                g.f0.push(f0);
            }
        }
        g
    }
    fn len(&self) -> usize {
        self.cs.len()
    }
    /// F(φₖ; u) (N), as [`shaking_force`].
    fn force(&self, k: usize, u: P2, w2: f64) -> P2 {
        (self.f0[k] + rot_cs(self.cs[k], u)) * w2
    }
    /// T(φₖ; u) (N·m), as [`drive_torque`].
    fn torque(&self, k: usize, gravity: P2, u: P2) -> f64 {
        self.t0[k] + weight_torque_cs(self.cs[k], gravity, u)
    }
}

impl Sampled {
    fn rms(&self) -> &Grid {
        self.rms.as_ref().unwrap_or(&self.scan)
    }

    fn new(scene: &Scene) -> Sampled {
        let s = &scene.resolved_settings();
        Sampled {
            // The grids of periodic_peak (n ≥ 8) and periodic_rms (even n ≥ 8).
            scan: Grid::new(scene, s.scan_samples.max(8), Columns::All),
            // Only the force's RMS is taken on it.
            rms: Some((s.rms_samples.max(8) + 1) & !1)
                .filter(|&n| n != s.scan_samples.max(8))
                .map(|n| Grid::new(scene, n, Columns::Force)),
            scratch: std::cell::RefCell::new(Vec::new()),
            torque_peak: std::cell::OnceCell::new(),
        }
    }
}

/// Refined figures of the counterweight `u` (kg·m).
pub fn metrics(scene: &Scene, u: P2) -> Result<Metrics, SolveError> {
    metrics_sampled(scene, u, &Sampled::new(scene))
}

/// The peak of a periodic function from its samples on the scan grid, refined by `f` to
/// `peak_xtol`, but not below 1e-8 rad (√ε: the value is then exact to round-off), and with
/// `minima` also the peak of −f (the negated minimum). `scale` is the size of the figure
/// the function is part of (e.g. the peak |F| for a component of F): a function whose
/// samples vary by less than 1e-12 of it is zero or constant up to round-off (F_y with the
/// y force zeroed, the torque of a balanced rotor), so its best sample is the peak, with
/// that variation as the error, and the round-off wiggles are not refined one by one.
fn grid_extremes(
    ys: &[f64],
    f: impl Fn(f64) -> f64,
    scale: f64,
    minima: bool,
    s: &cw::Settings,
) -> Result<(PeriodicPeak, Option<PeriodicPeak>), SolveError> {
    let num = |e: crate::numeric::SearchError| SolveError::Numeric(e.to_string());
    let shape = Shape::of(ys, minima, Refine::PeakOnly).map_err(num)?;
    let spread = shape.best - shape.worst;
    let peak = |sign: f64| -> Result<PeriodicPeak, SolveError> {
        if spread <= 1e-12 * scale {
            let target = if sign > 0.0 { shape.best } else { shape.worst };
            let k = ys.iter().position(|&y| y == target).unwrap_or(0);
            let best = Extremum {
                x: k as f64 * shape.h,
                fx: sign * target,
            };
            return Ok(PeriodicPeak {
                maxima: vec![best],
                peak: best,
                error: spread,
                evals: 0,
            });
        }
        shape.peak(ys, sign, &f, Some(value_xtol(s))).map_err(num)
    };
    Ok((peak(1.0)?, if minima { Some(peak(-1.0)?) } else { None }))
}

/// The angle tolerance of a refined figure: `peak_xtol`, but not below 1e-8 rad. A value
/// needs its maximum located only to √ε (≈ 1e-8 rad): closer, the values differ by
/// round-off (½|f''|δ² < ε|f|).
fn value_xtol(s: &cw::Settings) -> f64 {
    s.peak_xtol.max(1e-8)
}

/// The largest and smallest F_x(φₖ) = ω²(f₀ₓ(φₖ) − κ cos φₖ) of U = −κ e_x on the grid
/// `g`, each with its index, in one tight pass.
fn grid_x_extremes(g: &Grid, kappa: f64, w2: f64) -> ((f64, usize), (f64, usize)) {
    let (mut hi, mut lo) = ((f64::NEG_INFINITY, 0), (f64::INFINITY, 0));
    for (k, (f0, [c, _])) in g.f0.iter().zip(&g.cs).enumerate() {
        let x = w2 * (f0.x - kappa * c);
        if x > hi.0 {
            hi = (x, k);
        }
        if x < lo.0 {
            lo = (x, k);
        }
    }
    (hi, lo)
}

/// Bounds on the round-off of one evaluation of the shaking force (N), the drive torque
/// (N·m) and the shaking moment (N·m) of the counterweight `u`, at any crank angle: the
/// conditioning term of every stated error. Built from the kinematic bounds of
/// [`SliderCrank::round_off`] through the formulas of [`SliderCrank::shaking_force0`],
/// [`SliderCrank::drive_torque0`], [`SliderCrank::load_torque0`] and
/// [`SliderCrank::shaking_moment0`], each product's error as |a|δb + |b|δa + (rounding)·|ab|.
/// Tested against a double-double evaluation in `tests/certified.rs`.
pub fn round_off_bounds(scene: &Scene, u: P2) -> [f64; 3] {
    let eps = f64::EPSILON;
    let m = &scene.mech;
    let ro = m.round_off();
    let w2 = scene.omega * scene.omega;
    let mu = (m.rod.centroid / m.l).abs();
    let (m2, m3, m4) = (m.crank.mass, m.rod.mass, m.slider_mass);
    let r = m.r;
    let [x0, x1, x2] = ro.x;
    let [dx0, dx1, dx2] = ro.dx;
    let [p1, p2] = ro.psi;
    let [dp1, dp2] = ro.dpsi;
    let i_eff = m.rod.inertia.abs() + m.rod_inertia_excess().abs();
    let un = u.norm();
    let r2 = (m.crank.centroid).abs();
    // Shaking force: f₀ = −(m2 (r2/R) A'' + m3 G3'' + m4 x'' e_x), F = ω²(f₀ + Rot U).
    let (g1, g2) = (r + x1, r + x2);
    let f0 = m2 * r2 + m3 * g2 + m4 * x2;
    let force = w2 * ((m3 * mu + m4) * dx2 + 20.0 * eps * (f0 + un));
    // Drive torque: ω²(m3 G3'·G3'' + I ψ'ψ'' + m4 x'x'') − Σ m g·r' − F_p x' − g·Rot'U.
    let t_in = m3 * (g1 * mu * dx2 + g2 * mu * dx1 + 6.0 * eps * g1 * g2)
        + i_eff * (p1 * dp2 + p2 * dp1 + 6.0 * eps * p1 * p2)
        + m4 * (x1 * dx2 + x2 * dx1 + 6.0 * eps * x1 * x2);
    let t_in_size = m3 * g1 * g2 + i_eff * p1 * p2 + m4 * x1 * x2;
    let g = scene.loads.gravity.norm();
    let fp = scene.loads.process.max_abs();
    let t_load = g
        * (4.0 * eps * m2 * r2 + m3 * (mu * dx1 + 4.0 * eps * g1) + m4 * (dx1 + 4.0 * eps * x1))
        + fp * (dx1 + 4.0 * eps * x1);
    let t_load_size = g * (m2 * r2 + m3 * g1 + m4 * x1) + fp * x1;
    let torque = w2 * t_in
        + t_load
        + 6.0 * eps * g * un
        + 6.0 * eps * (w2 * t_in_size + t_load_size + g * un);
    // Shaking moment: −ω²(m3 G3 × G3'' + I ψ'' + m4 B × B'').
    let b0 = x0 + m.e.abs();
    let m_err = m3 * (b0 * (mu * dx2 + 4.0 * eps * g2) + g2 * (mu * dx0 + 4.0 * eps * b0))
        + i_eff * (dp2 + 2.0 * eps * p2)
        + m4 * (b0 * dx2 + x2 * dx0 + 4.0 * eps * b0 * x2)
        + 6.0 * eps * (m3 * b0 * g2 + i_eff * p2 + m4 * b0 * x2);
    // The balancers: a few roundings of n²|B_n| (cos nφ, sin nφ) each.
    let (mut bf, mut bm, mut bt) = (0.0, 0.0, 0.0);
    for b in &scene.balancers {
        let n = b.pair.order as f64;
        let mag = b.unbalance[0].abs() + b.unbalance[1].abs();
        bf += 8.0 * eps * n * n * mag;
        bm += 8.0 * eps * n * n * mag * b.pair.offset.abs();
        bt += 8.0 * eps * n * mag * g;
    }
    [
        force + w2 * bf,
        torque + bt,
        w2 * (m_err + bm) * (1.0 + 4.0 * eps),
    ]
}

/// A bound on the round-off of one evaluation of the joint loads (N) of
/// [`SliderCrank::joint_loads`] for the counterweight `u` of mass `cw_mass`: the kinematic
/// round-off of [`SliderCrank::round_off`] through the accelerations (each divided once by
/// k = L cos ψ ≥ k_min in F_43,y), and 64ε plus twice the relative round-off of k on the
/// size of every term.
pub fn joint_load_round_off(scene: &Scene, u: P2, cw_mass: f64) -> f64 {
    let eps = f64::EPSILON;
    let m = &scene.mech;
    let ro = m.round_off();
    let w2 = scene.omega * scene.omega;
    let a = m.r + m.e.abs();
    let kmin = ((m.l - a) * (m.l + a)).sqrt();
    let lever = 1.0 + (m.l + a) / kmin;
    let (m2, m3, m4) = (m.crank.mass, m.rod.mass, m.slider_mass);
    let i3 = m.rod.inertia.abs();
    let g = scene.loads.gravity.norm();
    let acc_err = w2 * ((m3 + m4) * ro.dx[2] * lever + i3 * ro.dpsi[1] / kmin);
    let size = (w2 * (m2 * m.crank.centroid.abs() + u.norm() + (m3 + m4) * (m.r + ro.x[2]))
        + w2 * i3 * ro.psi[1] / kmin
        + g * (m2 + m3 + m4 + cw_mass)
        + scene.loads.process.max_abs())
        * lever;
    acc_err + (64.0 * eps + 2.0 * ro.rho_k) * size
}

fn metrics_sampled(scene: &Scene, u: P2, tab: &Sampled) -> Result<Metrics, SolveError> {
    let (omega, s) = (scene.omega, &scene.settings);
    let w2 = omega * omega;
    let g = scene.loads.gravity;
    let f = |phi: f64| scene_force(scene, u, phi);
    // The sampled figures in one pass: F_x, |F| and |T| on the scan grid.
    let n = tab.scan.len();
    // The three columns in one buffer kept by the table (no allocation per counterweight);
    // every element is written before it is read.
    let mut cols = tab.scratch.borrow_mut();
    cols.resize(3 * n, 0.0);
    let (fx, rest) = cols.split_at_mut(n);
    let (norms, ts) = rest.split_at_mut(n);
    for k in 0..n {
        let v = tab.scan.force(k, u, w2);
        fx[k] = v.x;
        norms[k] = (v.x * v.x + v.y * v.y).sqrt();
        ts[k] = tab.scan.torque(k, g, u).abs();
    }
    let scale = norms.iter().fold(0.0, |a: f64, &b| a.max(b));
    let (pk, _) = grid_extremes(norms, |p| f(p).norm(), scale, false, s)?;
    let (xmax, xmin) = grid_extremes(fx, |p| f(p).x, scale, true, s)?;
    let xmin = xmin.expect("asked");
    // F_y is one harmonic: max F_y = −min F_y in closed form, exact (no sampling error).
    let y_amp = w2 * scene.mech.force_y_amplitude(u);
    // Without gravity the drive torque does not depend on the counterweight (its weight is
    // its only path into the torque): every counterweight of the table has the same peak,
    // computed once (the same numbers bit for bit: the weight term adds ±0).
    let torque_peak = || -> Result<(f64, f64, f64), SolveError> {
        let tscale = ts.iter().fold(0.0, |a: f64, &b| a.max(b));
        let (tq, _) = grid_extremes(ts, |p| drive_torque(scene, u, p).abs(), tscale, false, s)?;
        Ok((tq.peak.fx, tq.peak.x, tq.error))
    };
    let fixed = torque_independent_of_counterweight(scene);
    let (tq_peak, tq_angle, tq_error) = match tab.torque_peak.get().filter(|_| fixed) {
        Some(t) => *t,
        None => {
            let t = torque_peak()?;
            if fixed {
                let _ = tab.torque_peak.set(t);
            }
            t
        }
    };
    let rms = if tab.rms.is_none() {
        periodic_rms_sampled(norms)
    } else {
        periodic_rms_sampled(
            &(0..tab.rms().len())
                .map(|k| tab.rms().force(k, u, w2).norm())
                .collect::<Vec<f64>>(),
        )
    };
    // Round-off of each evaluation (conditioning), on top of sampling and refinement.
    let [ro_f, ro_t, _] = round_off_bounds(scene, u);
    Ok(Metrics {
        unbalance: [u.x, u.y],
        peak: pk.peak.fx,
        peak_angle: pk.peak.x,
        peak_error: pk.error + ro_f,
        rms: rms.rms,
        rms_error: rms.error + ro_f,
        ptp_x: xmax.peak.fx + xmin.peak.fx,
        ptp_y: 2.0 * y_amp,
        peak_x: xmax.peak.fx.max(xmin.peak.fx),
        peak_y: y_amp,
        peak_torque: tq_peak,
        peak_torque_angle: tq_angle,
        peak_torque_error: tq_error + ro_t,
    })
}

/// max F_x − min F_x (N) of the counterweight U = −κ e_x, from the remembered kinematics
/// (the part of [`metrics`] the `equal_ranges` root search needs), with cos φ at the maximum
/// and at the minimum (the envelope theorem gives the range's derivative in κ from them).
/// `refined`: the extremes refined as in [`metrics`]; else those of the scan grid, found by
/// one tight pass over F_x(φₖ) = ω²(f₀ₓ(φₖ) − κ cos φₖ).
fn x_range_sampled(
    scene: &Scene,
    kappa: f64,
    tab: &Sampled,
    refined: bool,
) -> Result<(f64, f64, f64), SolveError> {
    let (omega, s) = (scene.omega, &scene.settings);
    let w2 = omega * omega;
    let g = &tab.scan;
    if !refined {
        let (hi, lo) = grid_x_extremes(g, kappa, w2);
        if !(hi.0 - lo.0).is_finite() {
            return Err(SolveError::Numeric(
                "F_x is not finite on the scan grid".into(),
            ));
        }
        return Ok((hi.0 - lo.0, g.cs[hi.1][0], g.cs[lo.1][0]));
    }
    let u = P2::new(-kappa, 0.0);
    let f = |phi: f64| scene_force(scene, u, phi).x;
    let xs: Vec<f64> = (0..g.len()).map(|k| g.force(k, u, w2).x).collect();
    let scale = xs.iter().fold(0.0, |a: f64, &b| a.max(b.abs()));
    let (xmax, xmin) = grid_extremes(&xs, f, scale, true, s)?;
    let xmin = xmin.expect("asked");
    Ok((
        xmax.peak.fx + xmin.peak.fx,
        xmax.peak.x.cos(),
        xmin.peak.x.cos(),
    ))
}

/// The classical counterweights, opposite the crank pin (β = π), as unbalances (kg·m).
///
/// * `none`: U = 0;
/// * `y_force_zeroed`: U = −m_tq R e_x, which cancels F_y exactly (every link's y motion
///   is proportional to sin φ);
/// * `fifty_percent`: U = −(m_tq + ½ m_ct) R e_x;
/// * `equal_ranges`: U = −κ e_x with κ ∈ [m_tq R, (m_tq + m_ct) R] such that the
///   peak-to-peak ranges of F_x and F_y are equal (Brent on κ).
pub fn baselines(scene: &Scene) -> Result<BTreeMap<String, Metrics>, SolveError> {
    check(scene)?;
    baselines_sampled(scene, &Sampled::new(scene))
}

fn baselines_sampled(
    scene: &Scene,
    tab: &Sampled,
) -> Result<BTreeMap<String, Metrics>, SolveError> {
    let mech = &scene.mech;
    let (mt, mc, r) = (mech.m_rot(), mech.m_rec(), mech.r);
    let mut out = BTreeMap::new();
    for (name, k) in [
        ("none", 0.0),
        ("y_force_zeroed", mt * r),
        ("fifty_percent", (mt + 0.5 * mc) * r),
    ] {
        out.insert(
            name.to_string(),
            metrics_sampled(scene, P2::new(-k, 0.0), tab)?,
        );
    }
    // For U = −κ e_x every link's y motion is proportional to sin φ, so F_y = ω²(m_tq R − κ)
    // sin φ and its range is 2ω²|m_tq R − κ| in closed form; only the x range needs peaks.
    // F_x = ω²(f₀ₓ(φ) − κ cos φ), so by the envelope theorem d(range)/dκ = ω²(cos φ₋ − cos φ₊)
    // (φ₊, φ₋ the angles of the max and the min), and D(κ) = range − 2ω²(κ − m_tq R) is
    // found by safeguarded Newton on [m_tq R, (m_tq + m_ct) R].
    // The root of the sampled D (extremes of the scan grid, piecewise linear in κ, cheap)
    // is within O(h²) of the refined one; a few Newton steps on the refined D from there
    // finish it (the full safeguarded search again if they do not converge).
    let w2 = scene.omega * scene.omega;
    let diff = |refined: bool| {
        move |k: f64| {
            x_range_sampled(scene, k, tab, refined)
                .map(|(x, cp, cm)| (x - 2.0 * w2 * (k - mt * r), w2 * (cm - cp) - 2.0 * w2))
                .unwrap_or((f64::NAN, f64::NAN))
        }
    };
    let (lo, hi) = (mt * r, (mt + mc) * r);
    let tol = 1e-12 * hi.max(1e-300);
    // The polish first refines only the grid extremes of the sampled root (no scan for
    // other candidates: ~12 evaluations a step instead of a scan and ~12); the root's
    // figures below are computed with the full scan, and if their range is not the one the
    // polish converged on (another extreme took over), the polish runs again with the full
    // scan at every step.
    let near = |k: (usize, usize)| {
        move |kappa: f64| {
            x_range_near(scene, kappa, tab, k)
                .map(|(x, cp, cm)| (x - 2.0 * w2 * (kappa - mt * r), w2 * (cm - cp) - 2.0 * w2))
                .unwrap_or((f64::NAN, f64::NAN))
        }
    };
    let full = |x0: f64| {
        newton_polish(diff(true), x0, lo, hi, tol, 6)
            .map_or_else(|| newton_root(diff(true), lo, hi, tol), Ok)
    };
    let root = newton_root(diff(false), lo, hi, 1e-6 * hi).and_then(|sampled| {
        let ((_, k_hi), (_, k_lo)) = grid_x_extremes(&tab.scan, sampled.x, w2);
        let k = (k_hi, k_lo);
        match newton_polish(near(k), sampled.x, lo, hi, tol, 6) {
            Some(r) => Ok((r, Some(k))),
            None => full(sampled.x).map(|r| (r, None)),
        }
    });
    if let Ok((mut root, k)) = root {
        let mut m = metrics_sampled(scene, P2::new(-root.x, 0.0), tab)?;
        let local = k
            .and_then(|k| x_range_near(scene, root.x, tab, k))
            .map(|(x, _, _)| x);
        if k.is_some() && local != Some(m.ptp_x) {
            if let Ok(r) = full(root.x) {
                root = r;
                m = metrics_sampled(scene, P2::new(-root.x, 0.0), tab)?;
            }
        }
        out.insert("equal_ranges".to_string(), m);
    }
    Ok(out)
}

/// max F_x − min F_x (N) of U = −κ e_x, with cos φ at the maximum and at the minimum (as
/// [`x_range_sampled`]), refined only from the scan grid's samples `k` = (index of the
/// maximum, index of the minimum) as [`grid_extremes`] refines a candidate (the same
/// numbers when they are the global extremes). `None` when either sample is no longer a
/// sampled extreme at this κ.
fn x_range_near(
    scene: &Scene,
    kappa: f64,
    tab: &Sampled,
    (k_hi, k_lo): (usize, usize),
) -> Option<(f64, f64, f64)> {
    let w2 = scene.omega * scene.omega;
    let u = P2::new(-kappa, 0.0);
    let g = &tab.scan;
    let n = g.len();
    let h = std::f64::consts::TAU / n as f64;
    let xtol = value_xtol(&scene.settings);
    let f = |phi: f64| scene_force(scene, u, phi).x;
    let refine = |k: usize, sign: f64| {
        let around = [(k + n - 1) % n, k, (k + 1) % n].map(|j| sign * g.force(j, u, w2).x);
        refine_periodic_sample(|p| sign * f(p), k as f64 * h, h, around, xtol).ok()
    };
    let ((hi, _), (lo, _)) = (refine(k_hi, 1.0)?, refine(k_lo, -1.0)?);
    Some((hi.fx + lo.fx, hi.x.cos(), lo.x.cos()))
}

/// Resolved bounds on |U|: the unbalance range, m_min r_min ≤ |U| ≤ m_max r_max, and the
/// plate envelope's U_max.
pub fn unbalance_bounds(cw: &CounterweightSpec) -> (f64, f64) {
    let (mut lo, mut hi) = cw.unbalance.bounds();
    if let (Some(m), Some(r)) = (cw.mass, cw.radius) {
        let (m0, m1) = m.bounds();
        let (r0, r1) = r.bounds();
        lo = lo.max(m0 * r0);
        hi = hi.min(m1 * r1);
    }
    if let Some(sh) = &cw.shape {
        hi = hi.min(sh.max_unbalance());
    }
    (lo.max(0.0), hi)
}

/// The counterweight that realises |U|: its mass and centroid radius, and the plate when the
/// scene gives one (then mass and radius are the plate's, so they cannot disagree).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Realised {
    /// m_cw (kg).
    pub mass: Option<f64>,
    /// r_cw (m): the centroid radius.
    pub radius: Option<f64>,
    /// The plate (with `[design.shape]`).
    pub plate: Option<Sector>,
    /// How the plate was found, or why the envelope cannot hold it.
    pub plate_note: Option<String>,
}

/// The counterweight realising |U| = `u` under `objective`: with a plate, the plate the
/// objective asks for (the lightest for `MinMass`, the smallest outer radius for
/// `MinRadius`, else `[design.shape] minimize`); otherwise |U| split into mass and radius.
pub fn realise(u: f64, cw: &CounterweightSpec, objective: Objective) -> Realised {
    if let Some(sh) = &cw.shape {
        let goal = match objective {
            Objective::MinMass => ShapeGoal::Mass,
            Objective::MinRadius => ShapeGoal::OuterRadius,
            _ => sh.goal,
        };
        return match shape::design(&ShapeSpec { goal, ..*sh }, u) {
            ShapeOutcome::Found { sector, method } => Realised {
                mass: Some(sector.mass_kg),
                radius: Some(sector.centroid_radius_m),
                plate: Some(sector),
                plate_note: Some(method),
            },
            ShapeOutcome::Infeasible { reason } => Realised {
                mass: None,
                radius: None,
                plate: None,
                plate_note: Some(reason),
            },
        };
    }
    let prefer = match objective {
        Objective::MinMass => Prefer::Lightest,
        Objective::MinRadius => Prefer::SmallestRadius,
        _ => cw.prefer,
    };
    let (mass, radius) = split_unbalance(u, &CounterweightSpec { prefer, ..*cw });
    Realised {
        mass,
        radius,
        plate: None,
        plate_note: None,
    }
}

/// Splits |U| into (mass, radius) by the scene's variables and preference.
pub fn split_unbalance(u: f64, cw: &CounterweightSpec) -> (Option<f64>, Option<f64>) {
    match (cw.mass, cw.radius) {
        (_, Some(Var::Fixed(r))) => (Some(if r > 0.0 { u / r } else { 0.0 }), Some(r)),
        (Some(Var::Fixed(m)), _) => (Some(m), Some(if m > 0.0 { u / m } else { 0.0 })),
        (Some(m), Some(r)) => {
            let (m0, m1) = m.bounds();
            let (r0, r1) = r.bounds();
            let r = match cw.prefer {
                Prefer::SmallestRadius => r0.max(if m1 > 0.0 { u / m1 } else { r0 }),
                Prefer::Lightest => r1.min(if m0 > 0.0 { u / m0 } else { r1 }),
            };
            (Some(if r > 0.0 { u / r } else { m0 }), Some(r))
        }
        _ => (None, None),
    }
}

/// The optimal counterweight of a scene, before its evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct Optimum {
    /// Solver status.
    pub status: Status,
    /// Unbalance U in the crank frame (kg·m).
    pub u: P2,
    /// Optimality gap of the objective (N), see [`Outcome::gap`].
    pub gap: f64,
    /// Solver description.
    pub method: String,
    /// clarabel solves of the exchange loop (0 when no convex solve was needed).
    pub rounds: usize,
    /// Warnings.
    pub warnings: Vec<String>,
    /// The balancers' unbalances B_n = (B_c, B_s) (kg·m), in the scene's order.
    pub balancers: Vec<[f64; 2]>,
}

/// Finds the counterweight: the convex solve and its exchange refinement (the part the
/// benchmark times), without the report figures and baselines.
pub fn optimise(scene: &Scene) -> Result<Optimum, SolveError> {
    check(scene)?;
    optimise_with(
        scene,
        scene.objective,
        scene.max_peak_force,
        scene.max_peak_torque,
        &Grid::new(
            scene,
            scene.resolved_settings().scan_samples,
            if needs_torque(scene.objective, scene.max_peak_torque) {
                Columns::All
            } else {
                Columns::Force
            },
        ),
    )
}

fn check(scene: &Scene) -> Result<(), SolveError> {
    let mech = &scene.mech;
    if mech.assembly_ratio() >= 1.0 {
        return Err(SolveError::CannotAssemble(mech.assembly_ratio()));
    }
    if !((mech.m_rot() + mech.m_rec()) * mech.r > 0.0) {
        return Err(SolveError::NoMass);
    }
    Ok(())
}

/// Whether the minimax of `objective` under these limits has the drive torque as a field
/// (its objective or a limit), so needs the torque on the scan grid.
fn needs_torque(objective: Objective, max_torque: Option<f64>) -> bool {
    objective == Objective::MinPeakTorque || max_torque.is_some()
}

/// [`optimise`] with the objective and limits given explicitly (the Pareto front solves the
/// scene again with other ones).
fn optimise_with(
    scene: &Scene,
    objective: Objective,
    max_force: Option<f64>,
    max_torque: Option<f64>,
    grid: &Grid,
) -> Result<Optimum, SolveError> {
    if scene.joint() {
        return optimise_joint(scene, objective, max_force, max_torque);
    }
    // The caller has run `check` (the grid needed it).
    let s = &scene.resolved_settings();
    let nf = Normalised::new(scene);
    // The fields on the scan grid (the scans of the exchange loop and the presolve).
    let force_grid: Vec<Affine> = (0..grid.len())
        .map(|k| nf.force_of(grid.cs[k], grid.f0[k]))
        .collect();
    // The torque on the grid only where a field needs it (the callers pass a grid with the
    // torque column then: `Columns::All`).
    let torque_grid: Vec<Affine> = if needs_torque(objective, max_torque) {
        debug_assert_eq!(grid.t0.len(), grid.len(), "the torque needs Columns::All");
        (0..grid.len())
            .map(|k| nf.torque_of(grid.cs[k], grid.t0[k]))
            .collect()
    } else {
        Vec::new()
    };
    let u_ref = nf.u_ref;
    let f_ref = scene.omega * scene.omega * u_ref; // N per normalised unit
    let force = |phi: f64| nf.force(phi);
    let torque = |phi: f64| nf.torque(phi);
    let (u_lo, u_hi) = unbalance_bounds(&scene.counterweight);
    let mut warnings = Vec::new();

    let cwspec = &scene.counterweight;
    let (beta_lo, beta_hi) = cwspec.angle.bounds();
    let full_circle = beta_hi - beta_lo >= std::f64::consts::TAU - 1e-9;
    let fixed_len = u_hi.is_finite() && (u_hi - u_lo) <= 1e-15 * u_hi.max(1e-300);

    let mut limits = Vec::new();
    if let Some(f) = max_force {
        limits.push((0, f / f_ref));
    }
    if let Some(t) = max_torque {
        limits.push((1, t / nf.t_ref));
    }
    let (goal, obj_ref) = match objective {
        Objective::MinPeakForce => (Goal::MinPeak(0), f_ref),
        Objective::MinRmsForce => (Goal::MinMeanSquare(0), f_ref),
        Objective::MinMass | Objective::MinRadius => (Goal::MinNorm, f_ref),
        Objective::MinPeakTorque => (Goal::MinPeak(1), nf.t_ref),
        // Never here: a moment objective is a joint scene (`optimise_joint`).
        Objective::MinPeakMoment => (Goal::MinPeak(0), f_ref),
    };

    let mut method;
    let mut rounds = 0;
    let (status, u, gap);
    if let (Some(beta), true) = (cwspec.angle.fixed(), fixed_len) {
        // Everything fixed: an analysis.
        status = Status::Optimal;
        u = P2::new(beta.cos(), beta.sin()) * u_lo;
        gap = 0.0;
        method = "analysis of the given counterweight (no free design variable)".to_string();
    } else if fixed_len && full_circle {
        // |U| fixed, direction free: a circle, not convex — 1-D search over β.
        let r = search_on_circle(&nf, objective, u_lo / u_ref)?;
        status = r.0;
        u = r.1 * u_ref;
        gap = 0.0;
        method = r.2;
    } else {
        let direction = if let Some(beta) = cwspec.angle.fixed() {
            Direction::Fixed {
                beta,
                min_len: u_lo / u_ref,
            }
        } else if full_circle {
            Direction::Free
        } else {
            Direction::Sector {
                lo: beta_lo,
                hi: beta_hi,
            }
        };
        let mut fields = vec![Field {
            name: "shaking force",
            dim: 2,
            eval: &force,
            grid: Some(&force_grid),
        }];
        if needs_torque(objective, max_torque) {
            fields.push(Field {
                name: "drive torque",
                dim: 1,
                eval: &torque,
                grid: Some(&torque_grid),
            });
        }
        let warm_angles = if s.warm_start && goal != Goal::MinNorm {
            warm_start(&nf, s)
        } else {
            Vec::new()
        };
        let pb = Problem {
            fields,
            goal,
            limits,
            u_max: u_hi / u_ref,
            direction,
            warm_angles,
        };
        let sol = cw::solve(&pb, s);
        let presolve = if sol.presolved {
            "geometric presolve (smallest disc enclosing the force-cancelling unbalances) + "
        } else {
            ""
        };
        method = if sol.disc {
            format!(
                "{presolve}exact sampled minimax (smallest enclosing disc, Welzl; the SOCP's optimum without clarabel) + exchange loop: {} rounds, {} angles",
                sol.rounds, sol.samples
            )
        } else {
            format!(
                "{presolve}clarabel {} + exchange loop: {} rounds, {} angles, {} interior-point iterations, last status {}",
                match goal {
                    Goal::MinPeak(0) => "SOCP (minimax force)",
                    Goal::MinPeak(_) => "SOCP/LP (minimax torque)",
                    Goal::MinMeanSquare(_) => "QP (mean square)",
                    Goal::MinNorm => "SOCP (least |U|)",
                },
                sol.rounds,
                sol.samples,
                sol.ipm_iterations,
                sol.solver_status
            )
        };
        if let Some(n) = &sol.note {
            warnings.push(n.clone());
        }
        rounds = if sol.disc { 0 } else { sol.rounds };
        let mut st = sol.status;
        let mut uu = sol.u * u_ref;
        let mut g = sol.gap * obj_ref;
        if st != Status::Infeasible
            && st != Status::Failed
            && matches!(direction, Direction::Free | Direction::Sector { .. })
            && uu.norm() < u_lo * (1.0 - 1e-9)
        {
            // The lower bound on |U| is active and not convex: search its circle.
            let r = search_on_circle(&nf, objective, u_lo / u_ref)?;
            st = r.0;
            uu = r.1 * u_ref;
            g = 0.0;
            method = format!("{method}; |U| ≥ {u_lo:.6e} kg·m active: {}", r.2);
        }
        status = st;
        u = uu;
        gap = g;
    }
    if status == Status::Infeasible {
        warnings.push(format!(
            "infeasible: no counterweight within the bounds meets the limits (peak force ≤ {:?} N, peak torque ≤ {:?} N·m)",
            max_force, max_torque
        ));
    }
    Ok(Optimum {
        status,
        u,
        gap,
        method,
        rounds,
        warnings,
        balancers: Vec::new(),
    })
}

/// Angles of the local maxima of |F| for the least-squares counterweight
/// û = −mean Rot(φ)ᵀ f̂₀(φ) (the RMS optimum of a free direction, in closed form): close to
/// the minimax optimum's active angles, so the first SOCP starts near them.
fn warm_start(nf: &Normalised, s: &cw::Settings) -> Vec<f64> {
    let n = 64;
    let mut u = P2::zeros();
    for k in 0..n {
        let phi = k as f64 * std::f64::consts::TAU / n as f64;
        let a = nf.force(phi);
        u -= rot(-phi, P2::new(a.b[0], a.b[1])) / n as f64;
    }
    periodic_peak(|p| nf.force(p).at(u).norm(), 90, s.peak_xtol.max(1e-6))
        .map(|p| p.maxima.iter().map(|m| m.x).collect())
        .unwrap_or_default()
}

/// The torque–force Pareto front by the ε-constraint method: the force optimum F* and the
/// torque optimum (whose peak force is F_T) bound the front; for `n` limits ε spaced evenly
/// in [F*, F_T], minimise the peak torque subject to peak force ≤ ε.
pub fn pareto(scene: &Scene, n: usize) -> Result<Vec<ParetoPoint>, SolveError> {
    check(scene)?;
    pareto_sampled(scene, n, &Sampled::new(scene))
}

fn pareto_sampled(scene: &Scene, n: usize, tab: &Sampled) -> Result<Vec<ParetoPoint>, SolveError> {
    let g = &tab.scan;
    let f_opt = optimise_with(
        scene,
        Objective::MinPeakForce,
        None,
        scene.max_peak_torque,
        g,
    )?;
    let t_opt = optimise_with(
        scene,
        Objective::MinPeakTorque,
        scene.max_peak_force,
        None,
        g,
    )?;
    let fmin = metrics_sampled(scene, f_opt.u, tab)?.peak;
    let fmax = metrics_sampled(scene, t_opt.u, tab)?.peak;
    let n = n.max(2);
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        // Slightly above F* so that the first point is feasible despite the gap.
        let eps = if k == 0 {
            fmin * (1.0 + 10.0 * scene.settings.rel_tol)
        } else {
            fmin + (fmax - fmin) * k as f64 / (n - 1) as f64
        };
        let o = optimise_with(scene, Objective::MinPeakTorque, Some(eps), None, g)?;
        let m = metrics_sampled(scene, o.u, tab)?;
        out.push(ParetoPoint {
            force_limit_n: eps,
            peak_shaking_force_n: m.peak,
            peak_drive_torque_nm: m.peak_torque,
            gap_nm: o.gap,
            unbalance_x_kgm: o.u.x,
            unbalance_y_kgm: o.u.y,
            status: o.status,
        });
    }
    Ok(out)
}

/// Solves the scene: [`optimise`], then the design's figures and the baselines.
///
/// Degenerate objectives are flagged, not solved: without gravity the drive torque of a
/// constant-speed crank does not depend on its counterweight (the counterweight's inertia
/// adds no torque, [`crate::families::slider_crank::model::SliderCrank::drive_torque0`]), so "minimise
/// the peak torque" leaves U arbitrary. The design is then the minimax-force counterweight
/// under the same limits, and [`Outcome::degenerate`] says why.
pub fn solve(scene: &Scene) -> Result<Outcome, SolveError> {
    check(scene)?;
    let tab = Sampled::new(scene);
    let torque_fixed = torque_independent_of_counterweight(scene);
    let mut degenerate = (torque_fixed && scene.objective == Objective::MinPeakTorque).then(|| {
        "the objective, the peak drive torque, does not depend on the counterweight: without \
         gravity a counterweight turning at constant speed adds no torque, so every \
         counterweight is equally 'optimal'; the design shown minimises the peak shaking force \
         instead (set model.gravity for a vertical machine, or minimise the shaking force)"
            .to_string()
    });
    if scene.objective == Objective::MinPeakMoment
        && scene.balancers.iter().all(|b| b.pair.offset == 0.0)
    {
        degenerate = Some(
            "the objective, the peak shaking moment, does not depend on the design: a crank \
             counterweight turning at constant speed adds no moment about the crank axis, and \
             balancer pairs on the line through it (offset 0) add none either; the design shown \
             minimises the peak shaking force instead (give the balancers their offsets)"
                .to_string(),
        );
    }
    let objective = if degenerate.is_some() {
        Objective::MinPeakForce
    } else {
        scene.objective
    };
    let Optimum {
        mut status,
        u,
        gap,
        method,
        mut warnings,
        balancers,
        ..
    } = optimise_with(
        scene,
        objective,
        scene.max_peak_force,
        scene.max_peak_torque,
        &tab.scan,
    )?;
    // The design's figures on the scene with its balancers (the scene itself without any);
    // the baselines on the scene as read (no balancers).
    let designed = scene.with_balancers(&balancers);
    let designed_tab = (!scene.balancers.is_empty()).then(|| Sampled::new(&designed));
    let (baseline_scene, scene) = (scene, &designed);
    let (baseline_tab, tab) = (&tab, designed_tab.as_ref().unwrap_or(&tab));
    let mech = &scene.mech;
    let s = &scene.settings;
    let w2 = scene.omega * scene.omega;
    let nf = Normalised::new(scene);
    let cwspec = &scene.counterweight;

    let design = metrics_sampled(scene, u, tab)?;
    let counterweight = realise(
        P2::new(design.unbalance[0], design.unbalance[1]).norm(),
        cwspec,
        scene.objective,
    );
    // The moment is zero for an in-line slider with a lumped rod: its scale is the force's
    // moment arm, the peak force times (R + L).
    let (mm, _) = grid_extremes(
        &tab.scan
            .m0
            .iter()
            .map(|m| (m * w2).abs())
            .collect::<Vec<f64>>(),
        |p| moment0(scene, &nf.state(p)).abs() * w2,
        design.peak * (mech.r + mech.l),
        false,
        s,
    )?;
    let exact_peak = if mech.kinematics == Kinematics::TwoHarmonic {
        let exact = Scene {
            mech: SliderCrank {
                kinematics: Kinematics::Exact,
                ..*mech
            },
            ..scene.clone()
        };
        let m = metrics(&exact, u)?;
        warnings.push(format!(
            "two-harmonic kinematics: the design's peak force with exact kinematics is {:.6} N ({:+.3e} N, {:+.3} %)",
            m.peak,
            m.peak - design.peak,
            100.0 * (m.peak - design.peak) / design.peak
        ));
        Some(m.peak)
    } else {
        None
    };
    // Model only what the scene needs: say when gravity is left out but matters, or is in
    // but does not.
    let g_ratio = 9.81 / (mech.r * w2);
    let g = scene.loads.gravity.norm();
    if g == 0.0 && g_ratio > 0.01 {
        warnings.push(format!(
            "gravity is not modelled but g/(Rω²) = {g_ratio:.3}: weights change the drive torque by up to about {:.0} % of its inertial part; set model.gravity for a vertical machine",
            100.0 * g_ratio
        ));
    } else if g > 0.0 && g / (mech.r * w2) < 1e-3 {
        warnings.push(format!(
            "gravity is modelled but g/(Rω²) = {:.2e}: its effect on the torque is below 0.1 %; it could be left out",
            g / (mech.r * w2)
        ));
    }
    let pareto = if scene.pareto_points > 0 && torque_fixed {
        warnings.push(
            "no torque–force Pareto front: without gravity the drive torque does not depend on \
             the counterweight, so the two objectives do not trade off"
                .into(),
        );
        Vec::new()
    } else if scene.pareto_points > 0 {
        let front = pareto_sampled(scene, scene.pareto_points, tab)?;
        // A front only where the two objectives trade off by more than their errors: ends
        // whose torques differ by no more than their gaps are one design, not a front.
        match (front.first(), front.last()) {
            (Some(a), Some(b))
                if a.peak_drive_torque_nm - b.peak_drive_torque_nm
                    <= a.gap_nm + b.gap_nm + 1e-12 * a.peak_drive_torque_nm.abs() =>
            {
                warnings.push(format!(
                    "no torque–force Pareto front: the torque optimum and the force optimum differ by {:.3e} N·m in peak torque, within their errors ({:.3e} N·m): the objectives do not trade off",
                    a.peak_drive_torque_nm - b.peak_drive_torque_nm,
                    a.gap_nm + b.gap_nm
                ));
                Vec::new()
            }
            _ => front,
        }
    } else {
        Vec::new()
    };
    let static_weight = mech.link_weight(&scene.loads) + g * counterweight.mass.unwrap_or(0.0);
    // Conditioning: say how many digits are left when round-off eats into them (near toggle).
    let round_off = round_off_bounds(scene, u);
    let rel = round_off[0] / design.peak.max(f64::MIN_POSITIVE);
    if rel > 1e-10 {
        warnings.push(format!(
            "ill-conditioned mechanism (assembly margin (L − R − |e|)/L = {:.2e}): round-off \
             alone can reach {:.1e} N in the shaking force, so about {:.0} significant digits \
             of the figures are reliable; the stated errors include it",
            (mech.l - mech.r - mech.e.abs()) / mech.l,
            round_off[0],
            (-rel.log10()).floor().max(0.0)
        ));
    }
    // The gap is the refined peak minus the solver's sampled lower bound: the bound was
    // computed in floating point too, so it carries the same round-off as one evaluation.
    let gap = if gap >= 0.0 {
        gap + match objective {
            Objective::MinPeakTorque => round_off[1],
            _ => round_off[0],
        }
    } else {
        gap
    };
    let joint_loads = if scene.bearing_loads || scene.load_limits != LoadLimits::default() {
        let cw_mass = counterweight.mass.unwrap_or(0.0);
        if g > 0.0 && counterweight.mass.is_none() && u.norm() > 0.0 {
            warnings.push(
                "the main bearing load leaves out the counterweight's weight: the scene does \
                 not size its mass (give design.radius or design.mass)"
                    .into(),
            );
        }
        let jl = joint_load_peaks(scene, u, cw_mass, tab)?;
        check_load_limits(scene, &jl, &mut status, &mut warnings);
        Some(jl)
    } else {
        None
    };
    Ok(Outcome {
        status,
        design,
        counterweight,
        gap,
        peak_shaking_moment: mm.peak.fx,
        peak_shaking_moment_error: mm.error + round_off[2],
        pareto,
        static_weight,
        baselines: baselines_sampled(baseline_scene, baseline_tab)?,
        exact_peak,
        method,
        warnings,
        degenerate,
        designed: scene.clone(),
        joint_loads,
    })
}

/// True when the drive torque cannot depend on the counterweight: its only path into the
/// torque is its weight, T_cw = −g·Rot'(φ)U, which is zero without gravity.
fn torque_independent_of_counterweight(scene: &Scene) -> bool {
    scene.loads.gravity.norm() == 0.0
}

/// Minimises the objective over U on the circle |U| = `len` (normalised): a 72-point scan in
/// β and Brent on the best bracket.
fn search_on_circle(
    nf: &Normalised,
    objective: Objective,
    len: f64,
) -> Result<(Status, P2, String), SolveError> {
    let scene = nf.scene;
    let s = &scene.resolved_settings();
    let obj = |beta: f64| -> f64 {
        let u = P2::new(beta.cos(), beta.sin()) * len;
        let mag = |p: f64| nf.force(p).at(u).norm();
        let tq = |p: f64| nf.torque(p).at(u).x.abs();
        let peak = |f: &dyn Fn(f64) -> f64| {
            periodic_peak(f, s.scan_samples, s.peak_xtol)
                .map(|p| p.peak.fx)
                .unwrap_or(f64::INFINITY)
        };
        match objective {
            Objective::MinRmsForce => periodic_rms(mag, s.rms_samples).rms,
            Objective::MinPeakTorque => peak(&tq),
            _ => peak(&mag),
        }
    };
    let (lo, hi) = scene.counterweight.angle.bounds();
    let full = hi - lo >= std::f64::consts::TAU - 1e-9;
    let n = 72;
    let h = (hi - lo) / if full { n as f64 } else { (n - 1) as f64 };
    let vals: Vec<f64> = (0..n).map(|k| obj(lo + k as f64 * h)).collect();
    let k = (0..n).min_by(|&a, &b| vals[a].total_cmp(&vals[b])).unwrap();
    let c = lo + k as f64 * h;
    let (a, b) = if full {
        (c - h, c + h)
    } else {
        ((c - h).max(lo), (c + h).min(hi))
    };
    let best = brent_max(|beta| -obj(beta), a, b, s.peak_xtol)
        .map_err(|e| SolveError::Numeric(e.to_string()))?;
    let u = P2::new(best.x.cos(), best.x.sin()) * len;
    Ok((
        Status::Optimal,
        u,
        "|U| fixed, 1-D search over β (72-point scan + Brent), objective not convex on the circle"
            .into(),
    ))
}

/// The paper's piston (`shared/domain/slider-crank.md`, Table 1): R = 35 mm, L = 140 mm,
/// m2 = 0.35 kg (uniform crank), m3 = 0.30 kg split half–half, m4 = 1.03 kg, at `rpm`, with
/// a free counterweight direction and size: the minimax scene of `problems/piston-*.toml`.
pub fn paper_piston(rpm: f64) -> Scene {
    use crate::families::slider_crank::model::{Crank, Rod};
    Scene {
        mech: SliderCrank {
            r: 0.035,
            l: 0.14,
            e: 0.0,
            kinematics: Kinematics::Exact,
            crank: Crank {
                mass: 0.35,
                centroid: 0.0175,
            },
            rod: Rod::lumped(0.30, 0.5, 0.14),
            slider_mass: 1.03,
        },
        omega: rpm * std::f64::consts::TAU / 60.0,
        counterweight: CounterweightSpec {
            unbalance: Var::Free {
                min: 0.0,
                max: f64::INFINITY,
            },
            angle: Var::Free {
                min: 0.0,
                max: std::f64::consts::TAU,
            },
            mass: None,
            radius: None,
            prefer: Prefer::SmallestRadius,
            shape: None,
        },
        objective: Objective::MinPeakForce,
        max_peak_force: None,
        max_peak_torque: None,
        loads: Loads::default(),
        pareto_points: 0,
        settings: cw::Settings::default(),
        balancers: Vec::new(),
        max_shaking_moment: None,
        load_limits: LoadLimits::default(),
        bearing_loads: false,
    }
}

/// A resolved speed sweep (rad/s).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SpeedSweep {
    /// Lowest ω.
    pub min: f64,
    /// Highest ω.
    pub max: f64,
    /// Number of speeds.
    pub points: usize,
}

/// One speed of a sweep: the optimum there, and the scene's design evaluated there.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SweepPoint {
    /// Speed (rad/s).
    pub omega_rad_s: f64,
    /// Speed (rpm), for reading.
    pub speed_rpm: f64,
    /// |U| of the optimum at this speed (kg·m).
    pub optimal_unbalance_kgm: f64,
    /// Objective value of that optimum (N or N·m).
    pub optimal_objective: f64,
    /// The same objective for the design found at the scene's own speed.
    pub design_objective: f64,
    /// The same objective without counterweight.
    pub none_objective: f64,
    /// Solver status at this speed.
    pub status: crate::report::Status,
}

/// Re-optimises the scene at each speed of the sweep and evaluates the design `u` (found at
/// the scene's own speed) and no counterweight there, in the scene's objective; a speed whose
/// solve fails is left out with a warning.
pub fn speed_sweep(s: &Scene, sw: &SpeedSweep, u: P2) -> (Vec<SweepPoint>, Vec<String>) {
    let value = |m: &Metrics| match s.objective {
        Objective::MinPeakTorque => m.peak_torque,
        Objective::MinRmsForce => m.rms,
        _ => m.peak,
    };
    let mut pts = Vec::with_capacity(sw.points);
    let mut warnings = Vec::new();
    for k in 0..sw.points {
        let omega = sw.min + (sw.max - sw.min) * k as f64 / (sw.points - 1) as f64;
        let at = Scene { omega, ..s.clone() };
        let point = optimise(&at).and_then(|o| {
            let opt = metrics(&at, o.u)?;
            let des = metrics(&at, u)?;
            let none = metrics(&at, P2::zeros())?;
            Ok(SweepPoint {
                omega_rad_s: omega,
                speed_rpm: omega * 60.0 / std::f64::consts::TAU,
                optimal_unbalance_kgm: o.u.norm(),
                optimal_objective: value(&opt),
                design_objective: value(&des),
                none_objective: value(&none),
                status: crate::families::family::cw_status(o.status),
            })
        });
        match point {
            Ok(p) => pts.push(p),
            Err(e) => warnings.push(format!("speed sweep at {omega:.3} rad/s: {e}")),
        }
    }
    (pts, warnings)
}

/// The peak joint loads of the design `u` (kg·m) of mass `cw_mass` over the cycle: sampled on
/// the scan grid, every local maximum refined as the peak force is.
fn joint_load_peaks(
    scene: &Scene,
    u: P2,
    cw_mass: f64,
    tab: &Sampled,
) -> Result<JointLoadPeaks, SolveError> {
    let (mech, omega, s) = (&scene.mech, scene.omega, &scene.settings);
    let at = |phi: f64| {
        let st = mech.state(phi).expect("assembly checked");
        mech.joint_loads(&st, omega, &scene.loads, u, cw_mass)
    };
    let n = tab.scan.len();
    let h = std::f64::consts::TAU / n as f64;
    let samples: Vec<_> = (0..n).map(|k| at(k as f64 * h)).collect();
    let ro = joint_load_round_off(scene, u, cw_mass);
    let peak = |pick: &dyn Fn(&crate::families::slider_crank::model::JointLoads) -> f64| {
        let ys: Vec<f64> = samples.iter().map(pick).collect();
        let scale = ys.iter().fold(0.0, |a: f64, &b| a.max(b));
        grid_extremes(&ys, |p| pick(&at(p)), scale, false, s).map(|(pk, _)| LoadPeak {
            peak: pk.peak.fx,
            angle: pk.peak.x,
            error: pk.error + ro,
        })
    };
    Ok(JointLoadPeaks {
        main_bearing: peak(&|j| j.main.norm())?,
        crank_pin: peak(&|j| j.crank_pin.norm())?,
        wrist_pin: peak(&|j| j.wrist_pin.norm())?,
        guide: peak(&|j| j.guide.abs())?,
    })
}

/// The joint-load limits against the design's peaks: a peak above its limit by more than its
/// error makes the result `infeasible` (the pin and guide loads do not depend on the design,
/// so no design meets such a limit); one within its error of the limit, `inaccurate`.
fn check_load_limits(
    scene: &Scene,
    jl: &JointLoadPeaks,
    status: &mut Status,
    warnings: &mut Vec<String>,
) {
    let ll = &scene.load_limits;
    for (name, key, lim, p) in [
        (
            "main bearing",
            "max_main_bearing_load",
            ll.main_bearing,
            jl.main_bearing,
        ),
        (
            "crank pin",
            "max_crank_pin_load",
            ll.crank_pin,
            jl.crank_pin,
        ),
        (
            "wrist pin",
            "max_wrist_pin_load",
            ll.wrist_pin,
            jl.wrist_pin,
        ),
        ("guide", "max_guide_load", ll.guide, jl.guide),
    ] {
        let Some(lim) = lim else { continue };
        // The main bearing's limit is a constraint of the design, met (to the engine's
        // tolerance) or declared infeasible by the engine; the others are only checked.
        let designed = name == "main bearing";
        let tol = if designed {
            scene.settings.rel_tol * lim
        } else {
            0.0
        };
        if p.peak - p.error > lim + tol {
            *status = Status::Infeasible;
            warnings.push(format!(
                "infeasible: objective.{key} = {lim} N cannot be met: the {name} load peaks at {:.6} N (± {:.1e} N) at φ = {:.3}°{}",
                p.peak,
                p.error,
                p.angle.to_degrees(),
                if name == "main bearing" {
                    ""
                } else {
                    " and does not depend on the counterweight or the balancers"
                }
            ));
        } else if !designed && p.peak + p.error > lim && *status == Status::Optimal {
            *status = Status::Inaccurate;
            warnings.push(format!(
                "objective.{key} = {lim} N: the {name} load peaks at {:.9} N ± {:.1e} N, within its error of the limit",
                p.peak, p.error
            ));
        }
    }
}

/// The joint design of the crank counterweight U and the balancers' unbalances B_n by the
/// certified affine minimax of [`crate::synth::minimax`]: every figure is affine in
/// x = (U; B_1; …), so the columns of the balancers are added to those of U and the same
/// cone program and exchange loop certify the joint optimum.
///
/// Variables: each unbalance is a 2-vector held as the first moment of one of the engine's
/// counterweights (m, u, I) with m_max = 1 and r_max = ρ = its bound, so |u| ≤ bound is the
/// engine's own cone (m and I enter no field). Fields (SI): 0 the shaking force (N),
/// 1 the shaking moment about O (N·m), 2 the drive torque (N·m), 3 the main bearing load
/// without the counterweight's weight (N).
///
/// Bounds: where the scene leaves |U| or |B_n| unbounded, the Fourier coefficients of the
/// force z = F_x + iF_y bound them at any design whose peak (or RMS) force is at most K:
/// z = z₀ + U e^{iφ} + Σ n²(B_n e^{inφ} + B̄_n e^{−inφ})/2, and |c_k(z)| ≤ max|z| (≤ RMS for
/// the RMS), so n²|B_n|/2 ≤ K + P₀ and |U| ≤ 2(K + P₀), P₀ the peak of z₀ (taken as 1.5 ×
/// its sampled maximum). K is the force limit, or P₀ for a force objective (reached by the
/// design 0). Where the other limits exclude the design 0 the optimum's force may exceed P₀,
/// so a design on an automatic bound is reported `inaccurate`; one inside them all is the
/// unbounded problem's optimum too (a convex problem: a local optimum is global).
fn optimise_joint(
    scene: &Scene,
    objective: Objective,
    max_force: Option<f64>,
    max_torque: Option<f64>,
) -> Result<Optimum, SolveError> {
    use crate::synth::minimax::{self as mm, AffineValue, CounterweightLimits, FnField};
    let mech = &scene.mech;
    let w2 = scene.omega * scene.omega;
    let g = scene.loads.gravity;
    let nb = scene.balancers.len();
    let st = |phi: f64| mech.state(phi).expect("assembly checked");
    let zero = scene.with_balancers(&vec![[0.0; 2]; nb]);
    let zero = &zero;
    // P₀, the peak of the force without design (sampled, with margin).
    let p0 = 1.5
        * (0..720)
            .map(|k| {
                let phi = k as f64 * std::f64::consts::TAU / 720.0;
                force0(zero, &st(phi)).norm() * w2
            })
            .fold(0.0, f64::max);
    let k_force = match (objective, max_force) {
        (Objective::MinPeakForce | Objective::MinRmsForce, Some(f)) => f.min(p0),
        (Objective::MinPeakForce | Objective::MinRmsForce, None) => p0,
        (_, Some(f)) => f,
        (_, None) => {
            return Err(SolveError::Numeric(
                "a joint design (balancers, moment or main-bearing limits) minimising the torque or the moment needs objective.max_peak_force: the counterweight is otherwise unbounded".into(),
            ))
        }
    };
    let auto = |n: f64| 2.0 * (k_force + p0) / (w2 * n * n);
    let (u_lo, u_hi) = unbalance_bounds(&scene.counterweight);
    let u_auto = 2.0 * auto(1.0);
    let u_max = u_hi.min(u_auto);
    let sector = match scene.counterweight.angle {
        Var::Fixed(b) => Some((b, b)),
        Var::Free { min, max } if max - min < std::f64::consts::TAU - 1e-9 => Some((min, max)),
        _ => None,
    };
    let limits_of = |bound: f64| CounterweightLimits {
        sector: None,
        ..CounterweightLimits::new(1.0, bound)
    };
    let mut cws = vec![CounterweightLimits {
        sector,
        ..limits_of(u_max)
    }];
    let b_max: Vec<f64> = scene
        .balancers
        .iter()
        .map(|b| b.max_unbalance.min(auto(b.pair.order as f64)))
        .collect();
    cws.extend(b_max.iter().map(|&b| limits_of(b)));
    let ub = |j: usize| mm::var_u(j);
    let fill_balancers = |out: &mut AffineValue, phi: f64, which: u8| {
        for (j, b) in scene.balancers.iter().enumerate() {
            let (c, scale) = match which {
                0 => (b.pair.force_coeffs(phi), w2),
                1 => (b.pair.moment_coeffs(phi), w2),
                _ => (b.pair.weight_torque_coeffs(phi, g), 1.0),
            };
            let row = out.row_mut(0);
            row[ub(j + 1)] = c[0] * scale;
            row[ub(j + 1) + 1] = c[1] * scale;
        }
    };
    let x_parts = |x: &[f64]| -> (P2, Vec<[f64; 2]>) {
        (
            P2::new(x[ub(0)], x[ub(0) + 1]),
            (0..nb).map(|j| [x[ub(j + 1)], x[ub(j + 1) + 1]]).collect(),
        )
    };
    let ro = |x: &[f64]| {
        let (u, b) = x_parts(x);
        round_off_bounds(&zero.with_balancers(&b), u)
    };
    let force = FnField::new("shaking force", 2, |phi: f64, out: &mut AffineValue| {
        let s = st(phi);
        let f0 = force0(zero, &s) * w2;
        let [c, sn] = s.cs;
        out.b = [f0.x, f0.y];
        out.row_mut(0)[ub(0)] = w2 * c;
        out.row_mut(0)[ub(0) + 1] = -w2 * sn;
        out.row_mut(1)[ub(0)] = w2 * sn;
        out.row_mut(1)[ub(0) + 1] = w2 * c;
        fill_balancers(out, phi, 0);
    })
    .with_error(|_, x: &[f64]| ro(x)[0]);
    let moment = FnField::new("shaking moment", 1, |phi: f64, out: &mut AffineValue| {
        out.b = [moment0(zero, &st(phi)) * w2, 0.0];
        fill_balancers(out, phi, 1);
    })
    .with_error(|_, x: &[f64]| ro(x)[2]);
    let torque = FnField::new("drive torque", 1, |phi: f64, out: &mut AffineValue| {
        let s = st(phi);
        out.b = [torque0(zero, &s), 0.0];
        out.row_mut(0)[ub(0)] = weight_torque_cs(s.cs, g, P2::new(1.0, 0.0));
        out.row_mut(0)[ub(0) + 1] = weight_torque_cs(s.cs, g, P2::new(0.0, 1.0));
        fill_balancers(out, phi, 2);
    })
    .with_error(|_, x: &[f64]| ro(x)[1]);
    let bearing = FnField::new("main bearing load", 2, |phi: f64, out: &mut AffineValue| {
        let s = st(phi);
        let f = mech
            .joint_loads(&s, scene.omega, &scene.loads, P2::zeros(), 0.0)
            .main;
        let [c, sn] = s.cs;
        out.b = [f.x, f.y];
        out.row_mut(0)[ub(0)] = -w2 * c;
        out.row_mut(0)[ub(0) + 1] = w2 * sn;
        out.row_mut(1)[ub(0)] = -w2 * sn;
        out.row_mut(1)[ub(0) + 1] = -w2 * c;
    })
    .with_error(|_, x: &[f64]| joint_load_round_off(scene, x_parts(x).0, 0.0));
    const FORCE: usize = 0;
    const MOMENT: usize = 1;
    const TORQUE: usize = 2;
    const BEARING: usize = 3;
    let goal = match objective {
        Objective::MinPeakForce => mm::Goal::MinPeak(vec![(FORCE, 1.0)]),
        Objective::MinRmsForce => mm::Goal::MinRms(FORCE),
        Objective::MinPeakTorque => mm::Goal::MinPeak(vec![(TORQUE, 1.0)]),
        Objective::MinPeakMoment => mm::Goal::MinPeak(vec![(MOMENT, 1.0)]),
        Objective::MinMass | Objective::MinRadius => {
            return Err(SolveError::Numeric(
                "minimising the counterweight's mass or radius is not available with balancers, moment or main-bearing limits".into(),
            ))
        }
    };
    let mut limits = Vec::new();
    for (f, lim) in [
        (FORCE, max_force),
        (TORQUE, max_torque),
        (MOMENT, scene.max_shaking_moment),
        (BEARING, scene.load_limits.main_bearing),
    ] {
        if let Some(l) = lim {
            limits.push((f, l));
        }
    }
    let pb = mm::Problem {
        fields: vec![&force, &moment, &torque, &bearing],
        counterweights: cws,
        extra: Vec::new(),
        linear: Vec::new(),
        goal,
        limits,
    };
    let cs = &scene.resolved_settings();
    let settings = mm::Settings {
        rel_tol: cs.rel_tol,
        initial_samples: cs.initial_samples,
        scan_samples: cs.scan_samples,
        max_rounds: cs.max_rounds,
        peak_xtol: cs.peak_xtol,
        rms_samples: (cs.rms_samples + 1) & !1,
        exact_disc: cs.exact_disc,
        ..mm::Settings::default()
    };
    let num = |e: mm::MinimaxError| SolveError::Numeric(e.to_string());
    let engine = mm::Engine::new(&pb, &settings).map_err(num)?;
    let sol = engine.solve().map_err(num)?;
    let mut warnings = Vec::new();
    if let Some(n) = &sol.note {
        warnings.push(n.clone());
    }
    let feasible = sol.x.iter().all(|v| v.is_finite());
    let (u, b) = if feasible {
        x_parts(&sol.x)
    } else {
        (P2::zeros(), vec![[0.0; 2]; nb])
    };
    if sol.status == Status::Infeasible {
        warnings.push(format!(
            "infeasible: no counterweight and balancers within the bounds meet the limits (peak force ≤ {max_force:?} N, peak torque ≤ {max_torque:?} N·m, shaking moment ≤ {:?} N·m, main bearing ≤ {:?} N); the figures shown are those of no counterweight and no balancers",
            scene.max_shaking_moment, scene.load_limits.main_bearing
        ));
    }
    // A design on a bound the scene did not set would be the bounds' optimum, not the
    // scene's: the Fourier bounds above exclude it, so say so if it happens.
    let on = |v: f64, auto: f64, given: f64| auto < given && v >= auto * (1.0 - 1e-6);
    let mut status = sol.status;
    if feasible
        && (on(u.norm(), u_auto, u_hi)
            || b.iter().zip(&scene.balancers).any(|(bb, spec)| {
                on(
                    bb[0].hypot(bb[1]),
                    auto(spec.pair.order as f64),
                    spec.max_unbalance,
                )
            }))
    {
        status = Status::Inaccurate;
        warnings.push(
            "the joint design reached an automatic bound on |U| or |B_n| (see the method); the optimum may lie beyond it".into(),
        );
    }
    if u_lo > 0.0 && u.norm() < u_lo * (1.0 - 1e-9) {
        return Err(SolveError::Numeric(format!(
            "|U| ≥ {u_lo} kg·m is not convex and not available with balancers, moment or main-bearing limits"
        )));
    }
    let gap = if feasible {
        sol.error.sampling + sol.error.solver
    } else {
        0.0
    };
    Ok(Optimum {
        status,
        u,
        gap,
        method: format!(
            "joint design of the crank counterweight and {nb} balancer pair(s) (synth::minimax, bounds |U| ≤ {u_max:.6e} kg·m{}): clarabel SOCP + exchange loop: {} rounds, {} angles, {} interior-point iterations, last status {}",
            b_max
                .iter()
                .zip(&scene.balancers)
                .map(|(m, s)| format!(", |B_{}| ≤ {m:.6e} kg·m", s.pair.order))
                .collect::<String>(),
            sol.rounds,
            sol.angles,
            sol.ipm_iterations,
            sol.solver_status
        ),
        rounds: sol.rounds,
        warnings,
        balancers: b,
    })
}
