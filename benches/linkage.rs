//! Speed of the linkage family against issue 17's targets: a four-bar minimax |F| with one
//! counterweight to 1e-9 under 0.2 ms; a 20-point force–moment front of a six-bar under 50 ms.
//!
//! * `minimax_force_fourbar_1cw/engine`: the crank-counterweight four-bar
//!   (`problems/linkage-fourbar-crank-counterweight.toml`), the minimax |F| alone: the engine
//!   built on the force field (its scan grid: 360 evaluations of the dyad chain) and solved
//!   with its certificate (rel_tol 1e-9).
//! * `minimax_force_fourbar_1cw/engine_clarabel`: the same with `exact_disc = false`
//!   (clarabel's SOCP exchange loop instead of the exact disc).
//! * `minimax_force_fourbar_1cw/solve_from_engine`: the same solve from an engine already
//!   built (the field tabulated once).
//! * `solve/<scene>`: the family's whole solve of a shipped scene (bare peaks, the minimax
//!   with its certificate, the RMS of 3 fields twice, κ).
//! * `pareto_sixbar_press_20`: the six-bar press's 20-point force–moment front (the two ends
//!   and 20 ε-constrained solves, each certified), on an engine with the force and moment.
//! * `linkage-envelope/press_nominal` and `press_8_vertices`: issue 33's "an envelope of 8
//!   vertices ≤ 5× the single-scenario solve": the family's solve (bare peaks, the certified
//!   minimax, the RMS of three fields) of `problems/linkage-sixbar-press-envelope.toml` over
//!   its 8 vertices and nominal scene (9 blocks of fields in one engine), and of the same scene
//!   without its envelope.
//! * `linkage-synthesis/candidate` and `candidate_path_error`: issue 36's "≥ 10,000 certified
//!   four-bar candidates per second on 2 cores": one candidate geometry of
//!   `problems/linkage-fourbar-path-synthesis.toml` (the next of 32 Halton points of its box
//!   that turn fully) balanced by the certified program as the search balances it (its scan
//!   grid at `SEARCH_SCAN_SAMPLES`), and its path error alone; `candidates_64_parallel`: 64
//!   candidates, each its path error and its balancing, over rayon's pool (all cores),
//!   reported as candidates per second.

// The shipped builds' allocator (src/main.rs, python/src/lib.rs): benches time what users run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use criterion::{criterion_group, criterion_main, Criterion};
use cwsynth::families::linkage::file::LinkageProblem;
use cwsynth::families::linkage::synth::{
    field_objects, limits_of, solve, SceneFields, FORCE, MOMENT,
};
use cwsynth::synth::minimax::{Engine, Goal, Problem, Settings};
use std::hint::black_box;

#[path = "common/synthesis.rs"]
mod synthesis_scene;

fn scene(name: &str) -> cwsynth::families::Scene {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let path = dir.join(format!("{name}.toml"));
    let path = if path.exists() {
        path
    } else {
        dir.join("pending").join(format!("{name}.toml"))
    };
    cwsynth::families::load(&path).unwrap()
}

fn bench(c: &mut Criterion) {
    let sc = scene("linkage-fourbar-crank-counterweight");
    let p: &LinkageProblem = sc.machine().unwrap();
    let fields = SceneFields::new(&p.scene);
    let (f, _, _) = field_objects(&fields, "");
    let pb = Problem {
        fields: vec![&f],
        counterweights: p.scene.counterweights.iter().map(limits_of).collect(),
        extra: Vec::new(),
        linear: Vec::new(),
        goal: Goal::MinPeak(vec![(0, 1.0)]),
        limits: Vec::new(),
    };
    c.bench_function("linkage/minimax_force_fourbar_1cw/engine", |b| {
        b.iter(|| {
            let e = Engine::new(black_box(&pb), &p.settings).unwrap();
            let s = e.solve().unwrap();
            assert_eq!(s.status, cwsynth::synth::counterweight::Status::Optimal);
            s
        })
    });
    let clarabel = Settings {
        exact_disc: false,
        ..p.settings
    };
    c.bench_function("linkage/minimax_force_fourbar_1cw/engine_clarabel", |b| {
        b.iter(|| {
            Engine::new(black_box(&pb), &clarabel)
                .unwrap()
                .solve()
                .unwrap()
        })
    });
    let e = Engine::new(&pb, &p.settings).unwrap();
    c.bench_function("linkage/minimax_force_fourbar_1cw/solve_from_engine", |b| {
        b.iter(|| black_box(&e).solve().unwrap())
    });
    for name in [
        "linkage-fourbar-crank-counterweight",
        "linkage-double-crank",
        "linkage-piston-1000rpm",
    ] {
        let sc = scene(name);
        let p: &LinkageProblem = sc.machine().unwrap();
        c.bench_function(&format!("linkage/solve/{name}"), |b| {
            b.iter(|| solve(black_box(&p.scene), &p.settings).unwrap())
        });
    }
}

