//! Statics of the luffing four-bar under gravity (thesis `003`: ch. 1, Fig 1.5, the boom's
//! self-weight balanced by a counterweight; §2.2, Fig 2.4, the forces of the load on the
//! boom system): the luffing drive torque, the tie force and the pin loads of boom, jib and
//! tie at one pose, with the boom counterweight's static moment as an input.
//!
//! Luffing is slow, so each body is in equilibrium under its weight, the load, its pin
//! forces and (the boom) the drive torque. The bodies, in the frame of [`super::model`]:
//! * boom AD: pin A to the frame, pin D to the jib; weight m_b g at G_b = s_b·D (s_b the
//!   centroid's fraction of AD); the counterweight, first moment u = m·p in the boom frame
//!   (see [`boom_frame`]); the drive torque T about A;
//! * jib C–D–E: weight m_j g at G_j = D + f_j (C − D) (f_j < 0: towards the tail E); the
//!   load Q g hangs at the head C (a hoist rope of constant length, parallel to the boom or
//!   the tie, thesis §2.1: the rope's own pull on the jib is not modelled);
//! * tie EB: weight m_t g at its middle; pin B to the frame.
//!
//! With F the force of the jib on the tie at E (all forces below act on the body named):
//! * tie, moments about B: (E − B) × F = −(G_t − B) × W_t;
//! * jib, moments about D: (E − D) × F = (C − D) × Q + (G_j − D) × W_j;
//!
//! a 2×2 system whose determinant (E − B) × (E − D) vanishes when the tie and the jib tail
//! align (transmission angle μ = 0): its condition is ~1/sin μ. Then the boom's force on the
//! jib at D is F_D = F − Q − W_j, the frame's force on the boom at A is
//! F_A = −F_D... written out in [`statics`], and the drive torque, positive in the sense of
//! increasing φ (raising the boom, shortening the reach), is
//!
//! T(φ) = D × (−F_D) + G_b × W_b + g (u_s cos φ + u_n sin φ),
//!
//! which is dV/dφ, V the potential energy of every weight (virtual work): affine in the
//! counterweight's first moment u, so its minimax over the luffing range is convex
//! ([`super::balance`]).

pub use super::model::HoistRope;
use super::model::{Linkage, Pose};
use crate::geom::{cross, P2};
use crate::units::STANDARD_GRAVITY as G;

/// Masses and centroids of the boom system (kg; centroids as fractions, see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SelfWeight {
    /// m_b, boom mass (kg).
    pub boom_mass: f64,
    /// s_b: the boom's centroid at s_b·AD from A.
    pub boom_centroid: f64,
    /// m_j, jib mass (kg).
    pub jib_mass: f64,
    /// f_j: the jib's centroid at D + f_j (C − D) (negative: behind D, towards the tail).
    pub jib_centroid: f64,
    /// m_t, tie mass (kg), its centroid at the middle of EB.
    pub tie_mass: f64,
}

impl SelfWeight {
    /// A weightless boom system: the load alone (thesis §2.2's load moment; an inclined
    /// rope's load path without masses).
    pub const NONE: SelfWeight = SelfWeight {
        boom_mass: 0.0,
        boom_centroid: 0.5,
        jib_mass: 0.0,
        jib_centroid: 0.5,
        tie_mass: 0.0,
    };
}

/// The boom frame at boom angle φ: e_b = (D − A)/L_c = (−cos φ, sin φ) (angle 0, towards the
/// boom head) and e_n = e_b turned +90° = (−sin φ, −cos φ). A counterweight's first moment
/// u = (u_s, u_n) is u_s e_b + u_n e_n in the world; on the boom's extension behind A it
/// points at 180°.
pub fn boom_frame(phi: f64) -> (P2, P2) {
    let (s, c) = phi.sin_cos();
    (P2::new(-c, s), P2::new(-s, -c))
}

/// The drive torque of a counterweight of first moment u (kg·m, boom frame) per unit u:
/// T_cw = g (u_s cos φ + u_n sin φ) = g·(cos φ, sin φ)·u (N·m per kg·m).
pub fn counterweight_torque_row(phi: f64) -> [f64; 2] {
    let (s, c) = phi.sin_cos();
    [G * c, G * s]
}

