//! `batch` (`src/batch/`): a fleet CSV read the fast way and the slow way, units from cells
//! and headers, row hashes and record lines (`fleet.rs`); formula escaping of a summary row
//! (`row.rs`); the shard from a job array's variables (`inputs.rs`); the hash of a written
//! file (`hash.rs`); the size a run with per-machine files announces (`mod.rs`); the names
//! taken twice (`names.rs`).
//!
//! These were the library's unit tests (`#[cfg(test)] mod tests` in the source file), moved
//! here so that the library is compiled once, not a second time as its unit-test harness
//! (`docs/performance.md`, "Build and test time").

/// The former unit tests of `src/batch/fleet.rs`.
mod fleet {
    use cwsynth::batch::{csv_reader, Lines, Template};
    use std::path::{Path, PathBuf};

    fn template_path() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/piston-1000rpm.toml")
    }

    /// Writes `rows` under `header` as `dir/name`, opens the fleet with `template`, and
    /// returns it with its records as [`Jobs`] reads them: (row, CSV line, cells).
    fn fleet(
        dir: &Path,
        name: &str,
        template: &Path,
        header: &[&str],
        rows: &[Vec<String>],
    ) -> (Template, Vec<(u64, u64, Vec<String>)>) {
        let csv = dir.join(name);
        let mut w = csv::WriterBuilder::new()
            .flexible(true)
            .from_path(&csv)
            .unwrap();
        w.write_record(header).unwrap();
        for r in rows {
            w.write_record(r).unwrap();
        }
        w.flush().unwrap();
        let tpl = Template::open(template, &csv).unwrap();
        let recs = csv_reader(&csv)
            .unwrap()
            .into_records()
            .enumerate()
            .map(|(k, r)| {
                let r = r.unwrap();
                let line = r.position().unwrap().line();
                (k as u64 + 1, line, r.iter().map(str::to_string).collect())
            })
            .collect();
        (tpl, recs)
    }

    /// Every row gives the same machine the fast way as the slow way (the template's text
    /// edited and re-parsed): equal scenes for a good row, and for a bad row the slow way's
    /// message from both [`Template::scene`] and the slow way. Returns (good, bad) counts.
    fn same_both_ways(tpl: &Template, recs: &[(u64, u64, Vec<String>)]) -> (usize, usize) {
        let (mut good, mut bad) = (0, 0);
        for (row, line, cells) in recs {
            let (slow_name, slow) = tpl.slow_scene(*row, *line, cells);
            let (name, scene) = tpl.scene(*row, *line, cells);
            assert_eq!(name, slow_name);
            let fast = tpl.fast_scene(&name, *line, cells);
            match slow {
                Ok(slow) => {
                    good += 1;
                    let fast = fast.unwrap_or_else(|| panic!("line {line}: no fast scene"));
                    let slow = format!("{slow:?}");
                    assert_eq!(format!("{fast:?}"), slow, "line {line}");
                    assert_eq!(format!("{:?}", scene.unwrap()), slow, "line {line}");
                    assert!(slow.contains(&format!("source: \"{}:{line}\"", tpl.csv.display())));
                }
                Err(m) => {
                    bad += 1;
                    assert!(fast.is_none(), "line {line}: fast scene of a bad row: {m}");
                    assert_eq!(scene.unwrap_err(), m, "line {line}");
                }
            }
        }
        (good, bad)
    }

    /// A unit in a column header (`mechanism.speed [rpm]`) is the unit of that column's bare
    /// numbers; a cell's own unit still counts; a bare number in a dimensional column
    /// without a unit in its header is an error naming the file, line and column; an
    /// unknown header unit is an error of the header line.
    #[test]
    fn units_come_from_the_cell_or_the_header_never_guessed() {
        let dir = tempfile::tempdir().unwrap();
        let header = ["mechanism.speed [rpm]", "mechanism.crank_mass"];
        let cell = |a: &str, b: &str| vec![a.to_string(), b.to_string()];
        let rows = [
            cell("1000", "0.35 kg"),
            cell("104.71975511965977 rad/s", "350 g"),
            cell("1000", "0.35"),
        ];
        let (tpl, recs) = fleet(dir.path(), "f.csv", &template_path(), &header, &rows);
        assert_eq!(same_both_ways(&tpl, &recs), (2, 1));
        let speed = |k: usize| {
            let (_, s) = tpl.scene(recs[k].0, recs[k].1, &recs[k].2);
            format!("{:?}", s.unwrap().machine)
        };
        let omega = 1000.0 * std::f64::consts::TAU / 60.0;
        assert!(
            speed(0).contains(&format!("omega: {omega:?}")),
            "{}",
            speed(0)
        );
        let (_, bad) = tpl.scene(recs[2].0, recs[2].1, &recs[2].2);
        let bad = bad.unwrap_err();
        assert!(
            bad.starts_with(&format!(
                "{}:4: field `mechanism.crank_mass` (column 2): `0.35` has no unit",
                tpl.csv.display()
            )),
            "{bad}"
        );
        assert!(bad.contains("kg"), "{bad}");
        let csv = dir.path().join("g.csv");
        std::fs::write(&csv, "mechanism.speed [furlong]\n1\n").unwrap();
        let e = Template::open(&template_path(), &csv)
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("g.csv:1: column `mechanism.speed [furlong]`: unknown unit `furlong`"),
            "{e}"
        );
    }

    /// Many rows of the piston fleet: cells with units, plain numbers under a header with a
    /// unit, plain numbers without one (errors), integers, empty cells, a `name` column (given, empty, not a file name), a key inside an inline table,
    /// quoted text, and every broken row of `scripts/make_fleet.py` (negative length, rod
    /// shorter than the crank, unknown unit, not a quantity, negative mass).
    #[test]
    fn fast_rows_equal_slow_rows() {
        let dir = tempfile::tempdir().unwrap();
        let header = [
            "name",
            "mechanism.crank_radius [m]",
            "mechanism.rod_length",
            "mechanism.crank_mass [kg]",
            "mechanism.rod_mass",
            "mechanism.slider_mass [ kg ]",
            "mechanism.speed [rad/s]",
            "model.rod_split",
            "design.unbalance.max [kg·m]",
            "accuracy.rel_tol",
            "description",
        ];
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        let mut rows = Vec::new();
        for i in 0..400u64 {
            let r = 25.0 + next(20_000) as f64 / 1000.0;
            let l = r * (3.0 + next(2000) as f64 / 1000.0);
            let mut c: Vec<String> = vec![
                match next(4) {
                    0 => format!("m-{i}"),
                    1 if i % 50 == 1 => "not a name!".into(),
                    _ => String::new(),
                },
                match next(4) {
                    0 => format!("{r:.3} mm"),
                    1 => format!("{}", r / 1000.0),
                    2 => format!("{:.4} cm", r / 10.0),
                    _ => String::new(),
                },
                match next(3) {
                    0 => format!("{:.3}", l / 1000.0),
                    1 => String::new(),
                    _ => format!("{l:.3} mm"),
                },
                match next(4) {
                    0 => "1".into(),
                    1 => format!("{:.4}", 0.2 + next(300) as f64 / 1000.0),
                    2 => String::new(),
                    _ => format!("{} g", 200 + next(300)),
                },
                match next(3) {
                    0 => format!(" {:.4} kg ", 0.2 + next(250) as f64 / 1000.0),
                    _ => String::new(),
                },
                match next(3) {
                    0 => "2".into(),
                    1 => format!("{:.4} kg", 0.6 + next(900) as f64 / 1000.0),
                    _ => String::new(),
                },
                match next(4) {
                    0 => format!("{}", 60 + next(250)),
                    1 => format!("{:.1} rpm", 600.0 + next(24_000) as f64 / 10.0),
                    2 => format!("{}.5", 60 + next(250)),
                    _ => String::new(),
                },
                match next(4) {
                    0 => "0.5".into(),
                    1 => "0".into(),
                    2 => "1".into(),
                    _ => String::new(),
                },
                match next(3) {
                    0 => "0.3 kg*m".into(),
                    1 => "0.25".into(),
                    _ => String::new(),
                },
                match next(3) {
                    0 => "1e-8".into(),
                    1 => "0.000001".into(),
                    _ => String::new(),
                },
                match next(3) {
                    0 => format!("row {i}: a \"quoted\", \\ back\\slash, tab\t, é"),
                    1 if i % 40 == 3 => "true".into(),
                    _ => String::new(),
                },
            ];
            // The broken rows of scripts/make_fleet.py, about one in four.
            match next(20) {
                0 => c[1] = format!("-{r:.3} mm"),
                1 => c[2] = format!("{:.3} mm", 0.5 * r),
                2 => c[3] = "0.3 furlong".into(),
                3 => c[6] = "fast".into(),
                4 => c[5] = "-1 kg".into(),
                _ => {}
            }
            rows.push(c);
        }
        let (tpl, recs) = fleet(dir.path(), "fleet.csv", &template_path(), &header, &rows);
        let (good, bad) = same_both_ways(&tpl, &recs);
        assert_eq!(good + bad, 400);
        assert!(good > 200 && bad > 60, "good {good}, bad {bad}");
    }

    /// Rows broken by their shape: a wrong cell count, a key through a value or an array, an
    /// unknown key, an empty key part, a value of the wrong type, another family.
    #[test]
    fn broken_shapes_fail_both_ways_with_the_slow_message() {
        let dir = tempfile::tempdir().unwrap();
        let cases: [(&str, &[&str]); 9] = [
            ("mechanism.speed", &["1000 rpm", "x"]),
            ("mechanism.speed.x", &["3"]),
            ("paper.value", &["3 N"]),
            ("mechanism.colour", &["red"]),
            ("mechanism..speed", &["3"]),
            ("model.rod_split", &["true"]),
            ("objective.minimize", &["everything"]),
            ("family", &["hypocycloid"]),
            ("name", &["../x"]),
        ];
        for (k, (key, cells)) in cases.iter().enumerate() {
            let rows = vec![cells.iter().map(|c| c.to_string()).collect()];
            let csv = format!("f{k}.csv");
            let (tpl, recs) = fleet(dir.path(), &csv, &template_path(), &[key], &rows);
            assert_eq!(same_both_ways(&tpl, &recs), (0, 1), "{key}");
        }
    }

    /// The input hash of a row changes with the template text, the header, the name and each
    /// cell, and is the same for the same input read again.
    #[test]
    fn row_hash_follows_the_input() {
        let dir = tempfile::tempdir().unwrap();
        let header = ["mechanism.speed", "mechanism.crank_mass"];
        let rows = vec![vec!["1000 rpm".to_string(), "0.3 kg".to_string()]];
        let t = template_path();
        let (a, _) = fleet(dir.path(), "a.csv", &t, &header, &rows);
        let (a2, _) = fleet(dir.path(), "a2.csv", &t, &header, &rows);
        let (b, _) = fleet(
            dir.path(),
            "b.csv",
            &t,
            &["mechanism.speed", "model.rod_split"],
            &rows,
        );
        let t2 = dir.path().join("t2.toml");
        std::fs::write(&t2, std::fs::read_to_string(&t).unwrap() + "# edited\n").unwrap();
        let (c, _) = fleet(dir.path(), "c.csv", &t2, &header, &rows);
        let cells = |x: &[&str]| x.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let h = a.input_hash("m", &cells(&["1000 rpm", "0.3 kg"]));
        assert_eq!(h.len(), 32);
        assert_eq!(h, a.input_hash("m", &cells(&["1000 rpm", "0.3 kg"])));
        assert_eq!(h, a2.input_hash("m", &cells(&["1000 rpm", "0.3 kg"])));
        for other in [
            a.input_hash("n", &cells(&["1000 rpm", "0.3 kg"])),
            a.input_hash("m", &cells(&["1001 rpm", "0.3 kg"])),
            a.input_hash("m", &cells(&["1000 rpm", "0.4 kg"])),
            a.input_hash("m", &cells(&["1000 rpm0.3 kg", ""])),
            a.input_hash("m", &cells(&["1000 rpm", "0.3 kg", ""])),
            b.input_hash("m", &cells(&["1000 rpm", "0.3 kg"])),
            c.input_hash("m", &cells(&["1000 rpm", "0.3 kg"])),
        ] {
            assert_ne!(h, other);
        }
    }

    /// The line of each record from its byte position: past CRLF ends, blank lines and
    /// comments.
    #[test]
    fn record_lines_skip_what_the_reader_skips() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("l.csv");
        std::fs::write(&p, "h\r\na\r\n# c\r\n\r\nb\n\n#x\n#y\nc").unwrap();
        let mut rdr = csv_reader(&p).unwrap();
        let mut lines = Lines::open(&p).unwrap();
        let got: Vec<(String, u64)> = rdr
            .records()
            .map(|r| {
                let r = r.unwrap();
                (
                    r[0].to_string(),
                    lines.record_line(r.position().unwrap().byte()),
                )
            })
            .collect();
        assert_eq!(got, [("a".into(), 2), ("b".into(), 5), ("c".into(), 9)]);
    }
}

