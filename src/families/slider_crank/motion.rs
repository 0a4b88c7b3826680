//! The slider-crank over one turn as the designer draws it (`crate::report::motion`), in the
//! mechanism's frame (the slider on the line y = e, whatever `slider_axis_angle` turns the
//! machine by): crank O→A, rod A→B, the slider at B, the counterweight (its plate as
//! designed, else a steel disc of its mass), the slider's guide, and the handles: the crank
//! radius (the crank pin along the crank), the rod length where the file gives it (the slider
//! pin along the rod), the offset (the guide's end across the guide) and a given
//! counterweight radius (the counterweight along its line). Exact kinematics, as the
//! drawing: the series models are approximations of the forces, not of where the parts are.

use super::model::{Kinematics, SliderCrank};
use super::synth::{Design, Scene};
use crate::geom::P2;
use crate::report::motion::{self as mo, pose, xy, Body, BodyKind, Frame, Handle, Motion};
use crate::synth::shape::Sector;
use crate::synth::Var;

/// The scene `s` with the design `d` (and its plate, if designed) over one turn.
/// `rod_given`: the file gives `mechanism.rod_length` (a handle for it at the slider pin).
pub fn motion(s: &Scene, d: &Design, plate: Option<Sector>, rod_given: bool) -> Motion {
    let m = SliderCrank {
        kinematics: Kinematics::Exact,
        ..s.mech
    };
    let body = body(s, d, plate);
    let rc = d
        .counterweight_radius_m
        .filter(|_| d.counterweight_unbalance_kgm > 0.0);
    let beta = d.counterweight_angle_rad;
    let frames: Vec<Frame> = mo::turn()
        .filter_map(|phi| {
            let st = m.state(phi)?;
            let (a, b) = (st.a[0], P2::new(st.x[0], m.e));
            let on_crank = |r: f64| r * P2::new((phi + beta).cos(), (phi + beta).sin());
            Some(Frame {
                theta: phi,
                links: vec![[xy(P2::zeros()), xy(a)], [xy(a), xy(b)], [xy(b), xy(b)]],
                counterweights: rc.map(|r| vec![xy(on_crank(r))]).unwrap_or_default(),
                poses: body.iter().map(|_| pose(P2::zeros(), phi)).collect(),
            })
        })
        .collect();
    let (lo, hi) = mo::span(frames.iter().map(|f| f.links[2][0][0]), 0.15);
    let handles = handles(s, d, &frames, hi, rod_given);
    Motion {
        names: vec!["crank".into(), "rod".into(), "slider".into()],
        guides: vec![[[lo, m.e], [hi, m.e]]],
        frames,
        handles,
        bodies: body.into_iter().collect(),
        marks: Vec::new(),
    }
}

/// The counterweight as it would be built, in the crank's frame: its plate, else a steel
/// disc of its mass at its radius.
fn body(s: &Scene, d: &Design, plate: Option<Sector>) -> Option<Body> {
    let beta = d.counterweight_angle_rad;
    if let (Some(p), Some(spec)) = (plate, s.counterweight.shape) {
        return Some(Body {
            name: "counterweight plate".into(),
            kind: BodyKind::Counterweight,
            loops: mo::annular_sector(p.inner_radius_m, p.outer_radius_m, beta, p.angle_rad),
            note: format!(
                "{:.4} kg: the plate as designed, {:.1} mm of {} kg/m³",
                p.mass_kg,
                spec.thickness * 1e3,
                spec.density
            ),
        });
    }
    let (m, r) = (d.counterweight_mass_kg?, d.counterweight_radius_m?);
    let c = r * P2::new(beta.cos(), beta.sin());
    (m > 0.0).then(|| mo::steel_disc("counterweight".into(), c, m, mo::DISC_THICKNESS))
}

/// The crank radius, the rod length where the file gives it (`rod_given`), the offset and a
/// given counterweight radius as handles.
fn handles(
    s: &Scene,
    d: &Design,
    frames: &[Frame],
    guide_end: f64,
    rod_given: bool,
) -> Vec<Handle> {
    let crank: Vec<[f64; 3]> = frames.iter().map(|f| pose(P2::zeros(), f.theta)).collect();
    let x = P2::new(1.0, 0.0);
    let mut out = vec![
        Handle::length("mechanism.crank_radius", s.mech.r * x, x, s.mech.r, "mm").on(crank.clone()),
    ];
    if rod_given {
        // At the slider pin B, along the rod (its frame: A, towards B).
        let rod: Vec<[f64; 3]> = frames
            .iter()
            .map(|f| {
                let (a, b) = (f.links[1][0], f.links[1][1]);
                pose(P2::new(a[0], a[1]), (b[1] - a[1]).atan2(b[0] - a[0]))
            })
            .collect();
        let l = s.mech.l;
        out.push(Handle::length("mechanism.rod_length", l * x, x, l, "mm").on(rod));
    }
    out.push(
        Handle::length(
            "mechanism.offset",
            P2::new(guide_end, s.mech.e),
            P2::new(0.0, 1.0),
            s.mech.e,
            "mm",
        )
        .signed(),
    );
    if let (Some(Var::Fixed(r)), true) = (s.counterweight.radius, s.counterweight.shape.is_none()) {
        let u = P2::new(
            d.counterweight_angle_rad.cos(),
            d.counterweight_angle_rad.sin(),
        );
        out.push(Handle::length("design.radius", r * u, u, r, "mm").on(crank));
    }
    out
}
