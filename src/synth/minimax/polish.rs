//! Newton polish of the minimax's optimality conditions (issue 17): the exchange loop's
//! SOCP on sampled angles yields a design only as accurate as clarabel (about 1e-8
//! relative where the cones cluster around moving maxima), which is not enough to certify
//! 1e-9. Once a round has located the active maxima, the semi-infinite problem's KKT system
//! is solved by Newton to machine precision instead, with the maxima's angles among the
//! unknowns; the design it gives and its multipliers then feed the engine's usual
//! certificate (refined true peak against the rigorous Lagrangian bound), so nothing here
//! has to be trusted.
//!
//! In the engine's scaled variables x̂ (x = S x̂) and objective t̂ = t/T, an active maximum p
//! of field f is the constraint φ_p = c_p·|g_f(θ_p; S x̂)| ≤ t̂ (objective, c_p = w/T) or
//! ≤ ε̂_p (limit, c_p = 1/G_f), with multiplier w_p; an active design constraint i is
//! d_i(x̂) ≤ 0 (or = 0) with multiplier ν_i ([`Design`]). The unknowns (x̂, t̂, θ, w, ν)
//! solve
//!
//! * Σ_p w_p ∇φ_p + Σ_i ν_i ∇d_i = 0 (stationarity in x̂), 1 − Σ_obj w_p = 0 (in t̂);
//! * ∂φ_p/∂θ = 0 (each θ_p a maximum of its field);
//! * φ_p = t̂ or ε̂_p, d_i = 0 (the active set).
//!
//! The field's θ-derivatives come from a five-point stencil (step 2·10⁻⁴ rad: truncation
//! and round-off both near 1e-12 relative for the first derivative); an error there moves
//! the angles, whose effect on the values is of second order. The Newton step is the
//! least-squares solution of minimum norm (SVD), so variables no active constraint
//! involves (a counterweight's mass or inertia the fields do not see) stay where clarabel
//! put them. Multipliers that come out negative drop their constraint and Newton reruns;
//! a maximum the refined scan finds above the polished level joins the set (the caller).

use super::assembly::Round;
pub(super) use super::constraints::Design;
use super::{AffineValue, Engine, Goal, MinimaxError, Multiplier, Solution, Stop};
use crate::numeric::PeriodicPeak;
use crate::synth::exchange::{angle_dist, Status};
use nalgebra::{DMatrix, DVector};

/// A sampled cone moved to a refined maximum, with its multiplier: the constraint
/// c·|g_f(θ; S x̂)| ≤ t̂ (objective, `eps` = None) or ≤ ε̂ (limit).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Term {
    /// The field f.
    pub field: usize,
    /// θ (rad).
    pub theta: f64,
    /// c: the factor of the field (w/T for the objective, 1/G_f for a limit).
    pub c: f64,
    /// ε̂ = ε/G_f for a limit.
    pub eps: Option<f64>,
    /// The multiplier (λ of an objective cone, normalised Σλ = 1; μ̂ of a limit).
    pub weight: f64,
}

/// A polished point: the scaled design and objective, the active maxima at their exact
/// angles with their multipliers, and the active design constraints with theirs.
#[derive(Debug, Clone)]
pub(super) struct Polished {
    /// x̂.
    pub x_hat: Vec<f64>,
    /// t̂.
    pub t_hat: f64,
    /// The active maxima.
    pub terms: Vec<Term>,
    /// The active design constraints (indices into `cons`, the polish's list) and their
    /// multipliers, as Newton works with them.
    pub design: Vec<(usize, f64)>,
    /// The same as indices into [`Engine::design_constraints`]; `None` when the polish
    /// added constraints of its own (a counterweight at the apex of its cones).
    pub design_nu: Option<Vec<(usize, f64)>>,
    /// The largest change of a term's multiplier in the Newton step from the last iterate:
    /// the multipliers' error (Newton converges quadratically).
    pub weight_error: f64,
    /// Whether the optimum is not isolated: the converged Newton system has a null
    /// direction that moves the design ([`flat_design`]).
    pub flat: bool,
}

/// φ = c|g_f(θ; S x̂)| and its derivatives at (θ, x̂).
struct Local {
    phi: f64,
    /// ∂φ/∂θ.
    d1: f64,
    /// ∂²φ/∂θ².
    d2: f64,
    /// ∇_x̂ φ.
    grad: Vec<f64>,
    /// ∂/∂θ ∇_x̂ φ.
    dgrad: Vec<f64>,
    /// ∇²_x̂ φ (2-D fields only; 0 for a scalar).
    hess: Option<DMatrix<f64>>,
}

