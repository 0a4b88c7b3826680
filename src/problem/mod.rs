//! Problem files: reading, the raw serde layer shared by every family, and the errors.
//!
//! A problem file is one machine ("scene") in TOML: `name`, `family`, `description`, then
//! the family's `[mechanism]`, `[model]`, `[design]`, `[objective]`, `[accuracy]` and any
//! `[[paper]]` reference values. Reading is two-pass: a tolerant header pass finds the
//! family, then the family's strict struct (`deny_unknown_fields`) reads the whole file, so
//! an unknown or misspelt key is an error with its line. Values are then checked in the
//! family's resolver, whose errors name the dotted field and get their line from
//! [`SourceMap`]. A table already parsed from TOML (a fleet row) goes through the same
//! passes and checks without its text (`families::parse_table`); its errors have no line.

pub mod calibrate;
pub mod drive;
pub mod edit;
pub mod envelope;
pub mod limits;
pub mod outline;
pub mod schema;
pub mod source;

use self::source::SourceMap;
use crate::units::{self, Dim, Dimension, Qty};
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use std::fmt;
use std::marker::PhantomData;
use std::path::{Path, PathBuf};

/// A value error found after parsing: the dotted field and what is wrong and allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("field `{field}`: {message}")]
pub struct FieldError {
    /// Dotted key, e.g. `mechanism.rod_length`.
    pub field: String,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl FieldError {
    /// Shorthand.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        FieldError {
            field: field.into(),
            message: message.into(),
        }
    }
}

/// A problem file that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    /// The file cannot be read.
    #[error("{}: cannot read: {source}", file.display())]
    Read {
        /// The file.
        file: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is read but wrong: syntax, an unknown or missing field, a bad value.
    #[error("{}{}: {}{message}", file.display(), line.map(|l| format!(":{l}")).unwrap_or_default(), field.as_ref().map(|f| format!("field `{f}`: ")).unwrap_or_default())]
    Invalid {
        /// The file.
        file: PathBuf,
        /// 1-based line, where known.
        line: Option<usize>,
        /// Dotted field, where known.
        field: Option<String>,
        /// What is wrong and what is allowed.
        message: String,
    },
}

impl ProblemError {
    /// The dotted field the error names, if any.
    pub fn field(&self) -> Option<&str> {
        match self {
            ProblemError::Invalid { field, .. } => field.as_deref(),
            ProblemError::Read { .. } => None,
        }
    }
    /// The line, if any.
    pub fn line(&self) -> Option<usize> {
        match self {
            ProblemError::Invalid { line, .. } => *line,
            ProblemError::Read { .. } => None,
        }
    }
}

/// Context for turning parse and value errors into [`ProblemError`]s.
pub struct Ctx<'a> {
    /// The file (for messages).
    pub file: &'a Path,
    /// Its text.
    pub text: &'a str,
    /// Its key index, built on the first error only (a valid file never needs it; a fleet
    /// parses one text per machine).
    map: std::cell::OnceCell<SourceMap>,
    /// Whether there is a text at all (a fleet row's table has none: no lines).
    has_text: bool,
    /// The folder the file's drawings (`outline.file`) are read from, when it is not the
    /// file's own: a fleet row (`fleet.csv:LINE`) reads its template's.
    dir: Option<&'a Path>,
}

impl<'a> Ctx<'a> {
    /// A context for `text` read from `file`.
    pub fn new(file: &'a Path, text: &'a str) -> Self {
        Ctx {
            file,
            text,
            map: std::cell::OnceCell::new(),
            has_text: true,
            dir: None,
        }
    }

    /// The same context with its drawings read from `dir` instead of the file's folder.
    pub fn in_dir(self, dir: &'a Path) -> Self {
        Ctx {
            dir: Some(dir),
            ..self
        }
    }

    /// The folder the file's drawings are read from: the one given by [`Ctx::in_dir`], else
    /// the file's own.
    pub fn dir(&self) -> &Path {
        self.dir
            .unwrap_or_else(|| self.file.parent().unwrap_or(Path::new("")))
    }

