//! The integer settings of every family and their documented ranges.
//!
//! A count of samples, points, rounds or iterations sizes an allocation or a loop, so a huge
//! one (`rms_samples = 18446744073709551615`) would overflow, abort or hang, and a tiny one
//! would mean nothing. Each integer key of a problem file has a range here, checked by the
//! family's resolver before anything is sized by it ([`check`], [`check_section`]), written in
//! `docs/problem-files.md`, and given to the JSON schema as `minimum`/`maximum`. Every
//! maximum keeps one run of an otherwise default scene within about a second
//! (`tests/integer_limits.rs` runs each at its minimum and maximum). Their products are
//! bounded by a per-family work budget ([`check_work`], formulas in each family's
//! `check_work` and in `docs/problem-files.md`).

use super::problem::{Family, FieldError};

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

const fn c(key: &'static str, min: u64, max: u64) -> Count {
    Count { key, min, max }
}

/// Slider-crank integer keys.
pub const SLIDER_CRANK: &[Count] = &[
    c("objective.pareto_points", 0, 200),
    c("objective.speed_sweep.points", 2, 200),
    c("accuracy.initial_samples", 3, 1024),
    c("accuracy.scan_samples", 16, 20_000),
    c("accuracy.max_rounds", 1, 1000),
    c("accuracy.rms_samples", 16, 100_000),
];

/// Luffing-crane integer keys.
pub const LUFFING_CRANE: &[Count] = &[
    c("accuracy.path_samples", 8, 1024),
    c("accuracy.plot_points", 2, 10_000),
    c("accuracy.global_samples", 1, 1000),
    c("accuracy.local_starts", 1, 50),
    c("accuracy.local_max_iters", 1, 2000),
    c("accuracy.landscape_k1", 0, 201),
    c("accuracy.landscape_k2", 0, 201),
];

/// Eccentric-gear integer keys.
pub const ECCENTRIC_GEAR: &[Count] = &[
    c("mechanism.turns_gear1", 1, 100),
    c("mechanism.turns_gear2", 1, 100),
    c("mechanism.teeth_gear1", 1, 10_000),
    c("mechanism.teeth_gear2", 1, 10_000),
    c("accuracy.samples_per_arch", 8, 1000),
    c("accuracy.peak_samples_per_arch", 8, 1000),
    c("accuracy.curvature_samples", 64, 50_000),
    c("accuracy.series_points", 16, 20_000),
    c("accuracy.curve_points", 16, 10_000),
    c("accuracy.sweep_points", 3, 101),
];

/// Hypocycloid integer keys.
pub const HYPOCYCLOID: &[Count] = &[
    c("mechanism.variant", 1, 2),
    c("model.orders", 6, 64),
    c("model.series_power", 1, 32),
    c("objective.balance_orders", 1, 64),
    c("objective.zero_search.order", 1, 64),
    c("accuracy.n_fft_min", 16, 1 << 20),
    c("accuracy.n_fft_max", 16, 1 << 20),
    c("accuracy.curve_points", 2, 400),
    c("accuracy.theta_scan", 4, 400),
    c("accuracy.peak_samples", 16, 4096),
    c("accuracy.opt_grid", 3, 40),
    c("accuracy.opt_starts", 1, 64),
    c("accuracy.nm_max_iters", 1, 5000),
    c("accuracy.plot_samples", 8, 100_000),
];

/// The integer keys of a family.
pub fn counts(family: Family) -> &'static [Count] {
    match family {
        Family::SliderCrank => SLIDER_CRANK,
        Family::LuffingCrane => LUFFING_CRANE,
        Family::EccentricGear => ECCENTRIC_GEAR,
        Family::Hypocycloid => HYPOCYCLOID,
    }
}

/// The range of `key` in `family`.
///
/// # Panics
/// If the key is not in the family's table (a programming error: every integer key of a
/// raw struct is listed; `tests/hostile_input.rs` reads them all).
pub fn count(family: Family, key: &str) -> Count {
    *counts(family)
        .iter()
        .find(|c| c.key == key)
        .unwrap_or_else(|| panic!("{key} is no integer key of {}", family.as_str()))
}

/// Checks `v` against the range of `key`: an error naming the key and the range.
pub fn check(family: Family, key: &str, v: i128) -> Result<(), FieldError> {
    let Count { min, max, .. } = count(family, key);
    if (i128::from(min)..=i128::from(max)).contains(&v) {
        Ok(())
    } else {
        Err(FieldError::new(
            key,
            format!("{v} is out of range; allowed: an integer from {min} to {max}"),
        ))
    }
}

/// Checks every integer key of `family` under `section` (`accuracy`) in `value` (a
/// section's struct, read through its serde form so that no key is forgotten).
pub fn check_section<T: serde::Serialize>(
    family: Family,
    section: &str,
    value: &T,
) -> Result<(), FieldError> {
    let json = serde_json::to_value(value).expect("settings serialise");
    for c in counts(family) {
        let Some(name) = c
            .key
            .strip_prefix(section)
            .and_then(|k| k.strip_prefix('.'))
        else {
            continue;
        };
        if let Some(v) = json.get(name).and_then(serde_json::Value::as_u64) {
            check(family, c.key, i128::from(v))?;
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

/// The work budget of one scene of each family, in the units of its estimate (see
/// `docs/problem-files.md`, "Work budget"): integer settings can each be at their maximum,
/// but their products multiply (samples × starts × iterations × grid points), so a scene's
/// estimated work is bounded too. Each budget lets every single setting at its maximum
/// (with the others at their defaults, on the shipped files) through and keeps a scene's run
/// to seconds: one row can neither stall a batch nor exhaust its memory.
pub fn budget(family: Family) -> f64 {
    match family {
        Family::SliderCrank => 1e7,
        Family::LuffingCrane => 2e7,
        Family::EccentricGear => 3e7,
        Family::Hypocycloid => 5e8,
    }
}

/// Checks a scene's work `estimate` (written as `formula`) against the family's
/// [`budget`]: over it, an error naming the term raised most above its default, and listing
/// every term with its value.
pub fn check_work(
    family: Family,
    estimate: f64,
    formula: &str,
    terms: &[Term],
) -> Result<(), FieldError> {
    let limit = budget(family);
    if estimate <= limit {
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
            "the scene's work estimate {formula} = {estimate:.3e} is above the {} budget {limit:.0e}, which keeps one machine to seconds; lower one of: {}",
            family.as_str(),
            list.join(", ")
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_ordered_and_keys_distinct() {
        for f in [
            Family::SliderCrank,
            Family::LuffingCrane,
            Family::EccentricGear,
            Family::Hypocycloid,
        ] {
            for (k, c) in counts(f).iter().enumerate() {
                assert!(c.min <= c.max, "{}", c.key);
                assert!(counts(f)[..k].iter().all(|d| d.key != c.key), "{}", c.key);
            }
        }
        let e = check(Family::SliderCrank, "accuracy.rms_samples", u64::MAX.into()).unwrap_err();
        assert_eq!(e.field, "accuracy.rms_samples");
        assert!(e.message.contains("16 to 100000"), "{}", e.message);
    }
}
