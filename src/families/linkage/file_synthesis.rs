//! `[design.synthesis]`, `[objective.path]`, `[objective.swing]`, `[objective.function]`,
//! `[objective.stroke]` and `[objective.dwell]` of a linkage file (issue 36): the geometry
//! the search may move —
//! link lengths, frame pivots, sliders' offsets, the tracer point — each within its bounds,
//! the least transmission angle and the largest crank ratio it must keep, and the kinematic
//! requirement: the path its tracer point must pass through, the swing of a rocker, a
//! rocker's angle against the crank's, a slider's stroke, or a slider's or a rocker's dwell.
//! Read, checked and resolved into [`Synthesis`], [`PathSpec`], [`SwingSpec`],
//! [`FunctionSpec`], [`StrokeSpec`] and [`DwellSpec`]; apart from `file.rs` so that each file
//! stays readable.

use super::model::{tip_of, Linkage};
use super::shape::{
    frame_pivot, slider_line, CrankRatio, DwellOf, DwellSpec, FunctionSpec, GeometryParam,
    JointBox, Kind, PathSpec, StrokeSpec, SwingSpec, Synthesis,
};
use crate::problem::{positive, FieldError};
use crate::units::{Angle, Dim, Length, Qty};

/// A pair of lengths: a point (x, y).
type XyRaw = crate::problem::Pair<Qty<Length>>;
use serde::Deserialize;

/// Geometry parameters a file may free, in all.
pub const MAX_FREE: usize = 10;

/// Precision points a path may have.
pub const MAX_POINTS: usize = 64;

/// `[design.synthesis]`: the geometry the search moves, and the search's size.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SynthesisRaw {
    /// Link lengths to choose: `of` a link with a length (the crank, an RRR link, an RRP
    /// rod), within [`min`, `max`]. A uniform bar's mass properties follow its length.
    #[serde(default)]
    #[schemars(length(max = MAX_FREE))]
    pub length: Vec<LengthFreeRaw>,
    /// Frame pivots to place: `of` a link pivoted on the frame (the crank: A0; an RRR link
    /// whose pivot is a frame point), within the box [`min`, `max`].
    #[serde(default)]
    #[schemars(length(max = MAX_FREE))]
    pub pivot: Vec<PivotFreeRaw>,
    /// Sliders' offsets to choose: `of` a slider (the second link of an RRP dyad), its
    /// line's signed distance e from the crank's pivot within [`min`, `max`] (the line
    /// moves along its normal; its direction stays).
    #[serde(default)]
    #[schemars(length(max = MAX_FREE))]
    pub offset: Vec<LengthFreeRaw>,
    /// The tracer point of `[objective.path]`, free within this box in its link's frame.
    pub tracer: Option<BoxRaw>,
    /// Halton points of the box ranked for the local searches (default 48, 8–4096).
    pub halton: Option<usize>,
    /// Local searches per front point (default 4, 1–64).
    pub starts: Option<usize>,
    /// Nelder–Mead iterations per local search (default 150, 10–5000).
    pub iterations: Option<usize>,
    /// Points of the kinematic error–objective front below `max_error` (default 3, 0–20).
    pub front_points: Option<usize>,
    /// The least transmission angle over the turn every candidate must keep (the angle
    /// between an RRR dyad's two links at their joint, folded into 0–90°), e.g. "40 deg".
    pub min_transmission_angle: Option<Qty<Angle>>,
    /// The largest crank ratio λ = r/l every candidate must keep (dimensionless, 0 < λ < 1):
    /// r the crank's length, l that of the rod of the RRP dyad on the crank's tip.
    pub max_crank_ratio: Option<f64>,
    /// The box every joint must stay inside over the whole turn (world frame): every
    /// link's reference joint and the tip of every link with a length.
    pub joint_box: Option<BoxRaw>,
}

/// A free link length.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LengthFreeRaw {
    /// The link.
    pub of: String,
    /// The shortest length.
    pub min: Qty<Length>,
    /// The longest length.
    pub max: Qty<Length>,
}

/// A free frame pivot.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PivotFreeRaw {
    /// The link pivoted on the frame.
    pub of: String,
    /// The box's lower corner (x, y).
    pub min: XyRaw,
    /// The box's upper corner (x, y).
    pub max: XyRaw,
}

/// A box of points.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BoxRaw {
    /// The lower corner (x, y).
    pub min: XyRaw,
    /// The upper corner (x, y).
    pub max: XyRaw,
}

