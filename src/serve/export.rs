//! `POST /api/export`: a result's files for the designer's downloads — the report as one
//! self-contained HTML page (its plots and drawings inlined as `data:` URIs, so the page
//! opens alone from a download folder), the drawing's DXF, and the JSON — made by the same
//! writers as `cwsynth solve --out` (`report::report_files`).

use crate::report::{json_text, report_files, SolveResult};
use std::path::Path;

/// What can be exported.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Export {
    /// `<name>.html`, self-contained.
    Html,
    /// `<name>-drawing.dxf` (the first drawing).
    Dxf,
    /// `<name>.json`.
    Json,
}

impl Export {
    /// The query's `what=`: `html`, `dxf` or `json`.
    pub fn parse(what: &str) -> Option<Export> {
        match what {
            "html" => Some(Export::Html),
            "dxf" => Some(Export::Dxf),
            "json" => Some(Export::Json),
            _ => None,
        }
    }
}

/// The exported file of the completed result `r`: (file name, content type, bytes); `None`
/// where the result has no such file (no drawing).
pub fn export(r: &SolveResult, what: Export) -> Option<(String, &'static str, Vec<u8>)> {
    let files = report_files(r, Path::new(""));
    let named = |name: &str| files.iter().find(|(p, _)| p == Path::new(name));
    match what {
        Export::Json => Some((
            format!("{}.json", r.name),
            "application/json",
            json_text(r).into_bytes(),
        )),
        Export::Dxf => {
            let d = r.drawings.first()?;
            let name = format!("{}-{}.dxf", r.name, d.suffix);
            let bytes = named(&name)?.1.clone();
            Some((name, "application/dxf", bytes))
        }
        Export::Html => {
            let name = format!("{}.html", r.name);
            let mut page = String::from_utf8_lossy(&named(&name)?.1).into_owned();
            for (path, bytes) in &files {
                let file = path.to_string_lossy();
                if file.ends_with(".svg") {
                    let from = format!("src=\"{file}\"");
                    let to = format!(
                        "src=\"data:image/svg+xml;charset=utf-8,{}\"",
                        percent(bytes)
                    );
                    page = page.replace(&from, &to);
                }
            }
            Some((name, "text/html; charset=utf-8", page.into_bytes()))
        }
    }
}

/// `bytes` percent-encoded for a `data:` URI (every byte but the unreserved ones, RFC 3986
/// §2.3): a `data:` SVG needs no base64, and this is the whole of the encoding a crate
/// would add.
fn percent(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len() * 3 / 2);
    for &b in bytes {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}
