//! Speed of the linkage family (issue 17's targets: a four-bar minimax |F| with one
//! counterweight to 1e-9 under 0.2 ms; a 20-point force–moment front of a six-bar under 50 ms,
//! not benchmarked while it takes seconds). The shipped drag-link (one crank counterweight)
//! and the piston written as a linkage are solved from their resolved scenes.

use criterion::{criterion_group, criterion_main, Criterion};
use cwsynth::families::linkage::file::LinkageProblem;
use cwsynth::families::linkage::synth::solve;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    for name in ["linkage-double-crank", "linkage-piston-1000rpm"] {
        let path = format!("{}/problems/{name}.toml", env!("CARGO_MANIFEST_DIR"));
        let scene = cwsynth::families::load(std::path::Path::new(&path)).unwrap();
        let p: &LinkageProblem = scene.machine().unwrap();
        c.bench_function(&format!("linkage/minimax_force_{name}"), |b| {
            b.iter(|| solve(black_box(&p.scene), &p.settings).unwrap())
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
