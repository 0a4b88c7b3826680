//! The speed band's proof (issue 33, `dynamics::cases::BandCheck::prove`): its bound on Cs
//! between solved speeds against Cs solved directly at 401 speeds of a band over which Cs
//! falls and rises, a band governed by its end proven within the bound's error, and a band
//! without load proven at once.
use cwsynth::dynamics::cases::{BandCheck, BAND_CHECK_SPEEDS, BAND_MAX_SPEEDS};
use cwsynth::dynamics::{steady_state, DriveSettings, Motor, SteadyState};

/// A machine whose Cs is not monotone in the speed: J swings from 0.8 to 3.2 kg·m² (a
/// fluctuation that does not fall with the speed) against a load whose second harmonic
/// (one that does) cancels it near 20 rad/s with the flywheel of 20 kg·m².
fn machine(phi: f64) -> [f64; 3] {
    [
        2.0 + 1.2 * (2.0 * phi).cos(),
        -2.4 * (2.0 * phi).sin(),
        480.0 * (2.0 * phi).sin() + 30.0 * (phi + 0.4).sin(),
    ]
}

fn at(w: f64, flywheel: f64) -> Result<SteadyState, String> {
    let s = DriveSettings::default();
    steady_state(&machine, &Motor::ConstantTorque, flywheel, w, &s).map_err(|e| e.to_string())
}

/// The bound covers Cs at 400 speeds of the band, each within its own error, whether
/// `cs` is met or missed.
#[test]
fn the_band_bound_covers_a_dense_scan() {
    let (band, flywheel) = ((10.0, 60.0), 20.0);
    let scan: Vec<SteadyState> = (0..=400)
        .map(|k| at(band.0 + (band.1 - band.0) * k as f64 / 400.0, flywheel).unwrap())
        .collect();
    let cs: Vec<f64> = scan.iter().map(|s| s.cs).collect();
    let top = cs.iter().cloned().fold(0.0, f64::max);
    let low = cs.iter().cloned().fold(f64::INFINITY, f64::min);
    // Cs falls with the speed and then rises (J's swing): both ends matter.
    assert!(
        low < 0.5 * cs[0].min(cs[400]),
        "{low} vs {} {}",
        cs[0],
        cs[400]
    );
    for (cs, proven) in [(1.01 * top, true), (0.5 * (low + top), false)] {
        let mut warnings = Vec::new();
        let solve = |w: f64, _: usize| at(w, flywheel);
        let c = BandCheck::prove(cs, band, &["one"], solve, &mut warnings).unwrap();
        assert_eq!(c.proven, proven, "cs {cs}: {c:?}");
        for s in &scan {
            assert!(s.cs <= c.cs_bound + c.cs_bound_error + s.cs_error, "{c:?}");
        }
        assert_eq!(warnings.is_empty(), proven, "{warnings:?}");
    }
}

/// With the flywheel whose Cs is `cs` exactly at the band's governing end (the least
/// flywheel of the ends, as the families size it), the band is proven to within the
/// bound's error, and the bound is that end's Cs to within it.
#[test]
fn a_band_governed_by_its_end_is_proven() {
    let (band, flywheel) = ((10.0, 14.0), 20.0);
    let cs = at(band.0, flywheel).unwrap().cs;
    assert!(cs > at(band.1, flywheel).unwrap().cs);
    let mut warnings = Vec::new();
    let solve = |w: f64, _: usize| at(w, flywheel);
    let c = BandCheck::prove(cs, band, &["one"], solve, &mut warnings).unwrap();
    assert!(c.proven, "{c:?} {warnings:?}");
    assert!(c.cs_bound - cs <= c.cs_bound_error, "{c:?}");
    assert!(c.speeds < BAND_MAX_SPEEDS, "{c:?}");
}

/// Without a load (W ≡ 0), ω ∝ 1/√(J + I_f) at every speed: Cs does not depend on the
/// speed and every interval's bound is Cs itself.
#[test]
fn a_band_without_load_is_proven_at_once() {
    let j = |phi: f64| [2.0 + 1.2 * (2.0 * phi).cos(), -2.4 * (2.0 * phi).sin(), 0.0];
    let s = DriveSettings::default();
    let solve = |w: f64, _: usize| {
        steady_state(&j, &Motor::ConstantTorque, 0.5, w, &s).map_err(|e| e.to_string())
    };
    let cs = solve(10.0, 0).unwrap().cs;
    let mut warnings = Vec::new();
    let c = BandCheck::prove(cs, (5.0, 50.0), &["bare"], solve, &mut warnings).unwrap();
    assert!(c.proven && c.speeds == BAND_CHECK_SPEEDS + 2, "{c:?}");
    assert!((c.cs_bound - cs).abs() <= c.cs_bound_error, "{c:?}");
}
