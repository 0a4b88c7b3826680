//! Speed targets: the 2-variable optimisation (k1, k2, tie-pin limit) ≤ 15 ms median
//! (issue 21; issue 4 asked 50 ms), the 6-variable one (k1, k2 and the four step-1 angles,
//! thesis scene and Tukan 40 t) under 300 ms (issue 14; issue 4 asked 1 s). The landscape
//! map is not part of a solve (it is report data, computed when files are written) and is
//! timed on its own; one Δh evaluation is benchmarked for scale.

// The shipped builds' allocator (src/main.rs, python/src/lib.rs): benches time what users run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use criterion::{criterion_group, criterion_main, Criterion};
use cwsynth::families::crane::synth::*;
use std::hint::black_box;

fn settings() -> Settings {
    Settings {
        landscape_k1: 0,
        landscape_k2: 0,
        ..Settings::default()
    }
}

fn bench(c: &mut Criterion) {
    let s = settings();
    let x = [
        0.2,
        0.4,
        35f64.to_radians(),
        10f64.to_radians(),
        5f64.to_radians(),
        12f64.to_radians(),
    ];
    let ex = thesis_example();
    c.bench_function("crane/evaluate_thesis_design", |b| {
        b.iter(|| evaluate(black_box(&ex), black_box(&x), &s).unwrap())
    });
    let two = thesis_optimisation();
    c.bench_function("crane/optimise_2var_k1_k2", |b| {
        b.iter(|| solve(black_box(&two), &s).unwrap())
    });
    let with_map = Settings::default();
    let mut g = c.benchmark_group("crane-slow");
    g.sample_size(10);
    // The landscape is computed only when a result's files are written: timed on its own.
    let o = solve(&two, &s).unwrap();
    g.bench_function("landscape_41x41", |b| {
        b.iter(|| landscape(black_box(&two), &with_map, &o.x).unwrap())
    });
    let six = thesis_optimisation_with_angles();
    g.bench_function("optimise_6var_thesis", |b| {
        b.iter(|| solve(black_box(&six), &s).unwrap())
    });
    let tukan = tukan_40t_optimisation();
    g.bench_function("optimise_6var_tukan", |b| {
        b.iter(|| solve(black_box(&tukan), &s).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
