//! The linkage over one crank turn as the designer draws it (`crate::report::motion`):
//! every link as a segment from its reference joint to its tip, the counterweights'
//! centroids, an RRP dyad's slide line, and the frame points the file gives by value — the
//! handles a user drags, each with the key it edits. Shared with the report's position plot
//! ([`segments`]).

use super::file::LinkageScene;
use super::model::{tip_of, Dyad, Linkage, Point, Pose};
use super::synth as ls;
use crate::geom::P2;
use crate::report::motion::{xy, Frame, Handle, Motion, FRAMES};
use std::f64::consts::TAU;

/// Each link of `pose` as (reference joint, tip) (m, world).
pub fn segments(l: &Linkage, crank_length: f64, pose: &Pose) -> Vec<(P2, P2)> {
    (pose.links.iter().enumerate())
        .map(|(i, st)| {
            let a = st.p[0];
            let b = tip_of(l.dyads(), crank_length, i)
                .map(|at| pose.point(&Point::On { link: i, at })[0])
                .unwrap_or(a);
            (a, b)
        })
        .collect()
}

/// The centroids of the design `x`'s counterweights that have a mass, on `pose` (m, world).
pub fn counterweights(sc: &LinkageScene, x: &[f64], pose: &Pose) -> Vec<P2> {
    ls::extras(&sc.counterweights, x)
        .iter()
        .filter(|(_, p)| p[0] > 0.0)
        .map(|(link, p)| {
            let at = P2::new(p[1] / p[0], p[2] / p[0]);
            pose.point(&Point::On { link: *link, at })[0]
        })
        .collect()
}

/// The frame points the file gives by value, with their keys.
fn handles(l: &Linkage) -> Vec<Handle> {
    let h = |key: String, p: P2| Handle {
        key,
        at: [p.x, p.y],
    };
    let mut out = vec![h("mechanism.crank_pivot".into(), l.pivot())];
    for (k, d) in l.dyads().iter().enumerate() {
        let key = |f: &str| format!("mechanism.dyads[{k}].{f}");
        let frame = |f: &str, p: &Point| match p {
            Point::Frame(at) => Some(h(key(f), *at)),
            Point::On { .. } => None,
        };
        match d {
            Dyad::Rrr { p, q, .. } | Dyad::Rpr { p, q, .. } => {
                out.extend(frame("p", p));
                out.extend(frame("q", q));
            }
            Dyad::Rrp { p, origin, .. } => {
                out.extend(frame("p", p));
                out.push(h(key("line_point"), *origin));
            }
        }
    }
    out
}

/// The scene `sc` with the design `x` (none: bare) over one turn.
pub fn motion(sc: &LinkageScene, x: Option<&[f64]>) -> Motion {
    let l = &sc.linkage;
    let frames: Vec<Frame> = (0..FRAMES)
        .filter_map(|k| {
            let theta = TAU * k as f64 / FRAMES as f64;
            let pose = l.pose(theta).ok()?;
            let links = segments(l, sc.crank_length, &pose)
                .into_iter()
                .map(|(a, b)| [xy(a), xy(b)])
                .collect();
            let counterweights = x
                .map(|x| counterweights(sc, x, &pose).into_iter().map(xy).collect())
                .unwrap_or_default();
            Some(Frame {
                theta,
                links,
                counterweights,
            })
        })
        .collect();
    Motion {
        names: sc.link_names.clone(),
        guides: guides(l, &frames),
        frames,
        handles: handles(l),
    }
}

/// Each RRP dyad's slide line, over the span its slider travels (and its line point).
fn guides(l: &Linkage, frames: &[Frame]) -> Vec<[[f64; 2]; 2]> {
    let mut out = Vec::new();
    for (k, d) in l.dyads().iter().enumerate() {
        let Dyad::Rrp { origin, angle, .. } = d else {
            continue;
        };
        let u = P2::new(angle.cos(), angle.sin());
        // The slider is the dyad's second link: 1 + 2k + 1.
        let along = |p: [f64; 2]| (P2::new(p[0], p[1]) - origin).dot(&u);
        let ts = frames
            .iter()
            .filter_map(|f| f.links.get(2 + 2 * k))
            .map(|s| along(s[0]))
            .chain([0.0]);
        let (lo, hi) = ts.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(t), b.max(t))
        });
        let pad = 0.1 * (hi - lo);
        out.push([xy(*origin + u * (lo - pad)), xy(*origin + u * (hi + pad))]);
    }
    out
}
