//! The command line as a user runs it: exit codes, the JSON contract, written files.

use std::path::PathBuf;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cwsynth"))
}

/// Runs `cwsynth ARGS` with `text` on its standard input; its output, both streams captured.
fn with_stdin(args: &[&str], text: &str) -> std::process::Output {
    use std::io::Write;
    use std::process::Stdio;
    let mut child = bin()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    child.wait_with_output().unwrap()
}

fn problem(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("problems")
        .join(name)
}

#[test]
fn solve_json_has_the_documented_keys() {
    let out = bin()
        .args(["solve", "--json"])
        .arg(problem("piston-1000rpm.toml"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for k in [
        "name",
        "family",
        "status",
        "design",
        "objectives",
        "baselines",
        "errors",
        "warnings",
        "timing",
        "model",
        "derived",
        "paper",
        "method",
    ] {
        assert!(v.get(k).is_some(), "missing key {k}");
    }
    assert_eq!(v["name"], "piston-1000rpm");
    assert_eq!(v["family"], "slider-crank");
    assert_eq!(v["status"], "optimal");
    for k in [
        "counterweight_unbalance_kgm",
        "counterweight_mass_kg",
        "counterweight_radius_m",
        "counterweight_angle_rad",
    ] {
        assert!(v["design"][k].is_f64(), "design.{k}");
    }
    for k in [
        "peak_shaking_force_n",
        "rms_shaking_force_n",
        "peak_drive_torque_nm",
    ] {
        assert!(v["objectives"][k].is_f64(), "objectives.{k}");
        assert!(v["errors"][k].as_f64().unwrap() >= 0.0, "errors.{k}");
    }
    for b in ["none", "y_force_zeroed", "fifty_percent", "equal_ranges"] {
        for k in [
            "peak_shaking_force_n",
            "rms_shaking_force_n",
            "peak_to_peak_x_n",
            "peak_to_peak_y_n",
        ] {
            assert!(v["baselines"][b][k].is_f64(), "baselines.{b}.{k}");
        }
    }
    // The optimum is never worse than a baseline.
    let peak = v["objectives"]["peak_shaking_force_n"].as_f64().unwrap();
    for (_, b) in v["baselines"].as_object().unwrap() {
        assert!(peak <= b["peak_shaking_force_n"].as_f64().unwrap() * (1.0 + 1e-9));
    }
    // The error estimate meets the scene's 1e-9 relative target.
    assert!(v["errors"]["peak_shaking_force_n"].as_f64().unwrap() <= 1e-9 * peak);
}

#[test]
fn out_dir_gets_json_markdown_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let out = bin()
        .args(["solve", "--out"])
        .arg(dir.path())
        .arg(problem("piston-2000rpm.toml"))
        .output()
        .unwrap();
    assert!(out.status.success());
    for f in [
        "piston-2000rpm.json",
        "piston-2000rpm.md",
        "piston-2000rpm-shaking-force.svg",
    ] {
        let p = dir.path().join(f);
        assert!(p.exists(), "{f}");
        assert!(std::fs::metadata(&p).unwrap().len() > 100);
    }
    let svg = std::fs::read_to_string(dir.path().join("piston-2000rpm-shaking-force.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("no counterweight") && svg.contains("optimum"));
    // No temporary files are left behind.
    assert!(std::fs::read_dir(dir.path()).unwrap().all(|e| !e
        .unwrap()
        .file_name()
        .to_string_lossy()
        .ends_with(".tmp")));
}

#[test]
fn check_reports_bad_files_and_fails() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    let text = std::fs::read_to_string(problem("piston-1000rpm.toml"))
        .unwrap()
        .replace("\"140 mm\"", "\"-140 mm\"");
    std::fs::write(&bad, text).unwrap();
    let out = bin()
        .arg("check")
        .arg(problem("piston-1000rpm.toml"))
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("bad.toml:") && stderr.contains("mechanism.rod_length"),
        "{stderr}"
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("ok    "));
    // A good file alone passes.
    assert!(bin()
        .arg("check")
        .arg(problem("piston-1000rpm.toml"))
        .status()
        .unwrap()
        .success());
}

#[test]
fn solve_keeps_going_past_a_bad_file() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "name = \"x\"\nfamily = \"slider-crank\"\n").unwrap();
    let out = bin()
        .args(["solve", "--json"])
        .arg(&bad)
        .arg(problem("piston-1000rpm.toml"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["name"], "piston-1000rpm");
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing field `mechanism`"));
}