/// The forces at one pose (N, N·m; each force acts on the body named).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Statics {
    /// T: the drive torque about A, positive raising the boom (N·m).
    pub drive_torque: f64,
    /// Bound on |T − exact T| from rounding and the pose's conditioning (N·m).
    pub drive_torque_error: f64,
    /// Frame on boom at A (N).
    pub pin_a: P2,
    /// Frame on tie at B (N).
    pub pin_b: P2,
    /// Boom on jib at D (N).
    pub pin_d: P2,
    /// Jib on tie at E (N).
    pub pin_e: P2,
    /// K, the tie's axial force at E, tension positive (N).
    pub tie_tension: f64,
    /// The boom's axial force at D, compression positive (N).
    pub boom_compression: f64,
    /// The force across the boom at D (N): the bending the jib puts into the boom head.
    pub boom_shear: f64,
    /// Thesis §2.2: N = |force of the jib on the boom at D| (N).
    pub head_force: f64,
    /// α, the angle between N and the boom axis (rad).
    pub head_force_angle: f64,
    /// M_Ah = N L_c sin α, the moment of N about A (N·m; with a weightless jib and tie, the
    /// thesis's unbalanced moment of the load).
    pub head_moment: f64,
    /// 1/sin μ, the condition of the tie–jib system at this pose.
    pub condition: f64,
    /// Bound on the error of every force above (N): rounding and the pose's conditioning.
    pub force_error: f64,
}

/// The loads a pose carries: the hanging load and the counterweight (kg, kg·m).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Loads {
    /// Q, the hanging load (kg).
    pub load_mass: f64,
    /// The counterweight's mass (kg): only its pin load at A depends on it.
    pub counterweight_mass: f64,
    /// Its first moment u about A in the boom frame (kg·m).
    pub counterweight_moment: [f64; 2],
    /// The hoist rope, if inclined (see [`HoistRope`]); `None`: the load hangs at the jib
    /// head and the rope runs parallel to the boom or the tie (thesis §2.1), pulling nothing.
    pub rope: Option<HoistRope>,
}

/// The tie pin B; `None` for the straight-guide limit, which pushes E along its normal
/// only (its "pin" is at infinity).
pub fn tie_pin(link: &Linkage) -> Option<P2> {
    match link.guide {
        super::model::Guide::Circle { centre, .. } => Some(centre),
        super::model::Guide::Line { .. } => None,
    }
}

/// The centroids of boom, jib and tie at `pose` with the tie pin `b`: G_b = s_b·D,
/// G_j = D + f_j (C − D), G_t = (E + B)/2 (module doc).
pub fn centroids(pose: &Pose, b: P2, w: &SelfWeight) -> [P2; 3] {
    let Pose { d, e, c } = *pose;
    [
        d * w.boom_centroid,
        d + (c - d) * w.jib_centroid,
        (e + b) * 0.5,
    ]
}

