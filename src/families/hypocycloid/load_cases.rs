//! Named load cases of the hypocycloid compressor (issue 33, `[[mechanism.load_cases]]`): the
//! same machine against other suction and discharge pressures, every drive figure stated over
//! all the cases with the case that governs it named.
//!
//! The gas force acts between the piston and the cylinder head, both parts of the machine: it
//! is internal, and the frame feels only the inertia forces. So the shaking force at constant
//! speed, the rotating counterweights and the Lanchester couples (`balance::rotating_outcome`,
//! `balance::couple_outcome`, which never read `[mechanism.gas]`) are the same in every case.
//! The case changes the gas torque, hence the drive torque T(φ), its mean T̄ and peak, ΔE, the
//! flywheel and the motor's steady state (whose ω(φ), α(φ) also change the shaking force and
//! the shaft torque at real speed). Each case is solved by the single-case code
//! (`balance::torque_outcome`, `balance::drive_outcome`) with its own [`GasCycle`]; the nominal
//! `[mechanism.gas]` is the case [`NOMINAL`], first, its figures those of the result's
//! single-case keys.
//!
//! The flywheel over the cases. In each case k the steady state's coefficient of fluctuation
//! Cs_k(I_f) does not increase with the flywheel I_f — the premise of
//! `dynamics::least_flywheel`, whose bracket grows I_f until Cs ≤ cs and whose Brent search
//! takes the one crossing. Then {I_f : Cs_k(I_f) ≤ cs} = [I_k, ∞), I_k the case's least
//! flywheel, and the flywheels that meet cs in every case are ∩_k [I_k, ∞) = [max_k I_k, ∞):
//!
//!   I* = max_k I_k,   |I* − Î*| ≤ max_k δI_k   (|max a − max â| ≤ max |a − â|).
//!
//! Every case's steady state at I* is solved and reported, and a case whose Cs there exceeds
//! cs by more than its error is warned about (the premise failing). A file's own `flywheel`
//! is I* instead: each case's Cs is reported with it.
//!
//! The speed band (`[mechanism.envelope] speed`). Every cycle — the nominal one and each
//! load case — is solved at both ends of the band too, each a case named "<name> at <n> rpm",
//! and I* is the largest least flywheel over all of them. The inertial part of the drive
//! torque scales with s = ω², the gas torque does not: E(φ; s) = E_g(φ) + s E_i(φ). So the
//! peak drive torque and ΔE (max − min of functions affine in s) are convex in s, and the
//! textbook flywheel ΔE(s)/(cs·s) = max over φ₁, φ₂ of (E_g(φ₁) − E_g(φ₂))·(1/s) +
//! (E_i(φ₁) − E_i(φ₂)) is convex in 1/s: each is largest at an end of the band, so the
//! worst cases over the band's end cases are the band's (proven). The least flywheel of the
//! exact steady state is not convex in the speed: every cycle's Cs at I* is then proven
//! below cs at every speed of the band, the intervals between solved speeds halved until
//! their bound closes ([`BandCheck::prove`]), or a warning says where it is not.

use super::balance::{drive_outcome, torque_outcome, At, DynamicsError, DynamicsSpec};
use super::balance::{DynamicsOutcome, RotatingOutcome, TorqueOutcome};
use super::gas::{GasCycle, LoadCase};
use crate::dynamics::cases::{argmax, at_rpm, cases_flywheel, check_cs, with_flywheel, CaseDrive};
pub use crate::dynamics::cases::{BandCheck, CasesFlywheel};
use crate::dynamics::{Drive, DriveFigures};
use crate::numeric::ordered;
use crate::report::drive::{case_numbers, load_cases_section, DriveNumbers};
use crate::report::{number_map, SolveResult, Table};
use rayon::prelude::*;
use serde::Serialize;
use serde_json::json;

