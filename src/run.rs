//! From a resolved scene to its result: dispatch to the family's solver. Each family's
//! `io` module shapes its outcome into the common [`SolveResult`] (keys, errors,
//! baselines, plots); the paper comparison and total timing are added here.

use crate::io::problem::{Scene, SceneKind};
use crate::io::result::SolveResult;
use std::time::Instant;

/// Solves a scene. Never panics on a valid scene; a solver failure becomes
/// `status = failed` with the reason in `warnings`.
pub fn solve_scene(scene: &Scene) -> SolveResult {
    let t0 = Instant::now();
    let mut r = match &scene.kind {
        SceneKind::SliderCrank(s) => crate::io::slider_crank::result(scene, s),
        SceneKind::LuffingCrane(s) => crate::io::crane::result(scene, s),
        SceneKind::EccentricGear(s) => crate::io::gear::result(scene, s),
        SceneKind::Hypocycloid(s) => crate::io::hypocycloid::result(scene, s),
    };
    r.timing.total_s = t0.elapsed().as_secs_f64();
    r.compare_with_paper(&scene.paper);
    r
}
