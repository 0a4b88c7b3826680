//! The slider-crank (piston machines, presses, the felling-head vibrator) family, whole: its physics (`model`), its problem file (`file`), its synthesis
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

/// Slider-crank with a crank counterweight (piston machines, the felling-head vibrator).
#[derive(Debug)]
pub struct SliderCrank;

impl Family for SliderCrank {
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

impl Machine for file::SliderCrankProblem {
    fn solve(&self, scene: &Scene) -> SolveResult {
        report::result(scene, self)
    }
    fn headline(&self) -> String {
        use synth::Objective;
        match self.core.objective {
            Objective::MinRmsForce => "objectives.rms_shaking_force_n",
            Objective::MinPeakTorque => "objectives.peak_drive_torque_nm",
            Objective::MinMass => "design.counterweight_mass_kg",
            Objective::MinRadius => "design.counterweight_radius_m",
            Objective::MinPeakForce => "objectives.peak_shaking_force_n",
        }
        .into()
    }
    fn ladder(&self) -> Ladder {
        study::ladder(self)
    }
    fn effects(&self, _reference: &SolveResult, headline: f64) -> Vec<Effect> {
        study::effects(self, headline)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}
