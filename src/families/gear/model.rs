//! Eccentric non-circular gear pair with cycloidal teeth (paper `001`, see
//! `shared/domain/eccentric-gear.md`).
//!
//! Exists because the pair's kinematics — the conjugate pitch curve, the closing centre
//! distance, the cycloidal contact point and the sliding coefficients µ1, µ2 with their
//! poles — are pure geometry of (R, e, r, a) that synthesis and reports both need.
//!
//! # Conventions (fixed frame)
//! O1 = (0, 0), O2 = (a, 0). Gear 1's pitch curve is a circle of radius R whose centre C
//! is at distance e from the pivot O1; α1 is the polar angle, in gear 1's own frame and
//! measured from the direction O1→C, of the pitch-curve point that is at the pitch point
//! P = (ρ1(α1), 0). Gear 1 turns clockwise (Ω1 = −ω1) so that α1 grows with time; gear 2
//! turns counter-clockwise with Ω2 = ω1 ρ1/ρ2. θ is the central angle (about C) of the same
//! point, so the arc length along gear 1's pitch curve is s = R θ and
//! θ = α1 − ψ, where ψ is the pitch-tangent obliquity (below).
//!
//! # Teeth
//! The pitch curve of gear 1 is cut into N = R/r arches of arc length 2πr (one turn of the
//! generating circle each), alternately epicycloid (even arch index i, σ = +1, addendum of
//! gear 1) and hypocycloid (odd i, σ = −1, dedendum). By Camus' theorem the contact point K
//! is the generating circle's tracing point while the circle touches both pitch curves at P:
//! with rolling angle ϕ = N(θ − 2πi/N) ∈ [0, 2π], pitch tangent T, outward normal n,
//!
//! K = P + r[σ n (1 − cos ϕ) − T sin ϕ] = P + 2r sin(ϕ/2) d,  d = σ n sin(ϕ/2) − T cos(ϕ/2),
//!
//! and d (a unit vector) is the common normal at K: it passes through P.

use crate::geom::{cross, P2};
use crate::numeric::{brent_root, SearchError};
use std::f64::consts::TAU;

mod mu_peak;
pub use mu_peak::{peak_mu, peak_mu_with, MuPeak};

/// Why a pair cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GearError {
    /// e ≥ R: the pivot is on or outside the pitch circle, the polar description ρ1(α1)
    /// fails (the pitch curve does not enclose its own pivot).
    #[error("eccentricity e = {e} m must be smaller than the pitch radius R = {r_pitch} m (the pivot must lie inside gear 1's pitch circle)")]
    PivotOutside { e: f64, r_pitch: f64 },
    /// A length or count is not finite / not positive.
    #[error("invalid gear data: {0}")]
    Invalid(String),
    /// The closure equation could not be solved.
    #[error("closure of gear 2 failed: {0}")]
    Closure(String),
}

/// Gear 1's pitch curve: a circle of radius R about a pivot at eccentricity e.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EccentricCircle {
    /// Pitch-circle radius R (m).
    pub r_pitch: f64,
    /// Eccentricity e (m), 0 ≤ e < R.
    pub e: f64,
}

impl EccentricCircle {
    /// Checked constructor: 0 ≤ e < R, both finite.
    pub fn new(r_pitch: f64, e: f64) -> Result<Self, GearError> {
        if !(r_pitch.is_finite() && r_pitch > 0.0) {
            return Err(GearError::Invalid(format!(
                "pitch radius R = {r_pitch} must be finite and > 0"
            )));
        }
        if !(e.is_finite() && e >= 0.0) {
            return Err(GearError::Invalid(format!(
                "eccentricity e = {e} must be finite and ≥ 0"
            )));
        }
        if e >= r_pitch {
            return Err(GearError::PivotOutside { e, r_pitch });
        }
        Ok(Self { r_pitch, e })
    }

    /// R cos ψ = sqrt(R² − e² sin² α1), in the factored form sqrt((R − e sin α1)(R + e sin α1))
    /// that keeps its digits when e → R and sin α1 → ±1.
    pub fn r_cos_psi(&self, alpha1: f64) -> f64 {
        let es = self.e * alpha1.sin();
        ((self.r_pitch - es) * (self.r_pitch + es)).sqrt()
    }

    /// Polar pitch radius ρ1(α1) = e cos α1 + sqrt(R² − e² sin² α1).
    ///
    /// For cos α1 < 0 the sum cancels (ρ1 → R − e when e → R); it is then evaluated as
    /// (R² − e²)/(sqrt(R² − e² sin² α1) − e cos α1), which has no cancellation.
    pub fn rho1(&self, alpha1: f64) -> f64 {
        let c = alpha1.cos();
        let root = self.r_cos_psi(alpha1);
        if c >= 0.0 {
            self.e * c + root
        } else {
            (self.r_pitch - self.e) * (self.r_pitch + self.e) / (root - self.e * c)
        }
    }

