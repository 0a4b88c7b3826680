//! The slider-crank problem file — its raw sections and their resolution into a checked
//! [`crate::families::slider_crank::synth::Scene`] (every field documented in
//! `docs/problem-files.md`) — and the shaping of its outcome into a result (keys in
//! `docs/results.md`). The `[design]` and `[objective]` checks are `file_design.rs`', the mass
//! items `file_masses.rs`', the envelope `file_envelope.rs`' and the textbook rules
//! `file_textbook.rs`'; their public items are re-exported here.

use super::file_design::{
    check_flywheel_objective, check_joint, resolve_balancers, resolve_counterweight,
    resolve_objective, resolve_paper, resolve_shape, resolve_speed_sweep,
};
pub use super::file_design::{
    BalancersRaw, DesignRaw, Minimize, ObjectiveRaw, PaperDesign, PaperDesignRaw, ShapeRaw,
    SpeedSweepRaw, COUNTS, MIN_RADIUS_OF_CRANK,
};
use super::file_envelope::{check_envelope, resolve_envelope, EnvelopeRaw};
use super::file_masses::{named_masses, resolve_link_masses, LinkMassKeys};
pub use super::file_masses::{DrawnMass, MassAt, MassItem, MassItemRaw, MAX_MASS_ITEMS};
use super::file_textbook::{resolve_evaluate_at, resolve_reference};
use crate::families::slider_crank::model::{Crank, Kinematics, Rod, SliderCrank};
use crate::families::slider_crank::model::{Loads, ProcessForce};
use crate::families::slider_crank::synth::{self as sc, CounterweightSpec};
use crate::problem::limits;
use crate::problem::{
    check_name, non_negative, positive, Ctx, FieldError, Input, ProblemError, RawFile, Resolved,
};
use crate::synth::counterweight::Settings;
use crate::units::{Acceleration, Angle, AngularSpeed, Force, Inertia, Length, Mass, Qty};
use serde::Deserialize;
use std::path::Path;

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
    /// `[design.balancers] compare`: the scene also solved with none and with each leading
    /// subset of its balancer orders (the result's `balancer_comparison`).
    pub compare_balancers: bool,
    /// The mass items whose mass was read from a drawing (`outline`), in the file's order.
    pub drawn_masses: Vec<DrawnMass>,
}

/// The whole slider-crank file.
pub type File = RawFile<MechanismRaw, ModelRaw, DesignRaw, ObjectiveRaw, AccuracyRaw>;

/// Reads and resolves a slider-crank problem file (its text or its table). A drawing named
/// in a mass item's `outline` is read relative to the file's folder ([`Ctx::dir`]: a fleet
/// row's is its template's).
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Resolved<SliderCrankProblem>, ProblemError> {
    let dir = ctx.dir();
    File::resolve(ctx, input, |raw| resolve_raw(raw, dir))
}

/// Most points of `[mechanism.process_force_table]` (a measured cycle at 0.1° is 3600).
pub const MAX_TABLE_POINTS: usize = 10_000;

/// The value checks of a slider-crank file, section by section in the file's order: the
/// name, the mechanism and its loads ([`resolve_mechanism`], mass items' drawings read from
/// `dir`), the counterweight's variables, the objective and its limits, the accuracy, the
/// paper's design, the plate, the balancers, the load limits, the joint design's
/// requirements, the speed sweep and the work budget.
pub fn resolve_raw(raw: &File, dir: &Path) -> Result<SliderCrankProblem, FieldError> {
    check_name(&raw.name)?;
    let m = &raw.mechanism;
    let md = &raw.model;
    let (mech, omega, loads, items) = resolve_mechanism(m, md, dir)?;
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
        core.envelope = resolve_envelope(&named_masses(&items), e, &core)?;
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
        compare_balancers: d.balancers.as_ref().is_some_and(|b| b.compare),
        drawn_masses: items.into_iter().filter_map(|it| it.drawn).collect(),
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
    dir: &Path,
) -> Result<(SliderCrank, f64, Loads, Vec<MassItem>), FieldError> {
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
    let keys = LinkMassKeys {
        crank_mass: m.crank_mass,
        slider_mass: m.slider_mass,
        crank_centroid: m.crank_centroid,
        mass_items: &m.mass_items,
    };
    let (m2, m4, r2, items) = resolve_link_masses(&keys, r, dir)?;
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
    Ok((mech, omega, Loads { gravity, process }, items))
}

/// The rod of `[model]`: lumped (its mass m₃ split between the crank pin and the slider by
/// `rod_split`) or rigid (centroid and inertia), on a rod of length `l`.
fn resolve_rod(md: &ModelRaw, m3: f64, l: f64) -> Result<Rod, FieldError> {
    rod_of(
        RodKeys {
            masses: md.masses,
            rod_split: md.rod_split,
            rod_centroid: md.rod_centroid,
            rod_inertia: md.rod_inertia,
        },
        m3,
        l,
    )
}

/// The `[model]` keys of a rod (the slider-crank's and the multi-cylinder's files).
#[derive(Debug, Clone, Copy)]
pub struct RodKeys {
    /// `masses`.
    pub masses: Masses,
    /// `rod_split`.
    pub rod_split: Option<f64>,
    /// `rod_centroid`.
    pub rod_centroid: Option<Qty<Length>>,
    /// `rod_inertia`.
    pub rod_inertia: Option<Qty<Inertia>>,
}

/// The rod of mass m₃ and length `l` the keys `md` describe (see [`resolve_rod`]); errors
/// name `model.<key>`.
pub fn rod_of(md: RodKeys, m3: f64, l: f64) -> Result<Rod, FieldError> {
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
