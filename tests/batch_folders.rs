//! Issue 34: a batch of [`LARGE_RUN`] machines or more writes each machine's files into
//! `machines/NNN/` (NNN = index ÷ 1000), with only the summary, the reports and the fleet's
//! table at the top; the links of `index.html` resolve, a resumed run finds the machines it
//! wrote (and removes the leftovers of a killed run in the folders), shards in one directory
//! find the same folders and merge into the unsharded summary. Smaller runs stay flat (every
//! other batch test, and `results/`).

use cwsynth::batch::{Layout, LARGE_RUN, MACHINES_DIR};
use std::collections::BTreeSet;
use std::path::Path;

/// `cwsynth ARGS…` (`batch` or `merge`), which must succeed (every machine solves); its
/// stderr.
fn cwsynth(args: &[&dyn AsRef<std::ffi::OsStr>]) -> String {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_cwsynth"))
        .args(args.iter().map(|a| a.as_ref()))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(0), "{err}");
    err
}

/// The summary's rows without `time_s`.
fn rows_sans_time(path: &Path) -> Vec<Vec<String>> {
    let mut rdr = csv::Reader::from_path(path).unwrap();
    let t = rdr.headers().unwrap().iter().position(|c| c == "time_s");
    rdr.records()
        .map(|r| {
            let r = r.unwrap();
            let cells = r.iter().enumerate().filter(|(i, _)| Some(*i) != t);
            cells.map(|(_, c)| c.to_string()).collect()
        })
        .collect()
}

/// Every local link (`href`, `src`) of the page `dir/page`, each checked to be a file.
fn links_resolve(dir: &Path, page: &str) -> Vec<String> {
    let html = std::fs::read_to_string(dir.join(page)).unwrap();
    let mut links = Vec::new();
    for attr in ["href=\"", "src=\""] {
        for (i, _) in html.match_indices(attr) {
            let rest = &html[i + attr.len()..];
            let link = &rest[..rest.find('"').unwrap()];
            if link.starts_with('#') {
                continue;
            }
            assert!(dir.join(link).is_file(), "{page}: {link} is not a file");
            links.push(link.to_string());
        }
    }
    links
}

/// The names of the entries of `dir`.
fn entries(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn a_large_fleet_writes_its_machines_into_folders_that_resume_merge_and_links_follow() {
    let n = LARGE_RUN + 1;
    let d = tempfile::tempdir().unwrap();
    let csv = d.path().join("fleet.csv");
    let mut text = String::from("name,mechanism.speed [rpm]\n");
    for i in 0..n {
        text += &format!("m-{i:05},{}\n", 800 + i % 1500);
    }
    std::fs::write(&csv, text).unwrap();
    let tpl = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/piston-1000rpm.toml");
    let input = format!("{tpl}:{}", csv.display());
    let out = d.path().join("out");
    let err = cwsynth(&[&"batch", &input, &"--out", &out, &"--threads", &"2"]);
    assert!(err.contains("machines a folder machines/NNN/"), "{err}");

    // At the top: the summary, the reports, the fleet's table, the lock and the folders.
    let top: BTreeSet<String> = [
        ".summary.csv.lock",
        "fleet-fleet.csv",
        "index.html",
        MACHINES_DIR,
        "summary.csv",
        "summary.md",
    ]
    .map(String::from)
    .into();
    assert_eq!(entries(&out), top);
    let folders = entries(&out.join(MACHINES_DIR));
    assert_eq!(folders, ["000", "001"].map(String::from).into());
    // Machines 0–999 in 000 (7 files each), machine 1000 in 001, each JSON's files beside it.
    assert_eq!(entries(&out.join("machines/000")).len(), 7000);
    let last: Vec<String> = entries(&out.join("machines/001")).into_iter().collect();
    assert!(last.contains(&"m-01000.json".into()), "{last:?}");
    assert!(last.iter().all(|f| f.starts_with("m-01000")), "{last:?}");
    let layout = Layout::of_run(n);
    for (index, name) in [(0, "m-00000"), (999, "m-00999"), (1000, "m-01000")] {
        let dir = layout.dir(&out, index);
        let v: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.join(format!("{name}.json"))).unwrap())
                .unwrap();
        for f in v["batch"]["files"].as_object().unwrap().keys() {
            assert!(dir.join(f).is_file(), "{index}: {f}");
        }
    }
    // The index links each shown machine's page and the plotted machines' files in their
    // folders, and every link resolves; so do a machine page's links, in its folder.
    let links = links_resolve(&out, "index.html");
    assert!(links.contains(&"machines/000/m-00000.html".to_string()));
    assert!(links.contains(&"machines/000/m-00000.json".to_string()));
    assert!(links_resolve(&out.join("machines/001"), "m-01000.html").len() > 3);
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        md.contains("`machines/NNN/`, NNN = its index ÷ 1000"),
        "{md}"
    );
    let first = rows_sans_time(&out.join("summary.csv"));
    assert_eq!(first.len() as u64, n);

    // Killed half-way: half a summary, a file of the last folder gone, a leftover temporary
    // file of a dead process in a folder. The re-run finds the machines in their folders.
    let s = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let half: String = s.lines().take(500).map(|l| format!("{l}\n")).collect();
    std::fs::write(out.join("summary.csv.partial"), half).unwrap();
    std::fs::remove_file(out.join("summary.csv")).unwrap();
    std::fs::remove_file(out.join("machines/001/m-01000.md")).unwrap();
    let stale = out.join("machines/000/.m-00005.json.4000000000.tmp");
    std::fs::write(&stale, "{\"half").unwrap();
    let err = cwsynth(&[&"batch", &input, &"--out", &out]);
    assert!(err.contains(&format!("{} skipped", n - 1)), "{err}");
    assert!(!stale.exists() && out.join("machines/001/m-01000.md").is_file());
    assert_eq!(rows_sans_time(&out.join("summary.csv")), first);

    // Shards in the same directory use the layout of the whole batch: each finds its
    // machines done in their folders; merged, the summary is the unsharded one.
    for (shard, mine) in [("0/2", 501), ("1/2", 500)] {
        let err = cwsynth(&[&"batch", &input, &"--out", &out, &"--shard", &shard]);
        assert!(err.contains(&format!("{mine} skipped")), "{err}");
    }
    cwsynth(&[&"batch", &"--merge", &"--out", &out, &"--quiet"]);
    assert_eq!(rows_sans_time(&out.join("summary.csv")), first);
    assert_eq!(links_resolve(&out, "index.html"), links);

    // Merged elsewhere (no machine files there): nothing links to a missing file.
    let merged = d.path().join("merged");
    cwsynth(&[&"merge", &out, &"--out", &merged]);
    assert_eq!(rows_sans_time(&merged.join("summary.csv")), first);
    assert_eq!(links_resolve(&merged, "index.html"), ["summary.csv"]);
    let md = std::fs::read_to_string(merged.join("summary.md")).unwrap();
    assert!(!md.contains("machines/NNN/"), "{md}");
}
