//! `geom` (`src/geom.rs`): circle–circle and link–slider intersections, the circumcentre,
//! the 2-D helpers and the smallest enclosing disc against brute force.
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

use cwsynth::geom::{
    circle_circle, circumcentre, cmul, cross, enclosing_disc, link_slider, perp, solve_columns,
    Disc, Side, P2,
};

#[test]
fn three_four_five_circles() {
    // Circles of radius 5 about (0,0) and 5 about (6,0) meet at (3, ±4).
    let p = circle_circle(P2::zeros(), 5.0, P2::new(6.0, 0.0), 5.0, Side::Left).unwrap();
    assert!((p - P2::new(3.0, 4.0)).norm() < 1e-15);
    let q = circle_circle(P2::zeros(), 5.0, P2::new(6.0, 0.0), 5.0, Side::Right).unwrap();
    assert!((q - P2::new(3.0, -4.0)).norm() < 1e-15);
}

#[test]
fn near_tangent_circles_keep_their_digits() {
    // Two unit circles at distance 2 − δ: the half chord is sqrt(δ − δ²/4) exactly.
    // δ is taken from the representable distance (2 − d is exact by Sterbenz's lemma).
    let d = 2.0 - 1e-12;
    let delta = 2.0 - d;
    let p = circle_circle(P2::zeros(), 1.0, P2::new(d, 0.0), 1.0, Side::Left).unwrap();
    let exact = (delta - delta * delta / 4.0).sqrt();
    assert!((p.y - exact).abs() < 1e-12 * exact, "{} vs {}", p.y, exact);
    assert!(circle_circle(P2::zeros(), 1.0, P2::new(2.0 + 1e-9, 0.0), 1.0, Side::Left).is_none());
    assert!(circle_circle(P2::zeros(), 1.0, P2::zeros(), 1.0, Side::Left).is_none());
}

#[test]
fn perp_cmul_and_cramer() {
    let (a, b) = (P2::new(2.0, 1.0), P2::new(-1.0, 3.0));
    assert_eq!(cross(a, b), perp(a).dot(&b));
    let e = P2::new(0.6, 0.8);
    assert!((cmul(e, P2::new(1.0, 0.0)) - e).norm() < 1e-16);
    assert!((cmul(e, P2::new(0.0, 1.0)) - perp(e)).norm() < 1e-16);
    let (x, y) = solve_columns(a, b, 3.0 * a - 2.0 * b).unwrap();
    assert!((x - 3.0).abs() < 1e-15 && (y + 2.0).abs() < 1e-15);
    assert!(solve_columns(a, 2.0 * a, b).is_none());
}

#[test]
fn link_slider_right_triangle() {
    // A at (0, 3), link 5, slider on the x axis: B = (4, 0).
    let b = link_slider(
        P2::new(0.0, 3.0),
        5.0,
        P2::zeros(),
        P2::new(1.0, 0.0),
        Side::Left,
    )
    .unwrap();
    assert!((b - P2::new(4.0, 0.0)).norm() < 1e-15);
    assert!(link_slider(
        P2::new(0.0, 6.0),
        5.0,
        P2::zeros(),
        P2::new(1.0, 0.0),
        Side::Left
    )
    .is_none());
}

#[test]
fn circumcentre_of_right_triangle_is_hypotenuse_midpoint() {
    let (c, r) = circumcentre(P2::zeros(), P2::new(4.0, 0.0), P2::new(0.0, 3.0)).unwrap();
    assert!((c - P2::new(2.0, 1.5)).norm() < 1e-15);
    assert!((r - 2.5).abs() < 1e-15);
    assert!(circumcentre(P2::zeros(), P2::new(1.0, 1.0), P2::new(2.0, 2.0)).is_none());
}

/// Brute force: the smallest of the discs on every pair and every triple that encloses
/// all points (the optimum is always one of them).
fn brute_disc(pts: &[P2]) -> f64 {
    let mut best = f64::INFINITY;
    let encloses = |d: &Disc| {
        pts.iter()
            .all(|q| (q - d.centre).norm() <= d.radius * (1.0 + 1e-12))
    };
    for i in 0..pts.len() {
        for j in i + 1..pts.len() {
            let d = Disc::through2(pts[i], pts[j]);
            if encloses(&d) {
                best = best.min(d.radius);
            }
            for k in j + 1..pts.len() {
                if let Some((centre, radius)) = circumcentre(pts[i], pts[j], pts[k]) {
                    let d = Disc { centre, radius };
                    if encloses(&d) {
                        best = best.min(radius);
                    }
                }
            }
        }
    }
    best
}

