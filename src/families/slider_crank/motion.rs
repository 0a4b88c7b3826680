//! The slider-crank over one turn as the designer draws it (`crate::report::motion`), in the
//! mechanism's frame (the slider on the line y = e, whatever `slider_axis_angle` turns the
//! machine by): crank O→A, rod A→B, the slider at B, the counterweight's centroid, and the
//! slider's guide. Exact kinematics, as the drawing: the series models are approximations of
//! the forces, not of where the parts are. No handles yet (its lengths are not frame points).

use super::model::{Kinematics, SliderCrank};
use super::synth::Design;
use crate::geom::P2;
use crate::report::motion::{xy, Frame, Motion, FRAMES};
use std::f64::consts::TAU;

/// The mechanism `mech` with the design `d` over one turn.
pub fn motion(mech: &SliderCrank, d: &Design) -> Motion {
    let m = SliderCrank {
        kinematics: Kinematics::Exact,
        ..*mech
    };
    let cw = d
        .counterweight_radius_m
        .filter(|_| d.counterweight_unbalance_kgm > 0.0);
    let frames: Vec<Frame> = (0..FRAMES)
        .filter_map(|k| {
            let phi = TAU * k as f64 / FRAMES as f64;
            let st = m.state(phi)?;
            let (a, b) = (st.a[0], P2::new(st.x[0], m.e));
            let beta = phi + d.counterweight_angle_rad;
            Some(Frame {
                theta: phi,
                links: vec![[xy(P2::zeros()), xy(a)], [xy(a), xy(b)], [xy(b), xy(b)]],
                counterweights: cw
                    .map(|r| vec![[r * beta.cos(), r * beta.sin()]])
                    .unwrap_or_default(),
            })
        })
        .collect();
    let xs = frames.iter().map(|f| f.links[2][0][0]);
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let pad = 0.15 * (hi - lo);
    Motion {
        names: vec!["crank".into(), "rod".into(), "slider".into()],
        guides: vec![[[lo - pad, m.e], [hi + pad, m.e]]],
        frames,
        handles: Vec::new(),
    }
}
