//! The full evaluation of one crane design for its result: dimensions, derived figures,
//! the thesis's checks, the path for the plots, Δh with its error and the largest load
//! moment; and the (k1, k2) landscape around a design, a diagnostic the report asks for.

use super::evaluate::{evaluate, path_heights, Evaluation};
use super::{
    is_free, Check, CraneScene, Derived, Design, Landscape, Objectives, Outcome, Positions,
    Settings, SizingRule, Status, TiePinLimit, Var, Vars,
};
use crate::families::crane::model::{
    level_load_moment, Angles, Branch, Guide, HeadHeights, HoistRope, Level, Linkage,
};
use crate::geom::P2;
use std::f64::consts::FRAC_PI_2;

/// Tolerance (rad) of the Brent refinement of the largest load moment: its value error
/// ½|M''|·tol² is ~1e-18 of |M| per rad², far below the moment's finite-difference error,
/// which is what `max_load_moment_error_nm` carries.
const MOMENT_PEAK_XTOL: f64 = 1e-9;

/// The jib head is at equal heights at both extremes by construction (the choice of k); the
/// check passes when they differ by less than this fraction of L_c (the rounding of k and of
/// the two head positions is a few ε·L_c).
const EQUAL_HEIGHTS_TOL: f64 = 1e-9;

/// A stated relative error of Δh above this draws the digits-left warning (well-conditioned
/// designs state ~1e-10 or less).
const DIGITS_WARNING: f64 = 1e-6;

/// The load's unbalanced moment about A at φ, M_A = W dy_C/dφ, and its error (N·m): from
/// the statics of a weightless boom system with the load W at the jib head (thesis §2.2,
/// M_Ah = N L_c sin α; exact up to the rounding and conditioning it states) when the tie is a
/// circle, by the finite difference [`load_moment`] for the straight-guide limit.
///
/// With an inclined hoist rope the load hangs on it: M_A = W dy_L/dφ, the rope's pull on the
/// jib head included (statics with [`Loads::rope`]).
fn load_moment_at(
    link: &Linkage,
    rope: Option<HoistRope>,
    w: f64,
    phi: f64,
    h: f64,
) -> Option<(f64, f64)> {
    use crate::families::crane::statics::{statics, Loads, SelfWeight};
    if let Guide::Circle { .. } = link.guide {
        let pose = link.pose(phi)?;
        let loads = Loads {
            load_mass: w / crate::units::STANDARD_GRAVITY,
            rope,
            ..Loads::default()
        };
        let s = statics(link, phi, &pose, &SelfWeight::NONE, &loads)?;
        return Some((s.drive_torque, s.drive_torque_error));
    }
    let level = rope.map_or(Level::Head, Level::Load);
    level_load_moment(link, &level, w, phi, h)
}

/// Full evaluation of one design for the result.
pub(super) fn report(
    scene: &CraneScene,
    settings: &Settings,
    x: &[f64; 6],
    warnings: &mut Vec<String>,
) -> Outcome {
    let mut out = empty(scene, x);
    let ev = match evaluate(scene, x, settings) {
        Ok(ev) => ev,
        Err(e) => {
            out.status = Status::NoGeometry;
            warnings.push(format!("no crane geometry for this design: {e}"));
            return out;
        }
    };
    dimensions(scene, &ev, &mut out, warnings);
    let tol = settings.constraint_tol * scene.length_scale();
    thesis_checks(scene, &ev, tol, &mut out);
    angle_warnings(&ev.boom.angles, warnings);
    if let Branch::Defect(sides) = ev.synthesis.branch {
        out.status = Status::BranchDefect;
        warnings.push(format!(
            "branch defect: the design positions lie on different assembly branches ({sides:?}); the linkage cannot \
             luff through all three without being taken apart. The path below follows the branch of position 1."
        ));
    }
    path(&ev.synthesis.linkage, settings.plot_points, &mut out);
    match &ev.heights {
        Ok(hh) => heights(scene, settings, &ev, hh, &mut out, warnings),
        Err(e) => {
            if out.status != Status::BranchDefect {
                out.status = Status::CannotAssemble;
            }
            warnings.push(format!("delta h not available: {e}"));
        }
    }
    let feasible = ev.violation() <= tol && ev.tie_pin_violation.is_finite();
    if !feasible && out.status == Status::Evaluated {
        out.status = Status::Infeasible;
    }
    if scene.vars().iter().all(|v| !is_free(v)) && out.status == Status::Infeasible {
        // A given design that misses a check is still an evaluated design: the checks say which.
        out.status = Status::Evaluated;
        warnings.push("the given design fails at least one check (see checks)".into());
    }
    out
}

