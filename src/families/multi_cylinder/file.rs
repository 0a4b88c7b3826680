//! The multi-cylinder problem file — its raw sections and their resolution into a checked
//! [`MultiCylinderProblem`] (every field documented in `docs/problem-files.md`, family
//! `multi-cylinder`): the cylinders on one crankshaft (each the slider-crank family's
//! mechanism with its phase, bank angle and plane), the rotating unbalances to design
//! (crank-web counterweights and balance shafts), what they minimise and the limits.

use super::articulated::Articulated;
use super::firing::{candidate_layouts, Admissible, Cycle};
use super::model::{Cylinder, Layout, Rotor};
use crate::families::slider_crank::file::{rod_of, Masses, RodKeys};
use crate::families::slider_crank::model::{Crank, Kinematics, SliderCrank};
use crate::problem::limits::{self, c, Count};
use crate::problem::{
    check_name, non_negative, positive, Ctx, FieldError, Input, ProblemError, RawFile, Resolved,
};
use crate::synth::minimax::Settings;
use crate::units::{
    Angle, AngularSpeed, Damping, Force, Inertia, Length, Mass, Qty, Stiffness, Torque,
};
use serde::Deserialize;

/// The `family = "…"` value of this family's files.
pub const FAMILY: &str = "multi-cylinder";

/// The problem file `cwsynth new` prints: the shipped inline-3 with its balance shaft.
pub const TEMPLATE: &str = include_str!("../../../problems/inline-3-balance-shaft.toml");

/// Most cylinders on one shaft.
pub const MAX_CYLINDERS: usize = 24;

/// Most crank-web counterweights and balance shafts, each.
pub const MAX_ROTORS: usize = 24;

/// Most mounts.
pub const MAX_MOUNTS: usize = 16;

/// Most candidate layouts of a phase search (each a whole solve).
pub const MAX_CANDIDATES: usize = 4096;

/// The number of candidates: (2π/step)^(N−1).
pub fn phase_layouts(step: f64, cylinders: usize) -> f64 {
    (std::f64::consts::TAU / step)
        .round()
        .powi(cylinders as i32 - 1)
}

/// The integer keys of this family's file and their ranges (see [`limits`]).
pub const COUNTS: &[Count] = &[
    c("model.orders", 2, 32),
    c("objective.pareto_points", 0, 16),
    c("accuracy.initial_samples", 3, 1024),
    c("accuracy.scan_samples", 16, 20_000),
    c("accuracy.max_rounds", 1, 1000),
    c("accuracy.rms_samples", 16, 100_000),
];

/// The work budget of one scene (see [`limits::check_work`]): cylinder evaluations of the
/// scan grid and the front, so one machine runs in seconds.
pub const WORK_BUDGET: f64 = 5e7;

/// `[mechanism]`: what every cylinder shares, and the cylinders.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MechanismRaw {
    /// ω, the constant crank speed.
    pub speed: Qty<AngularSpeed>,
    /// R, every throw's radius.
    pub crank_radius: Qty<Length>,
    /// L, every rod's length.
    pub rod_length: Qty<Length>,
    /// m2, each throw's own mass (crank pin, webs' share) at `crank_centroid`.
    pub crank_mass: Qty<Mass>,
    /// r2, its centroid radius (default R: the mass at the crank pin).
    pub crank_centroid: Option<Qty<Length>>,
    /// m3, each rod's mass.
    pub rod_mass: Qty<Mass>,
    /// m4, each piston's mass (with its pin and rings).
    pub slider_mass: Qty<Mass>,
    /// e, each cylinder axis' offset from the shaft (default 0).
    pub offset: Option<Qty<Length>>,
    /// z₀, the point of the shaft the couples are taken about (default the middle of the
    /// cylinders' planes).
    pub couple_reference: Option<Qty<Length>>,
    /// The cylinders, at least one.
    #[schemars(length(min = 1, max = MAX_CYLINDERS))]
    pub cylinders: Vec<CylinderRaw>,
    /// The cylinders' cycle, for their firing: `two-stroke` (every cylinder fires once a turn;
    /// also a single-acting compressor) or `four-stroke` (once every two turns). Default none:
    /// no firing is reported.
    pub cycle: Option<Cycle>,
    /// The firing order, cylinder numbers from 1, cylinder 1 first (`[1, 3, 4, 2]`; needs
    /// `cycle`): the report says whether the layout fires evenly in it, and with
    /// `[design.phases] even_firing = true` the search admits only layouts that do.
    pub firing_order: Option<Vec<u32>>,
    /// The frame the cylinders shake (with `[[mechanism.mounts]]`; default: rigid ground).
    pub frame: Option<FrameRaw>,
    /// The frame's elastic mounts.
    #[serde(default)]
    #[schemars(length(max = MAX_MOUNTS))]
    pub mounts: Vec<MountRaw>,
}

