//! The slider-crank problem file — its raw sections and their resolution into a checked
//! [`crate::families::slider_crank::synth::Scene`] (every field documented in
//! `docs/problem-files.md`) — and the shaping of its outcome into a result (keys in
//! `docs/results.md`).

use super::file_envelope::{check_envelope, resolve_envelope, EnvelopeRaw, NamedMass};
use super::file_textbook::{
    fraction_rule, resolve_evaluate_at, resolve_reference, ReferenceRaw, MAX_EVALUATE_AT,
};
use crate::families::slider_crank::model::{Crank, Kinematics, Rod, SliderCrank};
use crate::families::slider_crank::model::{Loads, ProcessForce};
use crate::families::slider_crank::synth::{self as sc, CounterweightSpec, Objective, Prefer};
use crate::problem::limits::{self, c, Count};
use crate::problem::{
    check_name, non_negative, positive, Ctx, FieldError, Input, ProblemError, RawFile, RawVar,
    Resolved,
};
use crate::synth::counterweight::Settings;
use crate::synth::shape::{ShapeGoal, ShapeSpec};
use crate::synth::Var;
use crate::units::{
    Acceleration, Angle, AngularSpeed, Density, Force, Inertia, Length, Mass, Qty, Torque,
    Unbalance,
};
use serde::Deserialize;
use std::f64::consts::{PI, TAU};

/// Smallest counterweight radius (`design.radius`, fixed or a range's lower end above 0) as a
/// fraction of the crank radius: below it the mass |U|/r is out of all proportion to the
/// machine (and at 1e-308 mm it overflowed to inf).
pub const MIN_RADIUS_OF_CRANK: f64 = 1e-6;

/// The least crank radius (m) of a file that leaves the rod length out: the model's stand-in
/// rod of 4R is squared in the loop closure, which must not underflow.
pub const MIN_STAND_IN_CRANK: f64 = 1e-100;

/// The `family = "…"` value of this family's files.
pub const FAMILY: &str = "slider-crank";

/// The problem file `cwsynth new` prints: a clean template (`templates/`), not a paper's
/// scene.
pub const TEMPLATE: &str = include_str!("../../../templates/slider-crank.toml");

/// The work budget of one scene (see [`limits::check_work`] and `check_work` below):
/// every single integer setting at its maximum passes on the shipped files, their products
/// do not, so one machine runs in seconds and can neither stall a batch nor exhaust memory.
pub const WORK_BUDGET: f64 = 1e7;

/// The integer keys of this family's file and their ranges (see [`limits`]).
pub const COUNTS: &[Count] = &[
    c("objective.pareto_points", 0, 200),
    c("objective.speed_sweep.points", 2, 200),
    c("accuracy.initial_samples", 3, 1024),
    c("accuracy.scan_samples", 16, 20_000),
    c("accuracy.max_rounds", 1, 1000),
    c("accuracy.rms_samples", 16, 100_000),
];

#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MechanismRaw {
    /// R.
    pub crank_radius: Qty<Length>,
    /// L (may be left out with `model.kinematics = "primary"`: obliquity neglected).
    pub rod_length: Option<Qty<Length>>,
    /// e (default 0).
    pub offset: Option<Qty<Length>>,
    /// n or ω.
    pub speed: Qty<AngularSpeed>,
    /// m2 (or from `mass_items`).
    pub crank_mass: Option<Qty<Mass>>,
    /// r2 (default R/2).
    pub crank_centroid: Option<Qty<Length>>,
    /// m3.
    pub rod_mass: Qty<Mass>,
    /// m4 (or from `mass_items`).
    pub slider_mass: Option<Qty<Mass>>,
    /// Itemised masses reduced to the crank pin or the slider (replace crank_mass and
    /// slider_mass).
    #[serde(default)]
    #[schemars(length(max = MAX_MASS_ITEMS))]
    pub mass_items: Vec<MassItemRaw>,
    /// Angle of the slider axis (from the crank axis towards the slider) above the horizontal.
    pub slider_axis_angle: Option<Qty<Angle>>,
    /// Constant process force on the slider along the axis, away from the crank.
    pub process_force: Option<Qty<Force>>,
    /// Process force as a periodic table against crank angle.
    pub process_force_table: Option<ForceTableRaw>,
    /// The drive: motor, flywheel and the coefficient of speed fluctuation to meet
    /// (`[mechanism.drive]`, the machine as it runs).
    pub drive: Option<crate::problem::drive::DriveRaw>,
    /// The operating envelope: speed band, mass intervals, length tolerances
    /// (`[mechanism.envelope]`).
    pub envelope: Option<EnvelopeRaw>,
}

/// Where an itemised mass is reduced to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum MassAt {
    /// Moves with the slider.
    Slider,
    /// Turns with the crank pin.
    CrankPin,
}

/// `[[mechanism.mass_items]]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MassItemRaw {
    /// Label.
    pub name: String,
    /// Mass.
    pub mass: Qty<Mass>,
    /// Reduced to.
    pub at: MassAt,
    /// Fraction of the mass reduced there (default 1; ½ for a boom resting on a sub-frame).
    pub fraction: Option<f64>,
}

/// `[mechanism.process_force_table]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ForceTableRaw {
    /// Crank angles, increasing, within one turn.
    #[schemars(length(max = MAX_TABLE_POINTS))]
    pub angle: Vec<Qty<Angle>>,
    /// Forces at those angles.
    #[schemars(length(max = MAX_TABLE_POINTS))]
    pub force: Vec<Qty<Force>>,
}

/// How the rod's mass is modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Masses {
    /// Two point masses (rod split).
    #[default]
    Lumped,
    /// A rigid rod with centre of mass and moment of inertia.
    Rigid,
}

