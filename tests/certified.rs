//! Issue 14's acceptance for the slider-crank family: every stated error covers the truth
//! and every `optimal` is unbeaten, on random and near-degenerate scenes (near toggle, tiny
//! and huge scales, offsets). The truth is an independent double-double (`twofloat`)
//! evaluation of the same closed-form kinematics, written out here from
//! `shared/domain/slider-crank.md`, not from the library's code path.

use common::Dd as D;
use cwsynth::families::slider_crank::model::{
    Crank, Kinematics, Loads, ProcessForce, Rod, SliderCrank,
};
use cwsynth::families::slider_crank::synth::{
    drive_torque, paper_piston, round_off_bounds, shaking_force, solve, Objective, Scene,
};
use cwsynth::geom::P2;
use std::f64::consts::TAU;

use crate::common;

use common::Lcg;

fn d(x: f64) -> D {
    D::from(x)
}

/// Shaking force (N), drive torque (N·m) and shaking moment (N·m) at φ in double-double,
/// exact kinematics: x = R cos φ + k, k = sqrt(L² − σ²), σ = R sin φ − e, and their
/// φ-derivatives by the chain rule; ψ from sin ψ = −σ/L.
fn truth(sc: &Scene, u: P2, phi: f64) -> (f64, f64, f64) {
    let m = &sc.mech;
    assert_eq!(m.kinematics, Kinematics::Exact);
    let (r, l, e) = (d(m.r), d(m.l), d(m.e));
    let (s, c) = common::dd_sin_cos(d(phi));
    let sigma = r * s - e;
    let (sigma1, sigma2) = (r * c, -(r * s));
    let k2 = (l - sigma) * (l + sigma);
    let k = k2.sqrt();
    // k' = −σσ'/k, k'' = −(σ'² + σσ'')/k − σ²σ'²/k³.
    let k1 = -(sigma * sigma1) / k;
    let kk2 = -(sigma1 * sigma1 + sigma * sigma2) / k - sigma * sigma * sigma1 * sigma1 / (k2 * k);
    let x = [r * c + k, -(r * s) + k1, -(r * c) + kk2];
    // ψ with sin ψ = −σ/L, cos ψ = k/L: ψ' = −σ'/k, ψ'' = −σ''/k + σ' k'/k².
    let p1 = -sigma1 / k;
    let p2 = -sigma2 / k + sigma1 * k1 / k2;
    let a = [[r * c, r * s], [-(r * s), r * c], [-(r * c), -(r * s)]];
    let mu = d(m.rod.centroid) / l;
    let one = d(1.0);
    let g3 = |i: usize| -> [D; 2] {
        [
            (one - mu) * a[i][0] + mu * x[i],
            (one - mu) * a[i][1] + if i == 0 { mu * e } else { d(0.0) },
        ]
    };
    let (m2, m3, m4) = (d(m.crank.mass), d(m.rod.mass), d(m.slider_mass));
    let r2r = d(m.crank.centroid) / r;
    let w2 = d(sc.omega) * d(sc.omega);
    let (ux, uy) = (d(u.x), d(u.y));
    // Rot(φ)U and its derivative.
    let ru = [c * ux - s * uy, s * ux + c * uy];
    let ru1 = [-(s * ux) - c * uy, c * ux - s * uy];
    let f = [
        w2 * (-(m2 * r2r * a[2][0] + m3 * g3(2)[0] + m4 * x[2]) + ru[0]),
        w2 * (-(m2 * r2r * a[2][1] + m3 * g3(2)[1]) + ru[1]),
    ];
    let fnorm = (f[0] * f[0] + f[1] * f[1]).sqrt();
    let (g31, g32) = (g3(1), g3(2));
    let i3 = d(m.rod.inertia);
    let t_in = m3 * (g31[0] * g32[0] + g31[1] * g32[1]) + i3 * p1 * p2 + m4 * x[1] * x[2];
    let g = [d(sc.loads.gravity.x), d(sc.loads.gravity.y)];
    let weights = m2 * r2r * (g[0] * a[1][0] + g[1] * a[1][1])
        + m3 * (g[0] * g31[0] + g[1] * g31[1])
        + m4 * g[0] * x[1];
    let fp = d(sc.loads.process.at(phi));
    let t_cw = -(g[0] * ru1[0] + g[1] * ru1[1]);
    let torque = w2 * t_in - weights - fp * x[1] + t_cw;
    let g30 = g3(0);
    let moment = -(w2
        * (m3 * (g30[0] * g32[1] - g30[1] * g32[0]) + i3 * p2 + m4 * (x[0] * d(0.0) - e * x[2])));
    (f64::from(fnorm), f64::from(torque), f64::from(moment))
}