/// `[objective.path]`: a point of a link through precision points (path generation; with
/// `crank_angles`, at those angles: path generation with prescribed timing).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PathRaw {
    /// The tracer point: `link` (a moving link) and `at` (in its frame).
    pub tracer: TracerRaw,
    /// The precision points (world frame), at least 2.
    #[schemars(length(min = 2, max = MAX_POINTS))]
    pub points: Vec<XyRaw>,
    /// The crank angle of each point (timing); absent: any angle over the turn.
    pub crank_angles: Option<Vec<Qty<Angle>>>,
    /// The path error the design must meet: the largest distance from a precision point to
    /// the tracer's path (at its crank angle, with timing).
    pub max_error: Qty<Length>,
}

/// `[objective.swing]`: the swing of a rocker over the turn (max − min of its angle).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SwingRaw {
    /// The rocker: a link pivoted on the frame.
    pub link: String,
    /// The swing to meet, below 180° (e.g. "60 deg").
    pub angle: Qty<Angle>,
    /// The swing error the design must meet, |swing − angle| (e.g. "0.5 deg").
    pub max_error: Qty<Angle>,
}

/// `[objective.function]`: a rocker's angle against the crank's (function generation), as
/// changes from the first point.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FunctionRaw {
    /// The rocker: a link pivoted on the frame.
    pub link: String,
    /// The crank angles θ_i, at least 2.
    #[schemars(length(min = 2, max = MAX_POINTS))]
    pub crank_angles: Vec<Qty<Angle>>,
    /// The rocker's angles ψ_i at them, one per crank angle: the design must turn the
    /// rocker by ψ_i − ψ_1 while the crank turns from θ_1 to θ_i.
    pub angles: Vec<Qty<Angle>>,
    /// The function error the design must meet: the largest |change of ψ − its target|.
    pub max_error: Qty<Angle>,
}

/// `[objective.stroke]`: the travel of a slider over the turn.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StrokeRaw {
    /// The slider: the second link of an RRP dyad.
    pub link: String,
    /// The stroke to meet: max − min of the slider's place along its line.
    pub stroke: Qty<Length>,
    /// The stroke error the design must meet, |stroke − target|.
    pub max_error: Qty<Length>,
}

/// `[objective.dwell]`: a slider or a rocker that stands still while the crank turns through
/// a window, and travels a stroke (a slider) or swings an angle (a rocker) over the turn (a
/// press's ram dwelling at the bottom of its stroke, an indexing arm at the end of its swing).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DwellRaw {
    /// The output: a slider (the second link of an RRP dyad) or a rocker (a dyad link
    /// pivoted on a frame point).
    pub link: String,
    /// The window [θ_a, θ_b] of crank angles the output must dwell over (θ_b below θ_a runs
    /// through 360°), shorter than a turn, e.g. ["150 deg", "210 deg"].
    pub crank_angles: crate::problem::Pair<Qty<Angle>>,
    /// A slider's stroke to meet over the turn: max − min of its place along its line.
    pub stroke: Option<Qty<Length>>,
    /// A rocker's swing to meet over the turn: max − min of its angle (below 180°).
    pub swing: Option<Qty<Angle>>,
    /// The dwell error the design must meet: the larger of the output's travel inside the
    /// window and |stroke − target| (a length, for a slider) or |swing − target| (an angle,
    /// for a rocker).
    pub max_error: crate::units::LengthOrAngle,
}

/// The tracer point of a path.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TracerRaw {
    /// A moving link.
    pub link: String,
    /// The point in the link's frame (origin at its reference joint, x along it).
    pub at: XyRaw,
}

fn xy(v: &XyRaw) -> crate::geom::P2 {
    crate::geom::P2::new(v[0].si(), v[1].si())
}

fn link_named(names: &[String], of: &str, key: &str) -> Result<usize, FieldError> {
    names.iter().position(|n| n == of).ok_or_else(|| {
        let all: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
        FieldError::new(
            key,
            format!("got \"{of}\"; allowed: a link, {}", all.join(", ")),
        )
    })
}

