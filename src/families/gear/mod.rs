//! The eccentric non-circular gear (seed 001) family, whole: its physics (`model`), its problem file (`file`), its synthesis
//! (`synth`), its result and plots (`report`) and its study
//! ladder and left-out effects (`study`), behind the `Family` and `Machine` traits.

pub mod file;
pub mod model;
pub mod motion;
pub mod numbers;
pub mod report;
pub mod solve;
pub mod stress;
pub mod study;
pub mod synth;
pub mod teeth;

crate::family_folder!(
    /// Eccentric non-circular gear pair.
    EccentricGear,
    file::GearProblem
);
