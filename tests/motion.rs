//! The designer's drawing data (`report::motion`, issue 35) for every shipped scene, checked
//! against each family's model rather than against the code that fills it: the frames are
//! finite, every link keeps the length the model gives it (the crank radius and rod of the
//! slider-crank's file, the crane's boom, jib and tie of its result, the hypocycloid's
//! R, r, L, the gear's eccentricity; a linkage's every link constant over the turn), the
//! hypocycloid's crank arm turns with its planet, the gears' posed pitch curves touch at
//! the model's pitch point (ρ1(α1), 0); every handle's key is in the file (or is one whose
//! default the edit adds), and writing a handle's own value as the page writes it changes
//! nothing drawn. The gear's stated centre distance and a drawn outline's origin are handles
//! exactly where the file gives them, at the model's point, and a drag of d changes the field
//! by d; the hypocycloid's Lanchester masses turn as the model's pairs do.

use cwsynth::families::gear::model::EccentricCircle;
use cwsynth::families::slider_crank::file as scf;
use cwsynth::families::{load, solve_scene};
use cwsynth::serve::edit::set_key;
use serde_json::{json, Value};
use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

fn problems() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("problems")
}

/// Keys a handle may edit that a file may leave out (their defaults: the origin, no offset).
const DEFAULTED: &[&str] = &["mechanism.crank_pivot", "mechanism.offset"];

/// The result's JSON and its motion, solved from the file `f` (or its edited `text`).
fn solved(f: &Path, text: Option<&str>) -> (Value, Value) {
    let scene = match text {
        None => load(f).unwrap(),
        Some(t) => {
            // Beside a link to the shipped drawings, which a file names relative to itself.
            let dir = std::env::temp_dir().join(format!("cwsynth-motion-{}", std::process::id()));
            if !dir.exists() {
                std::fs::create_dir_all(&dir).unwrap();
                std::os::unix::fs::symlink(problems().join("drawings"), dir.join("drawings"))
                    .unwrap();
            }
            let tmp = dir.join(f.file_name().unwrap());
            std::fs::write(&tmp, t).unwrap();
            load(&tmp).unwrap()
        }
    };
    let mut r = solve_scene(&scene);
    r.draw();
    (r.to_json(), r.motion.clone().unwrap_or(Value::Null))
}

