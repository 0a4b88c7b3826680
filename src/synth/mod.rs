//! Synthesis: design vectors with bounds, objectives and the solvers that optimise them.
//!
//! A design variable is either fixed or free within bounds ([`Var`]), so the same scene
//! serves analysis (everything fixed) and synthesis.

pub mod counterweight;
pub mod crane;
pub mod gear;
pub mod hypocycloid;
pub mod shape;
pub mod slider_crank;

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