/// The outcome of the design x before it is evaluated: its variables, nothing else.
fn empty(scene: &CraneScene, x: &[f64; 6]) -> Outcome {
    Outcome {
        status: Status::Evaluated,
        sizing_rule: scene.sizing.describe(),
        design: Design {
            vars: Vars::of(x),
            phi_max_rad: FRAC_PI_2 - x[3],
            boom_length_m: None,
            jib_length_m: None,
            jib_tail_m: None,
            tie_pin_x_m: None,
            tie_pin_y_m: None,
            tie_length_m: None,
        },
        objectives: Objectives::default(),
        errors: Objectives::default(),
        derived: Derived::default(),
        checks: Vec::new(),
        warnings: Vec::new(),
        method: String::new(),
        evaluations: 1,
        positions: None,
        path: Vec::new(),
        tail_path: Vec::new(),
        path_phi_rad: Vec::new(),
        basins: Vec::new(),
        x: *x,
        search: None,
    }
}

/// A point as `[x, y]`.
fn p2(p: P2) -> [f64; 2] {
    [p.x, p.y]
}

/// The boom, jib and tie dimensions, the reaches and heights, the design positions.
fn dimensions(scene: &CraneScene, ev: &Evaluation, out: &mut Outcome, warnings: &mut Vec<String>) {
    let (boom, syn) = (&ev.boom, &ev.synthesis);
    let angles = boom.angles;
    out.design.boom_length_m = Some(boom.l_c);
    out.design.jib_length_m = Some(boom.l_v());
    out.design.jib_tail_m = Some(syn.linkage.a);
    let lc_min_reach = CraneScene {
        sizing: SizingRule::MinReach,
        ..scene.clone()
    }
    .boom_length(&angles, boom.k);
    out.derived.k = Some(boom.k);
    out.derived.boom_length_min_reach_rule_m = Some(lc_min_reach);
    out.derived.boom_length_max_reach_rule_m =
        Some((scene.reach_max - scene.foot_offset) / angles.unit_reach_max(boom.k));
    let h1 = boom.head_height();
    out.derived.head_height_m = Some(h1);
    out.derived.head_height_min_reach_m = Some(boom.c3().y);
    out.derived.head_height_above_rail_m = Some(h1 + scene.foot_height);
    out.derived.reach_max_m = Some(scene.foot_offset + boom.l_c * angles.unit_reach_max(boom.k));
    out.derived.reach_min_m = Some(scene.foot_offset + boom.l_c * angles.unit_reach_min(boom.k));
    out.derived.phi2_rad = Some(syn.positions.phi[1]);
    out.derived.allowed_delta_h_m = Some(scene.allowed_delta_h());
    out.positions = Some(Positions {
        phi_rad: syn.positions.phi,
        c: syn.positions.c.map(p2),
        d: syn.positions.d.map(p2),
        e: syn.positions.e.map(p2),
        tie_pin: match syn.guide {
            Guide::Circle { centre, .. } => Some(p2(centre)),
            Guide::Line { .. } => None,
        },
    });
    match syn.guide {
        Guide::Circle { centre, radius } => {
            out.design.tie_pin_x_m = Some(centre.x);
            out.design.tie_pin_y_m = Some(centre.y);
            out.design.tie_length_m = Some(radius);
            out.derived.tie_pin_distance_m = Some(centre.norm());
            out.derived.tie_pin_error_m = Some(syn.guide_error);
        }
        Guide::Line { dir, .. } => {
            warnings.push(
                "E1, E2, E3 are collinear: the tie pin is at infinity; the tail runs on the straight-guide limit \
                 (tie_pin_* and tie_length_m omitted)"
                    .into(),
            );
            out.derived.guide_angle_rad = Some(dir.y.atan2(dir.x));
        }
    }
    out.derived.tie_pin_violation_m = Some(finite_or_max(ev.tie_pin_violation));
}