/// `[model]`.
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelRaw {
    /// `exact` (default), `two-harmonic` or `primary` (obliquity neglected).
    pub kinematics: Option<Kinematics>,
    /// `lumped` (default) or `rigid`.
    #[serde(default)]
    pub masses: Masses,
    /// Lumped: fraction of the rod mass at the crank pin (default 0.5).
    pub rod_split: Option<f64>,
    /// Rigid: rod centre of mass from the crank pin (default L/2).
    pub rod_centroid: Option<Qty<Length>>,
    /// Rigid: rod moment of inertia about its centre of mass (default m3 L²/12).
    pub rod_inertia: Option<Qty<Inertia>>,
    /// Model the weights (default false).
    #[serde(default)]
    pub gravity: bool,
    /// g (default 9.80665 m/s²).
    pub gravity_acceleration: Option<Qty<Acceleration>>,
    /// Report the joint loads over the cycle — main bearing O, crank pin A, wrist pin B and
    /// the guide's normal force — from Newton–Euler of the rigid links (default false; on
    /// whenever a joint-load limit is given).
    #[serde(default)]
    pub bearing_loads: bool,
}

/// `[design]`: the counterweight.
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignRaw {
    /// |U| = m r.
    pub unbalance: Option<RawVar<Unbalance>>,
    /// β from the crank line.
    pub angle: Option<RawVar<Angle>>,
    /// m.
    pub mass: Option<RawVar<Mass>>,
    /// r.
    pub radius: Option<RawVar<Length>>,
    /// The textbook rule "balance the rotating mass and a fraction c of the reciprocating
    /// mass" (c = 2/3: the two-thirds rule): fixes U = −(m_tq + c·m_ct)·R opposite the crank
    /// pin (0 ≤ c ≤ 1, dimensionless), so the design is analysed, not optimised.
    pub reciprocating_fraction: Option<f64>,
    /// Split preference.
    #[serde(default)]
    pub prefer: Prefer,
    /// The paper's classical counterweight (formula (6)) as printed.
    pub paper: Option<PaperDesignRaw>,
    /// A reference counterweight of the designer's own (a current design, a supplier's part,
    /// a handbook rule's result), evaluated as the baseline `reference_counterweight`.
    pub reference: Option<ReferenceRaw>,
    /// A plate shape to realise the counterweight.
    pub shape: Option<ShapeRaw>,
    /// Lanchester balancers designed jointly with the counterweight.
    pub balancers: Option<BalancersRaw>,
}

/// `[design.balancers]`: Lanchester balancers, one pair of counter-rotating shafts per order
/// n turning at n·ω, each pair's unbalance B_n designed jointly with the crank counterweight
/// (its force ω²n²|B_n| cos(nφ + arg B_n) acts along the slider axis only).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BalancersRaw {
    /// The orders n of the pairs (each 1 to 4, distinct): 1 balances the primary, 2 the
    /// secondary reciprocating force.
    #[schemars(length(min = 1, max = 4))]
    pub orders: Vec<u32>,
    /// Largest unbalance |B_n| of each pair, the two shafts together (one per order, in the
    /// order of `orders`; default none).
    #[schemars(length(max = 4))]
    pub max_unbalance: Option<Vec<Qty<Unbalance>>>,
    /// The y coordinate of each pair's mid-line across the slider axis, from the crank axis
    /// (one per order; default 0: the pair symmetric about the line through the crank axis,
    /// which adds no shaking moment). A pair at offset h adds the couple −h·F_n,x.
    #[schemars(length(max = 4))]
    pub offset: Option<Vec<Qty<Length>>>,
}

/// `[design.paper]`: the paper's printed inputs and result of the classical formula (6),
/// m_pr = (m_r + ½ m_s)·R / r_pr.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PaperDesignRaw {
    /// The paper's printed rotating mass m_r.
    pub rotating_mass: Option<Qty<Mass>>,
    /// The paper's printed reciprocating mass m_s.
    pub reciprocating_mass: Option<Qty<Mass>>,
    /// The paper's printed counterweight mass m_pr (at the lever radius `lever_radius`,
    /// opposite the crank pin).
    pub counterweight_mass: Option<Qty<Mass>>,
    /// The paper's lever radius r_pr, where its counterweight mass sits (default:
    /// `design.radius` when that is fixed; needed with `[design.shape]`, whose plate sets the
    /// design's own radius).
    pub lever_radius: Option<Qty<Length>>,
}

/// `[design.shape]`: the counterweight is an annular-sector plate; its mass and centroid
/// radius follow from the plate, and |U| is kept within what the envelope holds.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ShapeRaw {
    /// Material density.
    pub density: Qty<Density>,
    /// Plate thickness.
    pub thickness: Qty<Length>,
    /// Smallest inner radius (clearance to the hub).
    pub inner_radius_min: Qty<Length>,
    /// Largest outer radius (envelope).
    pub outer_radius_max: Qty<Length>,
    /// Largest sector angle (default 180°).
    pub max_angle: Option<Qty<Angle>>,
    /// `mass` (default) or `outer-radius`.
    pub minimize: Option<ShapeGoal>,
}

/// What `objective.minimize` can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Minimize {
    /// Peak |F|.
    PeakForce,
    /// RMS |F|.
    RmsForce,
    /// Counterweight mass under `max_peak_force`.
    Mass,
    /// Counterweight radius under `max_peak_force`.
    Radius,
    /// Peak drive torque.
    PeakTorque,
    /// Peak shaking moment about the crank axis, under `max_peak_force`.
    PeakMoment,
    /// Energy fluctuation ΔE of the drive at constant speed (max E − min E, E = ∫ (T − T̄) dφ):
    /// the flywheel a coefficient of speed fluctuation needs is proportional to it.
    EnergyFluctuation,
    /// The least flywheel that meets `[mechanism.drive] cs` in the exact periodic steady
    /// state: not convex in the design, so a search (`best_found` with its evidence).
    FlywheelInertia,
}

