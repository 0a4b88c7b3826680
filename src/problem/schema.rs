//! A JSON Schema (draft 2020-12) of the problem file, for editors (`cwsynth schema`),
//! derived from the raw serde structs themselves (`schemars`), so that it cannot drift from
//! what the reader accepts.
//!
//! Each family's branch is the schema of its [`super::RawFile`] (`families/<family>/file.rs`
//! and the settings structs its `[accuracy]` reads), generated with every subschema inlined;
//! [`assemble`] puts one branch per family under `allOf` as `if: {family: const} then:
//! branch` — discriminated on `family`, so an editor checks a file against its own family's
//! branch only and points at the wrong key, not at the whole file. Each struct is closed
//! (`additionalProperties: false`) by its `deny_unknown_fields`; field doc comments become
//! descriptions. A dimensional quantity ([`Qty`]) is a `string` whose pattern is a number and
//! one of the units of its dimension, built from [`crate::units::UNITS`] (units are never
//! guessed: no bare number); a pure number (λ, k1) is a `number`; a design variable
//! ([`RawVar`]) is a quantity or `{ min, max }`. Input-size limits are `maxLength`/`maxItems`
//! attributes on the structs; every integer setting gets the `minimum` and `maximum` of
//! [`super::limits`] here. The schema checks shape and spelling; other value ranges (λ < 1,
//! min ≤ max, …) stay with the resolvers, whose errors name the field.
//!
//! `tests/schema.rs` validates every shipped problem file against it and shows that unknown
//! keys fail.

use crate::problem::limits::Count;
use crate::problem::{PaperValue, RawVar};
use crate::units::{Dim, Dimension, Qty, UNITS};
use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, Schema, SchemaGenerator};
use serde_json::{json, Value};
use std::borrow::Cow;

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

/// The schema of a quantity of dimension `dim`: a plain number for a pure number, else a
/// string with a unit of that dimension (its `title` lists the units).
fn quantity(dim: Dim) -> Value {
    match dim {
        Dim::Dimensionless => json!({ "type": "number", "title": dim.allowed() }),
        _ => json!({
            "title": dim.allowed(),
            "type": "string",
            "maxLength": crate::units::MAX_QUANTITY_LEN,
            "pattern": quantity_pattern(Some(dim))
        }),
    }
}

fn schema(v: Value) -> Schema {
    Schema::try_from(v).expect("a schema object")
}

impl<D: Dimension> JsonSchema for Qty<D> {
    fn inline_schema() -> bool {
        true
    }
    fn schema_name() -> Cow<'static, str> {
        format!("Qty{:?}", D::DIM).into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        schema(quantity(D::DIM))
    }
}

impl<D: Dimension> JsonSchema for RawVar<D> {
    fn inline_schema() -> bool {
        true
    }
    fn schema_name() -> Cow<'static, str> {
        format!("RawVar{:?}", D::DIM).into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        let q = quantity(D::DIM);
        let bound = |d: &str| {
            let mut b = q.clone();
            b["description"] = d.into();
            b
        };
        schema(json!({
            "anyOf": [
                q,
                {
                    "type": "object",
                    "title": "free within [min, max]",
                    "properties": { "min": bound("lower bound"), "max": bound("upper bound") },
                    "required": ["min", "max"],
                    "additionalProperties": false
                }
            ]
        }))
    }
}

impl JsonSchema for crate::units::LengthOrAngle {
    fn inline_schema() -> bool {
        true
    }
    fn schema_name() -> Cow<'static, str> {
        "LengthOrAngle".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        schema(json!({ "anyOf": [quantity(Dim::Length), quantity(Dim::Angle)] }))
    }
}

impl JsonSchema for PaperValue {
    fn inline_schema() -> bool {
        true
    }
    fn schema_name() -> Cow<'static, str> {
        "PaperValue".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        schema(json!({
            "description": "the paper's value: a quantity string whose unit is of the dimension of the key's SI unit suffix (`_n`: \"900 N\"), or a plain number for a key without one (`_pct`, a ratio)",
            "anyOf": [
                { "type": "number" },
                { "type": "string", "pattern": quantity_pattern(None) }
            ]
        }))
    }
}

