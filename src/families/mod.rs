//! One home per mechanism family, and the seam every engine above talks through.
//!
//! Each folder holds one family whole: `model` (pure physics), `file` (its problem file: raw
//! serde layer and resolution), `synth` (design vector, objectives, solves), `report` (its
//! result, tables and plots) and `study` (its ladder of settings and the effects its model
//! leaves out). A family is a [`Family`] (what reads its files) whose resolved scenes are
//! [`Machine`]s (what solves and studies them); [`FAMILIES`] lists them, one line each.
//! Nothing above this module — `batch`, `study`, `cli` — names a family.

pub mod crane;
pub mod gear;
pub mod hypocycloid;
pub mod linkage;
pub mod multi_cylinder;
pub mod slider_crank;

pub mod driver;
pub mod family;

pub use driver::{drive, Claim, Solve};

pub use family::{machine, relative, Effect, Family, Ladder, Machine, Rung, Scene};

use crate::problem::{check_size, text_of, Ctx, FieldError, Header, Input, ProblemError};
use crate::report::{SolveResult, Status};
use serde::Deserialize;
use std::path::Path;
use std::time::Instant;

/// The registry: every family, one line each. Adding a family is one folder and one line.
pub static FAMILIES: [&dyn Family; 6] = [
    &slider_crank::SliderCrank,
    &crane::LuffingCrane,
    &hypocycloid::HypocycloidFamily,
    &gear::EccentricGear,
    &linkage::LinkageFamily,
    &multi_cylinder::MultiCylinder,
];

/// Families added at run time by a program or test that links cwsynth as a library
/// ([`register`]), after the shipped [`FAMILIES`].
static REGISTERED: std::sync::RwLock<Vec<&'static dyn Family>> = std::sync::RwLock::new(Vec::new());

/// Adds a family defined outside this crate to the registry: its files then load, solve,
/// batch and study as the shipped families' do (the JSON Schema and the CLI's lists stay the
/// shipped families'). Registering the same family again is a no-op; another family under a
/// name already taken is refused.
pub fn register(family: &'static dyn Family) -> Result<(), String> {
    let mut reg = REGISTERED.write().unwrap_or_else(|e| e.into_inner());
    match all_in(&reg).into_iter().find(|f| f.name() == family.name()) {
        Some(f) if same_type(f, family) => Ok(()),
        Some(_) => Err(format!(
            "a family named `{}` is already registered",
            family.name()
        )),
        None => {
            reg.push(family);
            Ok(())
        }
    }
}

/// Are `a` and `b` the same family type (a unit struct has no address of its own to compare)?
fn same_type(a: &'static dyn Family, b: &'static dyn Family) -> bool {
    let (a, b): (&dyn std::any::Any, &dyn std::any::Any) = (a, b);
    a.type_id() == b.type_id()
}

/// Every family: the shipped ones, then the registered ones.
pub fn all() -> Vec<&'static dyn Family> {
    all_in(&REGISTERED.read().unwrap_or_else(|e| e.into_inner()))
}

