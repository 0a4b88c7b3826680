//! The plates that realise a counterweight's mass properties, and the circular cap that bounds
//! them. A counterweight is a flat plate of areal density σ (kg/m²) cut from anywhere inside
//! an envelope disc of radius R about the joint (the origin); its mass m = σA, first moment
//! u = σ∫∫p dA and polar moment about the joint I = σ∫∫|p|² dA. An optimiser works with
//! (m, u, I) under convex necessary conditions; this module gives the function those conditions
//! are written with ([`cap`]) and a concrete plate that realises a chosen (m, u, I) as nearly
//! as plates can ([`ring`], [`realise`]).
//!
//! **The cap.** Of all regions of area A inside the disc, the one whose first moment
//! S = |∫∫p dA| is largest is the circular segment cut off by a chord (every point kept is
//! farther along the axis than every point left out). With α the half-angle its chord
//! subtends at the centre, A = R² (α − sin α cos α) and S = ⅔ R³ sin³α; S(A) is concave with
//! dS/dA = R cos α = h, the chord's signed distance from the centre. So |u| ≤ σ S(m/σ) for
//! every plate, and S(A) ≤ S(A₀) + h(A₀)(A − A₀) gives its linear cuts.
//!
//! **Inertia bounds.** At fixed m and u, I = |u|²/m + I_c with I_c the polar moment about
//! the centroid, at least the disc's m²/(2πσ); and a region of area A has ∫∫|p|² dA at most
//! the rim annulus's R²A − A²/(2π). So |u|²/m + m²/(2πσ) ≤ I ≤ R²m − m²/(2πσ).
//!
//! **Realising.** A ring (annulus) of inner radius a, outer b, centred at c has
//! A = π(b² − a²), I_c = m(a² + b²)/2, so for a given (m, u, I): c = u/m,
//! b² = I_c/m + A/(2π), a² = I_c/m − A/(2π) ([`ring`]). When even the disc of area A centred
//! at the wanted centroid sticks out of the envelope, the plate is the **lens**: the envelope
//! intersected with a second disc whose centre lies along u. It is parametrised by its chord
//! (where the two circles cross) at distance x from the joint, half-length y = √(R² − x²), and
//! the sagitta s of the second disc's arc (how far it bulges from the chord towards the
//! joint): that disc has radius ρ = (y² + s²)/(2s) and centre D = x + (y² − s²)/(2s) along u.
//! s → 0 is the cap with chord x; x → R is the disc of diameter s touching the envelope from
//! inside. At each x the area grows with s (the second discs through the chord's ends are
//! nested), and is solved for; the centroid distance then runs from the cap's (x = h) to the
//! touching disc's, R − √(A/π) (x = R), and x is bisected on it ([`realise`]).
//!
//! The integrals of both shapes are outline's exact Green integrals of their boundary arcs
//! ([`PlateShape::moments`]).

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::outline::{x_minus_sin, Edge, Loop, Moments};
use super::{dir, perp, P2};

/// The circular segment ("cap") of area A cut from the disc of radius R by a chord: the region
/// of area A whose first moment about the centre is the largest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cap {
    /// α ∈ [0, π], the half-angle the chord subtends at the centre.
    pub half_angle: f64,
    /// A = R² (α − sin α cos α).
    pub area: f64,
    /// S = (2/3) R³ sin³α, its first moment about the centre (along its axis).
    pub first_moment: f64,
    /// h = R cos α = dS/dA, the chord's signed distance from the centre (S is concave in A).
    pub slope: f64,
}

