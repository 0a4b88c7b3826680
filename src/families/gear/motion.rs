//! The eccentric gear pair over one cycle as the designer draws it
//! (`crate::report::motion`): both pitch curves (and the tooth outlines, with
//! `model.tooth_profiles`) as rigid bodies turning about their pivots — gear 1 clockwise by
//! α1 about O1, gear 2 anticlockwise by the model's α2(α1) ([`Alpha2Map`]) about O2 at the
//! closing centre distance — so that they touch at the pitch point (ρ1(α1), 0); the
//! eccentric O1→C; a given eccentricity as a handle (C along O1C on gear 1) and a stated
//! centre distance as a handle (gear 2's centre along the line of centres O1O2).

use super::model::{Alpha2Map, EccentricCircle};
use super::synth::{GearScene, Outcome};
use crate::geom::{rot, P2};
use crate::report::motion::{self as mo, pose, xy, Body, BodyKind, Frame, Handle, Motion};
use crate::synth::Var;
use std::f64::consts::TAU;

/// The pair of the scene `s` with the outcome `out` over one cycle (n1 turns of gear 1, at
/// most four); `None` without pitch curves.
pub fn motion(s: &GearScene, out: &Outcome) -> Option<Motion> {
    let pc = &out.pitch_curves;
    if pc.gear2_m.is_empty() {
        return None;
    }
    let (o1, o2) = (P2::from(pc.center1_m), P2::from(pc.center2_m));
    let (big_r, e) = (out.design.pitch_radius_m, out.design.eccentricity_m);
    let map = Alpha2Map::new(&EccentricCircle::new(big_r, e).ok()?, (o2 - o1).norm());
    let turns = s.turns_gear1.clamp(1, 4);
    let n = mo::FRAMES * turns as usize;
    let bodies = bodies(out, o1, o2);
    let frames: Vec<Frame> = (0..n)
        .map(|k| {
            let a1 = TAU * turns as f64 * k as f64 / n as f64;
            let (g1, g2) = (pose(o1, -a1), pose(o2, map.alpha2(a1)));
            Frame {
                theta: a1,
                links: vec![
                    [xy(o1), xy(o1 + rot(-a1, P2::new(e, 0.0)))],
                    [xy(o2), xy(o2)],
                ],
                counterweights: Vec::new(),
                poses: bodies.iter().map(|(i, _)| [g1, g2][*i]).collect(),
            }
        })
        .collect();
    let mut handles = Vec::new();
    if let Var::Fixed(_) = s.eccentricity {
        let x = P2::new(1.0, 0.0);
        let placed = frames.iter().map(|f| pose(o1, -f.theta)).collect();
        handles.push(Handle::length("design.eccentricity", e * x, x, e, "mm").on(placed));
    }
    handles.extend(center_distance_handle(s, o1, o2));
    Some(Motion {
        names: vec!["gear 1 (O1→C)".into(), "gear 2".into()],
        frames,
        guides: vec![[xy(o1), xy(line_end(s, o1, o2))]],
        handles,
        bodies: bodies.into_iter().map(|(_, b)| b).collect(),
        marks: Vec::new(),
    })
}

/// A stated `mechanism.center_distance` a12 as a handle: the centre of gear 2 where a12 puts
/// it, O1 + a12·u with u the unit vector O1→O2 of the line of centres, moving along that line
/// (a12 grows by the distance moved, in mm; at least 0.1 mm, the file's least positive value
/// at the handle's step). The pair is built and drawn at its closing centre distance (the
/// model's, `closing_center_distance`), so the handle sits on gear 2's drawn centre where the
/// file states the closing distance (the paper's 148 mm against 147.97 mm: 0.03 mm apart)
/// and shows how far off a stated value is where it is not. `None` where the file leaves
/// a12 out (the closing one is computed, not edited).
fn center_distance_handle(s: &GearScene, o1: P2, o2: P2) -> Option<Handle> {
    let a12 = s.center_distance?;
    let u = (o2 - o1).try_normalize(0.0)?;
    Some(Handle::length("mechanism.center_distance", o1 + a12 * u, u, a12, "mm").at_least(0.1))
}

/// The far end of the line of centres drawn from O1: O2, or the stated centre distance's
/// point where that is farther (its handle then stays on the line).
fn line_end(s: &GearScene, o1: P2, o2: P2) -> P2 {
    let a = (o2 - o1).norm();
    match s.center_distance {
        Some(a12) if a12 > a && a > 0.0 => o1 + (o2 - o1) * (a12 / a),
        _ => o2,
    }
}

/// The pitch curves and tooth outlines in their gears' frames, with their gear (0, 1).
fn bodies(out: &Outcome, o1: P2, o2: P2) -> Vec<(usize, Body)> {
    let pc = &out.pitch_curves;
    let local = |pts: &[[f64; 2]], o: P2| pts.iter().map(|p| xy(P2::from(*p) - o)).collect();
    let curve = |name: &str, loops, kind, note: &str| Body {
        name: name.into(),
        kind,
        loops: vec![loops],
        note: note.into(),
    };
    let mut v = vec![
        (
            0,
            curve(
                "gear 1 pitch curve",
                local(&pc.gear1_m, o1),
                BodyKind::Pitch,
                "a circle of radius R about C",
            ),
        ),
        (
            1,
            curve(
                "gear 2 pitch curve",
                local(&pc.gear2_m, o2),
                BodyKind::Pitch,
                "conjugate to gear 1's",
            ),
        ),
    ];
    if let Some(t) = &out.teeth {
        let outline = |arches: &[super::teeth::Arch]| -> Vec<[f64; 2]> {
            arches
                .iter()
                .flat_map(|a| a.points.iter().map(|p| xy(*p)))
                .collect()
        };
        let note = "cycloidal teeth: epicycloid addenda, hypocycloid dedenda";
        v.push((
            0,
            curve(
                "gear 1 teeth",
                outline(&t.profiles.gear1),
                BodyKind::Part,
                note,
            ),
        ));
        v.push((
            1,
            curve(
                "gear 2 teeth",
                outline(&t.profiles.gear2),
                BodyKind::Part,
                note,
            ),
        ));
    }
    v
}
