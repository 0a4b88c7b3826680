//! The RMS of a field over the turn, and the least-squares form of an RMS objective: the
//! trapezoid rule on uniform angles θ_k = 2πk/N, N doubled from `rms_samples` until the
//! field's mean-square form stops moving. A periodic field that is analytic in a strip
//! |Im θ| < a is integrated with an error ~ e^(−aN); near a fold (a dyad close to its
//! assembly limit) a is small, the field a spike a few milliradians wide, and 360 samples
//! weight a sample on the spike by more than its width (issue 34: a four-bar 1 µm from its
//! change point, RMS 108.4 N reported at 360 angles where the truth is 80.68 N). The count
//! therefore follows the field's bandwidth, and the stated error bounds the quadrature over
//! the whole design box, not only at the design found.
//!
//! Hand-written: the quantity compared between N and N/2 is a matrix (the mean-square form
//! over every design), which no quadrature crate integrates; the rule itself is the
//! trapezoid's.

use super::validate::check_finite;
use super::{AffineValue, Engine, MinimaxError};
use crate::numeric::periodic_rms_sampled;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Most doublings of `rms_samples` (2¹⁰: 360 → 368,640 angles).
const MAX_DOUBLINGS: u32 = 10;

/// Most multiply-adds of one mean-square form (N·d·(n+1)²): caps N for many variables.
const MAX_FORM_WORK: f64 = 4e8;

/// The form's relative change at which the grid of a field whose RMS is only reported (not
/// the objective) stops: its value and error at the design are what the result shows. A
/// field with a kink (a process load switching on) converges as N⁻², and `rel_tol` would
/// take it to the cap (the six-bar press's torque: 0.16 s → 1.1 s per solve).
const REPORT_TOL: f64 = 1e-5;

/// A field on the RMS grid, with what its last doubling showed.
#[derive(Debug, Clone)]
pub(super) struct RmsGrid {
    /// The field at θ_k = 2πk/N.
    pub(super) values: Vec<AffineValue>,
    /// ‖Q_N − Q_{N/2}‖_F: the change of the scaled mean-square form
    /// Q_N = (1/N) Σ_k Σ_r a_rk a_rkᵀ, a_rk = [A_r(θ_k) S, b_r(θ_k)] / G_f, over the last
    /// halving, so |R_N(x)² − R_{N/2}(x)²| ≤ G_f² ‖Q_N − Q_{N/2}‖ ‖[x̂; 1]‖² for every x.
    pub(super) form_change: f64,
    /// ‖Q_N‖_F.
    pub(super) form_size: f64,
    /// Whether the form met its tolerance (or round-off) before the cap on N.
    pub(super) converged: bool,
}

impl<'p, 'a> Engine<'p, 'a> {
    /// The RMS of field f at x on its RMS grid, with its quadrature error |R_N − R_{N/2}|.
    pub fn rms(&self, f: usize, x: &[f64]) -> (f64, f64) {
        let d = self.pb.fields[f].dim();
        let ys: Vec<f64> = self
            .rms_grid(f)
            .values
            .iter()
            .map(|v| v.magnitude(d, x))
            .collect();
        let r = periodic_rms_sampled(&ys);
        (r.rms, r.error)
    }

    /// A bound on |R(x) − R_N(x)| that holds for every design whose scaled ‖x̂‖² is at most
    /// `xhat_sq`, from the form's last change: e² = G_f² ‖ΔQ‖ (1 + ‖x̂‖²), and
    /// |R − R_N| ≤ min(e, e²/R_N) (|a − b| = |a² − b²|/(a + b)).
    pub(super) fn rms_uniform_error(&self, f: usize, xhat_sq: f64, rms: f64) -> f64 {
        let g = self.rms_grid(f);
        let e2 = self.g_ref()[f].powi(2) * g.form_change * (1.0 + xhat_sq);
        let e = e2.sqrt();
        if rms > 0.0 {
            e.min(e2 / rms)
        } else {
            e
        }
    }

    /// The field's RMS grid, built on first use: N = `rms_samples` (the scan grid's values
    /// when the counts agree), doubled while the mean-square form moves by more than
    /// τ‖Q‖ (and more than its round-off), at most [`MAX_DOUBLINGS`] times and within
    /// [`MAX_FORM_WORK`]; τ = `rel_tol` for the problem's RMS objective, [`REPORT_TOL`] for a
    /// field whose RMS is only reported.
    pub(super) fn rms_grid(&self, f: usize) -> &RmsGrid {
        if let Some(g) = self.rms_grids[f].get() {
            return g;
        }
        let g = self.build_rms_grid(f);
        self.rms_grids[f].get_or_init(|| g)
    }

