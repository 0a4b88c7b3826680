//! The candidates of `benches/linkage.rs`'s `linkage-synthesis` group, shared with
//! `examples/synthesis_candidates.rs` (which counts their instructions under callgrind): the
//! shipped path synthesis's scene, its shape as the search sees it (the inner program's scan
//! grid at `SEARCH_SCAN_SAMPLES`) and the first 32 Halton points of its box that turn fully
//! and balance.

use cwsynth::families::linkage::file::LinkageProblem;
use cwsynth::families::linkage::synthesis::{LinkageShape, Requirement, SEARCH_SCAN_SAMPLES};
use cwsynth::synth::minimax::Settings;
use cwsynth::synth::search::constrained::Shape;

/// `problems/linkage-fourbar-path-synthesis.toml`.
pub fn scene() -> cwsynth::families::Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems/linkage-fourbar-path-synthesis.toml");
    cwsynth::families::load(&path).unwrap()
}

/// The shape of the problem `p` with the search's inner settings.
pub fn shape(p: &LinkageProblem) -> LinkageShape<'_> {
    let (syn, path) = (p.synthesis.as_ref().unwrap(), p.path.as_ref().unwrap());
    let settings = Settings {
        scan_samples: SEARCH_SCAN_SAMPLES,
        ..p.settings
    };
    LinkageShape::new(&p.scene, syn, Requirement::Path(path), settings)
}

/// The admissible candidates among the first 32 Halton points of the shape's box.
pub fn candidates(shape: &LinkageShape) -> Vec<Vec<f64>> {
    let bounds = shape.bounds();
    cwsynth::synth::search::starts::halton_points(32, bounds.len())
        .into_iter()
        .map(|u| {
            (u.iter().zip(bounds))
                .map(|(v, b)| b.0 + v * (b.1 - b.0))
                .collect()
        })
        .filter(|x: &Vec<f64>| shape.error(x).is_some() && shape.objective(x).is_some())
        .collect()
}
