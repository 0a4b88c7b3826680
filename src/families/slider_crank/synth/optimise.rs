//! The optimiser: maps the scene onto the convex engine [`crate::synth::counterweight`]
//! (the minimax or RMS of the force or torque, the least |U| under limits), with its warm
//! start and the 1-D search where |U| is fixed; a joint design goes to `joint.rs`.

use super::fields::{Columns, Grid, Normalised};
use super::joint::optimise_joint;
use super::outcome::Optimum;
use super::realise::{fixed_length, unbalance_bounds};
use super::scene::{check, Objective, Scene, SolveError};
use crate::families::slider_crank::model::rot;
use crate::geom::P2;
use crate::numeric::{brent_max, periodic_peak, periodic_rms};
use crate::synth::counterweight::{self as cw, Affine, Direction, Field, Goal, Problem, Status};

/// Finds the counterweight: the convex solve and its exchange refinement (the part the
/// benchmark times), without the report figures and baselines.
pub fn optimise(scene: &Scene) -> Result<Optimum, SolveError> {
    check(scene)?;
    // A joint design scans its own fields (per scenario): the grid would go unused.
    if joint_design(scene, scene.objective) {
        return optimise_joint(
            scene,
            scene.objective,
            scene.max_peak_force,
            scene.max_peak_torque,
        );
    }
    optimise_with(
        scene,
        scene.objective,
        scene.max_peak_force,
        scene.max_peak_torque,
        &Grid::new(
            scene,
            scene.resolved_settings().scan_samples,
            if needs_torque(scene.objective, scene.max_peak_torque) {
                Columns::All
            } else {
                Columns::Force
            },
        ),
    )
}

/// Whether the minimax of `objective` under these limits has the drive torque as a field
/// (its objective or a limit), so needs the torque on the scan grid.
pub(super) fn needs_torque(objective: Objective, max_torque: Option<f64>) -> bool {
    objective == Objective::MinPeakTorque || max_torque.is_some()
}

/// Whether the scene's design for `objective` is the joint one of `joint.rs` (balancers, a
/// moment or main-bearing limit, the energy fluctuation or an operating envelope), which
/// builds its own fields and grids, rather than the counterweight engine's on [`Grid`].
fn joint_design(scene: &Scene, objective: Objective) -> bool {
    let joint =
        scene.joint() || objective == Objective::MinEnergyFluctuation || !scene.envelope.is_empty();
    joint && !scene.given()
}

/// [`optimise`] with the objective and limits given explicitly (the Pareto front solves the
/// scene again with other ones). A scene with balancers, a moment or a main-bearing limit
/// goes to the joint design; otherwise the counterweight is analysed (all fixed), searched
/// on its circle (|U| fixed, β free) or found by the convex engine ([`convex_optimum`]).
pub(super) fn optimise_with(
    scene: &Scene,
    objective: Objective,
    max_force: Option<f64>,
    max_torque: Option<f64>,
    grid: &Grid,
) -> Result<Optimum, SolveError> {
    if joint_design(scene, objective) {
        return optimise_joint(scene, objective, max_force, max_torque);
    }
    // The caller has run `check` (the grid needed it).
    let nf = Normalised::new(scene);
    let u_ref = nf.u_ref;
    let u_lo = unbalance_bounds(&scene.counterweight).0;
    let mut warnings = Vec::new();

    let cwspec = &scene.counterweight;
    let fixed_len = fixed_length(&scene.counterweight);
    let found = if scene.given() {
        // Everything fixed: an analysis (the solve claims `analysed`).
        let beta = cwspec.angle.fixed().unwrap_or(0.0);
        Found {
            status: Status::Optimal,
            u: P2::new(beta.cos(), beta.sin()) * u_lo,
            gap: 0.0,
            method: "analysis of the given counterweight (no free design variable)".to_string(),
            rounds: 0,
        }
    } else if fixed_len && full_circle(scene) {
        // |U| fixed, direction free: a circle, not convex — 1-D search over β.
        let r = search_on_circle(&nf, objective, u_lo / u_ref)?;
        Found {
            status: r.0,
            u: r.1 * u_ref,
            gap: 0.0,
            method: r.2,
            rounds: 0,
        }
    } else {
        let limits = Limits {
            force: max_force,
            torque: max_torque,
        };
        convex_optimum(&nf, objective, limits, grid, &mut warnings)?
    };
    Ok(Optimum {
        status: found.status,
        u: found.u,
        gap: found.gap,
        method: found.method,
        rounds: found.rounds,
        warnings,
        balancers: Vec::new(),
        duals: None,
    })
}

/// The optimiser's answer before it becomes an [`Optimum`]: status, U (kg·m), gap in the
/// objective's SI unit, method and exchange rounds (0 without a convex solve).
struct Found {
    status: Status,
    u: P2,
    gap: f64,
    method: String,
    rounds: usize,
}

/// The peak-force and peak-torque limits of one solve (N, N·m).
#[derive(Clone, Copy)]
struct Limits {
    force: Option<f64>,
    torque: Option<f64>,
}

