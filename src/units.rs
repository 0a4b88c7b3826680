//! Quantities with units at the edges of the program.
//!
//! Inside, everything is SI (m, kg, s, rad, N, N·m). Problem files and fleet CSV cells
//! write a dimensional quantity as a string with a unit, `"35 mm"`, `"1000 rpm"`,
//! `"12 deg"`; units are never guessed, so a bare number (`speed = 1500`) is an error for
//! any dimension but [`Dim::Dimensionless`] (λ, k1, counts stay plain numbers). [`parse`]
//! turns such a string into SI for an expected [`Dim`]; a missing, unknown or wrong unit
//! is an error that lists the units allowed. [`Qty`] is the serde face of the same thing, so that a bad unit in a
//! problem file is reported by the TOML reader with its line and column.

use serde::de::{self, Deserializer, Visitor};
use std::fmt;
use std::marker::PhantomData;

/// Standard gravity g₀ (m/s², exact by definition, CGPM 1901).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// Physical dimension of a quantity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Dim {
    /// A pure number (ratios such as λ, k1).
    Dimensionless,
    /// m.
    Length,
    /// kg.
    Mass,
    /// rad.
    Angle,
    /// rad/s.
    AngularSpeed,
    /// N.
    Force,
    /// N·m.
    Torque,
    /// kg·m (a static moment, the unbalance m·r of a counterweight).
    Unbalance,
    /// kg·m² (a moment of inertia).
    Inertia,
    /// kg/m³.
    Density,
    /// m/s².
    Acceleration,
    /// s.
    Time,
    /// Pa (a gas pressure, absolute unless a key says otherwise).
    Pressure,
    /// N/m (a spring's stiffness: a mount's).
    Stiffness,
    /// N·s/m (a viscous damper's coefficient: a mount's).
    Damping,
}

impl Dim {
    /// Human name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Dim::Dimensionless => "pure number",
            Dim::Length => "length",
            Dim::Mass => "mass",
            Dim::Angle => "plane angle",
            Dim::AngularSpeed => "rotational speed",
            Dim::Force => "force",
            Dim::Torque => "torque",
            Dim::Unbalance => "static unbalance (mass × length)",
            Dim::Inertia => "mass moment of inertia",
            Dim::Density => "density",
            Dim::Acceleration => "linear acceleration",
            Dim::Time => "time",
            Dim::Pressure => "pressure",
            Dim::Stiffness => "stiffness (force per length)",
            Dim::Damping => "viscous damping (force per speed)",
        }
    }

    /// The SI unit written in results.
    pub fn si(self) -> &'static str {
        UNITS
            .iter()
            .find(|u| u.dim == self && u.factor == 1.0)
            .map_or("", |u| u.symbol)
    }

    /// What a value of this dimension may be written as: for a pure number a plain
    /// number, else a string with a number and one of the accepted units.
    pub fn allowed(self) -> String {
        let list: Vec<&str> = UNITS
            .iter()
            .filter(|u| u.dim == self)
            .map(|u| u.symbol)
            .collect();
        if list.is_empty() {
            "a plain number".into()
        } else {
            format!(
                "a string with a number and one of the units: {} (e.g. \"1 {}\")",
                list.join(", "),
                list[0]
            )
        }
    }
}

/// One accepted unit: its symbol, dimension and factor to SI.
#[derive(Debug, Clone, Copy)]
pub struct Unit {
    /// As written (`"mm"`).
    pub symbol: &'static str,
    /// Dimension.
    pub dim: Dim,
    /// SI value of one unit.
    pub factor: f64,
}

const DEG: f64 = std::f64::consts::PI / 180.0;
const RPM: f64 = std::f64::consts::TAU / 60.0;
/// One inch (m), exact.
const IN: f64 = 0.0254;
/// One foot (m), exact.
const FT: f64 = 12.0 * IN;
/// One pound (kg), exact.
const LB: f64 = 0.453_592_37;
/// One ounce (kg), exact.
const OZ: f64 = LB / 16.0;
/// One pound-force (N), exact: 1 lb × standard gravity.
const LBF: f64 = LB * STANDARD_GRAVITY;

