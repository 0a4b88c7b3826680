//! Issue 15: a deterministic mutation suite over every shipped problem file.
//!
//! The generator below (a fixed-seed splitmix64, no time or thread dependence) turns each
//! `problems/*.toml` into mutants: every line deleted and duplicated, adjacent and random
//! lines swapped, truncation at random byte offsets, extreme numbers (0, −1, ±1e308, 1e-308,
//! NaN, ±inf, huge integers, i64::MAX, u64::MAX) in each value, wrong units (`parsec`, a unit
//! of another dimension, none), wrong types (string ↔ number ↔ table ↔ array ↔ boolean ↔
//! date, a table turned into an array of tables), bad UTF-8 bytes, 10,000-deep nesting,
//! very long strings, numbers and keys, huge arrays and tables; then every integer setting
//! of `cwsynth::problem::limits` at 0, 1, its maximum and u64::MAX, and every family's integer
//! settings all at their maxima together (the combinations a work budget must refuse).
//!
//! Each mutant goes the way of `cwsynth solve`, in process: [`parse_bytes`] (read, resolve)
//! and, when accepted, [`solve_scene`] — on a thread with the main thread's stack, under a
//! time limit. Every mutant is read; distinct accepted scenes are solved once each (a deleted
//! comment gives the scene of the shipped file), at most [`SOLVES_PER_FILE`] of each file's
//! (fewer of a synthesis scene's, each a whole search), a fixed, evenly spread choice: solving
//! all 802 was 72 s, most of it in the search scenes. Asserted for every mutant:
//!
//! * no panic (caught), no hang (over [`LIMIT`]), no abort (the binary would die);
//! * an accepted scene's result has only finite numbers (`common::non_finite`);
//! * a rejection starts `problems/mut.toml:LINE:` with the line inside the file; it names the field
//!   (`` field `…` ``) whenever the text is TOML (read by the `toml` crate as an independent
//!   check) within the size limit, so only a text that is not TOML at all (syntax, bad
//!   UTF-8, too deep) or too large may lack one; a duplicated key names the key.
//!
//! The tallies of every kind of failure are printed before the assertion, so a run on an
//! older build is the issue's table (`cargo test --test integration mutants:: -- --nocapture`);
//! with `MUTANTS_TIMES=1` also the time spent on each file's mutants (what to look at when
//! this test, the longest of the suite, grows).

use crate::common;

use common::{non_finite, set_key};
use cwsynth::families::solve_scene;
use cwsynth::families::{parse_bytes, parse_str, FAMILIES};
use cwsynth::problem::MAX_FILE_BYTES;
use std::collections::{BTreeMap, HashSet};
use std::path::Path;
use std::sync::{mpsc, Mutex};
use std::time::{Duration, Instant};

/// Time allowed to one mutant (read, resolve and solve) before it counts as a hang: far
/// above any accepted scene's run (the work budgets keep those to seconds) so that a loaded
/// 2-core machine does not make a false alarm.
const LIMIT: Duration = Duration::from_secs(20);

/// The file name the mutants are read as: beside the shipped scenes (never written), so a
/// drawing a scene names (`outline.file`, relative to its folder) resolves as it does for
/// the shipped file and its mutants are solved, not refused for a missing drawing.
const FILE: &str = "problems/mut.toml";

/// splitmix64: a small deterministic generator (the sequence is part of the suite).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

/// One mutant: where it came from, what was done, and its bytes.
pub(crate) struct Mutant {
    pub(crate) what: String,
    pub(crate) bytes: Vec<u8>,
    /// A key the mutant duplicated: the rejection must name it.
    duplicated: Option<String>,
}

const EXTREMES: &[&str] = &[
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-308",
    "nan",
    "inf",
    "-inf",
    "99999999999999999999",
    "9223372036854775807",
    "18446744073709551615",
    "-9223372036854775808",
];

const WRONG_TYPES: &[&str] = &[
    "\"text\"",
    "42",
    "-7.5",
    "{ a = 1 }",
    "{ min = 1, max = \"x\" }",
    "[1, 2]",
    "[\"1 m\", \"2 m\"]",
    "[]",
    "{}",
    "true",
    "1979-05-27",
    "07:32:00",
];

/// The shipped problem files, sorted: (file name, text).
fn seeds() -> Vec<(String, String)> {
    let mut v: Vec<_> = std::fs::read_dir(common::problem(""))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    v.sort();
    v.iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(p).unwrap())
        })
        .collect()
}

