//! Issue 39: the firing orders a layout admits and the phase search restricted to the layouts
//! that fire evenly. The matching of cylinders to firing slots
//! (`multi_cylinder::firing::even_orders`) against a brute force over every assignment of the
//! four-stroke cycle's two turns, on random layouts (on and just off the even grid); the
//! inline-4's three even-firing cranks and the flat one's two orders; the shipped inline-6's
//! mirror-symmetric crank with no couple; and the problem file's errors.

use crate::common::{assert_names, problem, with, Lcg};
use cwsynth::families::multi_cylinder::file::MultiCylinderProblem;
use cwsynth::families::multi_cylinder::firing::{self, Cycle};
use cwsynth::families::multi_cylinder::model::{Cylinder, Layout};
use cwsynth::families::slider_crank::model::{Crank, Kinematics, Rod, SliderCrank};
use cwsynth::families::{load, parse_str, solve_scene};
use cwsynth::report::Status;
use std::collections::BTreeSet;
use std::f64::consts::TAU;
use std::path::Path;

/// A layout whose cylinders reach their dead centres at `tdc` (rad), banks random.
fn layout_with_tdc(rng: &mut Lcg, tdc: &[f64]) -> Layout {
    let sc = SliderCrank {
        r: 0.04,
        l: 0.14,
        e: 0.0,
        kinematics: Kinematics::Exact,
        crank: Crank {
            mass: 0.0,
            centroid: 0.04,
        },
        rod: Rod::lumped(0.5, 0.33, 0.14),
        slider_mass: 0.5,
    };
    let cylinders = tdc
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let bank = rng.range(-3.0, 3.0);
            Cylinder {
                phase: bank - t,
                bank,
                z: 0.1 * i as f64,
                sc: sc.clone(),
                articulated: None,
            }
        })
        .collect();
    Layout { cylinders, z0: 0.0 }
}

/// Every even firing order by brute force: each cylinder fires at its dead centre plus 0 or
/// (four-stroke) one turn, measured from cylinder 1's; the firing angles sorted must be
/// j·P/N.
fn brute_force(layout: &Layout, cycle: Cycle) -> BTreeSet<Vec<usize>> {
    let n = layout.cylinders.len();
    let p = cycle.period();
    let turns = if cycle == Cycle::FourStroke { 2 } else { 1 };
    let t0 = firing::tdc(&layout.cylinders[0]);
    let mut out = BTreeSet::new();
    for k in 0..turns_pow(turns, n - 1) {
        let mut rest = k;
        let mut f: Vec<(f64, usize)> = vec![(0.0, 1)];
        for (i, c) in layout.cylinders.iter().enumerate().skip(1) {
            let extra = (rest % turns) as f64 * TAU;
            rest /= turns;
            let mut a = (firing::tdc(c) + extra - t0).rem_euclid(p);
            if p - a < 1e-9 {
                a = 0.0;
            }
            f.push((a, i + 1));
        }
        f.sort_by(|a, b| a.0.total_cmp(&b.0));
        let even = f
            .iter()
            .enumerate()
            .all(|(j, (a, _))| (a - j as f64 * p / n as f64).abs() < 1e-9);
        if even && f[0].1 == 1 {
            out.insert(f.iter().map(|x| x.1).collect());
        }
    }
    out
}

fn turns_pow(t: usize, e: usize) -> usize {
    t.pow(e as u32)
}

#[test]
fn the_even_firing_orders_are_every_assignment_that_fires_evenly() {
    let mut rng = Lcg(39_001);
    let (mut with_orders, mut without) = (0, 0);
    for case in 0..400 {
        let n = 2 + case % 7;
        let cycle = if case % 3 == 0 {
            Cycle::TwoStroke
        } else {
            Cycle::FourStroke
        };
        let dt = cycle.period() / n as f64;
        let mut tdc: Vec<f64> = (0..n)
            .map(|_| {
                if rng.next() < 0.8 {
                    (rng.next() * n as f64).floor() * dt
                } else {
                    rng.range(0.0, TAU)
                }
            })
            .collect();
        // Every fifth case on a permutation of the grid itself (always even), every seventh
        // one of those just off it (never even): the near-degenerate side of the tolerance.
        if case % 5 == 0 {
            let mut slots: Vec<usize> = (0..n).collect();
            for i in (1..n).rev() {
                slots.swap(i, (rng.next() * (i + 1) as f64) as usize);
            }
            tdc = slots.iter().map(|&j| j as f64 * dt).collect();
            if case % 7 == 0 {
                tdc[n - 1] += 1e-6;
            }
        }
        let layout = layout_with_tdc(&mut rng, &tdc);
        let expected = brute_force(&layout, cycle);
        let (listed, count) = firing::even_orders(&layout, cycle);
        assert_eq!(count, expected.len(), "case {case}: {tdc:?} {cycle:?}");
        let want: Vec<Vec<usize>> = expected.iter().take(firing::MAX_LISTED).cloned().collect();
        assert_eq!(listed, want, "case {case}");
        for o in &expected {
            assert!(
                firing::fires_evenly_in(&layout, cycle, o),
                "case {case}: {o:?}"
            );
        }
        // An order that is not even is refused.
        let mut other: Vec<usize> = (1..=n).collect();
        for i in (2..n).rev() {
            other.swap(i, 1 + (rng.next() * i as f64) as usize);
        }
        assert_eq!(
            firing::fires_evenly_in(&layout, cycle, &other),
            expected.contains(&other),
            "case {case}: {other:?}"
        );
        if count > 0 {
            with_orders += 1;
        } else {
            without += 1;
        }
    }
    // Both sides were exercised.
    assert!(with_orders > 50 && without > 50, "{with_orders} {without}");
}

