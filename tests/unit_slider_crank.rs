//! The slider-crank family's model (`src/families/slider_crank/model.rs`: the force-only
//! evaluation, derivatives, torque as dE/dφ, the two-harmonic and primary models) and its
//! study's headlines (`study.rs`).
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

/// The former unit tests of `src/families/slider_crank/model.rs`.
mod model {
    use cwsynth::families::slider_crank::model::{rot_cs, Crank, Kinematics, Rod, SliderCrank};
    use cwsynth::geom::P2;

    fn piston() -> SliderCrank {
        SliderCrank {
            r: 0.035,
            l: 0.14,
            e: 0.01,
            kinematics: Kinematics::Exact,
            crank: Crank {
                mass: 0.35,
                centroid: 0.0175,
            },
            rod: Rod::rigid(0.3, 0.14, Some(0.05), Some(4e-4)),
            slider_mass: 1.03,
        }
    }

    #[test]
    fn force_only_evaluation_is_bit_identical_to_the_state() {
        for kin in [
            Kinematics::Exact,
            Kinematics::TwoHarmonic,
            Kinematics::Primary,
        ] {
            let m = SliderCrank {
                kinematics: kin,
                ..piston()
            };
            for k in 0..10_007 {
                let phi = k as f64 * std::f64::consts::TAU / 10_007.0 - 1.0;
                let st = m.state(phi).unwrap();
                let (cs, f0) = m.shaking_force0_at(phi).unwrap();
                assert_eq!(cs, st.cs);
                assert_eq!(f0, m.shaking_force0(&st), "{kin:?} at {phi}");
            }
        }
        let toggle = SliderCrank { e: 0.2, ..piston() };
        assert!(toggle.state(1.5).is_none() && toggle.shaking_force0_at(1.5).is_none());
    }