/// The cap of area `area` of the disc of radius `r`: A clamped to [0, πR²] (a NaN area is 0),
/// α solved from A = R² (α − sin α cos α) by a safeguarded Newton iteration to full double
/// precision, S = ⅔ R³ sin³α, h = R cos α. Past half the disc α = π − β with β the half-angle
/// of the complement πR² − A, so sin α and cos α keep their digits near A = πR² as near A = 0.
/// A radius that is not positive and finite gives the empty cap (all zero).
pub fn cap(area: f64, r: f64) -> Cap {
    if !(r > 0.0 && r.is_finite()) {
        return Cap {
            half_angle: 0.0,
            area: 0.0,
            first_moment: 0.0,
            slope: 0.0,
        };
    }
    let r2 = r * r;
    let full = PI * r2;
    let a = area.max(0.0).min(full);
    let (alpha, sin, cos) = if a <= 0.5 * full {
        let b = half_angle_of(a / r2);
        (b, b.sin(), b.cos())
    } else {
        let b = half_angle_of((full - a) / r2);
        (PI - b, b.sin(), -b.cos())
    };
    Cap {
        half_angle: alpha,
        area: a,
        first_moment: 2.0 / 3.0 * r * r2 * sin.powi(3),
        slope: r * cos,
    }
}

/// The areas whose cap has first moment `s`: (A_lo, A_hi), the two solutions of S(A) = s
/// (sin³α = 3s/(2R³): α and π − α), so every A in [A_lo, A_hi] has a region of first moment
/// s (the caps' S is at least s there, and the centred disc's is 0). `None` when s exceeds
/// the half disc's ⅔R³ or R is not positive and finite; s ≤ 0 gives (0, πR²).
pub fn cap_areas(s: f64, r: f64) -> Option<(f64, f64)> {
    if !(r > 0.0 && r.is_finite()) {
        return None;
    }
    let full = PI * r * r;
    if !(s > 0.0) {
        return Some((0.0, full));
    }
    let sin = (1.5 * s / (r * r * r)).cbrt();
    if sin > 1.0 {
        return None;
    }
    let lo = r * r * segment(sin.asin());
    Some((lo, full - lo))
}

/// g(β) = β − sin β cos β = (x − sin x)/2 with x = 2β, without its cancellation near 0.
fn segment(beta: f64) -> f64 {
    x_minus_sin(2.0 * beta) / 2.0
}

/// β ∈ [0, π/2] with g(β) = t (0 ≤ t ≤ π/2): Newton on g, g′(β) = 2 sin²β, from
/// β₀ = (3t/2)^⅓ (g ≈ ⅔β³), kept inside a bracket that every step narrows and bisected when a
/// step would leave it; stops when a step moves β by less than an ulp.
fn half_angle_of(t: f64) -> f64 {
    if !(t > 0.0) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, FRAC_PI_2);
    let mut b = (1.5 * t).cbrt().min(FRAC_PI_2);
    for _ in 0..200 {
        let f = segment(b) - t;
        if f == 0.0 {
            break;
        }
        if f < 0.0 {
            lo = b;
        } else {
            hi = b;
        }
        let s = b.sin();
        let mut next = b - f / (2.0 * s * s);
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        let step = (next - b).abs();
        b = next;
        if step <= f64::EPSILON * b || hi - lo <= f64::EPSILON * b {
            break;
        }
    }
    b
}

/// A concrete plate that realises a counterweight: its shape and its exact (m, u, I).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlateShape {
    /// A ring (annulus, inner radius 0 = a full disc) centred at `centre`: inner radius a,
    /// outer b. A = π(b² − a²), S = A c, J = A (|c|² + (a² + b²)/2).
    Ring {
        /// Its centre c (m).
        centre: P2,
        /// a ≥ 0 (m).
        inner: f64,
        /// b ≥ a (m).
        outer: f64,
    },
    /// The lens: the envelope disc (centre 0, radius `envelope`) intersected with the disc of
    /// centre `disc_centre` and radius `disc_radius` (as disc_radius → ∞ with its centre far
    /// away this tends to the cap).
    Lens {
        /// R, the envelope's radius (m).
        envelope: f64,
        /// The second disc's centre (m).
        disc_centre: P2,
        /// ρ, the second disc's radius (m).
        disc_radius: f64,
    },
}

