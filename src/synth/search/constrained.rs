//! A shape search written once for every family (issue 36): over a box of geometry
//! parameters x, the least kinematic error e(x), and the least objective f(x) (a certified
//! inner optimum: the balancing of that geometry) with e(x) ≤ ε — the ε-constraint method
//! whose ends over several ε are the front of kinematic error against balance.
//!
//! A multistart: Halton points of the box ranked by their cost, the best distinct ones as
//! starts of argmin's Nelder–Mead ([`super::nelder_mead`]), the starts run in parallel
//! (rayon, results in the starts' order: the same answer whatever the thread count). The
//! constraint enters as a barrier the search cannot cross downhill: a point with e(x) > ε
//! costs [`INFEASIBLE`] plus its excess, above every admissible point's f(x)/f_ref. Nothing
//! here proves a global optimum, so its ends are `best_found` with their
//! [`SearchEvidence`].

use super::starts::{distance, distinct_starts, halton_points, ranked};
use super::{nelder_mead, NelderMead, SameBasin, SearchEvidence};
use rayon::prelude::*;

/// A geometry problem: the box of its parameters, the kinematic error and the balanced
/// objective of a geometry.
pub trait Shape: Sync {
    /// (lo, hi) of each parameter (SI), lo < hi.
    fn bounds(&self) -> &[(f64, f64)];
    /// The kinematic error e(x) (SI, ≥ 0); `None` where the geometry is not admissible
    /// (it does not assemble over the whole turn).
    fn error(&self, x: &[f64]) -> Option<f64>;
    /// The objective f(x) > 0 of the geometry's certified inner optimum (SI); `None` where
    /// the inner program is not solved to a certificate.
    fn objective(&self, x: &[f64]) -> Option<f64>;
    /// The bound e(x) ≤ ε in words for the search's evidence, with its unit ("the path
    /// error 0.5 mm"); by default the bare number, SI.
    fn bound_text(&self, eps: f64) -> String {
        format!("the kinematic error {eps:e} (SI)")
    }
}

/// The search's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Halton points of the box ranked for the starts.
    pub halton: usize,
    /// Local searches (at most; fewer where the ranked points are not distinct).
    pub starts: usize,
    /// Nelder–Mead iterations per local search.
    pub max_iters: u64,
    /// Nelder–Mead's stop: the standard deviation of the simplex's costs.
    pub sd_tolerance: f64,
}

/// The cost of a point that breaks the constraint or is not admissible, before its excess
/// is added: above every admissible point's f/f_ref for any f within 100× the reference.
pub const INFEASIBLE: f64 = 100.0;

/// Where a search ended: the best parameters, their kinematic error and objective, and what
/// the search did.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    /// The parameters (SI).
    pub x: Vec<f64>,
    /// e(x).
    pub error: f64,
    /// f(x) (`None` for the kinematic search where it was not computed or not certified).
    pub objective: Option<f64>,
    /// The evidence of the multistart.
    pub evidence: SearchEvidence,
}

/// x of the unit-box point u (each coordinate clamped to [0, 1] first).
fn unmap(bounds: &[(f64, f64)], u: &[f64]) -> Vec<f64> {
    u.iter()
        .zip(bounds)
        .map(|(&v, &(lo, hi))| lo + v.clamp(0.0, 1.0) * (hi - lo))
        .collect()
}

/// How far u lies outside the unit box (0 inside): the penalty that keeps the simplex in.
fn outside(u: &[f64]) -> f64 {
    u.iter().map(|&v| (-v).max(v - 1.0).max(0.0)).sum()
}

/// A start's simplex in the unit box: the start and a step of 0.08 along each axis, towards
/// the box's inside.
fn simplex(u: &[f64]) -> Vec<Vec<f64>> {
    let mut s = vec![u.to_vec()];
    for i in 0..u.len() {
        let mut v = u.to_vec();
        v[i] += if u[i] > 0.5 { -0.08 } else { 0.08 };
        s.push(v);
    }
    s
}

