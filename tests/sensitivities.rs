//! The operating envelope's sensitivity tables (issue 33, item 3), read off the optimum's
//! multipliers by the envelope theorem, against an independent evaluation: central
//! differences of whole re-solves with the interval end moved (h and 2h, the method the
//! slider-crank's table used before: 4 solves per end). The slider-crank's felling head (ΔE
//! over speed and tree mass) and piston (peak force over speed and two masses, where two
//! vertices tie), and the linkage press (peak force over speed and two link masses).

use crate::common::{problem, set_key};
use cwsynth::families::linkage::file::LinkageProblem;
use cwsynth::families::linkage::synth as ls;
use cwsynth::families::slider_crank::file::SliderCrankProblem;
use cwsynth::families::slider_crank::synth as sc;
use cwsynth::families::{parse_str, solve_scene};
use cwsynth::report::Status;
use serde_json::Value;
use std::path::Path;

/// dV*/d(end) by central differences of `v(d)` (the re-solved worst case and its error with
/// the end moved by d): the value at h and its error, |d_h − d_2h| plus the solves' errors
/// over the step.
pub(crate) fn resolved(h: f64, v: impl Fn(f64) -> (f64, f64)) -> (f64, f64) {
    let ((p1, e1), (m1, f1)) = (v(h), v(-h));
    let ((p2, e2), (m2, f2)) = (v(2.0 * h), v(-2.0 * h));
    let d1 = (p1 - m1) / (2.0 * h);
    let d2 = (p2 - m2) / (4.0 * h);
    (
        d1,
        (d1 - d2).abs() + (e1 + f1) / (2.0 * h) + (e2 + f2) / (4.0 * h),
    )
}

/// The solved file's status and its sensitivity rows.
pub(crate) fn rows_of(text: &str) -> (cwsynth::families::Scene, Vec<Value>) {
    let s = parse_str(text, Path::new("s.toml")).unwrap();
    let r = solve_scene(&s);
    assert_eq!(r.status, Status::Optimal, "{:?}", r.warnings);
    let rows = r.extra["envelope"]["sensitivities"]
        .as_array()
        .unwrap_or_else(|| panic!("no sensitivities: {:?}", r.warnings))
        .clone();
    (s, rows)
}

fn num(v: &Value, k: &str) -> f64 {
    v[k].as_f64().unwrap()
}

/// Row `k` (parameter k / 2, end min for even k) against `reference(i, upper)`: within both
/// errors and 1e-6 of the table's largest derivative, its error below `max_error` of it.
pub(crate) fn agree(
    rows: &[Value],
    which: impl Fn(usize) -> bool,
    max_error: f64,
    reference: impl Fn(usize, bool) -> (f64, f64),
) {
    let scale = rows
        .iter()
        .map(|r| num(r, "derivative").abs())
        .fold(0.0, f64::max);
    for (k, row) in rows.iter().enumerate() {
        if !which(k) {
            continue;
        }
        let (d, e) = (num(row, "derivative"), num(row, "error"));
        let (want, we) = reference(k / 2, k % 2 == 1);
        assert!(
            (d - want).abs() <= e + we + 1e-6 * scale,
            "{} {}: multipliers {d} ± {e}, re-solves {want} ± {we}",
            row["parameter"],
            row["end"]
        );
        assert!(e <= max_error * scale, "{row}: error too large");
    }
}

/// The slider-crank's table against re-solves of its scene with the end moved.
fn slider_crank_against_re_solves(text: &str) {
    let (s, rows) = rows_of(text);
    let base = s.machine::<SliderCrankProblem>().unwrap().core.clone();
    agree(
        &rows,
        |_| true,
        1e-5,
        |i, upper| {
            let (lo, hi) = base.envelope.ranges()[i];
            let h = 1e-3 * (hi - lo);
            resolved(h, |d| {
                let mut s = base.clone();
                s.envelope.monte_carlo = 0;
                s.envelope.sensitivities = false;
                let r = s.envelope.range_mut(i);
                if upper {
                    r.1 += d
                } else {
                    r.0 += d
                }
                let out = sc::solve(&s).unwrap();
                let w = out.envelope.unwrap().worst_for(s.objective).unwrap();
                (w.value, w.error + out.gap.max(0.0))
            })
        },
    );
}

