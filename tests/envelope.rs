//! The operating envelope (issue 33, item 3), checked independently: the certified worst case
//! against brute force over the design (the worst over the vertices evaluated by the family's
//! own figures, not the envelope code) and against 10⁵ random samples of the box evaluated
//! from the affine structure on a fine angle grid (none may exceed the worst case beyond its
//! error); the length tolerances' `best_found`; the input errors; thread-count independence.

use cwsynth::families::slider_crank::file::SliderCrankProblem;
use cwsynth::families::slider_crank::synth::{
    energy_fluctuation, metrics, optimise, shaking_force, Objective, Scene,
};
use cwsynth::families::{parse_str, solve_scene};
use cwsynth::geom::P2;
use cwsynth::report::Status;
use cwsynth::synth::counterweight::Status as CwStatus;
use std::f64::consts::TAU;
use std::path::Path;

use crate::common::{self, Lcg};

const PISTON: &str = include_str!("../problems/piston-1000rpm-envelope.toml");
const FELLING: &str = include_str!("../problems/felling-head-envelope.toml");

/// The scene of `text` (with `edit` applied).
fn scene(text: &str, edit: impl Fn(String) -> String) -> Scene {
    let s = parse_str(&edit(text.to_string()), Path::new("env.toml")).unwrap();
    s.machine::<SliderCrankProblem>().unwrap().core.clone()
}

/// The piston file without its length tolerance (speed and ±2 % masses: certified).
fn piston_masses_text() -> String {
    let i = PISTON.find("\n[[mechanism.envelope.length]]").unwrap();
    let j = PISTON.find("\n[model]").unwrap();
    format!("{}{}", &PISTON[..i], &PISTON[j..])
}

/// The piston over speed and ±2 % masses only.
fn piston_masses() -> Scene {
    scene(&piston_masses_text(), |t| t)
}

/// max over the vertices of the design's peak force (N), from the family's `metrics`.
fn worst_force(sc: &Scene, u: P2) -> f64 {
    sc.envelope
        .scenarios(sc)
        .iter()
        .map(|s| metrics(&s.scene, u).unwrap().peak)
        .fold(0.0, f64::max)
}

#[test]
fn piston_worst_case_is_certified_and_unbeaten_by_brute_force() {
    let sc = piston_masses();
    let o = optimise(&sc).unwrap();
    assert_eq!(o.status, CwStatus::Optimal, "{}", o.method);
    let w = worst_force(&sc, o.u);
    let err = o.gap.max(0.0) + 1e-9 * w;
    // A polar grid around the optimum and over the whole bound.
    for i in 0..=20 {
        for j in 0..24 {
            let r = 0.2 * i as f64 / 20.0;
            let b = TAU * j as f64 / 24.0;
            let v = P2::new(r * b.cos(), r * b.sin());
            assert!(worst_force(&sc, v) >= w - err, "{v:?}");
        }
    }
    for k in 0..16 {
        let a = TAU * k as f64 / 16.0;
        let v = o.u + P2::new(a.cos(), a.sin()) * 2e-4;
        assert!(worst_force(&sc, v) >= w - err, "{v:?}");
    }
}

#[test]
fn a_hundred_thousand_samples_stay_under_the_certified_worst_case() {
    let sc = piston_masses();
    let r = solve_scene(&parse_str(&piston_masses_text(), Path::new("env.toml")).unwrap());
    assert_eq!(r.status, Status::Optimal);
    let worst = r.objectives["worst_case_peak_shaking_force_n"];
    let err = r.errors["worst_case_peak_shaking_force_n"];
    let u = P2::new(
        r.design["counterweight_unbalance_x_kgm"],
        r.design["counterweight_unbalance_y_kgm"],
    );
    // F(φ; ω, Δm4, Δm3) = ω² (f(φ) + Δm4 a(φ) + Δm3 c(φ)): the columns from finite
    // differences of the mechanism's own force (exact: F is affine in the masses).
    let n = 2048;
    let at = |dm4: f64, dm3: f64| -> Vec<P2> {
        let mut s = sc.clone();
        s.mech.slider_mass += dm4;
        s.mech.rod.inertia *= (s.mech.rod.mass + dm3) / s.mech.rod.mass;
        s.mech.rod.mass += dm3;
        (0..n)
            .map(|k| shaking_force(&s.mech, 1.0, u, TAU * k as f64 / n as f64).unwrap())
            .collect()
    };
    let (f, f4, f3) = (at(0.0, 0.0), at(1.0, 0.0), at(0.0, 1.0));
    let (m4, m3) = (sc.mech.slider_mass, sc.mech.rod.mass);
    let (w_lo, w_hi) = (800.0 * TAU / 60.0, 1200.0 * TAU / 60.0);
    let mut rng = Lcg(33);
    let mut largest: f64 = 0.0;
    for _ in 0..100_000 {
        let w = rng.range(w_lo, w_hi);
        let d4 = rng.range(-0.02, 0.02) * m4;
        let d3 = rng.range(-0.02, 0.02) * m3;
        let peak = (0..n)
            .map(|k| (f[k] + (f4[k] - f[k]) * d4 + (f3[k] - f[k]) * d3).norm())
            .fold(0.0, f64::max)
            * w
            * w;
        largest = largest.max(peak);
        assert!(
            peak <= worst + err + 1e-9 * worst,
            "{peak} N > {worst} ± {err} N"
        );
    }
    // The samples come close to the vertices' worst case (it is attained at a corner).
    assert!(largest > 0.98 * worst, "{largest} vs {worst}");
}

