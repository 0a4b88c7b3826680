//! `geom::plate`: the cap function and the ring and lens plates that realise a counterweight's
//! (m, u, I), each checked against a reference computed here another way:
//!
//! * the cap's area and first moment against Gauss–Legendre quadrature of the segment in the
//!   angle θ of x = R cos θ (chord half-length R sin θ), and its area as a function of its
//!   half-angle in double-double (the round trip), from 1e-10 of the disc to 1 − 1e-10;
//! * the cap's slope against a central difference of S(A), and S's concavity (tangent cuts);
//! * a ring built from its radii against its closed-form (m, u, I);
//! * lenses from `realise` against the requested area and centroid, inside the envelope and
//!   within the necessary inertia bounds; a lens's `moments()` against a grid count and against
//!   quadrature of its two arcs' cross-sections.

use crate::common::{dd_sin_cos, Dd, Lcg};
use cwsynth::geom::plate::{cap, realise, ring, PlateShape};
use cwsynth::geom::{dir, P2};
use std::f64::consts::{PI, TAU};

/// Envelope radius (m) and areal density (kg/m², 5 mm of steel) of the fixtures.
const R: f64 = 0.3;
const SIGMA: f64 = 7850.0 * 0.005;

/// The n-point Gauss–Legendre nodes and weights on [−1, 1] (Newton on Pₙ from the
/// Chebyshev-like guess cos(π(i + 3/4)/(n + 1/2))).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / dp;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// ∫ₐᵇ f by 20-point Gauss–Legendre on 16 equal panels (f analytic on [a, b]).
fn quad(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let nodes = gauss_legendre(20);
    let panels = 16;
    let h = (b - a) / panels as f64;
    (0..panels)
        .map(|p| {
            let mid = a + (p as f64 + 0.5) * h;
            nodes
                .iter()
                .map(|&(x, w)| w * f(mid + 0.5 * h * x))
                .sum::<f64>()
                * 0.5
                * h
        })
        .sum()
}

/// The segment beyond x = R cos α (α ≤ π/2) by quadrature in θ: A = ∫₀^α 2R² sin²θ dθ,
/// S = ∫₀^α 2R³ cos θ sin²θ dθ. Past π/2 the complement (θ ∈ [α, π]) is integrated, whose
/// S is the segment's with the sign reversed and whose A is πR² less the segment's.
fn segment_by_quadrature(alpha: f64) -> (f64, f64) {
    let area = |t: f64| 2.0 * R * R * t.sin().powi(2);
    let first = |t: f64| 2.0 * R.powi(3) * t.cos() * t.sin().powi(2);
    if alpha <= PI / 2.0 {
        (quad(&area, 0.0, alpha), quad(&first, 0.0, alpha))
    } else {
        (
            PI * R * R - quad(&area, alpha, PI),
            -quad(&first, alpha, PI),
        )
    }
}

#[test]
fn cap_matches_quadrature_and_round_trips() {
    let full = PI * R * R;
    for frac in [
        1e-10,
        1e-6,
        0.01,
        0.3,
        0.5,
        0.7,
        0.99,
        1.0 - 1e-6,
        1.0 - 1e-10,
    ] {
        let a = frac * full;
        let c = cap(a, R);
        assert_eq!(c.area, a);
        let (qa, qs) = segment_by_quadrature(c.half_angle);
        // A double-double A(α) of the returned α: the round trip.
        let al = Dd::from(c.half_angle);
        let (s, co) = dd_sin_cos(al);
        let dd_area = f64::from((al - s * co) * (R * R));
        assert!(
            ((dd_area - a) / a).abs() <= 1e-13,
            "frac {frac}: A(α) {dd_area} vs {a}"
        );
        assert!(((qa - a) / a).abs() <= 1e-13, "frac {frac}: quad A {qa}");
        // sin³ at α rounded near π: 3 ε cot-conditioning on top of the quadrature's 1e-13.
        let tol_s = 1e-13 + 3.0 * f64::EPSILON * c.half_angle / c.half_angle.sin();
        assert!(
            ((qs - c.first_moment) / qs).abs() <= tol_s,
            "frac {frac}: S {} vs quad {qs}",
            c.first_moment
        );
        assert!((c.slope - R * c.half_angle.cos()).abs() <= 1e-15 * R);
    }
    // Clamped: nothing, and the whole disc.
    let none = cap(-1.0, R);
    assert_eq!(
        (none.half_angle, none.area, none.first_moment),
        (0.0, 0.0, 0.0)
    );
    let all = cap(2.0 * full, R);
    assert_eq!((all.half_angle, all.area), (PI, full));
    assert!(all.first_moment.abs() <= 1e-30 && (all.slope + R).abs() <= 1e-15);
}

