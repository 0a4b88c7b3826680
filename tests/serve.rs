//! `cwsynth serve`'s HTTP API (issue 35) against the library it serves: for every shipped
//! problem `POST /api/solve` is `cwsynth solve --json`'s object (apart from the timing and
//! the source path); errors are JSON naming file, line and field; bodies over the limit,
//! solves over their budget, paths outside the folder and missing tokens get their own
//! errors and the server goes on; 50 requests at once are all answered. The client is a
//! plain HTTP/1.1 exchange over a socket (no HTTP library between the test and the server).

use cwsynth::families::{load, solve_scene};
use cwsynth::serve::{start, Options};
use serde_json::Value;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::time::Duration;

fn problems() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("problems")
}

/// A server on the shipped problems, on a free port.
fn server(tune: impl FnOnce(&mut Options)) -> SocketAddr {
    let mut o = Options::new(problems());
    o.port = 0;
    tune(&mut o);
    start(o).unwrap()
}

/// One request: (status, headers, body).
fn http(
    addr: SocketAddr,
    method: &str,
    path: &str,
    body: &[u8],
    extra: &str,
) -> (u16, String, String) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
    let head = format!(
        "{method} {path} HTTP/1.1\r\nHost: test\r\nContent-Length: {}\r\nConnection: close\r\n{extra}\r\n",
        body.len()
    );
    s.write_all(head.as_bytes()).unwrap();
    let _ = s.write_all(body);
    let mut out = Vec::new();
    s.read_to_end(&mut out).unwrap();
    let text = String::from_utf8_lossy(&out).to_string();
    let (head, body) = text.split_once("\r\n\r\n").unwrap();
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, head.to_lowercase(), body.to_string())
}

/// The shipped problem file `name` posted to `route` (`?name=` it): (status, headers, body).
fn post_problem(addr: SocketAddr, route: &str, name: &str) -> (u16, String, String) {
    let text = std::fs::read(problems().join(name)).unwrap();
    http(addr, "POST", &format!("{route}?name={name}"), &text, "")
}

fn json(body: &str) -> Value {
    serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {body}"))
}

/// The result without what differs between two runs or two names of one file.
fn comparable(mut v: Value) -> Value {
    let o = v.as_object_mut().unwrap();
    o.remove("timing");
    o.remove("source");
    v
}

#[test]
fn every_shipped_problem_solves_as_the_command_line_does() {
    let addr = server(|_| {});
    let files = crate::common::shipped();
    assert!(files.len() >= 30);
    let (status, _, body) = http(addr, "GET", "/api/files", b"", "");
    assert_eq!(status, 200);
    assert_eq!(json(&body)["files"].as_array().unwrap().len(), files.len());
    for f in &files {
        let name = f.file_name().unwrap().to_str().unwrap();
        let text = std::fs::read(f).unwrap();
        let (status, _, body) = http(addr, "POST", &format!("/api/solve?name={name}"), &text, "");
        assert_eq!(status, 200, "{name}: {body}");
        let direct = solve_scene(&load(f).unwrap()).to_json();
        assert_eq!(comparable(json(&body)), comparable(direct), "{name}");
        // The file as the page opens it.
        let (status, _, served) = http(addr, "GET", &format!("/api/file/{name}"), b"", "");
        assert_eq!((status, served.as_bytes()), (200, &text[..]), "{name}");
    }
}