/// Whether the counterweight's angle range is the whole circle (β_hi − β_lo ≥ 2π).
fn full_circle(scene: &Scene) -> bool {
    let (beta_lo, beta_hi) = scene.counterweight.angle.bounds();
    beta_hi - beta_lo >= std::f64::consts::TAU - 1e-9
}

/// The convex solve of [`crate::synth::counterweight`] on the normalised fields: the force
/// f̂ (and the torque T̂ where the objective or a limit needs it) on the scan `grid`, the
/// engine's goal and limits, U's direction (fixed, a sector or free) and |U| ≤ U_max/U_ref;
/// then, where the optimum lies inside the non-convex lower bound |U| ≥ U_min, the search on
/// that circle. The engine's note goes to `warnings`.
fn convex_optimum(
    nf: &Normalised,
    objective: Objective,
    limits: Limits,
    grid: &Grid,
    warnings: &mut Vec<String>,
) -> Result<Found, SolveError> {
    let scene = nf.scene;
    let s = &scene.resolved_settings();
    let torque_needed = needs_torque(objective, limits.torque);
    let (force_grid, torque_grid) = field_grids(nf, grid, torque_needed);
    let u_ref = nf.u_ref;
    let force = |phi: f64| nf.force(phi);
    let torque = |phi: f64| nf.torque(phi);
    let (u_lo, u_hi) = unbalance_bounds(&scene.counterweight);
    let (goal, obj_ref, limits) = goal_and_limits(nf, objective, limits);
    let direction = direction_of(scene, u_lo / u_ref);
    let mut fields = vec![Field {
        name: "shaking force",
        dim: 2,
        eval: &force,
        grid: Some(&force_grid),
    }];
    if torque_needed {
        fields.push(Field {
            name: "drive torque",
            dim: 1,
            eval: &torque,
            grid: Some(&torque_grid),
        });
    }
    let warm_angles = if s.warm_start && goal != Goal::MinNorm {
        warm_start(nf, s)
    } else {
        Vec::new()
    };
    let pb = Problem {
        fields,
        goal,
        limits,
        u_max: u_hi / u_ref,
        direction,
        warm_angles,
    };
    let sol = cw::solve(&pb, s);
    let method = convex_method(&sol, goal);
    if let Some(n) = &sol.note {
        warnings.push(n.clone());
    }
    let mut found = Found {
        status: sol.status,
        u: sol.u * u_ref,
        gap: sol.gap * obj_ref,
        method,
        rounds: if sol.disc { 0 } else { sol.rounds },
    };
    if found.status != Status::Infeasible
        && found.status != Status::Failed
        && matches!(direction, Direction::Free | Direction::Sector { .. })
        && found.u.norm() < u_lo * (1.0 - 1e-9)
    {
        // The lower bound on |U| is active and not convex: search its circle.
        let r = search_on_circle(nf, objective, u_lo / u_ref)?;
        found.status = r.0;
        found.u = r.1 * u_ref;
        found.gap = 0.0;
        found.method = format!("{}; |U| ≥ {u_lo:.6e} kg·m active: {}", found.method, r.2);
    }
    Ok(found)
}

/// The fields on the scan grid (the scans of the exchange loop and the presolve): f̂(φₖ),
/// and T̂(φₖ) only where a field needs the torque (the callers pass a grid with the torque
/// column then: `Columns::All`), else empty.
fn field_grids(nf: &Normalised, grid: &Grid, torque: bool) -> (Vec<Affine>, Vec<Affine>) {
    let force_grid: Vec<Affine> = (0..grid.len())
        .map(|k| nf.force_of(grid.cs[k], grid.f0[k]))
        .collect();
    let torque_grid: Vec<Affine> = if torque {
        debug_assert_eq!(grid.t0.len(), grid.len(), "the torque needs Columns::All");
        (0..grid.len())
            .map(|k| nf.torque_of(grid.cs[k], grid.t0[k]))
            .collect()
    } else {
        Vec::new()
    };
    (force_grid, torque_grid)
}

/// The engine's goal for `objective` with the SI size of its normalised unit (ω²U_ref in N
/// for the force, t_ref in N·m for the torque), and the limits as (field, normalised bound):
/// field 0 the force F/(ω²U_ref), field 1 the torque T/t_ref.
fn goal_and_limits(
    nf: &Normalised,
    objective: Objective,
    limits: Limits,
) -> (Goal, f64, Vec<(usize, f64)>) {
    let f_ref = nf.scene.omega * nf.scene.omega * nf.u_ref; // N per normalised unit
    let mut out = Vec::new();
    if let Some(f) = limits.force {
        out.push((0, f / f_ref));
    }
    if let Some(t) = limits.torque {
        out.push((1, t / nf.t_ref));
    }
    let (goal, obj_ref) = match objective {
        Objective::MinPeakForce => (Goal::MinPeak(0), f_ref),
        Objective::MinRmsForce => (Goal::MinMeanSquare(0), f_ref),
        Objective::MinMass | Objective::MinRadius => (Goal::MinNorm, f_ref),
        Objective::MinPeakTorque => (Goal::MinPeak(1), nf.t_ref),
        // Never here: a moment or ΔE objective is a joint design (`optimise_joint`).
        Objective::MinPeakMoment | Objective::MinEnergyFluctuation => (Goal::MinPeak(0), f_ref),
    };
    (goal, obj_ref, out)
}

