//! The scenes of the envelope bench (`benches/drive.rs`, issue 33: an envelope of 8 vertices
//! ≤ 5× the single-scenario solve) and of its ΔE-optimal counterweight (≤ 1 ms), shared with
//! `examples/envelope_ratio.rs`, which counts their instructions.

use cwsynth::families::slider_crank::file::SliderCrankProblem;
use cwsynth::families::slider_crank::synth::{Objective, Scene};

/// The piston of `problems/piston-1000rpm-envelope.toml` without its length tolerance
/// (800–1200 rpm, ±2 % slider and rod masses: 8 vertices and the nominal scene) and the same
/// piston without its envelope (the single scenario): (envelope, nominal).
pub fn scenes() -> (Scene, Scene) {
    let text = include_str!("../../problems/piston-1000rpm-envelope.toml");
    let i = text.find("\n[[mechanism.envelope.length]]").unwrap();
    let j = text.find("\n[model]").unwrap();
    let text = format!("{}{}", &text[..i], &text[j..]);
    let s = cwsynth::families::parse_str(&text, std::path::Path::new("env.toml")).unwrap();
    let env = s.machine::<SliderCrankProblem>().unwrap().core.clone();
    let nominal = Scene {
        envelope: Default::default(),
        ..env.clone()
    };
    (env, nominal)
}

/// The felling head (`problems/felling-head-150rpm.toml`) minimising ΔE within its plate.
pub fn felling_head_energy() -> Scene {
    let text = include_str!("../../problems/felling-head-150rpm.toml");
    let s = cwsynth::families::parse_str(text, std::path::Path::new("felling.toml")).unwrap();
    let mut sc = s.machine::<SliderCrankProblem>().unwrap().core.clone();
    sc.objective = Objective::MinEnergyFluctuation;
    sc
}
