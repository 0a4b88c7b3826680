//! `index.html`, the batch's one page: the family table, the histogram of improvements, the
//! first machines, the failures and the plots of the first machines that have them. Built
//! with maud (every value escaped, the markup checked at compile time) in the shared page
//! frame of [`crate::report::page`]; the histogram is drawn by [`crate::report::plot::bars`].
//! No I/O here: [`super::overview`] reads what the page shows.

use super::layout::Layout;
use super::overview::{
    opt, opt_err, opt_pct, MachinePlots, Overview, IMPROVEMENT_BINS, REPORT_ROWS,
};
use super::row::Row;
use crate::report::fmt_num;
use crate::report::page::document;
use crate::report::plot;
use maud::{html, Markup, PreEscaped};
use std::collections::HashSet;

/// The index's own style: right-aligned numbers, a scrolling machine table.
const STYLE: &str = "\
td,th{text-align:right}td.l,th.l{text-align:left}.scroll th{position:sticky;top:0}\
.plots svg{border:1px solid #eee;margin:4px 0}.cap{font-size:12px;color:#555}\
.scroll{max-height:640px;overflow:auto;border:1px solid #ddd}.scroll table{margin:0}\
td{white-space:nowrap}td.l{white-space:normal}td.n{white-space:nowrap}td.design{font-size:12px}";

/// The page, from what [`super::overview`] read: `plots` of the first machines that have
/// them, and `has_page` telling which machines have a report page (`<name>.html`); a
/// machine's files are linked in its folder of `layout`.
pub(super) fn index(
    o: &Overview,
    plots: &[MachinePlots],
    layout: Layout,
    has_page: impl Fn(&Row) -> bool,
) -> String {
    let file = |r: &Row, ext: &str| layout.href(r.index, &format!("{}.{ext}", r.name));
    let plotted: HashSet<&str> = plots.iter().map(|m| m.row.name.as_str()).collect();
    let body = html! {
        h1 { "cwsynth batch" }
        p {
            (o.total) " machines, " b { (o.failed) } " failed. Every row is in "
            a href="summary.csv" { "summary.csv" }
            @if o.total as usize > REPORT_ROWS { "; the table shows the first " (REPORT_ROWS) }
            "."
        }
        (families(o))
        @if o.improvement_bins.iter().any(|&c| c > 0) {
            h2 { "Improvement over the best classical baseline" }
            (histogram(&o.improvement_bins))
        }
        h2 { "Machines" }
        div.scroll { table {
            tr {
                th { "#" } th.l { "name" } th.l { "family" } th.l { "status" }
                th.l { "objective" } th { "value" } th { "± error" } th.l { "best baseline" }
                th { "baseline" } th { "improvement %" } th.l { "design" } th { "time ms" }
            }
            @for r in &o.shown {
                tr {
                    td { (r.index) }
                    td.l.n {
                        @if plotted.contains(r.name.as_str()) {
                            a href={ "#m-" (r.name) } { (r.name) }
                        } @else if has_page(r) {
                            a href=(file(r, "html")) { (r.name) }
                        } @else {
                            (r.name)
                        }
                    }
                    td.l.n { (r.family) }
                    td class={ "l n " (r.status) } { (r.status) }
                    td.l { (r.objective) }
                    td { (opt(r.value)) }
                    td { (opt_err(r.error)) }
                    td.l { (r.baseline) }
                    td { (opt(r.baseline_value)) }
                    td { (opt_pct(r.improvement_pct)) }
                    td.l.design { (design(&r.design)) }
                    td { (format!("{:.2}", r.time_s * 1e3)) }
                }
            }
        } }
        @if o.failed > 0 {
            h2 { "Failures (" (o.failed) ")" }
            ul {
                @for r in &o.failures {
                    li { code { (r.name) } " " span class=(r.status) { (r.status) } ": " (r.message) }
                }
                @if o.failed as usize > o.failures.len() {
                    li {
                        "… " (o.failed as usize - o.failures.len()) " more: "
                        code { "grep -E ',(error|failed|infeasible),' summary.csv" }
                    }
                }
            }
        }
        @if !plots.is_empty() {
            h2 { "Plots" }
            p.cap {
                "The first " (plots.len())
                " machines with plots; every machine's plots are beside its JSON."
            }
            @for m in plots {
                @let r = &m.row;
                h3 id={ "m-" (r.name) } {
                    (r.name) " " span class=(r.status) { "(" (r.family) ", " (r.status) ")" }
                    @if has_page(r) { " · " a href=(file(r, "html")) { "report" } }
                    " · " a href=(file(r, "md")) { "Markdown" }
                    " · " a href=(file(r, "json")) { "JSON" }
                }
                div.plots {
                    @for (suffix, svg) in &m.svgs {
                        div.cap { (suffix) }
                        // A plot cwsynth wrote beside the machine's JSON.
                        (PreEscaped(svg))
                    }
                }
            }
        }
    };
    document("cwsynth batch", STYLE, body)
}

/// The family table: machines, statuses and the improvement over the best baseline.
fn families(o: &Overview) -> Markup {
    html! {
        table {
            tr {
                th.l { "family" } th { "machines" } th.l { "by status" }
                th { "mean improvement %" } th { "min–max %" }
            }
            @for (f, a) in &o.families {
                @let imp = a.improvement();
                tr {
                    td.l { (f) }
                    td { (a.n) }
                    td.l {
                        @for (k, (s, n)) in a.by_status.iter().enumerate() {
                            @if k > 0 { ", " }
                            span class=(s) { (s) } " " (n)
                        }
                    }
                    td { (imp.map_or("–".into(), |(mean, _, _)| format!("{mean:.2}"))) }
                    td { (imp.map_or("–".into(), |(_, lo, hi)| format!("{lo:.2}–{hi:.2}"))) }
                }
            }
        }
    }
}

/// The improvement histogram (1 % bins, the last `19+`), drawn by plotters.
fn histogram(bins: &[u64; IMPROVEMENT_BINS]) -> Markup {
    let labelled: Vec<(String, u64)> = bins
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let plus = if k + 1 == IMPROVEMENT_BINS { "+" } else { "" };
            (format!("{k}{plus}"), c)
        })
        .collect();
    let svg = plot::bars(
        &labelled,
        "improvement of the optimum over the best classical baseline (%, 1 % bins)",
        "machines (count)",
        760,
        260,
    );
    match svg {
        Ok(svg) => html! { div.plots { (PreEscaped(svg)) } },
        Err(e) => html! { p.cap { "histogram not drawn: " (e) } },
    }
}

/// A row's design `k=v;…` for reading: `k = v, …` with numbers in [`fmt_num`].
fn design(d: &str) -> String {
    d.split(';')
        .filter(|s| !s.is_empty())
        .map(|kv| match kv.split_once('=') {
            Some((k, v)) => format!(
                "{k} = {}",
                v.parse::<f64>().map(fmt_num).unwrap_or(v.into())
            ),
            None => kv.into(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}
