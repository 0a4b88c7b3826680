//! The linkage as a one-degree-of-freedom machine for the drive (`crate::dynamics`): its
//! terms J, J′, G and momentum at any crank angle for a design, and ΔE at constant speed —
//! shared by the drive of the whole solve and by the scenarios of the operating envelope.

use super::file::LinkageScene;
use super::model::DriveTerms;
use super::synth as ls;
use crate::dynamics::{self, Drive, DriveError, DriveFigures, DriveSettings};
use crate::numeric::AngleMemo;

/// The drive's terms (J, J′, G and the momentum, `Linkage::drive_terms`) of `sc` with the
/// design `x` (without one, the bare linkage's) at any crank angle; `None` where it does not
/// assemble.
pub fn terms<'a>(
    sc: &'a LinkageScene,
    x: Option<&[f64]>,
) -> impl Fn(f64) -> Option<DriveTerms> + Sync + 'a {
    terms_with(sc, x, None)
}

/// The drive's terms of several scenes that differ in their speed alone, remembered by
/// angle: J, J′, G and the momentum per unit crank speed do not depend on ω (the loads are
/// tables over the angle, the weights constant), so the drive of one load case at the band's
/// ends and inside it samples its linkage once per grid angle. Only for scenes of one
/// geometry, masses, loads and design.
pub type TermsMemo = AngleMemo<Option<DriveTerms>>;

/// [`terms`], looked up in and added to `memo` where one is given.
fn terms_with<'a>(
    sc: &'a LinkageScene,
    x: Option<&[f64]>,
    memo: Option<&'a TermsMemo>,
) -> impl Fn(f64) -> Option<DriveTerms> + Sync + 'a {
    let extra = x
        .map(|x| ls::extras(&sc.counterweights, x))
        .unwrap_or_default();
    move |th: f64| {
        let at = || {
            let lk = &sc.linkage;
            lk.pose(th).ok().map(|pose| lk.drive_terms(&pose, &extra))
        };
        match memo {
            Some(m) => m.get_or(th, at),
            None => at(),
        }
    }
}

/// The one-degree-of-freedom machine (J, J′, G) of the drive's terms; not finite where the
/// linkage does not assemble (the drive then fails naming the angle).
pub fn one_dof(
    terms: &(impl Fn(f64) -> Option<DriveTerms> + Sync),
) -> impl Fn(f64) -> [f64; 3] + Sync + '_ {
    move |th| terms(th).map_or([f64::NAN; 3], |t| [t.j, t.dj, t.g])
}

/// The drive's accuracy: a load table's corners are kinks of G.
pub fn settings(sc: &LinkageScene) -> DriveSettings {
    if sc.linkage.loads().is_empty() {
        DriveSettings::default()
    } else {
        DriveSettings::for_kinks()
    }
}

/// ΔE of `sc` with the design `x` (the bare linkage's without) and its error bound: the
/// drive's own quadrature of T = ½ J′ ω² + G (`dynamics::constant_speed`), independent of the
/// engine's energy field.
pub fn delta_e(sc: &LinkageScene, x: Option<&[f64]>) -> Result<(f64, f64), String> {
    let terms = terms(sc, x);
    let c = dynamics::constant_speed(&one_dof(&terms), sc.linkage.omega(), &settings(sc))
        .map_err(|e| e.to_string())?;
    Ok((c.energy_fluctuation, c.energy_fluctuation_error))
}

/// The periodic steady state of `sc` with the design `x` on the motor of `d` with the
/// flywheel `flywheel` (`dynamics::steady_state`): what a check at a given flywheel needs,
/// without the constant-speed turn, the least flywheel or the peaks at real speed.
pub fn steady(
    sc: &LinkageScene,
    d: &Drive,
    flywheel: f64,
    x: Option<&[f64]>,
    memo: Option<&TermsMemo>,
) -> Result<dynamics::SteadyState, DriveError> {
    let terms = terms_with(sc, x, memo);
    let m = one_dof(&terms);
    dynamics::steady_state(&m, &d.motor, flywheel, sc.linkage.omega(), &settings(sc))
}

/// The drive `d` of `sc` with the design `x` (without one, the bare linkage's): ΔE, the least
/// flywheel for its Cs, the steady state with its flywheel (or the least one, or none), and
/// the shaking force at real speed, F = −(ω² Σ m r_G'' + α Σ m r_G')
/// ([`crate::families::linkage::model::Linkage::drive_terms`]).
pub fn figures(
    sc: &LinkageScene,
    d: &Drive,
    x: Option<&[f64]>,
) -> Result<DriveFigures, DriveError> {
    figures_with(sc, d, x, None)
}

/// [`figures`] with the drive's terms remembered in `memo` ([`TermsMemo`]).
pub fn figures_with(
    sc: &LinkageScene,
    d: &Drive,
    x: Option<&[f64]>,
    memo: Option<&TermsMemo>,
) -> Result<DriveFigures, DriveError> {
    let terms = terms_with(sc, x, memo);
    let figures = dynamics::drive(&one_dof(&terms), sc.linkage.omega(), d, &settings(sc))?;
    Ok(figures.with_real_speed(&d.motor, |th, w, a| {
        terms(th).map(|t| (t.momentum_rate * (w * w) + t.momentum * a).norm())
    }))
}
