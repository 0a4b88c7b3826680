//! Re-runs and interruptions: what a re-run may skip, and what makes that safe.
//!
//! A machine's files are written with its JSON last, and the JSON lists every other file with
//! its size and [`file_hash`] (`batch.files`, the manifest): a machine is done when its JSON
//! has the machine's input hash now and every listed file is whole ([`complete_result`]).
//! The files are not synced one by one; one `syncfs` makes them durable just before the
//! summary's commit ([`sync_filesystem`], [`super::summary::SummaryWriter::commit`]). With
//! `--summary-only` the previous summary row of the same index carries the hash
//! ([`Previous`]: the checkpoint of an interrupted run, then the last complete summary). One
//! process writes a summary at a time ([`lock_out`]); temporary files of dead runs are removed
//! ([`remove_stale_tmp`], in the machine folders of a large run too). A machine's files are
//! looked for in its folder of the run's [`super::Layout`].

use super::error::BatchError;
use super::hash::file_hash;
use super::layout::machine_folders;
use super::row::Row;
use super::summary::{beside, SummaryRows};
use crate::report::{json_path, report_files, write_replace, SolveResult};
use std::path::{Path, PathBuf};

/// Writes a machine's result files into `dir` so that a re-run can check them: every report
/// file first, then `<name>.json` last, whose `batch` object is `batch` with `files` added
/// (every other file's name, size and [`file_hash`]). Returns the JSON and how the writing
/// went (the first error, which names the file).
pub(super) fn write_result(
    r: &mut SolveResult,
    mut batch: serde_json::Value,
    dir: &Path,
) -> (serde_json::Value, std::io::Result<()>) {
    let files = report_files(r, dir);
    let mut written = Ok(());
    let mut listed = serde_json::Map::new();
    for (path, bytes) in &files {
        let file = path.file_name().map(|n| n.to_string_lossy().into_owned());
        listed.insert(
            file.unwrap_or_default(),
            serde_json::json!({"bytes": bytes.len(), "hash": file_hash(bytes)}),
        );
        if written.is_ok() {
            written = write_replace(path, bytes);
        }
    }
    batch["files"] = listed.into();
    r.extra.insert("batch".into(), batch);
    let v = r.to_json();
    let json = serde_json::to_string_pretty(&v).expect("plain data") + "\n";
    let written = written.and_then(|()| write_replace(&json_path(r, dir), json.as_bytes()));
    (v, written)
}

/// A result file's bytes, if it is a regular file within [`crate::problem::MAX_RESULT_BYTES`]
/// (a FIFO or `/dev/zero` under a result's name is not read; it is solved again).
pub(super) fn read_result(path: &Path) -> Option<Vec<u8>> {
    let limit = crate::problem::MAX_RESULT_BYTES;
    crate::problem::read_bounded(path, limit)
        .ok()
        .filter(|b| b.len() <= limit)
}

/// The result JSON at `json` if the machine is done: the JSON parses, its `batch.input_hash`
/// is `hash`, and every file it lists in `batch.files` (name: size and [`file_hash`]) is in
/// `dir` with that size and hash. Anything else (a file missing, torn by a crash, edited, a
/// JSON of an older cwsynth without the list) means the machine is solved again.
pub(super) fn complete_result(json: &Path, hash: &str, dir: &Path) -> Option<serde_json::Value> {
    let v: serde_json::Value = serde_json::from_slice(&read_result(json)?).ok()?;
    let batch = v.get("batch")?;
    if batch.get("input_hash")?.as_str()? != hash {
        return None;
    }
    for (name, f) in batch.get("files")?.as_object()? {
        // Only plain file names of this directory (the JSON is input like any other).
        if Path::new(name).file_name() != Some(std::ffi::OsStr::new(name)) {
            return None;
        }
        let bytes = read_result(&dir.join(name))?;
        if f.get("bytes")?.as_u64()? != bytes.len() as u64
            || f.get("hash")?.as_str()? != file_hash(&bytes)
        {
            return None;
        }
    }
    Some(v)
}

/// Locks `<out>/.<summary>.lock` for this process: one writer per summary. A second batch
/// (or merge) on the same --out and shard does not wait, it stops with a clear message. The
/// OS releases the lock when the process ends, even by kill -9, so a crash never leaves a
/// stale lock. The lock is held while the returned file lives.
pub(super) fn lock_out(out: &Path, summary: &str) -> Result<std::fs::File, BatchError> {
    let lock_path = out.join(format!(".{summary}.lock"));
    let lock = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&lock_path)
        .map_err(|e| BatchError::io("cannot create", &lock_path, e))?;
    match lock.try_lock() {
        Ok(()) => Ok(lock),
        Err(std::fs::TryLockError::WouldBlock) => Err(BatchError::InUse {
            out: out.into(),
            lock: lock_path,
        }),
        Err(std::fs::TryLockError::Error(e)) => Err(BatchError::io("cannot lock", &lock_path, e)),
    }
}

