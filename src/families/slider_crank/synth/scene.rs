//! The slider-crank scene: the mechanism, its speed and loads, the counterweight's and the
//! balancers' variables, the objective and the limits, and the checks that make it solvable.

use super::envelope::Envelope;
use crate::families::slider_crank::model::{
    BalancerPair, Kinematics, Loads, ProcessForce, SliderCrank,
};
use crate::synth::counterweight::{self as cw};
use crate::synth::shape::ShapeSpec;
use crate::synth::Var;

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
    /// The energy fluctuation ΔE = max E − min E of the drive at constant speed, E(φ) =
    /// ∫₀^φ (T − T̄) dφ: affine in U through the counterweight's weight (and the balancers'),
    /// so ΔE is convex in the design. Solved jointly by [`crate::synth::minimax`] with the
    /// energy curve as a field ([`crate::synth::energy`]).
    MinEnergyFluctuation,
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
    /// The operating envelope (empty: the nominal scene only).
    pub envelope: Envelope,
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
    /// The centroid radius of each shaft's eccentric mass (m), when the file gives it: each
    /// shaft then carries |B_n|/(2r) kg.
    pub mass_radius: Option<f64>,
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
    pub(super) fn balancer_force0(&self, phi: f64) -> f64 {
        self.balancers
            .iter()
            .map(|b| {
                let c = b.pair.force_coeffs(phi);
                c[0] * b.unbalance[0] + c[1] * b.unbalance[1]
            })
            .sum()
    }

    /// Σ_n M_n/ω² of the balancers (kg·m²).
    pub(super) fn balancer_moment0(&self, phi: f64) -> f64 {
        self.balancers
            .iter()
            .map(|b| {
                let c = b.pair.moment_coeffs(phi);
                c[0] * b.unbalance[0] + c[1] * b.unbalance[1]
            })
            .sum()
    }

    /// Σ_n T_n of the balancers' weights (N·m).
    pub(super) fn balancer_torque(&self, phi: f64) -> f64 {
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

/// Checks that the scene can be solved: the mechanism assembles over the whole revolution
/// ((R + |e|)/L < 1) and some link has mass ((m_tq + m_ct)·R > 0).
pub(super) fn check(scene: &Scene) -> Result<(), SolveError> {
    let mech = &scene.mech;
    if mech.assembly_ratio() >= 1.0 {
        return Err(SolveError::CannotAssemble(mech.assembly_ratio()));
    }
    if !((mech.m_rot() + mech.m_rec()) * mech.r > 0.0) {
        return Err(SolveError::NoMass);
    }
    Ok(())
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
        envelope: Envelope::default(),
    }
}