/// `[objective.path]` for the links `names`.
pub fn resolve_path(p: &PathRaw, names: &[String]) -> Result<PathSpec, FieldError> {
    let key = "objective.path";
    let link = link_named(names, &p.tracer.link, &format!("{key}.tracer.link"))?;
    if p.points.len() < 2 || p.points.len() > MAX_POINTS {
        return Err(FieldError::new(
            format!("{key}.points"),
            format!("got {} points; allowed: 2 to {MAX_POINTS}", p.points.len()),
        ));
    }
    let angles = match &p.crank_angles {
        Some(a) if a.len() != p.points.len() => {
            return Err(FieldError::new(
                format!("{key}.crank_angles"),
                format!(
                    "got {} angles for {} points; allowed: one per point",
                    a.len(),
                    p.points.len()
                ),
            ))
        }
        Some(a) => Some(a.iter().map(|q| q.si()).collect()),
        None => None,
    };
    Ok(PathSpec {
        link,
        at: xy(&p.tracer.at),
        points: p.points.iter().map(xy).collect(),
        angles,
        max_error: positive(&format!("{key}.max_error"), p.max_error.si())?,
    })
}

/// The rocker `of` of `l` (a dyad link pivoted on a frame point) at `key`.
fn rocker(l: &Linkage, names: &[String], of: &str, key: &str) -> Result<usize, FieldError> {
    let link = link_named(names, of, key)?;
    if !is_rocker(l, link) {
        return Err(FieldError::new(
            key,
            format!("link \"{of}\" is not a rocker; allowed: a dyad link pivoted on a frame point"),
        ));
    }
    Ok(link)
}

/// Whether link `link` of `l` is a rocker: a dyad link pivoted on a frame point.
fn is_rocker(l: &Linkage, link: usize) -> bool {
    link != 0 && frame_pivot(l, link).is_some()
}

/// A rocker's swing at `key`: positive and below 180° (the angle ψ is measured continuously
/// from its direction at θ = 0).
fn swing_angle(key: &str, v: f64) -> Result<f64, FieldError> {
    let angle = positive(key, v)?;
    if angle >= std::f64::consts::PI {
        return Err(FieldError::new(
            key,
            format!("got {}°; allowed: below 180°", angle.to_degrees()),
        ));
    }
    Ok(angle)
}

/// `[objective.function]` for the linkage `l` with links `names`.
pub fn resolve_function(
    f: &FunctionRaw,
    l: &Linkage,
    names: &[String],
) -> Result<FunctionSpec, FieldError> {
    let key = "objective.function";
    let link = rocker(l, names, &f.link, &format!("{key}.link"))?;
    let n = f.crank_angles.len();
    if !(2..=MAX_POINTS).contains(&n) {
        return Err(FieldError::new(
            format!("{key}.crank_angles"),
            format!("got {n} angles; allowed: 2 to {MAX_POINTS}"),
        ));
    }
    if f.angles.len() != n {
        return Err(FieldError::new(
            format!("{key}.angles"),
            format!(
                "got {} angles for {n} crank angles; allowed: one per crank angle",
                f.angles.len()
            ),
        ));
    }
    Ok(FunctionSpec {
        link,
        crank_angles: f.crank_angles.iter().map(|q| q.si()).collect(),
        angles: f.angles.iter().map(|q| q.si()).collect(),
        max_error: positive(&format!("{key}.max_error"), f.max_error.si())?,
    })
}

/// The slider `of` of `l` (the second link of an RRP dyad) at `key`.
fn slider(l: &Linkage, names: &[String], of: &str, key: &str) -> Result<usize, FieldError> {
    let link = link_named(names, of, key)?;
    if slider_line(l, link).is_none() {
        return Err(FieldError::new(
            key,
            format!("link \"{of}\" is not a slider; allowed: the second link of an RRP dyad"),
        ));
    }
    Ok(link)
}

/// `[objective.stroke]` for the linkage `l` with links `names`.
pub fn resolve_stroke(
    s: &StrokeRaw,
    l: &Linkage,
    names: &[String],
) -> Result<StrokeSpec, FieldError> {
    let key = "objective.stroke";
    Ok(StrokeSpec {
        link: slider(l, names, &s.link, &format!("{key}.link"))?,
        stroke: positive(&format!("{key}.stroke"), s.stroke.si())?,
        max_error: positive(&format!("{key}.max_error"), s.max_error.si())?,
    })
}