/// `key = value` split of a line (not a comment, not a table header).
fn assignment(line: &str) -> Option<(&str, &str)> {
    let t = line.trim_start();
    if t.starts_with('#') || t.starts_with('[') {
        return None;
    }
    line.split_once('=')
}

/// The first number in `value` replaced by `by`, or the whole value when it has none.
fn replace_number(value: &str, by: &str) -> String {
    let b = value.as_bytes();
    let start = (0..b.len()).find(|&i| {
        b[i].is_ascii_digit()
            || (matches!(b[i], b'-' | b'+' | b'.') && b.get(i + 1).is_some_and(u8::is_ascii_digit))
    });
    match start {
        Some(s) => {
            let end = (s + 1..b.len())
                .find(|&i| !matches!(b[i], b'0'..=b'9' | b'.' | b'e' | b'E' | b'_' | b'+' | b'-'))
                .unwrap_or(b.len());
            format!("{}{by}{}", &value[..s], &value[end..])
        }
        None => format!(" {by}"),
    }
}

/// The unit of the first quoted quantity in `value` (`"35 mm"` → `mm`), with its span.
fn quoted_unit(value: &str) -> Option<(usize, usize)> {
    let open = value.find('"')?;
    let close = open + 1 + value[open + 1..].find('"')?;
    let inner = &value[open + 1..close];
    let num_end = inner.find(|c: char| !matches!(c, '0'..='9' | '.' | 'e' | 'E' | '+' | '-'))?;
    if num_end == 0 {
        return None;
    }
    let unit_start =
        open + 1 + num_end + (inner[num_end..].len() - inner[num_end..].trim_start().len());
    (unit_start < close).then_some((unit_start, close))
}

/// A unit of another dimension than `unit`'s.
fn wrong_dimension(unit: &str) -> &'static str {
    match unit {
        "m" | "mm" | "cm" | "km" => "kg",
        _ => "m",
    }
}

/// The dotted key of line `i` (its table prefix and key), for the duplicate-key rule.
fn dotted_key(lines: &[&str], i: usize) -> Option<String> {
    let t = lines[i].trim();
    if let Some(h) = t.strip_prefix("[[") {
        // A repeated array-of-tables header is a new element, not a duplicate.
        let _ = h;
        return None;
    }
    if let Some(h) = t.strip_prefix('[') {
        return Some(h.split(']').next()?.trim().to_string());
    }
    let (k, _) = assignment(lines[i])?;
    Some(k.trim().trim_matches('"').to_string())
}

fn join(lines: &[String]) -> Vec<u8> {
    (lines.join("\n") + "\n").into_bytes()
}

