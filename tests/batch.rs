//! `cwsynth batch`: fleets with broken rows, determinism across threads and shards, re-runs
//! that skip finished machines, and interrupted runs that complete.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cwsynth"))
}

fn template() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("problems/piston-1000rpm.toml")
        .display()
        .to_string()
}

/// 12 machines, rows 3, 7 and 10 broken (negative length, unknown unit, rod too short).
fn fleet(dir: &Path) -> String {
    let mut s = String::from(
        "mechanism.crank_radius,mechanism.rod_length,mechanism.slider_mass,mechanism.speed\n",
    );
    for i in 0..12 {
        let r = 25.0 + 1.5 * i as f64;
        let row = match i {
            2 => format!("-{r} mm,{} mm,1.0 kg,1000 rpm", 4.0 * r),
            6 => format!("{r} mm,{} mm,1.0 furlong,1000 rpm", 4.0 * r),
            9 => format!("{r} mm,{} mm,1.0 kg,1000 rpm", 0.5 * r),
            _ => format!(
                "{r} mm,{} mm,{} kg,{} rpm",
                4.0 * r,
                0.8 + 0.05 * i as f64,
                800 + 100 * i
            ),
        };
        s += &row;
        s.push('\n');
    }
    let p = dir.join("fleet.csv");
    std::fs::write(&p, s).unwrap();
    format!("{}:{}", template(), p.display())
}

/// The fleet `TEMPLATE:DIR/FILE` of the shipped piston with the CSV `text`.
fn fleet_of(dir: &Path, file: &str, text: &str) -> String {
    let p = dir.join(file);
    std::fs::write(&p, text).unwrap();
    format!("{}:{}", template(), p.display())
}

/// `cwsynth batch INPUT --out OUT EXTRA…` with its progress and final message on stderr.
fn loud(input: &str, out: &Path, extra: &[&str]) -> Output {
    bin()
        .arg("batch")
        .arg(input)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

fn batch(input: &str, out: &Path, extra: &[&str]) -> Output {
    bin()
        .arg("batch")
        .arg(input)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(extra)
        .output()
        .unwrap()
}

/// The summary without the timing column.
fn summary_sans_time(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    let h = rdr.headers().unwrap().clone();
    let t = h.iter().position(|c| c == "time_s").unwrap();
    rdr.records()
        .map(|r| {
            let r = r.unwrap();
            r.iter()
                .enumerate()
                .filter(|(i, _)| *i != t)
                .map(|(_, c)| c.to_string())
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect()
}

/// The result JSON without `timing` and the size and hash of the `.md` (which shows the
/// timing).
fn json_sans_time(path: &Path) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    v.as_object_mut().unwrap().remove("timing");
    if let Some(f) = v.pointer_mut("/batch/files") {
        f.as_object_mut()
            .unwrap()
            .retain(|k, _| !k.ends_with(".md"));
    }
    v
}

#[test]
fn broken_rows_are_listed_and_good_rows_finish() {
    let d = tempfile::tempdir().unwrap();
    let input = fleet(d.path());
    let out = d.path().join("out");
    let o = batch(&input, &out, &["--threads", "2"]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let rows = summary_sans_time(&out.join("summary.csv"));
    assert_eq!(rows.len(), 12);
    let text = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    let mut bad = Vec::new();
    for r in rdr.records() {
        let r = r.unwrap();
        let (index, name, status, msg) = (&r[0], &r[1], &r[3], &r[15]);
        if matches!(index, "2" | "6" | "9") {
            assert!(
                status == "error" || status == "infeasible" || status == "failed",
                "row {index}: {status}"
            );
            assert!(!msg.is_empty(), "row {index} has no reason");
            bad.push(msg.to_string());
        } else {
            assert_eq!(status, "optimal", "row {index}: {msg}");
            assert!(out.join(format!("{name}.json")).exists());
        }
    }
    assert!(
        bad[0].contains("fleet.csv:4: field `mechanism.crank_radius`"),
        "{}",
        bad[0]
    );
    assert!(
        bad[1].contains("fleet.csv:8: field `mechanism.slider_mass`"),
        "{}",
        bad[1]
    );
    assert!(bad[1].contains("furlong"), "{}", bad[1]);
    assert!(bad[2].contains("fleet.csv:11"), "{}", bad[2]);
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.contains("## Failures (3)"), "{md}");
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(html.contains("<svg") && !html.contains("http://cdn") && !html.contains("<script src"));
}

#[test]
fn threads_and_shards_give_identical_results() {
    let d = tempfile::tempdir().unwrap();
    let input = fleet(d.path());
    let (o1, o2, os) = (
        d.path().join("t1"),
        d.path().join("t2"),
        d.path().join("sh"),
    );
    batch(&input, &o1, &["--threads", "1"]);
    batch(&input, &o2, &["--threads", "2"]);
    let s1 = summary_sans_time(&o1.join("summary.csv"));
    assert_eq!(s1, summary_sans_time(&o2.join("summary.csv")));
    let mut n = 0;
    for e in std::fs::read_dir(&o1).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "json") {
            let q = o2.join(p.file_name().unwrap());
            assert_eq!(json_sans_time(&p), json_sans_time(&q), "{}", p.display());
            // Byte-identical apart from the timing object and the `.md`'s size and hash.
            let strip = |p: &Path| {
                let mut t = std::fs::read_to_string(p).unwrap();
                for key in ["\"timing\"", ".md\": {"] {
                    let i = t.find(key).unwrap();
                    let j = i + t[i..].find('}').unwrap();
                    t = format!("{}{}", &t[..i], &t[j..]);
                }
                t
            };
            assert_eq!(strip(&p), strip(&q));
            n += 1;
        }
    }
    assert_eq!(n, 9);
    // Shards 0/2 and 1/2 into one directory, then merge.
    batch(&input, &os, &["--shard", "0/2", "--summary-only"]);
    batch(&input, &os, &["--shard", "1/2", "--summary-only"]);
    assert!(os.join("summary-shard-0-of-2.csv").exists());
    assert!(!os.join("summary.csv").exists());
    let m = bin()
        .args(["batch", "--merge", "--quiet", "--out"])
        .arg(&os)
        .output()
        .unwrap();
    assert_eq!(
        m.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&m.stderr)
    );
    assert_eq!(summary_sans_time(&os.join("summary.csv")), s1);
    assert!(os.join("index.html").exists() && os.join("summary.md").exists());
}