/// Every unit accepted. The first entry of each dimension with factor 1 is its SI unit.
pub const UNITS: &[Unit] = &[
    Unit {
        symbol: "m",
        dim: Dim::Length,
        factor: 1.0,
    },
    Unit {
        symbol: "mm",
        dim: Dim::Length,
        factor: 1e-3,
    },
    Unit {
        symbol: "cm",
        dim: Dim::Length,
        factor: 1e-2,
    },
    Unit {
        symbol: "km",
        dim: Dim::Length,
        factor: 1e3,
    },
    Unit {
        symbol: "kg",
        dim: Dim::Mass,
        factor: 1.0,
    },
    Unit {
        symbol: "g",
        dim: Dim::Mass,
        factor: 1e-3,
    },
    Unit {
        symbol: "t",
        dim: Dim::Mass,
        factor: 1e3,
    },
    Unit {
        symbol: "rad",
        dim: Dim::Angle,
        factor: 1.0,
    },
    Unit {
        symbol: "deg",
        dim: Dim::Angle,
        factor: DEG,
    },
    Unit {
        symbol: "°",
        dim: Dim::Angle,
        factor: DEG,
    },
    Unit {
        symbol: "rad/s",
        dim: Dim::AngularSpeed,
        factor: 1.0,
    },
    Unit {
        symbol: "rpm",
        dim: Dim::AngularSpeed,
        factor: RPM,
    },
    Unit {
        symbol: "r/min",
        dim: Dim::AngularSpeed,
        factor: RPM,
    },
    Unit {
        symbol: "N",
        dim: Dim::Force,
        factor: 1.0,
    },
    Unit {
        symbol: "kN",
        dim: Dim::Force,
        factor: 1e3,
    },
    Unit {
        symbol: "MN",
        dim: Dim::Force,
        factor: 1e6,
    },
    Unit {
        symbol: "N·m",
        dim: Dim::Torque,
        factor: 1.0,
    },
    Unit {
        symbol: "N*m",
        dim: Dim::Torque,
        factor: 1.0,
    },
    Unit {
        symbol: "Nm",
        dim: Dim::Torque,
        factor: 1.0,
    },
    Unit {
        symbol: "N·mm",
        dim: Dim::Torque,
        factor: 1e-3,
    },
    Unit {
        symbol: "N*mm",
        dim: Dim::Torque,
        factor: 1e-3,
    },
    Unit {
        symbol: "Nmm",
        dim: Dim::Torque,
        factor: 1e-3,
    },
    Unit {
        symbol: "kN·m",
        dim: Dim::Torque,
        factor: 1e3,
    },
    Unit {
        symbol: "kN*m",
        dim: Dim::Torque,
        factor: 1e3,
    },
    Unit {
        symbol: "kg·m",
        dim: Dim::Unbalance,
        factor: 1.0,
    },
    Unit {
        symbol: "kg*m",
        dim: Dim::Unbalance,
        factor: 1.0,
    },
    Unit {
        symbol: "kg·mm",
        dim: Dim::Unbalance,
        factor: 1e-3,
    },
    Unit {
        symbol: "kg*mm",
        dim: Dim::Unbalance,
        factor: 1e-3,
    },
    Unit {
        symbol: "g·mm",
        dim: Dim::Unbalance,
        factor: 1e-6,
    },
    Unit {
        symbol: "g*mm",
        dim: Dim::Unbalance,
        factor: 1e-6,
    },
    Unit {
        symbol: "kg·m²",
        dim: Dim::Inertia,
        factor: 1.0,
    },
    Unit {
        symbol: "kg*m^2",
        dim: Dim::Inertia,
        factor: 1.0,
    },
    Unit {
        symbol: "kg·mm²",
        dim: Dim::Inertia,
        factor: 1e-6,
    },
    Unit {
        symbol: "kg*mm^2",
        dim: Dim::Inertia,
        factor: 1e-6,
    },
    Unit {
        symbol: "kg/m³",
        dim: Dim::Density,
        factor: 1.0,
    },
    Unit {
        symbol: "kg/m^3",
        dim: Dim::Density,
        factor: 1.0,
    },
    Unit {
        symbol: "kg/m3",
        dim: Dim::Density,
        factor: 1.0,
    },
    Unit {
        symbol: "g/cm³",
        dim: Dim::Density,
        factor: 1e3,
    },
    Unit {
        symbol: "g/cm^3",
        dim: Dim::Density,
        factor: 1e3,
    },
    Unit {
        symbol: "m/s²",
        dim: Dim::Acceleration,
        factor: 1.0,
    },
    Unit {
        symbol: "m/s^2",
        dim: Dim::Acceleration,
        factor: 1.0,
    },
    Unit {
        symbol: "s",
        dim: Dim::Time,
        factor: 1.0,
    },
    Unit {
        symbol: "ms",
        dim: Dim::Time,
        factor: 1e-3,
    },
    Unit {
        symbol: "N/m",
        dim: Dim::Stiffness,
        factor: 1.0,
    },
    Unit {
        symbol: "N/mm",
        dim: Dim::Stiffness,
        factor: 1e3,
    },
    Unit {
        symbol: "kN/m",
        dim: Dim::Stiffness,
        factor: 1e3,
    },
    Unit {
        symbol: "kN/mm",
        dim: Dim::Stiffness,
        factor: 1e6,
    },
    Unit {
        symbol: "MN/m",
        dim: Dim::Stiffness,
        factor: 1e6,
    },
    Unit {
        symbol: "N·s/m",
        dim: Dim::Damping,
        factor: 1.0,
    },
    Unit {
        symbol: "N*s/m",
        dim: Dim::Damping,
        factor: 1.0,
    },
    Unit {
        symbol: "kN·s/m",
        dim: Dim::Damping,
        factor: 1e3,
    },
    Unit {
        symbol: "kN*s/m",
        dim: Dim::Damping,
        factor: 1e3,
    },
    Unit {
        symbol: "Pa",
        dim: Dim::Pressure,
        factor: 1.0,
    },
    Unit {
        symbol: "kPa",
        dim: Dim::Pressure,
        factor: 1e3,
    },
    Unit {
        symbol: "MPa",
        dim: Dim::Pressure,
        factor: 1e6,
    },
    Unit {
        symbol: "GPa",
        dim: Dim::Pressure,
        factor: 1e9,
    },
    Unit {
        symbol: "bar",
        dim: Dim::Pressure,
        factor: 1e5,
    },
    // US customary units (exact by definition: 1 in = 25.4 mm, 1 lb = 0.45359237 kg,
    // 1 lbf = 1 lb × standard gravity); rotational frequency 1 Hz = 1 rev/s.
    Unit {
        symbol: "in",
        dim: Dim::Length,
        factor: IN,
    },
    Unit {
        symbol: "ft",
        dim: Dim::Length,
        factor: FT,
    },
    Unit {
        symbol: "lb",
        dim: Dim::Mass,
        factor: LB,
    },
    Unit {
        symbol: "oz",
        dim: Dim::Mass,
        factor: OZ,
    },
    Unit {
        symbol: "RPM",
        dim: Dim::AngularSpeed,
        factor: RPM,
    },
    Unit {
        symbol: "rev/min",
        dim: Dim::AngularSpeed,
        factor: RPM,
    },
    Unit {
        symbol: "rev/s",
        dim: Dim::AngularSpeed,
        factor: std::f64::consts::TAU,
    },
    Unit {
        symbol: "Hz",
        dim: Dim::AngularSpeed,
        factor: std::f64::consts::TAU,
    },
    Unit {
        symbol: "lbf",
        dim: Dim::Force,
        factor: LBF,
    },
    Unit {
        symbol: "lbf·ft",
        dim: Dim::Torque,
        factor: LBF * FT,
    },
    Unit {
        symbol: "lbf*ft",
        dim: Dim::Torque,
        factor: LBF * FT,
    },
    Unit {
        symbol: "lbf·in",
        dim: Dim::Torque,
        factor: LBF * IN,
    },
    Unit {
        symbol: "lbf*in",
        dim: Dim::Torque,
        factor: LBF * IN,
    },
    Unit {
        symbol: "lb·in",
        dim: Dim::Unbalance,
        factor: LB * IN,
    },
    Unit {
        symbol: "lb*in",
        dim: Dim::Unbalance,
        factor: LB * IN,
    },
    Unit {
        symbol: "oz·in",
        dim: Dim::Unbalance,
        factor: OZ * IN,
    },
    Unit {
        symbol: "oz*in",
        dim: Dim::Unbalance,
        factor: OZ * IN,
    },
    Unit {
        symbol: "lb·in²",
        dim: Dim::Inertia,
        factor: LB * IN * IN,
    },
    Unit {
        symbol: "lb*in^2",
        dim: Dim::Inertia,
        factor: LB * IN * IN,
    },
    Unit {
        symbol: "lb·ft²",
        dim: Dim::Inertia,
        factor: LB * FT * FT,
    },
    Unit {
        symbol: "lb*ft^2",
        dim: Dim::Inertia,
        factor: LB * FT * FT,
    },
    Unit {
        symbol: "lb/in³",
        dim: Dim::Density,
        factor: LB / (IN * IN * IN),
    },
    Unit {
        symbol: "lb/in^3",
        dim: Dim::Density,
        factor: LB / (IN * IN * IN),
    },
    Unit {
        symbol: "ft/s²",
        dim: Dim::Acceleration,
        factor: FT,
    },
    Unit {
        symbol: "ft/s^2",
        dim: Dim::Acceleration,
        factor: FT,
    },
    Unit {
        symbol: "psi",
        dim: Dim::Pressure,
        factor: LBF / (IN * IN),
    },
];

