//! The hypocycloidal machine over one turn of the carrier as the designer draws it
//! (`crate::report::motion`): the carrier O→O₁, the crank arm O₁→A on the planet, the rod
//! A→B and the piston B on the x axis, posed by the model ([`Hypocycloid::point_a`],
//! [`Hypocycloid::piston`]); the fixed ring's and the turning planet's pitch circles; the
//! rotating counterweights as steel discs of their masses at their centroids (their size
//! assumed); where the file places them (`[mechanism.lanchester]`), the Lanchester shafts
//! and their masses turning at ±iω ([`lanchester_masses`], also in the report's drawing);
//! the handles: the carrier radius R (O₁ along the carrier) and the counterweights' given
//! radii (each along its line on its body).

use super::dynamics::{Counterweight, ShaftLayout};
use super::file::HypocycloidProblem;
use super::model::{Hypocycloid, LanchesterPair};
use super::synth::Design;
use crate::geom::{rot, P2};
use crate::report::motion::{self as mo, pose, xy, Body, BodyKind, Frame, Handle, Motion};
use std::f64::consts::PI;

/// One mass of a Lanchester pair as it would be built: a steel half-disc (the usual
/// balancer web) of [`mo::DISC_THICKNESS`] and [`mo::STEEL_DENSITY`] (assumed: the model
/// knows only its static moment m′r′) on its shaft, turning with it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShaftMass {
    /// The order i of its pair.
    pub order: usize,
    /// +1 on the co-rotating shaft (turning at +iω with the carrier), −1 on the
    /// counter-rotating one.
    pub sense: f64,
    /// The shaft's centre (m, the frame): (±d/2, e), as the model takes the couples
    /// ([`ShaftLayout::couple_direct`]).
    pub centre: P2,
    /// The mass's direction at φ = 0 (rad): the pair's `phase_co` or `phase_counter`.
    pub phase: f64,
    /// m′r′, the model's static moment of each mass (kg·m).
    pub static_moment: f64,
    /// ρ, the half-disc's radius (m): m′r′ = σ·(2/3)ρ³ with σ = ρ_steel t (a half-disc's
    /// first moment about its diameter is 2ρ³/3 per unit area density).
    pub radius: f64,
    /// Its mass σπρ²/2 (kg); its centroid is 4ρ/(3π) from the shaft.
    pub mass: f64,
}

impl ShaftMass {
    /// The direction of the mass from its shaft at the carrier angle φ: ±iφ + phase, the
    /// angle of its centrifugal force in [`LanchesterPair::force`].
    pub fn angle(&self, phi: f64) -> f64 {
        self.sense * self.order as f64 * phi + self.phase
    }

    /// Its centroid at φ (m, the frame).
    pub fn centroid(&self, phi: f64) -> P2 {
        let a = self.angle(phi);
        self.centre + 4.0 * self.radius / (3.0 * PI) * P2::new(a.cos(), a.sin())
    }

    /// Its outline in its own frame (x axis towards the mass): the half-disc of radius ρ.
    pub fn outline(&self) -> Vec<Vec<[f64; 2]>> {
        mo::annular_sector(0.0, self.radius, 0.0, PI)
    }
}

/// Every pair's two masses, co-rotating then counter-rotating, order by order, on the
/// shafts `layout` places: the co-rotating shaft at (d/2, e), the counter-rotating one at
/// (−d/2, e), e the offset from the piston line and d the spacing. The file gives no place
/// along the piston line (no figure depends on it): the shafts are centred about the
/// carrier's axis O, where the model takes their couples. Every pair shares the one layout,
/// so each shaft carries a mass of every order (in planes of their own along the shaft,
/// drawn over each other). A pair with no static moment has none.
pub fn lanchester_masses(layout: &ShaftLayout, pairs: &[LanchesterPair]) -> Vec<ShaftMass> {
    let sigma = mo::STEEL_DENSITY * mo::DISC_THICKNESS;
    let shafts = [
        (1.0, P2::new(0.5 * layout.spacing, layout.offset)),
        (-1.0, P2::new(-0.5 * layout.spacing, layout.offset)),
    ];
    shafts
        .iter()
        .flat_map(|&(sense, centre)| {
            pairs
                .iter()
                .filter(|p| p.static_moment > 0.0)
                .map(move |p| {
                    let radius = (1.5 * p.static_moment / sigma).cbrt();
                    ShaftMass {
                        order: p.order,
                        sense,
                        centre,
                        phase: if sense > 0.0 {
                            p.phase_co
                        } else {
                            p.phase_counter
                        },
                        static_moment: p.static_moment,
                        radius,
                        mass: 0.5 * sigma * PI * radius * radius,
                    }
                })
        })
        .collect()
}

