//! The shape of a linkage a shape search moves (issue 36), below the file and the search
//! that use it: the free geometry parameters and the kinematic requirements resolved
//! (`[objective.path]`, `[objective.swing]`, `[objective.function]`, the least transmission
//! angle), the path error of a tracer point against its precision points, a rocker's swing
//! and its angle against the crank's, the transmission angle over the turn, a linkage with its frame pivots moved, and what a search found. The search
//! itself is `synthesis.rs`.

use super::model::{Dyad, Linkage, LinkageError, Place, Point};
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
    /// The offset e of a slider's line: its signed distance from the crank's pivot A0,
    /// e = d × (O − A0) with d the line's direction and O its point ([`line_offset`]).
    LineOffset {
        /// The slider (the second link of an RRP dyad).
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

/// `[objective.swing]` resolved: a rocker's swing over the turn.
#[derive(Debug, Clone, PartialEq)]
pub struct SwingSpec {
    /// The rocker: a link pivoted on the frame.
    pub link: usize,
    /// The swing to meet (rad): max ψ − min ψ over the turn.
    pub angle: f64,
    /// The swing error allowed (rad).
    pub max_error: f64,
}

/// `[objective.function]` resolved: a rocker's angle against the crank's (function
/// generation), both as changes from the first point.
#[derive(Debug, Clone, PartialEq)]
pub struct FunctionSpec {
    /// The rocker: a link pivoted on the frame.
    pub link: usize,
    /// The crank angles θ_i (rad), at least 2.
    pub crank_angles: Vec<f64>,
    /// The rocker's angles ψ_i (rad) at them: the requirement is ψ(θ_i) − ψ(θ_1) =
    /// ψ_i − ψ_1.
    pub angles: Vec<f64>,
    /// The function error allowed (rad).
    pub max_error: f64,
}

/// `[objective.stroke]` resolved: a slider's travel over the turn.
#[derive(Debug, Clone, PartialEq)]
pub struct StrokeSpec {
    /// The slider: the second link of an RRP dyad.
    pub link: usize,
    /// The stroke to meet (m): max s − min s of the slider's place along its line.
    pub stroke: f64,
    /// The stroke error allowed (m).
    pub max_error: f64,
}

/// What dwells ([`DwellSpec`]): a slider's place along its line or a rocker's angle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DwellOf {
    /// A slider (the second link of an RRP dyad): its place s = P·d along its line (m).
    Slider,
    /// A rocker (a link pivoted on the frame): its angle ψ from its direction at θ = 0 (rad).
    Rocker,
}

impl DwellOf {
    /// "slider" or "rocker".
    pub fn name(self) -> &'static str {
        match self {
            DwellOf::Slider => "slider",
            DwellOf::Rocker => "rocker",
        }
    }
    /// The file's key of the range over the turn: `stroke` or `swing`.
    pub fn range_key(self) -> &'static str {
        match self {
            DwellOf::Slider => "stroke",
            DwellOf::Rocker => "swing",
        }
    }
    /// The SI unit of its figures, as the result's keys end: `m` or `rad`.
    pub fn si_unit(self) -> &'static str {
        match self {
            DwellOf::Slider => "m",
            DwellOf::Rocker => "rad",
        }
    }
}

/// `[objective.dwell]` resolved: a slider or a rocker that stands still while the crank
/// turns through a window, and travels a stroke or swings an angle over the turn (a press's
/// ram dwelling at the bottom, an indexing arm at the end of its swing).
#[derive(Debug, Clone, PartialEq)]
pub struct DwellSpec {
    /// The output: a slider or a rocker ([`DwellSpec::of`]).
    pub link: usize,
    /// Which of the two the output is.
    pub of: DwellOf,
    /// The window's first crank angle θ_a (rad).
    pub from: f64,
    /// Its last, θ_b, with θ_a < θ_b < θ_a + 2π (rad).
    pub to: f64,
    /// The range to meet over the turn: a slider's stroke (m) or a rocker's swing (rad).
    pub range: f64,
    /// The dwell error allowed (m for a slider, rad for a rocker; [`Dwell::error`]).
    pub max_error: f64,
}

/// `design.synthesis.max_crank_ratio` resolved: λ = r/l ≤ `max`, r the crank's length and l
/// that of the rod of the RRP dyad on the crank's tip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrankRatio {
    /// The largest λ.
    pub max: f64,
    /// The rod (the first link of that RRP dyad).
    pub rod: usize,
}

