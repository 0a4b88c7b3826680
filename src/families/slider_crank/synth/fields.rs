//! The slider-crank's fields as functions of the crank angle φ and the unbalance U: the
//! shaking force, moment and drive torque without counterweight (f₀, M₀, T₀) and with it,
//! normalised for the convex engine ([`Normalised`]) and remembered on the scan grid
//! ([`Sampled`]).

use super::scene::Scene;
use crate::families::slider_crank::model::{rot_cs, weight_torque_cs, SliderCrank, State};
use crate::geom::P2;
use crate::synth::counterweight::Affine;

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
pub(super) fn force0_at(scene: &Scene, phi: f64) -> ([f64; 2], P2) {
    let (cs, f) = scene.mech.shaking_force0_at(phi).expect("assembly checked");
    if scene.balancers.is_empty() {
        (cs, f)
    } else {
        (cs, f + P2::new(scene.balancer_force0(phi), 0.0))
    }
}

/// The normalised fields of a scene. Force: f̂(φ; û) = f₀(φ)/U_ref + Rot(φ)·û with
/// U_ref = (m_tq + m_ct)R; torque: T̂ = T(φ; U)/(ω² U_ref R), affine in û through the
/// counterweight's weight.
pub(super) struct Normalised<'a> {
    pub(super) scene: &'a Scene,
    pub(super) u_ref: f64,
    pub(super) t_ref: f64,
}

impl<'a> Normalised<'a> {
    pub(super) fn new(scene: &'a Scene) -> Self {
        let m = &scene.mech;
        let u_ref = (m.m_rot() + m.m_rec()) * m.r;
        Normalised {
            scene,
            u_ref,
            t_ref: scene.omega * scene.omega * u_ref * m.r,
        }
    }
    pub(super) fn state(&self, phi: f64) -> State {
        // Assembly was checked for the whole revolution before any field is evaluated.
        self.scene.mech.state(phi).expect("assembly checked")
    }
    pub(super) fn force(&self, phi: f64) -> Affine {
        let (cs, f0) = force0_at(self.scene, phi);
        self.force_of(cs, f0)
    }
    /// f̂ from (cos φ, sin φ) and f₀(φ).
    pub(super) fn force_of(&self, [c, s]: [f64; 2], f0: P2) -> Affine {
        let f0 = f0 / self.u_ref;
        Affine {
            a: [[c, -s], [s, c]],
            b: [f0.x, f0.y],
        }
    }
    pub(super) fn torque(&self, phi: f64) -> Affine {
        let st = self.state(phi);
        self.torque_of(st.cs, torque0(self.scene, &st))
    }
    /// T̂ from (cos φ, sin φ) and T(φ; 0) (N·m).
    pub(super) fn torque_of(&self, cs: [f64; 2], t0: f64) -> Affine {
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
pub(super) fn torque0(scene: &Scene, st: &State) -> f64 {
    let m = &scene.mech;
    let t = scene.omega * scene.omega * m.drive_torque0(st) + m.load_torque0(st, &scene.loads);
    if scene.balancers.is_empty() {
        t
    } else {
        t + scene.balancer_torque(st.phi)
    }
}

/// True when the drive torque cannot depend on the counterweight: its only path into the
/// torque is its weight, T_cw = −g·Rot'(φ)U, which is zero without gravity.
pub(super) fn torque_independent_of_counterweight(scene: &Scene) -> bool {
    scene.loads.gravity.norm() == 0.0
}

/// The counterweight-independent parts of the shaking force (f₀, before the ω² factor) and
/// of the drive torque, with cos φ and sin φ, sampled on the scan grid and the RMS grid of
/// [`periodic_peak`] and [`periodic_rms`]. Evaluating many counterweights of one scene (the
/// design, the baselines, the `equal_ranges` root search, the Pareto points) then computes
/// the kinematics once per grid angle instead of once per angle, peak and counterweight;
/// the refinement of a peak between grid angles evaluates the mechanism directly. Values
/// are bit-identical to the direct evaluation: the same expressions on the same states,
/// only remembered.
pub(super) struct Sampled {
    pub(super) scan: Grid,
    /// The RMS grid when it differs from the scan grid.
    pub(super) rms: Option<Grid>,
    /// Work space of [`metrics_sampled`] (3 columns of the scan grid).
    pub(super) scratch: std::cell::RefCell<Vec<f64>>,
    /// The refined peak drive torque (value, angle, error) when it does not depend on the
    /// counterweight (no gravity), once computed.
    pub(super) torque_peak: std::cell::OnceCell<(f64, f64, f64)>,
}

pub(super) struct Grid {
    /// (cos φₖ, sin φₖ).
    pub(super) cs: Vec<[f64; 2]>,
    /// f₀(φₖ) (kg·m).
    pub(super) f0: Vec<P2>,
    /// ω²·T_drive0(φₖ) + T_load0(φₖ) (N·m); empty in a force-only grid.
    pub(super) t0: Vec<f64>,
    /// Shaking moment per ω², M₀(φₖ) (kg·m²); empty in a force-only grid.
    pub(super) m0: Vec<f64>,
}

/// What a [`Grid`] remembers besides the force.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Columns {
    /// Only f₀ (the minimax of the force needs nothing else).
    Force,
    /// f₀, the torque and the moment (the figures of a design).
    All,
}

impl Grid {
    pub(super) fn new(scene: &Scene, n: usize, columns: Columns) -> Grid {
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
    pub(super) fn len(&self) -> usize {
        self.cs.len()
    }
    /// F(φₖ; u) (N), as [`shaking_force`].
    pub(super) fn force(&self, k: usize, u: P2, w2: f64) -> P2 {
        (self.f0[k] + rot_cs(self.cs[k], u)) * w2
    }
    /// T(φₖ; u) (N·m), as [`drive_torque`].
    pub(super) fn torque(&self, k: usize, gravity: P2, u: P2) -> f64 {
        self.t0[k] + weight_torque_cs(self.cs[k], gravity, u)
    }
}

impl Sampled {
    pub(super) fn rms(&self) -> &Grid {
        self.rms.as_ref().unwrap_or(&self.scan)
    }

    pub(super) fn new(scene: &Scene) -> Sampled {
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
