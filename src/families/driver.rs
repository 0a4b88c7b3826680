//! The one driver every family's solve goes through, so that no family writes the
//! scaffolding: solve → the result's numbers → (only when the result's files are written) the
//! analyses that only the files need, then the tables, plots and drawings.
//!
//! A family supplies the parts through [`Solve`] (the way Clarabel.rs writes its solver loop
//! once and takes the cone and KKT parts through traits): its `solve.rs` computes every number
//! into a typed [`Solve::Solution`] — the synthesis and every second solve that the result
//! reports (a speed sweep, a boom counterweight, joint loads, the dynamics) — with the
//! [`Claim`] every family makes of its design (status, method, evidence, bounds), and its
//! `numbers.rs` shapes that value into the result's number maps and its `report.rs` draws it,
//! neither calling a solver.
//! A `--summary-only` batch, a study rung or a calibration step pays for the solve and the
//! numbers only: the drawing stage is a [`Deferred`] ([`DOCUMENTS`]) that runs in
//! [`SolveResult::draw`] or [`SolveResult::complete`], and the analyses only written files
//! carry ([`ANALYSES`], a crane's Δh landscape) run in [`SolveResult::complete`] alone.

use super::family::{Machine, Scene};
use crate::report::{Deferred, SolveResult, Status, ANALYSES, DOCUMENTS};
use crate::synth::{ActiveBound, SearchEvidence, Shortfall};
use serde_json::Value;
use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

/// What a family's solve claims of its design, typed, in every family's words: the status
/// (a claim: `optimal` only with a certificate, `best_found` with its search's evidence), the
/// family's finer detail, the method that found it, the evidence, the bounds the design sits
/// on and the solve's own warnings. The family's numbers are its `Solution`'s; this is what
/// every result says about them.
#[derive(Debug, Clone, PartialEq)]
pub struct Claim {
    /// The status.
    pub status: Status,
    /// The family's finer status (`branch-defect`, the reason of a `degenerate`), if any.
    pub status_detail: Option<String>,
    /// The method: solver, crate, evaluations.
    pub method: String,
    /// With `best_found`: what the heuristic search did.
    pub search: Option<SearchEvidence>,
    /// The design variables left on a bound of their range.
    pub bounds: Vec<ActiveBound>,
    /// The solve's warnings (the report adds those of its checks after them).
    pub warnings: Vec<String>,
    /// With `infeasible`: each limit and the least value of its quantity that any design
    /// within the bounds reaches (how far off the limit is).
    pub infeasibility: Vec<Shortfall>,
}

impl Claim {
    /// A claim of `status` by `method`, with nothing else to say.
    pub fn new(status: Status, method: impl Into<String>) -> Claim {
        Claim {
            status,
            status_detail: None,
            method: method.into(),
            search: None,
            bounds: Vec::new(),
            warnings: Vec::new(),
            infeasibility: Vec::new(),
        }
    }

    /// An `infeasible` claim: the shortfalls, and a status detail that says them (unless
    /// the family gave one).
    pub fn infeasible(&mut self, shortfalls: Vec<Shortfall>) {
        self.status = Status::Infeasible;
        if self.status_detail.is_none() && !shortfalls.is_empty() {
            let said: Vec<String> = shortfalls.iter().map(Shortfall::describe).collect();
            self.status_detail = Some(said.join("; "));
        }
        self.infeasibility = shortfalls;
    }

    /// Writes the claim into the result.
    fn fill(&self, r: &mut SolveResult) {
        r.status = self.status;
        r.status_detail = self.status_detail.clone();
        r.method = self.method.clone();
        r.search = self.search.clone();
        r.bounds = self.bounds.clone();
        r.warnings = self.warnings.clone();
        r.infeasibility = self.infeasibility.clone();
    }
}

/// A family's parts of a solve: what [`drive`] calls, in this order.
pub trait Solve: Send + Sync + 'static {
    /// Every number of a solved scene: the family's outcome and its second solves.
    type Solution: Send + Sync + 'static;
    /// What only a result's files need beyond the solution (a diagnostic grid over the design
    /// space), computed by [`Solve::analyse`] when the files are written; `()` for none.
    type Analyses: Send + Sync + 'static;

    /// The result's `model` section: the fidelity the solve uses (`None` before, or without,
    /// a solution).
    fn model(&self, sol: Option<&Self::Solution>) -> BTreeMap<String, Value>;
    /// The solve: every number, nothing drawn. An error is why the result is `failed`.
    fn solve(&self) -> Result<Self::Solution, String>;
    /// What the solve claims of its design.
    fn claim<'s>(&self, sol: &'s Self::Solution) -> &'s Claim;
    /// The result's numbers from the solution — design, objectives, errors, derived figures,
    /// baselines, sections, and the warnings of the report's own checks — computing nothing
    /// new.
    fn numbers(&self, scene: &Scene, sol: &Self::Solution, r: &mut SolveResult);
    /// The tables, plots and drawings of the solution: made only when they are asked for
    /// ([`SolveResult::draw`], [`SolveResult::complete`]).
    fn documents(&self, scene: &Scene, sol: &Self::Solution, r: &mut SolveResult);
    /// The analyses that only the result's files need: run by [`SolveResult::complete`] only.
    fn analyse(&self, sol: &Self::Solution) -> Self::Analyses;
    /// The sections, tables and plots of the analyses, in their places among the documents.
    fn analysis_documents(
        &self,
        scene: &Scene,
        sol: &Self::Solution,
        analyses: &Self::Analyses,
        r: &mut SolveResult,
    );
}

/// Solves `scene`, whose resolved part is `part`: the numbers now, the drawing stage deferred
/// to [`SolveResult::complete`]. A solve that fails gives a `failed` result with the reason in
/// `warnings`. `timing.solve_s` is the whole [`Solve::solve`].
pub fn drive<P: Solve + Machine>(scene: &Scene, part: &P) -> SolveResult {
    let mut r = scene.new_result();
    let t0 = Instant::now();
    let sol = match Solve::solve(part) {
        Ok(s) => s,
        Err(why) => {
            r.model = part.model(None);
            r.warnings.push(why);
            return r;
        }
    };
    r.timing.solve_s = t0.elapsed().as_secs_f64();
    r.model = part.model(Some(&sol));
    part.claim(&sol).fill(&mut r);
    part.numbers(scene, &sol, &mut r);
    let (scene, sol) = (Arc::new(scene.clone()), Arc::new(sol));
    let (s, x) = (scene.clone(), sol.clone());
    r.deferred
        .push(Deferred::new(DOCUMENTS, move |r: &mut SolveResult| {
            own::<P>(&s).documents(&s, &x, r)
        }));
    r.deferred
        .push(Deferred::new(ANALYSES, move |r: &mut SolveResult| {
            let part = own::<P>(&scene);
            let analyses = part.analyse(&sol);
            part.analysis_documents(&scene, &sol, &analyses, r);
        }));
    r
}

/// The scene's own resolved part: the family whose driver deferred the work.
fn own<P: Machine>(scene: &Scene) -> &P {
    scene
        .machine::<P>()
        .expect("a scene's deferred work is its own family's")
}
