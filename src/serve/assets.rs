//! The designer's page, its scripts and its style, compiled into the binary so that the page
//! works offline (no CDN). Plain HTML, CSS and JavaScript with no build step: the page draws
//! the plots of x–y panels itself with uPlot (`vendor/`, the npm package's files as
//! `scripts/vendor.sh` copies them; MIT, its licence served beside it), the others as the
//! server's own SVG (plotters), and builds every element with `textContent`, so no text from
//! a problem file or a result is ever parsed as HTML.

use axum::http::header;
use axum::response::{IntoResponse, Response};

/// `GET /`.
pub(super) fn page() -> Response {
    asset(
        "text/html; charset=utf-8",
        include_str!("assets/index.html"),
    )
}

/// `GET /app.js`.
pub(super) fn script() -> Response {
    asset(
        "text/javascript; charset=utf-8",
        include_str!("assets/app.js"),
    )
}

/// `GET /form.js`: the form generated from the problem file's schema.
pub(super) fn form_script() -> Response {
    asset(
        "text/javascript; charset=utf-8",
        include_str!("assets/form.js"),
    )
}

/// `GET /plots.js`: the plots drawn in the page.
pub(super) fn plots_script() -> Response {
    asset(
        "text/javascript; charset=utf-8",
        include_str!("assets/plots.js"),
    )
}

/// `GET /vendor/uPlot.iife.min.js`: the plotting library (uPlot).
pub(super) fn uplot_script() -> Response {
    asset(
        "text/javascript; charset=utf-8",
        include_str!("assets/vendor/uPlot.iife.min.js"),
    )
}

/// `GET /vendor/uPlot.min.css`: the plotting library's style.
pub(super) fn uplot_style() -> Response {
    asset(
        "text/css; charset=utf-8",
        include_str!("assets/vendor/uPlot.min.css"),
    )
}

/// `GET /vendor/uPlot.LICENSE`: the plotting library's licence (MIT).
pub(super) fn uplot_license() -> Response {
    asset(
        "text/plain; charset=utf-8",
        include_str!("assets/vendor/uPlot.LICENSE"),
    )
}

/// `GET /app.css`.
pub(super) fn style() -> Response {
    asset("text/css; charset=utf-8", include_str!("assets/app.css"))
}

fn asset(kind: &'static str, body: &'static str) -> Response {
    ([(header::CONTENT_TYPE, kind)], body).into_response()
}