/// Issue 15: `solve --json` prints one shape whatever the number of files — one compact JSON
/// object per line (JSON Lines) — and a closed pipe ends the run quietly.
#[test]
fn solve_json_is_json_lines_and_a_closed_pipe_is_quiet() {
    let out = bin()
        .args(["solve", "--json"])
        .arg(problem("piston-1000rpm.toml"))
        .arg(problem("piston-2000rpm.toml"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let names: Vec<String> = text
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap()["name"].to_string())
        .collect();
    assert_eq!(names, ["\"piston-1000rpm\"", "\"piston-2000rpm\""]);

    // A reader that closes the pipe at once (`| head -c0`): no panic, no message.
    let mut child = bin()
        .args(["solve", "--json"])
        .arg(problem("piston-1000rpm.toml"))
        .arg(problem("piston-2000rpm.toml"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.code(), Some(0), "{err}");
}

/// Issue 15: a missing input or a directory without problem files is a usage error (exit 2,
/// as the README says), named in the message.
#[test]
fn missing_inputs_and_empty_directories_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    for verb in ["solve", "check"] {
        let out = bin()
            .arg(verb)
            .arg(dir.path().join("nope.toml"))
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{verb}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("nope.toml: no such file"));
        let out = bin().arg(verb).arg(dir.path()).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{verb}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("no problem files"));
    }
}

/// Issue 15: `solve --out` never lets two scenes overwrite each other's files (same name, or
/// names equal but for case).
#[test]
fn solve_out_refuses_clashing_names() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(problem("piston-1000rpm.toml")).unwrap();
    let a = dir.path().join("a.toml");
    let b = dir.path().join("b.toml");
    std::fs::write(&a, &text).unwrap();
    std::fs::write(
        &b,
        text.replace("name = \"piston-1000rpm\"", "name = \"Piston-1000RPM\""),
    )
    .unwrap();
    let out_dir = dir.path().join("out");
    let out = bin()
        .args(["solve", "--out"])
        .arg(&out_dir)
        .arg(&a)
        .arg(&b)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("b.toml") && err.contains("clashes with"),
        "{err}"
    );
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out_dir.join("piston-1000rpm.json")).unwrap())
            .unwrap();
    assert!(v["source"].as_str().unwrap().ends_with("a.toml"));
    assert!(!out_dir.join("Piston-1000RPM.json").exists());
}

/// Issue 15: one file's panic does not stop `solve` with several files: that file is
/// reported once on stderr (with the panic's message), the others are solved, exit 1. The
/// panic comes from the debug builds' test hook `CWSYNTH_TEST_PANIC=<name>`.
#[test]
fn solve_survives_a_panicking_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = bin()
        .env("CWSYNTH_TEST_PANIC", "piston-1000rpm")
        .args(["solve", "--json", "--out"])
        .arg(dir.path())
        .arg(problem("piston-1000rpm.toml"))
        .arg(problem("piston-2000rpm.toml"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("piston-1000rpm.toml: internal error (a panic")
            && err.contains("CWSYNTH_TEST_PANIC"),
        "{err}"
    );
    // The default hook's report ("thread … panicked at …") is replaced by that one line.
    assert!(!err.contains("panicked at"), "{err}");
    let text = String::from_utf8(out.stdout).unwrap();
    let v: serde_json::Value = serde_json::from_str(text.trim()).unwrap();
    assert_eq!(v["name"], "piston-2000rpm");
    assert!(dir.path().join("piston-2000rpm.json").exists());
    assert!(!dir.path().join("piston-1000rpm.json").exists());
}

