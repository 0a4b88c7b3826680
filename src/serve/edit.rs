//! `POST /api/edit`: one key of a problem file set to a new value (or removed) with
//! `toml_edit`, every other byte of the file kept (its comments, order and layout, and the
//! key's own trailing comment): what a drag or a form field in the designer writes, so that
//! the saved file is the user's file.

use serde_json::Value;
use toml_edit::{Array, ArrayOfTables, DocumentMut, InlineTable, Item, Table, TableLike};

/// `text` with the dotted `key` (`mechanism.dyads[1].q`: tables, `[i]` the i-th entry of an
/// array of tables, or on the way of an inline array of inline tables) set to `value` (a
/// string, number, boolean, array of them, or an object: a table) or removed (`null`); the
/// last name may be new in an existing table; a last `name[i]` replaces or removes entry `i`
/// of an array of tables, or appends one where `i` is its length (`name[0]` creates a missing
/// array). `Err`: why not (the text does not parse, a name or an entry does not exist, the
/// value is not one TOML holds).
pub fn set_key(text: &str, key: &str, value: &Value) -> Result<String, String> {
    let mut doc: DocumentMut = text
        .parse()
        .map_err(|e| format!("the file does not parse: {e}"))?;
    let parts = path(key)?;
    let (last, parents) = parts.split_last().ok_or("an empty key")?;
    let mut table: &mut dyn TableLike = doc.as_table_mut();
    // Whether `table` is a section (`[table]`, an `[[array]]` entry), not an inline table.
    let mut section = true;
    for (name, index) in parents {
        let item = table
            .get_mut(name)
            .ok_or_else(|| format!("{key}: no `{name}` there"))?;
        section = item.is_table() || item.is_array_of_tables();
        table = match index {
            None => item
                .as_table_like_mut()
                .ok_or_else(|| format!("{key}: `{name}` is not a table"))?,
            Some(k) => {
                entry(item, *k).ok_or_else(|| format!("{key}: `{name}` has no entry {k}"))?
            }
        };
    }
    match last {
        (name, None) => set_value(table, section, name, value)?,
        (name, Some(k)) => {
            if *k == 0 && section && value.is_object() && table.get(name).is_none() {
                table.insert(name, Item::ArrayOfTables(ArrayOfTables::new()));
            }
            let item = table
                .get_mut(name)
                .ok_or_else(|| format!("{key}: no `{name}` there"))?;
            set_entry(entries(item, key, name)?, *k, value, key)?
        }
    }
    Ok(doc.to_string())
}

/// Entry `k` of `item`, an array of tables or an inline array of inline tables.
fn entry(item: &mut Item, k: usize) -> Option<&mut dyn TableLike> {
    match item {
        Item::ArrayOfTables(a) => a.get_mut(k).map(|t| t as &mut dyn TableLike),
        Item::Value(toml_edit::Value::Array(a)) => a
            .get_mut(k)
            .and_then(|v| v.as_inline_table_mut())
            .map(|t| t as &mut dyn TableLike),
        _ => None,
    }
}

/// The array of tables `item` (named `name` in `key`), or why not.
fn entries<'a>(item: &'a mut Item, key: &str, name: &str) -> Result<&'a mut ArrayOfTables, String> {
    item.as_array_of_tables_mut()
        .ok_or_else(|| format!("{key}: `{name}` is not an array of tables"))
}

/// `table.name` set to `value` (its old decor kept), or removed (`null`). An object becomes a
/// `[table]` section where it is new or was one in a `section` table, else an inline table.
fn set_value(
    table: &mut dyn TableLike,
    section: bool,
    name: &str,
    value: &Value,
) -> Result<(), String> {
    if value.is_null() {
        table.remove(name);
        return Ok(());
    }
    let old = table.get(name);
    let new = match (value, section && old.is_none_or(Item::is_table)) {
        (Value::Object(_), true) => Item::Table(toml_table(value)?),
        _ => {
            let mut new = toml_value(value)?;
            if let Some(old) = old.and_then(Item::as_value) {
                *new.decor_mut() = old.decor().clone();
            }
            Item::Value(new)
        }
    };
    table.insert(name, new);
    Ok(())
}

/// Entry `k` of `entries` replaced by the object `value`, appended where `k` is the length,
/// or removed (`null`).
fn set_entry(
    entries: &mut ArrayOfTables,
    k: usize,
    value: &Value,
    key: &str,
) -> Result<(), String> {
    let n = entries.len();
    match (value.is_null(), k.cmp(&n)) {
        (true, std::cmp::Ordering::Less) => {
            entries.remove(k);
        }
        (false, std::cmp::Ordering::Less) => {
            let decor = entries.get(k).map(|t| t.decor().clone());
            let mut t = toml_table(value)?;
            if let Some(d) = decor {
                *t.decor_mut() = d;
            }
            *entries.get_mut(k).expect("k < n") = t;
        }
        (false, std::cmp::Ordering::Equal) => entries.push(toml_table(value)?),
        _ => return Err(format!("{key}: there are {n} entries")),
    }
    Ok(())
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

/// A JSON object as a `[table]` section (its objects inline).
fn toml_table(v: &Value) -> Result<Table, String> {
    let Value::Object(o) = v else {
        return Err("allowed: an object (a table)".into());
    };
    let mut t = Table::new();
    for (k, x) in o {
        t.insert(k, Item::Value(toml_value(x)?));
    }
    Ok(t)
}

/// A JSON value as a TOML one (an object as an inline table).
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
        Value::Object(o) => {
            let mut out = InlineTable::new();
            for (k, x) in o {
                out.insert(k, toml_value(x)?);
            }
            out.into()
        }
        Value::Null => return Err("allowed: a string, number, boolean, array or table".into()),
    })
}
