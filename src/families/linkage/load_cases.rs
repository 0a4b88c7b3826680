//! The linkage's drive in every named load case (issue 33, item 3: `[[mechanism.load_cases]]`
//! with `[mechanism.drive]`): each case's own drive (its ΔE, textbook and least flywheel) at
//! the nominal speed and masses and, with an envelope, at every vertex of its box — the ends
//! of the speed band, where a flywheel sized at the nominal speed is too small: I ≈ ΔE/(Cs ω̄²)
//! grows as ω̄ falls — the flywheel of all of them — the largest least flywheel, exact
//! ([`crate::dynamics::cases`]) over those scenarios — the least flywheel is not convex in
//! ω, so with a constant-torque drive every case's Cs at that flywheel is then proven below
//! `cs` over the band's inside, or shown not to be ([`BandCheck::prove`]) — and every
//! scenario's steady state with it. The
//! counterweights are the solve's (the worst case over the cases is the envelope's,
//! `solve_envelope`).

use super::drive::{figures_with, steady, TermsMemo};
use super::file::LinkageScene;
use super::synth as ls;
use crate::dynamics::cases::{
    argmax, at_rpm, cases_flywheel, check_cs, with_flywheel, BandCheck, CaseDrive, CasesFlywheel,
};
use crate::dynamics::{Drive, DriveFigures, Motor, SteadyState};
use crate::report::drive::{case_numbers, load_cases_section, DriveNumbers};
use crate::report::{SolveResult, Table};
use rayon::prelude::*;
use serde::Serialize;
use serde_json::json;

/// One case's drive in one scenario of the envelope.
#[derive(Debug, Clone)]
pub struct CaseDrives {
    /// The case's name (`nominal` first), with ` at vertex N` (1-based,
    /// [`crate::synth::envelope::vertices`]' order) at a vertex of the envelope's box, or
    /// ` at <n> rpm` at an end of a box that is a speed band alone.
    pub name: String,
    /// The envelope's parameters there ([`crate::families::linkage::envelope::LinkageEnvelope::names`]
    /// with their values; empty without an envelope).
    pub values: Vec<(String, f64)>,
    /// Its own drive: its least flywheel for `cs`, its steady state with it (`Err`: why not).
    pub own: Result<DriveFigures, String>,
    /// Its steady state with the flywheel of all the cases (its own drive where that is its
    /// own flywheel, or where there is no flywheel of all the cases).
    pub at_flywheel: Option<Result<DriveFigures, String>>,
}

/// Every case's drive and the flywheel of all the cases.
#[derive(Debug, Clone)]
pub struct LoadCaseDrives {
    /// The cases, the nominal first.
    pub cases: Vec<CaseDrives>,
    /// I*: the largest least flywheel (with `cs`) or the file's `flywheel`; `None` without
    /// either, or where a case's drive failed (a warning).
    pub flywheel: Option<CasesFlywheel>,
    /// With a speed band, a constant-torque drive and `cs`: every case over the band with I*
    /// ([`BandCheck::prove`]; the masses and lengths nominal).
    pub band: Option<BandCheck>,
}

