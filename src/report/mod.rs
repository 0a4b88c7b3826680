//! The result of one scene: the JSON object of `cwsynth solve --json` (schema in
//! `docs/results.md`), its Markdown summary and its HTML page (`page`), and atomic writing
//! of result files.
//!
//! Every number is SI and its key carries the unit as a suffix (`_n`, `_nm`, `_kgm`, `_m`,
//! `_rad`, `_kg`, `_s`, `_pct`); pure numbers have no suffix.

pub mod drawing;
pub mod drive;
pub mod envelope;
pub mod motion;
pub mod numbers;
pub mod page;
pub mod plot;

pub use numbers::number_map;

use serde::Serialize;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Result status: one vocabulary for every family, each a claim the result can back
/// (`docs/results.md`, "Statuses").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Certified optimum: a convex problem solved to its tolerance (clarabel's duality gap,
    /// the exchange loop's refined peak), or a search whose bound is proven (a 1-D problem
    /// bracketed and converged, a lower bound within the stated error). `errors` bounds the
    /// distance of every objective from the true optimum.
    Optimal,
    /// A heuristic global search (multistart, Halton + local) found this design; nothing proves
    /// it is the global optimum. The evidence is in `search` (starts, distinct basins,
    /// evaluations, the spread of the best few); `errors` covers evaluation of this design only.
    BestFound,
    /// The problem is meaningless as posed: the objective does not depend on a free variable,
    /// or the optimum sits on a bound that turns the machine into another one.
    /// `status_detail` says which; the numbers are those of the given or bounding design.
    Degenerate,
    /// Nothing free: the given design was analysed.
    Analysed,
    /// Stopped with a larger error than requested; `errors` says how large.
    Inaccurate,
    /// The constraints cannot be met.
    Infeasible,
    /// The solve failed; `warnings` says why.
    Failed,
}

impl Status {
    /// The JSON / summary spelling (`optimal`, `best_found`, …).
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Optimal => "optimal",
            Status::BestFound => "best_found",
            Status::Degenerate => "degenerate",
            Status::Analysed => "analysed",
            Status::Inaccurate => "inaccurate",
            Status::Infeasible => "infeasible",
            Status::Failed => "failed",
        }
    }

    /// What the status promises, one line (reports, `docs/results.md`).
    pub fn promise(self) -> &'static str {
        match self {
            Status::Optimal => "certified optimum: the true optimum is within the stated error",
            Status::BestFound => {
                "best design found, not proven optimal: the search evidence or the status detail says what was done"
            }
            Status::Degenerate => {
                "the problem is degenerate as posed (see the detail); the numbers optimise nothing"
            }
            Status::Analysed => "nothing free: the given design, evaluated to the stated error",
            Status::Inaccurate => "stopped short of the requested accuracy; the stated error says how far",
            Status::Infeasible => {
                "no design within the bounds meets the limits; `infeasibility` says how far off each is, and the design shown is the closest"
            }
            Status::Failed => "the solve failed; the warnings say why",
        }
    }

    /// What the result's design is, in a label (plots, the terminal summary): the
    /// `optimum` only where the status claims one.
    pub fn design_label(self) -> &'static str {
        match self {
            Status::Optimal => "optimum",
            Status::BestFound => "best found",
            Status::Analysed => "given design",
            Status::Infeasible => "closest design",
            Status::Degenerate | Status::Inaccurate | Status::Failed => "design",
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The evidence of a `best_found` result (defined with the searches that produce it).
pub use crate::synth::{ActiveBound, BoundSide, SearchEvidence, Shortfall};

/// A paper's printed value against the program's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PaperCheck {
    /// What the number is.
    pub quantity: String,
    /// The result key compared with.
    pub key: String,
    /// The paper's value (SI).
    pub paper: f64,
    /// The program's value (SI), if the key exists.
    pub computed: Option<f64>,
    /// (computed − paper)/|paper| in %.
    pub diff_pct: Option<f64>,
    /// How to read it.
    pub note: String,
}

impl PaperCheck {
    /// A paper's printed value `paper` against the program's `computed` (key `key`), with
    /// the relative difference (none against a printed 0).
    pub fn new(
        quantity: impl Into<String>,
        key: impl Into<String>,
        paper: f64,
        computed: f64,
        note: impl Into<String>,
    ) -> PaperCheck {
        PaperCheck {
            quantity: quantity.into(),
            key: key.into(),
            paper,
            computed: Some(computed),
            diff_pct: (paper != 0.0).then(|| 100.0 * (computed - paper) / paper.abs()),
            note: note.into(),
        }
    }
}

/// Wall-clock times (s): the only fields that differ between identical runs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct Timing {
    /// The family's solve.
    pub solve_s: f64,
    /// Solve plus evaluation, baselines and report data.
    pub total_s: f64,
}

/// One SVG plot of a result, drawn only when it is written: solving computes numbers, and a
/// result that is only printed or summarised (`solve --json`, `batch --summary-only`,
/// `study`) samples and draws nothing. A plot of x–y panels ([`Plot::of_panels`]) also gives
/// its data apart from its SVG ([`Plot::figure`]: the page of `cwsynth serve` draws it
/// itself).
#[derive(Clone)]
pub struct Plot {
    /// File name suffix: `<name>-<suffix>.svg`.
    pub suffix: String,
    /// Caption for reports.
    pub caption: String,
    /// Samples the plot's data and draws the SVG document.
    source: Source,
}

