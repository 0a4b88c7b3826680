//! The luffing crane's whole solve: the linkage synthesis and its search ([`cr::solve`]),
//! then, where the scene has them, the boom system's statics at the reported design — the
//! load's path with an inclined hoist rope, and the drive torque, member forces and the boom
//! counterweight ([`balance::solve`], a certified SOCP) — every number the result reports.
//! The Δh landscape, a diagnostic grid only the result's files carry, is
//! [`analyse`]'s.

use super::balance;
use super::file::CraneProblem;
use super::synth::{self as cr, Landscape};

/// Series points of the balance's table and plots.
const BALANCE_SAMPLES: usize = 120;

/// Every number of a solved crane scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The synthesis: design, objectives, checks, path, search evidence.
    pub out: cr::Outcome,
    /// The boom system's statics at the reported design, where the scene asks for them
    /// (`mechanism.self_weight`, `design.counterweight`, `mechanism.hoist_rope`) and the
    /// design has positions: `Err` says why the linkage could not be built for them.
    pub statics: Option<Result<Statics, String>>,
}

/// The boom system's statics at the reported design.
#[derive(Debug, Clone)]
pub struct Statics {
    /// With an inclined hoist rope: the load's path (`None` inside: it could not be
    /// evaluated).
    pub rope: Option<Option<balance::LoadPath>>,
    /// With the boom system's masses: the drive torque, member forces and the counterweight,
    /// or why they could not be computed.
    pub masses: Option<Result<balance::Balance, String>>,
}

impl Solution {
    /// The statics' balance, where it was computed.
    pub fn balance(&self) -> Option<&balance::Balance> {
        match &self.statics {
            Some(Ok(Statics {
                masses: Some(Ok(b)),
                ..
            })) => Some(b),
            _ => None,
        }
    }
}

/// Solves the scene: the synthesis, then the statics at its design.
pub fn solve(p: &CraneProblem) -> Result<Solution, String> {
    let out = cr::solve(&p.scene, &p.settings).map_err(|e| e.to_string())?;
    let statics = statics(p, &out);
    Ok(Solution { out, statics })
}

/// The statics at the design `out.x`, where the scene asks for them and the design has
/// positions.
fn statics(p: &CraneProblem, out: &cr::Outcome) -> Option<Result<Statics, String>> {
    let (cs, set) = (&p.scene, &p.settings);
    let bs = cs.balance.as_ref()?;
    out.positions.as_ref()?;
    let link = match cr::build(cs, &out.x) {
        Ok((_, syn)) => syn.linkage,
        Err(e) => return Some(Err(e.to_string())),
    };
    let rope = bs
        .rope
        .as_ref()
        .map(|rope| balance::load_path(&link, rope, set.path_samples, 1e-9));
    let masses = bs.masses.then(|| {
        balance::solve(
            &link,
            bs,
            cs.foot_offset,
            &crate::synth::minimax::Settings::default(),
            BALANCE_SAMPLES,
        )
        .map_err(|e| e.to_string())
    });
    Some(Ok(Statics { rope, masses }))
}

/// The file-only analyses: the Δh landscape over (k1, k2) (`landscape.k1_points` > 0), a
/// diagnostic grid of full evaluations (~99 % of an analysis), computed only when the result's
/// files are written.
pub type Analyses = Option<Landscape>;

/// See [`Analyses`].
pub fn analyse(p: &CraneProblem, sol: &Solution) -> Analyses {
    if p.settings.landscape_k1 == 0 {
        return None;
    }
    cr::landscape(&p.scene, &p.settings, &sol.out.x)
}