/// U's direction for the engine: fixed at β with |U| ≥ `min_len` (normalised), free on the
/// whole circle, or in the sector [β_lo, β_hi].
fn direction_of(scene: &Scene, min_len: f64) -> Direction {
    let angle = &scene.counterweight.angle;
    let (beta_lo, beta_hi) = angle.bounds();
    if let Some(beta) = angle.fixed() {
        Direction::Fixed { beta, min_len }
    } else if full_circle(scene) {
        Direction::Free
    } else {
        Direction::Sector {
            lo: beta_lo,
            hi: beta_hi,
        }
    }
}

/// The method string of a convex solve: the presolve if it ran, then the exact smallest
/// disc (Welzl) or the clarabel program of `goal`, with the exchange loop's rounds, angles,
/// iterations and last status.
fn convex_method(sol: &cw::Solution, goal: Goal) -> String {
    let presolve = if sol.presolved {
        "geometric presolve (smallest disc enclosing the force-cancelling unbalances) + "
    } else {
        ""
    };
    if sol.disc {
        format!(
            "{presolve}exact sampled minimax (smallest enclosing disc, Welzl; the SOCP's optimum without clarabel) + exchange loop: {} rounds, {} angles",
            sol.rounds, sol.samples
        )
    } else {
        format!(
            "{presolve}clarabel {} + exchange loop: {} rounds, {} angles, {} interior-point iterations, last status {}",
            match goal {
                Goal::MinPeak(0) => "SOCP (minimax force)",
                Goal::MinPeak(_) => "SOCP/LP (minimax torque)",
                Goal::MinMeanSquare(_) => "QP (mean square)",
                Goal::MinNorm => "SOCP (least |U|)",
            },
            sol.rounds,
            sol.samples,
            sol.ipm_iterations,
            sol.solver_status
        )
    }
}

/// Angles of the local maxima of |F| for the least-squares counterweight
/// û = −mean Rot(φ)ᵀ f̂₀(φ) (the RMS optimum of a free direction, in closed form): close to
/// the minimax optimum's active angles, so the first SOCP starts near them.
pub(super) fn warm_start(nf: &Normalised, s: &cw::Settings) -> Vec<f64> {
    let n = 64;
    let mut u = P2::zeros();
    for k in 0..n {
        let phi = k as f64 * std::f64::consts::TAU / n as f64;
        let a = nf.force(phi);
        u -= rot(-phi, P2::new(a.b[0], a.b[1])) / n as f64;
    }
    periodic_peak(|p| nf.force(p).at(u).norm(), 90, s.peak_xtol.max(1e-6))
        .map(|p| p.maxima.iter().map(|m| m.x).collect())
        .unwrap_or_default()
}

/// Minimises the objective over U on the circle |U| = `len` (normalised): a 72-point scan in
/// β and Brent on the best bracket.
pub(super) fn search_on_circle(
    nf: &Normalised,
    objective: Objective,
    len: f64,
) -> Result<(Status, P2, String), SolveError> {
    let scene = nf.scene;
    let s = &scene.resolved_settings();
    let obj = |beta: f64| -> f64 {
        let u = P2::new(beta.cos(), beta.sin()) * len;
        let mag = |p: f64| nf.force(p).at(u).norm();
        let tq = |p: f64| nf.torque(p).at(u).x.abs();
        let peak = |f: &dyn Fn(f64) -> f64| {
            periodic_peak(f, s.scan_samples, s.peak_xtol)
                .map(|p| p.peak.fx)
                .unwrap_or(f64::INFINITY)
        };
        match objective {
            Objective::MinRmsForce => periodic_rms(mag, s.rms_samples).rms,
            Objective::MinPeakTorque => peak(&tq),
            _ => peak(&mag),
        }
    };
    let (lo, hi) = scene.counterweight.angle.bounds();
    let full = hi - lo >= std::f64::consts::TAU - 1e-9;
    let n = 72;
    let h = (hi - lo) / if full { n as f64 } else { (n - 1) as f64 };
    let vals: Vec<f64> = (0..n).map(|k| obj(lo + k as f64 * h)).collect();
    let k = (0..n).min_by(|&a, &b| vals[a].total_cmp(&vals[b])).unwrap();
    let c = lo + k as f64 * h;
    let (a, b) = if full {
        (c - h, c + h)
    } else {
        ((c - h).max(lo), (c + h).min(hi))
    };
    let best = brent_max(|beta| -obj(beta), a, b, s.peak_xtol)
        .map_err(|e| SolveError::Numeric(e.to_string()))?;
    let u = P2::new(best.x.cos(), best.x.sin()) * len;
    Ok((
        Status::Optimal,
        u,
        "|U| fixed, 1-D search over β (72-point scan + Brent), objective not convex on the circle"
            .into(),
    ))
}
