//! The slider-crank (piston) mechanism: exact kinematics with derivatives, shaking force,
//! shaking moment and drive torque at constant crank speed.
//!
//! Notation follows `shared/domain/slider-crank.md`: crank OA of radius R at angle φ, rod AB
//! of length L, slider B on the line y = e (e = 0: in-line), λ = R/L. ' is d/dφ; at constant
//! ω every acceleration is ω² times a second derivative, so the functions here return
//! quantities per ω² (kg·m for forces, kg·m² for torques and moments) and the caller scales.
//!
//! The rod is a rigid body (mass m3, centre of mass G3 at l3 from A, moment of inertia I3
//! about G3). The classical lumped model — m3·s at A and m3·(1−s) at B — is exactly the rigid
//! body with l3 = (1−s)·L and I3 = m3·s·(1−s)·L², so both fidelities share one code path
//! ([`Rod::lumped`], [`Rod::rigid`]).

use crate::geom::{cross, P2};

/// How the slider's position is computed.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Kinematics {
    /// x = R cos φ + sqrt(L² − (R sin φ − e)²), differentiated exactly.
    Exact,
    /// The textbook truncation x'' ≈ −R(cos φ + λ cos 2φ) (in-line slider only), applied
    /// consistently: the rod is its two point masses m3(1 − l3/L) at A and m3·l3/L at B plus
    /// the correction couple of its remaining inertia ΔI = I3 − m3 l3 (L − l3), whose angle is
    /// the series to the same order, ψ ≈ −λ sin φ (so ψ' = −λ cos φ, ψ'' = λ sin φ). A lumped
    /// rod (ΔI = 0) then has exactly zero shaking moment and the torque m_ct x'x''.
    TwoHarmonic,
    /// "Obliquity neglected", the textbooks' primary-only model (in-line slider only): the
    /// rod stays parallel to the slider axis, x = R cos φ + L, x'' = −R cos φ, ψ ≡ 0 — the
    /// two-harmonic series at λ = 0, so the rod is again its two point masses plus ΔI, and
    /// ΔI enters nothing (ψ' = ψ'' = 0). Every force, torque and moment is independent of L:
    /// the rod length may be left out of the file.
    Primary,
}

/// The crank's own mass (a point mass at the centroid on the crank line).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Crank {
    /// m2 (kg).
    pub mass: f64,
    /// r2, distance of the crank's centre of mass from O along OA (m); R/2 for a uniform bar.
    pub centroid: f64,
}

/// The connecting rod as a rigid body.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Rod {
    /// m3 (kg).
    pub mass: f64,
    /// l3, distance of G3 from the crank pin A (m).
    pub centroid: f64,
    /// I3, moment of inertia about G3 (kg·m²).
    pub inertia: f64,
}

impl Rod {
    /// Two point masses: `split`·m3 at the crank pin A, the rest at the slider B
    /// (l3 = (1 − s)L, I3 = m3 s (1 − s) L²).
    pub fn lumped(mass: f64, split: f64, length: f64) -> Self {
        Rod {
            mass,
            centroid: (1.0 - split) * length,
            inertia: mass * split * (1.0 - split) * length * length,
        }
    }
    /// A rigid rod; `None` for the centroid or inertia means a uniform bar (L/2, m3 L²/12).
    pub fn rigid(mass: f64, length: f64, centroid: Option<f64>, inertia: Option<f64>) -> Self {
        Rod {
            mass,
            centroid: centroid.unwrap_or(0.5 * length),
            inertia: inertia.unwrap_or(mass * length * length / 12.0),
        }
    }
}

/// A slider-crank mechanism.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SliderCrank {
    /// R, crank radius (m).
    pub r: f64,
    /// L, rod length (m).
    pub l: f64,
    /// e, slider offset: the slider runs on y = e (m).
    pub e: f64,
    /// Kinematic model.
    pub kinematics: Kinematics,
    /// Crank.
    pub crank: Crank,
    /// Connecting rod.
    pub rod: Rod,
    /// m4, slider (piston) mass (kg).
    pub slider_mass: f64,
}