    /// dρ1/dα1 = −e sin α1 · ρ1/(R cos ψ).
    pub fn rho1_d1(&self, alpha1: f64) -> f64 {
        -self.e * alpha1.sin() * self.rho1(alpha1) / self.r_cos_psi(alpha1)
    }

    /// d²ρ1/dα1² = −e cos α1 − e² cos 2α1/S − e⁴ sin² α1 cos² α1/S³, S = R cos ψ.
    pub fn rho1_d2(&self, alpha1: f64) -> f64 {
        let (s, c) = alpha1.sin_cos();
        let q = self.r_cos_psi(alpha1);
        let e = self.e;
        -e * c - e * e * (c * c - s * s) / q - e.powi(4) * s * s * c * c / q.powi(3)
    }

    /// Pitch-tangent obliquity ψ(α1) = −asin(e sin α1 / R): the angle from the
    /// perpendicular to the line of centres to the pitch tangent, tan ψ = ρ1'/ρ1. It is also
    /// the pressure angle of a cycloidal contact at the pitch point. Returns (sin ψ, cos ψ).
    pub fn psi_sin_cos(&self, alpha1: f64) -> (f64, f64) {
        (
            -self.e * alpha1.sin() / self.r_pitch,
            self.r_cos_psi(alpha1) / self.r_pitch,
        )
    }

    /// Central angle θ about C of the pitch-curve point at polar angle α1:
    /// θ = α1 + asin(e sin α1 / R) = α1 − ψ (continuous, θ(0) = 0, θ(2π) = 2π).
    pub fn theta_of_alpha(&self, alpha1: f64) -> f64 {
        alpha1 + (self.e * alpha1.sin()).atan2(self.r_cos_psi(alpha1))
    }

    /// Inverse of [`Self::theta_of_alpha`]: α1 = θ − atan2(e sin θ, R + e cos θ).
    pub fn alpha_of_theta(&self, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        theta - (self.e * s).atan2(self.r_pitch + self.e * c)
    }

    /// Point of the pitch curve in gear 1's frame (origin O1, x towards C):
    /// ρ1(α1)(cos α1, sin α1).
    pub fn point(&self, alpha1: f64) -> P2 {
        let (s, c) = alpha1.sin_cos();
        P2::new(c, s) * self.rho1(alpha1)
    }
}

/// Trapezoid rule on `n` points of a 2π-periodic function, spectrally accurate when
/// smooth. Returns (∫f, ∫|f|) — the second scales the round-off floor.
fn trapezoid_periodic<F: Fn(f64) -> f64>(f: &F, n: usize) -> (f64, f64) {
    let h = TAU / n as f64;
    let (s, sa) = (0..n)
        .map(|k| f(k as f64 * h))
        .fold((0.0, 0.0), |(s, sa), y| (s + y, sa + y.abs()));
    (s * h, sa * h)
}

/// A converged periodic integral.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quadrature {
    /// The integral.
    pub value: f64,
    /// |I(n) − I(n/2)| plus the round-off floor 16ε∫|f|: an over-estimate of the error
    /// once converged.
    pub error: f64,
    /// Points of the last rule.
    pub n: usize,
}

/// ∫₀^{2π} f by the trapezoid rule, doubling n from 32 until two rules agree to `rtol`
/// (relative) or to the round-off floor 16ε∫|f|, or n reaches 2²⁰.
pub fn periodic_integral<F: Fn(f64) -> f64>(f: F, rtol: f64) -> Quadrature {
    let mut n = 32;
    let mut prev = trapezoid_periodic(&f, n / 2).0;
    loop {
        let (cur, abs) = trapezoid_periodic(&f, n);
        let floor = 16.0 * f64::EPSILON * abs;
        let err = (cur - prev).abs();
        if err <= rtol * cur.abs() + floor || n >= 1 << 20 || !cur.is_finite() {
            return Quadrature {
                value: cur,
                error: err + floor,
                n,
            };
        }
        prev = cur;
        n *= 2;
    }
}

/// Closure integral J(a) = ∫₀^{2π} ρ1/(a − ρ1) dα1, the turn of gear 2 per turn of gear 1.
/// Requires a > R + e.
pub fn closure_integral(c: &EccentricCircle, a: f64, rtol: f64) -> Quadrature {
    periodic_integral(
        |al| {
            let r1 = c.rho1(al);
            r1 / (a - r1)
        },
        rtol,
    )
}

/// The centre distance that closes gear 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Closure {
    /// Centre distance a (m).
    pub a: f64,
    /// Estimated absolute error of a (m): quadrature error / |dJ/da| plus the root tolerance.
    pub a_error: f64,
    /// Closure-integral evaluations spent by the root finder.
    pub evals: u64,
}

