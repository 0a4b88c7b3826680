//! The linkage over one crank turn as the designer draws it (`crate::report::motion`):
//! every link as a segment from its reference joint to its tip, a link drawn in a DXF file
//! (`outline`) as drawn, the counterweights' centroids and bodies (a plate as cut, a drawn
//! outline as drawn, else the annular sector with their mass, centroid and inertia, else a
//! steel disc), an RRP dyad's slide line, and the points the file gives by value — the
//! handles a user drags, each with the key it edits: the frame points, a given
//! counterweight's centroid on its link, and a drawn outline's given `origin` (the drawing
//! point at the link's reference joint, in the drawing's frame). Shared with the report's
//! position plot ([`segments`]).

use super::file::{DrawnLink, LinkageProblem, LinkageScene};
use super::model::{tip_of, Dyad, Linkage, Point, Pose};
use super::synth as ls;
use crate::geom::plate::Realised;
use crate::geom::{rot, P2};
use crate::problem::outline::Placement;
use crate::report::motion::{self as mo, pose, xy, Body, BodyKind, Frame, Handle, Mark, Motion};
use crate::synth::Var;
use std::f64::consts::TAU;

/// Per counterweight: its annular sector (rᵢ, rₒ, θ) and its plate, where it has them.
pub type Bodies<'a> = (&'a [Option<(f64, f64, f64)>], &'a [Option<Realised>]);

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
    let h = |key: String, p: P2| Handle::point(key, p);
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

/// The scene `sc` with the design `x` (none: bare) and its counterweights' `bodies` over one
/// turn.
pub fn motion(sc: &LinkageScene, x: Option<&[f64]>, bodies: Bodies) -> Motion {
    let l = &sc.linkage;
    let mut cws = link_bodies(sc);
    cws.extend(
        x.map(|x| counterweight_bodies(sc, x, bodies))
            .unwrap_or_default(),
    );
    let mut placed: Vec<Vec<[f64; 3]>> = vec![Vec::new(); sc.link_names.len()];
    let frames: Vec<Frame> = mo::turn()
        .filter_map(|theta| {
            let pose = l.pose(theta).ok()?;
            let links = segments(l, sc.crank_length, &pose)
                .into_iter()
                .map(|(a, b)| [xy(a), xy(b)])
                .collect();
            let counterweights = x
                .map(|x| counterweights(sc, x, &pose).into_iter().map(xy).collect())
                .unwrap_or_default();
            let at = |i: usize| pose_of(&pose, i);
            for (i, p) in placed.iter_mut().enumerate() {
                p.push(at(i));
            }
            Some(Frame {
                theta,
                links,
                counterweights,
                poses: cws.iter().map(|(i, _)| at(*i)).collect(),
            })
        })
        .collect();
    let mut handles = handles(l);
    handles.extend(centroid_handles(sc, &placed));
    handles.extend(origin_handles(sc, &placed));
    Motion {
        names: sc.link_names.clone(),
        guides: guides(l, &frames),
        frames,
        handles,
        bodies: cws.into_iter().map(|(_, b)| b).collect(),
        marks: Vec::new(),
    }
}

