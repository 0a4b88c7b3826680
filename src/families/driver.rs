//! The one driver every family's solve goes through, so that no family writes the
//! scaffolding: solve → the result's numbers → (only when the result's files are written) the
//! analyses that only the files need, then the tables, plots and drawings.
//!
//! A family supplies the parts through [`Solve`] (the way Clarabel.rs writes its solver loop
//! once and takes the cone and KKT parts through traits): its `solve.rs` computes every number
//! into a typed [`Solve::Solution`] — the synthesis and every second solve that the result
//! reports (a speed sweep, a boom counterweight, joint loads, the dynamics) — and its
//! `report.rs` shapes that value into the result's number maps and draws it, calling no solver.
//! A `--summary-only` batch, a study rung or a calibration step pays for the solve and the
//! numbers only: the drawing stage is a [`Deferred`] ([`DOCUMENTS`]) that runs in
//! [`SolveResult::draw`] or [`SolveResult::complete`], and the analyses only written files
//! carry ([`ANALYSES`], a crane's Δh landscape) run in [`SolveResult::complete`] alone.

use super::family::Scene;
use crate::report::{Deferred, SolveResult, ANALYSES, DOCUMENTS};
use serde_json::Value;
use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

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
    /// The result's numbers from the solution — status, design, objectives, errors, derived
    /// figures, baselines, bounds, sections, warnings, method — computing nothing new.
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
pub fn drive<P: Solve + super::Machine>(scene: &Scene, part: &P) -> SolveResult {
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
fn own<P: super::Machine>(scene: &Scene) -> &P {
    scene
        .machine::<P>()
        .expect("a scene's deferred work is its own family's")
}