/// Positions and their first two φ-derivatives at one crank angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// Crank angle φ (rad).
    pub phi: f64,
    /// (cos φ, sin φ).
    pub cs: [f64; 2],
    /// Crank pin A, A', A''.
    pub a: [P2; 3],
    /// Slider position x, x', x'' along the slider line.
    pub x: [f64; 3],
    /// ψ' and ψ'' of the rod angle ψ (from A to B); ψ itself is [`State::psi`].
    pub dpsi: [f64; 2],
    /// σ = R sin φ − e and k = L cos ψ, kept for [`State::psi`].
    pub sigma_k: [f64; 2],
    /// Rod centre of mass G3, G3', G3''.
    pub g3: [P2; 3],
}

/// The loop closure at one crank angle ([`SliderCrank::close`]).
#[derive(Debug, Clone, Copy)]
struct Loop {
    s: f64,
    c: f64,
    sigma: f64,
    k: f64,
    k2: f64,
}

impl State {
    /// Rod angle ψ = atan2(−σ, k) (rad), from A towards B.
    pub fn psi(&self) -> f64 {
        (-self.sigma_k[0]).atan2(self.sigma_k[1])
    }
}

impl SliderCrank {
    /// λ = R/L.
    pub fn lambda(&self) -> f64 {
        self.r / self.l
    }

    /// The λ of the series kinematics: R/L for the two-harmonic series, 0 with the obliquity
    /// neglected (0 too for exact kinematics, which use no series).
    pub fn series_lambda(&self) -> f64 {
        match self.kinematics {
            Kinematics::TwoHarmonic => self.lambda(),
            Kinematics::Primary | Kinematics::Exact => 0.0,
        }
    }

    /// The largest (R + |e|)/L: below 1 the crank turns a full revolution.
    pub fn assembly_ratio(&self) -> f64 {
        (self.r + self.e.abs()) / self.l
    }

    /// Rotating mass equivalent at the crank pin, m_tq = m2 r2/R + m3 (1 − l3/L).
    pub fn m_rot(&self) -> f64 {
        self.crank.mass * self.crank.centroid / self.r
            + self.rod.mass * (1.0 - self.rod.centroid / self.l)
    }

    /// Reciprocating mass equivalent at the slider, m_ct = m4 + m3 l3/L.
    pub fn m_rec(&self) -> f64 {
        self.slider_mass + self.rod.mass * self.rod.centroid / self.l
    }

    /// Whether [`SliderCrank::state`] is the same function of φ for `other`: the same R, L,
    /// e, kinematic model and rod centroid l3 (the masses and inertias do not enter it).
    pub fn same_kinematics(&self, other: &SliderCrank) -> bool {
        let key = |m: &SliderCrank| {
            (
                [m.r, m.l, m.e, m.rod.centroid].map(f64::to_bits),
                m.kinematics,
            )
        };
        key(self) == key(other)
    }

    /// Kinematic state at φ, or `None` where the rod cannot reach the slider line
    /// (|R sin φ − e| ≥ L).
    ///
    /// With σ = R sin φ − e and k = sqrt((L − σ)(L + σ)) = L cos ψ:
    /// x = R cos φ + k, x' = −R sin φ − σ R cos φ / k,
    /// x'' = −R cos φ − (R² cos²φ − σ R sin φ)/k − σ² R² cos²φ / k³,
    /// ψ = atan2(−σ, k), ψ' = −R cos φ / k, ψ'' = R sin φ / k − σ R² cos²φ / k³.
    pub fn state(&self, phi: f64) -> Option<State> {
        let lp = self.close(phi)?;
        let Loop { s, c, sigma, k, k2 } = lp;
        let r = self.r;
        let rc = r * c;
        let dpsi = match self.kinematics {
            Kinematics::Exact => [-rc / k, r * s / k - sigma * rc * rc / (k * k2)],
            Kinematics::TwoHarmonic | Kinematics::Primary => {
                let lam = self.series_lambda();
                [-lam * c, lam * s]
            }
        };
        let x2 = self.slider_acc(phi, &lp);
        let x = match self.kinematics {
            Kinematics::Exact => [rc + k, -r * s - sigma * rc / k, x2],
            Kinematics::TwoHarmonic | Kinematics::Primary => {
                let lam = self.series_lambda();
                let (s2, c2) = (2.0 * phi).sin_cos();
                [
                    r * (c + 0.25 * lam * c2) + self.l - 0.25 * r * lam,
                    -r * (s + 0.5 * lam * s2),
                    x2,
                ]
            }
        };
        let a = [
            P2::new(rc, r * s),
            P2::new(-r * s, rc),
            P2::new(-rc, -r * s),
        ];
        let g3 = [
            self.rod_centroid(a[0], P2::new(x[0], self.e)),
            self.rod_centroid(a[1], P2::new(x[1], 0.0)),
            self.rod_centroid(a[2], P2::new(x[2], 0.0)),
        ];
        Some(State {
            phi,
            cs: [c, s],
            a,
            x,
            dpsi,
            sigma_k: [sigma, k],
            g3,
        })
    }

