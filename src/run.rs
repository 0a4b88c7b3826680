//! From a resolved scene to its result: dispatch to the family's solver. Each family's
//! `io` module shapes its outcome into the common [`SolveResult`] (keys, errors,
//! baselines, plots); the paper comparison and total timing are added here.

use crate::problem::{Scene, SceneKind};
use crate::report::SolveResult;
use std::time::Instant;

/// Solves a scene. Never panics on a valid scene; a solver failure becomes
/// `status = failed` with the reason in `warnings`.
pub fn solve_scene(scene: &Scene) -> SolveResult {
    let t0 = Instant::now();
    let mut r = match &scene.kind {
        SceneKind::SliderCrank(s) => crate::families::slider_crank::file::result(scene, s),
        SceneKind::LuffingCrane(s) => crate::families::crane::file::result(scene, s),
        SceneKind::EccentricGear(s) => crate::families::gear::file::result(scene, s),
        SceneKind::Hypocycloid(s) => crate::families::hypocycloid::file::result(scene, s),
    };
    r.timing.total_s = t0.elapsed().as_secs_f64();
    r.compare_with_paper(&scene.paper);
    reject_non_finite(&mut r);
    r
}

/// No result carries inf or NaN in its number maps: a figure that is not finite (a derived
/// quantity blown up by an absurd input) is removed, and the result becomes `failed` with a
/// `status_detail` naming the figures; the inputs' own checks should have stopped it first.
fn reject_non_finite(r: &mut SolveResult) {
    let mut bad = Vec::new();
    let mut sweep = |section: String, m: &mut std::collections::BTreeMap<String, f64>| {
        m.retain(|k, v| {
            let ok = v.is_finite();
            if !ok {
                bad.push(format!("{section}.{k} = {v}"));
            }
            ok
        });
    };
    sweep("design".into(), &mut r.design);
    sweep("objectives".into(), &mut r.objectives);
    sweep("errors".into(), &mut r.errors);
    sweep("derived".into(), &mut r.derived);
    for (b, m) in r.baselines.iter_mut() {
        sweep(format!("baselines.{b}"), m);
    }
    if !bad.is_empty() {
        r.status = crate::report::Status::Failed;
        r.status_detail = Some(format!(
            "not finite, so not reported: {}; an input is out of proportion (e.g. a counterweight radius far below the machine's size)",
            bad.join(", ")
        ));
    }
}
