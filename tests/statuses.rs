//! A status is a claim (issue 34): a given design is `analysed`, a limit no design meets is
//! `infeasible` and says how far off it is (the least reachable value, checked against the
//! solve that minimises that quantity alone), and a counterweight that cannot move the
//! objective makes the problem `degenerate`.

use crate::common::{problem, set_key, with};
use cwsynth::families::{parse_str, solve_scene};
use cwsynth::report::{SolveResult, Status};
use std::path::Path;

fn solve(text: &str) -> SolveResult {
    solve_scene(&parse_str(text, Path::new("case.toml")).expect("a valid problem"))
}

fn shipped(name: &str) -> String {
    std::fs::read_to_string(problem(name)).unwrap()
}

/// The piston with its counterweight given (mass, radius and angle): an analysis.
#[test]
fn a_given_slider_crank_counterweight_is_analysed_not_optimal() {
    let base = shipped("piston-1000rpm.toml");
    let text = with(
        &with(
            &base,
            "unbalance = { min = \"0 kg*m\", max = \"0.2 kg*m\" }",
            "mass = \"4.68 kg\"",
        ),
        "angle = { min = \"0 deg\", max = \"360 deg\" }",
        "angle = \"180 deg\"",
    );
    let r = solve(&text);
    assert_eq!(r.status, Status::Analysed, "{:?}", r.status_detail);
    // No "a larger counterweight would lower the objective": nothing was optimised.
    assert!(r.bounds.is_empty(), "{:?}", r.bounds);
    assert!((r.design["counterweight_unbalance_kgm"] - 0.234).abs() < 1e-12);
    assert_eq!(r.status.design_label(), "given design");
    // A given design over a limit is still analysed, and says so.
    let over = set_key(&text, "objective.max_peak_force", "\"50 N\"");
    let r = solve(&over);
    assert_eq!(r.status, Status::Analysed);
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("exceeds objective.max_peak_force")),
        "{:?}",
        r.warnings
    );
}

/// `max_peak_force = 50 N` on the piston, whose best possible peak is the minimax optimum
/// (298.9 N): `infeasible`, the least reachable value in the detail and in `infeasibility`,
/// equal to the free solve's optimum within the stated errors; the design shown is that
/// closest one, so every figure is finite.
#[test]
fn an_unreachable_force_limit_is_infeasible_and_says_how_far_off() {
    let base = shipped("piston-1000rpm.toml");
    let free = solve(&base);
    assert_eq!(free.status, Status::Optimal);
    let best = free.objectives["peak_shaking_force_n"];
    let best_err = free.errors["peak_shaking_force_n"];
    assert!((best - 298.947).abs() < 1e-3, "{best}");

    let r = solve(&set_key(&base, "objective.max_peak_force", "\"50 N\""));
    assert_eq!(r.status, Status::Infeasible, "{:?}", r.status_detail);
    let detail = r.status_detail.clone().unwrap();
    assert!(detail.contains("objective.max_peak_force"), "{detail}");
    assert!(detail.contains("298.94"), "{detail}");
    assert!(!detail.contains("Some("), "{detail}");
    assert!(
        r.warnings.iter().all(|w| !w.contains("Some(")),
        "{:?}",
        r.warnings
    );
    assert_eq!(r.infeasibility.len(), 1);
    let s = &r.infeasibility[0];
    assert_eq!(s.limit, "objective.max_peak_force");
    assert!(s.certified && !s.reachable_alone());
    assert!(
        (s.closest - best).abs() <= s.error + best_err + 1e-9 * best,
        "{s:?} vs {best}"
    );
    // The design shown is the closest one: its peak is the least reachable.
    assert!((r.objectives["peak_shaking_force_n"] - best).abs() < 1e-6 * best);
    let json = serde_json::to_value(&r).unwrap();
    assert_eq!(json["status"], "infeasible");
    assert_eq!(
        json["infeasibility"][0]["limit"],
        "objective.max_peak_force"
    );
    assert!((json["infeasibility"][0]["closest"].as_f64().unwrap() - best).abs() < 1e-6);
    // A limit just above the least reachable value is met.
    let ok = solve(&set_key(
        &base,
        "objective.max_peak_force",
        &format!("\"{} N\"", best * 1.001),
    ));
    assert_eq!(ok.status, Status::Optimal, "{:?}", ok.status_detail);
}