/// `[mechanism.frame]`: a rigid body, its principal axes along the shaft frame's.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FrameRaw {
    /// M: the frame with everything fixed to it.
    pub mass: Qty<Mass>,
    /// Principal moments of inertia about its centre of mass, about x, y, z.
    pub inertia: [Qty<Inertia>; 3],
    /// G, its centre of mass (x, y, z in the shaft frame).
    pub centroid: [Qty<Length>; 3],
}

/// `[[mechanism.mounts]]`: a spring and a damper along each axis at a point of the frame.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MountRaw {
    /// Its point (x, y, z in the shaft frame).
    pub position: [Qty<Length>; 3],
    /// Stiffness along x, y, z.
    pub stiffness: [Qty<Stiffness>; 3],
    /// Viscous damping along x, y, z (default none).
    pub damping: Option<[Qty<Damping>; 3]>,
}

/// `[[mechanism.cylinders]]`: one throw and its cylinder.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CylinderRaw {
    /// αᵢ, the throw's angle at φ = 0.
    pub phase: Qty<Angle>,
    /// γᵢ, the direction of the cylinder axis (default 0: every cylinder along x, inline).
    pub bank: Option<Qty<Angle>>,
    /// zᵢ, the throw's plane along the shaft.
    pub position: Qty<Length>,
    /// This cylinder's piston mass (default `mechanism.slider_mass`).
    pub slider_mass: Option<Qty<Mass>>,
    /// This cylinder's rod mass (default `mechanism.rod_mass`).
    pub rod_mass: Option<Qty<Mass>>,
    /// This throw's own mass (default `mechanism.crank_mass`).
    pub crank_mass: Option<Qty<Mass>>,
    /// This cylinder's offset (default `mechanism.offset`).
    pub offset: Option<Qty<Length>>,
    /// On a radial's throw: this cylinder's rod is pinned to the master rod (the cylinder of
    /// the same `phase` and `position` without this table) at a knuckle pin.
    pub articulated: Option<ArticulatedRaw>,
}

/// `[mechanism.cylinders.articulated]`: an articulated rod and its knuckle pin.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ArticulatedRaw {
    /// r_k, from the crank pin to the knuckle pin on the master rod.
    pub knuckle_radius: Qty<Length>,
    /// δ, the knuckle pin's angle on the master rod from its axis (crank pin → piston pin),
    /// anticlockwise (default: this cylinder's bank minus the master's).
    pub knuckle_angle: Option<Qty<Angle>>,
    /// l, the articulated rod's length, knuckle pin to piston pin.
    pub rod_length: Qty<Length>,
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
    /// Orders of the harmonic tables (default 4).
    pub orders: Option<u32>,
}

/// The order of a balance shaft: its speed over the crank's.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Order {
    /// At the crank's speed (1×).
    Primary,
    /// At twice the crank's speed (2×, a Lanchester shaft).
    Secondary,
}

/// Which way a balance shaft turns.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Turning {
    /// As the crank does.
    With,
    /// Against the crank.
    Against,
}

