//! `[mechanism.envelope]` of a linkage file (issue 33, item 3): a speed band and link-mass
//! intervals, read, checked and resolved into the scene's [`LinkageEnvelope`]. Apart from
//! `file.rs` so that each file stays readable; the speed band, the mass interval and the
//! Monte Carlo count are read as every family reads them (`crate::problem::envelope`).

use super::envelope::{LinkMassRange, LinkageEnvelope};
use super::model::Linkage;
use crate::problem::envelope::{
    check_parameters, mass_interval, monte_carlo, speed_band, MassRangeRaw, SpeedRangeRaw,
};
use crate::problem::FieldError;
use crate::synth::envelope::MAX_PARAMETERS;
use serde::Deserialize;

/// `[mechanism.envelope]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LinkageEnvelopeRaw {
    /// The speed band: every figure over it (the inertial parts scale with ω², the weights
    /// and process loads do not).
    pub speed: Option<SpeedRangeRaw>,
    /// Link-mass intervals.
    #[serde(default)]
    #[schemars(length(max = MAX_PARAMETERS))]
    pub mass: Vec<MassRangeRaw>,
    /// Samples of the Monte Carlo check over the whole box (default 1000; 0: none; at most
    /// 1,000,000).
    pub monte_carlo: Option<usize>,
    /// The sensitivity table (default false): what each interval end costs, dV*/d(end) of the
    /// optimised worst case, from the optimum's multipliers (free once solved).
    #[serde(default)]
    pub sensitivities: bool,
}

/// The envelope of `[mechanism.envelope]` for the linkage `l` with links `names`.
pub fn resolve_envelope(
    e: &LinkageEnvelopeRaw,
    l: &Linkage,
    names: &[String],
) -> Result<LinkageEnvelope, FieldError> {
    let speed = speed_band(e.speed.as_ref())?;
    let mut masses: Vec<LinkMassRange> = Vec::new();
    for (i, r) in e.mass.iter().enumerate() {
        let f = format!("mechanism.envelope.mass[{i}]");
        let Some(link) = names.iter().position(|n| *n == r.of) else {
            let all: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
            return Err(FieldError::new(
                format!("{f}.of"),
                format!("got \"{}\"; allowed: a link, {}", r.of, all.join(", ")),
            ));
        };
        if masses.iter().any(|m| m.link == link) {
            return Err(FieldError::new(
                format!("{f}.of"),
                format!("link \"{}\" has an interval already", r.of),
            ));
        }
        let nominal = l.inertia()[link].mass;
        if nominal <= 0.0 {
            return Err(FieldError::new(
                format!("{f}.of"),
                format!("link \"{}\" has no mass to scale (its centroid and inertia scale with the mass)", r.of),
            ));
        }
        let mass = mass_interval(r.min, r.max, r.tolerance, nominal, &f)?;
        if mass.0 <= 0.0 {
            return Err(FieldError::new(
                format!("{f}.min"),
                "allowed: a positive mass (the link's inertia scales with it)",
            ));
        }
        masses.push(LinkMassRange {
            name: r.of.clone(),
            link,
            mass,
        });
    }
    let env = LinkageEnvelope {
        speed,
        masses,
        monte_carlo: monte_carlo(e.monte_carlo)?,
        sensitivities: e.sensitivities,
    };
    check_parameters(env.names().len(), MAX_PARAMETERS)?;
    Ok(env)
}

/// What an operating envelope cannot be combined with (yet), each refused with the key to
/// change: an RMS objective (the worst case is of peaks and ΔE), the Pareto front and full
/// force balance (its equalities hold at one mass distribution, not over an interval).
/// `rms`: the objective is an RMS.
pub fn check_envelope(
    rms: bool,
    pareto_points: usize,
    full_force_balance: bool,
) -> Result<(), FieldError> {
    if rms {
        return Err(FieldError::new(
            "objective.minimize",
            "with [mechanism.envelope] the objective is a worst case over it; allowed: \"peak-force\", \"peak-moment\", \"peak-torque\", \"energy-fluctuation\", \"counterweight-mass\"",
        ));
    }
    let refuse = |key: &str, what: &str| {
        Err(FieldError::new(
            key,
            format!("{what} is not available with [mechanism.envelope] yet"),
        ))
    };
    if pareto_points > 0 {
        return refuse("objective.pareto_points", "the Pareto front");
    }
    if full_force_balance {
        return refuse(
            "objective.full_force_balance",
            "full force balance (its equalities hold at one mass distribution)",
        );
    }
    Ok(())
}
