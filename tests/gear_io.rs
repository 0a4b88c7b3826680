//! The eccentric-gear family end to end: every shipped problem file solves through the real
//! binary with the issue-6 contract keys and sane values (checked against closed forms, an
//! independent closure quadrature and the library's example scenes), `--out` writes every
//! file, and bad input names the file, the line and the dotted field.

use crate::common;
use common::*;
use cwsynth::families::gear::synth::{paper_table1, paper_table1_design, solve, Settings};
use cwsynth::families::parse_str;
use std::f64::consts::{PI, TAU};
use std::path::Path;

const TABLE1: &str = include_str!("../problems/gear-paper-table1.toml");

/// ρ1(α) = e cos α + sqrt(R² − e² sin² α).
fn rho1(r: f64, e: f64, a: f64) -> f64 {
    e * a.cos() + (r * r - e * e * a.sin().powi(2)).sqrt()
}

/// The closing centre distance by bisection on a plain midpoint-rule closure integral
/// (independent of the library's trapezoid + Brent).
fn closing_a(r: f64, e: f64, n1: f64, n2: f64) -> f64 {
    let j = |a: f64| {
        let n = 4000;
        (0..n)
            .map(|k| {
                let al = TAU * (k as f64 + 0.5) / n as f64;
                let p = rho1(r, e, al);
                p / (a - p)
            })
            .sum::<f64>()
            * TAU
            / n as f64
            - TAU * n2 / n1
    };
    let (mut lo, mut hi) = (r + e + 1e-9, 100.0 * r);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if j(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn every_shipped_gear_file_has_the_contract_keys() {
    let files = family_files("eccentric-gear");
    assert!(files.len() >= 2, "{files:?}");
    for p in &files {
        let v = solve_json(p);
        let name = p.display();
        assert_eq!(v["family"], "eccentric-gear");
        let (r, e, rg) = (
            num(&v, "design.pitch_radius_m"),
            num(&v, "design.eccentricity_m"),
            num(&v, "design.generating_radius_m"),
        );
        assert!(e >= 0.0 && e < r, "{name}");
        // Closure against an independent quadrature (n1/n2 = 3/1 in both files).
        let a = closing_a(r, e, 3.0, 1.0);
        assert!(
            (num(&v, "derived.center_distance_m") - a).abs() < 1e-10,
            "{name}: a = {} vs {a}",
            num(&v, "derived.center_distance_m")
        );
        // Ratio range in closed form: i12 = (a − ρ1)/ρ1 at ρ1 = R ± e.
        assert!((num(&v, "derived.ratio_min") - (a - r - e) / (r + e)).abs() < 1e-8);
        assert!((num(&v, "derived.ratio_max") - (a - r + e) / (r - e)).abs() < 1e-8);
        assert!(
            (num(&v, "objectives.ratio_variation")
                - num(&v, "derived.ratio_max") / num(&v, "derived.ratio_min"))
            .abs()
                < 1e-12
        );
        assert_eq!(num(&v, "derived.teeth_gear1"), (r / (2.0 * rg)).round());
        let mu = num(&v, "objectives.peak_sliding_coefficient");
        assert!(mu.is_finite() && mu > 0.0 && mu < 10.0, "{name}: {mu}");
        // errors has exactly the objectives' keys, all ≥ 0 and small.
        let ok: Vec<&String> = v["objectives"].as_object().unwrap().keys().collect();
        let ek: Vec<&String> = v["errors"].as_object().unwrap().keys().collect();
        assert_eq!(ok, ek, "{name}");
        for (k, x) in v["errors"].as_object().unwrap() {
            let x = x.as_f64().unwrap();
            assert!((0.0..1e-6).contains(&x), "{name}: errors.{k} = {x}");
        }
        // Poles: α1 in [0, 2π), which µ, located to 1e-12 rad; as many µ1 as µ2 ones.
        let poles = v["poles"].as_array().unwrap();
        assert!(!poles.is_empty(), "{name}");
        let mut n1 = 0;
        for p in poles {
            let al = p["alpha1_rad"].as_f64().unwrap();
            assert!((0.0..TAU).contains(&al));
            assert!(p["error_rad"].as_f64().unwrap() <= 1e-12);
            match p["which"].as_str().unwrap() {
                "mu1" => n1 += 1,
                "mu2" => {}
                w => panic!("which = {w}"),
            }
        }
        assert_eq!(2 * n1, poles.len(), "{name}");
        assert_eq!(n1 as f64, num(&v, "derived.poles_mu1_per_turn"));
        assert!(v["timing"]["solve_s"].as_f64().unwrap() > 0.0);
        // Compact: dense series live in the SVG/CSV files.
        assert!(v.get("series").is_none() && v.get("pitch_curves").is_none());
        assert!(serde_json::to_string(&v).unwrap().len() < 40_000, "{name}");
    }
}

#[test]
fn paper_table1_reports_the_closing_center_distance_and_the_inconsistencies() {
    let v = solve_json(&problem("gear-paper-table1.toml"));
    assert_eq!(v["status"], "analysed");
    assert_eq!(num(&v, "design.eccentricity_m"), 0.015);
    // Same values as the library's own Table 1 scene.
    let lib = solve(&paper_table1(), &Settings::default()).unwrap();
    for k in ["peak_sliding_coefficient", "ratio_variation"] {
        assert!(
            (num(&v, &format!("objectives.{k}")) - cwsynth::report::number_map(&lib.objectives)[k])
                .abs()
                < 1e-12
        );
    }
    assert_eq!(v["poles"].as_array().unwrap().len(), lib.poles.len());
    // The closing a12 rounds to the paper's 148 mm but is not it.
    let a = num(&v, "derived.center_distance_m");
    assert!(
        (a - 0.148).abs() < 0.05e-3 && (a - 0.148).abs() > 1e-6,
        "{a}"
    );
    let paper = v["paper"].as_array().unwrap();
    let check = |key: &str| {
        paper
            .iter()
            .find(|c| c["key"] == key)
            .unwrap_or_else(|| panic!("no paper check of {key}"))
    };
    let c = check("derived.center_distance_m");
    assert_eq!(c["paper"].as_f64().unwrap(), 0.148);
    assert!(c["diff_pct"].as_f64().unwrap().abs() < 0.05);
    assert_eq!(check("derived.teeth_gear1")["paper"], 12.0);
    assert_eq!(check("derived.teeth_gear1")["computed"], 15.0);
    assert_eq!(check("derived.teeth_gear2")["computed"], 45.0);
    // The file's own [[paper]] entry comes after the family's checks.
    let last = paper.last().unwrap();
    assert_eq!(last["key"], "derived.ratio_at_stated_center_distance");
    assert!((last["computed"].as_f64().unwrap() - 3.0).abs() < 1e-3);
    // Every inconsistency of the table is a warning naming its field.
    let w: Vec<&str> = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap())
        .collect();
    for k in [
        "mechanism.teeth_gear1",
        "mechanism.teeth_gear2",
        "mechanism.center_distance",
    ] {
        assert!(w.iter().any(|x| x.starts_with(k)), "{k}: {w:?}");
    }
    // Pitch 15.71 mm and tooth 7.85 mm agree with 4πr and 2πr to the printed rounding.
    assert!(!w.iter().any(|x| x.starts_with("mechanism.tooth_pitch")));
    assert!((num(&v, "derived.pitch_m") - 4.0 * PI * 1.25e-3).abs() < 1e-15);
}

#[test]
fn design_file_matches_the_library_scene_and_meets_its_limits() {
    let v = solve_json(&problem("gear-eccentricity-design.toml"));
    // A sampled sweep + Brent is not a certificate: best_found, with its evidence.
    assert_eq!(v["status"], "best_found");
    assert_eq!(v["status_detail"], "constraint-bound");
    assert!(v["search"]["evaluations"].as_u64().unwrap() >= 31);
    let lib = solve(&paper_table1_design(), &Settings::default()).unwrap();
    let e = num(&v, "design.eccentricity_m");
    assert!((e - lib.design.eccentricity_m).abs() < 1e-9, "{e}");
    assert!(num(&v, "objectives.peak_sliding_coefficient") <= 0.6 * (1.0 + 1e-9));
    assert!((e / 0.0375).asin() <= 30f64.to_radians());
    assert!(num(&v, "objectives.min_gear2_curvature_per_m") > 0.0);
    // The sweep's best feasible point is no better than the refined design.
    assert!(e >= num(&v, "derived.sweep_best_feasible_eccentricity_m"));
}

#[test]
fn out_dir_gets_json_markdown_svg_and_csv() {
    let dir = solve_out(&["gear-eccentricity-design.toml"]);
    let n = "gear-eccentricity-design";
    for (suffix, needle) in [
        (".json", "\"center_distance_m\""),
        (".md", "## Against the paper"),
        ("-pitch-curves.svg", "gear 2"),
        ("-sliding.svg", "poles of µ1"),
        ("-sweep.svg", "eccentricity e (mm)"),
        ("-series.csv", "alpha1_rad,i12,mu1,mu2"),
        ("-pitch-curves.csv", "gear,x_m,y_m"),
        ("-poles.csv", "alpha1_rad,which"),
        ("-sweep.csv", "eccentricity_m,center_distance_m"),
    ] {
        let p = dir.path().join(format!("{n}{suffix}"));
        let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{suffix}: {e}"));
        assert!(text.contains(needle), "{suffix} lacks {needle}");
    }
    // The series CSV has empty µ cells inside the pole windows and finite values elsewhere.
    let csv = std::fs::read_to_string(dir.path().join(format!("{n}-series.csv"))).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), Settings::default().series_points);
    assert!(rows.iter().any(|r| r[2].is_empty()));
    assert!(rows
        .iter()
        .filter(|r| !r[2].is_empty())
        .all(|r| r[2].parse::<f64>().unwrap().abs() <= 0.6 * (1.0 + 1e-9)));
    let sweep = std::fs::read_to_string(dir.path().join(format!("{n}-sweep.csv"))).unwrap();
    assert_eq!(sweep.lines().count(), 32);
}

