//! The Python extension `cwsynth._cwsynth`: thin bindings of the library, so Python gets the
//! CLI's results to the bit. Every entry point calls what `cli.rs` calls
//! (`families::{load, parse_str, solve_scene}`, `SolveResult::to_json`, `batch::run`,
//! `batch::merge`, `families::problem_schema`); results cross as the CLI's JSON text, which
//! the Python side (`cwsynth/__init__.py`) turns into a dict and the CSV tables into NumPy
//! arrays. The GIL is released while Rust solves.

use cwsynth::batch::{self, BatchError as RsBatchError, Counts};
use cwsynth::families::{self, Scene};
use cwsynth::problem::ProblemError as RsProblemError;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::PathBuf;

// Same allocator as the CLI (`src/main.rs`): the batch throughput depends on it.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

create_exception!(
    _cwsynth,
    ProblemError,
    PyValueError,
    "A problem file that cannot be used; attributes `file`, `line`, `field` (None where not \
     known) and `message`."
);
create_exception!(
    _cwsynth,
    BatchError,
    PyRuntimeError,
    "A batch or merge that could not run at all (usage or I/O error, as the CLI's exit status 2)."
);

/// The Python `ProblemError` of a library [`RsProblemError`]: its text (the CLI's line) and
/// its `file`, `line`, `field` and `message`.
fn problem_error(py: Python<'_>, e: &RsProblemError) -> PyErr {
    let err = ProblemError::new_err(e.to_string());
    let v = err.value(py);
    let (file, message) = match e {
        RsProblemError::Read { file, source } => (file, format!("cannot read: {source}")),
        RsProblemError::Invalid { file, message, .. } => (file, message.clone()),
    };
    let set = || -> PyResult<()> {
        v.setattr("file", file.display().to_string())?;
        v.setattr("line", e.line())?;
        v.setattr("field", e.field())?;
        v.setattr("message", message)?;
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(e) => e,
    }
}

fn batch_error(e: RsBatchError) -> PyErr {
    BatchError::new_err(e.to_string())
}

/// Where a problem comes from: a file (read as `cwsynth solve FILE` reads it) or text named
/// `source` (its file name in messages and in the result's `source`).
enum Problem {
    File(PathBuf),
    Text { text: String, source: PathBuf },
}

impl Problem {
    fn of(path: Option<PathBuf>, text: Option<String>, source: Option<PathBuf>) -> PyResult<Self> {
        match (path, text) {
            (Some(p), None) => Ok(Problem::File(p)),
            (None, Some(text)) => Ok(Problem::Text {
                text,
                source: source.unwrap_or_else(|| PathBuf::from("<string>")),
            }),
            _ => Err(PyTypeError::new_err(
                "give exactly one of `path` and `text`",
            )),
        }
    }
    fn load(&self) -> Result<Scene, RsProblemError> {
        match self {
            Problem::File(p) => families::load(p),
            Problem::Text { text, source } => families::parse_str(text, source),
        }
    }
}

/// A solve's JSON text and its tables `(suffix, caption, csv)`.
type Solved = (String, Vec<(String, String, String)>);

/// Solves one problem: `(json, tables)` — the result's JSON text exactly as `cwsynth solve
/// --json` prints it (one line) and its CSV tables `(suffix, caption, csv)`. With `complete`
/// the tables include those only written files carry ([`SolveResult::complete`]; the JSON is
/// taken before, as the CLI's).
#[pyfunction]
#[pyo3(signature = (*, path=None, text=None, source=None, complete=false))]
fn solve(
    py: Python<'_>,
    path: Option<PathBuf>,
    text: Option<String>,
    source: Option<PathBuf>,
    complete: bool,
) -> PyResult<Solved> {
    let problem = Problem::of(path, text, source)?;
    let out = py.allow_threads(|| {
        let scene = problem.load()?;
        // As the CLI: one scene's panic is that call's error, not the interpreter's end.
        Ok(batch::isolate(|| {
            let mut r = families::solve_scene(&scene);
            let json = serde_json::to_string(&r.to_json()).expect("plain data");
            // The tables are the report's, made now: all of them with `complete`, else
            // those of the solution without the analyses only written files carry.
            if complete {
                r.complete();
            } else {
                r.draw();
            }
            let tables = r
                .tables
                .iter()
                .map(|t| (t.suffix.clone(), t.caption.clone(), t.csv.clone()))
                .collect::<Vec<_>>();
            (json, tables)
        }))
    });
    match out {
        Err(e) => Err(problem_error(py, &e)),
        Ok(Err(panic)) => Err(PyRuntimeError::new_err(format!(
            "internal error (a panic, please report it): {panic}"
        ))),
        Ok(Ok(v)) => Ok(v),
    }
}

/// Validates one problem without solving (as `cwsynth check`); raises `ProblemError`.
#[pyfunction]
#[pyo3(signature = (*, path=None, text=None, source=None))]
fn check(
    py: Python<'_>,
    path: Option<PathBuf>,
    text: Option<String>,
    source: Option<PathBuf>,
) -> PyResult<()> {
    let problem = Problem::of(path, text, source)?;
    match py.allow_threads(|| problem.load().map(|_| ())) {
        Ok(()) => Ok(()),
        Err(e) => Err(problem_error(py, &e)),
    }
}

/// The JSON Schema of the problem file, as `cwsynth schema` prints it.
#[pyfunction]
fn schema() -> String {
    serde_json::to_string_pretty(&families::problem_schema()).expect("plain data") + "\n"
}

