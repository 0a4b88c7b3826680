//! The run's reports, written from its `summary.csv` after the commit (or a merge):
//! `summary.md` here and `index.html` by [`super::html`], both from one [`Overview`].

use super::error::BatchError;
use super::html;
use super::layout::{Layout, MACHINES_DIR, MACHINES_PER_FOLDER};
use super::overview::{machine_plots, opt, opt_err, opt_pct, Overview, REPORT_ROWS};
use super::row::Row;
use crate::report::{md_escape, truncate, write_atomic};
use std::path::Path;

/// Writes `summary.md` and `index.html` from `DIR/summary.csv` (streaming; tables capped at
/// [`REPORT_ROWS`] rows, plots inlined for the first [`REPORT_PLOTS`] machines that have
/// them).
///
/// A machine's files are looked for, and linked, in its folder of the run's [`Layout`] (of
/// the summary's row count): `machines/NNN/` in a large run, else beside the summary.
pub fn write_reports(dir: &Path) -> Result<(), BatchError> {
    let o = Overview::read(&dir.join("summary.csv"))?;
    let layout = Layout::of_run(o.total);
    // Only where machine folders were written (not with `--summary-only`).
    let folders = layout.folders && dir.join(MACHINES_DIR).is_dir();
    write_atomic(&dir.join("summary.md"), markdown(&o, folders).as_bytes())
        .map_err(BatchError::Written)?;
    let plots = machine_plots(dir, layout, &o.shown);
    // A machine's report page, where its files were written (not with `--summary-only`).
    let has_page = |r: &Row| {
        !r.failed()
            && crate::problem::check_name(&r.name).is_ok()
            && layout
                .dir(dir, r.index)
                .join(format!("{}.html", r.name))
                .is_file()
    };
    let page = html::index(&o, &plots, layout, has_page);
    write_atomic(&dir.join("index.html"), page.as_bytes()).map_err(BatchError::Written)
}

/// `summary.md`; `folders`: the machines' files are in folders `machines/NNN/`.
fn markdown(o: &Overview, folders: bool) -> String {
    let (total, n_fail) = (o.total, o.failed);
    let mut md = String::new();
    md += &format!(
        "# Batch summary\n\n{total} machines, {n_fail} failed. Every row is in `summary.csv`"
    );
    md += if total as usize > REPORT_ROWS {
        " (this page shows the first rows only).\n\n"
    } else {
        ".\n\n"
    };
    if folders {
        md += &format!(
            "Each machine's files are in `{MACHINES_DIR}/NNN/`, NNN = its index ÷ {MACHINES_PER_FOLDER} (machine 1234: `{MACHINES_DIR}/001/`).\n\n"
        );
    }
    md += "| family | machines | by status | improvement over best baseline (mean, min–max) |\n|---|---|---|---|\n";
    for (f, a) in &o.families {
        md += &format!(
            "| {} | {} | {} | {} |\n",
            md_escape(f),
            a.n,
            a.by_status
                .iter()
                .map(|(s, n)| format!("{s} {n}"))
                .collect::<Vec<_>>()
                .join(", "),
            match a.improvement() {
                Some((mean, min, max)) => format!("{mean:.2} % ({min:.2}–{max:.2})"),
                None => "–".into(),
            }
        );
    }
    md += "\n## Machines\n\n| # | name | family | status | objective | value | ± error | best baseline | baseline value | improvement % | time (ms) |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in &o.shown {
        md += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |\n",
            r.index,
            md_escape(&r.name),
            md_escape(&r.family),
            md_escape(&r.status),
            md_escape(&r.objective),
            opt(r.value),
            opt_err(r.error),
            if r.baseline.is_empty() {
                "–".to_string()
            } else {
                md_escape(&r.baseline)
            },
            opt(r.baseline_value),
            opt_pct(r.improvement_pct),
            r.time_s * 1e3
        );
    }
    if n_fail > 0 {
        md += &format!("\n## Failures ({n_fail})\n\n");
        for r in &o.failures {
            md += &format!(
                "- {} ({}): {}\n",
                md_escape(&r.name),
                md_escape(&r.status),
                md_escape(&truncate(&r.message, 2000))
            );
        }
        if n_fail as usize > o.failures.len() {
            md += &format!(
                "- … {} more: `grep -E ',(error|failed|infeasible),' summary.csv`\n",
                n_fail as usize - o.failures.len()
            );
        }
    }
    md
}
