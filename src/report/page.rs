//! HTML pages: a result's Markdown report rendered as a readable page (`<name>.html` beside
//! `<name>.md`, so a browser shows tables and plots instead of raw Markdown), and the page
//! frame and style every cwsynth page shares (the batch's `index.html` too).
//!
//! Pages are self-contained (inline style, no script, no network) and built with maud, which
//! escapes every value it inserts; Markdown is rendered by pulldown-cmark with raw HTML shown
//! as text, since a report's text comes partly from input (names, notes, messages).

use super::{markdown_report, SolveResult};
use maud::{html, Markup, PreEscaped, DOCTYPE};
use pulldown_cmark::{Event, Options, Parser};

/// The style of every page.
const STYLE: &str = "\
body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;margin:24px;color:#222;max-width:1350px;line-height:1.4}\
h1{font-size:24px}h2{font-size:19px;margin-top:32px;border-bottom:1px solid #ccc}h3{font-size:16px;margin:20px 0 6px}\
table{border-collapse:collapse;font-size:13px;margin:8px 0}td,th{border:1px solid #ddd;padding:3px 7px;vertical-align:top}\
th{background:#f2f2f2}tr:nth-child(even){background:#fafafa}\
code{font-size:90%;background:#f4f4f4;padding:0 3px;border-radius:3px}\
img,svg{max-width:100%;height:auto}nav{font-size:13px;color:#555;margin-bottom:8px}\
.optimal{color:#1a7f37}.best_found{color:#1a7f37;font-style:italic}.analysed{color:#0550ae}\
.inaccurate,.degenerate{color:#9a6700}.infeasible,.failed,.error{color:#cf222e;font-weight:600}";

/// A whole page: its `title`, the shared style and `style` (the page's own rules), and
/// `body`.
pub fn document(title: &str, style: &str, body: Markup) -> String {
    html! {
        (DOCTYPE)
        html lang="en" {
            head {
                meta charset="utf-8";
                meta name="viewport" content="width=device-width, initial-scale=1";
                title { (title) }
                style { (PreEscaped(STYLE)) (PreEscaped(style)) }
            }
            body { (body) }
        }
    }
    .into_string()
        + "\n"
}

/// Markdown (CommonMark with tables) as HTML. Raw HTML in the text is shown as text, never
/// passed through.
pub fn markdown_html(md: &str) -> String {
    let events = Parser::new_ext(md, Options::ENABLE_TABLES).map(|e| match e {
        Event::Html(t) | Event::InlineHtml(t) => Event::Text(t),
        e => e,
    });
    let mut out = String::new();
    pulldown_cmark::html::push_html(&mut out, events);
    out
}

/// The page of a result, `<name>.html`: its Markdown report without the wall times (so the
/// page is the same in every run; the times are in `<name>.md` and `<name>.json`), with
/// links to both. Its plots are the SVG files beside it.
pub fn result_page(r: &SolveResult) -> String {
    let body = html! {
        nav {
            a href={ (r.name) ".md" } { "Markdown" }
            " · "
            a href={ (r.name) ".json" } { "JSON" }
            " · the times of the solve are in both"
        }
        (PreEscaped(markdown_html(&markdown_report(r, false))))
    };
    // A wide table (many baselines) scrolls by itself instead of widening the page.
    let style = "table{display:block;overflow-x:auto;max-width:100%}";
    document(&format!("{} ({})", r.name, r.family), style, body)
}
