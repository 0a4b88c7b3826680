//! The exchange loop: each round solves the SOCP on the sampled angles, refines the true
//! peaks of its design, certifies the gap, and exchanges angles (the refined maxima above
//! the bound in, the inactive ones out) until the gap is within the tolerance (module doc of
//! [`super`]: "The exchange loop and its certificate").

use super::assembly::Round;
use super::polish::{KktStart, PolishOutcome, Term, MAX_POLISH};
use super::validate::validate_goal;
use super::{
    var_m, AffineValue, Engine, Goal, MinimaxError, Solution, Stop, NEWTON_ONLY, POLISHED,
};
use crate::numeric::PeriodicPeak;
use crate::synth::conic::dual_lower_bound;
use crate::synth::exchange::{
    angle_dist, first_round_tol, is_new, max_rounds_note, next_round_tol, stalled_note,
    uniform_angles, Status,
};
use clarabel::solver::SolverStatus;

/// The end of a solve: the solution, and its polished optimality conditions when it has
/// them (the start of a neighbouring solve's Newton).
pub(super) type Done = (Solution, Option<KktStart>);

/// The relative gap V − L (of the gap's scale) above which a round's Lagrangian bound at the
/// refined maxima is not computed ([`Engine::refine_lower`]).
const DUAL_BOUND_NEAR: f64 = 1e-2;

/// The sampled angles per field, each with the field's value there.
type Sets = Vec<Vec<(f64, AffineValue)>>;

/// The best design of the rounds so far (smallest refined peak among those within the
/// limits' tolerance), with its peaks.
struct BestDesign {
    x: Vec<f64>,
    pk: Vec<Option<PeriodicPeak>>,
    value: f64,
    lim_rel: f64,
}

/// What the solve of one goal keeps fixed over its rounds.
struct GoalRun<'g> {
    goal: &'g Goal,
    limits: &'g [(usize, f64)],
    /// Per field: sampled (the objective's fields of a peak goal, and the limited ones).
    sampled: Vec<bool>,
    /// Whether the rounds start from a neighbouring solve's angles.
    warm_given: bool,
    /// R of an RMS goal ([`Engine::rms_factor`]).
    rms_r: Option<nalgebra::DMatrix<f64>>,
    /// `abs_floor`·U₀ of a peak goal (U₀ the weighted unbalanced peak, else the weighted
    /// fields' size), 0 for the other goals.
    obj_floor: f64,
    /// Whether the program has the objective variable t̂ (all goals but the mass).
    has_t: bool,
}

/// What the rounds carry from one to the next.
struct Rounds {
    /// The sampled angles per field, with the field's value there.
    sets: Vec<Vec<(f64, AffineValue)>>,
    /// clarabel's tolerance for the next round.
    round_tol: f64,
    /// clarabel interior-point iterations so far.
    iters: u32,
    /// The last round's solution.
    last: Option<Solution>,
    /// The angles active in the last round, per field (kept against cycling).
    prev_active: Vec<Vec<f64>>,
    /// The largest rigorous L so far, with its residual part.
    best_l: Option<(f64, f64)>,
    /// The best design so far.
    best_x: Option<BestDesign>,
    /// Whether the one restart from the refined maxima has run.
    restarted: bool,
    /// The solution before that restart.
    before_restart: Option<Solution>,
    /// Newton polishes tried.
    polish_tries: usize,
    /// The objective's scale T for clarabel: the unbalanced peak at first, then the last
    /// round's bound (so that t̂ ≈ 1 and clarabel's tolerances are relative to the optimum,
    /// not to the design box), never below the absolute floor.
    level: f64,
}

/// How a round ended, for its solution.
struct RoundEnd {
    round: usize,
    converged: bool,
    /// Every local maximum above the bound already sampled, at the target tolerance.
    stalled: bool,
    /// The round restarted the sets from its refined maxima.
    restarting: bool,
    /// clarabel's status, as text.
    status_txt: String,
}

/// A round's lower bound L of the optimum.
struct Lower {
    /// L (caller's units).
    lower: f64,
    /// Its part due to clarabel's dual residual.
    solver_err: f64,
    /// Whether the program it comes from was solved to full accuracy (or it is a
    /// Lagrangian bound).
    bound_solved: bool,
    /// Whether it holds whatever clarabel's accuracy (weak duality at a bounded design).
    rigorous: bool,
}

impl<'p, 'a> Engine<'p, 'a> {
    /// The problem's own goal and limits.
    pub fn solve(&self) -> Result<Solution, MinimaxError> {
        self.solve_goal(&self.pb.goal, &self.pb.limits, None)
    }

