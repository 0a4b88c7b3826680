//! The textbooks' and the designer's own inputs of a slider-crank file: the rule "balance the
//! revolving masses and a fraction of the reciprocating masses"
//! (`design.reciprocating_fraction`), the crank angles a book quotes its forces at
//! (`objective.evaluate_at`) and a reference counterweight to compare with
//! (`[design.reference]`), read and checked (issue 34). Their keys are documented in
//! `docs/problem-files.md`.

use crate::families::slider_crank::model::SliderCrank;
use crate::problem::positive;
use crate::problem::FieldError;
use crate::synth::Var;
use crate::units::{Angle, Length, Mass, Qty};
use serde::Deserialize;
use std::f64::consts::{PI, TAU};

/// Most angles of `objective.evaluate_at`.
pub const MAX_EVALUATE_AT: usize = 360;

/// `design.reciprocating_fraction` = c: the textbook counterweight U = −(m_tq + c·m_ct)·R,
/// |U| and β = 180° fixed; the mass or the radius (not both) may be given, the other follows.
/// `given` lists the `[design]` keys that contradict the rule, each with whether the file gives
/// it.
pub fn fraction_rule(
    c: f64,
    given: &[(bool, &str)],
    mech: &SliderCrank,
    mass: Option<Var>,
    radius: Option<Var>,
) -> Result<(Var, Var, Option<Var>, Option<Var>), FieldError> {
    const F: &str = "design.reciprocating_fraction";
    if !(0.0..=1.0).contains(&c) {
        return Err(FieldError::new(
            F,
            format!("got {c}; allowed: 0 ≤ c ≤ 1 (the fraction of the reciprocating mass balanced, dimensionless)"),
        ));
    }
    if let Some((_, f)) = given.iter().find(|(on, _)| *on) {
        return Err(FieldError::new(
            *f,
            format!("given together with {F}, which fixes the counterweight's unbalance and angle; give at most its radius or its mass"),
        ));
    }
    let u = (mech.m_rot() + c * mech.m_rec()) * mech.r;
    let u_var = Var::Fixed(u);
    for (v, f) in [(mass, "design.mass"), (radius, "design.radius")] {
        if let Some(v) = v.filter(|v| v.fixed().is_none()) {
            return Err(FieldError::new(
                f,
                format!("a range {:?} with {F}; allowed: a fixed value (the other follows from |U| = {u} kg·m)", v.bounds()),
            ));
        }
    }
    Ok((u_var, Var::Fixed(PI), mass, radius))
}

/// `objective.evaluate_at`: at most [`MAX_EVALUATE_AT`] crank angles, each within one turn.
pub fn resolve_evaluate_at(angles: &[Qty<Angle>]) -> Result<Vec<f64>, FieldError> {
    if angles.len() > MAX_EVALUATE_AT {
        return Err(FieldError::new(
            "objective.evaluate_at",
            format!(
                "{} angles; allowed: at most {MAX_EVALUATE_AT}",
                angles.len()
            ),
        ));
    }
    angles
        .iter()
        .map(|q| {
            let a = q.si();
            if (-TAU..=TAU).contains(&a) {
                Ok(a)
            } else {
                Err(FieldError::new(
                    "objective.evaluate_at",
                    format!("{a} rad; allowed: within one turn either way (−360° to 360°)"),
                ))
            }
        })
        .collect()
}

/// `[design.reference]`: a counterweight to compare with — its mass at a lever radius, at an
/// angle from the crank line (default 180°: opposite the pin).
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReferenceRaw {
    /// Its mass.
    pub counterweight_mass: Qty<Mass>,
    /// Where its mass sits (default: `design.radius` when that is fixed).
    pub lever_radius: Option<Qty<Length>>,
    /// β from the crank line (default 180°).
    pub angle: Option<Qty<Angle>>,
}

/// `[design.reference]`: its unbalance U = m·r·(cos β, sin β), r the lever radius (or the
/// fixed `design.radius`).
pub fn resolve_reference(
    reference: Option<&ReferenceRaw>,
    radius: Option<Var>,
) -> Result<Option<[f64; 2]>, FieldError> {
    let Some(rf) = reference else {
        return Ok(None);
    };
    let m = positive(
        "design.reference.counterweight_mass",
        rf.counterweight_mass.si(),
    )?;
    let r = match rf.lever_radius {
        Some(q) => positive("design.reference.lever_radius", q.si())?,
        None => radius.and_then(|r| r.fixed()).ok_or_else(|| {
            FieldError::new(
                "design.reference.lever_radius",
                "missing: the reference counterweight needs its lever radius (or design.radius as a fixed value)",
            )
        })?,
    };
    let b = rf.angle.map_or(PI, |q| q.si());
    Ok(Some([m * r * b.cos(), m * r * b.sin()]))
}
