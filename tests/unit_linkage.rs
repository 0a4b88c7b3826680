//! The general linkage's process loads (`src/families/linkage/model/loads.rs`): the
//! magnitude table interpolated and periodic.
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

use cwsynth::families::linkage::model::ProcessLoad;
use cwsynth::geom::P2;
use std::f64::consts::TAU;

#[test]
fn the_magnitude_is_linear_between_points_and_periodic() {
    let l = ProcessLoad {
        link: 0,
        at: P2::zeros(),
        direction: P2::new(0.0, 1.0),
        table: vec![(1.0, 0.0), (2.0, 10.0), (3.0, 0.0)],
    };
    assert_eq!(l.magnitude(1.5), 5.0);
    assert_eq!(l.magnitude(2.0), 10.0);
    assert_eq!(l.magnitude(0.0), 0.0);
    assert_eq!(l.magnitude(5.0), 0.0);
    assert!((l.magnitude(2.5 + TAU) - 5.0).abs() < 1e-12);
    let one = ProcessLoad {
        table: vec![(1.0, 7.0)],
        ..l.clone()
    };
    assert_eq!(one.magnitude(4.0), 7.0);
}