/// What a [`Plot`] makes when it is drawn.
#[derive(Clone)]
enum Source {
    /// Any SVG document (a heat map, bars, a mechanism's drawing).
    Svg(std::sync::Arc<dyn Fn() -> Result<String, plot::PlotError> + Send + Sync>),
    /// Side-by-side panels of nominal size `w`×`h` each ([`plot::panels`]).
    Panels {
        w: u32,
        h: u32,
        make: std::sync::Arc<dyn Fn() -> Result<Vec<plot::Panel>, plot::PlotError> + Send + Sync>,
    },
}

impl Plot {
    /// A plot whose SVG document `draw` makes when the plot is written.
    pub fn new(
        suffix: impl Into<String>,
        caption: impl Into<String>,
        draw: impl Fn() -> Result<String, plot::PlotError> + Send + Sync + 'static,
    ) -> Plot {
        Plot {
            suffix: suffix.into(),
            caption: caption.into(),
            source: Source::Svg(std::sync::Arc::new(draw)),
        }
    }

    /// A plot of side-by-side x–y panels, each `w`×`h` nominal pixels, that `make` samples
    /// when the plot is written or shown: its SVG is [`plot::panels`] of them.
    pub fn of_panels(
        suffix: impl Into<String>,
        caption: impl Into<String>,
        w: u32,
        h: u32,
        make: impl Fn() -> Result<Vec<plot::Panel>, plot::PlotError> + Send + Sync + 'static,
    ) -> Plot {
        Plot {
            suffix: suffix.into(),
            caption: caption.into(),
            source: Source::Panels {
                w,
                h,
                make: std::sync::Arc::new(make),
            },
        }
    }

    /// The plot's panels with their size, sampled now; `None` for a plot that is only an
    /// SVG document ([`Plot::new`]).
    pub fn figure(&self) -> Option<Result<plot::Figure, plot::PlotError>> {
        match &self.source {
            Source::Svg(_) => None,
            Source::Panels { w, h, make } => {
                Some(make().and_then(|panels| plot::Figure::new(panels, *w, *h)))
            }
        }
    }

    /// The SVG document, drawn now.
    pub fn svg(&self) -> Result<String, plot::PlotError> {
        match &self.source {
            Source::Svg(draw) => draw(),
            Source::Panels { w, h, make } => plot::Figure::new(make()?, *w, *h)?.svg(),
        }
    }

    /// The SVG document, or, if it cannot be drawn, a small SVG that says why (a report's
    /// image link never breaks; a plot that cannot be drawn is a bug to report).
    pub fn svg_or_note(&self) -> String {
        self.svg().unwrap_or_else(|e| plot_note(&e))
    }
}

/// A small SVG document that says why a plot was not drawn.
pub fn plot_note(e: &plot::PlotError) -> String {
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"40\"><text x=\"8\" y=\"24\">plot not drawn: {}</text></svg>\n",
        html_escape(&e.to_string())
    )
}

impl std::fmt::Debug for Plot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Plot")
            .field("suffix", &self.suffix)
            .field("caption", &self.caption)
            .finish_non_exhaustive()
    }
}

impl PartialEq for Plot {
    /// Plots are equal when they would be written to the same file with the same caption.
    fn eq(&self, other: &Plot) -> bool {
        self.suffix == other.suffix && self.caption == other.caption
    }
}

/// The label of the [`Deferred`] work that makes a result's tables, plots and drawings.
pub const DOCUMENTS: &str = "documents";
/// The label of the [`Deferred`] work that runs the analyses only a result's files carry (a
/// diagnostic grid) and adds their sections, tables and plots.
pub const ANALYSES: &str = "analyses";

/// Work on a result that only its files need (its documents, a diagnostic grid): run by
/// [`SolveResult::complete`] when the result is written, never for a result that is only
/// printed or summarised (`solve --json`, `batch --summary-only`, `study`). It may add
/// `extra` sections, tables and plots.
#[derive(Clone)]
pub struct Deferred {
    /// What it adds, for debugging and equality.
    pub label: String,
    fill: std::sync::Arc<dyn Fn(&mut SolveResult) + Send + Sync>,
}

impl Deferred {
    /// Deferred work `fill`, labelled `label`.
    pub fn new(
        label: impl Into<String>,
        fill: impl Fn(&mut SolveResult) + Send + Sync + 'static,
    ) -> Deferred {
        Deferred {
            label: label.into(),
            fill: std::sync::Arc::new(fill),
        }
    }
}

impl std::fmt::Debug for Deferred {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Deferred")
            .field("label", &self.label)
            .finish_non_exhaustive()
    }
}

impl PartialEq for Deferred {
    fn eq(&self, other: &Deferred) -> bool {
        self.label == other.label
    }
}

/// A data table of a result, written as `<name>-<suffix>.csv` beside the JSON (a landscape
/// grid, a zero curve, a Pareto front).
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// File name suffix: `<name>-<suffix>.csv`.
    pub suffix: String,
    /// Caption for reports.
    pub caption: String,
    /// The CSV text, header line first.
    pub csv: String,
}