/// Solve J(a) = 2π n2/n1 for a (Brent on a bracket in (R + e, (R + e)(2 + n1/n2)]: J
/// decreases from +∞ at a = R + e to below the target at the upper end, where
/// J ≤ 2π/(1 + n1/n2)).
pub fn closing_center_distance(
    c: &EccentricCircle,
    n1: u32,
    n2: u32,
) -> Result<Closure, GearError> {
    if n1 == 0 || n2 == 0 {
        return Err(GearError::Invalid("turn counts n1, n2 must be ≥ 1".into()));
    }
    let ratio = n1 as f64 / n2 as f64;
    let target = TAU / ratio;
    let rmax = c.r_pitch + c.e;
    let hi = rmax * (2.0 + ratio);
    let count = std::cell::Cell::new(0u64);
    let f = |a: f64| {
        count.set(count.get() + 1);
        closure_integral(c, a, 1e-15).value - target
    };
    // Lower end: approach ρ1max geometrically until J exceeds the target (J → ∞ there);
    // close to ρ1max the integrand is nearly singular and costly, so start 1 % above it.
    let mut lo = rmax * (1.0 + 1e-2);
    while f(lo) <= 0.0 && lo - rmax > 1e-12 * rmax {
        lo = rmax + 0.1 * (lo - rmax);
    }
    let root =
        brent_root(f, lo, hi, 1e-15 * rmax).map_err(|e| GearError::Closure(e.to_string()))?;
    let a = root.x;
    let q = closure_integral(c, a, 1e-15);
    let dj = periodic_integral(
        |al| {
            let r1 = c.rho1(al);
            r1 / ((a - r1) * (a - r1))
        },
        1e-12,
    )
    .value;
    let a_error =
        (q.error + 4.0 * f64::EPSILON * q.value.abs()) / dj + 1e-15 * rmax + (root.fx.abs() / dj);
    Ok(Closure {
        a,
        a_error,
        evals: count.get(),
    })
}

/// Gear 2 angle α2(α1) = ∫₀^α1 ρ1/(a − ρ1) dα1, integrated from the trigonometric
/// interpolant of the integrand (spectrally accurate; the mean term is exact).
#[derive(Debug, Clone)]
pub struct Alpha2Map {
    mean: f64,
    a_k: Vec<f64>,
    b_k: Vec<f64>,
    /// Sum of |coefficients| of the upper half of the retained spectrum: a bound on the
    /// truncation error of α2 (rad).
    pub error: f64,
}

impl Alpha2Map {
    /// Build the map for the pair (c, a), doubling the number of samples (64 … 2¹⁶) until
    /// the largest coefficient of the upper half of the spectrum is below 4·10⁻¹⁵ of the
    /// integrand's maximum (the FFT's round-off floor); coefficients below 10⁻¹⁷ of it are
    /// dropped. The error bound is 2π × (sum of dropped and upper-half coefficients) plus
    /// the round-off of the mean term.
    pub fn new(c: &EccentricCircle, a: f64) -> Self {
        use rustfft::{num_complex::Complex, FftPlanner};
        let mut planner = FftPlanner::<f64>::new();
        let mut n = 64;
        loop {
            let h = TAU / n as f64;
            let mut fmax: f64 = 0.0;
            let mut buf: Vec<Complex<f64>> = (0..n)
                .map(|k| {
                    let r1 = c.rho1(k as f64 * h);
                    let f = r1 / (a - r1);
                    fmax = fmax.max(f.abs());
                    Complex::new(f, 0.0)
                })
                .collect();
            planner.plan_fft_forward(n).process(&mut buf);
            let mean = buf[0].re / n as f64;
            let kmax = n / 2 - 1;
            let mut a_k: Vec<f64> = (1..=kmax).map(|k| 2.0 * buf[k].re / n as f64).collect();
            let mut b_k: Vec<f64> = (1..=kmax).map(|k| -2.0 * buf[k].im / n as f64).collect();
            let upper = (kmax / 2..kmax)
                .map(|j| a_k[j].abs() + b_k[j].abs())
                .fold(0.0, f64::max);
            if upper <= 4e-15 * fmax || n >= 1 << 16 {
                let keep = (0..kmax)
                    .rev()
                    .find(|&j| a_k[j].abs() + b_k[j].abs() > 1e-17 * fmax)
                    .map_or(0, |j| j + 1);
                let dropped: f64 = (keep..kmax).map(|j| a_k[j].abs() + b_k[j].abs()).sum();
                a_k.truncate(keep);
                b_k.truncate(keep);
                let error = TAU * (dropped + upper * (kmax / 2) as f64) / (kmax / 2).max(1) as f64
                    + 4.0 * f64::EPSILON * TAU * mean.abs();
                return Self {
                    mean,
                    a_k,
                    b_k,
                    error,
                };
            }
            n *= 2;
        }
    }

