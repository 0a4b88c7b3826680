//! The parts of `[mechanism.envelope]` every family with an operating envelope reads alike
//! (issue 33, item 3): the speed band, a mass interval given as `min`/`max` or as a relative
//! `tolerance`, a length tolerance, and the Monte Carlo sample count; and the names of
//! `[[mechanism.load_cases]]`. What a mass interval may name is the family's.

use crate::problem::{positive, FieldError};
use crate::units::{AngularSpeed, Length, Mass, Qty};
use serde::Deserialize;

/// `speed = { min, max }`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpeedRangeRaw {
    /// Lowest speed.
    pub min: Qty<AngularSpeed>,
    /// Highest speed.
    pub max: Qty<AngularSpeed>,
}

/// `[[mechanism.envelope.mass]]`: a mass as `min`/`max` or a relative `tolerance`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MassRangeRaw {
    /// What it changes: the slider-crank's `"slider_mass"`, `"crank_mass"`, `"rod_mass"` or a
    /// mass item's name; a linkage's link (its centroid stays, its inertia scales with it).
    pub of: String,
    /// The least mass.
    pub min: Option<Qty<Mass>>,
    /// The largest mass.
    pub max: Option<Qty<Mass>>,
    /// ± this fraction of the nominal (dimensionless, e.g. 0.02 for a ±2 % casting).
    pub tolerance: Option<f64>,
}

/// `[[mechanism.envelope.length]]`: a length tolerance, ± `tolerance`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LengthRangeRaw {
    /// What length: the slider-crank's `"crank_radius"` or `"rod_length"`; a linkage's link
    /// (the crank, an RRR link or an RRP rod: its length to its tip).
    pub of: String,
    /// ± this length.
    pub tolerance: Qty<Length>,
}

/// At most `max` interval parameters: `k` of them is an error of `mechanism.envelope`.
pub fn check_parameters(k: usize, max: usize) -> Result<(), FieldError> {
    if k > max {
        return Err(FieldError::new(
            "mechanism.envelope",
            format!("{k} interval parameters; allowed: at most {max} (2^{max} vertices)"),
        ));
    }
    Ok(())
}

/// Most Monte Carlo samples.
pub const MAX_MONTE_CARLO: usize = 1_000_000;

/// The speed band (rad/s) of `mechanism.envelope.speed`: both ends positive, max ≥ min.
pub fn speed_band(s: Option<&SpeedRangeRaw>) -> Result<Option<(f64, f64)>, FieldError> {
    let Some(s) = s else { return Ok(None) };
    let lo = positive("mechanism.envelope.speed.min", s.min.si())?;
    let hi = positive("mechanism.envelope.speed.max", s.max.si())?;
    if hi < lo {
        return Err(FieldError::new(
            "mechanism.envelope.speed.max",
            "allowed: max ≥ min",
        ));
    }
    Ok(Some((lo, hi)))
}

/// `mechanism.envelope.monte_carlo`: default 1000, at most [`MAX_MONTE_CARLO`].
pub fn monte_carlo(n: Option<usize>) -> Result<usize, FieldError> {
    let n = n.unwrap_or(1000);
    if n > MAX_MONTE_CARLO {
        return Err(FieldError::new(
            "mechanism.envelope.monte_carlo",
            format!("got {n}; allowed: 0 to {MAX_MONTE_CARLO}"),
        ));
    }
    Ok(n)
}

/// A mass interval's ends (kg) at field `f`: `min` and `max`, or ± `tolerance` × `nominal`
/// (0 ≤ tolerance < 1); 0 ≤ min ≤ max.
pub fn mass_interval(
    min: Option<Qty<Mass>>,
    max: Option<Qty<Mass>>,
    tolerance: Option<f64>,
    nominal: f64,
    f: &str,
) -> Result<(f64, f64), FieldError> {
    let (lo, hi) = match (min, max, tolerance) {
        (Some(lo), Some(hi), None) => (lo.si(), hi.si()),
        (None, None, Some(t)) if (0.0..1.0).contains(&t) => {
            (nominal * (1.0 - t), nominal * (1.0 + t))
        }
        (None, None, Some(t)) => {
            return Err(FieldError::new(
                format!("{f}.tolerance"),
                format!("got {t}; allowed: 0 ≤ tolerance < 1 (a fraction of the nominal)"),
            ))
        }
        _ => {
            return Err(FieldError::new(
                f,
                "give min and max (masses), or tolerance (a fraction), not both",
            ))
        }
    };
    if !(lo >= 0.0 && hi >= lo && hi.is_finite()) {
        return Err(FieldError::new(
            format!("{f}.max"),
            format!("got {lo} kg to {hi} kg; allowed: 0 ≤ min ≤ max"),
        ));
    }
    Ok((lo, hi))
}

/// The name of the nominal case, the file's own loads (no load case may take it).
pub const NOMINAL: &str = "nominal";

/// Most entries of `[[mechanism.load_cases]]` (the nominal case comes on top).
pub const MAX_LOAD_CASES: usize = 16;

/// Longest name of a load case (characters).
pub const MAX_CASE_NAME: usize = 64;

/// The checked name of load case `key` (`mechanism.load_cases[i]`): `raw` trimmed, 1 to
/// [`MAX_CASE_NAME`] characters, no comma, quote or control character (it is a CSV cell),
/// not [`NOMINAL`] and none of `taken`; `nominal_is` says what the nominal case is in the
/// error.
pub fn case_name<'a>(
    key: &str,
    raw: &str,
    mut taken: impl Iterator<Item = &'a str>,
    nominal_is: &str,
) -> Result<String, FieldError> {
    let name = raw.trim();
    let bad = name.is_empty()
        || name.chars().count() > MAX_CASE_NAME
        || name
            .chars()
            .any(|ch| ch == ',' || ch == '"' || ch.is_control());
    let used = name == NOMINAL || taken.any(|k| k == name);
    if bad || used {
        return Err(FieldError::new(
            format!("{key}.name"),
            format!(
                "{raw:?} {}; allowed: a unique name of 1 to {MAX_CASE_NAME} characters, no comma, quote or control character, not \"{NOMINAL}\" ({nominal_is})",
                if used { "is taken" } else { "is no name" }
            ),
        ));
    }
    Ok(name.to_string())
}

/// At most [`MAX_LOAD_CASES`] entries of `[[mechanism.load_cases]]`: more name the first one
/// too many (an array of tables has no line of its own).
pub fn case_count(n: usize) -> Result<(), FieldError> {
    if n > MAX_LOAD_CASES {
        return Err(FieldError::new(
            format!("mechanism.load_cases[{MAX_LOAD_CASES}]"),
            format!("{n} load cases; allowed: at most {MAX_LOAD_CASES}"),
        ));
    }
    Ok(())
}
