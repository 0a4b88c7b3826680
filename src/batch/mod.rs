//! Batch design: many machines at once (`cwsynth batch`), with streaming fleets, rayon
//! across machines, resumable atomic output, deterministic sharding and merged reports
//! (`docs/batch.md`). This module is the run itself: inputs in, one row per machine out, each
//! machine isolated from the others; the rest is one concern per file:
//!
//! | file | concern |
//! |---|---|
//! | `inputs.rs` | the inputs (files, directories, fleets) streamed as numbered machines |
//! | `fleet.rs` | a fleet CSV: template, cells and units, real line numbers, row errors |
//! | `row.rs` | one summary row: from a result JSON or an error, formula escaping, checks; the counts |
//! | `summary.rs` | the summary CSV file: written to `.partial`, committed by a rename, read back |
//! | `resume.rs` | re-runs: the manifest of a machine's files, the skip decision, the lock |
//! | `layout.rs` | where a machine's files go: beside the summary, or `machines/NNN/` in a large run |
//! | `hash.rs` | the input hash of a machine and the hash of a written file |
//! | `isolate.rs` | one machine's panic fails that machine only |
//! | `progress.rs` | the progress bar or lines on stderr |
//! | `merge.rs` | shard summaries joined into one |
//! | `overview.rs` | what the reports show, read from the summary in one pass |
//! | `reports.rs`, `html.rs` | `summary.md` and `index.html` |
//! | `error.rs` | why a run could not run ([`BatchError`]) |
//!
//! Machines are numbered in input order (0-based `index`, across all inputs). The work is
//! streamed in chunks of [`CHUNK`] machines: each chunk is solved in parallel on a dedicated
//! rayon pool, then its summary rows are appended in input order to the summary CSV, so
//! memory is bounded by one chunk whatever the fleet size. `--shard i/n` keeps the machines
//! with `index % n == i`. The batch knows no family by name: a machine is a
//! [`crate::families::Scene`] and its result a [`crate::report::SolveResult`].

mod error;
mod fleet;
mod fleet_table;
mod hash;
mod html;
mod inputs;
mod isolate;
mod layout;
mod merge;
mod names;
mod overview;
mod progress;
mod reports;
mod resume;
mod row;
mod summary;

pub use error::BatchError;
pub use fleet::Template;
// pub for the tests in tests/unit_batch.rs
#[doc(hidden)]
pub use fleet::{csv_reader, Lines};
pub use fleet_table::{fleet_table_path, write_fleet_tables};
pub use hash::{content_hash, file_hash, problem_hash};
pub use inputs::{expand, expand_inputs, parse_shard, shard_from_env, Input};
pub use isolate::{isolate, test_panic};
pub use layout::{Layout, LARGE_RUN, MACHINES_DIR, MACHINES_PER_FOLDER};
pub use merge::merge;
#[doc(hidden)]
pub use names::first_of_repeated;
pub use overview::{REPORT_PLOTS, REPORT_ROWS};
pub use reports::write_reports;
pub use row::{
    error_row, is_failure, row_from_json, row_from_result, Counts, Row, HEADER, MESSAGE_BYTES,
    ROW_STATUSES,
};
pub use summary::summary_name;

use crate::families::{parse_str, solve_scene};
use inputs::{count_machines, Jobs, Work};
use names::Names;
use progress::Progress;
use rayon::prelude::*;
use resume::{
    complete_result, lock_out, remove_stale_tmp, sync_filesystem, write_result, Previous,
};
use row::panic_row;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use summary::SummaryWriter;

/// Machines solved per chunk (the memory bound: one chunk of summary rows).
pub const CHUNK: usize = 2048;

/// Batch options.
#[derive(Debug, Clone)]
pub struct Options {
    /// Output directory.
    pub out: PathBuf,
    /// Worker threads (default: available parallelism).
    pub threads: Option<usize>,
    /// `(i, n)`: only machines with `index % n == i`.
    pub shard: Option<(u64, u64)>,
    /// No progress output (errors are still in the summary).
    pub quiet: bool,
    /// Write only the summary (no per-machine JSON, Markdown, plots).
    pub summary_only: bool,
    /// Units of the machines' reports (their JSON is SI).
    pub units: crate::report::Units,
}

/// One machine to solve: its index, its work, and its row of the previous run, if any.
struct Job {
    index: u64,
    work: Work,
    /// The previous summary row of this index, if any (for `--summary-only` re-runs).
    old: Option<Row>,
}

