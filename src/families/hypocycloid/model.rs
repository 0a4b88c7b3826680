//! Hypocycloidal reciprocating machine: a planet carrier OO1 (length R, angle φ), a planet
//! rolling inside a fixed ring with diameter ratio 3:1 (absolute angle −2φ), a crank arm O1A
//! (length r) on the planet and a rod AB (length L) to the piston B on the x axis.
//!
//! This module is the pure, dimensionless physics (everything divided by R): the piston
//! position S/R and its φ-derivatives in closed form, the exact Fourier coefficients of S/R
//! (FFT with an aliasing estimate), the paper-style truncated binomial series, and the
//! inertia force of each order with its Lanchester balancing pair. It exists so that the
//! synthesis layer (`synth::hypocycloid`) and the tests can ask "what is C4 at (λ, θ)" and get
//! a number with an error bar, without any design-variable or I/O machinery.
//!
//! Notation (paper `004`): λ = R/L, θ = r/R, α0 = orientation of the curve
//! (variant 1: α0 = 0, variant 2: α0 = 3π/2).
//!
//!   A/R = (x, y) = (cos φ + θ cos(α0 − 2φ), sin φ + θ sin(α0 − 2φ))
//!   S/R = x + (1/λ) sqrt(1 − λ² y²)
//!       = x + 1/λ − λ y²/2 − λ³ y⁴ / (2 (1 + w)²),   w = sqrt(1 − λ² y²)
//!
//! The second line is exact (1 − w = z/(1 + w) and z/(1+w) − z/2 = z²/(2(1+w)²) with
//! z = λ²y²) and is what the program evaluates: it has no cancellation as λ → 0, and its
//! first two parts are trigonometric polynomials whose Fourier coefficients are computed
//! exactly, so the FFT only sees the O(λ³) remainder.

// `!(x > 0.0)` is deliberate: a NaN must fail every range check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;
use std::f64::consts::{PI, TAU};

use crate::numeric::{periodic_peak, SearchError};

/// Orientation α0 of the paper's variant 1 (Fig. 1: curve symmetric about x, suction
/// lengthened by a dwell).
pub const ALPHA0_VARIANT1: f64 = 0.0;
/// Orientation α0 of the paper's variant 2 (Fig. 3: curve turned 90° in the sense of
/// rotation, suction lengthened by a longer path): α0 = 270°.
pub const ALPHA0_VARIANT2: f64 = 1.5 * PI;

/// Why the model cannot give a value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MechError {
    /// λ·max|y/R| ≥ 1: at some φ the rod cannot reach the slider axis.
    #[error(
        "the mechanism cannot assemble: λ·max|y_A/R| = {lambda_ymax} ≥ 1 (λ = {lambda}, θ = {theta}); \
         λ must stay below {lambda_limit}"
    )]
    CannotAssemble {
        lambda: f64,
        theta: f64,
        lambda_ymax: f64,
        lambda_limit: f64,
    },
    /// A ratio is NaN, infinite or out of its range.
    #[error("invalid ratio {name} = {value}: {allowed}")]
    BadRatio {
        name: &'static str,
        value: f64,
        allowed: &'static str,
    },
    /// A 1-D search inside the model failed.
    #[error("search failed: {0}")]
    Search(#[from] SearchError),
}

/// The dimensionless mechanism (all lengths divided by the carrier length R).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hypocycloid {
    /// λ = R/L.
    pub lambda: f64,
    /// θ = r/R.
    pub theta: f64,
    /// Curve orientation α0 (rad).
    pub alpha0: f64,
}

/// Position of the piston and its φ-derivatives, all divided by R.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PistonKinematics {
    /// S/R − 1/λ (the displacement measured from the rod length; no cancellation).
    pub s_rel: f64,
    /// (S/R)' = dS/dφ / R.
    pub ds: f64,
    /// (S/R)'' = d²S/dφ² / R.
    pub dds: f64,
}

/// max_φ |sin φ + θ sin(α0 − 2φ)|, the largest distance of A from the slider axis (÷R),
/// refined by Brent on every sampled maximum (value error ≤ 1e-18 for θ ≤ 10).
pub fn max_abs_y(theta: f64, alpha0: f64) -> Result<f64, MechError> {
    let p = periodic_peak(
        |f| (f.sin() + theta * (alpha0 - 2.0 * f).sin()).abs(),
        72,
        1e-10,
    )?;
    Ok(p.peak.fx)
}