#[test]
fn errors_are_json_and_the_server_goes_on() {
    let addr = server(|o| o.max_body = 4096);
    // A located error: file, line and field.
    let bad = "name = \"x\"\nfamily = \"slider-crank\"\n[mechanism]\ncrank_radius = \"35\"\n";
    let (status, head, body) = http(addr, "POST", "/api/check?name=bad.toml", bad.as_bytes(), "");
    assert_eq!(status, 400);
    assert!(head.contains("content-type: application/json"), "{head}");
    assert!(
        head.contains("content-security-policy: default-src 'self'"),
        "{head}"
    );
    let e = &json(&body)["error"];
    assert_eq!(e["file"], "bad.toml");
    assert!(
        e["line"].as_u64().is_some() && e["field"].is_string(),
        "{e}"
    );
    // A body over the limit.
    let (status, _, body) = http(addr, "POST", "/api/solve", &[b'#'; 5000], "");
    assert_eq!(status, 413);
    assert!(json(&body)["error"]["message"]
        .as_str()
        .unwrap()
        .contains("4096"));
    // Paths outside the folder: a file, a drawing.
    for path in [
        "/api/file/..%2FCargo.toml",
        "/api/file/%2Fetc%2Fpasswd",
        "/api/file/.hidden.toml",
    ] {
        let (status, _, body) = http(addr, "GET", path, b"", "");
        assert_eq!(status, 404, "{path}: {body}");
    }
    let outline =
        std::fs::read_to_string(problems().join("linkage-fourbar-crank-outline.toml")).unwrap();
    let outside = outline.replace("file = \"", "file = \"../");
    let (status, _, body) = http(addr, "POST", "/api/check", outside.as_bytes(), "");
    assert_eq!(status, 400);
    assert!(
        json(&body)["error"]["field"]
            .as_str()
            .unwrap()
            .ends_with("outline.file"),
        "{body}"
    );
    let (status, _, _) = http(addr, "POST", "/api/check", outline.as_bytes(), "");
    assert_eq!(status, 200, "a drawing inside the folder is read");
    // Markup in a name comes back as JSON text, never as a page.
    let evil = std::fs::read_to_string(problems().join("piston-1000rpm.toml"))
        .unwrap()
        .replace(
            "name = \"piston-1000rpm\"",
            "name = \"<script>alert(1)</script>\"",
        );
    let (status, head, _) = http(addr, "POST", "/api/check", evil.as_bytes(), "");
    assert_eq!(status, 400, "not a valid name");
    assert!(head.contains("application/json"));
    // An unknown route, and the server still answers.
    assert_eq!(http(addr, "GET", "/nothing", b"", "").0, 404);
    assert_eq!(http(addr, "GET", "/api/templates", b"", "").0, 200);
}

#[test]
fn a_solve_over_its_budget_is_an_error_and_the_server_goes_on() {
    let addr = server(|o| o.solve_budget = Duration::from_millis(1));
    let text = std::fs::read(problems().join("linkage-sixbar-press-envelope.toml")).unwrap();
    let (status, _, body) = http(addr, "POST", "/api/solve", &text, "");
    assert_eq!(status, 503, "{body}");
    assert!(json(&body)["error"]["message"]
        .as_str()
        .unwrap()
        .contains("budget"));
    assert_eq!(http(addr, "GET", "/api/schema", b"", "").0, 200);
}

#[test]
fn a_token_guards_the_api() {
    let token = "0123456789abcdef0123";
    let addr = server(|o| o.token = Some(token.into()));
    assert_eq!(http(addr, "GET", "/api/files", b"", "").0, 401);
    let with = format!("Authorization: Bearer {token}\r\n");
    assert_eq!(http(addr, "GET", "/api/files", b"", &with).0, 200);
    // The page itself carries no data: it loads, and asks for the token in its fragment.
    assert_eq!(http(addr, "GET", "/", b"", "").0, 200);
    // Listening beyond this machine needs a token.
    let mut o = Options::new(problems());
    o.listen = "0.0.0.0".parse().unwrap();
    assert!(o.validate().unwrap_err().to_string().contains("--token"));
}

#[test]
fn fifty_requests_at_once_are_all_answered() {
    let addr = server(|_| {});
    let text = std::fs::read(problems().join("piston-1000rpm.toml")).unwrap();
    let expected =
        comparable(solve_scene(&load(&problems().join("piston-1000rpm.toml")).unwrap()).to_json());
    let handles: Vec<_> = (0..50)
        .map(|_| {
            let text = text.clone();
            std::thread::spawn(move || {
                http(
                    addr,
                    "POST",
                    "/api/solve?name=piston-1000rpm.toml",
                    &text,
                    "",
                )
            })
        })
        .collect();
    for h in handles {
        let (status, _, body) = h.join().unwrap();
        assert_eq!(status, 200);
        assert_eq!(comparable(json(&body)), expected);
    }
}