#[test]
fn enclosing_disc_matches_brute_force_on_random_sets() {
    // A small deterministic LCG: 300 sets of 2–12 points.
    let mut rnd = crate::common::uniform_pm1(0x2545_f491_4f6c_dd1d);
    for case in 0..300 {
        let n = 2 + case % 11;
        let pts: Vec<P2> = (0..n).map(|_| P2::new(rnd(), rnd())).collect();
        let d = enclosing_disc(&pts).unwrap();
        let r = brute_disc(&pts);
        assert!(
            (d.radius - r).abs() <= 1e-12,
            "case {case}: {} vs {r}",
            d.radius
        );
        for q in &pts {
            assert!((q - d.centre).norm() <= d.radius * (1.0 + 1e-12) + 1e-15);
        }
    }
}

#[test]
fn enclosing_disc_of_sampled_circle_and_degenerate_sets() {
    // 360 points on the circle of radius 2 about (1, −3): the disc is that circle.
    let pts: Vec<P2> = (0..360)
        .map(|k| {
            let t = k as f64 * std::f64::consts::TAU / 360.0;
            P2::new(1.0 + 2.0 * t.cos(), -3.0 + 2.0 * t.sin())
        })
        .collect();
    let d = enclosing_disc(&pts).unwrap();
    assert!((d.centre - P2::new(1.0, -3.0)).norm() < 1e-14);
    assert!((d.radius - 2.0).abs() < 1e-14);
    // Collinear points: the disc on the two ends.
    let line: Vec<P2> = (0..7).map(|k| P2::new(k as f64, 2.0 * k as f64)).collect();
    let d = enclosing_disc(&line).unwrap();
    assert!((d.centre - P2::new(3.0, 6.0)).norm() < 1e-14);
    assert!((d.radius - 45f64.sqrt()).abs() < 1e-14);
    // One point, repeated points, empty and NaN.
    let one = enclosing_disc(&[P2::new(5.0, 5.0); 4]).unwrap();
    assert_eq!(one.radius, 0.0);
    assert!(enclosing_disc(&[]).is_none());
    assert!(enclosing_disc(&[P2::new(f64::NAN, 0.0)]).is_none());
}

/// The disc is the smallest: every point inside, and the points on its rim leave no gap
/// wider than a half turn around its centre (else it could shrink towards them).
fn assert_smallest(pts: &[P2], d: &cwsynth::geom::Disc, what: &str) {
    let tol = 1e-9 * d.radius.max(1e-300);
    for q in pts {
        assert!(
            (q - d.centre).norm() <= d.radius + tol,
            "{what}: a point outside"
        );
    }
    let mut angles: Vec<f64> = pts
        .iter()
        .filter(|q| ((*q - d.centre).norm() - d.radius).abs() <= tol)
        .map(|q| (q.y - d.centre.y).atan2(q.x - d.centre.x))
        .collect();
    angles.sort_by(f64::total_cmp);
    assert!(angles.len() >= 2 || d.radius == 0.0, "{what}: no rim");
    let gap = angles
        .windows(2)
        .map(|w| w[1] - w[0])
        .chain(
            angles
                .first()
                .map(|a| a + std::f64::consts::TAU - angles[angles.len() - 1]),
        )
        .fold(0.0, f64::max);
    assert!(gap <= std::f64::consts::PI + 1e-6, "{what}: rim gap {gap}");
}

#[test]
fn enclosing_disc_of_many_points_and_of_nearly_coincident_curves_is_the_smallest() {
    // Over 64 points the disc is found on a few candidates and checked against them all:
    // random clouds, several nearly coincident sampled curves (an envelope's scenarios),
    // collinear and repeated points.
    let mut rnd = crate::common::uniform_pm1(0x9e37_79b9_7f4a_7c15);
    for case in 0..120 {
        let n = 65 + (case * 37) % 400;
        let pts: Vec<P2> = match case % 4 {
            0 => (0..n).map(|_| P2::new(rnd(), 0.3 * rnd())).collect(),
            1 => {
                let curves = 2 + case % 7;
                let per = n / curves + 1;
                (0..curves)
                    .flat_map(|c| {
                        let s = 1.0 + 0.02 * c as f64 / curves as f64;
                        (0..per).map(move |k| {
                            let t = k as f64 * std::f64::consts::TAU / per as f64;
                            P2::new(s * (t.cos() + 0.25 * (2.0 * t).cos()), s * 0.8 * t.sin())
                        })
                    })
                    .collect()
            }
            2 => (0..n)
                .map(|k| P2::new(k as f64 * 1e-3 - 0.1, 2.0 * k as f64 * 1e-3))
                .collect(),
            _ => (0..n)
                .map(|k| P2::new((k % 5) as f64, ((k % 3) as f64).sqrt()))
                .collect(),
        };
        let d = enclosing_disc(&pts).unwrap();
        assert_smallest(&pts, &d, &format!("case {case}"));
    }
}