    #[test]
    fn force_y_is_one_harmonic_of_the_stated_amplitude() {
        for kin in [
            Kinematics::Exact,
            Kinematics::TwoHarmonic,
            Kinematics::Primary,
        ] {
            let m = SliderCrank {
                kinematics: kin,
                ..piston()
            };
            for u in [P2::zeros(), P2::new(-0.02, 0.003), P2::new(0.01, -0.04)] {
                let a = m.force_y_amplitude(u);
                let (mut hi, mut lo) = (f64::MIN, f64::MAX);
                for k in 0..20_000 {
                    let phi = k as f64 * std::f64::consts::TAU / 20_000.0;
                    let st = m.state(phi).unwrap();
                    let y = (m.shaking_force0(&st) + rot_cs(st.cs, u)).y;
                    // F_y/ω² = A sin(φ + φ₀) at every angle, not only at the extremes.
                    let s0 = m.force_y_amplitude(P2::new(u.x, 0.0)).copysign(
                        m.crank.mass * m.crank.centroid
                            + m.rod.mass * (1.0 - m.rod.centroid / m.l) * m.r
                            + u.x,
                    );
                    let exact = s0 * phi.sin() + u.y * phi.cos();
                    assert!(
                        (y - exact).abs() <= 1e-15 * a.max(1e-300),
                        "{kin:?} {u:?} {phi}"
                    );
                    hi = hi.max(y);
                    lo = lo.min(y);
                }
                // Sampled every 3e-4 rad: within a·δ²/2 of the amplitude.
                assert!((hi - a).abs() <= 1e-7 * a && (lo + a).abs() <= 1e-7 * a);
            }
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        let m = piston();
        let h = 1e-5;
        for k in 0..24 {
            let phi = 0.3 + k as f64 * 0.26;
            let (s0, sm, sp) = (
                m.state(phi).unwrap(),
                m.state(phi - h).unwrap(),
                m.state(phi + h).unwrap(),
            );
            for i in 0..2 {
                let fd_x = (sp.x[i] - sm.x[i]) / (2.0 * h);
                assert!((fd_x - s0.x[i + 1]).abs() < 1e-8, "x^({}) at {phi}", i + 1);
                let (pp, pm) = if i == 0 {
                    (sp.psi(), sm.psi())
                } else {
                    (sp.dpsi[0], sm.dpsi[0])
                };
                let fd_psi = (pp - pm) / (2.0 * h);
                assert!(
                    (fd_psi - s0.dpsi[i]).abs() < 1e-7,
                    "psi^({}) at {phi}",
                    i + 1
                );
                let fd_g = (sp.g3[i] - sm.g3[i]) / (2.0 * h);
                assert!((fd_g - s0.g3[i + 1]).norm() < 1e-8);
            }
            // The rod really has length L and ends on the slider line.
            let b = P2::new(s0.x[0], m.e);
            assert!(((b - s0.a[0]).norm() - m.l).abs() < 1e-15);
        }
    }

    #[test]
    fn cannot_assemble_past_the_reach() {
        let mut m = piston();
        m.l = 0.04; // R + e = 0.045 > L
        assert!(m.state(-std::f64::consts::FRAC_PI_2).is_none());
        assert!(m.state(0.0).is_some());
    }

    #[test]
    fn torque_is_the_derivative_of_kinetic_energy() {
        let m = piston();
        let h = 1e-5;
        for k in 0..16 {
            let phi = 0.1 + k as f64 * 0.39;
            let de = (m.kinetic_energy0(&m.state(phi + h).unwrap())
                - m.kinetic_energy0(&m.state(phi - h).unwrap()))
                / (2.0 * h);
            let t = m.drive_torque0(&m.state(phi).unwrap());
            assert!((de - t).abs() < 1e-9, "{de} vs {t}");
        }
    }

    /// Issue 14 item 3: two-harmonic kinematics is one consistent model. A lumped rod (two
    /// point masses) has zero shaking moment and the torque m_ct x'x'' exactly; a rigid rod's
    /// torque is still dE/dφ of the same model, and its moment is −ΔI ψ''.
    #[test]
    fn two_harmonic_model_is_consistent() {
        let mut m = piston();
        m.e = 0.0;
        m.kinematics = Kinematics::TwoHarmonic;
        m.rod = Rod::lumped(0.3, 0.5, m.l);
        assert!(m.rod_inertia_excess().abs() < 1e-18);
        let h = 1e-5;
        for k in 0..24 {
            let phi = 0.05 + k as f64 * 0.27;
            let st = m.state(phi).unwrap();
            assert_eq!(m.shaking_moment0(&st), 0.0, "lumped moment at {phi}");
            let t = m.drive_torque0(&st);
            assert!((t - m.m_rec() * st.x[1] * st.x[2]).abs() < 1e-18);
        }
        m.rod = Rod::rigid(0.3, m.l, Some(0.05), Some(4e-4));
        let di = m.rod_inertia_excess();
        assert!(di.abs() > 1e-5);
        for k in 0..16 {
            let phi = 0.1 + k as f64 * 0.39;
            let de = (m.kinetic_energy0(&m.state(phi + h).unwrap())
                - m.kinetic_energy0(&m.state(phi - h).unwrap()))
                / (2.0 * h);
            let st = m.state(phi).unwrap();
            assert!((de - m.drive_torque0(&st)).abs() < 1e-9);
            let lam = m.lambda();
            assert!((m.shaking_moment0(&st) + di * lam * phi.sin()).abs() < 1e-15);
            // ψ' and ψ'' are the derivatives of the series ψ = −λ sin φ.
            assert!((st.dpsi[0] + lam * phi.cos()).abs() < 1e-15);
        }
    }

    /// Obliquity neglected: the textbooks' primary forces, F/ω² = (m_tq R + U_x, …) with the
    /// whole reciprocating mass on −R cos φ, the torque m_ct x'x'' and no moment (lumped rod),
    /// whatever the rod length — the figures for L and for 7L agree to the last bits.
    #[test]
    fn primary_model_is_the_textbooks_and_ignores_the_rod_length() {
        let mut m = piston();
        m.e = 0.0;
        m.kinematics = Kinematics::Primary;
        m.rod = Rod::lumped(0.3, 0.5, m.l);
        let long = SliderCrank {
            l: 7.0 * m.l,
            rod: Rod::lumped(0.3, 0.5, 7.0 * m.l),
            ..m
        };
        let (mt, mc, r) = (m.m_rot(), m.m_rec(), m.r);
        for k in 0..36 {
            let phi = 0.01 + k as f64 * 0.17;
            let (st, sl) = (m.state(phi).unwrap(), long.state(phi).unwrap());
            let f = m.shaking_force0(&st);
            let (s, c) = phi.sin_cos();
            // F = −Σ m a: the pin's mass on the circle, the slider's on −R cos φ.
            let want = P2::new((mt + mc) * r * c, mt * r * s);
            assert!(
                (f - want).norm() <= 1e-15 * (mt + mc) * r,
                "{phi}: {f:?} {want:?}"
            );
            assert!((f - long.shaking_force0(&sl)).norm() <= 1e-16 * (mt + mc) * r);
            assert_eq!(m.shaking_moment0(&st), 0.0);
            let t = m.drive_torque0(&st);
            assert!((t - mc * r * r * s * c).abs() <= 1e-15 * mc * r * r);
            assert!((t - long.drive_torque0(&sl)).abs() <= 1e-16 * mc * r * r);
        }
    }
}

/// The former unit tests of `src/families/slider_crank/study.rs`.
mod study {
    use cwsynth::families::slider_crank::synth::{headline, Design, Objective, Objectives};
    use cwsynth::report::numbers::declared_keys;

    #[test]
    fn every_headline_is_a_field_of_the_design_or_the_objectives() {
        let o = Objectives {
            peak_shaking_force_n: 0.0,
            rms_shaking_force_n: 0.0,
            peak_drive_torque_nm: 0.0,
            peak_shaking_moment_nm: 0.0,
            energy_fluctuation_j: None,
            worst_case_peak_shaking_force_n: None,
            worst_case_peak_drive_torque_nm: None,
            worst_case_energy_fluctuation_j: None,
        };
        let d = Design::new(
            [0.0, 0.0],
            &cwsynth::families::slider_crank::synth::Realised {
                mass: None,
                radius: None,
                plate: None,
                plate_note: None,
            },
            None,
        );
        use Objective::*;
        for obj in [MinPeakForce, MinRmsForce, MinMass, MinRadius, MinPeakTorque] {
            let h = headline(obj);
            let (section, key) = h.split_once('.').unwrap();
            let keys = if section == "design" {
                declared_keys(&d)
            } else {
                declared_keys(&o)
            };
            assert!(keys.contains(&key.to_string()), "{h}");
            assert!(declared_keys(&o).contains(&Objectives::key(obj).to_string()));
        }
    }
}