#[test]
fn reruns_skip_finished_machines_and_interrupted_runs_complete() {
    let d = tempfile::tempdir().unwrap();
    let input = fleet(d.path());
    let out = d.path().join("out");
    let o = batch(&input, &out, &[]);
    assert_eq!(o.status.code(), Some(1));
    let first = summary_sans_time(&out.join("summary.csv"));
    let json = out.join("piston-1000rpm-1.json");
    let mtime = |p: &Path| std::fs::metadata(p).unwrap().modified().unwrap();
    let t0 = mtime(&json);

    // A re-run solves nothing: every good machine is skipped, files untouched.
    let o = loud(&input, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("9 skipped"), "{err}");
    assert_eq!(mtime(&json), t0);
    assert_eq!(summary_sans_time(&out.join("summary.csv")), first);

    // Interrupted: a leftover temporary file, a missing result and a half summary.
    std::fs::write(out.join(".piston-1000rpm-2.json.12345.tmp"), "{\"half").unwrap();
    std::fs::remove_file(out.join("piston-1000rpm-5.json")).unwrap();
    let s = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let half: String = s.lines().take(5).map(|l| format!("{l}\n")).collect();
    std::fs::write(out.join("summary.csv.partial"), half).unwrap();
    std::fs::remove_file(out.join("summary.csv")).unwrap();
    let o = loud(&input, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("8 skipped"), "{err}");
    assert!(out.join("piston-1000rpm-5.json").exists());
    assert_eq!(summary_sans_time(&out.join("summary.csv")), first);
    assert!(!out.join("summary.csv.partial").exists());

    // --summary-only re-runs skip through the previous summary.
    let so = d.path().join("so");
    batch(&input, &so, &["--summary-only"]);
    let o = bin()
        .arg("batch")
        .arg(&input)
        .arg("--out")
        .arg(&so)
        .arg("--summary-only")
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&o.stderr).contains("9 skipped"));
    assert_eq!(summary_sans_time(&so.join("summary.csv")), first);

    // A changed row is re-solved, the others are not.
    let csv_path = d.path().join("fleet.csv");
    let t = std::fs::read_to_string(&csv_path).unwrap();
    std::fs::write(&csv_path, t.replacen("800 rpm", "850 rpm", 1)).unwrap();
    let o = loud(&input, &out, &[]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("8 skipped"));
}

