//! Closed-form planar constructions shared by the mechanism models: circle–circle
//! intersection (a dyad), link–slider intersection, circumcentre.
//!
//! A construction that has no solution (the links cannot reach) returns `None`, never NaN:
//! whether that is an error is for the caller to decide. Every formula is written in the
//! form that stays accurate near tangency and near collinearity.

use nalgebra::Vector2;

/// A point or vector in the plane (m).
pub type P2 = Vector2<f64>;

/// Which of the two solutions of a dyad to take, seen from the first centre looking at the
/// second (or along the slider direction): `Left` is the counter-clockwise side.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    /// Counter-clockwise of the centre line.
    Left,
    /// Clockwise of the centre line.
    Right,
}

impl Side {
    /// +1 for `Left`, −1 for `Right`.
    pub fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }
}

/// 2-D cross product (z component) `a × b`.
pub fn cross(a: P2, b: P2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Intersection of the circle (`c0`, `r0`) with the circle (`c1`, `r1`) on `side`.
///
/// With d = |c1 − c0|, the foot of the chord is at a = (d² + r0² − r1²)/(2d) from c0 and the
/// half chord is h = sqrt((r0+r1−d)(r0+r1+d)(d−r0+r1)(d+r0−r1))/(2d); the factored form keeps
/// h accurate near tangency, where the textbook sqrt(r0² − a²) loses all its digits. A
/// negative product within rounding (relative 1e-14) is tangency (h = 0); beyond that the
/// circles do not meet and the result is `None`. Concentric circles give `None`.
pub fn circle_circle(c0: P2, r0: f64, c1: P2, r1: f64, side: Side) -> Option<P2> {
    let dv = c1 - c0;
    let d = dv.x.hypot(dv.y);
    if !(d > 0.0) || !(r0 >= 0.0) || !(r1 >= 0.0) {
        return None;
    }
    let prod = (r0 + r1 - d) * (r0 + r1 + d) * (d - r0 + r1) * (d + r0 - r1);
    let scale = (r0 + r1 + d).powi(4);
    let h = if prod >= 0.0 {
        prod.sqrt() / (2.0 * d)
    } else if prod >= -1e-14 * scale {
        0.0
    } else {
        return None;
    };
    let a = (d * d + (r0 - r1) * (r0 + r1)) / (2.0 * d);
    let u = dv / d;
    let n = P2::new(-u.y, u.x);
    Some(c0 + u * a + n * (side.sign() * h))
}

/// Point B on the line through `p0` with unit direction `u` at distance `l` from `a`, on the
/// `side` of the foot of the perpendicular from `a` (`Left` = further along `u`).
///
/// With w = p0 − a and c = w × u (the signed distance of `a` from the line),
/// B = p0 + t u, t = −w·u ± sqrt((l − c)(l + c)). `None` when |c| > l (the link cannot reach).
pub fn link_slider(a: P2, l: f64, p0: P2, u: P2, side: Side) -> Option<P2> {
    let w = p0 - a;
    let c = cross(w, u);
    let disc = (l - c) * (l + c);
    if !(disc >= 0.0) {
        return None;
    }
    Some(p0 + u * (-w.dot(&u) + side.sign() * disc.sqrt()))
}

/// Circumcentre and radius of the triangle `p1 p2 p3`, or `None` when the points are
/// collinear to within relative `1e-12` (the centre runs to infinity).
///
/// Computed relative to `p1` (b = p2 − p1, c = p3 − p1, D = 2 b × c):
/// centre = p1 + (c_y|b|² − b_y|c|², b_x|c|² − c_x|b|²)/D.
pub fn circumcentre(p1: P2, p2: P2, p3: P2) -> Option<(P2, f64)> {
    let b = p2 - p1;
    let c = p3 - p1;
    let d = 2.0 * cross(b, c);
    let (bb, cc) = (b.norm_squared(), c.norm_squared());
    if !(d.abs() > 1e-12 * (bb * cc).sqrt() * 2.0) {
        return None;
    }
    let o = P2::new((c.y * bb - b.y * cc) / d, (b.x * cc - c.x * bb) / d);
    Some((p1 + o, o.norm()))
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert!(
            circle_circle(P2::zeros(), 1.0, P2::new(2.0 + 1e-9, 0.0), 1.0, Side::Left).is_none()
        );
        assert!(circle_circle(P2::zeros(), 1.0, P2::zeros(), 1.0, Side::Left).is_none());
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
}
