//! The rotating masses of the hypocycloidal machine, their counterweights, the kinetic
//! energy and inertia torque of the whole mechanism, and the couples of offset Lanchester
//! shafts. Paper 004 assumes the rotating masses "balanced by known methods"; this module
//! is that method written out, in SI and without design variables (the synthesis is in
//! `balance.rs`).
//!
//! Bodies and frames (φ the carrier angle, constant speed ω):
//! - the carrier OO1 turns about O at +φ; its centroid is c_c in the carrier frame (x along
//!   OO1);
//! - the planet (gear + crank arm O1A) turns about O1 = R(cos φ, sin φ) at the absolute angle
//!   g = α0 − 2φ of its frame (x along O1A); its centroid is c_p in that frame;
//! - the rod AB (mass m_r, centroid G at AG = a from A, inertia I_G about G) is split, for
//!   the force, exactly into m_A = m_r(L − a)/L at A and m_r·a/L at B (G is a fixed affine
//!   combination of A and B); the B share is part of the reciprocating mass m_B.
//!
//! Inertia (shaking) force of the rotating parts, F = −Σ m a:
//!
//!   F_rot(φ) = ω² [ Rot(φ) U1 + 4 Rot(α0 − 2φ) U2 ],
//!   U1 = m_c c_c + (m_p + m_A) R e_x   (carrier frame, turning at +ω),
//!   U2 = m_p c_p + m_A r e_x            (planet frame, turning at −2ω).
//!
//! A counterweight W1 (first moment m1ρ1 in the carrier frame) on the carrier and W2 (m2ρ2
//! in the planet frame, about O1) on the planet add ω²[Rot(φ)(W1 + m2 R e_x) +
//! 4 Rot(α0 − 2φ) W2] (the planet counterweight's mass also rides on the carrier at R). The
//! two harmonics turn at different speeds, so the force vanishes identically iff
//! W2 = −U2 and W1 = −(U1 + m2 R e_x): with the planet counterweight at radius ρ2,
//! m2 = |U2|/ρ2 (closed form, [`cancelling_counterweights`]).

use crate::geom::{dir, rot, P2};
use std::f64::consts::TAU;

/// The rotating masses (SI).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RotatingMasses {
    /// m_c, the carrier OO1 (kg).
    pub carrier_mass: f64,
    /// c_c, its centroid in the carrier frame (x along OO1, from O) (m).
    pub carrier_centroid: [f64; 2],
    /// m_p, the planet gear with its crank arm O1A (kg).
    pub planet_mass: f64,
    /// c_p, its centroid in the planet frame (x along O1A, from O1) (m).
    pub planet_centroid: [f64; 2],
    /// m_r, the rod AB (kg); 0 when the rod is not described.
    pub rod_mass: f64,
    /// a = AG, its centroid's distance from A along AB (m).
    pub rod_centroid: f64,
    /// I_G, its inertia about G (kg·m²); `None`: the two-point rod, I_G = m_r a (L − a).
    pub rod_inertia: Option<f64>,
}

/// The lengths and speed of one machine (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// R = OO1 (m).
    pub r_carrier: f64,
    /// r = O1A = θR (m).
    pub r_crank: f64,
    /// L = AB = R/λ (m).
    pub l_rod: f64,
    /// α0 (rad).
    pub alpha0: f64,
    /// ω (rad/s).
    pub omega: f64,
}

impl RotatingMasses {
    /// m_A = m_r (L − a)/L: the rod's share at the crank pin A.
    pub fn rod_at_a(&self, g: &Geometry) -> f64 {
        self.rod_mass * (g.l_rod - self.rod_centroid) / g.l_rod
    }

    /// m_r a/L: the rod's share at the piston pin B (part of m_B).
    pub fn rod_at_b(&self, g: &Geometry) -> f64 {
        self.rod_mass * self.rod_centroid / g.l_rod
    }

    /// I_G of the rod: the given one, else the two-point value m_r a (L − a).
    pub fn rod_inertia(&self, g: &Geometry) -> f64 {
        self.rod_inertia
            .unwrap_or(self.rod_mass * self.rod_centroid * (g.l_rod - self.rod_centroid))
    }

    /// (U1, U2): the static unbalances of the parts turning at +ω (carrier frame) and at
    /// −2ω (planet frame) (kg·m), U1 = m_c c_c + (m_p + m_A) R e_x, U2 = m_p c_p + m_A r e_x.
    pub fn unbalances(&self, g: &Geometry) -> (P2, P2) {
        let m_a = self.rod_at_a(g);
        let cc = P2::from(self.carrier_centroid);
        let cp = P2::from(self.planet_centroid);
        (
            self.carrier_mass * cc + P2::new((self.planet_mass + m_a) * g.r_carrier, 0.0),
            self.planet_mass * cp + P2::new(m_a * g.r_crank, 0.0),
        )
    }
}