/// Why a quantity string was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UnitError {
    /// The text does not start with a number.
    #[error("`{text}` is not a quantity: expected a number, optionally followed by a unit; allowed for a {dim}: {allowed}", dim = .dim.name())]
    NotANumber {
        text: String,
        dim: Dim,
        allowed: String,
    },
    /// The number is NaN or infinite.
    #[error("`{text}` is not a finite number")]
    NotFinite { text: String },
    /// A dimensional quantity is written without a unit.
    #[error("`{text}` has no unit, and units are never guessed: a {dim} needs one; allowed: {allowed}", dim = .dim.name())]
    NoUnit {
        text: String,
        dim: Dim,
        allowed: String,
    },
    /// The unit is not known at all (`hint`: "; did you mean `mm`?" or empty).
    #[error("unknown unit `{unit}` for a {dim}{hint}; allowed: {allowed}", dim = .dim.name())]
    UnknownUnit {
        unit: String,
        dim: Dim,
        hint: String,
        allowed: String,
    },
    /// A decimal comma (`1,5 mm`): numbers are written with a decimal point.
    #[error("`{text}` has a decimal comma; write numbers with a decimal point: \"{with_point}\"")]
    DecimalComma { text: String, with_point: String },
    /// The text is longer than any quantity ([`MAX_QUANTITY_LEN`] bytes).
    #[error(
        "a quantity of {len} bytes; allowed: at most {MAX_QUANTITY_LEN} bytes, e.g. \"35 mm\""
    )]
    TooLong { len: usize },
    /// The value is beyond [`Dim::max_magnitude`] in SI.
    #[error("`{text}` is {si:e} {unit} in SI, beyond any machine; allowed: a magnitude up to {max:e} {unit}", unit = .dim.si(), max = .dim.max_magnitude())]
    OutOfRange { text: String, si: f64, dim: Dim },
    /// The value is nonzero but below [`MIN_MAGNITUDE`] in SI.
    #[error("`{text}` is {si:e} {unit} in SI, below any machine (its squares would lose their digits); allowed: 0 or a magnitude from {MIN_MAGNITUDE:e} {unit}", unit = .dim.si())]
    BelowRange { text: String, si: f64, dim: Dim },
    /// The unit is known but measures something else.
    #[error("`{unit}` is a unit of {found}, but this field is a {dim}; allowed: {allowed}", found = .found.name(), dim = .dim.name())]
    WrongDimension {
        unit: String,
        found: Dim,
        dim: Dim,
        allowed: String,
    },
}

