//! The peak of the sliding ratio |µ| over the working window of a gear pair: each arch
//! scanned outside the windows around the poles and the singular cusps, every sampled local
//! maximum refined, with an error bound from the sampling, the refinement and the rounding
//! of µ at the peak (and the largest asymmetry |µ1 + µ2| away from the poles).

use super::{GearPair, Singularities, Which};
use crate::numeric::{brent_max, SearchError};
use std::f64::consts::TAU;

/// The peak of |µ| on the working window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MuPeak {
    /// max over the window of max(|µ1|, |µ2|).
    pub value: f64,
    /// α1 where it occurs.
    pub alpha1: f64,
    /// Which coefficient attains it.
    pub which: Which,
    /// Error bound: refinement (½|f''|xtol²), window-edge shift from the pole error
    /// (|µ'|·δα) and the change from a half-density sampling.
    pub error: f64,
    /// max over the window of |µ1 + µ2| (the paper claims µ2 = −µ1).
    pub max_asymmetry: f64,
    /// Evaluations spent.
    pub evals: usize,
}

/// Peak |µ1|, |µ2| over α1 ∈ [0, 2π) outside windows of half-width `window` (rad in α1)
/// around each coefficient's own poles and around 0/0 cusps.
pub fn peak_mu(
    pair: &GearPair,
    sing: &Singularities,
    window: f64,
    samples_per_arch: usize,
    xtol: f64,
) -> Result<MuPeak, SearchError> {
    peak_mu_with(pair, sing, window, samples_per_arch, Some(xtol))
}

/// [`peak_mu`] with `Some(xtol)`; with `None` the sampled maxima are not refined (each is
/// low by at most |µ''|h²/8, which the error then carries).
///
/// `window = 0` leaves nothing out: if µ1 or µ2 has a pole, the peak is unbounded and the
/// result has `value = +∞` at the first pole (error 0, `max_asymmetry = +∞`, since
/// µ1 + µ2 = −µ1²/(1 − µ1) is unbounded there too).
pub fn peak_mu_with(
    pair: &GearPair,
    sing: &Singularities,
    window: f64,
    samples_per_arch: usize,
    xtol: Option<f64>,
) -> Result<MuPeak, SearchError> {
    if window == 0.0 {
        if let Some(p) = sing.poles.first() {
            return Ok(MuPeak {
                value: f64::INFINITY,
                alpha1: p.alpha1_rad,
                which: p.which,
                error: 0.0,
                max_asymmetry: f64::INFINITY,
                evals: 0,
            });
        }
    }
    let fine = peak_mu_once(pair, sing, window, samples_per_arch.max(8), xtol)?;
    let coarse = peak_mu_once(pair, sing, window, (samples_per_arch / 2).max(4), xtol)?;
    let mut out = fine;
    out.error = fine.error + (fine.value - coarse.value).abs();
    out.evals += coarse.evals;
    Ok(out)
}

/// One scan of the peak of |µ| (µ1 and µ2) over every arch, `m` intervals per allowed piece
/// (the arch outside the pole and cusp windows), with the error bound of the sampling, the
/// refinement and the rounding of µ = v_slide/v_t at the peak, and the largest asymmetry
/// |µ1 + µ2| away from the poles.
fn peak_mu_once(
    pair: &GearPair,
    sing: &Singularities,
    window: f64,
    m: usize,
    xtol: Option<f64>,
) -> Result<MuPeak, SearchError> {
    let mut acc = PeakScan {
        best: MuPeak {
            value: 0.0,
            alpha1: 0.0,
            which: Which::Mu1,
            error: 0.0,
            max_asymmetry: 0.0,
            evals: 0,
        },
        evals: 0,
        err: 0.0,
    };
    let singular_cusps = sing.singular_cusps();
    for i in 0..pair.n_arches {
        let a0 = pair.arch_start(i);
        let a1 = pair.arch_start(i + 1);
        let nearby = poles_near_arch(sing, a0, a1, window);
        for which in [Which::Mu1, Which::Mu2] {
            let pieces = arch_pieces(sing, &singular_cusps, which, window, a0, a1);
            // Exactly at a 0/0 cusp (reachable only with a zero window) µ has no value; its
            // one-sided limit from inside the arch is taken, 1e-9 of the arch away.
            let nudge = 1e-9 * (a1 - a0);
            // The window edges are uncertain by the pole errors (and the nudge), and every
            // sample by the rounding of its evaluation point.
            let edge_shift = sing
                .poles
                .iter()
                .map(|p| p.error_rad)
                .fold(if window == 0.0 { nudge } else { 0.0 }, f64::max)
                + pair.eval_shift(a1);
            let arch = ArchScan {
                pair,
                arch: i,
                which,
                a0,
                a1,
                nudge,
                edge_shift,
                window,
                m,
                xtol,
                nearby: &nearby,
            };
            for (u, v) in pieces {
                if v <= u {
                    continue;
                }
                arch.piece(u, v, &mut acc)?;
            }
        }
    }
    let mut best = acc.best;
    if !best.value.is_finite() {
        return Err(SearchError::NotFinite { x: best.alpha1 });
    }
    // Rounding of µ = v_slide/v_t at the peak (the shift of the evaluation point is in the
    // edge term above): v_t/Ω is the pole function f, whose products round by δf, a relative
    // δf/|f| that is large near a pole and grows like κ = R/(R − e).
    let arch = pair.arch_of(best.alpha1);
    let f = match best.which {
        Which::Mu1 => pair.pole_fn_mu1(best.alpha1, arch),
        Which::Mu2 => pair.pole_fn_mu2(best.alpha1, arch),
    };
    let rel = pair.pole_fn_product_roundoff(best.alpha1, arch, best.which)
        / f.abs().max(f64::MIN_POSITIVE)
        + 16.0 * f64::EPSILON * pair.condition();
    best.error = acc.err + rel * best.value;
    best.evals = acc.evals;
    Ok(best)
}

