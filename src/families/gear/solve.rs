//! The eccentric gear's whole solve ([`sg::solve`]: the closure, the transmission, the
//! sliding coefficients with every pole, the tooth profiles and the eccentricity design) —
//! every number the result reports.

use super::file::GearProblem;
use super::synth::{self as sg, Outcome};
use crate::families::driver::Claim;
use crate::report::Status;

/// Every number of a solved gear scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// What the solve claims: `best_found` for a designed e (a sampled sweep and Brent, not a
    /// certificate), the finer detail, the method, the evidence, the warnings.
    pub claim: Claim,
    /// The analysis (and design) of the pair.
    pub out: Outcome,
}

/// Solves the scene.
pub fn solve(p: &GearProblem) -> Result<Solution, String> {
    let out = sg::solve(&p.gear, &p.settings).map_err(|e| e.to_string())?;
    Ok(Solution {
        claim: claim(&out),
        out,
    })
}

/// What the solve claims of its design.
fn claim(out: &Outcome) -> Claim {
    let status = match out.status {
        sg::Status::Analysed => Status::Analysed,
        // A sampled sweep + Brent is a heuristic search, not a certificate.
        sg::Status::Optimal | sg::Status::ConstraintBound | sg::Status::AtBound => {
            Status::BestFound
        }
        sg::Status::Infeasible => Status::Infeasible,
    };
    let mut c = Claim::new(status, out.method.clone());
    c.status_detail = Some(status_detail(out.status).into());
    c.search = out.search.clone();
    c.warnings = out.warnings.clone();
    c
}

/// The family's finer status, in words.
fn status_detail(s: sg::Status) -> &'static str {
    match s {
        sg::Status::Analysed => "analysed",
        sg::Status::Optimal => "interior-optimum",
        sg::Status::ConstraintBound => "constraint-bound",
        sg::Status::AtBound => "at-bound",
        sg::Status::Infeasible => "infeasible",
    }
}

/// The file-only analyses: none for the gear.
pub type Analyses = ();

/// See [`Analyses`].
pub fn analyse(_: &GearProblem, _: &Solution) -> Analyses {}
