//! The slider-crank (piston machines, presses, the felling-head vibrator) family, whole: its physics (`model`), its problem file (`file`), its synthesis
//! (`synth`), its result and plots (`report`) and its study
//! ladder and left-out effects (`study`), behind the `Family` and `Machine` traits.

pub mod file;
pub mod file_design;
pub mod file_envelope;
pub mod file_masses;
pub mod file_textbook;
pub mod flywheel_design;
pub mod model;
pub mod motion;
pub mod numbers;
pub mod report;
pub mod solve;
pub mod study;
pub mod synth;

crate::family_folder!(
    /// Slider-crank with a crank counterweight (piston machines, the felling-head vibrator).
    SliderCrank,
    file::SliderCrankProblem
);
