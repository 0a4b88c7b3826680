//! Where the links are at a crank angle, without their derivatives (issue 36, throughput): the
//! closed-form position of each dyad, shared by [`Linkage::pose`] (which adds the velocities
//! and accelerations) and [`Linkage::places`] (which does not). A shape search's path error
//! and the full-turn check need the positions only, at hundreds of angles per candidate; the
//! derivatives' two 2×2 solves and the angles' `atan2` were half of a search's time.
//!
//! The positions are the same operations in the same order in both, so [`Linkage::places`]
//! gives [`Linkage::pose`]'s P and e bit for bit.

use super::{Dyad, Linkage, NoAssembly, Point};
use crate::geom::{circle_circle, cmul, cross, link_slider, Side, P2};

/// A link's place at θ: its reference joint P and e = (cos ψ, sin ψ); a point fixed to it at
/// `at` in its frame is X = P + R(ψ)·at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Place {
    /// P (m, world).
    pub p: P2,
    /// e = (cos ψ, sin ψ), from the construction.
    pub e: P2,
}

impl Place {
    /// X = P + R(ψ)·at, R(ψ)·at the complex product e·at.
    pub fn point(&self, at: P2) -> P2 {
        self.p + cmul(self.e, at)
    }
}

/// One dyad's closed-form position: its links' places, its inner joint and its conditioning.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Placed {
    /// Link a's place.
    pub a: Place,
    /// Link b's place.
    pub b: Place,
    /// The inner joint: B for RRR and RRP, Q for RPR.
    pub joint: P2,
    /// sin μ ([`super::DyadState::sin_mu`]).
    pub sin_mu: f64,
    /// RPR's s (m, along the guide); 0 for the others.
    pub slide: f64,
    /// The gap a failure at the toggle reports, where the dyad's derivative systems are
    /// singular (RRR's distance from assembling, within rounding of 0; 0 for the others;
    /// [`NoAssembly::gap`]).
    pub gap: f64,
}

/// RRR: B on the circles (P, l1) and (Q, l2) on `side` ([`circle_circle`]);
/// e_a = (B − P)/|B − P|, e_b = (B − Q)/|B − Q|, sin μ = e_a × e_b. `Err(gap)` where the
/// circles do not meet, gap = max(|PQ| − (l1 + l2), |l1 − l2| − |PQ|).
#[inline]
pub(super) fn rrr(p: P2, l1: f64, q: P2, l2: f64, side: Side) -> Result<Placed, f64> {
    let dist = (q - p).norm();
    let gap = (dist - (l1 + l2)).max((l1 - l2).abs() - dist);
    let b = circle_circle(p, l1, q, l2, side).ok_or(gap)?;
    let (da, db) = (b - p, b - q);
    let (ea, eb) = (da / da.norm(), db / db.norm());
    Ok(Placed {
        a: Place { p, e: ea },
        b: Place { p: q, e: eb },
        joint: b,
        sin_mu: cross(ea, eb),
        slide: 0.0,
        gap,
    })
}

/// RRP: B on the line through `origin` along u = (cos angle, sin angle) at `l` from P
/// ([`link_slider`]); e_a = (B − P)/|B − P|, the slider's place (B, u), sin μ = e_a·u.
/// `Err(gap)` where the rod cannot reach the line, gap = |(origin − P) × u| − l.
#[inline]
pub(super) fn rrp(p: P2, l: f64, origin: P2, angle: f64, side: Side) -> Result<Placed, f64> {
    let (su, cu) = angle.sin_cos();
    let u = P2::new(cu, su);
    let gap = cross(origin - p, u).abs() - l;
    let b = link_slider(p, l, origin, u, side).ok_or(gap)?;
    let da = b - p;
    let ea = da / da.norm();
    Ok(Placed {
        a: Place { p, e: ea },
        b: Place { p: b, e: u },
        joint: b,
        sin_mu: ea.dot(&u),
        slide: 0.0,
        gap: 0.0,
    })
}

/// RPR: v = Q − P = R(ψ)(s, e) with s = ±sqrt(|v|² − e²) (the sign of `side`), so
/// (cos ψ, sin ψ) = (s v_x + e v_y, s v_y − e v_x)/|v|², normalised; sin μ = −s/|v|.
/// `Err(gap)` where |v| < |e| or P = Q, gap = |e| − |v|.
#[inline]
pub(super) fn rpr(p: P2, q: P2, offset: f64, side: Side) -> Result<Placed, f64> {
    let v = q - p;
    let dist = v.norm();
    let e_abs = offset.abs();
    let s2 = (dist - e_abs) * (dist + e_abs);
    if !(s2 >= 0.0) || dist == 0.0 {
        return Err(e_abs - dist);
    }
    let s = side.sign() * s2.sqrt();
    let eg = P2::new(s * v.x + offset * v.y, s * v.y - offset * v.x);
    let eg = eg / eg.norm();
    Ok(Placed {
        a: Place { p, e: eg },
        b: Place { p: q, e: eg },
        joint: q,
        sin_mu: -s / dist,
        slide: s,
        gap: 0.0,
    })
}

impl Linkage {
    /// Every link's place at θ, crank first: [`Linkage::pose`]'s P and e bit for bit, without
    /// the derivatives, the angles ψ and the dyads' states. It fails where a dyad does not
    /// assemble or sits exactly at a toggle (sin μ = 0), as `pose` does; `pose` fails besides
    /// where a derivative system is singular to rounding with sin μ ≠ 0 or overflows.
    pub fn places(&self, theta: f64) -> Result<Vec<Place>, NoAssembly> {
        let mut out = Vec::with_capacity(self.n_links());
        self.places_into(theta, &mut out)?;
        Ok(out)
    }

    /// [`Linkage::places`] into `out` (cleared first), for a caller that reuses one buffer.
    pub fn places_into(&self, theta: f64, out: &mut Vec<Place>) -> Result<(), NoAssembly> {
        let (s, c) = theta.sin_cos();
        out.clear();
        out.push(Place {
            p: self.pivot,
            e: P2::new(c, s),
        });
        for (k, d) in self.dyads.iter().enumerate() {
            let fail = |gap: f64| NoAssembly {
                theta,
                dyad: k,
                gap: gap.max(0.0),
            };
            let at = |pt: &Point| match *pt {
                Point::Frame(x) => x,
                Point::On { link, at } => out[link].point(at),
            };
            let placed = match *d {
                Dyad::Rrr { p, l1, q, l2, side } => rrr(at(&p), l1, at(&q), l2, side),
                Dyad::Rrp {
                    p,
                    l,
                    origin,
                    angle,
                    side,
                } => rrp(at(&p), l, origin, angle, side),
                Dyad::Rpr { p, q, offset, side } => rpr(at(&p), at(&q), offset, side),
            }
            .map_err(fail)?;
            if placed.sin_mu == 0.0 {
                return Err(fail(placed.gap)); // `pose`'s derivative system fails first
            }
            out.extend([placed.a, placed.b]);
        }
        Ok(())
    }
}
