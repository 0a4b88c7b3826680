//! What a batch solves, in input order: its inputs (problem files, directories, fleets
//! `TEMPLATE.toml:FLEET.csv`) streamed as numbered pieces of [`Work`], one per machine. A
//! fleet that cannot be opened still yields one error row per data line (rows in = rows
//! out); the fleet's own reading (units, line numbers, rows) is in [`super::fleet`].

use super::error::BatchError;
use super::fleet::{csv_reader, swallowed_lines, FleetFile, Lines, Template};
use crate::report::truncate;
use std::path::PathBuf;
use std::sync::Arc;

/// One batch input.
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    /// A problem file.
    File(PathBuf),
    /// A template and a fleet CSV.
    Fleet {
        /// The template problem file.
        template: PathBuf,
        /// The CSV of overrides, one row per machine.
        csv: PathBuf,
    },
}

impl Input {
    /// Parses `FILE`, `DIR` (expanded later) or `TEMPLATE.toml:FLEET.csv`.
    pub fn parse(s: &str) -> Input {
        if let Some(i) = s.find(".toml:") {
            let (t, c) = (&s[..i + 5], &s[i + 6..]);
            if !c.is_empty() {
                return Input::Fleet {
                    template: t.into(),
                    csv: c.into(),
                };
            }
        }
        Input::File(s.into())
    }
}

