//! The HTTP API the designer's page and other tools use (docs/serve.md): every route, its
//! limits, and its JSON errors `{"error": {"file", "line", "field", "message"}}`.

use super::{assets, State};
use crate::families::{self, Scene};
use crate::problem::ProblemError;
use axum::extract::{Path as UrlPath, Request, State as Shared};
use axum::http::{header, HeaderValue, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use serde_json::{json, Value};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// The Content-Security-Policy of every answer: the binary's own scripts and styles only (the
/// plotting library among them: it evaluates no strings and sets styles through the CSSOM
/// only), images from itself or inline data (the SVG plots), no plugins, frames or foreign
/// forms.
const CSP: &str = "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data:; object-src 'none'; base-uri 'none'; frame-ancestors 'none'; form-action 'none'";

/// The routes on the shared state.
pub(super) fn routes(state: Arc<State>) -> Router {
    let api = Router::new()
        .route("/api/solve", post(solve))
        .route("/api/report", post(report))
        .route("/api/check", post(check))
        .route("/api/edit", post(edit))
        .route("/api/fields", post(fields))
        .route("/api/export", post(export))
        .route("/api/templates", get(templates))
        .route("/api/schema", get(schema))
        .route("/api/files", get(files))
        .route("/api/file/{name}", get(file))
        .route_layer(middleware::from_fn_with_state(state.clone(), token));
    assets::routes(Router::new())
        .route("/favicon.ico", get(|| async { StatusCode::NO_CONTENT }))
        .merge(api)
        .fallback(|| async { error(StatusCode::NOT_FOUND, None, None, "no such page or route") })
        .layer(middleware::map_response(secure))
        .with_state(state)
}

/// The headers every answer carries.
async fn secure(mut r: Response) -> Response {
    let h = r.headers_mut();
    h.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(CSP),
    );
    h.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    h.insert(
        header::REFERRER_POLICY,
        HeaderValue::from_static("no-referrer"),
    );
    h.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    r
}

/// With a token, every API request carries `Authorization: Bearer <token>`.
async fn token(Shared(st): Shared<Arc<State>>, req: Request, next: Next) -> Response {
    if let Some(t) = &st.opts.token {
        let given = req
            .headers()
            .get(header::AUTHORIZATION)
            .and_then(|v| v.to_str().ok())
            .and_then(|v| v.strip_prefix("Bearer "));
        if given != Some(t.as_str()) {
            return error(
                StatusCode::UNAUTHORIZED,
                None,
                None,
                "this server needs its token: Authorization: Bearer <token> (printed when it started)",
            );
        }
    }
    next.run(req).await
}

/// A JSON error answer.
pub(super) fn error(
    status: StatusCode,
    file: Option<&str>,
    line: Option<usize>,
    message: &str,
) -> Response {
    let body =
        json!({"error": {"file": file, "line": line, "field": Value::Null, "message": message}});
    (status, json_headers(), body.to_string()).into_response()
}

/// A problem file's error as a JSON answer (400): its file, line, field and message.
fn problem_error(e: &ProblemError) -> Response {
    let (file, message) = match e {
        ProblemError::Invalid { file, message, .. } => {
            (file.display().to_string(), message.clone())
        }
        ProblemError::Read { file, source } => (file.display().to_string(), source.to_string()),
    };
    let body =
        json!({"error": {"file": file, "line": e.line(), "field": e.field(), "message": message}});
    (StatusCode::BAD_REQUEST, json_headers(), body.to_string()).into_response()
}

