//! The lever counterweight's linkage (thesis Fig 1.5c, issue 38): a lever pivoted at O on the
//! A-frame, linked to the boom by a rod from its pin L to the boom point K — a four-bar
//! A–K–L–O whose input is the boom angle φ and whose output is the lever angle ψ. Pure
//! kinematics, no masses.
//!
//! K(φ) = s e_b + n e_n turns with the boom ([`boom_frame`]), dK/dφ = (K_y, −K_x). The rod
//! pin is L = circle(K, c) ∩ circle(O, ρ) on the branch of the given lever angle ψ₁ at
//! maximum reach (φ_min), with the rod length c = |L(ψ₁) − K(φ_min)|; ψ = atan2(L − O). The
//! rod is rigid, (L − K)·(L′ − K′) = 0 with L′ = ψ′ ẑ × (L − O), so
//!
//! ψ′(φ) = (L − K)·K′ / ((L − K)·(ẑ × (L − O))),
//!
//! singular where the rod and the lever align (the denominator is ρ c sin of their angle).
//! A counterweight on the lever with the first moment w = (w_s, w_n) about O in the lever
//! frame (w_s along O→L) has the height m y = m O_y + w_s sin ψ + w_n cos ψ, so its torque
//! at the boom foot is T_cw = dV/dφ = g ψ′ (w_s cos ψ − w_n sin ψ): affine in w, and the
//! minimax of the drive torque over w is convex as for a counterweight on the boom.

use super::statics::boom_frame;
use crate::geom::{circle_circle, cross, Side, P2};
use crate::units::STANDARD_GRAVITY as G;

/// The lever's four-bar (SI, frame of A).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LeverLinkage {
    /// O, the lever's pivot on the A-frame (m).
    #[serde(rename = "pivot_m")]
    pub pivot: P2,
    /// ρ = |OL|, the lever's arm to the rod pin (m).
    #[serde(rename = "arm_m")]
    pub arm: f64,
    /// c = |LK|, the rod's length (m), from the lever angle at maximum reach.
    #[serde(rename = "rod_m")]
    pub rod: f64,
    /// K = (s, n) on the boom, the rod's boom pin (m, boom frame).
    #[serde(rename = "boom_point_m")]
    pub boom_point: [f64; 2],
    /// The assembly branch (side of L from the line K → O).
    #[serde(skip)]
    pub side: Side,
}

/// A pose of the lever: ψ, ψ′ and the points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeverPose {
    /// ψ, the lever's direction O → L (rad).
    pub psi: f64,
    /// ψ′ = dψ/dφ.
    pub psi_rate: f64,
    /// K, the rod's boom pin.
    pub k: P2,
    /// L, the rod's lever pin.
    pub l: P2,
    /// ρ c/|(L − K)·(ẑ × (L − O))|, the condition of ψ′ (1/sin of the rod–lever angle).
    pub condition: f64,
}

impl LeverLinkage {
    /// The linkage with the lever at angle ψ₁ at φ_min: c = |O + ρ(cos ψ₁, sin ψ₁) − K(φ_min)|
    /// and the branch of that pose. `None` for a zero arm or rod, or a degenerate pose.
    pub fn new(pivot: P2, arm: f64, psi1: f64, boom_point: [f64; 2], phi_min: f64) -> Option<Self> {
        let k = boom_point_at(boom_point, phi_min);
        let l = pivot + arm * P2::new(psi1.cos(), psi1.sin());
        let rod = (l - k).norm();
        let s = cross(pivot - k, l - k);
        if !(arm > 0.0 && rod > 0.0 && s != 0.0 && s.is_finite()) {
            return None;
        }
        let side = if s > 0.0 { Side::Left } else { Side::Right };
        Some(LeverLinkage {
            pivot,
            arm,
            rod,
            boom_point,
            side,
        })
    }

    /// The pose at φ (module doc); `None` where the rod cannot reach the lever or ψ′ is
    /// singular.
    pub fn pose(&self, phi: f64) -> Option<LeverPose> {
        let k = boom_point_at(self.boom_point, phi);
        let l = circle_circle(k, self.rod, self.pivot, self.arm, self.side)?;
        let r = l - self.pivot;
        let rod = l - k;
        let k_rate = P2::new(k.y, -k.x);
        let den = rod.dot(&P2::new(-r.y, r.x));
        let psi_rate = rod.dot(&k_rate) / den;
        psi_rate.is_finite().then_some(LeverPose {
            psi: r.y.atan2(r.x),
            psi_rate,
            k,
            l,
            condition: self.arm * self.rod / den.abs(),
        })
    }

    /// The counterweight's drive torque per unit first moment w (N·m per kg·m):
    /// g ψ′ (cos ψ, −sin ψ).
    pub fn torque_row(p: &LeverPose) -> [f64; 2] {
        let (s, c) = p.psi.sin_cos();
        [G * p.psi_rate * c, -G * p.psi_rate * s]
    }

    /// The first moment w (lever frame) in the world about O: w_s (cos ψ, sin ψ) +
    /// w_n (−sin ψ, cos ψ) (kg·m).
    pub fn world_moment(p: &LeverPose, w: [f64; 2]) -> P2 {
        let (s, c) = p.psi.sin_cos();
        P2::new(w[0] * c - w[1] * s, w[0] * s + w[1] * c)
    }
}

/// K(φ) = s e_b + n e_n.
pub fn boom_point_at(boom_point: [f64; 2], phi: f64) -> P2 {
    let (e_b, e_n) = boom_frame(phi);
    e_b * boom_point[0] + e_n * boom_point[1]
}
