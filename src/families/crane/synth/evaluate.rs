//! One crane design evaluated: steps 1 and 2 of the thesis (boom, then the four-bar
//! synthesis), the head heights over the luffing range and the constraint violations —
//! what the search's cost and the full evaluation of a design share.

use super::{CraneScene, Settings, REACH_ROUNDING};
use crate::families::crane::model::{
    head_heights_with, synthesize, Angles, Boom, Branch, CraneGeomError, Guide, HeadHeights,
    PathError, Synthesis,
};

/// One design point evaluated: boom, synthesis, heights and constraint violations.
#[derive(Debug, Clone)]
pub struct Evaluation {
    /// Step 1.
    pub boom: Boom,
    /// Step 2.
    pub synthesis: Synthesis,
    /// Δh and the extrema, or why the path fails.
    pub heights: Result<HeadHeights, PathError>,
    /// Tie-pin violation (m); infinite for the straight-guide limit.
    pub tie_pin_violation: f64,
    /// Shortfall of the maximum reach (m, 0 when met).
    pub reach_max_violation: f64,
    /// Excess of the minimum reach (m, 0 when met).
    pub reach_min_violation: f64,
    /// Shortfall of the head height (m, 0 when met).
    pub height_violation: f64,
}

impl Evaluation {
    /// Sum of the finite constraint violations (m).
    pub fn violation(&self) -> f64 {
        self.tie_pin_violation
            + self.reach_max_violation
            + self.reach_min_violation
            + self.height_violation
    }

    /// Δh if the linkage is valid (no branch defect, assembles over the range).
    pub fn delta_h(&self) -> Option<f64> {
        match (&self.synthesis.branch, &self.heights) {
            (Branch::Consistent(_), Ok(h)) => Some(h.delta_h),
            _ => None,
        }
    }
}

/// Evaluate the design x = (k1, k2, φ_min, γ1, γ2, γ3) of a scene.
pub fn evaluate(
    scene: &CraneScene,
    x: &[f64; 6],
    settings: &Settings,
) -> Result<Evaluation, CraneGeomError> {
    let (boom, synthesis) = build(scene, x)?;
    let (angles, k) = (boom.angles, boom.k);
    // The tie pin's rounding (its condition, see `tie_circle`) moves the tail by at most
    // |δB| + |δb| over sin μ (μ the smallest transmission angle) and the head by that over
    // k2, each extremum: Δh by twice that.
    let heights = head_heights_with(
        &synthesis.linkage,
        settings.path_samples,
        settings.refine_peaks.then_some(settings.xtol),
    )
    .map(|mut h| {
        let tangency = h.min_transmission.sin().max(f64::EPSILON.sqrt());
        h.error += 4.0 * synthesis.guide_error / (x[1] * tangency);
        h
    });
    let tie_pin_violation = match synthesis.guide {
        Guide::Circle { centre, .. } => scene.tie_pin.violation(centre),
        Guide::Line { .. } if scene.tie_pin.is_bounded() => f64::INFINITY,
        Guide::Line { .. } => 0.0,
    };
    let r_max = boom.l_c * angles.unit_reach_max(k);
    let r_min = boom.l_c * angles.unit_reach_min(k);
    let tol = REACH_ROUNDING * scene.length_scale();
    let pos = |v: f64| if v > tol { v } else { 0.0 };
    Ok(Evaluation {
        boom,
        synthesis,
        heights,
        tie_pin_violation,
        reach_max_violation: pos(scene.reach_max - scene.foot_offset - r_max),
        reach_min_violation: pos(r_min - (scene.reach_min - scene.foot_offset)),
        height_violation: pos(scene.lift_height - scene.foot_height - boom.head_height()),
    })
}

/// Boom and synthesis of the design x (steps 1 and 2).
pub(crate) fn build(scene: &CraneScene, x: &[f64; 6]) -> Result<(Boom, Synthesis), CraneGeomError> {
    let angles = Angles {
        phi_min: x[2],
        gamma1: x[3],
        gamma2: x[4],
        gamma3: x[5],
    };
    let k = Boom::new(1.0, angles)?.k;
    let boom = Boom::new(scene.boom_length(&angles, k), angles)?;
    let synthesis = synthesize(&boom, x[0], x[1])?;
    Ok((boom, synthesis))
}
