//! Pure mechanism models: positions, their derivatives with respect to the input angle,
//! forces and torques. No design variables, no I/O: a model is data plus formulas.
pub mod crane;
pub mod gear;
pub mod hypocycloid;
pub mod slider_crank;
