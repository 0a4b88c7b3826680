//! Helpers shared by the integration tests: shipped problem files, editing a fixture, and
//! asserting that a rejection names the file, the line and the field.
#![allow(dead_code)]

pub mod dd;

use cwsynth::families::parse_str;
use cwsynth::problem::ProblemError;
use std::path::{Path, PathBuf};

/// A shipped problem file.
pub fn problem(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("problems")
        .join(name)
}

/// `base` with the first `replace` replaced by `by` (the fixture must contain it).
#[track_caller]
pub fn with(base: &str, replace: &str, by: &str) -> String {
    assert!(base.contains(replace), "fixture lacks `{replace}`");
    base.replacen(replace, by, 1)
}

/// The rejection of `text` (read as `bad.toml`).
#[track_caller]
pub fn err(text: &str) -> ProblemError {
    parse_str(text, Path::new("bad.toml")).expect_err("should be rejected")
}

/// The 1-based line of the first `needle` in `text`.
pub fn line_of(text: &str, needle: &str) -> usize {
    text[..text.find(needle).unwrap()].matches('\n').count() + 1
}

/// `text` with `key = value` set: the key's line replaced inside its `[table]`, else
/// inserted after the table's header, else the table appended.
pub fn set_key(text: &str, key: &str, value: &str) -> String {
    let (table, name) = key.rsplit_once('.').unwrap();
    let header = format!("[{table}]");
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let Some(h) = lines
        .iter()
        .position(|l| l.split('#').next().unwrap().trim() == header)
    else {
        return format!("{text}\n{header}\n{name} = {value}\n");
    };
    let end = lines[h + 1..]
        .iter()
        .position(|l| l.trim_start().starts_with('['))
        .map_or(lines.len(), |k| h + 1 + k);
    let line = format!("{name} = {value}");
    match (h + 1..end).find(|&k| {
        lines[k]
            .split_once('=')
            .is_some_and(|(a, _)| a.trim() == name)
    }) {
        Some(k) => lines[k] = line,
        None => lines.insert(h + 1, line),
    }
    lines.join("\n") + "\n"
}

/// The shipped file a key is tried on: one where the key takes effect.
pub fn integer_key_base(family: &str, key: &str) -> &'static str {
    match family {
        "slider-crank" => "felling-head-150rpm.toml",
        "luffing-crane" if key.starts_with("mechanism.hoist_rope") => {
            "crane-thesis-inclined-rope.toml"
        }
        "luffing-crane" => "crane-thesis-optimise.toml",
        "eccentric-gear" if key == "accuracy.sweep_points" => "gear-eccentricity-design.toml",
        "eccentric-gear" if key == "model.profile_points_per_arch" => "gear-tooth-profiles.toml",
        "eccentric-gear" => "gear-paper-table1.toml",
        "hypocycloid"
            if key.starts_with("objective.zero_search")
                || ["curve_points", "theta_scan", "opt_grid", "nm_max_iters"]
                    .iter()
                    .any(|k| key == format!("accuracy.{k}")) =>
        {
            "hypocycloid-c4-variant1.toml"
        }
        "hypocycloid" => "hypocycloid-variant1.toml",
        "linkage" => "linkage-piston-1000rpm.toml",
        "multi-cylinder" => "inline-3-balance-shaft.toml",
        f => panic!("no base file for family {f}"),
    }
}

/// `text` is rejected naming `field` on the line of `line_needle`, saying `says`.
#[track_caller]
pub fn assert_names(text: &str, field: &str, line_needle: &str, says: &str) {
    let e = err(text);
    let msg = e.to_string();
    assert_eq!(e.field(), Some(field), "{msg}");
    assert_eq!(e.line(), Some(line_of(text, line_needle)), "{msg}");
    assert!(msg.starts_with("bad.toml:"), "{msg}");
    assert!(msg.contains(says), "`{msg}` should say `{says}`");
}