#[test]
fn cap_slope_is_the_derivative_of_its_first_moment() {
    let full = PI * R * R;
    let step = 1e-5 * full;
    for k in 1..20 {
        let a = k as f64 / 20.0 * full;
        let fd = (cap(a + step, R).first_moment - cap(a - step, R).first_moment) / (2.0 * step);
        let h = cap(a, R).slope;
        assert!((fd - h).abs() <= 1e-8 * R, "A {a}: slope {h} vs {fd}");
    }
}

#[test]
fn cap_first_moment_is_concave() {
    let full = PI * R * R;
    let mut g = Lcg(3);
    for _ in 0..2000 {
        let (a, a0) = (g.range(0.0, full), g.range(0.0, full));
        let c0 = cap(a0, R);
        let cut = c0.first_moment + c0.slope * (a - a0);
        assert!(
            cap(a, R).first_moment <= cut + 1e-15 * R.powi(3),
            "A {a}, A0 {a0}"
        );
    }
}

/// (m, u, I) of the ring of centre c, radii a ≤ b: m = σπ(b² − a²), u = m c,
/// I = m(|c|² + (a² + b²)/2).
fn ring_properties(c: P2, a: f64, b: f64) -> (f64, P2, f64) {
    let m = SIGMA * PI * (b * b - a * a);
    (m, c * m, m * (c.norm_squared() + 0.5 * (a * a + b * b)))
}

#[test]
fn ring_realises_its_request_exactly() {
    let mut g = Lcg(11);
    for _ in 0..200 {
        let b = g.range(0.01, 0.9) * R;
        let a = g.range(0.0, 0.99) * b;
        let c = dir(g.range(0.0, TAU)) * g.range(0.0, 1.0) * (R - b);
        let (m, u, i) = ring_properties(c, a, b);
        let Some(shape) = ring(m, u, i, SIGMA, R) else {
            panic!("ring {c:?} {a} {b} refused");
        };
        let PlateShape::Ring {
            centre,
            inner,
            outer,
        } = shape
        else {
            panic!("not a ring");
        };
        assert!((centre - c).norm() <= 1e-12 * R && (outer - b).abs() <= 1e-12 * R);
        // a = √(a²) with a² the difference of two ~b² terms: δa ≤ min(δ/(2a), √δ), δ = 8ε b².
        let slack = 8.0 * f64::EPSILON * b * b;
        let tol_a = 1e-12 * R + slack.sqrt().min(slack / (2.0 * a));
        assert!((inner - a).abs() <= tol_a, "inner {inner} vs {a}");
        let mo = shape.moments() * SIGMA;
        assert!(((mo.area - m) / m).abs() <= 1e-12, "m {} vs {m}", mo.area);
        assert!((mo.first - u).norm() <= 1e-12 * m * R);
        assert!(
            ((mo.second - i) / i).abs() <= 1e-12,
            "I {} vs {i}",
            mo.second
        );
    }
}

#[test]
fn ring_refuses_what_no_ring_can_be() {
    let c = P2::new(0.1, -0.05);
    let (m, u, i) = ring_properties(c, 0.0, 0.12);
    // The disc itself (its inner radius the square root of a rounding error), and a shade
    // below its I_c.
    let disc = ring(m, u, i, SIGMA, R);
    assert!(matches!(disc, Some(PlateShape::Ring { inner, .. }) if inner <= 1e-7 * 0.12));
    assert_eq!(ring(m, u, i - 1e-9 * i, SIGMA, R), None);
    // A ring that would cross the envelope, and one just inside it.
    let far = c * ((R - 0.12) / c.norm());
    let (m, u, i) = ring_properties(far, 0.05, 0.12);
    assert!(ring(m, u, i, SIGMA, R).is_some());
    let (m, u, i) = ring_properties(far * 1.0001, 0.05, 0.12);
    assert_eq!(ring(m, u, i, SIGMA, R), None);
    assert_eq!(ring(0.0, u, i, SIGMA, R), None);
    assert_eq!(ring(-m, u, i, SIGMA, R), None);
    assert_eq!(ring(m, u, f64::NAN, SIGMA, R), None);
}