    /// α2(α1) = J̄ α1 + Σ_k [A_k sin kα1 + B_k (1 − cos kα1)]/k.
    pub fn alpha2(&self, alpha1: f64) -> f64 {
        let mut acc = self.mean * alpha1;
        for (j, (ak, bk)) in self.a_k.iter().zip(&self.b_k).enumerate() {
            let k = (j + 1) as f64;
            let (s, c) = (k * alpha1).sin_cos();
            acc += (ak * s + bk * (1.0 - c)) / k;
        }
        acc
    }

    /// Turn of gear 2 per turn of gear 1 (2π J̄).
    pub fn per_turn(&self) -> f64 {
        self.mean * TAU
    }
}

/// One contact state at gear-1 angle α1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Arch index i (0 ≤ i < N) on gear 1; even = epicycloid (addendum), odd = hypocycloid.
    pub arch: usize,
    /// σ = +1 on an epicycloid arch, −1 on a hypocycloid arch.
    pub sigma: f64,
    /// Rolling angle ϕ ∈ [0, 2π] of the generating circle along the arch.
    pub phi: f64,
    /// Pitch point P (fixed frame).
    pub p: P2,
    /// Contact point K (fixed frame).
    pub k: P2,
    /// Unit common normal d at K (along P − K reversed: K = P + 2r sin(ϕ/2) d).
    pub d: P2,
    /// Velocity of K as a point of gear 1: Ω1 ẑ × (K − O1).
    pub v1: P2,
    /// Velocity of K as a point of gear 2: Ω2 ẑ × (K − O2).
    pub v2: P2,
    /// Components of v1, v2 along the common tangent τ = ẑ × d.
    pub vt1: f64,
    pub vt2: f64,
    /// Sliding velocity v_t1 − v_t2 = (Ω1 − Ω2)·2r sin(ϕ/2) (m/s), computed without
    /// cancellation.
    pub v_slide: f64,
    /// µ1 = (v_t1 − v_t2)/v_t1; `None` exactly at a pole or at the 0/0 point.
    pub mu1: Option<f64>,
    /// µ2 = (v_t2 − v_t1)/v_t2; `None` exactly at a pole or at the 0/0 point.
    pub mu2: Option<f64>,
    /// Pressure angle γ ∈ [0, π/2] between the common normal and the velocity of gear 2's
    /// point K: tan γ = |d·(K − O2)| / |(K − O2) × d|.
    pub pressure_angle: f64,
}

/// The generating circle rolled to one α1 ([`GearPair::rolling`]).
#[derive(Debug, Clone, Copy)]
struct Rolling {
    sigma: f64,
    phi: f64,
    r1: f64,
    r2: f64,
    d: P2,
    two_r_s: f64,
}

/// Tangential and sliding velocities and µ of a rolled state ([`GearPair::sliding`]).
#[derive(Debug, Clone, Copy)]
struct Sliding {
    /// −Ω1 and Ω2 = Ω1 ρ1/ρ2.
    om1: f64,
    om2: f64,
    vt1: f64,
    vt2: f64,
    v_slide: f64,
    mu1: Option<f64>,
    mu2: Option<f64>,
}

/// The assembled pair: gear 1, its generating circle and the centre distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearPair {
    /// Gear 1's pitch curve.
    pub c: EccentricCircle,
    /// Generating (rolling) circle radius r (m).
    pub r_gen: f64,
    /// Number of arches N = R/r on gear 1 (even; N/2 teeth).
    pub n_arches: usize,
    /// Centre distance a (m).
    pub a: f64,
    /// Driving speed ω1 (rad/s), > 0.
    pub omega1: f64,
}

impl GearPair {
    /// Checked constructor: N = R/r must be an even integer (to 1e-9 relative) so that the
    /// arches close around gear 1, a > R + e, ω1 > 0.
    pub fn new(c: EccentricCircle, r_gen: f64, a: f64, omega1: f64) -> Result<Self, GearError> {
        if !(r_gen.is_finite() && r_gen > 0.0) {
            return Err(GearError::Invalid(format!(
                "generating radius r = {r_gen} must be > 0"
            )));
        }
        let nf = c.r_pitch / r_gen;
        let n = nf.round();
        if (nf - n).abs() > 1e-9 * nf || n < 2.0 || !(n as usize).is_multiple_of(2) {
            return Err(GearError::Invalid(format!(
                "R/r = {nf} must be an even integer (2 × teeth of gear 1) for the cycloid arches to close"
            )));
        }
        if !(a.is_finite() && a > c.r_pitch + c.e) {
            return Err(GearError::Invalid(format!(
                "centre distance a = {a} must exceed R + e = {}",
                c.r_pitch + c.e
            )));
        }
        if !(omega1.is_finite() && omega1 > 0.0) {
            return Err(GearError::Invalid(format!("ω1 = {omega1} must be > 0")));
        }
        Ok(Self {
            c,
            r_gen,
            n_arches: n as usize,
            a,
            omega1,
        })
    }

    /// Speed ratio i12 = ω1/ω2 = (a − ρ1)/ρ1.
    pub fn i12(&self, alpha1: f64) -> f64 {
        let r1 = self.c.rho1(alpha1);
        (self.a - r1) / r1
    }

