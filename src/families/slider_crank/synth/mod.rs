//! Crank counterweight synthesis for a slider-crank machine.
//!
//! The scene fixes the mechanism and the speed; the design is the counterweight (unbalance
//! U = m·r at angle β from the crank line, and how |U| splits into mass and radius). The
//! objective is the peak or the RMS shaking force, or the lightest / smallest-radius
//! counterweight under a peak-force limit. The convex core is [`crate::synth::counterweight`];
//! this module maps the scene onto it, splits |U| into m and r, and evaluates the result
//! and the classical baselines (no counterweight, y force zeroed, the 50 % rule, equal x and
//! y ranges) with the same refined peaks.
//!
//! By concern: `scene` (the scene and its checks), `fields` (f₀, M₀, T₀ and the sampled
//! grids), `round_off` (the conditioning bounds), `metrics` (the refined figures of one
//! counterweight), `baselines`, `realise` (|U| into mass, radius and plate), `optimise`
//! (the convex engine and its warm start), `joint` (the joint design with balancers by
//! [`crate::synth::minimax`]), `loads` (joint loads and their limits), `sweep` (Pareto front
//! and speed sweep), `solve` (the whole solve) and `outcome` (the types it returns).

mod baselines;
mod drive;
mod envelope;
mod fields;
mod joint;
mod loads;
mod metrics;
mod optimise;
mod outcome;
mod realise;
mod round_off;
mod scenarios;
mod scene;
mod solve;
mod sweep;

pub use crate::synth::envelope::{End, Sensitivity};
pub use baselines::{baselines, judge_baseline};
pub use drive::{energy_fluctuation, machine, real_speed_force};
pub use envelope::{
    Envelope, EnvelopeOutcome, LengthOf, LengthRange, MassOf, MassRange, MonteCarlo, VertexFigures,
    WorstCase, MAX_PARAMETERS,
};
pub use fields::{drive_torque, force0, moment0, scene_force, shaking_force};
pub use joint::{sensitivity_table, EnvelopeDuals};
pub use metrics::metrics;
pub use optimise::optimise;
pub use outcome::{
    headline, Baseline, Derived, Design, Errors, JointLoadAngles, JointLoadFigures, JointLoadPeaks,
    LoadPeak, Metrics, Objectives, Optimum, Outcome, ParetoPoint,
};
pub use realise::{fixed_length, realise, split_unbalance, unbalance_bounds, Realised};
pub use round_off::{joint_load_round_off, round_off_bounds};
pub use scenarios::Scenario;
pub use scene::{
    paper_piston, BalancerSpec, CounterweightSpec, LoadLimits, Objective, Prefer, Scene, SolveError,
};
pub use solve::solve;
pub use sweep::{pareto, speed_sweep, SpeedSweep, SweepPoint};