/// Asserts that points along every edge of the shape's loops (33 per edge, ends included) lie
/// in the envelope: |p| ≤ R (1 + 1e-12), plus the rounding of centre + radius·(cos, sin) for a
/// far disc's arc, 4ε(|c| + ρ).
fn assert_inside(shape: &PlateShape) {
    for edge in shape.loops().into_iter().flatten() {
        let arc = edge.arc.expect("plates are bounded by arcs");
        let slack = 1e-12 * R + 4.0 * f64::EPSILON * (arc.centre.norm() + arc.radius);
        for k in 0..=32 {
            let t = arc.start + arc.sweep * k as f64 / 32.0;
            let p = arc.centre + dir(t) * arc.radius;
            assert!(
                p.norm() <= R + slack,
                "outside by {:e}: {shape:?}",
                p.norm() - R
            );
        }
    }
}

/// The necessary conditions on I: |u|²/m + m²/(2πσ) ≤ I ≤ R²m − m²/(2πσ) (relative 1e-12).
fn assert_inertia_bounds(m: f64, u: P2, i: f64) {
    let disc = m * m / (TAU * SIGMA);
    let (lo, hi) = (u.norm_squared() / m + disc, R * R * m - disc);
    let tol = 1e-12 * R * R * m;
    assert!(i >= lo - tol && i <= hi + tol, "I {i} outside [{lo}, {hi}]");
}

#[test]
fn realise_lens_meets_area_and_centroid() {
    let mut g = Lcg(5);
    for frac in [0.02, 0.3, 0.7, 0.95] {
        let area = frac * PI * R * R;
        let m = SIGMA * area;
        let d0 = R - (area / PI).sqrt();
        let dcap = cap(area, R).first_moment / area;
        for d in [d0 + 1e-6 * R, 0.5 * (d0 + dcap), dcap * (1.0 - 1e-6)] {
            let e = dir(g.range(0.0, TAU));
            let u = e * (m * d);
            let got = realise(m, u, 0.0, SIGMA, R);
            assert!(
                matches!(got.shape, PlateShape::Lens { .. }),
                "{:?}",
                got.shape
            );
            assert!(((got.mass - m) / m).abs() <= 1e-10, "frac {frac} d {d}: m");
            assert!(
                (got.first_moment - u).norm() <= 1e-10 * m * d,
                "frac {frac} d {d}: centroid {} vs {d}",
                got.first_moment.norm() / got.mass
            );
            assert_inside(&got.shape);
            assert_inertia_bounds(got.mass, got.first_moment, got.inertia);
        }
    }
}

#[test]
fn realise_random_plates_stay_within_the_bounds() {
    let mut g = Lcg(7);
    let full = SIGMA * PI * R * R;
    let (mut rings, mut lenses) = (0, 0);
    for _ in 0..60 {
        let m = g.log(1e-4, 1.0) * full;
        let dcap = cap(m / SIGMA, R).first_moment * SIGMA / m;
        let u = dir(g.range(0.0, TAU)) * (m * dcap * g.range(0.0, 1.2));
        let i = g.range(0.0, 1.5) * R * R * m;
        let got = realise(m, u, i, SIGMA, R);
        assert!(
            ((got.mass - m) / m).abs() <= 1e-10,
            "m {m} u {u:?} I {i}: {got:?}"
        );
        assert_inside(&got.shape);
        assert_inertia_bounds(got.mass, got.first_moment, got.inertia);
        // A request a ring can meet is met (to rounding).
        if ring(m, u, i, SIGMA, R).is_some() {
            assert!(matches!(got.shape, PlateShape::Ring { .. }));
            assert!((got.first_moment - u).norm() <= 1e-12 * m * R);
            assert!(((got.inertia - i) / i).abs() <= 1e-12);
            rings += 1;
        }
        lenses += matches!(got.shape, PlateShape::Lens { .. }) as usize;
    }
    assert!(
        rings >= 5 && lenses >= 5,
        "{rings} exact rings, {lenses} lenses"
    );
}

