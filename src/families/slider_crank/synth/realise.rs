//! From the unbalance |U| to a counterweight: its bounds, and its mass, radius and plate.

use super::scene::{CounterweightSpec, Objective, Prefer};
use crate::synth::shape::{self, Sector, ShapeGoal, ShapeOutcome, ShapeSpec};
use crate::synth::Var;

/// Resolved bounds on |U|: the unbalance range, m_min r_min ≤ |U| ≤ m_max r_max, and the
/// plate envelope's U_max.
pub fn unbalance_bounds(cw: &CounterweightSpec) -> (f64, f64) {
    let (mut lo, mut hi) = cw.unbalance.bounds();
    if let (Some(m), Some(r)) = (cw.mass, cw.radius) {
        let (m0, m1) = m.bounds();
        let (r0, r1) = r.bounds();
        lo = lo.max(m0 * r0);
        hi = hi.min(m1 * r1);
    }
    if let Some(sh) = &cw.shape {
        hi = hi.min(sh.max_unbalance());
    }
    (lo.max(0.0), hi)
}

impl super::scene::Scene {
    /// Whether nothing is free: the counterweight's direction β is fixed and its bounds
    /// (|U|, mass × radius, the plate's envelope) leave one |U|, with no balancer or joint
    /// limit to design. The solve then analyses the given counterweight (`analysed`).
    pub fn given(&self) -> bool {
        !self.joint()
            && self.counterweight.angle.fixed().is_some()
            && fixed_length(&self.counterweight)
    }
}

/// Whether the bounds of |U| ([`unbalance_bounds`]) leave one value (to 10⁻¹⁵ relative).
pub fn fixed_length(cw: &CounterweightSpec) -> bool {
    let (lo, hi) = unbalance_bounds(cw);
    hi.is_finite() && (hi - lo) <= 1e-15 * hi.max(1e-300)
}

/// The counterweight that realises |U|: its mass and centroid radius, and the plate when the
/// scene gives one (then mass and radius are the plate's, so they cannot disagree).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Realised {
    /// m_cw (kg).
    pub mass: Option<f64>,
    /// r_cw (m): the centroid radius.
    pub radius: Option<f64>,
    /// The plate (with `[design.shape]`).
    pub plate: Option<Sector>,
    /// How the plate was found, or why the envelope cannot hold it.
    pub plate_note: Option<String>,
}

impl Realised {
    /// Its inertia about the crank axis as the drive counts it, m·r² (a point mass at its
    /// centroid radius; 0 where the scene does not size it): a constant part of J.
    pub fn drive_inertia(&self) -> f64 {
        self.mass.zip(self.radius).map_or(0.0, |(m, r)| m * r * r)
    }
}

/// The counterweight realising |U| = `u` under `objective`: with a plate, the plate the
/// objective asks for (the lightest for `MinMass`, the smallest outer radius for
/// `MinRadius`, else `[design.shape] minimize`); otherwise |U| split into mass and radius.
pub fn realise(u: f64, cw: &CounterweightSpec, objective: Objective) -> Realised {
    if let Some(sh) = &cw.shape {
        let goal = match objective {
            Objective::MinMass => ShapeGoal::Mass,
            Objective::MinRadius => ShapeGoal::OuterRadius,
            _ => sh.goal,
        };
        return match shape::design(&ShapeSpec { goal, ..*sh }, u) {
            ShapeOutcome::Found { sector, method } => Realised {
                mass: Some(sector.mass_kg),
                radius: Some(sector.centroid_radius_m),
                plate: Some(sector),
                plate_note: Some(method),
            },
            ShapeOutcome::Infeasible { reason } => Realised {
                mass: None,
                radius: None,
                plate: None,
                plate_note: Some(reason),
            },
        };
    }
    let prefer = match objective {
        Objective::MinMass => Prefer::Lightest,
        Objective::MinRadius => Prefer::SmallestRadius,
        _ => cw.prefer,
    };
    let (mass, radius) = split_unbalance(u, &CounterweightSpec { prefer, ..*cw });
    Realised {
        mass,
        radius,
        plate: None,
        plate_note: None,
    }
}

/// Splits |U| into (mass, radius) by the scene's variables and preference.
pub fn split_unbalance(u: f64, cw: &CounterweightSpec) -> (Option<f64>, Option<f64>) {
    match (cw.mass, cw.radius) {
        (_, Some(Var::Fixed(r))) => (Some(if r > 0.0 { u / r } else { 0.0 }), Some(r)),
        (Some(Var::Fixed(m)), _) => (Some(m), Some(if m > 0.0 { u / m } else { 0.0 })),
        (Some(m), Some(r)) => {
            let (m0, m1) = m.bounds();
            let (r0, r1) = r.bounds();
            let r = match cw.prefer {
                Prefer::SmallestRadius => r0.max(if m1 > 0.0 { u / m1 } else { r0 }),
                Prefer::Lightest => r1.min(if m0 > 0.0 { u / m0 } else { r1 }),
            };
            (Some(if r > 0.0 { u / r } else { m0 }), Some(r))
        }
        _ => (None, None),
    }
}
