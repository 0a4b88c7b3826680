//! The linkage problem file — its raw sections and their resolution into a checked
//! [`LinkageScene`]: the [`Linkage`] (crank, dyads, link masses), the counterweights that may be
//! added and the objective (every field documented in `docs/problem-files.md`, family
//! `linkage`).
//!
//! Links are named in the file: `crank`, then the two names each dyad gives in `links`. A point
//! of the mechanism is written as a frame point `["100 mm", "0 mm"]`, as `"NAME.pivot"` (the
//! link's reference joint) or `"NAME.tip"` (its other joint: the crank pin, an RRR link's
//! joint B, an RRP rod's slider pin), or as a point fixed to a link,
//! `{ link = "coupler", at = ["60 mm", "20 mm"] }`, in the link's own frame (origin at its
//! reference joint, x axis along it).

use crate::families::linkage::model::{tip_of, Dyad, Inertia, Linkage, Point};
use crate::geom::outline::{Edge, Plate};
use crate::geom::{Side, P2};
use crate::problem::limits::{self, c, Count};
use crate::problem::outline::{self, set_by, OutlineRaw, Placement, OUTLINE_SETS};
use crate::problem::{
    check_name, non_negative, positive, Ctx, FieldError, Input, ProblemError, RawFile, RawVar,
    Resolved,
};
use crate::synth::minimax::Settings;
use crate::synth::Var;
use crate::units::{Acceleration, Angle, AngularSpeed, Density, Force, Inertia as InertiaDim};
use crate::units::{Length, Mass, Qty, Torque};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// The `family = "…"` value of this family's files.
pub const FAMILY: &str = "linkage";

/// The problem file `cwsynth new` prints: a clean template (`templates/`), not a paper's
/// scene.
pub const TEMPLATE: &str = include_str!("../../../templates/linkage.toml");

/// Dyads a file may chain (each adds two links and a closed-form construction per angle).
pub const MAX_DYADS: usize = 32;

/// Counterweights a file may ask for.
pub const MAX_COUNTERWEIGHTS: usize = 16;

/// The integer keys of this family's file and their ranges (see [`crate::problem::limits`]).
pub const COUNTS: &[Count] = &[
    c("objective.pareto_points", 0, 200),
    c("accuracy.initial_samples", 3, 1024),
    c("accuracy.scan_samples", 16, 20_000),
    c("accuracy.max_rounds", 1, 1000),
    c("accuracy.rms_samples", 16, 100_000),
    c("design.synthesis.halton", 8, 4096),
    c("design.synthesis.starts", 1, 64),
    c("design.synthesis.iterations", 10, 5000),
    c("design.synthesis.front_points", 0, 20),
];

/// The work budget of one scene (see [`limits::check_work`]): field evaluations (one dyad
/// chain each), so one machine runs in seconds.
pub const WORK_BUDGET: f64 = 5e7;

/// A pair of lengths: a point in the plane (x, y).
pub type XyRaw = crate::problem::Pair<Qty<Length>>;

/// `[mechanism]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MechanismRaw {
    /// ω, the constant crank speed.
    pub speed: Qty<AngularSpeed>,
    /// A0, the crank's frame pivot (default the origin).
    pub crank_pivot: Option<XyRaw>,
    /// The crank's length |A0 A| (to its tip, the crank pin).
    pub crank_length: Qty<Length>,
    /// g: the weights act in −y (default: not modelled). Only the input torque feels them.
    pub gravity: Option<Qty<Acceleration>>,
    /// The dyads, in order: each uses points already defined.
    #[serde(default)]
    #[schemars(length(max = MAX_DYADS))]
    pub dyads: Vec<DyadRaw>,
    /// Mass data of every link, by name (`crank` and the dyads' `links`).
    #[serde(default)]
    pub links: BTreeMap<String, LinkRaw>,
    /// The drive: motor, flywheel and the coefficient of speed fluctuation to meet
    /// (`[mechanism.drive]`, the machine as it runs).
    pub drive: Option<crate::problem::drive::DriveRaw>,
    /// Process forces on points of links (a press's pressing force): they enter the input
    /// torque, the drive and the joint loads, not the shaking force.
    #[serde(default)]
    #[schemars(length(max = super::file_loads::MAX_LOADS))]
    pub loads: Vec<super::file_loads::LoadRaw>,
    /// The operating envelope: a speed band and link-mass intervals; every objective and
    /// limit then means the worst case over it.
    pub envelope: Option<super::file_envelope::LinkageEnvelopeRaw>,
    /// Named load cases: each its own process loads in place of `[[mechanism.loads]]` (the
    /// nominal case); every objective and limit then means the worst case over them.
    #[serde(default)]
    #[schemars(length(max = crate::problem::envelope::MAX_LOAD_CASES))]
    pub load_cases: Vec<super::file_loads::LoadCaseRaw>,
}

/// The kinds of dyad.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
pub enum DyadKind {
    /// Revolute–revolute–revolute: two links from two known points meeting at a new joint.
    #[serde(rename = "RRR")]
    Rrr,
    /// Revolute–revolute–prismatic: a rod from a known point to a slider on a frame line.
    #[serde(rename = "RRP")]
    Rrp,
    /// Revolute–prismatic–revolute: a guide pivoted at a known point, a block sliding on it
    /// pivoted at another known point.
    #[serde(rename = "RPR")]
    Rpr,
}

/// The assembly branch of a dyad.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Branch {
    /// RRR: B to the left of P→Q; RRP: B further along the line than the foot of P; RPR: Q
    /// ahead of P along the slide.
    Left,
    /// The other one.
    Right,
}

/// `[[mechanism.dyads]]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DyadRaw {
    /// `RRR`, `RRP` or `RPR`.
    pub kind: DyadKind,
    /// The names of its two links (RRR: from p, from q; RRP: rod, slider; RPR: guide, block).
    pub links: [String; 2],
    /// P: the first known point.
    #[schemars(schema_with = "crate::problem::schema::point_ref")]
    pub p: toml::Value,
    /// Q: the second known point (RRR, RPR).
    #[serde(default)]
    #[schemars(schema_with = "crate::problem::schema::point_ref")]
    pub q: Option<toml::Value>,
    /// RRR: |PB|.
    pub length1: Option<Qty<Length>>,
    /// RRR: |QB|.
    pub length2: Option<Qty<Length>>,
    /// RRP: the rod's length |PB|.
    pub length: Option<Qty<Length>>,
    /// RRP: a point of the slider's frame line.
    pub line_point: Option<XyRaw>,
    /// RRP: the line's direction.
    pub line_angle: Option<Qty<Angle>>,
    /// RPR: the slide line's offset from P (to the left of its direction; default 0).
    pub offset: Option<Qty<Length>>,
    /// The assembly branch.
    pub branch: Branch,
}

