//! `POST /api/edit`: one key of a problem file set to a new value with `toml_edit`, every
//! other byte of the file kept (its comments, order and layout, and the key's own trailing
//! comment): what a drag in the designer writes, so that the saved file is the user's file.

use serde_json::Value;
use toml_edit::{Array, DocumentMut, Item, TableLike};

/// `text` with the dotted `key` (`mechanism.dyads[1].q`: tables, `[i]` the i-th entry of an
/// array of tables) set to `value` (a string, number, boolean or array of them); the last
/// name may be new in an existing table. `Err`: why not (the text does not parse, a name or
/// an entry does not exist, the value is not one TOML holds).
pub fn set_key(text: &str, key: &str, value: &Value) -> Result<String, String> {
    let mut doc: DocumentMut = text
        .parse()
        .map_err(|e| format!("the file does not parse: {e}"))?;
    let parts = path(key)?;
    let mut table: &mut dyn TableLike = doc.as_table_mut();
    for (i, (name, index)) in parts.iter().enumerate() {
        if i + 1 == parts.len() && index.is_none() {
            let mut new = toml_value(value)?;
            if let Some(old) = table.get(name).and_then(Item::as_value) {
                *new.decor_mut() = old.decor().clone();
            }
            table.insert(name, Item::Value(new));
            return Ok(doc.to_string());
        }
        let item = table
            .get_mut(name)
            .ok_or_else(|| format!("{key}: no `{name}` there"))?;
        table = match index {
            None => item
                .as_table_like_mut()
                .ok_or_else(|| format!("{key}: `{name}` is not a table"))?,
            Some(k) => match item {
                Item::ArrayOfTables(a) => a
                    .get_mut(*k)
                    .map(|t| t as &mut dyn TableLike)
                    .ok_or_else(|| format!("{key}: `{name}` has no entry {k}"))?,
                _ => return Err(format!("{key}: `{name}` is not an array of tables")),
            },
        };
    }
    Err(format!("{key}: allowed: a dotted key ending in a name"))
}

/// The parts of a dotted key: each name with its `[i]`, if any.
fn path(key: &str) -> Result<Vec<(String, Option<usize>)>, String> {
    key.split('.')
        .map(|part| {
            let (name, index) = match part.split_once('[') {
                Some((n, rest)) => {
                    let i = rest
                        .strip_suffix(']')
                        .and_then(|i| i.parse().ok())
                        .ok_or_else(|| format!("{key}: `{part}` is no name[index]"))?;
                    (n, Some(i))
                }
                None => (part, None),
            };
            let ok = !name.is_empty()
                && name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            ok.then(|| (name.to_string(), index))
                .ok_or_else(|| format!("{key}: `{name}` is no key name"))
        })
        .collect()
}

/// A JSON value as a TOML one.
fn toml_value(v: &Value) -> Result<toml_edit::Value, String> {
    Ok(match v {
        Value::String(s) => s.as_str().into(),
        Value::Bool(b) => (*b).into(),
        Value::Number(n) => match n.as_i64() {
            Some(i) => i.into(),
            None => n.as_f64().ok_or("a number TOML cannot hold")?.into(),
        },
        Value::Array(a) => {
            let mut out = Array::new();
            for x in a {
                out.push(toml_value(x)?);
            }
            out.into()
        }
        _ => return Err("allowed: a string, number, boolean or array of them".into()),
    })
}