    /// A context for a table already parsed (no text, so its errors have no line).
    pub fn of_table(file: &'a Path) -> Self {
        Ctx {
            has_text: false,
            ..Ctx::new(file, "")
        }
    }

    /// The key index of the text.
    pub fn map(&self) -> &SourceMap {
        self.map.get_or_init(|| SourceMap::new(self.text))
    }

    /// Whether the context has a text (a fleet row's table has none: its errors have no
    /// line; an empty file does have one).
    fn has_text(&self) -> bool {
        self.has_text
    }

    /// A value error, located by its field: the field's line, or for a missing field the
    /// line of its nearest present table (line 1 for a top-level key).
    pub fn field_error(&self, e: FieldError) -> ProblemError {
        let line = self.map().line_of(&e.field);
        ProblemError::Invalid {
            file: self.file.into(),
            line: line.or(self.has_text().then_some(1)),
            field: Some(shorten(&e.field, 200)),
            message: e.message,
        }
    }

    /// A serde/TOML error, located by its span. A missing field is named with its table
    /// (`mechanism.rod_length`) at the table's line (a table without text has no spans: its
    /// error keeps serde's words without a field); an unknown key, variant or field gets
    /// "did you mean" when one of the allowed names is close; an error without a span (the
    /// TOML reader's recursion limit) gets the line where the nesting is deepest.
    pub fn toml_error(&self, e: toml::de::Error) -> ProblemError {
        let start = e.span().map(|s| s.start);
        let mut line = start.map(|o| self.map().line_of_offset(o));
        let mut field = start.and_then(|o| self.map().key_at(o)).map(str::to_string);
        let mut message = shorten(&e.message().trim().replace('\n', " "), 1000);
        let missing = quoted_after(&message, "missing field `").filter(|_| self.has_text());
        if let Some(missing) = missing {
            // The span is the table's (or the whole text's): the field goes in that table.
            let at = |o: usize| self.text.get(o..).unwrap_or("");
            let table = match start {
                Some(o) if at(o).starts_with(['[', '{']) => field.take(),
                Some(o) if o > 0 => self.table_at(o),
                _ => None,
            };
            let path = match &table {
                Some(t) => format!("{t}.{missing}"),
                None => missing.to_string(),
            };
            line = table
                .as_deref()
                .and_then(|t| self.map().line_of(t))
                .or(line);
            message = format!("missing field `{missing}`: it is required; allowed: add it");
            field = Some(path);
        } else if let Some(hint) = suggestion(&message) {
            message.push_str(&hint);
        }
        if line.is_none() && self.has_text() {
            line = Some(deepest_line(self.text));
        }
        ProblemError::Invalid {
            file: self.file.into(),
            line,
            field: field.map(|f| shorten(&f, 200)),
            message,
        }
    }

    /// The dotted name of the `[table]` whose header comes last before `offset`.
    fn table_at(&self, offset: usize) -> Option<String> {
        let before = &self.text[..offset.min(self.text.len())];
        before.lines().rev().find_map(|l| {
            let t = l.trim();
            let name = t.strip_prefix("[[").or_else(|| t.strip_prefix('['))?;
            Some(name.split(']').next()?.trim().to_string())
        })
    }

    /// Deserialises the whole text as `T`.
    pub fn parse<T: for<'de> Deserialize<'de>>(&self, text: &str) -> Result<T, ProblemError> {
        toml::from_str(text).map_err(|e| self.toml_error(e))
    }
}

/// `s` cut to at most `max` characters (with `…`): a message never echoes a megabyte.
fn shorten(s: &str, max: usize) -> String {
    match s.char_indices().nth(max) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// The text between `prefix` and the next backtick.
fn quoted_after<'a>(message: &'a str, prefix: &str) -> Option<&'a str> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    rest.split('`').next()
}

/// "; did you mean `x`?" for serde's "unknown field `y`, expected one of `x`, …" (and
/// "unknown variant"), when one of the expected names is close to the one written.
fn suggestion(message: &str) -> Option<String> {
    let word = quoted_after(message, "unknown field `")
        .or_else(|| quoted_after(message, "unknown variant `"))?;
    let expected = &message[message.find("expected")?..];
    let names = expected.split('`').skip(1).step_by(2);
    units::did_you_mean(word, names).map(|n| format!("; did you mean `{n}`?"))
}