#[test]
fn the_felling_heads_energy_table_matches_re_solves() {
    let text = std::fs::read_to_string(problem("felling-head-envelope.toml")).unwrap();
    slider_crank_against_re_solves(&set_key(&text, "mechanism.envelope.monte_carlo", "0"));
}

#[test]
fn the_pistons_force_table_matches_re_solves_where_two_vertices_tie() {
    let text = std::fs::read_to_string(problem("piston-1000rpm-envelope.toml")).unwrap();
    // Without the length tolerance (its worst case is not proven): speed and two masses.
    let i = text.find("\n[[mechanism.envelope.length]]").unwrap();
    let j = text.find("\n[model]").unwrap();
    let text = format!("{}{}", &text[..i], &text[j..]);
    slider_crank_against_re_solves(&set_key(&text, "mechanism.envelope.monte_carlo", "0"));
}

/// The press: every end against re-solves (two vertices, the heaviest and the lightest
/// coupler at the top speed and ram, tie at the optimum: the coupler's lower end costs too).
#[test]
fn the_linkage_press_table_matches_re_solves() {
    let text = std::fs::read_to_string(problem("linkage-sixbar-press-envelope.toml")).unwrap();
    let text = set_key(&text, "mechanism.envelope.monte_carlo", "0");
    let text = set_key(&text, "mechanism.envelope.sensitivities", "true");
    let (s, rows) = rows_of(&text);
    assert_eq!(rows.len(), 6);
    let p: &LinkageProblem = s.machine().unwrap();
    agree(
        &rows,
        |_| true,
        1e-5,
        |i, upper| {
            let (lo, hi) = p.scene.envelope.ranges()[i];
            resolved(1e-3 * (hi - lo), |d| linkage_resolved(p, i, upper, d))
        },
    );
}

/// An optimum without multipliers (the lightest counterweights: no peak objective for
/// Newton's polish) gets a warning saying why, and no table.
#[test]
fn an_optimum_without_multipliers_says_why_instead_of_a_table() {
    let text = std::fs::read_to_string(problem("linkage-sixbar-press-envelope.toml")).unwrap();
    let text = set_key(&text, "mechanism.envelope.monte_carlo", "0");
    let text = set_key(&text, "objective.minimize", "\"counterweight-mass\"");
    let text = set_key(&text, "objective.max_peak_force", "\"200 N\"");
    let s = parse_str(&text, Path::new("m.toml")).unwrap();
    let r = solve_scene(&s);
    assert!(r.extra["envelope"].get("sensitivities").is_none());
    assert!(
        r.warnings.iter().any(|w| w.contains("no multipliers")),
        "{:?}",
        r.warnings
    );
}

/// The linkage scene's optimised worst case (the engine's objective and its error), re-solved
/// with the end of its envelope's parameter `i` (speed, masses, lengths in that order) moved
/// by `d`: the reference of the linkage tables.
pub(crate) fn linkage_resolved(p: &LinkageProblem, i: usize, upper: bool, d: f64) -> (f64, f64) {
    let mut sc = p.scene.clone();
    sc.envelope.monte_carlo = 0;
    sc.envelope.sensitivities = false;
    let (speeds, masses) = (
        usize::from(sc.envelope.speed.is_some()),
        sc.envelope.masses.len(),
    );
    let e = &mut sc.envelope;
    let r: &mut (f64, f64) = if i < speeds {
        e.speed.as_mut().unwrap()
    } else if i - speeds < masses {
        &mut e.masses[i - speeds].mass
    } else {
        &mut e.lengths[i - speeds - masses].delta
    };
    if upper {
        r.1 += d
    } else {
        r.0 += d
    }
    let sol = ls::solve(&sc, &p.settings).unwrap().design.unwrap();
    (sol.objective, sol.error.total)
}