fn json_headers() -> [(header::HeaderName, &'static str); 1] {
    [(header::CONTENT_TYPE, "application/json")]
}

fn json_answer(v: &Value) -> Response {
    (StatusCode::OK, json_headers(), v.to_string()).into_response()
}

/// The request's problem file: its body ([`body_of`]) read as a file named by the query's `name` (a bare file name, default
/// `request.toml`), its drawings read from the served folder; a drawing path must stay
/// inside it ([`confined`]).
async fn problem(st: &State, req: Request) -> Result<Scene, Response> {
    let (name, bytes) = named_body(st, req).await?;
    // The file is named by its bare name (no server path in a message or the result); its
    // drawings are read from the served folder.
    let path = PathBuf::from(&name);
    if let Some(e) = confined(&bytes, &path) {
        return Err(problem_error(&e));
    }
    match std::str::from_utf8(&bytes) {
        Ok(text) => families::parse_str_in(text, &path, &st.root),
        Err(_) => families::parse_bytes(&bytes, &path),
    }
    .map_err(|e| problem_error(&e))
}

/// The request's file name (the query's bare `name=`, default `request.toml`) and its body
/// ([`body_of`], at most `max_body` bytes), or the located error.
async fn named_body(st: &State, req: Request) -> Result<(String, axum::body::Bytes), Response> {
    let name = file_name(req.uri().query())
        .unwrap_or("request.toml")
        .to_string();
    let bytes = body_of(&st.opts, req.into_body(), st.opts.max_body)
        .await
        .map_err(|(status, why)| error(status, Some(&name), None, &why))?;
    Ok((name, bytes))
}

/// A request body of at most `limit` bytes sent within `opts.body_time`; else the status
/// (408, 413) and why.
async fn body_of(
    opts: &super::Options,
    body: axum::body::Body,
    limit: usize,
) -> Result<axum::body::Bytes, (StatusCode, String)> {
    match tokio::time::timeout(opts.body_time, axum::body::to_bytes(body, limit)).await {
        Ok(Ok(b)) => Ok(b),
        Err(_) => Err((
            StatusCode::REQUEST_TIMEOUT,
            format!(
                "the request body did not arrive within {} s",
                opts.body_time.as_secs_f64()
            ),
        )),
        Ok(Err(_)) => Err((
            StatusCode::PAYLOAD_TOO_LARGE,
            format!("the request body is over {limit} bytes"),
        )),
    }
}

/// The value of `key=` in the query, if any.
fn query_value<'q>(query: Option<&'q str>, key: &str) -> Option<&'q str> {
    query?
        .split('&')
        .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
}

/// A bare file name: letters, digits, `.`, `-`, `_`, not starting with `.`, at most 128
/// characters (no path, nothing hidden).
fn bare_name(v: &str) -> bool {
    !v.is_empty()
        && v.len() <= 128
        && !v.starts_with('.')
        && v.chars()
            .all(|c| c.is_ascii_alphanumeric() || "._-".contains(c))
}

/// The query's `name=`, where it is a [`bare_name`].
fn file_name(query: Option<&str>) -> Option<&str> {
    query_value(query, "name").filter(|v| bare_name(v))
}

/// A drawing (`file` key anywhere in the problem) named outside the served folder: an
/// absolute path or one with `..` — the client names no file outside it.
fn confined(bytes: &[u8], path: &Path) -> Option<ProblemError> {
    let text = std::str::from_utf8(bytes).ok()?;
    let doc: toml::Table = toml::from_str(text).ok()?;
    let mut bad = None;
    walk(&toml::Value::Table(doc), "", &mut |key, v| {
        let Some(s) = v.as_str() else { return };
        let p = Path::new(s);
        let outside = p.is_absolute()
            || p.components()
                .any(|c| !matches!(c, Component::Normal(_) | Component::CurDir));
        if key.ends_with(".file") && outside && bad.is_none() {
            bad = Some(ProblemError::Invalid {
                file: path.into(),
                line: text.lines().position(|l| l.contains(s)).map(|i| i + 1),
                field: Some(key.to_string()),
                message: format!(
                    "\"{s}\": allowed: a drawing inside the served folder, named relative to it"
                ),
            });
        }
    });
    bad
}

/// Calls `f` on every value of `v` with its dotted key.
fn walk(v: &toml::Value, key: &str, f: &mut dyn FnMut(&str, &toml::Value)) {
    match v {
        toml::Value::Table(t) => {
            for (k, x) in t {
                let sub = if key.is_empty() {
                    k.clone()
                } else {
                    format!("{key}.{k}")
                };
                walk(x, &sub, f);
            }
        }
        toml::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                walk(x, &format!("{key}[{i}]"), f);
            }
        }
        other => f(key, other),
    }
}

/// What a solve makes beside its numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Documents {
    /// Nothing (`cwsynth solve --json`).
    None,
    /// The plots, drawings and motion ([`crate::report::SolveResult::draw`]).
    Drawn,
    /// Everything the written files carry ([`crate::report::SolveResult::complete`]).
    Complete,
}

