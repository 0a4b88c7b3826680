//! The luffing crane over its luffing range as the designer draws it
//! (`crate::report::motion`), in the frame of the boom foot A (x behind the foot, y up): the
//! boom A→D, the jib E→C through D, the tie B→E (a straight guide in its line limit), posed
//! by the synthesised linkage ([`Linkage::pose`]) from maximum to minimum reach and back; the
//! boom counterweight as a steel disc of its mass at its centroid (its size assumed) — on the
//! boom, hung below its suspension point on its hanger, or on its lever with the rod to the
//! boom —, the slewing axis and the rail; the handles: the foot offset, a given boom length,
//! the counterweight's lever (on the boom) and an inclined rope's sheave.

use super::file::CraneProblem;
use super::lever::{boom_point_at, LeverLinkage};
use super::model::{synthesize, Boom, Guide, Linkage};
use super::synth::{Outcome, SizingRule};
use crate::geom::P2;
use crate::report::motion::{self as mo, pose, xy, Body, Frame, Handle, Motion, FRAMES};
use std::f64::consts::PI;

/// The thickness of the boom counterweight drawn as a steel disc (its mass only, m).
pub const DISC_THICKNESS: f64 = 1.0;

/// The designed counterweight as the motion view moves it: its first moment u and mass m,
/// and how it hangs on the boom system (`balance::CounterweightKind`).
#[derive(Debug, Clone, Copy)]
pub enum CounterweightMotion {
    /// On the boom: u in the boom frame about A.
    Boom { u: [f64; 2], m: f64 },
    /// Hung: u = m·(suspension point) in the boom frame, the centroid `hang` below it.
    Hanging { u: [f64; 2], m: f64, hang: f64 },
    /// On the lever: u about its pivot O in the lever frame, the lever posed by its four-bar.
    Lever {
        u: [f64; 2],
        m: f64,
        lever: LeverLinkage,
    },
}

impl CounterweightMotion {
    /// u and m.
    fn moment_and_mass(&self) -> ([f64; 2], f64) {
        match *self {
            Self::Boom { u, m } | Self::Hanging { u, m, .. } | Self::Lever { u, m, .. } => (u, m),
        }
    }

    /// The links it adds to the linkage's (names in frame order).
    fn link_names(&self) -> Vec<String> {
        match self {
            Self::Boom { .. } => vec![],
            Self::Hanging { .. } => vec!["boom tail".into(), "hanger".into()],
            Self::Lever { .. } => vec!["lever".into(), "rod".into()],
        }
    }
}

/// The crane `p`'s design `out` (and its counterweight, if designed) from maximum to minimum
/// reach and back; `None` without a linkage.
pub fn motion(p: &CraneProblem, out: &Outcome, cw: Option<CounterweightMotion>) -> Option<Motion> {
    let l = linkage(p, out)?;
    let cw = cw.filter(|c| c.moment_and_mass().1 > 0.0);
    let [lo, hi] = l.phi_range;
    let frames: Vec<Frame> = (0..FRAMES)
        .filter_map(|k| {
            let t = 1.0 - (1.0 - 2.0 * k as f64 / FRAMES as f64).abs();
            let phi = lo + t * (hi - lo);
            frame(&l, phi, cw.as_ref())
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
    if let (Some(CounterweightMotion::Boom { u, .. }), Some(lever)) = (cw, lever) {
        let dir = P2::new(u[0], u[1]).normalize();
        let key = "design.counterweight.lever";
        handles.push(Handle::length(key, lever * dir, dir, lever, "m").on(boom.clone()));
    }
    if let Some(rope) = s.balance.and_then(|b| b.rope) {
        handles.push(Handle::point("mechanism.hoist_rope.sheave", rope.sheave));
    }
    let mut names: Vec<String> = vec!["boom".into(), "jib".into(), "tie".into()];
    names.extend(cw.iter().flat_map(|c| c.link_names()));
    Some(Motion {
        names,
        guides: guides(&l, &frames, r, h),
        frames,
        handles,
        bodies: cw.map(body).into_iter().collect(),
        marks: Vec::new(),
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
fn frame(l: &Linkage, phi: f64, cw: Option<&CounterweightMotion>) -> Option<Frame> {
    let p = l.pose(phi)?;
    let tie = match l.guide {
        Guide::Circle { centre, .. } => [xy(centre), xy(p.e)],
        Guide::Line { .. } => [xy(p.e), xy(p.e)],
    };
    let mut f = Frame {
        theta: phi,
        links: vec![[[0.0, 0.0], xy(p.d)], [xy(p.e), xy(p.c)], tie],
        counterweights: Vec::new(),
        poses: Vec::new(),
    };
    if let Some(cw) = cw {
        counterweight_in(&mut f, phi, cw)?;
    }
    Some(f)
}

/// The counterweight at the boom angle φ: its centroid, its body's pose and the links it
/// hangs on. A boom counterweight turns with the boom (its body in the boom frame); a hung
/// one hangs `hang` below its suspension point u/m (boom frame, on the boom's tail from A),
/// and a lever's sits at
/// O + R(ψ)·u/m on the lever posed by its four-bar (their bodies translate).
fn counterweight_in(f: &mut Frame, phi: f64, cw: &CounterweightMotion) -> Option<()> {
    let on_boom = |u: [f64; 2], m: f64| boom_point_at(u, phi) / m;
    let centroid = match *cw {
        CounterweightMotion::Boom { u, m } => {
            f.poses.push(boom_pose(phi));
            on_boom(u, m)
        }
        CounterweightMotion::Hanging { u, m, hang } => {
            let top = on_boom(u, m);
            let g = top - P2::new(0.0, hang);
            f.links.push([[0.0, 0.0], xy(top)]);
            f.links.push([xy(top), xy(g)]);
            f.poses.push(pose(g, 0.0));
            g
        }
        CounterweightMotion::Lever { u, m, lever } => {
            let lp = lever.pose(phi)?;
            let g = lever.pivot + LeverLinkage::world_moment(&lp, u) / m;
            f.links.push([xy(lever.pivot), xy(lp.l)]);
            f.links.push([xy(lp.l), xy(lp.k)]);
            f.poses.push(pose(g, 0.0));
            g
        }
    };
    f.counterweights.push(xy(centroid));
    Some(())
}

/// The counterweight as a steel disc of its mass: in the boom frame at u/m for one on the
/// boom, about its own centroid (its frame's origin) for a hung or lever one.
fn body(cw: CounterweightMotion) -> Body {
    match cw {
        CounterweightMotion::Boom { u, m } => {
            let c = P2::new(u[0], u[1]) / m;
            mo::steel_disc("boom counterweight".into(), c, m, DISC_THICKNESS)
        }
        CounterweightMotion::Hanging { m, .. } => {
            mo::steel_disc("hung counterweight".into(), P2::zeros(), m, DISC_THICKNESS)
        }
        CounterweightMotion::Lever { m, .. } => {
            mo::steel_disc("lever counterweight".into(), P2::zeros(), m, DISC_THICKNESS)
        }
    }
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
