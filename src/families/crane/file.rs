//! The luffing-crane problem file — its raw sections and their resolution into a checked
//! [`crate::families::crane::synth::CraneScene`] with its solver [`Settings`] (every field documented
//! in `docs/problem-files.md`) — and the shaping of its outcome into a result (keys in
//! `docs/results.md`): design, Δh and its error, the thesis's checks, the jib-head path and
//! the Δh landscape over (k1, k2) as SVG and CSV.

use crate::families::crane::actuator::{ActuatorKind, ActuatorSpec};
use crate::families::crane::balance::{
    BalanceScene, CounterweightKind, CounterweightSpec, LeverSpec,
};
use crate::families::crane::model::{HoistRope, Level};
use crate::families::crane::stability::StabilitySpec;
use crate::families::crane::statics::SelfWeight;
use crate::families::crane::synth::{self as cr, Settings, SizingRule, TiePinLimit};
use crate::problem::limits::{self, c, Count};
use crate::problem::{
    check_name, Ctx, FieldError, Input, Pair, ProblemError, RawFile, RawVar, Resolved,
};
use crate::units::{Angle, Dimensionless, Length, Mass, Qty, Time};
use serde::Deserialize;

/// `[mechanism]`: the crane's requirements (thesis §3.1).
/// The `family = "…"` value of this family's files.
pub const FAMILY: &str = "luffing-crane";

/// The problem file `cwsynth new` prints: the shipped `problems/crane-tukan-40t-counterweight.toml`, a design with no
/// paper's numbers to check.
pub const TEMPLATE: &str = include_str!("../../../problems/crane-tukan-40t-counterweight.toml");

/// The work budget of one scene (see [`limits::check_work`] and `check_work` below):
/// every single integer setting at its maximum passes on the shipped files, their products
/// do not, so one machine runs in seconds and can neither stall a batch nor exhaust memory.
pub const WORK_BUDGET: f64 = 2e7;

/// The integer keys of this family's file and their ranges (see [`limits`]).
pub const COUNTS: &[Count] = &[
    c("accuracy.path_samples", 8, 1024),
    c("accuracy.plot_points", 2, 10_000),
    c("accuracy.global_samples", 1, 1000),
    c("accuracy.local_starts", 1, 50),
    c("accuracy.local_max_iters", 1, 2000),
    c("accuracy.landscape_k1", 0, 201),
    c("accuracy.landscape_k2", 0, 201),
    c("mechanism.hoist_rope.parts", 1, 64),
];

#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MechanismRaw {
    /// R_max, largest reach from the slewing axis.
    pub reach_max: Qty<Length>,
    /// R_min, smallest reach from the slewing axis.
    pub reach_min: Qty<Length>,
    /// r, slewing axis to the boom-foot pin A.
    pub foot_offset: Qty<Length>,
    /// H, lift height above the rail.
    pub lift_height: Qty<Length>,
    /// h, rail to the boom-foot pin.
    pub foot_height: Qty<Length>,
    /// Q, rated load (optional): the unbalanced load moment about A is reported, and with
    /// `self_weight` the loaded case of the drive torque and the forces.
    pub load_mass: Option<Qty<Mass>>,
    /// The boom system's masses: with them the luffing drive torque, the tie force and the pin
    /// loads are computed over the luffing range (empty, and loaded with `load_mass`).
    pub self_weight: Option<SelfWeightRaw>,
    /// An inclined hoist rope (thesis §2.2): the load's path and, with `self_weight`, the
    /// rope's pull on the jib head. Absent: the rope runs parallel to the boom or the tie and
    /// the load hangs at the jib head (thesis §2.1).
    pub hoist_rope: Option<HoistRopeRaw>,
    /// The luffing drive at a given luffing speed: with `self_weight`, the drive power
    /// over the luffing stroke beside the work (`[mechanism.drive]`).
    pub drive: Option<CraneDriveRaw>,
    /// The crane's stability against tipping (`[mechanism.stability]`, needs `self_weight`):
    /// the slewing part, the base and the tipping lines.
    pub stability: Option<StabilityRaw>,
    /// The real luffing drive (`[[mechanism.luffing_actuator]]`, needs `self_weight`): each a
    /// hydraulic cylinder, a rope tackle or a rack between the A-frame and the boom (thesis §1.1).
    pub luffing_actuator: Option<Vec<ActuatorRaw>>,
}