/// Makes every file written to the file system of `dir` durable at once (Linux `syncfs`,
/// one call instead of one sync per file; `sync` on other Unix systems; elsewhere each file
/// was left to the operating system and a crash is caught at resume by [`complete_result`]).
pub(super) fn sync_filesystem(dir: &Path) -> Result<(), BatchError> {
    #[cfg(target_os = "linux")]
    {
        use std::os::fd::AsRawFd;
        let d = std::fs::File::open(dir).map_err(|e| BatchError::io("cannot open", dir, e))?;
        // SAFETY: `syncfs` reads only the descriptor, which `d` keeps open.
        if unsafe { libc::syncfs(d.as_raw_fd()) } != 0 {
            let e = std::io::Error::last_os_error();
            return Err(BatchError::io("cannot sync the files in", dir, e));
        }
    }
    #[cfg(all(unix, not(target_os = "linux")))]
    // SAFETY: `sync` takes no arguments and cannot fail.
    unsafe {
        libc::sync()
    };
    let _ = dir;
    Ok(())
}

/// Removes the temporary files (`.NAME.PID.tmp`) a killed run left in the output directory
/// `out` and in its machine folders (`machines/NNN/`, [`super::Layout`]): those whose process
/// is gone (Unix: `kill(PID, 0)` fails), so a live run sharing the directory (another shard)
/// keeps its own. Elsewhere every leftover of another process id is removed.
pub(super) fn remove_stale_tmp(out: &Path) {
    remove_stale_tmp_in(out);
    for dir in machine_folders(out) {
        remove_stale_tmp_in(&dir);
    }
}

/// [`remove_stale_tmp`] in one directory.
fn remove_stale_tmp_in(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(pid) = name
            .to_str()
            .filter(|n| n.starts_with('.'))
            .and_then(|n| n.strip_suffix(".tmp"))
            .and_then(|n| n.rsplit_once('.'))
            .and_then(|(_, pid)| pid.parse::<u32>().ok())
        else {
            continue;
        };
        if !process_alive(pid) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Whether process `pid` runs (this one always does).
fn process_alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    #[cfg(unix)]
    {
        let Ok(p) = libc::pid_t::try_from(pid) else {
            return false;
        };
        // SAFETY: signal 0 only checks that the process exists; nothing is sent.
        let r = unsafe { libc::kill(p, 0) };
        r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
    }
    #[cfg(not(unix))]
    false
}

/// The rows of the previous runs of a summary, for a `--summary-only` re-run to skip
/// machines whose input is unchanged: the checkpoint of an interrupted run
/// (`<summary>.resume`), then the last complete summary.
pub(super) struct Previous {
    resume_path: PathBuf,
    resume: SummaryRows,
    last: SummaryRows,
}

impl Previous {
    /// Opens the previous rows of the summary `summary`. An interrupted run's
    /// `<summary>.partial` becomes the checkpoint `<summary>.resume`, unless the checkpoint
    /// there already has more rows (after a second interruption): a checkpoint never goes
    /// backwards.
    pub(super) fn open(summary: &Path) -> Result<Previous, BatchError> {
        let (partial, resume) = (beside(summary, "partial"), beside(summary, "resume"));
        if partial.exists() {
            let rows =
                |p: &Path| read_result(p).map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count());
            if resume.exists() && rows(&resume) > rows(&partial) {
                std::fs::remove_file(&partial).map_err(|e| {
                    BatchError::io("cannot remove the smaller checkpoint", &partial, e)
                })?;
            } else {
                std::fs::rename(&partial, &resume).map_err(|cause| BatchError::Rename {
                    from: partial.clone(),
                    to: resume.clone(),
                    cause,
                })?;
            }
        }
        Ok(Previous {
            resume: SummaryRows::open(&resume),
            last: SummaryRows::open(summary),
            resume_path: resume,
        })
    }

    /// The previous row of machine `index`, if any (indices must increase from call to call).
    pub(super) fn take(&mut self, index: u64) -> Option<Row> {
        self.resume.take(index).or_else(|| self.last.take(index))
    }

    /// Drops the checkpoint, once the new summary is committed.
    pub(super) fn finish(self) {
        let _ = std::fs::remove_file(&self.resume_path);
    }
}