/// Closed form of [`max_abs_y`] for variant 1 (α0 = 0): with c = cos φ at the maximum,
/// 4θc² − c − 2θ = 0, c = −4θ/(1 + sqrt(1 + 32θ²)), max|y| = sqrt(1 − c²)·(1 − 2θc).
pub fn max_abs_y_variant1(theta: f64) -> f64 {
    let c = -4.0 * theta / (1.0 + (1.0 + 32.0 * theta * theta).sqrt());
    ((1.0 - c) * (1.0 + c)).sqrt() * (1.0 - 2.0 * theta * c)
}

/// Closed form of [`max_abs_y`] for variant 2 (α0 = 3π/2): y = 2θs² + s − θ with s = sin φ,
/// a parabola on [−1, 1] whose largest magnitude is 1 + θ (θ ≥ 0).
pub fn max_abs_y_variant2(theta: f64) -> f64 {
    1.0 + theta.abs()
}

impl Hypocycloid {
    /// A checked model: λ > 0 finite, θ ≥ 0 finite, α0 finite, and λ·max|y| < 1.
    pub fn new(lambda: f64, theta: f64, alpha0: f64) -> Result<Self, MechError> {
        if !(lambda.is_finite() && lambda > 0.0) {
            return Err(MechError::BadRatio {
                name: "lambda",
                value: lambda,
                allowed: "finite and > 0",
            });
        }
        if !(theta.is_finite() && theta >= 0.0) {
            return Err(MechError::BadRatio {
                name: "theta",
                value: theta,
                allowed: "finite and ≥ 0",
            });
        }
        if !alpha0.is_finite() {
            return Err(MechError::BadRatio {
                name: "alpha0",
                value: alpha0,
                allowed: "finite",
            });
        }
        let ym = max_abs_y(theta, alpha0)?;
        if !(lambda * ym < 1.0) {
            return Err(MechError::CannotAssemble {
                lambda,
                theta,
                lambda_ymax: lambda * ym,
                lambda_limit: 1.0 / ym,
            });
        }
        Ok(Hypocycloid {
            lambda,
            theta,
            alpha0,
        })
    }

    /// λ·max|y_A/R| (< 1 for a model built by [`Hypocycloid::new`]); 1 − this is the
    /// assembly margin.
    pub fn lambda_ymax(&self) -> f64 {
        self.lambda * max_abs_y(self.theta, self.alpha0).unwrap_or(f64::INFINITY)
    }

    /// Crank pin A/R = (cos φ + θ cos(α0 − 2φ), sin φ + θ sin(α0 − 2φ)).
    pub fn point_a(&self, phi: f64) -> (f64, f64) {
        let g = self.alpha0 - 2.0 * phi;
        (
            phi.cos() + self.theta * g.cos(),
            phi.sin() + self.theta * g.sin(),
        )
    }

    /// S/R and its derivatives. With w = sqrt(1 − λ²y²):
    /// S/R − 1/λ = x − λy²/(1 + w),  (S/R)' = x' − λ y y'/w,
    /// (S/R)'' = x'' − λ (y'² + y y'')/w − λ³ y² y'²/w³.
    pub fn piston(&self, phi: f64) -> PistonKinematics {
        let (l, t) = (self.lambda, self.theta);
        let g = self.alpha0 - 2.0 * phi;
        let (sp, cp) = phi.sin_cos();
        let (sg, cg) = g.sin_cos();
        let x = cp + t * cg;
        let y = sp + t * sg;
        let dx = -sp + 2.0 * t * sg;
        let dy = cp - 2.0 * t * cg;
        let ddx = -cp - 4.0 * t * cg;
        let ddy = -sp - 4.0 * t * sg;
        let ly = l * y;
        let w = ((1.0 - ly) * (1.0 + ly)).max(0.0).sqrt();
        let s_rel = x - l * y * y / (1.0 + w);
        let ds = dx - l * y * dy / w;
        let dds = ddx - l * (dy * dy + y * ddy) / w - l * l * l * y * y * dy * dy / (w * w * w);
        PistonKinematics { s_rel, ds, dds }
    }