    /// The loop closure at φ: sin φ, cos φ, σ = R sin φ − e, k² = (L − σ)(L + σ) and
    /// k = L cos ψ; `None` where the rod cannot reach the slider line (k² ≤ 0).
    fn close(&self, phi: f64) -> Option<Loop> {
        let lp = self.close_unchecked(phi);
        (lp.k2 > 0.0).then_some(lp)
    }

    /// [`Self::close`] without the check (k is NaN where k² < 0): a caller that checks
    /// k² > 0 only at its end keeps its arithmetic in one basic block, where the compiler
    /// fuses sin φ and cos φ into one `sincos` call (behind an early return it calls `sin`
    /// and `cos` apart, at twice the cost).
    fn close_unchecked(&self, phi: f64) -> Loop {
        let (s, c) = phi.sin_cos();
        let sigma = self.r * s - self.e;
        let k2 = (self.l - sigma) * (self.l + sigma);
        Loop {
            s,
            c,
            sigma,
            k: k2.sqrt(),
            k2,
        }
    }

    /// Slider acceleration x'' (per ω², m): exact,
    /// x'' = −R cos φ − (R² cos²φ − σ R sin φ)/k − σ² R² cos²φ / k³; two-harmonic,
    /// x'' = −R (cos φ + λ cos 2φ); obliquity neglected, x'' = −R cos φ.
    fn slider_acc(&self, phi: f64, lp: &Loop) -> f64 {
        let Loop { s, c, sigma, k, k2 } = *lp;
        let r = self.r;
        let rc = r * c;
        match self.kinematics {
            Kinematics::Exact => {
                -rc - (rc * rc - sigma * r * s) / k - sigma * sigma * rc * rc / (k * k2)
            }
            Kinematics::TwoHarmonic => -r * (c + self.lambda() * (2.0 * phi).cos()),
            Kinematics::Primary => -rc,
        }
    }

    /// A point of the rod's centroid from the crank pin's and the slider's:
    /// G3 = (1 − µ)A + µB with µ = l3/L (and so for the derivatives).
    fn rod_centroid(&self, a: P2, b: P2) -> P2 {
        let mu = self.rod.centroid / self.l;
        a * (1.0 - mu) + b * mu
    }

    /// Shaking force per ω² without counterweight (kg·m): the force the moving links exert
    /// on the frame, f₀ = −(m2 G2'' + m3 G3'' + m4 B''), with G2 = (r2/R)·A.
    pub fn shaking_force0(&self, st: &State) -> P2 {
        self.force0_of(st.a[2], st.g3[2], st.x[2])
    }

    /// The links' momentum per ω, negated (kg·m): p₀ = −(m2 G2' + m3 G3' + m4 B'). At real
    /// speed, with α = dω/dt, the shaking force is ω² f₀ + α p₀ (a_G = r_G″ ω² + r_G′ α).
    pub fn momentum0(&self, st: &State) -> P2 {
        self.force0_of(st.a[1], st.g3[1], st.x[1])
    }

    /// f₀ from A'', G3'' and x'' ([`Self::shaking_force0`]).
    fn force0_of(&self, a2: P2, g3: P2, x2: f64) -> P2 {
        let g2 = a2 * (self.crank.centroid / self.r);
        -(g2 * self.crank.mass + g3 * self.rod.mass + P2::new(x2, 0.0) * self.slider_mass)
    }

