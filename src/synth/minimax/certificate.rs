//! The certificate: rigorous lower bounds of the optimum (the Lagrangian bound at a round's
//! dual or at Newton's multipliers, made rigorous by weak duality), and the solution with
//! its gap and error bounds (`finish`).

use super::assembly::Round;
use super::polish::{self, Design, Term};
use super::validate::bad;
use super::{AffineValue, Engine, ErrorBound, Goal, MinimaxError, Solution, Stop};
use crate::numeric::PeriodicPeak;
use crate::synth::conic::{dual_lower_bound, run_clarabel_with, Rows};
use crate::synth::exchange::{angle_dist, Status};
use clarabel::algebra::CscMatrix;
use clarabel::solver::SolverStatus;

impl<'p, 'a> Engine<'p, 'a> {
    /// A Lagrangian lower bound of a peak goal from a round's dual, with the sampled angles
    /// moved to the refined maxima at x. For weights λ_k ≥ 0 with Σλ = 1 (objective cones)
    /// and μ_l ≥ 0 (limit cones), every design y meeting the limits at all angles has
    /// max_θ ‖ĝ(θ; y)‖ ≥ Σ_k λ_k ‖ĝ(θ'_k; y)‖ + Σ_l μ_l (‖ĥ(θ'_l; y)‖ − ε̂_l)
    /// at any angles θ', so the minimum of the right side over the design constraints (a
    /// small SOCP: one cone per distinct angle, min Σλ_k s_k + Σμ_l s_l s.t. ‖ĝ_k‖ ≤ s_k) is a
    /// lower bound. λ, μ are the round's duals (z₀ of each cone, normalised by Σ z₀ over the
    /// objective cones), summed over the sampled angles that move to one refined maximum.
    /// The bound is stationary in λ (at the optimum all active ‖ĝ_k‖ are equal) and in the
    /// angles (the field is stationary in θ at a maximum), so their errors enter at second
    /// order, while the sampled SOCP's own bound needs angles clustered around each maximum
    /// (nearly parallel cones, which cost clarabel accuracy) and carries the residual of its
    /// objective variable. Returns (bound, its residual part), caller's units, made rigorous
    /// by [`dual_lower_bound`] (s_k ≤ c·G_f over the design box); `None` if it fails.
    pub(super) fn dual_bound(
        &self,
        rd: &Round,
        x: &[f64],
        pk: &[Option<PeriodicPeak>],
    ) -> Result<Option<(f64, f64)>, MinimaxError> {
        match self.round_terms(rd, pk) {
            Some(terms) => self.lagrangian_bound(&terms, x, rd.t_scale),
            None => Ok(None),
        }
    }

    /// A round's cones with their multipliers (z₀ of each, normalised by Σ z₀ over the
    /// objective cones), moved to the refined maximum of their field within two scan steps
    /// and merged there; weights ≤ 1e-9 dropped. `None` without objective weight.
    pub(super) fn round_terms(&self, rd: &Round, pk: &[Option<PeriodicPeak>]) -> Option<Vec<Term>> {
        let z = &rd.res.z;
        let sum = rd.objective_weight();
        if !(sum > 0.0) {
            return None;
        }
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        // (field, angle, c, ε̂) → weight, merged over the tags that move to one maximum.
        let mut terms: Vec<Term> = Vec::new();
        for t in &rd.tags {
            let lam = z[t.row].max(0.0) / sum;
            // Weights of inactive cones (interior-point noise) are dropped: any subset of
            // the terms still gives a lower bound (each dropped term is ≥ 0 or, for a
            // limit, ≤ 0 at every admissible design).
            if lam <= 1e-9 {
                continue;
            }
            let f = t.field;
            let theta = pk[f]
                .as_ref()
                .and_then(|p| {
                    p.maxima
                        .iter()
                        .map(|m| (angle_dist(m.x, t.theta), m.x))
                        .filter(|m| m.0 <= 2.0 * h)
                        .min_by(|a, b| a.0.total_cmp(&b.0))
                })
                .map_or(t.theta, |m| m.1);
            match terms
                .iter_mut()
                .find(|e| e.field == f && e.theta == theta && e.c == t.c && e.eps == t.eps)
            {
                Some(e) => e.weight += lam,
                None => terms.push(Term {
                    field: f,
                    theta,
                    c: t.c,
                    eps: t.eps,
                    weight: lam,
                }),
            }
        }
        Some(terms)
    }

