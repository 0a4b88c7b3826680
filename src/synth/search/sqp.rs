//! A trust-region Sℓ1QP for a constrained minimax: minimise max_i f_i(u) − min_k g_k(u)
//! subject to c_m(u) ≤ 0 over the unit box, where the pieces f_i, g_k are the local maxima
//! and minima of a smooth function along a parameter t (the crane's jib-head height over
//! the luffing range: Δh, thesis `003`).
//!
//! The method is Fletcher's Sℓ1QP (R. Fletcher, *Practical Methods of Optimization*, 2nd
//! ed., Wiley 1987, §14.5, with the second-order correction of §14.4): every piece a
//! linearised row of a QP, the constraints linearised with elastic slacks, an exact ℓ1
//! merit, a trust region in the ∞-norm, and a damped BFGS Hessian of the Lagrangian (Powell
//! 1978). Each QP is solved by the dense primal active-set method of [`super::qp`] (tens of
//! thousands of instructions for the crane's ~11 variables and ~25 rows, where clarabel's
//! interior point costs ~0.86 M), with clarabel as the fallback when that answer fails its
//! check.
//!
//! It is hand-written because no well-kept crate provides it: argmin has unconstrained
//! methods (its trust region takes no constraints) and none of them for a minimax of
//! pieces that appear and vanish; the SQP crates on crates.io are unmaintained or wrap a C
//! or Fortran library (NLopt's SLSQP, IPOPT), which would neither see the minimax structure
//! nor keep the build pure Rust. The subproblems are small convex QPs ([`super::qp`]).
//!
//! The problem supplies its pieces and constraints through [`Minimax`]; the search moves u
//! in the unit box (the caller maps it onto its variables) and counts its evaluations.

use std::cell::Cell;

use super::qp::{active_set, solve_dense, DenseQp, QpSolution};

/// Step (in the unit box) of the central differences of the Jacobian. With values good to
/// ~1e-15 of their scale the derivative's rounding is ~1e-9 relative and its truncation
/// ~H² = 1e-12: the QP's model is good to ~1e-9, far below what moves the merit (a reported
/// value is evaluated, never modelled).
const JACOBIAN_STEP: f64 = 1e-6;

/// Initial trust-region radius (∞-norm, unit box) and its cap: a tenth and a half of the
/// box's side.
const TRUST_INITIAL: f64 = 0.1;
/// See [`TRUST_INITIAL`].
const TRUST_MAX: f64 = 0.5;

/// The search stops when the trust region or the step falls below this (unit box): 1e-12
/// of the box is ~1e-13 rad in an angle, beyond what moves a value by more than round-off.
const TRUST_MIN: f64 = 1e-12;

/// Initial ℓ1 merit weight (raised to twice the largest multiplier).
const MU_INITIAL: f64 = 1e-2;

/// Initial Hessian of the Lagrangian, a multiple of the identity (the objective is scaled
/// to ~1e-2, the crane's Δh over its length scale; its curvature over the unit box is of
/// that order or less).
const HESSIAN_INITIAL: f64 = 1e-3;

/// Linearised constraint values within this of 0 count as active in the QP's step, for the
/// second-order correction.
const ACTIVE_TOL: f64 = 1e-9;

/// A constraint's derivative (per unit box) below this is rounding noise (a real limit
/// moves by ~0.1–1 of the scale across the box; the noise of an exactly met one is
/// ~ε/JACOBIAN_STEP ≈ 1e-10).
const FLAT_ROW: f64 = 1e-6;

/// A constrained minimax problem over the unit box [0, 1]ⁿ, seen by [`sqp`].
pub trait Minimax {
    /// The pieces and the signed constraints (≤ 0 met) at u; `None` where the problem has
    /// no valid point.
    fn probe(&self, u: &[f64]) -> Option<Probe>;
    /// The signed constraints, then the smooth function at each parameter of `ts` (held
    /// fixed), at u: what the finite differences of the Jacobian take.
    fn values(&self, u: &[f64], ts: &[f64]) -> Option<Vec<f64>>;
    /// The signed constraints alone at u (cheap: no pieces).
    fn constraints(&self, u: &[f64]) -> Option<Vec<f64>>;
}

