//! The shape of a linkage a shape search moves (issue 36), below the file and the search
//! that use it: the free geometry parameters and the path of `[objective.path]` resolved, the
//! path error of a tracer point against its precision points, a linkage with its frame pivots
//! moved, and what a search found. The search itself is `synthesis.rs`.

use super::model::{Dyad, Linkage, LinkageError, Point};
use crate::geom::P2;
use crate::synth::search::constrained;
use crate::synth::search::SearchEvidence;

/// What a geometry parameter moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A link's length ([`super::model::tip_of`]); a uniform bar's mass properties follow it.
    Length {
        /// The link.
        link: usize,
        /// Whether it is a uniform bar.
        bar: bool,
    },
    /// The x of a link's frame pivot ([`frame_pivot`]).
    PivotX {
        /// The link.
        link: usize,
    },
    /// The y of a link's frame pivot.
    PivotY {
        /// The link.
        link: usize,
    },
    /// The tracer point's x in its link's frame.
    TracerX,
    /// The tracer point's y in its link's frame.
    TracerY,
}

/// One free geometry parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct GeometryParam {
    /// What it is, as the result names it ("length of coupler", "pivot of rocker x").
    pub name: String,
    /// What it moves.
    pub kind: Kind,
    /// Its bounds (m).
    pub bounds: (f64, f64),
}

/// `[objective.path]` resolved: the tracer point and its precision points.
#[derive(Debug, Clone, PartialEq)]
pub struct PathSpec {
    /// The tracer's link.
    pub link: usize,
    /// The tracer in its link's frame (m): the file's, the search's reference.
    pub at: P2,
    /// The precision points (m, world).
    pub points: Vec<P2>,
    /// The crank angle of each point (rad), with timing.
    pub angles: Option<Vec<f64>>,
    /// The path error to meet (m).
    pub max_error: f64,
}

/// `[design.synthesis]` resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Synthesis {
    /// The free parameters, in the order of the search's x.
    pub params: Vec<GeometryParam>,
    /// The multistart's settings.
    pub search: constrained::Settings,
    /// Front points below `max_error`.
    pub front_points: usize,
}

/// Crank angles sampled for the path error before refining each point's nearest one.
pub const PATH_SAMPLES: usize = 360;

/// The path error's refinement tolerance in the crank angle (rad).
const ANGLE_TOL: f64 = 1e-10;

/// The frame point link `link` of `l` is pivoted at: the crank's A0, or a dyad link's pivot
/// where it is a frame point.
pub fn frame_pivot(l: &Linkage, link: usize) -> Option<P2> {
    if link == 0 {
        return Some(l.pivot());
    }
    let (k, second) = ((link - 1) / 2, (link - 1) % 2 == 1);
    let p = match (l.dyads().get(k)?, second) {
        (Dyad::Rrr { p, .. } | Dyad::Rrp { p, .. } | Dyad::Rpr { p, .. }, false) => *p,
        (Dyad::Rrr { q, .. } | Dyad::Rpr { q, .. }, true) => *q,
        _ => return None,
    };
    match p {
        Point::Frame(x) => Some(x),
        Point::On { .. } => None,
    }
}

/// The linkage with the frame pivots of the links `pivots` moved: A0 for the crank, a dyad
/// link's frame point for the others.
pub fn with_pivots(l: &Linkage, pivots: &[(usize, P2)]) -> Result<Linkage, LinkageError> {
    let at = |link: usize, old: Point| match pivots.iter().find(|p| p.0 == link) {
        Some(&(_, x)) => Point::Frame(x),
        None => old,
    };
    let dyads = l
        .dyads()
        .iter()
        .enumerate()
        .map(|(k, d)| d.remapped(Linkage::dyad_links(k), at, |_, l| l))
        .collect();
    let pivot = pivots.iter().find(|p| p.0 == 0).map_or(l.pivot(), |p| p.1);
    Linkage::new(pivot, dyads, l.inertia().to_vec(), l.omega(), l.gravity())?
        .with_loads(l.loads().to_vec())
}