    /// The Lagrangian lower bound (see [`Engine::dual_bound`]) of the given terms (their
    /// negative weights taken as 0), caller's units with the objective scale T.
    pub(super) fn lagrangian_bound(
        &self,
        terms: &[Term],
        x: &[f64],
        t_scale: f64,
    ) -> Result<Option<(f64, f64)>, MinimaxError> {
        let n = self.n;
        let Some(terms) = Self::bound_terms(terms) else {
            return Ok(None);
        };
        let k = terms.len();
        let nv = n + k;
        let mut rows = Rows::default();
        let mut q = vec![0.0; nv];
        let mut xb = self.xbound.clone();
        let mut cst = 0.0;
        for (i, t) in terms.iter().enumerate() {
            let (f, theta, c, eps, lam) = (t.field, t.theta, t.c, t.eps, t.weight);
            let d = self.pb.fields[f].dim();
            let v = self.eval(f, theta)?;
            q[n + i] = lam;
            if let Some(e) = eps {
                cst -= lam * e;
            }
            xb.push(c * self.g_ref()[f]);
            self.field_cone(&mut rows, &v, d, c, Some(n + i), 0.0);
        }
        self.design_rows(&mut rows);
        let built = rows.build(nv, CscMatrix::zeros((nv, nv)), q);
        // The linearised form: ‖ĝ‖ ≥ ⟨ν, ĝ⟩ with ν the field's direction at x — a linear
        // objective over the design constraints, tight where one maximum meets a curved
        // constraint (the norm form lets the design slide along it there).
        let (ql, cl) = self.linearised(&terms, x)?;
        let mut lrows = Rows::default();
        self.design_rows(&mut lrows);
        let lin = lrows.build(n, CscMatrix::zeros((n, n)), ql);
        let mut best: Option<(f64, f64)> = None;
        for (bt, xbb, c0) in [(&built, &xb, cst), (&lin, &self.xbound, cl)] {
            let res = run_clarabel_with(bt, 1e-11, |g| g.clamp(1e-11, 1e-8), false)
                .map_err(|e| bad("clarabel", e))?;
            // The bound rests on weak duality at the dual point (`dual_lower_bound`), not
            // on clarabel's claim: a reduced-accuracy end is usable.
            if !matches!(
                res.status,
                SolverStatus::Solved | SolverStatus::AlmostSolved
            ) {
                continue;
            }
            let (lb, pen) = dual_lower_bound(bt, &res.z, xbb);
            if lb.is_finite() && best.is_none_or(|b| lb + c0 > b.0) {
                best = Some((lb + c0, pen));
            }
        }
        let _ = k;
        Ok(best.map(|(lb, pen)| (t_scale * lb, t_scale * pen)))
    }

    /// The terms with positive weight, the objective's
    /// renormalised to Σλ = 1 (another admissible choice; the dropped mass would otherwise
    /// lower the bound by itself times V); `None` without objective weight.
    pub(super) fn bound_terms(terms: &[Term]) -> Option<Vec<Term>> {
        let mut terms: Vec<Term> = terms.iter().filter(|t| t.weight > 0.0).cloned().collect();
        let kept: f64 = terms
            .iter()
            .filter(|t| t.eps.is_none())
            .map(|t| t.weight)
            .sum();
        if !(kept > 0.0) {
            return None;
        }
        terms.iter_mut().for_each(|t| t.weight /= kept);
        Some(terms)
    }