/// A machine's input, before it is resolved (only if the machine is not skipped): a file's
/// text, or a fleet row (whose error is phrased for the row).
enum Ready {
    Text(String, PathBuf),
    Row {
        tpl: Arc<Template>,
        row: u64,
        line: u64,
        cells: Vec<String>,
    },
}

/// Solves (or skips) one machine; writes its files (into its folder of `layout`) unless
/// `summary_only`.
fn process(job: Job, opts: &Options, layout: Layout) -> (Row, bool) {
    let index = job.index;
    let (name, source, input) = match job.work.read() {
        Work::Path(_) => unreachable!("`read` turns a path into a file"),
        Work::File { path, text } => {
            let name = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let source = path.display().to_string();
            let input = text.map(|t| (problem_hash(&t, &path), Ready::Text(t, path)));
            (name, source, input)
        }
        Work::Row {
            tpl,
            row,
            line,
            cells,
        } => {
            let (name, source) = (tpl.row_name(row, &cells), tpl.source(line));
            let hash = tpl.input_hash(&name, &cells);
            let ready = Ready::Row {
                tpl,
                row,
                line,
                cells,
            };
            (name, source, Ok((hash, ready)))
        }
        Work::Broken { name, message } => {
            return (error_row(index, &name, "", "", message), false);
        }
    };
    let (hash, ready) = match input {
        Ok(x) => x,
        Err(m) => return (error_row(index, &name, &source, "", m), false),
    };
    if opts.summary_only {
        if let Some(old) = job.old {
            if old.input_hash == hash && old.status != "error" {
                return (old, true);
            }
        }
    }
    // A bad file's error row keeps its hash; a bad row's has none (as when it was read).
    let scene = match ready {
        Ready::Text(text, path) => parse_str(&text, &path).map_err(|e| (e.to_string(), &*hash)),
        Ready::Row {
            tpl,
            row,
            line,
            cells,
        } => tpl.scene(row, line, &cells).1.map_err(|m| (m, "")),
    };
    let scene = match scene {
        Ok(s) => s,
        Err((m, h)) => return (error_row(index, &name, &source, h, m), false),
    };
    let dir = layout.dir(&opts.out, index);
    if !opts.summary_only {
        let jp = dir.join(format!("{}.json", scene.name));
        if let Some(v) = complete_result(&jp, &hash, &dir) {
            return (row_from_json(index, &source, &hash, &v), true);
        }
    }
    test_panic(&scene.name);
    let mut r = solve_scene(&scene);
    r.units = opts.units;
    if !opts.summary_only {
        // What only the files carry (e.g. the crane's landscape grid).
        r.complete();
    }
    let batch = serde_json::json!({
        "input_hash": hash,
        "plots": r.plots.iter().map(|p| p.suffix.clone()).collect::<Vec<_>>(),
    });
    if opts.summary_only {
        // Without result files only the row is needed: its fields, not the whole JSON.
        r.extra.insert("batch".into(), batch);
        return (row_from_result(index, &source, &hash, &r), false);
    }
    // The report files first, each listed in the JSON with its size and hash; the JSON
    // last: a machine is done when its JSON and every file it lists are whole.
    let (v, written) = write_result(&mut r, batch, &dir);
    let mut row = row_from_json(index, &source, &hash, &v);
    if let Err(e) = written {
        row.status = "error".into();
        row.input_hash.clear();
        row.message = format!("writing the results: {e}");
    }
    (row, false)
}

/// The most worker threads a batch starts (`--threads` refuses more).
pub const MAX_THREADS: usize = 1024;

/// Files and bytes one machine's results take: about 7 files and 180 kB, measured on a
/// 1000-machine fleet of `problems/piston-1000rpm.toml` (7,004 files, 181 MB with the
/// summary, the fleet's table and the index; a 20,000-machine fleet of another template wrote
/// 5.9 files and 125 kB a machine).
const FILES_PER_MACHINE: u64 = 7;
/// See [`FILES_PER_MACHINE`].
const BYTES_PER_MACHINE: u64 = 180_000;

