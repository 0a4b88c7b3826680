//! Two machines of one run with the same name would write the same result files: the first
//! in input order keeps the name, every later one gets an error row. This module decides
//! that with memory that does not grow with the run, so a fleet of 10⁷ rows runs in the
//! memory of 10⁵ (issue 37).
//!
//! How: before solving, one pass over the run's machines writes each name's 64-bit key and
//! the machine's index to spill buckets (in memory for small runs, else up to
//! [`MAX_BUCKETS`] anonymous temporary files split by the key's top bits); each bucket is
//! then sorted on its own, and only the keys claimed twice or more are kept, with their
//! first claimant. The solve loop asks that small table. Memory: the bucket buffers, one
//! bucket's entries (n/256 × 16 bytes at most: 0.6 MB at 10⁷ machines) and one entry per
//! name taken twice. An external sort by hand: the crates that sort on disk
//! (`extsort`, …) serialise through serde per item and keep their own run files, where
//! a radix split into fixed-size records needs neither.
//!
//! Keys are SipHash with fixed keys (the same in every run) of the name without case.
//! Two different names colliding (probability ~n²/2⁶⁵) would be reported as a duplicate,
//! never silently overwritten. Each shard checks its own machines only.

use super::error::BatchError;
use super::inputs::Work;
use std::collections::HashMap;
use std::io::{BufReader, BufWriter, Read, Seek, Write};
use std::path::Path;

/// Runs of at most this many named machines are checked in memory (1 MB).
const IN_MEMORY: u64 = 1 << 16;
/// Target entries per spilled bucket; the bucket count is the run's size over this.
const PER_BUCKET: u64 = 1 << 15;
/// At most this many spill files (each with an 8 KB write buffer).
const MAX_BUCKETS: u64 = 256;

/// The names taken twice or more in a run, with their first claimant.
#[derive(Default)]
pub(super) struct Names {
    taken: HashMap<u64, Claim>,
}

/// The first machine (in input order) with a name that later machines also have.
struct Claim {
    first: u64,
    /// Its source (a file's path; empty for a fleet row, or until the solve loop meets it).
    source: String,
}

/// The key of a machine's name: case-insensitive (names equal but for case clash on
/// case-insensitive file systems).
fn key(name: &str) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for b in name.bytes() {
        b.to_ascii_lowercase().hash(&mut h);
    }
    h.finish()
}

impl Names {
    /// Scans the run's machines `jobs` (about `expected` of them; the spill files go in
    /// `dir`) and keeps the names claimed more than once.
    pub(super) fn scan(
        jobs: impl Iterator<Item = (u64, Work)>,
        expected: u64,
        dir: &Path,
    ) -> Result<Names, BatchError> {
        let claims = jobs.filter_map(|(index, work)| Some((key(&work.read().name()?), index)));
        let taken = first_of_repeated(claims, expected, dir)?
            .into_iter()
            .map(|(k, first)| {
                (
                    k,
                    Claim {
                        first,
                        source: String::new(),
                    },
                )
            })
            .collect();
        Ok(Names { taken })
    }

    /// The work of machine `index`, or, if its name (known before solving) is taken by an
    /// earlier machine, an error row's work saying so: both would write the same files.
    pub(super) fn check(&mut self, index: u64, work: Work) -> Work {
        if self.taken.is_empty() {
            return work;
        }
        let Some(name) = work.name() else {
            return work;
        };
        let Some(claim) = self.taken.get_mut(&key(&name)) else {
            return work;
        };
        if claim.first == index {
            if let Work::File { .. } = work {
                claim.source = work.source();
            }
            return work;
        }
        let first_src = match claim.source.as_str() {
            "" => String::new(),
            s => format!(" ({s})"),
        };
        Work::Broken {
            message: format!(
                "{}: duplicate name `{name}`: machine {}{first_src} already has it, and both would write `{name}.json`; give this machine another name",
                work.source(),
                claim.first,
            ),
            name,
        }
    }
}

