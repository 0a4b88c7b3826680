//! Speed targets of issue 5: tracing a zero curve of 100 points at 1e-12 (< 50 ms median),
//! plus the cost of one exact coefficient table and of a full `solve` of the paper example.

// The shipped builds' allocator (src/main.rs, python/src/lib.rs): benches time what users run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use criterion::{criterion_group, criterion_main, Criterion};
use cwsynth::families::hypocycloid::model::{Hypocycloid, ALPHA0_VARIANT2};
use cwsynth::families::hypocycloid::synth::{
    paper_example, solve, zero_search, PaperVariant, Settings, ZeroSearch,
};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let s = Settings::default();
    assert_eq!(s.curve_points, 100);
    assert_eq!(s.root_tol, 1e-12);
    let zs = ZeroSearch {
        order: 4,
        lambda: (0.02, 0.5),
        theta: (0.0, 0.9),
    };
    c.bench_function("zero_curve_100pts_1e-12_variant1", |b| {
        b.iter(|| {
            let z = zero_search(PaperVariant::Variant1.alpha0(), black_box(&zs), 3, 1e-3, &s);
            assert_eq!(z.roots.len(), 100);
            z
        })
    });
    c.bench_function("zero_search_no_zero_variant2", |b| {
        b.iter(|| zero_search(PaperVariant::Variant2.alpha0(), black_box(&zs), 3, 1e-3, &s))
    });
    let m = Hypocycloid::new(0.25, 0.5, ALPHA0_VARIANT2).unwrap();
    c.bench_function("coefficients_order8_fft", |b| {
        b.iter(|| black_box(&m).coefficients(8, 64, 1 << 16))
    });
    let scene = paper_example(PaperVariant::Variant2);
    c.bench_function("solve_paper_example_variant2", |b| {
        b.iter(|| solve(black_box(&scene), &s).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
