//! Issue 15: a mutation suite over fleet CSVs, run in process through `batch::run` (the code
//! `cwsynth batch TEMPLATE.toml:FLEET.csv` runs). A fixed-seed generator mutates a small
//! fleet of the shipped piston template — deleted, duplicated and swapped lines, truncation at
//! any byte, stray and unterminated quotes, extra and missing cells, extreme numbers, wrong
//! units and types, bad UTF-8, CRLF, a byte-order mark, comments and blank lines, a repeated
//! column, a huge cell — and asserts for every mutant: no panic; the batch either refuses the
//! whole fleet with a message or writes a summary whose every row has a known status; no row
//! that is not an error carries a non-finite number; every error row names the fleet file and
//! a line; and rows in = rows out. The independent reference for "rows in" is a count of the
//! file's physical lines: after the header (its first line that is neither blank nor a `#`
//! comment), every line that is not empty and not a `#`
//! comment is one machine (a line of spaces is a row of one cell, an error row) (docs/batch.md, "Rows in = rows out"); where a quote is left open
//! (the lines it swallows become error rows too, comments included) the summary holds at
//! least that many rows; a fleet without data lines is one error row saying so.

use cwsynth::batch::{expand, run, Options, ROW_STATUSES};

const TEMPLATE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/piston-1000rpm.toml");

const BASE: &str = "name,mechanism.crank_radius [mm],mechanism.rod_length [mm],mechanism.speed [rpm],mechanism.slider_mass,design.radius
pump-a,35,140,1000,1.03 kg,50 mm
pump-b,30,120,1500,0.9 kg,
# a comment
pump-c,0.03 m,120,157.08 rad/s,1.1 kg,
pump-d,40,160,800,,60 mm

pump-e,25,100,3000,0.5 kg,40 mm
";

/// xorshift64*: a fixed-seed generator (no dependency, same mutants on every machine).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a>(&mut self, v: &[&'a str]) -> &'a str {
        v[self.below(v.len())]
    }
}

const VALUES: &[&str] = &[
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-308",
    "NaN",
    "inf",
    "9223372036854775807",
    "18446744073709551615",
    "3 parsec",
    "3 kg",
    "3",
    "\"\"",
    "true",
    "[1, 2]",
    "{ a = 1 }",
    "peak-force",
    "1,5",
    "\u{00e9}\u{00e9}",
    "=HYPERLINK(\"x\")",
];

/// One mutant of `BASE` (bytes: some are not UTF-8).
fn mutate(rng: &mut Rng) -> (String, Vec<u8>) {
    let lines: Vec<&str> = BASE.lines().collect();
    let mut ls: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    let k = rng.below(14);
    let i = 1 + rng.below(ls.len() - 1);
    let what;
    match k {
        0 => {
            let j = rng.below(ls.len());
            what = format!("delete line {}", j + 1);
            ls.remove(j);
        }
        1 => {
            what = format!("duplicate line {}", i + 1);
            let l = ls[i].clone();
            ls.insert(i, l);
        }
        2 => {
            let j = rng.below(ls.len());
            what = format!("swap lines {} and {}", i + 1, j + 1);
            ls.swap(i, j);
        }
        3 => {
            let mut cells: Vec<String> = ls[i].split(',').map(str::to_string).collect();
            let c = rng.below(cells.len());
            let v = rng.pick(VALUES);
            what = format!("line {} cell {} = {v}", i + 1, c + 1);
            cells[c] = v.to_string();
            ls[i] = cells.join(",");
        }
        4 => {
            what = format!("extra cell on line {}", i + 1);
            ls[i].push_str(",7");
        }
        5 => {
            what = format!("missing cell on line {}", i + 1);
            if let Some(p) = ls[i].rfind(',') {
                ls[i].truncate(p);
            }
        }
        6 => {
            let p = rng.below(ls[i].len() + 1);
            let p = (0..=p)
                .rev()
                .find(|&q| ls[i].is_char_boundary(q))
                .unwrap_or(0);
            what = format!("quote at line {} byte {p}", i + 1);
            ls[i].insert(p, '"');
        }
        7 => {
            what = "CRLF and a byte-order mark".into();
            let text = format!("\u{feff}{}", ls.join("\r\n"));
            return (what, text.into_bytes());
        }
        8 => {
            let mut h: Vec<String> = ls[0].split(',').map(str::to_string).collect();
            let c = rng.below(h.len());
            let v = rng.pick(&[
                "mechanism.speed",
                "mechanism.sped",
                "mechanism.speed [parsec]",
                "name",
                "",
                "mechanism",
                "design.unbalance.max",
                "accuracy.scan_samples",
            ]);
            what = format!("header column {} = {v}", c + 1);
            h[c] = v.to_string();
            ls[0] = h.join(",");
        }
        9 => {
            what = format!("huge cell on line {}", i + 1);
            ls[i] = format!("{},{}", "x".repeat(100_000), ls[i]);
        }
        10 => {
            what = format!("comments and blanks around line {}", i + 1);
            ls.insert(i, "# inserted".into());
            ls.insert(i, String::new());
            ls.insert(i, "   ".into());
        }
        11 => {
            let n = 1 + rng.below(4);
            what = format!("{n} settings columns at their extremes");
            ls[0].push_str(",accuracy.scan_samples,accuracy.max_rounds");
            for l in ls.iter_mut().skip(1) {
                if !l.is_empty() && !l.starts_with('#') {
                    l.push_str(if n.is_multiple_of(2) {
                        ",20000,1000"
                    } else {
                        ",18446744073709551615,0"
                    });
                }
            }
        }
        12 => {
            let mut b = ls.join("\n").into_bytes();
            let p = rng.below(b.len());
            what = format!("byte 0xff at {p}");
            b.insert(p, 0xff);
            return (what, b);
        }
        _ => {
            let b = ls.join("\n").into_bytes();
            let p = rng.below(b.len() + 1);
            what = format!("truncated at byte {p}");
            return (what, b[..p].to_vec());
        }
    }
    (what, (ls.join("\n") + "\n").into_bytes())
}

