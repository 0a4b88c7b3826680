//! Hostile input: random and mutated problem files through the parser, the resolver and
//! (when the file resolves) the solver, under a time bound. No input may panic; every
//! rejection must start `FILE:LINE:` (the field rule is checked by `tests/mutants.rs`).
//!
//! The mutations start from the shipped `problems/*.toml`: delete, duplicate or swap lines,
//! rename keys (to random names or to keys of other families), replace values (other types,
//! random units, NaN/inf, huge and negative numbers, arrays, tables), insert random bytes,
//! truncate, or throw the file away for random text.
//!
//! `cargo test --test integration hostile_input::` runs 2000 inputs (about 10–30 s). A longer campaign:
//!
//! ```text
//! FUZZ_CASES=200000 FUZZ_SOLVE_BUDGET_S=600 cargo test --release --test integration hostile_input:: -- --nocapture
//! ```
//!
//! (`FUZZ_CASES`: inputs tried; `FUZZ_SOLVE_BUDGET_S`: total seconds spent solving the inputs
//! that resolve — after it is used up, later inputs are only parsed and resolved;
//! `PROPTEST_RNG_SEED` changes the sequence.)

use cwsynth::families::parse_str;
use cwsynth::families::solve_scene;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Mutex};
use std::time::{Duration, Instant};

fn seeds() -> Vec<String> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/problems");
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    v.sort();
    v.iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect()
}

/// Every key written in the seeds (the left side of `key = value`, and section names).
fn known_keys(seeds: &[String]) -> Vec<String> {
    let mut k: Vec<String> = seeds
        .iter()
        .flat_map(|s| s.lines())
        .filter_map(|l| {
            let l = l.trim();
            if l.starts_with('[') {
                Some(l.trim_matches(|c| c == '[' || c == ']').to_string())
            } else {
                l.split_once('=')
                    .map(|(a, _)| a.trim().to_string())
                    .filter(|a| !a.is_empty() && !a.starts_with('#'))
            }
        })
        .collect();
    k.sort();
    k.dedup();
    k
}

#[derive(Debug, Clone)]
enum Mutation {
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    RenameKey(usize, String),
    ReplaceValue(usize, String),
    InsertBytes(usize, String),
    Truncate(usize),
    AppendLine(String),
}

const UNITS: &[&str] = &[
    "mm", "m", "cm", "km", "kg", "g", "t", "deg", "rad", "rpm", "rad/s", "N", "kN", "N*m", "N·m",
    "kg*m", "kg*m^2", "kg/m^3", "m/s^2", "s", "ms", "", "furlong", "mm mm", "°", "1/s", "kg m",
    "Nm", "rpm/s",
];

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<f64>().prop_map(|x| format!("{x:e}")),
        (-1e6f64..1e6).prop_map(|x| format!("{x}")),
        any::<i64>().prop_map(|x| x.to_string()),
        prop::sample::select(vec![
            "nan",
            "inf",
            "-inf",
            "+nan",
            "0",
            "-0.0",
            "1e308",
            "-1e308",
            "1e-320",
            "-1",
            "9999999999",
            "4294967296",
            "18446744073709551615",
            "0x10",
            "1_000",
            "1e",
            "--1",
            ".5",
            "5.",
        ])
        .prop_map(String::from),
    ]
}

fn value() -> impl Strategy<Value = String> {
    let quantity = || {
        (number(), prop::sample::select(UNITS))
            .prop_map(|(n, u)| format!("\"{n} {u}\"").replace(" \"", "\""))
    };
    prop_oneof![
        4 => number(),
        4 => quantity(),
        1 => Just("true".to_string()),
        1 => Just("\"\"".to_string()),
        1 => "\"[a-z\\- ]{0,12}\"".prop_map(|s| s),
        1 => (quantity(), quantity()).prop_map(|(a, b)| format!("{{ min = {a}, max = {b} }}")),
        1 => (number(), quantity()).prop_map(|(a, b)| format!("[{a}, {b}]")),
        1 => Just("[]".to_string()),
        1 => Just("{}".to_string()),
        1 => Just("1979-05-27T07:32:00Z".to_string()),
    ]
}