/// `[objective]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectiveRaw {
    /// What to minimise.
    pub minimize: Minimize,
    /// Peak shaking-force limit.
    pub max_peak_force: Option<Qty<Force>>,
    /// Peak drive-torque limit.
    pub max_peak_torque: Option<Qty<Torque>>,
    /// Peak shaking-moment limit (about the crank axis).
    pub max_shaking_moment: Option<Qty<Torque>>,
    /// Peak main-bearing load limit (a cone constraint on the counterweight; not with
    /// gravity, whose counterweight weight depends on how |U| splits into mass and radius).
    pub max_main_bearing_load: Option<Qty<Force>>,
    /// Peak crank-pin load limit (checked: the load does not depend on the design).
    pub max_crank_pin_load: Option<Qty<Force>>,
    /// Peak wrist-pin load limit (checked: the load does not depend on the design).
    pub max_wrist_pin_load: Option<Qty<Force>>,
    /// Peak guide normal-force limit (checked: the force does not depend on the design).
    pub max_guide_load: Option<Qty<Force>>,
    /// Points of the torque–force Pareto front (0 or absent: none).
    #[serde(default)]
    pub pareto_points: usize,
    /// Re-optimise over a range of speeds.
    pub speed_sweep: Option<SpeedSweepRaw>,
    /// Crank angles (φ from the crank pin towards the slider: inner dead centre) at which the
    /// result lists the design's shaking force, its components and the drive torque
    /// (`at_angles`), e.g. a textbook's "30° from inner dead centre".
    #[serde(default)]
    #[schemars(length(max = MAX_EVALUATE_AT))]
    pub evaluate_at: Vec<Qty<Angle>>,
}

/// `[objective.speed_sweep]`: the scene re-optimised at evenly spaced speeds.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpeedSweepRaw {
    /// Lowest speed.
    pub min: Qty<AngularSpeed>,
    /// Highest speed.
    pub max: Qty<AngularSpeed>,
    /// Number of speeds (2–200).
    pub points: usize,
}

pub use super::synth::{SpeedSweep, SweepPoint};

/// `[accuracy]`: the family's solver [`Settings`] read directly (every key optional, unknown
/// keys rejected), then validated; errors name `accuracy.<key>`.
pub type AccuracyRaw = Settings;

/// Validates the `[accuracy]` section.
fn resolve_accuracy(s: &Settings) -> Result<Settings, FieldError> {
    let s = *s;
    // The defaults are in range (tested); a fleet's rows mostly keep them.
    if s != Settings::default() {
        limits::check_section(COUNTS, "accuracy", &s)?;
    }
    s.validate()
        .map_err(|(f, m)| FieldError::new(format!("accuracy.{f}"), m))?;
    Ok(s)
}

/// A resolved slider-crank scene: the synthesis scene plus what only the report needs.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SliderCrankProblem {
    /// The synthesis scene.
    pub core: sc::Scene,
    /// The paper's printed classical design (formula (6)), if given.
    pub paper: Option<PaperDesign>,
    /// Speeds to re-optimise at, if asked for.
    pub speed_sweep: Option<SpeedSweep>,
    /// The drive at real speed (`[mechanism.drive]`), if given.
    pub drive: Option<crate::dynamics::Drive>,
    /// Whether the file gives the rod length: left out (obliquity neglected), the model
    /// carries a stand-in of 4R that no figure depends on, and nothing draws the rod.
    pub rod_length_given: bool,
    /// The crank angles (rad) of `objective.evaluate_at`.
    pub evaluate_at: Vec<f64>,
    /// `[design.reference]`: the reference counterweight's unbalance U (kg·m, crank frame).
    pub reference: Option<[f64; 2]>,
    /// `minimize = "flywheel-inertia"`: the design searched for the least flywheel that meets
    /// the drive's Cs (the core scene then holds the force objective of its start).
    pub flywheel_objective: bool,
}

/// The paper's printed inputs and output of formula (6) (SI).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PaperDesign {
    /// Printed m_r (kg).
    pub rotating_mass: Option<f64>,
    /// Printed m_s (kg).
    pub reciprocating_mass: Option<f64>,
    /// Printed m_pr (kg).
    pub counterweight_mass: Option<f64>,
    /// The lever radius r_pr (m) of formula (6): `lever_radius` or the fixed `design.radius`.
    pub lever_radius: Option<f64>,
}

/// The whole slider-crank file.
pub type File = RawFile<MechanismRaw, ModelRaw, DesignRaw, ObjectiveRaw, AccuracyRaw>;

/// Reads and resolves a slider-crank problem file (its text or its table).
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Resolved<SliderCrankProblem>, ProblemError> {
    File::resolve(ctx, input, resolve_raw)
}

/// Most points of `[mechanism.process_force_table]` (a measured cycle at 0.1° is 3600).
pub const MAX_TABLE_POINTS: usize = 10_000;

/// Most `[[mechanism.mass_items]]`.
pub const MAX_MASS_ITEMS: usize = 1000;

