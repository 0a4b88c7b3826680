//! Validation of a problem and a goal, and of the fields' values, with errors that name the
//! part of the problem at fault.

use super::{AffineField, AffineValue, Goal, MinimaxError, Problem};

pub(super) fn bad(what: impl Into<String>, message: impl Into<String>) -> MinimaxError {
    MinimaxError::Problem {
        what: what.into(),
        message: message.into(),
    }
}

pub(super) fn check_finite(
    f: &dyn AffineField,
    theta: f64,
    v: &AffineValue,
) -> Result<(), MinimaxError> {
    // Each entry compared on its own (a sum of y·0 over the entries, NaN for any
    // non-finite y, was one chain of dependent additions: slower on every grid value).
    if v.b.iter().chain(v.a.iter()).all(|a| a.is_finite()) {
        Ok(())
    } else {
        Err(MinimaxError::NotFinite {
            field: f.name().to_string(),
            theta,
        })
    }
}

pub(super) fn validate_structure(pb: &Problem) -> Result<(), MinimaxError> {
    let n = pb.n();
    if n == 0 {
        return Err(bad(
            "counterweights",
            "no design variable (no counterweight, no extra variable)",
        ));
    }
    if pb.fields.is_empty() {
        return Err(bad("fields", "no field"));
    }
    for (f, field) in pb.fields.iter().enumerate() {
        if !matches!(field.dim(), 1 | 2) {
            return Err(bad(
                format!("fields[{f}].dim"),
                format!(
                    "must be 1 or 2, got {} (field `{}`)",
                    field.dim(),
                    field.name()
                ),
            ));
        }
    }
    for (j, c) in pb.counterweights.iter().enumerate() {
        let w = |k: &str| format!("counterweights[{j}].{k}");
        if !(c.m_max.is_finite() && c.m_max > 0.0) {
            return Err(bad(
                w("m_max"),
                format!("must be finite and > 0 kg, got {}", c.m_max),
            ));
        }
        for (k, v) in [
            ("r_max", c.r_max),
            ("inertia_max", c.inertia_max),
            ("envelope", c.envelope),
        ] {
            if !(v > 0.0) {
                return Err(bad(
                    w(k),
                    format!("must be > 0 (infinite: no limit), got {v}"),
                ));
            }
        }
        if !(c.inertia_max.is_finite() || c.envelope.is_finite()) {
            return Err(bad(
                w("inertia_max"),
                "the inertia must be bounded: give inertia_max or an envelope radius",
            ));
        }
        if let Some(sigma) = c.plate {
            let most = sigma * std::f64::consts::PI * c.envelope * c.envelope;
            if !(sigma.is_finite() && sigma > 0.0 && c.envelope.is_finite()) {
                return Err(bad(
                    w("plate"),
                    format!("a plate needs a finite areal density > 0 and a finite envelope, got σ = {sigma} kg/m², envelope {} m", c.envelope),
                ));
            }
            if !(c.m_max <= most * (1.0 + 1e-12)) {
                return Err(bad(
                    w("m_max"),
                    format!(
                        "{} kg is more than the plate's whole envelope holds, σπρ² = {most} kg",
                        c.m_max
                    ),
                ));
            }
        }
        if let Some((lo, hi)) = c.sector {
            if !(lo.is_finite()
                && hi.is_finite()
                && hi >= lo
                && hi - lo <= std::f64::consts::PI + 1e-12)
            {
                return Err(bad(
                    w("sector"),
                    format!("must be [lo, hi] with 0 ≤ hi − lo ≤ π, got [{lo}, {hi}]"),
                ));
            }
        }
    }
    for (e, &(lo, hi)) in pb.extra.iter().enumerate() {
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return Err(bad(
                format!("extra[{e}]"),
                format!("bounds must be lo ≤ hi, got [{lo}, {hi}]"),
            ));
        }
    }
    for (k, lc) in pb.linear.iter().enumerate() {
        if lc.coeffs.is_empty() || lc.coeffs.iter().all(|c| c.1 == 0.0) {
            return Err(bad(format!("linear[{k}]"), "has no nonzero coefficient"));
        }
        for &(j, c) in &lc.coeffs {
            if j >= n || !c.is_finite() {
                return Err(bad(
                    format!("linear[{k}]"),
                    format!(
                        "coefficient ({j}, {c}): the variable must be < {n} and the value finite"
                    ),
                ));
            }
        }
        if !lc.rhs.is_finite() {
            return Err(bad(format!("linear[{k}].rhs"), "must be finite"));
        }
    }
    validate_goal(pb, &pb.goal, &pb.limits)
}

pub(super) fn validate_goal(
    pb: &Problem,
    goal: &Goal,
    limits: &[(usize, f64)],
) -> Result<(), MinimaxError> {
    let nf = pb.fields.len();
    match goal {
        Goal::MinPeak(list) => {
            if list.is_empty() {
                return Err(bad("goal", "a peak goal needs at least one field"));
            }
            for (k, &(f, w)) in list.iter().enumerate() {
                if f >= nf {
                    return Err(bad(
                        format!("goal[{k}]"),
                        format!("field {f} does not exist ({nf} fields)"),
                    ));
                }
                if !(w.is_finite() && w > 0.0) {
                    return Err(bad(
                        format!("goal[{k}]"),
                        format!("weight must be finite and > 0, got {w}"),
                    ));
                }
                if list[..k].iter().any(|p| p.0 == f) {
                    return Err(bad(
                        format!("goal[{k}]"),
                        format!("field {f} is listed twice"),
                    ));
                }
            }
        }
        Goal::MinRms(f) => {
            if *f >= nf {
                return Err(bad(
                    "goal",
                    format!("field {f} does not exist ({nf} fields)"),
                ));
            }
        }
        Goal::MinMass => {
            if pb.counterweights.is_empty() {
                return Err(bad("goal", "minimum mass needs a counterweight"));
            }
        }
    }
    for (k, &(f, e)) in limits.iter().enumerate() {
        if f >= nf {
            return Err(bad(
                format!("limits[{k}]"),
                format!("field {f} does not exist ({nf} fields)"),
            ));
        }
        if !(e.is_finite() && e >= 0.0) {
            return Err(bad(
                format!("limits[{k}]"),
                format!("ε must be finite and ≥ 0, got {e}"),
            ));
        }
    }
    Ok(())
}
