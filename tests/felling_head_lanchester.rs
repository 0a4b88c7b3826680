//! Issue 38: the felling head with Lanchester balancers (`problems/felling-head-lanchester.toml`)
//! — its force–torque front (every point `optimal`, none outside its limit), one point checked
//! by brute force from the mechanism's positions alone (not the engine's fields), the
//! comparison crank counterweight / one pair / two pairs against separate solves, and the
//! front point that ended `inaccurate` before the polish's flat direction was handled.

use cwsynth::families::slider_crank::file::SliderCrankProblem;
use cwsynth::families::slider_crank::synth::Scene;
use cwsynth::families::{load, parse_str, solve_scene};
use cwsynth::geom::P2;
use cwsynth::report::{SolveResult, Status};
use std::f64::consts::TAU;
use std::path::Path;

const FILE: &str = "problems/felling-head-lanchester.toml";

fn solved(text: &str) -> SolveResult {
    solve_scene(&parse_str(text, Path::new("t.toml")).unwrap_or_else(|e| panic!("{e}")))
}

fn shipped() -> (SolveResult, Scene) {
    let s = load(Path::new(FILE)).unwrap_or_else(|e| panic!("{e}"));
    let core = s
        .machine::<SliderCrankProblem>()
        .expect("family")
        .core
        .clone();
    (solve_scene(&s), core)
}

/// The shipped file with `from` replaced by `to` (each must occur).
fn variant(edits: &[(&str, &str)]) -> String {
    let mut t = std::fs::read_to_string(FILE).expect("shipped");
    for (from, to) in edits {
        assert!(t.contains(from), "{from}");
        t = t.replacen(from, to, 1);
    }
    t
}

/// Position, velocity and acceleration (in φ) of the rod's centroid G3 and the slider B, and
/// ψ', ψ'' of the rod, from the slider-crank's closed form written out here (A = R e^{iφ},
/// B = (R cos φ + k, e), k = √(L² − σ²), σ = R sin φ − e, ψ = atan2(−σ, k), G3 on AB at
/// the rod's centroid), not from the engine's fields.
struct Kin {
    g3: [P2; 3],
    b: [P2; 3],
    psi: [f64; 2],
}

fn kinematics(s: &Scene, phi: f64) -> Kin {
    let m = &s.mech;
    let (c, sn) = (phi.cos(), phi.sin());
    let (sg, sg1, sg2) = (m.r * sn - m.e, m.r * c, -m.r * sn);
    let k = (m.l * m.l - sg * sg).sqrt();
    let k1 = -sg * sg1 / k;
    let k2 = -(sg1 * sg1 + sg * sg2) / k - sg * sg * sg1 * sg1 / (k * k * k);
    let a = [
        P2::new(m.r * c, m.r * sn),
        P2::new(-m.r * sn, m.r * c),
        P2::new(-m.r * c, -m.r * sn),
    ];
    let b = [
        P2::new(m.r * c + k, m.e),
        P2::new(-m.r * sn + k1, 0.0),
        P2::new(-m.r * c + k2, 0.0),
    ];
    let f = m.rod.centroid / m.l;
    let g3 = [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * f);
    Kin {
        g3,
        b,
        psi: [-sg1 / k, -sg2 / k - sg * sg1 * sg1 / (k * k * k)],
    }
}

/// The first moment Σ m r of every moving mass at φ and its derivatives in φ (order 0, 1, 2):
/// the crank, the rod, the slider, the counterweight U turning with the crank and each pair's
/// two shafts at ±(nφ + arg B_n) (together |B_n| cos(nφ + arg B_n) along the slider axis).
fn first_moment(s: &Scene, u: P2, bal: &[[f64; 2]], phi: f64, order: usize) -> P2 {
    let m = &s.mech;
    let kin = kinematics(s, phi);
    // d^order/dφ^order of Rot(φ)v.
    let turn = |v: P2| {
        let t = phi + order as f64 * std::f64::consts::FRAC_PI_2;
        P2::new(t.cos() * v.x - t.sin() * v.y, t.sin() * v.x + t.cos() * v.y)
    };
    let mut p = turn(P2::new(m.crank.mass * m.crank.centroid, 0.0))
        + kin.g3[order] * m.rod.mass
        + kin.b[order] * m.slider_mass
        + turn(u);
    for (spec, bn) in s.balancers.iter().zip(bal) {
        let n = spec.pair.order as f64;
        let t = n * phi + bn[1].atan2(bn[0]) + order as f64 * std::f64::consts::FRAC_PI_2;
        p += P2::new(bn[0].hypot(bn[1]) * n.powi(order as i32) * t.cos(), 0.0);
    }
    p
}

