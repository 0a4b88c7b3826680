//! Tests of the eccentric gear's tooth-level outputs (issue 19) against independent
//! references: closed-form epi/hypocycloids (e = 0, and gear 1 for any e), rolling of the
//! generating circle on gear 2's pitch curve placed by an independent arc-length quadrature,
//! finite differences of material-point positions for the contact velocities, a brute-force
//! trapezoid (and the e = 0 closed form) for the sliding distance, a geometric evaluation of
//! the involute pair, and a dense sign scan for the pole certificate.

use cwsynth::families::gear::model::*;
use cwsynth::families::gear::teeth::*;
use cwsynth::geom::P2;
use std::f64::consts::{PI, TAU};

use crate::common;

const R: f64 = 37.5e-3;
const RG: f64 = 1.25e-3;

fn pair_with(e: f64, rg: f64, n1: u32, n2: u32) -> GearPair {
    let c = EccentricCircle::new(R, e).unwrap();
    let cl = closing_center_distance(&c, n1, n2).unwrap();
    GearPair::new(c, rg, cl.a, 15.0).unwrap()
}

fn pair(e: f64) -> GearPair {
    pair_with(e, RG, 3, 1)
}

fn u(t: f64) -> P2 {
    P2::new(t.cos(), t.sin())
}

fn rot(v: P2, a: f64) -> P2 {
    let (s, c) = a.sin_cos();
    P2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Gear 1's arch i in its frame, closed form about C = (e, 0): the generating circle
/// rolled ϕ along the pitch circle from θ_i = 2πi/N (σ = +1 outside, −1 inside):
/// C + (R + σr)u(θ) − σr·u(θ + σϕ), θ = θ_i + rϕ/R.
fn cycloid1(e: f64, rg: f64, n: usize, i: usize, phi: f64) -> P2 {
    let sigma = if i.is_multiple_of(2) { 1.0 } else { -1.0 };
    let th = TAU * i as f64 / n as f64 + rg * phi / R;
    P2::new(e, 0.0) + u(th) * (R + sigma * rg) - u(th + sigma * phi) * (sigma * rg)
}

/// Composite Simpson of f on [a, b] with n (even) panels.
fn simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let mut s = f(a) + f(b);
    for k in 1..n {
        s += f(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

/// Cumulative integral of f on a uniform knot grid over [0, x_max] (Simpson per knot).
struct Cumulative {
    h: f64,
    at: Vec<f64>,
}

impl Cumulative {
    fn new(f: &dyn Fn(f64) -> f64, x_max: f64, knots: usize) -> Self {
        let h = x_max / knots as f64;
        let mut at = vec![0.0];
        for k in 0..knots {
            let v = at[k] + simpson(f, k as f64 * h, (k + 1) as f64 * h, 64);
            at.push(v);
        }
        Self { h, at }
    }
    fn eval(&self, f: &dyn Fn(f64) -> f64, x: f64) -> f64 {
        let k = ((x / self.h).floor() as usize).min(self.at.len() - 2);
        self.at[k] + simpson(f, k as f64 * self.h, x, 64)
    }
}

#[test]
fn circular_pair_outlines_are_closed_form_cycloids() {
    let p = pair(0.0);
    let a2 = Alpha2Map::new(&p.c, p.a);
    let pr = profiles(&p, &a2, 3, 1, 32);
    let n = p.n_arches;
    let (r2, m) = (p.a - R, pr.gear2.len());
    assert_eq!(m, 3 * n);
    let mut worst: f64 = 0.0;
    for arch in &pr.gear1 {
        assert_eq!(arch.epicycloid, arch.index % 2 == 0);
        for (ph, k) in arch.phi.iter().zip(&arch.points) {
            let want = cycloid1(0.0, RG, n, arch.index, *ph);
            worst = worst.max((k - want).norm() / R);
        }
    }
    eprintln!("e = 0: gear 1 outline vs closed form, worst {worst:e} (relative to R)");
    assert!(
        worst < 1e-12,
        "gear 1 off its cycloid by {worst:e} (relative)"
    );
    // Gear 2: a circle of radius R2 = 3R about O2; its pitch point starts at angle π and the
    // contact runs clockwise in gear 2's frame: θ2 = π − (2πg + ϕ)/M, and the arch is an
    // epicycloid where gear 1's is a hypocycloid: (R2 + σ2 r)u(θ2) − σ2 r u(θ2 − σ2 ϕ).
    let mut worst: f64 = 0.0;
    for arch in &pr.gear2 {
        let s2 = if arch.index % 2 == 0 { -1.0 } else { 1.0 };
        assert_eq!(arch.epicycloid, s2 > 0.0);
        for (ph, k) in arch.phi.iter().zip(&arch.points) {
            let th = PI - (TAU * arch.index as f64 + ph) / m as f64;
            let want = u(th) * (r2 + s2 * RG) - u(th - s2 * ph) * (s2 * RG);
            worst = worst.max((k - want).norm() / r2);
        }
    }
    eprintln!("e = 0: gear 2 outline vs closed form, worst {worst:e} (relative to R2)");
    assert!(
        worst < 1e-12,
        "gear 2 off its cycloid by {worst:e} (relative)"
    );
    assert!(pr.gear2_closure_gap_m < 1e-12 * r2);
}

#[test]
fn eccentric_outlines_roll_the_generating_circle_and_close() {
    let e = 15e-3;
    let p = pair(e);
    let a2 = Alpha2Map::new(&p.c, p.a);
    let pr = profiles(&p, &a2, 3, 1, 24);
    let n = p.n_arches;
    // Gear 1: the closed-form cycloid about C for any e.
    for arch in &pr.gear1 {
        for (ph, k) in arch.phi.iter().zip(&arch.points) {
            let want = cycloid1(e, RG, n, arch.index, *ph);
            assert!((k - want).norm() < 1e-12 * R, "gear 1 arch {}", arch.index);
        }
    }
    // Gear 2: its own polar pitch curve P2(α1) = ρ2 u(π − α2), ρ2 = a − ρ1,
    // α2 = ∫ρ1/ρ2 dα1 and arc length s = ∫sqrt(ρ2'² + ρ2² α2'²) dα1, both by Simpson here.
    let a = p.a;
    let f_a2 = |x: f64| {
        let r1 = p.c.rho1(x);
        r1 / (a - r1)
    };
    let f_s = |x: f64| {
        let r1 = p.c.rho1(x);
        let r2 = a - r1;
        let d = p.c.rho1_d1(x);
        (d * d + r2 * r2 * (r1 / r2).powi(2)).sqrt()
    };
    let xmax = 3.0 * TAU;
    let cum_a2 = Cumulative::new(&f_a2, xmax, 1800);
    let cum_s = Cumulative::new(&f_s, xmax, 1800);
    let total_a2 = cum_a2.eval(&f_a2, xmax);
    assert!(
        (total_a2 - TAU).abs() < 1e-12,
        "closure: gear 2 turns {total_a2}"
    );
    let mut worst_d: f64 = 0.0;
    let mut worst_c: f64 = 0.0;
    for arch in &pr.gear2 {
        let s2 = if arch.epicycloid { 1.0 } else { -1.0 };
        for (ph, k) in arch.phi.iter().zip(&arch.points) {
            // The pitch point at arc length 2πr·g + rϕ on gear 2 (Newton on s(α1)).
            let target = RG * (TAU * arch.index as f64 + ph);
            let mut x = target / R;
            for _ in 0..6 {
                x -= (cum_s.eval(&f_s, x) - target) / f_s(x);
            }
            let r2 = a - p.c.rho1(x);
            let al2 = cum_a2.eval(&f_a2, x);
            let pp = u(PI - al2) * r2;
            // Outward normal of gear 2's curve: its tangent dP2/dα1 turned clockwise.
            let t = u(PI - al2) * (-p.c.rho1_d1(x)) - rot(u(PI - al2), PI / 2.0) * (r2 * f_a2(x));
            let nu = P2::new(-t.y, t.x).normalize();
            let nu = if nu.dot(&pp) < 0.0 { -nu } else { nu };
            let centre = pp + nu * (s2 * RG);
            worst_d = worst_d.max(((k - pp).norm() - 2.0 * RG * (0.5 * ph).sin()).abs());
            worst_c = worst_c.max(((k - centre).norm() - RG).abs());
        }
    }
    eprintln!("e = 15 mm: rolling |K − P| worst {worst_d:e} m, |K − centre| worst {worst_c:e} m, gear 2 closure gap {:e} m", pr.gear2_closure_gap_m);
    assert!(
        worst_d < 1e-9 * RG,
        "|K − P| ≠ 2r sin(ϕ/2) by {worst_d:e} m"
    );
    assert!(
        worst_c < 1e-9 * RG,
        "K off the generating circle by {worst_c:e} m"
    );
    // Both outlines close: gear 1 over its turn, gear 2 after n1 = 3 turns of gear 1.
    let g1 = &pr.gear1;
    let gap1 = (g1[n - 1].points.last().unwrap() - g1[0].points[0]).norm();
    assert!(gap1 < 1e-15, "gear 1 gap {gap1:e}");
    assert!(
        pr.gear2_closure_gap_m < 1e-13,
        "gear 2 gap {:e}",
        pr.gear2_closure_gap_m
    );
    // Consecutive arches meet.
    for w in pr.gear2.windows(2) {
        let gap = (w[0].points.last().unwrap() - w[1].points[0]).norm();
        assert!(
            gap < 1e-15,
            "gear 2 arches {} / {}: {gap:e}",
            w[0].index,
            w[1].index
        );
    }
}

#[test]
fn contact_radii_and_velocities_match_finite_differences() {
    for e in [0.0, 15e-3, 30e-3] {
        let p = pair(e);
        let n = p.n_arches;
        let a = p.a;
        let o2 = P2::new(a, 0.0);
        let f_a2 = |x: f64| {
            let r1 = p.c.rho1(x);
            r1 / (a - r1)
        };
        let cum_a2 = Cumulative::new(&f_a2, TAU + 0.1, 700);
        let al2 = |x: f64| cum_a2.eval(&f_a2, x);
        let h = 1e-5;
        let dt = 2.0 * h / p.omega1;
        let mut worst: f64 = 0.0;
        for k in 0..613 {
            let x = 0.05 + (TAU - 0.1) * (k as f64 + 0.5) / 613.0;
            let ck = contact_kinematics(&p, x);
            // K from the closed-form cycloid of gear 1 at the rolling angle of α1.
            let th = x + (e * x.sin()).atan2(((R - e * x.sin()) * (R + e * x.sin())).sqrt());
            let i = ((th * n as f64 / TAU).floor() as usize).min(n - 1);
            let phi = th * n as f64 - TAU * i as f64;
            if !(0.02..TAU - 0.02).contains(&phi) {
                continue; // at a cusp the tangent turns over
            }
            let k1 = cycloid1(e, RG, n, i, phi);
            let kf = rot(k1, -x);
            let scale = ck.v_k1.max(ck.v_k2);
            worst = worst.max((ck.rho_k1 - kf.norm()).abs() / R);
            worst = worst.max((ck.rho_k2 - (kf - o2).norm()).abs() / R);
            // Material points: gear 1's K1, gear 2's K2, moved by ±h of α1.
            let v1 = (rot(k1, -(x + h)) - rot(k1, -(x - h))) / dt;
            let k2 = rot(kf - o2, -al2(x));
            let v2 = (rot(k2, al2(x + h)) - rot(k2, al2(x - h))) / dt;
            worst = worst.max((v1.norm() - ck.v_k1).abs() / scale);
            worst = worst.max((v2.norm() - ck.v_k2).abs() / scale);
            // The common tangent: the profile's tangent dK1/dϕ of the closed-form cycloid,
            // (R + σr)(r/R)u⊥(θ) − σr(r/R + σ)u⊥(θ + σϕ), turned into the fixed frame.
            let sigma = if i.is_multiple_of(2) { 1.0 } else { -1.0 };
            let th_c = TAU * i as f64 / n as f64 + RG * phi / R;
            let q = RG / R;
            let dk = rot(u(th_c), PI / 2.0) * ((R + sigma * RG) * q)
                - rot(u(th_c + sigma * phi), PI / 2.0) * (sigma * RG * (q + sigma));
            let t = rot(dk, -x).normalize();
            let (a1, a2) = (v1.dot(&t), v2.dot(&t));
            let s = (a1 * ck.v_t1 + a2 * ck.v_t2).signum();
            worst = worst.max((s * a1 - ck.v_t1).abs() / scale);
            worst = worst.max((s * a2 - ck.v_t2).abs() / scale);
            worst = worst.max((s * (a1 - a2) - ck.v_slide).abs() / scale);
            assert!((ck.cos_beta1 - ck.v_t1 / ck.v_k1).abs() < 1e-15);
        }
        eprintln!("e = {e}: contact kinematics vs finite differences, worst {worst:e} (relative)");
        assert!(worst < 1e-7, "e = {e}: contact kinematics off by {worst:e}");
    }
}

/// Sliding distance of gear 1's arch i by a fine trapezoid in the central angle θ (not α1):
/// ∫ (a/ρ2)·2r sin(ϕ/2) (dα1/dθ) dθ, ϕ = Nθ − 2πi, dα1/dθ = R(R + e cos θ)/ρ²,
/// ρ² = R² + e² + 2eR cos θ.
fn sliding_brute(p: &GearPair, i: usize, m: usize) -> f64 {
    let (e, a, n) = (p.c.e, p.a, p.n_arches as f64);
    let f = |th: f64| {
        let rho2 = R * R + e * e + 2.0 * e * R * th.cos();
        let r1 = rho2.sqrt();
        let phi = n * th - TAU * i as f64;
        a / (a - r1) * 2.0 * RG * (0.5 * phi).sin().abs() * R * (R + e * th.cos()) / rho2
    };
    let (t0, t1) = (TAU * i as f64 / n, TAU * (i + 1) as f64 / n);
    let h = (t1 - t0) / m as f64;
    let mut s = 0.5 * (f(t0) + f(t1));
    for k in 1..m {
        s += f(t0 + k as f64 * h);
    }
    s * h
}

#[test]
fn sliding_distance_per_flank_matches_closed_form_and_brute_force() {
    // e = 0: s = 8r²a/(R(a − R)) per engagement, on every arch.
    let p = pair(0.0);
    let w = flank_wear(&p, 3, 1, 1e-12);
    let want = 8.0 * RG * RG * p.a / (R * (p.a - R));
    for (i, s) in w.per_engagement.iter().enumerate() {
        assert!(
            (s.value - want).abs() < 1e-12 * want,
            "arch {i}: {} vs {want}",
            s.value
        );
        assert!(s.error < 1e-10 * want);
        assert!((w.gear1[i].0 - 3.0 * want).abs() < 1e-12 * want);
    }
    // e = 15 mm: every arch carries poles of µ, v_s stays finite; brute force in θ.
    let p = pair(15e-3);
    let sing = singularities(&p, 24, 1e-13).unwrap();
    let w = flank_wear(&p, 3, 1, 1e-12);
    for i in certified_pole_arches(&p) {
        assert!(
            sing.poles.iter().any(|q| q.arch == i),
            "arch {i} has no pole"
        );
    }
    for (i, s) in w.per_engagement.iter().enumerate() {
        let bf = sliding_brute(&p, i, 200_000);
        // Richardson on the trapezoid (error h², so (4T(h/2) − T(h))/3 is O(h⁴)): the
        // library's error bound must cover the difference to it, up to its own rounding.
        let bf2 = sliding_brute(&p, i, 400_000);
        let rich = (4.0 * bf2 - bf) / 3.0;
        if i == 14 {
            eprintln!(
                "arch 14: Simpson {} ± {:e} m, trapezoid {bf} m, Richardson {rich} m",
                s.value, s.error
            );
        }
        assert!(
            (s.value - rich).abs() <= s.error + 1e-13 * rich,
            "arch {i}: {} ± {:e} vs Richardson {rich}",
            s.value,
            s.error
        );
        assert!(
            (s.value - bf).abs() < 1e-9 * bf,
            "arch {i}: {} vs brute force {bf}",
            s.value
        );
        assert!(s.error < 1e-10 * bf, "arch {i}: error bound {}", s.error);
        // Gear 2's arch g meets gear 1's arch g mod N once per cycle (n2 = 1).
        for g in [i, i + p.n_arches, i + 2 * p.n_arches] {
            assert_eq!(w.gear2[g].0, s.value);
        }
    }
    // Symmetry about the line of centres: arch i and arch N − 1 − i slide alike.
    let n = p.n_arches;
    for i in 0..n {
        let (x, y) = (w.per_engagement[i].value, w.per_engagement[n - 1 - i].value);
        assert!((x - y).abs() < 1e-11 * x, "arch {i}");
    }
}

#[test]
fn involute_equivalent_matches_a_geometric_evaluation() {
    // m = 4r = 5 mm, z1 = 15, z2 = 45, α = 20°, standard addendum (the paper pair's
    // circular equivalent), and a pair without interference.
    for (z1, z2, alpha) in [(15.0, 45.0, 20f64), (30.0, 60.0, 25.0)] {
        let m = 5e-3;
        let al = alpha.to_radians();
        let inv = involute(m, z1, z2, al, 1.0);
        let (r1, r2) = (0.5 * m * z1, 0.5 * m * z2);
        let a = r1 + r2;
        let o2 = P2::new(a, 0.0);
        let (w1, w2) = (1.0, z1 / z2);
        // Line of action through P = (r1, 0), direction w, tangent to both base circles.
        let w = P2::new(al.sin(), al.cos());
        let pp = P2::new(r1, 0.0);
        let n1 = pp - w * pp.dot(&w);
        let x_of = |x: f64| n1 + w * x;
        let g = (o2 - n1).dot(&w);
        let (ra1, ra2) = (r1 + m, r2 + m);
        let xa = cwsynth::numeric::brent_root(|x| (x_of(x) - o2).norm() - ra2, -g, g, 1e-16)
            .unwrap()
            .x;
        let xe = cwsynth::numeric::brent_root(|x| x_of(x).norm() - ra1, 0.0, 2.0 * g, 1e-16)
            .unwrap()
            .x;
        let mu = |x: f64| {
            let k = x_of(x);
            let tau = P2::new(-w.y, w.x);
            let v1 = P2::new(-k.y, k.x) * w1;
            let d = k - o2;
            let v2 = P2::new(-d.y, d.x) * (-w2);
            let (t1, t2) = (v1.dot(&tau), v2.dot(&tau));
            ((t1 - t2) / t1, (t2 - t1) / t2)
        };
        let (m1a, m2a) = mu(xa);
        let (m1e, m2e) = mu(xe);
        assert!((inv.line_of_action_m - g).abs() < 1e-15);
        assert!(
            (inv.x_start_m - xa).abs() < 1e-14,
            "{} vs {xa}",
            inv.x_start_m
        );
        assert!((inv.x_end_m - xe).abs() < 1e-14);
        for (got, want) in [
            (inv.mu1_start, m1a),
            (inv.mu2_start, m2a),
            (inv.mu1_end, m1e),
            (inv.mu2_end, m2e),
        ] {
            assert!(
                (got - want).abs() < 1e-7 * want.abs().max(1.0),
                "z {z1}/{z2}: {got} vs {want}"
            );
        }
        let eps = (xe - xa) / (PI * m * al.cos());
        assert!((inv.contact_ratio - eps).abs() < 1e-10);
        assert!(!inv.interference);
    }
    // The circular cycloidal equivalent is the model at e = 0.
    let p = pair(0.0);
    let [(m1a, m2a), (m1d, m2d)] = circular_cycloidal_mu(R, RG, 3.0);
    for (i, (m1, m2)) in [(0, (m1a, m2a)), (1, (m1d, m2d))] {
        let x = 0.5 * (p.arch_start(i) + p.arch_start(i + 1));
        let ct = p.contact_on(x, i);
        assert!((ct.mu1.unwrap() - m1).abs() < 1e-13);
        assert!((ct.mu2.unwrap() - m2).abs() < 1e-13);
    }
}

#[test]
fn no_generating_radius_removes_the_poles_of_an_eccentric_pair() {
    // The certificate (a sign change of (K − O_j)·d between the cusps of an arch) against a
    // dense scan of v_t1 and v_t2 on every arch, for several r and e; e = 0 has no poles.
    for n_arch in [10usize, 20, 30, 60] {
        let rg = R / n_arch as f64;
        for e in [0.0, 5e-3, 15e-3, 30e-3] {
            let p = pair_with(e, rg, 3, 1);
            let cert = certified_pole_arches(&p);
            let mut with_both = Vec::new();
            for i in 0..p.n_arches {
                let (a0, a1) = (p.arch_start(i), p.arch_start(i + 1));
                let m = 4000;
                let xs: Vec<f64> = (1..m)
                    .map(|k| a0 + (a1 - a0) * k as f64 / m as f64)
                    .collect();
                let changes = |f: &dyn Fn(f64) -> f64| {
                    xs.windows(2).filter(|w| f(w[0]) * f(w[1]) < 0.0).count()
                };
                let c1 = changes(&|x| p.contact_on(x, i).vt1);
                let c2 = changes(&|x| p.contact_on(x, i).vt2);
                if c1 > 0 && c2 > 0 {
                    with_both.push(i);
                }
            }
            if e == 0.0 {
                assert!(cert.is_empty() && with_both.is_empty());
            } else {
                assert_eq!(cert.len(), p.n_arches - 4, "N {n_arch} e {e}");
                for i in &cert {
                    assert!(with_both.contains(i), "N {n_arch} e {e}: arch {i}");
                }
            }
        }
    }
}

#[test]
fn tooth_options_are_checked_and_off_by_default() {
    let base = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/gear-tooth-profiles.toml"),
    )
    .unwrap();
    // The options need tooth_profiles = true.
    let off = base.replace("tooth_profiles = true", "tooth_profiles = false");
    common::assert_names(
        &off,
        "model.profile_points_per_arch",
        "profile_points_per_arch",
        "only with model.tooth_profiles = true",
    );
    let bad = base.replace("\"20 deg\"", "\"50 deg\"");
    common::assert_names(
        &bad,
        "model.involute_pressure_angle",
        "involute_pressure_angle",
        "(0, 45°)",
    );
    // Off: the result has none of the tooth-level keys, tables or plots.
    let plain: String = base
        .lines()
        .filter(|l| {
            ![
                "tooth_profiles",
                "profile_points_per_arch",
                "involute_pressure_angle",
            ]
            .iter()
            .any(|k| l.starts_with(k))
        })
        .collect::<Vec<_>>()
        .join("\n");
    let r = cwsynth::families::solve_scene(
        &cwsynth::families::parse_str(&plain, std::path::Path::new("plain.toml")).unwrap(),
    );
    assert!(!r.derived.contains_key("sliding_distance_max_gear1_m"));
    assert!(!r.extra.contains_key("flank_wear"));
    let mut r = r;
    r.complete();
    assert!(!r.tables.is_empty());
    assert!(r.tables.iter().all(|t| t.suffix != "tooth-profiles"));
    let on = cwsynth::families::solve_scene(
        &cwsynth::families::parse_str(&base, std::path::Path::new("on.toml")).unwrap(),
    );
    assert!(on.derived.contains_key("sliding_distance_max_gear1_m"));
    // Everything else is the same numbers.
    for (k, v) in &r.derived {
        assert_eq!(on.derived.get(k), Some(v), "derived.{k}");
    }
    assert_eq!(r.objectives, on.objectives);
}