// --- bad input -----------------------------------------------------------------------

#[test]
fn the_table1_file_resolves_to_the_library_scene() {
    let s = parse_str(TABLE1, Path::new("t.toml")).unwrap();
    let Some(p) = s.machine::<cwsynth::families::gear::file::GearProblem>() else {
        panic!("not a gear scene")
    };
    // mm → m may round in the last bit: compare that field approximately.
    let mut g = p.gear.clone();
    assert!((g.tooth_pitch.unwrap() - 15.71e-3).abs() < 1e-17);
    g.tooth_pitch = paper_table1().tooth_pitch;
    assert_eq!(g, paper_table1());
    assert_eq!(p.settings, Settings::default());
}

#[test]
fn unknown_and_missing_fields() {
    let t = with(
        TABLE1,
        "speed = \"15 rad/s\"",
        "speed = \"15 rad/s\"\nspeeed = 3",
    );
    assert_names(&t, "mechanism.speeed", "speeed", "unknown field `speeed`");
    let t = with(
        TABLE1,
        "pole_window = \"0.01 rad\"",
        "pole_widow = \"0.01 rad\"",
    );
    assert_names(
        &t,
        "model.pole_widow",
        "pole_widow",
        "unknown field `pole_widow`",
    );
    let e = err(&with(
        TABLE1,
        "pitch_radius = \"37.5 mm\"      # R, Table 1\n",
        "",
    ));
    assert!(
        e.to_string().contains("missing field `pitch_radius`"),
        "{e}"
    );
    assert_eq!(e.field(), Some("mechanism.pitch_radius"));
    let t = with(TABLE1, "eccentricity = \"15 mm\"", "# no e");
    assert_names(&t, "design.eccentricity", "[design]", "missing; allowed");
    let t = with(TABLE1, "teeth_gear2 = 36\n", "");
    assert_names(
        &t,
        "mechanism.teeth_gear2",
        "[mechanism]",
        "both teeth_gear1 and teeth_gear2",
    );
}