/// A random scene: log-uniform scales from micro-machines to presses, an offset slider, and
/// an assembly margin (L − R − |e|)/L from 0.5 down to 1e-9 (near toggle).
fn random_scene(g: &mut Lcg, margin: f64) -> Scene {
    let mut sc = paper_piston(1000.0);
    let r = g.log(1e-4, 10.0);
    let e = if g.next() < 0.5 {
        0.0
    } else {
        (g.next() - 0.5) * r
    };
    let l = (r + e.abs()) / (1.0 - margin);
    let mass = g.log(1e-6, 1e6);
    sc.mech = SliderCrank {
        r,
        l,
        e,
        kinematics: Kinematics::Exact,
        crank: Crank {
            mass: mass * g.log(0.1, 10.0),
            centroid: r * g.next(),
        },
        rod: Rod::rigid(
            mass * g.log(0.1, 10.0),
            l,
            Some(l * g.next()),
            Some(mass * l * l * g.log(0.01, 0.2)),
        ),
        slider_mass: mass * g.log(0.1, 10.0),
    };
    sc.omega = g.log(1.0, 3000.0);
    if g.next() < 0.5 {
        sc.loads = Loads {
            gravity: Loads::gravity_for_axis(9.80665, TAU * g.next()),
            process: ProcessForce::Constant(mass * r * sc.omega * sc.omega * (g.next() - 0.5)),
        };
    }
    sc
}

#[test]
fn round_off_bounds_cover_a_double_double_evaluation() {
    let mut g = Lcg(14);
    let mut worst = [0.0f64; 3];
    for case in 0..400 {
        let margin = if case % 4 == 0 {
            g.log(1e-9, 1e-3)
        } else {
            g.log(1e-3, 0.5)
        };
        let sc = random_scene(&mut g, margin);
        let m = &sc.mech;
        let uscale = (m.crank.mass + m.rod.mass + m.slider_mass) * m.r;
        let u = P2::new(g.next() - 0.5, g.next() - 0.5) * (2.0 * uscale);
        let bound = round_off_bounds(&sc, u);
        for j in 0..16 {
            // Include the toggle-critical angles ±π/2 (σ extreme) exactly.
            let phi = match j {
                0 => TAU / 4.0,
                1 => 3.0 * TAU / 4.0,
                _ => TAU * g.next(),
            };
            let Some(f) = shaking_force(m, sc.omega, u, phi) else {
                continue;
            };
            let st = m.state(phi).unwrap();
            let (tf, tt, tm) = truth(&sc, u, phi);
            let got = [
                f.norm(),
                drive_torque(&sc, u, phi),
                m.shaking_moment0(&st) * sc.omega * sc.omega,
            ];
            for (i, (gv, tv)) in got.iter().zip([tf, tt, tm]).enumerate() {
                let err = (gv - tv).abs();
                assert!(
                    err <= bound[i],
                    "case {case} quantity {i} at φ = {phi}: error {err:e} > bound {:e} (value {tv:e}, margin {margin:e}, {m:?})",
                    bound[i]
                );
                worst[i] = worst[i].max(err / bound[i]);
            }
        }
    }
    eprintln!("worst error/bound {worst:?}");
    // The bounds are not vacuous: the worst case uses a visible part of them.
    assert!(
        worst.iter().all(|&w| w > 1e-4),
        "worst error/bound {worst:?}"
    );
}