/// The name of the nominal case (`[mechanism.gas]` itself), the most load cases and the
/// longest name: every family's (`crate::problem::envelope`).
pub use crate::problem::envelope::{MAX_CASE_NAME, MAX_LOAD_CASES, NOMINAL};

/// One case solved.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseOutcome {
    /// The case.
    pub case: LoadCase,
    /// Its speed ω (rad/s): the nominal one, or an end of the speed band.
    pub speed: f64,
    /// Its drive torque at constant speed.
    pub torque: TorqueOutcome,
    /// Its drive with `[mechanism.drive]` (its own least flywheel for `cs`); `Err`: why not.
    pub drive: Option<Result<DriveFigures, String>>,
    /// Its steady state (and peaks at real speed) at the flywheel of all the cases,
    /// [`LoadCasesOutcome::flywheel`]; without one, its own drive's.
    pub at_flywheel: Option<Result<DriveFigures, String>>,
}

/// Every case, the nominal first, and the flywheel that meets `cs` in all of them.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadCasesOutcome {
    /// The cases, [`NOMINAL`] first.
    pub cases: Vec<CaseOutcome>,
    /// I*: the largest least flywheel (with `cs`), or the file's `flywheel`; `None` without
    /// either, or where a case's drive failed.
    pub flywheel: Option<CasesFlywheel>,
    /// With a speed band and `cs`: the steady state inside the band at I*.
    pub band: Option<BandCheck>,
}

/// Solves every load case of `spec` beside the nominal one, whose figures are the dynamics
/// `d` already solved at the design `at` (its torque and drive; the case-independent rotating
/// outcome with them), and with a speed band every case at both its ends too; then each
/// case's steady state at the flywheel of all the cases, and with a band the interior check
/// ([`BandCheck`]); the cases' warnings join `d`'s. `None` without load cases or band (or
/// without a drive torque).
pub fn solve(
    spec: &DynamicsSpec,
    at: &At,
    d: &mut DynamicsOutcome,
) -> Result<Option<LoadCasesOutcome>, DynamicsError> {
    let asked = !spec.load_cases.is_empty() || spec.speed_band.is_some();
    let (Some(torque), true) = (&d.torque, asked) else {
        return Ok(None);
    };
    let (rotating, warnings) = (d.rotating.as_ref(), &mut d.warnings);
    let first = spec.gas.map(|gas| LoadCase {
        name: NOMINAL.into(),
        gas,
    });
    let first = first.ok_or_else(|| DynamicsError {
        key: "mechanism.load_cases".into(),
        message: "load cases need [mechanism.gas]".into(),
    })?;
    let gases: Vec<LoadCase> = std::iter::once(first.clone())
        .chain(spec.load_cases.iter().cloned())
        .collect();
    let mut cases = vec![CaseOutcome {
        case: first,
        speed: at.omega,
        torque: torque.clone(),
        drive: d.drive.clone(),
        at_flywheel: None,
    }];
    let ends = spec.speed_band.map_or(Vec::new(), |(lo, hi)| vec![lo, hi]);
    let speeds: Vec<f64> = std::iter::once(at.omega).chain(ends).collect();
    // Every (speed, gas) but the nominal one, solved in parallel and collected in order (the
    // same result and warnings whatever the threads).
    let jobs: Vec<(usize, &f64, &LoadCase)> = (speeds.iter().enumerate())
        .flat_map(|(si, w)| gases.iter().enumerate().map(move |(gi, g)| (si, gi, w, g)))
        .filter(|&(si, gi, _, _)| si > 0 || gi > 0)
        .map(|(si, _, w, g)| (si, w, g))
        .collect();
    let solved = ordered(jobs.par_iter().map(|&(si, &w, g)| {
        let name = match si {
            0 => g.name.clone(),
            _ => at_rpm(&g.name, w),
        };
        let case = LoadCase { name, gas: g.gas };
        let mut w_ = Vec::new();
        solve_case(spec, &at.at_speed(w), case, rotating, &mut w_).map(|c| (c, w_))
    }))?;
    for (c, w) in solved {
        cases.push(c);
        warnings.extend(w);
    }
    let flywheel = spec
        .drive
        .as_ref()
        .and_then(|d| cases_flywheel(d, &named(&cases, true), warnings));
    let at_flywheel = ordered(cases.par_iter().map(|c| {
        Ok::<_, DynamicsError>(match (&c.drive, flywheel, &spec.drive) {
            (Some(Ok(f)), Some(fw), Some(d)) if f.steady.flywheel != fw.inertia => {
                let at = at.at_speed(c.speed);
                let s = with_gas(spec, c.case.gas);
                Some(drive_outcome(
                    &s,
                    &with_flywheel(d, fw.inertia),
                    &at,
                    &at.geometry(),
                    rotating,
                )?)
            }
            (own, _, _) => own.clone(),
        })
    }))?;
    for (c, f) in cases.iter_mut().zip(at_flywheel) {
        c.at_flywheel = f;
    }
    let cs = spec.drive.as_ref().and_then(|d| d.cs);
    check_cs(cs, &named(&cases, false), warnings);
    let band = match (spec.speed_band, flywheel, &spec.drive) {
        (Some(band), Some(fw), Some(d)) => band_check(
            spec,
            at,
            &gases,
            band,
            with_flywheel(d, fw.inertia),
            rotating,
            warnings,
        ),
        _ => None,
    };
    Ok(Some(LoadCasesOutcome {
        cases,
        flywheel,
        band,
    }))
}

