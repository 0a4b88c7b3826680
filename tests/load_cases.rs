//! Named load cases of the hypocycloid compressor (`[[mechanism.load_cases]]`, issue 33)
//! against independent solves: each case's figures against a separate single-case solve of
//! the file rewritten with that case's pressure; the flywheel of all the cases against the
//! largest least flywheel, its steady state meeting Cs in every case and 0.1 % less failing
//! the governing case; the case-independent shaking force and counterweights; a given
//! flywheel; and the rejections, each naming the file, the line and the field.

use crate::common::{err, num, problem, set_key, solve_json, with};
use cwsynth::families::{parse_str, solve_scene};
use cwsynth::report::{SolveResult, Status};
use serde_json::Value;
use std::path::Path;

const COMPRESSOR: &str = include_str!("../problems/hypocycloid-compressor.toml");

/// The compressor's text without its load cases (everything from the first
/// `[[mechanism.load_cases]]` to the next plain `[table]`).
fn single_case(text: &str) -> String {
    let start = text.find("[[mechanism.load_cases]]").unwrap();
    let end = start + text[start..].find("\n[model]").unwrap();
    format!("{}{}", &text[..start], &text[end + 1..])
}

/// `text` solved through the library (no result files); it must succeed.
fn solve(text: &str) -> SolveResult {
    let s = parse_str(text, Path::new("cases.toml")).unwrap();
    let r = solve_scene(&s);
    assert_eq!(r.status, Status::Analysed, "{:?}", r.warnings);
    r
}

/// The `load_cases` section's rows of a result.
fn rows(r: &SolveResult) -> Vec<Value> {
    r.extra["load_cases"]["cases"].as_array().unwrap().clone()
}

/// The discharge pressure of a row as the file writes it (`"6 bar"`).
fn bar(row: &Value) -> String {
    format!("{} bar", num(row, "discharge_pressure_pa") / 1e5)
}

#[test]
fn each_case_is_the_single_case_solve_of_its_pressure() {
    let r = solve_json(&problem("hypocycloid-compressor.toml"));
    let cases = r["load_cases"]["cases"].as_array().unwrap().clone();
    let names: Vec<&str> = cases.iter().map(|c| c["case"].as_str().unwrap()).collect();
    assert_eq!(names, ["nominal", "6 bar", "10 bar"]);
    let base = single_case(COMPRESSOR);
    // The nominal row is the result's own single-case keys (below); the others, solved alone.
    for row in &cases[1..] {
        let text = with(
            &base,
            "discharge_pressure = \"8 bar\"",
            &format!("discharge_pressure = \"{}\"", bar(row)),
        );
        let one = solve(&text);
        let d = &one.derived;
        // The same single-case code on the same cycle: equal within the stated errors
        // (measured: bit-identical).
        for (key, err) in [
            ("drive_torque_mean_nm", "drive_torque_mean_error_nm"),
            ("drive_torque_peak_nm", "drive_torque_peak_error_nm"),
            ("energy_fluctuation_j", "energy_fluctuation_error_j"),
            ("flywheel_least_kgm2", "flywheel_least_error_kgm2"),
            ("flywheel_textbook_kgm2", "flywheel_least_error_kgm2"),
        ] {
            let (a, b) = (num(row, key), d[key]);
            eprintln!("{} {key}: {a} vs {b}, difference {:e}", row["case"], a - b);
            assert!((a - b).abs() <= d[err], "{} {key}: {a} vs {b}", row["case"]);
        }
        // The gas force is internal: the shaking force and the counterweights are the
        // nominal's in every case.
        for key in [
            "minimax_shaking_force_peak_n",
            "shaking_force_peak_n",
            "rotating_force_peak_n",
        ] {
            assert_eq!(d[key], num(&r, &format!("derived.{key}")), "{key}");
        }
        for key in [
            "carrier_counterweight_mass_kg",
            "planet_counterweight_mass_kg",
        ] {
            assert_eq!(one.design[key], num(&r, &format!("design.{key}")), "{key}");
        }
    }
    // The nominal row is the result's single-case keys.
    for key in [
        "energy_fluctuation_j",
        "flywheel_least_kgm2",
        "drive_torque_peak_nm",
    ] {
        assert_eq!(
            num(&cases[0], key),
            num(&r, &format!("derived.{key}")),
            "{key}"
        );
    }
}