/// The path error of the tracer at `at` on link `path.link` of `l`: the largest distance
/// from a precision point to the tracer's path, max_i min_θ |X(θ) − Q_i| (with timing,
/// max_i |X(θ_i) − Q_i|), and each point's distance. Without timing each point's nearest
/// sample of [`PATH_SAMPLES`] is refined by Brent's method in the two intervals beside it
/// (to [`ANGLE_TOL`] in θ: the distance's error is second order in it). `None` where the
/// linkage does not assemble at a sampled angle (the crank must turn fully). Positions only
/// ([`Linkage::places`]: the tracer's X of [`Linkage::pose`] bit for bit, without its
/// derivatives).
pub fn path_error(l: &Linkage, path: &PathSpec, at: P2) -> Option<(f64, Vec<f64>)> {
    let x = |theta: f64| -> Option<P2> { Some(l.places(theta).ok()?[path.link].point(at)) };
    let d: Vec<f64> = match &path.angles {
        Some(angles) => (path.points.iter().zip(angles))
            .map(|(q, &t)| x(t).map(|p| (p - q).norm()))
            .collect::<Option<_>>()?,
        None => {
            let h = std::f64::consts::TAU / PATH_SAMPLES as f64;
            let curve: Vec<P2> = (0..PATH_SAMPLES)
                .map(|k| x(k as f64 * h))
                .collect::<Option<_>>()?;
            path.points
                .iter()
                .map(|q| nearest(&curve, h, *q, &x))
                .collect::<Option<_>>()?
        }
    };
    Some((d.iter().copied().fold(0.0, f64::max), d))
}

/// The distance from `q` to the closed curve X(θ) sampled as `curve` at spacing `h`: each
/// local minimum of the sampled distance refined by Brent's method on [θ_k − h, θ_k + h],
/// the least of them (a curve passing near `q` twice has two).
fn nearest(curve: &[P2], h: f64, q: P2, x: &dyn Fn(f64) -> Option<P2>) -> Option<f64> {
    let n = curve.len();
    let d2: Vec<f64> = curve.iter().map(|p| (p - q).norm_squared()).collect();
    let f = |th: f64| x(th).map_or(f64::NEG_INFINITY, |p| -(p - q).norm_squared());
    let mut best = f64::INFINITY;
    for k in 0..n {
        let (prev, next) = (d2[(k + n - 1) % n], d2[(k + 1) % n]);
        if d2[k] > prev || d2[k] > next {
            continue;
        }
        let t = k as f64 * h;
        let m = crate::numeric::brent_max(f, t - h, t + h, ANGLE_TOL).ok()?;
        best = best.min((-m.fx).max(0.0).min(d2[k]));
    }
    best.is_finite().then(|| best.sqrt())
}

/// The error bound of a path error from [`path_error`]: the refinement's tolerance in θ
/// times the tracer's largest speed |X'| over the samples (a first-order bound, though at a
/// nearest point the distance moves only to second order), plus the poses' round-off,
/// 1e-15 of the mechanism's size times its largest dyad conditioning.
pub fn path_error_bound(l: &Linkage, path: &PathSpec, at: P2) -> f64 {
    let h = std::f64::consts::TAU / PATH_SAMPLES as f64;
    let (mut v, mut size, mut kappa) = (0.0f64, 0.0f64, 1.0f64);
    for k in 0..PATH_SAMPLES {
        if let Ok(pose) = l.pose(k as f64 * h) {
            let x = pose.links[path.link].point(at);
            v = v.max(x[1].norm());
            size = size.max(x[0].norm());
            kappa = kappa.max(pose.kappa());
        }
    }
    let size = path.points.iter().map(|p| p.norm()).fold(size, f64::max);
    v * ANGLE_TOL + 1e-15 * size * kappa
}

/// A geometry of the front: its parameters, path error and certified objective.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ShapePoint {
    /// The path error the search was held to (m; `None` for the least-error geometry).
    pub max_error_m: Option<f64>,
    /// The parameters (m), in the order of `parameters`.
    pub x: Vec<f64>,
    /// Its path error (m).
    pub path_error_m: f64,
    /// Its certified optimum's objective (SI), `None` where the balancing is not `optimal`.
    pub objective: Option<f64>,
    /// The search's evidence.
    pub search: SearchEvidence,
}

/// What a shape search found: "synthesise first, balance afterwards" (the least path error,
/// then its certified balancing) and the front of path error against the certified
/// objective, the last point at `max_error` the design.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ShapeOutcome {
    /// The parameters' names.
    pub parameters: Vec<String>,
    /// The file's geometry where it lies in the box: its parameters, path error and
    /// objective (a seed of the searches).
    pub nominal: Option<ShapePoint>,
    /// The least path error, balanced afterwards.
    pub kinematic_first: ShapePoint,
    /// The front, ascending in the path error held to; the last at `max_error`.
    pub front: Vec<ShapePoint>,
}

impl ShapeOutcome {
    /// The design: the front's point at `max_error`.
    pub fn chosen(&self) -> Option<&ShapePoint> {
        self.front.last()
    }
}
