//! Speed target of issue 6: a full-cycle analysis of the paper's pair with every pole of
//! µ1, µ2 located (closure of a, all poles and zeros, peak |µ| on the working window,
//! gear 2's convexity) under 10 ms median.

// The shipped builds' allocator (src/main.rs, python/src/lib.rs): benches time what users run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use criterion::{criterion_group, criterion_main, Criterion};
use cwsynth::families::gear::model::{
    closing_center_distance, singularities, EccentricCircle, GearPair,
};
use cwsynth::families::gear::synth::{analyse, paper_table1, solve, Settings};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let scene = paper_table1();
    let settings = Settings::default();
    c.bench_function("gear/full_cycle_analysis_paper", |b| {
        b.iter(|| analyse(black_box(&scene), black_box(15e-3), &settings).unwrap())
    });
    c.bench_function("gear/poles_only_paper", |b| {
        let ec = EccentricCircle::new(37.5e-3, 15e-3).unwrap();
        let a = closing_center_distance(&ec, 3, 1).unwrap().a;
        let pair = GearPair::new(ec, 1.25e-3, a, 15.0).unwrap();
        b.iter(|| singularities(black_box(&pair), 24, 1e-13).unwrap())
    });
    c.bench_function("gear/solve_with_report_paper", |b| {
        b.iter(|| solve(black_box(&scene), &settings).unwrap())
    });
    // The units of the arithmetic floor (docs/performance.md): one evaluation of the whole
    // contact state, one of µ alone (what the peak search samples; the pole functions cost
    // about the same) and one of gear 2's pitch-curve curvature, at an angle that changes
    // every call.
    let ec = EccentricCircle::new(37.5e-3, 15e-3).unwrap();
    let a = closing_center_distance(&ec, 3, 1).unwrap().a;
    let pair = GearPair::new(ec, 1.25e-3, a, 15.0).unwrap();
    let mut alpha = 0.0f64;
    c.bench_function("gear/one_contact_evaluation", |b| {
        b.iter(|| {
            alpha = (alpha + 0.618_033_988_75) % std::f64::consts::TAU;
            black_box(&pair).contact_on(black_box(alpha), 0)
        })
    });
    c.bench_function("gear/one_mu_evaluation", |b| {
        b.iter(|| {
            alpha = (alpha + 0.618_033_988_75) % std::f64::consts::TAU;
            black_box(&pair).mu_on(black_box(alpha), 0)
        })
    });
    c.bench_function("gear/one_curvature_evaluation", |b| {
        b.iter(|| {
            alpha = (alpha + 0.618_033_988_75) % std::f64::consts::TAU;
            black_box(&pair).gear2_curvature(black_box(alpha))
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