/// Expands directories into their `*.toml` files (sorted), keeps files as given. A path
/// that does not exist, or a directory without a problem file, is a usage error (exit 2).
pub fn expand_inputs(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, BatchError> {
    let mut out = Vec::new();
    for p in inputs {
        if !p.exists() {
            return Err(BatchError::NoSuchInput(p.clone()));
        }
        if p.is_dir() {
            let mut v: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| BatchError::io("cannot list", p, e))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|q| q.extension().is_some_and(|x| x == "toml"))
                .collect();
            v.sort();
            if v.is_empty() {
                return Err(BatchError::NoProblemFiles(p.clone()));
            }
            out.extend(v);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

/// The inputs of `cwsynth batch`: each argument parsed by [`Input::parse`], a directory
/// expanded into its problem files ([`expand_inputs`]).
pub fn expand(args: &[String]) -> Result<Vec<Input>, BatchError> {
    let mut out = Vec::new();
    for a in args {
        match Input::parse(a) {
            Input::File(p) if p.is_dir() => {
                for f in expand_inputs(&[p])? {
                    out.push(Input::File(f));
                }
            }
            i => out.push(i),
        }
    }
    Ok(out)
}

/// Parses `--shard i/n` (0 ≤ i < n), or `--shard auto`: the array index of the job
/// scheduler that started this process ([`shard_from_env`]).
pub fn parse_shard(s: &str) -> Result<(u64, u64), BatchError> {
    if s.trim() == "auto" {
        return shard_from_env(|k| std::env::var(k).ok());
    }
    let (a, b) = s
        .split_once('/')
        .ok_or_else(|| BatchError::ShardSyntax("expected i/n, e.g. 0/4".into()))?;
    let number = |x: &str, which: &str| {
        x.trim()
            .parse::<u64>()
            .map_err(|e| BatchError::ShardSyntax(format!("{which} is not a number: {e}")))
    };
    let (i, n) = (number(a, "i")?, number(b, "n")?);
    if n == 0 || i >= n {
        return Err(BatchError::ShardRange(s.into()));
    }
    Ok((i, n))
}

/// `--shard auto`: (i, n) from a job array's environment, read through `var`:
/// * Slurm job arrays (`sbatch --array=0-15`): i = `SLURM_ARRAY_TASK_ID` −
///   `SLURM_ARRAY_TASK_MIN`, n = `SLURM_ARRAY_TASK_COUNT` (the array must be contiguous with
///   step 1: max − min + 1 = count);
/// * Kubernetes Indexed Jobs (`completionMode: Indexed`): i = `JOB_COMPLETION_INDEX`, n =
///   `CWSYNTH_SHARDS` (set it to the job's `completions`; Kubernetes does not pass that);
/// * anything else: `CWSYNTH_SHARD_INDEX` and `CWSYNTH_SHARDS`.
///
/// An error says which variables were looked for.
pub fn shard_from_env(var: impl Fn(&str) -> Option<String>) -> Result<(u64, u64), BatchError> {
    let num = |k: &str| -> Result<Option<u64>, BatchError> {
        match var(k) {
            None => Ok(None),
            Some(v) => v.trim().parse::<u64>().map(Some).map_err(|e| {
                BatchError::ShardSyntax(format!("auto: {k} = `{v}` is not a number: {e}"))
            }),
        }
    };
    let checked = |i: u64, n: u64, from: &str| {
        if n == 0 || i >= n {
            Err(BatchError::ShardRange(format!("{i}/{n} (from {from})")))
        } else {
            Ok((i, n))
        }
    };
    if let Some(id) = num("SLURM_ARRAY_TASK_ID")? {
        let min = num("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let count = num("SLURM_ARRAY_TASK_COUNT")?.ok_or_else(|| {
            BatchError::ShardSyntax(
                "auto: SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not".into(),
            )
        })?;
        if let Some(max) = num("SLURM_ARRAY_TASK_MAX")? {
            if max < min || max - min + 1 != count {
                return Err(BatchError::ShardSyntax(format!(
                    "auto: the Slurm array {min}-{max} has {count} tasks: it must be contiguous with step 1 (e.g. --array=0-{})",
                    count.saturating_sub(1)
                )));
            }
        }
        let i = id.checked_sub(min).ok_or_else(|| {
            BatchError::ShardSyntax(format!(
                "auto: SLURM_ARRAY_TASK_ID {id} is below SLURM_ARRAY_TASK_MIN {min}"
            ))
        })?;
        return checked(i, count, "SLURM_ARRAY_TASK_ID");
    }
    let index = match num("JOB_COMPLETION_INDEX")? {
        Some(i) => Some((i, "JOB_COMPLETION_INDEX")),
        None => num("CWSYNTH_SHARD_INDEX")?.map(|i| (i, "CWSYNTH_SHARD_INDEX")),
    };
    match (index, num("CWSYNTH_SHARDS")?) {
        (Some((i, from)), Some(n)) => checked(i, n, from),
        (Some((_, from)), None) => Err(BatchError::ShardSyntax(format!(
            "auto: {from} is set but CWSYNTH_SHARDS (the number of shards) is not; set it to the job's completions"
        ))),
        (None, _) => Err(BatchError::ShardSyntax(
            "auto: no job-array index in the environment (looked for SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX, CWSYNTH_SHARD_INDEX)".into(),
        )),
    }
}

/// What a worker gets: where the machine's text comes from.
pub(super) enum Work {
    /// A problem file of the input (in this shard or not).
    Path(PathBuf),
    /// A problem file of this shard and its text (read once, in input order, when the job is
    /// made), or why it could not be read.
    File {
        path: PathBuf,
        text: Result<String, String>,
    },
    /// A fleet row: its template, its number (1-based, counting data rows), its CSV line and
    /// its cells.
    Row {
        tpl: Arc<Template>,
        row: u64,
        line: u64,
        cells: Vec<String>,
    },
    /// The CSV itself could not be read at this point.
    Broken { name: String, message: String },
}

impl Work {
    /// Reads a file's text (other work is returned as it is).
    pub(super) fn read(self) -> Work {
        match self {
            Work::Path(path) => {
                let text = crate::problem::read_bounded(&path, crate::problem::MAX_FILE_BYTES)
                    .map_err(|e| format!("{}: cannot read: {e}", path.display()))
                    .and_then(|b| {
                        crate::problem::text_of(&b, &path)
                            .map(str::to_string)
                            .map_err(|e| e.to_string())
                    });
                Work::File { path, text }
            }
            w => w,
        }
    }

    /// The machine's name as far as it is known before solving (a file's `name` key, a
    /// row's name), which names its result files.
    pub(super) fn name(&self) -> Option<String> {
        match self {
            Work::File { text, .. } => {
                let t: toml::Table = toml::from_str(text.as_ref().ok()?).ok()?;
                t.get("name")?.as_str().map(str::to_string)
            }
            Work::Row {
                tpl, row, cells, ..
            } => Some(tpl.row_name(*row, cells)),
            Work::Path(_) | Work::Broken { .. } => None,
        }
    }

    /// The machine's name and source for its row before it is read: a file's stem, a row's
    /// name (the row of a machine that panicked).
    pub(super) fn label(&self) -> (String, String) {
        match self {
            Work::Path(path) | Work::File { path, .. } => (
                path.file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                path.display().to_string(),
            ),
            Work::Row {
                tpl,
                row,
                line,
                cells,
            } => (tpl.row_name(*row, cells), tpl.source(*line)),
            Work::Broken { name, .. } => (name.clone(), String::new()),
        }
    }

    pub(super) fn source(&self) -> String {
        match self {
            Work::Path(path) | Work::File { path, .. } => path.display().to_string(),
            Work::Row { tpl, line, .. } => tpl.source(*line),
            Work::Broken { .. } => String::new(),
        }
    }
}

/// Streams every machine of the inputs in order, as `(index, work)`.
pub(super) struct Jobs {
    inputs: std::vec::IntoIter<Input>,
    fleet: Option<(
        Arc<Template>,
        csv::StringRecordsIntoIter<FleetFile>,
        u64,
        Lines,
    )>,
    next: u64,
    /// Error rows still to emit for the lines an unterminated quote swallowed.
    swallowed: std::collections::VecDeque<Work>,
    /// A fleet whose template or header is broken: each of its rows is an error row.
    dead: Option<DeadFleet>,
}

/// A fleet that cannot be read (broken template or header): its rows are still streamed,
/// each an error row with the reason, so rows in = rows out.
struct DeadFleet {
    recs: csv::StringRecordsIntoIter<FleetFile>,
    lines: Lines,
    csv: PathBuf,
    /// The name stem of its rows (the CSV's file stem): `<stem>-<row>`.
    stem: String,
    reason: String,
    row: u64,
}

impl Jobs {
    pub(super) fn new(inputs: Vec<Input>) -> Jobs {
        Jobs {
            inputs: inputs.into_iter(),
            fleet: None,
            next: 0,
            swallowed: Default::default(),
            dead: None,
        }
    }
}

impl Iterator for Jobs {
    type Item = (u64, Work);
    fn next(&mut self) -> Option<(u64, Work)> {
        loop {
            if let Some(w) = self.swallowed.pop_front() {
                let i = self.next;
                self.next += 1;
                return Some((i, w));
            }
            if let Some(d) = &mut self.dead {
                match d.recs.next() {
                    Some(rec) => {
                        d.row += 1;
                        let line = rec
                            .ok()
                            .and_then(|r| r.position().map(|p| d.lines.record_line(p.byte())))
                            .unwrap_or(d.row + 1);
                        let i = self.next;
                        self.next += 1;
                        let message = format!(
                            "{}:{line}: this row was not read: {}",
                            d.csv.display(),
                            truncate(&d.reason, 500)
                        );
                        let name = format!("{}-{}", d.stem, d.row);
                        return Some((i, Work::Broken { name, message }));
                    }
                    None => {
                        let d = self.dead.take().expect("matched");
                        if d.row == 0 {
                            // No data rows: the reason is one row.
                            let i = self.next;
                            self.next += 1;
                            let w = Work::Broken {
                                name: d.stem,
                                message: d.reason,
                            };
                            return Some((i, w));
                        }
                    }
                }
            }
            if let Some((tpl, recs, row, lines)) = &mut self.fleet {
                match recs.next() {
                    Some(rec) => {
                        *row += 1;
                        let i = self.next;
                        self.next += 1;
                        let w = match rec {
                            Ok(r) => {
                                let line = r
                                    .position()
                                    .map(|p| lines.record_line(p.byte()))
                                    .unwrap_or(*row + 1);
                                match swallowed_lines(&r) {
                                    0 => Work::Row {
                                        tpl: tpl.clone(),
                                        row: *row,
                                        line,
                                        cells: r.iter().map(str::to_string).collect(),
                                    },
                                    extra => {
                                        let csv = tpl.csv.display();
                                        for k in 1..=extra {
                                            *row += 1;
                                            self.swallowed.push_back(Work::Broken {
                                                name: format!("{}-{}", tpl.name, row),
                                                message: format!(
                                                    "{csv}:{}: this line is inside the quoted cell opened on line {line} (an unterminated `\"`); it was not read",
                                                    line + k
                                                ),
                                            });
                                        }
                                        Work::Broken {
                                            name: format!("{}-{}", tpl.name, *row - extra),
                                            message: format!(
                                                "{csv}:{line}: a `\"` opens a quoted cell that is never closed on its line: it runs over lines {line}–{}, so those {} rows are lost; close the quote",
                                                line + extra,
                                                extra + 1
                                            ),
                                        }
                                    }
                                }
                            }
                            Err(e) => Work::Broken {
                                name: format!("{}-{}", tpl.name, row),
                                message: match e.position() {
                                    Some(p) => {
                                        let line = lines.record_line(p.byte());
                                        format!("{}: {e}", tpl.source(line))
                                    }
                                    None => format!("{}: {e}", tpl.csv.display()),
                                },
                            },
                        };
                        return Some((i, w));
                    }
                    None => self.fleet = None,
                }
            }
            let input = self.inputs.next()?;
            match input {
                Input::File(p) => {
                    let i = self.next;
                    self.next += 1;
                    return Some((i, Work::Path(p)));
                }
                Input::Fleet { template, csv } => {
                    let opened = Template::open(&template, &csv)
                        .and_then(|t| Ok((t, csv_reader(&csv)?, Lines::open(&csv)?)));
                    match opened {
                        Ok((t, rdr, lines)) => {
                            self.fleet = Some((Arc::new(t), rdr.into_records(), 0, lines));
                        }
                        Err(e) => {
                            let stem = csv
                                .file_stem()
                                .map(|s| s.to_string_lossy().into_owned())
                                .unwrap_or_default();
                            let reason = e.to_string();
                            // Every data row is reported (rows in = rows out); a fleet that
                            // cannot be opened, or has no rows, is one error row.
                            let rows = csv_reader(&csv)
                                .ok()
                                .and_then(|r| Some((r.into_records(), Lines::open(&csv).ok()?)));
                            match rows {
                                Some((recs, lines)) => {
                                    self.dead = Some(DeadFleet {
                                        recs,
                                        lines,
                                        csv,
                                        stem,
                                        reason,
                                        row: 0,
                                    });
                                }
                                None => {
                                    let i = self.next;
                                    self.next += 1;
                                    let w = Work::Broken {
                                        name: stem,
                                        message: reason,
                                    };
                                    return Some((i, w));
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Counts the machines of the inputs (a streaming pass over each CSV) for the progress bar.
pub(super) fn count_machines(inputs: &[Input]) -> u64 {
    inputs
        .iter()
        .map(|i| match i {
            Input::File(_) => 1,
            Input::Fleet { csv, .. } => csv_reader(csv)
                .map(|r| {
                    r.into_records()
                        .map(|rec| 1 + rec.map_or(0, |r| swallowed_lines(&r)))
                        .sum::<u64>()
                })
                .unwrap_or(1),
        })
        .sum()
}