/// Every mutant, in a fixed order.
pub(crate) fn mutants() -> Vec<Mutant> {
    let mut out = Vec::new();
    let mut rng = Rng(0x15_0015_2026);
    for (name, text) in seeds() {
        let lines: Vec<&str> = text.lines().collect();
        let owned = || lines.iter().map(|l| l.to_string()).collect::<Vec<_>>();
        let mut push = |what: String, bytes: Vec<u8>, duplicated: Option<String>| {
            out.push(Mutant {
                what: format!("{name}: {what}"),
                bytes,
                duplicated,
            })
        };
        let n = lines.len();
        for i in 0..n {
            let mut l = owned();
            l.remove(i);
            push(format!("line {} deleted", i + 1), join(&l), None);
            let mut l = owned();
            l.insert(i, lines[i].to_string());
            push(
                format!("line {} duplicated", i + 1),
                join(&l),
                dotted_key(&lines, i),
            );
            if i + 1 < n {
                let mut l = owned();
                l.swap(i, i + 1);
                push(
                    format!("lines {} and {} swapped", i + 1, i + 2),
                    join(&l),
                    None,
                );
            }
        }
        for _ in 0..10 {
            let (a, b) = (rng.below(n), rng.below(n));
            let mut l = owned();
            l.swap(a, b);
            push(
                format!("lines {} and {} swapped", a + 1, b + 1),
                join(&l),
                None,
            );
        }
        for _ in 0..25 {
            let at = rng.below(text.len() + 1);
            push(
                format!("truncated at byte {at}"),
                text.as_bytes()[..at].to_vec(),
                None,
            );
        }
        for (i, line) in lines.iter().enumerate() {
            let Some((k, v)) = assignment(line) else {
                if line.trim_start().starts_with('[') {
                    let t = line.trim();
                    let flipped = match t.strip_prefix("[[") {
                        Some(r) => format!("[{}", r.trim_end_matches(']')) + "]",
                        None => format!("[{t}]"),
                    };
                    let mut l = owned();
                    l[i] = flipped;
                    push(
                        format!("line {}: table ↔ array of tables", i + 1),
                        join(&l),
                        None,
                    );
                }
                continue;
            };
            for _ in 0..3 {
                let e = rng.pick(EXTREMES);
                let mut l = owned();
                l[i] = format!("{k}={}", replace_number(v, e));
                push(format!("line {}: number {e}", i + 1), join(&l), None);
            }
            for _ in 0..2 {
                let t = rng.pick(WRONG_TYPES);
                let mut l = owned();
                l[i] = format!("{k}= {t}");
                push(format!("line {}: value {t}", i + 1), join(&l), None);
            }
            if let Some((us, ue)) = quoted_unit(v) {
                let unit = &v[us..ue];
                for (label, by) in [
                    ("unknown unit", "parsec"),
                    ("wrong dimension", wrong_dimension(unit)),
                    ("no unit", ""),
                    ("misspelt unit", &format!("{unit}x")),
                ] {
                    let mut l = owned();
                    l[i] = format!("{k}={}{by}{}", &v[..us], &v[ue..]);
                    push(format!("line {}: {label} `{by}`", i + 1), join(&l), None);
                }
                // The quantity as a bare number, no quotes.
                let mut l = owned();
                let num = v[..us].rsplit('"').next().unwrap_or("").trim();
                l[i] = format!("{k}= {}", if num.is_empty() { "3" } else { num });
                push(format!("line {}: bare number", i + 1), join(&l), None);
            }
            // A misspelt key.
            let mut l = owned();
            let key = k.trim();
            l[i] = format!("{}{}={v}", &key[..key.len() - 1], "x");
            push(
                format!("line {}: key `{key}` misspelt", i + 1),
                join(&l),
                None,
            );
        }
        for _ in 0..6 {
            const BAD: [&[u8]; 6] = [
                &[0xff],
                &[0xc3, 0x28],
                &[0xed, 0xa0, 0x80],
                &[0xf8, 0x88, 0x80, 0x80, 0x80],
                &[0xe2, 0x82],
                &[0x80],
            ];
            let bad: &[u8] = BAD[rng.below(BAD.len())];
            let at = rng.below(text.len() + 1);
            let mut b = text.as_bytes().to_vec();
            b.splice(at..at, bad.iter().copied());
            push(format!("bad UTF-8 {bad:x?} at byte {at}"), b, None);
        }
        let deep = 10_000;
        let nests = [
            (
                "array",
                format!("{}1{}", "[".repeat(deep), "]".repeat(deep)),
            ),
            (
                "inline table",
                format!("{}1{}", "{ a = ".repeat(deep), " }".repeat(deep)),
            ),
        ];
        for (kind, v) in &nests {
            push(
                format!("{kind} nested {deep} deep at the top"),
                format!("deep = {v}\n{text}").into_bytes(),
                None,
            );
            // In place of a real value.
            if let Some(i) = lines
                .iter()
                .position(|l| assignment(l).is_some() && !l.starts_with("name"))
            {
                let mut l = owned();
                l[i] = format!("{}= {v}", assignment(lines[i]).unwrap().0);
                push(
                    format!("line {}: {kind} nested {deep} deep", i + 1),
                    join(&l),
                    None,
                );
            }
        }
        push(
            format!("table header nested {deep} deep"),
            format!("{text}\n[{}]\n", vec!["a"; deep].join(".")).into_bytes(),
            None,
        );
        let long = "x".repeat(100_000);
        for (label, edit) in [
            ("description of 100 kB", format!("description = \"{long}\"")),
            ("name of 100 kB", format!("name = \"{long}\"")),
            ("key of 100 kB", format!("{long} = 1")),
            (
                "number of 100,000 digits",
                format!("mechanism_x = \"{}1 m\"", "1".repeat(100_000)),
            ),
            (
                "quantity of 100,000 dots",
                format!("mechanism_x = \"1{} m\"", ".1".repeat(50_000)),
            ),
        ] {
            let key = edit.split('=').next().unwrap().trim().to_string();
            let mut l = owned();
            let replaced = if key.starts_with("mechanism_x") {
                // Into the first quantity of the file.
                let i = lines
                    .iter()
                    .position(|l| assignment(l).is_some_and(|(_, v)| quoted_unit(v).is_some()));
                i.map(|i| {
                    let (k, _) = assignment(lines[i]).unwrap();
                    l[i] = format!("{k}={}", edit.split_once('=').unwrap().1);
                })
            } else {
                lines
                    .iter()
                    .position(|x| x.starts_with(&key))
                    .map(|i| l[i] = edit.clone())
            };
            if replaced.is_none() {
                l.insert(0, edit);
            }
            push(label.to_string(), join(&l), None);
        }
        // Many elements: [[paper]] entries, a long array, many keys in one table.
        let paper =
            "[[paper]]\nquantity = \"q\"\nvalue = 1\nkey = \"objectives.x_pct\"\n".repeat(5_000);
        push(
            "5,000 [[paper]] entries".into(),
            format!("{text}\n{paper}").into_bytes(),
            None,
        );
        let many = (0..100_000)
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .join(", ");
        push(
            "array of 100,000 numbers".into(),
            format!("big = [{many}]\n{text}").into_bytes(),
            None,
        );
        let keys: String = (0..50_000).map(|k| format!("k{k} = 1\n")).collect();
        push(
            "50,000 keys in a table".into(),
            format!("{text}\n[accuracy_x]\n{keys}").into_bytes(),
            None,
        );
        push(
            "file of 16 MiB (comments)".into(),
            format!(
                "{text}\n{}",
                format!("# {}\n", "c".repeat(1000)).repeat(16_000)
            )
            .into_bytes(),
            None,
        );
    }
    out.extend(slider_crank_arrays());
    out.extend(integer_settings());
    out
}