/// One case solved at the design and speed `at`: its torque and its own drive; its warnings,
/// named with the case, join `warnings`.
fn solve_case(
    spec: &DynamicsSpec,
    at: &At,
    case: LoadCase,
    rotating: Option<&RotatingOutcome>,
    warnings: &mut Vec<String>,
) -> Result<CaseOutcome, DynamicsError> {
    let (s, geo) = (with_gas(spec, case.gas), at.geometry());
    let mut w = Vec::new();
    let torque = torque_outcome(&s, at, &geo, rotating, &mut w)?;
    warnings.extend(w.iter().map(|w| format!("load case {}: {w}", case.name)));
    let drive = spec
        .drive
        .as_ref()
        .map(|d| drive_outcome(&s, d, at, &geo, rotating))
        .transpose()?;
    Ok(CaseOutcome {
        case,
        speed: at.omega,
        torque,
        drive,
        at_flywheel: None,
    })
}

/// [`BandCheck::prove`] over the band `band` (rad/s) for the `gases`, with the flywheel drive
/// `d` (a constant torque: the file refuses a band with a motor's characteristic); `None`
/// without a Cs to meet or where a steady state failed (a warning, as is a cycle that cannot
/// be built at a speed inside the band).
fn band_check(
    spec: &DynamicsSpec,
    at: &At,
    gases: &[LoadCase],
    band: (f64, f64),
    d: Drive,
    rotating: Option<&RotatingOutcome>,
    warnings: &mut Vec<String>,
) -> Option<BandCheck> {
    let cs = spec.drive.as_ref().and_then(|d| d.cs)?;
    let names: Vec<&str> = gases.iter().map(|g| g.name.as_str()).collect();
    let solve = |w: f64, c: usize| {
        let at = at.at_speed(w);
        let s = with_gas(spec, gases[c].gas);
        match drive_outcome(&s, &d, &at, &at.geometry(), rotating) {
            Ok(f) => f.map(|f| f.steady),
            Err(e) => Err(e.to_string()),
        }
    };
    BandCheck::prove(cs, band, &names, solve, warnings)
}

/// `spec` with the cycle `gas`, no load cases and no band: one case, for the single-case
/// code.
fn with_gas(spec: &DynamicsSpec, gas: GasCycle) -> DynamicsSpec {
    DynamicsSpec {
        gas: Some(gas),
        load_cases: Vec::new(),
        speed_band: None,
        ..spec.clone()
    }
}