/// The former unit tests of `src/batch/row.rs`.
mod row {
    use cwsynth::batch::{error_row, Row, HEADER};

    /// Formula escaping round-trips every text exactly, escapes only texts a spreadsheet
    /// would run, and never numbers.
    #[test]
    fn formula_escape_round_trips() {
        let texts = [
            "", "plain", "=1+2", "+x", "-x", "@x", "\tx", "\rx", "'x", "''=x", "'", "a=b", "-",
            "é=",
        ];
        for t in texts {
            let mut r = error_row(0, t, t, "", t.to_string());
            r.value = Some(-3.5);
            let e = r.csv_escaped();
            let risky = t.starts_with(['=', '+', '-', '@', '\t', '\r', '\'']);
            assert_eq!(
                e.name.starts_with('\'') && e.name.len() == t.len() + 1,
                risky,
                "{t:?}"
            );
            assert_eq!(e.value, Some(-3.5));
            let mut w = csv::Writer::from_writer(Vec::new());
            w.serialize(&e).unwrap();
            let bytes = w.into_inner().unwrap();
            let mut rdr = csv::Reader::from_reader(&bytes[..]);
            let hdr = rdr.headers().unwrap().clone();
            assert!(hdr.iter().eq(HEADER));
            let rec = rdr.records().next().unwrap().unwrap();
            let back: Row = rec.deserialize::<Row>(Some(&hdr)).unwrap().csv_unescaped();
            assert_eq!(back, r, "{t:?}");
        }
    }
}