/// The value checks of a slider-crank file, section by section in the file's order: the
/// name, the mechanism and its loads ([`resolve_mechanism`]), the counterweight's variables
/// ([`resolve_counterweight`]), the objective and its limits ([`resolve_objective`]), the
/// accuracy, the paper's design, the plate, the balancers, the load limits, the joint
/// design's requirements, the speed sweep and the work budget.
pub fn resolve_raw(raw: &File) -> Result<SliderCrankProblem, FieldError> {
    check_name(&raw.name)?;
    let m = &raw.mechanism;
    let md = &raw.model;
    let (mech, omega, loads) = resolve_mechanism(m, md)?;
    let d = &raw.design;
    let o = &raw.objective;
    let (unbalance, angle, mass, radius) = resolve_counterweight(d, &mech)?;
    let (objective, max_peak_force, max_peak_torque) = resolve_objective(o, d, mass, radius)?;
    let settings = resolve_accuracy(&raw.accuracy)?;
    let paper = resolve_paper(d, radius)?;
    let shape = resolve_shape(d, unbalance)?;
    let balancers = match &d.balancers {
        None => Vec::new(),
        Some(b) => resolve_balancers(b)?,
    };
    let force_limit = |q: Option<Qty<Force>>, f: &str| q.map(|q| positive(f, q.si())).transpose();
    let load_limits = sc::LoadLimits {
        main_bearing: force_limit(o.max_main_bearing_load, "objective.max_main_bearing_load")?,
        crank_pin: force_limit(o.max_crank_pin_load, "objective.max_crank_pin_load")?,
        wrist_pin: force_limit(o.max_wrist_pin_load, "objective.max_wrist_pin_load")?,
        guide: force_limit(o.max_guide_load, "objective.max_guide_load")?,
    };
    let max_shaking_moment = o
        .max_shaking_moment
        .map(|q| positive("objective.max_shaking_moment", q.si()))
        .transpose()?;
    let mut core = sc::Scene {
        mech,
        omega,
        counterweight: CounterweightSpec {
            unbalance,
            angle,
            mass,
            radius,
            prefer: d.prefer,
            shape,
        },
        objective,
        max_peak_force,
        max_peak_torque,
        loads,
        pareto_points: o.pareto_points,
        settings,
        balancers,
        max_shaking_moment,
        load_limits,
        bearing_loads: md.bearing_loads,
        envelope: sc::Envelope::default(),
    };
    if let Some(e) = &m.envelope {
        let items: Vec<NamedMass> = m
            .mass_items
            .iter()
            .map(|it| NamedMass {
                name: &it.name,
                of: match it.at {
                    MassAt::Slider => sc::MassOf::Slider,
                    MassAt::CrankPin => sc::MassOf::CrankPin,
                },
                mass: it.mass.si(),
                fraction: it.fraction.unwrap_or(1.0),
            })
            .collect();
        core.envelope = resolve_envelope(&items, e, &core)?;
        check_envelope(&core, o.speed_sweep.is_some())?;
    }
    if core.joint() {
        check_joint(&core, o.speed_sweep.is_some(), md.gravity)?;
    }
    let speed_sweep = resolve_speed_sweep(o)?;
    check_work(&core, speed_sweep.as_ref())?;
    let drive = m
        .drive
        .as_ref()
        .map(crate::problem::drive::resolve)
        .transpose()?;
    let rod_length_given = m.rod_length.is_some();
    if !rod_length_given
        && core
            .envelope
            .lengths
            .iter()
            .any(|l| l.of == sc::LengthOf::RodLength)
    {
        return Err(FieldError::new(
            "mechanism.envelope.length",
            "a rod-length tolerance needs mechanism.rod_length",
        ));
    }
    let flywheel_objective = o.minimize == Minimize::FlywheelInertia;
    if flywheel_objective {
        check_flywheel_objective(&core, drive.as_ref(), speed_sweep.is_some())?;
    }
    Ok(SliderCrankProblem {
        core,
        paper,
        speed_sweep,
        drive,
        rod_length_given,
        flywheel_objective,
        reference: resolve_reference(d.reference.as_ref(), radius)?,
        evaluate_at: resolve_evaluate_at(&o.evaluate_at)?,
    })
}

/// `[mechanism]` and `[model]`: the slider-crank (R, L, e, the kinematics, the crank, the
/// rod and the slider), its speed ω and its loads (gravity in the slider axis' frame,
/// the process force); the crank must turn a full revolution, (R + |e|)/L < 1.
fn resolve_mechanism(
    m: &MechanismRaw,
    md: &ModelRaw,
) -> Result<(SliderCrank, f64, Loads), FieldError> {
    let r = positive("mechanism.crank_radius", m.crank_radius.si())?;
    let e = m.offset.map_or(0.0, |q| q.si());
    let kinematics = md.kinematics.unwrap_or(Kinematics::Exact);
    let l = match m.rod_length {
        Some(q) => positive("mechanism.rod_length", q.si())?,
        // Obliquity neglected: no figure depends on L (a lumped rod's split is a fraction).
        None if kinematics == Kinematics::Primary && md.masses == Masses::Lumped => {
            // The stand-in's square must not underflow (the loop closure squares it).
            if r < MIN_STAND_IN_CRANK {
                return Err(FieldError::new(
                    "mechanism.crank_radius",
                    format!("{r:e} m without a rod length; allowed: at least {MIN_STAND_IN_CRANK:e} m (or give mechanism.rod_length)"),
                ));
            }
            4.0 * r
        }
        None => {
            return Err(FieldError::new(
                "mechanism.rod_length",
                "missing field `rod_length`: it may be left out only with model.kinematics = \"primary\" (obliquity neglected) and a lumped rod",
            ))
        }
    };
    let omega = positive("mechanism.speed", m.speed.si())?;
    let m3 = non_negative("mechanism.rod_mass", m.rod_mass.si())?;
    let (m2, m4, r2) = resolve_link_masses(m, r)?;
    let ratio = (r + e.abs()) / l;
    if ratio >= 1.0 {
        return Err(FieldError::new(
            "mechanism.rod_length",
            format!(
                "the crank cannot turn a full revolution: (R + |e|)/L = {ratio:.6} ≥ 1 (λ = R/L = {:.6}); allowed: rod_length > crank_radius + |offset| = {} m",
                r / l,
                r + e.abs()
            ),
        ));
    }
    if m2 + m3 + m4 <= 0.0 {
        return Err(FieldError::new(
            "mechanism.slider_mass",
            "all link masses are zero: nothing to balance; allowed: some mass > 0",
        ));
    }
    if kinematics != Kinematics::Exact && e != 0.0 {
        return Err(FieldError::new(
            "model.kinematics",
            "the two-harmonic series and the primary-only model are the in-line slider's; with an offset use \"exact\"",
        ));
    }
    let rod = resolve_rod(md, m3, l)?;
    let g = md.gravity_acceleration.map_or(9.80665, |q| q.si());
    if md.gravity_acceleration.is_some() && !md.gravity {
        return Err(FieldError::new(
            "model.gravity_acceleration",
            "given but model.gravity is false; set gravity = true or remove it",
        ));
    }
    non_negative("model.gravity_acceleration", g)?;
    let axis = m.slider_axis_angle.map_or(0.0, |q| q.si());
    let gravity = if md.gravity {
        Loads::gravity_for_axis(g, axis)
    } else {
        crate::geom::P2::zeros()
    };
    let process = resolve_process_force(m)?;
    let mech = SliderCrank {
        r,
        l,
        e,
        kinematics,
        crank: Crank {
            mass: m2,
            centroid: r2,
        },
        rod,
        slider_mass: m4,
    };
    Ok((mech, omega, Loads { gravity, process }))
}