    /// (i12 min, i12 max) in closed form: ρ1 ranges over [R − e, R + e], so
    /// i12 ∈ [(a − R − e)/(R + e), (a − R + e)/(R − e)].
    pub fn ratio_range(&self) -> (f64, f64) {
        let (r, e, a) = (self.c.r_pitch, self.c.e, self.a);
        ((a - r - e) / (r + e), (a - r + e) / (r - e))
    }

    /// Signed curvature (1/m) of gear 2's pitch curve at the point meshing at α1, positive
    /// where convex. With ' = d/dα1, q = ρ2/ρ1 = dα1/dα2, ρ̇2 = −ρ1' q,
    /// ρ̈2 = −(ρ1'' q + ρ1' q') q, q' = −a ρ1'/ρ1²:
    /// κ2 = (ρ2² + 2ρ̇2² − ρ2 ρ̈2)/(ρ2² + ρ̇2²)^{3/2}.
    pub fn gear2_curvature(&self, alpha1: f64) -> f64 {
        let r1 = self.c.rho1(alpha1);
        let d1 = self.c.rho1_d1(alpha1);
        let d2 = self.c.rho1_d2(alpha1);
        let r2 = self.a - r1;
        let q = r2 / r1;
        let qp = -self.a * d1 / (r1 * r1);
        let r2d = -d1 * q;
        let r2dd = -(d2 * q + d1 * qp) * q;
        (r2 * r2 + 2.0 * r2d * r2d - r2 * r2dd) / (r2 * r2 + r2d * r2d).powf(1.5)
    }

    /// Arch index containing α1 ∈ [0, 2π) (by θ = α1 − ψ).
    pub fn arch_of(&self, alpha1: f64) -> usize {
        let th = self.c.theta_of_alpha(alpha1.rem_euclid(TAU));
        ((th / TAU * self.n_arches as f64).floor() as isize).clamp(0, self.n_arches as isize - 1)
            as usize
    }

    /// α1 at the start of arch i (a cusp, contact at the pitch point), closed form
    /// α_i = θ_i − atan2(e sin θ_i, R + e cos θ_i), θ_i = 2πi/N.
    ///
    /// dα/dθ = R/(R − e) at θ = π, so the rounding of θ_i would move the cusp by
    /// ε·π·R/(R − e) (4.6e-13 rad at e/R = 0.9997): θ_i is written as π − δ with
    /// δ = π(N − 2i)/N exact in its integer part, sin θ_i = sin δ and
    /// R + e cos θ_i = (R − e) + 2e sin²(δ/2), which have no cancellation; the ψ = 0 cusps
    /// (i = 0 and i = N/2) come out exactly at 0 and π.
    pub fn arch_start(&self, i: usize) -> f64 {
        let n = self.n_arches;
        let k = i / n;
        let j = i % n;
        let base = TAU * k as f64;
        if j == 0 {
            return base;
        }
        if 2 * j == n {
            return base + std::f64::consts::PI;
        }
        let (r, e) = (self.c.r_pitch, self.c.e);
        let m = n as isize - 2 * j as isize; // θ_i = π − δ, δ = πm/N
        let delta = std::f64::consts::PI * m as f64 / n as f64;
        let (sd, _) = delta.sin_cos();
        let sh = (0.5 * delta).sin();
        let theta = base + TAU * j as f64 / n as f64;
        theta - (e * sd).atan2((r - e) + 2.0 * e * sh * sh)
    }

    /// Whether the cusp at the start of arch i has ψ = 0 (sin α_i = 0, i.e. θ_i ∈ {0, π},
    /// or e = 0 where ψ ≡ 0): there a µ pole merges with the zero and µ is 0/0. Decided from
    /// the integers (i = 0 or 2i = N), not from a rounded ψ.
    pub fn cusp_is_indeterminate(&self, i: usize) -> bool {
        let j = i % self.n_arches;
        self.c.e == 0.0 || j == 0 || 2 * j == self.n_arches
    }

    /// Condition factor κ = R/(R − e) of the model near α1 = π: dα1/dθ there, and the
    /// relative rounding of R cos ψ = sqrt((R − e sin α)(R + e sin α)) near sin α = ±1 grows
    /// with it. Every round-off bound below is proportional to it.
    pub fn condition(&self) -> f64 {
        self.c.r_pitch / (self.c.r_pitch - self.c.e)
    }

    /// Bound on the shift (rad) of the point at which the model is effectively evaluated:
    /// θ(α1) and ϕ carry 4ε(|θ| + 2π) of rounding, which is a shift of α1 by that times
    /// dα1/dθ ≤ κ, times κ again for the rounding of R cos ψ: 4εκ²(|θ| + 2π).
    pub fn eval_shift(&self, alpha1: f64) -> f64 {
        let th = self.c.theta_of_alpha(alpha1).abs();
        4.0 * f64::EPSILON * self.condition().powi(2) * (th + TAU)
    }