/// Huge arrays in the slider-crank's own arrays: the process-force table, mass items.
fn slider_crank_arrays() -> Vec<Mutant> {
    let text = std::fs::read_to_string(common::problem("piston-1000rpm.toml")).unwrap();
    let table = |n: usize| {
        let angle = (0..n)
            .map(|k| format!("\"{} deg\"", k as f64 * 360.0 / n as f64))
            .collect::<Vec<_>>()
            .join(", ");
        let force = vec!["\"1 N\""; n].join(", ");
        format!("\n[mechanism.process_force_table]\nangle = [{angle}]\nforce = [{force}]\n")
    };
    let with_table = |n: usize| text.replace("\n[model]", &format!("{}\n[model]", table(n)));
    let items = |n: usize| {
        let t = text
            .replace("crank_mass = \"0.35 kg\"", "")
            .replace("slider_mass = \"1.03 kg\"", "");
        let items: String = (0..n)
            .map(|k| format!("[[mechanism.mass_items]]\nname = \"i{k}\"\nmass = \"0.001 kg\"\nat = \"slider\"\n"))
            .collect();
        t.replace("\n[model]", &format!("\n{items}\n[model]"))
    };
    [
        ("process_force_table of 1,000 points", with_table(1000)),
        ("process_force_table of 20,000 points", with_table(20_000)),
        ("5,000 mass_items", items(5_000)),
        ("100 mass_items", items(100)),
    ]
    .into_iter()
    .map(|(w, t)| Mutant {
        what: format!("piston-1000rpm.toml: {w}"),
        bytes: t.into_bytes(),
        duplicated: None,
    })
    .collect()
}

/// Every integer setting at 0, 1, its maximum and u64::MAX; and per family every setting
/// at its maximum at once, on each of the family's shipped files.
fn integer_settings() -> Vec<Mutant> {
    let mut out = Vec::new();
    let write = |key: &str, v: u64| {
        if key == "objective.balance_orders" {
            format!("[{v}]")
        } else {
            v.to_string()
        }
    };
    for family in FAMILIES.iter().map(|f| f.name()) {
        for c in cwsynth::families::by_name(family).unwrap().counts() {
            let file = common::integer_key_base(family, c.key);
            let text = std::fs::read_to_string(common::problem(file)).unwrap();
            for v in [0, 1, c.max, u64::MAX] {
                out.push(Mutant {
                    what: format!("{file}: {} = {v}", c.key),
                    bytes: set_key(&text, c.key, &write(c.key, v)).into_bytes(),
                    duplicated: None,
                });
            }
        }
        for file in common::family_files(family) {
            let mut text = std::fs::read_to_string(&file).unwrap();
            for c in cwsynth::families::by_name(family).unwrap().counts() {
                // n_fft_min must stay a power of two; the variant 1 or 2.
                let v = match c.key {
                    "mechanism.variant"
                    | "mechanism.turns_gear1"
                    | "mechanism.turns_gear2"
                    | "mechanism.teeth_gear1"
                    | "mechanism.teeth_gear2" => continue,
                    _ => c.max,
                };
                text = set_key(&text, c.key, &write(c.key, v));
            }
            out.push(Mutant {
                what: format!(
                    "{}: every integer setting at its maximum",
                    file.file_name().unwrap().to_string_lossy()
                ),
                bytes: text.into_bytes(),
                duplicated: None,
            });
        }
    }
    out
}

