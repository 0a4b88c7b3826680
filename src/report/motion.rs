//! The mechanism over one turn as the designer draws it (`cwsynth serve`, issue 35): the
//! data every family with a drawing fills the same way — the moving links as segments per
//! crank angle, the counterweights' centroids, the rigid bodies (the counterweights as they
//! would be built, a gear's pitch curve) outlined in their own frames and placed per frame,
//! the frame's fixed lines, and the handles a user drags, each with the key of the problem
//! file it edits. SI (m, rad), the world frame.

use crate::geom::outline::Edge;
use crate::geom::P2;
use serde::Serialize;
use std::f64::consts::TAU;

/// Frames of one turn the designer animates.
pub const FRAMES: usize = 72;

/// The density of a counterweight drawn as a steel disc where the file gives only its mass
/// and centroid (kg/m³).
pub const STEEL_DENSITY: f64 = 7850.0;

/// The thickness of a machine's counterweight drawn as a steel disc (m): the slider-crank's,
/// the linkage's and the hypocycloid's (a crane's, much larger, is its own).
pub const DISC_THICKNESS: f64 = 0.02;

/// One crank angle: the links' segments, the counterweights' centroids, the bodies' places.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Frame {
    /// θ (rad).
    pub theta: f64,
    /// Each link's [reference joint, tip] (a link without a tip: both ends equal).
    pub links: Vec<[[f64; 2]; 2]>,
    /// Each counterweight with a mass: its centroid.
    pub counterweights: Vec<[f64; 2]>,
    /// Each body of [`Motion::bodies`]: where its frame is, [x, y, angle] (its outline's
    /// point p is at (x, y) + p turned by the angle).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub poses: Vec<[f64; 3]>,
}

/// What a body is, for the page's style and legend.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyKind {
    /// A counterweight as it would be built (a plate, a drawn outline, an assumed disc).
    Counterweight,
    /// A pitch curve (a gear's, a planet's, a ring's): a line, not filled.
    Pitch,
    /// A part's outline (a gear's teeth, a linkage's link drawn in a DXF file).
    Part,
}

/// A rigid outline drawn in every frame at its pose ([`Frame::poses`]).
#[derive(Debug, Clone, Serialize)]
pub struct Body {
    /// What it is (`counterweight on crank`, `gear 1`).
    pub name: String,
    /// Its kind.
    pub kind: BodyKind,
    /// Closed loops in its own frame (m); several: a plate with a hole (even-odd filled).
    pub loops: Vec<Vec<[f64; 2]>>,
    /// Where its shape comes from (the page's tooltip): `plate 20 mm of 7850 kg/m³`, …
    pub note: String,
}

/// How a drag writes a scalar key: the value grows along `axis` from the handle's `at`.
#[derive(Debug, Clone, Serialize)]
pub struct Scalar {
    /// Unit direction along which the value grows, in the handle's frame.
    pub axis: [f64; 2],
    /// The key's value at `at`, in `unit`.
    pub value: f64,
    /// Change of the value per metre moved along `axis`.
    pub per_metre: f64,
    /// The unit written after the number (`mm`, `m`; empty: a bare number).
    pub unit: String,
    /// The written value's resolution (in `unit`).
    pub step: f64,
    /// The least value allowed, if any (a drag below it writes it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
}

/// A point a user drags: dragging it edits `key` — a point `[x, y]` (`"… mm"` strings), or
/// with `scalar` one number along an axis.
#[derive(Debug, Clone, Serialize)]
pub struct Handle {
    /// The dotted key (`mechanism.crank_pivot`, `mechanism.dyads[1].q`, …).
    pub key: String,
    /// Where it is: in the world, or with `poses` in the moving part's frame (m).
    pub at: [f64; 2],
    /// A handle on a moving part: the part's frame [x, y, angle] in each frame of the
    /// motion; `at`, `scalar.axis` and a written point are in that frame.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub poses: Vec<[f64; 3]>,
    /// A scalar key: how the drag maps to its value.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scalar: Option<Scalar>,
    /// Drawn as a ring about its point, under the other handles and grabbed by its rim: a
    /// reference point that may sit on another handle (a drawn outline's `origin` at its
    /// link's joint, often a pivot), which stays grabbable inside the ring.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub ring: bool,
}