/// Machines the file holds by its physical lines (after the header: not blank, not `#`), and
/// whether a quote is left open somewhere (then lines it swallows are rows too).
fn lines_in(bytes: &[u8]) -> (usize, bool) {
    let text = String::from_utf8_lossy(bytes);
    let text = text.trim_start_matches('\u{feff}');
    // The header is the first line that is neither blank nor a comment.
    let (mut n, mut open) = (0usize, false);
    let mut header_seen = false;
    for l in text.lines() {
        let t = l.trim_end_matches('\r');
        open |= t.matches('"').count() % 2 == 1;
        // Only an empty line is blank: a line of spaces is a row (with one cell).
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        if header_seen {
            n += 1;
        }
        header_seen = true;
    }
    (n, open)
}

#[test]
fn fleet_mutants_never_panic_and_keep_every_row() {
    let mut rng = Rng(0x5eed_f1ee_7000_0015);
    let n_mutants: usize = std::env::var("CWSYNTH_FLEET_MUTANTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(400);
    let dir = tempfile::tempdir().unwrap();
    let mut refused = 0;
    let mut rows_total = 0;
    for m in 0..n_mutants {
        let (what, bytes) = mutate(&mut rng);
        let csv = dir.path().join(format!("f{m}.csv"));
        std::fs::write(&csv, &bytes).unwrap();
        let out = dir.path().join(format!("out{m}"));
        let opts = Options {
            out: out.clone(),
            threads: Some(1),
            shard: None,
            quiet: true,
            summary_only: true,
            units: Default::default(),
        };
        let arg = format!("{TEMPLATE}:{}", csv.display());
        let res = std::panic::catch_unwind(|| run(expand(&[arg]).unwrap(), &opts));
        let res = match res {
            Ok(r) => r,
            Err(_) => panic!("mutant {m} ({what}): panicked"),
        };
        let counts = match res {
            Ok(c) => c,
            Err(e) => {
                // A fleet refused whole must say why, naming the file.
                let msg = format!("{e:#}");
                assert!(
                    msg.contains(&format!("f{m}.csv")),
                    "mutant {m} ({what}): {msg}"
                );
                refused += 1;
                continue;
            }
        };
        let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
        let mut rdr = csv::Reader::from_reader(summary.as_bytes());
        let h = rdr.headers().unwrap().clone();
        let col = |name: &str| h.iter().position(|c| c == name).unwrap();
        let (st, msg, src) = (col("status"), col("message"), col("source"));
        let rows: Vec<csv::StringRecord> = rdr.records().map(Result::unwrap).collect();
        assert_eq!(rows.len() as u64, counts.total, "mutant {m} ({what})");
        let (lines, open) = lines_in(&bytes);
        if lines == 0 {
            // A fleet without data rows is one error row saying so.
            assert!(
                rows.len() <= 1 && rows.iter().all(|r| &r[st] == "error"),
                "mutant {m} ({what}): {summary}"
            );
        } else if open {
            assert!(
                rows.len() >= lines,
                "mutant {m} ({what}): {} rows for {lines} lines",
                rows.len()
            );
        } else {
            assert_eq!(
                rows.len(),
                lines,
                "mutant {m} ({what}): rows in ≠ rows out\n{summary}"
            );
        }
        for r in &rows {
            assert!(
                ROW_STATUSES.contains(&&r[st]),
                "mutant {m} ({what}): status {}",
                &r[st]
            );
            if &r[st] == "error" {
                let located = r[msg].contains(&format!("f{m}.csv:"))
                    || r[src].contains(&format!("f{m}.csv:"));
                assert!(
                    located,
                    "mutant {m} ({what}): error row without file and line: {:?}",
                    r
                );
            } else {
                // The numeric columns (and every number of the packed design/objectives).
                for k in [
                    "value",
                    "error",
                    "baseline_value",
                    "improvement_pct",
                    "time_s",
                ] {
                    let v = &r[col(k)];
                    if !v.is_empty() {
                        let x: f64 = v.parse().unwrap();
                        assert!(x.is_finite(), "mutant {m} ({what}): {k} = {v}");
                    }
                }
                for k in ["design", "objectives"] {
                    for kv in r[col(k)].split(';').filter(|c| !c.is_empty()) {
                        let x: f64 = kv.split_once('=').unwrap().1.parse().unwrap();
                        assert!(x.is_finite(), "mutant {m} ({what}): {k} {kv}");
                    }
                }
            }
        }
        rows_total += rows.len();
        std::fs::remove_dir_all(&out).ok();
    }
    eprintln!(
        "{n_mutants} fleet mutants: {refused} refused whole, {rows_total} rows in the summaries"
    );
}