/// What a luffing actuator is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ActuatorKindRaw {
    /// A hydraulic cylinder (pushes; pulls when double-acting).
    Cylinder,
    /// A rope tackle from a sheave on the A-frame to the boom (pulls only).
    Rope,
    /// A rack pinned to the boom, driven by a pinion in a gearbox swinging about the A-frame
    /// point (pushes and pulls; needs `pinion_radius`).
    Rack,
}

/// `[[mechanism.luffing_actuator]]`: a cylinder, rope or rack between a point on the A-frame
/// and a point on the boom.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ActuatorRaw {
    /// `"cylinder"`, `"rope"` or `"rack"`.
    pub kind: ActuatorKindRaw,
    /// P = [x, y], its point on the A-frame (the cylinder's base pin, the rope's sheave, the
    /// rack gearbox's swing pin) in
    /// the frame of A (x behind the foot, y up), e.g. `["-1 m", "-3 m"]`.
    pub frame_point: Pair<Qty<Length>>,
    /// Q = [s, n], its point on the boom: s along the boom from A towards D, n across it
    /// (positive on the boom's underside, the boom's direction turned a quarter turn
    /// anticlockwise), e.g. `["8 m", "0.5 m"]`.
    pub boom_point: Pair<Qty<Length>>,
    /// For a rope: the tackle's parts n between sheave and boom (default 1, 1 to 64).
    pub parts: Option<u32>,
    /// For a rack: the pitch radius of its pinion, e.g. `"150 mm"` (required for a rack).
    pub pinion_radius: Option<Qty<Length>>,
}

/// `[mechanism.stability]`: the weights that are not the boom system's and the tipping lines
/// (the boom's plane perpendicular to them), against a required stability factor.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StabilityRaw {
    /// M_s, the slewing part's mass without boom, jib, tie, load and boom counterweight (the
    /// A-frame, machinery house, its ballast), e.g. `"160 t"`.
    pub slewing_mass: Qty<Mass>,
    /// x_s, the slewing part's centroid behind the slewing axis (negative: in front, on the
    /// boom's side), e.g. `"1.5 m"`.
    pub slewing_centroid: Qty<Length>,
    /// The non-slewing base (portal) with its centroid on the slewing axis (default 0 kg).
    pub base_mass: Option<Qty<Mass>>,
    /// b, the distance of each tipping line (forward and backward) from the slewing axis,
    /// e.g. half the portal's gauge `"5.25 m"`.
    pub tipping_distance: Qty<Length>,
    /// K_min, the required stability factor (stabilising over overturning moment), ≥ 1.
    pub min_factor: f64,
}

/// `[mechanism.drive]` of the crane: the luffing speed. Luffing is a stroke, not a cycle, so
/// the other families' flywheel, `cs` and motor do not apply (refused as unknown keys).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CraneDriveRaw {
    /// t_l, the time to luff from φ_min to φ_max (maximum to minimum reach) at a constant
    /// boom angular speed φ̇ = (φ_max − φ_min)/t_l, e.g. `"55 s"`.
    pub luffing_time: Qty<Time>,
}

/// `[mechanism.hoist_rope]`: the rope from a fixed sheave over the jib head to the load.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HoistRopeRaw {
    /// S = [x, y], the fixed sheave the rope comes from, in the frame of A (x behind the foot,
    /// y up), e.g. `["3 m", "12 m"]`.
    pub sheave: Pair<Qty<Length>>,
    /// n, the falls between the jib head and the load (default 1).
    pub parts: Option<u32>,
}

/// `[mechanism.self_weight]`: masses and centroids of boom, jib and tie.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SelfWeightRaw {
    /// m_b, the boom's mass.
    pub boom_mass: Qty<Mass>,
    /// The boom's centroid as a fraction of AD from the foot A (default 0.5, a uniform boom).
    pub boom_centroid: Option<f64>,
    /// m_j, the jib's mass.
    pub jib_mass: Qty<Mass>,
    /// The jib's centroid at D + f·(C − D), f a fraction of the jib head length DC (negative:
    /// behind D, towards the tail E). Default (1 − k2)/2: the middle of the straight jib E–C.
    pub jib_centroid: Option<f64>,
    /// m_t, the tie's mass (its centroid at the middle of EB).
    pub tie_mass: Qty<Mass>,
}