/// `[mechanism.links.NAME]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LinkRaw {
    /// m (required unless `outline`).
    pub mass: Option<Qty<Mass>>,
    /// c, the centroid in the link's frame (required unless `uniform_bar`).
    pub centroid: Option<XyRaw>,
    /// J, the moment of inertia about the centroid (required unless `uniform_bar`).
    pub inertia: Option<Qty<InertiaDim>>,
    /// A uniform bar along the link (c at half its length, J = m l²/12): links with a length
    /// only (crank, RRR links, RRP rod).
    #[serde(default)]
    pub uniform_bar: bool,
    /// The link drawn as a plate in a DXF file: its mass, centroid and inertia from the
    /// drawing (the drawing's origin at the link's reference joint, its x axis along the
    /// link, unless `origin` and `angle` say otherwise); not together with `mass`,
    /// `centroid`, `inertia`, `uniform_bar`.
    pub outline: Option<OutlineRaw>,
}

/// `[model]`.
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelRaw {
    /// O, the frame point the shaking moment is taken about (default the crank pivot).
    pub moment_about: Option<XyRaw>,
}

/// `[[design.counterweights]]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CounterweightRaw {
    /// The link it is fixed to (by name).
    pub link: String,
    /// Its mass: fixed or a range (`{ min = "0 kg", max = "2 kg" }`; required unless
    /// `outline`).
    pub mass: Option<RawVar<Mass>>,
    /// The envelope: all of it within this distance of the link's reference joint (so its
    /// centroid too: |u| ≤ m r, and I ≤ m r²).
    pub radius: Qty<Length>,
    /// Directions its centroid may take in the link's frame, at most 180° wide (default any).
    pub sector: Option<RawVar<Angle>>,
    /// The plate's material: its density gives the thickness of the annular sector that
    /// realises the counterweight (t = m / (ρ · area)).
    pub density: Option<Qty<Density>>,
    /// The plate's thickness t (with `density`): the counterweight is then a flat plate of
    /// areal density σ = ρt cut within `radius`, and the plate's necessary conditions are
    /// constraints of the design (m ≤ σπr²; its first moment at most the circular
    /// segment's of its area; its inertia between the disc's and the rim annulus's); the
    /// result gives the plate that realises it.
    pub thickness: Option<Qty<Length>>,
    /// A given counterweight's centroid in the link's frame (with a fixed `mass`): fixes its
    /// first moment u = m c.
    pub centroid: Option<XyRaw>,
    /// A given counterweight's moment of inertia about its own centroid (with `centroid`):
    /// fixes I about the joint, I_c + m |c|². Mass, centroid and inertia all given: the
    /// counterweight is analysed, not designed.
    pub inertia: Option<Qty<InertiaDim>>,
    /// A given counterweight drawn as a plate in a DXF file: its mass, centroid and inertia
    /// from the drawing (origin at the link's reference joint, x axis along the link, unless
    /// `origin` and `angle` say otherwise); not together with `mass`, `centroid`, `inertia`,
    /// `sector`, `density`.
    pub outline: Option<OutlineRaw>,
}

/// `[design]`.
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignRaw {
    /// The counterweights the optimiser sizes (none: the linkage is analysed).
    #[serde(default)]
    #[schemars(length(max = MAX_COUNTERWEIGHTS))]
    pub counterweights: Vec<CounterweightRaw>,
    /// The geometry a shape search moves (issue 36): link lengths, frame pivots and the
    /// tracer point of `[objective.path]`, each within bounds.
    pub synthesis: Option<super::file_synthesis::SynthesisRaw>,
}

/// What `objective.minimize` can name.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Goal {
    /// max_θ |F|.
    PeakForce,
    /// max_θ |M_O|.
    PeakMoment,
    /// max_θ |T|.
    PeakTorque,
    /// RMS of |F| over the cycle.
    RmsForce,
    /// RMS of M_O.
    RmsMoment,
    /// RMS of T.
    RmsTorque,
    /// The total counterweight mass (with limits on the fields).
    CounterweightMass,
    /// The energy fluctuation ΔE = max E − min E of the input torque at constant speed,
    /// E = ∫₀^θ (T − T̄) dθ (`crate::synth::energy`): the least flywheel's driver.
    EnergyFluctuation,
}

/// `[objective]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectiveRaw {
    /// What the counterweights minimise.
    pub minimize: Goal,
    /// Limit on the peak shaking force.
    pub max_peak_force: Option<Qty<Force>>,
    /// Limit on the peak shaking moment about O.
    pub max_peak_moment: Option<Qty<Torque>>,
    /// Limit on the peak input torque.
    pub max_peak_torque: Option<Qty<Torque>>,
    /// Limit on every joint's peak load (a bearing's rating): |R| of a pin, the normal force
    /// of a slide.
    pub max_joint_force: Option<Qty<Force>>,
    /// `true`: the total centre of mass stationary (shaking force 0 at every angle).
    #[serde(default)]
    pub full_force_balance: bool,
    /// Points of the peak-force against peak-moment front (0: none).
    #[serde(default)]
    pub pareto_points: u32,
    /// A tracer point through precision points: its path error is reported, and with
    /// `[design.synthesis]` it is the shape search's kinematic requirement.
    pub path: Option<super::file_synthesis::PathRaw>,
    /// A rocker's swing over the turn: reported, and with `[design.synthesis]` the shape
    /// search's kinematic requirement (instead of a path).
    pub swing: Option<super::file_synthesis::SwingRaw>,
    /// A rocker's angle against the crank's at given points (function generation):
    /// reported, and with `[design.synthesis]` the shape search's kinematic requirement.
    pub function: Option<super::file_synthesis::FunctionRaw>,
    /// A slider's stroke over the turn: reported, and with `[design.synthesis]` the shape
    /// search's kinematic requirement.
    pub stroke: Option<super::file_synthesis::StrokeRaw>,
    /// A slider's or a rocker's dwell over a window of the turn, with its stroke or swing:
    /// reported, and with `[design.synthesis]` the shape search's kinematic requirement.
    pub dwell: Option<super::file_synthesis::DwellRaw>,
}

