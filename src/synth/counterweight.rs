//! Counterweight synthesis as a convex program over the unbalance vector U, solved by
//! clarabel and refined by an exchange (Remez-like) loop.
//!
//! Everything a crank counterweight changes at constant speed is affine in U = m·r·(cos β,
//! sin β) (crank frame): the shaking force f(φ; U) = f₀(φ) + Rot(φ)·U, and with gravity the
//! drive torque. So, over a finite set of sample angles φ_k,
//!
//! * min over U of max_k ‖A_k U + b_k‖ is the SOCP  min t s.t. ‖A_k U + b_k‖ ≤ t;
//! * min of the mean of ‖A U + b‖² is a QP;
//! * min ‖U‖ subject to ‖A_k U + b_k‖ ≤ F_max is an SOCP;
//!
//! each with optional limits on other fields, ‖U‖ ≤ U_max, a fixed direction of U (with
//! a lower bound on its length) or a sector of directions up to 180° wide. The sampled
//! optimum is a lower bound of the true one; the exchange loop locates every local maximum
//! of each field on the current design with [`crate::numeric::periodic_peak`], adds those
//! angles and re-solves until the true peak is within the tolerance of the sampled bound.
//!
//! Where the sampled problem is a smallest enclosing disc (the peak force of a counterweight
//! turning with the crank, free direction, no limits, |U| bound inactive), each round is
//! solved exactly by Welzl's algorithm instead (`disc_exchange`, `Settings::exact_disc`);
//! clarabel solves every other variant.
//!
//! All quantities are expected already non-dimensionalised by the caller (O(1) numbers);
//! clarabel's tolerances are relative to that scale.

use crate::geom::P2;
use crate::numeric::{periodic_peak, periodic_peak_sampled, PeriodicPeak, Refine, SearchError};
use crate::synth::conic::{run_clarabel, Built, ConicResult, Rows};
use crate::synth::exchange::{
    check_exchange, first_round_tol, is_new, max_rounds_note, next_round_tol, stalled_note,
    DiscForm, DiscSamples,
};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{SolverStatus, SupportedConeT};

/// The exchange vocabulary this engine shares with `synth::minimax`, at its old paths.
pub use crate::synth::exchange::{angle_dist, uniform_angles, Affine, Status};

/// A field over the crank angle, affine in the unbalance.
pub struct Field<'a> {
    /// Name used in messages and results.
    pub name: &'static str,
    /// 2 for a planar force, 1 for a scalar (torque): only the first row is used.
    pub dim: usize,
    /// The field at φ.
    pub eval: &'a (dyn Fn(f64) -> Affine + Sync),
    /// The field at the scan angles 2πk/n, k = 0…n−1, if the caller has them: the scans use
    /// them when n = `scan_samples` (they must equal `eval` there), so only the refinement
    /// between grid angles calls `eval`.
    pub grid: Option<&'a [Affine]>,
}

impl Field<'_> {
    /// |f(φ; u)| (Euclidean for a vector field, absolute value for a scalar).
    pub fn magnitude(&self, phi: f64, u: P2) -> f64 {
        self.magnitude_of(&(self.eval)(phi), u)
    }

    /// |A u + b| of one affine value of this field.
    pub fn magnitude_of(&self, aff: &Affine, u: P2) -> f64 {
        let v = aff.at(u);
        if self.dim == 2 {
            v.x.hypot(v.y)
        } else {
            v.x.abs()
        }
    }

    /// The grid, if it is the scan grid of `s`.
    fn scan_grid(&self, s: &Settings) -> Option<&[Affine]> {
        self.grid.filter(|g| g.len() == s.scan_n())
    }
}

/// What to minimise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Goal {
    /// The peak over φ of |field i|.
    MinPeak(usize),
    /// The mean over φ of |field i|² (so its RMS).
    MinMeanSquare(usize),
    /// ‖U‖ (the lightest counterweight at a given radius).
    MinNorm,
}

/// Restrictions on the direction of U.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Direction {
    /// Any direction.
    Free,
    /// U = s·(cos β, sin β) with s ≥ `min_len`.
    Fixed { beta: f64, min_len: f64 },
    /// β in [β_lo, β_hi] with β_hi − β_lo ≤ π: the convex cone between the two rays.
    Sector { lo: f64, hi: f64 },
}

/// The convex counterweight problem.
pub struct Problem<'a> {
    /// Fields (index 0 usually the shaking force).
    pub fields: Vec<Field<'a>>,
    /// Objective.
    pub goal: Goal,
    /// Upper limits on the peak of fields: (field index, limit).
    pub limits: Vec<(usize, f64)>,
    /// ‖U‖ ≤ u_max (infinite: no bound).
    pub u_max: f64,
    /// Direction restriction.
    pub direction: Direction,
    /// Extra angles for the first SOCP (e.g. the maxima of a good initial guess), added to
    /// the equally spaced ones.
    pub warm_angles: Vec<f64>,
}