/// `[objective.dwell]` for the linkage `l` with links `names`: a slider with its `stroke` and
/// an error in length, or a rocker with its `swing` and an error in angle.
pub fn resolve_dwell(d: &DwellRaw, l: &Linkage, names: &[String]) -> Result<DwellSpec, FieldError> {
    let key = "objective.dwell";
    let tau = std::f64::consts::TAU;
    let (a, b) = (d.crank_angles[0].si(), d.crank_angles[1].si());
    let from = a.rem_euclid(tau);
    let to = from + (b - a).rem_euclid(tau);
    if !(a.is_finite() && b.is_finite()) || to == from {
        return Err(FieldError::new(
            format!("{key}.crank_angles"),
            format!(
                "got [{:.6}°, {:.6}°]; allowed: two different angles, a window shorter than a turn",
                a.to_degrees(),
                b.to_degrees()
            ),
        ));
    }
    let link = link_named(names, &d.link, &format!("{key}.link"))?;
    let is_slider = slider_line(l, link).is_some();
    if !is_slider && !is_rocker(l, link) {
        return Err(FieldError::new(
            format!("{key}.link"),
            format!("link \"{}\" is neither a slider nor a rocker; allowed: the second link of an RRP dyad, or a dyad link pivoted on a frame point", d.link),
        ));
    }
    let wrong = |k: &str, why: &str| Err(FieldError::new(format!("{key}.{k}"), why.to_string()));
    let (of, range, dim) = match (is_slider, &d.stroke, &d.swing) {
        (true, Some(s), None) => (DwellOf::Slider, s.si(), Dim::Length),
        (false, None, Some(w)) => (DwellOf::Rocker, w.si(), Dim::Angle),
        (true, _, Some(_)) => {
            return wrong(
                "swing",
                "the output is a slider: give its stroke (a length), not a swing",
            )
        }
        (true, None, None) => {
            return wrong(
                "stroke",
                "a slider's dwell needs its stroke over the turn (a length, e.g. \"40 mm\")",
            )
        }
        (false, Some(_), _) => {
            return wrong(
                "stroke",
                "the output is a rocker: give its swing (an angle), not a stroke",
            )
        }
        (false, None, None) => {
            return wrong(
                "swing",
                "a rocker's dwell needs its swing over the turn (an angle, e.g. \"30 deg\")",
            )
        }
    };
    if d.max_error.dim != dim {
        return Err(FieldError::new(
            format!("{key}.max_error"),
            format!(
                "got a {}; allowed: a {} for a {} (e.g. \"{}\")",
                d.max_error.dim.name(),
                dim.name(),
                of.name(),
                if dim == Dim::Length {
                    "0.5 mm"
                } else {
                    "0.5 deg"
                }
            ),
        ));
    }
    Ok(DwellSpec {
        link,
        of,
        from,
        to,
        range: match of {
            DwellOf::Slider => positive(&format!("{key}.stroke"), range)?,
            DwellOf::Rocker => swing_angle(&format!("{key}.swing"), range)?,
        },
        max_error: positive(&format!("{key}.max_error"), d.max_error.si)?,
    })
}

/// `max_crank_ratio` of the linkage `l` at `key`: 0 < λ < 1, with an RRP dyad whose rod is
/// pivoted on the crank's tip.
fn crank_ratio(l: &Linkage, max: f64, key: &str) -> Result<CrankRatio, FieldError> {
    if !(max > 0.0 && max < 1.0) {
        return Err(FieldError::new(
            key,
            format!("got {max}; allowed: 0 < λ < 1 (e.g. 0.3)"),
        ));
    }
    let on_tip = |p: &super::model::Point| matches!(p, super::model::Point::On { link: 0, at } if at.y == 0.0 && at.x > 0.0);
    let k = (l.dyads().iter())
        .position(|d| matches!(d, super::model::Dyad::Rrp { p, .. } if on_tip(p)))
        .ok_or_else(|| FieldError::new(key, "no RRP dyad's rod is pivoted on the crank's tip"))?;
    Ok(CrankRatio {
        max,
        rod: Linkage::dyad_links(k).0,
    })
}

/// `[objective.swing]` for the linkage `l` with links `names`.
pub fn resolve_swing(s: &SwingRaw, l: &Linkage, names: &[String]) -> Result<SwingSpec, FieldError> {
    let key = "objective.swing";
    let link = rocker(l, names, &s.link, &format!("{key}.link"))?;
    let angle = swing_angle(&format!("{key}.angle"), s.angle.si())?;
    Ok(SwingSpec {
        link,
        angle,
        max_error: positive(&format!("{key}.max_error"), s.max_error.si())?,
    })
}