#[test]
fn reports_are_in_workshop_units_unless_asked_for_si() {
    let d = tempfile::tempdir().unwrap();
    for (units, dir) in [("workshop", "w"), ("si", "s")] {
        let o = bin()
            .args(["solve", "--units", units, "--out"])
            .arg(d.path().join(dir))
            .arg(problem("piston-1000rpm.toml"))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let md =
        |dir: &str| std::fs::read_to_string(d.path().join(dir).join("piston-1000rpm.md")).unwrap();
    let (w, s) = (md("w"), md("s"));
    assert!(w.contains("| counterweight radius | 50 | mm |"), "{w}");
    assert!(
        s.contains("| counterweight radius | 0.0500000 | m |"),
        "{s}"
    );
    assert!(w.contains("| counterweight angle | 180 | ° |"));
    assert!(s.contains("| counterweight angle | 3.14159 | rad |"));
    // The JSON is SI either way.
    let j = |dir: &str| {
        std::fs::read_to_string(d.path().join(dir).join("piston-1000rpm.json")).unwrap()
    };
    let strip = |t: String| -> serde_json::Value {
        let mut v: serde_json::Value = serde_json::from_str(&t).unwrap();
        v.as_object_mut().unwrap().remove("timing");
        v
    };
    assert_eq!(strip(j("w")), strip(j("s")));
}

/// Issue 20: `cwsynth new <family> > my.toml && cwsynth solve my.toml` works for every
/// family, from a machine with no paper's numbers (`templates/` or a shipped scene, issue 34);
/// an unknown family names the nearest one.
#[test]
fn new_writes_a_commented_file_that_solves_for_every_family() {
    let dir = std::env::temp_dir().join(format!("cwsynth-new-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for f in cwsynth::families::FAMILIES.iter() {
        let name = f.name();
        let out = bin().args(["new", name]).output().unwrap();
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(text.starts_with("# A cwsynth problem file"), "{name}");
        assert!(text.contains(&format!("name = \"my-{name}\"")), "{name}");
        let file = dir.join(format!("my-{name}.toml"));
        std::fs::write(&file, &text).unwrap();
        let solved = bin()
            .arg("solve")
            .arg(&file)
            .arg("--json")
            .output()
            .unwrap();
        assert!(
            solved.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&solved.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&solved.stdout).unwrap();
        assert_eq!(v["name"], format!("my-{name}"));
        assert_eq!(v["family"], name);
        assert_ne!(v["status"], "failed", "{name}");
        // A clean start (issue 34): no paper's numbers to check, a design (not a given
        // one), no warning but the eccentric gear's notes on its own geometry.
        let no_paper = v["paper"].as_array().is_none_or(|a| a.is_empty());
        // (The hypocycloid's and the gear's results always set their paper's claims about
        // the method beside the computation — the series against the exact coefficients, µ2
        // against −µ1 — whatever the data: not a paper's numbers for this machine.)
        assert!(!text.contains("[[paper]]"), "{name}");
        assert!(
            no_paper || ["hypocycloid", "eccentric-gear"].contains(&name),
            "{name}"
        );
        assert!(
            ["optimal", "best_found"].contains(&v["status"].as_str().unwrap())
                || name == "hypocycloid",
            "{name}: {}",
            v["status"]
        );
        let warnings = v["warnings"].as_array().unwrap();
        let geometry = |w: &serde_json::Value| {
            let w = w.as_str().unwrap();
            w.contains("cusp") || w.contains("poles are as close") || w.contains("pole window")
        };
        assert!(
            warnings.is_empty() || (name == "eccentric-gear" && warnings.iter().all(geometry)),
            "{name}: {warnings:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
    let bad = bin().args(["new", "slidercrank"]).output().unwrap();
    assert!(!bad.status.success());
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("slider-crank"), "{err}");
}

/// Shell completions and the manual page are generated from the CLI's own definition.
#[test]
fn completions_and_man_page_are_written() {
    for shell in ["bash", "zsh", "fish"] {
        let out = bin().args(["completions", shell]).output().unwrap();
        assert!(out.status.success(), "{shell}");
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(
            text.contains("calibrate") && text.contains("new"),
            "{shell}"
        );
    }
    let man = bin().arg("man").output().unwrap();
    assert!(man.status.success());
    let text = String::from_utf8(man.stdout).unwrap();
    assert!(
        text.contains(".TH cwsynth 1") && text.contains("batch"),
        "{text}"
    );
    // One page: every command in it, no pointers to `cwsynth-solve(1)` pages that are not
    // installed; its exit statuses and examples (issue 34).
    for want in [
        ".SS \"cwsynth solve\"",
        ".SS \"cwsynth study\"",
        ".SH \"EXIT STATUS\"",
        ".SH EXAMPLES",
        "cat my.toml | cwsynth solve \\-",
    ] {
        assert!(text.contains(want), "{want}");
    }
    assert!(!text.contains("(1)"), "a page that is not installed");
    // Every verb's --help ends with an example.
    for verb in [
        "solve",
        "batch",
        "merge",
        "check",
        "schema",
        "new",
        "study",
        "calibrate",
    ] {
        let out = bin().args([verb, "--help"]).output().unwrap();
        let help = String::from_utf8(out.stdout).unwrap();
        assert!(help.contains("\n  cwsynth "), "{verb}: {help}");
    }
}

/// `check -` reads the problem file from standard input, as `solve -` does.
#[test]
fn check_reads_standard_input() {
    let text = std::fs::read_to_string(problem("piston-1000rpm.toml")).unwrap();
    let out = with_stdin(&["check", "-"], &text);
    assert!(out.status.success());
    let said = String::from_utf8(out.stdout).unwrap();
    assert!(said.starts_with("ok    <stdin> (piston-1000rpm"), "{said}");
}

/// `--threads` is bounded: a mistyped count is refused before a thread starts (issue 34).
#[test]
fn an_absurd_thread_count_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = problem("piston-1000rpm.toml");
    let out = bin()
        .args([
            "batch",
            p.to_str().unwrap(),
            "--out",
            dir.path().to_str().unwrap(),
            "--threads",
            "100000",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--threads") && err.contains("1..=1024"),
        "{err}"
    );
}

/// Result names in `--out` that are a FIFO or a link to `/dev/zero` are not read: the batch
/// ends and writes its results (issue 34).
#[cfg(unix)]
#[test]
fn a_fifo_or_dev_zero_in_the_output_does_not_hang_a_batch() {
    let dir = tempfile::tempdir().unwrap();
    let status = std::process::Command::new("mkfifo")
        .arg(dir.path().join("piston-1000rpm.json"))
        .status()
        .unwrap();
    assert!(status.success());
    std::os::unix::fs::symlink("/dev/zero", dir.path().join("summary.csv.resume")).unwrap();
    let p = problem("piston-1000rpm.toml");
    let mut child = bin()
        .args([
            "batch",
            p.to_str().unwrap(),
            "--out",
            dir.path().to_str().unwrap(),
            "--quiet",
        ])
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    loop {
        if let Some(st) = child.try_wait().unwrap() {
            assert!(st.success());
            break;
        }
        if t0.elapsed() > std::time::Duration::from_secs(60) {
            let _ = child.kill();
            panic!("the batch hangs on a FIFO or /dev/zero in --out");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let json = std::fs::read_to_string(dir.path().join("piston-1000rpm.json")).unwrap();
    assert!(json.contains("\"optimal\""));
}

/// A problem file far over the limit is refused after reading at most the limit (issue 34):
/// a 1 GB sparse file costs no more memory than 1 MiB.
#[test]
fn a_huge_problem_file_is_refused_without_reading_it() {
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.toml");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(1 << 30)
        .unwrap();
    let bytes = cwsynth::problem::read_bounded(&big, cwsynth::problem::MAX_FILE_BYTES).unwrap();
    assert_eq!(bytes.len(), cwsynth::problem::MAX_FILE_BYTES + 1);
    let e = cwsynth::families::load(&big).unwrap_err().to_string();
    assert!(e.contains("passes the limit"), "{e}");
    // A directory is not a problem file.
    assert!(cwsynth::problem::read_bounded(dir.path(), 10).is_err());
}

/// `merge` refuses the same shard twice and a shard whose rows belong to another split
/// (issue 34): it would duplicate or mix machines.
#[test]
fn merge_refuses_a_shard_given_twice_or_from_another_run() {
    let (a, b, out) = (
        tempfile::tempdir().unwrap(),
        tempfile::tempdir().unwrap(),
        tempfile::tempdir().unwrap(),
    );
    let inputs = [
        problem("piston-1000rpm.toml"),
        problem("piston-2000rpm.toml"),
    ];
    for d in [&a, &b] {
        let st = bin()
            .args([
                "batch",
                "--quiet",
                "--summary-only",
                "--shard",
                "0/2",
                "--out",
            ])
            .arg(d.path())
            .args(&inputs)
            .status()
            .unwrap();
        assert!(st.success());
    }
    let merge = |dirs: &[&std::path::Path]| {
        let o = bin()
            .arg("merge")
            .args(dirs)
            .arg("--out")
            .arg(out.path())
            .output()
            .unwrap();
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let (ok, err) = merge(&[a.path(), b.path()]);
    assert!(!ok && err.contains("given twice"), "{err}");
    // Shard 0's rows renamed shard 1: its machine 0 is not of shard 1.
    std::fs::rename(
        b.path().join("summary-shard-0-of-2.csv"),
        b.path().join("summary-shard-1-of-2.csv"),
    )
    .unwrap();
    let (ok, err) = merge(&[a.path(), b.path()]);
    assert!(!ok && err.contains("another run"), "{err}");
}

/// `cwsynth solve -` reads the problem file from standard input (issue 34); a bad one is
/// an error at `<stdin>:LINE`.
#[test]
fn solve_reads_a_problem_from_standard_input() {
    let run = |text: &str| with_stdin(&["solve", "--json", "-"], text);
    let text = std::fs::read_to_string(problem("piston-1000rpm.toml")).unwrap();
    let out = run(&text);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "optimal");
    assert_eq!(v["source"], "<stdin>");
    let out = run("name = \"x\"\n");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("<stdin>:1") && err.contains("family"), "{err}");
}