/// Accuracy settings of the exchange loop (flat, with defaults, Clarabel style).
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// Stop when (true peak − sampled bound) ≤ `rel_tol`·true peak. Default 1e-9.
    pub rel_tol: f64,
    /// Equally spaced angles in the first SOCP. Default 8.
    pub initial_samples: usize,
    /// Angles of the scan that brackets the local maxima of a design, or `"auto"` (the
    /// default, stored as [`AUTO`]): the family chooses the count from the scene's bandwidth
    /// (the slider-crank: `Scene::auto_samples`); an engine given `AUTO` uses [`FALLBACK_SAMPLES`].
    #[serde(with = "samples_setting")]
    #[schemars(with = "samples_setting::Schema")]
    pub scan_samples: usize,
    /// Exchange rounds at most. Default 30.
    pub max_rounds: usize,
    /// Angle tolerance of the peak refinement (rad). Default 1e-10. (1e-7 gives the same
    /// peak values to 16 digits at a third of the Brent evaluations, but the exchange loop
    /// then stalls a few 1e-9 short of the target on constrained or offset scenes: tried and
    /// reverted.)
    #[serde(with = "crate::units::angle_setting")]
    #[schemars(with = "crate::units::Qty<crate::units::Angle>")]
    pub peak_xtol: f64,
    /// Quadrature points of mean-square objectives (and of RMS values), or `"auto"` (the
    /// default, [`AUTO`]: as many as the scan, so that the slider-crank solve samples the
    /// kinematics once for both). The trapezoid rule is spectrally accurate for these smooth
    /// periodic functions (the paper piston's RMS agrees to 4e-16 relative at 180, 360 and
    /// 720 points).
    #[serde(with = "samples_setting")]
    #[schemars(with = "samples_setting::Schema")]
    pub rms_samples: usize,
    /// Between exchange rounds, keep only the sampled angles whose value is within this
    /// fraction of the current level (the near-active set). Default 0.05; 1 keeps all.
    pub keep_band: f64,
    /// Start the first SOCP also at the local maxima of a closed-form initial guess (the
    /// least-squares counterweight). Default false: it costs ~25 % on a symmetric in-line
    /// piston (3 rounds either way) but cuts an offset slider from 8 rounds to 3, where
    /// the loop otherwise creeps along clarabel's accuracy near 1e-9.
    pub warm_start: bool,
    /// Pick the first SOCP's angles by the geometric presolve (see [`enclosing_presolve`])
    /// when the objective is a rotating counterweight's peak force. Default true; false
    /// starts from `initial_samples` equally spaced angles.
    pub presolve: bool,
    /// After the presolve, solve each round's sampled minimax exactly as a smallest enclosing
    /// disc (Welzl) instead of by clarabel's SOCP, when the problem is one (peak force of a
    /// turning counterweight, free direction, no limits, |U| bound not active; see
    /// `disc_exchange`). Default true; false always runs clarabel.
    pub exact_disc: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            rel_tol: 1e-9,
            initial_samples: 8,
            scan_samples: AUTO,
            max_rounds: 30,
            peak_xtol: 1e-10,
            rms_samples: AUTO,
            keep_band: 0.05,
            warm_start: false,
            presolve: true,
            exact_disc: true,
        }
    }
}

/// A sample count of [`Settings`] left to the family (`"auto"` in a problem file).
pub const AUTO: usize = 0;

/// The count an engine uses for an [`AUTO`] count it was given unresolved (the fixed default
/// before counts could be chosen per scene).
pub const FALLBACK_SAMPLES: usize = 360;

impl Settings {
    /// The scan's sample count ([`FALLBACK_SAMPLES`] for [`AUTO`]).
    pub fn scan_n(&self) -> usize {
        if self.scan_samples == AUTO {
            FALLBACK_SAMPLES
        } else {
            self.scan_samples
        }
    }

    /// The RMS quadrature's point count ([`Settings::scan_n`] for [`AUTO`]).
    pub fn rms_n(&self) -> usize {
        if self.rms_samples == AUTO {
            self.scan_n()
        } else {
            self.rms_samples
        }
    }

    /// Checks every field; the error names the field (as in `[accuracy]`) and its range.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        check_exchange(
            self.rel_tol,
            self.initial_samples,
            self.scan_n(),
            self.max_rounds,
            self.peak_xtol,
        )?;
        if !(self.keep_band > 0.0 && self.keep_band <= 1.0) {
            return Err((
                "keep_band",
                format!("must be in (0, 1], got {}", self.keep_band),
            ));
        }
        if self.rms_samples != AUTO && self.rms_samples < 16 {
            return Err((
                "rms_samples",
                format!("must be at least 16 or \"auto\", got {}", self.rms_samples),
            ));
        }
        Ok(())
    }
}

