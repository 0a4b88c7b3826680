//! Several slider-cranks on one crankshaft (`shared/domain/multi-cylinder.md`): the shaking
//! force in the plane of motion and the couple about the two axes normal to the shaft, per
//! ω², the design's rotating unbalances (crank-web counterweights and balance shafts) as the
//! columns of an affine field, the harmonics of every order by FFT, and the textbook's
//! primary and secondary sums as forward- and backward-turning vectors.
//!
//! Conventions: the shaft is the z axis; the crank turns by φ (anticlockwise seen from +z);
//! throw i sits at ψᵢ = φ + αᵢ (its phase αᵢ), its cylinder axis points along
//! eᵢ = (cos γᵢ, sin γᵢ) (its bank angle γᵢ) in the plane z = zᵢ. Each cylinder is the
//! slider-crank family's mechanism ([`SliderCrank`]: exact, two-harmonic or primary
//! kinematics, lumped or rigid rod, offset) turned by γᵢ, at its own crank angle
//! θᵢ = φ + αᵢ − γᵢ, so one cylinder is exactly the slider-crank family's machine.
//!
//! Shaking force (what the links exert on the frame) per ω²: f(φ) = Σ Rot(γᵢ)·f₀ᵢ(θᵢ) (kg·m),
//! with f₀ the slider-crank's [`SliderCrank::shaking_force0`]. Couple about the point z₀ of
//! the shaft per ω²: m(φ) = Σ (zᵢ − z₀) ẑ × fᵢ = Σ (zᵢ − z₀)(−f_y,i, f_x,i) (kg·m²): its x
//! component pitches the frame, its y component yaws it. A rotating unbalance u (kg·m, in the
//! frame of a body turning at angle β) adds ω_b²·Rot(β)·u at its plane z: a crank-web
//! counterweight turns with the crank (β = φ), a balance shaft of order n at β = ±nφ.

use super::articulated::Articulated;
use crate::families::slider_crank::model::{Kinematics, SliderCrank};
use crate::geom::{rot, P2};
use rustfft::num_complex::Complex64;
use std::f64::consts::TAU;

/// One cylinder: a slider-crank with its throw's phase, its bank angle and its plane.
#[derive(Debug, Clone, PartialEq)]
pub struct Cylinder {
    /// αᵢ, the throw's angle at φ = 0 (rad).
    pub phase: f64,
    /// γᵢ, the direction of the cylinder axis (rad).
    pub bank: f64,
    /// zᵢ, the plane of the throw along the shaft (m).
    pub z: f64,
    /// The cylinder's mechanism in its own frame (slider on +x); for an articulated
    /// cylinder its rod is the articulated rod (length l, from the knuckle pin) and it has no
    /// throw of its own (crank mass 0).
    pub sc: SliderCrank,
    /// On a radial's throw: the articulated rod's knuckle pin on the master rod (`None`: the
    /// rod is on the crank pin).
    pub articulated: Option<Articulated>,
}

impl Cylinder {
    /// θᵢ = φ + αᵢ − γᵢ, the crank angle the cylinder's own slider-crank sees.
    pub fn theta(&self, phi: f64) -> f64 {
        phi + self.phase - self.bank
    }

    /// fᵢ(φ) = Rot(γᵢ)·f₀ᵢ(θᵢ), the cylinder's shaking force per ω² (kg·m); `None` where its
    /// slider-crank does not assemble.
    pub fn force0(&self, phi: f64) -> Option<P2> {
        if let Some(a) = &self.articulated {
            let sc = &self.sc;
            let masses = (sc.slider_mass, sc.rod.mass, sc.rod.centroid / sc.l);
            let theta = phi + self.phase - a.master_bank;
            return a.force0(sc.r, sc.l, self.bank, masses, theta);
        }
        let (_, f) = self.sc.shaking_force0_at(self.theta(phi))?;
        Some(rot(self.bank, f))
    }

