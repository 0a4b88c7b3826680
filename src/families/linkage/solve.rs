//! The linkage's whole solve: the counterweights ([`ls::solve`]: the certified minimax, RMS,
//! lightest or full-balance program and its front), each counterweight realised as an annular
//! sector about its joint, every joint's Newton–Euler load over the cycle without and with
//! them, and the Berkof–Lowen closed form of a four-bar — every number the result reports.

use super::file::LinkageProblem;
use super::model::ForceBalance;
use super::synth::{self as ls, JointPeak, Outcome};
use crate::synth::shape::sector_realising;

/// Every number of a solved linkage scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The counterweights, the bare and balanced fields, the front.
    pub out: Outcome,
    /// Per counterweight of the design with a mass, the annular sector (rᵢ, rₒ, θ) about its
    /// joint that has its mass, centroid and inertia within its envelope (`None`: no sector
    /// does, or no mass).
    pub sectors: Vec<Option<(f64, f64, f64)>>,
    /// The joints' peak loads, or why they could not be computed.
    pub joints: Result<JointLoads, String>,
    /// A four-bar's full force balance in closed form (Berkof–Lowen), where the linkage is one.
    pub berkof_lowen: Option<ForceBalance>,
}

/// Every joint's peak load over the cycle.
#[derive(Debug, Clone)]
pub struct JointLoads {
    /// Without counterweights.
    pub bare: Vec<JointPeak>,
    /// With the design's counterweights (absent without a design; `Err`: why not computed).
    pub design: Option<Result<Vec<JointPeak>, String>>,
}

impl Solution {
    /// The design vector, where there is a design and all of it is finite.
    pub fn design_x(&self) -> Option<&[f64]> {
        self.out
            .design
            .as_ref()
            .map(|s| s.x.as_slice())
            .filter(|x| x.iter().all(|v| v.is_finite()))
    }
}

/// Solves the scene: the counterweights, their sectors, the joint loads, Berkof–Lowen.
pub fn solve(p: &LinkageProblem) -> Result<Solution, String> {
    let sc = &p.scene;
    let out = ls::solve(sc, &p.settings).map_err(|e| e.to_string())?;
    let sectors = match &out.design {
        Some(sol) => (0..sc.counterweights.len())
            .map(|j| {
                let d = sol.counterweight(j);
                let envelope = sc.counterweights[j].radius;
                (d.mass > 0.0)
                    .then(|| sector_realising(d.mass, d.radius, d.inertia, envelope))
                    .flatten()
            })
            .collect(),
        None => Vec::new(),
    };
    let mut sol = Solution {
        out,
        sectors,
        joints: Err(String::new()),
        berkof_lowen: sc.linkage.berkof_lowen().ok(),
    };
    sol.joints = joint_loads(p, sol.design_x());
    Ok(sol)
}

/// The joints' peak loads without counterweights and with the design `x`.
fn joint_loads(p: &LinkageProblem, x: Option<&[f64]>) -> Result<JointLoads, String> {
    let sc = &p.scene;
    let zeros = vec![0.0; crate::synth::minimax::PER_COUNTERWEIGHT * sc.counterweights.len()];
    let bare = ls::joint_peaks(sc, &zeros, &p.settings).map_err(|e| e.to_string())?;
    let design = x.map(|x| ls::joint_peaks(sc, x, &p.settings).map_err(|e| e.to_string()));
    Ok(JointLoads { bare, design })
}

/// The file-only analyses: none for the linkage (its curves over the cycle are drawn with its
/// plots).
pub type Analyses = ();

/// See [`Analyses`].
pub fn analyse(_: &LinkageProblem, _: &Solution) -> Analyses {}