/// One point seen by the search: the objective, every local maximum and minimum as a piece
/// (t, value), and the signed constraints (≤ 0 met).
#[derive(Debug, Clone)]
pub struct Probe {
    /// max over the maxima − min over the minima.
    pub value: f64,
    /// (t, value) of the local maxima.
    pub maxima: Vec<(f64, f64)>,
    /// (t, value) of the local minima.
    pub minima: Vec<(f64, f64)>,
    /// Signed constraints.
    pub cons: Vec<f64>,
}

impl Probe {
    /// The probe of these pieces and constraints; its value max_i y_i − min_k y_k.
    pub fn new(maxima: Vec<(f64, f64)>, minima: Vec<(f64, f64)>, cons: Vec<f64>) -> Probe {
        let top = maxima.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let bottom = minima.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        Probe {
            value: top - bottom,
            maxima,
            minima,
            cons,
        }
    }

    /// Exact ℓ1 merit value + μ Σ max(0, c).
    pub fn merit(&self, mu: f64) -> f64 {
        self.value + mu * self.cons.iter().map(|c| c.max(0.0)).sum::<f64>()
    }
}

/// The settings of one search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sqp {
    /// Iteration limit.
    pub max_iters: u64,
    /// Stop when the predicted gain of the merit falls below this fraction of the merit.
    pub tol: f64,
    /// The largest ℓ1 weight of the merit.
    pub penalty: f64,
}

/// Where one search ended.
#[derive(Debug, Clone)]
pub struct LocalRun {
    /// The last accepted point.
    pub u: Vec<f64>,
    /// Its probe (`None` when the start had no valid point or no Jacobian).
    pub probe: Option<Probe>,
    /// Whether it met its stopping test (predicted gain or trust region below tolerance).
    pub converged: bool,
    /// Iterations.
    pub iterations: u64,
    /// Evaluations of the problem's pieces: one a probe, two a column of the Jacobian.
    pub evaluations: usize,
}

/// A problem with its evaluations counted.
struct Counted<'a, P: ?Sized> {
    problem: &'a P,
    evals: Cell<usize>,
}

impl<P: Minimax + ?Sized> Counted<'_, P> {
    fn probe(&self, u: &[f64]) -> Option<Probe> {
        self.evals.set(self.evals.get() + 1);
        self.problem.probe(u)
    }

    /// Jacobian (rows: constraints, then maxima, then minima; columns: variables) by
    /// central differences at fixed t (one-sided at the box faces or where one side fails).
    fn jacobian(&self, u: &[f64], p: &Probe) -> Option<Vec<Vec<f64>>> {
        let ts: Vec<f64> = p.maxima.iter().chain(&p.minima).map(|q| q.0).collect();
        let rows = p.cons.len() + ts.len();
        let mut centre: Option<Vec<f64>> = None;
        let mut jac = vec![vec![0.0; u.len()]; rows];
        const H: f64 = JACOBIAN_STEP;
        for j in 0..u.len() {
            let step = |s: f64| {
                let mut w = u.to_vec();
                w[j] = (u[j] + s).clamp(0.0, 1.0);
                let dw = w[j] - u[j];
                (w, dw)
            };
            let (wp, hp) = step(H);
            let (wm, hm) = step(-H);
            self.evals.set(self.evals.get() + 2);
            let (fp, fm) = (self.problem.values(&wp, &ts), self.problem.values(&wm, &ts));
            let (a, b, h) = match (fp, fm) {
                (Some(a), Some(b)) if hp > hm => (a, b, hp - hm),
                (a, b) => {
                    if centre.is_none() {
                        centre = Some(self.problem.values(u, &ts)?);
                    }
                    let c = centre.clone()?;
                    match (a, b) {
                        (Some(a), _) if hp > 0.0 => (a, c, hp),
                        (_, Some(b)) if hm < 0.0 => (c, b, -hm),
                        _ => return None,
                    }
                }
            };
            for r in 0..rows {
                jac[r][j] = (a[r] - b[r]) / h;
            }
        }
        Some(jac)
    }
}