    /// The cylinder's shaking moment about the shaft (roll) per ω² (kg·m²): the slider-crank's
    /// [`SliderCrank::shaking_moment0`] (the crank adds none at constant speed), or the
    /// articulated rod's and piston's ([`Articulated::roll0`]); `None` where it does not
    /// assemble.
    pub fn roll0(&self, phi: f64) -> Option<f64> {
        let sc = &self.sc;
        if let Some(a) = &self.articulated {
            let masses = (
                sc.slider_mass,
                sc.rod.mass,
                sc.rod.centroid / sc.l,
                sc.rod.inertia,
            );
            return a.roll0(
                sc.r,
                sc.l,
                self.bank,
                masses,
                phi + self.phase - a.master_bank,
            );
        }
        let st = sc.state(self.theta(phi))?;
        Some(sc.shaking_moment0(&st))
    }

    /// A bound on the round-off of [`Self::roll0`] (kg·m²): the force's bound
    /// ([`Self::force_error0`]) times twice the largest arm (R + L + r_k), plus the rod's
    /// inertia times twice the acceleration bound over its length for χ″.
    pub fn roll_error0(&self) -> f64 {
        let sc = &self.sc;
        let rk = self.articulated.map_or(0.0, |a| a.knuckle_radius);
        let acc = match &self.articulated {
            Some(a) => a.acc_error(sc.r, sc.l),
            None => sc.round_off().dx[2],
        };
        2.0 * self.force_error0() * (sc.r + sc.l + rk) + 2.0 * sc.rod.inertia * 2.0 * acc / sc.l
    }

    /// A bound on the round-off of [`Self::force0`] at any φ (kg·m): the slider-crank's bound
    /// on x″ ([`SliderCrank::round_off`]) times the moving mass, plus 8ε of its largest
    /// value; for an articulated cylinder 3·(m_p + m_rod) times [`Articulated::acc_error`]
    /// (the piston's s″ and the rod's G″ = K″ + µ(P″ − K″)).
    pub fn force_error0(&self) -> f64 {
        let sc = &self.sc;
        if let Some(a) = &self.articulated {
            return 3.0 * (sc.slider_mass + sc.rod.mass) * a.acc_error(sc.r, sc.l);
        }
        let ro = sc.round_off();
        let mass = sc.crank.mass + sc.rod.mass + sc.slider_mass;
        mass * (ro.dx[2] + 8.0 * f64::EPSILON * ro.x[2])
    }

    /// Does the cylinder assemble over the whole turn? A slider-crank: R + |e| < L; an
    /// articulated rod: R + r_k < l (its knuckle pin never farther from its axis than the
    /// rod reaches) and R < L.
    pub fn assembles(&self) -> bool {
        match &self.articulated {
            Some(a) => self.sc.r + a.knuckle_radius < self.sc.l && self.sc.r < a.master_rod,
            None => self.sc.assembly_ratio() < 1.0,
        }
    }
}

/// ẑ × f scaled by the arm z − z₀: the couple of a force f (in the plane z) about z₀.
pub fn couple_of(arm: f64, f: P2) -> P2 {
    P2::new(-arm * f.y, arm * f.x)
}

/// A rotating unbalance: a body turning at β = `sense`·`order`·φ carrying u at the plane z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rotor {
    /// n: 1 for the crank and a primary shaft, 2 for a secondary shaft.
    pub order: u32,
    /// +1 turning with the crank, −1 against it.
    pub sense: f64,
    /// z, its plane (m).
    pub z: f64,
}

impl Rotor {
    /// The crank itself (a crank-web counterweight at the plane z).
    pub fn crank(z: f64) -> Rotor {
        Rotor {
            order: 1,
            sense: 1.0,
            z,
        }
    }
    /// β(φ), the body's angle.
    pub fn angle(&self, phi: f64) -> f64 {
        self.sense * self.order as f64 * phi
    }
    /// n², its speed squared over the crank's.
    pub fn speed2(&self) -> f64 {
        let n = self.order as f64;
        n * n
    }
    /// The force per ω² of the unbalance u (kg·m): n²·Rot(β)·u.
    pub fn force0(&self, phi: f64, u: P2) -> P2 {
        rot(self.angle(phi), u) * self.speed2()
    }
}

/// The machine: its cylinders and the point z₀ the couples are taken about.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// The cylinders, in order along the shaft as the file lists them.
    pub cylinders: Vec<Cylinder>,
    /// z₀ (m).
    pub z0: f64,
}

