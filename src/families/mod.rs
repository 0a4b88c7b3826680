//! One home per mechanism family: each folder holds one family whole — `model` (pure
//! physics), `file` (its problem file: raw serde layer and resolution) and `synth` (design
//! vector, objectives, solves).

pub mod crane;
pub mod gear;
pub mod hypocycloid;
pub mod slider_crank;
