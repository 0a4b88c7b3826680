//! The flywheel-inertia objective (issue 33, "design for the drive"): the counterweight whose
//! exact least flywheel for the drive's Cs is least, found by a search (`best_found` with its
//! evidence), checked against brute force over the allowed disc and the limit.

use cwsynth::families::slider_crank::file::SliderCrankProblem;
use cwsynth::families::slider_crank::flywheel_design::least_flywheel_of;
use cwsynth::families::{parse_str, solve_scene};
use cwsynth::geom::P2;
use cwsynth::report::Status;
use std::f64::consts::TAU;
use std::path::Path;

/// The paper piston standing (gravity along the slider), Cs 0.02, a constant-torque motor, the
/// counterweight at 50 mm under a 400 N peak-force limit.
const PISTON: &str = r#"
name = "piston-flywheel-design"
family = "slider-crank"

[mechanism]
crank_radius = "35 mm"
rod_length = "140 mm"
speed = "1000 rpm"
crank_mass = "0.35 kg"
rod_mass = "0.30 kg"
slider_mass = "1.03 kg"
slider_axis_angle = "90 deg"

[mechanism.drive]
cs = 0.02
motor = "constant-torque"

[model]
gravity = true

[design]
unbalance = { min = "0 kg*m", max = "0.2 kg*m" }
angle = { min = "0 deg", max = "360 deg" }
radius = "50 mm"

[objective]
minimize = "flywheel-inertia"
max_peak_force = "400 N"
"#;

#[test]
fn the_least_flywheel_design_is_unbeaten_by_brute_force_within_the_limit() {
    let scene = parse_str(PISTON, Path::new("f.toml")).unwrap();
    let r = solve_scene(&scene);
    assert_eq!(r.status, Status::BestFound, "{:?}", r.warnings);
    assert_eq!(r.objective.as_deref(), Some("flywheel_inertia_kgm2"));
    let search = r.search.as_ref().expect("the search's evidence");
    assert!(search.starts >= 4 && search.evaluations > 0, "{search:?}");
    let found = r.objectives["flywheel_inertia_kgm2"];
    assert!(r.objectives["peak_shaking_force_n"] <= 400.0 * (1.0 + 1e-9));
    // The drive of the design agrees with the search's figure.
    assert!((r.derived["flywheel_least_kgm2"] - found).abs() <= 1e-9 * found);
    // Every baseline needs more flywheel.
    for (name, b) in &r.baselines {
        assert!(b["flywheel_inertia_kgm2"] >= found, "{name}");
    }
    // Brute force: 21 × 24 designs of the allowed disc, those within the limit.
    let p = scene.machine::<SliderCrankProblem>().unwrap();
    let d = p.drive.as_ref().unwrap();
    let mut best = f64::INFINITY;
    for i in 0..=20 {
        for k in 0..24 {
            let (m, b) = (0.01 * i as f64, TAU * k as f64 / 24.0);
            let u = P2::new(m * b.cos(), m * b.sin());
            let peak = cwsynth::families::slider_crank::synth::metrics(&p.core, u)
                .unwrap()
                .peak;
            if peak <= 400.0 {
                best = best.min(least_flywheel_of(p, d, u).unwrap());
            }
        }
    }
    eprintln!("flywheel design: found {found:.9} kg·m², brute force over the grid {best:.9}");
    assert!(found <= best * (1.0 + 1e-9), "{found} vs {best}");
}

#[test]
fn the_flywheel_objective_needs_a_cs_and_a_lone_counterweight() {
    let no_cs = PISTON.replace("cs = 0.02\n", "");
    let e = parse_str(&no_cs, Path::new("f.toml")).unwrap_err();
    assert_eq!(e.field(), Some("objective.minimize"), "{e}");
    let with_plate = PISTON.replace(
        "[objective]",
        "[design.balancers]\norders = [2]\n\n[objective]",
    );
    let e = parse_str(&with_plate, Path::new("f.toml")).unwrap_err();
    assert_eq!(e.field(), Some("design.balancers"), "{e}");
}