/// The links' shaking force and couple per ω² at one angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shaking {
    /// f (kg·m).
    pub force: P2,
    /// m = (m_x, m_y) about z₀ (kg·m²).
    pub couple: P2,
}

impl Layout {
    /// The links' shaking force and couple per ω² at φ; `None` where a cylinder does not
    /// assemble.
    pub fn shaking0(&self, phi: f64) -> Option<Shaking> {
        let mut s = Shaking {
            force: P2::zeros(),
            couple: P2::zeros(),
        };
        for c in &self.cylinders {
            let f = c.force0(phi)?;
            s.force += f;
            s.couple += couple_of(c.z - self.z0, f);
        }
        Some(s)
    }

    /// The links' shaking moment about the shaft (roll) per ω² at φ (kg·m²).
    pub fn roll0(&self, phi: f64) -> Option<f64> {
        self.cylinders.iter().map(|c| c.roll0(phi)).sum()
    }

    /// Does every cylinder assemble over the whole turn ([`Cylinder::assembles`])?
    pub fn assembles(&self) -> bool {
        self.cylinders.iter().all(Cylinder::assembles)
    }

    /// The largest |fᵢ| scale Σ (m_rot + m_rec)·R over the cylinders (kg·m): a size for
    /// round-off bounds.
    pub fn scale(&self) -> f64 {
        self.cylinders
            .iter()
            .map(|c| (c.sc.m_rot() + c.sc.m_rec()) * c.sc.r)
            .sum()
    }

    /// The largest |zᵢ − z₀| (m).
    pub fn arm(&self) -> f64 {
        self.cylinders
            .iter()
            .map(|c| (c.z - self.z0).abs())
            .fold(0.0, f64::max)
    }
}

/// A complex signal's harmonics: the forward (e^{+inφ}) and backward (e^{−inφ}) coefficient
/// of each order n = 1..=`orders`, of a planar vector written as x + iy.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Harmonic {
    /// n.
    pub order: u32,
    /// The forward-turning vector's coefficient c₊ₙ (x + iy, the signal's units): it turns
    /// with the crank at nω, from the angle arg c₊ₙ at φ = 0.
    pub forward: [f64; 2],
    /// The backward-turning vector's c₋ₙ: it turns against the crank at nω.
    pub backward: [f64; 2],
}

impl Harmonic {
    /// |c₊ₙ|.
    pub fn forward_amplitude(&self) -> f64 {
        self.forward[0].hypot(self.forward[1])
    }
    /// |c₋ₙ|.
    pub fn backward_amplitude(&self) -> f64 {
        self.backward[0].hypot(self.backward[1])
    }
    /// The largest magnitude of the order's vector over a turn, |c₊ₙ| + |c₋ₙ| (an ellipse
    /// whose half-axes are the sum and the difference).
    pub fn peak(&self) -> f64 {
        self.forward_amplitude() + self.backward_amplitude()
    }
}

/// The forward and backward coefficients of orders 1..=`orders` of the periodic planar
/// signal whose N samples (N a power of two ≥ 2·orders + 2) at φ_k = 2πk/N are `z`, by FFT
/// (rustfft): c_k = (1/N) Σ z_j e^{−2πijk/N}, c₊ₙ = c_n, c₋ₙ = c_{N−n}. Aliasing adds the
/// coefficients of orders n ± N, N − n, …: a smooth machine's decay geometrically (λⁿ for
/// exact kinematics), and [`alias_bound`] bounds them from the top of the spectrum.
pub fn harmonics(z: &[Complex64], orders: u32) -> Vec<Harmonic> {
    let n = z.len();
    let mut buf = z.to_vec();
    rustfft::FftPlanner::new()
        .plan_fft_forward(n)
        .process(&mut buf);
    let scale = 1.0 / n as f64;
    (1..=orders as usize)
        .map(|k| Harmonic {
            order: k as u32,
            forward: [buf[k].re * scale, buf[k].im * scale],
            backward: [buf[n - k].re * scale, buf[n - k].im * scale],
        })
        .collect()
}

