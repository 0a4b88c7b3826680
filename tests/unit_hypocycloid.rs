//! The hypocycloid family's model (`src/families/hypocycloid/model.rs`: the series
//! coefficients, max |y| against closed forms, derivatives, a Lanchester pair) and its
//! study's key objectives (`study.rs`).
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

/// The former unit tests of `src/families/hypocycloid/model.rs`.
mod model {
    use cwsynth::families::hypocycloid::model::{
        lanchester_pair, max_abs_y, max_abs_y_variant1, max_abs_y_variant2, order_force,
        Hypocycloid, ALPHA0_VARIANT1, ALPHA0_VARIANT2,
    };

    #[test]
    fn series_a_is_series_coefficients_bit_for_bit() {
        for &lambda in &[0.02, 0.1, 0.25, 0.5] {
            for &theta in &[0.0, 0.13, 0.5, 0.9] {
                for &alpha0 in &[0.0, 0.3, ALPHA0_VARIANT2] {
                    let m = Hypocycloid {
                        lambda,
                        theta,
                        alpha0,
                    };
                    for power in 0..=6 {
                        for k in 0..=30 {
                            let full = m.series_coefficients(power, k).0[k];
                            let one = m.series_a(power, k);
                            assert_eq!(
                                one.to_bits(),
                                full.to_bits(),
                                "λ {lambda} θ {theta} α0 {alpha0} power {power} k {k}: {one} vs {full}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn max_abs_y_matches_closed_forms() {
        for &t in &[0.0, 0.1, 0.25, 0.5, 0.9] {
            let v1 = max_abs_y(t, ALPHA0_VARIANT1).unwrap();
            assert!((v1 - max_abs_y_variant1(t)).abs() < 1e-14, "{t}: {v1}");
            let v2 = max_abs_y(t, ALPHA0_VARIANT2).unwrap();
            assert!((v2 - max_abs_y_variant2(t)).abs() < 1e-14, "{t}: {v2}");
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let m = Hypocycloid::new(0.3, 0.4, ALPHA0_VARIANT2).unwrap();
        let h = 1e-4;
        for k in 0..12 {
            let p = 0.3 + k as f64 * 0.5;
            let (f0, fp, fm) = (m.piston(p), m.piston(p + h), m.piston(p - h));
            let d1 = (fp.s_rel - fm.s_rel) / (2.0 * h);
            let d2 = (fp.s_rel - 2.0 * f0.s_rel + fm.s_rel) / (h * h);
            assert!((d1 - f0.ds).abs() < 1e-7, "{d1} {}", f0.ds);
            assert!((d2 - f0.dds).abs() < 1e-5, "{d2} {}", f0.dds);
        }
    }

    #[test]
    fn pair_cancels_its_order() {
        let (a, b, m, r, w) = (0.3, -0.2, 2.0, 0.05, 100.0);
        let p = lanchester_pair(3, a, b, m, r, w);
        for k in 0..10 {
            let phi = k as f64 * 0.7;
            let (fx, fy) = p.force(phi);
            let f = order_force(3, a, b, m, r, w, phi);
            assert!((fx + f).abs() < 1e-10 * f.abs().max(1.0));
            assert!(fy.abs() < 1e-10);
        }
    }
}

/// The former unit tests of `src/families/hypocycloid/study.rs`.
mod study {
    use cwsynth::families::hypocycloid::synth::Objectives;
    use cwsynth::report::numbers::declared_keys;

    #[test]
    fn the_key_objectives_are_fields_of_the_objectives() {
        let o = Objectives {
            c4: 0.0,
            residual_force_peak_n: 0.0,
            residual_force_rms_n: 0.0,
            unbalanced_force_peak_n: 0.0,
            stroke_m: 0.0,
            suction_gain: 0.0,
        };
        for zero_search in [false, true] {
            assert!(declared_keys(&o).contains(&Objectives::key(zero_search).to_string()));
        }
    }
}
