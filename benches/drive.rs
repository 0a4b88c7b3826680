//! The machine as it runs (issue 33) on the paper's piston with its minimax counterweight:
//! ΔE at constant speed, the periodic steady state with a flywheel (constant torque and a
//! motor line), and the least flywheel for Cs = 0.02; and the felling head's counterweight
//! that minimises ΔE (certified). Targets: the steady state ≤ 2 ms, the ΔE-optimal
//! counterweight ≤ 1 ms; the piston over an envelope of 8 vertices against the nominal piston
//! (target ≤ 5×).

// The shipped builds' allocator (src/main.rs, python/src/lib.rs): benches time what users run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;
use criterion::{criterion_group, criterion_main, Criterion};
use cwsynth::dynamics::{constant_speed, least_flywheel, steady_state, DriveSettings, Motor};
use cwsynth::families::slider_crank::synth::{machine, optimise, paper_piston, sensitivity_table};
use cwsynth::geom::P2;

#[path = "common/envelope.rs"]
mod envelope;

fn bench(c: &mut Criterion) {
    let sc = paper_piston(1000.0);
    let u = P2::new(-0.0357393, 0.0);
    let m = machine(&sc, u, 0.0018);
    let s = DriveSettings::default();
    let w = sc.omega;
    let cs = constant_speed(&m, w, &s).unwrap();
    eprintln!("ΔE {} J on {} samples", cs.energy_fluctuation, cs.samples);
    c.bench_function("drive/energy_fluctuation", |b| {
        b.iter(|| constant_speed(std::hint::black_box(&m), w, &s).unwrap())
    });
    let st = steady_state(&m, &Motor::ConstantTorque, 0.0355, w, &s).unwrap();
    eprintln!("steady state (constant torque) on {} samples", st.samples);
    c.bench_function("drive/steady_state_constant_torque", |b| {
        b.iter(|| {
            steady_state(
                std::hint::black_box(&m),
                &Motor::ConstantTorque,
                0.0355,
                w,
                &s,
            )
            .unwrap()
        })
    });
    let line = Motor::Line {
        rated_torque: 20.0,
        rated_speed: 100.0,
        no_load_speed: 110.0,
    };
    let st = steady_state(&m, &line, 0.0355, w, &s).unwrap();
    eprintln!("steady state (motor line) on {} samples", st.samples);
    c.bench_function("drive/steady_state_motor_line", |b| {
        b.iter(|| steady_state(std::hint::black_box(&m), &line, 0.0355, w, &s).unwrap())
    });
    c.bench_function("drive/least_flywheel_cs_0.02", |b| {
        b.iter(|| {
            least_flywheel(
                std::hint::black_box(&m),
                &Motor::ConstantTorque,
                &cs,
                0.02,
                &s,
            )
            .unwrap()
        })
    });
}

/// The felling head (problems/felling-head-150rpm.toml) minimising ΔE within its plate.
fn bench_energy_design(c: &mut Criterion) {
    let sc = envelope::felling_head_energy();
    let o = optimise(&sc).unwrap();
    eprintln!("least ΔE design U = {:?}, {:?}", o.u, o.status);
    c.bench_function("drive/least_energy_fluctuation_counterweight", |b| {
        b.iter(|| optimise(std::hint::black_box(&sc)).unwrap())
    });
}

/// The piston over 800–1200 rpm and ±2 % piston and rod masses (8 vertices and the nominal
/// scene) against the nominal piston alone (issue 33: ≤ 5× the single-scenario solve).
fn bench_envelope(c: &mut Criterion) {
    let (env, nominal) = envelope::scenes();
    c.bench_function("drive/envelope_8_vertices_minimax_force", |b| {
        b.iter(|| optimise(std::hint::black_box(&env)).unwrap())
    });
    c.bench_function("drive/envelope_nominal_only_minimax_force", |b| {
        b.iter(|| optimise(std::hint::black_box(&nominal)).unwrap())
    });
    // The envelope's sensitivity table from the optimum's duals (the solve's report stage
    // computes it where the problem asks: `sensitivities = true`).
    let duals = optimise(&env)
        .unwrap()
        .duals
        .expect("an envelope solve's duals");
    c.bench_function("drive/envelope_sensitivity_table", |b| {
        b.iter(|| sensitivity_table(std::hint::black_box(&env), &duals).unwrap())
    });
    // The same single scenario through the engine the envelope uses (clarabel's rounds, not
    // the exact disc path that only a single turning counterweight's force allows).
    let mut general = nominal.clone();
    general.settings.exact_disc = false;
    c.bench_function("drive/envelope_nominal_only_general_engine", |b| {
        b.iter(|| optimise(std::hint::black_box(&general)).unwrap())
    });
}

criterion_group!(benches, bench, bench_energy_design, bench_envelope);
criterion_main!(benches);
