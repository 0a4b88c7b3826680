//! The crane's real luffing drive (issue 38, `families::crane::actuator`): the force along a
//! hydraulic cylinder and a rope tackle against virtual work (U times the finite difference of
//! the actuator's length is the drive torque of the potential energy's finite difference), the
//! force extremes against a brute-force scan of 4001 angles, the stroke and the power from the
//! attachment points written out here, a dead centre refused, and the file's errors naming
//! file, line and field.

use crate::common::{self, assert_names, tukan_linkage, tukan_scene, with};
use cwsynth::families::crane::actuator::{self, ActuatorKind, ActuatorSpec};
use cwsynth::families::crane::balance;
use cwsynth::families::crane::statics::{statics, virtual_work_torque, Loads, SelfWeight};
use cwsynth::families::{parse_str, solve_scene};
use cwsynth::geom::P2;
use cwsynth::synth::minimax::Settings;

/// The Tukan 40T masses of the shipped scene.
const MASSES: SelfWeight = common::TUKAN_MASSES;

/// The shipped scene's cylinder, rope tackle and rack (at the cylinder's points, a 150 mm
/// pinion).
fn specs() -> [ActuatorSpec; 3] {
    [
        ActuatorSpec {
            kind: ActuatorKind::Cylinder,
            frame_point: P2::new(-1.0, -3.0),
            boom_point: [8.0, 0.5],
            parts: 1.0,
            pinion_radius: None,
        },
        ActuatorSpec {
            kind: ActuatorKind::Rope,
            frame_point: P2::new(4.0, 14.0),
            boom_point: [20.0, 0.0],
            parts: 6.0,
            pinion_radius: None,
        },
        ActuatorSpec {
            kind: ActuatorKind::Rack,
            frame_point: P2::new(-1.0, -3.0),
            boom_point: [8.0, 0.5],
            parts: 1.0,
            pinion_radius: Some(0.15),
        },
    ]
}

/// The actuator's length from its points written out: Q = s(−cos φ, sin φ) + n(−sin φ, −cos φ).
fn length(s: &ActuatorSpec, phi: f64) -> f64 {
    let [a, n] = s.boom_point;
    let q = P2::new(
        -a * phi.cos() - n * phi.sin(),
        a * phi.sin() - n * phi.cos(),
    );
    (q - s.frame_point).norm()
}

/// dℓ/dφ by the fourth-order central difference of [`length`].
fn length_fd(s: &ActuatorSpec, phi: f64) -> f64 {
    let h = 1e-4;
    let l = |k: f64| length(s, phi + k * h);
    (8.0 * (l(1.0) - l(-1.0)) - (l(2.0) - l(-2.0))) / (12.0 * h)
}

/// Virtual work, independently of the statics: the force U the actuator reports at φ (the
/// statics' T over its closed-form lever arm) times the finite difference of its length is
/// the drive torque dV/dφ of the potential energy (`virtual_work_torque`, no force solved):
/// U ℓ′ = T for the cylinder (pushing), −T for the rope (pulling), at 9 angles, both cases.
#[test]
fn the_actuator_force_does_the_work_of_the_torque() {
    let link = tukan_linkage();
    let [p0, p1] = link.phi_range;
    let mut worst = 0.0_f64;
    for s in specs() {
        for q in [0.0, 40e3] {
            for i in 1..=9 {
                let phi = p0 + (p1 - p0) * i as f64 / 10.0;
                let pose = link.pose(phi).unwrap();
                let l = Loads {
                    load_mass: q,
                    ..Loads::default()
                };
                let st = statics(&link, phi, &pose, &MASSES, &l).unwrap();
                let u = s.force(phi, st.drive_torque);
                let (t_vw, e_vw) = virtual_work_torque(&link, phi, 1e-3, &MASSES, q, None).unwrap();
                let work = u * length_fd(&s, phi);
                let expect = s.sense() * t_vw;
                let diff = (work - expect).abs();
                assert!(
                    diff <= e_vw + 1e-9 * t_vw.abs(),
                    "{:?} q {q} phi {phi}: U ℓ′ {work} vs T {expect}: {diff:e}",
                    s.kind
                );
                worst = worst.max(diff / t_vw.abs());
            }
        }
    }
    eprintln!("largest |U ℓ′ − (±T)|/|T| over 36 points: {worst:.1e}");
}