    /// Complex Fourier coefficients c_k (k = −2..2, index k+2) of y/R = sin φ + θ sin(α0 − 2φ).
    fn y_poly(&self) -> Vec<Complex64> {
        let inv2i = Complex64::new(0.0, -0.5); // 1/(2i) = −i/2
        let e = Complex64::from_polar(1.0, self.alpha0);
        let mut c = vec![Complex64::new(0.0, 0.0); 5];
        c[3] = inv2i; // e^{iφ}/(2i)
        c[1] = -inv2i; // −e^{−iφ}/(2i)
        c[0] = self.theta * e * inv2i; // θ e^{iα0} e^{−2iφ}/(2i)
        c[4] = -self.theta * e.conj() * inv2i;
        c
    }

    /// Exact cosine/sine coefficients (orders 0..=4) of x/R − λ y²/2 (the polynomial part).
    fn poly_part(&self, order: usize) -> (Vec<f64>, Vec<f64>) {
        let y = self.y_poly();
        let y2 = conv(&y, &y); // orders −4..4
        let mut a = vec![0.0; order + 1];
        let mut b = vec![0.0; order + 1];
        for k in 0..=order.min(4) {
            let c = y2[k + 4] * (-0.5 * self.lambda);
            if k == 0 {
                a[0] += c.re;
            } else {
                a[k] += 2.0 * c.re;
                b[k] -= 2.0 * c.im;
            }
        }
        // x/R = cos φ + θ cos(α0 − 2φ) = cos φ + θ cos α0 cos 2φ + θ sin α0 sin 2φ.
        if order >= 1 {
            a[1] += 1.0;
        }
        if order >= 2 {
            a[2] += self.theta * self.alpha0.cos();
            b[2] += self.theta * self.alpha0.sin();
        }
        (a, b)
    }

    /// The O(λ³) remainder g(φ) = −λ³ y⁴ / (2 (1 + w)²).
    fn remainder(&self, phi: f64) -> f64 {
        let (_, y) = self.point_a(phi);
        let ly = self.lambda * y;
        let w = ((1.0 - ly) * (1.0 + ly)).max(0.0).sqrt();
        let opw = 1.0 + w;
        -self.lambda * ly * ly * y * y / (2.0 * opw * opw)
    }

    /// Trapezoid (= DFT) coefficients of the remainder on `n` points, orders 0..=order,
    /// and max|g| over the samples.
    fn remainder_dft(
        &self,
        n: usize,
        order: usize,
        planner: &mut FftPlanner<f64>,
    ) -> (Vec<f64>, Vec<f64>, f64) {
        let h = TAU / n as f64;
        let mut buf: Vec<Complex64> = (0..n)
            .map(|j| Complex64::new(self.remainder(j as f64 * h), 0.0))
            .collect();
        let gmax = buf.iter().fold(0.0f64, |m, c| m.max(c.re.abs()));
        planner.plan_fft_forward(n).process(&mut buf);
        let mut a = vec![0.0; order + 1];
        let mut b = vec![0.0; order + 1];
        let inv = 1.0 / n as f64;
        for k in 0..=order.min(n / 2 - 1) {
            let c = buf[k] * inv;
            if k == 0 {
                a[0] = c.re;
            } else {
                a[k] = 2.0 * c.re;
                b[k] = -2.0 * c.im;
            }
        }
        (a, b, gmax)
    }

    /// Exact Fourier coefficients of S/R = a0 + Σ (a_i cos iφ + b_i sin iφ), i = 1..=order.
    ///
    /// The polynomial part is exact; the remainder is transformed on n = n_min, 2n_min, …
    /// points until two successive sizes agree to within the rounding floor
    /// 8ε·(max|g| + λ max y²) for every order, or n reaches `n_max`. The reported error of
    /// each coefficient is |c(2n) − c(n)| (a bound on the aliasing of the n-point value,
    /// hence conservative for the 2n-point value returned) plus that rounding floor.
    pub fn coefficients(&self, order: usize, n_min: usize, n_max: usize) -> Coefficients {
        let mut planner = FftPlanner::new();
        let mut n = n_min.max(2 * order + 2).next_power_of_two().max(16);
        let n_max = n_max.max(n);
        let (mut ra, mut rb, mut gmax) = self.remainder_dft(n, order, &mut planner);
        loop {
            let (a2, b2, g2) = self.remainder_dft(2 * n, order, &mut planner);
            gmax = gmax.max(g2);
            let (delta, floor) = self.change(&ra, &rb, &a2, &b2, gmax);
            let converged = delta.iter().all(|&d| d <= floor);
            n *= 2;
            ra = a2;
            rb = b2;
            if converged || n >= n_max {
                return self.assemble(order, ra, rb, &delta, floor, n, converged);
            }
        }
    }

