//! The JSON Schema of the problem file (`cwsynth schema`): every shipped problem file
//! validates against it, and files with unknown keys, wrong types or bad units do not.
//!
//! The validator below implements exactly the subset of JSON Schema the program emits:
//! type, properties, required, additionalProperties (false or a schema), enum, const, oneOf, anyOf,
//! allOf, if/then, items,
//! minItems/maxItems, minimum, maxLength and pattern. TOML is converted to JSON with `toml` and
//! `serde_json`.

use cwsynth::families::problem_schema;
use serde_json::Value;

/// Errors of `v` against schema `s`, each with its JSON path.
fn validate(s: &Value, v: &Value, path: &str, errs: &mut Vec<String>) {
    let Some(s) = s.as_object() else { return };
    for key in s.keys() {
        assert!(
            [
                "$schema",
                "$id",
                "title",
                "description",
                "type",
                "properties",
                "required",
                "additionalProperties",
                "enum",
                "oneOf",
                "anyOf",
                "allOf",
                "if",
                "then",
                "const",
                "items",
                "minItems",
                "maxItems",
                "minimum",
                "maximum",
                "maxLength",
                "pattern",
                // Annotations: no effect on validity.
                "default",
                "format"
            ]
            .contains(&key.as_str()),
            "the schema uses `{key}`, which this validator does not implement"
        );
    }
    if let Some(t) = s.get("type").and_then(Value::as_str) {
        let ok = match t {
            "object" => v.is_object(),
            "array" => v.is_array(),
            "string" => v.is_string(),
            "number" => v.is_number(),
            "integer" => v.is_i64() || v.is_u64(),
            "boolean" => v.is_boolean(),
            other => panic!("type {other}"),
        };
        if !ok {
            errs.push(format!("{path}: not of type {t}: {v}"));
            return;
        }
    }
    if let (Some(m), Some(x)) = (s.get("maxLength").and_then(Value::as_u64), v.as_str()) {
        if x.chars().count() as u64 > m {
            errs.push(format!("{path}: longer than {m} characters"));
        }
    }
    if let Some(c) = s.get("const") {
        if c != v {
            errs.push(format!("{path}: {v} is not {c}"));
        }
    }
    if let Some(e) = s.get("enum").and_then(Value::as_array) {
        if !e.contains(v) {
            errs.push(format!("{path}: {v} not in {e:?}"));
        }
    }
    if let (Some(m), Some(x)) = (s.get("minimum").and_then(Value::as_f64), v.as_f64()) {
        if x < m {
            errs.push(format!("{path}: {x} < minimum {m}"));
        }
    }
    if let (Some(m), Some(x)) = (s.get("maximum").and_then(Value::as_f64), v.as_f64()) {
        if x > m {
            errs.push(format!("{path}: {x} > maximum {m}"));
        }
    }
    if let (Some(p), Some(x)) = (s.get("pattern").and_then(Value::as_str), v.as_str()) {
        if !regex::Regex::new(p).unwrap().is_match(x) {
            errs.push(format!("{path}: {x:?} does not match {p}"));
        }
    }
    if let Some(o) = v.as_object() {
        let props = s.get("properties").and_then(Value::as_object);
        for r in s
            .get("required")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            let r = r.as_str().unwrap();
            if !o.contains_key(r) {
                errs.push(format!("{path}: missing required `{r}`"));
            }
        }
        for (k, x) in o {
            match props.and_then(|p| p.get(k)) {
                Some(ps) => validate(ps, x, &format!("{path}.{k}"), errs),
                None => match s.get("additionalProperties") {
                    Some(Value::Bool(false)) => errs.push(format!("{path}: unknown key `{k}`")),
                    // A map (`[mechanism.links.NAME]`): every value against one schema.
                    Some(extra @ Value::Object(_)) => {
                        validate(extra, x, &format!("{path}.{k}"), errs)
                    }
                    _ => {}
                },
            }
        }
    }
    if let Some(a) = v.as_array() {
        if let Some(n) = s.get("minItems").and_then(Value::as_u64) {
            if (a.len() as u64) < n {
                errs.push(format!("{path}: fewer than {n} items"));
            }
        }
        if let Some(n) = s.get("maxItems").and_then(Value::as_u64) {
            if (a.len() as u64) > n {
                errs.push(format!("{path}: more than {n} items"));
            }
        }
        if let Some(it) = s.get("items") {
            for (i, x) in a.iter().enumerate() {
                validate(it, x, &format!("{path}[{i}]"), errs);
            }
        }
    }
    let branch_errors = |bs: &Vec<Value>| -> Vec<Vec<String>> {
        bs.iter()
            .map(|b| {
                let mut e = Vec::new();
                validate(b, v, path, &mut e);
                e
            })
            .collect()
    };
    for b in s
        .get("allOf")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
    {
        validate(b, v, path, errs);
    }
    if let Some(cond) = s.get("if") {
        let mut e = Vec::new();
        validate(cond, v, path, &mut e);
        if e.is_empty() {
            if let Some(then) = s.get("then") {
                validate(then, v, path, errs);
            }
        }
    }
    if let Some(bs) = s.get("anyOf").and_then(Value::as_array) {
        let r = branch_errors(bs);
        if r.iter().all(|e| !e.is_empty()) {
            errs.push(format!("{path}: matches no anyOf branch: {r:?}"));
        }
    }
    if let Some(bs) = s.get("oneOf").and_then(Value::as_array) {
        let r = branch_errors(bs);
        let n = r.iter().filter(|e| e.is_empty()).count();
        if n != 1 {
            // Report the branch of the right family (fewest errors) for a readable message.
            let best = r.iter().min_by_key(|e| e.len()).unwrap();
            errs.push(format!(
                "{path}: matches {n} oneOf branches (want 1); nearest: {best:?}"
            ));
        }
    }
}