/// The former unit tests of `src/batch/inputs.rs`.
mod inputs {
    use cwsynth::batch::shard_from_env;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| {
            vars.iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn the_array_index_of_slurm_kubernetes_or_our_own_variables() {
        let slurm = [
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_MAX", "8"),
            ("SLURM_ARRAY_TASK_COUNT", "8"),
        ];
        assert_eq!(shard_from_env(env(&slurm)).unwrap(), (4, 8));
        let k8s = [("JOB_COMPLETION_INDEX", "3"), ("CWSYNTH_SHARDS", "10")];
        assert_eq!(shard_from_env(env(&k8s)).unwrap(), (3, 10));
        let own = [("CWSYNTH_SHARD_INDEX", "0"), ("CWSYNTH_SHARDS", "1")];
        assert_eq!(shard_from_env(env(&own)).unwrap(), (0, 1));
        // A stepped Slurm array, a missing count, an index past the count, nothing set.
        let stepped = [
            ("SLURM_ARRAY_TASK_ID", "4"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "8"),
            ("SLURM_ARRAY_TASK_COUNT", "5"),
        ];
        assert!(shard_from_env(env(&stepped))
            .unwrap_err()
            .to_string()
            .contains("contiguous"));
        let no_count = [("JOB_COMPLETION_INDEX", "3")];
        assert!(shard_from_env(env(&no_count))
            .unwrap_err()
            .to_string()
            .contains("CWSYNTH_SHARDS"));
        let past = [("JOB_COMPLETION_INDEX", "3"), ("CWSYNTH_SHARDS", "3")];
        assert!(shard_from_env(env(&past)).is_err());
        let none: [(&str, &str); 0] = [];
        assert!(shard_from_env(env(&none))
            .unwrap_err()
            .to_string()
            .contains("SLURM_ARRAY_TASK_ID"));
    }
}

/// The former unit tests of `src/batch/hash.rs`.
mod hash {
    use cwsynth::batch::file_hash;

