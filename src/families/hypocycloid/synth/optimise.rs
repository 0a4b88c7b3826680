//! A hypocycloid design evaluated (coefficients, residual force, stroke) and the search of
//! (λ, θ) that minimises the residual inertia force: a grid over the free box, then argmin's
//! Nelder–Mead from the best distinct grid points through the shared search layer
//! ([`crate::synth::search`]), with its evidence.

use super::{is_free, CoefficientModel, HypocycloidScene, OptStatus, Settings};
use crate::families::hypocycloid::model::{max_abs_y, Coefficients, Hypocycloid, MechError};
use crate::numeric::periodic_peak_with;
use crate::synth::search::starts::{axis, distinct_starts, grid, ranked};
use crate::synth::search::{nelder_mead, NelderMead, SameBasin, SearchEvidence};
use std::f64::consts::PI;

/// Evaluation of one design.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Eval {
    pub(super) coef: Coefficients,
    pub(super) residual_peak: f64,
    pub(super) residual_peak_err: f64,
    pub(super) stroke: f64,
    pub(super) stroke_err: f64,
    pub(super) suction_gain: f64,
    pub(super) ratio_ymax: f64,
}

/// Peak over φ of |residual inertia force| / (m_B R ω²):
/// F_res/(m_B R ω²) = −(S/R)'' − Σ_{i∈K} i² (a_i cos iφ + b_i sin iφ), with (S/R)'' in closed
/// form (independent of the coefficients). Error: refinement + Σ i² err_i.
fn residual_peak(
    m: &Hypocycloid,
    c: &Coefficients,
    orders: &[usize],
    s: &Settings,
) -> Result<(f64, f64), MechError> {
    let f = |p: f64| residual_rel(m, c, orders, p).abs();
    let pk = periodic_peak_with(f, s.peak_samples, s.peak_tol())?;
    let cerr: f64 = orders.iter().map(|&i| (i * i) as f64 * c.err[i]).sum();
    Ok((pk.peak.fx, pk.error + cerr))
}

/// The residual inertia force of m_B after the Lanchester pairs of `orders`, over m_B R ω²:
/// −(S/R)'' − Σ_{i∈K} i² (a_i cos iφ + b_i sin iφ).
pub fn residual_rel(m: &Hypocycloid, c: &Coefficients, orders: &[usize], p: f64) -> f64 {
    let mut f = -m.piston(p).dds;
    for &i in orders {
        let k = i as f64;
        let (sn, cs) = (k * p).sin_cos();
        f -= k * k * (c.a[i] * cs + c.b[i] * sn);
    }
    f
}

/// The φ-derivative of the residual piston position per R, s_res′ = s′ − Σ_i i (b_i cos iφ −
/// a_i sin iφ) over the cancelled orders (the Lanchester pairs cancel their order of the
/// position, hence of the force at any speed and acceleration): at real speed the residual
/// force is m_B R (ω² [`residual_rel`] − α s_res′).
pub fn residual_rate(m: &Hypocycloid, c: &Coefficients, orders: &[usize], p: f64) -> f64 {
    let mut v = m.piston(p).ds;
    for &i in orders {
        let k = i as f64;
        let (sn, cs) = (k * p).sin_cos();
        v -= k * (c.b[i] * cs - c.a[i] * sn);
    }
    v
}

pub(super) fn evaluate(
    scene: &HypocycloidScene,
    l: f64,
    t: f64,
    s: &Settings,
) -> Result<Eval, MechError> {
    let m = Hypocycloid::new(l, t, scene.alpha0)?;
    let ratio_ymax = m.lambda_ymax();
    let order = scene
        .orders
        .max(*scene.balance_orders.iter().max().unwrap_or(&0));
    let mut coef = s.coefficients(&m, order);
    if scene.coefficients == CoefficientModel::Series {
        (coef.a, coef.b) = m.series_coefficients(scene.series_power, order);
    }
    let (rp, rpe) = residual_peak(&m, &coef, &scene.balance_orders, s)?;
    let st = m.stroke()?;
    Ok(Eval {
        coef,
        residual_peak: rp,
        residual_peak_err: rpe,
        stroke: st.stroke,
        stroke_err: st.error,
        suction_gain: st.suction_angle / PI - 1.0,
        ratio_ymax,
    })
}

