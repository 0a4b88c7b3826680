//! The affine minimax engine (`synth::minimax`): a synthetic four-counterweight mechanism
//! (force and moment fields), a 20-point force–moment Pareto front (each point its own
//! certified SOCP exchange loop).

// The shipped builds' allocator (src/main.rs, python/src/lib.rs): benches time what users run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[path = "../tests/common/synthetic_linkage.rs"]
mod synthetic_linkage;

use criterion::{criterion_group, criterion_main, Criterion};
use cwsynth::synth::minimax::{
    AffineValue, CounterweightLimits, Engine, FnField, Goal, Problem, Settings,
};
use std::hint::black_box;
use synthetic_linkage::Synthetic;

fn pareto_4cw(c: &mut Criterion) {
    let mech = Synthetic::random(4, 11, 50.0);
    let f = FnField::new("force", 2, |th: f64, out: &mut AffineValue| {
        mech.eval(0, th, out)
    });
    let m = FnField::new("moment", 1, |th: f64, out: &mut AffineValue| {
        mech.eval(1, th, out)
    });
    let pb = Problem {
        fields: vec![&f, &m],
        counterweights: vec![CounterweightLimits::new(2.0, 0.1); 4],
        extra: Vec::new(),
        linear: Vec::new(),
        goal: Goal::MinPeak(vec![(0, 1.0)]),
        limits: Vec::new(),
    };
    c.bench_function(
        "minimax pareto 4 counterweights, 2 fields, 20 points",
        |b| {
            b.iter(|| {
                let eng = Engine::new(&pb, &Settings::default()).unwrap();
                black_box(eng.pareto_front(1, 0, 20).unwrap())
            })
        },
    );
}

criterion_group!(benches, pareto_4cw);
criterion_main!(benches);
