//! Shared 1-D numerics: bracketing root finding, bounded maximisation and the refined
//! peak of a periodic function.
//!
//! Every family needs "locate this to 1e-12 in one variable" (a root of C4, a pole of µ, a
//! local maximum of |F|). These functions take plain closures, so that a model module only
//! writes `f(x)`, and they never panic: a failure is a value. Roots go through argmin's
//! Brent solver; maxima through a direct Brent search (see [`brent_max`]).

use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::brent::{BrentOpt, BrentRoot};

mod peaks;
pub use peaks::{
    interval_peak, interval_peak_with, periodic_peak, periodic_peak_sampled,
    periodic_peak_unrefined, periodic_peak_with, IntervalPeak, PeriodicPeak, Refine, Shape,
};

/// A closure as an argmin cost function.
struct FnCost<F>(F);

impl<F: Fn(f64) -> f64> CostFunction for FnCost<F> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, x: &f64) -> Result<f64, ArgminError> {
        Ok((self.0)(*x))
    }
}

/// A root located by [`brent_root`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Root {
    /// The root's abscissa.
    pub x: f64,
    /// The function's value there.
    pub fx: f64,
    /// Function evaluations spent.
    pub evals: u64,
}

/// Why a 1-D search did not return a value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SearchError {
    /// `f(a)` and `f(b)` have the same sign: there is no bracket.
    #[error("no sign change on [{a:e}, {b:e}]: f(a) = {fa:e}, f(b) = {fb:e}")]
    NotBracketed { a: f64, b: f64, fa: f64, fb: f64 },
    /// The function returned NaN or an infinity inside the interval.
    #[error("the function is not finite at x = {x}")]
    NotFinite { x: f64 },
    /// The solver itself failed.
    #[error("1-D solver failed: {0}")]
    Solver(String),
}

/// The checks of a bracket `[a, b]` before a root search: a non-finite end value is an error,
/// an end where f = 0 is the root, and ends of one sign are not a bracket.
fn bracket_ends(a: f64, fa: f64, b: f64, fb: f64) -> Result<Option<Root>, SearchError> {
    for (x, v) in [(a, fa), (b, fb)] {
        if !v.is_finite() {
            return Err(SearchError::NotFinite { x });
        }
    }
    for (x, v) in [(a, fa), (b, fb)] {
        if v == 0.0 {
            return Ok(Some(Root {
                x,
                fx: 0.0,
                evals: 2,
            }));
        }
    }
    if fa.signum() == fb.signum() {
        return Err(SearchError::NotBracketed { a, b, fa, fb });
    }
    Ok(None)
}

/// Root of `f` on the bracket `[a, b]` (`f(a)·f(b) ≤ 0`) by Brent's method (argmin's
/// [`BrentRoot`]) to an absolute tolerance `tol` in x.
pub fn brent_root<F: Fn(f64) -> f64>(f: F, a: f64, b: f64, tol: f64) -> Result<Root, SearchError> {
    let (fa, fb) = (f(a), f(b));
    if let Some(end) = bracket_ends(a, fa, b, fb)? {
        return Ok(end);
    }
    let count = std::cell::Cell::new(0u64);
    let fc = |x: f64| {
        count.set(count.get() + 1);
        f(x)
    };
    let solver = BrentRoot::new(a, b, tol);
    let res = Executor::new(FnCost(&fc), solver)
        .configure(|s| s.param(0.5 * (a + b)).max_iters(200))
        .run()
        .map_err(|e| SearchError::Solver(e.to_string()))?;
    let st = res.state();
    let x = *st
        .get_best_param()
        .ok_or(SearchError::Solver("no root returned".into()))?;
    let fx = f(x);
    if !fx.is_finite() {
        return Err(SearchError::NotFinite { x });
    }
    Ok(Root {
        x,
        fx,
        evals: count.get() + 3,
    })
}

