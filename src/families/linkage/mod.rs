//! Any one-degree-of-freedom planar linkage, whole: a crank and a chain of Assur dyads with the
//! shaking force, shaking moment, input torque and joint reactions as linear maps in the links'
//! inertial parameters (`model`), its problem file (`file`, `file_loads`, `file_envelope`), its operating envelope (`envelope`), its shape search (`shape`, `synthesis`, `file_synthesis`), the certified counterweight cone
//! programs (`synth`), its result and plots (`report`) and its
//! study ladder (`study`), behind the `Family` and `Machine` traits.

pub mod drive;
pub mod envelope;
pub mod file;
pub mod file_envelope;
pub mod file_loads;
pub mod file_synthesis;
pub mod load_cases;
pub mod model;
pub mod motion;
pub mod numbers;
pub mod report;
pub mod shape;
pub mod solve;
pub mod solve_envelope;
pub mod study;
pub mod synth;
pub mod synthesis;

crate::family_folder!(
    /// Any one-degree-of-freedom planar linkage (crank + dyads) with counterweights.
    LinkageFamily,
    file::LinkageProblem,
    drive = synthesis::drive
);