    /// Another goal and limits on the same fields and constraints; `warm` (per field) are
    /// angles to start from (e.g. a neighbouring solve's `angle_sets`) instead of the
    /// uniform ones.
    pub fn solve_goal(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
        warm: Option<&[Vec<f64>]>,
    ) -> Result<Solution, MinimaxError> {
        Ok(self.solve_goal_from(goal, limits, warm, None)?.0)
    }

    /// [`Engine::solve_goal`], first trying Newton from a neighbouring solve's polished
    /// optimality conditions (`start`; the limits' ε̂ updated to `limits`) before any SOCP;
    /// also returns this solve's polished conditions when it has them. The exact disc path
    /// first where it applies, then the exchange rounds ([`Engine::round`]).
    pub(super) fn solve_goal_from(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
        warm: Option<&[Vec<f64>]>,
        start: Option<&KktStart>,
    ) -> Result<Done, MinimaxError> {
        validate_goal(self.pb, goal, limits)?;
        if let Some(sol) = self.disc_path(goal, limits)? {
            return Ok((sol, None));
        }
        let (run, mut sets) = self.goal_run(goal, limits, warm)?;
        if let (Goal::MinPeak(list), Some(st)) = (goal, start) {
            if let Some(done) = self.newton_from(&run, list, st, &mut sets)? {
                return Ok(done);
            }
        }
        let mut rs = self.first_rounds(&run, sets);
        for round in 1..=self.s.max_rounds {
            if let Some(done) = self.round(&run, &mut rs, round)? {
                return Ok(done);
            }
        }
        unreachable!("the last round returns")
    }

