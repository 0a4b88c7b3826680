//! One home per mechanism family, and the seam every engine above talks through.
//!
//! Each folder holds one family whole: `model` (pure physics), `file` (its problem file: raw
//! serde layer and resolution), `synth` (design vector, objectives, solves), `schema` (its
//! branch of the JSON Schema) and `study` (its ladder of settings and the effects its model
//! leaves out). A family is a [`Family`] (what reads its files) whose resolved scenes are
//! [`Machine`]s (what solves and studies them); [`FAMILIES`] lists them, one line each.
//! Nothing above this module — `batch`, `study`, `cli` — names a family.

pub mod crane;
pub mod gear;
pub mod hypocycloid;
pub mod slider_crank;

use crate::problem::edit::Edit;
use crate::problem::limits::Count;
use crate::problem::{Ctx, FieldError, Header, Input, PaperRef, ProblemError, Resolved};
use crate::report::{SolveResult, Status};
use serde::Deserialize;
use std::any::Any;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// The registry: every family, one line each. Adding a family is one folder and one line.
pub static FAMILIES: [&dyn Family; 4] = [
    &slider_crank::SliderCrank,
    &crane::LuffingCrane,
    &hypocycloid::HypocycloidFamily,
    &gear::EccentricGear,
];

/// A mechanism family: what reads its problem files.
pub trait Family: Sync + fmt::Debug {
    /// The `family = "…"` value of its files and results (`slider-crank`).
    fn name(&self) -> &'static str;
    /// The integer keys of its files and their ranges.
    fn counts(&self) -> &'static [Count];
    /// Its branch of the JSON Schema (ranges are added from [`Family::counts`]).
    fn schema(&self) -> serde_json::Value;
    /// Reads and checks a file of this family.
    fn resolve(&self, ctx: &Ctx, input: Input) -> Result<Resolved<Arc<dyn Machine>>, ProblemError>;
}

/// A resolved scene's own part: what solves and studies it.
pub trait Machine: fmt::Debug + Send + Sync + Any {
    /// Solves the scene (numbers, report tables and plots). Never panics on a resolved
    /// scene; a solver failure is `status = failed`.
    fn solve(&self, scene: &Scene) -> SolveResult;
    /// The headline: the dotted result key the design is judged on (`objectives.delta_h_m`)
    /// — the objective the scene optimises, or its main figure for an analysis.
    fn headline(&self) -> String;
    /// The reference edits (tightest settings) and the ladder of settings of `cwsynth study`.
    fn ladder(&self) -> Ladder;
    /// What the model leaves out or includes, each with a bound; `reference` is the solution
    /// at the tightest settings, whose headline value is `headline`.
    fn effects(&self, reference: &SolveResult, headline: f64) -> Vec<Effect>;
    /// For [`Scene::machine`].
    fn as_any(&self) -> &dyn Any;
}

/// One entry of [`Machine::effects`]: (effect, what is left out or included, with its bound).
pub type Effect = (String, String);

/// A rung of a study's ladder: one change of the settings.
#[derive(Debug, Clone)]
pub struct Rung {
    /// Short label.
    pub label: String,
    /// `accuracy` or `model`.
    pub kind: &'static str,
    /// Edits applied to the file as written.
    pub edits: Vec<Edit>,
}

impl Rung {
    /// A rung.
    pub fn new(label: &str, kind: &'static str, edits: Vec<Edit>) -> Rung {
        Rung {
            label: label.into(),
            kind,
            edits,
        }
    }
}

/// A family's study plan for one scene.
#[derive(Debug, Clone)]
pub struct Ladder {
    /// The edits of the reference (tightest settings).
    pub reference: Vec<Edit>,
    /// The rungs, each against the reference.
    pub rungs: Vec<Rung>,
}

/// A resolved scene of any family.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Name.
    pub name: String,
    /// Family.
    pub family: &'static dyn Family,
    /// Description.
    pub description: String,
    /// The file it came from.
    pub source: PathBuf,
    /// Paper reference values.
    pub paper: Vec<PaperRef>,
    /// The family's resolved part.
    pub machine: Arc<dyn Machine>,
}

impl Scene {
    /// The family's resolved part as its concrete type (`None` for another family).
    pub fn machine<T: Machine>(&self) -> Option<&T> {
        self.machine.as_any().downcast_ref()
    }

    /// An empty result of this scene: its name, family, description and source.
    pub fn new_result(&self) -> SolveResult {
        SolveResult::new(
            &self.name,
            self.family.name(),
            &self.description,
            &self.source,
        )
    }
}

/// `x` relative to a headline value (a bound stated against the headline; never divides by 0).
pub fn relative(x: f64, headline: f64) -> f64 {
    x / headline.abs().max(1e-300)
}

/// The family named `name` in a file or result.
pub fn by_name(name: &str) -> Option<&'static dyn Family> {
    FAMILIES.iter().copied().find(|f| f.name() == name)
}

/// Wraps a family's resolved part as a [`Machine`].
pub fn machine<K: Machine>(r: Resolved<K>) -> Resolved<Arc<dyn Machine>> {
    Resolved {
        name: r.name,
        description: r.description,
        source: r.source,
        paper: r.paper,
        part: Arc::new(r.part),
    }
}

/// Reads and resolves a problem file.
pub fn load(path: &Path) -> Result<Scene, ProblemError> {
    let text = std::fs::read_to_string(path).map_err(|source| ProblemError::Read {
        file: path.into(),
        source,
    })?;
    parse_str(&text, path)
}

/// Resolves problem-file text; `path` is used for messages and as the scene's source.
pub fn parse_str(text: &str, path: &Path) -> Result<Scene, ProblemError> {
    let ctx = Ctx::new(path, text);
    let header: Header = ctx.parse(text)?;
    resolve(&ctx, header, Input::Text(text))
}

/// Resolves a problem file already parsed into a table, with the same checks as
/// [`parse_str`] (which gives the same scene for the table's text); `path` is used for
/// messages and as the scene's source. Its errors have no line: a caller that needs one reads
/// the text with [`parse_str`]. A fleet row takes this way and never prints TOML.
pub fn parse_table(table: toml::Table, path: &Path) -> Result<Scene, ProblemError> {
    let ctx = Ctx::new(path, "");
    let header = Header::of_table(&ctx, &table)?;
    resolve(&ctx, header, Input::Table(table))
}

/// The allowed `family` values, for messages.
fn allowed() -> String {
    let names: Vec<String> = FAMILIES
        .iter()
        .map(|f| format!("\"{}\"", f.name()))
        .collect();
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
            ctx.field_error(FieldError::new(
                "family",
                format!("unknown family {value}; {}", allowed()),
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