/// `[accuracy]`: the engine's [`Settings`] read directly (every key optional, unknown keys
/// rejected), then validated; errors name `accuracy.<key>`.
pub type AccuracyRaw = Settings;

/// The whole linkage file.
pub type File = RawFile<MechanismRaw, ModelRaw, DesignRaw, ObjectiveRaw, AccuracyRaw>;

/// A resolved linkage scene with its settings.
#[derive(Debug, Clone)]
pub struct LinkageProblem {
    /// The scene.
    pub scene: LinkageScene,
    /// The exchange loop's settings.
    pub settings: Settings,
    /// The drive at real speed (`[mechanism.drive]`), if given.
    pub drive: Option<crate::dynamics::Drive>,
    /// The path (`[objective.path]`), if given.
    pub path: Option<super::shape::PathSpec>,
    /// The rocker's swing (`[objective.swing]`), if given.
    pub swing: Option<super::shape::SwingSpec>,
    /// The rocker's function (`[objective.function]`), if given.
    pub function: Option<super::shape::FunctionSpec>,
    /// The slider's stroke (`[objective.stroke]`), if given.
    pub stroke: Option<super::shape::StrokeSpec>,
    /// The slider's or rocker's dwell (`[objective.dwell]`), if given.
    pub dwell: Option<super::shape::DwellSpec>,
    /// The shape search (`[design.synthesis]`), if given.
    pub synthesis: Option<super::shape::Synthesis>,
    /// What the shape search found, once it has run: the scene is then its chosen geometry
    /// (`synthesis::drive`).
    pub shape: Option<super::shape::ShapeOutcome>,
}

impl LinkageProblem {
    /// The shape search's kinematic requirement: the path, the swing, the function, the
    /// stroke or the dwell (a file with a search has one of them).
    pub fn requirement(&self) -> Option<super::shape::Requirement<'_>> {
        use super::shape::Requirement;
        (self.path.as_ref().map(Requirement::Path))
            .or(self.swing.as_ref().map(Requirement::Swing))
            .or(self.function.as_ref().map(Requirement::Function))
            .or(self.stroke.as_ref().map(Requirement::Stroke))
            .or(self.dwell.as_ref().map(Requirement::Dwell))
    }
}

/// Reads and resolves a linkage problem file (its text or its table).
/// A drawing named in an `outline` key is read relative to the file's folder ([`Ctx::dir`]: a
/// fleet row's is its template's).
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Resolved<LinkageProblem>, ProblemError> {
    let dir = ctx.dir();
    File::resolve(ctx, input, |raw| resolve_raw(raw, dir))
}

/// The value checks of a linkage file; `dir` is the folder `outline` drawings are read from.
pub fn resolve_raw(raw: &File, dir: &Path) -> Result<LinkageProblem, FieldError> {
    let scene = resolve_scene(
        &raw.name,
        &raw.mechanism,
        &raw.model,
        &raw.design,
        &raw.objective,
        dir,
    )?;
    let settings = raw.accuracy;
    limits::check_section(COUNTS, "accuracy", &settings)?;
    settings.validate().map_err(|(key, message)| {
        FieldError::new(format!("accuracy.{key}"), format!("{key} {message}"))
    })?;
    check_work(&scene, &settings)?;
    let drive = raw
        .mechanism
        .drive
        .as_ref()
        .map(crate::problem::drive::resolve)
        .transpose()?;
    let path = (raw.objective.path.as_ref())
        .map(|p| super::file_synthesis::resolve_path(p, &scene.link_names))
        .transpose()?;
    let swing = (raw.objective.swing.as_ref())
        .map(|s| super::file_synthesis::resolve_swing(s, &scene.linkage, &scene.link_names))
        .transpose()?;
    let function = (raw.objective.function.as_ref())
        .map(|f| super::file_synthesis::resolve_function(f, &scene.linkage, &scene.link_names))
        .transpose()?;
    let stroke = (raw.objective.stroke.as_ref())
        .map(|s| super::file_synthesis::resolve_stroke(s, &scene.linkage, &scene.link_names))
        .transpose()?;
    let dwell = (raw.objective.dwell.as_ref())
        .map(|d| super::file_synthesis::resolve_dwell(d, &scene.linkage, &scene.link_names))
        .transpose()?;
    let bars: Vec<bool> = (scene.link_names.iter())
        .map(|n| raw.mechanism.links.get(n).is_some_and(|l| l.uniform_bar))
        .collect();
    let synthesis = (raw.design.synthesis.as_ref())
        .map(|r| {
            let l = (&scene.linkage, &scene.link_names[..], scene.crank_length);
            let kin = [
                path.is_some(),
                swing.is_some(),
                function.is_some(),
                stroke.is_some(),
                dwell.is_some(),
            ];
            super::file_synthesis::resolve_synthesis(r, l, kin, &bars)
        })
        .transpose()?;
    if let Some(syn) = &synthesis {
        super::file_synthesis::check_search_work(syn)?;
    }
    Ok(LinkageProblem {
        scene,
        settings,
        drive,
        path,
        swing,
        function,
        stroke,
        dwell,
        synthesis,
        shape: None,
    })
}

/// The work budget ([`limits::check_work`]): each SOCP round scans the three fields
/// (`scan_samples` evaluations of the dyad chain, 2 + 2·dyads links each); at most
/// `max_rounds` rounds per solve, and 2 + `pareto_points` solves.
fn check_work(sc: &LinkageScene, s: &Settings) -> Result<(), FieldError> {
    let d = Settings::default();
    let f = |v: usize| v as f64;
    let links = f(sc.linkage.n_links());
    let solves = 1.0
        + if sc.objective.pareto_points > 0 {
            2.0 + f(sc.objective.pareto_points)
        } else {
            0.0
        };
    let estimate =
        3.0 * links * (f(s.scan_samples) + f(s.rms_samples)) * f(s.max_rounds.min(30)) * solves;
    let t = |k, v: f64, d: f64| limits::term(k, v, d);
    limits::check_work(
        WORK_BUDGET,
        FAMILY,
        estimate,
        "3·links·(scan_samples + rms_samples)·min(max_rounds, 30)·(1 + (2 + pareto_points if any))",
        &[
            t(
                "accuracy.scan_samples",
                f(s.scan_samples),
                f(d.scan_samples),
            ),
            t("accuracy.rms_samples", f(s.rms_samples), f(d.rms_samples)),
            t(
                "objective.pareto_points",
                f(sc.objective.pareto_points),
                0.0,
            ),
            t("mechanism.dyads", f(sc.linkage.dyads().len()), 1.0),
        ],
    )
}

