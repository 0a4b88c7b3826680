//! The candidates of `benches/linkage.rs`'s `linkage-synthesis` group (issue 36), each
//! evaluated once as the bench times it — its path error, then its certified balancing — in
//! functions of their own so that callgrind can count each one's instructions alone,
//! independent of the machine's load:
//!
//! ```text
//! cargo build --release --example synthesis_candidates
//! valgrind --tool=callgrind --toggle-collect='*synthesis_candidates::path_errors' \
//!     target/release/examples/synthesis_candidates
//! valgrind --tool=callgrind --toggle-collect='*synthesis_candidates::balancings' \
//!     target/release/examples/synthesis_candidates
//! ```
//!
//! It prints the candidates' count and their path errors and objectives. With `--times N` it
//! also times every candidate's balancing N times (after one untimed pass) and prints the
//! distribution of the inner solve's time over the candidates — each candidate's median of
//! its N — as min, median, p95 and max in µs (issue 36: "report the distribution of inner
//! solve times").
use cwsynth::families::linkage::file::LinkageProblem;
use cwsynth::families::linkage::synthesis::LinkageShape;
use cwsynth::synth::search::constrained::Shape;

#[path = "../benches/common/synthesis.rs"]
mod synthesis_scene;

/// Every candidate's path error.
#[inline(never)]
fn path_errors(shape: &LinkageShape, xs: &[Vec<f64>]) -> Vec<f64> {
    xs.iter().map(|x| shape.error(x).unwrap()).collect()
}

/// Every candidate's certified balancing (its objective).
#[inline(never)]
fn balancings(shape: &LinkageShape, xs: &[Vec<f64>]) -> Vec<f64> {
    xs.iter().map(|x| shape.objective(x).unwrap()).collect()
}

/// Each candidate's median time of its balancing over `n` runs (µs), sorted.
fn inner_times(shape: &LinkageShape, xs: &[Vec<f64>], n: usize) -> Vec<f64> {
    let mut medians: Vec<f64> = xs
        .iter()
        .map(|x| {
            let mut t: Vec<f64> = (0..n)
                .map(|_| {
                    let t0 = std::time::Instant::now();
                    std::hint::black_box(shape.objective(std::hint::black_box(x)));
                    t0.elapsed().as_secs_f64() * 1e6
                })
                .collect();
            t.sort_by(f64::total_cmp);
            t[n / 2]
        })
        .collect();
    medians.sort_by(f64::total_cmp);
    medians
}

fn main() {
    let sc = synthesis_scene::scene();
    let p: &LinkageProblem = sc.machine().unwrap();
    let shape = synthesis_scene::shape(p);
    let xs = synthesis_scene::candidates(&shape);
    let (e, f) = (path_errors(&shape, &xs), balancings(&shape, &xs));
    println!("{} candidates", xs.len());
    for (e, f) in e.iter().zip(&f) {
        println!("{e:e} {f:e}");
    }
    let args: Vec<String> = std::env::args().collect();
    if let Some(n) = (args.iter().position(|a| a == "--times"))
        .and_then(|i| args.get(i + 1)?.parse::<usize>().ok())
    {
        let t = inner_times(&shape, &xs, n.max(1));
        let at = |q: f64| t[((t.len() - 1) as f64 * q).round() as usize];
        println!(
            "inner solve (µs, each candidate's median of {n}): min {:.1}, median {:.1}, p95 {:.1}, max {:.1}",
            t[0],
            at(0.5),
            at(0.95),
            t[t.len() - 1]
        );
    }
}
