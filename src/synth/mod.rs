//! Synthesis: design vectors with bounds, objectives and the solvers that optimise them.
//!
//! A design variable is either fixed or free within bounds ([`Var`]), so the same scene
//! serves analysis (everything fixed) and synthesis.

pub(crate) mod conic;
pub mod counterweight;
pub mod exchange;
pub mod minimax;
pub mod shape;

/// The evidence behind a `best_found` status: what a heuristic global search did and how
/// consistent its best results were (JSON key `search`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, Default)]
pub struct SearchEvidence {
    /// The search, with its reference (e.g. "Halton 256 + Nelder–Mead (Lagarias 1998) from 8 starts").
    pub method: String,
    /// Local searches started.
    pub starts: usize,
    /// Distinct local optima (basins) the starts ended in.
    pub distinct_basins: usize,
    /// Objective evaluations in all.
    pub evaluations: usize,
    /// The best few distinct local optima's objective values, best first (SI, the objective's unit).
    pub best_values: Vec<f64>,
    /// How many starts ended within `rel_tol` of the best value.
    pub starts_at_best: usize,
    /// (second best − best)/|best| over distinct basins; absent with one basin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spread_rel: Option<f64>,
}

impl SearchEvidence {
    /// The evidence of a minimising multistart from the objective values its starts ended
    /// at (feasible ends only) out of `starts` starts: ends within `same_rel` (relative) of
    /// each other are one basin; the best five distinct values are kept, best first.
    pub fn of_minima(
        method: String,
        mut ends: Vec<f64>,
        starts: usize,
        evaluations: usize,
        same_rel: f64,
    ) -> SearchEvidence {
        ends.sort_by(f64::total_cmp);
        let best = ends.first().copied();
        let at_best = best.map_or(0, |b| {
            ends.iter()
                .filter(|&&d| d <= b + same_rel * b.abs())
                .count()
        });
        ends.dedup_by(|a, b| (*a - *b).abs() <= same_rel * b.abs());
        let spread_rel = (ends.len() > 1).then(|| (ends[1] - ends[0]) / ends[0].abs().max(1e-300));
        SearchEvidence {
            method,
            starts,
            distinct_basins: ends.len(),
            evaluations,
            starts_at_best: at_best,
            spread_rel,
            best_values: ends.into_iter().take(5).collect(),
        }
    }
}

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