/// The state of a search between iterations.
struct Iterate {
    u: Vec<f64>,
    p: Probe,
    jac: Vec<Vec<f64>>,
    /// Hessian of the Lagrangian.
    b: Vec<Vec<f64>>,
    /// Trust-region radius.
    delta: f64,
    /// ℓ1 weight of the merit.
    mu: f64,
}

/// What one iteration did.
enum Step {
    /// Go on.
    Continue,
    /// Converged.
    Converged,
    /// The QP failed: stop where it is.
    Stop,
}

/// Minimise the problem's minimax from u0 by the trust-region Sℓ1QP (module doc): every
/// local extremum a piece, the constraints linearised with elastic slacks, damped BFGS for
/// the Hessian of the Lagrangian, exact ℓ1 merit. A constraint is followed as a constraint,
/// not a penalty, so the search slides along it when it is active.
pub fn sqp<P: Minimax + ?Sized>(problem: &P, u0: &[f64], settings: &Sqp) -> LocalRun {
    let n = u0.len();
    let cp = Counted {
        problem,
        evals: Cell::new(0),
    };
    let fail = |u: Vec<f64>, it| LocalRun {
        u,
        probe: None,
        converged: false,
        iterations: it,
        evaluations: cp.evals.get(),
    };
    let u = u0.to_vec();
    let Some(p) = cp.probe(&u) else {
        return fail(u, 0);
    };
    let Some(jac) = cp.jacobian(&u, &p) else {
        return fail(u, 0);
    };
    let b = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| if i == j { HESSIAN_INITIAL } else { 0.0 })
                .collect()
        })
        .collect();
    // The ℓ1 weight: above the largest constraint multiplier seen (so the merit is exact),
    // but no larger, since a large weight lets the constraints' curvature eat the gain of
    // a step along them (the Maratos effect). Raised when the QP leans on a slack.
    let mut s = Iterate {
        u,
        p,
        jac,
        b,
        delta: TRUST_INITIAL,
        mu: MU_INITIAL,
    };
    let mut converged = false;
    let mut it = 0;
    while it < settings.max_iters {
        it += 1;
        match iteration(&cp, &mut s, settings) {
            Step::Continue => {}
            Step::Converged => {
                converged = true;
                break;
            }
            Step::Stop => break,
        }
    }
    LocalRun {
        u: s.u,
        probe: Some(s.p),
        converged,
        iterations: it,
        evaluations: cp.evals.get(),
    }
}

/// The QP step at the iterate, the ℓ1 weight raised while the QP leans on a slack (and to
/// twice the largest multiplier).
fn penalised_step(s: &mut Iterate, settings: &Sqp) -> Option<QpStep> {
    let mut st = qp_step(&s.u, &s.p, &s.jac, &s.b, s.delta, s.mu)?;
    while st.slack > 1e-13 && s.mu < settings.penalty {
        s.mu = (10.0 * s.mu).min(settings.penalty);
        match qp_step(&s.u, &s.p, &s.jac, &s.b, s.delta, s.mu) {
            Some(s2) => st = s2,
            None => break,
        }
    }
    let lam = st.lam_con.iter().fold(0.0f64, |a, &l| a.max(l));
    if 2.0 * lam > s.mu {
        s.mu = (2.0 * lam).min(settings.penalty);
    }
    Some(st)
}

