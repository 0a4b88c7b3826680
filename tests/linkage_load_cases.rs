//! The linkage's named load cases (issue 33, item 3: `[[mechanism.load_cases]]`) against
//! independent evaluations: each case's scenario is the file rewritten with that case's
//! loads as its own `[[mechanism.loads]]` and the speed at the band's end (parsed and scanned
//! afresh, not through the envelope), the shaking force is the same in every case (the frame
//! reacts the loads), no random design has a smaller worst torque over all the scenarios,
//! and the errors name their key.

use crate::common::{err, problem, set_key, Lcg};
use crate::linkage_envelope::random_design;
use cwsynth::families::linkage::file::LinkageProblem;
use cwsynth::families::linkage::solve_envelope::peaks;
use cwsynth::families::linkage::synth as ls;
use cwsynth::families::{parse_str, solve_scene};
use cwsynth::report::Status;
use serde_json::Value;
use std::path::Path;

fn press() -> String {
    std::fs::read_to_string(problem("linkage-sixbar-press-load-cases.toml")).unwrap()
}

/// The blanking case's table, as the file gives it.
const BLANKING: &str = r#"angles = ["195 deg", "200 deg", "222 deg", "225 deg"]
forces = ["0 N", "10 kN", "10 kN", "0 N"]"#;

/// The press without its envelope and cases, at `speed`, with `loads` (the body of one
/// `[[mechanism.loads]]` table's angles and forces; `None`: no load) in place of its own.
fn single(text: &str, speed: &str, loads: Option<&str>) -> String {
    let (a, b) = (
        text.find("[mechanism.envelope]").unwrap(),
        text.find("[[mechanism.dyads]]").unwrap(),
    );
    let t = format!("{}{}", &text[..a], &text[b..]);
    let t = set_key(&t, "mechanism.speed", &format!("\"{speed}\""));
    let (c, d) = (
        t.find("angles = [\"185 deg\"").unwrap(),
        t.find("\n\n[[mechanism.dyads]]").unwrap(),
    );
    match loads {
        Some(l) => format!("{}{l}{}", &t[..c], &t[d..]),
        None => {
            let e = t.find("\n[[mechanism.loads]]").unwrap();
            format!("{}{}", &t[..e], &t[d..])
        }
    }
}

/// The design's figures of one row of the result's `envelope.scenarios`.
fn row(r: &Value, i: usize) -> (String, f64, f64, f64) {
    let s = &r["envelope"]["scenarios"][i];
    (
        s["case"].as_str().unwrap().to_string(),
        s["values"][0].as_f64().unwrap(),
        s["peak_shaking_force_n"][0].as_f64().unwrap(),
        s["peak_input_torque_nm"][0].as_f64().unwrap(),
    )
}

