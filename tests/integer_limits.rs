//! Issue 14, item 7: every integer setting of every family (the table of
//! `cwsynth::problem::limits`) at 0, 1, its minimum, its maximum, one past each end, i64::MAX and
//! u64::MAX. Out of its range a value is an error naming the file, the line and the key; in
//! its range the file either resolves, or is rejected by another check with a field and a
//! line; a resolved file solves within a time bound (no panic, abort or hang) and its result
//! has no inf or NaN in its number maps. Independent reference: the documented range itself
//! (`docs/problem-files.md`), and the finiteness of every reported number.

use cwsynth::families::by_name;
use cwsynth::families::parse_str;
use cwsynth::families::solve_scene;
use cwsynth::problem::limits::Count;
use cwsynth::report::SolveResult;
use std::path::Path;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::common;
use common::{assert_finite_as, integer_key_base, set_key};

fn problem(name: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems")
        .join(name);
    std::fs::read_to_string(p).unwrap()
}

/// Solves on a thread; the result, or an error after `limit`.
fn solve_bounded(s: cwsynth::families::Scene, limit: Duration) -> Result<SolveResult, String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(solve_scene(&s));
    });
    rx.recv_timeout(limit)
        .map_err(|_| format!("no result within {limit:?}"))
}

/// The sweep of one family (one test per family, so that they run side by side).
fn sweep(family: &str) {
    // Generous for a shared 2-core machine in the test profile; each maximum was chosen to
    // solve in about a second or less there.
    let limit = Duration::from_secs(20);
    let mut slowest = (Duration::ZERO, String::new());
    let mut slow = Vec::new();
    {
        for &Count { key, min, max } in by_name(family).unwrap().counts() {
            let text = problem(integer_key_base(family, key));
            let mut values = vec![0, 1, min, max, max + 1, i64::MAX as u64, u64::MAX];
            if min > 0 {
                values.push(min - 1);
            }
            values.sort_unstable();
            values.dedup();
            for v in values {
                let written = if key == "objective.balance_orders" {
                    format!("[{v}]")
                } else {
                    v.to_string()
                };
                let t = set_key(&text, key, &written);
                let what = format!("{family} {key} = {written}");
                let file = Path::new("limits.toml");
                match parse_str(&t, file) {
                    Err(e) => {
                        assert!(e.line().is_some() && e.field().is_some(), "{what}: {e}");
                        if !(min..=max).contains(&v) {
                            assert_eq!(e.field(), Some(key), "{what}: {e}");
                            assert!(e.to_string().starts_with("limits.toml:"), "{what}: {e}");
                        }
                    }
                    Ok(scene) => {
                        assert!((min..=max).contains(&v), "{what}: accepted out of range");
                        let t0 = Instant::now();
                        let r = match solve_bounded(scene, limit) {
                            Ok(r) => r,
                            Err(e) => {
                                slow.push(format!("{what}: {e}"));
                                continue;
                            }
                        };
                        let dt = t0.elapsed();
                        if dt > Duration::from_millis(300) {
                            eprintln!("{what}: {dt:?}");
                        }
                        if dt > slowest.0 {
                            slowest = (dt, what.clone());
                        }
                        assert_finite_as(&r, &what);
                    }
                }
            }
        }
    }
    eprintln!("slowest accepted run: {:?} ({})", slowest.0, slowest.1);
    assert!(slow.is_empty(), "{slow:#?}");
}

#[test]
fn slider_crank_integer_settings() {
    sweep("slider-crank");
}

#[test]
fn luffing_crane_integer_settings() {
    sweep("luffing-crane");
}

#[test]
fn eccentric_gear_integer_settings() {
    sweep("eccentric-gear");
}

#[test]
fn hypocycloid_integer_settings() {
    sweep("hypocycloid");
}