/// A counterweight the optimiser sizes, resolved (SI, link index).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CounterweightSpec {
    /// Link index (0 the crank).
    pub link: usize,
    /// The link's name.
    pub link_name: String,
    /// Mass (kg), fixed or free.
    pub mass: Var,
    /// Envelope radius about the link's reference joint (m).
    pub radius: f64,
    /// Sector of centroid directions in the link's frame (rad, width ≤ π), if limited.
    pub sector: Option<(f64, f64)>,
    /// A given centroid in the link's frame (m) and, with it, a given moment of inertia
    /// about the centroid (kg·m²): (c, I_c).
    pub given: Option<(P2, Option<f64>)>,
    /// The plate's density (kg/m³), if given.
    pub density: Option<f64>,
    /// The plate's thickness (m), if given (with `density`): a plate of the design.
    pub thickness: Option<f64>,
    /// A drawn counterweight's outline (`outline`): its closed loops in the link's frame
    /// (m), to draw it as drawn.
    #[serde(skip)]
    pub drawing: Option<Vec<Vec<Edge>>>,
    /// Where a drawn counterweight's drawing sits on its link (`outline`'s `origin` and
    /// `angle`): the designer's handle for a given `origin`.
    #[serde(skip)]
    pub placement: Option<Placement>,
}

/// A link drawn in a DXF file (`[mechanism.links.NAME] outline`), as the designer draws it:
/// its closed loops in the link's frame (m) and where the drawing sits there.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnLink {
    /// The outline's closed loops in the link's frame (m).
    pub loops: Vec<Vec<Edge>>,
    /// `outline`'s `origin` and `angle`.
    pub placement: Placement,
}

impl CounterweightSpec {
    /// Whether mass, centroid and inertia are all given: nothing of it is designed.
    pub fn is_given(&self) -> bool {
        matches!(self.mass, Var::Fixed(_)) && matches!(self.given, Some((_, Some(_))))
    }
    /// σ = ρt (kg/m²), for a counterweight designed as a plate of given thickness.
    pub fn areal_density(&self) -> Option<f64> {
        Some(self.density? * self.thickness?)
    }
}

/// The objective, resolved (SI).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Objective {
    /// What is minimised.
    pub minimize: Goal,
    /// Limit on the peak |F| (N).
    pub max_peak_force: Option<f64>,
    /// Limit on the peak |M_O| (N·m).
    pub max_peak_moment: Option<f64>,
    /// Limit on the peak |T| (N·m).
    pub max_peak_torque: Option<f64>,
    /// Limit on every joint's peak load (N).
    pub max_joint_force: Option<f64>,
    /// Full force balance asked for.
    pub full_force_balance: bool,
    /// Pareto points (0 none).
    pub pareto_points: usize,
}

/// A resolved linkage scene (everything in SI).
#[derive(Debug, Clone)]
pub struct LinkageScene {
    /// The mechanism with its link masses.
    pub linkage: Linkage,
    /// |A0 A|, the crank's length to its pin (m).
    pub crank_length: f64,
    /// Link names, index = link (crank first).
    pub link_names: Vec<String>,
    /// O, the moment point (m).
    pub moment_about: P2,
    /// The counterweights to size.
    pub counterweights: Vec<CounterweightSpec>,
    /// The objective.
    pub objective: Objective,
    /// The operating envelope (empty: the nominal machine only).
    pub envelope: super::envelope::LinkageEnvelope,
    /// Each link drawn in a DXF file (`outline`), index = link; `None` for a link given by
    /// its numbers (the designer draws the drawn ones).
    pub drawn_links: Vec<Option<DrawnLink>>,
}

fn xy(v: &XyRaw) -> P2 {
    v.si()
}

/// Reads a point reference (`[x, y]`, `"NAME.pivot"`, `"NAME.tip"`, `{ link, at }`) with the
/// links known so far.
fn point(
    key: &str,
    v: &toml::Value,
    names: &[String],
    dyads: &[Dyad],
    crank_length: f64,
) -> Result<Point, FieldError> {
    const ALLOWED: &str = "allowed: a frame point [\"x mm\", \"y mm\"], \"NAME.pivot\", \"NAME.tip\" or { link = \"NAME\", at = [\"x mm\", \"y mm\"] } for a link defined before this dyad";
    let link_of = |name: &str| {
        names.iter().position(|n| n == name).ok_or_else(|| {
            let hint = crate::units::did_you_mean(name, names.iter().map(String::as_str))
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            FieldError::new(
                key,
                format!(
                    "no link `{name}` is defined before this dyad{hint}; known: {}; {ALLOWED}",
                    names.join(", ")
                ),
            )
        })
    };
    let pair = |v: &toml::Value| -> Result<P2, FieldError> {
        XyRaw::deserialize(v.clone())
            .map(|p| xy(&p))
            .map_err(|e| FieldError::new(key, format!("{e}; {ALLOWED}")))
    };
    match v {
        toml::Value::Array(_) => Ok(Point::Frame(pair(v)?)),
        toml::Value::String(s) => {
            let (name, what) = s
                .rsplit_once('.')
                .ok_or_else(|| FieldError::new(key, format!("`{s}` is not a point; {ALLOWED}")))?;
            let link = link_of(name)?;
            match what {
                "pivot" => Ok(Point::On {
                    link,
                    at: P2::zeros(),
                }),
                "tip" => tip_of(dyads, crank_length, link)
                    .map(|at| Point::On { link, at })
                    .ok_or_else(|| {
                        FieldError::new(
                            key,
                            format!("link `{name}` has no tip (only the crank, RRR links and RRP rods have one); use \"{name}.pivot\" or {{ link = \"{name}\", at = [...] }}"),
                        )
                    }),
                _ => Err(FieldError::new(
                    key,
                    format!("`{s}`: `.{what}` is no point of a link; {ALLOWED}"),
                )),
            }
        }
        toml::Value::Table(t) => {
            let bad = t.keys().find(|k| *k != "link" && *k != "at");
            if let Some(k) = bad {
                return Err(FieldError::new(
                    key,
                    format!("unknown key `{k}`; {ALLOWED}"),
                ));
            }
            let (Some(toml::Value::String(name)), Some(at)) = (t.get("link"), t.get("at")) else {
                return Err(FieldError::new(
                    key,
                    format!("needs `link` and `at`; {ALLOWED}"),
                ));
            };
            Ok(Point::On {
                link: link_of(name)?,
                at: pair(at)?,
            })
        }
        _ => Err(FieldError::new(
            key,
            format!("`{v}` is not a point; {ALLOWED}"),
        )),
    }
}

