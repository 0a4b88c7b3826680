//! Acceptance tests of the hypocycloidal machine (issue 5). Every expected value comes from an
//! independent source: the slider-crank closed form, Gauss–Legendre quadrature of the plain
//! formula, the binomial series to high power, leading-order asymptotics, symmetry, Parseval.

use cwsynth::families::hypocycloid::model::{
    max_abs_y_variant1, max_abs_y_variant2, Hypocycloid, MechError, ALPHA0_VARIANT1,
    ALPHA0_VARIANT2,
};
use cwsynth::families::hypocycloid::synth::{
    c4_search_example, paper_example, solve, zero_search, PaperVariant, Settings, Var, ZeroSearch,
    ZeroStatus,
};
use std::f64::consts::PI;

/// binom(1/2, n).
fn binom_half(n: usize) -> f64 {
    let mut b = 1.0;
    for k in 0..n {
        b *= (0.5 - k as f64) / (k as f64 + 1.0);
    }
    b
}

/// Slider-crank (θ = 0) closed form: 1 − λ² sin²φ = c |1 + ρ e^{2iφ}|² with
/// ρ = (λ/(1 + sqrt(1 − λ²)))², sqrt(c) = (1 + sqrt(1 − λ²))/2, hence
/// a_{2j} = (2/λ) sqrt(c) Σ_n binom(½, n + j) binom(½, n) ρ^{2n + j}   (j ≥ 1).
fn slider_crank_a(lambda: f64, order: usize) -> f64 {
    if order == 1 {
        return 1.0;
    }
    if order % 2 == 1 {
        return 0.0;
    }
    let j = order / 2;
    let q = (1.0 - lambda * lambda).sqrt();
    let rho = (lambda / (1.0 + q)).powi(2);
    let sc = (1.0 + q) / 2.0;
    let mut s = 0.0;
    for n in 0..400 {
        s += binom_half(n + j) * binom_half(n) * rho.powi((2 * n + j) as i32);
    }
    2.0 / lambda * sc * s
}

#[test]
fn theta_zero_is_the_slider_crank_closed_form() {
    for &l in &[0.05, 0.25, 0.5, 0.8, 0.95] {
        let m = Hypocycloid::new(l, 0.0, ALPHA0_VARIANT1).unwrap();
        let c = m.coefficients(10, 64, 1 << 16);
        assert!(c.converged);
        for i in 1..=10 {
            let exact = slider_crank_a(l, i);
            let tol = 4.0 * c.err[i] + 1e-15;
            assert!(
                (c.a[i] - exact).abs() <= tol,
                "λ={l} a{i}: {} vs {exact} (err {})",
                c.a[i],
                c.err[i]
            );
            assert!(c.b[i].abs() <= tol);
        }
        // The textbook expansion of a4: −(λ³/64 + 3λ⁵/256 + …).
        if l <= 0.05 {
            assert!((c.a[4] + l.powi(3) / 64.0 + 3.0 * l.powi(5) / 256.0).abs() < 1e-3 * l.powi(5));
        }
    }
}

