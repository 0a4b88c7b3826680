//! Why a batch, a merge or the reports could not run at all (usage and I/O errors: the CLI
//! exits with status 2). A machine that fails is not one of these: it is a row of the
//! summary with its reason, and the run goes on.
//!
//! Every message names the file or directory, and carries its cause in its text (no error
//! source is chained, so the CLI's `{:#}` prints each cause once).

use crate::problem::ProblemError;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// A batch, merge or report error.
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// An input path that does not exist.
    #[error("{}: no such file or directory", .0.display())]
    NoSuchInput(PathBuf),
    /// A directory input without problem files.
    #[error("{}: no problem files (*.toml) in this directory", .0.display())]
    NoProblemFiles(PathBuf),
    /// `--shard` not written `i/n`.
    #[error("--shard: {0}")]
    ShardSyntax(String),
    /// `--shard i/n` without 0 ≤ i < n.
    #[error("--shard {0}: need 0 ≤ i < n")]
    ShardRange(String),
    /// A fleet's template is not a valid problem file by itself.
    #[error("template {0}")]
    Template(ProblemError),
    /// A fleet's template is not TOML.
    #[error("{}: not TOML: {why}", path.display())]
    NotToml {
        /// The template.
        path: PathBuf,
        /// The TOML parser's message.
        why: String,
    },
    /// A fleet CSV's header (line 1): an unknown unit, a key set by two columns.
    #[error("{}:1: {why}", path.display())]
    FleetHeader {
        /// The fleet CSV.
        path: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// A file that cannot be read (`FILE: cannot read: cause`).
    #[error("{}: cannot read: {cause}", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// The system's reason.
        cause: std::io::Error,
    },
    /// A file-system operation that failed (`cannot create DIR: cause`, `writing FILE: …`).
    #[error("{action} {}: {cause}", path.display())]
    Io {
        /// What was done: `cannot create`, `cannot list`, `writing`, …
        action: &'static str,
        /// The file or directory.
        path: PathBuf,
        /// The system's reason.
        cause: std::io::Error,
    },
    /// A CSV that cannot be read or written (`cannot read FILE: cause`).
    #[error("{action} {}: {cause}", path.display())]
    Csv {
        /// What was done: `cannot read`, `writing`.
        action: &'static str,
        /// The CSV file.
        path: PathBuf,
        /// The CSV reader's or writer's reason.
        cause: csv::Error,
    },
    /// A fleet CSV whose header line cannot be read.
    #[error("{}: cannot read the header: {cause}", path.display())]
    FleetHeaderUnreadable {
        /// The fleet CSV.
        path: PathBuf,
        /// The CSV reader's reason.
        cause: csv::Error,
    },
    /// A rename that failed (a checkpoint moved, a summary committed).
    #[error("cannot rename {} to {}: {cause}", from.display(), to.display())]
    Rename {
        /// The file renamed.
        from: PathBuf,
        /// Its new name.
        to: PathBuf,
        /// The system's reason.
        cause: std::io::Error,
    },
    /// Another batch or merge holds the output directory's lock.
    #[error("{} is in use by another cwsynth batch or merge (lock {}); wait for it to finish or choose another --out", out.display(), lock.display())]
    InUse {
        /// The output directory.
        out: PathBuf,
        /// Its lock file.
        lock: PathBuf,
    },
    /// The worker pool could not be started.
    #[error("cannot start the worker threads: {0}")]
    Threads(rayon::ThreadPoolBuildError),
    /// `merge` found no shard summary.
    #[error("no shard summaries (summary-shard-i-of-n.csv) found")]
    NoShards,
    /// `merge` found shard summaries of different splits `n`.
    #[error("shard summaries of different splits: n = {0:?}")]
    MixedSplits(BTreeSet<u64>),
    /// `merge` is missing shards.
    #[error("shards {missing:?} of {n} are missing")]
    MissingShards {
        /// The shard numbers not found.
        missing: Vec<u64>,
        /// The split.
        n: u64,
    },
    /// A summary given to `merge` that is not a cwsynth summary (`FILE:LINE: what is wrong`).
    #[error("{0}")]
    BadSummary(String),
    /// A summary without one of cwsynth's columns.
    #[error("{}: no column `{column}`", path.display())]
    NoColumn {
        /// The summary.
        path: PathBuf,
        /// The missing column.
        column: &'static str,
    },
    /// A summary cell that should be a number.
    #[error("{}: {column} `{text}` is not a number: {cause}", path.display())]
    NotANumber {
        /// The summary.
        path: PathBuf,
        /// The column.
        column: &'static str,
        /// The cell.
        text: String,
        /// The parser's reason.
        cause: std::num::ParseFloatError,
    },
    /// A report file that could not be written (the message names it).
    #[error(transparent)]
    Written(std::io::Error),
}

impl BatchError {
    /// `action PATH: cause` for an I/O error.
    pub(crate) fn io(action: &'static str, path: &Path, cause: std::io::Error) -> BatchError {
        BatchError::Io {
            action,
            path: path.into(),
            cause,
        }
    }

    /// `action PATH: cause` for a CSV error.
    pub(crate) fn csv(action: &'static str, path: &Path, cause: csv::Error) -> BatchError {
        BatchError::Csv {
            action,
            path: path.into(),
            cause,
        }
    }
}
