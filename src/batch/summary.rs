//! The summary CSV file of a run (`summary.csv`, `summary-shard-i-of-n.csv`): written row by
//! row to `<summary>.partial` and committed by one rename, the run's one commit point; read
//! back in index order as input (a resumed run's checkpoint, a shard given to `merge`).

use super::error::BatchError;
use super::row::{Row, HEADER};
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// The summary file name of a run: `summary.csv`, or `summary-shard-i-of-n.csv`.
pub fn summary_name(shard: Option<(u64, u64)>) -> String {
    match shard {
        Some((i, n)) => format!("summary-shard-{i}-of-{n}.csv"),
        None => "summary.csv".into(),
    }
}

/// The file `<path>.<ext>` beside `path` (`summary.csv.partial`).
pub(super) fn beside(path: &Path, ext: &str) -> PathBuf {
    let mut p = path.as_os_str().to_owned();
    p.push(".");
    p.push(ext);
    p.into()
}

/// Reads a summary CSV in index order: a resumed run's checkpoint (merge-join with the
/// current run) or a shard given to `merge`. A file written by someone else is input like
/// any other: the header must be cwsynth's and every row must parse, validate
/// ([`Row::validate`]) and come in increasing index order. Reading stops at the first row
/// that does not, and [`SummaryRows::stopped`] says where and why: a resumed run re-solves
/// from there (as after a truncated tail), `merge` refuses the shard.
pub(super) struct SummaryRows {
    path: PathBuf,
    rdr: Option<csv::StringRecordsIntoIter<std::fs::File>>,
    header: csv::StringRecord,
    /// The next row, read ahead.
    pub(super) peek: Option<Row>,
    last: Option<u64>,
    /// `FILE:LINE: what is wrong`, when reading stopped before the end of the file.
    pub(super) stopped: Option<String>,
}

impl SummaryRows {
    /// Opens `path` (a missing file has no rows and no error).
    pub(super) fn open(path: &Path) -> SummaryRows {
        let mut o = SummaryRows {
            path: path.to_path_buf(),
            rdr: None,
            header: csv::StringRecord::new(),
            peek: None,
            last: None,
            stopped: None,
        };
        // Only a regular file: a FIFO or `/dev/zero` under the summary's name would never end.
        if path.exists() && !path.metadata().is_ok_and(|m| m.is_file()) {
            o.stopped = Some(format!(
                "{}: not a regular file (a directory, a FIFO or a device): not read",
                path.display()
            ));
            return o;
        }
        match csv::Reader::from_path(path) {
            Ok(mut r) => match r.headers() {
                Ok(h) if h.iter().eq(HEADER.iter().copied()) => {
                    o.header = h.clone();
                    o.rdr = Some(r.into_records());
                }
                _ => {
                    o.stopped = Some(format!(
                        "{}:1: the header is not a cwsynth summary header ({})",
                        path.display(),
                        HEADER.join(",")
                    ))
                }
            },
            Err(e) if e.is_io_error() && !path.exists() => {}
            Err(e) => o.stopped = Some(format!("{}: {e}", path.display())),
        }
        o.advance();
        o
    }
    /// Reads the next row into `peek` (or stops).
    pub(super) fn advance(&mut self) {
        self.peek = None;
        let Some(rec) = self.rdr.as_mut().and_then(|r| r.next()) else {
            return;
        };
        let row = rec.map_err(|e| e.to_string()).and_then(|rec| {
            let line = rec.position().map_or(0, |p| p.line());
            let row = rec
                .deserialize::<Row>(Some(&self.header))
                .map_err(|e| format!("{line}: {e}"))?
                .csv_unescaped();
            row.validate().map_err(|e| format!("{line}: {e}"))?;
            if self.last.is_some_and(|l| row.index <= l) {
                return Err(format!("{line}: index {} is out of order", row.index));
            }
            Ok(row)
        });
        match row {
            Ok(r) => {
                self.last = Some(r.index);
                self.peek = Some(r);
            }
            Err(e) => {
                self.stopped = Some(format!("{}:{e}", self.path.display()));
                self.rdr = None;
            }
        }
    }
    /// The old row with this index, if any.
    pub(super) fn take(&mut self, index: u64) -> Option<Row> {
        while let Some(p) = &self.peek {
            if p.index < index {
                self.advance();
            } else if p.index == index {
                let r = self.peek.take();
                self.advance();
                return r;
            } else {
                return None;
            }
        }
        None
    }
}

/// A summary being written: rows go to `<summary>.partial` (the checkpoint of an interrupted
/// run), in the order given, formula-escaped ([`Row::csv_escaped`]); [`SummaryWriter::commit`]
/// makes it the summary.
pub(super) struct SummaryWriter {
    w: csv::Writer<BufWriter<std::fs::File>>,
    partial: PathBuf,
    path: PathBuf,
    rows: u64,
}

impl SummaryWriter {
    /// Starts writing the summary `path` (into `path.partial`, replacing one there).
    pub(super) fn create(path: &Path) -> Result<SummaryWriter, BatchError> {
        let partial = beside(path, "partial");
        let file = std::fs::File::create(&partial)
            .map_err(|e| BatchError::io("cannot write", &partial, e))?;
        Ok(SummaryWriter {
            w: csv::Writer::from_writer(BufWriter::new(file)),
            partial,
            path: path.into(),
            rows: 0,
        })
    }

    /// Appends a row.
    pub(super) fn write(&mut self, row: &Row) -> Result<(), BatchError> {
        self.rows += 1;
        self.w
            .serialize(row.csv_escaped())
            .map_err(|e| BatchError::csv("writing", &self.partial, e))
    }

    /// Hands the rows so far to the operating system (after each chunk: the checkpoint).
    pub(super) fn flush(&mut self) -> Result<(), BatchError> {
        self.w
            .flush()
            .map_err(|e| BatchError::io("writing", &self.partial, e))
    }

    /// Commits the summary: writes the header if there was no row, flushes and syncs the
    /// partial file, renames it to the summary and syncs the directory, so the summary is
    /// durable once this returns (the run's one commit point).
    pub(super) fn commit(mut self) -> Result<(), BatchError> {
        let writing = |e| BatchError::io("writing", &self.partial, e);
        if self.rows == 0 {
            // An empty run still gets a header line.
            self.w
                .write_record(HEADER)
                .map_err(|e| BatchError::csv("writing", &self.partial, e))?;
        }
        let file = self
            .w
            .into_inner()
            .map_err(|e| writing(e.into_error()))?
            .into_inner()
            .map_err(|e| writing(e.into_error()))?;
        file.sync_all().map_err(writing)?;
        std::fs::rename(&self.partial, &self.path).map_err(|cause| BatchError::Rename {
            from: self.partial.clone(),
            to: self.path.clone(),
            cause,
        })?;
        sync_dir(self.path.parent().unwrap_or(Path::new(".")))
    }

    /// Gives up: the partial file is removed, the summary is left as it was.
    pub(super) fn abandon(self) {
        drop(self.w);
        let _ = std::fs::remove_file(&self.partial);
    }
}

/// Syncs a directory (its entries: a rename in it becomes durable). Unix only; elsewhere a
/// no-op.
fn sync_dir(dir: &Path) -> Result<(), BatchError> {
    #[cfg(unix)]
    std::fs::File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(|e| BatchError::io("cannot sync", dir, e))?;
    let _ = dir;
    Ok(())
}
