//! The level-luffing crane (four-bar jib, seed 003) family, whole: its physics (`model`), its problem file (`file`), its synthesis
//! (`synth`), its result and plots (`report`) and its study
//! ladder and left-out effects (`study`), behind the `Family` and `Machine` traits.

pub mod actuator;
pub mod balance;
pub mod file;
pub mod lever;
pub mod luffing;
pub mod model;
pub mod motion;
pub mod numbers;
pub mod report;
pub mod solve;
pub mod stability;
pub mod statics;
pub mod study;
pub mod synth;

crate::family_folder!(
    /// Level-luffing four-bar jib crane.
    LuffingCrane,
    file::CraneProblem
);
