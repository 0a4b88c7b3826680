//! Certified affine minimax over a periodic parameter: the convex engine of the general
//! planar-linkage family (issue 17), written against callbacks so that it knows no
//! mechanism.
//!
//! # The problem
//! A design vector x ∈ Rⁿ holds, first, four variables per counterweight j — its mass m_j,
//! its first moment u_j = m_j p_j (2 components, in its link's frame, about its joint P_j)
//! and its inertia about P_j, I_j = J_j + m_j|p_j|² — and then any `extra` scalar variables.
//! Each field f is affine in x at every angle θ ∈ [0, 2π):
//!
//! g_f(θ; x) = b_f(θ) + A_f(θ) x ∈ R^d,  d = 1 (a moment, a torque: |g| = abs) or
//! d = 2 (a force: |g| = Euclidean norm),
//!
//! given by an [`AffineField`] callback. The constraints on x (all convex):
//! * 0 ≤ m_j ≤ m_max; the centroid radius |u_j| ≤ r_max m_j (second-order cone);
//! * a real body, J_j ≥ 0: I_j m_j ≥ |u_j|², the rotated cone, written as the standard
//!   cone ‖(2u_j, I_j − m_j)‖ ≤ I_j + m_j (clarabel 0.11 has no rotated cone; its generalised
//!   power cone would do it too, but is non-symmetric and slower);
//! * optional: I_j ≤ I_max, an envelope I_j ≤ ρ² m_j (all the body within ρ of P_j, which
//!   implies both |u_j| ≤ ρ m_j and bounded I_j), a sector of directions of u_j up to π wide
//!   (two half-planes and u·bisector ≥ 0);
//! * bounds on the extra variables and generic linear equalities / inequalities (full force
//!   balance, fixed values).
//!
//! The goals ([`Goal`]), over a finite set of angles θ_k per field:
//! 1. min t s.t. w_f |g_f(θ_k; x)| ≤ t for the objective fields (weighted minimax);
//! 2. with any goal, ε-constraints |g_f(θ_k; x)| ≤ ε_f on limited fields;
//! 3. min RMS of one field over N uniform angles: (1/√N)‖(g(θ_k; x))_k‖ = ‖R [x; 1]‖ with R
//!    the triangular factor of the stacked rows (Householder QR), one cone of size n + 2;
//! 4. min Σ m_j (the lightest counterweights) subject to the limits.
//!
//! [`Engine::pareto`] minimises the peak of field A subject to peak B ≤ ε for a list of ε,
//! each point its own certified solve.
//!
//! # The exchange loop and its certificate
//! The problem on a subset of angles is a relaxation, so its optimum is a lower bound of the
//! true optimum. At the returned design x̂ the true peak of each field is found over the
//! whole period (the field on `scan_samples` angles, cached once per engine since it is
//! affine in x, then every sampled local maximum refined by
//! [`crate::numeric::periodic_peak_sampled`]); the objective there, V, is an upper bound.
//! The new peak angles are added and the SOCP re-solved until V − L ≤ `rel_tol`·max(V,
//! `abs_floor`·U₀) (U₀ the unbalanced peak, max w_f|b_f|) and every limited field's peak is
//! within `rel_tol`·max(ε_f, `abs_floor`·|b_f|max) of ε_f.
//!
//! L is not clarabel's reported objective but a weak-duality bound at its dual point
//! (`conic::dual_lower_bound`: z put into the dual cone, then qᵀx ≥ −bᵀz − Σ|r_j|B_j with r
//! the dual residual and B_j the bound on |x̂_j| implied by the design constraints), so it
//! holds whatever clarabel's accuracy. Each round also forms the Lagrangian bound at the
//! refined maxima ([`Engine`]'s `dual_bound`: the round's multipliers on the cones moved to
//! the exact maximum angles, in a norm and a linearised form, each a small SOCP over the
//! design constraints, again bounded by weak duality); L is the best of these. Where a
//! maximum creeps (a single active maximum against a curved constraint such as the inertia
//! cone) the angles θ ± δ are added around it, δ = √(2·rel_tol·level/|f''|); a stall with
//! a gap left restarts once from the refined maxima alone.
//!
//! Between rounds the angle sets are pruned to the cones active at the round's optimum
//! (dual weight, or value within 1e-6 of the sampled bound) and those of the previous round
//! (against cycling), so the SOCP stays small; a subset still gives a relaxation. V and L
//! carry over: the gap is taken between the best design so far (smallest refined peak
//! within the limits' tolerance, the design returned) and the largest rigorous L so far.
//!
//! # The Newton polish
//! clarabel's design is only as accurate as its cones allow (about 1e-8 relative where the
//! sampled angles cluster around maxima that move with the design), so the loop alone stalls
//! short of 1e-9. Once a round's refined maxima are within 1e-3 of its bound, the engine
//! solves the continuous problem's optimality conditions by Newton (`polish`: the design,
//! the peak, the active maxima's angles, their multipliers and those of the active design
//! constraints; negative multipliers drop their constraint, violated maxima and design
//! constraints join). The polished design, if it meets the design constraints to 1e-12, is
//! certified as any other: V its refined true peak, L the Lagrangian bound at the polished
//! angles and multipliers, first with the design cones' dual point formed from Newton's
//! multipliers (`kkt_bound`, rigorous by weak duality at any dual point, and tight where
//! large limit multipliers make a clarabel solve of the bound lose digits), else by the
//! SOCPs of `dual_bound`. A Pareto front starts each point's Newton from its neighbour's
//! polished conditions before any SOCP. Where Newton fails the loop goes on unchanged.
//!
//! The status is `optimal` only when the gap is within the tolerance and clarabel reported
//! `Solved` on the design's SOCP (or its bound came from a Lagrangian bound); otherwise
//! `inaccurate` with the reason ([`Stop`]) and the gap, or `infeasible` when clarabel
//! certifies the sampled problem infeasible (then the continuous one is too).
//!
//! # The exact disc path
//! The peak of one 2-D field that depends only on a single counterweight's u through a
//! scaled rotation, g = b(θ) + c·Q(θ)u (a counterweight on a frame pivot turning with the
//! crank), with no limit, linear row, extra variable or sector, is a smallest enclosing disc
//! of the curve p(θ) = −Qᵀb/c: the engine solves it without clarabel (`Engine::disc_path`:
//! Welzl on the sampled points, the disc's support angles polished by Newton on the curve,
//! since a disc on two points leaves the exchange creeping along its diameter). Its
//! certificate is the same pair: the refined peak at the design and a Lagrangian lower
//! bound (weights on the support, `Engine::disc_bound`), neither resting on the form;
//! `exact_disc = false` always runs clarabel.
//!
//! # Error bound (every figure, caller's units)
//! For a field's peak P_f at x̂: E_f = e_refine + e_eval, with e_refine = ½|f''|·xtol² (the
//! refinement, [`crate::numeric::PeriodicPeak::error`]) and e_eval = max over the refined
//! local maxima θ_i of [err_f(θ_i, x̂) + (n + 3)·ε·‖(|b_r| + Σ_j |A_rj x̂_j|)_r‖]: the
//! callback's own bound on the evaluation of b and A (round-off, conditioning near toggle)
//! plus the engine's round-off of b + A x̂ and of the norm. A peak narrower than the scan
//! spacing 2π/`scan_samples` is assumed absent (callers choose the scan for their fields).
//!
//! For the objective V as an estimate of the true optimum V*:
//! |V − V*| ≤ `total` = gap + e_eval + e_refine (+ e_quad for an RMS), where gap =
//! |V − L| is the sampling certificate (it contains the solver's residual part,
//! reported as `solver`), e_eval is the largest evaluation error over the objective fields'
//! sampled angles and maxima (a field wrong by e at θ_k moves the sampled optimum by at most
//! e), e_refine the largest refinement error, and for an RMS e_quad = |rms_N − rms_{N/2}|
//! (the trapezoid rule's estimate, [`crate::numeric::periodic_rms_sampled`]). Only with an
//! unbounded extra variable is L clarabel's own bound; `solver` is then an estimate
//! (T·(|p − d| + r_d·max(1, ‖b‖ + ‖x‖ + ‖s‖ + ‖z‖ + ‖q‖))) and is added to `total`.
//! The design's own objective is within e_eval + e_refine (+ e_quad) of V.
//!
//! # Scaling
//! clarabel works on non-dimensional numbers: each counterweight's variables are divided by
//! s_m = m_max, s_u = s_m ℓ, s_I = s_m ℓ² (ℓ = r_max, else ρ, else √(I_max/m_max)), which
//! keeps the rotated cone Î m̂ ≥ |û|² unchanged; an extra variable by its largest finite bound
//! (else by the field's size over its sensitivity); each field by its size over the design
//! box, G_f = max_grid (‖b_f‖ + Σ_j ‖A_f,j‖ s_j); linear rows by their largest coefficient.
//! Results are returned in the caller's units.
//!
//! # Determinism
//! Everything is sequential; angle sets are kept sorted and a new angle is one not within
//! 1e-9 rad of a sampled one, so the result does not depend on the thread count.

use crate::numeric::{periodic_peak_sampled, periodic_rms_sampled, Extremum, PeriodicPeak, Refine};
use crate::synth::conic::{dual_lower_bound, run_clarabel_with, Built, ConicResult, Rows};
use crate::synth::counterweight::{check_exchange, is_new, uniform_angles, Status};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{SolverStatus, SupportedConeT};
use polish::{Design, Term};
use std::cell::RefCell;

mod polish;

/// `Solution::solver_status` of a solve by the exact disc path (no clarabel).
pub const DISC_SOLVER: &str = "exact: smallest enclosing disc";

/// Variables per counterweight: m, u_x, u_y, I (in this order, at `4j`).
pub const PER_COUNTERWEIGHT: usize = 4;

/// Index of counterweight j's mass m_j in x.
pub fn var_m(j: usize) -> usize {
    PER_COUNTERWEIGHT * j
}
/// Index of u_j,x (u_j,y follows).
pub fn var_u(j: usize) -> usize {
    PER_COUNTERWEIGHT * j + 1
}
/// Index of I_j, the inertia about the joint.
pub fn var_i(j: usize) -> usize {
    PER_COUNTERWEIGHT * j + 3
}

/// One value of an affine field at an angle: g = b + A x, with A stored row-major as two
/// rows of n (a scalar field uses row 0 and b[0] only).
#[derive(Debug, Clone, PartialEq)]
pub struct AffineValue {
    /// b (caller's units of the field).
    pub b: [f64; 2],
    /// A, rows 0 and 1, each of length n.
    pub a: Vec<f64>,
}

impl AffineValue {
    /// All zero, for n variables.
    pub fn zeros(n: usize) -> Self {
        AffineValue {
            b: [0.0; 2],
            a: vec![0.0; 2 * n],
        }
    }
    /// n.
    pub fn n(&self) -> usize {
        self.a.len() / 2
    }
    /// Row r of A.
    pub fn row(&self, r: usize) -> &[f64] {
        let n = self.n();
        &self.a[r * n..(r + 1) * n]
    }
    /// Row r of A, to fill in.
    pub fn row_mut(&mut self, r: usize) -> &mut [f64] {
        let n = self.n();
        &mut self.a[r * n..(r + 1) * n]
    }
    /// b + A x (row 1 is 0 for a scalar field).
    pub fn at(&self, dim: usize, x: &[f64]) -> [f64; 2] {
        let mut v = [0.0; 2];
        for (r, vr) in v.iter_mut().enumerate().take(dim) {
            *vr = self.b[r] + dot(self.row(r), x);
        }
        v
    }
    /// |b + A x|: abs for dim 1, Euclidean for dim 2.
    pub fn magnitude(&self, dim: usize, x: &[f64]) -> f64 {
        let v = self.at(dim, x);
        if dim == 2 {
            v[0].hypot(v[1])
        } else {
            v[0].abs()
        }
    }
    /// ‖(|b_r| + Σ_j |A_rj x_j|)_r‖: the size the round-off of b + A x is relative to.
    fn size(&self, dim: usize, x: &[f64]) -> f64 {
        let mut s = 0.0;
        for r in 0..dim {
            let t = self.b[r].abs()
                + self
                    .row(r)
                    .iter()
                    .zip(x)
                    .map(|(a, x)| (a * x).abs())
                    .sum::<f64>();
            s += t * t;
        }
        s.sqrt()
    }
}

