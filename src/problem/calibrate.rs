//! The `[calibrate]` section every problem file may carry: unknown data (a length the paper
//! lost, a mass nobody weighed) named with bounds, and the measured or printed values of
//! the result they must reproduce. `cwsynth calibrate` fits them (`crate::calibrate`); here
//! the section is read and checked (units of each value against its key), so a bad entry is
//! an error at its own line like any other key.

use super::{key_dim, FieldError, PaperValue};
use crate::units::Dim;
use serde::Deserialize;

/// `[calibrate]`: the parameters to fit and the values to match.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CalibrateRaw {
    /// `[[calibrate.parameter]]`: each unknown, a dotted key of this file with bounds.
    #[serde(rename = "parameter")]
    pub parameters: Vec<CalParameterRaw>,
    /// `[[calibrate.match]]`: each value the result must reproduce.
    #[serde(rename = "match")]
    pub matches: Vec<CalMatchRaw>,
}

/// One unknown parameter.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CalParameterRaw {
    /// Dotted key of this problem file (`mechanism.rod_length`).
    pub key: String,
    /// Lower bound, with its unit (`"200 mm"`; a plain number for a pure number).
    pub min: PaperValue,
    /// Upper bound, same dimension.
    pub max: PaperValue,
}

/// One value to reproduce.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CalMatchRaw {
    /// Dotted key of the result (`baselines.none.peak_drive_torque_nm`).
    pub key: String,
    /// The measured or printed value, with a unit of the key's dimension.
    pub value: PaperValue,
    /// Its standard uncertainty (e.g. half the last printed digit), same dimension, > 0.
    pub uncertainty: PaperValue,
    /// Where the value comes from.
    #[serde(default)]
    pub note: String,
}

/// A parameter, resolved (SI).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CalParameter {
    /// Dotted key of the problem file.
    pub key: String,
    /// Bounds (SI).
    pub min: f64,
    /// See `min`.
    pub max: f64,
    /// Its dimension (how the fitted value is written back: in the SI unit).
    #[serde(skip)]
    pub dim: Dim,
}

/// A value to match, resolved (SI).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CalMatch {
    /// Dotted result key.
    pub key: String,
    /// Target (SI).
    pub value: f64,
    /// Standard uncertainty (SI).
    pub uncertainty: f64,
    /// Source note.
    pub note: String,
}

/// The section, resolved.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Calibration {
    /// Unknowns.
    pub parameters: Vec<CalParameter>,
    /// Values to reproduce.
    pub matches: Vec<CalMatch>,
}

/// Most parameters and most matches of a calibration.
pub const MAX_CALIBRATION_ENTRIES: usize = 16;

/// Checks the section: 1 to 16 parameters and matches, bounds min < max of one dimension,
/// each match's value and uncertainty of its key's dimension (from the key's SI suffix,
/// as `[[paper]]`), the uncertainty > 0.
pub fn resolve_calibration(raw: &CalibrateRaw) -> Result<Calibration, FieldError> {
    for (n, what) in [
        (raw.parameters.len(), "calibrate.parameter"),
        (raw.matches.len(), "calibrate.match"),
    ] {
        if n == 0 || n > MAX_CALIBRATION_ENTRIES {
            return Err(FieldError::new(
                what,
                format!("{n} entries; allowed: 1 to {MAX_CALIBRATION_ENTRIES}"),
            ));
        }
    }
    let mut parameters = Vec::new();
    for (i, p) in raw.parameters.iter().enumerate() {
        let f = |k: &str| format!("calibrate.parameter[{i}].{k}");
        let (PaperValue(lo, d0), PaperValue(hi, d1)) = (p.min, p.max);
        if d0 != d1 {
            return Err(FieldError::new(
                f("max"),
                format!(
                    "a {}, but min is a {}; allowed: the same dimension",
                    d1.name(),
                    d0.name()
                ),
            ));
        }
        if !(lo < hi) {
            return Err(FieldError::new(f("max"), "allowed: max > min"));
        }
        if p.key.split('.').count() < 2 || p.key.split('.').any(|s| s.trim().is_empty()) {
            return Err(FieldError::new(
                f("key"),
                format!(
                    "`{}`: allowed: a dotted key of this file (`mechanism.rod_length`)",
                    p.key
                ),
            ));
        }
        parameters.push(CalParameter {
            key: p.key.clone(),
            min: lo,
            max: hi,
            dim: d0,
        });
    }
    let mut matches = Vec::new();
    for (i, m) in raw.matches.iter().enumerate() {
        let f = |k: &str| format!("calibrate.match[{i}].{k}");
        let want = key_dim(&m.key);
        for (k, PaperValue(_, d)) in [("value", m.value), ("uncertainty", m.uncertainty)] {
            if d != want {
                return Err(FieldError::new(
                    f(k),
                    format!(
                        "a {}, but the key `{}` is a {}; allowed: {}",
                        d.name(),
                        m.key,
                        want.name(),
                        want.allowed()
                    ),
                ));
            }
        }
        if !(m.uncertainty.0 > 0.0) {
            return Err(FieldError::new(f("uncertainty"), "allowed: > 0"));
        }
        matches.push(CalMatch {
            key: m.key.clone(),
            value: m.value.0,
            uncertainty: m.uncertainty.0,
            note: m.note.clone(),
        });
    }
    Ok(Calibration {
        parameters,
        matches,
    })
}