    /// Bound on the rounding error (m) of the products in the pole function at a given
    /// evaluation point: f_j = ρ_j(σ cos ψ sin(ϕ/2) − sin ψ cos(ϕ/2)) + 2r sin(ϕ/2),
    /// ρ_j = ρ1 − a_j (a_1 = 0, a_2 = a), bounded by the sum of its terms' magnitudes,
    /// 16εκ(|ρ_j|(|cos ψ sin(ϕ/2)| + |sin ψ cos(ϕ/2)|) + 2r|sin(ϕ/2)|).
    pub fn pole_fn_product_roundoff(&self, alpha1: f64, arch: usize, which: Which) -> f64 {
        let ct = self.contact_on(alpha1, arch);
        let (sp, cp) = self.c.psi_sin_cos(alpha1);
        let (sh, ch) = (0.5 * ct.phi).sin_cos();
        let rho = match which {
            Which::Mu1 => ct.p.x,
            Which::Mu2 => ct.p.x - self.a,
        };
        16.0 * f64::EPSILON
            * self.condition()
            * (rho.abs() * ((cp * sh).abs() + (sp * ch).abs()) + 2.0 * self.r_gen * sh.abs())
    }

    /// Bound on the rounding error (m) of the pole functions (K − O_j)·d at α1 on arch i:
    /// 16ε·κ·(a + ρ1 + 2r + 2r·N·(|θ| + 2π)) — the rolling angle ϕ = N(θ − θ_i) carries
    /// N·ε·(|θ| + 2π), the contact point moves by 2r times that, and the rest is the
    /// rounding of the products, amplified by κ = [`Self::condition`].
    pub fn pole_fn_roundoff(&self, alpha1: f64) -> f64 {
        let th = self.c.theta_of_alpha(alpha1).abs();
        let nr = 2.0 * self.r_gen * self.n_arches as f64 * (th + TAU);
        16.0 * f64::EPSILON
            * self.condition()
            * (self.a + self.c.rho1(alpha1) + 2.0 * self.r_gen + nr)
    }

    /// Contact state at α1 on the arch containing it.
    pub fn contact(&self, alpha1: f64) -> Contact {
        self.contact_on(alpha1, self.arch_of(alpha1))
    }

    /// Contact state at α1 with the rolling angle measured on arch i (so that ϕ may be
    /// evaluated at both cusps of the arch, 0 and 2π).
    pub fn contact_on(&self, alpha1: f64, arch: usize) -> Contact {
        let rl = self.rolling(alpha1, arch);
        let Rolling {
            sigma, phi, r1, d, ..
        } = rl;
        let p = P2::new(r1, 0.0);
        let k = Self::contact_point(&rl);
        let Sliding {
            om1,
            om2,
            vt1,
            vt2,
            v_slide,
            mu1,
            mu2,
        } = self.sliding(&rl);
        let w1 = k;
        let w2 = k - P2::new(self.a, 0.0);
        let v1 = P2::new(-w1.y, w1.x) * om1;
        let v2 = P2::new(-w2.y, w2.x) * om2;
        let pressure_angle = w2.dot(&d).abs().atan2(cross(w2, d).abs());
        Contact {
            arch,
            sigma,
            phi,
            p,
            k,
            d,
            v1,
            v2,
            vt1,
            vt2,
            v_slide,
            mu1,
            mu2,
            pressure_angle,
        }
    }

    /// (µ1, µ2) at α1 on arch i, as [`Self::contact_on`] computes them (the same
    /// expressions, so the same bits) without the contact point's velocities and the
    /// pressure angle: what the peak search samples.
    pub fn mu_on(&self, alpha1: f64, arch: usize) -> (Option<f64>, Option<f64>) {
        let sl = self.sliding(&self.rolling(alpha1, arch));
        (sl.mu1, sl.mu2)
    }

    /// The generating circle rolled to α1 on arch i: σ, ϕ, ρ1, ρ2 = a − ρ1, the unit normal
    /// d = σ sin(ϕ/2)·n − cos(ϕ/2)·t (t, n the pitch tangent and normal) and 2r sin(ϕ/2).
    fn rolling(&self, alpha1: f64, arch: usize) -> Rolling {
        let c = &self.c;
        let sigma = if arch.is_multiple_of(2) { 1.0 } else { -1.0 };
        let phi = self.n_arches as f64
            * (c.theta_of_alpha(alpha1) - TAU * arch as f64 / self.n_arches as f64);
        let (sh, ch) = (0.5 * phi).sin_cos();
        let r1 = c.rho1(alpha1);
        let (sp, cp) = c.psi_sin_cos(alpha1);
        let t = P2::new(sp, cp);
        let n = P2::new(cp, -sp);
        Rolling {
            sigma,
            phi,
            r1,
            r2: self.a - r1,
            d: n * (sigma * sh) - t * ch,
            two_r_s: 2.0 * self.r_gen * sh,
        }
    }

