//! `[mechanism.envelope]` of a linkage file (issue 33, item 3): a speed band and link-mass
//! intervals, read, checked and resolved into the scene's [`LinkageEnvelope`]. Apart from
//! `file.rs` so that each file stays readable; the speed band, the mass interval and the
//! Monte Carlo count are read as every family reads them (`crate::problem::envelope`).

use super::envelope::{LinkLengthRange, LinkMassRange, LinkageEnvelope};
use super::model::tip_of;
use super::model::Linkage;
use crate::problem::envelope::{
    check_parameters, mass_interval, monte_carlo, speed_band, LengthRangeRaw, MassRangeRaw,
    SpeedRangeRaw,
};
use crate::problem::{positive, FieldError};
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
    /// Link-length tolerances: `of` a link with a tip (the crank, an RRR link, an RRP rod),
    /// ± `tolerance` (the worst case over them is sampled, not proven: `best_found`).
    #[serde(default)]
    #[schemars(length(max = MAX_PARAMETERS))]
    pub length: Vec<LengthRangeRaw>,
    /// Samples of the Monte Carlo check over the whole box (default 1000; 0: none; at most
    /// 1,000,000).
    pub monte_carlo: Option<usize>,
    /// The sensitivity table (default false): what each interval end costs, dV*/d(end) of the
    /// optimised worst case, from the optimum's multipliers (free once solved).
    #[serde(default)]
    pub sensitivities: bool,
}

/// The envelope of `[mechanism.envelope]` for the linkage `l` with links `names`, its crank
/// `crank_length` long, `bars[i]` true where link i is a uniform bar.
pub fn resolve_envelope(
    e: &LinkageEnvelopeRaw,
    l: &Linkage,
    names: &[String],
    crank_length: f64,
    bars: &[bool],
) -> Result<LinkageEnvelope, FieldError> {
    let speed = speed_band(e.speed.as_ref())?;
    let mut masses: Vec<LinkMassRange> = Vec::new();
    for (i, r) in e.mass.iter().enumerate() {
        let f = format!("mechanism.envelope.mass[{i}]");
        let link = link_named(names, &r.of, &format!("{f}.of"))?;
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
    let mut lengths: Vec<LinkLengthRange> = Vec::new();
    for (i, r) in e.length.iter().enumerate() {
        let f = format!("mechanism.envelope.length[{i}]");
        let link = link_named(names, &r.of, &format!("{f}.of"))?;
        let Some(tip) = tip_of(l.dyads(), crank_length, link) else {
            return Err(FieldError::new(
                format!("{f}.of"),
                format!(
                    "link \"{}\" has no length (only the crank, RRR links and RRP rods have one)",
                    r.of
                ),
            ));
        };
        if lengths.iter().any(|m| m.link == link) {
            return Err(FieldError::new(
                format!("{f}.of"),
                format!("link \"{}\" has a tolerance already", r.of),
            ));
        }
        let t = positive(&format!("{f}.tolerance"), r.tolerance.si())?;
        if t >= tip.x {
            return Err(FieldError::new(
                format!("{f}.tolerance"),
                format!(
                    "got ±{t} m on a length of {} m; allowed: less than the length",
                    tip.x
                ),
            ));
        }
        lengths.push(LinkLengthRange {
            name: r.of.clone(),
            link,
            nominal: tip.x,
            delta: (-t, t),
            bar: bars.get(link).copied().unwrap_or(false),
        });
    }
    let env = LinkageEnvelope {
        speed,
        masses,
        lengths,
        monte_carlo: monte_carlo(e.monte_carlo)?,
        sensitivities: e.sensitivities,
        cases: Vec::new(),
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

/// The index of the link named `of` (the error at `key` lists the links).
/// The index of the link named `of`, or the error at `key` listing the links.
pub(super) fn link_named(names: &[String], of: &str, key: &str) -> Result<usize, FieldError> {
    names.iter().position(|n| n == of).ok_or_else(|| {
        let all: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
        FieldError::new(
            key,
            format!("got \"{of}\"; allowed: a link, {}", all.join(", ")),
        )
    })
}