/// Solves `scene` on a blocking thread, at most `max_solves` at once, within the solve
/// budget: the result with its `documents`, or a JSON error (over the budget, or a panic of
/// the solve, which fails this request only).
async fn solved(
    st: &Arc<State>,
    scene: Scene,
    documents: Documents,
) -> Result<crate::report::SolveResult, Response> {
    let budget = st.opts.solve_budget;
    let name = scene.source.display().to_string();
    let run = async {
        let permit = st
            .solves
            .clone()
            .acquire_owned()
            .await
            .expect("never closed");
        tokio::task::spawn_blocking(move || {
            let _running = permit;
            crate::batch::isolate(|| {
                let mut r = families::solve_scene(&scene);
                match documents {
                    Documents::None => {}
                    Documents::Drawn => r.draw(),
                    Documents::Complete => r.complete(),
                }
                r
            })
        })
        .await
    };
    match tokio::time::timeout(budget, run).await {
        Err(_) => Err(error(StatusCode::SERVICE_UNAVAILABLE, Some(&name), None, &format!(
            "the solve took longer than its budget of {} s; the server goes on (a smaller problem, or `cwsynth solve` on the command line)",
            budget.as_secs_f64()
        ))),
        Ok(Err(_)) | Ok(Ok(Err(_))) => Err(error(StatusCode::INTERNAL_SERVER_ERROR, Some(&name), None,
            "the solve stopped on an internal error (a bug: please report it with the problem file); the server goes on")),
        Ok(Ok(Ok(r))) => Ok(r),
    }
}

/// `POST /api/solve`: the problem file's result, the same JSON object as
/// `cwsynth solve FILE --json` prints.
async fn solve(Shared(st): Shared<Arc<State>>, req: Request) -> Response {
    let scene = match problem(&st, req).await {
        Ok(s) => s,
        Err(r) => return r,
    };
    match solved(&st, scene, Documents::None).await {
        Ok(r) => json_answer(&r.to_json()),
        Err(r) => r,
    }
}

/// `POST /api/report[?plots=data]`: the result and its plots, for the page: `{"result": …,
/// "plots": [{"suffix", "caption", "svg", "width", "height", "panels"}], "motion": …,
/// "units": {key: [words, unit, factor]}}` ([`plot_json`]; `plots=data`: a plot of panels
/// without its `svg`).
///
/// `digits=D` (1–17; the page asks for 7): the drawing's and the plots' numbers — the
/// motion's `bodies`, `frames`, `guides` and `marks`, the panels' points — rounded to D significant
/// digits ([`round_drawn`]), which a screen cannot tell apart and which halves the answer of
/// a scene with long outlines; the result's numbers and the handles' values stay exact.
async fn report(Shared(st): Shared<Arc<State>>, req: Request) -> Response {
    let query = req.uri().query();
    let svg_of_panels = query_value(query, "plots") != Some("data");
    let digits = match query_value(query, "digits").map(str::parse::<i32>) {
        None => None,
        Some(Ok(d)) if (1..=17).contains(&d) => Some(d),
        Some(_) => {
            return error(
                StatusCode::BAD_REQUEST,
                None,
                None,
                "digits: a whole number of significant digits from 1 to 17",
            )
        }
    };
    let scene = match problem(&st, req).await {
        Ok(s) => s,
        Err(r) => return r,
    };
    match solved(&st, scene, Documents::Drawn).await {
        Ok(r) => {
            let mut plots: Vec<Value> = r
                .plots
                .iter()
                .map(|p| plot_json(p, svg_of_panels))
                .collect();
            let result = r.to_json();
            let units = workshop_units(&result);
            let mut motion = r.motion;
            if let Some(d) = digits {
                for p in &mut plots {
                    round_drawn(&mut p["panels"], d);
                }
                if let Some(Value::Object(m)) = &mut motion {
                    for (_, v) in m.iter_mut().filter(|(k, _)| *k != "handles") {
                        round_drawn(v, d);
                    }
                }
            }
            json_answer(
                &json!({"result": result, "plots": plots, "motion": motion, "units": units}),
            )
        }
        Err(r) => r,
    }
}