/// `[[design.counterweights]]`: a crank-web counterweight, an unbalance turning with the
/// crank at its plane, designed in size and direction.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CounterweightRaw {
    /// Label (default `web counterweight k`).
    pub name: Option<String>,
    /// Its plane along the shaft.
    pub position: Qty<Length>,
    /// Its largest mass.
    pub mass_max: Qty<Mass>,
    /// Its largest centroid radius (and the body within it).
    pub radius_max: Qty<Length>,
}

/// `[[design.shafts]]`: a balance shaft's unbalance, designed in size and phase.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ShaftRaw {
    /// Label (default `balance shaft k`).
    pub name: Option<String>,
    /// `primary` (1×) or `secondary` (2×).
    pub order: Order,
    /// `with` or `against` the crank.
    pub turning: Turning,
    /// Its plane along the shaft.
    pub position: Qty<Length>,
    /// Its largest mass.
    pub mass_max: Qty<Mass>,
    /// Its largest centroid radius.
    pub radius_max: Qty<Length>,
}

/// `[design]`: the unbalances to design (none: the layout is analysed).
#[derive(Debug, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignRaw {
    /// Crank-web counterweights.
    #[serde(default)]
    #[schemars(length(max = MAX_ROTORS))]
    pub counterweights: Vec<CounterweightRaw>,
    /// Balance shafts.
    #[serde(default)]
    #[schemars(length(max = MAX_ROTORS))]
    pub shafts: Vec<ShaftRaw>,
    /// The crank phases chosen by exhaustive search.
    pub phases: Option<PhasesRaw>,
}

/// `[design.phases]`: every throw but the first at a multiple of `step`, each layout solved.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PhasesRaw {
    /// The admissible phases' spacing: a whole turn divided by an integer (`"90 deg"`).
    pub step: Qty<Angle>,
    /// Admit only the layouts that fire evenly in `mechanism.cycle` (in
    /// `mechanism.firing_order`, if given). Default false: every layout.
    #[serde(default)]
    pub even_firing: bool,
}

/// What the unbalances minimise.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Goal {
    /// max over φ of |F|.
    PeakForce,
    /// max over φ of |M| (the couple about the two axes normal to the shaft).
    PeakCouple,
    /// Σ m, the counterweights' and shafts' masses at their largest radii (with limits).
    CounterweightMass,
    /// max over φ and the mounts of the force a mount transmits normal to the shaft (needs
    /// `[mechanism.frame]` and `[[mechanism.mounts]]`).
    PeakMountForce,
}

/// `[objective]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectiveRaw {
    /// What the unbalances minimise (ignored without `[design]` entries).
    pub minimize: Goal,
    /// Limit on the peak shaking force.
    pub max_peak_force: Option<Qty<Force>>,
    /// Limit on the peak couple.
    pub max_peak_couple: Option<Qty<Torque>>,
    /// Limit on every mount's peak transmitted force normal to the shaft.
    pub max_mount_force: Option<Qty<Force>>,
    /// Points of the peak-force against peak-couple front (0: none).
    #[serde(default)]
    pub pareto_points: u32,
}

/// `[accuracy]`: the minimax engine's [`Settings`] read directly.
pub type AccuracyRaw = Settings;

/// The whole multi-cylinder file.
pub type File = RawFile<MechanismRaw, ModelRaw, DesignRaw, ObjectiveRaw, AccuracyRaw>;

/// A designed rotating unbalance: a crank-web counterweight or a balance shaft.
#[derive(Debug, Clone, PartialEq)]
pub struct RotorSpec {
    /// Label.
    pub name: String,
    /// How it turns and where.
    pub rotor: Rotor,
    /// m_max (kg).
    pub mass_max: f64,
    /// r_max (m).
    pub radius_max: f64,
    /// `true` for a balance shaft, `false` for a crank-web counterweight.
    pub shaft: bool,
}

