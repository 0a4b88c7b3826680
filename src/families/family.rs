//! What a mechanism family is to the engines above it: the [`Family`] that reads its files
//! and the [`Machine`] that solves and studies a resolved scene, with the [`Scene`] they
//! make and the vocabulary of a study (rungs, ladders, effects). Each family's folder
//! implements these; the registry in `families/mod.rs` lists them.

use crate::problem::edit::Edit;
use crate::problem::limits::Count;
use crate::problem::{Ctx, Input, PaperRef, ProblemError, Resolved};
use crate::report::SolveResult;
use std::any::Any;
use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

/// A mechanism family: what reads its problem files.
pub trait Family: Sync + fmt::Debug + Any {
    /// The `family = "…"` value of its files and results (`slider-crank`).
    fn name(&self) -> &'static str;
    /// The integer keys of its files and their ranges.
    fn counts(&self) -> &'static [Count];
    /// Its branch of the JSON Schema (ranges are added from [`Family::counts`]).
    fn schema(&self) -> serde_json::Value;
    /// Reads and checks a file of this family.
    fn resolve(&self, ctx: &Ctx, input: Input) -> Result<Resolved<Arc<dyn Machine>>, ProblemError>;
    /// A commented problem file to start from (`cwsynth new <family>`): one of the shipped
    /// scenes, which the tests solve.
    fn template(&self) -> &'static str;
}

/// A resolved scene's own part: what solves and studies it.
pub trait Machine: fmt::Debug + Send + Sync + Any {
    /// Solves the scene (numbers, report tables and plots). Never panics on a resolved
    /// scene; a solver failure is `status = failed`.
    fn solve(&self, scene: &Scene) -> SolveResult;
    /// The headline: the dotted result key the design is judged on (`objectives.delta_h_m`)
    /// — the objective the scene optimises, or its main figure for an analysis.
    fn headline(&self) -> String;
    /// The reference edits (tightest settings) and the ladder of settings of `cwsynth study`.
    fn ladder(&self) -> Ladder;
    /// What the model leaves out or includes, each with a bound; `reference` is the solution
    /// at the tightest settings, whose headline value is `headline`.
    fn effects(&self, reference: &SolveResult, headline: f64) -> Vec<Effect>;
    /// For [`Scene::machine`].
    fn as_any(&self) -> &dyn Any;
}

/// One entry of [`Machine::effects`]: (effect, what is left out or included, with its bound).
pub type Effect = (String, String);

/// A rung of a study's ladder: one change of the settings.
#[derive(Debug, Clone)]
pub struct Rung {
    /// Short label.
    pub label: String,
    /// `accuracy` or `model`.
    pub kind: &'static str,
    /// Edits applied to the file as written.
    pub edits: Vec<Edit>,
}

impl Rung {
    /// A rung.
    pub fn new(label: &str, kind: &'static str, edits: Vec<Edit>) -> Rung {
        Rung {
            label: label.into(),
            kind,
            edits,
        }
    }
}

/// A family's study plan for one scene.
#[derive(Debug, Clone)]
pub struct Ladder {
    /// The edits of the reference (tightest settings).
    pub reference: Vec<Edit>,
    /// The rungs, each against the reference.
    pub rungs: Vec<Rung>,
}

/// A resolved scene of any family.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Name.
    pub name: String,
    /// Family.
    pub family: &'static dyn Family,
    /// Description.
    pub description: String,
    /// The file it came from.
    pub source: PathBuf,
    /// Paper reference values.
    pub paper: Vec<PaperRef>,
    /// The family's resolved part.
    pub machine: Arc<dyn Machine>,
}

impl Scene {
    /// The family's resolved part as its concrete type (`None` for another family).
    pub fn machine<T: Machine>(&self) -> Option<&T> {
        self.machine.as_any().downcast_ref()
    }

    /// An empty result of this scene: its name, family, description and source.
    pub fn new_result(&self) -> SolveResult {
        SolveResult::new(
            &self.name,
            self.family.name(),
            &self.description,
            &self.source,
        )
    }
}

/// The claim of an exchange-loop solve (slider-crank counterweight, linkage counterweights) as
/// a result status: the same words, one place.
pub fn cw_status(s: crate::synth::counterweight::Status) -> crate::report::Status {
    use crate::report::Status;
    use crate::synth::counterweight::Status as Cw;
    match s {
        Cw::Optimal => Status::Optimal,
        Cw::Inaccurate => Status::Inaccurate,
        Cw::Infeasible => Status::Infeasible,
        Cw::Failed => Status::Failed,
    }
}

/// `x` relative to a headline value (a bound stated against the headline; never divides by 0).
pub fn relative(x: f64, headline: f64) -> f64 {
    x / headline.abs().max(1e-300)
}

/// Wraps a family's resolved part as a [`Machine`].
pub fn machine<K: Machine>(r: Resolved<K>) -> Resolved<Arc<dyn Machine>> {
    Resolved {
        name: r.name,
        description: r.description,
        source: r.source,
        paper: r.paper,
        part: Arc::new(r.part),
    }
}