/// `[design.counterweight]`: the boom counterweight to design (its static moment minimises
/// the peak luffing drive torque over the range, empty and loaded).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CounterweightRaw {
    /// The heaviest counterweight allowed.
    pub max_mass: Qty<Mass>,
    /// ℓ, the farthest its centroid (or, hung, its suspension point) may be from the foot A:
    /// the lightest counterweight sits there.
    pub lever: Qty<Length>,
    /// Allowed directions of its centroid from A in the boom frame, `[from, to]` at most
    /// 180° apart (0° along the boom towards its head, 90° the boom turned a quarter turn
    /// anticlockwise, 180° the boom's extension behind A). Default: any direction. For a
    /// lever counterweight: from the lever's pivot in the lever frame (0° towards the rod's
    /// pin).
    pub directions: Option<Pair<Qty<Angle>>>,
    /// The type (thesis Fig 1.5): `"boom"` (default, on the boom), `"hanging"` (hung from
    /// the boom by `hang_length`), `"lever"` (on a lever pivoted on the A-frame, linked to the
    /// boom by a rod: `lever_pivot`, `lever_arm`, `lever_angle`, `rod_boom_point`).
    pub kind: Option<CounterweightKindRaw>,
    /// Hanging: L_h, the rope from the suspension point to the counterweight's centroid.
    pub hang_length: Option<Qty<Length>>,
    /// Lever: O = [x, y], its pivot on the A-frame in the frame of A.
    pub lever_pivot: Option<Pair<Qty<Length>>>,
    /// Lever: ρ, the pivot to the rod's pin on the lever.
    pub lever_arm: Option<Qty<Length>>,
    /// Lever: ψ₁, its direction from the pivot to the rod's pin at maximum reach (from +x,
    /// behind the foot, anticlockwise); the rod's length follows.
    pub lever_angle: Option<Qty<Angle>>,
    /// Lever: K = [s, n], the rod's pin on the boom (s along the boom from A, n across it,
    /// positive on its underside).
    pub rod_boom_point: Option<Pair<Qty<Length>>>,
}

/// The boom counterweight's type (thesis Fig 1.5 a, b, c).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum CounterweightKindRaw {
    /// On the boom (Fig 1.5a).
    Boom,
    /// Hung from the boom (Fig 1.5b).
    Hanging,
    /// On a lever linked to the boom by a rod (Fig 1.5c).
    Lever,
}

/// How the boom length follows from the step-1 angles when `design.boom_length` is absent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Sizing {
    /// L_c = (R_min − r)/(sin γ1 + k sin γ2).
    MinReach,
    /// L_c = (R_max − r)/(cos φ_min + k cos γ3).
    MaxReach,
}

/// `[model]`.
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelRaw {
    /// Boom-length rule (default `min-reach`; not with `design.boom_length`).
    pub sizing: Option<Sizing>,
}

/// `[design]`: k1, k2, the step-1 angles (each fixed or `{ min, max }`), and L_c if given.
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignRaw {
    /// k1 = C1C2/C1C3.
    pub k1: Option<RawVar<Dimensionless>>,
    /// k2 = a/L_v.
    pub k2: Option<RawVar<Dimensionless>>,
    /// φ_min, boom elevation at maximum reach.
    pub phi_min: Option<RawVar<Angle>>,
    /// γ1, boom from vertical at minimum reach.
    pub gamma1: Option<RawVar<Angle>>,
    /// γ2, jib from vertical at minimum reach.
    pub gamma2: Option<RawVar<Angle>>,
    /// γ3, jib below horizontal at maximum reach.
    pub gamma3: Option<RawVar<Angle>>,
    /// L_c given (fixed); otherwise `model.sizing` computes it.
    pub boom_length: Option<Qty<Length>>,
    /// The boom counterweight to design (needs `mechanism.self_weight`).
    pub counterweight: Option<CounterweightRaw>,
}

/// What `objective.minimize` can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Minimize {
    /// Δh, the height variation of the jib head over the luffing range; the precision points
    /// put the head level (thesis §2.1).
    DeltaH,
    /// Δh_L, the height variation of the load on the inclined hoist rope
    /// (`mechanism.hoist_rope`); the precision points put the load level (thesis §2.2: the
    /// head at C2 and C3 higher than at C1 by h2 and h3, the rope's run-out per fall).
    LoadDeltaH,
}

/// `[objective.tie_pin]`: where the tie pin B may be (frame of A, x behind the foot).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TiePinRaw {
    /// |AB| ≤ max_distance.
    pub max_distance: Option<Qty<Length>>,
    /// x_B within [min, max].
    pub x_range: Option<Pair<Qty<Length>>>,
    /// y_B within [min, max].
    pub y_range: Option<Pair<Qty<Length>>>,
}

