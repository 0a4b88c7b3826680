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