fn p(v: &Value) -> [f64; 2] {
    [v[0].as_f64().unwrap(), v[1].as_f64().unwrap()]
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Link `i`'s length in frame `f`.
fn len(f: &Value, i: usize) -> f64 {
    dist(p(&f["links"][i][0]), p(&f["links"][i][1]))
}

/// `a` is `b` within `tol` of `scale`.
fn near(a: f64, b: f64, scale: f64, what: &str) {
    assert!((a - b).abs() <= 1e-9 * scale, "{what}: {a} against {b}");
}

/// Every number of the frames, bodies and handles is finite.
fn finite(m: &Value) {
    fn walk(v: &Value, at: &str) {
        match v {
            Value::Number(n) => assert!(n.as_f64().unwrap().is_finite(), "{at}"),
            Value::Null => panic!("{at}: null (a number that was not finite)"),
            Value::Array(a) => a.iter().for_each(|x| walk(x, at)),
            Value::Object(o) => o.iter().for_each(|(k, x)| walk(x, &format!("{at}.{k}"))),
            _ => {}
        }
    }
    for k in ["frames", "guides", "handles", "bodies"] {
        if let Some(v) = m.get(k) {
            walk(v, k);
        }
    }
}

/// The links keep the model's lengths in every frame.
fn rigid(f: &Path, family: &str, d: &Value, m: &Value) {
    let frames = m["frames"].as_array().unwrap();
    assert!(frames.len() >= 36, "{f:?}: {} frames", frames.len());
    let g = |k: &str| d[k].as_f64().unwrap();
    for fr in frames {
        let what = format!("{f:?} at θ = {}", fr["theta"]);
        match family {
            "slider-crank" => {
                let text = std::fs::read_to_string(f).unwrap();
                let raw: scf::File = toml::from_str(&text).unwrap();
                let mech = scf::resolve_raw(&raw, &problems()).unwrap().core.mech;
                near(len(fr, 0), mech.r, mech.l, &what);
                near(len(fr, 1), mech.l, mech.l, &what);
                near(p(&fr["links"][2][0])[1], mech.e, mech.l, &what);
                break;
            }
            "luffing-crane" => {
                let s = g("boom_length_m");
                near(len(fr, 0), s, s, &what);
                near(len(fr, 1), g("jib_length_m") + g("jib_tail_m"), s, &what);
                let (e, dd) = (p(&fr["links"][1][0]), p(&fr["links"][0][1]));
                near(dist(e, dd), g("jib_tail_m"), s, &what);
                if let Some(b) = d["tie_length_m"].as_f64() {
                    near(len(fr, 2), b, s, &what);
                }
                // A hung counterweight's hanger, a lever's lever and rod keep their lengths.
                for i in 3..fr["links"].as_array().unwrap().len() {
                    near(len(fr, i), len(&frames[0], i), s, &what);
                }
            }
            "hypocycloid" => {
                let s = g("rod_length_m");
                near(len(fr, 0), g("carrier_radius_m"), s, &what);
                near(len(fr, 1), g("crank_arm_m"), s, &what);
                near(len(fr, 2), s, s, &what);
                near(p(&fr["links"][3][0])[1], 0.0, s, &what);
                // The crank arm is fixed on the planet (body 1): it turns with it.
                let (o1, a) = (p(&fr["links"][1][0]), p(&fr["links"][1][1]));
                let arm = (a[1] - o1[1]).atan2(a[0] - o1[0]);
                let turn =
                    (arm - fr["poses"][1][2].as_f64().unwrap()).rem_euclid(std::f64::consts::TAU);
                assert!(turn.min(std::f64::consts::TAU - turn) < 1e-9, "{what}");
            }
            "eccentric-gear" => gear_frame(fr, m, d, &what),
            _ => {
                // A linkage: every link keeps its length over the turn.
                for i in 0..fr["links"].as_array().unwrap().len() {
                    near(len(fr, i), len(&frames[0], i), 1.0, &what);
                }
            }
        }
    }
}

/// The gears' posed pitch curves both pass through the model's pitch point (ρ1(α1), 0),
/// within their polylines' spacing; the eccentric O1C is e long.
fn gear_frame(fr: &Value, m: &Value, d: &Value, what: &str) {
    let (big_r, e) = (
        d["pitch_radius_m"].as_f64().unwrap(),
        d["eccentricity_m"].as_f64().unwrap(),
    );
    near(len(fr, 0), e, big_r, what);
    let a1 = fr["theta"].as_f64().unwrap();
    let o1 = p(&fr["links"][0][0]);
    let pitch = [
        o1[0] + EccentricCircle::new(big_r, e).unwrap().rho1(a1),
        o1[1],
    ];
    for (i, b) in m["bodies"].as_array().unwrap().iter().enumerate().take(2) {
        let pose = &fr["poses"][i];
        let [x, y, t] = [0, 1, 2].map(|k| pose[k].as_f64().unwrap());
        let pts: Vec<[f64; 2]> = b["loops"][0]
            .as_array()
            .unwrap()
            .iter()
            .map(|q| {
                let q = p(q);
                [
                    x + t.cos() * q[0] - t.sin() * q[1],
                    y + t.sin() * q[0] + t.cos() * q[1],
                ]
            })
            .collect();
        let gap = pts.windows(2).map(|w| dist(w[0], w[1])).fold(0.0, f64::max);
        let nearest = pts
            .iter()
            .map(|q| dist(*q, pitch))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest <= gap,
            "{what}: gear {} misses the pitch point by {nearest} (spacing {gap})",
            i + 1
        );
    }
}