impl CrankRatio {
    /// λ = r/l of the linkage `l` with its crank `crank_length` long.
    pub fn of(&self, l: &Linkage, crank_length: f64) -> Option<f64> {
        Some(crank_length / super::model::tip_of(l.dyads(), crank_length, self.rod)?.x)
    }
}

/// `design.synthesis.joint_box` resolved: the box every joint must stay inside over the turn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointBox {
    /// The lower corner (m, world).
    pub min: P2,
    /// The upper corner (m, world).
    pub max: P2,
}

/// `[design.synthesis]` resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Synthesis {
    /// The free parameters, in the order of the search's x.
    pub params: Vec<GeometryParam>,
    /// The least transmission angle every candidate must keep over the turn (rad), if any
    /// ([`min_transmission`]).
    pub min_transmission: Option<f64>,
    /// The largest crank ratio λ = r/l every candidate must keep, if any.
    pub max_crank_ratio: Option<CrankRatio>,
    /// The box every joint must stay inside over the turn, if any ([`box_margin`]).
    pub joint_box: Option<JointBox>,
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

/// The line (its point O, its direction angle) of the slider `link` of `l`: the second link
/// of an RRP dyad; `None` for any other link.
pub fn slider_line(l: &Linkage, link: usize) -> Option<(P2, f64)> {
    let (k, second) = ((link.checked_sub(1)?) / 2, (link - 1) % 2 == 1);
    match (l.dyads().get(k)?, second) {
        (Dyad::Rrp { origin, angle, .. }, true) => Some((*origin, *angle)),
        _ => None,
    }
}

/// The offset e of the slider `link`'s line from the crank's pivot A0: e = d × (O − A0),
/// d = (cos α, sin α) the line's direction, O its point (positive with A0 to the line's
/// right). `None` where `link` is not a slider.
pub fn line_offset(l: &Linkage, link: usize) -> Option<f64> {
    let (o, angle) = slider_line(l, link)?;
    let d = P2::new(angle.cos(), angle.sin());
    Some(crate::geom::cross(d, o - l.pivot()))
}

/// The linkage with the slider `link`'s line moved along its normal n = (−sin α, cos α) to
/// the offset `e` ([`line_offset`]): O' = O + (e − e₀)·n, its direction unchanged.
pub fn with_line_offset(l: &Linkage, link: usize, e: f64) -> Result<Linkage, LinkageError> {
    let e0 = line_offset(l, link).ok_or(LinkageError::NotSlider { link })?;
    let k = (link - 1) / 2;
    let dyads = (l.dyads().iter().enumerate())
        .map(|(j, d)| match *d {
            Dyad::Rrp {
                p,
                l,
                origin,
                angle,
                side,
            } if j == k => Dyad::Rrp {
                p,
                l,
                origin: origin + P2::new(-angle.sin(), angle.cos()) * (e - e0),
                angle,
                side,
            },
            d => d,
        })
        .collect();
    Linkage::new(
        l.pivot(),
        dyads,
        l.inertia().to_vec(),
        l.omega(),
        l.gravity(),
    )?
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
    let placer = Placer::new(l);
    let x = |theta: f64| placer.at(theta, |p| p[path.link].point(at));
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

/// The links' places at one crank angle after another into one buffer
/// ([`Linkage::places_into`]): a path error or a swing asks for hundreds of them, and a fresh
/// vector each was a sixth of a path error's instructions.
struct Placer<'a> {
    l: &'a Linkage,
    buf: std::cell::RefCell<Vec<Place>>,
}

impl<'a> Placer<'a> {
    fn new(l: &'a Linkage) -> Self {
        let buf = std::cell::RefCell::new(Vec::with_capacity(l.n_links()));
        Placer { l, buf }
    }
    /// g(places at θ); `None` where the linkage does not assemble there.
    fn at<T>(&self, theta: f64, g: impl FnOnce(&[Place]) -> T) -> Option<T> {
        let mut b = self.buf.borrow_mut();
        self.l.places_into(theta, &mut b).ok()?;
        Some(g(&b))
    }
}