/// A sample count that may be `"auto"` ([`AUTO`]): reads an integer ≥ 1 or the word `auto`,
/// writes `"auto"` or the integer. Use with `#[serde(with = "samples_setting")]`.
pub mod samples_setting {
    use super::AUTO;
    use serde::de::{self, Visitor};
    use serde::{Deserializer, Serializer};

    /// The schema: an integer or the string `"auto"`.
    #[derive(schemars::JsonSchema)]
    #[serde(untagged)]
    #[allow(dead_code)]
    pub enum Schema {
        /// A fixed count.
        Count(u64),
        /// Chosen from the scene.
        Auto(Word),
    }

    /// The word `auto`.
    #[derive(schemars::JsonSchema)]
    #[allow(dead_code)]
    pub enum Word {
        /// `"auto"`.
        #[serde(rename = "auto")]
        Auto,
    }

    struct V;
    impl Visitor<'_> for V {
        type Value = usize;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("an integer sample count or \"auto\"")
        }
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<usize, E> {
            match usize::try_from(v) {
                Ok(0) | Err(_) => Err(E::custom(format!(
                    "{v} is out of range; allowed: a sample count (see the key's range) or \"auto\""
                ))),
                Ok(n) => Ok(n),
            }
        }
        fn visit_i64<E: de::Error>(self, v: i64) -> Result<usize, E> {
            match u64::try_from(v) {
                Ok(u) => self.visit_u64(u),
                Err(_) => Err(E::custom(format!(
                    "{v} is out of range; allowed: a sample count (see the key's range) or \"auto\""
                ))),
            }
        }
        fn visit_str<E: de::Error>(self, v: &str) -> Result<usize, E> {
            if v == "auto" {
                Ok(AUTO)
            } else {
                Err(E::custom(format!(
                    "\"{v}\" is no sample count; allowed: an integer or \"auto\""
                )))
            }
        }
    }

    /// Reads an integer ≥ 1 or `"auto"`.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
        d.deserialize_any(V)
    }
    /// Writes `"auto"` or the integer.
    pub fn serialize<S: Serializer>(v: &usize, s: S) -> Result<S::Ok, S::Error> {
        if *v == AUTO {
            s.serialize_str("auto")
        } else {
            s.serialize_u64(*v as u64)
        }
    }
}

/// The outcome of [`solve`].
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Status.
    pub status: Status,
    /// The unbalance found (normalised units).
    pub u: P2,
    /// Objective value on the samples (lower bound of the true optimum for `MinPeak`).
    pub sampled_objective: f64,
    /// Refined peak of every field at `u`.
    pub peaks: Vec<PeriodicPeak>,
    /// For `MinPeak`: true peak − sampled bound (≥ 0 up to solver tolerance); for limits:
    /// the largest violation; else 0.
    pub gap: f64,
    /// Exchange rounds (SOCP solves).
    pub rounds: usize,
    /// Angles in the final SOCP.
    pub samples: usize,
    /// Total clarabel interior-point iterations.
    pub ipm_iterations: u32,
    /// The last clarabel status, as text.
    pub solver_status: String,
    /// Whether the geometric presolve chose the first angles.
    pub presolved: bool,
    /// Whether the rounds were solved exactly as smallest enclosing discs, without clarabel
    /// (`rounds` are then disc rounds and `ipm_iterations` is 0).
    pub disc: bool,
    /// Why the loop stopped where not optimal.
    pub note: Option<String>,
}

impl Solution {
    /// No design yet.
    fn failed() -> Solution {
        Solution {
            status: Status::Failed,
            u: P2::zeros(),
            sampled_objective: f64::NAN,
            peaks: Vec::new(),
            gap: f64::INFINITY,
            rounds: 0,
            samples: 0,
            ipm_iterations: 0,
            solver_status: String::new(),
            presolved: false,
            disc: false,
            note: None,
        }
    }
}

/// The peaks of all fields at `u`.
pub fn field_peaks(
    fields: &[Field],
    u: P2,
    s: &Settings,
) -> Result<Vec<PeriodicPeak>, SearchError> {
    fields
        .iter()
        .map(|f| match f.scan_grid(s) {
            Some(g) => {
                let ys: Vec<f64> = g.iter().map(|a| f.magnitude_of(a, u)).collect();
                periodic_peak_sampled(
                    &ys,
                    |phi| f.magnitude(phi, u),
                    Some(s.peak_xtol),
                    Refine::All,
                )
            }
            None => periodic_peak(|phi| f.magnitude(phi, u), s.scan_n(), s.peak_xtol),
        })
        .collect()
}

/// ‖A u + b‖ ≤ (t-variable `t` or the constant `bound`) as one second-order cone.
fn affine_cone(rows: &mut Rows, aff: &Affine, dim: usize, t: Option<usize>, bound: f64) {
    match t {
        Some(tj) => rows.row(&[(tj, -1.0)], 0.0),
        None => rows.row(&[], bound),
    }
    for r in 0..dim {
        rows.row(&[(0, -aff.a[r][0]), (1, -aff.a[r][1])], aff.b[r]);
    }
    rows.cones.push(SupportedConeT::SecondOrderConeT(dim + 1));
}