fn pareto(c: &mut Criterion) {
    let sc = scene("linkage-sixbar-press");
    let p: &LinkageProblem = sc.machine().unwrap();
    let fields = SceneFields::new(&p.scene);
    let (f, m, t) = field_objects(&fields, "");
    let pb = Problem {
        fields: vec![&f, &m, &t],
        counterweights: p.scene.counterweights.iter().map(limits_of).collect(),
        extra: Vec::new(),
        linear: Vec::new(),
        goal: Goal::MinPeak(vec![(FORCE, 1.0)]),
        limits: Vec::new(),
    };
    let mut g = c.benchmark_group("linkage-slow");
    g.sample_size(10);
    g.bench_function("pareto_sixbar_press_20", |b| {
        b.iter(|| {
            let e = Engine::new(black_box(&pb), &p.settings).unwrap();
            e.pareto_front(FORCE, MOMENT, 20).unwrap()
        })
    });
    g.finish();
}

fn envelope(c: &mut Criterion) {
    let sc = scene("linkage-sixbar-press-envelope");
    let p: &LinkageProblem = sc.machine().unwrap();
    let nominal = cwsynth::families::linkage::file::LinkageScene {
        envelope: Default::default(),
        ..p.scene.clone()
    };
    let mut g = c.benchmark_group("linkage-envelope");
    g.sample_size(20);
    g.bench_function("press_nominal", |b| {
        b.iter(|| solve(black_box(&nominal), &p.settings).unwrap())
    });
    g.bench_function("press_8_vertices", |b| {
        b.iter(|| solve(black_box(&p.scene), &p.settings).unwrap())
    });
    g.finish();
}

/// One shape-search candidate of the shipped path synthesis: its certified balancing, and its
/// path error alone (cycling over the admissible Halton points of the box).
fn synthesis(c: &mut Criterion) {
    use cwsynth::synth::search::constrained::Shape;
    let sc = synthesis_scene::scene();
    let p: &LinkageProblem = sc.machine().unwrap();
    let shape = synthesis_scene::shape(p);
    let xs = synthesis_scene::candidates(&shape);
    assert!(xs.len() >= 8, "{} admissible candidates", xs.len());
    let mut g = c.benchmark_group("linkage-synthesis");
    let mut k = 0;
    g.bench_function("candidate", |b| {
        b.iter(|| {
            k = (k + 1) % xs.len();
            shape.objective(black_box(&xs[k])).unwrap()
        })
    });
    g.bench_function("candidate_path_error", |b| {
        b.iter(|| {
            k = (k + 1) % xs.len();
            shape.error(black_box(&xs[k])).unwrap()
        })
    });
    // The throughput on every core of the pool: 64 candidates, each its path error and its
    // certified balancing, spread by rayon as the search spreads its starts.
    g.throughput(criterion::Throughput::Elements(64));
    g.bench_function("candidates_64_parallel", |b| {
        b.iter(|| {
            use rayon::prelude::*;
            (0..64usize)
                .into_par_iter()
                .map(|i| {
                    let x = black_box(&xs[i % xs.len()]);
                    shape.error(x).unwrap() + shape.objective(x).unwrap()
                })
                .sum::<f64>()
        })
    });
    g.finish();
}

criterion_group!(benches, bench, pareto, envelope, synthesis);
criterion_main!(benches);
