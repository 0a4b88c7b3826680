//! A slider-crank `[[mechanism.mass_items]]` item whose mass comes from its drawing
//! (`outline = { … }`, `families::slider_crank::file_masses`): the piston drawn as a 60 × 40 mm
//! rectangle with a 10 mm pin bore, written with the `dxf` crate into a temporary folder next
//! to the problem file.
//!
//! * its mass is ρ·t·A of the closed form A = 60·40 − π·10² mm² (1e-12 relative), and the
//!   result says where it came from (`model.mass_items_from_drawings`);
//! * the scene solves to the same result, to the bit, as the same mass typed in;
//! * `outline` beside `mass`, neither of them, and a missing drawing are refused with the
//!   file, line and field.

use cwsynth::families::{load, solve_scene};
use dxf::entities::{Circle, Entity, EntityType, Line};
use dxf::enums::{AcadVersion, Units};
use dxf::{Drawing, Point};
use std::f64::consts::PI;
use std::path::Path;

/// Thickness (m) and density (kg/m³) of the drawn piston.
const T: f64 = 0.05;
const RHO: f64 = 7850.0;

/// The drawn item's key.
const PISTON_OUTLINE: &str = r#"outline = { file = "drawings/piston.dxf", layer = "PISTON", thickness = "50 mm", density = "7850 kg/m^3" }"#;

/// Writes the piston (a 60 × 40 mm rectangle of LINEs with a CIRCLE of radius 10 mm at its
/// centre, layer PISTON, in mm) to `dir/drawings/piston.dxf`.
fn piston_drawing(dir: &Path) {
    let mut d = Drawing::new();
    d.header.version = AcadVersion::R2010;
    d.header.default_drawing_units = Units::Millimeters;
    let mut add = |specific: EntityType| {
        let mut e = Entity::new(specific);
        e.common.layer = "PISTON".into();
        d.add_entity(e);
    };
    let corners = [(0.0, 0.0), (60.0, 0.0), (60.0, 40.0), (0.0, 40.0)];
    for k in 0..4 {
        let ((x0, y0), (x1, y1)) = (corners[k], corners[(k + 1) % 4]);
        let l = Line::new(Point::new(x0, y0, 0.0), Point::new(x1, y1, 0.0));
        add(EntityType::Line(l));
    }
    add(EntityType::Circle(Circle::new(
        Point::new(30.0, 20.0, 0.0),
        10.0,
    )));
    std::fs::create_dir_all(dir.join("drawings")).unwrap();
    d.save_file(dir.join("drawings/piston.dxf")).unwrap();
}

/// A piston machine whose piston item is `piston` (its `mass` or `outline` line).
fn machine(piston: &str) -> String {
    format!(
        r#"name = "drawn-piston"
family = "slider-crank"

[mechanism]
crank_radius = "35 mm"
rod_length = "140 mm"
speed = "1000 rpm"
rod_mass = "0.30 kg"

[[mechanism.mass_items]]
name = "crank"
mass = "0.35 kg"
at = "crank-pin"

[[mechanism.mass_items]]
name = "piston"
{piston}
at = "slider"

[[mechanism.mass_items]]
name = "gudgeon pin"
mass = "0.2 kg"
at = "slider"

[design]
unbalance = {{ min = "0 kg*m", max = "0.2 kg*m" }}
radius = "50 mm"

[objective]
minimize = "peak-force"
"#
    )
}

/// ρ·t·A of the drawn piston, A = 60·40 − π·10² mm².
fn closed_form_mass() -> f64 {
    (60.0 * 40.0 - PI * 100.0) * 1e-6 * T * RHO
}

