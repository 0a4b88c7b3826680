//! The refined peak of a sampled function: of a 2π-periodic function ([`periodic_peak`],
//! from the [`Shape`] of its samples on a uniform grid) and of a function on an interval
//! ([`interval_peak`]), every sampled local maximum refined by Brent, with a bound on the
//! value's error.

use super::{brent_max, refine_periodic_sample, Extremum, SearchError};

/// The refined maxima of a 2π-periodic function.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicPeak {
    /// Every refined local maximum `(φ in [0, 2π), value)`, sorted by φ.
    pub maxima: Vec<Extremum>,
    /// The largest of them.
    pub peak: Extremum,
    /// Bound on |true peak − `peak.fx`|: the refinement tolerance (the value error of a
    /// maximum located to `xtol` is ½·|f''|·xtol², |f''| estimated from the samples) plus
    /// the round-off of evaluating f, taken as 16 ulp of the peak.
    pub error: f64,
    /// Function evaluations spent.
    pub evals: usize,
}

/// Which sampled local maxima [`periodic_peak_sampled`] refines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refine {
    /// Every local maximum (the exchange loop needs them all).
    All,
    /// Only those that can be the peak: a local maximum lies within h = 2π/n of its
    /// sample, so it exceeds the sample by at most ½·|f''|·h²; a candidate whose sample plus
    /// 2·|f''|·h² (four times that, for the estimate of |f''|) is below the best sample
    /// cannot be the peak and is skipped. The peak is the same as with `All`.
    PeakOnly,
}

/// Peak of a 2π-periodic `f`: sample `n` equally spaced angles, take every sample that is
/// not below its two neighbours as a candidate, and refine each on its two neighbouring
/// intervals by Brent to `xtol`. A maximum narrower than `2π/n` can be missed; callers pick
/// `n` for their function's bandwidth and test the choice.
pub fn periodic_peak<F: Fn(f64) -> f64>(
    f: F,
    n: usize,
    xtol: f64,
) -> Result<PeriodicPeak, SearchError> {
    periodic_peak_with(f, n, Some(xtol))
}

/// [`periodic_peak`] without the refinement: the largest sample is the peak. A smooth
/// maximum lies within h/2 = π/n of a sample, so the sampled peak is low by at most
/// ½|f''|(h/2)² = |f''|h²/8 (|f''| estimated from the samples), which is the `error`.
pub fn periodic_peak_unrefined<F: Fn(f64) -> f64>(
    f: F,
    n: usize,
) -> Result<PeriodicPeak, SearchError> {
    periodic_peak_with(f, n, None)
}

/// [`periodic_peak`] (`Some(xtol)`) or [`periodic_peak_unrefined`] (`None`).
pub fn periodic_peak_with<F: Fn(f64) -> f64>(
    f: F,
    n: usize,
    xtol: Option<f64>,
) -> Result<PeriodicPeak, SearchError> {
    let n = n.max(8);
    let h = std::f64::consts::TAU / n as f64;
    let ys: Vec<f64> = (0..n).map(|k| f(k as f64 * h)).collect();
    periodic_peak_sampled(&ys, f, xtol, Refine::All)
}

/// [`periodic_peak_with`] on samples already taken, `ys[k] = f(k·h)` with h = 2π/n computed
/// as `TAU / n as f64` and n = `ys.len()` ≥ 3 (a caller evaluating many functions on one
/// grid computes the expensive part once); `f` is only called by the refinement (`xtol` =
/// `None`: none), which starts from the samples
/// ([`refine_sampled_max`](super::refine_sampled_max)), so they must be the function's values
/// at exactly those abscissae.
pub fn periodic_peak_sampled<F: Fn(f64) -> f64>(
    ys: &[f64],
    f: F,
    xtol: Option<f64>,
    refine: Refine,
) -> Result<PeriodicPeak, SearchError> {
    Shape::of(ys, false, refine)?.peak(ys, 1.0, f, xtol)
}

/// What a pass over the samples `ys[k] = f(k·h)` of a periodic function finds: its
/// curvature bound, its extreme samples and the candidates of its maxima (and, if asked, of
/// its minima, so that both extremes come from one scan without a negated copy).
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// Grid spacing h = 2π/n.
    pub h: f64,
    /// The largest second difference |y_{k−1} − 2y_k + y_{k+1}| (≈ |f''|h²).
    pub d2max: f64,
    /// The largest sample.
    pub best: f64,
    /// The smallest sample.
    pub worst: f64,
    /// Samples above their left and not below their right neighbour (a plateau, all equal,
    /// has every sample a "maximum": only strict-left ones are kept); with
    /// `Refine::PeakOnly`, only those that can be the peak.
    maxima: Vec<usize>,
    /// The same for −f, when asked for.
    minima: Vec<usize>,
}

