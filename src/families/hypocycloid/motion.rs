//! The hypocycloidal machine over one turn of the carrier as the designer draws it
//! (`crate::report::motion`): the carrier O→O₁, the crank arm O₁→A on the planet, the rod
//! A→B and the piston B on the x axis, posed by the model ([`Hypocycloid::point_a`],
//! [`Hypocycloid::piston`]); the fixed ring's and the turning planet's pitch circles; the
//! rotating counterweights as steel discs of their masses at their centroids (their size
//! assumed); the handles: the carrier radius R (O₁ along the carrier) and the
//! counterweights' given radii (each along its line on its body).

use super::dynamics::Counterweight;
use super::file::HypocycloidProblem;
use super::model::Hypocycloid;
use super::synth::Design;
use crate::geom::{rot, P2};
use crate::report::motion::{self as mo, pose, xy, Body, BodyKind, Frame, Handle, Motion};

/// The problem `p`'s design `d` with its (carrier, planet) counterweights over one turn;
/// `None` where the model does not assemble.
pub fn motion(
    p: &HypocycloidProblem,
    d: &Design,
    cws: Option<(Counterweight, Counterweight)>,
) -> Option<Motion> {
    let model = Hypocycloid::new(d.lambda, d.theta, p.scene.alpha0).ok()?;
    let big_r = d.carrier_radius_m;
    let cws: Vec<(usize, Counterweight)> = cws
        .map(|(c, q)| vec![(0, c), (1, q)])
        .unwrap_or_default()
        .into_iter()
        .filter(|(_, c)| c.mass > 0.0)
        .collect();
    let frames: Vec<Frame> = mo::turn()
        .map(|phi| frame(&model, big_r, phi, &cws))
        .collect();
    let (lo, hi) = mo::span(frames.iter().map(|f| f.links[3][0][0]), 0.15);
    let mut bodies = vec![
        pitch("ring gear (fixed)", 1.5 * big_r),
        pitch("planet", 0.5 * big_r),
    ];
    bodies.extend(cws.iter().map(|(i, c)| body(*i, c)));
    Some(Motion {
        names: ["carrier", "crank arm", "rod", "piston"]
            .map(String::from)
            .to_vec(),
        guides: vec![[[lo, 0.0], [hi, 0.0]]],
        handles: handles(p, big_r, &cws, &frames),
        frames,
        bodies,
    })
}

/// The frames of the carrier (0) and the planet (1) at φ (the planet's x along O₁A).
fn frames_at(model: &Hypocycloid, big_r: f64, phi: f64) -> [[f64; 3]; 2] {
    let o1 = big_r * P2::new(phi.cos(), phi.sin());
    [pose(P2::zeros(), phi), pose(o1, model.alpha0 - 2.0 * phi)]
}

/// The machine at φ.
fn frame(model: &Hypocycloid, big_r: f64, phi: f64, cws: &[(usize, Counterweight)]) -> Frame {
    let (x, y) = model.point_a(phi);
    let a = big_r * P2::new(x, y);
    let o1 = big_r * P2::new(phi.cos(), phi.sin());
    let b = P2::new(big_r * (model.piston(phi).s_rel + 1.0 / model.lambda), 0.0);
    let f = frames_at(model, big_r, phi);
    let world = |i: usize, c: &Counterweight| {
        let [x, y, t] = f[i];
        xy(P2::new(x, y) + rot(t + c.angle, P2::new(c.radius, 0.0)))
    };
    let mut poses = vec![pose(P2::zeros(), 0.0), f[1]];
    poses.extend(cws.iter().map(|(i, _)| f[*i]));
    Frame {
        theta: phi,
        links: vec![
            [[0.0, 0.0], xy(o1)],
            [xy(o1), xy(a)],
            [xy(a), xy(b)],
            [xy(b), xy(b)],
        ],
        counterweights: cws.iter().map(|(i, c)| world(*i, c)).collect(),
        poses,
    }
}

/// A pitch circle of radius `r` about its frame's origin.
fn pitch(name: &str, r: f64) -> Body {
    Body {
        name: name.into(),
        kind: BodyKind::Pitch,
        loops: vec![mo::circle(P2::zeros(), r)],
        note: format!("pitch circle, radius {:.2} mm", r * 1e3),
    }
}

/// The carrier's (0) or the planet's (1) counterweight as a steel disc in its body's frame.
fn body(i: usize, c: &Counterweight) -> Body {
    let at = c.radius * P2::new(c.angle.cos(), c.angle.sin());
    let name = ["carrier counterweight", "planet counterweight"][i];
    mo::steel_disc(name.into(), at, c.mass, mo::DISC_THICKNESS)
}

/// R along the carrier; each counterweight's given radius along its line on its body.
fn handles(
    p: &HypocycloidProblem,
    big_r: f64,
    cws: &[(usize, Counterweight)],
    frames: &[Frame],
) -> Vec<Handle> {
    let x = P2::new(1.0, 0.0);
    let carrier: Vec<[f64; 3]> = frames.iter().map(|f| pose(P2::zeros(), f.theta)).collect();
    let mut out =
        vec![Handle::length("mechanism.carrier_radius", big_r * x, x, big_r, "mm").on(carrier)];
    if p.dynamics.design.is_some() {
        for (k, (i, c)) in cws.iter().enumerate() {
            let u = P2::new(c.angle.cos(), c.angle.sin());
            let key = [
                "design.rotating.carrier_radius",
                "design.rotating.planet_radius",
            ][*i];
            let placed = frames.iter().map(|f| f.poses[2 + k]).collect();
            out.push(Handle::length(key, c.radius * u, u, c.radius, "mm").on(placed));
        }
    }
    out
}
