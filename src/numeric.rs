//! Shared 1-D numerics: bracketing root finding, bounded maximisation and the refined
//! peak of a periodic function.
//!
//! Every family needs "locate this to 1e-12 in one variable" (a root of C4, a pole of µ, a
//! local maximum of |F|). These functions take plain closures, so that a model module only
//! writes `f(x)`, and they never panic: a failure is a value. Roots go through argmin's
//! Brent solver; maxima through a direct Brent search (see [`brent_max`]).

use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::brent::{BrentOpt, BrentRoot};

mod parallel;
mod peaks;
pub use parallel::{ordered, AngleMemo};
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
