//! The cylinders over one turn as the designer draws them (`crate::report::motion`), seen
//! along the shaft (every throw in the one x–y view, whatever its plane z): each cylinder's
//! crank O→Aᵢ, rod Aᵢ→Bᵢ and piston at Bᵢ (exact kinematics, turned by its bank angle; an
//! articulated cylinder's knuckle arm A→K on its master rod in place of the crank), its
//! cylinder axis as a guide, the crank-web counterweights' centroids at their largest radius,
//! and the shared crank radius as a handle on the first throw.

use super::file::MultiCylinderProblem;
use crate::families::slider_crank::model::{Kinematics, SliderCrank};
use crate::geom::{rot, P2};
use crate::report::motion::{self as mo, pose, xy, Frame, Handle, Motion};
use crate::synth::minimax::var_u;

/// The layout of `p` with the design `x` (the engine's vector) over one turn.
pub fn motion(p: &MultiCylinderProblem, x: &[f64]) -> Motion {
    let cyl = &p.layout.cylinders;
    let exact = |sc: &SliderCrank| SliderCrank {
        kinematics: Kinematics::Exact,
        ..*sc
    };
    let frames: Vec<Frame> = mo::turn()
        .filter_map(|phi| {
            let mut links = Vec::new();
            for c in cyl {
                if let Some(art) = &c.articulated {
                    // The master rod's knuckle arm A→K, the articulated rod K→B, the piston.
                    let st = art.state(c.sc.r, c.sc.l, c.bank, phi + c.phase - art.master_bank)?;
                    let to_world = |v: P2| rot(art.master_bank, v);
                    let (a, k, b) = (
                        to_world(st.c),
                        to_world(st.k[0]),
                        to_world(st.axis * st.s[0]),
                    );
                    links.extend([[xy(a), xy(k)], [xy(k), xy(b)], [xy(b), xy(b)]]);
                    continue;
                }
                let st = exact(&c.sc).state(c.theta(phi))?;
                let (a, b) = (st.a[0], P2::new(st.x[0], c.sc.e));
                let (a, b) = (rot(c.bank, a), rot(c.bank, b));
                links.extend([[xy(P2::zeros()), xy(a)], [xy(a), xy(b)], [xy(b), xy(b)]]);
            }
            Some(Frame {
                theta: phi,
                links,
                counterweights: counterweights(p, x, phi),
                poses: Vec::new(),
            })
        })
        .collect();
    let names = (cyl.iter().enumerate())
        .flat_map(|(i, c)| {
            let first = if c.articulated.is_some() {
                "knuckle"
            } else {
                "crank"
            };
            [
                format!("{first} {}", i + 1),
                format!("rod {}", i + 1),
                format!("piston {}", i + 1),
            ]
        })
        .collect();
    let guides = cyl
        .iter()
        .map(|c| {
            let throw = c.sc.r + c.articulated.map_or(0.0, |a| a.knuckle_radius);
            let (lo, hi) = (c.sc.l - throw, (throw + c.sc.l) * 1.15);
            [
                xy(rot(c.bank, P2::new(lo, c.sc.e))),
                xy(rot(c.bank, P2::new(hi, c.sc.e))),
            ]
        })
        .collect();
    let r = cyl[0].sc.r;
    let crank: Vec<[f64; 3]> = frames
        .iter()
        .map(|f| pose(P2::zeros(), f.theta + cyl[0].phase))
        .collect();
    let x_axis = P2::new(1.0, 0.0);
    Motion {
        names,
        frames,
        guides,
        handles: vec![
            Handle::length("mechanism.crank_radius", r * x_axis, x_axis, r, "mm").on(crank),
        ],
        bodies: Vec::new(),
        marks: Vec::new(),
    }
}

/// Each crank-web counterweight with an unbalance: its centroid at its largest radius, in
/// the direction of its first moment, turned by φ.
fn counterweights(p: &MultiCylinderProblem, x: &[f64], phi: f64) -> Vec<[f64; 2]> {
    (p.rotors.iter().enumerate())
        .filter(|(j, r)| !r.shaft && var_u(*j) + 1 < x.len())
        .filter_map(|(j, r)| {
            let u = P2::new(x[var_u(j)], x[var_u(j) + 1]);
            (u.norm() > 0.0 && u.norm().is_finite())
                .then(|| xy(rot(phi, u / u.norm() * r.radius_max)))
        })
        .collect()
}