impl Table {
    /// The table of JSON objects `rows`: their keys the columns in first-seen order, a
    /// string as is, a number as JSON writes it, a key a row lacks (or null) empty.
    pub fn of_rows(suffix: &str, caption: &str, rows: &[serde_json::Value]) -> Table {
        let mut cols: Vec<&str> = Vec::new();
        for row in rows.iter().filter_map(|x| x.as_object()) {
            for k in row.keys() {
                if !cols.contains(&k.as_str()) {
                    cols.push(k);
                }
            }
        }
        let mut csv = cols.join(",") + "\n";
        for row in rows {
            let cells: Vec<String> = cols
                .iter()
                .map(|k| match row.get(*k) {
                    Some(serde_json::Value::String(s)) => s.clone(),
                    Some(serde_json::Value::Null) | None => String::new(),
                    Some(v) => v.to_string(),
                })
                .collect();
            csv += &(cells.join(",") + "\n");
        }
        Table {
            suffix: suffix.into(),
            caption: caption.into(),
            csv,
        }
    }
}

/// The result of one scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolveResult {
    /// Scene name.
    pub name: String,
    /// Family.
    pub family: String,
    /// Status.
    pub status: Status,
    /// The family's own, finer status where it has one (e.g. `branch-defect`), else absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub status_detail: Option<String>,
    /// With `best_found`: what the heuristic search did (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search: Option<SearchEvidence>,
    /// The problem file's `description` (absent when empty).
    #[serde(skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// Problem file.
    pub source: String,
    /// The model fidelity actually used (kinematics, masses, …).
    pub model: BTreeMap<String, serde_json::Value>,
    /// Design variables (SI, unit suffix).
    pub design: BTreeMap<String, f64>,
    /// Design variables the optimum left on a bound, with the problem-file key that sets it
    /// and what that means for the machine (absent when none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub bounds: Vec<ActiveBound>,
    /// With `infeasible`: each limit no design meets and the least value of its quantity that
    /// any design within the bounds reaches (absent otherwise).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub infeasibility: Vec<Shortfall>,
    /// The key of `objectives` that the scene optimised, where it is one of them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub objective: Option<String>,
    /// Objective values of the design (SI, unit suffix).
    pub objectives: BTreeMap<String, f64>,
    /// Estimated absolute error of each objective (same keys and units).
    pub errors: BTreeMap<String, f64>,
    /// Other computed figures.
    pub derived: BTreeMap<String, f64>,
    /// Classical designs evaluated the same way, by name.
    pub baselines: BTreeMap<String, BTreeMap<String, f64>>,
    /// The paper's numbers against ours.
    pub paper: Vec<PaperCheck>,
    /// Warnings (model limits, paper inconsistencies, solver notes).
    pub warnings: Vec<String>,
    /// Solver and evaluation count.
    pub method: String,
    /// Wall-clock times.
    pub timing: Timing,
    /// Family-specific sections (`pareto`, `zero_curve`, `coefficients`, `poles`, …).
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
    /// Plots (not in the JSON; written beside it).
    #[serde(skip)]
    pub plots: Vec<Plot>,
    /// CSV tables (not in the JSON; written beside it).
    #[serde(skip)]
    pub tables: Vec<Table>,
    /// Dimensioned drawings of the design (not in the JSON; written beside it as
    /// `<name>-<suffix>.dxf` and `.svg`, linked from the report's design section).
    #[serde(skip)]
    pub drawings: Vec<drawing::Sheet>,
    /// Work only the written files need, done by [`SolveResult::complete`].
    #[serde(skip)]
    pub deferred: Vec<Deferred>,
    /// The mechanism over one turn for the designer (`cwsynth serve`): the family's frames
    /// and the handles a user drags (not in the JSON; made with the documents, by the
    /// families that have one).
    #[serde(skip)]
    pub motion: Option<serde_json::Value>,
    /// The units of the report (`--units`; not in the JSON, which is SI).
    #[serde(skip)]
    pub units: Units,
}

impl SolveResult {
    /// Sets the four number maps from a family's typed sections (`#[derive(Serialize)]`
    /// structs whose fields are the keys, through [`number_map`]): the design, the objectives,
    /// their errors and the derived figures.
    pub fn set_figures<D, O, E, X>(&mut self, design: &D, objectives: &O, errors: &E, derived: &X)
    where
        D: serde::Serialize + ?Sized,
        O: serde::Serialize + ?Sized,
        E: serde::Serialize + ?Sized,
        X: serde::Serialize + ?Sized,
    {
        self.design = number_map(design);
        self.objectives = number_map(objectives);
        self.errors = number_map(errors);
        self.derived = number_map(derived);
    }

    /// An empty result of a scene (its name, family, description and source file) with
    /// status `failed`, to be filled by its family.
    pub fn new(
        name: &str,
        family: &str,
        description: &str,
        source: &std::path::Path,
    ) -> SolveResult {
        SolveResult {
            name: name.into(),
            family: family.into(),
            status: Status::Failed,
            status_detail: None,
            search: None,
            description: description.into(),
            source: source.display().to_string(),
            model: BTreeMap::new(),
            design: BTreeMap::new(),
            bounds: Vec::new(),
            infeasibility: Vec::new(),
            objective: None,
            objectives: BTreeMap::new(),
            errors: BTreeMap::new(),
            derived: BTreeMap::new(),
            baselines: BTreeMap::new(),
            paper: Vec::new(),
            warnings: Vec::new(),
            method: String::new(),
            timing: Timing::default(),
            extra: serde_json::Map::new(),
            plots: Vec::new(),
            tables: Vec::new(),
            drawings: Vec::new(),
            deferred: Vec::new(),
            motion: None,
            units: Units::default(),
        }
    }

    /// Does the [`Deferred`] work (once), in order: what a result's files carry beyond its
    /// numbers — its tables, plots and drawings ([`DOCUMENTS`]) and the analyses only the
    /// files need ([`ANALYSES`]). Writers call it before they write; [`write_outputs`] does.
    pub fn complete(&mut self) {
        for d in std::mem::take(&mut self.deferred) {
            (d.fill)(self);
        }
    }