fn mutation(keys: Vec<String>) -> impl Strategy<Value = Mutation> {
    let line = 0usize..200;
    let ident = prop_oneof![
        "[a-z_]{1,12}".prop_map(|s| s),
        prop::sample::select(keys.clone()),
        prop::sample::select(keys.clone()).prop_map(|k| format!("{k}.x")),
        Just("\"quoted key\"".to_string()),
    ];
    prop_oneof![
        3 => line.clone().prop_map(Mutation::DeleteLine),
        2 => line.clone().prop_map(Mutation::DuplicateLine),
        1 => (line.clone(), line.clone()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        3 => (line.clone(), ident.clone()).prop_map(|(a, k)| Mutation::RenameKey(a, k)),
        6 => (line.clone(), value()).prop_map(|(a, v)| Mutation::ReplaceValue(a, v)),
        2 => (0usize..8000, prop::collection::vec(any::<u8>(), 1..12))
            .prop_map(|(a, b)| Mutation::InsertBytes(a, String::from_utf8_lossy(&b).into_owned())),
        1 => (0usize..8000).prop_map(Mutation::Truncate),
        2 => (ident, value()).prop_map(|(k, v)| Mutation::AppendLine(format!("{k} = {v}"))),
    ]
}

fn apply(text: &str, muts: &[Mutation]) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    for m in muts {
        let n = lines.len().max(1);
        match m {
            Mutation::DeleteLine(i) if !lines.is_empty() => {
                lines.remove(i % n);
            }
            Mutation::DuplicateLine(i) if !lines.is_empty() => {
                let l = lines[i % n].clone();
                lines.insert(i % n, l);
            }
            Mutation::SwapLines(a, b) if !lines.is_empty() => lines.swap(a % n, b % n),
            Mutation::RenameKey(i, k) if !lines.is_empty() => {
                let l = &mut lines[i % n];
                if let Some((_, v)) = l.split_once('=') {
                    *l = format!("{k} ={v}");
                } else if l.trim_start().starts_with('[') {
                    *l = format!("[{k}]");
                }
            }
            Mutation::ReplaceValue(i, v) if !lines.is_empty() => {
                let l = &mut lines[i % n];
                if let Some((k, _)) = l.split_once('=') {
                    *l = format!("{k}= {v}");
                }
            }
            Mutation::InsertBytes(at, b) => {
                let mut s = lines.join("\n");
                let mut at = at % (s.len() + 1);
                while !s.is_char_boundary(at) {
                    at -= 1;
                }
                s.insert_str(at, b);
                lines = s.lines().map(String::from).collect();
            }
            Mutation::Truncate(at) => {
                let mut s = lines.join("\n");
                let mut at = at % (s.len() + 1);
                while !s.is_char_boundary(at) {
                    at -= 1;
                }
                s.truncate(at);
                lines = s.lines().map(String::from).collect();
            }
            Mutation::AppendLine(l) => lines.push(l.clone()),
            _ => {}
        }
    }
    lines.join("\n")
}

fn env_or<T: std::str::FromStr>(k: &str, d: T) -> T {
    std::env::var(k)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(d)
}

/// Solves on a worker thread; `Err` when it takes longer than `limit` (the thread is left
/// behind: the test fails anyway) or panics.
fn solve_bounded(s: cwsynth::families::Scene, limit: Duration) -> Result<(), String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| solve_scene(&s)));
        let _ = tx.send(r.map(|_| ()).map_err(|_| "solver panicked".to_string()));
    });
    match rx.recv_timeout(limit) {
        Ok(r) => r,
        Err(_) => Err(format!("solver took longer than {limit:?}")),
    }
}

