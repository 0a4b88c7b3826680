//! The hypocycloid's whole solve: the coefficients, balancing and searches ([`hy::solve`]),
//! then, where the file gives the bodies and the gas cycle, the dynamics at the reported
//! design — the rotating-mass counterweights (closed form, or the certified minimax of the
//! whole shaking force), the drive torque and the shafts' couples ([`balance::solve`]) —
//! every number the result reports.

use super::balance::{self, At, DynamicsOutcome};
use super::file::HypocycloidProblem;
use super::model::{Coefficients, Hypocycloid};
use super::synth::{self as hy, Outcome};

/// Every number of a solved hypocycloid scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The coefficients, balancing pairs, zero curve and searches.
    pub out: Outcome,
    /// The dynamics at the reported design, where the file asks for any (`Err`: why they
    /// failed, which fails the result).
    pub dynamics: Option<Result<DynamicsOutcome, String>>,
}

/// Solves the scene: the synthesis, then the dynamics at its design.
pub fn solve(p: &HypocycloidProblem) -> Result<Solution, String> {
    let out = hy::solve(&p.scene, &p.settings).map_err(|e| e.to_string())?;
    let dynamics = p.dynamics.any().then(|| dynamics(p, &out));
    Ok(Solution { out, dynamics })
}

/// The rotating counterweights, drive torque and couples at the design of `out`.
fn dynamics(p: &HypocycloidProblem, out: &Outcome) -> Result<DynamicsOutcome, String> {
    let h = &p.scene;
    let m = Hypocycloid {
        lambda: out.design.lambda,
        theta: out.design.theta,
        alpha0: h.alpha0,
    };
    let c = &out.coefficients;
    let coef = Coefficients {
        a: c.a.clone(),
        b: c.b.clone(),
        err: c.error.clone(),
        n_fft: c.n_fft,
        converged: c.converged,
    };
    let at = At {
        model: &m,
        coef: &coef,
        orders: &h.balance_orders,
        pairs: &out.balancing,
        r_carrier: h.r_carrier,
        m_b: h.m_b,
        omega: h.omega,
        plot_samples: p.settings.plot_samples,
    };
    balance::solve(&p.dynamics, &at).map_err(|e| e.to_string())
}

/// The file-only analyses: none for the hypocycloid.
pub type Analyses = ();

/// See [`Analyses`].
pub fn analyse(_: &HypocycloidProblem, _: &Solution) -> Analyses {}
