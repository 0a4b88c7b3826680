//! The luffing crane over its luffing range as the designer draws it
//! (`crate::report::motion`), in the frame of the boom foot A (x behind the foot, y up): the
//! boom A→D, the jib E→C through D, the tie B→E (a straight guide in its line limit), posed
//! by the synthesised linkage ([`Linkage::pose`]) from maximum to minimum reach and back; the
//! boom counterweight as a steel disc of its mass at its centroid (its size assumed), the
//! slewing axis and the rail; the handles: the foot offset, a given boom length, the
//! counterweight's lever and an inclined rope's sheave.

use super::file::CraneProblem;
use super::model::{synthesize, Boom, Guide, Linkage};
use super::synth::{Outcome, SizingRule};
use crate::geom::P2;
use crate::report::motion::{self as mo, pose, xy, Body, Frame, Handle, Motion, FRAMES};
use std::f64::consts::PI;

/// The thickness of the boom counterweight drawn as a steel disc (its mass only, m).
pub const DISC_THICKNESS: f64 = 1.0;

/// The crane `p`'s design `out` (and its counterweight's first moment u, boom frame, and
/// mass) from maximum to minimum reach and back; `None` without a linkage.
pub fn motion(p: &CraneProblem, out: &Outcome, cw: Option<([f64; 2], f64)>) -> Option<Motion> {
    let l = linkage(p, out)?;
    let cw = cw.filter(|&(_, m)| m > 0.0);
    let [lo, hi] = l.phi_range;
    let frames: Vec<Frame> = (0..FRAMES)
        .filter_map(|k| {
            let t = 1.0 - (1.0 - 2.0 * k as f64 / FRAMES as f64).abs();
            let phi = lo + t * (hi - lo);
            frame(&l, phi, cw)
        })
        .collect();
    let boom: Vec<[f64; 3]> = frames.iter().map(|f| boom_pose(f.theta)).collect();
    let s = &p.scene;
    let (r, h) = (s.foot_offset, s.foot_height);
    let mut handles = vec![Handle::length(
        "mechanism.foot_offset",
        P2::new(r, -h),
        P2::new(1.0, 0.0),
        r,
        "m",
    )];
    if let SizingRule::Given(lc) = s.sizing {
        let x = P2::new(1.0, 0.0);
        handles.push(Handle::length("design.boom_length", lc * x, x, lc, "m").on(boom.clone()));
    }
    let lever = s.balance.and_then(|b| b.counterweight).map(|c| c.lever);
    if let (Some((u, _)), Some(lever)) = (cw, lever) {
        let dir = P2::new(u[0], u[1]).normalize();
        let key = "design.counterweight.lever";
        handles.push(Handle::length(key, lever * dir, dir, lever, "m").on(boom.clone()));
    }
    if let Some(rope) = s.balance.and_then(|b| b.rope) {
        handles.push(Handle::point("mechanism.hoist_rope.sheave", rope.sheave));
    }
    Some(Motion {
        names: vec!["boom".into(), "jib".into(), "tie".into()],
        guides: guides(&l, &frames, r, h),
        frames,
        handles,
        bodies: cw.map(body).into_iter().collect(),
    })
}

/// The synthesised linkage of the design, if it has one.
fn linkage(p: &CraneProblem, out: &Outcome) -> Option<Linkage> {
    let v = &out.design.vars;
    let boom = Boom::levelled(out.design.boom_length_m?, v.angles(), p.scene.level).ok()?;
    synthesize(&boom, v.k1, v.k2).ok().map(|s| s.linkage)
}

/// The boom frame at φ: origin A, x along A→D (D = L_c(−cos φ, sin φ)).
fn boom_pose(phi: f64) -> [f64; 3] {
    pose(P2::zeros(), PI - phi)
}

/// The linkage at the boom angle φ (`None` where it does not assemble).
fn frame(l: &Linkage, phi: f64, cw: Option<([f64; 2], f64)>) -> Option<Frame> {
    let p = l.pose(phi)?;
    let tie = match l.guide {
        Guide::Circle { centre, .. } => [xy(centre), xy(p.e)],
        Guide::Line { .. } => [xy(p.e), xy(p.e)],
    };
    let (s, c) = (PI - phi).sin_cos();
    let centroid = |u: [f64; 2], m: f64| xy(P2::new(c * u[0] - s * u[1], s * u[0] + c * u[1]) / m);
    Some(Frame {
        theta: phi,
        links: vec![[[0.0, 0.0], xy(p.d)], [xy(p.e), xy(p.c)], tie],
        counterweights: cw.map(|(u, m)| vec![centroid(u, m)]).unwrap_or_default(),
        poses: cw.map(|_| vec![boom_pose(phi)]).unwrap_or_default(),
    })
}

/// The boom counterweight (first moment u in the boom frame, mass m) as a steel disc.
fn body((u, m): ([f64; 2], f64)) -> Body {
    let c = P2::new(u[0], u[1]) / m;
    mo::steel_disc("boom counterweight".into(), c, m, DISC_THICKNESS)
}

/// The slewing axis (from the rail up to the foot's height), the rail, and a straight
/// guide of the jib tail over its travel.
fn guides(l: &Linkage, frames: &[Frame], r: f64, h: f64) -> Vec<[[f64; 2]; 2]> {
    let xs = frames
        .iter()
        .flat_map(|f| f.links.iter().flatten().map(|p| p[0]));
    let (x0, x1) = mo::span(xs.chain([r]), 0.05);
    let mut out = vec![[[r, -h], [r, 0.0]], [[x0, -h], [x1, -h]]];
    if let Guide::Line { point, dir } = l.guide {
        let ts = frames
            .iter()
            .map(|f| (P2::new(f.links[1][0][0], f.links[1][0][1]) - point).dot(&dir));
        let (t0, t1) = mo::span(ts, 0.1);
        out.push([xy(point + t0 * dir), xy(point + t1 * dir)]);
    }
    out
}