/// Penalised objective of the optimiser (dimensionless residual peak; +1e3·violation and
/// +1e6 when the mechanism cannot be built).
fn penalised(scene: &HypocycloidScene, x: [f64; 2], s: &Settings) -> f64 {
    let (lb, tb) = (scene.lambda.bounds(), scene.theta.bounds());
    let mut viol = 0.0;
    let l = x[0].clamp(lb.0, lb.1);
    let t = x[1].clamp(tb.0, tb.1);
    viol += (x[0] - l).abs() + (x[1] - t).abs();
    let ym = max_abs_y(t, scene.alpha0).unwrap_or(f64::INFINITY);
    let over = l * ym - (1.0 - scene.assembly_margin);
    if over > 0.0 {
        return 1e6 + over + viol;
    }
    match evaluate(scene, l, t, s) {
        Ok(e) => {
            if let Some(ms) = scene.min_stroke {
                viol += (ms / scene.r_carrier - e.stroke).max(0.0);
            }
            if let Some(g) = scene.min_suction_gain {
                viol += (g - e.suction_gain).max(0.0);
            }
            e.residual_peak + 1e3 * viol
        }
        Err(_) => 1e6 + viol,
    }
}

/// What the search of (λ, θ) found.
pub(super) struct Optimum {
    /// The design (before it is kept inside the assembly margin).
    pub(super) x: [f64; 2],
    /// How the search ended.
    pub(super) status: OptStatus,
    /// The method, in words.
    pub(super) method: String,
    /// The multistart's evidence (absent without a multistart).
    pub(super) search: Option<SearchEvidence>,
}

/// The design of the scene: the fixed (λ, θ), or the search of the free ones — a grid of
/// `opt_grid` points per free variable, then Nelder–Mead from the best grid points at least
/// two grid steps apart. Evaluations are added to `evals`, what the user should know to
/// `warnings`.
pub(super) fn optimise(
    scene: &HypocycloidScene,
    s: &Settings,
    evals: &mut usize,
    warnings: &mut Vec<String>,
) -> Optimum {
    let (lb, tb) = (scene.lambda.bounds(), scene.theta.bounds());
    if !(is_free(&scene.lambda) || is_free(&scene.theta)) {
        return Optimum {
            x: [lb.0, tb.0],
            status: OptStatus::Analysis,
            method: "analysis of the fixed design".to_string(),
            search: None,
        };
    }
    // Grid start over the free box.
    let g = s.opt_grid;
    let pts = |b: (f64, f64), f: bool| if f { axis(b.0, b.1, g) } else { vec![b.0] };
    let mut best = ([lb.0, tb.0], f64::INFINITY);
    let mut points = Vec::new();
    for p in grid(&[
        pts(lb, is_free(&scene.lambda)),
        pts(tb, is_free(&scene.theta)),
    ]) {
        let v = penalised(scene, [p[0], p[1]], s);
        *evals += 1;
        if v < best.1 {
            best = ([p[0], p[1]], v);
        }
        points.push((p, v));
    }
    if best.1 >= 1e3 {
        warnings.push(format!(
            "no grid point satisfies the assembly margin, stroke and suction constraints (best penalised value {:e}); \
             the least-violating point is reported",
            best.1
        ));
        return Optimum {
            x: best.0,
            status: OptStatus::Infeasible,
            method: format!("grid {g}×{g}: infeasible"),
            search: None,
        };
    }
    multistart(scene, s, ranked(points), best, evals, warnings)
}

/// The initial simplex at x0: a step of one grid step (dl, dt) along each free variable,
/// backwards where it would leave the box (upper ends `hi`).
fn simplex(x0: &[f64], (dl, dt): (f64, f64), hi: (f64, f64)) -> Vec<Vec<f64>> {
    let mut simplex = vec![x0.to_vec()];
    if dl > 0.0 {
        simplex.push(vec![
            x0[0] + dl * if x0[0] + dl > hi.0 { -1.0 } else { 1.0 },
            x0[1],
        ]);
    }
    if dt > 0.0 {
        simplex.push(vec![
            x0[0],
            x0[1] + dt * if x0[1] + dt > hi.1 { -1.0 } else { 1.0 },
        ]);
    }
    simplex
}

