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
//! It prints the candidates' count and their path errors and objectives.
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
}
