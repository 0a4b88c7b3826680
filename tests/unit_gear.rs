//! The non-circular gear family's model (`src/families/gear/model.rs`: µ and the pole
//! functions against the contact state, ρ1 against the law of cosines and finite
//! differences) and its study's key objectives (`study.rs`).
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

/// The former unit tests of `src/families/gear/model.rs`.
mod model {
    use cwsynth::families::gear::model::{closing_center_distance, EccentricCircle, GearPair};
    use cwsynth::geom::P2;
    use std::f64::consts::TAU;

    #[test]
    fn mu_only_and_pole_functions_are_bit_identical_to_the_contact_state() {
        let ec = EccentricCircle::new(37.5e-3, 15e-3).unwrap();
        let a = closing_center_distance(&ec, 3, 1).unwrap().a;
        let pair = GearPair::new(ec, 1.25e-3, a, 15.0).unwrap();
        for k in 0..5_003 {
            let al = k as f64 * TAU / 5_003.0;
            for arch in [pair.arch_of(al), 0, 1] {
                let ct = pair.contact_on(al, arch);
                assert_eq!(pair.mu_on(al, arch), (ct.mu1, ct.mu2), "α {al} arch {arch}");
                assert_eq!(pair.pole_fn_mu1(al, arch), ct.k.dot(&ct.d));
                assert_eq!(
                    pair.pole_fn_mu2(al, arch),
                    (ct.k - P2::new(pair.a, 0.0)).dot(&ct.d)
                );
            }
        }
    }

    #[test]
    fn rho1_stable_form_agrees_with_law_of_cosines() {
        // |O1P|² from the triangle O1-C-P: ρ² − 2eρ cos α + e² = R² (law of cosines).
        for e in [0.0, 1.0, 2.9, 3.0 - 1e-9] {
            let c = EccentricCircle::new(3.0, e).unwrap();
            for k in 0..360 {
                let al = k as f64 * TAU / 360.0;
                let r = c.rho1(al);
                let res = (r - e * al.cos()).powi(2) + (e * al.sin()).powi(2) - 9.0;
                assert!(res.abs() < 1e-14 * 9.0, "e {e} α {al}: {res}");
            }
        }
        // At e → R and α = π: ρ1 = R − e exactly, not a cancelled difference.
        let e = 1.0 - 1e-12;
        let c = EccentricCircle::new(1.0, e).unwrap();
        let exact = 1.0 - e; // exact by Sterbenz's lemma
        assert!((c.rho1(PI_TEST) - exact).abs() < 1e-14 * exact);
    }

    const PI_TEST: f64 = std::f64::consts::PI;

    #[test]
    fn second_derivative_matches_finite_difference() {
        let c = EccentricCircle::new(37.5, 15.0).unwrap();
        for k in 0..50 {
            let x = 0.1 + k as f64 * 0.12;
            let h = 1e-4;
            let fd = (c.rho1(x + h) - 2.0 * c.rho1(x) + c.rho1(x - h)) / (h * h);
            assert!((fd - c.rho1_d2(x)).abs() < 1e-5, "{x}");
            let fd1 = (c.rho1(x + h) - c.rho1(x - h)) / (2.0 * h);
            assert!((fd1 - c.rho1_d1(x)).abs() < 1e-6);
        }
    }
}

/// The former unit tests of `src/families/gear/study.rs`.
mod study {
    use cwsynth::families::gear::synth::{Objectives, Var};
    use cwsynth::report::numbers::declared_keys;

    #[test]
    fn the_key_objectives_are_fields_of_the_objectives() {
        let o = Objectives {
            peak_sliding_coefficient: 0.0,
            ratio_variation: 0.0,
            max_pitch_pressure_angle_rad: 0.0,
            min_gear2_curvature_per_m: 0.0,
        };
        let keys = declared_keys(&o);
        for v in [
            Var::Fixed(0.01),
            Var::Free {
                min: 0.0,
                max: 0.01,
            },
        ] {
            assert!(keys.contains(&Objectives::key(&v).to_string()));
        }
    }
}