/// A resolved multi-cylinder scene.
#[derive(Debug, Clone)]
pub struct MultiCylinderProblem {
    /// The cylinders and the couples' reference.
    pub layout: Layout,
    /// ω (rad/s).
    pub omega: f64,
    /// The unbalances to design: the counterweights, then the shafts.
    pub rotors: Vec<RotorSpec>,
    /// The goal.
    pub goal: Goal,
    /// Limits (N, N·m).
    pub max_peak_force: Option<f64>,
    /// See `max_peak_force`.
    pub max_peak_couple: Option<f64>,
    /// Every mount's peak transmitted force normal to the shaft (N).
    pub max_mount_force: Option<f64>,
    /// The frame on its mounts, if any (else rigid ground).
    pub frame: Option<super::mounts::Frame>,
    /// With `[design.phases]`: the admissible phases' spacing (rad).
    pub phase_step: Option<f64>,
    /// The cylinders' cycle, if given.
    pub cycle: Option<Cycle>,
    /// The firing order asked for (cylinder numbers from 1), if given.
    pub firing_order: Option<Vec<usize>>,
    /// With `even_firing`: what the phase search admits.
    pub admissible: Option<Admissible>,
    /// Front points.
    pub pareto_points: u32,
    /// Harmonic orders reported.
    pub orders: u32,
    /// The engine's settings.
    pub settings: Settings,
}

/// Reads and checks a multi-cylinder file.
pub fn resolve(ctx: &Ctx, input: Input) -> Result<Resolved<MultiCylinderProblem>, ProblemError> {
    File::resolve(ctx, input, resolve_raw)
}

/// The value checks of a multi-cylinder file.
pub fn resolve_raw(raw: &File) -> Result<MultiCylinderProblem, FieldError> {
    check_name(&raw.name)?;
    let m = &raw.mechanism;
    let omega = positive("mechanism.speed", m.speed.si())?;
    let layout = resolve_layout(m, &raw.model)?;
    let layout_len = layout.cylinders.len();
    let orders = raw.model.orders.unwrap_or(4);
    limits::check(COUNTS, "model.orders", orders.into())?;
    let rotors = resolve_rotors(&raw.design)?;
    let o = &raw.objective;
    limits::check(COUNTS, "objective.pareto_points", o.pareto_points.into())?;
    let max_peak_force = o
        .max_peak_force
        .map(|q| positive("objective.max_peak_force", q.si()))
        .transpose()?;
    let max_peak_couple = o
        .max_peak_couple
        .map(|q| positive("objective.max_peak_couple", q.si()))
        .transpose()?;
    let max_mount_force = o
        .max_mount_force
        .map(|q| positive("objective.max_mount_force", q.si()))
        .transpose()?;
    let frame = resolve_frame(m)?;
    let firing_order = resolve_firing_order(m, layout_len)?;
    check_goal(
        o,
        !rotors.is_empty(),
        max_peak_force.or(max_peak_couple).or(max_mount_force),
    )?;
    if frame.is_none() && (o.minimize == Goal::PeakMountForce || max_mount_force.is_some()) {
        let key = if max_mount_force.is_some() {
            "objective.max_mount_force"
        } else {
            "objective.minimize"
        };
        return Err(FieldError::new(
            key,
            "the mount force needs the frame and its mounts: [mechanism.frame] and [[mechanism.mounts]]",
        ));
    }
    let settings = raw.accuracy;
    limits::check_section(COUNTS, "accuracy", &settings)?;
    settings.validate().map_err(|(key, message)| {
        FieldError::new(format!("accuracy.{key}"), format!("{key} {message}"))
    })?;
    let work = layout.cylinders.len() as f64
        * settings.scan_samples as f64
        * (1.0 + o.pareto_points as f64)
        * (1.0 + rotors.len() as f64);
    limits::check_work(
        WORK_BUDGET,
        FAMILY,
        work,
        "cylinders × accuracy.scan_samples × (1 + objective.pareto_points) × (1 + rotors)",
        &[
            limits::term("accuracy.scan_samples", settings.scan_samples as f64, 360.0),
            limits::term("objective.pareto_points", o.pareto_points as f64, 0.0),
        ],
    )?;
    Ok(MultiCylinderProblem {
        layout: layout.clone(),
        omega,
        rotors,
        goal: o.minimize,
        max_peak_force,
        max_peak_couple,
        max_mount_force,
        frame,
        phase_step: resolve_phases(
            &raw.design,
            layout_len,
            layout.cylinders.iter().any(|c| c.articulated.is_some()),
        )?,
        cycle: m.cycle,
        admissible: resolve_admissible(m, &raw.design, &layout, &firing_order)?,
        firing_order,
        pareto_points: o.pareto_points,
        orders,
        settings,
    })
}

