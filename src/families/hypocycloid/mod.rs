//! The hypocycloid family, whole: its physics (`model`), its problem file (`file`) and its synthesis (`synth`).

pub mod file;
pub mod model;
pub mod synth;