/// The value a zero drag writes, as the page writes it (rounded to the step).
fn page_value(h: &Value) -> Value {
    match h.get("scalar") {
        Some(s) => {
            let inv = 1.0 / s["step"].as_f64().unwrap();
            let v = (s["value"].as_f64().unwrap() * inv).round() / inv;
            json!(format!("{v} {}", s["unit"].as_str().unwrap()))
        }
        None => {
            let mm = |v: f64| format!("{} mm", (v * 1e4).round() / 10.0);
            let at = p(&h["at"]);
            json!([mm(at[0]), mm(at[1])])
        }
    }
}

/// Whether the dotted key (`a.b[1].c`) is in the TOML text.
fn has_key(text: &str, key: &str) -> bool {
    let mut v: toml::Value = toml::from_str(text).unwrap();
    for part in key.split('.') {
        let (name, index) = match part.split_once('[') {
            Some((n, i)) => (n, Some(i.trim_end_matches(']').parse::<usize>().unwrap())),
            None => (part, None),
        };
        let Some(next) = v.get(name).cloned() else {
            return false;
        };
        v = match index {
            Some(i) => match next.get(i) {
                Some(x) => x.clone(),
                None => return false,
            },
            None => next,
        };
    }
    true
}

/// Every handle's key is in the file (or defaulted), and its own value written back draws
/// the same mechanism.
fn handles(f: &Path, text: &str, m: &Value) {
    for h in m["handles"].as_array().unwrap() {
        let key = h["key"].as_str().unwrap();
        assert!(
            has_key(text, key) || DEFAULTED.contains(&key),
            "{f:?}: {key} is not in the file"
        );
        if !has_key(text, key) {
            // Left to its default (the origin, no offset): the handle is there.
            let v = h["scalar"]
                .get("value")
                .map_or(p(&h["at"]), |v| [v.as_f64().unwrap(), 0.0]);
            assert_eq!(v, [0.0, 0.0], "{f:?}: {key}");
            continue;
        }
        let edited = set_key(text, key, &page_value(h)).unwrap();
        if edited == text {
            continue;
        }
        let (_, again) = solved(f, Some(&edited));
        let scale = 1.0
            + p(&m["frames"][0]["links"][0][1])
                .iter()
                .map(|x| x.abs())
                .sum::<f64>();
        for (a, b) in [
            (&m["handles"], &again["handles"]),
            (&m["frames"][0]["links"], &again["frames"][0]["links"]),
        ] {
            let flat = |v: &Value| -> Vec<f64> {
                fn walk(v: &Value, out: &mut Vec<f64>) {
                    match v {
                        Value::Number(n) => out.push(n.as_f64().unwrap()),
                        Value::Array(a) => a.iter().for_each(|x| walk(x, out)),
                        Value::Object(o) => o.values().for_each(|x| walk(x, out)),
                        _ => {}
                    }
                }
                let mut out = Vec::new();
                walk(v, &mut out);
                out
            };
            let (x, y) = (flat(a), flat(b));
            assert_eq!(x.len(), y.len(), "{f:?}: {key}");
            for (u, v) in x.iter().zip(&y) {
                assert!(
                    (u - v).abs() <= 1e-6 * scale,
                    "{f:?}: {key} written as {}: {u} became {v}",
                    page_value(h)
                );
            }
        }
    }
}

#[test]
fn every_shipped_scene_moves_rigidly_and_its_handles_edit_its_keys() {
    let files = crate::common::shipped();
    let mut families = std::collections::BTreeSet::new();
    for f in &files {
        let (r, m) = solved(f, None);
        let family = r["family"].as_str().unwrap().to_string();
        assert!(m.is_object(), "{f:?}: no motion");
        finite(&m);
        rigid(f, &family, &r["design"], &m);
        handles(f, &std::fs::read_to_string(f).unwrap(), &m);
        families.insert(family);
    }
    assert_eq!(families.len(), 6, "{families:?}");
}