/// The 1-based line where brackets and braces nest deepest, or a `[table]` header has the
/// most dots: where the TOML reader's recursion limit was met.
fn deepest_line(text: &str) -> usize {
    let mut depth = 0i64;
    let (mut best, mut at) = (-1i64, 1);
    for (i, line) in text.lines().enumerate() {
        let t = line.trim_start();
        if t.starts_with('[') && !line.contains('=') {
            let dots = t.matches('.').count() as i64;
            if dots > best {
                (best, at) = (dots, i + 1);
            }
            continue;
        }
        for c in line.chars() {
            match c {
                '[' | '{' => depth += 1,
                ']' | '}' => depth -= 1,
                '#' => break,
                _ => {}
            }
            if depth > best {
                (best, at) = (depth, i + 1);
            }
        }
    }
    at
}

/// The largest problem file read (bytes): the shipped ones are a few kB.
pub const MAX_FILE_BYTES: usize = 1 << 20;

/// The largest result file read back (bytes: a result JSON, a file it lists).
pub const MAX_RESULT_BYTES: usize = 256 << 20;

/// The bytes of the regular file at `path`, at most `limit` + 1 of them (one more than the
/// limit, so that the caller can say the file passes it): a FIFO, a device or a directory is
/// refused before a byte is read (`/dev/zero` or a pipe would otherwise never end), and a
/// huge file costs no more memory than the limit. A symlink is followed to what it names.
pub fn read_bounded(path: &std::path::Path, limit: usize) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file (a directory, a FIFO or a device)",
        ));
    }
    let mut bytes = Vec::with_capacity((meta.len() as usize).min(limit + 1));
    std::fs::File::open(path)?
        .take(limit as u64 + 1)
        .read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// The longest `description` and `[[paper]]` text (characters).
pub const MAX_TEXT_CHARS: usize = 10_000;

/// Most `[[paper]]` entries.
pub const MAX_PAPER_ENTRIES: usize = 1000;

/// What a problem file is read from: its text, or a table already parsed from TOML (a
/// fleet row: the template's table with the row's cells set, see `families::parse_table`).
pub enum Input<'a> {
    /// The file's text.
    Text(&'a str),
    /// The file's parsed table.
    Table(toml::Table),
}

impl Input<'_> {
    /// Deserialises the whole input as `T` (a table's errors have no line).
    pub fn parse<T: for<'de> Deserialize<'de>>(self, ctx: &Ctx) -> Result<T, ProblemError> {
        match self {
            Input::Text(text) => ctx.parse(text),
            Input::Table(table) => T::deserialize(table).map_err(|e| ctx.toml_error(e)),
        }
    }
}

/// The first pass: only what every file has, read leniently so that the family can be
/// chosen before its strict struct reads the whole file.
#[derive(Debug, Deserialize)]
pub struct Header {
    /// `name`, if present.
    pub name: Option<String>,
    /// `family`, if present (any TOML value: checked against the registry).
    pub family: Option<toml::Value>,
}

impl Header {
    /// The header of a table: its `name` and `family` entries read as in a text.
    pub fn of_table(ctx: &Ctx, table: &toml::Table) -> Result<Header, ProblemError> {
        let part: toml::Table = ["name", "family"]
            .into_iter()
            .filter_map(|k| Some((k.to_string(), table.get(k)?.clone())))
            .collect();
        Input::Table(part).parse(ctx)
    }
}

