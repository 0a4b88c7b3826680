//! `cwsynth study`: every rung of a slider-crank and a hypocycloid ladder resolves, the
//! default is within its tolerance of the reference, and the outputs are well formed; the
//! coarse rungs trade speed for error, and each family's stated bounds on the effects its
//! model leaves out hold against an independent computation (brute force, closed form, or
//! the scene re-solved with the effect switched on).

use cwsynth::families::crane::model::{head_heights, head_heights_with};
use cwsynth::families::crane::study::{crane_design, unrefined_path_bound};
use cwsynth::families::gear::study::window_edge_mu;
use cwsynth::families::hypocycloid::model::Hypocycloid;
use cwsynth::families::hypocycloid::study::{series_change, series_tail_bound};
use cwsynth::families::parse_str;
use cwsynth::families::solve_scene;
use cwsynth::numeric::{interval_peak_with, periodic_peak_unrefined};
use cwsynth::problem::edit::{apply, Edit};
use cwsynth::study::{csv, markdown, study, svg};
use cwsynth::synth::Var;
use std::f64::consts::{PI, TAU};
use std::path::Path;
use toml_edit::Value;

#[test]
fn piston_ladder_runs_and_the_default_is_accurate() {
    let text = include_str!("../problems/piston-1000rpm.toml");
    let s = study(text, Path::new("piston-1000rpm.toml"), 1).unwrap();
    assert_eq!(s.rungs.first().unwrap().kind, "default");
    assert_eq!(s.rungs.last().unwrap().kind, "reference");
    for r in &s.rungs {
        assert!(
            !r.status.starts_with("rejected"),
            "{}: {}",
            r.label,
            r.status
        );
        assert!(r.rel_error.unwrap().is_finite());
    }
    assert!(s.rungs[0].rel_error.unwrap() < 1e-8);
    // No exchange with 8 samples is visibly worse than the default.
    let no_ex = s
        .rungs
        .iter()
        .find(|r| r.label.starts_with("8 samples"))
        .unwrap();
    assert!(no_ex.rel_error.unwrap() > 1e-4);
    assert_eq!(s.effects.len(), 3);
    assert_eq!(csv(&s).lines().count(), s.rungs.len() + 1);
    assert!(markdown(&s).contains("| reference |"));
    assert!(svg(&s).unwrap().starts_with("<svg"));
}

#[test]
fn hypocycloid_ladder_runs() {
    let text = include_str!("../problems/hypocycloid-variant1.toml");
    let s = study(text, Path::new("h.toml"), 1).unwrap();
    assert!(s.rungs.len() >= 10);
    assert!(s.rungs.iter().all(|r| r.rel_error.is_some()));
}

// ---------------------------------------------------------------------------------------
// Ladders that trade speed for error, and the bounds of the effects left out
// ---------------------------------------------------------------------------------------

fn solve_edited(text: &str, edits: &[Edit]) -> cwsynth::report::SolveResult {
    let t = apply(text, edits).unwrap();
    solve_scene(&parse_str(&t, Path::new("x.toml")).unwrap())
}

#[test]
fn unrefined_peaks_are_within_the_curvature_bound() {
    // cos(φ − φ0) peaks at exactly 1 (closed form); the maximum sits 0.37 h from a sample,
    // so the sampled peak is low by 1 − cos(0.37 h) and the bound is ½·|f''|·(h/2)².
    for n in [16usize, 64, 256] {
        let h = TAU / n as f64;
        let phi0 = 5.0 * h + 0.37 * h;
        let pk = periodic_peak_unrefined(|p| (p - phi0).cos(), n).unwrap();
        let actual = 1.0 - pk.peak.fx;
        assert!(
            actual > 0.0 && actual <= pk.error,
            "n {n}: {actual} > {}",
            pk.error
        );
        assert!(
            pk.error < 2.5 * actual,
            "n {n}: bound {} vs {actual}",
            pk.error
        );
        let hi = PI / n as f64;
        let phi0 = 5.0 * hi + 0.37 * hi;
        let ip = interval_peak_with(|p| (p - phi0).cos(), 0.0, PI, n, None).unwrap();
        let actual = 1.0 - ip.peak.fx;
        assert!(actual > 0.0 && actual <= ip.error && ip.error < 2.5 * actual);
    }
}

/// c_k of sqrt(1 − z) = 1 − Σ c_k z^k from the generalised binomial coefficient:
/// sqrt(1 − z) = Σ binom(½, k)(−z)^k, so c_k = −(−1)^k binom(½, k),
/// binom(½, k) = Π_{j<k} (½ − j)/(j + 1) (a different recursion from the library's).
fn c_binom(k: usize) -> f64 {
    let b = (0..k).fold(1.0, |p, j| p * (0.5 - j as f64) / (j as f64 + 1.0));
    -b * if k.is_multiple_of(2) { 1.0 } else { -1.0 }
}