    /// The linearised Lagrangian of the terms at x: Σ_k λ_k ⟨ν_k, ĝ_k(x̂')⟩ − Σ_l μ_l ε̂_l
    /// = qᵀx̂' + c (ν_k the field's direction at x, |ν_k| = 1), a lower bound of the
    /// Lagrangian at every design x̂'. Returns (q, c).
    pub(super) fn linearised(
        &self,
        terms: &[Term],
        x: &[f64],
    ) -> Result<(Vec<f64>, f64), MinimaxError> {
        let (mut ql, mut cl) = (vec![0.0; self.n], 0.0);
        for t in terms {
            let (f, theta, c, eps, lam) = (t.field, t.theta, t.c, t.eps, t.weight);
            let d = self.pb.fields[f].dim();
            let v = self.eval(f, theta)?;
            let g = v.at(d, x);
            let norm = g[..d].iter().map(|a| a * a).sum::<f64>().sqrt();
            if let Some(e) = eps {
                cl -= lam * e;
            }
            if !(norm > 0.0) {
                continue;
            }
            for (r, gr) in g.iter().enumerate().take(d) {
                let kk = lam * c * gr / norm;
                cl += kk * v.b[r];
                for (j, a) in v.row(r).iter().enumerate() {
                    ql[j] += kk * a * self.scale[j];
                }
            }
        }
        Ok((ql, cl))
    }

    /// The linearised Lagrangian bound of a polish with the dual point of the design cones
    /// formed from Newton's multipliers ν_i instead of a clarabel solve: min qᵀx̂ + c over
    /// the design constraints is bounded by weak duality ([`dual_lower_bound`], rigorous at
    /// any dual point) at z_i = ν_i (a linear row), ν(1, −û/|û|) (the radius cone
    /// s = (k m̂ + c, û)), ν/2·(s₀, −s_t) (the body cone s = (x + m̂, 2û, x − m̂),
    /// x = Î − p m̂ + q; the rim s = (w + 1, 2m̂, w − 1), w = p m̂ − q Î). With
    /// multipliers accurate to round-off this is tight where a clarabel solve is not: the
    /// limits' multipliers can be large near the front's end, and the bound is then a small
    /// difference of large terms. Caller's units; `None` when the polish has no design
    /// multipliers.
    pub(super) fn kkt_bound(
        &self,
        p: &polish::Polished,
        x: &[f64],
        t_scale: f64,
    ) -> Result<Option<(f64, f64)>, MinimaxError> {
        let (Some(terms), Some(design)) = (Self::bound_terms(&p.terms), p.design_nu.as_ref())
        else {
            return Ok(None);
        };
        let (ql, cl) = self.linearised(&terms, x)?;
        let mut rows = Rows::default();
        self.design_rows(&mut rows);
        let lin = rows.build(self.n, CscMatrix::zeros((self.n, self.n)), ql);
        let cons = self.design_constraints();
        // The rows of `design_rows` are those of `design_constraints`, in order: a linear
        // constraint one row, the radius cone three, the body cone four.
        let rows_of = |d: &Design| match d {
            Design::Linear { .. } => 1,
            Design::Radius { .. } | Design::Rim { .. } => 3,
            Design::Body { .. } => 4,
        };
        if cons.iter().map(rows_of).sum::<usize>() != lin.b.len() {
            return Ok(None);
        }
        let mut z = vec![0.0; lin.b.len()];
        let xh = &p.x_hat;
        let mut at = 0;
        for (i, d) in cons.iter().enumerate() {
            let nu = design.iter().find(|e| e.0 == i).map_or(0.0, |e| e.1);
            match d {
                Design::Linear { .. } => {
                    z[at] = nu;
                    at += 1;
                }
                Design::Radius { u, .. } => {
                    let r = xh[*u].hypot(xh[u + 1]);
                    if nu != 0.0 && r > 0.0 {
                        z[at] = nu;
                        z[at + 1] = -nu * xh[*u] / r;
                        z[at + 2] = -nu * xh[u + 1] / r;
                    }
                    at += 3;
                }
                Design::Body { m, u, i, p, q } => {
                    let h = 0.5 * nu;
                    let xi = xh[*i] - p * xh[*m] + q;
                    z[at] = h * (xi + xh[*m]);
                    z[at + 1] = -h * 2.0 * xh[*u];
                    z[at + 2] = -h * 2.0 * xh[u + 1];
                    z[at + 3] = -h * (xi - xh[*m]);
                    at += 4;
                }
                Design::Rim { m, i, p, q } => {
                    let (h, w) = (0.5 * nu, p * xh[*m] - q * xh[*i]);
                    z[at] = h * (w + 1.0);
                    z[at + 1] = -h * 2.0 * xh[*m];
                    z[at + 2] = -h * (w - 1.0);
                    at += 3;
                }
            }
        }
        let (lb, pen) = dual_lower_bound(&lin, &z, &self.xbound);
        Ok(lb
            .is_finite()
            .then_some((t_scale * (lb + cl), t_scale * pen)))
    }