/// Root of `f` on the bracket `[a, b]` (`f(a)·f(b) ≤ 0`) by Newton's method safeguarded by
/// bisection (Numerical Recipes' `rtsafe`), to an absolute tolerance `tol` in x. `f` returns
/// (f(x), f'(x)); a Newton step that leaves the current bracket, or does not halve the
/// step before last, is replaced by a bisection, so a kink (a one-sided derivative) costs
/// bisections, never convergence. For functions whose derivative is free, e.g. a peak's
/// derivative in a parameter by the envelope theorem.
pub fn newton_root<F: Fn(f64) -> (f64, f64)>(
    f: F,
    a: f64,
    b: f64,
    tol: f64,
) -> Result<Root, SearchError> {
    let ((fa, _), (fb, _)) = (f(a), f(b));
    if let Some(end) = bracket_ends(a, fa, b, fb)? {
        return Ok(end);
    }
    // Orient so that f(lo) < 0 < f(hi).
    let (mut lo, mut hi) = if fa < 0.0 { (a, b) } else { (b, a) };
    let mut x = 0.5 * (a + b);
    let (mut dx_old, mut dx) = ((b - a).abs(), (b - a).abs());
    let (mut fx, mut dfx) = f(x);
    let mut evals = 3;
    for _ in 0..200 {
        if !(fx.is_finite() && dfx.is_finite()) {
            return Err(SearchError::NotFinite { x });
        }
        let newton_out = ((x - hi) * dfx - fx) * ((x - lo) * dfx - fx) > 0.0;
        if newton_out || (2.0 * fx).abs() > (dx_old * dfx).abs() {
            dx_old = dx;
            dx = 0.5 * (hi - lo);
            x = lo + dx;
        } else {
            dx_old = dx;
            dx = fx / dfx;
            x -= dx;
        }
        if dx.abs() < tol {
            break;
        }
        (fx, dfx) = f(x);
        evals += 1;
        if fx < 0.0 {
            lo = x;
        } else if fx > 0.0 {
            hi = x;
        } else {
            break;
        }
    }
    let fx = f(x).0;
    if !fx.is_finite() {
        return Err(SearchError::NotFinite { x });
    }
    Ok(Root { x, fx, evals })
}

/// Newton's method from a start `x0` already close to a root (e.g. the root of a cheaper
/// approximation of `f`), without a bracket search: at most `max_steps` steps, each of
/// which must stay in [a, b] and at least halve the previous one (quadratic convergence
/// does far better). `None` when a step breaks that, a value or derivative is not finite
/// or the derivative is zero, or the steps do not get below `tol` — the caller then falls
/// back to [`newton_root`]. `Root::fx` is f at the last evaluated point, one step (< `tol`)
/// before `x`.
pub fn newton_polish<F: Fn(f64) -> (f64, f64)>(
    f: F,
    x0: f64,
    a: f64,
    b: f64,
    tol: f64,
    max_steps: usize,
) -> Option<Root> {
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    let (mut x, mut last) = (x0, f64::INFINITY);
    for evals in 1..=max_steps as u64 {
        let (fx, dfx) = f(x);
        if !(fx.is_finite() && dfx.is_finite()) || dfx == 0.0 {
            return None;
        }
        let dx = fx / dfx;
        if fx == 0.0 || dx.abs() < tol {
            return Some(Root {
                x: x - dx,
                fx,
                evals,
            });
        }
        let shrinks = dx.abs() <= 0.5 * last;
        if !(shrinks && x - dx >= lo && x - dx <= hi) {
            return None;
        }
        (x, last) = (x - dx, dx.abs());
    }
    None
}

/// A maximum located by [`brent_max`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extremum {
    /// Abscissa of the maximum.
    pub x: f64,
    /// Value of the function there.
    pub fx: f64,
}