/// The kinematic requirement of `p` drawn over its mechanism ([`Mark`]): a path's tracer path
/// over the turn, its precision points and the tracer point on its moving link; a function's
/// rocker tip at its crank angles; a swing's or a stroke's output point (the rocker's tip,
/// the slider's pin) over the turn; a dwell's over its window, with the crank's tip over that
/// window. None without a requirement.
pub fn requirement_marks(p: &LinkageProblem) -> Vec<Mark> {
    let (sc, deg) = (&p.scene, f64::to_degrees);
    let name = |i: usize| sc.link_names.get(i).cloned().unwrap_or_default();
    // The whole turn, closed (the last point the first again).
    let turn: Vec<f64> = mo::turn().chain([TAU]).collect();
    let mut marks = Vec::new();
    if let Some(path) = &p.path {
        let label = format!("path of {}'s tracer", name(path.link));
        marks.push(Mark::trace(label, trace(sc, path.link, path.at, &turn)));
        // The tracer itself, moving with its link (the frames' angles).
        let poses = (mo::turn().filter_map(|t| sc.linkage.pose(t).ok()))
            .map(|pose| pose_of(&pose, path.link))
            .collect();
        let label = format!("{}'s tracer point", name(path.link));
        marks.push(Mark::tracer(label, path.at, poses));
        let label = format!(
            "precision points Q1–Q{}, within {:.3} mm",
            path.points.len(),
            path.max_error * 1e3
        );
        marks.push(Mark::points(
            label,
            path.points.iter().map(|q| xy(*q)).collect(),
        ));
    }
    if let Some(f) = &p.function {
        let at = output_point(sc, f.link);
        let label = format!(
            "{}'s tip at the function's {} crank angles",
            name(f.link),
            f.crank_angles.len()
        );
        marks.push(Mark::points(label, trace(sc, f.link, at, &f.crank_angles)));
    }
    if let Some(s) = &p.swing {
        let label = format!("swing of {}: {:.3}° to meet", name(s.link), deg(s.angle));
        marks.push(Mark::trace(
            label,
            trace(sc, s.link, output_point(sc, s.link), &turn),
        ));
    }
    if let Some(s) = &p.stroke {
        let label = format!(
            "stroke of {}: {:.3} mm to meet",
            name(s.link),
            s.stroke * 1e3
        );
        marks.push(Mark::trace(label, trace(sc, s.link, P2::zeros(), &turn)));
    }
    if let Some(d) = &p.dwell {
        let window: Vec<f64> = (0..=64)
            .map(|k| d.from + (d.to - d.from) * k as f64 / 64.0)
            .collect();
        let label = format!(
            "dwell of {} over θ = {:.0}°–{:.0}°",
            name(d.link),
            deg(d.from),
            deg(d.to)
        );
        marks.push(Mark::trace(
            label,
            trace(sc, d.link, output_point(sc, d.link), &window),
        ));
        // Where the crank is while the output dwells: its tip over the same window.
        let label = format!("crank over θ = {:.0}°–{:.0}°", deg(d.from), deg(d.to));
        marks.push(Mark::trace(
            label,
            trace(sc, 0, output_point(sc, 0), &window),
        ));
    }
    marks
}

/// The point that carries a link's output: its tip where it has one (a rocker's), else its
/// reference joint (a slider's pin), in its frame.
fn output_point(sc: &LinkageScene, link: usize) -> P2 {
    tip_of(sc.linkage.dyads(), sc.crank_length, link).unwrap_or_else(P2::zeros)
}

/// The point `at` of link `link` (its frame) at the crank angles `thetas` where the linkage
/// assembles (m, world).
fn trace(sc: &LinkageScene, link: usize, at: P2, thetas: &[f64]) -> Vec<[f64; 2]> {
    (thetas.iter())
        .filter_map(|&t| sc.linkage.pose(t).ok())
        .map(|pose| xy(pose.point(&Point::On { link, at })[0]))
        .collect()
}

/// Link `i`'s frame on `pose`: its reference joint and its axis's angle.
fn pose_of(p: &Pose, i: usize) -> [f64; 3] {
    let st = &p.links[i];
    pose(st.p[0], st.e.y.atan2(st.e.x))
}

/// A counterweight given by mass and centroid: its centroid on its link as a handle.
fn centroid_handles(sc: &LinkageScene, placed: &[Vec<[f64; 3]>]) -> Vec<Handle> {
    (sc.counterweights.iter().enumerate())
        .filter(|(_, c)| c.drawing.is_none() && matches!(c.mass, Var::Fixed(_)))
        .filter_map(|(j, c)| {
            let (at, _) = c.given?;
            let key = format!("design.counterweights[{j}].centroid");
            Some(Handle::point(key, at).on(placed[c.link].clone()))
        })
        .collect()
}

