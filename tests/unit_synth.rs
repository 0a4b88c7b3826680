//! `synth::shape` (`src/synth/shape.rs`): a counterweight sector realising a mass, centroid
//! and inertia.
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

use cwsynth::synth::shape::{sector_realising, Sector, ShapeGoal, ShapeSpec};
use std::f64::consts::PI;

#[test]
fn a_sector_realises_mass_centroid_and_inertia() {
    // Figures of a known sector come back.
    let spec = ShapeSpec {
        density: 7850.0,
        thickness: 0.02,
        inner_radius_min: 0.0,
        outer_radius_max: 0.1,
        max_angle: PI,
        goal: ShapeGoal::Mass,
    };
    for (ri, ro, th) in [(0.03, 0.1, 1.2), (0.0, 0.07, 2.5), (0.0995, 0.1, 0.4)] {
        let s = Sector::new(&spec, ri, ro, th);
        let (ri2, ro2, th2) =
            sector_realising(s.mass_kg, s.centroid_radius_m, s.inertia_kgm2, 0.1).unwrap();
        let back = Sector::new(&spec, ri2, ro2, th2);
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
        // The same inertia and centroid (the mass is the caller's: any thickness).
        assert!(rel(back.inertia_kgm2 / back.mass_kg, s.inertia_kgm2 / s.mass_kg) < 1e-9);
        assert!(
            rel(back.centroid_radius_m, s.centroid_radius_m) < 1e-9,
            "{ri} {ro} {th}"
        );
        assert!(ro2 <= 0.1);
    }
    // More inertia than the envelope allows: no sector.
    assert!(sector_realising(1.0, 0.05, 1.01 * 0.01, 0.1).is_none());
}