/// |F| = ω²|P''(φ)|, the shaking force of the design (U, B_n) at constant speed.
fn force(s: &Scene, u: P2, bal: &[[f64; 2]], phi: f64) -> f64 {
    first_moment(s, u, bal, phi, 2).norm() * s.omega * s.omega
}

/// The drive torque at constant speed as the energy's rate, T = dE/dφ with E = ½ω²(m3|G3'|² +
/// I3 ψ'² + m4|B'|²) − g·P (the crank, the counterweight and the shafts turn at constant
/// speed: their kinetic energy is constant): T = ω²(m3 G3'·G3'' + I3 ψ'ψ'' + m4 B'·B'') − g·P'.
fn torque(s: &Scene, u: P2, bal: &[[f64; 2]], phi: f64) -> f64 {
    let m = &s.mech;
    let g = s.loads.gravity;
    let kin = kinematics(s, phi);
    let inertial = m.rod.mass * kin.g3[1].dot(&kin.g3[2])
        + m.rod.inertia * kin.psi[0] * kin.psi[1]
        + m.slider_mass * kin.b[1].dot(&kin.b[2]);
    s.omega * s.omega * inertial - g.dot(&first_moment(s, u, bal, phi, 1))
}

/// max over φ of `f`: a scan of 20 000 angles, then golden-section refinement about the best.
fn peak(f: impl Fn(f64) -> f64) -> f64 {
    let n = 20_000;
    let h = TAU / n as f64;
    let best = (0..n)
        .map(|k| k as f64 * h)
        .max_by(|a, b| f(*a).total_cmp(&f(*b)))
        .expect("angles");
    let (mut lo, mut hi) = (best - h, best + h);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if f(x1) > f(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    f(0.5 * (lo + hi)).max(f(best))
}

fn num(v: &serde_json::Value, k: &str) -> f64 {
    v[k].as_f64().unwrap_or_else(|| panic!("{k}"))
}

#[test]
fn felling_head_lanchester_front_every_point_optimal_within_its_limit() {
    let (r, _) = shipped();
    assert_eq!(r.status, Status::Optimal);
    let pts = r.extra["pareto"].as_array().expect("a front");
    assert!(pts.len() >= 8, "{} points", pts.len());
    let mut last_torque = f64::INFINITY;
    for p in pts {
        assert_eq!(p["status"], "optimal", "{p}");
        let (f, eps) = (num(p, "peak_shaking_force_n"), num(p, "force_limit_n"));
        // No point outside its limit, to the polish's round-off (the torque end's limit, the
        // torque optimum's own force, is met to 2.6e-13 of it).
        assert!(f <= eps * (1.0 + 1e-12), "{f} > {eps}");
        let t = num(p, "peak_drive_torque_nm");
        assert!(t < last_torque, "the torque falls along the front");
        last_torque = t;
        assert_eq!(p["balancers_kgm"].as_array().map(Vec::len), Some(2));
    }
    // The force optimum's end: the two pairs leave about 102 N of the bare 5957 N.
    assert!((num(&pts[0], "peak_shaking_force_n") - 101.741).abs() < 1e-2);
}

#[test]
fn felling_head_lanchester_front_point_by_brute_force() {
    let (r, s) = shipped();
    for p in r.extra["pareto"].as_array().expect("a front") {
        let u = P2::new(num(p, "unbalance_x_kgm"), num(p, "unbalance_y_kgm"));
        let bal: Vec<[f64; 2]> = p["balancers_kgm"]
            .as_array()
            .expect("pairs")
            .iter()
            .map(|b| [b[0].as_f64().unwrap(), b[1].as_f64().unwrap()])
            .collect();
        let f = peak(|phi| force(&s, u, &bal, phi));
        let t = peak(|phi| torque(&s, u, &bal, phi).abs());
        let (fe, te) = (
            num(p, "peak_shaking_force_n"),
            num(p, "peak_drive_torque_nm"),
        );
        // Both to their round-off (the engine states about 1e-10 N and 1e-11 N·m).
        eprintln!(
            "brute force: force {:.3e}, torque {:.3e} relative",
            (f - fe).abs() / fe,
            (t - te).abs() / te
        );
        assert!((f - fe).abs() <= 1e-10 * fe, "force {f} against {fe}");
        assert!((t - te).abs() <= 1e-10 * te, "torque {t} against {te}");
    }
}

#[test]
fn felling_head_lanchester_comparison_equals_separate_solves() {
    let (r, _) = shipped();
    let rows = r.extra["balancer_comparison"].as_array().expect("rows");
    assert_eq!(rows.len(), 3);
    let one = variant(&[
        ("orders = [1, 2]", "orders = [1]"),
        (
            "max_unbalance = [\"20 kg*m\", \"5 kg*m\"]",
            "max_unbalance = [\"20 kg*m\"]",
        ),
        ("radius = [\"126 mm\", \"63 mm\"]", "radius = [\"126 mm\"]"),
    ]);
    let cut = |t: &str| {
        let a = t.find("[design.balancers]").expect("section");
        let b = t[a..].find("[design.paper]").expect("next") + a;
        format!("{}{}", &t[..a], &t[b..])
    };
    let files = [
        cut(&variant(&[])).replace("pareto_points = 9", ""),
        one.replace("pareto_points = 9", ""),
        variant(&[("pareto_points = 9", "")]),
    ];
    for (row, text) in rows.iter().zip(&files) {
        let alone = solved(text);
        assert_eq!(alone.status, Status::Optimal);
        assert_eq!(row["status"], "optimal");
        for (key, of) in [
            ("peak_shaking_force_n", "peak_shaking_force_n"),
            ("peak_drive_torque_nm", "peak_drive_torque_nm"),
        ] {
            assert_eq!(
                num(row, key),
                alone.objectives[of],
                "{key} of {}",
                row["orders"]
            );
        }
    }
    // Counterweight only > one pair > two pairs in force; the shafts' mass grows with them.
    let f: Vec<f64> = rows
        .iter()
        .map(|r| num(r, "peak_shaking_force_n"))
        .collect();
    let m: Vec<f64> = rows
        .iter()
        .map(|r| num(r, "balancer_shafts_mass_kg"))
        .collect();
    assert!(f[0] > f[1] && f[1] > f[2], "{f:?}");
    assert!(m[0] == 0.0 && m[1] > 100.0 && m[2] > m[1], "{m:?}");
    // One order-1 pair of centroid radius R balances m_s·R: its two shafts weigh m_s.
    assert!((m[1] - 126.75).abs() < 1e-6, "{}", m[1]);
}

/// Issue 38's hand-made front point: both pairs, the drive torque limited, the peak force
/// minimised. At 355 and 360 N·m it ended `inaccurate` after 30 exchange rounds (Newton's
/// polish drifted along the flat direction U against B₁).
#[test]
fn felling_head_lanchester_torque_limited_points_certify() {
    for limit in ["350 N*m", "355 N*m", "360 N*m"] {
        let text = variant(&[
            (
                "pareto_points = 9",
                &format!("max_peak_torque = \"{limit}\""),
            ),
            ("compare = true", "compare = false"),
        ]);
        let r = solved(&text);
        assert_eq!(r.status, Status::Optimal, "{limit}: {:?}", r.warnings);
        let t = r.objectives["peak_drive_torque_nm"];
        let lim: f64 = limit.split(' ').next().unwrap().parse().unwrap();
        assert!(t <= lim * (1.0 + 1e-9), "{limit}: {t}");
    }
}