/// The schema of a 2-D frame point written in a file as a TOML value the resolver reads
/// (linkage points): `["x mm", "y mm"]`, `"NAME.pivot"`, `"NAME.tip"` or `{ link, at }`.
pub fn point_ref(_: &mut SchemaGenerator) -> Schema {
    let xy = json!({
        "type": "array", "items": quantity(Dim::Length), "minItems": 2, "maxItems": 2
    });
    schema(json!({
        "description": "a frame point [\"x mm\", \"y mm\"], \"NAME.pivot\", \"NAME.tip\" or { link = \"NAME\", at = [\"x mm\", \"y mm\"] }",
        "anyOf": [
            xy,
            { "type": "string", "pattern": "^[A-Za-z0-9_-]+\\.(pivot|tip)$", "maxLength": 80 },
            {
                "type": "object",
                "properties": {
                    "link": { "type": "string", "description": "the link's name" },
                    "at": { "description": "the point in the link's frame", "allOf": [xy] }
                },
                "required": ["link", "at"],
                "additionalProperties": false
            }
        ]
    }))
}

/// One family's branch: the schema of its whole raw file `F` (a [`super::RawFile`]), every
/// subschema inlined, `family` fixed to `name`. TOML has no null, so the `null` that
/// `schemars` allows for an `Option` is taken out again.
pub fn branch<F: JsonSchema>(name: &str) -> Value {
    let generator = SchemaSettings::draft2020_12()
        .with(|s| {
            s.inline_subschemas = true;
            s.meta_schema = None;
        })
        .into_generator();
    let mut v = generator.into_root_schema_for::<F>().to_value();
    strip_null(&mut v);
    let o = v.as_object_mut().expect("an object schema");
    o.remove("title");
    o.insert("description".into(), format!("a {name} scene").into());
    v["properties"]["family"] = json!({ "type": "string", "enum": [name] });
    v
}

/// Removes `null` from `type` lists and `{type: null}` from `anyOf`/`oneOf`, recursively.
fn strip_null(v: &mut Value) {
    match v {
        Value::Object(o) => {
            if let Some(Value::Array(ts)) = o.get_mut("type") {
                ts.retain(|t| t != "null");
                if ts.len() == 1 {
                    let t = ts[0].clone();
                    o.insert("type".into(), t);
                }
            }
            for k in ["anyOf", "oneOf"] {
                if let Some(Value::Array(alts)) = o.get_mut(k) {
                    alts.retain(|a| *a != json!({ "type": "null" }));
                    if alts.len() == 1 {
                        // `Option<T>` of a non-inline T: the alternative is T itself.
                        let only = alts.pop().expect("one");
                        o.remove(k);
                        if let Value::Object(only) = only {
                            for (key, val) in only {
                                o.entry(key).or_insert(val);
                            }
                        }
                    }
                }
            }
            if o.get("default").is_some_and(Value::is_null) {
                o.remove("default");
            }
            for x in o.values_mut() {
                strip_null(x);
            }
        }
        Value::Array(a) => a.iter_mut().for_each(strip_null),
        _ => {}
    }
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
        // A count that may also be `"auto"`: the range is on its integer member.
        if let Some(i) = node
            .get("anyOf")
            .and_then(Value::as_array)
            .and_then(|a| a.iter().position(|m| m["type"] == "integer"))
        {
            node = &mut node["anyOf"][i];
        }
        assert!(
            node["type"] == "integer",
            "schema: {family} {} is no integer: {node}",
            c.key
        );
        node["minimum"] = c.min.into();
        node["maximum"] = c.max.into();
        if let Some(o) = node.as_object_mut() {
            o.remove("format");
        }
    }
}