/// A plate and the mass properties it has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Realised {
    /// The plate.
    pub shape: PlateShape,
    /// m (kg), u (kg·m), I about the joint (kg·m²) of the shape at areal density σ, computed
    /// from the shape (exactly, not copied from the request).
    pub mass: f64,
    /// u = σ ∫∫ p dA (kg·m).
    pub first_moment: P2,
    /// I = σ ∫∫ |p|² dA about the joint (kg·m²).
    pub inertia: f64,
}

impl PlateShape {
    /// The shape's boundary as closed counter-clockwise loops of `outline::Edge`, for drawings
    /// and for its integrals. A ring: its outer circle, then its inner circle (left out when
    /// the inner radius is 0; nothing for a zero outer radius). A lens: one loop of two arcs,
    /// the envelope's from the lower crossing P₋ to the upper P₊ (seen along the second disc's
    /// centre) and the second disc's back from P₊ to P₋; a lens whose discs do not cross is the
    /// smaller disc when it lies inside the other, else empty.
    pub fn loops(&self) -> Vec<Vec<Edge>> {
        match *self {
            PlateShape::Ring {
                centre,
                inner,
                outer,
            } => [outer, inner]
                .into_iter()
                .filter(|&r| r > 0.0)
                .map(|r| vec![Edge::arc(centre, r, 0.0, TAU)])
                .collect(),
            PlateShape::Lens {
                envelope,
                disc_centre,
                disc_radius,
            } => lens_loops(envelope, disc_centre, disc_radius),
        }
    }

    /// Its region's Moments about the joint (area, first, second), by outline's Green
    /// integrals of [`loops`](Self::loops): the first loop counted positive, the others (a
    /// ring's inner circle) subtracted.
    pub fn moments(&self) -> Moments {
        self.loops()
            .into_iter()
            .enumerate()
            .map(|(i, edges)| Loop { edges }.moments() * if i == 0 { 1.0 } else { -1.0 })
            .fold(Moments::default(), |s, m| s + m)
    }
}

/// The lens's boundary (see [`PlateShape::loops`]). With d = |c| and the axis e = c/d, the
/// circles cross on the chord at x = (R² + (d − ρ)(d + ρ))/(2d) along e (factored, so a
/// large far disc keeps its digits), half-length y = √((R − x)(R + x)); the envelope's arc
/// has half-sweep atan2(y, x) about e, the second disc's atan2(y, d − x) about −e.
fn lens_loops(r: f64, c: P2, rho: f64) -> Vec<Vec<Edge>> {
    let d = c.norm();
    let circle = |centre: P2, radius: f64| vec![vec![Edge::arc(centre, radius, 0.0, TAU)]];
    if !(r > 0.0 && rho > 0.0) || d >= r + rho {
        return Vec::new();
    }
    if d + rho <= r {
        return circle(c, rho);
    }
    if d + r <= rho {
        return circle(P2::zeros(), r);
    }
    let x = (r * r + (d - rho) * (d + rho)) / (2.0 * d);
    let y = ((r - x) * (r + x)).max(0.0).sqrt();
    let theta = c.y.atan2(c.x);
    let (e, n) = (dir(theta), perp(dir(theta)));
    let (upper, lower) = (e * x + n * y, e * x - n * y);
    let beta = y.atan2(x);
    let gamma = y.atan2(d - x);
    let envelope = Edge {
        from: lower,
        to: upper,
        ..Edge::arc(P2::zeros(), r, theta - beta, 2.0 * beta)
    };
    let disc = Edge {
        from: upper,
        to: lower,
        ..Edge::arc(c, rho, theta + PI - gamma, 2.0 * gamma)
    };
    vec![vec![envelope, disc]]
}

/// The relative tolerance of [`ring`]'s two conditions.
const RING_TOL: f64 = 1e-12;