/// `[objective]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectiveRaw {
    /// `delta-h` (the jib head level) or `load-delta-h` (the load on the inclined rope level).
    pub minimize: Minimize,
    /// Allowed Δh (of the head, or with `load-delta-h` of the load) of the check (default 0.1·H).
    pub max_delta_h: Option<Qty<Length>>,
    /// Tie-pin limit (required when a variable is free).
    pub tie_pin: Option<TiePinRaw>,
}

/// `[accuracy]`: the crane solver's [`Settings`] read directly (every key optional, unknown
/// keys rejected); validated with the scene in `resolve_raw`.
pub type AccuracyRaw = Settings;

/// The whole luffing-crane file.
pub type File = RawFile<MechanismRaw, ModelRaw, DesignRaw, ObjectiveRaw, AccuracyRaw>;

/// A resolved luffing-crane scene: the synthesis scene and its solver settings.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CraneProblem {
    /// Requirements, variables, sizing rule, tie-pin limit.
    pub scene: cr::CraneScene,
    /// Solver and sampling settings.
    pub settings: Settings,
    /// t_l, the luffing time from φ_min to φ_max (s), `mechanism.drive.luffing_time`.
    pub luffing_time: Option<f64>,
    /// The stability data, `mechanism.stability`.
    pub stability: Option<StabilitySpec>,
    /// The luffing actuators, `mechanism.luffing_actuator` (empty: none).
    pub actuators: Vec<ActuatorSpec>,
}

/// Reads and resolves a luffing-crane problem file (its text or its table).
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Resolved<CraneProblem>, ProblemError> {
    File::resolve(ctx, input, resolve_raw)
}

/// A required design variable.
fn var<D>(v: &Option<RawVar<D>>, key: &str, allowed: &str) -> Result<cr::Var, FieldError> {
    match v {
        Some(v) => v.resolve(key),
        None => Err(FieldError::new(
            key,
            format!("missing; allowed: a fixed value ({allowed}) or a range {{ min = …, max = … }} to search"),
        )),
    }
}

/// The value checks of a luffing-crane file.
pub fn resolve_raw(raw: &File) -> Result<CraneProblem, FieldError> {
    check_name(&raw.name)?;
    let m = &raw.mechanism;
    let d = &raw.design;
    let k1 = var(&d.k1, "design.k1", "a number in (0, 1), e.g. 0.2")?;
    let k2 = var(&d.k2, "design.k2", "a number in (0, 5], e.g. 0.4")?;
    let phi_min = var(&d.phi_min, "design.phi_min", "an angle, e.g. \"35 deg\"")?;
    let gamma1 = var(&d.gamma1, "design.gamma1", "an angle, e.g. \"10 deg\"")?;
    let gamma2 = var(&d.gamma2, "design.gamma2", "an angle, e.g. \"5 deg\"")?;
    let gamma3 = var(&d.gamma3, "design.gamma3", "an angle, e.g. \"12 deg\"")?;
    let sizing = match (d.boom_length, raw.model.sizing) {
        (Some(_), Some(_)) => {
            return Err(FieldError::new(
                "model.sizing",
                "only used without design.boom_length (a given L_c needs no rule); allowed: remove one of the two",
            ))
        }
        (Some(l), None) => SizingRule::Given(l.si()),
        (None, Some(Sizing::MaxReach)) => SizingRule::MaxReach,
        (None, Some(Sizing::MinReach) | None) => SizingRule::MinReach,
    };
    let o = &raw.objective;
    let range = |r: &Option<Pair<Qty<Length>>>| r.map(|Pair([a, b])| [a.si(), b.si()]);
    let tie_pin = o
        .tie_pin
        .as_ref()
        .map(|t| TiePinLimit {
            max_distance: t.max_distance.map(|q| q.si()),
            x_range: range(&t.x_range),
            y_range: range(&t.y_range),
        })
        .unwrap_or_default();
    let scene = cr::CraneScene {
        reach_max: m.reach_max.si(),
        reach_min: m.reach_min.si(),
        foot_offset: m.foot_offset.si(),
        lift_height: m.lift_height.si(),
        foot_height: m.foot_height.si(),
        k1,
        k2,
        phi_min,
        gamma1,
        gamma2,
        gamma3,
        sizing,
        tie_pin,
        max_delta_h: o.max_delta_h.map(|q| q.si()),
        load_mass: m.load_mass.map(|q| q.si()),
        balance: balance_scene(raw)?,
        level: level_of(raw)?,
    };
    scene.validate()?;
    if let Some(t) = &o.tie_pin {
        if t.max_distance.is_none() && t.x_range.is_none() && t.y_range.is_none() {
            return Err(FieldError::new(
                "objective.tie_pin",
                "an empty tie-pin limit; allowed: max_distance, x_range = [min, max], y_range = [min, max] (m)",
            ));
        }
    }
    let settings = raw.accuracy.clone();
    limits::check_section(COUNTS, "accuracy", &settings)?;
    settings.validate()?;
    check_work(&scene, &settings)?;
    Ok(CraneProblem {
        scene,
        settings,
        luffing_time: luffing_time(raw)?,
        stability: stability(raw)?,
        actuators: actuators(raw)?,
    })
}