/// The longest quantity string read (bytes): a longer one is a mistake, and parsing it
/// would take time for nothing.
pub const MAX_QUANTITY_LEN: usize = 256;

/// The smallest nonzero magnitude of a dimensional quantity in SI (1e-30 m, kg, N, rad/s, …):
/// far below any machine (an atom is 1e-10 m, an electron 9e-31 kg), and large enough that
/// the products the models form (m·R·ω², up to four such factors) and their squares (|F|²
/// in the cone programs, 1e-240 at worst) stay normal floats. Measured: a piston scaled by
/// 1e-60 in every length and mass solves to the same optimum as the original to 1e-15,
/// scaled by 1e-80 it does not (its squared forces are subnormal); a value such as
/// `1e-80 m` is therefore an error instead of a wrong `optimal`.
pub const MIN_MAGNITUDE: f64 = 1e-30;

/// The largest magnitude of a dimensional quantity in SI (1e9 m, kg, N, rad/s, …): far
/// beyond any machine, and small enough that products of a few such values (m·R·ω²) stay
/// finite, so a typo such as `1e308 mm` is an error instead of an overflow deep inside.
pub const MAX_MAGNITUDE: f64 = 1e9;

impl Dim {
    /// The largest magnitude accepted in SI: [`MAX_MAGNITUDE`], except for a pressure, which
    /// also names the stiffest materials (steel's Young's modulus is 2.1e11 Pa, diamond's
    /// 1.2e12 Pa): up to 1e13 Pa.
    pub fn max_magnitude(self) -> f64 {
        match self {
            Dim::Pressure => 1e13,
            _ => MAX_MAGNITUDE,
        }
    }
}