/// Maximum of a unimodal `f` on `[a, b]` by Brent's parabolic/golden search, to an
/// absolute tolerance `xtol` in x (plus 1e-14 relative). The returned value is never below
/// `max(f(a), f(b))`.
///
/// This is Brent's `fmin` (Algorithms for Minimization without Derivatives, 1973) on −f,
/// written out rather than driven through argmin's `Executor`: it runs in the innermost
/// loop (every local maximum of every exchange round), where the executor's per-call state,
/// hashing and allocation cost more than the function evaluations. argmin drives the outer
/// searches.
pub fn brent_max<F: Fn(f64) -> f64>(
    f: F,
    a: f64,
    b: f64,
    xtol: f64,
) -> Result<Extremum, SearchError> {
    const CGOLD: f64 = 0.381_966_011_250_105_1;
    let g = |x: f64| -f(x);
    let (mut a, mut b) = if a <= b { (a, b) } else { (b, a) };
    let (a0, b0) = (a, b);
    let (fa0, fb0) = (f(a0), f(b0));
    let mut x = a + CGOLD * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = g(x);
    if !fx.is_finite() {
        return Err(SearchError::NotFinite { x });
    }
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e): (f64, f64) = (0.0, 0.0);
    for _ in 0..200 {
        let xm = 0.5 * (a + b);
        let tol1 = 1e-14 * x.abs() + xtol / 3.0;
        let tol2 = 2.0 * tol1;
        if (x - xm).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 {
            // Parabola through x, w, v.
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            let etemp = e;
            e = d;
            if p.abs() < (0.5 * q * etemp).abs() && p > q * (a - x) && p < q * (b - x) {
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = if xm >= x { tol1 } else { -tol1 };
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= xm { a - x } else { b - x };
            d = CGOLD * e;
        }
        let u = if d.abs() >= tol1 {
            x + d
        } else {
            x + tol1.copysign(d)
        };
        let fu = g(u);
        if !fu.is_finite() {
            return Err(SearchError::NotFinite { x: u });
        }
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    let mut best = Extremum { x, fx: -fx };
    for (e, fe) in [(a0, fa0), (b0, fb0)] {
        if fe > best.fx {
            best = Extremum { x: e, fx: fe };
        }
    }
    Ok(best)
}

/// A maximum of a 2π-periodic f refined from its sampled maximum at c with `ys` = f at
/// c − h, c, c + h, as [`refine_sampled_max`] does, the angle wrapped into [0, 2π) and the
/// value never below the sample's: how [`Shape::peak`] refines each candidate (and a caller
/// that refines one known sample the same way gets the same numbers).
pub fn refine_periodic_sample<F: Fn(f64) -> f64>(
    f: F,
    c: f64,
    h: f64,
    ys: [f64; 3],
    xtol: f64,
) -> Result<(Extremum, usize), SearchError> {
    let (e, used) = refine_sampled_max(f, c, h, ys, xtol)?;
    Ok((
        Extremum {
            x: e.x.rem_euclid(std::f64::consts::TAU),
            fx: e.fx.max(ys[1]),
        },
        used,
    ))
}

/// Refines a sampled local maximum: `c` is a sample not below its neighbours, `ys` =
/// [f(c − h), f(c), f(c + h)] their known values, f unimodal on [c − h, c + h]. Returns the
/// maximum to `xtol` in x (plus 1e-14 relative), or to the round-off limit δ =
/// sqrt(8ε|f|/|C|) (C = f''/2 estimated from the samples) where that is larger — within δ
/// of the maximum the values differ from it by at most 8ε|f|, so the value is exact to
/// round-off either way — and the evaluations spent.
///
/// Safeguarded parabolic interpolation, as in Brent's `fmin`, but started from the scan's
/// three samples: a bracket a < x < b holds the maximum (x the best point so far, w and v
/// the next best, which start as the samples at c ∓ h); each step evaluates the vertex of
/// the parabola through x, w, v, u = x − ½[(x−w)²(f_x−f_v) − (x−v)²(f_x−f_w)] /
/// [(x−w)(f_x−f_v) − (x−v)(f_x−f_w)], and shrinks the bracket around the better point.
/// A vertex within `xtol` of x, or one that would gain only round-off (|C|·(u − x)² ≤ 4ε|f|,
/// C the parabola's leading coefficient), probes x ± `xtol` on the longer side instead,
/// which closes the bracket; a vertex outside it, or a bracket that has not halved in three steps (a
/// kink, a flat top), takes a golden step into the longer side, so the bracket shrinks at
/// least linearly. It stops when both sides are within the tolerance: for a unimodal f the
/// maximum is certified within [a, b] (or, where a probe gained only round-off, its value
/// is exact to round-off). Brent's `fmin` starts from one interior point and
/// needs golden steps to build its parabola; from the samples, a smooth maximum takes
/// about five evaluations instead of about fifteen.
pub fn refine_sampled_max<F: Fn(f64) -> f64>(
    f: F,
    c: f64,
    h: f64,
    ys: [f64; 3],
    xtol: f64,
) -> Result<(Extremum, usize), SearchError> {
    const CGOLD: f64 = 0.381_966_011_250_105_1;
    let [fl, fc, fr] = ys;
    if !(fc >= fl && fc >= fr) {
        return Err(SearchError::Solver(format!(
            "refine_sampled_max: the sample at {c} is not a sampled maximum"
        )));
    }
    let (mut a, mut b) = (c - h, c + h);
    let (mut x, mut fx) = (c, fc);
    let ((mut w, mut fw), (mut v, mut fv)) = if fl >= fr {
        ((a, fl), (b, fr))
    } else {
        ((b, fr), (a, fl))
    };
    // Below δ = sqrt(8ε|f|/|C|) (C = f''/2 from the samples) the values near the maximum
    // differ from it only by round-off, |C|δ² = 8ε|f|: x cannot be located closer from
    // values, and the value is exact to round-off there. Not below that.
    let c0 = (fl - 2.0 * fc + fr).abs() / (2.0 * h * h);
    let noise = if c0 > 0.0 {
        (8.0 * f64::EPSILON * fc.abs() / c0).sqrt()
    } else {
        0.0
    };
    let tol = (xtol + 1e-14 * c.abs()).max(noise);
    let mut widths = [f64::INFINITY; 3];
    let mut evals = 0;
    for step in 0..400 {
        let (d1, d2) = (x - a, b - x);
        if d1 <= tol && d2 <= tol {
            break;
        }
        let stalled = b - a > 0.5 * widths[step % 3];
        widths[step % 3] = b - a;
        let golden = || {
            if d2 >= d1 {
                x + CGOLD * d2
            } else {
                x - CGOLD * d1
            }
        };
        let probe = || {
            if d2 >= d1 {
                x + tol.min(0.5 * d2)
            } else {
                x - tol.min(0.5 * d1)
            }
        };
        let (r, q) = ((x - w) * (fx - fv), (x - v) * (fx - fw));
        let den = r - q;
        // The vertex of the parabola through x, w, v and its gain over f(x), |C|·(u − x)²
        // with C the parabola's leading coefficient (none when the points are collinear).
        let vertex = (den != 0.0).then(|| {
            let u = x - 0.5 * ((x - w) * r - (x - v) * q) / den;
            let curv = ((fw - fx) / (w - x) - (fv - fx) / (v - x)) / (w - v);
            (u, (curv * (u - x) * (u - x)).abs())
        });
        let flat = fx == fw && fx == fv;
        let converged = match vertex {
            Some((u, gain)) => (u - x).abs() < tol || gain <= 4.0 * f64::EPSILON * fx.abs(),
            None => flat,
        };
        let u = match vertex {
            // Nothing left to gain (or flat to the last bit where sampled): close the bracket.
            _ if converged => probe(),
            Some((u, _)) if !stalled && u > a && u < b => {
                // At least `tol` away from the ends.
                u.clamp(a + tol.min(0.5 * d1), b - tol.min(0.5 * d2))
            }
            _ => golden(),
        };
        let fu = f(u);
        evals += 1;
        if !fu.is_finite() {
            return Err(SearchError::NotFinite { x: u });
        }
        // A probe that gains only round-off (a few ulps of f) closes its side: the value is
        // then exact to round-off, and the search does not wander in the noise.
        let gain = if converged {
            4.0 * f64::EPSILON * fx.abs()
        } else {
            0.0
        };
        if fu > fx + gain {
            if u > x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u > x {
                b = u;
            } else {
                a = u;
            }
            if fu > fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu > fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    Ok((Extremum { x, fx }, evals))
}

/// A minimum located by [`minimize_1d`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Minimum {
    /// Abscissa.
    pub x: f64,
    /// Value.
    pub fx: f64,
    /// Function evaluations spent.
    pub evals: u64,
}

/// Minimum of a unimodal `f` on `[a, b]` by argmin's [`BrentOpt`] to an absolute tolerance
/// `xtol` in x: for outer design searches (the inner peak loops use [`brent_max`]).
pub fn minimize_1d<F: Fn(f64) -> f64>(
    f: F,
    a: f64,
    b: f64,
    xtol: f64,
) -> Result<Minimum, SearchError> {
    if !(a < b) {
        let fa = f(a);
        return if fa.is_finite() {
            Ok(Minimum {
                x: a,
                fx: fa,
                evals: 1,
            })
        } else {
            Err(SearchError::NotFinite { x: a })
        };
    }
    let count = std::cell::Cell::new(0u64);
    let fc = |x: f64| {
        count.set(count.get() + 1);
        f(x)
    };
    let res = Executor::new(FnCost(&fc), BrentOpt::new(a, b).set_tolerance(1e-14, xtol))
        .configure(|s| s.max_iters(200))
        .run()
        .map_err(|e| SearchError::Solver(e.to_string()))?;
    let st = res.state();
    let x = *st
        .get_best_param()
        .ok_or(SearchError::Solver("no minimum returned".into()))?;
    let fx = f(x);
    if !fx.is_finite() {
        return Err(SearchError::NotFinite { x });
    }
    let evals = count.get();
    // The ends, in case the minimum is on the boundary.
    let (fa, fb) = (f(a), f(b));
    let best = [(x, fx), (a, fa), (b, fb)]
        .into_iter()
        .filter(|p| p.1.is_finite())
        .min_by(|p, q| p.1.total_cmp(&q.1))
        .unwrap();
    Ok(Minimum {
        x: best.0,
        fx: best.1,
        evals: evals + 3,
    })
}

/// Mean and RMS of a 2π-periodic function by the trapezoid rule on `n` points, which is
/// spectrally accurate for smooth periodic functions; the error estimate is the change from
/// `n/2` points (an over-estimate once the rule has converged).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeriodicRms {
    /// sqrt(mean(f²)).
    pub rms: f64,
    /// |rms(n) − rms(n/2)|.
    pub error: f64,
}

/// RMS of a periodic function (see [`PeriodicRms`]); `n` is rounded up to an even number.
pub fn periodic_rms<F: Fn(f64) -> f64>(f: F, n: usize) -> PeriodicRms {
    let n = (n.max(8) + 1) & !1;
    let h = std::f64::consts::TAU / n as f64;
    let ys: Vec<f64> = (0..n).map(|k| f(k as f64 * h)).collect();
    periodic_rms_sampled(&ys)
}

/// [`periodic_rms`] of samples already taken, `ys[k] = f(2πk/n)`, n = `ys.len()` even.
pub fn periodic_rms_sampled(ys: &[f64]) -> PeriodicRms {
    let n = ys.len();
    let (mut even, mut odd) = (0.0, 0.0);
    for (k, y) in ys.iter().enumerate() {
        if k % 2 == 0 {
            even += y * y;
        } else {
            odd += y * y;
        }
    }
    let full = ((even + odd) / n.max(1) as f64).sqrt();
    let half = (even / (n / 2).max(1) as f64).sqrt();
    PeriodicRms {
        rms: full,
        error: (full - half).abs(),
    }
}

/// Test helper: a deterministic stream of numbers uniform in [−1, 1) (a 64-bit LCG, Knuth's
/// MMIX constants), for randomised tests that must not depend on a crate or a seed file.
#[cfg(test)]
pub(crate) fn uniform_pm1(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn root_of_cosine_is_half_pi() {
        let r = brent_root(f64::cos, 1.0, 2.0, 1e-14).unwrap();
        assert!((r.x - std::f64::consts::FRAC_PI_2).abs() < 1e-13);
    }

    #[test]
    fn unbracketed_root_is_an_error() {
        assert!(matches!(
            brent_root(|x| x * x + 1.0, -1.0, 1.0, 1e-12),
            Err(SearchError::NotBracketed { .. })
        ));
        assert!(matches!(
            brent_root(|_| f64::NAN, -1.0, 1.0, 1e-12),
            Err(SearchError::NotFinite { .. })
        ));
    }

    #[test]
    fn peak_of_two_harmonics_matches_closed_form() {
        // f = cos φ + 0.5 cos 2φ: maxima 1.5 at 0 and −0.5 at π (f'' = 1 − 4·0.5 < 0 there);
        // its minima are at cos φ = −1/2.
        let p = periodic_peak(|x| x.cos() + 0.5 * (2.0 * x).cos(), 36, 1e-10).unwrap();
        assert!((p.peak.fx - 1.5).abs() < 1e-15);
        assert_eq!(p.maxima.len(), 2);
        // A maximum is flat: its abscissa is only defined to ~sqrt(ε), its value to ε.
        let low = p
            .maxima
            .iter()
            .min_by(|a, b| a.fx.total_cmp(&b.fx))
            .unwrap();
        assert!((low.x - std::f64::consts::PI).abs() < 1e-6);
        assert!((low.fx + 0.5).abs() < 1e-15);
        // 3 sin φ peaks at π/2 exactly, between samples of a 7-point grid.
        let p = periodic_peak(|x| 3.0 * x.sin(), 7, 1e-10).unwrap();
        assert!((p.peak.x - std::f64::consts::FRAC_PI_2).abs() < 1e-8);
        assert!((p.peak.fx - 3.0).abs() < 1e-15);
    }

    #[test]
    fn brent_max_finds_interior_and_end_maxima() {
        // x e^{-x} peaks at x = 1 with value 1/e.
        let m = brent_max(|x| x * (-x).exp(), 0.0, 3.0, 1e-12).unwrap();
        assert!((m.fx - (-1f64).exp()).abs() < 1e-16);
        assert!((m.x - 1.0).abs() < 1e-7);
        // Monotone: the maximum is the right end.
        let m = brent_max(|x| x, 0.0, 2.0, 1e-12).unwrap();
        assert_eq!((m.x, m.fx), (2.0, 2.0));
        assert!(matches!(
            brent_max(|_| f64::NAN, 0.0, 1.0, 1e-9),
            Err(SearchError::NotFinite { .. })
        ));
    }

    #[test]
    fn rms_of_sine_is_one_over_root_two() {
        let r = periodic_rms(|x| x.sin() + 0.5, 64);
        assert!((r.rms - (0.5f64 + 0.25).sqrt()).abs() < 1e-14);
    }
    #[test]
    fn interval_peak_finds_interior_and_end_maxima() {
        // f = sin x on [0, 3]: single interior maximum 1 at π/2.
        let p = interval_peak(f64::sin, 0.0, 3.0, 7, 1e-10).unwrap();
        assert!((p.peak.fx - 1.0).abs() < 1e-15);
        assert!((p.peak.x - std::f64::consts::FRAC_PI_2).abs() < 1e-7);
        // f = x² on [−1, 2]: maxima at both ends, 1 at −1 and 4 at 2; the minimum at 0 is not one.
        let p = interval_peak(|x| x * x, -1.0, 2.0, 9, 1e-10).unwrap();
        assert_eq!(p.maxima.len(), 2);
        assert_eq!(p.peak.x, 2.0);
        assert_eq!(p.peak.fx, 4.0);
        assert!((p.maxima[0].x + 1.0).abs() < 1e-12 && (p.maxima[0].fx - 1.0).abs() < 1e-12);
        // A maximum next to an end point but inside the first interval: −(x − 0.05)² on [0, 1].
        let p = interval_peak(|x| -(x - 0.05) * (x - 0.05), 0.0, 1.0, 4, 1e-10).unwrap();
        assert!(p.peak.fx.abs() < 1e-15 && (p.peak.x - 0.05).abs() < 1e-7);
        assert!(matches!(
            interval_peak(|_| f64::NAN, 0.0, 1.0, 4, 1e-9),
            Err(SearchError::NotFinite { .. })
        ));
    }

    /// A random trigonometric polynomial Σ_{k=1..12} a_k cos kx + b_k sin kx, coefficients
    /// uniform in [−1, 1] (several near-equal maxima).
    fn random_trig(rnd: &mut impl FnMut() -> f64) -> impl Fn(f64) -> f64 + Copy {
        let mut c = [(0.0, 0.0); 12];
        for ck in &mut c {
            *ck = (rnd(), rnd());
        }
        move |x: f64| {
            c.iter()
                .enumerate()
                .map(|(k, (a, b))| {
                    let t = (k + 1) as f64 * x;
                    a * t.cos() + b * t.sin()
                })
                .sum::<f64>()
        }
    }

    /// [`random_trig`] and its samples on the grid of `periodic_peak` with n = 360: φ_k = k·h,
    /// h = 2π/n (the refinement starts from the samples, so they must be at the very same
    /// abscissae).
    fn random_trig_on_grid(
        rnd: &mut impl FnMut() -> f64,
    ) -> (impl Fn(f64) -> f64 + Copy, Vec<f64>, f64) {
        let f = random_trig(rnd);
        let h = std::f64::consts::TAU / 360.0;
        (f, (0..360).map(|k| f(k as f64 * h)).collect(), h)
    }

    #[test]
    fn peak_only_refinement_finds_the_same_peak_as_refining_all() {
        // Random trigonometric polynomials of order ≤ 12 (several near-equal maxima): the
        // pruned refinement must return the very peak of the full one, and the sampled
        // variant must equal the one that samples itself.
        let mut rnd = uniform_pm1(0x9e37_79b9_7f4a_7c15);
        for _ in 0..200 {
            let (f, ys, _) = random_trig_on_grid(&mut rnd);
            let all = periodic_peak(f, ys.len(), 1e-10).unwrap();
            let same = periodic_peak_sampled(&ys, f, Some(1e-10), Refine::All).unwrap();
            let pruned = periodic_peak_sampled(&ys, f, Some(1e-10), Refine::PeakOnly).unwrap();
            assert_eq!(
                (&all.maxima, all.peak, all.evals),
                (&same.maxima, same.peak, same.evals)
            );
            assert!((all.error - same.error).abs() <= 1e-12 * all.error);
            assert_eq!(
                pruned.peak, all.peak,
                "{:?}\n{:?}",
                pruned.maxima, all.maxima
            );
            assert!(pruned.maxima.len() <= all.maxima.len());
        }
    }

    #[test]
    fn sampled_refinement_matches_brent_with_fewer_evaluations() {
        // Every sampled maximum of random trigonometric polynomials (order ≤ 12), refined from
        // its three samples and by Brent's fmin on the same bracket (a different algorithm,
        // started from scratch): the values agree to round-off plus the tolerance's bound
        // ½|f''|xtol², and the refinement needs far fewer evaluations on average.
        let mut rnd = uniform_pm1(0x2545_f491_4f6c_dd1d);
        let (mut ours, mut brents, mut count) = (0usize, 0usize, 0usize);
        for _ in 0..100 {
            let (f, ys, h) = random_trig_on_grid(&mut rnd);
            let n = ys.len();
            for k in 0..n {
                let around = [ys[(k + n - 1) % n], ys[k], ys[(k + 1) % n]];
                if !(around[1] >= around[0] && around[1] > around[2]) {
                    continue;
                }
                let x0 = k as f64 * h;
                for xtol in [1e-8, 1e-10] {
                    let (e, used) = refine_sampled_max(f, x0, h, around, xtol).unwrap();
                    let evals = std::cell::Cell::new(0usize);
                    let b = brent_max(
                        |x| {
                            evals.set(evals.get() + 1);
                            f(x)
                        },
                        x0 - h,
                        x0 + h,
                        xtol,
                    )
                    .unwrap();
                    // Round-off of the 24-term sum (≤ 24ε·Σ(|a| + |b|) ≤ 24ε·24, doubled for
                    // both values) plus the tolerance's bound: |f''| ≤ Σ k²(|a| + |b|) ≤ 1300.
                    let bound = 2.0 * 24.0 * 24.0 * f64::EPSILON + 650.0 * xtol * xtol;
                    assert!((e.fx - b.fx).abs() <= bound, "{e:?} vs {b:?}");
                    assert!((e.x - b.x).abs() <= 1e-6, "{e:?} vs {b:?}");
                    ours += used;
                    brents += evals.get();
                    count += 1;
                }
            }
        }
        let (mean, mean_brent) = (ours as f64 / count as f64, brents as f64 / count as f64);
        assert!(
            mean <= 8.0 && mean < 0.6 * mean_brent,
            "{mean} vs Brent {mean_brent}"
        );
    }

    #[test]
    fn sampled_refinement_survives_kinks_flat_tops_and_bad_input() {
        let h = 0.02;
        // A kink (no parabola fits): golden steps still close the bracket to xtol.
        let f = |x: f64| -(x - 0.013).abs();
        let (e, used) = refine_sampled_max(f, 0.02, h, [f(0.0), f(0.02), f(0.04)], 1e-9).unwrap();
        assert!((e.x - 0.013).abs() <= 2e-9 && used < 80, "{e:?} {used}");
        // A flat top: nothing to gain, the bracket closes at once.
        let (e, used) = refine_sampled_max(|_| 2.5, 1.0, h, [2.5; 3], 1e-9).unwrap();
        assert_eq!(e.fx, 2.5);
        assert!(used <= 4, "{used}");
        // Not a sampled maximum, or a NaN inside: errors, not panics or NaN results.
        assert!(refine_sampled_max(|x| x, 1.0, h, [0.98, 1.0, 1.02], 1e-9).is_err());
        assert!(matches!(
            refine_sampled_max(|_| f64::NAN, 1.0, h, [0.0, 1.0, 0.0], 1e-9),
            Err(SearchError::NotFinite { .. })
        ));
    }

    #[test]
    fn extremes_in_one_pass_equal_the_peaks_of_f_and_of_minus_f() {
        // The one-pass extremes against two separate peak searches, the second on a negated
        // copy of the samples (the way they were computed before).
        let mut rnd = uniform_pm1(0x0123_4567_89ab_cdef);
        for _ in 0..50 {
            let (f, ys, _) = random_trig_on_grid(&mut rnd);
            let neg: Vec<f64> = ys.iter().map(|y| -y).collect();
            for (xtol, refine) in [(Some(1e-8), Refine::PeakOnly), (None, Refine::All)] {
                let shape = Shape::of(&ys, true, refine).unwrap();
                let (mx, mn) = (
                    shape.peak(&ys, 1.0, f, xtol).unwrap(),
                    shape.peak(&ys, -1.0, f, xtol).unwrap(),
                );
                let mx2 = periodic_peak_sampled(&ys, f, xtol, refine).unwrap();
                let mn2 = periodic_peak_sampled(&neg, |x| -f(x), xtol, refine).unwrap();
                assert_eq!((mx.peak, mn.peak), (mx2.peak, mn2.peak));
                assert_eq!(mn.maxima.len(), mn2.maxima.len());
            }
        }
        let flat = [1.0; 16];
        let shape = Shape::of(&flat, true, Refine::All).unwrap();
        let (mx, mn) = (
            shape.peak(&flat, 1.0, |_| 1.0, Some(1e-9)).unwrap(),
            shape.peak(&flat, -1.0, |_| 1.0, Some(1e-9)).unwrap(),
        );
        assert_eq!((mx.peak.fx, mn.peak.fx), (1.0, -1.0));
    }

    #[test]
    fn newton_polish_finishes_close_starts_and_declines_far_ones() {
        // x³ − 2 from 1.3 (the cube root of 2 is 1.2599…): quadratic convergence.
        let cube = |x: f64| (x * x * x - 2.0, 3.0 * x * x);
        let r = newton_polish(cube, 1.3, 0.0, 3.0, 1e-14, 8).unwrap();
        assert!((r.x - 2f64.cbrt()).abs() < 1e-14 && r.evals <= 5, "{r:?}");
        // atan from 1.5: Newton overshoots and diverges; polish declines instead.
        assert!(newton_polish(
            |x: f64| (x.atan(), 1.0 / (1.0 + x * x)),
            1.5,
            -10.0,
            10.0,
            1e-12,
            8
        )
        .is_none());
        // A step out of the bracket, a zero derivative, too few steps: None.
        assert!(newton_polish(cube, 1.3, 1.28, 3.0, 1e-14, 8).is_none());
        assert!(newton_polish(|x: f64| (x * x - 1.0, 2.0 * x), 0.0, -2.0, 2.0, 1e-12, 8).is_none());
        assert!(newton_polish(cube, 3.0, 0.0, 3.0, 1e-14, 2).is_none());
    }

    #[test]
    fn newton_root_matches_closed_forms_and_survives_a_kink() {
        // x³ − 2 on [0, 3]: the cube root of 2.
        let r = newton_root(|x| (x * x * x - 2.0, 3.0 * x * x), 0.0, 3.0, 1e-14).unwrap();
        assert!((r.x - 2f64.cbrt()).abs() < 1e-13, "{}", r.x);
        assert!(r.evals < 15, "{} evaluations", r.evals);
        // A convex kinked function max(2x − 1, x/2 − 0.25) − 0.1 (root at x = 0.55, on the
        // steep branch) with the derivative of the active branch.
        let k = |x: f64| {
            if 2.0 * x - 1.0 >= 0.5 * x - 0.25 {
                (2.0 * x - 1.1, 2.0)
            } else {
                (0.5 * x - 0.35, 0.5)
            }
        };
        let r = newton_root(k, -2.0, 2.0, 1e-13).unwrap();
        assert!((r.x - 0.55).abs() < 1e-12, "{}", r.x);
        assert!(matches!(
            newton_root(|x| (x * x + 1.0, 2.0 * x), -1.0, 1.0, 1e-12),
            Err(SearchError::NotBracketed { .. })
        ));
    }
}