/// A shaft's speed as written, `+ω`, `−2ω` (`sense` > 0: co-rotating).
pub fn speed_name(order: usize, sense: f64) -> String {
    let sign = if sense > 0.0 { "+" } else { "−" };
    match order {
        1 => format!("{sign}ω"),
        i => format!("{sign}{i}ω"),
    }
}

/// A Lanchester mass as a body in its own frame (placed per frame at its shaft, turned by
/// [`ShaftMass::angle`]).
fn shaft_body(m: &ShaftMass) -> Body {
    Body {
        name: format!(
            "Lanchester mass, order {} ({})",
            m.order,
            speed_name(m.order, m.sense)
        ),
        kind: BodyKind::Counterweight,
        loops: m.outline(),
        note: format!(
            "m′r′ = {:.4e} kg·m (the model's); drawn as a steel half-disc ({} kg/m³) {:.0} mm thick, radius {:.1} mm, {:.3} kg (assumed)",
            m.static_moment,
            mo::STEEL_DENSITY,
            mo::DISC_THICKNESS * 1e3,
            m.radius * 1e3,
            m.mass
        ),
    }
}

/// The problem `p`'s design `d` with its (carrier, planet) counterweights over one turn;
/// `None` where the model does not assemble.
pub fn motion(
    p: &HypocycloidProblem,
    d: &Design,
    cws: Option<(Counterweight, Counterweight)>,
    pairs: &[LanchesterPair],
) -> Option<Motion> {
    let model = Hypocycloid::new(d.lambda, d.theta, p.scene.alpha0).ok()?;
    let big_r = d.carrier_radius_m;
    let cws: Vec<(usize, Counterweight)> = cws
        .map(|(c, q)| vec![(0, c), (1, q)])
        .unwrap_or_default()
        .into_iter()
        .filter(|(_, c)| c.mass > 0.0)
        .collect();
    let shafts = p
        .dynamics
        .shafts
        .map(|l| lanchester_masses(&l, pairs))
        .unwrap_or_default();
    let frames: Vec<Frame> = mo::turn()
        .map(|phi| frame(&model, big_r, phi, &cws, &shafts))
        .collect();
    let (lo, hi) = mo::span(frames.iter().map(|f| f.links[3][0][0]), 0.15);
    let mut bodies = vec![
        pitch("ring gear (fixed)", 1.5 * big_r),
        pitch("planet", 0.5 * big_r),
    ];
    bodies.extend(cws.iter().map(|(i, c)| body(*i, c)));
    bodies.extend(shafts.iter().map(shaft_body));
    let mut names: Vec<String> = ["carrier", "crank arm", "rod", "piston"]
        .map(String::from)
        .to_vec();
    names.extend(shaft_names(&shafts));
    Some(Motion {
        names,
        guides: vec![[[lo, 0.0], [hi, 0.0]]],
        handles: handles(p, big_r, &cws, &frames),
        frames,
        bodies,
        marks: Vec::new(),
    })
}

/// The frames of the carrier (0) and the planet (1) at φ (the planet's x along O₁A).
fn frames_at(model: &Hypocycloid, big_r: f64, phi: f64) -> [[f64; 3]; 2] {
    let o1 = big_r * P2::new(phi.cos(), phi.sin());
    [pose(P2::zeros(), phi), pose(o1, model.alpha0 - 2.0 * phi)]
}

/// The Lanchester shafts' names, their speeds (`+ω, +2ω`: short, as the page writes a
/// name beside its joint), co-rotating then counter-rotating, one per shaft with masses
/// (none without).
fn shaft_names(shafts: &[ShaftMass]) -> Vec<String> {
    [1.0, -1.0]
        .iter()
        .filter_map(|&sense| {
            let speeds: Vec<String> = (shafts.iter())
                .filter(|m| m.sense == sense)
                .map(|m| speed_name(m.order, m.sense))
                .collect();
            (!speeds.is_empty()).then(|| speeds.join(", "))
        })
        .collect()
}

/// The machine at φ; each Lanchester shaft a link without a tip at its centre (as many as
/// [`shaft_names`] names), each of its masses a body turned by [`ShaftMass::angle`].
fn frame(
    model: &Hypocycloid,
    big_r: f64,
    phi: f64,
    cws: &[(usize, Counterweight)],
    shafts: &[ShaftMass],
) -> Frame {
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
    poses.extend(shafts.iter().map(|m| pose(m.centre, m.angle(phi))));
    let mut links = vec![
        [[0.0, 0.0], xy(o1)],
        [xy(o1), xy(a)],
        [xy(a), xy(b)],
        [xy(b), xy(b)],
    ];
    for sense in [1.0, -1.0] {
        if let Some(m) = shafts.iter().find(|m| m.sense == sense) {
            links.push([xy(m.centre), xy(m.centre)]);
        }
    }
    Frame {
        theta: phi,
        links,
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
