//! What the batch reports show of a summary: an [`Overview`] read from `summary.csv` in one
//! streaming pass (counts per family and status, the improvement histogram, the first rows
//! and failures whole), the plots of the first machines that have them, and the formats of
//! the table cells that `summary.md` and `index.html` share.

use super::error::BatchError;
use super::layout::Layout;
use super::row::{is_failure, Row};
use crate::report::fmt_num;
use std::collections::BTreeMap;
use std::path::Path;

/// Rows shown in the tables of `summary.md` and `index.html` (all rows are in `summary.csv`).
pub const REPORT_ROWS: usize = 1000;
/// Machines whose plots are inlined in `index.html`.
pub const REPORT_PLOTS: usize = 40;

/// Bins of the improvement histogram: 1 % each, `0` (below 1 %, negative included) to
/// `19+`.
pub(super) const IMPROVEMENT_BINS: usize = 20;

/// What a family's machines did.
#[derive(Default)]
pub(super) struct FamilyCounts {
    /// Machines.
    pub n: u64,
    /// Machines per status.
    pub by_status: BTreeMap<String, u64>,
    imp_sum: f64,
    imp_n: u64,
    imp_min: f64,
    imp_max: f64,
}

impl FamilyCounts {
    fn add_improvement(&mut self, i: f64) {
        if self.imp_n == 0 {
            self.imp_min = i;
            self.imp_max = i;
        }
        self.imp_sum += i;
        self.imp_n += 1;
        self.imp_min = self.imp_min.min(i);
        self.imp_max = self.imp_max.max(i);
    }

    /// (mean, min, max) of the improvements over the best baseline, %, if any machine has
    /// one.
    pub fn improvement(&self) -> Option<(f64, f64, f64)> {
        (self.imp_n > 0).then(|| (self.imp_sum / self.imp_n as f64, self.imp_min, self.imp_max))
    }
}

/// What the reports show of a summary.
pub(super) struct Overview {
    /// Machines.
    pub total: u64,
    /// Failed machines ([`is_failure`]).
    pub failed: u64,
    /// Counts per family (`(unread)` for inputs that could not be read).
    pub families: BTreeMap<String, FamilyCounts>,
    /// Machines per 1 % bin of improvement ([`IMPROVEMENT_BINS`]).
    pub improvement_bins: [u64; IMPROVEMENT_BINS],
    /// The first [`REPORT_ROWS`] rows.
    pub shown: Vec<Row>,
    /// The first [`REPORT_ROWS`] failures.
    pub failures: Vec<Row>,
}

impl Overview {
    /// Reads `path` (a summary CSV) in one pass. Only the first rows and the first failures
    /// are deserialised whole; the rest only count (100 000 rows take a fraction of a second).
    pub fn read(path: &Path) -> Result<Overview, BatchError> {
        let reading = |e| BatchError::csv("cannot read", path, e);
        let mut rdr = csv::Reader::from_path(path).map_err(reading)?;
        let headers = rdr.headers().map_err(reading)?.clone();
        let col = |column: &'static str| {
            headers
                .iter()
                .position(|h| h == column)
                .ok_or_else(|| BatchError::NoColumn {
                    path: path.into(),
                    column,
                })
        };
        let (c_family, c_status, c_imp) = (col("family")?, col("status")?, col("improvement_pct")?);
        let mut o = Overview {
            total: 0,
            failed: 0,
            families: BTreeMap::new(),
            improvement_bins: [0; IMPROVEMENT_BINS],
            shown: Vec::new(),
            failures: Vec::new(),
        };
        let mut rec = csv::StringRecord::new();
        while rdr.read_record(&mut rec).map_err(reading)? {
            o.total += 1;
            let family = match &rec[c_family] {
                "" => "(unread)",
                f => f,
            };
            let status = &rec[c_status];
            let whole = || -> Result<Row, BatchError> {
                Ok(rec
                    .deserialize::<Row>(Some(&headers))
                    .map_err(reading)?
                    .csv_unescaped())
            };
            if is_failure(status) {
                o.failed += 1;
                if o.failures.len() < REPORT_ROWS {
                    o.failures.push(whole()?);
                }
            }
            if o.shown.len() < REPORT_ROWS {
                o.shown.push(whole()?);
            }
            if !o.families.contains_key(family) {
                o.families
                    .insert(family.to_string(), FamilyCounts::default());
            }
            let a = o.families.get_mut(family).expect("inserted");
            a.n += 1;
            match a.by_status.get_mut(status) {
                Some(k) => *k += 1,
                None => {
                    a.by_status.insert(status.to_string(), 1);
                }
            }
            match &rec[c_imp] {
                "" => {}
                t => {
                    let i = t.parse::<f64>().map_err(|cause| BatchError::NotANumber {
                        path: path.into(),
                        column: "improvement_pct",
                        text: t.into(),
                        cause,
                    })?;
                    a.add_improvement(i);
                    let bin = i.floor().clamp(0.0, (IMPROVEMENT_BINS - 1) as f64);
                    o.improvement_bins[bin as usize] += 1;
                }
            }
        }
        Ok(o)
    }
}

/// The plots of one machine, as its result files hold them.
pub(super) struct MachinePlots {
    /// The machine's row.
    pub row: Row,
    /// (suffix, SVG document) of each plot, in the order of its JSON's `batch.plots`.
    pub svgs: Vec<(String, String)>,
}

/// The plots of the first [`REPORT_PLOTS`] shown machines that have them: the SVG files
/// their JSON lists in `batch.plots`, beside it in the machine's folder of `layout` in the
/// output directory `top`.
pub(super) fn machine_plots(top: &Path, layout: Layout, shown: &[Row]) -> Vec<MachinePlots> {
    let mut out = Vec::new();
    for r in shown {
        if out.len() >= REPORT_PLOTS {
            break;
        }
        if crate::problem::check_name(&r.name).is_err() {
            continue;
        }
        let dir = layout.dir(top, r.index);
        let Some(b) = super::resume::read_result(&dir.join(format!("{}.json", r.name))) else {
            continue;
        };
        let Ok(v) = serde_json::from_slice::<serde_json::Value>(&b) else {
            continue;
        };
        let suffixes = v
            .pointer("/batch/plots")
            .and_then(|p| p.as_array())
            .into_iter()
            .flatten()
            .filter_map(|s| s.as_str());
        let mut svgs = Vec::new();
        for s in suffixes {
            // A plain suffix only: the JSON is input, and a plot is a file of this folder.
            let file = format!("{}-{s}.svg", r.name);
            if Path::new(&file).file_name() != Some(std::ffi::OsStr::new(&file)) {
                continue;
            }
            if let Ok(svg) = std::fs::read_to_string(dir.join(&file)) {
                if let Some(i) = svg.find("<svg") {
                    svgs.push((s.to_string(), svg[i..].to_string()));
                }
            }
        }
        if !svgs.is_empty() {
            out.push(MachinePlots {
                row: r.clone(),
                svgs,
            });
        }
    }
    out
}

/// An optional number for a table: [`fmt_num`], or `–`.
pub(super) fn opt(v: Option<f64>) -> String {
    v.map(fmt_num).unwrap_or_else(|| "–".into())
}

/// An optional error estimate for a table: `1.2e-9`, or `–`.
pub(super) fn opt_err(v: Option<f64>) -> String {
    v.map(|e| format!("{e:.1e}")).unwrap_or("–".into())
}

/// An optional improvement for a table: `6.12`, or `–`.
pub(super) fn opt_pct(v: Option<f64>) -> String {
    v.map(|i| format!("{i:.2}")).unwrap_or("–".into())
}
