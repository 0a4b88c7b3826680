//! The luffing-crane family's model (`src/families/crane/model.rs`: the thesis example
//! against an independent reconstruction) and its study's key objective (`study.rs`).
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

/// The former unit tests of `src/families/crane/model.rs`.
mod model {
    use cwsynth::families::crane::model::{head_heights, synthesize, Angles, Boom, Branch, Guide};
    use cwsynth::geom::{Side, P2};

    fn thesis_boom(l_c: f64) -> Boom {
        let d = f64::to_radians;
        Boom::new(
            l_c,
            Angles {
                phi_min: d(35.0),
                gamma1: d(10.0),
                gamma2: d(5.0),
                gamma3: d(12.0),
            },
        )
        .unwrap()
    }

    #[test]
    fn thesis_example_matches_independent_reconstruction() {
        // Reference: an independent Python reconstruction (textbook circle intersection,
        // determinant circumcentre, 200 001 samples, max − min), /tmp/crane_proto.py:
        // k = 0.5216797937624817, B = (11.853886600000907, 4.155751777343402),
        // b = 27.70985907306044, Δh = 0.5488653233583047 (sampled, a lower bound within ~1e-11).
        let boom = thesis_boom(22.8);
        assert!((boom.k - 0.5216797937624817).abs() < 1e-15);
        let s = synthesize(&boom, 0.2, 0.4).unwrap();
        assert_eq!(s.branch, Branch::Consistent(Side::Left));
        let Guide::Circle { centre, radius } = s.guide else {
            panic!("circle expected")
        };
        assert!((centre - P2::new(11.853886600000907, 4.155751777343402)).norm() < 1e-10);
        assert!((radius - 27.70985907306044).abs() < 1e-10);
        let hh = head_heights(&s.linkage, 64, 1e-10).unwrap();
        assert!((hh.delta_h - 0.5488653233583047).abs() < 1e-9, "{hh:?}");
        assert!(hh.error < 1e-9);
    }
}

/// The former unit tests of `src/families/crane/study.rs`.
mod study {
    use cwsynth::families::crane::synth::Objectives;
    use cwsynth::report::numbers::declared_keys;

    #[test]
    fn the_key_objective_is_a_field_of_the_objectives() {
        assert!(declared_keys(&Objectives::default()).contains(&Objectives::KEY.to_string()));
    }
}