/// What the peak scan of |µ| carries from piece to piece: the best sample or refined
/// maximum so far (with the largest asymmetry |µ1 + µ2| seen), the evaluations, and the
/// largest error term.
struct PeakScan {
    best: MuPeak,
    evals: usize,
    err: f64,
}

/// Distance on the circle between two angles of [0, 2π] (samples of the arches and poles):
/// |x − c| folded once, without the `rem_euclid` (a software `fmod`) that made this test,
/// run for every sample against every pole, a third of the peak search.
fn circle_distance(x: f64, c: f64) -> f64 {
    let mut d = (x - c).abs();
    while d > TAU {
        d -= TAU;
    }
    d.min(TAU - d)
}

/// The poles (of either µ) that can be within the window of a sample of the arch
/// [a0, a1]: the asymmetry's test needs only these (the others are farther than the window
/// from every point of [a0, a1]; a margin of 1e-9 rad keeps the borderline).
fn poles_near_arch(sing: &Singularities, a0: f64, a1: f64, window: f64) -> Vec<f64> {
    sing.poles
        .iter()
        .map(|p| p.alpha1_rad)
        .filter(|&c| {
            [-TAU, 0.0, TAU]
                .iter()
                .any(|s| c + s >= a0 - window - 1e-9 && c + s <= a1 + window + 1e-9)
        })
        .collect()
}

/// The pieces of the arch [a0, a1] where |µ_which| is searched: the arch without the
/// windows around the poles of µ_which (widened by each pole's error) and around the
/// singular cusps, in each of the three turns −2π, 0, 2π.
fn arch_pieces(
    sing: &Singularities,
    singular_cusps: &[f64],
    which: Which,
    window: f64,
    a0: f64,
    a1: f64,
) -> Vec<(f64, f64)> {
    // Excluded intervals inside this arch.
    let mut cuts: Vec<(f64, f64)> = Vec::new();
    for p in sing.poles.iter().filter(|p| p.which == which) {
        for shift in [-TAU, 0.0, TAU] {
            let c = p.alpha1_rad + shift;
            if c + window > a0 && c - window < a1 {
                cuts.push((c - window - p.error_rad, c + window + p.error_rad));
            }
        }
    }
    for &c0 in singular_cusps {
        for shift in [-TAU, 0.0, TAU] {
            let c = c0 + shift;
            if c + window > a0 && c - window < a1 {
                cuts.push((c - window, c + window));
            }
        }
    }
    cuts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut pieces = Vec::new();
    let mut start = a0;
    for (lo, hi) in cuts {
        if lo > start {
            pieces.push((start, lo.min(a1)));
        }
        start = start.max(hi);
    }
    if start < a1 {
        pieces.push((start, a1));
    }
    pieces
}