#[test]
fn a_given_counterweight_is_a_handle_on_its_link() {
    let f = problems().join("linkage-fourbar-crank-counterweight.toml");
    let text = std::fs::read_to_string(&f).unwrap().replace(
        "mass = { min = \"0 kg\", max = \"2 kg\" }",
        "mass = \"0.5 kg\"\ncentroid = [\"-30 mm\", \"5 mm\"]",
    );
    let (_, m) = solved(&f, Some(&text));
    let h = (m["handles"].as_array().unwrap().iter())
        .find(|h| h["key"] == "design.counterweights[0].centroid")
        .expect("the centroid's handle");
    assert_eq!(p(&h["at"]), [-0.030, 0.005]);
    // On the crank: placed by its pose, it is the frame's counterweight centroid.
    for (k, fr) in m["frames"].as_array().unwrap().iter().enumerate() {
        let pose = &h["poses"][k];
        let [x, y, t] = [0, 1, 2].map(|i| pose[i].as_f64().unwrap());
        let at = [
            x + t.cos() * -0.030 - t.sin() * 0.005,
            y + t.sin() * -0.030 + t.cos() * 0.005,
        ];
        assert!(dist(at, p(&fr["counterweights"][0])) < 1e-12, "frame {k}");
        near(
            t.rem_euclid(std::f64::consts::TAU),
            fr["theta"].as_f64().unwrap(),
            1.0,
            "crank",
        );
    }
    handles(&f, &text, &m);
}

/// The value the page writes for a drag of `d` (m, in the handle's frame) from the handle
/// `h` (`dragged` in `app.js`): a scalar `value + per_metre·(d·axis)` rounded to its step,
/// not below its least value, with its unit; a point the drop point `at + d` in mm, to
/// 0.1 mm.
fn page_value_moved(h: &Value, d: [f64; 2]) -> Value {
    match h.get("scalar") {
        Some(s) => {
            let g = |k: &str| s[k].as_f64().unwrap();
            let (axis, step) = (p(&s["axis"]), g("step"));
            let t = d[0] * axis[0] + d[1] * axis[1];
            let mut v = ((g("value") + g("per_metre") * t) / step).round() * step;
            if let Some(min) = s["min"].as_f64() {
                v = v.max(min);
            }
            let digits = (-(step.log10() + 1e-9).floor()).max(0.0) as usize;
            json!(format!("{v:.digits$} {}", s["unit"].as_str().unwrap()))
        }
        None => {
            let mm = |v: f64| format!("{} mm", (v * 1e4).round() / 10.0);
            let at = p(&h["at"]);
            json!([mm(at[0] + d[0]), mm(at[1] + d[1])])
        }
    }
}

/// The handles of `m` with the key `key`.
fn handles_of<'a>(m: &'a Value, key: &str) -> Vec<&'a Value> {
    (m["handles"].as_array().unwrap().iter())
        .filter(|h| h["key"] == key)
        .collect()
}

/// A length or a point of the TOML `text` at the dotted `key` (m), read by the program's
/// unit parser.
fn toml_lengths(text: &str, key: &str) -> Vec<f64> {
    let mut v: toml::Value = toml::from_str(text).unwrap();
    for part in key.split('.') {
        v = match part.split_once('[') {
            Some((n, i)) => v[n][i.trim_end_matches(']').parse::<usize>().unwrap()].clone(),
            None => v[part].clone(),
        };
    }
    let one = |x: &toml::Value| cwsynth::units::parse_any(x.as_str().unwrap()).unwrap().0;
    match &v {
        toml::Value::Array(a) => a.iter().map(one).collect(),
        x => vec![one(x)],
    }
}

/// The point `q` of a frame at `pose` ([x, y, angle]) in the world.
fn placed(pose: &Value, q: [f64; 2]) -> [f64; 2] {
    let [x, y, t] = [0, 1, 2].map(|k| pose[k].as_f64().unwrap());
    [
        x + t.cos() * q[0] - t.sin() * q[1],
        y + t.sin() * q[0] + t.cos() * q[1],
    ]
}

