//! What a slider-crank solve returns: the figures of a counterweight ([`Metrics`]), the
//! design, objectives, errors and derived keys of a result, the baselines, the joint-load
//! peaks, the Pareto points and the optimum before its evaluation ([`Optimum`]).

use super::realise::Realised;
use super::scene::{BalancerSpec, Objective, Scene};
use crate::geom::P2;
use crate::report::numbers::key;
use crate::synth::counterweight::Status;
use crate::synth::shape::ShapeSpec;
use serde::Serialize;
use std::collections::BTreeMap;

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
    /// ΔE of the drive at constant speed and its error bound (J), where the scene asks for
    /// it (the energy-fluctuation objective; [`super::drive::energy_fluctuation`]).
    pub energy_fluctuation: Option<[f64; 2]>,
    /// With an operating envelope: the worst case over its vertices of the figure the scene
    /// minimises (N, N·m or J; [`super::envelope::Envelope::worst_of`]), for a baseline.
    pub worst_case: Option<f64>,
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
            energy_fluctuation_j: self.energy_fluctuation.map(|e| e[0]),
            worst_case: Default::default(),
            improvement_pct: None,
        }
    }
}

/// |U| (kg·m) and its angle from the crank direction in [0, 2π) (rad; 0 for U = 0).
pub(super) fn polar(u: [f64; 2]) -> (f64, f64) {
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
    /// ΔE = max E − min E, the energy fluctuation of the drive at constant speed, E(φ) =
    /// ∫₀^φ (T − T̄) dφ (J; with the energy-fluctuation objective).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_fluctuation_j: Option<f64>,
    /// With an operating envelope: the largest peak force over it (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub worst_case_peak_shaking_force_n: Option<f64>,
    /// With an operating envelope: the largest peak drive torque over it (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub worst_case_peak_drive_torque_nm: Option<f64>,
    /// With an operating envelope and the energy-fluctuation objective: the largest ΔE over it (J).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub worst_case_energy_fluctuation_j: Option<f64>,
}

impl Objectives {
    /// The key objective of a scene with an operating envelope: the worst case of the
    /// objective over it (the peak moment's worst case is not reported: its own key).
    pub fn worst_case_key(objective: Objective) -> &'static str {
        match objective {
            Objective::MinPeakTorque => key!(Objectives, worst_case_peak_drive_torque_nm),
            Objective::MinEnergyFluctuation => key!(Objectives, worst_case_energy_fluctuation_j),
            _ => key!(Objectives, worst_case_peak_shaking_force_n),
        }
    }

    /// The key objective of a scene: the one minimised (`peak_shaking_force_n` for the mass
    /// and radius objectives, whose peak force is their constraint).
    pub fn key(objective: Objective) -> &'static str {
        match objective {
            Objective::MinPeakTorque => key!(Objectives, peak_drive_torque_nm),
            Objective::MinEnergyFluctuation => key!(Objectives, energy_fluctuation_j),
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
    /// λ = r/l: crank over rod (absent where the file leaves the rod length out: obliquity
    /// neglected).
    pub lambda: Option<f64>,
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
    /// ΔE span of a ΔE–force Pareto front (J).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pareto_energy_span_j: Option<f64>,
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
    /// ΔE, the energy fluctuation of the drive at constant speed (J; with the
    /// energy-fluctuation objective).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_fluctuation_j: Option<f64>,
    /// With an operating envelope: the worst case of the scene's objective over it, under
    /// the objective's own key (`worst_case_peak_shaking_force_n`, …).
    #[serde(flatten, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub worst_case: std::collections::BTreeMap<String, f64>,
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
    /// With an infeasible scene: how far off each limit is (the design is then the closest).
    pub infeasibility: Vec<crate::synth::Shortfall>,
    /// With an operating envelope: the design over it (vertices, worst cases, the check).
    pub envelope: Option<super::envelope::EnvelopeOutcome>,
    /// The envelope's sensitivity table, where asked ([`Optimum::sensitivities`]).
    pub sensitivities: Option<Result<Vec<super::Sensitivity>, String>>,
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
    /// Its optimality gap in torque (N·m; a torque–force front).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gap_nm: Option<f64>,
    /// ΔE of the point's design, the energy fluctuation (J; a ΔE–force front).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_fluctuation_j: Option<f64>,
    /// Its optimality gap in ΔE (J; a ΔE–force front).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gap_j: Option<f64>,
    /// Unbalance in the crank frame (kg·m).
    pub unbalance_x_kgm: f64,
    /// See `unbalance_x_kgm`.
    pub unbalance_y_kgm: f64,
    /// With balancers: each pair's B_n = (B_c, B_s) (kg·m), in the order of `orders`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub balancers_kgm: Vec<[f64; 2]>,
    /// Solver status.
    pub status: Status,
}

impl ParetoPoint {
    /// The objective the front trades against the peak force: ΔE on a ΔE–force front, else
    /// the peak drive torque.
    pub fn traded(&self) -> f64 {
        self.energy_fluctuation_j
            .unwrap_or(self.peak_drive_torque_nm)
    }

    /// The optimality gap in [`Self::traded`].
    pub fn gap(&self) -> f64 {
        self.gap_j.or(self.gap_nm).unwrap_or(0.0)
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
    /// What the envelope's sensitivity table is computed from, for an envelope solve by the
    /// joint engine ([`super::sensitivity_table`], in the solve's report stage as the
    /// linkage does: a sweep or a front of optima does not pay for tables it never shows).
    pub duals: Option<super::EnvelopeDuals>,
}
