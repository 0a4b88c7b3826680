//! The hypocycloidal reciprocating machine (seed 004) family, whole: its physics (`model`), its problem file (`file`), its synthesis
//! (`synth`), its result and plots (`report`), its schema branch (`schema`) and its study
//! ladder and left-out effects (`study`), behind the `Family` and `Machine` traits.

pub mod file;
pub mod model;
pub mod report;
pub mod schema;
pub mod study;
pub mod synth;

use crate::families::family::{Effect, Family, Ladder, Machine, Scene};
use crate::problem::limits::Count;
use crate::problem::{Ctx, Input, ProblemError, Resolved};
use crate::report::SolveResult;
use std::any::Any;
use std::sync::Arc;

/// Hypocycloidal (3:1 planetary) reciprocating machine.
#[derive(Debug)]
pub struct HypocycloidFamily;

impl Family for HypocycloidFamily {
    fn name(&self) -> &'static str {
        file::FAMILY
    }
    fn counts(&self) -> &'static [Count] {
        file::COUNTS
    }
    fn schema(&self) -> serde_json::Value {
        schema::schema()
    }
    fn resolve(&self, ctx: &Ctx, input: Input) -> Result<Resolved<Arc<dyn Machine>>, ProblemError> {
        file::resolve(ctx, input).map(crate::families::family::machine)
    }
}

impl Machine for file::HypocycloidProblem {
    fn solve(&self, scene: &Scene) -> SolveResult {
        report::result(scene, self)
    }
    // A scene asking the paper's C4 question is judged on C4 (a4 of S/R) itself.
    fn headline(&self) -> String {
        if self.scene.zero_search.is_some() {
            "objectives.c4"
        } else {
            "objectives.residual_force_peak_n"
        }
        .into()
    }
    fn ladder(&self) -> Ladder {
        study::ladder(self)
    }
    fn effects(&self, reference: &SolveResult, headline: f64) -> Vec<Effect> {
        study::effects(self, reference, headline)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}