    /// The coefficients on one fixed `n`-point rule (`n` a power of two ≥ 16), without the
    /// adaptive check of [`Hypocycloid::coefficients`]: orders ≥ n/2 of the remainder are
    /// left out (zero). The error of each order is |c(n) − c(n/2)| plus the rounding floor
    /// (the n/2 rule is only used for this estimate; for orders ≥ n/4 it is the size of the
    /// coefficient itself, since the n/2 rule has none).
    pub fn coefficients_fixed(&self, order: usize, n: usize) -> Coefficients {
        let mut planner = FftPlanner::new();
        let n = n.next_power_of_two().max(16);
        let (ra, rb, g) = self.remainder_dft(n, order, &mut planner);
        let (ha, hb, gh) = self.remainder_dft(n / 2, order, &mut planner);
        let (delta, floor) = self.change(&ha, &hb, &ra, &rb, g.max(gh));
        let converged = delta.iter().all(|&d| d <= floor);
        self.assemble(order, ra, rb, &delta, floor, n, converged)
    }

    /// |c(2n) − c(n)| per order and the rounding floor 8ε·(max|g| + λ max y² + 1 + θ).
    fn change(&self, a: &[f64], b: &[f64], a2: &[f64], b2: &[f64], gmax: f64) -> (Vec<f64>, f64) {
        let ymax2 = (1.0 + self.theta).powi(2);
        let floor = 8.0 * f64::EPSILON * (gmax + self.lambda * ymax2 + 1.0 + self.theta);
        let delta = (0..a.len())
            .map(|k| (a2[k] - a[k]).hypot(b2[k] - b[k]))
            .collect();
        (delta, floor)
    }

    /// Polynomial part + remainder coefficients + 1/λ, with the error |Δ| + floor.
    #[allow(clippy::too_many_arguments)]
    fn assemble(
        &self,
        order: usize,
        ra: Vec<f64>,
        rb: Vec<f64>,
        delta: &[f64],
        floor: f64,
        n: usize,
        converged: bool,
    ) -> Coefficients {
        let (mut a, mut b) = self.poly_part(order);
        for k in 0..=order {
            a[k] += ra[k];
            b[k] += rb[k];
        }
        a[0] += 1.0 / self.lambda;
        Coefficients {
            a,
            b,
            err: delta.iter().map(|d| d + floor).collect(),
            n_fft: n,
            converged,
        }
    }

    /// Only the cosine coefficient a_k of S/R on a fixed `n`-point trapezoid rule (the k-th
    /// DFT bin of the remainder plus the exact polynomial part). Used by the zero search,
    /// which picks `n` once per column with [`Hypocycloid::coefficients`]'s criterion.
    pub fn cos_coefficient(&self, k: usize, n: usize) -> f64 {
        let (pa, _) = self.poly_part(k);
        let h = TAU / n as f64;
        let mut s = 0.0;
        for j in 0..n {
            let p = j as f64 * h;
            s += self.remainder(p) * (k as f64 * p).cos();
        }
        let r = if k == 0 {
            s / n as f64
        } else {
            2.0 * s / n as f64
        };
        pa[k] + r + if k == 0 { 1.0 / self.lambda } else { 0.0 }
    }

