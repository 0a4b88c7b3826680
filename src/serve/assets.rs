//! The designer's page, its scripts and its style, compiled into the binary so that the page
//! works offline (no CDN). Plain HTML, CSS and JavaScript with no build step: the page draws
//! the plots of x–y panels itself with uPlot (`vendor/`, the npm package's files as
//! `scripts/vendor.sh` copies them; MIT, its licence served beside it), the others as the
//! server's own SVG (plotters), and builds every element with `textContent`, so no text from
//! a problem file or a result is ever parsed as HTML.

use axum::http::header;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;

const HTML: &str = "text/html; charset=utf-8";
const JS: &str = "text/javascript; charset=utf-8";
const CSS: &str = "text/css; charset=utf-8";

/// Every file the page loads: (route, content type, body).
const ASSETS: &[(&str, &str, &str)] = &[
    ("/", HTML, include_str!("assets/index.html")),
    ("/app.js", JS, include_str!("assets/app.js")),
    ("/app.css", CSS, include_str!("assets/app.css")),
    // The form generated from the problem file's schema.
    ("/form.js", JS, include_str!("assets/form.js")),
    // The plots drawn in the page.
    ("/plots.js", JS, include_str!("assets/plots.js")),
    // The plotting library (uPlot), its style and its licence (MIT).
    (
        "/vendor/uPlot.iife.min.js",
        JS,
        include_str!("assets/vendor/uPlot.iife.min.js"),
    ),
    (
        "/vendor/uPlot.min.css",
        CSS,
        include_str!("assets/vendor/uPlot.min.css"),
    ),
    (
        "/vendor/uPlot.LICENSE",
        "text/plain; charset=utf-8",
        include_str!("assets/vendor/uPlot.LICENSE"),
    ),
];

/// `r` with a `GET` route for every file of [`ASSETS`].
pub(super) fn routes<S: Clone + Send + Sync + 'static>(mut r: Router<S>) -> Router<S> {
    for &(path, kind, body) in ASSETS {
        r = r.route(path, get(move || async move { asset(kind, body) }));
    }
    r
}

fn asset(kind: &'static str, body: &'static str) -> Response {
    ([(header::CONTENT_TYPE, kind)], body).into_response()
}
