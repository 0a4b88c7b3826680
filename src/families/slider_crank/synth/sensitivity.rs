//! What each interval of the operating envelope costs (issue 33, item 3): the derivative of
//! the optimised worst case V* with respect to every interval end, so a designer sees which
//! tolerance or speed limit to tighten first.
//!
//! By the envelope theorem dV*/dθ = Σ λᵢ ∂gᵢ/∂θ at the optimum (λ the multipliers of the
//! active maxima): the design's own response to θ does not enter. It is computed here as the
//! central difference of two re-solves with the end moved by ±h (h = 10⁻³ of the interval, or
//! of the end's magnitude for a point interval) — the same number wherever V* is smooth in θ,
//! without reaching into the engine's multipliers, and right across a change of the active
//! set too, where the multipliers' formula gives one side only. Its error bound is the
//! re-solves' own (value errors and optimality gaps, over 2h) plus the change from the
//! difference over ±2h (the truncation). A kink of V* inside ±2h shows as a large error.
//! Opt-in (`[mechanism.envelope] sensitivities = true`): 4 re-solves per end.

use super::scene::{Scene, SolveError};
use super::solve::solve;

/// Which end of an interval.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum End {
    /// The lower end.
    Min,
    /// The upper end.
    Max,
}

/// One row of the sensitivity table.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Sensitivity {
    /// The parameter ([`super::Envelope::names`]).
    pub parameter: String,
    /// Which end moves.
    pub end: End,
    /// The end's value (SI: rad/s for the speed; kg or m added to the nominal otherwise).
    pub at: f64,
    /// dV*/d(end): the optimised worst case's change per unit of the end (the objective's
    /// unit per the parameter's SI unit).
    pub derivative: f64,
    /// Bound on its error (same unit).
    pub error: f64,
}

/// The worst case the scene's objective minimises, and its error (value error plus gap).
fn optimum(scene: &Scene) -> Result<(f64, f64), SolveError> {
    let out = solve(scene)?;
    let worst = out
        .envelope
        .as_ref()
        .and_then(|e| e.worst_for(scene.objective))
        .ok_or_else(|| SolveError::Numeric("the envelope's worst case was not evaluated".into()))?;
    Ok((worst.value, worst.error + out.gap.max(0.0)))
}

/// `scene` with the end `end` of parameter `i` moved by `d`, with no Monte Carlo check nor
/// front (they do not change the optimum).
fn moved(scene: &Scene, i: usize, end: End, d: f64) -> Scene {
    let mut s = scene.clone();
    s.pareto_points = 0;
    s.envelope.monte_carlo = 0;
    let r = s.envelope.range_mut(i);
    match end {
        End::Min => r.0 += d,
        End::Max => r.1 += d,
    }
    s
}

/// The sensitivity of the scene's optimised worst case to every interval end.
pub fn sensitivities(scene: &Scene) -> Result<Vec<Sensitivity>, SolveError> {
    let e = &scene.envelope;
    let mut rows = Vec::new();
    for (i, (name, (lo, hi))) in e.names().into_iter().zip(e.ranges()).enumerate() {
        let width = hi - lo;
        for (end, at) in [(End::Min, lo), (End::Max, hi)] {
            let h = if width > 0.0 {
                1e-3 * width
            } else {
                1e-3 * at.abs().max(1e-6)
            };
            let v = |d: f64| optimum(&moved(scene, i, end, d));
            let ((p1, e1), (m1, f1)) = (v(h)?, v(-h)?);
            let ((p2, e2), (m2, f2)) = (v(2.0 * h)?, v(-2.0 * h)?);
            let d1 = (p1 - m1) / (2.0 * h);
            let d2 = (p2 - m2) / (4.0 * h);
            rows.push(Sensitivity {
                parameter: name.clone(),
                end,
                at,
                derivative: d1,
                error: (d1 - d2).abs() + (e1 + f1) / (2.0 * h) + (e2 + f2) / (4.0 * h),
            });
        }
    }
    Ok(rows)
}
