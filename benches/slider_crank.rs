//! The full minimax counterweight solve of the paper's piston (Table 1, 1000 rpm, rod split
//! half–half) to 1e-9 relative: presolve + exact disc rounds (the default) or clarabel's SOCP
//! (`exact_disc = false`) + exchange loop + verified refined peak.

// The shipped builds' allocator (src/main.rs, python/src/lib.rs): benches time what users run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;
use criterion::{criterion_group, criterion_main, Criterion};
use cwsynth::families::slider_crank::synth::{optimise, shaking_force, solve, Scene};

fn scene() -> Scene {
    cwsynth::families::slider_crank::synth::paper_piston(1000.0)
}

fn bench(c: &mut Criterion) {
    let sc: Scene = scene();
    let o = optimise(&sc).unwrap();
    assert!(o.gap <= 1e-9 * 300.0, "gap {}", o.gap);
    c.bench_function("slider_crank/minimax_1e-9", |b| {
        b.iter(|| optimise(std::hint::black_box(&sc)).unwrap())
    });
    let mut socp = sc.clone();
    socp.settings.exact_disc = false;
    let os = optimise(&socp).unwrap();
    assert!(os.gap <= 1e-9 * 300.0 && os.method.contains("clarabel"));
    c.bench_function("slider_crank/minimax_1e-9_clarabel", |b| {
        b.iter(|| optimise(std::hint::black_box(&socp)).unwrap())
    });
    c.bench_function("slider_crank/full_solve_with_baselines", |b| {
        b.iter(|| solve(std::hint::black_box(&sc)).unwrap())
    });
    // The unit of the arithmetic floor (docs/performance.md): one kinematic state and the
    // shaking force from it, at a crank angle that changes every call.
    let u = cwsynth::geom::P2::new(-0.0357, 0.0);
    let mut phi = 0.0f64;
    c.bench_function("slider_crank/one_force_evaluation", |b| {
        b.iter(|| {
            phi += 0.618_033_988_75;
            shaking_force(
                &sc.mech,
                sc.omega,
                std::hint::black_box(u),
                phi % std::f64::consts::TAU,
            )
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