    fn build_rms_grid(&self, f: usize) -> RmsGrid {
        let d = self.pb.fields[f].dim();
        let n0 = self.s.rms_samples;
        let mut values = if n0 == self.s.scan_samples {
            self.grid[f].to_values()
        } else {
            (0..n0)
                .map(|k| self.eval_raw(f, TAU * k as f64 / n0 as f64))
                .collect()
        };
        let work = |n: usize| n as f64 * d as f64 * ((self.n + 1) as f64).powi(2);
        let objective = matches!(self.pb.goal, super::Goal::MinRms(g) if g == f);
        let tol = if objective {
            self.s.rel_tol
        } else {
            REPORT_TOL.max(self.s.rel_tol)
        };
        // Σ a aᵀ over the even values and over all: N·Q_N and (N/2)·Q_{N/2}. A doubling keeps
        // the grid as its even points, so the old total is the new even sum.
        let mut even = self.form_sum(f, values.iter().step_by(2));
        let mut total = add(&even, &self.form_sum(f, values.iter().skip(1).step_by(2)));
        let mut doublings = 0;
        loop {
            let n = values.len();
            let q: Vec<f64> = total.iter().map(|t| t / n as f64).collect();
            let form_size = frobenius(&q);
            let change = q
                .iter()
                .zip(&even)
                .map(|(a, e)| (a - e / (n / 2) as f64).powi(2))
                .sum::<f64>()
                .sqrt();
            let roundoff = 64.0 * n as f64 * f64::EPSILON * form_size;
            let converged = change <= (tol * form_size).max(roundoff);
            let stop = converged
                || !change.is_finite()
                || doublings == MAX_DOUBLINGS
                || work(2 * n) > MAX_FORM_WORK;
            if stop {
                return RmsGrid {
                    values,
                    form_change: change,
                    form_size,
                    converged,
                };
            }
            // The field at the odd points of the grid of 2N angles, in parallel (each a
            // mechanism's pose and loads; collected in order, so the same values whatever
            // the threads).
            let odd: Vec<AffineValue> = (0..n)
                .into_par_iter()
                .with_min_len(64)
                .map(|k| self.eval_raw(f, TAU * (2 * k + 1) as f64 / (2 * n) as f64))
                .collect();
            even = total;
            total = add(&even, &self.form_sum(f, odd.iter()));
            values = values
                .into_iter()
                .zip(odd)
                .flat_map(|(e, o)| [e, o])
                .collect();
            doublings += 1;
        }
    }

    /// The field at θ (non-finite values are caught where they are used).
    fn eval_raw(&self, f: usize, theta: f64) -> AffineValue {
        let mut v = AffineValue::zeros(self.n);
        self.pb.fields[f].eval(theta, &mut v);
        v
    }

    /// Σ_k Σ_r a_rk a_rkᵀ over `values`, a = [A_r S, b_r]/G_f, row-major (n+1)²: the
    /// unnormalised mean-square form of those angles.
    fn form_sum<'v>(&self, f: usize, values: impl Iterator<Item = &'v AffineValue>) -> Vec<f64> {
        let d = self.pb.fields[f].dim();
        let m = self.n + 1;
        let mut sum = vec![0.0; m * m];
        let mut a = vec![0.0; m];
        for v in values {
            for r in 0..d {
                self.scaled_row(v, r, 1.0 / self.g_ref()[f], &mut a);
                for i in 0..m {
                    for j in 0..m {
                        sum[i * m + j] += a[i] * a[j];
                    }
                }
            }
        }
        sum
    }

    /// a = [A_r S, b_r]·w: row r of the field at one angle in the scaled variables.
    fn scaled_row(&self, v: &AffineValue, r: usize, w: f64, a: &mut [f64]) {
        for (j, aj) in a.iter_mut().take(self.n).enumerate() {
            *aj = v.row(r)[j] * self.scale[j] * w;
        }
        a[self.n] = v.b[r] * w;
    }

    /// R, the (n+1)×(n+1) triangular factor of the scaled stacked rows
    /// [A_r(θ_k) S, b_r(θ_k)] / (G_f √N): mean |g|²/G_f² = ‖R [x̂; 1]‖². Factored in chunks
    /// (each QR of the last R stacked over the next rows), so memory stays bounded on a
    /// fine grid.
    pub(super) fn rms_factor(&self, f: usize) -> Result<nalgebra::DMatrix<f64>, MinimaxError> {
        let d = self.pb.fields[f].dim();
        let vals = &self.rms_grid(f).values;
        let nn = vals.len();
        for (k, v) in vals.iter().enumerate() {
            check_finite(self.pb.fields[f], TAU * k as f64 / nn as f64, v)?;
        }
        let m = self.n + 1;
        let w = 1.0 / (self.g_ref()[f] * (nn as f64).sqrt());
        let mut r = nalgebra::DMatrix::<f64>::zeros(0, m);
        let mut a = vec![0.0; m];
        for chunk in vals.chunks(2048) {
            let top = r.nrows();
            let mut stack = nalgebra::DMatrix::<f64>::zeros(top + chunk.len() * d, m);
            stack.rows_mut(0, top).copy_from(&r);
            for (k, v) in chunk.iter().enumerate() {
                for row in 0..d {
                    self.scaled_row(v, row, w, &mut a);
                    for (j, aj) in a.iter().enumerate() {
                        stack[(top + k * d + row, j)] = *aj;
                    }
                }
            }
            r = stack.qr().r();
        }
        Ok(r)
    }
}

/// a + b, elementwise.
fn add(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(a, b)| a + b).collect()
}

fn frobenius(q: &[f64]) -> f64 {
    q.iter().map(|v| v * v).sum::<f64>().sqrt()
}