    /// (cos φ, sin φ) and f₀(φ) ([`Self::shaking_force0`]) without the rest of the state —
    /// the same expressions on the same numbers, so bit for bit the same values, at about
    /// two thirds of the cost: the refinements of force peaks evaluate only this. `None`
    /// where [`Self::state`] is.
    pub fn shaking_force0_at(&self, phi: f64) -> Option<([f64; 2], P2)> {
        let lp = self.close_unchecked(phi);
        let (r, s, c) = (self.r, lp.s, lp.c);
        let rc = r * c;
        let x2 = self.slider_acc(phi, &lp);
        let a2 = P2::new(-rc, -r * s);
        let g3 = self.rod_centroid(a2, P2::new(x2, 0.0));
        let f0 = self.force0_of(a2, g3, x2);
        (lp.k2 > 0.0).then_some(([c, s], f0))
    }

    /// Amplitude of the shaking force's y component per ω² (kg·m) with the unbalance `u`
    /// (crank frame): every moving mass's y coordinate is proportional to sin φ (the crank
    /// pin R sin φ, G2 at r2 sin φ, G3 = (1 − µ)A + µB at (1 − µ)R sin φ + µe, the slider at
    /// e), in exact and in two-harmonic kinematics, so
    /// F_y/ω² = (m_tq R + U_x) sin φ + U_y cos φ, a pure first harmonic of amplitude
    /// |(m_tq R + U_x, U_y)|: max F_y = −min F_y = ω² times this, at
    /// φ = atan2(m_tq R + U_x, U_y) and half a turn on. Balancers add no y force.
    pub fn force_y_amplitude(&self, u: P2) -> f64 {
        let mu = self.rod.centroid / self.l;
        let s = self.crank.mass * self.crank.centroid + self.rod.mass * (1.0 - mu) * self.r;
        (s + u.x).hypot(u.y)
    }

    /// Drive torque per ω² at constant speed without gravity or load (kg·m²):
    /// T/ω² = dE_kin/dφ / ω² = m3 G3'·G3'' + I3 ψ'ψ'' + m4 x'x''. The crank and any
    /// counterweight turn uniformly and contribute nothing.
    ///
    /// Two-harmonic kinematics: the rod as two point masses plus the couple ΔI ψ'ψ''
    /// (see [`Kinematics::TwoHarmonic`]): T/ω² = m_ct x'x'' + ΔI ψ'ψ'' (A'·A'' = 0 on the
    /// crank circle).
    pub fn drive_torque0(&self, st: &State) -> f64 {
        match self.kinematics {
            Kinematics::Exact => {
                self.rod.mass * st.g3[1].dot(&st.g3[2])
                    + self.rod.inertia * st.dpsi[0] * st.dpsi[1]
                    + self.slider_mass * st.x[1] * st.x[2]
            }
            Kinematics::TwoHarmonic | Kinematics::Primary => {
                self.m_rec() * st.x[1] * st.x[2]
                    + self.rod_inertia_excess() * st.dpsi[0] * st.dpsi[1]
            }
        }
    }

    /// ΔI = I3 − m3 l3 (L − l3) (kg·m²): the rod's inertia about G3 beyond that of its two
    /// point masses at A and B; 0 for a lumped rod.
    pub fn rod_inertia_excess(&self) -> f64 {
        let l3 = self.rod.centroid;
        self.rod.inertia - self.rod.mass * l3 * (self.l - l3)
    }

    /// Shaking moment about O per ω² (kg·m²): the moment the moving links exert on the
    /// frame (motor stator included), −Σ(mᵢ rᵢ × rᵢ'' + Iᵢ θᵢ''). Crank and counterweight
    /// contribute nothing at constant speed.
    ///
    /// Two-harmonic kinematics (in-line, e = 0): the two point masses at A (on the crank
    /// circle at constant speed, A × A'' = 0) and B (on the line through O, B × B'' = 0)
    /// exert none, so M₀ = −ΔI ψ''.
    pub fn shaking_moment0(&self, st: &State) -> f64 {
        let b = P2::new(st.x[0], self.e);
        let b2 = P2::new(st.x[2], 0.0);
        match self.kinematics {
            Kinematics::Exact => {
                -(self.rod.mass * cross(st.g3[0], st.g3[2])
                    + self.rod.inertia * st.dpsi[1]
                    + self.slider_mass * cross(b, b2))
            }
            Kinematics::TwoHarmonic | Kinematics::Primary => {
                -(self.rod_inertia_excess() * st.dpsi[1] + self.m_rec() * cross(b, b2))
            }
        }
    }