/// The candidate closest to `word` by edit distance (Damerau–Levenshtein, ignoring case),
/// if it is close enough to be a misspelling: at most a third of the longer word's length,
/// and at least one edit allowed. For "did you mean" in errors (unknown keys, units, values).
/// (Misspelt key `crank_mas` against `crank_mass`: 1 edit.)
pub fn did_you_mean<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    if word.len() > 64 {
        return None;
    }
    let w = word.to_lowercase();
    candidates
        .into_iter()
        .map(|c| (strsim::damerau_levenshtein(&w, &c.to_lowercase()), c))
        .filter(|&(d, c)| d > 0 && d <= (w.chars().count().max(c.chars().count()) / 3).max(1))
        // The fewest edits; of those, the candidate of the written length (`mn`: `mm`).
        .min_by_key(|&(d, c)| (d, c.chars().count().abs_diff(w.chars().count())))
        .map(|(_, c)| c)
}

/// Whether `a` and `b` are one unit once the spellings people type for a product of units
/// are normalised: `N.m`, `N-m`, `N⋅m` and `N · m` all read as `N·m` (trimmed, `.`, `⋅`, `-`
/// read as `·`, spaces dropped). Compares without allocating.
// pub for the tests in tests/unit_units.rs
#[doc(hidden)]
pub fn same_unit(a: &str, b: &str) -> bool {
    fn normalised(s: &str) -> impl Iterator<Item = char> + '_ {
        s.trim().chars().filter(|&c| c != ' ').map(|c| {
            if matches!(c, '.' | '⋅' | '-') {
                '·'
            } else {
                c
            }
        })
    }
    normalised(a).eq(normalised(b))
}

/// The accepted unit written `symbol` (in any of its spellings), if any. Every symbol of
/// [`UNITS`] is written normalised, so the symbol itself is looked for first.
fn find_unit(symbol: &str) -> Option<&'static Unit> {
    UNITS
        .iter()
        .find(|u| u.symbol == symbol)
        .or_else(|| UNITS.iter().find(|u| same_unit(u.symbol, symbol)))
}

/// Splits trimmed text into its number (the longest prefix that parses as a float) and the
/// rest, trimmed (the unit, maybe empty); `None` if it does not start with a number.
fn split_number(t: &str) -> Option<(f64, &str)> {
    // A float is written in these characters, but for `inf`, `infinity` and `nan`: so the
    // number ends before the first other one (a longer prefix that parses only adds spaces).
    let word = t
        .trim_start_matches(['+', '-'])
        .starts_with(['i', 'I', 'n', 'N']);
    let end = match word {
        true => t.len(),
        false => t
            .find(|c: char| !matches!(c, '0'..='9' | '.' | 'e' | 'E' | '+' | '-'))
            .unwrap_or(t.len()),
    };
    let i = (1..=end)
        .rev()
        .filter(|&i| t.is_char_boundary(i))
        .find(|&i| t[..i].trim_end().parse::<f64>().is_ok())?;
    let value = t[..i].trim_end().parse().expect("checked above");
    Some((value, t[i..].trim()))
}