/// What `objective.minimize` puts level: `load-delta-h` needs the inclined rope.
fn level_of(raw: &File) -> Result<Level, FieldError> {
    match raw.objective.minimize {
        Minimize::DeltaH => Ok(Level::Head),
        Minimize::LoadDeltaH => match hoist_rope(raw)? {
            Some(rope) => Ok(Level::Load(rope)),
            None => Err(FieldError::new(
                "objective.minimize",
                "load-delta-h levels the load on an inclined hoist rope; allowed: add [mechanism.hoist_rope] with its sheave, or minimize = \"delta-h\"",
            )),
        },
    }
}

/// `mechanism.hoist_rope` checked: a finite sheave, 1 to 64 falls.
fn hoist_rope(raw: &File) -> Result<Option<HoistRope>, FieldError> {
    let Some(r) = &raw.mechanism.hoist_rope else {
        return Ok(None);
    };
    let [x, y] = r.sheave.0.map(|q| q.si());
    if !(x.is_finite() && y.is_finite()) {
        return Err(FieldError::new(
            "mechanism.hoist_rope.sheave",
            "must be two finite lengths [x, y]",
        ));
    }
    let parts = r.parts.unwrap_or(1);
    if parts == 0 || parts > 64 {
        return Err(FieldError::new(
            "mechanism.hoist_rope.parts",
            format!("must be 1 to 64 falls, got {parts}"),
        ));
    }
    Ok(Some(HoistRope {
        sheave: crate::geom::P2::new(x, y),
        parts: parts as f64,
    }))
}

/// `mechanism.luffing_actuator` checked: finite points, P not on the boom's line through A
/// at Q's radius (a zero length), `parts` only for a rope, with the masses.
fn actuators(raw: &File) -> Result<Vec<ActuatorSpec>, FieldError> {
    let Some(list) = &raw.mechanism.luffing_actuator else {
        return Ok(Vec::new());
    };
    if raw.mechanism.self_weight.is_none() {
        return Err(FieldError::new(
            "mechanism.luffing_actuator[0].kind",
            "needs the boom system's masses whose torque it carries; allowed: add [mechanism.self_weight] with boom_mass, jib_mass and tie_mass",
        ));
    }
    list.iter()
        .enumerate()
        .map(|(i, a)| {
            let key = |k: &str| format!("mechanism.luffing_actuator[{i}].{k}");
            let [px, py] = a.frame_point.0.map(|q| q.si());
            let [s, n] = a.boom_point.0.map(|q| q.si());
            if !(px.is_finite() && py.is_finite()) {
                return Err(FieldError::new(
                    key("frame_point"),
                    "must be two finite lengths [x, y]",
                ));
            }
            if !(s.is_finite() && n.is_finite() && s.hypot(n) > 0.0) {
                return Err(FieldError::new(
                    key("boom_point"),
                    "must be two finite lengths [s, n], not the boom foot itself",
                ));
            }
            let kind = match a.kind {
                ActuatorKindRaw::Cylinder => ActuatorKind::Cylinder,
                ActuatorKindRaw::Rope => ActuatorKind::Rope,
                ActuatorKindRaw::Rack => ActuatorKind::Rack,
            };
            let pinion_radius = pinion_radius(kind, a, &key)?;
            let parts = match (kind, a.parts) {
                (ActuatorKind::Cylinder | ActuatorKind::Rack, Some(_)) => {
                    return Err(FieldError::new(
                        key("parts"),
                        "only for a rope tackle; allowed: remove it, or kind = \"rope\"",
                    ))
                }
                (_, Some(p)) if !(1..=64).contains(&p) => {
                    return Err(FieldError::new(
                        key("parts"),
                        format!("must be 1 to 64 parts, got {p}"),
                    ))
                }
                (_, p) => p.unwrap_or(1) as f64,
            };
            Ok(ActuatorSpec {
                kind,
                frame_point: crate::geom::P2::new(px, py),
                boom_point: [s, n],
                parts,
                pinion_radius,
            })
        })
        .collect()
}