    /// Kinetic energy per ω² (kg·m²) of the links without counterweight, used by tests of
    /// T = dE/dφ: ½(m2 |G2'|² + I2 + m3 |G3'|² + I3 ψ'² + m4 x'²) with the crank's own
    /// rotational energy omitted (it is constant).
    pub fn kinetic_energy0(&self, st: &State) -> f64 {
        let g2 = st.a[1] * (self.crank.centroid / self.r);
        let rod = match self.kinematics {
            Kinematics::Exact => {
                self.rod.mass * st.g3[1].norm_squared() + self.rod.inertia * st.dpsi[0] * st.dpsi[0]
            }
            // Two point masses (the one at A moves at constant speed) and ΔI.
            Kinematics::TwoHarmonic | Kinematics::Primary => {
                let mu = self.rod.centroid / self.l;
                self.rod.mass * ((1.0 - mu) * st.a[1].norm_squared() + mu * st.x[1] * st.x[1])
                    + self.rod_inertia_excess() * st.dpsi[0] * st.dpsi[0]
            }
        };
        0.5 * (self.crank.mass * g2.norm_squared() + rod + self.slider_mass * st.x[1] * st.x[1])
    }
}

/// A priori bounds, over every crank angle, on the kinematic quantities of
/// [`SliderCrank::state`] and on the round-off committed in computing them: the
/// conditioning part of every stated error (issue 14).
///
/// With a = R + |e| (the largest |σ|), the assembly margin d = L − a and
/// k_min = sqrt(d (L + a)), the computed k = sqrt((L − σ)(L + σ)) carries a relative error
/// ρ_k ≤ ε (2 + (L + 4a)/d): L − σ loses the digits that the margin d does not have. Then,
/// term by term of the formulas in [`SliderCrank::state`] (each a few roundings, k^−n
/// amplifying ρ_k n times):
/// |x''| ≤ X2 = R + R(R + a)/k_min + a²R²/k_min³,
/// δx'' ≤ 6ε X2 + ρ_k (R(R + a)/k_min + 3a²R²/k_min³), and likewise for x, x', ψ', ψ''.
/// Near toggle (d → 0) the bounds grow as d^−3/2 and the stated errors with them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoundOff {
    /// Bounds on |x|, |x'|, |x''| (m per rad^n).
    pub x: [f64; 3],
    /// Bounds on their round-off.
    pub dx: [f64; 3],
    /// Bounds on |ψ'|, |ψ''|.
    pub psi: [f64; 2],
    /// Bounds on their round-off.
    pub dpsi: [f64; 2],
    /// ρ_k, the relative round-off of k (0 for two-harmonic kinematics).
    pub rho_k: f64,
}

impl SliderCrank {
    /// [`RoundOff`] of this mechanism (it must assemble: R + |e| < L).
    pub fn round_off(&self) -> RoundOff {
        let eps = f64::EPSILON;
        let (r, l) = (self.r, self.l);
        match self.kinematics {
            Kinematics::Exact => {
                let a = r + self.e.abs();
                let d = l - a;
                let kmin = (d * (l + a)).sqrt();
                let rho = eps * (2.0 + (l + 4.0 * a) / d);
                let t2 = r * (r + a) / kmin;
                let t3 = a * a * r * r / (kmin * kmin * kmin);
                let x1 = r + a * r / kmin;
                let p1 = r / kmin;
                let p2 = r / kmin + a * r * r / (kmin * kmin * kmin);
                RoundOff {
                    x: [r + l, x1, r + t2 + t3],
                    dx: [
                        3.0 * eps * (r + l) + rho * l,
                        4.0 * eps * x1 + rho * a * r / kmin,
                        6.0 * eps * (r + t2 + t3) + rho * (t2 + 3.0 * t3),
                    ],
                    psi: [p1, p2],
                    dpsi: [
                        3.0 * eps * p1 + rho * p1,
                        5.0 * eps * p2 + rho * (r / kmin + 3.0 * a * r * r / (kmin * kmin * kmin)),
                    ],
                    rho_k: rho,
                }
            }
            Kinematics::TwoHarmonic | Kinematics::Primary => {
                let lam = self.series_lambda();
                let xb = r * (1.0 + lam);
                RoundOff {
                    x: [r + l + xb, xb, xb],
                    dx: [8.0 * eps * (r + l + xb), 6.0 * eps * xb, 6.0 * eps * xb],
                    psi: [lam, lam],
                    dpsi: [3.0 * eps * lam, 3.0 * eps * lam],
                    rho_k: 0.0,
                }
            }
        }
    }
}