    /// The fixed parts of a goal's solve and the first sampled angles: each sampled field's
    /// warm angles when every sampled field has some, else `initial_samples` uniform ones.
    fn goal_run<'g>(
        &self,
        goal: &'g Goal,
        limits: &'g [(usize, f64)],
        warm: Option<&[Vec<f64>]>,
    ) -> Result<(GoalRun<'g>, Sets), MinimaxError> {
        let nf = self.pb.fields.len();
        let s = &self.s;
        // Sampled fields: the objective's (peak goals) and the limited ones.
        let mut sampled = vec![false; nf];
        if let Goal::MinPeak(list) = goal {
            for &(f, _) in list {
                sampled[f] = true;
            }
        }
        for &(f, _) in limits {
            sampled[f] = true;
        }
        let mut sets: Vec<Vec<(f64, AffineValue)>> = vec![Vec::new(); nf];
        let warm_given =
            warm.is_some_and(|w| w.len() == nf && (0..nf).all(|f| !sampled[f] || !w[f].is_empty()));
        for f in (0..nf).filter(|&f| sampled[f]) {
            let start = match warm {
                Some(w) if warm_given => w[f].clone(),
                _ => uniform_angles(s.initial_samples),
            };
            for theta in start {
                self.insert(&mut sets[f], f, theta)?;
            }
        }
        let rms_r = match goal {
            Goal::MinRms(f) => Some(self.rms_factor(*f)?),
            _ => None,
        };
        let obj_floor = match goal {
            Goal::MinPeak(_) => self.goal_floor(goal),
            _ => 0.0,
        };
        let has_t = !matches!(goal, Goal::MinMass);
        let run = GoalRun {
            goal,
            limits,
            sampled,
            warm_given,
            rms_r,
            obj_floor,
            has_t,
        };
        Ok((run, sets))
    }

    /// Newton from a neighbouring solve's polished optimality conditions, before any SOCP:
    /// its active maxima, their limits moved to these ε. The solve ends here when the
    /// polished design's certificate meets the tolerance both ways (|V − L|: the polished
    /// design meets its limits to round-off, so an L above V would be a flaw, never a
    /// claim); the sets are then taken.
    fn newton_from(
        &self,
        run: &GoalRun,
        list: &[(usize, f64)],
        st: &KktStart,
        sets: &mut Vec<Vec<(f64, AffineValue)>>,
    ) -> Result<Option<Done>, MinimaxError> {
        let terms: Vec<Term> = st
            .terms
            .iter()
            .filter_map(|t| match t.eps {
                None => list.iter().any(|l| l.0 == t.field).then(|| t.clone()),
                Some(_) => run
                    .limits
                    .iter()
                    .find(|l| l.0 == t.field)
                    .map(|&(f, e)| Term {
                        eps: Some(e / self.g_ref()[f]),
                        ..t.clone()
                    }),
            })
            .collect();
        let t_scale = self.peak_scale(list);
        if let Some(po) =
            self.polish_certify(list, run.limits, terms, &st.x_hat, st.t_hat, t_scale, false)?
        {
            if self.certifies(run, &po) {
                let sets = std::mem::take(sets);
                return self
                    .polished_solution(run.goal, run.limits, sets, po, 0, 0, NEWTON_ONLY.into())
                    .map(|(sol, st)| Some((sol, Some(st))));
            }
        }
        Ok(None)
    }

    /// The rounds' state before the first: clarabel's first tolerance loose (1e-6) unless
    /// the angles are warm (already the active ones) or nothing is sampled.
    fn first_rounds(&self, run: &GoalRun, sets: Vec<Vec<(f64, AffineValue)>>) -> Rounds {
        let s = &self.s;
        let nf = self.pb.fields.len();
        Rounds {
            sets,
            round_tol: if run.warm_given || !run.sampled.iter().any(|&b| b) {
                s.rel_tol
            } else {
                first_round_tol(s.rel_tol)
            },
            iters: 0,
            last: None,
            prev_active: vec![Vec::new(); nf],
            best_l: None,
            best_x: None,
            restarted: false,
            before_restart: None,
            polish_tries: 0,
            level: match run.goal {
                Goal::MinPeak(_) => run.obj_floor / s.abs_floor,
                _ => 0.0,
            },
        }
    }

    /// One exchange round: the SOCP on the sampled angles, the true peaks at its design,
    /// the lower bound, the Newton polish when near, the certificate carried over from the
    /// earlier rounds, the verdict and the exchange of angles. `Some` when the solve ends.
    fn round(
        &self,
        run: &GoalRun,
        rs: &mut Rounds,
        round: usize,
    ) -> Result<Option<Done>, MinimaxError> {
        let s = &self.s;
        let (goal, limits) = (run.goal, run.limits);
        let nf = self.pb.fields.len();
        let tol_used = rs.round_tol;
        let rd = self.solve_round(
            goal,
            limits,
            &rs.sets,
            run.rms_r.as_ref(),
            tol_used,
            rs.level,
        )?;
        rs.iters += rd.res.iterations;
        let status_txt = format!("{:?}", rd.res.status);

        if let Some(sol) = self.solver_stopped(run, rs, &rd, round, &status_txt) {
            return Ok(Some((sol, None)));
        }
        let raw: Vec<f64> = rd
            .res
            .x
            .iter()
            .zip(&self.scale)
            .map(|(v, s)| v * s)
            .collect();
        let x = self.project(&raw);
        // True peaks of the sampled fields.
        let mut pk: Vec<Option<PeriodicPeak>> = vec![None; nf];
        for f in (0..nf).filter(|&f| run.sampled[f]) {
            pk[f] = Some(self.scan(f, &x)?);
        }
        let (value, gap_scale) = self.round_value(run, &x, &pk);
        let mut lb = self.sampled_lower(run, &rd, value);
        let lim_rel = self.lim_rel(limits, &pk);
        // The polish first: where it certifies, the round's Lagrangian bound is not needed;
        // where it is not tried, the better bound may bring the round near enough for it.
        let tries = rs.polish_tries;
        let at = (value, lb.lower, gap_scale, lim_rel);
        if let Some(done) = self.polish_round(run, rs, &rd, &x, &pk, at, round, &status_txt)? {
            return Ok(Some(done));
        }
        if self.refine_lower(run, &mut lb, &rd, &x, &pk, (value, gap_scale))?
            && rs.polish_tries == tries
        {
            let at = (value, lb.lower, gap_scale, lim_rel);
            if let Some(done) = self.polish_round(run, rs, &rd, &x, &pk, at, round, &status_txt)? {
                return Ok(Some(done));
            }
        }
        if matches!(goal, Goal::MinPeak(_)) {
            rs.level = lb.lower.max(run.obj_floor);
        }
        let (value, gap_scale, lim_rel) =
            self.carry_over(run, rs, &mut lb, &x, &pk, (value, gap_scale, lim_rel));
        let converged = self.verdict(run, rs, lb.lower, (value, gap_scale, lim_rel), tol_used);
        let mut added = 0;
        if !converged {
            // A plate's design that breaks its exact conditions: tangents there.
            added += self.add_plate_cuts(&raw) as usize;
            added += self.exchange(run, rs, &rd, &x, &pk, lb.lower, gap_scale)?;
        }
        // A stall with a gap left: clarabel's accuracy on clustered angles. Once, restart
        // from the refined maxima alone (well separated: the active set of a vertex-type
        // optimum), keeping the better of the two solutions.
        let restarting = !converged && added == 0 && tol_used <= s.rel_tol && !rs.restarted;
        if restarting {
            rs.restarted = true;
            self.restart(run, &mut rs.sets, &pk)?;
            added = 1;
        }
        let end = RoundEnd {
            round,
            converged,
            stalled: added == 0 && tol_used <= s.rel_tol,
            restarting,
            status_txt,
        };
        self.end_round(run, rs, (x, pk, value), &lb, end)
    }

    /// Whether the round converged: the objective's gap V − L within `rel_tol` of its
    /// scale, the limits within `rel_tol`, and the round solved at the target tolerance (a
    /// round solved more loosely cannot certify it). Sets the next round's clarabel
    /// tolerance: two orders below the gap, down to the target.
    fn verdict(
        &self,
        run: &GoalRun,
        rs: &mut Rounds,
        lower: f64,
        (value, gap_scale, lim_rel): (f64, f64, f64),
        tol_used: f64,
    ) -> bool {
        let s = &self.s;
        // An RMS or mass goal's program is exact on its own; a plate's projection onto its
        // exact conditions (`plate.rs`) moves the design off the program's, so the gap counts.
        let obj_gap = match run.goal {
            Goal::MinPeak(_) => (value - lower).max(0.0),
            _ if self.has_plate() => (value - lower).max(0.0),
            _ => 0.0,
        };
        let obj_ok = obj_gap <= s.rel_tol * gap_scale;
        let within = obj_ok && lim_rel <= s.rel_tol;
        let rel_gap = if gap_scale > 0.0 {
            obj_gap / gap_scale
        } else {
            0.0
        }
        .max(lim_rel);
        rs.round_tol = if within {
            s.rel_tol
        } else {
            next_round_tol(rs.round_tol, rel_gap, s.rel_tol)
        };
        within && tol_used <= s.rel_tol
    }

    /// The solution of a round (of the best design so far for a peak goal) with its claim
    /// ([`Engine::round_status`]); `Some` when the solve ends with it (converged, stalled or
    /// the last round: after a restart the better certified of the two), else it becomes
    /// `last` (and, on a restart, the stalled solution to compare with).
    fn end_round(
        &self,
        run: &GoalRun,
        rs: &mut Rounds,
        (x, pk, value): (Vec<f64>, Vec<Option<PeriodicPeak>>, f64),
        lb: &Lower,
        end: RoundEnd,
    ) -> Result<Option<Done>, MinimaxError> {
        let RoundEnd {
            round,
            converged,
            stalled,
            restarting,
            status_txt,
        } = end;
        let (status, stop, note) =
            self.round_status(converged, !lb.bound_solved, stalled, round, &status_txt);
        let (x, pk) = match &rs.best_x {
            Some(b) if matches!(run.goal, Goal::MinPeak(_)) => (b.x.clone(), b.pk.clone()),
            _ => (x, pk),
        };
        let sol = self.finish(
            run.goal,
            run.limits,
            &rs.sets,
            &x,
            pk,
            value,
            (lb.lower, lb.solver_err, lb.rigorous),
            status,
            stop,
            note,
            round,
            rs.iters,
            status_txt,
        )?;
        if converged || stalled || round == self.s.max_rounds {
            return Ok(Some((
                match rs.before_restart.take() {
                    Some(b) if b.error.total < sol.error.total && !converged => b,
                    _ => sol,
                },
                None,
            )));
        }
        if restarting {
            rs.before_restart = Some(Solution {
                stop: Stop::Stalled,
                note: Some(stalled_note(round, "clarabel's accuracy")),
                ..sol.clone()
            });
        }
        rs.last = Some(sol);
        Ok(None)
    }

    /// clarabel's status of a round: infeasible (the sampled problem, so the continuous
    /// one), or stopped short (the previous round's design kept, or none). `Some` when the
    /// solve ends there.
    fn solver_stopped(
        &self,
        run: &GoalRun,
        rs: &mut Rounds,
        rd: &Round,
        round: usize,
        status_txt: &str,
    ) -> Option<Solution> {
        let finite = rd.res.x.iter().all(|v| v.is_finite());
        let (status, stop, note) = match rd.res.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => return None,
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                let what = self.infeasible_what(run.limits);
                let note = format!("infeasible: {what} within the counterweight limits");
                (Status::Infeasible, Stop::Infeasible, note)
            }
            _ if finite && rs.last.is_some() => {
                let mut l = rs.last.take().expect("checked");
                l.status = Status::Inaccurate;
                l.stop = Stop::SolverAccuracy;
                l.rounds = round;
                l.ipm_iterations = rs.iters;
                l.note = Some(format!(
                    "clarabel stopped with {status_txt} in round {round}; the previous round's design is kept"
                ));
                return Some(l);
            }
            _ if finite => return None,
            _ => (
                Status::Failed,
                Stop::SolverFailed,
                "clarabel returned no finite iterate".into(),
            ),
        };
        let txt = status_txt.to_string();
        Some(self.empty(status, stop, round, &rs.sets, rs.iters, txt, note))
    }

    /// What cannot be met, in words, when the sampled problem is infeasible.
    fn infeasible_what(&self, limits: &[(usize, f64)]) -> String {
        if limits.is_empty() {
            "the design constraints (bounds, cones, linear rows) cannot all be met".to_string()
        } else {
            format!(
                "no design meets the limits {} on the sampled angles (so none on all angles)",
                limits
                    .iter()
                    .map(|&(f, e)| format!("peak |{}| ≤ {e:e}", self.pb.fields[f].name()))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
    }

    /// V, the goal's value at the round's design (for a peak goal the weighted refined
    /// peak), and the scale its gap is relative to ([`Engine::goal_value`]).
    fn round_value(&self, run: &GoalRun, x: &[f64], pk: &[Option<PeriodicPeak>]) -> (f64, f64) {
        let peak_of = |f: usize| {
            let p = pk[f].as_ref().expect("sampled");
            (p.peak.fx, p.error)
        };
        let (v, scale, _) = self.goal_value(run.goal, x, peak_of);
        (v, scale)
    }

    /// The goal's value V at x from each field's (peak, error) `peak_of`, the scale of its
    /// gap, max(V, [`Engine::goal_floor`]), and V's own error (the peaks' or the RMS
    /// quadrature's). The gap of an RMS or mass goal counts only with a plate (`verdict`):
    /// their programs are otherwise exact.
    pub(super) fn goal_value(
        &self,
        goal: &Goal,
        x: &[f64],
        peak_of: impl Fn(usize) -> (f64, f64),
    ) -> (f64, f64, f64) {
        let (v, e) = match goal {
            Goal::MinPeak(list) => list.iter().fold((0.0, 0.0), |(v, e): (f64, f64), &(f, w)| {
                let (p, pe) = peak_of(f);
                (v.max(w * p), e.max(w * pe))
            }),
            Goal::MinRms(f) => self.rms(*f, x),
            Goal::MinMass => (
                (0..self.pb.counterweights.len())
                    .map(|j| x[var_m(j)])
                    .sum::<f64>(),
                0.0,
            ),
        };
        (v, v.max(self.goal_floor(goal)), e)
    }

    /// `abs_floor` times the goal's size where V vanishes: the objective fields' unbalanced
    /// peak (their size over the design box where that is 0), the RMS field's, the largest
    /// total mass.
    pub(super) fn goal_floor(&self, goal: &Goal) -> f64 {
        let size = match goal {
            Goal::MinPeak(list) => {
                let most = |g: &[f64]| list.iter().map(|&(f, w)| w * g[f]).fold(0.0, f64::max);
                let u0 = most(&self.g0);
                if u0 > 0.0 {
                    u0
                } else {
                    most(self.g_ref())
                }
            }
            Goal::MinRms(f) => self.g0[*f],
            Goal::MinMass => self.pb.counterweights.iter().map(|c| c.m_max).sum(),
        };
        self.s.abs_floor * size
    }

    /// The round's sampled lower bound: the sampled problem's, from clarabel's dual iterate
    /// made rigorous (`dual_lower_bound`; t̂ ≤ 2·max(t̂ found, V/T) bounds the objective
    /// variable).
    fn sampled_lower(&self, run: &GoalRun, rd: &Round, value: f64) -> Lower {
        let mut xb = self.xbound.clone();
        if run.has_t {
            xb.push(2.0 * rd.res.x[self.n].abs().max(value / rd.t_scale));
        }
        let (lb, pen) = dual_lower_bound(&rd.built, &rd.res.z, &xb);
        if lb.is_finite() {
            Lower {
                lower: rd.t_scale * lb,
                solver_err: rd.t_scale * pen,
                bound_solved: rd.res.status == SolverStatus::Solved,
                rigorous: true,
            }
        } else {
            // An unbounded extra variable: clarabel's own bound and residual estimate.
            let r = &rd.res;
            Lower {
                lower: rd.t_scale * r.obj.min(r.obj_dual),
                solver_err: rd.t_scale * ((r.obj - r.obj_dual).abs() + r.r_dual * r.norms.max(1.0)),
                bound_solved: r.status == SolverStatus::Solved,
                rigorous: false,
            }
        }
    }

    /// For a peak goal, the Lagrangian bound at the refined maxima ([`Engine::dual_bound`]:
    /// free of the objective variable's residual and of the clustered angles' conditioning)
    /// in place of the sampled bound where it is better; whether it was. Far from
    /// convergence (the design misses maxima, not the bound) it cannot close the gap — its
    /// gain over the sampled bound is of second order in the angles' moves and of the order
    /// of the round's own tolerance, two orders below the gap — and its two SOCPs are skipped.
    fn refine_lower(
        &self,
        run: &GoalRun,
        out: &mut Lower,
        rd: &Round,
        x: &[f64],
        pk: &[Option<PeriodicPeak>],
        (value, gap_scale): (f64, f64),
    ) -> Result<bool, MinimaxError> {
        let far = out.bound_solved && value - out.lower > DUAL_BOUND_NEAR * gap_scale;
        if !matches!(run.goal, Goal::MinPeak(_)) || far {
            return Ok(false);
        }
        let Some((lb, err)) = self.dual_bound(rd, x, pk)? else {
            return Ok(false);
        };
        let better =
            lb > out.lower || (!out.bound_solved && value - lb <= self.s.rel_tol * gap_scale);
        if better {
            *out = Lower {
                lower: lb,
                solver_err: err,
                bound_solved: true,
                rigorous: true,
            };
        }
        Ok(better)
    }

    /// ε_f or, below `abs_floor` times the field's unbalanced peak, that: the scale a
    /// limit's tolerance is relative to.
    pub(super) fn lim_floor(&self, f: usize, eps: f64) -> f64 {
        eps.max(self.s.abs_floor * self.g0[f])
    }

    /// The limits' largest relative violation at the round's design.
    fn lim_rel(&self, limits: &[(usize, f64)], pk: &[Option<PeriodicPeak>]) -> f64 {
        let peak_of = |f: usize| pk[f].as_ref().expect("sampled").peak.fx;
        limits
            .iter()
            .map(|&(f, e)| (peak_of(f) - e).max(0.0) / self.lim_floor(f, e).max(f64::MIN_POSITIVE))
            .fold(0.0, f64::max)
    }

    /// The Newton polish of the round's active set (`polish`), once the round is near
    /// (gap and limits within 1e-3), at most `MAX_POLISH` times: when its design and
    /// multipliers certify the tolerance the solve ends here (`Some`; the sets are taken);
    /// otherwise the loop goes on as if it had not run. `at` = (V, L, gap scale, lim_rel).
    #[allow(clippy::too_many_arguments)]
    fn polish_round(
        &self,
        run: &GoalRun,
        rs: &mut Rounds,
        rd: &Round,
        x: &[f64],
        pk: &[Option<PeriodicPeak>],
        (value, lower, gap_scale, lim_rel): (f64, f64, f64, f64),
        round: usize,
        status_txt: &str,
    ) -> Result<Option<Done>, MinimaxError> {
        let Goal::MinPeak(list) = run.goal else {
            return Ok(None);
        };
        let near = (value - lower).max(0.0) <= 1e-3 * gap_scale && lim_rel <= 1e-3;
        // A plate's tangents are outer approximations the polish would hold as exact.
        if !(near && rs.polish_tries < MAX_POLISH) || self.has_plate() {
            return Ok(None);
        }
        rs.polish_tries += 1;
        let certifies = |po: &PolishOutcome| self.certifies(run, po);
        // Plain Newton first; where it fails, the proximal retry (`polish::PROX`: a flat
        // direction of the optimum).
        let mut po = self.try_polish(list, run.limits, rd, x, pk, false)?;
        if !po.as_ref().is_some_and(certifies) {
            po = self.try_polish(list, run.limits, rd, x, pk, true)?;
        }
        let Some(po) = po.filter(certifies) else {
            return Ok(None);
        };
        let sets = std::mem::take(&mut rs.sets);
        let status = format!("{status_txt}; {POLISHED}");
        self.polished_solution(run.goal, run.limits, sets, po, round, rs.iters, status)
            .map(|(sol, st)| Some((sol, Some(st))))
    }

    /// Whether a polished point certifies the goal: |V − L| within `rel_tol` of its scale
    /// (both ways: the polished design meets its limits to round-off, so an L above V would
    /// be a flaw, never a claim) and every limit within `rel_tol`.
    fn certifies(&self, run: &GoalRun, po: &PolishOutcome) -> bool {
        let tol = self.s.rel_tol;
        (po.value - po.lower).abs() <= tol * po.value.max(run.obj_floor) && po.lim_rel <= tol
    }

    /// The certificate carries over between rounds: every rigorous L is a lower bound of
    /// the same optimum, and every design's refined peak an upper bound, so the best of
    /// each so far is kept (the rounds' designs jitter at clarabel's accuracy). Updates `lb`
    /// and returns (V, gap scale, lim_rel) of the best design (peak goals; the round's own
    /// otherwise).
    fn carry_over(
        &self,
        run: &GoalRun,
        rs: &mut Rounds,
        lb: &mut Lower,
        x: &[f64],
        pk: &[Option<PeriodicPeak>],
        (value, gap_scale, lim_rel): (f64, f64, f64),
    ) -> (f64, f64, f64) {
        let s = &self.s;
        let (mut value, mut gap_scale, mut lim_rel) = (value, gap_scale, lim_rel);
        if !matches!(run.goal, Goal::MinPeak(_)) {
            return (value, gap_scale, lim_rel);
        }
        if lb.rigorous && lb.bound_solved && rs.best_l.is_none_or(|b| lb.lower > b.0) {
            rs.best_l = Some((lb.lower, lb.solver_err));
        }
        if let Some((l, e)) = rs.best_l {
            if !(lb.rigorous && lb.bound_solved) || l > lb.lower {
                (lb.lower, lb.solver_err, lb.rigorous, lb.bound_solved) = (l, e, true, true);
            }
        }
        let ok = |lr: f64| lr <= s.rel_tol;
        let better =
            rs.best_x
                .as_ref()
                .is_none_or(|b: &BestDesign| match (ok(lim_rel), ok(b.lim_rel)) {
                    (true, false) => true,
                    (false, true) => false,
                    (true, true) => value < b.value,
                    (false, false) => lim_rel < b.lim_rel,
                });
        if better {
            rs.best_x = Some(BestDesign {
                x: x.to_vec(),
                pk: pk.to_vec(),
                value,
                lim_rel,
            });
        }
        let b = rs.best_x.as_ref().expect("set");
        (value, lim_rel) = (b.value, b.lim_rel);
        gap_scale = value.max(run.obj_floor);
        (value, gap_scale, lim_rel)
    }

    /// Exchange: the sets pruned to the active angles ([`Engine::prune`]), then the local
    /// maxima of the round's design above the bound (objective) or the limit added
    /// ([`Engine::add_peak`]). Returns the number of angles added.
    #[allow(clippy::too_many_arguments)]
    fn exchange(
        &self,
        run: &GoalRun,
        rs: &mut Rounds,
        rd: &Round,
        x: &[f64],
        pk: &[Option<PeriodicPeak>],
        lower: f64,
        gap_scale: f64,
    ) -> Result<usize, MinimaxError> {
        let s = &self.s;
        self.prune(&mut rs.sets, rd, x, &mut rs.prev_active);
        let mut added = 0;
        if let Goal::MinPeak(list) = run.goal {
            for &(f, w) in list {
                let above: Vec<f64> = pk[f]
                    .as_ref()
                    .expect("sampled")
                    .maxima
                    .iter()
                    .filter(|m| w * m.fx > lower + 0.5 * s.rel_tol * gap_scale)
                    .map(|m| m.x)
                    .collect();
                for theta in above {
                    added += self.add_peak(&mut rs.sets[f], f, theta, x, gap_scale / w)?;
                }
            }
        }
        for &(f, e) in run.limits {
            let above: Vec<f64> = pk[f]
                .as_ref()
                .expect("sampled")
                .maxima
                .iter()
                .filter(|m| m.fx > e)
                .map(|m| m.x)
                .collect();
            for theta in above {
                added += self.add_peak(&mut rs.sets[f], f, theta, x, self.lim_floor(f, e))?;
            }
        }
        Ok(added)
    }

    /// The restart after a stall: each sampled field's set replaced by its refined maxima
    /// within 1 % of its peak.
    fn restart(
        &self,
        run: &GoalRun,
        sets: &mut [Vec<(f64, AffineValue)>],
        pk: &[Option<PeriodicPeak>],
    ) -> Result<(), MinimaxError> {
        for f in (0..self.pb.fields.len()).filter(|&f| run.sampled[f]) {
            let p = pk[f].as_ref().expect("sampled");
            let keep: Vec<f64> = p
                .maxima
                .iter()
                .filter(|m| m.fx >= 0.99 * p.peak.fx)
                .map(|m| m.x)
                .collect();
            let mut fresh = Vec::new();
            for theta in keep {
                self.insert(&mut fresh, f, theta)?;
            }
            sets[f] = fresh;
        }
        Ok(())
    }

    /// The claim of a round: optimal when converged on a fully solved bound, else
    /// inaccurate with why (reduced accuracy, a stall, the last round).
    fn round_status(
        &self,
        converged: bool,
        almost: bool,
        stalled: bool,
        round: usize,
        status_txt: &str,
    ) -> (Status, Stop, Option<String>) {
        if converged && !almost {
            (Status::Optimal, Stop::Converged, None)
        } else if converged {
            (
                Status::Inaccurate,
                Stop::SolverAccuracy,
                Some(format!(
                    "clarabel reached reduced accuracy only ({status_txt})"
                )),
            )
        } else if stalled {
            (
                Status::Inaccurate,
                Stop::Stalled,
                Some(stalled_note(round, "clarabel's accuracy")),
            )
        } else if round == self.s.max_rounds {
            (
                Status::Inaccurate,
                Stop::MaxRounds,
                Some(max_rounds_note(self.s.max_rounds)),
            )
        } else {
            (Status::Inaccurate, Stop::MaxRounds, None)
        }
    }

    /// Adds θ (mod 2π) to a field's sampled set if new, keeping it sorted; true if added.
    pub(super) fn insert(
        &self,
        set: &mut Vec<(f64, AffineValue)>,
        f: usize,
        theta: f64,
    ) -> Result<bool, MinimaxError> {
        let theta = theta.rem_euclid(std::f64::consts::TAU);
        let angles: Vec<f64> = set.iter().map(|p| p.0).collect();
        if !is_new(&angles, theta) {
            return Ok(false);
        }
        let v = self.eval(f, theta)?;
        let at = set.partition_point(|p| p.0 < theta);
        set.insert(at, (theta, v));
        Ok(true)
    }

    /// Adds a local maximum θ of field f (at design x) to its sampled set; returns the angles
    /// added. Where a sampled angle is already within a scan step of θ, the loop is creeping
    /// towards a maximum whose position moves with the design (a single active maximum
    /// against a curved constraint: the sampled bound then converges only linearly), so θ ± δ
    /// are added too: with the maximum anywhere in [θ − δ, θ + δ] the sampled value is within
    /// |f''|δ²/8 of it, and δ = √(2·rel_tol·level/|f''|) makes that rel_tol·level/4 (|f''|
    /// from a central difference at θ; `level` the value the tolerance is relative to).
    pub(super) fn add_peak(
        &self,
        set: &mut Vec<(f64, AffineValue)>,
        f: usize,
        theta: f64,
        x: &[f64],
        level: f64,
    ) -> Result<usize, MinimaxError> {
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        let t = theta.rem_euclid(std::f64::consts::TAU);
        let creeping = set.iter().any(|p| angle_dist(p.0, t) < h);
        let mut added = self.insert(set, f, t)? as usize;
        if creeping && added > 0 {
            let d = self.pb.fields[f].dim();
            let eta = 0.25 * h;
            let g = |th: f64| self.eval(f, th).map(|v| v.magnitude(d, x));
            let curv = ((g(t + eta)? - 2.0 * g(t)? + g(t - eta)?) / (eta * eta)).abs();
            let delta = if curv > 0.0 {
                (2.0 * self.s.rel_tol * level / curv).sqrt()
            } else {
                0.5 * h
            }
            .clamp(1e-8, 0.5 * h);
            for th in [t - delta, t + delta] {
                added += self.insert(set, f, th)? as usize;
            }
        }
        Ok(added)
    }

    /// Keeps of each sampled set only the angles that matter for the next round: the cones
    /// active at the round's optimum (dual weight z₀ above 1e-7 of the objective cones' total,
    /// or value at x within 1e-6 of the sampled bound: t̂ for an objective cone, ε̂ for a
    /// limit), and those active in the previous round (against cycling). Dropping inactive
    /// angles keeps the relaxation a relaxation (any subset gives a lower bound) while the
    /// SOCP stays small and free of stale clusters around earlier maximum positions.
    pub(super) fn prune(
        &self,
        sets: &mut [Vec<(f64, AffineValue)>],
        rd: &Round,
        x: &[f64],
        prev_active: &mut [Vec<f64>],
    ) {
        let z = &rd.res.z;
        let sum = rd.objective_weight();
        let t_hat = rd.res.x.get(self.n).copied().unwrap_or(0.0);
        let mut active: Vec<Vec<f64>> = vec![Vec::new(); sets.len()];
        for t in &rd.tags {
            let d = self.pb.fields[t.field].dim();
            let Some(v) = sets[t.field].iter().find(|p| p.0 == t.theta) else {
                continue;
            };
            let val = t.c * v.1.magnitude(d, x);
            let bound = t.eps.unwrap_or(t_hat);
            let dual = sum > 0.0 && z[t.row].max(0.0) > 1e-7 * sum;
            if dual || val >= bound * (1.0 - 1e-6) {
                active[t.field].push(t.theta);
            }
        }
        for (f, set) in sets.iter_mut().enumerate() {
            if active[f].is_empty() && prev_active[f].is_empty() {
                continue;
            }
            set.retain(|p| active[f].contains(&p.0) || prev_active[f].contains(&p.0));
        }
        prev_active.clone_from_slice(&active);
    }
}
