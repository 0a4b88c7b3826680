//! The radial engine's articulated rods: on a throw with several cylinders, one (the master)
//! has its rod on the crank pin, and every other cylinder's rod is pinned to the master rod
//! at a knuckle pin — so its piston does not move as a slider-crank's would, and the layout's
//! harmonics differ from the textbook's "every rod on the crank pin" sums (a radial of five or
//! more equal cylinders on one pin has no secondary force; with articulated rods it does).
//! Closed-form dyads, written here because they are a few lines (the linkage family's general
//! engine computes the same machine, and `tests/multi_cylinder_radial.rs` compares the two).
//!
//! In the master cylinder's frame (x along its axis, γ_m; θ = φ + α − γ_m the crank angle it
//! sees; no offset), with ′ = d/dθ at constant speed (so an acceleration is ω² times ″):
//! * crank pin C = R(cos θ, sin θ), C″ = −C;
//! * master rod from C to its piston pin on the x axis: h = R sin θ, c = √(L² − h²),
//!   its unit vector u = (c, −h)/L, c′ = −h h′/c, c″ = −(h′² + h h″ + c′²)/c;
//! * knuckle pin K = C + r_k Rot(δ) u (r_k the knuckle radius, δ the knuckle angle from the
//!   master rod's axis), K″ = C″ + r_k Rot(δ) u″;
//! * the articulated piston on the axis eₐ = (cos ψ, sin ψ), ψ = γᵢ − γ_m, normal nₐ:
//!   a = K·eₐ, b = K·nₐ, d = √(l² − b²), s = a + d (its distance from the shaft),
//!   d′ = −b b′/d, d″ = −(b′² + b b″ + d′²)/d, s″ = a″ + d″;
//! * the articulated rod's centre of mass G = K + µ(s eₐ − K), µ = its centroid over l.
//!
//! The shaking force per ω² of the articulated cylinder is −(m_p s″ eₐ + m_rod G″), turned by
//! γ_m; the master cylinder is the slider-crank family's machine as before (the knuckle pins'
//! masses belong to the articulated rods' ends).

use crate::geom::{rot, P2};

/// An articulated rod's connection to its throw's master rod.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Articulated {
    /// γ_m, the master cylinder's bank angle (rad).
    pub master_bank: f64,
    /// L, the master rod's length (crank pin to its piston pin, m).
    pub master_rod: f64,
    /// r_k, the knuckle radius: crank pin to knuckle pin on the master rod (m).
    pub knuckle_radius: f64,
    /// δ, the knuckle pin's angle on the master rod from its axis (crank pin → piston pin),
    /// anticlockwise (rad).
    pub knuckle_angle: f64,
}

/// The articulated cylinder's state at one crank angle, in the master's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// The crank pin C.
    pub c: P2,
    /// The master piston pin's distance from the shaft along the master's axis, R cos θ + c.
    pub master: f64,
    /// The knuckle pin K, K′, K″.
    pub k: [P2; 3],
    /// The piston's distance s from the shaft along its axis, s′, s″.
    pub s: [f64; 3],
    /// eₐ, the articulated cylinder's axis (unit).
    pub axis: P2,
}

impl Articulated {
    /// ψ = γᵢ − γ_m, the articulated axis in the master's frame.
    fn psi(&self, bank: f64) -> f64 {
        bank - self.master_bank
    }

    /// The state at the master's crank angle θ, for the throw radius R, the articulated rod
    /// length l and the cylinder's bank γᵢ; `None` where the rod cannot reach its axis.
    pub fn state(&self, r: f64, l: f64, bank: f64, theta: f64) -> Option<State> {
        let big_l = self.master_rod;
        let (st, ct) = theta.sin_cos();
        let c = P2::new(r * ct, r * st);
        let c1 = P2::new(-r * st, r * ct);
        let (h, h1) = (r * st, r * ct);
        let h2 = -h;
        let cc = (big_l * big_l - h * h).sqrt();
        let cc1 = -h * h1 / cc;
        let cc2 = -(h1 * h1 + h * h2 + cc1 * cc1) / cc;
        let u = [
            P2::new(cc, -h) / big_l,
            P2::new(cc1, -h1) / big_l,
            P2::new(cc2, -h2) / big_l,
        ];
        let rk = self.knuckle_radius;
        let k = [
            c + rot(self.knuckle_angle, u[0]) * rk,
            c1 + rot(self.knuckle_angle, u[1]) * rk,
            -c + rot(self.knuckle_angle, u[2]) * rk,
        ];
        let (sp, cp) = self.psi(bank).sin_cos();
        let (ea, na) = (P2::new(cp, sp), P2::new(-sp, cp));
        let a = k.map(|v| v.dot(&ea));
        let b = k.map(|v| v.dot(&na));
        let d2 = l * l - b[0] * b[0];
        if !(d2 > 0.0 && cc > 0.0) {
            return None;
        }
        let d = d2.sqrt();
        let d1 = -b[0] * b[1] / d;
        let dd = -(b[1] * b[1] + b[0] * b[2] + d1 * d1) / d;
        Some(State {
            c,
            master: r * ct + cc,
            k,
            s: [a[0] + d, a[1] + d1, a[2] + dd],
            axis: ea,
        })
    }

