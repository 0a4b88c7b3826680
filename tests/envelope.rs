//! The operating envelope (issue 33, item 3), checked independently: the certified worst case
//! against brute force over the design (the worst over the vertices evaluated by the family's
//! own figures, not the envelope code) and against 10⁵ random samples of the box evaluated
//! from the affine structure on a fine angle grid (none may exceed the worst case beyond its
//! error); the length tolerances' `best_found`; the input errors; thread-count independence.

use cwsynth::families::slider_crank::file::SliderCrankProblem;
use cwsynth::families::slider_crank::synth::{
    energy_fluctuation, metrics, optimise, sensitivity_table, shaking_force, Objective, Scene,
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
    cut(PISTON, "\n[[mechanism.envelope.length]]")
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

/// The envelope's worst case solved as one disc over the top-speed vertices' curves (the
/// engine's exact disc path) against clarabel's exchange rounds over every scenario
/// (`exact_disc = false`): the same design and worst case within both certificates' gaps,
/// both `optimal`, the disc path's sensitivities from its support weights equal to the
/// rounds' Newton multipliers within their stated errors.
#[test]
fn the_envelopes_disc_path_agrees_with_clarabels_rounds() {
    let sc = piston_masses();
    let disc = optimise(&sc).unwrap();
    let mut general = sc.clone();
    general.settings.exact_disc = false;
    let rounds = optimise(&general).unwrap();
    assert!(
        disc.method.contains("smallest enclosing disc"),
        "{}",
        disc.method
    );
    assert!(
        !rounds.method.contains("smallest enclosing disc"),
        "{}",
        rounds.method
    );
    for o in [&disc, &rounds] {
        assert_eq!(o.status, CwStatus::Optimal, "{}", o.method);
    }
    let (wd, wr) = (worst_force(&sc, disc.u), worst_force(&sc, rounds.u));
    let tol = disc.gap.max(0.0) + rounds.gap.max(0.0) + 1e-9 * wd;
    assert!((wd - wr).abs() <= tol, "{wd} against {wr} (±{tol})");
    assert!(
        (disc.u - rounds.u).norm() <= 1e-6 * disc.u.norm(),
        "{:?} {:?}",
        disc.u,
        rounds.u
    );
    let (sd, sr) = (
        sensitivity_table(&sc, disc.duals.as_ref().unwrap()).unwrap(),
        sensitivity_table(&general, rounds.duals.as_ref().unwrap()).unwrap(),
    );
    assert_eq!(sd.len(), sr.len());
    for (a, b) in sd.iter().zip(&sr) {
        let bar = a.error + b.error + 1e-9 * a.derivative.abs().max(1.0);
        assert!(
            (a.derivative - b.derivative).abs() <= bar,
            "{:?} {:?}: {} against {} (±{bar})",
            a.parameter,
            a.end,
            a.derivative,
            b.derivative
        );
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

/// `text` without its lines from `from` up to `[model]`.
fn cut(text: &str, from: &str) -> String {
    let i = text.find(from).unwrap();
    let j = text.find("\n[model]").unwrap();
    format!("{}{}", &text[..i], &text[j..])
}

/// The scene of `text` without its Monte Carlo check (the shipped files ask for the
/// sensitivity table), its result (`optimal`) and the table's rows.
fn sensitivity_rows(
    text: String,
) -> (
    cwsynth::families::Scene,
    cwsynth::report::SolveResult,
    Vec<serde_json::Value>,
) {
    let text = text.replace("monte_carlo = 2000", "monte_carlo = 0");
    let s = parse_str(&text, Path::new("s.toml")).unwrap();
    let r = solve_scene(&s);
    assert_eq!(r.status, Status::Optimal, "{:?}", r.warnings);
    let rows = r.extra["envelope"]["sensitivities"]
        .as_array()
        .unwrap()
        .clone();
    (s, r, rows)
}

/// The sensitivity table against closed forms and re-solves of the nominal scene. Over a
/// speed band alone (no gravity) every force scales with ω², so the optimal design does not
/// depend on the speed and the worst case is V*(ω_max) = V₁ (ω_max/ω₁)²: dV*/dω_max =
/// 2 V*/ω_max and dV*/dω_min = 0. With the masses too, where the vertex (ω_max, m_max, …)
/// alone binds, V* is the nominal minimax of that vertex's machine, so dV*/d(m_max) is the
/// derivative of the nominal minimax in that mass (central differences of nominal solves).
#[test]
fn sensitivities_match_the_closed_form_speed_law_and_nominal_re_solves() {
    let (_, r, rows) = sensitivity_rows(cut(PISTON, "\n[[mechanism.envelope.mass]]"));
    assert_eq!(rows.len(), 2);
    let v = r.objectives["worst_case_peak_shaking_force_n"];
    let w_max = 1200.0 * TAU / 60.0;
    let (lo, hi) = (&rows[0], &rows[1]);
    assert_eq!(lo["end"], "min");
    assert_eq!(hi["end"], "max");
    let f = |x: &serde_json::Value, k: &str| x[k].as_f64().unwrap();
    let want = 2.0 * v / w_max;
    assert!(
        (f(hi, "derivative") - want).abs() <= f(hi, "error") + 1e-9 * want,
        "dV/dω_max {} ± {} vs 2V/ω = {want}",
        f(hi, "derivative"),
        f(hi, "error")
    );
    assert!(f(hi, "error") < 1e-5 * want, "{}", f(hi, "error"));
    assert!(f(lo, "derivative").abs() <= f(lo, "error") + 1e-9 * want);

    // The speed band and the slider's ±2 % (the rod's too would make two vertices bind):
    // the slider mass's upper end against nominal re-solves of the binding vertex.
    let rod = "\n[[mechanism.envelope.mass]]\nof = \"rod_mass\"";
    let (s, r, rows) = sensitivity_rows(cut(&piston_masses_text(), rod));
    let row = rows
        .iter()
        .find(|x| x["parameter"] == "slider_mass_delta_kg" && x["end"] == "max")
        .unwrap();
    let sc = s.machine::<SliderCrankProblem>().unwrap().core.clone();
    let d_hi = sc.envelope.masses[0].delta.1;
    let nominal_at = |dm: f64| {
        let mut v = sc.envelope.at(&sc, vec![w_max, d_hi + dm]).scene;
        v.objective = Objective::MinPeakForce;
        let o = optimise(&v).unwrap();
        metrics(&v, o.u).unwrap().peak
    };
    // The premise: that vertex alone binds, so V* is its own minimax.
    let v = r.objectives["worst_case_peak_shaking_force_n"];
    assert!(
        (v - nominal_at(0.0)).abs() < 1e-8 * v,
        "{v} vs {}",
        nominal_at(0.0)
    );
    let h = 1e-3 * d_hi;
    let reference = (nominal_at(h) - nominal_at(-h)) / (2.0 * h);
    assert!(
        (f(row, "derivative") - reference).abs() <= f(row, "error") + 1e-5 * reference.abs(),
        "dV/dm {} ± {} vs nominal re-solves {reference}",
        f(row, "derivative"),
        f(row, "error")
    );
}

/// A limit no design meets over the envelope is `infeasible`, and how far off it is counts
/// over the envelope too: the least worst case any design reaches (the envelope's own
/// optimum, certified for masses and speed), not the nominal scene's least peak (reported
/// before: 10.0006 N·m for a torque limit whose worst case is 14.78 N·m at 1200 rpm).
#[test]
fn an_unreachable_limit_over_the_envelope_says_how_far_off_its_worst_case_is() {
    let free = solve_scene(&parse_str(&piston_masses_text(), Path::new("f.toml")).unwrap());
    assert_eq!(free.status, Status::Optimal);
    let best = free.objectives["worst_case_peak_shaking_force_n"];
    let text = piston_masses_text().replace(
        "minimize = \"peak-force\"",
        "minimize = \"peak-force\"\nmax_peak_force = \"300 N\"\nmax_peak_torque = \"1 N*m\"",
    );
    let r = solve_scene(&parse_str(&text, Path::new("i.toml")).unwrap());
    assert_eq!(r.status, Status::Infeasible, "{:?}", r.status_detail);
    let rows = &r.infeasibility;
    assert_eq!(rows.len(), 2);
    let force = rows
        .iter()
        .find(|s| s.limit == "objective.max_peak_force")
        .unwrap();
    assert!(force.certified);
    assert!(
        (force.closest - best).abs() <= force.error + 1e-9 * best,
        "{} vs the envelope's optimum {best}",
        force.closest
    );
    let torque = rows
        .iter()
        .find(|s| s.limit == "objective.max_peak_torque")
        .unwrap();
    let worst_torque = free.objectives["worst_case_peak_drive_torque_nm"];
    assert!(
        (torque.closest - worst_torque).abs() <= 1e-9 * worst_torque,
        "{} vs {worst_torque}",
        torque.closest
    );
    assert!(torque.closest > 1.4 * r.objectives["peak_drive_torque_nm"]);
}