#[test]
fn the_flywheel_of_all_cases_is_the_largest_least_one_and_meets_cs_in_each() {
    let r = solve(COMPRESSOR);
    let (rows, d) = (rows(&r), &r.derived);
    let cs = 0.02;
    let least: Vec<f64> = rows.iter().map(|c| num(c, "flywheel_least_kgm2")).collect();
    let top = least.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let k = least.iter().position(|&l| l == top).unwrap();
    assert_eq!(d["load_cases_flywheel_kgm2"], top);
    let sec = &r.extra["load_cases"];
    assert_eq!(sec["flywheel_case"], rows[k]["case"]);
    assert_eq!(rows[k]["case"], "10 bar");
    for (key, unit) in [("energy_fluctuation", "j"), ("drive_torque_peak", "nm")] {
        let v = |c: &Value| num(c, &format!("{key}_{unit}"));
        let worst = rows.iter().max_by(|a, b| v(a).total_cmp(&v(b))).unwrap();
        assert_eq!(sec[format!("{key}_case")], worst["case"], "{key}");
        assert_eq!(d[&format!("worst_case_{key}_{unit}")], v(worst), "{key}");
    }
    for row in &rows {
        assert_eq!(num(row, "steady_flywheel_kgm2"), top);
        let (c, e) = (num(row, "steady_cs"), num(row, "steady_cs_error"));
        assert!(c <= cs + e, "{}: Cs {c} ± {e}", row["case"]);
    }
    let (c, e) = (num(&rows[k], "steady_cs"), num(&rows[k], "steady_cs_error"));
    assert!((c - cs).abs() <= 1e-9 + e, "governing Cs {c} ± {e}");
    assert!(d["worst_case_steady_cs"] <= cs + d["worst_case_steady_cs_error"]);
    // Independently: a case alone, with I* given (and no `cs`), has the steady state of its
    // row — the governing one (whose state is its least flywheel's) and one re-solved at I*
    // (the nominal's path is the same); the governing case with 0.1 % less misses Cs.
    let alone = single_case(COMPRESSOR).replace("cs = 0.02 ", "# cs = 0.02 ");
    for (i, row) in rows.iter().enumerate().skip(1) {
        let text = with(
            &alone,
            "discharge_pressure = \"8 bar\"",
            &format!("discharge_pressure = \"{}\"", bar(row)),
        );
        let less = if i == k { vec![0.999 * top] } else { vec![] };
        for f in std::iter::once(top).chain(less) {
            let t = set_key(
                &text,
                "mechanism.drive.flywheel",
                &format!("\"{f:e} kg*m^2\""),
            );
            let one = solve(&t);
            let (c, e) = (one.derived["steady_cs"], one.derived["steady_cs_error"]);
            if f < top {
                assert!(c > cs + e, "{}: flywheel {f}: Cs {c} ± {e}", row["case"]);
                continue;
            }
            for key in [
                "steady_cs",
                "steady_omega_min_rad_s",
                "steady_omega_max_rad_s",
            ] {
                let (a, b) = (num(row, key), one.derived[key]);
                eprintln!(
                    "{} at I*: {key} {a} vs {b}, difference {:e}",
                    row["case"],
                    a - b
                );
                assert!(
                    (a - b).abs() <= e.max(one.derived["steady_omega_error_rad_s"]),
                    "{key}"
                );
            }
        }
    }
}

#[test]
fn a_given_flywheel_reports_each_cases_cs_with_it() {
    let text = set_key(COMPRESSOR, "mechanism.drive.flywheel", "\"0.05 kg*m^2\"");
    let r = solve(&text);
    let sec = &r.extra["load_cases"];
    assert_eq!(r.derived["load_cases_flywheel_kgm2"], 0.05);
    assert!(sec["flywheel_case"].is_null());
    let rows = rows(&r);
    for row in &rows {
        assert_eq!(num(row, "steady_flywheel_kgm2"), 0.05);
    }
    // More discharge pressure, more swing.
    let cs: Vec<f64> = rows.iter().map(|c| num(c, "steady_cs")).collect();
    assert!(cs[1] < cs[0] && cs[0] < cs[2], "{cs:?}");
}

