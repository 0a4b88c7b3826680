//! `[mechanism.envelope]` of a slider-crank file: the operating envelope (issue 33, item 3) —
//! a speed band, mass intervals and length tolerances — read, checked and resolved into the
//! scene's [`Envelope`]. Apart from `file.rs` so that each file stays readable.

use super::synth::{
    fixed_length, Envelope, LengthOf, LengthRange, MassOf, MassRange, Objective, Scene,
    MAX_PARAMETERS,
};
use crate::problem::envelope::{check_parameters, mass_interval, monte_carlo, speed_band};
pub use crate::problem::envelope::{LengthRangeRaw, MassRangeRaw, SpeedRangeRaw, MAX_MONTE_CARLO};
use crate::problem::{positive, FieldError};
use serde::Deserialize;

/// `[mechanism.envelope]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EnvelopeRaw {
    /// The speed band: every figure over it (the inertial parts scale with ω², the weights do
    /// not).
    pub speed: Option<SpeedRangeRaw>,
    /// Mass intervals.
    #[serde(default)]
    #[schemars(length(max = MAX_PARAMETERS))]
    pub mass: Vec<MassRangeRaw>,
    /// Length tolerances (the worst case over them is sampled, not proven: `best_found`).
    #[serde(default)]
    #[schemars(length(max = MAX_PARAMETERS))]
    pub length: Vec<LengthRangeRaw>,
    /// Samples of the Monte Carlo check over the whole box (default 1000; 0: none; at most
    /// 1,000,000).
    pub monte_carlo: Option<usize>,
    /// The sensitivity table: the optimised worst case's derivative with respect to every
    /// interval end, from the optimum's multipliers (free once solved; default false).
    #[serde(default)]
    pub sensitivities: bool,
}

/// A `[[mechanism.mass_items]]` entry as the envelope sees it: its name, where it is reduced
/// to, its nominal mass (kg) and the fraction reduced there.
pub struct NamedMass<'a> {
    /// The item's name.
    pub name: &'a str,
    /// [`MassOf::Slider`] or [`MassOf::CrankPin`].
    pub of: MassOf,
    /// Its mass (kg).
    pub mass: f64,
    /// The fraction reduced there.
    pub fraction: f64,
}

/// The envelope of `[mechanism.envelope]` for the resolved scene `core` (its nominal values)
/// and the file's mass items.
pub fn resolve_envelope(
    items: &[NamedMass],
    e: &EnvelopeRaw,
    core: &Scene,
) -> Result<Envelope, FieldError> {
    let speed = speed_band(e.speed.as_ref())?;
    let masses = e
        .mass
        .iter()
        .enumerate()
        .map(|(i, r)| mass_range(items, r, core, &format!("mechanism.envelope.mass[{i}]")))
        .collect::<Result<Vec<_>, _>>()?;
    let lengths = e
        .length
        .iter()
        .enumerate()
        .map(|(i, r)| length_range(r, core, &format!("mechanism.envelope.length[{i}]")))
        .collect::<Result<Vec<_>, _>>()?;
    let monte_carlo = monte_carlo(e.monte_carlo)?;
    let env = Envelope {
        speed,
        masses,
        lengths,
        monte_carlo,
        sensitivities: e.sensitivities,
    };
    check_parameters(env.names().len(), MAX_PARAMETERS)?;
    Ok(env)
}

/// One mass interval: what it changes, its nominal, and Δm at its ends.
fn mass_range(
    items: &[NamedMass],
    r: &MassRangeRaw,
    core: &Scene,
    f: &str,
) -> Result<MassRange, FieldError> {
    let mech = &core.mech;
    let item = items.iter().find(|it| it.name == r.of);
    let (of, nominal, fraction) = match (r.of.as_str(), item) {
        (_, Some(it)) => (it.of, it.mass, it.fraction),
        ("slider_mass", None) if items.is_empty() => (MassOf::Slider, mech.slider_mass, 1.0),
        ("crank_mass", None) if items.is_empty() => (MassOf::Crank, mech.crank.mass, 1.0),
        ("rod_mass", None) => (MassOf::Rod, mech.rod.mass, 1.0),
        _ => {
            let names: Vec<String> = items.iter().map(|i| format!("\"{}\"", i.name)).collect();
            let keys = if items.is_empty() {
                "\"slider_mass\", \"crank_mass\", \"rod_mass\"".to_string()
            } else {
                format!("\"rod_mass\", {}", names.join(", "))
            };
            return Err(FieldError::new(
                format!("{f}.of"),
                format!("got \"{}\"; allowed: {keys}", r.of),
            ));
        }
    };
    let (lo, hi) = mass_interval(r.min, r.max, r.tolerance, nominal, f)?;
    if of == MassOf::Rod && mech.rod.mass <= 0.0 {
        return Err(FieldError::new(
            format!("{f}.of"),
            "the rod has no mass to vary",
        ));
    }
    Ok(MassRange {
        name: r.of.clone(),
        of,
        delta: ((lo - nominal) * fraction, (hi - nominal) * fraction),
    })
}

/// One length tolerance: ±t on R or L, each end checked to assemble (R + |e| < L).
fn length_range(r: &LengthRangeRaw, core: &Scene, f: &str) -> Result<LengthRange, FieldError> {
    let mech = &core.mech;
    let of = match r.of.as_str() {
        "crank_radius" => LengthOf::CrankRadius,
        "rod_length" => LengthOf::RodLength,
        other => {
            return Err(FieldError::new(
                format!("{f}.of"),
                format!("got \"{other}\"; allowed: \"crank_radius\", \"rod_length\""),
            ))
        }
    };
    let t = positive(&format!("{f}.tolerance"), r.tolerance.si())?;
    let (rr, l) = match of {
        LengthOf::CrankRadius => (mech.r + t, mech.l),
        LengthOf::RodLength => (mech.r, mech.l - t),
    };
    if t >= 0.5 * mech.r || rr + mech.e.abs() >= l {
        return Err(FieldError::new(
            format!("{f}.tolerance"),
            format!("{t} m: at the tolerance's end the crank cannot turn (or R changes by half); allowed: R + |e| < L over the whole band"),
        ));
    }
    Ok(LengthRange {
        name: r.of.clone(),
        of,
        delta: (-t, t),
    })
}

/// What an operating envelope cannot be combined with (yet), each refused with the key to
/// change: the objectives that are not a peak (RMS, mass, radius), a given counterweight, the
/// Pareto front and the speed sweep.
pub fn check_envelope(core: &Scene, sweep: bool) -> Result<(), FieldError> {
    if matches!(
        core.objective,
        Objective::MinRmsForce | Objective::MinMass | Objective::MinRadius
    ) {
        return Err(FieldError::new(
            "objective.minimize",
            "with [mechanism.envelope] the objective is a worst case over it; allowed: \"peak-force\", \"peak-torque\", \"peak-moment\", \"energy-fluctuation\"",
        ));
    }
    let refuse = |key: &str, what: &str| {
        Err(FieldError::new(
            key,
            format!("{what} is not available with [mechanism.envelope] yet"),
        ))
    };
    if core.pareto_points > 0 {
        return refuse("objective.pareto_points", "the Pareto front");
    }
    if sweep {
        return refuse(
            "objective.speed_sweep",
            "the speed sweep (the envelope's speed band covers it)",
        );
    }
    if fixed_length(&core.counterweight) && !core.given() {
        return refuse(
            "design.unbalance",
            "a fixed |U| with a free angle (not convex)",
        );
    }
    Ok(())
}