/// How deep a problem given as a dict may nest (tables and arrays together). A problem file
/// nests 4 levels at most; the limit turns a dict or list that contains itself, or a hostile
/// nesting thousands deep, into a `ValueError` instead of a stack overflow.
const MAX_NESTING: usize = 64;

/// A Python value as a TOML value: dict → table, list/tuple → array, str, bool, int, float.
/// `depth` is the nesting of `v` (0 for the problem's own keys).
fn toml_value(v: &Bound<'_, PyAny>, key: &str, depth: usize) -> PyResult<toml::Value> {
    let bad = |what: &str| PyTypeError::new_err(format!("`{key}`: {what} has no TOML form"));
    if depth > MAX_NESTING {
        return Err(PyValueError::new_err(format!(
            "`{key}`: nested deeper than {MAX_NESTING} levels (a dict or list that contains itself?)"
        )));
    }
    if v.is_instance_of::<PyBool>() {
        Ok(toml::Value::Boolean(v.extract()?))
    } else if v.is_instance_of::<PyInt>() {
        Ok(toml::Value::Integer(
            v.extract().map_err(|_| bad("an integer beyond 64 bits"))?,
        ))
    } else if v.is_instance_of::<PyFloat>() {
        Ok(toml::Value::Float(v.extract()?))
    } else if v.is_instance_of::<PyString>() {
        Ok(toml::Value::String(v.extract()?))
    } else if let Ok(d) = v.downcast::<PyDict>() {
        Ok(toml::Value::Table(toml_table(d, key, depth + 1)?))
    } else if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut a = Vec::new();
        for (i, x) in v.try_iter()?.enumerate() {
            a.push(toml_value(&x?, &format!("{key}[{i}]"), depth + 1)?);
        }
        Ok(toml::Value::Array(a))
    } else {
        Err(bad(&format!("a {}", v.get_type().name()?)))
    }
}

fn toml_table(d: &Bound<'_, PyDict>, prefix: &str, depth: usize) -> PyResult<toml::Table> {
    let mut t = toml::Table::new();
    for (k, v) in d.iter() {
        let k: String = k
            .extract()
            .map_err(|_| PyTypeError::new_err(format!("`{prefix}`: keys must be str")))?;
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        if v.is_none() {
            continue; // None: the key is absent (the file's default applies).
        }
        t.insert(k, toml_value(&v, &path, depth)?);
    }
    Ok(t)
}

/// A problem given as a dict, as TOML text (the toml crate's writer), so it is read exactly
/// as a file: keys whose value is None are left out.
#[pyfunction]
fn dict_to_toml(d: &Bound<'_, PyDict>) -> PyResult<String> {
    toml::to_string(&toml_table(d, "", 0)?)
        .map_err(|e| PyValueError::new_err(format!("not TOML: {e}")))
}

fn counts(py: Python<'_>, c: Counts) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("total", c.total)?;
    d.set_item("ok", c.ok)?;
    d.set_item("failed", c.failed)?;
    d.set_item("skipped", c.skipped)?;
    Ok(d)
}

/// `cwsynth batch INPUTS --out OUT …`: the library's batch run; returns the counts.
#[pyfunction]
#[pyo3(signature = (inputs, out, *, threads=None, shard=None, quiet=true, summary_only=false, units="workshop"))]
#[allow(clippy::too_many_arguments)]
fn run_batch<'py>(
    py: Python<'py>,
    inputs: Vec<String>,
    out: PathBuf,
    threads: Option<usize>,
    shard: Option<String>,
    quiet: bool,
    summary_only: bool,
    units: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let units = match units {
        "workshop" => cwsynth::report::Units::Workshop,
        "si" => cwsynth::report::Units::Si,
        u => {
            return Err(PyValueError::new_err(format!(
                "units `{u}`: allowed \"workshop\", \"si\""
            )))
        }
    };
    if inputs.is_empty() {
        return Err(BatchError::new_err("batch: no inputs"));
    }
    let c = py.allow_threads(|| -> Result<Counts, RsBatchError> {
        let opts = batch::Options {
            out,
            threads,
            shard: shard.as_deref().map(batch::parse_shard).transpose()?,
            quiet,
            summary_only,
            units,
        };
        batch::run(batch::expand(&inputs)?, &opts)
    });
    counts(py, c.map_err(batch_error)?)
}

/// `cwsynth merge DIRS --out OUT`: joins shard summaries; returns the counts.
#[pyfunction]
fn merge(py: Python<'_>, dirs: Vec<PathBuf>, out: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let c = py.allow_threads(|| batch::merge(&dirs, &out));
    counts(py, c.map_err(batch_error)?)
}

/// Writes each fleet's own table `OUT/fleet-<csv stem>.csv` from `OUT/summary.csv`, as an
/// unsharded `cwsynth batch` does at its end (after a merge, say).
#[pyfunction]
fn fleet_tables(py: Python<'_>, inputs: Vec<String>, out: PathBuf) -> PyResult<()> {
    py.allow_threads(|| batch::write_fleet_tables(&out, &batch::expand(&inputs)?))
        .map_err(batch_error)
}

/// The file name of a (shard's) summary: `summary.csv`, `summary-shard-i-of-n.csv`.
#[pyfunction]
#[pyo3(signature = (shard=None))]
fn summary_name(shard: Option<(u64, u64)>) -> String {
    batch::summary_name(shard)
}

#[pymodule]
fn _cwsynth(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ProblemError", py.get_type::<ProblemError>())?;
    m.add("BatchError", py.get_type::<BatchError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(schema, m)?)?;
    m.add_function(wrap_pyfunction!(dict_to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(run_batch, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(summary_name, m)?)?;
    m.add_function(wrap_pyfunction!(fleet_tables, m)?)?;
    Ok(())
}