fn problem_text(name: &str) -> String {
    std::fs::read_to_string(problem(name)).unwrap()
}

#[test]
fn the_four_stroke_inline_4_admits_three_cranks_and_the_flat_one_fires_1_3_4_2() {
    let text = with(
        &problem_text("inline-4-phases.toml"),
        "slider_mass = \"0.50 kg\"",
        "slider_mass = \"0.50 kg\"\ncycle = \"four-stroke\"",
    );
    let text = with(
        &text,
        "step = \"90 deg\"",
        "step = \"90 deg\"\neven_firing = true",
    );
    let text = with(
        &text,
        "minimize = \"peak-force\"",
        "minimize = \"peak-couple\"",
    );
    let s = parse_str(&text, Path::new("inline-4-four-stroke.toml")).unwrap();
    let r = solve_scene(&s);
    assert_eq!(r.status, Status::Optimal, "{:?}", r.warnings);
    let rows = r.extra["phases"].as_array().unwrap();
    let layouts: BTreeSet<&str> = rows
        .iter()
        .map(|row| row["phases_deg"].as_str().unwrap())
        .collect();
    assert_eq!(
        layouts,
        BTreeSet::from([
            "0.0 180.0 180.0 0.0",
            "0.0 0.0 180.0 180.0",
            "0.0 180.0 0.0 180.0"
        ]),
    );
    // The flat crank cancels the primary couple: it is the best, firing 1-2-4-3 or 1-3-4-2.
    assert_eq!(rows[0]["phases_deg"], "0.0 180.0 180.0 0.0");
    assert_eq!(rows[0]["firing_order"], "1-2-4-3");
    assert_eq!(
        r.model["firing"],
        "four-stroke: 2 even firing orders, every 180.0000°: 1-2-4-3, 1-3-4-2"
    );
    assert_eq!(r.derived["even_firing_orders"], 2.0);
    assert!((r.derived["firing_interval_rad"] - TAU / 2.0).abs() < 1e-15);
}

#[test]
fn the_shipped_inline_6_is_mirror_symmetric_and_has_no_couple() {
    let s = load(&problem("inline-6-firing.toml")).unwrap();
    let p = s.machine::<MultiCylinderProblem>().unwrap();
    assert_eq!(p.layout.cylinders.len(), 6);
    let r = solve_scene(&s);
    assert_eq!(r.status, Status::Optimal, "{:?}", r.warnings);
    let phase = |i: usize| r.design[&format!("cylinder_{i}_phase_rad")];
    for (a, b) in [(1, 6), (2, 5), (3, 4)] {
        assert!((phase(a) - phase(b)).abs() < 1e-12, "{a} {b}");
    }
    let (v, e) = (r.objectives["peak_couple_nm"], r.errors["peak_couple_nm"]);
    assert!(v <= e && e < 1e-9, "{v} ± {e}");
    assert_eq!(r.extra["phases"].as_array().unwrap().len(), 30);
    assert!(
        r.model["firing"].as_str().unwrap().contains("1-5-3-6-2-4"),
        "{}",
        r.model["firing"]
    );
}

#[test]
fn firing_keys_are_checked_with_file_line_and_field() {
    let base = problem_text("inline-4-phases.toml");
    let four = with(
        &base,
        "slider_mass = \"0.50 kg\"",
        "slider_mass = \"0.50 kg\"\ncycle = \"four-stroke\"",
    );
    assert_names(
        &with(
            &base,
            "rod_mass = \"0.55 kg\"",
            "rod_mass = \"0.55 kg\"\nfiring_order = [1, 3, 4, 2]",
        ),
        "mechanism.firing_order",
        "firing_order",
        "needs the cycle",
    );
    assert_names(
        &with(&four, "cycle = ", "firing_order = [1, 3, 3, 2]\ncycle = "),
        "mechanism.firing_order",
        "firing_order",
        "no firing order of 4 cylinders",
    );
    assert_names(
        &with(
            &base,
            "step = \"90 deg\"",
            "step = \"90 deg\"\neven_firing = true",
        ),
        "design.phases.even_firing",
        "even_firing",
        "needs the cycle",
    );
    // 90° steps on a two-stroke four: the dead centres must be 90° apart, possible; on a
    // 180° step they cannot be.
    let two = with(&four, "four-stroke", "two-stroke");
    let two = with(
        &two,
        "step = \"90 deg\"",
        "step = \"180 deg\"\neven_firing = true",
    );
    assert_names(
        &two,
        "design.phases.even_firing",
        "even_firing",
        "no layout with every throw at a multiple of 180.0000° fires evenly in a two-stroke cycle",
    );
    // A given order the analysed layout does not fire evenly in is a warning.
    let flat = problem_text("inline-4-lanchester.toml");
    let flat = flat.replacen(
        "[[mechanism.cylinders]]",
        "cycle = \"four-stroke\"\nfiring_order = [1, 2, 3, 4]\n\n[[mechanism.cylinders]]",
        1,
    );
    let r = solve_scene(&parse_str(&flat, Path::new("flat.toml")).unwrap());
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("does not fire evenly in the order 1-2-3-4")),
        "{:?}",
        r.warnings
    );
}