/// Each case's name and one of its drives (`own`: its own; else at the flywheel of all the
/// cases), for [`crate::dynamics::cases`].
fn named(cases: &[CaseOutcome], own: bool) -> Vec<CaseDrive<'_>> {
    cases
        .iter()
        .map(|c| {
            let d = if own { &c.drive } else { &c.at_flywheel };
            (c.case.name.as_str(), d.as_ref())
        })
        .collect()
}

/// One case's row of the `load_cases` section and of `<name>-load-cases.csv` (keys with
/// their unit suffix, `docs/results.md`): its pressures, its drive torque (the single-case
/// keys of `numbers::DynamicsDerived`) and, with `[mechanism.drive]`, the single-case drive
/// keys ([`DriveNumbers`]) of its own constant-speed figures and least flywheel with its
/// steady state at the flywheel of all the cases.
#[derive(Debug, Serialize)]
struct CaseRow<'a> {
    case: &'a str,
    speed_rad_s: f64,
    suction_pressure_pa: f64,
    discharge_pressure_pa: f64,
    drive_torque_mean_nm: f64,
    drive_torque_peak_nm: f64,
    drive_torque_peak_error_nm: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    indicated_work_nm: Option<f64>,
    #[serde(flatten)]
    drive: Option<DriveNumbers>,
    #[serde(skip_serializing_if = "Option::is_none")]
    drive_error: Option<&'a str>,
}