/// The scan of |µ_which| on one arch [a0, a1] of the pair: `m` intervals per piece, each
/// sampled local maximum refined by Brent to `xtol` (or bounded by its curvature without),
/// µ at a 0/0 cusp taken `nudge` inside the arch, the window edges uncertain by
/// `edge_shift`, and the asymmetry tested away (by `window`) from the `nearby` poles.
struct ArchScan<'a> {
    pair: &'a GearPair,
    arch: usize,
    which: Which,
    a0: f64,
    a1: f64,
    nudge: f64,
    edge_shift: f64,
    window: f64,
    m: usize,
    xtol: Option<f64>,
    nearby: &'a [f64],
}

impl ArchScan<'_> {
    /// µ_which of the pair (µ1, µ2).
    fn pick(&self, (mu1, mu2): (Option<f64>, Option<f64>)) -> Option<f64> {
        match self.which {
            Which::Mu1 => mu1,
            Which::Mu2 => mu2,
        }
    }

    /// |µ| at x from its value there (`first`, None at a 0/0 cusp: then the one-sided
    /// limit, `nudge` towards the arch's inside).
    fn mu_from(&self, x: f64, first: Option<f64>) -> f64 {
        let (a0, a1, nudge) = (self.a0, self.a1, self.nudge);
        let mu_at = |x: f64| self.pick(self.pair.mu_on(x, self.arch));
        first
            .or_else(|| {
                mu_at(if x - a0 < a1 - x {
                    x + nudge
                } else {
                    x - nudge
                })
            })
            .map_or(f64::INFINITY, f64::abs)
    }

    /// |µ| at x.
    fn mu(&self, x: f64) -> f64 {
        self.mu_from(x, self.pick(self.pair.mu_on(x, self.arch)))
    }

    /// Scans the piece [u, v] into `acc`: m + 1 samples, the asymmetry on the µ1 pass, the
    /// edge-slope term |y'|·edge_shift, and every sampled local maximum refined (error
    /// ½|y''|xtol²) or bounded (⅛|y''|h²).
    fn piece(&self, u: f64, v: f64, acc: &mut PeakScan) -> Result<(), SearchError> {
        let (m, which, i) = (self.m, self.which, self.arch);
        let h = (v - u) / m as f64;
        let xs: Vec<f64> = (0..=m)
            .map(|k| if k == m { v } else { u + k as f64 * h })
            .collect();
        // One evaluation per sample gives |µ| and, on the µ1 pass, the asymmetry.
        let mus: Vec<(Option<f64>, Option<f64>)> =
            xs.iter().map(|&x| self.pair.mu_on(x, i)).collect();
        let ys: Vec<f64> = xs
            .iter()
            .zip(&mus)
            .map(|(&x, &m12)| self.mu_from(x, self.pick(m12)))
            .collect();
        acc.evals += m + 1;
        // Asymmetry µ1 + µ2 at the samples (only once, on the µ1 pass).
        if which == Which::Mu1 {
            for (&x, &m12) in xs.iter().zip(&mus) {
                if let (Some(m1), Some(m2)) = m12 {
                    if self
                        .nearby
                        .iter()
                        .all(|&c| circle_distance(x, c) > self.window)
                    {
                        acc.best.max_asymmetry = acc.best.max_asymmetry.max((m1 + m2).abs());
                    }
                }
            }
        }
        let best = &mut acc.best;
        let mut consider = |x: f64, y: f64| {
            if y > best.value {
                best.value = y;
                best.alpha1 = x.rem_euclid(TAU);
                best.which = which;
            }
        };
        for k in 0..=m {
            consider(xs[k], ys[k]);
        }
        // Edge slopes: the window edges move with the pole error.
        let edge_slope = ((ys[1] - ys[0]) / h)
            .abs()
            .max(((ys[m] - ys[m - 1]) / h).abs());
        acc.err = acc.err.max(edge_slope * self.edge_shift);
        for k in 1..m {
            if ys[k] >= ys[k - 1] && ys[k] >= ys[k + 1] {
                let curv = ((ys[k - 1] - 2.0 * ys[k] + ys[k + 1]) / (h * h)).abs();
                let Some(xtol) = self.xtol else {
                    acc.err = acc.err.max(0.125 * curv * h * h);
                    continue;
                };
                let c = std::cell::Cell::new(0usize);
                let g = |x: f64| {
                    c.set(c.get() + 1);
                    self.mu(x)
                };
                let e = brent_max(g, xs[k - 1], xs[k + 1], xtol)?;
                acc.evals += c.get();
                acc.err = acc.err.max(0.5 * curv * xtol * xtol);
                consider(e.x, e.fx.max(ys[k]));
            }
        }
        Ok(())
    }
}