#[test]
fn a_duplicate_name_is_reported_and_never_overwrites_the_first_machine() {
    // Two problem files and two fleet rows with one name each: the first in input order
    // keeps the name and its results; the later one is an error row naming the first, and
    // the rest of the batch still runs. Checked with 1 and 2 threads (the decision is made
    // in input order, not by whichever thread finishes first).
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(template()).unwrap();
    let slow = text.replace("speed = \"1000 rpm\"", "speed = \"1500 rpm\"");
    assert_ne!(slow, text, "the template sets the speed as \"1000 rpm\"");
    let (a, b) = (dir.path().join("a.toml"), dir.path().join("b.toml"));
    std::fs::write(&a, &text).unwrap();
    std::fs::write(&b, &slow).unwrap();
    let csv = dir.path().join("named.csv");
    std::fs::write(
        &csv,
        "name,mechanism.speed\nm-one,900 rpm\nm-two,1100 rpm\nM-One,1300 rpm\n",
    )
    .unwrap();
    let fleet = format!("{}:{}", template(), csv.display());
    for threads in ["1", "2"] {
        let out = dir.path().join(format!("out{threads}"));
        let o = batch(
            &format!("{}", a.display()),
            &out,
            &["--threads", threads, b.to_str().unwrap(), &fleet],
        );
        assert_eq!(o.status.code(), Some(1), "{o:?}");
        let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
        let rows: Vec<&str> = summary.lines().skip(1).collect();
        assert_eq!(rows.len(), 5, "{summary}");
        // Row 1 (b.toml) and row 4 (`M-One`, equal to m-one but for case: one file on a
        // case-insensitive file system) are the duplicates.
        assert!(rows[0].contains(",optimal,"), "{}", rows[0]);
        assert!(
            rows[1].contains("duplicate name `piston-1000rpm`"),
            "{}",
            rows[1]
        );
        assert!(rows[1].contains("a.toml"), "{}", rows[1]);
        assert!(rows[2].contains(",optimal,") && rows[3].contains(",optimal,"));
        assert!(rows[4].contains("duplicate name `M-One`"), "{}", rows[4]);
        assert!(rows[4].contains("machine 2"), "{}", rows[4]);
        // The first machines' results are theirs: 1000 rpm for a.toml, 900 rpm for m-one.
        let speed = |name: &str| {
            let v: serde_json::Value =
                serde_json::from_slice(&std::fs::read(out.join(format!("{name}.json"))).unwrap())
                    .unwrap();
            v["derived"]["omega_rad_s"].as_f64().unwrap() * 60.0 / std::f64::consts::TAU
        };
        assert!((speed("piston-1000rpm") - 1000.0).abs() < 1e-9);
        assert!((speed("m-one") - 900.0).abs() < 1e-9);
    }
}

#[test]
fn summary_rows_need_only_the_short_json_and_lookups_match_the_full_json() {
    // For every shipped scene: the row made from the result itself (what `--summary-only`
    // writes, no JSON built) equals the row made from the whole result JSON, and `lookup`'s
    // direct path through the number maps gives what a JSON pointer into the whole result
    // gives.
    use cwsynth::batch::{row_from_json, row_from_result};
    use cwsynth::families::load;
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("problems");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let r = cwsynth::families::solve_scene(&load(&p).unwrap());
        let full = r.to_json();
        assert_eq!(
            row_from_result(7, "src", "hash", &r),
            row_from_json(7, "src", "hash", &full),
            "{}",
            p.display()
        );
        let mut keys = 0;
        for section in ["design", "objectives", "errors", "derived", "baselines"] {
            let Some(m) = full.get(section).and_then(|m| m.as_object()) else {
                continue;
            };
            for (k, v) in m {
                let leaves: Vec<(String, String)> = match v.as_object() {
                    Some(inner) => inner
                        .keys()
                        .map(|k2| {
                            (
                                format!("{section}.{k}.{k2}"),
                                format!("/{section}/{k}/{k2}"),
                            )
                        })
                        .collect(),
                    None => vec![(format!("{section}.{k}"), format!("/{section}/{k}"))],
                };
                for (dotted, pointer) in leaves {
                    let want = full.pointer(&pointer).and_then(|x| x.as_f64());
                    assert_eq!(r.lookup(&dotted), want, "{}: {dotted}", p.display());
                    keys += 1;
                }
            }
        }
        assert!(keys > 5, "{}: {keys} keys", p.display());
        n += 1;
    }
    assert!(n >= 10, "{n} problem files");
}

/// Issue 15: `merge` validates shard summaries like any other input — a forged status or a
/// name that points outside the folder is an error naming the file and line — and nothing
/// from input reaches the reports as markup.
#[test]
fn merge_validates_shards_and_reports_escape_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = fleet(dir.path());
    let s0 = dir.path().join("s0");
    let s1 = dir.path().join("s1");
    for (i, d) in [(0, &s0), (1, &s1)] {
        let shard = format!("{i}/2");
        batch(&input, d, &["--shard", &shard, "--summary-only"]);
    }
    let merged = dir.path().join("m");
    let merge = || {
        bin()
            .args(["merge", "--out"])
            .arg(&merged)
            .arg(&s0)
            .arg(&s1)
            .output()
            .unwrap()
    };
    assert_eq!(merge().status.code(), Some(1), "3 broken rows");
    // Forge shard 1: a status carrying markup, then a name leaving the folder.
    let p1 = s1.join("summary-shard-1-of-2.csv");
    let good = std::fs::read_to_string(&p1).unwrap();
    for (from, to, says) in [
        (",optimal,", ",<script>alert(1)</script>,", "status"),
        ("piston-1000rpm-2,", "../evil,", "name"),
    ] {
        std::fs::write(&p1, good.replacen(from, to, 1)).unwrap();
        let out = merge();
        assert_eq!(out.status.code(), Some(2), "{from}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("summary-shard-1-of-2.csv:") && err.contains(says),
            "{err}"
        );
    }
    std::fs::write(&p1, good).unwrap();
    let html = std::fs::read_to_string(merged.join("index.html")).unwrap();
    assert!(!html.contains("<script"));
    // An error message quoting input (a unit `<b>furlong</b>`) is escaped in both reports.
    let input = fleet_of(
        dir.path(),
        "x.csv",
        "mechanism.slider_mass\n\"1.0 <b>furlong</b>\"\n\"1.0 kg\"\n",
    );
    let out_dir = dir.path().join("x");
    batch(&input, &out_dir, &[]);
    let md = std::fs::read_to_string(out_dir.join("summary.md")).unwrap();
    let html = std::fs::read_to_string(out_dir.join("index.html")).unwrap();
    assert!(md.contains("furlong") && !md.contains("<b>"), "{md}");
    assert!(
        html.contains("furlong") && !html.contains("<b>furlong"),
        "{html}"
    );
}