/// F = ω²[Rot(φ) V1 + 4 Rot(α0 − 2φ) V2] (N): the inertia force of unbalances V1 turning
/// with the carrier and V2 with the planet.
pub fn harmonic_force(g: &Geometry, v1: P2, v2: P2, phi: f64) -> P2 {
    harmonic_force_at(g, v1, v2, phi, g.omega, 0.0)
}

/// [`harmonic_force`] at real speed ω (`omega`) and angular acceleration α (`alpha`) of the
/// carrier: F = ω²[Rot(φ) V1 + 4 Rot(g) V2] + α[−J Rot(φ) V1 + 2 J Rot(g) V2], g = α0 − 2φ
/// (each unbalance's position Rot(kφ)V has the velocity k J Rot(kφ)V per unit speed).
pub fn harmonic_force_at(g: &Geometry, v1: P2, v2: P2, phi: f64, omega: f64, alpha: f64) -> P2 {
    let (a, b) = (rot(phi, v1), rot(g.alpha0 - 2.0 * phi, v2));
    omega * omega * (a + 4.0 * b) + alpha * (2.0 * crate::geom::perp(b) - crate::geom::perp(a))
}

/// One counterweight: its first moment m·ρ (kg·m) in its body's frame, its angle there, and
/// its mass at the chosen centroid radius ρ.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Counterweight {
    /// m·ρ = |W| (kg·m).
    pub first_moment: f64,
    /// Direction of W in the body's frame (rad, in [0, 2π)).
    pub angle: f64,
    /// ρ, the centroid radius chosen (m).
    pub radius: f64,
    /// m = |W|/ρ (kg).
    pub mass: f64,
    /// W (kg·m), body frame.
    pub w: [f64; 2],
}

impl Counterweight {
    /// The counterweight of first moment `w` at radius `radius`.
    pub fn new(w: P2, radius: f64) -> Self {
        let n = w.norm();
        Counterweight {
            first_moment: n,
            angle: if n > 0.0 {
                w.y.atan2(w.x).rem_euclid(TAU)
            } else {
                0.0
            },
            radius,
            mass: n / radius,
            w: [w.x, w.y],
        }
    }
}

/// The counterweights that cancel the rotating force exactly (closed form):
/// W2 = −U2 at radius ρ2 (m2 = |U2|/ρ2), W1 = −(U1 + m2 R e_x) at radius ρ1.
pub fn cancelling_counterweights(
    u1: P2,
    u2: P2,
    r_carrier: f64,
    rho1: f64,
    rho2: f64,
) -> (Counterweight, Counterweight) {
    let w2 = -u2;
    let m2 = w2.norm() / rho2;
    let w1 = -(u1 + P2::new(m2 * r_carrier, 0.0));
    (Counterweight::new(w1, rho1), Counterweight::new(w2, rho2))
}

/// W1 from the effective first-harmonic variable V1 = W1 + m2 R e_x of the synthesis.
pub fn carrier_from_effective(v1: P2, m2: f64, r_carrier: f64) -> P2 {
    v1 - P2::new(m2 * r_carrier, 0.0)
}

/// Position, velocity and acceleration per unit ω (d/dφ, d²/dφ²) of a point or an angle.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Motion {
    p: P2,
    v: P2,
    a: P2,
}

/// The kinematics of every body at φ (SI; derivatives with respect to φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyKinematics {
    o1: Motion,
    a: Motion,
    b: Motion,
    /// Planet frame angle g = α0 − 2φ.
    g: f64,
    /// Rod angle ψ and its φ-derivatives.
    psi: (f64, f64, f64),
}

/// The kinematics at φ from the dimensionless model `m` (its S/R and derivatives) and R.
pub fn kinematics(
    m: &crate::families::hypocycloid::model::Hypocycloid,
    geo: &Geometry,
    phi: f64,
) -> BodyKinematics {
    let rr = geo.r_carrier;
    let r = geo.r_crank;
    let l = geo.l_rod;
    let g = geo.alpha0 - 2.0 * phi;
    let e = dir(phi);
    let o1 = Motion {
        p: rr * e,
        v: rr * crate::geom::perp(e),
        a: -rr * e,
    };
    let d = dir(g);
    let a = Motion {
        p: o1.p + r * d,
        v: o1.v - 2.0 * r * crate::geom::perp(d),
        a: o1.a - 4.0 * r * d,
    };
    let pk = m.piston(phi);
    let b = Motion {
        p: P2::new(rr * pk.s_rel + l, 0.0),
        v: P2::new(rr * pk.ds, 0.0),
        a: P2::new(rr * pk.dds, 0.0),
    };
    // L sin ψ = −y_A, L cos ψ = x_B − x_A.
    let (sp, cp) = (-a.p.y / l, (b.p.x - a.p.x) / l);
    let d1 = -a.v.y / (l * cp);
    let d2 = (-a.a.y + l * sp * d1 * d1) / (l * cp);
    BodyKinematics {
        o1,
        a,
        b,
        g,
        psi: (sp.atan2(cp), d1, d2),
    }
}