/// A whole problem file of one family: the common fields plus the family's sections (its
/// JSON Schema is derived from these structs, [`schema`]).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(
    bound = "M: schemars::JsonSchema, Mo: schemars::JsonSchema + Default, D: schemars::JsonSchema + Default, O: schemars::JsonSchema, A: schemars::JsonSchema + Default"
)]
pub struct RawFile<M, Mo, D, O, A> {
    /// Scene name (also the result file's stem): letters, digits, `-`, `_`, `.`.
    #[schemars(regex(pattern = r"^[A-Za-z0-9_-][A-Za-z0-9._-]{0,127}$"))]
    pub name: String,
    /// Family (already matched against the registry by the header pass).
    pub family: String,
    /// Free text.
    #[serde(default)]
    #[schemars(length(max = MAX_TEXT_CHARS))]
    pub description: String,
    /// Mechanism data.
    pub mechanism: M,
    /// Model fidelity.
    #[serde(default)]
    pub model: Mo,
    /// Design variables.
    #[serde(default)]
    pub design: D,
    /// Objective and constraints.
    pub objective: O,
    /// Accuracy targets.
    #[serde(default)]
    pub accuracy: A,
    /// Printed values of the source paper to compare with.
    #[serde(default)]
    #[schemars(length(max = MAX_PAPER_ENTRIES))]
    pub paper: Vec<PaperRaw>,
    /// Unknown data to fit to measured or printed values (`cwsynth calibrate`; `solve` and
    /// `batch` use the file's own values).
    #[serde(default)]
    pub calibrate: Option<calibrate::CalibrateRaw>,
}

impl<M, Mo, D, O, A> RawFile<M, Mo, D, O, A>
where
    Self: for<'de> Deserialize<'de>,
{
    /// Reads `input` as this family's file and checks its values with `resolve_raw` (a
    /// [`FieldError`] is located by its field): the family's resolved part with the parts
    /// every file has.
    pub fn resolve<K>(
        ctx: &Ctx,
        input: Input,
        resolve_raw: impl FnOnce(&Self) -> Result<K, FieldError>,
    ) -> Result<Resolved<K>, ProblemError> {
        let raw: Self = input.parse(ctx)?;
        check_texts(&raw.description, &raw.paper).map_err(|e| ctx.field_error(e))?;
        let part = resolve_raw(&raw).map_err(|e| ctx.field_error(e))?;
        let paper = resolve_paper(&raw.paper).map_err(|e| ctx.field_error(e))?;
        if let Some(c) = &raw.calibrate {
            calibrate::resolve_calibration(c).map_err(|e| ctx.field_error(e))?;
        }
        Ok(Resolved {
            name: raw.name,
            description: raw.description,
            source: ctx.file.into(),
            paper,
            part,
        })
    }
}

/// A problem file read and checked: the parts every file has, and the family's own part.
#[derive(Debug, Clone)]
pub struct Resolved<K> {
    /// Name.
    pub name: String,
    /// Description.
    pub description: String,
    /// The file it came from.
    pub source: PathBuf,
    /// Paper reference values.
    pub paper: Vec<PaperRef>,
    /// The family's resolved part.
    pub part: K,
}

/// The input-size limits of the common keys: `description` and every `[[paper]]` text at
/// most [`MAX_TEXT_CHARS`] characters, at most [`MAX_PAPER_ENTRIES`] entries.
fn check_texts(description: &str, paper: &[PaperRaw]) -> Result<(), FieldError> {
    let long = |field: String, t: &str| {
        let n = t.chars().count();
        if n > MAX_TEXT_CHARS {
            Err(FieldError::new(
                field,
                format!("{n} characters; allowed: at most {MAX_TEXT_CHARS}"),
            ))
        } else {
            Ok(())
        }
    };
    long("description".into(), description)?;
    if paper.len() > MAX_PAPER_ENTRIES {
        return Err(FieldError::new(
            format!("paper[{MAX_PAPER_ENTRIES}]"),
            format!(
                "{} [[paper]] entries; allowed: at most {MAX_PAPER_ENTRIES}",
                paper.len()
            ),
        ));
    }
    for (i, p) in paper.iter().enumerate() {
        long(format!("paper[{i}].quantity"), &p.quantity)?;
        long(format!("paper[{i}].key"), &p.key)?;
        long(format!("paper[{i}].note"), &p.note)?;
    }
    Ok(())
}

