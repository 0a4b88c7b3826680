//! Joining shard summaries (`summary-shard-i-of-n.csv`, from `--shard i/n` runs) into one
//! `summary.csv` in index order — a streaming k-way merge that reads each shard as input
//! (checked row by row) — and writing the reports from it.

use super::error::BatchError;
use super::reports::write_reports;
use super::resume::lock_out;
use super::row::Counts;
use super::summary::{SummaryRows, SummaryWriter};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Joins the shard summaries found in `dirs` (`summary-shard-i-of-n.csv`) into
/// `out/summary.csv` (in index order, a streaming k-way merge) and writes the reports.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Counts, BatchError> {
    // The shard files by shard number i (each i once), and the splits n they name.
    let mut shards: BTreeMap<u64, PathBuf> = BTreeMap::new();
    let mut ns = BTreeSet::new();
    for d in dirs {
        let listing = |e| BatchError::io("cannot list", d, e);
        for e in std::fs::read_dir(d).map_err(listing)? {
            let p = e.map_err(listing)?.path();
            let Some((i, n)) = p.file_name().and_then(|f| f.to_str()).and_then(shard_name) else {
                continue;
            };
            ns.insert(n);
            // The same shard twice (two copies of one run, or shards of two runs) would
            // duplicate or mix rows: refused.
            if let Some(first) = shards.get(&i) {
                return Err(BatchError::BadSummary(format!(
                    "{}: shard {i} of {n} is given twice (also {}); merge the shards of one run, once each",
                    p.display(),
                    first.display()
                )));
            }
            shards.insert(i, p);
        }
    }
    let mut files: Vec<(PathBuf, u64)> = shards.into_iter().map(|(i, p)| (p, i)).collect();
    files.sort();
    if files.is_empty() {
        return Err(BatchError::NoShards);
    }
    if ns.len() != 1 {
        return Err(BatchError::MixedSplits(ns));
    }
    let n = *ns.iter().next().expect("one split");
    let missing: Vec<u64> = (0..n)
        .filter(|i| !files.iter().any(|(_, j)| j == i))
        .collect();
    if !missing.is_empty() {
        return Err(BatchError::MissingShards { missing, n });
    }
    std::fs::create_dir_all(out).map_err(|e| BatchError::io("cannot create", out, e))?;
    let _lock = lock_out(out, "summary.csv")?;
    let mut readers: Vec<SummaryRows> = files.iter().map(|(f, _)| SummaryRows::open(f)).collect();
    let mut w = SummaryWriter::create(&out.join("summary.csv"))?;
    let mut counts = Counts::default();
    loop {
        let k = readers
            .iter()
            .enumerate()
            .filter_map(|(k, r)| r.peek.as_ref().map(|p| (p.index, k)))
            .min();
        let Some((_, k)) = k else { break };
        let row = readers[k].peek.take().expect("peeked");
        // A shard holds the machines with index % n == i: a row that does not belongs to
        // another split or another run.
        let (file, i) = &files[k];
        if row.index % n != *i {
            w.abandon();
            return Err(BatchError::BadSummary(format!(
                "{}: machine {} is not of shard {i} of {n} (index % {n} = {}): the shard belongs to another run",
                file.display(),
                row.index,
                row.index % n
            )));
        }
        readers[k].advance();
        counts.add(&row, false);
        w.write(&row)?;
    }
    // Shard summaries are input: a row that did not parse, validate or keep the index
    // order stopped its reader, and the merge is refused.
    if let Some(e) = readers.iter().find_map(|r| r.stopped.clone()) {
        w.abandon();
        return Err(BatchError::BadSummary(e));
    }
    w.commit()?;
    write_reports(out)?;
    Ok(counts)
}

/// (i, n) of a shard summary's file name `summary-shard-i-of-n.csv`.
fn shard_name(name: &str) -> Option<(u64, u64)> {
    let (i, n) = name
        .strip_prefix("summary-shard-")?
        .strip_suffix(".csv")?
        .split_once("-of-")?;
    Some((i.parse().ok()?, n.parse().ok()?))
}