/// The statics at `pose` (boom angle φ) of the linkage `link` (module doc). `None` where the
/// tie and the jib tail are aligned (no finite solution).
pub fn statics(
    link: &Linkage,
    phi: f64,
    pose: &Pose,
    w: &SelfWeight,
    l: &Loads,
) -> Option<Statics> {
    let Pose { d, e, c } = *pose;
    let b = tie_pin(link)?;
    let down = |m: f64| P2::new(0.0, -m * G);
    let (w_t, w_j, w_b, q) = (
        down(w.tie_mass),
        down(w.jib_mass),
        down(w.boom_mass),
        down(l.load_mass),
    );
    let [g_b, g_j, g_t] = centroids(pose, b, w);
    // (E − B) × F = r1, (E − D) × F = r2.
    let (a1, a2) = (e - b, e - d);
    let t_r1 = [cross(g_t - b, w_t)];
    // The jib head carries the load and, with an inclined rope, the lead rope's pull W/n
    // towards the sheave S.
    let head = match l.rope {
        Some(r) => {
            let to_s = r.sheave - c;
            q + to_s * (q.norm() / (r.parts * to_s.norm()))
        }
        None => q,
    };
    let q = head;
    let t_r2 = [cross(c - d, q), cross(g_j - d, w_j)];
    let r1 = -t_r1[0];
    let r2 = t_r2[0] + t_r2[1];
    let det = cross(a1, a2);
    if !(det.abs() > 0.0) {
        return None;
    }
    let f = P2::new((a2.x * r1 - a1.x * r2) / det, (a2.y * r1 - a1.y * r2) / det);
    let pin_d = f - q - w_j;
    let u = l.counterweight_moment;
    let w_cw = down(l.counterweight_mass);
    let row = counterweight_torque_row(phi);
    let t_parts = [
        cross(d, -pin_d),
        cross(g_b, w_b),
        row[0] * u[0],
        row[1] * u[1],
    ];
    let drive_torque: f64 = t_parts.iter().sum();
    let pin_a = pin_d - w_b - w_cw;
    let pin_b = -(f + w_t);
    let (na1, na2) = (a1.norm(), a2.norm());
    let condition = na1 * na2 / det.abs();
    // Rounding and conditioning (module doc): the pose carries δp = 8ε·L·(1 + 1/k2)/sin μ
    // (circle intersection near tangency, the head C = D + (D − E)/k2); the 2×2 solve
    // amplifies the perturbation of its data by ‖M⁻¹‖ ≤ (|a1| + |a2|)/|det|.
    let eps = f64::EPSILON;
    let dp = 8.0 * eps * link.length_scale() * (1.0 + 1.0 / link.k2) * condition;
    let w_sum = q.norm() + w_j.norm() + w_t.norm();
    let d_r = 16.0 * eps * (t_r1[0].abs() + t_r2[0].abs() + t_r2[1].abs()) + 4.0 * dp * w_sum;
    let d_m = 16.0 * eps * (na1 + na2) + 4.0 * dp;
    let df = (na1 + na2) / det.abs() * (d_r + d_m * f.norm());
    let drive_torque_error = link.l_c * (df + 8.0 * eps * pin_d.norm())
        + 16.0 * eps * t_parts.iter().map(|t| t.abs()).sum::<f64>()
        + dp * pin_d.norm();
    let force_error = 2.0 * df
        + 16.0 * eps * (f.norm() + pin_d.norm() + w_sum + w_b.norm() + l.counterweight_mass * G);
    let axis = d / link.l_c;
    let on_boom = -pin_d;
    let head_force = on_boom.norm();
    let head_moment = cross(d, on_boom);
    Some(Statics {
        drive_torque,
        drive_torque_error,
        pin_a,
        pin_b,
        pin_d,
        pin_e: f,
        tie_tension: f.dot(&a1) / na1,
        boom_compression: -on_boom.dot(&axis),
        boom_shear: cross(axis, on_boom),
        head_force,
        head_force_angle: cross(axis, on_boom).abs().atan2(on_boom.dot(&axis).abs()),
        head_moment,
        condition,
        force_error,
    })
}

/// The potential energy V(φ) = g Σ m_i y_i of the boom, jib, tie and load (not the
/// counterweight) at a pose (J, A at height 0; with an inclined rope the load's height up
/// to a constant, [`HoistRope::load_height`]).
pub fn potential(
    pose: &Pose,
    link: &Linkage,
    w: &SelfWeight,
    load_mass: f64,
    rope: Option<&HoistRope>,
) -> Option<f64> {
    let b = tie_pin(link)?;
    let Pose { d, e, c } = *pose;
    let y_t = 0.5 * (e.y + b.y);
    let y_j = d.y + (c.y - d.y) * w.jib_centroid;
    Some(
        G * (w.boom_mass * w.boom_centroid * d.y
            + w.jib_mass * y_j
            + w.tie_mass * y_t
            + load_mass * rope.map_or(c.y, |r| r.load_height(c))),
    )
}

/// The drive torque without counterweight by virtual work, T = dV/dφ, V from
/// [`potential`]: central differences D(h), D(h/2), D(h/4) combined by Richardson,
/// R(h) = (4 D(h/2) − D(h))/3 (error O(h⁴)); the value is R(h/2) and its error estimate
/// |R(h/2) − R(h)| plus the rounding 4ε·max|V|/h. An evaluation independent of [`statics`]
/// (no force is solved), used as the report's check. `None` if a pose fails.
pub fn virtual_work_torque(
    link: &Linkage,
    phi: f64,
    h: f64,
    w: &SelfWeight,
    load_mass: f64,
    rope: Option<&HoistRope>,
) -> Option<(f64, f64)> {
    let v = |p: f64| {
        link.pose(p)
            .and_then(|q| potential(&q, link, w, load_mass, rope))
    };
    let mut vmax: f64 = 0.0;
    let mut dh = |h: f64| {
        let (a, b) = (v(phi + h)?, v(phi - h)?);
        vmax = vmax.max(a.abs()).max(b.abs());
        Some((a - b) / (2.0 * h))
    };
    let (d1, d2, d4) = (dh(h)?, dh(0.5 * h)?, dh(0.25 * h)?);
    let (r1, r2) = ((4.0 * d2 - d1) / 3.0, (4.0 * d4 - d2) / 3.0);
    Some((r2, (r2 - r1).abs() + 4.0 * f64::EPSILON * vmax / (0.25 * h)))
}