fn all_in(registered: &[&'static dyn Family]) -> Vec<&'static dyn Family> {
    FAMILIES.iter().chain(registered).copied().collect()
}

/// The family named `name` in a file or result.
pub fn by_name(name: &str) -> Option<&'static dyn Family> {
    FAMILIES
        .iter()
        .copied()
        .find(|f| f.name() == name)
        .or_else(|| {
            let reg = REGISTERED.read().unwrap_or_else(|e| e.into_inner());
            reg.iter().copied().find(|f| f.name() == name)
        })
}

/// A commented problem file of `family` to start from (`cwsynth new <family>`): the
/// family's template ([`Family::template`]: `templates/<family>.toml` for the slider-crank
/// and the linkage, a shipped scene for the others — a machine with no paper's numbers to
/// check whose solve gives a buildable design) under a header that says where every key is
/// documented, named `my-<family>`. `None` for an unknown family.
pub fn new_problem(family: &str) -> Option<String> {
    let f = by_name(family)?;
    let mut out = format!(
        "# A cwsynth problem file for the `{family}` family, to start from (`cwsynth new {family}`).\n\
         # Edit the machine's data below, then `cwsynth check FILE` and\n\
         # `cwsynth solve FILE --out DIR`. Every key, its unit and its range:\n\
         # docs/problem-files.md (family `{family}`); `cwsynth schema` prints the JSON Schema.\n\
         # Dimensional values need a unit (\"35 mm\", \"1500 rpm\"): a bare number is an error.\n\
         #\n"
    );
    let mut renamed = false;
    for line in f.template().lines() {
        if !renamed && line.trim_start().starts_with("name =") {
            out += &format!("name = \"my-{family}\"\n");
            renamed = true;
        } else {
            out += line;
            out.push('\n');
        }
    }
    Some(out)
}

/// Reads and resolves a problem file.
pub fn load(path: &Path) -> Result<Scene, ProblemError> {
    let bytes =
        crate::problem::read_bounded(path, crate::problem::MAX_FILE_BYTES).map_err(|source| {
            ProblemError::Read {
                file: path.into(),
                source,
            }
        })?;
    parse_bytes(&bytes, path)
}

/// Resolves the bytes of a problem file (what [`load`] reads); `path` is used for messages
/// and as the scene's source.
///
/// Bytes that are not UTF-8 are an error at the line of the first bad byte.
pub fn parse_bytes(bytes: &[u8], path: &Path) -> Result<Scene, ProblemError> {
    parse_str(text_of(bytes, path)?, path)
}

/// Resolves problem-file text; `path` is used for messages and as the scene's source, and
/// its folder is where the file's drawings (`outline.file`) are read from.
pub fn parse_str(text: &str, path: &Path) -> Result<Scene, ProblemError> {
    parse_text(Ctx::new(path, text))
}

/// [`parse_str`] with the drawings read from `dir`: a fleet row (`path` is `fleet.csv:LINE`)
/// reads the drawings its template names from the template's folder.
pub fn parse_str_in(text: &str, path: &Path, dir: &Path) -> Result<Scene, ProblemError> {
    parse_text(Ctx::new(path, text).in_dir(dir))
}

/// Resolves the text of `ctx`.
fn parse_text(ctx: Ctx) -> Result<Scene, ProblemError> {
    check_size(ctx.text.as_bytes(), ctx.file)?;
    let header: Header = ctx.parse(ctx.text)?;
    resolve(&ctx, header, Input::Text(ctx.text))
}

/// Resolves a problem file already parsed into a table, with the same checks as
/// [`parse_str`] (which gives the same scene for the table's text); `path` is used for
/// messages and as the scene's source. Its errors have no line: a caller that needs one reads
/// the text with [`parse_str`]. A fleet row takes this way and never prints TOML.
pub fn parse_table(table: toml::Table, path: &Path) -> Result<Scene, ProblemError> {
    parse_table_of(Ctx::of_table(path), table)
}

/// [`parse_table`] with the drawings read from `dir` (a fleet row's: its template's folder).
pub fn parse_table_in(table: toml::Table, path: &Path, dir: &Path) -> Result<Scene, ProblemError> {
    parse_table_of(Ctx::of_table(path).in_dir(dir), table)
}

/// Resolves `table` in the context `ctx`.
fn parse_table_of(ctx: Ctx, table: toml::Table) -> Result<Scene, ProblemError> {
    let header = Header::of_table(&ctx, &table)?;
    resolve(&ctx, header, Input::Table(table))
}

/// The allowed `family` values, for messages.
fn allowed() -> String {
    let names: Vec<String> = all().iter().map(|f| format!("\"{}\"", f.name())).collect();
    format!("allowed: {}", names.join(", "))
}

/// Checks the header and resolves `input` as a file of its family.
fn resolve(ctx: &Ctx, header: Header, input: Input) -> Result<Scene, ProblemError> {
    let Some(value) = header.family else {
        return Err(ctx.field_error(FieldError::new("family", format!("missing; {}", allowed()))));
    };
    let family = String::deserialize(value.clone())
        .ok()
        .and_then(|n| by_name(&n))
        .ok_or_else(|| {
            let hint = value
                .as_str()
                .and_then(|v| crate::units::did_you_mean(v, all().iter().map(|f| f.name())))
                .map(|n| format!("; did you mean `{n}`?"))
                .unwrap_or_default();
            ctx.field_error(FieldError::new(
                "family",
                format!("unknown family {value}{hint}; {}", allowed()),
            ))
        })?;
    if header.name.is_none() {
        return Err(ctx.field_error(FieldError::new(
            "name",
            "missing; a scene needs a name (letters, digits, -, _, .)",
        )));
    }
    let r = family.resolve(ctx, input)?;
    Ok(Scene {
        name: r.name,
        family,
        description: r.description,
        source: r.source,
        paper: r.paper,
        machine: r.part,
    })
}

/// The JSON Schema of a problem file, every family.
pub fn problem_schema() -> serde_json::Value {
    crate::problem::schema::assemble(
        FAMILIES
            .iter()
            .map(|f| (f.name(), f.schema(), f.counts()))
            .collect(),
    )
}

/// Solves a scene. Never panics on a valid scene; a solver failure becomes
/// `status = failed` with the reason in `warnings`. The paper comparison and the total
/// timing are added here, and no figure that is not finite is reported.
pub fn solve_scene(scene: &Scene) -> SolveResult {
    let t0 = Instant::now();
    let mut r = scene.machine.solve(scene);
    if r.objective.is_none() {
        // The key objective of the result is the family's headline (declared once, in its
        // `Machine::headline`) when that is an objective.
        let headline = scene.machine.headline();
        r.objective = headline.strip_prefix("objectives.").map(str::to_string);
    }
    r.timing.total_s = t0.elapsed().as_secs_f64();
    r.compare_with_paper(&scene.paper);
    reject_non_finite(&mut r);
    r
}

/// No result carries inf or NaN in its number maps: a figure that is not finite (a derived
/// quantity blown up by an absurd input) is removed, and the result becomes `failed` with a
/// `status_detail` naming the figures; the inputs' own checks should have stopped it first.
fn reject_non_finite(r: &mut SolveResult) {
    let mut bad = Vec::new();
    let mut sweep = |section: String, m: &mut std::collections::BTreeMap<String, f64>| {
        m.retain(|k, v| {
            let ok = v.is_finite();
            if !ok {
                bad.push(format!("{section}.{k} = {v}"));
            }
            ok
        });
    };
    sweep("design".into(), &mut r.design);
    sweep("objectives".into(), &mut r.objectives);
    sweep("errors".into(), &mut r.errors);
    sweep("derived".into(), &mut r.derived);
    for (b, m) in r.baselines.iter_mut() {
        sweep(format!("baselines.{b}"), m);
    }
    if !bad.is_empty() {
        r.status = Status::Failed;
        r.status_detail = Some(format!(
            "not finite, so not reported: {}; an input is out of proportion (e.g. a counterweight radius far below the machine's size)",
            bad.join(", ")
        ));
    }
}
