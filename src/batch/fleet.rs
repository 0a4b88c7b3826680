//! Fleets: a template problem file and a CSV whose rows are machines. Each row sets dotted
//! keys of the template (`mechanism.speed`, `design.radius`, …). Units are never guessed: a
//! dimensional cell carries its unit (`35 mm`), or its column header does
//! (`mechanism.speed [rpm]`: a bare number in that column is in rpm); a bare number with
//! neither is an error naming the file, line and column.
//!
//! The template is parsed once; a row sets its cells in a copy of the parsed table and
//! resolves that with [`parse_table`] (the checks of `cwsynth solve`, no TOML printed or
//! re-parsed). A row that fails there is redone the slow way, editing the template text with
//! `toml_edit` and running [`parse_str`], so its message is the one `cwsynth solve` gives,
//! reported as `fleet.csv:LINE: field `x.y`: reason`. Lines are the file's own
//! ([`Lines`]: CRLF, comments and blank lines counted).

use super::error::BatchError;
use super::hash::Hasher;
use crate::families::{parse_str, parse_str_in, parse_table_in, Scene};
use crate::problem::ProblemError;
use crate::report::truncate;
use crate::units::Unit;
use std::path::{Path, PathBuf};

/// A fleet template: its parsed table (the fast way), its document (the slow way, for a
/// bad row's message), name, path, the CSV header, and the input hash of the template text
/// and the header (each row's is finished by [`Template::input_hash`]).
pub struct Template {
    path: PathBuf,
    /// The fleet CSV.
    // pub for the tests in tests/unit_batch.rs
    #[doc(hidden)]
    pub csv: PathBuf,
    table: toml::Table,
    doc: toml_edit::DocumentMut,
    /// The template's `name` (a row without a `name` cell is `<name>-<row>`).
    pub(super) name: String,
    /// The dotted keys of the columns (the header without its units).
    header: Vec<String>,
    /// The unit of each column's bare numbers (`mechanism.speed [rpm]`), if its header
    /// gives one.
    units: Vec<Option<&'static Unit>>,
    hash: Hasher,
    /// The template's folder: a row's drawings (`outline.file`) are read from it, as the
    /// template's are.
    dir: PathBuf,
    /// The drawings a row reads: (the template's `outline.file`, empty where it has none;
    /// the column `….outline.file` that sets it, if any), in the template's key order, then
    /// the `outline` tables only a column names.
    drawings: Vec<(String, Option<usize>)>,
}