/// A violation as a number: the straight-guide limit's infinite one as `f64::MAX`.
fn finite_or_max(v: f64) -> f64 {
    if v.is_finite() {
        v
    } else {
        f64::MAX
    }
}

/// A thesis check, pass or fail.
fn check(out: &mut Outcome, name: &str, value: f64, limit: f64, pass: bool, note: &str) {
    out.checks.push(Check {
        name: name.into(),
        value,
        limit,
        pass,
        note: note.into(),
    });
}

/// The thesis's checks of the geometry: equal head heights, the reaches, the head height,
/// the jib's attitude, the tie-pin limit (violations within `tol` pass).
fn thesis_checks(scene: &CraneScene, ev: &Evaluation, tol: f64, out: &mut Outcome) {
    let boom = &ev.boom;
    let angles = boom.angles;
    let (h1, c3) = (boom.head_height(), boom.c3());
    let r_max = scene.foot_offset + boom.l_c * angles.unit_reach_max(boom.k);
    let r_min = scene.foot_offset + boom.l_c * angles.unit_reach_min(boom.k);
    let equal_tol = EQUAL_HEIGHTS_TOL * boom.l_c;
    match boom.level {
        Level::Head => {
            let equal = (c3.y - h1).abs();
            check(
                out,
                "equal_head_heights",
                equal,
                equal_tol,
                equal <= equal_tol,
                "|y_C3 - y_C1| (m)",
            );
        }
        level @ Level::Load(_) => {
            let c = ev.synthesis.positions.c;
            let y = c.map(|ci| level.height(ci));
            let equal = (y[1] - y[0]).abs().max((y[2] - y[0]).abs());
            check(
                out,
                "level_load_at_precision_points",
                equal,
                equal_tol,
                equal <= equal_tol,
                "max |y_L(C_i) - y_L(C1)|, the load's heights at the three precision points (m)",
            );
            out.derived.h2_m = Some(c[1].y - c[0].y);
            out.derived.h3_m = Some(c[2].y - c[0].y);
        }
    }
    check(
        out,
        "reach_max",
        r_max,
        scene.reach_max,
        ev.reach_max_violation <= tol,
        "reach at phi_min from the slewing axis >= R_max (m)",
    );
    check(
        out,
        "reach_min",
        r_min,
        scene.reach_min,
        ev.reach_min_violation <= tol,
        "reach at phi_max from the slewing axis <= R_min (m)",
    );
    check(
        out,
        "head_height",
        h1 + scene.foot_height,
        scene.lift_height,
        ev.height_violation <= tol,
        "jib head above the rail at the extremes >= H (m)",
    );
    check(
        out,
        "jib_not_horizontal_at_max_reach",
        angles.gamma3,
        0.0,
        angles.gamma3 > 0.0,
        "gamma3 > 0 (rad)",
    );
    check(
        out,
        "jib_not_vertical_at_min_reach",
        angles.gamma2,
        0.0,
        angles.gamma2 > 0.0,
        "gamma2 > 0 (rad)",
    );
    if scene.tie_pin != TiePinLimit::default() {
        check(
            out,
            "tie_pin_limit",
            finite_or_max(ev.tie_pin_violation),
            0.0,
            ev.tie_pin_violation <= tol,
            "violation of the tie-pin limit (m)",
        );
    }
}