fn dot(a: &[f64], x: &[f64]) -> f64 {
    a.iter().zip(x).map(|(a, x)| a * x).sum()
}

/// A field over θ, affine in the design: g(θ; x) = b(θ) + A(θ) x.
pub trait AffineField: Sync {
    /// Name used in messages and results.
    fn name(&self) -> &str;
    /// 1 (scalar: moment, torque) or 2 (planar force).
    fn dim(&self) -> usize;
    /// Writes b(θ) and A(θ) into `out` (zeroed beforehand, n = `out.n()`), caller's units.
    fn eval(&self, theta: f64, out: &mut AffineValue);
    /// A bound on |computed − exact| of g(θ; x) from the evaluation of b and A (round-off,
    /// conditioning), caller's units. Default 0 (only the engine's own round-off is counted).
    fn error(&self, theta: f64, x: &[f64]) -> f64 {
        let _ = (theta, x);
        0.0
    }
}

/// An [`AffineField`] from closures: `eval(θ, out)` and optionally `error(θ, x)`.
pub struct FnField<E, R> {
    /// Name.
    pub name: String,
    /// 1 or 2.
    pub dim: usize,
    /// Fills b(θ), A(θ).
    pub eval: E,
    /// Evaluation error bound at (θ, x).
    pub error: R,
}

/// The error callback of a field without one.
pub type NoError = fn(f64, &[f64]) -> f64;

fn no_error(_: f64, _: &[f64]) -> f64 {
    0.0
}

impl<E: Fn(f64, &mut AffineValue) + Sync> FnField<E, NoError> {
    /// A field without an error callback.
    pub fn new(name: impl Into<String>, dim: usize, eval: E) -> Self {
        FnField {
            name: name.into(),
            dim,
            eval,
            error: no_error,
        }
    }
}

impl<E, R> FnField<E, R> {
    /// The same field with an evaluation error bound `error(θ, x)`.
    pub fn with_error<R2: Fn(f64, &[f64]) -> f64 + Sync>(self, error: R2) -> FnField<E, R2> {
        FnField {
            name: self.name,
            dim: self.dim,
            eval: self.eval,
            error,
        }
    }
}

impl<E, R> AffineField for FnField<E, R>
where
    E: Fn(f64, &mut AffineValue) + Sync,
    R: Fn(f64, &[f64]) -> f64 + Sync,
{
    fn name(&self) -> &str {
        &self.name
    }
    fn dim(&self) -> usize {
        self.dim
    }
    fn eval(&self, theta: f64, out: &mut AffineValue) {
        (self.eval)(theta, out)
    }
    fn error(&self, theta: f64, x: &[f64]) -> f64 {
        (self.error)(theta, x)
    }
}

/// The limits of one counterweight (SI: kg, m, kg·m²).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CounterweightLimits {
    /// m_max: 0 ≤ m ≤ m_max (finite, > 0).
    pub m_max: f64,
    /// r_max: centroid radius |u| ≤ r_max·m (> 0; infinite: none).
    pub r_max: f64,
    /// I ≤ I_max about the joint (> 0; infinite: none).
    pub inertia_max: f64,
    /// Envelope radius ρ: I ≤ ρ²·m, all the body within ρ of the joint (> 0; infinite:
    /// none). I must be bounded: by `inertia_max` or by ρ.
    pub envelope: f64,
    /// Directions of u allowed: the angles [lo, hi] (rad, link frame), hi − lo ≤ π.
    pub sector: Option<(f64, f64)>,
}

impl CounterweightLimits {
    /// Mass up to `m_max` within `r_max` of the joint (centroid and envelope), any direction,
    /// no other inertia limit.
    pub fn new(m_max: f64, r_max: f64) -> Self {
        CounterweightLimits {
            m_max,
            r_max,
            inertia_max: f64::INFINITY,
            envelope: r_max,
            sector: None,
        }
    }
    /// ℓ, the length scale of this counterweight's variables.
    fn length(&self) -> f64 {
        if self.r_max.is_finite() {
            self.r_max
        } else if self.envelope.is_finite() {
            self.envelope
        } else {
            (self.inertia_max / self.m_max).sqrt()
        }
    }
}

/// `=` or `≤`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Relation {
    /// Σ c_j x_j = rhs.
    Eq,
    /// Σ c_j x_j ≤ rhs.
    Le,
}

/// A linear constraint Σ c_j x_j (= or ≤) rhs, caller's units.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LinearConstraint {
    /// (variable index, coefficient).
    pub coeffs: Vec<(usize, f64)>,
    /// Relation.
    pub relation: Relation,
    /// Right-hand side.
    pub rhs: f64,
}

/// What to minimise.
#[derive(Debug, Clone, PartialEq)]
pub enum Goal {
    /// max over θ and over the listed (field, weight w > 0) of w·|g_f(θ; x)|.
    MinPeak(Vec<(usize, f64)>),
    /// The RMS over θ of |g_f| (`rms_samples` uniform angles).
    MinRms(usize),
    /// Σ m_j, the total counterweight mass.
    MinMass,
}

/// The convex problem (caller's units).
pub struct Problem<'a> {
    /// The fields.
    pub fields: Vec<&'a dyn AffineField>,
    /// One entry per counterweight: its variables are x[4j..4j+4] = (m, u_x, u_y, I).
    pub counterweights: Vec<CounterweightLimits>,
    /// Bounds (lo, hi) of the extra variables that follow (either may be infinite).
    pub extra: Vec<(f64, f64)>,
    /// Linear constraints on x.
    pub linear: Vec<LinearConstraint>,
    /// Objective.
    pub goal: Goal,
    /// Peak limits: (field, ε): max_θ |g_f(θ; x)| ≤ ε.
    pub limits: Vec<(usize, f64)>,
}

impl Problem<'_> {
    /// n, the length of x.
    pub fn n(&self) -> usize {
        PER_COUNTERWEIGHT * self.counterweights.len() + self.extra.len()
    }
}

/// Why a problem or its settings cannot be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MinimaxError {
    /// A setting out of range (the key as in `[accuracy]`).
    #[error("settings: {field}: {message}")]
    Settings {
        /// The setting.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The problem is malformed (e.g. `counterweights[1].m_max`).
    #[error("problem: {what}: {message}")]
    Problem {
        /// The dotted part of the problem.
        what: String,
        /// What is wrong.
        message: String,
    },
    /// A field returned NaN or an infinity.
    #[error("field `{field}` is not finite at θ = {theta} rad")]
    NotFinite {
        /// The field's name.
        field: String,
        /// The angle.
        theta: f64,
    },
}

fn bad(what: impl Into<String>, message: impl Into<String>) -> MinimaxError {
    MinimaxError::Problem {
        what: what.into(),
        message: message.into(),
    }
}

/// Accuracy settings of the exchange loop (flat, with defaults, Clarabel style).
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// Stop when V − L ≤ `rel_tol`·max(V, `abs_floor`·U₀) and every limit holds to the same
    /// relative tolerance. Default 1e-9.
    pub rel_tol: f64,
    /// Below `abs_floor` times the unbalanced peak U₀ the tolerance is absolute (an optimum of
    /// zero, full force balance, cannot be certified relatively). Default 0.1.
    pub abs_floor: f64,
    /// Equally spaced angles per field in the first SOCP (without warm angles). Default 8.
    pub initial_samples: usize,
    /// Angles of the scan that brackets the local maxima of a design. Default 360.
    pub scan_samples: usize,
    /// Exchange rounds at most. Default 30.
    pub max_rounds: usize,
    /// Angle tolerance of the peak refinement (rad; in a file an angle with its unit,
    /// `"1e-10 rad"`). Default 1e-10.
    #[serde(with = "crate::units::angle_setting")]
    #[schemars(with = "crate::units::Qty<crate::units::Angle>")]
    pub peak_xtol: f64,
    /// Uniform angles of RMS objectives (even). Default 360.
    pub rms_samples: usize,
    /// Solve the peak of a turning counterweight's force exactly, as a smallest enclosing
    /// disc (the engine's `disc_path`), when the problem is one. Default true; false always
    /// runs clarabel's exchange loop.
    pub exact_disc: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            rel_tol: 1e-9,
            abs_floor: 0.1,
            initial_samples: 8,
            scan_samples: 360,
            max_rounds: 30,
            peak_xtol: 1e-10,
            rms_samples: 360,
            exact_disc: true,
        }
    }
}

impl Settings {
    /// Checks every field; the error names the field and its range.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        check_exchange(
            self.rel_tol,
            self.initial_samples,
            self.scan_samples,
            self.max_rounds,
            self.peak_xtol,
        )?;
        if !(self.abs_floor > 0.0 && self.abs_floor <= 1.0) {
            return Err((
                "abs_floor",
                format!("must be in (0, 1], got {}", self.abs_floor),
            ));
        }
        if self.rms_samples < 16 || !self.rms_samples.is_multiple_of(2) {
            return Err((
                "rms_samples",
                format!("must be even and at least 16, got {}", self.rms_samples),
            ));
        }
        Ok(())
    }
}

/// Why the exchange loop stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stop {
    /// Gap and limits within tolerance.
    Converged,
    /// `max_rounds` reached; the gap is stated.
    MaxRounds,
    /// Every local maximum above the bound is already sampled: the remaining gap is the
    /// solver's accuracy.
    Stalled,
    /// clarabel reached reduced accuracy only (AlmostSolved, or an iteration limit after a
    /// usable round).
    SolverAccuracy,
    /// clarabel certified the sampled problem infeasible.
    Infeasible,
    /// clarabel failed before any usable design.
    SolverFailed,
}

/// The refined peak of one field at the design.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FieldPeak {
    /// The field's name.
    pub name: String,
    /// max over θ of |g_f(θ; x)| (caller's units).
    pub peak: f64,
    /// Its angle (rad, in [0, 2π)).
    pub angle: f64,
    /// Bound on |peak − true peak| at this x: refinement + evaluation (module doc).
    pub error: f64,
    /// Every refined local maximum (angle, value), sorted by angle.
    #[serde(skip)]
    pub maxima: Vec<Extremum>,
    /// The limit ε when the field is limited.
    pub limit: Option<f64>,
    /// max(peak − ε, 0).
    pub violation: f64,
}

/// The parts of an objective's error bound (caller's units); see the module doc.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct ErrorBound {
    /// |V − L|: the sampling certificate (V < L only for a design over a limit within
    /// its tolerance).
    pub sampling: f64,
    /// The part of `sampling` due to clarabel's dual residual (Σ|r_j|B_j, scaled back); an
    /// estimate added to `total` only when L could not be made rigorous (module doc).
    pub solver: f64,
    /// The fields' evaluation error (callback + engine round-off).
    pub evaluation: f64,
    /// The peak refinement's error.
    pub refinement: f64,
    /// The RMS quadrature's error estimate (RMS goals only).
    pub quadrature: f64,
    /// |V − V*| ≤ total = sampling + evaluation + refinement + quadrature (module doc).
    pub total: f64,
}

/// One counterweight of a design, in physical terms.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CounterweightDesign {
    /// m (kg).
    pub mass: f64,
    /// u = m p (kg·m, link frame).
    pub first_moment: [f64; 2],
    /// |p| = |u|/m (m); 0 when m = 0.
    pub radius: f64,
    /// Direction of u (rad); 0 when u = 0.
    pub angle: f64,
    /// I about the joint (kg·m²).
    pub inertia: f64,
    /// J = I − |u|²/m ≥ 0, the own centroidal inertia (kg·m²); 0 when m = 0.
    pub centroidal_inertia: f64,
}

