//! cwsynth — optimisation-driven counterweight and mechanism synthesis.
//!
//! The crate is layered so that physics, synthesis and I/O can change independently (the
//! layers and one file's way from text to report: `docs/architecture.md`):
//!
//! * [`units`], [`numeric`], [`geom`] — quantities with units at the edges (`"35 mm"` →
//!   0.035 m), shared 1-D solvers and closed-form constructions.
//! * [`problem`], [`report`], [`synth`] — the generic engines: reading a problem file with
//!   located errors; the common result, Markdown and plots; design variables, the
//!   counterweight SOCP and the affine minimax with their exchange loops, and the outer
//!   searches behind one interface ([`synth::search`]: argmin's Nelder–Mead, a hand-written
//!   trust-region SQP, multistart starts and the evidence of a heuristic search).
//! * [`families`] — one folder per mechanism family (model, file, synth, report, schema,
//!   study) behind the `Family` and `Machine` traits, with a one-line-per-family registry.
//! * [`batch`], [`study`], [`calibrate`] — many machines; speed against error
//!   (`cwsynth study`); fitting unknown data to measured values (`cwsynth calibrate`).
//! * [`cli`] — the command line; `main.rs` only calls [`cli::main`].

// `!(x > 0.0)` is how the value checks reject NaN together with the out-of-range values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod batch;
pub mod calibrate;
pub mod cli;
pub mod dynamics;
pub mod families;
pub mod geom;
pub mod numeric;
pub mod problem;
pub mod report;
pub mod serve;
pub mod study;
pub mod synth;
pub mod units;
