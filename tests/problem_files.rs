//! Problem files: every shipped file loads, and every kind of bad input is rejected with
//! the file, the line and the field named, and what is allowed said.

use crate::common;
use common::*;
use cwsynth::families::{load, parse_str};
use std::path::Path;

const PISTON: &str = include_str!("../problems/piston-1000rpm.toml");

#[test]
fn every_shipped_problem_file_loads() {
    let mut n = 0;
    for entry in std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/problems")).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "toml") {
            let s = load(&p).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(
                p.file_stem().unwrap().to_str().unwrap(),
                s.name,
                "file name and scene name differ"
            );
            n += 1;
        }
    }
    assert!(n >= 2);
}

#[test]
fn units_are_converted_to_si() {
    let s = parse_str(PISTON, Path::new("p.toml")).unwrap();
    let Some(sc) = s.machine::<cwsynth::families::slider_crank::file::SliderCrankProblem>() else {
        panic!("family")
    };
    let sc = &sc.core;
    assert_eq!(sc.mech.r, 0.035);
    assert_eq!(sc.mech.l, 0.14);
    assert!((sc.omega - 1000.0 * std::f64::consts::TAU / 60.0).abs() < 1e-12);
    // mm and m files give the same scene.
    let m = parse_str(
        &with(
            PISTON,
            "crank_radius = \"35 mm\"",
            "crank_radius = \"0.035 m\"",
        ),
        Path::new("p.toml"),
    )
    .unwrap();
    let Some(sm) = m.machine::<cwsynth::families::slider_crank::file::SliderCrankProblem>() else {
        panic!("family")
    };
    let sm = &sm.core;
    assert_eq!(sm.mech.r, sc.mech.r);
}