/// A point of a body turning with the planet: O1 + Rot(g) c, per unit ω.
fn planet_point(k: &BodyKinematics, c: P2) -> Motion {
    let q = rot(k.g, c);
    Motion {
        p: k.o1.p + q,
        v: k.o1.v - 2.0 * crate::geom::perp(q),
        a: k.o1.a - 4.0 * q,
    }
}

/// Everything that moves with a varying speed, for the kinetic energy: the masses above,
/// the piston m_B − m_r a/L, and the planet counterweight (mass m2, first moment W2 in the
/// planet frame). The carrier, its counterweight, the planet's own spin and the Lanchester
/// rotors turn at constant speed: their energy is constant and gives no torque.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MovingMasses {
    /// The rotating parts.
    pub rotating: RotatingMasses,
    /// m_B, the reciprocating mass (piston + the rod's B share) (kg).
    pub m_b: f64,
    /// m2 (kg) and W2 (kg·m) of the planet counterweight (0 without one).
    pub planet_cw: (f64, P2),
}

impl MovingMasses {
    /// (E/ω², T_in/ω²) at φ: the varying part of the kinetic energy per ω² (kg·m²) and its
    /// φ-derivative, the inertia torque at constant speed per ω² (T_in = dE/dφ):
    ///
    ///   E/ω² = ½ Σ m_k |G_k'|² + ½ I_G ψ'²,   T_in/ω² = Σ m_k G_k'·G_k'' + I_G ψ' ψ''
    ///
    /// over the planet centroid, the planet counterweight (its centroid W2/m2), the rod
    /// centroid G = A + (a/L)(B − A) and the piston (m_B − m_r a/L at B).
    pub fn energy_and_torque(&self, k: &BodyKinematics, geo: &Geometry) -> (f64, f64) {
        let rm = &self.rotating;
        let mut e = 0.0;
        let mut t = 0.0;
        let mut add = |m: f64, mo: Motion| {
            e += 0.5 * m * mo.v.norm_squared();
            t += m * mo.v.dot(&mo.a);
        };
        add(
            rm.planet_mass,
            planet_point(k, P2::from(rm.planet_centroid)),
        );
        let (m2, w2) = self.planet_cw;
        if m2 > 0.0 {
            add(m2, planet_point(k, w2 / m2));
        }
        let f = rm.rod_centroid / geo.l_rod;
        let gm = Motion {
            p: (1.0 - f) * k.a.p + f * k.b.p,
            v: (1.0 - f) * k.a.v + f * k.b.v,
            a: (1.0 - f) * k.a.a + f * k.b.a,
        };
        add(rm.rod_mass, gm);
        add(self.m_b - rm.rod_at_b(geo), k.b);
        let ig = rm.rod_inertia(geo);
        e += 0.5 * ig * k.psi.1 * k.psi.1;
        t += ig * k.psi.1 * k.psi.2;
        (e, t)
    }
}

/// The two shafts of one Lanchester pair seen from the frame: the co-rotating shaft at
/// (x_s + d/2, e), the counter-rotating one at (x_s − d/2, e), e the offset of the pair
/// from the piston line (the x axis through O) and d their spacing along it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ShaftLayout {
    /// e, the offset of both shafts from the piston line (m).
    pub offset: f64,
    /// d, the distance between the two shafts along the piston line (m).
    pub spacing: f64,
}

impl ShaftLayout {
    /// The moment about O (N·m, counter-clockwise positive) of the pair's two forces at φ,
    /// summed directly: Σ_k x_k F_y,k − y_k F_x,k with each mass's force from
    /// [`crate::families::hypocycloid::model::LanchesterPair`] (x_s drops out: the y-forces
    /// are equal and opposite).
    pub fn couple_direct(
        &self,
        p: &crate::families::hypocycloid::model::LanchesterPair,
        phi: f64,
    ) -> f64 {
        let f = p.static_moment * p.speed * p.speed;
        let i = p.order as f64;
        let f_co = f * dir(i * phi + p.phase_co);
        let f_counter = f * dir(-i * phi + p.phase_counter);
        let (x_co, x_counter) = (0.5 * self.spacing, -0.5 * self.spacing);
        let y = self.offset;
        (x_co * f_co.y - y * f_co.x) + (x_counter * f_counter.y - y * f_counter.x)
    }

    /// Amplitude of the pair's couple (N·m): with Φ_i = F_i cos(iφ − γ_i) its order's
    /// force, the x-forces sum to −Φ_i and the y-forces to ±½F_i sin(iφ − γ_i), so
    /// M_i(φ) = e Φ_i(φ) − (d/2) F_i sin(iφ − γ_i) and |M_i| = F_i sqrt(e² + d²/4),
    /// F_i = 2 m′r′ (iω)².
    pub fn couple_amplitude(&self, p: &crate::families::hypocycloid::model::LanchesterPair) -> f64 {
        let f_i = 2.0 * p.static_moment * p.speed * p.speed;
        f_i * self.offset.hypot(0.5 * self.spacing)
    }
}