/// A luffing actuator's `pinion_radius`: required, finite and > 0 for a rack, refused for the
/// others.
fn pinion_radius(
    kind: ActuatorKind,
    a: &ActuatorRaw,
    key: &dyn Fn(&str) -> String,
) -> Result<Option<f64>, FieldError> {
    match (kind, a.pinion_radius) {
        (ActuatorKind::Rack, None) => Err(FieldError::new(
            key("kind"),
            "a rack needs its pinion; allowed: add pinion_radius = \"150 mm\" (the pinion's pitch radius)",
        )),
        (ActuatorKind::Rack, Some(q)) => {
            let r = q.si();
            if r.is_finite() && r > 0.0 {
                Ok(Some(r))
            } else {
                Err(FieldError::new(
                    key("pinion_radius"),
                    format!("must be a finite length > 0, got {r} m"),
                ))
            }
        }
        (_, Some(_)) => Err(FieldError::new(
            key("pinion_radius"),
            "only for a rack; allowed: remove it, or kind = \"rack\"",
        )),
        (_, None) => Ok(None),
    }
}

/// `mechanism.stability` checked: positive masses and distances, the slewing part's centroid
/// between the tipping lines (else it tips the crane alone), K_min ≥ 1, with the masses.
fn stability(raw: &File) -> Result<Option<StabilitySpec>, FieldError> {
    let Some(s) = &raw.mechanism.stability else {
        return Ok(None);
    };
    let key = |k: &str| format!("mechanism.stability.{k}");
    if raw.mechanism.self_weight.is_none() {
        return Err(FieldError::new(
            "mechanism.stability",
            "needs the boom system's masses; allowed: add [mechanism.self_weight] with boom_mass, jib_mass and tie_mass",
        ));
    }
    let b = s.tipping_distance.si();
    if !(b.is_finite() && b > 0.0) {
        return Err(FieldError::new(
            &key("tipping_distance"),
            format!("must be a finite length > 0, got {b} m"),
        ));
    }
    let m = s.slewing_mass.si();
    if !(m.is_finite() && m > 0.0) {
        return Err(FieldError::new(
            &key("slewing_mass"),
            format!("must be a finite mass > 0, got {m} kg"),
        ));
    }
    let x = s.slewing_centroid.si();
    if !(x.is_finite() && x.abs() < b) {
        return Err(FieldError::new(
            &key("slewing_centroid"),
            format!(
                "must lie between the tipping lines, |x_s| < tipping_distance = {b} m, got {x} m"
            ),
        ));
    }
    let base = s.base_mass.map_or(0.0, |q| q.si());
    if !(base.is_finite() && base >= 0.0) {
        return Err(FieldError::new(
            &key("base_mass"),
            format!("must be a finite mass >= 0, got {base} kg"),
        ));
    }
    let k = s.min_factor;
    if !(k.is_finite() && (1.0..=100.0).contains(&k)) {
        return Err(FieldError::new(
            &key("min_factor"),
            format!("must be a number in [1, 100] (stabilising over overturning moment), got {k}"),
        ));
    }
    Ok(Some(StabilitySpec {
        slewing_mass: m,
        slewing_centroid: x,
        base_mass: base,
        tipping_distance: b,
        min_factor: k,
    }))
}

/// `mechanism.drive.luffing_time` t_l checked: a finite time > 0, with the masses whose drive
/// it times (`mechanism.self_weight`).
fn luffing_time(raw: &File) -> Result<Option<f64>, FieldError> {
    const KEY: &str = "mechanism.drive.luffing_time";
    let Some(d) = &raw.mechanism.drive else {
        return Ok(None);
    };
    let t = d.luffing_time.si();
    if !(t.is_finite() && t > 0.0) {
        return Err(FieldError::new(
            KEY,
            format!("must be a finite time > 0 (the time from maximum to minimum reach, e.g. \"55 s\"), got {t} s"),
        ));
    }
    if raw.mechanism.self_weight.is_none() {
        return Err(FieldError::new(
            KEY,
            "needs the masses whose drive it times; allowed: add [mechanism.self_weight] with boom_mass, jib_mass and tie_mass",
        ));
    }
    Ok(Some(t))
}

