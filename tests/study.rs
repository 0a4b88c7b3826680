//! `cwsynth study`: every rung of a slider-crank and a hypocycloid ladder resolves, the
//! default is within its tolerance of the reference, and the outputs are well formed.

use cwsynth::study::{csv, markdown, study, svg};
use std::path::Path;

#[test]
fn piston_ladder_runs_and_the_default_is_accurate() {
    let text = include_str!("../problems/piston-1000rpm.toml");
    let s = study(text, Path::new("piston-1000rpm.toml"), 1).unwrap();
    assert_eq!(s.rungs.first().unwrap().kind, "default");
    assert_eq!(s.rungs.last().unwrap().kind, "reference");
    for r in &s.rungs {
        assert!(
            !r.status.starts_with("rejected"),
            "{}: {}",
            r.label,
            r.status
        );
        assert!(r.rel_error.unwrap().is_finite());
    }
    assert!(s.rungs[0].rel_error.unwrap() < 1e-8);
    // No exchange with 8 samples is visibly worse than the default.
    let no_ex = s
        .rungs
        .iter()
        .find(|r| r.label.starts_with("8 samples"))
        .unwrap();
    assert!(no_ex.rel_error.unwrap() > 1e-4);
    assert_eq!(s.effects.len(), 3);
    assert_eq!(csv(&s).lines().count(), s.rungs.len() + 1);
    assert!(markdown(&s).contains("| reference |"));
    assert!(svg(&s).unwrap().starts_with("<svg"));
}

#[test]
fn hypocycloid_ladder_runs() {
    let text = include_str!("../problems/hypocycloid-variant1.toml");
    let s = study(text, Path::new("h.toml"), 1).unwrap();
    assert!(s.rungs.len() >= 10);
    assert!(s.rungs.iter().all(|r| r.rel_error.is_some()));
}
