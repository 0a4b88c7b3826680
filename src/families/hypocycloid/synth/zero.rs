//! The zero search of a Fourier coefficient a_i over (λ, θ) (paper `004`'s conjecture that
//! a (λ, θ) exists where the fourth-order coefficient vanishes): a sign scan of the
//! feasible grid, each sign change refined by Brent's root (argmin's `BrentRoot` through
//! [`crate::numeric::brent_root`]), and the evidence of what was (not) found.

use super::{
    CoefficientMap, GridMin, Settings, ZeroRoot, ZeroSearch, ZeroSearchResult, ZeroStatus,
};
use crate::families::hypocycloid::model::{max_abs_y, CosBin, Hypocycloid};
use crate::numeric::brent_root;

/// Largest θ in [t0, t1] with λ·max|y(θ)| ≤ 1 − margin (max|y| is convex in θ, so the
/// feasible θ form an interval containing 0); `None` if even t0 is infeasible.
fn theta_limit(lambda: f64, alpha0: f64, t0: f64, t1: f64, margin: f64) -> Option<f64> {
    let g = |t: f64| lambda * max_abs_y(t, alpha0).unwrap_or(f64::INFINITY) - (1.0 - margin);
    if g(t0) > 0.0 {
        return None;
    }
    if g(t1) <= 0.0 {
        return Some(t1);
    }
    brent_root(g, t0, t1, 1e-13)
        .ok()
        .map(|r| if g(r.x) > 0.0 { r.x - 1e-13 } else { r.x })
}

/// FFT size at which all orders ≤ `order` converge at (λ, θ) (see
/// [`Hypocycloid::coefficients`]) and the error of order `order` there.
fn column_size(lambda: f64, theta: f64, alpha0: f64, order: usize, s: &Settings) -> (usize, f64) {
    let m = Hypocycloid {
        lambda,
        theta,
        alpha0,
    };
    let c = s.coefficients(&m, order);
    (c.n_fft, c.err[order])
}

/// The scan of one zero search: the scene's data and the common θ grid.
struct Scan<'a> {
    alpha0: f64,
    zs: &'a ZeroSearch,
    series_power: usize,
    margin: f64,
    s: &'a Settings,
    /// The θ grid.
    th: Vec<f64>,
}

impl Scan<'_> {
    /// The λ column `l`: a_k at the feasible θ samples (into `row`), each sign change
    /// refined into `roots`; the number of roots, `None` when no θ of the column is
    /// feasible. The FFT size is the converged size at the column's largest feasible θ
    /// (cosine bins cached in `bins` by size).
    fn column(
        &self,
        l: f64,
        bins: &mut Vec<CosBin>,
        row: &mut [Option<f64>],
        roots: &mut Vec<ZeroRoot>,
        evals: &mut usize,
    ) -> Option<usize> {
        let (alpha0, zs, s, k) = (self.alpha0, self.zs, self.s, self.zs.order);
        let tmax = theta_limit(l, alpha0, zs.theta.0, zs.theta.1, self.margin)?;
        let (n, err) = column_size(l, tmax, alpha0, k, s);
        let bin = match bins.iter().position(|b| b.n() == n) {
            Some(i) => &bins[i],
            None => {
                bins.push(CosBin::new(k, alpha0, n));
                bins.last().unwrap()
            }
        };
        // Feasible θ samples of this column, plus the limit itself when it cuts the grid.
        let mut ts: Vec<(Option<usize>, f64)> = self
            .th
            .iter()
            .enumerate()
            .filter(|(_, &t)| t <= tmax)
            .map(|(c, &t)| (Some(c), t))
            .collect();
        if tmax < zs.theta.1 {
            ts.push((None, tmax));
        }
        let fs: Vec<f64> = ts.iter().map(|&(_, t)| bin.eval(l, t)).collect();
        *evals += fs.len();
        // The truncated series' own roots anywhere in the column's feasible θ range (they
        // need not lie in the exact roots' brackets).
        let ser = |t: f64| {
            Hypocycloid {
                lambda: l,
                theta: t,
                alpha0,
            }
            .series_a(self.series_power, k)
        };
        let ss: Vec<f64> = ts.iter().map(|&(_, t)| ser(t)).collect();
        let series_roots: Vec<f64> = (0..ss.len().saturating_sub(1))
            .filter(|&w| ss[w] == 0.0 || ss[w].signum() != ss[w + 1].signum())
            .filter_map(|w| brent_root(ser, ts[w].1, ts[w + 1].1, s.root_tol).ok())
            .map(|r| r.x)
            .collect();
        for (&(c, _), &f) in ts.iter().zip(&fs) {
            if let Some(c) = c {
                row[c] = Some(f);
            }
        }
        let mut count = 0;
        for w in 0..fs.len().saturating_sub(1) {
            let (ta, tb, fa, fb) = (ts[w].1, ts[w + 1].1, fs[w], fs[w + 1]);
            // A sign change, or an exact zero at the left sample.
            if !(fa == 0.0 || fa.signum() != fb.signum()) || fb == 0.0 && w + 2 < fs.len() {
                continue;
            }
            let cnt = std::cell::Cell::new(0usize);
            let f = |t: f64| {
                cnt.set(cnt.get() + 1);
                bin.eval(l, t)
            };
            if let Ok(rt) = brent_root(f, ta, tb, s.root_tol) {
                *evals += cnt.get();
                let series_theta = series_roots
                    .iter()
                    .copied()
                    .min_by(|a, b| (a - rt.x).abs().total_cmp(&(b - rt.x).abs()));
                roots.push(ZeroRoot {
                    lambda: l,
                    theta: rt.x,
                    value: rt.fx,
                    bracket: (ta, tb),
                    f_bracket: (fa, fb),
                    value_error: err,
                    series_value: ser(rt.x),
                    series_theta,
                });
                count += 1;
            }
        }
        Some(count)
    }
}