/// Gauss–Legendre nodes/weights on [−1, 1] by Newton on P_n.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (1..=n)
        .map(|i| {
            let mut x = (PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

#[test]
fn fft_agrees_with_direct_quadrature() {
    let gl = gauss_legendre(20);
    for (alpha0, l, t) in [
        (ALPHA0_VARIANT1, 0.25, 0.5),
        (ALPHA0_VARIANT2, 0.25, 0.5),
        (1.0, 0.4, 0.3),
    ] {
        let m = Hypocycloid::new(l, t, alpha0).unwrap();
        let c = m.coefficients(8, 64, 1 << 16);
        // Plain formula, no splitting: S/R − 1/λ = x + (sqrt(1 − λ²y²) − 1)/λ.
        let f = |p: f64| {
            let (x, y) = m.point_a(p);
            x + ((1.0 - l * l * y * y).sqrt() - 1.0) / l
        };
        let panels = 64;
        let h = 2.0 * PI / panels as f64;
        for i in 1..=8 {
            let (mut qa, mut qb) = (0.0, 0.0);
            for k in 0..panels {
                for &(x, w) in &gl {
                    let p = h * (k as f64 + 0.5 + 0.5 * x);
                    qa += w * 0.5 * h * f(p) * (i as f64 * p).cos();
                    qb += w * 0.5 * h * f(p) * (i as f64 * p).sin();
                }
            }
            qa /= PI;
            qb /= PI;
            assert!((c.a[i] - qa).abs() < 1e-13, "a{i}: {} vs {qa}", c.a[i]);
            assert!((c.b[i] - qb).abs() < 1e-13, "b{i}: {} vs {qb}", c.b[i]);
            assert!(c.err[i] < 1e-14);
        }
    }
}

#[test]
fn truncated_series_converges_to_the_fft() {
    for alpha0 in [ALPHA0_VARIANT1, ALPHA0_VARIANT2] {
        let (l, t) = (0.25, 0.5);
        let m = Hypocycloid::new(l, t, alpha0).unwrap();
        let c = m.coefficients(8, 64, 1 << 16);
        let q = m.lambda_ymax();
        let mut prev = f64::INFINITY;
        for p in 1..=24 {
            let (a, b) = m.series_coefficients(p, 8);
            let e = (1..=8)
                .map(|i| (a[i] - c.a[i]).abs().max((b[i] - c.b[i]).abs()))
                .fold(0.0, f64::max);
            // Tail of the binomial series: ≤ (1/λ) Σ_{k>p} c_k q^{2k} ≤ q^{2p+2}/λ.
            assert!(e <= q.powi(2 * p as i32 + 2) / l + 1e-15, "power {p}: {e}");
            assert!(e <= prev + 1e-16, "power {p}: {e} > {prev}");
            prev = e;
        }
        assert!(prev < 1e-14);
    }
}

#[test]
fn coefficients_are_invariant_to_fft_size() {
    let m = Hypocycloid::new(0.3, 0.45, ALPHA0_VARIANT2).unwrap();
    let c0 = m.coefficients(12, 64, 1 << 16);
    for n in [256, 1024, 8192] {
        let c = m.coefficients(12, n, 1 << 16);
        for i in 0..=12 {
            assert!(
                (c.a[i] - c0.a[i]).abs() <= c.err[i] + c0.err[i],
                "n={n} a{i}"
            );
            assert!(
                (c.b[i] - c0.b[i]).abs() <= c.err[i] + c0.err[i],
                "n={n} b{i}"
            );
        }
    }
    // Single-bin evaluation used by the zero search: same numbers.
    let a4 = m.cos_coefficient(4, c0.n_fft);
    assert!((a4 - c0.a[4]).abs() <= 2.0 * c0.err[4]);
}

#[test]
fn tiny_lambda_has_no_cancellation() {
    let l = 1e-8;
    // θ = 0: a2 = λ/4 + λ³/16, a4 = −λ³/64 (slider crank), relative accuracy kept.
    let m = Hypocycloid::new(l, 0.0, ALPHA0_VARIANT1).unwrap();
    let c = m.coefficients(6, 64, 1 << 16);
    assert!((c.a[2] / (l / 4.0) - 1.0).abs() < 1e-14, "{}", c.a[2]);
    assert!(
        (c.a[4] / (-l.powi(3) / 64.0) - 1.0).abs() < 1e-10,
        "{}",
        c.a[4]
    );
    // Variant 1, θ = 0.5: a1 = 1 + λθ/2, a2 = θ + λ/4, a3 = −λθ/2, a4 = λθ²/4 (+ O(λ³)).
    let t = 0.5;
    let m = Hypocycloid::new(l, t, ALPHA0_VARIANT1).unwrap();
    let c = m.coefficients(6, 64, 1 << 16);
    assert!(((c.a[1] - 1.0) / (l * t / 2.0) - 1.0).abs() < 1e-7);
    assert!(((c.a[2] - t) / (l / 4.0) - 1.0).abs() < 1e-7);
    assert!((c.a[3] / (-l * t / 2.0) - 1.0).abs() < 1e-12);
    assert!((c.a[4] / (l * t * t / 4.0) - 1.0).abs() < 1e-12);
    // Variant 2: a4 = −λθ²/4, b3 = λθ/2 − …, b2 = −θ exactly.
    let m = Hypocycloid::new(l, t, ALPHA0_VARIANT2).unwrap();
    let c = m.coefficients(6, 64, 1 << 16);
    assert!((c.a[4] / (-l * t * t / 4.0) - 1.0).abs() < 1e-12);
    assert!((c.b[2] + t).abs() < 1e-15);
}

#[test]
fn symmetries_of_the_two_variants() {
    let m1 = Hypocycloid::new(0.3, 0.4, ALPHA0_VARIANT1).unwrap();
    let c1 = m1.coefficients(8, 64, 1 << 16);
    for i in 1..=8 {
        assert!(c1.b[i].abs() < 1e-15, "variant 1 b{i}");
    }
    let m2 = Hypocycloid::new(0.3, 0.4, ALPHA0_VARIANT2).unwrap();
    let c2 = m2.coefficients(8, 64, 1 << 16);
    assert!((c2.a[1] - 1.0).abs() < 1e-15);
    assert!((c2.b[2] + 0.4).abs() < 1e-15);
    for i in [3, 5, 7] {
        assert!(c2.a[i].abs() < 1e-15, "variant 2 a{i}");
    }
    for i in [4, 6, 8] {
        assert!(c2.b[i].abs() < 1e-15, "variant 2 b{i}");
    }
}

#[test]
fn assembly_limits_match_closed_forms_and_fail_cleanly() {
    // Variant 2: λ(1 + θ) < 1; variant 1: λ·max|y| with the quadratic closed form.
    for (alpha0, ym) in [
        (ALPHA0_VARIANT1, max_abs_y_variant1(0.5)),
        (ALPHA0_VARIANT2, max_abs_y_variant2(0.5)),
    ] {
        let lim = 1.0 / ym;
        assert!(Hypocycloid::new(lim * (1.0 - 1e-9), 0.5, alpha0).is_ok());
        match Hypocycloid::new(lim * (1.0 + 1e-9), 0.5, alpha0) {
            Err(MechError::CannotAssemble { lambda_limit, .. }) => {
                assert!((lambda_limit - lim).abs() < 1e-13)
            }
            other => panic!("expected CannotAssemble, got {other:?}"),
        }
    }
    assert!(matches!(
        Hypocycloid::new(f64::NAN, 0.5, 0.0),
        Err(MechError::BadRatio { name: "lambda", .. })
    ));
    assert!(matches!(
        Hypocycloid::new(0.2, -0.1, 0.0),
        Err(MechError::BadRatio { name: "theta", .. })
    ));
    // Near the limit (λ(1+θ) = 1 − 1e-6): finite values, honest error, no panic.
    let m = Hypocycloid::new((1.0 - 1e-6) / 1.5, 0.5, ALPHA0_VARIANT2).unwrap();
    let c = m.coefficients(8, 64, 1 << 14);
    assert!(c.a.iter().chain(&c.b).chain(&c.err).all(|v| v.is_finite()));
    assert!(!c.converged && c.err[4] > 0.0);
    // Scene errors name the key.
    let mut s = paper_example(PaperVariant::Variant2);
    s.lambda = Var::Fixed(0.7);
    let e = s.validate().unwrap_err();
    assert_eq!(e.field, "design.lambda");
    s.lambda = Var::Fixed(0.25);
    s.m_b = f64::NAN;
    assert_eq!(
        s.validate().unwrap_err().field,
        "mechanism.reciprocating_mass"
    );
    s.m_b = 0.35;
    s.theta = Var::Free { min: 0.5, max: 0.2 };
    assert_eq!(s.validate().unwrap_err().field, "design.theta");
    assert!(solve(&s, &Settings::default()).is_err());
}

#[test]
fn every_root_is_bracketed_and_below_1e13() {
    let s = Settings::default();
    for v in [PaperVariant::Variant1, PaperVariant::Variant2] {
        let zs = ZeroSearch {
            order: 4,
            lambda: (0.02, 0.6),
            theta: (0.0, 0.9),
        };
        let z = zero_search(v.alpha0(), &zs, 3, 1e-3, &s);
        for r in &z.roots {
            assert!(r.value.abs() < 1e-13, "{r:?}");
            assert!(r.f_bracket.0.signum() != r.f_bracket.1.signum() || r.f_bracket.0 == 0.0);
            assert!(r.bracket.0 <= r.theta && r.theta <= r.bracket.1);
            // Independent re-evaluation by the full FFT path.
            let m = Hypocycloid::new(r.lambda, r.theta, v.alpha0()).unwrap();
            let c = m.coefficients(4, 64, 1 << 16);
            assert!(c.a[4].abs() < 1e-13 + c.err[4], "{} at {r:?}", c.a[4]);
        }
        match v {
            PaperVariant::Variant1 => {
                assert_eq!(z.status, ZeroStatus::Found);
                assert!(z.single_valued);
                // Leading order: λθ²/4 = λ³/64 ⇒ θ* ≈ λ/4 for small λ.
                let r = z
                    .roots
                    .iter()
                    .find(|r| (r.lambda - 0.02).abs() < 1e-15)
                    .expect("root at λ = 0.02");
                assert!((r.theta / (r.lambda / 4.0) - 1.0).abs() < 0.01, "{r:?}");
            }
            PaperVariant::Variant2 => {
                // a4 = −λθ²/4 − λ³(1/8 + 3θ²/2 + θ⁴/2)/8 − …: every term negative.
                assert_eq!(z.status, ZeroStatus::NoZero, "{}", z.reason);
                assert_eq!(z.sign, -1);
                let g = z.grid_min_abs.unwrap();
                assert!((g.lambda - 0.02).abs() < 1e-15 && g.theta == 0.0);
                assert!((g.value / (-(0.02f64).powi(3) / 64.0) - 1.0).abs() < 1e-3);
            }
        }
    }
}

#[test]
fn parseval_links_the_force_and_the_coefficients() {
    // RMS of the unbalanced inertia force from the closed-form acceleration equals
    // m_B R ω² sqrt(½ Σ i⁴ (a_i² + b_i²)) from the FFT coefficients.
    let mut scene = paper_example(PaperVariant::Variant2);
    scene.balance_orders = vec![];
    scene.orders = 40;
    let o = solve(&scene, &Settings::default()).unwrap();
    let f = o.derived.force_scale_n;
    let sum: f64 = (1..=40)
        .map(|i| (i as f64).powi(4) * (o.coefficients.a[i].powi(2) + o.coefficients.b[i].powi(2)))
        .sum();
    let rms = f * (0.5 * sum).sqrt();
    assert!(
        (o.objectives.residual_force_rms_n - rms).abs()
            < 1e-9 * rms + o.errors.residual_force_rms_n
    );
    // Balancing orders 1..=3 removes exactly their share of the mean square.
    scene.balance_orders = vec![1, 2, 3];
    let o3 = solve(&scene, &Settings::default()).unwrap();
    let sum3: f64 = (4..=40)
        .map(|i| (i as f64).powi(4) * (o.coefficients.a[i].powi(2) + o.coefficients.b[i].powi(2)))
        .sum();
    assert!((o3.objectives.residual_force_rms_n - f * (0.5 * sum3).sqrt()).abs() < 1e-9 * rms);
    // m′r′ = ½ m_B R C_i (paper).
    for p in &o3.balancing {
        let c = o3.coefficients.a[p.order].hypot(o3.coefficients.b[p.order]);
        assert!((p.static_moment - 0.5 * scene.m_b * scene.r_carrier * c).abs() < 1e-15);
    }
}

#[test]
fn scale_invariance_mm_to_km() {
    let base = solve(&paper_example(PaperVariant::Variant1), &Settings::default()).unwrap();
    for k in [1e-3, 1e3] {
        let mut s = paper_example(PaperVariant::Variant1);
        s.r_carrier *= k;
        s.m_b *= 1.0 / k;
        let o = solve(&s, &Settings::default()).unwrap();
        assert_eq!(o.objectives.c4, base.objectives.c4);
        let (a, b) = (
            o.objectives.residual_force_peak_n,
            base.objectives.residual_force_peak_n,
        );
        assert!((a - b).abs() < 1e-12 * b);
    }
}

#[test]
fn json_contract_and_paper_checks() {
    let o = solve(&paper_example(PaperVariant::Variant2), &Settings::default()).unwrap();
    let j = serde_json::to_value(&o).unwrap();
    assert!(j["objectives"]["c4"].is_f64());
    assert!(j["errors"]["c4"].is_f64());
    assert_eq!(j["coefficients"]["a"].as_array().unwrap().len(), 9);
    assert_eq!(j["coefficients"]["b"].as_array().unwrap().len(), 9);
    assert!(j["zero_curve"].as_array().unwrap().is_empty());
    assert!(o
        .paper
        .iter()
        .any(|p| p.quantity.starts_with("C1^I") && (p.computed.unwrap() - 1.0).abs() < 1e-15));
    let errors = cwsynth::report::number_map(&o.errors);
    for key in cwsynth::report::number_map(&o.objectives).keys() {
        assert!(errors.contains_key(key), "{key} has no error estimate");
    }
    let o = solve(
        &c4_search_example(PaperVariant::Variant1),
        &Settings::default(),
    )
    .unwrap();
    let j = serde_json::to_value(&o).unwrap();
    let zc = j["zero_curve"].as_array().unwrap();
    assert!(!zc.is_empty());
    assert!(zc[0]["lambda"].is_f64() && zc[0]["theta"].is_f64());
    assert!(o.objectives.stroke_m >= 0.045 - 1e-9, "{:?}", o.objectives);
}

#[test]
fn print_summary() {
    for v in [PaperVariant::Variant1, PaperVariant::Variant2] {
        let o = solve(&paper_example(v), &Settings::default()).unwrap();
        println!(
            "{v:?} example: {:?}\n derived {:?}\n warnings {:?}",
            o.objectives, o.derived, o.warnings
        );
        for p in &o.paper {
            println!(
                "  paper {}: {} vs {} — {}",
                p.quantity,
                p.paper,
                p.computed.unwrap_or(f64::NAN),
                p.note
            );
        }
        let o = solve(&c4_search_example(v), &Settings::default()).unwrap();
        println!(
            "{v:?} search: design {:?} status {:?}\n obj {:?}\n {}",
            o.design, o.status, o.objectives, o.method
        );
        let z = o.zero_search.as_ref().unwrap();
        println!(
            " zero: {:?} {} roots; {}",
            z.status,
            z.roots.len(),
            z.reason
        );
        for r in z.roots.iter().step_by(10) {
            println!(
                "  λ={:.4} θ*={:.12} series θ={:?} a4={:e}",
                r.lambda, r.theta, r.series_theta, r.value
            );
        }
        println!(" derived {:?}\n warnings {:?}", o.derived, o.warnings);
    }
}
