//! The hypocycloidal reciprocating machine (seed 004) family, whole: its physics (`model`), its problem file (`file`), its synthesis
//! (`synth`), its result and plots (`report`) and its study
//! ladder and left-out effects (`study`), behind the `Family` and `Machine` traits.

pub mod balance;
pub mod closed_form;
pub mod dynamics;
pub mod file;
pub mod gas;
pub mod load_cases;
pub mod model;
pub mod motion;
pub mod numbers;
pub mod report;
pub mod solve;
pub mod study;
pub mod synth;

crate::family_folder!(
    /// Hypocycloidal (3:1 planetary) reciprocating machine.
    HypocycloidFamily,
    file::HypocycloidProblem
);