#[test]
fn negative_nan_and_wrong_unit() {
    let t = with(TABLE1, "\"37.5 mm\"", "\"-37.5 mm\"");
    assert_names(
        &t,
        "mechanism.pitch_radius",
        "pitch_radius",
        "allowed: a value > 0",
    );
    let t = with(TABLE1, "\"1.25 mm\"", "\"NaN mm\"");
    assert_names(
        &t,
        "mechanism.generating_radius",
        "generating_radius",
        "not a finite number",
    );
    let t = with(TABLE1, "\"15 rad/s\"", "nan");
    assert_names(&t, "mechanism.speed", "speed", "not a finite number");
    let t = with(TABLE1, "\"15 rad/s\"", "\"15 mm\"");
    assert_names(
        &t,
        "mechanism.speed",
        "speed",
        "`mm` is a unit of length, but this field is a rotational speed",
    );
    let t = with(
        TABLE1,
        "eccentricity = \"15 mm\"",
        "eccentricity = \"15 deg\"",
    );
    assert_names(
        &t,
        "design.eccentricity",
        "eccentricity",
        "is a unit of plane angle",
    );
    let t = with(
        TABLE1,
        "eccentricity = \"15 mm\"",
        "eccentricity = \"-1 mm\"",
    );
    assert_names(
        &t,
        "design.eccentricity",
        "eccentricity",
        "allowed: a value ≥ 0",
    );
    let t = with(TABLE1, "turns_gear2 = 1", "turns_gear2 = -1");
    assert_names(&t, "mechanism.turns_gear2", "turns_gear2", "u32");
}