/// Parses `"35 mm"` (or `"35mm"`, `"1e3 rpm"`) into SI for the dimension `dim`. A number
/// without a unit is a pure number: accepted for [`Dim::Dimensionless`] only, else
/// [`UnitError::NoUnit`] (see [`bare`]).
pub fn parse(text: &str, dim: Dim) -> Result<f64, UnitError> {
    if text.len() > MAX_QUANTITY_LEN {
        return Err(UnitError::TooLong { len: text.len() });
    }
    let si = parse_unbounded(text, dim)?;
    if dim != Dim::Dimensionless && si.abs() > dim.max_magnitude() {
        return Err(UnitError::OutOfRange {
            text: text.into(),
            si,
            dim,
        });
    }
    if dim != Dim::Dimensionless && si != 0.0 && si.abs() < MIN_MAGNITUDE {
        return Err(UnitError::BelowRange {
            text: text.into(),
            si,
            dim,
        });
    }
    Ok(si)
}

/// [`parse`] without the magnitude bound.
fn parse_unbounded(text: &str, dim: Dim) -> Result<f64, UnitError> {
    let Some((value, unit)) = split_number(text.trim()) else {
        return Err(UnitError::NotANumber {
            text: text.into(),
            dim,
            allowed: dim.allowed(),
        });
    };
    // "1e" would parse "1" and leave "e": fine, "e" is no unit and is rejected below.
    if !value.is_finite() {
        return Err(UnitError::NotFinite { text: text.into() });
    }
    if unit.is_empty() {
        return bare(value, dim);
    }
    // `1,5 mm`: a decimal comma leaves `,5 mm` as the unit.
    if let Some(rest) = unit.strip_prefix(',') {
        if rest.starts_with(|c: char| c.is_ascii_digit()) {
            let t = text.trim();
            return Err(UnitError::DecimalComma {
                text: text.into(),
                with_point: t.replacen(',', ".", 1),
            });
        }
    }
    match find_unit(unit) {
        Some(u) if u.dim == dim => Ok(value * u.factor),
        Some(u) => Err(UnitError::WrongDimension {
            unit: unit.into(),
            found: u.dim,
            dim,
            allowed: dim.allowed(),
        }),
        None => Err(UnitError::UnknownUnit {
            unit: unit.into(),
            dim,
            hint: did_you_mean(
                unit,
                UNITS.iter().filter(|u| u.dim == dim).map(|u| u.symbol),
            )
            .map(|u| format!("; did you mean `{u}`?"))
            .unwrap_or_default(),
            allowed: dim.allowed(),
        }),
    }
}

/// A number written without a unit, for a field of dimension `dim`: itself for a pure
/// number, [`UnitError::NoUnit`] for anything else (units are never guessed).
pub fn bare(value: f64, dim: Dim) -> Result<f64, UnitError> {
    match dim {
        Dim::Dimensionless => Ok(value),
        _ => Err(UnitError::NoUnit {
            text: value.to_string(),
            dim,
            allowed: dim.allowed(),
        }),
    }
}

/// The accepted unit written `symbol` (any of its spellings), if any: for a unit written
/// once for many values (a fleet CSV column header `mechanism.speed [rpm]`).
pub fn unit(symbol: &str) -> Option<&'static Unit> {
    find_unit(symbol.trim())
}

/// Parses a quantity whose dimension is given by its unit; returns the SI value and the
/// dimension (`Dimensionless` for a bare number). Text that is no quantity is reported as
/// for a length.
pub fn parse_any(text: &str) -> Result<(f64, Dim), UnitError> {
    let dim = match split_number(text.trim()) {
        Some((_, "")) => Dim::Dimensionless,
        s => s
            .and_then(|(_, unit)| find_unit(unit))
            .map_or(Dim::Length, |u| u.dim),
    };
    Ok((parse(text, dim)?, dim))
}

/// Compile-time dimension marker for [`Qty`].
pub trait Dimension {
    /// The dimension checked on input.
    const DIM: Dim;
}