    /// Paper-style truncated series: sqrt(1 − z) expanded binomially to z^power,
    /// S/R ≈ x + 1/λ − Σ_{k=1..power} c_k λ^{2k−1} y^{2k}, c_k = −binom(1/2, k)
    /// (1/2, 1/8, 1/16, 5/128, …), with every power of y expanded exactly into harmonics
    /// (the paper: power 3, i.e. y⁶). Returns (a, b) for orders 0..=order.
    pub fn series_coefficients(&self, power: usize, order: usize) -> (Vec<f64>, Vec<f64>) {
        let y = self.y_poly();
        let y2 = conv(&y, &y);
        // Three buffers for the whole series (this runs inside root searches): y^{2k} (orders
        // −4k..4k) and the sum, centred, at their final length 8·power + 1. The sum's
        // entries outside the previous power's reach are assigned, inside it added to
        // (acc + s·p): the same numbers, to the sign of a zero, as building each partial sum
        // afresh.
        let z = Complex64::new(0.0, 0.0);
        let full = 8 * power + 1;
        let mut acc = vec![z; full.max(1)];
        let mut pw = Vec::with_capacity(full); // y^{2(k−1)}
        pw.push(Complex64::new(1.0, 0.0));
        let mut next = Vec::with_capacity(full);
        let centre = full / 2;
        for (k, s) in (1..=power).zip(self.series_weights()) {
            conv_into(&pw, &y2, &mut next);
            std::mem::swap(&mut pw, &mut next);
            let (half, reach) = (pw.len() / 2, 4 * (k - 1));
            for (i, c) in pw.iter().enumerate() {
                let j = centre + i - half;
                acc[j] = if j.abs_diff(centre) <= reach {
                    acc[j] + c * s
                } else {
                    c * s
                };
            }
        }
        let m = acc.len() / 2;
        let mut a = vec![0.0; order + 1];
        let mut b = vec![0.0; order + 1];
        for k in 0..=order.min(m) {
            let c = acc[m + k];
            if k == 0 {
                a[0] = c.re;
            } else {
                a[k] = 2.0 * c.re;
                b[k] = -2.0 * c.im;
            }
        }
        if order >= 1 {
            a[1] += 1.0;
        }
        if order >= 2 {
            a[2] += self.theta * self.alpha0.cos();
            b[2] += self.theta * self.alpha0.sin();
        }
        a[0] += 1.0 / self.lambda;
        (a, b)
    }

    /// The weights of the truncated series, −c_k λ^{2k−1} for k = 1, 2, …: c_k = −binom(½, k)
    /// = ½, ⅛, 1/16, 5/128, … by c_{k+1} = c_k (2k − 1)/(2k + 2).
    fn series_weights(&self) -> impl Iterator<Item = f64> + '_ {
        (1..).scan((0.5, self.lambda), move |(ck, lk), k: usize| {
            let s = -*ck * *lk;
            *ck *= (2.0 * k as f64 - 1.0) / (2.0 * k as f64 + 2.0);
            *lk *= self.lambda * self.lambda;
            Some(s)
        })
    }

    /// The cosine coefficient a_k of [`Hypocycloid::series_coefficients`]`(power, k)` alone,
    /// the same number bit for bit, for root searches in θ (the zero search evaluates it
    /// thousands of times): the powers y^{2j} are built in full up to power − 1, the last
    /// only at order k, and the sum only at order k, each entry summed in the same order.
    pub fn series_a(&self, power: usize, k: usize) -> f64 {
        let y = self.y_poly();
        let y2 = conv(&y, &y);
        let m = 4 * power;
        let mut c = Complex64::new(0.0, 0.0); // the sum at order k
        if power > 0 && k <= m {
            let mut pw = Vec::with_capacity(8 * power + 1); // y^{2(j−1)}, orders −4(j−1)..
            pw.push(Complex64::new(1.0, 0.0));
            let mut next = Vec::with_capacity(8 * power + 1);
            for (j, s) in (1..=power).zip(self.series_weights()) {
                let p = if j < power {
                    conv_into(&pw, &y2, &mut next);
                    std::mem::swap(&mut pw, &mut next);
                    (k <= 4 * j).then(|| pw[4 * j + k])
                } else {
                    // Only entry 4j + k of conv(pw, y2), summed in conv's order.
                    let t = 4 * j + k;
                    let mut r = Complex64::new(0.0, 0.0);
                    for (i, &x) in pw.iter().enumerate() {
                        if let Some(&q) = t.checked_sub(i).and_then(|d| y2.get(d)) {
                            r += x * q;
                        }
                    }
                    Some(r)
                };
                if let Some(p) = p {
                    c = if k <= 4 * (j - 1) { c + p * s } else { p * s };
                }
            }
        }
        let mut a = match k {
            0 => c.re,
            _ if k <= m => 2.0 * c.re,
            _ => 0.0,
        };
        if k == 1 {
            a += 1.0;
        }
        if k == 2 {
            a += self.theta * self.alpha0.cos();
        }
        if k == 0 {
            a += 1.0 / self.lambda;
        }
        a
    }

    /// Stroke (S_max − S_min)/R and the suction angle: the rotation from the φ of S_max
    /// (the dead centre nearest the head, the head being at +x) forward to the φ of S_min.
    /// Both extrema are refined by Brent; the angle error is that of the refinement.
    pub fn stroke(&self) -> Result<Stroke, MechError> {
        let hi = periodic_peak(|p| self.piston(p).s_rel, 360, 1e-9)?;
        let lo = periodic_peak(|p| -self.piston(p).s_rel, 360, 1e-9)?;
        // Where the dwell splits the bottom dead centre into two equal minima (variant 1: S
        // is even in φ), the suction runs to the later one; which of the two the refinement
        // calls the peak is round-off, so the angle is taken as the largest over the minima
        // equal to the peak within the refinement's error.
        let tol = 1e-9 * (hi.peak.fx + lo.peak.fx).abs().max(1e-300) + lo.error;
        let suction = lo
            .maxima
            .iter()
            .filter(|m| m.fx >= lo.peak.fx - tol)
            .map(|m| (m.x - hi.peak.x).rem_euclid(TAU))
            .fold((lo.peak.x - hi.peak.x).rem_euclid(TAU), f64::max);
        Ok(Stroke {
            stroke: hi.peak.fx + lo.peak.fx,
            phi_top: hi.peak.x,
            phi_bottom: lo.peak.x,
            suction_angle: suction,
            reversals: hi.maxima.len().max(lo.maxima.len()),
            error: hi.error + lo.error,
        })
    }
}