/// A force on the slider along its axis (+x, away from the crank axis), as a function of
/// the crank angle: the gas or process load.
#[derive(Debug, Clone, PartialEq, serde::Serialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ProcessForce {
    /// No process force.
    #[default]
    None,
    /// A constant force (N).
    Constant(f64),
    /// A periodic table: crank angles (rad, increasing, within one turn) and forces (N),
    /// linearly interpolated, wrapping from the last angle to the first + 2π.
    Table {
        /// Crank angles (rad).
        angles: Vec<f64>,
        /// Forces (N).
        forces: Vec<f64>,
    },
}

impl ProcessForce {
    /// max over φ of |F_p| (N).
    pub fn max_abs(&self) -> f64 {
        match self {
            ProcessForce::None => 0.0,
            ProcessForce::Constant(f) => f.abs(),
            ProcessForce::Table { forces, .. } => forces.iter().fold(0.0, |a, f| a.max(f.abs())),
        }
    }

    /// The force at φ (N).
    pub fn at(&self, phi: f64) -> f64 {
        match self {
            ProcessForce::None => 0.0,
            ProcessForce::Constant(f) => *f,
            ProcessForce::Table { angles, forces } => {
                let n = angles.len();
                if n == 0 {
                    return 0.0;
                }
                if n == 1 {
                    return forces[0];
                }
                let t = (phi - angles[0]).rem_euclid(std::f64::consts::TAU) + angles[0];
                // The segment [angles[k], angles[k+1]] holding t, or the wrap segment.
                let k = angles.partition_point(|&a| a <= t).saturating_sub(1);
                let (a0, f0) = (angles[k], forces[k]);
                let (a1, f1) = if k + 1 < n {
                    (angles[k + 1], forces[k + 1])
                } else {
                    (angles[0] + std::f64::consts::TAU, forces[0])
                };
                if a1 > a0 {
                    f0 + (f1 - f0) * (t - a0) / (a1 - a0)
                } else {
                    f0
                }
            }
        }
    }
}

/// External loads on the mechanism: gravity and a process force on the slider.
#[derive(Debug, Clone, PartialEq, serde::Serialize, Default)]
pub struct Loads {
    /// Gravitational acceleration in the mechanism frame (x along the slider axis, from the
    /// crank axis towards the slider), m/s²; zero when gravity is not modelled.
    pub gravity: P2,
    /// Force on the slider along +x.
    pub process: ProcessForce,
}

impl Loads {
    /// Gravity of magnitude `g` for a slider axis at `axis_angle` above the horizontal
    /// (90°: slider above the crank, −90°: below, 0: horizontal), in the mechanism frame:
    /// g_m = (−g sin α, −g cos α).
    pub fn gravity_for_axis(g: f64, axis_angle: f64) -> P2 {
        P2::new(-g * axis_angle.sin(), -g * axis_angle.cos())
    }
}

impl SliderCrank {
    /// Torque (N·m) of the weights and the process force at constant speed, the part of
    /// T = d(E_kin + E_pot)/dφ − F_p x' that is not inertial: −Σ mᵢ g·rᵢ' − F_p(φ) x'
    /// (without counterweight; see [`counterweight_weight_torque`]).
    pub fn load_torque0(&self, st: &State, loads: &Loads) -> f64 {
        let g = loads.gravity;
        let g2 = st.a[1] * (self.crank.centroid / self.r);
        let weights = self.crank.mass * g.dot(&g2)
            + self.rod.mass * g.dot(&st.g3[1])
            + self.slider_mass * g.x * st.x[1];
        -weights - loads.process.at(st.phi) * st.x[1]
    }

