//! `cwsynth calibrate`: unknown data fitted to the values a result must reproduce, checked
//! against independent solves of the fitted file.

use cwsynth::calibrate::calibrate;
use cwsynth::families::{parse_str, solve_scene};
use std::path::Path;

const FELLING: &str = include_str!("../problems/felling-head-150rpm.toml");
const PISTON: &str = include_str!("../problems/piston-1000rpm.toml");

/// The text with `key = "<v> m"` (a length in the `[mechanism]` table).
fn with_length(text: &str, key: &str, v: f64) -> String {
    let mut doc: toml_edit::DocumentMut = text.parse().unwrap();
    doc["mechanism"][key] = toml_edit::value(format!("{v:e} m"));
    doc.to_string()
}

#[test]
fn the_felling_heads_conrod_is_recovered_from_the_papers_torque() {
    let path = Path::new("problems/felling-head-150rpm.toml");
    let c = calibrate(FELLING, path).unwrap();
    let p = &c.fit.parameters[0];
    assert_eq!(p.key, "mechanism.rod_length");
    // The file's 283.6 mm is this fit rounded to 0.1 mm.
    assert!((p.value - 0.2836).abs() < 0.05e-3, "L = {}", p.value);
    let sigma = p.uncertainty.expect("identifiable");
    assert!(c.fit.identifiable);
    // Independently: the file with the fitted L reproduces 435 804 N·mm within its σ.
    let r = solve_scene(&parse_str(&with_length(FELLING, "rod_length", p.value), path).unwrap());
    let t = r.lookup("baselines.none.peak_drive_torque_nm").unwrap();
    assert!((t - 435.804).abs() <= 0.5e-3, "T = {t}");
    // And σ_L = σ_T/|dT/dL| from two more solves 1 µm apart.
    let h = 1e-6;
    let tl = |l: f64| {
        solve_scene(&parse_str(&with_length(FELLING, "rod_length", l), path).unwrap())
            .lookup("baselines.none.peak_drive_torque_nm")
            .unwrap()
    };
    let slope = (tl(p.value + h) - tl(p.value - h)) / (2.0 * h);
    let want = 0.5e-3 / slope.abs();
    assert!(
        (sigma - want).abs() <= 0.02 * want,
        "σ {sigma} against {want}"
    );
    assert_eq!(c.result.name, "felling-head-150rpm-calibrated");
    assert!(c.result.extra.contains_key("calibration"));
}

#[test]
fn a_known_mass_is_recovered_and_two_unknowns_for_one_value_are_not_identifiable() {
    let path = Path::new("piston.toml");
    // The truth: the shipped piston's slider mass (1.03 kg) gives this peak force.
    let truth = solve_scene(&parse_str(PISTON, path).unwrap());
    let f = truth.lookup("objectives.peak_shaking_force_n").unwrap();
    let section = format!(
        "\n[[calibrate.parameter]]\nkey = \"mechanism.slider_mass\"\nmin = \"0.5 kg\"\nmax = \"2 kg\"\n\n[[calibrate.match]]\nkey = \"objectives.peak_shaking_force_n\"\nvalue = \"{f} N\"\nuncertainty = \"1e-6 N\"\n"
    );
    // Start elsewhere: the fit must move the mass back.
    let text = PISTON.replacen("slider_mass = \"1.03 kg\"", "slider_mass = \"0.8 kg\"", 1);
    assert_ne!(text, PISTON, "the piston's slider mass line moved");
    let c = calibrate(&(text.clone() + &section), path).unwrap();
    let p = &c.fit.parameters[0];
    let s = p.uncertainty.unwrap();
    assert!(
        (p.value - 1.03).abs() <= 3.0 * s + 1e-12,
        "m = {} ± {s}",
        p.value
    );
    assert!(s < 1e-6, "σ = {s}");

    // Two masses against one force: only a combination is fixed.
    let two = section.replacen(
        "[[calibrate.match]]",
        "[[calibrate.parameter]]\nkey = \"mechanism.crank_mass\"\nmin = \"0.1 kg\"\nmax = \"1 kg\"\n\n[[calibrate.match]]",
        1,
    );
    let c = calibrate(&(text + &two), path).unwrap();
    assert!(!c.fit.identifiable);
    assert!(c.fit.parameters.iter().all(|p| p.uncertainty.is_none()));
    assert!(c.fit.notes.iter().any(|n| n.contains("not identifiable")));
}

#[test]
fn a_bad_calibration_entry_names_its_line_and_field() {
    let bad = format!(
        "{FELLING}\n[[calibrate.match]]\nkey = \"baselines.none.peak_drive_torque_nm\"\nvalue = \"435 kg\"\nuncertainty = \"1 N*m\"\n"
    );
    let e = parse_str(&bad, Path::new("f.toml")).expect_err("a mass for a torque");
    assert_eq!(e.field(), Some("calibrate.match[1].value"), "{e}");
    assert!(e.line().is_some(), "{e}");
}
