//! Tests of the eccentric gear's contact stress and load-weighted wear (issue 38) against
//! independent references: the closed-form radii of curvature of epi- and hypocycloids
//! (gear 1 for any e, both gears for e = 0), circles through three points of gear 2's
//! flank placed by the drawing's own α2 map (e ≠ 0), the closed-form Hertz pressure and
//! Archard integral of the circular pair, and a dense sign scan for the driving fraction.
//! The error bars are checked to cover the reference, near the cusps as well.

use cwsynth::families::gear::model::*;
use cwsynth::families::gear::stress::*;
use cwsynth::geom::P2;
use std::f64::consts::{PI, TAU};

use crate::common::Lcg;

const R: f64 = 37.5e-3;
const RG: f64 = 1.25e-3;

fn pair(e: f64) -> GearPair {
    let c = EccentricCircle::new(R, e).unwrap();
    let cl = closing_center_distance(&c, 3, 1).unwrap();
    GearPair::new(c, RG, cl.a, 15.0).unwrap()
}

const LOAD: ToothLoad = ToothLoad {
    torque: 20.0,
    face_width: 20e-3,
    youngs_modulus: 210e9,
    poisson_ratio: 0.3,
};

/// Radius of curvature of the cycloid arch traced by a circle of radius r rolled ϕ on a
/// circle of radius Rb, outside (epicycloid, `outside`) or inside (hypocycloid):
/// 4r(Rb ± r)/(Rb ± 2r)·sin(ϕ/2).
fn cycloid_radius(rb: f64, outside: bool, phi: f64) -> f64 {
    let s = if outside { 1.0 } else { -1.0 };
    4.0 * RG * (rb + s * RG) / (rb + 2.0 * s * RG) * (0.5 * phi).sin()
}

/// α1 on arch i at rolling angle ϕ (the arch's θ = (2πi + ϕ)/N mapped back).
fn alpha(p: &GearPair, arch: usize, phi: f64) -> f64 {
    p.c.alpha_of_theta((TAU * arch as f64 + phi) / p.n_arches as f64)
}

#[test]
fn gear1_flank_curvature_is_the_closed_form_cycloids_for_any_e_with_covering_errors() {
    let mut rng = Lcg(3801);
    let mut worst: f64 = 0.0;
    for k in 0..400 {
        let e = if k % 4 == 0 {
            0.0
        } else {
            rng.range(0.0, 0.9 * R)
        };
        let p = pair(e);
        let arch = (rng.next() * p.n_arches as f64) as usize;
        // Random, and near the cusps (ϕ → 0, 2π: the radius of curvature → 0).
        let phi = match k % 3 {
            0 => rng.log(1e-4, 0.1),
            1 => TAU - rng.log(1e-4, 0.1),
            _ => rng.range(0.1, TAU - 0.1),
        };
        let a = alpha(&p, arch, phi);
        let phi_model = p.contact_on(a, arch).phi;
        let sigma_plus = arch % 2 == 0;
        // Gear 1's addendum (σ = +1) is convex towards gear 2, its dedendum concave.
        let want = if sigma_plus { 1.0 } else { -1.0 } / cycloid_radius(R, sigma_plus, phi_model);
        let (c, ce) = flank_curvatures(&p, a, arch);
        let dev = (c[0] - want).abs();
        worst = worst.max(dev / want.abs());
        assert!(
            dev <= ce[0],
            "e = {e}, arch {arch}, ϕ = {phi_model}: c1 = {} vs closed form {want}, error bar {} (deviation {dev:e})",
            c[0],
            ce[0]
        );
        assert!(ce[0] < 1e-6 * want.abs(), "error bar {} too loose", ce[0]);
    }
    eprintln!("gear 1 flank curvature vs closed form: worst relative deviation {worst:e}");
}