    /// Makes the result's tables, plots and drawings ([`DOCUMENTS`]) without the analyses
    /// only written files carry (those stay deferred for [`SolveResult::complete`]).
    pub fn draw(&mut self) {
        let (now, later): (Vec<Deferred>, Vec<Deferred>) = std::mem::take(&mut self.deferred)
            .into_iter()
            .partition(|d| d.label == DOCUMENTS);
        self.deferred = later;
        for d in now {
            (d.fill)(self);
        }
    }

    /// The JSON value.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).expect("results are plain data")
    }

    /// Looks up a dotted key (`baselines.none.peak_shaking_force_n`) as a number: directly
    /// in the number maps (`design`, `objectives`, `errors`, `derived`, `baselines.NAME`),
    /// through the JSON value for any other key.
    pub fn lookup(&self, key: &str) -> Option<f64> {
        // (A non-finite number is null in the JSON, so not a number there either.)
        let direct =
            |m: &BTreeMap<String, f64>, k: &str| m.get(k).copied().filter(|v| v.is_finite());
        match key.split_once('.') {
            Some(("design", k)) => direct(&self.design, k),
            Some(("objectives", k)) => direct(&self.objectives, k),
            Some(("errors", k)) => direct(&self.errors, k),
            Some(("derived", k)) => direct(&self.derived, k),
            Some(("baselines", k)) => {
                let (name, k) = k.split_once('.')?;
                direct(self.baselines.get(name)?, k)
            }
            _ => lookup_json(&self.to_json(), key),
        }
    }

    /// Appends to `paper` the scene file's `[[paper]]` references, looked up in this result
    /// (a family may already have put its own checks there).
    pub fn compare_with_paper(&mut self, refs: &[crate::problem::PaperRef]) {
        let from_file: Vec<PaperCheck> = refs
            .iter()
            .map(|r| {
                let computed = self.lookup(&r.key);
                PaperCheck {
                    quantity: r.quantity.clone(),
                    key: r.key.clone(),
                    paper: r.value,
                    computed,
                    diff_pct: computed.map(|c| 100.0 * (c - r.value) / r.value.abs().max(1e-300)),
                    note: if computed.is_some() {
                        r.note.clone()
                    } else {
                        format!("no such result key; {}", r.note)
                    },
                }
            })
            .collect();
        self.paper.extend(from_file);
    }
}

/// The number at a dotted key (`baselines.none.peak_shaking_force_n`, `coefficients.a.4`).
fn lookup_json(v: &serde_json::Value, key: &str) -> Option<f64> {
    let mut v = v;
    for part in key.split('.') {
        v = match v {
            serde_json::Value::Object(m) => m.get(part)?,
            serde_json::Value::Array(a) => a.get(part.parse::<usize>().ok()?)?,
            _ => return None,
        };
    }
    v.as_f64()
}

/// Writes `bytes` to `path` atomically: a temporary file in the same directory, synced,
/// then renamed over the target, so a reader never sees a half-written file. An error names
/// the file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_via_tmp(path, bytes, true)
}

/// [`write_atomic`] without the sync: the rename still makes the file appear whole to every
/// reader, but after a power loss it may be missing or torn. For files whose wholeness is
/// checked later (a batch's per-machine files, listed with their sizes and hashes in the
/// machine's JSON, made durable at once at the end of the run: `docs/batch.md`).
pub fn write_replace(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_via_tmp(path, bytes, false)
}

/// The temporary file of [`write_atomic`] for `path`: `.<name>.<pid>.tmp` beside it.
pub fn tmp_path(path: &Path) -> PathBuf {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    dir.join(format!(".{name}.{}.tmp", std::process::id()))
}

fn write_via_tmp(path: &Path, bytes: &[u8], sync: bool) -> std::io::Result<()> {
    write_stream_via_tmp(path, sync, |f| f.write_all(bytes))
}

/// [`write_atomic`] for a file written piece by piece (a table of a million rows is not held
/// in memory): `write` fills a buffered temporary file, which is synced and renamed over
/// `path` only when `write` succeeded.
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    write_stream_via_tmp(path, true, |f| {
        let mut b = std::io::BufWriter::new(f);
        write(&mut b)?;
        b.flush()
    })
}

fn write_stream_via_tmp(
    path: &Path,
    sync: bool,
    write: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let at = |e: std::io::Error, p: &Path| {
        std::io::Error::new(e.kind(), format!("{}: {e}", p.display()))
    };
    let tmp = tmp_path(path);
    if let Some(dir) = tmp.parent() {
        std::fs::create_dir_all(dir).map_err(|e| at(e, dir))?;
    }
    let res = (|| {
        let mut f = std::fs::File::create(&tmp).map_err(|e| at(e, &tmp))?;
        write(&mut f).map_err(|e| at(e, &tmp))?;
        if sync {
            f.sync_all().map_err(|e| at(e, &tmp))?;
        }
        std::fs::rename(&tmp, path).map_err(|e| at(e, path))
    })();
    if res.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    res
}

/// Escapes text that comes from input (names, paper notes, messages) for a Markdown page:
/// HTML-significant characters become entities, Markdown markup characters are
/// backslash-escaped, and line breaks become spaces, so the text can never open a tag, a
/// link or a table cell.
pub fn md_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '\\' | '`' | '*' | '_' | '[' | ']' | '|' | '#' | '!' => {
                out.push('\\');
                out.push(c);
            }
            '\n' | '\r' | '\t' => out.push(' '),
            c if c.is_control() => {}
            c => out.push(c),
        }
    }
    out
}