/// What went wrong with one mutant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Failure {
    Panic,
    Hang,
    NonFinite,
    NoLine,
    NoField,
    DuplicateWithoutKey,
}

/// The outcome of one mutant, computed on its own thread.
enum Outcome {
    Rejected(String, Option<usize>, Option<String>),
    /// Read and resolved; the scene's `Debug` text (what makes two mutants the same scene).
    Accepted(String),
    Solved(Option<String>),
    Panicked(String),
}

/// Reads (and resolves) a mutant and, when `solve`, solves the scene it gives.
fn run_one(bytes: Vec<u8>, solve: bool) -> Outcome {
    let r = std::panic::catch_unwind(move || match parse_bytes(&bytes, Path::new(FILE)) {
        Err(e) => Outcome::Rejected(e.to_string(), e.line(), e.field().map(str::to_string)),
        Ok(scene) if solve => Outcome::Solved(non_finite(&solve_scene(&scene))),
        Ok(scene) => Outcome::Accepted(format!("{scene:?}")),
    });
    r.unwrap_or_else(|p| {
        let m = p
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default();
        Outcome::Panicked(m)
    })
}

/// A checked mutant: its index, its failures (empty when all is well), its time, and the
/// scene's text when it was accepted (read pass only).
type Checked = (usize, Vec<(Failure, String)>, Duration, Option<String>);

/// Checks one mutant (read only, or read and solve): its failures (empty when all is well),
/// its time and, for an accepted mutant on the read pass, its scene's text.
fn check(m: &Mutant, solve: bool) -> (Vec<(Failure, String)>, Duration, Option<String>) {
    let (tx, rx) = mpsc::channel();
    let bytes = m.bytes.clone();
    let t0 = Instant::now();
    std::thread::Builder::new()
        .stack_size(8 << 20)
        .spawn(move || {
            let _ = tx.send(run_one(bytes, solve));
        })
        .unwrap();
    let outcome = rx.recv_timeout(LIMIT);
    let dt = t0.elapsed();
    let mut f = Vec::new();
    let mut accepted = None;
    match outcome {
        Err(_) => f.push((Failure::Hang, format!("no answer within {LIMIT:?}"))),
        Ok(Outcome::Panicked(p)) => f.push((Failure::Panic, p)),
        Ok(Outcome::Solved(Some(bad))) => f.push((Failure::NonFinite, bad)),
        Ok(Outcome::Solved(None)) => {}
        Ok(Outcome::Accepted(key)) => accepted = Some(key),
        Ok(Outcome::Rejected(msg, line, field)) => {
            let n_lines = m.bytes.split(|&b| b == b'\n').count();
            let located = line.is_some_and(|l| {
                l >= 1 && l <= n_lines && msg.starts_with(&format!("{FILE}:{l}:"))
            });
            if !located {
                f.push((Failure::NoLine, msg.clone()));
            }
            let is_toml = std::str::from_utf8(&m.bytes)
                .ok()
                .is_some_and(|t| t.parse::<toml::Table>().is_ok());
            let named = field
                .as_ref()
                .is_some_and(|k| msg.contains(&format!("field `{k}`")));
            if is_toml && m.bytes.len() <= MAX_FILE_BYTES && !named {
                f.push((Failure::NoField, msg.clone()));
            }
            if let Some(k) = &m.duplicated {
                let last = k.rsplit('.').next().unwrap();
                if !(msg.contains("duplicate") && msg.contains(last)) {
                    f.push((Failure::DuplicateWithoutKey, msg.clone()));
                }
            }
        }
    }
    (f, dt, accepted)
}

