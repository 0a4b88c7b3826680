//! The batch index page's histogram is the same bytes run after run: its bars are drawn in
//! bin order (plotters' own histogram series collected them in a HashMap, so their order — not
//! the picture — changed from run to run, and `index.html` with it).

use cwsynth::batch::{expand, run, Options};

#[test]
fn the_index_histogram_is_deterministic() {
    let dir = tempfile::tempdir().unwrap();
    let problems = concat!(env!("CARGO_MANIFEST_DIR"), "/problems");
    // One batch solves; the reruns into the same folder skip every finished machine and
    // draw the page again (a fresh HashMap each time, as in a new process).
    let out = dir.path().join("out");
    let svgs: Vec<String> = (0..3)
        .map(|_| {
            let opts = Options {
                out: out.clone(),
                threads: Some(2),
                shard: None,
                quiet: true,
                summary_only: true,
                units: Default::default(),
            };
            run(expand(&[problems.to_string()]).unwrap(), &opts).unwrap();
            let page = std::fs::read_to_string(out.join("index.html")).unwrap();
            let a = page.find("<svg").expect("the histogram");
            let b = page[a..].find("</svg>").unwrap();
            page[a..a + b].to_string()
        })
        .collect();
    assert!(svgs.iter().all(|s| *s == svgs[0]));
}
