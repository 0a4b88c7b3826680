//! The two scenes of `benches/drive.rs::bench_envelope` (issue 33: an envelope of 8 vertices
//! ≤ 5× the single-scenario solve), each solved once by `optimise` exactly as the bench
//! times it, in functions of their own so that callgrind can count each one's instructions
//! alone, independent of the machine's load:
//!
//! ```text
//! cargo build --release --example envelope_ratio
//! valgrind --tool=callgrind --toggle-collect='*envelope_ratio::envelope' \
//!     target/release/examples/envelope_ratio
//! valgrind --tool=callgrind --toggle-collect='*envelope_ratio::nominal' \
//!     target/release/examples/envelope_ratio
//! valgrind --tool=callgrind --toggle-collect='*envelope_ratio::energy_design' \
//!     target/release/examples/envelope_ratio
//! valgrind --tool=callgrind --toggle-collect='*envelope_ratio::sensitivities' \
//!     target/release/examples/envelope_ratio
//! ```
//!
//! The third counts `benches/drive.rs::bench_energy_design`: the felling head's counterweight
//! that minimises ΔE (issue 33: ≤ 1 ms); the last the envelope's sensitivity table from its
//! optimum's duals (`drive/envelope_sensitivity_table`).
// The shipped builds' allocator (src/main.rs, python/src/lib.rs), as in the benches.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use cwsynth::families::slider_crank::synth::{
    optimise, sensitivity_table, EnvelopeDuals, Optimum, Scene, Sensitivity,
};

#[path = "../benches/common/envelope.rs"]
mod bench_scenes;

/// The envelope's scene: the piston over 800–1200 rpm and ±2 % slider and rod masses.
#[inline(never)]
fn envelope(scene: &Scene) -> Optimum {
    optimise(std::hint::black_box(scene)).unwrap()
}

/// The same piston without its envelope (the special exact-disc path).
#[inline(never)]
fn nominal(scene: &Scene) -> Optimum {
    optimise(std::hint::black_box(scene)).unwrap()
}

/// The felling head's counterweight that minimises ΔE within its plate.
#[inline(never)]
fn energy_design(scene: &Scene) -> Optimum {
    optimise(std::hint::black_box(scene)).unwrap()
}

/// The envelope's sensitivity table from its optimum's duals (computed by the solve's report
/// stage where the problem asks for it, not by `optimise`).
#[inline(never)]
fn sensitivities(scene: &Scene, duals: &EnvelopeDuals) -> Vec<Sensitivity> {
    sensitivity_table(std::hint::black_box(scene), duals).unwrap()
}

/// Solves each scene once outside the counted functions.
#[inline(never)]
fn warm_up(scenes: &[&Scene]) {
    for s in scenes {
        optimise(std::hint::black_box(s)).unwrap();
    }
}

fn main() {
    let (env, nom) = bench_scenes::scenes();
    // Once untimed each first, as criterion's warm-up does (the thread pool, lazy tables).
    let fh = bench_scenes::felling_head_energy();
    warm_up(&[&env, &nom, &fh]);
    let (e, n, d) = (envelope(&env), nominal(&nom), energy_design(&fh));
    let table = sensitivities(&env, e.duals.as_ref().expect("an envelope solve's duals"));
    println!("sensitivity table: {} rows", table.len());
    println!(
        "least ΔE U = {:?} {:?} {} rounds, {}",
        d.u, d.status, d.rounds, d.method
    );
    println!("envelope U = {:?} {:?}", e.u, e.status);
    println!("nominal  U = {:?} {:?}", n.u, n.status);
}
