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

/// The result JSON without `timing`.
fn json_sans_time(path: &Path) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    v.as_object_mut().unwrap().remove("timing");
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
            // Byte-identical apart from the timing object.
            let strip = |p: &Path| {
                let t = std::fs::read_to_string(p).unwrap();
                let i = t.find("\"timing\"").unwrap();
                let j = i + t[i..].find('}').unwrap();
                format!("{}{}", &t[..i], &t[j..])
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
    let o = bin()
        .arg("batch")
        .arg(&input)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
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
    let o = bin()
        .arg("batch")
        .arg(&input)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
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
    let o = bin()
        .arg("batch")
        .arg(&input)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
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
    // For every shipped scene: the row made from `summary_json` (what `--summary-only`
    // serialises) equals the row made from the whole result JSON, and `lookup`'s direct
    // path through the number maps gives what a JSON pointer into the whole result gives.
    use cwsynth::batch::row_from_json;
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
            row_from_json(7, "src", "hash", &r.summary_json()),
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
