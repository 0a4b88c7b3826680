//! Pareto fronts: min peak A subject to peak B ≤ ε for a list of ε, each point its own
//! certified solve, continued in ε from its neighbour. A front is computed only between ends
//! that did not spend every exchange round, and it ends after two points in a row that did: the
//! rounds a front spends are bounded, and few of them on a front that cannot certify.

use super::polish::KktStart;
use super::{Engine, Goal, MinimaxError, ParetoFront, ParetoPoint, Solution, Stop};
use crate::synth::exchange::{is_new, Status};

impl<'p, 'a> Engine<'p, 'a> {
    /// Min peak of field `a` subject to peak of field `b` ≤ ε, for each ε (plus the problem's
    /// own limits); each point first tries Newton from the last polished point's optimality
    /// conditions (a continuation in ε, no SOCP), else runs the exchange loop warm-started
    /// from the previous point's final angles only. Stops after two points in a row that
    /// spent every round or failed: the ε after them are not solved (an ill-conditioned
    /// front would otherwise spend `max_rounds` rounds on every point; an infeasible point
    /// is cheap and certified, an `Inaccurate` one that stalled or ended with clarabel's
    /// reduced accuracy states its small gap, so the front goes on past them).
    pub fn pareto(
        &self,
        a: usize,
        b: usize,
        eps: &[f64],
        warm: Option<&[Vec<f64>]>,
    ) -> Result<Vec<ParetoPoint>, MinimaxError> {
        let mut out: Vec<ParetoPoint> = Vec::with_capacity(eps.len());
        let mut warm_sets: Option<Vec<Vec<f64>>> = warm.map(|w| w.to_vec());
        let mut start: Option<KktStart> = None;
        let mut spent_in_row = 0;
        for &e in eps {
            let mut limits = self.pb.limits.clone();
            limits.push((b, e));
            // Newton first from the previous point's polished optimality conditions (a
            // continuation in ε), then the exchange loop from its angles.
            let (sol, st) = self.solve_goal_from(
                &Goal::MinPeak(vec![(a, 1.0)]),
                &limits,
                warm_sets.as_deref(),
                start.as_ref(),
            )?;
            if st.is_some() {
                start = st;
            }
            if sol.status != Status::Infeasible && sol.status != Status::Failed {
                // Only the previous point's (pruned) angles: merged sets would grow to
                // hundreds of cones over a front.
                warm_sets = Some(sol.angle_sets.clone());
            }
            // Two points in a row that spent every round: the rest of the front would too.
            spent_in_row = if spent(&sol) { spent_in_row + 1 } else { 0 };
            let stop = spent_in_row == 2;
            out.push(ParetoPoint {
                eps: e,
                solution: sol,
            });
            if stop {
                break;
            }
        }
        Ok(out)
    }

    /// The front of peak A against peak B in `n` ≥ 2 points: the two single-field optima
    /// bound it, and no point is computed when either is [`unusable_end`]; ε runs evenly
    /// from B* (the min-B peak, raised by 10 `rel_tol` so the first point is feasible
    /// despite the gap) to the peak B of the min-A design.
    pub fn pareto_front(&self, a: usize, b: usize, n: usize) -> Result<ParetoFront, MinimaxError> {
        let n = n.max(2);
        let min_b = self.solve_goal(&Goal::MinPeak(vec![(b, 1.0)]), &self.pb.limits, None)?;
        let min_a = self.solve_goal(&Goal::MinPeak(vec![(a, 1.0)]), &self.pb.limits, None)?;
        if unusable_end(&min_b) || unusable_end(&min_a) {
            return Ok(ParetoFront {
                points: Vec::new(),
                requested: n,
                min_b,
                min_a,
            });
        }
        let lo = min_b.peaks[b].peak * (1.0 + 10.0 * self.s.rel_tol) + min_b.peaks[b].error;
        let hi = min_a.peaks[b].peak.max(lo);
        let eps: Vec<f64> = (0..n)
            .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
            .collect();
        let warm = merge_sets(Some(&min_b.angle_sets), &min_a.angle_sets);
        let points = self.pareto(a, b, &eps, Some(&warm))?;
        Ok(ParetoFront {
            requested: n,
            min_b,
            min_a,
            points,
        })
    }
}

/// Whether a solve spent its every round (`max_rounds`) or failed: the points after it, or a
/// front between such ends, would spend as much each.
fn spent(s: &Solution) -> bool {
    s.stop == Stop::MaxRounds || s.status == Status::Failed
}

/// Whether an end of a front (the least of one peak alone) leaves no front to compute: it
/// has no design, or it spent every round (such ends leave thousands of angles to warm-start
/// from: each point would then take seconds for a front that would not certify either).
pub(super) fn unusable_end(s: &Solution) -> bool {
    spent(s) || s.status == Status::Infeasible
}

/// Per field, the union of two angle sets (sorted, near-duplicates dropped).
fn merge_sets(a: Option<&[Vec<f64>]>, b: &[Vec<f64>]) -> Vec<Vec<f64>> {
    (0..b.len())
        .map(|f| {
            let mut v: Vec<f64> = a.and_then(|a| a.get(f)).cloned().unwrap_or_default();
            for &t in &b[f] {
                if is_new(&v, t) {
                    v.push(t);
                }
            }
            v.sort_by(f64::total_cmp);
            v
        })
        .collect()
}