/// A warning for each step-1 angle outside the thesis's recommended range.
fn angle_warnings(angles: &Angles, warnings: &mut Vec<String>) {
    let in_range =
        |v: f64, a: f64, b: f64| v >= a.to_radians() - 1e-12 && v <= b.to_radians() + 1e-12;
    for (name, v, a, b) in [
        ("phi_min", angles.phi_min, 30.0, 45.0),
        ("gamma1", angles.gamma1, 5.0, 15.0),
        ("gamma2", angles.gamma2, 5.0, 10.0),
        ("gamma3", angles.gamma3, 10.0, 25.0),
    ] {
        if !in_range(v, a, b) {
            warnings.push(format!(
                "{name} = {:.3} deg is outside the thesis's recommended {a}-{b} deg",
                v.to_degrees()
            ));
        }
    }
}

/// The path for the plots: `m` boom angles over the range, on the followed branch, the
/// points that assemble.
fn path(l: &Linkage, m: usize, out: &mut Outcome) {
    let [p0, p1] = l.phi_range;
    for i in 0..m {
        let phi = p0 + (p1 - p0) * i as f64 / (m - 1) as f64;
        if let Some(pose) = l.pose(phi) {
            out.path.push(p2(pose.c));
            out.tail_path.push(p2(pose.e));
            out.path_phi_rad.push(phi);
        }
    }
}

/// Δh with its error and conditioning, the allowed-Δh check, the extremes of the head
/// height, the transmission angle and the largest load moment.
fn heights(
    scene: &CraneScene,
    settings: &Settings,
    ev: &Evaluation,
    hh: &HeadHeights,
    out: &mut Outcome,
    warnings: &mut Vec<String>,
) {
    let syn = &ev.synthesis;
    out.evaluations = 1;
    // The head's own heights: the levelled ones, or for the load level a second pass.
    let head = match scene.level {
        Level::Head => Ok(*hh),
        Level::Load(_) => path_heights(syn, &Level::Head, settings),
    };
    let (what, name) = match scene.level {
        Level::Head => ("delta h", "delta_h_allowed"),
        Level::Load(_) => ("the load's delta h", "load_delta_h_allowed"),
    };
    if out.status != Status::BranchDefect {
        if let Level::Load(_) = scene.level {
            out.objectives.load_delta_h_m = Some(hh.delta_h);
            out.errors.load_delta_h_m = Some(hh.error);
        }
        if let Ok(h) = &head {
            out.objectives.delta_h_m = Some(h.delta_h);
            out.errors.delta_h_m = Some(h.error);
        }
        let rel = hh.error / hh.delta_h.abs();
        if rel >= 1.0 {
            out.status = Status::Degenerate;
            warnings.push(format!(
                "ill-conditioned design: the rounding bound of {what} ({:.1e} m) exceeds it; no \
                 digit is certain (smallest angle of the triangle E1 E2 E3 {:.2e} rad, tie-pin error bound {:.1e} m)",
                hh.error, syn.min_angle, syn.guide_error
            ));
        } else if rel > DIGITS_WARNING {
            warnings.push(format!(
                "ill-conditioned design: {what} is good to {:.1e} m, about {:.0} significant digits (smallest \
                 angle of the triangle E1 E2 E3 {:.2e} rad, tie-pin error bound {:.1e} m)",
                hh.error,
                (-rel.log10()).floor(),
                syn.min_angle,
                syn.guide_error
            ));
        }
        check(
            out,
            name,
            hh.delta_h,
            scene.allowed_delta_h(),
            hh.delta_h <= scene.allowed_delta_h(),
            &format!("{what} <= [delta h] (0.1 H unless given) (m)"),
        );
    }
    if let Ok(h) = &head {
        out.derived.head_y_max_m = Some(h.y_max);
        out.derived.head_y_min_m = Some(h.y_min);
        out.derived.phi_at_head_max_rad = Some(h.phi_at_max);
        out.derived.phi_at_head_min_rad = Some(h.phi_at_min);
    }
    out.derived.min_transmission_angle_rad = Some(hh.min_transmission);
    out.derived.phi_at_min_transmission_rad = Some(hh.phi_at_min_transmission);
    if hh.min_transmission < 10f64.to_radians() {
        warnings.push(format!(
            "the tie and the jib tail come within {:.2} deg of alignment (at phi = {:.2} deg): the linkage is \
             near its singular pose",
            hh.min_transmission.to_degrees(),
            hh.phi_at_min_transmission.to_degrees()
        ));
    }
    if let Some(q) = scene.load_mass {
        let rope = scene.balance.as_ref().and_then(|b| b.rope);
        max_load_moment(&syn.linkage, rope, q * 9.80665, settings, out);
    }
}