/// The crank-pin mass m₂, the slider mass m₄ and the crank's centroid radius r₂: given
/// (r₂ = R/2 by default), or summed from `[[mechanism.mass_items]]` (each item's fraction
/// of its mass at the crank pin or at the slider; r₂ = R).
fn resolve_link_masses(m: &MechanismRaw, r: f64) -> Result<(f64, f64, f64), FieldError> {
    Ok(if m.mass_items.is_empty() {
        let need = |q: Option<Qty<Mass>>, f: &str| {
            q.map(|q| q.si()).ok_or_else(|| {
                FieldError::new(
                    f,
                    "missing: give it, or itemise the masses in [[mechanism.mass_items]]",
                )
            })
        };
        let m2 = non_negative(
            "mechanism.crank_mass",
            need(m.crank_mass, "mechanism.crank_mass")?,
        )?;
        let m4 = non_negative(
            "mechanism.slider_mass",
            need(m.slider_mass, "mechanism.slider_mass")?,
        )?;
        let r2 = non_negative(
            "mechanism.crank_centroid",
            m.crank_centroid.map_or(0.5 * r, |q| q.si()),
        )?;
        (m2, m4, r2)
    } else {
        for (q, f) in [
            (m.crank_mass, "mechanism.crank_mass"),
            (m.slider_mass, "mechanism.slider_mass"),
        ] {
            if q.is_some() {
                return Err(FieldError::new(
                    f,
                    "given together with mechanism.mass_items; allowed: one or the other",
                ));
            }
        }
        if m.crank_centroid.is_some() {
            return Err(FieldError::new(
                "mechanism.crank_centroid",
                "itemised crank-pin masses are at the crank pin (r2 = R); remove crank_centroid",
            ));
        }
        if m.mass_items.len() > MAX_MASS_ITEMS {
            return Err(FieldError::new(
                format!("mechanism.mass_items[{MAX_MASS_ITEMS}]"),
                format!(
                    "{} items; allowed: at most {MAX_MASS_ITEMS}",
                    m.mass_items.len()
                ),
            ));
        }
        let (mut pin, mut slider) = (0.0, 0.0);
        for (i, it) in m.mass_items.iter().enumerate() {
            let f = format!("mechanism.mass_items[{i}]");
            let mass = non_negative(&format!("{f}.mass"), it.mass.si())?;
            let frac = it.fraction.unwrap_or(1.0);
            if !(0.0..=1.0).contains(&frac) {
                return Err(FieldError::new(
                    format!("{f}.fraction"),
                    format!("got {frac}; allowed: 0 ≤ fraction ≤ 1"),
                ));
            }
            match it.at {
                MassAt::CrankPin => pin += frac * mass,
                MassAt::Slider => slider += frac * mass,
            }
        }
        (pin, slider, r)
    })
}

/// The rod of `[model]`: lumped (its mass m₃ split between the crank pin and the slider by
/// `rod_split`) or rigid (centroid and inertia), on a rod of length `l`.
fn resolve_rod(md: &ModelRaw, m3: f64, l: f64) -> Result<Rod, FieldError> {
    Ok(match md.masses {
        self::Masses::Lumped => {
            if md.rod_centroid.is_some() || md.rod_inertia.is_some() {
                let f = if md.rod_centroid.is_some() {
                    "model.rod_centroid"
                } else {
                    "model.rod_inertia"
                };
                return Err(FieldError::new(
                    f,
                    "only used with masses = \"rigid\"; a lumped rod takes rod_split",
                ));
            }
            let s = md.rod_split.unwrap_or(0.5);
            if !(0.0..=1.0).contains(&s) {
                return Err(FieldError::new(
                    "model.rod_split",
                    format!("got {s}; allowed: 0 ≤ rod_split ≤ 1 (fraction at the crank pin)"),
                ));
            }
            Rod::lumped(m3, s, l)
        }
        self::Masses::Rigid => {
            if md.rod_split.is_some() {
                return Err(FieldError::new("model.rod_split", "only used with masses = \"lumped\"; a rigid rod takes rod_centroid and rod_inertia"));
            }
            let c = md.rod_centroid.map(|q| q.si());
            if let Some(c) = c {
                if !(0.0..=l).contains(&c) {
                    return Err(FieldError::new(
                        "model.rod_centroid",
                        format!("got {c} m; allowed: 0 ≤ rod_centroid ≤ rod_length = {l} m"),
                    ));
                }
            }
            let i = md.rod_inertia.map(|q| q.si());
            if let Some(i) = i {
                non_negative("model.rod_inertia", i)?;
            }
            Rod::rigid(m3, l, c, i)
        }
    })
}

/// The process force on the slider: none, a constant, or a table over the crank angle
/// (strictly increasing angles spanning less than a turn, at most [`MAX_TABLE_POINTS`]).
fn resolve_process_force(m: &MechanismRaw) -> Result<ProcessForce, FieldError> {
    Ok(match (&m.process_force, &m.process_force_table) {
        (Some(_), Some(_)) => {
            return Err(FieldError::new(
                "mechanism.process_force_table",
                "given together with mechanism.process_force; allowed: one or the other",
            ))
        }
        (Some(f), None) => ProcessForce::Constant(f.si()),
        (None, Some(t)) => {
            if t.angle.len() > MAX_TABLE_POINTS {
                return Err(FieldError::new(
                    "mechanism.process_force_table.angle",
                    format!(
                        "{} points; allowed: at most {MAX_TABLE_POINTS}",
                        t.angle.len()
                    ),
                ));
            }
            let angles: Vec<f64> = t.angle.iter().map(|q| q.si()).collect();
            let forces: Vec<f64> = t.force.iter().map(|q| q.si()).collect();
            if angles.len() != forces.len() || angles.is_empty() {
                return Err(FieldError::new(
                    "mechanism.process_force_table",
                    format!(
                        "{} angles and {} forces; allowed: equal, non-empty lists",
                        angles.len(),
                        forces.len()
                    ),
                ));
            }
            if angles.windows(2).any(|w| !(w[1] > w[0]))
                || angles[angles.len() - 1] - angles[0] >= std::f64::consts::TAU
            {
                return Err(FieldError::new(
                    "mechanism.process_force_table.angle",
                    "allowed: strictly increasing angles spanning less than one turn",
                ));
            }
            ProcessForce::Table { angles, forces }
        }
        (None, None) => ProcessForce::None,
    })
}

