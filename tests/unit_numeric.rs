//! `numeric` (`src/numeric.rs`, `src/numeric/peaks.rs`): Brent roots and maxima, refined
//! periodic and interval peaks against closed forms and against Brent from scratch on random
//! trigonometric polynomials, the one-pass extremes, Newton polish and the safeguarded Newton
//! root.
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

use crate::common::uniform_pm1;
use cwsynth::numeric::{
    brent_max, brent_root, interval_peak, newton_polish, newton_root, periodic_peak,
    periodic_peak_sampled, periodic_rms, refine_sampled_max, Refine, SearchError, Shape,
};

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
