//! Synthesis: design vectors with bounds, objectives and the solvers that optimise them.
//!
//! A design variable is either fixed or free within bounds ([`Var`]), so the same scene
//! serves analysis (everything fixed) and synthesis.

pub(crate) mod conic;
pub mod counterweight;
pub mod energy;
pub mod envelope;
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

/// A limit that no design within the design variables' bounds meets, and how far off it is:
/// the value of the limited quantity closest to the limit that any design within the bounds
/// reaches — the least for an upper limit — with every other limit left out (JSON key
/// `infeasibility`, one entry per limit of an `infeasible` result). The designer relaxes the
/// limit to at least that, or widens the bounds. `certified` says whether that value is
/// proven (a convex solve) or only the best a heuristic search found.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Shortfall {
    /// The key of the limit (the problem file's, e.g. `objective.max_peak_force`, or the
    /// result's check, e.g. `checks.reach_max`).
    pub limit: String,
    /// What it limits, in words (e.g. `peak shaking force`).
    pub quantity: String,
    /// `at_most` (the quantity must not exceed the limit) or `at_least`.
    pub sense: Sense,
    /// The limit (SI).
    pub value: f64,
    /// The value of the quantity closest to the limit that a design within the bounds
    /// reaches (SI): the least for `at_most`, the greatest for `at_least`.
    pub closest: f64,
    /// Bound on the error of `closest` (SI): the certificate's gap and round-off (0 when not
    /// certified).
    pub error: f64,
    /// Whether `closest` is proven (the certified optimum of that quantity alone), or only
    /// what the best design of a heuristic search reaches.
    pub certified: bool,
    /// The SI unit of `value`, `closest` and `error`.
    pub unit: String,
}

/// The sense of a limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Sense {
    /// quantity ≤ limit.
    AtMost,
    /// quantity ≥ limit.
    AtLeast,
}

impl Shortfall {
    /// An upper limit `key` = `value` on `quantity`, whose least reachable value is
    /// certified to be `closest` ± `error` (SI, `unit`).
    pub fn at_most(
        key: &str,
        quantity: &str,
        value: f64,
        closest: f64,
        error: f64,
        unit: &str,
    ) -> Self {
        Shortfall {
            limit: key.into(),
            quantity: quantity.into(),
            sense: Sense::AtMost,
            value,
            closest,
            error,
            certified: true,
            unit: unit.into(),
        }
    }

    /// How far `closest` lies beyond the limit (SI; ≤ `error` when the limit alone is
    /// within reach).
    pub fn excess(&self) -> f64 {
        match self.sense {
            Sense::AtMost => self.closest - self.value,
            Sense::AtLeast => self.value - self.closest,
        }
    }

    /// Whether the limit alone is within reach (then only the combination of limits is not).
    pub fn reachable_alone(&self) -> bool {
        self.excess() <= self.error
    }

    /// The shortfall in words, for the status detail and the warnings.
    pub fn describe(&self) -> String {
        let (key, q) = (&self.limit, &self.quantity);
        let val = |x: f64| {
            let s = format!("{x:.6}");
            let s = s.trim_end_matches('0').trim_end_matches('.');
            if self.unit.is_empty() {
                s.to_string()
            } else {
                format!("{s} {}", self.unit)
            }
        };
        let (v, c) = (val(self.value), val(self.closest));
        let (least, bound) = match self.sense {
            Sense::AtMost => ("least", "at most"),
            Sense::AtLeast => ("greatest", "at least"),
        };
        let limit = format!("{key} ({q} {bound} {v})");
        if !self.certified {
            return format!(
                "{limit} is not met: the best design the search found reaches {c}, {} beyond \
                 the limit (a heuristic search: not a proof that no design meets it)",
                val(self.excess())
            );
        }
        let err = format!("{:.1e}", self.error);
        if self.reachable_alone() {
            format!(
                "{limit} is reachable alone (the {least} {q} within the bounds is {c} ± {err}) \
                 but not together with the other limits"
            )
        } else {
            format!(
                "{limit} cannot be met: the {least} {q} any design within the bounds reaches \
                 is {c} ± {err}, {:.1} % beyond the limit; relax the limit to that, or widen \
                 the design's bounds",
                100.0 * self.excess() / self.value.abs().max(f64::MIN_POSITIVE)
            )
        }
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