/// The counterweight's variables of `[design]`: the unbalance |U|, the angle β (fixed, a
/// range at most 180° wide, or the full circle), and the mass and radius when given (the
/// radius not below [`MIN_RADIUS_OF_CRANK`] × R, a fixed m·r inside the unbalance bounds).
fn resolve_counterweight(
    d: &DesignRaw,
    mech: &SliderCrank,
) -> Result<(Var, Var, Option<Var>, Option<Var>), FieldError> {
    let r = mech.r;
    let var = |v: &Option<RawVar<_>>, f: &str, default: Var| -> Result<Var, FieldError> {
        let v = v.map(|v| v.resolve(f)).transpose()?.unwrap_or(default);
        let (lo, _) = v.bounds();
        non_negative(f, lo)?;
        Ok(v)
    };
    let unbalance = var(
        &d.unbalance,
        "design.unbalance",
        Var::Free {
            min: 0.0,
            max: f64::INFINITY,
        },
    )?;
    let mass = d.mass.map(|v| v.resolve("design.mass")).transpose()?;
    let radius = d.radius.map(|v| v.resolve("design.radius")).transpose()?;
    for (v, f) in [(mass, "design.mass"), (radius, "design.radius")] {
        if let Some(v) = v {
            non_negative(f, v.bounds().0)?;
        }
    }
    // m = |U|/r: a counterweight radius far below the crank's makes the mass overflow (a
    // radius of 1e-308 mm gave an infinite mass), so it has a floor relative to the machine.
    if let Some(v) = radius {
        let floor = MIN_RADIUS_OF_CRANK * r;
        let lo = v.bounds().0;
        if lo < floor && (v.fixed().is_some() || lo > 0.0) {
            return Err(FieldError::new(
                "design.radius",
                format!(
                    "{lo:e} m is below {MIN_RADIUS_OF_CRANK:e} × crank_radius = {floor:e} m: the counterweight's mass |U|/r would be out of all proportion to the machine; allowed: a radius ≥ {floor:e} m (a free range may start at 0)"
                ),
            ));
        }
    }
    if let (Some(Var::Fixed(mm)), Some(Var::Fixed(rr))) = (mass, radius) {
        if !unbalance.contains(mm * rr) {
            return Err(FieldError::new(
                "design.unbalance",
                format!(
                    "mass × radius = {} kg·m is outside the unbalance bounds {:?}",
                    mm * rr,
                    unbalance.bounds()
                ),
            ));
        }
    }
    if let Some(c) = d.reciprocating_fraction {
        let given = [
            (d.unbalance.is_some(), "design.unbalance"),
            (d.angle.is_some(), "design.angle"),
            (d.shape.is_some(), "design.shape"),
            (d.balancers.is_some(), "design.balancers"),
            (mass.is_some() && radius.is_some(), "design.mass"),
        ];
        return fraction_rule(c, &given, mech, mass, radius);
    }
    let angle = match d.angle.map(|v| v.resolve("design.angle")).transpose()? {
        None => Var::Free { min: 0.0, max: TAU },
        Some(Var::Free { min, max }) if max - min < TAU - 1e-9 && max - min > PI + 1e-12 => {
            return Err(FieldError::new(
                "design.angle",
                format!(
                    "a range {:.3}° wide is not convex; allowed: a fixed angle, a range at most 180° wide, or the full circle (360°)",
                    (max - min).to_degrees()
                ),
            ))
        }
        Some(v) => v,
    };
    Ok((unbalance, angle, mass, radius))
}

/// `minimize = "flywheel-inertia"` needs `[mechanism.drive]` with `cs` and no given
/// flywheel, and a counterweight its search can move alone: no balancers, envelope, plate,
/// front, sweep, moment or joint-load limit.
fn check_flywheel_objective(
    core: &sc::Scene,
    drive: Option<&crate::dynamics::Drive>,
    sweep: bool,
) -> Result<(), FieldError> {
    const F: &str = "objective.minimize";
    match drive {
        Some(d) if d.cs.is_some() && d.flywheel.is_none() => {}
        _ => {
            return Err(FieldError::new(
                F,
                "\"flywheel-inertia\" needs [mechanism.drive] with cs (the coefficient of speed fluctuation to meet) and no flywheel (the flywheel is what it minimises)",
            ))
        }
    }
    let other = [
        (!core.balancers.is_empty(), "design.balancers"),
        (!core.envelope.is_empty(), "mechanism.envelope"),
        (core.counterweight.shape.is_some(), "design.shape"),
        (core.pareto_points > 0, "objective.pareto_points"),
        (sweep, "objective.speed_sweep"),
        (
            core.max_shaking_moment.is_some(),
            "objective.max_shaking_moment",
        ),
        (core.joint(), "objective.max_main_bearing_load"),
    ];
    match other.iter().find(|(on, _)| *on) {
        Some((_, f)) => Err(FieldError::new(
            *f,
            "not with minimize = \"flywheel-inertia\" (a search over the counterweight alone, with max_peak_force and max_peak_torque as its limits)",
        )),
        None => Ok(()),
    }
}