/// What a run with per-machine files will write, said before it starts when that is a lot
/// ([`LARGE_RUN`] machines or more: such a run writes its machines into folders, [`Layout`]),
/// with the way out (`--summary-only`).
pub fn size_note(machines: u64, opts: &Options) -> Option<String> {
    (!opts.summary_only && machines >= LARGE_RUN).then(|| {
        format!(
            "batch: {machines} machines with their result files: about {} files and {:.1} GB in {} (about {FILES_PER_MACHINE} files and {} kB a machine, {MACHINES_PER_FOLDER} machines a folder {MACHINES_DIR}/NNN/ by index); --summary-only writes only the summary, the fleet's table and the index",
            machines * FILES_PER_MACHINE + 3,
            (machines * BYTES_PER_MACHINE) as f64 / 1e9,
            opts.out.display(),
            BYTES_PER_MACHINE / 1000
        )
    })
}

/// Runs a batch; writes the summary (and, unsharded, `summary.md` and `index.html`).
pub fn run(inputs: Vec<Input>, opts: &Options) -> Result<Counts, BatchError> {
    std::fs::create_dir_all(&opts.out)
        .map_err(|e| BatchError::io("cannot create", &opts.out, e))?;
    let threads = opts
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    // At most MAX_THREADS: a mistyped count must not spawn thousands of threads.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.clamp(1, MAX_THREADS))
        .build()
        .map_err(BatchError::Threads)?;
    let (si, sn) = opts.shard.unwrap_or((0, 1));
    let _lock = lock_out(&opts.out, &summary_name(opts.shard))?;
    remove_stale_tmp(&opts.out);
    let all = count_machines(&inputs);
    let mine = all / sn + u64::from(all % sn > si);
    let layout = Layout::of_run(all); // of the whole batch: every shard and merge agree

    let summary = opts.out.join(summary_name(opts.shard));
    let mut previous = Previous::open(&summary)?;
    let mut w = SummaryWriter::create(&summary)?;
    let mut counts = Counts::default();
    let mut progress = Progress::new(mine, opts.quiet);
    if let Some(line) = size_note(mine, opts) {
        progress.note(&line);
    }
    let done = AtomicU64::new(0);

    let fleets: Vec<Input> = inputs
        .iter()
        .filter(|i| matches!(i, Input::Fleet { .. }))
        .cloned()
        .collect();
    // Two machines with one name would write the same result files: the first (in input
    // order) keeps the name, every later one is reported and not solved. Decided in a pass
    // before the solve, in memory that does not grow with the run, so the outcome does
    // not depend on threads.
    let mine_only = move |(i, _): &(u64, Work)| i % sn == si;
    let mut names = Names::scan(Jobs::new(inputs.clone()).filter(mine_only), mine, &opts.out)?;
    let mut jobs = Jobs::new(inputs).filter(mine_only);
    loop {
        let chunk: Vec<Job> = jobs
            .by_ref()
            .take(CHUNK)
            .map(|(index, work)| Job {
                index,
                old: previous.take(index),
                work: names.check(index, work.read()),
            })
            .collect();
        if chunk.is_empty() {
            break;
        }
        let tick = progress.ticker();
        let rows: Vec<(Row, bool)> = pool.install(|| {
            chunk
                .into_par_iter()
                .map(|j| {
                    // Whatever one machine does, the others finish (a panic is its row).
                    let (index, (name, source)) = (j.index, j.work.label());
                    let r = isolate(|| process(j, opts, layout))
                        .unwrap_or_else(|m| (panic_row(index, &name, &source, &m), false));
                    done.fetch_add(1, Ordering::Relaxed);
                    if let Some(pb) = &tick {
                        pb.inc(1);
                    }
                    r
                })
                .collect()
        });
        for (row, skipped) in rows {
            if counts.add(&row, skipped) {
                progress.error(&if row.message.is_empty() {
                    format!("{}: {}", row.name, row.status)
                } else {
                    format!("{}: {}: {}", row.name, row.status, row.message)
                });
            }
            w.write(&row)?;
        }
        w.flush()?;
        progress.update(done.load(Ordering::Relaxed), &counts, false);
    }
    progress.update(done.load(Ordering::Relaxed), &counts, true);
    progress.finish();
    if !opts.summary_only {
        // The per-machine files were written without a sync each: made durable here at once,
        // before the summary that lists them is committed.
        sync_filesystem(&opts.out)?;
    }
    w.commit()?;
    previous.finish();
    if opts.shard.is_none() {
        // Both read the finished summary.csv and write their own files: side by side on
        // the pool (a 100 000-machine fleet spends ~0.3 s in each).
        let (reports, tables) = pool.install(|| {
            rayon::join(
                || write_reports(&opts.out),
                || write_fleet_tables(&opts.out, &fleets),
            )
        });
        reports?;
        tables?;
    }
    Ok(counts)
}
