//! The flywheel of several load cases (issue 33, item 3), written once for every family
//! with named load cases: each case's Cs_k(I_f) does not increase with I_f (the premise of
//! the least-flywheel search itself, [`super::least_flywheel`]), so the flywheels that meet
//! `cs` in case k are [I_k, ∞) and those that meet it in every case [max_k I_k, ∞): the
//! flywheel of all the cases is the largest least flywheel, exactly, with the largest of
//! their errors.

use super::{Drive, DriveFigures};

/// The flywheel of all the cases.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CasesFlywheel {
    /// I* (kg·m²).
    pub inertia: f64,
    /// Bound on its error (kg·m²): max_k δI_k, 0 for a given flywheel.
    pub error: f64,
    /// The case whose least flywheel it is; `None`: the file's `flywheel`.
    pub governing: Option<usize>,
}

/// One case's own drive, as the flywheel of all the cases reads it: its name and its drive
/// (`None`: not computed; `Err`: why it failed).
pub type CaseDrive<'a> = (&'a str, Option<&'a Result<DriveFigures, String>>);

/// I*: the file's `flywheel`, else with `cs` the largest of the cases' least flywheels (the
/// module's doc), else none. A case whose drive failed leaves it unknown (a warning).
pub fn cases_flywheel(
    d: &Drive,
    cases: &[CaseDrive],
    warnings: &mut Vec<String>,
) -> Option<CasesFlywheel> {
    if let Some(f) = d.flywheel {
        return Some(CasesFlywheel {
            inertia: f,
            error: 0.0,
            governing: None,
        });
    }
    d.cs?;
    let mut least = Vec::with_capacity(cases.len());
    for (name, drive) in cases {
        match drive {
            Some(Ok(DriveFigures {
                flywheel: Some(f), ..
            })) => least.push((f.inertia, f.inertia_error)),
            Some(Err(why)) => {
                warnings.push(format!(
                    "no flywheel for all the load cases: the drive of load case {name} failed: {why}"
                ));
                return None;
            }
            _ => return None,
        }
    }
    let k = argmax(least.iter().map(|l| l.0))?;
    Some(CasesFlywheel {
        inertia: least[k].0,
        error: least.iter().map(|l| l.1).fold(0.0, f64::max),
        governing: Some(k),
    })
}

/// The drive `d` with the flywheel `inertia` given instead of a Cs to meet: each case's
/// steady state at the flywheel of all the cases.
pub fn with_flywheel(d: &Drive, inertia: f64) -> Drive {
    Drive {
        cs: None,
        flywheel: Some(inertia),
        motor: d.motor.clone(),
    }
}

/// A warning for every case (name, its drive at the flywheel of all the cases) whose steady
/// state swings more than `cs` beyond its error.
pub fn check_cs(cs: Option<f64>, cases: &[CaseDrive], warnings: &mut Vec<String>) {
    let Some(cs) = cs else { return };
    for (name, drive) in cases {
        if let Some(Ok(f)) = drive {
            let st = &f.steady;
            if st.cs > cs + st.cs_error {
                warnings.push(format!(
                    "load case {name}: Cs = {:.6} ± {:.1e} with the flywheel {:.6} kg·m² is above mechanism.drive.cs = {cs}",
                    st.cs, st.cs_error, st.flywheel
                ));
            }
        }
    }
}

/// The index of the largest value (the first of equal ones); `None` for no values or NaN.
pub fn argmax(v: impl Iterator<Item = f64>) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, x) in v.enumerate() {
        if x.is_nan() {
            return None;
        }
        if best.is_none_or(|b| x > b.1) {
            best = Some((i, x));
        }
    }
    best.map(|b| b.0)
}

/// Interior speeds of a speed band at which every case's steady state is checked.
pub const BAND_CHECK_SPEEDS: usize = 7;

/// The [`BAND_CHECK_SPEEDS`] evenly spaced speeds inside the band `(lo, hi)` (rad/s), its
/// ends left out.
pub fn band_speeds(band: (f64, f64)) -> impl Iterator<Item = f64> {
    let n = BAND_CHECK_SPEEDS;
    (1..=n).map(move |j| band.0 + (band.1 - band.0) * j as f64 / (n + 1) as f64)
}

/// A case's name at an end of a speed band: `"<case> at <n> rpm"`, n from ω (rad/s) to
/// 10⁻⁹ rpm (so that 110 rpm, through rad/s and back, reads 110).
pub fn at_rpm(case: &str, omega: f64) -> String {
    let rpm = (omega * 60.0 / std::f64::consts::TAU * 1e9).round() / 1e9;
    format!("{case} at {rpm} rpm")
}

/// The steady state inside the speed band, at the flywheel of all the cases: the exact least
/// flywheel is not proven to be largest at the band's ends (it is not convex in the speed),
/// so every case is solved at [`BAND_CHECK_SPEEDS`] evenly spaced interior speeds with that
/// flywheel and its Cs compared with `cs`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BandCheck {
    /// Speeds checked per cycle.
    pub speeds: usize,
    /// The largest Cs over them, its error and the speed (rad/s) and cycle it is at.
    pub max_cs: f64,
    /// Its error bound.
    pub max_cs_error: f64,
    /// Where: ω (rad/s).
    pub max_cs_speed_rad_s: f64,
    /// Where: the cycle's name.
    pub max_cs_case: String,
    /// Checks whose Cs is above `cs` beyond its error (0: the band's ends govern).
    pub beyond: usize,
}

impl BandCheck {
    /// The check of the steady states `rows` — (ω in rad/s, the case's name, its steady
    /// state with the flywheel of all the cases or why it failed), [`BAND_CHECK_SPEEDS`] = `n`
    /// speeds per case — against `cs`: the largest Cs and where; a warning where one swings
    /// more than `cs` beyond its error; `None` (a warning) where a steady state failed.
    pub fn of<'a>(
        cs: f64,
        n: usize,
        rows: impl IntoIterator<Item = (f64, &'a str, Result<super::SteadyState, String>)>,
        warnings: &mut Vec<String>,
    ) -> Option<BandCheck> {
        let mut out: Option<BandCheck> = None;
        let mut beyond = 0;
        for (w, name, st) in rows {
            let st = match st {
                Ok(st) => st,
                Err(why) => {
                    warnings.push(format!(
                        "the speed band's check: load case {name} at {w} rad/s failed: {why}"
                    ));
                    return None;
                }
            };
            beyond += usize::from(st.cs > cs + st.cs_error);
            if out.as_ref().is_none_or(|o| st.cs > o.max_cs) {
                out = Some(BandCheck {
                    speeds: n,
                    max_cs: st.cs,
                    max_cs_error: st.cs_error,
                    max_cs_speed_rad_s: w,
                    max_cs_case: name.to_string(),
                    beyond: 0,
                });
            }
        }
        if beyond > 0 {
            warnings.push(format!(
                "the speed band's check: {beyond} steady states inside the band swing more than mechanism.drive.cs = {cs} with the flywheel of all the cases: the band's interior needs more flywheel than its ends"
            ));
        }
        out.map(|o| BandCheck { beyond, ..o })
    }
}
