//! Synthesis: design vectors with bounds, objectives and the solvers that optimise them.
//!
//! A design variable is either fixed or free within bounds ([`Var`]), so the same scene
//! serves analysis (everything fixed) and synthesis.

pub(crate) mod conic;
pub mod counterweight;
pub mod exchange;
pub mod minimax;
pub mod search;
pub mod shape;

pub use search::SearchEvidence;

/// A design variable the optimum left on one of its bounds: the bound, not an interior
/// optimum, decides it, and when the bound is a machine limit the designer should know that
/// the limit shapes the machine (JSON key `bounds`, one entry each).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ActiveBound {
    /// The result key of the variable (e.g. `design.lambda`).
    pub key: String,
    /// Its value (SI).
    pub value: f64,
    /// The bound it sits on (SI).
    pub bound: f64,
    /// `lower` or `upper`.
    pub side: BoundSide,
    /// The problem-file key that sets the bound (e.g. `objective.max_rod_length`).
    pub set_by: String,
    /// What it means for the machine, in words.
    pub meaning: String,
}

/// Which bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundSide {
    /// The lower bound.
    Lower,
    /// The upper bound.
    Upper,
}

impl ActiveBound {
    /// The bound `value` sits on within `rel` of the range `(lo, hi)` (of the value's scale
    /// when the range is a point or unbounded), if any; `set_by` and `meaning` name each side.
    pub fn check(
        key: &str,
        value: f64,
        (lo, hi): (f64, f64),
        rel: f64,
        lower: (&str, &str),
        upper: (&str, &str),
    ) -> Option<ActiveBound> {
        let span = if hi.is_finite() && hi > lo {
            hi - lo
        } else {
            value.abs().max(lo.abs())
        };
        let tol = rel * span;
        let (side, bound, (set_by, meaning)) = if hi.is_finite() && (hi - value).abs() <= tol {
            (BoundSide::Upper, hi, upper)
        } else if lo.is_finite() && (value - lo).abs() <= tol {
            (BoundSide::Lower, lo, lower)
        } else {
            return None;
        };
        Some(ActiveBound {
            key: key.into(),
            value,
            bound,
            side,
            set_by: set_by.into(),
            meaning: meaning.into(),
        })
    }
}

/// A design variable: a fixed value, or free within `[min, max]` (SI units).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "kebab-case", untagged)]
pub enum Var {
    /// Fixed at this value.
    Fixed(f64),
    /// Free in `[min, max]`.
    Free {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
}

impl Var {
    /// The value if fixed.
    pub fn fixed(&self) -> Option<f64> {
        match *self {
            Var::Fixed(v) => Some(v),
            Var::Free { .. } => None,
        }
    }
    /// `(min, max)`; a fixed value is its own bounds.
    pub fn bounds(&self) -> (f64, f64) {
        match *self {
            Var::Fixed(v) => (v, v),
            Var::Free { min, max } => (min, max),
        }
    }
    /// Whether `x` lies within the bounds (to a relative `1e-12`).
    pub fn contains(&self, x: f64) -> bool {
        let (lo, hi) = self.bounds();
        let tol = 1e-12
            * x.abs()
                .max(lo.abs())
                .max(if hi.is_finite() { hi.abs() } else { 0.0 });
        x >= lo - tol && x <= hi + tol
    }
}