impl<'a> CaseRow<'a> {
    /// `c`'s row; `peak_force` the design's constant-speed peak shaking force (N).
    fn of(c: &'a CaseOutcome, peak_force: Option<f64>) -> CaseRow<'a> {
        let (t, g) = (&c.torque, &c.case.gas);
        let (drive, why) = case_numbers(c.drive.as_ref(), c.at_flywheel.as_ref(), peak_force);
        CaseRow {
            case: &c.case.name,
            speed_rad_s: c.speed,
            suction_pressure_pa: g.suction,
            discharge_pressure_pa: g.discharge,
            drive_torque_mean_nm: t.mean,
            drive_torque_peak_nm: t.peak,
            drive_torque_peak_error_nm: t.peak_error,
            indicated_work_nm: t.indicated_work,
            drive,
            drive_error: why,
        }
    }

    /// The drive's numbers, if the case has them.
    fn d(&self) -> Option<&DriveNumbers> {
        self.drive.as_ref()
    }
}

/// The worst case's figures over the load cases (`derived`, `docs/results.md`): each the
/// largest over the cases (ω_min the smallest), its error the largest of the cases' errors.
#[derive(Debug, Default, Serialize)]
struct WorstCase {
    load_case_count: f64,
    worst_case_drive_torque_mean_nm: Option<f64>,
    worst_case_drive_torque_peak_nm: Option<f64>,
    worst_case_drive_torque_peak_error_nm: Option<f64>,
    worst_case_energy_fluctuation_j: Option<f64>,
    worst_case_energy_fluctuation_error_j: Option<f64>,
    worst_case_flywheel_textbook_kgm2: Option<f64>,
    load_cases_flywheel_kgm2: Option<f64>,
    load_cases_flywheel_error_kgm2: Option<f64>,
    worst_case_steady_cs: Option<f64>,
    worst_case_steady_cs_error: Option<f64>,
    worst_case_steady_omega_min_rad_s: Option<f64>,
    worst_case_steady_omega_max_rad_s: Option<f64>,
    worst_case_steady_peak_shaft_torque_nm: Option<f64>,
    worst_case_steady_peak_shaft_torque_error_nm: Option<f64>,
}

/// The largest of one figure over the rows (`None` if a row lacks it) and its case's index.
fn worst(rows: &[CaseRow], f: impl Fn(&CaseRow) -> Option<f64>) -> Option<(f64, usize)> {
    let v: Option<Vec<f64>> = rows.iter().map(&f).collect();
    let v = v?;
    argmax(v.iter().copied()).map(|k| (v[k], k))
}

/// The load cases in the result: the worst case's figures in `derived`, the `load_cases`
/// section (the flywheel of all the cases, the governing cases' names, one row per case).
pub fn numbers(r: &mut SolveResult, lc: &LoadCasesOutcome, peak_force: Option<f64>) {
    let rows: Vec<CaseRow> = lc
        .cases
        .iter()
        .map(|c| CaseRow::of(c, peak_force))
        .collect();
    let max = |f: &dyn Fn(&CaseRow) -> Option<f64>| worst(&rows, f).map(|w| w.0);
    let name = |w: Option<(f64, usize)>| w.map(|w| rows[w.1].case);
    let peak = worst(&rows, |c| Some(c.drive_torque_peak_nm));
    let energy = worst(&rows, |c| c.d().map(|d| d.energy_fluctuation_j));
    let cs = worst(&rows, |c| c.d().map(|d| d.steady_cs));
    let shaft = worst(&rows, |c| c.d().and_then(|d| d.steady_peak_shaft_torque_nm));
    r.derived.extend(number_map(&WorstCase {
        load_case_count: rows.len() as f64,
        worst_case_drive_torque_mean_nm: max(&|c| Some(c.drive_torque_mean_nm)),
        worst_case_drive_torque_peak_nm: peak.map(|w| w.0),
        worst_case_drive_torque_peak_error_nm: max(&|c| Some(c.drive_torque_peak_error_nm)),
        worst_case_energy_fluctuation_j: energy.map(|w| w.0),
        worst_case_energy_fluctuation_error_j: max(&|c| {
            c.d().map(|d| d.energy_fluctuation_error_j)
        }),
        worst_case_flywheel_textbook_kgm2: max(&|c| c.d().and_then(|d| d.flywheel_textbook_kgm2)),
        load_cases_flywheel_kgm2: lc.flywheel.map(|f| f.inertia),
        load_cases_flywheel_error_kgm2: lc.flywheel.map(|f| f.error),
        worst_case_steady_cs: cs.map(|w| w.0),
        worst_case_steady_cs_error: max(&|c| c.d().map(|d| d.steady_cs_error)),
        worst_case_steady_omega_min_rad_s: max(&|c| c.d().map(|d| -d.steady_omega_min_rad_s))
            .map(|w| -w),
        worst_case_steady_omega_max_rad_s: max(&|c| c.d().map(|d| d.steady_omega_max_rad_s)),
        worst_case_steady_peak_shaft_torque_nm: shaft.map(|w| w.0),
        worst_case_steady_peak_shaft_torque_error_nm: max(&|c| {
            c.d().and_then(|d| d.steady_peak_shaft_torque_error_nm)
        }),
    }));
    let own = json!({
        "drive_torque_peak_case": name(peak),
        "energy_fluctuation_case": name(energy),
        "steady_cs_case": name(cs),
        "steady_peak_shaft_torque_case": name(shaft),
        "speed_band_check": lc.band,
        "cases": rows,
    });
    let section = load_cases_section(rows.len(), lc.flywheel, |k| rows[k].case, own);
    r.extra.insert("load_cases".into(), section);
}

/// `<name>-load-cases.csv`: the `load_cases` section's rows, one per case, its keys the
/// columns in the JSON's order (`case` first); a figure a case lacks is empty.
pub fn table(r: &mut SolveResult, lc: &LoadCasesOutcome, peak_force: Option<f64>) {
    let rows: Vec<serde_json::Value> = lc
        .cases
        .iter()
        .map(|c| json!(CaseRow::of(c, peak_force)))
        .collect();
    r.tables.push(Table::of_rows(
        "load-cases",
        "The load cases: each case's pressures, drive torque, energy fluctuation, flywheels (textbook and least) and steady state at the flywheel of all the cases",
        &rows,
    ));
}