/// A value printed in the source paper, compared with a key of the result.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PaperRaw {
    /// What the paper's number is.
    #[schemars(length(max = MAX_TEXT_CHARS))]
    pub quantity: String,
    /// The number with a unit (`"900 N"`), of the dimension of the key's unit suffix; a
    /// plain number only for a key without one (`_pct`, a ratio).
    pub value: PaperValue,
    /// Dotted key of the result to compare with (`baselines.none.peak_shaking_force_n`).
    #[schemars(length(max = MAX_TEXT_CHARS))]
    pub key: String,
    /// How to read the comparison.
    #[serde(default)]
    #[schemars(length(max = MAX_TEXT_CHARS))]
    pub note: String,
}

/// A paper value: a quantity string of any dimension (SI value and the dimension of its
/// unit), or a plain number (a pure number, [`Dim::Dimensionless`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperValue(pub f64, pub Dim);

/// The dimension of a result key, read from its SI unit suffix (`peak_force_n`: force,
/// `delta_h_m`: length); a key without one (`_pct`, `_rpm`, a ratio) is a pure number.
pub fn key_dim(key: &str) -> Dim {
    let last = key.rsplit('.').next().unwrap_or(key);
    [
        ("_rad_s", Dim::AngularSpeed),
        ("_m_s2", Dim::Acceleration),
        ("_kg_m3", Dim::Density),
        ("_n_per_m", Dim::Stiffness),
        ("_ns_per_m", Dim::Damping),
        ("_kgm2", Dim::Inertia),
        ("_kgm", Dim::Unbalance),
        ("_nm", Dim::Torque),
        ("_n", Dim::Force),
        ("_kg", Dim::Mass),
        ("_m", Dim::Length),
        ("_rad", Dim::Angle),
        ("_s", Dim::Time),
        ("_pa", Dim::Pressure),
    ]
    .into_iter()
    .find(|(suffix, _)| last.ends_with(suffix))
    .map_or(Dim::Dimensionless, |(_, d)| d)
}

impl<'de> Deserialize<'de> for PaperValue {
    fn deserialize<De: Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = PaperValue;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a quantity string such as \"900 N\" (a plain number for a pure number)",
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<PaperValue, E> {
                if v.is_finite() {
                    Ok(PaperValue(v, Dim::Dimensionless))
                } else {
                    Err(E::custom("not a finite number"))
                }
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<PaperValue, E> {
                self.visit_f64(v as f64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<PaperValue, E> {
                self.visit_f64(v as f64)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<PaperValue, E> {
                units::parse_any(v)
                    .map(|(x, d)| PaperValue(x, d))
                    .map_err(E::custom)
            }
        }
        d.deserialize_any(V)
    }
}

/// A paper reference, resolved.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PaperRef {
    /// What the paper's number is.
    pub quantity: String,
    /// The paper's value in SI.
    pub value: f64,
    /// The result key compared with.
    pub key: String,
    /// How to read the comparison.
    pub note: String,
}

/// A design variable in a file: a quantity (fixed) or `{ min = …, max = … }` (free).
#[derive(Debug, PartialEq)]
pub enum RawVar<D> {
    /// Fixed.
    Fixed(Qty<D>),
    /// Free within bounds.
    Free {
        /// Lower bound.
        min: Qty<D>,
        /// Upper bound.
        max: Qty<D>,
    },
}

impl<D> Clone for RawVar<D> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<D> Copy for RawVar<D> {}

impl<D> RawVar<D> {
    /// Checks min ≤ max and converts; `field` names the variable in errors.
    pub fn resolve(&self, field: &str) -> Result<crate::synth::Var, FieldError> {
        use crate::synth::Var;
        match *self {
            RawVar::Fixed(q) => Ok(Var::Fixed(q.si())),
            RawVar::Free { min, max } if min.si() <= max.si() => Ok(Var::Free {
                min: min.si(),
                max: max.si(),
            }),
            RawVar::Free { min, max } => Err(FieldError::new(
                field,
                format!(
                    "min = {} is above max = {} (SI); allowed: min ≤ max",
                    min.si(),
                    max.si()
                ),
            )),
        }
    }
}

impl<'de, D: Dimension> Deserialize<'de> for RawVar<D> {
    fn deserialize<De: Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        struct V<D>(PhantomData<D>);
        impl<'de, D: Dimension> Visitor<'de> for V<D> {
            type Value = RawVar<D>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(
                    f,
                    "a fixed {} ({}) or a free range {{ min = …, max = … }}",
                    D::DIM.name(),
                    D::DIM.allowed()
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
                Qty::<D>::deserialize(de::value::F64Deserializer::new(v)).map(RawVar::Fixed)
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
                self.visit_f64(v as f64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
                self.visit_f64(v as f64)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                units::parse(v, D::DIM)
                    .map(|x| RawVar::Fixed(Qty::new(x)))
                    .map_err(E::custom)
            }
            fn visit_map<M: MapAccess<'de>>(self, mut m: M) -> Result<Self::Value, M::Error> {
                let (mut min, mut max) = (None, None);
                while let Some(k) = m.next_key::<String>()? {
                    match k.as_str() {
                        "min" => min = Some(m.next_value::<Qty<D>>()?),
                        "max" => max = Some(m.next_value::<Qty<D>>()?),
                        other => return Err(de::Error::unknown_field(other, &["min", "max"])),
                    }
                }
                match (min, max) {
                    (Some(min), Some(max)) => Ok(RawVar::Free { min, max }),
                    (None, _) => Err(de::Error::missing_field("min")),
                    (_, None) => Err(de::Error::missing_field("max")),
                }
            }
        }
        d.deserialize_any(V(PhantomData))
    }
}