    /// The shaking force per ω² (kg·m) of the articulated cylinder in the world frame: its
    /// piston m_p and its rod m_rod (centre of mass at µ·l from the knuckle pin), at the
    /// master's crank angle θ.
    pub fn force0(
        &self,
        r: f64,
        l: f64,
        bank: f64,
        masses: (f64, f64, f64),
        theta: f64,
    ) -> Option<P2> {
        let (m_p, m_rod, mu) = masses;
        let st = self.state(r, l, bank, theta)?;
        let p2 = st.axis * st.s[2];
        let g2 = st.k[2] + (p2 - st.k[2]) * mu;
        Some(rot(self.master_bank, -(p2 * m_p + g2 * m_rod)))
    }

    /// The shaking moment about the shaft per ω² (kg·m²) of the articulated cylinder — the
    /// moment its rod and piston exert on the frame, −[m_rod G × G″ + I_rod χ″ + m_p P × P″]
    /// with P = s·eₐ, G = K + µ(P − K) and the rod's angle χ: P − K = l(cos χ, sin χ), so
    /// χ″ = (P″ − K″)·(−sin χ, cos χ)/l (the cross products do not depend on the frame).
    pub fn roll0(
        &self,
        r: f64,
        l: f64,
        bank: f64,
        masses: (f64, f64, f64, f64),
        theta: f64,
    ) -> Option<f64> {
        let (m_p, m_rod, mu, inertia) = masses;
        let st = self.state(r, l, bank, theta)?;
        let cross = |a: P2, b: P2| a.x * b.y - a.y * b.x;
        let (p, p2) = (st.axis * st.s[0], st.axis * st.s[2]);
        let (k, k2) = (st.k[0], st.k[2]);
        let w = (p - k) / l;
        let chi2 = (p2 - k2).dot(&P2::new(-w.y, w.x)) / l;
        let (g, g2) = (k + (p - k) * mu, k2 + (p2 - k2) * mu);
        Some(-(m_rod * cross(g, g2) + inertia * chi2 + m_p * cross(p, p2)))
    }

    /// A bound on the round-off of s″ and of K″ (m per rad², so per ω²): 64ε·F²·(K₂ + D₂),
    /// with K₂ and D₂ bounds on |K″| and |d″| over the turn, and F = 1 + L²/c_min² + l²/d_min²
    /// the amplification of the two square roots' cancellations (c_min = √(L² − R²),
    /// d_min = √(l² − (R + r_k)²): |b| ≤ |K| ≤ R + r_k). `tests/multi_cylinder_radial.rs`
    /// checks it against a double-double evaluation, near the fold d_min → 0 too.
    pub fn acc_error(&self, r: f64, l: f64) -> f64 {
        let big_l = self.master_rod;
        let rho = r + self.knuckle_radius;
        let c_min = (big_l * big_l - r * r).sqrt();
        let d_min = (l * l - rho * rho).max(0.0).sqrt();
        let c1 = r * r / c_min;
        let c2 = (2.0 * r * r + c1 * c1) / c_min;
        let (u1, u2) = ((r + c1) / big_l, (r + c2) / big_l);
        let (k1, k2) = (r + self.knuckle_radius * u1, r + self.knuckle_radius * u2);
        let d1 = rho * k1 / d_min;
        let d2 = (k1 * k1 + rho * k2 + d1 * d1) / d_min;
        let f = 1.0 + big_l * big_l / (c_min * c_min) + l * l / (d_min * d_min);
        64.0 * f64::EPSILON * f * f * (k2 + d2)
    }
}