/// Escapes text for HTML or SVG text and attribute values (`&`, `<`, `>`, `"`).
pub fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// At most `max` bytes of `s` (on a character boundary), with `…` and the length cut.
pub fn truncate(s: &str, max: usize) -> std::borrow::Cow<'_, str> {
    if s.len() <= max {
        return s.into();
    }
    let mut i = max;
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    format!("{}… ({} more bytes)", &s[..i], s.len() - i).into()
}

/// Formats a number for humans: 6 significant digits, exponent outside [1e-3, 1e7).
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if (1e-3..1e7).contains(&a) {
        let digits = (5 - a.log10().floor() as i32).clamp(0, 9) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.5e}")
    }
}

/// How a result key reads in a workshop: its words, the unit shown and the factor from SI
/// (`crank_counterweight_radius_m` = 0.08 → "crank counterweight radius", mm, 1000; `_m2` in
/// mm²; `_rad` in degrees, `_rad_s` in rpm, `_pa` in bar, a force of 10 kN or more in kN, a
/// power of 10 kW or more in kW). A key without a unit suffix is a
/// pure number.
pub fn workshop_unit(key: &str, v: f64) -> (String, &'static str, f64) {
    use std::f64::consts::PI;
    let table: [(&str, &str, f64); 21] = [
        ("_rad_s2", "rad/s²", 1.0),
        ("_rad_s", "rpm", 30.0 / PI),
        ("_per_m", "1/m", 1.0),
        ("_j", "J", 1.0),
        ("_w", "W", 1.0),
        ("_m_s2", "m/s²", 1.0),
        ("_m_per_s", "m/s", 1.0),
        ("_kg_m3", "kg/m³", 1.0),
        ("_kgm2", "kg·m²", 1.0),
        ("_kgm", "kg·m", 1.0),
        ("_nm", "N·m", 1.0),
        ("_n", "N", 1.0),
        ("_kg", "kg", 1.0),
        ("_rad", "°", 180.0 / PI),
        ("_pct", "%", 1.0),
        ("_rpm", "rpm", 1.0),
        ("_pa", "bar", 1e-5),
        ("_mm", "mm", 1.0),
        ("_m2", "mm²", 1e6),
        ("_m", "m", 1.0),
        ("_s", "s", 1.0),
    ];
    for (suffix, unit, f) in table {
        if let Some(stem) = key.strip_suffix(suffix) {
            let words = stem.replace('_', " ");
            return match unit {
                // Machine parts in mm, a crane's boom in m.
                "m" if v.abs() < 2.0 => (words, "mm", 1e3),
                "N" if v.abs() >= 1e4 => (words, "kN", 1e-3),
                "N·m" if v.abs() >= 1e4 => (words, "kN·m", 1e-3),
                "W" if v.abs() >= 1e4 => (words, "kW", 1e-3),
                _ => (words, unit, f),
            };
        }
    }
    (key.replace('_', " "), "–", 1.0)
}

/// The units a report is written in (`--units`): the workshop's (mm, °, rpm, kN; the
/// default) or SI as in the JSON. The JSON is always SI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Units {
    /// mm for machine lengths (m from 2 m), ° for angles, rpm for speeds, kN from 10 kN.
    #[default]
    Workshop,
    /// The JSON's SI units (m, rad, rad/s, N).
    Si,
}

/// How a result key reads in a report in `units`: its words, the unit shown and the factor
/// from SI ([`workshop_unit`], or the key's SI unit with factor 1).
pub fn display_unit(units: Units, key: &str, v: f64) -> (String, &'static str, f64) {
    let (words, unit, f) = workshop_unit(key, v);
    match units {
        Units::Workshop => (words, unit, f),
        // A key already in a non-SI unit (`_mm`, `_rpm`) reads as it is.
        Units::Si if key.ends_with("_mm") || key.ends_with("_rpm") => (words, unit, f),
        Units::Si => {
            let si = match unit {
                "mm" | "m" => "m",
                "°" => "rad",
                "rpm" if key.ends_with("_rad_s") => "rad/s",
                "kN" => "N",
                "kN·m" => "N·m",
                "kW" => "W",
                "bar" => "Pa",
                other => other,
            };
            (words, si, 1.0)
        }
    }
}

/// A value of a key with its unit as a report writes it (`50 mm`; a pure number bare).
fn value_with_unit(u: Units, key: &str, x: f64) -> String {
    let (_, unit, f) = display_unit(u, key, x);
    let shown = fmt_value(x * f);
    if unit == "–" {
        shown
    } else {
        format!("{shown} {unit}")
    }
}

/// A table column's head for a key: its words and, in parentheses, its unit (none for a
/// pure number). The column's values are in that unit: converted at the value 0.
fn column_head(u: Units, key: &str) -> String {
    let (w, unit, _) = display_unit(u, key, 0.0);
    if unit == "–" {
        w
    } else {
        format!("{w} ({unit})")
    }
}

/// [`fmt_num`], but a whole number as an integer (`32`, not `32.0000`).
fn fmt_value(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e9 {
        format!("{}", x as i64)
    } else {
        fmt_num(x)
    }
}