/// The ring centred at the centroid c = u/m that realises (m, u, I) exactly, if one exists
/// within the envelope: I_c = I − |u|²/m, b² = I_c/m + A/(2π), a² = I_c/m − A/(2π)
/// (A = m/σ), requiring a² ≥ 0 (I_c ≥ m²/(2πσ), the disc's) and |c| + b ≤ R (relative
/// tolerance 1e-12 on both, the radii then clamped: a² ≥ 0, b ≤ R − |c|). `None` otherwise,
/// for m ≤ 0, σ ≤ 0 or R ≤ 0, or a non-finite result.
pub fn ring(m: f64, u: P2, inertia: f64, sigma: f64, r: f64) -> Option<PlateShape> {
    if !(m > 0.0 && sigma > 0.0 && r > 0.0) {
        return None;
    }
    let half = m / sigma / TAU;
    let c = u / m;
    let ic_m = (inertia - u.norm_squared() / m) / m;
    let (a2, b2) = (ic_m - half, ic_m + half);
    let outer = b2.sqrt();
    let reach = r - c.norm();
    let fits = c.norm() + outer <= r * (1.0 + RING_TOL);
    if !(a2 >= -RING_TOL * half && fits && outer.is_finite()) {
        return None;
    }
    Some(PlateShape::Ring {
        centre: c,
        inner: a2.max(0.0).sqrt(),
        outer: outer.min(reach).max(0.0),
    })
}

/// A plate as near to (m, u, I) as the shapes above give, always within the envelope:
/// - m is kept (clamped to [0, σπR²]);
/// - the centroid direction is u's (the x axis for u = 0 or non-finite, whose distance is
///   then 0); its distance |u|/m is kept if a region of area A = m/σ can have it
///   (≤ cap(A).first_moment/A), else it is the cap's;
/// - if the disc of area A centred at that centroid c fits (|c| + √(A/π) ≤ R): the ring with
///   I_c = I − m|c|² clamped into [the disc's mA/(2π), the largest ring's whose outer radius
///   touches the envelope, m((R − |c|)² − A/(2π))] (a NaN I gives the disc);
/// - else the lens with that area and centroid distance (module doc: the chord position x is
///   bisected on the centroid distance, the sagitta s at each x on the area), whose I is what
///   it is. The cap itself is the lens's limit s → 0 (a disc of infinite radius): a distance
///   that needs a sagitta below [`MIN_SAGITTA`] R is realised by the lens with that sagitta.
///
/// Returns the shape and its exact (m, u, I) from `moments()` × σ. m = 0 (or σ, R not
/// positive and finite) → a Ring of zero radii at the origin with zeros.
pub fn realise(m: f64, u: P2, inertia: f64, sigma: f64, r: f64) -> Realised {
    let valid = sigma > 0.0 && sigma.is_finite() && r > 0.0 && r.is_finite();
    let m = if valid {
        m.max(0.0).min(sigma * PI * r * r)
    } else {
        0.0
    };
    if !(m > 0.0) {
        return Realised {
            shape: PlateShape::Ring {
                centre: P2::zeros(),
                inner: 0.0,
                outer: 0.0,
            },
            mass: 0.0,
            first_moment: P2::zeros(),
            inertia: 0.0,
        };
    }
    let area = m / sigma;
    let norm = u.norm();
    let (e, wanted) = if norm > 0.0 && norm.is_finite() {
        (u / norm, norm / m)
    } else {
        (P2::new(1.0, 0.0), 0.0)
    };
    let cap = cap(area, r);
    let d = wanted.min(cap.first_moment / area);
    let shape = if d + (area / PI).sqrt() <= r {
        ring_within(area, m, e * d, inertia, r)
    } else {
        lens(area, d, e, r, cap.slope)
    };
    let mo = shape.moments() * sigma;
    Realised {
        shape,
        mass: mo.area,
        first_moment: mo.first,
        inertia: mo.second,
    }
}

