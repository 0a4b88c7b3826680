//! cwsynth — optimisation-driven counterweight and mechanism synthesis.
//!
//! The crate is layered so that physics, synthesis and I/O can change independently:
//!
//! * [`units`] — quantities with units at the edges (`"35 mm"` → 0.035 m).
//! * [`numeric`], [`geom`] — shared 1-D solvers and closed-form constructions.
//! * [`mech`] — pure mechanism models (kinematics, forces, torques); no I/O, no design
//!   variables.
//! * [`synth`] — design vectors, bounds, objectives and the solvers (clarabel for the convex
//!   sub-problems, argmin for the outer searches).
//! * [`io`] — problem files (raw serde layer and resolved, checked scenes), results, reports,
//!   plots.
//! * [`study`] — speed against error: a scene along a ladder of settings (`cwsynth study`).
//! * [`cli`] — the command line; `main.rs` only calls [`cli::main`].

// `!(x > 0.0)` is how the value checks reject NaN together with the out-of-range values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod batch;
pub mod cli;
pub mod families;
pub mod geom;
pub mod numeric;
pub mod problem;
pub mod report;
pub mod study;
pub mod synth;
pub mod units;