#[test]
fn a_stated_centre_distance_is_a_handle_on_gear_2s_centre_along_the_line_of_centres() {
    let key = "mechanism.center_distance";
    // Where the file leaves it out (the pair's closing distance is computed): no handle.
    for n in ["gear-tooth-profiles.toml", "gear-eccentricity-design.toml"] {
        let f = problems().join(n);
        assert!(!has_key(&std::fs::read_to_string(&f).unwrap(), key), "{n}");
        let (_, m) = solved(&f, None);
        assert!(handles_of(&m, key).is_empty(), "{n}");
    }
    // The paper's a12 = 148 mm: one handle, fixed to the frame at O1 + a12·u on the line of
    // centres O1 → O2 (O2 at the closing distance the model builds the pair with).
    let f = problems().join("gear-paper-table1.toml");
    let text = std::fs::read_to_string(&f).unwrap();
    let (r, m) = solved(&f, None);
    let hs = handles_of(&m, key);
    assert_eq!(hs.len(), 1);
    let h = hs[0];
    let a12 = toml_lengths(&text, key)[0];
    near(a12, 0.148, 1.0, "a12");
    let fr = &m["frames"][0];
    let (o1, o2) = (p(&fr["links"][0][0]), p(&fr["links"][1][0]));
    let closing = r["derived"]["center_distance_m"].as_f64().unwrap();
    near(dist(o1, o2), closing, closing, "O1O2, the closing distance");
    let u = [(o2[0] - o1[0]) / closing, (o2[1] - o1[1]) / closing];
    let at = p(&h["at"]);
    assert!(dist(at, [o1[0] + a12 * u[0], o1[1] + a12 * u[1]]) < 1e-12);
    assert!(
        dist(at, o2) < 0.05e-3,
        "on gear 2's drawn centre: {at:?} {o2:?}"
    );
    assert!(h.get("poses").is_none(), "fixed to the frame");
    let s = &h["scalar"];
    assert!(dist(p(&s["axis"]), u) < 1e-15);
    near(s["value"].as_f64().unwrap(), 148.0, 148.0, "a12 in mm");
    assert_eq!(s["unit"], "mm");
    // Moved by d along the line, a12 grows by d and the handle follows; the pair stays at
    // its closing distance, and the result compares the new stated value with it.
    for d in [2.5e-3, -1.2e-3, 0.5e-3] {
        let v = page_value_moved(h, [d * u[0], d * u[1]]);
        let edited = set_key(&text, key, &v).unwrap();
        let got = toml_lengths(&edited, key)[0];
        assert!((got - (a12 + d)).abs() < 1e-12, "{v}: {got}");
        let (r2, m2) = solved(&f, Some(&edited));
        let h2 = handles_of(&m2, key);
        assert_eq!(h2.len(), 1);
        let moved = [at[0] + d * u[0], at[1] + d * u[1]];
        assert!(dist(p(&h2[0]["at"]), moved) < 1e-12, "{v}");
        assert_eq!(m2["frames"][0]["links"][1][0], fr["links"][1][0], "{v}: O2");
        let said = format!("mechanism.center_distance: stated {:.4} mm", got * 1e3);
        assert!(
            r2["warnings"]
                .as_array()
                .unwrap()
                .iter()
                .any(|w| w.as_str().unwrap().starts_with(&said)),
            "{said}"
        );
    }
}