/// The cone program of the sampled problem; each limit `pb.limits[i]` is imposed as
/// `lim·(1 − margin[i])` (a margin that keeps the continuous peak under the limit). Returns
/// also, per limit, the rows holding its cones' bound (their duals z₀ are the limit's
/// multiplier: ∂(dual objective)/∂lim = −Σ z₀).
fn build(pb: &Problem, samples: &[f64], s: &Settings, margin: &[f64]) -> (Built, Vec<Vec<usize>>) {
    // Variables: u (0, 1), then t or s (2) when the goal needs it.
    let extra = !matches!(pb.goal, Goal::MinMeanSquare(_));
    let n = if extra { 3 } else { 2 };
    let mut rows = Rows::default();
    let mut q = vec![0.0; n];
    let mut p = CscMatrix::zeros((n, n));
    match pb.goal {
        Goal::MinPeak(i) => {
            q[2] = 1.0;
            let f = &pb.fields[i];
            for &phi in samples {
                affine_cone(&mut rows, &(f.eval)(phi), f.dim, Some(2), 0.0);
            }
        }
        Goal::MinNorm => {
            q[2] = 1.0;
            rows.row(&[(2, -1.0)], 0.0);
            rows.row(&[(0, -1.0)], 0.0);
            rows.row(&[(1, -1.0)], 0.0);
            rows.cones.push(SupportedConeT::SecondOrderConeT(3));
        }
        Goal::MinMeanSquare(i) => {
            // mean |A u + b|² = uᵀ H u + 2 gᵀ u + c, with clarabel's ½ xᵀ P x + qᵀ x: P = 2H, q = 2g.
            let f = &pb.fields[i];
            let m = s.rms_n();
            let (mut h, mut g) = ([[0.0; 2]; 2], [0.0; 2]);
            for k in 0..m {
                let aff = (f.eval)(k as f64 * std::f64::consts::TAU / m as f64);
                for r in 0..f.dim {
                    for c in 0..2 {
                        g[c] += aff.a[r][c] * aff.b[r] / m as f64;
                        for (d, hcd) in h[c].iter_mut().enumerate() {
                            *hcd += aff.a[r][c] * aff.a[r][d] / m as f64;
                        }
                    }
                }
            }
            p = CscMatrix::new_from_triplets(
                2,
                2,
                vec![0, 0, 1],
                vec![0, 1, 1],
                vec![2.0 * h[0][0], 2.0 * h[0][1], 2.0 * h[1][1]],
            );
            q = vec![2.0 * g[0], 2.0 * g[1]];
        }
    }
    let mut limit_rows = Vec::with_capacity(pb.limits.len());
    for (k, &(i, lim)) in pb.limits.iter().enumerate() {
        let f = &pb.fields[i];
        let lim = lim * (1.0 - margin.get(k).copied().unwrap_or(0.0));
        let mut at = Vec::with_capacity(samples.len());
        for &phi in samples {
            at.push(rows.b.len());
            affine_cone(&mut rows, &(f.eval)(phi), f.dim, None, lim);
        }
        limit_rows.push(at);
    }
    if pb.u_max.is_finite() {
        rows.row(&[], pb.u_max);
        rows.row(&[(0, -1.0)], 0.0);
        rows.row(&[(1, -1.0)], 0.0);
        rows.cones.push(SupportedConeT::SecondOrderConeT(3));
    }
    match pb.direction {
        Direction::Free => {}
        Direction::Fixed { beta, min_len } => {
            let (sb, cb) = beta.sin_cos();
            // −sin β·u_x + cos β·u_y = 0 and cos β·u_x + sin β·u_y ≥ min_len.
            rows.row(&[(0, -sb), (1, cb)], 0.0);
            rows.cones.push(SupportedConeT::ZeroConeT(1));
            rows.row(&[(0, -cb), (1, -sb)], -min_len);
            rows.cones.push(SupportedConeT::NonnegativeConeT(1));
        }
        Direction::Sector { lo, hi } => {
            // u inside the wedge: left of the ray at lo and right of the ray at hi.
            let (sl, cl) = lo.sin_cos();
            let (sh, ch) = hi.sin_cos();
            rows.row(&[(0, sl), (1, -cl)], 0.0); // cos lo·u_y − sin lo·u_x ≥ 0
            rows.row(&[(0, -sh), (1, ch)], 0.0); // sin hi·u_x − cos hi·u_y ≥ 0
            rows.cones.push(SupportedConeT::NonnegativeConeT(2));
        }
    }
    (rows.build(n, p, q), limit_rows)
}