/// The outcome of a solve.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Solution {
    /// The claim.
    pub status: Status,
    /// Why the loop stopped.
    pub stop: Stop,
    /// The design (caller's units); NaN when infeasible or failed.
    pub x: Vec<f64>,
    /// V: the goal's value at x (for a peak goal the true refined peak, an upper bound of
    /// the optimum).
    pub objective: f64,
    /// L: the sampled optimum, a lower bound of the optimum (up to `error.solver`).
    pub lower_bound: f64,
    /// The bound on |V − optimum| and its parts.
    pub error: ErrorBound,
    /// The refined peak of every field of the problem, in order.
    pub peaks: Vec<FieldPeak>,
    /// Largest relative violation of the design constraints at x (bounds, cones, sector,
    /// linear rows; each relative to its scale): clarabel's feasibility accuracy.
    pub design_violation: f64,
    /// SOCP solves (0 when Newton alone certified the point from a neighbouring solve's
    /// polished optimality conditions: `solver_status` is then [`NEWTON_ONLY`]).
    pub rounds: usize,
    /// Angles in the final SOCP, all fields.
    pub angles: usize,
    /// The final sampled angles per field (sorted; empty for fields not sampled): warm
    /// starts for a neighbouring solve.
    #[serde(skip)]
    pub angle_sets: Vec<Vec<f64>>,
    /// clarabel interior-point iterations, all rounds.
    pub ipm_iterations: u32,
    /// The last clarabel status, as text.
    pub solver_status: String,
    /// Why the status is not `optimal`, if it is not.
    pub note: Option<String>,
}

impl Solution {
    /// Counterweight j of the design.
    pub fn counterweight(&self, j: usize) -> CounterweightDesign {
        let base = var_m(j);
        let (m, ux, uy, i) = (
            self.x[base],
            self.x[base + 1],
            self.x[base + 2],
            self.x[base + 3],
        );
        let u2 = ux * ux + uy * uy;
        CounterweightDesign {
            mass: m,
            first_moment: [ux, uy],
            radius: if m > 0.0 { u2.sqrt() / m } else { 0.0 },
            angle: if u2 > 0.0 { uy.atan2(ux) } else { 0.0 },
            inertia: i,
            centroidal_inertia: if m > 0.0 { (i - u2 / m).max(0.0) } else { 0.0 },
        }
    }
    /// The peak of field f.
    pub fn peak(&self, f: usize) -> &FieldPeak {
        &self.peaks[f]
    }
}

/// One point of a Pareto front: min peak A subject to peak B ≤ ε.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ParetoPoint {
    /// ε, the limit on field B.
    pub eps: f64,
    /// The certified solve.
    pub solution: Solution,
}

/// A Pareto front with its two ends.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ParetoFront {
    /// min peak B alone (its peak B is the smallest ε).
    pub min_b: Solution,
    /// min peak A alone (its peak B is the largest useful ε).
    pub min_a: Solution,
    /// The points, ε increasing.
    pub points: Vec<ParetoPoint>,
}

/// A problem prepared for solving: validated, scaled, its fields cached on the scan grid.
/// Several goals (a Pareto front) share one engine.
pub struct Engine<'p, 'a> {
    pb: &'p Problem<'a>,
    s: Settings,
    n: usize,
    /// Column scales s_j (x = s ⊙ x̂).
    scale: Vec<f64>,
    /// G_f, each field's size over the design box.
    g_ref: Vec<f64>,
    /// max over the grid of |b_f|: the unbalanced peak (sampled).
    g0: Vec<f64>,
    /// Each field on the scan grid θ_k = 2πk/`scan_samples`.
    grid: Vec<Vec<AffineValue>>,
    /// Bounds on |x̂_j| implied by the design constraints (∞ for an unbounded extra).
    xbound: Vec<f64>,
}

/// The best design of the rounds so far (smallest refined peak among those within the
/// limits' tolerance), with its peaks.
struct BestDesign {
    x: Vec<f64>,
    pk: Vec<Option<PeriodicPeak>>,
    value: f64,
    lim_rel: f64,
}

/// The SOCP solved on one round.
struct Round {
    res: ConicResult,
    /// T: objective scale (L = T·min(p, d)).
    t_scale: f64,
    /// The sampled cones, for the dual bound.
    tags: Vec<ConeTag>,
    /// The program solved.
    built: Built,
}

/// One sampled cone ‖c·g_f(θ; x)‖ ≤ t̂ (objective) or ≤ ε̂ (limit) of a round's SOCP.
struct ConeTag {
    /// Its first row (the t̂ or ε̂ row; its dual is the cone's multiplier).
    row: usize,
    field: usize,
    theta: f64,
    /// The factor c of the field's rows.
    c: f64,
    /// ε̂ for a limit, `None` for an objective cone.
    eps: Option<f64>,
}

/// Newton polishes at most per solve.
const MAX_POLISH: usize = 3;

/// What `Solution::solver_status` contains when the design and its certificate come from
/// the Newton polish of the optimality conditions.
pub const POLISHED: &str = "optimality conditions polished by Newton";

/// `Solution::solver_status` of a solve by Newton alone from a neighbouring solve (no SOCP).
pub const NEWTON_ONLY: &str =
    "not run: optimality conditions polished by Newton from the neighbouring solve";

/// A solve's polished optimality conditions, the start of a neighbouring solve's Newton:
/// the scaled design x̂, t̂ and the active maxima with their multipliers.
struct KktStart {
    x_hat: Vec<f64>,
    t_hat: f64,
    terms: Vec<Term>,
}

/// A polished design with its certificate parts (caller's units).
struct PolishOutcome {
    x: Vec<f64>,
    pk: Vec<Option<PeriodicPeak>>,
    /// V: the refined objective peak at x.
    value: f64,
    /// The limits' relative violation at x.
    lim_rel: f64,
    /// L, rigorous, and its residual part.
    lower: f64,
    lower_err: f64,
    /// The polished x̂ and t̂ (before the projection) and active maxima: the start of a
    /// neighbouring solve's Newton.
    x_hat: Vec<f64>,
    t_hat: f64,
    terms: Vec<Term>,
}

impl<'p, 'a> Engine<'p, 'a> {
    /// Validates `pb` and `s`, evaluates the fields on the scan grid and fixes the scales.
    pub fn new(pb: &'p Problem<'a>, s: &Settings) -> Result<Self, MinimaxError> {
        s.validate()
            .map_err(|(field, message)| MinimaxError::Settings { field, message })?;
        validate_structure(pb)?;
        let n = pb.n();
        let mut scale = vec![1.0; n];
        for (j, c) in pb.counterweights.iter().enumerate() {
            let (sm, l) = (c.m_max, c.length());
            scale[var_m(j)] = sm;
            scale[var_u(j)] = sm * l;
            scale[var_u(j) + 1] = sm * l;
            scale[var_i(j)] = sm * l * l;
        }
        let nf = pb.fields.len();
        let mut grid = Vec::with_capacity(nf);
        for f in &pb.fields {
            let mut g = Vec::with_capacity(s.scan_samples);
            for theta in uniform_angles(s.scan_samples) {
                let mut v = AffineValue::zeros(n);
                f.eval(theta, &mut v);
                check_finite(*f, theta, &v)?;
                g.push(v);
            }
            grid.push(g);
        }
        let g0: Vec<f64> = (0..nf)
            .map(|f| {
                let d = pb.fields[f].dim();
                grid[f]
                    .iter()
                    .map(|v| v.b[..d].iter().map(|b| b * b).sum::<f64>().sqrt())
                    .fold(0.0, f64::max)
            })
            .collect();
        // Extra variables: their largest finite bound, else field size / sensitivity.
        let n_cw = PER_COUNTERWEIGHT * pb.counterweights.len();
        for (e, &(lo, hi)) in pb.extra.iter().enumerate() {
            let j = n_cw + e;
            let bound = [lo, hi]
                .into_iter()
                .filter(|v| v.is_finite())
                .fold(0.0, |a: f64, v| a.max(v.abs()));
            scale[j] = if bound > 0.0 {
                bound
            } else {
                let mut best: f64 = 0.0;
                for f in 0..nf {
                    let d = pb.fields[f].dim();
                    let sens = grid[f]
                        .iter()
                        .map(|v| (0..d).map(|r| v.row(r)[j].powi(2)).sum::<f64>().sqrt())
                        .fold(0.0, f64::max);
                    if sens > 0.0 && g0[f] > 0.0 {
                        best = best.max(g0[f] / sens);
                    }
                }
                if best > 0.0 {
                    best
                } else {
                    1.0
                }
            };
        }
        let g_ref: Vec<f64> = (0..nf)
            .map(|f| {
                let d = pb.fields[f].dim();
                let g = grid[f]
                    .iter()
                    .map(|v| {
                        let b = v.b[..d].iter().map(|b| b * b).sum::<f64>().sqrt();
                        b + (0..n)
                            .map(|j| {
                                (0..d).map(|r| v.row(r)[j].powi(2)).sum::<f64>().sqrt() * scale[j]
                            })
                            .sum::<f64>()
                    })
                    .fold(0.0, f64::max);
                if g > 0.0 {
                    g
                } else {
                    1.0
                }
            })
            .collect();
        // |x̂| bounds: m̂ ≤ 1; Î ≤ min(I_max/s_I, (ρ/ℓ)²); |û|² ≤ Î m̂ and |û| ≤ r_max/ℓ.
        let mut xbound = vec![f64::INFINITY; n];
        for (j, c) in pb.counterweights.iter().enumerate() {
            let l = c.length();
            let i_hat = (c.inertia_max / scale[var_i(j)]).min((c.envelope / l).powi(2));
            let u_hat = i_hat.sqrt().min(c.r_max / l);
            xbound[var_m(j)] = 1.0;
            xbound[var_u(j)] = u_hat;
            xbound[var_u(j) + 1] = u_hat;
            xbound[var_i(j)] = i_hat;
        }
        for (e, &(lo, hi)) in pb.extra.iter().enumerate() {
            let j = n_cw + e;
            xbound[j] = lo.abs().max(hi.abs()) / scale[j];
        }
        Ok(Engine {
            pb,
            s: *s,
            n,
            scale,
            g_ref,
            g0,
            grid,
            xbound,
        })
    }

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
    /// also returns this solve's polished conditions when it has them.
    fn solve_goal_from(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
        warm: Option<&[Vec<f64>]>,
        start: Option<&KktStart>,
    ) -> Result<(Solution, Option<KktStart>), MinimaxError> {
        validate_goal(self.pb, goal, limits)?;
        if let Some(sol) = self.disc_path(goal, limits)? {
            return Ok((sol, None));
        }
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
            Goal::MinPeak(list) => {
                let u0 = list
                    .iter()
                    .map(|&(f, w)| w * self.g0[f])
                    .fold(0.0, f64::max);
                let u0 = if u0 > 0.0 {
                    u0
                } else {
                    list.iter()
                        .map(|&(f, w)| w * self.g_ref[f])
                        .fold(0.0, f64::max)
                };
                s.abs_floor * u0
            }
            _ => 0.0,
        };
        let lim_floor = |f: usize, eps: f64| eps.max(s.abs_floor * self.g0[f]);
        let has_t = !matches!(goal, Goal::MinMass);