/// The balance section of the scene: `mechanism.self_weight` and `design.counterweight`.
fn balance_scene(raw: &File) -> Result<Option<BalanceScene>, FieldError> {
    let m = &raw.mechanism;
    let rope = hoist_rope(raw)?;
    let Some(sw) = &m.self_weight else {
        return match raw.design.counterweight {
            Some(_) => Err(FieldError::new(
                "design.counterweight",
                "needs the masses it balances; allowed: add [mechanism.self_weight] with boom_mass, jib_mass and tie_mass",
            )),
            None => Ok(rope.map(|rope| BalanceScene {
                self_weight: SelfWeight::NONE,
                jib_centroid: None,
                counterweight: None,
                load_mass: m.load_mass.map(|q| q.si()),
                rope: Some(rope),
                masses: false,
            })),
        };
    };
    let mass = |key: &str, q: Qty<Mass>| {
        let v = q.si();
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(FieldError::new(
                key,
                format!("must be a finite mass >= 0 kg, got {v}"),
            ))
        }
    };
    let fraction = |key: &str, v: Option<f64>, lo: f64, hi: f64| match v {
        Some(f) if !(f.is_finite() && (lo..=hi).contains(&f)) => Err(FieldError::new(
            key,
            format!("must be a fraction in [{lo}, {hi}], got {f}"),
        )),
        _ => Ok(v),
    };
    let k2_max = match raw.design.k2.as_ref().map(|v| v.resolve("design.k2")) {
        Some(Ok(v)) => v.bounds().1,
        _ => 1.0,
    };
    let self_weight = SelfWeight {
        boom_mass: mass("mechanism.self_weight.boom_mass", sw.boom_mass)?,
        boom_centroid: fraction(
            "mechanism.self_weight.boom_centroid",
            sw.boom_centroid,
            0.0,
            1.0,
        )?
        .unwrap_or(0.5),
        jib_mass: mass("mechanism.self_weight.jib_mass", sw.jib_mass)?,
        // Resolved against the design's k2 (`BalanceScene::self_weight_at`).
        jib_centroid: 0.0,
        tie_mass: mass("mechanism.self_weight.tie_mass", sw.tie_mass)?,
    };
    let counterweight = match &raw.design.counterweight {
        None => None,
        Some(c) => {
            let max_mass = c.max_mass.si();
            if !(max_mass.is_finite() && max_mass > 0.0) {
                return Err(FieldError::new(
                    "design.counterweight.max_mass",
                    format!("must be a finite positive mass, got {max_mass} kg"),
                ));
            }
            let lever = c.lever.si();
            if !(lever.is_finite() && lever > 0.0) {
                return Err(FieldError::new(
                    "design.counterweight.lever",
                    format!("must be a finite positive length, got {lever} m"),
                ));
            }
            let directions = match c.directions {
                None => None,
                Some(Pair([a, b])) => {
                    let (lo, hi) = (a.si(), b.si());
                    if !(lo.is_finite()
                        && hi.is_finite()
                        && lo <= hi
                        && hi - lo <= std::f64::consts::PI)
                    {
                        return Err(FieldError::new(
                            "design.counterweight.directions",
                            format!(
                                "must be [from, to] with from <= to and at most 180 deg apart, got [{:.6} deg, {:.6} deg]",
                                lo.to_degrees(),
                                hi.to_degrees()
                            ),
                        ));
                    }
                    Some((lo, hi))
                }
            };
            Some(CounterweightSpec {
                max_mass,
                lever,
                directions,
                kind: counterweight_kind(c)?,
            })
        }
    };
    Ok(Some(BalanceScene {
        self_weight,
        jib_centroid: fraction(
            "mechanism.self_weight.jib_centroid",
            sw.jib_centroid,
            -k2_max,
            1.0,
        )?,
        counterweight,
        load_mass: m.load_mass.map(|q| q.si()),
        rope,
        masses: true,
    }))
}