#[test]
fn a_drawn_mass_item_is_rho_t_a_and_solves_as_the_same_mass_typed_in() {
    let dir = tempfile::tempdir().unwrap();
    piston_drawing(dir.path());
    let drawn = dir.path().join("drawn.toml");
    std::fs::write(&drawn, machine(PISTON_OUTLINE)).unwrap();
    let a = solve_scene(&load(&drawn).unwrap_or_else(|e| panic!("{e}")));
    let from = &a.model["mass_items_from_drawings"];
    let entries = from.as_array().expect("one entry per drawn item");
    assert_eq!(entries.len(), 1, "{from}");
    let e = &entries[0];
    assert_eq!(e["item"], "piston");
    assert_eq!(e["file"], "drawings/piston.dxf");
    assert_eq!(e["layer"], "PISTON");
    let mass = e["mass_kg"].as_f64().unwrap();
    let want = closed_form_mass();
    assert!(
        ((mass - want) / want).abs() < 1e-12,
        "{mass} kg vs the closed form {want} kg"
    );
    let area = e["area_m2"].as_f64().unwrap();
    let want_area = (60.0 * 40.0 - PI * 100.0) * 1e-6;
    assert!(((area - want_area) / want_area).abs() < 1e-12, "{area}");
    assert_eq!(e["thickness_m"].as_f64(), Some(T));
    assert_eq!(e["density_kg_m3"].as_f64(), Some(RHO));

    // The same mass typed in (`{:e}` prints the shortest text that reads back to the bit).
    let typed = dir.path().join("typed.toml");
    std::fs::write(&typed, machine(&format!("mass = \"{mass:e} kg\""))).unwrap();
    let b = solve_scene(&load(&typed).unwrap());
    assert_eq!(a.status, b.status);
    assert!(!a.objectives.is_empty());
    assert_eq!(a.objectives, b.objectives);
    assert_eq!(a.errors, b.errors);
    assert_eq!(a.design, b.design);
    assert_eq!(a.derived, b.derived);
    assert_eq!(a.baselines, b.baselines);
    assert_eq!(a.warnings, b.warnings);
    assert!(!b.model.contains_key("mass_items_from_drawings"));
    let mut model = a.model.clone();
    model.remove("mass_items_from_drawings");
    assert_eq!(model, b.model);
    // The slider's mass is the drawn piston's, the pin's and half the rod's.
    let scene = load(&drawn).unwrap();
    let p = scene
        .machine::<cwsynth::families::slider_crank::file::SliderCrankProblem>()
        .unwrap();
    assert_eq!(p.core.mech.slider_mass, mass + 0.2);
}

/// The error of loading `machine(piston)` from `dir/bad.toml`, and the 1-based line of the
/// piston item's line that starts with `start`.
fn refused(dir: &Path, piston: &str, start: &str) -> (String, usize) {
    let f = dir.join("bad.toml");
    let text = machine(piston);
    std::fs::write(&f, &text).unwrap();
    let from = text.lines().position(|l| l == "name = \"piston\"").unwrap();
    let n = from
        + 1
        + text
            .lines()
            .skip(from)
            .position(|l| l.starts_with(start))
            .unwrap();
    (load(&f).map(|_| ()).unwrap_err().to_string(), n)
}

#[test]
fn a_mass_item_takes_exactly_one_of_mass_and_outline() {
    let dir = tempfile::tempdir().unwrap();
    piston_drawing(dir.path());
    let bad = dir.path().join("bad.toml");
    let bad = bad.display();
    // Both: the typed mass is the key the drawing would set.
    let both = format!("mass = \"1 kg\"\n{PISTON_OUTLINE}");
    let (e, n) = refused(dir.path(), &both, "mass");
    assert!(
        e.starts_with(&format!(
            "{bad}:{n}: field `mechanism.mass_items[1].mass`: given with outline, which sets it from the drawing; allowed: one or the other"
        )),
        "{e}"
    );
    // Neither.
    let (e, _) = refused(dir.path(), "fraction = 1.0", "fraction");
    assert!(
        e.contains("field `mechanism.mass_items[1].mass`: missing: the item's mass"),
        "{e}"
    );
}

#[test]
fn a_missing_drawing_names_the_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    let (e, n) = refused(dir.path(), PISTON_OUTLINE, "outline");
    let missing = dir.path().join("drawings/piston.dxf");
    assert!(
        e.starts_with(&format!(
            "{}:{n}: field `mechanism.mass_items[1].outline.file`: {}: cannot read",
            bad.display(),
            missing.display()
        )),
        "{e}"
    );
}