/// Solves the problem by the exchange loop (see the module doc): the geometric presolve
/// and the exact disc rounds where they apply, else clarabel's rounds ([`Rounds::round`]).
pub fn solve(pb: &Problem, s: &Settings) -> Solution {
    let presolved = if s.presolve {
        enclosing_presolve(pb, s)
    } else {
        None
    };
    if let (Some(start), true) = (&presolved, s.exact_disc) {
        if let Some(sol) = disc_exchange(pb, s, start) {
            return sol;
        }
    }
    let mut rounds = Rounds::start(pb, s, presolved);
    for round in 1..=s.max_rounds {
        if rounds.round(pb, s, round) {
            return rounds.last;
        }
    }
    rounds.last.note = Some(max_rounds_note(s.max_rounds));
    rounds.last
}

/// What clarabel's exchange rounds carry from one round to the next.
struct Rounds {
    /// The sampled angles.
    samples: Vec<f64>,
    /// clarabel interior-point iterations so far.
    iters: u32,
    /// clarabel's accuracy for the next round: a round far from convergence only needs to
    /// locate the next angles, so its tolerance follows the last round's relative gap (two
    /// orders tighter), down to the target in the final rounds.
    round_tol: f64,
    /// The last round's solution (a failed one before the first).
    last: Solution,
    /// Relative tightening of each limit in the cone program: a limit is met only when the
    /// design's continuous (refined) peak is at or under it, so a design over it by v·lim
    /// tightens the next round's limit by about v (and the bound pays for it, in
    /// [`Rounds::limit_shift`]).
    margin: Vec<f64>,
    /// Whether the geometric presolve chose the first angles.
    presolved: bool,
}

impl Rounds {
    /// The first round's angles: the presolve's (already the active ones: the first round
    /// is the last, at the target tolerance), else `initial_samples` uniform ones; then the
    /// problem's warm angles.
    fn start(pb: &Problem, s: &Settings, presolved: Option<Vec<(f64, P2)>>) -> Rounds {
        let was_presolved = presolved.is_some();
        let mut samples = presolved.map_or_else(
            || uniform_angles(s.initial_samples),
            |at| at.iter().map(|&(a, _)| a).collect(),
        );
        for &phi in &pb.warm_angles {
            if is_new(&samples, phi) {
                samples.push(phi);
            }
        }
        Rounds {
            samples,
            iters: 0,
            round_tol: if was_presolved {
                s.rel_tol
            } else {
                first_round_tol(s.rel_tol)
            },
            last: Solution::failed(),
            margin: vec![0.0; pb.limits.len()],
            presolved: was_presolved,
        }
    }

    /// One round: the SOCP on the sampled angles, the refined peaks at its design, the
    /// verdict and the exchange of angles. True when the solve ends (`last` is the result).
    fn round(&mut self, pb: &Problem, s: &Settings, round: usize) -> bool {
        let (bt, limit_rows) = build(pb, &self.samples, s, &self.margin);
        let res = match run_clarabel(&bt, self.round_tol) {
            Ok(r) => r,
            Err(e) => {
                self.last.note = Some(e);
                return true;
            }
        };
        self.iters += res.iterations;
        let status_txt = format!("{:?}", res.status);
        if self.solver_stopped(&res, &status_txt, round) {
            return true;
        }
        let u = P2::new(res.x[0], res.x[1]);
        let peaks = match field_peaks(&pb.fields, u, s) {
            Ok(p) => p,
            Err(e) => {
                self.last.note = Some(format!("peak evaluation failed: {e}"));
                return true;
            }
        };
        let lower = res.obj.min(res.obj_dual) - self.limit_shift(pb, &res.z, &limit_rows);
        // Gap of the objective.
        let (obj_gap, scale) = match pb.goal {
            Goal::MinPeak(i) => ((peaks[i].peak.fx - lower).max(0.0), peaks[i].peak.fx),
            _ => (0.0, 1.0),
        };
        let (converged, tightened) = self.verdict(pb, s, &peaks, obj_gap, scale);
        let almost = res.status == SolverStatus::AlmostSolved;
        self.last = Solution {
            status: if converged && !almost {
                Status::Optimal
            } else {
                Status::Inaccurate
            },
            u,
            sampled_objective: match pb.goal {
                Goal::MinPeak(_) => lower,
                _ => res.obj,
            },
            peaks,
            gap: obj_gap,
            rounds: round,
            samples: self.samples.len(),
            ipm_iterations: self.iters,
            solver_status: status_txt,
            presolved: self.presolved,
            disc: false,
            note: if almost {
                Some("clarabel reached reduced accuracy only (AlmostSolved)".into())
            } else {
                None
            },
        };
        // Limit violations are reported in the gap too (absolute, normalised units).
        let viol_abs = pb
            .limits
            .iter()
            .map(|&(i, lim)| (self.last.peaks[i].peak.fx - lim).max(0.0))
            .fold(0.0, f64::max);
        self.last.gap = self.last.gap.max(viol_abs);
        if converged {
            return true;
        }
        if self.exchange(pb, s, u, lower, scale) == 0 && !tightened {
            self.last.note = Some(stalled_note(round, "clarabel's accuracy"));
            return true;
        }
        false
    }

