//! The luffing crane's whole solve: the linkage synthesis and its search ([`cr::solve`]),
//! then, where the scene has them, the boom system's statics at the reported design — the
//! load's path with an inclined hoist rope, and the drive torque, member forces and the boom
//! counterweight ([`balance::solve`], a certified SOCP) and the luffing drive
//! ([`luffing::drive`]) — every number the result reports.
//! The Δh landscape, a diagnostic grid only the result's files carry, is
//! [`analyse`]'s.

use super::actuator;
use super::balance;
use super::file::CraneProblem;
use super::luffing;
use super::model::Level;
use super::stability;
use super::synth::{self as cr, Landscape, Status as CraneStatus};
use crate::families::driver::Claim;
use crate::report::Status;
use crate::synth::{ActiveBound, Sense, Shortfall};

/// Series points of the balance's table and plots.
const BALANCE_SAMPLES: usize = 120;

/// Every number of a solved crane scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// What the solve claims: the status (`best_found` for a multistart search), its finer
    /// detail, the method, the search's evidence, the free variables on a bound of their
    /// range, the synthesis's warnings.
    pub claim: Claim,
    /// The synthesis: design, objectives, checks, path, search evidence.
    pub out: cr::Outcome,
    /// The boom system's statics at the reported design, where the scene asks for them
    /// (`mechanism.self_weight`, `design.counterweight`, `mechanism.hoist_rope`) and the
    /// design has positions: `Err` says why the linkage could not be built for them.
    pub statics: Option<Result<Statics, String>>,
    /// With `minimize = "load-delta-h"`: the baseline the thesis's §2.1 method gives, the
    /// same scene searched for a level head, with its load's path on the same rope.
    pub level_head: Option<LevelHead>,
}

/// The level-head design of a load-level scene, the baseline (`baselines.level_head`).
#[derive(Debug, Clone)]
pub struct LevelHead {
    /// Its synthesis: design, Δh of the head, the load moment with the rope.
    pub out: cr::Outcome,
    /// The load's path on the rope at that design (`None`: it could not be evaluated).
    pub load: Option<balance::LoadPath>,
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
    /// With the balance: the luffing drive (work, mean torque, and with a luffing time the
    /// power), or why it could not be computed.
    pub luffing: Option<Result<luffing::LuffingDrive, String>>,
    /// With the balance and `mechanism.stability`: the stability against tipping, or why it
    /// could not be computed.
    pub stability: Option<Result<stability::Stability, String>>,
    /// With the balance and `mechanism.luffing_actuator`: the actuators' forces, strokes and
    /// powers, or why they could not be computed.
    pub actuators: Option<Result<actuator::LuffingActuators, String>>,
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
    Ok(Solution {
        claim: claim(&p.scene, &out),
        out,
        statics,
        level_head: level_head(p),
    })
}

/// For a load-level scene, the same scene searched for a level head (the thesis's §2.1
/// synthesis, what the rope's sheave would be ignored by) and its load's path on the rope.
fn level_head(p: &CraneProblem) -> Option<LevelHead> {
    let Level::Load(rope) = p.scene.level else {
        return None;
    };
    let scene = cr::CraneScene {
        level: Level::Head,
        ..p.scene.clone()
    };
    let out = cr::solve(&scene, &p.settings).ok()?;
    let load = cr::build(&scene, &out.x).ok().and_then(|(_, syn)| {
        balance::load_path(&syn.linkage, &rope, p.settings.path_samples, 1e-9)
    });
    Some(LevelHead { out, load })
}

/// What the solve claims of its design.
fn claim(cs: &cr::CraneScene, out: &cr::Outcome) -> Claim {
    let status = match out.status {
        CraneStatus::Evaluated => Status::Analysed,
        CraneStatus::BestFound => Status::BestFound,
        CraneStatus::Degenerate => Status::Degenerate,
        CraneStatus::Infeasible => Status::Infeasible,
        CraneStatus::BranchDefect | CraneStatus::CannotAssemble | CraneStatus::NoGeometry => {
            Status::Failed
        }
    };
    let mut c = Claim::new(status, out.method.clone());
    c.status_detail = Some(status_detail(out.status).into());
    c.search = out.search.clone();
    c.warnings = out.warnings.clone();
    if status == Status::BestFound {
        c.bounds = range_bounds(cs, out);
    }
    if status == Status::Infeasible {
        c.status_detail = None;
        c.infeasible(failed_checks(out));
    }
    c
}

