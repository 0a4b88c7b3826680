//! The linkage over one crank turn as the designer draws it (`cwsynth serve`, issue 35):
//! every link as a segment from its reference joint to its tip, the counterweights'
//! centroids, and the frame points the file gives by value — the handles a user drags, each
//! with the key it edits. Shared with the report's position plot ([`segments`]).

use super::file::LinkageScene;
use super::model::{tip_of, Dyad, Linkage, Point, Pose};
use super::synth as ls;
use crate::geom::P2;
use serde::Serialize;
use std::f64::consts::TAU;

/// Frames of one turn the designer animates.
pub const FRAMES: usize = 72;

/// One crank angle: the links' segments and the counterweights' centroids (m, world).
#[derive(Debug, Clone, Serialize)]
pub struct Frame {
    /// θ (rad).
    pub theta: f64,
    /// Each link's [reference joint, tip] (a link without a tip: a point, both ends equal).
    pub links: Vec<[[f64; 2]; 2]>,
    /// Each counterweight with a mass: its centroid.
    pub counterweights: Vec<[f64; 2]>,
}

/// A frame point the file gives by value: dragging it edits `key` (a point `[x, y]`).
#[derive(Debug, Clone, Serialize)]
pub struct Handle {
    /// The dotted key (`mechanism.crank_pivot`, `mechanism.dyads[1].q`, …).
    pub key: String,
    /// Where it is (m, world).
    pub at: [f64; 2],
}

/// The linkage over one turn: [`FRAMES`] frames (angles where it does not assemble left
/// out), the handles and the link names (crank first).
#[derive(Debug, Clone, Serialize)]
pub struct Motion {
    /// The links' names, in the frames' order.
    pub names: Vec<String>,
    /// The frames.
    pub frames: Vec<Frame>,
    /// The frame points to drag.
    pub handles: Vec<Handle>,
}

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
    let xy = |p: P2| [p.x, p.y];
    let frames = (0..FRAMES)
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
        frames,
        handles: handles(l),
    }
}