/// The true peak of |F| (`which` = 0) or |T| (1) for the design `u`: every sampled maximum
/// refined by golden section on the double-double values (independent of the library's
/// refinement).
fn true_peak(sc: &Scene, u: P2, which: usize) -> f64 {
    let val = |phi: f64| {
        let (f, t, _) = truth(sc, u, phi);
        if which == 0 {
            f
        } else {
            t.abs()
        }
    };
    let n = 1024;
    let h = TAU / n as f64;
    let v: Vec<f64> = (0..n).map(|k| val(k as f64 * h)).collect();
    let mut best = 0.0f64;
    for k in 0..n {
        let (a, b, c) = (v[(k + n - 1) % n], v[k], v[(k + 1) % n]);
        if b >= a && b >= c {
            let (mut lo, mut hi) = ((k as f64 - 1.0) * h, (k as f64 + 1.0) * h);
            let gr = 0.5 * (5f64.sqrt() - 1.0);
            for _ in 0..60 {
                let (x1, x2) = (hi - gr * (hi - lo), lo + gr * (hi - lo));
                if val(x1) < val(x2) {
                    lo = x1
                } else {
                    hi = x2
                }
            }
            best = best.max(val(0.5 * (lo + hi))).max(b);
        }
    }
    best
}

/// Random scenes of three kinds — free minimax force (the exact-disc route), minimax force
/// with the direction restricted to a sector (clarabel's SOCP), and the peak drive torque
/// with gravity (an LP) — each solved, its stated error checked against the double-double
/// true peak, and its `optimal` checked against perturbed designs.
#[test]
fn stated_peak_errors_cover_the_truth_and_optimal_is_unbeaten() {
    use cwsynth::synth::Var;
    let mut g = Lcg(1414);
    let mut optimal = 0;
    for case in 0..24 {
        let margin = if case % 4 == 0 {
            g.log(1e-7, 1e-3)
        } else {
            g.log(1e-3, 0.5)
        };
        let mut sc = random_scene(&mut g, margin);
        let kind = case % 3;
        sc.loads = Loads::default();
        sc.objective = Objective::MinPeakForce;
        if kind == 1 {
            let mid = std::f64::consts::PI + (g.next() - 0.5);
            sc.counterweight.angle = Var::Free {
                min: mid - 0.3,
                max: mid + 0.3,
            };
        } else if kind == 2 {
            // A slow vertical machine, where weights matter: g/(Rω²) ~ 0.1–3.
            sc.omega = (9.80665 / (sc.mech.r * g.log(0.1, 3.0))).sqrt();
            sc.loads.gravity = Loads::gravity_for_axis(9.80665, TAU / 4.0);
            sc.objective = Objective::MinPeakTorque;
        }
        let out = solve(&sc).unwrap();
        // `inaccurate` (an exchange loop stalled at clarabel's accuracy) is an honest status
        // too; its stated error must cover the truth all the same.
        let status = format!("{:?}", out.status);
        assert!(
            status == "Optimal" || status == "Inaccurate",
            "case {case}: {status} {:?}",
            out.warnings
        );
        optimal += usize::from(status == "Optimal");
        let which = usize::from(kind == 2);
        let u = P2::from(out.design.unbalance);
        let (value, stated) = if which == 0 {
            (out.design.peak, out.design.peak_error)
        } else {
            (out.design.peak_torque, out.design.peak_torque_error)
        };
        let truth_peak = true_peak(&sc, u, which);
        assert!(
            (value - truth_peak).abs() <= stated,
            "case {case} kind {kind}: {value} vs true {truth_peak} (diff {:e} > stated {stated:e}, margin {margin:e})",
            (value - truth_peak).abs()
        );
        // `optimal`: no feasible counterweight near the optimum has a lower true peak than the
        // stated optimum minus its error (gap + evaluation error).
        let err = out.gap + stated;
        let scale = u.norm().max(sc.mech.m_rec() * sc.mech.r);
        for j in 0..12 {
            let ang = TAU * j as f64 / 12.0;
            for rad in [1e-3, 1e-6] {
                let v = u + P2::new(ang.cos(), ang.sin()) * (rad * scale);
                if kind == 1 {
                    let (Var::Free { min, max }, beta) =
                        (sc.counterweight.angle, v.y.atan2(v.x).rem_euclid(TAU))
                    else {
                        unreachable!()
                    };
                    if beta < min || beta > max {
                        continue;
                    }
                }
                let p = true_peak(&sc, v, which);
                assert!(
                    p >= value - err,
                    "case {case} kind {kind}: U + δ beats the optimum: {p} < {value} − {err:e}"
                );
            }
        }
    }
    // 17 of 24 on this seed: the rest stop `inaccurate` at clarabel's accuracy, and say so.
    assert!(optimal >= 16, "only {optimal} of 24 certified");
}