/// The checks the search's best design fails, as shortfalls: what it reaches against each
/// limit. The search is heuristic, so none is certified the closest a design can come.
fn failed_checks(out: &cr::Outcome) -> Vec<Shortfall> {
    out.checks
        .iter()
        .filter(|k| !k.pass)
        .map(|k| {
            // The note ends with the unit: "reach at phi_min … >= R_max (m)".
            let (quantity, unit) = match k.note.rsplit_once(" (") {
                Some((q, u)) if u.ends_with(')') => (q, u.trim_end_matches(')')),
                _ => (k.note.as_str(), ""),
            };
            (k, quantity.to_string(), unit.to_string())
        })
        .map(|(k, quantity, unit)| Shortfall {
            limit: format!("checks.{}", k.name),
            quantity,
            sense: if k.value > k.limit {
                Sense::AtMost
            } else {
                Sense::AtLeast
            },
            value: k.limit,
            closest: k.value,
            error: 0.0,
            certified: false,
            unit,
        })
        .collect()
}

/// The family's finer status, in words.
fn status_detail(s: CraneStatus) -> &'static str {
    match s {
        CraneStatus::Evaluated => "evaluated",
        CraneStatus::BestFound => {
            "best-found: multistart (Halton + SQP), not proven globally optimal"
        }
        CraneStatus::Infeasible => "infeasible",
        CraneStatus::BranchDefect => "branch-defect",
        CraneStatus::CannotAssemble => "cannot-assemble",
        CraneStatus::NoGeometry => "no-geometry",
        CraneStatus::Degenerate => "ill-conditioned: the rounding bound of delta h exceeds delta h",
    }
}

/// Free variables the search left on a bound of their range: the range decides them.
fn range_bounds(cs: &cr::CraneScene, out: &cr::Outcome) -> Vec<ActiveBound> {
    let mut bounds = Vec::new();
    let v = &out.design.vars;
    let free = [
        (
            "k1",
            "design.k1",
            &cs.k1,
            v.k1,
            "the middle design position C2 between C1 and C3",
        ),
        (
            "k2",
            "design.k2",
            &cs.k2,
            v.k2,
            "the jib tail over the jib head length",
        ),
        (
            "phi_min_rad",
            "design.phi_min",
            &cs.phi_min,
            v.phi_min_rad,
            "the boom elevation at maximum reach",
        ),
        (
            "gamma1_rad",
            "design.gamma1",
            &cs.gamma1,
            v.gamma1_rad,
            "the boom from vertical at minimum reach",
        ),
        (
            "gamma2_rad",
            "design.gamma2",
            &cs.gamma2,
            v.gamma2_rad,
            "the jib from vertical at minimum reach",
        ),
        (
            "gamma3_rad",
            "design.gamma3",
            &cs.gamma3,
            v.gamma3_rad,
            "the jib below horizontal at maximum reach",
        ),
    ];
    for (key, field, var, value, what) in free {
        if var.fixed().is_none() {
            let lo = format!("{what} at the least the range allows: the range, not an interior optimum, decides it");
            let hi = format!("{what} at the most the range allows: the range, not an interior optimum, decides it");
            bounds.extend(ActiveBound::check(
                &format!("design.{key}"),
                value,
                var.bounds(),
                1e-6,
                (field, &lo),
                (field, &hi),
            ));
        }
    }
    bounds
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
    let luffing = match &masses {
        Some(Ok(bal)) => {
            Some(luffing::drive(&link, bs, bal, p.luffing_time).map_err(|e| e.to_string()))
        }
        _ => None,
    };
    let stability = match (&masses, &p.stability) {
        (Some(Ok(bal)), Some(spec)) => Some(
            stability::stability(&link, bs, spec, cs.foot_offset, bal).map_err(|e| e.to_string()),
        ),
        _ => None,
    };
    let actuators = match &masses {
        Some(Ok(bal)) if !p.actuators.is_empty() => Some(
            actuator::actuators(&link, bs, bal, &p.actuators, p.luffing_time)
                .map_err(|e| e.to_string()),
        ),
        _ => None,
    };
    Some(Ok(Statics {
        rope,
        masses,
        luffing,
        stability,
        actuators,
    }))
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
