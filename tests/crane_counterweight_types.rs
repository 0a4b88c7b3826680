//! The crane's counterweight types (issue 38, thesis Fig 1.5 b, c; `families::crane::lever`,
//! `balance`): the lever counterweight's torque against virtual work (the finite difference of
//! its potential energy, its four-bar solved here by a circle intersection written out) and
//! its certified optimum against a brute-force grid of its first moment; the hanging
//! counterweight's optimum the same as on the boom (it acts at its suspension point) and its
//! lowest point against a scan of its path.

use crate::common::{tukan_linkage, tukan_scene, TUKAN_MASSES};
use cwsynth::families::crane::balance::{self, CounterweightKind, LeverSpec};
use cwsynth::families::crane::lever::LeverLinkage;
use cwsynth::families::crane::statics::{statics, Loads};
use cwsynth::geom::{cross, P2};
use cwsynth::synth::counterweight::Status;
use cwsynth::synth::minimax::Settings;

const G: f64 = 9.80665;

/// The shipped lever: pivot (4, 12) m, arm 3 m at 200° at maximum reach, rod to the boom 8 m
/// up from the foot; at most 150 t at 4 m from the pivot, any direction.
const LEVER: LeverSpec = LeverSpec {
    pivot_m: [4.0, 12.0],
    arm_m: 3.0,
    angle_at_max_reach_rad: 200.0 * std::f64::consts::PI / 180.0,
    rod_boom_point_m: [8.0, 0.0],
};

/// The Tukan scene with a counterweight of `kind`, at most `max_mass` kg within `lever` m of its
/// pivot, any direction.
fn scene(kind: CounterweightKind, max_mass: f64, lever: f64) -> balance::BalanceScene {
    let mut sc = tukan_scene(TUKAN_MASSES, true);
    let cw = sc.counterweight.as_mut().unwrap();
    cw.kind = kind;
    cw.max_mass = max_mass;
    cw.lever = lever;
    cw.directions = None;
    sc
}

/// The lever's rod pin L at φ, solved here: K(φ) on the boom, L on the circle (O, ρ) at the rod's
/// length c from K, on the side of the line K → O where it is at maximum reach (the pose ψ₁).
fn rod_pin(phi: f64, p0: f64) -> P2 {
    let o = P2::new(LEVER.pivot_m[0], LEVER.pivot_m[1]);
    let k_at = |p: f64| P2::new(-8.0 * p.cos(), 8.0 * p.sin());
    let l1 = o + 3.0
        * P2::new(
            LEVER.angle_at_max_reach_rad.cos(),
            LEVER.angle_at_max_reach_rad.sin(),
        );
    let c = (l1 - k_at(p0)).norm();
    let side = |k: P2, l: P2| cross(o - k, l - k).signum();
    let want = side(k_at(p0), l1);
    // Circle (K, c) ∩ circle (O, ρ): the foot of the chord and the half chord.
    let k = k_at(phi);
    let d = (o - k).norm();
    let a = (d * d + c * c - 9.0) / (2.0 * d);
    let h = (c * c - a * a).sqrt();
    let u = (o - k) / d;
    let n = P2::new(-u.y, u.x);
    let cands = [k + u * a + n * h, k + u * a - n * h];
    *cands.iter().find(|&&l| side(k, l) == want).unwrap()
}