#[test]
fn a_drawn_outlines_given_origin_is_a_ring_handle_at_its_links_joint() {
    let f = problems().join("linkage-fourbar-crank-outline.toml");
    let shipped = std::fs::read_to_string(&f).unwrap();
    let origins = |m: &Value| -> Vec<String> {
        (m["handles"].as_array().unwrap().iter())
            .map(|h| h["key"].as_str().unwrap().to_string())
            .filter(|k| k.ends_with(".outline.origin"))
            .collect()
    };
    // The shipped file gives the crank's origin only.
    let (_, m) = solved(&f, None);
    assert_eq!(origins(&m), ["mechanism.links.crank.outline.origin"]);
    // Without it, none; with the counterweight's too (its drawing turned by 30°), two.
    let crank = ", origin = [\"0 mm\", \"0 mm\"] }";
    let (_, bare) = solved(&f, Some(&crate::common::with(&shipped, crank, " }")));
    assert!(origins(&bare).is_empty());
    let cw = "thickness = \"28 mm\", density = \"7850 kg/m^3\" }";
    let text = crate::common::with(
        &shipped,
        cw,
        "thickness = \"28 mm\", density = \"7850 kg/m^3\", origin = [\"2 mm\", \"-1 mm\"], angle = \"30 deg\" }",
    );
    let (r, m) = solved(&f, Some(&text));
    let keys = origins(&m);
    assert_eq!(
        keys,
        [
            "mechanism.links.crank.outline.origin",
            "design.counterweights[0].outline.origin"
        ]
    );
    let angle = [0.0, 30f64.to_radians()];
    let frames = m["frames"].as_array().unwrap();
    // The counterweight's centroid in the crank's frame (the crank: A0 → its pin).
    let local_cw = |fr: &Value| {
        let (a0, pin) = (p(&fr["links"][0][0]), p(&fr["links"][0][1]));
        let psi = (pin[1] - a0[1]).atan2(pin[0] - a0[0]);
        let c = p(&fr["counterweights"][0]);
        let (dx, dy) = (c[0] - a0[0], c[1] - a0[1]);
        [
            psi.cos() * dx + psi.sin() * dy,
            -psi.sin() * dx + psi.cos() * dy,
        ]
    };
    let drawn_crank = |m: &Value| -> Vec<[f64; 2]> {
        let b = (m["bodies"].as_array().unwrap().iter())
            .find(|b| b["name"] == "crank (drawn)")
            .expect("the crank as drawn");
        (b["loops"].as_array().unwrap().iter())
            .flat_map(|l| l.as_array().unwrap().iter().map(p))
            .collect()
    };
    for (k, key) in keys.iter().enumerate() {
        let hs = handles_of(&m, key);
        assert_eq!(hs.len(), 1, "{key}");
        let h = hs[0];
        assert_eq!(h["ring"], true, "{key}");
        // Its `at` is the origin as the file gives it (the drawing's coordinates, m) ...
        let given = toml_lengths(&text, key);
        assert!(dist(p(&h["at"]), [given[0], given[1]]) < 1e-15, "{key}");
        // ... and that drawing point is the reference point: the crank pivot A0 in every
        // frame, the drawing's axes turned by −angle from the crank's.
        for (fr, pose) in frames.iter().zip(h["poses"].as_array().unwrap()) {
            let a0 = p(&fr["links"][0][0]);
            assert!(dist(placed(pose, p(&h["at"])), a0) < 1e-12, "{key}");
            let theta = fr["theta"].as_f64().unwrap();
            let turn = (pose[2].as_f64().unwrap() - (theta - angle[k])).rem_euclid(TAU);
            assert!(turn.min(TAU - turn) < 1e-12, "{key} at θ = {theta}");
        }
        assert_eq!(h["poses"].as_array().unwrap().len(), frames.len());
        // Moved by d (mm steps, in its frame): the field changes by d; re-solved, the
        // handle is at the new origin, again at A0, and the part has moved the other way:
        // by −Rot(−angle) d in the crank's frame.
        for d in [[1.5e-3, -0.7e-3], [-4e-3, 2.2e-3]] {
            let v = page_value_moved(h, d);
            let edited = set_key(&text, key, &v).unwrap();
            let got = toml_lengths(&edited, key);
            for i in 0..2 {
                assert!((got[i] - (given[i] + d[i])).abs() < 1e-12, "{key} {v}");
            }
            let (r2, m2) = solved(&f, Some(&edited));
            assert_ne!(r2["objectives"], r["objectives"], "{key} {v}");
            let h2 = handles_of(&m2, key)[0];
            assert!(dist(p(&h2["at"]), [got[0], got[1]]) < 1e-15);
            let fr2 = &m2["frames"][7];
            assert!(
                dist(
                    placed(&h2["poses"][7], p(&h2["at"])),
                    p(&fr2["links"][0][0])
                ) < 1e-12
            );
            let (c, s) = (angle[k].cos(), angle[k].sin());
            let shift = [-(c * d[0] + s * d[1]), -(-s * d[0] + c * d[1])];
            if key.starts_with("design.") {
                let (before, after) = (local_cw(&frames[7]), local_cw(fr2));
                for i in 0..2 {
                    assert!((after[i] - before[i] - shift[i]).abs() < 1e-12, "{key} {v}");
                }
            } else {
                let (before, after) = (drawn_crank(&m), drawn_crank(&m2));
                assert_eq!(before.len(), after.len());
                for (a, b) in before.iter().zip(&after) {
                    for i in 0..2 {
                        assert!((b[i] - a[i] - shift[i]).abs() < 1e-12, "{key} {v}");
                    }
                }
            }
        }
    }
    handles(&f, &text, &m);
}

