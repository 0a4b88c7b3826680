//! Dotted-key edits of a problem file's text (`accuracy.rel_tol = 1e-11`, or a key removed),
//! kept with its comments and layout by `toml_edit`: `cwsynth study` builds every rung of its
//! ladder this way, so a rung goes through the same reading and checks as a file would.

use toml_edit::{DocumentMut, Item, Value};

/// One change of the problem text.
#[derive(Debug, Clone)]
pub enum Edit {
    /// Set `section.key` to a value.
    Set(&'static str, Value),
    /// Remove `section.key` if present.
    Remove(&'static str),
}

/// An integer value.
pub fn v_int(x: i64) -> Value {
    Value::from(x)
}
/// A float value.
pub fn v_f(x: f64) -> Value {
    Value::from(x)
}
/// A string value.
pub fn v_s(x: &str) -> Value {
    Value::from(x)
}

/// The value at a dotted key of a parsed problem file (`mechanism.rod_length`), if any.
pub fn dotted_get<'a>(table: &'a toml::Table, key: &str) -> Option<&'a toml::Value> {
    let mut parts = key.split('.').map(str::trim);
    let mut v = table.get(parts.next()?)?;
    for p in parts {
        v = v.as_table()?.get(p)?;
    }
    Some(v)
}

/// Why edits could not be applied.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EditError {
    /// The text is not TOML (the parser's message).
    #[error("{0}")]
    NotToml(String),
    /// The section of an edited key is a value, not a table.
    #[error("`{0}` is not a table")]
    NotATable(String),
}

/// The problem text with `edits` applied (tables created as needed).
pub fn apply(text: &str, edits: &[Edit]) -> Result<String, EditError> {
    let mut doc: DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| EditError::NotToml(e.to_string()))?;
    for e in edits {
        match e {
            Edit::Set(path, v) => {
                let (sec, key) = path.split_once('.').expect("section.key");
                if doc.get(sec).is_none() {
                    doc.insert(sec, Item::Table(toml_edit::Table::new()));
                }
                let t = doc[sec]
                    .as_table_like_mut()
                    .ok_or_else(|| EditError::NotATable(sec.into()))?;
                t.insert(key, Item::Value(v.clone()));
            }
            Edit::Remove(path) => {
                let (sec, key) = path.split_once('.').expect("section.key");
                if let Some(t) = doc.get_mut(sec).and_then(Item::as_table_like_mut) {
                    t.remove(key);
                }
            }
        }
    }
    Ok(doc.to_string())
}