/// `[objective]`: what is minimised and the peak-force and peak-torque limits (a mass or
/// radius objective needs a force limit and a counterweight that has a mass and a radius),
/// and the Pareto points' count (0, or 2 to 200).
fn resolve_objective(
    o: &ObjectiveRaw,
    d: &DesignRaw,
    mass: Option<Var>,
    radius: Option<Var>,
) -> Result<(Objective, Option<f64>, Option<f64>), FieldError> {
    let objective = match o.minimize {
        Minimize::PeakForce => Objective::MinPeakForce,
        Minimize::RmsForce => Objective::MinRmsForce,
        Minimize::Mass => Objective::MinMass,
        Minimize::Radius => Objective::MinRadius,
        Minimize::PeakTorque => Objective::MinPeakTorque,
        Minimize::PeakMoment => Objective::MinPeakMoment,
        Minimize::EnergyFluctuation => Objective::MinEnergyFluctuation,
        // Searched over the certified force optimum's scene (`flywheel_design.rs`).
        Minimize::FlywheelInertia => Objective::MinPeakForce,
    };
    let max_peak_force = o
        .max_peak_force
        .map(|q| positive("objective.max_peak_force", q.si()))
        .transpose()?;
    if matches!(objective, Objective::MinMass | Objective::MinRadius) {
        if max_peak_force.is_none() {
            return Err(FieldError::new(
                "objective.max_peak_force",
                "missing: minimize = \"mass\" or \"radius\" needs a peak-force limit (e.g. \"400 N\")",
            ));
        }
        if let Some(want) = d.shape.as_ref().and_then(|sh| sh.minimize) {
            let asked = if objective == Objective::MinMass {
                ShapeGoal::Mass
            } else {
                ShapeGoal::OuterRadius
            };
            if want != asked {
                return Err(FieldError::new(
                    "design.shape.minimize",
                    "contradicts objective.minimize: the objective chooses the plate (\"mass\": the lightest, \"radius\": the smallest outer radius); remove design.shape.minimize",
                ));
            }
        }
        if d.shape.is_none() && (mass.is_none() || radius.is_none()) {
            return Err(FieldError::new(
                "objective.minimize",
                "minimizing the counterweight's mass or radius needs design.mass and design.radius (fixed or ranges)",
            ));
        }
    }
    let max_peak_torque = o
        .max_peak_torque
        .map(|q| positive("objective.max_peak_torque", q.si()))
        .transpose()?;
    limits::check(COUNTS, "objective.pareto_points", o.pareto_points as i128)?;
    if o.pareto_points == 1 {
        return Err(FieldError::new(
            "objective.pareto_points",
            format!("got {}; allowed: 0 (none) or 2 to 200", o.pareto_points),
        ));
    }
    Ok((objective, max_peak_force, max_peak_torque))
}

/// `[design.paper]`: the paper's printed design, its counterweight with a lever radius
/// (`lever_radius` or the fixed `design.radius`).
fn resolve_paper(d: &DesignRaw, radius: Option<Var>) -> Result<Option<PaperDesign>, FieldError> {
    Ok(match &d.paper {
        None => None,
        Some(p) => {
            let pos = |q: Option<Qty<Mass>>, f: &str| q.map(|q| positive(f, q.si())).transpose();
            let lever_radius = match p.lever_radius {
                Some(q) => Some(positive("design.paper.lever_radius", q.si())?),
                None => radius.and_then(|r| r.fixed()),
            };
            let pd = PaperDesign {
                rotating_mass: pos(p.rotating_mass, "design.paper.rotating_mass")?,
                reciprocating_mass: pos(p.reciprocating_mass, "design.paper.reciprocating_mass")?,
                counterweight_mass: pos(p.counterweight_mass, "design.paper.counterweight_mass")?,
                lever_radius,
            };
            if pd.counterweight_mass.is_some() && lever_radius.is_none() {
                return Err(FieldError::new(
                    "design.paper.counterweight_mass",
                    "the paper's counterweight needs its lever radius: give design.paper.lever_radius (or design.radius as a fixed value)",
                ));
            }
            Some(pd)
        }
    })
}

/// `[design.shape]`: the plate's envelope (outer radius above the inner, 0 < angle ≤ 360°),
/// which is the counterweight (no design.mass or design.radius with it) and must hold the
/// unbalance's minimum.
fn resolve_shape(d: &DesignRaw, unbalance: Var) -> Result<Option<ShapeSpec>, FieldError> {
    Ok(match &d.shape {
        None => None,
        Some(sh) => {
            let spec = ShapeSpec {
                density: positive("design.shape.density", sh.density.si())?,
                thickness: positive("design.shape.thickness", sh.thickness.si())?,
                inner_radius_min: non_negative(
                    "design.shape.inner_radius_min",
                    sh.inner_radius_min.si(),
                )?,
                outer_radius_max: positive(
                    "design.shape.outer_radius_max",
                    sh.outer_radius_max.si(),
                )?,
                max_angle: sh.max_angle.map_or(std::f64::consts::PI, |q| q.si()),
                goal: sh.minimize.unwrap_or_default(),
            };
            if spec.outer_radius_max <= spec.inner_radius_min {
                return Err(FieldError::new(
                    "design.shape.outer_radius_max",
                    "allowed: outer_radius_max > inner_radius_min",
                ));
            }
            if !(spec.max_angle > 0.0 && spec.max_angle <= TAU) {
                return Err(FieldError::new(
                    "design.shape.max_angle",
                    "allowed: 0 < max_angle ≤ 360°",
                ));
            }
            // One object: the plate sets the mass and the radius.
            for (given, f) in [
                (d.mass.is_some(), "design.mass"),
                (d.radius.is_some(), "design.radius"),
            ] {
                if given {
                    return Err(FieldError::new(
                        f,
                        "not allowed with [design.shape]: the plate is the counterweight, its mass and centroid radius follow from the plate (a lever radius for the paper's formula goes in design.paper.lever_radius)",
                    ));
                }
            }
            let u_max = spec.max_unbalance();
            let u_min = unbalance.bounds().0;
            if u_min > u_max {
                return Err(FieldError::new(
                    "design.shape",
                    format!(
                        "the envelope holds at most |U| = {u_max:.6} kg·m, below design.unbalance's minimum {u_min:.6} kg·m: enlarge outer_radius_max, thickness or max_angle"
                    ),
                ));
            }
            Some(spec)
        }
    })
}

/// `[objective.speed_sweep]`: the speeds 0 < min < max (rad/s) and their count.
fn resolve_speed_sweep(o: &ObjectiveRaw) -> Result<Option<SpeedSweep>, FieldError> {
    Ok(match &o.speed_sweep {
        None => None,
        Some(sw) => {
            let min = positive("objective.speed_sweep.min", sw.min.si())?;
            let max = positive("objective.speed_sweep.max", sw.max.si())?;
            if max <= min {
                return Err(FieldError::new(
                    "objective.speed_sweep.max",
                    "allowed: max > min",
                ));
            }
            limits::check(COUNTS, "objective.speed_sweep.points", sw.points as i128)?;
            Some(SpeedSweep {
                min,
                max,
                points: sw.points,
            })
        }
    })
}