/// Virtual work: with the designed first moment w on the lever, T_cw(φ) (the drive torque with
/// it less without it) is dV/dφ of the counterweight's potential g (w_s sin ψ + w_n cos ψ), ψ
/// from the rod pin solved here, by the fourth-order central difference, at 9 angles; and the
/// optimum is certified.
#[test]
fn the_lever_counterweight_does_the_work_of_its_potential() {
    let link = tukan_linkage();
    let sc = scene(CounterweightKind::Lever(LEVER), 150e3, 4.0);
    let bal = balance::solve(&link, &sc, 2.5, &Settings::default(), 16).unwrap();
    let cw = bal.counterweight.as_ref().unwrap();
    assert_eq!(cw.status, Status::Optimal, "{cw:?}");
    let w = cw.static_moment_kgm;
    let [p0, p1] = link.phi_range;
    let o = P2::new(LEVER.pivot_m[0], LEVER.pivot_m[1]);
    let v = |phi: f64| {
        let r = rod_pin(phi, p0) - o;
        let psi = r.y.atan2(r.x);
        G * (w[0] * psi.sin() + w[1] * psi.cos())
    };
    let lk = LEVER.linkage(p0).unwrap();
    let mut worst = 0.0_f64;
    for i in 1..=9 {
        let phi = p0 + (p1 - p0) * i as f64 / 10.0;
        let h = 1e-4;
        let dv =
            (8.0 * (v(phi + h) - v(phi - h)) - (v(phi + 2.0 * h) - v(phi - 2.0 * h))) / (12.0 * h);
        let row = LeverLinkage::torque_row(&lk.pose(phi).unwrap());
        let t_cw = row[0] * w[0] + row[1] * w[1];
        let diff = (t_cw - dv).abs();
        assert!(
            diff <= 1e-7 * dv.abs().max(1.0),
            "phi {phi}: {t_cw} vs {dv}: {diff:e}"
        );
        worst = worst.max(diff / dv.abs());
    }
    eprintln!("lever T_cw against dV/dφ: largest relative difference {worst:.1e}");
}

/// The certified optimum against brute force: the peak |T0(φ) + row(φ)·w| over 1001 angles and
/// both cases, minimised over a 161 × 161 grid of w around the optimum inside |w| ≤ ℓ m_max.
/// The grid's best is at least the certified lower bound (less the sampling's slack) and
/// within the grid's spacing of the optimum.
#[test]
fn the_lever_counterweight_is_the_brute_force_optimum() {
    let link = tukan_linkage();
    let sc = scene(CounterweightKind::Lever(LEVER), 150e3, 4.0);
    let bal = balance::solve(&link, &sc, 2.5, &Settings::default(), 16).unwrap();
    let cw = bal.counterweight.as_ref().unwrap();
    let [p0, p1] = link.phi_range;
    let lk = LEVER.linkage(p0).unwrap();
    let n = 1000;
    let rows: Vec<([f64; 2], [f64; 2])> = (0..=n)
        .map(|i| {
            let phi = p0 + (p1 - p0) * i as f64 / n as f64;
            let pose = link.pose(phi).unwrap();
            let t0 = [0.0, 40e3].map(|q| {
                let l = Loads {
                    load_mass: q,
                    ..Loads::default()
                };
                statics(&link, phi, &pose, &TUKAN_MASSES, &l)
                    .unwrap()
                    .drive_torque
            });
            (t0, LeverLinkage::torque_row(&lk.pose(phi).unwrap()))
        })
        .collect();
    let peak = |w: [f64; 2]| {
        rows.iter()
            .flat_map(|(t0, r)| t0.map(|t| (t + r[0] * w[0] + r[1] * w[1]).abs()))
            .fold(0.0, f64::max)
    };
    let w0 = cw.static_moment_kgm;
    let span = 0.2 * cw.static_moment_magnitude_kgm;
    let m = 80;
    let step = span / m as f64;
    let mut best = (f64::INFINITY, [0.0; 2]);
    for i in -m..=m {
        for j in -m..=m {
            let w = [w0[0] + step * i as f64, w0[1] + step * j as f64];
            if w[0].hypot(w[1]) <= 4.0 * 150e3 {
                let p = peak(w);
                if p < best.0 {
                    best = (p, w);
                }
            }
        }
    }
    let v = cw.peak_drive_torque_nm;
    assert!(
        best.0 >= cw.lower_bound_nm - cw.error_nm,
        "{best:?} vs {cw:?}"
    );
    // The row's size times the grid's half diagonal bounds how far the grid's best can be
    // above the optimum.
    let row_max = rows
        .iter()
        .map(|(_, r)| r[0].hypot(r[1]))
        .fold(0.0, f64::max);
    assert!(best.0 - v <= row_max * step, "{best:?} vs {v}");
    assert!((peak(w0) - v).abs() <= 1e-6 * v, "{} vs {v}", peak(w0));
    eprintln!(
        "certified {v:.6} N·m (lower bound {:.6}); grid best {:.6} at {:?} (step {step:.1} kg·m)",
        cw.lower_bound_nm, best.0, best.1
    );
}

