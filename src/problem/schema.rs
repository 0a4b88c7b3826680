//! A JSON Schema (draft 2020-12) of the problem file, for editors (`cwsynth schema`): the
//! builders every family's branch is written with, and the assembly of the branches.
//!
//! Each family writes its branch by hand from its raw serde structs
//! (`families/<family>/schema.rs`); [`assemble`] puts one branch per family under `allOf` as
//! `if: {family: const} then: branch` — discriminated on `family`, so an editor checks a file
//! against its own family's branch only and points at the wrong key, not at the whole file —
//! each branch closed with
//! `additionalProperties: false` like the structs' `deny_unknown_fields`. A dimensional
//! quantity is a `string` whose pattern is a number and one of the units of its dimension,
//! built from [`crate::units::UNITS`] (units are never guessed: no bare number); a pure
//! number (λ, k1) is a `number`. The input sizes have `maxLength`/`maxItems` (quantity
//! strings, `description`, `[[paper]]`, the slider-crank's arrays). Every integer setting has
//! the `minimum` and `maximum` of
//! [`super::limits`]. The schema checks shape and spelling; other value ranges (λ < 1,
//! min ≤ max, …) stay with the resolvers, whose errors name the field.
//!
//! Keep it in step with the structs: `tests/schema.rs` validates every shipped problem file
//! against it and shows that unknown keys fail.

use crate::problem::limits::Count;
use crate::problem::{MAX_PAPER_ENTRIES, MAX_TEXT_CHARS};
use crate::units::{Dim, UNITS};
use serde_json::{json, Map, Value};

/// A number, then optional spaces and a unit of `dim` (`None`: any known unit, or none).
pub fn quantity_pattern(dim: Option<Dim>) -> String {
    let mut alts: Vec<String> = UNITS
        .iter()
        .filter(|u| dim.is_none_or(|d| u.dim == d))
        .map(|u| {
            let mut s = String::new();
            for c in u.symbol.chars() {
                match c {
                    // The reader treats `·`, `*`, `.`, `⋅`, `-` and spaces alike.
                    '·' | '*' => s.push_str("\\s*[·*.⋅-]?\\s*"),
                    '^' | '/' | '.' | '+' | '(' | ')' | '[' | ']' | '?' | '|' | '$' | '\\' => {
                        s.push('\\');
                        s.push(c);
                    }
                    c => s.push(c),
                }
            }
            s
        })
        .collect();
    // Longest first, so that `mm` is not read as `m` + rest.
    alts.sort_by_key(|a| std::cmp::Reverse(a.len()));
    let num = r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?";
    let optional = if dim.is_none() { "?" } else { "" };
    if alts.is_empty() {
        format!(r"^\s*{num}\s*$")
    } else {
        format!(r"^\s*{num}\s*({}){optional}\s*$", alts.join("|"))
    }
}

pub fn qty(dim: Dim, desc: &str) -> Value {
    let description = format!("{desc} — {}", dim.allowed());
    match dim {
        Dim::Dimensionless => json!({ "type": "number", "description": description }),
        _ => json!({
            "description": description,
            "type": "string",
            "maxLength": crate::units::MAX_QUANTITY_LEN,
            "pattern": quantity_pattern(Some(dim))
        }),
    }
}

pub fn var(dim: Dim, desc: &str) -> Value {
    json!({
        "description": format!("{desc}: fixed, or free within {{ min, max }}"),
        "anyOf": [
            qty(dim, desc),
            obj(&[("min", qty(dim, "lower bound")), ("max", qty(dim, "upper bound"))], &["min", "max"], "a free range")
        ]
    })
}

pub fn num(desc: &str) -> Value {
    json!({ "type": "number", "description": desc })
}

pub fn uint(desc: &str) -> Value {
    json!({ "type": "integer", "minimum": 0, "description": desc })
}

pub fn boolean(desc: &str) -> Value {
    json!({ "type": "boolean", "description": desc })
}

pub fn string(desc: &str) -> Value {
    json!({ "type": "string", "description": desc })
}

pub fn one_of(values: &[&str], desc: &str) -> Value {
    json!({ "type": "string", "enum": values, "description": desc })
}

pub fn array(items: Value, desc: &str) -> Value {
    json!({ "type": "array", "items": items, "description": desc })
}