/// The stencil step (rad).
const STEP: f64 = 2e-4;
/// Newton iterations at most per active set.
const MAX_NEWTON: usize = 40;
/// Active-set passes at most (drops of negative multipliers, additions of violated
/// design constraints).
const MAX_PASSES: usize = 6;
/// A polished design must meet every design constraint to this (scaled) value: its peak is
/// the certificate's upper bound only if it is a design at all.
pub(super) const FEASIBLE: f64 = 1e-12;
/// A design constraint is taken as active at the start when d(x̂) ≥ −this.
const ACTIVE_SLACK: f64 = 1e-5;

impl Engine<'_, '_> {
    /// The local expansion of a term's φ.
    fn local(&self, t: &Term, x_hat: &[f64]) -> Result<Local, MinimaxError> {
        let n = self.n;
        let d = self.pb.fields[t.field].dim();
        let xs: Vec<f64> = x_hat.iter().zip(&self.scale).map(|(a, s)| a * s).collect();
        let vals: Vec<AffineValue> = (-2..=2)
            .map(|k| self.eval(t.field, t.theta + k as f64 * STEP))
            .collect::<Result<_, _>>()?;
        let d1 = |f: &dyn Fn(&AffineValue) -> f64| {
            (f(&vals[0]) - 8.0 * f(&vals[1]) + 8.0 * f(&vals[3]) - f(&vals[4])) / (12.0 * STEP)
        };
        let d2 = |f: &dyn Fn(&AffineValue) -> f64| {
            (-f(&vals[0]) + 16.0 * f(&vals[1]) - 30.0 * f(&vals[2]) + 16.0 * f(&vals[3])
                - f(&vals[4]))
                / (12.0 * STEP * STEP)
        };
        let c = t.c;
        let (mut g, mut g1, mut g2) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        let mut jx = vec![[0.0; 2]; n];
        let mut j1 = vec![[0.0; 2]; n];
        for r in 0..d {
            let gr = |v: &AffineValue| c * v.at(d, &xs)[r];
            g[r] = c * vals[2].at(d, &xs)[r];
            g1[r] = d1(&gr);
            g2[r] = d2(&gr);
            for j in 0..n {
                let a = |v: &AffineValue| c * v.row(r)[j] * self.scale[j];
                jx[j][r] = c * vals[2].row(r)[j] * self.scale[j];
                j1[j][r] = d1(&a);
            }
        }
        if d == 1 {
            let s = if g[0] < 0.0 { -1.0 } else { 1.0 };
            return Ok(Local {
                phi: s * g[0],
                d1: s * g1[0],
                d2: s * g2[0],
                grad: jx.iter().map(|a| s * a[0]).collect(),
                dgrad: j1.iter().map(|a| s * a[0]).collect(),
                hess: None,
            });
        }
        let phi = g[0].hypot(g[1]);
        let e = [g[0] / phi, g[1] / phi];
        let dot = |a: [f64; 2], b: [f64; 2]| a[0] * b[0] + a[1] * b[1];
        let gg1 = dot(g, g1);
        // P g' / φ with P = I − ê êᵀ.
        let pg1 = [
            (g1[0] - e[0] * dot(e, g1)) / phi,
            (g1[1] - e[1] * dot(e, g1)) / phi,
        ];
        let mut hess = DMatrix::zeros(n, n);
        for a in 0..n {
            for b in 0..n {
                hess[(a, b)] = (dot(jx[a], jx[b]) - dot(e, jx[a]) * dot(e, jx[b])) / phi;
            }
        }
        Ok(Local {
            phi,
            d1: gg1 / phi,
            d2: (dot(g1, g1) + dot(g, g2)) / phi - gg1 * gg1 / phi.powi(3),
            grad: jx.iter().map(|a| dot(e, *a)).collect(),
            dgrad: (0..n).map(|j| dot(e, j1[j]) + dot(pg1, jx[j])).collect(),
            hess: Some(hess),
        })
    }