fn need<T: Copy>(key: &str, v: Option<T>, kind: &str) -> Result<T, FieldError> {
    v.ok_or_else(|| FieldError::new(key, format!("missing: an {kind} dyad needs it")))
}

fn side(b: Branch) -> Side {
    match b {
        Branch::Left => Side::Left,
        Branch::Right => Side::Right,
    }
}

/// The dyads, resolved in order, with the link names they add.
fn dyads(m: &MechanismRaw, crank_length: f64) -> Result<(Vec<Dyad>, Vec<String>), FieldError> {
    if m.dyads.len() > MAX_DYADS {
        return Err(FieldError::new(
            "mechanism.dyads",
            format!("{} dyads; allowed: at most {MAX_DYADS}", m.dyads.len()),
        ));
    }
    let mut names = vec!["crank".to_string()];
    let mut out: Vec<Dyad> = Vec::new();
    for (k, d) in m.dyads.iter().enumerate() {
        let at = |f: &str| format!("mechanism.dyads[{k}].{f}");
        let pt = |f: &str, v: &toml::Value| point(&at(f), v, &names, &out, crank_length);
        let p = pt("p", &d.p)?;
        let kind = match d.kind {
            DyadKind::Rrr => "RRR",
            DyadKind::Rrp => "RRP",
            DyadKind::Rpr => "RPR",
        };
        // Keys of another kind are mistakes, not silently ignored.
        let used: &[&str] = match d.kind {
            DyadKind::Rrr => &["q", "length1", "length2"],
            DyadKind::Rrp => &["length", "line_point", "line_angle"],
            DyadKind::Rpr => &["q", "offset"],
        };
        for (f, given) in [
            ("q", d.q.is_some()),
            ("length1", d.length1.is_some()),
            ("length2", d.length2.is_some()),
            ("length", d.length.is_some()),
            ("line_point", d.line_point.is_some()),
            ("line_angle", d.line_angle.is_some()),
            ("offset", d.offset.is_some()),
        ] {
            if given && !used.contains(&f) {
                return Err(FieldError::new(
                    at(f),
                    format!(
                        "not a key of an {kind} dyad; allowed: kind, links, p, branch, {}",
                        used.join(", ")
                    ),
                ));
            }
        }
        let dyad = match d.kind {
            DyadKind::Rrr => Dyad::Rrr {
                p,
                l1: positive(&at("length1"), need(&at("length1"), d.length1, kind)?.si())?,
                q: pt("q", need(&at("q"), d.q.as_ref(), kind)?)?,
                l2: positive(&at("length2"), need(&at("length2"), d.length2, kind)?.si())?,
                side: side(d.branch),
            },
            DyadKind::Rrp => Dyad::Rrp {
                p,
                l: positive(&at("length"), need(&at("length"), d.length, kind)?.si())?,
                origin: xy(&need(&at("line_point"), d.line_point, kind)?),
                angle: need(&at("line_angle"), d.line_angle, kind)?.si(),
                side: side(d.branch),
            },
            DyadKind::Rpr => Dyad::Rpr {
                p,
                q: pt("q", need(&at("q"), d.q.as_ref(), kind)?)?,
                offset: d.offset.map_or(0.0, Qty::si),
                side: side(d.branch),
            },
        };
        for name in &d.links {
            if names.contains(name) || !valid_link_name(name) {
                return Err(FieldError::new(
                    at("links"),
                    format!("link name `{name}` is taken or invalid; allowed: two new names of letters, digits, `_` or `-` (`crank` is the input link)"),
                ));
            }
            names.push(name.clone());
        }
        out.push(dyad);
    }
    Ok((out, names))
}