/// One iteration: the QP step, the trial point (with its second-order correction), and
/// its acceptance by the ratio of actual to predicted merit gain.
fn iteration<P: Minimax + ?Sized>(cp: &Counted<P>, s: &mut Iterate, settings: &Sqp) -> Step {
    let Some(st) = penalised_step(s, settings) else {
        return Step::Stop;
    };
    let m0 = s.p.merit(s.mu);
    // s − r does not depend on the shift y0 of the QP: the model at d = 0 is m0.
    let pred = m0 - st.model;
    let dn = st.d.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if pred <= settings.tol * m0.abs().max(1e-12) || dn < TRUST_MIN {
        return Step::Converged;
    }
    let un: Vec<f64> =
        s.u.iter()
            .zip(&st.d)
            .map(|(a, d)| (a + d).clamp(0.0, 1.0))
            .collect();
    let un = second_order_correction(cp.problem, un, &s.p, &s.jac, &st);
    let pn = cp.probe(&un);
    let rho = pn.as_ref().map_or(-1.0, |q| (m0 - q.merit(s.mu)) / pred);
    if rho >= 0.1 {
        let (pn, jn) = match pn.and_then(|q| cp.jacobian(&un, &q).map(|j| (q, j))) {
            Some(v) => v,
            None => {
                s.delta = 0.25 * dn;
                return Step::Continue;
            }
        };
        // Damped BFGS (Powell 1978) on the Lagrangian's gradient.
        let g1 = lagrangian_gradient(&pn, &jn, &s.p, &st);
        let g0 = lagrangian_gradient(&s.p, &s.jac, &s.p, &st);
        let sv: Vec<f64> = un.iter().zip(&s.u).map(|(a, c)| a - c).collect();
        let yv: Vec<f64> = g1.iter().zip(&g0).map(|(a, c)| a - c).collect();
        damped_bfgs(&mut s.b, &sv, yv);
        if rho > 0.75 && dn > 0.8 * s.delta {
            s.delta = (2.0 * s.delta).min(TRUST_MAX);
        }
        s.u = un;
        s.p = pn;
        s.jac = jn;
    } else {
        s.delta = 0.25 * dn;
    }
    if s.delta < TRUST_MIN {
        return Step::Converged;
    }
    Step::Continue
}

/// Powell's damped BFGS update (1978) of B by the step s and the gradient change y: y is
/// moved towards Bs until sᵀy ≥ 0.2 sᵀBs, so that B stays positive definite.
#[allow(clippy::needless_range_loop)]
fn damped_bfgs(b: &mut [Vec<f64>], s: &[f64], mut yv: Vec<f64>) {
    let n = s.len();
    let bs: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| b[i][j] * s[j]).sum())
        .collect();
    let sbs: f64 = s.iter().zip(&bs).map(|(a, c)| a * c).sum();
    let sy: f64 = s.iter().zip(&yv).map(|(a, c)| a * c).sum();
    if sbs > 0.0 {
        if sy < 0.2 * sbs {
            let th = 0.8 * sbs / (sbs - sy);
            for i in 0..n {
                yv[i] = th * yv[i] + (1.0 - th) * bs[i];
            }
        }
        let sy: f64 = s.iter().zip(&yv).map(|(a, c)| a * c).sum();
        if sy > 0.0 {
            for i in 0..n {
                for j in 0..n {
                    b[i][j] += yv[i] * yv[j] / sy - bs[i] * bs[j] / sbs;
                }
            }
        }
    }
}