/// Issue 15: names that would clash with the batch's own files or with devices are refused.
#[test]
fn reserved_machine_names_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(template()).unwrap();
    for name in [
        "summary",
        "Index",
        "CON",
        "nul.txt",
        "com1",
        "summary-shard-0-of-2",
        "a.",
    ] {
        let p = dir.path().join("n.toml");
        std::fs::write(
            &p,
            text.replace("name = \"piston-1000rpm\"", &format!("name = \"{name}\"")),
        )
        .unwrap();
        let out = bin().arg("check").arg(&p).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{name}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("n.toml:") && err.contains("field `name`"),
            "{name}: {err}"
        );
    }
}

/// Issue 15: one writer per --out. A second batch on a directory in use stops at once with a
/// clear message (here the test holds the lock); a checkpoint never goes backwards (a newer,
/// smaller `.partial` does not replace a larger `.resume`).
#[test]
fn a_busy_out_directory_is_refused_and_checkpoints_never_shrink() {
    let dir = tempfile::tempdir().unwrap();
    let input = fleet(dir.path());
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    let lock = std::fs::File::create(out.join(".summary.csv.lock")).unwrap();
    lock.lock().unwrap();
    let o = batch(&input, &out, &["--summary-only"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("in use by another cwsynth batch"));
    drop(lock);
    assert_eq!(
        batch(&input, &out, &["--summary-only"]).status.code(),
        Some(1)
    );
    // Pretend two interruptions: the first left 12 rows (now `.resume`), the second only the
    // header (`.partial`). The re-run must skip the 9 good machines of the larger one.
    let summary = out.join("summary.csv");
    let header = std::fs::read_to_string(&summary)
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .to_string();
    std::fs::rename(&summary, out.join("summary.csv.resume")).unwrap();
    std::fs::write(out.join("summary.csv.partial"), header + "\n").unwrap();
    let o = bin()
        .arg("batch")
        .arg(&input)
        .arg("--out")
        .arg(&out)
        .arg("--summary-only")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("9 skipped"), "{err}");
}

/// Issue 15: rows in = rows out. An unterminated `"` in a fleet CSV is an error at its real
/// line, and every line it swallowed is reported as its own error row; nothing is dropped.
#[test]
fn an_unterminated_quote_loses_no_row_silently() {
    let dir = tempfile::tempdir().unwrap();
    let input = fleet_of(
        dir.path(),
        "q.csv",
        "mechanism.slider_mass\n1.0 kg\n\"1.1 kg\n1.2 kg\n1.3 kg\n1.4 kg\n",
    );
    let out = dir.path().join("out");
    let o = batch(&input, &out, &["--summary-only"]);
    assert_eq!(o.status.code(), Some(1));
    let text = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    let rows: Vec<csv::StringRecord> = rdr.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 5, "{text}");
    assert_eq!(&rows[0][3], "optimal");
    assert!(rows[1][15].contains("q.csv:3:") && rows[1][15].contains("never closed"));
    for (k, line) in (2..5).zip(4..) {
        assert_eq!(&rows[k][3], "error");
        assert!(
            rows[k][15].contains(&format!("q.csv:{line}:")),
            "{}",
            &rows[k][15]
        );
    }
}

/// The summary's rows as records.
fn records(path: &Path) -> Vec<csv::StringRecord> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    rdr.records().map(Result::unwrap).collect()
}