/// A column header: its dotted key and, if written `key [unit]`, its unit (an unknown unit
/// is an error).
fn column(h: &str) -> Result<(String, Option<&'static Unit>), String> {
    let h = h.trim();
    let Some((key, rest)) = h.split_once('[') else {
        return Ok((h.to_string(), None));
    };
    let Some(symbol) = rest.trim().strip_suffix(']') else {
        return Err(format!(
            "column `{h}`: a unit is written `key [unit]`, e.g. `mechanism.speed [rpm]`"
        ));
    };
    match crate::units::unit(symbol) {
        Some(u) => Ok((key.trim().to_string(), Some(u))),
        None => Err(format!(
            "column `{h}`: unknown unit `{}`; allowed: {}",
            symbol.trim(),
            crate::units::UNITS
                .iter()
                .map(|u| u.symbol)
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// The TOML value of a CSV cell: integer, float, boolean, else a string (quantities with
/// units stay strings, as in a problem file); a number in a column whose header has a unit
/// is that quantity (`1500` under `mechanism.speed [rpm]` is `"1500 rpm"`).
enum Cell<'a> {
    Int(i64),
    Float(f64),
    Bool(bool),
    Str(&'a str),
    Qty(&'a str, &'static str),
}

impl Cell<'_> {
    /// The value of a cell as written in the CSV, in a column of unit `unit`.
    fn of<'a>(cell: &'a str, unit: Option<&'static Unit>) -> Cell<'a> {
        let c = cell.trim();
        if let Some(u) = unit {
            if c.parse::<f64>().is_ok_and(f64::is_finite) {
                return Cell::Qty(c, u.symbol);
            }
        }
        if let Ok(i) = c.parse::<i64>() {
            return Cell::Int(i);
        }
        if let Ok(x) = c.parse::<f64>() {
            if x.is_finite() {
                return Cell::Float(x);
            }
        }
        match c {
            "true" => Cell::Bool(true),
            "false" => Cell::Bool(false),
            _ => Cell::Str(c),
        }
    }

    /// The cell as a value of `toml` or `toml_edit`.
    fn value<V>(self) -> V
    where
        V: From<i64> + From<f64> + From<bool> + for<'s> From<&'s str>,
    {
        match self {
            Cell::Int(i) => i.into(),
            Cell::Float(x) => x.into(),
            Cell::Bool(b) => b.into(),
            Cell::Str(s) => s.into(),
            Cell::Qty(x, unit) => format!("{x} {unit}").as_str().into(),
        }
    }
}

/// The parts of a dotted key (`mechanism.speed`), each trimmed and not empty.
fn key_parts(key: &str) -> Result<Vec<&str>, String> {
    let parts: Vec<&str> = key.split('.').map(str::trim).collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err("empty key part".into());
    }
    Ok(parts)
}

/// Sets the dotted `key` of `table` to `v`, creating tables as needed; `None` where a part
/// of the key is a value, not a table.
fn set_dotted_table(table: &mut toml::Table, key: &str, v: toml::Value) -> Option<()> {
    let parts = key_parts(key).ok()?;
    let (last, path) = parts.split_last()?;
    let mut t = table;
    for p in path {
        t = t
            .entry(*p)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            .as_table_mut()?;
    }
    t.insert(last.to_string(), v);
    Some(())
}

/// Sets the dotted `key` of `doc` to `v`, creating tables as needed.
fn set_dotted(
    doc: &mut toml_edit::DocumentMut,
    key: &str,
    v: toml_edit::Value,
) -> Result<(), String> {
    let parts = key_parts(key)?;
    let mut t: &mut dyn toml_edit::TableLike = doc.as_table_mut();
    for (k, p) in parts[..parts.len() - 1].iter().enumerate() {
        if t.get(p).is_none() {
            t.insert(p, toml_edit::Item::Table(toml_edit::Table::new()));
        }
        let item = t.get_mut(p).expect("just inserted");
        t = item.as_table_like_mut().ok_or_else(|| {
            format!(
                "`{}` is a value in the template, not a table",
                parts[..=k].join(".")
            )
        })?;
    }
    let last = parts[parts.len() - 1];
    match t.get_mut(last) {
        Some(item) if item.is_value() => {
            // Keep the template's comment and spacing around the value.
            let decor = item.as_value().map(|x| x.decor().clone());
            let mut nv = v;
            if let Some(d) = decor {
                *nv.decor_mut() = d;
            }
            *item = toml_edit::Item::Value(nv);
        }
        _ => {
            t.insert(last, toml_edit::Item::Value(v));
        }
    }
    Ok(())
}

impl Template {
    /// Reads the template and the CSV header.
    pub fn open(template: &Path, csv: &Path) -> Result<Template, BatchError> {
        let bytes = crate::problem::read_bounded(template, crate::problem::MAX_FILE_BYTES)
            .map_err(|cause| BatchError::Unreadable {
                path: template.into(),
                cause,
            })?;
        let text = crate::problem::text_of(&bytes, template)
            .map_err(BatchError::Template)?
            .to_string();
        let not_toml = |why: String| BatchError::NotToml {
            path: template.into(),
            why,
        };
        let doc: toml_edit::DocumentMut = text
            .parse()
            .map_err(|e: toml_edit::TomlError| not_toml(e.to_string()))?;
        // The template itself must be valid (without overrides); a name template
        // (`name = "pump-{speed}"`) is checked with a plain name in its place.
        let named = doc.get("name").and_then(|n| n.as_str()).unwrap_or("");
        if named.contains('{') {
            let mut plain = doc.clone();
            plain["name"] = toml_edit::value("fleet-template");
            parse_str(&plain.to_string(), template).map_err(BatchError::Template)?;
        } else {
            parse_str(&text, template).map_err(BatchError::Template)?;
        }
        let table: toml::Table =
            toml::from_str(&text).map_err(|e: toml::de::Error| not_toml(e.to_string()))?;
        let name = doc
            .get("name")
            .and_then(|n| n.as_str())
            .unwrap_or("machine")
            .to_string();
        let mut rdr = csv_reader(csv)?;
        let columns: Vec<String> = rdr
            .headers()
            .map_err(|cause| BatchError::FleetHeaderUnreadable {
                path: csv.into(),
                cause,
            })?
            .iter()
            .map(|h| h.trim().to_string())
            .collect();
        let (header, units) = columns
            .iter()
            .map(|h| column(h))
            .collect::<Result<(Vec<_>, Vec<_>), String>>()
            .map_err(|why| BatchError::FleetHeader {
                path: csv.into(),
                why,
            })?;
        // A key set by two columns: which cell wins would be a guess.
        let mut seen: std::collections::HashMap<String, usize> = Default::default();
        for (k, key) in header.iter().enumerate() {
            let dotted = canonical(key);
            if let Some(first) = seen.insert(dotted.clone(), k) {
                return Err(BatchError::FleetHeader {
                    path: csv.into(),
                    why: format!(
                        "columns {} (`{}`) and {} (`{}`) both set `{dotted}`; keep one",
                        first + 1,
                        truncate(&columns[first], 200),
                        k + 1,
                        truncate(&columns[k], 200)
                    ),
                });
            }
        }
        // A name template's placeholders must each name a column.
        if name.contains('{') {
            for ph in placeholders(&name) {
                if ph != "row" && column_of(&header, ph).is_none() {
                    return Err(BatchError::FleetHeader {
                        path: csv.into(),
                        why: format!(
                            "the template's name `{}` uses `{{{ph}}}`, which is no column of this fleet; allowed: `{{row}}`, a column's key (`{{mechanism.speed}}`) or its last part (`{{speed}}`)",
                            truncate(&name, 200)
                        ),
                    });
                }
            }
        }
        let mut hash = Hasher::new();
        hash.bytes(b"fleet row\0");
        hash.field(&text);
        hash.field(&columns.len().to_string());
        for h in &columns {
            hash.field(h);
        }
        let drawings = row_drawings(&table, &header);
        Ok(Template {
            path: template.into(),
            csv: csv.into(),
            table,
            doc,
            name,
            header,
            units,
            hash,
            dir: template.parent().unwrap_or(Path::new("")).into(),
            drawings,
        })
    }

    /// The input hash of a row named `name` with these cells: the template text, the CSV
    /// header, the name and the cells (as they are in the CSV), the bytes of every drawing
    /// the row reads (the template's `outline.file`s, each replaced by the row's cell of a
    /// column `….outline.file` that sets it), and the cwsynth build.
    pub fn input_hash(&self, name: &str, cells: &[String]) -> String {
        let mut h = self.hash.clone();
        h.field(name);
        h.field(&cells.len().to_string());
        for c in cells {
            h.field(c);
        }
        for (file, column) in &self.drawings {
            let cell = column
                .and_then(|k| cells.get(k))
                .map(|c| c.trim())
                .filter(|c| !c.is_empty());
            match cell.or(Some(file.as_str()).filter(|f| !f.is_empty())) {
                Some(f) => h.drawing(f, &self.dir),
                None => h.field(""),
            }
        }
        h.hex()
    }

    /// The (dotted key, cell value) pairs a row overrides: every column but `name`, without
    /// the empty cells (which keep the template's value).
    fn overrides<'a>(&'a self, cells: &'a [String]) -> impl Iterator<Item = (&'a str, Cell<'a>)> {
        self.header
            .iter()
            .zip(&self.units)
            .zip(cells)
            .filter(|((h, _), c)| *h != "name" && !c.trim().is_empty())
            .map(|((h, u), c)| (h.as_str(), Cell::of(c, *u)))
    }

    /// The scene of one CSV row (its source `fleet.csv:LINE`), the fast way: the row's
    /// cells set in a copy of the template's table, resolved by [`parse_table`]. `None` for
    /// a row that cannot be read this way; [`Template::scene`] then takes the slow way.
    pub fn fast_scene(&self, name: &str, line: u64, cells: &[String]) -> Option<Scene> {
        if cells.len() != self.header.len() {
            return None;
        }
        let mut table = self.table.clone();
        table.insert("name".into(), name.into());
        for (key, cell) in self.overrides(cells) {
            set_dotted_table(&mut table, key, cell.value())?;
        }
        parse_table_in(table, Path::new(&self.source(line)), &self.dir).ok()
    }

    /// The machine of one CSV row: (name, its scene) or `fleet.csv:LINE: reason`. A good row
    /// takes the fast way ([`Template::fast_scene`]); a bad one is read again as the
    /// template's edited text ([`Template::machine`], [`parse_str`]) for the message of
    /// `cwsynth solve`, with the CSV line and the template line.
    pub fn scene(&self, row: u64, line: u64, cells: &[String]) -> (String, Result<Scene, String>) {
        let name = self.row_name(row, cells);
        match self.fast_scene(&name, line, cells) {
            Some(scene) => (name, Ok(scene)),
            None => self.slow_scene(row, line, cells),
        }
    }

    /// The machine of one CSV row the slow way: the template's text edited
    /// ([`Template::machine`]) and read by [`parse_str`]; an error is phrased for the row.
    pub fn slow_scene(
        &self,
        row: u64,
        line: u64,
        cells: &[String],
    ) -> (String, Result<Scene, String>) {
        let (name, text) = self.machine(row, line, cells);
        let src = self.source(line);
        let scene = text.and_then(|t| {
            parse_str_in(&t, Path::new(&src), &self.dir).map_err(|e| row_error(self, line, e))
        });
        (name, scene)
    }

    /// Where CSV line `line` comes from, `fleet.csv:LINE`: a row's scene source and the
    /// start of its messages.
    pub fn source(&self, line: u64) -> String {
        format!("{}:{line}", self.csv.display())
    }

    /// The name of the machine of CSV row `row` (1-based): its `name` cell, else the
    /// template's name with its placeholders filled ([`Template::fill_name`]), else
    /// `<template name>-<row>`.
    pub fn row_name(&self, row: u64, cells: &[String]) -> String {
        self.header
            .iter()
            .position(|h| h == "name")
            .and_then(|i| cells.get(i))
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| {
                if self.name.contains('{') {
                    self.fill_name(row, cells)
                } else {
                    format!("{}-{}", self.name, row)
                }
            })
    }

    /// Column `k` of a row as the machine got it: the cell, or the template's value where
    /// the cell is empty.
    pub(super) fn effective_cell(&self, k: usize, cells: &[String]) -> String {
        let cell = cells.get(k).map(|c| c.trim()).unwrap_or("");
        if cell.is_empty() {
            dotted_text(&self.table, &self.header[k]).unwrap_or_default()
        } else {
            cell.to_string()
        }
    }

    /// The template's name with each `{column}` replaced by the row's cell (its header unit
    /// appended to a bare number: `{speed}` of `1500` under `mechanism.speed [rpm]` is
    /// `1500rpm`) and `{row}` by the row number; spaces are dropped and any other character
    /// a file name cannot hold becomes `_`. An empty cell gives the template's value's text.
    fn fill_name(&self, row: u64, cells: &[String]) -> String {
        let text: String = template_pieces(&self.name)
            .into_iter()
            .map(|piece| match piece {
                Piece::Text(t) => t.to_string(),
                Piece::Place("row") => row.to_string(),
                Piece::Place(ph) => column_of(&self.header, ph).map_or(String::new(), |k| {
                    let cell = self.effective_cell(k, cells);
                    let own = !cells.get(k).is_none_or(|c| c.trim().is_empty());
                    match self.units[k] {
                        Some(u) if own && cell.parse::<f64>().is_ok() => {
                            format!("{cell}{}", u.symbol)
                        }
                        _ => cell,
                    }
                }),
            })
            .collect();
        text.chars()
            .filter(|c| !c.is_whitespace())
            .map(|c| {
                if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    }

    /// The machine of one CSV row: (name, resolved problem text) or `csv:LINE: reason`.
    pub fn machine(
        &self,
        row: u64,
        line: u64,
        cells: &[String],
    ) -> (String, Result<String, String>) {
        let at = self.source(line);
        let name = self.row_name(row, cells);
        if cells.len() != self.header.len() {
            return (
                name,
                Err(format!(
                    "{at}: {} cells, the header has {}",
                    cells.len(),
                    self.header.len()
                )),
            );
        }
        let mut doc = self.doc.clone();
        if let Err(e) = set_dotted(&mut doc, "name", name.as_str().into()) {
            return (name, Err(format!("{at}: field `name`: {e}")));
        }
        for (h, c) in self.overrides(cells) {
            if let Err(e) = set_dotted(&mut doc, h, c.value()) {
                return (name, Err(format!("{at}: field `{h}`: {e}")));
            }
        }
        (name, Ok(doc.to_string()))
    }
}

/// A dotted key with its parts trimmed (`mechanism . speed` is `mechanism.speed`); a key with
/// an empty part as written.
fn canonical(key: &str) -> String {
    key_parts(key).map_or_else(|_| key.to_string(), |p| p.join("."))
}

/// The drawings a row of the template `table` with these column keys can read (see
/// `Template::drawings`): the template's `outline` tables with their files and the column
/// `….outline.file` that sets each, then each `outline` table only a column names.
fn row_drawings(table: &toml::Table, header: &[String]) -> Vec<(String, Option<usize>)> {
    let columns: Vec<(String, usize)> = header
        .iter()
        .enumerate()
        .filter_map(|(k, h)| {
            let key = canonical(h);
            let outline = key.strip_suffix(".file")?;
            (outline == "outline" || outline.ends_with(".outline")).then(|| (outline.into(), k))
        })
        .collect();
    let column = |outline: &str| columns.iter().find(|(o, _)| o == outline).map(|c| c.1);
    let template = super::hash::drawings(table);
    let mut out: Vec<(String, Option<usize>)> = template
        .iter()
        .map(|(outline, file)| (file.clone(), column(outline)))
        .collect();
    for (outline, k) in &columns {
        if !template.iter().any(|(o, _)| o == outline) {
            out.push((String::new(), Some(*k)));
        }
    }
    out
}

/// A piece of a name template: text as written, or a `{…}` placeholder.
enum Piece<'a> {
    Text(&'a str),
    Place(&'a str),
}

/// A name template in pieces (an unclosed `{` ends the template).
fn template_pieces(name: &str) -> Vec<Piece<'_>> {
    let mut out = Vec::new();
    let mut rest = name;
    while let Some(open) = rest.find('{') {
        out.push(Piece::Text(&rest[..open]));
        let Some(close) = rest[open..].find('}') else {
            return out;
        };
        out.push(Piece::Place(&rest[open + 1..open + close]));
        rest = &rest[open + close + 1..];
    }
    out.push(Piece::Text(rest));
    out
}

/// The `{…}` placeholders of a name template.
fn placeholders(name: &str) -> Vec<&str> {
    template_pieces(name)
        .into_iter()
        .filter_map(|p| match p {
            Piece::Place(ph) => Some(ph),
            Piece::Text(_) => None,
        })
        .collect()
}

/// The column a placeholder names: its dotted key, or the key's last part when only one
/// column ends so.
fn column_of(header: &[String], ph: &str) -> Option<usize> {
    let ph = ph.trim();
    if let Some(k) = header.iter().position(|h| h == ph) {
        return Some(k);
    }
    let ends: Vec<usize> = (0..header.len())
        .filter(|&k| header[k].rsplit('.').next() == Some(ph))
        .collect();
    (ends.len() == 1).then(|| ends[0])
}

/// The template's value at a dotted key as text (a string without its quotes).
fn dotted_text(table: &toml::Table, key: &str) -> Option<String> {
    Some(match crate::problem::edit::dotted_get(table, key)? {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    })
}

/// A reader of the fleet CSV `csv` (flexible rows, `#` comments; see [`FleetFile`]).
// pub for the tests in tests/unit_batch.rs
#[doc(hidden)]
pub fn csv_reader(csv: &Path) -> Result<csv::Reader<FleetFile>, BatchError> {
    let f = std::fs::File::open(csv).map_err(|cause| BatchError::Unreadable {
        path: csv.into(),
        cause,
    })?;
    Ok(csv::ReaderBuilder::new()
        .flexible(true)
        .comment(Some(b'#'))
        .from_reader(std::io::Read::chain(f, &b"\n"[..])))
}

/// A fleet CSV as read: the file, then one line break. The `csv` reader takes a `#` comment
/// on a last line without a line break for a record; with the break it is a comment like any
/// other, and no other line changes (a last line is the same line with its break).
pub(super) type FleetFile = std::io::Chain<std::fs::File, &'static [u8]>;

/// The real line numbers of a fleet CSV's records. The `csv` crate's own line count is off
/// with CRLF line endings, and a record's position is where its reading started, which is
/// before any comment or blank lines the reader skipped: so the line is counted here, from
/// the record's byte position, in a second sequential pass over the file (streamed with the
/// records: every byte is read once more, nothing is kept).
// pub for the tests in tests/unit_batch.rs
#[doc(hidden)]
pub struct Lines {
    rdr: std::io::BufReader<std::fs::File>,
    /// Bytes consumed so far.
    pos: u64,
    /// The (1-based) line of byte `pos`.
    line: u64,
}

impl Lines {
    /// Starts counting the lines of `csv`.
    pub fn open(csv: &Path) -> Result<Lines, BatchError> {
        let f = std::fs::File::open(csv).map_err(|cause| BatchError::Unreadable {
            path: csv.into(),
            cause,
        })?;
        Ok(Lines {
            rdr: std::io::BufReader::new(f),
            pos: 0,
            line: 1,
        })
    }

    /// The line where the record whose reading started at byte `byte` begins: the line of
    /// that byte, past the rest of a line already ended (a CRLF's `\n`), blank lines and
    /// comment lines (`#`), as the CSV reader skips them. Bytes must not decrease from call
    /// to call.
    pub fn record_line(&mut self, byte: u64) -> u64 {
        use std::io::BufRead;
        while self.pos < byte {
            let Ok(buf) = self.rdr.fill_buf() else { break };
            if buf.is_empty() {
                break;
            }
            let n = buf.len().min((byte - self.pos) as usize);
            self.line += buf[..n].iter().filter(|&&b| b == b'\n').count() as u64;
            self.rdr.consume(n);
            self.pos += n as u64;
        }
        // Skip what the reader skipped: line ends, blank lines and comments.
        let mut comment = false;
        while let Some(&b) = self.rdr.fill_buf().ok().and_then(|buf| buf.first()) {
            match b {
                b'\n' => {
                    self.line += 1;
                    comment = false;
                }
                _ if comment => {}
                b'\r' => {}
                b'#' => comment = true,
                _ => break,
            }
            self.rdr.consume(1);
            self.pos += 1;
        }
        self.line
    }
}

/// Lines of the file a CSV record spans beyond its first: a line break can only be inside a
/// record through a quoted cell, which in a fleet is always an unterminated `"` (no cell of
/// a fleet holds a line break). Each such line is a machine the user wrote, so each is
/// reported (rows in = rows out); [`count_machines`] counts them the same way.
pub(super) fn swallowed_lines(r: &csv::StringRecord) -> u64 {
    r.iter()
        // (An unterminated quote on the last line runs to the end of the file and takes its
        // final line break along: that one starts no line.)
        .map(|c| {
            c.trim_end_matches(['\n', '\r'])
                .bytes()
                .filter(|&b| b == b'\n')
                .count() as u64
        })
        .sum()
}

/// Re-formats a problem error of a fleet row as `fleet.csv:LINE: field …` (with the
/// template line where the key is).
fn row_error(tpl: &Template, line: u64, e: ProblemError) -> String {
    match e {
        ProblemError::Invalid {
            line: tl,
            field,
            message,
            ..
        } => {
            // A field set by a column: name the column (1-based, as written in the header).
            let col = field
                .as_ref()
                .and_then(|f| tpl.header.iter().position(|h| h == f))
                .map(|k| format!(" (column {})", k + 1))
                .unwrap_or_default();
            format!(
                "{}: {}{message}{}",
                tpl.source(line),
                field
                    .map(|f| format!("field `{f}`{col}: "))
                    .unwrap_or_default(),
                tl.map(|l| format!(" (template {}:{l})", tpl.path.display()))
                    .unwrap_or_default()
            )
        }
        e => format!("{}: {e}", tpl.source(line)),
    }
}
