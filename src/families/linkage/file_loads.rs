//! `[[mechanism.loads]]` of a linkage file: process forces on points of links (a press's
//! pressing force), read and checked into [`ProcessLoad`]s (`docs/problem-files.md`,
//! "Process loads").

use crate::families::linkage::envelope::LinkageLoadCase;
use crate::families::linkage::model::{Point, ProcessLoad};
use crate::geom::P2;
use crate::problem::FieldError;
use crate::units::{Angle, Force, Qty};
use serde::Deserialize;
use std::f64::consts::TAU;

/// Most process loads on one linkage.
pub const MAX_LOADS: usize = 16;

/// Most points of one load's table (a measured force at 0.1° is 3600).
pub const MAX_LOAD_POINTS: usize = 3600;

/// `[[mechanism.loads]]`: a force on a point of a link, of fixed direction, its magnitude a
/// table over the crank angle.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LoadRaw {
    /// Its point on a link: `"NAME.pivot"`, `"NAME.tip"` or `{ link = "NAME", at = [x, y] }`
    /// (a frame point carries no load).
    #[schemars(schema_with = "crate::problem::schema::point_ref")]
    pub point: toml::Value,
    /// The force's direction in the world, counter-clockwise from +x (`"90 deg"`: upwards,
    /// as a workpiece pushes back on a ram that presses down).
    pub direction: Qty<Angle>,
    /// The crank angles of the table, increasing, in [0°, 360°).
    #[schemars(length(min = 1, max = MAX_LOAD_POINTS))]
    pub angles: Vec<Qty<Angle>>,
    /// The force's magnitude at each angle, linear in between and from the last angle across
    /// 360° back to the first.
    #[schemars(length(min = 1, max = MAX_LOAD_POINTS))]
    pub forces: Vec<Qty<Force>>,
}

/// `[[mechanism.load_cases]]`: a named load case, its own process loads in place of the
/// file's `[[mechanism.loads]]` (none: the machine idle).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LoadCaseRaw {
    /// Its name in the result: unique, not `"nominal"` (the file's own loads).
    #[schemars(length(max = crate::problem::envelope::MAX_CASE_NAME))]
    pub name: String,
    /// Its loads, as `[[mechanism.loads]]` (`[[mechanism.load_cases.loads]]` after the case).
    #[serde(default)]
    #[schemars(length(max = MAX_LOADS))]
    pub loads: Vec<LoadRaw>,
}

/// Reads a point reference against the links: `point(key, value)`.
pub type PointOf<'a> = &'a dyn Fn(&str, &toml::Value) -> Result<Point, FieldError>;

/// The loads checked.
pub fn resolve_loads(raw: &[LoadRaw], point: PointOf) -> Result<Vec<ProcessLoad>, FieldError> {
    loads_at("mechanism.loads", raw, point)
}

/// The load cases checked: at most [`crate::problem::envelope::MAX_LOAD_CASES`], each named
/// ([`crate::problem::envelope::case_name`]) with its loads checked as `[[mechanism.loads]]`.
pub fn resolve_cases(
    raw: &[LoadCaseRaw],
    point: PointOf,
) -> Result<Vec<LinkageLoadCase>, FieldError> {
    crate::problem::envelope::case_count(raw.len())?;
    let mut cases: Vec<LinkageLoadCase> = Vec::with_capacity(raw.len());
    for (i, c) in raw.iter().enumerate() {
        let key = format!("mechanism.load_cases[{i}]");
        let taken = cases.iter().map(|k| k.name.as_str());
        let name = crate::problem::envelope::case_name(
            &key,
            &c.name,
            taken,
            "the file's own [[mechanism.loads]]",
        )?;
        let loads = loads_at(&format!("{key}.loads"), &c.loads, point)?;
        cases.push(LinkageLoadCase { name, loads });
    }
    Ok(cases)
}

/// The loads of the array `key` checked.
fn loads_at(key: &str, raw: &[LoadRaw], point: PointOf) -> Result<Vec<ProcessLoad>, FieldError> {
    if raw.len() > MAX_LOADS {
        return Err(FieldError::new(
            format!("{key}[{MAX_LOADS}]"),
            format!("{} loads; allowed: at most {MAX_LOADS}", raw.len()),
        ));
    }
    raw.iter()
        .enumerate()
        .map(|(i, l)| load(&format!("{key}[{i}]"), l, point))
        .collect()
}

/// One load.
fn load(key: &str, l: &LoadRaw, point: PointOf) -> Result<ProcessLoad, FieldError> {
    let pk = format!("{key}.point");
    let (link, at) = match point(&pk, &l.point)? {
        Point::On { link, at } => (link, at),
        Point::Frame(_) => {
            return Err(FieldError::new(
                pk,
                "a frame point carries no load; allowed: \"NAME.pivot\", \"NAME.tip\" or { link = \"NAME\", at = [...] }",
            ))
        }
    };
    let (n, m) = (l.angles.len(), l.forces.len());
    if n == 0 || n != m || n > MAX_LOAD_POINTS {
        return Err(FieldError::new(
            format!("{key}.forces"),
            format!("{m} forces for {n} angles; allowed: as many forces as angles, 1 to {MAX_LOAD_POINTS}"),
        ));
    }
    let table: Vec<(f64, f64)> = l
        .angles
        .iter()
        .zip(&l.forces)
        .map(|(a, f)| (a.si(), f.si()))
        .collect();
    let in_turn = table.iter().all(|p| (0.0..TAU).contains(&p.0));
    if !in_turn || !table.windows(2).all(|w| w[0].0 < w[1].0) {
        return Err(FieldError::new(
            format!("{key}.angles"),
            "allowed: increasing crank angles in [0°, 360°)",
        ));
    }
    if !table.iter().all(|p| p.1.is_finite()) {
        return Err(FieldError::new(
            format!("{key}.forces"),
            "allowed: finite forces",
        ));
    }
    let d = l.direction.si();
    if !d.is_finite() {
        return Err(FieldError::new(
            format!("{key}.direction"),
            "allowed: a finite angle",
        ));
    }
    Ok(ProcessLoad {
        link,
        at,
        direction: P2::new(d.cos(), d.sin()),
        table,
    })
}