/// The multistart of a cost over the unit box: the Halton points and `seeds` (unit-box
/// points, e.g. a neighbouring front point) ranked, the distinct best `starts` searched by
/// Nelder–Mead in parallel. The ends (u, cost) in the starts' order and the evaluations.
fn multistart(
    cost: &(dyn Fn(&[f64]) -> f64 + Sync),
    dim: usize,
    seeds: &[Vec<f64>],
    s: &Settings,
) -> (Vec<(Vec<f64>, f64)>, usize) {
    let mut points = halton_points(s.halton, dim);
    points.extend(seeds.iter().cloned());
    let costs: Vec<f64> = points.par_iter().map(|u| cost(u)).collect();
    let evaluations = points.len();
    let pool = ranked(points.into_iter().zip(costs).collect());
    let starts = distinct_starts(&pool, s.starts, f64::is_finite, |a, b| {
        distance(a, b) > 0.05
    });
    let boxed = |u: &[f64]| cost(u) + INFEASIBLE * outside(u);
    let ends: Vec<(Vec<f64>, f64, usize)> = starts
        .par_iter()
        .map(|u| {
            let settings = NelderMead {
                simplex: simplex(u),
                sd_tolerance: s.sd_tolerance,
                max_iters: s.max_iters,
            };
            match nelder_mead(&boxed, &settings) {
                Ok(end) => {
                    let v = boxed(&end.x);
                    (end.x, v, end.evaluations + 1)
                }
                Err(_) => (u.clone(), boxed(u), 1),
            }
        })
        .collect();
    let evaluations = evaluations + ends.iter().map(|e| e.2).sum::<usize>();
    (
        ends.into_iter().map(|(u, v, _)| (u, v)).collect(),
        evaluations,
    )
}

/// The best end of a multistart with its evidence (ends within 1e-6 relative, or within
/// 1e-3 of the box's span in every coordinate, are one basin); `None` without an end below
/// `admit`.
fn best(
    method: String,
    ends: Vec<(Vec<f64>, f64)>,
    evaluations: usize,
    admit: f64,
) -> Option<(Vec<f64>, SearchEvidence)> {
    let starts = ends.len();
    let spans = vec![1.0; ends.first().map_or(0, |e| e.0.len())];
    let admitted: Vec<(Vec<f64>, f64)> = ends.into_iter().filter(|e| e.1 < admit).collect();
    let u = admitted
        .iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))?
        .0
        .clone();
    let same = SameBasin {
        rel: 1e-6,
        point: Some((&spans, 1e-3)),
    };
    let evidence = SearchEvidence::of_ends(method, admitted, starts, evaluations, &same, 1.0);
    Some((u, evidence))
}

/// The unit-box points of the parameters `seeds` (SI).
fn to_unit(b: &[(f64, f64)], seeds: &[Vec<f64>]) -> Vec<Vec<f64>> {
    seeds
        .iter()
        .map(|x| {
            x.iter()
                .zip(b)
                .map(|(&v, &(lo, hi))| (v - lo) / (hi - lo))
                .collect()
        })
        .collect()
}

/// The least kinematic error over the box (`None`: no admissible point found), searched
/// from the Halton points and the `seeds` (parameters, SI: e.g. the file's geometry), its
/// objective left for the caller.
pub fn least_error(shape: &dyn Shape, seeds: &[Vec<f64>], s: &Settings) -> Option<Found> {
    let b = shape.bounds();
    let cost = |u: &[f64]| shape.error(&unmap(b, u)).unwrap_or(f64::INFINITY);
    let (ends, evaluations) = multistart(&cost, b.len(), &to_unit(b, seeds), s);
    let method = format!(
        "least kinematic error: Halton {} + Nelder–Mead (argmin) from {} starts",
        s.halton, s.starts
    );
    let (u, evidence) = best(method, ends, evaluations, f64::INFINITY)?;
    let x = unmap(b, &u);
    Some(Found {
        error: shape.error(&x)?,
        x,
        objective: None,
        evidence,
    })
}

/// The least objective f(x) with e(x) ≤ `eps` over the box, searched from the Halton points
/// and the `seeds` (parameters, SI: e.g. the least-error geometry), f scaled by `f_ref` in
/// the cost. `None` when no point within the constraint was found.
pub fn least_objective(
    shape: &dyn Shape,
    eps: f64,
    f_ref: f64,
    seeds: &[Vec<f64>],
    s: &Settings,
) -> Option<Found> {
    let b = shape.bounds();
    let cost = |u: &[f64]| {
        let x = unmap(b, u);
        match shape.error(&x) {
            None => f64::INFINITY,
            Some(e) if e > eps => INFEASIBLE + (e - eps) / eps,
            Some(_) => shape
                .objective(&x)
                .map_or(INFEASIBLE, |f| (f / f_ref).min(INFEASIBLE)),
        }
    };
    let (ends, evaluations) = multistart(&cost, b.len(), &to_unit(b, seeds), s);
    let method = format!(
        "least objective with {} at most: Halton {} + Nelder–Mead (argmin) from {} starts, the constraint as a barrier",
        shape.bound_text(eps),
        s.halton, s.starts
    );
    let (u, mut evidence) = best(method, ends, evaluations, INFEASIBLE)?;
    for v in &mut evidence.best_values {
        *v *= f_ref;
    }
    let x = unmap(b, &u);
    Some(Found {
        error: shape.error(&x)?,
        objective: Some(shape.objective(&x)?),
        x,
        evidence,
    })
}