/// Implements [`Family`] for the unit struct `$family` (declared here, with its doc),
/// [`Machine`] for `$problem` through the one driver ([`super::driver::drive`]), and the
/// driver's [`super::driver::Solve`] from the parts every family folder has:
/// `file::{FAMILY, COUNTS, resolve, File, TEMPLATE}` (its schema derived from `File`),
/// `solve::{solve, Solution, analyse, Analyses}` (every solve), `numbers::{model, numbers}` (the
/// solution's figures into the result's maps, at solve time), `report::{documents,
/// analysis_documents}` (the result drawn from the solution, only when asked for) and `study::{headline, ladder, effects}`.
/// Invoked once in each family's `mod.rs` (`cwsynth::family_folder!(Family, Problem)`); a
/// family defined outside this crate invokes it the same way beside the same four modules and
/// adds itself with [`super::register`].
#[macro_export]
macro_rules! family_folder {
    ($(#[$doc:meta])* $family:ident, $problem:ty) => {
        $crate::family_folder!(@parts $(#[$doc])* $family, $problem);
        $crate::family_folder!(@machine $problem, |scene, p| {
            $crate::families::driver::drive(scene, p)
        });
    };
    // A family whose machine solves through its own `$drive(scene, p)` (which calls the one
    // driver): the linkage's shape search chooses the geometry first.
    ($(#[$doc:meta])* $family:ident, $problem:ty, drive = $drive:path) => {
        $crate::family_folder!(@parts $(#[$doc])* $family, $problem);
        $crate::family_folder!(@machine $problem, |scene, p| $drive(scene, p));
    };
    (@parts $(#[$doc:meta])* $family:ident, $problem:ty) => {
        $crate::family_folder!(@family $(#[$doc])* $family);

        impl $crate::families::driver::Solve for $problem {
            type Solution = solve::Solution;
            type Analyses = solve::Analyses;
            fn model(
                &self,
                sol: Option<&solve::Solution>,
            ) -> std::collections::BTreeMap<String, serde_json::Value> {
                numbers::model(self, sol)
            }
            fn solve(&self) -> Result<solve::Solution, String> {
                solve::solve(self)
            }
            fn claim<'s>(&self, sol: &'s solve::Solution) -> &'s $crate::families::driver::Claim {
                &sol.claim
            }
            fn numbers(
                &self,
                scene: &$crate::families::family::Scene,
                sol: &solve::Solution,
                r: &mut $crate::report::SolveResult,
            ) {
                numbers::numbers(scene, self, sol, r)
            }
            fn documents(
                &self,
                scene: &$crate::families::family::Scene,
                sol: &solve::Solution,
                r: &mut $crate::report::SolveResult,
            ) {
                report::documents(scene, self, sol, r)
            }
            fn analyse(&self, sol: &solve::Solution) -> solve::Analyses {
                solve::analyse(self, sol)
            }
            fn analysis_documents(
                &self,
                scene: &$crate::families::family::Scene,
                sol: &solve::Solution,
                analyses: &solve::Analyses,
                r: &mut $crate::report::SolveResult,
            ) {
                report::analysis_documents(scene, self, sol, analyses, r)
            }
        }
    };
    (@family $(#[$doc:meta])* $family:ident) => {
        $(#[$doc])*
        #[derive(Debug)]
        pub struct $family;

        impl $crate::families::family::Family for $family {
            fn name(&self) -> &'static str {
                file::FAMILY
            }
            fn counts(&self) -> &'static [$crate::problem::limits::Count] {
                file::COUNTS
            }
            fn schema(&self) -> serde_json::Value {
                $crate::problem::schema::branch::<file::File>(file::FAMILY)
            }
            fn resolve(
                &self,
                ctx: &$crate::problem::Ctx,
                input: $crate::problem::Input,
            ) -> Result<
                $crate::problem::Resolved<
                    std::sync::Arc<dyn $crate::families::family::Machine>,
                >,
                $crate::problem::ProblemError,
            > {
                file::resolve(ctx, input).map($crate::families::family::machine)
            }
            fn template(&self) -> &'static str {
                file::TEMPLATE
            }
        }
    };
    (@machine $problem:ty, |$scene:ident, $p:ident| $solve:expr) => {
        impl $crate::families::family::Machine for $problem {
            fn solve(&self, $scene: &$crate::families::family::Scene) -> $crate::report::SolveResult {
                let $p = self;
                $solve
            }
            fn headline(&self) -> String {
                study::headline(self)
            }
            fn ladder(&self) -> $crate::families::family::Ladder {
                study::ladder(self)
            }
            fn effects(
                &self,
                reference: &$crate::report::SolveResult,
                headline: f64,
            ) -> Vec<$crate::families::family::Effect> {
                study::effects(self, reference, headline)
            }
            fn as_any(&self) -> &dyn std::any::Any {
                self
            }
        }
    };
}