#[test]
fn felling_head_worst_delta_e_against_brute_force_and_samples() {
    let sc = scene(FELLING, |t| t);
    assert_eq!(sc.objective, Objective::MinEnergyFluctuation);
    let o = optimise(&sc).unwrap();
    assert_eq!(o.status, CwStatus::Optimal, "{}", o.method);
    let worst_de = |u: P2| {
        sc.envelope
            .scenarios(&sc)
            .iter()
            .map(|s| energy_fluctuation(&s.scene, u).unwrap()[0])
            .fold(0.0, f64::max)
    };
    let w = worst_de(o.u);
    let err = o.gap.max(0.0) + 1e-8 * w;
    let u_max = o.u.norm().max(1e-9); // on the plate's bound
    for i in 0..=8 {
        for j in 0..16 {
            let r = u_max * i as f64 / 8.0;
            let b = TAU * j as f64 / 16.0;
            let v = P2::new(r * b.cos(), r * b.sin());
            assert!(worst_de(v) >= w - err, "{v:?}: {} < {w}", worst_de(v));
        }
    }
    // Random (tree, speed) points of the box: none above the vertices' worst case.
    let mut rng = Lcg(2);
    for _ in 0..40 {
        let values = vec![rng.range(12.566, 18.849), rng.range(-50.0, 0.0)];
        let s = sc.envelope.at(&sc, values).scene;
        let de = energy_fluctuation(&s, o.u).unwrap()[0];
        assert!(de <= w + err, "{de} J > {w} J");
    }
}

#[test]
fn length_tolerances_claim_best_found_with_their_evidence() {
    let r = solve_scene(&parse_str(PISTON, Path::new("p.toml")).unwrap());
    assert_eq!(r.status, Status::BestFound);
    let why = r.status_detail.clone().unwrap();
    assert!(
        why.contains("not proven") && why.contains("quasi-Monte Carlo"),
        "{why}"
    );
    let env = &r.extra["envelope"];
    assert_eq!(env["certified"], false);
    assert_eq!(env["vertices"].as_array().unwrap().len(), 17);
    assert_eq!(
        r.objective.as_deref(),
        Some("worst_case_peak_shaking_force_n")
    );
}

#[test]
fn envelope_input_errors_name_their_field() {
    let cases = [
        (
            "of = \"slider_mass\"",
            "of = \"piston\"",
            "mechanism.envelope.mass[0].of",
            "allowed",
        ),
        (
            "tolerance = 0.02              # ±2 % of 1.03 kg",
            "tolerance = 1.5",
            "mechanism.envelope.mass[0].tolerance",
            "fraction",
        ),
        (
            "tolerance = \"0.1 mm\"",
            "tolerance = \"120 mm\"",
            "mechanism.envelope.length[0].tolerance",
            "cannot turn",
        ),
        (
            "tolerance = \"0.1 mm\"",
            "tolerance = 0.1",
            "mechanism.envelope.length[0].tolerance",
            "unit",
        ),
        (
            "monte_carlo = 2000",
            "monte_carlo = 2000000",
            "mechanism.envelope.monte_carlo",
            "allowed",
        ),
        (
            "speed = { min = \"800 rpm\", max = \"1200 rpm\" }",
            "speed = { min = \"1200 rpm\", max = \"800 rpm\" }",
            "mechanism.envelope.speed.max",
            "max ≥ min",
        ),
        (
            "minimize = \"peak-force\"",
            "minimize = \"rms-force\"",
            "objective.minimize",
            "worst case",
        ),
    ];
    for (from, to, field, says) in cases {
        let text = common::with(PISTON, from, to);
        let e = common::err(&text);
        let msg = e.to_string();
        assert!(msg.contains(field), "{to}: {msg}");
        assert!(msg.contains(says), "{to}: {msg}");
    }
}

#[test]
fn the_check_does_not_depend_on_the_thread_count() {
    let sc = piston_masses();
    let o = optimise(&sc).unwrap();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| sc.envelope.evaluate(&sc, o.u, &[], false).unwrap())
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn a_fleet_varies_the_envelope_and_reports_its_worst_cases() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("fleet.csv");
    std::fs::write(
        &csv,
        "name,mechanism.envelope.speed.max [rpm],mechanism.envelope.monte_carlo\n\
         env-a,1100,0\nenv-b,1300,0\nenv-c,900 furlong,0\n",
    )
    .unwrap();
    let template = common::problem("piston-1000rpm-envelope.toml");
    let out = dir.path().join("out");
    let st = std::process::Command::new(env!("CARGO_BIN_EXE_cwsynth"))
        .args([
            "batch",
            &format!("{}:{}", template.display(), csv.display()),
        ])
        .arg("--out")
        .arg(&out)
        .args(["--summary-only", "--quiet"])
        .status()
        .unwrap();
    assert_eq!(st.code(), Some(1), "one bad row, the others solved");
    let text = std::fs::read_to_string(out.join("fleet-fleet.csv")).unwrap();
    let mut rows = csv::Reader::from_reader(text.as_bytes());
    let head = rows.headers().unwrap().clone();
    let col = |k: &str| head.iter().position(|h| h == k).unwrap();
    let worst = col("objectives.worst_case_peak_shaking_force_n");
    let recs: Vec<csv::StringRecord> = rows.records().map(|r| r.unwrap()).collect();
    let w = |i: usize| recs[i][worst].parse::<f64>().unwrap();
    assert_eq!(&recs[0][col("status")], "best_found");
    // The worst case is at the band's top speed: it grows as ω².
    let ratio = w(1) / w(0);
    assert!(
        (ratio / (1300.0f64 / 1100.0).powi(2) - 1.0).abs() < 0.01,
        "{ratio}"
    );
    assert_eq!(&recs[2][col("status")], "error", "{:?}", recs[2]);
    assert!(recs[2][col("message")].contains("mechanism.envelope.speed.max"));
}