/// The line of the `n`-th (0-based) `needle` in `text`.
fn nth_line(text: &str, needle: &str, n: usize) -> usize {
    let at = text.match_indices(needle).nth(n).unwrap().0;
    text[..at].matches('\n').count() + 1
}

#[test]
fn bad_load_cases_name_the_file_line_and_field() {
    let c = COMPRESSOR;
    let ten = "discharge_pressure = \"10 bar\"";
    let many: String = (0..17)
        .map(|i| {
            let p = 5 + i;
            format!(
                "\n[[mechanism.load_cases]]\nname = \"c{i}\"\ndischarge_pressure = \"{p} bar\"\n"
            )
        })
        .collect();
    let many = with(&single_case(c), "\n[model]", &format!("{many}\n[model]"));
    let start = c.find("\n[mechanism.gas]").unwrap() + 1;
    let end = start + c[start..].find("\n[mechanism.lanchester]").unwrap();
    let no_gas = format!("{}{}", &c[..start], &c[end + 1..]);
    let header = "[[mechanism.load_cases]]";
    // (file, field, the line's needle and which of them, what the message says)
    let cases = [
        (
            with(c, "name = \"10 bar\"", "name = \"6 bar\""),
            "[1].name",
            ("name = \"6 bar\"", 1),
            "is taken",
        ),
        (
            with(c, "name = \"6 bar\"", "name = \"nominal\""),
            "[0].name",
            ("name = \"nominal\"", 0),
            "is taken",
        ),
        (
            with(c, "name = \"6 bar\"", "name = \" \""),
            "[0].name",
            ("name = \" \"", 0),
            "is no name",
        ),
        (
            with(c, ten, "discharge_pressure = 10"),
            "[1].discharge_pressure",
            ("discharge_pressure = 10", 0),
            "unit",
        ),
        (
            with(c, ten, "discharge_pressure = \"0.5 bar\""),
            "[1].discharge_pressure",
            ("\"0.5 bar\"", 0),
            "above the suction",
        ),
        (
            with(c, ten, &format!("{ten}\nbore = \"60 mm\"")),
            "[1].bore",
            ("bore = \"60 mm\"", 0),
            "unknown",
        ),
        (
            with(c, &format!("{ten}\n"), ""),
            "[1]",
            (header, 1),
            "changes nothing",
        ),
        (many, "[16]", (header, 16), "at most 16"),
        (no_gas, "[0]", (header, 0), "[mechanism.gas]"),
    ];
    for (text, field, (needle, n), says) in cases {
        let e = err(&text);
        let msg = e.to_string();
        assert_eq!(
            e.field(),
            Some(format!("mechanism.load_cases{field}").as_str()),
            "{msg}"
        );
        assert_eq!(e.line(), Some(nth_line(&text, needle, n)), "{msg}");
        assert!(msg.starts_with("bad.toml:"), "{msg}");
        assert!(msg.contains(says), "`{msg}` should say `{says}`");
    }
}

const BAND: &str = include_str!("../problems/hypocycloid-compressor-speed-band.toml");