/// Runs `cwsynth solve --json` on `text` written to a temporary `bad.toml`; returns the exit
/// code and the standard error.
pub fn solve_text(text: &str) -> (Option<i32>, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cwsynth"))
        .args(["solve", "--json"])
        .arg(&path)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `cwsynth solve --json FILE`, which must succeed: the result object.
#[track_caller]
pub fn solve_json(path: &Path) -> serde_json::Value {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cwsynth"))
        .args(["solve", "--json"])
        .arg(path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// `cwsynth solve --out DIR` of shipped problem files, which must succeed: the directory.
#[track_caller]
pub fn solve_out(names: &[&str]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cwsynth"))
        .args(["solve", "--out"])
        .arg(dir.path())
        .args(names.iter().map(|n| problem(n)))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir
}

/// The number at a dotted key of a result (`objectives.c4`, `coefficients.a.4`).
#[track_caller]
pub fn num(v: &serde_json::Value, path: &str) -> f64 {
    let mut x = v;
    for p in path.split('.') {
        x = match x {
            serde_json::Value::Array(a) => &a[p.parse::<usize>().unwrap()],
            _ => &x[p],
        };
    }
    x.as_f64()
        .unwrap_or_else(|| panic!("{path} is not a number: {x}"))
}

/// Every shipped problem file, sorted.
pub fn shipped() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(problem(""))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

/// The shipped problem files of one family (`"luffing-crane"`, …), sorted.
pub fn family_files(family: &str) -> Vec<PathBuf> {
    let tag = format!("family = \"{family}\"");
    (shipped().into_iter())
        .filter(|p| std::fs::read_to_string(p).unwrap().contains(&tag))
        .collect()
}

#[allow(unused_imports)]
pub use dd::{dd_sin_cos, Dd};

/// Every number of a result (JSON) is finite: serde_json writes NaN and ±inf as `null`, so a
/// `null` where the result has numbers is what a NaN looks like there; the maps are checked
/// directly.
#[track_caller]
pub fn assert_finite(r: &cwsynth::report::SolveResult) {
    assert_finite_as(r, &r.name);
}

/// [`assert_finite`], naming the case `what` in the message.
#[track_caller]
pub fn assert_finite_as(r: &cwsynth::report::SolveResult, what: &str) {
    if let Some(bad) = non_finite(r) {
        panic!("{what}: {bad}");
    }
}

/// The first number of a result's maps that is not finite (`section.key = value`), if any.
pub fn non_finite(r: &cwsynth::report::SolveResult) -> Option<String> {
    let sections = [
        ("design".to_string(), &r.design),
        ("objectives".to_string(), &r.objectives),
        ("errors".to_string(), &r.errors),
        ("derived".to_string(), &r.derived),
    ];
    let baselines = r
        .baselines
        .iter()
        .map(|(b, m)| (format!("baselines.{b}"), m));
    sections.into_iter().chain(baselines).find_map(|(sec, m)| {
        m.iter()
            .find(|(_, v)| !v.is_finite())
            .map(|(k, v)| format!("{sec}.{k} = {v}"))
    })
}

/// A small deterministic generator (tests must not depend on a seed source).
pub struct Lcg(pub u64);
impl Lcg {
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    /// Log-uniform in [lo, hi].
    pub fn log(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + self.next() * (hi.ln() - lo.ln())).exp()
    }
}

/// A deterministic stream of numbers uniform in [−1, 1) (a 64-bit LCG, Knuth's MMIX
/// constants), for randomised tests that must not depend on a crate or a seed file (was
/// `numeric::uniform_pm1`, the library's unit-test helper).
pub fn uniform_pm1(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// ΔE of the torque `t` by a composite Simpson running integral of T − T̄ on `n` panels (an
/// evaluation independent of the library's trigonometric interpolants).
pub fn simpson_delta_e(t: &dyn Fn(f64) -> f64, n: usize) -> f64 {
    let h = std::f64::consts::TAU / n as f64;
    let mean = (0..n).map(|k| t(k as f64 * h)).sum::<f64>() / n as f64;
    let (mut e, mut hi, mut lo) = (0.0_f64, 0.0_f64, 0.0_f64);
    for k in 0..n {
        let p = k as f64 * h;
        e += h / 6.0 * (t(p) + 4.0 * t(p + h / 2.0) + t(p + h) - 6.0 * mean);
        hi = hi.max(e);
        lo = lo.min(e);
    }
    hi - lo
}

/// A luffing-crane linkage: L_c (m), the step-1 angles φ_min, γ1, γ2, γ3 (deg), k1, k2.
pub fn crane_linkage(
    l_c: f64,
    deg: [f64; 4],
    k1: f64,
    k2: f64,
) -> cwsynth::families::crane::model::Linkage {
    use cwsynth::families::crane::model::{synthesize, Angles, Boom};
    let d = f64::to_radians;
    let boom = Boom::new(
        l_c,
        Angles {
            phi_min: d(deg[0]),
            gamma1: d(deg[1]),
            gamma2: d(deg[2]),
            gamma3: d(deg[3]),
        },
    )
    .unwrap();
    synthesize(&boom, k1, k2).unwrap().linkage
}

/// The Tukan 40T geometry the optimiser finds (results/crane-tukan-40t-optimise.json).
pub fn tukan_linkage() -> cwsynth::families::crane::model::Linkage {
    crane_linkage(
        24.077272214917357,
        [45.0, 10.754095, 5.0, 25.0],
        0.26742325077812024,
        0.41627966970417185,
    )
}

/// The Tukan 40T masses of the shipped scenes (assumed there), jib centroid at 0.29 of DC.
pub const TUKAN_MASSES: cwsynth::families::crane::statics::SelfWeight =
    cwsynth::families::crane::statics::SelfWeight {
        boom_mass: 22e3,
        boom_centroid: 0.45,
        jib_mass: 9e3,
        jib_centroid: 0.29,
        tie_mass: 3.5e3,
    };

/// The Tukan scene with masses `w` and the 40 t load, with the shipped counterweight's limits
/// (at most 80 t, 6 m behind the foot within ±30°) when `cw`, no inclined rope.
pub fn tukan_scene(
    w: cwsynth::families::crane::statics::SelfWeight,
    cw: bool,
) -> cwsynth::families::crane::balance::BalanceScene {
    use cwsynth::families::crane::balance::{BalanceScene, CounterweightSpec};
    BalanceScene {
        self_weight: w,
        jib_centroid: Some(w.jib_centroid),
        counterweight: cw.then_some(CounterweightSpec {
            max_mass: 80e3,
            lever: 6.0,
            directions: Some((150f64.to_radians(), 210f64.to_radians())),
            kind: cwsynth::families::crane::balance::CounterweightKind::Boom,
        }),
        load_mass: Some(40e3),
        rope: None,
        masses: true,
    }
}