pub fn obj(props: &[(&str, Value)], required: &[&str], desc: &str) -> Value {
    let mut p = Map::new();
    for (k, v) in props {
        p.insert((*k).to_string(), v.clone());
    }
    json!({
        "type": "object",
        "description": desc,
        "properties": p,
        "required": required,
        "additionalProperties": false
    })
}

/// `v` with the JSON Schema keyword `key` set to `n` (an input-size limit).
pub fn limited(mut v: Value, key: &str, n: usize) -> Value {
    v[key] = json!(n);
    v
}

fn paper() -> Value {
    let text = |d| limited(string(d), "maxLength", MAX_TEXT_CHARS);
    let entries = array(
        obj(
            &[
                ("quantity", text("what the paper's number is")),
                (
                    "value",
                    json!({
                        "description": "the paper's value: a quantity string whose unit is of the dimension of the key's SI unit suffix (`_n`: \"900 N\"), or a plain number for a key without one (`_pct`, a ratio)",
                        "anyOf": [
                            { "type": "number" },
                            { "type": "string", "pattern": quantity_pattern(None) }
                        ]
                    }),
                ),
                ("key", text("dotted result key compared with")),
                ("note", text("how to read the comparison")),
            ],
            &["quantity", "value", "key"],
            "a value printed in the source paper",
        ),
        "printed values of the source paper to compare with",
    );
    limited(entries, "maxItems", MAX_PAPER_ENTRIES)
}

/// One family's branch: the common keys plus its sections.
pub fn family(
    name: &str,
    mechanism: Value,
    model: Value,
    design: Value,
    objective: Value,
    accuracy: Value,
) -> Value {
    obj(
        &[
            (
                "name",
                json!({
                    "type": "string",
                    "pattern": "^[A-Za-z0-9_-][A-Za-z0-9._-]{0,127}$",
                    "description": "scene name (also the result file's stem)"
                }),
            ),
            ("family", json!({ "type": "string", "enum": [name] })),
            (
                "description",
                limited(string("free text"), "maxLength", MAX_TEXT_CHARS),
            ),
            ("mechanism", mechanism),
            ("model", model),
            ("design", design),
            ("objective", objective),
            ("accuracy", accuracy),
            ("paper", paper()),
        ],
        &["name", "family", "mechanism", "objective"],
        &format!("a {name} scene"),
    )
}

/// The JSON Schema of a problem file from each family's `(name, branch, integer ranges)`:
/// one `if: {family: const name} then: branch` per family under `allOf` (the `family` enum
/// lists the names), each branch with the `minimum` and `maximum` of its integer keys.
pub fn assemble(families: Vec<(&str, Value, &[Count])>) -> Value {
    let names: Vec<&str> = families.iter().map(|(n, _, _)| *n).collect();
    let branches: Vec<Value> = families
        .into_iter()
        .map(|(name, mut branch, counts)| {
            with_ranges(name, counts, &mut branch);
            json!({
                "if": {
                    "properties": { "family": { "const": name } },
                    "required": ["family"]
                },
                "then": branch
            })
        })
        .collect();
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": "https://github.com/cwsynth/cwsynth/problem-file.schema.json",
        "title": "cwsynth problem file",
        "description": "One machine (scene) in TOML; see docs/problem-files.md. A dimensional quantity is a string with a unit (\"35 mm\"); a bare number is a pure number.",
        "type": "object",
        "required": ["name", "family", "mechanism", "objective"],
        "properties": {
            "family": {
                "type": "string",
                "enum": names
            }
        },
        "allOf": branches
    })
}

/// Sets `minimum` and `maximum` of every integer key of a family ([`super::limits`]) in its
/// branch (for an array of integers, on its items).
fn with_ranges(family: &str, counts: &[Count], branch: &mut Value) {
    for c in counts {
        let mut node = &mut *branch;
        for part in c.key.split('.') {
            node = &mut node["properties"][part];
        }
        if node.get("items").is_some() {
            node = &mut node["items"];
        }
        assert!(
            node["type"] == "integer",
            "schema: {family} {} is no integer",
            c.key
        );
        node["minimum"] = c.min.into();
        node["maximum"] = c.max.into();
    }
}