/// Issue 15: whatever one machine does (here a panic from the debug builds' test hook
/// `CWSYNTH_TEST_PANIC=<name>`), the batch finishes, that row is `failed` with the panic's
/// message, every other machine is solved and written, the reports are written, exit 1. A
/// re-run without the panic solves that machine (a failed row is not kept).
#[test]
fn a_panicking_machine_fails_alone() {
    let d = tempfile::tempdir().unwrap();
    let input = fleet(d.path());
    let out = d.path().join("out");
    let o = bin()
        .env("CWSYNTH_TEST_PANIC", "piston-1000rpm-5")
        .args(["batch", &input, "--threads", "2", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked at"), "{err}");
    let rows = records(&out.join("summary.csv"));
    assert_eq!(rows.len(), 12);
    for r in &rows {
        let (index, name, status, msg) = (&r[0], &r[1], &r[3], &r[15]);
        match index {
            "4" => {
                assert_eq!((name, status), ("piston-1000rpm-5", "failed"));
                assert!(
                    msg.contains("fleet.csv:6: internal error (a panic")
                        && msg.contains("CWSYNTH_TEST_PANIC"),
                    "{msg}"
                );
                assert!(!out.join("piston-1000rpm-5.json").exists());
            }
            "2" | "6" | "9" => assert_eq!(status, "error"),
            _ => {
                assert_eq!(status, "optimal", "{msg}");
                assert!(out.join(format!("{name}.md")).exists());
            }
        }
    }
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.contains("## Failures (4)"), "{md}");
    assert!(out.join("index.html").exists());
    // --summary-only: the same row, and the run goes on.
    let so = d.path().join("so");
    let o = bin()
        .env("CWSYNTH_TEST_PANIC", "piston-1000rpm-5")
        .args(["batch", &input, "--quiet", "--summary-only", "--out"])
        .arg(&so)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let rows = records(&so.join("summary.csv"));
    assert_eq!((rows.len(), &rows[4][3]), (12, "failed"));
    // Without the panic the machine is solved; the 8 others are skipped.
    let o = loud(&input, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("8 skipped"), "{err}");
    assert_eq!(&records(&out.join("summary.csv"))[4][3], "optimal");
}

/// Issue 15: resume is complete. A machine is done only when its JSON and every file the
/// JSON lists (with size and hash) are there and whole: a deleted report, a torn plot or a
/// torn JSON is solved again; a leftover temporary file of a dead run is removed.
#[test]
fn resume_redoes_machines_with_missing_or_torn_files() {
    let d = tempfile::tempdir().unwrap();
    let input = fleet(d.path());
    let out = d.path().join("out");
    assert_eq!(batch(&input, &out, &[]).status.code(), Some(1));
    let first = summary_sans_time(&out.join("summary.csv"));
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("piston-1000rpm-1.json")).unwrap()).unwrap();
    let files = v["batch"]["files"].as_object().unwrap();
    assert!(files.contains_key("piston-1000rpm-1.md"), "{files:?}");
    assert!(files.contains_key("piston-1000rpm-1-shaking-force.svg"));
    std::fs::remove_file(out.join("piston-1000rpm-2.md")).unwrap();
    let svg = out.join("piston-1000rpm-4-shaking-force.svg");
    let text = std::fs::read(&svg).unwrap();
    std::fs::write(&svg, &text[..text.len() / 2]).unwrap();
    // Same size, other bytes (a crash can leave zeros in place of the data).
    let md = out.join("piston-1000rpm-6.md");
    std::fs::write(
        &md,
        vec![0u8; std::fs::metadata(&md).unwrap().len() as usize],
    )
    .unwrap();
    std::fs::write(out.join("piston-1000rpm-8.json"), "{\"name\": \"piston-10").unwrap();
    // A temporary file of a process that is gone (no process has this id).
    let stale = out.join(".piston-1000rpm-1.json.4000000000.tmp");
    std::fs::write(&stale, "{\"half").unwrap();
    let o = loud(&input, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("5 skipped"), "{err}");
    assert!(!stale.exists());
    assert!(out.join("piston-1000rpm-2.md").exists());
    assert_eq!(std::fs::read(&svg).unwrap().len(), text.len());
    assert_ne!(std::fs::read(&md).unwrap()[0], 0);
    assert_eq!(summary_sans_time(&out.join("summary.csv")), first);
    // Now complete: everything is skipped.
    let o = loud(&input, &out, &[]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("9 skipped"));
}

/// Issue 15: summary.csv cells are safe to open in a spreadsheet: a text cell starting with
/// `=`, `+`, `-`, `@` (or the escape `'`) gets a leading `'`, numbers never do, and the
/// summary reader undoes it (a --summary-only re-run skips through it, shards merge to the
/// same summary).
#[test]
fn summary_cells_are_formula_escaped_and_read_back() {
    let d = tempfile::tempdir().unwrap();
    let input = fleet_of(
        d.path(),
        "inj.csv",
        "name,mechanism.slider_mass\n-minus,1.0 kg\n=HYPERLINK(\"x\"),1.1 kg\n@sum,1.2 kg\nplain,1.3 kg\n+plus,1.4 kg\n",
    );
    let out = d.path().join("out");
    assert_eq!(
        batch(&input, &out, &["--summary-only"]).status.code(),
        Some(1)
    );
    let text = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let rows = records(&out.join("summary.csv"));
    let names: Vec<&str> = rows.iter().map(|r| &r[1]).collect();
    assert_eq!(
        names,
        ["'-minus", "'=HYPERLINK(\"x\")", "'@sum", "plain", "'+plus"],
        "{text}"
    );
    assert_eq!(
        (&rows[0][3], &rows[1][3], &rows[2][3]),
        ("optimal", "error", "error")
    );
    for r in &rows {
        for c in [5, 6, 8, 9, 12] {
            assert!(r[c].is_empty() || r[c].parse::<f64>().is_ok(), "{:?}", r);
        }
    }
    // A negative number in a numeric column stays a number.
    let neg = rows.iter().find(|r| r[9].starts_with('-'));
    assert!(neg.is_none_or(|r| r[9].parse::<f64>().is_ok()));
    let o = loud(&input, &out, &["--summary-only"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("2 skipped"));
    assert_eq!(
        std::fs::read_to_string(out.join("summary.csv"))
            .unwrap()
            .lines()
            .count(),
        6
    );
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.contains("| -minus |") && !md.contains("'-minus"), "{md}");
    let sh = d.path().join("sh");
    for s in ["0/2", "1/2"] {
        batch(&input, &sh, &["--summary-only", "--shard", s]);
    }
    let m = bin()
        .args(["merge", "--out"])
        .arg(&sh)
        .arg(&sh)
        .output()
        .unwrap();
    assert_eq!(
        m.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&m.stderr)
    );
    assert_eq!(
        summary_sans_time(&sh.join("summary.csv")),
        summary_sans_time(&out.join("summary.csv"))
    );
}