/// The most distinct accepted scenes of one shipped file that are solved. A file with more
/// has this many solved, spread evenly over its mutants in order (deletions, duplications,
/// swaps, truncations, extremes, units, types, …); the rest are read and resolved only.
/// Fixed, so the same mutants are solved on every run and every machine.
const SOLVES_PER_FILE: usize = 12;

/// The same for a search scene (a `[design.synthesis]` or `[design.phases]` table): each
/// solve is a whole search, a second or two in the test profile, 60 % of this test's time
/// when they had 12.
const SOLVES_PER_SEARCH_FILE: usize = 4;

/// The file a mutant came from (its description's first part).
fn file_of(m: &Mutant) -> &str {
    m.what.split(':').next().unwrap_or("")
}

/// The mutants to solve: each distinct accepted scene once (the first mutant that gives it),
/// at most [`SOLVES_PER_FILE`] (or [`SOLVES_PER_SEARCH_FILE`]) of each file's, evenly spaced.
fn to_solve(all: &[Mutant], read: &[Checked]) -> Vec<usize> {
    let mut seen = HashSet::new();
    let mut per: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for (i, _, _, key) in read {
        if let Some(k) = key {
            if seen.insert(k.as_str()) {
                per.entry(file_of(&all[*i])).or_default().push(*i);
            }
        }
    }
    let mut out: Vec<usize> = per
        .values()
        .flat_map(|v| {
            let text = String::from_utf8_lossy(&all[v[0]].bytes);
            let search = text.contains("[design.synthesis") || text.contains("[design.phases");
            let cap = if search {
                SOLVES_PER_SEARCH_FILE
            } else {
                SOLVES_PER_FILE
            };
            let n = v.len().min(cap);
            (0..n).map(move |j| v[j * v.len() / n])
        })
        .collect();
    out.sort_unstable();
    out
}

/// Checks the mutants `which` on two lanes (the machine has two cores), each on its own
/// thread under [`LIMIT`]; in the order of `which`.
fn check_all(all: &[Mutant], which: &[usize], solve: bool) -> Vec<Checked> {
    let next = Mutex::new(0usize);
    let results: Mutex<Vec<Checked>> = Mutex::default();
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let k = {
                    let mut n = next.lock().unwrap();
                    *n += 1;
                    *n - 1
                };
                let Some(&i) = which.get(k) else { break };
                let (f, dt, key) = check(&all[i], solve);
                results.lock().unwrap().push((i, f, dt, key));
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by_key(|r| r.0);
    results
}

#[test]
fn mutants_of_every_shipped_problem_file() {
    let all = mutants();
    let t0 = Instant::now();
    let read = check_all(&all, &(0..all.len()).collect::<Vec<_>>(), false);
    let which = to_solve(&all, &read);
    let solved = check_all(&all, &which, true);
    let mut tally: BTreeMap<Failure, Vec<String>> = BTreeMap::new();
    for (i, f, _, _) in read.iter().chain(&solved) {
        for (kind, msg) in f {
            let msg: String = msg.chars().take(300).collect();
            tally
                .entry(*kind)
                .or_default()
                .push(format!("{} → {msg}", all[*i].what));
        }
    }
    let accepted = read.iter().filter(|r| r.3.is_some()).count();
    let distinct: HashSet<_> = read.iter().filter_map(|r| r.3.as_deref()).collect();
    let slowest = solved.iter().max_by_key(|r| r.2);
    println!(
        "mutants: {} in {:.1} s; {accepted} accepted, {} distinct scenes, {} solved \
         (at most {SOLVES_PER_FILE} a file, {SOLVES_PER_SEARCH_FILE} a search file); slowest solve {:.2} s ({})",
        all.len(),
        t0.elapsed().as_secs_f64(),
        distinct.len(),
        solved.len(),
        slowest.map_or(0.0, |r| r.2.as_secs_f64()),
        slowest.map_or("", |r| all[r.0].what.as_str())
    );
    if std::env::var_os("MUTANTS_TIMES").is_some() {
        let mut per: BTreeMap<&str, f64> = BTreeMap::new();
        for (i, _, dt, _) in read.iter().chain(&solved) {
            *per.entry(file_of(&all[*i])).or_default() += dt.as_secs_f64();
        }
        let mut v: Vec<_> = per.into_iter().collect();
        v.sort_by(|a, b| b.1.total_cmp(&a.1));
        for (f, t) in v.iter().take(12) {
            println!("  {t:8.2} s  {f}");
        }
    }
    for (kind, v) in &tally {
        println!("{kind:?}: {}", v.len());
        for m in v.iter().take(if std::env::var_os("MUTANTS_ALL").is_some() {
            usize::MAX
        } else {
            8
        }) {
            println!("    {m}");
        }
    }
    assert!(
        tally.is_empty(),
        "failures: {:?}",
        tally.iter().map(|(k, v)| (k, v.len())).collect::<Vec<_>>()
    );
}