    /// Newton on the KKT system for the given active maxima (their angles and multipliers
    /// the start) from the scaled design x̂ and objective t̂; the active design constraints
    /// are those within [`ACTIVE_SLACK`] of their bound at x̂ (equalities always). Returns
    /// `None` when no active set gives a converged system with multipliers ≥ 0.
    pub(super) fn polish(
        &self,
        terms: &[Term],
        x_hat: &[f64],
        t_hat: f64,
        prox: bool,
    ) -> Result<Option<Polished>, MinimaxError> {
        let cons = self.design_constraints();
        let active: Vec<usize> = (0..cons.len())
            .filter(|&i| cons[i].is_eq() || cons[i].value(x_hat) >= -ACTIVE_SLACK)
            .collect();
        // A counterweight at m̂ = 0 sits at the apex of its cones: there its û is 0 and the
        // two cones (not smooth there) leave the set; the bounds hold m̂ and û at 0.
        let mut extra: Vec<Design> = Vec::new();
        let mut active = active;
        active.retain(|&i| match &cons[i] {
            Design::Radius { m, u, .. } | Design::Body { m, u, .. } => {
                let apex = x_hat[*m] < ACTIVE_SLACK && x_hat[*u].hypot(x_hat[u + 1]) < ACTIVE_SLACK;
                if apex
                    && !extra
                        .iter()
                        .any(|e| matches!(e, Design::Linear { a, .. } if a[0].0 == *u))
                {
                    for k in 0..2 {
                        extra.push(Design::Linear {
                            a: vec![(u + k, 1.0)],
                            r: 0.0,
                            eq: true,
                        });
                    }
                }
                !apex
            }
            _ => true,
        });
        let base = cons.len();
        let cons: Vec<Design> = cons.into_iter().chain(extra).collect();
        active.extend(base..cons.len());
        // Dependent active constraints (a point mass at the radius limit with the envelope
        // of the same radius: I = ρ²m and |u| = ρm imply I·m = |u|²) leave no unique
        // multipliers; each pass keeps only those whose gradients are independent.
        let mut candidates = active;
        let mut terms = terms.to_vec();
        for _ in 0..MAX_PASSES {
            let active = independent(&cons, candidates.clone(), x_hat);
            let Some(p) = self.newton(&terms, &cons, &active, x_hat, t_hat, prox)? else {
                return Ok(None);
            };
            // The most negative multiplier (relative to the objective's, Σλ = 1) leaves.
            let worst_term = p
                .terms
                .iter()
                .enumerate()
                .map(|(k, t)| (k, t.weight))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let worst_design = p
                .design
                .iter()
                .enumerate()
                .filter(|(_, (i, _))| !cons[*i].is_eq())
                .map(|(k, &(_, v))| (k, v))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            const NEG: f64 = -1e-10;
            match (worst_term, worst_design) {
                (Some((k, w)), d) if w < NEG && d.is_none_or(|d| w <= d.1) => {
                    terms.remove(k);
                }
                (_, Some((k, v))) if v < NEG => {
                    // It leaves; a constraint it made dependent may come back.
                    candidates.retain(|&i| i != active[k]);
                }
                _ => {
                    // A design constraint the polished design violates joins the set.
                    let worst = (0..cons.len())
                        .filter(|i| !candidates.contains(i))
                        .map(|i| (i, cons[i].value(&p.x_hat)))
                        .max_by(|a, b| a.1.total_cmp(&b.1));
                    if let Some((i, v)) = worst {
                        if v > FEASIBLE {
                            candidates.push(i);
                            continue;
                        }
                    }
                    // The apex's equalities are not the design cones': no multipliers then.
                    let design = (cons.len() == base).then(|| p.design.clone());
                    return Ok(Some(Polished {
                        design_nu: design,
                        ..p
                    }));
                }
            }
            if terms.iter().all(|t| t.eps.is_some()) {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// Newton on one active set; `None` if it diverges or an angle leaves its maximum's
    /// neighbourhood. With `prox` each step is the proximal one ([`kkt_step`]'s ρ =
    /// [`PROX`]·√|r|∞ on the design's block): the retry where the plain polish fails.
    #[allow(clippy::too_many_arguments)]
    fn newton(
        &self,
        terms: &[Term],
        cons: &[Design],
        active: &[usize],
        x_hat: &[f64],
        t_hat: f64,
        prox: bool,
    ) -> Result<Option<Polished>, MinimaxError> {
        let n = self.n;
        let np = terms.len();
        let ni = active.len();
        let (it, ith, iw, inu) = (n, n + 1, n + 1 + np, n + 1 + 2 * np);
        let mut x = x_hat.to_vec();
        let mut t = t_hat;
        let mut terms = terms.to_vec();
        let start: Vec<f64> = terms.iter().map(|p| p.theta).collect();
        let mut nu = vec![0.0; ni];
        let mut last = f64::INFINITY;
        let mut stalls = 0;
        let mut weight_error = f64::INFINITY;
        let mut flat = false;
        // At the converged system: the step's largest change of a term's multiplier, and
        // whether the optimum is flat.
        let converged = |jac: &DMatrix<f64>, r: &DVector<f64>| {
            let dw = kkt_step(jac, r, n, 0.0).map_or(f64::INFINITY, |s| {
                (0..np).map(|p| s[iw + p].abs()).fold(0.0, f64::max)
            });
            (dw, flat_design(jac, n))
        };
        for _ in 0..MAX_NEWTON {
            let (r, jac) = self.kkt_system(&terms, cons, active, &x, t, &nu)?;
            let res = r.amax();
            if !res.is_finite() {
                return Ok(None);
            }
            if res <= 1e-14 {
                last = res;
                (weight_error, flat) = converged(&jac, &r);
                break;
            }
            if res >= 0.99 * last {
                stalls += 1;
                if stalls >= 3 {
                    last = last.min(res);
                    (weight_error, flat) = converged(&jac, &r);
                    break;
                }
            }
            last = res;
            let rho = if prox { PROX * res.sqrt() } else { 0.0 };
            let Some(step) = kkt_step(&jac, &r, n, rho) else {
                return Ok(None);
            };
            for j in 0..n {
                x[j] += step[j];
            }
            t += step[it];
            for (p, term) in terms.iter_mut().enumerate() {
                term.theta += step[ith + p];
                term.weight += step[iw + p];
            }
            for (k, v) in nu.iter_mut().enumerate() {
                *v += step[inu + k];
            }
            let h = std::f64::consts::TAU / self.s.scan_samples as f64;
            if terms
                .iter()
                .zip(&start)
                .any(|(p, s)| angle_dist(p.theta, *s) > 2.0 * h)
                || !x.iter().all(|v| v.is_finite())
            {
                return Ok(None);
            }
        }
        if !(last <= 1e-6) {
            return Ok(None);
        }
        if !weight_error.is_finite() {
            let (r, jac) = self.kkt_system(&terms, cons, active, &x, t, &nu)?;
            (weight_error, flat) = converged(&jac, &r);
        }
        for term in &mut terms {
            term.theta = term.theta.rem_euclid(std::f64::consts::TAU);
        }
        Ok(Some(Polished {
            x_hat: x,
            t_hat: t,
            terms,
            design: active.iter().copied().zip(nu).collect(),
            design_nu: None,
            weight_error,
            flat,
        }))
    }

    /// The Newton system at (x̂, t̂, θ, w, ν) (module doc): the residual r of the
    /// optimality conditions and its Jacobian, the unknowns in the order x̂, t̂, θ, w, ν.
    fn kkt_system(
        &self,
        terms: &[Term],
        cons: &[Design],
        active: &[usize],
        x: &[f64],
        t: f64,
        nu: &[f64],
    ) -> Result<(DVector<f64>, DMatrix<f64>), MinimaxError> {
        let n = self.n;
        let np = terms.len();
        let (it, ith, iw, inu) = (n, n + 1, n + 1 + np, n + 1 + 2 * np);
        let size = inu + active.len();
        let mut grad_d = vec![0.0; n];
        let mut r = DVector::<f64>::zeros(size);
        let mut jac = DMatrix::<f64>::zeros(size, size);
        let mut hxx = DMatrix::<f64>::zeros(n, n);
        r[it] = 1.0;
        for (p, term) in terms.iter().enumerate() {
            let l = self.local(term, x)?;
            let w = term.weight;
            for j in 0..n {
                r[j] += w * l.grad[j];
                jac[(j, ith + p)] = w * l.dgrad[j];
                jac[(j, iw + p)] = l.grad[j];
                jac[(ith + p, j)] = l.dgrad[j];
                jac[(iw + p, j)] = l.grad[j];
            }
            if let Some(h) = &l.hess {
                hxx += w * h;
            }
            r[ith + p] = l.d1;
            jac[(ith + p, ith + p)] = l.d2;
            jac[(iw + p, ith + p)] = l.d1;
            match term.eps {
                None => {
                    r[it] -= w;
                    jac[(it, iw + p)] = -1.0;
                    r[iw + p] = l.phi - t;
                    jac[(iw + p, it)] = -1.0;
                }
                Some(e) => r[iw + p] = l.phi - e,
            }
        }
        for (k, &i) in active.iter().enumerate() {
            cons[i].grad(x, &mut grad_d);
            cons[i].add_hessian(x, nu[k], &mut hxx);
            for j in 0..n {
                r[j] += nu[k] * grad_d[j];
                jac[(j, inu + k)] = grad_d[j];
                jac[(inu + k, j)] = grad_d[j];
            }
            r[inu + k] = cons[i].value(x);
        }
        jac.view_mut((0, 0), (n, n)).copy_from(&hxx);
        Ok((r, jac))
    }
}

/// Newton polishes at most per solve.
pub(super) const MAX_POLISH: usize = 3;

/// A solve's polished optimality conditions, the start of a neighbouring solve's Newton:
/// the scaled design x̂, t̂ and the active maxima with their multipliers.
pub(super) struct KktStart {
    pub(super) x_hat: Vec<f64>,
    pub(super) t_hat: f64,
    pub(super) terms: Vec<Term>,
}

/// A polished design with its certificate parts (caller's units).
pub(super) struct PolishOutcome {
    pub(super) x: Vec<f64>,
    pub(super) pk: Vec<Option<PeriodicPeak>>,
    /// V: the refined objective peak at x.
    pub(super) value: f64,
    /// The limits' relative violation at x.
    pub(super) lim_rel: f64,
    /// L, rigorous, and its residual part.
    pub(super) lower: f64,
    pub(super) lower_err: f64,
    /// The polished x̂ and t̂ (before the projection) and active maxima: the start of a
    /// neighbouring solve's Newton.
    pub(super) x_hat: Vec<f64>,
    pub(super) t_hat: f64,
    pub(super) terms: Vec<Term>,
    /// The active maxima's multipliers in the caller's units.
    pub(super) multipliers: Vec<Multiplier>,
    /// The polish's [`Polished::flat`].
    pub(super) flat: bool,
}

/// The polished terms' multipliers in the caller's units (`t_scale` T): weight T·λ·c with
/// λ normalised to Σλ = 1 over the objective's terms ([`Multiplier`]).
fn multipliers(p: &Polished, t_scale: f64) -> Vec<Multiplier> {
    let kept: f64 = p
        .terms
        .iter()
        .filter(|t| t.eps.is_none())
        .map(|t| t.weight)
        .sum();
    p.terms
        .iter()
        .map(|t| Multiplier {
            field: t.field,
            angle: t.theta,
            weight: t_scale * t.c * t.weight / kept,
            weight_error: t_scale * t.c * p.weight_error / kept,
            limit: t.eps.is_some(),
        })
        .collect()
}

impl<'p, 'a> Engine<'p, 'a> {
    /// The certified solution of a polish (`optimal`), its active maxima the sampled
    /// angles (the other fields keep theirs), and the conditions for a neighbour's start.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn polished_solution(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
        mut sets: Vec<Vec<(f64, AffineValue)>>,
        po: PolishOutcome,
        round: usize,
        iters: u32,
        solver_status: String,
    ) -> Result<(Solution, KktStart), MinimaxError> {
        for (f, set) in sets.iter_mut().enumerate() {
            if po.terms.iter().any(|t| t.field == f) {
                set.clear();
            }
        }
        for t in &po.terms {
            self.insert(&mut sets[t.field], t.field, t.theta)?;
        }
        let mut sol = self.finish(
            goal,
            limits,
            &sets,
            &po.x,
            po.pk,
            po.value,
            (po.lower, po.lower_err, true),
            Status::Optimal,
            Stop::Converged,
            None,
            round,
            iters,
            solver_status,
        )?;
        sol.multipliers = po.multipliers;
        sol.flat = po.flat;
        Ok((
            sol,
            KktStart {
                x_hat: po.x_hat,
                t_hat: po.t_hat,
                terms: po.terms,
            },
        ))
    }

    /// A round's active set polished by Newton ([`polish`]) into a candidate certificate
    /// ([`Engine::polish_certify`]): the round's cones with multiplier ≥ 1e-6 whose refined
    /// maxima are within 1e-5 (relative) of their bound at x start it. `None` when Newton fails (the
    /// caller's loop goes on).
    pub(super) fn try_polish(
        &self,
        list: &[(usize, f64)],
        limits: &[(usize, f64)],
        rd: &Round,
        x: &[f64],
        pk: &[Option<PeriodicPeak>],
        prox: bool,
    ) -> Result<Option<PolishOutcome>, MinimaxError> {
        let n = self.n;
        let Some(all) = self.round_terms(rd, pk) else {
            return Ok(None);
        };
        let t_hat = rd.res.x[n];
        let level = |t: &Term, th: f64| t.eps.unwrap_or(th);
        let value_at = |t: &Term, x: &[f64]| -> Result<f64, MinimaxError> {
            let d = self.pb.fields[t.field].dim();
            Ok(t.c * self.eval(t.field, t.theta)?.magnitude(d, x))
        };
        let mut terms = Vec::new();
        for t in all {
            if t.weight >= 1e-6 && value_at(&t, x)? >= (1.0 - 1e-5) * level(&t, t_hat) {
                terms.push(t);
            }
        }
        let x_hat: Vec<f64> = x.iter().zip(&self.scale).map(|(v, s)| v / s).collect();
        self.polish_certify(list, limits, terms, &x_hat, t_hat, rd.t_scale, prox)
    }

    /// Newton from the given active maxima, design x̂ and objective t̂ ([`polish`]); the
    /// polished design (projected) is scanned for its true peaks, a maximum found above the
    /// polished level joins the set and Newton reruns (at most twice), and the lower bound
    /// is the rigorous Lagrangian bound ([`Engine::lagrangian_bound`]) at the polished
    /// angles and multipliers. `None` when Newton fails.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn polish_certify(
        &self,
        list: &[(usize, f64)],
        limits: &[(usize, f64)],
        mut terms: Vec<Term>,
        x_hat: &[f64],
        t_hat: f64,
        t_scale: f64,
        prox: bool,
    ) -> Result<Option<PolishOutcome>, MinimaxError> {
        if !terms.iter().any(|t| t.eps.is_none()) {
            return Ok(None);
        }
        let mut x_hat = x_hat.to_vec();
        let mut t_hat = t_hat;
        let nf = self.pb.fields.len();
        for pass in 0..3 {
            let Some(p) = self.polish(&terms, &x_hat, t_hat, prox)? else {
                return Ok(None);
            };
            let xp = self.project(
                &p.x_hat
                    .iter()
                    .zip(&self.scale)
                    .map(|(v, s)| v * s)
                    .collect::<Vec<_>>(),
            );
            // The upper bound is a design's peak only if it is a design.
            if self.design_violation(&xp) > FEASIBLE {
                return Ok(None);
            }
            let mut pkp: Vec<Option<PeriodicPeak>> = vec![None; nf];
            for &(f, _) in list.iter().chain(limits) {
                if pkp[f].is_none() {
                    pkp[f] = Some(self.scan(f, &xp)?);
                }
            }
            let peak_of = |f: usize| pkp[f].as_ref().expect("scanned").peak.fx;
            let value = list
                .iter()
                .map(|&(f, w)| w * peak_of(f))
                .fold(0.0, f64::max);
            let lim_rel = limits
                .iter()
                .map(|&(f, e)| (peak_of(f) - e).max(0.0) / self.lim_floor(f, e))
                .fold(0.0, f64::max);
            let missing = self.missing_maxima(list, limits, &p, &pkp, t_scale);
            if !missing.is_empty() && pass < 2 {
                terms = p.terms.clone();
                terms.extend(missing);
                x_hat = p.x_hat.clone();
                t_hat = p.t_hat;
                continue;
            }
            // Newton's own dual point first; clarabel's Lagrangian SOCPs where it falls short.
            let mut bound = self.kkt_bound(&p, &xp, t_scale)?;
            if bound.is_none_or(|b| value - b.0 > self.s.rel_tol * value) {
                if let Some(b) = self.lagrangian_bound(&p.terms, &xp, t_scale)? {
                    if bound.is_none_or(|a| b.0 > a.0) {
                        bound = Some(b);
                    }
                }
            }
            let Some((lower, lower_err)) = bound else {
                return Ok(None);
            };
            return Ok(Some(PolishOutcome {
                multipliers: multipliers(&p, t_scale),
                flat: p.flat,
                x: xp,
                pk: pkp,
                value,
                lim_rel,
                lower,
                lower_err,
                x_hat: p.x_hat,
                t_hat: p.t_hat,
                terms: p.terms,
            }));
        }
        Ok(None)
    }

    /// The refined maxima of the polished design above the polished level t̂·T (objective)
    /// or above their limit, by more than 0.1 `rel_tol`, that the polished set lacks (none of
    /// its angles of the field within a scan step): they join it with weight 0.
    fn missing_maxima(
        &self,
        list: &[(usize, f64)],
        limits: &[(usize, f64)],
        p: &Polished,
        pkp: &[Option<PeriodicPeak>],
        t_scale: f64,
    ) -> Vec<Term> {
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        let mut missing = Vec::new();
        let known = |f: usize, th: f64| {
            p.terms
                .iter()
                .any(|t| t.field == f && angle_dist(t.theta, th) <= h)
        };
        let t_level = p.t_hat * t_scale;
        for &(f, w) in list {
            for m in &pkp[f].as_ref().expect("scanned").maxima {
                if w * m.fx > t_level * (1.0 + 0.1 * self.s.rel_tol) && !known(f, m.x) {
                    missing.push(Term {
                        field: f,
                        theta: m.x,
                        c: w / t_scale,
                        eps: None,
                        weight: 0.0,
                    });
                }
            }
        }
        for &(f, e) in limits {
            for m in &pkp[f].as_ref().expect("scanned").maxima {
                if m.fx > e * (1.0 + 0.1 * self.s.rel_tol) && !known(f, m.x) {
                    let g = self.g_ref()[f];
                    missing.push(Term {
                        field: f,
                        theta: m.x,
                        c: 1.0 / g,
                        eps: Some(e / g),
                        weight: 0.0,
                    });
                }
            }
        }
        missing
    }
}

/// The Newton step J Δ = −r. Unknowns whose column of J is zero (to 1e-14 of the largest
/// entry: a variable no active constraint involves) stay fixed; the rest is solved by LU
/// with full pivoting where its pivots show full rank (the smallest |U_kk| above
/// [`RANK_CUT`] of the largest), else in least squares of minimum norm by SVD (singular
/// values below [`RANK_CUT`] of the largest cut) wherever that solves the system as well as
/// LU (its residual within 10× LU's, plus 1e-10 of |r|; LU's step otherwise, or where SVD
/// fails).
///
/// A rank-deficient J whose null space is not a variable of its own but a combination of
/// live ones is a flat direction of the optimum: the felling head's crank counterweight U
/// against the order-1 balancer pair B₁ (both move the force along the slider axis and the
/// weight torque alike; they differ only across the axis, where the active maxima at φ = 0
/// and π see nothing). LU's step then has an arbitrary component along that direction
/// (finite: the system is consistent to round-off), so Newton wandered along the optimal
/// face, converged only linearly and left the face where other maxima rise above the level:
/// the polish failed and the exchange loop ran out of rounds a few 1e-8 short (issue 38).
/// The minimum-norm step stays where the exchange loop put the design.
fn kkt_step(jac: &DMatrix<f64>, r: &DVector<f64>, n: usize, rho: f64) -> Option<DVector<f64>> {
    let size = r.len();
    let (live, sub) = live_block(jac, n, rho);
    let rhs = DVector::from_fn(live.len(), |a, _| -r[live[a]]);
    let lu = sub.clone().full_piv_lu();
    let by_lu = lu
        .solve(&rhs)
        .filter(|s| s.iter().all(|v| v.is_finite()) && s.amax() < 1e8);
    let solved = match by_lu {
        Some(s) if full_rank(&lu) => s,
        by_lu => {
            let svd = sub.clone().svd(true, true);
            let cut = RANK_CUT * svd.singular_values.max();
            let least = svd.solve(&rhs, cut).ok();
            match (by_lu, least) {
                (Some(s), Some(m)) => {
                    // The minimum-norm step where it solves J Δ = −r as well as LU's.
                    let miss = |d: &DVector<f64>| (&sub * d - &rhs).norm();
                    if miss(&m) <= 10.0 * miss(&s) + 1e-10 * rhs.norm() {
                        m
                    } else {
                        s
                    }
                }
                (s, m) => m.or(s)?,
            }
        }
    };
    let mut step = DVector::zeros(size);
    for (a, &j) in live.iter().enumerate() {
        step[j] = solved[a];
    }
    Some(step)
}

/// Whether the converged Newton system J of the optimality conditions (unknowns x̂ first, `n`
/// of them) leaves the design free to move: a singular value of J's live block below
/// [`RANK_CUT`] of the largest whose singular vector has at least a tenth of its length in
/// x̂. Such a null direction moves the design along the optimal set without changing the
/// conditions to first order: the optimum is not unique (a counterweight that buys nothing,
/// the felling head's crank counterweight against its balancer pair). A null direction in
/// the angles or multipliers alone (a tie of maxima, a weakly active one) is not.
fn flat_design(jac: &DMatrix<f64>, n: usize) -> bool {
    let (live, sub) = live_block(jac, n, 0.0);
    // Full rank by LU's pivots (the common case) needs no SVD.
    if full_rank(&sub.clone().full_piv_lu()) {
        return false;
    }
    let svd = sub.svd(false, true);
    let Some(vt) = svd.v_t else {
        return false;
    };
    let cut = RANK_CUT * svd.singular_values.max();
    svd.singular_values.iter().enumerate().any(|(k, &sv)| {
        let in_x: f64 = live
            .iter()
            .enumerate()
            .filter(|&(_, &j)| j < n)
            .map(|(a, _)| vt[(k, a)] * vt[(k, a)])
            .sum();
        sv <= cut && in_x.sqrt() >= 0.1
    })
}

/// J's live block: the unknowns whose column of J is not zero (to 1e-14 of its largest
/// entry: a variable no active constraint involves), with ρ·max|J| added to the diagonal of
/// the design's first `n` unknowns (the proximal step, [`PROX`]; 0 for Newton's own).
fn live_block(jac: &DMatrix<f64>, n: usize, rho: f64) -> (Vec<usize>, DMatrix<f64>) {
    let big = jac.amax();
    let live: Vec<usize> = (0..jac.ncols())
        .filter(|&j| jac.column(j).amax() > 1e-14 * big)
        .collect();
    let prox = |j: usize| if j < n { rho * big } else { 0.0 };
    let k = live.len();
    let sub = DMatrix::from_fn(k, k, |a, b| {
        jac[(live[a], live[b])] + if a == b { prox(live[a]) } else { 0.0 }
    });
    (live, sub)
}

/// Whether LU's pivots show full rank: the smallest |U_kk| above [`RANK_CUT`] of the largest.
fn full_rank(lu: &nalgebra::linalg::FullPivLU<f64, nalgebra::Dyn, nalgebra::Dyn>) -> bool {
    let pivots = lu.u().diagonal().abs();
    pivots.min() > RANK_CUT * pivots.max()
}

/// The proximal weight of the retry ([`Engine::newton`] with `prox`): ρ = PROX·√|r|∞ times
/// the largest entry of J is added to the design's diagonal block of the Newton system
/// (`kkt_step`), so each step also keeps the design near the last one.
///
/// It is there for a flat direction of the optimum (the felling head's crank counterweight
/// against its order-1 balancer pair, `kkt_step`) where J is nearly singular while the
/// angles settle: the plain step's component along the flat direction is the residual's
/// over the small singular value, so Newton drifts along the optimal face, converges only
/// linearly, and lands where maxima it does not hold rise above the level. The proximal
/// step bounds that component by |r|/ρ ~ √|r| (the drift sums to little as |r| falls) and
/// leaves the other directions' steps within O(ρ) of Newton's: convergence stays
/// superlinear (the stabilised Newton of non-isolated solutions: Yamashita–Fukushima,
/// Wright's stabilised SQP). The point it reaches solves the same optimality conditions to
/// the same 1e-14 and is certified the same way: nothing rests on ρ.
const PROX: f64 = 1.0;

/// The numerical rank's threshold of the Newton system ([`kkt_step`]): a pivot or a singular
/// value below this fraction of the largest counts as zero.
const RANK_CUT: f64 = 1e-13;

/// The active constraints whose gradients at x̂ are independent, kept in order (equalities
/// first): each one's gradient, less its projection on the span of those kept, must keep
/// 1e-8 of its norm (Gram–Schmidt).
fn independent(cons: &[Design], active: Vec<usize>, x_hat: &[f64]) -> Vec<usize> {
    let n = x_hat.len();
    let mut order = active;
    order.sort_by_key(|&i| !cons[i].is_eq());
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut kept = Vec::new();
    let mut g = vec![0.0; n];
    for i in order {
        cons[i].grad(x_hat, &mut g);
        let norm = g.iter().map(|v| v * v).sum::<f64>().sqrt();
        for b in &basis {
            let p: f64 = g.iter().zip(b).map(|(a, b)| a * b).sum();
            g.iter_mut().zip(b).for_each(|(a, b)| *a -= p * b);
        }
        let rest = g.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > 0.0 && rest > 1e-8 * norm {
            basis.push(g.iter().map(|v| v / rest).collect());
            kept.push(i);
        }
    }
    kept.sort_unstable();
    kept
}