/// An extreme over the turn with its error bound.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurnExtreme {
    /// The value.
    pub value: f64,
    /// Bound on its error.
    pub error: f64,
    /// The crank angle where it is reached (rad).
    pub angle: f64,
}

/// g(places) at the [`PATH_SAMPLES`] crank angles θ_k = 2πk/n ([`Linkage::places`]: the
/// links' positions without their derivatives); `None` where the linkage does not assemble
/// at one of them.
fn sampled<T>(l: &Linkage, g: &impl Fn(&[Place]) -> T) -> Option<Vec<T>> {
    let h = std::f64::consts::TAU / PATH_SAMPLES as f64;
    let placer = Placer::new(l);
    (0..PATH_SAMPLES)
        .map(|k| placer.at(k as f64 * h, g))
        .collect()
}

/// The largest of `sign`·g(places) over the turn from its samples `ys` (of g): every local
/// maximum refined by Brent to [`ANGLE_TOL`] ([`crate::numeric::periodic_peak_sampled`],
/// whose error bound it carries). `None` where the refinement meets a pose that does not
/// assemble.
fn turn_max(
    l: &Linkage,
    ys: &[f64],
    sign: f64,
    g: &impl Fn(&[Place]) -> f64,
) -> Option<TurnExtreme> {
    let signed: Vec<f64> = ys.iter().map(|y| sign * y).collect();
    let placer = Placer::new(l);
    let f = |t: f64| placer.at(t, |p| sign * g(p)).unwrap_or(f64::NAN);
    let all = crate::numeric::Refine::All;
    let p = crate::numeric::periodic_peak_sampled(&signed, f, Some(ANGLE_TOL), all).ok()?;
    p.peak.fx.is_finite().then_some(TurnExtreme {
        value: p.peak.fx,
        error: p.error,
        angle: p.peak.x,
    })
}

/// The swing of link `link` (a rocker) over the turn without its round-off term: max ψ −
/// min ψ (rad), ψ measured from its direction at θ = 0 (continuous while the swing stays
/// below π), each extreme refined, with the refinements' error bounds — what the search
/// asks of every candidate. `None` where the linkage does not assemble over the turn.
pub fn swing_refined(l: &Linkage, link: usize) -> Option<TurnExtreme> {
    let e0 = l.places(0.0).ok()?.get(link)?.e;
    turn_range(l, |p: &[Place]| crate::geom::turn(e0, p[link].e))
}

/// max g − min g over the turn, each extreme refined ([`turn_max`]), their error bounds
/// added; the angle is the maximum's.
fn turn_range(l: &Linkage, g: impl Fn(&[Place]) -> f64) -> Option<TurnExtreme> {
    let ys = sampled(l, &g)?;
    let hi = turn_max(l, &ys, 1.0, &g)?;
    let lo = turn_max(l, &ys, -1.0, &g)?;
    Some(TurnExtreme {
        value: hi.value + lo.value,
        error: hi.error + lo.error,
        angle: hi.angle,
    })
}

/// [`swing_refined`] with the round-off of the directions added to its error bound: 1e-15
/// times the largest dyad conditioning over the samples ([`Linkage::pose`]'s κ).
pub fn swing(l: &Linkage, link: usize) -> Option<TurnExtreme> {
    let w = swing_refined(l, link)?;
    Some(TurnExtreme {
        error: w.error + angle_round_off(l)?,
        ..w
    })
}

/// The round-off of a link's direction: 1e-15 times the largest dyad conditioning over the
/// samples ([`Linkage::pose`]'s κ); `None` where the linkage does not assemble.
fn angle_round_off(l: &Linkage) -> Option<f64> {
    let h = std::f64::consts::TAU / PATH_SAMPLES as f64;
    let kappa = (0..PATH_SAMPLES)
        .map(|k| l.pose(k as f64 * h).map(|p| p.kappa()).ok())
        .collect::<Option<Vec<f64>>>()?
        .into_iter()
        .fold(1.0, f64::max);
    Some(1e-15 * kappa)
}

/// The stroke of the slider `link` of `l` without its round-off term: max s − min s (m) of
/// its place along its line, s = P·d (d the line's direction), each extreme refined, with
/// the refinements' error bounds — what the search asks of every candidate. For the
/// slider-crank with crank r, rod l and offset e it is
/// √((l + r)² − e²) − √((l − r)² − e²). `None` where the linkage does not assemble over
/// the turn.
pub fn stroke_refined(l: &Linkage, link: usize) -> Option<TurnExtreme> {
    let d = l.places(0.0).ok()?.get(link)?.e;
    turn_range(l, |p: &[Place]| p[link].p.dot(&d))
}