/// The largest |load moment| of the load weight `w` over the luffing range: sampled at
/// `path_samples` + 1 angles, the largest refined by Brent's fmin (hand-written,
/// [`crate::numeric::brent_max`]) around its sample. With a tie, the moment from the statics
/// (closed form, its rounding and conditioning bounded); a straight guide by the finite
/// difference.
fn max_load_moment(
    l: &Linkage,
    rope: Option<HoistRope>,
    w: f64,
    settings: &Settings,
    out: &mut Outcome,
) {
    let h = settings.moment_step;
    let [p0, p1] = l.phi_range;
    let mut worst = (0.0f64, 0.0f64, p0);
    let n = settings.path_samples;
    for i in 0..=n {
        let phi = p0 + (p1 - p0) * i as f64 / n as f64;
        if let Some((mm, e)) = load_moment_at(l, rope, w, phi, h) {
            if mm.abs() > worst.0.abs() {
                worst = (mm, e, phi);
            }
        }
    }
    // Refine the largest |M| by Brent around the best sample.
    let dphi = (p1 - p0) / n as f64;
    let f = |phi: f64| load_moment_at(l, rope, w, phi, h).map_or(0.0, |(mm, _)| mm.abs());
    if let Ok(e) = crate::numeric::brent_max(
        f,
        (worst.2 - dphi).max(p0),
        (worst.2 + dphi).min(p1),
        MOMENT_PEAK_XTOL,
    ) {
        let err = load_moment_at(l, rope, w, e.x, h).map_or(worst.1, |(_, er)| er);
        out.derived.max_load_moment_nm = Some(e.fx);
        out.derived.max_load_moment_error_nm = Some(err);
        out.derived.phi_at_max_load_moment_rad = Some(e.x);
    }
}

/// Δh over a (k1, k2) grid: the free bounds of k1 and k2, or [0.05, 0.95] × [0.2, 1.0] for a
/// fixed one; the other variables at `x`. `None` when the settings ask for no landscape.
/// A diagnostic of the design, not part of the solve: `landscape_k1`·`landscape_k2` full
/// evaluations (41 × 41 by default, ~99 % of an analysis), so the report computes it only
/// when a result's files are written.
pub fn landscape(scene: &CraneScene, settings: &Settings, x: &[f64; 6]) -> Option<Landscape> {
    let (n1, n2) = (settings.landscape_k1, settings.landscape_k2);
    if n1 == 0 {
        return None;
    }
    let range = |v: &Var, d: (f64, f64)| if is_free(v) { v.bounds() } else { d };
    let (a1, b1) = range(&scene.k1, (0.05, 0.95));
    let (a2, b2) = range(&scene.k2, (0.2, 1.0));
    let k1: Vec<f64> = (0..n1)
        .map(|i| a1 + (b1 - a1) * i as f64 / (n1 - 1) as f64)
        .collect();
    let k2: Vec<f64> = (0..n2)
        .map(|j| a2 + (b2 - a2) * j as f64 / (n2 - 1) as f64)
        .collect();
    let mut dh = vec![vec![None; n1]; n2];
    let mut viol = vec![vec![None; n1]; n2];
    for (j, &v2) in k2.iter().enumerate() {
        for (i, &v1) in k1.iter().enumerate() {
            let mut y = *x;
            y[0] = v1;
            y[1] = v2;
            if let Ok(ev) = evaluate(scene, &y, settings) {
                if let Some(d) = ev.delta_h() {
                    dh[j][i] = Some(d);
                    viol[j][i] = ev
                        .tie_pin_violation
                        .is_finite()
                        .then_some(ev.tie_pin_violation);
                }
            }
        }
    }
    Some(Landscape {
        k1,
        k2,
        delta_h_m: dh,
        tie_pin_violation_m: viol,
        optimum: [x[0], x[1]],
    })
}