        if let (Goal::MinPeak(list), Some(st)) = (goal, start) {
            // The neighbouring solve's active maxima, their limits moved to these ε.
            let terms: Vec<Term> = st
                .terms
                .iter()
                .filter_map(|t| match t.eps {
                    None => list.iter().any(|l| l.0 == t.field).then(|| t.clone()),
                    Some(_) => limits.iter().find(|l| l.0 == t.field).map(|&(f, e)| Term {
                        eps: Some(e / self.g_ref[f]),
                        ..t.clone()
                    }),
                })
                .collect();
            let t_scale = self.peak_scale(list);
            // |V − L| both ways: the polished design meets its limits to round-off, so an L
            // above V would be a flaw, never a claim.
            if let Some(po) =
                self.polish_certify(list, limits, terms, &st.x_hat, st.t_hat, t_scale)?
            {
                if (po.value - po.lower).abs() <= s.rel_tol * po.value.max(obj_floor)
                    && po.lim_rel <= s.rel_tol
                {
                    return self
                        .polished_solution(goal, limits, sets, po, 0, 0, NEWTON_ONLY.into())
                        .map(|(sol, st)| (sol, Some(st)));
                }
            }
        }
        let mut round_tol = if warm_given || !sampled.iter().any(|&b| b) {
            s.rel_tol
        } else {
            1e-6_f64.max(s.rel_tol)
        };
        let mut iters = 0u32;
        let mut last: Option<Solution> = None;
        let mut prev_active: Vec<Vec<f64>> = vec![Vec::new(); nf];
        let mut best_l: Option<(f64, f64)> = None;
        let mut best_x: Option<BestDesign> = None;
        let (mut polished, mut before_polish) = (false, None::<Solution>);
        let mut polish_tries = 0;
        // The objective's scale T for clarabel: the unbalanced peak at first, then the
        // last round's bound (so that t̂ ≈ 1 and clarabel's tolerances are relative to the
        // optimum, not to the design box), never below the absolute floor.
        let mut level = match goal {
            Goal::MinPeak(_) => obj_floor / s.abs_floor,
            _ => 0.0,
        };
        for round in 1..=s.max_rounds {
            let tol_used = round_tol;
            let rd = self.solve_round(goal, limits, &sets, rms_r.as_ref(), tol_used, level)?;
            iters += rd.res.iterations;
            let status_txt = format!("{:?}", rd.res.status);
            let finite = rd.res.x.iter().all(|v| v.is_finite());
            match rd.res.status {
                SolverStatus::Solved | SolverStatus::AlmostSolved => {}
                SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                    let what = if limits.is_empty() {
                        "the design constraints (bounds, cones, linear rows) cannot all be met"
                            .to_string()
                    } else {
                        format!(
                            "no design meets the limits {} on the sampled angles (so none on all angles)",
                            limits
                                .iter()
                                .map(|&(f, e)| format!(
                                    "peak |{}| ≤ {e:e}",
                                    self.pb.fields[f].name()
                                ))
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    };
                    return Ok((
                        self.empty(
                            Status::Infeasible,
                            Stop::Infeasible,
                            round,
                            &sets,
                            iters,
                            status_txt,
                            format!("infeasible: {what} within the counterweight limits"),
                        ),
                        None,
                    ));
                }
                _ if finite && last.is_some() => {
                    let mut l = last.take().expect("checked");
                    l.status = Status::Inaccurate;
                    l.stop = Stop::SolverAccuracy;
                    l.rounds = round;
                    l.ipm_iterations = iters;
                    l.note = Some(format!(
                        "clarabel stopped with {status_txt} in round {round}; the previous round's design is kept"
                    ));
                    return Ok((l, None));
                }
                _ if finite => {}
                _ => {
                    return Ok((
                        self.empty(
                            Status::Failed,
                            Stop::SolverFailed,
                            round,
                            &sets,
                            iters,
                            status_txt,
                            "clarabel returned no finite iterate".into(),
                        ),
                        None,
                    ));
                }
            }
            let x = self.project(
                &rd.res
                    .x
                    .iter()
                    .zip(&self.scale)
                    .map(|(v, s)| v * s)
                    .collect::<Vec<_>>(),
            );
            // True peaks of the sampled fields.
            let mut pk: Vec<Option<PeriodicPeak>> = vec![None; nf];
            for f in (0..nf).filter(|&f| sampled[f]) {
                pk[f] = Some(self.scan(f, &x)?);
            }
            let peak_of = |f: usize| pk[f].as_ref().expect("sampled").peak.fx;
            let (value, gap_scale) = match goal {
                Goal::MinPeak(list) => {
                    let v = list
                        .iter()
                        .map(|&(f, w)| w * peak_of(f))
                        .fold(0.0, f64::max);
                    (v, v.max(obj_floor))
                }
                Goal::MinRms(f) => (self.rms_at(*f, &x).0, 0.0),
                Goal::MinMass => (
                    (0..self.pb.counterweights.len())
                        .map(|j| x[var_m(j)])
                        .sum::<f64>(),
                    0.0,
                ),
            };
            // The sampled problem's lower bound from clarabel's dual iterate, made rigorous
            // (`dual_lower_bound`); t̂ ≤ 2·max(t̂ found, V/T) bounds the objective variable.
            let (mut lower, mut solver_err, mut bound_solved, mut rigorous) = {
                let mut xb = self.xbound.clone();
                if has_t {
                    xb.push(2.0 * rd.res.x[self.n].abs().max(value / rd.t_scale));
                }
                let (lb, pen) = dual_lower_bound(&rd.built, &rd.res.z, &xb);
                if lb.is_finite() {
                    (
                        rd.t_scale * lb,
                        rd.t_scale * pen,
                        rd.res.status == SolverStatus::Solved,
                        true,
                    )
                } else {
                    // An unbounded extra variable: clarabel's own bound and residual estimate.
                    let r = &rd.res;
                    (
                        rd.t_scale * r.obj.min(r.obj_dual),
                        rd.t_scale * ((r.obj - r.obj_dual).abs() + r.r_dual * r.norms.max(1.0)),
                        r.status == SolverStatus::Solved,
                        false,
                    )
                }
            };
            if matches!(goal, Goal::MinPeak(_)) {
                // The Lagrangian bound at the refined maxima (`dual_bound`): free of the
                // objective variable's residual and of the clustered angles' conditioning.
                let db = self.dual_bound(&rd, &x, &pk)?;
                if let Some((lb, err)) = db {
                    if lb > lower || (!bound_solved && value - lb <= s.rel_tol * gap_scale) {
                        lower = lb;
                        solver_err = err;
                        bound_solved = true;
                        rigorous = true;
                    }
                }
            }
            if matches!(goal, Goal::MinPeak(_)) {
                level = lower.max(obj_floor);
            }
            let lim_rel = limits
                .iter()
                .map(|&(f, e)| (peak_of(f) - e).max(0.0) / lim_floor(f, e).max(f64::MIN_POSITIVE))
                .fold(0.0, f64::max);
            // The Newton polish of the round's active set (`polish`): when its design and
            // multipliers certify the tolerance, the solve ends here; otherwise the loop goes
            // on as if it had not run.
            if let Goal::MinPeak(list) = goal {
                let near = (value - lower).max(0.0) <= 1e-3 * gap_scale && lim_rel <= 1e-3;
                if near && polish_tries < MAX_POLISH {
                    polish_tries += 1;
                    if let Some(po) = self.try_polish(list, limits, &rd, &x, &pk)? {
                        let gs = po.value.max(obj_floor);
                        if (po.value - po.lower).abs() <= s.rel_tol * gs && po.lim_rel <= s.rel_tol
                        {
                            return self
                                .polished_solution(
                                    goal,
                                    limits,
                                    sets,
                                    po,
                                    round,
                                    iters,
                                    format!("{status_txt}; {POLISHED}"),
                                )
                                .map(|(sol, st)| (sol, Some(st)));
                        }
                    }
                }
            }
            // The certificate carries over between rounds: every rigorous L is a lower bound
            // of the same optimum, and every design's refined peak an upper bound, so the
            // best of each so far is kept (the rounds' designs jitter at clarabel's accuracy).
            let (mut value, mut gap_scale, mut lim_rel) = (value, gap_scale, lim_rel);
            if matches!(goal, Goal::MinPeak(_)) {
                if rigorous && bound_solved && best_l.is_none_or(|b| lower > b.0) {
                    best_l = Some((lower, solver_err));
                }
                if let Some((l, e)) = best_l {
                    if !(rigorous && bound_solved) || l > lower {
                        (lower, solver_err, rigorous, bound_solved) = (l, e, true, true);
                    }
                }
                let ok = |lr: f64| lr <= s.rel_tol;
                let better = best_x.as_ref().is_none_or(|b: &BestDesign| {
                    match (ok(lim_rel), ok(b.lim_rel)) {
                        (true, false) => true,
                        (false, true) => false,
                        (true, true) => value < b.value,
                        (false, false) => lim_rel < b.lim_rel,
                    }
                });
                if better {
                    best_x = Some(BestDesign {
                        x: x.clone(),
                        pk: pk.clone(),
                        value,
                        lim_rel,
                    });
                }
                let b = best_x.as_ref().expect("set");
                (value, lim_rel) = (b.value, b.lim_rel);
                gap_scale = value.max(obj_floor);
            }
            let obj_gap = match goal {
                Goal::MinPeak(_) => (value - lower).max(0.0),
                _ => 0.0,
            };
            let obj_ok = obj_gap <= s.rel_tol * gap_scale;
            // A round solved more loosely than the target cannot certify it.
            let within = obj_ok && lim_rel <= s.rel_tol;
            let converged = within && tol_used <= s.rel_tol;
            let almost = !bound_solved;
            let rel_gap = if gap_scale > 0.0 {
                obj_gap / gap_scale
            } else {
                0.0
            }
            .max(lim_rel);
            // The next round's clarabel tolerance: two orders below the gap, down to the target.
            let next_tol = (0.01 * rel_gap).min(1e-6).max(s.rel_tol);
            round_tol = if round_tol > s.rel_tol && !within {
                next_tol.min(round_tol * 0.01).max(s.rel_tol)
            } else {
                s.rel_tol
            };
            // Exchange: the local maxima above the bound (objective) or the limit.
            let mut added = 0;
            if !converged {
                self.prune(&mut sets, &rd, &x, &mut prev_active);
                if let Goal::MinPeak(list) = goal {
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
                            added += self.add_peak(&mut sets[f], f, theta, &x, gap_scale / w)?;
                        }
                    }
                }
                for &(f, e) in limits {
                    let above: Vec<f64> = pk[f]
                        .as_ref()
                        .expect("sampled")
                        .maxima
                        .iter()
                        .filter(|m| m.fx > e)
                        .map(|m| m.x)
                        .collect();
                    for theta in above {
                        added += self.add_peak(&mut sets[f], f, theta, &x, lim_floor(f, e))?;
                    }
                }
            }
            // A stall with a gap left: clarabel's accuracy on clustered angles. Once, restart
            // from the refined maxima alone (well separated: the active set of a vertex-type
            // optimum), keeping the better of the two solutions.
            let mut polishing = false;
            if !converged && added == 0 && tol_used <= s.rel_tol && !polished {
                polished = true;
                polishing = true;
                for f in (0..nf).filter(|&f| sampled[f]) {
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
                added = 1;
            }
            let (status, stop, note) = if converged && !almost {
                (Status::Optimal, Stop::Converged, None)
            } else if converged {
                (
                    Status::Inaccurate,
                    Stop::SolverAccuracy,
                    Some(format!(
                        "clarabel reached reduced accuracy only ({status_txt})"
                    )),
                )
            } else if added == 0 && tol_used <= s.rel_tol {
                (
                    Status::Inaccurate,
                    Stop::Stalled,
                    Some(format!(
                        "exchange stalled after {round} rounds: every local maximum is already sampled; the remaining gap is clarabel's accuracy"
                    )),
                )
            } else if round == s.max_rounds {
                (
                    Status::Inaccurate,
                    Stop::MaxRounds,
                    Some(format!(
                        "stopped after max_rounds = {} exchange rounds",
                        s.max_rounds
                    )),
                )
            } else {
                (Status::Inaccurate, Stop::MaxRounds, None)
            };
            let (x, pk) = match &best_x {
                Some(b) if matches!(goal, Goal::MinPeak(_)) => (b.x.clone(), b.pk.clone()),
                _ => (x, pk),
            };
            let sol = self.finish(
                goal,
                limits,
                &sets,
                &x,
                pk,
                value,
                (lower, solver_err, rigorous),
                status,
                stop,
                note,
                round,
                iters,
                status_txt,
            )?;
            if converged || (added == 0 && tol_used <= s.rel_tol) || round == s.max_rounds {
                // After a polish, the better certified of the two.
                return Ok((
                    match before_polish {
                        Some(b) if b.error.total < sol.error.total && !converged => b,
                        _ => sol,
                    },
                    None,
                ));
            }
            if polishing {
                before_polish = Some(Solution {
                    stop: Stop::Stalled,
                    note: Some(format!(
                        "exchange stalled after {round} rounds: every local maximum is already sampled; the remaining gap is clarabel's accuracy"
                    )),
                    ..sol.clone()
                });
            }
            last = Some(sol);
        }
        unreachable!("the last round returns")
    }

    /// Min peak of field `a` subject to peak of field `b` ≤ ε, for each ε (plus the problem's
    /// own limits); each point first tries Newton from the last polished point's optimality
    /// conditions (a continuation in ε, no SOCP), else runs the exchange loop warm-started
    /// from the previous point's final angles only.
    pub fn pareto(
        &self,
        a: usize,
        b: usize,
        eps: &[f64],
        warm: Option<&[Vec<f64>]>,
    ) -> Result<Vec<ParetoPoint>, MinimaxError> {
        let mut out: Vec<ParetoPoint> = Vec::with_capacity(eps.len());
        let mut warm_sets: Option<Vec<Vec<f64>>> = warm.map(|w| w.to_vec());
        let mut start: Option<KktStart> = None;
        for &e in eps {
            let mut limits = self.pb.limits.clone();
            limits.push((b, e));
            // Newton first from the previous point's polished optimality conditions (a
            // continuation in ε), then the exchange loop from its angles.
            let (sol, st) = self.solve_goal_from(
                &Goal::MinPeak(vec![(a, 1.0)]),
                &limits,
                warm_sets.as_deref(),
                start.as_ref(),
            )?;
            if st.is_some() {
                start = st;
            }
            if sol.status != Status::Infeasible && sol.status != Status::Failed {
                // Only the previous point's (pruned) angles: merged sets would grow to
                // hundreds of cones over a front.
                warm_sets = Some(sol.angle_sets.clone());
            }
            out.push(ParetoPoint {
                eps: e,
                solution: sol,
            });
        }
        Ok(out)
    }

    /// The front of peak A against peak B in `n` ≥ 2 points: the two single-field optima
    /// bound it; ε runs evenly from B* (the min-B peak, raised by 10 `rel_tol` so the first
    /// point is feasible despite the gap) to the peak B of the min-A design.
    pub fn pareto_front(&self, a: usize, b: usize, n: usize) -> Result<ParetoFront, MinimaxError> {
        let min_b = self.solve_goal(&Goal::MinPeak(vec![(b, 1.0)]), &self.pb.limits, None)?;
        let min_a = self.solve_goal(&Goal::MinPeak(vec![(a, 1.0)]), &self.pb.limits, None)?;
        for (sol, which) in [(&min_b, "B"), (&min_a, "A")] {
            if matches!(sol.status, Status::Infeasible | Status::Failed) {
                return Ok(ParetoFront {
                    points: Vec::new(),
                    min_b: min_b.clone(),
                    min_a: {
                        let _ = which;
                        min_a.clone()
                    },
                });
            }
        }
        let lo = min_b.peaks[b].peak * (1.0 + 10.0 * self.s.rel_tol) + min_b.peaks[b].error;
        let hi = min_a.peaks[b].peak.max(lo);
        let n = n.max(2);
        let eps: Vec<f64> = (0..n)
            .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
            .collect();
        let warm = merge_sets(Some(&min_b.angle_sets), &min_a.angle_sets);
        let points = self.pareto(a, b, &eps, Some(&warm))?;
        Ok(ParetoFront {
            min_b,
            min_a,
            points,
        })
    }

    /// The refined peaks of every field at a given design (an analysis, e.g. without
    /// counterweights), with their error bounds; `limits` only mark violations.
    pub fn peaks(&self, x: &[f64]) -> Result<Vec<FieldPeak>, MinimaxError> {
        if x.len() != self.n {
            return Err(bad(
                "x",
                format!("has {} values, the problem {}", x.len(), self.n),
            ));
        }
        (0..self.pb.fields.len())
            .map(|f| {
                let p = self.scan(f, x)?;
                self.field_peak(f, x, &p, &self.pb.limits)
            })
            .collect()
    }

    /// The RMS of field f at x over `rms_samples` uniform angles, with its quadrature error.
    pub fn rms(&self, f: usize, x: &[f64]) -> (f64, f64) {
        self.rms_at(f, x)
    }

    // ---- internals ----------------------------------------------------------------------

    fn eval(&self, f: usize, theta: f64) -> Result<AffineValue, MinimaxError> {
        let mut v = AffineValue::zeros(self.n);
        self.pb.fields[f].eval(theta, &mut v);
        check_finite(self.pb.fields[f], theta, &v)?;
        Ok(v)
    }

    /// Adds θ (mod 2π) to a field's sampled set if new, keeping it sorted; true if added.
    fn insert(
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
    fn add_peak(
        &self,
        set: &mut Vec<(f64, AffineValue)>,
        f: usize,
        theta: f64,
        x: &[f64],
        level: f64,
    ) -> Result<usize, MinimaxError> {
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        let t = theta.rem_euclid(std::f64::consts::TAU);
        let creeping = set
            .iter()
            .any(|p| crate::synth::counterweight::angle_dist(p.0, t) < h);
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

    /// The refined peak of field f at x (grid scan + refinement of every local maximum).
    fn scan(&self, f: usize, x: &[f64]) -> Result<PeriodicPeak, MinimaxError> {
        let field = self.pb.fields[f];
        let d = field.dim();
        let ys: Vec<f64> = self.grid[f].iter().map(|v| v.magnitude(d, x)).collect();
        let buf = RefCell::new(AffineValue::zeros(self.n));
        periodic_peak_sampled(
            &ys,
            |theta| {
                let mut v = buf.borrow_mut();
                v.b = [0.0; 2];
                v.a.iter_mut().for_each(|a| *a = 0.0);
                field.eval(theta, &mut v);
                v.magnitude(d, x)
            },
            Some(self.s.peak_xtol),
            Refine::All,
        )
        .map_err(|e| match e {
            crate::numeric::SearchError::NotFinite { x } => MinimaxError::NotFinite {
                field: field.name().to_string(),
                theta: x,
            },
            other => bad(format!("fields[{f}]"), other.to_string()),
        })
    }

    /// The evaluation error bound of field f at θ for x: callback + engine round-off.
    fn eval_error(&self, f: usize, v: &AffineValue, theta: f64, x: &[f64]) -> f64 {
        let field = self.pb.fields[f];
        let gamma = (self.n as f64 + 3.0) * f64::EPSILON;
        field.error(theta, x) + gamma * v.size(field.dim(), x)
    }

    fn field_peak(
        &self,
        f: usize,
        x: &[f64],
        p: &PeriodicPeak,
        limits: &[(usize, f64)],
    ) -> Result<FieldPeak, MinimaxError> {
        let mut e_eval: f64 = 0.0;
        for m in &p.maxima {
            let v = self.eval(f, m.x)?;
            e_eval = e_eval.max(self.eval_error(f, &v, m.x, x));
        }
        let limit = limits
            .iter()
            .filter(|l| l.0 == f)
            .map(|l| l.1)
            .fold(None, |a: Option<f64>, e| Some(a.map_or(e, |a| a.min(e))));
        Ok(FieldPeak {
            name: self.pb.fields[f].name().to_string(),
            peak: p.peak.fx,
            angle: p.peak.x,
            error: p.error + e_eval,
            maxima: p.maxima.clone(),
            limit,
            violation: limit.map_or(0.0, |e| (p.peak.fx - e).max(0.0)),
        })
    }

    /// (RMS, quadrature error) of field f at x on `rms_samples` uniform angles.
    fn rms_at(&self, f: usize, x: &[f64]) -> (f64, f64) {
        let d = self.pb.fields[f].dim();
        let ys: Vec<f64> = self
            .rms_values(f)
            .iter()
            .map(|v| v.magnitude(d, x))
            .collect();
        let r = periodic_rms_sampled(&ys);
        (r.rms, r.error)
    }

    /// The field on the RMS grid (the scan grid when they coincide).
    fn rms_values(&self, f: usize) -> std::borrow::Cow<'_, [AffineValue]> {
        if self.s.rms_samples == self.s.scan_samples {
            std::borrow::Cow::Borrowed(&self.grid[f])
        } else {
            std::borrow::Cow::Owned(
                uniform_angles(self.s.rms_samples)
                    .into_iter()
                    .map(|t| {
                        let mut v = AffineValue::zeros(self.n);
                        self.pb.fields[f].eval(t, &mut v);
                        v
                    })
                    .collect(),
            )
        }
    }

    /// R, the (n+1)×(n+1) triangular factor of the scaled stacked rows
    /// [A_r(θ_k) S, b_r(θ_k)] / (G_f √N): mean |g|²/G_f² = ‖R [x̂; 1]‖².
    fn rms_factor(&self, f: usize) -> Result<nalgebra::DMatrix<f64>, MinimaxError> {
        let d = self.pb.fields[f].dim();
        let vals = self.rms_values(f);
        let nn = vals.len();
        for (k, v) in vals.iter().enumerate() {
            check_finite(
                self.pb.fields[f],
                k as f64 * std::f64::consts::TAU / nn as f64,
                v,
            )?;
        }
        let w = 1.0 / (self.g_ref[f] * (nn as f64).sqrt());
        let m = nalgebra::DMatrix::from_fn(nn * d, self.n + 1, |row, col| {
            let (k, r) = (row / d, row % d);
            if col < self.n {
                vals[k].row(r)[col] * self.scale[col] * w
            } else {
                vals[k].b[r] * w
            }
        });
        Ok(m.qr().r())
    }

    /// Keeps of each sampled set only the angles that matter for the next round: the cones
    /// active at the round's optimum (dual weight z₀ above 1e-7 of the objective cones' total,
    /// or value at x within 1e-6 of the sampled bound: t̂ for an objective cone, ε̂ for a
    /// limit), and those active in the previous round (against cycling). Dropping inactive
    /// angles keeps the relaxation a relaxation (any subset gives a lower bound) while the
    /// SOCP stays small and free of stale clusters around earlier maximum positions.
    fn prune(
        &self,
        sets: &mut [Vec<(f64, AffineValue)>],
        rd: &Round,
        x: &[f64],
        prev_active: &mut [Vec<f64>],
    ) {
        let z = &rd.res.z;
        let sum: f64 = rd
            .tags
            .iter()
            .filter(|t| t.eps.is_none())
            .map(|t| z[t.row].max(0.0))
            .sum();
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

    /// The peak of a turning counterweight's force solved exactly, without clarabel, when
    /// the problem is one: the goal is the peak of one 2-D field w·|g|, with no limit, no
    /// extra variable, no linear row, one counterweight without a sector, and at every scan
    /// angle A(θ) has zero m and I columns and a u block c·Q(θ) (Q orthogonal, one constant
    /// c > 0: a counterweight on a frame pivot turning with the crank, F = b + c·Rot(θ)·u).
    /// Then |g| = c|u − p(θ)| with p = −Qᵀb/c, and the minimax over sampled angles is the
    /// smallest disc enclosing the points p(θ_k) (Welzl, [`crate::geom::enclosing_disc`],
    /// first on the scan grid), its support angles polished on the continuous curve by
    /// Newton (`polish_support`).
    ///
    /// The certificate is the engine's own: V is the refined peak at the design (the scan of
    /// [`Engine::scan`]), L the Lagrangian bound of [`Engine::disc_bound`] at the disc's
    /// support, with its weights (the barycentric coordinates of the centre) moved to the
    /// nearby refined maxima; both rest on no structure (the form only chooses the design).
    /// The maxima above L are added until V − L ≤ `rel_tol`·max(V, `abs_floor`·U₀); `None`
    /// (clarabel's loop runs instead) when the problem is not of this form, the centre is
    /// out of the counterweight's reach (|u| ≤ m_max·min(r_max, ρ), |u|² ≤ I_max·m_max) or
    /// the gap does not close in a few rounds. Of all the counterweights with the optimal u
    /// the design is the lightest: m = max(|u|/r_max, |u|/ρ, |u|²/I_max), a point mass
    /// (I = |u|²/m); the field does not depend on m or I.
    fn disc_path(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
    ) -> Result<Option<Solution>, MinimaxError> {
        use crate::synth::counterweight as cw;
        let pb = self.pb;
        let Goal::MinPeak(list) = goal else {
            return Ok(None);
        };
        let &[(f, w)] = list.as_slice() else {
            return Ok(None);
        };
        if !(self.s.exact_disc
            && limits.is_empty()
            && pb.extra.is_empty()
            && pb.linear.is_empty()
            && pb.counterweights.len() == 1
            && pb.counterweights[0].sector.is_none()
            && pb.fields[f].dim() == 2)
        {
            return Ok(None);
        }
        let (m, ux, ii) = (var_m(0), var_u(0), var_i(0));
        let only_u = |v: &AffineValue| (0..2).all(|r| v.row(r)[m] == 0.0 && v.row(r)[ii] == 0.0);
        if !self.grid[f].iter().all(only_u) {
            return Ok(None);
        }
        let to_affine = |v: &AffineValue| cw::Affine {
            a: [
                [v.row(0)[ux], v.row(0)[ux + 1]],
                [v.row(1)[ux], v.row(1)[ux + 1]],
            ],
            b: v.b,
        };
        let grid: Vec<cw::Affine> = self.grid[f].iter().map(to_affine).collect();
        let field = self.pb.fields[f];
        let eval = |phi: f64| {
            let mut v = AffineValue::zeros(self.n);
            field.eval(phi, &mut v);
            to_affine(&v)
        };
        let cpb = cw::Problem {
            fields: vec![cw::Field {
                name: "field",
                dim: 2,
                eval: &eval,
                grid: Some(&grid),
            }],
            goal: cw::Goal::MinPeak(0),
            limits: Vec::new(),
            u_max: f64::INFINITY,
            direction: cw::Direction::Free,
            warm_angles: Vec::new(),
        };
        let Some(form) = cw::DiscForm::of(&cpb) else {
            return Ok(None);
        };
        // The sampled points: the scan grid's (already evaluated), then the angles added.
        let mut pts: Vec<(f64, crate::geom::P2)> = Vec::with_capacity(grid.len() + 8);
        for (t, a) in uniform_angles(grid.len()).into_iter().zip(&grid) {
            match form.point_of(a) {
                Some(p) => pts.push((t, p)),
                None => return Ok(None),
            }
        }
        let c = &pb.counterweights[0];
        let reach = (c.m_max * c.r_max.min(c.envelope)).min((c.inertia_max * c.m_max).sqrt());
        let floor = self.s.abs_floor * w * self.g0[f];
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        const ROUNDS: usize = 6;
        for round in 1..=ROUNDS {
            let just: Vec<crate::geom::P2> = pts.iter().map(|p| p.1).collect();
            let Some(disc) = crate::geom::enclosing_disc(&just) else {
                return Ok(None);
            };
            let point = |t: f64| form.point_of(&eval(t));
            let mut weights = support_weights(&pts, &disc);
            let mut u = disc.centre;
            // The disc's support angles polished to the continuous curve's (Newton), so the
            // design does not creep towards a maximum that moves with it.
            // Kept only if the centre is inside the polished points' hull (all weights > 0:
            // still a disc's support).
            if let Some((t, c)) = polish_support(&point, &weights, h) {
                let ps: Vec<(f64, crate::geom::P2)> =
                    t.iter().filter_map(|&a| point(a).map(|p| (a, p))).collect();
                let d = crate::geom::Disc {
                    centre: c,
                    radius: ps.iter().map(|q| (q.1 - c).norm()).fold(0.0, f64::max),
                };
                let wt = support_weights(&ps, &d);
                if wt.len() == ps.len() {
                    weights = wt;
                    u = c;
                }
            }
            let un = u.norm();
            if !(un <= reach) {
                return Ok(None);
            }
            // The lightest counterweight with this u.
            let mass = [un / c.r_max, un / c.envelope, un * un / c.inertia_max]
                .into_iter()
                .filter(|v| v.is_finite())
                .fold(0.0, f64::max)
                .min(c.m_max);
            let mut x = vec![0.0; self.n];
            x[m] = mass;
            x[ux] = u.x;
            x[ux + 1] = u.y;
            x[ii] = if mass > 0.0 { un * un / mass } else { 0.0 };
            let x = self.project(&x);
            let pk = self.scan(f, &x)?;
            let value = w * pk.peak.fx;
            let moved: Vec<(f64, f64)> = weights
                .iter()
                .map(|&(t, l)| {
                    let near = pk
                        .maxima
                        .iter()
                        .map(|e| (cw::angle_dist(e.x, t), e.x))
                        .filter(|e| e.0 <= 2.0 * h)
                        .min_by(|a, b| a.0.total_cmp(&b.0))
                        .map_or(t, |e| e.1);
                    (near, l)
                })
                .collect();
            let lower = w * self
                .disc_bound(f, &weights)?
                .max(self.disc_bound(f, &moved)?);
            let gap_scale = value.max(floor);
            if value - lower <= self.s.rel_tol * gap_scale {
                let mut sets: Vec<Vec<(f64, AffineValue)>> = vec![Vec::new(); pb.fields.len()];
                for &(t, _) in &moved {
                    self.insert(&mut sets[f], f, t)?;
                }
                let mut pks = vec![None; pb.fields.len()];
                pks[f] = Some(pk);
                return self
                    .finish(
                        goal,
                        limits,
                        &sets,
                        &x,
                        pks,
                        value,
                        (lower, 0.0, true),
                        Status::Optimal,
                        Stop::Converged,
                        None,
                        round,
                        0,
                        DISC_SOLVER.into(),
                    )
                    .map(Some);
            }
            let before = pts.len();
            let add = |t: f64, pts: &mut Vec<(f64, crate::geom::P2)>| {
                let angles: Vec<f64> = pts.iter().map(|p| p.0).collect();
                if is_new(&angles, t) {
                    if let Some(p) = point(t) {
                        pts.push((t, p));
                    }
                }
            };
            for &(t, _) in &weights {
                add(t, &mut pts);
            }
            for e in &pk.maxima {
                if w * e.fx > lower + 0.5 * self.s.rel_tol * gap_scale {
                    add(e.x, &mut pts);
                }
            }
            if pts.len() == before {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// A Lagrangian lower bound of min_u max_θ |g_f(θ; u)| for a field that depends on
    /// counterweight 0's u only: for weights λ_k ≥ 0, Σλ_k = 1 at any angles θ_k,
    /// max_θ |g|² ≥ Σ_k λ_k |b_k + A_k u|² =: q(u) ≥ min q, so √(min q) is a lower bound.
    /// min q is computed as q(u*) − ¼∇qᵀQ⁻¹∇q at the computed minimiser u* = −Q⁻¹r
    /// (q = uᵀQu + 2rᵀu + c: exact for a quadratic, whatever the error of u*), less the
    /// round-off of q(u*) (16(n + 3)ε of its absolute terms). 0 when Q is singular.
    fn disc_bound(&self, f: usize, terms: &[(f64, f64)]) -> Result<f64, MinimaxError> {
        let ux = var_u(0);
        let (mut q, mut r) = ([[0.0; 2]; 2], [0.0; 2]);
        let mut vals = Vec::with_capacity(terms.len());
        for &(t, l) in terms {
            let v = self.eval(f, t)?;
            let a = [
                [v.row(0)[ux], v.row(0)[ux + 1]],
                [v.row(1)[ux], v.row(1)[ux + 1]],
            ];
            for i in 0..2 {
                for j in 0..2 {
                    q[i][j] += l * (a[0][i] * a[0][j] + a[1][i] * a[1][j]);
                }
                r[i] += l * (a[0][i] * v.b[0] + a[1][i] * v.b[1]);
            }
            vals.push((l, a, v.b));
        }
        let det = q[0][0] * q[1][1] - q[0][1] * q[1][0];
        if !(det > 0.0) || terms.is_empty() {
            return Ok(0.0);
        }
        let inv = [
            [q[1][1] / det, -q[0][1] / det],
            [-q[1][0] / det, q[0][0] / det],
        ];
        let u = [
            -(inv[0][0] * r[0] + inv[0][1] * r[1]),
            -(inv[1][0] * r[0] + inv[1][1] * r[1]),
        ];
        let (mut val, mut size) = (0.0, 0.0);
        let mut grad = [0.0; 2];
        for (l, a, b) in &vals {
            let mut s2 = 0.0;
            for k in 0..2 {
                let g = b[k] + a[k][0] * u[0] + a[k][1] * u[1];
                val += l * g * g;
                let abs = b[k].abs() + (a[k][0] * u[0]).abs() + (a[k][1] * u[1]).abs();
                s2 += abs * abs;
                for (i, gi) in grad.iter_mut().enumerate() {
                    *gi += 2.0 * l * a[k][i] * g;
                }
            }
            size += l * s2;
        }
        let gamma = 16.0 * (self.n as f64 + 3.0) * f64::EPSILON;
        // ¼∇ᵀQ⁻¹∇ ≤ ¼|∇|²/λ_min(Q), with |∇| raised by its own round-off.
        let tr = q[0][0] + q[1][1];
        let lmin = 0.5 * (tr - ((q[0][0] - q[1][1]).powi(2) + 4.0 * q[0][1] * q[1][0]).sqrt());
        let gn = grad[0].hypot(grad[1]) + 2.0 * gamma * size.sqrt() * tr.sqrt();
        if !(lmin > 0.0) {
            return Ok(0.0);
        }
        let l2 = val - 0.25 * gn * gn / (lmin * (1.0 - 1e-12)) - gamma * size;
        Ok(l2.max(0.0).sqrt())
    }

    /// Builds and solves the SOCP on the sampled angles.
    fn solve_round(
        &self,
        goal: &Goal,
        limits: &[(usize, f64)],
        sets: &[Vec<(f64, AffineValue)>],
        rms_r: Option<&nalgebra::DMatrix<f64>>,
        tol: f64,
        level: f64,
    ) -> Result<Round, MinimaxError> {
        let n = self.n;
        let has_t = !matches!(goal, Goal::MinMass);
        let nv = n + has_t as usize;
        let mut rows = Rows::default();
        let mut q = vec![0.0; nv];
        let sc = &self.scale;
        // ‖(c/…)(b + A S x̂)‖ ≤ t̂ (t = Some) or ≤ bound.
        let mut tags = Vec::new();
        let cone =
            |rows: &mut Rows, v: &AffineValue, d: usize, c: f64, t: Option<usize>, bound: f64| {
                match t {
                    Some(tj) => rows.row(&[(tj, -1.0)], 0.0),
                    None => rows.row(&[], bound),
                }
                for r in 0..d {
                    let coeffs: Vec<(usize, f64)> = v
                        .row(r)
                        .iter()
                        .enumerate()
                        .map(|(j, a)| (j, -c * a * sc[j]))
                        .collect();
                    rows.row(&coeffs, c * v.b[r]);
                }
                rows.cones.push(SupportedConeT::SecondOrderConeT(d + 1));
            };
        let t_scale = match goal {
            Goal::MinPeak(list) => {
                let _ = level;
                let t = self.peak_scale(list);
                q[n] = 1.0;
                for &(f, w) in list {
                    let d = self.pb.fields[f].dim();
                    for (theta, v) in &sets[f] {
                        tags.push(ConeTag {
                            row: rows.b.len(),
                            field: f,
                            theta: *theta,
                            c: w / t,
                            eps: None,
                        });
                        cone(&mut rows, v, d, w / t, Some(n), 0.0);
                    }
                }
                t
            }
            Goal::MinRms(f) => {
                q[n] = 1.0;
                let r = rms_r.expect("factor computed");
                rows.row(&[(n, -1.0)], 0.0);
                for i in 0..r.nrows() {
                    let coeffs: Vec<(usize, f64)> = (0..n).map(|j| (j, -r[(i, j)])).collect();
                    rows.row(&coeffs, r[(i, n)]);
                }
                rows.cones
                    .push(SupportedConeT::SecondOrderConeT(r.nrows() + 1));
                self.g_ref[*f]
            }
            Goal::MinMass => {
                let t: f64 = self.pb.counterweights.iter().map(|c| c.m_max).sum();
                for j in 0..self.pb.counterweights.len() {
                    q[var_m(j)] = sc[var_m(j)] / t;
                }
                t
            }
        };
        for &(f, e) in limits {
            let d = self.pb.fields[f].dim();
            let g = self.g_ref[f];
            for (theta, v) in &sets[f] {
                tags.push(ConeTag {
                    row: rows.b.len(),
                    field: f,
                    theta: *theta,
                    c: 1.0 / g,
                    eps: Some(e / g),
                });
                cone(&mut rows, v, d, 1.0 / g, None, e / g);
            }
        }
        self.design_rows(&mut rows);
        let p = CscMatrix::zeros((nv, nv));
        let built = rows.build(nv, p, q);
        // Feasibility as tight as the gap: a design infeasible by r moves the true peak at
        // the projected design by about r, which the certificate then has to absorb.
        let gap_tol = (0.01 * tol).clamp(1e-12, 1e-8);
        let res = run_clarabel_with(&built, gap_tol, |g| g.clamp(1e-12, 1e-8), false)
            .map_err(|e| bad("clarabel", e))?;
        Ok(Round {
            res,
            t_scale,
            tags,
            built,
        })
    }

    /// T, the objective scale of a peak goal: max w·G_f over its fields.
    fn peak_scale(&self, list: &[(usize, f64)]) -> f64 {
        list.iter()
            .map(|&(f, w)| w * self.g_ref[f])
            .fold(0.0, f64::max)
    }

    /// The certified solution of a polish (`optimal`), its active maxima the sampled
    /// angles (the other fields keep theirs), and the conditions for a neighbour's start.
    #[allow(clippy::too_many_arguments)]
    fn polished_solution(
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
        let sol = self.finish(
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
    fn try_polish(
        &self,
        list: &[(usize, f64)],
        limits: &[(usize, f64)],
        rd: &Round,
        x: &[f64],
        pk: &[Option<PeriodicPeak>],
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
        self.polish_certify(list, limits, terms, &x_hat, t_hat, rd.t_scale)
    }

    /// Newton from the given active maxima, design x̂ and objective t̂ ([`polish`]); the
    /// polished design (projected) is scanned for its true peaks, a maximum found above the
    /// polished level joins the set and Newton reruns (at most twice), and the lower bound
    /// is the rigorous Lagrangian bound ([`Engine::lagrangian_bound`]) at the polished
    /// angles and multipliers. `None` when Newton fails.
    fn polish_certify(
        &self,
        list: &[(usize, f64)],
        limits: &[(usize, f64)],
        mut terms: Vec<Term>,
        x_hat: &[f64],
        t_hat: f64,
        t_scale: f64,
    ) -> Result<Option<PolishOutcome>, MinimaxError> {
        if !terms.iter().any(|t| t.eps.is_none()) {
            return Ok(None);
        }
        let mut x_hat = x_hat.to_vec();
        let mut t_hat = t_hat;
        let nf = self.pb.fields.len();
        let h = std::f64::consts::TAU / self.s.scan_samples as f64;
        for pass in 0..3 {
            let Some(p) = self.polish(&terms, &x_hat, t_hat)? else {
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
            if self.design_violation(&xp) > polish::FEASIBLE {
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
                .map(|&(f, e)| (peak_of(f) - e).max(0.0) / e.max(self.s.abs_floor * self.g0[f]))
                .fold(0.0, f64::max);
            // Maxima above the polished level that the set lacks join it (weight 0).
            let mut missing = Vec::new();
            let known = |f: usize, th: f64| {
                p.terms.iter().any(|t| {
                    t.field == f && crate::synth::counterweight::angle_dist(t.theta, th) <= h
                })
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
                        let g = self.g_ref[f];
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
    fn dual_bound(
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
    fn round_terms(&self, rd: &Round, pk: &[Option<PeriodicPeak>]) -> Option<Vec<Term>> {
        let z = &rd.res.z;
        let sum: f64 = rd
            .tags
            .iter()
            .filter(|t| t.eps.is_none())
            .map(|t| z[t.row].max(0.0))
            .sum();
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
                        .map(|m| (crate::synth::counterweight::angle_dist(m.x, t.theta), m.x))
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
    fn lagrangian_bound(
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
            xb.push(c * self.g_ref[f]);
            rows.row(&[(n + i, -1.0)], 0.0);
            for r in 0..d {
                let coeffs: Vec<(usize, f64)> = v
                    .row(r)
                    .iter()
                    .enumerate()
                    .map(|(j, a)| (j, -c * a * self.scale[j]))
                    .collect();
                rows.row(&coeffs, c * v.b[r]);
            }
            rows.cones.push(SupportedConeT::SecondOrderConeT(d + 1));
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
    fn bound_terms(terms: &[Term]) -> Option<Vec<Term>> {
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
    fn linearised(&self, terms: &[Term], x: &[f64]) -> Result<(Vec<f64>, f64), MinimaxError> {
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
    /// s = (k m̂, û)), ν/2·(s₀, −s_t) (the body cone s = (Î + m̂, 2û, Î − m̂)). With
    /// multipliers accurate to round-off this is tight where a clarabel solve is not: the
    /// limits' multipliers can be large near the front's end, and the bound is then a small
    /// difference of large terms. Caller's units; `None` when the polish has no design
    /// multipliers.
    fn kkt_bound(
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
            Design::Radius { .. } => 3,
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
                Design::Body { m, u, i } => {
                    let h = 0.5 * nu;
                    z[at] = h * (xh[*i] + xh[*m]);
                    z[at + 1] = -h * 2.0 * xh[*u];
                    z[at + 2] = -h * 2.0 * xh[u + 1];
                    z[at + 3] = -h * (xh[*i] - xh[*m]);
                    at += 4;
                }
            }
        }
        let (lb, pen) = dual_lower_bound(&lin, &z, &self.xbound);
        Ok(lb
            .is_finite()
            .then_some((t_scale * (lb + cl), t_scale * pen)))
    }

    /// The design constraints in scaled variables.
    fn design_rows(&self, rows: &mut Rows) {
        let sc = &self.scale;
        let nonneg =
            |rows: &mut Rows, k: usize| rows.cones.push(SupportedConeT::NonnegativeConeT(k));
        for (j, c) in self.pb.counterweights.iter().enumerate() {
            let (m, ux, uy, i) = (var_m(j), var_u(j), var_u(j) + 1, var_i(j));
            let l = c.length();
            // 0 ≤ m̂ ≤ 1 (s_m = m_max), Î ≥ 0.
            rows.row(&[(m, -1.0)], 0.0);
            rows.row(&[(m, 1.0)], 1.0);
            rows.row(&[(i, -1.0)], 0.0);
            nonneg(rows, 3);
            if c.inertia_max.is_finite() {
                rows.row(&[(i, 1.0)], c.inertia_max / sc[i]);
                nonneg(rows, 1);
            }
            if c.envelope.is_finite() {
                // ρ² m − I ≥ 0 → (ρ/ℓ)² m̂ − Î ≥ 0.
                let k = (c.envelope / l).powi(2);
                rows.row(&[(m, -k), (i, 1.0)], 0.0);
                nonneg(rows, 1);
            }
            if c.r_max.is_finite() {
                // ‖û‖ ≤ (r_max/ℓ) m̂.
                rows.row(&[(m, -c.r_max / l)], 0.0);
                rows.row(&[(ux, -1.0)], 0.0);
                rows.row(&[(uy, -1.0)], 0.0);
                rows.cones.push(SupportedConeT::SecondOrderConeT(3));
            }
            // Î m̂ ≥ |û|²: ‖(2û, Î − m̂)‖ ≤ Î + m̂.
            rows.row(&[(i, -1.0), (m, -1.0)], 0.0);
            rows.row(&[(ux, -2.0)], 0.0);
            rows.row(&[(uy, -2.0)], 0.0);
            rows.row(&[(i, -1.0), (m, 1.0)], 0.0);
            rows.cones.push(SupportedConeT::SecondOrderConeT(4));
            if let Some((lo, hi)) = c.sector {
                let (sl, cl) = lo.sin_cos();
                let (sh, ch) = hi.sin_cos();
                let (sm, cm) = (0.5 * (lo + hi)).sin_cos();
                rows.row(&[(ux, sl), (uy, -cl)], 0.0); // cos lo·u_y − sin lo·u_x ≥ 0
                rows.row(&[(ux, -sh), (uy, ch)], 0.0); // sin hi·u_x − cos hi·u_y ≥ 0
                rows.row(&[(ux, -cm), (uy, -sm)], 0.0); // u·bisector ≥ 0
                nonneg(rows, 3);
            }
        }
        let n_cw = PER_COUNTERWEIGHT * self.pb.counterweights.len();
        for (e, &(lo, hi)) in self.pb.extra.iter().enumerate() {
            let j = n_cw + e;
            if lo.is_finite() {
                rows.row(&[(j, -1.0)], -lo / sc[j]);
                nonneg(rows, 1);
            }
            if hi.is_finite() {
                rows.row(&[(j, 1.0)], hi / sc[j]);
                nonneg(rows, 1);
            }
        }
        for lc in &self.pb.linear {
            let big = lc
                .coeffs
                .iter()
                .map(|&(j, c)| (c * sc[j]).abs())
                .fold(0.0, f64::max);
            let coeffs: Vec<(usize, f64)> = lc
                .coeffs
                .iter()
                .map(|&(j, c)| (j, c * sc[j] / big))
                .collect();
            rows.row(&coeffs, lc.rhs / big);
            rows.cones.push(match lc.relation {
                Relation::Eq => SupportedConeT::ZeroConeT(1),
                Relation::Le => SupportedConeT::NonnegativeConeT(1),
            });
        }
    }

    /// Makes a solver iterate a real body: m and I clamped to ≥ 0 and ≤ their bounds, and
    /// where I·m < |u|² by the solver's tolerance, I raised to |u|²/m (u = 0 at m = 0). The
    /// peaks are then computed at this x, so the certificate is of the design returned.
    fn project(&self, x: &[f64]) -> Vec<f64> {
        let mut x = x.to_vec();
        for (j, c) in self.pb.counterweights.iter().enumerate() {
            let (m, ux, i) = (var_m(j), var_u(j), var_i(j));
            x[m] = x[m].clamp(0.0, c.m_max);
            x[i] = x[i].max(0.0);
            let u2 = x[ux] * x[ux] + x[ux + 1] * x[ux + 1];
            if x[i] * x[m] < u2 {
                if x[m] > 0.0 {
                    x[i] = u2 / x[m] * (1.0 + 4.0 * f64::EPSILON);
                } else {
                    x[ux] = 0.0;
                    x[ux + 1] = 0.0;
                }
            }
        }
        x
    }

    /// The design constraints in scaled variables as smooth functions d(x̂) ≤ 0 (or = 0),
    /// each relative to its scale (the same constraints as [`Engine::design_rows`]'s cones).
    fn design_constraints(&self) -> Vec<Design> {
        let sc = &self.scale;
        let lin = |a: Vec<(usize, f64)>, r: f64| Design::Linear { a, r, eq: false };
        let mut out = Vec::new();
        for (j, c) in self.pb.counterweights.iter().enumerate() {
            let (m, u, i) = (var_m(j), var_u(j), var_i(j));
            let l = c.length();
            out.push(lin(vec![(m, -1.0)], 0.0));
            out.push(lin(vec![(m, 1.0)], 1.0));
            out.push(lin(vec![(i, -1.0)], 0.0));
            if c.inertia_max.is_finite() {
                out.push(lin(vec![(i, 1.0)], c.inertia_max / sc[i]));
            }
            if c.envelope.is_finite() {
                out.push(lin(vec![(i, 1.0), (m, -(c.envelope / l).powi(2))], 0.0));
            }
            if c.r_max.is_finite() {
                out.push(Design::Radius {
                    m,
                    u,
                    k: c.r_max / l,
                });
            }
            out.push(Design::Body { m, u, i });
            if let Some((lo, hi)) = c.sector {
                let (sl, cl) = lo.sin_cos();
                let (sh, ch) = hi.sin_cos();
                let (sm, cm) = (0.5 * (lo + hi)).sin_cos();
                out.push(lin(vec![(u, sl), (u + 1, -cl)], 0.0));
                out.push(lin(vec![(u, -sh), (u + 1, ch)], 0.0));
                out.push(lin(vec![(u, -cm), (u + 1, -sm)], 0.0));
            }
        }
        let n_cw = PER_COUNTERWEIGHT * self.pb.counterweights.len();
        for (e, &(lo, hi)) in self.pb.extra.iter().enumerate() {
            let j = n_cw + e;
            if lo.is_finite() {
                out.push(lin(vec![(j, -1.0)], -lo / sc[j]));
            }
            if hi.is_finite() {
                out.push(lin(vec![(j, 1.0)], hi / sc[j]));
            }
        }
        for lc in &self.pb.linear {
            let big = lc
                .coeffs
                .iter()
                .map(|&(j, c)| (c * sc[j]).abs())
                .fold(0.0, f64::max);
            out.push(Design::Linear {
                a: lc
                    .coeffs
                    .iter()
                    .map(|&(j, c)| (j, c * sc[j] / big))
                    .collect(),
                r: lc.rhs / big,
                eq: lc.relation == Relation::Eq,
            });
        }
        out
    }

    /// Largest relative violation of the design constraints at x.
    fn design_violation(&self, x: &[f64]) -> f64 {
        let xh: Vec<f64> = x.iter().zip(&self.scale).map(|(v, s)| v / s).collect();
        self.design_constraints()
            .iter()
            .map(|d| {
                let v = d.value(&xh);
                if d.is_eq() {
                    v.abs()
                } else {
                    v
                }
            })
            .fold(0.0, f64::max)
    }

    /// The solution of one round with its figures and error bounds.
    #[allow(clippy::too_many_arguments)]
    fn finish(
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
                let vals = self.rms_values(*f);
                let nn = vals.len();
                let e = vals
                    .iter()
                    .enumerate()
                    .map(|(k, v)| {
                        self.eval_error(*f, v, k as f64 * std::f64::consts::TAU / nn as f64, x)
                    })
                    .fold(0.0, f64::max);
                (e, 0.0, self.rms_at(*f, x).1)
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
            angle_sets: sets
                .iter()
                .map(|s| s.iter().map(|p| p.0).collect())
                .collect(),
            ipm_iterations: iters,
            solver_status,
            note,
        })
    }

    /// A solution without a design (infeasible or failed).
    #[allow(clippy::too_many_arguments)]
    fn empty(
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
            angle_sets: sets
                .iter()
                .map(|s| s.iter().map(|p| p.0).collect())
                .collect(),
            ipm_iterations: iters,
            solver_status,
            note: Some(note),
        }
    }
}

/// Solves `pb` with its own goal and limits (an [`Engine`] for one solve).
pub fn solve(pb: &Problem, s: &Settings) -> Result<Solution, MinimaxError> {
    Engine::new(pb, s)?.solve()
}

/// Weights λ ≥ 0, Σλ = 1, on the support of a smallest enclosing disc of the points
/// (angle, p): the points within 1e-9 of the radius from the centre; the centre's
/// barycentric coordinates in a triangle of them that contains it, else in their farthest
/// pair (projected onto it). Any weights give a valid bound ([`Engine::disc_bound`]); these
/// make it the disc's radius.
fn support_weights(pts: &[(f64, crate::geom::P2)], disc: &crate::geom::Disc) -> Vec<(f64, f64)> {
    let on: Vec<&(f64, crate::geom::P2)> = pts
        .iter()
        .filter(|(_, p)| (p - disc.centre).norm() >= disc.radius * (1.0 - 1e-9))
        .collect();
    let c = disc.centre;
    for i in 0..on.len() {
        for j in i + 1..on.len() {
            for k in j + 1..on.len() {
                let (a, b, d) = (on[i].1, on[j].1, on[k].1);
                let det = crate::geom::cross(b - a, d - a);
                if det == 0.0 {
                    continue;
                }
                let lb = crate::geom::cross(c - a, d - a) / det;
                let ld = crate::geom::cross(b - a, c - a) / det;
                let la = 1.0 - lb - ld;
                if la >= 0.0 && lb >= 0.0 && ld >= 0.0 {
                    return vec![(on[i].0, la), (on[j].0, lb), (on[k].0, ld)];
                }
            }
        }
    }
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..on.len() {
        for j in i + 1..on.len() {
            let d = (on[i].1 - on[j].1).norm();
            if best.is_none_or(|b| d > b.0) {
                best = Some((d, i, j));
            }
        }
    }
    match best {
        Some((d, i, j)) if d > 0.0 => {
            let (a, b) = (on[i].1, on[j].1);
            let t = ((c - a).dot(&(b - a)) / (d * d)).clamp(0.0, 1.0);
            vec![(on[i].0, 1.0 - t), (on[j].0, t)]
        }
        _ => on.first().map_or(Vec::new(), |p| vec![(p.0, 1.0)]),
    }
}

/// Newton on the support angles θ_i of a smallest enclosing disc of a curve p(θ) (2 or 3
/// points): each must be a stationary point of |p(θ) − v| with v the centre of the disc
/// through the points (their midpoint, or circumcentre), F_i = (p(θ_i) − v)·p'(θ_i) = 0,
/// p' by central differences (step 1e-5), the Jacobian by forward differences of F. Where
/// a maximum moves with the design (a disc on two points, free to slide across their
/// diameter), the exchange alone creeps towards it; this locates it in a few steps.
/// `None` if a step leaves the scan spacing `h` or the iteration does not settle.
fn polish_support(
    point: &dyn Fn(f64) -> Option<crate::geom::P2>,
    weights: &[(f64, f64)],
    h: f64,
) -> Option<(Vec<f64>, crate::geom::P2)> {
    use crate::geom::P2;
    let centre = |ps: &[P2]| -> Option<P2> {
        if ps.len() == 2 {
            Some(0.5 * (ps[0] + ps[1]))
        } else {
            crate::geom::circumcentre(ps[0], ps[1], ps[2]).map(|c| c.0)
        }
    };
    let eta = 1e-5;
    let resid = |th: &[f64]| -> Option<(Vec<f64>, P2)> {
        let ps: Vec<P2> = th.iter().map(|&t| point(t)).collect::<Option<_>>()?;
        let v = centre(&ps)?;
        let mut f = Vec::with_capacity(th.len());
        for (i, &t) in th.iter().enumerate() {
            let d = (point(t + eta)? - point(t - eta)?) / (2.0 * eta);
            f.push((ps[i] - v).dot(&d));
        }
        Some((f, v))
    };
    // Support points around one maximum of the curve (neighbouring samples) are one.
    let mut merged: Vec<(f64, f64)> = Vec::new();
    for &(t, l) in weights {
        match merged
            .iter_mut()
            .find(|m| crate::synth::counterweight::angle_dist(m.0, t) <= 2.0 * h)
        {
            Some(m) if l > m.1 => *m = (t, m.1 + l),
            Some(m) => m.1 += l,
            None => merged.push((t, l)),
        }
    }
    let k = merged.len();
    if !(k == 2 || k == 3) {
        return None;
    }
    let mut th: Vec<f64> = merged.iter().map(|w| w.0).collect();
    let start = th.clone();
    let eta2 = 1e-6;
    let mut last_step = f64::INFINITY;
    for _ in 0..10 {
        let (f, _) = resid(&th)?;
        let mut jac = nalgebra::DMatrix::<f64>::zeros(k, k);
        for j in 0..k {
            let mut t2 = th.clone();
            t2[j] += eta2;
            let (f2, _) = resid(&t2)?;
            for i in 0..k {
                jac[(i, j)] = (f2[i] - f[i]) / eta2;
            }
        }
        let step = jac.lu().solve(&nalgebra::DVector::from_vec(f))?;
        let mut big: f64 = 0.0;
        for j in 0..k {
            th[j] -= step[j];
            big = big.max(step[j].abs());
        }
        if th
            .iter()
            .zip(&start)
            .any(|(a, b)| crate::synth::counterweight::angle_dist(*a, *b) > h)
        {
            return None;
        }
        // Quadratic convergence: the next step would be below 1e-16; a step that does not
        // shrink is the differences' noise.
        if big <= 1e-9 || big >= last_step {
            break;
        }
        last_step = big;
    }
    let (_, v) = resid(&th)?;
    Some((
        th.iter()
            .map(|t| t.rem_euclid(std::f64::consts::TAU))
            .collect(),
        v,
    ))
}

/// Per field, the union of two angle sets (sorted, near-duplicates dropped).
fn merge_sets(a: Option<&[Vec<f64>]>, b: &[Vec<f64>]) -> Vec<Vec<f64>> {
    (0..b.len())
        .map(|f| {
            let mut v: Vec<f64> = a.and_then(|a| a.get(f)).cloned().unwrap_or_default();
            for &t in &b[f] {
                if is_new(&v, t) {
                    v.push(t);
                }
            }
            v.sort_by(f64::total_cmp);
            v
        })
        .collect()
}

fn check_finite(f: &dyn AffineField, theta: f64, v: &AffineValue) -> Result<(), MinimaxError> {
    if v.b.iter().chain(&v.a).all(|a| a.is_finite()) {
        Ok(())
    } else {
        Err(MinimaxError::NotFinite {
            field: f.name().to_string(),
            theta,
        })
    }
}

fn validate_structure(pb: &Problem) -> Result<(), MinimaxError> {
    let n = pb.n();
    if n == 0 {
        return Err(bad(
            "counterweights",
            "no design variable (no counterweight, no extra variable)",
        ));
    }
    if pb.fields.is_empty() {
        return Err(bad("fields", "no field"));
    }
    for (f, field) in pb.fields.iter().enumerate() {
        if !matches!(field.dim(), 1 | 2) {
            return Err(bad(
                format!("fields[{f}].dim"),
                format!(
                    "must be 1 or 2, got {} (field `{}`)",
                    field.dim(),
                    field.name()
                ),
            ));
        }
    }
    for (j, c) in pb.counterweights.iter().enumerate() {
        let w = |k: &str| format!("counterweights[{j}].{k}");
        if !(c.m_max.is_finite() && c.m_max > 0.0) {
            return Err(bad(
                w("m_max"),
                format!("must be finite and > 0 kg, got {}", c.m_max),
            ));
        }
        for (k, v) in [
            ("r_max", c.r_max),
            ("inertia_max", c.inertia_max),
            ("envelope", c.envelope),
        ] {
            if !(v > 0.0) {
                return Err(bad(
                    w(k),
                    format!("must be > 0 (infinite: no limit), got {v}"),
                ));
            }
        }
        if !(c.inertia_max.is_finite() || c.envelope.is_finite()) {
            return Err(bad(
                w("inertia_max"),
                "the inertia must be bounded: give inertia_max or an envelope radius",
            ));
        }
        if let Some((lo, hi)) = c.sector {
            if !(lo.is_finite()
                && hi.is_finite()
                && hi >= lo
                && hi - lo <= std::f64::consts::PI + 1e-12)
            {
                return Err(bad(
                    w("sector"),
                    format!("must be [lo, hi] with 0 ≤ hi − lo ≤ π, got [{lo}, {hi}]"),
                ));
            }
        }
    }
    for (e, &(lo, hi)) in pb.extra.iter().enumerate() {
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return Err(bad(
                format!("extra[{e}]"),
                format!("bounds must be lo ≤ hi, got [{lo}, {hi}]"),
            ));
        }
    }
    for (k, lc) in pb.linear.iter().enumerate() {
        if lc.coeffs.is_empty() || lc.coeffs.iter().all(|c| c.1 == 0.0) {
            return Err(bad(format!("linear[{k}]"), "has no nonzero coefficient"));
        }
        for &(j, c) in &lc.coeffs {
            if j >= n || !c.is_finite() {
                return Err(bad(
                    format!("linear[{k}]"),
                    format!(
                        "coefficient ({j}, {c}): the variable must be < {n} and the value finite"
                    ),
                ));
            }
        }
        if !lc.rhs.is_finite() {
            return Err(bad(format!("linear[{k}].rhs"), "must be finite"));
        }
    }
    validate_goal(pb, &pb.goal, &pb.limits)
}

fn validate_goal(pb: &Problem, goal: &Goal, limits: &[(usize, f64)]) -> Result<(), MinimaxError> {
    let nf = pb.fields.len();
    match goal {
        Goal::MinPeak(list) => {
            if list.is_empty() {
                return Err(bad("goal", "a peak goal needs at least one field"));
            }
            for (k, &(f, w)) in list.iter().enumerate() {
                if f >= nf {
                    return Err(bad(
                        format!("goal[{k}]"),
                        format!("field {f} does not exist ({nf} fields)"),
                    ));
                }
                if !(w.is_finite() && w > 0.0) {
                    return Err(bad(
                        format!("goal[{k}]"),
                        format!("weight must be finite and > 0, got {w}"),
                    ));
                }
                if list[..k].iter().any(|p| p.0 == f) {
                    return Err(bad(
                        format!("goal[{k}]"),
                        format!("field {f} is listed twice"),
                    ));
                }
            }
        }
        Goal::MinRms(f) => {
            if *f >= nf {
                return Err(bad(
                    "goal",
                    format!("field {f} does not exist ({nf} fields)"),
                ));
            }
        }
        Goal::MinMass => {
            if pb.counterweights.is_empty() {
                return Err(bad("goal", "minimum mass needs a counterweight"));
            }
        }
    }
    for (k, &(f, e)) in limits.iter().enumerate() {
        if f >= nf {
            return Err(bad(
                format!("limits[{k}]"),
                format!("field {f} does not exist ({nf} fields)"),
            ));
        }
        if !(e.is_finite() && e >= 0.0) {
            return Err(bad(
                format!("limits[{k}]"),
                format!("ε must be finite and ≥ 0, got {e}"),
            ));
        }
    }
    Ok(())
}