fn valid_link_name(s: &str) -> bool {
    !s.is_empty()
        && s.len() <= 64
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The link masses, one per named link (an `outline` read from `dir`, with its drawing).
fn inertias(
    m: &MechanismRaw,
    names: &[String],
    dyads: &[Dyad],
    crank_length: f64,
    dir: &Path,
) -> Result<Vec<(Inertia, Option<DrawnLink>)>, FieldError> {
    if let Some(extra) = m.links.keys().find(|k| !names.contains(k)) {
        let hint = crate::units::did_you_mean(extra, names.iter().map(String::as_str))
            .map(|n| format!(" (did you mean `{n}`?)"))
            .unwrap_or_default();
        return Err(FieldError::new(
            format!("mechanism.links.{extra}"),
            format!(
                "no link `{extra}` in the mechanism{hint}; links: {}",
                names.join(", ")
            ),
        ));
    }
    names
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let key = format!("mechanism.links.{name}");
            let Some(l) = m.links.get(name) else {
                return Err(FieldError::new(
                    "mechanism.links",
                    format!("missing the mass data of link `{name}`: add [mechanism.links.{name}] with mass, centroid and inertia (or uniform_bar = true); a massless link says mass = \"0 kg\""),
                ));
            };
            if let Some(o) = &l.outline {
                let given = [
                    ("mass", l.mass.is_some()),
                    ("centroid", l.centroid.is_some()),
                    ("inertia", l.inertia.is_some()),
                    ("uniform_bar", l.uniform_bar),
                ];
                set_by(&key, &given, OUTLINE_SETS)?;
                let (p, loops) = outline::drawn(o, dir, &format!("{key}.outline"))?;
                let drawn = DrawnLink {
                    loops,
                    placement: Placement::of(o),
                };
                let inertia = Inertia {
                    mass: p.mass,
                    centroid: p.centroid,
                    j: p.inertia,
                };
                return Ok((inertia, Some(drawn)));
            }
            let mass = l.mass.map(Qty::si).ok_or_else(|| {
                FieldError::new(
                    format!("{key}.mass"),
                    "missing: the link's mass; allowed: mass = \"… kg\" (\"0 kg\" for a massless link), or outline = { file = \"….dxf\", thickness = \"… mm\", density = \"… kg/m^3\" }",
                )
            })?;
            let mass = non_negative(&format!("{key}.mass"), mass)?;
            if l.uniform_bar {
                let given = [("centroid", l.centroid.is_some()), ("inertia", l.inertia.is_some())];
                set_by(&key, &given, "uniform_bar = true, which sets it")?;
                let Some(tip) = tip_of(dyads, crank_length, i) else {
                    return Err(FieldError::new(
                        format!("{key}.uniform_bar"),
                        format!("link `{name}` has no length (a slider, guide or block); give centroid and inertia"),
                    ));
                };
                return Ok((Inertia::bar(mass, tip.x), None));
            }
            let centroid = l.centroid.as_ref().map(xy).ok_or_else(|| {
                FieldError::new(
                    format!("{key}.centroid"),
                    "missing; allowed: [\"x mm\", \"y mm\"] in the link's frame, or uniform_bar = true",
                )
            })?;
            let j = l.inertia.map(Qty::si).ok_or_else(|| {
                FieldError::new(
                    format!("{key}.inertia"),
                    "missing: the moment of inertia about the centroid; allowed: \"… kg*m^2\" ≥ 0, or uniform_bar = true",
                )
            })?;
            let inertia = Inertia {
                mass,
                centroid,
                j: non_negative(&format!("{key}.inertia"), j)?,
            };
            Ok((inertia, None))
        })
        .collect()
}

/// The smallest counterweight envelope radius, relative to the crank length (as the
/// slider-crank's `design.radius` ≥ 1e-6 × `crank_radius`).
pub const MIN_RADIUS_RATIO: f64 = 1e-6;

/// The counterweights, resolved.
fn counterweights(
    d: &DesignRaw,
    names: &[String],
    crank_length: f64,
    dir: &Path,
) -> Result<Vec<CounterweightSpec>, FieldError> {
    if d.counterweights.len() > MAX_COUNTERWEIGHTS {
        return Err(FieldError::new(
            "design.counterweights",
            format!(
                "{} counterweights; allowed: at most {MAX_COUNTERWEIGHTS}",
                d.counterweights.len()
            ),
        ));
    }
    let mut out: Vec<CounterweightSpec> = Vec::new();
    for (j, cw) in d.counterweights.iter().enumerate() {
        let at = |f: &str| format!("design.counterweights[{j}].{f}");
        let link = names.iter().position(|n| *n == cw.link).ok_or_else(|| {
            FieldError::new(
                at("link"),
                format!("no link `{}`; links: {}", cw.link, names.join(", ")),
            )
        })?;
        if out.iter().any(|o| o.link == link) {
            return Err(FieldError::new(
                at("link"),
                format!("link `{}` already has a counterweight; allowed: one per link (one body is the sum of two)", cw.link),
            ));
        }
        let drawn = drawn_body(cw, dir, &at)?;
        let mass = match (cw.mass, &drawn) {
            (Some(m), _) => m.resolve(&at("mass"))?,
            (None, Some((p, _))) => Var::Fixed(p.mass),
            (None, None) => {
                return Err(FieldError::new(
                    at("mass"),
                    "missing: the counterweight's mass, fixed or a range; allowed: mass = { min = \"0 kg\", max = \"2 kg\" }, or outline = { … } for a drawn one",
                ))
            }
        };
        let (lo, hi) = mass.bounds();
        non_negative(&at("mass"), lo)?;
        positive(&at("mass"), hi)?;
        let radius = positive(&at("radius"), cw.radius.si())?;
        // A radius far below the machine's size is a typo, and it would scale the cone
        // program's variables by it (1e-308 mm stalled the solver for minutes).
        if radius < MIN_RADIUS_RATIO * crank_length {
            return Err(FieldError::new(
                at("radius"),
                format!(
                    "{radius:e} m is below {MIN_RADIUS_RATIO:e} × the crank length ({crank_length} m); allowed: at least {:e} m",
                    MIN_RADIUS_RATIO * crank_length
                ),
            ));
        }
        let sector = match cw.sector {
            None => None,
            Some(RawVar::Fixed(a)) => Some((a.si(), a.si())),
            Some(RawVar::Free { min, max }) => {
                let (a, b) = (min.si(), max.si());
                if !(a <= b && b - a <= std::f64::consts::PI + 1e-12) {
                    return Err(FieldError::new(
                        at("sector"),
                        format!("[{a}, {b}] rad; allowed: min ≤ max and at most 180° wide (a convex set of directions)"),
                    ));
                }
                Some((a, b))
            }
        };
        let given = match &drawn {
            Some((p, _)) => {
                let key = at("outline");
                fits_envelope(p.mass, p.centroid, Some(p.inertia), radius, &key, &key)?;
                Some((p.centroid, Some(p.inertia)))
            }
            None => given_body(cw, &mass, radius, sector.is_some(), &at)?,
        };
        let density = cw
            .density
            .map(|d| positive(&at("density"), d.si()))
            .transpose()?;
        let thickness = plate_thickness(cw, density, &mass, radius, &at)?;
        out.push(CounterweightSpec {
            link,
            link_name: cw.link.clone(),
            mass,
            radius,
            sector,
            given,
            density,
            thickness,
            drawing: drawn.map(|(_, loops)| loops),
            placement: cw.outline.as_ref().map(Placement::of),
        });
    }
    Ok(out)
}