/// The speed band (`[mechanism.envelope] speed`): the cycle at both ends beside the nominal
/// speed, each end's row equal to a separate solve of the file at that speed; the flywheel of
/// all the cases the largest least flywheel, its steady state meeting Cs at the ends and at
/// the interior speeds checked, and 0.1 % less missing it at the governing end; and,
/// independently of the band code, the textbook flywheel of single-speed solves over a sweep
/// of the band never above the largest of its ends' (its convexity in 1/ω², the module doc of
/// `load_cases.rs`).
#[test]
fn a_speed_band_takes_the_largest_flywheel_of_its_ends_and_holds_inside() {
    let r = solve(BAND);
    let rows = rows(&r);
    let names: Vec<&str> = rows.iter().map(|c| c["case"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        ["nominal", "nominal at 1200 rpm", "nominal at 1500 rpm"]
    );
    let start = BAND.find("\n[mechanism.envelope]").unwrap() + 1;
    let end = start + BAND[start..].find("\n[model]").unwrap();
    let alone = format!("{}{}", &BAND[..start], &BAND[end + 1..]);
    let at = |rpm: f64| {
        let t = with(
            &alone,
            "speed = \"1450 rpm\"",
            &format!("speed = \"{rpm} rpm\""),
        );
        solve(&t)
    };
    for (row, rpm) in rows[1..].iter().zip([1200.0, 1500.0]) {
        assert!((num(row, "speed_rad_s") - rpm * std::f64::consts::TAU / 60.0).abs() < 1e-9);
        let d = at(rpm).derived;
        for (key, err) in [
            ("drive_torque_peak_nm", "drive_torque_peak_error_nm"),
            ("energy_fluctuation_j", "energy_fluctuation_error_j"),
            ("flywheel_least_kgm2", "flywheel_least_error_kgm2"),
        ] {
            let (a, b) = (num(row, key), d[key]);
            assert!((a - b).abs() <= d[err], "{rpm} rpm {key}: {a} vs {b}");
        }
    }
    let least: Vec<f64> = rows.iter().map(|c| num(c, "flywheel_least_kgm2")).collect();
    let top = least.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let k = least.iter().position(|&l| l == top).unwrap();
    assert_eq!(r.derived["load_cases_flywheel_kgm2"], top);
    let cs = 0.02;
    for row in &rows {
        let (c, e) = (num(row, "steady_cs"), num(row, "steady_cs_error"));
        assert!(c <= cs + e, "{}: Cs {c} ± {e}", row["case"]);
    }
    let check = &r.extra["load_cases"]["speed_band_check"];
    assert_eq!(check["beyond"], 0, "{check}");
    assert_eq!(check["proven"], true, "{check}");
    assert!(
        num(check, "cs_bound") <= cs + num(check, "cs_bound_error"),
        "{check}"
    );
    assert!(
        num(check, "max_cs") <= cs + num(check, "max_cs_error"),
        "{check}"
    );
    // 0.1 % less flywheel misses Cs at the governing speed.
    let rpm = num(&rows[k], "speed_rad_s") * 60.0 / std::f64::consts::TAU;
    let t = with(
        &alone,
        "speed = \"1450 rpm\"",
        &format!("speed = \"{rpm} rpm\""),
    );
    let t = set_key(
        &t.replace("cs = 0.02 ", "# cs = 0.02 "),
        "mechanism.drive.flywheel",
        &format!("\"{:e} kg*m^2\"", 0.999 * top),
    );
    let d = solve(&t).derived;
    assert!(
        d["steady_cs"] > cs + d["steady_cs_error"],
        "{}",
        d["steady_cs"]
    );
    // The textbook flywheel over the band is largest at an end (9 single-speed solves).
    let ends = rows[1..]
        .iter()
        .map(|c| num(c, "flywheel_textbook_kgm2"))
        .fold(f64::NEG_INFINITY, f64::max);
    for j in 1..=9 {
        let rpm = 1200.0 + 300.0 * j as f64 / 10.0;
        let d = at(rpm).derived;
        let (tb, e) = (d["flywheel_textbook_kgm2"], d["flywheel_least_error_kgm2"]);
        assert!(
            tb <= ends + e,
            "{rpm} rpm: textbook {tb} above the ends' {ends}"
        );
    }
}

/// A speed band with a motor's torque–speed line, or without a gas cycle, is refused with
/// its field.
#[test]
fn a_speed_band_needs_a_gas_cycle_and_no_motor_line() {
    let motor = with(
        BAND,
        "[mechanism.drive]\n",
        "[mechanism.drive]\nmotor = { rated_torque = \"5 N*m\", rated_speed = \"1430 rpm\", no_load_speed = \"1500 rpm\" }\n",
    );
    let e = err(&motor).to_string();
    assert!(e.contains("mechanism.envelope.speed"), "{e}");
    assert!(e.contains("motor"), "{e}");
    let start = BAND.find("\n[mechanism.gas]").unwrap() + 1;
    let end = start + BAND[start..].find("\n[mechanism.lanchester]").unwrap();
    let e = err(&format!("{}{}", &BAND[..start], &BAND[end + 1..])).to_string();
    assert!(e.contains("mechanism.envelope.speed"), "{e}");
    // Only the speed: the other intervals are the slider-crank's and the linkage's.
    let e = err(&with(
        BAND,
        "[mechanism.envelope]\n",
        "[mechanism.envelope]\nmonte_carlo = 10\n",
    ));
    assert!(e.to_string().contains("monte_carlo"), "{e}");
}