/// [`stroke_refined`] with the round-off of the places added to its error bound: 1e-15 times
/// the mechanism's size (the largest |P| over the samples) times its largest dyad
/// conditioning.
pub fn stroke(l: &Linkage, link: usize) -> Option<TurnExtreme> {
    let w = stroke_refined(l, link)?;
    Some(TurnExtreme {
        error: w.error + place_round_off(l)?,
        ..w
    })
}

/// The round-off of a place along a line: 1e-15 times the mechanism's size (the largest |P|
/// over the samples) times its largest dyad conditioning; `None` where it does not assemble.
fn place_round_off(l: &Linkage) -> Option<f64> {
    let h = std::f64::consts::TAU / PATH_SAMPLES as f64;
    let (mut size, mut kappa) = (0.0f64, 1.0f64);
    for k in 0..PATH_SAMPLES {
        let pose = l.pose(k as f64 * h).ok()?;
        kappa = kappa.max(pose.kappa());
        size = (pose.links.iter()).fold(size, |m, x| m.max(x.point(P2::zeros())[0].norm()));
    }
    Some(1e-15 * size * kappa)
}

/// The crank-angle samples of a dwell window (end points included): 64 steps of at most
/// 5.6°, so that a maximum of the slider's place narrower than a step is not missed (the
/// place varies by a fraction of a millimetre inside a dwell).
const DWELL_STEPS: usize = 64;

/// A dwell's figures ([`dwell`]): the output's travel inside the window and its range over
/// the turn, each with its error bound (m for a slider, rad for a rocker).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dwell {
    /// max g − min g over θ ∈ [θ_a, θ_b], g the slider's place along its line or the
    /// rocker's angle; its angle is that of the window's highest g.
    pub travel: TurnExtreme,
    /// max g − min g over the turn: the slider's [`stroke`] or the rocker's [`swing`].
    pub range: TurnExtreme,
}

impl Dwell {
    /// The dwell error: max(travel in the window, |range − target|) — one figure for the
    /// search, met when the output stands still within it and travels its stroke (swings its
    /// angle) within it.
    pub fn error(&self, spec: &DwellSpec) -> f64 {
        self.travel.value.max((self.range.value - spec.range).abs())
    }
    /// The bound on [`Dwell::error`]'s error: the larger of its two parts' (the max of two
    /// figures moves by at most the larger of their moves).
    pub fn error_bound(&self) -> f64 {
        self.travel.error.max(self.range.error)
    }
}

/// The output's travel in the dwell window and its range over the turn, without their
/// round-off terms: each extreme in the window refined by Brent
/// ([`crate::numeric::interval_peak`], on [`DWELL_STEPS`] samples, to [`ANGLE_TOL`]), with
/// the refinements' error bounds — what the search asks of every candidate. The slider's
/// place is s = P·d (d its line's direction), the rocker's angle ψ its turn from its
/// direction at θ = 0 (as [`swing_refined`]'s). `None` where the linkage does not assemble.
pub fn dwell_refined(l: &Linkage, spec: &DwellSpec) -> Option<Dwell> {
    let (link, of) = (spec.link, spec.of);
    let range = match of {
        DwellOf::Slider => stroke_refined(l, link)?,
        DwellOf::Rocker => swing_refined(l, link)?,
    };
    let d = l.places(0.0).ok()?.get(link)?.e;
    let g = move |p: &[Place]| match of {
        DwellOf::Slider => p[link].p.dot(&d),
        DwellOf::Rocker => crate::geom::turn(d, p[link].e),
    };
    let placer = Placer::new(l);
    let placer = &placer;
    let s = |sign: f64| move |t: f64| placer.at(t, |p| sign * g(p)).unwrap_or(f64::NAN);
    let (a, b) = (spec.from, spec.to);
    let hi = crate::numeric::interval_peak(s(1.0), a, b, DWELL_STEPS, ANGLE_TOL).ok()?;
    let lo = crate::numeric::interval_peak(s(-1.0), a, b, DWELL_STEPS, ANGLE_TOL).ok()?;
    let travel = TurnExtreme {
        value: hi.peak.fx + lo.peak.fx,
        error: hi.error + lo.error,
        angle: hi.peak.x,
    };
    Some(Dwell { travel, range })
}

