//! Closed-form planar constructions shared by the mechanism models: circle–circle
//! intersection (a dyad), link–slider intersection, the 2×2 solve of a differentiated dyad,
//! circumcentre, and the smallest disc enclosing a point set (the geometric form of a
//! minimax counterweight); the exact mass properties of a region bounded by lines and arcs
//! (`outline`: a plate drawn in a DXF file); the cap bounding a counterweight's first moment
//! in its envelope disc and the ring or lens plate that realises its mass properties (`plate`).
//!
//! A construction that has no solution (the links cannot reach) returns `None`, never NaN:
//! whether that is an error is for the caller to decide. Every formula is written in the
//! form that stays accurate near tangency and near collinearity.

use nalgebra::Vector2;

pub mod outline;
pub mod plate;

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

/// The unit vector at angle ψ: (cos ψ, sin ψ).
pub fn dir(psi: f64) -> P2 {
    let (s, c) = psi.sin_cos();
    P2::new(c, s)
}

/// `v` turned anticlockwise by ψ: Rot(ψ)·v = (cos ψ v_x − sin ψ v_y, sin ψ v_x + cos ψ v_y).
pub fn rot(psi: f64, v: P2) -> P2 {
    cmul(dir(psi), v)
}
/// 2-D cross product (z component) `a × b`.
pub fn cross(a: P2, b: P2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// The signed angle turning the direction `a` into `b`, in (−π, π]: atan2(a × b, a·b).
pub fn turn(a: P2, b: P2) -> f64 {
    cross(a, b).atan2(a.dot(&b))
}

/// The rotation by +90°: J v = (−v_y, v_x), so that a × b = (J a)·b.
pub fn perp(v: P2) -> P2 {
    P2::new(-v.y, v.x)
}

/// The complex product a·b = (a_x b_x − a_y b_y, a_x b_y + a_y b_x). With a = (cos ψ, sin ψ)
/// it is the rotation R(ψ) b; with a general a, a rotation and a scaling.
pub fn cmul(a: P2, b: P2) -> P2 {
    P2::new(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x)
}

/// The solution (x, y) of x a + y b = w by Cramer's rule: with D = a × b,
/// x = (w × b)/D, y = (a × w)/D. `None` when D is zero or the result is not finite.
///
/// This is the 2×2 system of a differentiated dyad loop equation; the sine of the angle
/// between the columns, D/(|a||b|), measures its conditioning, and the relative round-off of
/// x, y is a few ε·|a||b|/|D| (plus the data's own error amplified by the same factor).
pub fn solve_columns(a: P2, b: P2, w: P2) -> Option<(f64, f64)> {
    let d = cross(a, b);
    let x = cross(w, b) / d;
    let y = cross(a, w) / d;
    (d != 0.0 && x.is_finite() && y.is_finite()).then_some((x, y))
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

/// A disc: centre and radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disc {
    /// Centre.
    pub centre: P2,
    /// Radius (≥ 0).
    pub radius: f64,
}

impl Disc {
    /// The disc with `a` and `b` at the ends of a diameter.
    pub fn through2(a: P2, b: P2) -> Disc {
        Disc {
            centre: 0.5 * (a + b),
            radius: 0.5 * (a - b).norm(),
        }
    }

    /// The smallest disc with `a`, `b`, `c` on its boundary or inside: the circumcircle, or
    /// for (near-)collinear points the disc on their farthest pair.
    fn through3(a: P2, b: P2, c: P2) -> Disc {
        match circumcentre(a, b, c) {
            Some((centre, radius)) => Disc { centre, radius },
            None => [(a, b), (a, c), (b, c)]
                .into_iter()
                .map(|(p, q)| Disc::through2(p, q))
                .max_by(|d, e| d.radius.total_cmp(&e.radius))
                .expect("three pairs"),
        }
    }
}

/// The smallest disc enclosing `points` (`None` for an empty set or a non-finite point).
///
/// Welzl's randomised incremental algorithm in its iterative form (de Berg et al.,
/// *Computational Geometry*, §4.7), with the points visited in a fixed scrambled order (a
/// golden-ratio stride through the indices) instead of a random one, so the result is
/// deterministic while points sampled along a curve still arrive well spread (expected
/// linear time). A point counts as inside when its distance from the centre exceeds the
/// radius by at most 1e-14 of the set's extent, so rounding cannot trigger a rebuild.
///
/// Over many points (the union of several sampled curves: an envelope's scenarios) Welzl's
/// pass runs first on a few candidates — the extreme points in 8 directions — and then on
/// those and the points left outside, until none is: the smallest disc of a subset that
/// encloses every point is the smallest disc of them all (it is no larger than theirs, and
/// that disc is unique), so the result is the same disc, found with a few linear checks
/// instead of the rebuilds a long run of nearly coincident curves costs.
pub fn enclosing_disc(points: &[P2]) -> Option<Disc> {
    let n = points.len();
    if n == 0 || points.iter().any(|p| !(p.x.is_finite() && p.y.is_finite())) {
        return None;
    }
    if n <= 64 {
        return Some(welzl(points));
    }
    let extent = points
        .iter()
        .map(|q| (q - points[0]).abs().max())
        .fold(0.0, f64::max);
    let slack = 1e-14 * extent;
    // The extreme points along x, y, x + y and x − y, both ways, found in one pass.
    let along = |p: &P2| [p.x, p.y, p.x + p.y, p.x - p.y];
    let mut ext = [(0usize, f64::NEG_INFINITY); 8];
    for (i, p) in points.iter().enumerate() {
        for (k, v) in along(p).into_iter().enumerate() {
            for (slot, v) in [(2 * k, v), (2 * k + 1, -v)] {
                if v > ext[slot].1 {
                    ext[slot] = (i, v);
                }
            }
        }
    }
    let mut chosen = vec![false; n];
    ext.iter().for_each(|&(i, _)| chosen[i] = true);
    loop {
        let subset: Vec<P2> = (0..n).filter(|&i| chosen[i]).map(|i| points[i]).collect();
        let d = welzl(&subset);
        let outside: Vec<usize> = (0..n)
            .filter(|&i| (points[i] - d.centre).norm() > d.radius + slack)
            .collect();
        if outside.is_empty() {
            return Some(d);
        }
        if outside.iter().all(|&i| chosen[i]) {
            // Rounding left a chosen point outside its own disc: Welzl over them all.
            return Some(welzl(points));
        }
        outside.into_iter().for_each(|i| chosen[i] = true);
    }
}

/// Welzl's pass over all of `points` (finite, at least one): [`enclosing_disc`]'s core.
fn welzl(points: &[P2]) -> Disc {
    let n = points.len();
    let mut stride = ((n as f64) * 0.618_033_988_749_894_9) as usize;
    while stride > 1 && gcd(stride, n) != 1 {
        stride -= 1;
    }
    let stride = stride.max(1);
    let p: Vec<P2> = (0..n).map(|k| points[(k * stride) % n]).collect();
    let extent = p.iter().map(|q| (q - p[0]).abs().max()).fold(0.0, f64::max);
    let slack = 1e-14 * extent;
    let out = |d: &Disc, q: P2| (q - d.centre).norm() > d.radius + slack;
    let mut d = Disc {
        centre: p[0],
        radius: 0.0,
    };
    for i in 1..n {
        if out(&d, p[i]) {
            d = Disc {
                centre: p[i],
                radius: 0.0,
            };
            for j in 0..i {
                if out(&d, p[j]) {
                    d = Disc::through2(p[i], p[j]);
                    for k in 0..j {
                        if out(&d, p[k]) {
                            d = Disc::through3(p[i], p[j], p[k]);
                        }
                    }
                }
            }
        }
    }
    d
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}