/// Issue 15: the fleet reader keeps line numbers right with a BOM, CRLF line endings,
/// comment lines and blank lines; a repeated header column is an error naming both; a huge
/// cell is not echoed whole; and rows in = rows out (ok + error) for broken fleets.
#[test]
fn fleet_lines_are_real_and_rows_in_equal_rows_out() {
    let d = tempfile::tempdir().unwrap();
    // Line:  1 header, 2 ok, 3 bad, 4 comment, 5 blank, 6 bad, 7 ok, 8 two cells, 9 bad.
    let text = "\u{feff}mechanism.slider_mass\r\n1.0 kg\r\nbad\r\n# comment, x\r\n\r\nbad2\r\n1.1 kg\r\n1 kg,2\r\nbad3\r\n";
    let input = fleet_of(d.path(), "crlf.csv", text);
    let out = d.path().join("o1");
    assert_eq!(
        batch(&input, &out, &["--summary-only"]).status.code(),
        Some(1)
    );
    let rows = records(&out.join("summary.csv"));
    let lines: Vec<String> = rows
        .iter()
        .map(|r| r[14].rsplit(':').next().unwrap().to_string())
        .collect();
    assert_eq!(lines, ["2", "3", "6", "7", "8", "9"], "{rows:?}");
    for r in &rows {
        if &r[3] == "error" {
            let line = r[14].rsplit(':').next().unwrap();
            assert!(r[15].contains(&format!("crlf.csv:{line}:")), "{:?}", r);
        }
    }
    // The same with LF line endings and comments right after the header.
    let lf = "mechanism.slider_mass\n# c1\n# c2\nbad\n\n\nbad2\n1 kg\n";
    let out = d.path().join("o2");
    batch(&fleet_of(d.path(), "lf.csv", lf), &out, &["--summary-only"]);
    let rows = records(&out.join("summary.csv"));
    let src: Vec<&str> = rows
        .iter()
        .map(|r| r[14].rsplit(':').next().unwrap())
        .collect();
    assert_eq!(src, ["4", "7", "8"]);

    // A repeated column (with and without a unit): an error naming both columns, in the
    // row of every data line (none is read).
    let out = d.path().join("o3");
    let dup = "mechanism.speed [rpm],mechanism.slider_mass,mechanism . speed\n1000,1 kg,900 rpm\n# c\n1000,1 kg,\n";
    let o = batch(
        &fleet_of(d.path(), "dup.csv", dup),
        &out,
        &["--summary-only"],
    );
    assert_eq!(o.status.code(), Some(1));
    let rows = records(&out.join("summary.csv"));
    assert_eq!(rows.len(), 2);
    for (r, line) in rows.iter().zip([2, 4]) {
        assert_eq!(&r[3], "error");
        assert!(
            r[15].starts_with(&format!("{}:{line}: this row was not read: ", d.path().join("dup.csv").display()))
                && r[15].contains("dup.csv:1: columns 1 (`mechanism.speed [rpm]`) and 3 (`mechanism . speed`) both set `mechanism.speed`"),
            "{}",
            &r[15]
        );
    }

    // A 10 MB cell: reported, not echoed whole (summary, stderr).
    let huge = format!(
        "mechanism.slider_mass\n1 kg\n{} kg\n1.2 kg\n",
        "9".repeat(10 << 20)
    );
    let out = d.path().join("o4");
    let o = bin()
        .args([
            "batch",
            &fleet_of(d.path(), "huge.csv", &huge),
            "--summary-only",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(
        o.stderr.len() < 20_000,
        "{} bytes on stderr",
        o.stderr.len()
    );
    assert!(std::fs::metadata(out.join("summary.csv")).unwrap().len() < 20_000);
    let rows = records(&out.join("summary.csv"));
    assert_eq!(
        rows.iter().map(|r| r[3].to_string()).collect::<Vec<_>>(),
        ["optimal", "error", "optimal"]
    );
    assert!(
        rows[1][15].contains("huge.csv:3:"),
        "{}",
        truncate(&rows[1][15])
    );

    // Rows in = rows out: every data line of a broken fleet is a row of the summary.
    let broken = "mechanism.slider_mass,mechanism.speed\n1 kg,1000 rpm\n# note\n1.3 kg,1000 rpm,x\n\n,\nfast,slow\n1.4 kg,1000 rpm\n\"1.1 kg,1000 rpm\n1.2 kg\n";
    let data_lines = broken
        .lines()
        .skip(1)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .count();
    let out = d.path().join("o5");
    batch(
        &fleet_of(d.path(), "broken.csv", broken),
        &out,
        &["--summary-only"],
    );
    let rows = records(&out.join("summary.csv"));
    assert_eq!(rows.len(), data_lines, "{rows:?}");
}

fn truncate(s: &str) -> &str {
    &s[..s.len().min(300)]
}

/// Issue 15: I/O errors name the path: an --out under a file (exit 2), and a result file
/// that cannot be written (its row is an error naming the file; the others are written).
#[test]
fn io_errors_name_the_path() {
    let d = tempfile::tempdir().unwrap();
    let input = fleet(d.path());
    let file = d.path().join("somefile");
    std::fs::write(&file, "x").unwrap();
    let o = batch(&input, &file.join("sub"), &[]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&file.join("sub").display().to_string()),
        "{err}"
    );
    // A directory where the JSON of machine 1 should go.
    let out = d.path().join("out");
    std::fs::create_dir_all(out.join("piston-1000rpm-1.json")).unwrap();
    let o = batch(&input, &out, &[]);
    assert_eq!(o.status.code(), Some(1));
    let rows = records(&out.join("summary.csv"));
    assert_eq!(&rows[0][3], "error");
    assert!(
        rows[0][15].contains("writing the results")
            && rows[0][15].contains(&out.join("piston-1000rpm-1.json").display().to_string()),
        "{}",
        &rows[0][15]
    );
    assert_eq!(&rows[1][3], "optimal");
}

/// Issue 15: a problem file of a batch that is not UTF-8 is an error row naming the file and
/// the line of the bad byte (the same reading as `cwsynth check`), and the others are solved.
#[test]
fn a_file_that_is_not_utf8_is_an_error_row_with_its_line() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("in");
    std::fs::create_dir(&dir).unwrap();
    let good = std::fs::read(template()).unwrap();
    std::fs::write(dir.join("a.toml"), &good).unwrap();
    let mut bad = b"# comment\n# \xff here\n".to_vec();
    bad.extend_from_slice(&good);
    std::fs::write(dir.join("b.toml"), bad).unwrap();
    let out = d.path().join("out");
    let o = batch(dir.to_str().unwrap(), &out, &["--summary-only"]);
    assert_eq!(o.status.code(), Some(1));
    let text = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let row = text
        .lines()
        .find(|l| l.contains("b.toml"))
        .expect("a row for b.toml");
    assert!(
        row.contains("b.toml:2") && row.contains("not UTF-8"),
        "{row}"
    );
    assert!(
        text.lines()
            .any(|l| l.contains("piston-1000rpm") && l.contains(",optimal,")),
        "{text}"
    );
}