/// A plate counterweight's thickness, checked: it needs `density`, is not beside a given
/// centroid, and the least mass asked fits the plate's whole envelope, σπr².
fn plate_thickness(
    cw: &CounterweightRaw,
    density: Option<f64>,
    mass: &Var,
    radius: f64,
    at: &dyn Fn(&str) -> String,
) -> Result<Option<f64>, FieldError> {
    let Some(t) = cw.thickness else {
        return Ok(None);
    };
    let t = positive(&at("thickness"), t.si())?;
    let Some(rho) = density else {
        return Err(FieldError::new(
            at("thickness"),
            "a plate's thickness needs its material; allowed: with density = \"… kg/m^3\"",
        ));
    };
    if cw.centroid.is_some() {
        return Err(FieldError::new(
            at("thickness"),
            "a given centroid is a given body, not a plate to design; allowed: thickness or centroid, not both",
        ));
    }
    let most = rho * t * std::f64::consts::PI * radius * radius;
    let (lo, _) = mass.bounds();
    if lo > most {
        return Err(FieldError::new(
            at("mass"),
            format!("{lo} kg is more than a plate {} mm thick of {rho} kg/m³ holds within its radius {} mm ({most:.6} kg, the whole disc); allowed: a smaller mass, or a thicker plate, a denser material, a larger radius", t * 1e3, radius * 1e3),
        ));
    }
    Ok(Some(t))
}

/// A given counterweight's centroid and inertia about it, checked: the centroid needs a
/// fixed mass and lies within the envelope (no `sector` beside it); the inertia needs the
/// centroid, is ≥ 0, and the body's inertia about the joint, I_c + m |c|², stays within the
/// envelope's m r².
fn given_body(
    cw: &CounterweightRaw,
    mass: &Var,
    radius: f64,
    sector: bool,
    at: &dyn Fn(&str) -> String,
) -> Result<Option<(P2, Option<f64>)>, FieldError> {
    let Some(c) = cw.centroid.as_ref().map(xy) else {
        if cw.inertia.is_some() {
            return Err(FieldError::new(
                at("inertia"),
                "a given inertia needs the given centroid it is taken about; allowed: with centroid = [\"… mm\", \"… mm\"] and a fixed mass",
            ));
        }
        return Ok(None);
    };
    let Var::Fixed(m) = *mass else {
        return Err(FieldError::new(
            at("centroid"),
            "a given centroid fixes the first moment m·c only with a given mass; allowed: mass = \"… kg\" (fixed), or no centroid (designed)",
        ));
    };
    if sector {
        return Err(FieldError::new(
            at("centroid"),
            "a given centroid leaves no direction to choose; allowed: centroid or sector, not both",
        ));
    }
    let ic = cw
        .inertia
        .map(|i| non_negative(&at("inertia"), i.si()))
        .transpose()?;
    fits_envelope(m, c, ic, radius, &at("centroid"), &at("inertia"))?;
    Ok(Some((c, ic)))
}

/// A counterweight drawn in a DXF file (`outline`): its mass, centroid and inertia about the
/// centroid, and its loops in the link's frame, or `None` without one. The keys it sets are
/// refused beside it, and so are `sector` (no direction is left to choose) and `density`
/// (the drawing has its own).
fn drawn_body(
    cw: &CounterweightRaw,
    dir: &Path,
    at: &dyn Fn(&str) -> String,
) -> Result<Option<(Plate, Vec<Vec<Edge>>)>, FieldError> {
    let Some(o) = &cw.outline else {
        return Ok(None);
    };
    let given = [
        ("mass", cw.mass.is_some()),
        ("centroid", cw.centroid.is_some()),
        ("inertia", cw.inertia.is_some()),
        ("sector", cw.sector.is_some()),
        ("density", cw.density.is_some()),
        ("thickness", cw.thickness.is_some()),
    ];
    let key = at("");
    set_by(key.trim_end_matches('.'), &given, OUTLINE_SETS)?;
    outline::drawn(o, dir, &at("outline")).map(Some)
}

/// A given body of mass `m`, centroid `c` and inertia `ic` about it fits the envelope of
/// radius `radius`: |c| ≤ r, and with a given `ic` I_c + m |c|² ≤ m r² (errors at `at_c` and
/// `at_i`).
fn fits_envelope(
    m: f64,
    c: P2,
    ic: Option<f64>,
    radius: f64,
    at_c: &str,
    at_i: &str,
) -> Result<(), FieldError> {
    if c.norm() > radius * (1.0 + 1e-12) {
        return Err(FieldError::new(
            at_c,
            format!(
                "|c| = {:e} m lies outside the envelope radius {radius:e} m; allowed: within it",
                c.norm()
            ),
        ));
    }
    if let Some(ic) = ic {
        let about = ic + m * c.norm_squared();
        if about > m * radius * radius * (1.0 + 1e-12) {
            return Err(FieldError::new(
                at_i,
                format!(
                    "I_c + m|c|² = {about:e} kg·m² about the joint exceeds m r² = {:e} kg·m² of the envelope: the body does not fit in it; allowed: a smaller inertia or a larger radius",
                    m * radius * radius
                ),
            ));
        }
    }
    Ok(())
}

/// The objective, resolved and checked against the counterweights.
fn objective(o: &ObjectiveRaw, cws: &[CounterweightSpec]) -> Result<Objective, FieldError> {
    let lim = |k: &str, v: Option<f64>| {
        v.map(|v| non_negative(&format!("objective.{k}"), v))
            .transpose()
    };
    let obj = Objective {
        minimize: o.minimize,
        max_peak_force: lim("max_peak_force", o.max_peak_force.map(Qty::si))?,
        max_peak_moment: lim("max_peak_moment", o.max_peak_moment.map(Qty::si))?,
        max_peak_torque: lim("max_peak_torque", o.max_peak_torque.map(Qty::si))?,
        max_joint_force: lim("max_joint_force", o.max_joint_force.map(Qty::si))?,
        full_force_balance: o.full_force_balance,
        pareto_points: o.pareto_points as usize,
    };
    crate::problem::limits::check(COUNTS, "objective.pareto_points", o.pareto_points.into())?;
    if obj.pareto_points == 1 {
        return Err(FieldError::new(
            "objective.pareto_points",
            "1 point is no front; allowed: 0 (none) or 2..=200",
        ));
    }
    if obj.pareto_points > 0
        && !matches!(
            obj.minimize,
            Goal::PeakForce | Goal::PeakMoment | Goal::EnergyFluctuation
        )
    {
        return Err(FieldError::new(
            "objective.pareto_points",
            "the front is peak force against peak moment, or ΔE against peak force; allowed with minimize = \"peak-force\", \"peak-moment\" or \"energy-fluctuation\"",
        ));
    }
    if cws.is_empty() && obj.max_joint_force.is_some() {
        return Err(FieldError::new(
            "objective.max_joint_force",
            "a limit on the joint loads needs something to change them; allowed: with at least one [[design.counterweights]] (the bare linkage's joint loads are reported anyway)",
        ));
    }
    if cws.is_empty() && (obj.pareto_points > 0 || obj.full_force_balance) {
        return Err(FieldError::new(
            "design.counterweights",
            "none given, but the objective asks for a balance; allowed: at least one [[design.counterweights]]",
        ));
    }
    if obj.minimize == Goal::CounterweightMass
        && obj.max_peak_force.is_none()
        && obj.max_peak_moment.is_none()
        && obj.max_peak_torque.is_none()
        && obj.max_joint_force.is_none()
        && !obj.full_force_balance
    {
        return Err(FieldError::new(
            "objective.minimize",
            "the lightest counterweights with no limit are none at all (a degenerate problem); allowed: with max_peak_force, max_peak_moment, max_peak_torque, max_joint_force or full_force_balance",
        ));
    }
    Ok(obj)
}