/// The work budget ([`limits::check_work`]): W = n_path·(1 + n·G + s·I·(n + 1) + k1·k2) +
/// n_plot, n the free variables (each path evaluation samples n_path angles; the global stage
/// evaluates n·G Halton points, each of s SQP searches at most I iterations of n + 1
/// evaluations; the landscape k1·k2 grid points).
fn check_work(scene: &cr::CraneScene, s: &cr::Settings) -> Result<(), FieldError> {
    let d = cr::Settings::default();
    let n = scene
        .vars()
        .iter()
        .filter(|v| matches!(v, crate::synth::Var::Free { .. }))
        .count() as f64;
    let (path, g, starts, iters) = (
        s.path_samples as f64,
        s.global_samples as f64,
        s.local_starts as f64,
        s.local_max_iters as f64,
    );
    let grid = (s.landscape_k1 * s.landscape_k2) as f64;
    let search = if n > 0.0 {
        n * g + starts * iters * (n + 1.0)
    } else {
        0.0
    };
    let estimate = path * (1.0 + search + grid) + s.plot_points as f64;
    let t = |k, v: f64, d: usize| limits::term(k, v, d as f64);
    limits::check_work(
        WORK_BUDGET,
        FAMILY,
        estimate,
        "path_samples·(1 + n·global_samples + local_starts·local_max_iters·(n + 1) + landscape_k1·landscape_k2) + plot_points",
        &[
            t("accuracy.path_samples", path, d.path_samples),
            t("accuracy.global_samples", g, d.global_samples),
            t("accuracy.local_starts", starts, d.local_starts),
            t("accuracy.local_max_iters", iters, d.local_max_iters as usize),
            t("accuracy.landscape_k1", s.landscape_k1 as f64, d.landscape_k1),
            t("accuracy.landscape_k2", s.landscape_k2 as f64, d.landscape_k2),
            t("accuracy.plot_points", s.plot_points as f64, d.plot_points),
        ],
    )
}

/// `design.counterweight.kind` and its keys: `hang_length` only and required for a hanging
/// counterweight, the four lever keys only and all for a lever.
fn counterweight_kind(c: &CounterweightRaw) -> Result<CounterweightKind, FieldError> {
    let key = |k: &str| format!("design.counterweight.{k}");
    let kind = c.kind.unwrap_or(CounterweightKindRaw::Boom);
    let lever_keys = [
        ("lever_pivot", c.lever_pivot.is_some()),
        ("lever_arm", c.lever_arm.is_some()),
        ("lever_angle", c.lever_angle.is_some()),
        ("rod_boom_point", c.rod_boom_point.is_some()),
    ];
    if kind != CounterweightKindRaw::Hanging && c.hang_length.is_some() {
        return Err(FieldError::new(
            key("hang_length"),
            "only for kind = \"hanging\"; allowed: remove it or set the kind",
        ));
    }
    if kind != CounterweightKindRaw::Lever {
        if let Some((k, _)) = lever_keys.iter().find(|(_, given)| *given) {
            return Err(FieldError::new(
                key(k),
                "only for kind = \"lever\"; allowed: remove it or set the kind",
            ));
        }
    }
    let length = |k: &str, q: Option<Qty<Length>>| -> Result<f64, FieldError> {
        let q = q.ok_or_else(|| {
            FieldError::new(
                key(k),
                format!(
                    "missing: kind = \"{}\" needs it (a length)",
                    if k == "hang_length" {
                        "hanging"
                    } else {
                        "lever"
                    }
                ),
            )
        })?;
        let v = q.si();
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(FieldError::new(
                key(k),
                format!("must be a finite length > 0, got {v} m"),
            ))
        }
    };
    let pair = |k: &str, p: Option<Pair<Qty<Length>>>| -> Result<[f64; 2], FieldError> {
        let p = p.ok_or_else(|| {
            FieldError::new(
                key(k),
                "missing: kind = \"lever\" needs it ([length, length])",
            )
        })?;
        let v = p.0.map(|q| q.si());
        if v.iter().all(|x| x.is_finite()) {
            Ok(v)
        } else {
            Err(FieldError::new(key(k), "must be two finite lengths"))
        }
    };
    Ok(match kind {
        CounterweightKindRaw::Boom => CounterweightKind::Boom,
        CounterweightKindRaw::Hanging => CounterweightKind::Hanging {
            hang_length_m: length("hang_length", c.hang_length)?,
        },
        CounterweightKindRaw::Lever => {
            let angle = c
                .lever_angle
                .ok_or_else(|| {
                    FieldError::new(
                        key("lever_angle"),
                        "missing: kind = \"lever\" needs it (an angle)",
                    )
                })?
                .si();
            if !angle.is_finite() {
                return Err(FieldError::new(
                    key("lever_angle"),
                    "must be a finite angle",
                ));
            }
            CounterweightKind::Lever(LeverSpec {
                pivot_m: pair("lever_pivot", c.lever_pivot)?,
                arm_m: length("lever_arm", c.lever_arm)?,
                angle_at_max_reach_rad: angle,
                rod_boom_point_m: pair("rod_boom_point", c.rod_boom_point)?,
            })
        }
    })
}