    /// clarabel's status of a round: infeasible, or stopped short (the previous round's
    /// design kept, or none). True when the solve ends there (`last` then says why).
    fn solver_stopped(&mut self, res: &ConicResult, status_txt: &str, round: usize) -> bool {
        let last = &mut self.last;
        match res.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => false,
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                last.status = Status::Infeasible;
                last.solver_status = status_txt.to_string();
                last.rounds = round;
                last.samples = self.samples.len();
                last.ipm_iterations = self.iters;
                last.note = Some("the constraints cannot all be met on the sampled angles (so not on all angles either)".into());
                true
            }
            // InsufficientProgress, MaxIterations, NumericalError …: keep the iterate if it
            // is finite and say so; the gap below tells how good it is.
            _ if res.x.iter().all(|v| v.is_finite()) && round > 1 => {
                last.status = Status::Inaccurate;
                last.solver_status = status_txt.to_string();
                last.note = Some(format!(
                    "clarabel stopped with {status_txt}; the previous round's design is kept"
                ));
                last.rounds = round;
                last.ipm_iterations = self.iters;
                true
            }
            _ if res.x.iter().all(|v| v.is_finite()) => false,
            _ => {
                last.solver_status = status_txt.to_string();
                last.note = Some("clarabel returned no finite iterate".into());
                true
            }
        }
    }

    /// The sampled bound at the tightened limits lim′ = lim(1 − margin) moved to the true
    /// limits by weak duality: the dual objective is affine in each limit with slope −Σz₀,
    /// so at lim it is the bound at lim′ minus Σz₀·(lim − lim′), the shift returned.
    fn limit_shift(&self, pb: &Problem, z: &[f64], limit_rows: &[Vec<usize>]) -> f64 {
        pb.limits
            .iter()
            .zip(limit_rows)
            .zip(&self.margin)
            .map(|((&(_, lim), rows), &mg)| {
                rows.iter().map(|&r| z[r].max(0.0)).sum::<f64>() * lim * mg
            })
            .sum()
    }

    /// The verdict on a round from its objective gap (relative to `scale`) and the limits'
    /// relative violations: (converged, a limit's margin tightened). Sets the next round's
    /// clarabel tolerance.
    fn verdict(
        &mut self,
        pb: &Problem,
        s: &Settings,
        peaks: &[PeriodicPeak],
        obj_gap: f64,
        scale: f64,
    ) -> (bool, bool) {
        let violation = pb
            .limits
            .iter()
            .map(|&(i, lim)| (peaks[i].peak.fx - lim).max(0.0) / lim.abs().max(1e-300))
            .fold(0.0, f64::max);
        // A limit is met when the refined peak is at or under it: not "within rel_tol".
        let converged = obj_gap <= s.rel_tol * scale.max(1e-300) && violation == 0.0;
        let mut tightened = false;
        for (k, &(i, lim)) in pb.limits.iter().enumerate() {
            let v = (peaks[i].peak.fx - lim) / lim.abs().max(1e-300);
            if v > 0.0 && v <= s.rel_tol.max(1e-6) {
                self.margin[k] += 1.05 * v + 4.0 * f64::EPSILON;
                tightened = true;
            }
        }
        let rel_gap = (obj_gap / scale.abs().max(1e-300)).max(violation);
        // A round solved at a looser tolerance than the target cannot certify the target:
        // unless it already meets it, the next round tightens.
        self.round_tol = next_round_tol(self.round_tol, rel_gap, s.rel_tol);
        (converged, tightened)
    }

    /// Exchange: drop the samples far from active (a subset still gives a lower bound, and
    /// a small SOCP is a fast one), then add every local maximum of the last design `u`
    /// that is above the sampled bound (objective) or above its limit. Returns the number
    /// added.
    fn exchange(&mut self, pb: &Problem, s: &Settings, u: P2, lower: f64, scale: f64) -> usize {
        let keep = |phi: f64| -> bool {
            let near = |i: usize, level: f64| {
                pb.fields[i].magnitude(phi, u) >= (1.0 - s.keep_band) * level
            };
            let obj = match pb.goal {
                Goal::MinPeak(i) => near(i, lower),
                _ => false,
            };
            obj || pb.limits.iter().any(|&(i, lim)| near(i, lim))
        };
        self.samples.retain(|&phi| keep(phi));
        let mut added = 0;
        let mut add = |phi: f64, samples: &mut Vec<f64>| {
            if is_new(samples, phi) {
                samples.push(phi);
                added += 1;
            }
        };
        if let Goal::MinPeak(i) = pb.goal {
            for m in &self.last.peaks[i].maxima {
                if m.fx > lower + 0.5 * s.rel_tol * scale {
                    add(m.x, &mut self.samples);
                }
            }
        }
        for &(i, lim) in &pb.limits {
            for m in &self.last.peaks[i].maxima {
                if m.fx > lim {
                    add(m.x, &mut self.samples);
                }
            }
        }
        added
    }
}