/// The goal's checks: a mass goal needs a limit; a front needs designed unbalances.
fn check_goal(o: &ObjectiveRaw, designed: bool, limit: Option<f64>) -> Result<(), FieldError> {
    if o.minimize == Goal::CounterweightMass && designed && limit.is_none() {
        return Err(FieldError::new(
            "objective.minimize",
            "\"counterweight-mass\" needs a limit (max_peak_force, max_peak_couple or max_mount_force): the lightest unbalance without one is none",
        ));
    }
    if o.pareto_points == 1 {
        return Err(FieldError::new(
            "objective.pareto_points",
            "1 is no front; allowed: 0 (none) or 2 to 16",
        ));
    }
    if o.pareto_points > 0 && !designed {
        return Err(FieldError::new(
            "objective.pareto_points",
            "a front needs unbalances to design ([[design.counterweights]] or [[design.shafts]])",
        ));
    }
    Ok(())
}

/// The cylinders: the shared slider-crank with each cylinder's own values.
fn resolve_layout(m: &MechanismRaw, md: &ModelRaw) -> Result<Layout, FieldError> {
    if m.cylinders.is_empty() || m.cylinders.len() > MAX_CYLINDERS {
        return Err(FieldError::new(
            "mechanism.cylinders",
            format!(
                "{} given; allowed: 1 to {MAX_CYLINDERS} [[mechanism.cylinders]]",
                m.cylinders.len()
            ),
        ));
    }
    let r = positive("mechanism.crank_radius", m.crank_radius.si())?;
    let l = positive("mechanism.rod_length", m.rod_length.si())?;
    let r2 = m
        .crank_centroid
        .map_or(Ok(r), |q| non_negative("mechanism.crank_centroid", q.si()))?;
    let kinematics = md.kinematics.unwrap_or(Kinematics::Exact);
    let keys = RodKeys {
        masses: md.masses,
        rod_split: md.rod_split,
        rod_centroid: md.rod_centroid,
        rod_inertia: md.rod_inertia,
    };
    let mut cylinders = Vec::with_capacity(m.cylinders.len());
    for (i, c) in m.cylinders.iter().enumerate() {
        let key = |k: &str| format!("mechanism.cylinders[{i}].{k}");
        let mass = |own: Option<Qty<Mass>>, shared: Qty<Mass>, k: &str| {
            let (q, f) = own.map_or((shared, format!("mechanism.{k}")), |q| (q, key(k)));
            non_negative(&f, q.si())
        };
        let e = c.offset.or(m.offset).map_or(0.0, |q| q.si());
        let e_key = if c.offset.is_some() {
            key("offset")
        } else {
            "mechanism.offset".into()
        };
        if e != 0.0 && kinematics != Kinematics::Exact {
            return Err(FieldError::new(
                e_key,
                "the two-harmonic series and the primary-only model are the in-line slider's; with an offset use model.kinematics = \"exact\"",
            ));
        }
        if (r + e.abs()) / l >= 1.0 {
            return Err(FieldError::new(
                e_key,
                format!("the crank cannot turn a full revolution: (R + |e|)/L = {:.6} ≥ 1; allowed: rod_length > crank_radius + |offset|", (r + e.abs()) / l),
            ));
        }
        let sc = SliderCrank {
            r,
            l,
            e,
            kinematics,
            crank: Crank {
                mass: mass(c.crank_mass, m.crank_mass, "crank_mass")?,
                centroid: r2,
            },
            rod: rod_of(keys, mass(c.rod_mass, m.rod_mass, "rod_mass")?, l)?,
            slider_mass: mass(c.slider_mass, m.slider_mass, "slider_mass")?,
        };
        cylinders.push(Cylinder {
            phase: c.phase.si(),
            bank: c.bank.map_or(0.0, |q| q.si()),
            z: c.position.si(),
            sc,
            articulated: None,
        });
    }
    articulate(m, md, keys, &mut cylinders)?;
    let (lo, hi) = cylinders
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
            (a.min(c.z), b.max(c.z))
        });
    let z0 = m.couple_reference.map_or(0.5 * (lo + hi), |q| q.si());
    Ok(Layout { cylinders, z0 })
}