/// Second-order correction of a trial point (Fletcher 1987, §14.4): the active constraints
/// are curved (the crane's tie pin moves on a curve as the variables change), so the full
/// step d leaves them by O(|d|²) and the merit gains less than the model predicted — the
/// Maratos effect, which pins the trust region and makes the search creep along an active
/// limit. Up to two chord Gauss–Newton steps δ = −Aᵀ(AAᵀ)⁻¹c(u + d), A the constraints'
/// Jacobian at u (rows: active in the QP, or violated at the trial point; columns:
/// variables not on a face of the box), bring the trial point back onto them. (Activity is
/// read from the linearisation, not the multipliers: clarabel's interior-point multipliers
/// are positive on every row.) Unchanged when the correction cannot be computed.
fn second_order_correction<P: Minimax + ?Sized>(
    problem: &P,
    mut un: Vec<f64>,
    p: &Probe,
    jac: &[Vec<f64>],
    st: &QpStep,
) -> Vec<f64> {
    let n = un.len();
    let lin = |m: usize| p.cons[m] + (0..n).map(|j| jac[m][j] * st.d[j]).sum::<f64>();
    let free: Vec<usize> = (0..n).filter(|&j| un[j] > 0.0 && un[j] < 1.0).collect();
    for _ in 0..2 {
        let Some(c) = problem.constraints(&un) else {
            break;
        };
        // A constraint the free variables cannot move (e.g. the reach met exactly by the
        // sizing rule) has a row of rounding noise only and is left out.
        let moves = |m: usize| free.iter().any(|&j| jac[m][j].abs() > FLAT_ROW);
        let rows: Vec<usize> = (0..p.cons.len())
            .filter(|&m| c[m] > 0.0 || lin(m) > -ACTIVE_TOL)
            .filter(|&m| moves(m))
            .collect();
        if rows.is_empty() || rows.len() > free.len() {
            break;
        }
        if rows.iter().all(|&m| c[m].abs() <= f64::EPSILON) {
            break;
        }
        let a = |r: usize, j: usize| jac[rows[r]][free[j]];
        let k = rows.len();
        let gram: Vec<f64> = (0..k * k)
            .map(|e| (0..free.len()).map(|j| a(e / k, j) * a(e % k, j)).sum())
            .collect();
        let rhs: Vec<f64> = rows.iter().map(|&m| c[m]).collect();
        let Some(w) = solve_dense(gram, rhs) else {
            break;
        };
        for (j, &col) in free.iter().enumerate() {
            let dj: f64 = (0..k).map(|r| a(r, j) * w[r]).sum();
            un[col] = (un[col] - dj).clamp(0.0, 1.0);
        }
    }
    un
}

struct QpStep {
    d: Vec<f64>,
    model: f64,
    lam_max: Vec<f64>,
    lam_min: Vec<f64>,
    lam_con: Vec<f64>,
    /// Σ v beyond the violation already present at d = 0 (the QP leaned on a slack).
    slack: f64,
}

/// The SQP subproblem of the minimax max_i y_i − min_k y_k (elastic ℓ1 form, trust
/// region Δ in the ∞-norm, inside the unit box):
///
/// min ½dᵀBd + s − r + μ Σ v  s.t.  y_i + g_i·d ≤ s,  y_k + g_k·d ≥ r,
/// c_m + a_m·d ≤ v_m,  v ≥ 0,  max(−Δ, −u) ≤ d ≤ min(Δ, 1 − u).
///
/// Solved by the dense active-set method ([`super::qp`]) from the feasible start d = 0 with
/// s, r and every v on one of their rows; by clarabel where that fails its check.
fn qp_step(
    u: &[f64],
    p: &Probe,
    jac: &[Vec<f64>],
    b: &[Vec<f64>],
    delta: f64,
    mu: f64,
) -> Option<QpStep> {
    let sub = Subproblem::new(u, p, jac, b, delta, mu);
    let (x, z, model) = match sub.dense() {
        Some(sol) => (sol.x, sol.lambda, sol.objective),
        None => sub.clarabel()?,
    };
    let n = u.len();
    let (nc, nx, nn) = (p.cons.len(), p.maxima.len(), p.minima.len());
    let v0: f64 = p.cons.iter().map(|c| c.max(0.0)).sum();
    let v: f64 = x[n + 2..].iter().sum();
    Some(QpStep {
        slack: (v - v0).max(0.0).max(if v0 == 0.0 { v } else { 0.0 }),
        d: x[..n].to_vec(),
        model,
        lam_con: z[..nc].to_vec(),
        lam_max: z[nc..nc + nx].to_vec(),
        lam_min: z[nc + nx..nc + nx + nn].to_vec(),
    })
}