/// Geometric presolve of a minimax force, `min_u max_φ ‖A(φ)u + b(φ)‖`, when every A(φ) is
/// c·Q(φ) with Q orthogonal and one constant c > 0 — the force of a counterweight turning
/// with the crank, c·Rot(φ)·U. Then ‖A u + b‖ = c‖u − p(φ)‖ with p(φ) = −Aᵀb/c² (the
/// unbalance that would cancel the force at φ), so the minimax over sampled angles is the
/// smallest disc enclosing the points p(φ_k): its centre is the optimal u and c times its
/// radius the optimal peak ([`crate::geom::enclosing_disc`], linear time).
///
/// On `scan_samples` angles this locates the optimum to the sampling error only, so the
/// angles of the disc's near-active points (local maxima of ‖u − p‖ within `keep_band` of
/// the radius) are refined on the continuous curve (from their three samples, Brent on the
/// neighbouring intervals as a fallback) and the disc of the refined points recomputed,
/// until the angles move less than x_tol = √(0.01·`rel_tol`) (the bound changes with the
/// square of an angle error), or are predicted to: the rounds are a fixed-point iteration
/// that contracts, and when the last move m_k times the last contraction m_k/m_{k−1} is
/// below x_tol, the confirming round is left to the exchange loop, whose first check
/// refines the same maxima at the same centre. Those angles, with their points p, start the
/// exchange loop: solved exactly as discs when `disc_exchange` applies, else by clarabel at
/// the target tolerance under all the problem's constraints. The presolve only chooses
/// where to look; the exchange loop still verifies (and corrects) the result. `None` when
/// the goal is not a peak force of that form.
pub fn enclosing_presolve(pb: &Problem, s: &Settings) -> Option<Vec<(f64, P2)>> {
    let form = ObjectiveDisc::of(pb)?;
    // p(φ) is independent of u, and each round's refinement ends on an angle it evaluated:
    // the disc of the refined angles and the next round's middle sample are remembered
    // values (the same numbers, not recomputed).
    let memo = std::cell::RefCell::new(Vec::<(f64, P2)>::with_capacity(32));
    let point = |phi: f64| -> Option<P2> {
        if let Some(&(_, p)) = memo
            .borrow()
            .iter()
            .find(|(a, _)| a.to_bits() == phi.to_bits())
        {
            return Some(p);
        }
        let p = form.point(phi)?;
        memo.borrow_mut().push((phi, p));
        Some(p)
    };
    let n = s.scan_n();
    let h = std::f64::consts::TAU / n as f64;
    let pts: Vec<P2> = match form.f.scan_grid(s) {
        Some(g) => g.iter().map(|a| form.point_of(a)).collect::<Option<_>>()?,
        None => (0..n)
            .map(|k| form.point(k as f64 * h))
            .collect::<Option<_>>()?,
    };
    let disc = crate::geom::enclosing_disc(&pts)?;
    let dist = |p: P2, u: P2| (p - u).norm();
    let level = (1.0 - s.keep_band) * disc.radius;
    let mut angles: Vec<f64> = (0..n)
        .filter(|&k| {
            let d = dist(pts[k], disc.centre);
            d >= level
                && d > dist(pts[(k + n - 1) % n], disc.centre)
                && d >= dist(pts[(k + 1) % n], disc.centre)
        })
        .map(|k| k as f64 * h)
        .collect();
    // An angle δ off a maximum of ‖u − p(φ)‖ moves p(φ) along the circle to first order,
    // so the disc, and the SOCP's bound, change by O(δ²): angles to √(0.01·rel_tol) are
    // enough (3e-6 rad for 1e-9), and the loose tolerance saves Brent's end game.
    let xtol = (0.01 * s.rel_tol).sqrt().max(s.peak_xtol);
    let mut u = disc.centre;
    let mut last_move = f64::INFINITY;
    let mut at: Vec<(f64, P2)> = Vec::new();
    for round in 0..8 {
        let mut moved: f64 = 0.0;
        let mut refined = Vec::with_capacity(angles.len());
        for &phi in &angles {
            // Refined from three samples around φ (`refine_sampled_max`, ~5 evaluations
            // where Brent from one point takes ~13): the first round's are on the scan
            // grid, already known; later rounds sample φ ± h afresh. Where φ is not the
            // best of its three samples (the maximum moved by over h/2), Brent on [φ − h,
            // φ + h] as before.
            let g = |x: f64| point(x).map_or(f64::NAN, |p| dist(p, u));
            let ys = if round == 0 {
                let k = (phi / h).round() as usize % n;
                [pts[(k + n - 1) % n], pts[k], pts[(k + 1) % n]].map(|p| dist(p, u))
            } else {
                [g(phi - h), g(phi), g(phi + h)]
            };
            let e = match crate::numeric::refine_sampled_max(g, phi, h, ys, xtol) {
                Ok((e, _)) => e,
                Err(_) => crate::numeric::brent_max(g, phi - h, phi + h, xtol).ok()?,
            };
            moved = moved.max(angle_dist(e.x, phi));
            refined.push(e.x.rem_euclid(std::f64::consts::TAU));
        }
        refined.dedup_by(|a, b| angle_dist(*a, *b) <= 1e-9);
        angles = refined;
        at = angles
            .iter()
            .map(|&a| point(a).map(|p| (a, p)))
            .collect::<Option<_>>()?;
        u = DiscSamples::of(&at).disc()?.centre;
        let contracting = round > 0 && moved < 0.5 * last_move;
        if moved <= xtol || (contracting && moved * (moved / last_move) <= xtol) {
            break;
        }
        last_move = moved;
    }
    Some(at)
}