macro_rules! dims {
    ($($name:ident),*) => {$(
        #[doc = concat!("Marker: a quantity of dimension [`Dim::", stringify!($name), "`].")]
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct $name;
        impl Dimension for $name { const DIM: Dim = Dim::$name; }
    )*};
}
dims!(
    Dimensionless,
    Length,
    Mass,
    Angle,
    AngularSpeed,
    Force,
    Torque,
    Unbalance,
    Inertia,
    Density,
    Acceleration,
    Time,
    Pressure,
    Stiffness,
    Damping
);

/// A quantity read from a problem file: a string with a unit (a plain number only for
/// [`Dimensionless`]), converted to SI and checked for dimension and finiteness while
/// deserialising.
#[derive(Debug, PartialEq)]
pub struct Qty<D>(pub f64, PhantomData<D>);

impl<D> Clone for Qty<D> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<D> Copy for Qty<D> {}

impl<D> Qty<D> {
    /// An SI value.
    pub fn new(si: f64) -> Self {
        Qty(si, PhantomData)
    }
    /// The SI value.
    pub fn si(self) -> f64 {
        self.0
    }
}

impl<D: Dimension> serde::Serialize for Qty<D> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_f64(self.0)
    }
}

struct QtyVisitor<D>(PhantomData<D>);

impl<D: Dimension> Visitor<'_> for QtyVisitor<D> {
    type Value = Qty<D>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a {}: {}", D::DIM.name(), D::DIM.allowed())
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
        if !v.is_finite() {
            return Err(E::custom(format!(
                "{v} is not a finite number; allowed: {}",
                D::DIM.allowed()
            )));
        }
        bare(v, D::DIM).map(Qty::new).map_err(E::custom)
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
        self.visit_f64(v as f64)
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
        self.visit_f64(v as f64)
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
        parse(v, D::DIM).map(Qty::new).map_err(E::custom)
    }
}

impl<'de, D: Dimension> serde::Deserialize<'de> for Qty<D> {
    fn deserialize<De: Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        d.deserialize_any(QtyVisitor(PhantomData))
    }
}

/// A quantity that is a length or an angle, its unit saying which (`"0.5 mm"`, `"0.5 deg"`):
/// for a figure whose dimension follows another key of the file (a dwell's error is a
/// slider's travel or a rocker's angle). A bare number, or a unit of any other dimension,
/// is an error, never a guess.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LengthOrAngle {
    /// The SI value (m or rad).
    pub si: f64,
    /// [`Dim::Length`] or [`Dim::Angle`].
    pub dim: Dim,
}

impl<'de> serde::Deserialize<'de> for LengthOrAngle {
    fn deserialize<De: Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = LengthOrAngle;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(
                    f,
                    "a length or an angle with its unit (\"0.5 mm\", \"0.5 deg\")"
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
                Err(E::custom(format!(
                    "got the bare number {v}; allowed: a length or an angle with its unit (\"0.5 mm\", \"0.5 deg\")"
                )))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
                self.visit_f64(v as f64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
                self.visit_f64(v as f64)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                match parse_any(v).map_err(E::custom)? {
                    (si, dim @ (Dim::Length | Dim::Angle)) => Ok(LengthOrAngle { si, dim }),
                    (_, dim) => Err(E::custom(format!(
                        "got \"{v}\", a {}; allowed: a length or an angle with its unit (\"0.5 mm\", \"0.5 deg\")",
                        dim.name()
                    ))),
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// Serde for an `f64` setting that is an angle (a tolerance or a step in rad): read as a
/// [`Qty<Angle>`], so `"1e-10 rad"` or `"1e-8 deg"` and never a bare number (units are never
/// guessed, tolerances included); written back as `"<value> rad"`.
/// Use with `#[serde(with = "crate::units::angle_setting")]`.
pub mod angle_setting {
    use super::{Angle, Qty};
    use serde::{Deserialize, Deserializer, Serializer};

    /// Reads the angle, SI (rad).
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Qty::<Angle>::deserialize(d).map(Qty::si)
    }
    /// Writes the angle as text with its unit, so that it reads back.
    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&format!("{v:e} rad"))
    }
}

/// The text of an angle setting in rad, as a problem file writes it (`"1e-12 rad"`): for
/// edits that set a tolerance.
pub fn rad_text(v: f64) -> String {
    format!("{v:e} rad")
}