/// A torque limit below the least peak torque (without gravity every counterweight has the
/// same torque): the shortfall names the torque.
#[test]
fn an_unreachable_torque_limit_names_the_torque() {
    let base = shipped("piston-1000rpm.toml");
    let free = solve(&base);
    let t = free.objectives["peak_drive_torque_nm"];
    let r = solve(&set_key(&base, "objective.max_peak_torque", "\"1 N*m\""));
    assert_eq!(r.status, Status::Infeasible, "{:?}", r.status_detail);
    let s = &r.infeasibility[0];
    assert_eq!(s.limit, "objective.max_peak_torque");
    assert!((s.closest - t).abs() < 1e-6 * t, "{s:?} vs {t}");
}

/// The crane's infeasible result says which check fails and by how much (a heuristic search:
/// not certified).
#[test]
fn an_infeasible_crane_says_which_check_fails() {
    let base = shipped("crane-thesis-optimise.toml");
    let r = solve(&with(
        &base,
        "max_distance = \"15 m\"",
        "max_distance = \"0.5 m\"",
    ));
    assert_eq!(r.status, Status::Infeasible);
    assert!(!r.infeasibility.is_empty());
    assert!(r.infeasibility.iter().all(|s| !s.certified));
    let detail = r.status_detail.unwrap();
    assert!(detail.contains("checks.tie_pin_limit"), "{detail}");
    assert!(detail.contains("not a proof"), "{detail}");
}

/// A linkage limit below what any counterweight reaches: the least peak force is that of the
/// free minimax solve.
#[test]
fn an_infeasible_linkage_limit_says_how_far_off() {
    let base = shipped("linkage-fourbar-crank-counterweight.toml");
    let free = solve(&base);
    assert_eq!(free.status, Status::Optimal);
    let best = free.objectives["peak_shaking_force_n"];
    let r = solve(&set_key(&base, "objective.max_peak_force", "\"1 N\""));
    assert_eq!(r.status, Status::Infeasible);
    let s = &r.infeasibility[0];
    assert!(s.certified && !s.reachable_alone());
    assert!(
        (s.closest - best).abs() <= s.error + free.errors["peak_shaking_force_n"] + 1e-9,
        "{s:?} vs {best}"
    );
    assert!(r.status_detail.unwrap().contains("52.8"));
}

/// A crank counterweight cannot change the drive torque of a constant-speed linkage without
/// gravity: minimising the torque with it is degenerate, not optimal. With the peak force it is
/// a proper problem again.
#[test]
fn a_counterweight_the_objective_ignores_makes_it_degenerate() {
    let base = shipped("linkage-fourbar-crank-counterweight.toml");
    let r = solve(&with(
        &base,
        "minimize = \"peak-force\"",
        "minimize = \"peak-torque\"",
    ));
    assert_eq!(r.status, Status::Degenerate);
    assert!(r.status_detail.unwrap().contains("crank"));
    // A limit on a field it enters makes it matter again.
    let limited = with(
        &base,
        "minimize = \"peak-force\"",
        "minimize = \"peak-torque\"\nmax_peak_force = \"80 N\"",
    );
    assert_ne!(solve(&limited).status, Status::Degenerate);
    // The shipped full-balance scene: the crank counterweight does not enter the moment, but
    // the balance constrains it.
    let fb = solve(&shipped("linkage-fourbar-force-balance.toml"));
    assert_eq!(fb.status, Status::Optimal);
}
