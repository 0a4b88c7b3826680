use cwsynth::synth::slider_crank::*;
#[test]
fn scratch() {
    let sc = paper_piston(1000.0);
    let n: u32 = std::env::var("N")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(50);
    for _ in 0..n {
        std::hint::black_box(optimise(&sc).unwrap());
    }
}