/// A model setting as a workshop reads it: a number in its workshop unit (from its key's
/// suffix), an object as `name value unit` pairs, a list joined by commas, text as is.
fn model_value(u: Units, key: &str, v: &serde_json::Value) -> String {
    use serde_json::Value;
    let number = |k: &str, x: f64| value_with_unit(u, k, x);
    match v {
        Value::Number(n) => n.as_f64().map_or(n.to_string(), |x| number(key, x)),
        Value::String(t) => t.clone(),
        Value::Array(a) if a.iter().all(Value::is_number) => {
            // A point or a list of one quantity: every entry in the key's unit.
            let xs: Vec<String> = a
                .iter()
                .filter_map(Value::as_f64)
                .map(|x| number(key, x))
                .collect();
            format!("({})", xs.join(", "))
        }
        Value::Array(a) => a
            .iter()
            .map(|x| x.as_str().map_or(x.to_string(), str::to_string))
            .collect::<Vec<_>>()
            .join(", "),
        Value::Object(o) => o
            .iter()
            .map(|(k, x)| {
                let (words, _, _) = workshop_unit(k, 0.0);
                format!("{words} {}", model_value(u, k, x))
            })
            .collect::<Vec<_>>()
            .join("; "),
        other => other.to_string(),
    }
}

/// Most rows of a family section's table in the report (the JSON and the CSV files have all).
const EXTRA_ROWS: usize = 40;

/// A family section of the JSON (`extra`: `checks`, `balancing`, `joints`, `pareto`, …) as
/// the report reads it, so that every figure of the JSON is readable in the report too: a
/// list of objects as a table (one column per key, numbers in their workshop units), an
/// object as name–value rows (its lists of objects as tables of their own), a scalar as one
/// line. Lists of plain numbers are summarised (their length; the values are in the JSON).
fn extra_section(u: Units, key: &str, v: &serde_json::Value) -> String {
    use serde_json::Value;
    let title = key.replace('_', " ");
    let cell = |k: &str, x: &Value| -> String {
        match x {
            Value::Number(_) | Value::Object(_) => md_escape(&model_value(u, k, x)),
            Value::Array(a) if a.iter().all(Value::is_number) && a.len() <= 4 => {
                md_escape(&model_value(u, k, x))
            }
            Value::Array(a) => format!("{} values (JSON)", a.len()),
            Value::Bool(b) => if *b { "yes" } else { "no" }.into(),
            Value::String(t) => md_escape(t),
            Value::Null => "–".into(),
        }
    };
    let table = |rows: &[Value]| -> String {
        let mut cols: Vec<String> = Vec::new();
        for r in rows.iter().take(EXTRA_ROWS) {
            if let Some(o) = r.as_object() {
                for k in o.keys() {
                    if !cols.contains(k) {
                        cols.push(k.clone());
                    }
                }
            }
        }
        let mut t = format!(
            "| {} |\n|{}\n",
            cols.iter()
                .map(|c| column_head(u, c))
                .collect::<Vec<_>>()
                .join(" | "),
            "---|".repeat(cols.len())
        );
        for r in rows.iter().take(EXTRA_ROWS) {
            let cells: Vec<String> = cols
                .iter()
                .map(|c| {
                    r.get(c).map_or("–".into(), |x| match x {
                        // In the column's unit, without repeating it in every cell.
                        Value::Number(n) => n
                            .as_f64()
                            .map_or(n.to_string(), |f| fmt_value(f * display_unit(u, c, 0.0).2)),
                        other => cell(c, other),
                    })
                })
                .collect();
            t += &format!("| {} |\n", cells.join(" | "));
        }
        if rows.len() > EXTRA_ROWS {
            t += &format!(
                "\n(first {EXTRA_ROWS} of {} rows; all in the JSON key `{key}`)\n",
                rows.len()
            );
        }
        t
    };
    let is_rows = |a: &[Value]| !a.is_empty() && a.iter().all(Value::is_object);
    match v {
        Value::Array(a) if is_rows(a) => format!("## {title}\n\n{}\n", table(a)),
        Value::Array(a) if a.is_empty() => String::new(),
        Value::Array(a) => format!(
            "## {title}\n\n{} values (in the JSON key `{key}`)\n\n",
            a.len()
        ),
        Value::Object(o) => {
            let mut out = format!("## {title}\n\n");
            let mut kv = String::new();
            let mut subs = String::new();
            for (k, x) in o {
                match x {
                    Value::Array(a) if is_rows(a) => {
                        subs += &format!("{}:\n\n{}\n", k.replace('_', " "), table(a));
                    }
                    _ => {
                        let (w, _, _) = workshop_unit(k, 0.0);
                        kv += &format!("| {w} | {} | `{k}` |\n", cell(k, x));
                    }
                }
            }
            if !kv.is_empty() {
                out += &format!("| item | value | key |\n|---|---|---|\n{kv}\n");
            }
            out + &subs
        }
        Value::Bool(b) => format!("{title}: {}\n\n", if *b { "yes" } else { "no" }),
        other => format!("{title}: {}\n\n", cell(key, other)),
    }
}

/// The Markdown summary of a result (`<name>.md`).
pub fn markdown(r: &SolveResult) -> String {
    markdown_report(r, true)
}