/// Find, bracket, refine and trace the zeros of a_i over the feasible part of the box.
///
/// Columns λ_j (`curve_points`, evenly spaced) × a common θ grid (`theta_scan` points): a
/// sign change between neighbouring θ samples is refined by Brent to `root_tol`; the FFT
/// size of a column is the converged size at its most demanding (largest feasible) θ.
/// Sign changes along λ between columns that no θ-root explains are reported as possible
/// folds in `reason`.
pub fn zero_search(
    alpha0: f64,
    zs: &ZeroSearch,
    series_power: usize,
    margin: f64,
    s: &Settings,
) -> ZeroSearchResult {
    let k = zs.order;
    let nl = s.curve_points;
    let nt = s.theta_scan;
    let lam: Vec<f64> = (0..nl)
        // The last sample is the bound itself (rounding must not push it out of the box).
        .map(|j| {
            (zs.lambda.0 + (zs.lambda.1 - zs.lambda.0) * j as f64 / (nl - 1) as f64)
                .min(zs.lambda.1)
        })
        .collect();
    let th: Vec<f64> = (0..nt)
        .map(|j| {
            (zs.theta.0 + (zs.theta.1 - zs.theta.0) * j as f64 / (nt - 1) as f64).min(zs.theta.1)
        })
        .collect();
    let scan = Scan {
        alpha0,
        zs,
        series_power,
        margin,
        s,
        th,
    };
    let mut value = vec![vec![None; nt]; nl];
    let mut roots = Vec::new();
    let mut evals = 0usize;
    let mut bins: Vec<CosBin> = Vec::new();
    let mut single = true;
    for (r, &l) in lam.iter().enumerate() {
        let found = scan.column(l, &mut bins, &mut value[r], &mut roots, &mut evals);
        if found.is_some_and(|count| count > 1) {
            single = false;
        }
    }
    let th = scan.th;
    let (pos, neg, best) = signs(&value, &lam, &th);
    let folds = folds(&value, &lam, &th, &roots);
    let max_abs_at_root = roots.iter().fold(0.0f64, |m, z| m.max(z.value.abs()));
    let sign = if neg == 0 && pos > 0 {
        1
    } else if pos == 0 && neg > 0 {
        -1
    } else {
        0
    };
    let status = if pos + neg == 0 {
        ZeroStatus::Infeasible
    } else if roots.is_empty() {
        ZeroStatus::NoZero
    } else {
        ZeroStatus::Found
    };
    let mut reason = match status {
        ZeroStatus::Infeasible => "no (λ, θ) of the search box assembles with the required margin".to_string(),
        ZeroStatus::Found => format!(
            "a_{k} changes sign on the feasible grid ({pos} samples > 0, {neg} < 0); {} bracketed roots refined to \
             {:e} in θ; the zero set is {}",
            roots.len(),
            s.root_tol,
            if single { "a single-valued curve θ*(λ)" } else { "multi-valued in some columns (several branches)" }
        ),
        ZeroStatus::NoZero => {
            let b = best.unwrap();
            let lead = leading_terms_keep_sign(alpha0, k, &th);
            format!(
                "a_{k} keeps one sign ({}) at all {} feasible grid samples; min |a_{k}| = {:e} at λ = {}, θ = {} \
                 (on the boundary of the box: |a_{k}| grows with λ). {}",
                if sign > 0 { "> 0" } else { "< 0" },
                pos + neg,
                b.value.abs(),
                b.lambda,
                b.theta,
                lead
            )
        }
    };
    if folds > 0 {
        reason.push_str(&format!(
            "; {folds} sign changes along λ are not explained by a θ-root nearby (possible fold of the zero set)"
        ));
    }
    ZeroSearchResult {
        order: k,
        status,
        roots,
        single_valued: single,
        grid_min_abs: best,
        sign,
        reason,
        max_abs_at_root,
        evals,
        map: CoefficientMap {
            order: k,
            lambda: lam,
            theta: th,
            value,
        },
    }
}