/// The shipped drive with its optimal counterweight, luffing in 55 s: every case's largest and
/// smallest force against T/ℓ′ scanned on 4001 angles with the length's finite difference
/// (the refined extreme is at least every sample less its error and within 1e-6 of the
/// densest), the stroke |ℓ(φ_max) − ℓ(φ_min)| and the power max|U|·stroke/t_l from the points.
#[test]
fn the_actuator_forces_are_the_brute_force_extremes() {
    let link = tukan_linkage();
    let sc = tukan_scene(MASSES, true);
    let bal = balance::solve(&link, &sc, 2.5, &Settings::default(), 16).unwrap();
    let cw = bal.counterweight.as_ref().unwrap();
    let t_l = 55.0;
    let specs = specs();
    let a = actuator::actuators(&link, &sc, &bal, &specs, Some(t_l)).unwrap();
    assert!(a.with_counterweight);
    let [p0, p1] = link.phi_range;
    let mut worst = 0.0_f64;
    for (s, act) in specs.iter().zip(&a.actuators) {
        let stroke = (length(s, p1) - length(s, p0)).abs();
        assert!((act.stroke_m - stroke).abs() <= 1e-12 * stroke, "{act:?}");
        for c in &act.cases {
            let q = if c.case == "loaded" { 40e3 } else { 0.0 };
            let (mut hi, mut lo) = (f64::NEG_INFINITY, f64::INFINITY);
            for k in 0..=4000 {
                let phi = p0 + (p1 - p0) * k as f64 / 4000.0;
                let pose = link.pose(phi).unwrap();
                let l = Loads {
                    load_mass: q,
                    counterweight_mass: cw.mass_kg,
                    counterweight_moment: cw.static_moment_kgm,
                    rope: None,
                };
                let t = statics(&link, phi, &pose, &MASSES, &l)
                    .unwrap()
                    .drive_torque;
                let f = s.sense() * t / length_fd(s, phi);
                hi = hi.max(f);
                lo = lo.min(f);
            }
            let scale = hi.abs().max(lo.abs());
            assert!(
                c.force_max_n >= hi - c.force_error_n - 1e-9 * scale,
                "{c:?}: {hi}"
            );
            assert!(c.force_max_n - hi <= 1e-6 * scale, "{c:?}: {hi}");
            assert!(
                c.force_min_n <= lo + c.force_error_n + 1e-9 * scale,
                "{c:?}: {lo}"
            );
            assert!(lo - c.force_min_n <= 1e-6 * scale, "{c:?}: {lo}");
            let power = scale * stroke / t_l;
            let p = c.peak_power_w.unwrap();
            assert!((p - power).abs() <= 1e-6 * power, "{p} vs {power}");
            // A rack's pinion: torque max|U|·r_p, at v/r_p.
            if let Some(r) = s.pinion_radius {
                let t = c.pinion_torque_max_nm.unwrap();
                assert!((t - scale * r).abs() <= 1e-6 * scale * r, "{t}");
                let rpm = stroke / t_l / r * 60.0 / std::f64::consts::TAU;
                assert!((act.pinion_speed_rpm.unwrap() - rpm).abs() <= 1e-12 * rpm);
            } else {
                assert!(c.pinion_torque_max_nm.is_none() && act.pinion_speed_rpm.is_none());
            }
            worst = worst
                .max((c.force_max_n - hi).abs() / scale)
                .max((c.force_min_n - lo).abs() / scale);
            eprintln!(
                "{:?} {}: U in [{:.6}, {:.6}] kN (scan [{:.6}, {:.6}]) ± {:.1e} N",
                s.kind,
                c.case,
                c.force_min_n / 1e3,
                c.force_max_n / 1e3,
                lo / 1e3,
                hi / 1e3,
                c.force_error_n
            );
        }
    }
    eprintln!("largest |refined − scan|/max|U|: {worst:.1e}");
    // The rack at the cylinder's points carries the cylinder's force, both ways.
    for (c, r) in a.actuators[0].cases.iter().zip(&a.actuators[2].cases) {
        assert_eq!(
            (c.force_max_n, c.force_min_n),
            (r.force_max_n, r.force_min_n)
        );
    }
    let rack = &a.actuators[2].verdict;
    assert!(
        rack.starts_with("The rack pushes") && rack.contains("pinion"),
        "{rack}"
    );
    // The rope is slack where the optimal counterweight over-balances the boom.
    assert!(
        a.actuators[1].verdict.contains("SLACK"),
        "{}",
        a.actuators[1].verdict
    );
}