/// Every number of `v` (recursively) that is not an integer rounded to `digits` significant
/// digits: x ↦ round(x·10^k)/10^k with k = digits − 1 − ⌊log₁₀|x|⌋, which JSON then writes
/// in at most about `digits` digits (its shortest form that reads back the same double).
fn round_drawn(v: &mut Value, digits: i32) {
    match v {
        Value::Array(a) => a.iter_mut().for_each(|x| round_drawn(x, digits)),
        Value::Object(o) => o.values_mut().for_each(|x| round_drawn(x, digits)),
        Value::Number(n) if n.is_f64() => {
            let x = n.as_f64().unwrap_or(0.0);
            if x != 0.0 && x.is_finite() {
                let k = digits - 1 - x.abs().log10().floor() as i32;
                let r = match k >= 0 {
                    true => (x * 10f64.powi(k)).round() / 10f64.powi(k),
                    false => (x / 10f64.powi(-k)).round() * 10f64.powi(-k),
                };
                if let Some(m) = serde_json::Number::from_f64(r) {
                    *n = m;
                }
            }
        }
        _ => {}
    }
}

/// One plot of `/api/report`: `{"suffix", "caption", "svg"}` (the report's SVG document, or
/// one that says why it was not drawn); a plot of x–y panels also carries its data,
/// `"width"`, `"height"` (each panel's nominal size, px) and `"panels"`
/// ([`crate::report::plot::Figure::to_json`]), and its `svg` only where `svg_of_panels`
/// (the page draws the panels itself).
fn plot_json(p: &crate::report::Plot, svg_of_panels: bool) -> Value {
    let mut v = json!({"suffix": p.suffix, "caption": p.caption});
    match p.figure() {
        None => v["svg"] = json!(p.svg_or_note()),
        Some(Err(e)) => v["svg"] = json!(crate::report::plot_note(&e)),
        Some(Ok(figure)) => {
            if svg_of_panels {
                let svg = figure
                    .svg()
                    .unwrap_or_else(|e| crate::report::plot_note(&e));
                v["svg"] = json!(svg);
            }
            if let (Value::Object(o), Value::Object(data)) = (&mut v, figure.to_json()) {
                o.extend(data);
            }
        }
    }
    v
}

/// `POST /api/edit`: `{"text", "key", "value"}` → `{"text"}`, the file with the key set
/// ([`super::edit::set_key`]: its comments and layout kept).
async fn edit(Shared(st): Shared<Arc<State>>, req: Request) -> Response {
    let bytes = match body_of(&st.opts, req.into_body(), 2 * st.opts.max_body).await {
        Ok(b) => b,
        Err((status, why)) => return error(status, None, None, &why),
    };
    let asked: Value = match serde_json::from_slice(&bytes) {
        Ok(v) => v,
        Err(e) => {
            return error(
                StatusCode::BAD_REQUEST,
                None,
                None,
                &format!("not JSON: {e}"),
            )
        }
    };
    let (Some(text), Some(key), Some(value)) = (
        asked["text"].as_str(),
        asked["key"].as_str(),
        asked.get("value"),
    ) else {
        return error(
            StatusCode::BAD_REQUEST,
            None,
            None,
            "allowed: {\"text\": …, \"key\": …, \"value\": …}",
        );
    };
    match super::edit::set_key(text, key, value) {
        Ok(text) => json_answer(&json!({ "text": text })),
        Err(why) => error(StatusCode::BAD_REQUEST, None, None, &why),
    }
}

/// `POST /api/fields`: the problem file's values as JSON for the page's form, `{"values":
/// {…}, "keys": [["dotted.key", line], …]}` (every key in the file's order), or its TOML
/// syntax error, located (400).
async fn fields(Shared(st): Shared<Arc<State>>, req: Request) -> Response {
    let (name, bytes) = match named_body(&st, req).await {
        Ok(nb) => nb,
        Err(r) => return r,
    };
    let path = PathBuf::from(&name);
    let Ok(text) = std::str::from_utf8(&bytes) else {
        return error(StatusCode::BAD_REQUEST, Some(&name), None, "not UTF-8 text");
    };
    let ctx = crate::problem::Ctx::new(&path, text);
    let table: toml::Table = match ctx.parse(text) {
        Ok(t) => t,
        Err(e) => return problem_error(&e),
    };
    let keys: Vec<Value> = ctx
        .map()
        .lines()
        .map(|(k, line)| json!([k, line]))
        .collect();
    json_answer(&json!({"values": table, "keys": keys}))
}

