//! `units` (`src/units.rs`): every unit converted to SI (NIST factors for the US customary
//! ones), units never guessed, wrong or unknown units and decimal commas named with what is
//! allowed, the dimension inferred from the text.
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

use cwsynth::units::{
    parse, parse_any, same_unit, AngularSpeed, Dim, Dimensionless, Qty, UnitError, UNITS,
};

#[test]
fn converts_every_unit_the_issue_names() {
    let cases = [
        ("35 mm", Dim::Length, 0.035),
        ("3.5 cm", Dim::Length, 0.035),
        ("0.035 m", Dim::Length, 0.035),
        ("350 g", Dim::Mass, 0.35),
        ("0.35 kg", Dim::Mass, 0.35),
        ("60 rpm", Dim::AngularSpeed, std::f64::consts::TAU),
        ("2 rad/s", Dim::AngularSpeed, 2.0),
        ("180 deg", Dim::Angle, std::f64::consts::PI),
        ("1 rad", Dim::Angle, 1.0),
        ("2 kN", Dim::Force, 2000.0),
        ("5 N", Dim::Force, 5.0),
        ("3 N·m", Dim::Torque, 3.0),
        ("3 N*m", Dim::Torque, 3.0),
        ("435804 N·mm", Dim::Torque, 435.804),
        ("2 kg·m", Dim::Unbalance, 2.0),
        ("2 kg*mm", Dim::Unbalance, 2e-3),
        ("7850 kg/m³", Dim::Density, 7850.0),
        ("35mm", Dim::Length, 0.035),
        (
            "1e3 rpm",
            Dim::AngularSpeed,
            1000.0 * std::f64::consts::TAU / 60.0,
        ),
        ("12", Dim::Dimensionless, 12.0),
    ];
    for (text, dim, si) in cases {
        let v = parse(text, dim).unwrap_or_else(|e| panic!("{text}: {e}"));
        assert!((v - si).abs() <= 1e-15 * si.abs(), "{text}: {v} vs {si}");
        assert_eq!(parse_any(text), Ok((v, dim)), "{text}");
    }
    // Spellings of a product of units.
    for text in ["3 N.m", "3 N-m", "3 N⋅m", " 3  N . m "] {
        assert_eq!(parse_any(text), Ok((3.0, Dim::Torque)), "{text}");
    }
    assert_eq!(parse_any("3 kg.m²"), Ok((3.0, Dim::Inertia)));
    assert_eq!(parse_any("3 rad / s"), Ok((3.0, Dim::AngularSpeed)));
}

#[test]
fn wrong_or_unknown_units_list_what_is_allowed() {
    let e = parse("35 kg", Dim::Length).unwrap_err();
    assert!(matches!(
        e,
        UnitError::WrongDimension {
            found: Dim::Mass,
            ..
        }
    ));
    assert!(e.to_string().contains("mm"), "{e}");
    let e = parse("35 furlong", Dim::Length).unwrap_err();
    assert!(matches!(e, UnitError::UnknownUnit { .. }));
    assert!(
        e.to_string()
            .contains("allowed: a string with a number and one of the units: m, mm"),
        "{e}"
    );
    assert!(matches!(
        parse("mm", Dim::Length),
        Err(UnitError::NotANumber { .. })
    ));
    assert!(matches!(
        parse("NaN mm", Dim::Length),
        Err(UnitError::NotFinite { .. })
    ));
    assert!(matches!(
        parse("inf", Dim::Length),
        Err(UnitError::NotFinite { .. })
    ));
    for text in ["3 N..m", "3 N\tm"] {
        assert!(matches!(
            parse(text, Dim::Torque),
            Err(UnitError::UnknownUnit { .. })
        ));
    }
}

#[test]
fn units_are_never_guessed() {
    // A bare number is a pure number: an error for every other dimension, as text or
    // as a TOML number (the serde face), naming the units allowed.
    let dims = [
        Dim::Length,
        Dim::Mass,
        Dim::Angle,
        Dim::AngularSpeed,
        Dim::Force,
        Dim::Torque,
        Dim::Unbalance,
        Dim::Inertia,
        Dim::Density,
        Dim::Acceleration,
        Dim::Time,
        Dim::Pressure,
    ];
    for dim in dims {
        for text in ["1500", " 0 ", "-2.5e3"] {
            let e = parse(text, dim).unwrap_err();
            assert!(matches!(e, UnitError::NoUnit { .. }), "{text}: {e}");
            assert!(e.to_string().contains(dim.name()), "{e}");
            assert!(e.to_string().contains(dim.si()), "{e}");
        }
    }
    assert_eq!(parse("1500", Dim::Dimensionless), Ok(1500.0));
    #[derive(serde::Deserialize, Debug)]
    struct T {
        #[allow(dead_code)]
        speed: Qty<AngularSpeed>,
    }
    for text in ["speed = 1500", "speed = 1500.0", "speed = -3"] {
        let e = toml::from_str::<T>(text).unwrap_err();
        assert!(e.message().contains("no unit"), "{e}");
        assert!(e.message().contains("rpm"), "{e}");
    }
    let t: T = toml::from_str("speed = \"60 rpm\"").unwrap();
    assert!((t.speed.si() - std::f64::consts::TAU).abs() < 1e-15);
    #[derive(serde::Deserialize, Debug)]
    struct P {
        lambda: Qty<Dimensionless>,
    }
    assert_eq!(toml::from_str::<P>("lambda = 3").unwrap().lambda.si(), 3.0);
}