/// The Markdown summary of a result, with or without the wall times of its solve (the only
/// text that differs between identical runs): the head, then what to build (the design,
/// the drawings, the bounds that decide it), then the evidence (objectives, search, model,
/// derived figures, baselines, the paper, the family's sections, warnings, plots, tables).
pub(crate) fn markdown_report(r: &SolveResult, timing: bool) -> String {
    let mut s = String::new();
    md_head(&mut s, r, timing);
    // What to build first, then the evidence.
    md_line(
        &mut s,
        md_table(r, "Design: what to build", &r.design, None),
    );
    md_drawings(&mut s, r);
    md_bounds(&mut s, r);
    md_line(
        &mut s,
        md_table(r, "Objectives", &r.objectives, Some(&r.errors)),
    );
    md_search(&mut s, r);
    md_model(&mut s, r);
    md_line(&mut s, md_table(r, "Derived", &r.derived, None));
    md_baselines(&mut s, r);
    md_paper(&mut s, r);
    // The family's own sections, readable here as in the JSON.
    for (k, v) in &r.extra {
        let sec = extra_section(r.units, k, v);
        if !sec.is_empty() {
            md_line(&mut s, sec);
        }
    }
    if !r.warnings.is_empty() {
        md_line(&mut s, "## Warnings\n");
        for w in &r.warnings {
            md_line(&mut s, format!("- {}", md_escape(w)));
        }
        md_line(&mut s, "");
    }
    for pl in &r.plots {
        md_line(
            &mut s,
            format!("![{}]({}-{}.svg)\n", pl.caption, r.name, pl.suffix),
        );
    }
    for t in &r.tables {
        md_line(
            &mut s,
            format!("- [{}]({}-{}.csv)", t.caption, r.name, t.suffix),
        );
    }
    s
}

/// Appends `line` and a newline to the Markdown `s`.
fn md_line(s: &mut String, line: impl AsRef<str>) {
    s.push_str(line.as_ref());
    s.push('\n');
}

/// The report's head: title and family, description, status (and the solve's wall times
/// with `timing`), status detail and method.
fn md_head(s: &mut String, r: &SolveResult, timing: bool) {
    md_line(s, format!("# {} ({})\n", md_escape(&r.name), r.family));
    if !r.description.is_empty() {
        md_line(s, format!("{}\n", md_escape(&r.description)));
    }
    md_line(
        s,
        format!(
            "Status: **{}** ({}) · source `{}`{}\n",
            r.status.as_str(),
            r.status.promise(),
            md_escape(&r.source),
            if timing {
                format!(
                    " · solve {:.3} ms, total {:.3} ms",
                    r.timing.solve_s * 1e3,
                    r.timing.total_s * 1e3
                )
            } else {
                String::new()
            }
        ),
    );
    if let Some(d) = &r.status_detail {
        md_line(s, format!("Status detail: {}\n", md_escape(d)));
    }
    md_line(s, format!("Method: {}\n", md_escape(&r.method)));
}

/// A section of SI figures `m` as a table in the result's units (quantity, value, unit,
/// the error where `errs` is given, the SI key); empty when `m` is.
fn md_table(
    r: &SolveResult,
    title: &str,
    m: &BTreeMap<String, f64>,
    errs: Option<&BTreeMap<String, f64>>,
) -> String {
    if m.is_empty() {
        return String::new();
    }
    let mut t = format!(
        "## {title}\n\n| quantity | value | unit |{} key (SI) |\n|---|---:|---|{}---|\n",
        if errs.is_some() { " ± error |" } else { "" },
        if errs.is_some() { "---:|" } else { "" }
    );
    for (k, v) in m {
        let (words, unit, f) = display_unit(r.units, k, *v);
        let err = errs.map(|e| {
            e.get(k)
                .map(|x| format!("{:.2e}", x * f))
                .unwrap_or("–".into())
        });
        let value = fmt_value(v * f);
        t += &format!(
            "| {words} | {value} | {unit} |{} `{k}` |\n",
            err.map(|e| format!(" {e} |")).unwrap_or_default()
        );
    }
    t
}

/// Each drawing's links (SVG, DXF) and its picture.
fn md_drawings(s: &mut String, r: &SolveResult) {
    for d in &r.drawings {
        md_line(
            s,
            format!(
                "Drawing, {}: [SVG]({n}-{s}.svg) · [DXF]({n}-{s}.dxf) (mm)\n\n![{}]({n}-{s}.svg)\n",
                d.caption,
                d.caption,
                n = r.name,
                s = d.suffix
            ),
        );
    }
}

/// The design figures that sit on a bound, each with its bound, side and what set it.
fn md_bounds(s: &mut String, r: &SolveResult) {
    if r.bounds.is_empty() {
        return;
    }
    md_line(
        s,
        "On a bound (the bound, not an interior optimum, decides these):\n",
    );
    for b in &r.bounds {
        let key = b.key.rsplit('.').next().unwrap_or(&b.key);
        md_line(
            s,
            format!(
                "- **{}** = {}, on its {} bound, set by `{}`: {}",
                workshop_unit(key, 0.0).0,
                value_with_unit(r.units, key, b.value),
                match b.side {
                    BoundSide::Lower => "lower",
                    BoundSide::Upper => "upper",
                },
                b.set_by,
                md_escape(&b.meaning)
            ),
        );
    }
    md_line(s, "");
}

/// The evidence of a multistart search (a `best_found` result): method, starts, basins,
/// evaluations, the best distinct values and the gap to the second basin.
fn md_search(s: &mut String, r: &SolveResult) {
    let Some(e) = &r.search else { return };
    md_line(
        s,
        "## Search evidence (status `best_found`: not proven optimal)\n",
    );
    md_line(s, format!("- method: {}", md_escape(&e.method)));
    md_line(
        s,
        format!(
            "- {} starts, {} distinct basins, {} at the best value, {} evaluations",
            e.starts, e.distinct_basins, e.starts_at_best, e.evaluations
        ),
    );
    if !e.best_values.is_empty() {
        let v: Vec<String> = e.best_values.iter().map(|x| fmt_num(*x)).collect();
        md_line(s, format!("- best distinct values: {}", v.join(", ")));
    }
    if let Some(sp) = e.spread_rel {
        md_line(s, format!("- relative gap to the second basin: {sp:.2e}"));
    }
    md_line(s, "");
}