/// [`dwell_refined`] with the round-off added to both error bounds: a slider's places'
/// ([`place_round_off`]) or a rocker's directions' ([`angle_round_off`]).
pub fn dwell(l: &Linkage, spec: &DwellSpec) -> Option<Dwell> {
    let w = dwell_refined(l, spec)?;
    let r = match spec.of {
        DwellOf::Slider => place_round_off(l)?,
        DwellOf::Rocker => angle_round_off(l)?,
    };
    let more = |e: TurnExtreme| TurnExtreme {
        error: e.error + r,
        ..e
    };
    Some(Dwell {
        travel: more(w.travel),
        range: more(w.range),
    })
}

/// The joints of `l` as (link, point in its frame): every link's reference joint P (the
/// crank's pivot A0, a dyad link's pivot, a slider's pin) and the tip of every link with a
/// length ([`super::model::tip_of`]; the crank's length is `crank_length`).
fn joints(l: &Linkage, crank_length: f64) -> Vec<(usize, P2)> {
    (0..l.n_links())
        .flat_map(|i| {
            let tip = super::model::tip_of(l.dyads(), crank_length, i);
            std::iter::once((i, P2::zeros())).chain(tip.map(|t| (i, t)))
        })
        .collect()
}

/// The margin of the joints of `l` inside the box `b` over the turn: the least, over the
/// joints ([`joints`]) and the crank angle, of the distance to the box's nearest wall,
/// min(x − x_min, x_max − x, y − y_min, y_max − y) — negative where a joint leaves the box —
/// refined like the swing ([`turn_max`], from [`PATH_SAMPLES`] samples), its error bound the
/// refinement's plus 1e-15 of the mechanism's size. `None` where the linkage does not
/// assemble over the turn.
pub fn box_margin(l: &Linkage, crank_length: f64, b: &JointBox) -> Option<TurnExtreme> {
    let pts = joints(l, crank_length);
    let g = |p: &[Place]| {
        (pts.iter())
            .map(|&(i, at)| {
                let x = p[i].point(at);
                (x.x - b.min.x)
                    .min(b.max.x - x.x)
                    .min(x.y - b.min.y)
                    .min(b.max.y - x.y)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let ys = sampled(l, &g)?;
    let m = turn_max(l, &ys, -1.0, &g)?;
    let size = b.min.norm().max(b.max.norm());
    Some(TurnExtreme {
        value: -m.value,
        error: m.error + 1e-15 * size,
        angle: m.angle,
    })
}

/// The least transmission angle over the turn of the RRR dyads of `l`: the angle between a
/// dyad's two links at their joint, folded into [0, π/2] — asin of the least |sin μ| over
/// the turn and the dyads, sin μ = e_a × e_b of the links' directions (the same operations
/// as [`super::model::DyadState::sin_mu`]) — with its error bound (the refinement's,
/// through asin's slope 1/cos μ). `None` without RRR dyads or where the linkage does not
/// assemble over the turn.
pub fn min_transmission(l: &Linkage) -> Option<TurnExtreme> {
    let rrr: Vec<(usize, usize)> = (l.dyads().iter().enumerate())
        .filter(|(_, d)| matches!(d, Dyad::Rrr { .. }))
        .map(|(k, _)| Linkage::dyad_links(k))
        .collect();
    if rrr.is_empty() {
        return None;
    }
    let least_sin = |p: &[Place]| {
        rrr.iter()
            .map(|&(a, b)| crate::geom::cross(p[a].e, p[b].e).abs())
            .fold(f64::INFINITY, f64::min)
    };
    let ys = sampled(l, &least_sin)?;
    let m = turn_max(l, &ys, -1.0, &least_sin)?;
    let s = (-m.value).clamp(0.0, 1.0);
    let slope = 1.0 / (1.0 - s * s).sqrt().max(1e-8);
    Some(TurnExtreme {
        value: s.asin(),
        error: (m.error + 4.0 * f64::EPSILON) * slope,
        angle: m.angle,
    })
}

/// The function error of the rocker `f.link` of `l`: max_i |(ψ(θ_i) − ψ(θ_1)) − (ψ_i − ψ_1)|
/// (rad), each change of ψ taken in (−π, π] from the link's directions (exact at the given
/// angles: no refinement), and each point's; with its round-off bound, 1e-15 times the
/// largest dyad conditioning at the points. `None` where the linkage does not assemble at a
/// point.
pub fn function_error(l: &Linkage, f: &FunctionSpec) -> Option<(TurnExtreme, Vec<f64>)> {
    let poses: Vec<_> = (f.crank_angles.iter())
        .map(|&t| l.pose(t).ok())
        .collect::<Option<_>>()?;
    let e0 = poses.first()?.links.get(f.link)?.e;
    // An angle into (−π, π].
    let wrap = |a: f64| {
        use std::f64::consts::{PI, TAU};
        (a + PI).rem_euclid(TAU) - PI
    };
    let each: Vec<f64> = (poses.iter().zip(&f.angles))
        .map(|(p, &psi)| {
            let turned = crate::geom::turn(e0, p.links[f.link].e);
            wrap(turned - wrap(psi - f.angles[0])).abs()
        })
        .collect();
    let kappa = poses.iter().map(|p| p.kappa()).fold(1.0, f64::max);
    let k = crate::dynamics::cases::argmax(each.iter().copied())?;
    let worst = TurnExtreme {
        value: each[k],
        error: 1e-15 * kappa,
        angle: f.crank_angles[k],
    };
    Some((worst, each))
}

/// A kinematic error, as the result names it: a path error (m) or a swing error (rad).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum KinematicError {
    /// The path error (m).
    #[serde(rename = "path_error_m")]
    Path(f64),
    /// The swing error |swing − angle| (rad).
    #[serde(rename = "swing_error_rad")]
    Swing(f64),
    /// The function error (rad, [`function_error`]).
    #[serde(rename = "function_error_rad")]
    Function(f64),
    /// The stroke error |stroke − target| (m, [`stroke`]).
    #[serde(rename = "stroke_error_m")]
    Stroke(f64),
    /// A slider's dwell error (m, [`Dwell::error`]).
    #[serde(rename = "dwell_error_m")]
    Dwell(f64),
    /// A rocker's dwell error (rad, [`Dwell::error`]).
    #[serde(rename = "dwell_error_rad")]
    DwellAngle(f64),
}

impl KinematicError {
    /// Its value (SI).
    pub fn value(self) -> f64 {
        match self {
            KinematicError::Path(v)
            | KinematicError::Swing(v)
            | KinematicError::Function(v)
            | KinematicError::Stroke(v)
            | KinematicError::Dwell(v)
            | KinematicError::DwellAngle(v) => v,
        }
    }
    /// The same kind of error with the value `v` (SI).
    pub fn with(self, v: f64) -> Self {
        match self {
            KinematicError::Path(_) => KinematicError::Path(v),
            KinematicError::Swing(_) => KinematicError::Swing(v),
            KinematicError::Function(_) => KinematicError::Function(v),
            KinematicError::Stroke(_) => KinematicError::Stroke(v),
            KinematicError::Dwell(_) => KinematicError::Dwell(v),
            KinematicError::DwellAngle(_) => KinematicError::DwellAngle(v),
        }
    }
    /// (its name, its value in the report's unit, that unit): mm for a path, a stroke or a
    /// slider's dwell, ° for a swing, a function or a rocker's dwell.
    pub fn shown(self) -> (&'static str, f64, &'static str) {
        match self {
            KinematicError::Path(v) => ("path error", v * 1e3, "mm"),
            KinematicError::Swing(v) => ("swing error", v.to_degrees(), "deg"),
            KinematicError::Function(v) => ("function error", v.to_degrees(), "deg"),
            KinematicError::Stroke(v) => ("stroke error", v * 1e3, "mm"),
            KinematicError::Dwell(v) => ("dwell error", v * 1e3, "mm"),
            KinematicError::DwellAngle(v) => ("dwell error", v.to_degrees(), "deg"),
        }
    }
}

/// The kinematic error a front point was held to, as the result names it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum HeldTo {
    /// A length's error: a path's, a stroke's or a slider's dwell's (m).
    #[serde(rename = "max_error_m")]
    Length(f64),
    /// An angle's error: a swing's, a function's or a rocker's dwell's (rad).
    #[serde(rename = "max_error_rad")]
    Angle(f64),
}

impl HeldTo {
    /// Its value (SI).
    pub fn value(self) -> f64 {
        match self {
            HeldTo::Length(v) | HeldTo::Angle(v) => v,
        }
    }
}

/// The kinematic requirement of a shape search: a tracer's path, a rocker's swing, a
/// rocker's angle against the crank's, a slider's stroke, or a slider's or a rocker's dwell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Requirement<'a> {
    /// `[objective.path]`.
    Path(&'a PathSpec),
    /// `[objective.swing]`.
    Swing(&'a SwingSpec),
    /// `[objective.function]`.
    Function(&'a FunctionSpec),
    /// `[objective.stroke]`.
    Stroke(&'a StrokeSpec),
    /// `[objective.dwell]`.
    Dwell(&'a DwellSpec),
}

impl Requirement<'_> {
    /// The kinematic error of `l` with the tracer at `at` (a path's; SI), `None` where it
    /// does not assemble over the turn.
    pub fn error(self, l: &Linkage, at: P2) -> Option<f64> {
        match self {
            Requirement::Path(p) => path_error(l, p, at).map(|e| e.0),
            Requirement::Swing(s) => swing_refined(l, s.link).map(|w| (w.value - s.angle).abs()),
            Requirement::Function(f) => function_error(l, f).map(|e| e.0.value),
            Requirement::Stroke(s) => stroke_refined(l, s.link).map(|w| (w.value - s.stroke).abs()),
            Requirement::Dwell(d) => dwell_refined(l, d).map(|w| w.error(d)),
        }
    }
    /// The error `v` (SI) as the result names it.
    pub fn named(self, v: f64) -> KinematicError {
        match self {
            Requirement::Path(_) => KinematicError::Path(v),
            Requirement::Swing(_) => KinematicError::Swing(v),
            Requirement::Function(_) => KinematicError::Function(v),
            Requirement::Stroke(_) => KinematicError::Stroke(v),
            Requirement::Dwell(d) if d.of == DwellOf::Rocker => KinematicError::DwellAngle(v),
            Requirement::Dwell(_) => KinematicError::Dwell(v),
        }
    }
    /// The tracer's reference: the path's (the origin of its link without a path).
    pub fn tracer(self) -> P2 {
        match self {
            Requirement::Path(p) => p.at,
            Requirement::Swing(_)
            | Requirement::Function(_)
            | Requirement::Stroke(_)
            | Requirement::Dwell(_) => P2::zeros(),
        }
    }
    /// The error allowed (SI).
    pub fn max_error(self) -> f64 {
        match self {
            Requirement::Path(p) => p.max_error,
            Requirement::Swing(s) => s.max_error,
            Requirement::Function(f) => f.max_error,
            Requirement::Stroke(s) => s.max_error,
            Requirement::Dwell(d) => d.max_error,
        }
    }
    /// ε as the bound a front point was held to.
    pub fn held_to(self, eps: f64) -> HeldTo {
        match self {
            Requirement::Dwell(d) if d.of == DwellOf::Rocker => HeldTo::Angle(eps),
            Requirement::Path(_) | Requirement::Stroke(_) | Requirement::Dwell(_) => {
                HeldTo::Length(eps)
            }
            Requirement::Swing(_) | Requirement::Function(_) => HeldTo::Angle(eps),
        }
    }
    /// The file's key of the requirement.
    pub fn key(self) -> &'static str {
        match self {
            Requirement::Path(_) => "objective.path",
            Requirement::Swing(_) => "objective.swing",
            Requirement::Function(_) => "objective.function",
            Requirement::Stroke(_) => "objective.stroke",
            Requirement::Dwell(_) => "objective.dwell",
        }
    }
}

/// A geometry of the front: its parameters, kinematic error and certified objective.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ShapePoint {
    /// The kinematic error the search was held to: `max_error_m` (a path) or
    /// `max_error_rad` (a swing) in the result; absent for the least-error geometry.
    #[serde(flatten)]
    pub held_to: Option<HeldTo>,
    /// The parameters (m), in the order of `parameters`.
    pub x: Vec<f64>,
    /// Its kinematic error: `path_error_m` or `swing_error_rad` in the result.
    #[serde(flatten)]
    pub error: KinematicError,
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