    /// The quadrature error of an RMS objective's optimum: at the design (|R_N − R_{N/2}|)
    /// and, since the optimum of the exact RMS may lie elsewhere, over every design of the
    /// box (‖x̂‖² ≤ Σ x̂_max², the form's change, [`Engine::rms_uniform_error`]); the larger.
    fn rms_quadrature_error(&self, f: usize, x: &[f64], value: f64) -> f64 {
        let at_x = self.rms(f, x).1;
        let xhat_sq: f64 = x
            .iter()
            .zip(&self.scale)
            .map(|(x, s)| (x / s).powi(2))
            .sum();
        let box_sq: f64 = self.xbound.iter().map(|b| b * b).sum();
        let reach = if box_sq.is_finite() {
            box_sq.max(xhat_sq)
        } else {
            xhat_sq
        };
        at_x.max(self.rms_uniform_error(f, reach, value))
    }

    /// An RMS objective whose grid met its cap before its form converged is not certified:
    /// its status drops to `Inaccurate`, with a note saying so.
    fn rms_claim(
        &self,
        goal: &Goal,
        status: Status,
        note: Option<String>,
    ) -> (Status, Option<String>) {
        let Goal::MinRms(f) = goal else {
            return (status, note);
        };
        let g = self.rms_grid(*f);
        if g.converged || status != Status::Optimal {
            return (status, note);
        }
        let why = format!(
            "the RMS quadrature did not converge within {} angles (the field's mean-square form still moved by {:.1e} of its size: a field too sharp near a fold); its error is stated, not certified",
            g.values.len(),
            g.form_change / g.form_size
        );
        let note = Some(match note {
            Some(n) => format!("{n}; {why}"),
            None => why,
        });
        (Status::Inaccurate, note)
    }

    /// The solution of one round with its figures and error bounds.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn finish(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
        sets: &[Vec<(f64, AffineValue)>],
        x: &[f64],
        mut pk: Vec<Option<PeriodicPeak>>,
        value: f64,
        (lower, solver, rigorous): (f64, f64, bool),
        status: Status,
        stop: Stop,
        note: Option<String>,
        round: usize,
        iters: u32,
        solver_status: String,
    ) -> Result<Solution, MinimaxError> {
        let (status, note) = self.rms_claim(goal, status, note);
        let nf = self.pb.fields.len();
        let mut peaks = Vec::with_capacity(nf);
        for (f, slot) in pk.iter_mut().enumerate() {
            if slot.is_none() {
                *slot = Some(self.scan(f, x)?);
            }
            peaks.push(self.field_peak(f, x, slot.as_ref().expect("set"), limits)?);
        }
        // Evaluation error at the objective's sampled angles.
        let sampled_err = |f: usize| {
            sets[f]
                .iter()
                .map(|(t, v)| self.eval_error(f, v, *t, x))
                .fold(0.0, f64::max)
        };
        let (evaluation, refinement, quadrature) = match goal {
            Goal::MinPeak(list) => {
                list.iter()
                    .fold((0.0, 0.0, 0.0), |acc: (f64, f64, f64), &(f, w)| {
                        let p = pk[f].as_ref().expect("scanned");
                        let e_peak = peaks[f].error - p.error;
                        (
                            acc.0.max(w * e_peak.max(sampled_err(f))),
                            acc.1.max(w * p.error),
                            0.0,
                        )
                    })
            }
            Goal::MinRms(f) => {
                let vals = &self.rms_grid(*f).values;
                let nn = vals.len();
                let e = vals
                    .iter()
                    .enumerate()
                    .map(|(k, v)| {
                        self.eval_error(*f, v, k as f64 * std::f64::consts::TAU / nn as f64, x)
                    })
                    .fold(0.0, f64::max);
                (e, 0.0, self.rms_quadrature_error(*f, x, value))
            }
            Goal::MinMass => (
                (self.pb.counterweights.len() as f64 + 1.0) * f64::EPSILON * value,
                0.0,
                0.0,
            ),
        };
        // |V − L|: V < L happens when the design exceeds a limit within its tolerance (it
        // is then optimal for a slightly wider limit), and the bound must cover that too.
        let sampling = (value - lower).abs();
        let error = ErrorBound {
            sampling,
            solver,
            evaluation,
            refinement,
            quadrature,
            // A rigorous L already contains the solver's part.
            total: sampling
                + if rigorous { 0.0 } else { solver }
                + evaluation
                + refinement
                + quadrature,
        };
        Ok(Solution {
            status,
            stop,
            x: x.to_vec(),
            objective: value,
            lower_bound: lower,
            error,
            peaks,
            design_violation: self.design_violation(x),
            rounds: round,
            angles: sets.iter().map(|s| s.len()).sum(),
            angle_sets: angle_sets(sets),
            ipm_iterations: iters,
            solver_status,
            note,
            multipliers: Vec::new(),
            flat: false,
        })
    }

    /// A solution without a design (infeasible or failed).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn empty(
        &self,
        status: Status,
        stop: Stop,
        round: usize,
        sets: &[Vec<(f64, AffineValue)>],
        iters: u32,
        solver_status: String,
        note: String,
    ) -> Solution {
        Solution {
            status,
            stop,
            x: vec![f64::NAN; self.n],
            objective: f64::NAN,
            lower_bound: f64::NAN,
            error: ErrorBound {
                total: f64::INFINITY,
                ..ErrorBound::default()
            },
            peaks: Vec::new(),
            design_violation: f64::NAN,
            rounds: round,
            angles: sets.iter().map(|s| s.len()).sum(),
            angle_sets: angle_sets(sets),
            ipm_iterations: iters,
            solver_status,
            note: Some(note),
            multipliers: Vec::new(),
            flat: false,
        }
    }
}