/// Sign bookkeeping over the feasible grid: samples > 0, samples < 0, and the smallest |a|.
fn signs(value: &[Vec<Option<f64>>], lam: &[f64], th: &[f64]) -> (usize, usize, Option<GridMin>) {
    let mut pos = 0usize;
    let mut neg = 0usize;
    let mut best: Option<GridMin> = None;
    for (r, row) in value.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            if let Some(v) = *v {
                if v > 0.0 {
                    pos += 1;
                } else if v < 0.0 {
                    neg += 1;
                }
                if best.is_none_or(|b| v.abs() < b.value.abs()) {
                    best = Some(GridMin {
                        lambda: lam[r],
                        theta: th[c],
                        value: v,
                    });
                }
            }
        }
    }
    (pos, neg, best)
}

/// Sign changes along λ not explained by a root in either neighbouring column.
fn folds(value: &[Vec<Option<f64>>], lam: &[f64], th: &[f64], roots: &[ZeroRoot]) -> usize {
    let mut folds = 0;
    for r in 0..lam.len().saturating_sub(1) {
        for c in 0..th.len() {
            if let (Some(a), Some(b)) = (value[r][c], value[r + 1][c]) {
                if a.signum() != b.signum() {
                    let near = roots.iter().any(|z| {
                        (z.lambda == lam[r] || z.lambda == lam[r + 1])
                            && (z.theta - th[c]).abs() <= 1.5 * (th[1] - th[0])
                    });
                    if !near {
                        folds += 1;
                    }
                }
            }
        }
    }
    folds
}

/// The series a_k = −Σ_p c_p λ^{2p−1} [y^{2p}]_k: report whether the first two terms
/// (λ¹ and λ³) have the same sign at every θ of the grid, which is why a_k cannot vanish for
/// small λ.
fn leading_terms_keep_sign(alpha0: f64, k: usize, th: &[f64]) -> String {
    // [y²]_k and [y⁴]_k from the series with λ = 1 (power 1 and power 2 differences).
    let mut same = true;
    let mut sgn = 0.0;
    for &t in th {
        let m = Hypocycloid {
            lambda: 1.0,
            theta: t,
            alpha0,
        };
        let p0 = m.series_coefficients(1, k).0[k] - if k == 1 { 1.0 } else { 0.0 };
        let x2 = if k == 2 { t * alpha0.cos() } else { 0.0 };
        let t1 = p0 - x2; // −½[y²]_k
        let t3 = m.series_coefficients(2, k).0[k] - m.series_coefficients(1, k).0[k]; // −⅛[y⁴]_k
        for v in [t1, t3] {
            if v != 0.0 && v.abs() > 1e-15 {
                if sgn == 0.0 {
                    sgn = v.signum();
                } else if v.signum() != sgn {
                    same = false;
                }
            }
        }
    }
    if same {
        format!(
            "The λ¹ and λ³ terms of the binomial series, −½λ[y²]_{k} and −⅛λ³[y⁴]_{k}, have the same sign at every \
             θ of the grid, so they add instead of cancelling"
        )
    } else {
        "The λ¹ and λ³ terms of the series change sign over θ; no zero was found on the grid nevertheless".to_string()
    }
}
