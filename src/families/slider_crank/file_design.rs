//! The `[design]` and `[objective]` sections of a slider-crank file resolved against its
//! mechanism: the counterweight's variables, the objective and its limits, the paper's
//! design, the plate, the balancers, the speed sweep, and what a joint design or the flywheel
//! objective cannot be combined with (keys in `docs/problem-files.md`), with their raw
//! sections. Split from `file.rs`, which keeps the other sections and the order the checks
//! run in, and re-exports these.

use super::file_textbook::{fraction_rule, ReferenceRaw, MAX_EVALUATE_AT};
use crate::families::slider_crank::model::SliderCrank;
use crate::families::slider_crank::synth::{self as sc, Objective, Prefer, SpeedSweep};
use crate::problem::limits::{self, c, Count};
use crate::problem::{non_negative, positive, FieldError, RawVar};
use crate::synth::shape::{ShapeGoal, ShapeSpec};
use crate::synth::Var;
use crate::units::{Angle, AngularSpeed, Density, Force, Length, Mass, Qty, Torque, Unbalance};
use serde::Deserialize;
use std::f64::consts::{PI, TAU};

/// Smallest counterweight radius (`design.radius`, fixed or a range's lower end above 0) as a
/// fraction of the crank radius: below it the mass |U|/r is out of all proportion to the
/// machine (and at 1e-308 mm it overflowed to inf).
pub const MIN_RADIUS_OF_CRANK: f64 = 1e-6;

/// The integer keys of this family's file and their ranges (see [`limits`]).
pub const COUNTS: &[Count] = &[
    c("objective.pareto_points", 0, 200),
    c("objective.speed_sweep.points", 2, 200),
    c("accuracy.initial_samples", 3, 1024),
    c("accuracy.scan_samples", 16, 20_000),
    c("accuracy.max_rounds", 1, 1000),
    c("accuracy.rms_samples", 16, 100_000),
];

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
    /// The centroid radius of the eccentric mass on each shaft (one per order; default
    /// none): with it the result states each shaft's mass, |B_n|/(2r).
    #[schemars(length(max = 4))]
    pub radius: Option<Vec<Qty<Length>>>,
    /// Also solve the scene with no pair, with the first order only, the first two, … up to
    /// all of `orders` (the same objective and limits), and compare them (the result's
    /// `balancer_comparison`).
    #[serde(default)]
    pub compare: bool,
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

/// The counterweight's variables of `[design]`: the unbalance |U|, the angle β (fixed, a
/// range at most 180° wide, or the full circle), and the mass and radius when given (the
/// radius not below [`MIN_RADIUS_OF_CRANK`] × R, a fixed m·r inside the unbalance bounds).
pub(super) fn resolve_counterweight(
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
pub(super) fn check_flywheel_objective(
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
pub(super) fn resolve_objective(
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
pub(super) fn resolve_paper(
    d: &DesignRaw,
    radius: Option<Var>,
) -> Result<Option<PaperDesign>, FieldError> {
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
pub(super) fn resolve_shape(
    d: &DesignRaw,
    unbalance: Var,
) -> Result<Option<ShapeSpec>, FieldError> {
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
pub(super) fn resolve_speed_sweep(o: &ObjectiveRaw) -> Result<Option<SpeedSweep>, FieldError> {
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
pub(super) fn resolve_balancers(b: &BalancersRaw) -> Result<Vec<sc::BalancerSpec>, FieldError> {
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
    per_order(b.radius.as_ref().map(Vec::len), "radius")?;
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
            let mass_radius = b
                .radius
                .as_ref()
                .map(|v| positive(&format!("{f}.radius[{i}]"), v[i].si()))
                .transpose()?;
            Ok(sc::BalancerSpec {
                pair: crate::families::slider_crank::model::BalancerPair { order, offset },
                max_unbalance,
                unbalance: [0.0; 2],
                mass_radius,
            })
        })
        .collect()
}

/// What a joint design (balancers, a moment objective or limit, a main-bearing limit) cannot
/// be combined with, each refused with the key to change.
pub(super) fn check_joint(core: &sc::Scene, sweep: bool, gravity: bool) -> Result<(), FieldError> {
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
    if core.pareto_points > 0 && core.objective == Objective::MinPeakMoment {
        return Err(FieldError::new(
            "objective.pareto_points",
            "the torque–force Pareto front is not available with minimize = \"peak-moment\" (it trades the torque or ΔE against the force); allowed: \"peak-force\", \"peak-torque\", \"energy-fluctuation\"",
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