/// The sampled angles per field, without the field values.
fn angle_sets(sets: &[Vec<(f64, AffineValue)>]) -> Vec<Vec<f64>> {
    sets.iter()
        .map(|s| s.iter().map(|p| p.0).collect())
        .collect()
}

impl<'p, 'a> Engine<'p, 'a> {
    /// `base` (a solve of the problem's own goal) moved to another design `x` — a plate
    /// that realises it, found by the caller: the peaks, the objective and its errors at x,
    /// against base's lower bound, which holds for every design. The claim stays `optimal`
    /// only if the gap V(x) − L and the limits stay within the tolerance; otherwise it is
    /// `inaccurate`, with `why` and the gap (the error still covers the optimum).
    pub fn moved(&self, base: &Solution, x: &[f64], why: &str) -> Result<Solution, MinimaxError> {
        let s = &self.s;
        let peaks = self.peaks(x)?;
        let (value, scale, own_error) =
            self.goal_value(&self.pb.goal, x, |f| (peaks[f].peak, peaks[f].error));
        let lim_rel = self
            .pb
            .limits
            .iter()
            .map(|&(f, e)| peaks[f].violation / self.lim_floor(f, e).max(f64::MIN_POSITIVE))
            .fold(0.0, f64::max);
        let gap = value - base.lower_bound;
        let held = gap.abs() <= s.rel_tol * scale && lim_rel <= s.rel_tol;
        let rest = (base.error.total - base.error.sampling).max(own_error);
        let (status, note) = match base.status {
            Status::Optimal if !held => (
                Status::Inaccurate,
                Some(format!(
                    "{why}: its objective {value:.9e} is {gap:.3e} above the lower bound {:.9e} of every design{}",
                    base.lower_bound,
                    if lim_rel > s.rel_tol {
                        format!(", and a limit is exceeded by {lim_rel:.2e} of itself")
                    } else {
                        String::new()
                    }
                )),
            ),
            st => (st, base.note.clone()),
        };
        Ok(Solution {
            status,
            note,
            x: x.to_vec(),
            objective: value,
            error: ErrorBound {
                sampling: gap.abs(),
                total: gap.abs() + rest,
                ..base.error
            },
            peaks,
            design_violation: self.design_violation(x),
            // The multipliers are the optimum's, not this design's.
            multipliers: Vec::new(),
            flat: false,
            ..base.clone()
        })
    }
}