#[test]
fn circular_pair_gear2_curvature_hertz_pressure_and_archard_are_the_closed_forms() {
    let p = pair(0.0);
    let r2 = p.a - R;
    let n = p.n_arches as f64;
    let es = LOAD.contact_modulus();
    for arch in [0usize, 1, 6, 17] {
        let plus = arch % 2 == 0;
        for phi in [0.01, 0.3, 1.0, 2.0, 3.0, 3.1, 3.3, 4.5, 6.2] {
            let a = alpha(&p, arch, phi);
            let (c, ce) = flank_curvatures(&p, a, arch);
            // Gear 2's flank is the other cycloid: a hypocycloid (concave) against gear 1's
            // addendum, an epicycloid (convex) against its dedendum.
            let want2 = if plus { -1.0 } else { 1.0 } / cycloid_radius(r2, !plus, phi);
            assert!(
                (c[1] - want2).abs() <= ce[1] && ce[1] < 1e-6 * want2.abs(),
                "arch {arch}, ϕ {phi}: c2 {} vs {want2} ± {}",
                c[1],
                ce[1]
            );
            let h = hertz_on(&p, a, arch, &LOAD);
            // Loaded where σ cos(ϕ/2) > 0: F = T1/(R|cos(ϕ/2)|).
            let cosh = (0.5 * phi).cos();
            let sigma = if plus { 1.0 } else { -1.0 };
            if sigma * cosh > 0.0 {
                let f = LOAD.torque / (R * cosh.abs());
                let kr = (if plus {
                    1.0 / (R + RG) + 1.0 / (r2 - RG)
                } else {
                    1.0 / (R - RG) + 1.0 / (r2 + RG)
                }) / (4.0 * (0.5 * phi).sin());
                let p0 = (f * es * kr / (PI * LOAD.face_width)).sqrt();
                assert!((h.force_n - f).abs() < 1e-12 * f, "F {} vs {f}", h.force_n);
                assert!(
                    (h.p0_pa - p0).abs() <= h.p0_error_pa && h.p0_error_pa < 1e-6 * p0,
                    "arch {arch}, ϕ {phi}: p0 {} vs {p0} ± {}",
                    h.p0_pa,
                    h.p0_error_pa
                );
                let aw = (4.0 * f / (PI * LOAD.face_width * es * kr)).sqrt();
                assert!((h.half_width_m - aw).abs() < 1e-6 * aw);
            } else {
                assert_eq!(
                    h.force_n, 0.0,
                    "arch {arch}, ϕ {phi}: the back flank carries no load"
                );
                assert_eq!(h.p0_pa, 0.0);
            }
        }
    }
    // The Archard integral per engagement: F|v_s|/ω1 = T1/(R cos(ϕ/2))·(1 + R/R2)·2r sin(ϕ/2)
    // and dα1 = dϕ/N, so W = (2rT1(1 + R/R2)/(NR))·2·ln(cos(ϕa/2)/cos(ϕb/2)) on the
    // addendum's window [Nw, π − Nw] (mirrored on the dedendum).
    let w = 0.004;
    let fs = flank_stress(&p, 3, 1, &LOAD, w).unwrap();
    let (pa, pb) = (n * w, PI - n * w);
    let want = 2.0 * RG * LOAD.torque * (1.0 + R / r2) / (n * R)
        * 2.0
        * ((0.5 * pa).cos() / (0.5 * pb).cos()).ln();
    for s in &fs.arches {
        let dev = (s.archard.value - want).abs();
        assert!(
            dev <= s.archard.error && s.archard.error < 1e-9 * want,
            "arch {}: W {} vs {want} ± {}",
            s.arch,
            s.archard.value,
            s.archard.error
        );
    }
    assert!((fs.driving_fraction.0 - 0.5).abs() <= fs.driving_fraction.1.max(1e-14));
    // Gear 2's arches each meet one gear-1 arch per cycle: the same W.
    assert_eq!(fs.gear2.len(), 3 * p.n_arches);
    assert!(fs.gear2.iter().all(|g| (g.0 - want).abs() < 1e-9 * want));
    assert!(fs
        .gear1
        .iter()
        .all(|g| (g.0 - 3.0 * want).abs() < 1e-9 * want));
}