/// The objective field of a problem in the smallest-disc form ([`DiscForm`]: every A(φ) is
/// c·Q(φ), Q orthogonal, c from φ = 0), when the goal is its peak and it has it.
struct ObjectiveDisc<'p, 'a> {
    /// The objective field and its index in the problem.
    f: &'p Field<'a>,
    i: usize,
    form: DiscForm,
}

impl<'p, 'a> ObjectiveDisc<'p, 'a> {
    /// The objective field of `pb`, when the goal is its peak and it has the form.
    fn of(pb: &'p Problem<'a>) -> Option<Self> {
        let Goal::MinPeak(i) = pb.goal else {
            return None;
        };
        let f = &pb.fields[i];
        if f.dim != 2 {
            return None;
        }
        DiscForm::scaled_by(&(f.eval)(0.0)).map(|form| ObjectiveDisc { f, i, form })
    }

    /// p of one affine value of the field.
    fn point_of(&self, aff: &Affine) -> Option<P2> {
        self.form.point_of(aff)
    }

    /// p(φ).
    fn point(&self, phi: f64) -> Option<P2> {
        self.form.point_of(&(self.f.eval)(phi))
    }
}

/// The exchange loop with the sampled minimax solved exactly, as the smallest disc enclosing
/// p(φ_k) ([`DiscForm`], [`DiscSamples`]) by Welzl's algorithm, instead of by clarabel's SOCP: the two are
/// the same problem when the goal is the peak of such a force, the direction is free, no
/// field has a limit and the disc's centre is within `u_max` (the disc is then also the
/// SOCP's optimum, to round-off instead of to an interior-point tolerance). Starts from the
/// presolve's angles; each round checks the refined true peak at the centre, as the SOCP
/// loop does, and adds the maxima above the disc's bound. `None` when the problem is not of
/// that kind (the caller then runs clarabel).
fn disc_exchange(pb: &Problem, s: &Settings, start: &[(f64, P2)]) -> Option<Solution> {
    if !(pb.limits.is_empty() && pb.direction == Direction::Free) {
        return None;
    }
    let form = ObjectiveDisc::of(pb)?;
    let (i, c) = (form.i, form.form.c());
    // The sampled angles and their points p(φ) (the presolve's are known).
    let mut sampled = DiscSamples::of(start);
    let mut last = None;
    for round in 1..=s.max_rounds {
        let disc = sampled.disc()?;
        if !(disc.centre.norm() <= pb.u_max) {
            return None;
        }
        let (u, lower) = (disc.centre, c * disc.radius);
        let peaks = match field_peaks(&pb.fields, u, s) {
            Ok(p) => p,
            Err(e) => {
                return Some(Solution {
                    note: Some(format!("peak evaluation failed: {e}")),
                    ..Solution::failed()
                })
            }
        };
        let peak = peaks[i].peak.fx;
        let gap = (peak - lower).max(0.0);
        let converged = gap <= s.rel_tol * peak.max(1e-300);
        let added: Vec<f64> = peaks[i]
            .maxima
            .iter()
            .filter(|m| m.fx > lower + 0.5 * s.rel_tol * peak)
            .map(|m| m.x)
            .filter(|&x| sampled.is_new(x))
            .collect();
        let sol = Solution {
            status: if converged {
                Status::Optimal
            } else {
                Status::Inaccurate
            },
            u,
            sampled_objective: lower,
            peaks,
            gap,
            rounds: round,
            samples: sampled.len(),
            ipm_iterations: 0,
            solver_status: "exact".into(),
            presolved: true,
            disc: true,
            note: None,
        };
        if converged {
            return Some(sol);
        }
        if added.is_empty() {
            return Some(Solution {
                note: Some(stalled_note(round, "the peak refinement's accuracy")),
                ..sol
            });
        }
        for phi in added {
            sampled.push(phi, form.point(phi)?);
        }
        last = Some(sol);
    }
    last.map(|l| Solution {
        note: Some(max_rounds_note(s.max_rounds)),
        ..l
    })
}