/// Fast evaluator of one cosine coefficient a_k of S/R on a fixed n-point trapezoid rule
/// for many (λ, θ) at one α0: the trigonometric tables are built once, so one value costs n
/// square roots. Same formula as [`Hypocycloid::cos_coefficient`].
#[derive(Debug, Clone)]
pub struct CosBin {
    k: usize,
    alpha0: f64,
    sin_phi: Vec<f64>,
    sin_g: Vec<f64>,
    cos_k: Vec<f64>,
}

impl CosBin {
    /// Tables for order `k`, orientation `alpha0` and `n` points.
    pub fn new(k: usize, alpha0: f64, n: usize) -> Self {
        let h = TAU / n as f64;
        let ph = |j: usize| j as f64 * h;
        CosBin {
            k,
            alpha0,
            sin_phi: (0..n).map(|j| ph(j).sin()).collect(),
            sin_g: (0..n).map(|j| (alpha0 - 2.0 * ph(j)).sin()).collect(),
            cos_k: (0..n).map(|j| ((k * j % n) as f64 * h).cos()).collect(),
        }
    }

    /// Number of points.
    pub fn n(&self) -> usize {
        self.sin_phi.len()
    }

    /// a_k(λ, θ) (requires λ·max|y| < 1; beyond it the square root is clamped at 0).
    pub fn eval(&self, lambda: f64, theta: f64) -> f64 {
        let mut s = 0.0;
        for j in 0..self.sin_phi.len() {
            let y = self.sin_phi[j] + theta * self.sin_g[j];
            let ly = lambda * y;
            let w = ((1.0 - ly) * (1.0 + ly)).max(0.0).sqrt();
            let opw = 1.0 + w;
            s += ly * ly * y * y / (opw * opw) * self.cos_k[j];
        }
        let n = self.sin_phi.len() as f64;
        let r = -lambda * s / 2.0 * if self.k == 0 { 1.0 / n } else { 2.0 / n };
        let m = Hypocycloid {
            lambda,
            theta,
            alpha0: self.alpha0,
        };
        let (pa, _) = m.poly_part(self.k);
        pa[self.k] + r + if self.k == 0 { 1.0 / lambda } else { 0.0 }
    }
}

/// Stroke and phase split of the piston motion (see [`Hypocycloid::stroke`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stroke {
    /// (S_max − S_min)/R.
    pub stroke: f64,
    /// φ of S_max (rad).
    pub phi_top: f64,
    /// φ of S_min (rad).
    pub phi_bottom: f64,
    /// Rotation from top to bottom dead centre (rad); π for a plain slider-crank.
    pub suction_angle: f64,
    /// Number of local maxima of S per turn (1 = no intermediate reversal).
    pub reversals: usize,
    /// Bound on the value error of the stroke from the refinement.
    pub error: f64,
}

