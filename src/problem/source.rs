//! Where each key of a problem file stands, so that an error found after parsing (a
//! negative length, λ ≥ 1) can still name the line.
//!
//! serde reports its own errors with a line and column; semantic checks run on the
//! resolved values and only know the dotted key (`mechanism.rod_length`). This index maps
//! dotted keys to lines, and a byte offset back to the innermost key that contains it.

use std::ops::Range;
use toml_edit::{Document, Item, Table, Value};

/// Dotted keys with their byte spans (key start to value end) and lines.
#[derive(Debug, Clone, Default)]
pub struct SourceMap {
    entries: Vec<(String, Range<usize>)>,
    line_starts: Vec<usize>,
}

impl SourceMap {
    /// Indexes a TOML text; an unparsable text gives an empty map (serde reports the syntax
    /// error itself).
    pub fn new(text: &str) -> Self {
        let mut map = SourceMap {
            entries: Vec::new(),
            line_starts: std::iter::once(0)
                .chain(text.match_indices('\n').map(|(i, _)| i + 1))
                .collect(),
        };
        match Document::parse(text) {
            Ok(doc) => map.walk_table(doc.as_table(), ""),
            // serde read it, but toml_edit does not (an integer above i64::MAX): index the
            // plain `key = value` lines under their `[table]` headers.
            Err(_) => map.walk_lines(text),
        }
        map
    }

    /// A line-by-line index of `[table]`, `[[array]]` and `key = value` lines, for a text
    /// that toml_edit cannot parse (inline tables and multi-line values are not entered).
    fn walk_lines(&mut self, text: &str) {
        let mut prefix = String::new();
        let mut arrays: Vec<(String, usize)> = Vec::new();
        let mut start = 0;
        for line in text.split_inclusive('\n') {
            let span = start..start + line.trim_end().len();
            start += line.len();
            let t = line.trim();
            if let Some(name) = t.strip_prefix("[[").and_then(|r| r.split_once("]]")) {
                let name = name.0.trim().to_string();
                let k = match arrays.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, k)) => {
                        *k += 1;
                        *k
                    }
                    None => {
                        arrays.push((name.clone(), 0));
                        0
                    }
                };
                prefix = format!("{name}[{k}]");
                self.entries.push((prefix.clone(), span));
            } else if let Some(name) = t.strip_prefix('[').and_then(|r| r.split_once(']')) {
                prefix = name.0.trim().to_string();
                self.entries.push((prefix.clone(), span));
            } else if let Some((key, _)) = t.split_once('=').filter(|_| !t.starts_with('#')) {
                let key = key.trim().trim_matches('"');
                let path = match prefix.as_str() {
                    "" => key.to_string(),
                    p => format!("{p}.{key}"),
                };
                self.entries.push((path, span));
            }
        }
    }

    fn push(
        &mut self,
        path: String,
        key_span: Option<Range<usize>>,
        val_span: Option<Range<usize>>,
    ) {
        let span = match (key_span, val_span) {
            (Some(k), Some(v)) => k.start.min(v.start)..k.end.max(v.end),
            (Some(k), None) => k,
            (None, Some(v)) => v,
            (None, None) => return,
        };
        self.entries.push((path, span));
    }

    fn walk_table(&mut self, t: &Table, prefix: &str) {
        for (k, item) in t.iter() {
            let path = if prefix.is_empty() {
                k.to_string()
            } else {
                format!("{prefix}.{k}")
            };
            let key_span = t.key(k).and_then(|k| k.span());
            match item {
                Item::Table(sub) => {
                    self.push(path.clone(), key_span.or(sub.span()), sub.span());
                    self.walk_table(sub, &path);
                }
                Item::ArrayOfTables(arr) => {
                    for (i, sub) in arr.iter().enumerate() {
                        let p = format!("{path}[{i}]");
                        self.push(p.clone(), sub.span(), None);
                        self.walk_table(sub, &p);
                    }
                }
                Item::Value(v) => {
                    self.push(path.clone(), key_span, v.span());
                    self.walk_value(v, &path);
                }
                Item::None => {}
            }
        }
    }

    fn walk_value(&mut self, v: &Value, path: &str) {
        if let Value::InlineTable(t) = v {
            for (k, val) in t.iter() {
                let p = format!("{path}.{k}");
                self.push(p.clone(), t.key(k).and_then(|k| k.span()), val.span());
                self.walk_value(val, &p);
            }
        }
    }

    /// Line (1-based) of a byte offset.
    pub fn line_of_offset(&self, offset: usize) -> usize {
        self.line_starts.partition_point(|&s| s <= offset).max(1)
    }

    /// Line of a dotted key; for a key that is absent, the line of its nearest present
    /// parent (where a missing field should go).
    pub fn line_of(&self, path: &str) -> Option<usize> {
        let mut p = path;
        loop {
            if let Some((_, span)) = self.entries.iter().find(|(k, _)| k == p) {
                return Some(self.line_of_offset(span.start));
            }
            p = &p[..p.rfind('.')?];
        }
    }

    /// Every dotted key (tables, `[[array]]` entries, values and inline tables' keys) with
    /// its line, in the file's order.
    pub fn lines(&self) -> impl Iterator<Item = (&str, usize)> + '_ {
        self.entries
            .iter()
            .map(|(k, span)| (k.as_str(), self.line_of_offset(span.start)))
    }

    /// The innermost dotted key whose span contains `offset`.
    pub fn key_at(&self, offset: usize) -> Option<&str> {
        self.entries
            .iter()
            .filter(|(_, s)| s.start <= offset && offset < s.end.max(s.start + 1))
            .min_by_key(|(_, s)| s.end - s.start)
            .map(|(k, _)| k.as_str())
    }
}
