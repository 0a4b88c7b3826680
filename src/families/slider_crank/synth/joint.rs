//! The joint design of the crank counterweight and the balancers (or a moment or a
//! main-bearing limit) by the certified affine minimax of [`crate::synth::minimax`].

use super::fields::{force0, moment0, torque0};
use super::outcome::Optimum;
use super::realise::unbalance_bounds;
use super::round_off::{joint_load_round_off, round_off_bounds};
use super::scene::{Objective, Scene, SolveError};
use crate::families::slider_crank::model::weight_torque_cs;
use crate::geom::P2;
use crate::synth::counterweight::Status;
use crate::synth::Var;

/// The joint design of the crank counterweight U and the balancers' unbalances B_n by the
/// certified affine minimax of [`crate::synth::minimax`]: every figure is affine in
/// x = (U; B_1; …), so the columns of the balancers are added to those of U and the same
/// cone program and exchange loop certify the joint optimum.
///
/// Variables: each unbalance is a 2-vector held as the first moment of one of the engine's
/// counterweights (m, u, I) with m_max = 1 and r_max = ρ = its bound, so |u| ≤ bound is the
/// engine's own cone (m and I enter no field). Fields (SI): 0 the shaking force (N),
/// 1 the shaking moment about O (N·m), 2 the drive torque (N·m), 3 the main bearing load
/// without the counterweight's weight (N).
///
/// Bounds: where the scene leaves |U| or |B_n| unbounded, the Fourier coefficients of the
/// force z = F_x + iF_y bound them at any design whose peak (or RMS) force is at most K:
/// z = z₀ + U e^{iφ} + Σ n²(B_n e^{inφ} + B̄_n e^{−inφ})/2, and |c_k(z)| ≤ max|z| (≤ RMS for
/// the RMS), so n²|B_n|/2 ≤ K + P₀ and |U| ≤ 2(K + P₀), P₀ the peak of z₀ (taken as 1.5 ×
/// its sampled maximum). K is the force limit, or P₀ for a force objective (reached by the
/// design 0). Where the other limits exclude the design 0 the optimum's force may exceed P₀,
/// so a design on an automatic bound is reported `inaccurate`; one inside them all is the
/// unbounded problem's optimum too (a convex problem: a local optimum is global).
pub(super) fn optimise_joint(
    scene: &Scene,
    objective: Objective,
    max_force: Option<f64>,
    max_torque: Option<f64>,
) -> Result<Optimum, SolveError> {
    use crate::synth::minimax::{self as mm, AffineValue, CounterweightLimits, FnField};
    let mech = &scene.mech;
    let w2 = scene.omega * scene.omega;
    let g = scene.loads.gravity;
    let nb = scene.balancers.len();
    let st = |phi: f64| mech.state(phi).expect("assembly checked");
    let zero = scene.with_balancers(&vec![[0.0; 2]; nb]);
    let zero = &zero;
    // P₀, the peak of the force without design (sampled, with margin).
    let p0 = 1.5
        * (0..720)
            .map(|k| {
                let phi = k as f64 * std::f64::consts::TAU / 720.0;
                force0(zero, &st(phi)).norm() * w2
            })
            .fold(0.0, f64::max);
    let k_force = match (objective, max_force) {
        (Objective::MinPeakForce | Objective::MinRmsForce, Some(f)) => f.min(p0),
        (Objective::MinPeakForce | Objective::MinRmsForce, None) => p0,
        (_, Some(f)) => f,
        (_, None) => {
            return Err(SolveError::Numeric(
                "a joint design (balancers, moment or main-bearing limits) minimising the torque or the moment needs objective.max_peak_force: the counterweight is otherwise unbounded".into(),
            ))
        }
    };
    let auto = |n: f64| 2.0 * (k_force + p0) / (w2 * n * n);
    let (u_lo, u_hi) = unbalance_bounds(&scene.counterweight);
    let u_auto = 2.0 * auto(1.0);
    let u_max = u_hi.min(u_auto);
    let sector = match scene.counterweight.angle {
        Var::Fixed(b) => Some((b, b)),
        Var::Free { min, max } if max - min < std::f64::consts::TAU - 1e-9 => Some((min, max)),
        _ => None,
    };
    let limits_of = |bound: f64| CounterweightLimits {
        sector: None,
        ..CounterweightLimits::new(1.0, bound)
    };
    let mut cws = vec![CounterweightLimits {
        sector,
        ..limits_of(u_max)
    }];
    let b_max: Vec<f64> = scene
        .balancers
        .iter()
        .map(|b| b.max_unbalance.min(auto(b.pair.order as f64)))
        .collect();
    cws.extend(b_max.iter().map(|&b| limits_of(b)));
    let ub = |j: usize| mm::var_u(j);
    let fill_balancers = |out: &mut AffineValue, phi: f64, which: u8| {
        for (j, b) in scene.balancers.iter().enumerate() {
            let (c, scale) = match which {
                0 => (b.pair.force_coeffs(phi), w2),
                1 => (b.pair.moment_coeffs(phi), w2),
                _ => (b.pair.weight_torque_coeffs(phi, g), 1.0),
            };
            let row = out.row_mut(0);
            row[ub(j + 1)] = c[0] * scale;
            row[ub(j + 1) + 1] = c[1] * scale;
        }
    };
    let x_parts = |x: &[f64]| -> (P2, Vec<[f64; 2]>) {
        (
            P2::new(x[ub(0)], x[ub(0) + 1]),
            (0..nb).map(|j| [x[ub(j + 1)], x[ub(j + 1) + 1]]).collect(),
        )
    };
    let ro = |x: &[f64]| {
        let (u, b) = x_parts(x);
        round_off_bounds(&zero.with_balancers(&b), u)
    };
    let force = FnField::new("shaking force", 2, |phi: f64, out: &mut AffineValue| {
        let s = st(phi);
        let f0 = force0(zero, &s) * w2;
        let [c, sn] = s.cs;
        out.b = [f0.x, f0.y];
        out.row_mut(0)[ub(0)] = w2 * c;
        out.row_mut(0)[ub(0) + 1] = -w2 * sn;
        out.row_mut(1)[ub(0)] = w2 * sn;
        out.row_mut(1)[ub(0) + 1] = w2 * c;
        fill_balancers(out, phi, 0);
    })
    .with_error(|_, x: &[f64]| ro(x)[0]);
    let moment = FnField::new("shaking moment", 1, |phi: f64, out: &mut AffineValue| {
        out.b = [moment0(zero, &st(phi)) * w2, 0.0];
        fill_balancers(out, phi, 1);
    })
    .with_error(|_, x: &[f64]| ro(x)[2]);
    let torque = FnField::new("drive torque", 1, |phi: f64, out: &mut AffineValue| {
        let s = st(phi);
        out.b = [torque0(zero, &s), 0.0];
        out.row_mut(0)[ub(0)] = weight_torque_cs(s.cs, g, P2::new(1.0, 0.0));
        out.row_mut(0)[ub(0) + 1] = weight_torque_cs(s.cs, g, P2::new(0.0, 1.0));
        fill_balancers(out, phi, 2);
    })
    .with_error(|_, x: &[f64]| ro(x)[1]);
    let bearing = FnField::new("main bearing load", 2, |phi: f64, out: &mut AffineValue| {
        let s = st(phi);
        let f = mech
            .joint_loads(&s, scene.omega, &scene.loads, P2::zeros(), 0.0)
            .main;
        let [c, sn] = s.cs;
        out.b = [f.x, f.y];
        out.row_mut(0)[ub(0)] = -w2 * c;
        out.row_mut(0)[ub(0) + 1] = w2 * sn;
        out.row_mut(1)[ub(0)] = -w2 * sn;
        out.row_mut(1)[ub(0) + 1] = -w2 * c;
    })
    .with_error(|_, x: &[f64]| joint_load_round_off(scene, x_parts(x).0, 0.0));
    const FORCE: usize = 0;
    const MOMENT: usize = 1;
    const TORQUE: usize = 2;
    const BEARING: usize = 3;
    let goal = match objective {
        Objective::MinPeakForce => mm::Goal::MinPeak(vec![(FORCE, 1.0)]),
        Objective::MinRmsForce => mm::Goal::MinRms(FORCE),
        Objective::MinPeakTorque => mm::Goal::MinPeak(vec![(TORQUE, 1.0)]),
        Objective::MinPeakMoment => mm::Goal::MinPeak(vec![(MOMENT, 1.0)]),
        Objective::MinMass | Objective::MinRadius => {
            return Err(SolveError::Numeric(
                "minimising the counterweight's mass or radius is not available with balancers, moment or main-bearing limits".into(),
            ))
        }
    };
    let mut limits = Vec::new();
    for (f, lim) in [
        (FORCE, max_force),
        (TORQUE, max_torque),
        (MOMENT, scene.max_shaking_moment),
        (BEARING, scene.load_limits.main_bearing),
    ] {
        if let Some(l) = lim {
            limits.push((f, l));
        }
    }
    let pb = mm::Problem {
        fields: vec![&force, &moment, &torque, &bearing],
        counterweights: cws,
        extra: Vec::new(),
        linear: Vec::new(),
        goal,
        limits,
    };
    let cs = &scene.resolved_settings();
    let settings = mm::Settings {
        rel_tol: cs.rel_tol,
        initial_samples: cs.initial_samples,
        scan_samples: cs.scan_samples,
        max_rounds: cs.max_rounds,
        peak_xtol: cs.peak_xtol,
        rms_samples: (cs.rms_samples + 1) & !1,
        exact_disc: cs.exact_disc,
        ..mm::Settings::default()
    };
    let num = |e: mm::MinimaxError| SolveError::Numeric(e.to_string());
    let engine = mm::Engine::new(&pb, &settings).map_err(num)?;
    let sol = engine.solve().map_err(num)?;
    let mut warnings = Vec::new();
    if let Some(n) = &sol.note {
        warnings.push(n.clone());
    }
    let feasible = sol.x.iter().all(|v| v.is_finite());
    let (u, b) = if feasible {
        x_parts(&sol.x)
    } else {
        (P2::zeros(), vec![[0.0; 2]; nb])
    };
    if sol.status == Status::Infeasible {
        warnings.push(format!(
            "infeasible: no counterweight and balancers within the bounds meet the limits (peak force ≤ {max_force:?} N, peak torque ≤ {max_torque:?} N·m, shaking moment ≤ {:?} N·m, main bearing ≤ {:?} N); the figures shown are those of no counterweight and no balancers",
            scene.max_shaking_moment, scene.load_limits.main_bearing
        ));
    }
    // A design on a bound the scene did not set would be the bounds' optimum, not the
    // scene's: the Fourier bounds above exclude it, so say so if it happens.
    let on = |v: f64, auto: f64, given: f64| auto < given && v >= auto * (1.0 - 1e-6);
    let mut status = sol.status;
    if feasible
        && (on(u.norm(), u_auto, u_hi)
            || b.iter().zip(&scene.balancers).any(|(bb, spec)| {
                on(
                    bb[0].hypot(bb[1]),
                    auto(spec.pair.order as f64),
                    spec.max_unbalance,
                )
            }))
    {
        status = Status::Inaccurate;
        warnings.push(
            "the joint design reached an automatic bound on |U| or |B_n| (see the method); the optimum may lie beyond it".into(),
        );
    }
    if u_lo > 0.0 && u.norm() < u_lo * (1.0 - 1e-9) {
        return Err(SolveError::Numeric(format!(
            "|U| ≥ {u_lo} kg·m is not convex and not available with balancers, moment or main-bearing limits"
        )));
    }
    let gap = if feasible {
        sol.error.sampling + sol.error.solver
    } else {
        0.0
    };
    Ok(Optimum {
        status,
        u,
        gap,
        method: format!(
            "joint design of the crank counterweight and {nb} balancer pair(s) (synth::minimax, bounds |U| ≤ {u_max:.6e} kg·m{}): clarabel SOCP + exchange loop: {} rounds, {} angles, {} interior-point iterations, last status {}",
            b_max
                .iter()
                .zip(&scene.balancers)
                .map(|(m, s)| format!(", |B_{}| ≤ {m:.6e} kg·m", s.pair.order))
                .collect::<String>(),
            sol.rounds,
            sol.angles,
            sol.ipm_iterations,
            sol.solver_status
        ),
        rounds: sol.rounds,
        warnings,
        balancers: b,
    })
}