    /// Weight of all links (N, magnitude |g|·Σm), the static load on the frame.
    pub fn link_weight(&self, loads: &Loads) -> f64 {
        loads.gravity.norm() * (self.crank.mass + self.rod.mass + self.slider_mass)
    }
}

/// Torque (N·m) of a counterweight's weight: its potential energy is −g·Rot(φ)U, so
/// T_cw = −g·Rot'(φ)U = −g·Rot(φ + π/2)U. Its inertia adds nothing at constant speed.
pub fn counterweight_weight_torque(phi: f64, gravity: P2, u: P2) -> f64 {
    let (s, c) = phi.sin_cos();
    weight_torque_cs([c, s], gravity, u)
}

/// [`counterweight_weight_torque`] from `cs` = (cos φ, sin φ): −g·Rot'(φ)U with
/// Rot'(φ)U = (−sin φ·U_x − cos φ·U_y, cos φ·U_x − sin φ·U_y).
pub fn weight_torque_cs(cs: [f64; 2], gravity: P2, u: P2) -> f64 {
    let [c, s] = cs;
    -gravity.dot(&P2::new(-s * u.x - c * u.y, c * u.x - s * u.y))
}

/// Rotation of the crank-fixed vector `u` to crank angle φ: Rot(φ)·u.
pub use crate::geom::rot;

/// [`rot`] from `cs` = (cos φ, sin φ) already computed (e.g. [`State::cs`]).
pub fn rot_cs(cs: [f64; 2], u: P2) -> P2 {
    let [c, s] = cs;
    P2::new(c * u.x - s * u.y, s * u.x + c * u.y)
}

/// A Lanchester balancer: a pair of shafts turning at n·ω in opposite senses, each carrying
/// half of the pair's unbalance B_n (kg·m). With the two eccentric masses symmetric about a
/// line parallel to the slider axis their forces across the axis cancel and the pair exerts on
/// the frame, per ω²,
///
/// F_n/ω² = n²·Re(B_n e^{inφ}) e_x = n²(B_c cos nφ − B_s sin nφ) e_x = n²|B_n| cos(nφ + arg B_n) e_x,
///
/// with B_n = B_c + i·B_s the design (the phase of the pair at φ = 0). The force acts on the
/// line y = `offset` (the pair's mid-line, in the mechanism frame: the crank axis at the
/// origin, x along the slider axis), so its moment about O is M_n = −offset·F_n,x: a pair on
/// the line through O (offset 0) adds no shaking moment. Turning uniformly, the shafts need no
/// drive torque except, with gravity, that of their weights: the pair's first moment is
/// Re(B_n e^{inφ}) e_x, so T_n = −g·d/dφ(Re(B_n e^{inφ}) e_x) = g_x·n·(B_c sin nφ + B_s cos nφ).
/// Every figure is linear in (B_c, B_s); the functions return the two coefficients.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BalancerPair {
    /// n, the order: the shafts turn at n·ω.
    pub order: u32,
    /// The y coordinate of the pair's mid-line (m).
    pub offset: f64,
}

impl BalancerPair {
    /// F_n,x/ω² = c·(B_c, B_s) (kg·m per kg·m): c = n²(cos nφ, −sin nφ).
    pub fn force_coeffs(&self, phi: f64) -> [f64; 2] {
        let n = self.order as f64;
        let (s, c) = (n * phi).sin_cos();
        [n * n * c, -n * n * s]
    }
    /// M_n/ω² about O = −offset·F_n,x/ω² (m per …).
    pub fn moment_coeffs(&self, phi: f64) -> [f64; 2] {
        let [a, b] = self.force_coeffs(phi);
        [-self.offset * a, -self.offset * b]
    }
    /// T_n (N·m per kg·m) of the weights for gravity `g` (mechanism frame): g_x·n·(sin nφ, cos nφ).
    pub fn weight_torque_coeffs(&self, phi: f64, g: P2) -> [f64; 2] {
        let n = self.order as f64;
        let (s, c) = (n * phi).sin_cos();
        [g.x * n * s, g.x * n * c]
    }
}