/// Fourier coefficients of S/R with their error estimate (see
/// [`Hypocycloid::coefficients`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Coefficients {
    /// Cosine coefficients a_0 … a_order (a_0 is the mean of S/R, it includes 1/λ).
    pub a: Vec<f64>,
    /// Sine coefficients b_0 (= 0) … b_order.
    pub b: Vec<f64>,
    /// Estimated absolute error of (a_i, b_i) together (aliasing + rounding).
    pub err: Vec<f64>,
    /// FFT size used.
    pub n_fft: usize,
    /// Whether the aliasing fell below the rounding floor before `n_max`.
    pub converged: bool,
}

impl Coefficients {
    /// Amplitude C_i = hypot(a_i, b_i).
    pub fn amplitude(&self, i: usize) -> f64 {
        self.a[i].hypot(self.b[i])
    }
}

/// Inertia force of order i of the reciprocating mass m_B (N) at angle φ:
/// Φ_i = m_B R ω² i² (a_i cos iφ + b_i sin iφ)   (= −m_B × the i-th order acceleration).
pub fn order_force(i: usize, a_i: f64, b_i: f64, m_b: f64, r: f64, omega: f64, phi: f64) -> f64 {
    let k = i as f64;
    let (s, c) = (k * phi).sin_cos();
    m_b * r * omega * omega * k * k * (a_i * c + b_i * s)
}

/// Lanchester pair cancelling order i: two equal masses on shafts turning at +iω and −iω.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LanchesterPair {
    /// Order i.
    pub order: usize,
    /// Shaft speed iω (rad/s); one shaft turns with the carrier, the other against it.
    pub speed: f64,
    /// Static moment of each mass m′r′ = ½ m_B R C_i, C_i = hypot(a_i, b_i) (kg·m).
    pub static_moment: f64,
    /// Angle of the co-rotating mass at φ = 0: π − γ_i, γ_i = atan2(b_i, a_i) (rad).
    pub phase_co: f64,
    /// Angle of the counter-rotating mass at φ = 0: π + γ_i (rad).
    pub phase_counter: f64,
}

/// The pair whose x-forces 2 m′r′ (iω)² cos(±(iφ − γ_i) + π) cancel Φ_i exactly and whose
/// y-forces cancel each other.
pub fn lanchester_pair(
    i: usize,
    a_i: f64,
    b_i: f64,
    m_b: f64,
    r: f64,
    omega: f64,
) -> LanchesterPair {
    let g = b_i.atan2(a_i);
    LanchesterPair {
        order: i,
        speed: i as f64 * omega,
        static_moment: 0.5 * m_b * r * a_i.hypot(b_i),
        phase_co: (PI - g).rem_euclid(TAU),
        phase_counter: (PI + g).rem_euclid(TAU),
    }
}

impl LanchesterPair {
    /// Force (x, y) of the pair at φ (N): each mass at angle ±iφ + phase, centrifugal force
    /// m′r′(iω)² along its radius.
    pub fn force(&self, phi: f64) -> (f64, f64) {
        let f = self.static_moment * self.speed * self.speed;
        let p1 = self.order as f64 * phi + self.phase_co;
        let p2 = -(self.order as f64) * phi + self.phase_counter;
        (f * (p1.cos() + p2.cos()), f * (p1.sin() + p2.sin()))
    }
}

/// Convolution of two centred coefficient arrays (lengths 2m+1, 2n+1 → 2(m+n)+1).
fn conv(p: &[Complex64], q: &[Complex64]) -> Vec<Complex64> {
    let mut r = Vec::new();
    conv_into(p, q, &mut r);
    r
}

/// [`conv`] into `r` (its old contents replaced; no allocation once it is large enough).
fn conv_into(p: &[Complex64], q: &[Complex64], r: &mut Vec<Complex64>) {
    r.clear();
    r.resize(p.len() + q.len() - 1, Complex64::new(0.0, 0.0));
    for (i, &x) in p.iter().enumerate() {
        for (j, &y) in q.iter().enumerate() {
            r[i + j] += x * y;
        }
    }
}