/// The text of a problem file's bytes: within [`MAX_FILE_BYTES`], and UTF-8 — bytes that are
/// not are an error at the line and column of the first bad byte.
pub fn text_of<'a>(bytes: &'a [u8], path: &Path) -> Result<&'a str, ProblemError> {
    check_size(bytes, path)?;
    std::str::from_utf8(bytes).map_err(|e| {
        let at = e.valid_up_to();
        let line_start = bytes[..at].iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        ProblemError::Invalid {
            file: path.into(),
            line: Some(bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1),
            field: None,
            message: format!(
                "not UTF-8 text: byte 0x{:02x} at column {} (byte {at}); allowed: a UTF-8 text file",
                bytes[at],
                String::from_utf8_lossy(&bytes[line_start..at]).chars().count() + 1
            ),
        }
    })
}

/// A file over [`MAX_FILE_BYTES`]: an error at the line where it passes the limit.
pub fn check_size(bytes: &[u8], path: &Path) -> Result<(), ProblemError> {
    if bytes.len() <= MAX_FILE_BYTES {
        return Ok(());
    }
    Err(ProblemError::Invalid {
        file: path.into(),
        line: Some(bytes[..MAX_FILE_BYTES].iter().filter(|&&b| b == b'\n').count() + 1),
        field: None,
        message: format!(
            "the file is {} bytes and passes the limit on this line; allowed: at most {MAX_FILE_BYTES} bytes",
            bytes.len()
        ),
    })
}

/// Names a machine cannot have, compared without case: the batch's own files
/// (`summary.csv`, `summary.md`, `index.html`, `summary-shard-*`) and the device names that
/// Windows reserves with any extension (`CON`, `nul.txt`, `COM1`, …).
pub const RESERVED_NAMES: [&str; 24] = [
    "summary", "index", "con", "prn", "aux", "nul", "com1", "com2", "com3", "com4", "com5", "com6",
    "com7", "com8", "com9", "lpt1", "lpt2", "lpt3", "lpt4", "lpt5", "lpt6", "lpt7", "lpt8", "lpt9",
];