impl Shape {
    /// Two passes over `ys` (n ≥ 3 finite values); the minima too when `minima`; with
    /// `Refine::PeakOnly` only the candidates that can be the peak are kept.
    pub fn of(ys: &[f64], minima: bool, refine: Refine) -> Result<Shape, SearchError> {
        let n = ys.len();
        if n < 3 {
            return Err(SearchError::Solver(format!(
                "a periodic peak needs at least 3 samples, got {n}"
            )));
        }
        let h = std::f64::consts::TAU / n as f64;
        // Pass 1, branch-free: the largest second difference and the extreme samples, in
        // two independent lanes (`if b > a {b} else {a}` is a max for finite values and
        // vectorises), and y·0, which is NaN for a NaN or infinite sample.
        let wrap = |k: usize| {
            let prev = if k == 0 { n - 1 } else { k - 1 };
            let next = if k + 1 == n { 0 } else { k + 1 };
            [ys[prev], ys[k], ys[next]]
        };
        let (mut d2, mut hi, mut lo, mut bad) =
            ([0.0f64; 2], [f64::MIN; 2], [f64::MAX; 2], [0.0; 2]);
        let (left, mid, right) = (&ys[..n - 2], &ys[1..n - 1], &ys[2..]);
        for ((a, b), c) in left
            .chunks_exact(2)
            .zip(mid.chunks_exact(2))
            .zip(right.chunks_exact(2))
        {
            for l in 0..2 {
                let v = (a[l] - 2.0 * b[l] + c[l]).abs();
                d2[l] = if v > d2[l] { v } else { d2[l] };
                hi[l] = if b[l] > hi[l] { b[l] } else { hi[l] };
                lo[l] = if b[l] < lo[l] { b[l] } else { lo[l] };
                bad[l] += b[l] * 0.0;
            }
        }
        let done = 2 * ((n - 2) / 2);
        for j in (done + 1..n - 1).chain([0, n - 1]) {
            let [yp, y, yn] = wrap(j);
            let v = (yp - 2.0 * y + yn).abs();
            d2[0] = if v > d2[0] { v } else { d2[0] };
            hi[0] = if y > hi[0] { y } else { hi[0] };
            lo[0] = if y < lo[0] { y } else { lo[0] };
            bad[0] += y * 0.0;
        }
        if bad.iter().any(|b| *b != 0.0) {
            let k = ys.iter().position(|y| !y.is_finite()).unwrap_or(0);
            return Err(SearchError::NotFinite { x: k as f64 * h });
        }
        let (d2max, best, worst) = (
            d2.into_iter().fold(0.0, f64::max),
            hi.into_iter().fold(f64::MIN, f64::max),
            lo.into_iter().fold(f64::MAX, f64::min),
        );
        // Pass 2: the candidates, only among the samples that can matter (see [`Refine`]):
        // four samples at a time tested without short-circuit (so that the test
        // vectorises); a block with a hit is then looked at sample by sample.
        let (hi_floor, lo_floor) = match refine {
            Refine::All => (f64::NEG_INFINITY, f64::INFINITY),
            Refine::PeakOnly => (best - 2.0 * d2max, worst + 2.0 * d2max),
        };
        let lo_floor = if minima { lo_floor } else { f64::NEG_INFINITY };
        let (mut maxima, mut minima_at) = (Vec::new(), Vec::new());
        let mut look = |j: usize| {
            let [yp, y, yn] = wrap(j);
            if y >= hi_floor && y >= yn && y > yp {
                maxima.push(j);
            }
            if y <= lo_floor && y <= yn && y < yp {
                minima_at.push(j);
            }
        };
        for (b, q) in ys.chunks_exact(4).enumerate() {
            let mut hit = false;
            for &v in q {
                hit |= (v >= hi_floor) | (v <= lo_floor);
            }
            if hit {
                (4 * b..4 * b + 4).for_each(&mut look);
            }
        }
        (4 * (n / 4)..n).for_each(look);
        Ok(Shape {
            h,
            d2max,
            best,
            worst,
            maxima,
            minima: minima_at,
        })
    }

    /// The refined peak of `sign`·f (`sign` = ±1: the minima need `Shape::of(…, true, …)`)
    /// from the samples `ys` this shape was made of; `xtol` = `None`: the sampled peak.
    pub fn peak<F: Fn(f64) -> f64>(
        &self,
        ys: &[f64],
        sign: f64,
        f: F,
        xtol: Option<f64>,
    ) -> Result<PeriodicPeak, SearchError> {
        let (n, h) = (ys.len(), self.h);
        let candidates = if sign > 0.0 {
            &self.maxima
        } else {
            &self.minima
        };
        let y = |k: usize| sign * ys[k];
        let mut maxima = Vec::with_capacity(candidates.len());
        let mut evals = n;
        for &k in candidates {
            let c = k as f64 * h;
            let Some(xtol) = xtol else {
                maxima.push(Extremum { x: c, fx: y(k) });
                continue;
            };
            let around = [y((k + n - 1) % n), y(k), y((k + 1) % n)];
            let (e, used) = refine_periodic_sample(|x| sign * f(x), c, h, around, xtol)?;
            evals += used;
            maxima.push(e);
        }
        if maxima.is_empty() {
            // A constant function: every point is the peak.
            maxima.push(Extremum { x: 0.0, fx: y(0) });
        }
        maxima.sort_by(|a, b| a.x.total_cmp(&b.x));
        let peak = *maxima.iter().max_by(|a, b| a.fx.total_cmp(&b.fx)).unwrap();
        Ok(PeriodicPeak {
            maxima,
            peak,
            error: peak_error(self.d2max / (h * h), xtol, h),
            evals,
        })
    }
}