#[test]
fn each_case_is_the_file_with_its_loads_and_the_force_is_the_same_in_all() {
    let text = press();
    let s = parse_str(&text, Path::new("press.toml")).unwrap();
    let r = solve_scene(&s);
    assert_eq!(r.status, Status::Optimal, "{:?}", r.warnings);
    assert_eq!(
        r.objective.as_deref(),
        Some("worst_case_peak_input_torque_nm")
    );
    let json = serde_json::to_value(&r).unwrap();
    let p: &LinkageProblem = s.machine().unwrap();
    let x = ls::solve(&p.scene, &p.settings).unwrap().design.unwrap().x;
    let x = &x[..4 * p.scene.counterweights.len()];
    // Scenarios: the nominal scene, then 110 and 130 rpm in each of the three cases.
    let names = [
        "nominal",
        "nominal",
        "nominal",
        "10 kN blanking",
        "10 kN blanking",
        "idle",
        "idle",
    ];
    let own = &text[text.find("angles = [\"185 deg\"").unwrap()
        ..text.find("\n\n[mechanism.envelope]").unwrap()];
    for (i, name) in names.iter().enumerate() {
        let (case, omega, force, torque) = row(&json, i);
        assert_eq!(&case, name);
        let rpm = omega * 60.0 / std::f64::consts::TAU;
        let speed = format!("{rpm:.12} rpm");
        let alone = match *name {
            "nominal" => single(&text, &speed, Some(own)),
            "idle" => single(&text, &speed, None),
            _ => single(&text, &speed, Some(BLANKING)),
        };
        let sa = parse_str(&alone, Path::new("alone.toml")).unwrap();
        let pa: &LinkageProblem = sa.machine().unwrap();
        let [(f, fe), _, (t, te)] = peaks(&pa.scene, Some(x), &pa.settings).unwrap();
        assert!(
            (f - force).abs() <= 2.0 * fe + 1e-9 * f,
            "{name} {rpm}: force {f} vs {force}"
        );
        assert!(
            (t - torque).abs() <= 2.0 * te + 1e-9 * t,
            "{name} {rpm}: torque {t} vs {torque}"
        );
        // The loads are the frame's: every case's force is its speed's nominal one.
        if i > 0 {
            let (_, _, nominal_force, _) = row(&json, 1 + (i - 1) % 2);
            assert_eq!(force, nominal_force, "{name} at {rpm} rpm");
        }
    }
    // The worst torque is the blanking stroke's, the worst force the first of the equal ones.
    let worst = &json["envelope"]["worst"];
    let (case, ..) = row(&json, worst[2]["vertex"].as_u64().unwrap() as usize);
    assert_eq!(case, "10 kN blanking");
    assert_eq!(worst[0]["vertex"].as_u64(), Some(2));
    let mc = &json["envelope"]["monte_carlo"];
    assert_eq!(mc["samples"].as_u64(), Some(600), "200 points × 3 cases");
    assert_eq!(mc["beyond_worst_case"].as_u64(), Some(0));
}

#[test]
fn no_random_design_has_a_smaller_worst_torque_over_the_cases() {
    let text = set_key(&press(), "mechanism.envelope.monte_carlo", "0");
    let s = parse_str(&text, Path::new("press.toml")).unwrap();
    let r = solve_scene(&s);
    let (w, e) = (
        r.objectives["worst_case_peak_input_torque_nm"],
        r.errors["worst_case_peak_input_torque_nm"],
    );
    let p: &LinkageProblem = s.machine().unwrap();
    let scenes: Vec<_> = std::iter::once(p.scene.clone())
        .chain(ls::vertex_scenes(&p.scene).unwrap())
        .collect();
    assert_eq!(scenes.len(), 7);
    let worst = |x: &[f64]| {
        scenes
            .iter()
            .map(|sc| peaks(sc, Some(x), &p.settings).unwrap()[2].0)
            .fold(0.0, f64::max)
    };
    let mut rng = Lcg(11);
    for _ in 0..40 {
        let x = random_design(p, &mut rng);
        let wx = worst(&x);
        assert!(wx >= w - e - 1e-9 * w, "{wx} < {w} − {e}");
    }
}

#[test]
fn load_case_errors_name_their_key() {
    let text = press();
    let bad = |t: &str, field: &str| {
        let e = err(t).to_string();
        assert!(e.contains(field), "{field}: {e}");
    };
    let idle = "name = \"idle\"";
    let ram = "point = \"ram.pivot\"\ndirection = \"90 deg\"\nangles = [\"195";
    for (from, to, field) in [
        (
            idle,
            "name = \"10 kN blanking\"",
            "mechanism.load_cases[1].name",
        ),
        (idle, "name = \"nominal\"", "mechanism.load_cases[1].name"),
        (idle, "name = \"a, b\"", "mechanism.load_cases[1].name"),
        (
            "\"10 kN\", \"10 kN\", \"0 N\"]",
            "\"10 kN\", \"0 N\"]",
            "mechanism.load_cases[0].loads[0].forces",
        ),
        (
            "forces = [\"0 N\", \"10 kN\"",
            "forces = [\"0\", \"10 kN\"",
            "forces",
        ),
        (
            ram,
            &ram.replace("ram.", "bed."),
            "mechanism.load_cases[0].loads[0].point",
        ),
    ] {
        bad(&text.replacen(from, to, 1), field);
    }
    let many: String = (0..17)
        .map(|i| format!("\n[[mechanism.load_cases]]\nname = \"case {i}\"\n"))
        .collect();
    bad(
        &text.replacen(
            "\n[[mechanism.dyads]]",
            &format!("{many}\n[[mechanism.dyads]]"),
            1,
        ),
        "mechanism.load_cases[16]",
    );
    bad(
        &set_key(&text, "objective.minimize", "\"rms-torque\""),
        "objective.minimize",
    );
}

