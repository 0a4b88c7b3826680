//! The lightest design of an optimum that is not unique (issue 37): where Newton's polish
//! finds the optimal set flat ([`Solution::flat`]: a direction of the design along which the
//! optimality conditions hold), the design the exchange loop ended on is one arbitrary point
//! of that set — the six-bar press's coupler counterweight of 5 kg that buys nothing. A
//! second program picks the lightest point instead:
//!
//! min Σ m_j  s.t.  w_f |g_f(θ; x)| ≤ V (every objective field), the problem's limits,
//!
//! with V the first solve's certified peak, warm-started from its angles. Its design is
//! re-certified against the first solve's lower bound ([`Engine::moved`]), and replaces the
//! first only if it stays `optimal` and is lighter by more than 1e-6 of the mass.

use super::{var_m, Engine, Goal, MinimaxError, Solution, Status};

/// The masses Σ m_j of the first design and of the lightest one that replaced it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lighter {
    /// Σ m_j of the exchange loop's design (kg).
    pub first: f64,
    /// Σ m_j of the lightest optimal design (kg).
    pub lightest: f64,
}

impl Engine<'_, '_> {
    /// The lightest design of `sol`'s optimal set where the polish found that set flat
    /// (module doc), with the two masses; `sol` itself, and `None`, where the goal is not a
    /// peak, the claim is not `optimal`, the set is not flat, or no lighter design certifies.
    pub fn lightest_of_optimum(
        &self,
        sol: Solution,
    ) -> Result<(Solution, Option<Lighter>), MinimaxError> {
        let Goal::MinPeak(list) = &self.pb.goal else {
            return Ok((sol, None));
        };
        let n_cw = self.pb.counterweights.len();
        if !sol.flat || sol.status != Status::Optimal || n_cw == 0 {
            return Ok((sol, None));
        }
        let mut limits = self.pb.limits.clone();
        limits.extend(list.iter().map(|&(f, w)| (f, sol.objective / w)));
        let light = self.solve_goal(&Goal::MinMass, &limits, Some(&sol.angle_sets))?;
        let mass = |x: &[f64]| (0..n_cw).map(|j| x[var_m(j)]).sum::<f64>();
        let (first, lightest) = (mass(&sol.x), mass(&light.x));
        if light.status != Status::Optimal || !(lightest < first - 1e-6 * first) {
            return Ok((sol, None));
        }
        let moved = self.moved(&sol, &light.x, "the lightest design of the optimal set")?;
        if moved.status != Status::Optimal {
            return Ok((sol, None));
        }
        Ok((moved, Some(Lighter { first, lightest })))
    }
}
