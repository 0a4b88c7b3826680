//! The integration tests as one test binary: each `tests/<name>.rs` is the module `<name>`
//! here, so the library and its dependencies are linked into one binary instead of one per file.
//! Run one file's tests with
//! `cargo test --test integration <name>::`, one test with
//! `cargo test --test integration <name>::<test> -- --exact`. `tests/batch_reports.rs` is its
//! own binary: it counts the documents drawn in its process.

mod common;

mod architecture;
mod batch;
mod calibrate;
mod certified;
mod cli;
mod crane;
mod crane_acceptance;
mod crane_balance;
mod crane_io;
mod drawings;
mod drive;
mod drive_families;
mod energy_design;
mod envelope;
mod felling_head;
mod fleet_mutants;
mod flywheel_design;
mod gear;
mod gear_conditioning;
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
mod linkage_model;
mod minimax_engine;
mod mutants;
mod problem_files;
mod properties;
mod schema;
mod scotch_yoke;
mod slider_crank;
mod slider_crank_balancers;
mod statuses;
mod study;
mod textbook;
