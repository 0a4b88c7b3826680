//! One crane design evaluated: steps 1 and 2 of the thesis (boom, then the four-bar
//! synthesis), the head heights over the luffing range and the constraint violations —
//! what the search's cost and the full evaluation of a design share.

use super::{CraneScene, Settings, REACH_ROUNDING};
use crate::families::crane::model::{
    level_heights_with, synthesize, Angles, Boom, Branch, CraneGeomError, Guide, HeadHeights,
    Level, PathError, Synthesis,
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
    let heights = path_heights(&synthesis, &scene.level, settings);
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

/// The heights `level` measures over the luffing range of a synthesis, Δh's error including
/// the tie pin's: its rounding (its condition, see `tie_circle`) moves the tail by at most
/// |δB| + |δb| over sin μ (μ the smallest transmission angle), the head by that over k2 and
/// the height by [`Level::gain`] times that, each extremum: Δh by twice that.
pub(super) fn path_heights(
    synthesis: &Synthesis,
    level: &Level,
    settings: &Settings,
) -> Result<HeadHeights, PathError> {
    let link = &synthesis.linkage;
    level_heights_with(
        link,
        level,
        settings.path_samples,
        settings.refine_peaks.then_some(settings.xtol),
    )
    .map(|mut h| {
        let tangency = h.min_transmission.sin().max(f64::EPSILON.sqrt());
        h.error += level.gain() * 4.0 * synthesis.guide_error / (link.k2 * tangency);
        h
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
    let boom = match scene.level {
        Level::Head => Boom::new(scene.boom_length(&angles, k), angles)?,
        level => sized_levelled(scene, angles, level, k)?,
    };
    let synthesis = synthesize(&boom, x[0], x[1])?;
    Ok((boom, synthesis))
}

/// Step 1 for the load level: its k depends on L_c (the sheave S is fixed, not scaled with
/// the boom) and the sizing rule's L_c on k, so L_c = rule(k(L_c)) is iterated from the
/// head's k until L_c moves by less than 1e-14 of itself (the rope's run-out changes k by a
/// small fraction of itself per unit change of L_c/L_c, so a few rounds suffice; 50 at most).
fn sized_levelled(
    scene: &CraneScene,
    angles: Angles,
    level: Level,
    k_head: f64,
) -> Result<Boom, CraneGeomError> {
    let mut l_c = scene.boom_length(&angles, k_head);
    for _ in 0..50 {
        let boom = Boom::levelled(l_c, angles, level)?;
        let next = scene.boom_length(&angles, boom.k);
        if (next - l_c).abs() <= 1e-14 * l_c {
            return Ok(boom);
        }
        l_c = next;
    }
    Err(CraneGeomError::Invalid {
        what: "boom length (sizing with the load level does not settle)",
        value: l_c,
    })
}