/// With `[mechanism.drive]`: each case's drive, at the nominal speed and at both ends of the
/// speed band, is the drive of the file rewritten with that case's loads at that speed (at
/// the same design, through `linkage::drive::figures` on the rewritten scene); the flywheel
/// of all of them is the largest least flywheel — at the band's lower end: I grows as ω̄
/// falls —, every one meets Cs with it, and 0.1 % less misses Cs in the governing one.
#[test]
fn the_flywheel_of_all_the_cases_is_the_largest_least_one() {
    use cwsynth::dynamics::Drive;
    use cwsynth::families::linkage::drive::figures;
    let text = set_key(&press(), "mechanism.envelope.monte_carlo", "0");
    let s = parse_str(&text, Path::new("press.toml")).unwrap();
    let json = serde_json::to_value(solve_scene(&s)).unwrap();
    let lc = &json["load_cases"];
    let p: &LinkageProblem = s.machine().unwrap();
    let x = ls::solve(&p.scene, &p.settings).unwrap().design.unwrap().x;
    let x = &x[..4 * p.scene.counterweights.len()];
    let d = p.drive.as_ref().unwrap();
    let own = &text[text.find("angles = [\"185 deg\"").unwrap()
        ..text.find("\n\n[mechanism.envelope]").unwrap()];
    let cases = [
        ("nominal", Some(own)),
        ("10 kN blanking", Some(BLANKING)),
        ("idle", None),
    ];
    let speeds = [
        ("120 rpm", ""),
        ("110 rpm", " at 110 rpm"),
        ("130 rpm", " at 130 rpm"),
    ];
    let mut least: Vec<(f64, String, &str, Option<&str>)> = Vec::new();
    for (i, (name, loads)) in cases.into_iter().enumerate() {
        for (j, (speed, suffix)) in speeds.into_iter().enumerate() {
            let row = &lc["cases"][3 * i + j];
            let label = format!("{name}{suffix}");
            assert_eq!(row["case"], label.as_str());
            let alone = parse_str(&single(&text, speed, loads), Path::new("a.toml")).unwrap();
            let pa: &LinkageProblem = alone.machine().unwrap();
            assert_eq!(row["speed_rad_s"].as_f64(), Some(pa.scene.linkage.omega()));
            let f = figures(&pa.scene, d, Some(x)).unwrap();
            let fw = f.flywheel.unwrap();
            let close = |key: &str, v: f64| {
                let got = row[key].as_f64().unwrap();
                assert!(
                    (got - v).abs() <= 1e-9 * v.abs().max(1e-12),
                    "{label} {key}: {got} vs {v}"
                );
            };
            close("energy_fluctuation_j", f.constant.energy_fluctuation);
            close("flywheel_least_kgm2", fw.inertia);
            close("flywheel_textbook_kgm2", fw.textbook);
            least.push((fw.inertia, label.clone(), speed, loads));
            // Every scenario meets Cs with the flywheel of all of them.
            let cs = row["steady_cs"].as_f64().unwrap();
            assert!(
                cs <= 0.1 + row["steady_cs_error"].as_f64().unwrap(),
                "{label}: Cs {cs}"
            );
        }
    }
    assert_eq!(lc["count"], 9);
    let istar = lc["flywheel_kgm2"].as_f64().unwrap();
    let most = least.iter().max_by(|a, b| a.0.total_cmp(&b.0)).unwrap();
    assert_eq!(istar, most.0);
    assert_eq!(lc["flywheel_case"], most.1.as_str());
    assert!(most.1.ends_with(" at 110 rpm"), "{}", most.1);
    // The nominal speed alone would have sized the flywheel too small.
    let at_120 = least.iter().step_by(3).map(|l| l.0).fold(0.0, f64::max);
    assert!(istar > 1.05 * at_120, "{istar} vs {at_120} at 120 rpm");
    assert_eq!(
        json["derived"]["load_cases_flywheel_kgm2"].as_f64(),
        Some(istar)
    );
    // Over the band (its ends and 7 speeds inside per case, more where the proof needs
    // them; I* given): proven within Cs, and the largest solved Cs is the file's own steady
    // state at that speed and case.
    let band = &lc["speed_band_check"];
    assert!(band["speeds"].as_u64().unwrap() >= 9, "{band}");
    assert_eq!(band["beyond"], 0);
    assert_eq!(band["proven"], true, "{band}");
    assert_eq!(band["open_intervals"], 0, "{band}");
    let bound = band["cs_bound"].as_f64().unwrap() - band["cs_bound_error"].as_f64().unwrap();
    assert!(bound <= 0.1, "{band}");
    let (w, worst) = (
        band["max_cs_speed_rad_s"].as_f64().unwrap(),
        band["max_cs"].as_f64().unwrap(),
    );
    assert!(w >= 110.0 / 60.0 * std::f64::consts::TAU && w <= 130.0 / 60.0 * std::f64::consts::TAU);
    let loads = cases.iter().find(|c| band["max_cs_case"] == c.0).unwrap().1;
    let rpm = format!("{:.9} rpm", w * 60.0 / std::f64::consts::TAU);
    let alone = parse_str(&single(&text, &rpm, loads), Path::new("a.toml")).unwrap();
    let pa: &LinkageProblem = alone.machine().unwrap();
    let given = Drive {
        cs: None,
        flywheel: Some(istar),
        motor: d.motor.clone(),
    };
    let st = figures(&pa.scene, &given, Some(x)).unwrap().steady;
    assert!(
        (st.cs - worst).abs() <= 1e-6 * worst,
        "{} vs {worst}",
        st.cs
    );
    let worst_error = band["max_cs_error"].as_f64().unwrap();
    assert!(worst <= 0.1 + worst_error, "{worst} ± {worst_error}");
    // 0.1 % less flywheel misses Cs in the governing scenario.
    let alone = parse_str(&single(&text, most.2, most.3), Path::new("a.toml")).unwrap();
    let pa: &LinkageProblem = alone.machine().unwrap();
    let short = Drive {
        cs: None,
        flywheel: Some(0.999 * istar),
        motor: d.motor.clone(),
    };
    let st = figures(&pa.scene, &short, Some(x)).unwrap().steady;
    assert!(
        st.cs > 0.1 + st.cs_error,
        "Cs {} with 0.1 % less flywheel",
        st.cs
    );
}

/// Every load case is drawn beside the governing one (`drive-cases`): its drive torque at
/// constant speed and its speed with the flywheel of all the cases, one line per case, each
/// steady state the one the table reports.
#[test]
fn every_case_is_plotted_with_the_flywheel_of_all_the_cases() {
    let s = parse_str(&press(), Path::new("p.toml")).unwrap();
    let mut r = solve_scene(&s);
    r.draw();
    let plot = r
        .plots
        .iter()
        .find(|p| p.suffix == "drive-cases")
        .expect("a plot of every case");
    let svg = plot.svg_or_note();
    for name in ["nominal", "10 kN blanking", "idle"] {
        assert!(svg.contains(name), "{name} is not in the plot");
    }
    assert!(
        svg.contains("flywheel 2.50435 kg·m²"),
        "the flywheel of all the cases"
    );
}