/// The keys that occur more than once among `claims` (`(key, index)`, about `expected` of
/// them, indices ascending), each with its smallest index; spill files go in `dir`.
pub fn first_of_repeated(
    claims: impl Iterator<Item = (u64, u64)>,
    expected: u64,
    dir: &Path,
) -> Result<HashMap<u64, u64>, BatchError> {
    let mut spill = Spill::new(expected, dir)?;
    for (k, index) in claims {
        spill.push(k, index)?;
    }
    let mut repeated = HashMap::new();
    spill.for_each_bucket(|entries| {
        entries.sort_unstable();
        for pair in entries.windows(2) {
            if pair[0].0 == pair[1].0 {
                // Sorted by (key, index): the group's first entry is its first claimant.
                repeated.entry(pair[0].0).or_insert(pair[0].1);
            }
        }
    })?;
    Ok(repeated)
}

/// `(key, index)` pairs split by the key's top bits: one vector for a small run, else
/// anonymous temporary files (removed by the system however the process ends).
enum Spill {
    Memory(Vec<(u64, u64)>),
    Files {
        files: Vec<BufWriter<std::fs::File>>,
        /// The key's top `bits` choose the bucket.
        bits: u32,
        dir: std::path::PathBuf,
    },
}

impl Spill {
    fn new(expected: u64, dir: &Path) -> Result<Spill, BatchError> {
        if expected <= IN_MEMORY {
            return Ok(Spill::Memory(Vec::new()));
        }
        let n = (expected / PER_BUCKET)
            .next_power_of_two()
            .clamp(2, MAX_BUCKETS);
        let files = (0..n)
            .map(|_| {
                tempfile::tempfile_in(dir)
                    .map(|f| BufWriter::with_capacity(8 << 10, f))
                    .map_err(|e| BatchError::io("cannot create a temporary file in", dir, e))
            })
            .collect::<Result<_, _>>()?;
        Ok(Spill::Files {
            files,
            bits: n.trailing_zeros(),
            dir: dir.to_path_buf(),
        })
    }

    fn push(&mut self, key: u64, index: u64) -> Result<(), BatchError> {
        match self {
            Spill::Memory(v) => v.push((key, index)),
            Spill::Files { files, bits, dir } => {
                let f = &mut files[(key >> (64 - *bits)) as usize];
                let mut rec = [0u8; 16];
                rec[..8].copy_from_slice(&key.to_le_bytes());
                rec[8..].copy_from_slice(&index.to_le_bytes());
                f.write_all(&rec)
                    .map_err(|e| BatchError::io("writing a temporary file in", dir, e))?;
            }
        }
        Ok(())
    }

    /// Hands each bucket's entries to `f`, one bucket in memory at a time.
    fn for_each_bucket(self, mut f: impl FnMut(&mut Vec<(u64, u64)>)) -> Result<(), BatchError> {
        match self {
            Spill::Memory(mut v) => f(&mut v),
            Spill::Files { files, dir, .. } => {
                let io = |e| BatchError::io("reading a temporary file in", &dir, e);
                let mut entries = Vec::new();
                for w in files {
                    let mut file = w.into_inner().map_err(|e| io(e.into_error()))?;
                    file.rewind().map_err(io)?;
                    let mut r = BufReader::with_capacity(64 << 10, file);
                    let mut rec = [0u8; 16];
                    entries.clear();
                    loop {
                        match r.read_exact(&mut rec) {
                            Ok(()) => entries.push((
                                u64::from_le_bytes(rec[..8].try_into().expect("8 bytes")),
                                u64::from_le_bytes(rec[8..].try_into().expect("8 bytes")),
                            )),
                            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
                            Err(e) => return Err(io(e)),
                        }
                    }
                    f(&mut entries);
                }
            }
        }
        Ok(())
    }
}
