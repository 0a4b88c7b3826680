//! Where a machine's files go in the output directory (`docs/batch.md`, "Outputs"). A run of
//! fewer than [`LARGE_RUN`] machines writes them beside the summary, as `cwsynth solve --out`
//! does; a larger one writes machine `index` into `machines/NNN/`, NNN = index ÷
//! [`MACHINES_PER_FOLDER`] (at least three digits: `machines/000/` holds machines 0–999,
//! `machines/001/` 1000–1999), so no folder holds more than about 7 000 files.
//!
//! The rule reads only the machine's index and the count of machines of the whole batch
//! (across all inputs, before `--shard`), both known before anything is solved and both in
//! the summary (`index`, its row count): every shard of a run, a re-run, `merge` and the
//! reports find a machine's files in the same folder whatever the threads or the split.

use std::path::{Path, PathBuf};

/// A run of this many machines or more is large: it says before it starts how much it will
/// write ([`super::size_note`]) and writes its machines into folders ([`Layout`]).
pub const LARGE_RUN: u64 = 1000;
/// Machines per folder `machines/NNN/` of a large run.
pub const MACHINES_PER_FOLDER: u64 = 1000;
/// The folder of a large run's machine folders, in the output directory.
pub const MACHINES_DIR: &str = "machines";

/// Where a batch of some number of machines puts each machine's files.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// Machines in folders `machines/NNN/` (a large run), else beside the summary.
    pub folders: bool,
}

impl Layout {
    /// The layout of a batch of `machines` machines (all inputs, every shard: the summary's
    /// row count).
    pub fn of_run(machines: u64) -> Layout {
        Layout {
            folders: machines >= LARGE_RUN,
        }
    }

    /// The folder of machine `index` relative to the output directory: `machines/NNN`, or
    /// `None` when the machine's files are beside the summary.
    pub fn folder(self, index: u64) -> Option<String> {
        self.folders
            .then(|| format!("{MACHINES_DIR}/{:03}", index / MACHINES_PER_FOLDER))
    }

    /// The directory of machine `index`'s files in the output directory `out`.
    pub fn dir(self, out: &Path, index: u64) -> PathBuf {
        match self.folder(index) {
            Some(f) => out.join(f),
            None => out.to_path_buf(),
        }
    }

    /// The relative link from a page in the output directory (`index.html`) to `file` of
    /// machine `index`: `machines/001/pump-7.html`, or `pump-7.html`.
    pub fn href(self, index: u64, file: &str) -> String {
        match self.folder(index) {
            Some(f) => format!("{f}/{file}"),
            None => file.to_string(),
        }
    }
}

/// The machine folders `out/machines/*` that exist (for the leftovers of killed runs).
pub(super) fn machine_folders(out: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(out.join(MACHINES_DIR)) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
        .map(|e| e.path())
        .collect()
}
