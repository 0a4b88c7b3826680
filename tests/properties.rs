//! Property tests over random valid scenes: no NaN, no panic, the optimum never worse than
//! any baseline, forces scale with ω², and the in-line slider's mirror symmetry puts the
//! force optimum on the crank axis. Case counts are kept small so the suite stays fast
//! (`PROPTEST_CASES` overrides them for a longer run).

use cwsynth::families::parse_str;
use cwsynth::families::slider_crank::model::{Crank, Kinematics, Rod, SliderCrank};
use cwsynth::families::slider_crank::synth::{
    baselines, metrics, optimise, paper_piston, Objective, Scene,
};
use cwsynth::families::solve_scene;
use proptest::prelude::*;
use std::path::Path;

fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// A random valid slider-crank: R in [1 cm, 1 m], λ in [0.02, 0.9], an offset for some,
/// masses log-uniform over six decades, lumped or rigid rod, ω in [1, 1000] rad/s.
fn scene() -> impl Strategy<Value = Scene> {
    (
        0.01f64..1.0,
        0.02f64..0.9,
        prop_oneof![Just(0.0), -0.9f64..0.9],
        (-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0),
        0.0f64..=1.0,
        any::<bool>(),
        any::<bool>(),
        1.0f64..1000.0,
    )
        .prop_map(|(r, lam, off, (a, b, c), split, rigid, two_h, omega)| {
            let l = r / lam;
            // |e| < (L − R)·0.9 keeps (R + |e|)/L < 1.
            let e = off * (l - r) * 0.9;
            let (m2, m3, m4) = (10f64.powf(a), 10f64.powf(b), 10f64.powf(c));
            let mut sc = paper_piston(1000.0);
            sc.mech = SliderCrank {
                r,
                l,
                e,
                kinematics: if two_h && e == 0.0 {
                    Kinematics::TwoHarmonic
                } else {
                    Kinematics::Exact
                },
                crank: Crank {
                    mass: m2,
                    centroid: 0.5 * r,
                },
                rod: if rigid {
                    Rod::rigid(m3, l, None, None)
                } else {
                    Rod::lumped(m3, split, l)
                },
                slider_mass: m4,
            };
            sc.omega = omega;
            sc
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(48), .. ProptestConfig::default() })]

    #[test]
    fn optimum_is_finite_and_never_worse_than_a_baseline(sc in scene()) {
        let o = optimise(&sc).expect("a valid scene solves");
        prop_assert!(o.u.x.is_finite() && o.u.y.is_finite());
        let m = metrics(&sc, o.u).unwrap();
        prop_assert!(m.peak.is_finite() && m.rms.is_finite() && m.peak_torque.is_finite());
        for (name, b) in baselines(&sc).unwrap() {
            prop_assert!(b.peak.is_finite());
            prop_assert!(
                m.peak <= b.peak * (1.0 + 1e-7) + m.peak_error + b.peak_error,
                "optimum {} worse than {name} {}", m.peak, b.peak
            );
        }
    }

    #[test]
    fn forces_scale_with_omega_squared(sc in scene(), k in 0.1f64..10.0) {
        let o = optimise(&sc).unwrap();
        let m1 = metrics(&sc, o.u).unwrap();
        let mut s2 = sc.clone();
        s2.omega *= k;
        let m2 = metrics(&s2, o.u).unwrap();
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
        prop_assert!(rel(m2.peak, k * k * m1.peak) < 1e-9, "{} vs {}", m2.peak, k * k * m1.peak);
        prop_assert!(rel(m2.rms, k * k * m1.rms) < 1e-9);
        // And the optimum itself does not move (the problem is ω² times the same one).
        let o2 = optimise(&s2).unwrap();
        let p2 = metrics(&s2, o2.u).unwrap().peak;
        prop_assert!(rel(p2, k * k * m1.peak) < 1e-6, "{p2} vs {}", k * k * m1.peak);
    }

    #[test]
    fn inline_slider_force_optimum_lies_on_the_crank_axis(mut sc in scene(), rms in any::<bool>()) {
        // F(−φ) mirrors F(φ) in x for U on the x axis: the mirror image of an optimum is an
        // optimum, the problem is convex, so their mean (on the axis) is one too. The RMS QP
        // is strictly convex, its optimum is unique and on the axis; the minimax one is
        // checked by its value on the axis.
        sc.mech.e = 0.0;
        sc.objective = if rms { Objective::MinRmsForce } else { Objective::MinPeakForce };
        let o = optimise(&sc).unwrap();
        let n = o.u.norm().max(1e-300);
        if rms {
            prop_assert!(o.u.y.abs() <= 1e-6 * n, "U = {:?}", o.u);
        } else {
            let on_axis = cwsynth::geom::P2::new(o.u.x, 0.0);
            let a = metrics(&sc, on_axis).unwrap();
            let b = metrics(&sc, o.u).unwrap();
            prop_assert!(a.peak <= b.peak * (1.0 + 1e-7) + a.peak_error, "{} vs {}", a.peak, b.peak);
            prop_assert!(o.u.y.abs() <= 1e-4 * n, "U = {:?}", o.u);
        }
    }
}

const HYPO: &str = include_str!("../problems/hypocycloid-variant1.toml");

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(16), .. ProptestConfig::default() })]

    #[test]
    fn hypocycloid_random_lambda_theta_is_finite(lam in 0.01f64..0.4, theta in 0.05f64..0.95) {
        let t = HYPO
            .replacen("lambda = 0.25", &format!("lambda = {lam}"), 1)
            .replacen("theta = 0.5", &format!("theta = {theta}"), 1);
        match parse_str(&t, Path::new("p.toml")) {
            Err(e) => prop_assert!(e.field().is_some(), "{e}"),
            Ok(s) => {
                let r = solve_scene(&s);
                for (k, v) in r.objectives.iter().chain(r.design.iter()) {
                    prop_assert!(v.is_finite(), "{k} = {v}");
                }
                let res = r.objectives["residual_force_peak_n"];
                let unb = r.objectives["unbalanced_force_peak_n"];
                prop_assert!(res <= unb * (1.0 + 1e-9), "balancing made it worse: {res} > {unb}");
            }
        }
    }
}