/// The subproblem of [`qp_step`] written out densely: variables (d, s, r, v), rows A x ≤ b
/// in the order constraints, maxima, minima, v ≥ 0, then the box of d (upper, lower).
struct Subproblem {
    /// Variables: the steps d, s, r, then one slack per constraint.
    nv: usize,
    /// H (nv×nv, row-major): B in the d block.
    h: Vec<f64>,
    /// The linear term.
    q: Vec<f64>,
    /// A (rows × nv, row-major).
    a: Vec<f64>,
    /// Right-hand sides.
    rhs: Vec<f64>,
    /// The feasible start and its working set (`None` without a maximum or a minimum to pin
    /// s or r on: the QP is then unbounded, and clarabel says so).
    x0: Vec<f64>,
    /// See `x0`.
    w0: Option<Vec<usize>>,
}

impl Subproblem {
    #[allow(clippy::needless_range_loop)]
    fn new(u: &[f64], p: &Probe, jac: &[Vec<f64>], b: &[Vec<f64>], delta: f64, mu: f64) -> Self {
        let n = u.len();
        let (nc, nx) = (p.cons.len(), p.maxima.len());
        let nv = n + 2 + nc;
        let (is, ir) = (n, n + 1);
        let top = p.maxima.iter().map(|q| q.1).fold(f64::MIN, f64::max);
        let bottom = p.minima.iter().map(|q| q.1).fold(f64::MAX, f64::min);
        // The shift y0 keeps s and r near 0 (s − r does not depend on it).
        let y0 = 0.5 * (top + bottom);
        let mut q = vec![0.0; nv];
        q[is] = 1.0;
        q[ir] = -1.0;
        q[n + 2..].fill(mu);
        let mut h = vec![0.0; nv * nv];
        for i in 0..n {
            h[i * nv..i * nv + n].copy_from_slice(&b[i]);
        }
        let (mut a, mut rhs) = (Vec::new(), Vec::new());
        let mut push = |coefs: &[(usize, f64)], r: f64| {
            let start = a.len();
            a.resize(start + nv, 0.0);
            for &(j, v) in coefs {
                a[start + j] += v;
            }
            rhs.push(r);
        };
        let d = |row: usize, sign: f64| (0..n).map(move |j| (j, sign * jac[row][j]));
        for (m, c) in p.cons.iter().enumerate() {
            push(
                &d(m, 1.0).chain([(n + 2 + m, -1.0)]).collect::<Vec<_>>(),
                -c,
            );
        }
        for (i, (_, y)) in p.maxima.iter().enumerate() {
            push(
                &d(nc + i, 1.0).chain([(is, -1.0)]).collect::<Vec<_>>(),
                -(y - y0),
            );
        }
        for (k, (_, y)) in p.minima.iter().enumerate() {
            push(
                &d(nc + nx + k, -1.0).chain([(ir, 1.0)]).collect::<Vec<_>>(),
                y - y0,
            );
        }
        for m in 0..nc {
            push(&[(n + 2 + m, -1.0)], 0.0);
        }
        for j in 0..n {
            push(&[(j, 1.0)], delta.min(1.0 - u[j]));
            push(&[(j, -1.0)], delta.min(u[j]));
        }
        // The start: d = 0, s on its highest maximum, r on its lowest minimum, each v on
        // its constraint's row where that is violated, else on v ≥ 0.
        let mut x0 = vec![0.0; nv];
        x0[is] = top - y0;
        x0[ir] = bottom - y0;
        let first = |set: &[(f64, f64)], v: f64| set.iter().position(|q| q.1 == v);
        let mut w0 = first(&p.maxima, top)
            .zip(first(&p.minima, bottom))
            .map(|(i, k)| vec![nc + i, nc + nx + k]);
        for (m, &c) in p.cons.iter().enumerate() {
            x0[n + 2 + m] = c.max(0.0);
            if let Some(w) = w0.as_mut() {
                w.push(if c > 0.0 {
                    m
                } else {
                    nc + nx + p.minima.len() + m
                });
            }
        }
        Subproblem {
            nv,
            h,
            q,
            a,
            rhs,
            x0,
            w0,
        }
    }

