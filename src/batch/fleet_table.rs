//! A fleet's own table, `DIR/fleet-<csv stem>.csv`: one row per machine of the fleet with
//! the inputs that vary per row (the fleet's columns, as written; an empty cell shows the
//! template's value) and every design value
//! and objective in its own column, so the table stands alone in a spreadsheet. The
//! summary's `design` and `objectives` cells (`k=v;…`, every family in one file) are split
//! here, after the run, from `summary.csv`.

use super::error::BatchError;
use super::fleet::{csv_reader, Lines, Template};
use super::inputs::Input;
use super::row::escape_formula;
use crate::report::write_atomic_with;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The table's path for the fleet CSV `csv` in `dir`.
pub fn fleet_table_path(dir: &Path, csv: &Path) -> PathBuf {
    let stem = csv.file_stem().and_then(|s| s.to_str()).unwrap_or("fleet");
    dir.join(format!("fleet-{stem}.csv"))
}

/// Writes the table of every fleet among `inputs` from `DIR/summary.csv`.
pub fn write_fleet_tables(dir: &Path, inputs: &[Input]) -> Result<(), BatchError> {
    let fleets: Vec<(&PathBuf, &PathBuf)> = inputs
        .iter()
        .filter_map(|i| match i {
            Input::Fleet { template, csv } => Some((template, csv)),
            Input::File(_) => None,
        })
        .collect();
    if fleets.is_empty() {
        return Ok(());
    }
    let summary = dir.join("summary.csv");
    let read_summary = || {
        csv::Reader::from_path(&summary)
            .map_err(|e| BatchError::io("cannot read", &summary, std::io::Error::other(e)))
    };
    // The `k=v;…` pairs of a design or objectives cell, borrowed.
    fn split(cell: &str) -> Vec<(&str, &str)> {
        cell.split(';')
            .filter_map(|kv| kv.split_once('='))
            .collect()
    }
    let get = |pairs: &[(&str, &str)], k: &str| -> String {
        pairs
            .iter()
            .find(|(a, _)| *a == k)
            .map_or_else(String::new, |(_, v)| (*v).to_string())
    };
    for (template, csv) in fleets {
        // A fleet that could not be opened has only error rows: no table.
        let Ok(tpl) = Template::open(template, csv) else {
            continue;
        };
        // The summary's rows of this fleet and their CSV lines (`fleet.csv:LINE`), in the
        // summary's (index) order, which is the fleet's row order. Streamed twice — once for
        // the columns (the union of the design and objective keys), once for the rows — so
        // the memory stays flat however long the fleet.
        let prefix = format!("{}:", csv.display());
        let rows = || SummaryCells::read(read_summary()?, &prefix, &summary);
        let mut design_keys: BTreeSet<String> = BTreeSet::new();
        let mut objective_keys: BTreeSet<String> = BTreeSet::new();
        for (_, r) in rows()? {
            for (set, c) in [
                (&mut design_keys, Col::Design),
                (&mut objective_keys, Col::Objectives),
            ] {
                for (k, _) in split(r.get(c)) {
                    if !set.contains(k) {
                        set.insert(k.to_string());
                    }
                }
            }
        }
        // The fleet's own rows, with their real line numbers.
        let Ok(mut fr) = csv_reader(csv) else {
            continue;
        };
        let Ok(mut lines) = Lines::open(csv) else {
            continue;
        };
        let header: Vec<String> = match fr.headers() {
            Ok(h) => h.iter().map(|c| c.trim().to_string()).collect(),
            Err(_) => continue,
        };
        let inputs: Vec<usize> = (0..header.len()).filter(|&k| header[k] != "name").collect();
        let mut head: Vec<String> = vec!["index".into(), "name".into(), "status".into()];
        head.extend(inputs.iter().map(|&k| header[k].clone()));
        head.extend(design_keys.iter().map(|k| format!("design.{k}")));
        head.extend(objective_keys.iter().map(|k| format!("objectives.{k}")));
        head.extend(["objective".into(), "error".into(), "message".into()]);
        let rows = rows()?;
        let to_io = std::io::Error::other;
        write_atomic_with(&fleet_table_path(dir, csv), |out| {
            let mut w = csv::Writer::from_writer(out);
            w.write_record(&head).map_err(to_io)?;
            // A merge join on the CSV line: both sides ascend.
            let mut records = fr.records().flatten().filter_map(|rec| {
                let line = rec.position().map(|p| lines.record_line(p.byte()))?;
                Some((line, rec))
            });
            let mut next = records.next();
            for (line, r) in rows {
                while next.as_ref().is_some_and(|(l, _)| *l < line) {
                    next = records.next();
                }
                let Some((l, rec)) = next.as_ref() else {
                    break;
                };
                if *l != line {
                    continue;
                }
                let cells: Vec<String> = rec.iter().map(str::to_string).collect();
                let (d, o) = (split(r.get(Col::Design)), split(r.get(Col::Objectives)));
                let mut out: Vec<String> = [Col::Index, Col::Name, Col::Status]
                    .map(|c| r.get(c).to_string())
                    .into();
                out.extend(inputs.iter().map(|&k| {
                    let mut c = tpl.effective_cell(k, &cells);
                    // The fleet's cells are text from outside: escaped like the summary's
                    // text columns (a number, `-3.5`, stays a number).
                    if c.parse::<f64>().is_err() {
                        escape_formula(&mut c);
                    }
                    c
                }));
                out.extend(design_keys.iter().map(|k| get(&d, k)));
                out.extend(objective_keys.iter().map(|k| get(&o, k)));
                out.push(r.get(Col::Objective).to_string());
                out.push(r.error());
                out.push(r.get(Col::Message).to_string());
                w.write_record(&out).map_err(to_io)?;
            }
            w.flush()
        })
        .map_err(BatchError::Written)?;
    }
    Ok(())
}