/// "Did you mean" for a misspelt key, enum value, family and unit; a missing field named
/// with its table at the table's line; a work estimate over the budget names the setting
/// raised most.
#[test]
fn rejections_suggest_and_name_missing_fields() {
    use common::assert_names;
    let piston = std::fs::read_to_string(common::problem("piston-1000rpm.toml")).unwrap();
    let p = |a: &str, b: &str| common::with(&piston, a, b);
    for (from, to, field, line, says) in [
        (
            "crank_mass =",
            "crank_mas =",
            "mechanism.crank_mas",
            "crank_mas =",
            "did you mean `crank_mass`?",
        ),
        (
            "\"peak-force\"",
            "\"peak-forse\"",
            "objective.minimize",
            "peak-forse",
            "did you mean `peak-force`?",
        ),
        (
            "\"slider-crank\"",
            "\"slider-crnk\"",
            "family",
            "slider-crnk",
            "did you mean `slider-crank`?",
        ),
        (
            "\"140 mm\"",
            "\"140 mn\"",
            "mechanism.rod_length",
            "140 mn",
            "did you mean `mm`?",
        ),
        (
            "minimize = \"peak-force\"\n",
            "",
            "objective.minimize",
            "[objective]",
            "missing field `minimize`",
        ),
        (
            "rod_length = \"140 mm\"\n",
            "",
            "mechanism.rod_length",
            "[mechanism]",
            "missing field `rod_length`",
        ),
        (
            "\"35 mm\"",
            "\"1e308 mm\"",
            "mechanism.crank_radius",
            "1e308",
            "allowed: a magnitude up to",
        ),
        (
            "[[paper]]",
            "[mechanism.x]\n[[paper]]",
            "mechanism.x",
            "[mechanism.x]",
            "unknown field",
        ),
    ] {
        assert_names(&p(from, to), field, line, says);
    }
    let no_name = p("name = \"piston-1000rpm\"\n", "");
    let e = parse_str(&no_name, Path::new("bad.toml")).unwrap_err();
    assert_eq!((e.line(), e.field()), (Some(1), Some("name")), "{e}");
    let crane = std::fs::read_to_string(common::problem("crane-thesis-optimise.toml")).unwrap();
    let big = set_key(
        &set_key(&crane, "accuracy.path_samples", "1024"),
        "accuracy.landscape_k1",
        "201",
    );
    let big = set_key(&big, "accuracy.landscape_k2", "201");
    // path_samples is raised most above its default (32×).
    assert_names(
        &big,
        "accuracy.path_samples",
        "path_samples",
        "work estimate",
    );
}

/// A few mutants through the `cwsynth` binary: exit 1 with `FILE:LINE:` on stderr, never a
/// crash (101 or a signal).
#[test]
fn cli_rejects_hostile_files_with_a_line() {
    let piston = std::fs::read_to_string(common::problem("piston-1000rpm.toml")).unwrap();
    let mut bad_utf8 = piston.clone().into_bytes();
    bad_utf8.splice(200..200, [0xff, 0xfe]);
    let deep = format!("{piston}\n[{}]\n", vec!["a"; 10_000].join("."));
    let huge = format!("{piston}\n{}", "# comment\n".repeat(200_000));
    let located = regex::Regex::new(r"bad\.toml:\d+: ").unwrap();
    for (what, bytes) in [
        ("bad UTF-8", bad_utf8),
        ("deep", deep.into_bytes()),
        ("huge", huge.into_bytes()),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.toml");
        std::fs::write(&path, bytes).unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_cwsynth"))
            .args(["check"])
            .arg(&path)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stdout).into_owned()
            + &String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{what}: {err}");
        assert!(located.is_match(&err), "{what}: {err}");
    }
}