#[test]
fn the_lanchester_shafts_turn_their_masses_as_the_model_does() {
    use cwsynth::families::hypocycloid::model::LanchesterPair;
    use cwsynth::report::motion::{DISC_THICKNESS, STEEL_DENSITY};
    // Without [mechanism.lanchester] the shafts have no place: not drawn.
    let (_, m) = solved(&problems().join("hypocycloid-variant1.toml"), None);
    assert_eq!(m["names"].as_array().unwrap().len(), 4);
    let lanchester = |m: &Value| -> Vec<Value> {
        (m["bodies"].as_array().unwrap().iter())
            .enumerate()
            .filter(|(_, b)| b["name"].as_str().unwrap().starts_with("Lanchester mass"))
            .map(|(i, b)| json!([i, b]))
            .collect()
    };
    assert!(lanchester(&m).is_empty());
    let f = problems().join("hypocycloid-compressor.toml");
    let (r, m) = solved(&f, None);
    let layout = &r["dynamics"]["couples"]["layout"];
    let (e, d) = (
        layout["offset"].as_f64().unwrap(),
        layout["spacing"].as_f64().unwrap(),
    );
    // The model's shafts: the co-rotating at (d/2, e), the counter-rotating at (−d/2, e).
    let shafts = [[0.5 * d, e], [-0.5 * d, e]];
    assert_eq!(m["names"][4], "+ω, +2ω, +3ω");
    assert_eq!(m["names"][5], "−ω, −2ω, −3ω");
    let pairs: Vec<LanchesterPair> = (r["balancing"].as_array().unwrap().iter())
        .map(|b| {
            let g = |k: &str| b[k].as_f64().unwrap();
            LanchesterPair {
                order: b["order"].as_u64().unwrap() as usize,
                speed: g("shaft_speed_rad_s"),
                static_moment: g("static_moment_kgm"),
                phase_co: g("phase_co_rad"),
                phase_counter: g("phase_counter_rad"),
            }
        })
        .collect();
    assert_eq!(pairs.len(), 3);
    let bodies = lanchester(&m);
    // Co-rotating masses order by order, then counter-rotating.
    assert_eq!(bodies.len(), 2 * pairs.len());
    let sigma = STEEL_DENSITY * DISC_THICKNESS;
    for fr in m["frames"].as_array().unwrap() {
        let phi = fr["theta"].as_f64().unwrap();
        for (k, s) in shafts.iter().enumerate() {
            let c = p(&fr["links"][4 + k][0]);
            assert!(dist(c, *s) < 1e-15 && dist(p(&fr["links"][4 + k][1]), *s) < 1e-15);
        }
        for (j, pair) in pairs.iter().enumerate() {
            // Σ over the pair's two bodies of (mass × centroid from its shaft) × (iω)²: the
            // pair's force in the model, each body's mass from its outline as drawn (a
            // steel half-disc of σ = ρt; its polygon of 48 chords per half turn holds the
            // disc's first moment to 1.07e-3, below).
            let mut force = [0.0, 0.0];
            for (side, (shaft, phase)) in [(0, pair.phase_co), (1, pair.phase_counter)]
                .iter()
                .map(|&(k, ph)| (k, (shafts[k], ph)))
            {
                let (i, b) = {
                    let x = &bodies[side * pairs.len() + j];
                    (x[0].as_u64().unwrap() as usize, &x[1])
                };
                let pose = &fr["poses"][i];
                assert!(dist(placed(pose, [0.0, 0.0]), shaft) < 1e-15);
                let sense = if side == 0 { 1.0 } else { -1.0 };
                let want = sense * pair.order as f64 * phi + phase;
                let turn = (pose[2].as_f64().unwrap() - want).rem_euclid(TAU);
                assert!(
                    turn.min(TAU - turn) < 1e-12,
                    "order {} at φ = {phi}",
                    pair.order
                );
                // The outline's first moment of area about the shaft (Green's theorem over
                // its polygon).
                let pts: Vec<[f64; 2]> = (b["loops"][0].as_array().unwrap().iter())
                    .map(|q| placed(pose, p(q)))
                    .collect();
                let (mut mx, mut my) = (0.0, 0.0);
                for w in 0..pts.len() {
                    let (a, c) = (pts[w], pts[(w + 1) % pts.len()]);
                    let (a, c) = (
                        [a[0] - shaft[0], a[1] - shaft[1]],
                        [c[0] - shaft[0], c[1] - shaft[1]],
                    );
                    let cr = a[0] * c[1] - a[1] * c[0];
                    mx += (a[0] + c[0]) * cr / 6.0;
                    my += (a[1] + c[1]) * cr / 6.0;
                }
                let moment = (sigma * mx).hypot(sigma * my);
                assert!(
                    (moment - pair.static_moment).abs() < 1.5e-3 * pair.static_moment,
                    "order {}: m′r′ {moment} against {}",
                    pair.order,
                    pair.static_moment
                );
                let w2 = pair.speed * pair.speed;
                force[0] += sigma * mx * w2;
                force[1] += sigma * my * w2;
            }
            let (fx, fy) = pair.force(phi);
            let scale = 2.0 * pair.static_moment * pair.speed * pair.speed;
            assert!(
                (force[0] - fx).hypot(force[1] - fy) < 1.5e-3 * scale,
                "order {} at φ = {phi}: {force:?} against ({fx}, {fy})",
                pair.order
            );
        }
    }
}