/// A count with its default and range, or the error naming it.
fn count(
    v: Option<usize>,
    key: &str,
    default: usize,
    lo: usize,
    hi: usize,
) -> Result<usize, FieldError> {
    match v.unwrap_or(default) {
        n if (lo..=hi).contains(&n) => Ok(n),
        n => Err(FieldError::new(
            format!("design.synthesis.{key}"),
            format!("got {n}; allowed: {lo} to {hi}"),
        )),
    }
}

/// An interval [lo, hi] of a parameter, checked (lo < hi). The mechanism's own value need
/// not lie inside: it seeds the search where it does (a drag in the designer may move it
/// out).
fn interval(lo: f64, hi: f64, key: &str) -> Result<(f64, f64), FieldError> {
    if !(lo < hi) {
        return Err(FieldError::new(
            key,
            format!("got min {lo} ≥ max {hi}; allowed: min < max"),
        ));
    }
    Ok((lo, hi))
}

/// `[design.synthesis]` for the linkage `l` with links `names`, its crank `crank_length`
/// long, `bars[i]` true where link i is a uniform bar, and which kinematic requirements
/// the file has — [path, swing, function, stroke, dwell]: exactly one required.
pub fn resolve_synthesis(
    r: &SynthesisRaw,
    (l, names, crank_length): (&Linkage, &[String], f64),
    kin: [bool; 5],
    bars: &[bool],
) -> Result<Synthesis, FieldError> {
    let key = "design.synthesis";
    if kin.iter().filter(|&&k| k).count() != 1 {
        return Err(FieldError::new(
            key,
            "a shape search needs one kinematic requirement; allowed: [objective.path], [objective.swing], [objective.function], [objective.stroke] or [objective.dwell]",
        ));
    }
    if r.tracer.is_some() && !kin[0] {
        return Err(FieldError::new(
            format!("{key}.tracer"),
            "a free tracer needs [objective.path]",
        ));
    }
    let min_transmission = match &r.min_transmission_angle {
        Some(q) => {
            let k = format!("{key}.min_transmission_angle");
            let mu = positive(&k, q.si())?;
            if mu >= std::f64::consts::FRAC_PI_2 {
                return Err(FieldError::new(
                    k,
                    format!("got {}°; allowed: below 90°", mu.to_degrees()),
                ));
            }
            if !l
                .dyads()
                .iter()
                .any(|d| matches!(d, super::model::Dyad::Rrr { .. }))
            {
                return Err(FieldError::new(k, "the linkage has no RRR dyad"));
            }
            Some(mu)
        }
        None => None,
    };
    let joint_box = match &r.joint_box {
        Some(b) => {
            let k = format!("{key}.joint_box");
            let (lo, hi) = (xy(&b.min), xy(&b.max));
            interval(lo.x, hi.x, &k)?;
            interval(lo.y, hi.y, &k)?;
            Some(JointBox { min: lo, max: hi })
        }
        None => None,
    };
    let max_crank_ratio = (r.max_crank_ratio)
        .map(|m| crank_ratio(l, m, &format!("{key}.max_crank_ratio")))
        .transpose()?;
    let mut params = Vec::new();
    for (i, f) in r.length.iter().enumerate() {
        let k = format!("{key}.length[{i}]");
        let link = link_named(names, &f.of, &format!("{k}.of"))?;
        if tip_of(l.dyads(), crank_length, link).is_none() {
            return Err(FieldError::new(
                format!("{k}.of"),
                format!(
                    "link \"{}\" has no length (only the crank, RRR links and RRP rods have one)",
                    f.of
                ),
            ));
        }
        let lo = positive(&format!("{k}.min"), f.min.si())?;
        let bounds = interval(lo, f.max.si(), &k)?;
        push(
            &mut params,
            &k,
            format!("length of {}", f.of),
            Kind::Length {
                link,
                bar: bars.get(link).copied().unwrap_or(false),
            },
            bounds,
        )?;
    }
    for (i, f) in r.pivot.iter().enumerate() {
        let k = format!("{key}.pivot[{i}]");
        let link = link_named(names, &f.of, &format!("{k}.of"))?;
        if frame_pivot(l, link).is_none() {
            return Err(FieldError::new(
                format!("{k}.of"),
                format!("link \"{}\" is not pivoted on the frame; allowed: the crank or a link whose pivot is a frame point [x, y]", f.of),
            ));
        }
        let (lo, hi) = (xy(&f.min), xy(&f.max));
        let bx = interval(lo.x, hi.x, &k)?;
        let by = interval(lo.y, hi.y, &k)?;
        push(
            &mut params,
            &k,
            format!("pivot of {} x", f.of),
            Kind::PivotX { link },
            bx,
        )?;
        push(
            &mut params,
            &k,
            format!("pivot of {} y", f.of),
            Kind::PivotY { link },
            by,
        )?;
    }
    for (i, f) in r.offset.iter().enumerate() {
        let k = format!("{key}.offset[{i}]");
        let link = slider(l, names, &f.of, &format!("{k}.of"))?;
        push(
            &mut params,
            &k,
            format!("offset of {}", f.of),
            Kind::LineOffset { link },
            interval(f.min.si(), f.max.si(), &k)?,
        )?;
    }
    if let Some(b) = &r.tracer {
        let k = format!("{key}.tracer");
        let (lo, hi) = (xy(&b.min), xy(&b.max));
        push(
            &mut params,
            &k,
            "tracer x".into(),
            Kind::TracerX,
            interval(lo.x, hi.x, &k)?,
        )?;
        push(
            &mut params,
            &k,
            "tracer y".into(),
            Kind::TracerY,
            interval(lo.y, hi.y, &k)?,
        )?;
    }
    if params.is_empty() {
        return Err(FieldError::new(
            key,
            "nothing free; allowed: at least one [[design.synthesis.length]], [[design.synthesis.pivot]], [[design.synthesis.offset]] or [design.synthesis.tracer]",
        ));
    }
    let search = crate::synth::search::constrained::Settings {
        halton: count(r.halton, "halton", 48, 8, 4096)?,
        starts: count(r.starts, "starts", 4, 1, 64)?,
        max_iters: count(r.iterations, "iterations", 150, 10, 5000)? as u64,
        sd_tolerance: 1e-9,
    };
    Ok(Synthesis {
        params,
        min_transmission,
        max_crank_ratio,
        joint_box,
        search,
        front_points: count(r.front_points, "front_points", 3, 0, 20)?,
    })
}