/// `POST /api/export?what=html|dxf|json`: the result's report page (self-contained), its
/// drawing's DXF or its JSON, as an attachment ([`super::export`]).
async fn export(Shared(st): Shared<Arc<State>>, req: Request) -> Response {
    let what = query_value(req.uri().query(), "what").and_then(super::export::Export::parse);
    let Some(what) = what else {
        return error(
            StatusCode::BAD_REQUEST,
            None,
            None,
            "allowed: ?what=html, dxf or json",
        );
    };
    let scene = match problem(&st, req).await {
        Ok(s) => s,
        Err(r) => return r,
    };
    let r = match solved(&st, scene, Documents::Complete).await {
        Ok(r) => r,
        Err(r) => return r,
    };
    match super::export::export(&r, what) {
        Some((name, kind, bytes)) => {
            let disposition = format!("attachment; filename=\"{name}\"");
            let headers = [
                (header::CONTENT_TYPE, kind.to_string()),
                (header::CONTENT_DISPOSITION, disposition),
            ];
            (headers, bytes).into_response()
        }
        None => error(
            StatusCode::NOT_FOUND,
            Some(&r.name),
            None,
            "this result has no drawing",
        ),
    }
}

/// `POST /api/check`: `{"ok": true, "name", "family"}`, or the file's error.
async fn check(Shared(st): Shared<Arc<State>>, req: Request) -> Response {
    match problem(&st, req).await {
        Ok(s) => json_answer(&json!({"ok": true, "name": s.name, "family": s.family.name()})),
        Err(r) => r,
    }
}

/// `GET /api/templates`: every family's `cwsynth new` file.
async fn templates() -> Response {
    let all: Vec<Value> = families::FAMILIES
        .iter()
        .map(|f| json!({"family": f.name(), "text": families::new_problem(f.name())}))
        .collect();
    json_answer(&json!({ "templates": all }))
}

/// `GET /api/schema`: the problem file's JSON Schema (`cwsynth schema`).
async fn schema() -> Response {
    json_answer(&families::problem_schema())
}

/// `GET /api/files`: the problem files (`*.toml`) of the served folder, by name.
async fn files(Shared(st): Shared<Arc<State>>) -> Response {
    let mut names: Vec<String> = std::fs::read_dir(&st.root)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter_map(|e| e.file_name().into_string().ok())
        .filter(|n| n.ends_with(".toml") && bare_name(n))
        .collect();
    names.sort();
    json_answer(&json!({ "files": names }))
}

/// `GET /api/file/{name}`: one problem file of the served folder, as text.
async fn file(Shared(st): Shared<Arc<State>>, UrlPath(name): UrlPath<String>) -> Response {
    let not = || {
        error(
            StatusCode::NOT_FOUND,
            Some(&name),
            None,
            "no such problem file in the served folder",
        )
    };
    if !bare_name(&name) || !name.ends_with(".toml") {
        return not();
    }
    let path: PathBuf = st.root.join(&name);
    match path.canonicalize() {
        Ok(p) if p.starts_with(&st.root) => {}
        _ => return not(),
    }
    match crate::problem::read_bounded(&path, crate::problem::MAX_FILE_BYTES) {
        Ok(b) => match String::from_utf8(b) {
            Ok(text) => {
                ([(header::CONTENT_TYPE, "text/plain; charset=utf-8")], text).into_response()
            }
            Err(_) => error(StatusCode::BAD_REQUEST, Some(&name), None, "not UTF-8 text"),
        },
        Err(_) => not(),
    }
}

/// How the page shows each number of the result's `objectives` and `design` in a workshop
/// ([`crate::report::workshop_unit`], as the reports write them): key → [words, unit, the
/// factor from SI]. The JSON itself stays SI.
fn workshop_units(result: &Value) -> Value {
    let mut out = serde_json::Map::new();
    for section in ["objectives", "design"] {
        let Some(map) = result.get(section).and_then(Value::as_object) else {
            continue;
        };
        for (key, v) in map {
            if let Some(x) = v.as_f64() {
                let (words, unit, factor) = crate::report::workshop_unit(key, x);
                out.insert(key.clone(), json!([words, unit, factor]));
            }
        }
    }
    Value::Object(out)
}