#[test]
fn an_edit_sets_one_key_and_keeps_the_rest_of_the_file() {
    let addr = server(|_| {});
    let name = "linkage-fourbar-crank-counterweight.toml";
    let text = std::fs::read_to_string(problems().join(name)).unwrap();
    let edit = |key: &str, value: Value| {
        let body = serde_json::json!({"text": text, "key": key, "value": value}).to_string();
        http(addr, "POST", "/api/edit", body.as_bytes(), "")
    };
    // A pivot moved: that line changes, every other line (comments included) stays.
    let (status, _, body) = edit(
        "mechanism.dyads[0].q",
        serde_json::json!(["110 mm", "5 mm"]),
    );
    assert_eq!(status, 200, "{body}");
    let new = json(&body)["text"].as_str().unwrap().to_string();
    let changed: Vec<(&str, &str)> = text
        .lines()
        .zip(new.lines())
        .filter(|(a, b)| a != b)
        .collect();
    assert_eq!(
        changed,
        vec![("q = [\"100 mm\", \"0 mm\"]", "q = [\"110 mm\", \"5 mm\"]")]
    );
    // The report of the edited file draws the moved pivot among its handles.
    let (status, _, body) = http(
        addr,
        "POST",
        &format!("/api/report?name={name}"),
        new.as_bytes(),
        "",
    );
    assert_eq!(status, 200);
    let m = &json(&body)["motion"];
    assert_eq!(m["frames"].as_array().unwrap().len(), 72);
    let q = m["handles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|h| h["key"] == "mechanism.dyads[0].q")
        .unwrap();
    assert!(
        (q["at"][0].as_f64().unwrap() - 0.110).abs() < 1e-12
            && (q["at"][1].as_f64().unwrap() - 0.005).abs() < 1e-12
    );
    // A key the file leaves out is added to its table (the crank pivot, default the origin).
    let (status, _, body) = edit("mechanism.crank_pivot", serde_json::json!(["1 mm", "2 mm"]));
    assert_eq!(status, 200);
    let with_pivot = json(&body)["text"].as_str().unwrap().to_string();
    assert!(
        with_pivot.contains("crank_pivot = [\"1 mm\", \"2 mm\"]"),
        "{with_pivot}"
    );
    let (status, _, _) = http(addr, "POST", "/api/check", with_pivot.as_bytes(), "");
    assert_eq!(status, 200);
    // Keys that are not there, or not keys.
    for key in [
        "mechanism.dyads[5].q",
        "nothing.here",
        "mechanism..x",
        "mechanism.dyads[x].q",
    ] {
        let (status, _, body) = edit(key, serde_json::json!(1));
        assert_eq!(status, 400, "{key}: {body}");
    }
}

/// The API campaign (issue 35): the `cwsynth serve` binary itself, 1,000 mutated problem files
/// (an even sample of the mutation suite's, `mutants::mutants`) solved by 4 clients at once,
/// oversized bodies, 20 clients that send half their headers and stall, 10 that promise a body
/// and never send it: every answer is JSON with a status in its set within its limit, the
/// server answers a shipped problem afterwards, and its peak memory stays bounded.
#[test]
fn the_api_campaign_leaves_the_server_answering() {
    use std::io::BufRead;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_cwsynth"))
        .args(["serve", "--no-open", "--port", "0", "--solve-budget", "5"])
        .arg(problems())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr: SocketAddr = line
        .trim()
        .trim_start_matches("cwsynth serve: http://")
        .trim_end_matches('/')
        .parse()
        .unwrap();
    // Stalled clients, held open through the campaign.
    let mut stalled = Vec::new();
    for k in 0..30 {
        let mut s = TcpStream::connect(addr).unwrap();
        let head = if k < 20 {
            "POST /api/solve HTTP/1.1\r\nHost: te".to_string()
        } else {
            "POST /api/solve HTTP/1.1\r\nHost: t\r\nContent-Length: 500\r\n\r\nname".to_string()
        };
        s.write_all(head.as_bytes()).unwrap();
        stalled.push(s);
    }
    let all = crate::mutants::mutants();
    let step = (all.len() / 1000).max(1);
    let sample: Vec<Vec<u8>> = all
        .into_iter()
        .step_by(step)
        .take(1000)
        .map(|m| m.bytes)
        .collect();
    assert_eq!(sample.len(), 1000);
    let sample = std::sync::Arc::new(sample);
    let workers: Vec<_> = (0..4)
        .map(|w| {
            let sample = sample.clone();
            std::thread::spawn(move || {
                let mut tally = [0usize; 4];
                for bytes in sample.iter().skip(w).step_by(4) {
                    let t0 = std::time::Instant::now();
                    let (status, head, body) =
                        http(addr, "POST", "/api/solve?name=mut.toml", bytes, "");
                    assert!(head.contains("application/json"), "{status}: {head}");
                    let v = json(&body);
                    match status {
                        200 => tally[0] += 1,
                        400 | 413 => tally[1] += 1,
                        503 => tally[2] += 1,
                        _ => panic!("{status}: {body}"),
                    }
                    if status != 200 {
                        assert!(v["error"]["message"].is_string(), "{body}");
                    }
                    tally[3] = tally[3].max(t0.elapsed().as_millis() as usize);
                }
                tally
            })
        })
        .collect();
    let mut total = [0usize; 4];
    for w in workers {
        let t = w.join().unwrap();
        for i in 0..3 {
            total[i] += t[i];
        }
        total[3] = total[3].max(t[3]);
    }
    eprintln!(
        "campaign: {} solved, {} refused, {} over the budget; slowest answer {} ms",
        total[0], total[1], total[2], total[3]
    );
    assert_eq!(total[0] + total[1] + total[2], 1000);
    assert!(total[3] < 60_000);
    // Oversized bodies.
    for n in [2 << 20, 8 << 20] {
        let (status, _, _) = http(addr, "POST", "/api/solve", &vec![b'#'; n], "");
        assert_eq!(status, 413);
    }
    // The stalled bodies time out by themselves (10 s); the server still answers.
    let (status, _, _) = post_problem(addr, "/api/solve", "piston-1000rpm.toml");
    assert_eq!(status, 200);
    let status =
        std::fs::read_to_string(format!("/proc/{}/status", child.id())).unwrap_or_default();
    let peak_kb: u64 = status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    eprintln!(
        "campaign: the server's peak resident memory {} MiB",
        peak_kb / 1024
    );
    child.kill().unwrap();
    child.wait().unwrap();
    drop(stalled);
    assert!(peak_kb < 1 << 20, "peak memory {peak_kb} kB");
}

#[test]
fn the_report_and_the_drawing_are_exported_as_solve_writes_them() {
    let addr = server(|_| {});
    let name = "linkage-fourbar-crank-counterweight";
    let path = problems().join(format!("{name}.toml"));
    let text = std::fs::read(&path).unwrap();
    let out = tempfile::tempdir().unwrap();
    let mut r = solve_scene(&load(&path).unwrap());
    cwsynth::report::write_outputs(&mut r, out.path()).unwrap();
    // The drawing: the bytes `solve --out` writes.
    let (status, head, dxf) = http(
        addr,
        "POST",
        &format!("/api/export?what=dxf&name={name}.toml"),
        &text,
        "",
    );
    assert_eq!(status, 200);
    assert!(
        head.contains(&format!(
            "content-disposition: attachment; filename=\"{name}-drawing.dxf\""
        )),
        "{head}"
    );
    let written = std::fs::read_to_string(out.path().join(format!("{name}-drawing.dxf"))).unwrap();
    assert_eq!(dxf, written);
    // The report: one page, every plot inlined, no file it needs beside it.
    let (status, _, html) = http(
        addr,
        "POST",
        &format!("/api/export?what=html&name={name}.toml"),
        &text,
        "",
    );
    assert_eq!(status, 200);
    assert!(html.contains("data:image/svg+xml;charset=utf-8,"));
    let images = html.matches("<img").count();
    assert!(images >= 2 && html.matches("src=\"data:image/svg+xml").count() == images);
    assert_eq!(http(addr, "POST", "/api/export?what=pdf", &text, "").0, 400);
}

/// The slider-crank's drawing for the designer: every frame's crank pin on its circle, the
/// rod its length, the slider on the guide, the counterweight at its radius opposite the
/// unbalance it balances (the design's angle from the crank).
#[test]
fn the_piston_is_drawn_over_a_turn() {
    let addr = server(|_| {});
    let (status, _, body) = post_problem(addr, "/api/report", "piston-1000rpm.toml");
    assert_eq!(status, 200);
    let v = json(&body);
    let (m, d) = (&v["motion"], &v["result"]["design"]);
    let frames = m["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 72);
    let p = |v: &Value| [v[0].as_f64().unwrap(), v[1].as_f64().unwrap()];
    let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let beta = d["counterweight_angle_rad"].as_f64().unwrap();
    let rc = d["counterweight_radius_m"].as_f64().unwrap();
    for f in frames {
        let th = f["theta"].as_f64().unwrap();
        let l = &f["links"];
        let (o, a, b) = (p(&l[0][0]), p(&l[0][1]), p(&l[1][1]));
        assert!(dist(o, [0.0, 0.0]) < 1e-15 && (dist(a, o) - 0.035).abs() < 1e-12);
        assert!((dist(b, a) - 0.140).abs() < 1e-12 && b[1].abs() < 1e-15);
        let c = p(&f["counterweights"][0]);
        assert!(dist(c, [rc * (th + beta).cos(), rc * (th + beta).sin()]) < 1e-12);
    }
    assert_eq!(m["guides"].as_array().unwrap().len(), 1);
}

/// A plot of x–y panels carries its data in `/api/report` (`width`, `height`, `panels`): the
/// numbers its SVG is drawn from, series by series (the linkage's `fields` plot: |F|, M_O and
/// T, bare and balanced, with their peaks), and the same SVG as the report writes; with
/// `?plots=data` its `svg` is left out, and a plot without panels (the linkage's drawing)
/// keeps its SVG.
#[test]
fn a_panel_plots_data_is_the_numbers_its_svg_is_drawn_from() {
    let addr = server(|_| {});
    let name = "linkage-sixbar-press.toml";
    let mut direct = solve_scene(&load(&problems().join(name)).unwrap());
    direct.draw();
    let plot = direct.plots.iter().find(|p| p.suffix == "fields").unwrap();
    let figure = plot.figure().unwrap().unwrap();
    let svg = plot.svg().unwrap();
    assert_eq!(figure.svg().unwrap(), svg);
    assert_eq!(figure.panels.len(), 3);
    let text = std::fs::read(problems().join(name)).unwrap();
    for query in ["", "plots=data&"] {
        let path = format!("/api/report?{query}name={name}");
        let (status, _, body) = http(addr, "POST", &path, &text, "");
        assert_eq!(status, 200, "{body}");
        let plots = json(&body)["plots"].as_array().unwrap().clone();
        let fields = plots.iter().find(|p| p["suffix"] == "fields").unwrap();
        assert_eq!(
            (fields["width"].as_u64(), fields["height"].as_u64()),
            (Some(420), Some(340))
        );
        assert_eq!(
            fields["svg"].as_str(),
            (query.is_empty()).then_some(svg.as_str())
        );
        let panels = fields["panels"].as_array().unwrap();
        assert_eq!(panels.len(), figure.panels.len());
        for (got, want) in panels.iter().zip(&figure.panels) {
            same_panel(got, want);
            assert!(svg.contains(&want.title), "{}", want.title);
        }
        // A plot without panels (the drawing at four crank angles) is its SVG.
        let drawing = plots.iter().find(|p| p["suffix"] == "linkage").unwrap();
        assert!(drawing["panels"].is_null());
        assert!(drawing["svg"].as_str().unwrap().starts_with("<svg"));
    }
}

/// `digits=7` (what the page asks for): the drawing's and the plots' numbers within half a
/// unit of the 7th significant digit of the exact ones, the answer smaller, the result and
/// the handles exactly the same; a number of digits out of 1–17 is a 400.
#[test]
fn the_pages_drawing_numbers_are_rounded_and_its_results_are_not() {
    let addr = server(|_| {});
    let name = "gear-tooth-profiles.toml";
    let text = std::fs::read(problems().join(name)).unwrap();
    let at = |q: &str| {
        let (status, _, body) = http(
            addr,
            "POST",
            &format!("/api/report?plots=data{q}&name={name}"),
            &text,
            "",
        );
        assert_eq!(status, 200, "{body}");
        body
    };
    let (exact, rounded) = (at(""), at("&digits=7"));
    assert!(
        rounded.len() * 3 < exact.len() * 2,
        "{} {}",
        rounded.len(),
        exact.len()
    );
    let (e, r) = (json(&exact), json(&rounded));
    let mut r_result = r["result"].clone();
    let mut e_result = e["result"].clone();
    for v in [&mut r_result, &mut e_result] {
        v.as_object_mut().unwrap().remove("timing");
    }
    assert_eq!(r_result, e_result);
    assert_eq!(r["motion"]["handles"], e["motion"]["handles"]);
    fn close(a: &Value, b: &Value, n: &mut usize) {
        match (a, b) {
            (Value::Array(x), Value::Array(y)) => {
                assert_eq!(x.len(), y.len());
                x.iter().zip(y).for_each(|(a, b)| close(a, b, n));
            }
            (Value::Object(x), Value::Object(y)) => {
                assert_eq!(x.len(), y.len());
                x.iter().for_each(|(k, a)| close(a, &y[k], n));
            }
            (Value::Number(x), Value::Number(y)) => {
                let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
                assert!((x - y).abs() <= 5.000001e-7 * y.abs(), "{x} {y}");
                *n += 1;
            }
            _ => assert_eq!(a, b),
        }
    }
    let mut n = 0;
    close(&r["motion"], &e["motion"], &mut n);
    close(&r["plots"], &e["plots"], &mut n);
    assert!(n > 10_000, "{n}");
    for bad in ["0", "18", "x"] {
        let (status, _, body) = http(
            addr,
            "POST",
            &format!("/api/report?digits={bad}&name={name}"),
            &text,
            "",
        );
        assert_eq!(status, 400, "{body}");
    }
}

/// A panel of `/api/report` against the library's: labels, every series' name, style and
/// points (a non-finite one as null; the JSON's numbers to the last bit or the one below it,
/// as serde_json reads them back).
fn same_panel(got: &Value, want: &cwsynth::report::plot::Panel) {
    assert_eq!(got["title"], want.title.as_str());
    assert_eq!(got["x_label"], want.x_label.as_str());
    assert_eq!(got["y_label"], want.y_label.as_str());
    assert_eq!(got["equal_aspect"], want.equal_aspect);
    assert_eq!(got["angle_x"], true, "θ (deg): the crank angle");
    let series = got["series"].as_array().unwrap();
    assert_eq!(series.len(), want.series.len());
    for (g, w) in series.iter().zip(&want.series) {
        assert_eq!(g["name"], w.name.as_str());
        assert_eq!(g["style"], w.style.as_str());
        for (axis, k) in [("x", 0), ("y", 1)] {
            let vs = g[axis].as_array().unwrap();
            assert_eq!(vs.len(), w.points.len(), "{} {axis}", w.name);
            for (v, p) in vs.iter().zip(&w.points) {
                let p = if k == 0 { p.0 } else { p.1 };
                match v.as_f64() {
                    None => assert!(!p.is_finite() && v.is_null()),
                    Some(v) => assert!((v - p).abs() <= 2.0 * f64::EPSILON * p.abs(), "{v} {p}"),
                }
            }
        }
    }
}

/// The page's plotting library and script are served from the binary (the page works
/// offline), the library as vendored from its npm package (`scripts/vendor.sh`), with its
/// licence.
#[test]
fn the_plotting_library_is_served_with_its_licence() {
    let addr = server(|_| {});
    let vendor = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/serve/assets/vendor");
    for (path, kind) in [
        ("uPlot.iife.min.js", "text/javascript"),
        ("uPlot.min.css", "text/css"),
        ("uPlot.LICENSE", "text/plain"),
    ] {
        let (status, head, body) = http(addr, "GET", &format!("/vendor/{path}"), b"", "");
        assert_eq!(status, 200, "{path}");
        assert!(head.contains(&format!("content-type: {kind}")), "{head}");
        assert_eq!(body, std::fs::read_to_string(vendor.join(path)).unwrap());
    }
    let (status, _, page) = http(addr, "GET", "/", b"", "");
    assert_eq!(status, 200);
    for src in [
        "/vendor/uPlot.iife.min.js",
        "/vendor/uPlot.min.css",
        "/plots.js",
    ] {
        assert!(page.contains(src), "{src}");
    }
    let (status, _, script) = http(addr, "GET", "/plots.js", b"", "");
    assert!(status == 200 && script.contains("new uPlot("));
}

/// Reads until the server closes the connection; how long that took.
fn closed_after(s: &mut TcpStream) -> Duration {
    let t = std::time::Instant::now();
    s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    let mut buf = [0u8; 256];
    loop {
        match s.read(&mut buf) {
            Ok(0) | Err(_) => return t.elapsed(),
            Ok(_) => {}
        }
    }
}

#[test]
fn slow_clients_lose_their_connection_and_the_server_goes_on() {
    let addr = server(|o| {
        o.header_time = Duration::from_millis(800);
        o.max_connections = 3;
    });
    // Three clients that never finish their request's head: the connections at once.
    let mut slow: Vec<TcpStream> = (0..3)
        .map(|_| {
            let mut s = TcpStream::connect(addr).unwrap();
            s.write_all(b"GET /api/templates HTTP/1.1\r\nHost: t")
                .unwrap();
            s
        })
        .collect();
    std::thread::sleep(Duration::from_millis(100));
    // One more is closed at once, without an answer.
    let mut over = TcpStream::connect(addr).unwrap();
    let _ = over.write_all(b"GET /api/templates HTTP/1.1\r\nHost: t\r\n\r\n");
    assert!(closed_after(&mut over) < Duration::from_millis(700));
    // The slow ones are closed once their head time is over …
    for s in &mut slow {
        let t = closed_after(s);
        assert!(t < Duration::from_secs(5), "{t:?}");
    }
    // … and the server answers again.
    let (status, _, body) = http(addr, "GET", "/api/templates", b"", "");
    assert_eq!(status, 200, "{body}");
}

/// The form's routes: `POST /api/fields` gives the file's values and every key's line (a
/// syntax error located), `POST /api/edit` removes a key (`null`), adds a table (an object)
/// and appends or removes an entry of an array of tables, the rest of the file kept; the
/// form's script is served.
#[test]
fn the_form_reads_the_fields_and_edits_tables() {
    let addr = server(|_| {});
    let name = "piston-1000rpm.toml";
    let text = std::fs::read_to_string(problems().join(name)).unwrap();
    let (status, _, body) = http(
        addr,
        "POST",
        &format!("/api/fields?name={name}"),
        text.as_bytes(),
        "",
    );
    assert_eq!(status, 200, "{body}");
    let v = json(&body);
    assert_eq!(v["values"]["mechanism"]["speed"], "1000 rpm");
    assert_eq!(v["values"]["paper"][1]["value"], "460 N");
    let keys = v["keys"].as_array().unwrap();
    let at = |k: &str| keys.iter().position(|e| e[0] == k).unwrap();
    let line = |k: &str| keys[at(k)][1].as_u64().unwrap() as usize;
    assert!(
        at("design.unbalance.min") < at("design.unbalance.max"),
        "the file's order"
    );
    assert!(text
        .lines()
        .nth(line("mechanism.speed") - 1)
        .unwrap()
        .starts_with("speed = "));
    assert!(text
        .lines()
        .nth(line("design.unbalance.max") - 1)
        .unwrap()
        .starts_with("unbalance = "));
    let (status, _, body) = http(
        addr,
        "POST",
        "/api/fields?name=x.toml",
        b"a = 1\nb = [\n",
        "",
    );
    assert_eq!(status, 400);
    let e = &json(&body)["error"];
    assert!(e["file"] == "x.toml" && e["line"].as_u64().is_some(), "{e}");
    let edit = |text: &str, key: &str, value: Value| {
        let body = serde_json::json!({"text": text, "key": key, "value": value}).to_string();
        let (status, _, body) = http(addr, "POST", "/api/edit", body.as_bytes(), "");
        assert_eq!(status, 200, "{key}: {body}");
        json(&body)["text"].as_str().unwrap().to_string()
    };
    let removed = edit(&text, "model.rod_split", Value::Null);
    assert_eq!(removed, text.replace("rod_split = 0.5\n", ""));
    // A table the file leaves out, written in one edit as a `[section]` after the others.
    let drive = edit(&text, "mechanism.drive", serde_json::json!({"cs": 0.05}));
    assert!(
        drive.starts_with(&text[..text.find("[model]").unwrap()]),
        "{drive}"
    );
    assert!(drive.contains("[mechanism.drive]\ncs = 0.05\n"), "{drive}");
    // Entries of an array of tables: appended, replaced, removed.
    let entry = serde_json::json!({"quantity": "q", "value": "1 N", "key": "objectives.peak_shaking_force_n"});
    let three = edit(&text, "paper[2]", entry.clone());
    let added =
        "[[paper]]\nkey = \"objectives.peak_shaking_force_n\"\nquantity = \"q\"\nvalue = \"1 N\"\n";
    assert_eq!(three, format!("{text}\n{added}"));
    assert_eq!(edit(&three, "paper[2]", Value::Null), text);
    let none = edit(&text, "paper", Value::Null);
    assert!(!none.contains("[[paper]]") && none.contains("[accuracy]\nrel_tol = 1e-9\n"));
    assert_eq!(
        edit(&none, "paper[0]", entry.clone())
            .matches("[[paper]]")
            .count(),
        1
    );
    let one = edit(&text, "paper[0]", Value::Null);
    assert_eq!(
        json(&http(addr, "POST", "/api/fields", one.as_bytes(), "").2)["values"]["paper"]
            .as_array()
            .unwrap()
            .len(),
        1
    );
    // A field of an inline array of inline tables.
    let inline = "a = [{ b = 1 }, { b = 2 }] # two\n";
    assert_eq!(
        edit(inline, "a[1].b", serde_json::json!(3)),
        "a = [{ b = 1 }, { b = 3 }] # two\n"
    );
    for (key, value) in [("paper[5]", entry), ("paper[0]", serde_json::json!(3))] {
        let body = serde_json::json!({"text": text, "key": key, "value": value}).to_string();
        assert_eq!(
            http(addr, "POST", "/api/edit", body.as_bytes(), "").0,
            400,
            "{key}"
        );
    }
    let (status, head, js) = http(addr, "GET", "/form.js", b"", "");
    assert!(status == 200 && head.contains("text/javascript") && js.contains("/api/fields"));
}