/// The ring of area `area` (mass m) centred at `c`, whose disc of that area fits the envelope,
/// with I_c = I − m|c|² clamped as [`realise`] says: a² = I_c/m − A/(2π) (≥ 0),
/// b² = a² + A/π, b ≤ R − |c|.
fn ring_within(area: f64, m: f64, c: P2, inertia: f64, r: f64) -> PlateShape {
    let reach = r - c.norm();
    let half = area / TAU;
    let ic = (inertia - m * c.norm_squared())
        .max(m * half)
        .min(m * (reach * reach - half));
    let a2 = ((ic - m * half) / m).max(0.0);
    PlateShape::Ring {
        centre: c,
        inner: a2.sqrt(),
        outer: (a2 + 2.0 * half).sqrt().min(reach),
    }
}

/// The smallest sagitta of a lens's second arc, relative to R: the nearest lens to the cap.
///
/// The cap is the lens's limit s → 0, where the second disc's radius ρ ≈ y²/(2s) grows without
/// bound; stored as a float, that disc fixes its arc's crossing of the axis, D − ρ, only to
/// ε ρ, so the lens's area only to about 2y ε ρ ≈ 1.5 ε R/s of a thin cap's. At s = 3e-5 R
/// that is 1e-11 relative, while the lens's centroid distance falls short of the cap's by
/// only (4/45) y s²/(A d) (second order: the cap is the maximum), 1e-10 relative for a third
/// of the disc.
pub const MIN_SAGITTA: f64 = 3e-5;

/// The lens of area `area` inside the envelope of radius `r` whose centroid lies at distance
/// `d` along the unit vector `e` (d between the touching disc's R − √(A/π) and the cap's):
/// bisection of the chord position x ∈ (h, R) on the centroid distance of
/// [`lens_of_area`]`(x)`, which falls from the cap's at x = h to the touching disc's at x = R,
/// while the sagitta rises from 0; x is kept where the sagitta is at least [`MIN_SAGITTA`] R.
fn lens(area: f64, d: f64, e: P2, r: f64, h: f64) -> PlateShape {
    let (mut lo, mut hi) = (h, r);
    let mut best = lens_of_area(area, 0.5 * (lo + hi), e, r).0;
    for _ in 0..200 {
        let x = 0.5 * (lo + hi);
        if !(x > lo && x < hi) {
            break;
        }
        let (shape, s) = lens_of_area(area, x, e, r);
        let mo = shape.moments();
        if mo.first.dot(&e) / mo.area > d || s < MIN_SAGITTA * r {
            lo = x;
        } else {
            hi = x;
        }
        best = shape;
    }
    best
}

/// The lens with its chord at distance `x` along `e` (h ≤ x < R) whose area is `area`, and its
/// sagitta: s ∈ (0, x + R) bisected on the area (the cap at s = 0 has at most `area`, the
/// whole envelope at s = x + R at least).
fn lens_of_area(area: f64, x: f64, e: P2, r: f64) -> (PlateShape, f64) {
    let (mut lo, mut hi) = (0.0, x + r);
    let mut best = (lens_at(x, 0.5 * hi, e, r), 0.5 * hi);
    for _ in 0..200 {
        let s = 0.5 * (lo + hi);
        if !(s > lo && s < hi) {
            break;
        }
        best = (lens_at(x, s, e, r), s);
        if best.0.moments().area < area {
            lo = s;
        } else {
            hi = s;
        }
    }
    best
}

/// The lens with its chord at `x` along `e` and sagitta `s` > 0: y² = (R − x)(R + x),
/// ρ = (y² + s²)/(2s), D = x + (y² − s²)/(2s).
fn lens_at(x: f64, s: f64, e: P2, r: f64) -> PlateShape {
    let y2 = (r - x) * (r + x);
    PlateShape::Lens {
        envelope: r,
        disc_centre: e * (x + (y2 - s * s) / (2.0 * s)),
        disc_radius: (y2 + s * s) / (2.0 * s),
    }
}