    /// The contact point K = P + 2r sin(ϕ/2)·d of a rolled state, P = (ρ1, 0).
    fn contact_point(rl: &Rolling) -> P2 {
        P2::new(rl.r1, 0.0) + rl.d * rl.two_r_s
    }

    /// The tangential velocities and the sliding coefficients of a rolled state:
    /// v_t1 = Ω1' (ρ1 d_x + 2r sin(ϕ/2)), v_t2 = Ω2 (−ρ2 d_x + 2r sin(ϕ/2)) with Ω1' = −Ω1,
    /// Ω2 = Ω1 ρ1/ρ2, v_slide = (Ω1' − Ω2)·2r sin(ϕ/2), µ1 = v_slide/v_t1, µ2 = −v_slide/v_t2.
    fn sliding(&self, rl: &Rolling) -> Sliding {
        let om1 = -self.omega1;
        let om2 = self.omega1 * rl.r1 / rl.r2;
        let vt1 = om1 * (rl.r1 * rl.d.x + rl.two_r_s);
        let vt2 = om2 * (-rl.r2 * rl.d.x + rl.two_r_s);
        let v_slide = (om1 - om2) * rl.two_r_s;
        Sliding {
            om1,
            om2,
            vt1,
            vt2,
            v_slide,
            mu1: (vt1 != 0.0).then(|| v_slide / vt1),
            mu2: (vt2 != 0.0).then(|| -v_slide / vt2),
        }
    }

    /// v_t1/Ω1 = (K − O1)·d (m): zero exactly at the poles of µ1.
    pub fn pole_fn_mu1(&self, alpha1: f64, arch: usize) -> f64 {
        let rl = self.rolling(alpha1, arch);
        Self::contact_point(&rl).dot(&rl.d)
    }

    /// v_t2/Ω2 = (K − O2)·d (m): zero exactly at the poles of µ2.
    pub fn pole_fn_mu2(&self, alpha1: f64, arch: usize) -> f64 {
        let rl = self.rolling(alpha1, arch);
        (Self::contact_point(&rl) - P2::new(self.a, 0.0)).dot(&rl.d)
    }
}

/// Which sliding coefficient a pole belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Which {
    /// µ1 → ±∞ (v_t1 = 0: the common tangent passes through O1).
    Mu1,
    /// µ2 → ±∞ (v_t2 = 0: the common tangent passes through O2).
    Mu2,
}

/// A located pole of µ1 or µ2.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Pole {
    /// α1 of the pole (rad, in [0, 2π)).
    pub alpha1_rad: f64,
    /// "mu1" or "mu2".
    pub which: Which,
    /// Arch of gear 1 it lies on.
    pub arch: usize,
    /// Rolling angle ϕ there (rad).
    pub phi_rad: f64,
    /// Bound on the location error in α1 (rad).
    pub error_rad: f64,
}

/// Kind of a zero of µ (contact at the pitch point, at a cusp of the teeth).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ZeroKind {
    /// µ1 = µ2 = 0: K = P with v_t ≠ 0.
    PitchPoint,
    /// K = P and ψ = 0: the common tangent passes through both centres, µ is 0/0 (a pole
    /// merged with the zero); the one-sided limits differ.
    Indeterminate,
}

/// A zero of µ (a cusp of the tooth profile, contact at the pitch point).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Zero {
    /// α1 of the zero (rad), closed form α1 = θ_i − atan2(e sin θ_i, R + e cos θ_i).
    pub alpha1_rad: f64,
    /// Arch that starts here.
    pub arch: usize,
    /// What happens there.
    pub kind: ZeroKind,
}

/// All singular points over one turn of gear 1 (the pattern repeats every turn).
#[derive(Debug, Clone, PartialEq)]
pub struct Singularities {
    /// Poles, sorted by α1.
    pub poles: Vec<Pole>,
    /// Zeros (cusps), sorted by α1.
    pub zeros: Vec<Zero>,
    /// Evaluations of the contact model spent.
    pub evals: usize,
}

impl Singularities {
    /// α1 of the cusps where a pole merges with the zero (µ is 0/0 there).
    pub fn singular_cusps(&self) -> Vec<f64> {
        self.zeros
            .iter()
            .filter(|z| z.kind == ZeroKind::Indeterminate)
            .map(|z| z.alpha1_rad)
            .collect()
    }
}

/// Locate every pole of µ1, µ2 and every zero over α1 ∈ [0, 2π).
///
/// Each arch [α_i, α_{i+1}] is sampled at `samples_per_arch` + 1 points of the pole
/// functions (K − O_j)·d; every strict sign change is refined by Brent to `tol` in α1.
/// At a frozen obliquity ψ ≠ 0 the pole function is A sin(ϕ/2) − B cos(ϕ/2) with a single
/// root per arch, so a sampling of 16+ points per arch only misses pole pairs that merge at
/// a ψ = 0 cusp, which are reported as [`ZeroKind::Indeterminate`].
pub fn singularities(
    pair: &GearPair,
    samples_per_arch: usize,
    tol: f64,
) -> Result<Singularities, SearchError> {
    singularities_with(pair, samples_per_arch, Some(tol))
}