/// A bound on the aliasing and round-off of [`harmonics`] from the same samples: the largest
/// coefficient in the top half of the spectrum (orders above N/4, which a smooth machine's
/// geometric decay makes an upper bound of everything folded back), times 4, plus the FFT's
/// round-off, 5·log₂N·ε·max|z|.
pub fn alias_bound(z: &[Complex64]) -> f64 {
    let n = z.len();
    let mut buf = z.to_vec();
    rustfft::FftPlanner::new()
        .plan_fft_forward(n)
        .process(&mut buf);
    let top = (n / 4..=3 * n / 4)
        .map(|k| buf[k].norm() / n as f64)
        .fold(0.0, f64::max);
    let zmax = z.iter().map(|v| v.norm()).fold(0.0, f64::max);
    4.0 * top + 5.0 * (n as f64).log2() * f64::EPSILON * zmax
}

/// N samples of a planar function of φ as complex numbers x + iy at φ_k = 2πk/N.
pub fn samples(n: usize, f: impl Fn(f64) -> P2) -> Vec<Complex64> {
    (0..n)
        .map(|k| {
            let v = f(TAU * k as f64 / n as f64);
            Complex64::new(v.x, v.y)
        })
        .collect()
}

/// The textbook's sums (two-harmonic model, lumped masses, in-line cylinders; λ = R/L, 0 for
/// the primary-only model, whatever the layout's own kinematics): the forward
/// and backward vectors of the primary (n = 1) and secondary (n = 2) force and couple per ω²,
/// as complex numbers x + iy at φ = 0 — `shared/domain/multi-cylinder.md`. A reciprocating
/// m_rec with x'' = −R(cos θ + λ cos 2θ) along eᵢ gives
/// * primary: ½m_rec R [e^{iαᵢ} e^{iφ} + e^{i(2γᵢ−αᵢ)} e^{−iφ}], plus the rotating
///   m_rot R e^{iαᵢ} e^{iφ} (forward only);
/// * secondary: ½m_rec R λ [e^{i(2αᵢ−γᵢ)} e^{2iφ} + e^{i(3γᵢ−2αᵢ)} e^{−2iφ}];
///
/// and the couple about z₀ is the same sum weighted by (zᵢ − z₀) and turned by ẑ×, i.e.
/// multiplied by i.
pub fn textbook(layout: &Layout) -> [Harmonic; 4] {
    let mut out = [0, 1, 2, 3].map(|k| Harmonic {
        order: if k % 2 == 0 { 1 } else { 2 },
        forward: [0.0; 2],
        backward: [0.0; 2],
    });
    let add = |h: &mut Harmonic, fwd: Complex64, bwd: Complex64| {
        h.forward[0] += fwd.re;
        h.forward[1] += fwd.im;
        h.backward[0] += bwd.re;
        h.backward[1] += bwd.im;
    };
    let e = |a: f64| Complex64::from_polar(1.0, a);
    for c in &layout.cylinders {
        let lam = match c.sc.kinematics {
            Kinematics::Primary => 0.0,
            Kinematics::Exact | Kinematics::TwoHarmonic => c.sc.lambda(),
        };
        let r = c.sc.r;
        let (a, g) = (c.phase, c.bank);
        let (rec, rotm) = (c.sc.m_rec() * r, c.sc.m_rot() * r);
        let p_f = e(a) * (0.5 * rec + rotm);
        let p_b = e(2.0 * g - a) * (0.5 * rec);
        let s_f = e(2.0 * a - g) * (0.5 * rec * lam);
        let s_b = e(3.0 * g - 2.0 * a) * (0.5 * rec * lam);
        let arm = Complex64::new(0.0, c.z - layout.z0);
        add(&mut out[0], p_f, p_b);
        add(&mut out[1], s_f, s_b);
        add(&mut out[2], p_f * arm, p_b * arm);
        add(&mut out[3], s_f * arm, s_b * arm);
    }
    out
}

/// The magnitude and direction of a complex coefficient, for tables: (|c|, arg c).
pub fn polar(c: [f64; 2]) -> (f64, f64) {
    (c[0].hypot(c[1]), c[1].atan2(c[0]))
}