/// Crank angles sampled to find where the linkage cannot assemble (a range narrower than
/// 360°/`TURN_SAMPLES` = 0.25° may slip through here; the solve's own scan then meets it and
/// fails naming the angle).
pub const TURN_SAMPLES: usize = 1440;

/// The crank must turn fully: a linkage that cannot assemble over part of the turn is an error
/// naming the dyad and the unreachable crank angles (in degrees, ends to 1e-9°).
/// With length tolerances, the crank must turn fully at every vertex of the envelope's box
/// too: an error at `mechanism.envelope.length` names the vertex and what fails.
fn check_vertices(env: &super::envelope::LinkageEnvelope, l: &Linkage) -> Result<(), FieldError> {
    if env.lengths.is_empty() {
        return Ok(());
    }
    let key = "mechanism.envelope.length";
    for v in crate::synth::envelope::vertices(&env.ranges()) {
        let at = |e: String| {
            FieldError::new(
                key,
                format!(
                    "at the envelope's vertex {:?} ({}): {e}",
                    v,
                    env.names().join(", ")
                ),
            )
        };
        let lv = env.at(l, &v).map_err(|e| at(e.to_string()))?;
        check_full_turn(&lv).map_err(|e| at(e.message))?;
    }
    Ok(())
}

pub(super) fn check_full_turn(l: &Linkage) -> Result<(), FieldError> {
    // A range that closes to nothing (the bisection meeting itself at the wrap) is none.
    let bad: Vec<_> = l
        .unreachable(TURN_SAMPLES, 1e-11)
        .into_iter()
        .filter(|u| u.to - u.from > 1e-9)
        .collect();
    let Some(first) = bad.first() else {
        return Ok(());
    };
    let ranges: Vec<String> = bad
        .iter()
        .map(|u| {
            format!(
                "{:.4}° to {:.4}° (dyad {})",
                u.from.to_degrees(),
                u.to.to_degrees(),
                u.dyad
            )
        })
        .collect();
    Err(FieldError::new(
        format!("mechanism.dyads[{}]", first.dyad),
        format!(
            "the crank cannot turn fully: the linkage does not assemble for crank angles {}; allowed: lengths that let the crank turn (a Grashof crank-rocker or double crank, a rod longer than the crank's reach to the line)",
            ranges.join(", ")
        ),
    ))
}

/// The value checks of a linkage file's mechanism, model, design and objective (`outline`
/// drawings read from `dir`).
pub fn resolve_scene(
    name: &str,
    m: &MechanismRaw,
    model: &ModelRaw,
    design: &DesignRaw,
    o: &ObjectiveRaw,
    dir: &Path,
) -> Result<LinkageScene, FieldError> {
    check_name(name)?;
    let omega = positive("mechanism.speed", m.speed.si())?;
    let crank_length = positive("mechanism.crank_length", m.crank_length.si())?;
    let pivot = m.crank_pivot.as_ref().map_or(P2::zeros(), xy);
    let g = m
        .gravity
        .map(|g| non_negative("mechanism.gravity", g.si()))
        .transpose()?
        .unwrap_or(0.0);
    let (dyads, names) = dyads(m, crank_length)?;
    let (inertia, drawn_links): (Vec<Inertia>, Vec<_>) =
        inertias(m, &names, &dyads, crank_length, dir)?
            .into_iter()
            .unzip();
    let loads = super::file_loads::resolve_loads(&m.loads, &|key: &str, v: &toml::Value| {
        point(key, v, &names, &dyads, crank_length)
    })?;
    let linkage = Linkage::new(pivot, dyads, inertia, omega, P2::new(0.0, -g))
        .and_then(|l| l.with_loads(loads))
        .map_err(|e| FieldError::new("mechanism", e.to_string()))?;
    check_full_turn(&linkage)?;
    let counterweights = counterweights(design, &names, crank_length, dir)?;
    let objective = objective(o, &counterweights)?;
    let mut envelope = match &m.envelope {
        Some(e) => {
            let bars: Vec<bool> = (names.iter())
                .map(|n| m.links.get(n).is_some_and(|l| l.uniform_bar))
                .collect();
            let env =
                super::file_envelope::resolve_envelope(e, &linkage, &names, crank_length, &bars)?;
            check_vertices(&env, &linkage)?;
            env
        }
        None => Default::default(),
    };
    envelope.cases = super::file_loads::resolve_cases(&m.load_cases, &|key, v| {
        point(key, v, &names, linkage.dyads(), crank_length)
    })?;
    if !envelope.is_empty() {
        super::file_envelope::check_envelope(
            matches!(
                objective.minimize,
                Goal::RmsForce | Goal::RmsMoment | Goal::RmsTorque
            ),
            objective.pareto_points,
            objective.full_force_balance,
        )?;
    }
    Ok(LinkageScene {
        moment_about: model.moment_about.as_ref().map_or(pivot, xy),
        linkage,
        crank_length,
        link_names: names,
        counterweights,
        objective,
        envelope,
        drawn_links,
    })
}