/// The drive `d` of the design `x` in every load case of `sc` beside the nominal one, whose
/// drive `nominal` the solve already has; `None` without named load cases. Warnings (a case
/// whose drive failed, a case that swings more than `cs` with I*) join `warnings`.
pub fn solve(
    sc: &LinkageScene,
    d: &Drive,
    x: Option<&[f64]>,
    nominal: &Result<DriveFigures, String>,
    warnings: &mut Vec<String>,
) -> Option<LoadCaseDrives> {
    let env = &sc.envelope;
    if env.cases.is_empty() {
        return None;
    }
    let scenarios = scenarios(sc);
    let scene = |k: usize| {
        let (c, _, values) = &scenarios[k];
        ls::scene_at_case(sc, *c, values).map_err(|e| e.to_string())
    };
    let names = env.names();
    let speed_band_alone = names.len() == 1 && env.speed.is_some();
    // A box that is a speed band alone: each case's scenes differ in their speed alone and
    // share its drive's terms ([`TermsMemo`]); otherwise each scene samples its own.
    let memos: Vec<TermsMemo> = match speed_band_alone {
        true => (0..=env.cases.len())
            .map(|_| TermsMemo::default())
            .collect(),
        false => Vec::new(),
    };
    let memo = |k: usize| memos.get(scenarios[k].0);
    // The scenarios' drives are independent: in parallel, collected in order (the same
    // result whatever the threads).
    let mut cases: Vec<CaseDrives> = (scenarios.par_iter().enumerate())
        .map(|(k, (c, vertex, values))| CaseDrives {
            name: match vertex {
                None => env.case_name(*c).to_string(),
                // A speed band alone: its end in rpm, as the hypocycloid's cases.
                Some(_) if speed_band_alone => at_rpm(env.case_name(*c), values[0]),
                Some(v) => format!("{} at vertex {}", env.case_name(*c), v + 1),
            },
            values: names.iter().cloned().zip(values.iter().copied()).collect(),
            own: match k {
                0 => nominal.clone(),
                k => scene(k)
                    .and_then(|s| figures_with(&s, d, x, memo(k)).map_err(|e| e.to_string())),
            },
            at_flywheel: None,
        })
        .collect();
    let own: Vec<CaseDrive> = cases
        .iter()
        .map(|c| (c.name.as_str(), Some(&c.own)))
        .collect();
    let flywheel = cases_flywheel(d, &own, warnings);
    cases.par_iter_mut().enumerate().for_each(|(k, case)| {
        case.at_flywheel = match (&case.own, flywheel) {
            (Ok(f), Some(fw)) if f.steady.flywheel != fw.inertia => Some(scene(k).and_then(|s| {
                figures_with(&s, &with_flywheel(d, fw.inertia), x, memo(k))
                    .map_err(|e| e.to_string())
            })),
            (own, _) => Some(own.clone()),
        };
    });
    let at: Vec<CaseDrive> = cases
        .iter()
        .map(|c| (c.name.as_str(), c.at_flywheel.as_ref()))
        .collect();
    check_cs(d.cs, &at, warnings);
    let band = match (env.speed, flywheel, d.cs) {
        (Some(band), Some(fw), Some(cs)) => {
            let job = BandJob {
                d,
                flywheel: fw.inertia,
                x,
                memos: &memos,
            };
            band_check(sc, band, &job, cs, warnings)
        }
        _ => None,
    };
    Some(LoadCaseDrives {
        cases,
        flywheel,
        band,
    })
}

/// Every load case over the band `band` (rad/s), the other parameters nominal, on the
/// constant torque of `d` with the flywheel `flywheel`: Cs proven below `cs` at every speed
/// of the band, or where not ([`BandCheck::prove`]; the terms are the same at every speed,
/// [`TermsMemo`]). With a motor's characteristic the motor sets the speed, not the band:
/// every speed would give the one steady state, so there is no check (`None`).
fn band_check(
    sc: &LinkageScene,
    band: (f64, f64),
    job: &BandJob,
    cs: f64,
    warnings: &mut Vec<String>,
) -> Option<BandCheck> {
    let BandJob {
        d,
        flywheel,
        x,
        memos,
    } = *job;
    if d.motor != Motor::ConstantTorque {
        return None;
    }
    let env = &sc.envelope;
    let nominal = env.nominal(&sc.linkage);
    let names: Vec<&str> = (0..=env.cases.len()).map(|c| env.case_name(c)).collect();
    let solve = |w: f64, c: usize| -> Result<SteadyState, String> {
        // The speed is the envelope's first parameter.
        let mut values = nominal.clone();
        values[0] = w;
        let s = ls::scene_at_case(sc, c, &values).map_err(|e| e.to_string())?;
        steady(&s, d, flywheel, x, memos.get(c)).map_err(|e| e.to_string())
    };
    BandCheck::prove(cs, band, &names, solve, warnings)
}

/// What the band's check solves: the drive `d` with the flywheel of all the cases, the
/// design `x`, and each case's terms memo (empty: none shared).
#[derive(Clone, Copy)]
struct BandJob<'a> {
    d: &'a Drive,
    flywheel: f64,
    x: Option<&'a [f64]>,
    memos: &'a [TermsMemo],
}