/// Issue 14 item 10: minimising the peak drive torque without gravity is degenerate (the
/// counterweight cannot change it); it is flagged, the design is the minimax-force one, and
/// no flat Pareto front is drawn.
#[test]
fn torque_objective_without_gravity_is_degenerate_not_optimal() {
    let mut sc = paper_piston(1000.0);
    sc.objective = Objective::MinPeakTorque;
    sc.pareto_points = 5;
    let out = solve(&sc).unwrap();
    assert!(out.degenerate.is_some());
    assert!(out.pareto.is_empty());
    let force_opt = solve(&paper_piston(1000.0)).unwrap();
    assert!((out.design.peak - force_opt.design.peak).abs() <= 1e-9 * force_opt.design.peak);

    let text = std::fs::read_to_string(common::problem("piston-1000rpm.toml"))
        .unwrap()
        .replace("minimize = \"peak-force\"", "minimize = \"peak-torque\"");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("torque.toml");
    std::fs::write(&path, text).unwrap();
    let v = common::solve_json(&path);
    assert_eq!(v["status"], "degenerate", "{v}");
    assert!(v["status_detail"]
        .as_str()
        .unwrap()
        .contains("does not depend on the counterweight"));
    // With gravity the same objective is a real (convex) problem again.
    let mut sc = paper_piston(150.0);
    sc.objective = Objective::MinPeakTorque;
    sc.loads.gravity = Loads::gravity_for_axis(9.80665, TAU / 4.0);
    assert!(solve(&sc).unwrap().degenerate.is_none());
}

#[test]
fn the_double_double_reference_keeps_its_digits() {
    // `common::Dd`: the reference arithmetic of this file and of the crane, gear and
    // hypocycloid tests.
    // Residuals computed exactly enough to see 1e-30: a·(1/a) − 1 and the like.
    let mut seed = 7u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut worst: f64 = 0.0;
    for _ in 0..2000 {
        let a = D::new_add(0.1 + 10.0 * next(), 1e-17 * (next() - 0.5));
        let b = D::new_add(1e-3 + 1e3 * next(), 1e-19 * (next() - 0.5));
        let q = a / b;
        worst = worst.max((f64::from((q * b - a) / a)).abs());
        let r = 1.0 / b;
        worst = worst.max(f64::from(r * b - 1.0).abs());
        let s = a.sqrt();
        worst = worst.max((f64::from((s * s - a) / a)).abs());
        let (sn, cs) = common::dd_sin_cos(a);
        worst = worst.max(f64::from(sn * sn + cs * cs - 1.0).abs());
    }
    assert!(worst < 1e-30, "worst relative residual {worst:e}");
    // The fault this type exists for: twofloat's own T / T is ~1e-17.
    let t = twofloat::TwoFloat::from(1.0) / twofloat::TwoFloat::from(3.0);
    assert!(f64::from(t * 3.0 - 1.0).abs() > 1e-20);
}