/// The model's settings, each in the result's units with its SI key.
fn md_model(s: &mut String, r: &SolveResult) {
    if r.model.is_empty() {
        return;
    }
    md_line(s, "## Model\n");
    md_line(s, "| setting | value | key (SI) |\n|---|---|---|");
    for (k, v) in &r.model {
        md_line(
            s,
            format!(
                "| {} | {} | `{k}` |",
                workshop_unit(k, 0.0).0,
                md_escape(&model_value(r.units, k, v))
            ),
        );
    }
    md_line(s, "");
}

/// The baselines as one table: a row per baseline, a column per key (the union of their
/// keys, sorted) in the result's units, the SI keys below.
fn md_baselines(s: &mut String, r: &SolveResult) {
    if r.baselines.is_empty() {
        return;
    }
    let keys: Vec<&String> = {
        let mut k: Vec<&String> = r.baselines.values().flat_map(|m| m.keys()).collect();
        k.sort();
        k.dedup();
        k
    };
    md_line(s, "## Baselines\n");
    // In workshop units: each column in the unit of its key (the SI key below the table).
    let head: Vec<String> = keys.iter().map(|k| column_head(r.units, k)).collect();
    md_line(s, format!("| baseline | {} |", head.join(" | ")));
    md_line(s, format!("|---|{}", "---:|".repeat(keys.len())));
    for (name, m) in &r.baselines {
        let cells: Vec<String> = keys
            .iter()
            .map(|k| {
                m.get(*k)
                    .map(|v| fmt_value(v * display_unit(r.units, k, 0.0).2))
                    .unwrap_or("–".into())
            })
            .collect();
        md_line(
            s,
            format!("| {} | {} |", name.replace('_', " "), cells.join(" | ")),
        );
    }
    md_line(
        s,
        format!(
            "\nKeys (SI, in the JSON `baselines.<name>.<key>`): {}",
            keys.iter()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    );
    md_line(s, "");
}

/// The comparison with the paper's figures: paper, computed, difference (%) and note.
fn md_paper(s: &mut String, r: &SolveResult) {
    if r.paper.is_empty() {
        return;
    }
    md_line(s, "## Against the paper\n");
    md_line(
        s,
        "| quantity | paper | cwsynth | diff | note |\n|---|---|---|---|---|",
    );
    for c in &r.paper {
        md_line(
            s,
            format!(
                "| {} ({}) | {} | {} | {} | {} |",
                md_escape(&c.quantity),
                md_escape(&c.key),
                fmt_num(c.paper),
                c.computed.map(fmt_num).unwrap_or("–".into()),
                c.diff_pct
                    .map(|d| format!("{d:+.2} %"))
                    .unwrap_or("–".into()),
                md_escape(&c.note)
            ),
        );
    }
    md_line(s, "");
}

/// The report files of a result beside its JSON: `<dir>/<name>.md`, its page
/// `<dir>/<name>.html`, every `<name>-<suffix>.svg` and `<name>-<suffix>.csv`, and each
/// drawing's `<name>-<suffix>.dxf` and `.svg`, with their contents.
pub fn report_files(r: &SolveResult, dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = vec![
        (dir.join(format!("{}.md", r.name)), markdown(r).into_bytes()),
        (
            dir.join(format!("{}.html", r.name)),
            page::result_page(r).into_bytes(),
        ),
    ];
    for pl in &r.plots {
        let path = dir.join(format!("{}-{}.svg", r.name, pl.suffix));
        files.push((path, pl.svg_or_note().into_bytes()));
    }
    for t in &r.tables {
        let path = dir.join(format!("{}-{}.csv", r.name, t.suffix));
        files.push((path, t.csv.as_bytes().to_vec()));
    }
    for d in &r.drawings {
        let (dxf, svg) = d.files();
        files.push((dir.join(format!("{}-{}.dxf", r.name, d.suffix)), dxf));
        files.push((dir.join(format!("{}-{}.svg", r.name, d.suffix)), svg));
    }
    files
}

/// The path of a result's JSON in `dir`, `<name>.json`.
pub fn json_path(r: &SolveResult, dir: &Path) -> PathBuf {
    dir.join(format!("{}.json", r.name))
}

/// The JSON file of a result, pretty-printed.
pub fn json_text(r: &SolveResult) -> String {
    serde_json::to_string_pretty(&r.to_json()).expect("plain data") + "\n"
}

/// Completes the result ([`SolveResult::complete`]) and writes `<dir>/<name>.json` and the
/// [`report_files`] (`<name>.md`, `<name>.html`, every `<name>-<suffix>.svg` and
/// `<name>-<suffix>.csv`, the drawings' `.dxf` and `.svg`), atomically.
pub fn write_outputs(r: &mut SolveResult, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    r.complete();
    let r = &*r;
    let json = json_path(r, dir);
    write_atomic(&json, json_text(r).as_bytes())?;
    let mut written = vec![json];
    for (path, bytes) in report_files(r, dir) {
        write_atomic(&path, &bytes)?;
        written.push(path);
    }
    Ok(written)
}