/// The articulated rods: each cylinder with an `articulated` table gets its throw's master
/// (the one cylinder of the same phase and plane without one), its own rod of length l from
/// the knuckle pin and no throw mass; exact kinematics, no offsets, R + r_k < l.
fn articulate(
    m: &MechanismRaw,
    md: &ModelRaw,
    keys: RodKeys,
    cylinders: &mut [Cylinder],
) -> Result<(), FieldError> {
    for (i, c) in m.cylinders.iter().enumerate() {
        let Some(a) = &c.articulated else { continue };
        let key = |k: &str| format!("mechanism.cylinders[{i}].articulated.{k}");
        let here = format!("mechanism.cylinders[{i}].articulated");
        let masters: Vec<usize> = (0..m.cylinders.len())
            .filter(|&j| {
                m.cylinders[j].articulated.is_none()
                    && cylinders[j].z == cylinders[i].z
                    && cylinders[j].phase == cylinders[i].phase
            })
            .collect();
        let [master] = masters[..] else {
            return Err(FieldError::new(
                here,
                format!("{} cylinders could be this rod's master; allowed: exactly one cylinder of the same phase and position without an `articulated` table", masters.len()),
            ));
        };
        if md.kinematics.is_some_and(|k| k != Kinematics::Exact) {
            return Err(FieldError::new(
                "model.kinematics",
                "articulated rods need model.kinematics = \"exact\" (the two-harmonic series is the slider-crank's)",
            ));
        }
        if cylinders[i].sc.e != 0.0 || cylinders[master].sc.e != 0.0 {
            return Err(FieldError::new(
                here,
                "an articulated rod and its master need cylinder axes through the shaft (offset 0)",
            ));
        }
        if c.crank_mass.is_some() {
            return Err(FieldError::new(
                format!("mechanism.cylinders[{i}].crank_mass"),
                "an articulated cylinder has no throw of its own: its master's crank_mass is the throw's",
            ));
        }
        let r = cylinders[i].sc.r;
        let rk = non_negative(&key("knuckle_radius"), a.knuckle_radius.si())?;
        let l = positive(&key("rod_length"), a.rod_length.si())?;
        if r + rk >= l {
            return Err(FieldError::new(
                key("rod_length"),
                format!("the articulated rod cannot reach its cylinder axis over a whole turn: crank_radius + knuckle_radius = {:.6} m ≥ rod_length = {l:.6} m", r + rk),
            ));
        }
        let (bank, master_bank) = (cylinders[i].bank, cylinders[master].bank);
        let sc = &mut cylinders[i].sc;
        sc.rod = rod_of(keys, sc.rod.mass, l)?;
        sc.l = l;
        sc.crank.mass = 0.0;
        cylinders[i].articulated = Some(Articulated {
            master_bank,
            master_rod: cylinders[master].sc.l,
            knuckle_radius: rk,
            knuckle_angle: a.knuckle_angle.map_or(bank - master_bank, |q| q.si()),
        });
    }
    Ok(())
}

