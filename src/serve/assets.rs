//! The designer's page, its script and its style, compiled into the binary so that the page
//! works offline (no CDN). Plain HTML, CSS and JavaScript with no build step: the page draws
//! the server's own plots (plotters' SVG) and builds every element with `textContent`, so no
//! text from a problem file or a result is ever parsed as HTML.

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

/// `GET /app.css`.
pub(super) fn style() -> Response {
    asset("text/css; charset=utf-8", include_str!("assets/app.css"))
}

fn asset(kind: &'static str, body: &'static str) -> Response {
    ([(header::CONTENT_TYPE, kind)], body).into_response()
}