/// The forces in the joints of the slider-crank at one crank angle (N), from Newton–Euler of
/// the three moving bodies at constant crank speed: F_ij is the force body i exerts on body j
/// (1 the frame, 2 the crank with its counterweight, 3 the rod, 4 the slider).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointLoads {
    /// F_12: the main bearing O on the crank.
    pub main: P2,
    /// F_23: the crank on the rod at the crank pin A.
    pub crank_pin: P2,
    /// F_43: the slider on the rod at the wrist pin B.
    pub wrist_pin: P2,
    /// N: the guide on the slider, across the slider axis (friction left out).
    pub guide: f64,
}

impl SliderCrank {
    /// [`JointLoads`] at the state `st`, speed ω, with the counterweight U (crank frame, kg·m)
    /// of mass `cw_mass` (its weight; 0 when unknown or without gravity). With
    /// a_B = ω²x'' e_x, a_G3 = ω²G3'', ψ̈ = ω²ψ'', the weights m·g and the process force F_p
    /// on the slider along +x:
    ///
    /// * slider, x: F_34,x = m4 a_B − F_p − m4 g_x, so F_43,x = −F_34,x;
    /// * rod, moment about G3: I3 ψ̈ = (A − G3) × F_23 + (B − G3) × F_43 with
    ///   F_23 = m3(a_G3 − g) − F_43, so, with B − A = (L cos ψ, −σ):
    ///   F_43,y = [I3 ψ̈ − (A − G3) × m3(a_G3 − g) + (B − A)_y F_43,x] / (B − A)_x;
    /// * slider, y: N = F_43,y − m4 g_y;
    /// * crank: F_12 = ω²(m2 (r2/R) A'' − Rot(φ)U) + F_23 − (m2 + m_cw) g.
    ///
    /// The main bearing load is affine in U; the pin loads and N do not depend on it.
    /// Two-harmonic kinematics uses its series accelerations on the exact geometry.
    pub fn joint_loads(
        &self,
        st: &State,
        omega: f64,
        loads: &Loads,
        u: P2,
        cw_mass: f64,
    ) -> JointLoads {
        self.joint_loads_at(st, omega, 0.0, loads, u, cw_mass)
    }

    /// [`Self::joint_loads`] at real speed, the crank at speed ω with angular acceleration α:
    /// every acceleration r″ω² + r′α (a_B = x″ω² + x′α, a_G3 = G3″ω² + G3′α,
    /// ψ̈ = ψ″ω² + ψ′α, the crank's m2 (r2/R)(A″ω² + A′α) and the counterweight's
    /// −Rot(φ)U ω² + Rot(φ + π/2)U α). At α = 0 it is the constant-speed load, bit for bit.
    pub fn joint_loads_at(
        &self,
        st: &State,
        omega: f64,
        alpha: f64,
        loads: &Loads,
        u: P2,
        cw_mass: f64,
    ) -> JointLoads {
        let w2 = omega * omega;
        let g = loads.gravity;
        let (m2, m3, m4) = (self.crank.mass, self.rod.mass, self.slider_mass);
        // (Each α term beside its ω² term, so that α = 0 adds exact zeros.)
        let f34x = m4 * w2 * st.x[2] + m4 * alpha * st.x[1] - loads.process.at(st.phi) - m4 * g.x;
        let f43x = -f34x;
        let a = st.a[0];
        let g3 = st.g3[0];
        let inert3 = (st.g3[2] * w2 + st.g3[1] * alpha - g) * m3;
        let [sigma, k] = st.sigma_k;
        let i3 = self.rod.inertia;
        let i3_psi2 = i3 * w2 * st.dpsi[1] + i3 * alpha * st.dpsi[0];
        let f43y = (i3_psi2 - cross(a - g3, inert3) - sigma * f43x) / k;
        let f43 = P2::new(f43x, f43y);
        let f23 = inert3 - f43;
        let [c, s] = st.cs;
        let k2 = m2 * self.crank.centroid / self.r;
        let crank =
            (st.a[2] * k2 - rot_cs(st.cs, u)) * w2 + (st.a[1] * k2 + rot_cs([-s, c], u)) * alpha;
        JointLoads {
            main: crank + f23 - g * (m2 + cw_mass),
            crank_pin: f23,
            wrist_pin: f43,
            guide: f43y - m4 * g.y,
        }
    }
}