/// The crank-web counterweights, then the balance shafts.
fn resolve_rotors(d: &DesignRaw) -> Result<Vec<RotorSpec>, FieldError> {
    for (n, k) in [
        (d.counterweights.len(), "design.counterweights"),
        (d.shafts.len(), "design.shafts"),
    ] {
        if n > MAX_ROTORS {
            return Err(FieldError::new(
                k,
                format!("{n} given; allowed: at most {MAX_ROTORS}"),
            ));
        }
    }
    let limits_of = |key: String, mass: Qty<Mass>, radius: Qty<Length>| {
        Ok::<_, FieldError>((
            positive(&format!("{key}.mass_max"), mass.si())?,
            positive(&format!("{key}.radius_max"), radius.si())?,
        ))
    };
    let mut out = Vec::new();
    for (j, c) in d.counterweights.iter().enumerate() {
        let (mass_max, radius_max) = limits_of(
            format!("design.counterweights[{j}]"),
            c.mass_max,
            c.radius_max,
        )?;
        out.push(RotorSpec {
            name: (c.name.clone()).unwrap_or_else(|| format!("web counterweight {}", j + 1)),
            rotor: Rotor::crank(c.position.si()),
            mass_max,
            radius_max,
            shaft: false,
        });
    }
    for (k, s) in d.shafts.iter().enumerate() {
        let (mass_max, radius_max) =
            limits_of(format!("design.shafts[{k}]"), s.mass_max, s.radius_max)?;
        out.push(RotorSpec {
            name: (s.name.clone()).unwrap_or_else(|| format!("balance shaft {}", k + 1)),
            rotor: Rotor {
                order: match s.order {
                    Order::Primary => 1,
                    Order::Secondary => 2,
                },
                sense: match s.turning {
                    Turning::With => 1.0,
                    Turning::Against => -1.0,
                },
                z: s.position.si(),
            },
            mass_max,
            radius_max,
            shaft: true,
        });
    }
    Ok(out)
}

/// The frame and its mounts: both or neither; a positive mass and inertias; stiffnesses and
/// dampings ≥ 0.
fn resolve_frame(m: &MechanismRaw) -> Result<Option<super::mounts::Frame>, FieldError> {
    use super::mounts::{Frame, Mount};
    let Some(f) = &m.frame else {
        if m.mounts.is_empty() {
            return Ok(None);
        }
        return Err(FieldError::new(
            "mechanism.mounts",
            "mounts need the frame they hold: [mechanism.frame] (mass, inertia, centroid)",
        ));
    };
    if m.mounts.is_empty() || m.mounts.len() > MAX_MOUNTS {
        return Err(FieldError::new(
            "mechanism.mounts",
            format!(
                "{} given; allowed: 1 to {MAX_MOUNTS} [[mechanism.mounts]] under the frame",
                m.mounts.len()
            ),
        ));
    }
    let mass = positive("mechanism.frame.mass", f.mass.si())?;
    let mut inertia = [0.0; 3];
    for (k, q) in f.inertia.iter().enumerate() {
        inertia[k] = positive(&format!("mechanism.frame.inertia[{k}]"), q.si())?;
    }
    let mut mounts = Vec::with_capacity(m.mounts.len());
    for (i, mt) in m.mounts.iter().enumerate() {
        let key = |k: &str, j: usize| format!("mechanism.mounts[{i}].{k}[{j}]");
        let mut stiffness = [0.0; 3];
        let mut damping = [0.0; 3];
        for j in 0..3 {
            stiffness[j] = non_negative(&key("stiffness", j), mt.stiffness[j].si())?;
            if let Some(d) = &mt.damping {
                damping[j] = non_negative(&key("damping", j), d[j].si())?;
            }
        }
        mounts.push(Mount {
            at: mt.position.map(|q| q.si()),
            stiffness,
            damping,
        });
    }
    Ok(Some(Frame {
        mass,
        inertia,
        centroid: f.centroid.map(|q| q.si()),
        mounts,
    }))
}