#[test]
fn realise_clamps_to_what_a_plate_can_be() {
    let area = 0.3 * PI * R * R;
    let m = SIGMA * area;
    let dcap = cap(area, R).first_moment / area;
    // Beyond the cap: the cap's distance, in u's direction.
    let e = dir(1.0);
    let got = realise(m, e * (2.0 * m * dcap), 0.0, SIGMA, R);
    let d = got.first_moment.norm() / got.mass;
    assert!(((d - dcap) / dcap).abs() <= 1e-9, "d {d} vs cap {dcap}");
    assert!((got.first_moment / got.first_moment.norm() - e).norm() <= 1e-12);
    assert!(((got.mass - m) / m).abs() <= 1e-10);
    assert!(d < dcap);
    // More than the envelope holds: the full disc.
    let full = SIGMA * PI * R * R;
    let got = realise(2.0 * full, P2::new(1.0, 2.0), 0.0, SIGMA, R);
    assert!(((got.mass - full) / full).abs() <= 1e-12);
    assert!(got.first_moment.norm() <= 1e-12 * full * R);
    assert!(((got.inertia - full * R * R / 2.0) / got.inertia).abs() <= 1e-12);
    // I out of the ring's reach: the disc, or the ring touching the envelope.
    let c = P2::new(0.05, 0.0);
    let (lo, hi) = (
        realise(m, c * m, 0.0, SIGMA, R),
        realise(m, c * m, 1e9, SIGMA, R),
    );
    let ring_radii = |s: PlateShape| match s {
        PlateShape::Ring { inner, outer, .. } => (inner, outer),
        _ => panic!("not a ring: {s:?}"),
    };
    assert_eq!(ring_radii(lo.shape), (0.0, (area / PI).sqrt()));
    let (a, b) = ring_radii(hi.shape);
    assert!(
        (b - (R - 0.05)).abs() <= 1e-15 && ((PI * (b * b - a * a) - area) / area).abs() <= 1e-12
    );
    // Nothing.
    let none = realise(0.0, P2::new(1.0, 0.0), 1.0, SIGMA, R);
    assert_eq!(
        (none.mass, none.first_moment, none.inertia),
        (0.0, P2::zeros(), 0.0)
    );
}

/// (A, S, J) of the region {|p| ≤ R, |p − c| ≤ ρ} by the midpoint rule on an n × n grid.
fn lens_by_grid(c: P2, rho: f64, n: usize) -> (f64, P2, f64) {
    let h = 2.0 * R / n as f64;
    let (mut a, mut s, mut j) = (0.0, P2::zeros(), 0.0);
    for ix in 0..n {
        for iy in 0..n {
            let p = P2::new(-R + (ix as f64 + 0.5) * h, -R + (iy as f64 + 0.5) * h);
            if p.norm() <= R && (p - c).norm() <= rho {
                a += h * h;
                s += p * (h * h);
                j += p.norm_squared() * h * h;
            }
        }
    }
    (a, s, j)
}

