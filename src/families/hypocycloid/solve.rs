//! The hypocycloid's whole solve: the coefficients, balancing and searches ([`hy::solve`]),
//! then, where the file gives the bodies and the gas cycle, the dynamics at the reported
//! design — the rotating-mass counterweights (closed form, or the certified minimax of the
//! whole shaking force), the drive torque and the shafts' couples ([`balance::solve`]), and
//! the named load cases' torques and drives ([`load_cases::solve`]) — every number the result
//! reports.

use super::balance::{self, At, DynamicsOutcome};
use super::file::HypocycloidProblem;
use super::load_cases::{self, LoadCasesOutcome};
use super::model::{Coefficients, Hypocycloid};
use super::synth::{self as hy, OptStatus, Outcome};
use crate::families::driver::Claim;
use crate::report::Status;
use std::fmt::Write as _;

/// Every number of a solved hypocycloid scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// What the solve claims: `best_found` for the multistart Nelder–Mead, `inaccurate` where
    /// the coefficients did not converge, `degenerate` with its reason; the method (without
    /// its zero-search part when none ran), the search's evidence, the bounds, the warnings.
    pub claim: Claim,
    /// The coefficients, balancing pairs, zero curve and searches.
    pub out: Outcome,
    /// The dynamics at the reported design, where the file asks for any (`Err`: why they
    /// failed, which fails the result).
    pub dynamics: Option<Result<DynamicsOutcome, String>>,
    /// The load cases' torques and drives beside the dynamics' nominal ones
    /// (`[[mechanism.load_cases]]`).
    pub load_cases: Option<LoadCasesOutcome>,
}

/// Solves the scene: the synthesis, then the dynamics at its design.
pub fn solve(p: &HypocycloidProblem) -> Result<Solution, String> {
    let out = hy::solve(&p.scene, &p.settings).map_err(|e| e.to_string())?;
    let (dynamics, load_cases) = match p.dynamics.any().then(|| dynamics(p, &out)) {
        None => (None, None),
        Some(Ok((d, lc))) => (Some(Ok(d)), lc),
        Some(Err(e)) => (Some(Err(e)), None),
    };
    Ok(Solution {
        claim: claim(&out),
        out,
        dynamics,
        load_cases,
    })
}

/// What the solve claims of its design.
fn claim(out: &Outcome) -> Claim {
    // Nelder–Mead from a few starts is a heuristic search: `best_found` with its evidence.
    let mut status = match out.status {
        OptStatus::Analysis => Status::Analysed,
        OptStatus::Converged => Status::BestFound,
        OptStatus::MaxIterations => Status::Inaccurate,
        OptStatus::Infeasible => Status::Infeasible,
    };
    if !out.coefficients.converged && matches!(status, Status::Analysed | Status::BestFound) {
        status = Status::Inaccurate;
    }
    let mut detail = kebab(out.status);
    if let Some(d) = &out.degenerate {
        status = Status::Degenerate;
        let _ = write!(detail, "; degenerate: {d}");
    }
    if let Some(z) = &out.zero_search {
        let _ = write!(detail, "; zero search: {}", kebab(z.status));
    }
    let method = if out.zero_search.is_some() {
        out.method.clone()
    } else {
        // No zero search ran: drop its part of the method text.
        out.method
            .split("; ")
            .filter(|p| !p.starts_with("zero search"))
            .collect::<Vec<_>>()
            .join("; ")
    };
    Claim {
        status,
        status_detail: Some(detail),
        method,
        search: out.search.clone(),
        bounds: out.bounds.clone(),
        warnings: out.warnings.clone(),
        infeasibility: Vec::new(),
    }
}

/// A serde enum value's spelling (`best-found`), as the result writes it.
pub fn kebab<T: serde::Serialize>(v: T) -> String {
    serde_json::to_value(v)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}

/// The rotating counterweights, drive torque and couples at the design of `out`, and the
/// load cases' torques and drives.
fn dynamics(
    p: &HypocycloidProblem,
    out: &Outcome,
) -> Result<(DynamicsOutcome, Option<LoadCasesOutcome>), String> {
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
    let mut d = balance::solve(&p.dynamics, &at).map_err(|e| e.to_string())?;
    let lc = load_cases::solve(&p.dynamics, &at, &mut d).map_err(|e| e.to_string())?;
    Ok((d, lc))
}

/// The file-only analyses: none for the hypocycloid.
pub type Analyses = ();

/// See [`Analyses`].
pub fn analyse(_: &HypocycloidProblem, _: &Solution) -> Analyses {}