impl Handle {
    /// A frame point written as `[x, y]`.
    pub fn point(key: impl Into<String>, at: P2) -> Handle {
        Handle {
            key: key.into(),
            at: xy(at),
            poses: Vec::new(),
            scalar: None,
            ring: false,
        }
    }

    /// A length (m) written in `unit` (`mm` or `m`, ≥ 0), growing along `axis` from `at`
    /// (a signed one: [`Handle::signed`]).
    pub fn length(key: impl Into<String>, at: P2, axis: P2, value: f64, unit: &str) -> Handle {
        let per_metre = if unit == "mm" { 1e3 } else { 1.0 };
        Handle {
            scalar: Some(Scalar {
                axis: xy(axis / axis.norm()),
                value: value * per_metre,
                per_metre,
                unit: unit.into(),
                step: if unit == "mm" { 0.1 } else { 1e-3 },
                min: Some(0.0),
            }),
            ..Handle::point(key, at)
        }
    }

    /// The same handle without a least value (a signed offset).
    pub fn signed(mut self) -> Handle {
        if let Some(s) = &mut self.scalar {
            s.min = None;
        }
        self
    }

    /// The same handle with the least value `min` (in its unit): a drag below it writes it
    /// (a key the file wants positive, where 0 would be refused).
    pub fn at_least(mut self, min: f64) -> Handle {
        if let Some(s) = &mut self.scalar {
            s.min = Some(min);
        }
        self
    }

    /// The same handle drawn as a ring (its field `ring`).
    pub fn as_ring(self) -> Handle {
        Handle { ring: true, ..self }
    }

    /// The same handle on a moving part placed at `poses`.
    pub fn on(self, poses: Vec<[f64; 3]>) -> Handle {
        Handle { poses, ..self }
    }
}

/// The mechanism over one turn: the frames (angles where it does not assemble left out).
#[derive(Debug, Clone, Serialize, Default)]
pub struct Motion {
    /// The links' names, in the frames' order.
    pub names: Vec<String>,
    /// The frames.
    pub frames: Vec<Frame>,
    /// Fixed lines of the frame (a slider's guide), as segments.
    pub guides: Vec<[[f64; 2]; 2]>,
    /// The points to drag.
    pub handles: Vec<Handle>,
    /// The rigid bodies, placed in each frame by [`Frame::poses`].
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<Body>,
    /// What a kinematic requirement asks, drawn over the mechanism (fixed in the world).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub marks: Vec<Mark>,
}

/// A kinematic requirement drawn over the mechanism: a stretch of a point's path (`trace`:
/// the tracer's path, the output's path over a dwell window), points to pass near
/// (`points`: a path's precision points, a function's), or a point that moves with a part
/// (`tracer`: a path's tracer point on its link, placed in each frame by `poses`), with
/// what it is (`label`).
#[derive(Debug, Clone, Serialize)]
pub struct Mark {
    /// `"trace"` (a polyline), `"points"` (each marked and numbered) or `"tracer"` (one
    /// point on a moving part).
    pub kind: &'static str,
    /// What it is, for the legend ("dwell of arm over θ = 150°–210°").
    pub label: String,
    /// Its points (m): in the world, or in the part's frame where `poses` is given.
    pub points: Vec<[f64; 2]>,
    /// The part's frame `[x, y, angle]` in each frame of the motion (a `tracer`'s).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub poses: Vec<[f64; 3]>,
}