/// [`singularities`] with `Some(tol)`; with `None` each bracketed pole is placed by one
/// false-position step x = x_a − f_a (x_b − x_a)/(f_b − f_a) instead of Brent, with the error
/// |f(x)|/|f'| (f' the bracket's secant slope) — cheaper and coarser.
pub fn singularities_with(
    pair: &GearPair,
    samples_per_arch: usize,
    tol: Option<f64>,
) -> Result<Singularities, SearchError> {
    let m = samples_per_arch.max(4);
    let mut poles = Vec::new();
    let mut zeros = Vec::new();
    let mut evals = 0usize;
    for i in 0..pair.n_arches {
        let a0 = pair.arch_start(i);
        let a1 = pair.arch_start(i + 1);
        let indeterminate = [
            pair.cusp_is_indeterminate(i),
            pair.cusp_is_indeterminate(i + 1),
        ];
        let kind = if indeterminate[0] {
            ZeroKind::Indeterminate
        } else {
            ZeroKind::PitchPoint
        };
        zeros.push(Zero {
            alpha1_rad: a0.rem_euclid(TAU),
            arch: i,
            kind,
        });
        for which in [Which::Mu1, Which::Mu2] {
            let count = std::cell::Cell::new(0usize);
            let f = |x: f64| {
                count.set(count.get() + 1);
                match which {
                    Which::Mu1 => pair.pole_fn_mu1(x, i),
                    Which::Mu2 => pair.pole_fn_mu2(x, i),
                }
            };
            let h = (a1 - a0) / m as f64;
            let xs: Vec<f64> = (0..=m)
                .map(|k| if k == m { a1 } else { a0 + k as f64 * h })
                .collect();
            let ys: Vec<f64> = xs.iter().map(|&x| f(x)).collect();
            for k in 0..m {
                let (ya, yb) = (ys[k], ys[k + 1]);
                // Endpoints at the cusps: at a ψ = 0 cusp the pole function vanishes (the
                // 0/0 point, not a pole), elsewhere a value within its rounding bound has no
                // reliable sign. The bound grows like κ = R/(R − e) (see `pole_fn_roundoff`).
                let end_a =
                    k == 0 && (indeterminate[0] || ya.abs() <= pair.pole_fn_roundoff(xs[0]));
                let end_b =
                    k + 1 == m && (indeterminate[1] || yb.abs() <= pair.pole_fn_roundoff(xs[m]));
                if end_a || end_b {
                    continue;
                }
                if ya * yb < 0.0 || (ya == 0.0 && k > 0) {
                    let slope = ((yb - ya) / (xs[k + 1] - xs[k]))
                        .abs()
                        .max(f64::MIN_POSITIVE);
                    let (x, fx, bracket) = match tol {
                        Some(tol) => {
                            let root = brent_root(f, xs[k], xs[k + 1], tol)?;
                            (root.x, root.fx, tol)
                        }
                        None => {
                            let x = if ya == 0.0 {
                                xs[k]
                            } else {
                                xs[k] - ya * (xs[k + 1] - xs[k]) / (yb - ya)
                            };
                            (x, f(x), 0.0)
                        }
                    };
                    let phi = pair.contact_on(x, i).phi;
                    // The root is bracketed to `tol`; the function value adds |f|/|f'| and
                    // the function's own rounding δf/|f'| (the conditioning of the root).
                    poles.push(Pole {
                        alpha1_rad: x.rem_euclid(TAU),
                        which,
                        arch: i,
                        phi_rad: phi,
                        error_rad: bracket + (fx.abs() + pair.pole_fn_roundoff(x)) / slope,
                    });
                }
            }
            evals += count.get();
        }
    }
    poles.sort_by(|a, b| a.alpha1_rad.total_cmp(&b.alpha1_rad));
    zeros.sort_by(|a, b| a.alpha1_rad.total_cmp(&b.alpha1_rad));
    Ok(Singularities {
        poles,
        zeros,
        evals,
    })
}

/// Minimum over α1 of gear 2's pitch-curve curvature (sampled at `n` points, each sampled
/// local minimum refined by Brent). Returns (κ_min, α1 at the minimum, error bound).
pub fn min_gear2_curvature(pair: &GearPair, n: usize) -> Result<(f64, f64, f64), SearchError> {
    let neg = |x: f64| -pair.gear2_curvature(x);
    let pk = crate::numeric::periodic_peak(neg, n, 1e-10)?;
    Ok((
        -pk.peak.fx,
        pk.peak.x,
        pk.error + 8.0 * f64::EPSILON * pk.peak.fx.abs(),
    ))
}