/// (A, S·e, J) of the lens of the far disc (centre D e, radius ρ, D > 0) by quadrature of its
/// cross-sections along e: the envelope's part beyond the chord x (t = R cos θ, half-width
/// R sin θ, θ ∈ [0, β]) and the disc's part before it (t = q + 2ρ sin²(φ/2) with q = D − ρ,
/// half-width ρ sin φ, φ ∈ [0, γ]); a section of half-width w at t contributes
/// 2w (area), 2wt (first moment) and 2wt² + ⅔w³ (polar moment).
fn lens_by_quadrature(d: f64, rho: f64) -> (f64, f64, f64) {
    let x = (R * R + (d - rho) * (d + rho)) / (2.0 * d);
    let y = ((R - x) * (R + x)).sqrt();
    let (beta, gamma) = (y.atan2(x), y.atan2(d - x));
    let q = d - rho;
    let env = |th: f64| (R * th.cos(), R * th.sin(), R * th.sin());
    let disc = |ph: f64| {
        let t = q + 2.0 * rho * (0.5 * ph).sin().powi(2);
        (t, rho * ph.sin(), rho * ph.sin())
    };
    let mut out = (0.0, 0.0, 0.0);
    for (f, top) in [
        (&env as &dyn Fn(f64) -> (f64, f64, f64), beta),
        (&disc, gamma),
    ] {
        let part = |k: usize| {
            move |v: f64| {
                let (t, w, dt) = f(v);
                [
                    2.0 * w,
                    2.0 * w * t,
                    2.0 * w * t * t + 2.0 / 3.0 * w.powi(3),
                ][k] * dt
            }
        };
        out.0 += quad(&part(0), 0.0, top);
        out.1 += quad(&part(1), 0.0, top);
        out.2 += quad(&part(2), 0.0, top);
    }
    out
}

#[test]
fn lens_moments_match_a_grid_and_quadrature() {
    // A minor second arc (its centre beyond the chord) and a major one (before it).
    for (c, rho) in [(P2::new(0.25, 0.1), 0.2), (P2::new(0.1, -0.15), 0.15)] {
        let shape = PlateShape::Lens {
            envelope: R,
            disc_centre: c,
            disc_radius: rho,
        };
        let mo = shape.moments();
        let (a, s, j) = lens_by_grid(c, rho, 1500);
        assert!(((mo.area - a) / a).abs() <= 1e-3, "A {} vs {a}", mo.area);
        assert!(
            (mo.first - s).norm() <= 1e-3 * s.norm(),
            "S {:?} vs {s:?}",
            mo.first
        );
        assert!(
            ((mo.second - j) / j).abs() <= 1e-3,
            "J {} vs {j}",
            mo.second
        );
        let (qa, qs, qj) = lens_by_quadrature(c.norm(), rho);
        let e = c / c.norm();
        assert!(
            ((mo.area - qa) / qa).abs() <= 1e-13,
            "A {} vs {qa}",
            mo.area
        );
        assert!((mo.first - e * qs).norm() <= 1e-13 * qs.abs(), "S vs {qs}");
        assert!(
            ((mo.second - qj) / qj).abs() <= 1e-13,
            "J {} vs {qj}",
            mo.second
        );
    }
}

#[test]
fn lens_moments_of_flat_arcs() {
    // Far discs whose arcs bulge s = 1e-2 … 1e-5 R from a chord at 0.1 R (ρ up to 5e4 R):
    // outline's arc integrals, taken about the far centre, against cross-section quadrature
    // (measured: A, S to 4e-16; J 3e-14, 3e-13, 3e-12, 4e-12).
    let x = 0.1 * R;
    let y2 = (R - x) * (R + x);
    for s in [1e-2 * R, 1e-3 * R, 1e-4 * R, 1e-5 * R] {
        let rho = (y2 + s * s) / (2.0 * s);
        let d = x + (y2 - s * s) / (2.0 * s);
        let mo = PlateShape::Lens {
            envelope: R,
            disc_centre: P2::new(d, 0.0),
            disc_radius: rho,
        }
        .moments();
        let (qa, qs, qj) = lens_by_quadrature(d, rho);
        // J = J_c + 2c·S_c + A|c|² about the far centre cancels by ~ρ/R: ε R/s relative.
        assert!(
            ((mo.area - qa) / qa).abs() <= 1e-14,
            "s {s}: A {} vs {qa}",
            mo.area
        );
        assert!(
            ((mo.first.x - qs) / qs).abs() <= 1e-14,
            "s {s}: S {:?} vs {qs}",
            mo.first
        );
        let tol_j = 1e-14 + 10.0 * f64::EPSILON * R / s;
        assert!(
            ((mo.second - qj) / qj).abs() <= tol_j,
            "s {s}: J {} vs {qj}",
            mo.second
        );
    }
}