/// `[design.balancers]` into the scene's pairs (their unbalance 0: the design variable).
fn resolve_balancers(b: &BalancersRaw) -> Result<Vec<sc::BalancerSpec>, FieldError> {
    let f = "design.balancers";
    if b.orders.is_empty() || b.orders.len() > 4 {
        return Err(FieldError::new(
            format!("{f}.orders"),
            format!(
                "{} orders; allowed: 1 to 4 distinct orders from 1 to 4",
                b.orders.len()
            ),
        ));
    }
    let mut seen = [false; 5];
    for (i, &n) in b.orders.iter().enumerate() {
        if !(1..=4).contains(&n) || seen[n as usize] {
            return Err(FieldError::new(
                format!("{f}.orders[{i}]"),
                format!("got {n}; allowed: distinct orders from 1 to 4"),
            ));
        }
        seen[n as usize] = true;
    }
    let per_order = |len: Option<usize>, key: &str| match len {
        Some(l) if l != b.orders.len() => Err(FieldError::new(
            format!("{f}.{key}"),
            format!(
                "{l} values for {} orders; allowed: one per order",
                b.orders.len()
            ),
        )),
        _ => Ok(()),
    };
    per_order(b.max_unbalance.as_ref().map(Vec::len), "max_unbalance")?;
    per_order(b.offset.as_ref().map(Vec::len), "offset")?;
    b.orders
        .iter()
        .enumerate()
        .map(|(i, &order)| {
            let max_unbalance = match &b.max_unbalance {
                Some(v) => positive(&format!("{f}.max_unbalance[{i}]"), v[i].si())?,
                None => f64::INFINITY,
            };
            let offset = b.offset.as_ref().map_or(0.0, |v| v[i].si());
            if !offset.is_finite() {
                return Err(FieldError::new(
                    format!("{f}.offset[{i}]"),
                    "allowed: a finite length",
                ));
            }
            Ok(sc::BalancerSpec {
                pair: crate::families::slider_crank::model::BalancerPair { order, offset },
                max_unbalance,
                unbalance: [0.0; 2],
            })
        })
        .collect()
}

/// What a joint design (balancers, a moment objective or limit, a main-bearing limit) cannot
/// be combined with, each refused with the key to change.
fn check_joint(core: &sc::Scene, sweep: bool, gravity: bool) -> Result<(), FieldError> {
    let why = "with design.balancers, minimize = \"peak-moment\", max_shaking_moment or max_main_bearing_load (the joint design)";
    if matches!(core.objective, Objective::MinMass | Objective::MinRadius) {
        return Err(FieldError::new(
            "objective.minimize",
            format!("\"mass\" and \"radius\" are not available {why}; allowed: \"peak-force\", \"rms-force\", \"peak-torque\", \"peak-moment\""),
        ));
    }
    if matches!(
        core.objective,
        Objective::MinPeakMoment | Objective::MinPeakTorque
    ) && core.max_peak_force.is_none()
    {
        return Err(FieldError::new(
            "objective.max_peak_force",
            format!("missing: minimising the moment or the torque {why} leaves the counterweight free (it adds no moment and, without gravity, no torque); give a peak-force limit"),
        ));
    }
    if core.pareto_points > 0 {
        return Err(FieldError::new(
            "objective.pareto_points",
            format!("the torque–force Pareto front is not available {why}"),
        ));
    }
    if sweep {
        return Err(FieldError::new(
            "objective.speed_sweep",
            format!("the speed sweep is not available {why}"),
        ));
    }
    let u = core.counterweight.unbalance;
    if u.bounds().0 > 0.0 {
        return Err(FieldError::new(
            "design.unbalance",
            format!("a lower bound on |U| (or a fixed |U|) is not convex and not available {why}; allowed: a range from 0"),
        ));
    }
    if !(sc::unbalance_bounds(&core.counterweight).1 > 0.0) {
        return Err(FieldError::new(
            "design.unbalance",
            format!("|U| bounded to 0 is not available {why}; allowed: an upper bound > 0"),
        ));
    }
    if core.load_limits.main_bearing.is_some() && gravity {
        return Err(FieldError::new(
            "objective.max_main_bearing_load",
            "not available with model.gravity: the main bearing carries the counterweight's weight, which depends on how |U| splits into mass and radius (not affine in U); remove the limit (the load is still reported with model.bearing_loads)",
        ));
    }
    Ok(())
}

/// The work budget ([`limits::check_work`]): W = (1 + P + S)·(K·(n_scan + n_init + K) +
/// n_rms), P the Pareto points, S the sweep's speeds (each a whole re-solve), K the exchange
/// rounds (each scans n_scan angles and solves a cone program of at most n_init + K
/// constraints), n_rms the RMS samples.
fn check_work(core: &sc::Scene, sweep: Option<&SpeedSweep>) -> Result<(), FieldError> {
    let s = &core.settings;
    let d = Settings::default();
    let sweep = sweep.map_or(0, |w| w.points);
    let rounds = s.max_rounds as f64;
    let estimate = (1.0 + core.pareto_points as f64 + sweep as f64)
        * (rounds * (s.scan_n() as f64 + s.initial_samples as f64 + rounds) + s.rms_n() as f64);
    limits::check_work(
        WORK_BUDGET,
        FAMILY,
        estimate,
        "(1 + pareto_points + speed_sweep.points)·(max_rounds·(scan_samples + initial_samples + max_rounds) + rms_samples)",
        &[
            limits::term("objective.pareto_points", core.pareto_points as f64, 1.0),
            limits::term("objective.speed_sweep.points", sweep as f64, 1.0),
            limits::term("accuracy.max_rounds", rounds, d.max_rounds as f64),
            limits::term("accuracy.scan_samples", s.scan_n() as f64, d.scan_n() as f64),
            limits::term("accuracy.initial_samples", s.initial_samples as f64, d.initial_samples as f64),
            limits::term("accuracy.rms_samples", s.rms_n() as f64, d.rms_n() as f64),
        ],
    )
}