/// The refined maxima of a function on a closed interval (not periodic).
#[derive(Debug, Clone, PartialEq)]
pub struct IntervalPeak {
    /// Every refined local maximum `(x in [a, b], value)`, end points included when they are
    /// maxima, sorted by x.
    pub maxima: Vec<Extremum>,
    /// The largest of them.
    pub peak: Extremum,
    /// Bound on |true peak − `peak.fx`| from the refinement tolerance, ½·|f''|·xtol² with
    /// |f''| estimated from the samples (as in [`periodic_peak`]).
    pub error: f64,
    /// Function evaluations spent.
    pub evals: usize,
}

/// Maximum of `f` on `[a, b]`: sample `n + 1` equally spaced points (end points included),
/// take every sample not below its neighbours (an end point needs only its one neighbour) as
/// a candidate, and refine each by Brent on the neighbouring intervals (clipped to `[a, b]`)
/// to `xtol`. A maximum narrower than `(b − a)/n` can be missed; callers pick `n` for their
/// function and test the choice. `a == b` returns `f(a)`; `a > b` is swapped.
pub fn interval_peak<F: Fn(f64) -> f64>(
    f: F,
    a: f64,
    b: f64,
    n: usize,
    xtol: f64,
) -> Result<IntervalPeak, SearchError> {
    interval_peak_with(f, a, b, n, Some(xtol))
}

/// [`interval_peak`] with `Some(xtol)`; with `None` the largest sample is the peak, with the
/// error bound |f''|h²/8 of a smooth interior maximum within h/2 of a sample.
pub fn interval_peak_with<F: Fn(f64) -> f64>(
    f: F,
    a: f64,
    b: f64,
    n: usize,
    xtol: Option<f64>,
) -> Result<IntervalPeak, SearchError> {
    let (a, b) = if a <= b { (a, b) } else { (b, a) };
    if !(a.is_finite() && b.is_finite()) {
        return Err(SearchError::NotFinite {
            x: if a.is_finite() { b } else { a },
        });
    }
    if a == b {
        let fa = f(a);
        if !fa.is_finite() {
            return Err(SearchError::NotFinite { x: a });
        }
        let e = Extremum { x: a, fx: fa };
        return Ok(IntervalPeak {
            maxima: vec![e],
            peak: e,
            error: 0.0,
            evals: 1,
        });
    }
    let n = n.max(4);
    let h = (b - a) / n as f64;
    let xs: Vec<f64> = (0..=n)
        .map(|k| if k == n { b } else { a + k as f64 * h })
        .collect();
    let ys: Vec<f64> = xs.iter().map(|&x| f(x)).collect();
    if let Some(k) = ys.iter().position(|y| !y.is_finite()) {
        return Err(SearchError::NotFinite { x: xs[k] });
    }
    let mut evals = n + 1;
    let mut curv: f64 = 0.0;
    for k in 1..n {
        curv = curv.max(((ys[k - 1] - 2.0 * ys[k] + ys[k + 1]) / (h * h)).abs());
    }
    let mut maxima = Vec::new();
    for k in 0..=n {
        let left_ok = k == 0 || ys[k] > ys[k - 1];
        let right_ok = k == n || ys[k] >= ys[k + 1];
        if !(left_ok && right_ok) {
            continue;
        }
        let Some(xtol) = xtol else {
            maxima.push(Extremum {
                x: xs[k],
                fx: ys[k],
            });
            continue;
        };
        let lo = if k == 0 { a } else { xs[k - 1] };
        let hi = if k == n { b } else { xs[k + 1] };
        let count = std::cell::Cell::new(0usize);
        let fc = |x: f64| {
            count.set(count.get() + 1);
            f(x)
        };
        let e = brent_max(fc, lo, hi, xtol)?;
        evals += count.get();
        maxima.push(if e.fx >= ys[k] {
            e
        } else {
            Extremum {
                x: xs[k],
                fx: ys[k],
            }
        });
    }
    if maxima.is_empty() {
        // Constant on the samples: every point is the peak.
        maxima.push(Extremum { x: a, fx: ys[0] });
    }
    maxima.sort_by(|p, q| p.x.total_cmp(&q.x));
    let peak = *maxima.iter().max_by(|p, q| p.fx.total_cmp(&q.fx)).unwrap();
    Ok(IntervalPeak {
        maxima,
        peak,
        error: peak_error(curv, xtol, h),
        evals,
    })
}

/// Value error of a located maximum: ½|f''|·xtol² when refined to `xtol`, ½|f''|(h/2)² when
/// only sampled on spacing h.
fn peak_error(curv: f64, xtol: Option<f64>, h: f64) -> f64 {
    let dx = xtol.unwrap_or(0.5 * h);
    0.5 * curv * dx * dx
}