/// A drawn outline's given `origin` as a handle: the drawing point `origin` is the body's
/// reference point, so the handle sits at its link's reference joint; it is in the
/// drawing's own frame as placed on the link ([`Placement::drawing_frame`]: the link's
/// frame moved by Rot(−angle)(−origin) and turned by −angle), where its `at` is `origin`'s
/// value. A drop at p in that frame writes `origin = p`: the drawing point under the
/// pointer becomes the reference point, `origin` changes by the distance moved (in the
/// drawing's axes: the link's where `angle` is 0), and the re-solve moves the drawn part by
/// as much the other way, bringing that point to the joint. A ring handle
/// ([`Handle::as_ring`]): the joint is often a pivot's handle too. `None` where the file
/// leaves `origin` out. Links' (`mechanism.links.NAME.outline.origin`) first, then
/// counterweights' (`design.counterweights[j].outline.origin`).
fn origin_handles(sc: &LinkageScene, placed: &[Vec<[f64; 3]>]) -> Vec<Handle> {
    let links = (sc.drawn_links.iter().enumerate()).filter_map(|(i, d)| {
        let d: &DrawnLink = d.as_ref()?;
        let key = format!("mechanism.links.{}.outline.origin", sc.link_names[i]);
        Some((key, i, d.placement))
    });
    let cws = (sc.counterweights.iter().enumerate()).filter_map(|(j, c)| {
        let key = format!("design.counterweights[{j}].outline.origin");
        Some((key, c.link, c.placement?))
    });
    links
        .chain(cws)
        .filter_map(|(key, i, pl)| {
            let origin = pl.origin?;
            let poses = placed[i].iter().map(|p| drawing_pose(*p, pl)).collect();
            Some(Handle::point(key, origin).on(poses).as_ring())
        })
        .collect()
}

/// The pose of a drawing placed by `pl` on a link at the pose `link` ([x, y, ψ]):
/// [P + Rot(ψ) t, ψ + β] with (t, β) = [`Placement::drawing_frame`].
fn drawing_pose(link: [f64; 3], pl: Placement) -> [f64; 3] {
    let (t, beta) = pl.drawing_frame();
    let at = P2::new(link[0], link[1]) + rot(link[2], t);
    pose(at, link[2] + beta)
}

/// Each link drawn in a DXF file (`outline`) as drawn, in its frame, with its index.
fn link_bodies(sc: &LinkageScene) -> Vec<(usize, Body)> {
    (sc.drawn_links.iter().enumerate())
        .filter_map(|(i, d)| {
            let d = d.as_ref()?;
            let name = &sc.link_names[i];
            Some((
                i,
                Body {
                    name: format!("{name} (drawn)"),
                    kind: BodyKind::Part,
                    loops: mo::polylines(&d.loops),
                    note: format!("as drawn in its outline (mechanism.links.{name}.outline)"),
                },
            ))
        })
        .collect()
}

/// Each counterweight of the design `x` with a mass as the body to build, in its link's
/// frame about the joint, with the link's index.
fn counterweight_bodies(
    sc: &LinkageScene,
    x: &[f64],
    (sectors, plates): Bodies,
) -> Vec<(usize, Body)> {
    let mut out = Vec::new();
    for (j, (link, m)) in ls::extras(&sc.counterweights, x).iter().enumerate() {
        if m[0] <= 0.0 {
            continue;
        }
        let spec = &sc.counterweights[j];
        let c = P2::new(m[1] / m[0], m[2] / m[0]);
        let name = format!("counterweight on {}", spec.link_name);
        let body = |loops, note: String| Body {
            name: name.clone(),
            kind: BodyKind::Counterweight,
            loops,
            note: format!("{:.4} kg: {note}", m[0]),
        };
        let plate = plates.get(j).copied().flatten();
        let b = if let Some(d) = &spec.drawing {
            body(mo::polylines(d), "as drawn in its outline".into())
        } else if let Some(p) = plate {
            body(mo::polylines(&p.shape.loops()), plate_note(spec))
        } else if let Some((ri, ro, th)) = sectors.get(j).copied().flatten().filter(|s| s.1 > 0.0) {
            let note = "the annular sector with its mass, centroid and inertia (an equivalent)";
            body(mo::annular_sector(ri, ro, c.y.atan2(c.x), th), note.into())
        } else {
            mo::steel_disc(name.clone(), c, m[0], mo::DISC_THICKNESS)
        };
        out.push((*link, b));
    }
    out
}

/// A plate's note: its thickness and material.
fn plate_note(spec: &super::file::CounterweightSpec) -> String {
    match (spec.thickness, spec.density) {
        (Some(t), Some(rho)) => format!("the plate to cut, {:.1} mm of {rho} kg/m³", t * 1e3),
        _ => "the plate to cut".into(),
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