    /// A file hash changes with any byte and the length.
    #[test]
    fn file_hash_sees_torn_files() {
        let a: Vec<u8> = (0..1000u32).map(|i| (i * 7 % 251) as u8).collect();
        let h = file_hash(&a);
        assert_eq!(h.len(), 32);
        assert_ne!(h, file_hash(&a[..999]));
        assert_ne!(h, file_hash(&a[..500]));
        assert_ne!(file_hash(&[0; 8]), file_hash(&[0; 9]));
        for k in [0, 7, 8, 500, 999] {
            let mut b = a.clone();
            b[k] ^= 1;
            assert_ne!(h, file_hash(&b), "{k}");
        }
    }
}

/// A run of 1000 machines or more with per-machine files says how much it will write before
/// it starts; a smaller one, or one with `--summary-only`, says nothing (issue 34).
#[test]
fn a_large_run_with_files_says_how_much_it_will_write() {
    use cwsynth::batch::{size_note, Options};
    let opts = |summary_only| Options {
        out: "out".into(),
        threads: None,
        shard: None,
        quiet: false,
        summary_only,
        units: cwsynth::report::Units::Workshop,
    };
    let note = size_note(20_000, &opts(false)).unwrap();
    assert!(
        note.contains("20000 machines") && note.contains("140003 files"),
        "{note}"
    );
    assert!(
        note.contains("3.6 GB") && note.contains("--summary-only"),
        "{note}"
    );
    assert_eq!(size_note(999, &opts(false)), None);
    assert_eq!(size_note(20_000, &opts(true)), None);
}

/// Where a machine's files go (issue 34): beside the summary below [`LARGE_RUN`] machines
/// (the size note's threshold), else `machines/NNN/` by index, 1000 machines a folder.
#[test]
fn a_large_run_puts_its_machines_in_folders_by_index() {
    use cwsynth::batch::{Layout, LARGE_RUN, MACHINES_PER_FOLDER};
    use std::path::Path;
    assert_eq!((LARGE_RUN, MACHINES_PER_FOLDER), (1000, 1000));
    let flat = Layout::of_run(LARGE_RUN - 1);
    assert_eq!(flat.folder(998), None);
    assert_eq!(flat.dir(Path::new("out"), 998), Path::new("out"));
    assert_eq!(flat.href(998, "m.html"), "m.html");
    let large = Layout::of_run(LARGE_RUN);
    for (index, folder) in [
        (0, "machines/000"),
        (999, "machines/000"),
        (1000, "machines/001"),
        (19_999, "machines/019"),
        (1_234_567, "machines/1234"),
    ] {
        assert_eq!(large.folder(index).as_deref(), Some(folder));
        assert_eq!(
            large.dir(Path::new("out"), index),
            Path::new("out").join(folder)
        );
        assert_eq!(large.href(index, "m.json"), format!("{folder}/m.json"));
    }
}

/// A re-run notices an edited drawing: the input hash of a problem file covers the bytes of
/// every `outline.file` it names (and whether it is there), not only its own text.
#[test]
fn the_input_hash_covers_the_drawings_a_problem_reads() {
    use cwsynth::batch::problem_hash;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.toml");
    let text = "[mechanism.links.crank]\noutline = { file = \"d.dxf\", thickness = \"1 mm\" }\n";
    std::fs::write(dir.path().join("d.dxf"), "one").unwrap();
    let a = problem_hash(text, &path);
    assert_eq!(a, problem_hash(text, &path), "deterministic");
    std::fs::write(dir.path().join("d.dxf"), "two").unwrap();
    let b = problem_hash(text, &path);
    assert_ne!(a, b);
    std::fs::remove_file(dir.path().join("d.dxf")).unwrap();
    let c = problem_hash(text, &path);
    assert!(c != a && c != b);
    // Without a drawing, the text alone.
    assert_eq!(
        problem_hash("x = 1\n", &path),
        cwsynth::batch::content_hash("x = 1\n")
    );
}

/// `src/batch/names.rs`: the names taken twice, found by the spilled radix split exactly as
/// by a hash map of every key (the old way, memory growing with the run).
mod names {
    use cwsynth::batch::first_of_repeated;
    use std::collections::HashMap;

