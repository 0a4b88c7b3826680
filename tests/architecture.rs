//! The seam between solving and reporting (issue 32), held against the code: a family's
//! `numbers.rs` and `report.rs` and the shared `report/` shape and draw a solved value and never
//! call a solve, a search or a peak refinement — every solve a result shows ran in the family's
//! `solve.rs` — and a solved scene carries no document until one is asked for.

use cwsynth::families::{load, solve_scene};
use std::path::Path;

/// Calls that solve or search: a report must not make them.
const SOLVING: [&str; 20] = [
    "solve(",
    "solve_dynamics",
    "optimise(",
    "metrics(",
    "landscape(",
    "joint_peaks(",
    "speed_sweep(",
    "pareto(",
    "sector_realising(",
    "brent_",
    "BrentOpt",
    "BrentRoot",
    "NelderMead",
    "Executor",
    "clarabel::",
    "periodic_peak",
    "interval_peak",
    "refine_sampled",
    "minimize_1d",
    "newton_root",
];

/// The report sources: every family's `numbers.rs` and `report.rs`, and everything under
/// `src/report/`.
fn report_sources() -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    for dir in ["src/families", "src/report"] {
        let mut stack = vec![Path::new(dir).to_path_buf()];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).unwrap().flatten() {
                let p = e.path();
                if p.is_dir() {
                    stack.push(p);
                } else if dir == "src/report"
                    || ["report.rs", "numbers.rs"]
                        .contains(&p.file_name().unwrap().to_str().unwrap())
                {
                    files.push(p);
                }
            }
        }
    }
    files.sort();
    files
}

#[test]
fn no_report_calls_a_solve_or_a_search() {
    let files = report_sources();
    assert!(files.len() >= 5 + 5, "{files:?}");
    let mut found = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for call in SOLVING {
                // A definition of that name (`fn solve(`) is not a call.
                if code.contains(call) && !code.contains(&format!("fn {call}")) {
                    found.push(format!("{}:{}: {}", f.display(), n + 1, line.trim()));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "reports that solve:\n{}",
        found.join("\n")
    );
}

/// A solved scene of every family has its numbers and no table, plot or drawing until they
/// are asked for: a `--summary-only` batch, a study rung or a calibration step makes none.
#[test]
fn a_solve_makes_no_documents_until_asked() {
    for name in [
        "piston-1000rpm",
        "crane-tukan-40t-counterweight",
        "hypocycloid-compressor",
        "gear-tooth-profiles",
        "linkage-fourbar-pareto",
    ] {
        let s = load(Path::new(&format!("problems/{name}.toml"))).unwrap();
        let mut r = solve_scene(&s);
        assert!(!r.objectives.is_empty(), "{name}");
        assert!(
            r.tables.is_empty() && r.plots.is_empty() && r.drawings.is_empty(),
            "{name}: documents made by the solve"
        );
        r.draw();
        assert!(!r.plots.is_empty() && !r.drawings.is_empty(), "{name}");
        let numbers = (r.design.clone(), r.objectives.clone(), r.warnings.clone());
        r.complete();
        assert!(r.deferred.is_empty(), "{name}");
        assert_eq!(
            numbers,
            (r.design.clone(), r.objectives.clone(), r.warnings.clone())
        );
    }
}