/// A hung counterweight acts at its suspension point: with the same limits its certified
/// optimum is the boom counterweight's; its lowest point is the suspension point's lowest less
/// the hanger, against a scan of 4001 angles, and the hanger carries m g.
#[test]
fn a_hanging_counterweight_hangs_below_its_suspension_point() {
    let link = tukan_linkage();
    let boom = tukan_scene(TUKAN_MASSES, true);
    let mut hung = tukan_scene(TUKAN_MASSES, true);
    hung.counterweight.as_mut().unwrap().kind = CounterweightKind::Hanging { hang_length_m: 2.5 };
    let solve = |sc| balance::solve(&link, sc, 2.5, &Settings::default(), 16).unwrap();
    let (b, h) = (solve(&boom), solve(&hung));
    let (cb, ch) = (b.counterweight.unwrap(), h.counterweight.unwrap());
    assert_eq!(ch.status, Status::Optimal);
    assert_eq!(cb.static_moment_kgm, ch.static_moment_kgm);
    assert!(b.counterweight_path.is_none());
    let path = h.counterweight_path.unwrap();
    assert_eq!(path.kind, "hanging");
    let u = ch.static_moment_kgm;
    let m = ch.mass_kg;
    let [p0, p1] = link.phi_range;
    let y = |phi: f64| (u[0] * phi.sin() - u[1] * phi.cos()) / m - 2.5;
    let lowest = (0..=4000)
        .map(|i| y(p0 + (p1 - p0) * i as f64 / 4000.0))
        .fold(f64::INFINITY, f64::min);
    assert!(
        path.lowest_y_m <= lowest + path.error_m,
        "{path:?} vs {lowest}"
    );
    assert!(lowest - path.lowest_y_m <= 1e-6, "{path:?} vs {lowest}");
    assert!((path.hanger_tension_n.unwrap() - m * G).abs() <= 1e-9 * m * G);
    eprintln!(
        "hanging: lowest {:.9} m (scan {lowest:.9}) ± {:.1e}",
        path.lowest_y_m, path.error_m
    );
}

/// The counterweight type's keys need their units and their kind, naming file, line and field.
#[test]
fn a_bad_counterweight_type_key_names_file_line_and_field() {
    use crate::common::{assert_names, with};
    let path = crate::common::problem("crane-tukan-40t-hanging-counterweight.toml");
    let hung = std::fs::read_to_string(path).unwrap();
    let t = with(&hung, "hang_length = \"2.5 m\"", "hang_length = 2.5");
    assert_names(
        &t,
        "design.counterweight.hang_length",
        "hang_length = 2.5",
        "has no unit, and units are never guessed",
    );
    let t = with(&hung, "kind = \"hanging\"", "kind = \"boom\"");
    assert_names(
        &t,
        "design.counterweight.hang_length",
        "hang_length",
        "only for kind = \"hanging\"",
    );
    let path = crate::common::problem("crane-tukan-40t-lever-counterweight.toml");
    let lever = std::fs::read_to_string(path).unwrap();
    let t = with(&lever, "lever_arm = \"3 m\"\n", "");
    assert_names(
        &t,
        "design.counterweight.lever_arm",
        "[design.counterweight]",
        "missing: kind = \"lever\" needs it",
    );
    let t = with(
        &lever,
        "lever_angle = \"200 deg\"",
        "lever_angle = \"200 m\"",
    );
    assert_names(
        &t,
        "design.counterweight.lever_angle",
        "lever_angle",
        "this field is a plane angle",
    );
}