#[test]
fn fleet_rows_are_named_by_the_template_and_tabled_with_their_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let tpl = dir.path().join("pump.toml");
    let text = std::fs::read_to_string(template()).unwrap();
    let text = text.replacen(
        "name = \"piston-1000rpm\"",
        "name = \"pump-{speed}-r{crank_radius}\"",
        1,
    );
    assert!(text.contains("pump-{speed}"));
    std::fs::write(&tpl, text).unwrap();
    let csv = dir.path().join("pumps.csv");
    std::fs::write(
        &csv,
        "mechanism.crank_radius [mm],mechanism.speed [rpm]\n35,1000\n30,1500\n,2500\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = batch(&format!("{}:{}", tpl.display(), csv.display()), &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for name in [
        "pump-1000rpm-r35mm",
        "pump-1500rpm-r30mm",
        "pump-2500rpm-r35mm",
    ] {
        assert!(out.join(format!("{name}.json")).is_file(), "{name}");
    }
    // The fleet's table: its inputs (an empty cell shows the template's value) and every
    // design value and objective in a column of its own.
    let t = std::fs::read_to_string(out.join("fleet-pumps.csv")).unwrap();
    let mut lines = t.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    for col in [
        "mechanism.crank_radius [mm]",
        "mechanism.speed [rpm]",
        "design.counterweight_unbalance_kgm",
        "objectives.peak_shaking_force_n",
    ] {
        assert!(head.contains(&col), "{col} in {head:?}");
    }
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 3);
    let at = |r: usize, c: &str| rows[r][head.iter().position(|h| *h == c).unwrap()];
    assert_eq!(at(1, "mechanism.speed [rpm]"), "1500");
    assert_eq!(at(2, "mechanism.crank_radius [mm]"), "35 mm");
    let f: f64 = at(0, "objectives.peak_shaking_force_n").parse().unwrap();
    assert!((f - 298.9472538).abs() < 1e-6, "{f}");

    // A placeholder that names no column is an error of the fleet, not a guess.
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        std::fs::read_to_string(&tpl)
            .unwrap()
            .replacen("{speed}", "{model}", 1),
    )
    .unwrap();
    let o = batch(
        &format!("{}:{}", bad.display(), csv.display()),
        &dir.path().join("o2"),
        &[],
    );
    assert!(!o.status.success());
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stderr),
        std::fs::read_to_string(dir.path().join("o2/summary.csv")).unwrap_or_default()
    );
    assert!(all.contains("{model}"), "{all}");
}