/// A hung and a lever counterweight move in the motion view along the paths the balance
/// computes (`balance.counterweight_path`): at maximum reach (the first frame) and at minimum
/// reach (the middle frame) the drawn centroid is the path's, the hanger runs from the
/// suspension point straight down, and the lever's rod ends at the path's rod pins.
#[test]
fn hung_and_lever_counterweights_move_along_their_paths() {
    for name in [
        "crane-tukan-40t-hanging-counterweight.toml",
        "crane-tukan-40t-lever-counterweight.toml",
    ] {
        let (r, m) = solved(&problems().join(name), None);
        let path = &r["balance"]["counterweight_path"];
        let frames = m["frames"].as_array().unwrap();
        let names: Vec<&str> = m["names"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_str().unwrap())
            .collect();
        for (i, f) in [(0, &frames[0]), (1, &frames[frames.len() / 2])] {
            let want = p(&path["centroid_m"][i]);
            let got = p(&f["counterweights"][0]);
            assert!(dist(want, got) <= 1e-9, "{name} {i}: {got:?} vs {want:?}");
            assert_eq!(f["links"].as_array().unwrap().len(), names.len(), "{name}");
            if path["kind"] == "hanging" {
                let top = p(&path["suspension_point_m"][i]);
                assert!(
                    dist(p(&f["links"][3][1]), top) <= 1e-9,
                    "{name}: the boom's tail"
                );
                assert!(dist(p(&f["links"][4][0]), top) <= 1e-9, "{name}");
                assert!(dist(p(&f["links"][4][1]), got) <= 1e-9, "{name}");
                assert!(
                    (top[0] - got[0]).abs() <= 1e-9,
                    "{name}: the hanger is vertical"
                );
            } else {
                let [l, k] = [0, 1].map(|j| p(&path["rod_pins_m"][i][j]));
                assert!(dist(p(&f["links"][4][0]), l) <= 1e-9, "{name}");
                assert!(dist(p(&f["links"][4][1]), k) <= 1e-9, "{name}");
            }
        }
        let bodies = m["bodies"].as_array().unwrap();
        assert_eq!(bodies.len(), 1, "{name}");
    }
}