/// The drive's scenarios: each load case (the nominal loads first) at the nominal values of
/// the envelope's parameters and then at every vertex of its box (none without a box), as
/// (case, vertex, the parameters' values).
fn scenarios(sc: &LinkageScene) -> Vec<(usize, Option<usize>, Vec<f64>)> {
    let env = &sc.envelope;
    let ranges = env.ranges();
    let vertices = match ranges.is_empty() {
        true => Vec::new(),
        false => crate::synth::envelope::vertices(&ranges),
    };
    let nominal = env.nominal(&sc.linkage);
    (0..=env.cases.len())
        .flat_map(|c| {
            let at_vertices = vertices.iter().enumerate();
            std::iter::once((c, None, nominal.clone()))
                .chain(at_vertices.map(move |(v, values)| (c, Some(v), values.clone())))
        })
        .collect()
}

/// One case's row of the `load_cases` section and of `<name>-load-cases.csv`: its name, the
/// drive's keys ([`DriveNumbers`]: its own constant-speed figures and least flywheel, its
/// steady state with the flywheel of all the cases) and why its drive failed, if it did.
#[derive(Debug, Serialize)]
struct CaseRow<'a> {
    case: &'a str,
    /// The envelope's parameters in this scenario (SI, [`CaseDrives::values`]).
    #[serde(flatten)]
    values: std::collections::BTreeMap<&'a str, f64>,
    #[serde(flatten)]
    drive: Option<DriveNumbers>,
    #[serde(skip_serializing_if = "Option::is_none")]
    drive_error: Option<&'a str>,
}

impl<'a> CaseRow<'a> {
    /// `c`'s row; `peak_force` the design's constant-speed peak shaking force (N).
    fn of(c: &'a CaseDrives, peak_force: Option<f64>) -> CaseRow<'a> {
        let at = c.at_flywheel.as_ref().unwrap_or(&c.own);
        let (drive, why) = case_numbers(Some(&c.own), Some(at), peak_force);
        CaseRow {
            case: &c.name,
            values: c.values.iter().map(|(k, v)| (k.as_str(), *v)).collect(),
            drive,
            drive_error: why,
        }
    }
}

/// The load cases in the result: `derived.load_case_count` and the flywheel of all the
/// cases (`load_cases_flywheel_kgm2`, its error), the section `load_cases` (that flywheel,
/// the cases that govern it, ΔE and Cs, one row per case) and `<name>-load-cases.csv`.
pub fn numbers(r: &mut SolveResult, lc: &LoadCaseDrives, peak_force: Option<f64>) {
    let rows: Vec<CaseRow> = lc
        .cases
        .iter()
        .map(|c| CaseRow::of(c, peak_force))
        .collect();
    let governing = |f: &dyn Fn(&DriveNumbers) -> f64| {
        let v: Option<Vec<f64>> = rows.iter().map(|r| r.drive.as_ref().map(f)).collect();
        argmax(v?.into_iter()).map(|k| rows[k].case)
    };
    r.derived
        .insert("load_case_count".into(), rows.len() as f64);
    if let Some(f) = lc.flywheel {
        r.derived
            .insert("load_cases_flywheel_kgm2".into(), f.inertia);
        r.derived
            .insert("load_cases_flywheel_error_kgm2".into(), f.error);
    }
    let own = json!({
        "energy_fluctuation_case": governing(&|d| d.energy_fluctuation_j),
        "steady_cs_case": governing(&|d| d.steady_cs),
        "speed_band_check": lc.band,
        "cases": rows,
    });
    let section = load_cases_section(rows.len(), lc.flywheel, |k| rows[k].case, own);
    r.extra.insert("load_cases".into(), section);
}

/// `<name>-load-cases.csv`: the `load_cases` section's rows, one per case, its keys the
/// columns in the JSON's order (`case` first); a figure a case lacks is empty.
pub fn table(r: &mut SolveResult, lc: &LoadCaseDrives, peak_force: Option<f64>) {
    let rows: Vec<serde_json::Value> = (lc.cases.iter())
        .map(|c| json!(CaseRow::of(c, peak_force)))
        .collect();
    r.tables.push(Table::of_rows(
        "load-cases",
        "The load cases: each case's drive at the nominal speed (T̄, ΔE, the textbook and the least flywheel) and its steady state with the flywheel of all the cases",
        &rows,
    ));
}
