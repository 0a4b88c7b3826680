//! Issue 16: the batch's pages. Each machine's report is also a page (`<name>.html`, listed in
//! the resume manifest, linked from `index.html`, without the wall times so it is the same in
//! every run); text from input stays text in every page (maud and pulldown-cmark escape it);
//! and `--summary-only` evaluates no machine's plot: the index's improvement histogram is its
//! one drawing. Run in process through `batch::run`, in one test, so the process-wide count of
//! drawn documents sees this batch only.

use cwsynth::batch::{expand, run, Options};
use cwsynth::report::plot::documents_drawn_in_process;
use std::path::Path;

const TEMPLATE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/piston-1000rpm.toml");

/// Three good machines (one with markup in its description, one named by the template) and
/// two error rows whose names and cells carry markup.
const FLEET: &str = "name,mechanism.slider_mass,description
plain-a,1.0 kg,<script>alert(1)</script> *not emphasis* | a pipe
<img src=x onerror=alert(1)>,1.1 kg,
plain-b,1.2 kg,
bad-unit,1.3 <b>furlong</b>,
,1.4 kg,
";

fn batch(fleet: &Path, out: &Path, summary_only: bool) -> cwsynth::batch::Counts {
    let input = format!("{TEMPLATE}:{}", fleet.display());
    let opts = Options {
        out: out.into(),
        threads: Some(2),
        shard: None,
        quiet: true,
        summary_only,
        units: Default::default(),
    };
    run(expand(&[input]).unwrap(), &opts).unwrap()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn report_pages_are_written_linked_and_escaped_and_summary_only_draws_no_plot() {
    let d = tempfile::tempdir().unwrap();
    let fleet = d.path().join("fleet.csv");
    std::fs::write(&fleet, FLEET).unwrap();

    // --summary-only: no machine's plot is drawn, only the index's histogram.
    let before = documents_drawn_in_process();
    let c = batch(&fleet, &d.path().join("so"), true);
    assert_eq!((c.total, c.ok, c.failed), (5, 3, 2));
    assert_eq!(
        documents_drawn_in_process() - before,
        1,
        "summary-only drew a plot"
    );
    let so = d.path().join("so");
    assert!(!so.join("plain-a.html").exists() && !so.join("plain-a.json").exists());
    let index = read(&so.join("index.html"));
    assert!(index.contains("<svg"), "the histogram");
    // No page to link: the names are plain text.
    assert!(!index.contains("href=\"plain-a.html\""));

    // With per-machine files: each plot is drawn once, when written, and every report has
    // its page.
    let out = d.path().join("out");
    let before = documents_drawn_in_process();
    batch(&fleet, &out, false);
    assert_eq!(
        documents_drawn_in_process() - before,
        3 + 1,
        "one plot per machine"
    );
    for name in ["plain-a", "plain-b", "piston-1000rpm-5"] {
        let page = read(&out.join(format!("{name}.html")));
        assert!(page.starts_with("<!DOCTYPE html>"), "{name}");
        assert!(
            page.contains("<table>") && page.contains("<th>quantity</th>"),
            "{name}"
        );
        assert!(
            page.contains(&format!("<img src=\"{name}-shaking-force.svg\"")),
            "{name}"
        );
        assert!(page.contains(&format!("href=\"{name}.md\"")), "{name}");
        // No wall time: the page is the same in every run.
        assert!(read(&out.join(format!("{name}.md"))).contains(" ms, total "));
        assert!(!page.contains(" ms, total "), "{name}");
        // Listed in the manifest with its size.
        let v: serde_json::Value =
            serde_json::from_str(&read(&out.join(format!("{name}.json")))).unwrap();
        let listed = &v["batch"]["files"][format!("{name}.html")];
        assert_eq!(listed["bytes"].as_u64(), Some(page.len() as u64), "{name}");
    }
    // Input markup is text in the page (a description is echoed in the report).
    let page = read(&out.join("plain-a.html"));
    assert!(!page.contains("<script"), "{page}");
    assert!(
        page.contains("&lt;script&gt;alert(1)&lt;/script&gt;"),
        "{page}"
    );
    assert!(!page.contains("<em>"), "{page}");

    let index = read(&out.join("index.html"));
    assert!(index.starts_with("<!DOCTYPE html>"));
    // Every plotted machine's heading links its page, its Markdown and its JSON.
    for name in ["plain-a", "plain-b", "piston-1000rpm-5"] {
        for link in [".html", ".md", ".json"] {
            assert!(
                index.contains(&format!("href=\"{name}{link}\"")),
                "{name}{link}"
            );
        }
        assert!(index.contains(&format!("href=\"#m-{name}\"")), "{name}");
    }
    // The hostile name and cell are escaped wherever they appear.
    assert!(!index.contains("<img") && !index.contains("<b>furlong") && !index.contains("<script"));
    assert!(
        index.contains("&lt;img src=x onerror=alert(1)&gt;"),
        "{index}"
    );
    assert!(index.contains("&lt;b&gt;furlong&lt;/b&gt;"), "{index}");

    // A re-run finds every machine whole (pages included) and skips it; a torn page is redone.
    let page = out.join("plain-b.html");
    let whole = read(&page);
    std::fs::write(&page, &whole[..whole.len() / 2]).unwrap();
    let c = batch(&fleet, &out, false);
    assert_eq!(c.skipped, 2);
    assert_eq!(read(&page), whole);
}
