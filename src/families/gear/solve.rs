//! The eccentric gear's whole solve ([`sg::solve`]: the closure, the transmission, the
//! sliding coefficients with every pole, the tooth profiles and the eccentricity design) —
//! every number the result reports.

use super::file::GearProblem;
use super::synth::{self as sg, Outcome};

/// Every number of a solved gear scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The analysis (and design) of the pair.
    pub out: Outcome,
}

/// Solves the scene.
pub fn solve(p: &GearProblem) -> Result<Solution, String> {
    let out = sg::solve(&p.gear, &p.settings).map_err(|e| e.to_string())?;
    Ok(Solution { out })
}

/// The file-only analyses: none for the gear.
pub type Analyses = ();

/// See [`Analyses`].
pub fn analyse(_: &GearProblem, _: &Solution) -> Analyses {}