#[test]
fn mutated_problem_files_never_panic_and_rejections_name_a_field_or_line() {
    let seeds = seeds();
    let keys = known_keys(&seeds);
    let cases: u32 = env_or("FUZZ_CASES", 2000);
    let budget = Duration::from_secs_f64(env_or("FUZZ_SOLVE_BUDGET_S", 6.0));
    let limit = Duration::from_secs_f64(env_or("FUZZ_SOLVE_LIMIT_S", 20.0));
    let tried = AtomicUsize::new(0);
    let (rejected, resolved, solved) = (
        AtomicUsize::new(0),
        AtomicUsize::new(0),
        AtomicUsize::new(0),
    );
    let solve_time = Mutex::new(Duration::ZERO);
    let n_seeds = seeds.len();
    let input = prop_oneof![
        // Mutated shipped files (mostly a few mutations, so many still resolve).
        9 => (0..n_seeds, prop::collection::vec(mutation(keys), 0..5))
            .prop_map(move |(i, m)| (i, m)),
        // Pure random text.
        1 => prop::collection::vec(any::<u8>(), 0..400).prop_map(|b| (usize::MAX, vec![
            Mutation::AppendLine(String::from_utf8_lossy(&b).into_owned())
        ])),
    ];
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let t0 = Instant::now();
    let out = runner.run(&input, |(i, muts)| {
        let base = if i == usize::MAX {
            ""
        } else {
            seeds[i].as_str()
        };
        let text = apply(base, &muts);
        tried.fetch_add(1, Ordering::Relaxed);
        let parsed = std::panic::catch_unwind(|| parse_str(&text, Path::new("fuzz.toml")))
            .map_err(|_| TestCaseError::fail(format!("parser panicked on:\n{text}")))?;
        match parsed {
            Err(e) => {
                rejected.fetch_add(1, Ordering::Relaxed);
                let located = e
                    .line()
                    .is_some_and(|l| e.to_string().starts_with(&format!("fuzz.toml:{l}:")));
                if !located {
                    return Err(TestCaseError::fail(format!(
                        "rejection without `FILE:LINE:`: {e}\n--- input:\n{text}"
                    )));
                }
            }
            Ok(s) => {
                resolved.fetch_add(1, Ordering::Relaxed);
                if *solve_time.lock().unwrap() < budget {
                    let t = Instant::now();
                    solve_bounded(s, limit)
                        .map_err(|m| TestCaseError::fail(format!("{m}; input:\n{text}")))?;
                    *solve_time.lock().unwrap() += t.elapsed();
                    solved.fetch_add(1, Ordering::Relaxed);
                }
            }
        }
        Ok(())
    });
    println!(
        "hostile input: {} inputs tried ({} rejected, {} resolved, {} of them solved) in {:.1} s",
        tried.load(Ordering::Relaxed),
        rejected.load(Ordering::Relaxed),
        resolved.load(Ordering::Relaxed),
        solved.load(Ordering::Relaxed),
        t0.elapsed().as_secs_f64()
    );
    if let Err(e) = out {
        panic!("{e}");
    }
}

/// A point or range given with a third value is refused at its field, not cut to two.
#[test]
fn a_pair_with_a_third_value_is_refused_at_its_field() {
    let cases = [
        (
            "crane-thesis-inclined-rope.toml",
            "sheave = [\"4 m\", \"9 m\"]",
            "sheave = [\"4 m\", \"9 m\", \"1 m\"]",
            "mechanism.hoist_rope.sheave",
        ),
        (
            "crane-tukan-40t-counterweight.toml",
            "directions = [\"150 deg\", \"210 deg\"]",
            "directions = [\"150 deg\", \"210 deg\", \"240 deg\"]",
            "design.counterweight.directions",
        ),
        (
            "crane-tukan-40t.toml",
            "x_range = [\"0 m\", \"12 m\"]",
            "x_range = [\"0 m\"]",
            "",
        ),
        (
            "hypocycloid-compressor.toml",
            "centroid = [\"12.5 mm\", \"0 mm\"]",
            "centroid = [\"12.5 mm\", \"0 mm\", \"3 mm\"]",
            "",
        ),
        (
            "linkage-sixbar-press.toml",
            "line_point = [\"120 mm\", \"0 mm\"]",
            "line_point = [\"120 mm\", \"0 mm\", \"0 mm\"]",
            "",
        ),
    ];
    for (file, from, to, field) in cases {
        let base = std::fs::read_to_string(crate::common::problem(file)).unwrap();
        let text = crate::common::with(&base, from, to);
        let e = crate::common::err(&text);
        let msg = e.to_string();
        assert!(msg.contains("exactly 2 values"), "{file}: {msg}");
        assert_eq!(
            e.line(),
            Some(crate::common::line_of(&text, to)),
            "{file}: {msg}"
        );
        if !field.is_empty() {
            assert!(msg.contains(field), "{file}: {msg}");
        }
    }
}