/// Nelder–Mead from the best grid points (`ranked`, cheapest first) at least two grid
/// steps apart; the best end is the design, the ends' basins the evidence.
fn multistart(
    scene: &HypocycloidScene,
    s: &Settings,
    ranked: Vec<(Vec<f64>, f64)>,
    best: ([f64; 2], f64),
    evals: &mut usize,
    warnings: &mut Vec<String>,
) -> Optimum {
    let g = s.opt_grid;
    let (lb, tb) = (scene.lambda.bounds(), scene.theta.bounds());
    let step = |b: (f64, f64), f: bool| if f { (b.1 - b.0) / (g - 1) as f64 } else { 0.0 };
    let (dl, dt) = (
        step(lb, is_free(&scene.lambda)),
        step(tb, is_free(&scene.theta)),
    );
    // Starts: the best grid points that are at least two grid steps apart.
    let steps = |a: f64, d: f64| if d > 0.0 { a.abs() / d } else { 0.0 };
    let starts = distinct_starts(
        &ranked,
        s.opt_starts,
        |v| !(v >= 1e3),
        |q, p| steps(p[0] - q[0], dl).max(steps(p[1] - q[1], dt)) >= 2.0 - 1e-9,
    );
    let mut runs: Vec<([f64; 2], f64, u64, bool)> = Vec::new();
    let mut total_iters = 0;
    for x0 in starts {
        let vertices = simplex(&x0, (dl, dt), (lb.1, tb.1));
        let cost = |p: &[f64]| penalised(scene, [p[0], p[1]], s);
        let local = NelderMead {
            simplex: vertices,
            sd_tolerance: s.nm_sd_tol,
            max_iters: s.nm_max_iters,
        };
        match nelder_mead(&cost, &local) {
            Ok(end) => {
                total_iters += end.iterations;
                *evals += end.evaluations;
                let px = [end.x[0].clamp(lb.0, lb.1), end.x[1].clamp(tb.0, tb.1)];
                let v = penalised(scene, px, s);
                *evals += 1;
                runs.push((px, v, end.iterations, end.converged));
            }
            Err(e) => warnings.push(format!(
                "Nelder–Mead from ({:.6}, {:.6}) failed ({e})",
                x0[0], x0[1]
            )),
        }
    }
    if runs.is_empty() {
        warnings.push("every Nelder–Mead run failed; the best grid point is reported".into());
        runs.push((best.0, best.1, 0, false));
    }
    runs.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (px, _, _, converged) = runs[0];
    if !converged {
        warnings.push(format!(
            "the best Nelder–Mead run stopped at its iteration limit ({})",
            s.nm_max_iters
        ));
    }
    // Basins: runs whose end points differ by more than 1e-6 of the box (or whose values
    // differ by more than 1e-9 relative) are distinct local optima.
    let spans = [lb.1 - lb.0, tb.1 - tb.0];
    let search = SearchEvidence::of_ends(
        format!(
            "grid {g} per free variable, then argmin Nelder–Mead (Nelder & Mead 1965) from the {} best \
             grid points at least two steps apart; penalised residual-force peak",
            runs.len()
        ),
        runs.iter().map(|r| (r.0.to_vec(), r.1)).collect(),
        runs.len(),
        *evals,
        &SameBasin {
            rel: 1e-9,
            point: Some((&spans, 1e-6)),
        },
        scene.m_b * scene.r_carrier * scene.omega * scene.omega,
    );
    Optimum {
        x: px,
        status: if converged {
            OptStatus::Converged
        } else {
            OptStatus::MaxIterations
        },
        method: format!(
            "grid {g}-per-free-variable start + argmin Nelder–Mead from {} starts ({total_iters} iterations)",
            runs.len()
        ),
        search: Some(search),
    }
}