#[test]
fn geometry_checks_name_their_field() {
    // e ≥ R: the pivot is outside the pitch circle.
    for e in [
        "\"37.5 mm\"",
        "\"40 mm\"",
        "{ min = \"0 mm\", max = \"38 mm\" }",
    ] {
        let t = with(
            TABLE1,
            "eccentricity = \"15 mm\"",
            &format!("eccentricity = {e}"),
        );
        assert_names(
            &t,
            "design.eccentricity",
            "eccentricity",
            "allowed: 0 ≤ e < R",
        );
    }
    let t = with(
        TABLE1,
        "eccentricity = \"15 mm\"",
        "eccentricity = { min = \"20 mm\", max = \"10 mm\" }",
    );
    assert_names(
        &t,
        "design.eccentricity",
        "eccentricity",
        "allowed: min ≤ max",
    );
    let t = with(TABLE1, "\"1.25 mm\"", "\"1.3 mm\"");
    assert_names(
        &t,
        "mechanism.generating_radius",
        "generating_radius",
        "even integer",
    );
    let t = with(TABLE1, "turns_gear1 = 3", "turns_gear1 = 0");
    assert_names(
        &t,
        "mechanism.turns_gear1",
        "turns_gear1",
        "an integer from 1 to 100",
    );
    let t = with(TABLE1, "\"0.01 rad\"", "\"10 deg\"");
    assert_names(
        &t,
        "model.pole_window",
        "pole_window",
        "must be in [0, π/N)",
    );
    let t = with(
        TABLE1,
        "require_gear2_convex = true",
        "require_gear2_convex = true\nmax_pressure_angle = \"95 deg\"",
    );
    assert_names(
        &t,
        "objective.max_pressure_angle",
        "max_pressure_angle",
        "(0, 90°)",
    );
    let t = with(
        TABLE1,
        "maximize = \"ratio-variation\"",
        "maximize = \"speed\"",
    );
    assert_names(
        &t,
        "objective.maximize",
        "maximize",
        "expected `ratio-variation`",
    );
    let t = with(
        TABLE1,
        "[objective]",
        "[accuracy]\nsamples_per_arch = 2\n\n[objective]",
    );
    assert_names(
        &t,
        "accuracy.samples_per_arch",
        "samples_per_arch",
        "allowed: an integer from 8 to 1000",
    );
}

#[test]
fn e_near_r_solves_with_a_warning_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("gear-near.toml");
    let t = with(
        TABLE1,
        "eccentricity = \"15 mm\"",
        "eccentricity = \"35 mm\"",
    )
    .replace("name = \"gear-paper-table1\"", "name = \"gear-near\"");
    std::fs::write(&p, t).unwrap();
    let v = solve_json(&p);
    assert_eq!(v["status"], "analysed");
    let w = v["warnings"].as_array().unwrap();
    assert!(
        w.iter().any(|w| w
            .as_str()
            .unwrap()
            .starts_with("design.eccentricity: e/R = 0.9333")),
        "{w:?}"
    );
    // i12 max in closed form with the independent closing a.
    let a = closing_a(0.0375, 0.035, 3.0, 1.0);
    assert!((num(&v, "derived.ratio_max") - (a - 0.0025) / 0.0025).abs() < 1e-6);
}

#[test]
fn bad_file_through_the_binary_names_file_line_and_field() {
    let (code, stderr) = solve_text(&with(
        TABLE1,
        "eccentricity = \"15 mm\"",
        "eccentricity = \"45 mm\"",
    ));
    assert_eq!(code, Some(1));
    let line = line_of(TABLE1, "eccentricity = ");
    assert!(
        stderr.contains(&format!("bad.toml:{line}: field `design.eccentricity`")),
        "{stderr}"
    );
}