fn to_json(toml_text: &str) -> Value {
    let t: toml::Value = toml::from_str(toml_text).unwrap();
    serde_json::to_value(t).unwrap()
}

fn errors(text: &str) -> Vec<String> {
    let mut e = Vec::new();
    validate(&problem_schema(), &to_json(text), "$", &mut e);
    e
}

fn shipped() -> Vec<(String, String)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/problems");
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| {
            (
                p.display().to_string(),
                std::fs::read_to_string(&p).unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

#[test]
fn every_shipped_problem_file_validates() {
    let files = shipped();
    assert!(files.len() >= 13);
    let mut families = std::collections::BTreeSet::new();
    for (p, text) in &files {
        let e = errors(text);
        assert!(e.is_empty(), "{p}:\n{}", e.join("\n"));
        families.insert(to_json(text)["family"].as_str().unwrap().to_string());
    }
    assert_eq!(
        families.len(),
        cwsynth::families::FAMILIES.len(),
        "{families:?}"
    );
}

#[test]
fn unknown_keys_wrong_types_and_bad_units_fail() {
    let piston = include_str!("../problems/piston-1000rpm.toml");
    let bad = [
        // An unknown key at the top, in a section, in a nested table.
        piston.replacen("name = ", "colour = \"red\"\nname = ", 1),
        piston.replacen("rod_mass = ", "rod_masss = ", 1),
        piston.replacen(
            "unbalance = { min = \"0 kg*m\"",
            "unbalance = { low = 1, min = \"0 kg*m\"",
            1,
        ),
        // A quantity of the wrong dimension, an unknown unit, a wrong type.
        piston.replacen("\"35 mm\"", "\"35 kg\"", 1),
        piston.replacen("\"35 mm\"", "\"35 furlong\"", 1),
        piston.replacen("\"35 mm\"", "true", 1),
        // An enum value misspelt; a family that does not exist.
        piston.replacen("\"exact\"", "\"exakt\"", 1),
        piston.replacen("\"slider-crank\"", "\"slider-rocker\"", 1),
        // A crane key in a slider-crank file.
        piston.replacen("[model]", "[model]\nsizing = \"min-reach\"", 1),
        // A required key missing.
        piston.replacen("crank_radius = \"35 mm\"\n", "", 1),
        // Units are never guessed: a bare number in a dimensional field, a bare range bound.
        piston.replacen("\"35 mm\"", "0.035", 1),
        piston.replacen("\"1000 rpm\"", "1500", 1),
        piston.replacen("\"35 mm\"", "\"35\"", 1),
        piston.replacen("min = \"0 deg\"", "min = 0", 1),
        // An integer setting above its maximum (u64::MAX is no JSON value to validate; the
        // reader's error for it is in tests/integer_limits.rs).
        piston.replacen("rel_tol = 1e-9", "rel_tol = 1e-9\nrms_samples = 100001", 1),
    ];
    for (i, t) in bad.iter().enumerate() {
        assert_ne!(t, piston, "case {i} did not change the file");
        let e = errors(t);
        assert!(!e.is_empty(), "case {i} should fail:\n{t}");
        // The program rejects it too (the schema is no looser than the reader here).
        assert!(
            cwsynth::families::parse_str(t, std::path::Path::new("x.toml")).is_err(),
            "case {i}"
        );
    }
    // Each accepted unit spelling of a length passes.
    for u in ["\"35mm\"", "\"3.5 cm\"", "\"3.5e-2 m\"", "\"35e-3 m\""] {
        let t = piston.replacen("\"35 mm\"", u, 1);
        assert!(errors(&t).is_empty(), "{u}: {:?}", errors(&t));
    }
}

#[test]
fn cli_prints_the_schema() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cwsynth"))
        .arg("schema")
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["$schema"], "https://json-schema.org/draft/2020-12/schema");
    let branches = v["allOf"].as_array().unwrap();
    assert_eq!(branches.len(), cwsynth::families::FAMILIES.len());
    for b in branches {
        assert!(b["if"]["properties"]["family"]["const"].is_string(), "{b}");
    }
}

/// The branches are discriminated on `family` (`if`/`then`): a typo in a file is an error at
/// its own key, checked against its own family only — not "matches no branch" for the file.
#[test]
fn a_typo_is_one_error_at_its_key() {
    let piston = include_str!("../problems/piston-1000rpm.toml");
    let e = errors(&piston.replacen("rod_split = ", "rod_splitt = ", 1));
    assert_eq!(e, ["$.model: unknown key `rod_splitt`"]);
    let e = errors(&piston.replacen("\"1000 rpm\"", "1500", 1));
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(e[0].contains(".mechanism.speed"), "{e:?}");
}

/// Every key of every family is described (the schema's descriptions are the raw structs'
/// doc comments, so an undocumented field shows up here).
#[test]
fn every_key_is_described() {
    fn walk(n: &Value, path: &str, missing: &mut Vec<String>) {
        match n {
            Value::Object(o) => {
                for (k, v) in o
                    .get("properties")
                    .and_then(Value::as_object)
                    .into_iter()
                    .flatten()
                {
                    if v.get("description").is_none() && k != "family" {
                        missing.push(format!("{path}.{k}"));
                    }
                }
                for (k, v) in o {
                    walk(v, &format!("{path}/{k}"), missing);
                }
            }
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    walk(x, &format!("{path}[{i}]"), missing);
                }
            }
            _ => {}
        }
    }
    let mut missing = Vec::new();
    walk(&problem_schema(), "", &mut missing);
    assert!(
        missing.is_empty(),
        "keys without a description: {missing:#?}"
    );
}