impl Mark {
    fn new(kind: &'static str, label: impl Into<String>, points: Vec<[f64; 2]>) -> Mark {
        Mark {
            kind,
            label: label.into(),
            points,
            poses: Vec::new(),
        }
    }
    /// A stretch of a path.
    pub fn trace(label: impl Into<String>, points: Vec<[f64; 2]>) -> Mark {
        Mark::new("trace", label, points)
    }
    /// Points to pass near.
    pub fn points(label: impl Into<String>, points: Vec<[f64; 2]>) -> Mark {
        Mark::new("points", label, points)
    }
    /// The point `at` of a part placed at `poses` (one per frame).
    pub fn tracer(label: impl Into<String>, at: P2, poses: Vec<[f64; 3]>) -> Mark {
        Mark {
            poses,
            ..Mark::new("tracer", label, vec![xy(at)])
        }
    }
}

/// A point as the frames write it.
pub fn xy(p: P2) -> [f64; 2] {
    [p.x, p.y]
}

/// A pose as the frames write it: a part's frame at `origin` turned by `angle`.
pub fn pose(origin: P2, angle: f64) -> [f64; 3] {
    [origin.x, origin.y, angle]
}

/// The angles of one turn's frames.
pub fn turn() -> impl Iterator<Item = f64> {
    (0..FRAMES).map(|k| TAU * k as f64 / FRAMES as f64)
}

/// The span [lo, hi] of `ts` widened by `pad` of its width on each side.
pub fn span(ts: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) = ts.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
        (a.min(t), b.max(t))
    });
    let w = pad * (hi - lo);
    (lo - w, hi + w)
}

/// A circle of radius `r` about `c` as a closed polyline.
pub fn circle(c: P2, r: f64) -> Vec<[f64; 2]> {
    arc_points(c, r, 0.0, TAU, false)
}

/// Points of the arc about `c` from `a0` sweeping `sweep` (`end`: its end point included).
fn arc_points(c: P2, r: f64, a0: f64, sweep: f64, end: bool) -> Vec<[f64; 2]> {
    let n = ((sweep.abs() / TAU * 96.0).ceil() as usize).max(2);
    (0..n + usize::from(end))
        .map(|k| {
            let a = a0 + sweep * k as f64 / n as f64;
            xy(c + r * P2::new(a.cos(), a.sin()))
        })
        .collect()
}

/// A counterweight of `mass` (kg) centred at `c` with only its mass and centroid known,
/// drawn as a steel disc ([`STEEL_DENSITY`]) of the stated `thickness` (m).
pub fn steel_disc(name: String, c: P2, mass: f64, thickness: f64) -> Body {
    let r = (mass / (STEEL_DENSITY * thickness * std::f64::consts::PI)).sqrt();
    Body {
        name,
        kind: BodyKind::Counterweight,
        loops: vec![circle(c, r)],
        note: format!(
            "{mass:.4} kg; only its mass and centroid are known: drawn as a steel disc \
             ({STEEL_DENSITY} kg/m³) {:.0} mm thick, Ø {:.1} mm (assumed)",
            thickness * 1e3,
            2e3 * r
        ),
    }
}

/// The annular sector about the origin between radii `ri` and `ro`, `width` wide about the
/// direction `mid` (a full ring where `width` is a turn), as loops.
pub fn annular_sector(ri: f64, ro: f64, mid: f64, width: f64) -> Vec<Vec<[f64; 2]>> {
    let o = P2::zeros();
    if width >= TAU - 1e-9 {
        return [ro, ri]
            .iter()
            .filter(|&&r| r > 0.0)
            .map(|&r| circle(o, r))
            .collect();
    }
    let a0 = mid - 0.5 * width;
    let mut lp = arc_points(o, ro, a0, width, true);
    if ri > 0.0 {
        lp.extend(arc_points(o, ri, a0 + width, -width, true));
    } else {
        lp.push([0.0, 0.0]);
    }
    vec![lp]
}

/// Closed outline loops (straight edges and arcs) as polylines.
pub fn polylines(loops: &[Vec<Edge>]) -> Vec<Vec<[f64; 2]>> {
    let edge = |e: &Edge| match e.arc {
        Some(a) => arc_points(a.centre, a.radius, a.start, a.sweep, false),
        None => vec![xy(e.from)],
    };
    loops
        .iter()
        .map(|l| l.iter().flat_map(edge).collect())
        .collect()
}