#[test]
fn series_tail_bound_holds_against_brute_force() {
    for alpha0 in [0.0, 1.5 * PI] {
        for (lambda, theta) in [(0.1, 0.2), (0.25, 0.5), (0.4, 0.5), (0.6, 0.1)] {
            let m = Hypocycloid {
                lambda,
                theta,
                alpha0,
            };
            for p in [1usize, 2, 3, 6] {
                let t = series_tail_bound(lambda, theta, alpha0, p).unwrap();
                // The tail (1/λ)(sqrt(1 − z) − 1 + Σ_{k≤P} c_k z^k) on 4096 angles, with
                // y = sin φ + θ sin(α0 − 2φ) evaluated directly.
                let mut tail: f64 = 0.0;
                for j in 0..4096 {
                    let phi = j as f64 * TAU / 4096.0;
                    let y = phi.sin() + theta * (alpha0 - 2.0 * phi).sin();
                    let z = (lambda * y).powi(2);
                    let partial: f64 = (1..=p).map(|k| c_binom(k) * z.powi(k as i32)).sum();
                    tail = tail.max(((1.0 - z).sqrt() - 1.0 + partial).abs() / lambda);
                }
                let slack = 1e-14 / lambda;
                assert!(
                    tail <= t + slack,
                    "{alpha0} {lambda} {theta} P{p}: {tail} > {t}"
                );
                if t > 1e-11 {
                    // Sharp to the factor 1/(1 − z_max) of the geometric sum (< 2 here).
                    assert!(
                        t < 2.0 * tail,
                        "{alpha0} {lambda} {theta} P{p}: {t} vs {tail}"
                    );
                }
                // Every Fourier coefficient of the tail is at most 2T: C4 against the FFT.
                let (_, da4) = series_change(&m, p, &[1, 2, 3]);
                assert!(da4 <= 2.0 * t + 1e-14, "P{p}: |Δa4| {da4} > 2T {}", 2.0 * t);
            }
        }
    }
}

#[test]
fn hypocycloid_series_rungs_stay_within_the_stated_bound() {
    for text in [
        include_str!("../problems/hypocycloid-variant1.toml"),
        include_str!("../problems/hypocycloid-variant2.toml"),
    ] {
        let base = solve_edited(text, &[]);
        let r0 = base.lookup("objectives.residual_force_peak_n").unwrap();
        let scene = parse_str(text, Path::new("h.toml")).unwrap();
        let Some(h) = scene.machine::<cwsynth::families::hypocycloid::file::HypocycloidProblem>()
        else {
            panic!()
        };
        let sc = &h.scene;
        let (Var::Fixed(lambda), Var::Fixed(theta)) = (sc.lambda, sc.theta) else {
            panic!()
        };
        let m = Hypocycloid {
            lambda,
            theta,
            alpha0: sc.alpha0,
        };
        let fscale = sc.m_b * sc.r_carrier * sc.omega * sc.omega;
        let sum_i2: f64 = sc.balance_orders.iter().map(|&i| (i * i) as f64).sum();
        for p in [1i64, 2, 3] {
            let r = solve_edited(
                text,
                &[
                    Edit::Set("model.coefficients", Value::from("series")),
                    Edit::Set("model.series_power", Value::from(p)),
                ],
            );
            let actual = (r.lookup("objectives.residual_force_peak_n").unwrap() - r0).abs();
            let (df, da4) = series_change(&m, p as usize, &sc.balance_orders);
            let measured = fscale * df;
            let closed = fscale
                * 2.0
                * series_tail_bound(lambda, theta, sc.alpha0, p as usize).unwrap()
                * sum_i2;
            assert!(
                actual <= measured * (1.0 + 1e-9) + 1e-12,
                "P{p}: {actual} > {measured}"
            );
            assert!(measured <= closed, "P{p}: {measured} > {closed}");
            assert!(
                measured < 50.0 * actual,
                "P{p}: bound {measured} vs change {actual}"
            );
            // The series C4 the solve reports is the paper's, |Δa4| away from the exact.
            let dc4 =
                (r.lookup("objectives.c4").unwrap() - base.lookup("objectives.c4").unwrap()).abs();
            assert!(
                (dc4 - da4).abs() <= 1e-12 * (1.0 + da4),
                "P{p}: {dc4} vs {da4}"
            );
        }
    }
}

