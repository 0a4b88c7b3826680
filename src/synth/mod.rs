//! Synthesis: design vectors with bounds, objectives and the solvers that optimise them.
pub mod gear;