/// A cylinder whose line passes through the boom foot within the range (Q = (8, −2) m in the
/// boom frame crosses x = 0 at tan φ = 4, φ = 76°, with P below A) is refused in the result's
/// warnings: its force would be infinite there.
#[test]
fn an_actuator_through_its_dead_centre_is_refused() {
    let path = common::problem("crane-tukan-40t-luffing-drive.toml");
    let base = std::fs::read_to_string(&path).unwrap();
    let t = with(
        &base,
        "frame_point = [\"-1 m\", \"-3 m\"]\nboom_point = [\"8 m\", \"0.5 m\"]",
        "frame_point = [\"0 m\", \"-3 m\"]\nboom_point = [\"8 m\", \"-2 m\"]",
    );
    let r = solve_scene(&parse_str(&t, &path).unwrap()).to_json();
    assert!(r.get("luffing_actuators").is_none());
    let w = r["warnings"].as_array().unwrap();
    assert!(
        w.iter()
            .any(|w| w.as_str().unwrap().contains("passes its dead centre")),
        "{w:?}"
    );
}

/// The actuator's values need their units, `parts` is for a rope only, and the drive needs
/// the masses, naming file, line and field.
#[test]
fn a_bad_actuator_key_names_file_line_and_field() {
    let path = common::problem("crane-tukan-40t-luffing-drive.toml");
    let base = std::fs::read_to_string(path).unwrap();
    let t = with(
        &base,
        "boom_point = [\"8 m\", \"0.5 m\"]",
        "boom_point = [8, 0.5]",
    );
    assert_names(
        &t,
        "mechanism.luffing_actuator[0].boom_point",
        "boom_point = [8, 0.5]",
        "has no unit, and units are never guessed",
    );
    let t = with(
        &base,
        "boom_point = [\"8 m\", \"0.5 m\"]",
        "boom_point = [\"8 m\", \"0.5 m\"]\nparts = 2",
    );
    assert_names(
        &t,
        "mechanism.luffing_actuator[0].parts",
        "parts = 2",
        "only for a rope tackle",
    );
    let t = with(&base, "parts = 6", "parts = 0");
    assert_names(
        &t,
        "mechanism.luffing_actuator[1].parts",
        "parts = 0",
        "must be 1 to 64 parts",
    );
    let t = with(&base, "kind = \"rope\"", "kind = \"winch\"");
    let e = cwsynth::families::parse_str(&t, std::path::Path::new("bad.toml"))
        .expect_err("a winch is not an actuator kind");
    assert!(e.to_string().contains("unknown variant `winch`"), "{e}");
    let t = with(&base, "pinion_radius = \"150 mm\"\n", "");
    assert_names(
        &t,
        "mechanism.luffing_actuator[2].kind",
        "kind = \"rack\"",
        "a rack needs its pinion",
    );
    let t = with(
        &base,
        "pinion_radius = \"150 mm\"",
        "pinion_radius = \"0 mm\"",
    );
    assert_names(
        &t,
        "mechanism.luffing_actuator[2].pinion_radius",
        "pinion_radius = \"0 mm\"",
        "must be a finite length > 0",
    );
    let t = with(&base, "parts = 6", "parts = 6\npinion_radius = \"1 m\"");
    assert_names(
        &t,
        "mechanism.luffing_actuator[1].pinion_radius",
        "pinion_radius = \"1 m\"",
        "only for a rack",
    );
    let path = common::problem("crane-tukan-40t.toml");
    let bare = std::fs::read_to_string(path).unwrap();
    let t = format!("{bare}\n[[mechanism.luffing_actuator]]\nkind = \"cylinder\"\nframe_point = [\"-1 m\", \"-3 m\"]\nboom_point = [\"8 m\", \"0.5 m\"]\n");
    assert_names(
        &t,
        "mechanism.luffing_actuator[0].kind",
        "kind = \"cylinder\"",
        "needs the boom system's masses",
    );
}