/// Signed curvature of the circle through three points (1/circumradius, positive when
/// a → b → c turns left).
fn three_point_curvature(a: P2, b: P2, c: P2) -> f64 {
    let (u, v) = (b - a, c - b);
    2.0 * (u.x * v.y - u.y * v.x) / (u.norm() * v.norm() * (c - a).norm())
}

#[test]
fn eccentric_gear2_curvature_matches_circles_through_its_drawn_flank() {
    let mut rng = Lcg(3802);
    let mut worst: f64 = 0.0;
    for k in 0..60 {
        let e = rng.range(1e-3, 0.6 * R);
        let p = pair(e);
        let map = Alpha2Map::new(&p.c, p.a);
        let arch = (rng.next() * p.n_arches as f64) as usize;
        let phi = rng.range(0.2, TAU - 0.2);
        let a = alpha(&p, arch, phi);
        let o2 = P2::new(p.a, 0.0);
        // Gear 2's flank point meshing at α1, in gear 2's frame: R(−α2)(K − O2).
        let pt = |x: f64| {
            let w = p.contact_on(x, arch).k - o2;
            let (s, c) = (-map.alpha2(x)).sin_cos();
            P2::new(c * w.x - s * w.y, s * w.x + c * w.y)
        };
        // Richardson on the three-point circle (error O(δ²)).
        let fit = |d: f64| three_point_curvature(pt(a - d), pt(a), pt(a + d));
        let d = 2e-4;
        let kappa = (4.0 * fit(0.5 * d) - fit(d)).abs() / 3.0;
        let (c, _) = flank_curvatures(&p, a, arch);
        let rel = (c[1].abs() - kappa).abs() / kappa;
        worst = worst.max(rel);
        assert!(
            rel < 1e-6,
            "case {k}: e = {e}, arch {arch}, ϕ = {phi}: |c2| = {} vs three-point circles {kappa} ({rel:e})",
            c[1].abs()
        );
        // The relative curvature of conjugate flanks is positive (they do not cut).
        assert!(c[0] + c[1] > 0.0, "case {k}: 1/R* = {}", c[0] + c[1]);
    }
    eprintln!("gear 2 flank curvature vs three-point circles (e ≠ 0): worst relative {worst:e}");
}

#[test]
fn driving_fraction_matches_a_dense_sign_scan() {
    for e in [0.0, 5e-3, 15e-3, 25e-3] {
        let p = pair(e);
        let fs = flank_stress(&p, 3, 1, &LOAD, 0.004).unwrap();
        let m = 400_000;
        let loaded = (0..m)
            .filter(|k| {
                let a = TAU * (*k as f64 + 0.5) / m as f64;
                arm(&p, a, p.contact(a).arch) > 0.0
            })
            .count();
        let scan = loaded as f64 / m as f64;
        eprintln!(
            "e = {e}: driving fraction {} ± {:e}, scan {scan}",
            fs.driving_fraction.0, fs.driving_fraction.1
        );
        assert!((fs.driving_fraction.0 - scan).abs() < 2.0 * p.n_arches as f64 / m as f64);
        // Each stretch starts or ends at a cusp; the peak is at a window end, the least
        // stress inside.
        for s in &fs.arches {
            let (w0, w1) = s.window.unwrap();
            let pk = s.peak.unwrap();
            assert!(pk.alpha1 == w0 || pk.alpha1 == w1, "arch {}", s.arch);
            let l = s.least.unwrap();
            assert!(l.alpha1 > w0 && l.alpha1 < w1 && l.p0_pa < pk.p0_pa);
            // A brute-force scan of the window finds nothing above the peak or below the least.
            for j in 0..=200 {
                let x = w0 + (w1 - w0) * j as f64 / 200.0;
                let v = hertz_on(&p, x, s.arch, &LOAD).p0_pa;
                assert!(v <= pk.p0_pa + pk.error_pa && v >= l.p0_pa - l.error_pa - 1e-9 * l.p0_pa);
            }
        }
    }
}