#[test]
fn parse_any_infers_the_dimension() {
    assert_eq!(parse_any("900 N").unwrap(), (900.0, Dim::Force));
    assert_eq!(parse_any("0.5").unwrap(), (0.5, Dim::Dimensionless));
    let (v, d) = parse_any("331931 N·mm").unwrap();
    assert_eq!(d, Dim::Torque);
    assert!((v - 331.931).abs() < 1e-12);
    // Text that is no quantity is reported as for a length.
    for bad in ["fast", "3 furlong", "inf N", "NaN", ""] {
        assert_eq!(
            parse_any(bad),
            Err(parse(bad, Dim::Length).unwrap_err()),
            "{bad}"
        );
    }
}

#[test]
fn numbers_end_where_the_unit_starts() {
    for (text, dim, si) in [
        ("-2.5e-3 m", Dim::Length, -2.5e-3),
        ("+4E2mm", Dim::Length, 0.4),
        ("1e mm", Dim::Length, f64::NAN),
        ("1e3", Dim::Dimensionless, 1e3),
        ("3 ms", Dim::Time, 3e-3),
        ("7 bar", Dim::Pressure, 7e5),
        ("0.1 MPa", Dim::Pressure, 1e5),
        (".5 kg", Dim::Mass, 0.5),
        ("5. kg", Dim::Mass, 5.0),
        ("7  \t kN", Dim::Force, 7e3),
        ("2 e", Dim::Length, f64::NAN),
    ] {
        match parse(text, dim) {
            Ok(v) => assert!((v - si).abs() <= 1e-15 * si.abs(), "{text}: {v}"),
            Err(e) => assert!(si.is_nan(), "{text}: {e}"),
        }
    }
    for text in ["inf", "-infinity mm", "NaN kg", "+Inf"] {
        assert!(
            matches!(parse(text, Dim::Length), Err(UnitError::NotFinite { .. })),
            "{text}"
        );
    }
}

#[test]
fn unit_symbols_are_distinct_and_normalised() {
    for (k, u) in UNITS.iter().enumerate() {
        assert!(!u.symbol.contains(['.', '⋅', '-', ' ']), "{}", u.symbol);
        assert!(UNITS[..k].iter().all(|v| !same_unit(u.symbol, v.symbol)));
    }
}

#[test]
fn us_customary_units_match_nist_conversion_factors() {
    // NIST SP 811 (2008), appendix B.8/B.9, the factors to SI.
    let cases = [
        ("1 in", Dim::Length, 2.54e-2),
        ("1 ft", Dim::Length, 3.048e-1),
        ("1 lb", Dim::Mass, 4.5359237e-1),
        ("1 oz", Dim::Mass, 2.834952e-2),
        ("1 lbf", Dim::Force, 4.448222),
        ("1 lbf*ft", Dim::Torque, 1.355818),
        ("1 lbf·in", Dim::Torque, 1.129848e-1),
        ("1 lb·in²", Dim::Inertia, 2.926397e-4),
        ("1 lb*ft^2", Dim::Inertia, 4.214011e-2),
        ("1 lb/in^3", Dim::Density, 2.767990e4),
        ("1 psi", Dim::Pressure, 6.894757e3),
        ("1 ft/s^2", Dim::Acceleration, 3.048e-1),
        ("1 oz*in", Dim::Unbalance, 2.834952e-2 * 2.54e-2),
        ("60 RPM", Dim::AngularSpeed, std::f64::consts::TAU),
        ("60 rev/min", Dim::AngularSpeed, std::f64::consts::TAU),
        ("1 Hz", Dim::AngularSpeed, std::f64::consts::TAU),
        ("1 rev/s", Dim::AngularSpeed, std::f64::consts::TAU),
    ];
    for (text, dim, si) in cases {
        let v = parse(text, dim).unwrap();
        // NIST prints 7 significant digits where the factor is not exact.
        assert!((v - si).abs() <= 1e-6 * si, "{text}: {v} vs {si}");
    }
    // A pound is a mass, a pound-force a force: never one for the other.
    assert!(matches!(
        parse("3 lb", Dim::Force),
        Err(UnitError::WrongDimension { .. })
    ));
}

#[test]
fn a_decimal_comma_is_named_with_the_fix() {
    let e = parse("1,5 mm", Dim::Length).unwrap_err();
    assert!(matches!(e, UnitError::DecimalComma { .. }), "{e}");
    assert!(e.to_string().contains("\"1.5 mm\""), "{e}");
    // A comma that is no decimal comma stays an unknown unit.
    assert!(matches!(
        parse("1, mm", Dim::Length),
        Err(UnitError::UnknownUnit { .. })
    ));
}