    /// The dense active-set solution ([`super::qp::active_set`]); `None` to fall back.
    fn dense(&self) -> Option<QpSolution> {
        let qp = DenseQp {
            n: self.nv,
            h: &self.h,
            c: &self.q,
            a: &self.a,
            b: &self.rhs,
        };
        active_set(
            &qp,
            self.x0.clone(),
            self.w0.clone()?,
            20 * (self.rhs.len() + 1),
        )
    }

    /// The interior-point solution by clarabel: (x, row multipliers, objective).
    fn clarabel(&self) -> Option<(Vec<f64>, Vec<f64>, f64)> {
        use clarabel::algebra::CscMatrix;
        use clarabel::solver::{
            DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
        };
        let (nv, rows) = (self.nv, self.rhs.len());
        let (mut ai, mut aj, mut av) = (vec![], vec![], vec![]);
        for r in 0..rows {
            for j in 0..nv {
                let v = self.a[r * nv + j];
                if v != 0.0 {
                    ai.push(r);
                    aj.push(j);
                    av.push(v);
                }
            }
        }
        let a = CscMatrix::new_from_triplets(rows, nv, ai, aj, av);
        let pm = upper_triangle(&self.h, nv);
        let cones = [SupportedConeT::NonnegativeConeT(rows)];
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_gap_abs(1e-13)
            .tol_gap_rel(1e-11)
            .tol_feas(1e-11)
            .max_iter(60)
            .build()
            .ok()?;
        let mut solver = DefaultSolver::new(&pm, &self.q, &a, &self.rhs, &cones, settings).ok()?;
        solver.solve();
        let sol = &solver.solution;
        if !matches!(
            sol.status,
            SolverStatus::Solved | SolverStatus::AlmostSolved
        ) {
            return None;
        }
        Some((sol.x.clone(), sol.z.clone(), sol.obj_val))
    }
}

/// The QP's quadratic term for clarabel: the nonzero upper triangle of the dense H (nv×nv).
fn upper_triangle(h: &[f64], nv: usize) -> clarabel::algebra::CscMatrix<f64> {
    let (mut pi, mut pj, mut pv) = (vec![], vec![], vec![]);
    for i in 0..nv {
        for j in i..nv {
            if h[i * nv + j] != 0.0 {
                pi.push(i);
                pj.push(j);
                pv.push(h[i * nv + j]);
            }
        }
    }
    clarabel::algebra::CscMatrix::new_from_triplets(nv, nv, pi, pj, pv)
}

/// Gradient of the Lagrangian Σ λ_i g_i − Σ λ_k g_k + Σ ν_m a_m at a probe, each multiplier
/// of a maximum (minimum) given to the piece of the probe nearest in t.
fn lagrangian_gradient(p: &Probe, jac: &[Vec<f64>], old: &Probe, st: &QpStep) -> Vec<f64> {
    let n = jac.first().map_or(0, |r| r.len());
    let nc = p.cons.len();
    let mut g = vec![0.0; n];
    let nearest = |set: &[(f64, f64)], t: f64| {
        (0..set.len())
            .min_by(|&a, &b| (set[a].0 - t).abs().total_cmp(&(set[b].0 - t).abs()))
            .unwrap_or(0)
    };
    for (m, lam) in st.lam_con.iter().enumerate() {
        for j in 0..n {
            g[j] += lam * jac[m][j];
        }
    }
    for (i, lam) in st.lam_max.iter().enumerate() {
        let r = nc + nearest(&p.maxima, old.maxima[i].0);
        for j in 0..n {
            g[j] += lam * jac[r][j];
        }
    }
    for (k, lam) in st.lam_min.iter().enumerate() {
        let r = nc + p.maxima.len() + nearest(&p.minima, old.minima[k].0);
        for j in 0..n {
            g[j] -= lam * jac[r][j];
        }
    }
    g
}