/// `[design.phases]`: a step that divides the turn, on two cylinders or more, within
/// [`MAX_CANDIDATES`] layouts.
fn resolve_phases(
    d: &DesignRaw,
    cylinders: usize,
    articulated: bool,
) -> Result<Option<f64>, FieldError> {
    let Some(ph) = &d.phases else { return Ok(None) };
    let step = positive("design.phases.step", ph.step.si())?;
    let m = std::f64::consts::TAU / step;
    if (m - m.round()).abs() > 1e-9 * m || m.round() < 2.0 {
        return Err(FieldError::new(
            "design.phases.step",
            format!("{:.6} deg does not divide the turn; allowed: 360°/k for an integer k ≥ 2 (\"90 deg\", \"60 deg\")", step.to_degrees()),
        ));
    }
    if cylinders < 2 {
        return Err(FieldError::new(
            "design.phases",
            "one cylinder has no phase to choose (the first throw is held)",
        ));
    }
    if articulated {
        return Err(FieldError::new(
            "design.phases",
            "a radial's articulated cylinders share their master's throw: its phase is not theirs to choose",
        ));
    }
    let n = phase_layouts(step, cylinders);
    if n > MAX_CANDIDATES as f64 {
        return Err(FieldError::new(
            "design.phases.step",
            format!(
                "{n:.0} layouts ((360°/step)^(cylinders − 1)); allowed: at most {}: a larger step",
                MAX_CANDIDATES
            ),
        ));
    }
    Ok(Some(step))
}

/// `mechanism.firing_order`: with a cycle, every cylinder once, cylinder 1 first.
fn resolve_firing_order(
    m: &MechanismRaw,
    cylinders: usize,
) -> Result<Option<Vec<usize>>, FieldError> {
    let Some(order) = &m.firing_order else {
        return Ok(None);
    };
    let key = "mechanism.firing_order";
    if m.cycle.is_none() {
        return Err(FieldError::new(
            key,
            "a firing order needs the cycle: mechanism.cycle = \"two-stroke\" or \"four-stroke\"",
        ));
    }
    let mut sorted: Vec<u32> = order.clone();
    sorted.sort_unstable();
    if order.first() != Some(&1) || sorted != (1..=cylinders as u32).collect::<Vec<_>>() {
        return Err(FieldError::new(
            key,
            format!("{order:?} is no firing order of {cylinders} cylinders; allowed: each of 1 to {cylinders} once, 1 first ([1, 3, 4, 2])"),
        ));
    }
    Ok(Some(order.iter().map(|&c| c as usize).collect()))
}

/// `[design.phases] even_firing`: with a cycle, and at least one admitted layout.
fn resolve_admissible(
    m: &MechanismRaw,
    d: &DesignRaw,
    layout: &Layout,
    order: &Option<Vec<usize>>,
) -> Result<Option<Admissible>, FieldError> {
    let Some(ph) = d.phases.as_ref().filter(|ph| ph.even_firing) else {
        return Ok(None);
    };
    let key = "design.phases.even_firing";
    let Some(cycle) = m.cycle else {
        return Err(FieldError::new(
            key,
            "even firing needs the cycle: mechanism.cycle = \"two-stroke\" or \"four-stroke\"",
        ));
    };
    let a = Admissible {
        cycle,
        order: order.clone(),
    };
    if candidate_layouts(layout, ph.step.si(), Some(&a)).is_empty() {
        let how = order.as_ref().map_or(String::new(), |o| {
            format!(" in the order {}", super::firing::order_text(o))
        });
        return Err(FieldError::new(
            key,
            format!(
                "no layout with every throw at a multiple of {:.4}° fires evenly{how} in a {} cycle: a smaller step, another order or another cycle",
                ph.step.si().to_degrees(),
                cycle.as_str()
            ),
        ));
    }
    Ok(Some(a))
}