/// Checks a scene name (it becomes a file name, the same on every file system): 1–128 ASCII
/// letters, digits, `-`, `_`, `.`, not starting or ending with `.`, not a reserved name
/// ([`RESERVED_NAMES`], before any extension, without case) nor a shard summary's name.
/// Names that differ only in case clash on case-insensitive file systems: `solve --out` and
/// `batch` compare them without case.
pub fn check_name(name: &str) -> Result<(), FieldError> {
    let charset = !name.is_empty()
        && name.len() <= 128
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
        && !name.starts_with('.')
        && !name.ends_with('.');
    if !charset {
        let shown: String = name.chars().take(64).collect();
        return Err(FieldError::new(
            "name",
            format!("`{}` cannot be a file name; allowed: 1–128 ASCII letters, digits, `-`, `_`, `.`, not starting or ending with `.`", shown.escape_debug()),
        ));
    }
    let stem = name.split('.').next().unwrap_or("").to_ascii_lowercase();
    if RESERVED_NAMES.contains(&stem.as_str()) || stem.starts_with("summary-shard-") {
        return Err(FieldError::new(
            "name",
            format!("`{name}` is reserved (the batch's own files `summary`, `index`, `summary-shard-*`, or a Windows device name such as `CON`, `NUL`, `COM1`); choose another name"),
        ));
    }
    Ok(())
}

/// Resolves the `[[paper]]` entries: each value's unit must be of the dimension of its
/// key's SI suffix ([`key_dim`]); a plain number only for a key that is a pure number.
pub fn resolve_paper(raw: &[PaperRaw]) -> Result<Vec<PaperRef>, FieldError> {
    raw.iter()
        .enumerate()
        .map(|(i, p)| {
            let PaperValue(value, dim) = p.value;
            let want = key_dim(&p.key);
            if dim != want {
                let field = format!("paper[{i}].value");
                let found = match dim {
                    Dim::Dimensionless => "a plain number (no unit)".to_string(),
                    d => format!("a {}", d.name()),
                };
                let allowed = match want {
                    Dim::Dimensionless => format!(
                        "a plain number in the unit of `{}` (its name has no SI unit suffix)",
                        p.key
                    ),
                    d => d.allowed(),
                };
                return Err(FieldError::new(
                    field,
                    format!(
                        "{found}, but the key `{}` is a {}; allowed: {allowed}",
                        p.key,
                        want.name()
                    ),
                ));
            }
            Ok(PaperRef {
                quantity: p.quantity.clone(),
                value,
                key: p.key.clone(),
                note: p.note.clone(),
            })
        })
        .collect()
}

/// Exactly two values `[a, b]` (a point, a range) in a problem file. serde's fixed-size
/// arrays read the first two elements of a longer array and drop the rest without a word;
/// this refuses any other length, so `[x, y, z]` for a planar point is an error at its field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair<T>(pub [T; 2]);

impl Pair<Qty<units::Length>> {
    /// The point (x, y) in metres.
    pub fn si(&self) -> crate::geom::P2 {
        crate::geom::P2::new(self.0[0].si(), self.0[1].si())
    }
}

impl<T> std::ops::Deref for Pair<T> {
    type Target = [T; 2];
    fn deref(&self) -> &[T; 2] {
        &self.0
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Pair<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<T>::deserialize(d)?;
        let n = v.len();
        <[T; 2]>::try_from(v)
            .map(Pair)
            .map_err(|_| de::Error::invalid_length(n, &"exactly 2 values, [a, b]"))
    }
}

impl<T: schemars::JsonSchema> schemars::JsonSchema for Pair<T> {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        <[T; 2]>::schema_name()
    }
    fn json_schema(g: &mut schemars::SchemaGenerator) -> schemars::Schema {
        <[T; 2]>::json_schema(g)
    }
    fn inline_schema() -> bool {
        <[T; 2]>::inline_schema()
    }
}

/// Checks that a value is finite and positive.
pub fn positive(field: &str, v: f64) -> Result<f64, FieldError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(FieldError::new(
            field,
            format!("must be positive, got {v}; allowed: a value > 0"),
        ))
    }
}

/// Checks that a value is finite and not negative.
pub fn non_negative(field: &str, v: f64) -> Result<f64, FieldError> {
    if v >= 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(FieldError::new(
            field,
            format!("must not be negative, got {v}; allowed: a value ≥ 0"),
        ))
    }
}