/// Issue 14, item 8: units are never guessed. A bare number in a dimensional field (a
/// fixed value, a design range's bound, an array of angles, a `[[paper]]` value whose key
/// has a unit) is an error naming the file, the line, the field and the units allowed;
/// pure numbers (λ, counts) stay plain numbers.
#[test]
fn bare_numbers_in_dimensional_fields_are_errors() {
    for (from, to, field, unit) in [
        ("\"1000 rpm\"", "1500", "mechanism.speed", "rpm"),
        ("\"35 mm\"", "0.035", "mechanism.crank_radius", "mm"),
        ("\"0.30 kg\"", "0", "mechanism.rod_mass", "kg"),
    ] {
        let t = with(PISTON, from, to);
        assert_names(
            &t,
            field,
            field.rsplit('.').next().unwrap(),
            "has no unit, and units are never guessed",
        );
        let e = parse_str(&t, Path::new("bad.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(unit), "{e}");
    }
    // A free range's bounds (an angle range of plain numbers would have been radians).
    let t = with(
        PISTON,
        "angle = { min = \"0 deg\", max = \"360 deg\" }",
        "angle = { min = 0, max = 3 }",
    );
    if let Err(e) = parse_str(&t, Path::new("bad.toml")) {
        assert!(
            e.field().is_some_and(|f| f.starts_with("design.angle.")),
            "{e}"
        );
        assert!(e.to_string().contains("no unit"), "{e}");
        assert!(e.line().is_some(), "{e}");
    } else {
        panic!("a bare angle range was accepted");
    }
    // A [[paper]] value: its unit must be of the dimension of its key's unit suffix.
    for (value, ok) in [("\"900 N\"", true), ("900", false), ("\"900 kg\"", false)] {
        let t = format!("{PISTON}\n[[paper]]\nquantity = \"q\"\nvalue = {value}\nkey = \"baselines.none.peak_shaking_force_n\"\n");
        match parse_str(&t, Path::new("bad.toml")) {
            Ok(_) => assert!(ok, "{value} accepted"),
            Err(e) => {
                assert!(!ok, "{value}: {e}");
                assert_eq!(e.field(), Some("paper[2].value"), "{e}");
                assert!(e.line().is_some() && e.to_string().contains("force"), "{e}");
            }
        }
    }
    // A key without a unit suffix takes a plain number (a percentage), not a quantity.
    let pct = "key = \"derived.paper_counterweight_torque_reduction_pct\"";
    let t = format!("{PISTON}\n[[paper]]\nquantity = \"q\"\nvalue = 23.8\n{pct}\n");
    parse_str(&t, Path::new("ok.toml")).unwrap();
    let t = format!("{PISTON}\n[[paper]]\nquantity = \"q\"\nvalue = \"23.8 N\"\n{pct}\n");
    assert!(parse_str(&t, Path::new("bad.toml")).is_err());
}

#[test]
fn unknown_field_names_field_and_line() {
    let t = with(
        PISTON,
        "rod_mass = \"0.30 kg\"",
        "rod_mass = \"0.30 kg\"\nrod_mas = \"1 kg\"",
    );
    assert_names(
        &t,
        "mechanism.rod_mas",
        "rod_mas =",
        "unknown field `rod_mas`",
    );
}

#[test]
fn missing_field_is_reported() {
    let t = with(PISTON, "rod_length = \"140 mm\"\n", "");
    let e = err(&t);
    assert!(e.to_string().contains("missing field `rod_length`"), "{e}");
    assert_eq!(e.field(), Some("mechanism.rod_length"));
}

#[test]
fn negative_length_is_rejected() {
    let t = with(
        PISTON,
        "crank_radius = \"35 mm\"",
        "crank_radius = \"-35 mm\"",
    );
    assert_names(
        &t,
        "mechanism.crank_radius",
        "crank_radius",
        "allowed: a value > 0",
    );
}

#[test]
fn crank_that_cannot_turn_is_rejected_with_lambda() {
    let t = with(PISTON, "rod_length = \"140 mm\"", "rod_length = \"30 mm\"");
    assert_names(
        &t,
        "mechanism.rod_length",
        "rod_length",
        "λ = R/L = 1.166667",
    );
    let t = with(PISTON, "rod_length = \"140 mm\"", "rod_length = \"35 mm\"");
    assert_names(
        &t,
        "mechanism.rod_length",
        "rod_length",
        "allowed: rod_length > crank_radius",
    );
}

#[test]
fn nan_is_rejected() {
    let t = with(PISTON, "slider_mass = \"1.03 kg\"", "slider_mass = nan");
    assert_names(
        &t,
        "mechanism.slider_mass",
        "slider_mass",
        "not a finite number",
    );
    let t = with(
        PISTON,
        "slider_mass = \"1.03 kg\"",
        "slider_mass = \"NaN kg\"",
    );
    assert_names(
        &t,
        "mechanism.slider_mass",
        "slider_mass",
        "not a finite number",
    );
}

#[test]
fn unknown_unit_and_wrong_dimension_list_the_allowed_units() {
    let t = with(PISTON, "\"35 mm\"", "\"35 furlong\"");
    assert_names(&t, "mechanism.crank_radius", "crank_radius", "unknown unit `furlong` for a length; allowed: a string with a number and one of the units: m, mm, cm");
    let t = with(PISTON, "\"1000 rpm\"", "\"1000 kg\"");
    assert_names(&t, "mechanism.speed", "speed", "`kg` is a unit of mass, but this field is a rotational speed; allowed: a string with a number and one of the units: rad/s, rpm");
}

#[test]
fn bad_family_and_bad_name() {
    let t = with(
        PISTON,
        "family = \"slider-crank\"",
        "family = \"slider_crank\"",
    );
    assert_names(&t, "family", "family", "allowed: \"slider-crank\"");
    let t = with(
        PISTON,
        "name = \"piston-1000rpm\"",
        "name = \"../etc/passwd\"",
    );
    assert_names(&t, "name", "name =", "cannot be a file name");
}

#[test]
fn design_ranges_must_be_ordered_and_convex() {
    let t = with(
        PISTON,
        "unbalance = { min = \"0 kg*m\", max = \"0.2 kg*m\" }",
        "unbalance = { min = \"0.3 kg*m\", max = \"0.2 kg*m\" }",
    );
    assert_names(&t, "design.unbalance", "unbalance =", "allowed: min ≤ max");
    let t = with(
        PISTON,
        "angle = { min = \"0 deg\", max = \"360 deg\" }",
        "angle = { min = \"0 deg\", max = \"270 deg\" }",
    );
    assert_names(&t, "design.angle", "angle =", "not convex");
    let t = with(
        PISTON,
        "angle = { min = \"0 deg\", max = \"360 deg\" }",
        "angle = { min = \"0 deg\", maxi = \"360 deg\" }",
    );
    assert_names(
        &t,
        "design.angle",
        "maxi",
        "unknown field `maxi`, expected `min` or `max`",
    );
}

#[test]
fn model_options_only_where_they_apply() {
    let t = with(PISTON, "rod_split = 0.5", "rod_split = 1.5");
    assert_names(
        &t,
        "model.rod_split",
        "rod_split",
        "allowed: 0 ≤ rod_split ≤ 1",
    );
    let t = with(
        PISTON,
        "rod_split = 0.5",
        "rod_split = 0.5\nrod_inertia = \"1 kg*m^2\"",
    );
    assert_names(
        &t,
        "model.rod_inertia",
        "rod_inertia",
        "only used with masses = \"rigid\"",
    );
    let t = with(
        PISTON,
        "kinematics = \"exact\"",
        "kinematics = \"exact\"\n[mechanism.extra]",
    );
    assert!(err(&t).to_string().contains("bad.toml:"));
    let t = with(
        PISTON,
        "kinematics = \"exact\"",
        "kinematics = \"three-harmonic\"",
    );
    assert_names(
        &t,
        "model.kinematics",
        "kinematics",
        "expected one of `exact`, `two-harmonic`, `primary`",
    );
}

#[test]
fn objective_needs_what_it_uses() {
    let t = with(PISTON, "minimize = \"peak-force\"", "minimize = \"mass\"");
    assert_names(
        &t,
        "objective.max_peak_force",
        "[objective]",
        "needs a peak-force limit",
    );
    let t = with(PISTON, "minimize = \"peak-force\"", "minimize = \"weight\"");
    assert_names(
        &t,
        "objective.minimize",
        "minimize",
        "expected one of `peak-force`, `rms-force`, `mass`, `radius`",
    );
}

#[test]
fn accuracy_settings_are_validated() {
    let t = with(PISTON, "rel_tol = 1e-9", "rel_tol = 2.0");
    assert_names(&t, "accuracy.rel_tol", "rel_tol", "must be in [1e-14, 1)");
}

#[test]
fn syntax_error_has_a_line() {
    let t = with(PISTON, "rod_mass = \"0.30 kg\"", "rod_mass = \"0.30 kg");
    let e = err(&t);
    assert_eq!(e.line(), Some(line_of(&t, "rod_mass")), "{e}");
}

#[test]
fn unreadable_file_is_an_error_not_a_panic() {
    let e = load(Path::new("/nonexistent/x.toml")).unwrap_err();
    assert!(e.to_string().contains("cannot read"));
}

/// Issue 16: solving computes numbers only. Solving a shipped scene draws no SVG document
/// (plots are drawn when written); writing the result draws each of its plots once.
#[test]
fn solving_draws_nothing_and_writing_draws_each_plot() {
    use cwsynth::report::plot::documents_drawn;
    for name in [
        "piston-1000rpm",
        "crane-thesis-example",
        "gear-paper-table1",
    ] {
        let s = load(&problem(&format!("{name}.toml"))).unwrap();
        let before = documents_drawn();
        let mut r = cwsynth::families::solve_scene(&s);
        assert_eq!(documents_drawn(), before, "{name}: solving drew a plot");
        // Tables, plots and drawings are the report's: made only when written.
        assert!(r.plots.is_empty() && r.tables.is_empty() && r.drawings.is_empty());
        let dir = tempfile::tempdir().unwrap();
        cwsynth::report::write_outputs(&mut r, dir.path()).unwrap();
        assert!(!r.plots.is_empty(), "{name}: no plots");
        assert_eq!(
            documents_drawn() - before,
            r.plots.len() as u64,
            "{name}: each plot drawn once when written"
        );
        for p in &r.plots {
            let svg = std::fs::read_to_string(dir.path().join(format!("{name}-{}.svg", p.suffix)))
                .unwrap();
            assert!(
                svg.contains("<svg") && !svg.contains("plot not drawn"),
                "{name}-{}",
                p.suffix
            );
        }
    }
}

/// Angle tolerances are plane angles: a bare number is rejected (units are never guessed),
/// the same value with `rad` or `deg` is read.
#[test]
fn angle_tolerances_need_their_unit() {
    let cases = [
        ("piston-1000rpm", "peak_xtol"),
        ("crane-thesis-example", "xtol"),
        ("crane-thesis-optimise", "moment_step"),
        ("gear-paper-table1", "pole_tol"), // (0, 1e-12] rad
        ("gear-paper-table1", "peak_xtol"),
        ("hypocycloid-variant1", "peak_xtol"),
    ];
    for (file, key) in cases {
        let path = format!("{}/problems/{file}.toml", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap();
        let with_value = |v: &str| {
            if text.contains("\n[accuracy]\n") {
                text.replacen("\n[accuracy]\n", &format!("\n[accuracy]\n{key} = {v}\n"), 1)
            } else {
                format!("{text}\n[accuracy]\n{key} = {v}\n")
            }
        };
        let bare = with_value("1e-13");
        assert_names(
            &bare,
            &format!("accuracy.{key}"),
            &format!("{key} = 1e-13"),
            "has no unit",
        );
        for ok in ["\"1e-13 rad\"", "\"5e-12 deg\""] {
            parse_str(&with_value(ok), Path::new("ok.toml"))
                .unwrap_or_else(|e| panic!("{file} {key} = {ok}: {e}"));
        }
    }
}

/// Issue 20: the units designers use are read exactly (the same machine in inches, pounds
/// and RPM solves to the same numbers as in mm, kg and rpm), and a decimal comma is an error
/// naming the file, the line and the field, with the value as it should be written.
#[test]
fn us_units_are_read_and_a_decimal_comma_is_named() {
    let base = std::fs::read_to_string(problem("piston-1000rpm.toml")).unwrap();
    let us = with(
        &with(
            &base,
            "crank_radius = \"35 mm\"",
            "crank_radius = \"1.3779527559055118 in\"",
        ),
        "speed = \"1000 rpm\"",
        "speed = \"1000 RPM\"",
    );
    let us = with(
        &us,
        "slider_mass = \"1.03 kg\"",
        "slider_mass = \"2.270761300504239 lb\"",
    );
    let a = cwsynth::families::solve_scene(&parse_str(&base, Path::new("a.toml")).unwrap());
    let b = cwsynth::families::solve_scene(&parse_str(&us, Path::new("b.toml")).unwrap());
    let (fa, fb) = (
        a.lookup("objectives.peak_shaking_force_n").unwrap(),
        b.lookup("objectives.peak_shaking_force_n").unwrap(),
    );
    assert!((fa - fb).abs() <= 1e-9 * fa, "{fa} vs {fb}");
    let comma = with(
        &base,
        "rod_length = \"140 mm\"",
        "rod_length = \"140,5 mm\"",
    );
    assert_names(
        &comma,
        "mechanism.rod_length",
        "rod_length",
        "decimal comma",
    );
    let e = err(&comma).to_string();
    assert!(e.contains("\"140.5 mm\""), "{e}");
}

/// A linkage counterweight's envelope far below the machine's size is refused (it would
/// scale the cone program by 1e-308: the mutation suite found the solve stalling on it).
#[test]
fn a_linkage_counterweight_radius_below_the_machines_scale_is_refused() {
    let base = std::fs::read_to_string(problem("linkage-fourbar-pareto.toml")).unwrap();
    let tiny = with(&base, "radius = \"60 mm\"", "radius = \"1e-9 mm\"");
    assert_names(
        &tiny,
        "design.counterweights[0].radius",
        "1e-9",
        "crank length",
    );
    // Below every machine: refused by the units, whatever the field.
    let tinier = with(&base, "radius = \"60 mm\"", "radius = \"1e-308 mm\"");
    assert_names(
        &tinier,
        "design.counterweights[0].radius",
        "1e-308",
        "below any machine",
    );
}

/// A machine scaled to 1e-80 of its size (every length and mass) is refused, naming one such
/// field: its squared forces would be subnormal and its `optimal` wrong. Scaled to 1e-30
/// it is accepted and solves to the original's optimum (forces ∝ s², as mass × length).
#[test]
fn a_machine_below_every_scale_is_refused_and_one_just_above_solves_exactly() {
    let base = std::fs::read_to_string(problem("piston-1000rpm.toml")).unwrap();
    let base = base.split("[[paper]]").next().unwrap().to_string();
    let scaled = |s: &str| {
        let mut t = base.clone();
        for (v, u) in [
            ("35", "mm"),
            ("140", "mm"),
            ("0.35", "kg"),
            ("0.30", "kg"),
            ("1.03", "kg"),
            ("0.2", "kg*m"),
            ("50", "mm"),
        ] {
            t = t.replacen(&format!("\"{v} {u}\""), &format!("\"{v}{s} {u}\""), 1);
        }
        t
    };
    assert_names(
        &scaled("e-80"),
        "design.radius",
        "radius = \"50e-80",
        "below any machine",
    );
    let solve = |t: &str| {
        cwsynth::families::solve_scene(
            &cwsynth::families::parse_str(t, std::path::Path::new("s.toml")).unwrap(),
        )
    };
    let (small, one) = (solve(&scaled("e-25")), solve(&base));
    assert_eq!(small.status, one.status);
    let f = |r: &cwsynth::report::SolveResult| r.objectives["peak_shaking_force_n"];
    assert!(
        (f(&small) * 1e50 / f(&one) - 1.0).abs() < 1e-12,
        "{} vs {}",
        f(&small),
        f(&one)
    );
}
