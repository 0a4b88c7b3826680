//! A link's length as a parameter (issue 33, the envelope's length tolerances): where a link's
//! second joint (its tip) is, and the same linkage with one link longer or shorter — every
//! point that sat at the old tip moving with it, so the chain stays connected.

use super::{Dyad, Inertia, Linkage, LinkageError, Point};
use crate::geom::P2;

/// What a link's `tip` is: its second joint in its own frame, where it has one — the crank's
/// pin at (|A0 A|, 0) (`crank_length`), an RRR link's B at (l1, 0) or (l2, 0), an RRP rod's
/// B at (l, 0). A slider, a guide or a block has none.
pub fn tip_of(dyads: &[Dyad], crank_length: f64, link: usize) -> Option<P2> {
    if link == 0 {
        return Some(P2::new(crank_length, 0.0));
    }
    let (k, second) = ((link - 1) / 2, (link - 1) % 2 == 1);
    match (dyads.get(k)?, second) {
        (Dyad::Rrr { l1, .. }, false) => Some(P2::new(*l1, 0.0)),
        (Dyad::Rrr { l2, .. }, true) => Some(P2::new(*l2, 0.0)),
        (Dyad::Rrp { l, .. }, false) => Some(P2::new(*l, 0.0)),
        _ => None,
    }
}

impl Dyad {
    /// The same dyad with its known points through `point(link, P)` — P of link a, Q of
    /// link b (`links` = (a, b), [`Linkage::dyad_links`]) — and its lengths through
    /// `length(link, l)`: the one place that takes a dyad apart, for a length or a pivot
    /// changed ([`Linkage::with_length`], the shape search's pivots).
    pub fn remapped(
        &self,
        (a, b): (usize, usize),
        point: impl Fn(usize, Point) -> Point,
        length: impl Fn(usize, f64) -> f64,
    ) -> Dyad {
        match *self {
            Dyad::Rrr { p, l1, q, l2, side } => Dyad::Rrr {
                p: point(a, p),
                l1: length(a, l1),
                q: point(b, q),
                l2: length(b, l2),
                side,
            },
            Dyad::Rrp {
                p,
                l,
                origin,
                angle,
                side,
            } => Dyad::Rrp {
                p: point(a, p),
                l: length(a, l),
                origin,
                angle,
                side,
            },
            Dyad::Rpr { p, q, offset, side } => Dyad::Rpr {
                p: point(a, p),
                q: point(b, q),
                offset,
                side,
            },
        }
    }
}

impl Linkage {
    /// The same linkage with link `link`'s length — the distance to its tip ([`tip_of`]),
    /// `old` now (the crank's |A0 A| is not stored in the dyads: the caller says it) — set to
    /// `new`: the dyad's length, and every point at the old tip in the link's frame (the next
    /// dyad's pivot, a process load) moved to the new one. The link's mass properties stay,
    /// unless `bar` (a uniform bar: its [`Inertia::bar`] of the new length). Checked as any
    /// linkage ([`Linkage::new`]); an error for a link without a tip.
    pub fn with_length(
        &self,
        link: usize,
        old: f64,
        new: f64,
        bar: bool,
    ) -> Result<Linkage, LinkageError> {
        if tip_of(&self.dyads, old, link).is_none() {
            return Err(LinkageError::NoLength { link });
        }
        let tip = P2::new(old, 0.0);
        let moved = |p: Point| match p {
            Point::On { link: l, at } if l == link && at == tip => Point::On {
                link: l,
                at: P2::new(new, 0.0),
            },
            p => p,
        };
        let set = |l: usize, v: f64| if l == link { new } else { v };
        let dyads = self
            .dyads
            .iter()
            .enumerate()
            .map(|(k, d)| d.remapped(Linkage::dyad_links(k), |_, p| moved(p), set))
            .collect();
        let mut inertia = self.inertia.clone();
        if bar {
            inertia[link] = Inertia::bar(inertia[link].mass, new);
        }
        let loads = self
            .loads
            .iter()
            .map(|l| {
                let mut l = l.clone();
                if l.link == link && l.at == tip {
                    l.at = P2::new(new, 0.0);
                }
                l
            })
            .collect();
        Linkage::new(self.pivot, dyads, inertia, self.omega, self.gravity)?.with_loads(loads)
    }
}