/// Issue 20: bad rows are counted, not flooded onto the terminal — the first few are shown
/// with file, line and field, one line says the rest are counted, and every one is in the
/// summary.
#[test]
fn many_bad_rows_show_the_first_few_and_count_the_rest() {
    let dir = std::env::temp_dir().join(format!("cwsynth-badrows-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut csv = String::from("mechanism.speed\n");
    for i in 0..40 {
        csv += &if i % 4 == 0 {
            format!("{} rpm\n", 900 + i)
        } else {
            format!("bad{i}\n")
        };
    }
    let fleet = dir.join("fleet.csv");
    std::fs::write(&fleet, csv).unwrap();
    let template = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/piston-1000rpm.toml");
    let out = bin()
        .arg("batch")
        .arg(format!("{}:{}", template.display(), fleet.display()))
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error ")).collect();
    assert_eq!(errors.len(), 6, "{err}");
    assert!(
        errors[0].contains("fleet.csv:3") && errors[0].contains("mechanism.speed"),
        "{err}"
    );
    assert!(errors[5].contains("counted, not shown"), "{err}");
    assert!(err.contains("30 failed"), "{err}");
    let summary = std::fs::read_to_string(dir.join("out/summary.csv")).unwrap();
    assert_eq!(
        summary
            .lines()
            .skip(1)
            .filter(|l| l.contains(",error,"))
            .count(),
        30
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A fleet whose column `mechanism.links.crank.outline.file` names a drawing per row: the rows
/// read it from the template's folder (the CSV is elsewhere), and a changed drawing re-solves
/// exactly the rows that read it; the others are skipped.
#[test]
fn a_changed_drawing_resolves_exactly_the_fleet_rows_that_name_it() {
    let d = tempfile::tempdir().unwrap();
    let shipped = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("problems");
    let (tpl, csv_dir) = (d.path().join("tpl"), d.path().join("csv"));
    std::fs::create_dir_all(tpl.join("drawings")).unwrap();
    std::fs::create_dir_all(&csv_dir).unwrap();
    let template = tpl.join("crank.toml");
    std::fs::copy(
        shipped.join("linkage-fourbar-crank-outline.toml"),
        &template,
    )
    .unwrap();
    let drawing = shipped.join("drawings/linkage-fourbar-crank.dxf");
    let (a, b) = ("drawings/linkage-fourbar-crank.dxf", "drawings/crank-b.dxf");
    std::fs::copy(&drawing, tpl.join(a)).unwrap();
    std::fs::copy(&drawing, tpl.join(b)).unwrap();
    let csv = csv_dir.join("fleet.csv");
    std::fs::write(
        &csv,
        format!("name,mechanism.links.crank.outline.file\nr1,\nr2,{b}\nr3,{b}\nr4,{a}\n"),
    )
    .unwrap();
    let input = format!("{}:{}", template.display(), csv.display());
    let out = d.path().join("out");
    let o = loud(&input, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("4 ok, 0 failed, 0 skipped"), "{err}");
    let mtime = |name: &str| {
        std::fs::metadata(out.join(format!("{name}.json")))
            .unwrap()
            .modified()
            .unwrap()
    };
    let before: Vec<_> = ["r1", "r2", "r3", "r4"].map(mtime).to_vec();
    let o = loud(&input, &out, &[]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("4 skipped"));

    // New bytes, the same part: a line on a layer the outline does not read.
    let mut dxf = dxf::Drawing::load_file(tpl.join(b)).unwrap();
    let line = dxf::entities::Line::new(
        dxf::Point::new(0.0, 0.0, 0.0),
        dxf::Point::new(1.0, 1.0, 0.0),
    );
    let mut e = dxf::entities::Entity::new(dxf::entities::EntityType::Line(line));
    e.common.layer = "NOTES".into();
    dxf.add_entity(e);
    dxf.save_file(tpl.join(b)).unwrap();
    std::thread::sleep(std::time::Duration::from_millis(20));
    let o = loud(&input, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("4 ok, 0 failed, 2 skipped"), "{err}");
    let after: Vec<_> = ["r1", "r2", "r3", "r4"].map(mtime).to_vec();
    let solved: Vec<bool> = before.iter().zip(&after).map(|(x, y)| x != y).collect();
    assert_eq!(solved, [false, true, true, false], "the rows naming {b}");
    // The same numbers: the drawing's part did not change.
    let v =
        |dir: &Path, n: &str| json_sans_time(&dir.join(format!("{n}.json")))["objectives"].clone();
    assert_eq!(v(&out, "r2"), v(&out, "r1"));

    // The template's drawing is read by every row's counterweight: all are solved again.
    std::fs::copy(tpl.join(b), tpl.join(a)).unwrap();
    let o = loud(&input, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("4 ok, 0 failed, 0 skipped"), "{err}");
}
