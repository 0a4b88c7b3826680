//! The integer settings of every family and their documented ranges.
//!
//! A count of samples, points, rounds or iterations sizes an allocation or a loop, so a huge
//! one (`rms_samples = 18446744073709551615`) would overflow, abort or hang, and a tiny one
//! would mean nothing. Each integer key of a problem file has a range in its family's table
//! (`COUNTS` in `families/<family>/file.rs`), checked by the
//! family's resolver before anything is sized by it ([`check`], [`check_section`]), written in
//! `docs/problem-files.md`, and given to the JSON schema as `minimum`/`maximum`. Every
//! maximum keeps one run of an otherwise default scene within about a second
//! (`tests/integer_limits.rs` runs each at its minimum and maximum). Their products are
//! bounded by a per-family work budget ([`check_work`], formulas in each family's
//! `check_work` and in `docs/problem-files.md`).

use crate::problem::FieldError;

/// One integer key of a problem file and its allowed range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Count {
    /// Dotted key as written in the file (`accuracy.rms_samples`); for an array, each
    /// element is checked.
    pub key: &'static str,
    /// Smallest value allowed.
    pub min: u64,
    /// Largest value allowed.
    pub max: u64,
}

pub const fn c(key: &'static str, min: u64, max: u64) -> Count {
    Count { key, min, max }
}

/// The range of `key` in a family's table.
///
/// # Panics
/// If the key is not in the table (a programming error: every integer key of a raw struct
/// is listed; `tests/hostile_input.rs` reads them all).
pub fn count(counts: &[Count], key: &str) -> Count {
    *counts
        .iter()
        .find(|c| c.key == key)
        .unwrap_or_else(|| panic!("{key} is no integer key of this family"))
}

/// Checks `v` against the range of `key`: an error naming the key and the range.
pub fn check(counts: &[Count], key: &str, v: i128) -> Result<(), FieldError> {
    let Count { min, max, .. } = count(counts, key);
    if (i128::from(min)..=i128::from(max)).contains(&v) {
        Ok(())
    } else {
        Err(FieldError::new(
            key,
            format!("{v} is out of range; allowed: an integer from {min} to {max}"),
        ))
    }
}

/// Checks every integer key of a family's table under `section` (`accuracy`) in `value` (a
/// section's struct, read through its serde form so that no key is forgotten).
pub fn check_section<T: serde::Serialize>(
    counts: &[Count],
    section: &str,
    value: &T,
) -> Result<(), FieldError> {
    let json = serde_json::to_value(value).expect("settings serialise");
    for c in counts {
        let Some(name) = c
            .key
            .strip_prefix(section)
            .and_then(|k| k.strip_prefix('.'))
        else {
            continue;
        };
        if let Some(v) = json.get(name).and_then(serde_json::Value::as_u64) {
            check(counts, c.key, i128::from(v))?;
        }
    }
    Ok(())
}

/// One factor of a work estimate: the dotted key, its value and its default (the key
/// raised most above its default is the one an error names).
#[derive(Debug, Clone, Copy)]
pub struct Term<'a> {
    /// Dotted key (or the keys that set a derived count, e.g. the arch count).
    pub key: &'a str,
    /// Its value in the scene.
    pub value: f64,
    /// Its default (or a typical value).
    pub default: f64,
}

/// A term: `key = value` with its default.
pub fn term(key: &str, value: impl Into<f64>, default: impl Into<f64>) -> Term<'_> {
    Term {
        key,
        value: value.into(),
        default: default.into(),
    }
}

/// Checks a scene's work `estimate` (written as `formula`) against its family's `budget`
/// (`WORK_BUDGET` in `families/<family>/file.rs`, see `docs/problem-files.md`, "Work
/// budget"): integer settings can each be at their maximum, but their products multiply
/// (samples × starts × iterations × grid points). Over the budget, an error naming the term
/// raised most above its default, and listing every term with its value.
pub fn check_work(
    budget: f64,
    family: &str,
    estimate: f64,
    formula: &str,
    terms: &[Term],
) -> Result<(), FieldError> {
    if estimate <= budget {
        return Ok(());
    }
    let worst = terms
        .iter()
        .max_by(|a, b| (a.value / a.default).total_cmp(&(b.value / b.default)))
        .map_or("accuracy", |t| t.key);
    let list: Vec<String> = terms
        .iter()
        .map(|t| format!("{} = {} (default {})", t.key, t.value, t.default))
        .collect();
    Err(FieldError::new(
        worst,
        format!(
            "the scene's work estimate {formula} = {estimate:.3e} is above the {family} budget {budget:.0e}, which keeps one machine to seconds; lower one of: {}",
            list.join(", ")
        ),
    ))
}