#[test]
fn crane_unrefined_path_error_matches_its_curvature_bound() {
    let text = include_str!("../problems/crane-thesis-example.toml");
    let scene = parse_str(text, Path::new("c.toml")).unwrap();
    let Some(c) = scene.machine::<cwsynth::families::crane::file::CraneProblem>() else {
        panic!()
    };
    let r = solve_scene(&scene);
    let ev = crane_design(c, &r).unwrap();
    let link = &ev.synthesis.linkage;
    let fine = head_heights(link, 1024, 1e-12).unwrap();
    let [p0, p1] = link.phi_range;
    // y_C'' at an extremum by a five-point difference (independent of the bound's stencil).
    let y = |p: f64| link.pose(p).unwrap().c.y;
    let ypp = |p: f64| {
        let d = 1e-3;
        (-y(p + 2.0 * d) + 16.0 * y(p + d) - 30.0 * y(p) + 16.0 * y(p - d) - y(p - 2.0 * d))
            / (12.0 * d * d)
    };
    let mut seen_error = false;
    for n in [8usize, 16, 32, 100, 128] {
        let coarse = head_heights_with(link, n, None).unwrap();
        let actual = (coarse.delta_h - fine.delta_h).abs();
        let bound = unrefined_path_bound(link, n, 1e-12).unwrap();
        assert!(actual <= bound, "n {n}: {actual} > {bound}");
        // The error predicted from the distance δ of each extremum to its nearest sample:
        // ½|y''|δ² per interior extremum.
        let h = (p1 - p0) / n as f64;
        let pred: f64 = [fine.phi_at_max, fine.phi_at_min]
            .iter()
            .filter(|&&p| p > p0 + 1e-9 && p < p1 - 1e-9)
            .map(|&p| {
                let u = (p - p0) / h;
                let dl = (u - u.round()).abs() * h;
                0.5 * ypp(p).abs() * dl * dl
            })
            .sum();
        assert!(
            (actual - pred).abs() <= 0.05 * pred + 1e-12,
            "n {n}: {actual} vs predicted {pred}"
        );
        seen_error |= actual > 1e-4;
        // The solve with the rung's settings reports the same Δh.
        if n == 8 {
            let rs = solve_edited(
                text,
                &[
                    Edit::Set("accuracy.refine_peaks", Value::from(false)),
                    Edit::Set("accuracy.path_samples", Value::from(8i64)),
                ],
            );
            let d = rs.lookup("objectives.delta_h_m").unwrap();
            assert!(
                (d - coarse.delta_h).abs() <= 1e-12,
                "{d} vs {}",
                coarse.delta_h
            );
        }
    }
    assert!(seen_error, "no rung shows an error");
}

#[test]
fn gear_window_edge_sets_the_peak_and_halving_it_gives_the_stated_value() {
    let text = include_str!("../problems/gear-paper-table1.toml");
    let scene = parse_str(text, Path::new("g.toml")).unwrap();
    let Some(g) = scene.machine::<cwsynth::families::gear::file::GearProblem>() else {
        panic!()
    };
    let r = solve_scene(&scene);
    let peak = r.lookup("objectives.peak_sliding_coefficient").unwrap();
    let e = r.lookup("design.eccentricity_m").unwrap();
    let w = g.gear.pole_window;
    let an = cwsynth::families::gear::synth::analyse(&g.gear, e, &g.settings).unwrap();
    // The sampled-and-refined peak equals |µ| evaluated directly at a window edge.
    let edge = window_edge_mu(&an.pair, &an.sing, w, w);
    assert!((edge - peak).abs() <= 1e-9 * peak, "{edge} vs {peak}");
    // Re-solved with windows of w/2, the peak is the stated edge value at w/2, ≈ 2× (1/d).
    let half = window_edge_mu(&an.pair, &an.sing, 0.5 * w, 0.5 * w);
    let r2 = solve_edited(
        text,
        &[Edit::Set(
            "model.pole_window",
            Value::from(format!("{} rad", 0.5 * w)),
        )],
    );
    let peak2 = r2.lookup("objectives.peak_sliding_coefficient").unwrap();
    assert!((peak2 - half).abs() <= 1e-8 * half, "{peak2} vs {half}");
    assert!(half / peak > 1.5 && half / peak < 2.5, "{}", half / peak);
}

#[test]
fn study_ladders_show_a_trade_off_and_every_family_states_bounds() {
    let text = include_str!("../problems/hypocycloid-variant1.toml");
    let s = study(text, Path::new("h.toml"), 1).unwrap();
    assert!(s.rungs[0].rel_error.unwrap() < 1e-12);
    let worst = s
        .rungs
        .iter()
        .filter(|r| r.kind == "accuracy")
        .filter_map(|r| r.rel_error)
        .fold(0.0, f64::max);
    assert!(worst > 1e-9, "the accuracy rungs are flat: {worst}");
    // The paper series of power 1 shows on the headline, power 6 barely.
    let p1 = s
        .rungs
        .iter()
        .find(|r| r.label == "paper series, power 1")
        .unwrap();
    let p6 = s
        .rungs
        .iter()
        .find(|r| r.label == "paper series, power 6")
        .unwrap();
    assert!(p1.rel_error.unwrap() > 1e3 * p6.rel_error.unwrap());
    let names: Vec<&str> = s.effects.iter().map(|e| e.0.as_str()).collect();
    assert_eq!(
        names,
        ["series truncation", "weights", "other masses, friction"]
    );
    let g = study(
        include_str!("../problems/gear-paper-table1.toml"),
        Path::new("g.toml"),
        1,
    )
    .unwrap();
    assert!(g
        .effects
        .iter()
        .any(|e| e.0 == "pole windows" && e.1.contains("set by the window")));
}