    /// The brute force: every key remembered with its first index.
    fn brute(claims: &[(u64, u64)]) -> HashMap<u64, u64> {
        let mut first: HashMap<u64, (u64, u32)> = HashMap::new();
        for &(k, i) in claims {
            first.entry(k).or_insert((i, 0)).1 += 1;
        }
        first
            .into_iter()
            .filter(|(_, (_, n))| *n > 1)
            .map(|(k, (i, _))| (k, i))
            .collect()
    }

    /// Random keys (a 64-bit LCG), some repeated up to four times, some sharing their top
    /// bits (one bucket), indices ascending.
    fn claims(n: u64) -> Vec<(u64, u64)> {
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            s
        };
        let mut out: Vec<(u64, u64)> = Vec::new();
        for i in 0..n {
            let r = next();
            let k = match r % 10 {
                0 if i > 0 => out[(next() % i) as usize].0, // an earlier name again
                1 => r & 0x00FF_FFFF,                       // top bits all zero
                _ => next(),
            };
            out.push((k, i));
        }
        out
    }

    #[test]
    fn the_spilled_split_finds_the_repeats_a_hash_map_finds() {
        let dir = tempfile::tempdir().unwrap();
        let c = claims(200_000);
        let expect = brute(&c);
        assert!(expect.len() > 10_000, "{} repeated keys", expect.len());
        // In memory (a small run), then spilled to 2 and to the most files.
        for expected in [1_000, 100_000, 10_000_000] {
            let got = first_of_repeated(c.iter().copied(), expected, dir.path()).unwrap();
            assert_eq!(got, expect, "expected size {expected}");
        }
        // The spill files are anonymous: nothing is left in the directory.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        // No claims, no repeats.
        let none = first_of_repeated(std::iter::empty(), 10_000_000, dir.path()).unwrap();
        assert!(none.is_empty());
    }
}