/// The shape search's budget in candidate geometries ([`check_search_work`]): each a
/// kinematic error and, within its bound, a certified cone program (about 0.1–0.3 ms on
/// the shipped four-bars), so a search stays within about two minutes at worst.
pub const SEARCH_BUDGET: f64 = 5e5;

/// The shape search's work, counted in candidate geometries at worst —
/// (`front_points` + 2)·(`halton` + `starts`·`iterations`·(n + 1)), n the free parameters
/// (the least-error search, the front's points and the design each search from the Halton
/// points; a Nelder–Mead iteration evaluates at most n + 1 points, its shrink) — against
/// [`SEARCH_BUDGET`]: each setting alone may be at its largest on the shipped files, but
/// their product would run for hours.
pub fn check_search_work(syn: &Synthesis) -> Result<(), FieldError> {
    let s = &syn.search;
    let f = |v: usize| v as f64;
    let n = f(syn.params.len());
    let estimate =
        f(syn.front_points + 2) * (f(s.halton) + f(s.starts) * s.max_iters as f64 * (n + 1.0));
    let t = |k, v: f64, d: f64| crate::problem::limits::term(k, v, d);
    crate::problem::limits::check_work(
        SEARCH_BUDGET,
        "shape-search",
        estimate,
        "(front_points + 2)·(halton + starts·iterations·(free parameters + 1))",
        &[
            t("design.synthesis.halton", f(s.halton), 48.0),
            t("design.synthesis.starts", f(s.starts), 4.0),
            t("design.synthesis.iterations", s.max_iters as f64, 150.0),
            t("design.synthesis.front_points", f(syn.front_points), 3.0),
        ],
    )
}

/// Adds a parameter unless one of the same kind is free already.
fn push(
    params: &mut Vec<GeometryParam>,
    key: &str,
    name: String,
    kind: Kind,
    bounds: (f64, f64),
) -> Result<(), FieldError> {
    if params.iter().any(|p| p.kind == kind) {
        return Err(FieldError::new(key, format!("{name} is free already")));
    }
    if params.len() >= MAX_FREE {
        return Err(FieldError::new(
            key,
            format!("more than {MAX_FREE} free parameters; allowed: at most {MAX_FREE}"),
        ));
    }
    params.push(GeometryParam { name, kind, bounds });
    Ok(())
}
