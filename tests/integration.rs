//! The integration tests as one test binary: each `tests/<name>.rs` is the module `<name>`
//! here, so the library and its dependencies are linked into one binary instead of one per file.
//! Run one file's tests with
//! `cargo test --test integration <name>::`, one test with
//! `cargo test --test integration <name>::<test> -- --exact`. `tests/batch_reports.rs` is its
//! own binary: it counts the documents drawn in its process.
//!
//! The `unit_<area>` modules are the library's former unit tests (`#[cfg(test)] mod tests` in
//! `src/`), moved here so that the library is compiled once instead of a second time as its
//! own unit-test harness (`docs/performance.md`, "Build and test time"); `Cargo.toml`'s `[lib]`
//! has `test = false`.

mod common;

mod architecture;
mod band_proof;
mod batch;
mod batch_folders;
mod calibrate;
mod certified;
mod cli;
mod crane;
mod crane_acceptance;
mod crane_actuator;
mod crane_balance;
mod crane_counterweight_types;
mod crane_drive;
mod crane_io;
mod crane_level_load;
mod crane_stability;
mod drawings;
mod drive;
mod drive_families;
mod dwell_synthesis;
mod energy_design;
mod envelope;
mod felling_head;
mod felling_head_lanchester;
mod fleet_mutants;
mod flywheel_design;
mod gear;
mod gear_conditioning;
mod gear_contact_stress;
mod gear_involute_shift;
mod gear_io;
mod gear_teeth;
mod hard_cases;
mod hostile_input;
mod hypocycloid;
mod hypocycloid_conditioning;
mod hypocycloid_dynamics;
mod hypocycloid_io;
mod index_page;
mod integer_limits;
mod linkage;
mod linkage_envelope;
mod linkage_load_cases;
mod linkage_model;
mod load_cases;
mod minimax_engine;
mod motion;
mod multi_cylinder;
mod multi_cylinder_firing;
mod multi_cylinder_radial;
mod mutants;
mod outline;
mod plate_counterweight;
mod plate_geom;
mod problem_files;
mod properties;
mod rms_near_fold;
mod schema;
mod scotch_yoke;
mod sensitivities;
mod serve;
mod slider_crank;
mod slider_crank_balancers;
mod slider_crank_outline;
mod statuses;
mod stroke_synthesis;
mod study;
mod synthesis;
mod textbook;
mod unit_batch;
mod unit_crane;
mod unit_gear;
mod unit_geom;
mod unit_hypocycloid;
mod unit_linkage;
mod unit_numeric;
mod unit_problem;
mod unit_report;
mod unit_slider_crank;
mod unit_synth;
mod unit_synth_envelope;
mod unit_units;