/// The summary cells the fleet table shows, by their header's position.
#[derive(Clone, Copy)]
enum Col {
    Index,
    Name,
    Status,
    Objective,
    Error,
    Design,
    Objectives,
    Source,
    Message,
}

const COLS: [&str; 9] = [
    "index",
    "name",
    "status",
    "objective",
    "error",
    "design",
    "objectives",
    "source",
    "message",
];

/// One summary row's cells as written (formula-escaped, as the table shows them): no
/// deserialisation into a [`super::row::Row`] and no copy of its texts per row.
struct SummaryCells {
    rec: csv::StringRecord,
    at: [usize; 9],
}

impl SummaryCells {
    /// The rows of `rdr` (the summary `path`) from the fleet whose sources start with
    /// `prefix` (`fleet.csv:`), with their CSV line; a summary without one of the columns
    /// gives none.
    fn read<'p>(
        mut rdr: csv::Reader<std::fs::File>,
        prefix: &'p str,
        path: &Path,
    ) -> Result<impl Iterator<Item = (u64, SummaryCells)> + 'p, BatchError> {
        let head = rdr
            .headers()
            .map_err(|e| BatchError::io("cannot read", path, std::io::Error::other(e)))?;
        let at = COLS.map(|c| head.iter().position(|h| h == c));
        let at: Option<[usize; 9]> = at
            .iter()
            .all(Option::is_some)
            .then(|| at.map(Option::unwrap_or_default));
        Ok(rdr.into_records().flatten().filter_map(move |rec| {
            let row = SummaryCells { rec, at: at? };
            // A source starting like a formula is written with a leading `'`.
            let source = row.get(Col::Source);
            let source = source.strip_prefix('\'').unwrap_or(source);
            let line = source.strip_prefix(prefix)?.parse::<u64>().ok()?;
            row.get(Col::Index).parse::<u64>().ok()?;
            Some((line, row))
        }))
    }

    fn get(&self, c: Col) -> &str {
        self.rec.get(self.at[c as usize]).unwrap_or("")
    }

    /// The error column as the table has always written it (a number's `Display`).
    fn error(&self) -> String {
        self.get(Col::Error)
            .parse::<f64>()
            .map(|e| e.to_string())
            .unwrap_or_default()
    }
}
